//! Circle–circle contact in closed form.
//!
//! The crossings lie on the radical line at distance `x = (d² + r_i² − r_j²)/(2d)` from c_i
//! along the line of centres, so the chord definition gives the textbook contact exactly:
//! normal along the line of centres, `δ = r_i + r_j − d`.

use super::record::{Contact, ContactState, OverlapArea, Request, TOUCH_TOL};
use crate::geometry::overlap_area::ellipse_cap;
use crate::geometry::{Pose, Vec2};

/// Contact between circle i (radius `ri`) and circle j (radius `rj`): the chord's half-length
/// when `request.chord` (a square root the dynamics does not read), the overlap area when
/// `request.area`.
///
/// Swap-symmetric by construction (bit for bit): every quantity is formed from expressions
/// that are exactly symmetric in i and j (`r_i + r_j`, `c_i + c_j`, `|c_j − c_i|`) or exactly
/// antisymmetric (`c_j − c_i`, `r_i − r_j`), so exchanging the circles negates the normal and
/// keeps the rest.
#[inline(always)]
pub fn contact_circle_circle(
    ri: f64,
    pi: &Pose,
    rj: f64,
    pj: &Pose,
    request: &Request,
) -> Option<Contact> {
    let dv = pj.position - pi.position;
    let d2 = dv.norm_squared();
    let sum = ri + rj;
    if d2 > sum * sum {
        return None;
    }
    let d = d2.sqrt();
    let depth = sum - d;
    let lean = |state, point, normal| Contact {
        state,
        point,
        normal,
        depth,
        half_chord: 0.0,
        area: None,
        flat: None,
    };
    if d <= (ri - rj).abs() {
        // One circle inside the other: normal along the line of centres; for concentric
        // circles the x axis, from the larger to the smaller (so that it flips with the pair;
        // two equal concentric circles are one and the same object, whichever is i).
        let n = if d > 0.0 {
            dv / d
        } else if ri >= rj {
            Vec2::x()
        } else {
            -Vec2::x()
        };
        let inner = if ri >= rj { pj.position } else { pi.position };
        return Some(lean(ContactState::Contained, inner, n));
    }
    let n = dv * (1.0 / d);
    // The radical line (the chord's line) is at (d² + r_i² − r_j²)/(2d) from c_i along n, i.e.
    // at (r_i − r_j)(r_i + r_j)/(2d) from the midpoint of the centres: its midpoint is the
    // contact point.
    let shift = 0.5 * ((ri - rj) * sum / d);
    let point = (pi.position + pj.position) * 0.5 + n * shift;
    let state = if depth <= TOUCH_TOL * ri.max(rj) {
        ContactState::Touching
    } else {
        ContactState::Overlap
    };
    let mut c = lean(state, point, n);
    if request.chord || request.area {
        // Half the chord is twice the area of the triangle of sides r_i, r_j, d over d (Heron),
        // written with δ = r_i + r_j − d: no cancellation at small overlaps, and symmetric.
        let d = ri + rj - depth;
        let heron = depth * ((2.0 * ri - depth) * (2.0 * rj - depth)) * (2.0 * (ri + rj) - depth);
        let half = heron.max(0.0).sqrt() / (2.0 * d);
        if request.chord {
            c.half_chord = half;
        }
        if request.area && state == ContactState::Overlap {
            // The cap of each circle beyond the chord, from its sagitta — h_i = δ(2r_j − δ)/(2d)
            // for i, h_j = δ(2r_i − δ)/(2d) for j (r − h would cancel at small overlaps) — in
            // the frame (t, n) about its centre.
            let cap = |r: f64, h: f64| ellipse_cap(r, r, [-half, r - h], [2.0 * half, 0.0], h > r);
            let (hi, hj) = (
                depth * (2.0 * rj - depth) / (2.0 * d),
                depth * (2.0 * ri - depth) / (2.0 * d),
            );
            c.area = Some(OverlapArea {
                area: cap(ri, hi) + cap(rj, hj),
                length: 2.0 * half,
                normal: n,
                point,
                couple: 0.0,
            });
        }
    }
    Some(c)
}

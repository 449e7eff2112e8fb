//! Circle–circle contact in closed form.
//!
//! The crossings lie on the radical line at distance `x = (d² + r_i² − r_j²)/(2d)` from c_i
//! along the line of centres, so the chord definition gives the textbook contact exactly:
//! normal along the line of centres, `δ = r_i + r_j − d`.

use super::{Contact, ContactGeometry, ContactState, OverlapArea, TOUCH_TOL};
use crate::geometry::overlap_area::ellipse_cap;
use crate::geometry::{Pose, Vec2};

/// What the dynamics needs of a circle pair — state, contact point, normal, depth — without
/// the chord (whose half-length costs a square root nobody then reads). `None` when separated.
/// [`contact_circle_circle`] is this plus the chord.
#[inline]
pub fn overlap_circle_circle(
    ri: f64,
    pi: &Pose,
    rj: f64,
    pj: &Pose,
) -> Option<(ContactState, Vec2, Vec2, f64)> {
    let dv = pj.position - pi.position;
    let d2 = dv.norm_squared();
    let sum = ri + rj;
    if d2 > sum * sum {
        return None;
    }
    let d = d2.sqrt();
    let depth = sum - d;
    if d <= (ri - rj).abs() {
        // One circle inside the other (or concentric): normal along the line of centres.
        let n = if d > 0.0 { dv / d } else { Vec2::x() };
        let inner = if ri >= rj { pj.position } else { pi.position };
        return Some((ContactState::Contained, inner, n, depth));
    }
    let inv_d = 1.0 / d;
    let n = dv * inv_d;
    // The radical line (the chord's line) is at x from c_i; its midpoint is the contact point.
    let x = 0.5 * (d + (ri - rj) * (ri + rj) * inv_d);
    let state = if depth <= TOUCH_TOL * ri.max(rj) {
        ContactState::Touching
    } else {
        ContactState::Overlap
    };
    Some((state, pi.position + n * x, n, depth))
}

/// Contact between circle i (radius `ri`) and circle j (radius `rj`), with the overlap area.
#[inline]
pub fn contact_circle_circle(ri: f64, pi: &Pose, rj: f64, pj: &Pose) -> Contact {
    contact_circle_circle_with(ri, pi, rj, pj, true)
}

/// [`contact_circle_circle`], with the overlap area only when `area` is set.
#[inline]
pub fn contact_circle_circle_with(ri: f64, pi: &Pose, rj: f64, pj: &Pose, area: bool) -> Contact {
    let Some((state, point, n, depth)) = overlap_circle_circle(ri, pi, rj, pj) else {
        return Contact::SEPARATED;
    };
    let mut overlap = None;
    let chord = if state == ContactState::Contained {
        (point, point)
    } else {
        // Sagittas of the two caps, h_i = δ(2r_j − δ)/(2d) and h_j = δ(2r_i − δ)/(2d): no
        // cancellation at small overlaps (r_i − x would cancel).
        let d = ri + rj - depth;
        let (hi, hj) = (
            depth * (2.0 * rj - depth) / (2.0 * d),
            depth * (2.0 * ri - depth) / (2.0 * d),
        );
        let half = (hi * (2.0 * ri - hi)).max(0.0).sqrt();
        let t = Vec2::new(-n.y, n.x);
        if area && state == ContactState::Overlap {
            // Both caps, in the frame (t, n) about each centre: the chord is at ri − hi from c_i.
            let e = [2.0 * half, 0.0];
            let cap_i = ellipse_cap(ri, ri, [-half, ri - hi], e, hi > ri);
            let cap_j = ellipse_cap(rj, rj, [-half, hj - rj], e, hj > rj);
            overlap = Some(OverlapArea {
                area: cap_i + cap_j,
                length: 2.0 * half,
                normal: n,
                point,
                couple: 0.0,
            });
        }
        (point - t * half, point + t * half)
    };
    Contact {
        state,
        geometry: Some(ContactGeometry {
            point,
            normal: n,
            depth,
            chord,
            flat: None,
            area: overlap,
        }),
    }
}

//! Wall–rectangle contact: the wall line ∩ the rectangle's edges.

use super::{Contact, ContactState, LocalFrame, LocalOverlap, TOUCH_TOL, pow2_floor};
use crate::geometry::overlap_area::polygon_area;
use crate::geometry::{Pose, Wall};

/// Corners of a `w × h` rectangle centred at the origin, counter-clockwise.
#[inline]
pub(crate) fn corners(w: f64, h: f64) -> [[f64; 2]; 4] {
    let (x, y) = (0.5 * w, 0.5 * h);
    [[-x, -y], [x, -y], [x, y], [-x, y]]
}

/// Contact between a wall (i) and a rectangle (j) of width `w` (along its x axis) and height `h`.
///
/// The depth is the deepest corner's penetration (`δ = s(n) − h_c`, the rectangle's support
/// being its farthest corner); the chord joins the two points where the wall line crosses the
/// edges, so a rectangle lying flat gets its contact point in the middle of its bottom edge and a
/// rectangle on a corner gets it next to that corner.
#[inline]
pub fn contact_wall_rectangle(wall: &Wall, w: f64, h: f64, pose: &Pose) -> Contact {
    let scale = pow2_floor(0.5 * w.hypot(h));
    let inv = 1.0 / scale;
    let hc = wall.signed_distance(pose.position) * inv;
    let nb = pose.to_body_vector(wall.normal);
    let q = corners(w * inv, h * inv);
    let s = q.map(|c| hc + nb.x * c[0] + nb.y * c[1]);
    let lowest = s.iter().copied().fold(f64::INFINITY, f64::min);
    let depth = -lowest;
    let tol = TOUCH_TOL;
    if depth < -tol {
        return Contact::SEPARATED;
    }
    let (c, sn) = pose.cos_sin();
    let frame = LocalFrame {
        origin: pose.position,
        cos: c,
        sin: sn,
        scale,
    };
    let mut cross = [[0.0f64; 2]; 4];
    let mut n = 0;
    // The part of the rectangle beyond the wall line, as a polygon (for its area).
    let mut under = [[0.0f64; 2]; 6];
    let mut nu = 0;
    for k in 0..4 {
        let (a, b) = (k, (k + 1) % 4);
        if s[a] < 0.0 {
            under[nu] = q[a];
            nu += 1;
        }
        if (s[a] < 0.0) != (s[b] < 0.0) {
            let t = s[a] / (s[a] - s[b]);
            cross[n] = [
                q[a][0] + t * (q[b][0] - q[a][0]),
                q[a][1] + t * (q[b][1] - q[a][1]),
            ];
            under[nu] = cross[n];
            nu += 1;
            n += 1;
        }
    }
    let normal_local = [nb.x, nb.y];
    let (state, p1, p2) = if n == 2 && depth > tol {
        (ContactState::Overlap, cross[0], cross[1])
    } else if s.iter().all(|&v| v < 0.0) {
        let c0 = [-hc * nb.x, -hc * nb.y];
        (ContactState::Contained, c0, c0)
    } else {
        // Touching: the corner (or edge) on the line; its midpoint.
        let (mut sx, mut sy, mut m) = (0.0, 0.0, 0.0);
        for (c, &v) in q.iter().zip(&s) {
            if v <= lowest + tol {
                sx += c[0];
                sy += c[1];
                m += 1.0;
            }
        }
        let p = [sx / m - lowest * nb.x, sy / m - lowest * nb.y];
        (ContactState::Touching, p, p)
    };
    let mid = super::midpoint(p1, p2);
    let mut g = frame.geometry(p1, p2, mid, normal_local, depth);
    g.normal = wall.normal;
    g.flat = Some(frame.flat(&under[..nu]));
    if state == ContactState::Overlap {
        // The overlap is the polygon below the line; its gradient is the chord's (cheap, so
        // always given).
        let a = polygon_area(&under[..nu]);
        let mut o = frame.overlap(&LocalOverlap::chord(a, p1, p2, normal_local));
        o.normal = wall.normal;
        g.area = Some(o);
    }
    Contact {
        state,
        geometry: Some(g),
    }
}

//! Wall–polygon contact (a rectangle as its four corners): the wall line ∩ the polygon's
//! edges, in the polygon's frame.

use super::local::{LocalFrame, LocalOverlap, pow2_floor};
use super::record::{Contact, ContactState, Request, TOUCH_TOL};
use super::small::List;
use crate::geometry::overlap_area::polygon_area;
use crate::geometry::{Pose, Shape, Vec2, Wall};

/// Contact between a wall (i) and a convex polygon `poly` (j): a polygon, or a rectangle as
/// its corners ([`Shape::vertices`]).
///
/// The depth is the deepest vertex's penetration (the polygon's support along the wall's
/// inward normal minus its centroid's height); the chord joins the two points where the wall
/// line crosses the edges, so a rectangle lying flat gets its contact point in the middle of
/// its bottom edge and one on a corner gets it next to that corner; the overlap area is the
/// polygon's part beyond the line (exact, a clipped polygon). For a flat-sided body
/// ([`Shape::is_flat_sided`]: a rectangle), the [`FlatOverlap`](super::FlatOverlap) of that
/// part too; a polygon takes the laws of smooth bodies.
pub fn contact_wall_polygon(
    wall: &Wall,
    poly: &Shape,
    pose: &Pose,
    request: &Request,
) -> Option<Contact> {
    let flat = poly.is_flat_sided();
    let scale = pow2_floor(poly.bounding_radius());
    let inv = 1.0 / scale;
    let hc = wall.signed_distance(pose.position) * inv;
    let nb = pose.to_body_vector(wall.normal);
    let mut corners = [Vec2::zeros(); 4];
    let verts = poly.vertices(&mut corners);
    let n = verts.len();
    let q: List<[f64; 2]> = verts.iter().map(|v| [v.x * inv, v.y * inv]).collect();
    let s: List<f64> = q.iter().map(|c| hc + nb.x * c[0] + nb.y * c[1]).collect();
    let lowest = s.iter().copied().fold(f64::INFINITY, f64::min);
    let depth = -lowest;
    let tol = TOUCH_TOL;
    if depth < -tol {
        return None;
    }
    let frame = LocalFrame::of(pose, scale);
    let mut cross = [[0.0f64; 2]; 2];
    let mut nc = 0;
    // The part of the polygon beyond the wall line, as a polygon (for its area).
    let mut under: List<[f64; 2]> = List::new();
    for a in 0..n {
        let b = (a + 1) % n;
        if s[a] < 0.0 {
            under.push(q[a]);
        }
        if (s[a] < 0.0) != (s[b] < 0.0) {
            // The fraction along the edge from the edge's own direction (the wall's offset `hc`
            // cancels from s[a] − s[b], but not its rounding).
            let e = [q[b][0] - q[a][0], q[b][1] - q[a][1]];
            let t = -s[a] / (nb.x * e[0] + nb.y * e[1]);
            let x = [q[a][0] + t * e[0], q[a][1] + t * e[1]];
            // A convex polygon's boundary crosses a line at most twice.
            if nc < 2 {
                cross[nc] = x;
            }
            nc += 1;
            under.push(x);
        }
    }
    let normal_local = [nb.x, nb.y];
    let (state, p1, p2) = if nc == 2 && depth > tol {
        (ContactState::Overlap, cross[0], cross[1])
    } else if s.iter().all(|&v| v < 0.0) {
        let c0 = [-hc * nb.x, -hc * nb.y];
        (ContactState::Contained, c0, c0)
    } else {
        // Touching: the vertex (or edge) on the line; its midpoint.
        let (mut sx, mut sy, mut m) = (0.0, 0.0, 0.0);
        for (c, &v) in q.iter().zip(s.iter()) {
            if v <= lowest + tol {
                sx += c[0];
                sy += c[1];
                m += 1.0;
            }
        }
        let p = [sx / m - lowest * nb.x, sy / m - lowest * nb.y];
        (ContactState::Touching, p, p)
    };
    let mid = super::local::midpoint(p1, p2);
    let mut c = frame.contact(state, p1, p2, mid, normal_local, depth, request);
    c.normal = wall.normal;
    if flat {
        c.flat = Some(frame.flat(&under));
    }
    if state == ContactState::Overlap && request.area {
        // The overlap is the polygon below the line; its gradient is the chord's.
        let a = polygon_area(&under);
        let mut o = frame.overlap(&LocalOverlap::chord(a, p1, p2, normal_local));
        o.normal = wall.normal;
        c.area = Some(o);
    }
    Some(c)
}

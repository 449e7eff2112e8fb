//! Wall–ellipse contact: the wall line ∩ the conic, in the ellipse's own frame
//! (`x²/a² + y²/b² = 1`), where both the depth and the chord have closed forms.

use super::local::{LocalFrame, LocalOverlap, pow2_floor};
use super::record::{Contact, ContactState, Request, TOUCH_TOL};
use crate::geometry::overlap_area::ellipse_cap_at_depth;
use crate::geometry::{Pose, Wall};

/// Contact between a wall (i) and an ellipse (j) with semi-axes `a` (along its x axis) and `b`.
/// The normal is the wall's normal; `δ = s(n) − h` with `h` the centre's height above the wall
/// line and `s(n) = √(a²n_x² + b²n_y²)` the ellipse's support in its own frame. With
/// `request.area`, the overlap area too (the ellipse's cap beyond the wall line).
#[inline]
pub fn contact_wall_ellipse(
    wall: &Wall,
    a: f64,
    b: f64,
    pose: &Pose,
    request: &Request,
) -> Option<Contact> {
    let area = request.area;
    let scale = pow2_floor(a.max(b));
    let inv = 1.0 / scale;
    let (a, b) = (a * inv, b * inv);
    let h = wall.signed_distance(pose.position) * inv;
    let nb = pose.to_body_vector(wall.normal);
    let (nx, ny) = (nb.x, nb.y);
    let s = ((a * nx) * (a * nx) + (b * ny) * (b * ny)).sqrt();
    let depth = s - h;
    if depth < -TOUCH_TOL {
        return None;
    }
    // The wall line in the body frame is n_b·x = −h: x = m + σ t, m = −h n_b, t ⟂ n_b.
    let (mx, my, tx, ty) = (-h * nx, -h * ny, -ny, nx);
    let (ia2, ib2) = (1.0 / (a * a), 1.0 / (b * b));
    let alpha = tx * tx * ia2 + ty * ty * ib2;
    let beta = mx * tx * ia2 + my * ty * ib2;
    let mqm = mx * mx * ia2 + my * my * ib2;
    let disc = beta * beta - alpha * (mqm - 1.0);
    let sigma = -beta / alpha;
    let mid = [mx + sigma * tx, my + sigma * ty];
    let frame = LocalFrame::of(pose, scale);
    // Classified by the depth, which is exact here; the half-chord only places the crossings
    // (at the tip of a thin ellipse it is tiny for a sizeable depth: half² ≈ 2(b²/a)δ).
    let half = disc.max(0.0).sqrt() / alpha;
    let p = [mid[0] - half * tx, mid[1] - half * ty];
    let q = [mid[0] + half * tx, mid[1] + half * ty];
    let state = if depth <= TOUCH_TOL {
        ContactState::Touching
    } else if depth < 2.0 * s - TOUCH_TOL {
        ContactState::Overlap
    } else {
        ContactState::Contained
    };
    let mut c = frame.contact(state, p, q, mid, [nx, ny], depth, request);
    c.normal = wall.normal;
    if area && state == ContactState::Overlap {
        // The part of the ellipse below the wall line, from the depth (exact to rounding).
        let cap = ellipse_cap_at_depth(a, b, [-nx, -ny], depth);
        let mut o = frame.overlap(&LocalOverlap::chord(cap, p, q, [nx, ny]));
        o.normal = wall.normal;
        c.area = Some(o);
    }
    Some(c)
}

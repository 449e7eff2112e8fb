//! Wall–circle contact in closed form: the chord is where the wall line cuts the circle.

use super::record::{Contact, ContactState, OverlapArea, Request, TOUCH_TOL};
use crate::geometry::overlap_area::ellipse_cap;
use crate::geometry::{Pose, Wall};

/// Contact between a wall (i) and a circle (j) of radius `r`; the normal is the wall's normal.
/// The chord's half-length when `request.chord` (a square root the dynamics does not read),
/// the overlap area when `request.area`.
#[inline(always)]
pub fn contact_wall_circle(wall: &Wall, r: f64, pose: &Pose, request: &Request) -> Option<Contact> {
    let h = wall.signed_distance(pose.position);
    let depth = r - h;
    if depth < -TOUCH_TOL * r {
        return None;
    }
    let n = wall.normal;
    let point = pose.position - n * h;
    let state = if h <= -r {
        ContactState::Contained
    } else if depth <= TOUCH_TOL * r {
        ContactState::Touching
    } else {
        ContactState::Overlap
    };
    let mut c = Contact {
        state,
        point,
        normal: n,
        depth,
        half_chord: 0.0,
        area: None,
        flat: None,
    };
    if state != ContactState::Contained && (request.chord || request.area) {
        // The sagitta is the depth: no cancellation at small overlaps.
        let half = (depth * (2.0 * r - depth)).max(0.0).sqrt();
        if request.chord {
            c.half_chord = half;
        }
        if request.area && state == ContactState::Overlap {
            // The cap below the wall line, in the frame (t, n) about the centre.
            let cap = ellipse_cap(r, r, [-half, depth - r], [2.0 * half, 0.0], depth > r);
            c.area = Some(OverlapArea {
                area: cap,
                length: 2.0 * half,
                normal: n,
                point,
                couple: 0.0,
            });
        }
    }
    Some(c)
}

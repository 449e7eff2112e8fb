//! Wall–circle contact in closed form: the chord is where the wall line cuts the circle.

use super::{Contact, ContactGeometry, ContactState, OverlapArea, Request, TOUCH_TOL};
use crate::geometry::overlap_area::ellipse_cap;
use crate::geometry::{Pose, Vec2, Wall};

/// A wall–circle pair's state, contact point, normal and depth, without the chord. `None` when
/// separated. [`contact_wall_circle`] is this plus what the request asks.
#[inline(always)]
pub fn overlap_wall_circle(
    wall: &Wall,
    r: f64,
    pose: &Pose,
) -> Option<(ContactState, Vec2, Vec2, f64)> {
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
    Some((state, point, n, depth))
}

/// Contact between a wall (i) and a circle (j) of radius `r`; the normal is the wall's normal.
/// The chord when `request.chord` (otherwise both ends at the contact point, unless the area is
/// asked), the overlap area when `request.area`.
#[inline(always)]
pub fn contact_wall_circle(wall: &Wall, r: f64, pose: &Pose, request: &Request) -> Contact {
    let Some((state, point, n, depth)) = overlap_wall_circle(wall, r, pose) else {
        return Contact::SEPARATED;
    };
    let area = request.area;
    let mut overlap = None;
    let chord = if state == ContactState::Contained || !(request.chord || area) {
        (point, point)
    } else {
        // The sagitta is the depth: no cancellation at small overlaps.
        let half = (depth * (2.0 * r - depth)).max(0.0).sqrt();
        let t = Vec2::new(-n.y, n.x);
        if area && state == ContactState::Overlap {
            // The cap below the wall line, in the frame (t, n) about the centre.
            let cap = ellipse_cap(r, r, [-half, depth - r], [2.0 * half, 0.0], depth > r);
            overlap = Some(OverlapArea {
                area: cap,
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

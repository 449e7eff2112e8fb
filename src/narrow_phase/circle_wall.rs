//! Wall–circle contact in closed form: the chord is where the wall line cuts the circle.

use super::{Contact, ContactGeometry, ContactState, TOUCH_TOL};
use crate::geometry::{Pose, Vec2, Wall};

/// What the dynamics needs of a wall–circle pair — state, contact point, normal, depth —
/// without the chord. `None` when separated. [`contact_wall_circle`] is this plus the chord.
#[inline]
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
#[inline]
pub fn contact_wall_circle(wall: &Wall, r: f64, pose: &Pose) -> Contact {
    let Some((state, point, n, depth)) = overlap_wall_circle(wall, r, pose) else {
        return Contact::SEPARATED;
    };
    let chord = if state == ContactState::Contained {
        (point, point)
    } else {
        let h = r - depth;
        let half = ((r - h) * (r + h)).max(0.0).sqrt();
        let t = Vec2::new(-n.y, n.x) * half;
        (point - t, point + t)
    };
    Contact {
        state,
        geometry: Some(ContactGeometry {
            point,
            normal: n,
            depth,
            chord,
            flat: None,
        }),
    }
}

//! Wall–circle contact in closed form: the chord is where the wall line cuts the circle.

use super::{Contact, ContactGeometry, ContactState, TOUCH_TOL};
use crate::geometry::{Pose, Vec2, Wall};

/// Contact between a wall (i) and a circle (j) of radius `r`; the normal is the wall's normal.
#[inline]
pub fn contact_wall_circle(wall: &Wall, r: f64, pose: &Pose) -> Contact {
    let h = wall.signed_distance(pose.position);
    let depth = r - h;
    if depth < -TOUCH_TOL * r {
        return Contact::SEPARATED;
    }
    let n = wall.normal;
    let point = pose.position - n * h;
    if h <= -r {
        return Contact {
            state: ContactState::Contained,
            geometry: Some(ContactGeometry {
                point,
                normal: n,
                depth,
                chord: (point, point),
                flat: None,
            }),
        };
    }
    let half = ((r - h) * (r + h)).max(0.0).sqrt();
    let t = Vec2::new(-n.y, n.x) * half;
    let state = if depth <= TOUCH_TOL * r {
        ContactState::Touching
    } else {
        ContactState::Overlap
    };
    Contact {
        state,
        geometry: Some(ContactGeometry {
            point,
            normal: n,
            depth,
            chord: (point - t, point + t),
            flat: None,
        }),
    }
}

//! Circle–circle contact in closed form.
//!
//! The crossings lie on the radical line at distance `x = (d² + r_i² − r_j²)/(2d)` from c_i
//! along the line of centres, so the chord definition gives the textbook contact exactly:
//! normal along the line of centres, `δ = r_i + r_j − d`.

use super::{Contact, ContactGeometry, ContactState, TOUCH_TOL};
use crate::geometry::{Pose, Vec2};

/// Contact between circle i (radius `ri`) and circle j (radius `rj`).
#[inline]
pub fn contact_circle_circle(ri: f64, pi: &Pose, rj: f64, pj: &Pose) -> Contact {
    let dv = pj.position - pi.position;
    let d2 = dv.norm_squared();
    let sum = ri + rj;
    if d2 > sum * sum {
        return Contact::SEPARATED;
    }
    let d = d2.sqrt();
    let depth = sum - d;
    let tol = TOUCH_TOL * ri.max(rj);
    if d <= (ri - rj).abs() {
        // One circle inside the other (or concentric): normal along the line of centres.
        let n = if d > 0.0 { dv / d } else { Vec2::x() };
        let inner = if ri >= rj { pj.position } else { pi.position };
        return Contact {
            state: ContactState::Contained,
            geometry: Some(ContactGeometry {
                point: inner,
                normal: n,
                depth,
                chord: (inner, inner),
                flat: None,
            }),
        };
    }
    let n = dv / d;
    let x = 0.5 * (d + (ri - rj) * (ri + rj) / d);
    let half = ((ri - x) * (ri + x)).max(0.0).sqrt();
    let point = pi.position + n * x;
    let t = Vec2::new(-n.y, n.x) * half;
    let state = if depth <= tol {
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

//! JSON form of a narrow-phase result, one object per pair:
//! `{"state": …, "depth": δ, "normal": [nx, ny], "point": [x, y], "chord": [[x1, y1], [x2, y2]]}`,
//! geometry fields `null` when separated. Numbers are written with full round-trip precision
//! (the shortest representation that reads back to the same double).

use crate::narrow_phase::{Contact, ContactState};
use serde::Serialize;

/// The serialised form of one contact (fields in this order).
#[derive(Serialize)]
pub struct ContactRecord {
    pub state: &'static str,
    pub depth: Option<f64>,
    pub normal: Option<[f64; 2]>,
    pub point: Option<[f64; 2]>,
    pub chord: Option<[[f64; 2]; 2]>,
}

/// `x`, with −0 written as 0 (a sign of zero carries no meaning in a contact record).
fn z(x: f64) -> f64 {
    x + 0.0
}

impl ContactRecord {
    /// The record of a query's result (`None`: apart).
    pub fn of(c: Option<&Contact>) -> Self {
        let v = |p: crate::geometry::Vec2| [z(p.x), z(p.y)];
        ContactRecord {
            state: ContactState::of(c).as_str(),
            depth: c.map(|c| z(c.depth)),
            normal: c.map(|c| v(c.normal)),
            point: c.map(|c| v(c.point)),
            chord: c.map(|c| {
                let (p, q) = c.chord();
                [v(p), v(q)]
            }),
        }
    }
}

/// One line of JSON for a query's result (`None`: apart).
pub fn contact_json(c: Option<&Contact>) -> String {
    serde_json::to_string(&ContactRecord::of(c)).expect("plain numbers and strings serialise")
}

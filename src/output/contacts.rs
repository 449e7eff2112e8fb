//! JSON form of a narrow-phase result, one object per pair:
//! `{"state": …, "depth": δ, "normal": [nx, ny], "point": [x, y], "chord": [[x1, y1], [x2, y2]]}`,
//! geometry fields `null` when separated. Numbers are written with full round-trip precision
//! (the shortest representation that reads back to the same double).

use crate::narrow_phase::Contact;
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

impl From<&Contact> for ContactRecord {
    fn from(c: &Contact) -> Self {
        let g = c.geometry.as_ref();
        let v = |p: crate::geometry::Vec2| [z(p.x), z(p.y)];
        ContactRecord {
            state: c.state.as_str(),
            depth: g.map(|g| z(g.depth)),
            normal: g.map(|g| v(g.normal)),
            point: g.map(|g| v(g.point)),
            chord: g.map(|g| [v(g.chord.0), v(g.chord.1)]),
        }
    }
}

/// One line of JSON for a contact.
pub fn contact_json(c: &Contact) -> String {
    serde_json::to_string(&ContactRecord::from(c)).expect("plain numbers and strings serialise")
}

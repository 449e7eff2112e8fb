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

impl From<&Contact> for ContactRecord {
    fn from(c: &Contact) -> Self {
        let g = c.geometry.as_ref();
        ContactRecord {
            state: c.state.as_str(),
            depth: g.map(|g| g.depth),
            normal: g.map(|g| [g.normal.x, g.normal.y]),
            point: g.map(|g| [g.point.x, g.point.y]),
            chord: g.map(|g| [[g.chord.0.x, g.chord.0.y], [g.chord.1.x, g.chord.1.y]]),
        }
    }
}

/// One line of JSON for a contact.
pub fn contact_json(c: &Contact) -> String {
    serde_json::to_string(&ContactRecord::from(c)).expect("plain numbers and strings serialise")
}

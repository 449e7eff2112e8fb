//! The list of contacts, carried from step to step with each contact's history.
//!
//! A contact is keyed by `(i, j)`: two body indices `i < j`, or a body `i` and wall `w` as
//! `j = WALL_BASE + w`. The list is kept sorted by key, so the previous step's history is found
//! by a merge, and both lists' buffers are reused (no allocation once warmed up).

use crate::contact_law::History;
use crate::geometry::Vec2;
use crate::narrow_phase::ContactState;

/// Wall `w` is keyed as `WALL_BASE + w`.
pub const WALL_BASE: u32 = u32::MAX / 2;

/// One contact of the current step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// First body.
    pub i: u32,
    /// Second body, or `WALL_BASE + w` for wall `w`.
    pub j: u32,
    /// Shear history (T16), dropped when the contact ends.
    pub history: History,
    /// Geometry state (overlap, deep, contained, …).
    pub state: ContactState,
    /// Contact point, normal (from the wall or from i towards j) and depth.
    pub point: Vec2,
    pub normal: Vec2,
    pub depth: f64,
    /// Force on j (the body, for a wall contact) this step, world components.
    pub force: Vec2,
    /// Energy stored in the springs.
    pub elastic_energy: f64,
    /// The part stored in the shear spring.
    pub shear_energy: f64,
    /// For the energy account: the non-elastic part of the normal force, the shear force, and
    /// the change of the shear spring's energy this step.
    pub normal_non_elastic: f64,
    pub tangential: f64,
    pub shear_energy_change: f64,
    /// Stiffness and damping now, normal and shear (for the critical time step).
    pub kn: f64,
    pub eta_n: f64,
    pub kt: f64,
    pub eta_t: f64,
}

impl Contact {
    /// True for a body–wall contact.
    #[inline]
    pub fn is_wall(&self) -> bool {
        self.j >= WALL_BASE
    }
}

/// This step's contacts and the previous step's (for their histories).
#[derive(Clone, Debug, Default)]
pub struct ContactList {
    pub current: Vec<Contact>,
    previous: Vec<Contact>,
    cursor: usize,
}

impl ContactList {
    /// Starts a new step: the current list becomes the previous one.
    pub fn begin_step(&mut self) {
        std::mem::swap(&mut self.current, &mut self.previous);
        self.current.clear();
        self.cursor = 0;
    }

    /// Shear-spring energy of the previous step's contacts that did not continue into this one
    /// (call once this step's contacts are all pushed).
    pub fn opened_shear_energy(&self) -> f64 {
        let mut b = 0;
        let mut lost = 0.0;
        for p in &self.previous {
            while b < self.current.len() && (self.current[b].i, self.current[b].j) < (p.i, p.j) {
                b += 1;
            }
            let continues =
                b < self.current.len() && (self.current[b].i, self.current[b].j) == (p.i, p.j);
            if !continues {
                lost += p.shear_energy;
            }
        }
        lost
    }

    /// The history of contact `(i, j)` if it existed last step. Keys must be asked for in
    /// increasing order within a step (a merge walk).
    pub fn carried(&mut self, i: u32, j: u32) -> Option<History> {
        while self.cursor < self.previous.len() {
            let c = &self.previous[self.cursor];
            match (c.i, c.j).cmp(&(i, j)) {
                std::cmp::Ordering::Less => self.cursor += 1,
                std::cmp::Ordering::Equal => return Some(c.history),
                std::cmp::Ordering::Greater => return None,
            }
        }
        None
    }
}

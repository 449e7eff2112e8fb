//! The state a run can be continued from exactly (a restart): everything the step reads that it
//! cannot recompute from the case, so that a world resumed from it steps to the same bits as the
//! world it was taken from.
//!
//! What that is, stage by stage of [`super::step`]:
//! - every body's pose, velocity and angular velocity, and the force and moment of the last
//!   evaluation (the first half-kick of the next step uses them; they were evaluated with the
//!   half-step velocities, so they cannot be evaluated again from the state); a circle's frame
//!   (the cosine and sine its pose keeps from its first pose, [`crate::geometry::Pose::moved`]);
//! - every wall's current point, the velocity of its next drift (a servo's was set from the last
//!   load) and that load, and a program's current stage with the point and time it began at
//!   (its anchor: the stage before may have been a servo's, which no case can replay);
//! - the neighbour list as built: every slot (pair) in key order, active or not, with its
//!   history — every part's history values, the energy they hold, the geometry state — its
//!   narrow-phase [`PairCache`] (the conic pairs' warm start: the next step's crossings are
//!   refined from it, so the last bits of the result depend on it) and its contact this step
//!   ([`ContactData`], for the outputs read before the next step); the positions the list was
//!   built from (they decide when it is rebuilt, and a body's number of slots enters the contact
//!   kinematics) and the number of builds;
//! - the step count (the time is `step × Δt`), the energy account and the diagnostic counters.
//!
//! It is the world's state only: what the run around the world keeps (the quiescence streak,
//! the summary's counters, the blow-up watch's reference) is [`crate::run::RunProgress`],
//! saved beside it. The core neither reads nor writes it: `output::state` writes it into
//! `state.json`, `scene::state` reads it back.

use super::account::{Diagnostics, Energies};
use super::body::BodyInit;
use super::boundary::{Boundary, WallLoad};
use super::cell::{Cell, LatticeMark};
use super::contacts::{ContactData, Slot};
use super::flow::FlowRestart;
use super::partner::Partner;
use crate::contact_law::{HISTORY_LEN, History};
use crate::geometry::Vec2;
use crate::narrow_phase::{ContactState, PairCache};
use std::fmt;

/// One body's part of a restart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyRestart {
    pub position: Vec2,
    pub angle: f64,
    /// The frame `(cos, sin)` of the body's pose (`angle.sin_cos()` but for circles).
    pub frame: (f64, f64),
    pub velocity: Vec2,
    pub omega: f64,
    /// Force and moment of the last evaluation.
    pub force: Vec2,
    pub torque: f64,
    /// In a periodic cell, its image counts (zero otherwise).
    pub image: [i32; 2],
}

/// One wall's part of a restart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallRestart {
    /// The wall's point now (it starts from the case's point).
    pub point: Vec2,
    /// Velocity of the next drift.
    pub velocity: Vec2,
    /// Its contacts in the last evaluation.
    pub load: WallLoad,
    /// A program's stage (see [`super::boundary`]; `None` for a wall without a program).
    pub program: Option<ProgramRestart>,
    /// A turning boundary's angle (`None` for one that does not turn; then `point` is its
    /// pivot: [`super::boundary::Boundary::anchor`]).
    pub turn: Option<TurnRestart>,
}

/// Where a turning boundary is in its turn (see [`super::boundary::Turn`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurnRestart {
    pub angle: f64,
    pub start_angle: f64,
    pub omega: f64,
}

/// Where a wall's program is: the stage of its last drift, and the point and time that stage
/// began at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProgramRestart {
    pub stage: usize,
    pub start: Vec2,
    pub start_time: f64,
}

/// One slot of the neighbour list: the pair, its history, its pair cache and its contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlotRestart {
    pub slot: Slot,
    /// The history values after the first (which the slot holds: [`History`]), zero where the
    /// scene's laws keep none.
    pub more: [f64; HISTORY_LEN - 1],
    pub cache: PairCache,
    pub data: ContactData,
}

/// A world's full state (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct RestartState {
    pub step: u64,
    /// `step × Δt` as the step computes it.
    pub time: f64,
    pub bodies: Vec<BodyRestart>,
    pub walls: Vec<WallRestart>,
    /// Every slot of the neighbour list, in key order.
    pub slots: Vec<SlotRestart>,
    /// Body positions and wall points when the list was built.
    pub built_at: Vec<Vec2>,
    pub wall_built_at: Vec<Vec2>,
    /// A periodic cell's lattice when the list was built (`None` outside a cell; in a state
    /// file written before it was kept, the cell's lattice now).
    pub lattice_built_at: Option<LatticeMark>,
    pub builds: u64,
    pub energies: Energies,
    pub diagnostics: Diagnostics,
    pub last_increments: [f64; 3],
    /// The periodic cell as it is now (its height, Lees–Edwards shift and last stress), if the
    /// scene has one.
    pub cell: Option<Cell>,
    /// Each body's identity ([`super::body::Bodies::id`]), and the next one to give.
    pub ids: Vec<u64>,
    pub next_id: u64,
    /// Where the scene's insertion and outflow stand, if it has any ([`super::flow`]).
    pub flow: Option<FlowRestart>,
}

/// A restart that does not fit the scene it is resumed with: where (a path below the state,
/// such as `slots[3].j`) and why.
#[derive(Clone, Debug, PartialEq)]
pub struct RestartError {
    pub path: String,
    pub message: String,
}

impl RestartError {
    fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        RestartError {
            path: path.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for RestartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

impl std::error::Error for RestartError {}

/// What the scene keeps beside its slots: pair caches (warm starts), and how many of the
/// [`History`] values its laws keep (the first is in the slot).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Kept {
    pub cached: bool,
    pub history: usize,
}

impl RestartState {
    /// Checks that this state fits the scene of `bodies` and `walls` stepped with `dt`, keeping
    /// what `kept` says: the counts, the time, the slots' keys (in order, each a pair of the
    /// scene), and no history of a kind the scene does not keep.
    pub(crate) fn check(
        &self,
        bodies: &[BodyInit],
        walls: &[Boundary],
        dt: f64,
        kept: Kept,
    ) -> Result<(), RestartError> {
        let (n, nw) = (bodies.len(), walls.len());
        let count = |path: &str, got: usize, want: usize, of: &str| {
            if got == want {
                Ok(())
            } else {
                Err(RestartError::new(
                    path,
                    format!("has {got} entries, but the case has {want} {of}"),
                ))
            }
        };
        count("bodies", self.bodies.len(), n, "bodies")?;
        count("ids", self.ids.len(), n, "bodies")?;
        let mut seen = std::collections::HashSet::new();
        for (k, &id) in self.ids.iter().enumerate() {
            if id >= self.next_id || !seen.insert(id) {
                return Err(RestartError::new(
                    format!("ids[{k}]"),
                    format!(
                        "{id}: identities must be distinct and below next_id = {}",
                        self.next_id
                    ),
                ));
            }
        }
        count("walls", self.walls.len(), nw, "walls")?;
        count("neighbour_list.built_at", self.built_at.len(), n, "bodies")?;
        count(
            "neighbour_list.wall_built_at",
            self.wall_built_at.len(),
            nw,
            "walls",
        )?;
        let time = self.step as f64 * dt;
        if self.time.to_bits() != time.to_bits() {
            return Err(RestartError::new(
                "time",
                format!(
                    "{} is not step × dt = {} × {dt:e} = {time} (a continued run keeps the time \
                     step of the run that wrote the state)",
                    self.time, self.step
                ),
            ));
        }
        let mut last: Option<(u32, u32, u32)> = None;
        for (k, s) in self.slots.iter().enumerate() {
            let at = |f: &str| format!("contacts[{k}].{f}");
            let (i, j, sub) = s.slot.key();
            if i as usize >= n {
                return Err(RestartError::new(
                    at("i"),
                    format!("body {i} does not exist (the case has {n} bodies)"),
                ));
            }
            let partner = s.slot.partner();
            match partner {
                Partner::Wall(w) if w >= nw => {
                    return Err(RestartError::new(
                        at("wall"),
                        format!("wall {w} does not exist (the case has {nw} walls)"),
                    ));
                }
                Partner::Body(j) if j >= n || j <= i as usize => {
                    return Err(RestartError::new(
                        at("j"),
                        format!("must be a body after i = {i} and below {n}, got {j}"),
                    ));
                }
                Partner::Wall(_) | Partner::Body(_) => {}
            }
            if last.is_some_and(|l| l >= (i, j, sub)) {
                return Err(RestartError::new(
                    at("i"),
                    "the contacts must be listed once each, in the order of (i, j), walls after \
                     bodies",
                ));
            }
            last = Some((i, j, sub));
            let member_count = |k: usize| bodies[k].shape.clump().map_or(1, |c| c.len());
            let clump_pair = bodies[i as usize].shape.clump().is_some()
                || partner
                    .body()
                    .is_some_and(|j| bodies[j].shape.clump().is_some());
            if clump_pair != (sub != 0) {
                return Err(RestartError::new(
                    at("members"),
                    if clump_pair {
                        "a clump pair's contact must give its `members`"
                    } else {
                        "`members` is only for the contacts of clumps"
                    },
                ));
            }
            let (a, b) = s.slot.members();
            let b_max = partner.body().map_or(1, member_count);
            if a >= member_count(i as usize) || b >= b_max {
                return Err(RestartError::new(
                    at("sub"),
                    format!(
                        "member pair ({a}, {b}) does not exist (body {i} has {} members, the \
                         other side {b_max})",
                        member_count(i as usize)
                    ),
                ));
            }
            if !kept.cached && !s.cache.is_empty() {
                return Err(RestartError::new(
                    at("warm"),
                    "a warm start, but no pair of this scene keeps one (no ellipse)",
                ));
            }
            for (m, &v) in s.more.iter().enumerate() {
                if 1 + m >= kept.history && v != 0.0 {
                    let name = History::NAMES[1 + m];
                    return Err(RestartError::new(
                        at(name),
                        format!(
                            "a `{name}` history value, but no contact law of this scene keeps \
                             one"
                        ),
                    ));
                }
            }
            if !s.slot.active
                && (s.slot.shear != 0.0
                    || s.slot.history_energy != 0.0
                    || s.more.iter().any(|&v| v != 0.0))
            {
                return Err(RestartError::new(
                    at("active"),
                    "an inactive contact carries no history",
                ));
            }
        }
        Ok(())
    }
}

/// The name of a contact's geometry state in a state file.
pub fn state_name(s: ContactState) -> &'static str {
    s.as_str()
}

/// The geometry state named `name` ([`state_name`]).
pub fn state_from_name(name: &str) -> Option<ContactState> {
    [
        ContactState::Separated,
        ContactState::Touching,
        ContactState::Overlap,
        ContactState::Deep,
        ContactState::Contained,
    ]
    .into_iter()
    .find(|s| s.as_str() == name)
}

//! Watching a run for a blow-up before anything is non-finite, and for bodies that overlap at
//! the start; the report of a blow-up ([`BlowupReport`]: the step, the body, the reason). The
//! checks read the world only (the contact extras they report are refreshed by the caller, with
//! [`World::refresh_contact_extras`]).
//!
//! # The energy criterion
//! With `D ≥ 0` the energy the contacts took out, `E = K + P + E_el + D` is constant in exact
//! arithmetic, up to the work `W` done on the bodies by moving walls (`Energies::boundary_work`,
//! see `dynamics::boundary`): `E − W` is. A stable explicit step does not
//! conserve `E` exactly but keeps its error bounded: velocity Verlet's measured energy swings by a
//! factor of at most `1/(1 − (ωΔt)²/4)` during a contact, ×11 only within 5 % of the stability
//! limit `ωΔt = 2`. An unstable step multiplies the energy at every step. The run therefore
//! stops when the energy created, `E − E₀ − W`, exceeds [`ENERGY_GROWTH`] times all the energy
//! that could be in motion: the initial kinetic and elastic energy, plus the most that gravity
//! has supplied so far (`max (P₀ − P)`), plus the work of the boundaries.
//!
//! Dissipation only ever grows: `D` falling below the most it has been, `D_max − D`, is energy
//! created too (an unstable dashpot, whose power the account books as negative dissipation),
//! and is added to `E − E₀ − W` rather than cancelling the kinetic energy it became. Without
//! that, a floor given 300 times launched a body at 200 cm/s with `D = −1.7e5` erg and the watch
//! never fired (issue 29).
//!
//! # The extent criterion
//! A body farther from the origin than [`MAX_EXTENT_RATIO`] × the smallest width (twice the
//! smallest inscribed radius) is beyond what a case or a state file may place a body at (the
//! reader refuses it: positions there no longer resolve the bodies), so the run could write a
//! state nobody can continue: a
//! body thrown up at 1e16 cm/s in a cell periodic in x, or pushed by an edited force of 1e300
//! dyn (issue 41). The positions are scanned every [`EXTENT_EVERY`] steps (an O(n) read: every
//! step it would cost a visible fraction of a step of free flight).
//!
//! # The depth criterion
//! An overlap deeper than the bodies themselves — more than twice the smaller inscribed radius
//! of the pair, the smaller body's whole thickness — is no contact any law describes: the step
//! let a body pass into another. The limit is raised to the deepest overlap of the initial
//! state, which the run reports as a warning and then pushes apart.

use super::time::time_value;
use crate::dynamics::{Blowup, Partner, World};
use std::fmt;

/// How many times the energy that could be in motion may be created before the run counts as
/// blown up.
pub const ENERGY_GROWTH: f64 = 10.0;

/// Farthest coordinate (|x| or |y|) of a body, in units of the smallest size: the case reader's
/// limit (`scene::ranges`, which reads this constant; its size of a shape is at most twice the
/// inscribed radius, which the run's watch takes, so that no state the reader accepts trips the
/// watch).
pub const MAX_EXTENT_RATIO: f64 = 1e9;

/// Steps between two scans of the positions for a body beyond [`MAX_EXTENT_RATIO`].
pub const EXTENT_EVERY: u64 = 64;

/// Deepest overlap accepted during a run, in units of the smaller inscribed radius of the pair.
pub const DEPTH_LIMIT: f64 = 2.0;

/// What a check found.
#[derive(Clone, Debug, PartialEq)]
pub enum Trigger {
    /// An energy is not finite.
    NonFinite(&'static str),
    /// Energy created beyond what the initial state, gravity and the boundaries supply.
    Energy { created: f64, available: f64 },
    /// An overlap deeper than the bodies (in units of the smaller inscribed radius).
    Depth { ratio: f64 },
    /// A periodic side following a stress shrank to the least the model allows
    /// ([`World::cell_below_limit`]): `side` 0 for x, 1 for y.
    CellLimit { side: usize, size: f64, least: f64 },
    /// A body beyond the resolvable extent: its coordinate and the limit (cm).
    Escaped {
        body: usize,
        coordinate: f64,
        limit: f64,
    },
}

/// The cell's limit, checked after every step whether or not the watch is on: beyond it the
/// model itself fails, not the physics ([`World::cell_below_limit`]).
pub fn cell_limit(world: &World) -> Option<Trigger> {
    world
        .cell_below_limit()
        .map(|(side, size, least)| Trigger::CellLimit { side, size, least })
}

/// The state a run is checked against (public: the run's saved progress carries it, so that a
/// continued run is checked against the start of the whole run).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlowupWatch {
    /// Kinetic, elastic, potential and total energy at the start.
    pub kinetic0: f64,
    pub elastic0: f64,
    pub potential0: f64,
    pub total0: f64,
    /// Most energy gravity has supplied so far, `max (P₀ − P)`.
    pub gravity_supplied: f64,
    /// Most work the walls have done so far, `max W`.
    pub boundary_supplied: f64,
    /// Most energy dissipated so far, `max D` (from the start of this run's watching).
    pub dissipated_max: f64,
    /// Deepest overlap accepted (in units of the smaller inscribed radius of the pair).
    pub depth_limit: f64,
}

impl BlowupWatch {
    /// Starts watching from the world's current (initial) state.
    pub fn new(world: &World) -> Self {
        let e = world.energies;
        BlowupWatch {
            kinetic0: e.kinetic,
            elastic0: e.elastic,
            potential0: e.potential,
            // (The work a state already holds was done before: see `Simulation::new`.)
            total0: e.total() - e.boundary_work,
            gravity_supplied: 0.0,
            boundary_supplied: 0.0,
            dissipated_max: e.dissipated,
            depth_limit: DEPTH_LIMIT.max(world.diagnostics.max_depth_ratio),
        }
    }

    /// The energy that could be in motion, as of the last check: the initial kinetic and
    /// elastic energy, the most gravity and the walls have supplied. (Cohesion stores a
    /// negative energy, `−c A`: the initial elastic energy counts by its size, the binding
    /// energy held now by [`BlowupWatch::check`]; both are the spring energy alone without it.)
    pub fn available(&self) -> f64 {
        self.kinetic0 + self.elastic0.abs() + self.gravity_supplied + self.boundary_supplied
    }

    /// Checks the world after a step; O(1).
    pub fn check(&mut self, world: &World) -> Option<Trigger> {
        let e = world.energies;
        for (name, v) in [
            ("kinetic energy", e.kinetic),
            ("potential energy", e.potential),
            ("elastic energy", e.elastic),
            ("dissipated energy", e.dissipated),
        ] {
            if !v.is_finite() {
                return Some(Trigger::NonFinite(name));
            }
        }
        // Work done on the bodies by moving walls: created energy is `E − E₀ − W`, and the most
        // work they have done so far is available.
        if !e.boundary_work.is_finite() {
            return Some(Trigger::NonFinite("work of the walls"));
        }
        self.boundary_supplied = self.boundary_supplied.max(e.boundary_work);
        self.gravity_supplied = self.gravity_supplied.max(self.potential0 - e.potential);
        // (A cohesive contact's binding energy can be set in motion too.)
        let available = self.available() + (-e.elastic).max(0.0);
        self.dissipated_max = self.dissipated_max.max(e.dissipated);
        let created =
            e.total() - self.total0 - e.boundary_work + (self.dissipated_max - e.dissipated);
        // The rounding of the sums that form the totals (the potential can dwarf the rest).
        let rounding = 1e-9
            * (self.potential0.abs()
                + e.potential.abs()
                + e.kinetic
                + e.elastic.abs()
                + e.dissipated.abs()
                + self.dissipated_max.abs()
                + e.boundary_work.abs()
                + self.kinetic0
                + self.elastic0.abs());
        if created > ENERGY_GROWTH * available + rounding {
            return Some(Trigger::Energy { created, available });
        }
        let ratio = world.diagnostics.max_depth_ratio;
        if ratio > self.depth_limit || ratio.is_nan() {
            return Some(Trigger::Depth { ratio });
        }
        if world.step.is_multiple_of(EXTENT_EVERY) {
            return escaped(world);
        }
        None
    }
}

/// The body farthest beyond [`MAX_EXTENT_RATIO`] × the smallest width (twice the smallest
/// inscribed radius), if any.
pub fn escaped(world: &World) -> Option<Trigger> {
    let b = &world.bodies;
    let smallest = b
        .shape
        .iter()
        .map(|s| s.inscribed_radius())
        .fold(f64::INFINITY, f64::min);
    let limit = MAX_EXTENT_RATIO * 2.0 * smallest;
    let (body, coordinate) = b
        .state
        .iter()
        .map(|s| s.pose.position.x.abs().max(s.pose.position.y.abs()))
        .enumerate()
        .max_by(|a, c| a.1.total_cmp(&c.1))?;
    (coordinate > limit).then_some(Trigger::Escaped {
        body,
        coordinate,
        limit,
    })
}

/// The body with the largest kinetic energy (a non-finite one first).
pub fn most_energetic_body(world: &World) -> usize {
    let b = &world.bodies;
    let energy = |k: usize| {
        let e = 0.5 * b.mass[k] * b.state[k].vel.norm_squared()
            + 0.5 * b.inertia[k] * b.state[k].omega * b.state[k].omega;
        if e.is_finite() { e } else { f64::INFINITY }
    };
    (0..b.len())
        .max_by(|&i, &j| energy(i).total_cmp(&energy(j)))
        .unwrap_or(0)
}

/// An overlapping pair: `i` a body, `j` a body or (`wall`) a wall index; the depth and its
/// ratio to the smaller inscribed radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlap {
    pub i: usize,
    pub j: usize,
    pub wall: bool,
    pub depth: f64,
    pub ratio: f64,
}

impl Overlap {
    /// `bodies 3 and 7` or `body 3 and wall 0`.
    pub fn names(&self) -> String {
        if self.wall {
            format!("body {} and wall {}", self.i, self.j)
        } else {
            format!("bodies {} and {}", self.i, self.j)
        }
    }
}

/// Every overlapping pair of the last evaluation, deepest (by ratio) first. Needs the contact
/// extras refreshed ([`World::refresh_contact_extras`]).
pub fn overlaps(world: &World) -> Vec<Overlap> {
    let shapes = &world.bodies.shape;
    let mut out: Vec<Overlap> = world
        .contacts
        .active()
        .filter(|c| c.extra.depth > 0.0)
        .map(|c| {
            let i = c.slot.i as usize;
            let (wall, j) = match c.slot.partner() {
                Partner::Wall(w) => (true, w),
                Partner::Body(j) => (false, j),
            };
            let mut scale = shapes[i].inscribed_radius();
            if !wall {
                scale = scale.min(shapes[j].inscribed_radius());
            }
            Overlap {
                i,
                j,
                wall,
                depth: c.extra.depth,
                ratio: c.extra.depth / scale,
            }
        })
        .collect();
    out.sort_by(|a, b| b.ratio.total_cmp(&a.ratio));
    out
}

/// A blow-up: where it was found and why.
#[derive(Clone, Debug, PartialEq)]
pub struct BlowupReport {
    /// The step at which it was found (the world's state is that step's: a step that stopped
    /// part-way on a non-finite value leaves the state where it stopped).
    pub step: u64,
    pub time: f64,
    /// The body most concerned (the most energetic one, or one of the pair that overlaps).
    pub body: usize,
    pub reason: String,
    /// Found inside the step, on a non-finite value ([`Blowup`]): the world's state is partly
    /// that step's, and not finite.
    pub within_step: bool,
}

impl fmt::Display for BlowupReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "blow-up at step {} (t = {}), body {}: {}",
            self.step, self.time, self.body, self.reason
        )
    }
}

impl std::error::Error for BlowupReport {}

impl BlowupReport {
    /// A non-finite state found inside a step.
    pub fn within_step(b: &Blowup, world: &World) -> BlowupReport {
        BlowupReport {
            step: b.step,
            time: time_value(b.step, world.dt),
            body: b.body,
            reason: format!(
                "non-finite {} (the state written last is where the step stopped)",
                b.what
            ),
            within_step: true,
        }
    }

    /// A trigger of the watch after the world's last step, with the body it concerns (an
    /// overlap's: the contact extras are refreshed to find it).
    pub fn of_trigger(trigger: Trigger, world: &mut World) -> BlowupReport {
        let (body, reason) = match trigger {
            Trigger::NonFinite(what) => (most_energetic_body(world), format!("non-finite {what}")),
            Trigger::Energy { created, available } => (
                most_energetic_body(world),
                format!(
                    "the energy grew by {created:.3e} erg, more than {ENERGY_GROWTH} × the \
                     {available:.3e} erg that the initial state and gravity can supply (the step \
                     is unstable: is dt above the critical step, or a stiffness far above what dt \
                     can follow?)"
                ),
            ),
            Trigger::Escaped {
                body,
                coordinate,
                limit,
            } => (
                body,
                format!(
                    "it is {coordinate:.3e} cm from the origin, beyond {MAX_EXTENT_RATIO:e} × the \
                     smallest body's width ({limit:.3e} cm), the farthest a case or a state \
                     file may place a body: positions there no longer resolve the bodies (a \
                     velocity or a force far beyond what the scene can give?)"
                ),
            ),
            Trigger::Depth { ratio } => {
                world.refresh_contact_extras();
                match overlaps(world).first() {
                    Some(o) => (
                        o.i,
                        format!(
                            "{} overlap by δ = {:.3e}, {:.3} × the smaller inscribed radius: \
                             deeper than the bodies themselves (the contact is too soft for the \
                             impact, or dt too large)",
                            o.names(),
                            o.depth,
                            o.ratio
                        ),
                    ),
                    None => (
                        most_energetic_body(world),
                        format!(
                            "an overlap reached {ratio:.3} × the smaller inscribed radius: \
                             deeper than the bodies themselves"
                        ),
                    ),
                }
            }
            Trigger::CellLimit { side, size, least } => {
                let axis = ["x", "y"][side];
                let p = world.cell.and_then(|c| match c.control[side] {
                    Some(crate::dynamics::cell::SideControl::Stress(p)) => Some(p),
                    _ => None,
                });
                (
                    most_energetic_body(world),
                    format!(
                        "the periodic cell's {axis} side shrank to {size:.6e} cm, not above twice \
                         the reach of a pair ({least:.6e} cm: two largest bounding diameters and \
                         the neighbour list's skin): a body would meet two images of another, or \
                         its own, and only the nearest is modelled. The bodies cannot carry the \
                         imposed stress or strain{} in a cell this small: give the cell more \
                         bodies (or smaller ones), or a lower stress",
                        p.map_or(String::new(), |p| format!(" ({} dyn/cm)", p.target))
                    ),
                )
            }
        };
        BlowupReport {
            step: world.step,
            time: time_value(world.step, world.dt),
            body,
            reason,
            within_step: false,
        }
    }
}

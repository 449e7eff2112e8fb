//! The world: bodies, walls, gravity, the contact law, time, and the running energy account.

use super::body::{Bodies, BodyInit};
use super::broad_phase::Grid;
use super::contacts::ContactList;
use crate::contact_law::ContactSpec;
use crate::geometry::{Vec2, Wall};

/// A wall and the contact parameters of contacts with it (the scene's, or its own overrides).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallSpec {
    pub wall: Wall,
    pub spec: ContactSpec,
}

/// Energies of the system, per unit thickness.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// `Σ ½ m v² + ½ I ω²`.
    pub kinetic: f64,
    /// `Σ −m g·x` (zero at the origin).
    pub potential: f64,
    /// Energy stored in the contact springs now.
    pub elastic: f64,
    /// Energy taken out by dashpots and sliding so far (including springs' energy lost when a
    /// contact opens).
    pub dissipated: f64,
}

impl Energies {
    /// Kinetic + potential + elastic + dissipated: constant in exact arithmetic.
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential + self.elastic + self.dissipated
    }
}

/// Counters a run reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Diagnostics {
    /// Largest `δ / (smaller inscribed radius of the pair)` seen.
    pub max_depth_ratio: f64,
    /// Contact-steps in the `deep` (four crossings) fallback.
    pub deep_contacts: u64,
    /// Contact-steps in the `contained` fallback.
    pub contained_contacts: u64,
    /// Smallest critical time step of the contact network sampled so far (∞ before any contact;
    /// see [`World::network_critical_dt`]).
    pub dt_critical_observed: f64,
}

/// Everything the step function evolves.
#[derive(Clone, Debug)]
pub struct World {
    pub bodies: Bodies,
    pub walls: Vec<WallSpec>,
    pub gravity: Vec2,
    /// The contact law between bodies (and with walls that do not override it).
    pub spec: ContactSpec,
    pub dt: f64,
    pub time: f64,
    pub step: u64,
    pub contacts: ContactList,
    pub energies: Energies,
    pub diagnostics: Diagnostics,
    /// Mean |Δx|, |Δy|, |Δθ| over bodies during the last step (P's quiescence measure).
    pub last_increments: [f64; 3],
    pub(crate) grid: Grid,
    pub(crate) candidates: Vec<(u32, u32)>,
}

impl World {
    /// A world at t = 0; the forces of the initial configuration are evaluated at once (the first
    /// half-kick needs them).
    pub fn new(
        bodies: &[BodyInit],
        walls: Vec<WallSpec>,
        gravity: Vec2,
        spec: ContactSpec,
        dt: f64,
    ) -> Self {
        let mut w = World {
            bodies: Bodies::new(bodies),
            walls,
            gravity,
            spec,
            dt,
            time: 0.0,
            step: 0,
            contacts: ContactList::default(),
            energies: Energies::default(),
            diagnostics: Diagnostics {
                dt_critical_observed: f64::INFINITY,
                ..Default::default()
            },
            last_increments: [0.0; 3],
            grid: Grid::default(),
            candidates: Vec::new(),
        };
        w.evaluate_forces();
        w.energies.kinetic = w.kinetic_energy();
        w.energies.potential = w.potential_energy();
        w
    }

    /// `Σ ½ m v² + ½ I ω²`.
    pub fn kinetic_energy(&self) -> f64 {
        let b = &self.bodies;
        (0..b.len())
            .map(|k| {
                0.5 * b.mass[k] * b.vel[k].norm_squared()
                    + 0.5 * b.inertia[k] * b.omega[k] * b.omega[k]
            })
            .sum()
    }

    /// `Σ −m g·x`.
    pub fn potential_energy(&self) -> f64 {
        let b = &self.bodies;
        (0..b.len())
            .map(|k| -b.mass[k] * self.gravity.dot(&b.pose[k].position))
            .sum()
    }

    /// Total linear momentum `Σ m v`.
    pub fn momentum(&self) -> Vec2 {
        let b = &self.bodies;
        (0..b.len()).map(|k| b.vel[k] * b.mass[k]).sum()
    }

    /// Total angular momentum about the origin, `Σ (I ω + m x × v)`.
    pub fn angular_momentum(&self) -> f64 {
        let b = &self.bodies;
        (0..b.len())
            .map(|k| {
                let (x, v) = (b.pose[k].position, b.vel[k]);
                b.inertia[k] * b.omega[k] + b.mass[k] * (x.x * v.y - x.y * v.x)
            })
            .sum()
    }
}

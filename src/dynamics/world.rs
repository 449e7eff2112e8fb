//! The world: bodies, walls, gravity, the contact law, time, and the running energy account.

use super::body::{Bodies, BodyInit};
pub use super::boundary::WallSpec;
use super::broad_phase::Grid;
use super::contacts::ContactList;
use crate::contact_law::ContactSpec;
use crate::geometry::Vec2;

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
    /// Work done on the bodies by moving walls so far (see [`super::boundary`]).
    pub boundary_work: f64,
}

impl Energies {
    /// Kinetic + potential + elastic + dissipated: in exact arithmetic, its initial value plus
    /// the walls' work [`Energies::boundary_work`].
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
    /// Scratch of the neighbour-list build (the grid's body pairs).
    pub(crate) pair_scratch: Vec<(u32, u32)>,
    /// Per-chunk partial results of the parallel passes (see `step`).
    pub(crate) body_partials: Vec<super::step::BodyPartial>,
    pub(crate) slot_partials: Vec<super::step::SlotPartial>,
    /// Per chunk of slots, per wall: the wall's contacts' sums (see `step`).
    pub(crate) wall_partials: Vec<super::boundary::WallLoad>,
    /// The density of every body when they all have the same (checked at each list build).
    pub(crate) uniform_density: Option<f64>,
    /// Laws resolved once per step when every pair of a kind has the same (see `step`).
    pub(crate) law_cache: Vec<crate::contact_law::Law>,
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
            pair_scratch: Vec::new(),
            body_partials: Vec::new(),
            slot_partials: Vec::new(),
            wall_partials: Vec::new(),
            uniform_density: None,
            law_cache: Vec::new(),
        };
        w.evaluate_forces();
        w.update_servos();
        w.energies.kinetic = w.kinetic_energy();
        w.energies.potential = w.potential_energy();
        w
    }

    /// `Σ ½ m v² + ½ I ω²`.
    pub fn kinetic_energy(&self) -> f64 {
        let b = &self.bodies;
        (0..b.len())
            .map(|k| {
                0.5 * b.mass[k] * b.state[k].vel.norm_squared()
                    + 0.5 * b.inertia[k] * b.state[k].omega * b.state[k].omega
            })
            .sum()
    }

    /// `Σ −m g·x`.
    pub fn potential_energy(&self) -> f64 {
        let b = &self.bodies;
        (0..b.len())
            .map(|k| -b.mass[k] * self.gravity.dot(&b.state[k].pose.position))
            .sum()
    }

    /// Total linear momentum `Σ m v`.
    pub fn momentum(&self) -> Vec2 {
        let b = &self.bodies;
        (0..b.len()).map(|k| b.state[k].vel * b.mass[k]).sum()
    }

    /// Total angular momentum about the origin, `Σ (I ω + m x × v)`.
    pub fn angular_momentum(&self) -> f64 {
        let b = &self.bodies;
        (0..b.len())
            .map(|k| {
                let (x, v) = (b.state[k].pose.position, b.state[k].vel);
                b.inertia[k] * b.state[k].omega + b.mass[k] * (x.x * v.y - x.y * v.x)
            })
            .sum()
    }
}

/// Heap bytes held by a vector (its capacity, not its length).
fn held<T>(v: &Vec<T>) -> usize {
    v.capacity() * std::mem::size_of::<T>()
}

impl World {
    /// Heap bytes the world holds, by part (capacities): bodies, neighbour-list slots and their
    /// contact data, the per-body adjacency, the grid and the build's scratch.
    pub fn heap_breakdown(&self) -> [(&'static str, usize); 5] {
        let b = &self.bodies;
        let c = &self.contacts;
        let bodies = held(&b.shape)
            + held(&b.density)
            + held(&b.mass)
            + held(&b.inv_mass)
            + held(&b.inertia)
            + held(&b.inv_inertia)
            + held(&b.bound)
            + held(&b.area_radius)
            + held(&b.state)
            + held(&b.is_circle)
            + held(&b.force)
            + held(&b.torque);
        [
            ("bodies", bodies),
            (
                "slots and contact data",
                held(&c.slots) + held(&c.data) + held(&c.extra) + held(&c.warm),
            ),
            (
                "adjacency",
                held(&c.adjacency) + held(&c.adjacency_start) + held(&c.adjacency_fill),
            ),
            ("grid", self.grid.heap_bytes()),
            (
                "build scratch",
                held(&c.keys)
                    + held(&self.wall_partials)
                    + held(&c.rebuilt)
                    + held(&c.rebuilt_warm)
                    + held(&c.built_at)
                    + held(&self.pair_scratch),
            ),
        ]
    }
}

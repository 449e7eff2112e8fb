//! The running account of a run: its energies and its diagnostic counters (written by the step,
//! read by the watch and the outputs).

use super::body::Bodies;
use super::boundary::Boundary;
use super::contact_pass::SlotPartial;
use std::fmt;
use std::time::Instant;

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
    /// Work done on the bodies by moving walls (see [`super::boundary`]) and by bodies whose
    /// motion is prescribed (see [`super::body::Bodies`]) so far.
    pub boundary_work: f64,
}

impl Energies {
    /// Kinetic + potential + elastic + dissipated: in exact arithmetic, its initial value plus
    /// the walls' work [`Energies::boundary_work`].
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential + self.elastic + self.dissipated
    }

    /// A step's energy flows (the step's stage 5), `dt` its length. Verlet applies the forces
    /// of time level n+1 over the interval centred on it, so their work is taken with the
    /// velocities at n+1 (after the second kick): the contacts take out the power
    /// `non_elastic_power` of the non-elastic forces, summed body by body (`Σ_c f·v_rel =
    /// Σ_k F_k·v_k + M_k ω_k − Σ_walls F_w·v_w`), less the change of the history springs'
    /// energy (`slots`). A moving wall does the work `F_w·v_w` (see [`super::boundary`]), and
    /// so does the seam of a Lees–Edwards cell (see [`super::cell`]).
    pub(crate) fn account_step(
        &mut self,
        dt: f64,
        walls: &[Boundary],
        bodies: &Bodies,
        slots: &SlotPartial,
        non_elastic_power: f64,
    ) {
        if walls.iter().any(Boundary::moves) || slots.image_power != 0.0 {
            let (mut power, mut power_ne) = (slots.image_power, slots.image_power_ne);
            for ws in walls {
                // A turning boundary adds ω Σ (x_c − P) × F_c (see `boundary::Turn`).
                let omega = ws.omega();
                power += ws.load.force.dot(&ws.velocity) + omega * ws.load.torque;
                power_ne += ws.load.force_non_elastic.dot(&ws.velocity)
                    + omega * ws.load.torque_non_elastic;
            }
            self.dissipated -= (non_elastic_power - power_ne) * dt + slots.history_energy_change;
            self.boundary_work += power * dt;
        } else {
            self.dissipated -= non_elastic_power * dt + slots.history_energy_change;
        }
        // A prescribed body does work on the scene, as a moving wall: the power of its
        // contacts' forces on the others, `−(F·v + M ω)` with F, M its contacts' force and
        // moment on it (it has no weight) and v, ω its prescribed motion. Its own contacts'
        // dissipation is in the bodies' sum, which holds its velocity.
        if !bodies.prescribed.is_empty() {
            let b = bodies;
            let power: f64 = b
                .prescribed
                .iter()
                .map(|&k| -(b.force[k].dot(&b.state[k].vel) + b.torque[k] * b.state[k].omega))
                .sum();
            self.boundary_work += power * dt;
        }
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

/// A non-finite state: the step and the body where it was found.
#[derive(Clone, Debug, PartialEq)]
pub struct Blowup {
    pub step: u64,
    pub time: f64,
    pub body: usize,
    pub what: &'static str,
}

impl fmt::Display for Blowup {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "non-finite {} of body {} at step {} (t = {}): the simulation blew up (is dt far above dt_critical?)",
            self.what, self.body, self.step, self.time
        )
    }
}

impl std::error::Error for Blowup {}

/// What one step measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepReport {
    /// Mean over bodies of |Δx|, |Δy|, |Δθ| during the step (P's quiescence measure).
    pub increments: [f64; 3],
    /// Number of contacts after the step.
    pub contacts: usize,
}

/// Wall-clock seconds a world's steps have spent in each stage (see [`super::step`]): where the
/// time goes, and what runs serially. The kick–drift, contact and gather passes run in parallel
/// (each but for a sum over its chunks); list builds and the rest (the sums of the partials,
/// the walls, the account) run on one thread. A diagnostic: no result depends on it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// Kick and drift (stages 1–2).
    pub drift: f64,
    /// Neighbour-list builds.
    pub list_builds: f64,
    /// The contact pass (stage 3).
    pub contacts: f64,
    /// Gathering each body's forces and the second kick (stage 4).
    pub gather: f64,
    /// Everything else: the partial sums, the walls' drift and servos, the account.
    pub rest: f64,
}

impl StageTimes {
    /// The seconds of all stages.
    pub fn total(&self) -> f64 {
        self.drift + self.list_builds + self.contacts + self.gather + self.rest
    }
}

/// A lap timer over the stages of one step: each [`Lap::to`] adds the time since the last to a
/// stage.
pub(crate) struct Lap(Instant);

impl Lap {
    pub fn start() -> Self {
        Lap(Instant::now())
    }

    /// Adds the seconds since the last lap to `stage`.
    pub fn to(&mut self, stage: &mut f64) {
        let now = Instant::now();
        *stage += (now - self.0).as_secs_f64();
        self.0 = now;
    }
}

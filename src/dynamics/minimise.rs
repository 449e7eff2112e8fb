//! Energy minimisation: FIRE, the fast inertial relaxation engine (Bitzek, Koskinen, Gähler,
//! Moseler & Gumbsch, PRL 97 (2006) 170201), in the form of FIRE 2.0 (Guénolé et al., Comput.
//! Mater. Sci. 175 (2020) 109584: semi-implicit Euler, the velocity mixed after the kick, half a
//! step back on uphill motion), on every body's position and angle.
//!
//! The forces are the contact law's at rest: the bodies' velocities are held at zero while the
//! forces are evaluated, so dashpots give nothing and the force is the law's elastic part (and
//! gravity). A frictionless law is required — a Coulomb slider's force depends on the path, not
//! on the configuration, so there is no energy to minimise; [`relax`] refuses a law with friction
//! or rolling resistance. Under the area law (and Hertz) the forces derive from the contacts'
//! stored energy, which FIRE then minimises with gravity's potential; under the depth law of a
//! non-circular pair the contact torque is not the derivative of an energy, and FIRE finds a
//! force and moment balance. Walls stay where they are (a moving or servo wall is not moved),
//! and so do prescribed bodies (their velocity is theirs again afterwards); a periodic cell keeps
//! its size and shift.
//!
//! Mixed translations and rotations are weighted by the bodies' masses and moments of inertia:
//! the mixing `v ← (1 − α) v + α |v|_M M⁻¹F / |F|_{M⁻¹}` uses the norms `|v|_M² = Σ m v² + I ω²`
//! and `|F|²_{M⁻¹} = Σ F²/m + M²/I`, which keep its units (a velocity) and make it independent
//! of the length unit of the angles.

use super::World;
use crate::geometry::{Pose, Vec2};

/// FIRE's parameters (FIRE 2.0's defaults, Guénolé et al. 2020, Table 1), the time step a
/// multiple of the case's `dt`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fire {
    /// Initial step, as a multiple of the case's `dt`.
    pub dt_start: f64,
    /// Largest step, as a multiple of the case's `dt`.
    pub dt_max: f64,
    /// Smallest step, as a multiple of the case's `dt`.
    pub dt_min: f64,
    /// Steps downhill before the step may grow.
    pub n_delay: u32,
    /// Factors of the step's growth and shrinkage.
    pub f_inc: f64,
    pub f_dec: f64,
    /// Initial mixing and its decay.
    pub alpha_start: f64,
    pub f_alpha: f64,
}

impl Default for Fire {
    fn default() -> Self {
        Fire {
            dt_start: 1.0,
            dt_max: 10.0,
            dt_min: 0.02,
            n_delay: 5,
            f_inc: 1.1,
            f_dec: 0.5,
            alpha_start: 0.25,
            f_alpha: 0.99,
        }
    }
}

/// When a minimisation stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    /// The residual force ([`Relaxed::residual`]) below which the bodies are at rest.
    pub force: f64,
    /// The most iterations (force evaluations) taken.
    pub max_iterations: u64,
    /// A potential energy (erg) at or below which the bodies count as at rest too (0: none;
    /// with neither gravity nor walls, a packing whose energy falls this low is unjammed, which
    /// FIRE otherwise approaches only slowly).
    pub energy: f64,
    /// A change of the potential energy over the last [`STALL_WINDOW`] iterations, as a
    /// fraction of it, below which the minimisation has stalled and stops, if the residual
    /// has not fallen by half over them either (0: never) — the form
    /// of O'Hern et al.'s second criterion (PRE 68 (2003) 011306: the energy's change between
    /// iterations), for packings whose soft modes FIRE relaxes only slowly (ellipses near
    /// jamming, where the residual force falls little while the energy hardly changes).
    pub stall: f64,
}

/// The iterations over which [`Tolerance::stall`] compares the potential energy.
pub const STALL_WINDOW: u64 = 1000;

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            force: 1e-9,
            max_iterations: 1_000_000,
            energy: 0.0,
            stall: 0.0,
        }
    }
}

/// How a minimisation ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Relaxed {
    /// Force evaluations taken.
    pub iterations: u64,
    /// The residual force: the largest out-of-balance force on a body, `|F| + |M|/r` (r its
    /// bounding radius), over the mean magnitude of the forces acting on a body (Σ |f| over its
    /// contacts plus its weight); 0 where nothing acts.
    pub residual: f64,
    /// The potential energy at the end: the contacts' stored energy plus gravity's (erg).
    pub potential: f64,
    /// The residual fell below the tolerance (or the energy below its floor).
    pub converged: bool,
    /// The energy stalled ([`Tolerance::stall`]) before the residual fell below the tolerance.
    pub stalled: bool,
}

/// Why a world cannot be minimised.
#[derive(Clone, Debug, PartialEq)]
pub enum RelaxError {
    /// A contact law with friction or rolling resistance (`"scene"` or a wall's index).
    Friction(String),
    /// A non-finite position or force arose at this iteration (body).
    NonFinite { iteration: u64, body: usize },
}

impl std::fmt::Display for RelaxError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RelaxError::Friction(whose) => write!(
                f,
                "`{whose}.friction`: energy minimisation needs a frictionless law (friction 0, no \
                 rolling resistance): a Coulomb slider's force depends on the path, not on the \
                 configuration"
            ),
            RelaxError::NonFinite { iteration, body } => write!(
                f,
                "iteration {iteration}: body {body} reached a non-finite position or force"
            ),
        }
    }
}

impl std::error::Error for RelaxError {}

/// Checks that `world`'s laws are frictionless (see the module documentation).
pub fn check_frictionless(world: &World) -> Result<(), RelaxError> {
    let rough = crate::contact_law::ContactSpec::path_dependent;
    if rough(&world.spec) {
        return Err(RelaxError::Friction("contact".into()));
    }
    if let Some(k) = world.walls.iter().position(|w| rough(&w.spec)) {
        return Err(RelaxError::Friction(format!("walls[{k}].contact")));
    }
    Ok(())
}

/// The residual force of the forces last evaluated (see [`Relaxed::residual`]).
pub fn residual(world: &World) -> f64 {
    let b = &world.bodies;
    let n = b.len();
    if n == 0 {
        return 0.0;
    }
    let g = world.gravity.norm();
    let mut acting: f64 = b.mass.iter().map(|m| m * g).sum();
    let list = &world.contacts;
    for (s, d) in list.slots.iter().zip(&list.data) {
        if s.active {
            // On both sides (a wall's side is not a body).
            let f = d.force.norm();
            acting += if s.is_wall() { f } else { 2.0 * f };
        }
    }
    let mean = acting / n as f64;
    if mean == 0.0 {
        return 0.0;
    }
    // (A prescribed body's force is the reaction it exerts, not out of balance.)
    let worst = (0..n)
        .filter(|&k| !b.is_prescribed(k))
        .map(|k| b.force[k].norm() + b.torque[k].abs() / b.bound[k])
        .fold(0.0f64, f64::max);
    worst / mean
}

/// Minimises the potential energy of `world` by FIRE from its present configuration, until the
/// residual force falls below `tol.force`, the energy stalls (`tol.stall`) or `tol.max_iterations` evaluations; leaves the world
/// at the configuration reached, at rest, with its forces and energies evaluated there.
pub fn relax(world: &mut World, fire: &Fire, tol: &Tolerance) -> Result<Relaxed, RelaxError> {
    check_frictionless(world)?;
    let n = world.bodies.len();
    let prescribed: Vec<(usize, Vec2, f64)> = world
        .bodies
        .prescribed
        .iter()
        .map(|&k| (k, world.bodies.state[k].vel, world.bodies.state[k].omega))
        .collect();
    for s in &mut world.bodies.state {
        s.vel = Vec2::zeros();
        s.omega = 0.0;
    }
    // FIRE's own velocities (the world's stay zero: no dashpot acts).
    let mut v = vec![Vec2::zeros(); n];
    let mut w = vec![0.0f64; n];
    let dt0 = world.dt;
    let (mut dt, mut alpha, mut downhill) = (fire.dt_start * dt0, fire.alpha_start, 0u32);
    let mut iterations = 0u64;
    let (mut window_start, mut stalled) = ((f64::INFINITY, f64::INFINITY), false);
    world.evaluate_forces();
    loop {
        let r = residual(world);
        let b = &world.bodies;
        if let Some(k) = (0..n).find(|&k| !(b.force[k].norm() + b.torque[k].abs()).is_finite()) {
            return Err(RelaxError::NonFinite {
                iteration: iterations,
                body: k,
            });
        }
        let potential = world.energies.elastic + world.potential_energy();
        let low = tol.energy > 0.0 && potential <= tol.energy;
        if iterations.is_multiple_of(STALL_WINDOW) {
            // Neither the energy nor the residual moving: a residual that still falls (by half
            // over the window) is converging, however little the energy changes.
            stalled = iterations > 0
                && (window_start.0 - potential).abs() < tol.stall * potential.abs()
                && r > 0.5 * window_start.1;
            window_start = (potential, r);
        }
        let converged = r < tol.force || low;
        if converged || stalled || iterations >= tol.max_iterations {
            for &(k, v, w) in &prescribed {
                world.bodies.state[k].vel = v;
                world.bodies.state[k].omega = w;
            }
            world.energies.kinetic = 0.0;
            world.energies.potential = world.potential_energy();
            return Ok(Relaxed {
                iterations,
                residual: r,
                potential: world.energies.elastic + world.energies.potential,
                converged,
                stalled: stalled && !converged,
            });
        }
        // The power of the forces on FIRE's velocities.
        let power: f64 = (0..n)
            .map(|k| b.force[k].dot(&v[k]) + b.torque[k] * w[k])
            .sum();
        if power > 0.0 {
            downhill += 1;
            if downhill > fire.n_delay {
                dt = (dt * fire.f_inc).min(fire.dt_max * dt0);
                alpha *= fire.f_alpha;
            }
        } else {
            // Uphill: back half a step, stop, and start again more carefully.
            downhill = 0;
            dt = (dt * fire.f_dec).max(fire.dt_min * dt0);
            alpha = fire.alpha_start;
            move_bodies(world, &v, &w, -0.5 * dt);
            v.fill(Vec2::zeros());
            w.fill(0.0);
        }
        // Semi-implicit Euler: kick, mix, drift.
        let b = &world.bodies;
        for k in 0..n {
            v[k] += b.force[k] * (dt * b.inv_mass[k]);
            w[k] += b.torque[k] * dt * b.inv_inertia[k];
        }
        let (mut v_norm, mut f_norm) = (0.0, 0.0);
        for k in 0..n {
            v_norm += b.mass[k] * v[k].norm_squared() + b.inertia[k] * w[k] * w[k];
            f_norm += b.force[k].norm_squared() * b.inv_mass[k]
                + b.torque[k] * b.torque[k] * b.inv_inertia[k];
        }
        if f_norm > 0.0 {
            let scale = alpha * (v_norm / f_norm).sqrt();
            for k in 0..n {
                v[k] = v[k] * (1.0 - alpha) + b.force[k] * (scale * b.inv_mass[k]);
                w[k] = w[k] * (1.0 - alpha) + b.torque[k] * scale * b.inv_inertia[k];
            }
        }
        move_bodies(world, &v, &w, dt);
        world.evaluate_forces_near();
        iterations += 1;
    }
}

/// Moves every body by `h` times its FIRE velocity, bringing it back into a periodic cell.
fn move_bodies(world: &mut World, v: &[Vec2], w: &[f64], h: f64) {
    let cell = world.cell;
    let b = &mut world.bodies;
    for k in 0..b.len() {
        let s = &mut b.state[k];
        let mut pos = s.pose.position + v[k] * h;
        if let Some(c) = cell
            && let Some(wrapped) = c.wrap(pos, Vec2::zeros())
        {
            pos = wrapped.position;
            let im = &mut b.image[k];
            im[0] += wrapped.images[0];
            im[1] += wrapped.images[1];
        }
        let angle = s.pose.angle() + w[k] * h;
        b.state[k].pose = Pose::new(pos, angle);
    }
}

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
//!
//! # The step and the stopping rules
//! - FIRE 2.0 (Guénolé et al. 2020, Algorithm 2) integrates `M ẍ = F` with semi-implicit Euler,
//!   which is stable for `Δt < 2/√λ_max`, λ_max the largest eigenvalue of the mass-weighted
//!   Hessian `M^{-1/2} H M^{-1/2}`. A step above it makes every move uphill (`P = F·v < 0`),
//!   and FIRE then halves the step and restarts the mixing at each reset: at a jamming
//!   threshold, where FIRE needs 10⁵–10⁶ iterations of large steps, that cycle keeps it from
//!   converging. The step is therefore held at [`STEP_SAFETY`] (0.8) of the stability bound
//!   `2/√λ_G`, with λ_G ≥ λ_max the block-Gershgorin bound of the contact network (see
//!   [`gershgorin_bound`]: per body the sum of its contacts' stiffnesses, mass- and
//!   lever-weighted), refreshed every [`STIFFNESS_EVERY`] iterations — as well as at
//!   [`Fire::dt_max`] times the case's `dt`.
//! - On an uphill move (`P ≤ 0`) the bodies go back half a step (`x ← x − ½ Δt v`, Guénolé et
//!   al. 2020, Algorithm 2, the line after the step's decrease), stop (`v ← 0`), the step is
//!   multiplied by `f_dec` and the mixing restarts at `α_start`.
//! - The residual force cannot fall below the round-off of the forces: a position of magnitude
//!   X is known to `ε X` (ε = 2⁻⁵², about 2.2e-16), so a contact of stiffness k carries a force
//!   error of about `k ε X`, and a body's net force that of its contacts together
//!   ([`Relaxed::round_off_residual`]). When over [`ROUND_OFF_WINDOW`] iterations the smallest
//!   residual has not halved and lies within [`ROUND_OFF_FACTOR`] of that level, the
//!   minimisation stops with [`Relaxed::round_off`] set: the configuration (the one of the
//!   smallest residual met) is the minimum as well as double precision resolves it. At a
//!   jamming threshold (256 disks, u ≈ 1e-12 k_n d², overlaps of 1e-6 of the diameter) that
//!   level is about 1e-8 — the residual LAMMPS's FIRE reaches there too.

use super::World;
use crate::geometry::{Pose, Vec2};
use std::sync::atomic::{AtomicI32, Ordering};

/// The fraction of the stability bound `2/√λ_G` the step is held at (see the module
/// documentation).
pub const STEP_SAFETY: f64 = 0.8;

/// Iterations between two evaluations of the stability bound (the contacts' stiffnesses are
/// evaluated again, about one force evaluation's cost).
pub const STIFFNESS_EVERY: u64 = 50;

/// The iterations over which the residual must halve before a residual near its round-off level
/// counts as stuck there.
pub const ROUND_OFF_WINDOW: u64 = 5000;

/// How far above its estimated round-off level ([`Relaxed::round_off_residual`]) a residual that
/// no longer falls counts as at that level.
pub const ROUND_OFF_FACTOR: f64 = 10.0;

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
    /// The residual stopped falling within [`ROUND_OFF_FACTOR`] of its round-off level before
    /// it reached the tolerance (see the module documentation).
    pub round_off: bool,
    /// The estimated round-off level of the residual at the end: the force error `ε` (2⁻⁵²)
    /// times `Σ (k X + |f|)` over a body's contacts (k a contact's stiffness, X the largest
    /// coordinate's magnitude, f its force), the largest over the bodies, over the same mean
    /// force as [`Relaxed::residual`].
    pub round_off_residual: f64,
    /// The signal (SIGINT 2, SIGTERM 15) that stopped the minimisation, if one did.
    pub signal: Option<i32>,
    /// The largest step allowed at the end (s): the smaller of `dt_max` and [`STEP_SAFETY`] of
    /// the stability bound.
    pub step_limit: f64,
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
/// residual force falls below `tol.force`, the energy stalls (`tol.stall`), the residual stops
/// falling at its round-off level, or `tol.max_iterations` evaluations; leaves the world at the
/// configuration reached, at rest, with its forces and energies evaluated there.
pub fn relax(world: &mut World, fire: &Fire, tol: &Tolerance) -> Result<Relaxed, RelaxError> {
    relax_until(world, fire, tol, None)
}

/// [`relax`], also stopping (after a whole iteration) once `stop` holds a non-zero signal
/// number: [`Relaxed::signal`] then says which, and the world is left at the configuration
/// reached, as at any other end.
pub fn relax_until(
    world: &mut World,
    fire: &Fire,
    tol: &Tolerance,
    stop: Option<&AtomicI32>,
) -> Result<Relaxed, RelaxError> {
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
    // The round-off watch: the smallest residual before this window and in it, the poses
    // where the smallest residual near the round-off level was met.
    let (mut best_before, mut best_now) = (f64::INFINITY, f64::INFINITY);
    let mut best_poses: Option<(f64, Vec<Pose>, Vec<[i32; 2]>)> = None;
    let (mut limit, mut floor) = (fire.dt_max * dt0, 0.0);
    world.evaluate_forces();
    loop {
        if iterations.is_multiple_of(STIFFNESS_EVERY) {
            let bound = gershgorin_bound(world);
            limit = fire.dt_max * dt0;
            if bound.lambda > 0.0 {
                limit = limit.min(STEP_SAFETY * 2.0 / bound.lambda.sqrt());
            }
            floor = bound.round_off;
            dt = dt.min(limit);
        }
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
        // The round-off watch (see the module documentation).
        best_now = best_now.min(r);
        if r <= ROUND_OFF_FACTOR * floor && best_poses.as_ref().is_none_or(|b| r < b.0) {
            let b = &world.bodies;
            best_poses = Some((r, b.state.iter().map(|s| s.pose).collect(), b.image.clone()));
        }
        let mut round_off = false;
        if iterations > 0 && iterations.is_multiple_of(ROUND_OFF_WINDOW) {
            round_off = best_now > 0.5 * best_before && best_now <= ROUND_OFF_FACTOR * floor;
            best_before = best_before.min(best_now);
            best_now = f64::INFINITY;
        }
        let converged = r < tol.force || low;
        let signal = stop.map(|s| s.load(Ordering::Relaxed)).filter(|&s| s != 0);
        if converged || stalled || round_off || signal.is_some() || iterations >= tol.max_iterations
        {
            let mut r = r;
            if round_off
                && !converged
                && let Some((best, poses, images)) = best_poses.take()
                && best < r
            {
                // Back to the smallest residual met at the round-off level.
                for (s, p) in world.bodies.state.iter_mut().zip(poses) {
                    s.pose = p;
                }
                world.bodies.image = images;
                world.evaluate_forces_near();
                r = residual(world);
            }
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
                round_off: round_off && !converged && !stalled,
                round_off_residual: floor,
                signal: if converged { None } else { signal },
                step_limit: limit,
            });
        }
        // The power of the forces on FIRE's velocities.
        let b = &world.bodies;
        let power: f64 = (0..n)
            .map(|k| b.force[k].dot(&v[k]) + b.torque[k] * w[k])
            .sum();
        if power > 0.0 {
            downhill += 1;
            if downhill > fire.n_delay {
                dt = (dt * fire.f_inc).min(limit);
                alpha *= fire.f_alpha;
            }
        } else {
            // Uphill: the step shrinks, the bodies go back half a (new) step and stop, and the
            // mixing starts again (Guénolé et al. 2020, Algorithm 2: `Δt ← Δt f_dec`,
            // `x ← x − ½ Δt v`, `v ← 0`).
            downhill = 0;
            dt = (dt * fire.f_dec).max(fire.dt_min * dt0).min(limit);
            alpha = fire.alpha_start;
            move_bodies(world, &v, &w, -0.5 * dt);
            v.fill(Vec2::zeros());
            w.fill(0.0);
        }
        // Semi-implicit Euler: kick, mix, drift (Guénolé et al. 2020, Algorithm 2 with the
        // semi-implicit Euler integrator, their Eq. 4: v ← v + Δt F/m, the mixing
        // v ← (1 − α) v + α |v| F/|F|, then x ← x + Δt v).
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

/// The block-Gershgorin bound of the contact network and the residual's round-off level (see
/// [`gershgorin_bound`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NetworkBound {
    /// An upper bound of the largest eigenvalue of the mass-weighted Hessian (1/s²).
    pub lambda: f64,
    /// The residual's round-off level ([`Relaxed::round_off_residual`]).
    pub round_off: f64,
}

/// An upper bound `λ_G` of the largest eigenvalue of the mass-weighted Hessian
/// `M^{-1/2} H M^{-1/2}` of the contact network at the present configuration, and the round-off
/// level of the residual there.
///
/// A contact of normal stiffness k (the law's, at its depth: [`World::refresh_contact_extras`])
/// between bodies i and j adds `k g_i g_iᵀ` to block (i, i), `k g_j g_jᵀ` to (j, j) and
/// `−k g_i g_jᵀ` to (i, j), with `g = (n/√m, (r × n)/√I)` (r the lever arm to the contact
/// point) the mass-weighted direction of the contact's normal for each body; its force f adds
/// the geometric stiffness `|f|/ℓ` (ℓ the distance between the centroids, through the contact
/// point) across the normal, the same way with the tangent t. Gershgorin's theorem for the
/// blocks (Feingold & Varga, Pacific J. Math. 12 (1962) 1241: every eigenvalue lies in a disc
/// of some block row, radius Σ_j ‖H_ij‖ about H_ii's spectrum) with the spectral norm
/// `‖k g_i g_jᵀ‖ = k |g_i| |g_j|` gives `λ_max ≤ max_i Σ_c k_c |g_i| (|g_i| + |g_j|)`.
pub fn gershgorin_bound(world: &mut World) -> NetworkBound {
    world.refresh_contact_extras();
    let cell = world.cell;
    let b = &world.bodies;
    let n = b.len();
    let mut row = vec![0.0f64; n];
    let mut noise = vec![0.0f64; n];
    // The largest coordinate's magnitude (a periodic cell's contact vectors are differences of
    // coordinates of up to its size).
    let mut x_max = b
        .state
        .iter()
        .map(|s| s.pose.position.abs().max())
        .fold(0.0f64, f64::max);
    if let Some(c) = &cell {
        x_max = x_max.max(c.size.abs().max());
    }
    let cross = |a: Vec2, c: Vec2| a.x * c.y - a.y * c.x;
    let lever = |body: usize, point: Vec2| {
        let r = point - b.state[body].pose.position;
        cell.as_ref().map_or(r, |c| c.shortest(r))
    };
    let g = |body: usize, r: Vec2, u: Vec2| {
        (b.inv_mass[body] + cross(r, u).powi(2) * b.inv_inertia[body]).sqrt()
    };
    let mut acting: f64 = b.mass.iter().map(|m| m * world.gravity.norm()).sum();
    for c in world.contacts.active() {
        let sides = c.sides();
        let (i, j) = (sides.receiver, sides.giving_body());
        let (k, nrm) = (f64::from(c.extra.kn).max(0.0), c.extra.normal);
        let t = Vec2::new(-nrm.y, nrm.x);
        let f = c.data.force.norm();
        acting += if j.is_some() { 2.0 * f } else { f };
        let ri = lever(i, c.data.point);
        let rj = j.map(|j| lever(j, c.data.point));
        let reach = ri.norm() + rj.map_or(0.0, |r| r.norm());
        let geometric = if reach > 0.0 { f / reach } else { 0.0 };
        let (gi, gti) = (g(i, ri, nrm), g(i, ri, t));
        let (gj, gtj) = match (j, rj) {
            (Some(j), Some(r)) => (g(j, r, nrm), g(j, r, t)),
            _ => (0.0, 0.0),
        };
        row[i] += k * gi * (gi + gj) + geometric * gti * (gti + gtj);
        noise[i] += k * x_max + f;
        if let Some(j) = j {
            row[j] += k * gj * (gj + gi) + geometric * gtj * (gtj + gti);
            noise[j] += k * x_max + f;
        }
    }
    let mean = if n > 0 { acting / n as f64 } else { 0.0 };
    let worst_noise = (0..n)
        .filter(|&k| !b.is_prescribed(k))
        .map(|k| noise[k])
        .fold(0.0f64, f64::max);
    NetworkBound {
        lambda: row.into_iter().fold(0.0f64, f64::max),
        round_off: if mean > 0.0 {
            f64::EPSILON * worst_noise / mean
        } else {
            0.0
        },
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

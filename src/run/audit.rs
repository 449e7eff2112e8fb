//! The energy audit: a run that checks, at every output frame, that its energy account still
//! closes, and says so once when it does not ([`EnergyAudit`]).
//!
//! # What it checks
//! The account of a run is `u = K + P + E_el + D − E₀ − W` (`unaccounted` in `summary.json`):
//! the energy the integration created (u > 0) or lost (u < 0) since the start, zero in exact
//! arithmetic ([`crate::dynamics::account::Energies`]). It is compared with the energy the run
//! has had in motion, the blow-up watch's scale ([`super::watch::BlowupWatch::available`]):
//! the initial kinetic and elastic energy, the most gravity has supplied (`max (P₀ − P)`) and
//! the most work the walls, prescribed bodies, a Lees–Edwards seam or a stress-controlled cell
//! have done (`max W`). When `|u|` exceeds the threshold times that scale (by default
//! [`DEFAULT_THRESHOLD`], 1 % — the case key `energy_audit`), the run warns once: the step, both
//! figures, and the likely causes. It does not stop the run: the blow-up watch does that, at
//! [`super::watch::ENERGY_GROWTH`] = 10 times the scale, and only for energy created.
//!
//! # What it can and cannot see
//! It sees any error that moves energy without booking it, whatever its cause: a Δt too large
//! for the stiffest contact (velocity Verlet's energy error grows as (ωΔt)²), a contact found
//! late and deep (its spring starts with energy no force put there), energy lost as well as
//! created (which the watch ignores), an account that a state file's edit left open. It samples
//! the account at the output frames only (a swing that closes between two frames is not seen),
//! and it cannot tell a wrong force that conserves energy: a law that is the gradient of a
//! wrong potential, a missed contact that would only have stored and returned energy, a wrong
//! friction that dissipates the wrong amount but books it. Those are the tests' to find.
//!
//! Its cost is a few arithmetic operations per output frame: nothing per body or step. It starts
//! with the first output frame after the start: before it, the scale is what the first few steps
//! have supplied, next to nothing.

use super::observer::{End, Observer, ObserverError, StepInfo};
use super::progress::RunProgress;
use crate::contact_law::NormalForce;
use crate::dynamics::World;

/// The default threshold: 1 % of the energy the run has had in motion.
pub const DEFAULT_THRESHOLD: f64 = 1e-2;

/// What the audit found when the account first failed to close.
#[derive(Clone, Debug, PartialEq)]
pub struct AuditFinding {
    pub step: u64,
    /// `K + P + E_el + D − E₀ − W` then.
    pub unaccounted: f64,
    /// The energy the run had had in motion then.
    pub scale: f64,
    /// The threshold it exceeded (a fraction of `scale`).
    pub threshold: f64,
    /// The time step and the contact network's critical step sampled so far (∞ before any
    /// contact).
    pub dt: f64,
    pub dt_critical: f64,
    /// Some law of the scene is P's spring on the depth, which conserves no energy on
    /// non-circular bodies.
    pub depth_law: bool,
}

impl AuditFinding {
    /// The warning (it contains the word "unaccounted", the step, both figures and the likely
    /// causes).
    pub fn warning(&self) -> String {
        let kind = if self.unaccounted > 0.0 {
            "created"
        } else {
            "lost"
        };
        let critical = match self.dt_critical.is_finite() {
            true => format!("{:.3e}", self.dt_critical),
            false => "not sampled".into(),
        };
        let law = match self.depth_law {
            true => {
                "a law that conserves no energy (P's spring on the depth, `normal_force: depth`, \
                 is no potential's gradient on non-circular bodies: the area law is); "
            }
            false => "",
        };
        format!(
            "the energy account stopped closing at step {}: {:.3e} erg unaccounted ({kind}), \
             {:.2e} of the {:.3e} erg the run has had in motion (the audit's threshold {:e}, key \
             `energy_audit`). Likely causes: {law}the time step, dt = {:e} against the contact \
             network's critical step {critical} (the error grows as (dt/critical)²: a smaller dt \
             closes the account if this is the cause); a contact found late and deep; an edited \
             state; a wall or cell driven faster than the contacts can follow",
            self.step,
            self.unaccounted,
            self.unaccounted.abs() / self.scale,
            self.scale,
            self.threshold,
            self.dt
        )
    }
}

/// The energy audit (see the module documentation): an observer that checks the account every
/// `every` steps (the output frames) and at the run's last step.
#[derive(Clone, Debug)]
pub struct EnergyAudit {
    threshold: f64,
    every: u64,
    initial_total: f64,
    /// The watch's reference of the whole run (a continued run's is its state's), its maxima
    /// kept up at each check.
    kinetic0: f64,
    elastic0: f64,
    potential0: f64,
    gravity_supplied: f64,
    boundary_supplied: f64,
    finding: Option<AuditFinding>,
}

impl EnergyAudit {
    /// An audit of the run whose progress is `progress` (its initial energy and the watch's
    /// reference), warning beyond `threshold` of the scale, checked every `every` steps.
    pub fn new(progress: &RunProgress, threshold: f64, every: u64) -> Self {
        let w = &progress.watch;
        EnergyAudit {
            threshold,
            every: every.max(1),
            initial_total: progress.initial_total,
            kinetic0: w.kinetic0,
            elastic0: w.elastic0,
            potential0: w.potential0,
            gravity_supplied: w.gravity_supplied,
            boundary_supplied: w.boundary_supplied,
            finding: None,
        }
    }

    /// What it found, if the account stopped closing.
    pub fn finding(&self) -> Option<&AuditFinding> {
        self.finding.as_ref()
    }

    /// Checks the world now (at `step`); records the first finding.
    pub fn check(&mut self, world: &World, step: u64) {
        if self.finding.is_some() {
            return;
        }
        let e = world.energies;
        self.gravity_supplied = self.gravity_supplied.max(self.potential0 - e.potential);
        self.boundary_supplied = self.boundary_supplied.max(e.boundary_work);
        let scale = self.kinetic0 + self.elastic0 + self.gravity_supplied + self.boundary_supplied;
        let unaccounted = e.total() - self.initial_total - e.boundary_work;
        // (A non-finite account is the watch's to report.)
        if unaccounted.abs() > self.threshold * scale && unaccounted.is_finite() {
            self.finding = Some(AuditFinding {
                step,
                unaccounted,
                scale,
                threshold: self.threshold,
                dt: world.dt,
                dt_critical: world.diagnostics.dt_critical_observed,
                depth_law: world
                    .pairs
                    .all()
                    .any(|p| p.spec.normal_force() == NormalForce::Depth),
            });
        }
    }
}

impl Observer for EnergyAudit {
    fn after_step(&mut self, world: &World, info: &StepInfo) -> Result<(), ObserverError> {
        if !info.blowup && info.step.is_multiple_of(self.every) {
            self.check(world, info.step);
        }
        Ok(())
    }

    /// The last state too, once the run has passed its first output frame: over the first
    /// few steps the scale is what gravity has supplied so far, next to nothing, and the
    /// account's rounding and a contact's first swing would read as a large fraction of it
    /// (P's three ellipses, 10 steps in: 1.5e-3 erg of 0.06).
    fn finish(&mut self, world: &World, end: &End) -> Result<(), ObserverError> {
        if end.finite && end.step >= self.every {
            self.check(world, end.step);
        }
        Ok(())
    }
}

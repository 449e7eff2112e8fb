//! The tangential part of a contact law, written once for every normal spring: a shear spring
//! on the accumulated shear displacement (T16), a shear dashpot, and Coulomb's slider (T20).

use super::normal::NormalSpring;
use super::{ContactForce, History};

/// How stiff the shear spring is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShearStiffness {
    /// A constant `k_s` (P §3).
    Constant(f64),
    /// Mindlin: `k_t = 8 G* √(R* δ)` (T18), with `G*` of T19.
    Mindlin { g_star: f64 },
}

/// A shear spring and a Coulomb slider, resolved for one pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentialPart {
    pub stiffness: ShearStiffness,
    /// Coulomb friction coefficient μ (0: no shear force and no shear history at all).
    pub friction: f64,
}

impl TangentialPart {
    /// The shear stiffness `k_t` with the normal spring `s` (Mindlin's scales with its `√(R*δ)`).
    #[inline]
    pub fn stiffness(&self, s: &NormalSpring) -> f64 {
        match self.stiffness {
            ShearStiffness::Constant(ks) => ks,
            ShearStiffness::Mindlin { g_star } => 8.0 * g_star * s.root, // T(18)
        }
    }

    /// Adds the shear force to `out` (whose `normal` is already set): `δ_t += v_t Δt` (T16),
    /// `F_t = −k_t δ_t − η_t v_t` (T15), limited by `μ F_n` (T20); with the shear spring's
    /// energy, its change over the step and the stiffness and dashpot for the time-step
    /// estimate. Nothing at all without friction.
    #[inline]
    pub fn apply(
        &self,
        kt: f64,
        eta_t: f64,
        vt: f64,
        dt: f64,
        h: &mut History,
        out: &mut ContactForce,
    ) {
        if self.friction > 0.0 {
            let before = 0.5 * kt * h.shear * h.shear;
            h.shear += vt * dt; // T(16)
            let trial = -kt * h.shear - eta_t * vt; // T(15)
            out.tangential = coulomb(trial, self.friction * out.normal, kt, h);
            let now = 0.5 * kt * h.shear * h.shear;
            out.history_energy += now;
            out.history_energy_change += now - before;
            out.elastic_energy += now;
            out.kt = kt;
            out.eta_t = eta_t;
        }
    }
}

/// The Coulomb slider (T20, T21) on a trial shear force: when `|F_t| > μ F_n` the force is
/// `μ F_n` with the trial's sign and the spring is reset to hold exactly that (`δ_t = −F_t/k_t`);
/// the dashpot then carries nothing. In 2D the direction `v_t/|v_t|` of T21 is a sign, and the
/// trial force's sign equals −sign(v_t) in steady sliding; using the trial's keeps the force
/// continuous when `v_t` passes through zero. Returns the force.
#[inline]
pub(crate) fn coulomb(trial: f64, limit: f64, kt: f64, history: &mut History) -> f64 {
    if trial.abs() > limit {
        let f = limit.copysign(trial); // T(20)
        history.shear = if kt > 0.0 { -f / kt } else { 0.0 };
        f
    } else {
        trial
    }
}

//! The tangential part of a contact law, written once for every normal spring: a shear spring
//! on the accumulated shear displacement (T16), a shear dashpot, and Coulomb's slider (T20). As
//! a case gives it ([`TangentialSpec`]: `friction`, and with the linear model `ks` absolute or
//! per ρg, default `k_n`) and resolved for a pair ([`TangentialPart`]). Its history: the shear
//! spring's elongation (one value).

use super::force::ContactForce;
use super::keys::{Check, Given, Keys, ParamError};
use super::mixing::{MixError, harmonic_scaled};
use super::normal::{NormalSpec, NormalSpring, SpringSpec};
use super::params::Scaled;

/// The shear spring as a case gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShearSpec {
    /// A constant `k_s`, absolute or per ρg (the linear model).
    Constant(Scaled),
    /// Mindlin's, from the normal part's moduli (the Hertz–Mindlin model, T18, T19).
    Mindlin,
}

/// The tangential part as a case gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentialSpec {
    pub stiffness: ShearSpec,
    /// Coulomb friction coefficient μ ≥ 0.
    pub friction: f64,
}

impl TangentialSpec {
    /// Reads `friction` and, for the linear model, `ks` (default: the normal spring's `k_n`).
    pub fn parse(k: &impl Keys, normal: &NormalSpec) -> Result<Self, ParamError> {
        let friction = k
            .number("friction", Check::NonNegative)?
            .ok_or_else(|| k.missing("friction", "is missing".into()))?;
        let stiffness = match normal.spring {
            SpringSpec::Linear { kn } => {
                ShearSpec::Constant(k.scaled("ks", "ks_over_rho_g", Check::Scale)?.unwrap_or(kn))
            }
            SpringSpec::Hertz { .. } => {
                k.refuse(&["ks", "ks_over_rho_g"], normal.model())?;
                ShearSpec::Mindlin
            }
        };
        Ok(TangentialSpec {
            stiffness,
            friction,
        })
    }

    /// The part for a pair: `normal` this side's normal spec, `other` the other side's (Mindlin
    /// mixes the two materials, T19; a linear material on the other side counts as this one),
    /// `rho` the pair's density and `g` = |gravity|.
    pub fn resolve(
        &self,
        normal: &NormalSpec,
        other: &NormalSpec,
        rho: f64,
        g: f64,
    ) -> TangentialPart {
        let stiffness = match (self.stiffness, normal.spring) {
            (ShearSpec::Constant(ks), _) => ShearStiffness::Constant(ks.value(rho, g)),
            (ShearSpec::Mindlin, SpringSpec::Hertz { young, poisson }) => {
                let (e2, nu2) = other.moduli().unwrap_or((young, poisson));
                ShearStiffness::Mindlin {
                    g_star: 1.0
                        / (2.0 * (2.0 - poisson) * (1.0 + poisson) / young
                            + 2.0 * (2.0 - nu2) * (1.0 + nu2) / e2), // T(19)
                }
            }
            // Mindlin's spring on a linear normal spring: the normal spring's stiffness.
            (ShearSpec::Mindlin, SpringSpec::Linear { kn }) => {
                ShearStiffness::Constant(kn.value(rho, g))
            }
        };
        TangentialPart {
            stiffness,
            friction: self.friction,
        }
    }
}

impl super::part::Part for TangentialSpec {
    /// The keys this part reads.
    const KEYS: &[&str] = &["friction", "ks", "ks_over_rho_g"];

    /// The shear spring's elongation ([`TangentialPart::HISTORY`]).
    const HISTORY: &[&str] = TangentialPart::HISTORY;

    /// The inherited keys a wall's override `key` replaces (see
    /// [`super::ContactSpec::replaced_by`]).
    fn replaced_by(key: &str) -> &'static [&'static str] {
        match key {
            "ks" | "ks_over_rho_g" => &["ks", "ks_over_rho_g"],
            _ => &[],
        }
    }

    /// The tangential part of contacts between the materials `self` and `other`
    /// ([`super::mixing`]): the smaller friction (Yade), the harmonic mean of the shear
    /// stiffnesses (Mindlin's is formed from both materials' moduli at resolution, T19).
    fn mix(&self, other: &TangentialSpec) -> Result<TangentialSpec, MixError> {
        let stiffness = match (self.stiffness, other.stiffness) {
            (ShearSpec::Constant(a), ShearSpec::Constant(b)) => {
                ShearSpec::Constant(harmonic_scaled(a, b, "ks")?)
            }
            (ShearSpec::Mindlin, ShearSpec::Mindlin) => ShearSpec::Mindlin,
            (ShearSpec::Constant(_), ShearSpec::Mindlin)
            | (ShearSpec::Mindlin, ShearSpec::Constant(_)) => {
                return Err(MixError::new("model", "the two materials' models differ"));
            }
        };
        Ok(TangentialSpec {
            stiffness,
            friction: self.friction.min(other.friction),
        })
    }

    /// Its keys as a case file gives them (what [`TangentialSpec::parse`] reads back).
    fn given(&self) -> Vec<(&'static str, Given)> {
        let mut keys = vec![("friction", Given::Number(self.friction))];
        if let ShearSpec::Constant(ks) = self.stiffness {
            keys.push(ks.given("ks", "ks_over_rho_g"));
        }
        keys
    }
}

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
    /// Its per-contact history: the shear spring's elongation δ_t along `t` (T16).
    pub const HISTORY: &[&str] = &["shear"];

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
        h: &mut [f64],
        out: &mut ContactForce,
    ) {
        if self.friction > 0.0 {
            let shear = &mut h[0];
            let before = 0.5 * kt * *shear * *shear;
            *shear += vt * dt; // T(16)
            let trial = -kt * *shear - eta_t * vt; // T(15)
            out.tangential = coulomb(trial, self.friction * out.normal, kt, shear);
            let now = 0.5 * kt * *shear * *shear;
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
/// continuous when `v_t` passes through zero. Returns the force; `shear` is the spring's
/// elongation.
#[inline]
pub(crate) fn coulomb(trial: f64, limit: f64, kt: f64, shear: &mut f64) -> f64 {
    if trial.abs() > limit {
        let f = limit.copysign(trial); // T(20)
        *shear = if kt > 0.0 { -f / kt } else { 0.0 };
        f
    } else {
        trial
    }
}

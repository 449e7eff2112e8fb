//! The rolling part of a contact law: a couple resisting the relative rotation of the two
//! bodies, after Ai, Chen, Rotter & Ooi (Powder Technol. 206 (2011) 269–282), in the two forms
//! that LIGGGHTS, Kratos, PFC and EDEM implement:
//!
//! - **CDT** (`"cdt"`, Ai et al.'s type A, constant directional torque): on j the couple
//!   `M = −μ_r R_r F_n sgn(ω_rel)`, with `ω_rel = ω_j − ω_i` (its opposite on i). It has no
//!   static state: the torque keeps its full size while ω_rel ≠ 0 and reverses with it, so a
//!   body that has stopped rolling chatters (ω flips sign every step). dem2d caps the couple so
//!   that it cannot reverse ω_rel within one step (a moment limiter, as STAR-CCM+'s
//!   constant-torque model has): within one step the couple turns the bodies about their
//!   centroids (the friction force that makes a rolling body pivot about the contact point is a
//!   spring, tens of steps slower), so the cap is `|M| ≤ I_s |ω_rel| / Δt` with
//!   `1/I_s = n_i/I_i + n_j/I_j` — centroidal inertias, each divided by the number of contacts
//!   its body may have (its neighbour-list slots), so that all of a body's contacts braking at
//!   once still cannot reverse it. A rolling body then comes to rest in about the step in which
//!   it would have reversed, and stays (CDT still cannot hold a body on a slope: nothing acts at
//!   ω_rel = 0).
//! - **EPSD** (`"epsd"`, type C, elastic–plastic spring–dashpot): a rolling spring on the
//!   relative rotation, `M_k ← M_k − k_r ω_rel Δt` (history, carried like the shear spring and
//!   dropped when the contact ends), capped at `μ_r R_r F_n` (kept at the cap, like Coulomb's
//!   slider), plus a dashpot `−C_r ω_rel` while the spring is below the cap (Ai et al.'s f = 0
//!   choice, as LIGGGHTS). A body on a slope β holds while `tan β ≤ μ_r` (for a disk, and for
//!   every shape with dem2d's rolling radius below).
//!   - Stiffness `k_r = k_t R_r²` (Iwashita & Oda 1998, as PFC's `rrlinear` and Kratos' type
//!     C): the shear spring acting at the rolling radius. It does not depend on μ_r, so the
//!     elastic response is the same whatever the plastic limit (LIGGGHTS' `epsd` takes
//!     `2.25 k_n μ_r² R_r²` instead, whose yield rotation `δ/(2.25 μ_r R_r)` grows without bound
//!     as μ_r → 0); and its frequency is of the shear spring's order (a body against a wall:
//!     `k_r/I_r = k_t R_r²/(I + m R_r²) < k_t/m`; a disk, `2k_t/(3m)`), so it sets no new
//!     limit on Δt (the critical-step estimate asks it all the same).
//!   - Damping `C_r = η_r · 2√(I_r k_r)` (LIGGGHTS' form), with `η_r` the key
//!     `rolling_damping`; by default the damping ratio of the contact's normal dashpot
//!     (`η_n/(2√(m* k_n))`, or β/2 for Hertz, T12, T14), so that a rolling oscillation decays
//!     like a normal one.
//!
//! The **rolling radius** `R_r` and the **rolling inertia** `I_r` come from the kinematics
//! ([`RollingKinematics`]); see `dynamics::kinematics` for dem2d's choice for non-round bodies.

use super::force::ContactForce;
use super::keys::{Check, Given, Keys, ParamError};
use super::mixing::{MixError, harmonic};

/// Which rolling-resistance model (a case's `rolling_model`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RollingModel {
    /// Constant directional torque (Ai et al.'s type A).
    Cdt,
    /// Elastic–plastic spring–dashpot (Ai et al.'s type C).
    Epsd,
}

impl RollingModel {
    /// The name used in case files.
    pub fn as_str(&self) -> &'static str {
        match self {
            RollingModel::Cdt => "cdt",
            RollingModel::Epsd => "epsd",
        }
    }
}

/// Rolling resistance as a case gives it, and (the parameters need no pair data) as a law uses
/// it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollingPart {
    pub model: RollingModel,
    /// Coefficient of rolling friction μ_r (dimensionless, ≥ 0).
    pub friction: f64,
    /// EPSD's damping ratio η_r (`None`: the normal dashpot's).
    pub damping: Option<f64>,
}

/// What the rolling part needs to know about a contact besides the normal force: the rolling
/// radius `R_r`, the rolling inertia `I_r` (the pair's equivalent moment of inertia for a
/// rotation about the contact point: EPSD's dashpot), and the inertia `I_s` against which the
/// CDT limiter caps the couple (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollingKinematics {
    pub radius: f64,
    pub inertia: f64,
    pub spin_inertia: f64,
}

impl RollingPart {
    /// The keys this part reads.
    pub const KEYS: &[&str] = &["rolling_model", "rolling_friction", "rolling_damping"];

    /// Its per-contact history: EPSD's rolling spring moment `M_k` on j (none for CDT: see
    /// [`RollingPart::keeps_history`]).
    pub const HISTORY: &[&str] = &["rolling"];

    /// Whether its contacts carry [`RollingPart::HISTORY`] (EPSD's spring; CDT has no state).
    pub fn keeps_history(&self) -> bool {
        self.model == RollingModel::Epsd
    }

    /// The inherited keys a wall's override `key` replaces (see
    /// [`super::ContactSpec::replaced_by`]): another rolling model does not inherit the scene's
    /// model's damping.
    pub fn replaced_by(key: &str) -> &'static [&'static str] {
        match key {
            "rolling_model" => &["rolling_damping"],
            _ => &[],
        }
    }

    /// Reads `rolling_model` (`cdt` or `epsd`) with `rolling_friction` μ_r ≥ 0, and for EPSD an
    /// optional `rolling_damping` η_r ≥ 0. `None` when not given, or when μ_r = 0 (no couple at
    /// all).
    pub fn parse(k: &impl Keys) -> Result<Option<Self>, ParamError> {
        let Some(model) = k.string("rolling_model")? else {
            for key in ["rolling_friction", "rolling_damping"] {
                if k.has(key) {
                    return Err(k.error(key, "needs `rolling_model` (`cdt` or `epsd`)".into()));
                }
            }
            return Ok(None);
        };
        let model = match model.as_str() {
            "cdt" => RollingModel::Cdt,
            "epsd" => RollingModel::Epsd,
            other => {
                return Err(k.error(
                    "rolling_model",
                    format!("unknown rolling model `{other}` (expected `cdt` or `epsd`)"),
                ));
            }
        };
        let friction = k
            .number("rolling_friction", Check::NonNegative)?
            .ok_or_else(|| {
                k.missing(
                "rolling_friction",
                "is missing (the coefficient of rolling friction μ_r that `rolling_model` needs)"
                    .into(),
            )
            })?;
        let damping = match model {
            RollingModel::Cdt if k.has("rolling_damping") => {
                return Err(k.error(
                    "rolling_damping",
                    "is not a parameter of the `cdt` rolling model (only `epsd` has a rolling \
                     dashpot)"
                        .into(),
                ));
            }
            RollingModel::Cdt => None,
            RollingModel::Epsd => k.number("rolling_damping", Check::NonNegative)?,
        };
        if friction == 0.0 {
            return Ok(None);
        }
        Ok(Some(RollingPart {
            model,
            friction,
            damping,
        }))
    }

    /// Its keys as a case file gives them (what [`RollingPart::parse`] reads back).
    pub fn given(&self) -> Vec<(&'static str, Given)> {
        let mut keys = vec![
            ("rolling_model", Given::Text(self.model.as_str())),
            ("rolling_friction", Given::Number(self.friction)),
        ];
        if let Some(d) = self.damping {
            keys.push(("rolling_damping", Given::Number(d)));
        }
        keys
    }

    /// The rolling part of contacts between two materials ([`super::mixing`]): none if either
    /// has none (μ_r = 0), else the smaller μ_r and the harmonic mean of the rolling damping;
    /// two models, or a damping given for one material only, have no common rule.
    pub fn mix(a: Option<Self>, b: Option<Self>) -> Result<Option<Self>, MixError> {
        let (Some(a), Some(b)) = (a, b) else {
            return Ok(None);
        };
        if a.model != b.model {
            return Err(MixError::new(
                "rolling_model",
                format!(
                    "one material rolls by `{}` and the other by `{}`",
                    a.model.as_str(),
                    b.model.as_str()
                ),
            ));
        }
        let damping = match (a.damping, b.damping) {
            (None, None) => None,
            (Some(x), Some(y)) => Some(harmonic(x, y)),
            (Some(_), None) | (None, Some(_)) => {
                return Err(MixError::new(
                    "rolling_damping",
                    "one material gives it and the other does not",
                ));
            }
        };
        Ok(Some(RollingPart {
            model: a.model,
            friction: a.friction.min(b.friction),
            damping,
        }))
    }

    /// A line for a case's description: the model and μ_r.
    pub fn describe(&self) -> String {
        format!("{} with μ_r = {}", self.model.as_str(), self.friction)
    }

    /// Adds the rolling couple to `out` (whose `normal` is set): on j (its opposite on i) for the
    /// relative spin `spin = ω_j − ω_i`, with the shear stiffness `kt` (EPSD's `k_r = k_t R_r²`),
    /// the normal mode's damping ratio `zeta_n` (EPSD's default) and the step `dt` (the
    /// rotation is integrated over it; the CDT limiter divides by it: Δt = 0 means no limiter).
    /// The whole couple counts as non-elastic; the rolling spring's energy and its change are
    /// accounted apart, like the shear spring's.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn apply(
        &self,
        rk: &RollingKinematics,
        spin: f64,
        kt: f64,
        zeta_n: f64,
        dt: f64,
        h: &mut [f64],
        out: &mut ContactForce,
    ) {
        let limit = self.friction * rk.radius * out.normal; // Ai et al.: M_r = μ_r R_r F_n
        let couple = match self.model {
            RollingModel::Cdt => {
                let mut m = limit;
                if dt > 0.0 {
                    // The limiter: the couple cannot reverse ω_rel within a step.
                    m = m.min(rk.spin_inertia * spin.abs() / dt);
                }
                if spin > 0.0 {
                    -m
                } else if spin < 0.0 {
                    m
                } else {
                    0.0
                }
            }
            RollingModel::Epsd => {
                let kr = kt * rk.radius * rk.radius; // Iwashita & Oda: k_r = k_t R_r²
                let energy = |m: f64| if kr > 0.0 { 0.5 * m * m / kr } else { 0.0 };
                let before = energy(h[0]);
                let mut m = h[0] - kr * spin * dt;
                let full = m.abs() > limit;
                if full {
                    m = limit.copysign(m);
                }
                h[0] = m;
                let zeta = self.damping.unwrap_or(zeta_n);
                let cr = zeta * 2.0 * (rk.inertia * kr).sqrt();
                let damper = if full { 0.0 } else { -cr * spin };
                let now = energy(m);
                out.history_energy += now;
                out.history_energy_change += now - before;
                out.elastic_energy += now;
                out.kr = kr;
                out.cr = cr;
                m + damper
            }
        };
        out.couple += couple;
        out.couple_non_elastic += couple;
    }

    /// The rolling spring's stiffness and dashpot for the time-step estimate, with the shear
    /// stiffness `kt` and the normal mode's damping ratio (0, 0 for CDT).
    pub fn mode(&self, rk: &RollingKinematics, kt: f64, zeta_n: f64) -> (f64, f64) {
        match self.model {
            RollingModel::Cdt => (0.0, 0.0),
            RollingModel::Epsd => {
                let kr = kt * rk.radius * rk.radius;
                let zeta = self.damping.unwrap_or(zeta_n);
                (kr, zeta * 2.0 * (rk.inertia * kr).sqrt())
            }
        }
    }
}

/// The rolling part as a case gives it: none (μ_r = 0), or the part.
impl super::part::Part for Option<RollingPart> {
    const KEYS: &[&str] = RollingPart::KEYS;
    const HISTORY: &[&str] = RollingPart::HISTORY;

    fn replaced_by(key: &str) -> &'static [&'static str] {
        RollingPart::replaced_by(key)
    }

    fn given(&self) -> Vec<(&'static str, Given)> {
        self.map_or(vec![], |r| r.given())
    }

    fn mix(&self, other: &Self) -> Result<Self, MixError> {
        RollingPart::mix(*self, *other)
    }
}

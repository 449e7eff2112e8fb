//! The damping part of a contact law: the normal and shear dashpots, given or derived from a
//! coefficient of restitution (T12, T14). As a case gives it ([`DampingSpec`]: `eta_n`, `eta_s`
//! absolute or per ρg, or `restitution`), and resolved for a pair ([`DampingPart`]).

use super::keys::{Check, Given, Keys, ParamError};
use super::mixing::{MixError, harmonic, harmonic_scaled};
use super::normal::{NormalSpec, NormalSpring, SpringSpec};
use super::params::Scaled;

/// How a linear contact is damped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinearDamping {
    /// Given dashpots.
    Dashpots { eta_n: Scaled, eta_s: Scaled },
    /// From a coefficient of restitution: `η_n = 2α√(m* k_n)` (T12), `η_s = η_n`.
    Restitution(f64),
}

/// The damping part as a case gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DampingSpec {
    /// With the linear spring.
    Linear(LinearDamping),
    /// With the Hertz spring: from a coefficient of restitution (T14).
    Hertz { restitution: f64 },
}

impl DampingSpec {
    /// Reads the dashpots or the restitution for the normal spring `normal`.
    pub fn parse(k: &impl Keys, normal: &NormalSpec) -> Result<Self, ParamError> {
        let restitution = |required: bool| -> Result<Option<f64>, ParamError> {
            match k.number("restitution", Check::Positive)? {
                Some(e) if e > 1.0 => {
                    Err(k.error("restitution", format!("must be in (0, 1], got {e}")))
                }
                None if required => Err(k.missing("restitution", "is missing".into())),
                e => Ok(e),
            }
        };
        match normal.spring {
            SpringSpec::Linear { .. } => {
                let eta_n = k.scaled("eta_n", "eta_n_over_rho_g", Check::NonNegative)?;
                let eta_s = k.scaled("eta_s", "eta_s_over_rho_g", Check::NonNegative)?;
                let damping = match (eta_n, restitution(false)?) {
                    (Some(_), Some(_)) => {
                        return Err(k.error(
                            "restitution",
                            "give dashpots (`eta_n…`) or `restitution`, not both".into(),
                        ));
                    }
                    (Some(eta_n), None) => LinearDamping::Dashpots {
                        eta_n,
                        eta_s: eta_s.unwrap_or(eta_n),
                    },
                    (None, Some(e)) => {
                        if eta_s.is_some() {
                            return Err(k.error(
                                "eta_s",
                                "with `restitution`, η_s = η_n (T); do not give `eta_s`".into(),
                            ));
                        }
                        LinearDamping::Restitution(e)
                    }
                    (None, None) => {
                        return Err(k.missing(
                            "eta_n_over_rho_g",
                            "is missing (or give `eta_n` or `restitution`)".into(),
                        ));
                    }
                };
                Ok(DampingSpec::Linear(damping))
            }
            SpringSpec::Hertz { .. } => {
                k.refuse(
                    &["eta_n", "eta_n_over_rho_g", "eta_s", "eta_s_over_rho_g"],
                    normal.model(),
                )?;
                Ok(DampingSpec::Hertz {
                    restitution: restitution(true)?.expect("required"),
                })
            }
        }
    }

    /// The dashpots for a pair of density `rho` under |g| `g`.
    pub fn resolve(&self, rho: f64, g: f64) -> DampingPart {
        match *self {
            DampingSpec::Linear(LinearDamping::Dashpots { eta_n, eta_s }) => {
                DampingPart::Dashpots {
                    eta_n: eta_n.value(rho, g),
                    eta_s: eta_s.value(rho, g),
                }
            }
            DampingSpec::Linear(LinearDamping::Restitution(e)) => DampingPart::Restitution {
                alpha: damping_ratio_linear(e),
            },
            DampingSpec::Hertz { restitution } => DampingPart::Hertz {
                beta: damping_factor_hertz(restitution),
            },
        }
    }

    /// True when the dashpots depend on the pair's effective mass (restitution-tuned linear
    /// dashpots), so that the law cannot be resolved once for every pair.
    pub fn depends_on_mass(&self) -> bool {
        matches!(self, DampingSpec::Linear(LinearDamping::Restitution(_)))
    }
}

impl super::part::Part for DampingSpec {
    /// The keys this part reads.
    const KEYS: &[&str] = &[
        "eta_n",
        "eta_n_over_rho_g",
        "eta_s",
        "eta_s_over_rho_g",
        "restitution",
    ];

    /// The inherited keys a wall's override `key` replaces (see
    /// [`super::ContactSpec::replaced_by`]): dashpots and a restitution are one choice.
    fn replaced_by(key: &str) -> &'static [&'static str] {
        if Self::KEYS.contains(&key) {
            Self::KEYS
        } else {
            &[]
        }
    }

    /// The damping of contacts between the materials `self` and `other` ([`super::mixing`]):
    /// the harmonic mean of the dashpots, or of the restitutions; dashpots and a restitution
    /// have no common rule.
    fn mix(&self, other: &DampingSpec) -> Result<DampingSpec, MixError> {
        use LinearDamping::{Dashpots, Restitution};
        Ok(match (*self, *other) {
            (
                DampingSpec::Linear(Dashpots { eta_n, eta_s }),
                DampingSpec::Linear(Dashpots {
                    eta_n: n2,
                    eta_s: s2,
                }),
            ) => DampingSpec::Linear(Dashpots {
                eta_n: harmonic_scaled(eta_n, n2, "eta_n")?,
                eta_s: harmonic_scaled(eta_s, s2, "eta_s")?,
            }),
            (DampingSpec::Linear(Restitution(a)), DampingSpec::Linear(Restitution(b))) => {
                DampingSpec::Linear(Restitution(harmonic(a, b)))
            }
            (DampingSpec::Hertz { restitution: a }, DampingSpec::Hertz { restitution: b }) => {
                DampingSpec::Hertz {
                    restitution: harmonic(a, b),
                }
            }
            (DampingSpec::Linear(Dashpots { .. }), DampingSpec::Linear(Restitution(_)))
            | (DampingSpec::Linear(Restitution(_)), DampingSpec::Linear(Dashpots { .. }))
            | (DampingSpec::Linear(Dashpots { .. }), DampingSpec::Hertz { .. })
            | (DampingSpec::Hertz { .. }, DampingSpec::Linear(Dashpots { .. })) => {
                return Err(MixError::new(
                    "restitution",
                    "one material gives dashpots and the other a restitution",
                ));
            }
            (DampingSpec::Linear(Restitution(_)), DampingSpec::Hertz { .. })
            | (DampingSpec::Hertz { .. }, DampingSpec::Linear(Restitution(_))) => {
                return Err(MixError::new("model", "the two materials' models differ"));
            }
        })
    }

    /// Its keys as a case file gives them (what [`DampingSpec::parse`] reads back).
    fn given(&self) -> Vec<(&'static str, Given)> {
        match *self {
            DampingSpec::Linear(LinearDamping::Dashpots { eta_n, eta_s }) => vec![
                eta_n.given("eta_n", "eta_n_over_rho_g"),
                eta_s.given("eta_s", "eta_s_over_rho_g"),
            ],
            DampingSpec::Linear(LinearDamping::Restitution(e))
            | DampingSpec::Hertz { restitution: e } => vec![("restitution", Given::Number(e))],
        }
    }
}

/// The dashpots of a contact, resolved for one pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DampingPart {
    /// Constant dashpots `η_n`, `η_s`.
    Dashpots { eta_n: f64, eta_s: f64 },
    /// From a restitution coefficient for the linear spring: `η_n = η_s = 2α√(m* k_n)` with α
    /// of T12.
    Restitution { alpha: f64 },
    /// Hertz: `η_n = β √(m* k_n)` with the current `k_n` (T14), `η_t = η_n`.
    Hertz { beta: f64 },
}

impl DampingPart {
    /// The normal dashpot for the spring `s` and the effective mass `m_eff` (m*, T13).
    #[inline]
    pub fn normal(&self, s: &NormalSpring, m_eff: f64) -> f64 {
        match *self {
            DampingPart::Dashpots { eta_n, .. } => eta_n,
            DampingPart::Restitution { alpha } => restitution_dashpot(alpha, m_eff, s.k),
            DampingPart::Hertz { beta } => hertz_dashpot(beta, m_eff, s.k),
        }
    }

    /// The shear dashpot, given the normal one `eta_n`.
    #[inline]
    pub fn tangential(&self, eta_n: f64) -> f64 {
        match *self {
            DampingPart::Dashpots { eta_s, .. } => eta_s,
            DampingPart::Restitution { .. } => eta_n, // η_s = η_n (T)
            DampingPart::Hertz { .. } => eta_n,       // η_t = η_n (T)
        }
    }

    /// The damping ratio of the normal mode, `ζ = η_n / (2√(m* k_n))`: other parts' dashpots
    /// take it when none is given.
    #[inline]
    pub fn ratio(&self, s: &NormalSpring, m_eff: f64) -> f64 {
        match *self {
            DampingPart::Dashpots { eta_n, .. } => eta_n / (2.0 * (m_eff * s.k).sqrt()),
            DampingPart::Restitution { alpha } => {
                restitution_dashpot(alpha, m_eff, s.k) / (2.0 * (m_eff * s.k).sqrt())
            }
            DampingPart::Hertz { beta } => 0.5 * beta,
        }
    }
}

/// T14's Hertz dashpot `η_n = β √(m* k_n)`, out of line: inlined, the compiler computes its
/// square root (and m* = 1/Σ(1/m), a division) for every contact of every law and then picks
/// the constant dashpot's value: a square root's latency on the path of every linear contact
/// (10⁴ disks: ~9 % of the step). A call is not speculated.
#[inline(never)]
fn hertz_dashpot(beta: f64, m_eff: f64, k: f64) -> f64 {
    beta * (m_eff * k).sqrt() // T(14)
}

/// T12's linear dashpot `η_n = 2α√(m* k_n)`, out of line for the same reason as
/// [`hertz_dashpot`].
#[inline(never)]
fn restitution_dashpot(alpha: f64, m_eff: f64, k: f64) -> f64 {
    2.0 * alpha * (m_eff * k).sqrt() // T(12)
}

/// α of T12: the damping ratio that gives restitution `e` for a linear spring–dashpot,
/// `α = −ln e / √(ln²e + π²)` (`η_n = 2α√(m* k_n)`).
pub fn damping_ratio_linear(e: f64) -> f64 {
    let l = e.ln();
    -l / (l * l + std::f64::consts::PI.powi(2)).sqrt() // T(12)
}

/// β of T14 for the Hertz spring: `β = −ln e · √(5/(ln²e + π²))` (`η_n = β√(m* k_n)`).
pub fn damping_factor_hertz(e: f64) -> f64 {
    let l = e.ln();
    -l * (5.0 / (l * l + std::f64::consts::PI.powi(2))).sqrt() // T(14)
}

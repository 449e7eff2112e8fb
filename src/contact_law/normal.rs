//! The normal part of a contact law: the spring on the overlap it acts on (the depth δ, or the
//! area law's equivalent overlap δ_eq — see [`super::Kinematics::spring_overlap`]).
//!
//! As a case gives it ([`NormalSpec`]: the keys `model`, `kn`/`kn_over_rho_g` or `young` and
//! `poisson`, and `normal_force`), and resolved for a pair ([`NormalPart`]).
//!
//! A spring is reported through its secant stiffness `k` (`F_s = k δ`), so that the force, its
//! stored energy and its tangent stiffness are one formula each for every spring:
//! `F_s = k δ`, energy `e k δ²` (e = ½ for the linear spring, 2/5 for Hertz),
//! `dF_s/dδ = t k` (t = 1, 3/2).

/// A normal spring with its parameters resolved for one pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NormalPart {
    /// `F_s = k_n δ` (P §3; T6 with a constant spring).
    Linear { kn: f64 },
    /// Hertz: `F_s = k_n δ`, `k_n = 4/3 E* √(R* δ)` (T10), with `E*` of T11. T's sphere formula
    /// used as written with forces per unit thickness (what 2D DEM codes commonly do; the exact
    /// line-contact law has a logarithmic term and no such simple form).
    Hertz { e_star: f64 },
}

/// The spring of one contact at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalSpring {
    /// Secant stiffness `k = F_s/δ`.
    pub k: f64,
    /// `dF_s/dδ = tangent · k`.
    pub tangent: f64,
    /// Stored energy `energy · k · δ · δ_e` (δ_e the energy overlap: δ for smooth contacts).
    pub energy: f64,
    /// `√(R* δ)` (Hertz; 1 for the linear spring): Mindlin's shear stiffness scales with it.
    pub root: f64,
}

impl NormalPart {
    /// The spring at the overlap `depth` with effective radius `r_eff` (R*, T11: read by Hertz
    /// only).
    #[inline]
    pub fn spring(&self, depth: f64, r_eff: f64) -> NormalSpring {
        match *self {
            NormalPart::Linear { kn } => NormalSpring {
                k: kn,
                tangent: 1.0,
                energy: 0.5,
                root: 1.0,
            },
            NormalPart::Hertz { e_star } => {
                let root = (r_eff * depth.max(0.0)).sqrt();
                NormalSpring {
                    k: 4.0 / 3.0 * e_star * root, // T(10)
                    tangent: 1.5,                 // dF/dδ = (3/2)(4/3)E*√(R*δ)
                    energy: 0.4,                  // ∫F dδ = (2/5) k_n δ²
                    root,
                }
            }
        }
    }
}

use super::keys::{Check, Given, Keys, ParamError};
use super::mixing::{MixError, harmonic_scaled};
use super::params::Scaled;

/// What the normal spring acts on (a case's `contact.normal_force`); see the module
/// documentation of [`super`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalForce {
    /// P's spring on the depth δ (kept to reproduce P; not conservative for non-circular bodies).
    Depth,
    /// The overlap-area potential `W(A)`: conservative for every pair.
    #[default]
    Area,
}

impl NormalForce {
    /// The name used in case files.
    pub fn as_str(&self) -> &'static str {
        match self {
            NormalForce::Depth => "depth",
            NormalForce::Area => "area",
        }
    }
}

/// The normal spring as a case gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpringSpec {
    /// `"model": "linear"`: `k_n` absolute or per ρg.
    Linear { kn: Scaled },
    /// `"model": "hertz_mindlin"`: Young's modulus and Poisson's ratio (T10, T11).
    Hertz { young: f64, poisson: f64 },
}

/// The normal part as a case gives it: the spring and what it acts on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalSpec {
    pub spring: SpringSpec,
    pub normal_force: NormalForce,
}

impl NormalSpec {
    /// The contact model's name (`linear`, `hertz_mindlin`).
    pub fn model(&self) -> &'static str {
        match self.spring {
            SpringSpec::Linear { .. } => "linear",
            SpringSpec::Hertz { .. } => "hertz_mindlin",
        }
    }

    /// Reads `model` and the spring's parameters, and `normal_force` (default: the area law).
    pub fn parse(k: &impl Keys) -> Result<Self, ParamError> {
        let model = k
            .string("model")?
            .ok_or_else(|| k.missing("model", "is missing".into()))?;
        let normal_force = match k.string("normal_force")?.as_deref() {
            None => NormalForce::default(),
            Some("area") => NormalForce::Area,
            Some("depth") => NormalForce::Depth,
            Some(other) => {
                return Err(k.error(
                    "normal_force",
                    format!("unknown normal force `{other}` (expected `area` or `depth`)"),
                ));
            }
        };
        let spring = match model.as_str() {
            "linear" => {
                k.refuse(&["young", "poisson"], "linear")?;
                let kn = k
                    .scaled("kn", "kn_over_rho_g", Check::Scale)?
                    .ok_or_else(|| {
                        k.missing("kn_over_rho_g", "is missing (or give `kn`)".into())
                    })?;
                SpringSpec::Linear { kn }
            }
            "hertz_mindlin" => {
                k.refuse(&["kn", "kn_over_rho_g"], "hertz_mindlin")?;
                let young = k
                    .number("young", Check::Scale)?
                    .ok_or_else(|| k.missing("young", "is missing".into()))?;
                let poisson = k
                    .number("poisson", Check::Any)?
                    .ok_or_else(|| k.missing("poisson", "is missing".into()))?;
                // At ν = −1 the contact moduli E* and G* (T11, T19) are infinite.
                if !(poisson > -1.0 && poisson < 0.5) {
                    return Err(k.error("poisson", format!("must be in (-1, 0.5), got {poisson}")));
                }
                SpringSpec::Hertz { young, poisson }
            }
            other => {
                return Err(k.error(
                    "model",
                    format!(
                        "unknown contact model `{other}` (expected `linear` or `hertz_mindlin`)"
                    ),
                ));
            }
        };
        Ok(NormalSpec {
            spring,
            normal_force,
        })
    }

    /// The spring for a pair: `other` is the other side's material (Hertz mixes the two, T11;
    /// a linear material on the other side counts as this one), `rho` the pair's density and
    /// `g` = |gravity| (for a stiffness given per ρg).
    pub fn resolve(&self, other: &NormalSpec, rho: f64, g: f64) -> NormalPart {
        match self.spring {
            SpringSpec::Linear { kn } => NormalPart::Linear {
                kn: kn.value(rho, g),
            },
            SpringSpec::Hertz { young, poisson } => {
                let (e2, nu2) = other.moduli().unwrap_or((young, poisson));
                NormalPart::Hertz {
                    e_star: 1.0 / ((1.0 - poisson * poisson) / young + (1.0 - nu2 * nu2) / e2), // T(11)
                }
            }
        }
    }

    /// Young's modulus and Poisson's ratio of a Hertz material.
    pub fn moduli(&self) -> Option<(f64, f64)> {
        match self.spring {
            SpringSpec::Hertz { young, poisson } => Some((young, poisson)),
            SpringSpec::Linear { .. } => None,
        }
    }
}

impl super::part::Part for NormalSpec {
    /// The keys this part reads.
    const KEYS: &[&str] = &[
        "model",
        "kn",
        "kn_over_rho_g",
        "young",
        "poisson",
        "normal_force",
    ];

    /// The inherited keys a wall's override `key` replaces (see
    /// [`super::ContactSpec::replaced_by`]): a stiffness given one way replaces it given the other.
    fn replaced_by(key: &str) -> &'static [&'static str] {
        match key {
            "kn" | "kn_over_rho_g" => &["kn", "kn_over_rho_g"],
            _ => &[],
        }
    }

    /// The normal part of contacts between the materials `self` and `other`
    /// ([`super::mixing`]): the harmonic mean of the linear stiffnesses; a Hertz material keeps
    /// its moduli (E* is formed from both at [`NormalSpec::resolve`], T11).
    fn mix(&self, other: &NormalSpec) -> Result<NormalSpec, MixError> {
        let spring = match (self.spring, other.spring) {
            (SpringSpec::Linear { kn: a }, SpringSpec::Linear { kn: b }) => SpringSpec::Linear {
                kn: harmonic_scaled(a, b, "kn")?,
            },
            (SpringSpec::Hertz { .. }, SpringSpec::Hertz { .. }) => self.spring,
            (SpringSpec::Linear { .. }, SpringSpec::Hertz { .. })
            | (SpringSpec::Hertz { .. }, SpringSpec::Linear { .. }) => {
                return Err(MixError::new("model", "the two materials' models differ"));
            }
        };
        Ok(NormalSpec {
            spring,
            normal_force: self.normal_force,
        })
    }

    /// Its keys as a case file gives them (what [`NormalSpec::parse`] reads back).
    fn given(&self) -> Vec<(&'static str, Given)> {
        let mut keys = vec![
            ("model", Given::Text(self.model())),
            ("normal_force", Given::Text(self.normal_force.as_str())),
        ];
        match self.spring {
            SpringSpec::Linear { kn } => keys.push(kn.given("kn", "kn_over_rho_g")),
            SpringSpec::Hertz { young, poisson } => {
                keys.push(("young", Given::Number(young)));
                keys.push(("poisson", Given::Number(poisson)));
            }
        }
        keys
    }
}

//! Contact parameters as a case gives them, and their resolution into a [`Law`] — its parts —
//! for one pair.
//!
//! Stiffness and damping may be absolute (per unit thickness) or normalised by ρg, as P gives
//! them (`K_n/ρg` in cm): then they are multiplied by the pair's density ([`pair_density`]) and
//! |g|, and in a scene of one density ρ cancels from every equation of motion.

use super::{
    DampingPart, Law, NormalForce, NormalPart, RollingPart, ShearStiffness, TangentialPart,
    damping_factor_hertz, damping_ratio_linear,
};

/// The density a pair's parameters given per ρg are scaled by: the mean of the two bodies'
/// (`rho_j` None: a body against a wall, the body's own).
#[inline]
pub fn pair_density(rho_i: f64, rho_j: Option<f64>) -> f64 {
    match rho_j {
        Some(r) => 0.5 * (rho_i + r),
        None => rho_i,
    }
}

/// A value given absolutely or divided by ρg.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scaled {
    Absolute(f64),
    OverRhoG(f64),
}

impl Scaled {
    /// The absolute value for density `rho` and gravity magnitude `g`.
    #[inline]
    pub fn value(&self, rho: f64, g: f64) -> f64 {
        match *self {
            Scaled::Absolute(v) => v,
            Scaled::OverRhoG(v) => v * rho * g,
        }
    }
}

/// How a linear contact is damped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinearDamping {
    /// Given dashpots.
    Dashpots { eta_n: Scaled, eta_s: Scaled },
    /// From a coefficient of restitution: `η_n = 2α√(m* k_n)` (T12), `η_s = η_n`.
    Restitution(f64),
}

/// The law and its parameters, as given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactSpec {
    Linear {
        kn: Scaled,
        ks: Scaled,
        damping: LinearDamping,
        friction: f64,
        normal_force: NormalForce,
        rolling: Option<RollingPart>,
    },
    HertzMindlin {
        young: f64,
        poisson: f64,
        restitution: f64,
        friction: f64,
        normal_force: NormalForce,
        rolling: Option<RollingPart>,
    },
}

impl ContactSpec {
    /// What the normal spring acts on.
    pub fn normal_force(&self) -> NormalForce {
        match *self {
            ContactSpec::Linear { normal_force, .. }
            | ContactSpec::HertzMindlin { normal_force, .. } => normal_force,
        }
    }

    /// The same spec with the normal spring acting on `normal_force`.
    pub fn with_normal_force(mut self, normal_force: NormalForce) -> Self {
        match &mut self {
            ContactSpec::Linear {
                normal_force: n, ..
            }
            | ContactSpec::HertzMindlin {
                normal_force: n, ..
            } => *n = normal_force,
        }
        self
    }

    /// Rolling resistance, if any.
    pub fn rolling(&self) -> Option<RollingPart> {
        match *self {
            ContactSpec::Linear { rolling, .. } | ContactSpec::HertzMindlin { rolling, .. } => {
                rolling
            }
        }
    }

    /// The same spec with rolling resistance `rolling`.
    pub fn with_rolling(mut self, rolling: Option<RollingPart>) -> Self {
        match &mut self {
            ContactSpec::Linear { rolling: r, .. }
            | ContactSpec::HertzMindlin { rolling: r, .. } => *r = rolling,
        }
        self
    }

    /// Coulomb friction coefficient.
    pub fn friction(&self) -> f64 {
        match *self {
            ContactSpec::Linear { friction, .. } | ContactSpec::HertzMindlin { friction, .. } => {
                friction
            }
        }
    }

    /// The law for a pair: `self` is the spec that governs the pair (a wall's own, when it
    /// overrides), `other_material` the spec of the other side's material (Hertz–Mindlin mixes
    /// the two materials, T11, T19); `rho` the pair's density, `g` = |gravity|, `m_eff` = m*.
    pub fn resolve(&self, other_material: &ContactSpec, rho: f64, g: f64, m_eff: f64) -> Law {
        match *self {
            ContactSpec::Linear {
                kn,
                ks,
                damping,
                friction,
                rolling,
                ..
            } => {
                let kn = kn.value(rho, g);
                let (eta_n, eta_s) = match damping {
                    LinearDamping::Dashpots { eta_n, eta_s } => {
                        (eta_n.value(rho, g), eta_s.value(rho, g))
                    }
                    LinearDamping::Restitution(e) => {
                        let eta = 2.0 * damping_ratio_linear(e) * (m_eff * kn).sqrt(); // T(12)
                        (eta, eta)
                    }
                };
                Law {
                    normal: NormalPart::Linear { kn },
                    damping: DampingPart::Dashpots { eta_n, eta_s },
                    tangential: TangentialPart {
                        stiffness: ShearStiffness::Constant(ks.value(rho, g)),
                        friction,
                    },
                    rolling,
                }
            }
            ContactSpec::HertzMindlin {
                young,
                poisson,
                restitution,
                friction,
                rolling,
                ..
            } => {
                let (e2, nu2) = match *other_material {
                    ContactSpec::HertzMindlin { young, poisson, .. } => (young, poisson),
                    ContactSpec::Linear { .. } => (young, poisson),
                };
                let e_star = 1.0 / ((1.0 - poisson * poisson) / young + (1.0 - nu2 * nu2) / e2); // T(11)
                let g_star = 1.0
                    / (2.0 * (2.0 - poisson) * (1.0 + poisson) / young
                        + 2.0 * (2.0 - nu2) * (1.0 + nu2) / e2); // T(19)
                Law {
                    normal: NormalPart::Hertz { e_star },
                    damping: DampingPart::Hertz {
                        beta: damping_factor_hertz(restitution),
                    },
                    tangential: TangentialPart {
                        stiffness: ShearStiffness::Mindlin { g_star },
                        friction,
                    },
                    rolling,
                }
            }
        }
    }

    /// True when the resolved law depends on the pair's effective mass (restitution-tuned
    /// linear dashpots), so that it cannot be resolved once for every pair.
    pub fn depends_on_mass(&self) -> bool {
        matches!(
            self,
            ContactSpec::Linear {
                damping: LinearDamping::Restitution(_),
                ..
            }
        )
    }
}

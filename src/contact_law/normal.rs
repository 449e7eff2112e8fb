//! The normal part of a contact law: the spring on the overlap it acts on (the depth δ, or the
//! area law's equivalent overlap δ_eq — see [`super::Kinematics::spring_overlap`]).
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

//! Contacts between two materials: the pair's parameters from each material's, by one rule per
//! parameter (each part's [`super::Part::mix`], which [`super::ContactSpec::mix`] applies), unless the case gives the pair its own (a case's `pairs`,
//! as LIGGGHTS's per-type-pair matrices).
//!
//! # The rules
//! - **Friction** μ and **rolling friction** μ_r: the smaller of the two (Yade's
//!   `Ip2_FrictMat_FrictMat_FrictPhys`: the contact's friction angle is the smaller material's,
//!   and μ = tan φ grows with φ). A material without rolling resistance has μ_r = 0: the pair
//!   has none.
//! - **Stiffnesses and dashpots** (`kn`, `ks`, `eta_n`, `eta_s`, and their per-ρg forms), the
//!   **restitution** and the **rolling damping** ratio: the harmonic mean `2ab/(a + b)`
//!   (MercuryDPM's default mixed species, `BaseSpecies::average`; Yade's
//!   `Ip2_ViscElMat_ViscElMat_ViscElPhys` for `kn`, `ks`, `en`, `et`): two springs of k in
//!   series are k/2, so the harmonic mean — twice the series stiffness — keeps a material's own
//!   value for contacts with itself, and the softer material dominates.
//! - **Young's modulus and Poisson's ratio** (Hertz–Mindlin): not averaged; the contact moduli
//!   E* and G* are formed from both materials' (T11, T19), as for a wall of another material.
//! - **Cohesion** `c`: the geometric mean `√(c_a c_b)` (Berthelot's rule; surface energies
//!   combine so, `W_ab = 2√(γ_a γ_b)`, Girifalco & Good 1957); a material without cohesion has
//!   c = 0: the pair has none.
//! - The **model** and **normal force** are the scene's (`contact`): a material cannot change
//!   them.
//!
//! Two values given in different forms (`kn` and `kn_over_rho_g`; dashpots and a
//! restitution; two rolling models; one rolling damping given and one not) have no rule: the
//! pair must then be given ([`MixError`] names the key). A material paired with itself keeps its
//! own parameters exactly (`a == b` gives `a`, bit for bit).

use super::params::Scaled;

/// Two materials' values of a key that no rule combines: the key.
#[derive(Clone, Debug, PartialEq)]
pub struct MixError {
    /// The key whose two values have no common rule.
    pub key: &'static str,
    /// Why.
    pub message: String,
}

impl MixError {
    pub(crate) fn new(key: &'static str, message: impl Into<String>) -> Self {
        MixError {
            key,
            message: message.into(),
        }
    }
}

/// The harmonic mean `2ab/(a + b)` (MercuryDPM's `BaseSpecies::average`; 0 if either is 0);
/// exactly `a` when `a == b`.
#[inline]
pub fn harmonic(a: f64, b: f64) -> f64 {
    if a == b {
        a
    } else if a == 0.0 || b == 0.0 {
        0.0
    } else {
        2.0 / (1.0 / a + 1.0 / b)
    }
}

/// The harmonic mean of two values given the same way (absolute, or per ρg); `key` the
/// absolute form's name, for the error when they are given differently.
pub(crate) fn harmonic_scaled(a: Scaled, b: Scaled, key: &'static str) -> Result<Scaled, MixError> {
    match (a, b) {
        (Scaled::Absolute(x), Scaled::Absolute(y)) => Ok(Scaled::Absolute(harmonic(x, y))),
        (Scaled::OverRhoG(x), Scaled::OverRhoG(y)) => Ok(Scaled::OverRhoG(harmonic(x, y))),
        (Scaled::Absolute(_), Scaled::OverRhoG(_)) | (Scaled::OverRhoG(_), Scaled::Absolute(_)) => {
            Err(MixError::new(
                key,
                format!("one material gives `{key}` and the other `{key}_over_rho_g`"),
            ))
        }
    }
}

//! Parameters given per ρg, and the density a pair's are scaled by.
//!
//! Stiffness and damping may be absolute (per unit thickness) or normalised by ρg, as P gives
//! them (`K_n/ρg` in cm): then they are multiplied by the pair's density ([`pair_density`]) and
//! |g|, and in a scene of one density ρ cancels from every equation of motion.

/// A key's value as a part gives it back for a case file ([`super::ContactSpec`]'s parts'
/// `given`): what the case reader reads back to the same part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Given {
    Number(f64),
    Text(&'static str),
}
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

impl Scaled {
    /// The key and value as a case file gives it: `abs` for an absolute value, `rel` per ρg.
    pub fn given(&self, abs: &'static str, rel: &'static str) -> (&'static str, Given) {
        match *self {
            Scaled::Absolute(v) => (abs, Given::Number(v)),
            Scaled::OverRhoG(v) => (rel, Given::Number(v)),
        }
    }
}

//! The damping part of a contact law: the normal and shear dashpots, given or derived from a
//! coefficient of restitution (T12, T14).

use super::normal::NormalSpring;

/// The dashpots of a contact, resolved for one pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DampingPart {
    /// Constant dashpots `η_n`, `η_s`: given, or from a restitution coefficient for the linear
    /// spring, `η_n = η_s = 2α√(m* k_n)` with α of T12 (resolved once per pair: k_n is
    /// constant).
    Dashpots { eta_n: f64, eta_s: f64 },
    /// Hertz: `η_n = β √(m* k_n)` with the current `k_n` (T14), `η_t = η_n`.
    Hertz { beta: f64 },
}

impl DampingPart {
    /// The normal dashpot for the spring `s` and the effective mass `m_eff` (m*, T13).
    #[inline]
    pub fn normal(&self, s: &NormalSpring, m_eff: f64) -> f64 {
        match *self {
            DampingPart::Dashpots { eta_n, .. } => eta_n,
            DampingPart::Hertz { beta } => hertz_dashpot(beta, m_eff, s.k),
        }
    }

    /// The shear dashpot, given the normal one `eta_n`.
    #[inline]
    pub fn tangential(&self, eta_n: f64) -> f64 {
        match *self {
            DampingPart::Dashpots { eta_s, .. } => eta_s,
            DampingPart::Hertz { .. } => eta_n, // η_t = η_n (T)
        }
    }

    /// The damping ratio of the normal mode, `ζ = η_n / (2√(m* k_n))`: the rolling dashpot takes
    /// it when none is given (see [`super::rolling`]).
    #[inline]
    pub fn ratio(&self, s: &NormalSpring, m_eff: f64) -> f64 {
        match *self {
            DampingPart::Dashpots { eta_n, .. } => eta_n / (2.0 * (m_eff * s.k).sqrt()),
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

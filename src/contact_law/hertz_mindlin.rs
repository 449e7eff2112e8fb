//! Hertz normal and Mindlin tangential springs with dashpots from the coefficient of restitution
//! (T10–T14, T18–T20).
//!
//! These are T's sphere formulas, used as written with forces per unit thickness — what 2D DEM
//! codes commonly do with disks; the exact 2D (line-contact) Hertz law has a logarithmic term and
//! no such simple form.

use super::{ContactForce, History, Kinematics, coulomb};

/// Hertz–Mindlin parameters for a pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HertzMindlin {
    /// `E*` with `1/E* = (1−ν_i²)/E_i + (1−ν_j²)/E_j` (T11).
    pub e_star: f64,
    /// `G*` with `1/G* = 2(2−ν_i)(1+ν_i)/E_i + 2(2−ν_j)(1+ν_j)/E_j` (T19).
    pub g_star: f64,
    /// β of T14 from the restitution coefficient.
    pub beta: f64,
    /// Coulomb friction coefficient μ.
    pub friction: f64,
}

impl HertzMindlin {
    /// `k_n = 4/3 E* √(R* δ)` (T10), `F_n = max(0, k_n δ − η_n v_n)` with
    /// `η_n = β √(m* k_n)` (T14), on the spring's overlap ([`Kinematics::spring_overlap`]: the
    /// depth, or the area law's `F_n = max(0, ρ k_n δ_eq + η_n δ̇_eq)`, with R* the
    /// equal-area disks'); `k_t = 8 G* √(R* δ)` (T18), `η_t = η_n`,
    /// `F_t = −k_t δ_t − η_t v_t` (T15) limited by `μ F_n` (T20).
    /// Elastic energy `∫F dδ = (2/5) k_n δ²` plus `½ k_t δ_t²`.
    #[inline]
    pub fn force(&self, k: &Kinematics, h: &mut History) -> ContactForce {
        let o = k.spring_overlap();
        let root = (k.r_eff * o.depth.max(0.0)).sqrt();
        let kn = 4.0 / 3.0 * self.e_star * root; // T(10)
        let eta_n = self.beta * (k.m_eff * kn).sqrt(); // T(14)
        let spring = o.rho * (kn * o.depth);
        let fn_ = (spring + eta_n * o.rate).max(0.0);
        // dF_n/dδ = (3/2) k_n ρ² for the time-step estimate.
        let mut out = ContactForce {
            normal: fn_,
            normal_non_elastic: fn_ - spring,
            elastic_energy: 0.4 * kn * o.depth * o.energy_depth,
            kn: 1.5 * kn * o.rho * o.rho,
            eta_n: eta_n * o.rho,
            ..Default::default()
        };
        (out.couple, out.couple_non_elastic) = o.couple(kn * o.depth, eta_n);
        if self.friction > 0.0 {
            let kt = 8.0 * self.g_star * root; // T(18)
            let before = 0.5 * kt * h.shear * h.shear;
            h.shear += k.vt * k.dt; // T(16)
            let trial = -kt * h.shear - eta_n * k.vt; // T(15), η_t = η_n
            let (ft, sliding) = coulomb(trial, self.friction * fn_, kt, h);
            out.tangential = ft;
            out.sliding = sliding;
            out.shear_energy = 0.5 * kt * h.shear * h.shear;
            out.shear_energy_change = out.shear_energy - before;
            out.elastic_energy += out.shear_energy;
            out.kt = kt;
            out.eta_t = eta_n;
        }
        out
    }
}

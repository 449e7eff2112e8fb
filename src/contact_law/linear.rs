//! The linear Voigt contact of P §3 (T6 and T15 with constant springs): normal spring and
//! dashpot, shear spring and dashpot, Coulomb slider.

use super::{ContactForce, History, Kinematics, coulomb};

/// Linear spring–dashpot parameters, per unit thickness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Linear {
    /// Normal spring `k_n`.
    pub kn: f64,
    /// Shear spring `k_s`.
    pub ks: f64,
    /// Normal dashpot `η_n`.
    pub eta_n: f64,
    /// Shear dashpot `η_s`.
    pub eta_s: f64,
    /// Coulomb friction coefficient μ (0: no shear force and no shear history at all).
    pub friction: f64,
}

impl Linear {
    /// `F_n = max(0, k_n δ − η_n v_n)` (T6, clamped so that the contact never pulls) on the
    /// spring's overlap ([`Kinematics::spring_overlap`]: the depth, or the area law's
    /// `F_n = max(0, ρ k_n δ_eq + η_n δ̇_eq)`);
    /// `F_t = −k_s δ_t − η_s v_t` (T15) with `δ_t += v_t Δt` (T16), limited by `μ F_n` (T20).
    /// Elastic energy `½k_n δ² + ½k_s δ_t²` (with `δ²` → `δ·energy_depth`).
    #[inline]
    pub fn force(&self, k: &Kinematics, h: &mut History) -> ContactForce {
        let o = k.spring_overlap();
        let spring = o.rho * (self.kn * o.depth);
        let fn_ = (spring + self.eta_n * o.rate).max(0.0); // T(6)
        let mut out = ContactForce {
            normal: fn_,
            normal_non_elastic: fn_ - spring,
            elastic_energy: 0.5 * self.kn * o.depth * o.energy_depth,
            kn: self.kn * o.rho * o.rho,
            eta_n: self.eta_n * o.rho,
            ..Default::default()
        };
        (out.couple, out.couple_non_elastic) = o.couple(self.kn * o.depth, self.eta_n);
        if self.friction > 0.0 {
            let before = 0.5 * self.ks * h.shear * h.shear;
            h.shear += k.vt * k.dt; // T(16)
            let trial = -self.ks * h.shear - self.eta_s * k.vt; // T(15)
            let (ft, sliding) = coulomb(trial, self.friction * fn_, self.ks, h);
            out.tangential = ft;
            out.sliding = sliding;
            out.shear_energy = 0.5 * self.ks * h.shear * h.shear;
            out.shear_energy_change = out.shear_energy - before;
            out.elastic_energy += out.shear_energy;
            out.kt = self.ks;
            out.eta_t = self.eta_s;
        }
        out
    }
}

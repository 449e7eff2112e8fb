//! Impact benchmarks after Chung & Ooi (Granular Matter 13 (2011) 643–656), adapted to a 2D
//! disk (unit thickness, `m = ρπr²`, `I = m r²/2`) on a wall, with their closed forms.
//!
//! # Normal elastic impact (their tests 1–2), no damping
//! - **Linear spring** `F = k_n δ`: a half period of the harmonic oscillator,
//!   contact time `t_c = π √(m*/k_n)`, peak overlap `δ_max = v √(m*/k_n)` (m* = m on a wall).
//! - **Hertz as dem2d implements it** (T10, the sphere formula per unit thickness,
//!   `F = (4/3) E* √R* δ^{3/2}` with `E* = [(1−ν₁²)/E₁ + (1−ν₂²)/E₂]⁻¹`, the wall of the
//!   same material, R* = r): energy `½ m v² = (8/15) E* √R* δ_max^{5/2}` gives
//!   `δ_max = (15 m v² / (16 E* √R*))^{2/5}`; the time `t_c = 2 ∫₀^{δ_max} dδ / v(δ)` with
//!   `v(δ) = v √(1 − (δ/δ_max)^{5/2})` is `t_c = (2 δ_max / v) ∫₀¹ (1 − x^{5/2})^{−1/2} dx
//!   = (2 δ_max/v) · Γ(2/5) Γ(1/2) / ((5/2) Γ(9/10)) = 2.943275… δ_max/v`.
//!
//! # Oblique impact at constant speed (their test 4), rigid-body Coulomb theory
//! A disk hits the wall with normal speed v_n, tangential speed v_t = v_n tan θ (θ the
//! incidence angle from the normal), no spin. Normal impulse `P_n = m(1+e) v_n`; a tangential
//! impulse P_t opposes the contact point's slip `s = v_t + r ω` and changes it by
//! `Δs = −P_t (1/m + r²/I) = −3 P_t/m` (`1 + m r²/I = 3` for a disk):
//! - **sliding** throughout when `v_t > 3 μ (1+e) v_n`, i.e. `tan θ > 3μ(1+e)`: `P_t = μ P_n`,
//!   `v_t' = v_t − μ(1+e)v_n`, `ω' = −2 μ (1+e) v_n / r` (clockwise for a disk moving to +x on a
//!   floor), rebound angle `tan θ' = v_t'/(e v_n)`;
//! - **sticking** (slip arrested before separation) otherwise: `v_t' = (2/3) v_t`,
//!   `r ω' = −v_t'`. A code with a tangential spring departs from this limit (the spring's
//!   elastic recoil), which is what the test shows; it is exact only in the sliding regime.
//!
//! The simulations run a single disk through the run driver (no gravity) and measure the
//! contact from the exact disk–wall overlap `δ = r − y`: start and end of contact by linear
//! interpolation of δ between steps, the peak as the largest δ sampled (its error is of order
//! `(ω Δt)²`). The lever arm of the friction force is the distance from the centre to the
//! chord midpoint, `r − δ`, not r: the spin differs from the rigid theory by at most δ_max/r.

use dem2d::dynamics::World;
use dem2d::run::{RunError, Simulation};
use dem2d::scene::Case;

/// What one impact gave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// Contact time (s) and peak overlap (cm).
    pub contact_time: f64,
    pub peak_overlap: f64,
    /// Rebound: normal and tangential velocity (cm/s), spin (rad/s).
    pub vn: f64,
    pub vt: f64,
    pub omega: f64,
    pub steps: u64,
}

/// The disk of the benchmarks: radius (cm), density (g/cm³).
pub const RADIUS: f64 = 1.0;
pub const DENSITY: f64 = 2.5;

/// Mass per unit thickness `ρπr²` (g/cm).
pub fn mass() -> f64 {
    DENSITY * std::f64::consts::PI * RADIUS * RADIUS
}

/// Runs a disk hitting the floor y = 0 at normal speed `vn` (> 0, downwards) and tangential speed
/// `vt` under the contact law `contact` (a case's `"contact"` object), with step `dt`.
pub fn disk_on_floor(
    contact: &serde_json::Value,
    vn: f64,
    vt: f64,
    dt: f64,
) -> Result<Impact, RunError> {
    let text = serde_json::json!({
        "version": 1, "name": "impact", "gravity": [0.0, 0.0], "dt": dt, "duration": 1.0,
        "contact": contact,
        "walls": [{"point": [0.0, 0.0], "normal": [0.0, 1.0]}],
        "bodies": [{"shape": {"type": "circle", "r": RADIUS}, "position": [0.0, RADIUS],
                    "velocity": [vt, -vn], "density": DENSITY}]
    })
    .to_string();
    let case = Case::from_json(&text).expect("the benchmark's case is valid");
    let mut w = case.build_world();
    let depth = |w: &World| RADIUS - w.bodies.state[0].pose.position.y;
    let (mut t0, mut t1, mut peak) = (None, None, 0.0f64);
    let mut last = depth(&w);
    let mut steps = 0;
    Simulation::new(&mut w)
        .for_steps(10_000_000)
        .run_until(|w, _| {
            steps += 1;
            let d = depth(w);
            let t = w.time;
            if t0.is_none() && last <= 0.0 && d > 0.0 {
                t0 = Some(t - dt * d / (d - last));
            }
            if t0.is_some() && last > 0.0 && d <= 0.0 {
                t1 = Some(t - dt * d / (d - last));
            }
            peak = peak.max(d);
            last = d;
            t1.is_some()
        })?;
    // Run on a little so that the contact has surely opened.
    Simulation::new(&mut w).for_steps(10).run()?;
    let s = &w.bodies.state[0];
    Ok(Impact {
        contact_time: t1.unwrap_or(f64::NAN) - t0.unwrap_or(f64::NAN),
        peak_overlap: peak,
        vn: s.vel.y,
        vt: s.vel.x,
        omega: s.omega,
        steps,
    })
}

/// The linear law of the normal benchmark: `k_n` (dyn/cm per cm), no damping, no friction.
pub fn linear_law(kn: f64, friction: f64) -> serde_json::Value {
    serde_json::json!({"model": "linear", "normal_force": "depth", "kn": kn, "ks": kn,
                       "eta_n": 0.0, "eta_s": 0.0, "friction": friction})
}

/// The Hertz–Mindlin law of the normal benchmark (E in dyn/cm², ν), elastic (e = 1).
pub fn hertz_law(young: f64, poisson: f64) -> serde_json::Value {
    serde_json::json!({"model": "hertz_mindlin", "normal_force": "depth", "young": young,
                       "poisson": poisson, "restitution": 1.0, "friction": 0.0})
}

/// Linear law: `(t_c, δ_max) = (π √(m/k_n), v √(m/k_n))`.
pub fn linear_reference(kn: f64, v: f64) -> (f64, f64) {
    let s = (mass() / kn).sqrt();
    (std::f64::consts::PI * s, v * s)
}

/// `2 Γ(2/5) Γ(1/2) / ((5/2) Γ(9/10))`: Hertz's contact time over `δ_max/v`.
pub const HERTZ_TIME_FACTOR: f64 = 2.943_275_184_324_704;

/// Hertz (wall of the same material): `(t_c, δ_max)`.
pub fn hertz_reference(young: f64, poisson: f64, v: f64) -> (f64, f64) {
    let e_star = young / (2.0 * (1.0 - poisson * poisson));
    let d = (15.0 * mass() * v * v / (16.0 * e_star * RADIUS.sqrt())).powf(0.4);
    (HERTZ_TIME_FACTOR * d / v, d)
}

/// Rigid-body Coulomb theory for the oblique impact: `(v_t', ω', sliding)` for normal speed
/// `vn`, tangential `vt` (≥ 0), restitution `e`, friction `mu`.
pub fn oblique_reference(vn: f64, vt: f64, e: f64, mu: f64) -> (f64, f64, bool) {
    if vt > 3.0 * mu * (1.0 + e) * vn {
        let vt1 = vt - mu * (1.0 + e) * vn;
        (vt1, -2.0 * mu * (1.0 + e) * vn / RADIUS, true)
    } else {
        let vt1 = 2.0 / 3.0 * vt;
        (vt1, -vt1 / RADIUS, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hertz_time_factor_is_the_integral_it_stands_for() {
        // ∫₀¹ (1 − x^{5/2})^{−1/2} dx with x = (1 − u²)^{2/5}, u = sin φ:
        // = ∫₀^{π/2} (4/5) cos(φ)^{−1/5} dφ, a mild singularity at π/2 (midpoint rule error
        // of order n^{−4/5}).
        let n = 1_000_000;
        let h = std::f64::consts::FRAC_PI_2 / n as f64;
        let s: f64 = (0..n)
            .map(|k| 0.8 * ((k as f64 + 0.5) * h).cos().powf(-0.2) * h)
            .sum();
        approx::assert_relative_eq!(2.0 * s, HERTZ_TIME_FACTOR, max_relative = 1e-4);
    }

    // The benchmarks against their closed forms (the tolerances' reasons are in the module
    // doc). They were `tests/impacts.rs` while this module was in the library.

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// The contact time and the peak overlap of an elastic normal impact against the closed
    /// forms, and the rebound speed equal to the impact speed.
    fn normal_impact(law: &serde_json::Value, (tc, d): (f64, f64), v: f64) {
        let r = disk_on_floor(law, v, 0.0, tc / 2000.0).unwrap();
        assert!(rel(r.contact_time, tc) < 1e-4, "{r:?} vs {tc}");
        assert!(rel(r.peak_overlap, d) < 1e-4, "{r:?} vs {d}");
        assert!(rel(r.vn, v) < 1e-6, "{r:?}");
    }

    #[test]
    fn a_linear_spring_impact_lasts_half_a_period_and_peaks_at_v_over_omega() {
        let (kn, v) = (1e10, 10.0);
        normal_impact(&linear_law(kn, 0.0), linear_reference(kn, v), v);
    }

    #[test]
    fn a_hertz_impact_matches_hertz_theory_for_the_law_as_implemented() {
        let (e, nu, v) = (7e11, 0.3, 10.0);
        normal_impact(&hertz_law(e, nu), hertz_reference(e, nu, v), v);
    }

    /// In the sliding regime (tan θ > 3μ(1+e)) the rigid-body Coulomb theory is exact: the centre
    /// loses μ(1+e)v_n of its tangential speed and the disk spins at −2μ(1+e)v_n/r. The spin's
    /// tolerance covers the lever arm r − δ of the friction force (≤ δ_max/r ≈ 3e-4).
    #[test]
    fn oblique_impacts_in_the_sliding_regime_follow_rigid_body_coulomb_theory() {
        let (kn, mu, v) = (1e10, 0.1, 10.0);
        for deg in [35.0f64, 50.0, 70.0, 85.0] {
            let th = deg.to_radians();
            let (vn, vt) = (v * th.cos(), v * th.sin());
            let (vt1, w1, sliding) = oblique_reference(vn, vt, 1.0, mu);
            assert!(sliding);
            let (tc, _) = linear_reference(kn, vn);
            let r = disk_on_floor(&linear_law(kn, mu), vn, vt, tc / 2000.0).unwrap();
            assert!(rel(r.vt, vt1) < 1e-6, "{deg}°: {r:?} vs v_t' = {vt1}");
            assert!(rel(r.omega, w1) < 1e-3, "{deg}°: {r:?} vs ω' = {w1}");
            assert!(rel(r.vn, vn) < 1e-6, "{deg}°: {r:?}");
        }
    }
}

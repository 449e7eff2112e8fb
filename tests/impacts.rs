//! Impact benchmarks (Chung & Ooi 2011, adapted to a 2D disk on a wall) against their closed
//! forms: see `dem2d::validation::impact` for the derivations and the tolerances' reasons.

use dem2d::validation::impact::{self, disk_on_floor};

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn a_linear_spring_impact_lasts_half_a_period_and_peaks_at_v_over_omega() {
    let (kn, v) = (1e10, 10.0);
    let (tc, d) = impact::linear_reference(kn, v);
    let r = disk_on_floor(&impact::linear_law(kn, 0.0), v, 0.0, tc / 2000.0).unwrap();
    assert!(rel(r.contact_time, tc) < 1e-4, "{r:?} vs {tc}");
    assert!(rel(r.peak_overlap, d) < 1e-4, "{r:?} vs {d}");
    assert!(rel(r.vn, v) < 1e-6, "{r:?}");
}

#[test]
fn a_hertz_impact_matches_hertz_theory_for_the_law_as_implemented() {
    let (e, nu, v) = (7e11, 0.3, 10.0);
    let (tc, d) = impact::hertz_reference(e, nu, v);
    let r = disk_on_floor(&impact::hertz_law(e, nu), v, 0.0, tc / 2000.0).unwrap();
    assert!(rel(r.contact_time, tc) < 1e-4, "{r:?} vs {tc}");
    assert!(rel(r.peak_overlap, d) < 1e-4, "{r:?} vs {d}");
    assert!(rel(r.vn, v) < 1e-6, "{r:?}");
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
        let (vt1, w1, sliding) = impact::oblique_reference(vn, vt, 1.0, mu);
        assert!(sliding);
        let (tc, _) = impact::linear_reference(kn, vn);
        let r = disk_on_floor(&impact::linear_law(kn, mu), vn, vt, tc / 2000.0).unwrap();
        assert!(rel(r.vt, vt1) < 1e-6, "{deg}°: {r:?} vs v_t' = {vt1}");
        assert!(rel(r.omega, w1) < 1e-3, "{deg}°: {r:?} vs ω' = {w1}");
        assert!(rel(r.vn, vn) < 1e-6, "{deg}°: {r:?}");
    }
}

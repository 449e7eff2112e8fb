//! Impact benchmarks (Chung & Ooi 2011, tests 1–2 and 4, adapted to a 2D disk on a wall):
//! normal elastic impact against the closed forms of the linear and Hertz springs, oblique
//! impact at constant speed across incidence angles against rigid-body Coulomb theory.
//! See [`crate::impact`] for the formulas.
//!
//! `dem2d study impacts` prints the tables and writes `figures/impacts.svg` (and `.png` into
//! `target/figure-png/`), `figures/impacts.md`.

use crate::impact::{self, Impact};
use dem2d::output::plot::{LinePanel, Series};
use dem2d::run::RunError;
use std::fmt::Write as _;
use std::time::Instant;

/// Linear normal stiffness (dyn/cm per cm) and the Hertz material (E in dyn/cm², ν).
pub const KN: f64 = 1e10;
pub const YOUNG: f64 = 7e11;
pub const POISSON: f64 = 0.3;
/// Speeds (cm/s) and the oblique test's friction.
pub const V_NORMAL: f64 = 10.0;
pub const V_OBLIQUE: f64 = 10.0;
pub const MU: f64 = 0.1;

/// One row of the comparisons: quantity, dem2d, reference, relative tolerance.
pub type Row = (String, f64, f64, f64);

/// The normal impacts: contact time and peak overlap for the linear and Hertz springs.
pub fn normal_rows() -> Result<Vec<Row>, RunError> {
    let mut rows = Vec::new();
    for (name, law, (tc, d)) in [
        (
            "linear",
            impact::linear_law(KN, 0.0),
            impact::linear_reference(KN, V_NORMAL),
        ),
        (
            "Hertz",
            impact::hertz_law(YOUNG, POISSON),
            impact::hertz_reference(YOUNG, POISSON, V_NORMAL),
        ),
    ] {
        let r = impact::disk_on_floor(&law, V_NORMAL, 0.0, tc / 2000.0)?;
        rows.push((
            format!("{name}: contact time (s)"),
            r.contact_time,
            tc,
            1e-4,
        ));
        rows.push((
            format!("{name}: peak overlap (cm)"),
            r.peak_overlap,
            d,
            1e-4,
        ));
        rows.push((
            format!("{name}: rebound speed / impact speed"),
            r.vn / V_NORMAL,
            1.0,
            1e-6,
        ));
    }
    Ok(rows)
}

/// The oblique impact at incidence `deg` (degrees from the normal).
pub fn oblique(deg: f64) -> Result<Impact, RunError> {
    let th = deg.to_radians();
    let (vn, vt) = (V_OBLIQUE * th.cos(), V_OBLIQUE * th.sin());
    let (tc, _) = impact::linear_reference(KN, vn);
    impact::disk_on_floor(&impact::linear_law(KN, MU), vn, vt, tc / 2000.0)
}

/// The oblique impacts in the sliding regime at the given angles: v_t' and ω' against the rigid
/// theory. Tolerance: the friction's lever arm is r − δ, not r (≤ δ_max/r = 3e-4 here), and
/// the time discretisation.
pub fn oblique_rows(angles: &[f64]) -> Result<Vec<Row>, RunError> {
    let mut rows = Vec::new();
    for &deg in angles {
        let th = deg.to_radians();
        let (vn, vt) = (V_OBLIQUE * th.cos(), V_OBLIQUE * th.sin());
        let (vt1, w1, sliding) = impact::oblique_reference(vn, vt, 1.0, MU);
        assert!(sliding, "{deg}° is not in the sliding regime");
        let r = oblique(deg)?;
        rows.push((format!("oblique {deg}°: v_t' (cm/s)"), r.vt, vt1, 1e-3));
        rows.push((format!("oblique {deg}°: ω' (rad/s)"), r.omega, w1, 1e-3));
    }
    Ok(rows)
}

fn table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| quantity | dem2d | closed form | relative error | tolerance |\n|---|---:|---:|---:|---:|\n",
    );
    for (q, v, r, tol) in rows {
        writeln!(
            s,
            "| {q} | {v:.6e} | {r:.6e} | {:.1e} | {tol:.0e} |",
            ((v - r) / r).abs()
        )
        .expect("string");
    }
    s
}

pub fn run() -> Result<String, RunError> {
    let start = Instant::now();
    let mut rows = normal_rows()?;
    rows.extend(oblique_rows(&[40.0, 60.0, 80.0])?);
    // The sweep of the figure.
    let angles: Vec<f64> = (1..=17).map(|k| 5.0 * k as f64).collect();
    let theta_c = (3.0 * MU * 2.0f64).atan().to_degrees();
    let mut sim = [Vec::new(), Vec::new(), Vec::new()];
    let mut steps = 0;
    for &deg in &angles {
        let r = oblique(deg)?;
        steps += r.steps;
        let th = deg.to_radians();
        let (vn, vt) = (V_OBLIQUE * th.cos(), V_OBLIQUE * th.sin());
        sim[0].push((deg, r.vt / vt));
        sim[1].push((deg, impact::RADIUS * r.omega / vn));
        sim[2].push((deg, (r.vt / r.vn).atan().to_degrees()));
    }
    let fine: Vec<f64> = (10..=890).map(|k| k as f64 * 0.1).collect();
    let mut theory = [Vec::new(), Vec::new(), Vec::new()];
    for &deg in &fine {
        let th = deg.to_radians();
        let (vn, vt) = (V_OBLIQUE * th.cos(), V_OBLIQUE * th.sin());
        let (vt1, w1, _) = impact::oblique_reference(vn, vt, 1.0, MU);
        theory[0].push((deg, vt1 / vt));
        theory[1].push((deg, impact::RADIUS * w1 / vn));
        theory[2].push((deg, (vt1 / vn).atan().to_degrees()));
    }
    let wall = start.elapsed().as_secs_f64();
    let titles = [
        ("Tangential restitution v_t'/v_t", "v_t'/v_t (–)"),
        ("Rebound spin", "r ω'/v_n (–)"),
        ("Rebound angle of the centre", "θ' (degrees)"),
    ];
    let panels: Vec<LinePanel> = (0..3)
        .map(|k| LinePanel {
            title: titles[k].0.into(),
            x_label: "incidence angle θ from the normal (degrees)".into(),
            y_label: titles[k].1.into(),
            series: vec![
                Series::line("rigid-body Coulomb theory", theory[k].clone(), 0),
                Series {
                    label: "dem2d (linear spring, k_t = k_n)".into(),
                    points: sim[k].clone(),
                    color: 1,
                    markers: true,
                    ..Default::default()
                },
            ],
            vlines: vec![(theta_c, format!("sliding above {theta_c:.1}°"))],
            x_range: Some((0.0, 90.0)),
            ..Default::default()
        })
        .collect();
    super::write_figure("impacts", (1500, 480), (1, 3), &panels)?;
    let mut md = table(&rows);
    writeln!(
        md,
        "\nDisk r = {} cm, ρ = {} g/cm³ (m = {:.4} g per cm of thickness, I = m r²/2), wall y = 0; \
         linear k_n = {KN:e} dyn/cm (of a 1 cm slice: dyn per cm of thickness per cm of overlap), Hertz E = {YOUNG:e} dyn/cm², ν = {POISSON} (the wall of the \
         same material), normal speed {V_NORMAL} cm/s; oblique at {V_OBLIQUE} cm/s, μ = {MU}, e = 1, \
         k_t = k_n; Δt = t_c/2000. Oblique sweep: {} impacts, {steps} steps.",
        impact::RADIUS,
        impact::DENSITY,
        impact::mass(),
        angles.len(),
    )
    .expect("string");
    super::write_text("impacts.md", &md)?;
    print!("{md}");
    // The machine's share stays out of the tracked table.
    eprintln!(
        "oblique sweep: wall time {wall:.2} s (one body: {:.2e} particle-steps/s)",
        steps as f64 / wall
    );
    Ok(md)
}

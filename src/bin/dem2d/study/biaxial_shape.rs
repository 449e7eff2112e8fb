//! Biaxial compression of dense samples of ellipses against their aspect ratio α.
//!
//! `dem2d study biaxial-shape` (α = 1, 1.5, 2, 2.5; 400 grains each: what runs in minutes on two
//! shared cores, not the few thousand of the literature) writes `figures/biaxial_shape.svg`
//! and `figures/biaxial_shape.md` and prints the table.
//!
//! Protocol (per α): the grains of [`ServoBox`] (equal areas: the disk of radius r ∈ [0.8, 1.2]
//! cm, ellipses a = r√α, b = r/√α, random orientations), frictionless walls;
//! 1. **isotropic compaction** by four servo walls to σ_c = 1e5 dyn/cm² with grain friction
//!    [`MU_COMPACTION`] (low, for a dense sample), until the box area changes by less than
//!    1e-5 of itself over 2000 steps with an unbalanced force ratio below 1e-2;
//! 2. **shear** with grain friction [`MU`]: the top and bottom walls approach each other at the
//!    axial strain rate [`STRAIN_RATE`], the side walls servo-controlled at σ_c. Inertial number
//!    `I = ε̇ d √(ρ/σ_c)` with d = 2 cm the mean equal-area diameter.
//!
//! Recorded every 0.5 % of axial strain: stresses from the walls (mean over the interval: the
//! top wall's load over the width, the side walls' over the height), the volumetric strain
//! `ε_v = 1 − A/A₀` (compression positive), the analysis of the state (fabric, packing,
//! coordination). Friction angles `sin φ = (σ₁ − σ₃)/(σ₁ + σ₃)` at the peak and over the last
//! 2 % (residual); dilatancy angle `sin ψ = −ε̇_v/(2ε̇₁ − ε̇_v)` from the slope of ε_v against
//! ε₁ over ±1 % around the peak.

use dem2d::analysis::statistics::mean_se;
use dem2d::analysis::{self, Frame, Measures};
use dem2d::dynamics::World;
use dem2d::dynamics::boundary::span_length;
use dem2d::dynamics::{BodyInit, Span};
use dem2d::output::plot::{self, LinePanel, Series};
use dem2d::output::progress::CommandProgress;
use dem2d::run::{RunError, Simulation};
use dem2d::scene::Case;
use dem2d::scene::servo_box::ServoBox;
use serde_json::json;
use std::fmt::Write as _;
use std::time::Instant;

pub const SIGMA_C: f64 = 1e5;
pub const MU: f64 = 0.5;
pub const MU_COMPACTION: f64 = 0.1;
/// Axial strain rate (1/s): I = 0.08 × 2 × √(2.65/1e5) ≈ 8.2e-4.
pub const STRAIN_RATE: f64 = 0.08;

/// Width, height, axial stress (the top wall's load over the width) and lateral stress (the
/// mean of the side walls' loads over the height) of a servo box (walls: bottom, top, left,
/// right).
pub fn wall_state(w: &World) -> (f64, f64, f64, f64) {
    let width = span_length(w.walls[1].line(), &Span::Between(2, 3), &w.walls);
    let height = span_length(w.walls[2].line(), &Span::Between(0, 1), &w.walls);
    let axial = w.walls[1].load.force.dot(&w.walls[1].line().normal) / width;
    let lateral = 0.5
        * (w.walls[2].load.force.dot(&w.walls[2].line().normal)
            + w.walls[3].load.force.dot(&w.walls[3].line().normal))
        / height;
    (width, height, axial, lateral)
}

/// Steps a servo-compaction world until it is still (see the module documentation) or
/// `max_time` passes; returns the steps taken.
pub fn compact(w: &mut World, max_time: f64) -> Result<u64, RunError> {
    let mut steps = 0;
    let mut last = f64::INFINITY;
    let mut lines = CommandProgress::new(format!("compaction of {} grains", w.bodies.len()));
    let mut sim = Simulation::new(w).observe(&mut lines).for_steps(2000);
    while sim.world().time < max_time {
        sim.run()?;
        steps += 2000;
        let w = sim.world();
        let (width, height, _, _) = wall_state(w);
        let a = width * height;
        if (a - last).abs() < 1e-5 * a && w.unbalanced_ratios().0 < 1e-2 {
            break;
        }
        last = a;
    }
    Ok(steps)
}

/// The box `[x0, x1, y0, y1]` of a servo box's walls (bottom, top, left, right) now.
pub fn box_of(w: &World) -> [f64; 4] {
    [
        w.walls[2].line().point.x,
        w.walls[3].line().point.x,
        w.walls[0].line().point.y,
        w.walls[1].line().point.y,
    ]
}

/// Runs the shear stage of a servo box (`case`'s world `w`) to the case's end; every `every` steps
/// calls `each` with the world and the axial and lateral wall stresses averaged over those
/// steps (see [`wall_state`]).
pub fn run_shear(
    w: &mut World,
    case: &Case,
    every: u64,
    mut each: impl FnMut(&mut World, f64, f64),
) -> Result<(), RunError> {
    let (mut sum, mut count) = ([0.0; 2], 0.0);
    let mut lines = CommandProgress::new(case.name.clone());
    Simulation::new(w)
        .observe(&mut lines)
        .until_step(case.steps())
        .run_each(|w, _| {
            let (_, _, ax, lat) = wall_state(w);
            sum[0] += ax;
            sum[1] += lat;
            count += 1.0;
            if w.step % every == 0 {
                each(w, sum[0] / count, sum[1] / count);
                (sum, count) = ([0.0; 2], 0.0);
            }
        })?;
    Ok(())
}

/// What a biaxial test's curve says (see the module documentation).
#[derive(Clone, Copy, Debug, Default)]
pub struct Summary {
    /// The point of the curve at the peak stress ratio.
    pub peak_index: usize,
    pub peak_ratio: f64,
    pub peak_strain: f64,
    /// The mean stress ratio over the last 2 % of axial strain.
    pub residual_ratio: f64,
    pub dilatancy_deg: f64,
}

/// The peak, residual and dilatancy of a curve of (axial strain, stress ratio, volumetric
/// strain) points.
pub fn summarise(curve: &[(f64, f64, f64)]) -> Summary {
    let (k, &(e1, q, _)) = curve
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.1.total_cmp(&b.1.1))
        .expect("a curve");
    let last = curve.last().expect("a curve").0;
    let tail: Vec<f64> = curve
        .iter()
        .filter(|c| c.0 >= last - 0.02)
        .map(|c| c.1)
        .collect();
    // Slope of ε_v against ε₁ over ±1 % around the peak (least squares).
    let pts: Vec<(f64, f64)> = curve
        .iter()
        .filter(|c| (c.0 - e1).abs() <= 0.0101)
        .map(|c| (c.0, c.2))
        .collect();
    let (_, s) = super::line_fit(&pts);
    Summary {
        peak_index: k,
        peak_ratio: q,
        peak_strain: e1,
        residual_ratio: tail.iter().sum::<f64>() / tail.len() as f64,
        dilatancy_deg: (-s / (2.0 - s)).asin().to_degrees(),
    }
}

/// The bodies of a compacted sample `w` where they are, at rest: the next stage's case.
pub fn at_rest(w: &World) -> Vec<BodyInit> {
    (0..w.bodies.len())
        .map(|k| BodyInit {
            material: 0,
            prescribed: false,
            shape: w.bodies.shape[k],
            position: w.bodies.state[k].pose.position,
            angle: w.bodies.state[k].pose.angle(),
            velocity: dem2d::geometry::Vec2::zeros(),
            omega: 0.0,
            density: w.bodies.density[k],
        })
        .collect()
}

/// One biaxial test.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    pub aspect: f64,
    pub grains: usize,
    /// The shear stage as a case file (the compacted sample at rest, the walls' motion and
    /// servos): `dem2d run` on it repeats the shear.
    pub shear_case: String,
    /// (axial strain, stress ratio, volumetric strain) every 0.5 %.
    pub curve: Vec<(f64, f64, f64)>,
    pub measures: Vec<Measures>,
    pub initial: Measures,
    pub peak_ratio: f64,
    pub peak_strain: f64,
    pub residual_ratio: f64,
    pub dilatancy_deg: f64,
    pub peak_measures: Measures,
    /// The state at the peak (for the force-chain figure).
    pub peak_frame: Frame,
    pub wall_seconds: f64,
    pub particle_steps: f64,
}

/// Compacts and shears a sample of `n_side²` grains of aspect ratio `aspect` to axial strain
/// `strain`, the grains drawn from `seed` (the study's first sample is seed 11).
pub fn run_one(
    n_side: usize,
    aspect: f64,
    strain: f64,
    seed: u64,
    verbose: bool,
) -> Result<Outcome, RunError> {
    let start = Instant::now();
    let prep = ServoBox {
        n_side,
        aspect,
        friction: MU_COMPACTION,
        sigma: SIGMA_C,
        seed,
    };
    let case = Case::from_json(&prep.compaction_case(5.0)).expect("valid case");
    let mut w = case.build_world();
    let mut steps = compact(&mut w, 5.0)?;
    let n = w.bodies.len();
    if verbose {
        eprintln!(
            "α = {aspect}: compacted at t = {:.2} s ({:.0} s wall)",
            w.time,
            start.elapsed().as_secs_f64()
        );
    }
    let bodies = at_rest(&w);
    let (_, height0, _, _) = wall_state(&w);
    let box_ = box_of(&w);
    let v = 0.5 * STRAIN_RATE * height0;
    let shear = ServoBox {
        friction: MU,
        ..prep
    };
    let duration = strain / STRAIN_RATE;
    let text = shear.case_json(
        &format!("biaxial_a{aspect}"),
        "biaxial shear stage",
        &bodies,
        box_,
        [
            json!({"velocity": [0.0, v]}),
            json!({"velocity": [0.0, -v]}),
            shear.servo(0, 1),
            shear.servo(0, 1),
        ],
        duration,
    );
    let case = Case::from_json(&text).expect("valid case");
    let mut w = case.build_world();
    w.refresh_contact_extras();
    let shear_case = text;
    let initial = analysis::measure(&Frame::from_world(&w), None);
    let (width0, height0, _, _) = wall_state(&w);
    let area0 = width0 * height0;
    let every = (0.005 / STRAIN_RATE / case.dt).round() as u64;
    let mut out = Outcome {
        aspect,
        grains: n,
        shear_case,
        initial,
        ..Default::default()
    };
    let mut frames = Vec::new();
    run_shear(&mut w, &case, every, |w, ax, lat| {
        let (width, height, _, _) = wall_state(w);
        out.curve.push((
            1.0 - height / height0,
            (ax - lat) / (ax + lat),
            1.0 - width * height / area0,
        ));
        w.refresh_contact_extras();
        let frame = Frame::from_world(w);
        out.measures.push(analysis::measure(&frame, None));
        frames.push(frame);
    })?;
    steps += case.steps();
    let summary = summarise(&out.curve);
    out.peak_ratio = summary.peak_ratio;
    out.peak_strain = summary.peak_strain;
    out.residual_ratio = summary.residual_ratio;
    out.dilatancy_deg = summary.dilatancy_deg;
    out.peak_measures = out.measures[summary.peak_index];
    out.peak_frame = frames.swap_remove(summary.peak_index);
    out.wall_seconds = start.elapsed().as_secs_f64();
    out.particle_steps = steps as f64 * n as f64;
    if verbose {
        eprintln!(
            "α = {aspect}: peak {:.3} at {:.3}, residual {:.3}, {:.0} s",
            out.peak_ratio, out.peak_strain, out.residual_ratio, out.wall_seconds
        );
    }
    Ok(out)
}

/// The two panels of biaxial curves against the axial strain: the stress ratio (titled
/// `stress_title`) and the volumetric strain; `series(0)` and `series(1)` give their series.
pub fn curve_panels(stress_title: &str, series: impl Fn(usize) -> Vec<Series>) -> [LinePanel; 2] {
    [
        LinePanel {
            title: stress_title.into(),
            x_label: "axial strain ε₁ (%)".into(),
            y_label: "(σ₁ − σ₃)/(σ₁ + σ₃) (–)".into(),
            series: series(0),
            ..Default::default()
        },
        LinePanel {
            title: "Volumetric strain (compression positive)".into(),
            x_label: "axial strain ε₁ (%)".into(),
            y_label: "ε_v = 1 − A/A₀ (%)".into(),
            series: series(1),
            ..Default::default()
        },
    ]
}

/// An SVG of force chains: each body's outline in grey, each body–body contact a line between
/// the two centroids of width ∝ F_n (the largest 6 px), panels side by side with a 10 cm scale.
fn force_chains(results: &[&Outcome]) -> String {
    let scale = 9.0; // px per cm
    let (pad, top) = (20.0, 55.0);
    let mut x_off = pad;
    let mut body = String::new();
    let mut height: f64 = 0.0;
    for r in results {
        let f = &r.peak_frame;
        let b = f.wall_box.expect("a wall box");
        let (w, h) = ((b.x1 - b.x0) * scale, (b.y1 - b.y0) * scale);
        let tx = |x: f64| x_off + (x - b.x0) * scale;
        let ty = |y: f64| top + h - (y - b.y0) * scale;
        let fmax = f
            .contacts
            .iter()
            .map(|c| c.normal_force())
            .fold(0.0, f64::max);
        writeln!(
            body,
            r#"<text x="{:.1}" y="22" font-family="sans-serif" font-size="15">α = {} at the peak (axial strain {:.1} %)</text><text x="{:.1}" y="42" font-family="sans-serif" font-size="13">line width ∝ F_n; widest {:.2e} dyn/cm</text>"#,
            x_off,
            r.aspect,
            100.0 * r.peak_strain,
            x_off,
            fmax
        )
        .expect("string");
        writeln!(
            body,
            r#"<rect x="{:.1}" y="{top}" width="{w:.1}" height="{h:.1}" fill="none" stroke="black"/>"#,
            x_off
        )
        .expect("string");
        for fb in &f.bodies {
            let pts: Vec<String> = plot::outline(&fb.shape, fb.position.x, fb.position.y, fb.angle)
                .iter()
                .map(|&(x, y)| format!("{:.1},{:.1}", tx(x), ty(y)))
                .collect();
            writeln!(
                body,
                r##"<polygon points="{}" fill="#eeeeee" stroke="#aaaaaa" stroke-width="0.5"/>"##,
                pts.join(" ")
            )
            .expect("string");
        }
        for c in &f.contacts {
            let Some(i) = c.giver_body() else { continue };
            let (p, q) = (f.bodies[i].position, f.bodies[c.j].position);
            let width = 6.0 * c.normal_force().max(0.0) / fmax;
            if width < 0.05 {
                continue;
            }
            writeln!(
                body,
                r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="black" stroke-width="{width:.2}" stroke-linecap="round"/>"#,
                tx(p.x),
                ty(p.y),
                tx(q.x),
                ty(q.y)
            )
            .expect("string");
        }
        writeln!(
            body,
            r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="black" stroke-width="3"/><text x="{:.1}" y="{:.1}" font-family="sans-serif" font-size="13">10 cm</text>"#,
            x_off,
            top + h + 20.0,
            x_off + 10.0 * scale,
            top + h + 20.0,
            x_off + 10.0 * scale + 8.0,
            top + h + 25.0
        )
        .expect("string");
        height = height.max(h);
        x_off += w + 3.0 * pad;
    }
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 0 {:.0} {:.0}"><rect width="100%" height="100%" fill="white"/>{body}</svg>"#,
        x_off,
        top + height + 40.0,
        x_off,
        top + height + 40.0
    )
}

/// Samples per aspect ratio by default: each number of the table is the mean over them ± its
/// standard error.
pub const SAMPLES: usize = 3;
/// With `--precision`, samples are added until the se of the peak stress ratio is at most it, up
/// to this many times the samples asked for.
pub const PRECISION_CAP: usize = 10;

/// Runs the study with samples of about `grains` grains (the nearest square number), `samples`
/// per aspect ratio (seeds 11 + `seed`, 12 + `seed`, …; with `precision`, more until the se of
/// the peak stress ratio is at most it); `write` also writes each α's shear stage (its first
/// sample's) to `cases/biaxial_shape/shear_a{α}.json`.
pub fn run(
    grains: usize,
    write: bool,
    samples: usize,
    seed: u64,
    precision: Option<f64>,
) -> Result<String, RunError> {
    let aspects = [1.0, 1.5, 2.0, 2.5];
    let n_side = ((grains as f64).sqrt().round() as usize).max(2);
    let samples = samples.max(1);
    let mut all: Vec<Vec<Outcome>> = Vec::new();
    for &a in &aspects {
        let mut of = Vec::new();
        while of.len() < samples
            || precision.is_some_and(|p| {
                let e = mean_se(
                    &of.iter()
                        .map(|r: &Outcome| r.peak_ratio)
                        .collect::<Vec<_>>(),
                );
                !(e.converged && e.se <= p) && of.len() < PRECISION_CAP * samples
            })
        {
            of.push(run_one(n_side, a, 0.1, 11 + seed + of.len() as u64, true)?);
        }
        all.push(of);
    }
    let results: Vec<&Outcome> = all.iter().map(|of| &of[0]).collect();
    if write {
        for r in &results {
            let path = format!("cases/biaxial_shape/shear_a{}.json", r.aspect);
            super::put_case(std::path::Path::new(&path), &r.shear_case);
        }
    }
    let mut md = String::from(
        "| α | grains | samples | φ after compaction | Z (no rattlers) | peak (σ₁−σ₃)/(σ₁+σ₃) | φ_peak (°) | φ_res (°) | ψ (°) | a_c | a_n | a_t | ½(a_c+a_n+a_t) | LW q/p at peak | orientation order at peak | wall time (s) | particle-steps/s |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for of in &all {
        // Each number over the samples (independent seeds): mean ± s/√m.
        let over = |f: &dyn Fn(&Outcome) -> f64, digits: usize| -> String {
            let x: Vec<f64> = of.iter().map(f).collect();
            if x.iter().any(|v| v.is_nan()) {
                "–".to_string()
            } else {
                mean_se(&x).pm(digits)
            }
        };
        let q = |r: &Outcome| {
            let (s1, s3, _) = analysis::stress::principal(r.peak_measures.stress);
            (s1 - s3) / (s1 + s3)
        };
        let wall: f64 = of.iter().map(|r| r.wall_seconds).sum();
        let particle_steps: f64 = of.iter().map(|r| r.particle_steps).sum();
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.0} | {:.2e} |",
            of[0].aspect,
            of[0].grains,
            of.len(),
            over(&|r| r.initial.packing_fraction, 4),
            over(&|r| r.initial.coordination_no_rattlers, 2),
            over(&|r| r.peak_ratio, 3),
            over(&|r| r.peak_ratio.asin().to_degrees(), 1),
            over(&|r| r.residual_ratio.asin().to_degrees(), 1),
            over(&|r| r.dilatancy_deg, 1),
            over(&|r| r.peak_measures.fabric.a_c, 3),
            over(&|r| r.peak_measures.fabric.a_n, 3),
            over(&|r| r.peak_measures.fabric.a_t, 3),
            over(
                &|r| {
                    let f = &r.peak_measures.fabric;
                    0.5 * (f.a_c + f.a_n + f.a_t)
                },
                3
            ),
            over(&q, 3),
            over(&|r| r.peak_measures.orientation_order, 3),
            wall,
            particle_steps / wall
        )
        .expect("string");
    }
    writeln!(
        md,
        "\n± one standard error over the samples (independent seeds from {}; \
         `analysis::statistics::mean_se`){}; the curves and the force chains are each α's first \
         sample's.",
        11 + seed,
        precision.map_or(String::new(), |p| format!(
            ", samples added until the se of the peak stress ratio is at most {p}"
        ))
    )
    .expect("string");
    writeln!(
        md,
        "\nσ_c = {SIGMA_C:e} dyn/cm², grain friction {MU} (compaction {MU_COMPACTION}), frictionless \
         walls, axial strain rate {STRAIN_RATE} /s: inertial number I = ε̇ d √(ρ/σ_c) = {:.1e} \
         (d = 2 cm, ρ = 2.65 g/cm³). Written by `dem2d study biaxial-shape --grains {}{}`.",
        STRAIN_RATE * 2.0 * (2.65 / SIGMA_C).sqrt(),
        n_side * n_side,
        if samples == SAMPLES {
            String::new()
        } else {
            format!(" --packings {samples}")
        }
    )
    .expect("string");
    let series = |k: usize| -> Vec<Series> {
        results
            .iter()
            .enumerate()
            .map(|(c, r)| {
                Series::line(
                    format!("α = {}", r.aspect),
                    r.curve
                        .iter()
                        .map(|p| (100.0 * p.0, if k == 0 { p.1 } else { 100.0 * p.2 }))
                        .collect(),
                    c,
                )
            })
            .collect()
    };
    let panels = curve_panels("Stress ratio", series);
    super::write_figure("biaxial_shape", (1200, 480), (1, 2), &panels)?;
    super::write_text("biaxial_shape.md", &md)?;
    let chains = force_chains(&[results[0], results[results.len() - 1]]);
    super::write_text("force_chains.svg", &chains)?;
    let png = plot::png_of_svg(&chains, 1.0)
        .map_err(|e| dem2d::run::RunError::Observer(format!("force_chains.png: {e}").into()))?;
    super::write_png("force_chains.png", &png)?;
    print!("{md}");
    Ok(md)
}

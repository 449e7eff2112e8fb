//! The walls' influence on a biaxial test: `dem2d study biaxial-periodic` runs the test of
//! `dem2d study biaxial-shape` (the same grains, contact law, confining stress σ_c, friction and
//! axial strain rate) twice per aspect ratio: in the servo-walled box, and in a fully periodic
//! cell without walls (`cell.stress`, `cell.strain_rate`: `dynamics::cell`), and tabulates the
//! two side by side (writes `figures/biaxial_periodic.svg` and `.md`).
//!
//! The periodic protocol: the lattice of [`ServoBox::bodies`] in an `"xy"` cell of the walled
//! box's size, isotropic compaction with both sides held at σ_c (grain friction
//! [`MU_COMPACTION`]) until the cell's area changes by less than 1e-5 of itself over 2000 steps
//! with an unbalanced force ratio below 1e-2 (the walled compaction's criterion); then grain
//! friction [`MU`], the height strained at the true rate −[`STRAIN_RATE`] and the width held at
//! σ_c (gain [`GAIN`]). Stresses are the cell's own Love–Weber stress (contacts and velocity
//! fluctuations over the cell's area, averaged over each 0.5 % of axial strain), where the
//! walled test reads its walls' loads; the axial strain is `1 − L_y/L_y0` in both. Peak,
//! residual and dilatancy angles as in [`super::biaxial_shape`].

use super::biaxial_shape::{self, MU, MU_COMPACTION, SIGMA_C, STRAIN_RATE};
use dem2d::analysis::{self, Frame, Measures};
use dem2d::dynamics::World;
use dem2d::output::plot::Series;
use dem2d::output::progress::CommandProgress;
use dem2d::run::{RunError, Simulation};
use dem2d::scene::Case;
use dem2d::scene::servo_box::ServoBox;
use serde_json::{Value, json};
use std::fmt::Write as _;
use std::time::Instant;

/// The fraction of a side's stress error its length corrects per step (`cell.pressure_gain`):
/// the lag of σ_xx behind its target under a strain rate is about `ε̇ Δt K/(α σ_c)` of it
/// (docs/src/physics/periodic.md).
pub const GAIN: f64 = 0.5;

/// A periodic case from the walled [`ServoBox`] case text `walled` (its grains, law, step): the
/// walls removed, the cell `cell` in their place.
fn periodic_case(walled: &str, name: &str, cell: Value) -> Case {
    let mut v: Value = serde_json::from_str(walled).expect("the servo box's JSON");
    let o = v.as_object_mut().expect("an object");
    o.remove("walls");
    o.insert("name".into(), json!(name));
    o.insert("cell".into(), cell);
    Case::from_json(&v.to_string()).expect("a valid periodic case")
}

/// The cell's size, σ_xx and σ_yy (compressive positive).
fn cell_state(w: &World) -> (f64, f64, f64, f64) {
    let c = w.cell.expect("a periodic cell");
    (
        c.size.x,
        c.size.y,
        c.normal_stress_of(0),
        c.normal_stress_of(1),
    )
}

/// One test in the periodic cell: the same fields as the walled one's.
pub fn run_periodic(n_side: usize, aspect: f64, strain: f64) -> Result<Outcome, RunError> {
    let start = Instant::now();
    let prep = ServoBox {
        n_side,
        aspect,
        friction: MU_COMPACTION,
        sigma: SIGMA_C,
        seed: 11,
    };
    let side = prep.spacing() * n_side as f64;
    let walled = prep.compaction_case(5.0);
    let case = periodic_case(
        &walled,
        &format!("periodic_compaction_a{aspect}"),
        json!({"size": [side, side], "periodic": "xy",
               "stress": {"xx": SIGMA_C, "yy": SIGMA_C}, "pressure_gain": GAIN}),
    );
    let mut w = case.build_world();
    let mut steps = 0;
    let mut last = f64::INFINITY;
    {
        let mut lines = CommandProgress::new(format!("periodic compaction, α = {aspect}"));
        let mut sim = Simulation::new(&mut w).observe(&mut lines).for_steps(2000);
        while sim.world().time < 5.0 {
            sim.run()?;
            steps += 2000;
            let w = sim.world();
            let a = w.cell.expect("a cell").area();
            if (a - last).abs() < 1e-5 * a && w.unbalanced_ratios().0 < 1e-2 {
                break;
            }
            last = a;
        }
    }
    let n = w.bodies.len();
    // The shear stage from the compacted sample at rest (its bodies in the cell's frame).
    let bodies = biaxial_shape::at_rest(&w);
    let (lx, ly, _, _) = cell_state(&w);
    let shear = ServoBox {
        friction: MU,
        ..prep
    };
    let duration = strain / STRAIN_RATE;
    // (The walls of this text are replaced by the cell.)
    let walled_shear = shear.case_json(
        "periodic_biaxial",
        "biaxial shear stage in a periodic cell",
        &bodies,
        [0.0, lx, 0.0, ly],
        std::array::from_fn(|_| json!({})),
        duration,
    );
    let case = periodic_case(
        &walled_shear,
        &format!("periodic_biaxial_a{aspect}"),
        json!({"size": [lx, ly], "periodic": "xy", "stress": {"xx": SIGMA_C},
               "strain_rate": {"yy": -STRAIN_RATE}, "pressure_gain": GAIN}),
    );
    let mut w = case.build_world();
    w.refresh_contact_extras();
    let initial = analysis::measure(&Frame::from_world(&w), None);
    let (lx0, ly0, _, _) = cell_state(&w);
    let area0 = lx0 * ly0;
    let every = (0.005 / STRAIN_RATE / case.dt).round() as u64;
    let mut out = Outcome {
        aspect,
        grains: n,
        initial,
        ..Default::default()
    };
    let (mut sum, mut count) = ([0.0; 2], 0.0);
    let mut lines = CommandProgress::new(case.name.clone());
    Simulation::new(&mut w)
        .observe(&mut lines)
        .until_step(case.steps())
        .run_each(|w, _| {
            let (lx, ly, sxx, syy) = cell_state(w);
            sum[0] += syy;
            sum[1] += sxx;
            count += 1.0;
            if w.step % every == 0 {
                let (ax, lat) = (sum[0] / count, sum[1] / count);
                out.curve.push((
                    1.0 - ly / ly0,
                    (ax - lat) / (ax + lat),
                    1.0 - lx * ly / area0,
                ));
                out.lateral.push(lat);
                (sum, count) = ([0.0; 2], 0.0);
            }
        })?;
    steps += case.steps();
    out.summary = biaxial_shape::summarise(&out.curve);
    out.wall_seconds = start.elapsed().as_secs_f64();
    out.particle_steps = steps as f64 * n as f64;
    Ok(out)
}

/// One test's numbers (walled or periodic).
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    pub aspect: f64,
    pub grains: usize,
    pub initial: Measures,
    /// (axial strain, stress ratio, volumetric strain) every 0.5 %.
    pub curve: Vec<(f64, f64, f64)>,
    /// The lateral stress σ_xx over each 0.5 % (periodic tests).
    pub lateral: Vec<f64>,
    pub summary: biaxial_shape::Summary,
    pub wall_seconds: f64,
    pub particle_steps: f64,
}

/// Runs the walled and the periodic test per aspect ratio with about `grains` grains (the
/// nearest square number) to 10 % axial strain.
pub fn run(grains: usize) -> Result<String, RunError> {
    let aspects = [1.0, 1.5, 2.0, 2.5];
    let n_side = ((grains as f64).sqrt().round() as usize).max(2);
    let mut rows = Vec::new();
    for &a in &aspects {
        let walled = biaxial_shape::run_one(n_side, a, 0.1, 11, true)?;
        let walled = Outcome {
            aspect: a,
            grains: walled.grains,
            initial: walled.initial,
            summary: biaxial_shape::summarise(&walled.curve),
            curve: walled.curve,
            lateral: Vec::new(),
            wall_seconds: walled.wall_seconds,
            particle_steps: walled.particle_steps,
        };
        let periodic = run_periodic(n_side, a, 0.1)?;
        eprintln!(
            "α = {a}: peak {:.3} walled, {:.3} periodic; residual {:.3}, {:.3}",
            walled.summary.peak_ratio,
            periodic.summary.peak_ratio,
            walled.summary.residual_ratio,
            periodic.summary.residual_ratio
        );
        rows.push((walled, periodic));
    }
    let deg = |s: f64| s.asin().to_degrees();
    let mut md = String::from(
        "| α | grains | φ after compaction (walls / periodic) | Z (no rattlers) | φ_peak (°) | φ_res (°) | ψ (°) | ε₁ at the peak (%) | ⟨σ_xx⟩/σ_c after the peak (periodic) | wall time (s) |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for (w, p) in &rows {
        let peak = p.summary.peak_index;
        let after = &p.lateral[peak.min(p.lateral.len())..];
        let lateral = after.iter().sum::<f64>() / after.len().max(1) as f64 / SIGMA_C;
        writeln!(
            md,
            "| {} | {} | {:.4} / {:.4} | {:.2} / {:.2} | {:.1} / {:.1} | {:.1} / {:.1} | {:.1} / {:.1} | {:.1} / {:.1} | {:.4} | {:.0} / {:.0} |",
            w.aspect,
            w.grains,
            w.initial.packing_fraction,
            p.initial.packing_fraction,
            w.initial.coordination_no_rattlers,
            p.initial.coordination_no_rattlers,
            deg(w.summary.peak_ratio),
            deg(p.summary.peak_ratio),
            deg(w.summary.residual_ratio),
            deg(p.summary.residual_ratio),
            w.summary.dilatancy_deg,
            p.summary.dilatancy_deg,
            100.0 * w.summary.peak_strain,
            100.0 * p.summary.peak_strain,
            lateral,
            w.wall_seconds,
            p.wall_seconds,
        )
        .expect("string");
    }
    writeln!(
        md,
        "\nEach cell: the walled test / the periodic one, one realisation each (the same lattice \
         and seed). σ_c = {SIGMA_C:e} dyn/cm², grain friction {MU} (compaction {MU_COMPACTION}), \
         axial strain rate {STRAIN_RATE} /s, periodic stress gain {GAIN}; φ of the walled sample \
         in the walls' box (clipped), of the periodic one in its cell. Written by `dem2d study \
         biaxial-periodic --grains {}` ({}).",
        n_side * n_side,
        super::threads()
    )
    .expect("string");
    let series = |k: usize| -> Vec<Series> {
        rows.iter()
            .enumerate()
            .flat_map(|(c, (w, p))| {
                let pick = move |o: &Outcome| -> Vec<(f64, f64)> {
                    o.curve
                        .iter()
                        .map(|q| (100.0 * q.0, if k == 0 { q.1 } else { 100.0 * q.2 }))
                        .collect()
                };
                [
                    Series::line(format!("α = {}, walls", w.aspect), pick(w), c),
                    Series {
                        label: format!("α = {}, periodic", p.aspect),
                        points: pick(p),
                        color: c,
                        markers: true,
                        ..Default::default()
                    },
                ]
            })
            .collect()
    };
    let panels = biaxial_shape::curve_panels(
        "Stress ratio: walls (lines), periodic cell (markers)",
        series,
    );
    super::write_figure("biaxial_periodic", (1200, 480), (1, 2), &panels)?;
    super::write_text("biaxial_periodic.md", &md)?;
    print!("{md}");
    Ok(md)
}

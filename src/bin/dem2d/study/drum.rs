//! A half-filled drum of disks and of ellipses (α = 1.5, 2) over Froude numbers
//! Fr = ω²R/g from 1e-5 to 2 (issue 44, item 3): the regime (Mellmann 2001), the free surface's
//! angle and the flowing layer's thickness. The runs and the measurements are the library's
//! ([`dem2d::scene::drum_flow`]); this prints the table and draws the figure.
//!
//! Each aspect ratio is one run: the bed settles, then the drum turns through the Froude
//! numbers in [`CHAIN`]'s order, each stage continuing from the last (down from 1e-3 to 1e-5,
//! then up from 3e-3 to 2). The runs of the aspect ratios go in parallel.

use super::Table;
use dem2d::output::plot::{self, LinePanel, Series};
use dem2d::run::RunError;
use dem2d::scene::drum_flow::{self, DrumRun, DrumSpec, Regime};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::time::Instant;

pub const ASPECTS: [f64; 3] = [1.0, 1.5, 2.0];
pub const CHAIN: [f64; 13] = [
    1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0, 1.5, 2.0,
];
/// `--quick`: the small drum, disks, five Froude numbers.
pub const QUICK: [f64; 5] = [1e-3, 1e-2, 0.3, 1.0, 2.0];

pub fn run(quick: bool, aspects: Option<&[f64]>) -> Result<String, RunError> {
    let start = Instant::now();
    let aspects: Vec<f64> = aspects
        .map(<[f64]>::to_vec)
        .unwrap_or_else(|| if quick { vec![1.0] } else { ASPECTS.to_vec() });
    let spec = |a: f64| {
        if quick {
            DrumSpec::quick(a, QUICK.to_vec())
        } else {
            DrumSpec::standard(a, CHAIN.to_vec())
        }
    };
    let runs: Vec<(f64, DrumRun, f64)> = aspects
        .par_iter()
        .map(|&a| {
            let t = Instant::now();
            let r = drum_flow::run(&spec(a))?;
            let wall = t.elapsed().as_secs_f64();
            eprintln!(
                "  α = {a}: {} grains, {} steps, {wall:.0} s",
                r.grains, r.steps
            );
            Ok((a, r, wall))
        })
        .collect::<Result<_, RunError>>()?;
    let mut table = Table::new(
        "| α | Fr | ω (rad/s) | regime | angle (°) | sd (°) | rms (d) | bulge (d) | flowing layer δ (d) | time flowing | avalanches | in flight | co-rotating | centre of mass (R) | overlap (d) |\n\
         |---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    );
    for (a, r, _) in &runs {
        let mut pts = r.points.clone();
        pts.sort_by(|x, y| x.froude.total_cmp(&y.froude));
        for p in &pts {
            let layer = match p.regime() {
                Regime::Centrifuging | Regime::Cataracting => "—".to_string(),
                _ if p.thickness.is_nan() => "—".to_string(),
                _ => format!("{:.1}", p.thickness),
            };
            table.row(format!(
                "| {a} | {:e} | {:.4} | {} | {:.1} | {:.1} | {:.2} | {:.2} | {layer} | {:.2} | {} | {:.3} | {:.2} | {:.2} | {:.3} |",
                p.froude,
                p.omega,
                p.regime().as_str(),
                p.angle,
                p.angle_sd,
                p.rms,
                p.bulge,
                p.flow_time,
                p.avalanches,
                p.flying,
                p.corotating,
                p.com,
                p.overlap
            ));
        }
    }
    let mut md = table.text();
    let s = spec(1.0);
    let wall = start.elapsed().as_secs_f64();
    let _ = writeln!(
        md,
        "\nDrum R = {} cm; grains of equal-area radii uniform in {}–{} cm (d = {} cm the mean \
         diameter, R/d = {:.1}), {} of them (half the drum at φ = {}); linear contacts \
         k_n = k_t = {}·ρg, e = {}, μ = {} (grains and drum); Δt = {} of the a-priori critical \
         step ({:.2e} s). {} runs, {} steps in all, {wall:.0} s of wall time on {}.",
        s.radius,
        s.r_min,
        s.r_max,
        s.diameter(),
        s.radius / s.diameter(),
        runs.first().map_or(0, |r| r.1.grains),
        s.fill_phi,
        s.kn_over_rho_g,
        s.restitution,
        s.friction,
        s.dt_fraction,
        runs.first().map_or(0.0, |r| r.1.dt),
        runs.len(),
        runs.iter().map(|r| r.1.steps).sum::<u64>(),
        super::threads()
    );
    let series = |layer: bool| -> Vec<Series> {
        runs.iter()
            .enumerate()
            .map(|(k, (a, r, _))| {
                let mut pts: Vec<(f64, f64)> = r
                    .points
                    .iter()
                    .filter(|p| {
                        matches!(
                            p.regime(),
                            Regime::Slumping | Regime::Rolling | Regime::Cascading
                        )
                    })
                    .map(|p| (p.froude, if layer { p.thickness } else { p.angle }))
                    .filter(|p| p.1.is_finite())
                    .collect();
                pts.sort_by(|x, y| x.0.total_cmp(&y.0));
                Series {
                    label: format!("α = {a}"),
                    points: pts,
                    color: k,
                    line: true,
                    markers: true,
                    ..Default::default()
                }
            })
            .collect()
    };
    let panels = [
        LinePanel {
            title: "Free surface angle (slumping, rolling, cascading)".into(),
            x_label: "Froude number Fr = ω²R/g (–)".into(),
            y_label: "angle of the mean surface (°)".into(),
            log_x: true,
            series: series(false),
            legend: plot::Legend::Auto,
            ..Default::default()
        },
        LinePanel {
            title: "Flowing layer at the centre line".into(),
            x_label: "Froude number Fr = ω²R/g (–)".into(),
            y_label: "thickness δ (mean diameters d)".into(),
            log_x: true,
            series: series(true),
            legend: plot::Legend::Auto,
            ..Default::default()
        },
    ];
    super::write_figure("drum", (1200, 480), (1, 2), &panels)?;
    super::write_text("drum.md", &md)?;
    Ok(md)
}

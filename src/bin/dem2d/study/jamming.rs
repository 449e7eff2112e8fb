//! Isotropic jamming of frictionless bidisperse grains in a periodic cell, against the aspect
//! ratio α (O'Hern, Silbert, Liu & Nagel, PRE 68 (2003) 011306; for ellipses Schreck, Xu &
//! O'Hern, Soft Matter 6 (2010) 2960, and VanderWerf, Jin, Shattuck & O'Hern, PRE 97 (2018)
//! 012909).
//!
//! `dem2d study jamming` writes `figures/jamming.svg` and `figures/jamming.md` and prints the
//! table. Each packing: [`N`] grains (`--grains`), half with equal-area radius [`R_SMALL`], half
//! 1.4 times it (the diameter ratio of the papers), ellipses `a = r√α`, `b = r/√α`, placed at
//! random (positions and orientations, overlaps allowed) in a square cell periodic in x and y at
//! φ = [`PHI_START`]; frictionless linear law on the overlap area (the energy-conserving default,
//! so that the forces derive from the energy minimised). The protocol is O'Hern's: minimise the
//! energy with FIRE (`dynamics::minimise`), compress or decompress affinely, minimise again,
//! until the energy per grain lies in `[U_TOL, 2 U_TOL] k_n d²` ([`U_TOL`] = 1e-12, d the small
//! diameter): φ_J is the packing fraction there, Z_J the contacts per grain with rattlers
//! (grains with fewer than 3 contacts, removed repeatedly) left out. The search compresses by
//! 5 % until jammed, then closes in on the band between the highest unjammed and the lowest
//! jammed φ by the secant of u^(2/5) against φ (the area law's energy grows as (φ − φ_J)^(5/2)
//! near φ_J), halving the bracket where the secant lands outside it or stalls; a bracket that
//! closes (1e-9) without the band has a stale jammed side, dropped for compression by 0.1 %
//! steps. A minimisation stops at a
//! residual force of 1e-9, at the residual's round-off level (`round_off`: near φ_J, about
//! 1e-8 for disks), at an energy half the band's floor (unjammed: minimising only
//! lowers it), or when
//! it stalls: its energy changes by less than [`STALL`] of itself over 1000 iterations while
//! its residual does not halve (O'Hern's second criterion; near jamming FIRE relaxes the soft
//! modes of ellipse packings only slowly, and the residual stays near 1e-3 for 10⁵ iterations).
//! A stalled minimisation that lands in the band runs on without the stall criterion (up to
//! 10⁵ iterations) before the band is checked again and the contacts counted.
//! [`PACKINGS`] packings per α (different seeds), in parallel.

use super::{Table, grain};
use dem2d::analysis::statistics::mean_se;
use dem2d::contact_law::{ContactSpec, LinearDamping, NormalForce, Scaled};
use dem2d::dynamics::BodyInit;
use dem2d::dynamics::World;
use dem2d::dynamics::cell::{Cell, Periodic};
use dem2d::dynamics::minimise::{Fire, Relaxed, Tolerance, relax};
use dem2d::dynamics::partner::Partner;
use dem2d::geometry::{Pose, Shape, Vec2};
use dem2d::output::plot::{self, LinePanel, Series};
use dem2d::scene::Case;
use dem2d::scene::generate::Xorshift;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::time::Instant;

/// Grains per packing by default.
pub const N: usize = 256;
/// Packings per aspect ratio.
pub const PACKINGS: usize = 10;
/// With `--precision`, the most rounds of `--packings` packings per aspect ratio.
pub const PRECISION_CAP: usize = 10;
/// The aspect ratios by default.
pub const ASPECTS: [f64; 8] = [1.0, 1.1, 1.2, 1.3, 1.5, 2.0, 2.5, 3.0];
/// Equal-area radius of the small grains (cm).
pub const R_SMALL: f64 = 0.5;
/// The packing fraction the grains are placed at.
pub const PHI_START: f64 = 0.70;
/// The energy band's lower edge, per grain, in units of `k_n d²`.
pub const U_TOL: f64 = 1e-12;
/// A minimisation has stalled when its energy changes by less than this fraction over
/// `minimise::STALL_WINDOW` iterations.
pub const STALL: f64 = 1e-3;
const KN: f64 = 1e3;

/// One jammed packing.
#[derive(Clone, Copy, Debug)]
pub struct Packing {
    pub aspect: f64,
    pub phi: f64,
    pub z: f64,
    pub rattlers: f64,
    pub minimisations: usize,
    pub iterations: u64,
    pub found: bool,
}

/// The world of packing `seed` at aspect ratio `aspect`, its grains placed at random.
fn world(n: usize, aspect: f64, seed: u64) -> World {
    let mut rng = Xorshift(0x9E37_79B9_7F4A_7C15 ^ seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 1);
    let shapes: Vec<Shape> = (0..n)
        .map(|k| grain(if k % 2 == 0 { R_SMALL } else { 1.4 * R_SMALL }, aspect))
        .collect();
    let total: f64 = shapes.iter().map(dem2d::geometry::mass::area).sum();
    let side = (total / PHI_START).sqrt();
    let bodies = shapes
        .into_iter()
        .map(|shape| BodyInit {
            material: 0,
            prescribed: false,
            shape,
            position: Vec2::new(side * rng.uniform(), side * rng.uniform()),
            angle: std::f64::consts::PI * rng.uniform(),
            velocity: Vec2::zeros(),
            omega: 0.0,
            density: 1.0,
        })
        .collect();
    let law = ContactSpec::linear(
        Scaled::Absolute(KN),
        Scaled::Absolute(KN),
        LinearDamping::Dashpots {
            eta_n: Scaled::Absolute(0.0),
            eta_s: Scaled::Absolute(0.0),
        },
        0.0,
    )
    .with_normal_force(NormalForce::Area);
    // FIRE's step: a tenth of the small grains' contact period.
    let m = std::f64::consts::PI * R_SMALL * R_SMALL;
    let dt = 0.1 * (m / KN).sqrt();
    let cell = Cell::new(Vec2::new(side, side), Periodic::XY, 0.0, None);
    Case::new(bodies, Vec::new(), Vec2::zeros(), law, dt)
        .with_cell(cell)
        .build_world()
}

/// The packing fraction of `w`'s grains in its cell.
fn phi(w: &World, total: f64) -> f64 {
    let c = w.cell.expect("a cell");
    total / (c.size.x * c.size.y)
}

/// Scales the cell and every grain's position by `f` (an affine compression for f < 1).
fn scale(w: &mut World, f: f64) {
    let c = w.cell.as_mut().expect("a cell");
    c.size *= f;
    for s in &mut w.bodies.state {
        s.pose = Pose::new(s.pose.position * f, s.pose.angle());
    }
}

/// Contacts per grain with rattlers (fewer than 3 contacts, removed repeatedly) left out, and
/// the rattlers' fraction.
fn coordination(w: &World) -> (f64, f64) {
    let n = w.bodies.len();
    let pairs: Vec<(usize, usize)> = w
        .contacts
        .active()
        .filter_map(|c| match c.slot.partner() {
            Partner::Body(j) => Some((c.slot.i as usize, j)),
            Partner::Wall(_) => None,
        })
        .collect();
    let mut alive = vec![true; n];
    loop {
        let mut z = vec![0usize; n];
        for &(i, j) in &pairs {
            if alive[i] && alive[j] {
                z[i] += 1;
                z[j] += 1;
            }
        }
        let gone: Vec<usize> = (0..n).filter(|&k| alive[k] && z[k] < 3).collect();
        if gone.is_empty() {
            let kept = alive.iter().filter(|&&a| a).count();
            let contacts: usize = z.iter().sum::<usize>() / 2;
            let zj = if kept > 0 {
                2.0 * contacts as f64 / kept as f64
            } else {
                f64::NAN
            };
            return (zj, (n - kept) as f64 / n as f64);
        }
        for k in gone {
            alive[k] = false;
        }
    }
}

/// The configuration a minimisation of [`jam_from`] started from: the periodic cell's size and
/// the grains' poses.
#[derive(Clone, Debug)]
pub struct Start {
    pub size: Vec2,
    pub poses: Vec<Pose>,
}

/// Jams packing `seed` at `aspect` (see the module documentation).
pub fn jam(n: usize, aspect: f64, seed: u64) -> Packing {
    jam_from(n, aspect, seed).0
}

/// [`jam`], with the configuration the last minimisation started from (for a packing in the
/// band: the affinely compressed or decompressed packing that this minimisation brought to the
/// jamming threshold).
pub fn jam_from(n: usize, aspect: f64, seed: u64) -> (Packing, Start) {
    let mut w = world(n, aspect, seed);
    let total: f64 = w.bodies.shape.iter().map(dem2d::geometry::mass::area).sum();
    let d = 2.0 * R_SMALL;
    let unit = n as f64 * KN * d * d;
    let tol = Tolerance {
        force: 1e-9,
        max_iterations: 100_000,
        stall: STALL,
        // Minimising only lowers the energy: once below the band it stays below (unjammed),
        // however slowly a floppy packing then decays towards zero.
        energy: 0.5 * U_TOL * unit,
    };
    let polish = Tolerance { stall: 0.0, ..tol };
    let fire = Fire::default();
    // The search for the band: compress by δφ = 5 % until jammed; then keep the highest
    // unjammed φ (u below the band) and the two lowest jammed ones (u above it) and aim at the
    // band's middle on the line through the jammed two of u^(2/5) against φ (near φ_J the
    // area law's energy grows as (φ − φ_J)^(5/2): lens areas as δ^(3/2)), or halfway in
    // between where no such line lands inside the bracket.
    let target = (1.5 * U_TOL).powf(0.4);
    let (mut below, mut above): (Option<f64>, Vec<(f64, f64)>) = (None, Vec::new());
    let (mut width, mut step) = (f64::INFINITY, 0.05);
    let (mut minimisations, mut iterations) = (0, 0);
    let mut found = false;
    let start_of = |w: &World| Start {
        size: w.cell.expect("a cell").size,
        poses: w.bodies.state.iter().map(|s| s.pose).collect(),
    };
    let mut start = start_of(&w);
    for _ in 0..200 {
        start = start_of(&w);
        let mut r = relax(&mut w, &fire, &tol).expect("frictionless");
        minimisations += 1;
        iterations += r.iterations;
        let in_band = |r: &Relaxed| (U_TOL..=2.0 * U_TOL).contains(&(r.potential / unit));
        if r.stalled && in_band(&r) {
            // In the band, but stalled: run on to the residual (or the iteration budget) before
            // counting contacts, so that Z_J is the minimum's.
            r = relax(&mut w, &fire, &polish).expect("frictionless");
            minimisations += 1;
            iterations += r.iterations;
        }
        let u = r.potential / unit;
        let now = phi(&w, total);
        if std::env::var_os("DEM2D_JAMMING_TRACE").is_some() {
            eprintln!(
                "    α = {aspect}, packing {seed}: φ = {now:.9}, u = {u:.3e}, {} iterations, residual {:.2e}",
                r.iterations, r.residual
            );
        }
        if (U_TOL..=2.0 * U_TOL).contains(&u) {
            found = true;
            break;
        }
        // The packing changes as it is compressed and decompressed: a point on the other side
        // of the newest one is stale and goes (the bracket must hold the newest).
        if u < U_TOL {
            above.retain(|&(p, _)| p > now);
            below = Some(below.map_or(now, |b: f64| b.max(now)));
        } else {
            below = below.filter(|&b| b < now);
            above.push((now, u.powf(0.4)));
            above.sort_by(|a, b| a.0.total_cmp(&b.0));
            above.truncate(2);
        }
        let next = match (below, above.first()) {
            (_, None) => now * (1.0 + step),
            (None, Some(&(hi, _))) => hi * (1.0 - step),
            (Some(lo), Some(&(hi, _))) if hi - lo < 1e-9 * hi => {
                // The bracket closed without the band: the jammed side is a configuration the
                // packing has left (decompressed, it rearranged and now stays unjammed up to
                // it). Drop it and compress on in small steps.
                above.clear();
                step = 1e-3;
                now * (1.0 + step)
            }
            (Some(lo), Some(&(hi, _))) => {
                let secant = match above[..] {
                    [(p0, g0), (p1, g1)] if g1 > g0 => {
                        Some(p0 + (target - g0) * (p1 - p0) / (g1 - g0))
                    }
                    _ => None,
                };
                // (A secant that has not halved the bracket since the last step is stalling on
                // one side, as regula falsi does: halve instead.)
                let shrinking = hi - lo < 0.5 * width;
                width = hi - lo;
                match secant {
                    Some(p)
                        if shrinking && p > lo + 0.01 * (hi - lo) && p < hi - 0.01 * (hi - lo) =>
                    {
                        p
                    }
                    _ => 0.5 * (lo + hi),
                }
            }
        };
        // φ → next: lengths by (next/φ)^(−1/2).
        scale(&mut w, (next / now).powf(-0.5));
    }
    let (z, rattlers) = coordination(&w);
    (
        Packing {
            aspect,
            phi: phi(&w, total),
            z,
            rattlers,
            minimisations,
            iterations,
            found,
        },
        start,
    )
}

/// The case file of a threshold packing of disks (`cases/jammed_disks_N.json`, written with
/// `--write-cases`): the grains of packing 0 at α = 1 as the last minimisation of the protocol
/// found them, before it brought them to the threshold — what `dem2d relax` must bring to a
/// residual force at its round-off level (issue 41, item 12).
fn threshold_case(n: usize, start: &Start, found: &Packing) -> String {
    let m = std::f64::consts::PI * R_SMALL * R_SMALL;
    let bodies: Vec<serde_json::Value> = start
        .poses
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let r = if k % 2 == 0 { R_SMALL } else { 1.4 * R_SMALL };
            serde_json::json!({
                "shape": {"type": "circle", "r": r},
                "position": [p.position.x, p.position.y],
            })
        })
        .collect();
    let case = serde_json::json!({
        "version": 1,
        "name": format!("jammed_disks_{n}"),
        "description": format!(
            "{n} frictionless bidisperse disks (r = 0.5 and 0.7 cm) in a periodic cell at the \
             jamming threshold: packing 0 at α = 1 of `dem2d study jamming --aspects 1 \
             --packings 1 --grains {n} --write-cases`, as its last minimisation started (it \
             ended at φ_J = {:.6}, Z_J = {:.4} with rattlers out); `dem2d relax` brings it to the \
             threshold, u ≈ 1e-12 k_n d² per grain (tests/relax_threshold.rs)",
            found.phi, found.z
        ),
        "units": "cm",
        "gravity": [0.0, 0.0],
        "dt": 0.1 * (m / KN).sqrt(),
        "duration": 1.0,
        "cell": {"size": [start.size.x, start.size.y], "periodic": "xy"},
        "contact": {
            "model": "linear",
            "normal_force": "area",
            "kn": KN,
            "ks": KN,
            "eta_n": 0.0,
            "eta_s": 0.0,
            "friction": 0.0,
        },
        "bodies": bodies,
    });
    serde_json::to_string_pretty(&case).expect("a JSON value serialises") + "\n"
}

/// The published values beside each aspect ratio: φ_J and Z_J (VanderWerf et al. 2018, Fig. 2
/// and 4; O'Hern et al. 2003 for disks), as text.
fn published(aspect: f64) -> &'static str {
    if aspect == 1.0 {
        "φ_J ≈ 0.84, Z_J = 4 (O'Hern 2003)"
    } else if (1.25..=1.5).contains(&aspect) {
        "φ_J peak 0.891–0.897 (α ≈ 1.3–1.45)"
    } else if aspect >= 1.5 {
        "Z_J ≈ 5.5–5.8 (1.5 ≤ α ≤ 3)"
    } else {
        "Z_J − 4 ∝ √(α − 1)"
    }
}

/// The study (see the module documentation); with `write`, also the case file of a threshold
/// packing ([`threshold_case`]) when α = 1 is among `aspects`. The packings of an aspect ratio
/// are seeds `seed`, `seed + 1`, …: `packings` of them, and with `precision` more in rounds of
/// `packings` until the standard error of φ_J over them is at most `precision` (at most
/// [`PRECISION_CAP`] rounds).
pub fn run(
    n: usize,
    packings: usize,
    aspects: &[f64],
    write: bool,
    seed: u64,
    precision: Option<f64>,
) -> Result<String, dem2d::run::RunError> {
    let start = Instant::now();
    eprintln!(
        "dem2d study jamming: {} packings of {n} grains ({} aspect ratios), seeds from {seed}{}",
        packings * aspects.len(),
        aspects.len(),
        precision.map_or(String::new(), |p| format!(", more until se(φ_J) ≤ {p}"))
    );
    let mut done: Vec<Packing> = Vec::new();
    let phi_j = |done: &[Packing], a: f64| {
        let phis: Vec<f64> = done
            .iter()
            .filter(|p| p.aspect == a && p.found)
            .map(|p| p.phi)
            .collect();
        mean_se(&phis)
    };
    for round in 0..PRECISION_CAP {
        // The aspect ratios that still want packings: all in the first round, then those whose
        // se(φ_J) is above the precision.
        let want: Vec<f64> = aspects
            .iter()
            .copied()
            .filter(|&a| {
                round == 0
                    || precision.is_some_and(|p| {
                        let e = phi_j(&done, a);
                        !(e.converged && e.se <= p)
                    })
            })
            .collect();
        if want.is_empty() {
            break;
        }
        let first = seed + (round * packings) as u64;
        let jobs: Vec<(f64, u64)> = want
            .iter()
            .flat_map(|&a| (first..first + packings as u64).map(move |s| (a, s)))
            .collect();
        let more: Vec<Packing> = jobs
            .par_iter()
            .map(|&(a, s)| {
                let (p, start) = jam_from(n, a, s);
                if write && a == 1.0 && s == seed {
                    super::put_case(
                        std::path::Path::new(&format!("cases/jammed_disks_{n}.json")),
                        &threshold_case(n, &start, &p),
                    );
                }
                eprintln!(
                    "  α = {a}, packing {s}: φ_J = {:.4}, Z_J = {:.3}{}",
                    p.phi,
                    p.z,
                    if p.found { "" } else { " (band not reached)" }
                );
                p
            })
            .collect();
        done.extend(more);
        if precision.is_none() {
            break;
        }
    }
    let mut table = Table::new(
        "| α | φ_J (mean ± se, in the band) | Z_J, rattlers out (mean ± se, in the band) | sd of φ_J, of Z_J | rattlers | packings in the band | minimisations, FIRE iterations (mean) | published |\n|---|---|---|---|---|---|---|---|",
    );
    let mut rows = Vec::new();
    for &a in aspects {
        let ps: Vec<&Packing> = done.iter().filter(|p| p.aspect == a).collect();
        // The means are over the packings that reached the band (a packing whose bracket
        // closed on a rearrangement without it is counted, not averaged); the packings are
        // independent (one seed each): se = sd/√m.
        let zs: Vec<f64> = ps.iter().filter(|p| p.found).map(|p| p.z).collect();
        let phi = phi_j(&done, a);
        let z = mean_se(&zs);
        let (psd, zsd) = (phi.se * (phi.n as f64).sqrt(), z.se * (z.n as f64).sqrt());
        let rat = ps.iter().map(|p| p.rattlers).sum::<f64>() / ps.len() as f64;
        let found = ps.iter().filter(|p| p.found).count();
        let k = ps.len() as f64;
        let mins = ps.iter().map(|p| p.minimisations as f64).sum::<f64>() / k;
        let its = ps.iter().map(|p| p.iterations as f64).sum::<f64>() / k;
        table.row(format!(
            "| {a} | {} | {} | {psd:.4}, {zsd:.3} | {:.1} % | {found} of {} | {mins:.0}, {its:.0} | {} |",
            phi.pm(4),
            z.pm(3),
            100.0 * rat,
            ps.len(),
            published(a)
        ));
        if found > 0 {
            rows.push((a, phi.mean, phi.se, z.mean, z.se));
        }
    }
    let wall = start.elapsed().as_secs_f64();
    let mut md = table.text();
    let _ = writeln!(
        md,
        "\n± one standard error over the packings (independent seeds, from {seed}; \
         `analysis::statistics::mean_se`){}. {} packings of {n} grains, {:.0} s of wall time on {}.",
        precision.map_or(String::new(), |p| format!(
            ", packings added until se(φ_J) ≤ {p}"
        )),
        done.len(),
        wall,
        super::threads()
    );
    let series = |k: usize| {
        vec![Series {
            label: "dem2d, FIRE, mean ± se".into(),
            points: rows
                .iter()
                .map(|r| (r.0, if k == 0 { r.1 } else { r.3 }))
                .collect(),
            color: 0,
            line: true,
            markers: true,
            y_errors: rows
                .iter()
                .map(|r| if k == 0 { r.2 } else { r.4 })
                // (One packing has no error bar: none drawn.)
                .map(|e| if e.is_finite() { e } else { 0.0 })
                .collect(),
            ..Default::default()
        }]
    };
    // φ_J and Z_J against α, each with its references.
    let panel = |title: &str, y_label: &str, k: usize, hlines: [(f64, &str); 2]| LinePanel {
        title: title.into(),
        x_label: "aspect ratio α = a/b (–)".into(),
        y_label: y_label.into(),
        series: series(k),
        hlines: hlines.map(|(y, label)| (y, label.to_string())).into(),
        legend: plot::Legend::Auto,
        ..Default::default()
    };
    let panels = [
        panel(
            "Jamming packing fraction",
            "φ_J (–)",
            0,
            [
                (0.84, "bidisperse disks ≈ 0.84 (O'Hern 2003)"),
                (0.894, "ellipses' peak 0.891–0.897 (VanderWerf 2018)"),
            ],
        ),
        panel(
            "Contacts per grain at jamming",
            "Z_J, rattlers out (–)",
            1,
            [(4.0, "isostatic disks: 4"), (6.0, "isostatic ellipses: 6")],
        ),
    ];
    super::write_figure("jamming", (1200, 480), (1, 2), &panels)?;
    super::write_text("jamming.md", &md)?;
    Ok(md)
}

//! The angle of repose of a 2D heap of cohesive disks against the Bond number.
//!
//! `dem2d study repose-cohesion` prints a Markdown table (about 14 min on one thread).
//!
//! Protocol: `dem2d study repose`'s dam break ([`super::repose`]: the same 300 disks, radii
//! uniform in 0.8–1.2 cm, ρ = 2.65, Coulomb friction 0.5, e = 0.5, the area law, a column
//! settled without cohesion nor rolling resistance; each Bo on three columns, [`SEEDS`], the
//! first `repose`'s), with a fixed rolling resistance (EPSD,
//! μ_r = 0.1, so that the cohesionless heap comes to rest) and cohesion `contact.cohesion` c
//! switched on when the right wall starts to withdraw, between the grains and with the floor
//! (not with the side walls: [`ColumnSpec::cohesive_case_json`]). The heap is measured as in
//! `repose` ([`heap_surface`]).
//!
//! # The Bond number
//! `Bo = P / (ρ g π r̄²)`: the pull-off force P of two disks of the mean radius r̄ = 1 cm (the
//! largest pull their contact holds against) over the weight of one of them (per unit
//! thickness). Two equal disks of radius r under the linear spring k on the depth δ (two disks
//! get exactly it under the area law) meet on the chord `ℓ(δ) = 2√((δ/2)(2r − δ/2))` (the
//! lens of two circles at distance `2r − δ`), so with cohesion the net push apart is
//! `F(δ) = k δ − c ℓ(δ)`. With `u = δ/2` this is twice `k u − c√(u(2r − u))`, which is half of
//! the disk-on-a-wall push `k′u − 2c√(u(2r − u))` with `k′ = 2k` (contact-laws.md, "Closed
//! forms": least value `−r(√(k′² + 4c²) − k′)`). So
//!
//! `P = −min F = 2r(√(k² + c²) − k)`   (≈ `c² r / k` for c ≪ k; a disk on the floor holds
//! `r(√(k² + 4c²) − k) ≈ 2c² r/k`, twice as much),
//!
//! and for a given Bo, with `W = ρ g π r̄²`: `√(k² + c²) = k + Bo W/(2r̄)`, i.e.
//! `c = √((k + Bo W/(2r̄))² − k²)`. `tests/cohesion.rs` checks P on two disks, one hanging under
//! the other.

use super::repose::{COLUMN, run_to_rest, settled_column};
use dem2d::contact_law::{RollingModel, RollingPart};
use dem2d::dynamics::analysis::heap_surface;
use dem2d::run::RunError;
use dem2d::scene::Case;
use dem2d::scene::generate::{ColumnSpec, DENSITY, G, KN_OVER_RHO_G};

/// The Bond numbers of the study's runs.
pub const BONDS: [f64; 7] = [0.0, 0.3, 1.0, 3.0, 10.0, 20.0, 30.0];

/// The rolling resistance of every run: EPSD, μ_r = 0.1.
const ROLLING: RollingPart = RollingPart {
    model: RollingModel::Epsd,
    friction: 0.1,
    damping: None,
};

/// The mean radius (cm): the Bond number's grain.
const R_MEAN: f64 = 1.0;

/// The linear spring on the depth k = (k_n/ρg) ρ g (dyn/cm per unit thickness).
fn stiffness() -> f64 {
    KN_OVER_RHO_G * DENSITY * G
}

/// The weight of a grain of the mean radius (dyn per unit thickness).
fn weight() -> f64 {
    DENSITY * G * std::f64::consts::PI * R_MEAN * R_MEAN
}

/// The cohesion c (dyn/cm²) whose pull-off force between two disks of the mean radius is `bo`
/// weights: `c = √((k + Bo W/(2r̄))² − k²)` (see the module documentation).
pub fn cohesion_for(bo: f64) -> f64 {
    let k = stiffness();
    let s = k + bo * weight() / (2.0 * R_MEAN);
    // (s − k)(s + k) rather than s² − k²: no cancellation.
    ((s - k) * (s + k)).sqrt()
}

/// The seeds of the study's columns (12 is `repose`'s): each Bo is run on each column.
pub const SEEDS: [u64; 3] = [12, 13, 14];

/// A number to one decimal, or "—" if it is not one.
fn one(x: f64) -> String {
    if x.is_nan() {
        "—".to_string()
    } else {
        format!("{x:.1}")
    }
}

pub fn run() -> Result<String, RunError> {
    let mut columns = Vec::new();
    for seed in SEEDS {
        let column = ColumnSpec { seed, ..COLUMN };
        columns.push((column, settled_column(&column)?));
    }
    let mut md = super::Table::new(
        "| Bo | c (dyn/cm²) | angle of repose (°), columns 12, 13, 14 | mean angle (°) | \
         heap height (cm), mean | toe (cm), mean | at rest at t (s) |\n\
         |---:|---:|---|---:|---:|---:|---|",
    );
    for bo in BONDS {
        let c = cohesion_for(bo);
        let note = format!(
            "Rolling resistance: {}. Cohesion {c} dyn/cm² (Bo = {bo}) between the grains and \
             with the floor.",
            ROLLING.describe()
        );
        let (mut angles, mut heights, mut toes, mut rests) = (vec![], vec![], vec![], vec![]);
        for (column, settled) in &columns {
            let text = column.cohesive_case_json(
                &format!("repose_bond_{bo}_seed_{}", column.seed),
                settled,
                super::repose::GATE_SPEED,
                &ROLLING.given(),
                c,
                &note,
            );
            let case = Case::from_json(&text).expect("case");
            let (w, rest) = run_to_rest(&case)?;
            let (angle, h, toe) = heap_surface(&w, 2.0);
            angles.push(angle);
            heights.push(h);
            toes.push(toe);
            rests.push(rest.map_or("not in 6 s".into(), |t| format!("{t:.2}")));
        }
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let standing = angles.iter().filter(|a| a.is_nan()).count();
        let measured: Vec<f64> = angles.iter().copied().filter(|a| !a.is_nan()).collect();
        let mean_angle = match standing {
            0 => one(mean(&measured)),
            n if n == angles.len() => "— (columns stand)".to_string(),
            n => format!("{} ({n} stand)", one(mean(&measured))),
        };
        md.row(format!(
            "| {bo} | {c:.4e} | {} | {mean_angle} | {:.1} | {:.1} | {} |",
            angles
                .iter()
                .map(|&a| one(a))
                .collect::<Vec<_>>()
                .join(", "),
            mean(&heights),
            mean(&toes),
            rests.join(", ")
        ));
    }
    Ok(md.text())
}

//! The angle of repose of a 2D heap of disks against the coefficient of rolling friction μ_r.
//!
//! `dem2d study repose [--write-cases]` prints a Markdown table.
//!
//! Protocol (a dam break, [`ColumnSpec`]): 300 disks (radii uniform in 0.8–1.2 cm, ρ = 2.65,
//! Coulomb friction 0.5, P's stiffness, dashpots for e = 0.5, the area law) are settled in a
//! column 20 cm wide between two walls on a floor, without rolling resistance, until at rest.
//! From that one settled column, for each rolling model and μ_r, the right wall is withdrawn at
//! 100 cm/s (a moving wall: it is out of the grains' way within a tenth of a second) and the
//! grains flow out over the floor until they are at rest (P's criterion, 1e-7 cm per step held
//! for 1000 steps, or 6 s). The angle of the heap left against the left wall is the slope of
//! its surface ([`heap_surface`]: the tops of the highest grains in 2 cm bins, fitted where the
//! surface is between 20 % and 80 % of the heap's height).
//!
//! With `--write-cases` each run is also written as a case file into `cases/repose/` (the
//! settled column, the withdrawing wall, the μ_r): an ordinary case,
//! `dem2d run cases/repose/epsd_mu_r_0.1.json`.

use dem2d::contact_law::{RollingModel, RollingPart};
use dem2d::dynamics::analysis::heap_surface;
use dem2d::dynamics::{BodyInit, World};
use dem2d::output::progress::CommandProgress;
use dem2d::run::{RunError, Simulation, Stop};
use dem2d::scene::Case;
use dem2d::scene::generate::ColumnSpec;

pub(super) const GATE_SPEED: f64 = 100.0;

/// Runs a case until P's criterion holds or its duration ends; returns the world and the time
/// at rest.
pub(super) fn run_to_rest(case: &Case) -> Result<(World, Option<f64>), RunError> {
    let mut w = case.build_world();
    let mut lines = CommandProgress::new(case.name.clone());
    let stop = Simulation::new(&mut w)
        .observe(&mut lines)
        .until_step(case.steps())
        .quiescence(case.quiescence_criterion())
        .run()?;
    let rest = match stop {
        Stop::AtRest { since } => Some(since as f64 * case.dt),
        _ => None,
    };
    Ok((w, rest))
}

/// The sentence on rolling resistance in a column case's description.
fn resistance(rolling: Option<RollingPart>) -> String {
    format!(
        "Rolling resistance: {}.",
        rolling.map_or("none".to_string(), |r| r.describe())
    )
}

/// The study's column: 300 disks, 20 cm wide.
pub(super) const COLUMN: ColumnSpec = ColumnSpec {
    n: 300,
    width: 20.0,
    seed: 12,
    friction: 0.5,
};

/// The column settled without rolling resistance (gate fixed) until at rest: its bodies, their
/// positions rounded to 1e-6 cm (as a case file keeps them).
pub(super) fn settled_column(column: &ColumnSpec) -> Result<Vec<BodyInit>, RunError> {
    let lattice = column.lattice_bodies();
    let settle =
        Case::from_json(&column.case_json("column", &lattice, 0.0, &[], &resistance(None)))
            .unwrap();
    let (w, rest) = run_to_rest(&settle)?;
    match rest {
        Some(t) => eprintln!("column settled at t = {t} s"),
        None => eprintln!("column not at rest within its duration: continuing from where it is"),
    }
    let settled: Vec<BodyInit> = (0..w.bodies.len())
        .map(|k| BodyInit {
            position: w.bodies.state[k]
                .pose
                .position
                .map(|x| (x * 1e6).round() / 1e6),
            ..lattice[k]
        })
        .collect();
    Ok(settled)
}

pub fn run(write: bool) -> Result<String, RunError> {
    let column = COLUMN;
    let settled = settled_column(&column)?;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/repose");
    if write {
        std::fs::create_dir_all(&dir).expect("cases/repose");
    }
    let mut md = super::Table::new(
        "| rolling model | μ_r | angle of repose (°) | heap height (cm) | toe (cm) | at rest at t (s) |\n\
         |---|---:|---:|---:|---:|---:|",
    );
    let mut runs: Vec<(Option<RollingModel>, f64)> = vec![(None, 0.0)];
    for model in [RollingModel::Epsd, RollingModel::Cdt] {
        for mu_r in [0.05, 0.1, 0.2, 0.4] {
            runs.push((Some(model), mu_r));
        }
    }
    for (model, mu_r) in runs {
        let rolling = model.map(|model| RollingPart {
            model,
            friction: mu_r,
            damping: None,
        });
        let name = match model {
            None => "none".to_string(),
            Some(m) => format!("{}_mu_r_{mu_r}", m.as_str()),
        };
        let text = column.case_json(
            &format!("repose_{name}"),
            &settled,
            GATE_SPEED,
            &rolling.map_or(vec![], |r| r.given()),
            &resistance(rolling),
        );
        if write {
            super::put_case(&dir.join(format!("{name}.json")), &text);
        }
        let case = Case::from_json(&text).expect("case");
        let (w, rest) = run_to_rest(&case)?;
        let (angle, h, toe) = heap_surface(&w, 2.0);
        md.row(format!(
            "| {} | {mu_r} | {angle:.1} | {h:.1} | {toe:.1} | {} |",
            model.map_or("none", |m| m.as_str()),
            rest.map_or("not in 6 s".into(), |t| format!("{t:.2}"))
        ));
    }
    Ok(md.text())
}

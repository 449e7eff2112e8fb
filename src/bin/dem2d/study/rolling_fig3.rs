//! P Fig. 3's thrown circle and ellipse with rolling resistance: when they come to rest.
//!
//! `dem2d study rolling-fig3` prints a Markdown table: for each shape, each
//! normal-force law, each rolling model and μ_r = 0.01, 0.05, the time at which P's quiescence
//! criterion (the case's threshold, held for the case's window) first holds, in a run of up to
//! 20 s.
use dem2d::contact_law::{NormalForce, RollingModel, RollingPart};
use dem2d::output::progress::CommandProgress;
use dem2d::run::{RunError, Simulation, Stop};
use dem2d::scene::Case;

/// When (and where: the body's x) P's criterion first holds, in a run of up to `limit` seconds.
fn rest_time(case: &Case, limit: f64) -> Result<Option<(f64, f64)>, RunError> {
    let mut w = case.build_world();
    let mut lines = CommandProgress::new(case.name.clone());
    let stop = Simulation::new(&mut w)
        .observe(&mut lines)
        .quiescence(case.quiescence_criterion())
        .run_until(|w, _| w.time >= limit)?;
    Ok(match stop {
        Stop::AtRest { since } => Some((since as f64 * w.dt, w.bodies.state[0].pose.position.x)),
        _ => None,
    })
}

pub fn run() -> Result<String, RunError> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let mut md = super::Table::new(
        "| shape | normal force | rolling model | μ_r | at rest at t (s) | x at rest (cm) |\n\
         |---|---|---|---:|---:|---:|",
    );
    for name in ["throw_circle", "throw_ellipse"] {
        let text = std::fs::read_to_string(root.join(format!("{name}.json"))).unwrap();
        let base = Case::from_json(&text).unwrap();
        for nf in [NormalForce::Depth, NormalForce::Area] {
            for model in [RollingModel::Cdt, RollingModel::Epsd] {
                for mu_r in [0.01, 0.05] {
                    let case = base.clone().with_normal_force(nf).map_contacts(|c| {
                        c.with_rolling(Some(RollingPart {
                            model,
                            friction: mu_r,
                            damping: None,
                        }))
                    });
                    let cell = match rest_time(&case, 20.0)? {
                        Some((t, x)) => format!("{t:.3} | {x:.2}"),
                        None => "not in 20 s | —".into(),
                    };
                    md.row(format!(
                        "| {} | {} | {} | {mu_r} | {cell} |",
                        name.trim_start_matches("throw_"),
                        nf.as_str(),
                        model.as_str()
                    ));
                }
            }
        }
    }
    Ok(md.text())
}

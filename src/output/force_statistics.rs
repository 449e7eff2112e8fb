//! `forces.csv` and `forces.json` (`dem2d forces`): the distribution of the normal contact
//! forces of a run's frames, or of a relaxed state, and the stress–fabric check
//! ([`crate::analysis::forces`]).
//!
//! - `forces.csv`: `f_over_mean,pdf,count` — each bin's centre `f/⟨f⟩`, the probability density
//!   (`Σ pdf Δ = 1`) and the number of contacts; body–body contacts with `F_n > 0`.
//! - `forces.json`: `source` (the file the forces come from), `frames`, `contacts`, `mean_force`
//!   (dyn/cm), the anisotropies `a_c`, `theta_c`, `a_n`, `theta_n`, `a_t`, `theta_t`, and
//!   `sin_phi` (`(σ₁ − σ₃)/(σ₁ + σ₃)` of the Love–Weber stress) beside `half_sum`
//!   (`½(a_c + a_n + a_t)`).
//!
//! The forces are the run's own (`contacts.csv`, `dem2d run --contacts`): the last frame, the
//! frame `--frame K`, or every frame from `--from T` pooled. A directory without `contacts.csv`
//! but with a `state.json` (a `dem2d relax` output, or a run's end) gives the forces of that
//! state, evaluated afresh.

use super::analysis::read_contact_frames;
use super::run_data::RunData;
use crate::analysis::forces::{Distribution, StressFabric, distribution, stress_fabric};
use crate::analysis::packing::bounding_window;
use crate::analysis::{Frame, FrameBody, wall_box};
use crate::geometry::Vec2;
use std::fmt::Write as _;
use std::path::Path;

/// What `dem2d forces` is asked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForcesRequest {
    /// The frame (0 the first, −1 the last); `None`: the last, or every frame from `from`.
    pub frame: Option<i64>,
    /// Every frame from this time on (s), pooled.
    pub from: Option<f64>,
    pub bins: usize,
}

/// The statistics and where they come from.
#[derive(Clone, Debug)]
pub struct ForcesReport {
    pub source: String,
    pub frames: usize,
    pub distribution: Distribution,
    pub check: StressFabric,
}

/// The region of a frame: its cell, its box of four walls, or its bodies' extent.
fn area_of(frame: &Frame) -> f64 {
    match (frame.cell, frame.wall_box) {
        (Some(c), _) => c.area(),
        (None, Some(b)) => b.area(),
        (None, None) => bounding_window(&frame.bodies).area(),
    }
}

/// The report of the run or relaxed state in `dir`. Errors that start with `--` are the
/// options' (exit 2); the others the files' (exit 1).
pub fn run_forces(dir: &Path, request: &ForcesRequest) -> Result<ForcesReport, String> {
    if request.bins == 0 || request.bins > 100_000 {
        return Err(format!("--bins: from 1 to 100000, got {}", request.bins));
    }
    if request.frame.is_some() && request.from.is_some() {
        return Err("--frame and --from: give one (a frame, or the frames from a time)".into());
    }
    let contacts_file = dir.join("contacts.csv");
    let (frames, source) = if contacts_file.exists() {
        let data = RunData::load(dir).map_err(|e| e.to_string())?;
        let contacts = read_contact_frames(dir)?;
        let n = data.frames.len() as i64;
        let chosen: Vec<usize> = match (request.frame, request.from) {
            (_, Some(t0)) => (0..data.frames.len())
                .filter(|&k| data.frames[k].t >= t0)
                .collect(),
            (k, None) => {
                let k = k.unwrap_or(-1);
                let at = if k < 0 { n + k } else { k };
                if !(0..n).contains(&at) {
                    return Err(format!(
                        "--frame: {k} is not one of the run's {n} frames (0 to {}, or −1 the \
                         last)",
                        n - 1
                    ));
                }
                vec![at as usize]
            }
        };
        if chosen.is_empty() {
            return Err(format!(
                "--from: no frame at or after {} s",
                request.from.unwrap_or(f64::NAN)
            ));
        }
        let mut frames = Vec::new();
        for k in chosen {
            let f = &data.frames[k];
            let bodies: Vec<FrameBody> = data
                .inits(k)
                .zip(&f.bodies)
                .map(|(b, s)| FrameBody {
                    shape: b.shape,
                    position: Vec2::new(s.x, s.y),
                    angle: s.angle,
                    density: b.density,
                })
                .collect();
            let Some((_, c)) = contacts.contacts.iter().find(|(s, _)| *s == f.step) else {
                return Err(format!(
                    "{}: no rows for step {} (frame {k} of trajectory.csv)",
                    contacts_file.display(),
                    f.step
                ));
            };
            if let Some(c) = c
                .iter()
                .find(|c| c.j >= bodies.len() || c.i.body().is_some_and(|i| i >= bodies.len()))
            {
                return Err(format!(
                    "{}: step {}: contact ({:?}, {}) names a body beyond the {} of the frame",
                    contacts_file.display(),
                    f.step,
                    c.i,
                    c.j,
                    bodies.len()
                ));
            }
            let (walls, _) = data.walls_at(k);
            let lines: Vec<_> = walls
                .iter()
                .filter(|w| w.segment().is_none())
                .map(|w| (w.line().point, w.line().normal))
                .collect();
            frames.push(Frame {
                time: f.t,
                bodies,
                contacts: c.clone(),
                wall_box: wall_box(&lines),
                cell: data.cell_at(k),
            });
        }
        (frames, contacts_file.display().to_string())
    } else {
        let state_file = dir.join("state.json");
        if request.frame.is_some() || request.from.is_some() {
            return Err(format!(
                "--frame, --from: {} has no contacts.csv (run the case with `dem2d run \
                 --contacts`); without them the forces are those of its state.json",
                dir.display()
            ));
        }
        let text = std::fs::read_to_string(&state_file).map_err(|e| {
            format!(
                "{}: cannot read: {e} (a run made with `--contacts`, or a directory with a \
                 state.json such as `dem2d relax` writes)",
                state_file.display()
            )
        })?;
        let file = crate::scene::state::CaseFile::from_json(&text)
            .map_err(|e| format!("{}: {e}", state_file.display()))?;
        let mut world = file.build_world();
        world.evaluate_forces();
        world.refresh_contact_extras();
        (
            vec![Frame::from_world(&world)],
            state_file.display().to_string(),
        )
    };
    let forces: Vec<f64> = frames
        .iter()
        .flat_map(|f| f.contacts.iter())
        .filter(|c| c.giver_body().is_some())
        .map(|c| c.normal_force())
        .collect();
    let with_areas: Vec<(Frame, f64)> = frames
        .into_iter()
        .map(|f| {
            let a = area_of(&f);
            (f, a)
        })
        .collect();
    Ok(ForcesReport {
        source,
        frames: with_areas.len(),
        distribution: distribution(&forces, request.bins),
        check: stress_fabric(&with_areas),
    })
}

/// `forces.csv`'s text.
pub fn forces_csv(r: &ForcesReport) -> String {
    let mut text = String::from("f_over_mean,pdf,count\n");
    for (x, p, n) in &r.distribution.rows {
        writeln!(text, "{x},{p},{n}").expect("string");
    }
    text
}

/// `forces.json`'s text.
pub fn forces_json(r: &ForcesReport) -> String {
    let f = &r.check.fabric;
    let num = |x: f64| {
        if x.is_finite() {
            serde_json::Value::from(x)
        } else {
            serde_json::Value::Null
        }
    };
    let v = serde_json::json!({
        "source": r.source,
        "frames": r.frames,
        "contacts": r.distribution.count,
        "mean_force": num(r.distribution.mean),
        "a_c": num(f.a_c),
        "theta_c": num(f.theta_c),
        "a_n": num(f.a_n),
        "theta_n": num(f.theta_n),
        "a_t": num(f.a_t),
        "theta_t": num(f.theta_t),
        "sin_phi": num(r.check.sin_phi),
        "half_sum": num(r.check.half_sum),
    });
    serde_json::to_string_pretty(&v).expect("json") + "\n"
}

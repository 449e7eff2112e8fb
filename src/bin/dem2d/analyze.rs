//! `dem2d analyze RUN_DIR`: recomputes `analysis.csv` from a run's files — the bodies' shapes
//! from `case.json`, their poses from `trajectory.csv`, the contacts from `contacts.csv` and the
//! walls from `walls.csv` (the first written by `dem2d run --contacts`, the second by every run
//! with walls). A run without `contacts.csv` cannot be analysed (the forces are not in its other
//! files): the command says so and exits 1. Without `walls.csv` (a run written before dem2d
//! recorded the walls), the walls of `case.json` as given are used. A run whose case inserts or
//! removes bodies (`insert`, `outflow`) is analysed over the bodies each frame holds, an inserted
//! body's shape from `inserted.csv`.

use dem2d::analysis::{self, Frame, FrameBody, Window, wall_box};
use dem2d::output::analysis::{analysis_header, analysis_row, read_contact_frames};
use dem2d::output::cell::read_cells;
use dem2d::output::run_data::RunData;
use dem2d::run::time::time_text;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

/// Writes the analysis; errors are `(exit code, message)`.
pub fn run(dir: &Path, window: Option<&[f64]>, out: Option<&Path>) -> Result<(), (u8, String)> {
    let window = match window {
        None => None,
        Some(&[x0, x1, y0, y1])
            if x0 < x1 && y0 < y1 && [x0, x1, y0, y1].iter().all(|v| v.is_finite()) =>
        {
            Some(Window { x0, x1, y0, y1 })
        }
        Some(w) => {
            return Err((
                2,
                format!("--window: expected x0,x1,y0,y1 with x0 < x1 and y0 < y1, got {w:?}"),
            ));
        }
    };
    let data = RunData::load(dir).map_err(|e| (1, e.to_string()))?;
    let contacts = read_contact_frames(dir).map_err(|e| (1, e))?;
    let by_step: HashMap<u64, usize> = contacts
        .contacts
        .iter()
        .enumerate()
        .map(|(k, (s, _))| (*s, k))
        .collect();
    let wall_frames: Vec<(u64, Vec<_>)> = data
        .walls
        .iter()
        .flat_map(|w| &w.frames)
        .map(|f| {
            (
                f.step,
                f.walls.iter().map(|w| (w.point, w.normal)).collect(),
            )
        })
        .collect();
    let walls_by_step: HashMap<u64, usize> = wall_frames
        .iter()
        .enumerate()
        .map(|(k, (s, _))| (*s, k))
        .collect();
    let case_walls: Vec<_> = data
        .case
        .walls
        .iter()
        // (The box of four half-plane walls: segment walls and drums bound no box.)
        .filter(|w| w.is_half_plane())
        .map(|w| (w.line().point, w.line().normal))
        .collect();
    // A periodic cell's state at each frame (its size, shift and stress: `cell.csv`).
    let cells: HashMap<u64, dem2d::dynamics::cell::Cell> = match &data.case.cell {
        Some(c) => read_cells(dir, c)
            .map_err(|e| (1, e.to_string()))?
            .into_iter()
            .collect(),
        None => HashMap::new(),
    };
    let mut text = format!("{}\n", analysis_header(data.case.cell.is_some()));
    for (i, f) in data.frames.iter().enumerate() {
        // The bodies the frame holds (all the case's, or where it inserts or removes bodies
        // those present at its step).
        let n = f.bodies.len();
        let bodies = data
            .inits(i)
            .zip(&f.bodies)
            .map(|(b, s)| FrameBody {
                shape: b.shape,
                position: dem2d::geometry::Vec2::new(s.x, s.y),
                angle: s.angle,
                density: b.density,
            })
            .collect();
        let frame_contacts = by_step
            .get(&f.step)
            .map(|&k| contacts.contacts[k].1.clone())
            .unwrap_or_default();
        if let Some(c) = frame_contacts
            .iter()
            .find(|c| c.j >= n || c.i.body().is_some_and(|i| i >= n))
        {
            return Err((
                1,
                format!(
                    "{}: step {}: contact ({:?}, {}) names a body beyond the {n} of the frame",
                    dir.join("contacts.csv").display(),
                    f.step,
                    c.i,
                    c.j
                ),
            ));
        }
        let walls = walls_by_step
            .get(&f.step)
            .map_or(&case_walls, |&k| &wall_frames[k].1);
        let cell = match data.case.cell {
            Some(_) => Some(*cells.get(&f.step).ok_or_else(|| {
                (
                    1,
                    format!(
                        "{}: no row for step {} of trajectory.csv",
                        dir.join("cell.csv").display(),
                        f.step
                    ),
                )
            })?),
            None => None,
        };
        let frame = Frame {
            time: f.t,
            bodies,
            contacts: frame_contacts,
            wall_box: wall_box(walls),
            cell,
        };
        let m = analysis::measure(&frame, window);
        let t = time_text(f.step, data.case.dt);
        writeln!(text, "{}", analysis_row(&t, &m)).expect("string");
    }
    let out = out.map_or_else(|| dir.join("analysis.csv"), Path::to_path_buf);
    std::fs::write(&out, text).map_err(|e| (1, format!("{}: cannot write: {e}", out.display())))?;
    println!("{}", out.display());
    Ok(())
}

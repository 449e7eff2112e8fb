//! Reading a run directory back (`case.json`, `trajectory.csv`, `increments.csv`,
//! `summary.json`, and `walls.csv` when the case has walls) for plots and reports.
//!
//! A run stopped while writing (killed, or a full disk) can leave a last line without its newline
//! and a last frame without all of its bodies: those are left out — every frame read has every
//! body — and [`RunData::incomplete`] says what was left out.

use crate::scene::Case;
use std::fmt;
use std::path::{Path, PathBuf};

/// State of one body in one frame (a row of `trajectory.csv`; the summary's `final_state`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct BodyState {
    pub x: f64,
    pub y: f64,
    pub angle: f64,
    pub vx: f64,
    pub vy: f64,
    pub omega: f64,
}

/// All bodies at one output step.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub step: u64,
    pub t: f64,
    pub bodies: Vec<BodyState>,
    /// In a periodic cell, each body's image counts `ix, iy` (the trajectory's last columns:
    /// see [`crate::dynamics::cell::Cell::unwrapped`]); empty otherwise.
    pub images: Vec<[i32; 2]>,
}

/// One row of `increments.csv`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Increments {
    pub step: u64,
    pub t: f64,
    pub mean_dx: f64,
    pub mean_dy: f64,
    pub mean_dtheta: f64,
    /// NaN on the rows that do not carry it (off the output steps).
    pub unbalanced_force_ratio: f64,
    pub contacts: u64,
}

/// A run read back from its directory.
#[derive(Clone, Debug)]
pub struct RunData {
    pub dir: PathBuf,
    pub case: Case,
    pub frames: Vec<Frame>,
    pub increments: Vec<Increments>,
    pub summary: serde_json::Value,
    /// The walls at the output frames (`walls.csv`; `None` for a run without one: no walls, or
    /// written before dem2d recorded them).
    pub walls: Option<super::walls::WallFrames>,
    /// What was left out of files that end part-way through a line or a frame (one note per
    /// file).
    pub incomplete: Vec<String>,
    /// In a periodic cell, the cell at each row of `cell.csv` by step (its size follows an
    /// imposed pressure); empty otherwise.
    pub cells: Vec<(u64, crate::dynamics::cell::Cell)>,
}

/// What went wrong reading a run directory: the file and why.
#[derive(Debug)]
pub struct ReadError {
    pub file: PathBuf,
    pub message: String,
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.file.display(), self.message)
    }
}

impl std::error::Error for ReadError {}

fn read(file: &Path) -> Result<String, ReadError> {
    std::fs::read_to_string(file).map_err(|e| ReadError {
        file: file.to_path_buf(),
        message: format!("cannot read: {e}"),
    })
}

/// The text up to its last newline, and whether anything followed it (a line cut short).
pub fn whole_lines(text: &str) -> (&str, bool) {
    match text.rfind('\n') {
        Some(k) => (&text[..=k], k + 1 < text.len()),
        None => ("", !text.is_empty()),
    }
}

/// The numbers of a CSV line; an empty field is a value not written on that row
/// (increments.csv's unbalanced ratio off the output steps, what a row of walls.csv does not
/// carry): NaN.
pub(crate) fn fields(line: &str) -> Result<Vec<f64>, std::num::ParseFloatError> {
    line.split(',')
        .map(|f| {
            if f.is_empty() {
                Ok(f64::NAN)
            } else {
                f.parse::<f64>()
            }
        })
        .collect()
}

/// Parses CSV rows of numbers with the expected header; a last line without its newline is
/// left out (the second value says so).
pub(crate) fn rows(file: &Path, header: &str) -> Result<(Vec<Vec<f64>>, bool), ReadError> {
    let text = read(file)?;
    let (whole, partial) = whole_lines(&text);
    // A header cut short is no table.
    let mut lines = if whole.is_empty() {
        text.lines()
    } else {
        whole.lines()
    };
    let bad = |line: usize, m: String| ReadError {
        file: file.to_path_buf(),
        message: format!("line {line}: {m}"),
    };
    match lines.next() {
        Some(h) if h == header => {}
        other => {
            return Err(bad(
                1,
                format!("expected the header `{header}`, got {other:?}"),
            ));
        }
    }
    let width = header.split(',').count();
    let mut out = Vec::new();
    for (k, line) in lines.enumerate() {
        let v = fields(line).map_err(|e| bad(k + 2, format!("not a number: {e}")))?;
        if v.len() != width {
            return Err(bad(k + 2, format!("{} fields, expected {width}", v.len())));
        }
        out.push(v);
    }
    Ok((out, partial && !whole.is_empty()))
}

impl RunData {
    /// Reads the run in `dir`.
    pub fn load(dir: &Path) -> Result<RunData, ReadError> {
        let case_file = dir.join("case.json");
        let case = Case::from_json(&read(&case_file)?).map_err(|e| ReadError {
            file: case_file.clone(),
            message: e.to_string(),
        })?;
        let traj_file = dir.join("trajectory.csv");
        if case.flow.is_some() {
            return Err(ReadError {
                file: case_file,
                message: "the case inserts or removes bodies (`insert`, `outflow`): its frames \
                          hold different bodies, which these plots and reports do not draw; \
                          read trajectory.csv by its `body` column (each body's identity) and \
                          discharge.csv"
                    .to_string(),
            });
        }
        let cell = case.cell.is_some();
        let header = if cell {
            super::trace::TRAJECTORY_HEADER_CELL
        } else {
            super::trace::TRAJECTORY_HEADER
        };
        let (traj, traj_partial) = rows(&traj_file, header)?;
        let n = case.bodies.len();
        let mut incomplete = Vec::new();
        let mut frames: Vec<Frame> = Vec::new();
        for (line, r) in traj.iter().enumerate() {
            let (step, t) = (r[0] as u64, r[1]);
            if frames.last().is_none_or(|f| f.step != step) {
                if let Some(f) = frames.last()
                    && f.bodies.len() != n
                {
                    return Err(ReadError {
                        file: traj_file,
                        message: format!(
                            "step {}: {} bodies, but case.json has {n}",
                            f.step,
                            f.bodies.len()
                        ),
                    });
                }
                frames.push(Frame {
                    step,
                    t,
                    bodies: Vec::new(),
                    images: Vec::new(),
                });
            }
            let f = frames.last_mut().expect("pushed");
            if r[2] != f.bodies.len() as f64 {
                return Err(ReadError {
                    file: traj_file,
                    message: format!(
                        "line {}: body {} where body {} was due (each frame lists bodies 0 to {})",
                        line + 2,
                        r[2],
                        f.bodies.len(),
                        n.saturating_sub(1)
                    ),
                });
            }
            f.bodies.push(BodyState {
                x: r[3],
                y: r[4],
                angle: r[5],
                vx: r[6],
                vy: r[7],
                omega: r[8],
            });
            if cell {
                f.images.push([r[9] as i32, r[10] as i32]);
            }
        }
        if let Some(last) = frames.last()
            && last.bodies.len() != n
        {
            incomplete.push(format!(
                "{}: the last frame (step {}) has {} of the {n} bodies (the run was stopped \
                 while writing it): drawn up to the frame before",
                traj_file.display(),
                last.step,
                last.bodies.len()
            ));
            frames.pop();
        } else if traj_partial {
            incomplete.push(format!(
                "{}: the last line is incomplete (the run was stopped while writing it): left out",
                traj_file.display()
            ));
        }
        let incs_file = dir.join("increments.csv");
        let (incs, incs_partial) = rows(
            &incs_file,
            "step,t,mean_dx,mean_dy,mean_dtheta,unbalanced_force_ratio,contacts",
        )?;
        if incs_partial {
            incomplete.push(format!(
                "{}: the last line is incomplete (the run was stopped while writing it): left out",
                incs_file.display()
            ));
        }
        let increments = incs
            .into_iter()
            .map(|r| Increments {
                step: r[0] as u64,
                t: r[1],
                mean_dx: r[2],
                mean_dy: r[3],
                mean_dtheta: r[4],
                unbalanced_force_ratio: r[5],
                contacts: r[6] as u64,
            })
            .collect();
        let summary_file = dir.join("summary.json");
        let summary = serde_json::from_str(&read(&summary_file)?).map_err(|e| ReadError {
            file: summary_file.clone(),
            message: format!("malformed JSON: {e}"),
        })?;
        if frames.is_empty() {
            return Err(ReadError {
                file: traj_file,
                message: "no complete frame".into(),
            });
        }
        let walls = match case.walls.is_empty() {
            true => None,
            false => super::walls::read_walls(dir, case.walls.len())?,
        };
        if let Some(note) = walls.as_ref().and_then(|w| w.incomplete.clone()) {
            incomplete.push(note);
        }
        let cells = match &case.cell {
            Some(c) => super::cell::read_cells(dir, c)?,
            None => Vec::new(),
        };
        Ok(RunData {
            dir: dir.to_path_buf(),
            case,
            frames,
            increments,
            summary,
            walls,
            incomplete,
            cells,
        })
    }
}

impl RunData {
    /// The periodic cell at frame `k`: as `cell.csv` recorded it at the frame's step, else the
    /// case's (`None` without a cell).
    pub fn cell_at(&self, k: usize) -> Option<crate::dynamics::cell::Cell> {
        let step = self.frames[k].step;
        match self.cells.binary_search_by_key(&step, |c| c.0) {
            Ok(at) => Some(self.cells[at].1),
            Err(_) => self.case.cell,
        }
    }

    /// The case's walls where they were at frame `k`: as `walls.csv` recorded them at its step,
    /// else placed by their motion (fixed; `p₀ + t v` at a constant velocity). The second value
    /// is false when some wall's place is not known (a servo wall in a run without `walls.csv`:
    /// left at its starting point).
    pub fn walls_at(&self, k: usize) -> (Vec<crate::dynamics::Boundary>, bool) {
        use crate::dynamics::boundary::Motion;
        let frame = &self.frames[k];
        let mut walls = self.case.walls.clone();
        let recorded = self.walls.as_ref().and_then(|w| {
            let at = w
                .frames
                .binary_search_by_key(&frame.step, |f| f.step)
                .ok()?;
            Some(&w.frames[at])
        });
        if let Some(r) = recorded {
            for (w, row) in walls.iter_mut().zip(&r.walls) {
                w.move_to(row.point);
                w.velocity = row.velocity;
            }
            return (walls, true);
        }
        let mut known = true;
        for w in &mut walls {
            match w.motion {
                Motion::Fixed => {}
                Motion::Velocity(v) => {
                    w.move_to(w.start + v * frame.t);
                    w.velocity = v;
                }
                Motion::Servo(_) | Motion::Program(_) => known = false,
            }
        }
        (walls, known)
    }
}

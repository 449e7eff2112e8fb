//! Reading a run directory back (`case.json`, `trajectory.csv`, `increments.csv`,
//! `summary.json`, `walls.csv` when the case has walls, `inserted.csv` when it inserts bodies)
//! for plots and reports.
//!
//! A frame holds the bodies present at its step, in increasing identity ([`Frame::ids`]): every
//! body of the case, or where the case inserts or removes bodies (`insert`, `outflow`) those
//! inserted by then and not yet removed. What each body is (its shape, density, material) is
//! [`RunData::init`] of its identity: the case's body, or for an inserted one its inserter's
//! shape of the radius and aspect `inserted.csv` records.
//!
//! A run stopped while writing (killed, or a full disk) can leave a last line without its newline
//! and a last frame without all of its bodies: those are left out — every frame read has every
//! body — and [`RunData::incomplete`] says what was left out.

use crate::dynamics::BodyInit;
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
    /// Each body's identity (`trajectory.csv`'s `body`), increasing: `0 … n − 1` in a case
    /// that neither inserts nor removes bodies.
    pub ids: Vec<u64>,
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
    /// What each body is, by identity (see [`RunData::init`]).
    known: Vec<Option<BodyInit>>,
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
        let flows = case.flow.is_some();
        let cell = case.cell.is_some();
        let header = if cell {
            super::trace::TRAJECTORY_HEADER_CELL
        } else {
            super::trace::TRAJECTORY_HEADER
        };
        let mut incomplete = Vec::new();
        let known = known_bodies(dir, &case_file, &case, &mut incomplete)?;
        let (traj, traj_partial) = rows(&traj_file, header)?;
        let n = case.bodies.len();
        let mut frames: Vec<Frame> = Vec::new();
        for (line, r) in traj.iter().enumerate() {
            let (step, t) = (r[0] as u64, r[1]);
            if frames.last().is_none_or(|f| f.step != step) {
                if let Some(f) = frames.last()
                    && !flows
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
                    ids: Vec::new(),
                    images: Vec::new(),
                });
            }
            let f = frames.last_mut().expect("pushed");
            let id = r[2];
            if !flows && id != f.bodies.len() as f64 {
                return Err(ReadError {
                    file: traj_file,
                    message: format!(
                        "line {}: body {id} where body {} was due (each frame lists bodies 0 to {})",
                        line + 2,
                        f.bodies.len(),
                        n.saturating_sub(1)
                    ),
                });
            }
            if flows {
                let known_id = id >= 0.0
                    && id.fract() == 0.0
                    && known.get(id as usize).is_some_and(Option::is_some);
                if !known_id {
                    return Err(ReadError {
                        file: traj_file,
                        message: format!(
                            "line {}: body {id} is neither a body of case.json nor one \
                             inserted.csv records",
                            line + 2
                        ),
                    });
                }
                if f.ids.last().is_some_and(|&last| last >= id as u64) {
                    return Err(ReadError {
                        file: traj_file,
                        message: format!(
                            "line {}: body {id} after body {} (a frame lists its bodies in \
                             increasing `body`)",
                            line + 2,
                            f.ids[f.ids.len() - 1]
                        ),
                    });
                }
            }
            f.ids.push(id as u64);
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
            && !flows
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
        } else if traj_partial && flows && frames.len() > 1 {
            // (Its bodies vary: a frame cut short cannot be told from a whole one.)
            let last = frames.pop().expect("two frames");
            incomplete.push(format!(
                "{}: the last line is incomplete (the run was stopped while writing it): its \
                 frame (step {}) is left out",
                traj_file.display(),
                last.step
            ));
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
            known,
        })
    }
}

/// What each body of the run is, by identity: the case's bodies (body k, or where a continued
/// run's case.json lists their identities in `state.ids`, the k-th of those), and the bodies
/// `inserted.csv` records (a case with an `insert`).
fn known_bodies(
    dir: &Path,
    case_file: &Path,
    case: &Case,
    incomplete: &mut Vec<String>,
) -> Result<Vec<Option<BodyInit>>, ReadError> {
    let n = case.bodies.len();
    let ids: Vec<u64> = match case.flow {
        None => (0..n as u64).collect(),
        Some(_) => {
            let value: serde_json::Value =
                serde_json::from_str(&read(case_file)?).map_err(|e| ReadError {
                    file: case_file.to_path_buf(),
                    message: format!("malformed JSON: {e}"),
                })?;
            match value["state"]["ids"].as_array() {
                Some(a) => a.iter().filter_map(serde_json::Value::as_u64).collect(),
                None => (0..n as u64).collect(),
            }
        }
    };
    if ids.len() != n {
        return Err(ReadError {
            file: case_file.to_path_buf(),
            message: format!("state.ids: {} identities for {n} bodies", ids.len()),
        });
    }
    let mut known: Vec<Option<BodyInit>> = Vec::new();
    let mut put = |id: u64, b: BodyInit| {
        let k = id as usize;
        if known.len() <= k {
            known.resize(k + 1, None);
        }
        known[k] = Some(b);
    };
    for (&id, b) in ids.iter().zip(&case.bodies) {
        put(id, *b);
    }
    let Some(flow) = case.flow.as_ref().filter(|f| !f.inserters.is_empty()) else {
        return Ok(known);
    };
    let file = dir.join("inserted.csv");
    if !file.exists() {
        return Err(ReadError {
            file,
            message: "is missing: the case inserts bodies (`insert`), and this file records \
                      what each inserted body is (a run by a dem2d older than it cannot be \
                      drawn)"
                .into(),
        });
    }
    let (rows, partial) = rows(&file, super::discharge::INSERTED_HEADER)?;
    if partial {
        incomplete.push(format!(
            "{}: the last line is incomplete (the run was stopped while writing it): left out",
            file.display()
        ));
    }
    for (line, r) in rows.iter().enumerate() {
        let which = r[3];
        let Some(ins) = (which >= 0.0 && which.fract() == 0.0)
            .then(|| flow.inserters.get(which as usize))
            .flatten()
        else {
            return Err(ReadError {
                file,
                message: format!(
                    "line {}: insert {which}: the case has {} insertion regions",
                    line + 2,
                    flow.inserters.len()
                ),
            });
        };
        let (id, r_eq, aspect) = (r[2], r[4], r[5]);
        if !(id >= 0.0 && id.fract() == 0.0 && r_eq > 0.0 && aspect >= 1.0) {
            return Err(ReadError {
                file,
                message: format!(
                    "line {}: body {id}, r {r_eq}, aspect {aspect}: expected an identity, a \
                     positive radius and an aspect ratio of at least 1",
                    line + 2
                ),
            });
        }
        put(
            id as u64,
            BodyInit {
                shape: ins.shape.make(r_eq, aspect),
                position: crate::geometry::Vec2::zeros(),
                angle: 0.0,
                velocity: ins.velocity,
                omega: ins.omega,
                density: ins.density,
                material: ins.material,
                prescribed: false,
            },
        );
    }
    Ok(known)
}

impl RunData {
    /// What the body of identity `id` is: the case's body, or an inserted body as its inserter
    /// made it (its shape, density, material and initial velocity; its position is the
    /// frames'). Every identity of a frame has one.
    pub fn init(&self, id: u64) -> &BodyInit {
        self.known[id as usize]
            .as_ref()
            .expect("the reader checked every frame's identities")
    }

    /// What each body of frame `k` is, in the frame's order.
    pub fn inits(&self, k: usize) -> impl Iterator<Item = &BodyInit> + '_ {
        self.frames[k].ids.iter().map(|&id| self.init(id))
    }

    /// Where the body of identity `id` is in frame `k` (`None`: not present then).
    pub fn place(&self, k: usize, id: u64) -> Option<usize> {
        self.frames[k].ids.binary_search(&id).ok()
    }

    /// The most bodies a frame holds.
    pub fn most_bodies(&self) -> usize {
        self.frames
            .iter()
            .map(|f| f.bodies.len())
            .max()
            .unwrap_or(0)
    }

    /// The identities of the bodies present in any of the frames `frames`, increasing.
    pub fn ids_in(&self, frames: &[usize]) -> Vec<u64> {
        let mut ids: Vec<u64> = frames
            .iter()
            .flat_map(|&k| self.frames[k].ids.iter().copied())
            .collect();
        ids.sort_unstable();
        ids.dedup();
        ids
    }

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
                w.place_by_point(row.point, row.angle);
                w.velocity = row.velocity;
            }
            return (walls, true);
        }
        let mut known = true;
        for w in &mut walls {
            match w.motion {
                Motion::Fixed => {}
                Motion::Velocity(v) => {
                    let angle = w.turn.map_or(0.0, |t| t.rate * frame.t);
                    w.place(w.start + v * frame.t, angle);
                    w.velocity = v;
                }
                Motion::Servo(_) | Motion::Program(_) => known = false,
            }
        }
        (walls, known)
    }
}

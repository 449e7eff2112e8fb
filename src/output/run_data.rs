//! Reading a run directory back (`case.json`, `trajectory.csv`, `increments.csv`,
//! `summary.json`) for plots and reports.

use crate::scene::Case;
use std::fmt;
use std::path::{Path, PathBuf};

/// State of one body in one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
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

/// Parses CSV rows of numbers with the expected header.
fn rows(file: &Path, header: &str) -> Result<Vec<Vec<f64>>, ReadError> {
    let text = read(file)?;
    let mut lines = text.lines();
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
        // An empty field is a value not written on that row (increments.csv's unbalanced ratio
        // off the output steps): NaN.
        let v: Result<Vec<f64>, _> = line
            .split(',')
            .map(|f| {
                if f.is_empty() {
                    Ok(f64::NAN)
                } else {
                    f.parse::<f64>()
                }
            })
            .collect();
        let v = v.map_err(|e| bad(k + 2, format!("not a number: {e}")))?;
        if v.len() != width {
            return Err(bad(k + 2, format!("{} fields, expected {width}", v.len())));
        }
        out.push(v);
    }
    Ok(out)
}

impl RunData {
    /// Reads the run in `dir`.
    pub fn load(dir: &Path) -> Result<RunData, ReadError> {
        let case_file = dir.join("case.json");
        let case = Case::from_json(&read(&case_file)?).map_err(|e| ReadError {
            file: case_file.clone(),
            message: e.to_string(),
        })?;
        let traj = rows(
            &dir.join("trajectory.csv"),
            "step,t,body,x,y,angle,vx,vy,omega",
        )?;
        let mut frames: Vec<Frame> = Vec::new();
        for r in traj {
            let (step, t) = (r[0] as u64, r[1]);
            if frames.last().is_none_or(|f| f.step != step) {
                frames.push(Frame {
                    step,
                    t,
                    bodies: Vec::new(),
                });
            }
            let f = frames.last_mut().expect("pushed");
            f.bodies.push(BodyState {
                x: r[3],
                y: r[4],
                angle: r[5],
                vx: r[6],
                vy: r[7],
                omega: r[8],
            });
        }
        let increments = rows(
            &dir.join("increments.csv"),
            "step,t,mean_dx,mean_dy,mean_dtheta,unbalanced_force_ratio,contacts",
        )?
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
                file: dir.join("trajectory.csv"),
                message: "no rows".into(),
            });
        }
        Ok(RunData {
            dir: dir.to_path_buf(),
            case,
            frames,
            increments,
            summary,
        })
    }
}

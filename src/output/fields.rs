//! `fields.csv`: the coarse-grained fields of a run directory (`dem2d fields`,
//! [`crate::analysis::fields`]), one row per bin, averaged over the output frames in a window of
//! time.
//!
//! `y,phi,vx,vy,temperature,sxx,syy,sxy,nematic,frames` (`x,…` for bins along x):
//! - `y` the bin's centre (cm); `phi` the packing fraction; `vx`, `vy` the mass-weighted mean
//!   velocity (cm/s; in a Lees–Edwards cell about the imposed profile with `--relative`);
//!   `temperature` the translational fluctuation per unit mass about it, `⟨|v − v̄|²⟩/2`
//!   (cm²/s²);
//! - `sxx`, `syy`, `sxy` the stress (dyn/cm, compression positive, the contact part spread along
//!   the branch vectors plus the kinetic part); empty for a run without `contacts.csv` (the
//!   forces are in no other file: run it with `--contacts`);
//! - `nematic` the order parameter S₂ of the long axes (empty where the bin saw only disks);
//!   `frames` the number of frames averaged.

use super::analysis::read_contact_frames;
use super::run_data::RunData;
use crate::analysis::fields::{Axis, Bin, Binning, FieldBody, FieldFrame, Span, fields};
use crate::analysis::packing::bounding_window;
use crate::analysis::{FrameBody, wall_box};
use crate::geometry::Vec2;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

/// What `dem2d fields` is asked.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldRequest {
    pub axis: Axis,
    pub bins: usize,
    /// The window of time (s): the frames with `from ≤ t ≤ to`.
    pub from: Option<f64>,
    pub to: Option<f64>,
    /// The range along the axis outside a periodic cell (default: the box of four walls, else
    /// the bodies' extent over the window).
    pub range: Option<(f64, f64)>,
    /// In a Lees–Edwards cell, `vx` about the imposed profile.
    pub relative: bool,
}

/// The fields of a run and what the reader should know about them.
#[derive(Clone, Debug)]
pub struct Fields {
    pub axis: Axis,
    pub bins: Vec<Bin>,
    /// Whether the stress columns hold anything (the run wrote `contacts.csv`).
    pub stress: bool,
    /// Notes for the terminal (no contacts, the range chosen).
    pub notes: Vec<String>,
}

/// The fields of the run in `dir` (see the module documentation). Errors name the file or the
/// option.
pub fn run_fields(dir: &Path, request: &FieldRequest) -> Result<Fields, String> {
    if request.bins == 0 || request.bins > 1_000_000 {
        return Err(format!("--bins: from 1 to 1000000, got {}", request.bins));
    }
    let data = RunData::load(dir).map_err(|e| e.to_string())?;
    let mut notes = Vec::new();
    let contacts = if dir.join("contacts.csv").exists() {
        Some(read_contact_frames(dir)?)
    } else {
        notes.push(format!(
            "{}: none — the stress columns are empty (the forces are in no other file: run the \
             case with `dem2d run --contacts`)",
            dir.join("contacts.csv").display()
        ));
        None
    };
    let by_step: HashMap<u64, usize> = contacts
        .iter()
        .flat_map(|c| c.contacts.iter().enumerate().map(|(k, (s, _))| (*s, k)))
        .collect();
    let (from, to) = (
        request.from.unwrap_or(f64::NEG_INFINITY),
        request.to.unwrap_or(f64::INFINITY),
    );
    if from > to || from.is_nan() || to.is_nan() {
        return Err(format!("--from {from} is after --to {to}"));
    }
    let mut frames = Vec::new();
    for (k, f) in data.frames.iter().enumerate() {
        if f.t < from || f.t > to {
            continue;
        }
        let bodies: Vec<FieldBody> = data
            .inits(k)
            .zip(&f.bodies)
            .map(|(b, s)| FieldBody {
                shape: b.shape,
                position: Vec2::new(s.x, s.y),
                angle: s.angle,
                velocity: Vec2::new(s.vx, s.vy),
                density: b.density,
            })
            .collect();
        let frame_contacts = match (&contacts, by_step.get(&f.step)) {
            (Some(c), Some(&at)) => c.contacts[at].1.clone(),
            _ => Vec::new(),
        };
        if let Some(c) = frame_contacts
            .iter()
            .find(|c| c.j >= bodies.len() || c.i.body().is_some_and(|i| i >= bodies.len()))
        {
            return Err(format!(
                "{}: step {}: contact ({:?}, {}) names a body beyond the {} of the frame",
                dir.join("contacts.csv").display(),
                f.step,
                c.i,
                c.j,
                bodies.len()
            ));
        }
        frames.push((
            k,
            FieldFrame {
                bodies,
                contacts: frame_contacts,
                cell: data.cell_at(k),
            },
        ));
    }
    if frames.is_empty() {
        return Err(format!(
            "no output frame in the window [{from}, {to}] s (the run's frames span {} to {} s)",
            data.frames.first().map_or(f64::NAN, |f| f.t),
            data.frames.last().map_or(f64::NAN, |f| f.t)
        ));
    }
    // The range outside a cell: given, the box of four walls, or the bodies' extent.
    let span = if data.case.cell.is_some() {
        Span {
            lo: 0.0,
            hi: 1.0,
            across: 1.0,
        }
    } else {
        let (walls, _) = data.walls_at(frames[0].0);
        let lines: Vec<_> = walls
            .iter()
            .filter(|w| w.segment().is_none())
            .map(|w| (w.line().point, w.line().normal))
            .collect();
        let extent = match wall_box(&lines) {
            Some(b) => b,
            None => {
                let all: Vec<FrameBody> = frames
                    .iter()
                    .flat_map(|(_, f)| f.bodies.iter())
                    .map(|b| FrameBody {
                        shape: b.shape,
                        position: b.position,
                        angle: b.angle,
                        density: b.density,
                    })
                    .collect();
                notes.push(
                    "no box of four walls: the bins span the bodies' extent over the window".into(),
                );
                bounding_window(&all)
            }
        };
        let (lo, hi, across) = match request.axis {
            Axis::X => (extent.x0, extent.x1, extent.y1 - extent.y0),
            Axis::Y => (extent.y0, extent.y1, extent.x1 - extent.x0),
        };
        let (lo, hi) = request.range.unwrap_or((lo, hi));
        if !(lo < hi && lo.is_finite() && hi.is_finite() && across > 0.0) {
            return Err(format!(
                "--range: the bins' range [{lo}, {hi}] (width across {across} cm) is empty"
            ));
        }
        Span { lo, hi, across }
    };
    if data.case.cell.is_some() && request.range.is_some() {
        return Err("--range: in a periodic cell the bins divide the cell's side".into());
    }
    let binning = Binning {
        axis: request.axis,
        bins: request.bins,
        span,
        relative: request.relative,
    };
    let frames: Vec<FieldFrame> = frames.into_iter().map(|(_, f)| f).collect();
    Ok(Fields {
        axis: request.axis,
        bins: fields(&frames, &binning),
        stress: contacts.is_some(),
        notes,
    })
}

/// The header of `fields.csv` for bins along `axis`.
pub fn fields_header(axis: Axis) -> String {
    format!(
        "{},phi,vx,vy,temperature,sxx,syy,sxy,nematic,frames",
        axis.name()
    )
}

/// `fields.csv`'s text.
pub fn fields_csv(f: &Fields) -> String {
    let mut text = fields_header(f.axis);
    text.push('\n');
    for b in &f.bins {
        let stress = if f.stress {
            format!("{},{},{}", b.sxx, b.syy, b.sxy)
        } else {
            ",,".into()
        };
        let nematic = b.nematic.map_or(String::new(), |s| s.to_string());
        writeln!(
            text,
            "{},{},{},{},{},{stress},{nematic},{}",
            b.at, b.phi, b.vx, b.vy, b.temperature, b.frames
        )
        .expect("string");
    }
    text
}

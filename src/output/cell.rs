//! `cell.csv`: a periodic cell's state at each output frame (written by every run whose case has
//! a cell), and its reader.
//!
//! `step,t,lx,ly,offset,shift,sxx,sxy,syx,syy,stiffness_yy`:
//! - `lx,ly` the cell's size now (cm; `ly` follows an imposed pressure);
//! - `offset` the Lees–Edwards shift of the image above modulo `lx`, `shift` the total shift S
//!   (cm): a body's unwrapped position is `x + ix lx + iy S`, `y + iy ly` with its image counts
//!   `ix,iy` from `trajectory.csv`;
//! - `sxx,sxy,syx,syy` the cell's mean stress (dyn/cm², compression positive, kinetic part
//!   included: see `dynamics::cell`), `stiffness_yy` the contacts' affine stiffness against a
//!   vertical stretch (dyn/cm²); these five are empty in an `"x"` cell, whose walls carry part
//!   of the load (`analysis.csv` gives the packing's stress).

use super::run_data::ReadError;
use super::trace::{FrameFile, LineFile, WriteError};
use crate::dynamics::World;
use crate::dynamics::cell::Cell;
use crate::geometry::Vec2;
use crate::run::time::time_text;
use std::path::Path;

pub const CELL_HEADER: &str = "step,t,lx,ly,offset,shift,sxx,sxy,syx,syy,stiffness_yy";

/// The writer of `cell.csv`; as an observer of a run, at the trajectory's frames.
pub struct CellWriter {
    out: LineFile,
    last_step: Option<u64>,
    every: u64,
}

impl CellWriter {
    /// Creates `dir/cell.csv` with its header; as an observer it writes every `every` steps.
    pub fn create(dir: &Path, every: u64) -> Result<Self, WriteError> {
        let mut out = LineFile::create(&dir.join("cell.csv"))?;
        out.line(format_args!("{CELL_HEADER}"))?;
        out.flush()?;
        Ok(CellWriter {
            out,
            last_step: None,
            every: every.max(1),
        })
    }

    /// The row of the world's cell now, labelled `step` (once per label; nothing without a
    /// cell).
    pub fn write(&mut self, world: &World, step: u64) -> Result<(), WriteError> {
        let Some(c) = &world.cell else {
            return Ok(());
        };
        if self.last_step == Some(step) {
            return Ok(());
        }
        self.last_step = Some(step);
        let t = time_text(step, world.dt);
        if c.measures_stress() {
            let [sxx, sxy, syx, syy] = c.stress;
            self.out.line(format_args!(
                "{step},{t},{},{},{},{},{sxx},{sxy},{syx},{syy},{}",
                c.size.x, c.size.y, c.offset, c.shift, c.stiffness_yy
            ))
        } else {
            // An `"x"` cell measures no stress: empty fields.
            self.out.line(format_args!(
                "{step},{t},{},{},{},{},,,,,",
                c.size.x, c.size.y, c.offset, c.shift
            ))
        }
    }

    pub fn flush(&mut self) -> Result<(), WriteError> {
        self.out.flush()
    }
}

impl FrameFile for CellWriter {
    fn every(&self) -> u64 {
        self.every
    }

    fn write_frame(&mut self, world: &World, step: u64) -> Result<(), WriteError> {
        self.write(world, step)
    }

    fn flush_frames(&mut self) -> Result<(), WriteError> {
        self.flush()
    }
}

/// The cell of every row of `dir/cell.csv`, by step: the case's cell (its periodicity, shear
/// rate and pressure) with the row's size, shift and stress.
pub fn read_cells(dir: &Path, case_cell: &Cell) -> Result<Vec<(u64, Cell)>, ReadError> {
    // (The run files' reader: an empty field is NaN — an "x" cell's stress — and a last line
    // cut short is left out.)
    let (rows, _) = super::run_data::rows(&dir.join("cell.csv"), CELL_HEADER)?;
    Ok(rows
        .into_iter()
        .map(|v| {
            let mut c = *case_cell;
            c.size = Vec2::new(v[2], v[3]);
            c.offset = v[4];
            c.shift = v[5];
            c.stress = [v[6], v[7], v[8], v[9]];
            c.stiffness_yy = v[10];
            (v[0] as u64, c)
        })
        .collect())
}

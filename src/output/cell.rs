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
use super::trace::{FrameRows, LineFile, Written};
use crate::dynamics::World;
use crate::dynamics::cell::Cell;
use crate::geometry::Vec2;
use std::path::Path;

pub const CELL_HEADER: &str = "step,t,lx,ly,offset,shift,sxx,sxy,syx,syy,stiffness_yy";

/// The row of `cell.csv` ([`CELL_HEADER`]): the world's cell (nothing without a cell).
pub struct CellRow;

impl FrameRows for CellRow {
    const FILE: &str = "cell.csv";
    const HEADER: &str = CELL_HEADER;
    fn rows(&self, out: &mut LineFile, world: &World, step: u64, t: &str) -> Written {
        let Some(c) = &world.cell else {
            return Ok(());
        };
        if c.measures_stress() {
            let [sxx, sxy, syx, syy] = c.stress;
            out.line(format_args!(
                "{step},{t},{},{},{},{},{sxx},{sxy},{syx},{syy},{}",
                c.size.x, c.size.y, c.offset, c.shift, c.stiffness[1]
            ))
        } else {
            // An `"x"` cell measures no stress: empty fields.
            out.line(format_args!(
                "{step},{t},{},{},{},{},,,,,",
                c.size.x, c.size.y, c.offset, c.shift
            ))
        }
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
            c.stiffness[1] = v[10];
            (v[0] as u64, c)
        })
        .collect())
}

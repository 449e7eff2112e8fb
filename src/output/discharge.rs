//! `discharge.csv` and `inserted.csv`: the bodies the outflow regions removed and those the
//! insertion regions placed (see [`crate::dynamics::flow`]), one row each.
//! - `discharge.csv`, `step,t,body,mass`: the step after which it was removed, its time, the
//!   body's identity ([`crate::dynamics::Bodies::id`], the `body` of `trajectory.csv`) and its
//!   mass (g per cm of thickness). Written by every run whose case has an `outflow`.
//! - `inserted.csv`, `step,t,body,insert,r,aspect`: the step after which it was placed (the
//!   trajectory's frame at that step holds it), its time, its identity, its inserter (an index into the case's `insert`) and the
//!   equal-area radius and aspect ratio drawn for it — its shape is the inserter's `shape` of
//!   that radius and aspect ([`crate::dynamics::flow::InsertShape::make`]). Written by every run
//!   whose case has an `insert`.
//!
//! The rows are on disk at every output frame and at the end.

use super::trace::{LineFile, WriteError};
use crate::dynamics::World;
use crate::run::time::time_text;
use crate::run::{End, Observer, ObserverError, StepInfo};
use std::path::Path;

/// The header of `discharge.csv`.
pub const DISCHARGE_HEADER: &str = "step,t,body,mass";

/// The header of `inserted.csv`.
pub const INSERTED_HEADER: &str = "step,t,body,insert,r,aspect";

/// The writer of `discharge.csv` and `inserted.csv` (an observer): takes the world's logs of
/// removals and insertions after every step.
pub struct DischargeWriter {
    out: Option<LineFile>,
    inserted: Option<LineFile>,
    every: u64,
    /// The flow application whose rows were written last ([`crate::dynamics::Flow::applied_step`]).
    taken: Option<u64>,
}

impl DischargeWriter {
    /// Creates `dir/discharge.csv` when `outflow`, `dir/inserted.csv` when `insert`, with their
    /// headers; flushed every `every` steps.
    pub fn create(dir: &Path, every: u64, outflow: bool, insert: bool) -> Result<Self, WriteError> {
        let open = |on: bool, name: &str, header: &str| -> Result<Option<LineFile>, WriteError> {
            if !on {
                return Ok(None);
            }
            let mut f = LineFile::create(&dir.join(name))?;
            f.line(format_args!("{header}"))?;
            f.flush()?;
            Ok(Some(f))
        };
        Ok(DischargeWriter {
            out: open(outflow, "discharge.csv", DISCHARGE_HEADER)?,
            inserted: open(insert, "inserted.csv", INSERTED_HEADER)?,
            every: every.max(1),
            taken: None,
        })
    }

    /// Writes the rows of the flow's last application (once: a writer called again at the same
    /// application, at a run's end or a continued run's start, writes nothing).
    fn take(&mut self, world: &World) -> Result<(), WriteError> {
        let dt = world.dt;
        let Some(flow) = world.flow.as_ref() else {
            return Ok(());
        };
        if flow.applied_step.is_none() || self.taken == flow.applied_step {
            return Ok(());
        }
        self.taken = flow.applied_step;
        let (removed, placed) = (&flow.log, &flow.inserted_log);
        if let Some(out) = &mut self.out {
            for d in removed {
                out.line(format_args!(
                    "{},{},{},{}",
                    d.step,
                    time_text(d.step, dt),
                    d.id,
                    d.mass
                ))?;
            }
        }
        if let Some(out) = &mut self.inserted {
            for i in placed {
                out.line(format_args!(
                    "{},{},{},{},{},{}",
                    i.step,
                    time_text(i.step, dt),
                    i.id,
                    i.inserter,
                    i.r,
                    i.aspect
                ))?;
            }
        }
        Ok(())
    }

    fn flush(&mut self) -> Result<(), WriteError> {
        for f in [&mut self.out, &mut self.inserted].into_iter().flatten() {
            f.flush()?;
        }
        Ok(())
    }
}

impl Observer for DischargeWriter {
    fn start(&mut self, world: &World, _: &crate::run::Plan) -> Result<(), ObserverError> {
        self.take(world)?;
        Ok(self.flush()?)
    }

    fn after_step(&mut self, world: &World, info: &StepInfo) -> Result<(), ObserverError> {
        self.take(world)?;
        if info.step.is_multiple_of(self.every) {
            self.flush()?;
        }
        Ok(())
    }

    fn finish(&mut self, world: &World, _: &End) -> Result<(), ObserverError> {
        self.take(world)?;
        Ok(self.flush()?)
    }
}

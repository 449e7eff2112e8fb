//! `discharge.csv`: the bodies the outflow regions removed (see [`crate::dynamics::flow`]), one
//! row each, `step,t,body,mass`: the step after which it was removed, its time, the body's
//! identity ([`crate::dynamics::Bodies::id`], the `body` of `trajectory.csv`) and its mass
//! (g per cm of thickness). Written by every run whose case has an `outflow`; the rows are on
//! disk at every output frame and at the end.

use super::trace::{LineFile, WriteError};
use crate::dynamics::World;
use crate::run::time::time_text;
use crate::run::{End, Observer, ObserverError, StepInfo};
use std::path::Path;

/// The header of `discharge.csv`.
pub const DISCHARGE_HEADER: &str = "step,t,body,mass";

/// The writer of `discharge.csv` (an observer): takes the world's log of removals after every
/// step.
pub struct DischargeWriter {
    out: LineFile,
    every: u64,
}

impl DischargeWriter {
    /// Creates `dir/discharge.csv` with its header; flushed every `every` steps.
    pub fn create(dir: &Path, every: u64) -> Result<Self, WriteError> {
        let mut out = LineFile::create(&dir.join("discharge.csv"))?;
        out.line(format_args!("{DISCHARGE_HEADER}"))?;
        out.flush()?;
        Ok(DischargeWriter {
            out,
            every: every.max(1),
        })
    }

    fn take(&mut self, world: &mut World) -> Result<(), WriteError> {
        let dt = world.dt;
        if let Some(flow) = world.flow.as_mut() {
            for d in flow.take_log() {
                self.out.line(format_args!(
                    "{},{},{},{}",
                    d.step,
                    time_text(d.step, dt),
                    d.id,
                    d.mass
                ))?;
            }
        }
        Ok(())
    }
}

impl Observer for DischargeWriter {
    fn start(&mut self, world: &mut World, _: &crate::run::Plan) -> Result<(), ObserverError> {
        self.take(world)?;
        Ok(self.out.flush()?)
    }

    fn after_step(&mut self, world: &mut World, info: &StepInfo) -> Result<(), ObserverError> {
        self.take(world)?;
        if info.step.is_multiple_of(self.every) {
            self.out.flush()?;
        }
        Ok(())
    }

    fn finish(&mut self, world: &mut World, _: &End) -> Result<(), ObserverError> {
        self.take(world)?;
        Ok(self.out.flush()?)
    }
}

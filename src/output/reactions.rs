//! `reactions.csv`: every prescribed body's reaction at each output frame (written by every run
//! whose case has bodies with `"fixed": true` or `"prescribed": true`).
//!
//! `step,t,body,x,y,angle,fx,fy,moment,power`:
//! - `x,y,angle` where the body is (it moves at its prescribed velocity and spin);
//! - `fx,fy,moment` the **reaction**: the sum of the forces its contacts exert on it (dyn per cm
//!   of thickness) and their moment about its centroid, couples included (dyn·cm per cm): what
//!   the scene pushes it with. A prescribed body has no weight; whatever holds it to its motion
//!   supplies the opposite;
//! - `power` the rate at which it does work on the scene, `−(F·v + M ω)` (erg/s per cm: positive
//!   when it drives the bodies, as a paddle; zero for a fixed body). Its integral over the run is
//!   its share of `boundary_work` in the energy account (with the moving walls').
//!
//! The forces are those of the frame's step (the last force evaluation).

use super::trace::{FrameFile, LineFile, WriteError};
use crate::dynamics::World;
use crate::run::time::time_text;
use std::path::Path;

pub const REACTIONS_HEADER: &str = "step,t,body,x,y,angle,fx,fy,moment,power";

/// The writer of `reactions.csv`; as an observer of a run, at the trajectory's frames (the
/// first, every `every` steps, the last).
pub struct ReactionsWriter {
    out: LineFile,
    last_step: Option<u64>,
    every: u64,
}

impl ReactionsWriter {
    /// Creates `dir/reactions.csv` with its header; as an observer it writes every `every`
    /// steps.
    pub fn create(dir: &Path, every: u64) -> Result<Self, WriteError> {
        let mut out = LineFile::create(&dir.join("reactions.csv"))?;
        out.line(format_args!("{REACTIONS_HEADER}"))?;
        out.flush()?;
        Ok(ReactionsWriter {
            out,
            last_step: None,
            every: every.max(1),
        })
    }

    /// One row per prescribed body for the world's current state, labelled `step` (once per
    /// label).
    pub fn write(&mut self, world: &World, step: u64) -> Result<(), WriteError> {
        if self.last_step == Some(step) {
            return Ok(());
        }
        self.last_step = Some(step);
        let t = time_text(step, world.dt);
        let b = &world.bodies;
        for &k in &b.prescribed {
            let s = &b.state[k];
            // (+ 0: no `-0` from a weightless body's zero weight.)
            let (f, m) = (
                b.force[k] + crate::geometry::Vec2::zeros(),
                b.torque[k] + 0.0,
            );
            let power = -(f.dot(&s.vel) + m * s.omega) + 0.0; // (no `-0`)
            self.out.line(format_args!(
                "{step},{t},{},{},{},{},{},{},{},{}",
                b.id[k],
                s.pose.position.x,
                s.pose.position.y,
                s.pose.angle(),
                f.x,
                f.y,
                m,
                power
            ))?;
        }
        Ok(())
    }

    pub fn flush(&mut self) -> Result<(), WriteError> {
        self.out.flush()
    }
}

impl FrameFile for ReactionsWriter {
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

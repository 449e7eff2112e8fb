//! CSV traces of a run: the trajectory (every `output_every` steps and the last step) and the
//! per-step quiescence measures. Writers only read the world.

use crate::dynamics::World;
use crate::dynamics::step::StepReport;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// `trajectory.csv`: `step,t,body,x,y,angle,vx,vy,omega`, full round-trip precision.
pub struct TrajectoryWriter {
    out: BufWriter<File>,
    last_step: Option<u64>,
}

impl TrajectoryWriter {
    pub fn create(path: &Path) -> io::Result<Self> {
        let mut out = BufWriter::new(File::create(path)?);
        writeln!(out, "step,t,body,x,y,angle,vx,vy,omega")?;
        Ok(TrajectoryWriter {
            out,
            last_step: None,
        })
    }

    /// One row per body for the world's current state (once per step).
    pub fn write(&mut self, world: &World) -> io::Result<()> {
        if self.last_step == Some(world.step) {
            return Ok(());
        }
        self.last_step = Some(world.step);
        let b = &world.bodies;
        for k in 0..b.len() {
            let p = &b.state[k].pose;
            writeln!(
                self.out,
                "{},{},{},{},{},{},{},{},{}",
                world.step,
                world.time,
                k,
                p.position.x,
                p.position.y,
                p.angle(),
                b.state[k].vel.x,
                b.state[k].vel.y,
                b.state[k].omega
            )?;
        }
        Ok(())
    }

    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

/// `increments.csv`: `step,t,mean_dx,mean_dy,mean_dtheta,unbalanced_force_ratio,contacts` —
/// P's quiescence measure (mean over bodies of the displacement increments of one step).
pub struct IncrementsWriter {
    out: BufWriter<File>,
}

impl IncrementsWriter {
    pub fn create(path: &Path) -> io::Result<Self> {
        let mut out = BufWriter::new(File::create(path)?);
        writeln!(
            out,
            "step,t,mean_dx,mean_dy,mean_dtheta,unbalanced_force_ratio,contacts"
        )?;
        Ok(IncrementsWriter { out })
    }

    pub fn write(&mut self, world: &World, r: &StepReport) -> io::Result<()> {
        writeln!(
            self.out,
            "{},{},{:e},{:e},{:e},{:e},{}",
            world.step,
            world.time,
            r.increments[0],
            r.increments[1],
            r.increments[2],
            world.unbalanced_ratios().0,
            r.contacts
        )
    }

    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

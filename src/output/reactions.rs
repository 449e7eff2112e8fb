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

use super::trace::{FrameRows, LineFile, Written};
use crate::dynamics::World;

pub const REACTIONS_HEADER: &str = "step,t,body,x,y,angle,fx,fy,moment,power";

/// The rows of `reactions.csv`, one per prescribed body ([`REACTIONS_HEADER`]).
pub struct Reactions;

impl FrameRows for Reactions {
    const FILE: &str = "reactions.csv";
    const HEADER: &str = REACTIONS_HEADER;
    fn rows(&self, out: &mut LineFile, world: &World, step: u64, t: &str) -> Written {
        let b = &world.bodies;
        for &k in &b.prescribed {
            let s = &b.state[k];
            // (+ 0: no `-0` from a weightless body's zero weight.)
            let (f, m) = (
                b.force[k] + crate::geometry::Vec2::zeros(),
                b.torque[k] + 0.0,
            );
            let power = -(f.dot(&s.vel) + m * s.omega) + 0.0; // (no `-0`)
            out.line(format_args!(
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
}

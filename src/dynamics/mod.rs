//! Rigid-body dynamics: bodies, the world, the step function, the quiescence criterion and the
//! critical time step. Reads no files and writes none.

pub mod account;
pub mod body;
pub mod boundary;
pub mod broad_phase;
pub mod contacts;
pub mod kinematics;
pub mod partner;
pub mod step;
pub mod timestep;
pub mod watch;
pub mod world;

pub use body::{Bodies, BodyInit, BodyState};
pub use boundary::{Motion, Servo, Span, WallSpec};
pub use partner::{Partner, Sides};
pub use step::{Blowup, StepReport};
pub use world::World;

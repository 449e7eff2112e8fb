//! Rigid-body dynamics: bodies, boundaries (walls that may move), the world, the step function,
//! the kinematics of a contact, the quiescence criterion, the critical time step and analyses of
//! a state. Reads no files and writes none.

pub mod account;
pub mod analysis;
pub mod body;
pub mod boundary;
pub mod broad_phase;
pub mod cell;
pub mod contact_pass;
pub mod contacts;
pub mod kinematics;
pub mod members;
pub mod neighbour_list;
pub mod partner;
pub mod quiescence;
pub mod restart;
pub mod step;
pub mod timestep;
pub mod watch;
pub mod world;

pub use body::{Bodies, BodyInit, BodyState};
pub use boundary::{Boundary, Motion, Servo, Span};
pub use partner::{Partner, Sides};
pub use quiescence::Quiescence;
pub use restart::{RestartError, RestartState, RunProgress};
pub use step::{Blowup, StepReport};
pub use world::World;

//! Rigid-body dynamics: bodies, boundaries (walls that may move), the world, the step function,
//! the kinematics of a contact, the critical time step and analyses of a state. Reads no files
//! and writes none; what runs a world (stop conditions, the blow-up watch, observers) is
//! [`crate::run`].

pub mod account;
pub mod analysis;
pub mod body;
pub mod boundary;
pub mod broad_phase;
pub mod cell;
pub mod contact_pass;
pub mod contacts;
pub mod flow;
pub mod kinematics;
pub mod local_damping;
pub mod materials;
pub mod members;
pub mod minimise;
pub mod neighbour_list;
pub mod partner;
pub mod restart;
pub mod step;
pub mod timestep;
pub mod world;

pub use account::{Blowup, StageTimes, StepReport};
pub use body::{Bodies, BodyInit, BodyState};
pub use boundary::{Boundary, Motion, Servo, Span};
pub use flow::Flow;
pub use materials::{Materials, PairTable};
pub use partner::{Partner, Sides};
pub use restart::{RestartError, RestartState};
pub use world::{Scene, World};

//! The run driver: a [`Simulation`] steps a [`World`](crate::dynamics::World) until a stop
//! condition holds and feeds the run's observers after every step.
//!
//! # One step of a run, in order
//! 1. The world's step ([`crate::dynamics::World::step`]); a non-finite state found inside it
//!    ends the run with a [`BlowupReport`] (`within_step`: the state is where the step stopped).
//! 2. The counters of the run's progress ([`RunProgress`]: contacts per step, the first step
//!    with a contact).
//! 3. The blow-up watch ([`watch`]: energy created beyond what the run can supply, an overlap
//!    deeper than the bodies): a trigger ends the run with a [`BlowupReport`].
//! 4. The stop conditions, in order of precedence: P's quiescence criterion held for its
//!    window ([`Stop::AtRest`]), a stop flag such as a signal's ([`Stop::Interrupted`]), the
//!    caller's predicate ([`Stop::Asked`]), the run's last step or end time
//!    ([`Stop::Completed`] at the end of its duration, [`Stop::MaxSteps`] at the end of its
//!    step budget).
//! 5. The observers ([`Observer`], in the order added): the writers of the run's files are in
//!    [`crate::output`] (trajectory, increments, walls, analysis and contacts, VTK, progress
//!    lines, the saved state). They read the world (`&World`); the contacts' extras that some
//!    of them read are computed once before them, when any asks ([`Observer::reads_extras`]),
//!    as is the sample of the contact network's critical step
//!    ([`Simulation::sample_critical_dt`]).
//!
//! Before the first step the observers see the start ([`Observer::start`]: the first frame);
//! when the run ends, however it ends, their last word ([`Observer::finish`]: the last frame,
//! the saved state). A blow-up and an observer's failure are errors returned to the caller,
//! never panics; the world is left as it was found.
//!
//! The driver reads the world only through its step's report and its energies: a run through
//! it gives the same bits as the world stepped alone.

pub mod audit;
mod observer;
mod outcome;
mod progress;
pub mod quiescence;
mod simulation;
pub mod threads;
pub mod time;
pub mod watch;

pub use audit::{AuditFinding, EnergyAudit};
pub use observer::{End, Moment, Observer, ObserverError, Plan, StepInfo};
pub use outcome::{RunError, Stop};
pub use progress::RunProgress;
pub use quiescence::Quiescence;
pub use simulation::Simulation;
pub use watch::{BlowupReport, BlowupWatch};

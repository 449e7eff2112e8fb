//! What a [`super::Simulation`] tells the observers of a run: its plan at the start, each step
//! after it is taken, and how the run ended.

pub use super::outcome::ObserverError;
use super::outcome::{RunError, Stop};
use super::progress::RunProgress;
use crate::dynamics::{StepReport, World};

/// The steps a run is to take, as it starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plan {
    /// The world's step at the start (0, or a saved state's).
    pub first: u64,
    /// The last step, if the run has one (its duration or its step budget; it may stop
    /// sooner).
    pub last: Option<u64>,
}

/// One step taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepInfo {
    /// The world's step count after the step.
    pub step: u64,
    pub report: StepReport,
    /// The run's last step, if it has one ([`Plan::last`]).
    pub last: Option<u64>,
    /// The run stops after this step (a stop condition held, or a blow-up was found).
    pub stopping: bool,
    /// The blow-up watch found the state after this step unphysical: it is the run's last, and
    /// what is written of it is only for the report.
    pub blowup: bool,
    /// The run's progress after this step (what a state written now continues with).
    pub progress: RunProgress,
}

/// How the run ended, for the observers' last word.
#[derive(Debug)]
pub struct End<'e> {
    /// The step the world's state belongs to (a step that stopped part-way on a non-finite
    /// value: that step, although the world's step count is the one before).
    pub step: u64,
    /// The world's state is finite (not one a step stopped part-way on).
    pub finite: bool,
    /// How the run ended (after the observers before this one: a write that failed in their
    /// last word shows here).
    pub outcome: &'e Result<Stop, RunError>,
    /// The run's progress as it ended.
    pub progress: &'e RunProgress,
}

/// A moment at which the observers are called: what [`Observer::reads_extras`] is asked
/// about.
#[derive(Clone, Copy, Debug)]
pub enum Moment<'m> {
    Start(&'m Plan),
    Step(&'m StepInfo),
    Finish(&'m End<'m>),
}

impl Moment<'_> {
    /// Whether a writer of frames every `every` steps, whose last frame was labelled `last`,
    /// writes one now: at the start, after every `every`-th step (not after a blow-up), and at
    /// the end (a finite state, once per label).
    pub fn writes_frame(&self, every: u64, last: Option<u64>) -> bool {
        match self {
            Moment::Start(_) => true,
            Moment::Step(info) => !info.blowup && info.step.is_multiple_of(every),
            Moment::Finish(end) => end.finite && last != Some(end.step),
        }
    }
}

/// An observer of a run (the writers of a run's files are in [`crate::output`]). It reads the
/// world and never changes it: what an observer needs computed that the step does not keep —
/// the contacts' extras ([`World::refresh_contact_extras`]: each contact's depth, stiffness
/// and damping) — it asks for ([`Observer::reads_extras`]), and the driver computes it once,
/// before the observers, for all who asked.
pub trait Observer {
    /// Whether this observer reads the contacts' extras at `moment` (default: never).
    fn reads_extras(&self, moment: Moment) -> bool {
        let _ = moment;
        false
    }

    /// Before the first step (the world at its start: the first frame).
    fn start(&mut self, world: &World, plan: &Plan) -> Result<(), ObserverError> {
        let _ = (world, plan);
        Ok(())
    }

    /// After every step taken (not after a step that stopped part-way).
    fn after_step(&mut self, world: &World, info: &StepInfo) -> Result<(), ObserverError>;

    /// When the run has ended, however it ended (the last frame, flushing).
    fn finish(&mut self, world: &World, end: &End) -> Result<(), ObserverError> {
        let _ = (world, end);
        Ok(())
    }
}

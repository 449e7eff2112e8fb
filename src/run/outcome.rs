//! How a run ended: stopped ([`Stop`]) or failed ([`RunError`]).

use super::watch::BlowupReport;
use std::fmt;

/// An observer's failure (a write that failed, naming its file): it ends the run.
pub type ObserverError = Box<dyn std::error::Error + Send + Sync>;

/// Why a run stopped (a blow-up is a [`RunError`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// The run's last step was reached: the end of its duration.
    Completed,
    /// The step budget ended the run before its duration.
    MaxSteps,
    /// P's quiescence criterion held for its window; rest began at step `since`.
    AtRest { since: u64 },
    /// The stop flag was raised (the signal's number).
    Interrupted(i32),
    /// The caller's predicate asked for the stop.
    Asked,
}

/// What ended a run early.
#[derive(Debug)]
pub enum RunError {
    Blowup(BlowupReport),
    /// An observer failed (a write, naming its file).
    Observer(ObserverError),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Blowup(b) => b.fmt(f),
            RunError::Observer(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for RunError {}

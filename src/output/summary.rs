//! `summary.json`: what a run did, in one object. It is written (atomically: a temporary file
//! renamed over it) with status `running` before the first step and once more at the end.

use super::run_data::BodyState;
use crate::run::{RunError, Stop};
use serde::Serialize;
use std::io;
use std::path::Path;

/// How a run stands, or how it ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Started and not finished (a summary still saying this after the process is gone: the run
    /// was killed).
    Running,
    /// Ran the case's whole duration.
    Completed,
    /// Stopped at rest (the case's quiescence criterion).
    AtRest,
    /// Stopped by `--max-steps` before the duration ended.
    MaxSteps,
    /// Stopped by a blow-up (see `error`).
    Blowup,
    /// Stopped by SIGINT or SIGTERM after a whole step.
    Interrupted,
    /// Stopped because an output could not be written (see `error`).
    IoError,
    /// Stopped by its caller's condition (a run driven from the library, not `dem2d run`).
    Stopped,
}

impl Status {
    /// The name written in `summary.json`.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Running => "running",
            Status::Completed => "completed",
            Status::AtRest => "at_rest",
            Status::MaxSteps => "max_steps",
            Status::Blowup => "blowup",
            Status::Interrupted => "interrupted",
            Status::IoError => "io_error",
            Status::Stopped => "stopped",
        }
    }

    /// How a run through the driver ended.
    pub fn of(outcome: &Result<Stop, RunError>) -> Status {
        match outcome {
            Ok(Stop::Completed) => Status::Completed,
            Ok(Stop::AtRest { .. }) => Status::AtRest,
            Ok(Stop::MaxSteps) => Status::MaxSteps,
            Ok(Stop::Interrupted(_)) => Status::Interrupted,
            Ok(Stop::Asked) => Status::Stopped,
            Err(RunError::Blowup(_)) => Status::Blowup,
            Err(RunError::Observer(_)) => Status::IoError,
        }
    }
}

/// Energies per unit thickness.
#[derive(Clone, Debug, Serialize)]
pub struct EnergyReport {
    pub kinetic: f64,
    pub potential: f64,
    pub elastic: f64,
    pub dissipated: f64,
    /// Work done on the bodies by moving walls and prescribed bodies since the start of the run
    /// (zero when nothing is prescribed to move).
    pub walls_work: f64,
    /// kinetic + potential + elastic + dissipated at the start and at the end: the second is the
    /// first plus the walls' work, up to the integration's error.
    pub initial_total: f64,
    pub final_total: f64,
    /// `final_total − initial_total − walls_work`: energy the integration created (or lost),
    /// zero in exact arithmetic.
    pub unaccounted: f64,
}

/// Counts of contact-steps in the fallback geometries.
#[derive(Clone, Debug, Serialize)]
pub struct DeepCounts {
    pub deep: u64,
    pub contained: u64,
}

/// The whole summary.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub name: String,
    pub status: Status,
    pub steps: u64,
    pub time: f64,
    pub quiescent: bool,
    pub quiescent_step: Option<u64>,
    /// First step after which any contact existed (null if none ever did).
    pub first_contact_step: Option<u64>,
    #[serde(rename = "final")]
    pub final_state: Vec<BodyState>,
    pub max_depth_ratio: f64,
    pub deep_contacts: DeepCounts,
    pub energies: EnergyReport,
    /// Unbalanced-force and -moment ratios at the last step.
    pub unbalanced_force_ratio: f64,
    pub unbalanced_moment_ratio: f64,
    pub dt: f64,
    /// A-priori estimate from the stiffest contact the scene can have.
    pub dt_critical: f64,
    /// Smallest critical step over the contacts that actually occurred (null if none).
    pub dt_critical_observed: Option<f64>,
    pub warnings: Vec<String>,
    pub wall_seconds: f64,
    /// Bodies × steps / wall time of the step loop.
    pub particle_steps_per_second: f64,
    /// Mean number of contacts per step.
    pub contacts_per_step: f64,
    /// Why the run stopped early (a blow-up, a failed write, a signal), or null.
    pub error: Option<String>,
}

/// Writes `dir/summary.json` atomically: into `summary.json.tmp`, synced, then renamed over it,
/// so that a reader sees the old summary or the new one, never a torn one.
pub fn write_summary(dir: &Path, summary: &Summary) -> io::Result<()> {
    let mut text = serde_json::to_string_pretty(summary).map_err(io::Error::other)?;
    text.push('\n');
    super::write_atomically(dir, "summary.json", &text)
}

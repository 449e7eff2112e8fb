//! `summary.json`: what a run did, in one object.

use serde::Serialize;

/// Final state of one body.
#[derive(Clone, Debug, Serialize)]
pub struct FinalBody {
    pub x: f64,
    pub y: f64,
    pub angle: f64,
    pub vx: f64,
    pub vy: f64,
    pub omega: f64,
}

/// Energies per unit thickness.
#[derive(Clone, Debug, Serialize)]
pub struct EnergyReport {
    pub kinetic: f64,
    pub potential: f64,
    pub elastic: f64,
    pub dissipated: f64,
    /// kinetic + potential + elastic + dissipated at the start and at the end.
    pub initial_total: f64,
    pub final_total: f64,
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
    pub steps: u64,
    pub time: f64,
    pub quiescent: bool,
    pub quiescent_step: Option<u64>,
    /// First step after which any contact existed (null if none ever did).
    pub first_contact_step: Option<u64>,
    #[serde(rename = "final")]
    pub final_state: Vec<FinalBody>,
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
    /// Why the run stopped early (a blow-up), or null.
    pub error: Option<String>,
}

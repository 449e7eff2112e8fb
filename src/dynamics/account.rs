//! The running account of a run: its energies and its diagnostic counters (written by the step,
//! read by the watch and the outputs).

/// Energies of the system, per unit thickness.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// `Σ ½ m v² + ½ I ω²`.
    pub kinetic: f64,
    /// `Σ −m g·x` (zero at the origin).
    pub potential: f64,
    /// Energy stored in the contact springs now.
    pub elastic: f64,
    /// Energy taken out by dashpots and sliding so far (including springs' energy lost when a
    /// contact opens).
    pub dissipated: f64,
    /// Work done on the bodies by moving walls (see [`super::boundary`]) and by bodies whose
    /// motion is prescribed (see [`super::body::Bodies`]) so far.
    pub boundary_work: f64,
}

impl Energies {
    /// Kinetic + potential + elastic + dissipated: in exact arithmetic, its initial value plus
    /// the walls' work [`Energies::boundary_work`].
    pub fn total(&self) -> f64 {
        self.kinetic + self.potential + self.elastic + self.dissipated
    }
}

/// Counters a run reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Diagnostics {
    /// Largest `δ / (smaller inscribed radius of the pair)` seen.
    pub max_depth_ratio: f64,
    /// Contact-steps in the `deep` (four crossings) fallback.
    pub deep_contacts: u64,
    /// Contact-steps in the `contained` fallback.
    pub contained_contacts: u64,
    /// Smallest critical time step of the contact network sampled so far (∞ before any contact;
    /// see [`World::network_critical_dt`]).
    pub dt_critical_observed: f64,
}

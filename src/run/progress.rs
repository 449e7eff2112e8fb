//! What a run keeps beside its world ([`RunProgress`]): saved with the world's state
//! (`state.json` writes it beside the world's, `scene::state` reads it back), so that a continued
//! run stops, and reports, as the uninterrupted one would.

use super::watch::BlowupWatch;

/// The run's progress: the quiescence streak, the counters of the summary and the blow-up
/// watch's reference state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunProgress {
    /// `K + P + E_el + D` at t = 0 of the whole run.
    pub initial_total: f64,
    /// Consecutive steps the quiescence criterion has held.
    pub quiescence_streak: u64,
    pub first_contact_step: Option<u64>,
    /// Σ over steps of the number of contacts (for the mean per step).
    pub contact_sum: u64,
    /// The blow-up watch's reference state (from t = 0 of the whole run).
    pub watch: BlowupWatch,
}

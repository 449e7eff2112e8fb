//! What a law returns for one contact ([`ContactForce`]).

/// Force on j (components along n and t), the elastic energy stored in the contact and its
/// instantaneous stiffness and damping (for the time-step estimate).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactForce {
    /// Normal force on j along n, `≥ 0`.
    pub normal: f64,
    /// Tangential force on j along t.
    pub tangential: f64,
    /// Energy stored in the normal, shear and rolling springs.
    pub elastic_energy: f64,
    /// Normal stiffness `dF_n/dδ` and dashpot now.
    pub kn: f64,
    pub eta_n: f64,
    /// Shear stiffness and dashpot now (zero without friction).
    pub kt: f64,
    pub eta_t: f64,
    /// Rolling stiffness and dashpot now (EPSD; zero otherwise).
    pub kr: f64,
    pub cr: f64,
    /// The part of `normal` that is not the spring's: the dashpot's, or what the clamp
    /// `F_n ≥ 0` withholds. Its work, and the shear force's and the rolling couple's work less
    /// the change of their springs' energy, is what the contact dissipates.
    pub normal_non_elastic: f64,
    /// Energy now stored in the contact's history springs (shear and rolling: lost when the
    /// contact opens).
    pub history_energy: f64,
    /// Change of the history springs' energy over this step (including resets by the sliders).
    pub history_energy_change: f64,
    /// A couple on j (its opposite on i) — the area law's deep overlaps' and the rolling
    /// resistance — and its non-elastic part (see [`SpringOverlap::couple`]; the whole rolling
    /// couple).
    pub couple: f64,
    pub couple_non_elastic: f64,
}

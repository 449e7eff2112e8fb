//! What a law reads of one contact at one instant ([`Kinematics`]): its overlap (the depth, or
//! the area law's view, [`AreaKinematics`], with its [`EquivalentOverlap`]), the relative
//! velocity, the pair's effective mass and radius, and what the optional parts read.

use super::cohesion::CohesionKinematics;
use super::rolling::RollingKinematics;
use crate::geometry::overlap_area::DiskLens;

/// How an overlap area A maps to the overlap the spring acts on, `δ_eq(A)`, and its
/// compliance `dδ_eq/dA = 1/L_eq`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EquivalentOverlap {
    /// The overlap of two disks (the bodies' equal-area radii; ∞ for a wall) whose lens has area
    /// A, with the lens's chord.
    Lens(DiskLens),
    /// Two flat faces: `δ_eq = A/ℓ`, `L_eq = ℓ` (ℓ the pair's mean face length), so two faces
    /// of length ℓ pressed flat by δ feel exactly the spring on δ. A potential of A alone
    /// cannot stiffen a face against tilting while both its ends stay in contact (A does not
    /// change): that rocking is neutral within a band of ±2δ/ℓ.
    Flat(f64),
}

impl EquivalentOverlap {
    /// `(δ_eq, dδ_eq/dA)` for the overlap area `area`.
    #[inline]
    pub fn depth_for_area(&self, area: f64) -> (f64, f64) {
        match *self {
            EquivalentOverlap::Lens(lens) => lens.equivalent_depth(area),
            EquivalentOverlap::Flat(ell) => {
                let g = 1.0 / ell;
                (area * g, g)
            }
        }
    }
}

/// The area law's view of a contact (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaKinematics {
    /// Overlap area A.
    pub area: f64,
    /// `|∂A/∂x_j|`: the chord length L for two crossings.
    pub length: f64,
    /// `dA/dt` (`−L v_n` for two crossings).
    pub rate: f64,
    /// The gradient's couple (see `narrow_phase::OverlapArea`; zero for two crossings).
    pub couple: f64,
    /// How A maps to the overlap the spring acts on.
    pub equivalent: EquivalentOverlap,
}

/// What a law needs to know about one contact at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kinematics {
    /// Overlap δ along the normal (> 0 when penetrating): the spring acts on it.
    pub depth: f64,
    /// The overlap whose product with `depth` gives twice the spring's energy over `k_n`: equal
    /// to `depth` for a contact of smooth bodies; for a flat-on-flat contact (a Winkler
    /// foundation, energy `k′ A ȳ`) twice the overlap centroid's distance from the chord.
    pub energy_depth: f64,
    /// Normal relative velocity `(v_j − v_i)·n` at the contact point (negative: approaching).
    pub vn: f64,
    /// Tangential relative velocity `(v_j − v_i)·t` at the contact point.
    pub vt: f64,
    /// Effective mass `m* = (1/m_i + 1/m_j)⁻¹` (T13; a wall has infinite mass). Read only by a
    /// Hertz dashpot and a rolling part (the step leaves it NaN for a law with neither).
    pub m_eff: f64,
    /// Effective radius of curvature `R* = (1/R_i + 1/R_j)⁻¹` (T11; a wall has R = ∞).
    pub r_eff: f64,
    /// Time step (the shear displacement is integrated over it, T16).
    pub dt: f64,
    /// For the area law: the overlap area and its rate (None: the spring acts on `depth`).
    pub area: Option<AreaKinematics>,
    /// Relative spin `ω_j − ω_i` (a wall does not turn).
    pub spin: f64,
    /// Rolling radius and inertia (read only by a rolling part; NaN when none is needed).
    pub rolling: RollingKinematics,
    /// The overlap chord and area (read only by a cohesion part; `None` when none is needed).
    pub cohesion: Option<CohesionKinematics>,
}

/// The overlap a normal spring acts on, for one contact (see [`Kinematics::spring_overlap`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringOverlap {
    /// The overlap the spring acts on: δ, or the area law's δ_eq.
    pub depth: f64,
    /// Its rate of change (`−v_n` for the depth).
    pub rate: f64,
    /// The factor mapping the spring's force onto the contact normal (1 for the depth).
    pub rho: f64,
    /// The overlap whose product with `depth` gives twice the spring's energy over `k_n`.
    pub energy_depth: f64,
    /// The compliance `dδ_eq/dA = 1/L_eq` and the gradient's couple (area law; 1 and 0 for
    /// the depth).
    pub compliance: f64,
    pub couple: f64,
}

impl SpringOverlap {
    /// The couple that goes with the normal force of a deep overlap, and its non-elastic part
    /// (zero but for the area law's four-crossing overlaps): the normal force per unit
    /// `|∂A/∂x_j|`, `λ = (F_s + (η/ρ) δ̇_eq)/L_eq` (so that `F_n = λ L`), times the
    /// gradient's couple. `spring` is `F_s(δ_eq)` (before ρ), `eta` the dashpot. For an
    /// exactly symmetric crossing the gradient is a pure couple (L = 0, ρ = 0): ρ is then taken
    /// as 1e-3 in the dashpot's share.
    #[inline]
    pub fn couple(&self, spring: f64, eta: f64) -> (f64, f64) {
        if self.couple == 0.0 {
            return (0.0, 0.0);
        }
        let g = self.compliance;
        let lambda = ((spring + eta / self.rho.max(1e-3) * self.rate) * g).max(0.0);
        (lambda * self.couple, (lambda - spring * g) * self.couple)
    }
}

impl Kinematics {
    /// The overlap the normal spring acts on: the depth `(δ, −v_n, ρ = 1)`, or for the area law
    /// `(δ_eq, Ȧ/L_eq, ρ = L/L_eq)`.
    #[inline(always)]
    pub fn spring_overlap(&self) -> SpringOverlap {
        match &self.area {
            None => SpringOverlap {
                depth: self.depth,
                rate: -self.vn,
                rho: 1.0,
                energy_depth: self.energy_depth,
                compliance: 1.0,
                couple: 0.0,
            },
            Some(a) => {
                let (delta, compliance) = a.equivalent.depth_for_area(a.area);
                SpringOverlap {
                    depth: delta,
                    rate: a.rate * compliance,
                    rho: a.length * compliance,
                    energy_depth: delta,
                    compliance,
                    couple: a.couple,
                }
            }
        }
    }
}

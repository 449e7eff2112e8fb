//! The cohesion part of a contact law: a pull `c ℓ` along the contact normal while the bodies
//! overlap, with `c` the key `cohesion` (dyn/cm², an energy per unit overlap volume: per 1 cm
//! of thickness, erg per cm² of overlap area) and `ℓ` the overlap chord's length.
//!
//! # The potential
//! The part is the gradient of the potential `U_c = −c A`, A the overlap area. Moving j by `du`
//! changes A by `−ℓ n·du` for two crossings (`narrow_phase::OverlapArea`: ℓ = |∂A/∂x_j| is the
//! chord length, n the chord normal), so the force on j is `−∇U_c = c ∇A = −c ℓ n`: a pull of
//! `c ℓ` towards i at the chord midpoint, for every shape (the same chord the area law's spring
//! acts on, `F = W′(A) ℓ n`: with cohesion the potential is `W(A) − c A`). For four crossings
//! the gradient's couple comes with it (`−c × couple` on j). It is the 2D form of LIGGGHTS'
//! simplified JKR cohesion (`cohesion sjkr`: `F = k_c A_contact`, the contact's area times an
//! energy density; in 2D per unit thickness the contact "area" is the chord ℓ).
//!
//! For two disks, or a disk and a straight wall, `dA/dδ = ℓ` exactly (the lens's or the cap's
//! chord), so the pull on the depth `c ℓ(δ)` is the gradient of `−c A(δ)` under either normal
//! law: `ℓ = 2√(δ(2r − δ))` for a disk of radius r on a wall, and for two disks Heron's
//! `ℓ = 2·2√(s(s−r_i)(s−r_j)(s−d))/d` (`narrow_phase::circle_circle`).
//!
//! # What it does not touch
//! The spring and the dashpot keep their clamp (`max(0, ρF_s + η δ̇)`: the repulsive part never
//! pulls), and the Coulomb slider and the rolling cap read that repulsive part only: cohesion
//! adds no friction (LIGGGHTS' `sjkr` adds its force after the normal model too). The pull is
//! elastic (it is the potential's gradient): it counts in the stored energy as `−c A`, not in
//! the dissipation. It adds no mode to the critical step (its stiffness `−c dℓ/dδ` is negative:
//! it softens the contact).
//!
//! # Where the chord comes from
//! The contact pass asks the narrow phase for the overlap area and the chord of every pair whose
//! law has cohesion ([`CohesionKinematics::of`]): ℓ and A are the area record's (every kernel
//! of two bodies, and of a body and a half-plane wall, gives it for two crossings and for the
//! deep overlaps it computes the gradient of); a touching pair (δ below rounding) takes its
//! chord `2 × half_chord` and the parabolic segment's area `(2/3) ℓ δ`. Against a drum and a
//! segment wall only a disk (a clump's member among them) has it: the disk's part beyond the
//! drum's circle, `πr² − lens(r, R, d)` with `dA/dd = ℓ` the circles' common chord
//! (`narrow_phase::drum`); over a segment's face the half-plane's cap, at an end the cap at the
//! end's depth `r − |p − E|` (`narrow_phase::segment`: one C¹ potential over face and ends).
//! Cohesion between them and an ellipse or a polygon is refused by the case reader, naming the
//! field.

use super::force::ContactForce;
use super::keys::{Check, Given, Keys, ParamError};
use super::mixing::MixError;
use crate::geometry::Vec2;
use crate::narrow_phase::Contact;

/// Cohesion as a case gives it and as a law uses it (its parameter needs no pair data).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CohesionPart {
    /// The pull per unit chord length `c` (dyn/cm²), `> 0`.
    pub cohesion: f64,
}

/// What the cohesion part reads of a contact: the chord length ℓ (`|∂A/∂x_j|`), the overlap
/// area A, and the couple on j per unit pull `c` that goes with the pull applied along the
/// contact's normal at the contact's point (the area gradient's own couple, and the lever of
/// its point about the contact's point: zero for two crossings under the area law).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CohesionKinematics {
    pub length: f64,
    pub area: f64,
    pub couple: f64,
}

impl CohesionKinematics {
    /// The cohesion's view of the contact record `c` (asked with its area and chord) whose
    /// force the pass applies at `point` along `normal`. `U_c = −cA`: the pull `c ℓ` along −n
    /// at the area gradient's point, plus `−c × couple` (see `narrow_phase::OverlapArea`),
    /// re-expressed at `point`: the couple on j grows by `(p_A − point) × (−ℓ n)`.
    #[inline]
    pub fn of(c: &Contact, point: Vec2, normal: Vec2) -> Self {
        match c.area {
            Some(a) => {
                let r = a.point - point;
                CohesionKinematics {
                    length: a.length,
                    area: a.area,
                    // Couple on j per unit c: −(a.couple) − ℓ (r × n).
                    couple: a.couple + a.length * (r.x * normal.y - r.y * normal.x),
                }
            }
            None => {
                // Touching (δ at rounding), or an overlap without an area record: the chord
                // and the parabolic segment's area (2/3)ℓδ (exact to O(δ²/r) for a smooth
                // boundary).
                let length = 2.0 * c.half_chord;
                CohesionKinematics {
                    length,
                    area: 2.0 / 3.0 * length * c.depth.max(0.0),
                    couple: 0.0,
                }
            }
        }
    }
}

impl CohesionPart {
    /// The keys this part reads.
    pub const KEYS: &[&str] = &["cohesion"];

    /// Reads `cohesion` (≥ 0, and when not zero within a scale's accepted range; `None` when
    /// not given or zero: no part at all).
    pub fn parse(k: &impl Keys) -> Result<Option<Self>, ParamError> {
        match k.number("cohesion", Check::NonNegative)? {
            Some(c) if c > 0.0 => {
                let c = k.number("cohesion", Check::Scale)?.unwrap_or(c);
                Ok(Some(CohesionPart { cohesion: c }))
            }
            Some(_) | None => Ok(None),
        }
    }

    /// Its keys as a case file gives them (what [`CohesionPart::parse`] reads back).
    pub fn given(&self) -> Vec<(&'static str, Given)> {
        vec![("cohesion", Given::Number(self.cohesion))]
    }

    /// The cohesion of contacts between two materials ([`super::mixing`]): the geometric mean
    /// `√(c_a c_b)` (Berthelot's rule, as the Girifalco–Good/Fowkes combination of surface
    /// energies, `W_ab = 2√(γ_a γ_b)`); none if either material has none; a material with
    /// itself keeps its own value exactly.
    pub fn mix(a: Option<Self>, b: Option<Self>) -> Option<Self> {
        match (a, b) {
            (Some(a), Some(b)) if a == b => Some(a),
            (Some(a), Some(b)) => Some(CohesionPart {
                cohesion: (a.cohesion * b.cohesion).sqrt(),
            }),
            _ => None,
        }
    }

    /// A line for a case's description.
    pub fn describe(&self) -> String {
        format!("cohesion {} dyn/cm²", self.cohesion)
    }

    /// Adds the pull to `out` (whose repulsive normal force, shear force and rolling couple are
    /// set): `F_n −= c ℓ`, the couple `−c × couple`, the stored energy `−c A` (all elastic).
    #[inline]
    pub fn apply(&self, k: &CohesionKinematics, out: &mut ContactForce) {
        let c = self.cohesion;
        out.normal -= c * k.length;
        out.couple -= c * k.couple;
        out.elastic_energy -= c * k.area;
    }
}

/// The cohesion part as a case gives it: none (c = 0), or the part. It keeps no history and
/// replaces no other key.
impl super::part::Part for Option<CohesionPart> {
    const KEYS: &[&str] = CohesionPart::KEYS;

    fn given(&self) -> Vec<(&'static str, Given)> {
        self.map_or(vec![], |c| c.given())
    }

    fn mix(&self, other: &Self) -> Result<Self, MixError> {
        Ok(CohesionPart::mix(*self, *other))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact_law::{
        ContactSpec, History, Kinematics, LinearDamping, LinearDashpots, RollingKinematics, Scaled,
    };

    fn spec(c: Option<f64>) -> ContactSpec {
        ContactSpec::linear(
            Scaled::Absolute(100.0),
            Scaled::Absolute(100.0),
            LinearDamping::Dashpots {
                eta_n: Scaled::Absolute(2.0),
                eta_s: Scaled::Absolute(2.0),
            },
            0.5,
        )
        .with_cohesion(c.map(|cohesion| CohesionPart { cohesion }))
    }

    fn kinematics(depth: f64, cohesion: Option<CohesionKinematics>) -> Kinematics {
        let nan = f64::NAN;
        Kinematics {
            depth,
            energy_depth: depth,
            vn: -0.5,
            vt: 0.1,
            m_eff: nan,
            r_eff: nan,
            dt: 1e-3,
            area: None,
            spin: 0.0,
            rolling: RollingKinematics {
                radius: nan,
                inertia: nan,
                spin_inertia: nan,
            },
            cohesion,
        }
    }

    #[test]
    fn a_law_with_cohesion_is_not_of_the_linear_fast_paths_kind() {
        let law = spec(None).resolve(&spec(None), 1.0, 980.0);
        assert!(LinearDashpots::of(&law).is_some());
        let law = spec(Some(3.0)).resolve(&spec(Some(3.0)), 1.0, 980.0);
        assert!(LinearDashpots::of(&law).is_none());
        assert!(law.needs().cohesion);
    }

    #[test]
    fn the_pull_is_c_times_the_chord_after_the_clamped_spring_and_the_slider() {
        // k δ − η v_n = 100 × 0.01 + 2 × 0.5 = 2 (repulsive); the pull c ℓ = 3 × 0.4 = 1.2;
        // the slider's cap μ × 2 = 1 reads the repulsive part only.
        let ck = CohesionKinematics {
            length: 0.4,
            area: 0.1,
            couple: 0.25,
        };
        let law = spec(Some(3.0)).resolve(&spec(None), 1.0, 980.0);
        let plain = spec(None).resolve(&spec(None), 1.0, 980.0);
        let with = law.force(&kinematics(0.01, Some(ck)), &mut History::default());
        let without = plain.force(&kinematics(0.01, None), &mut History::default());
        assert_eq!(without.normal, 2.0);
        assert_eq!(with.normal, 2.0 - 3.0 * 0.4);
        assert_eq!(with.tangential, without.tangential);
        assert_eq!(with.normal_non_elastic, without.normal_non_elastic);
        assert_eq!(with.elastic_energy, without.elastic_energy - 3.0 * 0.1);
        assert_eq!(with.couple, without.couple - 3.0 * 0.25);
        // A separating contact whose dashpot cancels the spring still pulls: −c ℓ.
        let mut k = kinematics(0.01, Some(ck));
        k.vn = 10.0;
        assert_eq!(law.force(&k, &mut History::default()).normal, -(3.0 * 0.4));
    }

    #[test]
    fn materials_mix_by_the_geometric_mean_and_a_material_keeps_its_own() {
        let c = |v: f64| Some(CohesionPart { cohesion: v });
        assert_eq!(CohesionPart::mix(c(4.0), c(9.0)), c(6.0));
        assert_eq!(CohesionPart::mix(c(0.3), c(0.3)), c(0.3));
        assert_eq!(CohesionPart::mix(c(4.0), None), None);
        assert_eq!(
            spec(Some(4.0)).mix(&spec(Some(9.0))).unwrap().cohesion,
            c(6.0)
        );
        // Mixed keys and given keys carry it (a pair written back reads back the same).
        let (keys, errors) = spec(Some(4.0)).mixed_keys(&spec(Some(9.0)));
        assert!(errors.is_empty());
        assert!(keys.contains(&("cohesion", Given::Number(6.0))));
        assert!(
            spec(Some(4.0))
                .given()
                .contains(&("cohesion", Given::Number(4.0)))
        );
        assert!(!spec(None).given().iter().any(|(k, _)| *k == "cohesion"));
    }
}

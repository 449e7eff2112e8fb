//! What the normal spring of a contact acts on, chosen from the contact record the narrow phase
//! found and a few numbers about the pair ([`PairFacts`]) — never from the shapes themselves.
//!
//! - **The depth** δ at the chord midpoint (P's model; two disks, a disk and a wall under either
//!   law: a disk's area potential *is* the spring on its depth).
//! - **A Winkler foundation** between flat faces (a flat-sided body against a wall under either
//!   law, two flat-sided bodies under the depth law): the resultant `k′A` with `k′ = k_n/ℓ` at
//!   the overlap's centroid, energy `k′Aȳ` (Tillemans & Herrmann's area-based polygon contact;
//!   see `narrow_phase::FlatOverlap`). The spring then acts on `δ_s = A/ℓ` with the energy
//!   overlap `2ȳ`.
//! - **The area potential** `W(A)` (Feng, Han & Owen 2012) on the overlap area, mapped to an
//!   equivalent overlap ([`EquivalentOverlap`]): between two flat-sided bodies the flat
//!   equivalent `A/ℓ`, otherwise the lens of the pair's equal-area disks.

use super::kinematics::{AreaKinematics, EquivalentOverlap};
use crate::geometry::Vec2;
use crate::geometry::overlap_area::DiskLens;
use crate::narrow_phase::{Contact, ContactState, OverlapArea};

/// What the normal spring of one contact acts on, and where it acts.
#[derive(Clone, Copy, Debug)]
pub enum SpringOn {
    /// The depth, at the chord midpoint.
    Depth,
    /// A Winkler foundation: the spring's overlap `δ_s = A/ℓ`, the energy overlap `2ȳ` (twice
    /// the centroid's distance from the chord), and the overlap's centroid (where it acts).
    Winkler(f64, f64, Vec2),
    /// The area potential, at the area gradient's point and along its normal.
    Area(OverlapArea, EquivalentOverlap),
}

/// The numbers about a pair that decide what its spring acts on, asked only when needed.
pub trait PairFacts {
    /// The other side is a wall.
    fn against_wall(&self) -> bool;
    /// Both sides are flat-sided bodies.
    fn flat_pair(&self) -> bool;
    /// The pair's mean face length ℓ (a body against a wall: the body's).
    fn face_length(&self) -> f64;
    /// The lens of the pair's equal-area disks (a wall: a disk of infinite radius).
    fn lens(&self) -> DiskLens;
}

impl SpringOn {
    /// What the spring acts on for the contact `c` (its flat overlap and its area when the
    /// narrow phase gave them), under the area law or not.
    #[inline(always)]
    pub fn of(c: &Contact, area_law: bool, pair: &impl PairFacts) -> SpringOn {
        // Flat on flat against a wall: a Winkler foundation under either law (against a
        // straight line it is the gradient of its energy); between two bodies under the depth
        // law only.
        if let Some(f) = c.flat
            && c.state == ContactState::Overlap
            && (pair.against_wall() || !area_law)
        {
            // ȳ: the centroid's distance from the chord's line.
            let ybar = (f.centroid - c.point).dot(&c.normal).abs();
            return SpringOn::Winkler(f.area / pair.face_length(), 2.0 * ybar, f.centroid);
        }
        match c.area {
            Some(a) if area_law => SpringOn::Area(
                a,
                // Two flat-sided bodies' overlap in two crossings carries its flat overlap
                // (`Contact::flat`, asked for above only against a wall or under the depth
                // law): the pair's facts are asked only for the other states.
                if c.flat.is_some() || (c.state != ContactState::Overlap && pair.flat_pair()) {
                    EquivalentOverlap::Flat(pair.face_length())
                } else {
                    EquivalentOverlap::Lens(pair.lens())
                },
            ),
            Some(_) | None => SpringOn::Depth,
        }
    }

    /// The spring's overlap and energy overlap for the contact's depth `depth`.
    #[inline(always)]
    pub fn depths(&self, depth: f64) -> (f64, f64) {
        match *self {
            SpringOn::Winkler(ds, de, _) => (ds, de),
            SpringOn::Area(..) | SpringOn::Depth => (depth, depth),
        }
    }

    /// Where the force acts and along which normal, given the record's point and normal: the
    /// chord midpoint and normal (the area gradient's, which equal them for two crossings); for a
    /// Winkler foundation the overlap's centroid.
    #[inline(always)]
    pub fn point_normal(&self, point: Vec2, normal: Vec2) -> (Vec2, Vec2) {
        match *self {
            SpringOn::Winkler(_, _, centroid) => (centroid, normal),
            SpringOn::Area(a, _) => (a.point, a.normal),
            SpringOn::Depth => (point, normal),
        }
    }
}

impl SpringOn {
    /// The area law's view of the contact (`None` unless the spring acts on the area): the
    /// area, `|∂A/∂x_j|`, the rate `dA/dt = −L v_n + couple · spin` for the relative normal
    /// velocity `vn` and spin `spin`, the couple and the equivalent overlap.
    #[inline(always)]
    pub fn area_kinematics(&self, vn: f64, spin: f64) -> Option<AreaKinematics> {
        match *self {
            SpringOn::Area(a, equivalent) => Some(AreaKinematics {
                area: a.area,
                length: a.length,
                rate: -a.length * vn + a.couple * spin,
                couple: a.couple,
                equivalent,
            }),
            SpringOn::Winkler(..) | SpringOn::Depth => None,
        }
    }

    /// The lens the area potential takes, when it takes one (its R* is the area law's, so that
    /// the potential depends on A alone).
    #[inline(always)]
    pub fn lens(&self) -> Option<DiskLens> {
        match *self {
            SpringOn::Area(_, EquivalentOverlap::Lens(lens)) => Some(lens),
            SpringOn::Area(_, EquivalentOverlap::Flat(_))
            | SpringOn::Winkler(..)
            | SpringOn::Depth => None,
        }
    }
}

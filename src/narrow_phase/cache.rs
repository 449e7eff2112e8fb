//! The per-pair cache: what a pair keeps from one query to the next, opaque to the caller (as
//! parry keeps a contact workspace per pair).
//!
//! A caller that queries the same pair step after step (the dynamics, one cache per neighbour-list
//! slot) hands the same [`PairCache`] to every query of that pair and never looks inside; a
//! one-off query passes a fresh one ([`PairCache::EMPTY`]). What a pair kind keeps is its own
//! business:
//! - the conic pairs (circle–ellipse, ellipse–ellipse) keep a warm start ([`Warm`]): a lasting
//!   contact's two crossings, or a separated pair's separating axis (see
//!   [`super::ellipse_ellipse`]);
//! - every other pair kind keeps nothing (its cache stays empty).
//!
//! The content is always relative to the caller's i, whichever order the dispatcher computes the
//! pair in ([`super::contact_with`] re-expresses it), so a pair whose canonical order flips from
//! one step to the next keeps its warm start.
//!
//! Stored in single precision (a starting point needs no more; 16 bytes a slot), so a warm start
//! read back is the one stored rounded to `f32`: the dynamics' results depend on that rounding,
//! and the golden trajectories hold it fixed.

use super::ellipse_ellipse::Warm;
use crate::geometry::Shape;

/// What a pair keeps between queries (see the module documentation). Empty when the pair has
/// nothing to keep, or has never been queried.
#[derive(Clone, Copy, Debug)]
pub struct PairCache(
    /// A conic pair's [`Warm`]: crossings as `[x₁, y₁, x₂, y₂]`, a separating axis as
    /// `[cos, sin, NaN, NaN]`; all NaN when empty.
    [f32; 4],
);

impl PairCache {
    /// The empty cache: a new pair.
    pub const EMPTY: PairCache = PairCache([f32::NAN; 4]);

    /// Whether a pair with a body of this shape can keep anything (a pair keeps something only
    /// if one of its shapes answers true): a scene none of whose shapes does needs no caches.
    /// The conic pairs keep their warm start, and every conic pair that is not two circles has
    /// an ellipse.
    #[inline]
    pub fn kept_with(shape: &Shape) -> bool {
        match shape {
            Shape::Ellipse { .. } => true,
            // A clump's contacts are its member disks'.
            Shape::Circle { .. }
            | Shape::Rectangle { .. }
            | Shape::Polygon(_)
            | Shape::Clump(_) => false,
        }
    }

    /// True when the cache holds nothing.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.0[0].is_nan()
    }

    /// The warm start held (as the next query will read it, rounded to `f32`), if any. Callers
    /// need not read it: this is for the tests of the warm path.
    #[inline]
    pub fn warm(&self) -> Option<Warm> {
        let w = self.0.map(f64::from);
        match (w[0].is_nan(), w[2].is_nan()) {
            (true, _) => None,
            (false, true) => Some(Warm::Axis([w[0], w[1]])),
            (false, false) => Some(Warm::Crossings([[w[0], w[1]], [w[2], w[3]]])),
        }
    }

    /// A cache holding `warm` (relative to the caller's i): for the tests of the warm path,
    /// which start a query from a chosen warm start.
    #[inline]
    pub fn with_warm(warm: Option<Warm>) -> PairCache {
        let mut c = PairCache::EMPTY;
        c.set_warm(warm);
        c
    }

    /// The cache's content, for a restart file: four single-precision numbers (NaN where the
    /// cache holds nothing). [`PairCache::from_saved`] gives back the same cache, bit for bit
    /// for every number and NaN for NaN, so that a restarted run starts its conic pairs from the
    /// same warm starts (and gets the same results) as the run that saved them.
    #[inline]
    pub fn saved(&self) -> [f32; 4] {
        self.0
    }

    /// The cache [`PairCache::saved`] gave `saved` (any NaN is the cache's NaN).
    #[inline]
    pub fn from_saved(saved: [f32; 4]) -> PairCache {
        PairCache(saved.map(|v| if v.is_nan() { f32::NAN } else { v }))
    }

    /// Keeps `warm` (or nothing) for the next query.
    #[inline]
    pub(crate) fn set_warm(&mut self, warm: Option<Warm>) {
        self.0 = match warm {
            Some(Warm::Crossings([p, q])) => [p[0] as f32, p[1] as f32, q[0] as f32, q[1] as f32],
            Some(Warm::Axis(a)) => [a[0] as f32, a[1] as f32, f32::NAN, f32::NAN],
            None => [f32::NAN; 4],
        };
    }
}

impl PartialEq for PairCache {
    /// The same bits, every NaN equal to every other.
    fn eq(&self, other: &PairCache) -> bool {
        self.0
            .iter()
            .zip(&other.0)
            .all(|(a, b)| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()))
    }
}

impl Default for PairCache {
    fn default() -> Self {
        PairCache::EMPTY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_saved_cache_comes_back_bit_for_bit() {
        let caches = [
            PairCache::EMPTY,
            PairCache::with_warm(Some(Warm::Axis([0.6, -0.8]))),
            PairCache::with_warm(Some(Warm::Crossings([[1.0 / 3.0, -0.0], [1e-40, -3.4e38]]))),
        ];
        for c in caches {
            let back = PairCache::from_saved(c.saved());
            assert_eq!(back, c);
            for (a, b) in back.saved().iter().zip(c.saved()) {
                assert!(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()));
            }
            assert_eq!(back.is_empty(), c.is_empty());
        }
    }
}

//! A drum: a circular wall of centre `c` and radius `R` with the bodies inside it (a concave
//! boundary). Its free side is the disk `|x − c| < R`; a body touches it where the body's point
//! farthest from `c` reaches the circle.

use super::pose::Vec2;

/// A circle of centre `center` and radius `radius` (> 0), solid outside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drum {
    pub center: Vec2,
    pub radius: f64,
}

impl Drum {
    /// The drum of centre `center` and radius `radius` (finite, > 0), else `None`.
    pub fn new(center: Vec2, radius: f64) -> Option<Self> {
        (center.x.is_finite() && center.y.is_finite() && radius.is_finite() && radius > 0.0)
            .then_some(Drum { center, radius })
    }

    /// The distance of the point `x` from the drum's circle, positive inside (the free side):
    /// `R − |x − c|`.
    #[inline]
    pub fn signed_distance(&self, x: Vec2) -> f64 {
        self.radius - (x - self.center).norm()
    }
}

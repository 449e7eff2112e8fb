//! A wall: a fixed half-plane, its distances compensated for rounding.

use super::pose::Vec2;

/// A fixed half-plane. Its solid side is `{x : normal·(x − point) ≤ 0}`; `normal` is a unit
/// vector pointing into the free side.
///
/// The wall is exactly the line through `point` perpendicular to the normal *as given*: the
/// given vector is kept (scaled by a power of two, which is exact) for the distances, and
/// `normal` is its rounded unit vector (for directions). Normalising rounds the direction by
/// ~ε rad, which turns the line about `point` and would move it by ε × (distance along the
/// line) at a body far from `point` — 2e-10 of a body's size at 1e6 sizes away.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wall {
    /// A point on the wall's boundary line.
    pub point: Vec2,
    /// Unit normal pointing into the free side (rounded).
    pub normal: Vec2,
    /// The normal as given, scaled by a power of two to a largest component in [1, 2).
    dir: Vec2,
    /// `1 / |dir|`.
    inv_len: f64,
}

impl Wall {
    /// A wall through `point` with free side towards `normal` (of any non-zero length, however
    /// small or large). Returns `None` when `normal` is zero or not finite, or `point` not
    /// finite.
    pub fn new(point: Vec2, normal: Vec2) -> Option<Self> {
        if !(normal.x.is_finite()
            && normal.y.is_finite()
            && point.x.is_finite()
            && point.y.is_finite())
        {
            return None;
        }
        let mut dir = normal;
        let mut largest = dir.x.abs().max(dir.y.abs());
        if largest == 0.0 {
            return None;
        }
        if largest < f64::MIN_POSITIVE {
            // Subnormal components: an exact power-of-two scale first.
            let up = 2f64.powi(60);
            dir *= up;
            largest *= up;
        }
        // The largest component's power of two: dividing by it is exact.
        let p2 = f64::from_bits(largest.to_bits() & 0x7FF0_0000_0000_0000);
        dir /= p2;
        let len = dir.x.hypot(dir.y);
        Some(Wall {
            point,
            normal: dir / len,
            dir,
            inv_len: 1.0 / len,
        })
    }

    /// Signed distance of `x` from the wall line, positive on the free side:
    /// `u·(x − point) / |u|` with `u` the normal as given.
    ///
    /// Evaluated to within a few units of rounding of the *result*, however far `x` lies from
    /// `point` along the wall: the plain dot product rounds each term at the scale of
    /// `|x − point|` (1e6 along a floor from its point makes an error of ~1e-10 in a distance
    /// of order one), and so do the differences `x − point` themselves. Here the differences
    /// are split into their rounded values and exact errors (two-sum), the products into
    /// theirs (FMA), and the terms summed with the errors carried (Ogita, Rump & Oishi's
    /// `Dot2`); what remains is a rounding or two of the result plus ~ε² of the terms.
    #[inline]
    pub fn signed_distance(&self, x: Vec2) -> f64 {
        let (u, p) = (self.dir, self.point);
        let (dx, ex) = two_sum(x.x, -p.x);
        let (dy, ey) = two_sum(x.y, -p.y);
        let (px, qx) = two_prod(u.x, dx);
        let (py, qy) = two_prod(u.y, dy);
        let (s, e) = two_sum(px, py);
        (s + (e + qx + qy + (u.x * ex + u.y * ey))) * self.inv_len
    }
}

/// `a + b` as its rounded value and the exact rounding error (Knuth's two-sum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a · b` as its rounded value and the exact rounding error (by a fused multiply-add).
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

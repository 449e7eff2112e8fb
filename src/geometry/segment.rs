//! A segment wall: a finite line segment `a b`, a thin plate whose two sides are both solid to
//! the bodies (a body meets whichever side its centroid is on) and whose two ends are points.
//!
//! # Conventions
//! - `t = (b − a)/|b − a|` is the tangent and `n` its quarter turn counter-clockwise,
//!   `n = (−t_y, t_x)`: the **front** side is the one to the left going from a to b. Its line
//!   with normal `n` is [`Segment::front`], with `−n` [`Segment::back`] (both through `a`).
//! - `τ(x) = (x − a)·t` is a point's place along the segment: `0` at a, `L` at b.
//! - The reference point of a moving segment is `a`; it translates (it does not turn).

use super::pose::Vec2;
use super::wall::Wall;

/// A finite line segment (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// First end.
    pub a: Vec2,
    /// Second end.
    pub b: Vec2,
    /// `b − a` as first given (a moved segment's `b` is `a` plus it: no rounding accumulates).
    offset: Vec2,
    /// Unit tangent from a to b.
    pub tangent: Vec2,
    /// Length `|b − a|` (> 0).
    pub length: f64,
    /// The segment's line with the normal `n` (the front side free).
    pub front: Wall,
    /// The segment's line with the normal `−n` (the back side free).
    pub back: Wall,
}

/// Why a segment cannot be made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentError {
    /// A coordinate is NaN or infinite.
    NonFinite,
    /// The two ends coincide.
    ZeroLength,
}

impl Segment {
    /// The segment from `a` to `b`.
    pub fn new(a: Vec2, b: Vec2) -> Result<Self, SegmentError> {
        if ![a.x, a.y, b.x, b.y].iter().all(|v| v.is_finite()) {
            return Err(SegmentError::NonFinite);
        }
        let d = b - a;
        if !(d.x.is_finite() && d.y.is_finite()) {
            return Err(SegmentError::NonFinite);
        }
        if d.x == 0.0 && d.y == 0.0 {
            return Err(SegmentError::ZeroLength);
        }
        // The unit normal first (`(−Δy, Δx)/|Δ|`, rounded), then the line through `a` with it:
        // the segment's line is then, bit for bit, the half-plane wall given that point and
        // normal — `[0, 1]` for a horizontal segment (a normal of another length would give
        // the same line with other roundings of the distance).
        let len = d.x.hypot(d.y);
        let dir = Vec2::new(-d.y / len, d.x / len);
        let front = Wall::new(a, dir).ok_or(SegmentError::ZeroLength)?;
        let back = Wall::new(a, -dir).ok_or(SegmentError::ZeroLength)?;
        let tangent = Vec2::new(front.normal.y, -front.normal.x);
        Ok(Segment {
            a,
            b,
            offset: d,
            tangent,
            length: tangent.dot(&d),
            front,
            back,
        })
    }

    /// The unit normal of the front side.
    #[inline]
    pub fn normal(&self) -> Vec2 {
        self.front.normal
    }

    /// The segment translated so that its first end is at `p`.
    #[inline]
    pub fn move_to(&mut self, p: Vec2) {
        self.a = p;
        self.b = p + self.offset;
        self.front.point = p;
        self.back.point = p;
    }

    /// `τ(x) = (x − a)·t`, the place of `x`'s projection along the segment.
    #[inline]
    pub fn along(&self, x: Vec2) -> f64 {
        (x - self.a).dot(&self.tangent)
    }

    /// The segment's point closest to `x`.
    #[inline]
    pub fn closest(&self, x: Vec2) -> Vec2 {
        let tau = self.along(x);
        if tau <= 0.0 {
            self.a
        } else if tau >= self.length {
            self.b
        } else {
            self.a + self.tangent * tau
        }
    }

    /// The distance from `x` to the segment (≥ 0).
    #[inline]
    pub fn distance(&self, x: Vec2) -> f64 {
        let tau = self.along(x);
        if tau <= 0.0 {
            (x - self.a).norm()
        } else if tau >= self.length {
            (x - self.b).norm()
        } else {
            self.front.signed_distance(x).abs()
        }
    }

    /// The segment's bounding box `(lower left, upper right)`.
    #[inline]
    pub fn bounds(&self) -> (Vec2, Vec2) {
        (
            Vec2::new(self.a.x.min(self.b.x), self.a.y.min(self.b.y)),
            Vec2::new(self.a.x.max(self.b.x), self.a.y.max(self.b.y)),
        )
    }

    /// Whether `x` lies in the bounding box grown by `reach` on every side (a body of
    /// bounding radius r at x can touch the segment only if this holds for `reach = r`).
    #[inline]
    pub fn box_holds(&self, x: Vec2, reach: f64) -> bool {
        let (lo, hi) = self.bounds();
        x.x >= lo.x - reach && x.x <= hi.x + reach && x.y >= lo.y - reach && x.y <= hi.y + reach
    }

    /// The side a body whose centroid is at `c` meets: the front line when `c` lies on the
    /// front side or on the line, else the back line.
    #[inline]
    pub fn facing(&self, c: Vec2) -> &Wall {
        if self.front.signed_distance(c) >= 0.0 {
            &self.front
        } else {
            &self.back
        }
    }
}

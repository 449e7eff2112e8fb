//! What the kernels share: a frame centred on a body ([`LocalFrame`]), the overlap record in it
//! ([`LocalOverlap`]), the fallback geometry of deep overlaps, and small exact helpers.

use super::record::{Contact, ContactState, FlatOverlap, OverlapArea, Request};
use crate::geometry::{Pose, Vec2};

/// A frame centred on a body: `origin` in world coordinates, local x axis at `(cos, sin)`,
/// lengths divided by `scale` (an exact power of two, so rescaling adds no rounding).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LocalFrame {
    pub origin: Vec2,
    pub cos: f64,
    pub sin: f64,
    pub scale: f64,
}

impl LocalFrame {
    /// The frame of `pose` (its centroid and axes), lengths scaled by `scale`.
    #[inline]
    pub fn of(pose: &Pose, scale: f64) -> LocalFrame {
        let (cos, sin) = pose.cos_sin();
        LocalFrame {
            origin: pose.position,
            cos,
            sin,
            scale,
        }
    }

    #[inline]
    pub fn vector(&self, v: [f64; 2]) -> Vec2 {
        Vec2::new(
            self.cos * v[0] - self.sin * v[1],
            self.sin * v[0] + self.cos * v[1],
        )
    }

    #[inline]
    pub fn point(&self, p: [f64; 2]) -> Vec2 {
        self.origin + self.vector(p) * self.scale
    }

    /// A contact record in state `state` from local quantities (lengths in units of `scale`):
    /// the chord `p1 p2` (its half-length when `request` asks for the chord), the contact point
    /// `mid`, the unit normal `n` and the depth.
    #[allow(clippy::too_many_arguments)] // the record's local quantities and the request
    #[inline(always)]
    pub fn contact(
        &self,
        state: ContactState,
        p1: [f64; 2],
        p2: [f64; 2],
        mid: [f64; 2],
        n: [f64; 2],
        depth: f64,
        request: &Request,
    ) -> Contact {
        let half_chord = if request.chord {
            0.5 * (p2[0] - p1[0]).hypot(p2[1] - p1[1]) * self.scale
        } else {
            0.0
        };
        Contact {
            state,
            point: self.point(mid),
            normal: self.vector(n),
            depth: depth * self.scale,
            half_chord,
            area: None,
            flat: None,
        }
    }

    /// The record of a containment ([`ContactState::Contained`]): the chord collapsed onto the
    /// point `inner` (local), the unit normal `n` and the depth.
    #[inline]
    pub fn contained(
        &self,
        inner: [f64; 2],
        n: [f64; 2],
        depth: f64,
        request: &Request,
    ) -> Contact {
        self.contact(
            ContactState::Contained,
            inner,
            inner,
            inner,
            n,
            depth,
            request,
        )
    }

    /// An [`OverlapArea`] from local quantities (lengths in units of `scale`): `grad` is
    /// `∂A/∂x_j`, the others as in [`LocalOverlap`].
    #[inline(always)]
    pub fn overlap(&self, o: &LocalOverlap) -> OverlapArea {
        let s2 = self.scale * self.scale;
        let (length, normal) = match o.chord {
            // Two crossings: the chord's own length and normal, already at hand.
            Some((len, n)) => (len, self.vector(n)),
            None => {
                let len = (o.grad[0] * o.grad[0] + o.grad[1] * o.grad[1]).sqrt();
                let n = if len > 0.0 {
                    self.vector([-o.grad[0] / len, -o.grad[1] / len])
                } else {
                    self.vector([1.0, 0.0]) // a pure couple (only at an exactly symmetric crossing)
                };
                (len, n)
            }
        };
        OverlapArea {
            area: o.area * s2,
            length: length * self.scale,
            normal,
            point: self.point(o.point),
            couple: o.couple * s2,
        }
    }
}

/// An [`OverlapArea`] in a pair's local frame: the area, `∂A/∂x_j` (for two crossings
/// `−L n`), the point and the couple.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LocalOverlap {
    pub area: f64,
    pub grad: [f64; 2],
    pub point: [f64; 2],
    pub couple: f64,
    /// For two crossings, the chord's length and unit normal (so that they need not be
    /// recovered from `grad`).
    pub chord: Option<(f64, [f64; 2])>,
}

impl LocalOverlap {
    /// Two crossings: area `cap_i + cap_j`, gradient `−L n` at the chord midpoint.
    #[inline]
    pub fn chord(area: f64, p: [f64; 2], q: [f64; 2], n: [f64; 2]) -> Self {
        let len = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
        Self::chord_of_length(area, p, q, n, len)
    }

    /// [`LocalOverlap::chord`] for a caller that has the chord's length `len` (`|q − p|`).
    #[inline]
    pub fn chord_of_length(area: f64, p: [f64; 2], q: [f64; 2], n: [f64; 2], len: f64) -> Self {
        LocalOverlap {
            area,
            grad: [-len * n[0], -len * n[1]],
            point: midpoint(p, q),
            couple: 0.0,
            chord: Some((len, n)),
        }
    }
}

/// The overlap area and its gradient for four or more crossings (`points`, sorted
/// counter-clockwise about their mean, as [`deep_fallback`] leaves them). The overlap is the
/// convex polygon of the crossings plus, beyond each of its edges, the cap of whichever body's
/// boundary bounds the overlap there — the one that bulges less past the edge, since both
/// boundaries run between the same two crossings and the inner one lies inside the other body.
/// `height(k, u, m)` is `max over body k of u·(x − m)` (k = 0 for i, 1 for j; u unit) and
/// `cap(k, p, q, u)` the area of body k beyond the chord pq towards u. `c_j` is j's centroid.
pub(crate) fn deep_overlap(
    points: &[[f64; 2]],
    c_j: [f64; 2],
    height: impl Fn(usize, [f64; 2], [f64; 2]) -> f64,
    cap: impl Fn(usize, [f64; 2], [f64; 2], [f64; 2]) -> f64,
) -> LocalOverlap {
    let k = points.len();
    let n = k as f64;
    let centre = [
        points.iter().map(|p| p[0]).sum::<f64>() / n,
        points.iter().map(|p| p[1]).sum::<f64>() / n,
    ];
    let mut twice_polygon = 0.0;
    let mut area = 0.0;
    let mut grad = [0.0f64; 2];
    let mut turn = 0.0; // ∂A/∂θ_j about c_j
    for idx in 0..k {
        let (p, q) = (points[idx], points[(idx + 1) % k]);
        let (rp, rq) = (
            [p[0] - centre[0], p[1] - centre[1]],
            [q[0] - centre[0], q[1] - centre[1]],
        );
        twice_polygon += rp[0] * rq[1] - rp[1] * rq[0];
        let e = [q[0] - p[0], q[1] - p[1]];
        let len = (e[0] * e[0] + e[1] * e[1]).sqrt();
        if len == 0.0 {
            continue;
        }
        let u = [e[1] / len, -e[0] / len]; // outward normal of a counter-clockwise polygon
        let m = midpoint(p, q);
        let body = if height(1, u, m) < height(0, u, m) {
            1
        } else {
            0
        };
        area += cap(body, p, q, u);
        if body == 1 {
            // j's boundary: its outward normal integrates to L u over the arc.
            grad[0] += len * u[0];
            grad[1] += len * u[1];
            turn += len * ((m[0] - c_j[0]) * u[1] - (m[1] - c_j[1]) * u[0]);
        }
    }
    // ∂A/∂θ_j = (point − c_j) × grad + (the couple of the gradient, with the sign of dA).
    let lever = (centre[0] - c_j[0]) * grad[1] - (centre[1] - c_j[1]) * grad[0];
    LocalOverlap {
        area: area + 0.5 * twice_polygon.abs(),
        grad,
        point: centre,
        couple: -(turn - lever),
        chord: None,
    }
}

/// The largest power of two not above `x` (1 for zero, subnormal or non-finite `x`).
#[inline]
pub(crate) fn pow2_floor(x: f64) -> f64 {
    let p = f64::from_bits(x.to_bits() & 0x7FF0_0000_0000_0000);
    if p.is_normal() { p } else { 1.0 }
}

/// Orders up to eight points counter-clockwise about their mean (for the fallback chords).
pub(crate) fn sort_ccw(points: &mut [[f64; 2]]) {
    let n = points.len() as f64;
    let cx = points.iter().map(|p| p[0]).sum::<f64>() / n;
    let cy = points.iter().map(|p| p[1]).sum::<f64>() / n;
    points.sort_by(|p, q| {
        let ap = (p[1] - cy).atan2(p[0] - cx);
        let aq = (q[1] - cy).atan2(q[0] - cx);
        ap.total_cmp(&aq)
    });
}

/// Unit normal of the chord `p1 p2`, oriented so that `depth(n)` is the smaller of the two
/// orientations, with that depth. `depth(n)` must be the penetration along `n` (i → j).
#[inline]
pub(crate) fn chord_normal(
    p1: [f64; 2],
    p2: [f64; 2],
    depth: impl Fn([f64; 2]) -> f64,
) -> ([f64; 2], f64) {
    let (dx, dy) = (p2[0] - p1[0], p2[1] - p1[1]);
    let len = (dx * dx + dy * dy).sqrt();
    let n = [-dy / len, dx / len];
    orient(n, depth)
}

/// [`orient`] for two centrally symmetric shapes, whose supports add up to `supports` along
/// both `n` and `−n`: the depth is `supports ∓ n·d` with `n_dot_d = n·(c_j − c_i)`.
#[inline]
pub(crate) fn orient_symmetric(n: [f64; 2], supports: f64, n_dot_d: f64) -> ([f64; 2], f64) {
    if n_dot_d >= 0.0 {
        (n, supports - n_dot_d)
    } else {
        ([-n[0], -n[1]], supports + n_dot_d)
    }
}

/// Of `n` and `−n`, the orientation with the smaller penetration depth, and that depth.
#[inline]
pub(crate) fn orient(n: [f64; 2], depth: impl Fn([f64; 2]) -> f64) -> ([f64; 2], f64) {
    let dp = depth(n);
    let m = [-n[0], -n[1]];
    let dm = depth(m);
    if dm < dp { (m, dm) } else { (n, dp) }
}

/// The fallback for four or more crossings: of the chords joining consecutive crossings (taken
/// counter-clockwise), the one whose normal gives the least penetration, like the minimum
/// translation direction of a separating-axis test. Returns `(p1, p2, n, depth)`.
pub(crate) fn deep_fallback(
    points: &mut [[f64; 2]],
    depth: impl Fn([f64; 2]) -> f64,
) -> ([f64; 2], [f64; 2], [f64; 2], f64) {
    sort_ccw(points);
    let k = points.len();
    let mut best = (points[0], points[1 % k], [1.0, 0.0], f64::INFINITY);
    for idx in 0..k {
        let (p, q) = (points[idx], points[(idx + 1) % k]);
        if p == q {
            continue;
        }
        let (n, dpt) = chord_normal(p, q, &depth);
        if dpt < best.3 {
            best = (p, q, n, dpt);
        }
    }
    best
}

/// Area and centroid of a simple polygon (shoelace formulas); the mean of the vertices when
/// the area vanishes.
pub(crate) fn polygon_area_centroid(poly: &[[f64; 2]]) -> (f64, [f64; 2]) {
    let n = poly.len();
    let mean = || {
        let k = n.max(1) as f64;
        [
            poly.iter().map(|p| p[0]).sum::<f64>() / k,
            poly.iter().map(|p| p[1]).sum::<f64>() / k,
        ]
    };
    if n < 3 {
        return (0.0, mean());
    }
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let (p, q) = (poly[k], poly[(k + 1) % n]);
        let cr = p[0] * q[1] - q[0] * p[1];
        a += cr;
        cx += (p[0] + q[0]) * cr;
        cy += (p[1] + q[1]) * cr;
    }
    if a == 0.0 {
        return (0.0, mean());
    }
    (0.5 * a.abs(), [cx / (3.0 * a), cy / (3.0 * a)])
}

impl LocalFrame {
    /// The flat overlap of a local polygon.
    #[inline]
    pub fn flat(&self, poly: &[[f64; 2]]) -> FlatOverlap {
        let (area, c) = polygon_area_centroid(poly);
        FlatOverlap {
            area: area * self.scale * self.scale,
            centroid: self.point(c),
        }
    }
}

#[inline]
pub(crate) fn midpoint(p: [f64; 2], q: [f64; 2]) -> [f64; 2] {
    [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]
}

//! High-precision reference contact geometry for the `dem2d` test suite.
//!
//! Everything is computed in double-double ([`DD`], ~106 bits) from the exact
//! `f64` inputs and only rounded to `f64` at the very end. The methods are
//! deliberately *different* from the crate's (no pencil of conics, no
//! `det(M_i + λ M_j)` cubic), so the two can be compared.
//!
//! # Conventions
//!
//! * Shapes: `Circle { r }`, `Ellipse { a, b }` (semi-axes, `a` along the body's
//!   own x axis), `Rectangle { w, h }` (full width and height, `w` along the body's
//!   x axis). A body is a shape, a position and an angle θ (radians, CCW). The
//!   rotation enters only through `(c, s) = (θ.cos(), θ.sin())` evaluated in `f64`
//!   by std; those two values are taken as exact and renormalised in DD so that
//!   `c² + s² = 1`. The body axes are `e1 = (c, s)`, `e2 = (−s, c)`.
//! * A wall is the half-plane `{x : normal·(x − point) ≤ 0}` (its solid side);
//!   `normal` points into the free side and is normalised in DD.
//! * For a pair `(i, j)` the unit normal `n` points from `i` towards `j`.
//! * All geometry is expressed relative to the *origin* of the pair: the position
//!   of the first body (`i` if it is a body, else `j`). Differences of `f64`
//!   positions are exact in DD, so bodies far from the world origin lose nothing.
//! * **Crossings** are the points where the two boundaries cross (for a wall: where
//!   its line crosses the body's boundary). For rectangles, a maximal boundary
//!   segment shared by both objects (collinear overlapping edges) counts as ONE
//!   crossing at the segment's midpoint if the boundary passes from inside to
//!   outside of the other object across it, and as a touching point otherwise;
//!   a corner lying exactly on the other boundary is treated the same way (a
//!   zero-length shared segment).
//! * **Chord definition** (exactly two crossings `p1`, `p2`): `normal` ⟂ `p2 − p1`,
//!   oriented `i → j`: for two bodies `n·(c_j − c_i) > 0` (*decision*: if that dot
//!   product is exactly 0 in DD, the orientation with the smaller depth is taken);
//!   wall as `i`: `n` = wall normal; wall as `j`: `n` = −wall normal. `point` =
//!   `(p1 + p2)/2`; `depth` δ = `h_i(n) + h_j(−n)` with the support function
//!   `h_X(u) = max_{x∈X} u·x` (circle `c·u + r`; ellipse
//!   `c·u + sqrt(a²(u·e1)² + b²(u·e2)²)`; rectangle `c·u + (w/2)|u·e1| + (h/2)|u·e2|`,
//!   which is the maximum over its corners; wall, at its own normal, `point·normal`).
//!   δ > 0 means overlap.
//! * **States**: [`RState::Separated`] (no crossings, neither contains the other),
//!   [`RState::Overlap`] (2 crossings), [`RState::Deep`]`(n)` (`n ≥ 4` crossings),
//!   [`RState::Contained`] (no crossings, one solid inside the other; for a wall:
//!   the body lies in the wall's solid side; *decision*: also returned for two
//!   coincident boundaries), [`RState::Touching`] (no crossings but a tangency to
//!   within the DD tolerance, relative ~1e-28).
//!
//! # Methods
//!
//! * Conic–conic (circle/ellipse pairs): `j`'s boundary is parametrised as
//!   `c_j + a_j cos t e1_j + b_j sin t e2_j`, with `t = t0 + τ` and
//!   `z = tan(τ/2)`, and substituted into `i`'s scaled implicit function
//!   `b_i²((x−c_i)·e1_i)² + a_i²((x−c_i)·e2_i)² − a_i²b_i²`; this gives a quartic
//!   in `z`. `t0` is chosen so that `τ = π` (z = ∞) is the sample (of 16) of `j`'s
//!   boundary with the largest |implicit value of i|, i.e. far from any crossing.
//!   All real roots are found by [`poly_real_roots`] (critical-point bracketing in
//!   DD). Odd-multiplicity roots are crossings, even ones tangencies.
//! * Wall–conic: a quadratic along the wall's line.
//! * Rectangles: the rectangle's boundary (4 segments between its DD corners) is
//!   walked and classified in/on/out of the other object, with breakpoints at the
//!   segment–line / segment–conic (quadratic) intersections.
//! * Containment (no crossings): one boundary point of each object is tested
//!   against the other's inside test.

use super::dd::DD;
use std::cmp::Ordering;
use std::f64::consts::PI;
use std::ops::{Add, Mul, Neg, Sub};

/// Relative tolerance for "zero" (tangency / on-boundary decisions).
const TOL_REL: f64 = 1e-28;
/// Relative error assumed for the coefficients of the conic–conic quartic.
const COEF_ERR_REL: f64 = 1e-30;
/// Safety factor on evaluation error bounds in the root finder.
const ROOT_SAFETY: f64 = 64.0;
/// Segment parameters closer than this to 0/1 (or to each other) are merged.
const S_MIN: f64 = 1e-30;
/// Number of boundary samples used to choose the quartic's offset and to test containment.
const N_SAMPLES: usize = 16;

// ---------------------------------------------------------------------------
// Public API
// ---------------------------------------------------------------------------

/// A body shape (sizes are exact `f64`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RShape {
    /// Circle of radius `r`.
    Circle { r: f64 },
    /// Ellipse with semi-axes `a` (along the body's x axis) and `b`.
    Ellipse { a: f64, b: f64 },
    /// Rectangle of full width `w` (along the body's x axis) and full height `h`.
    Rectangle { w: f64, h: f64 },
}

/// One object of a pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RObj {
    /// A body at `pos`, rotated by `angle` (radians, CCW).
    Body {
        shape: RShape,
        pos: [f64; 2],
        angle: f64,
    },
    /// The half-plane `{x : normal·(x − point) ≤ 0}`; `normal` points into the free side.
    Wall { point: [f64; 2], normal: [f64; 2] },
}

/// Topological state of a pair (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RState {
    /// No crossings and neither contains the other.
    Separated,
    /// Tangent to within the DD tolerance (no crossings).
    Touching,
    /// Exactly two crossings.
    Overlap,
    /// `n ≥ 4` crossings.
    Deep(usize),
    /// No crossings, one solid inside the other (or the body inside the wall's solid).
    Contained,
}

/// Reference contact of a pair.
#[derive(Clone, Debug, PartialEq)]
pub struct RContact {
    /// Topological state.
    pub state: RState,
    /// Crossing points relative to `origin`, computed in DD then rounded, sorted
    /// by angle (atan2, ascending in (−π, π]) about their mean. For `Touching`
    /// this holds the tangency point(s) instead.
    pub crossings: Vec<[f64; 2]>,
    /// Only for `Overlap`/`Touching`: the unit normal, pointing from `i` to `j`.
    /// For `Touching` it is the boundary normal at the tangency point (None if
    /// both boundaries have a corner there).
    pub normal: Option<[f64; 2]>,
    /// Only for `Overlap`/`Touching`: chord midpoint (or tangency point), relative to `origin`.
    pub point_rel: Option<[f64; 2]>,
    /// Only for `Overlap`/`Touching`: `h_i(n) + h_j(−n)`.
    pub depth: Option<f64>,
    /// Position of the first body of the pair (`i` if it is a body, else `j`).
    pub origin: [f64; 2],
}

/// Reference contact geometry of the pair `(i, j)`; see the module documentation.
///
/// Panics if both objects are walls, or if an odd number of crossings is found
/// (only possible for degenerate, non-generic input).
pub fn reference_contact(i: &RObj, j: &RObj) -> RContact {
    let origin = origin_of(i, j);
    let gi = Geo::new(i, origin);
    let gj = Geo::new(j, origin);
    let found = find(&gi, &gj);
    let mut out = RContact {
        state: RState::Separated,
        crossings: Vec::new(),
        normal: None,
        point_rel: None,
        depth: None,
        origin,
    };
    if found.coincident {
        out.state = RState::Contained;
        return out;
    }
    let mut crossings = found.crossings;
    sort_about_mean(&mut crossings);
    out.crossings = crossings.iter().map(|p| p.to_f64()).collect();
    match crossings.len() {
        0 => {
            let mut touches = found.touches;
            if touches.is_empty() {
                out.state = if found.contained {
                    RState::Contained
                } else {
                    RState::Separated
                };
                return out;
            }
            sort_about_mean(&mut touches);
            let pt = touches[0];
            out.state = RState::Touching;
            out.crossings = touches.iter().map(|p| p.to_f64()).collect();
            out.point_rel = Some(pt.to_f64());
            let n = gi.normal_at(pt).or_else(|| gj.normal_at(pt).map(|m| -m));
            if let Some(n) = n {
                let n = orient(&gi, &gj, n);
                out.normal = Some(n.to_f64());
                out.depth = Some(depth_dd(&gi, &gj, n).to_f64());
            }
        }
        2 => {
            let (p1, p2) = (crossings[0], crossings[1]);
            let n = orient(&gi, &gj, (p2 - p1).perp().unit());
            out.state = RState::Overlap;
            out.normal = Some(n.to_f64());
            out.point_rel = Some(p1.mid(p2).to_f64());
            out.depth = Some(depth_dd(&gi, &gj, n).to_f64());
        }
        n if n % 2 == 0 => out.state = RState::Deep(n),
        n => panic!(
            "reference_contact: odd number of crossings ({n}) for {i:?} / {j:?}: degenerate input"
        ),
    }
    out
}

/// Penetration depth along the unit direction `u` (pointing `i → j`, renormalised
/// in DD): `h_i(u) + h_j(−u)`, computed in DD.
///
/// A half-plane's support function is finite only along its own normal, so with a
/// wall this returns the *translation of the body along `u`* that brings it onto
/// the wall's line, `δ_n / (u·n)`, where `δ_n` is the depth along the oriented wall
/// normal `n` (wall normal if the wall is `i`, its negative if it is `j`). This
/// equals `h_i(n) + h_j(−n)` when `u = n`. Panics if `u·n ≤ 0` for a wall.
pub fn depth_along(i: &RObj, j: &RObj, u: [f64; 2]) -> f64 {
    let origin = origin_of(i, j);
    let gi = Geo::new(i, origin);
    let gj = Geo::new(j, origin);
    let u = V::from_f64(u).unit();
    let wall_normal = match (&gi, &gj) {
        (Geo::Wall(w), _) => Some(w.n),
        (_, Geo::Wall(w)) => Some(-w.n),
        _ => None,
    };
    match wall_normal {
        Some(n) => {
            let un = u.dot(n);
            assert!(
                un > 0.0,
                "depth_along: direction {u:?} does not point from i to j across the wall"
            );
            (depth_dd(&gi, &gj, n) / un).to_f64()
        }
        None => depth_dd(&gi, &gj, u).to_f64(),
    }
}

/// All real roots of `t1 λ³ + t2 λ² + t3 λ + t4` (exact `f64` coefficients; leading
/// ones may be 0), ascending, each with its multiplicity; computed in DD by
/// [`poly_real_roots`]. An identically zero polynomial gives no roots.
pub fn cubic_real_roots(t: [f64; 4]) -> Vec<(f64, usize)> {
    let coeffs: Vec<DD> = t.iter().rev().map(|&c| DD::from(c)).collect();
    poly_real_roots(&coeffs)
        .into_iter()
        .map(|(r, m)| (r.to_f64(), m))
        .collect()
}

/// All real roots of the polynomial `Σ p[k] z^k` with exact DD coefficients
/// (ascending order), ascending, with multiplicities.
pub fn poly_real_roots(p: &[DD]) -> Vec<(DD, usize)> {
    poly_real_roots_err(p, &vec![0.0; p.len()])
}

/// As [`poly_real_roots`], with an absolute error bound `err[k]` on each coefficient.
///
/// Recursive critical-point bracketing: the real roots of `p'` split the line
/// (bounded by the Cauchy bound) into monotone pieces; a critical point where
/// `|p|` is below the evaluation error bound `64·Σ (err_k + EPS·|p_k|)|z|^k` is a
/// root of multiplicity (its multiplicity in `p'`) + 1; every other sign change
/// between consecutive nodes is a simple root, refined by safeguarded Newton /
/// bisection to full DD precision. Exactly-zero leading coefficients are dropped.
pub fn poly_real_roots_err(p: &[DD], err: &[f64]) -> Vec<(DD, usize)> {
    let n = p.iter().rposition(|c| !c.is_zero()).map_or(0, |k| k + 1);
    let (p, err) = (&p[..n], &err[..n]);
    match n {
        0 | 1 => return Vec::new(),
        2 => return vec![(-p[0] / p[1], 1)],
        _ => {}
    }
    let dp: Vec<DD> = p
        .iter()
        .enumerate()
        .skip(1)
        .map(|(k, c)| *c * k as f64)
        .collect();
    let derr: Vec<f64> = err
        .iter()
        .enumerate()
        .skip(1)
        .map(|(k, e)| e * k as f64)
        .collect();
    let crit = poly_real_roots_err(&dp, &derr);
    let lead = p[n - 1];
    let cauchy = p[..n - 1]
        .iter()
        .map(|c| (*c / lead).abs())
        .fold(DD::ZERO, DD::max)
        + 1.0;
    let bound = crit
        .iter()
        .map(|(r, _)| r.abs() * 2.0 + 1.0)
        .fold(cauchy, DD::max);

    let mut roots = Vec::new();
    // Nodes (z, p(z)) with p(z) replaced by 0 at critical points that are roots.
    let mut nodes = vec![(-bound, poly_eval(p, -bound))];
    for &(r, m) in &crit {
        let v = poly_eval(p, r);
        if v.abs() <= eval_tolerance(p, err, r) {
            roots.push((r, m + 1));
            nodes.push((r, DD::ZERO));
        } else {
            nodes.push((r, v));
        }
    }
    nodes.push((bound, poly_eval(p, bound)));
    for w in nodes.windows(2) {
        let ((a, fa), (b, fb)) = (w[0], w[1]);
        if fa.signum() * fb.signum() < 0.0 {
            roots.push((solve_bracket(p, &dp, a, b, fa), 1));
        }
    }
    roots.sort_by(|x, y| x.0.cmp_total(&y.0));
    roots
}

// ---------------------------------------------------------------------------
// Polynomial helpers
// ---------------------------------------------------------------------------

/// Horner evaluation of `Σ p[k] z^k` in DD.
fn poly_eval(p: &[DD], z: DD) -> DD {
    p.iter().rev().fold(DD::ZERO, |acc, c| acc * z + *c)
}

/// Bound on the error of `poly_eval(p, z)` (coefficient errors + DD rounding), times a safety factor.
fn eval_tolerance(p: &[DD], err: &[f64], z: DD) -> f64 {
    let az = z.abs().to_f64();
    let s: f64 = p
        .iter()
        .zip(err)
        .rev()
        .fold(0.0, |acc, (c, e)| acc * az + e + DD::EPS * c.abs().to_f64());
    ROOT_SAFETY * s
}

/// The root of `p` in `[a, b]`, where `p` is monotone and `p(a)` (= `fa`), `p(b)`
/// have strictly opposite signs. Safeguarded Newton (every 8th step a bisection),
/// until the step or the bracket is at DD resolution.
fn solve_bracket(p: &[DD], dp: &[DD], a: DD, b: DD, fa: DD) -> DD {
    let neg_at_lo = fa.is_negative();
    let (mut lo, mut hi) = (a, b);
    let mut x = lo + (hi - lo).mul_pow2(0.5);
    for it in 0..4000 {
        let fx = poly_eval(p, x);
        if fx.is_zero() {
            return x;
        }
        if fx.is_negative() == neg_at_lo {
            lo = x;
        } else {
            hi = x;
        }
        let scale = lo.abs().max(hi.abs()).to_f64();
        if (hi - lo).to_f64() <= 2.0 * DD::EPS * scale {
            return x;
        }
        let d = poly_eval(dp, x);
        let newton = x - fx / d;
        let next = if it % 8 != 7 && !d.is_zero() && newton > lo && newton < hi {
            newton
        } else {
            lo + (hi - lo).mul_pow2(0.5)
        };
        let step = (next - x).abs().to_f64();
        if step <= 0.5 * DD::EPS * x.abs().to_f64() || step < 1e-300 {
            return next;
        }
        x = next;
    }
    x
}

// ---------------------------------------------------------------------------
// DD vectors
// ---------------------------------------------------------------------------

/// A 2-vector of DD numbers.
#[derive(Clone, Copy, Debug)]
pub(super) struct V {
    pub(super) x: DD,
    pub(super) y: DD,
}

impl V {
    pub(super) fn new(x: DD, y: DD) -> V {
        V { x, y }
    }

    fn from_f64(p: [f64; 2]) -> V {
        V::new(DD::from(p[0]), DD::from(p[1]))
    }

    /// `p − origin`, exact.
    fn rel(p: [f64; 2], origin: [f64; 2]) -> V {
        V::new(DD::from(p[0]) - origin[0], DD::from(p[1]) - origin[1])
    }

    pub(super) fn dot(self, o: V) -> DD {
        self.x * o.x + self.y * o.y
    }

    /// Rotation by +90°.
    pub(super) fn perp(self) -> V {
        V::new(-self.y, self.x)
    }

    fn norm(self) -> DD {
        self.dot(self).sqrt()
    }

    /// `|x| + |y|` (for tolerance scales).
    pub(super) fn norm1(self) -> f64 {
        self.x.abs().to_f64() + self.y.abs().to_f64()
    }

    fn unit(self) -> V {
        let k = self.norm();
        V::new(self.x / k, self.y / k)
    }

    pub(super) fn mid(self, o: V) -> V {
        (self + o) * 0.5
    }

    pub(super) fn to_f64(self) -> [f64; 2] {
        [self.x.to_f64(), self.y.to_f64()]
    }
}

impl Add for V {
    type Output = V;
    fn add(self, o: V) -> V {
        V::new(self.x + o.x, self.y + o.y)
    }
}

impl Sub for V {
    type Output = V;
    fn sub(self, o: V) -> V {
        V::new(self.x - o.x, self.y - o.y)
    }
}

impl Neg for V {
    type Output = V;
    fn neg(self) -> V {
        V::new(-self.x, -self.y)
    }
}

impl Mul<DD> for V {
    type Output = V;
    fn mul(self, k: DD) -> V {
        V::new(self.x * k, self.y * k)
    }
}

impl Mul<f64> for V {
    type Output = V;
    fn mul(self, k: f64) -> V {
        V::new(self.x * k, self.y * k)
    }
}

/// Sorts points by angle about their mean (atan2 ascending).
fn sort_about_mean(pts: &mut [V]) {
    if pts.is_empty() {
        return;
    }
    let k = DD::from(pts.len() as f64);
    let sum = pts
        .iter()
        .fold(V::new(DD::ZERO, DD::ZERO), |acc, p| acc + *p);
    let mean = V::new(sum.x / k, sum.y / k);
    let angle = |p: &V| {
        let d = *p - mean;
        d.y.to_f64().atan2(d.x.to_f64())
    };
    pts.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
}

// ---------------------------------------------------------------------------
// Geometry in DD, relative to the pair origin
// ---------------------------------------------------------------------------

/// In / on / out classification of a point with respect to a closed solid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Cls {
    In,
    On,
    Out,
}

/// Classifies a signed value (negative inside) with tolerance `tol`.
fn cls_of(v: DD, tol: f64) -> Cls {
    if v > tol {
        Cls::Out
    } else if v < -tol {
        Cls::In
    } else {
        Cls::On
    }
}

/// Unit body axes `(e1, e2)` from `θ`: `(θ.cos(), θ.sin())` in `f64`, renormalised in DD.
fn axes(angle: f64) -> (V, V) {
    let e1 = V::new(DD::from(angle.cos()), DD::from(angle.sin())).unit();
    (e1, e1.perp())
}

/// Circle or ellipse.
#[derive(Clone, Copy, Debug)]
pub(super) struct Conic {
    pub(super) c: V,
    pub(super) e1: V,
    pub(super) e2: V,
    pub(super) a: DD,
    pub(super) b: DD,
}

impl Conic {
    pub(super) fn local(&self, x: V) -> (DD, DD) {
        let w = x - self.c;
        (w.dot(self.e1), w.dot(self.e2))
    }

    /// Scaled implicit function `b²ξ² + a²η² − a²b²` (negative inside) and the
    /// magnitude of its terms.
    fn implicit(&self, x: V) -> (DD, f64) {
        let (l1, l2) = self.local(x);
        let t1 = (self.b * l1).sqr();
        let t2 = (self.a * l2).sqr();
        let t0 = (self.a * self.b).sqr();
        (t1 + t2 - t0, t1.to_f64() + t2.to_f64() + t0.to_f64())
    }

    pub(super) fn classify(&self, x: V) -> Cls {
        let (v, scale) = self.implicit(x);
        cls_of(v, TOL_REL * scale)
    }

    /// Boundary point with parameter `(cos t, sin t)`.
    pub(super) fn point_at(&self, cos: DD, sin: DD) -> V {
        self.c + self.e1 * (self.a * cos) + self.e2 * (self.b * sin)
    }

    /// Outward unit normal at (or near) a boundary point.
    fn normal_at(&self, x: V) -> V {
        let (l1, l2) = self.local(x);
        (self.e1 * (self.b.sqr() * l1) + self.e2 * (self.a.sqr() * l2)).unit()
    }

    fn support(&self, u: V) -> DD {
        let s = ((self.a * u.dot(self.e1)).sqr() + (self.b * u.dot(self.e2)).sqr()).sqrt();
        self.c.dot(u) + s
    }
}

/// Rectangle with half sizes `hw`, `hh`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Rect {
    pub(super) c: V,
    pub(super) e1: V,
    pub(super) e2: V,
    pub(super) hw: DD,
    pub(super) hh: DD,
}

impl Rect {
    /// Corners in CCW order, starting at the (−,−) corner.
    pub(super) fn corners(&self) -> [V; 4] {
        let u = self.e1 * self.hw;
        let v = self.e2 * self.hh;
        [
            self.c - u - v,
            self.c + u - v,
            self.c + u + v,
            self.c - u + v,
        ]
    }

    /// Outward normals of the four edge lines, matching [`Rect::edge_values`].
    fn edge_normals(&self) -> [V; 4] {
        [self.e1, -self.e1, self.e2, -self.e2]
    }

    /// Signed distances of `x` to the four edge lines (positive outside) and a tolerance.
    fn edge_values(&self, x: V) -> ([DD; 4], f64) {
        let w = x - self.c;
        let (l1, l2) = (w.dot(self.e1), w.dot(self.e2));
        let g = [l1 - self.hw, -l1 - self.hw, l2 - self.hh, -l2 - self.hh];
        let scale = l1.abs().to_f64() + l2.abs().to_f64() + self.hw.to_f64() + self.hh.to_f64();
        (g, TOL_REL * scale)
    }

    pub(super) fn classify(&self, x: V) -> Cls {
        let (g, tol) = self.edge_values(x);
        cls_of(g.into_iter().fold(g[0], DD::max), tol)
    }

    /// Outward unit normal if `x` is on exactly one edge line (not at a corner).
    fn normal_at(&self, x: V) -> Option<V> {
        let (g, tol) = self.edge_values(x);
        let mut on = g
            .iter()
            .zip(self.edge_normals())
            .filter(|(v, _)| v.abs() <= tol)
            .map(|(_, n)| n);
        match (on.next(), on.next()) {
            (Some(n), None) => Some(n),
            _ => None,
        }
    }

    fn support(&self, u: V) -> DD {
        self.c.dot(u) + self.hw * u.dot(self.e1).abs() + self.hh * u.dot(self.e2).abs()
    }
}

/// Wall half-plane `{x : n·(x − p) ≤ 0}` with unit `n`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Wall {
    pub(super) p: V,
    pub(super) n: V,
}

impl Wall {
    /// `n·(x − p)` (negative in the solid) and a tolerance.
    fn value(&self, x: V) -> (DD, f64) {
        (
            self.n.dot(x - self.p),
            TOL_REL * (x.norm1() + self.p.norm1()),
        )
    }

    pub(super) fn classify(&self, x: V) -> Cls {
        let (v, tol) = self.value(x);
        cls_of(v, tol)
    }
}

/// An object of the pair in DD, relative to the pair origin.
#[derive(Clone, Copy, Debug)]
pub(super) enum Geo {
    Conic(Conic),
    Rect(Rect),
    Wall(Wall),
}

impl Geo {
    pub(super) fn new(obj: &RObj, origin: [f64; 2]) -> Geo {
        match *obj {
            RObj::Body { shape, pos, angle } => {
                let c = V::rel(pos, origin);
                let (e1, e2) = axes(angle);
                match shape {
                    RShape::Circle { r } => Geo::Conic(Conic {
                        c,
                        e1,
                        e2,
                        a: DD::from(r),
                        b: DD::from(r),
                    }),
                    RShape::Ellipse { a, b } => Geo::Conic(Conic {
                        c,
                        e1,
                        e2,
                        a: DD::from(a),
                        b: DD::from(b),
                    }),
                    RShape::Rectangle { w, h } => Geo::Rect(Rect {
                        c,
                        e1,
                        e2,
                        hw: DD::from(w).mul_pow2(0.5),
                        hh: DD::from(h).mul_pow2(0.5),
                    }),
                }
            }
            RObj::Wall { point, normal } => Geo::Wall(Wall {
                p: V::rel(point, origin),
                n: V::from_f64(normal).unit(),
            }),
        }
    }

    /// Body centre (wall: its point).
    fn center(&self) -> V {
        match self {
            Geo::Conic(c) => c.c,
            Geo::Rect(r) => r.c,
            Geo::Wall(w) => w.p,
        }
    }

    /// Support function `h(u)`; for a wall only meaningful at `u` = its normal.
    fn support(&self, u: V) -> DD {
        match self {
            Geo::Conic(c) => c.support(u),
            Geo::Rect(r) => r.support(u),
            Geo::Wall(w) => w.p.dot(u),
        }
    }

    /// Outward unit normal at a boundary point where the boundary is smooth.
    fn normal_at(&self, x: V) -> Option<V> {
        match self {
            Geo::Conic(c) => Some(c.normal_at(x)),
            Geo::Rect(r) => r.normal_at(x),
            Geo::Wall(w) => Some(w.n),
        }
    }
}

pub(super) fn origin_of(i: &RObj, j: &RObj) -> [f64; 2] {
    match (i, j) {
        (RObj::Body { pos, .. }, _) | (RObj::Wall { .. }, RObj::Body { pos, .. }) => *pos,
        _ => panic!("reference: a pair of two walls has no contact geometry"),
    }
}

/// `h_i(n) + h_j(−n)`.
fn depth_dd(gi: &Geo, gj: &Geo, n: V) -> DD {
    gi.support(n) + gj.support(-n)
}

/// Orients a unit normal from `i` to `j` (see the module documentation).
fn orient(gi: &Geo, gj: &Geo, n: V) -> V {
    match (gi, gj) {
        (Geo::Wall(w), _) => w.n,
        (_, Geo::Wall(w)) => -w.n,
        _ => match n.dot(gj.center() - gi.center()).partial_cmp(&DD::ZERO) {
            Some(Ordering::Greater) => n,
            Some(Ordering::Less) => -n,
            _ => {
                if depth_dd(gi, gj, -n) < depth_dd(gi, gj, n) {
                    -n
                } else {
                    n
                }
            }
        },
    }
}

// ---------------------------------------------------------------------------
// Crossing search
// ---------------------------------------------------------------------------

/// Raw result of the crossing search.
#[derive(Debug, Default)]
pub(super) struct Found {
    pub(super) crossings: Vec<V>,
    pub(super) touches: Vec<V>,
    /// Only meaningful without crossings and touches.
    pub(super) contained: bool,
    /// The two boundaries coincide.
    pub(super) coincident: bool,
}

pub(super) fn find(gi: &Geo, gj: &Geo) -> Found {
    match (gi, gj) {
        (Geo::Conic(a), Geo::Conic(b)) => conic_conic(a, b),
        (Geo::Wall(w), Geo::Conic(c)) | (Geo::Conic(c), Geo::Wall(w)) => wall_conic(w, c),
        (Geo::Wall(w), Geo::Rect(r)) | (Geo::Rect(r), Geo::Wall(w)) => wall_rect(w, r),
        (Geo::Rect(r), Geo::Conic(c)) | (Geo::Conic(c), Geo::Rect(r)) => rect_conic(r, c),
        (Geo::Rect(a), Geo::Rect(b)) => rect_rect(a, b),
        (Geo::Wall(_), Geo::Wall(_)) => unreachable!("two walls are rejected by origin_of"),
    }
}

/// Unit vectors at angles `2πk/16`, (`f64` cos/sin renormalised in DD).
fn unit_samples() -> impl Iterator<Item = (DD, DD)> {
    (0..N_SAMPLES).map(|k| {
        let t = k as f64 * (2.0 * PI / N_SAMPLES as f64);
        let u = V::new(DD::from(t.cos()), DD::from(t.sin())).unit();
        (u.x, u.y)
    })
}

/// The sample `(cos t, sin t)` of `on`'s boundary with the largest |implicit of
/// `against`|, and that implicit value.
fn farthest_sample(on: &Conic, against: &Conic) -> (DD, DD, DD) {
    unit_samples()
        .map(|(c, s)| (c, s, against.implicit(on.point_at(c, s)).0))
        .max_by(|x, y| x.2.abs().cmp_total(&y.2.abs()))
        .expect("N_SAMPLES > 0")
}

/// Conic–conic crossings via the tangent-half-angle quartic (see the module docs).
fn conic_conic(ci: &Conic, cj: &Conic) -> Found {
    let (cs, sn, v_far) = farthest_sample(cj, ci);
    // t0 = t_far − π, so that z = tan((t − t0)/2) = ∞ at the farthest sample.
    let (c0, s0) = (-cs, -sn);
    // x(τ) = c_j + cos τ · p + sin τ · r
    let p = cj.e1 * (cj.a * c0) + cj.e2 * (cj.b * s0);
    let r = cj.e2 * (cj.b * c0) - cj.e1 * (cj.a * s0);
    let d = cj.c - ci.c;
    let mag = d.norm1() + p.norm1() + r.norm1();

    // Quartic Σ_k q_k(z)² − (a_i b_i)² (1 + z²)², with (1 + z²)·u_k(τ) = q_k(z).
    let mut coef = [DD::ZERO; 5];
    let mut abs = [0.0f64; 5];
    for (axis, k) in [(ci.e1, ci.b), (ci.e2, ci.a)] {
        let (dk, pk, rk) = (k * d.dot(axis), k * p.dot(axis), k * r.dot(axis));
        let q = [dk + pk, rk * 2.0, dk - pk];
        let m = k.to_f64() * mag;
        let qa = [m, 2.0 * m, m];
        for (ia, (qi, mi)) in q.iter().zip(qa).enumerate() {
            for (ib, (qj, mj)) in q.iter().zip(qa).enumerate() {
                coef[ia + ib] += *qi * *qj;
                abs[ia + ib] += mi * mj;
            }
        }
    }
    let ab2 = (ci.a * ci.b).sqr();
    for (k, m) in [(0usize, 1.0), (2, 2.0), (4, 1.0)] {
        coef[k] -= ab2 * m;
        abs[k] += ab2.to_f64() * m;
    }
    let err: Vec<f64> = abs.iter().map(|a| a * COEF_ERR_REL).collect();

    let mut found = Found::default();
    if coef
        .iter()
        .zip(&err)
        .all(|(c, e)| c.abs().to_f64() <= ROOT_SAFETY * e)
    {
        found.coincident = true;
        return found;
    }
    for (z, mult) in poly_real_roots_err(&coef, &err) {
        let z2 = z.sqr();
        let den = z2 + 1.0;
        let cos = (1.0 - z2) / den;
        let sin = z * 2.0 / den;
        let x = cj.c + p * cos + r * sin;
        if mult % 2 == 1 {
            found.crossings.push(x);
        } else {
            found.touches.push(x);
        }
    }
    if found.crossings.is_empty() && found.touches.is_empty() {
        // j inside i, or else (test a far sample of i's boundary) i inside j.
        found.contained = v_far.is_negative() || farthest_sample(ci, cj).2.is_negative();
    }
    found
}

/// Real roots of the conic's implicit function along the line `base + s·dir`.
enum LineRoots {
    None,
    Double(DD),
    Two(DD, DD),
}

impl LineRoots {
    fn into_vec(self) -> Vec<DD> {
        match self {
            LineRoots::None => Vec::new(),
            LineRoots::Double(s) => vec![s],
            LineRoots::Two(s1, s2) => vec![s1, s2],
        }
    }
}

/// Quadratic `A s² + B s + C` of the scaled implicit along a line, solved in DD
/// (discriminant within the relative tolerance ⇒ double root).
fn line_roots(c: &Conic, base: V, dir: V) -> LineRoots {
    let (w1, w2) = c.local(base);
    let (al1, al2) = (c.b * w1, c.a * w2);
    let (be1, be2) = (c.b * dir.dot(c.e1), c.a * dir.dot(c.e2));
    let ab2 = (c.a * c.b).sqr();
    let qa = be1.sqr() + be2.sqr();
    let qb = (al1 * be1 + al2 * be2) * 2.0;
    let qc = al1.sqr() + al2.sqr() - ab2;
    let disc = qb.sqr() - qa * qc * 4.0;
    let scale = qb.sqr() + qa * (al1.sqr() + al2.sqr() + ab2) * 4.0;
    let tol = TOL_REL * scale.to_f64();
    if disc < -tol {
        LineRoots::None
    } else if disc <= tol {
        LineRoots::Double(-qb / (qa * 2.0))
    } else {
        let sq = disc.sqrt();
        let q = if qb.is_negative() {
            (sq - qb).mul_pow2(0.5)
        } else {
            -(qb + sq).mul_pow2(0.5)
        };
        LineRoots::Two(q / qa, qc / q)
    }
}

fn wall_conic(w: &Wall, c: &Conic) -> Found {
    let dir = w.n.perp();
    // Foot of the centre on the wall line: keeps the line parameter small.
    let base = c.c - w.n * w.n.dot(c.c - w.p);
    let mut found = Found::default();
    match line_roots(c, base, dir) {
        LineRoots::Two(s1, s2) => found.crossings = vec![base + dir * s1, base + dir * s2],
        LineRoots::Double(s) => found.touches = vec![base + dir * s],
        LineRoots::None => found.contained = w.value(c.c).0.is_negative(),
    }
    found
}

/// One piece of the walked polygon boundary: a point (`a == b`) or an open segment `a → b`.
#[derive(Clone, Copy, Debug)]
struct Item {
    a: V,
    b: V,
    cls: Cls,
}

/// Result of walking a polygon boundary against another solid.
#[derive(Debug)]
struct Walk {
    crossings: Vec<V>,
    touches: Vec<V>,
    /// Class of every piece when there are no transitions at all.
    uniform: Cls,
}

/// Walks the closed polygon `corners` (CCW), splitting each edge `a → b` at the
/// parameters `breaks(a, b)` (where it may meet the other boundary) and
/// classifying corners, breakpoints and open sub-segments (at their midpoints)
/// with `classify`. Every maximal run of `On` pieces is one crossing (at the
/// midpoint of the run's end points) if the pieces before and after it are
/// `In`/`Out` (in either order), and a touching point if they agree.
fn walk_polygon(
    corners: &[V; 4],
    breaks: impl Fn(V, V) -> Vec<DD>,
    classify: impl Fn(V) -> Cls,
) -> Walk {
    let mut items = Vec::new();
    let s_max = DD::ONE - S_MIN;
    for (k, &a) in corners.iter().enumerate() {
        let b = corners[(k + 1) % corners.len()];
        items.push(Item {
            a,
            b: a,
            cls: classify(a),
        });
        let mut ss: Vec<DD> = breaks(a, b)
            .into_iter()
            .filter(|&s| s > S_MIN && s < s_max)
            .collect();
        ss.sort_by(DD::cmp_total);
        ss.dedup_by(|x, y| (*x - *y).abs() <= S_MIN);
        let mut prev = a;
        for s in ss {
            let x = a + (b - a) * s;
            items.push(Item {
                a: prev,
                b: x,
                cls: classify(prev.mid(x)),
            });
            items.push(Item {
                a: x,
                b: x,
                cls: classify(x),
            });
            prev = x;
        }
        items.push(Item {
            a: prev,
            b,
            cls: classify(prev.mid(b)),
        });
    }

    let n = items.len();
    let mut walk = Walk {
        crossings: Vec::new(),
        touches: Vec::new(),
        uniform: Cls::On,
    };
    let Some(start) = items.iter().position(|it| it.cls != Cls::On) else {
        return walk; // all On: coincident boundaries
    };
    let seq: Vec<Item> = (0..n).map(|k| items[(start + k) % n]).collect();
    walk.uniform = seq[0].cls;
    let mut k = 0;
    while k < n {
        let cur = seq[k];
        let mut m = k + 1;
        while seq[m % n].cls == Cls::On {
            m += 1;
        }
        let next = seq[m % n];
        if m > k + 1 {
            let run_mid = seq[k + 1].a.mid(seq[m - 1].b);
            if cur.cls == next.cls {
                walk.touches.push(run_mid);
            } else {
                walk.crossings.push(run_mid);
            }
        } else if cur.cls != next.cls {
            // Direct in/out transition without an `On` piece (not expected):
            // the crossing is at the shared end point.
            walk.crossings.push(cur.b);
        }
        k = m;
    }
    walk
}

/// Converts a walk into a [`Found`]; `other_inside` tells whether the other
/// object lies inside the walked polygon (asked only if the polygon is entirely outside it).
fn found_from_walk(walk: Walk, other_inside: impl FnOnce() -> bool) -> Found {
    let quiet = walk.crossings.is_empty() && walk.touches.is_empty();
    Found {
        contained: quiet
            && match walk.uniform {
                Cls::In => true,
                Cls::Out => other_inside(),
                Cls::On => false,
            },
        coincident: quiet && walk.uniform == Cls::On,
        crossings: walk.crossings,
        touches: walk.touches,
    }
}

fn wall_rect(w: &Wall, r: &Rect) -> Found {
    let walk = walk_polygon(
        &r.corners(),
        |a, b| {
            let ((fa, ta), (fb, tb)) = (w.value(a), w.value(b));
            let straddle = (fa < -ta && fb > tb) || (fa > ta && fb < -tb);
            if straddle {
                vec![fa / (fa - fb)]
            } else {
                Vec::new()
            }
        },
        |x| w.classify(x),
    );
    found_from_walk(walk, || false)
}

fn rect_conic(r: &Rect, c: &Conic) -> Found {
    let walk = walk_polygon(
        &r.corners(),
        |a, b| line_roots(c, a, b - a).into_vec(),
        |x| c.classify(x),
    );
    found_from_walk(walk, || {
        r.classify(c.point_at(DD::ONE, DD::ZERO)) == Cls::In
    })
}

/// Walks `rj`'s boundary against `ri`.
fn rect_rect(ri: &Rect, rj: &Rect) -> Found {
    let walk = walk_polygon(
        &rj.corners(),
        |a, b| {
            let ((ga, ta), (gb, tb)) = (ri.edge_values(a), ri.edge_values(b));
            ga.iter()
                .zip(gb)
                .filter(|&(&g0, g1)| (g0 < -ta && g1 > tb) || (g0 > ta && g1 < -tb))
                .map(|(&g0, g1)| g0 / (g0 - g1))
                .collect()
        },
        |x| ri.classify(x),
    );
    found_from_walk(walk, || rj.classify(ri.corners()[0]) == Cls::In)
}

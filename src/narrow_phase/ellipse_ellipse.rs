//! Ellipse–ellipse contact by the pencil of conics (P5–P10).
//!
//! 1. Cheap rejection: bounding circles, then the separating-axis test along the line of centres
//!    (two square roots).
//! 2. The paper's local frame (P5–P7): origin at the centroid of i, x axis through the centroid of
//!    j; lengths in units of a power of two near the larger semi-axis.
//! 3. The real roots of `D(λ) = 0` (P10) by the solvers of [`crate::geometry::cubic`]: the fast
//!    one when the cubic certainly has a single real root, the robust one otherwise.
//! 4. Each real root's member of the pencil (P9) is split into two lines; a line that meets
//!    ellipse i in real points meets ellipse j in the same points (on the line `f ≡ −λ g`), so
//!    the real crossings are read off line ∩ ellipse i alone.
//! 5. Two crossings: the chord definition. One tangent point: touching. Four: deep fallback.
//!    None: separated, or one inside the other (one boundary point tested against the other).
//!
//! Which roots give what (projective facts): two ellipses crossing at two points have one real
//! root, whose member is the chord line plus a line through the two complex crossings (which
//! meets ellipse i in complex points only); separated or nested ellipses have three real roots
//! and no member meets them in real points; four crossings give three real members, each through
//! all four points. At tangency two roots merge (a double root, a point-ellipse member).
//! Equal shapes with equal orientation give the root λ = −1 exactly, whose member is one finite
//! line (the chord) plus the line at infinity.
//!
//! # Warm start (the dynamics' path)
//! A contact that lasts moves little from one step to the next. Given last step's two crossings
//! ([`Warm`], kept in the pair's [`super::PairCache`]), the kernel first refines them by
//! Newton's method on the two boundary equations `Q_i(p) = 1`, `Q_j(p) = 1` — a few flops per
//! iteration, two iterations (rarely more) from a guess of the last step, both crossings as the
//! two lanes of one SIMD register ([`newton_crossings`]) — and applies the chord definition to
//! them (both caps of the area law in two lanes too: they are minor and short there, see
//! [`crate::geometry::overlap_area::minor_caps_sum`]), all in body i's own frame (no line of centres, so no
//! square root or division before the first Newton step; see [`warm_crossings`]). It accepts the result
//! only when it is certain to be the one the pencil would give, to rounding: Newton converged
//! to two distinct points, the boundaries cross there at an angle (|sin| ≥ [`WARM_MIN_SINE`],
//! so the points are well conditioned; grazing contacts go to the pencil, which gets the chord
//! line without computing the points first), and the overlap is shallow (δ ≤
//! [`WARM_MAX_DEPTH`] × the smaller semi-axis, far from the depths at which four crossings are
//! possible). Anything else — a first contact, a deep or grazing one, no convergence — takes
//! the pencil.

use super::local::{
    LocalFrame, LocalOverlap, deep_fallback, deep_overlap, orient_symmetric, pow2_floor,
};
use super::record::{Contact, ContactState, Request, TOUCH_TOL};
use crate::geometry::Pose;
use crate::geometry::conic::EllipseForm;
use crate::geometry::cubic::{one_real_root, solve_cubic};
use crate::geometry::overlap_area::{ellipse_cap_inverse, minor_caps_sum};
use crate::geometry::pencil::{
    LineCut, Pencil, cut_line, mixed_invariant_from_inverse_squares, split_degenerate,
};
use wide::f64x2;

/// Half-chords² (in units of the larger semi-axis squared) below which a line counts as nearly
/// tangent and is judged by the depth along its normal. The line itself carries the rounding of
/// λ and of the splitting (measured up to ~1e-14 at a/b = 100), which `half_sq_err` does not
/// include; a generous band costs nothing, since the depth decides.
const NEAR_TANGENT: f64 = 1e-10;

/// Smallest |sin| of the angle between the boundaries at a crossing for the warm path: the
/// crossings' error is then at most ~ε/|sin| of the size, and the chord normal's at most that
/// over the chord's length (≲ 1e-10 rad).
pub const WARM_MIN_SINE: f64 = 1e-3;

/// Deepest overlap, as a fraction of the pair's smaller semi-axis, taken by the warm path (two
/// ellipses overlapping this little cross at exactly two points).
pub const WARM_MAX_DEPTH: f64 = 0.05;

/// What a pair carries from one step to the next to start from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Warm {
    /// A lasting contact's two crossings, relative to body i's centroid in body i's own frame
    /// (so that they move with the pair).
    Crossings([[f64; 2]; 2]),
    /// A separated pair's separating axis, as `(cos ψ, sin ψ)` of its angle ψ from the line of
    /// centres (so that it turns with the pair).
    Axis([f64; 2]),
}

impl Warm {
    /// The same warm start carried by the pair seen the other way round: given relative to the
    /// body at `from`, returned relative to the body at `to` (the other body of the pair).
    /// Crossings are re-expressed in the other body's frame; a separating axis, an angle from
    /// the line of centres with both the line and the axis pointing from the first body to the
    /// second, is the same for either order.
    #[inline]
    pub(crate) fn seen_from(self, from: &Pose, to: &Pose) -> Warm {
        match self {
            Warm::Crossings(ps) => {
                let offset = from.position - to.position;
                Warm::Crossings(ps.map(|p| {
                    let w = from.to_world_vector(crate::geometry::Vec2::new(p[0], p[1])) + offset;
                    let q = to.to_body_vector(w);
                    [q.x, q.y]
                }))
            }
            Warm::Axis(a) => Warm::Axis(a),
        }
    }
}

/// An ellipse placed in a pair's frame (lengths scaled): semi-axes, the direction `(cos, sin)`
/// of its `a` axis, and its centre `(x, y)` — in P's local frame `(x, 0)` on the line of
/// centres, in body i's own frame (the warm path) anywhere.
#[derive(Clone, Copy, Debug)]
struct Placed {
    a: f64,
    b: f64,
    /// `[1/a², 1/b²]`, as the pair's conic forms hold them.
    inv2: [f64; 2],
    cos: f64,
    sin: f64,
    x: f64,
    y: f64,
}

impl Placed {
    /// An ellipse of semi-axes `a`, `b` (with `inv2 = [1/a², 1/b²]`) whose `a` axis is at
    /// `(cos, sin)` and whose centre is at `centre`, in the pair's frame.
    #[inline(always)]
    fn at(a: f64, b: f64, inv2: [f64; 2], (cos, sin): (f64, f64), centre: [f64; 2]) -> Self {
        Placed {
            a,
            b,
            inv2,
            cos,
            sin,
            x: centre[0],
            y: centre[1],
        }
    }

    /// Centred support along `u`.
    #[inline]
    fn support(&self, u: [f64; 2]) -> f64 {
        support(self.a, self.b, self.cos, self.sin, u[0], u[1])
    }

    /// `max over the ellipse of u·(p − m)` for a unit `u`.
    #[inline]
    fn height(&self, u: [f64; 2], m: [f64; 2]) -> f64 {
        self.support(u) + u[0] * (self.x - m[0]) + u[1] * (self.y - m[1])
    }

    /// Area of the ellipse beyond the chord from `p` (on its boundary) by `e`, on the side
    /// towards `u`: the minor cap, or the rest when its centre is on that side.
    #[inline(always)]
    fn cap(&self, p: [f64; 2], e: [f64; 2], u: [f64; 2]) -> f64 {
        let (c, s) = (self.cos, self.sin);
        let body = move |v: [f64; 2]| [c * v[0] + s * v[1], -s * v[0] + c * v[1]];
        let rel = [p[0] - self.x, p[1] - self.y];
        let major = u[0] * rel[0] + u[1] * rel[1] < 0.0;
        ellipse_cap_inverse(self.a, self.b, self.inv2, || body(rel), body(e), major)
    }
}

/// The overlap of two crossings p, p + e with chord normal `n` (i → j): the cap of i beyond the
/// chord towards j and the cap of j towards i.
#[inline(always)]
fn chord_overlap(ei: &Placed, ej: &Placed, p: [f64; 2], e: [f64; 2], n: [f64; 2]) -> LocalOverlap {
    let area = ei.cap(p, e, n) + ej.cap(p, e, [-n[0], -n[1]]);
    LocalOverlap::chord(area, p, [p[0] + e[0], p[1] + e[1]], n)
}

/// Centred support function of an ellipse along a direction `(ux, uy)` of a frame in which its
/// `a` axis is at `(cos, sin)`.
#[inline]
fn support(a: f64, b: f64, cos: f64, sin: f64, ux: f64, uy: f64) -> f64 {
    let (pa, pb) = (a * (cos * ux + sin * uy), b * (cos * uy - sin * ux));
    (pa * pa + pb * pb).sqrt()
}

/// Refines two crossings of the boundaries `Q_i(p) = 1` (i centred at the origin) and
/// `Q_j(p − c) = 1` (j centred at `c`: `(d, 0)` in P's local frame) by Newton's method. `None`
/// unless both converge to distinct, well conditioned points (see the module documentation).
///
/// The two crossings are independent Newton iterations, run as the two lanes of one SIMD
/// register (`wide::f64x2`: each lane's arithmetic is IEEE's, the same bits as scalar code), with
/// no branch inside an iteration. Both lanes take the same steps: at least two — a warm start
/// is last step's crossing rounded to `f32` ([`super::PairCache`]), ~3e-8 of the size off,
/// which the first step brings to ~1e-15 and the second below rounding — then more until both
/// steps are below 1e-9 of the size (after such a step, quadratic convergence puts the error
/// below rounding), six at most. A lane whose step is already that small takes the next ones
/// anyway: they are of the size of rounding and leave it at the root. The crossing angle is
/// checked once, at the last iterate (where the result's conditioning is decided), not at every
/// one: a NaN or a wild jump on the way is caught by the tests at the end.
///
/// Inlined: its callers have just computed the forms, which then stay in registers.
#[inline(always)]
fn newton_crossings(
    fi: &EllipseForm,
    fj: &EllipseForm,
    c: [f64; 2],
    guess: [[f64; 2]; 2],
) -> Option<[[f64; 2]; 2]> {
    let splat = f64x2::splat;
    let (ai, bi, ci) = (splat(fi.a_coef), splat(fi.b_coef), splat(fi.c_coef));
    let (aj, bj, cj) = (splat(fj.a_coef), splat(fj.b_coef), splat(fj.c_coef));
    let (cx, cy) = (splat(c[0]), splat(c[1]));
    let (half, one) = (splat(0.5), splat(1.0));
    let x0 = f64x2::new([guess[0][0], guess[1][0]]);
    let y0 = f64x2::new([guess[0][1], guess[1][1]]);
    // One Newton step from (x, y) in both lanes: the step, `det²` and `|g₁|²|g₂|²`. With the
    // gradients and residuals both halved (exact), the step is the same; the half residual is
    // `½(p·∇Q − 1) = ½(p·g − 1)` for the half gradient g (Q is a quadratic form).
    let step = |x: f64x2, y: f64x2| {
        let (xj, yj) = (x - cx, y - cy);
        let (g1x, g1y) = (ai * x + bi * y, bi * x + ci * y);
        let (g2x, g2y) = (aj * xj + bj * yj, bj * xj + cj * yj);
        let f1 = half * ((x * g1x + y * g1y) - one);
        let f2 = half * ((xj * g2x + yj * g2y) - one);
        let det = g1x * g2y - g1y * g2x;
        let inv = one / det;
        let dx = (g1y * f2 - g2y * f1) * inv;
        let dy = (g2x * f1 - g1x * f2) * inv;
        let norms = (g1x * g1x + g1y * g1y) * (g2x * g2x + g2y * g2y);
        (dx, dy, det * det, norms)
    };
    let (dx, dy, _, _) = step(x0, y0);
    let (mut x, mut y) = (x0 + dx, y0 + dy);
    let mut iterations = 1;
    let (det2, norms) = loop {
        let (dx, dy, det2, norms) = step(x, y);
        // Quadratic convergence: after a step this small the error is below rounding.
        let (d2, p2) = ((dx * dx + dy * dy).to_array(), (x * x + y * y).to_array());
        (x, y) = (x + dx, y + dy);
        iterations += 1;
        if d2[0] <= 1e-18 * (1.0 + p2[0]) && d2[1] <= 1e-18 * (1.0 + p2[1]) {
            break (det2.to_array(), norms.to_array());
        }
        if iterations == 6 {
            return None;
        }
    };
    // Grazing (or not finite): an ill-conditioned crossing, for the pencil.
    let min2 = WARM_MIN_SINE * WARM_MIN_SINE;
    if !(det2[0] >= min2 * norms[0] && det2[1] >= min2 * norms[1]) {
        return None;
    }
    let ([x, y], [x0, y0]) = ([x.to_array(), y.to_array()], [x0.to_array(), y0.to_array()]);
    let out = [[x[0], y[0]], [x[1], y[1]]];
    // Lengths here are of order one (the frame is scaled): no over- or underflow to guard
    // against, so squares rather than `hypot`.
    let (ex, ey) = (x[1] - x[0], y[1] - y[0]);
    let chord2 = ex * ex + ey * ey;
    // The same crossing twice, or a wild jump: not the chord we are tracking.
    let moved2 = |k: usize| {
        let (mx, my) = (x[k] - x0[k], y[k] - y0[k]);
        mx * mx + my * my
    };
    if chord2.is_nan() || chord2 <= 1e-12 || moved2(0) > 0.25 * chord2 || moved2(1) > 0.25 * chord2
    {
        return None;
    }
    Some(out)
}

/// A separating axis of the two ellipses, if a few steps find one: the gap along the unit
/// vector at angle φ from the line of centres, `g(φ) = d cos φ − S(φ)` (S the sum of the
/// centred supports), is maximised by Newton's method on `g′ = 0` from `start`, stopping as
/// soon as `g > tol` — a proof of separation (the supports are exact to rounding) — or after
/// `iterations`. `None` when none is found (overlapping, touching, too close to tell, or not
/// within the iterations): the pencil then decides.
/// `(ai, bi, cti, sti)` and `(aj, bj, ctj, stj)` are the ellipses as in [`support`].
fn separating_axis(
    (ai, bi, cti, sti): (f64, f64, f64, f64),
    (aj, bj, ctj, stj): (f64, f64, f64, f64),
    d: f64,
    start: [f64; 2],
    tol: f64,
    iterations: usize,
) -> Option<[f64; 2]> {
    // Support, its first and second derivatives in φ: with p = (a u·e_a, b u·e_b),
    // s = |p|, s′ = p_a p_b (b/a − a/b)/s, s″ = ((a/b)² p_b² + (b/a)² p_a² − s² − s′²)/s.
    let derivs = |a: f64, b: f64, c: f64, sn: f64, ux: f64, uy: f64| {
        let (pa, pb) = (a * (c * ux + sn * uy), b * (c * uy - sn * ux));
        let s = (pa * pa + pb * pb).sqrt();
        let (ab, ba) = (a / b, b / a);
        let s1 = pa * pb * (ba - ab) / s;
        let s2 = (ab * ab * pb * pb + ba * ba * pa * pa - s * s - s1 * s1) / s;
        (s, s1, s2)
    };
    let (mut c, mut sn) = (start[0], start[1]);
    for _ in 0..iterations {
        let (si, si1, si2) = derivs(ai, bi, cti, sti, c, sn);
        let (sj, sj1, sj2) = derivs(aj, bj, ctj, stj, c, sn);
        let g = d * c - si - sj;
        if g > tol {
            return Some([c, sn]);
        }
        let g1 = -d * sn - si1 - sj1;
        let g2 = -d * c - si2 - sj2;
        // The quadratic model's maximum, g − g′²/(2g″), well below zero: the pair almost surely
        // overlaps, and the pencil will tell; only a found axis is ever taken as a proof.
        if g2 < 0.0 && g - g1 * g1 / (2.0 * g2) < -1e-3 * (ai.min(bi) + aj.min(bj)) {
            return None;
        }
        // Newton where g is concave; otherwise a bounded step uphill.
        let step = if g2 < 0.0 {
            (-g1 / g2).clamp(-0.5, 0.5)
        } else {
            0.25f64.copysign(g1)
        };
        if !step.is_finite() || step.abs() < 1e-9 {
            return None; // converged on a maximum that does not separate
        }
        // Turn by `step` (a unit vector again after normalising; no sine or cosine needed).
        let (nc, ns) = (c - step * sn, sn + step * c);
        let inv = 1.0 / (nc * nc + ns * ns).sqrt();
        (c, sn) = (nc * inv, ns * inv);
    }
    None
}

/// The warm path of a lasting contact (see the module documentation), in body i's own frame
/// (centred on i, x axis along i's `a` axis, lengths divided by `scale`): last step's crossings
/// `guess` (kept in that frame, unscaled) refined by Newton's method, and the chord definition
/// applied to them; `None` unless the result is accepted.
///
/// No line of centres is needed here: in this frame i's form is diagonal, j's centre is
/// `u = R(−θ_i)(c_j − c_i)` and its axis is at the relative angle φ, so the frame costs no
/// square root and no division (P's local frame, which the pencil needs, costs one of each and
/// lies on the path to every Newton step). The crossings are as well conditioned in either
/// frame, and both are centred on i, so the results agree with the pencil's to rounding.
/// `(ai, bi, aj, bj)` are the semi-axes (unscaled), `dv = c_j − c_i`, `scale` the pair's power
/// of two ([`pow2_floor`] of the larger bounding radius). Returns the contact and the next
/// step's warm start.
#[inline(always)]
fn warm_crossings(
    (ai, bi, aj, bj): (f64, f64, f64, f64),
    pi: &Pose,
    pj: &Pose,
    dv: crate::geometry::Vec2,
    scale: f64,
    guess: [[f64; 2]; 2],
    request: &Request,
) -> Option<(Contact, Warm)> {
    let inv = pow2_recip(scale);
    let (ci, si) = pi.cos_sin();
    let (cj, sj) = pj.cos_sin();
    // Relative angle φ from i's a axis to j's a axis (frame independent).
    let (cphi, sphi) = (cj * ci + sj * si, sj * ci - cj * si);
    let (ai, bi, aj, bj) = (ai * inv, bi * inv, aj * inv, bj * inv);
    // j's centre in i's frame (scaled).
    let u = [(ci * dv.x + si * dv.y) * inv, (ci * dv.y - si * dv.x) * inv];
    let inv_i = [1.0 / (ai * ai), 1.0 / (bi * bi)];
    let inv_j = [1.0 / (aj * aj), 1.0 / (bj * bj)];
    // P(7) in i's own frame (θ = 0: the diagonal form) and j's at the angle φ.
    let form_i = EllipseForm::from_inverse_squares(inv_i[0], inv_i[1], 1.0, 0.0);
    let form_j = EllipseForm::from_inverse_squares(inv_j[0], inv_j[1], cphi, sphi);
    // The guess is kept unscaled in this frame: scaling by a power of two is exact.
    let start = guess.map(|q| [q[0] * inv, q[1] * inv]);
    let [p, q] = newton_crossings(&form_i, &form_j, u, start)?;
    let (ex, ey) = (q[0] - p[0], q[1] - p[1]);
    // The depth along ±n, n = m/|m| with m = (−e_y, e_x) ⊥ the chord: the centred supports
    // (both ellipses symmetric) minus n·u. Supports are positively homogeneous, so they are
    // taken along m and the sum divided by |m|: the three square roots do not wait on one
    // another.
    let m = [-ey, ex];
    let len = (ex * ex + ey * ey).sqrt(); // order one: no `hypot` needed
    let inv_len = 1.0 / len;
    let supports = support(ai, bi, 1.0, 0.0, m[0], m[1]) + support(aj, bj, cphi, sphi, m[0], m[1]);
    let (m, dpt_m) = orient_symmetric(m, supports, m[0] * u[0] + m[1] * u[1]);
    let (n, dpt) = ([m[0] * inv_len, m[1] * inv_len], dpt_m * inv_len);
    if !(dpt > TOUCH_TOL && dpt <= WARM_MAX_DEPTH * bi.min(bj)) {
        return None;
    }
    let frame = LocalFrame {
        origin: pi.position,
        cos: ci,
        sin: si,
        scale,
    };
    let mid = super::local::midpoint(p, q);
    // (The half-chord, when asked for, from the length at hand rather than `hypot`: lengths here
    // are of order one.)
    let lean = Request {
        chord: false,
        ..*request
    };
    let mut c = frame.contact(ContactState::Overlap, p, q, mid, n, dpt, &lean);
    if request.chord {
        c.half_chord = 0.5 * len * scale;
    }
    if request.area {
        // The caps of i and j beyond the chord. Both are minor, with the chord's images on the
        // unit disks of both well short of a diameter: a cap's height along n is at most the
        // depth δ ≤ WARM_MAX_DEPTH·b, and its image's at most δ/b ≤ 0.05 of the unit radius.
        // The chord's image on each: e in each body's axes, scaled by 1/a, 1/b.
        let ej = [cphi * ex + sphi * ey, -sphi * ex + cphi * ey];
        let l2 = [
            ex * ex * inv_i[0] + ey * ey * inv_i[1],
            ej[0] * ej[0] * inv_j[0] + ej[1] * ej[1] * inv_j[1],
        ];
        let area = minor_caps_sum([ai * bi, aj * bj], l2);
        let o = LocalOverlap::chord_of_length(area, p, q, n, len);
        c.area = Some(frame.overlap(&o));
    }
    let unscaled = |p: [f64; 2]| [p[0] * scale, p[1] * scale];
    Some((c, Warm::Crossings([unscaled(p), unscaled(q)])))
}

/// `1/x` for a power of two `x` (as [`pow2_floor`] gives), exactly, without a division.
#[inline(always)]
fn pow2_recip(x: f64) -> f64 {
    let e = (x.to_bits() >> 52) & 0x7FF;
    if (1..=2045).contains(&e) {
        f64::from_bits((2046 - e) << 52) // 2^(e − 1023) → 2^(1023 − e)
    } else {
        1.0 / x
    }
}

/// The contact of two conics (ellipses; a circle is `a = b = r`) by the pencil, with a warm
/// start: ellipse–ellipse and circle–ellipse (the circle as i). `guess` is last step's [`Warm`]
/// (None for a new contact); `request` says whether to give the overlap area and its gradient,
/// and the chord. Returns the contact (`None`: apart) and leaves in `next` what the next step
/// starts from (a two-crossing overlap's crossings, or a separating axis); records in
/// `request.trace` whether the result came from the warm start (the refined crossings, or the
/// carried separating axis) rather than from the pencil — for the tests that hold the warm path
/// to the same bars as the pencil.
///
/// Always inlined (its cold half, the pencil, is [`conic_pair_inner`]): the caller's request
/// is then a constant, and the warm path builds its record in the caller's (the 10⁴-ellipse
/// pile under the area law: 4412 → 4360 instructions per body-step, callgrind's count of
/// `World::step` over 10 steps).
#[allow(clippy::too_many_arguments)] // the two ellipses, the guess, the next one and the request
#[inline(always)]
pub(crate) fn conic_pair(
    ai: f64,
    bi: f64,
    pi: &Pose,
    aj: f64,
    bj: f64,
    pj: &Pose,
    guess: Option<Warm>,
    next: &mut Option<Warm>,
    request: &Request,
) -> Option<Contact> {
    // Bounding circles first, here where it inlines: separated pairs cost a few ns.
    let dv = pj.position - pi.position;
    let (ri, rj) = (ai.max(bi), aj.max(bj));
    if dv.norm_squared() > (ri + rj) * (ri + rj) {
        *next = None;
        return None;
    }
    // A lasting contact's warm path, here too: the dynamics' common case then inlines into its
    // caller, and its record is built in place rather than returned through another call.
    if let Some(Warm::Crossings(g)) = guess {
        let scale = pow2_floor(ri.max(rj));
        if let Some((c, w)) = warm_crossings((ai, bi, aj, bj), pi, pj, dv, scale, g, request) {
            *next = Some(w);
            if let Some(t) = request.trace {
                t.set(true);
            }
            return Some(c);
        }
    }
    conic_pair_inner(ai, bi, pi, aj, bj, pj, guess, next, *request)
}

#[allow(clippy::too_many_arguments)] // the two ellipses, the guess, the next one and the request
fn conic_pair_inner(
    ai: f64,
    bi: f64,
    pi: &Pose,
    aj: f64,
    bj: f64,
    pj: &Pose,
    guess: Option<Warm>,
    next: &mut Option<Warm>,
    request: Request,
) -> Option<Contact> {
    let request = &request;
    let dv = pj.position - pi.position;
    let (ri, rj) = (ai.max(bi), aj.max(bj));
    let (ci, si) = pi.cos_sin();
    let (cj, sj) = pj.cos_sin();
    // Relative angle φ from i's a axis to j's a axis (frame independent).
    let (cphi, sphi) = (cj * ci + sj * si, sj * ci - cj * si);
    let scale = pow2_floor(ri.max(rj));
    let inv = pow2_recip(scale);
    // (A lasting contact's warm path was tried by [`conic_pair`].)
    let d = dv.norm();
    if d > ri + rj {
        *next = None;
        return None; // bounding circles
    }
    // P's local frame: x axis from O_i through O_j (α of Fig. 1); any axis when concentric.
    let (ca, sa) = if d > 0.0 {
        (dv.x / d, dv.y / d)
    } else {
        (1.0, 0.0)
    };
    // θ_n = (body angle) − α, by the angle-difference formulas.
    let (cti, sti) = (ci * ca + si * sa, si * ca - ci * sa);
    let (ctj, stj) = (cj * ca + sj * sa, sj * ca - cj * sa);
    // Separating axis along the line of centres (not for a lasting contact: it overlapped a
    // step ago, so this test would almost surely fail).
    let lasting = matches!(guess, Some(Warm::Crossings(_)));
    if !lasting && support(ai, bi, cti, sti, 1.0, 0.0) + support(aj, bj, ctj, stj, 1.0, 0.0) < d {
        *next = None;
        return None;
    }
    let (ai, bi, aj, bj, d) = (ai * inv, bi * inv, aj * inv, bj * inv, d * inv);
    let frame = LocalFrame {
        origin: pi.position,
        cos: ca,
        sin: sa,
        scale,
    };

    let inv_i = [1.0 / (ai * ai), 1.0 / (bi * bi)];
    let inv_j = [1.0 / (aj * aj), 1.0 / (bj * bj)];
    let form_i = EllipseForm::from_inverse_squares(inv_i[0], inv_i[1], cti, sti); // P(5), P(7)
    let form_j = EllipseForm::from_inverse_squares(inv_j[0], inv_j[1], ctj, stj); // P(6), P(7)
    // Sum of the centred supports along n (both ellipses are symmetric, so the same along −n);
    // the depth along n (i → j) is that minus n·d.
    let supports =
        |n: [f64; 2]| support(ai, bi, cti, sti, n[0], n[1]) + support(aj, bj, ctj, stj, n[0], n[1]);
    let depth = |n: [f64; 2]| supports(n) - n[0] * d;
    let oriented = |n: [f64; 2]| orient_symmetric(n, supports(n), n[0] * d);
    // Body i's frame ↔ this frame: a rotation by θ_i − α (cos `cti`, sin `sti`) and the scale.
    let to_warm = |p: [f64; 2]| -> [f64; 2] {
        [
            (cti * p[0] + sti * p[1]) * scale,
            (-sti * p[0] + cti * p[1]) * scale,
        ]
    };
    let tol = TOUCH_TOL;
    let placed_i = Placed::at(ai, bi, inv_i, (cti, sti), [0.0, 0.0]);
    let placed_j = Placed::at(aj, bj, inv_j, (ctj, stj), [d, 0.0]);

    // A separated pair's warm path (see the module documentation): its separating axis
    // confirmed or turned until it separates. (A lasting contact's was tried above.)
    if !lasting {
        // From last step's axis, a full search; from the line of centres (already tested
        // above), a short one: a cold overlapping pair should not pay much before the pencil.
        let (start, iterations) = match guess {
            Some(Warm::Axis(a)) => (a, 8),
            None | Some(Warm::Crossings(_)) => ([1.0, 0.0], 3),
        };
        let (ei, ej) = ((ai, bi, cti, sti), (aj, bj, ctj, stj));
        if let Some(axis) = separating_axis(ei, ej, d, start, tol, iterations) {
            if let Some(t) = request.trace {
                t.set(matches!(guess, Some(Warm::Axis(_))));
            }
            *next = Some(Warm::Axis(axis));
            return None;
        }
    }

    let mut crossings = [[0.0f64; 2]; 4];
    let mut n_cross = 0;
    let mut chord: Option<LineCut> = None;
    // A line whose half-chord is within rounding of zero nearly touches both ellipses at one
    // point. Its half-length cannot tell a tiny overlap from a tiny gap where the curvature is
    // high (half² ≈ 2Rδ, R = b²/a at the tip of a thin ellipse), but its direction is accurate
    // and the depth along it is first-order insensitive to that direction: decide by δ(n).
    let mut near_tangent: Option<LineCut> = None;
    let mut coincident = false;
    if d == 0.0 {
        // One centre: no pencil needed (and its cubic has a double or triple root here). The
        // boundaries cross where the forms agree, on the lines xᵀ(Q_j − Q_i)x = 0, real when
        // Q_j − Q_i is indefinite (four crossings); otherwise one ellipse lies in the other,
        // or they are the same curve.
        match concentric_crossings(&form_i, &form_j) {
            Some(points) => {
                crossings = points;
                n_cross = 4;
            }
            None => coincident = true, // nested or coincident: the containment test below
        }
    } else {
        let pencil = Pencil {
            i: form_i,
            j: form_j,
            d,
            x_mixed: mixed_invariant_from_inverse_squares(inv_i, inv_j, cphi, sphi),
        };
        let [t1, t2, t3, t4] = pencil.cubic(); // P(10)
        // Every real root is tried in turn. When the cubic certainly has a single real root (every
        // two-crossing overlap) the fast solver finds it and there is nothing else to try; otherwise
        // the robust solver gives them all.
        let single = one_real_root(t1, t2, t3, t4);
        let all;
        let roots: &[f64] = match &single {
            Some(lambda) => std::slice::from_ref(lambda),
            None => {
                all = solve_cubic(t1, t2, t3, t4);
                all.as_slice()
            }
        };

        let reach = ri * inv * (1.0 + 1e-9);
        for &lambda in roots {
            let member = pencil.member(lambda);
            let Some(lines) = split_degenerate(&member) else {
                // Imaginary lines (a point-ellipse member) — or no member at all: f + λg ≡ 0 means
                // the two conics are one and the same curve.
                let size = [member.a, member.h, member.b, member.g, member.f, member.c]
                    .iter()
                    .fold(0.0f64, |m, v| m.max(v.abs()));
                coincident |= size <= 1e-12 * (pencil.i.a_coef + pencil.i.c_coef);
                continue;
            };
            let mut found = 0;
            let distinct = if lines[0] == lines[1] { 1 } else { 2 }; // a double line counts once
            for line in &lines[..distinct] {
                let Some(cut) = cut_line(&pencil.i, line, reach) else {
                    continue;
                };
                if cut.half_sq > cut.half_sq_err {
                    let [p, q] = cut.points();
                    crossings[found] = p;
                    crossings[found + 1] = q;
                    found += 2;
                    chord = Some(cut);
                    if single.is_some() {
                        break; // one real root: two crossings at most, and here they are
                    }
                } else if cut.half_sq >= -NEAR_TANGENT.max(cut.half_sq_err)
                    && near_tangent.is_none()
                {
                    near_tangent = Some(cut);
                }
            }
            if found > 0 {
                n_cross = found;
                break;
            }
        }
    }

    // The depth along a direction is exact to rounding (support functions), while a chord line
    // carries the rounding of λ and of the splitting: the depth's sign has the last word. A
    // negative depth along any direction proves separation (a separating axis).
    let candidate = match (n_cross, chord) {
        (2, Some(cut)) => Some(cut),
        (4, _) => {
            let (p, q, n, dpt) = deep_fallback(&mut crossings, depth);
            if dpt > tol {
                let mid = super::local::midpoint(p, q);
                let mut c = frame.contact(ContactState::Deep, p, q, mid, n, dpt, request);
                if request.area {
                    let placed = [placed_i, placed_j];
                    let o = deep_overlap(
                        &crossings,
                        [d, 0.0],
                        |k, u, m| placed[k].height(u, m),
                        |k, p, q, u| placed[k].cap(p, [q[0] - p[0], q[1] - p[1]], u),
                    );
                    c.area = Some(frame.overlap(&o));
                }
                *next = None;
                return Some(c);
            }
            None
        }
        _ => near_tangent,
    };
    if let Some(cut) = candidate {
        let (n, dpt) = oriented(cut.normal);
        // A nearly tangent line with no crossing found is an external tangency (a tiny lens, or
        // a tiny gap) only if, along its normal, neither ellipse's extent lies within the
        // other's: the depth is then below the smaller width `2 s(n)`. One inside the other, a
        // line of the pencil can still pass within rounding of tangency to i (near where j
        // almost touches i from inside) and the depth along it is large and positive: that is
        // nesting, decided below, not an overlap with a zero-length chord.
        let nested = n_cross == 0 && {
            let s_min = placed_i.support(n).min(placed_j.support(n));
            dpt >= 2.0 * s_min - tol
        };
        if nested {
            // Fall through to the containment test.
        } else if dpt >= -tol {
            let [p, q] = cut.points();
            let state = if dpt <= tol {
                ContactState::Touching
            } else {
                ContactState::Overlap
            };
            let warm = (state == ContactState::Overlap && n_cross == 2)
                .then(|| Warm::Crossings([to_warm(p), to_warm(q)]));
            let mut c = frame.contact(state, p, q, cut.mid, n, dpt, request);
            if request.area && state == ContactState::Overlap {
                // The caps follow the crossings to first order (A changes by L × their shift), and
                // the pencil's crossings carry the rounding of λ and of the splitting (up to
                // ~1e-13 of the size, more in one order of the pair than in the other): polished
                // by Newton's method on both boundaries, as the warm path does, they are accurate
                // to ε/sin(crossing angle). Grazing crossings, where Newton is ill-conditioned,
                // keep the pencil's, with the chord vector from the half-length rather than from
                // two rounded end points.
                let (p0, e) = match newton_crossings(&form_i, &form_j, [d, 0.0], [p, q]) {
                    Some([a, b]) => (a, [b[0] - a[0], b[1] - a[1]]),
                    None => {
                        let s = 2.0 * cut.half_sq.max(0.0).sqrt();
                        (p, [s * cut.dir[0], s * cut.dir[1]])
                    }
                };
                let o = chord_overlap(&placed_i, &placed_j, p0, e, n);
                c.area = Some(frame.overlap(&o));
            }
            *next = warm;
            return Some(c);
        } else {
            *next = None;
            return None;
        }
    }
    // No crossing: nested or apart. With no crossing, the two solids meet only if one lies
    // inside the other, and then the inner one's centre lies inside the outer one — by at
    // least the inner one's smaller semi-axis, so the test is robust where a boundary point of
    // the inner one (which may touch the outer boundary) would not be. The inner one is the
    // smaller in area.
    let nested = coincident
        || form_i.quad(d, 0.0) < 1.0 // c_j in i
        || form_j.quad(-d, 0.0) < 1.0; // c_i in j
    if !nested {
        *next = None;
        return None;
    }
    let (n, dpt) = oriented([1.0, 0.0]);
    let inner = if aj * bj <= ai * bi {
        [d, 0.0]
    } else {
        [0.0, 0.0]
    };
    *next = None;
    Some(frame.contact(
        ContactState::Contained,
        inner,
        inner,
        inner,
        n,
        dpt,
        request,
    ))
}

/// The crossings of two ellipses with one centre (the origin), given by their forms in one
/// frame: the four points where the lines `xᵀ(Q_j − Q_i)x = 0` meet ellipse i, when
/// `Q_j − Q_i` is indefinite; `None` when it is semi-definite (one inside the other, touching
/// from inside at most) or zero to rounding (one and the same ellipse).
fn concentric_crossings(fi: &EllipseForm, fj: &EllipseForm) -> Option<[[f64; 2]; 4]> {
    let m = [
        fj.a_coef - fi.a_coef,
        fj.b_coef - fi.b_coef,
        fj.c_coef - fi.c_coef,
    ];
    let size = fi.a_coef.max(fi.c_coef).max(fj.a_coef).max(fj.c_coef);
    if m.iter().all(|v| v.abs() <= 8.0 * f64::EPSILON * size) {
        return None; // the same ellipse, to the rounding of the forms
    }
    let neg_det = m[1] * m[1] - m[0] * m[2];
    if neg_det <= 0.0 {
        return None;
    }
    // The two directions (x, y) with m0 x² + 2 m1 xy + m2 y² = 0, by the stable quadratic
    // formula in the ratio of the smaller coefficient's variable.
    let root = neg_det.sqrt();
    let q = -(m[1] + root.copysign(m[1]));
    let dirs = if m[0].abs() >= m[2].abs() {
        // x/y = q/m0 or m2/q.
        [[q / m[0], 1.0], [m[2] / q, 1.0]]
    } else {
        // y/x = q/m2 or m0/q.
        [[1.0, q / m[2]], [1.0, m[0] / q]]
    };
    let mut out = [[0.0; 2]; 4];
    for (k, u) in dirs.iter().enumerate() {
        let t = 1.0 / fi.quad(u[0], u[1]).sqrt();
        out[2 * k] = [t * u[0], t * u[1]];
        out[2 * k + 1] = [-t * u[0], -t * u[1]];
    }
    Some(out)
}

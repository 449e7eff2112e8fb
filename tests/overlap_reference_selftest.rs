//! Self-tests of the double-double elementary functions (`validation::dd`) and of the
//! overlap-area reference (`validation::overlap_reference`), each against something
//! independent of the code under test:
//!
//! * DD functions: values computed with mpmath at 300 bits (constants below), identities
//!   (`sin² + cos² = 1`, `atan2(sin x, cos x) = x`, Machin's formula, `sin(π/6) = 1/2`, …);
//! * areas: closed forms evaluated in DD (circular lens, circular and elliptic segments,
//!   hand-clipped polygons), an `f64` polygon clipper, and an `f64` quadrature of the
//!   vertical extent of the intersection (a completely different method).

use dem2d_validation::dd::DD;
use dem2d_validation::overlap_reference::{OverlapState, Side, reference_overlap};
use dem2d_validation::reference::{RObj, RShape};
use dem2d_validation::rng::Rng;

/// `|got − want|`, as an `f64`.
fn err(got: DD, want: DD) -> f64 {
    (got - want).abs().to_f64()
}

fn dd(hi: f64, lo: f64) -> DD {
    DD::new(hi, lo)
}

// ---------------------------------------------------------------------------
// DD elementary functions
// ---------------------------------------------------------------------------

/// Values from mpmath (300-bit), rounded to DD: `(argument, (hi, lo))`.
#[test]
fn dd_trig_against_mpmath() {
    // Tolerance 1e-31 absolute on values of order 1: two to three units of DD::EPS
    // (4.9e-32) plus the rounding of the mpmath value to DD (≤ 1 EPS/2).
    let tol = 1e-31;
    let mut worst = 0.0f64;
    let sins = [
        (1.0, dd(0.8414709848078965, 1.776845092935536e-18)),
        (10.0, dd(-0.5440211108893698, -3.8949898668223557e-17)),
        (0.5, dd(0.479425538604203, -5.103969860556013e-18)),
        (0.1, dd(0.09983341664682815, 3.08001512929492e-18)),
    ];
    for (x, want) in sins {
        let e = err(DD::from(x).sin(), want);
        worst = worst.max(e);
        assert!(e < tol, "sin({x}): error {e:e}");
    }
    let coss = [
        (1.0, dd(0.5403023058681398, -4.760954612604417e-17)),
        (-7.0, dd(0.7539022543433046, 3.728245359710072e-17)),
    ];
    for (x, want) in coss {
        let e = err(DD::from(x).cos(), want);
        worst = worst.max(e);
        assert!(e < tol, "cos({x}): error {e:e}");
    }
    let checks = [
        (
            "atan(0.3)",
            DD::from(0.3).atan(),
            dd(0.2914567944778671, -1.6448555435075034e-17),
        ),
        (
            "atan2(-2.5, -1.7)",
            DD::from(-2.5).atan2(DD::from(-1.7)),
            dd(-2.167972984887574, -2.0489901029157467e-16),
        ),
        (
            "asin(0.9)",
            DD::from(0.9).asin(),
            dd(1.1197695149986342, 4.092642558112641e-17),
        ),
        (
            "acos(-0.3)",
            DD::from(-0.3).acos(),
            dd(1.8754889808102941, -2.1748551325047183e-17),
        ),
        (
            "0.7 - sin(0.7)",
            DD::from(0.7).x_minus_sin(),
            dd(0.05578231276230894, -2.8740567927338755e-18),
        ),
        (
            "(1 − 2^-53) − sin(1 − 2^-53) (series branch)",
            DD::from(0.9999999999999999).x_minus_sin(),
            dd(0.15852901519210344, 2.6976096990938964e-18),
        ),
        (
            "1 − sin(1) (difference branch)",
            DD::ONE.x_minus_sin(),
            dd(0.1585290151921035, -1.776845092935536e-18),
        ),
        (
            "-2.5 - sin(-2.5)",
            DD::from(-2.5).x_minus_sin(),
            dd(-1.9015278558960436, 5.580826912169191e-17),
        ),
        (
            "3 - sin(3)",
            DD::from(3.0).x_minus_sin(),
            dd(2.8588799919401326, 1.3020060829112707e-16),
        ),
    ];
    for (what, got, want) in checks {
        let e = err(got, want);
        worst = worst.max(e);
        assert!(e < tol, "{what}: error {e:e}");
    }
    eprintln!("DD functions vs mpmath: worst absolute error {worst:e}");
    // Small argument: relative accuracy (x − sin x ≈ 1.7e-10 here).
    let got = DD::from(1e-3).x_minus_sin();
    let want = dd(1.6666665833333355e-10, -5.6979554413661525e-27);
    let rel = err(got, want) / want.to_f64();
    assert!(rel < 1e-30, "1e-3 - sin(1e-3): relative error {rel:e}");
}

#[test]
fn dd_trig_identities() {
    let pi = DD::PI;
    // Exact special values.
    let cases = [
        ("sin(π/6)", (pi / 6.0).sin(), DD::from(0.5)),
        ("cos(π/3)", (pi / 3.0).cos(), DD::from(0.5)),
        ("sin(π/4)", (pi / 4.0).sin(), DD::from(0.5).sqrt()),
        ("cos(-3π/4)", (pi * -0.75).cos(), -DD::from(0.5).sqrt()),
        ("sin(5π/6)", (pi * 5.0 / 6.0).sin(), DD::from(0.5)),
        ("sin(π/2)", DD::FRAC_PI_2.sin(), DD::ONE),
        ("cos(π)", pi.cos(), -DD::ONE),
        ("sin(π)", pi.sin(), DD::ZERO),
        ("4 atan(1)", DD::ONE.atan() * 4.0, pi),
        (
            "atan2(1, √3)·6",
            DD::ONE.atan2(DD::from(3.0).sqrt()) * 6.0,
            pi,
        ),
        ("asin(1/2)·6", DD::from(0.5).asin() * 6.0, pi),
        ("acos(-1)", DD::from(-1.0).acos(), pi),
        ("acos(1)", DD::ONE.acos(), DD::ZERO),
        ("asin(-1)", DD::from(-1.0).asin(), -DD::FRAC_PI_2),
        ("atan2(0, -1)", DD::ZERO.atan2(-DD::ONE), pi),
        ("atan2(-1, 0)", (-DD::ONE).atan2(DD::ZERO), -DD::FRAC_PI_2),
        // Machin: π/4 = 4 atan(1/5) − atan(1/239).
        (
            "Machin",
            ((DD::ONE / 5.0).atan() * 4.0 - (DD::ONE / 239.0).atan()) * 4.0,
            pi,
        ),
        ("τ", DD::TAU, pi * 2.0),
        ("π/2", DD::FRAC_PI_2 * 2.0, pi),
    ];
    // 2e-31: a few EPS on values ≤ π (the special arguments are themselves DD-rounded,
    // e.g. π/6, and the error of π/6 propagates with slope ≤ 1).
    let mut worst_special = 0.0f64;
    for (what, got, want) in cases {
        let e = err(got, want);
        worst_special = worst_special.max(e);
        assert!(e < 2e-31, "{what}: error {e:e}");
    }
    eprintln!("DD special values: worst absolute error {worst_special:e}");

    // sin² + cos² = 1, double angle, atan2 round trip, symmetry, on a spread of arguments
    // (including the range the overlap reference uses, [−2π, 4π]).
    let mut worst = [0.0f64; 5];
    for k in -400..=800 {
        let x = DD::from(k as f64 * 0.0157) + 1e-18 * k as f64;
        let (s, c) = x.sin_cos();
        worst[0] = worst[0].max(err(s.sqr() + c.sqr(), DD::ONE));
        let (s2, _) = (x * 2.0).sin_cos();
        worst[1] = worst[1].max(err(s2, s * c * 2.0));
        // atan2 returns (−π, π]: compare modulo 2π.
        let back = s.atan2(c);
        let turns = ((x - back) / DD::TAU).to_f64().round();
        worst[2] = worst[2].max(err(back + DD::TAU * turns, x));
        worst[3] = worst[3].max(err((-x).sin(), -s).max(err((-x).cos(), c)));
        worst[4] = worst[4].max(err((pi - x).sin(), s));
        // Scaling the point does not change the angle.
        assert!(err((s * 3.7).atan2(c * 3.7), back) < 4e-31, "k = {k}");
    }
    // sin²+cos² and the double angle: a few EPS; atan2 round trip: a few EPS times |x| ≤ 4π;
    // sin(π − x): the reduction of π − x is exact only to the DD rounding of π − x.
    eprintln!(
        "DD identities (sin²+cos², double angle, atan2 round trip, odd/even, sin(π−x)): {worst:?}"
    );
    let tols = [2e-31, 3e-31, 1e-30, 0.0, 1e-30];
    for (w, t) in worst.iter().zip(tols) {
        assert!(*w <= t, "identities: worst errors {worst:?}");
    }

    // Small arguments: sin x = x − x³/6 + x⁵/120 (next term ~1e-61 for x = 1e-10).
    let x = DD::from(1e-10);
    let series = x - x * x * x / 6.0;
    assert!(err(x.sin(), series) < 1e-40);
    assert!(err(x.cos(), DD::ONE - x * x / 2.0) < 1e-40);
    assert!(err(x.atan(), x - x * x * x / 3.0) < 1e-40);
    assert!(err(x.asin(), x + x * x * x / 6.0) < 1e-40);
    // x − sin x = x³/6 (1 − x²/20 + …): relative difference 5e-22 from the next term.
    let cube = x * x * x / 6.0;
    assert!(err(x.x_minus_sin(), cube) / cube.to_f64() < 1e-21);
    assert_eq!((-x).x_minus_sin(), -x.x_minus_sin());
}

// ---------------------------------------------------------------------------
// Overlap area: helpers
// ---------------------------------------------------------------------------

fn body(shape: RShape, pos: [f64; 2], angle: f64) -> RObj {
    RObj::Body { shape, pos, angle }
}

fn circle(r: f64, pos: [f64; 2]) -> RObj {
    body(RShape::Circle { r }, pos, 0.0)
}

fn ellipse(a: f64, b: f64, pos: [f64; 2], angle: f64) -> RObj {
    body(RShape::Ellipse { a, b }, pos, angle)
}

fn rect(w: f64, h: f64, pos: [f64; 2], angle: f64) -> RObj {
    body(RShape::Rectangle { w, h }, pos, angle)
}

fn wall(point: [f64; 2], normal: [f64; 2]) -> RObj {
    RObj::Wall { point, normal }
}

/// Body axes as the reference takes them: `f64` cos/sin, renormalised in DD.
fn axes(angle: f64) -> ([DD; 2], [DD; 2]) {
    let (c, s) = (DD::from(angle.cos()), DD::from(angle.sin()));
    let k = (c * c + s * s).sqrt();
    let (c, s) = (c / k, s / k);
    ([c, s], [-s, c])
}

fn dotd(a: [DD; 2], b: [DD; 2]) -> DD {
    a[0] * b[0] + a[1] * b[1]
}

/// `|got − want| / |want|` in DD, as an `f64`.
fn rel(got: DD, want: DD) -> f64 {
    err(got, want) / want.abs().to_f64()
}

/// Area of a circular segment of radius `r` and sagitta `h ∈ [0, 2r]`, in DD without
/// cancellation: half-angle `α = acos(1 − h/r) = 2 asin(√(h/2r))`, area `½r²(2α − sin 2α)`.
fn circular_segment(r: DD, h: DD) -> DD {
    let alpha = (h / (r * 2.0)).sqrt().asin() * 2.0;
    (r.sqr() * (alpha * 2.0).x_minus_sin()).mul_pow2(0.5)
}

#[track_caller]
fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got:e}, want {want:e} (diff {:e} > tol {tol:e})",
        (got - want).abs()
    );
}

// ---------------------------------------------------------------------------
// Circles: the lens in closed form
// ---------------------------------------------------------------------------

/// Two circles, `j` at distance `dist` from `ci` in direction `phi`: the lens area in closed
/// form (two circular segments with sagittas `h_i = δ(r_j + d − r_i)/2d`, `h_j` alike, from the
/// exact `δ = r_i + r_j − d`), the caps and crossings of the two pieces. Returns the relative
/// error of the area (0 if the closed form is 0).
fn check_lens(ri: f64, rj: f64, ci: [f64; 2], phi: f64, dist: f64) -> f64 {
    let cj = [ci[0] + dist * phi.cos(), ci[1] + dist * phi.sin()];
    let (i, j) = (circle(ri, ci), circle(rj, cj));
    let o = reference_overlap(&i, &j);
    let (dx, dy) = (DD::from(cj[0]) - ci[0], DD::from(cj[1]) - ci[1]);
    let d = (dx * dx + dy * dy).sqrt();
    let (rid, rjd) = (DD::from(ri), DD::from(rj));
    // δ = r_i + r_j − d without cancellation: ((r_i + r_j)² − dx² − dy²) / (r_i + r_j + d),
    // exact up to DD rounding of the result since dx, dy are exact f64 differences here.
    assert!(
        dx.lo == 0.0 && dy.lo == 0.0,
        "centre offsets must be exact f64"
    );
    let sum = rid + rj;
    let delta = (sum.sqr() - dx.sqr() - dy.sqr()) / (sum + d);
    assert_eq!(o.origin, ci);
    if d.is_zero() && ri == rj {
        assert_eq!(o.state, OverlapState::Coincident);
        let e = rel(o.area_dd, DD::PI * ri * ri);
        assert!(e < 1e-31, "coincident: {e:e}");
        return e;
    }
    if d <= (rid - rj).abs() {
        let small = if ri < rj { Side::I } else { Side::J };
        assert_eq!(o.state, OverlapState::Contained(small), "d = {d:?}");
        let want = DD::PI * ri.min(rj) * ri.min(rj);
        let e = rel(o.area_dd, want);
        assert!(e < 1e-31, "contained: {e:e}");
        return e;
    }
    if delta <= 0.0 {
        assert_eq!(o.state, OverlapState::Separated, "d = {d:?}");
        assert_eq!(o.area, 0.0);
        return 0.0;
    }
    assert_eq!(o.state, OverlapState::Overlap, "d = {d:?}");
    let hi = delta * (rjd + d - ri) / (d * 2.0);
    let hj = delta * (rid + d - rj) / (d * 2.0);
    let (seg_i, seg_j) = (circular_segment(rid, hi), circular_segment(rjd, hj));
    let want = seg_i + seg_j;
    let e = rel(o.area_dd, want);
    // Pieces: i's (inside j) first, then j's; caps are the two segments.
    assert_eq!(o.pieces.len(), 2);
    assert_eq!(o.pieces[0].owner, Side::I);
    assert_eq!(o.pieces[1].owner, Side::J);
    assert_close(
        "cap i",
        o.pieces[0].cap,
        seg_i.to_f64(),
        1e-15 * seg_i.to_f64(),
    );
    assert_close(
        "cap j",
        o.pieces[1].cap,
        seg_j.to_f64(),
        1e-15 * seg_j.to_f64(),
    );
    // Crossings: i's piece runs counter-clockwise about i, from d_i u − c u⊥ to d_i u + c u⊥.
    let (ux, uy) = (dx / d, dy / d);
    let di = rid - hi;
    let c = (hi * (rid * 2.0 - hi)).sqrt();
    let start = [(ux * di + uy * c).to_f64(), (uy * di - ux * c).to_f64()];
    let end = [(ux * di - uy * c).to_f64(), (uy * di + ux * c).to_f64()];
    let tol = 1e-15 * ri.max(rj);
    for (got, want) in [(o.pieces[0].start, start), (o.pieces[0].end, end)] {
        assert_close("crossing x", got[0], want[0], tol);
        assert_close("crossing y", got[1], want[1], tol);
    }
    assert_eq!(o.pieces[1].start, o.pieces[0].end);
    assert_eq!(o.pieces[1].end, o.pieces[0].start);
    assert_eq!(o.crossings, vec![o.pieces[0].start, o.pieces[1].start]);
    e
}

/// Lens areas over radii ratios, directions, positions (also 1e6 from the origin) and
/// overlaps from deep to δ/d = 1e-12, against the closed form in DD.
#[test]
fn lens_area_closed_form() {
    let mut worst = 0.0f64;
    let mut worst_tiny = 0.0f64; // relative error / (EPS·r/δ)
    for (ri, rj) in [(1.0f64, 1.0f64), (1.0, 0.25), (0.3, 2.0), (300.0, 500.0)] {
        let sum = ri + rj;
        for &ci in &[[0.0, 0.0], [1e6 + 0.25, -3e6 + 0.125]] {
            for (k, phi) in [0.0, 0.7, 2.5, -1.9].into_iter().enumerate() {
                for f in [0.0, 0.1, 0.5, 0.9, 0.999, 1.3] {
                    // f < 0.6 is measured from |ri − rj| (deep, down to internal tangency).
                    let dist = if f < 0.6 {
                        (ri - rj).abs() + 0.5 * sum * f
                    } else {
                        sum * f
                    };
                    worst = worst.max(check_lens(ri, rj, ci, phi + 0.01 * k as f64, dist));
                }
                for f in [1e-6, 1e-9, 1e-12] {
                    let e = check_lens(ri, rj, ci, phi + 0.01 * k as f64, sum * (1.0 - f));
                    // δ ≈ f·(r_i + r_j): error in units of EPS·max(r)/δ.
                    worst_tiny = worst_tiny.max(e / (DD::EPS * ri.max(rj) / (f * sum)));
                }
            }
        }
    }
    eprintln!(
        "lens: worst relative area error {worst:e}; tiny overlaps (δ/r = 1e-6..1e-12): \
         {worst_tiny:.3} × EPS·r/δ"
    );
    // Generic overlaps (δ/r ≥ 1e-3): the crossings are simple roots (DD accuracy) and the caps
    // are evaluated without cancellation: relative error a few EPS · r/δ ≤ 1e-28.
    assert!(worst < 1e-28, "lens: worst relative error {worst:e}");
    // Tiny overlaps: the two crossing roots are close (angular separation s ~ √(δ/r)); an
    // error EPS·r in the implicit values moves them by ~EPS·r/s along the boundary, i.e. a
    // relative error ~EPS/s² = EPS·r/δ in the chord and ~3 EPS·r/δ in the area (∝ chord³).
    assert!(
        worst_tiny < 4.0,
        "lens, tiny overlaps: worst error {worst_tiny} × EPS·r/δ"
    );
}

/// The brief's tiny-overlap case on its own: δ/r = 1e-9 for a circle pair far from the origin.
#[test]
fn lens_tiny_overlap() {
    let (r, dist) = (1.0, 2.0 * (1.0 - 0.5e-9));
    let e = check_lens(r, r, [1e6 + 0.5, 2e6], 0.3, dist);
    eprintln!("lens δ/r = 1e-9: relative area error {e:e}");
    // Bound from the conditioning of the crossings (see `lens_area_closed_form`): a few
    // EPS·r/δ ≈ 5e-23 per unit; measured 3.6e-24.
    assert!(e < DD::EPS * 1e9, "tiny lens: relative error {e:e}");
}

// ---------------------------------------------------------------------------
// Walls against circles and ellipses: the elliptic segment in closed form
// ---------------------------------------------------------------------------

/// Area of `{x²/a² + y²/b² ≤ 1}` (body pose `pos`, `angle`) in the solid `n·(x − p) ≤ 0`:
/// with `x = c + a u₁ e1 + b u₂ e2` the condition is `m·u ≤ n·(p − c)`, `m = (a n·e1, b n·e2)`,
/// i.e. the unit disk cut at distance `D = n·(p − c)/|m|`: `ab · segment(1, 1 + D)`.
/// Returns `(area, 1 + D)`.
fn elliptic_segment_in_wall(
    a: f64,
    b: f64,
    pos: [f64; 2],
    angle: f64,
    point: [f64; 2],
    normal: [f64; 2],
) -> (DD, DD) {
    let (nx, ny) = (DD::from(normal[0]), DD::from(normal[1]));
    let k = (nx * nx + ny * ny).sqrt();
    let n = [nx / k, ny / k];
    let (e1, e2) = axes(angle);
    let m = ((dotd(n, e1) * a).sqr() + (dotd(n, e2) * b).sqr()).sqrt();
    let pc = [DD::from(point[0]) - pos[0], DD::from(point[1]) - pos[1]];
    let one_plus_d = (m + dotd(n, pc)) / m;
    let area = if one_plus_d <= 0.0 {
        DD::ZERO
    } else if one_plus_d >= 2.0 {
        DD::PI * a * b
    } else {
        circular_segment(DD::ONE, one_plus_d) * a * b
    };
    (area, one_plus_d)
}

#[test]
fn wall_circle_and_ellipse_segments() {
    let bodies = [
        (RShape::Circle { r: 0.5 }, [0.3, 0.2], 0.0f64),
        (RShape::Circle { r: 2.0 }, [1e6 + 0.3, -2e6], 0.4),
        (RShape::Ellipse { a: 1.5, b: 0.5 }, [1e6, 2e6], 0.7),
        (RShape::Ellipse { a: 0.4, b: 1.1 }, [-3.0, 5.0], -2.2),
        (RShape::Ellipse { a: 3.0, b: 0.01 }, [0.25, -0.5], 1.0),
    ];
    let normals: [[f64; 2]; 4] = [[0.0, 1.0], [1.0, 2.0], [-0.3, 1.0], [-1.0, -0.2]];
    let depths = [
        -1.5,
        -1.0 + 1e-9,
        -1.0 + 1e-5,
        -0.9,
        -0.3,
        0.0,
        0.5,
        0.99,
        1.0 - 1e-7,
        1.5,
    ];
    let (mut worst, mut states) = (0.0f64, [0usize; 3]);
    for (shape, pos, angle) in bodies {
        let (a, b) = match shape {
            RShape::Circle { r } => (r, r),
            RShape::Ellipse { a, b } => (a, b),
            RShape::Rectangle { .. } => unreachable!(),
        };
        for normal in normals {
            // Place the wall so that D ≈ the wanted value (the closed form uses the actual point).
            let len = normal[0].hypot(normal[1]);
            let (ca, sa) = (angle.cos(), angle.sin());
            let m = (a * (normal[0] * ca + normal[1] * sa) / len)
                .hypot(b * (-normal[0] * sa + normal[1] * ca) / len);
            for want_d in depths {
                let s = want_d * m / len;
                let point = [pos[0] + s * normal[0], pos[1] + s * normal[1]];
                let (want, one_plus_d) = elliptic_segment_in_wall(a, b, pos, angle, point, normal);
                let (bd, w) = (body(shape, pos, angle), wall(point, normal));
                for (first_is_wall, o) in [
                    (true, reference_overlap(&w, &bd)),
                    (false, reference_overlap(&bd, &w)),
                ] {
                    assert_eq!(o.origin, pos);
                    if one_plus_d <= 0.0 {
                        assert_eq!(o.state, OverlapState::Separated);
                        assert_eq!(o.area, 0.0);
                        states[0] += 1;
                        continue;
                    }
                    if one_plus_d >= 2.0 {
                        let body_side = if first_is_wall { Side::J } else { Side::I };
                        assert_eq!(o.state, OverlapState::Contained(body_side));
                        assert!(rel(o.area_dd, want) < 1e-31);
                        states[1] += 1;
                        continue;
                    }
                    states[2] += 1;
                    assert_eq!(o.state, OverlapState::Overlap, "D + 1 = {one_plus_d:?}");
                    // Relative error: the cut position D carries EPS-level errors, amplified
                    // by 1/(1 + D) for a thin segment (area ∝ (1 + D)^{3/2}).
                    let e = rel(o.area_dd, want);
                    let scale = 1.0 / one_plus_d.to_f64().min(2.0 - one_plus_d.to_f64());
                    worst = worst.max(e / (DD::EPS * scale));
                    assert!(
                        e < 1e-29 + 10.0 * DD::EPS * scale,
                        "{shape:?} n = {normal:?} D + 1 = {one_plus_d:?}: relative error {e:e}"
                    );
                    // Two pieces: the wall's (cap 0, along perp(n)) and the body's (cap = area).
                    assert_eq!(o.pieces.len(), 2);
                    let (wp, bp) = if first_is_wall {
                        (o.pieces[0], o.pieces[1])
                    } else {
                        (o.pieces[1], o.pieces[0])
                    };
                    assert_eq!(wp.cap, 0.0);
                    assert_eq!(bp.cap, o.area);
                    let t = [-normal[1], normal[0]];
                    let along = t[0] * (wp.end[0] - wp.start[0]) + t[1] * (wp.end[1] - wp.start[1]);
                    assert!(along > 0.0, "wall piece runs against perp(n)");
                    assert_eq!((wp.start, wp.end), (bp.end, bp.start));
                }
            }
        }
    }
    eprintln!(
        "wall–conic segments: worst error {worst:.3} × EPS/min(1 + D, 1 − D); states {states:?}"
    );
    assert!(states.iter().all(|&k| k > 0));
}

// ---------------------------------------------------------------------------
// Rectangles and walls: polygon areas
// ---------------------------------------------------------------------------

/// A closed half-plane `n·x ≤ k` in DD (coordinates relative to some origin).
type HalfPlane = ([DD; 2], DD);

/// Corners (counter-clockwise) of a rectangle body, relative to `origin`, in DD, with the
/// reference's axes convention.
fn rect_corners_dd(w: f64, h: f64, pos: [f64; 2], angle: f64, origin: [f64; 2]) -> Vec<[DD; 2]> {
    let (e1, e2) = axes(angle);
    let c = [DD::from(pos[0]) - origin[0], DD::from(pos[1]) - origin[1]];
    let (hw, hh) = (DD::from(w).mul_pow2(0.5), DD::from(h).mul_pow2(0.5));
    [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(sx, sy)| {
            [
                c[0] + e1[0] * hw * sx + e2[0] * hh * sy,
                c[1] + e1[1] * hw * sx + e2[1] * hh * sy,
            ]
        })
        .collect()
}

/// The half-planes whose intersection is the solid of a rectangle or a wall.
fn half_planes(o: &RObj, origin: [f64; 2]) -> Vec<HalfPlane> {
    match *o {
        RObj::Body {
            shape: RShape::Rectangle { w, h },
            pos,
            angle,
        } => {
            let (e1, e2) = axes(angle);
            let c = [DD::from(pos[0]) - origin[0], DD::from(pos[1]) - origin[1]];
            let (hw, hh) = (DD::from(w).mul_pow2(0.5), DD::from(h).mul_pow2(0.5));
            vec![
                (e1, dotd(e1, c) + hw),
                ([-e1[0], -e1[1]], hw - dotd(e1, c)),
                (e2, dotd(e2, c) + hh),
                ([-e2[0], -e2[1]], hh - dotd(e2, c)),
            ]
        }
        RObj::Wall { point, normal } => {
            let n = [DD::from(normal[0]), DD::from(normal[1])];
            let p = [
                DD::from(point[0]) - origin[0],
                DD::from(point[1]) - origin[1],
            ];
            vec![(n, dotd(n, p))]
        }
        RObj::Body { .. } => panic!("not a polygon"),
    }
}

/// Sutherland–Hodgman: the convex polygon `poly` clipped by the half-planes, in DD.
fn clip(mut poly: Vec<[DD; 2]>, planes: &[HalfPlane]) -> Vec<[DD; 2]> {
    for (n, k) in planes {
        let g = |p: &[DD; 2]| dotd(*n, *p) - *k;
        let mut out = Vec::new();
        for idx in 0..poly.len() {
            let (p, q) = (poly[idx], poly[(idx + 1) % poly.len()]);
            let (gp, gq) = (g(&p), g(&q));
            if gp <= 0.0 {
                out.push(p);
            }
            if (gp < 0.0 && gq > 0.0) || (gp > 0.0 && gq < 0.0) {
                let t = gp / (gp - gq);
                out.push([p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t]);
            }
        }
        poly = out;
        if poly.is_empty() {
            break;
        }
    }
    poly
}

/// Shoelace area of a polygon in DD (relative to its first vertex).
fn polygon_area(poly: &[[DD; 2]]) -> DD {
    if poly.len() < 3 {
        return DD::ZERO;
    }
    let p0 = poly[0];
    let twice: DD = poly[1..]
        .windows(2)
        .map(|w| {
            let (u, v) = (
                [w[0][0] - p0[0], w[0][1] - p0[1]],
                [w[1][0] - p0[0], w[1][1] - p0[1]],
            );
            u[0] * v[1] - u[1] * v[0]
        })
        .sum();
    twice.mul_pow2(0.5)
}

/// Overlap of a rectangle `j` with a rectangle or wall `i` by polygon clipping in DD.
fn clipped_area(i: &RObj, j: &RObj) -> DD {
    let RObj::Body {
        shape: RShape::Rectangle { w, h },
        pos,
        angle,
    } = *j
    else {
        panic!("j must be a rectangle")
    };
    polygon_area(&clip(
        rect_corners_dd(w, h, pos, angle, pos),
        &half_planes(i, pos),
    ))
}

/// Axis-aligned boxes (exact areas written down), shared edges, touching, contained,
/// coincident; a 45° wall across a unit square (through corners too); everything also
/// 1e6 from the origin.
#[test]
fn rectangles_exact_polygons() {
    for off in [[0.0, 0.0], [1e6, -2e6]] {
        let at = |x: f64, y: f64| [off[0] + x, off[1] + y];
        // (i, j, area, state)
        let cases = [
            // Corner region: x overlap 0.75, y overlap 1.
            (
                rect(2.0, 1.0, at(0.0, 0.0), 0.0),
                rect(1.0, 3.0, at(0.75, 0.5), 0.0),
                0.75,
                OverlapState::Overlap,
            ),
            // A plus: four crossings, the central unit square.
            (
                rect(4.0, 1.0, at(0.0, 0.0), 0.0),
                rect(1.0, 4.0, at(0.0, 0.0), 0.0),
                1.0,
                OverlapState::Deep(4),
            ),
            // Collinear bottom and top edges: [1, 2] × [0, 1].
            (
                rect(2.0, 1.0, at(1.0, 0.5), 0.0),
                rect(2.0, 1.0, at(2.0, 0.5), 0.0),
                1.0,
                OverlapState::Overlap,
            ),
            // Collinear bottom edges only: [1, 2] × [0, 1].
            (
                rect(2.0, 1.0, at(1.0, 0.5), 0.0),
                rect(2.0, 2.0, at(2.0, 1.0), 0.0),
                1.0,
                OverlapState::Overlap,
            ),
            // Touching along an edge, at a corner: no overlap.
            (
                rect(2.0, 1.0, at(1.0, 0.5), 0.0),
                rect(1.0, 1.0, at(2.5, 0.5), 0.0),
                0.0,
                OverlapState::Separated,
            ),
            (
                rect(2.0, 1.0, at(1.0, 0.5), 0.0),
                rect(1.0, 1.0, at(2.5, 1.5), 0.0),
                0.0,
                OverlapState::Separated,
            ),
            // Contained (strictly, and sharing two edges), coincident.
            (
                rect(2.0, 1.0, at(0.0, 0.0), 0.0),
                rect(0.5, 0.25, at(0.25, -0.125), 0.0),
                0.125,
                OverlapState::Contained(Side::J),
            ),
            (
                rect(1.0, 1.0, at(0.5, 0.5), 0.0),
                rect(2.0, 2.0, at(1.0, 1.0), 0.0),
                1.0,
                OverlapState::Contained(Side::I),
            ),
            (
                rect(1.5, 0.5, at(0.5, 0.5), 0.3),
                rect(1.5, 0.5, at(0.5, 0.5), 0.3),
                0.75,
                OverlapState::Coincident,
            ),
            // Wall y ≤ 0.25 across a 2 × 1 box centred at (0, 0.5): 2 × 0.25.
            (
                wall(at(3.0, 0.25), [0.0, 1.0]),
                rect(2.0, 1.0, at(0.0, 0.5), 0.0),
                0.5,
                OverlapState::Overlap,
            ),
            // The box resting on the wall's line, inside / outside the solid.
            (
                wall(at(3.0, 0.0), [0.0, -1.0]),
                rect(2.0, 1.0, at(0.0, 0.5), 0.0),
                2.0,
                OverlapState::Contained(Side::J),
            ),
            (
                wall(at(3.0, 0.0), [0.0, 1.0]),
                rect(2.0, 1.0, at(0.0, 0.5), 0.0),
                0.0,
                OverlapState::Separated,
            ),
        ];
        for (k, (i, j, want, state)) in cases.iter().enumerate() {
            for (a, b, swapped) in [(i, j, false), (j, i, true)] {
                if swapped && matches!(b, RObj::Wall { .. }) {
                    // Wall second: the body is `i`.
                    let o = reference_overlap(a, b);
                    let s = match state {
                        OverlapState::Contained(_) => OverlapState::Contained(Side::I),
                        s => *s,
                    };
                    assert_eq!(o.state, s, "case {k} swapped");
                    assert_eq!(o.area_dd, DD::from(*want), "case {k} swapped");
                    continue;
                }
                let o = reference_overlap(a, b);
                let s = match (state, swapped) {
                    (OverlapState::Contained(Side::I), true) => OverlapState::Contained(Side::J),
                    (OverlapState::Contained(Side::J), true) => OverlapState::Contained(Side::I),
                    (s, _) => *s,
                };
                assert_eq!(o.state, s, "case {k} (swapped: {swapped})");
                // Axis-aligned: every crossing, cap and polygon term is exact here.
                assert_eq!(o.area_dd, DD::from(*want), "case {k} (swapped: {swapped})");
            }
        }

        // Wall x + y ≤ t across the unit square [0, 1]²: t²/2, then 1 − (2 − t)²/2.
        for t in [0.0, 0.25, 0.5, 1.0, 1.5, 1.75, 2.0, 2.5] {
            let i = wall(at(t, 0.0), [1.0, 1.0]);
            let j = rect(1.0, 1.0, at(0.5, 0.5), 0.0);
            let want = if t <= 0.0 {
                0.0
            } else if t <= 1.0 {
                t * t / 2.0
            } else if t < 2.0 {
                1.0 - (2.0 - t) * (2.0 - t) / 2.0
            } else {
                1.0
            };
            let o = reference_overlap(&i, &j);
            let e = err(o.area_dd, DD::from(want));
            // The wall normal is normalised in DD (1/√2 rounded): crossings carry ~EPS errors.
            assert!(
                e < 1e-31,
                "45° wall t = {t}: {o:?}, want {want} (error {e:e})"
            );
            let state = match t {
                t if t <= 0.0 => OverlapState::Separated,
                t if t >= 2.0 => OverlapState::Contained(Side::J),
                _ => OverlapState::Overlap,
            };
            assert_eq!(o.state, state, "45° wall t = {t}");
        }
    }
}

/// Rotated rectangles against rectangles and walls: the reference against polygon clipping
/// (Sutherland–Hodgman) in DD, on the same DD corners; plus the brief's square rotated 45°
/// with a corner through a wall, whose area is the triangle `t²` (t = the corner's depth).
#[test]
fn rectangles_vs_polygon_clipping() {
    let mut g = Rng(0x5eed_0001);
    let mut worst = 0.0f64;
    let mut states = std::collections::BTreeMap::new();
    for it in 0..400 {
        let pos = [g.range(-1.0, 1.0), g.range(-1.0, 1.0)];
        let j = rect(g.range(0.2, 2.0), g.range(0.05, 2.0), pos, g.angle());
        let i = if it % 3 == 0 {
            let p = [g.range(-1.5, 1.5), g.range(-1.5, 1.5)];
            wall(p, [g.range(-1.0, 1.0), g.range(-1.0, 1.0)])
        } else {
            let p = [g.range(-1.5, 1.5), g.range(-1.5, 1.5)];
            rect(g.range(0.2, 2.0), g.range(0.05, 2.0), p, g.angle())
        };
        let want = clipped_area(&i, &j);
        let o = reference_overlap(&i, &j);
        *states.entry(format!("{:?}", o.state)).or_insert(0) += 1;
        let scale = 4.0; // (sizes ≤ 2)²
        let e = err(o.area_dd, want);
        worst = worst.max(e / scale);
        // Both methods are exact up to DD rounding of the crossings (≈ EPS·scale each).
        assert!(
            e < 1e-29 * scale,
            "it {it}: {i:?} {j:?}: {o:?} vs {want:?} ({e:e})"
        );
        if want.is_zero() {
            assert!(matches!(o.state, OverlapState::Separated), "it {it}");
        }
    }
    eprintln!("rectangles vs polygon clipping: worst |error|/4 = {worst:e}; states {states:?}");
    assert!(states.len() >= 4, "states {states:?}");

    // Square of side 1 at 45°, centre at height hgt above the line y = 0 (solid below): the
    // bottom corner is at depth t = 1/√2 − hgt, the part below is a right isosceles triangle
    // of area t². Computed from the DD corners (the angle is π/4 only to f64 precision).
    for hgt in [0.7, 0.5, 0.1, 0.01] {
        let sq = rect(1.0, 1.0, [0.0, hgt], std::f64::consts::FRAC_PI_4);
        let o = reference_overlap(&wall([0.0, 0.0], [0.0, 1.0]), &sq);
        let corners = rect_corners_dd(
            1.0,
            1.0,
            [0.0, hgt],
            std::f64::consts::FRAC_PI_4,
            [0.0, hgt],
        );
        let bottom = corners
            .iter()
            .copied()
            .min_by(|p, q| p[1].cmp_total(&q[1]))
            .unwrap();
        let t = -(bottom[1] + hgt);
        let want = t.sqr();
        let e = rel(o.area_dd, want);
        // The DD axes are orthonormal to ~EPS, so the triangle is isosceles to ~EPS.
        assert!(
            e < 1e-30,
            "45° square at height {hgt}: relative error {e:e}"
        );
        assert_eq!(o.state, OverlapState::Overlap);
        assert_eq!(o.pieces.len(), 2);
    }
}

// ---------------------------------------------------------------------------
// Quadrature in f64: a completely different method for conic pairs
// ---------------------------------------------------------------------------

/// The vertical extent `[lo, hi]` of an object's solid on the line `x = const` (plain `f64`),
/// `None` if the line misses it. A wall gives a half-line (±∞).
fn vertical_extent(o: &RObj, x: f64) -> Option<(f64, f64)> {
    match *o {
        RObj::Body { shape, pos, angle } => {
            let (c, s) = (angle.cos(), angle.sin());
            let xx = x - pos[0];
            let shift = |(lo, hi): (f64, f64)| (lo + pos[1], hi + pos[1]);
            match shape {
                RShape::Circle { r } => ellipse_extent(r, r, c, s, xx).map(shift),
                RShape::Ellipse { a, b } => ellipse_extent(a, b, c, s, xx).map(shift),
                RShape::Rectangle { w, h } => {
                    // |c X + s Y| ≤ w/2 and |−s X + c Y| ≤ h/2, linear in Y.
                    let mut lo = f64::NEG_INFINITY;
                    let mut hi = f64::INFINITY;
                    for (k, m, half) in [(s, c * xx, w / 2.0), (c, -s * xx, h / 2.0)] {
                        if k == 0.0 {
                            if m.abs() > half {
                                return None;
                            }
                        } else {
                            let (p, q) = ((-half - m) / k, (half - m) / k);
                            lo = lo.max(p.min(q));
                            hi = hi.min(p.max(q));
                        }
                    }
                    (lo <= hi).then_some((lo + pos[1], hi + pos[1]))
                }
            }
        }
        RObj::Wall { point, normal } => {
            let (nx, ny) = (normal[0], normal[1]);
            let xx = x - point[0];
            if ny == 0.0 {
                (nx * xx <= 0.0).then_some((f64::NEG_INFINITY, f64::INFINITY))
            } else {
                let y = point[1] - nx * xx / ny;
                Some(if ny > 0.0 {
                    (f64::NEG_INFINITY, y)
                } else {
                    (y, f64::INFINITY)
                })
            }
        }
    }
}

/// Extent relative to the centre: `C Y² + B X Y + A X² = 1` with `C = s²/a² + c²/b²`, `B = 2cs(1/a² − 1/b²)`; the
/// discriminant simplifies with `4AC − B² = 4/(a²b²)`.
fn ellipse_extent(a: f64, b: f64, c: f64, s: f64, xx: f64) -> Option<(f64, f64)> {
    let cc = s * s / (a * a) + c * c / (b * b);
    let bb = 2.0 * c * s * (1.0 / (a * a) - 1.0 / (b * b));
    let rad = cc - xx * xx / (a * a * b * b);
    if rad < 0.0 {
        return None;
    }
    let (mid, half) = (-bb * xx / (2.0 * cc), rad.sqrt() / cc);
    Some((mid - half, mid + half))
}

/// `x` range of a body (`None` for a wall) and the `x` of its corners (kinks of its extent).
fn x_features(o: &RObj) -> (Option<(f64, f64)>, Vec<f64>) {
    match *o {
        RObj::Body { shape, pos, angle } => {
            let (c, s) = (angle.cos(), angle.sin());
            match shape {
                RShape::Circle { r } => (Some((pos[0] - r, pos[0] + r)), vec![]),
                RShape::Ellipse { a, b } => {
                    let half = (a * c).hypot(b * s);
                    (Some((pos[0] - half, pos[0] + half)), vec![])
                }
                RShape::Rectangle { w, h } => {
                    let xs: Vec<f64> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                        .iter()
                        .map(|(p, q)| pos[0] + c * p * w / 2.0 - s * q * h / 2.0)
                        .collect();
                    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
                    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    (Some((lo, hi)), xs)
                }
            }
        }
        RObj::Wall { point, normal } => (
            None,
            if normal[1] == 0.0 {
                vec![point[0]]
            } else {
                vec![]
            },
        ),
    }
}

/// Gauss–Legendre nodes and weights on [0, 1] (Newton on the Legendre recurrence).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|k| {
            let mut x = (std::f64::consts::PI * (k as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for m in 2..=n {
                    let m = m as f64;
                    (p0, p1) = (p1, ((2.0 * m - 1.0) * x * p1 - (m - 1.0) * p0) / m);
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            ((1.0 - x) / 2.0, 1.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Area of the intersection by integrating its vertical extent over `x` in `f64`:
/// the `x` axis is split at every kink and end (body `x` ranges, rectangle corners, and
/// the crossings, found here by bisection on sign changes of the differences of the extent
/// bounds on a 4000-point grid); each piece is mapped by `x = u + (v − u)(1 − cos πs)/2`
/// (which smooths the square-root ends of an ellipse) and integrated by adaptive
/// 20-point Gauss–Legendre to `tol` (absolute).
fn quadrature_area(i: &RObj, j: &RObj, tol: f64) -> f64 {
    let (ri, ki) = x_features(i);
    let (rj, kj) = x_features(j);
    let (lo, hi) = match (ri, rj) {
        (Some(a), Some(b)) => (a.0.max(b.0), a.1.min(b.1)),
        (Some(a), None) | (None, Some(a)) => a,
        (None, None) => panic!("two walls"),
    };
    if lo >= hi {
        return 0.0;
    }
    let height = |x: f64| -> f64 {
        match (vertical_extent(i, x), vertical_extent(j, x)) {
            (Some(a), Some(b)) => (a.1.min(b.1) - a.0.max(b.0)).max(0.0),
            _ => 0.0,
        }
    };
    // Differences whose sign changes are crossings of the two boundaries.
    let diffs = |x: f64| -> Option<[f64; 4]> {
        let (a, b) = (vertical_extent(i, x)?, vertical_extent(j, x)?);
        Some([a.1 - b.1, a.0 - b.0, a.1 - b.0, b.1 - a.0])
    };
    let mut breaks: Vec<f64> = vec![lo, hi];
    breaks.extend(ki.into_iter().chain(kj).filter(|x| *x > lo && *x < hi));
    let n = 4000;
    let grid: Vec<f64> = (0..=n)
        .map(|k| lo + (hi - lo) * k as f64 / n as f64)
        .collect();
    for w in grid.windows(2) {
        let (Some(da), Some(db)) = (diffs(w[0]), diffs(w[1])) else {
            continue;
        };
        for m in 0..4 {
            if !(da[m].is_finite() && db[m].is_finite()) || (da[m] > 0.0) == (db[m] > 0.0) {
                continue;
            }
            let (mut a, mut b) = (w[0], w[1]);
            for _ in 0..200 {
                let mid = 0.5 * (a + b);
                if mid <= a || mid >= b {
                    break;
                }
                match diffs(mid) {
                    Some(dm) if (dm[m] > 0.0) == (da[m] > 0.0) => a = mid,
                    _ => b = mid,
                }
            }
            breaks.push(0.5 * (a + b));
        }
    }
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    let gl = gauss_legendre(20);
    let panel = |u: f64, v: f64, s0: f64, s1: f64| -> f64 {
        gl.iter()
            .map(|&(t, wt)| {
                let s = s0 + (s1 - s0) * t;
                let x = u + (v - u) * 0.5 * (1.0 - (std::f64::consts::PI * s).cos());
                let dx = (v - u) * 0.5 * std::f64::consts::PI * (std::f64::consts::PI * s).sin();
                wt * height(x) * dx
            })
            .sum::<f64>()
            * (s1 - s0)
    };
    fn adapt(
        panel: &dyn Fn(f64, f64) -> f64,
        s0: f64,
        s1: f64,
        whole: f64,
        tol: f64,
        depth: u32,
    ) -> f64 {
        let m = 0.5 * (s0 + s1);
        let (l, r) = (panel(s0, m), panel(m, s1));
        if (l + r - whole).abs() <= tol || depth > 40 {
            l + r
        } else {
            adapt(panel, s0, m, l, tol / 2.0, depth + 1)
                + adapt(panel, m, s1, r, tol / 2.0, depth + 1)
        }
    }
    breaks
        .windows(2)
        .map(|w| {
            let f = |s0: f64, s1: f64| panel(w[0], w[1], s0, s1);
            adapt(&f, 0.0, 1.0, f(0.0, 1.0), tol, 0)
        })
        .sum()
}

/// Plain-f64 signed "distance-like" inside function (negative inside).
fn inside_f64(o: &RObj, x: [f64; 2]) -> f64 {
    match *o {
        RObj::Body { shape, pos, angle } => {
            let (c, s) = (angle.cos(), angle.sin());
            let (dx, dy) = (x[0] - pos[0], x[1] - pos[1]);
            let (l1, l2) = (c * dx + s * dy, -s * dx + c * dy);
            match shape {
                RShape::Circle { r } => l1.hypot(l2) - r,
                RShape::Ellipse { a, b } => (l1 / a).hypot(l2 / b) - 1.0,
                RShape::Rectangle { w, h } => (l1.abs() - w / 2.0).max(l2.abs() - h / 2.0),
            }
        }
        RObj::Wall { point, normal } => {
            let d = normal[0] * (x[0] - point[0]) + normal[1] * (x[1] - point[1]);
            d / normal[0].hypot(normal[1])
        }
    }
}

/// Area of a body (f64).
fn body_area(o: &RObj) -> f64 {
    match *o {
        RObj::Body { shape, .. } => match shape {
            RShape::Circle { r } => std::f64::consts::PI * r * r,
            RShape::Ellipse { a, b } => std::f64::consts::PI * a * b,
            RShape::Rectangle { w, h } => w * h,
        },
        RObj::Wall { .. } => f64::INFINITY,
    }
}

/// Compares the reference with the quadrature: relative 1e-10, or 1e-13 of the smaller
/// body's area for overlaps so small that the quadrature's absolute error dominates.
/// Returns the relative difference.
#[track_caller]
fn check_quadrature(i: &RObj, j: &RObj) -> f64 {
    let small = body_area(i).min(body_area(j));
    let o = reference_overlap(i, j);
    let q = quadrature_area(i, j, 1e-15 * small);
    let d = (o.area - q).abs();
    assert!(
        d <= 1e-10 * q + 1e-13 * small,
        "{i:?} / {j:?}: reference {:e} ({:?}), quadrature {q:e}",
        o.area,
        o.state
    );
    if q > 0.0 { d / q } else { d / small }
}

/// Ellipse–ellipse, circle–ellipse, rectangle–ellipse and rectangle–circle pairs (and the
/// brief's plus of two thin ellipses, four crossings) against the quadrature.
#[test]
fn conic_pairs_vs_quadrature() {
    let mut worst = 0.0f64;
    let fixed = [
        // Plus-shaped thin ellipses: four crossings.
        (
            ellipse(2.0, 0.2, [0.0, 0.0], 0.3),
            ellipse(1.5, 0.1, [0.1, -0.05], 0.3 + 1.4),
            OverlapState::Deep(4),
        ),
        (
            ellipse(2.0, 0.05, [0.0, 0.0], 0.0),
            ellipse(2.0, 0.05, [0.0, 0.0], 1.2),
            OverlapState::Deep(4),
        ),
        (
            ellipse(1.5, 0.5, [0.0, 0.0], 0.7),
            ellipse(1.0, 0.4, [1.6, 0.8], -0.4),
            OverlapState::Overlap,
        ),
        (
            circle(1.0, [0.0, 0.0]),
            ellipse(2.0, 0.5, [1.8, 0.3], 0.9),
            OverlapState::Overlap,
        ),
        (
            rect(2.0, 1.0, [0.0, 0.0], 0.2),
            ellipse(1.2, 0.4, [1.3, 0.4], 1.1),
            OverlapState::Overlap,
        ),
        // A thin ellipse through a rectangle: four crossings.
        (
            rect(1.0, 1.0, [0.0, 0.0], 0.1),
            ellipse(2.0, 0.1, [0.05, 0.1], 0.5),
            OverlapState::Deep(4),
        ),
        (
            rect(1.0, 0.5, [0.0, 0.0], 0.0),
            circle(0.6, [0.7, 0.2]),
            OverlapState::Overlap,
        ),
        // A circle over a rectangle's corner and edges: 4 crossings.
        (
            rect(1.0, 1.0, [0.0, 0.0], 0.0),
            circle(0.6, [0.0, 0.0]),
            OverlapState::Deep(8),
        ),
    ];
    for (i, j, state) in &fixed {
        let o = reference_overlap(i, j);
        assert_eq!(o.state, *state, "{i:?} / {j:?}");
        worst = worst.max(check_quadrature(i, j));
        worst = worst.max(check_quadrature(j, i));
        // Crossings on both boundaries (to f64 rounding of the check), in counter-clockwise
        // order (the crossing polygon has positive area); pieces alternate between the owners and each ends where the next
        // starts.
        let world = |p: [f64; 2]| [o.origin[0] + p[0], o.origin[1] + p[1]];
        for p in &o.crossings {
            assert!(inside_f64(i, world(*p)).abs() < 1e-14, "{p:?} off i");
            assert!(inside_f64(j, world(*p)).abs() < 1e-14, "{p:?} off j");
        }
        let c = &o.crossings;
        let twice: f64 = (0..c.len())
            .map(|k| {
                let (p, q) = (c[k], c[(k + 1) % c.len()]);
                p[0] * q[1] - p[1] * q[0]
            })
            .sum();
        // (Two crossings span no area; their order is checked on the lens.)
        assert!(
            c.len() < 3 || twice > 0.0,
            "crossings not counter-clockwise: {c:?}"
        );
        let n = o.pieces.len();
        for k in 0..n {
            assert_ne!(o.pieces[k].owner, o.pieces[(k + 1) % n].owner);
            assert_eq!(o.pieces[k].end, o.pieces[(k + 1) % n].start);
            assert!(o.pieces[k].cap >= 0.0);
        }
    }
    // Random pairs of bodies (all kinds) and walls against bodies.
    let mut g = Rng(0x5eed_0002);
    let mut states = std::collections::BTreeMap::new();
    for it in 0..300 {
        let i = random_object(&mut g, it % 7 != 0);
        let j = random_object(&mut g, true);
        let o = reference_overlap(&i, &j);
        *states.entry(format!("{:?}", o.state)).or_insert(0) += 1;
        worst = worst.max(check_quadrature(&i, &j));
    }
    eprintln!("conic pairs vs quadrature: worst relative difference {worst:e}; states {states:?}");
    assert!(states.len() >= 5, "states {states:?}");
}

/// A random body (circle, ellipse up to aspect 10, rectangle) near the origin, or a wall.
fn random_object(g: &mut Rng, body_only: bool) -> RObj {
    let pos = [g.range(-1.0, 1.0), g.range(-1.0, 1.0)];
    let kind = if body_only {
        (g.uniform() * 3.0) as u32
    } else {
        3
    };
    match kind {
        0 => circle(g.range(0.2, 1.5), pos),
        1 => {
            let a = g.range(0.3, 2.0);
            ellipse(a, a * g.range(0.1, 1.0), pos, g.angle())
        }
        2 => rect(g.range(0.2, 2.0), g.range(0.1, 2.0), pos, g.angle()),
        _ => wall(pos, [g.range(-1.0, 1.0), g.range(-1.0, 1.0)]),
    }
}

// ---------------------------------------------------------------------------
// Containment, coincidence, symmetry, rigid motions
// ---------------------------------------------------------------------------

/// Every pair kind wholly inside the other (also with an internal tangency), coincident,
/// separated and externally tangent: the state and the area (the inner body's, exact in DD).
#[test]
fn contained_coincident_separated() {
    let pi = DD::PI;
    let (i_in, j_in) = (Side::I, Side::J);
    let cases: Vec<(RObj, RObj, OverlapState, DD)> = vec![
        // circle / circle, internal tangency.
        (
            circle(0.5, [0.1, 0.2]),
            circle(2.0, [0.3, -0.1]),
            OverlapState::Contained(i_in),
            pi * 0.25,
        ),
        (
            circle(2.0, [0.0, 0.0]),
            circle(1.0, [1.0, 0.0]),
            OverlapState::Contained(j_in),
            pi,
        ),
        // circle / ellipse, both ways, and an ellipse tangent inside a circle at its tips.
        (
            circle(0.3, [0.2, 0.1]),
            ellipse(2.0, 1.0, [0.0, 0.0], 0.4),
            OverlapState::Contained(i_in),
            pi * 0.3 * 0.3,
        ),
        (
            ellipse(2.0, 0.5, [0.0, 0.0], 0.0),
            circle(2.0, [0.0, 0.0]),
            OverlapState::Contained(i_in),
            pi,
        ),
        (
            ellipse(0.5, 0.25, [0.1, 0.0], 1.0),
            circle(1.0, [0.0, 0.0]),
            OverlapState::Contained(i_in),
            pi * 0.125,
        ),
        // ellipse / ellipse.
        (
            ellipse(3.0, 2.0, [0.0, 0.0], 0.3),
            ellipse(1.0, 0.5, [0.5, -0.25], 2.0),
            OverlapState::Contained(j_in),
            pi * 0.5,
        ),
        (
            ellipse(1.5, 0.5, [0.25, 0.5], 0.7),
            ellipse(1.5, 0.5, [0.25, 0.5], 0.7),
            OverlapState::Coincident,
            pi * 0.75,
        ),
        // rectangle / conic, both ways (a square inscribed in a circle: corners on it).
        (
            rect(1.0, 0.5, [0.0, 0.0], 0.3),
            circle(2.0, [0.1, 0.0]),
            OverlapState::Contained(i_in),
            DD::from(0.5),
        ),
        (
            rect(2.0, 2.0, [0.0, 0.0], 0.0),
            circle(1.0, [0.0, 0.0]),
            OverlapState::Contained(j_in),
            pi,
        ),
        (
            rect(4.0, 4.0, [0.0, 0.0], 0.5),
            ellipse(1.0, 0.5, [0.25, 0.25], -0.4),
            OverlapState::Contained(j_in),
            pi * 0.5,
        ),
        (
            rect(1.0, 1.0, [0.0, 0.0], 0.0),
            circle(0.5f64.sqrt(), [0.0, 0.0]),
            OverlapState::Contained(i_in),
            DD::ONE,
        ),
        // rectangle / rectangle.
        (
            rect(1.0, 0.5, [0.0, 0.0], 0.3),
            rect(3.0, 3.0, [0.0, 0.0], -0.2),
            OverlapState::Contained(i_in),
            DD::from(0.5),
        ),
        (
            rect(1.0, 0.5, [0.0, 0.0], 0.3),
            rect(1.0, 0.5, [0.0, 0.0], 0.3),
            OverlapState::Coincident,
            DD::from(0.5),
        ),
        // wall / body: inside the solid, tangent from inside, outside, tangent from outside.
        (
            wall([0.0, 0.0], [0.0, 1.0]),
            circle(1.0, [0.0, -1.5]),
            OverlapState::Contained(j_in),
            pi,
        ),
        (
            wall([0.0, 0.0], [0.0, 1.0]),
            circle(1.0, [0.3, -1.0]),
            OverlapState::Contained(j_in),
            pi,
        ),
        (
            wall([0.0, 0.0], [1.0, 1.0]),
            ellipse(1.0, 0.5, [-2.0, -1.0], 0.6),
            OverlapState::Contained(j_in),
            pi * 0.5,
        ),
        (
            wall([0.0, 0.0], [1.0, 1.0]),
            rect(1.0, 0.5, [-2.0, -1.0], 0.6),
            OverlapState::Contained(j_in),
            DD::from(0.5),
        ),
        (
            wall([0.0, 0.0], [0.0, 1.0]),
            circle(1.0, [0.0, 1.5]),
            OverlapState::Separated,
            DD::ZERO,
        ),
        (
            wall([0.0, 0.0], [0.0, 1.0]),
            circle(1.0, [0.3, 1.0]),
            OverlapState::Separated,
            DD::ZERO,
        ),
        (
            wall([0.0, 0.0], [1.0, 0.0]),
            rect(1.0, 1.0, [1.0, 0.0], 0.2),
            OverlapState::Separated,
            DD::ZERO,
        ),
        // separated and externally tangent bodies.
        (
            circle(1.0, [0.0, 0.0]),
            circle(1.0, [2.0, 0.0]),
            OverlapState::Separated,
            DD::ZERO,
        ),
        (
            ellipse(2.0, 1.0, [0.0, 0.0], 0.0),
            ellipse(2.0, 1.0, [0.0, 2.0], 0.0),
            OverlapState::Separated,
            DD::ZERO,
        ),
        (
            ellipse(2.0, 1.0, [0.0, 0.0], 0.0),
            ellipse(1.0, 0.3, [3.0, 2.0], 0.5),
            OverlapState::Separated,
            DD::ZERO,
        ),
        (
            rect(1.0, 1.0, [0.0, 0.0], 0.0),
            circle(0.5, [1.0, 0.0]),
            OverlapState::Separated,
            DD::ZERO,
        ),
        (
            rect(1.0, 1.0, [0.0, 0.0], 0.0),
            ellipse(1.0, 0.5, [0.0, 2.0], 0.1),
            OverlapState::Separated,
            DD::ZERO,
        ),
    ];
    for (k, (i, j, state, area)) in cases.iter().enumerate() {
        let o = reference_overlap(i, j);
        assert_eq!(o.state, *state, "case {k}: {i:?} / {j:?}");
        // Areas are πab, πr² or wh from the exact sizes: a few EPS relative.
        assert!(
            err(o.area_dd, *area) <= 4.0 * DD::EPS * area.to_f64(),
            "case {k}: area {:?}, want {area:?}",
            o.area_dd
        );
        assert!(o.crossings.is_empty() && o.pieces.is_empty(), "case {k}");
        // Swapped: the same area, the other side contained.
        let s = reference_overlap(j, i);
        let swapped = match *state {
            OverlapState::Contained(Side::I) => OverlapState::Contained(Side::J),
            OverlapState::Contained(Side::J) => OverlapState::Contained(Side::I),
            st => st,
        };
        let swapped = match (i, swapped) {
            // A wall second: the body is i.
            (RObj::Wall { .. }, OverlapState::Contained(_)) => OverlapState::Contained(Side::I),
            (_, st) => st,
        };
        assert_eq!(s.state, swapped, "case {k} swapped");
        assert_eq!(s.area_dd, o.area_dd, "case {k} swapped");
    }
}

/// Rigid motions and swapping: area(i, j) = area(j, i); translating the pair by (1e6, −2e6)
/// (exact in f64 for these positions) changes nothing (the reference works relative to the
/// pair); an exact quarter turn of axis-aligned shapes (`(x, y) → (−y, x)`, swapping the
/// semi-axes / width and height) changes nothing to DD rounding; a general rotation (inputs
/// rotated in f64) changes the area by the f64 perturbation of the inputs only.
#[test]
fn symmetry_and_rigid_motions() {
    let mut g = Rng(0x5eed_0003);
    let (mut worst_swap, mut worst_rot) = (0.0f64, 0.0f64);
    let mut n_overlap = 0;
    for it in 0..400 {
        // Positions on a 2^-20 grid, so that adding 1e6 is exact.
        let q = |x: f64| (x * 1048576.0).round() / 1048576.0;
        let mut i = random_object(&mut g, it % 5 != 0);
        let mut j = random_object(&mut g, true);
        for o in [&mut i, &mut j] {
            match o {
                RObj::Body { pos, .. } => *pos = [q(pos[0]), q(pos[1])],
                RObj::Wall { point, .. } => *point = [q(point[0]), q(point[1])],
            }
        }
        let o = reference_overlap(&i, &j);
        if matches!(o.state, OverlapState::Overlap | OverlapState::Deep(_)) {
            n_overlap += 1;
        }

        // Swap: different crossing computations (the quartic is built on the other body's
        // boundary); the areas agree to DD rounding of the crossings.
        let s = reference_overlap(&j, &i);
        let scale = body_area(&i).min(body_area(&j));
        let e = err(s.area_dd, o.area_dd) / scale;
        worst_swap = worst_swap.max(e);
        assert!(e < 1e-28, "it {it}: swap {e:e}: {i:?} / {j:?}");
        assert_eq!(o.pieces.len(), s.pieces.len(), "it {it}");

        // Translation: identical relative geometry, identical result.
        let shift = |o: &RObj| match *o {
            RObj::Body { shape, pos, angle } => body(shape, [pos[0] + 1e6, pos[1] - 2e6], angle),
            RObj::Wall { point, normal } => wall([point[0] + 1e6, point[1] - 2e6], normal),
        };
        let t = reference_overlap(&shift(&i), &shift(&j));
        assert_eq!(t.area_dd, o.area_dd, "it {it}: translation");
        assert_eq!(t.crossings, o.crossings, "it {it}: translation");

        // General rotation by β about the origin, inputs rotated in f64 (perturbation ~1e-16).
        let beta = 0.3 + it as f64 * 0.01;
        let (cb, sb) = (beta.cos(), beta.sin());
        let rot = |p: [f64; 2]| [cb * p[0] - sb * p[1], sb * p[0] + cb * p[1]];
        let turn = |o: &RObj| match *o {
            RObj::Body { shape, pos, angle } => body(shape, rot(pos), angle + beta),
            RObj::Wall { point, normal } => wall(rot(point), rot(normal)),
        };
        let r = reference_overlap(&turn(&i), &turn(&j));
        let e = (r.area - o.area).abs() / scale;
        worst_rot = worst_rot.max(e);
        // An input perturbation ε·size moves the area by at most ~ε·size·perimeter.
        assert!(e < 1e-14, "it {it}: rotation {e:e}: {i:?} / {j:?}");
    }
    eprintln!(
        "symmetry: swap worst |ΔA|/A_small = {worst_swap:e}; rotation (f64 inputs) {worst_rot:e}; \
         {n_overlap} overlapping pairs"
    );
    assert!(n_overlap > 100);

    // Exact quarter turns of axis-aligned shapes.
    let quarter = |o: &RObj| match *o {
        RObj::Body { shape, pos, angle } => {
            assert_eq!(angle, 0.0);
            let shape = match shape {
                RShape::Circle { r } => RShape::Circle { r },
                RShape::Ellipse { a, b } => RShape::Ellipse { a: b, b: a },
                RShape::Rectangle { w, h } => RShape::Rectangle { w: h, h: w },
            };
            body(shape, [-pos[1], pos[0]], 0.0)
        }
        RObj::Wall { point, normal } => wall([-point[1], point[0]], [-normal[1], normal[0]]),
    };
    let pairs = [
        (
            ellipse(2.0, 0.5, [0.0, 0.0], 0.0),
            ellipse(1.0, 0.75, [1.5, 0.625], 0.0),
        ),
        (
            ellipse(2.0, 0.25, [0.0, 0.0], 0.0),
            ellipse(0.25, 2.0, [0.125, 0.0], 0.0),
        ),
        (
            rect(2.0, 1.0, [0.0, 0.0], 0.0),
            ellipse(1.0, 0.75, [1.25, 0.5], 0.0),
        ),
        (rect(2.0, 1.0, [0.0, 0.0], 0.0), circle(0.75, [-1.0, 0.25])),
        (
            wall([0.5, 0.0], [1.0, 2.0]),
            ellipse(1.0, 0.75, [0.25, 0.5], 0.0),
        ),
        (
            wall([0.5, 0.0], [1.0, 2.0]),
            rect(1.0, 0.75, [0.25, 0.5], 0.0),
        ),
    ];
    for (k, (i, j)) in pairs.iter().enumerate() {
        let o = reference_overlap(i, j);
        let mut a = (*i, *j);
        for turn in 1..4 {
            a = (quarter(&a.0), quarter(&a.1));
            let r = reference_overlap(&a.0, &a.1);
            let e = rel(r.area_dd, o.area_dd);
            assert!(e < 1e-29, "pair {k}, {turn} quarter turns: relative {e:e}");
            assert_eq!(r.state, o.state);
        }
    }
}

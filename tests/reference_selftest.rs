//! Self-tests of the double-double type and of the reference contact geometry
//! (`dem2d_validation`) against closed forms. Closed forms are evaluated in DD from
//! the same exact `f64` inputs, so most comparisons are at the level of the final
//! rounding to `f64`.

use dem2d_validation::dd::DD;
use dem2d_validation::reference::{
    RContact, RObj, RShape, RState, cubic_real_roots, depth_along, poly_real_roots,
    reference_contact,
};

// ---------------------------------------------------------------------------
// Helpers
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

#[track_caller]
fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got:e}, want {want:e} (diff {:e} > tol {tol:e})",
        (got - want).abs()
    );
}

#[track_caller]
fn assert_vclose(what: &str, got: [f64; 2], want: [f64; 2], tol: f64) {
    assert_close(&format!("{what}.x"), got[0], want[0], tol);
    assert_close(&format!("{what}.y"), got[1], want[1], tol);
}

/// Each expected point matches some reported crossing (and the counts agree).
#[track_caller]
fn assert_crossings(c: &RContact, want: &[[f64; 2]], tol: f64) {
    assert_eq!(c.crossings.len(), want.len(), "crossings {:?}", c.crossings);
    for w in want {
        let best = c
            .crossings
            .iter()
            .map(|p| (p[0] - w[0]).abs().max((p[1] - w[1]).abs()))
            .fold(f64::INFINITY, f64::min);
        assert!(
            best <= tol,
            "no crossing near {w:?} (closest {best:e}); got {:?}",
            c.crossings
        );
    }
}

/// Body axes as used by the reference: f64 cos/sin renormalised in DD.
fn axes(angle: f64) -> ([DD; 2], [DD; 2]) {
    let (c, s) = (DD::from(angle.cos()), DD::from(angle.sin()));
    let k = (c * c + s * s).sqrt();
    let (c, s) = (c / k, s / k);
    ([c, s], [-s, c])
}

fn dot(a: [DD; 2], b: [DD; 2]) -> DD {
    a[0] * b[0] + a[1] * b[1]
}

/// World position of a reported relative point, exactly (`origin + rel`).
fn world(c: &RContact, rel: [f64; 2]) -> [DD; 2] {
    [
        DD::from(c.origin[0]) + rel[0],
        DD::from(c.origin[1]) + rel[1],
    ]
}

/// Normalised implicit value `(ξ/a)² + (η/b)² − 1` of an ellipse at a world point.
fn ellipse_residual(a: f64, b: f64, pos: [f64; 2], angle: f64, x: [DD; 2]) -> f64 {
    let (e1, e2) = axes(angle);
    let w = [x[0] - pos[0], x[1] - pos[1]];
    ((dot(w, e1) / a).sqr() + (dot(w, e2) / b).sqr() - 1.0).to_f64()
}

/// Checks that the result is an `Overlap` and that swapping `i` and `j` gives
/// the same crossings (in world coordinates), the opposite normal and the same depth.
#[track_caller]
fn assert_swap_symmetric(i: &RObj, j: &RObj, tol: f64) {
    let c = reference_contact(i, j);
    let s = reference_contact(j, i);
    assert_eq!(c.state, s.state);
    assert_eq!(c.crossings.len(), s.crossings.len());
    for p in &c.crossings {
        let wp = world(&c, *p);
        let best = s
            .crossings
            .iter()
            .map(|q| {
                let wq = world(&s, *q);
                (wp[0] - wq[0]).abs().max((wp[1] - wq[1]).abs()).to_f64()
            })
            .fold(f64::INFINITY, f64::min);
        assert!(best <= tol, "swap: crossing {p:?} unmatched ({best:e})");
    }
    if c.state == RState::Overlap {
        let (n, m) = (c.normal.unwrap(), s.normal.unwrap());
        assert_vclose("swap normal", n, [-m[0], -m[1]], 1e-15);
        assert_close("swap depth", c.depth.unwrap(), s.depth.unwrap(), tol);
    }
}

// ---------------------------------------------------------------------------
// DD arithmetic
// ---------------------------------------------------------------------------

#[test]
fn dd_arithmetic() {
    let tiny = 2f64.powi(-80);
    let x = (DD::ONE + tiny) - 1.0;
    assert_eq!(x, DD::from(tiny));
    assert!(DD::ONE + 2f64.powi(-100) > DD::ONE);

    // Exact product (1 + 2^-30)^2 = 1 + 2^-29 + 2^-60.
    let y = DD::from(1.0 + 2f64.powi(-30)).sqr();
    assert_eq!(y.hi, 1.0 + 2f64.powi(-29));
    assert_eq!(y.lo, 2f64.powi(-60));

    let r2 = DD::from(2.0).sqrt();
    assert!((r2 * r2 - 2.0).abs().to_f64() < 1e-30);
    assert!((r2.hi - std::f64::consts::SQRT_2).abs() <= f64::EPSILON);
    assert_eq!(DD::from(4.0).sqrt(), DD::from(2.0));
    let big = DD::from(1e300).sqrt();
    assert!((big * big / 1e300 - 1.0).abs().to_f64() < 1e-30);

    let third = DD::ONE / 3.0;
    assert!((third * 3.0 - 1.0).abs().to_f64() < 1e-31);
    assert_eq!(DD::from(10.0) / 4.0, DD::from(2.5));
    let (p, q) = (DD::from(0.1) + 1e-20, DD::from(7.0).sqrt());
    assert!(((p / q) * q - p).abs().to_f64() < 1e-31 * p.to_f64());
    assert!((q.recip() * q - 1.0).abs().to_f64() < 1e-31);
    assert!((-p).is_negative() && (-p).abs() == p);
    assert!(DD::from(3.0).max(DD::from(2.0)) == 3.0 && DD::from(3.0).min(DD::from(2.0)) == 2.0);
    let s: DD = [0.1, 0.2, 0.3].iter().map(|&v| DD::from(v)).sum();
    // 0.1 + 0.2 + 0.3 as exact binary fractions: compare with a two-step exact sum.
    let exact = DD::from_sum(0.1, 0.2) + 0.3;
    assert!((s - exact).abs().to_f64() < 1e-32);
}

// ---------------------------------------------------------------------------
// Polynomial roots
// ---------------------------------------------------------------------------

/// The polynomial changes sign across `r` (or vanishes at `r`) at the
/// neighbouring f64 values: `r` is a correctly bracketed simple root.
fn brackets_root(t: [f64; 4], r: f64) -> bool {
    let eval = |x: f64| t.iter().fold(DD::ZERO, |acc, &c| acc * x + c);
    let up = f64::from_bits(r.to_bits() + 1);
    let down = f64::from_bits(r.to_bits() - 1);
    let (lo, hi) = if r > 0.0 { (down, up) } else { (up, down) };
    eval(r).is_zero() || eval(lo).signum() * eval(hi).signum() < 0.0
}

#[test]
fn cubic_roots_closed_forms() {
    assert_eq!(
        cubic_real_roots([1.0, 0.0, -12.0, 16.0]),
        vec![(-4.0, 1), (2.0, 2)]
    );
    assert_eq!(
        cubic_real_roots([1.0, -6.0, 11.0, -6.0]),
        vec![(1.0, 1), (2.0, 1), (3.0, 1)]
    );
    assert_eq!(cubic_real_roots([1.0, -3.0, 3.0, -1.0]), vec![(1.0, 3)]);
    assert_eq!(cubic_real_roots([2.0, 0.0, 0.0, 0.0]), vec![(0.0, 3)]);
    assert_eq!(
        cubic_real_roots([0.0, 1.0, -3.0, 2.0]),
        vec![(1.0, 1), (2.0, 1)]
    );
    assert_eq!(cubic_real_roots([0.0, 0.0, 2.0, -1.0]), vec![(0.5, 1)]);
    assert_eq!(cubic_real_roots([1.0, 0.0, 1.0, 0.0]), vec![(0.0, 1)]);
    assert!(cubic_real_roots([0.0, 0.0, 0.0, 0.0]).is_empty());
    assert!(cubic_real_roots([0.0, 1.0, 0.0, 1.0]).is_empty());
}

#[test]
fn cubic_roots_tiny_leading_and_wide_range() {
    // 1e-10 λ³ + λ² − 3λ + 2: roots ≈ 1, 2 and ≈ −1e10.
    let t = [1e-10, 1.0, -3.0, 2.0];
    let roots = cubic_real_roots(t);
    assert_eq!(roots.len(), 3, "{roots:?}");
    assert!(roots.iter().all(|&(r, m)| m == 1 && brackets_root(t, r)));
    assert_close("far root", roots[0].0, -1e10, 1e-6 * 1e10);
    assert_close("root 1", roots[1].0, 1.0, 1e-9);
    assert_close("root 2", roots[2].0, 2.0, 1e-9);

    // 1e-8 (λ + 1e6)(λ − 1e2)(λ − 1e7), coefficients rounded: spans 1e-8 … 1e7.
    let t = [1e-8, -0.090001, -99991.0, 1e7];
    let roots = cubic_real_roots(t);
    assert_eq!(roots.len(), 3, "{roots:?}");
    for ((r, m), want) in roots.iter().zip([-1e6, 1e2, 1e7]) {
        assert_eq!(*m, 1);
        assert!(brackets_root(t, *r), "root {r} not bracketed");
        assert_close("wide root", *r, want, 1e-6 * want.abs());
    }

    // A quartic through the DD interface: (z² − 2)² has double roots ±√2.
    let p: Vec<DD> = [4.0, 0.0, -4.0, 0.0, 1.0].map(DD::from).to_vec();
    let roots = poly_real_roots(&p);
    assert_eq!(roots.len(), 2);
    for ((r, m), s) in roots.iter().zip([-1.0, 1.0]) {
        assert_eq!(*m, 2);
        assert!((r.sqr() - 2.0).abs().to_f64() < 1e-30 && r.signum() == s);
    }
}

// ---------------------------------------------------------------------------
// Circles
// ---------------------------------------------------------------------------

/// Two circles, `j` at distance `dist` from `ci` in direction `phi`; compares with
/// the closed forms (depth `r_i + r_j − d`, normal along the centres, lens chord).
fn check_two_circles(ri: f64, rj: f64, ci: [f64; 2], phi: f64, dist: f64) {
    let cj = [ci[0] + dist * phi.cos(), ci[1] + dist * phi.sin()];
    let c = reference_contact(&circle(ri, ci), &circle(rj, cj));
    let (dx, dy) = (DD::from(cj[0]) - ci[0], DD::from(cj[1]) - ci[1]);
    let d = (dx * dx + dy * dy).sqrt();
    let depth = DD::from(ri) + rj - d;
    if depth.is_zero() {
        // Exactly tangent (happens when the offset is below the ulp of the centres).
        assert_eq!(c.state, RState::Touching, "d = {d:?}");
        assert!(c.depth.unwrap().abs() < 1e-28 * ri.max(rj));
        return;
    }
    if depth.is_negative() {
        assert_eq!(c.state, RState::Separated, "d = {d:?}");
        assert!(c.crossings.is_empty());
        return;
    }
    assert_eq!(c.state, RState::Overlap, "d = {d:?}");
    assert_eq!(c.origin, ci);
    let (ux, uy) = (dx / d, dy / d);
    let x = (d * d + DD::from(ri).sqr() - DD::from(rj).sqr()) / (d * 2.0);
    let h = (DD::from(ri).sqr() - x * x).sqrt();
    let mid = [(ux * x).to_f64(), (uy * x).to_f64()];
    let p1 = [(ux * x - uy * h).to_f64(), (uy * x + ux * h).to_f64()];
    let p2 = [(ux * x + uy * h).to_f64(), (uy * x - ux * h).to_f64()];
    let scale = ri.max(rj);
    assert_crossings(&c, &[p1, p2], 4e-16 * scale);
    assert_vclose(
        "normal",
        c.normal.unwrap(),
        [ux.to_f64(), uy.to_f64()],
        4e-16,
    );
    assert_vclose("point", c.point_rel.unwrap(), mid, 4e-16 * scale);
    let depth = depth.to_f64();
    assert_close(
        "depth",
        c.depth.unwrap(),
        depth,
        2.3e-16 * depth + 1e-30 * scale,
    );
    assert_close(
        "depth_along",
        depth_along(&circle(ri, ci), &circle(rj, cj), c.normal.unwrap()),
        depth,
        2.3e-16 * depth + 1e-30 * scale,
    );
}

#[test]
fn two_circles_closed_form() {
    for (ri, rj) in [(1.0f64, 1.0f64), (1.0, 0.25), (0.3, 2.0), (300.0, 500.0)] {
        let sum = ri + rj;
        for &ci in &[[0.0, 0.0], [1e6 + 0.25, -3e6 + 0.125]] {
            for (k, phi) in [0.0, 0.7, 2.5, -1.9].into_iter().enumerate() {
                for f in [0.5, 0.9, 0.999, 1.0 - 1e-9, 1.0 - 1e-12, 1.0 + 1e-12, 1.3] {
                    let dist = if f < 0.6 {
                        (ri - rj).abs() + 0.5 * sum * f
                    } else {
                        sum * f
                    };
                    check_two_circles(ri, rj, ci, phi + 0.01 * k as f64, dist);
                }
            }
        }
    }
}

#[test]
fn circles_touching_and_contained() {
    let c = reference_contact(&circle(1.0, [0.0, 0.0]), &circle(1.0, [2.0, 0.0]));
    assert_eq!(c.state, RState::Touching);
    assert_vclose("touch point", c.point_rel.unwrap(), [1.0, 0.0], 1e-15);
    assert_vclose("touch normal", c.normal.unwrap(), [1.0, 0.0], 1e-15);
    assert!(c.depth.unwrap().abs() < 1e-28);

    // Internal tangency at (−1, 0).
    let c = reference_contact(&circle(1.0, [0.0, 0.0]), &circle(2.0, [1.0, 0.0]));
    assert_eq!(c.state, RState::Touching);
    assert_vclose("internal touch", c.point_rel.unwrap(), [-1.0, 0.0], 1e-15);

    let c = reference_contact(&circle(0.5, [0.1, 0.2]), &circle(2.0, [0.3, -0.1]));
    assert_eq!(c.state, RState::Contained);
    let c = reference_contact(&circle(2.0, [0.3, -0.1]), &circle(0.5, [0.1, 0.2]));
    assert_eq!(c.state, RState::Contained);
}

// ---------------------------------------------------------------------------
// Walls
// ---------------------------------------------------------------------------

#[test]
fn circle_and_ellipse_vs_wall() {
    let cases = [
        (
            RShape::Circle { r: 0.5 },
            [0.3, 0.2],
            0.0,
            [0.0, 0.0],
            [1.0, 2.0],
        ),
        (
            RShape::Circle { r: 0.5 },
            [1e6 + 0.3, 0.2],
            0.0,
            [1e6, 0.0],
            [0.0, 1.0],
        ),
        (
            RShape::Ellipse { a: 1.5, b: 0.5 },
            [1e6, 2e6],
            0.7,
            [1e6 + 0.1, 2e6 - 0.3],
            [-0.3, 1.0],
        ),
        (
            RShape::Ellipse { a: 0.4, b: 1.1 },
            [-3.0, 5.0],
            -2.2,
            [-2.5, 4.0],
            [-1.0, 0.2],
        ),
    ];
    for (shape, pos, angle, point, normal) in cases {
        let b = body(shape, pos, angle);
        let w = wall(point, normal);
        // Closed form: depth = support half-width along n − signed distance of the centre.
        let (nx, ny) = (DD::from(normal[0]), DD::from(normal[1]));
        let k = (nx * nx + ny * ny).sqrt();
        let n = [nx / k, ny / k];
        let (e1, e2) = axes(angle);
        let (a, bb) = match shape {
            RShape::Circle { r } => (r, r),
            RShape::Ellipse { a, b } => (a, b),
            RShape::Rectangle { .. } => unreachable!(),
        };
        let half = ((dot(n, e1) * a).sqr() + (dot(n, e2) * bb).sqr()).sqrt();
        let cp = [DD::from(pos[0]) - point[0], DD::from(pos[1]) - point[1]];
        let dist = dot(n, cp);
        let depth = (half - dist).to_f64();
        assert!(depth > 0.0);
        let nf = [n[0].to_f64(), n[1].to_f64()];

        for (c, sign) in [
            (reference_contact(&w, &b), 1.0),
            (reference_contact(&b, &w), -1.0),
        ] {
            assert_eq!(c.state, RState::Overlap);
            assert_eq!(c.origin, pos);
            assert_vclose(
                "wall normal",
                c.normal.unwrap(),
                [sign * nf[0], sign * nf[1]],
                0.0,
            );
            assert_close("wall depth", c.depth.unwrap(), depth, 4e-16 * depth);
            assert_eq!(c.crossings.len(), 2);
            for p in &c.crossings {
                let x = world(&c, *p);
                let on_line = dot(n, [x[0] - point[0], x[1] - point[1]]).to_f64();
                assert!(
                    on_line.abs() < 1e-15 * a.max(bb),
                    "off the wall line: {on_line:e}"
                );
                let res = ellipse_residual(a, bb, pos, angle, x);
                assert!(res.abs() < 1e-15, "off the body: {res:e}");
            }
            let m = c.point_rel.unwrap();
            let mean = [
                0.5 * (c.crossings[0][0] + c.crossings[1][0]),
                0.5 * (c.crossings[0][1] + c.crossings[1][1]),
            ];
            assert_vclose("chord midpoint", m, mean, 1e-15);
            let u = c.normal.unwrap();
            assert_close(
                "depth_along",
                depth_along(
                    if sign > 0.0 { &w } else { &b },
                    if sign > 0.0 { &b } else { &w },
                    u,
                ),
                depth,
                4e-16 * depth,
            );
        }
    }

    // Separated / contained / touching.
    let c = reference_contact(&wall([0.0, 0.0], [0.0, 1.0]), &circle(1.0, [0.0, 1.5]));
    assert_eq!(c.state, RState::Separated);
    let c = reference_contact(&wall([0.0, 0.0], [0.0, 1.0]), &circle(1.0, [0.0, -1.5]));
    assert_eq!(c.state, RState::Contained);
    let c = reference_contact(&wall([0.0, 0.0], [0.0, 1.0]), &circle(1.0, [0.3, 1.0]));
    assert_eq!(c.state, RState::Touching);
    assert_vclose("wall touch", c.point_rel.unwrap(), [0.0, -1.0], 1e-15);
}

// ---------------------------------------------------------------------------
// Ellipses
// ---------------------------------------------------------------------------

#[test]
fn ellipse_pair_symmetric_closed_form() {
    let (a, b) = (2.0, 1.0);
    // Side by side along the major axis (x) and along the minor axis (y), with
    // overlaps down to 1e-12·b.
    for along_major in [true, false] {
        let semi = if along_major { a } else { b };
        let other = if along_major { b } else { a };
        for f in [0.3, 0.9, 0.99, 1.0 - 1e-6, 1.0 - 1e-9, 1.0 - 1e-12] {
            let d = 2.0 * semi * f;
            let pos = if along_major { [d, 0.0] } else { [0.0, d] };
            let c = reference_contact(&ellipse(a, b, [0.0, 0.0], 0.0), &ellipse(a, b, pos, 0.0));
            assert_eq!(c.state, RState::Overlap, "major={along_major} f={f}");
            let half = DD::from(d).mul_pow2(0.5);
            let lateral = ((DD::ONE - (half / semi).sqr()).sqrt() * other).to_f64();
            let h = half.to_f64();
            let (want, normal, point) = if along_major {
                ([[h, lateral], [h, -lateral]], [1.0, 0.0], [h, 0.0])
            } else {
                ([[lateral, h], [-lateral, h]], [0.0, 1.0], [0.0, h])
            };
            assert_crossings(&c, &want, 4e-16 * a);
            assert_vclose("normal", c.normal.unwrap(), normal, 1e-15);
            assert_vclose("point", c.point_rel.unwrap(), point, 4e-16 * a);
            let depth = (DD::from(2.0 * semi) - d).to_f64();
            assert_close("depth", c.depth.unwrap(), depth, 2.3e-16 * depth);
        }
        // Slightly separated.
        let d = 2.0 * semi * (1.0 + 1e-12);
        let pos = if along_major { [d, 0.0] } else { [0.0, d] };
        let c = reference_contact(&ellipse(a, b, [0.0, 0.0], 0.0), &ellipse(a, b, pos, 0.0));
        assert_eq!(c.state, RState::Separated);
    }
}

#[test]
fn ellipse_deep_contained_separated() {
    let c = reference_contact(
        &ellipse(2.0, 1.0, [0.0, 0.0], 0.0),
        &ellipse(2.0, 1.0, [0.0, 0.0], std::f64::consts::FRAC_PI_2),
    );
    assert_eq!(c.state, RState::Deep(4));
    let x = 2.0 / 5f64.sqrt();
    assert_crossings(&c, &[[x, x], [-x, x], [-x, -x], [x, -x]], 1e-15);
    // Sorted by angle about the mean (≈ origin): third quadrant first.
    assert!(c.crossings[0][0] < 0.0 && c.crossings[0][1] < 0.0);
    assert!(c.normal.is_none() && c.depth.is_none());

    let big = ellipse(2.0, 1.0, [1e6, 1e6], 0.2);
    let small = circle(0.3, [1e6 + 0.5, 1e6 + 0.1]);
    assert_eq!(reference_contact(&big, &small).state, RState::Contained);
    assert_eq!(reference_contact(&small, &big).state, RState::Contained);
    let far = circle(0.3, [1e6 + 5.0, 1e6 + 0.1]);
    assert_eq!(reference_contact(&big, &far).state, RState::Separated);
    assert_eq!(reference_contact(&big, &big).state, RState::Contained);
}

/// Boundary point of an ellipse with the given outward world normal `m` (DD).
fn point_with_normal(a: f64, b: f64, angle: f64, m: [DD; 2]) -> [DD; 2] {
    let (e1, e2) = axes(angle);
    let (m1, m2) = (dot(m, e1), dot(m, e2));
    let k = ((m1 * a).sqr() + (m2 * b).sqr()).sqrt();
    let (p1, p2) = (m1 * DD::from(a).sqr() / k, m2 * DD::from(b).sqr() / k);
    [e1[0] * p1 + e2[0] * p2, e1[1] * p1 + e2[1] * p2]
}

#[test]
fn rotated_ellipses_near_tangency() {
    let ci = [0.125, -0.5];
    let cases = [
        ((2.0, 0.5, 0.3), (1.0, 0.7, -1.1), 0.4),
        ((1.5, 1.0, 2.0), (3.0, 0.2, 0.9), 2.8),
        ((0.6, 0.6, 0.0), (2.5, 1.2, 0.45), -1.7),
    ];
    for ((ai, bi, thi), (aj, bj, thj), phi) in cases {
        let nrm = [DD::from(f64::cos(phi)), DD::from(f64::sin(phi))];
        let k = (nrm[0].sqr() + nrm[1].sqr()).sqrt();
        let nrm = [nrm[0] / k, nrm[1] / k];
        let xi = point_with_normal(ai, bi, thi, nrm);
        let xj = point_with_normal(aj, bj, thj, [-nrm[0], -nrm[1]]);
        let bmin = bi.min(bj);
        for eps in [1e-12 * bmin, 1e-9, -1e-12 * bmin, 1e-2] {
            // Tangent placement, then pushed together by eps along the normal.
            let cj = [
                (DD::from(ci[0]) + xi[0] - xj[0] - nrm[0] * eps).to_f64(),
                (DD::from(ci[1]) + xi[1] - xj[1] - nrm[1] * eps).to_f64(),
            ];
            let ei = ellipse(ai, bi, ci, thi);
            let ej = ellipse(aj, bj, cj, thj);
            let c = reference_contact(&ei, &ej);
            if eps < 0.0 {
                assert_eq!(c.state, RState::Separated);
                continue;
            }
            assert_eq!(c.state, RState::Overlap, "eps {eps:e}");
            for p in &c.crossings {
                let x = world(&c, *p);
                assert!(ellipse_residual(ai, bi, ci, thi, x).abs() < 1e-15);
                assert!(ellipse_residual(aj, bj, cj, thj, x).abs() < 1e-15);
            }
            if eps < 1e-6 {
                // Rounding cj to f64 moves it by ≲ 2e-16.
                assert_close("near-tangent depth", c.depth.unwrap(), eps, 1e-15);
                let n = c.normal.unwrap();
                assert_vclose(
                    "near-tangent normal",
                    n,
                    [nrm[0].to_f64(), nrm[1].to_f64()],
                    1e-6,
                );
                let sep = (c.crossings[0][0] - c.crossings[1][0])
                    .hypot(c.crossings[0][1] - c.crossings[1][1]);
                assert!(sep > 0.0 && sep < 1e-3, "crossing separation {sep:e}");
            }
            assert_swap_symmetric(&ei, &ej, 1e-15);
        }
    }
}

// ---------------------------------------------------------------------------
// Rectangles
// ---------------------------------------------------------------------------

#[test]
fn stacked_squares() {
    for base in [[0.0, 0.0], [5e5 + 0.5, -7e5]] {
        for delta in [0.1, 1e-3, 1e-9] {
            let pj = [base[0], base[1] + 1.0 - delta];
            let i = rect(1.0, 1.0, base, 0.0);
            let j = rect(1.0, 1.0, pj, 0.0);
            // Exact overlap from the f64 positions.
            let dl = (DD::ONE - (DD::from(pj[1]) - base[1])).to_f64();
            let ymid = (DD::from(0.5) - DD::from(dl).mul_pow2(0.5)).to_f64();
            for (c, s) in [
                (reference_contact(&i, &j), 1.0),
                (reference_contact(&j, &i), -1.0),
            ] {
                assert_eq!(c.state, RState::Overlap, "delta {delta}");
                assert_vclose("stack normal", c.normal.unwrap(), [0.0, s], 0.0);
                assert_close("stack depth", c.depth.unwrap(), dl, 2.3e-16 * dl);
                if s > 0.0 {
                    assert_crossings(&c, &[[-0.5, ymid], [0.5, ymid]], 1e-16);
                    assert_vclose("stack point", c.point_rel.unwrap(), [0.0, ymid], 1e-16);
                }
            }
        }
    }
    // Exactly touching (shared edge) and a corner-to-corner diagonal miss.
    let c = reference_contact(
        &rect(1.0, 1.0, [0.0, 0.0], 0.0),
        &rect(1.0, 1.0, [0.0, 1.0], 0.0),
    );
    assert_eq!(c.state, RState::Touching);
    assert_vclose("touch", c.point_rel.unwrap(), [0.0, 0.5], 0.0);
    assert_vclose("touch normal", c.normal.unwrap(), [0.0, 1.0], 0.0);
    let c = reference_contact(
        &rect(1.0, 1.0, [0.0, 0.0], 0.0),
        &rect(1.0, 1.0, [1.5, 1.5], 0.0),
    );
    assert_eq!(c.state, RState::Separated);
    let c = reference_contact(
        &rect(3.0, 2.0, [0.0, 0.0], 0.1),
        &rect(1.0, 0.5, [0.2, 0.1], -0.4),
    );
    assert_eq!(c.state, RState::Contained);
}

/// Collinear shared edges and exact tangencies of rectangles.
#[test]
fn rectangle_shared_edges_and_tangency() {
    let unit = |p: [f64; 2]| rect(1.0, 1.0, p, 0.0);
    // Side by side with overlap 0.1: top and bottom edges share [0.4, 0.5].
    let c = reference_contact(&unit([0.0, 0.0]), &unit([0.9, 0.0]));
    assert_eq!(c.state, RState::Overlap);
    assert_crossings(&c, &[[0.45, -0.5], [0.45, 0.5]], 1e-16);
    assert_vclose("side normal", c.normal.unwrap(), [1.0, 0.0], 0.0);
    assert_close("side depth", c.depth.unwrap(), 0.1, 1e-16);
    // Narrower box on top, left edges collinear: one shared-segment crossing
    // and one proper crossing.
    let c = reference_contact(&unit([0.0, 0.0]), &rect(0.5, 1.0, [-0.25, 0.75], 0.0));
    assert_eq!(c.state, RState::Overlap);
    assert_crossings(&c, &[[-0.5, 0.375], [0.0, 0.5]], 1e-16);
    // Edge against edge with a half-length shared segment: touching at its middle.
    let c = reference_contact(&unit([0.0, 0.0]), &unit([1.0, 0.5]));
    assert_eq!(c.state, RState::Touching);
    assert_vclose("edge touch", c.point_rel.unwrap(), [0.5, 0.25], 0.0);
    assert_vclose("edge touch normal", c.normal.unwrap(), [1.0, 0.0], 0.0);
    // Corner on corner: touching, no smooth normal.
    let c = reference_contact(&unit([0.0, 0.0]), &unit([1.0, 1.0]));
    assert_eq!(c.state, RState::Touching);
    assert!(c.normal.is_none() && c.depth.is_none());
    // Coincident squares.
    assert_eq!(
        reference_contact(&unit([0.0, 0.0]), &unit([0.0, 0.0])).state,
        RState::Contained
    );
    // Circle resting exactly on the top face.
    let c = reference_contact(&rect(2.0, 2.0, [0.0, 0.0], 0.0), &circle(1.0, [0.25, 2.0]));
    assert_eq!(c.state, RState::Touching);
    assert_vclose("circle touch", c.point_rel.unwrap(), [0.25, 1.0], 1e-16);
    assert_vclose("circle touch normal", c.normal.unwrap(), [0.0, 1.0], 1e-16);
    assert!(c.depth.unwrap().abs() < 1e-30);
}

#[test]
fn rotated_square_corner_into_face() {
    // i: 2×2 square at the origin (top face y = 1); j: unit square rotated by θ,
    // its lowest corner pushed `delta` below the face.
    for (theta, delta, cx) in [(0.4, 0.05, 0.1), (-1.2, 1e-7, -0.3), (2.0, 1e-11, 0.45)] {
        let (e1, e2) = axes(theta);
        let half = DD::from(0.5);
        let reach = (e1[1].abs() + e2[1].abs()) * half;
        let cy = (DD::from(1.0 - delta) + reach).to_f64();
        let i = rect(2.0, 2.0, [0.0, 0.0], 0.0);
        let j = rect(1.0, 1.0, [cx, cy], theta);
        let c = reference_contact(&i, &j);
        assert_eq!(c.state, RState::Overlap);
        let depth = (DD::ONE - (DD::from(cy) - reach)).to_f64();
        assert_close(
            "corner depth",
            c.depth.unwrap(),
            depth,
            2.3e-16 * depth + 1e-30,
        );
        assert_vclose("corner normal", c.normal.unwrap(), [0.0, 1.0], 1e-15);
        for p in &c.crossings {
            assert_close("crossing on face", p[1], 1.0, 2.3e-16);
        }
        assert_close("point on face", c.point_rel.unwrap()[1], 1.0, 2.3e-16);
        assert_swap_symmetric(&i, &j, 1e-15);
    }
}

#[test]
fn rectangle_vs_circle_and_wall() {
    // Circle of radius 1 dipping delta into the top face of a 2×2 square.
    for delta in [0.3, 1e-6, 1e-12] {
        let pos = [0.2, 2.0 - delta];
        let i = rect(2.0, 2.0, [0.0, 0.0], 0.0);
        let j = circle(1.0, pos);
        let c = reference_contact(&i, &j);
        assert_eq!(c.state, RState::Overlap, "delta {delta}");
        let dl = (DD::from(2.0) - pos[1]).to_f64();
        let dy = DD::from(pos[1]) - 1.0;
        let hx = (DD::ONE - dy * dy).sqrt().to_f64();
        assert_crossings(&c, &[[0.2 - hx, 1.0], [0.2 + hx, 1.0]], 4e-16);
        assert_vclose("normal", c.normal.unwrap(), [0.0, 1.0], 1e-15);
        assert_close("depth", c.depth.unwrap(), dl, 2.3e-16 * dl);
        assert_swap_symmetric(&i, &j, 1e-15);
    }
    // Circle inside a rectangle, rectangle inside a circle.
    let r = rect(4.0, 3.0, [1.0, 1.0], 0.3);
    assert_eq!(
        reference_contact(&r, &circle(0.5, [1.2, 0.9])).state,
        RState::Contained
    );
    assert_eq!(
        reference_contact(&circle(9.0, [1.2, 0.9]), &r).state,
        RState::Contained
    );

    // Rotated rectangle vs wall y = 0.
    let (w, h, theta) = (2.0, 1.0, 0.3);
    let r = rect(w, h, [0.0, 0.5], theta);
    let wl = wall([0.0, 0.0], [0.0, 1.0]);
    let (e1, e2) = axes(theta);
    let depth = (e1[1].abs() * (w / 2.0) + e2[1].abs() * (h / 2.0) - 0.5).to_f64();
    let c = reference_contact(&wl, &r);
    assert_eq!(c.state, RState::Overlap);
    assert_vclose("wall normal", c.normal.unwrap(), [0.0, 1.0], 0.0);
    assert_close("rect-wall depth", c.depth.unwrap(), depth, 2.3e-16 * depth);
    for p in &c.crossings {
        assert_close("on wall", p[1], -0.5, 1e-16);
    }
    let c = reference_contact(&r, &wl);
    assert_vclose("wall normal (j)", c.normal.unwrap(), [0.0, -1.0], 0.0);
    assert_close(
        "rect-wall depth (j)",
        c.depth.unwrap(),
        depth,
        2.3e-16 * depth,
    );
    // Flat on the wall: touching at the middle of the bottom edge.
    let c = reference_contact(&wl, &rect(2.0, 1.0, [0.3, 0.5], 0.0));
    assert_eq!(c.state, RState::Touching);
    assert_vclose("flat touch", c.point_rel.unwrap(), [0.0, -0.5], 0.0);
    assert_eq!(
        reference_contact(&wl, &rect(2.0, 1.0, [0.3, -1.0], 0.2)).state,
        RState::Contained
    );
}

// ---------------------------------------------------------------------------
// Randomised consistency
// ---------------------------------------------------------------------------

/// Deterministic LCG (no external crates).
struct Lcg(u64);

impl Lcg {
    fn unit(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    fn object(&mut self, allow_wall: bool) -> RObj {
        let kinds = if allow_wall { 4.0 } else { 3.0 };
        let pos = [self.range(-1.0, 1.0), self.range(-1.0, 1.0)];
        let angle = self.range(-4.0, 4.0);
        match (self.unit() * kinds) as usize {
            0 => body(
                RShape::Circle {
                    r: self.range(0.2, 1.5),
                },
                pos,
                angle,
            ),
            1 => {
                let (a, b) = (self.range(0.1, 2.0), self.range(0.1, 2.0));
                body(RShape::Ellipse { a, b }, pos, angle)
            }
            2 => {
                let (w, h) = (self.range(0.1, 2.0), self.range(0.1, 2.0));
                body(RShape::Rectangle { w, h }, pos, angle)
            }
            _ => wall(pos, [self.range(-1.0, 1.0), self.range(-1.0, 1.0)]),
        }
    }
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

/// `n` points evenly spaced (in parameter) along a body's boundary.
fn boundary_f64(o: &RObj, n: usize) -> Vec<[f64; 2]> {
    let RObj::Body { shape, pos, angle } = *o else {
        return Vec::new();
    };
    let (c, s) = (angle.cos(), angle.sin());
    (0..n)
        .map(|k| {
            let t = k as f64 / n as f64;
            let q = t * std::f64::consts::TAU;
            let (l1, l2) = match shape {
                RShape::Circle { r } => (r * q.cos(), r * q.sin()),
                RShape::Ellipse { a, b } => (a * q.cos(), b * q.sin()),
                RShape::Rectangle { w, h } => {
                    let u = t * 2.0 * (w + h);
                    let (hw, hh) = (w / 2.0, h / 2.0);
                    if u < w {
                        (u - hw, -hh)
                    } else if u < w + h {
                        (hw, u - w - hh)
                    } else if u < 2.0 * w + h {
                        (hw - (u - w - h), hh)
                    } else {
                        (-hw, hh - (u - 2.0 * w - h))
                    }
                }
            };
            [pos[0] + c * l1 - s * l2, pos[1] + s * l1 + c * l2]
        })
        .collect()
}

/// Random pairs of all kinds: swap symmetry, crossings on both boundaries, the
/// crossing count against brute-force sign changes along a finely sampled
/// boundary, and containment/separation against sampled boundaries.
#[test]
fn random_pairs_consistency() {
    let mut g = Lcg(12345);
    for it in 0..3000 {
        let i = g.object(true);
        let j = g.object(!matches!(i, RObj::Wall { .. }));
        let c = reference_contact(&i, &j);
        let s = reference_contact(&j, &i);
        assert_eq!(c.state, s.state, "it {it}: {i:?} {j:?}");
        for p in &c.crossings {
            let w = [c.origin[0] + p[0], c.origin[1] + p[1]];
            assert!(inside_f64(&i, w).abs() < 1e-12, "it {it}: crossing off i");
            assert!(inside_f64(&j, w).abs() < 1e-12, "it {it}: crossing off j");
        }
        if c.state == RState::Overlap {
            let (n, m) = (c.normal.unwrap(), s.normal.unwrap());
            assert_vclose("swapped normal", n, [-m[0], -m[1]], 1e-14);
            assert_close("swapped depth", c.depth.unwrap(), s.depth.unwrap(), 1e-14);
            assert_close(
                "depth_along",
                depth_along(&i, &j, n),
                c.depth.unwrap(),
                1e-14,
            );
        }
        let (walker, other) = if matches!(i, RObj::Wall { .. }) {
            (&j, &i)
        } else {
            (&i, &j)
        };
        let vals: Vec<f64> = boundary_f64(walker, 4000)
            .into_iter()
            .map(|p| inside_f64(other, p))
            .collect();
        let changes = vals
            .iter()
            .zip(vals.iter().cycle().skip(1))
            .filter(|(a, b)| (**a > 0.0) != (**b > 0.0))
            .count();
        let other_pts = boundary_f64(other, 200);
        match c.state {
            RState::Overlap => assert_eq!(changes, 2, "it {it}"),
            RState::Deep(n) => assert_eq!(changes, n, "it {it}"),
            RState::Contained => {
                assert_eq!(changes, 0, "it {it}");
                let walker_in = vals.iter().all(|v| *v < 0.0);
                let other_in =
                    !other_pts.is_empty() && other_pts.iter().all(|p| inside_f64(walker, *p) < 0.0);
                assert!(walker_in || other_in, "it {it}: not contained");
            }
            RState::Separated => {
                assert_eq!(changes, 0, "it {it}");
                assert!(vals.iter().all(|v| *v > 0.0), "it {it}");
                assert!(
                    other_pts.iter().all(|p| inside_f64(walker, *p) > 0.0),
                    "it {it}"
                );
            }
            RState::Touching => panic!("it {it}: unexpected tangency"),
        }
    }
}

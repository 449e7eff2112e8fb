//! The energy-conserving normal force (`normal_force: "area"`), against independent references:
//!
//! - **force = −∇W**: the force and moment the dynamics applies (a two-body world, forces
//!   evaluated by the step's own path) equal a fourth-order central difference of
//!   `W(A)`, with the overlap area `A` from the double-double reference
//!   (`dem2d_validation::overlap_reference`, no pencil, no chord), for random overlapping pairs
//!   of every kind, δ/b from 1e-6 to 0.2, aspect ratios 1 to 10;
//! - **closed loops**: the work of the force and moment around closed loops in (x, y, θ) is zero
//!   to ≤ 1e-9 of |F| × the loop's size, for every pair kind — and the depth law's loops, the
//!   control, gain what the issue measured (0.10 and 0.46 of F·Δx);
//! - **the area itself** against the reference, δ/b from 1e-9 to 0.3, at the origin and 1e6
//!   away.
//!
//! Convex polygons: the closed loops for every pair kind with a polygon are here
//! (`no_work_around_closed_loops_for_polygon_pairs`); their force = −∇W and area checks against
//! their own double-double reference are in `tests/polygons.rs`.

use dem2d::contact_law::{ContactSpec, EquivalentOverlap, LinearDamping, NormalForce, Scaled};
use dem2d::dynamics::{Boundary, World};
use dem2d::geometry::overlap_area::DiskLens;
use dem2d::geometry::{Polygon, Pose, Shape, Vec2, Wall};
use dem2d::narrow_phase::{ContactState, Object, contact};
use dem2d::run::Simulation;
use dem2d_validation::overlap_reference::{OverlapState, reference_overlap};
use dem2d_validation::reference::{RObj, RShape};
use dem2d_validation::rng::Rng;

mod common;
use common::{body, floor, worst_energy_error};

/// k_n of the tests' linear law (undamped, frictionless).
const KN: f64 = 1.0;

fn spec(normal_force: NormalForce) -> ContactSpec {
    ContactSpec::linear(
        Scaled::Absolute(KN),
        Scaled::Absolute(KN),
        LinearDamping::Dashpots {
            eta_n: Scaled::Absolute(0.0),
            eta_s: Scaled::Absolute(0.0),
        },
        0.0,
    )
    .with_normal_force(normal_force)
}

/// One side of a pair: a body (shape, position, angle) or a wall.
#[derive(Clone, Copy, Debug)]
enum Side {
    Body(Shape, Vec2, f64),
    Wall(Wall),
}

fn r_shape(s: &Shape) -> RShape {
    match *s {
        Shape::Circle { r } => RShape::Circle { r },
        Shape::Ellipse { a, b } => RShape::Ellipse { a, b },
        Shape::Rectangle { w, h } => RShape::Rectangle { w, h },
        Shape::Polygon(_) => unreachable!("polygons have their own reference (tests/polygons.rs)"),
        Shape::Clump(_) => unreachable!("clumps: tests/clumps.rs"),
    }
}

fn r_obj(s: &Side) -> RObj {
    match *s {
        Side::Body(shape, x, angle) => RObj::Body {
            shape: r_shape(&shape),
            pos: [x.x, x.y],
            angle,
        },
        Side::Wall(w) => RObj::Wall {
            point: [w.point.x, w.point.y],
            normal: [w.normal.x, w.normal.y],
        },
    }
}

fn object(s: &Side) -> Object {
    match *s {
        Side::Body(shape, x, angle) => Object::Body {
            shape,
            pose: Pose::new(x, angle),
        },
        Side::Wall(w) => Object::Wall(w),
    }
}

/// Force and moment (about its centroid) on body j from i, as the step computes them.
fn force_on_j(i: &Side, j: &Side, nf: NormalForce) -> (Vec2, f64) {
    let Side::Body(sj, xj, tj) = *j else {
        panic!("j must be a body")
    };
    let (bodies, walls, k) = match *i {
        Side::Body(si, xi, ti) => (vec![body(si, xi, ti), body(sj, xj, tj)], vec![], 1),
        Side::Wall(w) => (vec![body(sj, xj, tj)], vec![Boundary::new(w, spec(nf))], 0),
    };
    let w = World::new(&bodies, walls, Vec2::zeros(), spec(nf), 1e-6);
    (w.bodies.force[k], w.bodies.torque[k])
}

fn moved(j: &Side, dx: f64, dy: f64, dth: f64) -> Side {
    match *j {
        Side::Body(s, x, t) => Side::Body(s, x + Vec2::new(dx, dy), t + dth),
        w => w,
    }
}

fn equal_area_radius(s: &Side) -> f64 {
    match *s {
        Side::Body(shape, ..) => {
            (dem2d::geometry::mass::area(&shape) / std::f64::consts::PI).sqrt()
        }
        Side::Wall(_) => f64::INFINITY,
    }
}

/// A body's bounding radius (0 for a wall).
fn size(s: &Side) -> f64 {
    match s {
        Side::Body(shape, ..) => shape.bounding_radius(),
        Side::Wall(_) => 0.0,
    }
}

fn is_rectangle(s: &Side) -> bool {
    matches!(s, Side::Body(Shape::Rectangle { .. }, ..))
}

/// `W(A)` as the law defines it for the pair (see `contact_law`): ½ k_n δ_eq(A)², with δ_eq the
/// equal-area disks' lens overlap (its series), or A/ℓ between two rectangles; two disks (or a
/// disk and a wall) keep the spring on their depth, the exact lens inverse.
fn potential(i: &Side, j: &Side, area: f64) -> f64 {
    let disk = |s: &Side| matches!(s, Side::Body(Shape::Circle { .. }, ..) | Side::Wall(_));
    if disk(i) && disk(j) {
        let (d, _) = DiskLens::new(equal_area_radius(i), equal_area_radius(j)).depth_for_area(area);
        return 0.5 * KN * d * d;
    }
    let face = |s: &Side| match *s {
        Side::Body(Shape::Rectangle { w, h }, ..) => 0.5 * (w + h),
        _ => unreachable!(),
    };
    let eq = if is_rectangle(i) && is_rectangle(j) {
        EquivalentOverlap::Flat(0.5 * (face(i) + face(j)))
    } else {
        EquivalentOverlap::Lens(DiskLens::new(equal_area_radius(i), equal_area_radius(j)))
    };
    let (d, _) = eq.depth_for_area(area);
    0.5 * KN * d * d
}

fn ref_area(i: &Side, j: &Side) -> f64 {
    reference_overlap(&r_obj(i), &r_obj(j)).area
}

/// Fourth-order central difference `(−f(2h) + 8f(h) − 8f(−h) + f(−2h)) / 12h`.
fn fd4(f: impl Fn(f64) -> f64, h: f64) -> f64 {
    (-f(2.0 * h) + 8.0 * f(h) - 8.0 * f(-h) + f(-2.0 * h)) / (12.0 * h)
}

/// The largest power of two not above `x` (so that `x ± h` are exact for coarse positions).
fn pow2(x: f64) -> f64 {
    2f64.powi(x.log2().floor() as i32)
}

/// A random shape with aspect ratio in [1, 10] and its smaller half-size `b`.
fn random_shape(rng: &mut Rng, kind: usize) -> (Shape, f64) {
    let size = rng.range(0.5, 2.0);
    let aspect = (rng.range(0.0, 10f64.ln())).exp();
    match kind {
        0 => (Shape::Circle { r: size }, size),
        1 => (
            Shape::Ellipse {
                a: size * aspect.sqrt(),
                b: size / aspect.sqrt(),
            },
            size / aspect.sqrt(),
        ),
        2 => (
            Shape::Rectangle {
                w: 2.0 * size * aspect.sqrt(),
                h: 2.0 * size / aspect.sqrt(),
            },
            size / aspect.sqrt(),
        ),
        _ => {
            // A convex polygon: 3 to 12 vertices on the ellipse (a, b), one per sector.
            let (a, b) = (size * aspect.sqrt(), size / aspect.sqrt());
            let n = 3 + (rng.uniform() * 10.0) as usize;
            let sector = std::f64::consts::TAU / n as f64;
            let v: Vec<[f64; 2]> = (0..n)
                .map(|k| {
                    let t = sector * (k as f64 + rng.range(0.1, 0.9));
                    [a * t.cos(), b * t.sin()]
                })
                .collect();
            let p = Polygon::new(&v).expect("convex");
            let half = p.inscribed_radius;
            (Shape::Polygon(p), half)
        }
    }
}

fn support(shape: &Shape, angle: f64, u: Vec2) -> f64 {
    let (c, s) = (angle.cos(), angle.sin());
    dem2d::geometry::support::support_local(shape, c * u.x + s * u.y, -s * u.x + c * u.y)
}

/// Rounds to a multiple of 2⁻²⁴ (so that small power-of-two steps are exact).
fn coarse(x: f64) -> f64 {
    (x * 16_777_216.0).round() / 16_777_216.0
}

/// A random overlapping pair of the given kinds (i: 0 circle, 1 ellipse, 2 rectangle, 3 wall,
/// 4 polygon; j: a body), overlapping by about `ratio` × j's (and i's) smaller half-size along a random
/// line of centres.
fn random_pair(rng: &mut Rng, ki: usize, kj: usize, ratio: f64) -> (Side, Side, f64) {
    let (sj, bj) = random_shape(rng, kj);
    let tj = coarse(rng.angle());
    if ki == 3 {
        let normal = Vec2::new(rng.range(-0.3, 0.3), 1.0).normalize();
        let wall = Wall::new(Vec2::new(0.0, 0.0), normal).unwrap();
        let h = support(&sj, tj, -normal) - ratio * bj;
        let x = Vec2::new(coarse(rng.range(-1.0, 1.0)), 0.0);
        let x = Vec2::new(x.x, coarse((h - normal.x * x.x) / normal.y));
        return (Side::Wall(wall), Side::Body(sj, x, tj), bj);
    }
    let (si, bi) = random_shape(rng, ki);
    let ti = coarse(rng.angle());
    let phi = rng.angle();
    let u = Vec2::new(phi.cos(), phi.sin());
    let b = bi.min(bj);
    // The distance along u at which they first touch (bisection on the narrow phase's state:
    // overlapping supports along u do not make an overlap), then pushed in by ratio × b.
    let i = Side::Body(si, Vec2::zeros(), ti);
    let overlaps = |d: f64| {
        let j = Side::Body(sj, u * d, tj);
        contact(&object(&i), &object(&j)).is_some()
    };
    let (mut lo, mut hi) = (0.0, support(&si, ti, u) + support(&sj, tj, -u));
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if overlaps(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let d = lo - ratio * b;
    let x = Vec2::new(coarse(d * u.x), coarse(d * u.y));
    (i, Side::Body(sj, x, tj), b)
}

#[test]
fn force_and_moment_are_minus_the_gradient_of_the_area_potential() {
    let mut rng = Rng(0x5eed_a4ea);
    let (mut worst_f, mut worst_m, mut checked) = (0.0f64, 0.0f64, 0);
    let mut deep = 0;
    // Crossed pairs (four or more crossings): a thin ellipse or rectangle across another body.
    let thin_e = Shape::Ellipse { a: 2.0, b: 0.25 };
    let thin_r = Shape::Rectangle { w: 4.0, h: 0.5 };
    for k in 0..48 {
        let (si, sj) = [
            (thin_e, thin_e),
            (thin_r, thin_r),
            (thin_r, thin_e),
            (thin_e, Shape::Ellipse { a: 1.2, b: 0.9 }),
        ][k % 4];
        let i = Side::Body(si, Vec2::zeros(), coarse(rng.range(-0.2, 0.2)));
        let x = Vec2::new(coarse(rng.range(-0.3, 0.3)), coarse(rng.range(-0.3, 0.3)));
        let j = Side::Body(
            sj,
            x,
            coarse(std::f64::consts::FRAC_PI_2 + rng.range(-0.5, 0.5)),
        );
        let Some(c) = contact(&object(&i), &object(&j)) else {
            continue;
        };
        if c.state != ContactState::Deep {
            continue;
        }
        let (f, m) = force_on_j(&i, &j, NormalForce::Area);
        let w =
            |dx: f64, dy: f64, dth: f64| potential(&i, &j, ref_area(&i, &moved(&j, dx, dy, dth)));
        let (h, ht) = (pow2(1e-3), pow2(1e-3));
        let (gx, gy, gt) = (
            fd4(|s| w(s, 0.0, 0.0), h),
            fd4(|s| w(0.0, s, 0.0), h),
            fd4(|s| w(0.0, 0.0, s), ht),
        );
        let scale = f.norm().max(gt.abs());
        let ef = ((f.x + gx).powi(2) + (f.y + gy).powi(2)).sqrt() / scale;
        let em = (m + gt).abs() / scale;
        assert!(
            ef <= 1e-7 && em <= 1e-7,
            "crossed pair {i:?} {j:?}: force {f:?} vs −∇W ({}, {}), moment {m} vs {}: errors {ef:.1e}, {em:.1e}",
            -gx,
            -gy,
            -gt
        );
        worst_f = worst_f.max(ef);
        worst_m = worst_m.max(em);
        deep += 1;
        checked += 1;
    }
    for (ki, kj) in [
        (1, 1),
        (0, 1),
        (1, 0),
        (3, 1),
        (2, 1),
        (1, 2),
        (2, 0),
        (2, 2),
        (3, 0),
    ] {
        for k in 0..24 {
            let ratio = 10f64.powf(-6.0 + 5.3 * k as f64 / 23.0); // 1e-6 … 0.2
            let (i, j, b) = random_pair(&mut rng, ki, kj, ratio);
            let Some(c) = contact(&object(&i), &object(&j)) else {
                continue;
            };
            let (ContactState::Overlap | ContactState::Deep) = c.state else {
                continue;
            };
            deep += usize::from(c.state == ContactState::Deep);
            let depth = c.depth;
            let (f, m) = force_on_j(&i, &j, NormalForce::Area);
            let w = |dx: f64, dy: f64, dth: f64| {
                potential(&i, &j, ref_area(&i, &moved(&j, dx, dy, dth)))
            };
            let h = pow2(0.01 * depth);
            let hb = match j {
                Side::Body(s, ..) => s.bounding_radius(),
                _ => unreachable!(),
            };
            let ht = pow2(0.01 * depth / hb);
            let gx = fd4(|s| w(s, 0.0, 0.0), h);
            let gy = fd4(|s| w(0.0, s, 0.0), h);
            let gt = fd4(|s| w(0.0, 0.0, s), ht);
            let scale = f.norm();
            let ef = ((f.x + gx).powi(2) + (f.y + gy).powi(2)).sqrt() / scale;
            let em = (m + gt).abs() / (scale * hb);
            assert!(
                ef <= 1e-7 && em <= 1e-7,
                "pair {ki}-{kj} {i:?} {j:?}, δ/b = {:.1e}: force {f:?} vs −∇W ({}, {}), moment {m} vs {}: errors {ef:.1e}, {em:.1e}",
                depth / b,
                -gx,
                -gy,
                -gt
            );
            worst_f = worst_f.max(ef);
            worst_m = worst_m.max(em);
            checked += 1;
        }
    }
    eprintln!(
        "force = −∇W(A_ref): {checked} pairs ({deep} deep), worst force error {worst_f:.1e} of |F|, moment {worst_m:.1e} of |F|·R"
    );
    assert!(checked >= 150, "only {checked} overlapping pairs checked");
    assert!(deep >= 20, "only {deep} deep pairs checked");
}

/// Work of the force and moment on j around the closed loop through the corners `c0 → c1 → c2 →
/// c3 → c0` in (x, y, θ), each leg by 16-point Gauss–Legendre quadrature (the force is smooth
/// along a leg).
fn loop_work(i: &Side, j: &Side, corners: [[f64; 3]; 4], nf: NormalForce) -> (f64, f64) {
    let (w, _, fmax) = loop_work_mean(i, j, corners, nf);
    (w, fmax)
}

/// [`loop_work`] with the mean |F| over the loop's length as well: `(work, mean, max)`.
fn loop_work_mean(i: &Side, j: &Side, corners: [[f64; 3]; 4], nf: NormalForce) -> (f64, f64, f64) {
    let (mut work, mut fmax, mut fsum) = (0.0, 0.0f64, 0.0);
    for leg in 0..4 {
        let (w, m, f) = leg_work(i, j, corners[leg], corners[(leg + 1) % 4], 1, nf);
        work += w;
        fsum += m;
        fmax = fmax.max(f);
    }
    (work, fsum, fmax)
}

/// Work of the force and moment on j along the straight leg from `a` to `z` in (x, y, θ), cut
/// into `pieces` equal parts, each by 16-point Gauss–Legendre quadrature: `(work, mean |F| ×
/// ¼ (the leg's share of a four-leg loop's mean), max |F|)`.
fn leg_work(
    i: &Side,
    j: &Side,
    a: [f64; 3],
    z: [f64; 3],
    pieces: usize,
    nf: NormalForce,
) -> (f64, f64, f64) {
    // Nodes and weights of 16-point Gauss–Legendre on [−1, 1] (positive half).
    const X: [f64; 8] = [
        0.0950125098376374,
        0.2816035507792589,
        0.4580167776572274,
        0.6178762444026438,
        0.755404408355003,
        0.8656312023878318,
        0.9445750230732326,
        0.9894009349916499,
    ];
    const W: [f64; 8] = [
        0.1894506104550685,
        0.1826034150449236,
        0.1691565193950025,
        0.1495959888165767,
        0.1246289712555339,
        0.0951585116824928,
        0.0622535239386479,
        0.0271524594117541,
    ];
    let (mut work, mut fmax, mut fsum) = (0.0, 0.0f64, 0.0);
    let d = [z[0] - a[0], z[1] - a[1], z[2] - a[2]];
    let h = 1.0 / pieces as f64;
    for piece in 0..pieces {
        for (x, wt) in X
            .iter()
            .flat_map(|&x| [x, -x])
            .zip(W.iter().flat_map(|&w| [w, w]))
        {
            let s = h * (piece as f64 + 0.5 * (1.0 + x));
            let p = moved(j, a[0] + s * d[0], a[1] + s * d[1], a[2] + s * d[2]);
            let (f, m) = force_on_j(i, &p, nf);
            fmax = fmax.max(f.norm());
            fsum += 0.125 * h * wt * f.norm();
            work += 0.5 * h * wt * (f.x * d[0] + f.y * d[1] + m * d[2]);
        }
    }
    (work, fsum, fmax)
}

/// A rectangular loop in the (x, θ) or (x, y) plane about j's pose.
fn around(dx: f64, second: f64, theta: bool) -> [[f64; 3]; 4] {
    let (p, q) = if theta {
        ([0.0, 0.0, second], [dx, 0.0, 0.0])
    } else {
        ([0.0, second, 0.0], [dx, 0.0, 0.0])
    };
    let c = |s: f64, t: f64| {
        [
            s * q[0] + t * p[0],
            s * q[1] + t * p[1],
            s * q[2] + t * p[2],
        ]
    };
    [c(-1.0, -1.0), c(1.0, -1.0), c(1.0, 1.0), c(-1.0, 1.0)]
}

#[test]
fn the_issues_loops_gain_work_under_the_depth_law_and_none_under_the_area_law() {
    let e = Shape::Ellipse { a: 1.5, b: 1.0 };
    let pair = (
        Side::Body(e, Vec2::zeros(), 0.3),
        Side::Body(e, Vec2::new(2.45, 0.2), 0.9),
    );
    let floor = Side::Wall(Wall::new(Vec2::zeros(), Vec2::new(0.0, 1.0)).unwrap());
    let on_floor = Side::Body(e, Vec2::new(0.0, 0.95), 0.6);
    // (pair, loop, size in x or y, what the issue measured for the depth law)
    let cases = [
        (&pair.0, &pair.1, around(0.03, 0.3, true), 2.0 * 0.03, 0.10),
        (
            &floor,
            &on_floor,
            [
                [0.0, -0.02, -0.3],
                [0.0, 0.02, -0.3],
                [0.0, 0.02, 0.3],
                [0.0, -0.02, 0.3],
            ],
            2.0 * 0.02,
            0.46,
        ),
    ];
    for (i, j, corners, size, issue) in cases {
        let (w_depth, f_mean, f_depth) = loop_work_mean(i, j, corners, NormalForce::Depth);
        let (w_area, f_area, _) = loop_work_mean(i, j, corners, NormalForce::Area);
        // Gains per turn in units of the mean |F| along the loop times its extent in x (or y).
        let gain_depth = w_depth.abs() / (f_mean * size);
        let gain_area = w_area.abs() / (f_area * size);
        eprintln!(
            "loop: the depth law gains {gain_depth:.3} × F·Δ per turn (the issue measured {issue}), the area law {gain_area:.1e} (max |F| {f_depth:.3}, {f_area:.3})"
        );
        // The control: the depth law's force is not a gradient, and the loop shows it.
        assert!(gain_depth > 0.05, "depth law's loop gain {gain_depth}");
        assert!(gain_area <= 1e-9, "area law's loop gain {gain_area:e}");
    }
}

#[test]
fn no_work_around_closed_loops_for_any_pair_kind() {
    let mut rng = Rng(0x0001_00b5);
    let mut worst = 0.0f64;
    let mut count = 0;
    for (ki, kj) in [(1, 1), (0, 1), (3, 1), (2, 1), (2, 0), (2, 2), (3, 2)] {
        for k in 0..4 {
            let ratio = [1e-3, 1e-2, 0.05, 0.15][k];
            let (i, j, b) = random_pair(&mut rng, ki, kj, ratio);
            let Some(c) = contact(&object(&i), &object(&j)) else {
                continue;
            };
            if c.state != ContactState::Overlap {
                continue;
            }
            let depth = c.depth;
            // Small enough loops that the contact keeps its two crossings (and a rectangle its
            // corners on the same sides) all the way round.
            let dx = 0.05 * depth;
            let dth = 0.05 * depth / b.max(0.5);
            for corners in [around(dx, dth, true), around(dx, dx, false)] {
                let (w, fmax) = loop_work(&i, &j, corners, NormalForce::Area);
                let gain = w.abs() / (fmax * 2.0 * dx);
                worst = worst.max(gain);
                count += 1;
                assert!(
                    gain <= 1e-9,
                    "pair {ki}-{kj}, δ/b = {:.1e}: loop gains {gain:e}",
                    depth / b
                );
            }
        }
    }
    eprintln!("closed loops (area law): {count}, worst |work| / (F × size) = {worst:.1e}");
    assert!(count >= 30);
}

/// The same closed loops for every pair kind with a convex polygon (kind 4): polygon with
/// polygon, circle, ellipse, rectangle and wall, under the area law.
#[test]
fn no_work_around_closed_loops_for_polygon_pairs() {
    let mut rng = Rng(0x0016_00b5);
    let mut worst = 0.0f64;
    let mut count = 0;
    for (ki, kj) in [
        (4, 4),
        (4, 0),
        (0, 4),
        (4, 1),
        (1, 4),
        (2, 4),
        (4, 2),
        (3, 4),
    ] {
        for k in 0..4 {
            let ratio = [1e-3, 1e-2, 0.05, 0.15][k];
            let (i, j, b) = random_pair(&mut rng, ki, kj, ratio);
            let Some(c) = contact(&object(&i), &object(&j)) else {
                continue;
            };
            if c.state != ContactState::Overlap {
                continue;
            }
            let depth = c.depth;
            // Small enough loops that the contact keeps its two crossings on the same edges.
            let dx = 0.05 * depth;
            let dth = 0.05 * depth / b.max(0.5);
            for corners in [around(dx, dth, true), around(dx, dx, false)] {
                // A vertex passing an edge line during the loop makes the force's derivative
                // jump (A stays C¹), where Gauss–Legendre converges only like (piece length)²:
                // one 16-point rule per leg gained 8e-6, 128 pieces 3.4e-9 and 1024 pieces
                // 4e-11 on the worst wall–polygon loop (whose force is −∇W(A) to rounding: a
                // 40 000-interval Simpson sum closes the loop to 6e-17 of the leg's work).
                let (mut w, mut fmax) = (0.0, 0.0f64);
                for leg in 0..4 {
                    let (a, z) = (corners[leg], corners[(leg + 1) % 4]);
                    let (lw, _, f) = leg_work(&i, &j, a, z, 1024, NormalForce::Area);
                    w += lw;
                    fmax = fmax.max(f);
                }
                let gain = w.abs() / (fmax * 2.0 * dx);
                worst = worst.max(gain);
                count += 1;
                assert!(
                    gain <= 1e-9,
                    "pair {ki}-{kj}, δ/b = {:.1e}: loop gains {gain:e}",
                    depth / b
                );
            }
        }
    }
    eprintln!("polygon closed loops (area law): {count}, worst |work| / (F × size) = {worst:.1e}");
    assert!(count >= 40, "{count}");
}

#[test]
fn overlap_area_matches_the_double_double_reference() {
    let mut rng = Rng(0xa4ea);
    let mut worst_cond = 0.0f64;
    let mut count = 0;
    let mut by_decade = [0.0f64; 9];
    for offset in [0.0, 1e6] {
        for (ki, kj) in [
            (1, 1),
            (0, 1),
            (3, 1),
            (2, 1),
            (2, 2),
            (3, 2),
            (0, 0),
            (3, 0),
        ] {
            for k in 0..20 {
                let ratio = 10f64.powf(-9.0 + 8.5 * k as f64 / 19.0); // 1e-9 … 0.3
                let (i, j, b) = random_pair(&mut rng, ki, kj, ratio);
                let shift = |s: Side| match s {
                    Side::Body(sh, x, t) => Side::Body(sh, x + Vec2::new(offset, -offset), t),
                    Side::Wall(w) => Side::Wall(
                        Wall::new(w.point + Vec2::new(offset, -offset), w.normal).unwrap(),
                    ),
                };
                let (i, j) = (shift(i), shift(j));
                let reference = reference_overlap(&r_obj(&i), &r_obj(&j));
                if !matches!(reference.state, OverlapState::Overlap) {
                    continue;
                }
                let c = contact(&object(&i), &object(&j)).unwrap();
                let Some(a) = c.area else {
                    panic!("no area for an overlapping pair {ki}-{kj}: {c:?}")
                };
                let err = (a.area - reference.area).abs();
                let rel = err / reference.area;
                // The area's conditioning: a rounding ε·a_max of the relative pose (a_max the
                // larger body's size) moves the chord by that much, changing A by about
                // L·ε·a_max (L the chord). Measured in those units.
                let a_max = size(&i).max(size(&j));
                let cond = err / (a.length * f64::EPSILON * a_max);
                let decade = (c.depth / b).log10().floor().clamp(-9.0, -1.0) as i32;
                let slot = &mut by_decade[(decade + 9) as usize];
                *slot = slot.max(rel);
                // The bar: an area error no larger than the chord times the kernel's depth bar
                // (1e-12·a_max), i.e. as accurate as the depth itself.
                assert!(
                    cond * f64::EPSILON <= 1e-12,
                    "offset {offset}, pair {ki}-{kj} {i:?} {j:?}, δ/b = {:.1e}: area {} vs {} ({cond:.1} × L·ε·size)",
                    c.depth / b,
                    a.area,
                    reference.area
                );
                worst_cond = worst_cond.max(cond);
                count += 1;
            }
        }
    }
    eprintln!(
        "area vs reference: {count} pairs at offsets 0 and 1e6; worst error {worst_cond:.1} × L·ε·size"
    );
    for (k, rel) in by_decade.iter().enumerate() {
        eprintln!(
            "  δ/b in [1e{}, 1e{}): worst relative error {rel:.1e}",
            k as i32 - 9,
            k as i32 - 8
        );
    }
    // Where the conditioning allows it (δ/b ≥ 0.1), the issue's 1e-13 relative.
    assert!(by_decade[8] <= 1e-13, "{by_decade:?}");
    assert!(count >= 200, "only {count} pairs");
}

/// A world for the energy tests: `kn_over_rho_g` = P's 36400 cm, ρ = 1, undamped or with a
/// restitution, frictionless.
fn energy_spec(nf: NormalForce, restitution: Option<f64>) -> ContactSpec {
    ContactSpec::linear(
        Scaled::Absolute(36400.0 * 980.0),
        Scaled::Absolute(36400.0 * 980.0),
        match restitution {
            Some(e) => LinearDamping::Restitution(e),
            None => LinearDamping::Dashpots {
                eta_n: Scaled::Absolute(0.0),
                eta_s: Scaled::Absolute(0.0),
            },
        },
        0.0,
    )
    .with_normal_force(nf)
}

/// The largest |E − E₀|/E₀ over `steps` steps (E = kinetic + potential + elastic; nothing
/// dissipates).
fn energy_drift(mut w: World, steps: u64) -> f64 {
    worst_energy_error(Simulation::new(&mut w).for_steps(steps))
}

/// An ellipse (1.5, 1) dropped tilted and spinning onto a floor: three bounces in 0.6 s;
/// `phase` (0…1) shifts the release height so that impacts fall elsewhere within a step.
fn ellipse_bouncing(nf: NormalForce, dt: f64, phase: f64) -> World {
    let spec = energy_spec(nf, None);
    let floor = floor(spec);
    let mut body = body(
        Shape::Ellipse { a: 1.5, b: 1.0 },
        Vec2::new(0.0, 2.2 + 0.013 * phase),
        0.5,
    );
    body.omega = 3.0;
    World::new(&[body], vec![floor], Vec2::new(0.0, -980.0), spec, dt)
}

/// Two ellipses colliding off-centre in free space (energy: kinetic + elastic only); `phase`
/// (0…1) shifts the first one's start.
fn ellipses_colliding(nf: NormalForce, dt: f64, phase: f64) -> World {
    let e = Shape::Ellipse { a: 1.5, b: 1.0 };
    let mut a = body(e, Vec2::new(-0.006 * phase, 0.0), 0.3);
    let mut b = body(e, Vec2::new(4.0, 0.9), 1.2);
    a.velocity = Vec2::new(60.0, 0.0);
    b.velocity = Vec2::new(-40.0, 5.0);
    b.omega = -2.0;
    World::new(&[a, b], vec![], Vec2::zeros(), energy_spec(nf, None), dt)
}

#[test]
fn undamped_frictionless_ellipses_conserve_energy_to_second_order() {
    for (name, scene, duration) in [
        (
            "ellipse bouncing on a floor",
            ellipse_bouncing as fn(NormalForce, f64, f64) -> World,
            0.6,
        ),
        ("ellipses colliding off-centre", ellipses_colliding, 0.05),
    ] {
        let dts = [4e-6, 2e-6, 1e-6];
        // The error of an impact depends on where its onset falls within a step (the force's
        // derivative jumps there): averaged over eight phases.
        let drift = |nf, dt: f64| {
            (0..8)
                .map(|k| {
                    energy_drift(
                        scene(nf, dt, k as f64 / 8.0),
                        (duration / dt).round() as u64,
                    )
                })
                .sum::<f64>()
                / 8.0
        };
        let area: Vec<f64> = dts.iter().map(|&dt| drift(NormalForce::Area, dt)).collect();
        let depth: Vec<f64> = dts
            .iter()
            .map(|&dt| drift(NormalForce::Depth, dt))
            .collect();
        let order = |e: &[f64]| (e[0] / e[2]).log2() / 2.0;
        eprintln!(
            "{name}: max |ΔE/E| at Δt = 4e-6, 2e-6, 1e-6 s — area law {:.1e} {:.1e} {:.1e} (order {:.2}); depth law {:.1e} {:.1e} {:.1e} (order {:.2})",
            area[0],
            area[1],
            area[2],
            order(&area),
            depth[0],
            depth[1],
            depth[2],
            order(&depth)
        );
        // Second order: halving Δt divides the error by about four.
        assert!(order(&area) > 1.8, "{name}: order {}", order(&area));
        assert!(area[2] < 1e-5, "{name}: {area:?}");
        // The control: the depth law's error does not converge with Δt.
        assert!(
            order(&depth) < 0.5 && depth[2] > 1e-4,
            "{name}: depth law {depth:?}"
        );
    }
}

/// Rebound speed over impact speed of a body thrown at a floor without gravity (a flat impact:
/// no rotation), under the linear law with restitution `e` or Hertz–Mindlin.
fn obtained_restitution(shape: Shape, angle: f64, nf: NormalForce, e: f64, hertz: bool) -> f64 {
    let spec = if hertz {
        ContactSpec::hertz_mindlin(1e8, 0.3, e, 0.0).with_normal_force(nf)
    } else {
        energy_spec(nf, Some(e))
    };
    let floor = floor(spec);
    let h = support(&shape, angle, Vec2::new(0.0, -1.0));
    let mut body = body(shape, Vec2::new(0.0, h + 0.05), angle);
    let v0 = 50.0;
    body.velocity = Vec2::new(0.0, -v0);
    let mut w = World::new(&[body], vec![floor], Vec2::zeros(), spec, 2e-7);
    let mut touched = false;
    Simulation::new(&mut w)
        .run_until(|w, _| {
            let c = !w.contacts.is_empty();
            touched |= c;
            touched && !c
        })
        .unwrap();
    w.bodies.state[0].vel.y / v0
}

#[test]
fn requested_restitution_keeps_its_meaning_under_the_area_law() {
    let disk = Shape::Circle { r: 1.5f64.sqrt() };
    let ellipse = Shape::Ellipse { a: 1.5, b: 1.0 };
    for hertz in [false, true] {
        for e in [0.9, 0.7, 0.5, 0.3] {
            let d = obtained_restitution(disk, 0.0, NormalForce::Depth, e, hertz);
            let flat = obtained_restitution(ellipse, 0.0, NormalForce::Area, e, hertz);
            let tip = obtained_restitution(
                ellipse,
                std::f64::consts::FRAC_PI_2,
                NormalForce::Area,
                e,
                hertz,
            );
            let flat_depth = obtained_restitution(ellipse, 0.0, NormalForce::Depth, e, hertz);
            eprintln!(
                "{} e = {e}: disk {d:.4}; ellipse (area law) flat side {flat:.4}, tip {tip:.4}; (depth law) flat {flat_depth:.4}",
                if hertz { "Hertz " } else { "linear" }
            );
            // The dashpot acts on δ_eq with η/ρ: the damping ratio, hence e, is the disk's
            // (itself the exact clamped solution, tests/dynamics_analytic.rs).
            assert!(
                (flat - d).abs() < 1e-3 && (tip - d).abs() < 1e-3,
                "{flat} {tip} vs {d}"
            );
        }
    }
}

//! Convex polygons as a shape (issue 16, item 1), against independent references:
//!
//! - **every polygon pair kind against the double-double reference**
//!   (`dem2d_validation::polygon_reference`: DD clipping, segment intersections, disk ∩
//!   triangle sums): the overlap area and the two boundary crossings, δ/b from 1e-9 to 0.3, at
//!   the origin and 1e6 away;
//! - **closed forms for disks**: a circle cut by a polygon's face (a circular segment), a circle
//!   inside a polygon and a polygon inside a circle;
//! - **convergence to the conic**: equal-area n-gons (n = 8 … 128) of P's ellipse (a = 1.5,
//!   b = 1 cm) against a floor and against another ellipse: the contact depth and the area
//!   law's force converge to the ellipse's, and the order is measured;
//! - the outline drawn is the polygon's own vertices.
//!
//! Swap symmetry and the loop work of the area law for polygon pairs are in
//! `tests/swap_symmetry.rs` and `tests/area_law.rs`.

use dem2d::contact_law::{ContactSpec, LinearDamping, Scaled};
use dem2d::dynamics::{Boundary, World};
use dem2d::geometry::{Polygon, Pose, Shape, Vec2, Wall};
use dem2d::narrow_phase::{Contact, ContactState, Object, contact};
use dem2d::run::Simulation;
use dem2d_validation::dd::DD;
use dem2d_validation::polygon_reference::{PObj, polygon_overlap};
use dem2d_validation::rng::Rng;

mod common;
use common::{body, floor, worst_energy_error};

const EPS: f64 = f64::EPSILON;

/// A random convex polygon: 3 to 12 vertices on an ellipse of half-size 0.5 … 2 and aspect
/// up to 4, one in each of equal sectors.
fn random_polygon(rng: &mut Rng) -> Polygon {
    let s = rng.range(0.5, 2.0);
    let aspect = rng.range(1.0, 4.0);
    let n = 3 + (rng.uniform() * 10.0) as usize;
    let sector = std::f64::consts::TAU / n as f64;
    let v: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let t = sector * (k as f64 + rng.range(0.1, 0.9));
            [s * t.cos(), s / aspect * t.sin()]
        })
        .collect();
    Polygon::new(&v).unwrap()
}

/// The other side of a pair.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Polygon,
    Circle,
    Ellipse,
    Rectangle,
    Wall,
}

fn r_obj(o: &Object) -> PObj {
    match *o {
        Object::Wall(w) => PObj::Wall {
            point: [w.point.x, w.point.y],
            normal: [w.normal.x, w.normal.y],
        },
        Object::Segment(_) | Object::Drum(_) => unreachable!("no segment walls or drums here"),
        Object::Body { shape, pose } => {
            let pos = [pose.position.x, pose.position.y];
            let angle = pose.angle();
            match shape {
                Shape::Circle { r } => PObj::Ellipse {
                    a: r,
                    b: r,
                    pos,
                    angle,
                },
                Shape::Ellipse { a, b } => PObj::Ellipse { a, b, pos, angle },
                Shape::Clump(_) => unreachable!("no clumps in the polygon tests"),
                Shape::Rectangle { .. } | Shape::Polygon(_) => PObj::Polygon {
                    vertices: shape
                        .corners()
                        .unwrap()
                        .iter()
                        .map(|v| [v.x, v.y])
                        .collect(),
                    pos,
                    angle,
                },
            }
        }
    }
}

fn object(shape: Shape, p: Vec2, angle: f64) -> Object {
    Object::Body {
        shape,
        pose: Pose::new(p, angle),
    }
}

/// A polygon i and an object of `kind` j overlapping by about `ratio` × the smaller inscribed
/// radius, along a random direction, both `offset` away from the origin; and that radius.
fn random_pair(rng: &mut Rng, kind: Kind, ratio: f64, offset: f64) -> (Object, Object, f64) {
    let pi = random_polygon(rng);
    let ti = rng.angle();
    let o = Vec2::new(offset, -0.37 * offset);
    if kind == Kind::Wall {
        let n = Vec2::new(rng.range(-0.5, 0.5), 1.0).normalize();
        let b = pi.inscribed_radius;
        // The polygon's lowest extent along −n, pushed in by ratio × b.
        let (s, c) = ti.sin_cos();
        let u = Vec2::new(-c * n.x - s * n.y, s * n.x - c * n.y); // −n in the body frame
        let h = pi.support(u);
        let wall = Wall::new(o - n * (h - ratio * b), n).unwrap();
        return (Object::Wall(wall), object(Shape::Polygon(pi), o, ti), b);
    }
    let sj = match kind {
        Kind::Polygon => Shape::Polygon(random_polygon(rng)),
        Kind::Circle => Shape::Circle {
            r: rng.range(0.5, 2.0),
        },
        Kind::Ellipse => {
            let a = rng.range(0.5, 2.0);
            Shape::Ellipse {
                a,
                b: a / rng.range(1.0, 4.0),
            }
        }
        Kind::Rectangle | Kind::Wall => Shape::Rectangle {
            w: rng.range(1.0, 4.0),
            h: rng.range(0.5, 2.0),
        },
    };
    let tj = rng.angle();
    let phi = rng.angle();
    let u = Vec2::new(phi.cos(), phi.sin());
    let b = pi.inscribed_radius.min(sj.inscribed_radius());
    let i = object(Shape::Polygon(pi), o, ti);
    let state = |d: f64| ContactState::of(contact(&i, &object(sj, o + u * d, tj)).as_ref());
    let (mut lo, mut hi) = (0.0, pi.bounding_radius + sj.bounding_radius());
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if state(mid) == ContactState::Separated {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    (i, object(sj, o + u * (lo - ratio * b), tj), b)
}

/// The two chord ends against the reference's two crossings: the larger distance, in the best
/// matching, beyond the rounding of world coordinates. The record's ends are `point ∓
/// half_chord · t` ([`Contact::chord`]), the contact point itself rounded to world coordinates:
/// an end is rounded twice, to within an ulp of its coordinates (what the contact point's own
/// comparisons allow too).
fn chord_error(c: &Contact, crossings: &[[f64; 2]]) -> f64 {
    let (p, q) = c.chord();
    let d = |a: Vec2, b: [f64; 2]| (a.x - b[0]).hypot(a.y - b[1]);
    let (x, y) = (crossings[0], crossings[1]);
    let ulp = |v: f64| f64::from_bits(v.abs().to_bits() + 1) - v.abs();
    let round = 2.0
        * [p.x, p.y, q.x, q.y]
            .into_iter()
            .map(ulp)
            .fold(0.0, f64::max);
    ((d(p, x).max(d(q, y))).min(d(p, y).max(d(q, x))) - round).max(0.0)
}

#[test]
fn polygon_contacts_match_the_double_double_reference() {
    let mut rng = Rng(0x0016_0001);
    let kinds = [
        Kind::Polygon,
        Kind::Circle,
        Kind::Ellipse,
        Kind::Rectangle,
        Kind::Wall,
    ];
    let mut compared = 0;
    for kind in kinds {
        // Worst area error in units of ε × the chord length × the size, worst relative area
        // error per decade of δ/b, worst crossing error over the size.
        let (mut worst_area, mut worst_cross) = (0.0f64, 0.0f64);
        let mut per_decade = [0.0f64; 9];
        let mut n = 0;
        for k in 0..400 {
            let decade = k % 9;
            let ratio = 10f64.powf(-9.0 + decade as f64 + rng.uniform()).min(0.3);
            let offset = if k % 2 == 0 { 0.0 } else { 1e6 };
            let (i, j, _b) = random_pair(&mut rng, kind, ratio, offset);
            // Both orders through the dispatcher: the record is the same (swap symmetry).
            for (i, j) in [(i, j), (j, i)] {
                let Some(c) = contact(&i, &j) else {
                    continue;
                };
                if c.state != ContactState::Overlap {
                    continue;
                }
                let r = polygon_overlap(&r_obj(&i), &r_obj(&j)).unwrap();
                if r.crossings.len() != 2 {
                    continue;
                }
                let g = c;
                let a = g.area.unwrap();
                let size = match (i, j) {
                    (Object::Body { shape, .. }, Object::Wall(_))
                    | (Object::Wall(_), Object::Body { shape, .. }) => shape.bounding_radius(),
                    (Object::Body { shape: s, .. }, Object::Body { shape: t, .. }) => {
                        s.bounding_radius().max(t.bounding_radius())
                    }
                    _ => unreachable!("a body and a half-plane, or two bodies"),
                };
                let err = (a.area - r.area).abs();
                let scaled = err / (EPS * a.length * size);
                worst_area = worst_area.max(scaled);
                per_decade[decade] = per_decade[decade].max(err / r.area);
                // A crossing on a nearly tangent edge is placed to ε/(the angle of crossing),
                // ~ε √(size/δ) (both kernels and reference agree on the area, which is not).
                let ce = chord_error(&c, &r.crossings) / size / (1.0 + (size / g.depth).sqrt());
                worst_cross = worst_cross.max(ce);
                // The chord's length and the area's gradient length agree with the reference's
                // crossings.
                n += 1;
                assert!(
                    scaled <= 64.0,
                    "{kind:?}: area {} vs {} ({scaled:.1} ε·L·size)\n i = {i:?}\n j = {j:?}",
                    a.area,
                    r.area
                );
                assert!(
                    ce <= 1e-13,
                    "{kind:?}: chord {:?} vs {:?}\n i = {i:?}\n j = {j:?}",
                    g.chord(),
                    r.crossings
                );
            }
        }
        println!(
            "{kind:?}: {n} overlaps; worst area error {worst_area:.2} ε·L·size, worst crossing \
             error {worst_cross:.1e} of the size × (1 + √(size/δ))"
        );
        for (d, e) in per_decade.iter().enumerate() {
            println!(
                "  δ/b in [1e{}, 1e{}): worst relative area error {e:.1e}",
                d as i32 - 9,
                d as i32 - 8
            );
        }
        assert!(
            n >= 300,
            "{kind:?}: only {n} two-crossing overlaps compared"
        );
        compared += n;
    }
    println!("{compared} polygon contacts compared with the reference");
}

#[test]
fn a_circle_cut_by_a_face_is_a_circular_segment() {
    // A square of side 4 at angle θ, a circle of radius r pressed by δ into its top face: the
    // overlap is the circle's segment of sagitta δ, the chord 2√(2rδ − δ²), the depth δ, the
    // normal the face's.
    let square = Shape::Polygon(
        Polygon::new(&[[-2.0, -2.0], [2.0, -2.0], [2.0, 2.0], [-2.0, 2.0]]).unwrap(),
    );
    let r = 0.8;
    let mut worst = [0.0f64; 3];
    for &theta in &[0.0, 0.3, -1.1, 2.5] {
        for &delta in &[1e-9, 1e-6, 1e-3, 0.1, 0.5, 1.2] {
            let up = Vec2::new(-f64::sin(theta), f64::cos(theta));
            let along = Vec2::new(f64::cos(theta), f64::sin(theta));
            let c = up * (2.0 + r - delta) + along * 0.3;
            let (i, j) = (
                object(square, Vec2::zeros(), theta),
                object(Shape::Circle { r }, c, 0.0),
            );
            let g = contact(&i, &j).unwrap();
            assert_eq!(g.state, ContactState::Overlap, "δ = {delta}");
            // The segment ½r²(φ − sin φ), φ = 2 atan2(half-chord, r − δ), in double-double
            // (the textbook r² acos(h/r) − h·half cancels for small δ).
            let (rd, dd) = (DD::from(r), DD::from(delta));
            let half_dd = (dd * (rd * 2.0 - dd)).sqrt();
            let phi = half_dd.atan2(rd - dd) * 2.0;
            let area = (rd * rd * phi.x_minus_sin() * 0.5).to_f64();
            let half = half_dd.to_f64();
            let a = g.area.unwrap();
            // In units of ε × chord × size: the depth is known to ε × the size, and the area's
            // sensitivity to it is the chord (so a tiny δ's relative error is ~ε·size/δ).
            let e_area = (a.area - area).abs() / (EPS * a.length * 2.0 * 2f64.sqrt());
            let e_chord = ((a.length - 2.0 * half) / (2.0 * half)).abs();
            let e_depth = (g.depth - delta).abs() / r;
            // The chord comes from the crossings of a nearly tangent face, a quadratic whose
            // discriminant is ∝ δ: relative error ~ ε r/δ (the area, from the depth, is not).
            let e_chord = e_chord / (EPS * (1.0 + r / delta));
            worst = [
                worst[0].max(e_area),
                worst[1].max(e_chord),
                worst[2].max(e_depth),
            ];
            assert!((g.normal - up).norm() < 1e-15, "{:?}", g.normal);
        }
    }
    println!(
        "circular segment: worst area error {:.2} ε·L·size, chord {:.2} ε(1 + r/δ), depth \
         {:.1e} of r",
        worst[0], worst[1], worst[2]
    );
    assert!(
        worst[0] < 8.0 && worst[1] < 16.0 && worst[2] < 1e-14,
        "{worst:?}"
    );
}

#[test]
fn containment_either_way_is_contained() {
    let hex = Shape::Polygon(Polygon::regular(6, 1.0, 0.1).unwrap());
    let small = Shape::Circle { r: 0.3 };
    let large = Shape::Circle { r: 3.0 };
    for (i, j) in [
        (
            object(hex, Vec2::zeros(), 0.2),
            object(small, Vec2::new(0.1, 0.2), 0.0),
        ),
        (
            object(large, Vec2::zeros(), 0.0),
            object(hex, Vec2::new(0.4, -0.5), 1.0),
        ),
    ] {
        for (a, b) in [(i, j), (j, i)] {
            let c = contact(&a, &b).unwrap();
            assert_eq!(c.state, ContactState::Contained, "{a:?} / {b:?}");
        }
    }
}

/// The law of the convergence test: linear, k_n = 1, undamped and frictionless, area law.
fn area_spec() -> ContactSpec {
    ContactSpec::linear(
        Scaled::Absolute(1.0),
        Scaled::Absolute(1.0),
        LinearDamping::Dashpots {
            eta_n: Scaled::Absolute(0.0),
            eta_s: Scaled::Absolute(0.0),
        },
        0.0,
    )
}

/// Depth (the narrow phase's) and force on the body (the dynamics') of `shape` at `(x, angle)`
/// against a floor `y = 0` (`partner` None) or against a partner body fixed at the origin.
fn depth_and_force(
    shape: Shape,
    x: Vec2,
    angle: f64,
    partner: Option<(Shape, f64)>,
) -> (f64, Vec2) {
    let j = object(shape, x, angle);
    match partner {
        None => {
            let floor = Wall::new(Vec2::zeros(), Vec2::new(0.0, 1.0)).unwrap();
            let c = contact(&Object::Wall(floor), &j);
            let w = World::new(
                &[body(shape, x, angle)],
                vec![Boundary::new(floor, area_spec())],
                Vec2::zeros(),
                area_spec(),
                1e-6,
            );
            (c.map_or(0.0, |g| g.depth), w.bodies.force[0])
        }
        Some((ps, pa)) => {
            let i = object(ps, Vec2::zeros(), pa);
            let c = contact(&i, &j);
            let w = World::new(
                &[body(ps, Vec2::zeros(), pa), body(shape, x, angle)],
                vec![],
                Vec2::zeros(),
                area_spec(),
                1e-6,
            );
            (c.map_or(0.0, |g| g.depth), w.bodies.force[1])
        }
    }
}

#[test]
fn equal_area_polygons_converge_to_the_ellipse() {
    // P's ellipse (a = 1.5, b = 1 cm) and its equal-area n-gons (vertices at equal eccentric
    // angles, scaled to area πab), pressed by δ = 0.02 cm (2 % of b) into a floor and into a
    // second ellipse, at 24 orientations; the worst relative errors of the depth and of the
    // area law's force against the ellipse's.
    let (a, b) = (1.5, 1.0);
    let ell = Shape::Ellipse { a, b };
    let delta = 0.02;
    let partner = (Shape::Ellipse { a, b }, 0.7);
    let ns = [8usize, 16, 32, 64, 128];
    let mut rows = Vec::new();
    for (label, with) in [("floor", None), ("ellipse", Some(partner))] {
        let mut errs = Vec::new();
        for &n in &ns {
            let poly = Shape::Polygon(Polygon::equal_area_ellipse(n, a, b, 0.0).unwrap());
            let (mut ed, mut ef) = (0.0f64, 0.0f64);
            for k in 0..24 {
                let angle = 0.1 + std::f64::consts::PI * k as f64 / 24.0;
                // The ellipse's centre where its depth is δ: on the floor, at height h − δ; on
                // the partner, along the direction φ at the touching distance minus δ.
                let x = match with {
                    None => {
                        let h = dem2d::geometry::support::support_rotated(
                            &ell,
                            angle.cos(),
                            angle.sin(),
                            0.0,
                            -1.0,
                        );
                        Vec2::new(0.0, h - delta)
                    }
                    Some((ps, pa)) => {
                        let phi = 0.4 + 0.25 * k as f64;
                        let u = Vec2::new(f64::cos(phi), f64::sin(phi));
                        let s = |sh: &Shape, th: f64, v: Vec2| {
                            dem2d::geometry::support::support_rotated(
                                sh,
                                th.cos(),
                                th.sin(),
                                v.x,
                                v.y,
                            )
                        };
                        // Bisection on the ellipse pair's depth (the chord normal is not u).
                        let depth_at = |d: f64| {
                            let c =
                                contact(&object(ps, Vec2::zeros(), pa), &object(ell, u * d, angle));
                            c.map_or(-1.0, |g| g.depth)
                        };
                        let (mut lo, mut hi) = (0.0, s(&ps, pa, u) + s(&ell, angle, -u));
                        for _ in 0..100 {
                            let mid = 0.5 * (lo + hi);
                            if depth_at(mid) > delta {
                                lo = mid;
                            } else {
                                hi = mid;
                            }
                        }
                        u * lo
                    }
                };
                let (de, fe) = depth_and_force(ell, x, angle, with);
                let (dp, fp) = depth_and_force(poly, x, angle, with);
                ed = ed.max((dp - de).abs() / de);
                ef = ef.max((fp - fe).norm() / fe.norm());
            }
            errs.push((n, ed, ef));
        }
        println!("{label}: n, depth error, force error, orders (log2 of the ratio to 2n)");
        for w in 0..errs.len() {
            let (n, ed, ef) = errs[w];
            let order = |k: usize| {
                errs.get(w + 1)
                    .map(|e| {
                        let (x, y) = if k == 0 { (ed, e.1) } else { (ef, e.2) };
                        format!("{:.2}", (x / y).log2())
                    })
                    .unwrap_or_else(|| "—".into())
            };
            println!("  {n:>4}  {ed:.2e}  {ef:.2e}  {}  {}", order(0), order(1));
        }
        // Converging, at about second order (the boundary's distance from the ellipse falls
        // like 1/n²).
        let last = errs.len() - 1;
        let (od, of) = (
            (errs[last - 2].1 / errs[last].1).log2() / 2.0,
            (errs[last - 2].2 / errs[last].2).log2() / 2.0,
        );
        println!("  measured order 32 → 128: depth {od:.2}, force {of:.2}");
        rows.push((label, od, of));
        assert!(
            errs[last].1 < 0.05 && errs[last].2 < 0.05,
            "{label}: {errs:?}"
        );
        assert!(od > 1.8 && of > 1.8, "{label}: orders {od} {of}");
    }
}

#[test]
fn the_outline_is_the_polygons_own_vertices() {
    let p = Polygon::new(&[[1.0, 1.0], [4.0, 1.0], [1.0, 4.0]]).unwrap();
    let v = dem2d::output::outline::body_frame_vertices(&Shape::Polygon(p));
    assert_eq!(v.len(), 3);
    // Shifted to the centroid (2, 2).
    assert_eq!(v[0], (-1.0, -1.0));
    assert_eq!(v[1], (2.0, -1.0));
    assert_eq!(v[2], (-1.0, 2.0));
}

/// Force and moment on body j from body (or wall) i as the dynamics computes them (the area
/// law of [`area_spec`]).
fn force_on(i: &Object, j: &Object) -> (Vec2, f64) {
    let Object::Body { shape, pose } = *j else {
        panic!("j must be a body")
    };
    let ij = body(shape, pose.position, pose.angle());
    let w = match *i {
        Object::Body {
            shape: si,
            pose: pi,
        } => World::new(
            &[body(si, pi.position, pi.angle()), ij],
            vec![],
            Vec2::zeros(),
            area_spec(),
            1e-6,
        ),
        Object::Wall(wall) => World::new(
            &[ij],
            vec![Boundary::new(wall, area_spec())],
            Vec2::zeros(),
            area_spec(),
            1e-6,
        ),
        Object::Segment(_) | Object::Drum(_) => unreachable!("no segment walls or drums here"),
    };
    let k = w.bodies.len() - 1;
    (w.bodies.force[k], w.bodies.torque[k])
}

/// `W(A) = ½ k_n δ_eq(A)²` with the equal-area disks' lens (a wall: ∞), the law's potential for
/// every pair with a polygon.
fn potential(i: &Object, j: &Object, area: f64) -> f64 {
    let r = |o: &Object| match o {
        Object::Body { shape, .. } => shape.equal_area_radius(),
        Object::Wall(_) | Object::Segment(_) | Object::Drum(_) => f64::INFINITY,
    };
    let lens = dem2d::geometry::overlap_area::DiskLens::new(r(i), r(j));
    let (d, _) = lens.equivalent_depth(area);
    0.5 * d * d
}

#[test]
fn force_and_moment_are_minus_the_gradient_of_the_reference_area_potential() {
    // F = −∂W/∂x_j and M = −∂W/∂θ_j with W of the double-double reference's area, by
    // fourth-order central differences: two crossings for every pair kind (δ/b 1e-4 … 0.2), and
    // thin polygons crossed over each other (four or more crossings: the exact gradient of the
    // clipped polygon).
    let mut rng = Rng(0x0016_0002);
    let fd4 = |f: &dyn Fn(f64) -> f64, h: f64| {
        (-f(2.0 * h) + 8.0 * f(h) - 8.0 * f(-h) + f(-2.0 * h)) / (12.0 * h)
    };
    let moved = |o: &Object, dx: f64, dy: f64, dt: f64| match *o {
        Object::Body { shape, pose } => {
            object(shape, pose.position + Vec2::new(dx, dy), pose.angle() + dt)
        }
        w => w,
    };
    let mut cases: Vec<(Object, Object)> = Vec::new();
    for kind in [
        Kind::Polygon,
        Kind::Circle,
        Kind::Ellipse,
        Kind::Rectangle,
        Kind::Wall,
    ] {
        for k in 0..24 {
            let ratio = 10f64.powf(-4.0 + 3.3 * k as f64 / 23.0);
            let (i, j, _) = random_pair(&mut rng, kind, ratio, 0.0);
            cases.push((i, j));
            cases.push((j, i));
        }
    }
    // Crossed thin polygons (a thin hexagon and a thin pentagon at right angles).
    let thin = |n: usize, a: f64, b: f64| {
        let v: Vec<[f64; 2]> = (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * (k as f64 + 0.3) / n as f64;
                [a * t.cos(), b * t.sin()]
            })
            .collect();
        Shape::Polygon(Polygon::new(&v).unwrap())
    };
    for k in 0..16 {
        let i = object(thin(6, 2.0, 0.3), Vec2::zeros(), rng.range(-0.2, 0.2));
        let x = Vec2::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3));
        let j = object(
            thin(5 + k % 3, 1.8, 0.25),
            x,
            std::f64::consts::FRAC_PI_2 + rng.range(-0.5, 0.5),
        );
        cases.push((i, j));
    }
    let (mut worst_f, mut worst_m, mut checked, mut deep, mut kinks) = (0.0f64, 0.0f64, 0, 0, 0);
    for (i, j) in cases {
        let Object::Body { .. } = j else { continue };
        let Some(c) = contact(&i, &j) else {
            continue;
        };
        if !matches!(c.state, ContactState::Overlap | ContactState::Deep) {
            continue;
        }
        let depth = c.depth;
        let (f, m) = force_on(&i, &j);
        let w = |dx: f64, dy: f64, dt: f64| {
            let jj = moved(&j, dx, dy, dt);
            potential(
                &i,
                &j,
                polygon_overlap(&r_obj(&i), &r_obj(&jj)).unwrap().area,
            )
        };
        // Steps well inside the overlap's own scale (a vertex event within ±2h blurs the
        // difference: such points are skipped by the check below).
        let h = 2f64.powi((1e-3 * depth).log2().floor() as i32);
        let grad = |h: f64| {
            (
                fd4(&|s| w(s, 0.0, 0.0), h),
                fd4(&|s| w(0.0, s, 0.0), h),
                fd4(&|s| w(0.0, 0.0, s), h),
            )
        };
        let (gx, gy, gt) = grad(h);
        let (hx, hy, ht) = grad(0.25 * h);
        let size = match j {
            Object::Body { shape, .. } => shape.bounding_radius(),
            Object::Wall(_) | Object::Segment(_) | Object::Drum(_) => unreachable!(),
        };
        // In units of the larger of |F| and |M|/size (a symmetric crossing is a pure couple).
        let scale = f.norm().max(m.abs() / size);
        let ef = ((f.x + gx).powi(2) + (f.y + gy).powi(2)).sqrt() / scale;
        let em = (m + gt).abs() / (scale * size);
        // Two steps that disagree: a vertex event (where A's second derivative jumps) within
        // ±2h; the differences are not the gradient there.
        let spread = ((gx - hx).powi(2) + (gy - hy).powi(2))
            .sqrt()
            .max((gt - ht).abs() / size);
        if spread > 1e-8 * scale {
            kinks += 1;
            continue;
        }
        worst_f = worst_f.max(ef);
        worst_m = worst_m.max(em);
        checked += 1;
        if c.state == ContactState::Deep {
            deep += 1;
        }
        assert!(
            ef <= 1e-6 && em <= 1e-6,
            "{:?}: force {f:?} vs −∇W ({}, {}), moment {m} vs {}: {ef:.1e}, {em:.1e}\n i = {i:?}\n j = {j:?}",
            c.state,
            -gx,
            -gy,
            -gt
        );
    }
    println!(
        "force = −∇W(A_ref): {checked} pairs with a polygon ({deep} deep; {kinks} skipped at a \
         vertex event), worst force error \
         {worst_f:.1e}, moment {worst_m:.1e} (of max(|F|, |M|/size), and × size)"
    );
    assert!(checked >= 200 && deep >= 8, "{checked} {deep}");
}

/// The largest |E − E₀|/E₀ over `steps` steps (E = kinetic + potential + elastic; nothing
/// dissipates).
fn energy_drift(mut w: World, steps: u64) -> f64 {
    worst_energy_error(Simulation::new(&mut w).for_steps(steps))
}

#[test]
fn undamped_frictionless_polygons_conserve_energy_to_second_order() {
    // P's stiffness, no damping, no friction, the area law: a 16-gon of the ellipse's area
    // dropped tilted and spinning onto a floor (bounces on vertices and faces), and two
    // polygons colliding off-centre in free space; the energy error over the run, averaged over
    // four release phases (where an impact's onset falls within a step), against Δt.
    let spec = ContactSpec::linear(
        Scaled::Absolute(36400.0 * 980.0),
        Scaled::Absolute(36400.0 * 980.0),
        LinearDamping::Dashpots {
            eta_n: Scaled::Absolute(0.0),
            eta_s: Scaled::Absolute(0.0),
        },
        0.0,
    );
    let p16 = Shape::Polygon(Polygon::equal_area_ellipse(16, 1.5, 1.0, 0.0).unwrap());
    let hex = Shape::Polygon(Polygon::regular(6, 1.2, 0.0).unwrap());
    let dropped = |dt: f64, phase: f64| {
        let floor = floor(spec);
        let mut b = body(p16, Vec2::new(0.0, 2.2 + 0.013 * phase), 0.5);
        b.omega = 3.0;
        World::new(&[b], vec![floor], Vec2::new(0.0, -980.0), spec, dt)
    };
    let colliding = |dt: f64, phase: f64| {
        let mut a = body(p16, Vec2::new(-0.006 * phase, 0.0), 0.3);
        let mut b = body(hex, Vec2::new(4.0, 0.9), 1.2);
        a.velocity = Vec2::new(60.0, 0.0);
        b.velocity = Vec2::new(-40.0, 5.0);
        b.omega = -2.0;
        World::new(&[a, b], vec![], Vec2::zeros(), spec, dt)
    };
    type Scene<'a> = &'a dyn Fn(f64, f64) -> World;
    let scenes: [(&str, Scene, f64); 2] = [
        ("16-gon bouncing on a floor", &dropped, 0.3),
        ("16-gon and hexagon colliding off-centre", &colliding, 0.05),
    ];
    for (name, scene, duration) in scenes {
        let dts = [4e-6, 2e-6, 1e-6];
        let drift: Vec<f64> = dts
            .iter()
            .map(|&dt| {
                (0..4)
                    .map(|k| {
                        energy_drift(scene(dt, k as f64 / 4.0), (duration / dt).round() as u64)
                    })
                    .sum::<f64>()
                    / 4.0
            })
            .collect();
        let order = (drift[0] / drift[2]).log2() / 2.0;
        println!(
            "{name}: max |ΔE/E| at Δt = 4e-6, 2e-6, 1e-6 s: {:.1e} {:.1e} {:.1e} (order {order:.2})",
            drift[0], drift[1], drift[2]
        );
        assert!(order > 1.5 && drift[2] < 1e-4, "{name}: {drift:?}");
    }
}

/// The representation study's polygons (`dem2d study representation`): vertices on the ellipse
/// scaled by `s = √(π / (½ n sin(2π/n)))`, area exactly the ellipse's `πab` (the closed form,
/// against the shoelace area the shape table computes), for every n, aspect ratio and phase the
/// study uses.
#[test]
fn equal_area_polygons_have_the_ellipse_area() {
    use std::f64::consts::PI;
    for n in [8usize, 16, 32, 64, 128] {
        for alpha in [1.5f64, 2.0, 3.0] {
            let (a, b) = ((1.5 * alpha).sqrt(), (1.5 / alpha).sqrt());
            for phase in [0.0, PI / n as f64] {
                let p = Polygon::equal_area_ellipse(n, a, b, phase).unwrap();
                let area = PI * a * b;
                assert!(
                    (p.area - area).abs() <= 1e-12 * area,
                    "n = {n}, α = {alpha}: {} against πab = {area}",
                    p.area
                );
                let s = (PI / (0.5 * n as f64 * (2.0 * PI / n as f64).sin())).sqrt();
                for v in p.vertices.iter() {
                    let r = (v.x / (s * a)).powi(2) + (v.y / (s * b)).powi(2);
                    assert!((r - 1.0).abs() < 1e-12, "n = {n}: vertex off the ellipse");
                }
            }
        }
    }
}

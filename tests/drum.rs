//! Drums and turning walls (issue 44, items 1 and 2): the drum's kernels against a brute-force
//! sampling of the bodies' boundaries, a disk rolling in place at the bottom of a turning drum
//! (the no-slip condition), a square carried up a turning drum slipping where tan θ = μ, the
//! energy account with a turning drum and a turning paddle, a turning segment's ends against the
//! closed-form rotation about its pivot, and a restart that continues a turning drum exactly.

use dem2d::dynamics::World;
use dem2d::geometry::{Drum, Pose, Shape, Vec2};
use dem2d::narrow_phase::drum::ellipse_farthest;
use dem2d::narrow_phase::{Object, contact};
use dem2d::run::Simulation;
use dem2d::scene::Case;
use dem2d::scene::drum_flow::{fit_line, surface_tops};

mod common;
use common::Rng;

fn world(walls: &str, bodies: &str, friction: f64, dt: f64) -> World {
    let text = format!(
        r#"{{ "version": 1, "name": "drum", "gravity": [0, -980], "dt": {dt}, "duration": 100,
        "contact": {{ "model": "linear", "kn_over_rho_g": 36400, "ks_over_rho_g": 36400,
                      "restitution": 0.5, "friction": {friction} }},
        "walls": {walls}, "bodies": {bodies} }}"#
    );
    Case::from_json(&text)
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .build_world()
}

/// The largest squared distance from `q` of `n` points evenly spaced in the parameter of the
/// ellipse `(a cos t, b sin t)`.
fn brute_farthest(a: f64, b: f64, q: [f64; 2], n: usize) -> f64 {
    (0..n)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            let (s, c) = t.sin_cos();
            (a * c - q[0]).powi(2) + (b * s - q[1]).powi(2)
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn the_farthest_point_of_an_ellipse_matches_a_sampling_of_a_million_boundary_points() {
    const N: usize = 1_000_000;
    let h = std::f64::consts::TAU / N as f64;
    let mut rng = Rng(0x5eed_d1ce);
    let mut cases: Vec<(f64, f64, [f64; 2])> = vec![
        // On the minor axis (two farthest points), on the major axis, at the centre, close to
        // the centres of curvature of a thin ellipse, far away.
        (1.0, 0.5, [0.0, 0.3]),
        (1.0, 0.5, [0.0, -7.0]),
        (1.0, 0.5, [0.4, 0.0]),
        (1.0, 0.5, [0.0, 0.0]),
        (1.0, 0.1, [0.99, 0.0]),
        (1.0, 0.1, [0.0, 9.9]),
        (2.0, 1.0, [1e-9, 0.2]),
        (1.0, 1.0, [0.3, -0.2]),
        (1.5, 1.0, [-30.0, 40.0]),
    ];
    for _ in 0..31 {
        let a = 0.1 + rng.next() * 2.0;
        let b = a * (0.05 + 0.95 * rng.next());
        let r = 5.0 * rng.next() * a;
        let phi = std::f64::consts::TAU * rng.next();
        cases.push((a, b, [r * phi.cos(), r * phi.sin()]));
    }
    for &(a, b, q) in &cases {
        let (t, f) = ellipse_farthest(a, b, q);
        let brute = brute_farthest(a, b, q, N);
        // The samples miss the maximum by at most max|f″| h²/8, with |f″| ≤ 2a(a + |q|) + 2b².
        let qn = q[0].hypot(q[1]);
        let bound = (2.0 * a * (a + qn) + 2.0 * b * b) * h * h / 8.0;
        assert!(
            f >= brute - 1e-14 * brute.max(1.0) && f - brute <= bound + 1e-14 * brute,
            "a {a} b {b} q {q:?}: {f} against the sampling's {brute} (bound {bound:e})"
        );
        let (s, c) = t.sin_cos();
        let at = (a * c - q[0]).powi(2) + (b * s - q[1]).powi(2);
        assert!(
            (at - f).abs() <= 1e-14 * f.max(1.0),
            "t gives {at}, not {f}"
        );
    }
}

/// Points on the boundary of a placed shape (`n` of a smooth one; a polygon's vertices).
fn boundary(shape: &Shape, pose: &Pose, n: usize) -> Vec<Vec2> {
    let mut corners = [Vec2::zeros(); 4];
    let local: Vec<Vec2> = match *shape {
        Shape::Circle { r } => (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                Vec2::new(r * t.cos(), r * t.sin())
            })
            .collect(),
        Shape::Ellipse { a, b } => (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                Vec2::new(a * t.cos(), b * t.sin())
            })
            .collect(),
        _ => shape.vertices(&mut corners).to_vec(),
    };
    local
        .iter()
        .map(|v| pose.position + pose.to_world_vector(*v))
        .collect()
}

#[test]
fn the_drum_contact_of_every_shape_is_its_farthest_boundary_point_from_the_centre() {
    let drum = Drum::new(Vec2::new(3.0, -2.0), 10.0).unwrap();
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let shapes = [
        Shape::Circle { r: 1.0 },
        Shape::Ellipse { a: 1.5, b: 0.5 },
        Shape::Ellipse { a: 1.0, b: 0.9 },
        Shape::Rectangle { w: 2.0, h: 0.6 },
    ];
    let n = 1_000_000;
    let h = std::f64::consts::TAU / n as f64;
    for shape in &shapes {
        for _ in 0..6 {
            let phi = std::f64::consts::TAU * rng.next();
            let reach = shape.bounding_radius();
            // From well inside to a little beyond the circle.
            let d = 10.0 - reach * (0.3 + 1.0 * rng.next());
            let pose = Pose::new(
                drum.center + Vec2::new(phi.cos(), phi.sin()) * d,
                std::f64::consts::TAU * rng.next(),
            );
            let pts = boundary(shape, &pose, n);
            let (far, rho) = pts.iter().map(|p| (*p, (p - drum.center).norm())).fold(
                (Vec2::zeros(), f64::NEG_INFINITY),
                |b, x| {
                    if x.1 > b.1 { x } else { b }
                },
            );
            let c = contact(
                &Object::Drum(drum),
                &Object::Body {
                    shape: *shape,
                    pose,
                },
            );
            let slack = if matches!(shape, Shape::Rectangle { .. }) {
                1e-13
            } else {
                // The sampling's miss, max|f″| h²/8 over ρ (in ρ rather than ρ²).
                (reach * (reach + d)) * h * h
            };
            match c {
                None => assert!(
                    rho - 10.0 < slack,
                    "{shape:?}: apart, but the sampling reaches {}",
                    rho - 10.0
                ),
                Some(c) => {
                    assert!(
                        (c.depth - (rho - 10.0)).abs() <= slack + 1e-13,
                        "{shape:?}: depth {} against {} sampled",
                        c.depth,
                        rho - 10.0
                    );
                    if !matches!(shape, Shape::Rectangle { .. }) {
                        // The normal points from the farthest point towards the centre, and
                        // the contact lies on the drum's circle on that line.
                        let want = (drum.center - far).normalize();
                        assert!((c.normal - want).norm() < 1e-5, "{shape:?}: normal");
                        assert!(((c.point - drum.center).norm() - 10.0).abs() < 1e-12);
                    }
                }
            }
        }
    }
}

#[test]
fn a_rectangle_lying_on_the_bottom_of_a_drum_pushes_at_the_middle_of_its_face() {
    let drum = Drum::new(Vec2::new(0.0, 0.0), 20.0).unwrap();
    // Its bottom corners 1e-4 beyond the circle: two crossings on its bottom face near each
    // corner, two on its sides; the chord of the outermost is the face's.
    let y = -(400.0f64 - 0.25).sqrt() - 1e-4 + 0.25;
    let body = Object::Body {
        shape: Shape::Rectangle { w: 1.0, h: 0.5 },
        pose: Pose::new(Vec2::new(0.0, y), 0.0),
    };
    let c = contact(&Object::Drum(drum), &body).unwrap();
    assert!(c.point.x.abs() < 1e-12, "point {:?}", c.point);
    assert!((c.normal - Vec2::new(0.0, 1.0)).norm() < 1e-12);
    let rho = Vec2::new(0.5, y - 0.25).norm();
    assert!((c.depth - (rho - 20.0)).abs() < 1e-12);
}

/// `(∫ r̂ dA, ∫ (ρ − R) dA)` over the part of the rectangle `w × h` (centred at the origin, its
/// own frame) beyond the circle of centre `q` and radius `big` (r̂ the unit vector from q,
/// ρ the distance from it): column by column (`n` columns, the midpoint rule), each column's
/// part inside the circle an interval, the integrals along y in closed form
/// (`∫ X/ρ dY = X asinh(Y/|X|)`, `∫ Y/ρ dY = ρ`, `∫ ρ dY = (Yρ + X² asinh(Y/|X|))/2`).
fn brute_radial(w: f64, h: f64, q: Vec2, big: f64, n: usize) -> (Vec2, f64) {
    let dx = w / n as f64;
    let (mut force, mut energy) = (Vec2::zeros(), 0.0);
    for k in 0..n {
        let x = -0.5 * w + (k as f64 + 0.5) * dx;
        let xx = x - q.x;
        let prim = |y: f64| {
            let yy = y - q.y;
            let rho = xx.hypot(yy);
            let ash = (yy / xx.abs()).asinh();
            (
                Vec2::new(xx * ash, rho),
                0.5 * (yy * rho + xx * xx * ash) - big * yy,
            )
        };
        let (y0, y1) = (-0.5 * h, 0.5 * h);
        let reach = big * big - xx * xx;
        let mut pieces = vec![(y0, y1)];
        if reach > 0.0 {
            let r = reach.sqrt();
            let (a, b) = (q.y - r, q.y + r);
            pieces = vec![(y0, a.min(y1)), (b.max(y0), y1)];
        }
        for (lo, hi) in pieces {
            if hi > lo {
                let (f1, e1) = prim(hi);
                let (f0, e0) = prim(lo);
                force += (f1 - f0) * dx;
                energy += (e1 - e0) * dx;
            }
        }
    }
    (force, energy)
}

#[test]
fn a_rectangle_on_a_drum_rests_on_radial_springs_over_its_part_beyond_the_circle() {
    // The Winkler record of a rectangle against a drum: |∫ r̂ dA| as its area, −∫ r̂ dA as its
    // normal, and k′ A ȳ = k′ ∫ (ρ − R) dA as its energy, against a column-by-column integration.
    let drum = Drum::new(Vec2::new(1.0, 2.0), 5.0).unwrap();
    for (angle, sink) in [
        (0.0, 1e-3),
        (0.05, 2e-3),
        (-0.2, 0.05),
        (0.7, 0.1),
        (0.0, 0.15),
    ] {
        let (w, h) = (2.0, 0.8);
        let centre = drum.center + Vec2::new(0.3, -(5.0 - 0.5 * h - sink));
        let pose = Pose::new(centre, angle);
        let shape = Shape::Rectangle { w, h };
        let c = contact(&Object::Drum(drum), &Object::Body { shape, pose }).unwrap();
        let f = c.flat.expect("a rectangle's flat overlap");
        let q = pose.to_body_vector(drum.center - centre);
        let (force, energy) = brute_radial(w, h, q, 5.0, 1_000_000);
        let size = force.norm();
        let normal = -pose.to_world_vector(force) / size;
        let ybar = (f.centroid - c.point).dot(&c.normal).abs();
        println!(
            "angle {angle} sink {sink}: |∫r̂dA| {} against {size}, ∫(ρ−R)dA {} against {energy}",
            f.area,
            f.area * ybar
        );
        assert!(
            (f.area - size).abs() < 1e-7 * size,
            "area {} against {size}",
            f.area
        );
        assert!(
            (c.normal - normal).norm() < 1e-7,
            "normal {:?} against {normal:?}",
            c.normal
        );
        assert!(
            (f.area * ybar - energy).abs() < 1e-6 * energy,
            "energy {} against {energy}",
            f.area * ybar
        );
        // The resultant's line passes through the drum's centre.
        let off = (f.centroid - drum.center).perp(&c.normal);
        assert!(off.abs() < 1e-12, "{off:e} off the centre");
    }
}

#[test]
fn a_disk_at_the_bottom_of_a_turning_drum_rolls_in_place_at_w_r_over_r() {
    // R = 10, r = 1, w = 2 rad/s: the drum's surface moves at 20 cm/s. At rest on the drum the
    // disk sinks δ = m g/k_n = π/36400 cm; rolling without slip (its contact point moves with
    // the drum's) it turns at ω = w R/(r − δ), its lever being r − δ: w R/r to δ/r = 8.6e-5.
    let (w, big, r) = (2.0, 10.0, 1.0);
    let delta = std::f64::consts::PI / 36400.0;
    let omega = w * big / (r - delta);
    let mut wd = world(
        &format!(
            r#"[{{ "drum": {{ "center": [0, 0], "radius": {big} }}, "angular_velocity": {w} }}]"#
        ),
        &format!(
            r#"[{{ "shape": {{"type": "circle", "r": {r}}}, "position": [0, {}], "omega": {omega} }}]"#,
            -(big - r + delta)
        ),
        0.8,
        1e-5,
    );
    let (mut lo, mut hi, mut xmax) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    Simulation::new(&mut wd)
        .for_steps(100_000)
        .run_each(|w, _| {
            let s = &w.bodies.state[0];
            lo = lo.min(s.omega);
            hi = hi.max(s.omega);
            xmax = xmax.max(s.pose.position.x.abs());
        })
        .unwrap();
    let rolling = w * big / r;
    println!("ω in [{lo}, {hi}] over 1 s, w R/r = {rolling}, |x| ≤ {xmax:e}");
    assert!((lo - omega).abs() < 1e-6 * omega && (hi - omega).abs() < 1e-6 * omega);
    assert!((hi - rolling).abs() < 1.01 * delta / r * rolling);
    assert!(xmax < 1e-6, "it stays at the bottom: |x| up to {xmax}");
}

/// `K + P + E_el + D − E₀ − W` over the walls' work `W`, after `steps` steps.
fn unaccounted(w: &mut World, steps: u64) -> (f64, f64) {
    let e0 = w.energies.total();
    Simulation::new(w).for_steps(steps).run().unwrap();
    let e = &w.energies;
    (
        (e.total() - e0 - e.boundary_work) / e.boundary_work,
        e.boundary_work,
    )
}

#[test]
fn the_energy_account_closes_with_the_work_of_a_turning_drum() {
    // A disk, an ellipse, a square and a clump dropped into a drum turning at 3 rad/s: the
    // drum's work ω Σ (x_c − c) × F_c enters the account, which closes to the step's order.
    let mut wd = world(
        r#"[{ "drum": { "center": [0, 0], "radius": 6 }, "angular_velocity": 3 }]"#,
        r#"[{ "shape": {"type": "circle", "r": 0.8}, "position": [-2, -3] },
            { "shape": {"type": "ellipse", "a": 1.0, "b": 0.5}, "position": [0, -4], "angle": 0.3 },
            { "shape": {"type": "rectangle", "w": 1.0, "h": 1.0}, "position": [2, -3] },
            { "shape": {"type": "clump", "disks": [{"center": [-0.4, 0], "r": 0.5},
                                                    {"center": [0.4, 0], "r": 0.5}]},
              "position": [0, -1] }]"#,
        0.5,
        1e-5,
    );
    let (rel, work) = unaccounted(&mut wd, 100_000);
    println!("drum: unaccounted {rel:e} of the drum's work {work:e} erg");
    assert!(work > 0.0);
    assert!(rel.abs() < 1e-3, "{rel:e}");
    for (k, s) in wd.bodies.state.iter().enumerate() {
        assert!(s.pose.position.norm() < 6.0, "body {k} left the drum");
    }
}

#[test]
fn a_square_carried_up_a_turning_drum_slips_where_tan_theta_is_mu() {
    // A unit square lying at the bottom of a drum of radius 20 that starts turning at
    // 0.05 rad/s after 0.2 s: static friction carries it up until the surface's slope θ where
    // it touches (the contact point's polar angle: the normal points from it to the centre)
    // reaches tan θ = μ, where it starts to slip (the centripetal w²R/g = 1e-4 aside). Slip: the
    // square's material point at the contact lags the drum's surface by 5 % of its speed.
    let (mu, w, big) = (0.3, 0.05, 20.0);
    let y = -(big * big - 0.25f64).sqrt() + 0.5;
    let mut wd = world(
        &format!(
            r#"[{{ "drum": {{ "center": [0, 0], "radius": {big} }},
              "motion": [{{"until": 0.2, "angular_velocity": 0}}, {{"angular_velocity": {w}}}] }}]"#
        ),
        &format!(
            r#"[{{ "shape": {{"type": "rectangle", "w": 1, "h": 1}}, "position": [0, {y}] }}]"#
        ),
        mu,
        2e-5,
    );
    let mut slipped = None;
    Simulation::new(&mut wd)
        .for_steps(400_000)
        .run_each(|wd, _| {
            if slipped.is_some() || wd.time < 0.5 {
                return;
            }
            let Some(d) = wd.contacts.data.iter().find(|d| d.force != Vec2::zeros()) else {
                return;
            };
            let s = &wd.bodies.state[0];
            let r = d.point - s.pose.position;
            let body = s.vel + Vec2::new(-r.y, r.x) * s.omega;
            let surface = Vec2::new(-d.point.y, d.point.x) * w;
            if (body - surface).norm() > 0.05 * w * big {
                // The contact's normal n = (−sin θ, cos θ) (the force acts at the overlap's
                // centroid, the normal is the chord's).
                let c = contact(
                    &Object::Drum(*wd.walls[0].drum().unwrap()),
                    &Object::Body {
                        shape: wd.bodies.shape[0],
                        pose: s.pose,
                    },
                )
                .unwrap();
                slipped = Some((-c.normal.x).atan2(c.normal.y));
            }
        })
        .unwrap();
    let theta = slipped.expect("it never slipped");
    println!(
        "slipped at θ = {theta} rad, tan θ = {} (μ = {mu})",
        theta.tan()
    );
    assert!(
        (theta.tan() - mu).abs() < 0.01 * mu,
        "tan θ = {}",
        theta.tan()
    );
}

#[test]
fn a_turning_segment_follows_the_rotation_about_its_pivot() {
    // A segment turning at 3 rad/s about [1, 1], away from a disk resting on a floor: its ends
    // are the case's rotated by 3 t about the pivot, to 1e-12.
    let mut wd = world(
        r#"[{ "point": [0, 0], "normal": [0, 1] },
            { "segment": [[1, 3], [4, 2]], "angular_velocity": 3, "pivot": [1, 1] },
            { "point": [-5, 5], "normal": [1, 1], "angular_velocity": -1, "pivot": [-5, 5] }]"#,
        r#"[{ "shape": {"type": "circle", "r": 0.5}, "position": [20, 0.5] }]"#,
        0.3,
        1e-5,
    );
    let pivot = Vec2::new(1.0, 1.0);
    let turn = |x: Vec2, a: f64| {
        let (s, c) = a.sin_cos();
        let r = x - pivot;
        pivot + Vec2::new(c * r.x - s * r.y, s * r.x + c * r.y)
    };
    let mut worst = 0.0f64;
    Simulation::new(&mut wd)
        .for_steps(20_000)
        .run_each(|w, _| {
            let seg = w.walls[1].segment().unwrap();
            let a = 3.0 * w.time;
            let err = (seg.a - turn(Vec2::new(1.0, 3.0), a))
                .norm()
                .max((seg.b - turn(Vec2::new(4.0, 2.0), a)).norm());
            worst = worst.max(err);
            // The half-plane's normal turns at −1 rad/s about its own point.
            let n = w.walls[2].line().normal;
            let b = std::f64::consts::FRAC_PI_4 - w.time;
            worst = worst.max((n - Vec2::new(b.cos(), b.sin())).norm());
        })
        .unwrap();
    println!("turning segment: largest error of an end {worst:e} cm");
    assert!(worst < 1e-12, "{worst:e}");
}

#[test]
fn the_energy_account_closes_with_the_work_of_a_turning_paddle() {
    // A paddle (a segment turning about its middle at 4 rad/s) stirring disks in a box.
    let bodies: Vec<String> = (0..24)
        .map(|k| {
            let (i, j) = (k % 8, k / 8);
            format!(
                r#"{{ "shape": {{"type": "circle", "r": 0.45}}, "position": [{}, {}] }}"#,
                -3.5 + i as f64,
                0.5 + j as f64
            )
        })
        .collect();
    let mut wd = world(
        r#"[{ "point": [0, 0], "normal": [0, 1] }, { "point": [-4, 0], "normal": [1, 0] },
            { "point": [4, 0], "normal": [-1, 0] },
            { "segment": [[-2.5, 4], [2.5, 4]], "angular_velocity": 4, "pivot": [0, 4] }]"#,
        &format!("[{}]", bodies.join(",")),
        0.3,
        1e-5,
    );
    let (rel, work) = unaccounted(&mut wd, 50_000);
    println!("paddle: unaccounted {rel:e} of its work {work:e} erg");
    assert!(work.abs() > 0.0);
    assert!(rel.abs() < 1e-3, "{rel:e}");
}

/// A drum turning by a program (still, then turning) and a turning segment, with disks, an
/// ellipse and a square: the state written part way reads back as written and continues to the
/// uninterrupted run's bits (the turn's angle, its anchor and the loads' moments kept).
#[test]
fn a_turning_drum_and_a_turning_segment_continue_exactly_from_a_state_file() {
    let text = r#"{ "version": 1, "name": "drum_restart", "gravity": [0, -980], "dt": 1e-5,
        "duration": 1,
        "contact": { "model": "linear", "kn_over_rho_g": 36400, "ks_over_rho_g": 36400,
                     "restitution": 0.5, "friction": 0.5, "rolling_model": "epsd",
                     "rolling_friction": 0.05 },
        "walls": [{ "drum": { "center": [0, 0], "radius": 6 },
                    "motion": [{"until": 0.01, "angular_velocity": 0}, {"angular_velocity": 3}] },
                  { "segment": [[-1, 2], [1, 2]], "angular_velocity": 5, "pivot": [0, 2] }],
        "bodies": [{ "shape": {"type": "circle", "r": 0.8}, "position": [-2, -4.5] },
                   { "shape": {"type": "circle", "r": 0.6}, "position": [0, -5] },
                   { "shape": {"type": "ellipse", "a": 1.0, "b": 0.5}, "position": [2, -4.5] },
                   { "shape": {"type": "rectangle", "w": 1, "h": 1}, "position": [0, -3] }] }"#;
    let file = dem2d::scene::CaseFile::from_json(text).unwrap();
    let (b_step, c_step) = (3000u64, 6000u64);
    let mut whole = file.build_world();
    Simulation::new(&mut whole).for_steps(c_step).run().unwrap();
    let mut first = file.build_world();
    Simulation::new(&mut first).for_steps(b_step).run().unwrap();
    let state = first.restart_state();
    assert!(state.walls[0].turn.is_some_and(|t| t.angle != 0.0));
    let written = dem2d::output::state::state_text(
        &file.value,
        file.case.duration,
        &state,
        None,
        &file.case.bodies,
        "max_steps",
    );
    let read = dem2d::scene::CaseFile::from_json(&written).unwrap();
    assert_eq!(
        format!("{:?}", read.restart.as_ref().unwrap()),
        format!("{state:?}"),
        "the state reads back as written"
    );
    let mut resumed = read.build_world();
    Simulation::new(&mut resumed)
        .until_step(c_step)
        .run()
        .unwrap();
    assert_eq!(
        format!("{:?}", resumed.restart_state()),
        format!("{:?}", whole.restart_state())
    );
}

/// The shipped case `cases/drum_disks.json`: 197 disks about half filling a drum turning at
/// Fr = w²R/g = 1e-3 (the rolling regime). Every body stays inside the drum at every step (its
/// centroid inside the circle, its reach beyond it no more than a contact's overlap), and at the
/// end the free surface is a plane: the top of the bed, column by column (1 cm wide, over the
/// middle 10 cm), lies within half a diameter (rms) of a straight line, inclined at a rolling
/// regime's angle.
#[test]
fn a_half_filled_drum_in_the_rolling_regime_has_a_plane_free_surface_and_keeps_its_bodies() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/drum_disks.json");
    let case = Case::from_json(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let fr = {
        let w = match &case.walls[0].motion {
            dem2d::dynamics::Motion::Program(p) => p.stages[1].angular_velocity,
            _ => panic!("a program"),
        };
        w * w * 10.0 / 980.0
    };
    assert!((fr - 1e-3).abs() < 1e-5, "Fr = {fr}");
    let mut wd = case.build_world();
    let mut worst = f64::NEG_INFINITY;
    Simulation::new(&mut wd)
        .until_step(case.steps())
        .run_each(|w, _| {
            for (s, r) in w.bodies.state.iter().zip(&w.bodies.bound) {
                worst = worst.max(s.pose.position.norm() + r - 10.0);
            }
        })
        .unwrap();
    assert!(worst < 0.01, "a body reached {worst} cm beyond the drum");
    // The bed's top in 1 cm columns over the middle 10 cm, and its line (the library's, which
    // `dem2d study drum` reads the surface with).
    let pts = surface_tops(&wd, Vec2::zeros(), 1.0, 5);
    let (_, slope, rms) = fit_line(&pts);
    let angle = slope.atan().to_degrees();
    println!(
        "Fr = {fr:.2e}: surface at {angle:.1}°, rms {rms:.3} cm off its line; reach {worst:.2e} cm"
    );
    assert!(rms < 0.4, "the free surface is not a plane: rms {rms}");
    assert!((15.0..40.0).contains(&angle), "angle {angle}°");
}

/// Issue 44: insertion inside a drum faked by a spinning clump placed nothing. An insertion
/// region inside a turning drum places its bodies (the drum's signed distance, `R − |x − c|`,
/// is the clearance the inserter asks of every wall), and they stay inside.
#[test]
fn an_insertion_region_inside_a_turning_drum_places_its_bodies() {
    let text = r#"{ "version": 1, "name": "drum_insert", "gravity": [0, -980], "dt": 1e-5,
        "duration": 0.3,
        "contact": { "model": "linear", "kn_over_rho_g": 36400, "restitution": 0.5,
                     "friction": 0.5 },
        "walls": [{ "drum": { "center": [0, 0], "radius": 8 }, "angular_velocity": 1 }],
        "bodies": [],
        "insert": [{ "region": [-4, 4, -2, 2], "rate": 400, "count": 60, "shape": "circle",
                     "size": 0.4 }] }"#;
    let case = Case::from_json(text).unwrap();
    let mut wd = case.build_world();
    Simulation::new(&mut wd)
        .until_step(case.steps())
        .run()
        .unwrap();
    let n = wd.bodies.len();
    println!("{n} bodies inserted in the drum");
    assert!(n >= 50, "only {n} bodies placed");
    for s in &wd.bodies.state {
        assert!(s.pose.position.norm() < 8.0);
    }
}

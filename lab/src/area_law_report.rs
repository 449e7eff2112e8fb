//! The area law's tables for `dem2d figures`: how its force compares with P's spring on the
//! depth, the restitution it gives, and the energy it conserves.

use dem2d::contact_law::{ContactSpec, LinearDamping, NormalForce, Scaled};
use dem2d::dynamics::{BodyInit, Boundary, World};
use dem2d::geometry::support::support_local;
use dem2d::geometry::{Shape, Vec2, Wall};
use dem2d::run::Simulation;
use dem2d::scene::Case;
use std::f64::consts::FRAC_PI_2;
use std::fmt::Write as _;

/// A linear law with stiffness `kn`, restitution `e` (None: undamped) and no friction.
fn linear(kn: f64, e: Option<f64>, nf: NormalForce) -> ContactSpec {
    ContactSpec::linear(
        Scaled::Absolute(kn),
        Scaled::Absolute(kn),
        match e {
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

fn body(shape: Shape, x: Vec2, angle: f64, v: Vec2, omega: f64) -> BodyInit {
    BodyInit {
        material: 0,
        prescribed: false,
        shape,
        position: x,
        angle,
        velocity: v,
        omega,
        density: 1.0,
    }
}

fn floor(spec: ContactSpec) -> Boundary {
    Boundary::new(
        Wall::new(Vec2::zeros(), Vec2::new(0.0, 1.0)).expect("unit normal"),
        spec,
    )
}

/// Support of `shape` at `angle` along the world direction `u`.
fn support(shape: &Shape, angle: f64, u: Vec2) -> f64 {
    let (s, c) = angle.sin_cos();
    support_local(shape, c * u.x + s * u.y, -s * u.x + c * u.y)
}

/// The normal force of a contact of depth `delta` (k_n = 1, at rest): an ellipse (1.5, 1) at
/// `angle` pressed into the floor, or two such ellipses (angles `pair`) along the x axis.
fn force(delta: f64, wall: Option<f64>, pair: (f64, f64), nf: NormalForce) -> f64 {
    let e = Shape::Ellipse { a: 1.5, b: 1.0 };
    let spec = linear(1.0, None, nf);
    let w = match wall {
        Some(angle) => {
            let h = support(&e, angle, Vec2::new(0.0, -1.0)) - delta;
            Case::new(
                vec![body(e, Vec2::new(0.0, h), angle, Vec2::zeros(), 0.0)],
                vec![floor(spec)],
                Vec2::zeros(),
                spec,
                1e-6,
            )
        }
        None => {
            let x = Vec2::x();
            let d = support(&e, pair.0, x) + support(&e, pair.1, -x) - delta;
            Case::new(
                vec![
                    body(e, Vec2::zeros(), pair.0, Vec2::zeros(), 0.0),
                    body(e, Vec2::new(d, 0.0), pair.1, Vec2::zeros(), 0.0),
                ],
                vec![],
                Vec2::zeros(),
                spec,
                1e-6,
            )
        }
    }
    .build_world();
    w.bodies.force[w.bodies.len() - 1].norm()
}

/// The area law's normal force over `k_n δ`, for ellipse–wall and ellipse–ellipse contacts of
/// an ellipse a/b = 1.5 at δ/b = 1e-4 … 1e-1, with the small-overlap prediction
/// `(R*_t/R*_eq)^{2/3}` (R*_t from the true radii of curvature at the contact, R*_eq from the
/// equal-area radii √(ab)).
pub fn force_overlap_table() -> String {
    let (a, b) = (1.5f64, 1.0f64);
    let r_eq = (a * b).sqrt();
    let (flat, tip) = (a * a / b, b * b / a); // radii of curvature
    let harm = |x: f64, y: f64| x * y / (x + y);
    // (label, wall angle or None, pair angles, R*_t, R*_eq)
    type Row<'a> = (&'a str, Option<f64>, (f64, f64), f64, f64);
    let rows: [Row; 6] = [
        ("ellipse–wall, flat side", Some(0.0), (0.0, 0.0), flat, r_eq),
        (
            "ellipse–wall, 45°",
            Some(0.25 * std::f64::consts::PI),
            (0.0, 0.0),
            f64::NAN,
            r_eq,
        ),
        ("ellipse–wall, tip", Some(FRAC_PI_2), (0.0, 0.0), tip, r_eq),
        (
            "ellipse–ellipse, flat on flat",
            None,
            (FRAC_PI_2, FRAC_PI_2),
            harm(flat, flat),
            0.5 * r_eq,
        ),
        (
            "ellipse–ellipse, tip on flat",
            None,
            (0.0, FRAC_PI_2),
            harm(tip, flat),
            0.5 * r_eq,
        ),
        (
            "ellipse–ellipse, tip on tip",
            None,
            (0.0, 0.0),
            harm(tip, tip),
            0.5 * r_eq,
        ),
    ];
    let ratios = [1e-4, 1e-3, 1e-2, 1e-1];
    let mut t = String::from(
        "| contact (ellipse a/b = 1.5) | prediction (R*_t/R*_eq)^{2/3} | F/(k_n δ) at δ/b = 1e-4 | 1e-3 | 1e-2 | 1e-1 | depth law |\n|---|---:|---:|---:|---:|---:|---:|\n",
    );
    for (label, wall, pair, rt, req) in rows {
        let pred = if rt.is_finite() {
            format!("{:.4}", (rt / req).powf(2.0 / 3.0))
        } else {
            "–".into()
        };
        let mut cells = Vec::new();
        for r in ratios {
            let delta = r * b;
            cells.push(format!(
                "{:.4}",
                force(delta, wall, pair, NormalForce::Area) / delta
            ));
        }
        let depth = force(1e-2 * b, wall, pair, NormalForce::Depth) / (1e-2 * b);
        writeln!(
            t,
            "| {label} | {pred} | {} | {depth:.4} |",
            cells.join(" | ")
        )
        .expect("string");
    }
    t
}

/// Rebound speed over impact speed of a body thrown at a floor (no gravity, no rotation).
fn rebound(shape: Shape, angle: f64, nf: NormalForce, e: f64, hertz: bool) -> f64 {
    let spec = if hertz {
        ContactSpec::hertz_mindlin(1e8, 0.3, e, 0.0).with_normal_force(nf)
    } else {
        linear(36400.0 * 980.0, Some(e), nf)
    };
    let h = support(&shape, angle, Vec2::new(0.0, -1.0));
    let v0 = 50.0;
    let mut w = Case::new(
        vec![body(
            shape,
            Vec2::new(0.0, h + 0.05),
            angle,
            Vec2::new(0.0, -v0),
            0.0,
        )],
        vec![floor(spec)],
        Vec2::zeros(),
        spec,
        2e-7,
    )
    .build_world();
    let mut touched = false;
    let mut ratio = f64::NAN;
    // A blow-up leaves the ratio undefined.
    let _ = Simulation::new(&mut w).until_time(1.0).run_until(|w, _| {
        let c = !w.contacts.is_empty();
        touched |= c;
        if touched && !c {
            ratio = w.bodies.state[0].vel.y / v0;
        }
        touched && !c
    });
    ratio
}

/// Requested → obtained restitution: a disk (the spring on the depth, whose exact answer is the
/// clamped spring–dashpot of tests/dynamics_analytic.rs) and an ellipse a/b = 1.5 falling flat or
/// on its tip under the area law.
pub fn restitution_table() -> String {
    let disk = Shape::Circle { r: 1.5f64.sqrt() };
    let ellipse = Shape::Ellipse { a: 1.5, b: 1.0 };
    let mut t = String::from(
        "| law | requested e | disk | ellipse, area law, flat side down | ellipse, area law, tip down |\n|---|---:|---:|---:|---:|\n",
    );
    for (hertz, name) in [(false, "linear (T12)"), (true, "Hertz (T14)")] {
        for e in [0.9, 0.7, 0.5, 0.3] {
            writeln!(
                t,
                "| {name} | {e} | {:.4} | {:.4} | {:.4} |",
                rebound(disk, 0.0, NormalForce::Depth, e, hertz),
                rebound(ellipse, 0.0, NormalForce::Area, e, hertz),
                rebound(ellipse, FRAC_PI_2, NormalForce::Area, e, hertz),
            )
            .expect("string");
        }
    }
    t
}

/// Largest |ΔE/E| over a run of `seconds`, mean over eight start phases (an impact's error
/// depends on where its onset falls within a step).
fn drift(scene: &dyn Fn(f64, f64) -> World, dt: f64, seconds: f64) -> f64 {
    let mut total = 0.0;
    for k in 0..8 {
        let mut w = scene(dt, k as f64 / 8.0);
        let e0 = w.energies.total();
        let mut worst = 0.0f64;
        let run = Simulation::new(&mut w)
            .until_time(seconds)
            .run_each(|w, _| worst = worst.max(((w.energies.total() - e0) / e0).abs()));
        if run.is_err() {
            return f64::NAN;
        }
        total += worst;
    }
    total / 8.0
}

/// Energy of undamped frictionless ellipses (a/b = 1.5, P's stiffness) under both laws: one
/// bouncing on a floor for 0.6 s (three bounces) and two colliding off-centre, at three Δt.
pub fn energy_table() -> String {
    let e = Shape::Ellipse { a: 1.5, b: 1.0 };
    let kn = 36400.0 * 980.0;
    let mut t = String::from(
        "| scene | normal force | max \\|ΔE/E\\| at Δt = 4e-6 s | 2e-6 s | 1e-6 s | order |\n|---|---|---:|---:|---:|---:|\n",
    );
    for nf in [NormalForce::Depth, NormalForce::Area] {
        let spec = linear(kn, None, nf);
        let bounce = move |dt: f64, phase: f64| {
            Case::new(
                vec![body(
                    e,
                    Vec2::new(0.0, 2.2 + 0.013 * phase),
                    0.5,
                    Vec2::zeros(),
                    3.0,
                )],
                vec![floor(spec)],
                Vec2::new(0.0, -980.0),
                spec,
                dt,
            )
            .build_world()
        };
        let collide = move |dt: f64, phase: f64| {
            Case::new(
                vec![
                    body(
                        e,
                        Vec2::new(-0.006 * phase, 0.0),
                        0.3,
                        Vec2::new(60.0, 0.0),
                        0.0,
                    ),
                    body(e, Vec2::new(4.0, 0.9), 1.2, Vec2::new(-40.0, 5.0), -2.0),
                ],
                vec![],
                Vec2::zeros(),
                spec,
                dt,
            )
            .build_world()
        };
        type Scene<'a> = (&'a str, &'a dyn Fn(f64, f64) -> World, f64);
        let scenes: [Scene; 2] = [
            ("ellipse bouncing on a floor (3 bounces)", &bounce, 0.6),
            ("two ellipses colliding off-centre", &collide, 0.05),
        ];
        for (label, scene, seconds) in scenes {
            let errs: Vec<f64> = [4e-6, 2e-6, 1e-6]
                .iter()
                .map(|&dt| drift(scene, dt, seconds))
                .collect();
            let order = (errs[0] / errs[2]).log2() / 2.0;
            writeln!(
                t,
                "| {label} | {} | {:.1e} | {:.1e} | {:.1e} | {order:.2} |",
                nf.as_str(),
                errs[0],
                errs[1],
                errs[2]
            )
            .expect("string");
        }
    }
    t
}

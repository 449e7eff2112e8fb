//! The stepper and the contact laws against closed-form solutions and conservation laws.
//! Each test states its tolerance and why it is that size.

use approx::assert_relative_eq;
use dem2d::contact_law::{ContactSpec, LinearDamping, NormalForce, Scaled};
use dem2d::dynamics::{BodyInit, Boundary, World};
use dem2d::geometry::{Shape, Vec2, Wall};
use dem2d::run::Simulation;

mod common;
use common::{body, floor, linear};

/// A body of `shape` at `(x, y)` and `angle`, moving with `v` and `omega`.
fn moving(shape: Shape, x: f64, y: f64, angle: f64, v: Vec2, omega: f64) -> BodyInit {
    BodyInit {
        velocity: v,
        omega,
        ..body(shape, Vec2::new(x, y), angle)
    }
}

/// One body at (0, y), angle 0, with velocity `v` and no spin, above the floor `y = 0`.
fn on_floor(shape: Shape, y: f64, v: Vec2, gravity: Vec2, spec: ContactSpec, dt: f64) -> World {
    World::new(
        &[moving(shape, 0.0, y, 0.0, v, 0.0)],
        vec![floor(spec)],
        gravity,
        spec,
        dt,
    )
}

/// Steps a disk of radius `r` that starts touching the floor y = 0, thrown down, until its
/// overlap closes again; returns that instant, interpolated between the steps (and fails past
/// `limit`).
fn separation_time(w: &mut World, r: f64, limit: f64) -> f64 {
    let (mut y_prev, mut t_prev, mut t_end) = (r, 0.0, None);
    Simulation::new(w)
        .run_until(|w, _| {
            let y = w.bodies.state[0].pose.position.y;
            if y >= r && y_prev < r {
                t_end = Some(t_prev + (r - y_prev) / (y - y_prev) * (w.time - t_prev));
            }
            (y_prev, t_prev) = (y, w.time);
            assert!(w.time < limit, "no rebound");
            t_end.is_some()
        })
        .unwrap();
    t_end.unwrap()
}

#[test]
fn free_fall_is_exact_to_round_off() {
    // Velocity Verlet integrates constant acceleration exactly: x = x0 + v0 t + ½ g t².
    let g = Vec2::new(0.0, -980.0);
    let v0 = Vec2::new(3.0, 20.0);
    let spec = linear(1e6, 0.0, 0.5);
    let mut w = World::new(
        &[moving(
            Shape::Ellipse { a: 1.5, b: 1.0 },
            0.0,
            100.0,
            0.3,
            v0,
            2.0,
        )],
        vec![],
        g,
        spec,
        1e-4,
    );
    Simulation::new(&mut w).for_steps(5000).run().unwrap();
    let t = w.time;
    let p = w.bodies.state[0].pose.position;
    // Round-off: each of the N steps rounds a position of size ≲ 120 (half an ulp each).
    let tol = 5000.0 * f64::EPSILON * 120.0;
    assert_relative_eq!(p.x, v0.x * t, epsilon = tol);
    assert_relative_eq!(p.y, 100.0 + v0.y * t + 0.5 * g.y * t * t, epsilon = tol);
    assert_relative_eq!(
        w.bodies.state[0].vel.y,
        v0.y + g.y * t,
        epsilon = 5000.0 * f64::EPSILON * 500.0
    );
    assert_relative_eq!(
        w.bodies.state[0].pose.angle(),
        0.3 + 2.0 * t,
        epsilon = 5000.0 * f64::EPSILON * 2.0
    );
}

/// The exact solution of a mass hitting a clamped linear spring–dashpot at speed v0 (no
/// gravity): δ(t) = (v0/ω_d) e^{−ζω₀t} sin ω_d t until the force kδ + ηδ̇ reaches zero at
/// tan(ω_d t_f) = −2ζ√(1−ζ²)/(1−2ζ²); then the mass leaves at the speed it has (restitution
/// e = |δ̇(t_f)|/v0) and the overlap closes at t_c = t_f + δ(t_f)/|δ̇(t_f)|.
fn clamped_impact(m: f64, k: f64, eta: f64, v0: f64) -> (f64, f64) {
    let w0 = (k / m).sqrt();
    let zeta = eta / (2.0 * (k * m).sqrt());
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    let phase = (2.0 * zeta * (1.0 - zeta * zeta).sqrt()).atan2(1.0 - 2.0 * zeta * zeta);
    let tf = (std::f64::consts::PI - phase) / wd;
    let decay = (-zeta * w0 * tf).exp();
    let delta = v0 / wd * decay * (wd * tf).sin();
    let rate = v0 * decay * ((wd * tf).cos() - zeta * w0 / wd * (wd * tf).sin());
    (-rate / v0, tf + delta / -rate)
}

#[test]
fn disk_impact_matches_the_exact_clamped_spring_dashpot() {
    for zeta in [0.05, 0.3, 0.6] {
        let r = 1.0;
        let m = std::f64::consts::PI; // density 1, r = 1
        let k = 1e5;
        let eta = 2.0 * zeta * (k * m).sqrt();
        let v0 = 10.0;
        let (e_exact, tc_exact) = clamped_impact(m, k, eta, v0);
        // ~20 000 steps per contact: the contact's start and end fall between steps, so the
        // measured times carry O(Δt/t_c) = 5e-5.
        let dt = tc_exact / 20_000.0;
        let spec = linear(k, eta, 0.0);
        let mut w = on_floor(
            Shape::Circle { r },
            r,
            Vec2::new(0.0, -v0),
            Vec2::zeros(),
            spec,
            dt,
        );
        let t_end = separation_time(&mut w, r, 10.0 * tc_exact);
        let e = w.bodies.state[0].vel.y / v0;
        assert_relative_eq!(e, e_exact, max_relative = 1e-3);
        assert_relative_eq!(t_end, tc_exact, max_relative = 1e-3);
    }
}

#[test]
fn sliding_disk_ends_rolling_at_two_thirds_speed() {
    // Friction impulse J: m(v0 − v) = J, I ω = J l, rolling v = ω l ⇒ v = v0 m l²/(I + m l²) = ⅔ v0
    // for a disk with l = r. The contact point sits at l = r − δ (δ ≈ mg/k_n = 3e-5 r here), which
    // shifts the ratio by O(δ/r): tolerance 1e-3.
    let r = 1.0;
    let v0 = 50.0;
    let g = 980.0;
    let m = std::f64::consts::PI;
    let kn: f64 = 1e8;
    let eta = 2.0 * 0.7 * (kn * m).sqrt();
    let spec = linear(kn, eta, 0.3);
    let depth = m * g / kn;
    let mut w = on_floor(
        Shape::Circle { r },
        r - depth,
        Vec2::new(v0, 0.0),
        Vec2::new(0.0, -g),
        spec,
        2e-6,
    );
    // Sliding lasts v0/(3μg) ≈ 0.057 s.
    Simulation::new(&mut w).for_steps(60_000).run().unwrap();
    let v = w.bodies.state[0].vel.x;
    assert_relative_eq!(v, 2.0 / 3.0 * v0, max_relative = 1e-3);
    assert_relative_eq!(w.bodies.state[0].omega * r, -v, max_relative = 1e-3);
}

#[test]
fn sliding_square_decelerates_at_mu_g_and_stops_at_v0_squared_over_2_mu_g() {
    // Started at its equilibrium sinking mg/k_n, the square slides with friction μ m g: it
    // decelerates at μg and stops at v0²/(2μg). The friction's moment makes it rock between its
    // centre and its front corner (one contact point per face: a small limit cycle, |v_y| ≈ 0.3
    // cm/s here, the same at every Δt and damping), so the deceleration is the least-squares slope
    // of v_x(t) over the sliding phase. The shear spring adds an elongation μmg/k_s ≈ 1e-5 of the
    // distance. Tolerance 1e-3.
    let (mu, g, v0) = (0.4, 980.0, 30.0);
    let side = 2.0;
    let m = side * side;
    let kn: f64 = 1e8;
    let eta = 2.0 * 0.7 * (kn * m).sqrt();
    let spec = linear(kn, eta, mu);
    let y0 = 0.5 * side - m * g / kn;
    let mut w = on_floor(
        Shape::Rectangle { w: side, h: side },
        y0,
        Vec2::new(v0, 0.0),
        Vec2::new(0.0, -g),
        spec,
        2e-6,
    );
    let t_stop = v0 / (mu * g);
    let (mut st, mut sv, mut stt, mut stv, mut count) = (0.0, 0.0, 0.0, 0.0, 0.0);
    Simulation::new(&mut w)
        .until_time(1.5 * t_stop)
        .run_each(|w, _| {
            if w.time > 0.1 * t_stop && w.time < 0.9 * t_stop {
                let (t, v) = (w.time, w.bodies.state[0].vel.x);
                st += t;
                sv += v;
                stt += t * t;
                stv += t * v;
                count += 1.0;
            }
        })
        .unwrap();
    let slope = (count * stv - st * sv) / (count * stt - st * st);
    assert_relative_eq!(slope, -mu * g, max_relative = 1e-3);
    assert!(
        w.bodies.state[0].vel.x.abs() < 1e-3 * v0,
        "still moving: {}",
        w.bodies.state[0].vel.x
    );
    assert_relative_eq!(
        w.bodies.state[0].pose.position.x,
        v0 * v0 / (2.0 * mu * g),
        max_relative = 1e-3
    );
}

#[test]
fn ellipse_on_its_flat_side_sinks_mg_over_kn() {
    // Static equilibrium: k_n δ = m g exactly (one contact, the normal under the centroid).
    let (a, b) = (1.5, 1.0);
    let g = 980.0;
    let m = std::f64::consts::PI * a * b;
    let kn = 36400.0 * g; // P's stiffness, ρ = 1
    let spec = ContactSpec::linear(
        Scaled::Absolute(kn),
        Scaled::Absolute(kn),
        LinearDamping::Restitution(0.1),
        0.5,
    )
    .with_normal_force(NormalForce::Depth);
    let mut w = on_floor(
        Shape::Ellipse { a, b },
        b,
        Vec2::zeros(),
        Vec2::new(0.0, -g),
        spec,
        1e-5,
    );
    Simulation::new(&mut w).for_steps(20_000).run().unwrap();
    let depth = b - w.bodies.state[0].pose.position.y;
    assert_relative_eq!(depth, m * g / kn, max_relative = 1e-9);
    assert!(w.bodies.state[0].pose.angle().abs() < 1e-12);
}

/// Maximum |E(t) − E(0)| / E(0) of an undamped frictionless disk bouncing on a floor (four
/// bounces), E = kinetic + potential + elastic.
fn bounce_energy_error(dt: f64) -> f64 {
    let spec = linear(1e6, 0.0, 0.0);
    let mut w = on_floor(
        Shape::Circle { r: 1.0 },
        3.0,
        Vec2::zeros(),
        Vec2::new(0.0, -980.0),
        spec,
        dt,
    );
    let e0 = w.energies.total();
    let mut worst: f64 = 0.0;
    Simulation::new(&mut w)
        .until_time(0.5)
        .run_each(|w, _| {
            let e = w.energies.kinetic + w.energies.potential + w.energies.elastic;
            worst = worst.max((e - e0).abs() / e0);
            assert_eq!(
                w.energies.dissipated, 0.0,
                "no dissipation without dashpots and friction"
            );
        })
        .unwrap();
    worst
}

#[test]
fn elastic_bounce_conserves_energy_to_second_order_in_dt() {
    // ω₀ = √(k/m) ≈ 564 rad/s. Velocity Verlet's energy error is O((ω₀Δt)²) — measured
    // 0.14–0.24 (ω₀Δt)², depending on where the impacts fall between steps: bound 0.3 (ω₀Δt)²,
    // and three halvings of Δt must cut it by at least 16 (64 expected).
    let w0 = (1e6f64 / std::f64::consts::PI).sqrt();
    let errs: Vec<f64> = [1e-4, 5e-5, 2.5e-5, 1.25e-5]
        .iter()
        .map(|&dt| {
            let err = bounce_energy_error(dt);
            assert!(
                err <= 0.3 * (w0 * dt).powi(2),
                "dt = {dt}: relative energy error {err:e}"
            );
            err
        })
        .collect();
    assert!(
        errs[3] < errs[0] / 16.0,
        "error did not shrink like dt²: {errs:?}"
    );
}

#[test]
fn free_collision_conserves_momentum_to_round_off() {
    // Two ellipses, friction and dashpots, no gravity: forces are equal and opposite at one point,
    // so linear and angular momentum are conserved to round-off while energy is dissipated.
    let spec = linear(1e5, 50.0, 0.5);
    let bodies = [
        moving(
            Shape::Ellipse { a: 1.5, b: 1.0 },
            0.0,
            0.0,
            0.3,
            Vec2::new(5.0, 0.5),
            1.0,
        ),
        moving(
            Shape::Ellipse { a: 1.2, b: 0.5 },
            4.0,
            0.7,
            -0.8,
            Vec2::new(-3.0, 0.0),
            -2.0,
        ),
    ];
    let mut w = World::new(&bodies, vec![], Vec2::zeros(), spec, 1e-5);
    let (p0, l0) = (w.momentum(), w.angular_momentum());
    let e0 = w.energies.total();
    let mut touched = false;
    Simulation::new(&mut w)
        .for_steps(100_000)
        .run_each(|w, _| touched |= !w.contacts.is_empty())
        .unwrap();
    assert!(touched, "the bodies never met");
    // Round-off: 1e5 steps each rounding terms of size Σm|v| (momentum) and Σ(m|x||v| + I|ω|)
    // (angular momentum about the origin) by an ulp or so.
    let b = &w.bodies;
    let p_scale: f64 = (0..2)
        .map(|k| b.mass[k] * b.state[k].vel.norm())
        .sum::<f64>()
        .max(p0.norm());
    let l_scale: f64 = (0..2)
        .map(|k| {
            b.mass[k] * b.state[k].pose.position.norm() * b.state[k].vel.norm()
                + b.inertia[k] * b.state[k].omega.abs()
        })
        .sum::<f64>()
        .max(l0.abs());
    let steps = 1e5;
    assert!(
        (w.momentum() - p0).norm() < steps * f64::EPSILON * p_scale,
        "{:?} vs {:?}",
        w.momentum(),
        p0
    );
    assert!(
        (w.angular_momentum() - l0).abs() < steps * f64::EPSILON * l_scale,
        "{} vs {}",
        w.angular_momentum(),
        l0
    );
    // (Energy is not a conserved quantity of this model for ellipses: a spring on the depth
    // acting at the chord midpoint is the gradient of ½k_nδ² only to O(δ/a) — see docs/src/physics/normal-force.md.)
    assert!(w.energies.dissipated > 0.0 && w.energies.total() < e0);
}

#[test]
fn rotating_the_whole_scene_rotates_the_trajectory() {
    // Wall, gravity and body rotated by ψ: every state is the rotated one, to the rounding of the
    // rotated inputs as the impacts amplify it (1e-9 of the body size over the first impacts;
    // each further bounce multiplies it, the motion being chaotic).
    let psi: f64 = 0.7391;
    let (s, c) = psi.sin_cos();
    let rot = |v: Vec2| Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y);
    let spec = linear(36400.0 * 980.0, 500.0, 0.3);
    let make = |r: &dyn Fn(Vec2) -> Vec2, angle: f64| {
        let wall = Wall::new(r(Vec2::new(0.0, 0.0)), r(Vec2::y())).unwrap();
        World::new(
            &[BodyInit {
                material: 0,
                prescribed: false,
                shape: Shape::Ellipse { a: 1.5, b: 1.0 },
                position: r(Vec2::new(0.3, 3.0)),
                angle: 0.4 + angle,
                velocity: r(Vec2::new(8.0, 0.0)),
                omega: 3.0,
                density: 1.0,
            }],
            vec![Boundary::new(wall, spec)],
            r(Vec2::new(0.0, -980.0)),
            spec,
            1e-5,
        )
    };
    let (mut a, mut b) = (make(&|v| v, 0.0), make(&rot, psi));
    // The two worlds in lockstep, one step per call.
    let mut sa = Simulation::new(&mut a).for_steps(1);
    let mut sb = Simulation::new(&mut b).for_steps(1);
    for step in 0..20_000 {
        sa.run().unwrap();
        sb.run().unwrap();
        let (a, b) = (sa.world(), sb.world());
        if step % 500 == 0 {
            let pa = rot(a.bodies.state[0].pose.position);
            let pb = b.bodies.state[0].pose.position;
            assert!(
                (pa - pb).norm() < 1e-9 * 1.5,
                "step {step}: {pa:?} vs {pb:?}"
            );
            assert!(
                (a.bodies.state[0].pose.angle() + psi - b.bodies.state[0].pose.angle()).abs()
                    < 1e-9
            );
        }
    }
    assert!(
        a.diagnostics.max_depth_ratio > 0.0,
        "the ellipse never hit the wall"
    );
}

/// Restitution of the 1D damped Hertz impact `m δ̈ = −max(0, k(δ)δ + η(δ)δ̇)` with
/// `k = 4/3 E*√(Rδ)` (T10) and `η = β√(m k)` (T14), by classical RK4 at 2e5 steps per contact —
/// an integrator independent of the code under test.
fn hertz_ode_restitution(m: f64, e_star: f64, r: f64, beta: f64, v0: f64, tc: f64) -> f64 {
    let force = |d: f64, v: f64| {
        let k = 4.0 / 3.0 * e_star * (r * d.max(0.0)).sqrt();
        let eta = beta * (m * k).sqrt();
        (k * d + eta * v).max(0.0)
    };
    let acc = |d: f64, v: f64| if d > 0.0 { -force(d, v) / m } else { 0.0 };
    let h = tc / 2e5;
    let (mut d, mut v) = (0.0, v0);
    loop {
        let (k1d, k1v) = (v, acc(d, v));
        let (k2d, k2v) = (v + 0.5 * h * k1v, acc(d + 0.5 * h * k1d, v + 0.5 * h * k1v));
        let (k3d, k3v) = (v + 0.5 * h * k2v, acc(d + 0.5 * h * k2d, v + 0.5 * h * k2v));
        let (k4d, k4v) = (v + h * k3v, acc(d + h * k3d, v + h * k3v));
        d += h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if d < 0.0 {
            return -v / v0;
        }
    }
}

#[test]
fn hertz_impact_matches_closed_form_and_an_independent_integration() {
    // Undamped: Hertz's contact time t_c = 2.9432 δ_max/v0, δ_max = (15 m* v0²/(16 E*√R*))^(2/5),
    // and e = 1. Damped (T14): the restitution of the 1D ODE integrated by RK4. Tolerance 1e-3
    // (2e4 steps per contact; the contact's ends fall between steps).
    let (young, nu, r, v0) = (1e8, 0.3, 1.0f64, 10.0);
    let m = std::f64::consts::PI;
    let e_star = 1.0 / (2.0 * (1.0 - nu * nu) / young); // T(11), body and wall of one material
    let d_max = (15.0 * m * v0 * v0 / (16.0 * e_star * r.sqrt())).powf(0.4);
    let tc = 2.9432 * d_max / v0;
    for e in [1.0, 0.9, 0.7, 0.5] {
        let spec =
            ContactSpec::hertz_mindlin(young, nu, e, 0.0).with_normal_force(NormalForce::Depth);
        let mut w = on_floor(
            Shape::Circle { r },
            r,
            Vec2::new(0.0, -v0),
            Vec2::zeros(),
            spec,
            tc / 2e4,
        );
        let t_end = separation_time(&mut w, r, 10.0 * tc);
        let measured = w.bodies.state[0].vel.y / v0;
        let beta = dem2d::contact_law::damping_factor_hertz(e);
        assert_relative_eq!(
            measured,
            hertz_ode_restitution(m, e_star, r, beta, v0, tc),
            max_relative = 1e-3
        );
        if e == 1.0 {
            assert_relative_eq!(t_end, tc, max_relative = 1e-3);
        }
    }
}

#[test]
fn network_critical_step_matches_the_modes_of_closed_form_systems() {
    use dem2d::dynamics::timestep::critical_dt;
    let m = std::f64::consts::PI; // disks of radius 1, density 1
    let k: f64 = 1e6;
    // Two disks squeezed between two walls, frictionless: a chain wall–m–m–wall of three equal
    // springs, eigenvalues (k/m)(2 ∓ 1): the stiffest ω² = 3k/m. Undamped: Δt = 2/ω.
    let spec = linear(k, 0.0, 0.0);
    let walls = vec![
        Boundary::new(Wall::new(Vec2::new(0.0, 0.0), Vec2::x()).unwrap(), spec),
        Boundary::new(Wall::new(Vec2::new(3.97, 0.0), -Vec2::x()).unwrap(), spec),
    ];
    let disks = [
        moving(Shape::Circle { r: 1.0 }, 0.99, 0.0, 0.0, Vec2::zeros(), 0.0),
        moving(Shape::Circle { r: 1.0 }, 2.98, 0.0, 0.0, Vec2::zeros(), 0.0),
    ];
    let mut w = World::new(&disks, walls, Vec2::zeros(), spec, 1e-6);
    assert_eq!(w.contacts.len(), 3);
    assert_relative_eq!(
        w.network_critical_dt(),
        2.0 / (3.0 * k / m).sqrt(),
        max_relative = 1e-5
    );
    // A disk resting on a floor with friction and dashpots: the normal mode has ω² = k_n/m; the
    // shear spring at the contact point drives slip and roll through the lever h (the centre's
    // height above the floor), w = 1/m + h²/I = (1 + 2h²)/m ≈ 3/m, ω² = k_s w, damping ratio
    // ζ = ηw/(2ω): Δt = 2(√(1+ζ²) − ζ)/ω of the stiffer of the two.
    let eta = 100.0;
    let spec = linear(k, eta, 0.5);
    let mut w = on_floor(
        Shape::Circle { r: 1.0 },
        1.0 - 1e-4,
        Vec2::zeros(),
        Vec2::new(0.0, -980.0),
        spec,
        1e-6,
    );
    let h = 1.0 - 1e-4;
    let expected = critical_dt(k, eta, (1.0 + 2.0 * h * h) / m).min(critical_dt(k, eta, 1.0 / m));
    assert_relative_eq!(w.network_critical_dt(), expected, max_relative = 1e-5);
}

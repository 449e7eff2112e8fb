//! Boundaries that move, against closed forms.
//!
//! - The moving mirror: a wall at constant speed V reaches a body resting at gap g at
//!   `t = g/V`; in the wall's (inertial) frame the body comes in at V and leaves at eV, so in
//!   the lab it leaves at `(1 + e)V` — `2V` for an elastic contact. The law sees the relative
//!   velocity, so the rebound is the fixed-wall one, shifted: compared exactly against the same
//!   collision with the wall at rest and the body thrown at it (the same relative motion from
//!   the same gap, so the contact starts at the same phase of the same step).
//! - The conveyor: a disk set down at rest on a belt moving at V is dragged until its contact
//!   point moves with the belt; the friction impulse P gives `v = P/m`, `ωr = 2P/m`
//!   (I = ½mr²) and `v + ωr = V`: it ends rolling with `v = V/3`. The shear spring acts on the
//!   relative velocity.
//! - The energy account: `K + P + E_el + D = E₀ + W`, W the walls' work.
//! - The servo: a wall on a settled pile holds its target stress.

use dem2d::contact_law::{ContactSpec, LinearDamping, NormalForce, Scaled};
use dem2d::dynamics::{BodyInit, Boundary, Motion, Servo, Span, World};
use dem2d::geometry::{Shape, Vec2, Wall};
use dem2d::run::Simulation;
use dem2d::scene::Case;
use dem2d::scene::generate::{PileShape, PileSpec};
use std::f64::consts::PI;

const KN: f64 = 36400.0 * 980.0;

fn spec(damping: LinearDamping, friction: f64, nf: NormalForce) -> ContactSpec {
    ContactSpec::linear(
        Scaled::Absolute(KN),
        Scaled::Absolute(KN),
        damping,
        friction,
    )
    .with_normal_force(nf)
}

fn body(shape: Shape, x: f64, y: f64, v: Vec2) -> BodyInit {
    BodyInit {
        material: 0,
        prescribed: false,
        shape,
        position: Vec2::new(x, y),
        angle: 0.0,
        velocity: v,
        omega: 0.0,
        density: 1.0,
    }
}

/// A body (support `h` along x) at the origin and a wall at x = −h − gap with normal +x, no
/// gravity: the wall moves at `wall_v` and the body at `body_v` (along x). Runs until they
/// separate; returns the step of first contact and the body's final velocity and the world.
fn collide(
    shape: Shape,
    h: f64,
    gap: f64,
    wall_v: f64,
    body_v: f64,
    s: ContactSpec,
    dt: f64,
) -> (u64, f64, World) {
    let wall = Wall::new(Vec2::new(-h - gap, 0.0), Vec2::x()).unwrap();
    let motion = if wall_v != 0.0 {
        Motion::Velocity(Vec2::new(wall_v, 0.0))
    } else {
        Motion::Fixed
    };
    let mut w = World::new(
        &[body(shape, 0.0, 0.0, Vec2::new(body_v, 0.0))],
        vec![Boundary::moving(wall, s, motion)],
        Vec2::zeros(),
        s,
        dt,
    );
    let mut first = None;
    Simulation::new(&mut w)
        .run_until(|w, r| {
            if r.contacts > 0 {
                first.get_or_insert(w.step);
            }
            r.contacts == 0 && first.is_some()
        })
        .unwrap();
    let v = w.bodies.state[0].vel.x;
    (first.unwrap(), v, w)
}

#[test]
fn a_moving_wall_reaches_a_resting_body_on_time_and_sends_it_off_at_one_plus_e_times_its_speed() {
    // A gap that the wall covers part-way through a step (at a step boundary, the rounding
    // of the positions would decide the step).
    let (speed, dt) = (10.0, 1e-6);
    let gap = 0.5 + 0.37 * speed * dt;
    let undamped = LinearDamping::Dashpots {
        eta_n: Scaled::Absolute(0.0),
        eta_s: Scaled::Absolute(0.0),
    };
    let shapes = [
        (Shape::Circle { r: 1.0 }, 1.0),
        (Shape::Ellipse { a: 1.5, b: 1.0 }, 1.5), // its tip towards the wall
        (Shape::Rectangle { w: 2.0, h: 1.0 }, 1.0), // a face towards the wall
    ];
    for (shape, h) in shapes {
        let m = shape.area();
        for nf in [NormalForce::Depth, NormalForce::Area] {
            for damping in [undamped, LinearDamping::Restitution(0.5)] {
                let s = spec(damping, 0.3, nf);
                let (step, v, w) = collide(shape, h, gap, speed, 0.0, s, dt);
                // Contact begins in the first step at whose end the wall has covered the gap
                // (the wall's position is p₀ + tV exactly: only the rounding of one product).
                let want_step = (gap / (speed * dt)).ceil() as u64;
                assert!(
                    step.abs_diff(want_step) <= 1,
                    "first contact {step} vs {want_step}"
                );
                // The same collision seen from the wall: the body thrown at a wall at rest.
                let (step_f, v_f, _) = collide(shape, h, gap, 0.0, -speed, s, dt);
                let e = v_f / speed;
                eprintln!(
                    "{} {} {:?}: contact at step {step} (want {want_step}), leaves at {:.8} V; \
                     fixed wall: e = {e:.8}; W = {:.6e} erg, ½m(v² − 0) = {:.6e} erg",
                    shape.type_name(),
                    nf.as_str(),
                    damping,
                    v / speed,
                    w.energies.boundary_work,
                    0.5 * m * v * v,
                );
                assert_eq!(step, step_f);
                // Galilean invariance, to the rounding of the positions: the thrown body's
                // position accumulates ~ε|x| per step, so over the steps to contact the two runs'
                // overlaps differ by up to ~N ε |x| of the peak overlap δ ≈ V√(m/k_n).
                let delta_peak = speed * (m / KN).sqrt();
                let rounding = 8.0 * step as f64 * f64::EPSILON * (h + gap) / delta_peak;
                assert!(
                    (v - (1.0 + e) * speed).abs() < rounding * speed,
                    "{v} vs (1 + {e})V: {:.2e} of V, rounding bound {rounding:.2e}",
                    (v - (1.0 + e) * speed).abs() / speed
                );
                if damping == undamped {
                    // Elastic: 2V, to Verlet's error on the impact (ωΔt = 3e-3 here).
                    assert!((v / speed - 2.0).abs() < 1e-5, "elastic: {}", v / speed);
                }
                // The walls' work: all the body's energy (elastic), plus the dissipated.
                let e_acc = w.energies;
                let account = e_acc.kinetic + e_acc.elastic + e_acc.dissipated;
                assert!(
                    (account - e_acc.boundary_work).abs() < 1e-6 * e_acc.boundary_work,
                    "K + E + D = {account}, W = {}",
                    e_acc.boundary_work
                );
                assert!(e_acc.kinetic > 0.0 && (e_acc.kinetic - 0.5 * m * v * v).abs() < 1e-9);
            }
        }
    }
}

#[test]
fn a_disk_set_down_on_a_moving_belt_ends_rolling_at_a_third_of_its_speed() {
    let (r, speed, g) = (1.0, 30.0, 980.0);
    let m = PI * r * r;
    let delta = m * g / KN;
    let s = spec(LinearDamping::Restitution(0.5), 0.5, NormalForce::Area);
    let belt = Wall::new(Vec2::zeros(), Vec2::y()).unwrap();
    let mut w = World::new(
        &[body(Shape::Circle { r }, 0.0, r - delta, Vec2::zeros())],
        vec![Boundary::moving(
            belt,
            s,
            Motion::Velocity(Vec2::new(speed, 0.0)),
        )],
        Vec2::new(0.0, -g),
        s,
        1e-5,
    );
    Simulation::new(&mut w).until_time(0.3).run().unwrap();
    let st = &w.bodies.state[0];
    eprintln!(
        "belt at {speed}: v = {:.6} ({:.6} V), ωr = {:.6}, slip {:.2e}",
        st.vel.x,
        st.vel.x / speed,
        -st.omega * r,
        st.vel.x + st.omega * (r - delta) - speed
    );
    // Rolling: the contact point moves with the belt (to the shear spring's creep δ/r).
    assert!(((st.vel.x + st.omega * (r - delta)) / speed - 1.0).abs() < 1e-6);
    // v = V/3: angular momentum about the contact point is conserved (the friction impulse
    // has no moment there), to the O(δ/r) of the lever r − δ.
    assert!(
        (st.vel.x / speed - 1.0 / 3.0).abs() < delta / r,
        "{}",
        st.vel.x / speed
    );
}

/// A pile of `n` disks settled in its box (floor, two side walls), then a top wall that holds
/// the normal stress `sigma` over the span between the side walls.
fn servo_on_pile(n: usize, sigma: f64) -> (World, Vec<f64>, f64) {
    let spec = PileSpec::new(PileShape::Disks, n, 3);
    let case = Case::from_json(&spec.case_json()).unwrap();
    let mut w = case.build_world();
    Simulation::new(&mut w).until_time(1.0).run().unwrap();
    let top = w
        .bodies
        .state
        .iter()
        .zip(&w.bodies.bound)
        .map(|(s, r)| s.pose.position.y + r)
        .fold(0.0f64, f64::max);
    let servo = Servo {
        stress: sigma,
        span: Span::Between(1, 2),
        gain: None,
        max_speed: 20.0,
    };
    let wall = Wall::new(Vec2::new(0.0, top + 0.2), Vec2::new(0.0, -1.0)).unwrap();
    let mut walls = w.walls.clone();
    walls.push(Boundary::moving(wall, case.contact, Motion::Servo(servo)));
    let bodies: Vec<BodyInit> = (0..w.bodies.len())
        .map(|k| BodyInit {
            material: 0,
            prescribed: false,
            shape: w.bodies.shape[k],
            position: w.bodies.state[k].pose.position,
            angle: w.bodies.state[k].pose.angle(),
            velocity: w.bodies.state[k].vel,
            omega: w.bodies.state[k].omega,
            density: w.bodies.density[k],
        })
        .collect();
    let mut w = World::new(&bodies, walls, case.gravity, case.contact, case.dt);
    let e0 = w.energies.total();
    let mut stress = Vec::new();
    Simulation::new(&mut w)
        .until_time(1.0)
        .run_each(|w, _| {
            let (s, _) = w.walls[3].measured_stress(&w.walls).unwrap();
            stress.push(s);
            if std::env::var_os("SERVO_TRACE").is_some() && w.step.is_multiple_of(500) {
                eprintln!(
                    "t {:.4} σ {s:.1} y {:.5} v {:.4e} contacts {} K {:.3e}",
                    w.time,
                    w.walls[3].line().point.y,
                    w.walls[3].velocity.y,
                    w.walls[3].load.contacts,
                    w.energies.kinetic
                );
            }
        })
        .unwrap();
    (w, stress, e0)
}

#[test]
fn a_servo_wall_on_a_settled_pile_holds_its_target_stress_within_one_percent() {
    let sigma = 2e4; // dyn/cm², about twice the weight of the pile per unit width
    let (w, stress, e0) = servo_on_pile(200, sigma);
    let last = &stress[stress.len() / 2..];
    let mean = last.iter().sum::<f64>() / last.len() as f64;
    let worst = last
        .iter()
        .map(|s| (s / sigma - 1.0).abs())
        .fold(0.0f64, f64::max);
    let e = w.energies;
    let account = e.total() - e0 - e.boundary_work;
    eprintln!(
        "servo σ_t = {sigma}: mean over the last 0.5 s {mean:.3} ({:.2e}), worst step {worst:.2e}; \
         wall at y = {:.4}; its work W = {:.4e} erg, dissipated {:.4e} erg, account \
         K + P + E + D − E₀ − W = {account:.2e} erg",
        mean / sigma - 1.0,
        w.walls[3].line().point.y,
        e.boundary_work,
        e.dissipated,
    );
    assert!((mean / sigma - 1.0).abs() < 0.01, "mean {mean}");
    assert!(
        worst < 0.01,
        "every step of the last 0.5 s within 1 %: worst {worst}"
    );
    // The walls' work is in the account (it closes to the accuracy P Fig. 4's does, 4e-4 of
    // what was dissipated).
    assert!(account.abs() < 1e-3 * e.dissipated, "account {account}");
}

/// The blow-up watch counts the walls' work: a wall that hits a resting body gives it all its
/// energy (nothing was in motion before), which is no blow-up; the same scene at a step far
/// above the critical one is one, found by the energy criterion before anything is non-finite.
#[test]
fn the_blow_up_watch_counts_the_work_of_moving_walls() {
    use dem2d::run::RunError;
    let undamped = LinearDamping::Dashpots {
        eta_n: Scaled::Absolute(0.0),
        eta_s: Scaled::Absolute(0.0),
    };
    let s = spec(undamped, 0.0, NormalForce::Area);
    let run = |dt: f64| {
        let wall = Wall::new(Vec2::new(-1.5, 0.0), Vec2::x()).unwrap();
        let mut w = World::new(
            &[body(Shape::Circle { r: 1.0 }, 0.0, 0.0, Vec2::zeros())],
            vec![Boundary::moving(
                wall,
                s,
                Motion::Velocity(Vec2::new(100.0, 0.0)),
            )],
            Vec2::zeros(),
            s,
            dt,
        );
        let ended = Simulation::new(&mut w).until_time(0.02).run();
        (ended, w)
    };
    let (ended, w) = run(1e-6);
    assert!(ended.is_ok(), "{ended:?}");
    assert!(w.energies.kinetic > 0.9 * 2.0 * PI * 100.0 * 100.0); // ½ m (2V)²
    // ωΔt = 3370 × 2e-3 ≫ 2: unstable.
    let (ended, _) = run(2e-3);
    assert!(
        matches!(&ended, Err(RunError::Blowup(b)) if !b.within_step && b.reason.contains("the energy grew")),
        "{ended:?}"
    );
}

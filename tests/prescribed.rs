//! Bodies whose motion is prescribed (`"fixed": true`, `"prescribed": true`) against closed
//! forms: a disk dropped on a fixed disk rebounds as from a wall (an obstacle of infinite mass),
//! a disk resting in the groove of two fixed disks loads each with `m g/(2 cos θ)` (their
//! reactions), a disk struck by a prescribed paddle leaves at `v(1 + ε)`, and a block carried by
//! a prescribed belt or by two spinning rollers reaches the surface's speed `v` after `v/(μg)`,
//! the drive having done the work `m v²` (half the block's energy of motion, half dissipated by
//! sliding); the energy account closes with the prescribed bodies' work.

use dem2d::dynamics::World;
use dem2d::geometry::Vec2;
use dem2d::run::Simulation;
use dem2d::scene::Case;
use std::f64::consts::PI;

mod common;

fn world(contact: &str, walls: &str, bodies: &str, dt: f64) -> World {
    world_in(contact, walls, bodies, dt, -980.0)
}

fn world_in(contact: &str, walls: &str, bodies: &str, dt: f64, gy: f64) -> World {
    let text = format!(
        r#"{{ "version": 1, "name": "prescribed", "gravity": [0, {gy}], "dt": {dt}, "duration": 10,
        "contact": {contact}, "walls": {walls}, "bodies": {bodies} }}"#
    );
    Case::from_json(&text)
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .build_world()
}

/// The restitution of T12's linear spring–dashpot whose force may not pull (Schwager & Pöschel,
/// Granular Matter 9 (2007) 465; see `tests/materials.rs`).
fn clamped_restitution(e: f64) -> f64 {
    let l = e.ln();
    let zeta = -l / (l * l + PI * PI).sqrt(); // T(12)
    let w = (1.0 - zeta * zeta).sqrt();
    (-(zeta / w) * (PI - (2.0 * zeta * w / (w * w - zeta * zeta)).atan())).exp()
}

/// `|E − E₀ − W| / E₀`: what the energy account leaves unexplained.
fn account_error(w: &World, e0: f64) -> f64 {
    let e = &w.energies;
    (e.total() - e0 - e.boundary_work).abs() / e0.abs()
}

#[test]
fn a_disk_rebounds_from_a_fixed_disk_as_from_a_wall() {
    // Dropped from rest 1 cm above, it meets the obstacle at √(2g·1) and must leave at ε times
    // that whatever the obstacle's density (it has none that matters: it does not move).
    let law = r#"{ "model": "linear", "kn": 1e7, "restitution": 0.7, "friction": 0 }"#;
    let v_in = (2.0 * 980.0 * 1.0f64).sqrt();
    for (walls, obstacle) in [
        (
            "[]",
            r#", { "shape": {"type": "circle", "r": 3}, "position": [0, -3], "fixed": true,
                       "density": 1e-3 }"#,
        ),
        (r#"[ { "point": [0, 0], "normal": [0, 1] } ]"#, ""),
    ] {
        let mut w = world(
            law,
            walls,
            &format!(
                r#"[ {{ "shape": {{"type": "circle", "r": 1}}, "position": [0, 2] }} {obstacle} ]"#
            ),
            1e-6,
        );
        // Falls for √(2/g) = 45 ms; the contact lasts under 2 ms.
        let mut top = 0.0f64;
        Simulation::new(&mut w)
            .until_time(0.06)
            .run_each(|w, _| top = top.max(w.bodies.state[0].vel.y))
            .unwrap();
        let (got, want) = (top / v_in, clamped_restitution(0.7));
        assert!(
            (got - want).abs() < 2e-3,
            "{obstacle}: ε = {got}, want {want}"
        );
        if !obstacle.is_empty() {
            // The obstacle never moved.
            assert_eq!(w.bodies.state[1].pose.position, Vec2::new(0.0, -3.0));
            assert_eq!(w.bodies.state[1].vel, Vec2::zeros());
        }
    }
}

#[test]
fn a_disk_in_the_groove_of_two_fixed_disks_loads_each_with_half_its_weight_over_cos_theta() {
    // Disks of radius 1 at x = ±1.2 hold a disk of radius 1: cos θ = y/(R + r) with
    // y = √(2² − 1.2²) = 1.6, so cos θ = 0.8: each reaction is (∓ m g tan θ/2, −m g/2)
    // (without friction: with it, the tangential forces make the supports' share statically
    // indeterminate).
    let mut w = world(
        r#"{ "model": "linear", "kn": 1e8, "restitution": 0.2, "friction": 0 }"#,
        "[]",
        r#"[ { "shape": {"type": "circle", "r": 1}, "position": [0, 1.6] },
             { "shape": {"type": "circle", "r": 1}, "position": [-1.2, 0], "fixed": true },
             { "shape": {"type": "circle", "r": 1}, "position": [1.2, 0], "fixed": true } ]"#,
        1e-6,
    );
    Simulation::new(&mut w).until_time(0.05).run().unwrap();
    let m = PI;
    let (fy, fx) = (-m * 980.0 / 2.0, m * 980.0 / 2.0 * 0.75);
    let b = &w.bodies;
    for (k, sign) in [(1, -1.0), (2, 1.0)] {
        let f = b.force[k];
        assert!(
            (f.y - fy).abs() < 1e-3 * fy.abs() && (f.x - sign * fx).abs() < 1e-3 * fx,
            "support {k}: {f:?}, want ({}, {fy})",
            sign * fx
        );
    }
    // The supports' reactions carry the whole weight, and the held disk is at rest.
    assert!(b.state[0].vel.norm() < 1e-4, "{:?}", b.state[0].vel);
    // Fixed bodies add no energy of motion or position.
    assert!(w.energies.kinetic < 1e-6 && w.energies.boundary_work == 0.0);
}

#[test]
fn a_paddle_at_speed_v_sends_a_disk_off_at_v_one_plus_epsilon() {
    let v = 50.0;
    let mut w = world_in(
        r#"{ "model": "linear", "kn": 1e7, "restitution": 0.6, "friction": 0 }"#,
        "[]",
        &format!(
            r#"[ {{ "shape": {{"type": "circle", "r": 1}}, "position": [3, 0] }},
                 {{ "shape": {{"type": "rectangle", "w": 1, "h": 4}}, "position": [0, 0],
                    "velocity": [{v}, 0], "prescribed": true }} ]"#
        ),
        1e-6,
        0.0,
    );
    let e0 = w.energies.total();
    // Meets after 1.5/v = 30 ms; the contact lasts about 2 ms.
    Simulation::new(&mut w).until_time(0.06).run().unwrap();
    let b = &w.bodies;
    assert!(w.contacts.active().next().is_none(), "still in contact");
    let want = v * (1.0 + clamped_restitution(0.6));
    assert!(
        (b.state[0].vel.x - want).abs() < 1e-3 * want,
        "{} {want}",
        b.state[0].vel.x
    );
    // The paddle kept its speed and went where it was sent.
    assert_eq!(b.state[1].vel, Vec2::new(v, 0.0));
    assert!((b.state[1].pose.position.x - v * w.time).abs() < 1e-9);
    // The work it did is the disk's energy of motion plus what the collision dissipated.
    assert!(w.energies.boundary_work > 0.0);
    let e = &w.energies;
    assert!((e.total() - e0 - e.boundary_work).abs() < 1e-6 * e.boundary_work);
}

/// A block of 4 × 0.5 cm on a surface moving at `v` (a belt, or two rollers' tops), dragged by
/// friction μ: the time its velocity takes to reach 99 % of v, its final velocity, the work the
/// drive did, the block's mass, and the energy account's error.
fn carried(bodies: &str, v: f64) -> (f64, f64, f64, f64, f64) {
    let mut w = world(
        r#"{ "model": "linear", "kn": 1e7, "restitution": 0.3, "friction": 0.25 }"#,
        "[]",
        bodies,
        1e-6,
    );
    // Let it settle on the surface first (the surface moves from the start: the block slides
    // from the first touch).
    let e0 = w.energies.total();
    let mut reached = None;
    Simulation::new(&mut w)
        .until_time(0.1)
        .run_each(|w, _| {
            if reached.is_none() && w.bodies.state[0].vel.x.abs() >= 0.99 * v.abs() {
                reached = Some(w.time);
            }
        })
        .unwrap();
    let b = &w.bodies;
    (
        reached.expect("the block reaches the surface's speed"),
        b.state[0].vel.x,
        w.energies.boundary_work,
        b.mass[0],
        account_error(&w, e0),
    )
}

#[test]
fn a_belt_carries_a_block_to_its_speed_after_v_over_mu_g_having_done_the_work_m_v_squared() {
    let v = 10.0;
    let (t, vx, work, m, err) = carried(
        &format!(
            r#"[ {{ "shape": {{"type": "rectangle", "w": 4, "h": 0.5}}, "position": [0, 0.2499] }},
                 {{ "shape": {{"type": "rectangle", "w": 40, "h": 1}}, "position": [0, -0.5],
                    "velocity": [{v}, 0], "prescribed": true }} ]"#
        ),
        v,
    );
    // Sliding at μg = 245 cm/s², it reaches 0.99 v at 0.99 v/(μg) = 40.4 ms.
    let want = 0.99 * v / (0.25 * 980.0);
    assert!((t - want).abs() < 0.01 * want, "{t} {want}");
    assert!((vx - v).abs() < 1e-3 * v, "{vx}");
    assert!(
        (work - m * v * v).abs() < 0.01 * m * v * v,
        "{work} {}",
        m * v * v
    );
    assert!(err < 1e-6, "{err}");
}

#[test]
fn two_spinning_rollers_carry_a_block_to_their_surface_speed() {
    // Rollers of radius 0.5 spinning at ω = −20 rad/s (clockwise): their tops move at
    // −ω r = +10 cm/s.
    let (omega, r) = (-20.0, 0.5);
    let v = -omega * r;
    let (t, vx, work, m, err) = carried(
        &format!(
            r#"[ {{ "shape": {{"type": "rectangle", "w": 4, "h": 0.5}}, "position": [0, 0.7499] }},
                 {{ "shape": {{"type": "circle", "r": {r}}}, "position": [-1, 0], "omega": {omega},
                    "prescribed": true }},
                 {{ "shape": {{"type": "circle", "r": {r}}}, "position": [1, 0], "omega": {omega},
                    "prescribed": true }} ]"#
        ),
        v,
    );
    let want = 0.99 * v / (0.25 * 980.0);
    assert!((t - want).abs() < 0.02 * want, "{t} {want}");
    assert!((vx - v).abs() < 1e-3 * v, "{vx}");
    assert!(
        (work - m * v * v).abs() < 0.02 * m * v * v,
        "{work} {}",
        m * v * v
    );
    assert!(err < 1e-6, "{err}");
}

#[test]
fn reactions_csv_reports_the_supports_reactions_at_every_frame() {
    let dir = common::scratch("reactions");
    let case = dir.join("groove.json");
    std::fs::write(
        &case,
        r#"{ "version": 1, "name": "groove", "gravity": [0, -980], "dt": 1e-6, "duration": 0.05,
        "output_every": 10000,
        "contact": { "model": "linear", "kn": 1e8, "restitution": 0.2, "friction": 0 },
        "bodies": [ { "shape": {"type": "circle", "r": 1}, "position": [0, 1.6] },
                    { "shape": {"type": "circle", "r": 1}, "position": [-1.2, 0], "fixed": true },
                    { "shape": {"type": "circle", "r": 1}, "position": [1.2, 0], "fixed": true } ] }"#,
    )
    .unwrap();
    let out = dir.join("run");
    let (code, _, err) = common::dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(out.join("reactions.csv")).unwrap();
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    // Frames at steps 0, 10000, …, 50000, two supports each.
    assert_eq!(rows.len(), 12, "{text}");
    let last = &rows[10..];
    for (row, (body, x)) in last.iter().zip([("1", -1.2), ("2", 1.2)]) {
        assert_eq!(row[0], "50000");
        assert_eq!(row[2], body);
        let num = |k: usize| row[k].parse::<f64>().unwrap();
        assert_eq!((num(3), num(4)), (x, 0.0), "a fixed body stays");
        let fy = -PI * 980.0 / 2.0;
        assert!((num(7) - fy).abs() < 1e-3 * fy.abs(), "{row:?}");
        assert!(
            (num(6) - x.signum() * 0.75 * fy.abs()).abs() < 1e-3 * fy.abs(),
            "{row:?}"
        );
        assert_eq!(num(9), 0.0, "a fixed body does no work");
    }
}

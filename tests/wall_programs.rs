//! Wall programs (`"motion": [stages]`) against independent answers: a wall's position is the
//! integral of its stages' velocities (each stage ending at the step nearest its `until`), a
//! servo stage holds its stress (a loading–unloading path of two targets), and the energy
//! account closes with the work of a lid driven by a program.

use dem2d::dynamics::World;
use dem2d::geometry::Vec2;
use dem2d::run::Simulation;
use dem2d::scene::Case;

mod common;

fn world(dt: f64, walls: &str, bodies: &str) -> World {
    let text = format!(
        r#"{{ "version": 1, "name": "program", "gravity": [0, -980], "dt": {dt}, "duration": 10,
        "contact": {{ "model": "linear", "kn_over_rho_g": 36400, "restitution": 0.5,
                      "friction": 0.5 }},
        "walls": {walls}, "bodies": {bodies} }}"#
    );
    Case::from_json(&text)
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .build_world()
}

/// The position at time `t` of a point starting at `p0` and moving at `stages[s].1` until
/// `stages[s].0` (the last one to the end), by hand: the sum of each stage's velocity times the
/// part of [0, t] it covers.
fn integral(p0: Vec2, stages: &[(f64, Vec2)], t: f64) -> Vec2 {
    let mut p = p0;
    let mut begin = 0.0;
    for &(end, v) in stages {
        p += v * (t.min(end) - begin).max(0.0);
        begin = end;
    }
    p
}

#[test]
fn a_walls_position_is_the_integral_of_its_stages() {
    let stages = [
        (0.1, Vec2::new(0.0, 0.0)),
        (0.25, Vec2::new(2.0, -1.0)),
        (0.4, Vec2::new(-3.0, 0.5)),
        (f64::INFINITY, Vec2::new(1.0, 1.0)),
    ];
    let motion = r#"[ { "until": 0.1, "velocity": [0, 0] }, { "until": 0.25, "velocity": [2, -1] },
                      { "until": 0.4, "velocity": [-3, 0.5] }, { "velocity": [1, 1] } ]"#;
    // dt = 1e-5 puts every end on a step; dt = 3e-5 does not: the stages then end at the steps
    // nearest them (3333 × 3e-5 = 0.09999, 8333 × 3e-5 = 0.24999, 13333 × 3e-5 = 0.39999).
    for dt in [1e-5, 3e-5] {
        let on_steps: Vec<(f64, Vec2)> = stages
            .iter()
            .map(|&(end, v)| ((end / dt).round() * dt, v))
            .collect();
        let mut w = world(
            dt,
            &format!(r#"[ {{ "point": [10, 20], "normal": [0, -1], "motion": {motion} }} ]"#),
            r#"[ { "shape": {"type": "circle", "r": 1}, "position": [0, 1] } ]"#,
        );
        let p0 = Vec2::new(10.0, 20.0);
        let mut worst = 0.0f64;
        let mut worst_vs_until = 0.0f64;
        Simulation::new(&mut w)
            .until_time(0.5)
            .run_each(|w, _| {
                let p = w.walls[0].point();
                worst = worst.max((p - integral(p0, &on_steps, w.time)).norm());
                worst_vs_until = worst_vs_until.max((p - integral(p0, &stages, w.time)).norm());
            })
            .unwrap();
        // To the rounding of the anchors' sums (each stage adds a few ulps of 20 cm).
        assert!(worst < 1e-12, "dt = {dt}: {worst:e} cm from the integral");
        // Against the ends as given: at most the velocity change times the distance to the
        // nearest step, per stage boundary.
        assert!(worst_vs_until <= 5.0 * dt, "dt = {dt}: {worst_vs_until:e}");
        // After 0.4 s the wall moves at (1, 1).
        assert_eq!(w.walls[0].velocity, Vec2::new(1.0, 1.0));
    }
}

/// A box of 30 disks whose lid follows a program: down at 20 cm/s until it meets the pile, then
/// servo stages.
fn lidded_box(lid_motion: &str) -> World {
    lidded_box_dt(lid_motion, 2e-5)
}

fn lidded_box_dt(lid_motion: &str, dt: f64) -> World {
    let mut bodies = Vec::new();
    for k in 0..30 {
        let (x, y) = (-4.0 + (k % 5) as f64 * 2.0, 1.0 + (k / 5) as f64 * 2.0);
        let r = 0.7 + 0.1 * ((k * 7) % 3) as f64;
        bodies.push(format!(
            r#"{{ "shape": {{"type": "circle", "r": {r}}}, "position": [{x}, {y}] }}"#
        ));
    }
    world(
        dt,
        &format!(
            r#"[ {{ "point": [0, 0], "normal": [0, 1] }}, {{ "point": [-5, 0], "normal": [1, 0] }},
                 {{ "point": [5, 0], "normal": [-1, 0] }},
                 {{ "point": [0, 13], "normal": [0, -1], "motion": {lid_motion} }} ]"#
        ),
        &format!("[{}]", bodies.join(",")),
    )
}

/// The lid's program: at rest while the pile settles (0.3 s), down at 20 cm/s until it has met
/// the pile (0.45 s), then a servo holding 5e4 dyn/cm² (until 0.8 s) and one holding 1e4
/// (loading, then unloading).
const LOAD_UNLOAD: &str = r#"[ { "until": 0.3, "velocity": [0, 0] },
    { "until": 0.45, "velocity": [0, -20] },
    { "until": 0.8, "servo": { "stress": 5e4, "span": [1, 2], "max_speed": 20 } },
    { "servo": { "stress": 1e4, "span": [1, 2], "max_speed": 20 } } ]"#;

#[test]
fn servo_stages_hold_each_target_stress_of_a_loading_unloading_path() {
    let mut w = lidded_box(LOAD_UNLOAD);
    let stress = |w: &World| w.walls[3].measured_stress(&w.walls).map(|s| s.0);
    let mut at = Vec::new();
    Simulation::new(&mut w)
        .until_time(1.2)
        .run_each(|w, _| {
            // The ends of the servo stages (steps 40 000 and 60 000).
            if w.step == 40_000 || w.step == 60_000 {
                at.push(stress(w).expect("a servo stage"));
            }
            // Before the servo stages the lid is moved, not servoed.
            if w.step == 20_000 {
                assert_eq!(stress(w), None);
                assert!((w.walls[3].point().y - (13.0 - 20.0 * 0.1)).abs() < 1e-12);
            }
        })
        .unwrap();
    assert_eq!(at.len(), 2);
    for (got, want) in at.into_iter().zip([5e4, 1e4]) {
        assert!((got - want).abs() < 0.01 * want, "σ = {got}, want {want}");
    }
}

#[test]
fn the_energy_account_closes_with_a_programs_work_as_the_step_shrinks() {
    // What the account leaves unexplained over the program's moving stages (from 0.3 s), against
    // the lid's work: the lid's impact and the switch of targets are sudden, and the walls' work
    // is taken with each step's end forces (first order in Δt, see `dynamics::boundary`).
    let unexplained = |dt: f64| {
        let mut w = lidded_box_dt(LOAD_UNLOAD, dt);
        let e0 = w.energies.total();
        let err = |w: &World| w.energies.total() - e0 - w.energies.boundary_work;
        let mut at_start = 0.0;
        let start = (0.3 / dt).round() as u64;
        Simulation::new(&mut w)
            .until_time(1.2)
            .run_each(|w, _| {
                if w.step == start {
                    at_start = err(w);
                }
            })
            .unwrap();
        ((err(&w) - at_start).abs(), w.energies.boundary_work.abs())
    };
    let (coarse, w1) = unexplained(1e-5);
    let (fine, w2) = unexplained(5e-6);
    assert!(w1 > 1e3 && w2 > 1e3, "the lid did work: {w1}, {w2}");
    assert!(coarse < 0.03 * w1, "{coarse} of {w1}");
    assert!(fine < 0.015 * w2, "{fine} of {w2}");
    assert!(fine < 0.75 * coarse, "first order: {fine} against {coarse}");
}

#[test]
fn a_velocity_stage_ends_where_the_integral_says_before_the_servo_takes_over() {
    let mut w = lidded_box(
        r#"[ { "until": 0.05, "velocity": [0, 0] }, { "until": 0.15, "velocity": [0, -20] },
             { "servo": { "stress": 2e4, "span": [1, 2], "max_speed": 20 } } ]"#,
    );
    let mut y = None;
    Simulation::new(&mut w)
        .until_time(0.2)
        .run_each(|w, _| {
            if w.step == 7_500 {
                y = Some(w.walls[3].point().y);
            }
        })
        .unwrap();
    // 13 − 20 × (0.15 − 0.05) = 11, to the anchor's rounding.
    let y = y.unwrap();
    assert!((y - 11.0).abs() < 1e-12, "{y}");
    assert_ne!(w.walls[3].point().y, y, "the servo moved it on");
}

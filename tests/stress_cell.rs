//! The stress-controlled periodic cell (`cell.stress`, `cell.strain_rate`: `dynamics::cell`),
//! against independent answers: the stress a brute-force search over every pair's nearest image
//! computes from the bodies' positions and velocities (linear frictionless springs, Love–Weber
//! with the kinetic part), the closed form `L(t) = L₀ exp(ε̇ t)` of a side strained at a true
//! rate, the energy account with the cell's work, and an exact restart.

use dem2d::dynamics::World;
use dem2d::dynamics::cell::{Pressure, SideControl};
use dem2d::run::Simulation;
use dem2d::scene::Case;

mod common;
use common::Rng;

const KN: f64 = 1e6;

/// `n × n` bidisperse disks (radii 0.5 and 0.35) on a lattice of spacing 1.25 cm in an `"xy"`
/// cell with the `cell` members `controls`, with random velocities; `friction` and the case's
/// other members as given.
fn case_text(n: usize, controls: &str, seed: u64, friction: f64, more: &str) -> String {
    let mut rng = Rng(seed);
    let side = 1.25 * n as f64;
    let bodies: Vec<String> = (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            let r = if rng.next() < 0.5 { 0.5 } else { 0.35 };
            format!(
                r#"{{"shape": {{"type": "circle", "r": {r}}}, "position": [{}, {}],
                "velocity": [{}, {}]}}"#,
                1.25 * i as f64 + 0.6,
                1.25 * j as f64 + 0.6,
                2.0 * (rng.next() - 0.5),
                2.0 * (rng.next() - 0.5)
            )
        })
        .collect();
    format!(
        r#"{{"version": 1, "name": "stress_cell", "gravity": [0, 0], "dt": 5e-5, "duration": 1,
        {more}
        "cell": {{"size": [{side}, {side}], "periodic": "xy", {controls}}},
        "contact": {{"model": "linear", "kn": {KN}, "restitution": 0.5, "friction": {friction}}},
        "bodies": [{}]}}"#,
        bodies.join(", ")
    )
}

/// [`case_text`], frictionless, read.
fn case(n: usize, controls: &str, seed: u64) -> Case {
    Case::from_json(&case_text(n, controls, seed, 0.0, "")).expect("a valid case")
}

/// σ_xx and σ_yy (compressive positive) by brute force over every pair's nearest image: the
/// elastic normal forces `k_n δ` of the linear frictionless law on the branch vectors, plus
/// `Σ m v v` — independent of the cell's own measure (which also sees the dashpots).
fn brute_force_stress(w: &World) -> [f64; 2] {
    let c = w.cell.expect("a cell");
    assert_eq!(c.offset, 0.0, "no Lees–Edwards shift here");
    let (lx, ly) = (c.size.x, c.size.y);
    let b = &w.bodies;
    let radius = |i: usize| match b.shape[i] {
        dem2d::geometry::Shape::Circle { r } => r,
        _ => unreachable!("disks only"),
    };
    let mut s = [0.0; 2];
    for i in 0..b.len() {
        let (pi, vi) = (b.state[i].pose.position, b.state[i].vel);
        let m = b.mass[i];
        s[0] += m * vi.x * vi.x;
        s[1] += m * vi.y * vi.y;
        for j in i + 1..b.len() {
            let mut d = b.state[j].pose.position - pi;
            d.x -= lx * (d.x / lx).round();
            d.y -= ly * (d.y / ly).round();
            let dist = d.norm();
            let overlap = radius(i) + radius(j) - dist;
            if overlap > 0.0 {
                let f = KN * overlap / dist;
                s[0] += f * d.x * d.x;
                s[1] += f * d.y * d.y;
            }
        }
    }
    let area = lx * ly;
    [s[0] / area, s[1] / area]
}

/// An isotropic compression without walls: from a loose lattice (φ ≈ 0.4) each side follows its
/// own stress, and once the grains are still, the stress the brute force computes from their
/// overlaps is each side's target within 2 % — equal targets and unequal ones.
#[test]
fn an_isotropic_and_an_anisotropic_compression_hold_each_side_at_its_stress() {
    for (sxx, syy) in [(1000.0, 1000.0), (1200.0, 1000.0)] {
        let c = case(
            10,
            &format!(r#""stress": {{"xx": {sxx}, "yy": {syy}}}"#),
            11,
        );
        let mut w = c.build_world();
        let e0 = w.energies.total();
        Simulation::new(&mut w)
            .for_steps(60_000)
            .run()
            .expect("no blow-up");
        let [bx, by] = brute_force_stress(&w);
        let cell = w.cell.unwrap();
        eprintln!(
            "targets ({sxx}, {syy}): brute force ({bx:.1}, {by:.1}), cell ({:.1}, {:.1}), size \
             {:.4} × {:.4}, kinetic {:.3e}",
            cell.stress[0], cell.stress[3], cell.size.x, cell.size.y, w.energies.kinetic
        );
        assert!((bx - sxx).abs() < 0.02 * sxx, "σ_xx {bx} against {sxx}");
        assert!((by - syy).abs() < 0.02 * syy, "σ_yy {by} against {syy}");
        // The cell shrank from 12.5 cm along both sides (the grains at φ ≈ 0.4 carried nothing).
        assert!(cell.size.x < 11.0 && cell.size.y < 11.0, "{:?}", cell.size);
        // K + E_el + D = E₀ + W: what is left is the integration's error.
        let e = w.energies;
        let unaccounted = e.total() - e0 - e.boundary_work;
        assert!(
            unaccounted.abs() < 2e-3 * e.dissipated,
            "energy account off by {unaccounted} (dissipated {}, the cell's work {})",
            e.dissipated,
            e.boundary_work
        );
    }
}

/// A biaxial test without walls: the compressed sample's height strained at a true rate ε̇ < 0
/// while the width follows σ_xx. The height is `L₀ exp(ε̇ t)` to round-off at every step, the
/// width holds σ_xx (by brute force from the overlaps and velocities, averaged over the test)
/// within 3 %, the sample carries more vertically than horizontally, and the energy account
/// closes with the cell's work.
#[test]
fn a_biaxial_test_strains_one_side_at_its_rate_and_holds_the_other_at_its_stress() {
    let s = 1000.0;
    let c = case(
        10,
        &format!(r#""stress": {{"xx": {s}, "yy": {s}}}, "pressure_gain": 0.5"#),
        5,
    );
    let mut w = c.build_world();
    Simulation::new(&mut w)
        .for_steps(40_000)
        .run()
        .expect("no blow-up");
    // The test proper from the compressed state: y strained at ε̇, x at σ_xx.
    let rate = -0.2;
    let dt = w.dt;
    {
        let cell = w.cell.as_mut().unwrap();
        cell.control[1] = Some(SideControl::StrainRate(rate));
        assert!(matches!(
            cell.control[0],
            Some(SideControl::Stress(Pressure { target, .. })) if target == s
        ));
    }
    let (ly0, step0) = (w.cell.unwrap().size.y, w.step);
    let before = w.energies;
    let steps = 10_000;
    let (mut sum, mut n, mut worst_height, mut syy_sum) = (0.0, 0, 0.0f64, 0.0);
    let mut own = 0.0;
    eprintln!("biaxial from {:?}", w.cell.unwrap().size);
    Simulation::new(&mut w)
        .for_steps(steps)
        .run_each(|w, _| {
            let cell = w.cell.unwrap();
            let t = (w.step - step0) as f64 * dt;
            let want = ly0 * (rate * t).exp();
            worst_height = worst_height.max((cell.size.y - want).abs() / want);
            if w.step - step0 > steps / 4 && w.step % 20 == 0 {
                let [bx, by] = brute_force_stress(w);
                sum += bx;
                syy_sum += by;
                own += cell.stress[0];
                n += 1;
            }
        })
        .expect("no blow-up");
    let (sxx, syy) = (sum / n as f64, syy_sum / n as f64);
    let cell = w.cell.unwrap();
    eprintln!(
        "biaxial: height off by {worst_height:.2e} at worst; ⟨σ_xx⟩ {sxx:.1} (the cell's {:.1}), \
         ⟨σ_yy⟩ {syy:.1}; size {:.4} × {:.4}",
        own / n as f64,
        cell.size.x,
        cell.size.y
    );
    assert!(worst_height < 1e-12, "height off by {worst_height:e}");
    assert!((sxx - s).abs() < 0.03 * s, "⟨σ_xx⟩ {sxx} against {s}");
    assert!(
        syy > 1.05 * sxx,
        "the axial stress {syy} above the lateral {sxx}"
    );
    // Over the test: ΔK + ΔE_el + ΔD = W.
    let e = w.energies;
    let (work, dissipated) = (
        e.boundary_work - before.boundary_work,
        e.dissipated - before.dissipated,
    );
    let unaccounted = (e.total() - before.total()) - work;
    assert!(
        unaccounted.abs() < 2e-3 * work.abs(),
        "energy account off by {unaccounted} (dissipated {dissipated}, the cell's work {work})"
    );
}

/// A sheared cell whose width follows σ_xx and whose height is strained at a rate, continued from
/// its `state.json`, ends in the same state bit for bit as the run that was not interrupted
/// (both sides' stiffness and elastic sums are in the state).
#[test]
fn a_stress_and_strain_controlled_sheared_cell_continues_exactly_from_its_state() {
    let dir = common::scratch("stress_cell_restart");
    let controls = r#""shear_rate": 2, "stress": {"xx": 800}, "strain_rate": {"yy": -0.3}"#;
    let text = case_text(10, controls, 9, 0.4, r#""output_every": 100,"#);
    std::fs::write(dir.join("case.json"), text).unwrap();
    let run = |args: &[&str]| {
        let s = std::process::Command::new(common::bin())
            .args(args)
            .current_dir(&dir)
            .status()
            .unwrap();
        assert!(s.success(), "dem2d {args:?}");
    };
    let quiet = ["--quiet", "--overwrite"];
    run(&[
        &["run", "case.json", "--out", "whole", "--max-steps", "3000"],
        &quiet[..],
    ]
    .concat());
    run(&[
        &["run", "case.json", "--out", "first", "--max-steps", "1700"],
        &quiet[..],
    ]
    .concat());
    run(&[
        &[
            "run",
            "first/state.json",
            "--out",
            "second",
            "--max-steps",
            "1300",
        ],
        &quiet[..],
    ]
    .concat());
    let last = |d: &str, file: &str, rows: usize| {
        let text = std::fs::read_to_string(dir.join(d).join(file)).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        lines[lines.len() - rows..].join("\n")
    };
    let whole = last("whole", "trajectory.csv", 100);
    assert!(whole.starts_with("3000,"), "{whole}");
    assert_eq!(last("second", "trajectory.csv", 100), whole);
    assert_eq!(last("second", "cell.csv", 1), last("whole", "cell.csv", 1));
    // The height strained at −0.3/s for 3000 steps of 5e-5 s: 12.5 exp(−0.045) (to round-off).
    let ly: f64 = last("whole", "cell.csv", 1)
        .split(',')
        .nth(3)
        .unwrap()
        .parse()
        .unwrap();
    let want = 12.5 * (-0.3f64 * 3000.0 * 5e-5).exp();
    assert!((ly - want).abs() < 1e-11 * want, "L_y {ly} against {want}");
}

/// Contradictory or meaningless controls are refused, naming the field.
#[test]
fn contradictory_controls_are_refused_naming_the_field() {
    let cell = |members: &str| {
        let text = format!(
            r#"{{"version": 1, "name": "c", "gravity": [0, 0], "dt": 1e-5, "duration": 0.01,
            "cell": {{"size": [10, 10], "periodic": "xy", {members}}},
            "contact": {{"model": "linear", "kn": 1e6, "restitution": 0.5, "friction": 0}},
            "bodies": [{{"shape": {{"type": "circle", "r": 0.5}}, "position": [5, 5]}}]}}"#
        );
        match Case::from_json(&text) {
            Ok(_) => String::from("accepted"),
            Err(e) => e.to_string(),
        }
    };
    for (members, field) in [
        (r#""pressure": 100, "stress": {"yy": 100}"#, "cell.pressure"),
        (
            r#""stress": {"xx": 100}, "strain_rate": {"xx": -1}"#,
            "cell.strain_rate.xx",
        ),
        (
            r#""pressure": 100, "strain_rate": {"yy": -1}"#,
            "cell.strain_rate.yy",
        ),
        (r#""stress": {}"#, "cell.stress"),
        (r#""stress": {"xx": -5}"#, "cell.stress.xx"),
        (r#""stress": {"zz": 5}"#, "cell.stress.zz"),
        (r#""strain_rate": {"yy": "fast"}"#, "cell.strain_rate.yy"),
        // 1e-5 s steps: at most 1000 /s either way (1 % per step).
        (r#""strain_rate": {"yy": -2000}"#, "cell.strain_rate.yy"),
        (r#""strain_rate": {"xx": 1e6}"#, "cell.strain_rate.xx"),
    ] {
        let e = cell(members);
        assert!(e.contains(field), "{members}: {e}");
    }
    // An "x" cell has walls above and below: no stress control.
    let text = r#"{"version": 1, "name": "c", "gravity": [0, -981], "dt": 1e-5, "duration": 0.01,
        "cell": {"size": [10, 10], "periodic": "x", "stress": {"xx": 5}},
        "contact": {"model": "linear", "kn": 1e6, "restitution": 0.5, "friction": 0},
        "bodies": [{"shape": {"type": "circle", "r": 0.5}, "position": [5, 5]}]}"#;
    let e = match Case::from_json(text) {
        Ok(_) => panic!("an \"x\" cell with a stress accepted"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("cell.stress"), "{e}");
    // Both sides given, each its own way: accepted.
    assert_eq!(
        cell(r#""stress": {"xx": 100}, "strain_rate": {"yy": -1}"#),
        "accepted"
    );
}

//! Energy minimisation (`dynamics::minimise`, `dem2d relax`) against closed forms: a disk at
//! rest on a floor sinks by `mg/k_n`; a compressed triangular crystal in a periodic cell, its
//! bodies displaced, returns to the perfect lattice, whose energy is `3N · ½ k_n δ²`; a law with
//! friction is refused; a frictionless poured ellipse pile, which dynamics never brings to rest,
//! relaxes to a state that stays at rest.

use dem2d::dynamics::World;
use dem2d::dynamics::cell::{Cell, Periodic};
use dem2d::dynamics::minimise::{Fire, RelaxError, Tolerance, relax};
use dem2d::geometry::{Shape, Vec2};
use dem2d::scene::Case;

mod common;

fn tight() -> Tolerance {
    Tolerance {
        force: 1e-11,
        max_iterations: 200_000,
        energy: 0.0,
        stall: 0.0,
    }
}

#[test]
fn a_disk_on_a_floor_sinks_by_its_weight_over_the_stiffness() {
    let (r, kn, g) = (1.0, 1e6, 980.0);
    // Started high and turned: FIRE must bring it down and stop it.
    let case = Case::new(
        vec![common::body(Shape::Circle { r }, Vec2::new(0.3, 1.4), 0.7)],
        vec![common::floor(common::linear(kn, 50.0, 0.0))],
        Vec2::new(0.0, -g),
        common::linear(kn, 50.0, 0.0),
        1e-5,
    );
    let mut world = case.build_world();
    let out = relax(&mut world, &Fire::default(), &tight()).unwrap();
    assert!(out.converged, "{out:?}");
    let m = std::f64::consts::PI * r * r; // density 1
    let depth = m * g / kn;
    let y = world.bodies.state[0].pose.position.y;
    assert!(
        ((r - y) - depth).abs() < 1e-8 * depth,
        "sank {} against mg/k = {depth}",
        r - y
    );
    assert_eq!(world.bodies.state[0].vel, Vec2::zeros());
}

/// A triangular lattice of `nx × ny` disks of radius `r` at spacing `a` < 2r in a periodic
/// cell that fits it exactly: every disk touches six, each bond compressed by `2r − a`.
fn crystal(nx: usize, ny: usize, a: f64, r: f64, jitter: f64) -> World {
    let h = a * 3f64.sqrt() / 2.0;
    let mut seed = 7u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut bodies = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let x = (i as f64 + 0.5 * (j % 2) as f64 + 0.25) * a + jitter * next();
            let y = (j as f64 + 0.5) * h + jitter * next();
            bodies.push(common::body(Shape::Circle { r }, Vec2::new(x, y), 0.0));
        }
    }
    let case = Case::new(
        bodies,
        vec![],
        Vec2::zeros(),
        common::linear(1e6, 10.0, 0.0),
        1e-5,
    );
    let cell = Cell::new(
        Vec2::new(nx as f64 * a, ny as f64 * h),
        Periodic::XY,
        0.0,
        None,
    );
    case.build_world().with_cell(cell).0
}

#[test]
fn a_compressed_crystal_returns_to_the_perfect_lattice_and_its_energy() {
    let (nx, ny, a, r, kn) = (6, 6, 1.0, 0.51, 1e6);
    let delta = 2.0 * r - a;
    let mut world = crystal(nx, ny, a, r, 0.2 * delta);
    let out = relax(&mut world, &Fire::default(), &tight()).unwrap();
    assert!(out.converged, "{out:?}");
    let n = (nx * ny) as f64;
    let exact = 3.0 * n * 0.5 * kn * delta * delta;
    assert!(
        (out.potential - exact).abs() < 1e-8 * exact,
        "energy {} against 3N·½kδ² = {exact}",
        out.potential
    );
    // Six contacts a disk, each as deep as the lattice's bonds.
    let active: Vec<_> = world.contacts.active().collect();
    assert_eq!(active.len(), 3 * nx * ny);
    for c in active {
        assert!((c.data.force.norm() - kn * delta).abs() < 1e-6 * kn * delta);
    }
}

#[test]
fn a_law_with_friction_is_refused() {
    let case = Case::new(
        vec![common::body(
            Shape::Circle { r: 1.0 },
            Vec2::new(0.0, 2.0),
            0.0,
        )],
        vec![common::floor(common::linear(1e6, 0.0, 0.0))],
        Vec2::new(0.0, -980.0),
        common::linear(1e6, 0.0, 0.4),
        1e-5,
    );
    let mut world = case.build_world();
    assert_eq!(
        relax(&mut world, &Fire::default(), &Tolerance::default()),
        Err(RelaxError::Friction("contact".into()))
    );
    let (code, _, err) = common::dem2d(&[
        "relax",
        "cases/settle3_dt1e-5.json",
        "--out",
        common::scratch_path("refused").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("field `contact.friction`"), "{err}");
    assert!(!common::scratch_path("refused").join("state.json").exists());
}

/// The largest speed in a run's last trajectory frame.
fn last_speed(dir: &std::path::Path) -> f64 {
    let text = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let mut rows = text.lines();
    let head: Vec<&str> = rows.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (step, vx, vy) = (col("step"), col("vx"), col("vy"));
    let rows: Vec<Vec<f64>> = rows
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    let last = rows.last().unwrap()[step];
    rows.iter()
        .filter(|r| r[step] == last)
        .map(|r| r[vx].hypot(r[vy]))
        .fold(0.0, f64::max)
}

#[test]
fn a_frictionless_poured_ellipse_pile_relaxes_to_rest() {
    let dir = common::scratch("pile");
    let d = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let run = |args: &[&str]| {
        let (code, _, err) = common::dem2d(args);
        assert_eq!(code, 0, "dem2d {args:?}: {err}");
    };
    run(&[
        "generate",
        "--shape",
        "ellipses",
        "--n",
        "40",
        "--aspect",
        "2",
        "--friction",
        "0",
        "--duration",
        "0.6",
        "--out",
        &d("pile.json"),
    ]);
    run(&["run", &d("pile.json"), "--out", &d("poured"), "--quiet"]);
    // Dynamics leaves it moving; continued at rest, it moves again (its soft modes).
    run(&[
        "relax",
        &d("poured/state.json"),
        "--out",
        &d("relaxed"),
        "--quiet",
    ]);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("relaxed/relax.json")).unwrap())
            .unwrap();
    assert_eq!(summary["status"], "relaxed", "{summary}");
    assert!(summary["residual"].as_f64().unwrap() < 1e-9);
    run(&[
        "run",
        &d("relaxed/state.json"),
        "--out",
        &d("after"),
        "--duration",
        "0.65",
        "--quiet",
    ]);
    let poured = last_speed(&dir.join("poured"));
    let after = last_speed(&dir.join("after"));
    assert!(
        after < 1e-3 * poured.max(1e-3),
        "after relaxing the pile moves at {after} cm/s (poured: {poured} cm/s)"
    );
}

/// `dem2d relax --energy`: eight pairs of disks (r = 0.5 cm, overlapping by 0.1 cm; no gravity,
/// no walls, a periodic cell) start with the energy 8 · ½ k_n δ² = 4e4 erg and have no jammed
/// state. Relaxed fully they separate (status `relaxed`, energy 0); with an energy floor of
/// 100 erg the minimiser stops at the floor, sooner, as unjammed (at or below the floor, its
/// residual still above the tolerance); with too few iterations it is not at rest (exit code 1,
/// `max_iterations`); a negative floor is refused.
#[test]
fn relax_stops_at_an_energy_floor_as_unjammed() {
    let dir = common::scratch("unjammed");
    let mut bodies = Vec::new();
    for k in 0..8 {
        let (x, y) = (2.5 + 5.0 * (k % 4) as f64, 5.0 + 10.0 * (k / 4) as f64);
        for dx in [-0.45, 0.45] {
            bodies.push(serde_json::json!({
                "shape": {"type": "circle", "r": 0.5},
                "position": [x + dx, y]
            }));
        }
    }
    let case = serde_json::json!({
        "version": 1, "name": "unjammed", "units": "cm", "gravity": [0, 0],
        "dt": 1e-5, "duration": 0.01,
        "cell": {"size": [20.0, 20.0], "periodic": "xy"},
        "contact": {"model": "linear", "kn": 1e6, "restitution": 0.5, "friction": 0},
        "bodies": bodies,
    });
    let file = dir.join("case.json");
    std::fs::write(&file, case.to_string()).unwrap();
    let relax = |out: &str, extra: &[&str]| {
        let out = dir.join(out);
        let mut args = vec![
            "relax",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.push("--quiet");
        args.extend_from_slice(extra);
        let (code, _, err) = common::dem2d(&args);
        let text = std::fs::read_to_string(out.join("relax.json")).unwrap();
        let summary: serde_json::Value = serde_json::from_str(&text).unwrap();
        (code, summary, err)
    };
    let field = |s: &serde_json::Value, k: &str| s[k].as_f64().unwrap();
    let (code, full, err) = relax("full", &[]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(full["status"], "relaxed", "{full}");
    assert_eq!(field(&full, "potential"), 0.0, "{full}");
    let (code, s, err) = relax("floor", &["--energy", "100"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(s["status"], "unjammed", "{s}");
    assert!(
        field(&s, "potential") <= 100.0 && field(&s, "potential") > 0.0,
        "{s}"
    );
    assert!(field(&s, "residual") > 1e-9, "{s}");
    assert!(
        field(&s, "iterations") < field(&full, "iterations"),
        "{s} {full}"
    );
    let (code, s, _) = relax("limit", &["--max-iterations", "3"]);
    assert_eq!(code, 1);
    assert_eq!(s["status"], "max_iterations", "{s}");
    assert!(field(&s, "potential") > 100.0, "{s}");
    let bad = dir.join("bad");
    let (code, _, err) = common::dem2d(&[
        "relax",
        file.to_str().unwrap(),
        "--out",
        bad.to_str().unwrap(),
        "--energy=-1",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--energy"), "{err}");
    assert!(!bad.exists());
}

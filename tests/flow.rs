//! Insertion and outflow (`insert`, `outflow`; `dynamics::flow`), each against an answer found
//! apart from the flow's own code: the count inserted against `⌊rate · t⌋`; no overlap at
//! insertion by a brute-force test of all pairs; the mass inserted less the mass discharged
//! against the mass in the scene; the discharge log against the bodies that left, found by
//! comparing the identities before and after every step; the same bits on 1 and 2 threads and
//! across a restart through `state.json`.

use dem2d::dynamics::World;
use dem2d::geometry::mass::area;
use dem2d::run::Simulation;
use dem2d::scene::{Case, CaseFile};
use std::collections::BTreeMap;

mod common;
use common::{dem2d, scratch};

/// Bodies falling freely (no walls) through an insertion region above an outflow region.
fn falling(rate: f64, count: Option<u64>, extra: &str) -> String {
    let count = count.map_or(String::new(), |c| format!("\"count\": {c}, "));
    format!(
        r#"{{
  "version": 1, "name": "falling", "units": "cm", "gravity": [0, -981], "dt": 1e-4,
  "duration": 0.2, "output_every": 100,
  "contact": {{"model": "linear", "kn_over_rho_g": 2000, "restitution": 0.5, "friction": 0.3}},
  "bodies": [],
  "insert": [{{"region": [-10, 10, 0, 4], "rate": {rate}, {count}"shape": "ellipse",
              "size": {{"uniform": [0.3, 0.5]}}, "aspect": {{"choice": [1.5, 2, 3]}},
              "velocity": [0, -100], "seed": 11}}],
  "outflow": [{{"region": [-20, 20, -1000, -20]}}]{extra}
}}"#
    )
}

fn world_of(text: &str) -> World {
    Case::from_json(text).unwrap().build_world()
}

/// The count inserted by time t is `⌊rate t⌋` (the region never fills: the bodies fall out of
/// it at 100 cm/s), capped by `count`.
#[test]
fn the_count_inserted_follows_rate_times_time() {
    for (rate, count) in [(500.0, None), (1234.5, None), (2000.0, Some(150))] {
        // At 500 cm/s a body leaves the region within 0.01 s: it never fills.
        let text = falling(rate, count, "").replace("[0, -100]", "[0, -500]");
        let mut w = world_of(&text);
        let mut sim = Simulation::new(&mut w).for_steps(2000);
        let mut checked = 0;
        sim.run_each(|w, _| {
            let inserted = w.next_id;
            let want = ((w.step as f64 * 1e-4) * rate).floor() as u64;
            let want = count.map_or(want, |c| want.min(c));
            assert_eq!(inserted, want, "rate {rate}, step {}", w.step);
            let f = w.flow.as_ref().unwrap();
            assert_eq!(f.state[0].inserted, want);
            checked += 1;
        })
        .unwrap();
        assert_eq!(checked, 2000);
    }
}

/// Every body inserted is clear of every other body at insertion: the distance between the
/// centroids of every pair with a new body exceeds the sum of their bounding radii (all pairs,
/// brute force), and a dense region's bodies never touch when placed.
#[test]
fn no_body_is_inserted_overlapping_another() {
    // A high rate into a small region: many rejected positions.
    let text = falling(20000.0, Some(400), "")
        .replace("[-10, 10, 0, 4]", "[-4, 4, 0, 4]")
        .replace("\"velocity\": [0, -100]", "\"velocity\": [0, -10]");
    let mut w = world_of(&text);
    let mut seen = 0;
    let mut checked_pairs = 0u64;
    Simulation::new(&mut w)
        .for_steps(3000)
        .run_each(|w, _| {
            let b = &w.bodies;
            let new: Vec<usize> = (0..b.len()).filter(|&k| b.id[k] >= seen).collect();
            for &i in &new {
                for j in 0..b.len() {
                    if i == j {
                        continue;
                    }
                    let d = (b.state[i].pose.position - b.state[j].pose.position).norm();
                    assert!(
                        d > b.bound[i] + b.bound[j],
                        "step {}: body {} inserted {d} from body {}",
                        w.step,
                        b.id[i],
                        b.id[j]
                    );
                    checked_pairs += 1;
                }
            }
            seen = w.next_id;
        })
        .unwrap();
    // The region filled: bodies had to wait for room (a retry is pending or was), and many
    // came in.
    assert!(w.next_id >= 50, "{}", w.next_id);
    assert!(w.next_id < 400, "{}", w.next_id);
    assert!(checked_pairs > 1000, "{checked_pairs}");
}

/// Mass is conserved through the flow: the masses of every body that ever entered (each
/// computed from its shape, ρ × area) less those of the bodies discharged equal the masses in
/// the scene; and the discharge log names exactly the bodies that disappeared during each
/// step (found by comparing the identities before and after), each with its mass, and no
/// body stays in the outflow region after a step.
#[test]
fn mass_is_conserved_and_the_log_names_the_bodies_that_left() {
    let mut w = world_of(&falling(800.0, None, ""));
    let region_top = -20.0;
    let mut mass_of: BTreeMap<u64, f64> = BTreeMap::new();
    let mut before: BTreeMap<u64, f64> = BTreeMap::new();
    let mut discharged_mass = 0.0;
    let mut discharged = 0;
    Simulation::new(&mut w)
        .for_steps(6000)
        .run_each(|w, _| {
            let b = &w.bodies;
            let now: BTreeMap<u64, f64> = (0..b.len())
                .map(|k| (b.id[k], b.density[k] * area(&b.shape[k])))
                .collect();
            for (&id, &m) in &now {
                mass_of.entry(id).or_insert(m);
            }
            let gone: Vec<u64> = before
                .keys()
                .filter(|id| !now.contains_key(id))
                .copied()
                .collect();
            let log = w.flow.as_mut().unwrap().take_log();
            let logged: Vec<u64> = log.iter().map(|d| d.id).collect();
            assert_eq!(logged, gone, "step {}", w.step);
            for d in &log {
                assert_eq!(d.step, w.step);
                assert_eq!(d.mass, mass_of[&d.id]);
                discharged_mass += d.mass;
                discharged += 1;
            }
            let b = &w.bodies;
            for k in 0..b.len() {
                assert!(b.state[k].pose.position.y > region_top, "step {}", w.step);
            }
            let inserted: f64 = mass_of.values().sum();
            let inside: f64 = now.values().sum();
            let scale = inserted.max(1.0);
            assert!(
                (inserted - discharged_mass - inside).abs() <= 1e-12 * scale,
                "step {}: {inserted} − {discharged_mass} ≠ {inside}",
                w.step
            );
            before = now;
        })
        .unwrap();
    // Bodies at 100 cm/s fall 20 cm in about 0.1 s: hundreds left during the 0.6 s.
    assert!(discharged > 200, "{discharged}");
    let f = w.flow.as_ref().unwrap();
    assert_eq!(f.discharged, discharged);
}

/// A flow between steps is on one thread: a run of more bodies than one parallel chunk (512)
/// gives the same bits on 1 and 2 threads, insertions and removals included.
#[test]
fn a_flow_gives_the_same_bits_on_one_and_two_threads() {
    // A box with a floor, filled quickly with 900 disks; an outflow region low in one corner.
    let text = r#"{
  "version": 1, "name": "box", "units": "cm", "gravity": [0, -981], "dt": 5e-5,
  "duration": 0.1, "contact": {"model": "linear", "kn_over_rho_g": 2000,
  "restitution": 0.5, "friction": 0.3},
  "walls": [{"point": [0, 0], "normal": [0, 1]}, {"point": [-15, 0], "normal": [1, 0]},
            {"point": [15, 0], "normal": [-1, 0]}],
  "bodies": [],
  "insert": [{"region": [-15, 15, 0, 40], "count": 900, "size": {"uniform": [0.3, 0.4]},
              "seed": 5}, {"region": [-15, 15, 40, 44], "rate": 3000, "size": 0.35,
              "shape": "rectangle", "aspect": 1.5, "seed": 6}],
  "outflow": [{"region": [-15, -12, 0, 3]}]
}"#;
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut w = world_of(text);
            let mut log = Vec::new();
            Simulation::new(&mut w)
                .for_steps(1500)
                .run_each(|w, _| log.extend(w.flow.as_mut().unwrap().take_log()))
                .unwrap();
            (w.restart_state(), log)
        })
    };
    let (one, log1) = run(1);
    let (two, log2) = run(2);
    assert!(one.bodies.len() > 900, "{}", one.bodies.len());
    assert!(!log1.is_empty());
    assert_eq!(one, two);
    assert_eq!(log1, log2);
}

/// A run continued from the `state.json` of a run stopped part-way inserts and removes the
/// same bodies as the uninterrupted run, to the bit: the generators' states, the counts and
/// the identities travel in the state (the command line, as a user runs it).
#[test]
fn a_restart_continues_the_flow_exactly() {
    let case = falling(900.0, None, "");
    let dir = scratch("flow-restart");
    let file = dir.join("case.in.json");
    std::fs::write(&file, &case).unwrap();
    let run = |args: &[&str]| {
        let (code, _, err) = dem2d(args);
        assert_eq!(code, 0, "{err}");
    };
    let (full, half, rest) = (dir.join("full"), dir.join("half"), dir.join("rest"));
    let f = file.to_str().unwrap();
    run(&["run", f, "--out", full.to_str().unwrap(), "--overwrite"]);
    run(&[
        "run",
        f,
        "--out",
        half.to_str().unwrap(),
        "--overwrite",
        "--max-steps",
        "1234",
    ]);
    let state = half.join("state.json");
    run(&[
        "run",
        state.to_str().unwrap(),
        "--out",
        rest.to_str().unwrap(),
        "--overwrite",
    ]);
    let read = |p: &std::path::Path, name: &str| std::fs::read_to_string(p.join(name)).unwrap();
    let last = |t: String| {
        let lines: Vec<String> = t.lines().map(str::to_string).collect();
        let step = lines.last().unwrap().split(',').next().unwrap().to_string();
        lines
            .into_iter()
            .filter(|l| l.starts_with(&format!("{step},")))
            .collect::<Vec<_>>()
    };
    let a = last(read(&full, "trajectory.csv"));
    let b = last(read(&rest, "trajectory.csv"));
    assert!(a.len() > 50, "{}", a.len());
    assert_eq!(a, b);
    // The discharges: the first part's and the rest's rows are the whole run's.
    let rows = |t: String| t.lines().skip(1).map(str::to_string).collect::<Vec<_>>();
    let mut joined = rows(read(&half, "discharge.csv"));
    joined.extend(rows(read(&rest, "discharge.csv")));
    let whole = rows(read(&full, "discharge.csv"));
    assert!(whole.len() > 50, "{}", whole.len());
    assert_eq!(joined, whole);
    // The state itself reads back as a case with its flow.
    let state = CaseFile::from_json(&read(&half, "state.json")).unwrap();
    assert!(state.case.flow.is_some());
}

/// `keep`: the scene holds the number of free bodies, re-inserting those the outflow took.
#[test]
fn keep_holds_the_number_of_bodies() {
    let text = falling(1.0, None, "")
        .replace("\"rate\": 1, ", "\"keep\": 15, ")
        .replace("[-10, 10, 0, 4]", "[-10, 10, 0, 10]")
        .replace("\"velocity\": [0, -100]", "\"velocity\": [0, -300]");
    let mut w = world_of(&text);
    Simulation::new(&mut w)
        .for_steps(3000)
        .run_each(|w, _| assert_eq!(w.bodies.len(), 15, "step {}", w.step))
        .unwrap();
    let f = w.flow.as_ref().unwrap();
    assert!(f.discharged > 30, "{}", f.discharged);
    assert_eq!(w.next_id, 15 + f.discharged);
}

/// The energy account through the flow: bodies falling freely (no contacts), inserted at
/// 500 cm/s and removed 20 cm below, conserve `K + P` but for the energy inserted and removed,
/// which the account books as boundary work: `E − E₀ − W` stays at round-off.
#[test]
fn the_energy_inserted_and_removed_is_booked_as_boundary_work() {
    let text = falling(500.0, None, "").replace("[0, -100]", "[0, -500]");
    let mut w = world_of(&text);
    let e0 = w.energies.total();
    let mut worst = 0.0f64;
    let mut scale = 0.0f64;
    Simulation::new(&mut w)
        .for_steps(5000)
        .run_each(|w, r| {
            assert_eq!(r.contacts, 0);
            let e = w.energies;
            worst = worst.max((e.total() - e0 - e.boundary_work).abs());
            scale = scale.max(e.kinetic + e.potential.abs());
        })
        .unwrap();
    assert!(w.flow.as_ref().unwrap().discharged > 100);
    assert!(worst <= 1e-12 * scale, "{worst} against {scale}");
}

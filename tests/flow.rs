//! Insertion and outflow (`insert`, `outflow`; `dynamics::flow`), each against an answer found
//! apart from the flow's own code: the count inserted against `⌊rate · t⌋`; no overlap at
//! insertion by a brute-force test of all pairs; the mass inserted less the mass discharged
//! against the mass in the scene; the discharge log against the bodies that left, found by
//! comparing the identities before and after every step; the same bits on 1 and 2 threads and
//! across a restart through `state.json`; `dem2d plot` and `dem2d analyze` on such a run, the
//! bodies drawn and measured at each frame against `inserted.csv` and `discharge.csv`, the
//! packing fraction against `Σ π r²` of the bodies present.

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
            let log = w.flow.as_ref().unwrap().log.clone();
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
                .run_each(|w, _| log.extend(w.flow.as_ref().unwrap().log.iter().cloned()))
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
    // So do the insertions; and the continued run reads back (its bodies from before the
    // restart are its case's, under their identities `state.ids`), ending as the whole run.
    let mut joined = rows(read(&half, "inserted.csv"));
    joined.extend(rows(read(&rest, "inserted.csv")));
    assert_eq!(joined, rows(read(&full, "inserted.csv")));
    let load = |p: &std::path::Path| dem2d::output::run_data::RunData::load(p).unwrap();
    let (whole, continued) = (load(&full), load(&rest));
    let (a, b) = (
        whole.frames.last().unwrap(),
        continued.frames.last().unwrap(),
    );
    assert_eq!((a.step, &a.ids, &a.bodies), (b.step, &b.ids, &b.bodies));
    for &id in &a.ids {
        assert_eq!(whole.init(id).shape, continued.init(id).shape, "body {id}");
    }
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

/// The rows of a CSV file of numbers (the header skipped; an empty field, undefined: NaN).
fn csv_rows(path: &std::path::Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|x| {
                    if x.is_empty() {
                        f64::NAN
                    } else {
                        x.parse().unwrap()
                    }
                })
                .collect()
        })
        .collect()
}

/// `dem2d plot` and `dem2d analyze` read a run whose bodies come and go: the bodies each frame
/// holds are those `inserted.csv` placed by its step less those `discharge.csv` says left by
/// then (the trajectory's own `body` column and the reader's frames both checked against
/// that); a snapshot draws one outline per body present; `analyze` counts them and finds the
/// packing fraction of a window holding them all as `Σ π r²` over the window's area (r the
/// equal-area radius `inserted.csv` records), and recomputes the run's own `analysis.csv`.
#[test]
fn plot_and_analyze_draw_and_measure_the_bodies_present_in_each_frame() {
    let dir = scratch("flow-plot");
    let file = dir.join("case.in.json");
    std::fs::write(&file, falling(900.0, None, "")).unwrap();
    let run = dir.join("run");
    let (code, _, err) = dem2d(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--overwrite",
        "--analysis",
        "--contacts",
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    // The logs: (step, body) placed, (step, body) removed; each body's equal-area radius.
    let placed: Vec<(u64, u64)> = csv_rows(&run.join("inserted.csv"))
        .iter()
        .map(|r| (r[0] as u64, r[2] as u64))
        .collect();
    let radius: BTreeMap<u64, f64> = csv_rows(&run.join("inserted.csv"))
        .iter()
        .map(|r| (r[2] as u64, r[4]))
        .collect();
    let removed: Vec<(u64, u64)> = csv_rows(&run.join("discharge.csv"))
        .iter()
        .map(|r| (r[0] as u64, r[2] as u64))
        .collect();
    assert!(
        placed.len() > 100 && removed.len() > 20,
        "{placed:?} {removed:?}"
    );
    // Bodies are placed and removed between steps: after step s (outflow first), so a frame
    // written after step s holds those placed at s or before and not removed at s or before.
    let present = |s: u64| -> Vec<u64> {
        placed
            .iter()
            .filter(|&&(at, id)| at <= s && !removed.iter().any(|&(out, o)| o == id && out <= s))
            .map(|&(_, id)| id)
            .collect()
    };
    // The trajectory's frames, by step: the identities it lists.
    let mut frames: BTreeMap<u64, Vec<u64>> = BTreeMap::new();
    for r in csv_rows(&run.join("trajectory.csv")) {
        frames.entry(r[0] as u64).or_default().push(r[2] as u64);
    }
    assert!(frames.len() > 15, "{} frames", frames.len());
    let data = dem2d::output::run_data::RunData::load(&run).unwrap();
    assert_eq!(data.frames.len(), frames.len());
    let mut counts = Vec::new();
    for (f, (&step, ids)) in data.frames.iter().zip(&frames) {
        assert_eq!(
            &present(step),
            ids,
            "step {step}: trajectory.csv against the logs"
        );
        assert_eq!((f.step, &f.ids), (step, ids), "step {step}: the reader");
        counts.push(ids.len());
    }
    // Bodies come and go: some frame has lost bodies the one before had.
    assert!(
        frames
            .values()
            .zip(frames.values().skip(1))
            .any(|(a, b)| a.iter().any(|id| !b.contains(id))),
        "no body left between frames"
    );
    // A snapshot of several frames (`--last` up to their time): one outline per body present,
    // each a closed polyline of many points (the axes' and ticks' have 2; no walls here).
    let times: Vec<f64> = data.frames.iter().map(|f| f.t).collect();
    for k in [3, times.len() / 2, times.len() - 1] {
        let svg = dir.join(format!("scene{k}.svg"));
        let (code, _, err) = dem2d(&[
            "plot",
            run.to_str().unwrap(),
            "--last",
            "--color",
            "body",
            "--to",
            &format!("{}", times[k]),
            "--out",
            svg.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        let text = std::fs::read_to_string(&svg).unwrap();
        let outlines = text
            .split("<polyline")
            .skip(1)
            .filter(|p| {
                let rest = &p[p.find("points=\"").unwrap() + 8..];
                rest[..rest.find('"').unwrap()].split_whitespace().count() > 20
            })
            .count();
        assert_eq!(outlines, counts[k], "frame {k}: outlines drawn");
    }
    // The paths and outlines over the whole run, and the series: they draw.
    for kind in ["scene", "series"] {
        let (code, _, err) = dem2d(&[
            "plot",
            run.to_str().unwrap(),
            "--kind",
            kind,
            "--out",
            dir.join(format!("{kind}.svg")).to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{kind}: {err}");
    }
    // analyze: recomputes the run's own analysis.csv (the bodies' extent at each frame)...
    let again = dir.join("again.csv");
    let (code, _, err) = dem2d(&[
        "analyze",
        run.to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    // (Less its rows of frames without a body, which trajectory.csv has no row to tell of:
    // here the first, before the first insertion.)
    let own: Vec<String> = std::fs::read_to_string(run.join("analysis.csv"))
        .unwrap()
        .lines()
        .filter(|l| !l.ends_with(",0,0"))
        .map(str::to_string)
        .collect();
    let redone: Vec<String> = std::fs::read_to_string(&again)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect();
    assert_eq!(redone.len(), frames.len() + 1);
    assert_eq!(redone, own);
    // ... and over a window holding every body: all of them, and Σ π r² over its area.
    let (code, _, err) = dem2d(&[
        "analyze",
        run.to_str().unwrap(),
        "--window=-15,15,-25,10",
        "--out",
        again.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&again).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows = csv_rows(&again);
    assert_eq!(rows.len(), frames.len());
    for (r, ids) in rows.iter().zip(frames.values()) {
        assert_eq!(r[col("bodies")] as usize, ids.len(), "t = {}", r[0]);
        let solid: f64 = ids
            .iter()
            .map(|id| std::f64::consts::PI * radius[id] * radius[id])
            .sum();
        let want = solid / (30.0 * 35.0);
        let got = r[col("packing_fraction")];
        assert!(
            (got - want).abs() <= 1e-12 * want.max(1e-300),
            "t = {}: packing fraction {got} against {want}",
            r[0]
        );
    }
}

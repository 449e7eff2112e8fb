//! Regressions of issue 29 ("Nothing silent, nothing stale"): what a fuzzing pass and a new user
//! found. One module per bug, named after it; its doc says what went wrong and what happens now.
//! Each test checks what the user sees (exit code, message, files) against an answer that does
//! not come from the code under test: a closed form, a force balance, the bytes of a file.

use serde_json::Value;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{bin, dem2d, scratch};

fn case(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name)
        .to_str()
        .unwrap()
        .to_string()
}

/// Writes `json` as `dir/name` and returns its path.
fn write(dir: &Path, name: &str, json: &Value) -> String {
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(json).unwrap()).unwrap();
    p.to_str().unwrap().to_string()
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// The rows of a CSV file as maps from the header's names to numbers (NaN for empty fields).
fn csv(file: &Path) -> Vec<std::collections::HashMap<String, f64>> {
    let text = std::fs::read_to_string(file).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(|v| v.parse().unwrap_or(f64::NAN)))
                .collect()
        })
        .collect()
}

/// Waits until the run in `dir` has written its first summary (status `running`) and its first
/// trajectory frame, so that it is inside its step loop.
fn wait_until_running(child: &mut Child, dir: &Path) {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        if let Ok(text) = std::fs::read_to_string(dir.join("summary.json"))
            && text.contains("\"running\"")
            && std::fs::metadata(dir.join("trajectory.csv")).is_ok_and(|m| m.len() > 100)
        {
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it was stopped"
        );
        assert!(Instant::now() < deadline, "the run never started");
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(300));
}

/// A long run (10⁴ disks on one thread) into `dir`, in the background.
fn long_run(dir: &Path, extra: &[&str]) -> Child {
    let mut args = vec![
        "run".to_string(),
        case("settle_disks_10k.json"),
        "--out".into(),
        dir.to_str().unwrap().into(),
        "--quiet".into(),
        "--threads".into(),
        "1".into(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    Command::new(bin())
        .args(&args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

/// The three-ellipse box of `cases/settle3_dt1e-5.json` as a JSON value.
fn settle3() -> Value {
    serde_json::from_str(&std::fs::read_to_string(case("settle3_dt1e-5.json")).unwrap()).unwrap()
}

/// Issue 29, item 2. Two `dem2d run --overwrite` into one directory at the same time both exited
/// 0, leaving one case's trajectory beside the other's summary and state. Now a run holds a lock
/// on its directory from before it touches anything until its last file: a second run is
/// refused (exit 2), naming the first; a lock left by a killed run locks nothing.
mod bug_two_runs_mixed_their_files_in_one_directory {
    use super::*;

    #[test]
    fn a_second_run_into_a_directory_being_written_is_refused_naming_the_first() {
        let dir = scratch("locked");
        let d = dir.to_str().unwrap();
        let mut first = long_run(&dir, &[]);
        wait_until_running(&mut first, &dir);
        let (code, out, err) = dem2d(&[
            "run",
            &case("settle3_dt1e-5.json"),
            "--out",
            d,
            "--overwrite",
            "--quiet",
        ]);
        assert_eq!(code, 2, "{err}");
        assert!(out.is_empty(), "{out}");
        assert!(
            err.contains("another dem2d run is writing into this directory")
                && err.contains(&format!("process {}", first.id()))
                && err.contains("settle_disks_10k"),
            "{err}"
        );
        // Nothing of the first run was touched: its summary still names it.
        assert_eq!(summary(&dir)["name"], "settle_disks_10k");
        // Killed outright: the kernel releases the lock, and the next run may go ahead.
        first.kill().unwrap();
        first.wait().unwrap();
        let (code, _, err) = dem2d(&[
            "run",
            &case("settle3_dt1e-5.json"),
            "--out",
            d,
            "--overwrite",
            "--quiet",
            "--max-steps",
            "100",
        ]);
        assert_eq!(code, 0, "{err}");
        assert_eq!(summary(&dir)["name"], "settle3_dt1e-5");
        // A finished run leaves no lock file behind.
        assert!(!dir.join(".dem2d.lock").exists());
    }
}

/// Issue 29, item 3. `dem2d run DIR/state.json --out DIR --overwrite` deleted the input
/// `state.json` before stepping: a kill or a full disk then left no state at all. Now the input
/// stays until the run's own state replaces it (atomically).
mod bug_the_only_checkpoint_was_deleted_before_its_replacement_existed {
    use super::*;

    #[test]
    fn a_run_continued_into_its_own_directory_keeps_the_state_it_started_from_until_replaced() {
        let dir = scratch("checkpoint");
        let d = dir.to_str().unwrap();
        let (code, _, err) = dem2d(&[
            "run",
            &case("settle_disks_10k.json"),
            "--out",
            d,
            "--quiet",
            "--max-steps",
            "20",
        ]);
        assert_eq!(code, 0, "{err}");
        let state = dir.join("state.json");
        let checkpoint = std::fs::read(&state).unwrap();
        // Continued into the same directory and killed part-way: the checkpoint is intact.
        let mut child = Command::new(bin())
            .args([
                "run",
                state.to_str().unwrap(),
                "--out",
                d,
                "--overwrite",
                "--quiet",
                "--threads",
                "1",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        wait_until_running(&mut child, &dir);
        child.kill().unwrap();
        child.wait().unwrap();
        assert_eq!(summary(&dir)["status"], "running");
        assert_eq!(std::fs::read(&state).unwrap(), checkpoint);
        // Continued from it again, to the end of this part: replaced by the later state.
        let (code, _, err) = dem2d(&[
            "run",
            state.to_str().unwrap(),
            "--out",
            d,
            "--overwrite",
            "--quiet",
            "--max-steps",
            "10",
        ]);
        assert_eq!(code, 0, "{err}");
        let s: Value = serde_json::from_slice(&std::fs::read(&state).unwrap()).unwrap();
        assert_eq!(s["state"]["step"], 30);
        assert_eq!(summary(&dir)["steps"], 30);
    }
}

/// Issue 29, item 4. `dem2d plot` panicked (exit 101, index out of bounds in `plot.rs` and
/// `panels.rs`) on a run killed while writing a frame: the last frame had fewer bodies than the
/// case, or the file ended mid-line. Now the complete frames are drawn and a warning says the
/// last was incomplete.
mod bug_plot_panicked_on_a_run_killed_mid_frame {
    use super::*;

    #[test]
    fn plot_draws_the_complete_frames_and_says_the_last_was_incomplete() {
        let dir = scratch("killed_mid_frame");
        let d = dir.to_str().unwrap();
        let (code, _, err) = dem2d(&[
            "run",
            &case("settle3_dt1e-5.json"),
            "--out",
            d,
            "--quiet",
            "--max-steps",
            "3000",
        ]);
        assert_eq!(code, 0, "{err}");
        let whole = std::fs::read(dir.join("trajectory.csv")).unwrap();
        let incs = std::fs::read(dir.join("increments.csv")).unwrap();
        let lines: Vec<usize> = whole
            .iter()
            .enumerate()
            .filter(|(_, b)| **b == b'\n')
            .map(|(k, _)| k)
            .collect();
        let n = lines.len();
        // Cut: after the first body of the last frame (whole lines), and in the middle of the
        // last frame's second line; increments.csv and walls.csv mid-line too.
        for (cut, what) in [
            (lines[n - 3] + 1, "1 of the 3 bodies"),
            (lines[n - 2] - 20, "1 of the 3 bodies"),
        ] {
            std::fs::write(dir.join("trajectory.csv"), &whole[..cut]).unwrap();
            std::fs::write(dir.join("increments.csv"), &incs[..incs.len() - 7]).unwrap();
            for kind in ["scene", "series", "quiescence"] {
                let out = dir.join(format!("{kind}.svg"));
                let (code, _, err) =
                    dem2d(&["plot", d, "--kind", kind, "--out", out.to_str().unwrap()]);
                assert_eq!(code, 0, "{kind}: {err}");
                assert!(
                    err.contains("the last frame (step 3000)") && err.contains(what),
                    "{kind}: {err}"
                );
                assert!(
                    err.contains("increments.csv: the last line is incomplete"),
                    "{err}"
                );
                assert!(std::fs::read_to_string(&out).unwrap().contains("</svg>"));
            }
        }
    }
}

/// Issue 29, item 5. `dem2d plot` drew every wall at its starting position and recomputed the
/// contact forces against that stale line: on the shipped repose cases (a wall withdrawing at
/// 100 cm/s) every grain past the wall's start showed 1e8–9e8 dyn. Now walls are drawn where
/// they are in each frame (`walls.csv`) and the forces come from the run's records
/// (`contacts.csv`) or are recomputed with the walls in place.
mod bug_plot_drew_moving_walls_at_their_start_and_coloured_forces_against_them {
    use super::*;
    use dem2d::output::forces::normal_force_per_body;
    use dem2d::output::run_data::RunData;

    #[test]
    fn walls_are_where_they_were_and_the_forces_are_the_weights_they_carry() {
        let dir = scratch("moving_wall_plot");
        // Six disks (r = 1) in a row on a floor against a left wall; the right wall starts
        // touching the last and withdraws at 100 cm/s, and the last two are thrown after it at
        // 50 cm/s: they roll on past the wall's starting line. The floor carries each disk's
        // weight and nothing else pushes: every body's Σ F_n is its weight, m g = π ρ g r²
        // (against the wall's starting line, the last two overlapped it by centimetres).
        let mut c = settle3();
        c["name"] = "withdrawing_wall".into();
        c["duration"] = 0.1.into();
        c.as_object_mut().unwrap().remove("quiescence");
        c["walls"][2] = serde_json::json!({"point": [12, 0], "normal": [-1, 0],
                                           "velocity": [100, 0]});
        c["bodies"] = (0..6)
            .map(|k| {
                let v = if k >= 4 { 50.0 } else { 0.0 };
                serde_json::json!({"shape": {"type": "circle", "r": 1.0},
                                   "position": [1.0 + 2.0 * k as f64, 1.0],
                                   "velocity": [v, 0]})
            })
            .collect();
        let file = write(&dir, "case.in.json", &c);
        let out = dir.join("run");
        let (code, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"]);
        assert_eq!(code, 0, "{err}");
        let run = RunData::load(&out).unwrap();
        let last = run.frames.len() - 1;
        let (walls, known) = run.walls_at(last);
        assert!(known);
        // At t = 0.1 s the wall is 10 cm further (a closed form of its motion).
        assert!((walls[2].line().point.x - 22.0).abs() < 1e-9, "{walls:?}");
        let x5 = run.frames[last].bodies[5].x;
        assert!(x5 > 13.0, "body 5 at x = {x5}, not past the wall's start");
        let weight = std::f64::consts::PI * 980.0;
        let f = normal_force_per_body(&run, last, None);
        for (k, fk) in f.iter().enumerate() {
            assert!(
                (fk / weight - 1.0).abs() < 0.02,
                "body {k}: {fk} vs {weight}"
            );
        }
        // The picture: drawn, and its force colour bar's largest tick is of the weight's order
        // (a wall drawn at its start put it near 1e8).
        let svg = out.join("scene.svg");
        let (code, _, err) = dem2d(&[
            "plot",
            out.to_str().unwrap(),
            "--last",
            "--color",
            "force",
            "--out",
            svg.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(std::fs::read_to_string(&svg).unwrap().contains("</svg>"));
    }
}

/// Issue 29, item 7. `summary.json` had no term for the work of moving walls: with servo walls
/// the total appeared to grow from 0 to 192 erg. Now it reports `walls_work` and
/// `unaccounted = final_total − initial_total − walls_work`.
mod bug_the_energy_account_left_out_the_work_of_moving_walls {
    use super::*;

    #[test]
    fn a_wall_that_kicks_a_resting_disk_has_done_two_m_v_squared_of_work() {
        // The moving mirror: a wall at V meets a resting disk with an undamped, frictionless
        // contact and sends it off at 2V. All its work is then the disk's kinetic energy,
        // W = ½ m (2V)² = 2 m V² (m = π r² ρ): nothing else was in motion.
        let dir = scratch("walls_work");
        let v = 50.0;
        let c = serde_json::json!({
            "version": 1, "name": "mirror", "gravity": [0, 0], "dt": 1e-6, "duration": 0.02,
            "output_every": 100,
            "contact": {"model": "linear", "kn": 3.5672e7, "eta_n": 0, "friction": 0},
            "walls": [{"point": [-1.5, 0], "normal": [1, 0], "velocity": [v, 0]}],
            "bodies": [{"shape": {"type": "circle", "r": 1}, "position": [0, 0]}]
        });
        let file = write(&dir, "mirror.json", &c);
        let out = dir.join("run");
        let (code, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"]);
        assert_eq!(code, 0, "{err}");
        let e = &summary(&out)["energies"];
        let m = std::f64::consts::PI;
        let w = 2.0 * m * v * v;
        let walls_work = e["walls_work"].as_f64().unwrap();
        assert!((walls_work / w - 1.0).abs() < 1e-3, "W {walls_work} vs {w}");
        assert_eq!(e["initial_total"], 0.0);
        let final_total = e["final_total"].as_f64().unwrap();
        assert!((final_total / w - 1.0).abs() < 1e-3, "{e}");
        let unaccounted = e["unaccounted"].as_f64().unwrap();
        assert!(unaccounted.abs() < 1e-4 * w, "{e}");
    }
}

/// Issue 29, item 14. `walls.csv` held each wall's line only, and only with `--contacts`: a
/// biaxial test's stress–strain curve needs the walls' loads. Now every run with walls writes
/// each wall's position, velocity, normal and tangential load, its span and its stresses at
/// every output frame.
mod bug_walls_csv_held_no_wall_loads {
    use super::*;

    #[test]
    fn the_walls_of_a_settled_box_carry_its_weight_and_a_servo_lid_its_target_stress() {
        // The three ellipses of settle3 in their box (floor, two sides 6 cm apart) under a lid
        // holding σ = 2000 dyn/cm² across the box. At rest the walls carry the weight and the
        // lid's load: Σ over the walls of their vertical force on the bodies is the weight
        // 3 π a b ρ g (the lid's counted downwards); the lid's stress is its target.
        let dir = scratch("walls_loads");
        let sigma = 2000.0;
        let mut c = settle3();
        c["name"] = "settle3_lid".into();
        c["duration"] = 1.0.into();
        c["walls"]
            .as_array_mut()
            .unwrap()
            .push(serde_json::json!({"point": [0, 5], "normal": [0, -1],
                 "servo": {"stress": sigma, "span": [1, 2], "max_speed": 20}}));
        let file = write(&dir, "lid.json", &c);
        let out = dir.join("run");
        let (code, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"]);
        assert_eq!(code, 0, "{err}");
        let rows = csv(&out.join("walls.csv"));
        let last: Vec<_> = rows[rows.len() - 4..].to_vec();
        let weight = 3.0 * std::f64::consts::PI * 1.5 * 1.0 * 980.0;
        // Vertical force of every wall on the bodies: fn n + ft t, t = (−n_y, n_x).
        let up: f64 = last
            .iter()
            .map(|r| r["fn"] * r["ny"] + r["ft"] * r["nx"])
            .sum();
        let lid = &last[3];
        assert!(
            (up / weight - 1.0).abs() < 1e-4,
            "Σ up {up}, weight {weight}"
        );
        assert_eq!(lid["span"], 6.0);
        assert!((lid["sn"] / sigma - 1.0).abs() < 0.01, "{lid:?}");
        assert!((lid["sn"] - lid["fn"] / 6.0).abs() < 1e-9 * sigma);
        let floor = &last[0];
        assert_eq!(floor["span"], 6.0);
        assert!((floor["sn"] - floor["fn"] / 6.0).abs() < 1e-9 * floor["fn"]);
        // The side walls are bounded by the floor and the lid: their span is the lid's height.
        assert!((last[1]["span"] - lid["y"]).abs() < 1e-9, "{:?}", last[1]);
        // Every frame has a row per wall, at the trajectory's steps.
        let traj = csv(&out.join("trajectory.csv"));
        assert_eq!(rows.len(), traj.len() / 3 * 4);
    }
}

/// Issue 29, item 1. A floor given 300 times ran to exit 0: the square left at ~200 cm/s, the
/// dissipated energy went to −1.7e5 erg, and that negative dissipation cancelled the created
/// energy so that the blow-up watch never fired. Now coincident walls are refused at load
/// (naming both), and the watch counts a fall of the dissipated energy as energy created.
mod bug_a_wall_given_300_times_ran_to_exit_0 {
    use super::*;
    use dem2d::run::watch::ENERGY_GROWTH;
    use dem2d::run::{RunError, Simulation};
    use dem2d::scene::Case;

    #[test]
    fn coincident_walls_are_refused_naming_both() {
        let dir = scratch("duplicate_walls");
        let mut c: Value =
            serde_json::from_str(&std::fs::read_to_string(case("throw_square.json")).unwrap())
                .unwrap();
        let floor = c["walls"][0].clone();
        c["walls"] = vec![floor; 300].into();
        let file = write(&dir, "dup.json", &c);
        let (code, out, err) = dem2d(&["run", &file, "--out", dir.join("run").to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(out.is_empty());
        assert!(
            err.contains("field `walls[1]`: coincides with walls[0]"),
            "{err}"
        );
        assert!(!dir.join("run").exists(), "nothing written");
        // Nearly coincident (a hundredth of a millimetre apart) is the same mistake.
        c["walls"] = serde_json::json!([{"point": [0, 0], "normal": [0, 1]},
                                        {"point": [0, 1e-3], "normal": [0, 2]}]);
        let file = write(&dir, "near.json", &c);
        let (code, _, err) = dem2d(&["run", &file, "--out", dir.join("run").to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("coincides with walls[0]"), "{err}");
    }

    #[test]
    fn energy_created_as_negative_dissipation_stops_the_run() {
        // The 300 floors built past the scene's check: the watch alone must stop it. The energy
        // the start and gravity can supply is the initial kinetic energy and the height the
        // square can fall; the square cannot leave faster than that allows.
        let mut c =
            Case::from_json(&std::fs::read_to_string(case("throw_square.json")).unwrap()).unwrap();
        let floor = c.walls[0].clone();
        c.walls = vec![floor; 300];
        let mut w = c.build_world();
        let mut sim = Simulation::new(&mut w).until_time(c.duration);
        let ended = sim.run();
        let watch = sim.progress().watch.clone();
        let e = w.energies;
        eprintln!(
            "300 floors: stopped at t = {:.4} s ({ended:?}); K {:.3e} D {:.3e}",
            w.time, e.kinetic, e.dissipated
        );
        let Err(RunError::Blowup(b)) = &ended else {
            panic!("{ended:?}");
        };
        assert!(b.reason.contains("the energy grew"), "{b}");
        // What the account alone shows, E − E₀ − W: the created kinetic energy cancelled by the
        // negative dissipation, far below the threshold (the watch that read only this never
        // fired).
        let account = e.total() - watch.total0 - e.boundary_work;
        assert!(account < ENERGY_GROWTH * watch.available(), "{account}");
        assert!(e.dissipated < 0.0);
    }
}

/// Issue 29, item 9. A floor given the normal `[0, -1]` only warned of overlaps and the run
/// "completed" with the bodies at y = −1398 cm. Now a wall with most bodies starting on its
/// solid side is refused, saying the normal may be flipped.
mod bug_a_flipped_wall_normal_ran_with_the_bodies_falling_forever {
    use super::*;

    #[test]
    fn a_wall_with_most_bodies_on_its_solid_side_is_refused() {
        let dir = scratch("flipped");
        let mut c = settle3();
        c["walls"][0]["normal"] = serde_json::json!([0, -1]);
        let file = write(&dir, "flipped.json", &c);
        let out = dir.join("run");
        let (code, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains(
                "field `walls[0].normal`: 3 of the 3 bodies start on the wall's solid side"
            ) && err.contains("may be flipped")
                && err.contains("[0, 1] rather than [0, -1]"),
            "{err}"
        );
        assert!(!out.exists());
        // One body of three below a floor is a placement mistake the overlap warning reports,
        // not a flipped wall.
        let mut c = settle3();
        c["bodies"][2]["position"] = serde_json::json!([3.2, -5.0]);
        let file = write(&dir, "one_below.json", &c);
        let (code, _, err) = dem2d(&[
            "run",
            &file,
            "--out",
            out.to_str().unwrap(),
            "--max-steps",
            "1",
        ]);
        assert_eq!(code, 0, "{err}");
    }
}

/// Issue 29, item 6. Values nobody could mean passed silently: `analysis.csv` wrote `inf` for
/// q/p at p = 0; a state file with `dissipated: -1e300` ran to exit 0; a state whose contact
/// list was emptied was accepted and blew up 1019 steps later; an edited state that created an
/// overlap was not warned of; a polygon of 100 000 vertices was accepted (200 steps took
/// 1.5 s). Now: an empty field; refused, naming `state.energies.dissipated`; refused, naming
/// the overlapping pair at `state.contacts`; a warning naming the pair; refused above 1000
/// vertices.
mod bug_impossible_values_passed_silently {
    use super::*;

    #[test]
    fn q_over_p_without_a_mean_stress_is_an_empty_field() {
        use dem2d::analysis::Measures;
        use dem2d::output::analysis::analysis_row;
        // Pure shear: σ₁ = −σ₃, so p = 0 and q = 1: q/p has no value.
        let m = Measures {
            stress: [1.0, -1.0, 0.0],
            ..Default::default()
        };
        let row = analysis_row("0", &m);
        assert!(!row.contains("inf") && !row.contains("NaN"), "{row}");
        let fields: Vec<&str> = row.split(',').collect();
        assert_eq!((fields[5], fields[6], fields[7]), ("0", "1", ""), "{row}");
    }

    /// A state written by a run of `settle3` (3 ellipses in a box) after 2000 steps.
    fn state(dir: &Path) -> Value {
        let (code, _, err) = dem2d(&[
            "run",
            &case("settle3_dt1e-5.json"),
            "--out",
            dir.join("first").to_str().unwrap(),
            "--quiet",
            "--max-steps",
            "2000",
        ]);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str(&std::fs::read_to_string(dir.join("first/state.json")).unwrap())
            .unwrap()
    }

    #[test]
    fn an_impossible_energy_account_and_an_emptied_contact_list_are_refused() {
        let dir = scratch("bad_states");
        let s = state(&dir);
        let out = dir.join("out");
        let run = |name: &str, v: &Value| {
            let file = write(&dir, name, v);
            dem2d(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"])
        };
        for (field, value, want) in [
            (
                "dissipated",
                -1e300,
                "field `state.energies.dissipated`: -1e300 is below zero",
            ),
            (
                "dissipated",
                1e300,
                "field `state.energies`: the account is that of a blow-up",
            ),
            (
                "kinetic",
                -1.0,
                "field `state.energies.kinetic`: must be zero or positive",
            ),
        ] {
            let mut bad = s.clone();
            bad["state"]["energies"][field] = value.into();
            let (code, _, err) = run("bad.json", &bad);
            assert_eq!(code, 2, "{field} = {value}: {err}");
            assert!(err.contains(want), "{err}");
            assert!(!out.exists());
        }
        let mut bad = s.clone();
        bad["state"]["contacts"] = serde_json::json!([]);
        let (code, _, err) = run("emptied.json", &bad);
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains("field `state.contacts`: bodies 0 and 1 overlap")
                && err.contains("does not hold their pair"),
            "{err}"
        );
        // The state as written continues.
        let (code, _, err) = dem2d(&[
            "run",
            dir.join("first/state.json").to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--max-steps",
            "10",
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(!err.contains("warning"), "{err}");
    }

    #[test]
    fn an_edited_state_that_creates_an_overlap_is_warned_of() {
        let dir = scratch("edited_state");
        let mut s = state(&dir);
        // Body 2 (resting on 0 and 1) pushed down into body 0: their pair is in the list, but
        // was not in contact.
        let contacts = s["state"]["contacts"].as_array().unwrap();
        let pair = contacts
            .iter()
            .find(|c| c["i"] == 0 && c["j"] == 2)
            .expect("the pair (0, 2) is listed");
        assert_ne!(pair["active"], true, "(0, 2) touches already: {pair}");
        let y = s["bodies"][2]["position"][1].as_f64().unwrap();
        s["bodies"][2]["position"][1] = (y - 0.2).into();
        let file = write(&dir, "edited.json", &s);
        let out = dir.join("out");
        let (code, _, err) = dem2d(&[
            "run",
            &file,
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--max-steps",
            "10",
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(
            err.contains("overlap where the state's contacts did not (an edited state?)")
                && err.contains("bodies 0 and 2 by δ"),
            "{err}"
        );
        let w = summary(&out)["warnings"].to_string();
        assert!(w.contains("an edited state?"), "{w}");
    }

    #[test]
    fn a_polygon_of_more_than_a_thousand_vertices_is_refused() {
        let dir = scratch("many_vertices");
        let mut c = settle3();
        let n = 100_000;
        let vertices: Vec<[f64; 2]> = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                [a.cos(), a.sin()]
            })
            .collect();
        c["bodies"][2]["shape"] = serde_json::json!({"type": "polygon", "vertices": vertices});
        let file = write(&dir, "many.json", &c);
        let (code, _, err) = dem2d(&["run", &file, "--out", dir.join("run").to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains("field `bodies[2].shape.vertices`: 100000 vertices: at most 1000"),
            "{err}"
        );
    }
}

/// Issue 29, item 10. Giving a wall a velocity in a state file made it jump at the first step:
/// its position was computed from the absolute time, `p₀ + v t`, and its velocity stayed the
/// state's 0 (the contacts and the walls' work saw a wall at rest). Now a wall continues from
/// where the state has it, `p = p_s + v (t − t_s)`, at the case's velocity.
mod bug_a_wall_given_a_velocity_in_a_state_file_jumped {
    use super::*;

    #[test]
    fn the_wall_continues_from_where_it_is() {
        let dir = scratch("wall_continues");
        // settle3 with its right wall moved out to x = 8 (out of reach), run 0.02 s.
        let mut c = settle3();
        c["walls"][2]["point"] = serde_json::json!([8, 0]);
        let file = write(&dir, "case.json", &c);
        let first = dir.join("first");
        let (code, _, err) = dem2d(&[
            "run",
            &file,
            "--out",
            first.to_str().unwrap(),
            "--quiet",
            "--max-steps",
            "2000",
        ]);
        assert_eq!(code, 0, "{err}");
        let mut s: Value =
            serde_json::from_str(&std::fs::read_to_string(first.join("state.json")).unwrap())
                .unwrap();
        // The wall withdraws at 10 cm/s from t_s = 0.02 s.
        s["walls"][2]["velocity"] = serde_json::json!([10, 0]);
        let file = write(&dir, "edited.json", &s);
        let out = dir.join("out");
        let (code, _, err) = dem2d(&[
            "run",
            &file,
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--max-steps",
            "1000",
        ]);
        assert_eq!(code, 0, "{err}");
        let rows: Vec<_> = csv(&out.join("walls.csv"))
            .into_iter()
            .filter(|r| r["wall"] == 2.0)
            .collect();
        assert_eq!(rows[0]["t"], 0.02);
        assert_eq!(rows[0]["x"], 8.0, "no jump at the start");
        for r in &rows[1..] {
            let want = 8.0 + 10.0 * (r["t"] - 0.02);
            assert!((r["x"] - want).abs() < 1e-12, "{r:?}: x should be {want}");
            assert_eq!(r["vx"], 10.0);
        }
        assert!((rows.last().unwrap()["x"] - 8.1).abs() < 1e-12);
    }
}

/// Issue 29, item 12. An unknown key said only "unknown field" (`frction`), and a misnamed one
/// made its proper key "missing" (`radius` for `r`); running a `dem2d contact` file as a case
/// said "must be an object, got an array"; `dem2d --help` named three shapes and three studies;
/// the impacts footnote gave a linear stiffness in dyn/cm²; `study repose` printed Rust's
/// `Some(0.65178)`. Now the messages say what was likely meant and list the valid keys, the
/// contact file is named as such, the help lists every shape and study, the stiffness is in
/// dyn/cm of a 1 cm slice, and repose prints `column settled at t = 0.65178 s`.
mod bug_messages_did_not_say_what_was_meant {
    use super::*;

    fn run_case(name: &str, v: &Value) -> String {
        let dir = scratch(name);
        let file = write(&dir, "case.json", v);
        let (code, _, err) = dem2d(&["run", &file, "--out", dir.join("run").to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        err
    }

    #[test]
    fn an_unknown_key_gets_did_you_mean_and_the_valid_keys() {
        let mut c = settle3();
        let f = c["contact"]
            .as_object_mut()
            .unwrap()
            .remove("friction")
            .unwrap();
        c["contact"]["frction"] = f;
        let err = run_case("frction", &c);
        assert!(
            err.contains("field `contact.frction`: unknown field: did you mean `friction`?")
                && err.contains("`kn_over_rho_g`")
                && err.contains("`rolling_model`"),
            "{err}"
        );
        let mut c = settle3();
        c["bodies"][0]["shape"] = serde_json::json!({"type": "circle", "radius": 1.0});
        let err = run_case("radius", &c);
        assert!(
            err.contains(
                "field `bodies[0].shape.r`: is missing (`radius` is given: did you mean `r`?)"
            ),
            "{err}"
        );
        let mut c = settle3();
        c["bodies"][1]["velocty"] = serde_json::json!([1, 0]);
        let err = run_case("velocty", &c);
        assert!(
            err.contains("did you mean `velocity`?")
                && err.contains("the valid keys here: `angle`, `density`, `fixed`, `material`, `omega`, `position`, `prescribed`, `shape`, `velocity`"),
            "{err}"
        );
        // Nothing like any key: the valid keys only.
        let mut c = settle3();
        c["walls"][0]["colour"] = "red".into();
        let err = run_case("colour", &c);
        assert!(
            err.contains("field `walls[0].colour`: unknown field (the valid keys here:")
                && err.contains("`servo`"),
            "{err}"
        );
    }

    #[test]
    fn the_help_lists_every_shape_and_study_and_the_impacts_stiffness_has_its_unit() {
        let (code, out, _) = dem2d(&["--help"]);
        assert_eq!(code, 0);
        assert!(
            out.contains("convex polygons") && out.contains("clumps of disks"),
            "{out}"
        );
        let (code, out, _) = dem2d(&["study", "--help"]);
        assert_eq!(code, 0);
        for study in [
            "rolling-fig3",
            "repose",
            "biaxial",
            "impacts",
            "biaxial-shape",
            "packing",
            "representation",
        ] {
            assert!(out.contains(study), "{study}: {out}");
        }
        // A linear stiffness is a force per unit thickness per overlap: dyn/cm for the 1 cm
        // slice (the guide's unit), not dyn/cm² (a pressure, E's unit).
        let dir = scratch("impacts_footnote");
        std::fs::create_dir_all(dir.join("figures")).unwrap();
        let out = Command::new(bin())
            .args(["study", "impacts"])
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(out.status.success());
        let md = String::from_utf8(out.stdout).unwrap();
        assert!(
            md.contains("linear k_n = 1e10 dyn/cm (of a 1 cm slice") && !md.contains("wall time"),
            "{md}"
        );
    }

    #[test]
    fn a_contact_file_run_as_a_case_is_named_as_one() {
        let c = serde_json::json!([{"i": {"shape": {"type": "circle", "r": 1}, "position": [0, 0]},
                                    "j": {"wall": {"point": [0, -1], "normal": [0, 1]}}}]);
        let err = run_case("contact_file", &c);
        assert!(
            err.contains("this is a `dem2d contact` input") && err.contains("dem2d contact FILE"),
            "{err}"
        );
    }
}

/// Issue 29, item 8. `contacts.csv` left out the couple of a four-crossing contact (the area
/// law's force acts at the crossings' mean together with a couple): torques rebuilt from the
/// file were off by 15 × max|F|·lever, and `analyze` (stress) missed the couple. Now the file
/// has a `couple` column, and the stress takes such a force at its line of action.
mod bug_contacts_csv_left_out_the_couple_of_deep_contacts {
    use super::*;

    #[test]
    fn each_bodys_torque_is_rebuilt_from_contacts_csv() {
        // A thin ellipse poking through another (their outlines cross four times), no
        // gravity: the area law acts with a couple. The torque the integrator used is in
        // state.json; rebuilt from the file's rows it is Σ (p − x) × F + couple, F and the
        // couple on j, their opposites on i.
        let dir = scratch("couple");
        let c = serde_json::json!({
            "version": 1, "name": "cross", "gravity": [0, 0], "dt": 1e-6, "duration": 1e-5,
            "output_every": 1,
            "contact": {"model": "linear", "kn": 1e6, "eta_n": 0, "friction": 0,
                        "normal_force": "area"},
            "bodies": [
                {"shape": {"type": "ellipse", "a": 2, "b": 0.3}, "position": [0, 0], "angle": 0},
                {"shape": {"type": "ellipse", "a": 2, "b": 0.5}, "position": [1.45, 0.1],
                 "angle": 1.5}]
        });
        let file = write(&dir, "cross.json", &c);
        let out = dir.join("run");
        let (code, _, err) = dem2d(&[
            "run",
            &file,
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--contacts",
        ]);
        assert_eq!(code, 0, "{err}");
        let text = std::fs::read_to_string(out.join("contacts.csv")).unwrap();
        assert!(text.starts_with("step,t,i,j,px,py,nx,ny,fn,ft,couple,depth,state\n"));
        let rows: Vec<Vec<&str>> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect())
            .filter(|f: &Vec<&str>| f[0] == "10")
            .collect();
        assert_eq!(rows.len(), 1, "{text}");
        let f: Vec<f64> = rows[0][4..11].iter().map(|v| v.parse().unwrap()).collect();
        let (px, py, nx, ny, fn_, ft, couple) = (f[0], f[1], f[2], f[3], f[4], f[5], f[6]);
        assert_eq!(rows[0][12], "deep");
        let (fx, fy) = (fn_ * nx - ft * ny, fn_ * ny + ft * nx);
        let state: Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("state.json")).unwrap())
                .unwrap();
        let lever = 2.0 * fx.hypot(fy);
        for (k, sign) in [(0usize, -1.0), (1, 1.0)] {
            let x = state["bodies"][k]["position"][0].as_f64().unwrap();
            let y = state["bodies"][k]["position"][1].as_f64().unwrap();
            let torque = state["state"]["bodies"][k]["torque"].as_f64().unwrap();
            let rebuilt = sign * ((px - x) * fy - (py - y) * fx + couple);
            assert!(
                (rebuilt - torque).abs() < 1e-9 * lever,
                "body {k}: rebuilt {rebuilt}, the step's {torque}"
            );
        }
        // The couple is no rounding: without it the rebuilt torque is wrong by a thousandth
        // of |F|·2a and more (a million times the tolerance).
        assert!(
            couple.abs() > 1e-3 * lever,
            "couple {couple}, |F|·2a {lever}"
        );
    }

    #[test]
    fn the_stress_takes_a_deep_contacts_force_at_its_line_of_action() {
        use dem2d::analysis::FrameContact;
        use dem2d::dynamics::Partner;
        use dem2d::geometry::Vec2;
        // A force F = (0, 1) at the origin with a couple M = 2 is the force alone at (2, 0):
        // its moment there about the origin is x F_y = 2.
        let c = FrameContact {
            i: Partner::Wall(0),
            j: 0,
            point: Vec2::zeros(),
            normal: Vec2::new(0.0, 1.0),
            force: Vec2::new(0.0, 1.0),
            couple: 2.0,
            depth: 0.1,
            state: "deep".into(),
        };
        let p = c.action_point();
        assert!((p - Vec2::new(2.0, 0.0)).norm() < 1e-15, "{p}");
        let moment = p.x * c.force.y - p.y * c.force.x;
        assert!((moment - 2.0).abs() < 1e-15);
    }
}

/// Issue 29, item 13. `dem2d verify` (31 s), the studies (repose 203 s) and `bench`'s settling
/// printed nothing while they worked; `bench`'s "settled" 1000-disk pile was reported with 0
/// contacts. Now every loop that steps a world shows `dem2d run`'s progress line (after two
/// seconds; once a second on a terminal, every 30 s in a log), and the settled pile touches
/// (`dem2d-lab bench`'s part: `lab/tests/regressions.rs`).
mod bug_long_commands_printed_nothing_while_they_worked {
    use super::*;
    use std::io::{BufRead, BufReader};

    /// Runs dem2d with `args` until a progress line of `dem2d run`'s form comes on stderr, then
    /// stops it; returns that line.
    fn first_progress_line(args: &[&str], dir: &Path) -> String {
        let mut child = Command::new(bin())
            .args(args)
            .current_dir(dir)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut seen = String::new();
        let mut found = None;
        for l in BufReader::new(child.stderr.take().unwrap()).lines() {
            let l = l.unwrap();
            seen.push_str(&l);
            seen.push('\n');
            if l.contains(": step ") && l.contains(" steps/s, ") {
                found = Some(l);
                break;
            }
        }
        let _ = child.kill();
        let _ = child.wait();
        let line = found.unwrap_or_else(|| panic!("{args:?}: no progress line in:\n{seen}"));
        // `NAME: step N/M (P %), t = T s, R steps/s, L left (at most), C contacts, unbalanced
        // force ratio U`, as `dem2d run` writes it.
        let fields: Vec<&str> = line.split(", ").collect();
        assert_eq!(fields.len(), 6, "{line}");
        assert!(
            fields[0].contains(" %)") && fields[1].starts_with("t = "),
            "{line}"
        );
        assert!(fields[5].starts_with("unbalanced force ratio "), "{line}");
        line
    }

    #[test]
    fn a_study_and_verify_show_the_progress_line() {
        let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
        let line = first_progress_line(&["study", "rolling-fig3"], repo);
        assert!(line.starts_with("throw_"), "{line}");
        let line = first_progress_line(&["verify"], repo);
        assert!(
            ["grains", "biaxial", "packing"]
                .iter()
                .any(|w| line.contains(w)),
            "{line}"
        );
    }
}

/// Issue 29, item 15 (its code part). Of `dem2d verify`'s 17 comparisons none involved an
/// ellipse under the area law, the default: the law most runs use had no row with an
/// independent answer. Now every level runs ellipses against closed forms and a conservation
/// law: the rocking period, a tilted drop's rebound, the resting pose on an incline (and none
/// beyond the angle the shape can hold), and the zero work around closed loops (with P's depth
/// law as the control that gains work).
mod bug_verify_had_no_ellipse_under_the_area_law {
    use super::*;

    #[test]
    fn verify_quick_runs_the_ellipse_rows_and_they_pass() {
        let (code, out, err) = dem2d(&["verify", "--quick"]);
        assert_eq!(code, 0, "{out}{err}");
        let rows: Vec<&str> = out
            .lines()
            .filter(|l| l.starts_with("| ") && l.contains("ellipse"))
            .collect();
        assert_eq!(rows.len(), 10, "{out}");
        assert!(rows.iter().all(|r| r.ends_with("| pass |")), "{out}");
        for what in [
            "rocking",
            "frictionless floor",
            "30° incline",
            "40° incline",
            "area law",
        ] {
            assert!(rows.iter().any(|r| r.contains(what)), "{what}: {out}");
        }
    }
}

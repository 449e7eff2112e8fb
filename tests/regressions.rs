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
        let watch = sim.progress().watch;
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
            "repose-cohesion",
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

/// Issue 29, item 15: the CDT limiter shared a body's couple by its neighbour-list slots, so a
/// neighbour inside the list's skin that did not touch it (0.05 cm away) doubled a creeping
/// ellipse's rate (2.95e-4 → 5.76e-4 rad/s). It is shared by the body's contacts now.
mod bug_the_cdt_limiter_counted_neighbours_that_do_not_touch {
    use dem2d::contact_law::{RollingModel, RollingPart};
    use dem2d::geometry::{Shape, Vec2};
    use dem2d::run::Simulation;
    use dem2d::scene::Case;

    /// An ellipse rocking on a floor under CDT rolling resistance, and with `neighbour` a fixed
    /// disk just above it; the ellipse's poses over 0.3 s and its contacts with the disk.
    fn ellipse_poses(neighbour: bool) -> (Vec<(Vec2, f64)>, usize) {
        let law = super::common::linear(1e6, 40.0, 0.5).with_rolling(Some(RollingPart {
            model: RollingModel::Cdt,
            friction: 0.1,
            damping: None,
        }));
        let mut bodies = vec![super::common::body(
            Shape::Ellipse { a: 1.0, b: 0.5 },
            Vec2::new(0.0, 0.52),
            0.15,
        )];
        if neighbour {
            // A fixed disk over the ellipse, 0.05 cm above its highest point (its top only
            // sinks as it rocks flatter): inside the list's skin (0.1 cm), never touching.
            bodies.push(dem2d::dynamics::BodyInit {
                prescribed: true,
                ..super::common::body(Shape::Circle { r: 0.5 }, Vec2::new(0.0, 1.587), 0.0)
            });
        }
        let case = Case::new(
            bodies,
            vec![super::common::floor(law)],
            Vec2::new(0.0, -980.0),
            law,
            1e-5,
        );
        let mut w = case.build_world();
        let mut poses = Vec::new();
        let mut touched = 0usize;
        Simulation::new(&mut w)
            .until_step(30_000)
            .run_each(|w, _| {
                let s = w.bodies.state[0];
                poses.push((s.pose.position, s.pose.angle()));
                touched += w
                    .contacts
                    .active()
                    .filter(|c| c.slot.i == 0 && !c.slot.is_wall())
                    .count();
            })
            .unwrap();
        (poses, touched)
    }

    #[test]
    fn a_neighbour_that_never_touches_changes_no_bit_of_the_ellipse() {
        let (alone, _) = ellipse_poses(false);
        let (beside, touched) = ellipse_poses(true);
        assert_eq!(touched, 0, "the neighbour touched the ellipse");
        // The ellipse moves (a creep or a rock to compare), and bit for bit as alone.
        let turned = (alone.last().unwrap().1 - alone[0].1).abs();
        assert!(turned > 1e-4, "the ellipse turned only {turned} rad");
        assert_eq!(alone.len(), beside.len());
        if let Some(k) = (0..alone.len()).find(|&k| alone[k] != beside[k]) {
            panic!(
                "step {}: the ellipse at {:?} beside the disk, {:?} alone",
                k + 1,
                beside[k],
                alone[k]
            );
        }
    }
}

/// The user guide's pouring example (`docs/src/reference/case-file.md`, the case named
/// `pouring`): fixed grains, three inserters of circles, ellipses and rectangles, an outflow
/// region below a gap.
fn pouring() -> Value {
    let page = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/src/reference/case-file.md"),
    )
    .unwrap();
    let block = page
        .split("```json\n")
        .skip(1)
        .map(|b| b.split("```").next().unwrap())
        .find(|b| b.contains("\"name\": \"pouring\""))
        .expect("the pouring example");
    serde_json::from_str(block).unwrap()
}

/// Each body's shape by identity, as the run's files give it: the case's bodies, then each
/// inserted body's inserter's shape at the radius and aspect `inserted.csv` records (the
/// formulas of docs/src/reference/outputs.md): (VTK shape code, semi-axes, exact area).
fn shapes_by_id(case: &Value, run: &Path) -> std::collections::HashMap<u64, (i32, [f64; 2], f64)> {
    let pi = std::f64::consts::PI;
    let of = |s: &Value| -> (i32, [f64; 2], f64) {
        let n = |k: &str| s[k].as_f64().unwrap();
        match s["type"].as_str().unwrap() {
            "circle" => (0, [n("r"), n("r")], pi * n("r") * n("r")),
            "ellipse" => (1, [n("a"), n("b")], pi * n("a") * n("b")),
            "rectangle" => (2, [n("w") / 2.0, n("h") / 2.0], n("w") * n("h")),
            t => panic!("{t}"),
        }
    };
    let mut out: std::collections::HashMap<u64, (i32, [f64; 2], f64)> = case["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(k, b)| (k as u64, of(&b["shape"])))
        .collect();
    for row in csv(&run.join("inserted.csv")) {
        let (r, a) = (row["r"], row["aspect"]);
        let shape = match case["insert"][row["insert"] as usize]["shape"].as_str() {
            Some("ellipse") => {
                serde_json::json!({"type": "ellipse", "a": r * a.sqrt(), "b": r / a.sqrt()})
            }
            Some("rectangle") => {
                serde_json::json!({"type": "rectangle", "w": r * (pi * a).sqrt(), "h": r * (pi / a).sqrt()})
            }
            _ => serde_json::json!({"type": "circle", "r": r}),
        };
        out.insert(row["body"] as u64, of(&shape));
    }
    out
}

/// Issue 41, item 5. `--vtk` on any run that inserts bodies panicked (`src/output/vtk.rs`:
/// index out of bounds, exit 101) at its first inserted body — the user guide's own pouring
/// example; from Python a `PanicException`. The writer kept one outline per body of the case,
/// by index. Now it keeps them by identity and makes an inserted body's when it first draws it.
mod bug_vtk_panicked_on_every_run_that_inserts_bodies {
    use super::*;

    #[test]
    fn the_guides_pouring_example_writes_every_frame_with_every_body() {
        let dir = scratch("vtk_pouring");
        let case = write(&dir, "pouring.json", &pouring());
        let out = dir.join("run");
        let (code, _, err) = dem2d(&[
            "run",
            &case,
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--vtk-every",
            "2000",
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(!err.contains("panicked"), "{err}");
        // Frames at steps 0, 2000, …, 10000, each with one body cell per row of the
        // trajectory at its step.
        let traj = csv(&out.join("trajectory.csv"));
        for k in 0..6 {
            let text = std::fs::read_to_string(out.join(format!("vtk/frame_{k:05}.vtu"))).unwrap();
            let a = super::common::vtu_arrays(&text);
            let step = super::common::i64s(&a["STEP"])[0] as f64;
            let rows = traj.iter().filter(|r| r["step"] == step).count();
            let bodies = super::common::i32s(&a["kind"])
                .iter()
                .filter(|&&k| k == 0)
                .count();
            assert_eq!(bodies, rows, "frame {k} (step {step})");
            assert!(k == 0 || rows > 4, "frame {k}: nothing inserted");
        }
    }
}

/// Issue 41, item 4. After an outflow removed a body, VTK drew every later body with its
/// predecessor's outline (an ellipse with the removed circle's, a square with the ellipse's):
/// the outlines were kept by index, which a removal shifts. Every silo or hopper looked wrong
/// in ParaView while the `shape` arrays were right. Now the outline, `id` and `pair` follow
/// the body's identity (`trajectory.csv`'s `body`).
mod bug_vtk_drew_each_body_after_a_removed_one_with_its_predecessors_outline {
    use super::*;

    #[test]
    fn each_body_is_drawn_with_its_own_shape_before_and_after_removals() {
        let dir = scratch("vtk_outflow");
        let case = pouring();
        let file = write(&dir, "pouring.json", &case);
        let out = dir.join("run");
        let (code, _, err) = dem2d(&[
            "run",
            &file,
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--vtk-every",
            "500",
        ]);
        assert_eq!(code, 0, "{err}");
        let removed = csv(&out.join("discharge.csv"));
        assert!(removed.len() >= 3, "{} bodies left", removed.len());
        let shapes = shapes_by_id(&case, &out);
        let traj = csv(&out.join("trajectory.csv"));
        let mut after_removal = 0;
        for k in 0..21 {
            let text = std::fs::read_to_string(out.join(format!("vtk/frame_{k:05}.vtu"))).unwrap();
            let a = super::common::vtu_arrays(&text);
            let step = super::common::i64s(&a["STEP"])[0] as f64;
            let ids: Vec<u64> = traj
                .iter()
                .filter(|r| r["step"] == step)
                .map(|r| r["body"] as u64)
                .collect();
            let (points, conn, offsets) = (
                super::common::f64s(&a["Points"]),
                super::common::i64s(&a["connectivity"]),
                super::common::i64s(&a["offsets"]),
            );
            let (id, code, axes) = (
                super::common::i64s(&a["id"]),
                super::common::i32s(&a["shape"]),
                super::common::f64s(&a["semi_axes"]),
            );
            for (c, &body) in ids.iter().enumerate() {
                let (want_code, want_axes, area) = shapes[&body];
                assert_eq!(id[c] as u64, body, "frame {k}, cell {c}");
                assert_eq!(code[c], want_code, "frame {k}: body {body}");
                assert_eq!(
                    [axes[2 * c], axes[2 * c + 1]],
                    want_axes,
                    "frame {k}: body {body}"
                );
                // The outline's area (shoelace) is the body's, short by at most the chords'
                // deficit (1e-3 of the smaller semi-axis per unit of perimeter: < 1 %).
                let from = if c == 0 { 0 } else { offsets[c - 1] as usize };
                let ring: Vec<(f64, f64)> = conn[from..offsets[c] as usize]
                    .iter()
                    .map(|&p| (points[3 * p as usize], points[3 * p as usize + 1]))
                    .collect();
                let drawn: f64 = (0..ring.len())
                    .map(|i| {
                        let (p, q) = (ring[i], ring[(i + 1) % ring.len()]);
                        0.5 * (p.0 * q.1 - q.0 * p.1)
                    })
                    .sum();
                assert!(
                    (drawn - area).abs() <= 1e-2 * area,
                    "frame {k} (step {step}): body {body}'s outline has area {drawn}, its shape {area}"
                );
            }
            if removed.iter().any(|r| r["step"] < step) {
                after_removal += 1;
            }
        }
        assert!(after_removal >= 3, "{after_removal} frames after a removal");
    }
}

/// Issue 41, item 6. In a cell periodic in x, a body thrown up fast made the broad phase tile
/// the bodies' whole vertical extent: at 1e16 cm/s the run hung, at 1e30 it asked for 37 TB,
/// and an edited state force of 1e300 panicked with a capacity overflow. The tiling's cap now
/// holds for the number of tiles, whatever its shape, and a body beyond the extent a case may
/// place one at (1e9 × the smallest width) stops the run as a blow-up naming the step and the
/// body.
mod bug_a_body_thrown_up_fast_in_a_cell_periodic_in_x_hung_the_run {
    use super::*;

    fn cell_x(vy: f64) -> Value {
        serde_json::json!({ "version": 1, "name": "thrown", "units": "cm",
          "gravity": [0, -980], "dt": 1e-5, "duration": 0.01, "output_every": 100,
          "cell": { "size": [8, 10], "periodic": "x" },
          "contact": { "model": "linear", "kn_over_rho_g": 36400, "restitution": 0.5, "friction": 0.5 },
          "walls": [ { "point": [0, 0], "normal": [0, 1] } ],
          "bodies": [ { "shape": {"type": "ellipse", "a": 1.0, "b": 0.5}, "position": [7.5, 1] },
                      { "shape": {"type": "circle", "r": 0.6}, "position": [2.2, 1], "velocity": [0, vy] },
                      { "shape": {"type": "circle", "r": 0.6}, "position": [4.2, 1] } ] })
    }

    /// Runs `args` with a deadline: (exit code, stderr), or a failure naming the hang.
    fn bounded(args: &[&str]) -> (i32, String) {
        let mut child = Command::new(bin())
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let start = Instant::now();
        while child.try_wait().unwrap().is_none() {
            if start.elapsed() > Duration::from_secs(60) {
                let _ = child.kill();
                panic!("{args:?}: no answer in 60 s (a hang)");
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let out = child.wait_with_output().unwrap();
        (
            out.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    }

    #[test]
    fn a_body_thrown_up_at_1e16_or_1e30_cm_per_s_stops_the_run_naming_it() {
        let dir = scratch("thrown");
        for vy in [1e16, 1e30] {
            let file = write(&dir, &format!("thrown_{vy:e}.json"), &cell_x(vy));
            let out = dir.join(format!("run_{vy:e}"));
            let (code, err) = bounded(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"]);
            assert_eq!(code, 1, "{err}");
            assert!(
                !err.contains("panicked") && !err.contains("memory"),
                "{err}"
            );
            // Found at the first scan (step 64), the body named; its height there is the free
            // flight's, y₀ + v t (gravity's −g t²/2 is below its rounding).
            assert!(
                err.contains("blow-up at step 64") && err.contains("body 1:"),
                "{err}"
            );
            let y = 1.0 + vy * 64.0 * 1e-5;
            assert!(
                err.contains(&format!("{y:.3e} cm from the origin")),
                "{y:.3e}: {err}"
            );
            assert_eq!(summary(&out)["status"], "blowup");
        }
    }

    #[test]
    fn an_edited_state_force_of_1e300_stops_the_run_at_its_first_step() {
        let dir = scratch("force1e300");
        let mut case = cell_x(0.0);
        case["duration"] = 0.005.into();
        let file = write(&dir, "case.json", &case);
        let first = dir.join("first");
        let (code, _, err) = dem2d(&["run", &file, "--out", first.to_str().unwrap(), "--quiet"]);
        assert_eq!(code, 0, "{err}");
        let mut state: Value =
            serde_json::from_str(&std::fs::read_to_string(first.join("state.json")).unwrap())
                .unwrap();
        state["state"]["bodies"][1]["force"] = serde_json::json!([0, 1e300]);
        let edited = write(&dir, "edited.json", &state);
        let out = dir.join("edited");
        let (code, err) = bounded(&[
            "run",
            &edited,
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--duration",
            "0.02",
        ]);
        assert_eq!(code, 1, "{err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(
            err.contains("blow-up at step 501") && err.contains("body 1:"),
            "{err}"
        );
    }
}

/// Issue 41, item 8. `--threads 20000` (and `threads=10**6` from Python) was accepted: thousands
/// of threads, the machine's load above 1000 for minutes. More than 4 × the machine's cores is
/// now refused (exit 2, naming `--threads` and what is accepted) by every command that takes it.
mod bug_thousands_of_worker_threads_were_accepted {
    use super::*;

    #[test]
    fn more_than_four_threads_per_core_are_refused_by_every_command() {
        let cores = std::thread::available_parallelism().unwrap().get();
        let (max, over) = (4 * cores, (4 * cores + 1).to_string());
        let settle = case("settle3_dt1e-5.json");
        let dir = scratch("threads");
        let out = dir.join("out");
        for args in [
            vec!["run", &settle, "--threads", "20000"],
            vec!["run", &settle, "--threads", &over],
            vec![
                "relax",
                &settle,
                "--out",
                out.to_str().unwrap(),
                "--threads",
                "20000",
            ],
            vec!["study", "impacts", "--threads", "20000"],
        ] {
            let (code, _, err) = dem2d(&args);
            assert_eq!(code, 2, "{args:?}: {err}");
            assert!(
                err.contains("--threads:") && err.contains(&format!("at most {max} accepted")),
                "{args:?}: {err}"
            );
            assert!(!out.exists(), "{args:?} wrote output");
        }
        // The most accepted runs.
        let (code, _, err) = dem2d(&[
            "run",
            &settle,
            "--threads",
            &max.to_string(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--max-steps",
            "100",
        ]);
        assert_eq!(code, 0, "{err}");
    }
}

/// Issue 41, item 9. `dem2d study shear` and `study jamming` over one aspect ratio panicked
/// (exit 101) drawing the figure, after printing the table: a series of one point had a value
/// range the plot refused. And a study run without `--docs` replaced the tracked
/// `figures/shear.svg` and `figures/shear.md` with the subset it ran. Now a range of one value
/// is padded by 5 % of it, and without `--docs` (or `--check`) a study writes its figures into
/// `runs/study/NAME` (or `--out`), and says so.
mod bug_a_study_of_one_aspect_ratio_panicked_and_replaced_the_tracked_figures {
    use super::*;

    #[test]
    fn one_aspect_ratio_draws_its_figure_outside_the_tracked_figures() {
        let tracked = |f: &str| {
            std::fs::read(
                Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("figures")
                    .join(f),
            )
            .unwrap()
        };
        let before: Vec<Vec<u8>> = ["shear.svg", "shear.md", "jamming.svg", "jamming.md"]
            .iter()
            .map(|f| tracked(f))
            .collect();
        // From an empty working directory: the default output, runs/study/NAME.
        let dir = scratch("study_one_alpha");
        for (name, args) in [
            (
                "shear",
                vec!["--grains", "16", "--aspects", "1", "--inertial", "0.1"],
            ),
            (
                "jamming",
                vec!["--grains", "16", "--packings", "1", "--aspects", "1.5"],
            ),
        ] {
            let out = Command::new(bin())
                .args(["study", name, "--threads", "1"])
                .args(&args)
                .current_dir(&dir)
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(0), "{name}: {err}");
            let at = dir.join("runs/study").join(name);
            assert!(err.contains(&format!("are in runs/study/{name}")), "{err}");
            for f in [
                format!("{name}.svg"),
                format!("{name}.md"),
                format!("{name}.png"),
            ] {
                assert!(at.join(&f).is_file(), "{name}: no {f}");
            }
            assert!(!dir.join("figures").exists());
            // The figure holds the one point (a marker in each panel).
            let svg = std::fs::read_to_string(at.join(format!("{name}.svg"))).unwrap();
            assert!(svg.contains("<circle"), "{name}: no point drawn");
        }
        // --out puts them there.
        let out_dir = dir.join("mine");
        let (code, _, err) = dem2d(&[
            "study",
            "shear",
            "--grains",
            "16",
            "--aspects",
            "1",
            "--inertial",
            "0.1",
            "--threads",
            "1",
            "--out",
            out_dir.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(out_dir.join("shear.svg").is_file());
        let after: Vec<Vec<u8>> = ["shear.svg", "shear.md", "jamming.svg", "jamming.md"]
            .iter()
            .map(|f| tracked(f))
            .collect();
        assert!(before == after, "a study without --docs changed figures/");
        // --out with --docs is refused (the tracked figures are --docs's).
        let (code, _, err) = dem2d(&["study", "impacts", "--docs", "--out", "x"]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("--out"), "{err}");
    }
}

/// Issue 41, item 10. Silent mistakes: SI gravity (`[0, -9.81]`) and a density in kg/m³ ran
/// without a hint (dem2d is cgs); `"units": "m"` was accepted and ignored; an insertion region
/// behind a wall placed no body and the run ended with exit 0; a scene filled only by insertion
/// had an a-priori critical step of `inf`, so a Δt far above it went unwarned. Now: a warning
/// (terminal and `summary.json`) for SI-looking gravity and densities; `units` other than
/// "cm" refused; a region behind a fixed wall refused, naming it, and an inserter that placed
/// nothing warned of at the end; the a-priori step counts the bodies the inserters can make.
mod bug_mistakes_of_units_and_insertion_ran_silently {
    use super::*;

    fn warnings(dir: &Path) -> Vec<String> {
        summary(dir)["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .map(|w| w.as_str().unwrap().to_string())
            .collect()
    }

    #[test]
    fn si_gravity_and_densities_are_warned_of_and_other_units_refused() {
        let dir = scratch("si_units");
        for (name, edit, want) in [
            (
                "gravity",
                ("gravity", serde_json::json!([0, -9.81])),
                "is Earth's in m/s²",
            ),
            (
                "density",
                ("density", serde_json::json!(2500.0)),
                "bodies[0] has a density of 2500 g/cm³",
            ),
        ] {
            let mut v = settle3();
            match edit.0 {
                "gravity" => v["gravity"] = edit.1,
                _ => v["bodies"][0]["density"] = edit.1,
            }
            let file = write(&dir, &format!("{name}.json"), &v);
            let out = dir.join(name);
            let (code, _, err) = dem2d(&[
                "run",
                &file,
                "--out",
                out.to_str().unwrap(),
                "--quiet",
                "--max-steps",
                "200",
            ]);
            assert_eq!(code, 0, "{err}");
            let said: Vec<&str> = err.lines().filter(|l| l.contains(want)).collect();
            assert_eq!(said.len(), 1, "{name}: once in the terminal: {err}");
            assert_eq!(
                warnings(&out).iter().filter(|w| w.contains(want)).count(),
                1,
                "{name}: once in summary.json"
            );
            assert!(said[0].contains("cgs"), "{}", said[0]);
        }
        // The shipped cases (cgs) warn of neither.
        let out = dir.join("cgs");
        let (code, _, err) = dem2d(&[
            "run",
            &case("settle3_dt1e-5.json"),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--max-steps",
            "10",
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(warnings(&out).is_empty(), "{:?}", warnings(&out));
        // Units other than cm.
        for units in ["m", "mm", "SI"] {
            let mut v = settle3();
            v["units"] = units.into();
            let file = write(&dir, "units.json", &v);
            let (code, _, err) = dem2d(&["run", &file, "--out", dir.join("u").to_str().unwrap()]);
            assert_eq!(code, 2, "{err}");
            assert!(
                err.contains("field `units`") && err.contains("may only be \"cm\""),
                "{err}"
            );
        }
    }

    #[test]
    fn an_insertion_region_behind_a_wall_is_refused_or_warned_of() {
        let dir = scratch("behind_wall");
        // A fixed lid at y = 8 over the box (free side below), the first region above it.
        let mut v = pouring();
        v["walls"]
            .as_array_mut()
            .unwrap()
            .push(serde_json::json!({"point": [0, 8], "normal": [0, -1]}));
        let file = write(&dir, "fixed.json", &v);
        let (code, _, err) = dem2d(&["run", &file, "--out", dir.join("f").to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains("field `insert[0].region`") && err.contains("behind walls[2]"),
            "{err}"
        );
        assert!(!dir.join("f").exists());
        // A lid that moves (away, slowly) may free the region later: the run goes on, and its
        // end says which inserter placed nothing of what was due (the counts: ⌊rate t⌋ capped,
        // and `keep`).
        v["walls"][2]["velocity"] = serde_json::json!([0, 0.001]);
        let file = write(&dir, "moving.json", &v);
        let out = dir.join("m");
        let (code, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"]);
        assert_eq!(code, 0, "{err}");
        assert!(!out.join("inserted.csv").exists() || csv(&out.join("inserted.csv")).is_empty());
        let w = warnings(&out);
        // insert[0]: 200/s from 0.01 s to 0.2 s, capped at 100: ⌊200 × 0.19⌋ = 38.
        for (k, due) in [(0, 38), (1, 40), (2, 20)] {
            let want = format!("insert[{k}] placed no body of the {due} due by t = 0.2 s");
            assert!(w.iter().any(|x| x.starts_with(&want)), "{want}: {w:?}");
            assert!(err.contains(&want), "{err}");
        }
    }

    #[test]
    fn a_scene_filled_only_by_insertion_has_a_finite_critical_step_and_its_warning() {
        let dir = scratch("insertion_only");
        let mut v = pouring();
        v["bodies"] = serde_json::json!([]);
        v["duration"] = 0.01.into();
        // The same scene with its inserters' extreme bodies given as bodies (each inserter's
        // smallest and largest size at its smallest and largest aspect ratio): the same
        // a-priori step.
        let mut listed = v.clone();
        let pi = std::f64::consts::PI;
        let mut bodies = Vec::new();
        for (k, ins) in v["insert"].as_array().unwrap().iter().enumerate() {
            let range = |key: &str| -> (f64, f64) {
                match &ins[key] {
                    Value::Null => (1.0, 1.0),
                    Value::Number(n) => (n.as_f64().unwrap(), n.as_f64().unwrap()),
                    d => {
                        let xs: Vec<f64> = d
                            .get("uniform")
                            .or_else(|| d.get("choice"))
                            .unwrap()
                            .as_array()
                            .unwrap()
                            .iter()
                            .map(|x| x.as_f64().unwrap())
                            .collect();
                        (
                            xs.iter().copied().fold(f64::INFINITY, f64::min),
                            xs.iter().copied().fold(0.0, f64::max),
                        )
                    }
                }
            };
            let ((r0, r1), (a0, a1)) = (range("size"), range("aspect"));
            for (r, a) in [(r0, a0), (r0, a1), (r1, a0), (r1, a1)] {
                let shape = match ins["shape"].as_str() {
                    Some("ellipse") => {
                        serde_json::json!({"type": "ellipse", "a": r * a.sqrt(), "b": r / a.sqrt()})
                    }
                    Some("rectangle") => {
                        serde_json::json!({"type": "rectangle", "w": r * (pi * a).sqrt(), "h": r * (pi / a).sqrt()})
                    }
                    _ => serde_json::json!({"type": "circle", "r": r}),
                };
                let mut b = serde_json::json!({"shape": shape, "position": [-5.0 + 3.0 * k as f64, 30.0 + 3.0 * bodies.len() as f64]});
                for key in ["density", "material"] {
                    if !ins[key].is_null() {
                        b[key] = ins[key].clone();
                    }
                }
                bodies.push(b);
            }
        }
        listed["bodies"] = Value::Array(bodies);
        listed.as_object_mut().unwrap().remove("insert");
        let mut dt = Vec::new();
        for (name, v) in [("inserted", &v), ("listed", &listed)] {
            let file = write(&dir, &format!("{name}.json"), v);
            let out = dir.join(name);
            let (code, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"]);
            assert_eq!(code, 0, "{name}: {err}");
            dt.push(
                summary(&out)["dt_critical"]
                    .as_f64()
                    .expect("a finite step"),
            );
        }
        assert!(dt[0].is_finite() && dt[0] > 0.0, "{dt:?}");
        assert_eq!(dt[0], dt[1], "insertion against the same bodies listed");
        // Δt above it is warned of, as for bodies listed in the case.
        v["dt"] = (2.0 * dt[0]).into();
        let file = write(&dir, "coarse.json", &v);
        let out = dir.join("coarse");
        let (_, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"]);
        assert!(
            err.contains("exceeds the critical time step estimated"),
            "{err}"
        );
    }
}

/// Issue 41's fuzzing round (`dem2d-lab fuzz`): an insertion region across the seam of a
/// periodic cell placed bodies at x < 0 and left them there, outside the cell, unwrapped (exit
/// 0, no word). Now an inserted body is brought into the cell as a case's bodies are, its image
/// counts keeping where it was placed.
mod bug_bodies_inserted_across_a_periodic_seam_ran_outside_the_cell {
    use super::*;

    #[test]
    fn every_inserted_body_is_in_the_cell_and_unwraps_to_where_its_region_put_it() {
        let dir = scratch("insert_across_seam");
        // The guide's cell periodic in x (8 cm wide, floor at 0, lid at 10), with an inserter
        // whose region [-2, 2] × [5, 8] straddles the seam x = 0: 20 disks at once (as many as
        // find a place), at rest.
        let lx = 8.0;
        let v = serde_json::json!({
            "version": 1, "name": "insert_across_seam", "units": "cm",
            "gravity": [0, -980], "dt": 1e-5, "duration": 0.01, "output_every": 100,
            "cell": { "size": [lx, 10], "periodic": "x" },
            "contact": { "model": "linear", "kn_over_rho_g": 36400, "restitution": 0.5,
                         "friction": 0.5 },
            "walls": [ { "point": [0, 0], "normal": [0, 1] },
                       { "point": [0, 10], "normal": [0, -1] } ],
            "bodies": [ { "shape": {"type": "circle", "r": 0.6}, "position": [4, 1] } ],
            "insert": [ { "region": [-2, 2, 5, 8], "count": 20, "size": 0.3, "seed": 3 } ]
        });
        let file = write(&dir, "case.json", &v);
        let out = dir.join("run");
        let (code, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"]);
        assert_eq!(code, 0, "{err}");
        let inserted = csv(&out.join("inserted.csv"));
        // (Each body tries 100 places: a few of the 20 may find none in the crowded region.)
        let n = inserted.len();
        assert!((10..=20).contains(&n), "{n} inserted");
        let rows = csv(&out.join("trajectory.csv"));
        let mut across = 0;
        for ins in &inserted {
            let id = ins["body"];
            let r = ins["r"];
            let mine: Vec<_> = rows.iter().filter(|row| row["body"] == id).collect();
            assert!(!mine.is_empty(), "body {id} in no frame");
            for row in &mine {
                // In the cell, and (a disk at rest in x, falling freely: nothing touches it in
                // 0.01 s) unwrapping to a place whose disk lies inside the region.
                assert!((0.0..lx).contains(&row["x"]), "body {id}: x = {}", row["x"]);
                let x = row["x"] + row["ix"] * lx;
                assert!(
                    (-2.0 + r..=2.0 - r).contains(&x),
                    "body {id}: unwrapped x = {x}, outside the region [-2, 2] less its radius"
                );
                assert_eq!(row["vx"], 0.0);
            }
            if mine[0]["ix"] != 0.0 {
                across += 1;
            }
        }
        // The seed places some bodies left of the seam (unwrapped x < 0): the case is tested.
        assert!(
            across > 0 && across < n,
            "{across} of {n} placed left of the seam"
        );
    }
}

/// Issue 41's fuzzing round: a state already at the end of its case's duration was refused
/// (exit 2) with a message that named neither a field nor an option of the file; it now names
/// the field `duration` (or the option `--duration`, when the command line gave one).
mod bug_a_finished_state_was_refused_naming_no_field {
    use super::*;

    #[test]
    fn the_refusal_names_the_duration_field_or_option() {
        let dir = scratch("finished_state");
        let mut v = settle3();
        v["duration"] = 0.001.into();
        v.as_object_mut().unwrap().remove("quiescence");
        let file = write(&dir, "case.json", &v);
        let out = dir.join("run");
        let (code, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"]);
        assert_eq!(code, 0, "{err}");
        let state = out.join("state.json");
        let state = state.to_str().unwrap();
        let again = dir.join("again");
        let (code, _, err) = dem2d(&["run", state, "--out", again.to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains("field `duration`: the state is at step"),
            "{err}"
        );
        assert!(!again.exists());
        let (code, _, err) = dem2d(&[
            "run",
            state,
            "--out",
            again.to_str().unwrap(),
            "--duration",
            "0.001",
        ]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("--duration: the state is at step"), "{err}");
    }
}

/// Issue 41's fuzzing round: an inserter given `"attempts": 1000000000` hung the run (no exit in
/// 10 s, and none in sight): each of its bodies that found no place tried a billion positions,
/// each against every body, at every retry. `attempts` is now at most 1e6 (the case-file page's
/// range), a larger count refused naming the field.
mod bug_a_billion_insertion_attempts_hung_the_run {
    use super::*;

    #[test]
    fn attempts_above_a_million_are_refused_and_a_million_runs() {
        let dir = scratch("attempts");
        let mut v = pouring();
        v["duration"] = 0.02.into();
        v["insert"][0]["attempts"] = 1_000_000_000u64.into();
        let file = write(&dir, "billion.json", &v);
        let out = dir.join("billion");
        let (code, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains("field `insert[0].attempts`: 1000000000 tries per body is more than the 1000000 accepted"),
            "{err}"
        );
        assert!(!out.exists());
        // The largest accepted count runs (its bodies find places in their first tries).
        v["insert"][0]["attempts"] = 1_000_000u64.into();
        let file = write(&dir, "million.json", &v);
        let out = dir.join("million");
        let (code, _, err) = dem2d(&["run", &file, "--out", out.to_str().unwrap(), "--quiet"]);
        assert_eq!(code, 0, "{err}");
        assert!(!csv(&out.join("inserted.csv")).is_empty());
    }
}

/// Issue 41's fuzzing (found by hand beside it): an inserter at 1e12 bodies per second asked
/// for 2e7 bodies in one step, each tested against every other, and never finished its first
/// step (a SIGTERM could not stop it between steps). More than 1e5 bodies in one step is
/// refused, naming the field; 1e5 in a step is accepted.
mod bug_an_inserter_asking_millions_of_bodies_per_step_hung_the_run {
    use super::*;

    #[test]
    fn a_rate_or_count_above_1e5_per_step_is_refused_naming_it() {
        let dir = scratch("per_step");
        let mut v = pouring();
        let dt = v["dt"].as_f64().unwrap();
        v["insert"][0]["rate"] = (1e12).into();
        let file = write(&dir, "fast.json", &v);
        let (code, _, err) = dem2d(&["run", &file, "--out", dir.join("fast").to_str().unwrap()]);
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains("field `insert[0].rate`") && err.contains("per step"),
            "{err}"
        );
        // Half the limit per step: read (the case is checked, not run).
        v["insert"][0]["rate"] = (5e4 / dt).into();
        let text = serde_json::to_string(&v).unwrap();
        assert!(dem2d::scene::Case::from_json(&text).is_ok());
    }
}

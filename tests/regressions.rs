//! Regressions of issue 29 ("Nothing silent, nothing stale"): what a fuzzing pass and a new user
//! found. One module per bug, named after it; its doc says what went wrong and what happens now.
//! Each test checks what the user sees (exit code, message, files) against an answer that does
//! not come from the code under test: a closed form, a force balance, the bytes of a file.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_dem2d")
}

/// Runs dem2d: (exit code, stdout, stderr).
fn dem2d(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(bin()).args(args).output().expect("run dem2d");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

fn case(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name)
        .to_str()
        .unwrap()
        .to_string()
}

/// An empty scratch directory of this test.
fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("regressions")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
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

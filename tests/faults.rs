//! Faults around a run (issue 11): signals, a re-run into the same directory, a full disk, a
//! full standard output, an endless input, a case name that is a path, bodies overlapping at the
//! start, and the status every run ends with. Each is a test of what the user sees: the exit
//! code, the message, `summary.json` and the CSV files left behind.

use serde_json::Value;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{bin, dem2d, scratch_path, signal};

fn case(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name)
        .to_str()
        .unwrap()
        .to_string()
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// Every line of a CSV file is whole: the file ends with a newline and every row has the
/// header's number of fields, each a number or empty (a value the row does not carry:
/// increments.csv's unbalanced ratio off the output steps, read as NaN). Returns the rows.
fn whole_csv(file: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(file).unwrap();
    assert!(text.ends_with('\n'), "{} ends mid-line", file.display());
    let mut lines = text.lines();
    let width = lines.next().unwrap().split(',').count();
    lines
        .enumerate()
        .map(|(k, l)| {
            let row: Vec<f64> = l
                .split(',')
                .map(|v| {
                    if v.is_empty() {
                        return f64::NAN;
                    }
                    v.parse()
                        .unwrap_or_else(|e| panic!("{} line {}: {e}", file.display(), k + 2))
                })
                .collect();
            assert_eq!(row.len(), width, "{} line {}: {l}", file.display(), k + 2);
            row
        })
        .collect()
}

/// Waits until the run in `dir` has written its first summary (status `running`) and then a
/// little longer, so that it is inside its step loop.
fn wait_until_running(child: &mut Child, dir: &Path) {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        // (The writers are made after the first summary: on a loaded machine a run can take
        // half a second between the two, and one killed there has no trajectory to draw.)
        if let Ok(text) = std::fs::read_to_string(dir.join("summary.json"))
            && text.contains("\"running\"")
            && dir.join("trajectory.csv").exists()
        {
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it was signalled"
        );
        assert!(Instant::now() < deadline, "the run never started");
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(400));
}

/// A long run (10⁴ disks settling, minutes) stopped by `sig`: exit code, status, whole lines.
fn interrupted_by(sig: &str, name: &str, code: i32) {
    let dir = scratch_path(&format!("signal_{name}"));
    let mut child = Command::new(bin())
        .args([
            "run",
            &case("settle_disks_10k.json"),
            "--out",
            dir.to_str().unwrap(),
            "--quiet",
            "--threads",
            "1",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_until_running(&mut child, &dir);
    signal(&child, sig);
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(code), "{sig}: {err}");
    assert!(err.contains(&format!("interrupted by {name}")), "{err}");
    let s = summary(&dir);
    assert_eq!(s["status"], "interrupted", "{sig}");
    let steps = s["steps"].as_u64().unwrap();
    assert!(steps > 0 && steps < 400_000, "{steps}");
    let traj = whole_csv(&dir.join("trajectory.csv"));
    let incs = whole_csv(&dir.join("increments.csv"));
    // The last rows are the state after the last whole step, as the summary says.
    assert_eq!(traj.last().unwrap()[0], steps as f64);
    assert_eq!(traj.len() % 10_000, 0, "whole frames of 10⁴ bodies");
    assert_eq!(incs.last().unwrap()[0], steps as f64);
    assert_eq!(
        traj.last().unwrap()[3],
        s["final"][9999]["x"].as_f64().unwrap()
    );
}

#[test]
fn sigint_and_sigterm_stop_after_a_whole_step() {
    interrupted_by("-INT", "SIGINT", 130);
    interrupted_by("-TERM", "SIGTERM", 143);
}

#[test]
fn a_run_into_a_directory_of_an_earlier_run_is_refused_or_replaces_it_whole() {
    let dir = scratch_path("rerun");
    let d = dir.to_str().unwrap();
    let settle = case("settle3_dt1e-5.json");
    let (code, _, err) = dem2d(&["run", &settle, "--out", d, "--quiet", "--max-steps", "300"]);
    assert_eq!(code, 0, "{err}");
    let first = std::fs::read(dir.join("trajectory.csv")).unwrap();
    assert_eq!(summary(&dir)["status"], "max_steps");
    // Without --overwrite: refused, exit 2, nothing touched.
    let (code, out, err) = dem2d(&["run", &settle, "--out", d, "--quiet"]);
    assert_eq!(code, 2, "{err}");
    assert!(out.is_empty());
    assert!(
        err.contains("holds the outputs of an earlier run") && err.contains("--overwrite"),
        "{err}"
    );
    assert_eq!(std::fs::read(dir.join("trajectory.csv")).unwrap(), first);
    assert_eq!(summary(&dir)["steps"], 300);
    // With --overwrite: the new run's files only.
    let (code, _, err) = dem2d(&[
        "run",
        &settle,
        "--out",
        d,
        "--quiet",
        "--max-steps",
        "100",
        "--overwrite",
    ]);
    assert_eq!(code, 0, "{err}");
    let s = summary(&dir);
    assert_eq!(
        (s["steps"].as_u64(), s["status"].as_str()),
        (Some(100), Some("max_steps"))
    );
    assert_eq!(
        whole_csv(&dir.join("trajectory.csv")).last().unwrap()[0],
        100.0
    );
    // A re-run killed outright (SIGKILL, no chance to write anything) leaves a summary saying
    // `running` — never the earlier run's complete summary beside the new case.json and CSVs.
    let mut child = Command::new(bin())
        .args([
            "run",
            &case("settle_disks_10k.json"),
            "--out",
            d,
            "--quiet",
            "--threads",
            "1",
            "--overwrite",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_until_running(&mut child, &dir);
    child.kill().unwrap();
    child.wait().unwrap();
    let s = summary(&dir);
    assert_eq!(s["status"], "running");
    assert_eq!(s["name"], "settle_disks_10k");
    // `plot` draws it, but says that the run did not finish.
    let (code, _, err) = dem2d(&["plot", d, "--kind", "quiescence"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("status is `running`"), "{err}");
}

#[test]
fn a_full_disk_stops_the_run_with_the_file_named_and_whole_lines() {
    // RLIMIT_FSIZE (ulimit -f) with SIGXFSZ ignored makes every write beyond the limit fail with
    // EFBIG, as a full disk fails with ENOSPC; no privileges needed. A 1-body case writes about
    // 150 000 increment rows (10 MB); the limit is 400 blocks (200 or 400 KB), so that a few
    // buffers of rows are written before one fails part-way.
    let dir = scratch_path("full_disk");
    let script = format!(
        "trap '' XFSZ; ulimit -f 400 && exec \"$0\" run {} --out {} --quiet",
        case("throw_circle.json"),
        dir.display()
    );
    let out = Command::new("sh")
        .args(["-c", &script, bin()])
        .output()
        .unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("increments.csv: cannot write"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let s = summary(&dir);
    assert_eq!(s["status"], "io_error");
    assert!(
        s["error"].as_str().unwrap().contains("increments.csv"),
        "{}",
        s["error"]
    );
    let incs = whole_csv(&dir.join("increments.csv"));
    assert!(
        incs.len() > 1000,
        "{} rows before the disk filled",
        incs.len()
    );
    // The trajectory, which did not fill, holds every row up to the step the run stopped at.
    let traj = whole_csv(&dir.join("trajectory.csv"));
    assert_eq!(traj.last().unwrap()[0], s["steps"].as_f64().unwrap());
}

#[test]
fn a_full_standard_output_is_an_error_for_every_command() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        eprintln!("no /dev/full here: skipped");
        return;
    };
    let dir = scratch_path("stdout_full");
    let d = dir.to_str().unwrap();
    let settle = case("settle3_dt1e-5.json");
    let runs: [&[&str]; 3] = [
        &["run", &settle, "--out", d, "--quiet"],
        &["plot", d],
        &["generate", "--shape", "disks", "--n", "10"],
    ];
    for args in runs {
        let out = Command::new(bin())
            .args(args)
            .stdout(full.try_clone().unwrap())
            .output()
            .unwrap();
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.contains("standard output: cannot write"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    // The run itself completed; only its one-line report could not be printed.
    assert_eq!(summary(&dir)["status"], "at_rest");
}

#[test]
fn an_endless_case_file_is_refused_at_the_size_limit() {
    if !Path::new("/dev/zero").exists() {
        eprintln!("no /dev/zero here: skipped");
        return;
    }
    let dir = scratch_path("dev_zero");
    let (code, _, err) = dem2d(&["run", "/dev/zero", "--out", dir.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("/dev/zero: larger than 256 MiB"), "{err}");
    assert!(!dir.exists());
}

#[test]
fn a_case_name_is_only_a_file_name_under_runs() {
    // Without --out, the name `../../escape` must give runs/_._.._escape, inside the working
    // directory; an absolute name likewise.
    let work = scratch_path("names");
    std::fs::create_dir_all(&work).unwrap();
    let text = std::fs::read_to_string(case("settle3_dt1e-5.json")).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    for (name, dir) in [("../../escape", "_._.._escape"), ("/tmp/abs", "_tmp_abs")] {
        v["name"] = Value::from(name);
        let file = work.join("case.json");
        std::fs::write(&file, serde_json::to_string(&v).unwrap()).unwrap();
        let out = Command::new(bin())
            .args([
                "run",
                file.to_str().unwrap(),
                "--quiet",
                "--max-steps",
                "10",
            ])
            .current_dir(&work)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(work.join("runs").join(dir).join("summary.json").exists());
    }
    let above = work.parent().unwrap().parent().unwrap();
    assert!(!above.join("escape").exists(), "wrote outside runs/");
    let entries: Vec<_> = std::fs::read_dir(work.join("runs"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(entries.len(), 2, "{entries:?}");
}

#[test]
fn bodies_overlapping_at_the_start_are_named_in_a_warning() {
    // The same ellipse listed twice (coincident: depth 2b along the minor axis) and a circle
    // below the floor.
    let text = r#"{"version": 1, "name": "overlap", "gravity": [0, -980], "dt": 1e-5, "duration": 0.001,
      "contact": {"model": "linear", "kn_over_rho_g": 36400, "restitution": 0.5, "friction": 0.3},
      "walls": [{"point": [0, 0], "normal": [0, 1]}],
      "bodies": [{"shape": {"type": "ellipse", "a": 1.5, "b": 1.0}, "position": [0, 5]},
                 {"shape": {"type": "ellipse", "a": 1.5, "b": 1.0}, "position": [0, 5]},
                 {"shape": {"type": "circle", "r": 1.0}, "position": [10, 0.5]},
                 {"shape": {"type": "circle", "r": 1.0}, "position": [20, 3]}]}"#;
    let dir = scratch_path("overlap");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("case.json");
    std::fs::write(&file, text).unwrap();
    let out = dir.join("out");
    let (code, _, err) = dem2d(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let s = summary(&out);
    let warnings: Vec<&str> = s["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap())
        .collect();
    let w = warnings
        .iter()
        .find(|w| w.contains("overlap at the start"))
        .unwrap_or_else(|| panic!("{warnings:?}"));
    assert!(w.starts_with("2 pairs overlap at the start"), "{w}");
    // Deepest first: the coincident ellipses, as deep as their whole width along the contact
    // normal, between 2b and 2a (2 and 3 × the inscribed radius b = 1).
    let first = w.split(": ").nth(1).unwrap();
    assert!(first.starts_with("bodies 0 and 1 by δ = "), "{w}");
    let ratio: f64 = first
        .split(" (")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((2.0..=3.0).contains(&ratio), "{w}");
    assert!(
        w.contains("body 2 and wall 0 by δ = 5.000e-1 (0.500 × the smaller inscribed radius)"),
        "{w}"
    );
    assert!(err.contains(w), "the warning goes to stderr too: {err}");
    assert_eq!(s["status"], "completed");
}

#[test]
fn a_case_file_with_a_byte_order_mark_runs_as_without() {
    let dir = scratch_path("bom");
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(case("settle3_dt1e-5.json")).unwrap();
    let file = dir.join("bom.json");
    std::fs::write(&file, format!("\u{feff}{text}")).unwrap();
    let (a, b) = (dir.join("a"), dir.join("b"));
    for (f, out) in [
        (file.to_str().unwrap().to_string(), &a),
        (case("settle3_dt1e-5.json"), &b),
    ] {
        let (code, _, err) = dem2d(&["run", &f, "--out", out.to_str().unwrap(), "--quiet"]);
        assert_eq!(code, 0, "{err}");
    }
    assert_eq!(
        std::fs::read(a.join("trajectory.csv")).unwrap(),
        std::fs::read(b.join("trajectory.csv")).unwrap()
    );
}

#[test]
fn every_way_a_run_ends_has_its_status_and_exit_code() {
    let dir = scratch_path("statuses");
    let run = |case_file: &str, out: &str, extra: &[&str]| {
        let out = dir.join(out);
        let mut args = vec!["run", case_file, "--out", out.to_str().unwrap(), "--quiet"];
        args.extend_from_slice(extra);
        let (code, stdout, err) = dem2d(&args);
        (code, stdout, err, summary(&out))
    };
    let (code, stdout, _, s) = run(&case("settle3_dt1e-5.json"), "rest", &[]);
    assert_eq!((code, s["status"].as_str()), (0, Some("at_rest")));
    assert!(stdout.contains("at rest at step 7493"), "{stdout}");
    let (code, stdout, _, s) = run(
        &case("settle3_dt1e-5.json"),
        "short",
        &["--max-steps", "50"],
    );
    assert_eq!((code, s["status"].as_str()), (0, Some("max_steps")));
    assert!(
        stdout.contains("50 steps (stopped by --max-steps)"),
        "{stdout}"
    );
    // No quiescence in the case: the one-line report has no dangling separator.
    let (code, stdout, _, s) = run(&case("drop_rebound_mu01.json"), "full", &[]);
    assert_eq!((code, s["status"].as_str()), (0, Some("completed")));
    assert!(stdout.contains("t = 1.2 s; wall time"), "{stdout}");
    assert!(!stdout.contains(", ;"), "{stdout}");
    // Times in the CSVs are step × dt in decimal: 0.009, not 0.009000000000000001.
    let traj = std::fs::read_to_string(dir.join("full").join("trajectory.csv")).unwrap();
    assert!(traj.contains("\n900,0.009,0,"), "{}", &traj[..300]);
    assert!(!traj.contains("00000000000001,"));
    assert_eq!(s["time"], 1.2);
}

/// Issue 41, items 4 and 5, off the beaten path: a run whose bodies come and go (the guide's
/// pouring example: insertion of three shapes, an outflow region), with VTK frames, stopped part
/// way and continued from its `state.json` with VTK again — the continued writer starts from a
/// world of inserted bodies, some removed (it panicked at the first inserted body, and drew
/// bodies by index). Every frame of both parts has one body cell per row of the trajectory at
/// its step, named by the same identities in the same order.
#[test]
fn a_pouring_run_with_vtk_continued_from_its_state_draws_the_bodies_it_holds() {
    let dir = scratch_path("pour_vtk_restart");
    std::fs::create_dir_all(&dir).unwrap();
    let page = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/src/reference/case-file.md"),
    )
    .unwrap();
    let pouring = page
        .split("```json\n")
        .skip(1)
        .map(|b| b.split("```").next().unwrap())
        .find(|b| b.contains("\"name\": \"pouring\""))
        .unwrap();
    let file = dir.join("pouring.json");
    std::fs::write(&file, pouring).unwrap();
    let (first, second) = (dir.join("first"), dir.join("second"));
    let (code, _, err) = dem2d(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        first.to_str().unwrap(),
        "--quiet",
        "--max-steps",
        "8000",
        "--vtk-every",
        "1000",
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = dem2d(&[
        "run",
        first.join("state.json").to_str().unwrap(),
        "--out",
        second.to_str().unwrap(),
        "--quiet",
        "--vtk-every",
        "1000",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let mut checked = 0;
    for run in [&first, &second] {
        let traj = whole_csv(&run.join("trajectory.csv"));
        let mut frames: Vec<_> = std::fs::read_dir(run.join("vtk"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        frames.sort();
        for f in frames {
            let a = common::vtu_arrays(&std::fs::read_to_string(&f).unwrap());
            let step = common::i64s(&a["STEP"])[0] as f64;
            let want: Vec<i64> = traj
                .iter()
                .filter(|r| r[0] == step)
                .map(|r| r[2] as i64)
                .collect();
            let kinds = common::i32s(&a["kind"]);
            let ids = common::i64s(&a["id"]);
            let got: Vec<i64> = (0..kinds.len())
                .filter(|&c| kinds[c] == 0)
                .map(|c| ids[c])
                .collect();
            assert_eq!(got, want, "{}: step {step}", f.display());
            checked += 1;
        }
    }
    // 0, 1000, …, 8000 and the continued run's 8000, 9000, 10000.
    assert_eq!(checked, 12);
    assert!(first.join("discharge.csv").exists());
}

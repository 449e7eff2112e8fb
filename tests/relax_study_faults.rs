//! Faults around `dem2d relax` and `dem2d study` (issue 41, item 7): like `dem2d run`, each
//! holds its output directory's lock (`DIR/.dem2d.lock`), so that a second relaxation, a run or
//! a second study into the same directory is refused (exit code 2, the message naming the lock
//! and its holder) and nothing of the first is touched; and SIGINT or SIGTERM end each with exit
//! code 130 or 143 and a message — a relaxation after writing the state it reached (status
//! `interrupted` in `relax.json` and `state.json`), which `dem2d run` continues from.
//! Each test spawns the binary, signals it with `kill`, and checks what the user sees: the exit
//! code, the message, the files left behind.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{bin, case_path, dem2d, scratch, signal};

/// A frictionless pile of 10 000 disks under gravity, between walls (`dem2d generate`): its
/// relaxation to a residual of 1e-15 takes minutes, so that it is still running when signalled.
fn pile(dir: &Path) -> PathBuf {
    let file = dir.join("pile.json");
    let (code, _, err) = dem2d(&[
        "generate",
        "--shape",
        "disks",
        "--n",
        "10000",
        "--friction",
        "0",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    file
}

/// `dem2d ARGS` started in the repository's root, its standard error kept.
fn spawn(args: &[&str]) -> Child {
    Command::new(bin())
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// A long relaxation of `case` into `out` (one thread).
fn long_relax(case: &Path, out: &Path) -> Child {
    spawn(&[
        "relax",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--tolerance",
        "1e-15",
        "--max-iterations",
        "1000000000",
        "--threads",
        "1",
    ])
}

/// Waits until `child` holds the lock of `dir` (its lock file names its process), then a little
/// longer, so that it is at work.
fn wait_for_lock(child: &mut Child, dir: &Path) {
    let deadline = Instant::now() + Duration::from_secs(120);
    let me = format!("process {},", child.id());
    loop {
        if std::fs::read_to_string(dir.join(".dem2d.lock")).is_ok_and(|t| t.contains(&me)) {
            break;
        }
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            use std::io::Read;
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut err)
                .unwrap();
            panic!("it ended ({status}) before it took the lock: {err}");
        }
        assert!(Instant::now() < deadline, "it never took the lock");
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(500));
}

/// Waits for `child`: its exit code and standard error.
fn finish(child: Child) -> (Option<i32>, String) {
    let out = child.wait_with_output().unwrap();
    (out.status.code(), String::from_utf8(out.stderr).unwrap())
}

fn json(file: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(file).unwrap())
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}

/// A relaxation stopped by `sig`: exit code `code`, a message naming the signal, the state
/// reached written (status `interrupted`), continued by `dem2d run`, and no lock left.
fn relax_interrupted_by(sig: &str, name: &str, code: i32) {
    let dir = scratch(&format!("relax_{name}"));
    let case = pile(&dir);
    let out = dir.join("relaxed");
    let mut child = long_relax(&case, &out);
    wait_for_lock(&mut child, &out);
    signal(&child, sig);
    let (exit, err) = finish(child);
    assert_eq!(exit, Some(code), "{sig}: {err}");
    assert!(
        err.contains(&format!("interrupted by {name} after"))
            && err.contains("state reached")
            && err.contains(out.join("state.json").to_str().unwrap()),
        "{err}"
    );
    let summary = json(&out.join("relax.json"));
    assert_eq!(summary["status"], "interrupted", "{summary}");
    assert_eq!(summary["signal"], name, "{summary}");
    let iterations = summary["iterations"].as_u64().unwrap();
    assert!(iterations > 0, "{summary}");
    let state = json(&out.join("state.json"));
    assert_eq!(
        state["state"]["status"], "interrupted",
        "{}",
        state["state"]
    );
    assert!(!out.join(".dem2d.lock").exists(), "the lock is released");
    // The state reached is a state to continue from.
    let run = dir.join("continued");
    let (c, _, e) = dem2d(&[
        "run",
        out.join("state.json").to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--max-steps",
        "2",
        "--quiet",
        "--threads",
        "1",
    ]);
    assert_eq!(c, 0, "{e}");
}

#[test]
fn sigint_and_sigterm_stop_a_relaxation_with_the_state_reached_written() {
    relax_interrupted_by("-INT", "SIGINT", 130);
    relax_interrupted_by("-TERM", "SIGTERM", 143);
}

#[test]
fn a_second_relaxation_into_a_directory_being_written_is_refused_naming_the_lock() {
    let dir = scratch("two_relaxations");
    let case = pile(&dir);
    let out = dir.join("relaxed");
    let mut first = long_relax(&case, &out);
    wait_for_lock(&mut first, &out);
    // The second, into the same directory (with --overwrite: the lock, not the files, stops it).
    let (code, _, err) = dem2d(&[
        "relax",
        case_path("jammed_disks_256.json").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--overwrite",
        "--threads",
        "1",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(out.join(".dem2d.lock").to_str().unwrap())
            && err.contains(&format!("process {}", first.id()))
            && err.contains("dem2d relax, case `settle_disks_mu0_10k`"),
        "{err}"
    );
    assert!(
        !out.join("relax.json").exists(),
        "nothing written by the second"
    );
    // The first goes on, and ends as a SIGTERM ends it.
    assert!(first.try_wait().unwrap().is_none(), "the first still runs");
    signal(&first, "-TERM");
    let (exit, err) = finish(first);
    assert_eq!(exit, Some(143), "{err}");
    assert_eq!(json(&out.join("relax.json"))["status"], "interrupted");
}

#[test]
fn a_relaxation_into_the_directory_of_a_run_under_way_is_refused() {
    let dir = scratch("relax_into_run");
    let run = dir.join("run");
    let mut child = spawn(&[
        "run",
        case_path("settle_disks_10k.json").to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--quiet",
        "--threads",
        "1",
    ]);
    wait_for_lock(&mut child, &run);
    let (code, _, err) = dem2d(&[
        "relax",
        case_path("jammed_disks_256.json").to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(run.join(".dem2d.lock").to_str().unwrap())
            && err.contains("case `settle_disks_10k`"),
        "{err}"
    );
    assert!(!run.join("relax.json").exists());
    signal(&child, "-INT");
    let (exit, err) = finish(child);
    assert_eq!(exit, Some(130), "{err}");
    // And the other way round: a run into a relaxation's directory under way is refused.
    let case = pile(&dir);
    let out = dir.join("relaxed");
    let mut relax = long_relax(&case, &out);
    wait_for_lock(&mut relax, &out);
    let (code, _, err) = dem2d(&[
        "run",
        case_path("settle3_dt1e-5.json").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(".dem2d.lock") && err.contains("dem2d relax"),
        "{err}"
    );
    signal(&relax, "-INT");
    assert_eq!(finish(relax).0, Some(130));
}

/// A jamming study of one packing of 256 ellipses α = 2 (about 45 s) into `out`.
fn study(out: &Path) -> Child {
    spawn(&[
        "study",
        "jamming",
        "--aspects",
        "2",
        "--packings",
        "1",
        "--threads",
        "1",
        "--out",
        out.to_str().unwrap(),
    ])
}

#[test]
fn a_study_holds_its_directory_and_ends_on_a_signal_with_a_message() {
    let dir = scratch("study");
    let out = dir.join("jamming");
    for (sig, name, code) in [("-INT", "SIGINT", 130), ("-TERM", "SIGTERM", 143)] {
        let mut first = study(&out);
        wait_for_lock(&mut first, &out);
        if sig == "-INT" {
            // A second study into the same directory is refused, naming the lock.
            let second = study(&out);
            let (exit, err) = finish(second);
            assert_eq!(exit, Some(2), "{err}");
            assert!(
                err.contains(out.join(".dem2d.lock").to_str().unwrap())
                    && err.contains(&format!("process {}", first.id()))
                    && err.contains("dem2d study jamming"),
                "{err}"
            );
        }
        signal(&first, sig);
        let (exit, err) = finish(first);
        assert_eq!(exit, Some(code), "{sig}: {err}");
        assert!(
            err.contains(&format!("study jamming: interrupted by {name}"))
                && err.contains("not written"),
            "{err}"
        );
        assert!(!out.join(".dem2d.lock").exists(), "the lock is released");
        assert!(
            !out.join("jamming.md").exists(),
            "no table of a study cut short"
        );
    }
}

//! Checkpoints (`dem2d run --checkpoint-every N`, issue 44): a run killed outright — SIGKILL, no
//! chance to write anything — continues from the last `state.json` it rewrote, and the continued
//! run's rows, summary and final state are the uninterrupted run's, byte for byte.

use serde_json::Value;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{bin, case_path, dem2d, scratch};

fn json(path: &Path) -> Option<Value> {
    serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()
}

/// The rows of a CSV whose step (first column) lies in `(after, upto]`.
fn rows(path: &Path, after: u64, upto: u64) -> Vec<String> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .filter(|l| {
            let s: u64 = l.split(',').next().unwrap().parse().unwrap();
            s > after && s <= upto
        })
        .map(str::to_string)
        .collect()
}

fn run_ok(args: &[&str]) {
    let (code, out, err) = dem2d(args);
    assert_eq!(code, 0, "dem2d {args:?}: {out}{err}");
}

#[test]
fn a_run_killed_outright_continues_from_its_last_checkpoint_as_if_never_stopped() {
    let dir = scratch("killed");
    // 2000 ellipses settling (the shipped pile), rows every 100 steps.
    let mut case = json(&case_path("settle_ellipses_bi_mu0_2k.json")).unwrap();
    case["output_every"] = 100.into();
    let file = dir.join("pile.json");
    std::fs::write(&file, case.to_string()).unwrap();
    let file = file.to_str().unwrap();
    let killed = dir.join("killed");
    let mut child = Command::new(bin())
        .args(["run", file, "--out", killed.to_str().unwrap(), "--quiet"])
        .args(["--threads", "1", "--checkpoint-every", "500"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Killed once a checkpoint past the start is on disk (read whole: it is replaced
    // atomically, never torn).
    let deadline = Instant::now() + Duration::from_secs(300);
    let at = loop {
        if let Some(s) = json(&killed.join("state.json"))
            && s["state"]["status"] == "checkpoint"
            && s["state"]["step"].as_u64().unwrap() >= 1000
        {
            break s["state"]["step"].as_u64().unwrap();
        }
        assert!(child.try_wait().unwrap().is_none(), "the run ended first");
        assert!(Instant::now() < deadline, "no checkpoint");
        std::thread::sleep(Duration::from_millis(20));
    };
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(
        json(&killed.join("summary.json")).unwrap()["status"],
        "running"
    );
    // The checkpoint may have moved on between the read and the kill: continue from the one on
    // disk now.
    let at = at.max(
        json(&killed.join("state.json")).unwrap()["state"]["step"]
            .as_u64()
            .unwrap(),
    );
    assert_eq!(at % 500, 0);
    let (rest, whole) = (dir.join("rest"), dir.join("whole"));
    let more = 1000;
    run_ok(&[
        "run",
        killed.join("state.json").to_str().unwrap(),
        "--out",
        rest.to_str().unwrap(),
        "--quiet",
        "--max-steps",
        &more.to_string(),
    ]);
    run_ok(&[
        "run",
        file,
        "--out",
        whole.to_str().unwrap(),
        "--quiet",
        "--max-steps",
        &(at + more).to_string(),
    ]);
    for csv in ["trajectory.csv", "increments.csv"] {
        let want = rows(&whole.join(csv), at, at + more);
        assert_eq!(
            want.len() as u64,
            if csv == "trajectory.csv" {
                2000 * more / 100
            } else {
                more
            }
        );
        assert_eq!(rows(&rest.join(csv), at, u64::MAX), want, "{csv}");
    }
    let (a, b) = (
        json(&whole.join("summary.json")).unwrap(),
        json(&rest.join("summary.json")).unwrap(),
    );
    for key in [
        "status",
        "steps",
        "energies",
        "final",
        "first_contact_step",
        "max_depth_ratio",
    ] {
        assert_eq!(a[key], b[key], "{key}");
    }
    assert_eq!(
        std::fs::read_to_string(whole.join("state.json")).unwrap(),
        std::fs::read_to_string(rest.join("state.json")).unwrap()
    );
}

#[test]
fn checkpoints_are_refused_at_zero_and_written_at_their_interval() {
    let dir = scratch("interval");
    let out = dir.join("o");
    let case = case_path("settle3_dt1e-5.json");
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--checkpoint-every",
        "0",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--checkpoint-every"), "{err}");
    // A run that ends normally leaves its end state, not a checkpoint.
    run_ok(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--checkpoint-every",
        "1000",
    ]);
    let s = json(&out.join("state.json")).unwrap();
    assert_eq!(s["state"]["status"], "at_rest");
}

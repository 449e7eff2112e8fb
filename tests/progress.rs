//! The progress line of a long run, as a log receives it (stderr not a terminal): the step, the
//! simulated time, steps per second, the time left and the unbalanced-force ratio, on one line.

use std::process::Command;

#[test]
fn a_long_run_logs_rate_time_left_and_the_unbalanced_ratio() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("progress");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let bin = env!("CARGO_BIN_EXE_dem2d");
    let case = dir.join("pile.json");
    let generated = Command::new(bin)
        .args([
            "generate",
            "--shape",
            "disks",
            "--n",
            "300",
            "--seed",
            "7",
            "--quiescence",
            "1e-12",
            "--out",
        ])
        .arg(&case)
        .output()
        .unwrap();
    assert!(generated.status.success());
    // More than the two seconds after which a run reports (about 4 s here on one idle core;
    // the pile's rest criterion set out of reach so that it runs them all); the first line is
    // due then, later ones every 30 s in a log.
    let out = Command::new(bin)
        .args(["run", "--max-steps", "250000", "--out"])
        .arg(dir.join("run"))
        .arg(&case)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let line = err
        .lines()
        .find(|l| l.starts_with("settle_disks_300: step "))
        .unwrap_or_else(|| panic!("no progress line in:\n{err}"));
    // e.g. `settle_disks_300: step 30368/250000 (12 %), t = 0.3037 s, 15181 steps/s, 0:03 left
    // (at most), 450 contacts, unbalanced force ratio 2.1e-1`
    let fields: Vec<&str> = line.split(", ").collect();
    assert_eq!(fields.len(), 6, "{line}");
    assert!(fields[0].contains("/250000 ("), "{line}");
    assert!(
        fields[1].starts_with("t = ") && fields[1].ends_with(" s"),
        "{line}"
    );
    assert!(fields[2].ends_with(" steps/s"), "{line}");
    assert!(fields[3].ends_with(" left (at most)"), "{line}");
    assert!(fields[4].ends_with(" contacts"), "{line}");
    let ratio: f64 = fields[5]
        .strip_prefix("unbalanced force ratio ")
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!(ratio.is_finite() && ratio >= 0.0, "{line}");
    // In a log the line is a whole line (no carriage return rewriting it in place).
    assert!(!err.contains('\r'), "{err}");
}

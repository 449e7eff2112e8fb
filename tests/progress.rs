//! The progress line of a long run, as a log receives it (stderr not a terminal): the step, the
//! simulated time, steps per second, the time left and the unbalanced-force ratio, on one line.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

#[test]
fn a_long_run_logs_rate_time_left_and_the_unbalanced_ratio() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("progress");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let bin = env!("CARGO_BIN_EXE_dem2d");
    let case = dir.join("pile.json");
    let generated = Command::new(bin)
        .args([
            "generate", "--shape", "disks", "--n", "2000", "--seed", "7", "--out",
        ])
        .arg(&case)
        .output()
        .unwrap();
    assert!(generated.status.success());
    // A run longer than the two seconds after which a run reports, read while it runs and
    // stopped once its first line has come (so the test does not depend on the machine's speed).
    let mut child = Command::new(bin)
        .args(["run", "--max-steps", "4000000", "--overwrite", "--out"])
        .arg(dir.join("run"))
        .arg(&case)
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let mut err = String::new();
    let mut line = None;
    for l in BufReader::new(child.stderr.take().unwrap()).lines() {
        let l = l.unwrap();
        err.push_str(&l);
        err.push('\n');
        if l.starts_with("settle_disks_2k: step ") {
            line = Some(l);
            break;
        }
    }
    let _ = child.kill();
    let _ = child.wait();
    let line = line.unwrap_or_else(|| panic!("no progress line in:\n{err}"));
    // e.g. `settle_disks_2k: step 30368/70000 (43 %), t = 0.3037 s, 15181 steps/s, 0:03 left
    // (at most), 450 contacts, unbalanced force ratio 2.1e-1`
    let fields: Vec<&str> = line.split(", ").collect();
    assert_eq!(fields.len(), 6, "{line}");
    assert!(
        fields[0].contains('/') && fields[0].contains(" %)"),
        "{line}"
    );
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
    assert!(!line.contains('\r') && !err.contains('\r'), "{err}");
}

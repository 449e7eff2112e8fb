//! `dem2d-lab fuzz` at a small size: 30 mutants of the newer features (periodic cells, imposed
//! pressure, Lees–Edwards shear, relax, insertion and outflow, segments, materials, wall
//! programs, restarts) give no panic, no hang, no silent nonsense and no undocumented exit, and
//! the report counts every mutant once. The fuzzer's own checks are tested too: a run it must
//! call silent (a body outside its cell) is called so. The `dem2d` binary is the one
//! `cargo test --release --workspace` built beside `dem2d-lab` (`DEM2D_BIN`).

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("fuzz")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn lab(args: &[&str]) -> (i32, String, String) {
    let lab = Path::new(env!("CARGO_BIN_EXE_dem2d-lab"));
    let dem2d = lab.with_file_name(format!("dem2d{}", std::env::consts::EXE_SUFFIX));
    assert!(
        dem2d.is_file(),
        "{}: no dem2d binary beside dem2d-lab (cargo build --release, or test the workspace)",
        dem2d.display()
    );
    let out = Command::new(lab)
        .args(args)
        .env("DEM2D_BIN", &dem2d)
        .current_dir(root())
        .output()
        .expect("run dem2d-lab");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// The `**all**` row of the report: total and the count of each class, in the report's order
/// (ok, refused, detected, PANIC, HANG, SILENT, BAD_EXIT).
fn totals(report: &str) -> Vec<usize> {
    let row = report
        .lines()
        .find(|l| l.starts_with("| **all**"))
        .expect("the report's total row");
    row.split('|')
        .skip(2)
        .filter(|c| !c.trim().is_empty())
        .map(|c| c.trim().trim_matches('*').parse().unwrap())
        .collect()
}

#[test]
fn thirty_mutants_of_the_newer_features_give_no_panic_hang_or_silent_nonsense() {
    let out = scratch("small");
    let (code, stdout, stderr) = lab(&[
        "fuzz",
        "--mutants",
        "30",
        "--seed",
        "7",
        "--max-steps",
        "600",
        "--timeout",
        "60",
        "--out",
        out.to_str().unwrap(),
    ]);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap_or_default();
    assert_eq!(code, 0, "{stdout}\n{stderr}\n{report}");
    let t = totals(&report);
    assert_eq!(t.len(), 8, "{report}");
    assert_eq!(t[0], 30, "{report}");
    assert_eq!(t[1..].iter().sum::<usize>(), 30, "{report}");
    assert_eq!(&t[4..], &[0, 0, 0, 0], "{report}");
    // The mutants reach the dynamics and the reader's refusals both.
    assert!(t[1] > 0 && t[2] > 0, "{report}");
    let list = std::fs::read_to_string(out.join("mutants.csv")).unwrap();
    assert_eq!(list.lines().count(), 31);
    // The same seed, the same mutants: mutant 3 replayed alone is the same file and outcome.
    let again = scratch("replay");
    let (code, _, stderr) = lab(&[
        "fuzz",
        "--seed",
        "7",
        "--only",
        "3",
        "--max-steps",
        "600",
        "--timeout",
        "60",
        "--out",
        again.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    // The line without its seconds, the work directory's path made the same.
    let line = |text: &str, k: &str, dir: &Path| {
        text.lines()
            .find(|l| l.starts_with(&format!("{k},")))
            .map(|l| {
                let f: Vec<&str> = l.splitn(7, ',').collect();
                let rest = f[6].replace(dir.to_str().unwrap(), "OUT");
                format!("{} {} {} {} {rest}", f[1], f[2], f[3], f[4])
            })
            .unwrap()
    };
    let replay = std::fs::read_to_string(again.join("mutants.csv")).unwrap();
    assert_eq!(line(&list, "3", &out), line(&replay, "3", &again));
}

//! `dem2d fields` on a run, against what the test computes on its own from the run's other files:
//! the packing fraction from the bodies' areas and the cell's size (`cell.csv`), the stress the
//! run measured over the whole cell at the same frames (`cell.csv`), and the imposed shear
//! profile; and the option mistakes refused with exit 2.

use std::path::Path;

mod common;
use common::{case_path, dem2d, scratch};

/// A CSV file's columns by name (an empty field is NaN).
fn columns(path: &Path) -> std::collections::HashMap<String, Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let names: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut out: std::collections::HashMap<String, Vec<f64>> =
        names.iter().map(|n| (n.clone(), Vec::new())).collect();
    for line in lines {
        for (n, v) in names.iter().zip(line.split(',')) {
            out.get_mut(n).unwrap().push(if v.is_empty() {
                f64::NAN
            } else {
                v.parse().unwrap()
            });
        }
    }
    out
}

#[test]
fn a_sheared_cells_profiles_add_up_to_the_whole_cell_and_follow_the_imposed_shear() {
    let dir = scratch("fields_shear");
    let mut case: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(case_path("shear_cell.json")).unwrap())
            .unwrap();
    case["duration"] = 1.2.into();
    let file = dir.join("shear.json");
    std::fs::write(&file, case.to_string()).unwrap();
    let run = dir.join("run");
    let (code, out, err) = dem2d(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--contacts",
        "--quiet",
        "--overwrite",
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let bins = 10;
    let (code, out, err) = dem2d(&[
        "fields",
        run.to_str().unwrap(),
        "--bins",
        &bins.to_string(),
        "--from",
        "0.4",
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let f = columns(&run.join("fields.csv"));
    assert_eq!(f["y"].len(), bins);
    let frames = f["frames"][0];
    // The frames of the window, from cell.csv: t ≥ 0.4.
    let cell = columns(&run.join("cell.csv"));
    let at: Vec<usize> = (0..cell["t"].len())
        .filter(|&k| cell["t"][k] >= 0.4)
        .collect();
    assert_eq!(at.len() as f64, frames);
    // φ: the bins (equal areas at each frame) average to the bodies' area over the cell's.
    let area: f64 = case["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| std::f64::consts::PI * b["shape"]["r"].as_f64().unwrap().powi(2))
        .sum();
    let want_phi = at
        .iter()
        .map(|&k| area / (cell["lx"][k] * cell["ly"][k]))
        .sum::<f64>()
        / at.len() as f64;
    let phi = f["phi"].iter().sum::<f64>() / bins as f64;
    assert!((phi - want_phi).abs() < 1e-12, "φ {phi} against {want_phi}");
    // σ: the bins average to the whole cell's stress as the run measured it (the contact parts
    // are the same sums; the kinetic parts differ by the bins' mean flow about the imposed one).
    let mean = |name: &str| f[name].iter().sum::<f64>() / bins as f64;
    let cell_mean = |name: &str| at.iter().map(|&k| cell[name][k]).sum::<f64>() / at.len() as f64;
    for (ours, theirs) in [("syy", "syy"), ("sxx", "sxx")] {
        let (a, b) = (mean(ours), cell_mean(theirs));
        eprintln!("{ours}: bins {a:.2}, cell {b:.2}");
        assert!(
            (a - b).abs() < 0.02 * b,
            "{ours} {a} against the cell's {b}"
        );
    }
    let (a, b) = (mean("sxy"), 0.5 * (cell_mean("sxy") + cell_mean("syx")));
    eprintln!("sxy: bins {a:.2}, cell {b:.2}");
    assert!(
        (a - b).abs() < 0.03 * b.abs(),
        "sxy {a} against the cell's {b}"
    );
    // The mean flow: γ̇ (y − L_y/2) within a tenth of γ̇ L_y in every bin, seam bins included.
    let (rate, ly) = (3.0, cell_mean("ly"));
    for (k, &y) in f["y"].iter().enumerate() {
        let want = rate * (y - 0.5 * ly);
        assert!(
            (f["vx"][k] - want).abs() < 0.1 * rate * ly,
            "bin {k}: vx {} against {want}",
            f["vx"][k]
        );
        assert!(f["temperature"][k] > 0.0 && f["nematic"][k].is_nan());
    }
    // About the imposed profile (--relative) the mean flow is gone.
    let (code, out, err) = dem2d(&[
        "fields",
        run.to_str().unwrap(),
        "--bins",
        &bins.to_string(),
        "--from",
        "0.4",
        "--relative",
        "--out",
        dir.join("relative.csv").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let r = columns(&dir.join("relative.csv"));
    for (k, vx) in r["vx"].iter().enumerate() {
        assert!(vx.abs() < 0.1 * rate * ly, "bin {k}: {vx}");
    }
}

#[test]
fn option_mistakes_are_refused_naming_the_option() {
    let dir = scratch("fields_refused");
    let run = dir.join("run");
    let (code, out, err) = dem2d(&[
        "run",
        case_path("throw_ellipse.json").to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--quiet",
        "--overwrite",
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let r = run.to_str().unwrap();
    for (args, code, says) in [
        (vec!["--bins", "0"], 2, "--bins"),
        (vec!["--bins", "4", "--range=3,1"], 2, "--range"),
        (vec!["--bins", "4", "--from", "2", "--to", "1"], 2, "--from"),
        (vec!["--bins", "4", "--from", "1e9"], 1, "no output frame"),
    ] {
        let mut all = vec!["fields", r];
        all.extend(args.iter());
        let (c, out, err) = dem2d(&all);
        assert_eq!(c, code, "{all:?}: {out}{err}");
        assert!(err.contains(says), "{all:?}: {err}");
    }
    // Without contacts.csv: written, the stress empty, and said.
    let (c, out, err) = dem2d(&["fields", r, "--bins", "4", "--axis", "x"]);
    assert_eq!(c, 0, "{out}{err}");
    assert!(
        err.contains("contacts.csv") && err.contains("--contacts"),
        "{err}"
    );
    let f = columns(&run.join("fields.csv"));
    assert!(f["sxx"].iter().all(|v| v.is_nan()));
    assert!(f["x"].len() == 4 && f["nematic"].iter().any(|v| v.is_finite()));
}

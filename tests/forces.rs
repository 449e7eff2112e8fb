//! `dem2d forces` against what the test counts on its own in `contacts.csv`, against the
//! frictionless closed form (no tangential force: a_t = 0) and the stress–fabric relation
//! `sin φ ≈ ½(a_c + a_n + a_t)` (Rothenburg & Bathurst 1989); the option mistakes refused.

use serde_json::Value;
use std::path::Path;

mod common;
use common::{case_path, dem2d, scratch};

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn ok(args: &[&str]) -> String {
    let (code, out, err) = dem2d(args);
    assert_eq!(code, 0, "dem2d {args:?}: {out}{err}");
    out
}

#[test]
fn a_sheared_cells_forces_are_those_of_its_contacts_file_and_obey_the_stress_fabric_relation() {
    let dir = scratch("forces_shear");
    let mut case = json(&case_path("shear_cell.json"));
    case["duration"] = 1.2.into();
    let file = dir.join("shear.json");
    std::fs::write(&file, case.to_string()).unwrap();
    let run = dir.join("run");
    let r = run.to_str().unwrap();
    ok(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        r,
        "--contacts",
        "--quiet",
        "--overwrite",
    ]);
    println!("{}", ok(&["forces", r, "--from", "0.4", "--bins", "30"]));
    let report = json(&run.join("forces.json"));
    // The body–body contacts with F_n > 0 at the frames from t = 0.4 s, counted here from
    // contacts.csv (`step,t,i,...`: i is -1 for a wall; fn is a column by name).
    let text = std::fs::read_to_string(run.join("contacts.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (t, i, f) = (col("t"), col("i"), col("fn"));
    let forces: Vec<f64> = lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|v| v[t].parse::<f64>().unwrap() >= 0.4 && v[i] != "-1")
        .map(|v| v[f].parse::<f64>().unwrap())
        .filter(|&x| x > 0.0)
        .collect();
    let mean = forces.iter().sum::<f64>() / forces.len() as f64;
    assert_eq!(report["contacts"].as_u64().unwrap() as usize, forces.len());
    let m = report["mean_force"].as_f64().unwrap();
    assert!((m - mean).abs() < 1e-9 * mean, "{m} against {mean}");
    // The density integrates to one over the bins, and the counts are the contacts.
    let csv = std::fs::read_to_string(run.join("forces.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 30);
    let width = 2.0 * rows[0][0];
    let total: f64 = rows.iter().map(|r| r[1] * width).sum();
    assert!((total - 1.0).abs() < 1e-12, "{total}");
    let counted: f64 = rows.iter().map(|r| r[2]).sum();
    assert_eq!(counted as usize, forces.len());
    // The largest force is in the last bin: its top is max f / ⟨f⟩.
    let top = forces.iter().copied().fold(0.0, f64::max) / mean;
    assert!((width * 30.0 - top).abs() < 1e-9 * top);
    // sin φ ≈ ½(a_c + a_n + a_t) within a tenth of sin φ in steady shear (μ ≈ 0.4).
    let (s, h) = (
        report["sin_phi"].as_f64().unwrap(),
        report["half_sum"].as_f64().unwrap(),
    );
    assert!(s > 0.2 && (s - h).abs() < 0.12 * s, "sin φ {s}, ½ Σ a {h}");
}

#[test]
fn a_relaxed_frictionless_packing_has_no_tangential_anisotropy() {
    let dir = scratch("forces_relaxed");
    let (comp, rel) = (dir.join("comp"), dir.join("rel"));
    let case = case_path("compress_cell_mu0.json");
    ok(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        comp.to_str().unwrap(),
        "--quiet",
    ]);
    let state = comp.join("state.json");
    ok(&[
        "relax",
        state.to_str().unwrap(),
        "--out",
        rel.to_str().unwrap(),
        "--quiet",
    ]);
    println!("{}", ok(&["forces", rel.to_str().unwrap()]));
    let report = json(&rel.join("forces.json"));
    assert!(report["source"].as_str().unwrap().ends_with("state.json"));
    assert!(report["contacts"].as_u64().unwrap() > 100);
    // No friction: every contact force is normal, so the tangential fit is round-off.
    let a_t = report["a_t"].as_f64().unwrap();
    assert!(a_t.abs() < 1e-12, "a_t {a_t}");
    let (s, h) = (
        report["sin_phi"].as_f64().unwrap(),
        report["half_sum"].as_f64().unwrap(),
    );
    assert!((s - h).abs() < 0.02, "sin φ {s}, ½ Σ a {h}");
    // Frames need the run's contacts.csv: refused, naming the option.
    let (code, _, err) = dem2d(&["forces", rel.to_str().unwrap(), "--frame", "0"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--frame") && err.contains("--contacts"),
        "{err}"
    );
}

#[test]
fn option_mistakes_and_missing_files_are_refused() {
    let dir = scratch("forces_refused");
    let run = dir.join("run");
    let r = run.to_str().unwrap();
    ok(&[
        "run",
        case_path("throw_ellipse.json").to_str().unwrap(),
        "--out",
        r,
        "--contacts",
        "--quiet",
        "--overwrite",
    ]);
    for (args, code, says) in [
        (vec!["--bins", "0"], 2, "--bins"),
        (vec!["--frame", "100000"], 2, "--frame"),
        (vec!["--frame=-100000"], 2, "--frame"),
        (vec!["--frame", "1", "--from", "0"], 2, "--from"),
        (vec!["--from", "1e9"], 2, "--from"),
    ] {
        let mut all = vec!["forces", r];
        all.extend(args.iter());
        let (c, out, err) = dem2d(&all);
        assert_eq!(c, code, "{all:?}: {out}{err}");
        assert!(err.contains(says), "{all:?}: {err}");
    }
    ok(&["forces", r, "--frame=-1"]);
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let (c, _, err) = dem2d(&["forces", empty.to_str().unwrap()]);
    assert_eq!(c, 1, "{err}");
    assert!(err.contains("state.json"), "{err}");
}

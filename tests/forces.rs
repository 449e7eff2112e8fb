//! `dem2d forces` against what the test counts on its own in `contacts.csv` (or by brute force
//! over the pairs of a relaxed state: the histogram, its normalisation, its tail), against the
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

/// The contact forces of the relaxed disks of a `dem2d relax` state, by brute force over all
/// pairs (nearest image in the cell as it ended, `state.cell.size`; linear law F = k_n δ, no
/// dashpot at rest): not through dem2d's contact detection.
fn relaxed_disk_forces(state: &Value) -> Vec<f64> {
    let cell = &state["state"]["cell"];
    assert_eq!(cell["offset"].as_f64(), Some(0.0), "no Lees–Edwards offset");
    let (lx, ly) = (
        cell["size"][0].as_f64().unwrap(),
        cell["size"][1].as_f64().unwrap(),
    );
    let kn = state["contact"]["kn"].as_f64().unwrap();
    let disks: Vec<(f64, f64, f64)> = state["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| {
            (
                b["shape"]["r"].as_f64().unwrap(),
                b["position"][0].as_f64().unwrap(),
                b["position"][1].as_f64().unwrap(),
            )
        })
        .collect();
    let mut forces = Vec::new();
    for (i, &(ri, xi, yi)) in disks.iter().enumerate() {
        for &(rj, xj, yj) in &disks[i + 1..] {
            let (mut dx, mut dy) = (xj - xi, yj - yi);
            dx -= lx * (dx / lx).round();
            dy -= ly * (dy / ly).round();
            let delta = ri + rj - dx.hypot(dy);
            if delta > 0.0 {
                forces.push(kn * delta);
            }
        }
    }
    forces
}

#[test]
fn a_relaxed_frictionless_packing_has_no_tangential_anisotropy_and_a_normalised_force_distribution_with_a_sub_exponential_tail()
 {
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
    let bins = 20;
    println!(
        "{}",
        ok(&["forces", rel.to_str().unwrap(), "--bins", &bins.to_string()])
    );
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
    relaxed_force_distribution(&rel, &report, bins);
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

/// Issue 45 item 2: the distribution of a relaxed jammed frictionless packing's forces is the
/// histogram of its contact forces counted here (brute force over all pairs), normalised
/// (`∫ P dx = 1` and `∫ x P dx = 1`, x = f/⟨f⟩), with a tail that falls faster than an
/// exponential's: such packings have `P(f) ~ exp(−c f^α)` with α ≈ 2 in 2D (van Eerd, Ellenbroek,
/// van Hecke & van Saarloos, PRE 75 (2007) 060302; O'Hern et al., PRL 86 (2001) 111).
fn relaxed_force_distribution(rel: &Path, report: &Value, bins: usize) {
    let forces = relaxed_disk_forces(&json(&rel.join("state.json")));
    let n = forces.len();
    let mean = forces.iter().sum::<f64>() / n as f64;
    assert_eq!(report["contacts"].as_u64().unwrap() as usize, n);
    let m = report["mean_force"].as_f64().unwrap();
    assert!((m - mean).abs() < 1e-9 * mean, "⟨f⟩ {m} against {mean}");
    // forces.csv: `f_over_mean,pdf,count`, bins of equal width Δ from 0 to max f/⟨f⟩.
    let csv = std::fs::read_to_string(rel.join("forces.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), bins);
    let top = forces.iter().copied().fold(0.0, f64::max) / mean;
    let width = top / bins as f64;
    // The histogram counted here: each bin's count within one of forces.csv's (a force on an
    // edge may fall either side by round-off), the density count / (n Δ).
    let mut count = vec![0usize; bins];
    for f in &forces {
        count[((f / mean / width) as usize).min(bins - 1)] += 1;
    }
    for (k, r) in rows.iter().enumerate() {
        assert!(
            (r[0] - (k as f64 + 0.5) * width).abs() < 1e-9,
            "bin {k}: {r:?}"
        );
        assert!(
            (r[2] - count[k] as f64).abs() <= 1.0,
            "bin {k}: {} against {} counted here",
            r[2],
            count[k]
        );
        assert!((r[1] - r[2] / (n as f64 * width)).abs() < 1e-9 * r[1].max(1.0));
    }
    // Normalised: ∫ P dx = 1 exactly, and the mean of x under the binned P is 1 up to the
    // midpoint rule's error (within 2 %).
    let total: f64 = rows.iter().map(|r| r[1] * width).sum();
    let first: f64 = rows.iter().map(|r| r[0] * r[1] * width).sum();
    eprintln!("∫P = {total}, ∫xP = {first}, {n} contacts");
    assert!((total - 1.0).abs() < 1e-12, "∫ P = {total}");
    assert!((first - 1.0).abs() < 0.02, "∫ x P = {first}");
    // The tail, faster than exponential: an exponential with the same mean, P = e^{−x}, puts
    // e^{−3} = 4.98 % of the forces above 3⟨f⟩ (16.1 of these contacts); this packing puts
    // fewer than half that there. (A sample of n exponential forces would do so with
    // probability P[Poisson(16.1) ≤ 8] = 2 %.)
    let above = forces.iter().filter(|&&f| f > 3.0 * mean).count();
    let share = above as f64 / n as f64;
    eprintln!(
        "above 3⟨f⟩: {above} of {n} ({share:.4}; exponential {:.4})",
        (-3f64).exp()
    );
    assert!(share < 0.5 * (-3f64).exp(), "{above} of {n} above 3⟨f⟩");
    // And the cumulative tail C(x) = P[f/⟨f⟩ > x] ~ exp(−c x^α) over 1 ≤ x ≤ 3: the slope of
    // ln(−ln C) against ln x is α, 1 for an exponential; here it is larger than 1.2.
    let mut x: Vec<f64> = forces.iter().map(|f| f / mean).collect();
    x.sort_by(f64::total_cmp);
    let pts: Vec<(f64, f64)> = x
        .iter()
        .enumerate()
        .filter(|&(_, &v)| (1.0..=3.0).contains(&v))
        .map(|(k, &v)| {
            let c = (n as f64 - k as f64 - 0.5) / n as f64;
            (v.ln(), (-c.ln()).ln())
        })
        .collect();
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / pts.len() as f64,
        pts.iter().map(|p| p.1).sum::<f64>() / pts.len() as f64,
    );
    let alpha = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
        / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>();
    eprintln!("α of the cumulative tail over 1 ≤ f/⟨f⟩ ≤ 3: {alpha:.3}");
    assert!(alpha > 1.2, "α {alpha}");
}

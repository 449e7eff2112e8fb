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

/// `dem2d run CASE --out RUN --contacts`, which must succeed.
fn run_case(case: &Path, run: &Path) {
    let (code, out, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--contacts",
        "--quiet",
        "--overwrite",
    ]);
    assert_eq!(code, 0, "{out}{err}");
}

/// `dem2d fields RUN --bins N --from T`, which must succeed (writes RUN/fields.csv).
fn fields(run: &Path, bins: usize, from: &str) {
    let (code, out, err) = dem2d(&[
        "fields",
        run.to_str().unwrap(),
        "--bins",
        &bins.to_string(),
        "--from",
        from,
    ]);
    assert_eq!(code, 0, "{out}{err}");
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
    run_case(&file, &run);
    let bins = 10;
    fields(&run, bins, "0.4");
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
    // The shear rate: the least-squares slope of vx(y) over the bins is γ̇ within 10 %.
    let ys = &f["y"];
    let (my, mv) = (
        ys.iter().sum::<f64>() / bins as f64,
        f["vx"].iter().sum::<f64>() / bins as f64,
    );
    let slope = ys
        .iter()
        .zip(&f["vx"])
        .map(|(y, v)| (y - my) * (v - mv))
        .sum::<f64>()
        / ys.iter().map(|y| (y - my).powi(2)).sum::<f64>();
    eprintln!("dvx/dy: {slope:.3} /s against γ̇ = {rate} /s");
    assert!((slope - rate).abs() < 0.1 * rate, "dvx/dy {slope}");
    // The granular temperature is uniform across a Lees–Edwards cell (no slab is special, the
    // seam included): every slab's T below twice the median slab's (they spread by about ±25 %
    // over this window). A slab at the seam that took a straddling body's own velocity for its
    // image's (v ∓ γ̇ L_y) had 3 to 4 times the others' T.
    let mut temps = f["temperature"].clone();
    temps.sort_by(f64::total_cmp);
    let median = 0.5 * (temps[bins / 2 - 1] + temps[bins / 2]);
    eprintln!("T: {temps:.2?} cm²/s²");
    for (k, t) in f["temperature"].iter().enumerate() {
        assert!(
            *t < 2.0 * median,
            "bin {k}: T {t} against the median {median}"
        );
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

/// A pile at rest carries its weight: 96 disks (ρ = 1, radii 0.4 and 0.5 cm) settled under
/// gravity in a box 12 cm wide (a floor, frictionless side walls, a lid far above), 2 s. With
/// the contact stress spread along the branch vectors, the force across a horizontal line at
/// height y is the weight of the bodies whose centres lie above it (their force balance at
/// rest; frictionless side walls carry no weight), so `σ_yy(y) L = Σ_b m_b g [y_b > y]`, and a
/// bin [y₀, y₀ + h) holds the mean over its height, `Σ_b m_b g clamp(y_b − y₀, 0, h) / (h L)`
/// (computed here from trajectory.csv). The bottom bin carries nearly the whole weight, W / L.
#[test]
fn a_pile_at_rest_carries_the_weight_of_the_bodies_above() {
    let dir = scratch("fields_pile");
    let (width, height, g) = (12.0, 14.0, 981.0);
    let mut bodies = Vec::new();
    for k in 0..96 {
        let (row, col) = (k / 12, k % 12);
        let r = if (k * 7) % 3 == 0 { 0.5 } else { 0.4 };
        let x: f64 = 0.5 + col as f64 + if row % 2 == 1 { 0.25 } else { 0.0 };
        // Deterministic velocities of up to 5 cm/s, to break the lattice.
        let (u, v) = (((k * 37) % 11) as f64 - 5.0, ((k * 53) % 11) as f64 - 5.0);
        bodies.push(serde_json::json!({
            "shape": {"type": "circle", "r": r},
            "position": [x.min(width - 0.5), 0.6 + 1.1 * row as f64],
            "velocity": [u, v],
        }));
    }
    let case = serde_json::json!({
        "version": 1, "name": "pile", "units": "cm", "gravity": [0, -g], "dt": 1e-4,
        "duration": 2.0, "output_every": 500,
        "contact": {"model": "linear", "kn": 1e6, "restitution": 0.3, "friction": 0.5},
        "walls": [
            {"point": [0, 0], "normal": [0, 1]},
            {"point": [0, 0], "normal": [1, 0], "friction": 0},
            {"point": [width, 0], "normal": [-1, 0], "friction": 0},
            {"point": [0, height], "normal": [0, -1]},
        ],
        "bodies": bodies,
    });
    let file = dir.join("pile.json");
    std::fs::write(&file, case.to_string()).unwrap();
    let run = dir.join("run");
    run_case(&file, &run);
    let bins = 28;
    fields(&run, bins, "1.5");
    let f = columns(&run.join("fields.csv"));
    // The masses from the case, the positions of the window's frames from trajectory.csv.
    let mass: Vec<f64> = bodies_of(&case)
        .iter()
        .map(|r| std::f64::consts::PI * r * r)
        .collect();
    let weight = g * mass.iter().sum::<f64>();
    let t = columns(&run.join("trajectory.csv"));
    let rows: Vec<usize> = (0..t["t"].len()).filter(|&k| t["t"][k] >= 1.5).collect();
    let frames = f["frames"][0];
    assert_eq!(rows.len() as f64, frames * mass.len() as f64);
    let h = height / bins as f64;
    for (k, y) in f["y"].iter().enumerate() {
        let y0 = y - 0.5 * h;
        let want = rows
            .iter()
            .map(|&i| mass[t["body"][i] as usize] * g * (t["y"][i] - y0).clamp(0.0, h))
            .sum::<f64>()
            / (h * width * frames);
        // At rest to within the residual accelerations (|v| ~ 1e-4 cm/s): 0.1 % of W / L.
        assert!(
            (f["syy"][k] - want).abs() < 1e-3 * weight / width,
            "bin {k} at y = {y}: σ_yy {} against {want}",
            f["syy"][k]
        );
    }
    let bottom = f["syy"][0];
    eprintln!(
        "bottom bin σ_yy {bottom:.1} dyn/cm against W/L = {:.1}",
        weight / width
    );
    assert!((bottom - weight / width).abs() < 0.1 * weight / width);
}

/// The radii of a case's disks.
fn bodies_of(case: &serde_json::Value) -> Vec<f64> {
    case["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b["shape"]["r"].as_f64().unwrap())
        .collect()
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

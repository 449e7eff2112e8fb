//! `dem2d relax` at the jamming threshold (issue 41, item 12): 256 frictionless bidisperse disks
//! (`cases/jammed_disks_256.json`, a packing of dem2d's own jamming protocol as its last
//! minimisation started, u ≈ 1e-12 k_n d² per grain at the end) relax to a residual force of at
//! most 1e-7 within 10⁶ iterations, ending `relaxed` or at the round-off level of the forces
//! (`round_off`, exit code 0). Checked against what does not come from dem2d's minimiser:
//! - the forces, the energy and the contacts of the relaxed positions, recomputed here by brute
//!   force over all pairs (nearest image; F = k_n δ and U = ½ k_n δ² for disks);
//! - the isostatic count: a jammed periodic packing of N′ non-rattlers has at least 2N′ − 1
//!   contacts (2N′ − 2 degrees of freedom, the two translations of the cell being free, plus
//!   one for the pressure), Z ≥ 4 − 2/N′ ≥ 3.985 here;
//! - LAMMPS's FIRE (`min_style fire`, `pair_style gran/hooke`, 10⁶ iterations) on the same
//!   packing: `lab/peers/jammed_disks_256.lammps.json`, written by `python3
//!   lab/peers/jamming_fire.py cases/jammed_disks_256.json` (LAMMPS 29 Sep 2021, Debian's
//!   `lammps`): the same energy, contacts and rattlers.

use serde_json::Value;
use std::path::Path;

mod common;
use common::{case_path, dem2d, scratch_path};

fn json(file: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(file).unwrap())
        .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}

/// The disks' network by brute force: (energy, residual as `dem2d relax` defines it, contacts,
/// Z with rattlers out, rattlers).
fn network(state: &Value, kn: f64) -> (f64, f64, usize, f64, usize) {
    let size = &state["cell"]["size"];
    let (lx, ly) = (size[0].as_f64().unwrap(), size[1].as_f64().unwrap());
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
    let n = disks.len();
    let (mut force, mut acting) = (vec![(0.0f64, 0.0f64); n], vec![0.0f64; n]);
    let (mut energy, mut pairs) = (0.0, Vec::new());
    for i in 0..n {
        for j in i + 1..n {
            let (ri, xi, yi) = disks[i];
            let (rj, xj, yj) = disks[j];
            let (mut dx, mut dy) = (xj - xi, yj - yi);
            dx -= lx * (dx / lx).round();
            dy -= ly * (dy / ly).round();
            let d = dx.hypot(dy);
            let delta = ri + rj - d;
            if delta > 0.0 {
                let f = kn * delta;
                energy += 0.5 * kn * delta * delta;
                let (ux, uy) = (dx / d, dy / d);
                force[i].0 -= f * ux;
                force[i].1 -= f * uy;
                force[j].0 += f * ux;
                force[j].1 += f * uy;
                acting[i] += f;
                acting[j] += f;
                pairs.push((i, j));
            }
        }
    }
    let mean = acting.iter().sum::<f64>() / n as f64;
    let residual = force.iter().map(|f| f.0.hypot(f.1)).fold(0.0f64, f64::max) / mean;
    // Rattlers: fewer than 3 contacts, removed repeatedly.
    let mut alive = vec![true; n];
    loop {
        let mut z = vec![0usize; n];
        for &(i, j) in &pairs {
            if alive[i] && alive[j] {
                z[i] += 1;
                z[j] += 1;
            }
        }
        let gone: Vec<usize> = (0..n).filter(|&k| alive[k] && z[k] < 3).collect();
        if gone.is_empty() {
            let kept = alive.iter().filter(|&&a| a).count();
            let contacts = z.iter().sum::<usize>() / 2;
            // The isostatic count of the kept disks.
            assert!(
                contacts + 1 >= 2 * kept,
                "{contacts} contacts among {kept} non-rattlers: fewer than 2N′ − 1"
            );
            return (
                energy,
                residual,
                pairs.len(),
                2.0 * contacts as f64 / kept as f64,
                n - kept,
            );
        }
        for k in gone {
            alive[k] = false;
        }
    }
}

#[test]
fn a_threshold_packing_of_256_disks_relaxes_to_its_isostatic_minimum() {
    let out = scratch_path("jammed_disks_256");
    let case = case_path("jammed_disks_256.json");
    let (code, _, err) = dem2d(&[
        "relax",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    assert_eq!(code, 0, "{err}");
    let summary = json(&out.join("relax.json"));
    let status = summary["status"].as_str().unwrap();
    assert!(status == "relaxed" || status == "round_off", "{summary}");
    let residual = summary["residual"].as_f64().unwrap();
    assert!(residual <= 1e-7, "{summary}");
    assert!(
        summary["iterations"].as_u64().unwrap() <= 1_000_000,
        "{summary}"
    );
    // The round-off level is what it says: the residual is within its factor of it.
    if status == "round_off" {
        assert!(residual <= 10.0 * summary["round_off_residual"].as_f64().unwrap());
    }
    // The relaxed positions, measured by brute force.
    let state = json(&out.join("state.json"));
    assert_eq!(state["state"]["status"], status);
    let kn = json(&case)["contact"]["kn"].as_f64().unwrap();
    let (energy, brute, contacts, z, rattlers) = network(&state, kn);
    assert!(brute <= 1e-7, "residual by brute force {brute:e}");
    // (The two residuals differ by the round-off of the two sums.)
    assert!(
        (brute - residual).abs() <= 0.5 * residual.max(brute),
        "{brute:e} against {residual:e}"
    );
    let potential = summary["potential"].as_f64().unwrap();
    assert!(
        (energy - potential).abs() <= 1e-9 * energy,
        "{energy:e} against {potential:e}"
    );
    assert_eq!(summary["contacts"].as_u64().unwrap() as usize, contacts);
    assert!(z >= 3.985, "Z_J = {z} with {rattlers} rattlers");
    // LAMMPS's FIRE on the same packing: the same minimum. At a minimum the energy is
    // stationary, so two residuals of 1e-7 or less leave energies equal to O(1e-14) relative,
    // times the packing's condition number (soft modes near jamming): 1e-8 allows 10⁶.
    let lammps =
        json(&Path::new(env!("CARGO_MANIFEST_DIR")).join("lab/peers/jammed_disks_256.lammps.json"));
    let reference = lammps["energy"].as_f64().unwrap();
    assert!(
        (energy - reference).abs() <= 1e-8 * reference,
        "dem2d {energy:e} erg, LAMMPS {reference:e} erg"
    );
    assert_eq!(lammps["contacts"].as_u64().unwrap() as usize, contacts);
    assert_eq!(lammps["rattlers"].as_u64().unwrap() as usize, rattlers);
    assert!(lammps["residual"].as_f64().unwrap() <= 1e-7, "{lammps}");
}

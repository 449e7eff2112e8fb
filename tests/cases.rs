//! The case files: every `cases/*.json` runs, and the studies' case sets in
//! `cases/{repose,packing,biaxial_shape}/`; every `cases/bad/*.json` is refused with the error
//! recorded beside it in `cases/bad/expected_errors.json`; a blow-up stops with the step and the
//! body and keeps what it wrote; and the paper's observations hold.

use serde_json::Value;
use std::path::{Path, PathBuf};

mod common;
use common::{dem2d, scratch_path};

fn cases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases")
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn every_case_runs() {
    let mut ran = 0;
    // The studies' case sets live in subdirectories (`dem2d study NAME --write-cases`).
    let files = std::fs::read_dir(cases_dir()).unwrap().chain(
        ["repose", "packing", "biaxial_shape"]
            .iter()
            .filter(|d| cases_dir().join(d).is_dir())
            .flat_map(|d| std::fs::read_dir(cases_dir().join(d)).unwrap()),
    );
    for entry in files {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "json") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let v: Value = serde_json::from_str(&text).unwrap();
        let p = path.to_str().unwrap();
        if v.is_array() {
            // A pairs file for `dem2d contact`.
            let (code, out, err) = dem2d(&["contact", p]);
            assert_eq!(code, 0, "{p}: {err}");
            assert_eq!(out.lines().count(), v.as_array().unwrap().len());
            continue;
        }
        let dir = scratch_path(path.file_stem().unwrap().to_str().unwrap());
        // 3000 steps; 300 for the piles of more than a thousand bodies (they only start to
        // fall in either), 3000 for them too in the long form (`DEM2D_LONG_TESTS=1`).
        let bodies = v["bodies"].as_array().map_or(0, Vec::len);
        let long = std::env::var_os("DEM2D_LONG_TESTS").is_some_and(|v| v != "0");
        let steps = if bodies > 1000 && !long {
            "300"
        } else {
            "3000"
        };
        let (code, _, err) = dem2d(&[
            "run",
            p,
            "--out",
            dir.to_str().unwrap(),
            "--max-steps",
            steps,
            "--quiet",
        ]);
        assert_eq!(code, 0, "{p}: {err}");
        let s = summary(&dir);
        assert!(s["error"].is_null(), "{p}: {}", s["error"]);
        assert!(s["steps"].as_u64().unwrap() >= 1);
        for field in [
            "time",
            "dt",
            "dt_critical",
            "max_depth_ratio",
            "wall_seconds",
            "particle_steps_per_second",
        ] {
            assert!(s[field].as_f64().unwrap().is_finite(), "{p}: {field}");
        }
        let traj = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
        let mut lines = traj.lines();
        let header = if v.get("cell").is_some() {
            // (A periodic cell's image counts.)
            "step,t,body,x,y,angle,vx,vy,omega,ix,iy"
        } else {
            "step,t,body,x,y,angle,vx,vy,omega"
        };
        assert_eq!(lines.next(), Some(header), "{p}");
        let bodies = v["bodies"].as_array().unwrap().len();
        assert!(lines.count() >= 2 * bodies, "{p}: initial and final rows");
        ran += 1;
    }
    assert!(ran >= 7, "only {ran} cases");
}

#[test]
fn every_bad_case_is_refused_with_its_error() {
    let bad = cases_dir().join("bad");
    let expected: Value =
        serde_json::from_str(&std::fs::read_to_string(bad.join("expected_errors.json")).unwrap())
            .unwrap();
    let expected = expected.as_object().unwrap();
    let mut seen = 0;
    for entry in std::fs::read_dir(&bad).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        if name == "expected_errors.json" {
            continue;
        }
        let want = expected
            .get(&name)
            .unwrap_or_else(|| panic!("{name} has no expected error"))
            .as_str()
            .unwrap();
        let dir = scratch_path(&format!("bad-{name}"));
        let (code, out, err) = dem2d(&[
            "run",
            path.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(
            err.contains(path.to_str().unwrap()),
            "{name}: the message names the file: {err}"
        );
        assert!(err.contains(want), "{name}: expected «{want}», got «{err}»");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(out.is_empty(), "{name}: {out}");
        assert!(
            !dir.exists(),
            "{name}: nothing is written for a refused case"
        );
        seen += 1;
    }
    assert_eq!(seen, expected.len(), "every expected error has its file");
}

#[test]
fn a_blow_up_stops_with_step_and_body_and_keeps_its_output() {
    // Two stiff, undamped disks squeezed between two walls with Δt far above the critical step
    // (ωΔt ≈ 18): every step multiplies the oscillation. The run must stop before anything is
    // non-finite, name the step and the body, keep what it wrote, and label the last rows with
    // the step whose state they hold.
    let case = r#"{"version": 1, "name": "blowup", "gravity": [0, 0], "dt": 1e-3, "duration": 10.0,
      "output_every": 1,
      "contact": {"model": "linear", "kn": 1e9, "eta_n": 0, "friction": 0},
      "walls": [{"point": [0, 0], "normal": [1, 0]}, {"point": [3.99, 0], "normal": [-1, 0]}],
      "bodies": [{"shape": {"type": "circle", "r": 1}, "position": [1, 0]},
                 {"shape": {"type": "circle", "r": 1}, "position": [3, 0]}]}"#;
    let dir = scratch_path("blowup");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("blowup.json");
    std::fs::write(&file, case).unwrap();
    let out = dir.join("out");
    let (code, _, err) = dem2d(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("blow-up at step 1 ") && err.contains("body") && err.contains("energy grew"),
        "{err}"
    );
    assert!(
        err.contains("warning: dt = 1e-3 exceeds the critical time step"),
        "{err}"
    );
    let s = summary(&out);
    assert_eq!(s["status"], "blowup");
    assert!(
        s["error"].as_str().unwrap().contains("step 1 "),
        "{}",
        s["error"]
    );
    for e in ["kinetic", "potential", "elastic", "dissipated"] {
        assert!(s["energies"][e].as_f64().unwrap().is_finite(), "{e}");
    }
    let traj = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let rows: Vec<Vec<f64>> = traj
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(
        rows.len(),
        4,
        "the initial state and the state at the blow-up"
    );
    let last = &rows[rows.len() - 1];
    assert_eq!(
        last[0], 1.0,
        "the last row is labelled with the step it holds"
    );
    assert_eq!(last[1], 1e-3);
    assert_eq!(last[3], s["final"][1]["x"].as_f64().unwrap());
    assert_eq!(last[6], s["final"][1]["vx"].as_f64().unwrap());
}

#[test]
fn paper_settling_case_rests_at_1e_5_and_never_at_1e_4() {
    // P Fig. 4: rest at Δt = 1e-5 (P: 881 steps); at Δt = 1e-4 no rest within 0.5 s, |Δθ| keeps
    // fluctuating, and the Δt warning fires.
    let fine = scratch_path("settle3_fine");
    let (code, _, err) = dem2d(&[
        "run",
        cases_dir().join("settle3_dt1e-5.json").to_str().unwrap(),
        "--out",
        fine.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let s = summary(&fine);
    assert_eq!(s["quiescent"], true, "no rest at Δt = 1e-5");
    assert!(s["warnings"].as_array().unwrap().is_empty());
    let coarse = scratch_path("settle3_coarse");
    let (code, _, err) = dem2d(&[
        "run",
        cases_dir().join("settle3_dt1e-4.json").to_str().unwrap(),
        "--out",
        coarse.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("warning: dt = 1e-4 exceeds the critical time step"),
        "{err}"
    );
    let s = summary(&coarse);
    assert_eq!(s["quiescent"], false);
    assert!((s["time"].as_f64().unwrap() - 0.5).abs() < 1e-9);
    // The rotation increments over the last tenth of the run: still well above the threshold.
    let incs = std::fs::read_to_string(coarse.join("increments.csv")).unwrap();
    let dtheta: Vec<f64> = incs
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
        .collect();
    let tail = &dtheta[dtheta.len() * 9 / 10..];
    let min_tail = tail.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(min_tail > 1e-9, "|Δθ| settled to {min_tail:e}");
}

#[test]
fn paper_drop_differs_visibly_with_floor_friction() {
    // P Fig. 2: the two frictions give visibly different motions (centimetres apart).
    let mut finals = Vec::new();
    for tag in ["mu01", "mu05"] {
        let dir = scratch_path(&format!("drop_{tag}"));
        let case = cases_dir().join(format!("drop_rebound_{tag}.json"));
        let (code, _, err) = dem2d(&[
            "run",
            case.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
            "--quiet",
        ]);
        assert_eq!(code, 0, "{err}");
        let f = &summary(&dir)["final"][0];
        finals.push((f["x"].as_f64().unwrap(), f["angle"].as_f64().unwrap()));
    }
    let dx = (finals[0].0 - finals[1].0).abs();
    assert!(
        dx > 1.0,
        "final positions differ by only {dx} cm: {finals:?}"
    );
}

#[test]
fn the_dynamics_is_the_same_at_every_scale_of_the_accepted_ranges() {
    // P's settling scene with every length (sizes, positions, gravity, stiffness per ρg) scaled
    // by 2^-64 ≈ 5e-20 and by 2^40 ≈ 1e12, times unchanged: scaling by a power of two is exact in
    // float64 and every formula of the step is homogeneous in length, so the trajectory divided
    // by the scale must be the same bits. (The case's quiescence is left out: P's criterion
    // compares angle increments with a length.) A difference means an absolute tolerance
    // somewhere, which the accepted ranges (1e-40 … 1e40) would expose.
    let base: Value = serde_json::from_str(
        &std::fs::read_to_string(cases_dir().join("settle3_dt1e-5.json")).unwrap(),
    )
    .unwrap();
    let dir = scratch_path("scales");
    std::fs::create_dir_all(&dir).unwrap();
    let run = |e: i32| -> Vec<[f64; 5]> {
        let s = 2f64.powi(e);
        let mut c = base.clone();
        let scale = |v: &mut Value| *v = Value::from(v.as_f64().unwrap() * s);
        c["gravity"]
            .as_array_mut()
            .unwrap()
            .iter_mut()
            .for_each(scale);
        for (k, v) in c["contact"].as_object_mut().unwrap() {
            if k.ends_with("_over_rho_g") {
                scale(v);
            }
        }
        for w in c["walls"].as_array_mut().unwrap() {
            assert!(
                w.as_object()
                    .unwrap()
                    .keys()
                    .all(|k| k == "point" || k == "normal")
            );
            w["point"]
                .as_array_mut()
                .unwrap()
                .iter_mut()
                .for_each(scale);
        }
        for b in c["bodies"].as_array_mut().unwrap() {
            b["position"]
                .as_array_mut()
                .unwrap()
                .iter_mut()
                .for_each(scale);
            for (k, v) in b["shape"].as_object_mut().unwrap() {
                if k != "type" {
                    scale(v);
                }
            }
            assert!(b.get("velocity").is_none());
        }
        c.as_object_mut().unwrap().remove("quiescence");
        c["output_every"] = Value::from(1);
        let file = dir.join(format!("scale{e}.json"));
        std::fs::write(&file, c.to_string()).unwrap();
        let out = dir.join(format!("out{e}"));
        let (code, _, err) = dem2d(&[
            "run",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--max-steps",
            "8000",
        ]);
        assert_eq!(code, 0, "2^{e}: {err}");
        let traj = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
        traj.lines()
            .skip(1)
            .map(|l| {
                let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
                [v[3] / s, v[4] / s, v[5], v[6] / s, v[8]]
            })
            .collect()
    };
    let unit = run(0);
    assert_eq!(unit.len(), 3 * 8001);
    for e in [-64, 40] {
        let scaled = run(e);
        let first = unit.iter().zip(&scaled).position(|(a, b)| a != b);
        assert_eq!(first, None, "2^{e}: first different row {first:?}");
    }
}

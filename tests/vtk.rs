//! `dem2d run --vtk`: the files are read back by VTK's own reader (`tests/vtk_check.py`, which
//! checks cell counts, polygon areas against the bodies' areas, and the arrays against the
//! trajectory); writing them changes nothing else; bad VTK options and an unwritable `vtk/` are
//! refused with the option or file named.
//!
//! The reader needs VTK's Python module (Debian: `python3-vtk9`). Without it the reader test
//! says so and passes, unless `DEM2D_REQUIRE_VTK` is set — as `.ci/run` does after installing
//! the package, so that CI never skips it.

use std::path::Path;
use std::process::Command;

mod common;
use common::{dem2d, f64s, i64s, scratch, vtu_arrays};

/// Every shape, an ellipse of a/b = 10 among them, on a floor between two walls, stacked so
/// that bodies touch bodies and walls within 0.1 s.
const CASE: &str = r#"{ "version": 1, "name": "vtk_mix", "units": "cm",
  "gravity": [0, -980], "dt": 1e-5, "duration": 0.1, "output_every": 1000,
  "contact": { "model": "linear", "kn_over_rho_g": 36400, "ks_over_rho_g": 36400,
               "eta_n_over_rho_g": 25.925, "eta_s_over_rho_g": 25.925, "friction": 0.5 },
  "walls": [ { "point": [0, 0], "normal": [0, 1] }, { "point": [0, 0], "normal": [1, 0] },
             { "point": [30, 0], "normal": [-1, 0] } ],
  "bodies": [
    { "shape": {"type": "circle", "r": 1}, "position": [1.02, 1.05], "velocity": [-5, 0] },
    { "shape": {"type": "ellipse", "a": 3, "b": 0.3}, "position": [7, 0.35], "angle": 0.1 },
    { "shape": {"type": "rectangle", "w": 2, "h": 1}, "position": [12, 0.55] },
    { "shape": {"type": "ellipse", "a": 1.5, "b": 1}, "position": [16, 1.2], "angle": 0.5 },
    { "shape": {"type": "circle", "r": 0.5}, "position": [12, 1.7] },
    { "shape": {"type": "ellipse", "a": 2, "b": 0.2}, "position": [12.3, 2.5], "angle": -0.2 },
    { "shape": {"type": "rectangle", "w": 1, "h": 3}, "position": [20, 1.6], "angle": 0.3 },
    { "shape": {"type": "circle", "r": 0.8}, "position": [28.9, 3], "velocity": [30, 0] }
  ] }"#;

/// A Python that has VTK's module: `DEM2D_VTK_PYTHON`, else Debian's own `/usr/bin/python3`
/// (where python3-vtk9 installs), else `python3` on the PATH.
fn vtk_python() -> Option<String> {
    let candidates: Vec<String> = std::env::var("DEM2D_VTK_PYTHON")
        .into_iter()
        .chain(["/usr/bin/python3".to_string(), "python3".to_string()])
        .collect();
    candidates.into_iter().find(|py| {
        Command::new(py)
            .args(["-c", "import vtk"])
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

#[test]
fn vtk_files_read_back_by_vtk_match_the_run() {
    let dir = scratch("mix");
    let case = dir.join("case.json");
    std::fs::write(&case, CASE).unwrap();
    let run = dir.join("run");
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--quiet",
        "--vtk-every",
        "2000",
    ]);
    assert_eq!(code, 0, "{err}");
    // Frames at steps 0, 2000, …, 10000, listed in run.pvd in order.
    let pvd = std::fs::read_to_string(run.join("run.pvd")).unwrap();
    for (k, t) in ["0", "0.02", "0.04", "0.06", "0.08", "0.1"]
        .iter()
        .enumerate()
    {
        let entry = format!("timestep=\"{t}\" group=\"\" part=\"0\" file=\"vtk/frame_{k:05}.vtu\"");
        assert!(pvd.contains(&entry), "{entry} not in\n{pvd}");
        assert!(run.join(format!("vtk/frame_{k:05}.vtu")).exists());
    }
    assert!(!run.join("vtk/frame_00006.vtu").exists());
    // Writing VTK changes nothing else: the same run without it has the same trajectory.
    let plain = dir.join("plain");
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        plain.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    for f in ["trajectory.csv", "increments.csv"] {
        assert!(
            std::fs::read(run.join(f)).unwrap() == std::fs::read(plain.join(f)).unwrap(),
            "{f} differs with --vtk"
        );
    }
    assert!(!plain.join("vtk").exists() && !plain.join("run.pvd").exists());

    let Some(py) = vtk_python() else {
        assert!(
            std::env::var_os("DEM2D_REQUIRE_VTK").is_none(),
            "DEM2D_REQUIRE_VTK is set but no Python with VTK was found (install python3-vtk9)"
        );
        eprintln!(
            "SKIPPED the VTK reader check: no Python with VTK's module (Debian: apt-get install \
             python3-vtk9; .ci/run installs it)"
        );
        return;
    };
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/vtk_check.py");
    let out = Command::new(&py)
        .arg(&script)
        .arg(&run)
        .output()
        .expect("run the VTK check");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("{stdout}{stderr}");
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("vtk check passed: 6 frames"), "{stdout}");
    // The scene is in contact by the end (bodies on the floor and on each other: 7 contacts),
    // so the contact lines were checked too.
    let last = stdout.lines().find(|l| l.contains("frame_00005")).unwrap();
    let contacts: usize = last
        .split(" contacts")
        .next()
        .and_then(|s| s.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap();
    assert!(contacts >= 5, "{last}");
}

#[test]
fn the_case_file_can_ask_for_vtk_and_bad_vtk_requests_are_refused() {
    let dir = scratch("options");
    // "output": {"vtk": true, "vtk_every": N} in the case does what --vtk-every does.
    let mut v: serde_json::Value = serde_json::from_str(CASE).unwrap();
    v["duration"] = 0.01.into();
    v["output"] = serde_json::json!({"vtk": true, "vtk_every": 400});
    let case = dir.join("case.json");
    std::fs::write(&case, v.to_string()).unwrap();
    let run = dir.join("run");
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    // Steps 0, 400, 800 and the last, 1000.
    let frames = std::fs::read_dir(run.join("vtk")).unwrap().count();
    assert_eq!(frames, 4);
    // A second run into the same directory is refused, naming the VTK output; --overwrite
    // removes the earlier frames (and only them) first.
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("run.pvd") && err.contains("vtk/ (4 frames)"),
        "{err}"
    );
    std::fs::write(run.join("vtk/notes.txt"), "mine").unwrap();
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--quiet",
        "--overwrite",
        "--vtk-every",
        "500",
    ]);
    assert_eq!(code, 0, "{err}");
    let mut names: Vec<String> = std::fs::read_dir(run.join("vtk"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "frame_00000.vtu",
            "frame_00001.vtu",
            "frame_00002.vtu",
            "notes.txt"
        ]
    );

    // Unknown or mistyped fields of "output" are refused with their path.
    for (output, want) in [
        (
            serde_json::json!({"vtk": true, "paraview": 1}),
            "field `output.paraview`: unknown field",
        ),
        (
            serde_json::json!({"vtk": "yes"}),
            "field `output.vtk`: must be true or false, got a string",
        ),
        (
            serde_json::json!({"vtk_every": 0}),
            "field `output.vtk_every`: must be a whole number ≥ 1, got 0",
        ),
    ] {
        v["output"] = output;
        std::fs::write(&case, v.to_string()).unwrap();
        let (code, _, err) = dem2d(&["run", case.to_str().unwrap(), "--out", "/nonexistent/x"]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(want), "{err}");
    }
    // --vtk-every 0.
    let (code, _, err) = dem2d(&["run", "cases/settle3_dt1e-5.json", "--vtk-every", "0"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--vtk-every: must be at least 1"), "{err}");
    // A `vtk` that is a file: the run does not start, and the message names it.
    let blocked = dir.join("blocked");
    std::fs::create_dir_all(&blocked).unwrap();
    std::fs::write(blocked.join("vtk"), "a file").unwrap();
    let (code, _, err) = dem2d(&[
        "run",
        "cases/settle3_dt1e-5.json",
        "--out",
        blocked.to_str().unwrap(),
        "--vtk",
        "--quiet",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains(&format!("{}: cannot write", blocked.join("vtk").display())),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

/// Runs `tests/vtk_check.py` on `run` and returns its output; `None` where no Python has VTK
/// (refused when `DEM2D_REQUIRE_VTK` is set).
fn vtk_check(run: &Path) -> Option<String> {
    let Some(py) = vtk_python() else {
        assert!(
            std::env::var_os("DEM2D_REQUIRE_VTK").is_none(),
            "DEM2D_REQUIRE_VTK is set but no Python with VTK was found (install python3-vtk9)"
        );
        eprintln!("SKIPPED the VTK reader check: no Python with VTK's module");
        return None;
    };
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/vtk_check.py");
    let out = Command::new(&py)
        .arg(&script)
        .arg(run)
        .output()
        .expect("run the VTK check");
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("{stdout}{stderr}");
    assert!(out.status.success(), "{stdout}\n{stderr}");
    Some(stdout)
}

#[test]
fn a_periodic_cell_is_drawn_with_its_size_and_shift_and_contacts_across_a_seam_to_an_image() {
    // The shear tutorial's Lees–Edwards cell at imposed pressure (its height shrinks from 20 cm
    // as it is compressed): the outline and the field data follow cell.csv frame by frame, and
    // the contacts across a seam end at the giver's image (tests/vtk_check.py).
    let dir = scratch("cell");
    let run = dir.join("shear");
    let (code, _, err) = dem2d(&[
        "run",
        "cases/shear_cell.json",
        "--out",
        run.to_str().unwrap(),
        "--quiet",
        "--max-steps",
        "12000",
        "--vtk-every",
        "2000",
    ]);
    assert_eq!(code, 0, "{err}");
    if let Some(out) = vtk_check(&run) {
        assert!(out.contains("vtk check passed: 7 frames"), "{out}");
        let seams: usize = out
            .rsplit("cells, ")
            .next()
            .and_then(|s| s.split(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap();
        assert!(
            seams >= 10,
            "too few contacts across a seam to check: {out}"
        );
    }
    // A cell periodic in x between a floor and a lid: its two seams.
    let case = dir.join("x.json");
    std::fs::write(
        &case,
        r#"{ "version": 1, "name": "periodic_x", "units": "cm",
  "gravity": [0, -980], "dt": 1e-5, "duration": 0.05, "output_every": 1000,
  "cell": { "size": [8, 10], "periodic": "x" },
  "contact": { "model": "linear", "kn_over_rho_g": 36400, "restitution": 0.5, "friction": 0.5 },
  "walls": [ { "point": [0, 0], "normal": [0, 1] },
             { "point": [0, 10], "normal": [0, -1], "velocity": [5, 0] } ],
  "bodies": [ { "shape": {"type": "ellipse", "a": 1.0, "b": 0.5}, "position": [7.5, 1] },
              { "shape": {"type": "circle", "r": 0.6}, "position": [0.2, 1] } ] }"#,
    )
    .unwrap();
    let run = dir.join("x");
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--quiet",
        "--vtk",
    ]);
    assert_eq!(code, 0, "{err}");
    if let Some(out) = vtk_check(&run) {
        assert!(out.contains("vtk check passed: 6 frames"), "{out}");
        assert!(out.contains("2 cell outlines"), "{out}");
    }
}

/// A silo whose bodies come and go: five bodies of three shapes fall into an outflow region one
/// after another (the circle first, then the ellipse, then the rectangle), while two inserters
/// rain ellipses and rectangles in from above. Issue 41, items 4 and 5: `--vtk` panicked on the
/// first inserted body (index out of bounds), and after a removal every later body was drawn
/// with its predecessor's outline (the outlines were kept by index, not by identity).
const SILO_MIX: &str = r#"{ "version": 1, "name": "silo_mix", "units": "cm",
  "gravity": [0, -980], "dt": 1e-4, "duration": 0.06, "output_every": 50,
  "contact": { "model": "linear", "kn_over_rho_g": 2000, "restitution": 0.5, "friction": 0.4 },
  "walls": [ { "point": [-30, 0], "normal": [1, 0] } ],
  "bodies": [
    { "shape": {"type": "circle", "r": 0.5}, "position": [0, -1], "velocity": [0, -300] },
    { "shape": {"type": "ellipse", "a": 1.2, "b": 0.4}, "position": [4, 1], "angle": 0.3,
      "velocity": [0, -250] },
    { "shape": {"type": "rectangle", "w": 1.5, "h": 0.6}, "position": [8, 3], "angle": 0.2,
      "velocity": [0, -200] },
    { "shape": {"type": "ellipse", "a": 0.9, "b": 0.6}, "position": [12, 5], "angle": -0.4 },
    { "shape": {"type": "circle", "r": 0.8}, "position": [16, 5] } ],
  "insert": [ { "region": [-10, 10, 10, 14], "rate": 400, "count": 12, "shape": "ellipse",
                "size": {"uniform": [0.3, 0.5]}, "aspect": {"choice": [1.5, 2.5]},
                "angle": "random", "velocity": [0, -50], "seed": 3 },
              { "region": [-10, 10, 16, 20], "rate": 200, "count": 6, "shape": "rectangle",
                "size": 0.4, "aspect": {"uniform": [1, 2]} } ],
  "outflow": [ { "region": [-20, 20, -100, -4] } ] }"#;

/// The largest distance of `points` from the boundary of `shape` (a case file's shape object)
/// placed at `(x, y)` turned by `angle`, relative to its size: a circle's at distance r, an
/// ellipse's on `(u/a)² + (v/b)² = 1`, a rectangle's its four corners.
fn off_boundary(
    shape: &serde_json::Value,
    points: &[(f64, f64)],
    x: f64,
    y: f64,
    angle: f64,
) -> f64 {
    let (s, c) = angle.sin_cos();
    let local = points
        .iter()
        .map(|&(px, py)| ((px - x) * c + (py - y) * s, -(px - x) * s + (py - y) * c));
    let num = |k: &str| shape[k].as_f64().unwrap();
    match shape["type"].as_str().unwrap() {
        "circle" => local
            .map(|(u, v)| (u.hypot(v) - num("r")).abs() / num("r"))
            .fold(0.0, f64::max),
        "ellipse" => local
            .map(|(u, v)| ((u / num("a")).powi(2) + (v / num("b")).powi(2)).sqrt() - 1.0)
            .map(f64::abs)
            .fold(0.0, f64::max),
        "rectangle" if points.len() == 4 => {
            let (hw, hh) = (num("w") / 2.0, num("h") / 2.0);
            local
                .map(|(u, v)| ((u.abs() - hw).abs() / hw).max((v.abs() - hh).abs() / hh))
                .fold(0.0, f64::max)
        }
        _ => f64::INFINITY,
    }
}

#[test]
fn a_silo_that_inserts_and_removes_bodies_draws_each_body_with_its_own_shape() {
    let dir = scratch("silo_mix");
    let case = dir.join("case.json");
    std::fs::write(&case, SILO_MIX).unwrap();
    let run = dir.join("run");
    let (code, _, err) = dem2d(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        run.to_str().unwrap(),
        "--quiet",
        "--vtk-every",
        "100",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("panicked"), "{err}");
    // The circle, the ellipse and the rectangle left, in that order (discharge.csv).
    let discharged: Vec<String> = std::fs::read_to_string(run.join("discharge.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(2).unwrap().to_string())
        .collect();
    assert_eq!(discharged, ["0", "1", "2"]);

    // Every body's shape by identity, apart from the writer: the case's, then each inserted
    // body's inserter's shape at the radius and aspect inserted.csv records (outputs.md).
    let v: serde_json::Value = serde_json::from_str(SILO_MIX).unwrap();
    let mut shapes: std::collections::HashMap<u64, serde_json::Value> = v["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(k, b)| (k as u64, b["shape"].clone()))
        .collect();
    for line in std::fs::read_to_string(run.join("inserted.csv"))
        .unwrap()
        .lines()
        .skip(1)
    {
        let f: Vec<&str> = line.split(',').collect();
        let (id, ins): (u64, usize) = (f[2].parse().unwrap(), f[3].parse().unwrap());
        let (r, alpha): (f64, f64) = (f[4].parse().unwrap(), f[5].parse().unwrap());
        let pi = std::f64::consts::PI;
        let shape = match v["insert"][ins]["shape"].as_str().unwrap() {
            "ellipse" => {
                serde_json::json!({"type": "ellipse", "a": r * alpha.sqrt(), "b": r / alpha.sqrt()})
            }
            "rectangle" => {
                serde_json::json!({"type": "rectangle", "w": r * (pi * alpha).sqrt(), "h": r * (pi / alpha).sqrt()})
            }
            other => panic!("{other}"),
        };
        shapes.insert(id, shape);
    }
    assert_eq!(shapes.len(), 5 + 18, "every inserter ran to its count");
    // The trajectory's rows by step: (identity, x, y, angle).
    let mut traj: std::collections::HashMap<u64, Vec<(u64, f64, f64, f64)>> = Default::default();
    for line in std::fs::read_to_string(run.join("trajectory.csv"))
        .unwrap()
        .lines()
        .skip(1)
    {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        traj.entry(f[0] as u64)
            .or_default()
            .push((f[2] as u64, f[3], f[4], f[5]));
    }
    // Each frame read back: body k's polygon lies on the boundary of the shape of the body
    // that has that identity, at its trajectory pose.
    let mut frames = 0;
    let mut bodies_checked = 0;
    for k in 0..7 {
        let text = std::fs::read_to_string(run.join(format!("vtk/frame_{k:05}.vtu"))).unwrap();
        let a = vtu_arrays(&text);
        let step = i64s(&a["STEP"])[0] as u64;
        assert_eq!(step, 100 * k as u64);
        let rows = &traj[&step];
        let (points, conn, offsets) = (
            f64s(&a["Points"]),
            i64s(&a["connectivity"]),
            i64s(&a["offsets"]),
        );
        let (kind, id, shape_code): (Vec<i32>, Vec<i64>, Vec<i32>) = (
            a["kind"]
                .chunks(4)
                .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
                .collect(),
            i64s(&a["id"]),
            a["shape"]
                .chunks(4)
                .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
                .collect(),
        );
        let n_body = kind.iter().filter(|&&k| k == 0).count();
        assert_eq!(n_body, rows.len(), "frame {k}: body cells");
        for (c, &(body, x, y, angle)) in rows.iter().enumerate() {
            assert_eq!(id[c] as u64, body, "frame {k}: cell {c}'s identity");
            let shape = &shapes[&body];
            let want = ["circle", "ellipse", "rectangle"]
                .iter()
                .position(|&s| s == shape["type"])
                .unwrap() as i32;
            assert_eq!(shape_code[c], want, "frame {k}: body {body}'s shape code");
            let from = if c == 0 { 0 } else { offsets[c - 1] as usize };
            let outline: Vec<(f64, f64)> = conn[from..offsets[c] as usize]
                .iter()
                .map(|&p| (points[3 * p as usize], points[3 * p as usize + 1]))
                .collect();
            let off = off_boundary(shape, &outline, x, y, angle);
            assert!(
                off <= 1e-9,
                "frame {k} (step {step}): body {body}'s outline is off its {shape} by {off:e}"
            );
            bodies_checked += 1;
        }
        frames += 1;
    }
    assert_eq!(frames, 7);
    assert!(bodies_checked >= 80, "{bodies_checked}");
    // And by VTK's own reader (tests/vtk_check.py reads inserted.csv likewise).
    if let Some(out) = vtk_check(&run) {
        assert!(out.contains("vtk check passed: 7 frames"), "{out}");
    }
}

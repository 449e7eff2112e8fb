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
use common::{dem2d, scratch};

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

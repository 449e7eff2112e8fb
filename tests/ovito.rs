//! OVITO reads `dem2d export --format lammps-dump`: `tests/ovito_check.py` opens the dumps of a
//! scene of ellipses, disks, a rectangle and a polygon and of a sheared periodic cell with
//! OVITO's own Python module (`pip install ovito`) and checks frame count, timesteps, times,
//! identities, positions (1e-9 cm), velocities, orientations (the quaternion's angle about z
//! against the trajectory's, mod π for ellipses and 2π for the others), Aspherical Shapes (an
//! ellipse's (a, b), a disk's (r, r), a polygon's bounding radius) and the cells against the
//! run's files; then renders the last frame offscreen with OVITO's Tachyon renderer and checks
//! the picture: not blank, every body drawn at its centre, every elongated ellipse along its
//! own axis. The picture is left at `TARGET_TMPDIR/ovito/ovito_render.png`.
//!
//! It needs a Python with the `ovito` module: `DEM2D_OVITO_PYTHON`, else
//! `target/ovito-venv/bin/python` (where `.ci/run` installs it), else `python3`. Without one it
//! says so and passes, unless `DEM2D_REQUIRE_OVITO` is set — as `.ci/run` sets it, so that CI
//! never skips it. The strict parser of the same format, `tests/export.rs`, always runs.

use std::path::Path;
use std::process::Command;

mod common;
use common::{MIXED_SCENE, dem2d, scratch, sheared_cell};

/// A Python that has OVITO's module.
fn ovito_python() -> Option<String> {
    let venv = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/ovito-venv/bin/python");
    let candidates: Vec<String> = std::env::var("DEM2D_OVITO_PYTHON")
        .into_iter()
        .chain([venv.to_string_lossy().into_owned(), "python3".to_string()])
        .collect();
    candidates.into_iter().find(|py| {
        Command::new(py)
            .args(["-c", "import ovito"])
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// Runs `case` into `dir/name` and exports its dump there (the default place).
fn run_and_export(dir: &Path, name: &str, case: &str) -> std::path::PathBuf {
    let file = dir.join(format!("{name}.json"));
    std::fs::write(&file, case).unwrap();
    let out = dir.join(name);
    let (code, _, err) = dem2d(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = dem2d(&["export", out.to_str().unwrap(), "--format", "lammps-dump"]);
    assert_eq!(code, 0, "{err}");
    out
}

#[test]
fn ovito_reads_the_dump_and_renders_it() {
    let dir = scratch("runs");
    let mix = run_and_export(&dir, "mix", MIXED_SCENE);
    let cell = run_and_export(&dir, "cell", &sheared_cell());
    let Some(py) = ovito_python() else {
        assert!(
            std::env::var_os("DEM2D_REQUIRE_OVITO").is_none(),
            "DEM2D_REQUIRE_OVITO is set but no Python with OVITO's module was found \
             (python3 -m venv target/ovito-venv && target/ovito-venv/bin/pip install ovito)"
        );
        eprintln!(
            "SKIPPED the OVITO check: no Python with OVITO's module (pip install ovito; \
             .ci/run installs it into target/ovito-venv)"
        );
        return;
    };
    let png = dir.join("ovito_render.png");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/ovito_check.py");
    let out = Command::new(&py)
        .arg(&script)
        .args([&mix, &cell, &png])
        .output()
        .expect("run the OVITO check");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("{stdout}{stderr}");
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(
        stdout.contains("ovito check passed: 11 frames, 7 bodies; 11 sheared-cell frames"),
        "{stdout}"
    );
    assert!(png.exists());
}

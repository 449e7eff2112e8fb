//! `dem2d-lab cross-check` against LAMMPS (`lmp`), in small: the state LAMMPS reads is dem2d's
//! (the data file round-trips to dem2d's loaded positions and radii), and the first force
//! evaluation from a static overlapping state gives the same σ_yy in both codes — the same
//! contacts through an independent implementation of the force law (LAMMPS's `pair_style
//! granular`). Skipped, with a note, where `lmp` is not installed (CI does not install LAMMPS:
//! Debian's `lammps` pulls in MPI and is not a quick install).

/// The numbers after `at most` in the report's round-trip sentences (cm).
fn roundtrips(md: &str) -> Vec<f64> {
    md.split("by at most ")
        .skip(1)
        .chain(md.split("Round trip of the data file: at most ").skip(1))
        .map(|s| s.split(' ').next().unwrap().parse::<f64>().unwrap())
        .collect()
}

/// The rows `| step | σ_yy dem2d | σ_yy LAMMPS | …` of the static table headed `name`.
fn static_rows(md: &str, name: &str) -> Vec<(f64, f64)> {
    let start = md
        .find(&format!("**Static state `{name}`**"))
        .expect("static table");
    md[start..]
        .lines()
        .skip_while(|l| !l.starts_with("|---"))
        .skip(1)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let f: Vec<&str> = l.split('|').map(str::trim).collect();
            (f[2].parse().unwrap(), f[3].parse().unwrap())
        })
        .collect()
}

#[test]
fn lammps_reads_dem2ds_state_and_finds_the_same_first_stress() {
    let have_lmp = std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join("lmp").is_file()));
    if !have_lmp {
        eprintln!("note: LAMMPS (`lmp`) is not installed: the cross-check test is skipped");
        return;
    }
    let work = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cross-check");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dem2d-lab"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args([
            "cross-check",
            "--dt",
            "5e-5",
            "--strain",
            "0.06",
            "--sample-strain",
            "0.015",
        ])
        .args(["--transient-strain", "0", "--work"])
        .arg(&work)
        .output()
        .expect("run dem2d-lab cross-check");
    let md = String::from_utf8(out.stdout).unwrap();
    assert!(
        out.status.success(),
        "{md}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Three states (two static, one sheared), each round-tripped to round-off (LAMMPS writes
    // 17 significant digits; the cell is ~20 cm: a few ulps of 20 is 1e-14).
    let rt = roundtrips(&md);
    assert_eq!(rt.len(), 3, "{md}");
    assert!(rt.iter().all(|&e| e <= 1e-13), "{rt:?}\n{md}");
    // The first evaluation from rest: the springs of the same overlaps (and, in the sheared
    // cell, the normal dashpots of the pairs across the seam, which see the image's velocity
    // γ̇ L_y) give σ_yy to round-off.
    for name in ["static", "static_unsheared"] {
        let rows = static_rows(&md, name);
        assert_eq!(rows.len(), 4, "{name}\n{md}");
        let (a, b) = rows[0];
        assert!(a > 1e3, "{name}: σ_yy {a} (the state must be loaded)");
        assert!((a - b).abs() <= 1e-12 * b.abs(), "{name}: {a} vs {b}\n{md}");
    }
    // Without shear the two integrators (velocity Verlet, the same time levels) agree on the
    // next step too.
    let (a, b) = static_rows(&md, "static_unsheared")[1];
    assert!((a - b).abs() <= 1e-12 * b.abs(), "step 1: {a} vs {b}\n{md}");
}

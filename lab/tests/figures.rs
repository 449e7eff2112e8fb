//! `dem2d-lab figures --quick` writes every figure and table the user guide embeds (and only
//! timings into its work directory); in the long form (`DEM2D_LONG_TESTS=1`) two runs write the
//! same bits. It runs the paper's cases through the `dem2d` binary, which `cargo test --release
//! --workspace` has built beside `dem2d-lab` (`DEM2D_BIN` is set to it, so that the lab does not
//! call cargo from inside a test).

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// Runs `dem2d-lab` in the repository's root with the `dem2d` binary beside it.
fn dem2d(args: &[&str]) -> (i32, String, String) {
    let lab = Path::new(env!("CARGO_BIN_EXE_dem2d-lab"));
    let dem2d = lab.with_file_name(format!("dem2d{}", std::env::consts::EXE_SUFFIX));
    assert!(
        dem2d.is_file(),
        "{}: no dem2d binary beside dem2d-lab (cargo build --release, or test the workspace)",
        dem2d.display()
    );
    let out = Command::new(lab)
        .args(args)
        .env("DEM2D_BIN", &dem2d)
        .current_dir(root())
        .output()
        .expect("run dem2d-lab");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("figures")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The user guide's pages and the README, with their text.
fn guide() -> Vec<(std::path::PathBuf, String)> {
    let root = root();
    let mut files = vec![root.join("README.md")];
    let mut dirs = vec![root.join("docs/src")];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "md") {
                files.push(p);
            }
        }
    }
    files.sort();
    files
        .into_iter()
        .map(|f| {
            let t = std::fs::read_to_string(&f).unwrap();
            (f, t)
        })
        .collect()
}

#[test]
fn figures_quick_writes_every_figure_and_table_of_the_guide() {
    let out = scratch("figures");
    let work = scratch("figure_runs");
    let before = guide();
    let figures = |out: &Path, work: &Path| {
        dem2d(&[
            "figures",
            "--quick",
            "--out",
            out.to_str().unwrap(),
            "--work",
            work.to_str().unwrap(),
        ])
    };
    let (code, stdout, err) = figures(&out, &work);
    assert_eq!(code, 0, "{err}");
    // Without --docs the guide is left alone.
    assert!(
        guide() == before,
        "dem2d figures without --docs changed the guide"
    );
    // Every figure the guide embeds and every table it includes.
    let mut wanted = Vec::new();
    for (_, text) in &before {
        for part in text.split("figures/").skip(1) {
            let Some(name) = part
                .split(')')
                .next()
                .filter(|n| n.ends_with(".svg") || n.ends_with(".png"))
            else {
                continue;
            };
            // The ParaView picture is pvpython's (figures/scripts/paraview_render.py), the
            // tutorial's pile `dem2d plot`'s, the Python tutorial's profile its script's
            // (docs/python/pour.py, with matplotlib); the research workflows' figures are `dem2d
            // study impacts|biaxial-shape|biaxial-periodic|packing|representation|jamming|shear|silo|drum`'s (minutes of runs); the
            // hopper's and the shear tutorial's are `dem2d run` and `dem2d plot` of their cases
            // (physics/segments.md, tutorials/shear-cell.md).
            let others = [
                "impacts.svg",
                "biaxial_shape.svg",
                "biaxial_periodic.svg",
                "force_chains.svg",
                "packing.svg",
                "representation_pareto.svg",
                "jamming.svg",
                "shear.svg",
                "silo.svg",
                "drum.svg",
                "tutorial_pile.png",
                "hopper_segments.svg",
                "tutorial_shear_cell.png",
                "python_pour.png",
                // The viewers' pictures: figures/scripts/player_screenshot.sh (Chromium) and
                // figures/scripts/ovito_render.py (OVITO) of the hopper's run (developer.md).
                "player_hopper.png",
                "ovito_hopper.png",
                // `dem2d-lab fields-forces`'s (a minute of runs; results/fields-forces.md).
                "fields_profiles.svg",
                "forces_pdf.svg",
            ];
            if !name.starts_with("paraview_") && !others.contains(&name) {
                wanted.push(name.to_string());
            }
        }
        for part in text.split("<!-- figures:").skip(1) {
            let name = part.split(" -->").next().unwrap();
            // The throughput, peer and kernel-speed tables are `dem2d bench [--peers]`'s and
            // `cargo bench`'s (minutes of timing); the studies' and verify's are theirs; the
            // LAMMPS cross-check's is `dem2d-lab cross-check`'s (LAMMPS installed).
            let others = [
                "bench",
                "peers",
                "lammps",
                "kernel_speed",
                "rolling_fig3",
                "repose",
                "repose_cohesion",
                "biaxial",
                "impacts",
                "biaxial_shape",
                "biaxial_periodic",
                "packing",
                "representation",
                "jamming",
                "shear",
                "silo",
                "drum",
                "verify",
                "verify_full",
            ];
            if !others.contains(&name) && !name.contains(char::is_uppercase) {
                wanted.push(format!("{name}.md"));
            }
        }
    }
    wanted.sort();
    wanted.dedup();
    assert!(wanted.len() >= 12, "{wanted:?}");
    for f in &wanted {
        let p = out.join(f);
        assert!(p.exists(), "figures did not write {f}; it wrote:\n{stdout}");
        assert!(
            std::fs::metadata(&p).unwrap().len() > 100,
            "{f} is almost empty"
        );
    }
    // The timings, and only they, go to the work directory.
    let timings = std::fs::read_to_string(work.join("timings.md")).unwrap();
    assert!(timings.contains("machine-dependent") && timings.contains("ns/pair"));
    // What goes to the output directory is the same bits every time (regenerating leaves a
    // clean tree). CI checks the full run against the tracked figures/ (`dem2d figures
    // --check`, then `git diff`); here, in the long form (`DEM2D_LONG_TESTS=1`), two quick runs
    // against each other.
    if std::env::var_os("DEM2D_LONG_TESTS").is_none_or(|v| v == "0") {
        return;
    }
    let (out2, work2) = (scratch("figures2"), scratch("figure_runs2"));
    let (code, _, err) = figures(&out2, &work2);
    assert_eq!(code, 0, "{err}");
    let mut files = 0;
    for entry in std::fs::read_dir(&out).unwrap() {
        let name = entry.unwrap().file_name();
        let (a, b) = (
            std::fs::read(out.join(&name)).unwrap(),
            std::fs::read(out2.join(&name)).unwrap(),
        );
        assert!(a == b, "{name:?} differs between two runs of figures");
        files += 1;
    }
    assert!(files >= 12);
}

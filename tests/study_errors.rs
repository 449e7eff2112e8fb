//! Error bars of `dem2d study shear` (issue 45, item 3): two seeds of a small shear cell give
//! values of μ that agree within their standard errors, `|μ₁ − μ₂| < 3 √(se₁² + se₂²)`; a run
//! with a loose `--precision` stops before the fixed strain with its se at most the precision;
//! bad `--precision` and `--seed` values are refused (exit code 2, naming the option); and
//! `study jamming --precision` adds rounds of packings until se(φ_J) reaches it.

mod common;
use common::{dem2d, scratch};

/// Grains of the small cell: 144 disks at I = 0.1, about 5 s a run (at 64 grains the stress is
/// correlated over so much of the strain 1.5 that a seed can leave μ's se unconverged, †).
const GRAINS: &str = "144";

/// A value `m ± s` of a table cell (a trailing `†` marks a se not converged).
fn pm(cell: &str) -> (f64, f64, bool) {
    let (m, s) = cell
        .split_once('±')
        .unwrap_or_else(|| panic!("no ± in {cell:?}"));
    let converged = !s.contains('†');
    let s = s.trim().trim_end_matches('†').trim();
    (m.trim().parse().unwrap(), s.parse().unwrap(), converged)
}

/// The shear study's single row: (μ, se, converged), φ's (m, se), the strain averaged.
fn shear(name: &str, extra: &[&str]) -> ((f64, f64, bool), (f64, f64), f64) {
    let out = scratch(name);
    let mut args = vec![
        "study",
        "shear",
        "--grains",
        GRAINS,
        "--aspects",
        "1",
        "--inertial",
        "0.1",
        "--threads",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, stdout, stderr) = dem2d(&args);
    assert_eq!(code, 0, "{stderr}");
    let row = stdout
        .lines()
        .find(|l| l.starts_with("| 1 | 0.1 |"))
        .unwrap_or_else(|| panic!("no row in {stdout}"));
    let cells: Vec<&str> = row.split('|').map(str::trim).collect();
    // | α | I target | I measured | μ | φ | S | angle | strain | steps |
    let mu = pm(cells[4]);
    let (phi, phi_se, _) = pm(cells[5]);
    let strain: f64 = cells[8].split_whitespace().next().unwrap().parse().unwrap();
    assert!(
        std::fs::read_to_string(out.join("shear.md"))
            .unwrap()
            .contains(row)
    );
    (mu, (phi, phi_se), strain)
}

#[test]
fn two_seeds_agree_within_their_errors() {
    let (m1, p1, strain1) = shear("seed1", &["--seed", "1"]);
    let (m2, p2, strain2) = shear("seed2", &["--seed", "2"]);
    eprintln!("seed 1: μ = {m1:?}, φ = {p1:?}; seed 2: μ = {m2:?}, φ = {p2:?}");
    // The fixed strain of the study (STRAIN_MEASURE), to the chunk.
    for s in [strain1, strain2] {
        assert!((s - 1.5).abs() < 0.01, "strain {s}");
    }
    // Different seeds: different draws.
    assert_ne!(m1.0, m2.0);
    for m in [m1, m2] {
        assert!(m.2, "μ's se not converged: {m:?}");
        assert!(m.1 > 0.0 && m.1 < 0.1 * m.0, "{m:?}");
    }
    assert!(
        (m1.0 - m2.0).abs() < 3.0 * m1.1.hypot(m2.1),
        "μ: {m1:?} against {m2:?}"
    );
    assert!(
        (p1.0 - p2.0).abs() < 3.0 * p1.1.hypot(p2.1),
        "φ: {p1:?} against {p2:?}"
    );
}

#[test]
fn a_loose_precision_stops_early() {
    let precision = 0.05;
    let (mu, _, strain) = shear("precision", &["--seed", "3", "--precision", "0.05"]);
    eprintln!("μ = {mu:?} over the strain {strain}");
    assert!(strain < 1.5, "ran the fixed strain: {strain}");
    assert!(mu.2 && mu.1 <= precision, "{mu:?}");
}

#[test]
fn bad_values_are_refused() {
    for (args, field) in [
        (&["--precision", "0"][..], "--precision"),
        (&["--precision=-0.01"][..], "--precision"),
        (&["--precision", "nan"][..], "--precision"),
        (&["--precision", "abc"][..], "--precision"),
        (&["--seed", "1.5"][..], "--seed"),
        (&["--seed=-1"][..], "--seed"),
    ] {
        let mut all = vec!["study", "shear", "--grains", "16"];
        all.extend_from_slice(args);
        let (code, _, err) = dem2d(&all);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(field), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

/// `dem2d study jamming --precision`: an aspect ratio whose first round of packings leaves
/// se(φ_J) above the precision gets more rounds, until it is at most the precision; its se is
/// the packings' sd (printed beside it) over √m.
#[test]
fn jamming_adds_packings_until_the_precision() {
    let out = scratch("jamming_precision");
    let (code, stdout, stderr) = dem2d(&[
        "study",
        "jamming",
        "--grains",
        "32",
        "--packings",
        "2",
        "--aspects",
        "2",
        "--seed",
        "5",
        "--precision",
        "0.002",
        "--threads",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let row = stdout
        .lines()
        .find(|l| l.starts_with("| 2 |"))
        .unwrap_or_else(|| panic!("no row in {stdout}"));
    let cells: Vec<&str> = row.split('|').map(str::trim).collect();
    // | α | φ_J | Z_J | sd of φ_J, of Z_J | rattlers | packings in the band | …
    let (phi, se, converged) = pm(cells[2]);
    let sd: f64 = cells[4].split(',').next().unwrap().trim().parse().unwrap();
    let m: f64 = cells[6].split_whitespace().next().unwrap().parse().unwrap();
    eprintln!("φ_J = {phi} ± {se} over {m} packings, sd {sd}");
    assert!(converged && se <= 0.002, "{row}");
    assert!(m > 2.0 && m % 2.0 == 0.0, "rounds of 2 packings: {row}");
    // The table's 4 decimals: se and sd/√m agree to their rounding.
    assert!(
        (se - sd / m.sqrt()).abs() <= 0.5e-4 * (1.0 + 1.0 / m.sqrt()),
        "{row}"
    );
}

//! Contact geometry against the independent high-precision reference
//! (`dem2d_validation::reference`: double-double, parametric boundary ∩ implicit form solved as
//! a quartic, no pencil, no cubic), over the families of hard cases of
//! `dem2d_validation::families`.
//!
//! Bars (from the kernel issue): |depth error| ≤ 1e-12·a_max; normal angle error ≤ 1e-8 rad;
//! contact point error ≤ 1e-9·a_max plus two ulps of the coordinates (far from the origin);
//! classification right whenever the true gap or depth is at least 1e-12·a_max; the same results
//! after a rigid motion of the pair and after swapping i and j. Corner-on-corner rectangle
//! contacts are held to the conditioning of their chord instead (see docs/src/validation/geometry.md).

use dem2d_validation::families::{markdown_table, run_families};

#[test]
fn contact_geometry_matches_high_precision_reference() {
    let reports = run_families();
    let table = markdown_table(&reports, None);
    println!("{table}");
    // The user guide's accuracy table (dem2d figures) comes from the same families.
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("kernel_accuracy.md");
    std::fs::write(&out, &table).expect("write target/tmp/kernel_accuracy.md");
    let failures: Vec<&String> = reports
        .iter()
        .flat_map(|r| r.failures.iter().take(5))
        .collect();
    assert!(
        failures.is_empty(),
        "{} failures, first ones:\n{}",
        failures.len(),
        failures
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
    assert!(reports.iter().all(|r| r.cases > 0));
}

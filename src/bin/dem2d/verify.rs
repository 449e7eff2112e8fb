//! `dem2d verify`: the benchmarks with known answers, each comparison printed as
//! `quantity | dem2d | reference | tolerance | pass/fail`, exit status 1 if any fails.
//!
//! - `--quick` (CI, a few seconds): the impact benchmarks (closed forms), the Love–Weber
//!   stress of a servo-compacted sample of 100 disks against its boundary stress (1 %), and
//!   ellipses under the area law against closed forms and a conservation law (rocking period,
//!   tilted drop, incline equilibrium, loop work: [`crate::verify_ellipses`]).
//! - default (about a minute): also the published trend of the biaxial test — the residual
//!   stress ratio grows with the grains' elongation (Rothenburg & Bathurst 1992; Azéma & Radjaï 2010;
//!   Saint-Cyr et al. 2012) — on samples of 144 grains, α = 1 and 2; and the packing fraction
//!   of 300 frictionless bidisperse disks poured into a box against the jamming fraction of that
//!   mixture.
//! - `--full` (about half an hour): the biaxial trend on the user guide's samples (2025 grains,
//!   α = 1, 1.5, 2, 2.5), each α against the next; and the poured frictionless ellipses at
//!   α = 1.5 against the published maxima of φ_J(α) and the hypostatic plateau of Z_J; jamming
//!   by FIRE in a periodic cell (64 grains, disks and α = 2) and Lees–Edwards shear of disks at
//!   I = 0.01 and 0.1 against the published φ_J, Z_J and μ(I), φ(I) ([`periodic_checks`]).

use crate::study::{biaxial_shape, impacts, jamming, packing, shear};
use dem2d::analysis::{self, Frame};
use dem2d::run::RunError;
use dem2d::scene::Case;
use dem2d::scene::servo_box::ServoBox;
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    Quick,
    Default,
    Full,
}

impl Level {
    /// The name of this level's marked table in the user guide (`dem2d verify --docs`).
    pub fn table_name(self) -> &'static str {
        match self {
            Level::Quick => "verify_quick",
            Level::Default => "verify",
            Level::Full => "verify_full",
        }
    }
}

/// One comparison, as a row of the table: what is compared, dem2d's value, the reference and
/// the tolerance (as text), and whether it passes.
pub struct Check {
    pub quantity: String,
    pub value: f64,
    pub reference: String,
    pub tolerance: String,
    pub pass: bool,
}

impl Check {
    /// `value` against `expected` within the relative tolerance `tol`; `source` (shown after
    /// `expected`) says where `expected` comes from.
    pub fn relative(quantity: String, value: f64, expected: f64, source: &str, tol: f64) -> Check {
        Check {
            quantity,
            value,
            reference: format!("{expected:.6e} ({source})"),
            tolerance: format!("{tol:.0e} relative"),
            pass: ((value - expected) / expected).abs() <= tol,
        }
    }

    /// `value` in the closed interval `band`, which the table shows as `tolerance`.
    pub fn within(
        quantity: String,
        value: f64,
        reference: impl Into<String>,
        (lo, hi): (f64, f64),
        tolerance: impl Into<String>,
    ) -> Check {
        Check {
            quantity,
            value,
            reference: reference.into(),
            tolerance: tolerance.into(),
            pass: (lo..=hi).contains(&value),
        }
    }
}

fn relative(rows: Vec<impacts::Row>) -> Vec<Check> {
    rows.into_iter()
        .map(|(q, v, r, tol)| Check::relative(q, v, r, "closed form", tol))
        .collect()
}

/// Love–Weber against the boundary stress of a compacted 10 × 10 disk sample.
fn stress_checks() -> Result<Vec<Check>, RunError> {
    let spec = ServoBox {
        n_side: 10,
        aspect: 1.0,
        friction: 0.5,
        sigma: 1e5,
        seed: 3,
    };
    let case = Case::from_json(&spec.compaction_case(5.0)).expect("valid case");
    let mut w = case.build_world();
    biaxial_shape::compact(&mut w, 5.0)?;
    w.refresh_contact_extras();
    let m = analysis::measure(&Frame::from_world(&w), None);
    let p = 0.5 * (m.boundary_stress[0] + m.boundary_stress[1]);
    Ok(["xx", "yy", "xy"]
        .iter()
        .enumerate()
        .map(|(k, c)| Check {
            quantity: format!("servo-compacted 100 disks: Love–Weber σ_{c} (dyn/cm²)"),
            value: m.stress[k],
            reference: format!(
                "{:.6e} (boundary stress from the wall forces)",
                m.boundary_stress[k]
            ),
            tolerance: "1 % of the mean stress".into(),
            pass: (m.stress[k] - m.boundary_stress[k]).abs() <= 0.01 * p,
        })
        .collect())
}

/// The residual stress ratio (the mean over the last 2 % of axial strain) grows with elongation.
fn biaxial_checks(n_side: usize, aspects: &[f64], strain: f64) -> Result<Vec<Check>, RunError> {
    let results: Vec<biaxial_shape::Outcome> = aspects
        .iter()
        .map(|&a| biaxial_shape::run_one(n_side, a, strain, 11, false))
        .collect::<Result<_, _>>()?;
    Ok(results
        .windows(2)
        .map(|w| Check {
            quantity: format!(
                "biaxial, {} grains: residual (σ₁−σ₃)/(σ₁+σ₃) at α = {}",
                n_side * n_side,
                w[1].aspect
            ),
            value: w[1].residual_ratio,
            reference: format!(
                "> {:.4} at α = {} (strength grows with elongation: Azéma & Radjaï 2010)",
                w[0].residual_ratio, w[0].aspect
            ),
            tolerance: "inequality".into(),
            pass: w[1].residual_ratio > w[0].residual_ratio,
        })
        .collect())
}

/// Poured frictionless piles against the jamming literature: disks (α = 1) always, ellipses of
/// α = 1.5 with `ellipses`. The bands are the published values (see the user guide's packing
/// section); below them 1 % is allowed for the protocol (gravity deposition with finite
/// stiffness, not isotropic compression to jamming).
fn packing_checks(ellipses: bool) -> Result<Vec<Check>, RunError> {
    let mut checks = Vec::new();
    let disks = packing::pour(1.0, 0.0, packing::N, false)?;
    checks.push(Check::within(
        format!(
            "{} frictionless bidisperse disks poured: packing fraction",
            packing::N
        ),
        disks.packing,
        "φ_J ≈ 0.84 (fast) … 0.853 (slow protocols), 1:1.4 disks (Schreck, O'Hern & Silbert 2011)",
        (0.99 * 0.84, 0.853),
        "[0.99 × 0.84, 0.853]",
    ));
    if ellipses {
        let e = packing::pour(1.5, 0.0, packing::N, false)?;
        checks.push(Check::within(
            format!(
                "{} frictionless bidisperse ellipses α = 1.5 poured: packing fraction",
                packing::N
            ),
            e.packing,
            "maxima of φ_J(α) 0.891 … 0.8974 at α = 1.30 … 1.45 (Delaney 2005, Donev 2007, VanderWerf 2018, Rocks & Hoy 2023, as tabulated by Hoy 2024)",
            (0.99 * 0.891, 1.01 * 0.8974),
            "[0.99 × 0.891, 1.01 × 0.8974]",
        ));
        checks.push(Check::within(
            format!(
                "{} frictionless bidisperse ellipses α = 1.5 poured: coordination (no rattlers)",
                packing::N
            ),
            e.z_no_rattlers,
            "hypostatic plateau 5.5 ≲ Z_J ≲ 5.8 for 1.5 ≲ α ≲ 3 (Hoy 2024's summary)",
            (5.5, 5.8),
            "[5.5, 5.8]",
        ));
    }
    Ok(checks)
}

/// Periodic cells against the jamming and μ(I) literature (`--full`): isotropic jamming of 64
/// frictionless bidisperse grains by FIRE (four packings each of disks and of ellipses α = 2,
/// the bands of the jamming page's published values) and steady Lees–Edwards shear of 256
/// frictional disks at I = 0.01 and 0.1 against da Cruz et al.'s linear laws (as the shear
/// page gives them: μ_min ≈ 0.25, b ≈ 1, φ_max ≈ 0.80–0.81, a ≈ 0.3).
fn periodic_checks() -> Result<Vec<Check>, RunError> {
    let mut checks = Vec::new();
    let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
    for (aspect, phi_band, z_band, z_ref) in [
        (
            1.0,
            (0.83, 0.85),
            (3.9, 4.1),
            "Z_J = 4 (O'Hern et al. 2003), 0.1 allowed",
        ),
        (
            2.0,
            (0.87, 0.90),
            (5.4, 5.9),
            "hypostatic 5.5–5.8 for 1.5 ≤ α ≤ 3 (Schreck 2010, VanderWerf 2018)",
        ),
    ] {
        let packings: Vec<jamming::Packing> = (0..4).map(|s| jamming::jam(64, aspect, s)).collect();
        let phi: Vec<f64> = packings.iter().map(|p| p.phi).collect();
        let z: Vec<f64> = packings.iter().map(|p| p.z).collect();
        let (phi, z) = (mean(&phi), mean(&z));
        let band = |(lo, hi): (f64, f64)| format!("[{lo}, {hi}]");
        checks.push(Check::within(
            format!("jamming by FIRE, 4 × 64 frictionless bidisperse grains, α = {aspect}: φ_J"),
            phi,
            if aspect == 1.0 {
                "φ_J ≈ 0.84 (O'Hern et al. 2003; 64 grains lie a little below)"
            } else {
                "φ_J(2) ≈ 0.88 on the published curve (VanderWerf et al. 2018)"
            },
            phi_band,
            band(phi_band),
        ));
        checks.push(Check::within(
            format!("jamming by FIRE, 4 × 64 frictionless bidisperse grains, α = {aspect}: Z_J (rattlers out)"),
            z,
            z_ref,
            z_band,
            band(z_band),
        ));
    }
    for i in [0.01, 0.1] {
        let f = shear::shear(shear::N, 1.0, i, 0, None)?;
        let inertial = f.inertial.mean;
        let what = |q: &str| {
            format!(
                "Lees–Edwards shear, {} disks μ_p = 0.4, I = {:.4}: {q}",
                shear::N,
                inertial
            )
        };
        let (mu_lo, mu_hi) = (0.2 + 0.7 * inertial, 0.3 + 1.3 * inertial);
        checks.push(Check::within(
            what("μ"),
            f.mu.mean,
            "μ_min + b I, μ_min ≈ 0.25, b ≈ 1 (da Cruz et al. 2005)",
            (mu_lo, mu_hi),
            format!("[0.2 + 0.7 I, 0.3 + 1.3 I] = [{mu_lo:.3}, {mu_hi:.3}]"),
        ));
        let (phi_lo, phi_hi) = (0.79 - 0.4 * inertial, 0.82 - 0.2 * inertial);
        checks.push(Check::within(
            what("φ"),
            f.phi.mean,
            "φ_max − a I, φ_max ≈ 0.80–0.81, a ≈ 0.3 (da Cruz et al. 2005)",
            (phi_lo, phi_hi),
            format!("[0.79 − 0.4 I, 0.82 − 0.2 I] = [{phi_lo:.4}, {phi_hi:.4}]"),
        ));
    }
    Ok(checks)
}

/// Runs the checks of `level` and prints them as a Markdown table (the wall time on a line of
/// its own after it); returns whether all pass, and the table (without the wall time, which is
/// the machine's and not the code's). A run that blows up is the error.
pub fn run(level: Level) -> Result<(bool, String), RunError> {
    use std::fmt::Write as _;
    let start = Instant::now();
    let mut checks = relative(impacts::normal_rows()?);
    checks.extend(relative(impacts::oblique_rows(&[40.0, 60.0, 80.0])?));
    checks.extend(stress_checks()?);
    checks.extend(crate::verify_ellipses::checks()?);
    match level {
        Level::Quick => {}
        Level::Default => {
            checks.extend(biaxial_checks(12, &[1.0, 2.0], 0.08)?);
            checks.extend(packing_checks(false)?);
        }
        Level::Full => {
            checks.extend(biaxial_checks(45, &[1.0, 1.5, 2.0, 2.5], 0.1)?);
            checks.extend(packing_checks(true)?);
            checks.extend(periodic_checks()?);
        }
    }
    let mut md = String::from(
        "| quantity | dem2d | reference | tolerance | result |\n|---|---:|---|---|---|\n",
    );
    for c in &checks {
        writeln!(
            md,
            "| {} | {:.6e} | {} | {} | {} |",
            c.quantity,
            c.value,
            c.reference,
            c.tolerance,
            if c.pass { "pass" } else { "FAIL" }
        )
        .expect("a string");
    }
    let failed = checks.iter().filter(|c| !c.pass).count();
    writeln!(md, "\n{} comparisons, {failed} failed.", checks.len()).expect("a string");
    println!("{md}wall time {:.1} s", start.elapsed().as_secs_f64());
    Ok((failed == 0, md))
}

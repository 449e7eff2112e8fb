//! Steady simple shear at imposed pressure in a Lees–Edwards cell: μ(I) and φ(I) of frictional
//! disks and ellipses (GDR MiDi, Eur. Phys. J. E 14 (2004) 341; for 2D disks da Cruz, Emam,
//! Prochnow, Roux & Chevoir, PRE 72 (2005) 021309).
//!
//! `dem2d study shear` writes `figures/shear.svg` and `figures/shear.md` and prints the table.
//! Each run: [`N`] grains (`--grains`) with equal-area diameters uniform in [0.8, 1.2] [`D`]
//! (ellipses `a = r√α`, `b = r/√α`), density [`RHO`], on a square lattice wide enough for the
//! longest grain, random orientations, in a cell periodic in x and y sheared at γ̇ with the
//! normal stress σ_yy held at [`P`] (`dynamics::cell`): the cell first shrinks to the pressure,
//! then shears; the initial velocity is the affine profile `v_x = γ̇ (y − L_y/2)`. The
//! shear rate is set from the target inertial number, `γ̇ = I √(P/ρ)/d` (d the mean
//! diameter); the table gives the I measured from the mean σ_yy. Linear law on the overlap
//! area (the default), stiffness level `κ = k_n/P` = [`KAPPA`], `k_s = k_n/2`, restitution
//! [`RESTITUTION`], friction [`FRICTION`], no gravity, Δt a fiftieth of the smallest grains'
//! contact time. Averages over the strain [`STRAIN_SETTLE`] … [`STRAIN_SETTLE`] +
//! [`STRAIN_MEASURE`] (the start later where the cell needs longer to shrink to the pressure): μ = −⟨σ_xy⟩/⟨σ_yy⟩ (Love–Weber with the kinetic part), φ the grains'
//! area over the cell's, and for ellipses the nematic order `S = |⟨e^{2iθ}⟩|` and the mean
//! orientation `θ̄ = ½ arg⟨e^{2iθ}⟩` of the long axes against the flow (x).

use super::{Table, grain, line_fit};
use dem2d::analysis::statistics::{self, Estimate, ratio_se, series_se};
use dem2d::contact_law::{ContactSpec, LinearDamping, Scaled};
use dem2d::dynamics::BodyInit;
use dem2d::dynamics::World;
use dem2d::dynamics::cell::{Cell, Periodic, Pressure};
use dem2d::geometry::{Shape, Vec2};
use dem2d::output::plot::{self, LinePanel, Series};
use dem2d::run::{RunError, Simulation};
use dem2d::scene::Case;
use dem2d::scene::generate::Xorshift;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::time::Instant;

/// Grains per cell by default.
pub const N: usize = 256;
/// The aspect ratios by default.
pub const ASPECTS: [f64; 4] = [1.0, 1.5, 2.0, 3.0];
/// The target inertial numbers by default.
pub const INERTIAL: [f64; 4] = [0.01, 0.03, 0.1, 0.3];
/// The inertial number added for disks by default: the quasi-static end, where da Cruz et al.'s
/// μ_min and φ_max are read. Its run takes ten times I = 0.01's steps (6.3 million), so
/// ellipses (whose steps cost about three times a disk's) get it only through `--inertial`.
pub const QUASI_STATIC: f64 = 0.001;
/// Mean equal-area diameter (cm).
pub const D: f64 = 1.0;
/// Density (g/cm³, of a 1 cm slice).
pub const RHO: f64 = 1.0;
/// The imposed σ_yy (dyn/cm² per unit thickness).
pub const P: f64 = 100.0;
/// Stiffness level k_n/P.
pub const KAPPA: f64 = 1e4;
/// Coefficient of restitution.
pub const RESTITUTION: f64 = 0.1;
/// Coefficient of friction between grains.
pub const FRICTION: f64 = 0.4;
/// Shear strain before the averages start.
pub const STRAIN_SETTLE: f64 = 0.5;
/// Shear strain over which the averages run.
pub const STRAIN_MEASURE: f64 = 1.5;

/// With `--precision`, a run measures until the standard error of μ is at most the precision,
/// or until this many times [`STRAIN_MEASURE`] (the table then says the precision was not
/// reached).
pub const PRECISION_CAP: f64 = 10.0;
/// The samples (chunk means) over [`STRAIN_MEASURE`]: a run averages its steps in chunks of
/// `STRAIN_MEASURE / SAMPLES` of strain and the error bars are read from the chunks' series.
pub const SAMPLES: u64 = 4096;

/// One steady shear run: each number with its standard error (`analysis::statistics`: the
/// chunk series blocked at the length chosen from its autocorrelation; μ by the delta method).
#[derive(Clone, Copy, Debug)]
pub struct Flow {
    pub aspect: f64,
    pub target: f64,
    pub inertial: Estimate,
    pub mu: Estimate,
    pub phi: Estimate,
    pub order: Estimate,
    /// The mean angle of the long axes to the flow (°).
    pub angle: Estimate,
    pub steps: u64,
    /// The strain the averages ran over.
    pub strain: f64,
    /// With a precision: whether the se of μ reached it.
    pub reached: Option<bool>,
}

/// The world of a run at `aspect` sheared at `rate`, its grains drawn from `seed` (seed 0 is the
/// study's historical draw).
fn world(n: usize, aspect: f64, rate: f64, seed: u64) -> World {
    let state = 0x9E37_79B9_7F4A_7C15 ^ aspect.to_bits() ^ seed.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let mut rng = Xorshift(if state == 0 { 1 } else { state });
    let side_count = (n as f64).sqrt().ceil() as usize;
    let longest = 0.6 * D * aspect.sqrt();
    let spacing = 2.1 * longest;
    let side = spacing * side_count as f64;
    let bodies = (0..n)
        .map(|k| {
            let shape = grain(0.5 * D * (0.8 + 0.4 * rng.uniform()), aspect);
            let position = Vec2::new(
                spacing * ((k % side_count) as f64 + 0.5),
                spacing * ((k / side_count) as f64 + 0.5),
            );
            BodyInit {
                material: 0,
                prescribed: false,
                shape,
                position,
                angle: std::f64::consts::PI * rng.uniform(),
                velocity: Vec2::new(rate * (position.y - 0.5 * side), 0.0),
                omega: 0.0,
                density: RHO,
            }
        })
        .collect();
    let kn = KAPPA * P;
    let law = ContactSpec::linear(
        Scaled::Absolute(kn),
        Scaled::Absolute(0.5 * kn),
        LinearDamping::Restitution(RESTITUTION),
        FRICTION,
    );
    // A fiftieth of the contact time of two of the smallest grains.
    let m = RHO * std::f64::consts::PI * (0.4 * D) * (0.4 * D);
    let dt = std::f64::consts::PI * (0.5 * m / kn).sqrt() / 50.0;
    let cell = Cell::new(
        Vec2::new(side, side),
        Periodic::XY,
        rate,
        Some(Pressure {
            target: P,
            gain: dem2d::dynamics::cell::PRESSURE_RELAXATION,
        }),
    );
    Case::new(bodies, Vec::new(), Vec2::zeros(), law, dt)
        .with_cell(cell)
        .build_world()
}

/// The orientation order `S = |⟨e^{2iθ}⟩|` and the mean angle `½ arg⟨e^{2iθ}⟩` (°) from the
/// series of the grains' mean `cos 2θ` and `sin 2θ`, with their se by the delta method on the
/// linearised series (`S`: `(c̄ c_t + s̄ s_t)/S`; the angle: `(c̄ s_t − s̄ c_t)/(2 S²)` rad).
fn orientation(c: &[f64], s: &[f64]) -> (Estimate, Estimate) {
    let (cm, sm) = (statistics::mean(c), statistics::mean(s));
    let order = cm.hypot(sm);
    let lin = |f: &dyn Fn(f64, f64) -> f64| -> Vec<f64> {
        c.iter().zip(s).map(|(&x, &y)| f(x, y)).collect()
    };
    let u = series_se(&lin(&|x, y| (cm * x + sm * y) / order));
    let v = series_se(&lin(&|x, y| (cm * y - sm * x) / (2.0 * order * order)));
    (
        Estimate { mean: order, ..u },
        Estimate {
            mean: 0.5 * sm.atan2(cm).to_degrees(),
            se: v.se.to_degrees(),
            ..v
        },
    )
}

/// Shears `n` grains of aspect ratio `aspect` at the target inertial number `target`, the
/// grains drawn from `seed`; with `precision`, measures until the se of μ is at most it (at
/// least 1/16 of [`STRAIN_MEASURE`], at most [`PRECISION_CAP`] times it), else over
/// [`STRAIN_MEASURE`].
pub fn shear(
    n: usize,
    aspect: f64,
    target: f64,
    seed: u64,
    precision: Option<f64>,
) -> Result<Flow, RunError> {
    let rate = target * (P / RHO).sqrt() / D;
    let mut w = world(n, aspect, rate, seed);
    let total_area: f64 = w.bodies.shape.iter().map(Shape::area).sum();
    let mean_d = w
        .bodies
        .shape
        .iter()
        .map(|s| 2.0 * s.equal_area_radius())
        .sum::<f64>()
        / n as f64;
    // The averages start after the strain STRAIN_SETTLE and after three times the steps the
    // cell needs to shrink from the lattice to φ = 0.85 at its largest stretch per step (a fast
    // shear covers its strain before the cell has reached the pressure).
    let phi0 = total_area / w.cell.as_ref().expect("a cell").area();
    let shrink = 3.0 * (0.85 / phi0).ln() / dem2d::dynamics::cell::MAX_STRETCH;
    let settle = ((STRAIN_SETTLE / (rate * w.dt)).max(shrink)).ceil() as u64;
    let measure = (STRAIN_MEASURE / (rate * w.dt)).ceil() as u64;
    let chunk = (measure / SAMPLES).max(1);
    let last = settle
        + match precision {
            Some(_) => (PRECISION_CAP * measure as f64).ceil() as u64,
            None => measure,
        };
    // Per chunk: the means of σ_xy, σ_yy and φ over its steps, and the grains' mean cos 2θ and
    // sin 2θ at its end.
    let (mut xy, mut yy, mut ph, mut c2, mut s2) = (vec![], vec![], vec![], vec![], vec![]);
    let (mut a_xy, mut a_yy, mut a_ph) = (0.0, 0.0, 0.0);
    let mut check = (SAMPLES / 16) as usize;
    let mut reached = false;
    Simulation::new(&mut w).until_step(last).run_until(|w, _| {
        if w.step <= settle {
            return false;
        }
        let c = w.cell.as_ref().expect("a cell");
        a_xy += c.shear_stress();
        a_yy += c.normal_stress();
        a_ph += total_area / c.area();
        if !(w.step - settle).is_multiple_of(chunk) {
            return false;
        }
        let k = chunk as f64;
        xy.push(-a_xy / k);
        yy.push(a_yy / k);
        ph.push(a_ph / k);
        (a_xy, a_yy, a_ph) = (0.0, 0.0, 0.0);
        if aspect != 1.0 {
            let (mut c, mut s) = (0.0, 0.0);
            for b in &w.bodies.state {
                let t = 2.0 * b.pose.angle();
                c += t.cos();
                s += t.sin();
            }
            c2.push(c / n as f64);
            s2.push(s / n as f64);
        }
        // The se of μ, at chunk counts growing by a tenth (the check costs a pass over the
        // series per lag of its window).
        if let Some(p) = precision
            && xy.len() >= check
        {
            check = (check + check / 10).max(check + 64);
            let e = ratio_se(&xy, &yy);
            reached = e.converged && e.se <= p;
            return reached;
        }
        false
    })?;
    let steps = w.step;
    let mu = ratio_se(&xy, &yy);
    let s_yy = series_se(&yy);
    let inertial = rate * mean_d / (s_yy.mean / RHO).sqrt();
    // I ∝ σ_yy^(−1/2): se(I) = I se(σ_yy) / (2 σ_yy).
    let inertial = Estimate {
        mean: inertial,
        se: 0.5 * inertial * s_yy.se / s_yy.mean,
        ..s_yy
    };
    let (order, angle) = if aspect == 1.0 {
        let none = Estimate {
            mean: f64::NAN,
            se: f64::NAN,
            ..mu
        };
        (none, none)
    } else {
        orientation(&c2, &s2)
    };
    Ok(Flow {
        aspect,
        target,
        inertial,
        mu,
        phi: series_se(&ph),
        order,
        angle,
        steps,
        strain: (xy.len() as u64 * chunk) as f64 * rate * w.dt,
        reached: precision.map(|p| reached || (mu.converged && mu.se <= p)),
    })
}

/// The study's runs, `(α, target I)`: every aspect ratio at every inertial number of `targets`,
/// or by default at [`INERTIAL`], with disks also at [`QUASI_STATIC`].
pub fn jobs(aspects: &[f64], targets: Option<&[f64]>) -> Vec<(f64, f64)> {
    aspects
        .iter()
        .flat_map(|&a| {
            let extra = (targets.is_none() && a == 1.0).then_some(QUASI_STATIC);
            let each = targets.unwrap_or(&INERTIAL).iter().copied();
            extra.into_iter().chain(each).map(move |i| (a, i))
        })
        .collect()
}

/// Runs the study's `jobs` (see [`jobs`] and the module documentation), the grains drawn from
/// `seed`, each run measuring to `precision` on μ when given (see [`shear`]).
pub fn run(
    n: usize,
    aspects: &[f64],
    targets: Option<&[f64]>,
    seed: u64,
    precision: Option<f64>,
) -> Result<String, RunError> {
    let start = Instant::now();
    let mut jobs = jobs(aspects, targets);
    eprintln!(
        "dem2d study shear: {} runs of {n} grains ({} aspect ratios), seed {seed}{}",
        jobs.len(),
        aspects.len(),
        precision.map_or(String::new(), |p| format!(", to se(μ) ≤ {p}"))
    );
    // The slowest runs (a run's steps go as 1/I) start first, so that they do not end alone.
    jobs.sort_by(|x, y| x.1.total_cmp(&y.1));
    let mut done: Vec<Flow> = jobs
        .par_iter()
        .map(|&(a, i)| {
            let f = shear(n, a, i, seed, precision)?;
            eprintln!(
                "  α = {a}, I = {i}: μ = {} (g = {:.0} chunks, blocks of {}), φ = {} ({} steps, \
                 strain {:.2})",
                f.mu.pm(4),
                f.mu.inefficiency,
                f.mu.block,
                f.phi.pm(4),
                f.steps,
                f.strain
            );
            Ok(f)
        })
        .collect::<Result<_, RunError>>()?;
    done.sort_by(|x, y| (x.aspect.total_cmp(&y.aspect)).then(x.target.total_cmp(&y.target)));
    let mut table = Table::new(
        "| α | I (target) | I (measured) | μ = −σ_xy/σ_yy | φ | nematic order S | mean angle to the flow (°) | strain averaged | steps |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    );
    for f in &done {
        let (s, t) = if f.aspect == 1.0 {
            ("—".to_string(), "—".to_string())
        } else {
            (f.order.pm(3), f.angle.pm(1))
        };
        let short = match f.reached {
            Some(false) => " (precision not reached)",
            _ => "",
        };
        table.row(format!(
            "| {} | {} | {} | {} | {} | {s} | {t} | {:.2}{short} | {} |",
            f.aspect,
            f.target,
            f.inertial.pm(4),
            f.mu.pm(4),
            f.phi.pm(4),
            f.strain,
            f.steps
        ));
    }
    let mut md = table.text();
    let _ = writeln!(md);
    for &a in aspects {
        let of: Vec<&Flow> = done.iter().filter(|f| f.aspect == a).collect();
        if of.len() < 2 {
            continue;
        }
        let mu: Vec<(f64, f64)> = of.iter().map(|f| (f.inertial.mean, f.mu.mean)).collect();
        let phi: Vec<(f64, f64)> = of.iter().map(|f| (f.inertial.mean, f.phi.mean)).collect();
        let (mu0, b) = line_fit(&mu);
        let (phi0, a_phi) = line_fit(&phi);
        let _ = writeln!(
            md,
            "- α = {a}: μ ≈ {mu0:.3} + {b:.2} I, φ ≈ {phi0:.4} − {:.3} I (least squares over the {} runs).",
            -a_phi,
            of.len()
        );
    }
    let wall = start.elapsed().as_secs_f64();
    let _ = writeln!(
        md,
        "\n± one standard error: each run's chunk series blocked at the length chosen from its \
         autocorrelation (Flyvbjerg–Petersen blocking, `analysis::statistics`; μ by the delta \
         method){}. Seed {seed}{}. {} runs of {n} grains, {wall:.0} s of wall time on {}.",
        if done.iter().any(|f| !f.mu.converged) {
            "; † a series shorter than its correlation time wants (its se may be low)"
        } else {
            ""
        },
        precision.map_or(String::new(), |p| format!(", each run to se(μ) ≤ {p}")),
        done.len(),
        super::threads()
    );
    let series = |phi: bool| -> Vec<Series> {
        aspects
            .iter()
            .enumerate()
            .map(|(k, &a)| Series {
                label: format!("α = {a}"),
                points: done
                    .iter()
                    .filter(|f| f.aspect == a)
                    .map(|f| (f.inertial.mean, if phi { f.phi.mean } else { f.mu.mean }))
                    .collect(),
                y_errors: done
                    .iter()
                    .filter(|f| f.aspect == a)
                    .map(|f| if phi { f.phi.se } else { f.mu.se })
                    .collect(),
                color: k,
                line: true,
                markers: true,
                ..Default::default()
            })
            .collect()
    };
    let panels = [
        LinePanel {
            title: "Effective friction".into(),
            x_label: "inertial number I (–)".into(),
            y_label: "μ = −σ_xy/σ_yy (–)".into(),
            log_x: true,
            series: series(false),
            legend: plot::Legend::Auto,
            ..Default::default()
        },
        LinePanel {
            title: "Packing fraction".into(),
            x_label: "inertial number I (–)".into(),
            y_label: "φ (–)".into(),
            log_x: true,
            series: series(true),
            legend: plot::Legend::Auto,
            ..Default::default()
        },
    ];
    super::write_figure("shear", (1200, 480), (1, 2), &panels)?;
    super::write_text("shear.md", &md)?;
    Ok(md)
}

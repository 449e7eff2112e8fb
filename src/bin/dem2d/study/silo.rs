//! Discharge of a flat-bottomed 2D silo through an outlet of width D: the rate W(D) of disks
//! against Beverloo's law, of ellipses (α = 2, 3), and the probability that a small outlet
//! clogs.
//!
//! `dem2d study silo` prints the tables, writes `figures/silo.svg` and `figures/silo.md`.
//! The silo: side walls (half-planes) [`WIDTH`] cm apart; a flat floor at y = 0 of two segment
//! walls from the side walls to the outlet's edges at x = ±D/2 (their ends are points: the
//! outlet's edges are sharp); below it an outflow region (y < −2 cm) that removes
//! the grains, and an insertion region at the top that keeps [`N`] grains in the silo (each
//! discharged grain is replaced: the usual trick for a steady flow). The grains: equal-area
//! radius uniform in [0.45, 0.55] cm (mean diameter d = 1 cm; the spread keeps disks from
//! crystallising), disks or ellipses of aspect ratio α with `a = r√α, b = r/√α`, density 2.5,
//! linear law on the overlap area with k_n/ρg = 2000 cm, restitution 0.5, friction 0.5 (walls
//! and floor alike), Δt = 1e-4 s. They are poured at t = 0 into the silo (the first inserter
//! places [`FILL`] at once in the box, the second tops up to [`N`] from above), flow from the start, and the rate is the
//! mass discharged between [`T0`] and [`T1`] divided by the interval.
//!
//! Beverloo's law in 2D, `W = C ρ_b √g (D − k d)^{3/2}`, with ρ_b = ρ φ the bulk density (φ the
//! packing fraction in the column, measured): fitted by least squares on `W^{2/3}` against D
//! (a line: slope `(C ρ_b √g)^{2/3}`, root `k d`) over the disks' outlets D/d ≥ 3.
//! For elongated grains Pongó et al. (PRE 103, 062905, 2021) find `W ∝ exp(κ D)` below
//! D/d ≈ 3 rather than a power law: the ellipses' rates are fitted both ways (Beverloo over the
//! outlets that flowed, the exponential through the three smallest of them).
//!
//! Clogging: for small outlets, [`TRIALS`] runs with different seeds (different fillings); a
//! run clogs when no grain leaves for [`CLOG_WAIT`] s once the grains are down ([`SETTLED`])
//! (an arch spans the outlet; without vibration it never breaks). The probability that the outlet clogs within
//! [`T_CLOG`] s of the start is the fraction of runs that did.
//!
//! The intermittent regime: Pongó et al. measured their exponential in a silo whose bottom
//! rotates, which breaks the arches of small outlets (the flow goes on in avalanches between
//! temporary clogs), and took the rate between clogs only. The 2D counterpart here: the floor
//! (its two segments, the outlet with them) shaken sideways in a square wave of velocity
//! ±[`SHAKE_SPEED`] of period [`SHAKE_PERIOD`], for [`T_SHAKE`] s; the rate is the mass of the
//! avalanches over their durations ([`between_clogs`]: an avalanche ends at a pause longer than
//! [`GAP`]).

use super::line_fit;
use dem2d::analysis::statistics::{Estimate, mean_se, ratio_se, series_se};
use dem2d::analysis::{self, Frame, Window};
use dem2d::dynamics::World;
use dem2d::output::plot::{self, LinePanel, Series};
use dem2d::run::{RunError, Simulation, Stop};
use dem2d::scene::Case;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::time::Instant;

/// Grains kept in the silo.
pub const N: usize = 600;
/// Grains placed at t = 0 in the lower 50 cm (the rest come from the top; the region holds all
/// of them placed at random, so that none is left to come later on top of the N kept).
pub const FILL: usize = 250;
/// Silo width (cm; 30 d).
pub const WIDTH: f64 = 30.0;
/// The rate is measured over [T0, T1] (s).
pub const T0: f64 = 0.8;
pub const T1: f64 = 2.0;
/// Clogging trials per outlet, their duration (s) and the wait without discharge that counts
/// as a clog (s).
pub const TRIALS: u64 = 6;
pub const T_CLOG: f64 = 2.0;
pub const CLOG_WAIT: f64 = 0.25;
/// By this time (s) the poured grains have reached the floor (a fall of 50 cm takes 0.32 s).
pub const SETTLED: f64 = 0.5;
/// The shaken floor: its speed (cm/s) and the period of its square wave of velocity (s): it
/// moves ±`SHAKE_SPEED · SHAKE_PERIOD / 4` (0.5 cm, half a grain) about its rest position.
pub const SHAKE_SPEED: f64 = 20.0;
pub const SHAKE_PERIOD: f64 = 0.1;
/// The shaken runs' duration (s; the outlets of D ≤ 3 d run three times as long: their
/// avalanches are short and rare).
pub const T_SHAKE: f64 = 8.0;
/// Fewer grains than this discharged in avalanches leave a rate out of the fits.
pub const MIN_GRAINS: usize = 50;
/// A pause in the discharge longer than this (s) ends an avalanche (a temporary clog): twice a
/// grain's mean passage at the smallest outlets' rates between clogs (about 20 grains/s).
pub const GAP: f64 = 0.1;
/// The bins of the discharge (s) whose series gives a rate's standard error.
pub const BIN: f64 = 0.01;
/// The column's packing fraction is sampled this often from T0 (s).
pub const PHI_EVERY: f64 = 0.05;
/// With `--precision`, a discharge measures until the se of its rate is at most the precision,
/// or for at most this many times T1 − T0.
pub const PRECISION_CAP: f64 = 10.0;
const DENSITY: f64 = 2.5;
const DT: f64 = 1e-4;
const G: f64 = 981.0;

/// The case of a silo of outlet `d_out` (cm) with grains of aspect `alpha`, filled with seed
/// `seed`, run for `duration` s; with `shake`, the floor shaken sideways (its segments then
/// reach 2 cm into the side walls, so that no gap opens at them).
pub fn case_text(d_out: f64, alpha: f64, seed: u64, duration: f64, shake: bool) -> String {
    let half = 0.5 * WIDTH;
    let (outer, motion) = if shake {
        // A square wave of velocity about the rest position: a quarter period out, then half
        // periods back and forth, to the end of the run.
        let mut stages = Vec::new();
        let (mut t, mut sign) = (0.25 * SHAKE_PERIOD, 1.0);
        while t < duration {
            stages.push(format!(
                r#"{{ "until": {t:.6}, "velocity": [{}, 0] }}"#,
                sign * SHAKE_SPEED
            ));
            t += 0.5 * SHAKE_PERIOD;
            sign = -sign;
        }
        stages.push(format!(r#"{{ "velocity": [{}, 0] }}"#, sign * SHAKE_SPEED));
        (
            half + 2.0,
            format!(r#", "motion": [{}]"#, stages.join(", ")),
        )
    } else {
        (half, String::new())
    };
    let shape = if alpha == 1.0 {
        "\"shape\": \"circle\"".to_string()
    } else {
        format!("\"shape\": \"ellipse\", \"aspect\": {alpha}")
    };
    format!(
        r#"{{ "version": 1, "name": "silo_D{d_out}_a{alpha}_s{seed}", "units": "cm",
  "description": "dem2d study silo: a flat-bottomed silo {WIDTH} cm wide (a floor of two segments), outlet {d_out} cm",
  "gravity": [0, -{G}], "dt": {DT}, "duration": {duration}, "output_every": 1000,
  "contact": {{ "model": "linear", "kn_over_rho_g": 2000, "restitution": 0.5, "friction": 0.5 }},
  "walls": [ {{ "point": [-{half}, 0], "normal": [1, 0] }}, {{ "point": [{half}, 0], "normal": [-1, 0] }},
             {{ "segment": [[-{outer}, 0], [-{e}, 0]]{motion} }}, {{ "segment": [[{e}, 0], [{outer}, 0]]{motion} }} ],
  "bodies": [],
  "insert": [ {{ "region": [-{half}, {half}, 2, 50], "count": {FILL}, {shape}, "size": {{"uniform": [0.45, 0.55]}},
                "density": {DENSITY}, "seed": {seed} }},
              {{ "region": [-{half}, {half}, 22, 40], "keep": {N}, {shape}, "size": {{"uniform": [0.45, 0.55]}},
                "density": {DENSITY}, "velocity": [0, -100], "retry": 0.002, "seed": {} }} ],
  "outflow": [ {{ "region": [-{half}, {half}, -200, -2] }} ] }}
"#,
        seed + 1000,
        e = 0.5 * d_out
    )
}

/// One discharge run.
#[derive(Clone, Debug)]
pub struct Discharge {
    pub d_out: f64,
    pub alpha: f64,
    /// Mass rate over [T0, T1] (g/s per cm of thickness), and grains per second, with their
    /// standard errors (the discharge in bins of [`BIN`] s, blocked).
    pub rate: Estimate,
    pub grains_per_s: Estimate,
    /// Packing fraction in the column (a window 10 cm wide, 4–12 cm above the floor), every
    /// [`PHI_EVERY`] s from T0.
    pub phi: Estimate,
    /// The end of the averages (T1, or later with a precision).
    pub t_end: f64,
    /// It paused (no discharge for CLOG_WAIT s after SETTLED: an arch) before T1.
    pub clogged: bool,
    /// Grains above the floor at T1 (the inserter keeps N in the scene: fewer in the silo
    /// means the top-up lags the discharge).
    pub in_silo: usize,
    pub wall_seconds: f64,
}

impl Discharge {
    /// A steady flow: no pause, and the silo held at least 90 % of its grains.
    pub fn steady(&self) -> bool {
        !self.clogged && self.in_silo * 10 >= N * 9
    }
}

fn world(d_out: f64, alpha: f64, seed: u64, duration: f64, shake: bool) -> World {
    Case::from_json(&case_text(d_out, alpha, seed, duration, shake))
        .expect("a valid silo case")
        .build_world()
}

/// A silo run: its discharges (time, mass), whether it clogged, and the world as it ended.
type Drained = (Vec<(f64, f64)>, bool, World);

/// Runs the silo until `until` s, or until it clogs when `stop_at_clog`, or until `more`
/// (called after every step with the world and the discharges so far) returns true.
fn run_silo(
    mut w: World,
    until: f64,
    stop_at_clog: bool,
    mut more: impl FnMut(&mut World, &[(f64, f64)]) -> bool,
) -> Result<Drained, RunError> {
    let mut out = Vec::new();
    let mut last_flow: Option<f64> = None;
    let mut clogged = false;
    let stop = Simulation::new(&mut w)
        .until_time(until)
        .run_until(|w, _| {
            let log = w.flow.as_ref().expect("a flow").log.clone();
            for d in &log {
                out.push((d.time, d.mass));
            }
            if !log.is_empty() {
                last_flow = Some(w.time);
            }
            // Nothing for CLOG_WAIT once the grains are down (by SETTLED; or since the last
            // grain left): an arch holds.
            let since = last_flow.unwrap_or(SETTLED);
            if w.time > SETTLED && w.time - since > CLOG_WAIT {
                clogged = true;
            }
            (stop_at_clog && clogged) || more(w, &out)
        })?;
    debug_assert!(matches!(stop, Stop::Completed | Stop::Asked));
    Ok((out, clogged, w))
}

/// The packing fraction in the column: a window 10 cm wide, 4 to 12 cm above the floor.
fn column_phi(w: &mut World) -> f64 {
    w.refresh_contact_extras();
    let frame = Frame::from_world(w);
    let m = analysis::measure(
        &frame,
        Some(Window {
            x0: -5.0,
            x1: 5.0,
            y0: 4.0,
            y1: 12.0,
        }),
    );
    m.packing_fraction
}

/// The mass rate and the grains per second of the discharges `log` over `(T0, t_end]`, each the
/// mean of the bins of [`BIN`] s with its blocked standard error.
fn binned_rates(log: &[(f64, f64)], t_end: f64) -> (Estimate, Estimate) {
    let bins = ((t_end - T0) / BIN).round() as usize;
    let (mut mass, mut count) = (vec![0.0; bins], vec![0.0; bins]);
    for &(t, m) in log.iter().filter(|(t, _)| *t > T0 && *t <= t_end) {
        let k = (((t - T0) / BIN) as usize).min(bins - 1);
        mass[k] += m / BIN;
        count[k] += 1.0 / BIN;
    }
    (series_se(&mass), series_se(&count))
}

/// The discharge rate of one outlet, the silo filled with `seed`; with `precision`, measured
/// until the se of the mass rate is at most it (from T1 on, at most until [`PRECISION_CAP`]
/// times T1 − T0 after T0).
pub fn discharge(
    d_out: f64,
    alpha: f64,
    seed: u64,
    precision: Option<f64>,
) -> Result<Discharge, RunError> {
    let start = Instant::now();
    let until = match precision {
        Some(_) => T0 + PRECISION_CAP * (T1 - T0),
        None => T1,
    };
    let mut phis = Vec::new();
    let mut next_phi = T0;
    let mut next_check = T1;
    let mut t_end = until;
    let (log, clogged, w) = run_silo(
        world(d_out, alpha, seed, until, false),
        until,
        false,
        |w, log| {
            if w.time >= next_phi {
                phis.push(column_phi(w));
                next_phi += PHI_EVERY;
            }
            if let Some(p) = precision
                && w.time >= next_check
            {
                next_check += 0.1 * (T1 - T0);
                let (rate, _) = binned_rates(log, w.time);
                if rate.converged && rate.se <= p {
                    t_end = w.time;
                    return true;
                }
            }
            false
        },
    )?;
    let t_end = t_end.min(w.time);
    let (rate, grains_per_s) = binned_rates(&log, t_end);
    let in_silo = (0..w.bodies.len())
        .filter(|&k| w.bodies.state[k].pose.position.y > 0.0)
        .count();
    Ok(Discharge {
        d_out,
        alpha,
        rate,
        grains_per_s,
        phi: series_se(&phis),
        t_end,
        clogged,
        in_silo,
        wall_seconds: start.elapsed().as_secs_f64(),
    })
}

/// Whether a silo of outlet `d_out` filled with `seed` clogs within T_CLOG, and the grains
/// discharged before.
pub fn clogs(d_out: f64, alpha: f64, seed: u64) -> Result<(bool, usize), RunError> {
    let (log, clogged, _) = run_silo(
        world(d_out, alpha, seed, T_CLOG, false),
        T_CLOG,
        true,
        |_, _| false,
    )?;
    Ok((clogged, log.len()))
}

/// The discharge between temporary clogs: the log's discharges `(time, mass)` after `t0`
/// grouped into avalanches (a pause longer than `gap` ends one); the rate is the mass each
/// avalanche discharged after its first grain over its duration (first to last grain), summed
/// over the avalanches. Returns (rate, time flowing, avalanches); an avalanche of one grain has
/// no duration and counts for neither.
pub fn between_clogs(log: &[(f64, f64)], t0: f64, gap: f64) -> (f64, f64, usize) {
    let each = avalanches(log, t0, gap);
    let mass: f64 = each.iter().map(|a| a.0).sum();
    let flowing: f64 = each.iter().map(|a| a.1).sum();
    let rate = if flowing > 0.0 { mass / flowing } else { 0.0 };
    (rate, flowing, each.len())
}

/// The avalanches of [`between_clogs`], in order: (mass after the first grain, duration).
pub fn avalanches(log: &[(f64, f64)], t0: f64, gap: f64) -> Vec<(f64, f64)> {
    let events: Vec<(f64, f64)> = log.iter().copied().filter(|(t, _)| *t > t0).collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < events.len() {
        let mut j = i;
        while j + 1 < events.len() && events[j + 1].0 - events[j].0 <= gap {
            j += 1;
        }
        if j > i {
            out.push((
                events[i + 1..=j].iter().map(|e| e.1).sum::<f64>(),
                events[j].0 - events[i].0,
            ));
        }
        i = j + 1;
    }
    out
}

/// The fits of one kind of grain's rates with the floor shaken: `ln W = ln_a + κ D` through the
/// `fitted` outlets of D ≤ 3 d, the power law's k through D ≥ 3.5 d, the two forms' rms misfit
/// of ln W over D ≤ 3 d, and the outlets there where the power law gives no flow.
#[derive(Clone, Copy)]
struct ShakenFit {
    alpha: f64,
    ln_a: f64,
    kappa: f64,
    k_pow: f64,
    rms_exp: f64,
    rms_pow: f64,
    none_pow: usize,
    fitted: usize,
    /// κ with the avalanches split at GAP/2 and 2 GAP.
    kappa_gaps: [f64; 2],
}

/// A run with the floor shaken (the intermittent regime).
#[derive(Clone, Debug)]
pub struct Intermittent {
    pub d_out: f64,
    pub alpha: f64,
    /// The rate between clogs (g/s per cm), the time flowing (s) out of the run's after T0,
    /// the avalanches, and the grains discharged after T0. The rate's se: the avalanches'
    /// (mass, duration) pairs as a series, the ratio of their sums by the delta method
    /// ([`ratio_se`]).
    pub rate: Estimate,
    pub flowing: f64,
    pub avalanches: usize,
    pub grains: usize,
    /// The rate between clogs with the avalanches split at pauses longer than GAP/2 and 2 GAP
    /// (how much the rate owes to that choice).
    pub other_gaps: [f64; 2],
    pub wall_seconds: f64,
}

/// How long a shaken run lasts (s).
pub fn shake_duration(d_out: f64) -> f64 {
    if d_out <= 3.0 { 3.0 * T_SHAKE } else { T_SHAKE }
}

/// The rate between clogs of one outlet with the floor shaken, the silo filled with `seed`.
pub fn intermittent(d_out: f64, alpha: f64, seed: u64) -> Result<Intermittent, RunError> {
    let start = Instant::now();
    let until = shake_duration(d_out);
    let (log, ..) = run_silo(
        world(d_out, alpha, seed, until, true),
        until,
        false,
        |_, _| false,
    )?;
    let (rate, flowing, avalanches) = between_clogs(&log, T0, GAP);
    let each = self::avalanches(&log, T0, GAP);
    let (m, d): (Vec<f64>, Vec<f64>) = each.into_iter().unzip();
    let rate = if flowing > 0.0 {
        Estimate {
            mean: rate,
            ..ratio_se(&m, &d)
        }
    } else {
        mean_se(&[0.0])
    };
    Ok(Intermittent {
        d_out,
        alpha,
        rate,
        flowing,
        avalanches,
        grains: log.iter().filter(|(t, _)| *t > T0).count(),
        other_gaps: [0.5, 2.0].map(|f| between_clogs(&log, T0, f * GAP).0),
        wall_seconds: start.elapsed().as_secs_f64(),
    })
}

/// The grains of aspect `alpha` as the tables and legends name them.
fn grains(alpha: f64) -> String {
    if alpha == 1.0 {
        "disks".into()
    } else {
        format!("ellipses α = {alpha}")
    }
}

/// Beverloo's `C` and `k` (D and d in cm, d = 1) from rates `(D, W)` with bulk density `rho_b`:
/// `W^{2/3} = (C ρ_b √g)^{2/3} (D − k d)`.
pub fn beverloo_fit(points: &[(f64, f64)], rho_b: f64) -> (f64, f64) {
    let p: Vec<(f64, f64)> = points
        .iter()
        .map(|&(d, w)| (d, w.powf(2.0 / 3.0)))
        .collect();
    let (a, b) = line_fit(&p);
    let k = -a / b;
    let c = b.powf(1.5) / (rho_b * G.sqrt());
    (c, k)
}

/// Runs the study on `threads` worker threads (its runs in parallel).
pub fn run(seed: u64, precision: Option<f64>) -> Result<String, RunError> {
    let start = Instant::now();
    let disk_outlets = [3.0, 4.0, 5.0, 6.0, 8.0, 10.0];
    let ellipse_outlets = [4.0, 5.0, 6.0, 8.0, 10.0];
    let clog_outlets = [2.5, 3.0, 3.5, 4.0, 4.5];
    let mut jobs: Vec<(f64, f64)> = disk_outlets.iter().map(|&d| (d, 1.0)).collect();
    for alpha in [2.0, 3.0] {
        jobs.extend(ellipse_outlets.iter().map(|&d| (d, alpha)));
    }
    let rates: Vec<Discharge> = jobs
        .par_iter()
        .map(|&(d, a)| {
            let r = discharge(d, a, 1 + seed, precision);
            if let Ok(r) = &r {
                eprintln!(
                    "α = {a}, D = {d}: W = {} g/s ({} grains/s), φ = {}, {} in the silo{}, {:.0} s",
                    r.rate.pm(1),
                    r.grains_per_s.pm(1),
                    r.phi.pm(3),
                    r.in_silo,
                    if r.clogged { ", clogged" } else { "" },
                    r.wall_seconds
                );
            }
            r
        })
        .collect::<Result<_, _>>()?;
    let clog_jobs: Vec<(f64, u64)> = clog_outlets
        .iter()
        .flat_map(|&d| (0..TRIALS).map(move |s| (d, 100 + seed + s)))
        .collect();
    let trials: Vec<(f64, bool, usize)> = clog_jobs
        .par_iter()
        .map(|&(d, seed)| clogs(d, 1.0, seed).map(|(c, n)| (d, c, n)))
        .collect::<Result<_, _>>()?;
    // The intermittent regime: the floor shaken.
    let shaken_outlets = [1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0];
    let shaken_jobs: Vec<(f64, f64)> = [1.0, 2.0, 3.0]
        .iter()
        .flat_map(|&a| shaken_outlets.iter().map(move |&d| (d, a)))
        .collect();
    // (The long runs first, so that the threads end together.)
    let mut order: Vec<usize> = (0..shaken_jobs.len()).collect();
    order.sort_by(|&i, &j| {
        let cost = |(d, a): (f64, f64)| shake_duration(d) * a.min(2.0);
        cost(shaken_jobs[j]).total_cmp(&cost(shaken_jobs[i]))
    });
    let shaken_jobs: Vec<(f64, f64)> = order.iter().map(|&i| shaken_jobs[i]).collect();
    let mut shaken: Vec<Intermittent> = shaken_jobs
        .par_iter()
        .map(|&(d, a)| {
            let r = intermittent(d, a, 1 + seed);
            if let Ok(r) = &r {
                eprintln!(
                    "shaken floor, α = {a}, D = {d}: W = {} g/s between clogs, flowing {:.2} s, \
                     {} avalanches, {} grains, {:.0} s",
                    r.rate.pm(1),
                    r.flowing,
                    r.avalanches,
                    r.grains,
                    r.wall_seconds
                );
            }
            r
        })
        .collect::<Result<_, _>>()?;
    shaken.sort_by(|p, q| {
        (p.alpha, p.d_out)
            .partial_cmp(&(q.alpha, q.d_out))
            .expect("finite")
    });
    let wall = start.elapsed().as_secs_f64();

    // Beverloo on the disks.
    let disks: Vec<&Discharge> = rates.iter().filter(|r| r.alpha == 1.0).collect();
    let steady: Vec<&&Discharge> = disks.iter().filter(|r| r.steady()).collect();
    let phi = steady.iter().map(|r| r.phi.mean).sum::<f64>() / steady.len() as f64;
    let rho_b = DENSITY * phi;
    let points: Vec<(f64, f64)> = steady.iter().map(|r| (r.d_out, r.rate.mean)).collect();
    let (c, k) = beverloo_fit(&points, rho_b);
    // Ellipses: Beverloo over D ≥ 4 d, exp(κ D) over D ≤ 3 d.
    let mut ellipse_fits = Vec::new();
    for alpha in [2.0, 3.0] {
        let of: Vec<&Discharge> = rates
            .iter()
            .filter(|r| r.alpha == alpha && r.steady())
            .collect();
        let big: Vec<(f64, f64)> = of
            .iter()
            .filter(|r| r.d_out >= 4.0)
            .map(|r| (r.d_out, r.rate.mean))
            .collect();
        let phi_a = of.iter().map(|r| r.phi.mean).sum::<f64>() / of.len().max(1) as f64;
        let (ca, ka) = beverloo_fit(&big, DENSITY * phi_a);
        // The exponential over the smallest outlets that flowed (the three smallest).
        let small: Vec<(f64, f64)> = of
            .iter()
            .take(3)
            .map(|r| (r.d_out, r.rate.mean.ln()))
            .collect();
        let kappa = if small.len() >= 2 {
            line_fit(&small).1
        } else {
            f64::NAN
        };
        ellipse_fits.push((alpha, phi_a, ca, ka, kappa));
    }

    let mut md = String::from(
        "| grains | D/d | W (g/s) | grains/s | φ column | averaged over t (s) | in the silo at the end | Beverloo fit (g/s) | steady |\n|---|---:|---:|---:|---:|---:|---:|---:|---|\n",
    );
    let bev = |c: f64, k: f64, rho: f64, d: f64| c * rho * G.sqrt() * (d - k).max(0.0).powf(1.5);
    for r in &rates {
        let (cc, kk, rho) = if r.alpha == 1.0 {
            (c, k, rho_b)
        } else {
            let f = ellipse_fits
                .iter()
                .find(|f| f.0 == r.alpha)
                .expect("fitted");
            (f.2, f.3, DENSITY * f.1)
        };
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {T0}–{:.1} | {} | {:.1} | {} |",
            grains(r.alpha),
            r.d_out,
            r.rate.pm(1),
            r.grains_per_s.pm(1),
            r.phi.pm(3),
            r.t_end,
            r.in_silo,
            bev(cc, kk, rho, r.d_out),
            if r.steady() {
                "yes"
            } else if r.clogged {
                "no: a pause ≥ 0.25 s (an arch)"
            } else {
                "no: the silo emptied"
            }
        )
        .expect("string");
    }
    writeln!(
        md,
        "\n**Beverloo fits** (`W = C ρ_b √g (D − k d)^{{3/2}}`, ρ_b = ρ φ, least squares on \
         W^{{2/3}}, over the steady runs): disks C = {c:.3}, k = {k:.2} (φ = {phi:.3}); the \
         literature's k for disks lies between 1 and 2, and C is of order 1."
    )
    .expect("string");
    for (alpha, phi_a, ca, ka, kappa) in &ellipse_fits {
        writeln!(
            md,
            "Ellipses α = {alpha} (the steady runs): C = {ca:.3}, k = {ka:.2} \
             (φ = {phi_a:.3}); exp(κD) through the three smallest steady ones: κ = {kappa:.2} \
             per d."
        )
        .expect("string");
    }
    md.push_str("\n| D/d (disks) | clogged within 2 s | probability (± se over the fillings) | grains discharged before the clog (mean ± se) |\n|---:|---:|---:|---:|\n");
    for &d in &clog_outlets {
        let of: Vec<&(f64, bool, usize)> = trials.iter().filter(|t| t.0 == d).collect();
        let n = of.iter().filter(|t| t.1).count();
        // Each filling clogs or not: the probability is the mean of 0/1 over independent
        // fillings, its se s/√m.
        let p = mean_se(
            &of.iter()
                .map(|t| f64::from(u8::from(t.1)))
                .collect::<Vec<_>>(),
        );
        let before: Vec<f64> = of.iter().filter(|t| t.1).map(|t| t.2 as f64).collect();
        writeln!(
            md,
            "| {d} | {n} of {} | {} | {} |",
            of.len(),
            p.pm(2),
            match before.len() {
                0 => "–".into(),
                1 => format!("{:.0}", before[0]),
                _ => mean_se(&before).pm(0),
            }
        )
        .expect("string");
    }
    // The shaken floor: exp(κD) through D ≤ 3 d, the power law through D ≥ 3.5 d.
    md.push_str(
        "\n| grains (floor shaken) | D/d | W between clogs (g/s) | time flowing (s) | avalanches | \
         grains out | exp(κD) fit, D ≤ 3 (g/s) | power law fitted over D ≥ 3.5 (g/s) |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let mut shaken_fits = Vec::new();
    for alpha in [1.0, 2.0, 3.0] {
        let of: Vec<&Intermittent> = shaken
            .iter()
            .filter(|r| r.alpha == alpha && r.rate.mean > 0.0 && r.grains >= MIN_GRAINS)
            .collect();
        let small: Vec<(f64, f64)> = of
            .iter()
            .filter(|r| r.d_out <= 3.0)
            .map(|r| (r.d_out, r.rate.mean.ln()))
            .collect();
        let (ln_a, kappa) = if small.len() >= 2 {
            line_fit(&small)
        } else {
            (f64::NAN, f64::NAN)
        };
        // κ with the avalanches split at GAP/2 and 2 GAP.
        let kappa_gaps = [0, 1].map(|g| {
            let pts: Vec<(f64, f64)> = of
                .iter()
                .filter(|r| r.d_out <= 3.0 && r.other_gaps[g] > 0.0)
                .map(|r| (r.d_out, r.other_gaps[g].ln()))
                .collect();
            if pts.len() >= 2 {
                line_fit(&pts).1
            } else {
                f64::NAN
            }
        });
        // W^{2/3} = s (D − k) over the larger outlets.
        let big: Vec<(f64, f64)> = of
            .iter()
            .filter(|r| r.d_out >= 3.5)
            .map(|r| (r.d_out, r.rate.mean.powf(2.0 / 3.0)))
            .collect();
        let (b0, slope) = line_fit(&big);
        let k_pow = -b0 / slope;
        let power = move |d: f64| (slope * (d - k_pow)).max(0.0).powf(1.5);
        let exp_fit = move |d: f64| (ln_a + kappa * d).exp();
        // The two forms' rms misfit of ln W over D ≤ 3 (where the form gives a flow), and the
        // outlets where it gives none.
        let rms = |f: &dyn Fn(f64) -> f64| {
            let on: Vec<f64> = small
                .iter()
                .filter(|&&(d, _)| f(d) > 0.0)
                .map(|&(d, lw)| (lw - f(d).ln()).powi(2))
                .collect();
            (
                (on.iter().sum::<f64>() / on.len().max(1) as f64).sqrt(),
                small.len() - on.len(),
            )
        };
        let (rms_exp, (rms_pow, none_pow)) = (rms(&exp_fit).0, rms(&power));
        for r in shaken.iter().filter(|r| r.alpha == alpha) {
            writeln!(
                md,
                "| {} | {} | {}{} | {:.2} | {} | {} | {} | {:.1} |",
                grains(alpha),
                r.d_out,
                r.rate.pm(1),
                if r.grains < MIN_GRAINS {
                    " (few grains: not fitted)"
                } else {
                    ""
                },
                r.flowing,
                r.avalanches,
                r.grains,
                if r.d_out <= 3.0 && kappa.is_finite() {
                    format!("{:.1}", exp_fit(r.d_out))
                } else {
                    "–".into()
                },
                power(r.d_out)
            )
            .expect("string");
        }
        shaken_fits.push(ShakenFit {
            alpha,
            ln_a,
            kappa,
            k_pow,
            rms_exp,
            rms_pow,
            none_pow,
            fitted: small.len(),
            kappa_gaps,
        });
    }
    md.push('\n');
    for f in &shaken_fits {
        let ShakenFit {
            alpha,
            kappa,
            k_pow,
            rms_exp,
            rms_pow,
            none_pow,
            fitted,
            kappa_gaps,
            ..
        } = *f;
        let name = {
            let mut name = grains(alpha);
            name[..1].make_ascii_uppercase();
            name
        };
        if fitted < 2 {
            writeln!(
                md,
                "{name} (floor shaken): fewer than two outlets of D/d ≤ 3 discharged \
                 {MIN_GRAINS} grains in avalanches: no exponential fitted; the power law \
                 through D/d ≥ 3.5 has k = {k_pow:.2}."
            )
            .expect("string");
            continue;
        }
        writeln!(
            md,
            "{name} (floor shaken): exp(κD) through the {fitted} outlets of D/d ≤ 3 with \
             {MIN_GRAINS} grains or more: κ = {kappa:.2} per d, rms misfit of ln W \
             {rms_exp:.2}; the power law W ∝ (D − k d)^{{3/2}} through D/d ≥ 3.5: k = \
             {k_pow:.2}, rms misfit of ln W over those outlets {rms_pow:.2}{}. κ with the \
             avalanches split at pauses longer than {} s and {} s instead: {:.2} and {:.2} per d.",
            if none_pow > 0 {
                format!(" where it gives a flow (none at {none_pow} of them: D ≤ k d)")
            } else {
                String::new()
            },
            0.5 * GAP,
            2.0 * GAP,
            kappa_gaps[0],
            kappa_gaps[1]
        )
        .expect("string");
    }
    writeln!(
        md,
        "\n{N} grains (equal-area radius 0.45–0.55 cm, d = 1 cm) kept in a silo {WIDTH} cm wide \
         with a flat floor of two segment walls, rates over t = {T0}–{T1} s, {TRIALS} \
         fillings per outlet for clogging; the floor shaken at ±{SHAKE_SPEED} cm/s (period \
         {SHAKE_PERIOD} s) for {T_SHAKE} s ({} s for D/d ≤ 3), rates between pauses longer \
         than {GAP} s after t = {T0} s; {} runs in all, wall time {:.0} s on {}. Written by `dem2d study silo`.\n\n\
         ± one standard error (`analysis::statistics`): a rate from the discharge in bins of {BIN} s, \
         φ from the column every {PHI_EVERY} s, each series blocked at the length chosen from its \
         autocorrelation (Flyvbjerg–Petersen); a clogging probability and the grains before a clog \
         over the independent fillings; a rate between clogs over the avalanches (the ratio of \
         their mass to their duration, by the delta method); † a series too short for its \
         correlation time (its se may be low). Fillings from seed {seed}{}; the fits' C, k and κ \
         carry no error bar.",
        3.0 * T_SHAKE,
        jobs.len() + clog_jobs.len() + shaken_jobs.len(),
        wall,
        super::threads(),
        precision.map_or(String::new(), |p| format!(
            "; each discharge measured until the se of W is at most {p} g/s"
        ))
    )
    .expect("string");

    // The figure.
    let mut rate_series = Vec::new();
    let mut log_series = Vec::new();
    for (c_i, alpha) in [1.0, 2.0, 3.0].iter().enumerate() {
        let pts: Vec<(f64, f64)> = rates
            .iter()
            .filter(|r| r.alpha == *alpha && r.steady())
            .map(|r| (r.d_out, r.rate.mean))
            .collect();
        let errors: Vec<f64> = rates
            .iter()
            .filter(|r| r.alpha == *alpha && r.steady())
            .map(|r| r.rate.se)
            .collect();
        let label = grains(*alpha);
        rate_series.push(Series {
            label: label.clone(),
            points: pts.clone(),
            y_errors: errors,
            color: c_i,
            markers: true,
            ..Default::default()
        });
        log_series.push(Series {
            label,
            points: pts,
            color: c_i,
            markers: true,
            line: true,
            ..Default::default()
        });
    }
    let fit_pts: Vec<(f64, f64)> = (0..=70)
        .map(|i| 3.0 + 7.0 * i as f64 / 70.0)
        .map(|d| (d, bev(c, k, rho_b, d)))
        .collect();
    rate_series.push(Series::line(
        format!("Beverloo fit, disks: C = {c:.2}, k = {k:.2}"),
        fit_pts,
        0,
    ));
    let clog_pts: Vec<(f64, f64)> = clog_outlets
        .iter()
        .map(|&d| {
            let of: Vec<_> = trials.iter().filter(|t| t.0 == d).collect();
            (
                d,
                of.iter().filter(|t| t.1).count() as f64 / of.len() as f64,
            )
        })
        .collect();
    let panels = [
        LinePanel {
            title: "Discharge rate".into(),
            x_label: "outlet D/d (–)".into(),
            y_label: "W (g/s per cm)".into(),
            series: rate_series,
            legend: plot::Legend::UpperLeft,
            ..Default::default()
        },
        LinePanel {
            title: "Discharge rate, log scale".into(),
            x_label: "outlet D/d (–)".into(),
            y_label: "W (g/s per cm)".into(),
            log_y: true,
            series: log_series,
            legend: plot::Legend::LowerRight,
            ..Default::default()
        },
        LinePanel {
            title: "Clogging within 2 s (disks)".into(),
            x_label: "outlet D/d (–)".into(),
            y_label: "probability (–)".into(),
            series: vec![Series {
                label: format!("{TRIALS} fillings per outlet"),
                points: clog_pts,
                color: 0,
                line: true,
                markers: true,
                ..Default::default()
            }],
            y_range: Some((-0.05, 1.1)),
            legend: plot::Legend::LowerLeft,
            ..Default::default()
        },
    ];
    let mut shaken_series = Vec::new();
    for (c_i, f) in shaken_fits.iter().enumerate() {
        let ShakenFit {
            alpha,
            ln_a,
            kappa,
            fitted,
            ..
        } = *f;
        let label = grains(alpha);
        shaken_series.push(Series {
            label,
            points: shaken
                .iter()
                .filter(|r| r.alpha == alpha && r.rate.mean > 0.0 && r.grains >= MIN_GRAINS)
                .map(|r| (r.d_out, r.rate.mean))
                .collect(),
            color: c_i,
            markers: true,
            ..Default::default()
        });
        if fitted >= 2 {
            shaken_series.push(Series::line(
                format!("exp(κD), κ = {kappa:.2}"),
                (0..=30)
                    .map(|i| 1.5 + 1.5 * i as f64 / 30.0)
                    .map(|d| (d, (ln_a + kappa * d).exp()))
                    .collect(),
                c_i,
            ));
        }
    }
    let mut panels = panels.to_vec();
    panels.push(LinePanel {
        title: "Floor shaken: W between clogs".into(),
        x_label: "outlet D/d (–)".into(),
        y_label: "W (g/s per cm)".into(),
        log_y: true,
        series: shaken_series,
        legend: plot::Legend::LowerRight,
        ..Default::default()
    });
    super::write_figure("silo", (2000, 480), (1, 4), &panels)?;
    super::write_text("silo.md", &md)?;
    print!("{md}");
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::{DT, SHAKE_PERIOD, SHAKE_SPEED, between_clogs, world};
    use dem2d::run::Simulation;

    #[test]
    fn the_shaken_floor_moves_as_a_triangle_wave_about_its_rest_position() {
        // The floor's program, a square wave of velocity ±v of period P starting with a quarter
        // period out, puts its segments at x₀ + the triangle wave of amplitude vP/4 (0.5 cm):
        // out at P/4, back at P/2, the other side at 3P/4, home at P; the outlet moves with them.
        let mut w = world(3.0, 2.0, 1, 0.2, true);
        let rest: Vec<f64> = [2, 3].map(|k| w.walls[k].point().x).to_vec();
        let amplitude = SHAKE_SPEED * SHAKE_PERIOD / 4.0;
        assert!((amplitude - 0.5).abs() < 1e-12);
        for (t, offset) in [
            (0.25, amplitude),
            (0.5, 0.0),
            (0.75, -amplitude),
            (1.0, 0.0),
        ] {
            let until = t * SHAKE_PERIOD;
            let step = (until / DT).round() as u64;
            Simulation::new(&mut w).until_step(step).run().unwrap();
            for (k, x0) in [2, 3].into_iter().zip(&rest) {
                let x = w.walls[k].point().x;
                assert!(
                    (x - x0 - offset).abs() < 1e-9,
                    "floor segment {k} at t = {until}: {x} against {}",
                    x0 + offset
                );
                assert_eq!(w.walls[k].point().y, 0.0);
            }
        }
    }

    #[test]
    fn the_rate_between_clogs_counts_the_avalanches_only() {
        // Two avalanches after t0 = 1: grains of 2 g at 1.0 (before t0: left out), 1.1, 1.15,
        // 1.2 (one avalanche, 0.1 s, 4 g after its first grain), a pause of 0.5 s, then 1.7,
        // 1.75 (0.05 s, 2 g), then a lone grain at 3.0 (no duration: left out).
        let log = [1.0, 1.1, 1.15, 1.2, 1.7, 1.75, 3.0].map(|t| (t, 2.0));
        let (rate, flowing, avalanches) = between_clogs(&log, 1.0, 0.1);
        assert_eq!(avalanches, 2);
        assert!((flowing - 0.15).abs() < 1e-12, "{flowing}");
        assert!((rate - 6.0 / 0.15).abs() < 1e-9, "{rate}");
        // A longer gap joins them: one avalanche of 0.65 s and 8 g.
        let (rate, flowing, avalanches) = between_clogs(&log, 1.0, 0.6);
        assert_eq!(avalanches, 1);
        assert!((rate - 8.0 / 0.65).abs() < 1e-9 && (flowing - 0.65).abs() < 1e-12);
    }
}

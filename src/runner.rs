//! Runs a case: builds the world, steps it until the duration ends or P's quiescence criterion
//! holds, and writes `trajectory.csv`, `increments.csv`, `case.json` and `summary.json` into
//! the output directory. A blow-up stops the run with the step and the body; what was written is
//! kept and the summary records the error.

use crate::dynamics::timestep::estimate_critical_dt;
use crate::dynamics::{Blowup, World};
use crate::output::progress::Progress;
use crate::output::summary::{DeepCounts, EnergyReport, FinalBody, Summary};
use crate::output::trace::{IncrementsWriter, TrajectoryWriter};
use crate::scene::Case;
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Where and how to run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    pub out_dir: PathBuf,
    /// Print a progress line on stderr (only for runs longer than about two seconds).
    pub progress: bool,
    /// Stop after this many steps even if the case's duration is longer (for quick checks).
    pub max_steps: Option<u64>,
}

/// The result of a run that could write its output.
#[derive(Debug)]
pub struct RunOutcome {
    pub summary: Summary,
    pub blowup: Option<Blowup>,
}

/// Per-step increments are written for runs of up to this many steps, thinned beyond.
const MAX_INCREMENT_ROWS: u64 = 200_000;

/// Runs `case` (whose JSON text is `case_text`, copied to the output) with `opts`.
pub fn run_case(case: &Case, case_text: &str, opts: &RunOptions) -> io::Result<RunOutcome> {
    std::fs::create_dir_all(&opts.out_dir)?;
    std::fs::write(opts.out_dir.join("case.json"), case_text)?;
    let mut world = World::new(
        &case.bodies,
        case.walls.clone(),
        case.gravity,
        case.contact,
        case.dt,
    );
    let dt_critical = estimate_critical_dt(
        &world.bodies,
        &world.spec,
        &world.walls,
        case.gravity.norm(),
    );
    let mut warnings = Vec::new();
    if case.dt > dt_critical {
        warnings.push(format!(
            "dt = {:e} exceeds the critical time step estimated from the stiffest possible contact, {:.3e} \
             (damping, rotational inertia and lever arms included): the explicit scheme may oscillate or blow up",
            case.dt, dt_critical
        ));
    }
    let initial_total = world.energies.total();
    let steps = opts.max_steps.map_or(case.steps(), |m| m.min(case.steps()));
    let thin = steps.div_ceil(MAX_INCREMENT_ROWS).max(1);
    let mut traj = TrajectoryWriter::create(&opts.out_dir.join("trajectory.csv"))?;
    let mut incs = IncrementsWriter::create(&opts.out_dir.join("increments.csv"))?;
    traj.write(&world)?;
    let start = Instant::now();
    let mut progress = Progress::new(opts.progress, Duration::from_secs(2));
    let mut quiescent_step = None;
    let mut streak = 0u64;
    let mut first_contact_step = None;
    let mut blowup = None;
    let mut contact_sum = 0u64;
    for s in 1..=steps {
        let report = match world.step() {
            Ok(r) => r,
            Err(b) => {
                blowup = Some(b);
                break;
            }
        };
        contact_sum += report.contacts as u64;
        if first_contact_step.is_none() && report.contacts > 0 {
            first_contact_step = Some(s);
        }
        if s % thin == 0 || s == steps {
            incs.write(&world, &report)?;
        }
        if s % case.output_every == 0 {
            traj.write(&world)?;
            world.network_critical_dt();
        }
        if let Some(q) = case.quiescence {
            if report.increments.iter().all(|&d| d <= q) {
                streak += 1;
            } else {
                streak = 0;
            }
            if streak >= case.quiescence_window {
                // At rest since the first step of the streak (P's count for a window of one).
                quiescent_step = Some(s + 1 - streak);
                if s % thin != 0 {
                    incs.write(&world, &report)?;
                }
                break;
            }
        }
        if progress.due() {
            let rate = s as f64 / start.elapsed().as_secs_f64();
            progress.show(&format!(
                "{}: step {s}/{steps} ({:.0} %), t = {:.4}, {:.0} steps/s, {} contacts",
                case.name,
                100.0 * s as f64 / steps as f64,
                world.time,
                rate,
                report.contacts
            ));
        }
    }
    let wall_seconds = start.elapsed().as_secs_f64();
    world.network_critical_dt();
    let observed = world.diagnostics.dt_critical_observed;
    if case.dt > observed && observed.is_finite() {
        warnings.push(format!(
            "dt = {:e} exceeds the critical time step of the contact network observed during the run, \
             {observed:.3e} (its stiffest mode, sampled every output interval): the explicit scheme may \
             oscillate or blow up",
            case.dt
        ));
    }
    progress.finish();
    traj.write(&world)?;
    traj.flush()?;
    incs.flush()?;
    let b = &world.bodies;
    let final_state = (0..b.len())
        .map(|k| FinalBody {
            x: b.state[k].pose.position.x,
            y: b.state[k].pose.position.y,
            angle: b.state[k].pose.angle(),
            vx: b.state[k].vel.x,
            vy: b.state[k].vel.y,
            omega: b.state[k].omega,
        })
        .collect();
    let e = world.energies;
    let done = world.step.max(1);
    let unbalanced = world.unbalanced_ratios();
    let summary = Summary {
        name: case.name.clone(),
        steps: world.step,
        time: world.time,
        quiescent: quiescent_step.is_some(),
        quiescent_step,
        first_contact_step,
        final_state,
        max_depth_ratio: world.diagnostics.max_depth_ratio,
        deep_contacts: DeepCounts {
            deep: world.diagnostics.deep_contacts,
            contained: world.diagnostics.contained_contacts,
        },
        energies: EnergyReport {
            kinetic: e.kinetic,
            potential: e.potential,
            elastic: e.elastic,
            dissipated: e.dissipated,
            initial_total,
            final_total: e.total(),
        },
        unbalanced_force_ratio: unbalanced.0,
        unbalanced_moment_ratio: unbalanced.1,
        dt: case.dt,
        dt_critical,
        dt_critical_observed: Some(world.diagnostics.dt_critical_observed)
            .filter(|v| v.is_finite()),
        warnings,
        wall_seconds,
        particle_steps_per_second: b.len() as f64 * world.step as f64 / wall_seconds.max(1e-9),
        contacts_per_step: contact_sum as f64 / done as f64,
        error: blowup.as_ref().map(|b| b.to_string()),
    };
    write_summary(&opts.out_dir, &summary)?;
    Ok(RunOutcome { summary, blowup })
}

/// Writes `summary.json` (pretty-printed).
pub fn write_summary(dir: &Path, summary: &Summary) -> io::Result<()> {
    let text = serde_json::to_string_pretty(summary).map_err(io::Error::other)?;
    std::fs::write(dir.join("summary.json"), text + "\n")
}

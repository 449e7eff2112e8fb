//! `dem2d relax CASE --out DIR`: the case's bodies brought to rest at a minimum of the potential
//! energy by FIRE (`dem2d::dynamics::minimise`), written as `DIR/state.json` (a state any run
//! continues from) and `DIR/relax.json` (the residual force, the potential energy, the
//! iterations).
//!
//! Like `dem2d run`, it holds the output directory's lock (`DIR/.dem2d.lock`, see
//! `dem2d::output::run_dir::DirLock`) from before it looks at the directory until its last file
//! is written, so that a second relaxation or a run into the same directory is refused (exit
//! code 2, naming the lock and its holder); and SIGINT or SIGTERM stop it after the iteration
//! under way: it writes the state reached (status `interrupted`) and exits with 128 + the
//! signal's number (130, 143).

use super::{Failure, read_input};
use dem2d::dynamics::minimise::{Fire, RelaxError, Tolerance, relax_until};
use dem2d::output::run_dir::{DirLock, RunError, signal_name};
use dem2d::output::state::state_text;
use dem2d::output::write_atomically;
use std::path::Path;

/// The files `relax` writes.
const OUTPUTS: [&str; 2] = ["state.json", "relax.json"];

pub struct RelaxArgs<'a> {
    pub case: &'a Path,
    pub out: &'a Path,
    pub tolerance: f64,
    pub max_iterations: u64,
    /// The energy floor (erg; 0: none) and the stall fraction (0: none) of [`Tolerance`].
    pub energy: f64,
    pub stall: f64,
    pub overwrite: bool,
    pub quiet: bool,
}

pub fn run(args: RelaxArgs) -> Result<(), Failure> {
    // (First: a signal from here on stops the minimisation, at its first iteration at the
    // latest, and the state reached is written.)
    #[cfg(unix)]
    let stop = Some(super::signals::install());
    #[cfg(not(unix))]
    let stop = None;
    let name = args.case.display().to_string();
    if !(args.tolerance.is_finite() && args.tolerance > 0.0) {
        return Err(Failure::input(format!(
            "--tolerance: must be a positive number, got {}",
            args.tolerance
        )));
    }
    for (option, value) in [("--energy", args.energy), ("--stall", args.stall)] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(Failure::input(format!(
                "{option}: must be a number ≥ 0, got {value}"
            )));
        }
    }
    let text = read_input(&name)?;
    let file = dem2d::scene::CaseFile::from_json(&text)
        .map_err(|e| Failure::input(format!("{name}: {e}")))?;
    let case = file.case;
    let mut world = match &file.restart {
        None => case.build_world(),
        Some(state) => case.resume_world(state).map_err(|e| {
            Failure::input(format!("{name}: field `state.{}`: {}", e.path, e.message))
        })?,
    };
    dem2d::dynamics::minimise::check_frictionless(&world).map_err(|e| match e {
        // (Named as the case file names the law: its `contact`, or a wall's.)
        RelaxError::Friction(_) => Failure::input(format!("{name}: field {e}")),
        other => Failure::input(format!("{name}: {other}")),
    })?;
    let out = args.out;
    std::fs::create_dir_all(out).map_err(|e| Failure::failed(format!("{}: {e}", out.display())))?;
    // Held until the last file is written (dropped at the end of this function).
    let _lock = DirLock::acquire_by(out, &format!("dem2d relax, case `{}`", case.name)).map_err(
        |e| match e {
            RunError::Locked { .. } => Failure::input(e.to_string()),
            other => Failure::failed(other.to_string()),
        },
    )?;
    for f in OUTPUTS {
        if out.join(f).exists() && !args.overwrite {
            return Err(Failure::input(format!(
                "{}: holds an earlier relaxation's {f}: give --overwrite to replace it",
                out.display()
            )));
        }
    }
    let tol = Tolerance {
        force: args.tolerance,
        max_iterations: args.max_iterations,
        energy: args.energy,
        stall: args.stall,
    };
    let start = std::time::Instant::now();
    let relaxed = relax_until(&mut world, &Fire::default(), &tol, stop)
        .map_err(|e| Failure::failed(format!("{name}: {e}")))?;
    let seconds = start.elapsed().as_secs_f64();
    // (At rest by the residual; else below the energy floor — an unjammed packing; else at the
    // round-off level of the forces — at rest as far as double precision tells; else
    // interrupted, the energy stalled, or the iterations ran out: not at rest.)
    let status = match relaxed {
        r if r.converged && r.residual <= args.tolerance => "relaxed",
        r if r.converged => "unjammed",
        r if r.round_off => "round_off",
        r if r.signal.is_some() => "interrupted",
        r if r.stalled => "stalled",
        _ => "max_iterations",
    };
    let state = state_text(
        &file.value,
        case.duration,
        &world.restart_state(),
        None,
        &case.bodies,
        status,
    );
    let summary = serde_json::json!({
        "name": case.name,
        "status": status,
        "iterations": relaxed.iterations,
        "residual": relaxed.residual,
        "tolerance": args.tolerance,
        "round_off_residual": relaxed.round_off_residual,
        "step_limit": relaxed.step_limit,
        "signal": relaxed.signal.map(signal_name),
        "energy_floor": args.energy,
        "potential": relaxed.potential,
        "elastic": world.energies.elastic,
        "gravity_potential": world.energies.potential,
        "contacts": world.contacts.active().count(),
        "wall_seconds": seconds,
    });
    let write = |file: &str, text: &str| {
        write_atomically(out, file, text)
            .map_err(|e| Failure::failed(format!("{}: {e}", out.join(file).display())))
    };
    write("state.json", &state)?;
    write(
        "relax.json",
        &(serde_json::to_string_pretty(&summary).expect("a JSON value serialises") + "\n"),
    )?;
    if !args.quiet {
        eprintln!(
            "{}: {status} after {} iterations, residual force {:.3e} (tolerance {:e}, round-off \
             level {:.1e}), potential energy {:.6e} erg; wall time {seconds:.2} s; output in {}",
            case.name,
            relaxed.iterations,
            relaxed.residual,
            args.tolerance,
            relaxed.round_off_residual,
            relaxed.potential,
            out.display()
        );
    }
    if let Some(sig) = relaxed.signal {
        return Err(Failure {
            code: (128 + sig).clamp(0, 255) as u8,
            message: format!(
                "{name}: interrupted by {} after {} iterations (residual force {:.3e}); the \
                 state reached is in {} (status `interrupted`)",
                signal_name(sig),
                relaxed.iterations,
                relaxed.residual,
                out.join("state.json").display()
            ),
        });
    }
    if relaxed.converged || relaxed.round_off {
        Ok(())
    } else {
        Err(Failure::failed(format!(
            "{name}: not at rest ({status}) after {} iterations (residual force {:.3e} > {:e}); \
             the state reached is in {}",
            relaxed.iterations,
            relaxed.residual,
            args.tolerance,
            out.display()
        )))
    }
}

//! Runs a case: builds the world (or resumes it from a state file's state), steps it until the
//! duration ends, P's quiescence criterion holds, `--max-steps` is reached, a blow-up is
//! detected or a stop is asked for (SIGINT, SIGTERM), and writes `trajectory.csv`,
//! `increments.csv`, `case.json`, `state.json` and `summary.json` into the output directory.
//!
//! # What a run leaves behind
//! - One run at a time writes into a directory: the run holds a lock on `DIR/.dem2d.lock`
//!   (`flock`, released by the kernel however the process ends) from before it touches anything
//!   until its last file is written; a second run into the directory is refused, naming the
//!   first (its process id and case). Two runs can otherwise interleave their files: one case's
//!   trajectory beside another's summary and state.
//! - A directory holding an earlier run's outputs is refused unless `overwrite` is set; then
//!   those outputs are removed first (`summary.json` before anything else), so that nothing of
//!   the earlier run can be mistaken for this one's — except the file the run reads its case or
//!   state from (`dem2d run DIR/state.json --out DIR --overwrite`): it stays until this run's own
//!   replaces it (atomically, a temporary file renamed over it), so that a run killed on the way,
//!   or a full disk, still leaves the state it started from. `case.json` is replaced the same way.
//! - `summary.json` is written atomically with status `running` before the first step, and at
//!   the end with one of `completed`, `at_rest`, `max_steps`, `blowup`, `interrupted`,
//!   `io_error` (see [`Status`]). A summary that still says `running` belongs to a run that was
//!   killed.
//! - The CSV files always end with a whole line; after a blow-up they hold everything up to it.
//!   `walls.csv` ([`dem2d::output::walls`]: each wall's position, velocity, load and stress) is
//!   written at the trajectory's frames by every run whose case has walls.
//! - The summary's energies include the work the moving walls did on the bodies (`walls_work`):
//!   `final_total − initial_total − walls_work` is the energy the integration created
//!   (`unaccounted`, zero in exact arithmetic).
//! - `state.json` (atomically, before the final summary) holds the state the run ended in, from
//!   which `dem2d run OUT/state.json` continues exactly (see [`dem2d::output::state`]). It is
//!   written whatever the status, but for `blowup` (a non-finite or unphysical state is nothing
//!   to continue from: restart from an earlier state, with a smaller Δt). A continued run numbers
//!   its steps on from the state's (the time is `step × Δt`), writes the rows of its outputs at
//!   the same steps as the uninterrupted run, and ends at the case's duration (the whole run's).
//! - A blow-up is detected before anything is non-finite where possible ([`BlowupWatch`]: energy
//!   created beyond what the initial state and gravity supply, or an overlap deeper than the
//!   bodies); the report names the step, the body and the reason.

use dem2d::dynamics::timestep::estimate_critical_dt;
use dem2d::dynamics::watch::{self, BlowupWatch, Trigger};
use dem2d::dynamics::{Blowup, RestartState, RunProgress, World};
use dem2d::output::analysis::AnalysisOutput;
use dem2d::output::cell::CellWriter;
use dem2d::output::progress::{self, Progress};
use dem2d::output::summary::{DeepCounts, EnergyReport, FinalBody, Status, Summary, write_summary};
use dem2d::output::trace::{IncrementsWriter, TrajectoryWriter, WriteError, time_value};
use dem2d::output::vtk::VtkWriter;
use dem2d::output::walls::WallsWriter;
use dem2d::scene::Case;
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicI32, Ordering};
use std::time::{Duration, Instant};

/// Where and how to run.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    pub out_dir: PathBuf,
    /// Print a progress line on stderr (only for runs longer than about two seconds).
    pub progress: bool,
    /// Stop after this many steps even if the case's duration is longer (for quick checks).
    pub max_steps: Option<u64>,
    /// Replace the outputs of an earlier run in `out_dir` (without it, such a directory is
    /// refused).
    pub overwrite: bool,
    /// Set to a signal number (non-zero) to stop the run after the current step, with status
    /// `interrupted` (the command line's SIGINT and SIGTERM handlers set it).
    pub stop: Option<&'static AtomicI32>,
    /// Write VTK frames (`vtk/frame_NNNNN.vtu`) every this many steps, at the start and at the
    /// end, and `run.pvd` (see [`dem2d::output::vtk`]); `None`: no VTK output.
    pub vtk_every: Option<u64>,
    /// Write `analysis.csv` at the output frames ([`dem2d::output::analysis`]).
    pub analysis: bool,
    /// Write `contacts.csv` and `walls.csv` at the output frames.
    pub contacts: bool,
    /// The region of the analysis measures (`[x0, x1, y0, y1]`; default: the wall box).
    pub analysis_window: Option<[f64; 4]>,
    /// Continue from this state (a state file's), instead of starting at t = 0.
    pub restart: Option<RestartState>,
    /// The file the case (or the state) was read from: never removed from the output directory
    /// before this run's own file replaces it.
    pub input: Option<PathBuf>,
    /// Warnings found in reading the input (reported with the run's own).
    pub warnings: Vec<String>,
}

/// The files a run writes (and `dem2d plot`'s default outputs, drawn from them): what is
/// removed from a directory before a run replaces an earlier one. The summary comes first.
pub const OUTPUT_FILES: [&str; 15] = [
    "summary.json",
    "summary.json.tmp",
    "case.json",
    "case.json.tmp",
    "state.json",
    "state.json.tmp",
    "trajectory.csv",
    "increments.csv",
    "scene.svg",
    "series.svg",
    "quiescence.svg",
    "analysis.csv",
    "contacts.csv",
    "walls.csv",
    "cell.csv",
];

/// A blow-up: where it was found and why.
#[derive(Clone, Debug, PartialEq)]
pub struct BlowupReport {
    /// The step at which it was found (the state written last is that step's).
    pub step: u64,
    pub time: f64,
    /// The body most concerned (the most energetic one, or one of the pair that overlaps).
    pub body: usize,
    pub reason: String,
}

impl fmt::Display for BlowupReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "blow-up at step {} (t = {}), body {}: {}",
            self.step, self.time, self.body, self.reason
        )
    }
}

/// The result of a run that started (its directory was prepared and its first summary written).
#[derive(Debug)]
pub struct RunOutcome {
    pub summary: Summary,
    pub blowup: Option<BlowupReport>,
    /// The signal that stopped the run (status `interrupted`).
    pub signal: Option<i32>,
    /// The write that failed (status `io_error`), naming the file.
    pub io_error: Option<String>,
    /// The final `summary.json` could not be written (the status above is then only reported
    /// here, and the file on disk still says `running`).
    pub summary_error: Option<String>,
}

/// Why a run did not start.
#[derive(Debug)]
pub enum RunError {
    /// The directory holds these outputs of an earlier run, and overwriting was not asked for.
    Occupied { dir: PathBuf, files: Vec<String> },
    /// Another run is writing into the directory (what its lock file says of it).
    Locked { dir: PathBuf, holder: String },
    /// The directory, `case.json` or the first `summary.json` could not be written.
    Io(WriteError),
    /// The state to continue from does not fit the case.
    State(String),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Occupied { dir, files } => write!(
                f,
                "{}: holds the outputs of an earlier run ({}); give --overwrite to replace them, \
                 or choose another --out",
                dir.display(),
                files.join(", ")
            ),
            RunError::Locked { dir, holder } => write!(
                f,
                "{}: another dem2d run is writing into this directory ({holder}); wait for it to \
                 end, or choose another --out",
                dir.display()
            ),
            RunError::Io(e) => e.fmt(f),
            RunError::State(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RunError {}

fn io_at(file: &Path) -> impl FnOnce(io::Error) -> RunError + '_ {
    move |error| {
        RunError::Io(WriteError {
            file: file.to_path_buf(),
            error,
        })
    }
}

/// The case name as one file-name component (the default output directory is
/// `runs/<this>`): characters other than letters, digits and `-_.+=,@` become `_`, a leading dot
/// too, and an empty result is `run`; at most 100 characters. A name such as `../../x` or
/// `/etc` can then never lead outside `runs/`.
pub fn file_name_component(name: &str) -> String {
    let mut s: String = name
        .chars()
        .take(100)
        .map(|c| {
            if c.is_alphanumeric() || "-_.+=,@".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.starts_with('.') {
        s.replace_range(..1, "_");
    }
    if s.is_empty() { "run".to_string() } else { s }
}

/// The default output directory of a case: `runs/<name as a file-name component>`.
pub fn default_out_dir(case: &Case) -> PathBuf {
    Path::new("runs").join(file_name_component(&case.name))
}

/// The lock a run holds on its output directory (see the module documentation): an open
/// `DIR/.dem2d.lock` with an exclusive `flock`. Dropping it removes the file and releases the
/// lock (and so does the end of the process, however it ends: a lock file left by a killed run
/// locks nothing).
pub struct DirLock {
    file: std::fs::File,
    path: PathBuf,
}

/// The lock file's name in an output directory.
pub const LOCK_FILE: &str = ".dem2d.lock";

impl DirLock {
    /// Takes the lock of `dir` (which exists), or says who holds it.
    pub fn acquire(dir: &Path, case_name: &str) -> Result<DirLock, RunError> {
        use std::io::{Read, Seek, Write};
        use std::os::unix::fs::MetadataExt;
        use std::os::unix::io::AsRawFd;
        let path = dir.join(LOCK_FILE);
        loop {
            let mut file = std::fs::OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(io_at(&path))?;
            // SAFETY: flock on a descriptor this function owns; no memory is involved.
            let locked = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
            if locked != 0 {
                let mut holder = String::new();
                let _ = file.read_to_string(&mut holder);
                let holder = holder.trim();
                return Err(RunError::Locked {
                    dir: dir.to_path_buf(),
                    holder: if holder.is_empty() {
                        "a run that has not yet said who it is".into()
                    } else {
                        holder.to_string()
                    },
                });
            }
            // The holder before us may have removed the file between our open and our lock: a
            // lock on a file no longer at `path` locks nothing: try again.
            let same = match (file.metadata(), path.metadata()) {
                (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
                _ => false,
            };
            if !same {
                continue;
            }
            let me = format!(
                "process {}, case `{case_name}`, started {}",
                std::process::id(),
                utc_now()
            );
            file.set_len(0)
                .and_then(|()| file.rewind())
                .and_then(|()| file.write_all(me.as_bytes()))
                .map_err(io_at(&path))?;
            return Ok(DirLock { file, path });
        }
    }
}

impl Drop for DirLock {
    fn drop(&mut self) {
        // Removed while still held: a run waiting on this file then finds it gone and retries.
        let _ = std::fs::remove_file(&self.path);
        let _ = &self.file;
    }
}

/// The time now as `YYYY-MM-DD hh:mm:ss UTC` (the civil date of the days since the Unix epoch:
/// Hinnant's `civil_from_days`).
fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs()) as i64;
    let (days, rest) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02} UTC",
        rest / 3600,
        rest % 3600 / 60,
        rest % 60
    )
}

/// True when `a` and `b` are the same file (both exist).
fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (a.metadata(), b.metadata()) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Writes `text` to `dir/name` atomically: into `name.tmp`, synced, renamed over it.
fn write_atomically(dir: &Path, name: &str, text: &str) -> io::Result<()> {
    use std::io::Write;
    let tmp = dir.join(format!("{name}.tmp"));
    let result = std::fs::File::create(&tmp).and_then(|mut f| {
        f.write_all(text.as_bytes())?;
        f.sync_all()
    });
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    std::fs::rename(&tmp, dir.join(name))
}

/// Refuses a directory holding an earlier run's outputs, or (with `overwrite`) removes them,
/// the summary first — all but `input`, the file this run reads, which its own output replaces.
fn prepare_dir(dir: &Path, overwrite: bool, input: Option<&Path>) -> Result<(), RunError> {
    let mut present: Vec<PathBuf> = OUTPUT_FILES
        .into_iter()
        .map(|f| dir.join(f))
        .filter(|p| p.symlink_metadata().is_ok())
        .collect();
    // An earlier run's VTK output: `run.pvd` and `vtk/frame_*.vtu` (nothing else in `vtk/`).
    present.extend(dem2d::output::vtk::existing_outputs(dir));
    if present.is_empty() {
        return Ok(());
    }
    if !overwrite {
        let frames = present
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "vtu"))
            .count();
        let mut files: Vec<String> = present
            .iter()
            .filter(|p| p.extension().is_none_or(|e| e != "vtu"))
            .map(|p| p.strip_prefix(dir).unwrap_or(p).display().to_string())
            .collect();
        if frames > 0 {
            files.push(format!("vtk/ ({frames} frames)"));
        }
        return Err(RunError::Occupied {
            dir: dir.to_path_buf(),
            files,
        });
    }
    for path in present {
        if input.is_some_and(|i| same_file(i, &path)) {
            continue;
        }
        std::fs::remove_file(&path).map_err(io_at(&path))?;
    }
    Ok(())
}

/// Per-step increments are written for runs of up to this many steps, thinned beyond.
const MAX_INCREMENT_ROWS: u64 = 200_000;

/// How the step loop ended.
enum Stop {
    Completed,
    AtRest,
    MaxSteps,
    Blowup(BlowupReport),
    Interrupted(i32),
}

/// What the loop counts, for the summary (and the state file).
#[derive(Default)]
struct Counters {
    quiescent_step: Option<u64>,
    first_contact_step: Option<u64>,
    contact_sum: u64,
    wall_seconds: f64,
    /// Consecutive steps the quiescence criterion has held.
    streak: u64,
    /// The blow-up watch as the loop left it.
    watch: Option<BlowupWatch>,
    /// The step this run started from (0, or a state file's).
    start_step: u64,
}

/// Runs `case` (whose JSON text is `case_text`, copied to the output) with `opts`.
pub fn run_case(case: &Case, case_text: &str, opts: &RunOptions) -> Result<RunOutcome, RunError> {
    let dir = &opts.out_dir;
    let mut world = match &opts.restart {
        None => case.build_world(),
        Some(state) => World::resume(
            &case.bodies,
            case.walls.clone(),
            case.gravity,
            case.contact,
            case.dt,
            state,
        )
        .map_err(|e| RunError::State(format!("field `state.{}`: {}", e.path, e.message)))?,
    };
    let progress = opts.restart.as_ref().and_then(|s| s.run.clone());
    std::fs::create_dir_all(dir).map_err(io_at(dir))?;
    // Held until the function returns, after the last file.
    let _lock = DirLock::acquire(dir, &case.name)?;
    prepare_dir(dir, opts.overwrite, opts.input.as_deref())?;
    let case_file = dir.join("case.json");
    write_atomically(dir, "case.json", case_text).map_err(io_at(&case_file))?;
    let dt_critical = estimate_critical_dt(
        &world.bodies,
        &world.spec,
        &world.walls,
        case.gravity.norm(),
    );
    let mut warnings = opts.warnings.clone();
    let outside = case.bodies_outside_cell();
    if outside > 0 && opts.restart.is_none() {
        warnings.push(format!(
            "{outside} bodies start outside the periodic cell: each is brought into it through \
             the seams (its image counts start from the crossings)"
        ));
    }
    if case.dt > dt_critical {
        warnings.push(format!(
            "dt = {:e} exceeds the critical time step estimated from the stiffest possible contact, {:.3e} \
             (damping, rotational inertia and lever arms included): the explicit scheme may oscillate or blow up",
            case.dt, dt_critical
        ));
    }
    // A continued run's contacts are the run's, not bodies placed overlapping.
    if opts.restart.is_none() {
        world.refresh_contact_extras();
        if let Some(w) = initial_overlap_warning(&watch::overlaps(&world)) {
            warnings.push(w);
        }
    }
    let initial_total = progress
        .as_ref()
        .map_or(world.energies.total(), |p| p.initial_total);
    let mut counters = Counters {
        first_contact_step: progress.as_ref().and_then(|p| p.first_contact_step),
        contact_sum: progress.as_ref().map_or(0, |p| p.contact_sum),
        // A run that stopped at rest asks for rest anew when continued (its window more steps);
        // any other keeps its streak, as the uninterrupted run would.
        streak: progress
            .as_ref()
            .map(|p| p.quiescence_streak)
            .filter(|&s| s < case.quiescence_window)
            .unwrap_or(0),
        start_step: world.step,
        watch: progress.map(|p| p.watch),
        ..Default::default()
    };
    let summary = summarize(
        case,
        &world,
        Status::Running,
        &counters,
        (dt_critical, initial_total),
        &warnings,
        None,
    );
    let summary_file = dir.join("summary.json");
    write_summary(dir, &summary).map_err(io_at(&summary_file))?;

    let mut last_label = None;
    let traj_file = dir.join("trajectory.csv");
    let incs_file = dir.join("increments.csv");
    let result = match TrajectoryWriter::create(&traj_file, world.cell.is_some())
        .and_then(|t| Ok((t, IncrementsWriter::create(&incs_file)?)))
        .and_then(|(t, i)| {
            let walls = match world.walls.is_empty() {
                true => None,
                false => Some(WallsWriter::create(dir)?),
            };
            let cell = match world.cell {
                None => None,
                Some(_) => Some(CellWriter::create(dir)?),
            };
            Ok((t, i, (walls, cell)))
        })
        .and_then(|(t, i, walls)| {
            let vtk = match opts.vtk_every {
                Some(_) => Some(VtkWriter::create(dir, &world)?),
                None => None,
            };
            let analysis = match opts.analysis || opts.contacts {
                true => Some(AnalysisOutput::create(
                    dir,
                    opts.analysis,
                    opts.contacts,
                    opts.analysis_window
                        .map(|[x0, x1, y0, y1]| dem2d::analysis::Window { x0, x1, y0, y1 }),
                    world.cell.is_some(),
                )?),
                false => None,
            };
            Ok((t, i, walls, vtk, analysis))
        }) {
        Err(e) => Err(e),
        Ok((mut traj, mut incs, (mut walls, mut cell), mut vtk, mut analysis)) => {
            let stopped = step_loop(
                case,
                opts,
                &mut world,
                Writers {
                    traj: &mut traj,
                    incs: &mut incs,
                    walls: walls.as_mut(),
                    cell: cell.as_mut(),
                    vtk: vtk.as_mut(),
                    analysis: analysis.as_mut(),
                },
                &mut counters,
                &mut last_label,
            );
            // The last rows — the state the loop left, labelled with the step it belongs to —
            // and the buffers, also after a failed write (to the other file, it may succeed).
            let label = last_label.unwrap_or(world.step);
            let traj_done = traj
                .write_labelled(&world, label)
                .and_then(|()| traj.flush());
            let incs_done = incs.flush();
            let walls_done = match &mut walls {
                Some(w) => w.write(&world, label).and_then(|()| w.flush()),
                None => Ok(()),
            }
            .and(match &mut cell {
                Some(c) => c.write(&world, label).and_then(|()| c.flush()),
                None => Ok(()),
            });
            let analysis_done = match &mut analysis {
                Some(a) if last_label.is_none() => {
                    a.write(&mut world, label).and_then(|()| a.flush())
                }
                Some(a) => a.flush(),
                None => Ok(()),
            };
            let vtk_done = match &mut vtk {
                // A non-finite state is not drawn (VTK readers choke on it); the trajectory
                // has it.
                Some(v) if last_label.is_none() => v.write_labelled(&mut world, label),
                _ => Ok(()),
            };
            stopped.and_then(|stop| {
                traj_done
                    .and(incs_done)
                    .and(walls_done)
                    .and(vtk_done)
                    .and(analysis_done)
                    .map(|()| stop)
            })
        }
    };
    // The state before the end-of-run sample of the network's critical step below (the
    // uninterrupted run takes none here).
    let state_error = match &result {
        Ok(Stop::Blowup(_)) => None,
        _ => write_state_file(
            dir,
            case,
            case_text,
            &world,
            &counters,
            initial_total,
            &result,
        )
        .err(),
    };
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
    let (status, blowup, signal, io_error) = match (result, state_error) {
        (Ok(Stop::Completed), None) => (Status::Completed, None, None, None),
        (Ok(Stop::AtRest), None) => (Status::AtRest, None, None, None),
        (Ok(Stop::MaxSteps), None) => (Status::MaxSteps, None, None, None),
        (Ok(Stop::Blowup(b)), _) => (Status::Blowup, Some(b), None, None),
        (Ok(Stop::Interrupted(sig)), None) => (Status::Interrupted, None, Some(sig), None),
        (Ok(_), Some(e)) => (Status::IoError, None, None, Some(e.to_string())),
        (Err(e), _) => (Status::IoError, None, None, Some(e.to_string())),
    };
    let error = match (&blowup, signal, &io_error) {
        (Some(b), _, _) => Some(b.to_string()),
        (_, Some(sig), _) => Some(format!(
            "interrupted by signal {sig} ({}) after step {}",
            signal_name(sig),
            world.step
        )),
        (_, _, Some(e)) => Some(e.clone()),
        _ => None,
    };
    let summary = summarize(
        case,
        &world,
        status,
        &counters,
        (dt_critical, initial_total),
        &warnings,
        error,
    );
    let summary_error = write_summary(dir, &summary)
        .err()
        .map(|e| format!("{}: cannot write: {e}", summary_file.display()));
    Ok(RunOutcome {
        summary,
        blowup,
        signal,
        io_error,
        summary_error,
    })
}

/// Writes `state.json` for a run that ended as `result` says (not a blow-up).
fn write_state_file(
    dir: &Path,
    case: &Case,
    case_text: &str,
    world: &World,
    counters: &Counters,
    initial_total: f64,
    result: &Result<Stop, WriteError>,
) -> Result<(), WriteError> {
    let file = Path::new("state.json");
    let status = match result {
        Ok(Stop::Completed) => Status::Completed,
        Ok(Stop::AtRest) => Status::AtRest,
        Ok(Stop::MaxSteps) => Status::MaxSteps,
        Ok(Stop::Interrupted(_)) => Status::Interrupted,
        Ok(Stop::Blowup(_)) => Status::Blowup,
        Err(_) => Status::IoError,
    };
    let value = dem2d::scene::fields::parse_json(case_text, "").map_err(|e| WriteError {
        file: file.to_path_buf(),
        error: io::Error::other(format!("the case text does not parse: {e}")),
    })?;
    let progress = RunProgress {
        initial_total,
        quiescence_streak: counters.streak,
        first_contact_step: counters.first_contact_step,
        contact_sum: counters.contact_sum,
        watch: counters
            .watch
            .clone()
            .unwrap_or_else(|| BlowupWatch::new(world)),
    };
    dem2d::output::state::write_state(
        dir,
        &value,
        case.duration,
        world,
        &case.bodies,
        progress,
        status.as_str(),
    )
    .map_err(|error| WriteError {
        file: dir.join(file),
        error,
    })
}

/// `SIGINT`, `SIGTERM` or the number.
pub fn signal_name(sig: i32) -> String {
    match sig {
        2 => "SIGINT".into(),
        15 => "SIGTERM".into(),
        n => format!("signal {n}"),
    }
}

/// The files the step loop writes into.
struct Writers<'a> {
    traj: &'a mut TrajectoryWriter,
    incs: &'a mut IncrementsWriter,
    walls: Option<&'a mut WallsWriter>,
    cell: Option<&'a mut CellWriter>,
    vtk: Option<&'a mut VtkWriter>,
    analysis: Option<&'a mut AnalysisOutput>,
}

/// The steps; returns how they ended. `last_label` is set when the world's state belongs to a
/// step that failed part-way (a non-finite state found inside the step).
fn step_loop(
    case: &Case,
    opts: &RunOptions,
    world: &mut World,
    Writers {
        traj,
        incs,
        mut walls,
        mut cell,
        mut vtk,
        mut analysis,
    }: Writers,
    counters: &mut Counters,
    last_label: &mut Option<u64>,
) -> Result<Stop, WriteError> {
    // Steps are numbered from the start of the whole run (a continued run goes on from its
    // state's), and every cadence counts them so: a continued run writes its rows at the steps
    // the uninterrupted run writes them.
    let case_steps = case.steps();
    let first = world.step;
    let steps = opts
        .max_steps
        .map_or(case_steps, |m| first.saturating_add(m).min(case_steps));
    let thin = steps.div_ceil(MAX_INCREMENT_ROWS).max(1);
    let vtk_every = opts.vtk_every.unwrap_or(u64::MAX).max(1);
    // The first frame on disk at once: a run killed at any later moment leaves one whole frame.
    traj.write(world).and_then(|()| traj.flush())?;
    if let Some(w) = walls.as_deref_mut() {
        w.write(world, world.step).and_then(|()| w.flush())?;
    }
    if let Some(c) = cell.as_deref_mut() {
        c.write(world, world.step).and_then(|()| c.flush())?;
    }
    if let Some(v) = vtk.as_deref_mut() {
        v.write(world)?;
    }
    if let Some(a) = analysis.as_deref_mut() {
        a.write(world, world.step)?;
    }
    // Kept in the counters, so that the state file has them however the loop ends.
    let watch = counters
        .watch
        .get_or_insert_with(|| BlowupWatch::new(world));
    let start = Instant::now();
    let mut progress = Progress::new(opts.progress, Duration::from_secs(2));
    let mut stop = if steps < case_steps {
        Stop::MaxSteps
    } else {
        Stop::Completed
    };
    for s in first + 1..=steps {
        let report = match world.step() {
            Ok(r) => r,
            Err(b) => {
                *last_label = Some(b.step);
                stop = Stop::Blowup(from_step_failure(&b, world));
                break;
            }
        };
        counters.contact_sum += report.contacts as u64;
        if counters.first_contact_step.is_none() && report.contacts > 0 {
            counters.first_contact_step = Some(s);
        }
        if let Some(trigger) = watch.check(world) {
            incs.write(world, &report, true)?;
            stop = Stop::Blowup(describe(trigger, world));
            break;
        }
        if s % thin == 0 || s == steps {
            // The unbalanced ratio (a pass over every contact) only on output steps.
            incs.write(world, &report, s % case.output_every == 0 || s == steps)?;
        }
        if s % case.output_every == 0 {
            traj.write(world)?;
            if let Some(w) = walls.as_deref_mut() {
                w.write(world, world.step)?;
            }
            if let Some(c) = cell.as_deref_mut() {
                c.write(world, world.step)?;
            }
            world.network_critical_dt();
            if let Some(a) = analysis.as_deref_mut() {
                a.write(world, world.step)?;
            }
        }
        if s % vtk_every == 0
            && let Some(v) = vtk.as_deref_mut()
        {
            v.write(world)?;
        }
        if let Some(q) = case.quiescence {
            if report.increments.iter().all(|&d| d <= q) {
                counters.streak += 1;
            } else {
                counters.streak = 0;
            }
            if counters.streak >= case.quiescence_window {
                // At rest since the first step of the streak (P's count for a window of one).
                counters.quiescent_step = Some(s + 1 - counters.streak);
                if s % thin != 0 && s != steps {
                    incs.write(world, &report, true)?;
                }
                stop = Stop::AtRest;
                break;
            }
        }
        if let Some(sig) = opts.stop.map(|f| f.load(Ordering::Relaxed))
            && sig != 0
        {
            if s % thin != 0 && s != steps {
                incs.write(world, &report, true)?;
            }
            stop = Stop::Interrupted(sig);
            break;
        }
        if progress.due() {
            // The unbalanced ratio costs a pass over the contacts: only when a line is due.
            progress.show(&progress::line(&progress::Fields {
                name: &case.name,
                step: s,
                steps,
                time: world.time,
                elapsed: start.elapsed().as_secs_f64(),
                contacts: report.contacts,
                unbalanced: world.unbalanced_ratios().0,
            }));
        }
    }
    counters.wall_seconds = start.elapsed().as_secs_f64();
    progress.finish();
    Ok(stop)
}

/// A non-finite state found inside a step.
fn from_step_failure(b: &Blowup, world: &World) -> BlowupReport {
    BlowupReport {
        step: b.step,
        time: time_value(b.step, world.dt),
        body: b.body,
        reason: format!(
            "non-finite {} (the state written last is where the step stopped)",
            b.what
        ),
    }
}

/// A trigger of the watch, with the body it concerns.
fn describe(trigger: Trigger, world: &mut World) -> BlowupReport {
    let (body, reason) = match trigger {
        Trigger::NonFinite(what) => (
            watch::most_energetic_body(world),
            format!("non-finite {what}"),
        ),
        Trigger::Energy { created, available } => (
            watch::most_energetic_body(world),
            format!(
                "the energy grew by {created:.3e} erg, more than {} × the {available:.3e} erg that \
                 the initial state and gravity can supply (the step is unstable: is dt above the \
                 critical step, or a stiffness far above what dt can follow?)",
                watch::ENERGY_GROWTH
            ),
        ),
        Trigger::Depth { ratio } => {
            world.refresh_contact_extras();
            match watch::overlaps(world).first() {
                Some(o) => (
                    o.i,
                    format!(
                        "{} overlap by δ = {:.3e}, {:.3} × the smaller inscribed radius: deeper \
                         than the bodies themselves (the contact is too soft for the impact, or \
                         dt too large)",
                        o.names(),
                        o.depth,
                        o.ratio
                    ),
                ),
                None => (
                    watch::most_energetic_body(world),
                    format!(
                        "an overlap reached {ratio:.3} × the smaller inscribed radius: deeper than \
                         the bodies themselves"
                    ),
                ),
            }
        }
    };
    BlowupReport {
        step: world.step,
        time: time_value(world.step, world.dt),
        body,
        reason,
    }
}

/// The warning for bodies that overlap at the start (deepest first, at most five named). A
/// settled pile given as a case overlaps everywhere by design, slightly; a body listed twice,
/// inside another or below the floor overlaps deeply and is flung out.
fn initial_overlap_warning(overlaps: &[watch::Overlap]) -> Option<String> {
    let first = overlaps.first()?;
    let named: Vec<String> = overlaps
        .iter()
        .take(5)
        .map(|o| {
            format!(
                "{} by δ = {:.3e} ({:.3} × the smaller inscribed radius)",
                o.names(),
                o.depth,
                o.ratio
            )
        })
        .collect();
    let more = overlaps.len().saturating_sub(5);
    Some(format!(
        "{} pair{} overlap{} at the start (their contacts act from the first step{}): {}{}",
        overlaps.len(),
        if overlaps.len() == 1 { "" } else { "s" },
        if overlaps.len() == 1 { "s" } else { "" },
        if first.ratio > 0.1 {
            "; deep overlaps fling the bodies apart, their elastic energy turned into speed"
        } else {
            ""
        },
        named.join("; "),
        if more > 0 {
            format!("; and {more} more")
        } else {
            String::new()
        }
    ))
}

/// The summary of the world as it stands.
fn summarize(
    case: &Case,
    world: &World,
    status: Status,
    counters: &Counters,
    (dt_critical, initial_total): (f64, f64),
    warnings: &[String],
    error: Option<String>,
) -> Summary {
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
    Summary {
        name: case.name.clone(),
        status,
        steps: world.step,
        time: time_value(world.step, world.dt),
        quiescent: counters.quiescent_step.is_some(),
        quiescent_step: counters.quiescent_step,
        first_contact_step: counters.first_contact_step,
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
            walls_work: e.boundary_work,
            initial_total,
            final_total: e.total(),
            unaccounted: e.total() - initial_total - e.boundary_work,
        },
        unbalanced_force_ratio: unbalanced.0,
        unbalanced_moment_ratio: unbalanced.1,
        dt: case.dt,
        dt_critical,
        dt_critical_observed: Some(world.diagnostics.dt_critical_observed)
            .filter(|v| v.is_finite()),
        warnings: warnings.to_vec(),
        wall_seconds: counters.wall_seconds,
        particle_steps_per_second: b.len() as f64 * (world.step - counters.start_step) as f64
            / counters.wall_seconds.max(1e-9),
        contacts_per_step: counters.contact_sum as f64 / done as f64,
        error,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_state_found_non_finite_inside_a_step_is_labelled_with_that_step() {
        // Beyond the accepted ranges on purpose (the case is changed after reading): a speed of
        // 1e300 over dt = 1e10 makes the position infinite in the first step's drift, inside
        // the step, which stops there (the body's velocity kicked to step ½, its position not
        // moved). The last rows hold that state, so they must say step 1, not step 0.
        let mut case = Case::from_json(
            r#"{"version": 1, "name": "t", "gravity": [0, 0], "dt": 1e-3, "duration": 1,
                "contact": {"model": "linear", "kn": 1, "eta_n": 0, "friction": 0},
                "bodies": [{"shape": {"type": "circle", "r": 1}, "position": [0, 0]}]}"#,
        )
        .unwrap();
        case.bodies[0].velocity = dem2d::geometry::Vec2::new(1e300, 0.0);
        case.dt = 1e10;
        case.duration = 1e11;
        let dir = std::env::temp_dir().join(format!("dem2d-runner-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let opts = RunOptions {
            out_dir: dir.clone(),
            ..Default::default()
        };
        let outcome = run_case(&case, "{}", &opts).unwrap();
        let b = outcome.blowup.expect("a blow-up");
        assert_eq!((b.step, b.body), (1, 0));
        assert!(b.reason.contains("non-finite position"), "{}", b.reason);
        assert_eq!(outcome.summary.status, Status::Blowup);
        assert_eq!(outcome.summary.steps, 0, "no step completed");
        let traj = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
        let rows: Vec<&str> = traj.lines().collect();
        assert_eq!(rows.len(), 3, "{traj}");
        assert!(rows[1].starts_with("0,0,0,0,0,"), "{}", rows[1]);
        let last: Vec<&str> = rows[2].split(',').collect();
        assert_eq!(&last[..3], ["1", "1e10", "0"], "{}", rows[2]);
        assert_eq!(last[6].parse::<f64>().unwrap(), 1e300);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn case_names_become_one_file_name_component() {
        assert_eq!(file_name_component("settle3_dt1e-5"), "settle3_dt1e-5");
        assert_eq!(file_name_component("../../etc/x"), "_._.._etc_x");
        assert_eq!(file_name_component("/abs/path"), "_abs_path");
        assert_eq!(file_name_component(".."), "_.");
        assert_eq!(file_name_component(""), "run");
        assert_eq!(file_name_component("P Fig. 4"), "P_Fig._4");
        for name in ["../../x", "/etc", "..", ".", "a/../../b", "c:\\x", "\0"] {
            let p = Path::new("runs").join(file_name_component(name));
            assert_eq!(p.components().count(), 2, "{name}: {}", p.display());
            assert!(p.starts_with("runs"));
            assert!(
                p.components()
                    .all(|c| matches!(c, std::path::Component::Normal(_))),
                "{name}"
            );
        }
    }
}

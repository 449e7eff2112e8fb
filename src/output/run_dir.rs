//! A run's output directory: what `dem2d run` does ([`run_case`]: builds the world, or resumes
//! it from a state file's state, steps it until the duration ends, P's quiescence criterion
//! holds, `--max-steps` is reached, a blow-up is detected or a stop is asked for — SIGINT,
//! SIGTERM — and writes `trajectory.csv`, `increments.csv`, `case.json`, `state.json` and
//! `summary.json` into the output directory), in three parts that the Python module drives in
//! several calls: [`RunDir::open`] (the lock, an earlier run's outputs, `case.json`, the first
//! summary, the writers), [`RunDir::run`] (a [`Simulation`] with the writers as its observers),
//! [`RunDir::finish`] (the summary of how it ended). The command line and Python share this code
//! path, so a case run from either writes the same files.
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
//!   `walls.csv` ([`crate::output::walls`]: each wall's position, velocity, load and stress) is
//!   written at the trajectory's frames by every run whose case has walls, `reactions.csv`
//!   ([`crate::output::reactions`]: each prescribed body's reaction and power) by every run
//!   whose case has prescribed bodies.
//! - The summary's energies include the work the moving walls and the prescribed bodies did on
//!   the bodies (`walls_work`):
//!   `final_total − initial_total − walls_work` is the energy the integration created
//!   (`unaccounted`, zero in exact arithmetic).
//! - `state.json` (atomically, before the final summary) holds the state the run ended in, from
//!   which `dem2d run OUT/state.json` continues exactly (see [`crate::output::state`]). It is
//!   written whatever the status, but for `blowup` (a non-finite or unphysical state is nothing
//!   to continue from: restart from an earlier state, with a smaller Δt). A continued run numbers
//!   its steps on from the state's (the time is `step × Δt`), writes the rows of its outputs at
//!   the same steps as the uninterrupted run, and ends at the case's duration (the whole run's).
//! - A blow-up is detected before anything is non-finite where possible ([`crate::run::watch`]: energy
//!   created beyond what the initial state and gravity supply, or an overlap deeper than the
//!   bodies); the report names the step, the body and the reason.

use crate::dynamics::{RestartState, World};
use crate::output::analysis::AnalysisOutput;
use crate::output::cell::CellRow;
use crate::output::discharge::DischargeWriter;
use crate::output::dump::{Dump, DumpWriter};
use crate::output::progress::ProgressLines;
use crate::output::reactions::Reactions;
use crate::output::run_data::BodyState;
use crate::output::state::StateWriter;
use crate::output::summary::{DeepCounts, EnergyReport, Status, Summary, write_summary};
use crate::output::trace::{Frames, IncrementsWriter, Trajectory, TrajectoryWriter, WriteError};
use crate::output::vtk::VtkWriter;
use crate::output::walls::Walls;
use crate::output::write_atomically;
use crate::run::time::time_value;
use crate::run::{EnergyAudit, RunProgress, Simulation, Stop, watch};
use crate::run::{ObserverError, RunError as RunFailure};
use crate::scene::Case;
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicI32;

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
    /// end, and `run.pvd` (see [`crate::output::vtk`]); `None`: no VTK output.
    pub vtk_every: Option<u64>,
    /// Write `dump.lammpstrj` at the output frames (a LAMMPS-style dump for OVITO:
    /// [`crate::output::dump`]).
    pub dump: bool,
    /// Write `analysis.csv` at the output frames ([`crate::output::analysis`]).
    pub analysis: bool,
    /// Rewrite `state.json` every this many steps (atomically, status `checkpoint`): a run killed
    /// outright continues from the last ([`crate::output::state::StateWriter`]).
    pub checkpoint_every: Option<u64>,
    /// Write `contacts.csv` and `walls.csv` at the output frames.
    pub contacts: bool,
    /// The region of the analysis measures (`[x0, x1, y0, y1]`; default: the wall box).
    pub analysis_window: Option<[f64; 4]>,
    /// Continue from this state (a state file's), instead of starting at t = 0.
    pub restart: Option<RestartState>,
    /// The progress of the run that wrote the state (a state file's `run`).
    pub run: Option<RunProgress>,
    /// The file the case (or the state) was read from: never removed from the output directory
    /// before this run's own file replaces it.
    pub input: Option<PathBuf>,
    /// Warnings found in reading the input (reported with the run's own).
    pub warnings: Vec<String>,
}

/// The files a run writes (and `dem2d plot`'s default outputs, drawn from them): what is
/// removed from a directory before a run replaces an earlier one. The summary comes first.
pub const OUTPUT_FILES: [&str; 21] = [
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
    "reactions.csv",
    "discharge.csv",
    "inserted.csv",
    "dump.lammpstrj",
    "dump.lammpstrj.tmp",
    "animation.html",
];

/// The result of a run that started (its directory was prepared and its first summary written).
#[derive(Debug)]
pub struct RunOutcome {
    pub summary: Summary,
    pub blowup: Option<crate::run::BlowupReport>,
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
                "{}: another dem2d run is writing into this directory ({holder}; it holds the \
                 lock {}); wait for it to end, or choose another --out",
                dir.display(),
                dir.join(LOCK_FILE).display()
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
        Self::acquire_by(dir, &format!("case `{case_name}`"))
    }

    /// [`DirLock::acquire`] by `who` (what the lock file says of its holder after its process
    /// id: `dem2d relax, case \`pile\``, `dem2d study jamming`).
    pub fn acquire_by(dir: &Path, who: &str) -> Result<DirLock, RunError> {
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
                "process {}, {who}, started {}",
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

/// Refuses a directory holding an earlier run's outputs, or (with `overwrite`) removes them,
/// the summary first — all but `input`, the file this run reads, which its own output replaces.
fn prepare_dir(dir: &Path, overwrite: bool, input: Option<&Path>) -> Result<(), RunError> {
    let mut present: Vec<PathBuf> = OUTPUT_FILES
        .into_iter()
        .map(|f| dir.join(f))
        .filter(|p| p.symlink_metadata().is_ok())
        .collect();
    // An earlier run's VTK output: `run.pvd` and `vtk/frame_*.vtu` (nothing else in `vtk/`).
    present.extend(super::vtk::existing_outputs(dir));
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

/// What the summary counts of a run: its progress (the saved counters) and this run's own.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Counts {
    pub quiescent_step: Option<u64>,
    pub first_contact_step: Option<u64>,
    pub contact_sum: u64,
    /// Wall time of the steps (s).
    pub wall_seconds: f64,
    /// The step this run started from (0, or a state file's).
    pub start_step: u64,
}

impl Counts {
    /// The counts of a simulation as it stands.
    pub fn of(sim: &Simulation) -> Counts {
        let p = sim.progress();
        Counts {
            quiescent_step: sim.quiescent_step(),
            first_contact_step: p.first_contact_step,
            contact_sum: p.contact_sum,
            wall_seconds: sim.wall_seconds(),
            start_step: sim.start_step(),
        }
    }
}

/// How a run through [`RunDir::run`] ended.
#[derive(Debug)]
pub struct Ended {
    pub outcome: Result<Stop, RunFailure>,
    pub counts: Counts,
    /// The run's progress as it ended (to continue it with [`Simulation::resume`]).
    pub progress: RunProgress,
}

impl Ended {
    fn of(outcome: Result<Stop, RunFailure>, sim: &Simulation) -> Ended {
        Ended {
            outcome,
            counts: Counts::of(sim),
            progress: *sim.progress(),
        }
    }
}

/// The run of `case` with `opts` through the driver (to the case's duration, stopping at rest
/// when the case says so, after `opts.max_steps`, when `opts.stop` is raised), continuing
/// `resumed` (a state file's progress) if given.
pub fn simulation<'a>(
    world: &'a mut World,
    case: &Case,
    opts: &RunOptions,
    resumed: Option<&RunProgress>,
) -> Simulation<'a> {
    let mut sim = Simulation::new(world)
        .until_step(case.steps())
        .quiescence(case.quiescence_criterion());
    if let Some(m) = opts.max_steps {
        sim = sim.for_steps(m);
    }
    if let Some(flag) = opts.stop {
        sim = sim.stop_flag(flag);
    }
    if let Some(p) = resumed {
        sim = sim.resume(continued(p, case));
    }
    sim
}

/// The progress a continued run starts from: a state file's `p`. A run that stopped at rest asks
/// for rest anew when continued (its window more steps); any other keeps its streak, as the
/// uninterrupted run would.
pub fn continued(p: &RunProgress, case: &Case) -> RunProgress {
    let mut p = *p;
    if p.quiescence_streak >= case.quiescence_window {
        p.quiescence_streak = 0;
    }
    p
}

/// The writers of a run's files (observers, in the order the run feeds them).
struct Writers {
    incs: IncrementsWriter,
    traj: TrajectoryWriter,
    walls: Option<Frames<Walls>>,
    cells: Option<Frames<CellRow>>,
    reactions: Option<Frames<Reactions>>,
    discharge: Option<DischargeWriter>,
    dump: Option<DumpWriter>,
    /// Every how many steps the network's critical step is sampled ([`Simulation::sample_critical_dt`]).
    critical_dt_every: u64,
    audit: EnergyAudit,
    analysis: Option<AnalysisOutput>,
    vtk: Option<VtkWriter>,
    lines: ProgressLines,
}

/// A run's output directory while runs write into it (see the module documentation): locked,
/// cleared of an earlier run's outputs, holding `case.json` and a `summary.json` that says
/// `running`, and the writers of the run's files. [`run_case`] (what `dem2d run` does) is
/// [`RunDir::open`], [`RunDir::run`] and [`RunDir::finish`]; the Python module drives a world
/// through the same three in several calls.
pub struct RunDir {
    dir: PathBuf,
    /// Held while this value lives (until the last file is written).
    _lock: DirLock,
    warnings: Vec<String>,
    dt_critical: f64,
    initial_total: f64,
    /// The writers, or why they could not be created (`None` once reported).
    writers: Result<Writers, Option<WriteError>>,
    /// The writer of `state.json` (none when the case text does not parse).
    state: Option<StateWriter>,
    /// The case text does not parse (only a caller's text can fail: `dem2d run` reads it).
    unparsed: Option<crate::scene::FieldError>,
}

impl RunDir {
    /// Prepares `opts.out_dir` for the run of `case` (written as `case_text`) from `world`'s
    /// state (`opts.restart`'s, continuing `opts.run`): takes the directory's lock, removes an
    /// earlier run's outputs (with `opts.overwrite`; refused without), writes `case.json` and a
    /// summary saying `running`, and creates the writers (a writer that cannot be created ends
    /// the first [`RunDir::run`] with status `io_error`).
    pub fn open(
        case: &Case,
        case_text: &str,
        world: &mut World,
        opts: &RunOptions,
    ) -> Result<RunDir, RunError> {
        let dir = &opts.out_dir;
        std::fs::create_dir_all(dir).map_err(io_at(dir))?;
        let lock = DirLock::acquire(dir, &case.name)?;
        prepare_dir(dir, opts.overwrite, opts.input.as_deref())?;
        let case_file = dir.join("case.json");
        write_atomically(dir, "case.json", case_text).map_err(io_at(&case_file))?;
        let dt_critical = case.critical_dt();
        // The case's own warnings (Δt, units), given by a caller that read the case
        // (`CaseFile::warnings`) or found here.
        let mut warnings = opts.warnings.clone();
        for w in case.warnings() {
            if !warnings.contains(&w) {
                warnings.push(w);
            }
        }
        let outside = case.bodies_outside_cell();
        if outside > 0 && opts.restart.is_none() {
            warnings.push(format!(
                "{outside} bodies start outside the periodic cell: each is brought into it \
                 through the seams (its image counts start from the crossings)"
            ));
        }
        // A continued run's contacts are the run's, not bodies placed overlapping.
        if opts.restart.is_none() {
            world.refresh_contact_extras();
            if let Some(w) = initial_overlap_warning(&watch::overlaps(world)) {
                warnings.push(w);
            }
        }
        let resumed = opts.run.as_ref();
        let (progress, counts) = {
            let sim = simulation(world, case, opts, resumed);
            (*sim.progress(), Counts::of(&sim))
        };
        let initial_total = progress.initial_total;
        let summary = summarize(
            case,
            world,
            Status::Running,
            &counts,
            (dt_critical, initial_total),
            &warnings,
            None,
        );
        let summary_file = dir.join("summary.json");
        write_summary(dir, &summary).map_err(io_at(&summary_file))?;

        // The case as parsed, for the state file (`dem2d run` reads the text it was given).
        let value = crate::scene::fields::parse_json(case_text, "");
        let state = value.as_ref().ok().map(|v| {
            StateWriter::new(dir, v, case.duration).checkpoint_every(opts.checkpoint_every)
        });
        let every = case.output_every;
        let cell = world.cell.is_some();
        let writers = Frames::create(dir, every, Trajectory { cell }).and_then(|traj| {
            let incs = IncrementsWriter::create(&dir.join("increments.csv"), every)?;
            let walls = match world.walls.is_empty() {
                true => None,
                false => Some(Frames::create(dir, every, Walls)?),
            };
            let cells = match cell {
                true => Some(Frames::create(dir, every, CellRow)?),
                false => None,
            };
            let reactions = match world.bodies.prescribed.is_empty() {
                true => None,
                false => Some(Frames::create(dir, every, Reactions)?),
            };
            let discharge = match world.flow.as_ref() {
                Some(f) => Some(DischargeWriter::create(
                    dir,
                    every,
                    !f.outflows.is_empty(),
                    !f.inserters.is_empty(),
                )?),
                None => None,
            };
            let dump = match opts.dump {
                true => Some(Frames::create(dir, every, Dump)?),
                false => None,
            };
            let vtk = match opts.vtk_every {
                Some(n) => Some(VtkWriter::create(dir, world, n)?),
                None => None,
            };
            let analysis = match opts.analysis || opts.contacts {
                true => Some(AnalysisOutput::create(
                    dir,
                    opts.analysis,
                    opts.contacts,
                    opts.analysis_window
                        .map(|[x0, x1, y0, y1]| crate::analysis::Window { x0, x1, y0, y1 }),
                    cell,
                    every,
                )?),
                false => None,
            };
            Ok(Writers {
                incs,
                traj,
                walls,
                cells,
                reactions,
                discharge,
                dump,
                critical_dt_every: every,
                audit: EnergyAudit::new(&progress, case.energy_audit, every),
                analysis,
                vtk,
                lines: ProgressLines::new(&case.name, opts.progress),
            })
        });
        Ok(RunDir {
            dir: dir.clone(),
            _lock: lock,
            warnings,
            dt_critical,
            initial_total,
            writers: writers.map_err(Some),
            state,
            unparsed: value.err(),
        })
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Runs `sim` (a simulation of the world [`RunDir::open`] was given, as it stands) with the
    /// run's writers as its observers, after any of its own: returns how it ended, its counts
    /// and its progress. A writer that could not be created ends the run before its first step
    /// (the state saved is the one it started from).
    pub fn run<'a>(&'a mut self, mut sim: Simulation<'a>) -> Ended {
        let w = match &mut self.writers {
            Ok(w) => w,
            Err(e) => {
                let error: ObserverError = match e.take() {
                    Some(e) => e.into(),
                    None => format!(
                        "{}: the run's files could not be created (reported before)",
                        self.dir.display()
                    )
                    .into(),
                };
                // Nothing ran: the state saved is the one the run started from.
                if let Some(s) = &self.state {
                    let _ = s.write(sim.world(), sim.progress(), Status::IoError);
                }
                return Ended::of(Err(RunFailure::Observer(error)), &sim);
            }
        };
        sim = sim.observe(&mut w.incs).observe(&mut w.traj);
        if let Some(x) = w.walls.as_mut() {
            sim = sim.observe(x);
        }
        if let Some(c) = w.cells.as_mut() {
            sim = sim.observe(c);
        }
        if let Some(x) = w.reactions.as_mut() {
            sim = sim.observe(x);
        }
        if let Some(x) = w.discharge.as_mut() {
            sim = sim.observe(x);
        }
        if let Some(x) = w.dump.as_mut() {
            sim = sim.observe(x);
        }
        sim = sim
            .sample_critical_dt(w.critical_dt_every)
            .observe(&mut w.audit);
        if let Some(a) = w.analysis.as_mut() {
            sim = sim.observe(a);
        }
        if let Some(v) = w.vtk.as_mut() {
            sim = sim.observe(v);
        }
        sim = sim.observe(&mut w.lines);
        if let Some(s) = self.state.as_mut() {
            sim = sim.observe(s);
        }
        let mut outcome = sim.run();
        // A case text that does not parse leaves no state: that is how the run ended.
        if let (Some(e), Ok(_)) = (&self.unparsed, &outcome) {
            outcome = Err(RunFailure::Observer(
                WriteError {
                    file: PathBuf::from("state.json"),
                    error: io::Error::other(format!("the case text does not parse: {e}")),
                }
                .into(),
            ));
        }
        Ended::of(outcome, &sim)
    }

    /// Writes the final `summary.json` of the world as a run left it, with how the run ended
    /// (`outcome`, `counts`), and returns what the caller reports.
    pub fn finish(
        &mut self,
        case: &Case,
        world: &mut World,
        outcome: Result<Stop, RunFailure>,
        counts: &Counts,
    ) -> RunOutcome {
        world.network_critical_dt();
        let observed = world.diagnostics.dt_critical_observed;
        let mut warnings = self.warnings.clone();
        if let Some(f) = self.writers.as_ref().ok().and_then(|w| w.audit.finding()) {
            warnings.push(f.warning());
        }
        if case.dt > observed && observed.is_finite() {
            warnings.push(format!(
                "dt = {:e} exceeds the critical time step of the contact network observed during the run, \
                 {observed:.3e} (its stiffest mode, sampled every output interval): the explicit scheme may \
                 oscillate or blow up",
                case.dt
            ));
        }
        if let Some(flow) = &world.flow {
            for (k, due) in flow.starved(world.time) {
                warnings.push(format!(
                    "insert[{k}] placed no body of the {due} due by t = {} s: no position in its \
                     region was clear of the walls and bodies in its `attempts` tries (is the \
                     region behind a wall, or full?)",
                    crate::run::time::time_text(world.step, world.dt)
                ));
            }
        }
        let status = Status::of(&outcome);
        let (blowup, signal, io_error) = match outcome {
            Ok(Stop::Interrupted(sig)) => (None, Some(sig), None),
            Ok(_) => (None, None, None),
            Err(RunFailure::Blowup(b)) => (Some(b), None, None),
            Err(RunFailure::Observer(e)) => (None, None, Some(e.to_string())),
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
            world,
            status,
            counts,
            (self.dt_critical, self.initial_total),
            &warnings,
            error,
        );
        let summary_error = write_summary(&self.dir, &summary).err().map(|e| {
            format!(
                "{}: cannot write: {e}",
                self.dir.join("summary.json").display()
            )
        });
        RunOutcome {
            summary,
            blowup,
            signal,
            io_error,
            summary_error,
        }
    }
}

/// Runs `case` (whose JSON text is `case_text`, copied to the output) with `opts`: what `dem2d
/// run` does.
pub fn run_case(case: &Case, case_text: &str, opts: &RunOptions) -> Result<RunOutcome, RunError> {
    let mut world = match &opts.restart {
        None => case.build_world(),
        Some(state) => case
            .resume_world(state)
            .map_err(|e| RunError::State(format!("field `state.{}`: {}", e.path, e.message)))?,
    };
    let mut files = RunDir::open(case, case_text, &mut world, opts)?;
    let sim = simulation(&mut world, case, opts, opts.run.as_ref());
    let ended = files.run(sim);
    Ok(files.finish(case, &mut world, ended.outcome, &ended.counts))
}

/// `SIGINT`, `SIGTERM` or the number.
pub fn signal_name(sig: i32) -> String {
    match sig {
        2 => "SIGINT".into(),
        15 => "SIGTERM".into(),
        n => format!("signal {n}"),
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
    counters: &Counts,
    (dt_critical, initial_total): (f64, f64),
    warnings: &[String],
    error: Option<String>,
) -> Summary {
    let b = &world.bodies;
    let final_state = (0..b.len())
        .map(|k| BodyState {
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
        case.bodies[0].velocity = crate::geometry::Vec2::new(1e300, 0.0);
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

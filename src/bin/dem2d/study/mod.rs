//! `dem2d study NAME`: the studies behind the user guide's tables that are not a single case — each
//! runs its cases through the library and prints a Markdown table (run from the repository: the
//! studies read `cases/`).
//!
//! A study holds the lock of its output directory (`DIR/.dem2d.lock`, as `dem2d run` does:
//! `figures/` with `--docs` or `--check`, else its `--out` directory) while it runs, so that two
//! studies never write the same figures at once (the second is refused, exit code 2, naming
//! the lock and its holder). SIGINT or SIGTERM end it with a message and exit code 130 or 143,
//! between two of its files, never inside one ([`WRITING`]): the files it writes at its end
//! (its table, its figures) are then not written.

pub mod biaxial;
pub mod biaxial_periodic;
pub mod biaxial_shape;
pub mod drum;
pub mod impacts;
pub mod jamming;
pub mod packing;
pub mod repose;
pub mod repose_cohesion;
pub mod representation;
pub mod rolling_fig3;
pub mod shear;
pub mod silo;

use dem2d::geometry::Shape;
use dem2d::output::docs_tables::Mode;
use dem2d::output::plot::{self, LinePanel};
use dem2d::output::run_dir::DirLock;
use dem2d::run::RunError;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU8, Ordering};

/// The studies `dem2d study` runs.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Study {
    /// P Fig. 3's thrown circle and ellipse with rolling resistance: when they come to rest.
    RollingFig3,
    /// The angle of repose of a 2D heap of disks against μ_r (CDT and EPSD).
    Repose,
    /// The angle of repose of the same heap with cohesion between the grains and with the floor
    /// (EPSD μ_r = 0.1) against the Bond number (pull-off force of two grains over a weight).
    ReposeCohesion,
    /// Servo compaction of 400 disks, then a biaxial test with servo side walls.
    Biaxial,
    /// Impact benchmarks (Chung & Ooi 2011) of a disk on a wall against closed forms; writes
    /// figures/impacts.svg and figures/impacts.md.
    Impacts,
    /// Biaxial tests of 400 (`--grains`) ellipses per aspect ratio (1, 1.5, 2, 2.5): stress ratio and
    /// volumetric strain, friction and dilatancy angles, fabric at the peak; writes
    /// figures/biaxial_shape.svg and figures/biaxial_shape.md.
    BiaxialShape,
    /// The walls' influence: the biaxial test of `biaxial-shape` (400 `--grains` per aspect
    /// ratio 1–2.5) in the servo-walled box and in a periodic cell held at its stress without
    /// walls, side by side; writes figures/biaxial_periodic.svg and .md.
    BiaxialPeriodic,
    /// Packing fraction and coordination of bidisperse grains poured into a box against the
    /// aspect ratio (1–3), frictionless and μ = 0.5; writes figures/packing.svg and .md.
    Packing,
    /// The ellipse as the exact conic against equal-area 8–128-gons: P Fig. 2's drop (α = 1.5,
    /// 2, 3), P Fig. 4's settling and a poured pile of 300 (`--grains`) grains; error against
    /// cost; writes figures/representation_pareto.svg and figures/representation.md.
    Representation,
    /// Isotropic jamming of 256 (`--grains`) frictionless bidisperse grains in a periodic cell
    /// by FIRE, 10 (`--packings`) packings per aspect ratio (1–3): φ_J and Z_J against the
    /// published values; writes figures/jamming.svg and figures/jamming.md.
    Jamming,
    /// Discharge of a flat-bottomed 2D silo (600 grains kept, outlet D): W(D) for disks against
    /// Beverloo's law (C, k fitted), ellipses α = 2 and 3, clogging probability of small
    /// outlets, and with the floor shaken the rate between clogs down to D = 1.5 d (exp(κD)
    /// against the power law); writes figures/silo.svg and figures/silo.md.
    Silo,
    /// Steady simple shear at imposed pressure in a Lees–Edwards cell: μ(I), φ(I) and the
    /// ellipses' orientation of 256 (`--grains`) frictional grains (μ = 0.4), α in 1–3
    /// (`--aspects`), I in 0.01–0.3 and disks at 0.001 too (`--inertial`); writes
    /// figures/shear.svg and .md.
    Shear,
    /// A half-filled drum of disks and ellipses (α = 1.5, 2) turned through Froude numbers
    /// 1e-5–2: the regime (Mellmann 2001), the free surface's angle and the flowing layer's
    /// thickness (`--quick`: a small drum of disks, five Froude numbers); writes
    /// figures/drum.svg and figures/drum.md.
    Drum,
}

/// The `dem2d study` command's description, naming every study of [`Study`] (so that the list
/// in `dem2d --help` cannot fall behind the studies: it named 7 of 10, issue 41).
pub fn about() -> String {
    use clap::ValueEnum;
    let names: Vec<String> = Study::value_variants()
        .iter()
        .filter_map(|s| s.to_possible_value())
        .map(|v| v.get_name().to_string())
        .collect();
    format!(
        "Run one of the studies behind the user guide's tables ({}) and print its Markdown \
         table; run from the repository (the studies read `cases/`)",
        names.join(", ")
    )
}

impl Study {
    /// Whether the study draws figures or writes a table file (see [`OUT`]).
    pub fn writes_figures(self) -> bool {
        !matches!(
            self,
            Study::RollingFig3 | Study::Repose | Study::ReposeCohesion | Study::Biaxial
        )
    }

    /// The name of the study's marked table in the user guide (`--docs`).
    pub fn table_name(self) -> &'static str {
        match self {
            Study::RollingFig3 => "rolling_fig3",
            Study::Repose => "repose",
            Study::ReposeCohesion => "repose_cohesion",
            Study::Biaxial => "biaxial",
            Study::Impacts => "impacts",
            Study::BiaxialShape => "biaxial_shape",
            Study::BiaxialPeriodic => "biaxial_periodic",
            Study::Packing => "packing",
            Study::Representation => "representation",
            Study::Jamming => "jamming",
            Study::Silo => "silo",
            Study::Shear => "shear",
            Study::Drum => "drum",
        }
    }
}

/// A grain of equal-area radius `r` and aspect ratio `aspect` = a/b: the disk of radius `r` at
/// 1, else the ellipse of the same area, `a = r√α`, `b = r/√α`.
pub fn grain(r: f64, aspect: f64) -> Shape {
    if aspect == 1.0 {
        Shape::Circle { r }
    } else {
        Shape::Ellipse {
            a: r * aspect.sqrt(),
            b: r / aspect.sqrt(),
        }
    }
}

/// The worker threads of the run, as a table's note says them ("1 thread", "2 threads").
pub fn threads() -> String {
    match rayon::current_num_threads() {
        1 => "1 thread".to_string(),
        n => format!("{n} threads"),
    }
}

/// The least-squares line `y = a + b x` through `points`: (a, b).
pub fn line_fit(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let (sxx, sxy) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + (x - mx) * (x - mx), b + (x - mx) * (y - my))
    });
    let b = sxy / sxx;
    (my - b * mx, b)
}

/// A Markdown table printed row by row as a study computes it (a long study shows its progress
/// on standard output), and kept for the user guide.
pub struct Table(String);

impl Table {
    /// A table with its header lines.
    pub fn new(header: &str) -> Table {
        println!("{header}");
        Table(format!("{header}\n"))
    }

    /// One more row.
    pub fn row(&mut self, line: String) {
        println!("{line}");
        self.0.push_str(&line);
        self.0.push('\n');
    }

    /// The whole table.
    pub fn text(self) -> String {
        self.0
    }
}

/// Where a study writes its figures and its table file: `figures/` with `--docs` or `--check`
/// (the tracked files the user guide shows, which CI compares with git), else the `--out`
/// directory (default `runs/study/NAME`), so that a study of a subset never replaces the
/// tracked figures (issue 41); and where their PNGs go (`target/figure-png/` beside the tracked
/// figures, else the same directory).
static OUT: Mutex<Option<(PathBuf, PathBuf)>> = Mutex::new(None);

/// Held while a study writes one of its files (a figure, its table, a case file, the guide's
/// table), so that a signal ends the process between two files, never inside one.
static WRITING: Mutex<()> = Mutex::new(());

/// The study's lock on its output directory (see the module documentation), released when the
/// study ends, however it ends.
static LOCK: Mutex<Option<DirLock>> = Mutex::new(None);

/// Takes [`WRITING`] (a study thread that panicked while writing has left nothing to protect).
fn writing() -> std::sync::MutexGuard<'static, ()> {
    WRITING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Ends the process at SIGINT or SIGTERM (see the module documentation): a thread that
/// watches the signal handlers' flag, waits until no file is being written, releases the lock,
/// says what happened and exits with 128 + the signal's number.
#[cfg(unix)]
fn exit_on_signal(study: Study, started: std::time::Instant) {
    let stop = crate::signals::install();
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(std::time::Duration::from_millis(50));
            let sig = stop.load(Ordering::Relaxed);
            if sig == 0 {
                continue;
            }
            let _writing = writing();
            drop(
                LOCK.lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
                    .take(),
            );
            crate::say(&format!(
                "dem2d: study {}: interrupted by {} after {:.0} s; the files it writes at its \
                 end (its table, its figures) are not written",
                study.table_name(),
                dem2d::output::run_dir::signal_name(sig),
                started.elapsed().as_secs_f64()
            ));
            std::process::exit(128 + sig);
        }
    });
}

/// The study's output directories (see [`OUT`]): (figures and tables, PNGs).
fn out_dirs() -> (PathBuf, PathBuf) {
    OUT.lock()
        .expect("not poisoned")
        .clone()
        .unwrap_or_else(|| (PathBuf::from("figures"), PathBuf::from("target/figure-png")))
}

/// An error writing a study's file, as the run error the studies return.
fn write_error(path: &Path, e: impl std::fmt::Display) -> RunError {
    RunError::Observer(format!("{}: cannot write: {e}", path.display()).into())
}

/// Writes a study's text file `name` (its table, `NAME.md`; an SVG) into its output directory.
pub fn write_text(name: &str, text: &str) -> Result<(), RunError> {
    let path = out_dirs().0.join(name);
    let _writing = writing();
    std::fs::write(&path, text).map_err(|e| write_error(&path, e))
}

/// Writes a study's PNG `name` beside its figures (see [`OUT`]).
pub fn write_png(name: &str, png: &[u8]) -> Result<(), RunError> {
    let dir = out_dirs().1;
    std::fs::create_dir_all(&dir).map_err(|e| write_error(&dir, e))?;
    let path = dir.join(name);
    let _writing = writing();
    std::fs::write(&path, png).map_err(|e| write_error(&path, e))
}

/// Draws a study's figure `panels` (`size` in pixels, a `grid` of rows × columns) into
/// `NAME.svg` in its output directory, and as a PNG `NAME.png` (to look at; see [`OUT`]).
pub fn write_figure(
    name: &str,
    size: (u32, u32),
    grid: (usize, usize),
    panels: &[LinePanel],
) -> Result<(), RunError> {
    let (dir, png) = out_dirs();
    std::fs::create_dir_all(&png).map_err(|e| write_error(&png, e))?;
    let _writing = writing();
    for path in [
        dir.join(format!("{name}.svg")),
        png.join(format!("{name}.png")),
    ] {
        plot::line_panels(&path, size, grid, panels).map_err(|e| write_error(&path, e))?;
    }
    Ok(())
}

/// What the studies do with the case files they can write (`--write-cases`): 0 nothing, 1 write
/// them, 2 compare them with the files there (`--check`), recording the ones that differ.
static CASE_FILES: AtomicU8 = AtomicU8::new(0);
static STALE_CASES: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Writes a study's case file `path`, or (checking) compares it with the file there.
pub fn put_case(path: &Path, text: &str) {
    match CASE_FILES.load(Ordering::Relaxed) {
        1 => {
            let _writing = writing();
            if let Some(dir) = path.parent() {
                std::fs::create_dir_all(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
            }
            std::fs::write(path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            eprintln!("wrote {}", path.display());
        }
        2 if std::fs::read_to_string(path).ok().as_deref() != Some(text) => {
            STALE_CASES
                .lock()
                .expect("not poisoned")
                .push(path.display().to_string());
        }
        _ => {}
    }
}

/// What a study is asked for beyond its defaults (each study ignores what it does not take).
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Also write the study's case files into `cases/`.
    pub write_cases: bool,
    /// The sample size.
    pub grains: Option<usize>,
    /// Packings per aspect ratio.
    pub packings: Option<usize>,
    /// The aspect ratios.
    pub aspects: Option<Vec<f64>>,
    /// The inertial numbers.
    pub inertial: Option<Vec<f64>>,
    /// Where the figures and the table file go without `--docs` (default `runs/study/NAME`).
    pub out: Option<PathBuf>,
    /// The study's small, fast version (drum).
    pub quick: bool,
    /// The first seed of the study's random draws (default 0, the tables' draw).
    pub seed: Option<u64>,
    /// The standard error of the study's headline number at which a run (or the series of
    /// repetitions) stops (positive and finite; checked by the command line).
    pub precision: Option<f64>,
}

/// Runs `study` with `options`. With `docs`, the study's table goes into its marked region of
/// the user guide ([`Study::table_name`]), or (checking) is compared with it, and so are the
/// case files with `write_cases`: a difference is a failure.
pub fn run(study: Study, options: &Options, docs: Option<Mode>) -> Result<(), crate::Failure> {
    let write_cases = options.write_cases;
    let checking = docs == Some(Mode::Check);
    CASE_FILES.store(
        match (write_cases, checking) {
            (false, _) => 0,
            (true, false) => 1,
            (true, true) => 2,
        },
        Ordering::Relaxed,
    );
    // The tracked figures with --docs or --check; else a directory of the run's own.
    let own = match docs {
        Some(_) => None,
        None => {
            let dir = options
                .out
                .clone()
                .unwrap_or_else(|| Path::new("runs/study").join(study.table_name()));
            std::fs::create_dir_all(&dir).map_err(|e| {
                crate::Failure::failed(format!("{}: cannot create: {e}", dir.display()))
            })?;
            Some(dir)
        }
    };
    *OUT.lock().expect("not poisoned") = own.clone().map(|d| (d.clone(), d));
    // The lock of the directory the study writes (see the module documentation).
    let locked = own.clone().unwrap_or_else(|| out_dirs().0);
    std::fs::create_dir_all(&locked)
        .map_err(|e| crate::Failure::failed(format!("{}: cannot create: {e}", locked.display())))?;
    let lock = DirLock::acquire_by(&locked, &format!("dem2d study {}", study.table_name()))
        .map_err(|e| match e {
            dem2d::output::run_dir::RunError::Locked { .. } => crate::Failure::input(e.to_string()),
            other => crate::Failure::failed(other.to_string()),
        })?;
    *LOCK.lock().expect("not poisoned") = Some(lock);
    #[cfg(unix)]
    exit_on_signal(study, std::time::Instant::now());
    let result = run_locked(study, options, docs, own);
    drop(
        LOCK.lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .take(),
    );
    result
}

/// [`run`] once the output directory is locked.
fn run_locked(
    study: Study,
    options: &Options,
    docs: Option<Mode>,
    own: Option<PathBuf>,
) -> Result<(), crate::Failure> {
    let Options {
        write_cases,
        grains,
        packings,
        ..
    } = *options;
    let write = write_cases;
    // The drum's grains are built from a/b ≥ 1 (a lattice of ellipses lying flat).
    if let (Study::Drum, Some(aspects)) = (study, options.aspects.as_deref())
        && let Some(bad) = aspects
            .iter()
            .find(|a| !(a.is_finite() && (1.0..=5.0).contains(*a)))
    {
        return Err(crate::Failure::input(format!(
            "--aspects: the drum study's aspect ratios must be in [1, 5], got {bad}"
        )));
    }
    let md = match study {
        Study::RollingFig3 => rolling_fig3::run(),
        Study::Repose => repose::run(write),
        Study::ReposeCohesion => repose_cohesion::run(),
        Study::Biaxial => biaxial::run(write),
        Study::Impacts => impacts::run(),
        Study::BiaxialShape => biaxial_shape::run(
            grains.unwrap_or(400),
            write,
            packings.unwrap_or(biaxial_shape::SAMPLES),
            options.seed.unwrap_or(0),
            options.precision,
        ),
        Study::BiaxialPeriodic => biaxial_periodic::run(grains.unwrap_or(400)),
        Study::Packing => packing::run(
            grains.unwrap_or(packing::N),
            write,
            packings.unwrap_or(packing::POURS),
            options.seed.unwrap_or(0),
            options.precision,
        ),
        Study::Representation => representation::run(grains.unwrap_or(packing::N)),
        Study::Jamming => jamming::run(
            grains.unwrap_or(jamming::N),
            packings.unwrap_or(jamming::PACKINGS),
            options.aspects.as_deref().unwrap_or(&jamming::ASPECTS),
            write,
            options.seed.unwrap_or(0),
            options.precision,
        ),
        Study::Shear => shear::run(
            grains.unwrap_or(shear::N),
            options.aspects.as_deref().unwrap_or(&shear::ASPECTS),
            options.inertial.as_deref(),
            options.seed.unwrap_or(0),
            options.precision,
        ),
        Study::Silo => silo::run(options.seed.unwrap_or(0), options.precision),
        Study::Drum => drum::run(options.quick, options.aspects.as_deref()),
    }
    // A run that blows up ends the study with its report.
    .map_err(|e| crate::Failure::failed(format!("dem2d study: {e}")))?;
    if let Some(mode) = docs {
        let _writing = writing();
        crate::refresh_docs(study.table_name(), &md, mode)?;
    }
    if let Some(dir) = own
        && study.writes_figures()
    {
        eprintln!(
            "dem2d study: its figures and table are in {} (figures/ is written only with --docs)",
            dir.display()
        );
    }
    let stale = std::mem::take(&mut *STALE_CASES.lock().expect("not poisoned"));
    if !stale.is_empty() {
        return Err(crate::Failure::failed(format!(
            "stale case files (the study writes them differently now): {}",
            stale.join(", ")
        )));
    }
    Ok(())
}

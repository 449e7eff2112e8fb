//! `dem2d` command line: parse arguments, call the library, map errors to exit codes
//! (0 success, 1 failure while running, 2 bad input).

mod analyze;
mod impact;
mod relax;
mod study;
mod verify;
mod verify_ellipses;

use clap::{Parser, Subcommand};
use dem2d::narrow_phase::contact;
use dem2d::output::contacts::contact_json;
use dem2d::output::run_dir::{RunError, RunOptions, default_out_dir, run_case, signal_name};
use dem2d::output::summary::Status;
use dem2d::scene::fields::parse_json;
use dem2d::scene::parse_pairs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The system allocator with transparent huge pages for large blocks (see [`dem2d::alloc`]): a
/// million-body step is ~3 % faster on them.
#[global_allocator]
static GLOBAL: dem2d::alloc::HugePageAllocator = dem2d::alloc::HugePageAllocator;

#[derive(Parser)]
#[command(
    name = "dem2d",
    version,
    about = "2D discrete element method with circles, ellipses, rectangles, convex polygons and \
             clumps of disks"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    // The first line (`dem2d --help`) names every study, from the list itself.
    #[command(about = study::about(), long_about = study::about())]
    Study {
        /// Which study.
        #[arg(value_enum)]
        name: study::Study,
        /// Also write the study's case files into `cases/` (repose, biaxial, biaxial-shape, packing,
        /// jamming: its threshold packing of disks).
        #[arg(long)]
        write_cases: bool,
        /// Grains per sample for the studies that take a size (biaxial-shape: rounded to a
        /// square number, default 400; packing: default 300).
        #[arg(long)]
        grains: Option<usize>,
        /// Independent samples per row, each number then given as mean ± standard error:
        /// packings per aspect ratio (jamming, default 10), samples per aspect ratio
        /// (biaxial-shape, default 3), pours per row (packing, default 3).
        #[arg(long)]
        packings: Option<usize>,
        /// Aspect ratios a/b, comma-separated (jamming and shear; default: each study's own
        /// list).
        #[arg(long, value_delimiter = ',')]
        aspects: Option<Vec<f64>>,
        /// Inertial numbers, comma-separated, for every aspect ratio (shear; default
        /// 0.01,0.03,0.1,0.3, and 0.001 for disks).
        #[arg(long, value_delimiter = ',')]
        inertial: Option<Vec<f64>>,
        /// Worker threads (default: all cores; the jamming study runs its packings in
        /// parallel).
        #[arg(long)]
        threads: Option<usize>,
        /// The study's small, fast version (drum: a small drum of disks, five Froude numbers).
        #[arg(long)]
        quick: bool,
        /// Also put the table into its marked region of the user guide (README.md, docs/src;
        /// run from the repository).
        #[arg(long)]
        docs: bool,
        /// Compare the table (and, with --write-cases, the case files) with the user guide's
        /// and the repository's instead of writing them; fail if they differ.
        #[arg(long)]
        check: bool,
        /// Where the figures and the table file go (default runs/study/NAME); with --docs or
        /// --check they go into figures/, the user guide's.
        #[arg(long, conflicts_with_all = ["docs", "check"])]
        out: Option<PathBuf>,
        /// The first seed of the study's random draws, a non-negative integer (shear: the
        /// grains' sizes, places and orientations; jamming: the first packing's; default 0,
        /// the guide's tables).
        #[arg(long)]
        seed: Option<u64>,
        /// Stop when the standard error of the study's headline number is at most this
        /// (positive): shear, se(μ) of each run (measuring up to 10 times the fixed strain);
        /// jamming, se(φ_J) over the packings of each aspect ratio (up to 10 times --packings).
        #[arg(long, value_parser = positive_precision)]
        precision: Option<f64>,
    },
    /// Contact geometry of pairs of bodies: reads a JSON array of {"i": BODY, "j": BODY} from FILE
    /// (or standard input for `-`) and prints one JSON result per pair.
    Contact {
        /// Input file, or `-` for standard input.
        file: String,
    },
    /// Run a case file: writes trajectory.csv, increments.csv, walls.csv (a case with walls),
    /// reactions.csv (a case with fixed or prescribed bodies), case.json, state.json and
    /// summary.json. Given a state file (a run's state.json), continues that run.
    Run {
        /// The case file (JSON, "version": 1), or a run's state.json to continue from.
        case: PathBuf,
        /// Output directory (default: runs/<case name>; for a state file
        /// runs/<case name>_from_step_<step>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Stop after this many steps of this run (for quick checks, or to continue a run in
        /// parts; the summary says how far it got).
        #[arg(long)]
        max_steps: Option<u64>,
        /// Replace the case's duration (s): the run ends at t = DURATION (counted from the
        /// start of the whole run, also when continuing from a state file).
        #[arg(long)]
        duration: Option<f64>,
        /// No progress line on stderr.
        #[arg(long)]
        quiet: bool,
        /// Worker threads (default: all cores). The results are the same bit for bit for any
        /// number.
        #[arg(long)]
        threads: Option<usize>,
        /// Replace the outputs of an earlier run in the output directory (without it, such a
        /// directory is refused).
        #[arg(long)]
        overwrite: bool,
        /// Also write VTK files for ParaView: OUT/vtk/frame_NNNNN.vtu at the output frames and
        /// OUT/run.pvd (the time series to open). The case's "output": {"vtk": true} does the
        /// same.
        #[arg(long)]
        vtk: bool,
        /// Steps between VTK frames (default: the case's output.vtk_every, else its
        /// output_every); implies --vtk.
        #[arg(long)]
        vtk_every: Option<u64>,
        /// Also write OUT/dump.lammpstrj at the output frames: a LAMMPS-style dump for OVITO
        /// (ellipses as ellipsoids, orientations as quaternions; what `dem2d export` writes
        /// from a run directory).
        #[arg(long)]
        dump: bool,
        /// Also write OUT/analysis.csv at the output frames: stress (Love–Weber and from the
        /// walls), packing fraction, coordination, fabric anisotropies, orientation order. The
        /// case's "output": {"analysis": true} does the same.
        #[arg(long)]
        analysis: bool,
        /// Also write every contact at the output frames, OUT/contacts.csv, which `dem2d
        /// analyze` reads (with OUT/walls.csv, which every run with walls writes). The case's
        /// "output": {"contacts": true} does the same.
        #[arg(long)]
        contacts: bool,
        /// Rewrite OUT/state.json every N steps (atomically; its status `checkpoint`): a run
        /// killed outright (SIGKILL, a lost node) continues from the last with `dem2d run
        /// OUT/state.json`, and its rows are the uninterrupted run's, byte for byte.
        #[arg(long, value_name = "N")]
        checkpoint_every: Option<u64>,
    },
    /// Bring a case's bodies to rest at a minimum of their potential energy (FIRE, on positions
    /// and angles, under the law's conservative part; frictionless laws only): writes
    /// OUT/state.json, which `dem2d run` continues from, and OUT/relax.json (residual force,
    /// potential energy, iterations). Exit code 1 when neither the tolerance nor the forces'
    /// round-off level is reached, 130/143 on SIGINT/SIGTERM (the state reached is written
    /// either way).
    Relax {
        /// The case file, or a run's state.json.
        case: PathBuf,
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// Residual force at which the bodies are at rest: the largest out-of-balance force on
        /// a body (|F| + |M|/r) over the mean magnitude of the forces on a body.
        #[arg(long, default_value_t = 1e-9)]
        tolerance: f64,
        /// The most force evaluations.
        #[arg(long, default_value_t = 1_000_000)]
        max_iterations: u64,
        /// A potential energy (erg) at or below which the bodies count as at rest too (status
        /// "unjammed": with neither gravity nor walls, a packing this close to zero energy is
        /// unjammed, and FIRE only approaches zero slowly); 0: none.
        #[arg(long, default_value_t = 0.0)]
        energy: f64,
        /// Stop when the potential energy changes by less than this fraction over 1000
        /// iterations while the residual force does not halve (status "stalled", exit code 1:
        /// O'Hern et al.'s second criterion, for packings FIRE relaxes slowly); 0: never.
        #[arg(long, default_value_t = 0.0)]
        stall: f64,
        /// Replace an earlier relaxation's files in OUT.
        #[arg(long)]
        overwrite: bool,
        /// No report on stderr.
        #[arg(long)]
        quiet: bool,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Recompute RUN_DIR/analysis.csv from a run's trajectory.csv, contacts.csv and walls.csv
    /// (a run made with --contacts; fails, naming the file, for a run without per-contact data).
    Analyze {
        /// The run directory.
        run_dir: PathBuf,
        /// The region, x0,x1,y0,y1 (cm; default: the box of four walls, else the bodies' extent);
        /// write `--window=-1,2,0,3` when x0 is negative.
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
        window: Option<Vec<f64>>,
        /// Output file (default: RUN_DIR/analysis.csv).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Coarse-grained fields across a run (a directory written by `dem2d run`): profiles of
    /// the packing fraction, mean velocity, granular temperature, stress (with the run's
    /// contacts.csv: run it with --contacts) and nematic order in bins along one axis, averaged
    /// over the output frames in a window of time, into RUN_DIR/fields.csv.
    Fields {
        /// The run directory.
        run_dir: PathBuf,
        /// The axis the bins follow: y (horizontal slabs) or x (vertical slabs).
        #[arg(long, value_enum, default_value = "y")]
        axis: AxisArg,
        /// The number of bins.
        #[arg(long)]
        bins: usize,
        /// Average over the frames from this time on (s).
        #[arg(long)]
        from: Option<f64>,
        /// Average over the frames up to this time (s).
        #[arg(long)]
        to: Option<f64>,
        /// Outside a periodic cell, the bins' range lo,hi along the axis (cm; default: the box
        /// of four walls, else the bodies' extent); write `--range=-1,2` when lo is negative.
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
        range: Option<Vec<f64>>,
        /// In a Lees–Edwards cell, vx about the imposed profile γ̇ (y − Ly/2).
        #[arg(long)]
        relative: bool,
        /// Output file (default: RUN_DIR/fields.csv).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Contact-force statistics of a run made with --contacts (or of a directory's state.json,
    /// such as `dem2d relax` writes): the distribution of the normal forces over their mean
    /// into RUN_DIR/forces.csv, and the anisotropies a_c, a_n, a_t with the check
    /// sin φ ≈ ½(a_c + a_n + a_t) into RUN_DIR/forces.json.
    Forces {
        /// The run directory (or a `dem2d relax` output directory).
        run_dir: PathBuf,
        /// The frame (0 the first, -1 the last: the default); write `--frame=-2` for negatives.
        #[arg(long, allow_negative_numbers = true)]
        frame: Option<i64>,
        /// Every frame from this time on (s), pooled.
        #[arg(long)]
        from: Option<f64>,
        /// The histogram's bins.
        #[arg(long, default_value_t = 40)]
        bins: usize,
    },
    /// Run the benchmarks with published or closed-form answers (impacts, stress, packing,
    /// biaxial) and print each comparison: quantity, value, reference, tolerance, pass or fail.
    /// Exits 1 if any fails.
    Verify {
        /// Only the fastest subset (what CI runs, well under two minutes).
        #[arg(long, conflicts_with = "full")]
        quick: bool,
        /// The sizes of the user guide's figures (tens of minutes).
        #[arg(long)]
        full: bool,
        /// Also put the table of comparisons into its marked region of the user guide
        /// (`verify` for the default level, `verify_quick`, `verify_full`).
        #[arg(long)]
        docs: bool,
        /// Compare the table with the user guide's instead; fail if they differ.
        #[arg(long)]
        check: bool,
    },
    /// Draw a run (a directory written by `dem2d run`) as an SVG, or a PNG for `--out x.png`.
    Plot {
        /// The run directory.
        run_dir: PathBuf,
        /// Output file, `.svg` or `.png` (default: RUN_DIR/<kind>.svg).
        #[arg(long)]
        out: Option<PathBuf>,
        /// What to draw: the scene (outlines along the paths), the time series (height and angle
        /// against time) or P's quiescence measures against the step.
        #[arg(long, value_enum, default_value = "scene")]
        kind: PlotKind,
        /// Draw from this time on (s).
        #[arg(long)]
        from: Option<f64>,
        /// Draw up to this time (s).
        #[arg(long)]
        to: Option<f64>,
        /// Scene: time between the outlines drawn (s; default: 24 outlines over the time shown).
        #[arg(long)]
        every: Option<f64>,
        /// Scene: the last frame of the time shown only.
        #[arg(long)]
        last: bool,
        /// Scene: what colours the bodies (auto: one colour per body, or the normal contact
        /// force for a snapshot of more than 100 bodies); speed, omega (angular velocity),
        /// rotation (since the first frame) and force (normal contact force on each body) come
        /// with a colour bar.
        #[arg(long, value_enum, default_value = "auto")]
        color: ColorArg,
        /// Scene: figure width in pixels (default: 1000, wider for a snapshot of many bodies).
        #[arg(long)]
        width: Option<u32>,
        /// Scene, in a periodic cell: also draw the periodic images of the bodies a seam cuts,
        /// so that grains at a seam look whole.
        #[arg(long)]
        images: bool,
    },
    /// Write a run (a directory written by `dem2d run`) in another program's format: a
    /// LAMMPS-style text dump for OVITO (`--format lammps-dump`), one frame per output frame.
    Export {
        /// The run directory.
        run_dir: PathBuf,
        /// The format.
        #[arg(long, value_enum)]
        format: ExportFormat,
        /// Output file (default: RUN_DIR/dump.lammpstrj).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Write a run (a directory written by `dem2d run`) as a player that opens in any browser:
    /// one self-contained HTML file (no network, no external script) with every output frame's
    /// true outlines, play/pause, a time slider, speed, colour by a quantity, the contact
    /// forces when the run has contacts.csv, zoom and pan. With --out FILE.mp4 or FILE.gif, a
    /// movie instead, through ffmpeg.
    Animate {
        /// The run directory.
        run_dir: PathBuf,
        /// Output file, .html (default: RUN_DIR/animation.html), or .mp4 or .gif (ffmpeg).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Keep every N-th output frame (and the last), for a smaller file.
        #[arg(long, default_value_t = 1)]
        every: usize,
        /// A movie's colouring: speed, spin (angular velocity), rotation (since the first
        /// frame), force (normal contact force on each body), body (one colour each); the
        /// player offers its own choice (speed, spin, angle, material, body, contact force).
        #[arg(long, value_enum, default_value = "speed")]
        color: AnimateColor,
        /// A movie's frames per second.
        #[arg(long, default_value_t = 20)]
        fps: u32,
        /// A movie's width in pixels.
        #[arg(long, default_value_t = 800)]
        width: u32,
    },
    /// Generate a pile of disks or ellipses on a jittered lattice in a box, as a case file
    /// (`cases/settle_disks_10k.json` is `--shape disks --n 10000 --seed 1`).
    Generate {
        /// The grains: disks, or ellipses a/b = 1.5 of the same areas.
        #[arg(long, value_enum)]
        shape: PileShapeArg,
        /// Number of bodies (the box width grows with √n: 500 cm at 10 000).
        #[arg(long, default_value_t = 10_000)]
        n: usize,
        /// Seed of the random radii, jitter, orientations and velocities.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Ellipses' aspect ratio a/b.
        #[arg(long, default_value_t = 1.5)]
        aspect: f64,
        /// Radii uniform in [0.8, 1.2] cm, or bidisperse 1:1.4 (half of each, mean 1 cm).
        #[arg(long, value_enum, default_value = "uniform")]
        sizes: PileSizesArg,
        /// Coulomb friction between grains and with the walls.
        #[arg(long, default_value_t = 0.3)]
        friction: f64,
        /// What the normal spring acts on: the overlap area (conservative) or the depth (P).
        #[arg(long, value_enum, default_value = "area")]
        normal_force: NormalForceArg,
        /// Rest criterion: mean increment per step (cm) held for 1000 steps (default: a mean speed
        /// of 0.01 cm/s, 1e-7 cm per step at Δt = 1e-5 s).
        #[arg(long)]
        quiescence: Option<f64>,
        /// Longest run (s of simulated time).
        #[arg(long, default_value_t = 4.0)]
        duration: f64,
        /// Time step (s).
        #[arg(long, default_value_t = 1e-5)]
        dt: f64,
        /// Output file (default: standard output).
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum AxisArg {
    X,
    Y,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum ExportFormat {
    /// A LAMMPS-style text dump (`dump.lammpstrj`), read by OVITO.
    LammpsDump,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum AnimateColor {
    Speed,
    Spin,
    Rotation,
    Force,
    Body,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum PileShapeArg {
    Disks,
    Ellipses,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum PileSizesArg {
    Uniform,
    Bidisperse,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum NormalForceArg {
    Area,
    Depth,
}

impl From<NormalForceArg> for dem2d::contact_law::NormalForce {
    fn from(n: NormalForceArg) -> Self {
        match n {
            NormalForceArg::Area => dem2d::contact_law::NormalForce::Area,
            NormalForceArg::Depth => dem2d::contact_law::NormalForce::Depth,
        }
    }
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum ColorArg {
    Auto,
    Body,
    Speed,
    Omega,
    Rotation,
    Force,
}

/// What `dem2d plot` was asked besides the run and the kind.
struct PlotArgs {
    out: Option<PathBuf>,
    from: Option<f64>,
    to: Option<f64>,
    every: Option<f64>,
    last: bool,
    color: ColorArg,
    width: Option<u32>,
    images: bool,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum PlotKind {
    Scene,
    Series,
    Quiescence,
}

/// `--precision`: a positive, finite number (a standard error to stop at).
fn positive_precision(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(p) if p > 0.0 && p.is_finite() => Ok(p),
        Ok(p) => Err(format!(
            "--precision must be a positive standard error, got {p}"
        )),
        Err(e) => Err(format!("--precision: not a number ({e})")),
    }
}

/// An error for the user, with its exit code.
struct Failure {
    code: u8,
    message: String,
}

impl Failure {
    fn input(message: String) -> Self {
        Failure { code: 2, message }
    }

    fn failed(message: String) -> Self {
        Failure { code: 1, message }
    }
}

/// Writes `text` to standard output; a failure (a full device, a closed pipe) is an error that
/// names it rather than a panic.
fn print_out(text: &str) -> Result<(), Failure> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| Failure::failed(format!("standard output: cannot write: {e}")))
}

/// A line on standard error; if even that cannot be written there is nobody to tell.
fn say(text: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{text}");
}

/// SIGINT and SIGTERM ask a run to stop after its current step: the handler only records the
/// signal (an atomic store, async-signal-safe) and restores the default action, so that a second
/// signal ends the process at once. A two-function binding to the C library's `signal`, which
/// every Unix target of Rust links; no crate needed for it.
#[cfg(unix)]
mod signals {
    use std::ffi::c_int;
    use std::sync::atomic::{AtomicI32, Ordering};

    /// The signal received (0: none yet).
    pub static STOP: AtomicI32 = AtomicI32::new(0);
    const SIGINT: c_int = 2;
    const SIGTERM: c_int = 15;
    const SIG_DFL: usize = 0;

    unsafe extern "C" {
        /// C's `signal(2)`: `sighandler_t signal(int, sighandler_t)`, a handler being a
        /// pointer-sized value.
        fn signal(signum: c_int, handler: usize) -> usize;
    }

    extern "C" fn on_signal(sig: c_int) {
        STOP.store(sig, Ordering::Relaxed);
        // SAFETY: `signal` is async-signal-safe (POSIX), restoring the default action.
        unsafe {
            signal(sig, SIG_DFL);
        }
    }

    /// Installs the handler for SIGINT and SIGTERM.
    pub fn install() -> &'static AtomicI32 {
        let handler = on_signal as extern "C" fn(c_int) as usize;
        // SAFETY: the handler only stores into an atomic and calls `signal`.
        unsafe {
            signal(SIGINT, handler);
            signal(SIGTERM, handler);
        }
        &STOP
    }
}

/// Reads an input file (`-`: standard input) with the size cap of the scene reader.
fn read_input(file: &str) -> Result<String, Failure> {
    let name = if file == "-" { "<stdin>" } else { file };
    dem2d::scene::ranges::read_input(file).map_err(|e| Failure::input(format!("{name}: {e}")))
}

fn run_contact(file: &str) -> Result<(), Failure> {
    let name = if file == "-" { "<stdin>" } else { file };
    let text = read_input(file)?;
    let value = parse_json(&text, "pairs").map_err(|e| Failure::input(format!("{name}: {e}")))?;
    let pairs = parse_pairs(&value).map_err(|e| Failure::input(format!("{name}: {e}")))?;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    let failed = |e: std::io::Error| Failure::failed(format!("standard output: cannot write: {e}"));
    for (i, j) in &pairs {
        // (`None`: apart; `parse_pairs` rejects wall–wall pairs.)
        let c = contact(i, j);
        if i.is_clump() || j.is_clump() {
            // A clump pair: its deepest member contact, and every member pair's under
            // `members` (with `i_member`, `j_member`; 0 for a side that is not a clump).
            let mut v: serde_json::Value =
                serde_json::from_str(&contact_json(c.as_ref())).expect("a record");
            let members = dem2d::narrow_phase::member_contacts(
                i.into(),
                j.into(),
                dem2d::narrow_phase::Request::FULL,
            )
            .into_iter()
            .map(|(a, b, m)| {
                let mut r: serde_json::Value =
                    serde_json::from_str(&contact_json(m.as_ref())).expect("a record");
                r["i_member"] = a.into();
                r["j_member"] = b.into();
                r
            })
            .collect::<Vec<_>>();
            v["members"] = members.into();
            writeln!(out, "{v}").map_err(failed)?;
        } else {
            writeln!(out, "{}", contact_json(c.as_ref())).map_err(failed)?;
        }
    }
    out.flush().map_err(failed)
}

/// Sizes the global thread pool (`None`: rayon's default, one thread per core).
/// (At most [`dem2d::run::threads::max_threads`]: more is refused, exit 2, naming `--threads`.)
fn set_threads(threads: Option<usize>) -> Result<(), Failure> {
    if let Some(n) = threads {
        dem2d::run::threads::check_threads(n)
            .map_err(|e| Failure::input(format!("--threads: {e}")))?;
    }
    match threads {
        None => rayon::ThreadPoolBuilder::new()
            .use_current_thread()
            .build_global()
            .map_err(|e| Failure::failed(format!("thread pool: {e}"))),
        // The main thread is one of the pool's threads: the step's passes then start on it
        // without handing each pass to another thread and waiting (on one thread: no rayon
        // hand-off at all, the passes run in place).
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .use_current_thread()
            .build_global()
            .map_err(|e| Failure::failed(format!("--threads: {e}"))),
    }
}

/// What `dem2d run` was asked.
struct RunArgs<'a> {
    case: &'a std::path::Path,
    out: Option<PathBuf>,
    max_steps: Option<u64>,
    duration: Option<f64>,
    quiet: bool,
    overwrite: bool,
    vtk: bool,
    vtk_every: Option<u64>,
    dump: bool,
    analysis: bool,
    contacts: bool,
    checkpoint_every: Option<u64>,
}

fn run(args: RunArgs) -> Result<(), Failure> {
    let name = args.case.display().to_string();
    let text = read_input(&name)?;
    let file = dem2d::scene::CaseFile::from_json(&text)
        .map_err(|e| Failure::input(format!("{name}: {e}")))?;
    let (mut case, restart, run, read_warnings) =
        (file.case, file.restart, file.run, file.warnings);
    if let Some(d) = args.duration {
        if !(d.is_finite() && d > 0.0) {
            return Err(Failure::input(format!(
                "--duration: must be a positive time (s), got {d}"
            )));
        }
        dem2d::scene::ranges::check_steps(d, case.dt)
            .map_err(|e| Failure::input(format!("--duration: {}", e.message)))?;
        case.duration = d;
    }
    if let Some(state) = &restart
        && state.step >= case.steps()
    {
        // Named as the other refusals are: the field (or the option) that would have to change.
        let what = match args.duration {
            Some(_) => "--duration",
            None => "field `duration`",
        };
        return Err(Failure::input(format!(
            "{name}: {what}: the state is at step {} (t = {} s), already at the end of the case's \
             duration ({} s, {} steps): give --duration to run further (or a longer `duration`)",
            state.step,
            dem2d::run::time::time_text(state.step, case.dt),
            case.duration,
            case.steps()
        )));
    }
    let out_dir = args.out.unwrap_or_else(|| match &restart {
        None => default_out_dir(&case),
        Some(state) => {
            let mut d = default_out_dir(&case).into_os_string();
            d.push(format!("_from_step_{}", state.step));
            PathBuf::from(d)
        }
    });
    if args.checkpoint_every == Some(0) {
        return Err(Failure::input(
            "--checkpoint-every: must be at least 1 (steps)".into(),
        ));
    }
    if args.vtk_every == Some(0) {
        return Err(Failure::input("--vtk-every: must be at least 1".into()));
    }
    let vtk_every = (args.vtk || args.vtk_every.is_some() || case.output.vtk).then(|| {
        args.vtk_every
            .or(case.output.vtk_every)
            .unwrap_or(case.output_every)
    });
    #[cfg(unix)]
    let stop = Some(signals::install());
    #[cfg(not(unix))]
    let stop = None;
    let opts = RunOptions {
        out_dir: out_dir.clone(),
        progress: !args.quiet,
        max_steps: args.max_steps,
        overwrite: args.overwrite,
        stop,
        vtk_every,
        dump: args.dump,
        analysis: args.analysis || case.output.analysis,
        checkpoint_every: args.checkpoint_every,
        contacts: args.contacts || case.output.contacts,
        analysis_window: case.output.analysis_window,
        restart,
        run,
        input: Some(args.case.to_path_buf()),
        warnings: read_warnings,
    };
    let outcome = run_case(&case, &text, &opts).map_err(|e| match e {
        RunError::Occupied { .. } | RunError::Locked { .. } => Failure::input(e.to_string()),
        RunError::State(_) => Failure::input(format!("{name}: {e}")),
        RunError::Io(_) => Failure::failed(e.to_string()),
    })?;
    let s = &outcome.summary;
    for w in &s.warnings {
        say(&format!("dem2d: warning: {w}"));
    }
    let kept = format!("output so far kept in {}", out_dir.display());
    if let Some(e) = &outcome.summary_error {
        let first = match (&outcome.io_error, &outcome.blowup, outcome.signal) {
            (Some(io), _, _) => format!("{io}; then "),
            (_, Some(b), _) => format!("{name}: {b}; then "),
            (_, _, Some(sig)) => format!("{name}: interrupted by {}; then ", signal_name(sig)),
            _ => String::new(),
        };
        return Err(Failure::failed(format!(
            "{first}{e} (it still says `running`)"
        )));
    }
    if let Some(e) = &outcome.io_error {
        return Err(Failure::failed(format!(
            "{e}; the run stopped at step {} (summary.json says io_error)",
            s.steps
        )));
    }
    if let Some(b) = &outcome.blowup {
        return Err(Failure::failed(format!("{name}: {b}; {kept}")));
    }
    if let Some(sig) = outcome.signal {
        return Err(Failure {
            code: (128 + sig).clamp(0, 255) as u8,
            message: format!(
                "{name}: interrupted by {} after step {}; {kept} (continue with `dem2d run {}`)",
                signal_name(sig),
                s.steps,
                out_dir.join("state.json").display()
            ),
        });
    }
    let rest = match s.quiescent_step {
        Some(q) => format!(
            ", at rest at step {q} (quiescence {:e})",
            case.quiescence.unwrap_or(0.0)
        ),
        None if case.quiescence.is_some() => ", not at rest".to_string(),
        None => String::new(),
    };
    let status = match s.status {
        Status::MaxSteps => " (stopped by --max-steps)",
        _ => "",
    };
    print_out(&format!(
        "{}: {} steps{status}, t = {} s{rest}; wall time {:.2} s; dt = {:e}, dt_critical = {:.3e} (a priori), {} (contact network); output in {}\n",
        s.name,
        s.steps,
        s.time,
        s.wall_seconds,
        s.dt,
        s.dt_critical,
        s.dt_critical_observed
            .map_or("none".to_string(), |v| format!("{v:.3e}")),
        out_dir.display()
    ))
}

fn plot(run_dir: &std::path::Path, kind: PlotKind, args: PlotArgs) -> Result<(), Failure> {
    use dem2d::output::panels;
    use dem2d::output::plot::{self, ColorBy, SceneOptions, ScenePanel};
    if let Some(out) = &args.out
        && !out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("svg") || e.eq_ignore_ascii_case("png"))
    {
        return Err(Failure::input(format!(
            "--out {}: dem2d plot writes SVG or PNG; give a file name ending in .svg or .png",
            out.display()
        )));
    }
    for (name, v) in [("--from", args.from), ("--to", args.to)] {
        if let Some(v) = v
            && !v.is_finite()
        {
            return Err(Failure::input(format!(
                "{name}: must be a finite time, got {v}"
            )));
        }
    }
    if let (Some(a), Some(b)) = (args.from, args.to)
        && a > b
    {
        return Err(Failure::input(format!(
            "--from {a} is after --to {b}: the time window is empty"
        )));
    }
    if let Some(e) = args.every
        && !(e.is_finite() && e > 0.0)
    {
        return Err(Failure::input(format!(
            "--every: must be a positive time (s), got {e}"
        )));
    }
    if let Some(w) = args.width
        && !(200..=20_000).contains(&w)
    {
        return Err(Failure::input(format!(
            "--width: must be 200 … 20000 pixels, got {w}"
        )));
    }
    let scene_only =
        args.every.is_some() || args.last || args.images || !matches!(args.color, ColorArg::Auto);
    if scene_only && !matches!(kind, PlotKind::Scene) {
        return Err(Failure::input(
            "--every, --last, --color and --images apply to --kind scene only".into(),
        ));
    }
    let run = dem2d::output::run_data::RunData::load(run_dir)
        .map_err(|e| Failure::input(e.to_string()))?;
    if args.images && run.case.cell.is_none() {
        return Err(Failure::input(format!(
            "--images: {} has no periodic cell (`cell` in its case), so no images to draw",
            run_dir.display()
        )));
    }
    match run.summary["status"].as_str() {
        Some("completed" | "at_rest" | "max_steps") => {}
        Some(status) => say(&format!(
            "dem2d: warning: {}: the run's status is `{status}`{}: drawing what it wrote",
            run_dir.join("summary.json").display(),
            if status == "running" {
                " (it did not finish: killed, or still running)"
            } else {
                ""
            }
        )),
        None => say(&format!(
            "dem2d: warning: {}: no status (written by an older dem2d)",
            run_dir.join("summary.json").display()
        )),
    }
    for note in &run.incomplete {
        say(&format!("dem2d: warning: {note}"));
    }
    if matches!(kind, PlotKind::Scene) && !run.walls_at(run.frames.len() - 1).1 {
        say(&format!(
            "dem2d: warning: {}: no walls.csv (a run by an older dem2d): its servo walls are \
             drawn at their starting points",
            run_dir.display()
        ));
    }
    let name = match kind {
        PlotKind::Scene => "scene",
        PlotKind::Series => "series",
        PlotKind::Quiescence => "quiescence",
    };
    let out = args
        .out
        .unwrap_or_else(|| run_dir.join(format!("{name}.svg")));
    let window = |t: f64| args.from.is_none_or(|a| t >= a) && args.to.is_none_or(|b| t <= b);
    let shown = run.frames.iter().filter(|f| window(f.t)).count();
    if shown == 0 {
        let (a, b) = (run.frames[0].t, run.frames[run.frames.len() - 1].t);
        return Err(Failure::input(format!(
            "--from/--to: no frame of {} in the time window (its frames are from t = {a} to {b} s)",
            run_dir.display()
        )));
    }
    let title = format!(
        "{} ({} steps, t = {:.4} s)",
        run.case.name,
        run.summary["steps"],
        run.summary["time"].as_f64().unwrap_or(f64::NAN)
    );
    // The series and quiescence panels take the window as a copy of the run cut to it.
    let mut cut = run.clone();
    cut.frames.retain(|f| window(f.t));
    cut.increments.retain(|i| window(i.t));
    let result = match kind {
        PlotKind::Scene => plot::scene(
            &out,
            &[ScenePanel {
                title,
                runs: vec![(&run, String::new())],
            }],
            &SceneOptions {
                t_min: args.from,
                t_max: args.to,
                outline_every: args.every,
                last_only: args.last,
                width: args.width,
                color: match args.color {
                    ColorArg::Auto => ColorBy::Auto,
                    ColorArg::Body => ColorBy::Body,
                    ColorArg::Speed => ColorBy::Speed,
                    ColorArg::Omega => ColorBy::Omega,
                    ColorArg::Rotation => ColorBy::Rotation,
                    ColorArg::Force => ColorBy::Force,
                },
                images: args.images,
                ..SceneOptions::default()
            },
        ),
        PlotKind::Series => plot::line_panels(
            &out,
            (1000, 700),
            (2, 1),
            &panels::time_series(&[(&cut, "")], &title),
        ),
        PlotKind::Quiescence => plot::line_panels(
            &out,
            (1000, 500),
            (1, 1),
            &[panels::quiescence(&cut, &title, None)],
        ),
    };
    result.map_err(|e| Failure::failed(format!("{}: {e}", out.display())))?;
    print_out(&format!("{}\n", out.display()))
}

/// Reads a run directory for `export` and `animate`, with the warnings `plot` gives for a run
/// that did not finish and for files cut short.
fn load_run(run_dir: &std::path::Path) -> Result<dem2d::output::run_data::RunData, Failure> {
    let run = dem2d::output::run_data::RunData::load(run_dir)
        .map_err(|e| Failure::input(e.to_string()))?;
    match run.summary["status"].as_str() {
        Some("completed" | "at_rest" | "max_steps") | None => {}
        Some(status) => say(&format!(
            "dem2d: warning: {}: the run's status is `{status}`: writing the frames it wrote",
            run_dir.join("summary.json").display()
        )),
    }
    for note in &run.incomplete {
        say(&format!("dem2d: warning: {note}"));
    }
    Ok(run)
}

fn export(run_dir: &std::path::Path, out: Option<&std::path::Path>) -> Result<(), Failure> {
    let run = load_run(run_dir)?;
    let out = out.map_or_else(
        || run_dir.join(dem2d::output::dump::FILE),
        std::path::Path::to_path_buf,
    );
    let frames =
        dem2d::output::dump::export_run(&run, &out).map_err(|e| Failure::failed(e.to_string()))?;
    print_out(&format!(
        "{}: {frames} frames, {} bodies at most\n",
        out.display(),
        run.most_bodies()
    ))
}

fn animate(
    run_dir: &std::path::Path,
    out: Option<&std::path::Path>,
    every: usize,
    (color, fps, width): (AnimateColor, u32, u32),
) -> Result<(), Failure> {
    use dem2d::output::player;
    if every == 0 {
        return Err(Failure::input("--every: must be at least 1".into()));
    }
    let out = out.map_or_else(
        || run_dir.join("animation.html"),
        std::path::Path::to_path_buf,
    );
    let ext = out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let movie = match ext.as_deref() {
        Some("html" | "htm") => None,
        Some("mp4") => Some(player::Movie::Mp4),
        Some("gif") => Some(player::Movie::Gif),
        _ => {
            return Err(Failure::input(format!(
                "--out {}: dem2d animate writes .html (the player), .mp4 or .gif (through \
                 ffmpeg); give a file name ending in one of them",
                out.display()
            )));
        }
    };
    if movie.is_some() {
        if !(1..=120).contains(&fps) {
            return Err(Failure::input(format!("--fps: must be 1 … 120, got {fps}")));
        }
        if !(100..=8000).contains(&width) {
            return Err(Failure::input(format!(
                "--width: must be 100 … 8000 pixels, got {width}"
            )));
        }
    }
    let run = load_run(run_dir)?;
    let frames = player::thin(&run, every);
    match movie {
        None => {
            let bytes = player::write_player(&run, &frames, &out)
                .map_err(|e| Failure::failed(e.to_string()))?;
            print_out(&format!(
                "{}: {} frames, {:.1} MB\n",
                out.display(),
                frames.len(),
                bytes as f64 / 1e6
            ))
        }
        Some(kind) => {
            use dem2d::output::plot::ColorBy;
            let by = match color {
                AnimateColor::Speed => ColorBy::Speed,
                AnimateColor::Spin => ColorBy::Omega,
                AnimateColor::Rotation => ColorBy::Rotation,
                AnimateColor::Force => ColorBy::Force,
                AnimateColor::Body => ColorBy::Body,
            };
            player::write_movie(&run, &frames, &out, kind, by, (fps, width)).map_err(
                |e| match e {
                    player::MovieError::NoFfmpeg(m) => Failure::input(m),
                    player::MovieError::Failed(m) => Failure::failed(m),
                },
            )?;
            print_out(&format!("{}: {} frames\n", out.display(), frames.len()))
        }
    }
}

fn generate(
    shape: PileShapeArg,
    n: usize,
    seed: u64,
    (aspect, sizes, friction, normal_force): (f64, PileSizesArg, f64, NormalForceArg),
    (quiescence, duration, dt): (Option<f64>, f64, f64),
    out: Option<&std::path::Path>,
) -> Result<(), Failure> {
    use dem2d::scene::generate::{PileShape, PileSizes, PileSpec};
    if n == 0 {
        return Err(Failure::input("--n: must be at least 1".into()));
    }
    if !(aspect.is_finite() && (1.0..=20.0).contains(&aspect)) {
        return Err(Failure::input(format!(
            "--aspect: must be in [1, 20], got {aspect}"
        )));
    }
    if !(friction.is_finite() && friction >= 0.0) {
        return Err(Failure::input(format!(
            "--friction: must be finite and ≥ 0, got {friction}"
        )));
    }
    let mut spec = PileSpec::new(
        match shape {
            PileShapeArg::Disks => PileShape::Disks,
            PileShapeArg::Ellipses => PileShape::Ellipses,
        },
        n,
        seed,
    );
    spec.aspect = aspect;
    spec.sizes = match sizes {
        PileSizesArg::Uniform => PileSizes::Uniform,
        PileSizesArg::Bidisperse => PileSizes::Bidisperse,
    };
    spec.friction = friction;
    spec.normal_force = normal_force.into();
    // The pile's stiffness puts its a-priori critical step near 1e-4 s.
    if !(dt.is_finite() && dt > 0.0 && dt <= 1e-4) {
        return Err(Failure::input(format!(
            "--dt: must be in (0, 1e-4] s, got {dt}"
        )));
    }
    // The default rest criterion is a mean speed (0.01 cm/s), whatever the step.
    let quiescence = quiescence.unwrap_or(spec.quiescence * dt / spec.dt);
    if !(quiescence.is_finite() && quiescence > 0.0) {
        return Err(Failure::input(format!(
            "--quiescence: must be positive, got {quiescence}"
        )));
    }
    if !(duration.is_finite() && duration > 0.0 && duration <= 1e4) {
        return Err(Failure::input(format!(
            "--duration: must be in (0, 1e4] s, got {duration}"
        )));
    }
    spec.quiescence = quiescence;
    spec.duration = duration;
    spec.dt = dt;
    let text = spec.case_json();
    match out {
        Some(path) => std::fs::write(path, text).map_err(|e| Failure {
            code: 1,
            message: format!("{}: cannot write: {e}", path.display()),
        }),
        None => print_out(&text),
    }
}

/// What `--docs` and `--check` ask of the user guide's tables.
fn docs_mode(docs: bool, check: bool) -> Option<dem2d::output::docs_tables::Mode> {
    use dem2d::output::docs_tables::Mode;
    match (docs, check) {
        (_, true) => Some(Mode::Check),
        (true, false) => Some(Mode::Write),
        (false, false) => None,
    }
}

/// Refreshes (or checks) the user guide's marked table `section` (`<!-- figures:SECTION -->`)
/// in the repository at the current directory; says what it did on stderr.
fn refresh_docs(
    section: &str,
    md: &str,
    mode: dem2d::output::docs_tables::Mode,
) -> Result<(), Failure> {
    use dem2d::output::docs_tables;
    let stale = docs_tables::refresh(
        std::path::Path::new("."),
        &[(section, md.to_string())],
        mode,
    )
    .map_err(Failure::failed)?;
    say(&format!(
        "dem2d: {}",
        docs_tables::report(&stale, mode).map_err(Failure::failed)?
    ));
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Contact { file } => run_contact(file),
        Command::Study {
            name,
            write_cases,
            grains,
            packings,
            aspects,
            inertial,
            threads,
            quick,
            docs,
            check,
            out,
            seed,
            precision,
        } => set_threads(*threads).and_then(|()| {
            study::run(
                *name,
                &study::Options {
                    write_cases: *write_cases,
                    grains: *grains,
                    packings: *packings,
                    aspects: aspects.clone(),
                    inertial: inertial.clone(),
                    out: out.clone(),
                    quick: *quick,
                    seed: *seed,
                    precision: *precision,
                },
                docs_mode(*docs, *check),
            )
        }),
        Command::Run {
            case,
            out,
            max_steps,
            duration,
            quiet,
            threads,
            overwrite,
            vtk,
            vtk_every,
            dump,
            analysis,
            contacts,
            checkpoint_every,
        } => set_threads(*threads).and_then(|()| {
            run(RunArgs {
                case,
                out: out.clone(),
                max_steps: *max_steps,
                duration: *duration,
                quiet: *quiet,
                overwrite: *overwrite,
                vtk: *vtk,
                vtk_every: *vtk_every,
                dump: *dump,
                analysis: *analysis,
                contacts: *contacts,
                checkpoint_every: *checkpoint_every,
            })
        }),
        Command::Relax {
            case,
            out,
            tolerance,
            max_iterations,
            energy,
            stall,
            overwrite,
            quiet,
            threads,
        } => set_threads(*threads).and_then(|()| {
            relax::run(relax::RelaxArgs {
                case,
                out,
                tolerance: *tolerance,
                max_iterations: *max_iterations,
                energy: *energy,
                stall: *stall,
                overwrite: *overwrite,
                quiet: *quiet,
            })
        }),
        Command::Analyze {
            run_dir,
            window,
            out,
        } => analyze::run(run_dir, window.as_deref(), out.as_deref())
            .map_err(|(code, message)| Failure { code, message }),
        Command::Fields {
            run_dir,
            axis,
            bins,
            from,
            to,
            range,
            relative,
            out,
        } => fields(
            run_dir,
            &dem2d::output::fields::FieldRequest {
                axis: match axis {
                    AxisArg::X => dem2d::analysis::fields::Axis::X,
                    AxisArg::Y => dem2d::analysis::fields::Axis::Y,
                },
                bins: *bins,
                from: *from,
                to: *to,
                range: None,
                relative: *relative,
            },
            range.as_deref(),
            out.as_deref(),
        ),
        Command::Forces {
            run_dir,
            frame,
            from,
            bins,
        } => forces(
            run_dir,
            &dem2d::output::force_statistics::ForcesRequest {
                frame: *frame,
                from: *from,
                bins: *bins,
            },
        ),
        Command::Verify {
            quick,
            full,
            docs,
            check,
        } => {
            let level = match (quick, full) {
                (true, _) => verify::Level::Quick,
                (_, true) => verify::Level::Full,
                _ => verify::Level::Default,
            };
            match verify::run(level) {
                Err(e) => Err(Failure::failed(format!("dem2d verify: {e}"))),
                Ok((passed, md)) => {
                    let docs = match docs_mode(*docs, *check) {
                        Some(mode) => refresh_docs(level.table_name(), &md, mode),
                        None => Ok(()),
                    };
                    if passed {
                        docs
                    } else {
                        Err(Failure::failed(
                            "dem2d verify: some comparisons failed".into(),
                        ))
                    }
                }
            }
        }
        Command::Plot {
            run_dir,
            out,
            kind,
            from,
            to,
            every,
            last,
            color,
            width,
            images,
        } => plot(
            run_dir,
            *kind,
            PlotArgs {
                out: out.clone(),
                from: *from,
                to: *to,
                every: *every,
                last: *last,
                color: *color,
                width: *width,
                images: *images,
            },
        ),
        Command::Export {
            run_dir,
            format: ExportFormat::LammpsDump,
            out,
        } => export(run_dir, out.as_deref()),
        Command::Animate {
            run_dir,
            out,
            every,
            color,
            fps,
            width,
        } => animate(run_dir, out.as_deref(), *every, (*color, *fps, *width)),
        Command::Generate {
            shape,
            n,
            seed,
            out,
            aspect,
            sizes,
            friction,
            normal_force,
            quiescence,
            duration,
            dt,
        } => generate(
            *shape,
            *n,
            *seed,
            (*aspect, *sizes, *friction, *normal_force),
            (*quiescence, *duration, *dt),
            out.as_deref(),
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            say(&format!("dem2d: {}", f.message));
            ExitCode::from(f.code)
        }
    }
}

/// `dem2d fields`: writes RUN_DIR/fields.csv (or `out`).
fn fields(
    dir: &Path,
    request: &dem2d::output::fields::FieldRequest,
    range: Option<&[f64]>,
    out: Option<&Path>,
) -> Result<(), Failure> {
    let mut request = request.clone();
    request.range = match range {
        None => None,
        Some(&[lo, hi]) if lo < hi && lo.is_finite() && hi.is_finite() => Some((lo, hi)),
        Some(r) => {
            return Err(Failure {
                code: 2,
                message: format!("--range: expected lo,hi with lo < hi, got {r:?}"),
            });
        }
    };
    let f = dem2d::output::fields::run_fields(dir, &request).map_err(|message| Failure {
        // The options' mistakes exit 2, the files' 1.
        code: if message.starts_with("--") { 2 } else { 1 },
        message,
    })?;
    for note in &f.notes {
        eprintln!("dem2d fields: {note}");
    }
    let out = out.map_or_else(|| dir.join("fields.csv"), Path::to_path_buf);
    std::fs::write(&out, dem2d::output::fields::fields_csv(&f))
        .map_err(|e| Failure::failed(format!("{}: cannot write: {e}", out.display())))?;
    println!("{}", out.display());
    Ok(())
}

/// `dem2d forces`: writes RUN_DIR/forces.csv and RUN_DIR/forces.json and prints the check.
fn forces(
    dir: &Path,
    request: &dem2d::output::force_statistics::ForcesRequest,
) -> Result<(), Failure> {
    use dem2d::output::force_statistics::{forces_csv, forces_json, run_forces};
    let r = run_forces(dir, request).map_err(|message| Failure {
        code: if message.starts_with("--") { 2 } else { 1 },
        message,
    })?;
    for (name, text) in [
        ("forces.csv", forces_csv(&r)),
        ("forces.json", forces_json(&r)),
    ] {
        let out = dir.join(name);
        std::fs::write(&out, text)
            .map_err(|e| Failure::failed(format!("{}: cannot write: {e}", out.display())))?;
        println!("{}", out.display());
    }
    let f = &r.check.fabric;
    println!(
        "{} contacts over {} frame(s) from {}: mean force {:.6e} dyn/cm; a_c {:.4}, a_n {:.4}, \
         a_t {:.4}: ½(a_c + a_n + a_t) = {:.4} against sin φ = {:.4}",
        r.distribution.count,
        r.frames,
        r.source,
        r.distribution.mean,
        f.a_c,
        f.a_n,
        f.a_t,
        r.check.half_sum,
        r.check.sin_phi
    );
    Ok(())
}

//! `dem2d-lab`: what regenerates this project's own figures, user-guide tables and benchmarks —
//! not what a user of dem2d runs (that is the `dem2d` binary). Run from the repository's root:
//!
//! ```sh
//! cargo run --release -p dem2d-lab -- figures --docs      # figures/ and the guide's tables
//! cargo run --release -p dem2d-lab -- bench --docs        # the throughput table
//! cargo run --release -p dem2d-lab -- bench --peers --steps 10000 --reps 3 --normal-force area,depth --docs
//! cargo run --release -p dem2d-lab -- fields-forces   # docs/src/results/fields-forces.md
//! cargo run --release -p dem2d-lab -- fuzz --mutants 2000 --seed 1   # a fuzzing round (fuzz.rs)
//! cargo run --release -p dem2d-lab -- cross-check --fire 10000   # against LAMMPS (crosscheck.rs)
//! ```
//!
//! `figures`, `fuzz` and `bench --peers` run the `dem2d` binary itself (as a user would): [`dem2d_exe`]
//! builds it first when the lab runs under `cargo run`.

mod area_law_report;
mod bench;
mod crosscheck;
mod fields_forces;
mod fuzz;
mod peers;
mod report;

use clap::{Parser, Subcommand};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

/// The allocator `dem2d run` has (huge pages), counting bytes for `bench`'s heap per body.
#[global_allocator]
static GLOBAL: dem2d::alloc::HugePageAllocator = dem2d::alloc::HugePageAllocator;

#[derive(Parser)]
#[command(
    name = "dem2d-lab",
    version,
    about = "Regenerates dem2d's own figures, user-guide tables and benchmarks"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Throughput of settled piles of disks and ellipses: particle-steps/s, ns per contact and
    /// heap bytes per body, at each size and thread count, and whether every thread count gives
    /// the bit-identical trajectory. Settled piles are cached in --cache.
    Bench {
        /// Piles to run.
        #[arg(
            long,
            value_enum,
            value_delimiter = ',',
            default_value = "disks,ellipses"
        )]
        shapes: Vec<PileShapeArg>,
        /// Numbers of bodies (multiples of 10 000 above 10 000: tiles of the 10⁴ pile).
        #[arg(long, value_delimiter = ',', default_value = "1000,10000,100000")]
        sizes: Vec<usize>,
        /// Timed steps per repetition (default 500; with --peers, 10 000).
        #[arg(long)]
        steps: Option<u64>,
        /// Repetitions (the median is reported); each times every size, thread count and law
        /// of a shape once, in turn.
        #[arg(long, default_value_t = 3)]
        reps: usize,
        /// Thread counts (default: 1 and all cores).
        #[arg(long, value_delimiter = ',')]
        threads: Vec<usize>,
        /// Normal-force laws to time each settled pile under (with --peers: to run the ellipse
        /// pile under, a row each).
        #[arg(long, value_enum, value_delimiter = ',', default_value = "area")]
        normal_force: Vec<NormalForceArg>,
        /// Cache of settled piles.
        #[arg(long, default_value = "target/bench-piles")]
        cache: PathBuf,
        /// Write the Markdown table here too.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Refresh the user guide's `<!-- figures:bench -->` table (with --peers,
        /// `<!-- figures:peers -->`); run from the repository.
        #[arg(long)]
        docs: bool,
        /// Instead: `dem2d run` (one thread) on the settled 10⁴-disk and 10⁴-ellipse piles (the
        /// ellipses under each --normal-force law) against LIGGGHTS (`liggghts`) and LAMMPS
        /// (`lmp`) on the disk pile, when installed (decks in lab/peers/), interleaved;
        /// particle-steps per CPU-second and per wall-second of the time loop, medians, and the
        /// ratios to LIGGGHTS.
        #[arg(long)]
        peers: bool,
    },
    /// Regenerate every figure and table of the user guide into figures/ (runs the paper's
    /// cases, the time-step sweeps and the contact-kernel report; about 10 s). The guide itself
    /// is refreshed only with --docs.
    Figures {
        /// Output directory for SVG, CSV and Markdown.
        #[arg(long, default_value = "figures")]
        out: PathBuf,
        /// Case directory.
        #[arg(long, default_value = "cases")]
        cases: PathBuf,
        /// Where the runs go.
        #[arg(long, default_value = "target/figure-runs")]
        work: PathBuf,
        /// Refresh the marked tables of the user guide (README.md, docs/src; run from the
        /// repository). The tables are deterministic; timings go to WORK/timings.md.
        #[arg(long)]
        docs: bool,
        /// Compare the guide's tables with these instead of writing them; fail if they differ.
        #[arg(long)]
        check: bool,
        /// Fewer sweep points and repetitions (a quick look, not the guide's numbers).
        #[arg(long)]
        quick: bool,
        /// Where every SVG is also rendered as PNG (default: WORK/png).
        #[arg(long)]
        png: Option<PathBuf>,
    },
    /// The same physics in another code: a constant-volume Lees–Edwards shear of frictional
    /// bidisperse disks in `dem2d run` and in LAMMPS (`lmp`, pair_style granular) from the same
    /// initial states, μ, σ_yy, Z and I side by side with standard errors and their ratios,
    /// and the first steps from a static state (docs/src/validation/lammps.md). Prints
    /// Markdown; exit code 2 without `lmp`.
    CrossCheck {
        /// The packing (disks, a cell periodic in x and y) the states are made from.
        #[arg(long, default_value = "cases/jammed_disks_256.json")]
        case: PathBuf,
        /// The shear run's packing fraction (the packing and its cell scaled).
        #[arg(long, default_value_t = 0.7855)]
        phi: f64,
        /// The static state's scale of the packing (below 1: overlapping).
        #[arg(long, default_value_t = 0.99)]
        static_scale: f64,
        /// γ̇ (1/s).
        #[arg(long, default_value_t = 3.0)]
        shear_rate: f64,
        /// Time steps (s): the static states run at the first, the shear at each.
        #[arg(long, value_delimiter = ',', default_values_t = [5e-5, 2e-5])]
        dt: Vec<f64>,
        /// Strain of each shear run.
        #[arg(long, default_value_t = 21.0)]
        strain: f64,
        /// Strain between samples.
        #[arg(long, default_value_t = 0.03)]
        sample_strain: f64,
        /// Strain left out of the means.
        #[arg(long, default_value_t = 3.0)]
        transient_strain: f64,
        /// k_n = k_t (dyn/cm).
        #[arg(long, default_value_t = 1e6)]
        kn: f64,
        /// Coulomb friction μ.
        #[arg(long, default_value_t = 0.4)]
        friction: f64,
        /// The restitution whose dashpot (for the small–large pair) both codes use.
        #[arg(long, default_value_t = 0.5)]
        restitution: f64,
        /// Where the runs go.
        #[arg(long, default_value = "target/cross-check")]
        work: PathBuf,
        /// Also LAMMPS's FIRE against `dem2d relax` on --case, this many iterations each.
        #[arg(long)]
        fire: Option<u64>,
        /// Refresh the user guide's `<!-- figures:lammps -->` section
        /// (docs/src/validation/lammps.md); run from the repository.
        #[arg(long)]
        docs: bool,
    },
    /// The figures and numbers of docs/src/results/fields-forces.md: the sheared cell's
    /// profiles (`dem2d fields`) and the contact-force distributions (`dem2d forces`) of
    /// relaxed and sheared disks and ellipses, with the fitted tail exponent α of each (about a
    /// minute of runs: not part of `figures`).
    FieldsForces {
        /// Output directory for the SVGs.
        #[arg(long, default_value = "figures")]
        out: PathBuf,
        /// Case directory.
        #[arg(long, default_value = "cases")]
        cases: PathBuf,
        /// Where the runs (and PNG copies of the figures) go.
        #[arg(long, default_value = "target/figure-runs/fields-forces")]
        work: PathBuf,
    },
    /// A seeded fuzzing round over the newer features (periodic cells, imposed pressure,
    /// Lees–Edwards shear, relax, insertion and outflow, segments, materials, wall programs,
    /// restarts): mutated case files run through `dem2d run` / `dem2d relax`, each classified
    /// ok, refused, detected, PANIC, HANG, SILENT (exit 0 with wrong outputs) or BAD_EXIT.
    /// Writes OUT/report.md, OUT/mutants.csv and the failing mutants to OUT/failures/; exit
    /// code 1 when any mutant fails.
    Fuzz {
        /// Number of mutants.
        #[arg(long, default_value_t = 2000)]
        mutants: usize,
        /// The seed: mutant k of a seed is always the same file.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Where the report, the list of mutants and the failures go.
        #[arg(long, default_value = "target/fuzz")]
        out: PathBuf,
        /// Seconds a run may take before it counts as a hang.
        #[arg(long, default_value_t = 10)]
        timeout: u64,
        /// Runs at a time.
        #[arg(long, default_value_t = 1)]
        jobs: usize,
        /// Steps per run (`--max-steps`; for relax, `--max-iterations`).
        #[arg(long, default_value_t = 20000)]
        max_steps: u64,
        /// Run only mutant K of the seed (a replay of a failure).
        #[arg(long)]
        only: Option<usize>,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum PileShapeArg {
    Disks,
    Ellipses,
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

/// Writes `text` to standard output; a failure is an error that names it.
fn print_out(text: &str) -> Result<(), Failure> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| Failure::failed(format!("standard output: cannot write: {e}")))
}

/// A line on standard error.
fn say(text: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{text}");
}

/// The `dem2d` binary the lab runs (`figures` runs the paper's cases through it, `bench --peers`
/// times it): `$DEM2D_BIN` if set, else the `dem2d` beside this binary (the same target
/// directory). Under `cargo run` (which sets `$CARGO`) it is built first with the same profile,
/// so that it is never an older build than the code the lab's numbers are said to come from.
pub fn dem2d_exe() -> Result<PathBuf, String> {
    if let Some(p) = std::env::var_os("DEM2D_BIN") {
        return Ok(PathBuf::from(p));
    }
    let me = std::env::current_exe().map_err(|e| format!("this program's path: {e}"))?;
    let dir = me.parent().ok_or("this program has no directory")?;
    if let Some(cargo) = std::env::var_os("CARGO") {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let mut build = std::process::Command::new(cargo);
        build
            .current_dir(&root)
            .args(["build", "--quiet", "--bin", "dem2d"]);
        if dir.ends_with("release") {
            build.arg("--release");
        }
        let status = build
            .status()
            .map_err(|e| format!("cargo build --bin dem2d: {e}"))?;
        if !status.success() {
            return Err("cargo build --bin dem2d failed".into());
        }
    }
    let exe = dir.join(format!("dem2d{}", std::env::consts::EXE_SUFFIX));
    if exe.is_file() {
        Ok(exe)
    } else {
        Err(format!(
            "{}: no dem2d binary beside dem2d-lab (build it: cargo build --release; or set DEM2D_BIN)",
            exe.display()
        ))
    }
}

/// `cross-check`: checks the options, finds `dem2d` and `lmp`, prints the report.
fn cross_check(mut o: crosscheck::CrossOptions, docs: bool) -> Result<(), Failure> {
    let positive = [
        ("--phi", o.phi),
        ("--static-scale", o.static_scale),
        ("--kn", o.kn),
        ("--strain", o.strain),
        ("--sample-strain", o.sample_strain),
        ("--shear-rate", o.shear_rate),
    ];
    if o.dt.is_empty() || o.dt.iter().any(|d| !(d.is_finite() && *d > 0.0)) {
        return Err(Failure::input(format!(
            "--dt: positive time steps, got {:?}",
            o.dt
        )));
    }
    for (name, v) in positive {
        if !(v.is_finite() && v > 0.0) {
            return Err(Failure::input(format!("{name}: must be positive, got {v}")));
        }
    }
    if o.phi >= 1.0 {
        return Err(Failure::input(format!(
            "--phi: must be below 1, got {}",
            o.phi
        )));
    }
    if !(o.restitution > 0.0 && o.restitution < 1.0) {
        return Err(Failure::input(format!(
            "--restitution: must be in (0, 1), got {}",
            o.restitution
        )));
    }
    if !(o.friction.is_finite() && o.friction >= 0.0) {
        return Err(Failure::input(format!(
            "--friction: must be non-negative, got {}",
            o.friction
        )));
    }
    if !(o.transient_strain.is_finite()
        && o.transient_strain >= 0.0
        && o.transient_strain < o.strain)
    {
        return Err(Failure::input(format!(
            "--transient-strain: in [0, --strain), got {}",
            o.transient_strain
        )));
    }
    if o.sample_strain > o.strain {
        return Err(Failure::input(format!(
            "--sample-strain: at most --strain ({}), got {}",
            o.strain, o.sample_strain
        )));
    }
    crosscheck::check_packing(&o.case).map_err(|e| Failure::input(format!("--case: {e}")))?;
    o.lmp = peers::find_executable(&["lmp", "lmp_serial", "lmp_mpi"]).ok_or_else(|| {
        Failure::input("LAMMPS (`lmp`) is not on PATH (Debian: apt-get install lammps)".into())
    })?;
    o.dem2d = dem2d_exe().map_err(Failure::failed)?;
    let md = crosscheck::run(&o).map_err(Failure::failed)?;
    publish_table(md, "lammps", None, docs_mode(docs, false))
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

/// Refreshes (or checks) the user guide's marked table `section` in the repository at the current
/// directory; says what it did on stderr.
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
        "dem2d-lab: {}",
        docs_tables::report(&stale, mode).map_err(Failure::failed)?
    ));
    Ok(())
}

#[allow(clippy::too_many_arguments)] // one argument per command-line option
fn bench(
    shapes: &[PileShapeArg],
    sizes: &[usize],
    steps: u64,
    reps: usize,
    threads: &[usize],
    normal_forces: &[NormalForceArg],
    cache: &std::path::Path,
    out: Option<&std::path::Path>,
    docs: bool,
) -> Result<(), Failure> {
    use dem2d::scene::generate::PileShape;
    if let Some(&n) = sizes
        .iter()
        .find(|&&n| n == 0 || (n > 10_000 && n % 10_000 != 0))
    {
        return Err(Failure::input(format!(
            "--sizes: {n} is not a pile size (1…10000, or a multiple of 10000)"
        )));
    }
    for &n in threads {
        dem2d::run::threads::check_threads(n)
            .map_err(|e| Failure::input(format!("--threads: {e}")))?;
    }
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = if threads.is_empty() {
        if all > 1 { vec![1, all] } else { vec![1] }
    } else {
        threads.to_vec()
    };
    let opts = crate::bench::BenchOptions {
        shapes: shapes
            .iter()
            .map(|s| match s {
                PileShapeArg::Disks => PileShape::Disks,
                PileShapeArg::Ellipses => PileShape::Ellipses,
            })
            .collect(),
        sizes: sizes.to_vec(),
        steps,
        reps,
        threads,
        normal_forces: normal_forces.iter().map(|&n| n.into()).collect(),
        cache: Some(cache.to_path_buf()),
        progress: true,
    };
    let rows = crate::bench::run(&opts, &dem2d::alloc::allocated, &dem2d::alloc::allocations)
        .map_err(|e| Failure {
            code: 1,
            message: e.to_string(),
        })?;
    publish_table(
        crate::bench::markdown(&rows),
        "bench",
        out,
        docs_mode(docs, false),
    )
}

/// Prints a Markdown table, writes it to `out` and refreshes the user guide's table `section`
/// (`<!-- figures:SECTION -->`) when asked.
fn publish_table(
    md: String,
    section: &str,
    out: Option<&std::path::Path>,
    docs: Option<dem2d::output::docs_tables::Mode>,
) -> Result<(), Failure> {
    print_out(&md)?;
    if let Some(path) = out {
        std::fs::write(path, &md).map_err(|e| Failure {
            code: 1,
            message: format!("{}: cannot write: {e}", path.display()),
        })?;
    }
    if let Some(mode) = docs {
        refresh_docs(section, &md, mode)?;
    }
    Ok(())
}

/// `dem2d bench --peers`: see [`peers`].
#[allow(clippy::too_many_arguments)] // one argument per command-line option
fn bench_peers(
    shapes: &[PileShapeArg],
    laws: &[NormalForceArg],
    sizes: &[usize],
    steps: u64,
    reps: usize,
    cache: &std::path::Path,
    out: Option<&std::path::Path>,
    docs: bool,
) -> Result<(), Failure> {
    use dem2d::scene::generate::PileShape;
    // The default sizes are the throughput table's; the peers compare the 10⁴ piles.
    let n = match sizes {
        [n] if *n >= 1 && *n <= 10_000 => *n,
        _ if sizes == [1000, 10_000, 100_000] => 10_000,
        _ => {
            return Err(Failure::input(
                "--sizes: --peers takes one pile size, 1…10000 (default 10000)".into(),
            ));
        }
    };
    if steps == 0 {
        return Err(Failure::input("--steps: must be at least 1".into()));
    }
    let opts = crate::peers::PeerOptions {
        shapes: shapes
            .iter()
            .map(|s| match s {
                PileShapeArg::Disks => PileShape::Disks,
                PileShapeArg::Ellipses => PileShape::Ellipses,
            })
            .collect(),
        laws: laws.iter().map(|&l| l.into()).collect(),
        n,
        steps,
        reps,
        cache: Some(cache.to_path_buf()),
        progress: true,
    };
    let load = crate::peers::load_average();
    let report = crate::peers::run(&opts).map_err(|e| Failure {
        code: 1,
        message: e.to_string(),
    })?;
    publish_table(
        crate::peers::markdown(&report, load.as_deref()),
        "peers",
        out,
        docs_mode(docs, false),
    )
}

fn figures(
    out: PathBuf,
    cases: PathBuf,
    work: PathBuf,
    docs: Option<dem2d::output::docs_tables::Mode>,
    (quick, png): (bool, Option<PathBuf>),
) -> Result<(), Failure> {
    let opts = crate::report::FigureOptions {
        cases,
        out,
        work,
        docs,
        quick,
        png,
    };
    let written = crate::report::figures(&opts).map_err(|e| Failure {
        code: 1,
        message: e.to_string(),
    })?;
    for f in written {
        print_out(&format!("{}\n", f.display()))?;
    }
    Ok(())
}

/// `dem2d-lab fuzz`: see [`fuzz`].
fn fuzz(opts: &fuzz::FuzzOptions) -> Result<(), Failure> {
    if opts.mutants == 0 && opts.only.is_none() {
        return Err(Failure::input("--mutants: must be at least 1".into()));
    }
    if opts.timeout.is_zero() {
        return Err(Failure::input("--timeout: must be at least 1 s".into()));
    }
    if opts.max_steps == 0 {
        return Err(Failure::input("--max-steps: must be at least 1".into()));
    }
    let exe = dem2d_exe().map_err(Failure::failed)?;
    std::fs::create_dir_all(&opts.out)
        .map_err(|e| Failure::failed(format!("{}: {e}", opts.out.display())))?;
    let report = fuzz::run(opts, &exe).map_err(Failure::failed)?;
    print_out(&report.markdown)?;
    say(&format!(
        "dem2d-lab fuzz: {}",
        report
            .counts
            .iter()
            .map(|(c, n)| format!("{c} {n}"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    if report.failures.is_empty() {
        Ok(())
    } else {
        Err(Failure::failed(format!(
            "{} mutants failed (see {})",
            report.failures.len(),
            opts.out.join("failures").display()
        )))
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Bench {
            shapes,
            sizes,
            steps,
            reps,
            threads: _,
            normal_force,
            cache,
            out,
            docs,
            peers: true,
        } => bench_peers(
            shapes,
            normal_force,
            sizes,
            steps.unwrap_or(10_000),
            *reps,
            cache,
            out.as_deref(),
            *docs,
        ),
        Command::Bench {
            shapes,
            sizes,
            steps,
            reps,
            threads,
            normal_force,
            cache,
            out,
            docs,
            peers: false,
        } => bench(
            shapes,
            sizes,
            steps.unwrap_or(500),
            *reps,
            threads,
            normal_force,
            cache,
            out.as_deref(),
            *docs,
        ),
        Command::Figures {
            out,
            cases,
            work,
            docs,
            check,
            quick,
            png,
        } => figures(
            out.clone(),
            cases.clone(),
            work.clone(),
            docs_mode(*docs, *check),
            (*quick, png.clone()),
        ),
        Command::CrossCheck {
            case,
            phi,
            static_scale,
            shear_rate,
            dt,
            strain,
            sample_strain,
            transient_strain,
            kn,
            friction,
            restitution,
            work,
            fire,
            docs,
        } => cross_check(
            crosscheck::CrossOptions {
                case: case.clone(),
                phi: *phi,
                static_scale: *static_scale,
                shear_rate: *shear_rate,
                dt: dt.clone(),
                strain: *strain,
                sample_strain: *sample_strain,
                transient_strain: *transient_strain,
                kn: *kn,
                friction: *friction,
                restitution: *restitution,
                work: work.clone(),
                dem2d: PathBuf::new(),
                lmp: PathBuf::new(),
                fire: *fire,
            },
            *docs,
        ),
        Command::FieldsForces { out, cases, work } => {
            fields_forces::fields_forces(&fields_forces::Options {
                cases: cases.clone(),
                out: out.clone(),
                work: work.clone(),
            })
            .map_err(Failure::failed)
            .and_then(|r| print_out(&r))
        }
        Command::Fuzz {
            mutants,
            seed,
            out,
            timeout,
            jobs,
            max_steps,
            only,
        } => fuzz(&fuzz::FuzzOptions {
            mutants: *mutants,
            seed: *seed,
            out: out.clone(),
            timeout: std::time::Duration::from_secs(*timeout),
            jobs: *jobs,
            root: PathBuf::from("."),
            only: *only,
            max_steps: *max_steps,
            progress: true,
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            say(&format!("dem2d-lab: {}", f.message));
            ExitCode::from(f.code)
        }
    }
}

//! `dem2d` command line: parse arguments, call the library, map errors to exit codes
//! (0 success, 1 failure while running, 2 bad input).

use clap::{Parser, Subcommand};
use dem2d::narrow_phase::contact;
use dem2d::output::contacts::contact_json;
use dem2d::runner::{RunOptions, run_case};
use dem2d::scene::fields::parse_lenient;
use dem2d::scene::{Case, parse_pairs};
use std::io::{Read, Write};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "dem2d",
    version,
    about = "2D discrete element method with circles, ellipses and rectangles"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Contact geometry of pairs of bodies: reads a JSON array of {"i": BODY, "j": BODY} from FILE
    /// (or standard input for `-`) and prints one JSON result per pair.
    Contact {
        /// Input file, or `-` for standard input.
        file: String,
    },
    /// Run a case file: writes trajectory.csv, increments.csv, case.json and summary.json.
    Run {
        /// The case file (JSON, "version": 1).
        case: PathBuf,
        /// Output directory (default: runs/<case name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Stop after this many steps (for quick checks; the summary says how far it got).
        #[arg(long)]
        max_steps: Option<u64>,
        /// No progress line on stderr.
        #[arg(long)]
        quiet: bool,
    },
    /// Draw a run (a directory written by `dem2d run`) as an SVG.
    Plot {
        /// The run directory.
        run_dir: PathBuf,
        /// Output file (default: RUN_DIR/<kind>.svg).
        #[arg(long)]
        out: Option<PathBuf>,
        /// What to draw: the scene (outlines along the paths), the time series (height and angle
        /// against time) or P's quiescence measures against the step.
        #[arg(long, value_enum, default_value = "scene")]
        kind: PlotKind,
    },
    /// Regenerate every figure and table of the README into figures/ (runs the paper's cases,
    /// the time-step sweeps and the contact-kernel report; about 5 s).
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
        /// README whose marked tables are refreshed ("" to leave it alone).
        #[arg(long, default_value = "README.md")]
        readme: String,
        /// Fewer sweep points and repetitions (a quick look, not the README's numbers).
        #[arg(long)]
        quick: bool,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum PlotKind {
    Scene,
    Series,
    Quiescence,
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
}

fn read_input(file: &str) -> Result<String, Failure> {
    let mut text = String::new();
    if file == "-" {
        std::io::stdin()
            .read_to_string(&mut text)
            .map_err(|e| Failure::input(format!("<stdin>: cannot read: {e}")))?;
    } else {
        text = std::fs::read_to_string(file)
            .map_err(|e| Failure::input(format!("{file}: cannot read: {e}")))?;
    }
    Ok(text)
}

fn run_contact(file: &str) -> Result<(), Failure> {
    let name = if file == "-" { "<stdin>" } else { file };
    let text = read_input(file)?;
    let value =
        parse_lenient(&text).map_err(|e| Failure::input(format!("{name}: malformed JSON: {e}")))?;
    let pairs = parse_pairs(&value).map_err(|e| Failure::input(format!("{name}: {e}")))?;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    for (i, j) in &pairs {
        let c = contact(i, j).expect("parse_pairs rejects wall–wall pairs");
        writeln!(out, "{}", contact_json(&c)).map_err(|e| Failure {
            code: 1,
            message: format!("cannot write output: {e}"),
        })?;
    }
    out.flush().map_err(|e| Failure {
        code: 1,
        message: format!("cannot write output: {e}"),
    })
}

fn run(
    case_path: &PathBuf,
    out: Option<PathBuf>,
    max_steps: Option<u64>,
    quiet: bool,
) -> Result<(), Failure> {
    let name = case_path.display().to_string();
    let text = std::fs::read_to_string(case_path)
        .map_err(|e| Failure::input(format!("{name}: cannot read: {e}")))?;
    let case = Case::from_json(&text).map_err(|e| Failure::input(format!("{name}: {e}")))?;
    let out_dir = out.unwrap_or_else(|| PathBuf::from("runs").join(&case.name));
    let opts = RunOptions {
        out_dir: out_dir.clone(),
        progress: !quiet,
        max_steps,
    };
    let outcome = run_case(&case, &text, &opts).map_err(|e| Failure {
        code: 1,
        message: format!("{}: cannot write output: {e}", out_dir.display()),
    })?;
    let s = &outcome.summary;
    for w in &s.warnings {
        eprintln!("dem2d: warning: {w}");
    }
    if let Some(b) = outcome.blowup {
        return Err(Failure {
            code: 1,
            message: format!("{name}: {b}; output so far kept in {}", out_dir.display()),
        });
    }
    let rest = match s.quiescent_step {
        Some(q) => format!(
            "at rest at step {q} (quiescence {:e})",
            case.quiescence.unwrap_or(0.0)
        ),
        None if case.quiescence.is_some() => "not at rest".to_string(),
        None => String::new(),
    };
    println!(
        "{}: {} steps, t = {:.6} s, {}; wall time {:.2} s; dt = {:e}, dt_critical = {:.3e} (a priori), {} (contact network); output in {}",
        s.name,
        s.steps,
        s.time,
        rest,
        s.wall_seconds,
        s.dt,
        s.dt_critical,
        s.dt_critical_observed
            .map_or("none".to_string(), |v| format!("{v:.3e}")),
        out_dir.display()
    );
    Ok(())
}

fn plot(run_dir: &std::path::Path, out: Option<PathBuf>, kind: PlotKind) -> Result<(), Failure> {
    use dem2d::output::panels;
    use dem2d::output::plot::{self, SceneOptions, ScenePanel};
    let run = dem2d::output::run_data::RunData::load(run_dir)
        .map_err(|e| Failure::input(e.to_string()))?;
    let name = match kind {
        PlotKind::Scene => "scene",
        PlotKind::Series => "series",
        PlotKind::Quiescence => "quiescence",
    };
    let out = out.unwrap_or_else(|| run_dir.join(format!("{name}.svg")));
    let title = format!(
        "{} ({} steps, t = {:.4} s)",
        run.case.name,
        run.summary["steps"],
        run.summary["time"].as_f64().unwrap_or(f64::NAN)
    );
    let result = match kind {
        PlotKind::Scene => plot::scene(
            &out,
            &[ScenePanel {
                title,
                runs: vec![(&run, String::new())],
            }],
            &SceneOptions::default(),
        ),
        PlotKind::Series => plot::line_panels(
            &out,
            (1000, 700),
            (2, 1),
            &panels::time_series(&[(&run, "")], &title),
        ),
        PlotKind::Quiescence => plot::line_panels(
            &out,
            (1000, 500),
            (1, 1),
            &[panels::quiescence(&run, &title, None)],
        ),
    };
    result.map_err(|e| Failure {
        code: 1,
        message: format!("{}: {e}", out.display()),
    })?;
    println!("{}", out.display());
    Ok(())
}

fn figures(
    out: PathBuf,
    cases: PathBuf,
    work: PathBuf,
    readme: String,
    quick: bool,
) -> Result<(), Failure> {
    let opts = dem2d::report::FigureOptions {
        cases,
        out,
        work,
        readme: (!readme.is_empty()).then(|| PathBuf::from(readme)),
        quick,
    };
    let written = dem2d::report::figures(&opts).map_err(|e| Failure {
        code: 1,
        message: e.to_string(),
    })?;
    for f in written {
        println!("{}", f.display());
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Contact { file } => run_contact(file),
        Command::Run {
            case,
            out,
            max_steps,
            quiet,
        } => run(case, out.clone(), *max_steps, *quiet),
        Command::Plot { run_dir, out, kind } => plot(run_dir, out.clone(), *kind),
        Command::Figures {
            out,
            cases,
            work,
            readme,
            quick,
        } => figures(
            out.clone(),
            cases.clone(),
            work.clone(),
            readme.clone(),
            *quick,
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("dem2d: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}

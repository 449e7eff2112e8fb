//! `dem2d` command line: parse arguments, call the library, map errors to exit codes
//! (0 success, 1 failure while running, 2 bad input).

use clap::{Parser, Subcommand};
use dem2d::narrow_phase::contact;
use dem2d::output::contacts::contact_json;
use dem2d::scene::parse_pairs;
use std::io::{Read, Write};
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
    let value: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| Failure::input(format!("{name}: malformed JSON: {e}")))?;
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Contact { file } => run_contact(file),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("dem2d: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}

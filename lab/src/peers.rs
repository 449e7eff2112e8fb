//! `dem2d bench --peers`: the throughput a user gets from `dem2d run`, against LIGGGHTS and LAMMPS
//! on the same settled pile, measured in the same session, interleaved.
//!
//! # What is compared
//! - `dem2d run` (this executable, as a child process, `--threads 1`) on the settled 10⁴-disk
//!   pile and on the settled 10⁴-ellipse pile of `dem2d bench` (the same cache of settled
//!   piles), the quiescence stop taken out so that every run does all its steps; the ellipse
//!   pile once under each normal-force law asked for (`--normal-force`: the area law, dem2d's
//!   default, and P's spring on the depth — the linear law the disks' engines apply), the disk
//!   pile once (a disk's area potential is the spring on its depth: the same run);
//! - LIGGGHTS (`liggghts`) and LAMMPS (`lmp`), when installed, on the disk pile: the decks of
//!   `lab/peers/` (compiled into this executable), the pile written as a LAMMPS data file
//!   into a temporary directory. The decks state the equivalence: 2D, the same particles
//!   (positions, radii, velocities, spins), mass ρπr² (unit thickness), the same linear law
//!   term by term (spring k_n δ, constant dashpot η v_n, tangential spring k_t with dashpot η
//!   and Coulomb friction μ; the walls the same), the same Δt, steps, gravity and neighbour skin
//!   (0.1 of the largest radius, binned).
//!
//! Each repetition runs every program once, one after the other (programs interleaved, so that
//! a change of the machine's load hits all of them alike); the medians over repetitions are
//! reported. Two rates per program: particle-steps per **CPU-second** of the whole process
//! (user + system time of the child, from `getrusage`: robust on a shared machine, includes
//! reading the input and writing the outputs) and per **wall-second of the time loop** (as the
//! program itself reports it: LAMMPS' and LIGGGHTS' "Loop time", dem2d's `wall_seconds` in
//! `summary.json`, which is what `dem2d run` prints).

use crate::bench::{BenchError, settled_pile_text};
use dem2d::contact_law::NormalForce;
use dem2d::scene::Case;
use dem2d::scene::generate::{DENSITY, G, KN_OVER_RHO_G, PileShape, PileSpec};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

/// The decks, as checked in (`lab/peers/`).
pub const LAMMPS_DECK: &str = include_str!("../peers/lammps.in");
pub const LIGGGHTS_DECK: &str = include_str!("../peers/liggghts.in");

/// What to measure.
#[derive(Clone, Debug)]
pub struct PeerOptions {
    /// The dem2d piles to run (the peers run the disk pile).
    pub shapes: Vec<PileShape>,
    /// The normal-force laws the ellipse pile is run under (one row each).
    pub laws: Vec<NormalForce>,
    /// Bodies per pile.
    pub n: usize,
    /// Steps per run.
    pub steps: u64,
    /// Repetitions (medians reported).
    pub reps: usize,
    /// Cache of settled piles (as `dem2d bench`).
    pub cache: Option<PathBuf>,
    pub progress: bool,
}

/// A program of the comparison.
#[derive(Clone, Debug, PartialEq)]
pub enum Program {
    /// `dem2d run` on a pile under a normal-force law.
    Dem2d(PileShape, NormalForce),
    Liggghts(PathBuf),
    Lammps(PathBuf),
}

impl Program {
    pub fn name(&self) -> &'static str {
        match self {
            Program::Dem2d(..) => "dem2d run",
            Program::Liggghts(_) => "LIGGGHTS",
            Program::Lammps(_) => "LAMMPS",
        }
    }

    pub fn pile(&self) -> &'static str {
        match self {
            Program::Dem2d(PileShape::Ellipses, NormalForce::Area) => "ellipses, area law",
            Program::Dem2d(PileShape::Ellipses, NormalForce::Depth) => "ellipses, depth law",
            _ => "disks",
        }
    }
}

/// One run of one program.
#[derive(Clone, Copy, Debug, Default)]
pub struct Sample {
    /// User + system CPU time of the process (s).
    pub cpu: f64,
    /// Wall time of the process (s).
    pub wall: f64,
    /// Wall time of the time loop, as the program reports it (s).
    pub loop_wall: f64,
    /// Contacts per body at the end (body–body and body–wall; from the program's own count).
    pub contacts_per_body: f64,
}

/// A program's medians.
#[derive(Clone, Debug)]
pub struct PeerRow {
    pub program: Program,
    pub n: usize,
    pub steps: u64,
    pub samples: Vec<Sample>,
    pub cpu: f64,
    pub loop_wall: f64,
    pub contacts_per_body: f64,
}

impl PeerRow {
    /// Particle-steps per CPU-second of the whole process.
    pub fn per_cpu_second(&self) -> f64 {
        self.n as f64 * self.steps as f64 / self.cpu
    }

    /// Particle-steps per wall-second of the time loop.
    pub fn per_loop_second(&self) -> f64 {
        self.n as f64 * self.steps as f64 / self.loop_wall
    }
}

/// What was found of the peers, for the report.
#[derive(Clone, Debug, Default)]
pub struct PeerReport {
    pub rows: Vec<PeerRow>,
    /// Peers not installed (said so in the table's notes).
    pub missing: Vec<&'static str>,
}

fn err(e: impl std::fmt::Display) -> BenchError {
    BenchError(e.to_string())
}

/// The first of `names` found as an executable file on `PATH`.
pub fn find_executable(names: &[&str]) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    for dir in std::env::split_paths(&path) {
        for name in names {
            let p = dir.join(name);
            if let Ok(meta) = std::fs::metadata(&p) {
                use std::os::unix::fs::PermissionsExt;
                if meta.is_file() && meta.permissions().mode() & 0o111 != 0 {
                    return Some(p);
                }
            }
        }
    }
    None
}

/// User + system CPU seconds of the children waited for so far.
pub fn children_cpu_seconds() -> f64 {
    // SAFETY: getrusage writes into the zeroed struct we own; RUSAGE_CHILDREN is a valid who.
    let ru = unsafe {
        let mut ru: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_CHILDREN, &mut ru);
        ru
    };
    let s = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    s(ru.ru_utime) + s(ru.ru_stime)
}

/// A settled pile's case text, for `dem2d run`: the quiescence stop taken out (the bench runs
/// every step), a duration that holds the steps (`--max-steps` stops the run).
fn run_case_text(text: &str, steps: u64, law: NormalForce) -> Result<String, BenchError> {
    let mut v: serde_json::Value = serde_json::from_str(text).map_err(err)?;
    let o = v
        .as_object_mut()
        .ok_or_else(|| BenchError("settled pile: not an object".into()))?;
    // The row is labelled with this law: a pile without its contact object is not run under
    // a law it does not name.
    o.get_mut("contact")
        .and_then(|c| c.as_object_mut())
        .ok_or_else(|| BenchError("settled pile: no `contact` object".into()))?
        .insert("normal_force".into(), law.as_str().into());
    o.remove("quiescence");
    o.remove("quiescence_window");
    let dt = o.get("dt").and_then(|d| d.as_f64()).unwrap_or(1e-5);
    o.insert(
        "duration".into(),
        serde_json::json!(dt * (steps + 10) as f64),
    );
    serde_json::to_string(&v).map_err(err)
}

/// The disk pile as a LAMMPS data file (`atom_style sphere`: id, type, diameter, density, x, y,
/// z; velocities with the spin about z), the box from 0 to `width` across and from the floor to
/// above the pile (the decks let the top grow).
pub fn lammps_data(case: &Case, width: f64) -> Result<String, BenchError> {
    let mut top: f64 = 0.0;
    let mut atoms = String::new();
    let mut vel = String::new();
    for (k, b) in case.bodies.iter().enumerate() {
        let r = match b.shape {
            dem2d::geometry::Shape::Circle { r } => r,
            s => return Err(BenchError(format!("the peers run disks only, got {s:?}"))),
        };
        top = top.max(b.position.y + r);
        writeln!(
            atoms,
            "{} 1 {:e} {:e} {:e} {:e} 0",
            k + 1,
            2.0 * r,
            b.density,
            b.position.x,
            b.position.y
        )
        .expect("string");
        writeln!(
            vel,
            "{} {:e} {:e} 0 0 0 {:e}",
            k + 1,
            b.velocity.x,
            b.velocity.y,
            b.omega
        )
        .expect("string");
    }
    Ok(format!(
        "{} settled disks of dem2d (written by dem2d bench --peers)\n\n{} atoms\n1 atom types\n\n\
         0 {width:e} xlo xhi\n0 {:e} ylo yhi\n-0.5 0.5 zlo zhi\n\nAtoms # sphere\n\n{atoms}\nVelocities\n\n{vel}",
        case.bodies.len(),
        case.bodies.len(),
        top + 20.0
    ))
}

/// The `-var` arguments of the decks: the pile's law, step and box.
fn deck_vars(data: &Path, steps: u64, width: f64, skin: f64) -> Vec<String> {
    let spec = PileSpec::new(PileShape::Disks, 10_000, 1);
    let kn = KN_OVER_RHO_G * DENSITY * G;
    let eta = (spec.eta() * 1e6).round() / 1e6; // as the case file holds it
    let vars = [
        ("data", data.display().to_string()),
        ("steps", steps.to_string()),
        ("dt", format!("{:e}", dem2d::scene::generate::DT)),
        ("kn", format!("{kn:e}")),
        ("kt", format!("{kn:e}")),
        ("eta", format!("{eta:e}")),
        ("mu", format!("{}", spec.friction)),
        ("g", format!("{G:e}")),
        ("width", format!("{width:e}")),
        ("skin", format!("{skin:e}")),
    ];
    vars.into_iter()
        .flat_map(|(k, v)| ["-var".to_string(), k.to_string(), v])
        .collect()
}

/// "Loop time of X on ..." and the last thermo line's contact count (the last column but one:
/// `step atoms ke c_contacts cpu`; every contact counted by both its bodies) from a log.
fn parse_log(log: &str) -> Option<(f64, f64)> {
    let loop_time = log.lines().find_map(|l| {
        l.strip_prefix("Loop time of ")
            .and_then(|r| r.split_whitespace().next())
            .and_then(|t| t.parse::<f64>().ok())
    })?;
    let lines: Vec<&str> = log.lines().collect();
    let at = lines.iter().position(|l| l.starts_with("Loop time of "))?;
    let contacts = lines[..at].iter().rev().find_map(|l| {
        let f: Vec<&str> = l.split_whitespace().collect();
        (f.len() == 5 && f[0].parse::<u64>().is_ok())
            .then(|| f[3].parse::<f64>().ok())
            .flatten()
    })?;
    Some((loop_time, contacts))
}

/// Runs one program once.
fn run_once(
    program: &Program,
    dir: &Path,
    opts: &PeerOptions,
    width: f64,
    skin: f64,
) -> Result<Sample, BenchError> {
    let cpu0 = children_cpu_seconds();
    let start = Instant::now();
    let (status, log_or_summary) = match program {
        Program::Dem2d(shape, law) => {
            let name = format!("{}_{}", shape_name(*shape), law.as_str());
            let case = dir.join(format!("{name}.json"));
            let out = dir.join(format!("run_{name}"));
            let exe = crate::dem2d_exe().map_err(err)?;
            let status = Command::new(exe)
                .arg("run")
                .arg(&case)
                .args(["--threads", "1", "--quiet", "--overwrite", "--max-steps"])
                .arg(opts.steps.to_string())
                .arg("--out")
                .arg(&out)
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status()
                .map_err(err)?;
            (status, out.join("summary.json"))
        }
        Program::Liggghts(exe) | Program::Lammps(exe) => {
            let (deck, name) = match program {
                Program::Liggghts(_) => ("liggghts.in", "liggghts.log"),
                _ => ("lammps.in", "lammps.log"),
            };
            let log = dir.join(name);
            let status = Command::new(exe)
                .current_dir(dir)
                .env("OMP_NUM_THREADS", "1")
                .args(["-in", deck, "-log"])
                .arg(&log)
                .args(["-screen", "none"])
                .args(deck_vars(&dir.join("pile.data"), opts.steps, width, skin))
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status()
                .map_err(err)?;
            (status, log)
        }
    };
    let wall = start.elapsed().as_secs_f64();
    let cpu = children_cpu_seconds() - cpu0;
    let text = std::fs::read_to_string(&log_or_summary)
        .map_err(|e| BenchError(format!("{}: {e}", log_or_summary.display())))?;
    let (loop_wall, contacts_per_body) = match program {
        Program::Dem2d(..) => {
            if !status.success() {
                return Err(BenchError(format!(
                    "dem2d run failed ({status}); see {}",
                    log_or_summary.display()
                )));
            }
            let v: serde_json::Value = serde_json::from_str(&text).map_err(err)?;
            let get = |k: &str| v.get(k).and_then(|x| x.as_f64()).unwrap_or(f64::NAN);
            (
                get("wall_seconds"),
                get("contacts_per_step") / opts.n as f64,
            )
        }
        _ => {
            let Some((loop_time, touching)) = parse_log(&text).filter(|_| status.success()) else {
                return Err(BenchError(format!(
                    "{} failed ({status}); see {}",
                    program.name(),
                    log_or_summary.display()
                )));
            };
            // contact/atom counts body–body contacts on both bodies, and no wall contacts.
            (loop_time, 0.5 * touching / opts.n as f64)
        }
    };
    Ok(Sample {
        cpu,
        wall,
        loop_wall,
        contacts_per_body,
    })
}

fn shape_name(s: PileShape) -> &'static str {
    match s {
        PileShape::Disks => "disks",
        PileShape::Ellipses => "ellipses",
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Runs the comparison.
pub fn run(opts: &PeerOptions) -> Result<PeerReport, BenchError> {
    let dir = std::env::temp_dir().join(format!("dem2d-peers-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| BenchError(format!("{}: {e}", dir.display())))?;
    let result = run_in(opts, &dir);
    let _ = std::fs::remove_dir_all(&dir);
    result
}

fn run_in(opts: &PeerOptions, dir: &Path) -> Result<PeerReport, BenchError> {
    let mut report = PeerReport::default();
    let mut programs: Vec<Program> = Vec::new();
    // The disk pile is needed by the peers whatever dem2d piles are asked for.
    let disk_text = settled_pile_text(
        PileShape::Disks,
        opts.n,
        opts.cache.as_deref(),
        opts.progress,
    )?;
    let disks = Case::from_json(&disk_text).map_err(err)?;
    let width = PileSpec::new(PileShape::Disks, opts.n, 1).width();
    let max_r = disks
        .bodies
        .iter()
        .map(|b| b.shape.bounding_radius())
        .fold(0.0f64, f64::max);
    let skin = dem2d::dynamics::neighbour_list::SKIN_FRACTION * max_r;
    for &shape in &opts.shapes {
        let (text, laws) = match shape {
            PileShape::Disks => (disk_text.clone(), vec![NormalForce::Area]),
            PileShape::Ellipses => (
                settled_pile_text(shape, opts.n, opts.cache.as_deref(), opts.progress)?,
                opts.laws.clone(),
            ),
        };
        for law in laws {
            let path = dir.join(format!("{}_{}.json", shape_name(shape), law.as_str()));
            std::fs::write(&path, run_case_text(&text, opts.steps, law)?)
                .map_err(|e| BenchError(format!("{}: {e}", path.display())))?;
            programs.push(Program::Dem2d(shape, law));
        }
    }
    match find_executable(&["liggghts", "lmp_liggghts"]) {
        Some(p) => programs.push(Program::Liggghts(p)),
        None => report.missing.push("LIGGGHTS (`liggghts`)"),
    }
    match find_executable(&["lmp", "lmp_serial", "lmp_mpi"]) {
        Some(p) => programs.push(Program::Lammps(p)),
        None => report.missing.push("LAMMPS (`lmp`)"),
    }
    if programs
        .iter()
        .any(|p| matches!(p, Program::Liggghts(_) | Program::Lammps(_)))
    {
        let data = dir.join("pile.data");
        std::fs::write(&data, lammps_data(&disks, width)?)
            .map_err(|e| BenchError(format!("{}: {e}", data.display())))?;
        for (name, deck) in [("lammps.in", LAMMPS_DECK), ("liggghts.in", LIGGGHTS_DECK)] {
            std::fs::write(dir.join(name), deck).map_err(err)?;
        }
    }
    for name in &report.missing {
        if opts.progress {
            eprintln!("peers: {name} not installed: skipped");
        }
    }
    let mut samples: Vec<Vec<Sample>> = vec![Vec::new(); programs.len()];
    for rep in 0..opts.reps.max(1) {
        for (k, p) in programs.iter().enumerate() {
            let s = run_once(p, dir, opts, width, skin)?;
            if opts.progress {
                eprintln!(
                    "peers: repetition {}/{}: {} ({}): {:.2} M particle-steps per CPU-second, {:.2} M per loop wall-second ({:.1} s CPU, {:.1} s wall)",
                    rep + 1,
                    opts.reps.max(1),
                    p.name(),
                    p.pile(),
                    opts.n as f64 * opts.steps as f64 / s.cpu / 1e6,
                    opts.n as f64 * opts.steps as f64 / s.loop_wall / 1e6,
                    s.cpu,
                    s.wall
                );
            }
            samples[k].push(s);
        }
    }
    for (program, s) in programs.into_iter().zip(samples) {
        report.rows.push(PeerRow {
            program,
            n: opts.n,
            steps: opts.steps,
            cpu: median(s.iter().map(|x| x.cpu).collect()),
            loop_wall: median(s.iter().map(|x| x.loop_wall).collect()),
            contacts_per_body: median(s.iter().map(|x| x.contacts_per_body).collect()),
            samples: s,
        });
    }
    Ok(report)
}

/// The report as Markdown: one row per program, then the ratios against LIGGGHTS' disks.
pub fn markdown(report: &PeerReport, load: Option<&str>) -> String {
    let mut t = String::from(
        "| program | pile | bodies × steps | contacts per body | CPU s (median) | particle-steps per CPU-second (M) | loop wall s (median) | particle-steps per loop wall-second (M) | vs LIGGGHTS disks (CPU) |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let liggghts = report
        .rows
        .iter()
        .find(|r| matches!(r.program, Program::Liggghts(_)))
        .map(PeerRow::per_cpu_second);
    for r in &report.rows {
        let ratio = liggghts.map_or("–".to_string(), |l| {
            format!("{:.2}×", r.per_cpu_second() / l)
        });
        writeln!(
            t,
            "| {} | {} | {} × {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {ratio} |",
            r.program.name(),
            r.program.pile(),
            r.n,
            r.steps,
            r.contacts_per_body,
            r.cpu,
            r.per_cpu_second() / 1e6,
            r.loop_wall,
            r.per_loop_second() / 1e6,
        )
        .expect("string");
    }
    let reps = report.rows.first().map_or(0, |r| r.samples.len());
    write!(
        t,
        "\nOne core each (`dem2d run --threads 1`, one MPI rank, `OMP_NUM_THREADS=1`); medians of {reps} interleaved repetitions."
    )
    .expect("string");
    if let Some(l) = load {
        write!(t, " Load average at the start: {l}.").expect("string");
    }
    if !report.missing.is_empty() {
        write!(t, " Not installed, skipped: {}.", report.missing.join(", ")).expect("string");
    }
    t.push('\n');
    t
}

/// The machine's load averages (`/proc/loadavg`), if readable.
pub fn load_average() -> Option<String> {
    let s = std::fs::read_to_string("/proc/loadavg").ok()?;
    let f: Vec<&str> = s.split_whitespace().take(3).collect();
    (f.len() == 3).then(|| f.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lammps_log_gives_its_loop_time_and_contacts() {
        let log = "Step Atoms KinEng c_contacts CPU \n       0    10000    15421.902        35146            0 \n    1000    10000    51123.442        34962     3.701385 \nLoop time of 3.70141 on 1 procs for 1000 steps with 10000 atoms\n";
        assert_eq!(parse_log(log), Some((3.70141, 34962.0)));
    }

    #[test]
    fn a_missing_loop_time_is_no_result() {
        assert_eq!(parse_log("ERROR: something\n"), None);
    }

    #[test]
    fn the_run_case_has_no_quiescence_and_room_for_the_steps() {
        let t = run_case_text(
            r#"{"version": 1, "dt": 1e-5, "duration": 4.0, "quiescence": 1e-7, "quiescence_window": 1000, "contact": {"model": "linear", "normal_force": "area"}}"#,
            1000,
            NormalForce::Depth,
        )
        .unwrap();
        let v: serde_json::Value = serde_json::from_str(&t).unwrap();
        assert!(v.get("quiescence").is_none() && v.get("quiescence_window").is_none());
        assert!(v["duration"].as_f64().unwrap() >= 1000.0 * 1e-5);
        assert_eq!(v["contact"]["normal_force"], "depth");
    }
}

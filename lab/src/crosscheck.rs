//! `dem2d-lab cross-check`: the same physics in another code. A constant-volume Lees–Edwards
//! shear of frictional bidisperse disks run by `dem2d run` and by LAMMPS (`lmp`, `pair_style
//! granular`) from the same initial state, and the steady state's μ = −σ_yx/σ_yy, σ_yy, Z and I
//! side by side with standard errors (docs/src/validation/lammps.md).
//!
//! The initial states are made from a packing of disks in a periodic cell (default
//! `cases/jammed_disks_256.json`): its positions and the cell scaled about the origin so that
//! the packing fraction is `--phi` (the shear run, every disk moving with the affine flow
//! `v_x = γ̇ (y − L_y/2)`) or the static state's (`--static-scale`, the disks at rest and
//! overlapping). Each state is written as a dem2d case and as a LAMMPS data file (`atom_style
//! sphere`, a triclinic box whose tilt `fix deform … xy erate γ̇ remap v` advances).
//!
//! The contact law is the same term by term in the two codes (docs/src/physics/contact-laws.md;
//! LAMMPS's `pair_granular.cpp`, 29 Sep 2021):
//! - normal: `F_n = max(0, k_n δ − η_n v_n)` (dem2d's linear Voigt law, T6, on the depth;
//!   LAMMPS `hooke k_n η_n … damping velocity limit_damping`: constant η_n, clamped at zero);
//! - tangential: `δ_t += v_t Δt`, `F_t = −k_t δ_t` capped at `μ F_n` with the spring reset to
//!   hold `μ F_n` (T15–T20; LAMMPS `tangential linear_history k_t 0 μ`). The shear dashpot is
//!   zero in both: LAMMPS resets a slipping spring to `−(μF_n t̂ + η_t v_t)/k_t`, dem2d to
//!   `−μF_n t̂/k_t`, which agree only when η_t = 0;
//! - masses ρπr², inertia ½mr² (LAMMPS `set … density/disc`, `fix nve/sphere disc`);
//! - the dashpot η_n is constant: dem2d's restitution map gives each pair its own
//!   `η_n = 2α√(m* k_n)` (T12), which LAMMPS's `damping` options cannot express (`velocity`:
//!   constant; `mass_velocity`: ∝ m*; `tsuji`: 2α√(m* k_n) only with its own α(e) and a
//!   non-linear form). Both codes get the constant η_n of the restitution `--restitution` for
//!   the small–large pair; the restitutions it gives the other pairs are printed.
//!
//! What is left different: this LAMMPS's `fix deform` moves the box at the end of a step, so
//! the forces of step n + 1 see the images' shift of step n (`γ̇ L_y Δt` behind; dem2d's shift
//! moves with the positions): the shear runs at each `--dt`. The lever arms differ by O(δ).

use serde_json::{Value, json};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What `cross-check` runs.
pub struct CrossOptions {
    /// The packing the initial states are made from.
    pub case: PathBuf,
    /// The shear run's packing fraction.
    pub phi: f64,
    /// The static state's scale of the packing (positions and cell).
    pub static_scale: f64,
    pub shear_rate: f64,
    /// Time steps: the static states run at the first, the shear at each.
    pub dt: Vec<f64>,
    /// Strain of the shear run.
    pub strain: f64,
    /// Strain between samples.
    pub sample_strain: f64,
    /// Strain before the steady state (left out of the means).
    pub transient_strain: f64,
    pub kn: f64,
    pub friction: f64,
    pub restitution: f64,
    /// Where the runs go.
    pub work: PathBuf,
    pub dem2d: PathBuf,
    pub lmp: PathBuf,
    /// Also LAMMPS's FIRE against `dem2d relax` on `case` (lab/peers/jamming_fire.py), with
    /// this many iterations.
    pub fire: Option<u64>,
}

/// A disk: radius, position, velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Disk {
    r: f64,
    x: f64,
    y: f64,
    vx: f64,
}

/// An initial state: a square-or-not cell `[0, lx) × [0, ly)` and its disks.
struct State {
    name: &'static str,
    lx: f64,
    ly: f64,
    disks: Vec<Disk>,
    shear_rate: f64,
}

fn input(path: &Path, field: &str, what: &str) -> String {
    format!("{}: {field}: {what}", path.display())
}

/// The packing's cell size and disks (circles, density 1, in a cell periodic in x and y).
fn read_packing(path: &Path) -> Result<(f64, f64, Vec<Disk>), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let cell = &v["cell"];
    if cell["periodic"] != "xy" {
        return Err(input(path, "cell.periodic", "must be \"xy\""));
    }
    let size = |k: usize| {
        cell["size"][k]
            .as_f64()
            .filter(|s| *s > 0.0)
            .ok_or_else(|| input(path, "cell.size", "two positive numbers"))
    };
    let (lx, ly) = (size(0)?, size(1)?);
    let bodies = v["bodies"]
        .as_array()
        .ok_or_else(|| input(path, "bodies", "an array"))?;
    let mut disks = Vec::with_capacity(bodies.len());
    for (k, b) in bodies.iter().enumerate() {
        let field = |f: &str| format!("bodies[{k}].{f}");
        if b["shape"]["type"] != "circle" {
            return Err(input(path, &field("shape.type"), "disks only (\"circle\")"));
        }
        if b.get("density").is_some_and(|d| d.as_f64() != Some(1.0)) {
            return Err(input(path, &field("density"), "must be 1 (or absent)"));
        }
        let num = |x: &Value, f: &str| x.as_f64().ok_or_else(|| input(path, &field(f), "a number"));
        let r = num(&b["shape"]["r"], "shape.r")?;
        let x = num(&b["position"][0], "position")?;
        let y = num(&b["position"][1], "position")?;
        disks.push(Disk {
            r,
            x: x.rem_euclid(lx),
            y: y.rem_euclid(ly),
            vx: 0.0,
        });
    }
    if disks.len() < 2 {
        return Err(input(path, "bodies", "at least two disks"));
    }
    Ok((lx, ly, disks))
}

/// Whether `path` is a packing the cross-check can start from (the error names the field).
pub fn check_packing(path: &Path) -> Result<(), String> {
    read_packing(path).map(|_| ())
}

/// The packing scaled about the origin by `s` (positions and cell), at rest or moving with the
/// affine shear flow `γ̇ (y − L_y/2)`.
fn scaled(name: &'static str, packing: &(f64, f64, Vec<Disk>), s: f64, shear_rate: f64) -> State {
    let (lx, ly) = (packing.0 * s, packing.1 * s);
    let disks = packing
        .2
        .iter()
        .map(|d| {
            let y = d.y * s;
            Disk {
                r: d.r,
                x: d.x * s,
                y,
                vx: shear_rate * (y - 0.5 * ly),
            }
        })
        .collect();
    State {
        name,
        lx,
        ly,
        disks,
        shear_rate,
    }
}

fn disk_area(disks: &[Disk]) -> f64 {
    disks.iter().map(|d| std::f64::consts::PI * d.r * d.r).sum()
}

/// α of T12: `η_n = 2α√(m* k_n)` gives the restitution e to a linear spring–dashpot.
fn alpha(e: f64) -> f64 {
    -e.ln() / (e.ln().powi(2) + std::f64::consts::PI.powi(2)).sqrt()
}

/// The restitution of a pair of effective mass `m` under `k_n` and a constant dashpot `eta`
/// (the unclamped linear oscillator, T12 inverted: ζ = η/(2√(m k)), e = exp(−πζ/√(1 − ζ²))).
fn restitution_of(eta: f64, m: f64, kn: f64) -> f64 {
    let zeta = eta / (2.0 * (m * kn).sqrt());
    (-std::f64::consts::PI * zeta / (1.0 - zeta * zeta).sqrt()).exp()
}

fn mass(r: f64) -> f64 {
    std::f64::consts::PI * r * r
}

fn case_json(s: &State, o: &CrossOptions, run: &Run) -> Value {
    let bodies: Vec<Value> = s
        .disks
        .iter()
        .map(|d| {
            json!({"shape": {"type": "circle", "r": d.r}, "position": [d.x, d.y],
                   "velocity": [d.vx, 0.0], "density": 1.0})
        })
        .collect();
    json!({
        "version": 1,
        "name": s.name,
        "description": "dem2d-lab cross-check: the state LAMMPS runs too (lab/src/crosscheck.rs)",
        "units": "cm",
        "gravity": [0.0, 0.0],
        "dt": run.dt,
        "duration": run.steps as f64 * run.dt,
        "output_every": run.every,
        "output": {"analysis": true},
        "cell": {"size": [s.lx, s.ly], "periodic": "xy", "shear_rate": s.shear_rate},
        "contact": {"model": "linear", "normal_force": "depth", "kn": o.kn, "ks": o.kn,
                    "eta_n": run.eta_n, "eta_s": 0.0, "friction": o.friction},
        "bodies": bodies,
    })
}

/// The state as a LAMMPS data file: `atom_style sphere` (id type diameter density x y z), the
/// velocities, a triclinic box with zero tilt.
fn lammps_data(s: &State) -> String {
    let mut t = format!(
        "dem2d-lab cross-check {}\n\n{} atoms\n1 atom types\n\n0 {:?} xlo xhi\n0 {:?} ylo yhi\n-0.5 0.5 zlo zhi\n0 0 0 xy xz yz\n\nAtoms # sphere\n\n",
        s.name,
        s.disks.len(),
        s.lx,
        s.ly
    );
    for (k, d) in s.disks.iter().enumerate() {
        let _ = writeln!(t, "{} 1 {:?} 1 {:?} {:?} 0", k + 1, 2.0 * d.r, d.x, d.y);
    }
    t.push_str("\nVelocities\n\n");
    for (k, d) in s.disks.iter().enumerate() {
        let _ = writeln!(t, "{} {:?} 0 0 0 0 0", k + 1, d.vx);
    }
    t
}

/// The LAMMPS deck: dem2d's law (see the module's comment), the shear by `fix deform`, and per
/// sample: the virial stress (per area in 2D: LAMMPS divides by x·y there), the kinetic part
/// about dem2d's mean flow γ̇ (y − L_y/2) (`Σ m v′v′`, divided by the area here), and the
/// contacts (`contact/atom`, summed: twice the pairs closer than r_i + r_j).
fn lammps_deck(s: &State, o: &CrossOptions, run: &Run) -> String {
    format!(
        "units cgs
dimension 2
boundary p p p
atom_style sphere
atom_modify map array
comm_modify vel yes
newton off
read_data state.data
set group all density/disc 1.0
write_data roundtrip.data
pair_style granular
pair_coeff * * hooke {kn:?} {eta_n:?} tangential linear_history {kn:?} 0.0 {mu:?} damping velocity limit_damping
neighbor {skin:?} bin
neigh_modify delay 0 every 1 check yes
timestep {dt:?}
fix shear all deform 1 xy erate {rate:?} remap v flip yes
fix move all nve/sphere disc
fix flat all enforce2d
compute pv all pressure NULL virial
compute touching all contact/atom
compute zsum all reduce sum c_touching
variable vxp atom vx-{rate:?}*(y-{half:?})
variable kyy atom mass*vy*vy
variable kxy atom mass*v_vxp*vy
compute ksum all reduce sum v_kyy v_kxy
thermo_style custom step c_pv[2] c_pv[4] c_ksum[1] c_ksum[2] c_zsum xy
thermo_modify format float %.17g norm no
thermo {every}
run {steps}
",
        eta_n = run.eta_n,
        every = run.every,
        steps = run.steps,
        kn = o.kn,
        mu = o.friction,
        skin = 0.1 * s.disks.iter().map(|d| d.r).fold(0.0, f64::max),
        dt = run.dt,
        rate = s.shear_rate,
        half = 0.5 * s.ly,
    )
}

/// A sample: time, σ_yy, σ_yx (compression positive, kinetic part included), Z.
#[derive(Clone, Copy, Debug)]
struct Sample {
    t: f64,
    syy: f64,
    syx: f64,
    z: f64,
}

/// The thermo table of a LAMMPS log: the rows under the `Step` header, before `Loop time`.
fn lammps_samples(log: &str, area: f64, n: usize, dt: f64) -> Result<Vec<Sample>, String> {
    let mut rows = Vec::new();
    let mut inside = false;
    for line in log.lines() {
        if line.trim_start().starts_with("Step ") {
            inside = true;
            continue;
        }
        if line.starts_with("Loop time") {
            inside = false;
            continue;
        }
        if inside {
            let v: Vec<f64> = line
                .split_whitespace()
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|_| format!("LAMMPS log: a thermo row that is not numbers: {line}"))?;
            if v.len() < 6 {
                return Err(format!("LAMMPS log: a short thermo row: {line}"));
            }
            rows.push(Sample {
                t: v[0] * dt,
                syy: v[1] + v[3] / area,
                syx: v[2] + v[4] / area,
                z: v[5] / n as f64,
            });
        }
    }
    if rows.is_empty() {
        return Err("LAMMPS log: no thermo rows".into());
    }
    Ok(rows)
}

/// dem2d's samples: `cell.csv` (t, syx, syy) and `analysis.csv` (contacts, bodies).
fn dem2d_samples(dir: &Path) -> Result<Vec<Sample>, String> {
    let read = |name: &str| -> Result<(Vec<String>, Vec<Vec<f64>>), String> {
        let p = dir.join(name);
        let text = std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?;
        let mut lines = text.lines();
        let head: Vec<String> = lines
            .next()
            .unwrap_or("")
            .split(',')
            .map(String::from)
            .collect();
        let rows = lines
            .map(|l| {
                l.split(',')
                    .map(|x| x.parse().unwrap_or(f64::NAN))
                    .collect()
            })
            .collect();
        Ok((head, rows))
    };
    let col = |head: &[String], k: &str| {
        head.iter()
            .position(|h| h == k)
            .ok_or_else(|| format!("{}: no column {k}", dir.display()))
    };
    let (ch, cell) = read("cell.csv")?;
    let (ah, an) = read("analysis.csv")?;
    let (ct, cyx, cyy) = (col(&ch, "t")?, col(&ch, "syx")?, col(&ch, "syy")?);
    let (ac, ab) = (col(&ah, "contacts")?, col(&ah, "bodies")?);
    if cell.len() != an.len() {
        return Err(format!(
            "{}: cell.csv and analysis.csv differ in rows",
            dir.display()
        ));
    }
    Ok(cell
        .iter()
        .zip(&an)
        .map(|(c, a)| Sample {
            t: c[ct],
            syy: c[cyy],
            syx: c[cyx],
            z: 2.0 * a[ac] / a[ab],
        })
        .collect())
}

/// Mean and standard error of a series by block averages: the block length is twice the
/// integrated autocorrelation time `τ = ½ + Σ_k ρ_k` (summed up to the first ρ_k ≤ 0), in
/// samples, at least one; returns (mean, standard error, block length, blocks).
pub fn block_mean(x: &[f64]) -> (f64, f64, usize, usize) {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
    let mut tau = 0.5;
    if var > 0.0 {
        for k in 1..n / 2 {
            let c = (0..n - k)
                .map(|i| (x[i] - mean) * (x[i + k] - mean))
                .sum::<f64>()
                / ((n - k) as f64 * var);
            if c <= 0.0 {
                break;
            }
            tau += c;
        }
    }
    let b = ((2.0 * tau).ceil() as usize).max(1);
    let nb = n / b;
    if nb < 2 {
        return (mean, f64::NAN, b, nb);
    }
    let means: Vec<f64> = (0..nb)
        .map(|j| x[j * b..(j + 1) * b].iter().sum::<f64>() / b as f64)
        .collect();
    let m = means.iter().sum::<f64>() / nb as f64;
    let s2 = means.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (nb - 1) as f64;
    (mean, (s2 / nb as f64).sqrt(), b, nb)
}

fn run_logged(cmd: &mut std::process::Command, what: &str) -> Result<f64, String> {
    let start = Instant::now();
    let out = cmd.output().map_err(|e| format!("{what}: {e}"))?;
    let wall = start.elapsed().as_secs_f64();
    if !out.status.success() {
        return Err(format!(
            "{what} failed ({}): {}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(wall)
}

/// One run of a state: its directory (under --work), time step, steps, steps between samples
/// and normal dashpot.
struct Run {
    dir: String,
    dt: f64,
    steps: u64,
    every: u64,
    eta_n: f64,
}

/// A state run in both codes: dem2d's samples and LAMMPS's, their wall and CPU seconds (dem2d,
/// LAMMPS), and the largest |Δ| of LAMMPS's round-tripped positions and diameters from dem2d's
/// loaded state.
struct Both {
    dem: Vec<Sample>,
    lmp: Vec<Sample>,
    wall: [f64; 2],
    cpu: [f64; 2],
    roundtrip: f64,
}

/// Runs one state in both codes.
fn run_both(s: &State, o: &CrossOptions, run: &Run) -> Result<Both, String> {
    let dir = o.work.join(&run.dir);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let case = dir.join("case.json");
    let text = serde_json::to_string_pretty(&case_json(s, o, run)).map_err(|e| e.to_string())?;
    std::fs::write(&case, text).map_err(|e| format!("{}: {e}", case.display()))?;
    let out = dir.join("dem2d");
    let cpu0 = crate::peers::children_cpu_seconds();
    let dem2d_wall = run_logged(
        std::process::Command::new(&o.dem2d)
            .arg("run")
            .arg(&case)
            .arg("--out")
            .arg(&out)
            .args(["--threads", "1", "--quiet", "--overwrite"]),
        "dem2d run",
    )?;
    let dem2d_cpu = crate::peers::children_cpu_seconds() - cpu0;
    let lmp_dir = dir.join("lammps");
    std::fs::create_dir_all(&lmp_dir).map_err(|e| format!("{}: {e}", lmp_dir.display()))?;
    std::fs::write(lmp_dir.join("state.data"), lammps_data(s)).map_err(|e| e.to_string())?;
    std::fs::write(lmp_dir.join("in.shear"), lammps_deck(s, o, run)).map_err(|e| e.to_string())?;
    let lmp_wall = run_logged(
        std::process::Command::new(&o.lmp)
            .current_dir(&lmp_dir)
            .args(["-in", "in.shear", "-log", "log.lammps", "-screen", "none"]),
        "lmp",
    )?;
    let lmp_cpu = crate::peers::children_cpu_seconds() - cpu0 - dem2d_cpu;
    let log = std::fs::read_to_string(lmp_dir.join("log.lammps")).map_err(|e| e.to_string())?;
    let area = s.lx * s.ly;
    let lmp = lammps_samples(&log, area, s.disks.len(), run.dt)?;
    let dem = dem2d_samples(&out)?;
    let roundtrip = roundtrip_error(&lmp_dir.join("roundtrip.data"), &out, s)?;
    Ok(Both {
        dem,
        lmp,
        wall: [dem2d_wall, lmp_wall],
        cpu: [dem2d_cpu, lmp_cpu],
        roundtrip,
    })
}

/// The largest difference between LAMMPS's `write_data` of the state it read (positions and
/// diameters, by id) and dem2d's loaded state (`trajectory.csv`'s step 0 and the case's radii).
fn roundtrip_error(data: &Path, dem2d: &Path, s: &State) -> Result<f64, String> {
    let text = std::fs::read_to_string(data).map_err(|e| format!("{}: {e}", data.display()))?;
    let traj = std::fs::read_to_string(dem2d.join("trajectory.csv")).map_err(|e| e.to_string())?;
    let mut dem = vec![(f64::NAN, f64::NAN); s.disks.len()];
    for l in traj.lines().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        if f[0] != "0" {
            break;
        }
        let k: usize = f[2].parse().map_err(|_| "trajectory.csv: body")?;
        dem[k] = (
            f[3].parse().unwrap_or(f64::NAN),
            f[4].parse().unwrap_or(f64::NAN),
        );
    }
    let mut worst = 0.0f64;
    let mut seen = 0;
    let mut inside = false;
    for l in text.lines() {
        if l.starts_with("Atoms") {
            inside = true;
            continue;
        }
        if inside && l.starts_with("Velocities") {
            break;
        }
        let f: Vec<&str> = l.split_whitespace().collect();
        if !inside || f.len() < 7 {
            continue;
        }
        let id: usize = f[0].parse().map_err(|_| "roundtrip.data: id")?;
        let num = |i: usize| f[i].parse::<f64>().unwrap_or(f64::NAN);
        let (d, x, y) = (num(2), num(4), num(5));
        let k = id - 1;
        let e = (d - 2.0 * s.disks[k].r)
            .abs()
            .max((x - dem[k].0).abs())
            .max((y - dem[k].1).abs());
        worst = if e.is_nan() {
            f64::INFINITY
        } else {
            worst.max(e)
        };
        seen += 1;
    }
    if seen != s.disks.len() {
        return Err(format!(
            "{}: {seen} atoms, not {}",
            data.display(),
            s.disks.len()
        ));
    }
    Ok(worst)
}

fn pm(m: f64, se: f64) -> String {
    format!("{} ± {}", sig(m, 4), sig(se, 2))
}

fn sig(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let rounded = format!("{:.*e}", digits - 1, x);
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e6) {
        return rounded;
    }
    rounded
        .parse::<f64>()
        .map(|v| format!("{v}"))
        .unwrap_or_default()
}

/// Runs the cross-check and returns its report (Markdown).
pub fn run(o: &CrossOptions) -> Result<String, String> {
    let packing = read_packing(&o.case)?;
    let n = packing.2.len();
    let phi0 = disk_area(&packing.2) / (packing.0 * packing.1);
    let (rmin, rmax) = packing.2.iter().fold((f64::INFINITY, 0.0f64), |(a, b), d| {
        (a.min(d.r), b.max(d.r))
    });
    let meff = |a: f64, b: f64| mass(a) * mass(b) / (mass(a) + mass(b));
    let eta_n = 2.0 * alpha(o.restitution) * (meff(rmin, rmax) * o.kn).sqrt();
    let d_mean = packing.2.iter().map(|d| 2.0 * d.r).sum::<f64>() / n as f64;
    let dt0 = o.dt[0];
    let mut md = String::new();
    let _ = writeln!(
        md,
        "{n} disks (r = {rmin} and {rmax} cm, ρ = 1 g/cm², mean diameter d = {} cm) from {}; k_n = k_t = {:e} dyn/cm, μ = {}, η_n = {} g/s (e = {} for the small–large pair: e = {} small–small, {} large–large), η_t = 0.\n",
        sig(d_mean, 6),
        o.case.display(),
        o.kn,
        o.friction,
        sig(eta_n, 6),
        o.restitution,
        sig(restitution_of(eta_n, meff(rmin, rmin), o.kn), 4),
        sig(restitution_of(eta_n, meff(rmax, rmax), o.kn), 4),
    );

    // The static state: the first force evaluation from rest, overlapping, sheared; and the
    // same state in a cell that is not sheared, for three steps.
    for (name, rate) in [("static", o.shear_rate), ("static_unsheared", 0.0)] {
        let st = scaled(name, &packing, o.static_scale, rate);
        let st = State {
            disks: st.disks.iter().map(|d| Disk { vx: 0.0, ..*d }).collect(),
            ..st
        };
        let run = Run {
            dir: name.to_string(),
            dt: dt0,
            steps: 3,
            every: 1,
            eta_n,
        };
        let both = run_both(&st, o, &run)?;
        let _ = writeln!(
            md,
            "**Static state `{name}`** (the packing scaled by {} about the origin: φ = {}, at rest, the cell sheared at γ̇ = {rate} /s from the first step; Δt = {dt0:e} s): the data file LAMMPS read and wrote back (`write_data`) differs from dem2d's loaded state (`trajectory.csv`, the case's radii) by at most {:e} cm.\n",
            o.static_scale,
            sig(disk_area(&st.disks) / (st.lx * st.ly), 6),
            both.roundtrip
        );
        md.push_str("| step | σ_yy dem2d (dyn/cm) | σ_yy LAMMPS (dyn/cm) | relative difference | σ_yx dem2d | σ_yx LAMMPS | Z dem2d | Z LAMMPS |\n|---|---|---|---|---|---|---|---|\n");
        for (k, (a, b)) in both.dem.iter().zip(&both.lmp).enumerate() {
            let _ = writeln!(
                md,
                "| {k} | {:.12e} | {:.12e} | {:.1e} | {:.9e} | {:.9e} | {:.4} | {:.4} |",
                a.syy,
                b.syy,
                (a.syy - b.syy).abs() / b.syy.abs(),
                a.syx,
                b.syx,
                a.z,
                b.z
            );
        }
        md.push('\n');
    }

    // The shear runs, one per time step.
    let sh = scaled("shear", &packing, (phi0 / o.phi).sqrt(), o.shear_rate);
    let t0 = o.transient_strain / o.shear_rate;
    for &dt in &o.dt {
        let run = Run {
            dir: format!("shear_dt{dt:e}"),
            dt,
            steps: (o.strain / (o.shear_rate.abs() * dt)).round().max(1.0) as u64,
            every: (o.sample_strain / (o.shear_rate.abs() * dt))
                .round()
                .max(1.0) as u64,
            eta_n,
        };
        let both = run_both(&sh, o, &run)?;
        let (dem, lmp) = (&both.dem, &both.lmp);
        let _ = writeln!(
            md,
            "**Shear** at constant volume, Δt = {dt:e} s: φ = {}, cell {} × {} cm, γ̇ = {} /s, {} steps (strain {}), sampled every {} steps; means over strain ≥ {} ({} samples in dem2d, {} in LAMMPS). Round trip of the data file: at most {:e} cm. CPU time (one thread): dem2d {:.1} s, LAMMPS {:.1} s (wall {:.1} s and {:.1} s).\n",
            o.phi,
            sig(sh.lx, 6),
            sig(sh.ly, 6),
            o.shear_rate,
            run.steps,
            sig(run.steps as f64 * dt * o.shear_rate, 4),
            run.every,
            o.transient_strain,
            dem.iter().filter(|s| s.t >= t0 - 1e-12).count(),
            lmp.iter().filter(|s| s.t >= t0 - 1e-12).count(),
            both.roundtrip,
            both.cpu[0],
            both.cpu[1],
            both.wall[0],
            both.wall[1],
        );
        md.push_str(&shear_table(dem, lmp, t0, o.shear_rate, d_mean));
        md.push('\n');
    }

    if let Some(iterations) = o.fire {
        md.push('\n');
        md.push_str(&fire(o, iterations)?);
    }
    Ok(md)
}

/// The steady state's means, standard errors and ratios (samples at t ≥ `t0`).
fn shear_table(dem: &[Sample], lmp: &[Sample], t0: f64, shear_rate: f64, d_mean: f64) -> String {
    let mut md = String::from(
        "| quantity | dem2d | LAMMPS | dem2d / LAMMPS | blocks × samples (dem2d; LAMMPS) |\n|---|---|---|---|---|\n",
    );
    let steady = |v: &[Sample], f: &dyn Fn(&Sample) -> f64| -> Vec<f64> {
        v.iter().filter(|s| s.t >= t0 - 1e-12).map(f).collect()
    };
    type Measure<'a> = (&'a str, Box<dyn Fn(&Sample) -> f64>);
    let measures: Vec<Measure> = vec![
        ("μ = −σ_yx/σ_yy", Box::new(|s: &Sample| -s.syx / s.syy)),
        ("σ_yy (dyn/cm)", Box::new(|s: &Sample| s.syy)),
        (
            "Z (contacts per disk, rattlers included)",
            Box::new(|s: &Sample| s.z),
        ),
    ];
    let mut syy = [(0.0, 0.0); 2];
    for (name, f) in &measures {
        let a = block_mean(&steady(dem, f.as_ref()));
        let b = block_mean(&steady(lmp, f.as_ref()));
        if name.starts_with("σ_yy") {
            syy = [(a.0, a.1), (b.0, b.1)];
        }
        let r = a.0 / b.0;
        let rse = r.abs() * ((a.1 / a.0).powi(2) + (b.1 / b.0).powi(2)).sqrt();
        let _ = writeln!(
            md,
            "| {name} | {} | {} | {} | {}×{}; {}×{} |",
            pm(a.0, a.1),
            pm(b.0, b.1),
            pm(r, rse),
            a.3,
            a.2,
            b.3,
            b.2
        );
    }
    let inertial = |(m, se): (f64, f64)| {
        let i = shear_rate.abs() * d_mean / m.sqrt();
        (i, 0.5 * i * se / m)
    };
    let (ia, ib) = (inertial(syy[0]), inertial(syy[1]));
    let r = ia.0 / ib.0;
    let rse = r * ((ia.1 / ia.0).powi(2) + (ib.1 / ib.0).powi(2)).sqrt();
    let _ = writeln!(
        md,
        "| I = γ̇ d √(ρ/⟨σ_yy⟩) | {} | {} | {} | from σ_yy |",
        pm(ia.0, ia.1),
        pm(ib.0, ib.1),
        pm(r, rse)
    );
    md
}

/// LAMMPS's FIRE (lab/peers/jamming_fire.py) and `dem2d relax` on the packing itself, measured
/// the same way (the script's `--measure`).
fn fire(o: &CrossOptions, iterations: u64) -> Result<String, String> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("peers/jamming_fire.py");
    let json_of = |out: std::process::Output, what: &str| -> Result<Value, String> {
        if !out.status.success() {
            return Err(format!(
                "{what} failed: {}",
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        serde_json::from_slice(&out.stdout).map_err(|e| format!("{what}: {e}"))
    };
    let start = Instant::now();
    let lmp = json_of(
        std::process::Command::new("python3")
            .arg(&script)
            .arg(&o.case)
            .args(["--lmp"])
            .arg(&o.lmp)
            .args(["--maxiter", &iterations.to_string()])
            .output()
            .map_err(|e| format!("python3: {e}"))?,
        "jamming_fire.py",
    )?;
    let lmp_wall = start.elapsed().as_secs_f64();
    let out = o.work.join("relax");
    let start = Instant::now();
    run_logged(
        std::process::Command::new(&o.dem2d)
            .arg("relax")
            .arg(&o.case)
            .arg("--out")
            .arg(&out)
            .args([
                "--threads",
                "1",
                "--max-iterations",
                &iterations.to_string(),
            ]),
        "dem2d relax",
    )
    .or_else(|e| {
        // relax exits 1 when it stops at its iteration cap or at round-off: its state is kept.
        if out.join("state.json").is_file() {
            Ok(0.0)
        } else {
            Err(e)
        }
    })?;
    let dem_wall = start.elapsed().as_secs_f64();
    let dem = json_of(
        std::process::Command::new("python3")
            .arg(&script)
            .arg(out.join("state.json"))
            .arg("--measure")
            .output()
            .map_err(|e| format!("python3: {e}"))?,
        "jamming_fire.py --measure",
    )?;
    let mut md = format!(
        "**FIRE** on {} (frictionless, k_n from the case), at most {iterations} iterations each: `dem2d relax` ({:.1} s) and LAMMPS's `min_style fire` through lab/peers/jamming_fire.py ({:.1} s, stop: {}), measured by the same script:\n\n| | energy (erg) | residual | contacts | Z (rattlers out) | rattlers |\n|---|---|---|---|---|---|\n",
        o.case.display(),
        dem_wall,
        lmp_wall,
        lmp["stopping_criterion"].as_str().unwrap_or("?")
    );
    for (name, v) in [("dem2d relax", &dem), ("LAMMPS FIRE", &lmp)] {
        let _ = writeln!(
            md,
            "| {name} | {} | {} | {} | {} | {} |",
            sig(v["energy"].as_f64().unwrap_or(f64::NAN), 6),
            sig(v["residual"].as_f64().unwrap_or(f64::NAN), 3),
            v["contacts"],
            sig(v["z"].as_f64().unwrap_or(f64::NAN), 5),
            v["rattlers"]
        );
    }
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn restitution_inverts_alpha() {
        // T12: η = 2α√(m k) gives back e.
        for e in [0.1, 0.5, 0.9] {
            let m: f64 = 0.7;
            let k = 1e6;
            let eta = 2.0 * alpha(e) * (m * k).sqrt();
            assert!((restitution_of(eta, m, k) - e).abs() < 1e-12);
        }
    }

    #[test]
    fn blocks_of_independent_samples_give_sd_over_root_n() {
        // Alternating ±1: the mean is 0, no positive correlation, blocks of one sample.
        let x: Vec<f64> = (0..1000)
            .map(|i| if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let (m, se, b, nb) = block_mean(&x);
        assert_eq!((m, b, nb), (0.0, 1, 1000));
        assert!((se - (1000.0f64 / 999.0).sqrt() / 1000f64.sqrt()).abs() < 1e-12);
    }
}

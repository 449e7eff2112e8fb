//! `dem2d-lab fuzz`: a seeded fuzzing round over the newer features (periodic cells, imposed
//! pressure, Lees–Edwards shear, `dem2d relax`, insertion and outflow, segment walls, materials,
//! wall programs and moving walls, restarts from an edited `state.json`).
//!
//! Each mutant is a base case (a shipped case of `cases/`, or a complete example of the
//! case-file page, or a `state.json` written by a short run of one of them) shortened to a few
//! hundred steps, then changed by one to three mutations drawn from the seed: numbers set to
//! extremes or scaled, wrong types, removed or unknown keys, duplicate keys, non-finite literals,
//! arrays of the wrong length, and mutations that know the features (a duplicated body, a body
//! moved outside the cell or behind a wall or by whole periods, extreme speeds, Δt and duration
//! to extremes, a cell shrunk or stretched, shear and pressure to extremes, a wall program's
//! stages reordered or driven hard, insertion regions behind walls, rates and counts to
//! extremes, outflow over everything, materials to extremes). Mutant `k` of seed `s` is the same
//! file whatever else is run (`--only k` replays it).
//!
//! Each mutant is run by the release `dem2d` binary (`run`, or `relax` for frictionless bases)
//! with `--max-steps`, one thread, a memory cap and a timeout, and classified:
//! - `ok`: exit 0 and every check below passes;
//! - `refused`: exit 2 naming a field (``field `…` ``), nothing written;
//! - `detected`: exit 1 with the documented status (`blowup`, `io_error`; relax: `stalled`,
//!   `max_iterations`) and a message;
//! - `PANIC`: exit 101, or `panicked` on stderr, or killed by a signal (an abort, a crash);
//! - `HANG`: no exit within the timeout;
//! - `SILENT`: exit 0 but a check fails (see [`silent_checks`]): a non-finite number in the
//!   outputs, a status or error that contradicts the exit, a body outside the periodic cell, a
//!   cell under imposed pressure shrunk below twice a pair's reach, an energy account off by more
//!   than the audit's threshold with no "unaccounted" warning, an inserter that placed nothing
//!   with no warning;
//! - `BAD_EXIT`: any other outcome (another exit code, a refusal that names no field, a refusal
//!   that wrote output, an exit 1 without its status).
//!
//! The counts go to `OUT/report.md` (and stdout), every mutant's line to `OUT/mutants.csv`, and
//! each failing mutant's file and outcome to `OUT/failures/`.

use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// What `dem2d-lab fuzz` is asked.
pub struct FuzzOptions {
    pub mutants: usize,
    pub seed: u64,
    pub out: PathBuf,
    pub timeout: Duration,
    pub jobs: usize,
    /// The repository's root (cases/ and docs/ are read from it).
    pub root: PathBuf,
    /// Run only this mutant (a replay).
    pub only: Option<usize>,
    pub max_steps: u64,
    pub progress: bool,
}

/// Outcome classes, in the report's order.
pub const CLASSES: [&str; 7] = [
    "ok", "refused", "detected", "PANIC", "HANG", "SILENT", "BAD_EXIT",
];

/// The classes that fail a round.
pub fn is_failure(class: &str) -> bool {
    matches!(class, "PANIC" | "HANG" | "SILENT" | "BAD_EXIT")
}

/// The counts of a round.
pub struct Report {
    pub counts: BTreeMap<String, usize>,
    pub markdown: String,
    pub failures: Vec<String>,
}

/// SplitMix64.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }

    /// Mutant `k` of `seed`: its own stream, so that a mutant does not depend on the others.
    fn for_mutant(seed: u64, k: usize) -> Rng {
        let mut r = Rng(seed ^ 0xD1B5_4A32_D192_ED03);
        for _ in 0..3 {
            r.next();
        }
        let mut r = Rng(r.next() ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        r.next();
        r
    }
}

/// A base case: its name, its JSON, and whether `dem2d relax` may take it (no friction).
struct Base {
    name: String,
    case: Value,
    relax: bool,
}

/// The shipped cases of the newer features.
const SHIPPED: [&str; 5] = [
    "shear_cell",
    "compress_cell_mu0",
    "hopper_segments",
    "lid_program",
    "paddle_materials",
];

/// The case-file page's complete examples of the newer features (by their `name`).
const EXAMPLES: [&str; 6] = [
    "pouring",
    "periodic_x",
    "shear_cell",
    "segments",
    "moving_walls",
    "materials",
];

/// Bases whose short run's `state.json` is a base too (restarts).
const STATE_BASES: [&str; 4] = [
    "example_shear_cell",
    "example_pouring",
    "lid_program",
    "example_periodic_x",
];

/// Steps a base is shortened to (its duration, and every time in it, scaled down).
const BASE_STEPS: f64 = 4000.0;

fn num(v: &Value, key: &str) -> Option<f64> {
    v.get(key).and_then(Value::as_f64)
}

/// Scales every time of a case (duration, program stages, insertion starts and retries) by `s`.
fn scale_times(case: &mut Value, s: f64) {
    if let Some(d) = num(case, "duration") {
        case["duration"] = json!(d * s);
    }
    if let Some(walls) = case.get_mut("walls").and_then(Value::as_array_mut) {
        for w in walls {
            if let Some(stages) = w.get_mut("motion").and_then(Value::as_array_mut) {
                for st in stages {
                    if let Some(u) = num(st, "until") {
                        st["until"] = json!(u * s);
                    }
                }
            }
        }
    }
    if let Some(ins) = case.get_mut("insert").and_then(Value::as_array_mut) {
        for i in ins {
            for key in ["start", "retry"] {
                if let Some(x) = num(i, key) {
                    i[key] = json!(x * s);
                }
            }
            // Rates scaled up so that the shortened run still inserts.
            if let Some(x) = num(i, "rate") {
                i["rate"] = json!(x / s);
            }
        }
    }
}

/// Shortens a base to about [`BASE_STEPS`] steps, output every 50.
fn shorten(case: &mut Value) {
    let (Some(dt), Some(d)) = (num(case, "dt"), num(case, "duration")) else {
        return;
    };
    let target = BASE_STEPS * dt;
    if d > target {
        scale_times(case, target / d);
    }
    case["output_every"] = json!(50);
    if let Some(o) = case.get_mut("output").and_then(Value::as_object_mut)
        && o.contains_key("vtk_every")
    {
        o.insert("vtk_every".into(), json!(100));
    }
}

/// The complete JSON examples of the case-file page, by name.
fn examples(root: &Path) -> Result<Vec<(String, Value)>, String> {
    let page = root.join("docs/src/reference/case-file.md");
    let text = std::fs::read_to_string(&page)
        .map_err(|e| format!("{}: cannot read: {e}", page.display()))?;
    let mut out = Vec::new();
    for block in text.split("```json\n").skip(1) {
        let block = block.split("```").next().unwrap_or("");
        if let Ok(v) = serde_json::from_str::<Value>(block)
            && let Some(name) = v.get("name").and_then(Value::as_str)
            && EXAMPLES.contains(&name)
        {
            out.push((format!("example_{name}"), v));
        }
    }
    for name in EXAMPLES {
        if !out.iter().any(|(n, _)| *n == format!("example_{name}")) {
            return Err(format!(
                "{}: no complete example named `{name}`",
                page.display()
            ));
        }
    }
    Ok(out)
}

fn frictionless(case: &Value) -> bool {
    case["contact"]["friction"].as_f64() == Some(0.0) && case.get("materials").is_none()
}

/// The bases: shipped cases, the page's examples, and states of short runs of some of them.
fn bases(root: &Path, exe: &Path, work: &Path) -> Result<Vec<Base>, String> {
    let mut out = Vec::new();
    for name in SHIPPED {
        let path = root.join("cases").join(format!("{name}.json"));
        let text = std::fs::read_to_string(&path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        let v: Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        out.push((name.to_string(), v));
    }
    out.extend(examples(root)?);
    let mut bases: Vec<Base> = out
        .into_iter()
        .map(|(name, mut case)| {
            shorten(&mut case);
            let relax = frictionless(&case);
            Base { name, case, relax }
        })
        .collect();
    // States: each run for half its steps; its state.json (the run's case with the bodies where
    // they are and the `state` block) is a base.
    let dir = work.join("states");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for name in STATE_BASES {
        let base = bases
            .iter()
            .find(|b| b.name == name)
            .ok_or(format!("no base {name}"))?;
        let file = dir.join(format!("{name}.json"));
        write_json(&file, &base.case)?;
        let run_dir = dir.join(name);
        // Half its steps, so that the state has steps left to run.
        let steps =
            num(&base.case, "duration").unwrap_or(0.0) / num(&base.case, "dt").unwrap_or(1.0);
        let half = ((steps / 2.0).round().max(1.0) as u64).to_string();
        let o = Command::new(exe)
            .args(["run", path_str(&file)?, "--out", path_str(&run_dir)?])
            .args(["--max-steps", &half, "--quiet", "--threads", "1"])
            .output()
            .map_err(|e| format!("{}: {e}", exe.display()))?;
        if !o.status.success() {
            return Err(format!(
                "the state base {name} did not run: {}",
                String::from_utf8_lossy(&o.stderr)
            ));
        }
        let state = run_dir.join("state.json");
        let text = std::fs::read_to_string(&state)
            .map_err(|e| format!("{}: cannot read: {e}", state.display()))?;
        let case: Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", state.display()))?;
        bases.push(Base {
            name: format!("state_{name}"),
            case,
            relax: false,
        });
    }
    Ok(bases)
}

fn path_str(p: &Path) -> Result<&str, String> {
    p.to_str()
        .ok_or_else(|| format!("{}: not UTF-8", p.display()))
}

fn write_json(path: &Path, v: &Value) -> Result<(), String> {
    let text = serde_json::to_string_pretty(v).map_err(|e| e.to_string())?;
    std::fs::write(path, text).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

// ----------------------------------------------------------------------------------------------
// Mutations
// ----------------------------------------------------------------------------------------------

/// Every path to a value (object keys and array indices; the first few elements of arrays).
fn paths(v: &Value, prefix: &mut Vec<Value>, out: &mut Vec<Vec<Value>>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                prefix.push(json!(k));
                out.push(prefix.clone());
                paths(x, prefix, out);
                prefix.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate().take(5) {
                prefix.push(json!(i));
                out.push(prefix.clone());
                paths(x, prefix, out);
                prefix.pop();
            }
        }
        _ => {}
    }
}

fn get_mut<'a>(v: &'a mut Value, path: &[Value]) -> Option<&'a mut Value> {
    let mut v = v;
    for k in path {
        v = match k {
            Value::String(s) => v.get_mut(s.as_str())?,
            _ => v.get_mut(k.as_u64()? as usize)?,
        };
    }
    Some(v)
}

fn path_name(path: &[Value]) -> String {
    path.iter()
        .map(|k| match k {
            Value::String(s) => s.clone(),
            other => other.to_string(),
        })
        .collect::<Vec<_>>()
        .join(".")
}

const EXTREMES: [f64; 16] = [
    0.0, -0.0, -1.0, 1e300, -1e300, 1e-300, -1e-300, 1e40, -1e40, 1e-40, 1e41, 5e-324, 1e20, -1e20,
    1e9, 0.5,
];
const FACTORS: [f64; 10] = [
    1e-6, 1e-3, 0.5, 0.999_999, 1.000_001, 2.0, 10.0, 1e3, 1e6, -1.0,
];
/// Extremes within the accepted ranges (they reach the dynamics).
const IN_RANGE: [f64; 12] = [
    1e-30, 1e30, 1e-10, 1e10, 1e39, -1e39, 3.0, 1e-3, 1e3, 0.0, 1e-39, 7e5,
];
const SPEEDS: [f64; 9] = [1e3, 1e6, 1e10, 1e15, 1e20, 1e30, 1e40, -1e40, -1e12];

/// A generic mutation of a random field (numbers mostly).
fn generic(rng: &mut Rng, case: &mut Value, text: &mut Vec<(String, String)>) -> String {
    let mut all = Vec::new();
    paths(case, &mut Vec::new(), &mut all);
    // A state's own block is half the mutations of a state base.
    if case.get("state").is_some() && rng.below(2) == 0 {
        all.retain(|p| p.first() == Some(&json!("state")));
    }
    if all.is_empty() {
        return "nothing to mutate".into();
    }
    let snapshot = case.clone();
    let numbers: Vec<Vec<Value>> = all
        .iter()
        .filter(|p| {
            let mut s = snapshot.clone();
            get_mut(&mut s, p).is_some_and(|v| v.is_number())
        })
        .cloned()
        .collect();
    let path = if rng.below(3) > 0 && !numbers.is_empty() {
        rng.pick(&numbers).clone()
    } else {
        rng.pick(&all).clone()
    };
    let name = path_name(&path);
    let Some(target) = get_mut(case, &path) else {
        return "no target".into();
    };
    match rng.below(16) {
        14 | 15 => {
            let x = *rng.pick(&IN_RANGE);
            *target = json!(x);
            format!("{name} = {x:e}")
        }
        0..=3 => {
            let x = *rng.pick(&EXTREMES);
            *target = json!(x);
            format!("{name} = {x:e}")
        }
        4..=6 => match target.as_f64() {
            Some(x) => {
                let f = *rng.pick(&FACTORS);
                *target = json!(x * f);
                format!("{name} ×= {f:e}")
            }
            None => {
                *target = json!(0);
                format!("{name} = 0")
            }
        },
        7 => {
            let r = rng
                .pick(&[
                    json!("NaN"),
                    json!("inf"),
                    json!("1e5"),
                    json!(""),
                    Value::Null,
                    json!(true),
                    json!([]),
                    json!({}),
                    json!([1]),
                    json!([1, 2, 3]),
                    json!(u64::MAX),
                    json!(-7),
                ])
                .clone();
            let d = format!("{name} = {r}");
            *target = r;
            d
        }
        8 => {
            // Arrays of the wrong length: an element dropped or one more.
            if let Some(a) = target.as_array_mut() {
                if rng.below(2) == 0 && !a.is_empty() {
                    a.pop();
                    format!("{name}: last element dropped")
                } else {
                    let last = a.last().cloned().unwrap_or(json!(0));
                    a.push(last);
                    format!("{name}: last element repeated")
                }
            } else {
                *target = json!([]);
                format!("{name} = []")
            }
        }
        9 | 10 => {
            let Some((last, parent)) = path.split_last() else {
                return "root".into();
            };
            let Some(parent) = get_mut(case, parent) else {
                return "no parent".into();
            };
            match (last, parent) {
                (Value::String(k), Value::Object(m)) => {
                    m.remove(k);
                }
                (i, Value::Array(a)) => {
                    let i = i.as_u64().unwrap_or(0) as usize;
                    if i < a.len() {
                        a.remove(i);
                    }
                }
                _ => {}
            }
            format!("remove {name}")
        }
        11 => {
            let obj = if target.is_object() {
                target
            } else {
                match get_mut(case, &path[..path.len() - 1]) {
                    Some(o) => o,
                    None => return "no parent".into(),
                }
            };
            if let Some(m) = obj.as_object_mut() {
                m.insert("extra_key".into(), json!(1));
                format!("unknown key beside {name}")
            } else {
                *obj = json!(0);
                format!("{name}'s parent = 0")
            }
        }
        12 => {
            if let (Some(Value::String(k)), Some(x)) = (path.last(), target.as_f64()) {
                let marker = format!("\"{k}\": {}", json!(x));
                text.push((marker.clone(), format!("\"{k}\": 1, {marker}")));
                format!("duplicate key {name}")
            } else {
                *target = json!(-1e-3);
                format!("{name} = -1e-3")
            }
        }
        _ => {
            let lit = *rng.pick(&["NaN", "Infinity", "-Infinity", "1e999"]);
            let mark = format!("\u{2}MARK{}", text.len());
            *target = json!(mark);
            text.push((
                serde_json::to_string(&json!(mark)).unwrap_or_default(),
                lit.into(),
            ));
            format!("{name} = {lit} (literal)")
        }
    }
}

fn bodies(case: &mut Value) -> Option<&mut Vec<Value>> {
    case.get_mut("bodies").and_then(Value::as_array_mut)
}

fn cell_size(case: &Value) -> Option<(f64, f64)> {
    let s = case.get("cell")?.get("size")?;
    Some((s.get(0)?.as_f64()?, s.get(1)?.as_f64()?))
}

/// A mutation that knows the features; falls back to a generic one where it does not apply.
fn featured(rng: &mut Rng, case: &mut Value, text: &mut Vec<(String, String)>) -> String {
    let n_bodies = case["bodies"].as_array().map_or(0, Vec::len);
    let cell = cell_size(case);
    match rng.below(16) {
        // A duplicated body: exactly on the original, or a hair off.
        0 if n_bodies > 0 => {
            let i = rng.below(n_bodies);
            if !case["bodies"][i].is_object() {
                return generic(rng, case, text);
            }
            let mut b = case["bodies"][i].clone();
            let off = *rng.pick(&[0.0, 1e-12, 1e-6, 0.01]);
            if let Some(x) = b["position"][0].as_f64() {
                b["position"][0] = json!(x + off);
            }
            if let Some(bs) = bodies(case) {
                bs.push(b);
            }
            format!("bodies[{i}] duplicated (offset {off:e})")
        }
        // A body moved: outside the cell by whole periods, onto a seam, behind a wall, far.
        1 | 2 if n_bodies > 0 => {
            let i = rng.below(n_bodies);
            if !case["bodies"][i].is_object() {
                return generic(rng, case, text);
            }
            let (lx, ly) = cell.unwrap_or((10.0, 10.0));
            let (x, y) = (
                case["bodies"][i]["position"][0].as_f64().unwrap_or(0.0),
                case["bodies"][i]["position"][1].as_f64().unwrap_or(0.0),
            );
            let choices = [
                (x + 3.0 * lx, y, "x + 3 Lx"),
                (x - lx, y - 2.0 * ly, "x - Lx, y - 2 Ly"),
                (x, y + 1e6 * ly, "y + 1e6 Ly"),
                (lx, y, "x = Lx (on the seam)"),
                (x, ly, "y = Ly (on the seam)"),
                (-1e-300, y, "x = -1e-300"),
                (
                    lx * (1.0 - 1e-16),
                    ly * (1.0 - 1e-16),
                    "just below the far corner",
                ),
                (x, -5.0, "y = -5 (behind a floor)"),
                (x, -1e4, "y = -1e4"),
                (1e8, 1e8, "far out (1e8, 1e8)"),
                (x + 1e-9, y, "x + 1e-9"),
            ];
            let (nx, ny, d) = *rng.pick(&choices);
            case["bodies"][i]["position"] = json!([nx, ny]);
            format!("bodies[{i}] moved to {d}")
        }
        // Extreme speeds and spins.
        3 | 4 if n_bodies > 0 => {
            let i = rng.below(n_bodies);
            if !case["bodies"][i].is_object() {
                return generic(rng, case, text);
            }
            let v = *rng.pick(&SPEEDS);
            match rng.below(3) {
                0 => case["bodies"][i]["velocity"] = json!([v, 0.0]),
                1 => case["bodies"][i]["velocity"] = json!([0.0, v]),
                _ => case["bodies"][i]["omega"] = json!(v),
            }
            if rng.below(3) == 0 {
                case["bodies"][i]["prescribed"] = json!(true);
                case["bodies"][i].as_object_mut().map(|m| m.remove("fixed"));
                format!("bodies[{i}] prescribed at speed {v:e}")
            } else {
                format!("bodies[{i}] speed {v:e}")
            }
        }
        // Δt and duration.
        5 => {
            let dt = num(case, "dt").unwrap_or(1e-5);
            let d = num(case, "duration").unwrap_or(1e-3);
            let (ndt, nd, what) = *rng.pick(&[
                (dt * 1e3, d, "dt × 1e3"),
                (dt * 30.0, d, "dt × 30"),
                (dt * 1e-3, d, "dt × 1e-3"),
                (d, d, "dt = duration"),
                (2.0 * d, d, "dt = 2 duration"),
                (dt, dt * 0.5, "duration = dt/2"),
                (dt, dt, "duration = dt"),
                (dt, 1e-40, "duration = 1e-40"),
                (1e-40, d, "dt = 1e-40"),
                (dt, dt * 1.5, "duration = 1.5 dt"),
            ]);
            case["dt"] = json!(ndt);
            case["duration"] = json!(nd);
            what.to_string()
        }
        // The cell.
        6 if cell.is_some() => {
            let (lx, ly) = cell.unwrap_or((1.0, 1.0));
            let c = &mut case["cell"];
            match rng.below(9) {
                0 => {
                    let f = *rng.pick(&[0.3, 0.5, 0.9, 0.1]);
                    c["size"] = json!([lx * f, ly * f]);
                    format!("cell.size × {f}")
                }
                1 => {
                    c["size"] = json!([lx, 1e6]);
                    "cell.size[1] = 1e6".into()
                }
                2 => {
                    let g = *rng.pick(&[1e6, -50.0, 1e3, 1e-300, -1e40, 1e12]);
                    c["shear_rate"] = json!(g);
                    format!("cell.shear_rate = {g:e}")
                }
                3 => {
                    let p = *rng.pick(&[1e10, 1e-10, 1e6, 1e30, 1e5]);
                    c["pressure"] = json!(p);
                    format!("cell.pressure = {p:e}")
                }
                4 => {
                    let g = *rng.pick(&[1.0, 1e-9, 0.999]);
                    c["pressure_gain"] = json!(g);
                    c["pressure"] = json!(1000.0);
                    format!("cell.pressure_gain = {g}, pressure 1000")
                }
                5 => {
                    let p = if c["periodic"] == "xy" { "x" } else { "xy" };
                    c["periodic"] = json!(p);
                    format!("cell.periodic = {p}")
                }
                6 => {
                    case["gravity"] = json!([0, -980]);
                    "gravity [0, -980] in the cell".into()
                }
                7 => {
                    case.as_object_mut().map(|m| m.remove("cell"));
                    "cell removed".into()
                }
                _ => {
                    let (nlx, nly) = (lx * 1e-3, ly * 1e3);
                    c["size"] = json!([nlx, nly]);
                    format!("cell.size = [{nlx}, {nly}]")
                }
            }
        }
        // A cell given to a scene that has none.
        6 => {
            let size = *rng.pick(&[[10.0, 10.0], [30.0, 30.0], [4.0, 100.0]]);
            let periodic = *rng.pick(&["x", "xy"]);
            case["cell"] = json!({"size": size, "periodic": periodic});
            if rng.below(2) == 0 && periodic == "xy" {
                case["cell"]["shear_rate"] = json!(5.0);
                case["cell"]["pressure"] = json!(1000.0);
            }
            format!("cell {size:?} {periodic} added")
        }
        // Walls: programs, speeds, servos, segments.
        7 | 8 if case["walls"].as_array().is_some_and(|w| !w.is_empty()) => {
            let nw = case["walls"].as_array().map_or(0, Vec::len);
            let k = rng.below(nw);
            if !case["walls"][k].is_object() {
                return generic(rng, case, text);
            }
            let w = &mut case["walls"][k];
            match rng.below(8) {
                0 => {
                    let v = *rng.pick(&SPEEDS);
                    w.as_object_mut().map(|m| m.remove("servo"));
                    w.as_object_mut().map(|m| m.remove("motion"));
                    w["velocity"] = json!([0.0, v]);
                    format!("walls[{k}].velocity = [0, {v:e}]")
                }
                1 if w["motion"].is_array() => {
                    if let Some(st) = w["motion"].as_array_mut() {
                        st.reverse();
                    }
                    format!("walls[{k}].motion reversed")
                }
                2 => {
                    let stress = *rng.pick(&[1e30, 1e-30, 1e12, 1.0]);
                    let speed = *rng.pick(&[1e10, 1e-10, 20.0]);
                    let servo = json!({"stress": stress, "span": 5.0, "max_speed": speed});
                    if w["motion"].is_array() {
                        w["motion"] =
                            json!([{"until": 1e-4, "velocity": [0, 0]}, {"servo": servo}]);
                        format!("walls[{k}].motion = rest, servo {stress:e} {speed:e}")
                    } else if w.get("segment").is_some() {
                        w["motion"] =
                            json!([{"until": 1e-4, "velocity": [0, -1e3]}, {"velocity": [1e3, 0]}]);
                        format!("walls[{k}] (segment) program of two fast stages")
                    } else {
                        w.as_object_mut().map(|m| m.remove("velocity"));
                        w["servo"] = servo;
                        format!("walls[{k}].servo {stress:e} {speed:e}")
                    }
                }
                3 => {
                    let u = *rng.pick(&[1e-40, 1e40, 0.0, -1.0, 1e-9]);
                    w["motion"] = json!([{"until": u, "velocity": [0, -5]}, {"velocity": [0, 5]}]);
                    w.as_object_mut().map(|m| m.remove("velocity"));
                    w.as_object_mut().map(|m| m.remove("servo"));
                    format!("walls[{k}].motion until {u:e}")
                }
                4 if w.get("segment").is_some() => {
                    let s = w["segment"].clone();
                    let choice = rng.below(3);
                    w["segment"] = match choice {
                        0 => json!([s[0].clone(), s[0].clone()]),
                        1 => json!([[-1e9, s[0][1].clone()], [1e9, s[1][1].clone()]]),
                        _ => json!([
                            s[0].clone(),
                            [s[0][0].as_f64().unwrap_or(0.0) + 1e-12, s[0][1].clone()]
                        ]),
                    };
                    format!("walls[{k}].segment mutated ({choice})")
                }
                5 => {
                    // The wall moved through the bodies.
                    if let Some(p) = w.get("point").cloned() {
                        let y = p[1].as_f64().unwrap_or(0.0);
                        w["point"] = json!([p[0].clone(), y + 5.0]);
                        format!("walls[{k}].point moved 5 cm in y")
                    } else {
                        w["segment"] = json!([[-5, 5], [5, 5]]);
                        format!("walls[{k}].segment across the scene")
                    }
                }
                6 => {
                    let f = *rng.pick(&[1e12, 0.0, 1e-30]);
                    w["friction"] = json!(f);
                    w.as_object_mut().map(|m| m.remove("material"));
                    format!("walls[{k}].friction = {f:e}")
                }
                _ => {
                    // A segment wall added across the scene, or a half-plane into a cell.
                    let seg = json!({"segment": [[-3, 2], [3, 2.5]]});
                    if let Some(ws) = case["walls"].as_array_mut() {
                        ws.push(seg);
                    }
                    "a segment wall added".into()
                }
            }
        }
        // Insertion.
        9 | 10 if case["insert"].as_array().is_some_and(|a| !a.is_empty()) => {
            let ni = case["insert"].as_array().map_or(0, Vec::len);
            let k = rng.below(ni);
            if !case["insert"][k].is_object() {
                return generic(rng, case, text);
            }
            let ins = &mut case["insert"][k];
            match rng.below(10) {
                0 => {
                    ins["region"] = json!([-6, 6, -30, -20]);
                    format!("insert[{k}].region below everything")
                }
                1 => {
                    ins["region"] = json!([-1e9, 1e9, -1e9, 1e9]);
                    format!("insert[{k}].region huge")
                }
                2 => {
                    let r = *rng.pick(&[1e7, 1e12, 1e-300]);
                    ins.as_object_mut().map(|m| m.remove("keep"));
                    ins["rate"] = json!(r);
                    format!("insert[{k}].rate = {r:e}")
                }
                3 => {
                    let c = *rng.pick(&[1_000_000u64, 100_000, 0, u64::MAX]);
                    ins["count"] = json!(c);
                    format!("insert[{k}].count = {c}")
                }
                4 => {
                    let c = *rng.pick(&[1_000_000u64, 5000, 0]);
                    ins.as_object_mut().map(|m| m.remove("rate"));
                    ins["keep"] = json!(c);
                    format!("insert[{k}].keep = {c}")
                }
                5 => {
                    let s = *rng.pick(&[1e-30, 1e3, 5.9, 1e-3]);
                    ins["size"] = json!(s);
                    format!("insert[{k}].size = {s:e}")
                }
                6 => {
                    let a = *rng.pick(&[1e3, 1e6, 1.0]);
                    ins["aspect"] = json!(a);
                    ins["shape"] = json!("ellipse");
                    format!("insert[{k}] ellipses of aspect {a:e}")
                }
                7 => {
                    let r = *rng.pick(&[1e-30, 1e-300, 1e30]);
                    ins["retry"] = json!(r);
                    format!("insert[{k}].retry = {r:e}")
                }
                8 => {
                    let a = *rng.pick(&[1_000_000_000u64, 1, 0]);
                    ins["attempts"] = json!(a);
                    format!("insert[{k}].attempts = {a}")
                }
                _ => {
                    let v = *rng.pick(&SPEEDS);
                    ins["velocity"] = json!([0.0, -v]);
                    format!("insert[{k}].velocity = [0, {:e}]", -v)
                }
            }
        }
        // Insertion given to a scene that has none.
        9 => {
            let region = *rng.pick(&[
                [-2.0, 2.0, 5.0, 8.0],
                [0.5, 3.0, 0.5, 3.0],
                [-50.0, -40.0, -50.0, -40.0],
            ]);
            case["insert"] = json!([{"region": region, "rate": 2e4, "count": 30, "size": 0.3}]);
            format!("insert added over {region:?}")
        }
        // Outflow.
        10 | 11 => {
            let region = *rng.pick(&[
                [-1e9, 1e9, -1e9, 1e9],
                [-6.0, 6.0, -20.0, -5.0],
                [-1.0, 1.0, 0.0, 50.0],
                [0.0, 5.0, 0.0, 5.0],
                [1.0, 1.0, 1.0, 1.0],
            ]);
            case["outflow"] = json!([{"region": region}]);
            format!("outflow over {region:?}")
        }
        // Materials.
        12 if case["materials"]
            .as_object()
            .is_some_and(|m| !m.is_empty() && m.values().all(Value::is_object)) =>
        {
            let names: Vec<String> = case["materials"]
                .as_object()
                .map(|m| m.keys().cloned().collect())
                .unwrap_or_default();
            let name = rng.pick(&names).clone();
            let (key, val) = *rng.pick(&[
                ("density", 1e-40),
                ("density", 1e40),
                ("kn_over_rho_g", 1e30),
                ("kn", 1e30),
                ("friction", 1e6),
                ("restitution", 1e-300),
                ("restitution", 1.0),
                ("young", 1e9),
            ]);
            case["materials"][name.as_str()][key] = json!(val);
            format!("materials.{name}.{key} = {val:e}")
        }
        12 if case["contact"].is_object() => {
            let k = *rng.pick(&["kn_over_rho_g", "kn", "friction", "restitution"]);
            let v = *rng.pick(&[1e30, 1e-30, 1e12]);
            case["contact"][k] = json!(v);
            format!("contact.{k} = {v:e}")
        }
        // Gravity.
        13 => {
            let g = *rng.pick(&[
                [0.0, -9.81],
                [0.0, -1e10],
                [1e6, 0.0],
                [0.0, 1e-300],
                [0.0, 0.0],
            ]);
            case["gravity"] = json!(g);
            format!("gravity = {g:?}")
        }
        // The audit's threshold and the output cadence.
        14 => {
            let (k, v) = rng
                .pick(&[
                    ("energy_audit", json!(1e-300)),
                    ("energy_audit", json!(1e300)),
                    ("energy_audit", json!(0)),
                    ("output_every", json!(1)),
                    ("output_every", json!(u64::MAX)),
                    ("quiescence", json!(1e300)),
                ])
                .clone();
            let d = format!("{k} = {v}");
            case[k] = v;
            d
        }
        _ => generic(rng, case, text),
    }
}

/// One mutant: its base, the mutations, the file's text, and whether it is relaxed.
struct Mutant {
    k: usize,
    base: String,
    what: Vec<String>,
    text: String,
    case: Value,
    relax: bool,
    extra: Vec<&'static str>,
}

fn make_mutant(seed: u64, k: usize, bases: &[Base]) -> Mutant {
    let mut rng = Rng::for_mutant(seed, k);
    let base = rng.pick(bases);
    let mut case = base.case.clone();
    let mut text_subs = Vec::new();
    let n = match rng.below(10) {
        0..=5 => 1,
        6..=8 => 2,
        _ => 3,
    };
    let what: Vec<String> = (0..n)
        .map(|_| {
            if rng.below(3) < 2 {
                featured(&mut rng, &mut case, &mut text_subs)
            } else {
                generic(&mut rng, &mut case, &mut text_subs)
            }
        })
        .collect();
    let mut text = serde_json::to_string_pretty(&case).unwrap_or_default();
    for (from, to) in &text_subs {
        text = text.replacen(from.as_str(), to, 1);
    }
    let relax = base.relax && rng.below(2) == 0;
    let extra = match rng.below(8) {
        // (Frames every 500 steps: a mutant with `output_every` 1 would write thousands.)
        0 => vec!["--vtk-every", "500"],
        1 => vec!["--dump"],
        2 => vec!["--analysis", "--contacts"],
        _ => vec![],
    };
    Mutant {
        k,
        base: base.name.clone(),
        what,
        text,
        case,
        relax: relax && extra.is_empty(),
        extra,
    }
}

// ----------------------------------------------------------------------------------------------
// Running and classifying
// ----------------------------------------------------------------------------------------------

/// Address space a run may take (a run that asks for terabytes is refused memory and aborts,
/// which counts as a crash, rather than taking the machine).
const MEMORY_CAP: u64 = 8 << 30;

struct Outcome {
    code: Option<i32>,
    timed_out: bool,
    stderr: String,
    seconds: f64,
}

fn run_bounded(exe: &Path, args: &[String], timeout: Duration) -> Result<Outcome, String> {
    let mut cmd = Command::new(exe);
    cmd.args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        // SAFETY: setrlimit is async-signal-safe; nothing else runs between fork and exec.
        unsafe {
            cmd.pre_exec(|| {
                let lim = libc::rlimit {
                    rlim_cur: MEMORY_CAP as libc::rlim_t,
                    rlim_max: MEMORY_CAP as libc::rlim_t,
                };
                libc::setrlimit(libc::RLIMIT_AS, &lim);
                Ok(())
            });
        }
    }
    let start = Instant::now();
    let mut child = cmd.spawn().map_err(|e| format!("{}: {e}", exe.display()))?;
    // Read stderr on a thread so that a chatty run never blocks on a full pipe.
    let mut pipe = child.stderr.take();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        if let Some(p) = pipe.as_mut() {
            let _ = std::io::Read::read_to_string(p, &mut s);
        }
        s
    });
    loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            let stderr = reader.join().unwrap_or_default();
            return Ok(Outcome {
                code: status.code(),
                timed_out: false,
                stderr,
                seconds: start.elapsed().as_secs_f64(),
            });
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            let stderr = reader.join().unwrap_or_default();
            return Ok(Outcome {
                code: None,
                timed_out: true,
                stderr,
                seconds: start.elapsed().as_secs_f64(),
            });
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn all_finite(v: &Value) -> bool {
    match v {
        Value::Number(n) => n.as_f64().is_some_and(f64::is_finite),
        Value::Array(a) => a.iter().all(all_finite),
        Value::Object(m) => m.values().all(all_finite),
        _ => false,
    }
}

/// A CSV file as its header and rows (fields as text).
fn read_csv(path: &Path) -> Option<(Vec<String>, Vec<Vec<String>>)> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut lines = text.lines();
    let header: Vec<String> = lines.next()?.split(',').map(str::to_string).collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    Some((header, rows))
}

fn col(header: &[String], name: &str) -> Option<usize> {
    header.iter().position(|h| h == name)
}

/// The largest bounding radius of a case's bodies (circles, ellipses, rectangles; `None` when
/// another shape is present).
fn max_bound(bodies: &[Value]) -> Option<f64> {
    let mut m = 0.0f64;
    for b in bodies {
        let s = &b["shape"];
        let r = match s["type"].as_str()? {
            "circle" => s["r"].as_f64()?,
            "ellipse" => s["a"].as_f64()?.max(s["b"].as_f64()?),
            "rectangle" => 0.5 * s["w"].as_f64()?.hypot(s["h"].as_f64()?),
            _ => return None,
        };
        m = m.max(r);
    }
    Some(m)
}

/// The first overlap at the start of a scene of circles (a pair, or a circle and a half-plane
/// or segment wall), brute force with the nearest periodic image; `None` when there is none, or
/// when a body is not a circle. Pairs of fixed or prescribed bodies, and such a body and a wall,
/// have no contact and are left out.
fn initial_overlap(case: &Value) -> Option<String> {
    let bodies = case["bodies"].as_array()?;
    let mut disks = Vec::new();
    for b in bodies {
        if b["shape"]["type"] != "circle" {
            return None;
        }
        let moved = b["fixed"] == true || b["prescribed"] == true;
        disks.push((
            b["position"][0].as_f64()?,
            b["position"][1].as_f64()?,
            b["shape"]["r"].as_f64()?,
            moved,
        ));
    }
    let (lx, ly, py) = match cell_size(case) {
        Some((lx, ly)) => (lx, ly, case["cell"]["periodic"] == "xy"),
        None => (f64::INFINITY, f64::INFINITY, false),
    };
    let near = |mut d: f64, l: f64| {
        if l.is_finite() {
            d -= (d / l).round() * l;
        }
        d
    };
    // (A margin for the rounding of a contact's depth: a pile's resting overlaps are 1e-4 of a
    // radius, a duplicated body's its whole diameter.)
    for (i, a) in disks.iter().enumerate() {
        for (j, b) in disks.iter().enumerate().skip(i + 1) {
            if a.3 && b.3 {
                continue;
            }
            let dx = near(b.0 - a.0, lx);
            let dy = if py { near(b.1 - a.1, ly) } else { b.1 - a.1 };
            let depth = a.2 + b.2 - dx.hypot(dy);
            if depth > 1e-6 * a.2.min(b.2) {
                return Some(format!("bodies {i} and {j} overlap by {depth:e}"));
            }
        }
    }
    for (k, w) in case["walls"].as_array().into_iter().flatten().enumerate() {
        for (i, a) in disks.iter().enumerate() {
            if a.3 {
                continue;
            }
            let dist = if let Some(seg) = w.get("segment") {
                let (x0, y0, x1, y1) = (
                    seg[0][0].as_f64()?,
                    seg[0][1].as_f64()?,
                    seg[1][0].as_f64()?,
                    seg[1][1].as_f64()?,
                );
                let (ex, ey) = (x1 - x0, y1 - y0);
                let t = (((a.0 - x0) * ex + (a.1 - y0) * ey) / (ex * ex + ey * ey)).clamp(0.0, 1.0);
                (a.0 - x0 - t * ex).hypot(a.1 - y0 - t * ey)
            } else {
                let (px, py, nx, ny) = (
                    w["point"][0].as_f64()?,
                    w["point"][1].as_f64()?,
                    w["normal"][0].as_f64()?,
                    w["normal"][1].as_f64()?,
                );
                ((a.0 - px) * nx + (a.1 - py) * ny) / nx.hypot(ny)
            };
            let depth = a.2 - dist;
            if depth > 1e-6 * a.2 {
                return Some(format!("body {i} and wall {k} overlap by {depth:e}"));
            }
        }
    }
    None
}

/// The checks of a run that exited 0; `Err` says what is silently wrong.
fn silent_checks(m: &Mutant, dir: &Path) -> Result<(), String> {
    let summary_text = std::fs::read_to_string(dir.join("summary.json"))
        .map_err(|e| format!("exit 0 and no summary.json: {e}"))?;
    let s: Value = serde_json::from_str(&summary_text).map_err(|e| format!("summary.json: {e}"))?;
    let status = s["status"].as_str().unwrap_or("");
    if !["completed", "at_rest", "max_steps"].contains(&status) {
        return Err(format!("exit 0 with status `{status}`"));
    }
    if !s["error"].is_null() {
        return Err(format!("exit 0 with error {}", s["error"]));
    }
    if !all_finite(&s["energies"]) || !all_finite(&s["final"]) {
        return Err("exit 0 with a non-finite energy or final state in summary.json".into());
    }
    let warnings: Vec<String> = s["warnings"]
        .as_array()
        .map(|w| {
            w.iter()
                .filter_map(|x| x.as_str().map(str::to_string))
                .collect()
        })
        .unwrap_or_default();
    // The energy account against the scale of the energy that moved (kinetic, elastic,
    // dissipated, the boundary work, the initial energy less the final potential), with the
    // audit's threshold; rounding of the totals allowed.
    let e = &s["energies"];
    let f = |k: &str| e[k].as_f64().unwrap_or(0.0);
    let u = f("unaccounted");
    let scale = f("kinetic")
        .abs()
        .max(f("elastic").abs())
        .max(f("dissipated").abs())
        .max(f("walls_work").abs());
    // The audit's scale is K₀ + E₀ + max (P₀ − P) + max W, at least E_total,0 − P_end (its
    // gravity term is at least P₀ − P_end): a lower bound of it.
    let scale = scale.max(f("initial_total") - f("potential"));
    let threshold = m.case["energy_audit"].as_f64().unwrap_or(0.01).max(0.01);
    let rounding = 1e-9 * (f("initial_total").abs() + f("final_total").abs());
    // The audit judges a run from its first output frame on (before it, the energy in motion is
    // next to nothing: src/run/audit.rs); a shorter run is not judged here either.
    let every = m.case["output_every"].as_u64().unwrap_or(100);
    if s["steps"].as_u64().unwrap_or(0) >= every
        && u.abs() > threshold * scale + rounding
        && !warnings.iter().any(|w| w.contains("unaccounted"))
    {
        return Err(format!(
            "energy account off by {u:e} erg against a scale of {scale:e} erg (ratio {:.3e}), \
             no `unaccounted` warning",
            u.abs() / scale.max(f64::MIN_POSITIVE)
        ));
    }
    // Overlaps at the start are warned of (circles, half-plane and segment walls; a case, not a
    // state, whose contacts overlap by design).
    if m.case.get("state").is_none()
        && let Some(d) = initial_overlap(&m.case)
        && !warnings.iter().any(|w| w.contains("overlap"))
    {
        return Err(format!("{d} at the start, no warning"));
    }
    // Every number of the trajectory finite; bodies inside a periodic cell.
    let (th, rows) = read_csv(&dir.join("trajectory.csv")).ok_or("exit 0 and no trajectory.csv")?;
    for r in &rows {
        for (h, v) in th.iter().zip(r) {
            if !v.is_empty() && !v.parse::<f64>().is_ok_and(f64::is_finite) {
                return Err(format!("trajectory.csv: {h} = {v}"));
            }
        }
    }
    let periodic = m.case["cell"]["periodic"].as_str();
    if let Some(p) = periodic {
        let (ch, crows) = read_csv(&dir.join("cell.csv")).ok_or("no cell.csv")?;
        let (cs, clx, cly) = (
            col(&ch, "step").ok_or("cell.csv: no step")?,
            col(&ch, "lx").ok_or("cell.csv: no lx")?,
            col(&ch, "ly").ok_or("cell.csv: no ly")?,
        );
        let mut sizes = std::collections::HashMap::new();
        let mut min_ly = f64::INFINITY;
        for r in &crows {
            let step = r.get(cs).cloned().unwrap_or_default();
            let lx: f64 = r.get(clx).and_then(|v| v.parse().ok()).unwrap_or(f64::NAN);
            let ly: f64 = r.get(cly).and_then(|v| v.parse().ok()).unwrap_or(f64::NAN);
            if !lx.is_finite() || !ly.is_finite() {
                return Err(format!("cell.csv: step {step}: lx = {lx}, ly = {ly}"));
            }
            min_ly = min_ly.min(ly);
            sizes.insert(step, (lx, ly));
        }
        let (ts, tx, ty, tb) = (
            col(&th, "step").ok_or("trajectory.csv: no step")?,
            col(&th, "x").ok_or("trajectory.csv: no x")?,
            col(&th, "y").ok_or("trajectory.csv: no y")?,
            col(&th, "body").ok_or("trajectory.csv: no body")?,
        );
        for r in &rows {
            let Some(&(lx, ly)) = sizes.get(&r[ts]) else {
                return Err(format!("cell.csv has no row for step {}", r[ts]));
            };
            let x: f64 = r[tx].parse().unwrap_or(f64::NAN);
            let y: f64 = r[ty].parse().unwrap_or(f64::NAN);
            let inside_x = (0.0..lx).contains(&x);
            let inside_y = p != "xy" || (0.0..ly).contains(&y);
            if !inside_x || !inside_y {
                return Err(format!(
                    "step {}: body {} at ({x}, {y}) outside the cell [0, {lx}) × [0, {ly})",
                    r[ts], r[tb]
                ));
            }
        }
        // Under imposed pressure, the cell never below twice a pair's contact reach (two
        // bounding diameters): below it a pair meets two images and only one is modelled.
        if m.case["cell"]["pressure"].is_number()
            && let Some(bodies) = m.case["bodies"].as_array()
            && let Some(b) = max_bound(bodies)
            && !m.case["insert"].is_array()
            && min_ly < 4.0 * b * (1.0 - 1e-12)
        {
            return Err(format!(
                "the cell's height reached {min_ly} cm, below twice a pair's reach (4 × {b} cm)"
            ));
        }
    }
    // Inserters that placed nothing of what was due, with no warning.
    if let Some(ins) = m.case["insert"].as_array() {
        let (ih, irows) = read_csv(&dir.join("inserted.csv")).ok_or("no inserted.csv")?;
        let ci = col(&ih, "insert").ok_or("inserted.csv: no insert")?;
        let t = s["time"].as_f64().unwrap_or(0.0);
        for (k, i) in ins.iter().enumerate() {
            let start = i["start"].as_f64().unwrap_or(0.0);
            let due = match (i["rate"].as_f64(), i["count"].as_f64(), i["keep"].as_f64()) {
                (Some(rate), count, _) => {
                    let n = ((t - start) * rate).floor();
                    count.map_or(n, |c| n.min(c))
                }
                (None, Some(c), None) => c,
                (None, count, Some(keep)) => count.map_or(keep, |c| keep.min(c)),
                _ => 0.0,
            };
            let placed = irows
                .iter()
                .filter(|r| r.get(ci).is_some_and(|v| *v == k.to_string()))
                .count();
            // A restart's inserter that placed bodies before the state was written.
            let before = m.case["state"]["flow"]["inserters"][k]["inserted"]
                .as_u64()
                .unwrap_or(0);
            if t >= start
                && due >= 1.0
                && placed == 0
                && before == 0
                && !warnings.iter().any(|w| w.contains(&format!("insert[{k}]")))
            {
                return Err(format!(
                    "insert[{k}] placed no body of {due} due by t = {t}, no warning"
                ));
            }
        }
    }
    // The state written for a restart: every number finite.
    let state = std::fs::read_to_string(dir.join("state.json"))
        .map_err(|e| format!("exit 0 and no state.json: {e}"))?;
    let sv: Value = serde_json::from_str(&state).map_err(|e| format!("state.json: {e}"))?;
    if !numbers_finite(&sv) {
        return Err("state.json holds a null where a number belongs".into());
    }
    Ok(())
}

/// Every number finite: no `null` in an array (a non-finite number is written as `null`) but in
/// a contact's `warm` start (four single-precision numbers, `null` for NaN by design: an unused
/// slot of the cache), and no `null` value of an object but for optional keys.
fn numbers_finite(v: &Value) -> bool {
    match v {
        Value::Number(n) => n.as_f64().is_some_and(f64::is_finite),
        Value::Array(a) => a.iter().all(numbers_finite),
        Value::Object(m) => m.iter().all(|(k, x)| {
            x.is_null()
                || (k == "warm"
                    && x.as_array()
                        .is_some_and(|a| a.iter().all(|y| y.is_null() || numbers_finite(y))))
                || numbers_finite(x)
        }),
        Value::Null => false,
        _ => true,
    }
}

/// The checks of a relaxation that exited 0.
fn silent_checks_relax(m: &Mutant, dir: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(dir.join("relax.json"))
        .map_err(|e| format!("exit 0 and no relax.json: {e}"))?;
    let r: Value = serde_json::from_str(&text).map_err(|e| format!("relax.json: {e}"))?;
    let status = r["status"].as_str().unwrap_or("");
    if !["relaxed", "unjammed"].contains(&status) {
        return Err(format!("relax exit 0 with status `{status}`"));
    }
    for k in ["residual", "potential", "elastic"] {
        if !r[k].as_f64().is_some_and(f64::is_finite) {
            return Err(format!("relax.json: {k} = {}", r[k]));
        }
    }
    if status == "relaxed" && r["residual"].as_f64() > r["tolerance"].as_f64() {
        return Err(format!(
            "relaxed with residual {} above tolerance {}",
            r["residual"], r["tolerance"]
        ));
    }
    let state = std::fs::read_to_string(dir.join("state.json"))
        .map_err(|e| format!("exit 0 and no state.json: {e}"))?;
    let sv: Value = serde_json::from_str(&state).map_err(|e| format!("state.json: {e}"))?;
    if !numbers_finite(&sv) {
        return Err("state.json holds a null where a number belongs".into());
    }
    if let (Some((lx, ly)), Some(bodies)) = (cell_size(&sv), sv["bodies"].as_array()) {
        let xy = sv["cell"]["periodic"] == "xy";
        for (i, b) in bodies.iter().enumerate() {
            let x = b["position"][0].as_f64().unwrap_or(f64::NAN);
            let y = b["position"][1].as_f64().unwrap_or(f64::NAN);
            if !(0.0..lx).contains(&x) || (xy && !(0.0..ly).contains(&y)) {
                return Err(format!(
                    "relaxed state: bodies[{i}] at ({x}, {y}) outside the cell [0, {lx}) × [0, {ly})"
                ));
            }
        }
    }
    let _ = m;
    Ok(())
}

/// Classifies one outcome: (class, why).
fn classify(m: &Mutant, o: &Outcome, dir: &Path) -> (&'static str, String) {
    let tail = |s: &str| -> String {
        let lines: Vec<&str> = s.lines().collect();
        lines[lines.len().saturating_sub(3)..].join(" | ")
    };
    if o.timed_out {
        return ("HANG", format!("no exit in {:.0} s", o.seconds));
    }
    if o.stderr.contains("panicked") || o.code == Some(101) {
        return ("PANIC", tail(&o.stderr));
    }
    let Some(code) = o.code else {
        return ("PANIC", format!("killed by a signal: {}", tail(&o.stderr)));
    };
    match code {
        0 => {
            let r = if m.relax {
                silent_checks_relax(m, dir)
            } else {
                silent_checks(m, dir)
            };
            match r {
                Ok(()) => ("ok", String::new()),
                Err(e) => ("SILENT", e),
            }
        }
        2 => {
            // A file that is not JSON (a number literal beyond float64, 1e999) cannot name a
            // field: the reader names the line and column instead.
            let located = o.stderr.contains("malformed JSON") && o.stderr.contains(" at line ");
            if !o.stderr.contains("field `") && !located {
                (
                    "BAD_EXIT",
                    format!("refused naming no field: {}", tail(&o.stderr)),
                )
            } else if std::fs::read_dir(dir).is_ok_and(|mut d| d.next().is_some()) {
                (
                    "BAD_EXIT",
                    format!("refused but wrote output: {}", tail(&o.stderr)),
                )
            } else {
                ("refused", tail(&o.stderr))
            }
        }
        1 => {
            let file = if m.relax {
                "relax.json"
            } else {
                "summary.json"
            };
            let status = std::fs::read_to_string(dir.join(file))
                .ok()
                .and_then(|t| serde_json::from_str::<Value>(&t).ok())
                .and_then(|v| v["status"].as_str().map(str::to_string))
                .unwrap_or_default();
            let documented: &[&str] = if m.relax {
                &["stalled", "max_iterations"]
            } else {
                &["blowup", "io_error"]
            };
            if documented.contains(&status.as_str()) && !o.stderr.trim().is_empty() {
                ("detected", format!("{status}: {}", tail(&o.stderr)))
            } else {
                (
                    "BAD_EXIT",
                    format!("exit 1 with status `{status}`: {}", tail(&o.stderr)),
                )
            }
        }
        other => ("BAD_EXIT", format!("exit {other}: {}", tail(&o.stderr))),
    }
}

/// Runs a round; writes the report, the list of mutants and the failures into `opts.out`.
pub fn run(opts: &FuzzOptions, exe: &Path) -> Result<Report, String> {
    let out = &opts.out;
    let work = out.join("work");
    let failures_dir = out.join("failures");
    for d in [&work, &failures_dir] {
        let _ = std::fs::remove_dir_all(d);
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let bases = bases(&opts.root, exe, &work)?;
    let ks: Vec<usize> = match opts.only {
        Some(k) => vec![k],
        None => (0..opts.mutants).collect(),
    };
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let results: Results = Mutex::new(Vec::new());
    let start = Instant::now();
    let errors: Mutex<Vec<String>> = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..opts.jobs.max(1) {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&k) = ks.get(i) else { return };
                    if let Err(e) = one(opts, exe, &bases, k, &work, &failures_dir, &results) {
                        errors.lock().unwrap_or_else(|p| p.into_inner()).push(e);
                    }
                    let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                    if opts.progress && n.is_multiple_of(50) {
                        eprintln!(
                            "fuzz: {n}/{} mutants, {:.0} s",
                            ks.len(),
                            start.elapsed().as_secs_f64()
                        );
                    }
                }
            });
        }
    });
    let errors = errors.into_inner().unwrap_or_default();
    if let Some(e) = errors.first() {
        return Err(e.clone());
    }
    let mut results = results.into_inner().unwrap_or_default();
    results.sort_by_key(|r| r.0);
    let _ = std::fs::remove_dir_all(&work);
    // The list of every mutant.
    let mut csv = String::from("mutant,base,command,class,exit,seconds,mutations,why\n");
    let mut counts: BTreeMap<String, usize> = CLASSES.iter().map(|c| (c.to_string(), 0)).collect();
    let mut per_base: BTreeMap<String, BTreeMap<&'static str, usize>> = BTreeMap::new();
    let mut failures = Vec::new();
    for (k, base, class, why, secs, code, what) in &results {
        *counts.entry(class.to_string()).or_default() += 1;
        *per_base
            .entry(base.clone())
            .or_default()
            .entry(class)
            .or_default() += 1;
        let cmd = if what.starts_with("[relax]") {
            "relax"
        } else {
            "run"
        };
        csv.push_str(&format!(
            "{k},{base},{cmd},{class},{},{secs:.3},\"{}\",\"{}\"\n",
            code.map_or("-".into(), |c| c.to_string()),
            what.replace('"', "'"),
            why.replace('"', "'")
        ));
        if is_failure(class) {
            failures.push(format!("#{k} {base}: {class}: {what}: {why}"));
        }
    }
    std::fs::write(out.join("mutants.csv"), csv).map_err(|e| format!("{}: {e}", out.display()))?;
    let total = results.len();
    let mut md = format!(
        "Fuzzing round: {total} mutants, seed {}, --max-steps {}, timeout {} s, {:.0} s wall\n\n",
        opts.seed,
        opts.max_steps,
        opts.timeout.as_secs(),
        start.elapsed().as_secs_f64()
    );
    md.push_str("| base | total |");
    for c in CLASSES {
        md.push_str(&format!(" {c} |"));
    }
    md.push_str("\n|---|---:|");
    for _ in CLASSES {
        md.push_str("---:|");
    }
    md.push('\n');
    for (base, c) in &per_base {
        md.push_str(&format!("| {base} | {} |", c.values().sum::<usize>()));
        for class in CLASSES {
            md.push_str(&format!(" {} |", c.get(class).copied().unwrap_or(0)));
        }
        md.push('\n');
    }
    md.push_str(&format!("| **all** | **{total}** |"));
    for class in CLASSES {
        md.push_str(&format!(" **{}** |", counts[class]));
    }
    md.push('\n');
    if !failures.is_empty() {
        md.push_str("\nFailures (the mutated files are in failures/):\n\n");
        for f in &failures {
            md.push_str(&format!("- {f}\n"));
        }
    }
    std::fs::write(out.join("report.md"), &md).map_err(|e| format!("{}: {e}", out.display()))?;
    Ok(Report {
        counts,
        markdown: md,
        failures,
    })
}

type Results = Mutex<
    Vec<(
        usize,
        String,
        &'static str,
        String,
        f64,
        Option<i32>,
        String,
    )>,
>;

/// Makes, runs and classifies mutant `k`.
fn one(
    opts: &FuzzOptions,
    exe: &Path,
    bases: &[Base],
    k: usize,
    work: &Path,
    failures_dir: &Path,
    results: &Results,
) -> Result<(), String> {
    let m = make_mutant(opts.seed, k, bases);
    let file = work.join(format!("m{k}.json"));
    std::fs::write(&file, &m.text).map_err(|e| format!("{}: {e}", file.display()))?;
    let dir = work.join(format!("m{k}"));
    let steps = opts.max_steps.to_string();
    let mut args: Vec<String> = if m.relax {
        vec![
            "relax".into(),
            path_str(&file)?.into(),
            "--out".into(),
            path_str(&dir)?.into(),
            "--max-iterations".into(),
            steps,
        ]
    } else {
        vec![
            "run".into(),
            path_str(&file)?.into(),
            "--out".into(),
            path_str(&dir)?.into(),
            "--max-steps".into(),
            steps,
        ]
    };
    args.extend(["--quiet".into(), "--threads".into(), "1".into()]);
    args.extend(m.extra.iter().map(|s| s.to_string()));
    let o = run_bounded(exe, &args, opts.timeout)?;
    let (class, why) = classify(&m, &o, &dir);
    let what = format!(
        "{}{}{}",
        if m.relax { "[relax] " } else { "" },
        m.what.join("; "),
        if m.extra.is_empty() {
            String::new()
        } else {
            format!(" [{}]", m.extra.join(" "))
        }
    );
    if is_failure(class) {
        let stem = failures_dir.join(format!("m{k}-{class}"));
        std::fs::write(stem.with_extension("json"), &m.text)
            .map_err(|e| format!("{}: {e}", stem.display()))?;
        let note = format!(
            "mutant {k} of seed {}: base {}\nmutations: {what}\ncommand: dem2d {}\nexit: {:?}, {:.2} s\nclass: {class}\nwhy: {why}\n\nstderr:\n{}\n",
            opts.seed,
            m.base,
            args.join(" "),
            o.code,
            o.seconds,
            o.stderr
        );
        std::fs::write(stem.with_extension("txt"), note)
            .map_err(|e| format!("{}: {e}", stem.display()))?;
    }
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_file(&file);
    results
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .push((m.k, m.base, class, why, o.seconds, o.code, what));
    Ok(())
}

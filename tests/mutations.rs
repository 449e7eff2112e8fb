//! A seeded property test over mutated case files: every good case (and a generated pile),
//! with one to three fields replaced by extremes, wrong types, scaled values, removed, or joined
//! by an unknown or a duplicate key, must end in exactly one of three ways:
//! - exit 0 with a summary whose status is `completed`, `at_rest` or `max_steps` and whose
//!   energies and final state are all finite numbers (never `null`);
//! - exit 1 with status `blowup`, the error naming the step and the body;
//! - exit 2 with a message naming the field (`field \`…\``), and nothing written.
//!
//! Every fourth run writes VTK frames too. Never a panic, never another exit code, never a hang: every run is bounded by `--max-steps`
//! and killed after [`TIMEOUT`]. The seed and the mutation are printed with any failure, so a
//! failure can be replayed (`MUTATION_SEED=… cargo test --release --test mutations`).
//!
//! The suite's run tries [`MUTATIONS`] mutated cases, run side by side on every core; the long
//! form, `DEM2D_LONG_TESTS=1` (or `MUTATION_COUNT=N`), tries [`LONG_MUTATIONS`] — the same seed,
//! so its first cases are the short form's.

use serde_json::{Map, Value, json};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;

/// Mutated cases run per test (`MUTATION_COUNT` overrides it, for a longer search).
const MUTATIONS: usize = 300;
/// Mutated cases of the long form (`DEM2D_LONG_TESTS=1`).
const LONG_MUTATIONS: usize = 1000;
/// Longest run allowed (the runs take milliseconds; this is the hang detector).
const TIMEOUT: Duration = Duration::from_secs(60);
/// Steps per run.
const MAX_STEPS: &str = "2000";

/// SplitMix64 (the generator of `dem2d generate`): the same seed, the same mutations.
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
        (self.next() % n as u64) as usize
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Every path to a value in `v` (object keys and array indices), the root excluded.
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
            // Long arrays (bodies of a pile): a few elements are enough.
            for (i, x) in a.iter().enumerate().take(4) {
                prefix.push(json!(i));
                out.push(prefix.clone());
                paths(x, prefix, out);
                prefix.pop();
            }
        }
        _ => {}
    }
}

fn at_mut<'a>(v: &'a mut Value, path: &[Value]) -> &'a mut Value {
    path.iter().fold(v, |v, k| match k {
        Value::String(s) => &mut v[s.as_str()],
        _ => &mut v[k.as_u64().unwrap() as usize],
    })
}

/// Numbers a mutation may put in: zeros, signs, subnormals, the edges of the accepted ranges and
/// beyond, float64's extremes.
const EXTREMES: [f64; 20] = [
    0.0,
    -0.0,
    -1.0,
    1.0,
    2.5,
    5e-324,
    1e-320,
    1e-200,
    1e-41,
    1e-40,
    1e-12,
    1e8,
    -1e8,
    1e12,
    1e40,
    1e41,
    1e160,
    1e200,
    1e308,
    -1.7976931348623157e308,
];
const FACTORS: [f64; 10] = [1e-30, 1e-6, 1e-3, 0.5, 2.0, 10.0, 1e3, 1e6, 1e30, -1.0];

/// Applies one mutation; returns its description. Some mutations are textual (a duplicate key,
/// a NaN literal) and are applied to `text` after serialisation: they are returned in `textual`.
fn mutate(rng: &mut Rng, case: &mut Value, textual: &mut Vec<(String, String)>) -> String {
    let mut all = Vec::new();
    paths(case, &mut Vec::new(), &mut all);
    // Mostly numbers: changing a number's value is what reaches the dynamics.
    let numbers: Vec<Vec<Value>> = all
        .iter()
        .filter(|p| at_mut(&mut case.clone(), p).is_number())
        .cloned()
        .collect();
    let path = if rng.below(4) > 0 && !numbers.is_empty() {
        rng.pick(&numbers).clone()
    } else {
        rng.pick(&all).clone()
    };
    let name = path
        .iter()
        .map(|k| k.to_string().trim_matches('"').to_string())
        .collect::<Vec<_>>()
        .join(".");
    let target = at_mut(case, &path);
    match rng.below(12) {
        0..=2 => {
            let x = *rng.pick(&EXTREMES);
            *target = json!(x);
            format!("{name} = {x:e}")
        }
        3..=6 => match target.as_f64() {
            Some(x) => {
                let f = *rng.pick(&FACTORS);
                *target = json!(x * f);
                format!("{name} ×= {f:e}")
            }
            None => {
                *target = json!(1e-3);
                format!("{name} = 1e-3")
            }
        },
        7 => {
            let replacements = [
                json!("x"),
                Value::Null,
                json!(true),
                json!([]),
                json!({}),
                json!([1]),
                json!([1, 2, 3]),
                json!(-7),
            ];
            let r = rng.pick(&replacements).clone();
            let d = format!("{name} = {r}");
            *target = r;
            d
        }
        8 => {
            // Remove the field (or the array element).
            let (last, parent) = path.split_last().unwrap();
            let parent = at_mut(case, parent);
            match last {
                Value::String(k) => {
                    parent.as_object_mut().unwrap().remove(k);
                }
                i => {
                    parent
                        .as_array_mut()
                        .unwrap()
                        .remove(i.as_u64().unwrap() as usize);
                }
            }
            format!("remove {name}")
        }
        9 => {
            // An unknown key next to it (in the innermost object).
            let obj = if target.is_object() {
                target
            } else {
                at_mut(case, &path[..path.len() - 1])
            };
            if let Some(m) = obj.as_object_mut() {
                m.insert("colour".into(), json!("red"));
                format!("unknown key beside {name}")
            } else {
                *obj = json!(0);
                format!("{name}'s parent = 0")
            }
        }
        10 => {
            // A duplicate key: the field given again with another value, before the original.
            if let (Some(Value::String(k)), Some(x)) = (path.last(), target.as_f64()) {
                let marker = format!("\"{k}\": {}", json!(x));
                textual.push((marker.clone(), format!("\"{k}\": -1, {marker}")));
                format!("duplicate {name}")
            } else {
                *target = json!(-1e-3);
                format!("{name} = -1e-3")
            }
        }
        _ => {
            // A non-finite literal in place of a number.
            let lit = *rng.pick(&["NaN", "Infinity", "-Infinity"]);
            *target = json!("\u{2}MARK");
            textual.push(("\"\\u0002MARK\"".into(), lit.into()));
            format!("{name} = {lit}")
        }
    }
}

fn base_cases() -> Vec<(String, Value)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let mut out = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        if path.extension().is_none_or(|e| e != "json") || name.contains("10k") {
            continue;
        }
        let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        if v.is_object() {
            out.push((name, v));
        }
    }
    // A small generated pile (walls on three sides, many contacts).
    let pile = Command::new(common::bin())
        .args([
            "generate", "--shape", "ellipses", "--n", "24", "--seed", "3",
        ])
        .output()
        .unwrap();
    assert!(pile.status.success());
    out.push((
        "pile24".into(),
        serde_json::from_slice(&pile.stdout).unwrap(),
    ));
    // The user guide's pouring example (insertion of three shapes, an outflow region, fixed
    // grains): bodies that come and go, which the shipped cases do not exercise (issue 41:
    // `--vtk` panicked on every run that inserts bodies).
    let page = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/src/reference/case-file.md"),
    )
    .unwrap();
    let pouring = page
        .split("```json\n")
        .skip(1)
        .map(|b| b.split("```").next().unwrap())
        .find(|b| b.contains("\"name\": \"pouring\""))
        .expect("the guide's pouring example");
    out.push(("pouring".into(), serde_json::from_str(pouring).unwrap()));
    out.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(out.len() >= 8, "{} base cases", out.len());
    out
}

/// Runs dem2d, killing it after [`TIMEOUT`]; `None` on a timeout.
fn run_bounded(args: &[&str]) -> Option<(i32, String)> {
    let mut child = Command::new(common::bin())
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
            return Some((status.code().unwrap_or(-1), err));
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(2));
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

/// Checks one run's outcome; `Err` says what is wrong.
fn check(code: i32, err: &str, out: &Path) -> Result<&'static str, String> {
    if err.contains("panicked") {
        return Err(format!("panic: {err}"));
    }
    let summary = || -> Result<Value, String> {
        let text = std::fs::read_to_string(out.join("summary.json"))
            .map_err(|e| format!("no summary: {e}"))?;
        serde_json::from_str(&text).map_err(|e| format!("summary: {e}"))
    };
    match code {
        0 => {
            let s = summary()?;
            let status = s["status"].as_str().unwrap_or("");
            if !["completed", "at_rest", "max_steps"].contains(&status) {
                return Err(format!("exit 0 with status {status}"));
            }
            if !all_finite(&s["energies"]) || !all_finite(&s["final"]) {
                return Err(format!(
                    "exit 0 with non-finite results: {} {}",
                    s["energies"], s["final"]
                ));
            }
            if !s["error"].is_null() {
                return Err(format!("exit 0 with error {}", s["error"]));
            }
            Ok("ran")
        }
        1 => {
            let s = summary()?;
            if s["status"] != "blowup" {
                return Err(format!("exit 1 with status {}: {err}", s["status"]));
            }
            if !(err.contains("blow-up at step") && err.contains("body")) {
                return Err(format!("blow-up without step and body: {err}"));
            }
            Ok("blew up")
        }
        2 => {
            if !err.contains("field `") {
                return Err(format!("refused without naming a field: {err}"));
            }
            if out.exists() {
                return Err("refused but wrote output".into());
            }
            Ok("refused")
        }
        other => Err(format!("exit code {other}: {err}")),
    }
}

#[test]
fn mutated_cases_run_blow_up_or_are_refused_with_the_field_named() {
    let seed: u64 = std::env::var("MUTATION_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(11);
    let long = std::env::var_os("DEM2D_LONG_TESTS").is_some_and(|v| v != "0");
    let count: usize = std::env::var("MUTATION_COUNT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(if long { LONG_MUTATIONS } else { MUTATIONS });
    let mut rng = Rng(seed);
    let bases = base_cases();
    let scratch = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("mutations");
    let _ = std::fs::remove_dir_all(&scratch);
    std::fs::create_dir_all(&scratch).unwrap();
    // The mutated cases, drawn in order from the seed (so that a seed names the same cases
    // however they are run), then run side by side.
    let mut jobs = Vec::with_capacity(count);
    for k in 0..count {
        let (base, case) = rng.pick(&bases);
        let mut case = case.clone();
        let mut textual = Vec::new();
        let n = 1 + rng.below(3).saturating_sub(1); // one mutation mostly, sometimes two
        let what: Vec<String> = (0..n)
            .map(|_| mutate(&mut rng, &mut case, &mut textual))
            .collect();
        let mut text = serde_json::to_string_pretty(&case).unwrap();
        for (from, to) in &textual {
            text = text.replacen(from.as_str(), to, 1);
        }
        let file = scratch.join(format!("m{k}.json"));
        std::fs::write(&file, &text).unwrap();
        let out = scratch.join(format!("m{k}"));
        let vtk = if k.is_multiple_of(4) {
            " (--vtk-every 500)"
        } else {
            ""
        };
        let label = format!("seed {seed}, #{k}: {base}{vtk}: {}", what.join("; "));
        jobs.push((label, file, out));
    }
    let start = Instant::now();
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results: Vec<(usize, Result<&'static str, String>)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some((label, file, out)) = jobs.get(k) else {
                            return done;
                        };
                        let mut args = vec![
                            "run",
                            file.to_str().unwrap(),
                            "--out",
                            out.to_str().unwrap(),
                            "--max-steps",
                            MAX_STEPS,
                            "--quiet",
                            "--threads",
                            "1",
                        ];
                        // Every fourth with VTK frames (every 500 steps): the writer meets
                        // what the mutations make too.
                        if k.is_multiple_of(4) {
                            args.extend(["--vtk-every", "500"]);
                        }
                        let result = run_bounded(&args);
                        done.push((
                            k,
                            match result {
                                None => Err(format!("{label}: no answer in {TIMEOUT:?} (a hang)")),
                                Some((code, err)) => {
                                    check(code, &err, out).map_err(|e| format!("{label}: {e}"))
                                }
                            },
                        ));
                    }
                })
            })
            .collect();
        let mut all: Vec<_> = handles
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect();
        all.sort_by_key(|(k, _)| *k);
        all
    });
    let mut tally: Map<String, Value> = Map::new();
    let mut failures = Vec::new();
    for (_, result) in results {
        match result {
            Ok(kind) => {
                let c = tally.entry(kind).or_insert(json!(0));
                *c = json!(c.as_u64().unwrap() + 1);
            }
            Err(e) => failures.push(e),
        }
    }
    eprintln!(
        "{count} mutated cases in {:.1} s: {}",
        start.elapsed().as_secs_f64(),
        Value::Object(tally.clone())
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The generator must exercise all three outcomes, or the test proves little.
    for kind in ["ran", "blew up", "refused"] {
        assert!(tally.contains_key(kind), "no mutation {kind}: {tally:?}");
    }
}

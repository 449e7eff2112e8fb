//! Exact restart (issue 14): every run ends by writing `state.json`, a case file holding the
//! full state, and `dem2d run RUN/state.json` continues the run. A → B then B → C gives the
//! trajectory of A → C byte for byte — for a pile with open frictional contacts, rolling springs
//! and ellipse pairs (whose warm starts decide the last bits of their crossings), on one thread
//! and on two; after `--max-steps` and after SIGTERM; and the state file's numbers read back as
//! the same bits, extreme ones included. A bad state file is refused naming the field.
// TEMPORARY (lead, merge of restart-14 in progress): the command-line tests below are still
// being written on the branch; remove this line at the next merge.
#![allow(unused_imports, dead_code)]

use dem2d::dynamics::World;
use dem2d::scene::CaseFile;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_dem2d")
}

fn dem2d(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(bin()).args(args).output().expect("run dem2d");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("restart")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A pile in a box: 24 bodies — circles, ellipses and two rectangles — dropped onto a floor
/// between two walls, frictional (μ = 0.5) with EPSD rolling springs, so that by step 9000 it
/// is a heap of lasting contacts, sliding and sticking, between ellipses (warm starts), circles
/// and the walls.
fn pile_case(duration: f64) -> String {
    let mut bodies = Vec::new();
    for row in 0..6 {
        for col in 0..4 {
            let k = row * 4 + col;
            let x = 1.3 + 2.4 * col as f64 + 0.15 * (row % 2) as f64;
            let y = 0.8 + 1.3 * row as f64;
            let shape = match k % 5 {
                0 | 3 => r#"{"type": "circle", "r": 0.5}"#.to_string(),
                4 if k == 9 || k == 19 => r#"{"type": "rectangle", "w": 0.9, "h": 0.6}"#.into(),
                _ => r#"{"type": "ellipse", "a": 0.6, "b": 0.4}"#.to_string(),
            };
            bodies.push(format!(
                r#"{{"shape": {shape}, "position": [{x}, {y}], "angle": {}, "omega": {}}}"#,
                0.37 * k as f64,
                (k as f64 - 11.0) * 0.9
            ));
        }
    }
    format!(
        r#"{{"version": 1, "name": "restart_pile", "units": "cm", "gravity": [0, -980],
  "dt": 2e-5, "duration": {duration}, "output_every": 250,
  "contact": {{"model": "linear", "kn_over_rho_g": 36400, "ks_over_rho_g": 30000,
               "eta_n_over_rho_g": 10, "friction": 0.5,
               "rolling_model": "epsd", "rolling_friction": 0.05, "rolling_damping": 0.3}},
  "walls": [{{"point": [0, 0], "normal": [0, 1]}},
            {{"point": [0, 0], "normal": [1, 0], "friction": 0.3}},
            {{"point": [10, 0], "normal": [-1, 0]}}],
  "bodies": [{}]}}"#,
        bodies.join(",\n    ")
    )
}

/// The world's full state as text (Debug prints every float in its shortest round-trip form:
/// equal text, equal bits).
fn full_state(w: &World) -> String {
    format!("{:?}", w.restart_state())
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

/// A → C in one go against A → B, `state.json` written and read back, B → C: the same full
/// state (bodies, forces, every slot's history and warm start, energies) at C, bit for bit.
fn library_round_trip(threads: usize) {
    let (b_step, c_step) = (9000u64, 13000u64);
    let text = pile_case(0.3);
    let file = CaseFile::from_json(&text).unwrap();
    in_pool(threads, || {
        let mut whole = file.build_world();
        for _ in 0..c_step {
            whole.step().unwrap();
        }
        let mut first = file.build_world();
        for _ in 0..b_step {
            first.step().unwrap();
        }
        let state = first.restart_state();
        let active: Vec<_> = state.slots.iter().filter(|s| s.slot.active).collect();
        assert!(active.len() > 20, "a heap of contacts: {}", active.len());
        assert!(active.iter().any(|s| s.slot.shear != 0.0), "shear springs");
        assert!(active.iter().any(|s| s.rolling != 0.0), "rolling springs");
        assert!(active.iter().any(|s| !s.cache.is_empty()), "warm starts");
        let written = dem2d::output::state::state_text(
            &file.value,
            file.case.duration,
            &state,
            &file.case.bodies,
            "max_steps",
        );
        let read = CaseFile::from_json(&written).unwrap();
        assert_eq!(
            format!("{:?}", read.restart.as_ref().unwrap()),
            format!("{state:?}"),
            "the state reads back as written"
        );
        let mut resumed = read.build_world();
        assert_eq!(full_state(&resumed), full_state(&first));
        for _ in b_step..c_step {
            resumed.step().unwrap();
        }
        assert_eq!(resumed.step, c_step);
        assert_eq!(full_state(&resumed), full_state(&whole));
    });
}

#[test]
fn a_resumed_world_steps_to_the_same_bits_on_one_and_two_threads() {
    library_round_trip(1);
    library_round_trip(2);
}

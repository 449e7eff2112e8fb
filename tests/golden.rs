//! Golden trajectories: the exact bits that the paper's cases (under both normal-force laws), P
//! Fig. 3's throws with rolling resistance (CDT and EPSD), small generated piles (disks and
//! ellipses, both laws, one and two threads), and scenes with moving walls and rolling
//! resistance (the biaxial test, the repose column; one and two threads) end in, stored in
//! `tests/golden/trajectories.json`. Any change to the dynamics that moves a single bit fails here:
//! a refactor must keep them; a deliberate change of the physics regenerates them and says why
//! in its commit:
//!
//! ```sh
//! DEM2D_REGENERATE_GOLDEN=1 cargo test --release --test golden
//! ```

use dem2d::contact_law::{NormalForce, RollingModel, RollingPart};
use dem2d::dynamics::World;
use dem2d::run::Simulation;
use dem2d::scene::Case;
use dem2d::scene::generate::{PileShape, PileSpec};
use serde_json::{Map, Value, json};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every body's state, as the hexadecimal bits of x, y, θ, vx, vy, ω, and the energies' bits.
fn state_bits(w: &World) -> Value {
    let b = &w.bodies;
    let hex = |v: f64| format!("{:016x}", v.to_bits());
    let bodies: Vec<Value> = (0..b.len())
        .map(|k| {
            let s = &b.state[k];
            json!([
                hex(s.pose.position.x),
                hex(s.pose.position.y),
                hex(s.pose.angle()),
                hex(s.vel.x),
                hex(s.vel.y),
                hex(s.omega)
            ])
        })
        .collect();
    let e = &w.energies;
    json!({
        "step": w.step,
        "bodies": bodies,
        "energies": [hex(e.kinetic), hex(e.potential), hex(e.elastic), hex(e.dissipated)],
    })
}

/// FNV-1a over the state's bits (for the piles, whose full state would be large).
fn hash(v: &Value) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in v.to_string().bytes() {
        h = (h ^ byte as u64).wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

fn run(case: &Case, steps: u64, threads: usize) -> Value {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    pool.install(|| {
        let mut w = case.build_world();
        // Without the blow-up watch, and a blow-up ends the run: the stored states are where
        // the steps got to (a scene past its stable step included).
        let _ = Simulation::new(&mut w)
            .without_watch()
            .for_steps(steps)
            .run();
        state_bits(&w)
    })
}

#[test]
fn trajectories_are_bit_identical_to_the_stored_ones() {
    let mut got = Map::new();
    // The paper's cases, 20 000 steps each (or to their end), under each law.
    for name in [
        "drop_rebound_mu01",
        "drop_rebound_mu05",
        "throw_circle",
        "throw_ellipse",
        "throw_square",
        "settle3_dt1e-5",
        "settle3_dt1e-4",
    ] {
        let text = std::fs::read_to_string(root().join("cases").join(format!("{name}.json")))
            .expect("case file");
        let case = Case::from_json(&text).expect("case");
        for nf in [NormalForce::Depth, NormalForce::Area] {
            let c = case.clone().with_normal_force(nf);
            let steps = c.steps().min(20_000);
            got.insert(format!("{name}/{}", nf.as_str()), run(&c, steps, 1));
        }
    }
    // Small piles in their first contacts (300 steps from 0.3 s in), on one and two threads.
    for shape in [PileShape::Disks, PileShape::Ellipses] {
        for nf in [NormalForce::Depth, NormalForce::Area] {
            let mut spec = PileSpec::new(shape, 400, 7);
            spec.normal_force = nf;
            let mut case = Case::from_json(&spec.case_json()).expect("pile");
            for b in &mut case.bodies {
                b.velocity.y -= 150.0; // into contact within a few hundred steps
            }
            for threads in [1, 2] {
                let v = run(&case, 3000, threads);
                got.insert(
                    format!("{}/{}/{threads} threads", spec.name(), nf.as_str()),
                    json!({"step": v["step"], "hash": hash(&v)}),
                );
            }
        }
    }
    // Rolling resistance: P Fig. 3's throws with each model (their own law, the depth law).
    for name in ["throw_circle", "throw_ellipse"] {
        let text = std::fs::read_to_string(root().join("cases").join(format!("{name}.json")))
            .expect("case file");
        let case = Case::from_json(&text).expect("case");
        for model in [RollingModel::Cdt, RollingModel::Epsd] {
            let c = case.clone().map_contacts(|c| {
                c.with_rolling(Some(RollingPart {
                    model,
                    friction: 0.05,
                    damping: None,
                }))
            });
            got.insert(
                format!("{name}/{} 0.05", model.as_str()),
                run(&c, 20_000, 1),
            );
        }
    }
    // Moving walls (two at a constant velocity, two servos) and rolling resistance in many-body
    // scenes, on one and two threads.
    for file in [
        "biaxial_disks.json",
        "repose/epsd_mu_r_0.1.json",
        "repose/cdt_mu_r_0.1.json",
    ] {
        let text = std::fs::read_to_string(root().join("cases").join(file)).expect("case file");
        let case = Case::from_json(&text).expect("case");
        for threads in [1, 2] {
            let v = run(&case, 3000, threads);
            got.insert(
                format!("{file}/{threads} threads"),
                json!({"step": v["step"], "hash": hash(&v)}),
            );
        }
    }
    let path = root().join("tests/golden/trajectories.json");
    let got = Value::Object(got);
    if std::env::var_os("DEM2D_REGENERATE_GOLDEN").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, serde_json::to_string_pretty(&got).unwrap() + "\n").unwrap();
        eprintln!("wrote {}", path.display());
        return;
    }
    let want: Value = serde_json::from_str(
        &std::fs::read_to_string(&path)
            .expect("tests/golden/trajectories.json (regenerate: see the module doc)"),
    )
    .expect("golden JSON");
    let mut differ = Vec::new();
    for (k, v) in got.as_object().unwrap() {
        if want.get(k) != Some(v) {
            differ.push(k.clone());
        }
    }
    for k in want.as_object().unwrap().keys() {
        if got.get(k).is_none() {
            differ.push(format!("{k} (missing)"));
        }
    }
    assert!(
        differ.is_empty(),
        "trajectories differ from tests/golden/trajectories.json: {differ:?} (if the physics changed on purpose, regenerate: see the module doc)"
    );
    // The many-body scenes: two threads give the bits of one.
    for (k, v) in got.as_object().unwrap() {
        if let Some(base) = k.strip_suffix("/2 threads") {
            assert_eq!(Some(v), got.get(format!("{base}/1 threads")), "{base}");
        }
    }
}

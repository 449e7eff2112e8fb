//! A biaxial test in a box of four walls: two walls at a prescribed strain rate, two holding the
//! confining stress.
//!
//! `dem2d study biaxial [--write-cases]`
//!
//! 1. **Compaction**: 400 disks (radii 0.8–1.2 cm, ρ = 2.65, friction 0.5, P's stiffness,
//!    dashpots for e = 0.5), no gravity, start on a loose lattice in a box whose four walls
//!    are servos holding σ_c = 1e5 dyn/cm² (each over the span between its two neighbours),
//!    until the box stops shrinking.
//! 2. **Shear**: the top and bottom walls move towards each other at `v = ε̇ H₀/2` each
//!    (ε̇ = 0.05 /s: inertial number `I = ε̇ d √(ρ/σ_c)` ≈ 5e-4, quasi-static), the side walls
//!    keep σ_c. Printed every 1 % of axial strain: the axial stress σ₁ (the top wall's load over
//!    the box's width), the side walls' σ₃ and their error against σ_c, the volumetric strain.
//!
//! With `--write-cases` the shear stage is written as `cases/biaxial_disks.json` (the compacted
//! assembly, the moving walls), an ordinary case.

use dem2d::dynamics::{BodyInit, World};
use dem2d::geometry::{Shape, Vec2};
use dem2d::output::progress::CommandProgress;
use dem2d::run::{RunError, Simulation};
use dem2d::scene::Case;
use dem2d::scene::generate::{Xorshift, case_text_from};
use dem2d::scene::servo_box::box_walls;
use serde_json::{Value, json};

const SIGMA_C: f64 = 1e5;
const STRAIN_RATE: f64 = 0.05;
const N_SIDE: usize = 20;

fn round6(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

/// The case: bodies, four walls (bottom, top, left, right) with their motions.
fn case_json(name: &str, bodies: &[BodyInit], box_: [f64; 4], motions: [Value; 4]) -> String {
    let kn = 36400.0 * 2.65 * 980.0;
    let eta = 2.0
        * dem2d::contact_law::damping_ratio_linear(0.5)
        * (2.65 * std::f64::consts::PI * kn).sqrt();
    let walls = box_walls(box_, motions);
    let head: [(&str, Value); 10] = [
        ("version", json!(1)),
        ("name", json!(name)),
        (
            "description",
            json!(format!(
                "Biaxial test (dem2d study biaxial): {} disks compacted under σ_c = {SIGMA_C:e} \
                 dyn/cm² by four servo walls; the top and bottom walls then approach each other at \
                 an axial strain rate of {STRAIN_RATE} /s while the side walls hold σ_c.",
                bodies.len()
            )),
        ),
        ("units", json!("cm")),
        ("gravity", json!([0.0, 0.0])),
        ("dt", json!(1e-5)),
        ("duration", json!(2.0)),
        ("output_every", json!(1000)),
        (
            "contact",
            json!({"model": "linear", "normal_force": "area", "kn": kn, "eta_n": round6(eta),
                   "friction": 0.5}),
        ),
        ("walls", Value::Array(walls)),
    ];
    let bodies: Vec<BodyInit> = bodies
        .iter()
        .map(|b| BodyInit {
            position: b.position.map(round6),
            ..*b
        })
        .collect();
    case_text_from(&head, &bodies)
}

fn servo(a: usize, b: usize) -> Value {
    json!({"servo": {"stress": SIGMA_C, "span": [a, b], "max_speed": 20.0}})
}

/// Axial stress, lateral stress, width and height of the servo box (see
/// [`super::biaxial_shape::wall_state`]).
fn stresses(w: &World) -> (f64, f64, f64, f64) {
    let (width, height, axial, lateral) = super::biaxial_shape::wall_state(w);
    (axial, lateral, width, height)
}

pub fn run(write: bool) -> Result<String, RunError> {
    // A loose lattice, 2.6 cm apart, radii uniform in 0.8–1.2 (a fixed sequence).
    let mut rng = Xorshift(7);
    let mut uniform = || rng.uniform();
    let s = 2.6;
    let bodies: Vec<BodyInit> = (0..N_SIDE * N_SIDE)
        .map(|k| BodyInit {
            material: 0,
            prescribed: false,
            shape: Shape::Circle {
                r: round6(0.8 + 0.4 * uniform()),
            },
            position: Vec2::new(
                s * ((k % N_SIDE) as f64 + 0.5),
                s * ((k / N_SIDE) as f64 + 0.5),
            ),
            angle: 0.0,
            velocity: Vec2::zeros(),
            omega: 0.0,
            density: 2.65,
        })
        .collect();
    let side = s * N_SIDE as f64;
    let compaction = case_json(
        "biaxial_compaction",
        &bodies,
        [0.0, side, 0.0, side],
        [servo(2, 3), servo(2, 3), servo(0, 1), servo(0, 1)],
    );
    let case = Case::from_json(&compaction).unwrap();
    let mut w = case.build_world();
    let mut last = f64::INFINITY;
    let mut lines = CommandProgress::new(case.name.clone());
    let mut sim = Simulation::new(&mut w).observe(&mut lines).for_steps(5000);
    loop {
        sim.run()?;
        let w = sim.world();
        let (ax, lat, width, height) = stresses(w);
        eprintln!(
            "compaction t = {:.2}: {width:.3} × {height:.3} cm, σ_axial {ax:.0}, σ_lateral {lat:.0}",
            w.time
        );
        if (last - width * height).abs() < 1e-5 * width * height || w.time > 3.0 {
            break;
        }
        last = width * height;
    }
    // The shear stage, from the compacted state.
    let compacted: Vec<BodyInit> = (0..w.bodies.len())
        .map(|k| BodyInit {
            position: w.bodies.state[k].pose.position,
            ..bodies[k]
        })
        .collect();
    let (_, _, width0, height0) = stresses(&w);
    let box_ = super::biaxial_shape::box_of(&w);
    let v = round6(0.5 * STRAIN_RATE * height0);
    let shear = case_json(
        "biaxial_disks",
        &compacted,
        box_,
        [
            json!({"velocity": [0.0, v]}),
            json!({"velocity": [0.0, -v]}),
            servo(0, 1),
            servo(0, 1),
        ],
    );
    if write {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/biaxial_disks.json");
        super::put_case(&path, &shear);
    }
    let case = Case::from_json(&shear).unwrap();
    let mut w = case.build_world();
    let area0 = width0 * height0;
    let mut md = super::Table::new(
        "| axial strain | σ₁ (dyn/cm²) | σ₃ (dyn/cm²) | σ₃/σ_c − 1 | (σ₁ − σ₃)/(σ₁ + σ₃) | volumetric strain |\n\
         |---:|---:|---:|---:|---:|---:|",
    );
    let steps_per_percent = (0.01 / STRAIN_RATE / case.dt).round() as u64;
    super::biaxial_shape::run_shear(&mut w, &case, steps_per_percent, |w, ax, lat| {
        let (_, _, width, height) = stresses(w);
        let strain = 1.0 - height / height0;
        md.row(format!(
            "| {strain:.3} | {ax:.4e} | {lat:.4e} | {:+.2e} | {:.3} | {:.4} |",
            lat / SIGMA_C - 1.0,
            (ax - lat) / (ax + lat),
            1.0 - width * height / area0
        ));
    })?;
    Ok(md.text())
}

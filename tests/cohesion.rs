//! Cohesion (`contact.cohesion` c, dyn/cm²): a pull `c ℓ` on the overlap chord ℓ, the gradient
//! of `−c A` (`contact_law::cohesion`), against closed forms.
//!
//! A disk of radius r against a straight wall at depth δ (linear spring k on δ): the chord is
//! `ℓ(δ) = 2√(δ(2r − δ))` and the net force pushing the disk out of the wall is
//!
//! `F(δ) = k δ − 2c √(δ(2r − δ))`   (1)
//!
//! - **At rest under a weight W pressing it in** `F(δ) = W`: squaring
//!   `(kδ − W)² = 4c² δ(2r − δ)` gives `(k² + 4c²) δ² − 2(kW + 4c²r) δ + W² = 0`, whose root with
//!   `kδ ≥ W` is `δ_rest = [kW + 4c²r + 2c √(4c²r² + 2kWr − W²)]/(k² + 4c²)`   (2)
//!   (the discriminant `(kW + 4c²r)² − (k² + 4c²)W² = 4c²(4c²r² + 2kWr − W²)`).
//! - **Pull-off**: F is least where `F′ = k − 2c(r − δ)/√(δ(2r − δ)) = 0`; with `u = r − δ`,
//!   `k²(r² − u²) = 4c²u²`, so `δ* = r − kr/√(k² + 4c²)` and the largest pull the contact holds
//!   against is `P = −F(δ*) = r(√(k² + 4c²) − k)`   (3).
//!   A disk hanging under a ceiling by its weight W stays iff `W ≤ P`; it then rests at the
//!   root of `F(δ) = −W` beyond δ*: `(k² + 4c²)δ² + 2(kW − 4c²r)δ + W² = 0`, the larger root
//!   `δ_hang = [4c²r − kW + 2c√(4c²r² − 2kWr − W²)]/(k² + 4c²)`   (4).
//! - **Energy**: the pull is the gradient of `−cA`, so an undamped, frictionless collision gives
//!   back its kinetic energy: the error is the integrator's, second order in Δt.

use dem2d::contact_law::{
    CohesionPart, ContactSpec, LinearDamping, LinearDashpots, NormalForce, Scaled,
};
use dem2d::dynamics::{Boundary, World};
use dem2d::geometry::{Shape, Vec2, Wall};
use dem2d::run::Simulation;
use std::f64::consts::PI;

mod common;
use common::{body, dem2d, floor, scratch, worst_energy_error};

const G: f64 = 980.0;
const KN: f64 = 36400.0 * G; // P's stiffness, ρ = 1
const C: f64 = 3e5; // dyn/cm²: the pull-off force (3) is 1.6 weights of a unit disk

fn spec(nf: NormalForce, c: f64, restitution: Option<f64>) -> ContactSpec {
    ContactSpec::linear(
        Scaled::Absolute(KN),
        Scaled::Absolute(KN),
        match restitution {
            Some(e) => LinearDamping::Restitution(e),
            None => LinearDamping::Dashpots {
                eta_n: Scaled::Absolute(0.0),
                eta_s: Scaled::Absolute(0.0),
            },
        },
        0.0,
    )
    .with_normal_force(nf)
    .with_cohesion(Some(CohesionPart { cohesion: c }))
}

/// (2): the rest depth of a disk pressed into a wall by W.
fn rest_depth(k: f64, c: f64, r: f64, w: f64) -> f64 {
    let root = (4.0 * c * c * r * r + 2.0 * k * w * r - w * w).sqrt();
    (k * w + 4.0 * c * c * r + 2.0 * c * root) / (k * k + 4.0 * c * c)
}

/// (3): the depth of the largest pull and the pull-off force.
fn pull_off(k: f64, c: f64, r: f64) -> (f64, f64) {
    let s = (k * k + 4.0 * c * c).sqrt();
    (r - k * r / s, r * (s - k))
}

/// (4): the depth of a disk hanging by the weight W ≤ P.
fn hang_depth(k: f64, c: f64, r: f64, w: f64) -> f64 {
    let root = (4.0 * c * c * r * r - 2.0 * k * w * r - w * w).sqrt();
    (4.0 * c * c * r - k * w + 2.0 * c * root) / (k * k + 4.0 * c * c)
}

/// The depth of body 0 against the wall y = 0 (a disk of radius r): `r − |y|`.
fn depth_of(w: &World, r: f64) -> f64 {
    r - w.bodies.state[0].pose.position.y.abs()
}

#[test]
fn a_cohesive_disk_rests_on_a_floor_at_the_closed_form_overlap() {
    let r = 1.0;
    let m = PI * r * r;
    let want = rest_depth(KN, C, r, m * G);
    let without = m * G / KN;
    for nf in [NormalForce::Depth, NormalForce::Area] {
        let s = spec(nf, C, Some(0.5));
        // Released touching the floor, at rest.
        let b = body(Shape::Circle { r }, Vec2::new(0.0, r), 0.0);
        let mut w = World::new(&[b], vec![floor(s)], Vec2::new(0.0, -G), s, 1e-5);
        Simulation::new(&mut w).until_time(0.2).run().unwrap();
        let got = depth_of(&w, r);
        eprintln!(
            "{nf:?}: rest depth {got:.12e} cm, closed form (2) {want:.12e} (rel {:.1e}); \
             without cohesion mg/k = {without:.6e}",
            got / want - 1.0
        );
        assert!((got / want - 1.0).abs() < 1e-6, "{got} vs {want}");
        assert!(w.bodies.state[0].vel.norm() < 1e-9);
    }
}

/// A disk hanging by cohesion under the ceiling y = 0 (free side down), gravity `g` down,
/// released at rest at the depth of the largest pull δ*.
fn hanging(g: f64, r: f64) -> World {
    let s = spec(NormalForce::Area, C, Some(0.5));
    let (d_star, _) = pull_off(KN, C, r);
    let ceiling = Boundary::new(Wall::new(Vec2::zeros(), -Vec2::y()).unwrap(), s);
    let b = body(Shape::Circle { r }, Vec2::new(0.0, -(r - d_star)), 0.0);
    World::new(&[b], vec![ceiling], Vec2::new(0.0, -g), s, 1e-5)
}

#[test]
fn a_hanging_disk_leaves_the_ceiling_at_the_pull_off_force() {
    let r = 1.0;
    let m = PI * r * r;
    let (d_star, p) = pull_off(KN, C, r);
    eprintln!(
        "pull-off force (3) P = {p:.6} dyn at δ* = {d_star:.6e} cm; weight m·980 = {:.1}",
        m * G
    );
    // Its weight 0.1 % below P: it holds, at the closed form's depth (4).
    let w_below = 0.999 * p;
    let mut w = hanging(w_below / m, r);
    Simulation::new(&mut w).until_time(0.3).run().unwrap();
    let got = depth_of(&w, r);
    let want = hang_depth(KN, C, r, w_below);
    eprintln!(
        "W = 0.999 P: hangs at depth {got:.12e} cm, closed form (4) {want:.12e} (rel {:.1e})",
        got / want - 1.0
    );
    assert!((got / want - 1.0).abs() < 1e-6, "{got} vs {want}");
    // 0.1 % above P: it leaves, and falls free.
    let mut w = hanging(1.001 * p / m, r);
    Simulation::new(&mut w).until_time(0.3).run().unwrap();
    let y = w.bodies.state[0].pose.position.y;
    eprintln!("W = 1.001 P: centre at y = {y:.4} cm after 0.3 s (it touched at y = -{r})");
    assert!(y < -2.0 * r, "still hanging at y = {y}");
    assert!(w.contacts.is_empty());
}

/// Two bodies colliding head-on in free space, undamped and frictionless, with cohesion:
/// their relative kinetic energy before and after, and the largest |ΔE/E| along the way
/// (`phase` shifts the first body's start within a step).
fn collision(shape: Shape, nf: NormalForce, dt: f64, phase: f64) -> (f64, f64, f64) {
    let s = spec(nf, 1e6, None);
    let mut a = body(shape, Vec2::new(-0.003 * phase, 0.0), 0.3);
    let mut b = body(shape, Vec2::new(3.5, 0.4), 1.1);
    a.velocity = Vec2::new(10.0, 0.0);
    b.velocity = Vec2::new(-10.0, 0.0);
    let mut w = World::new(&[a, b], vec![], Vec2::zeros(), s, dt);
    let k0 = w.energies.kinetic;
    let worst = worst_energy_error(Simulation::new(&mut w).until_time(0.2));
    assert_eq!(w.contacts.len(), 0, "still in contact");
    (k0, w.energies.kinetic, worst)
}

#[test]
fn a_cohesive_collision_gives_back_its_kinetic_energy_under_the_area_law() {
    // The law conserves energy (the force is −∇(W − cA): checked to rounding below, in
    // `force_is_minus_the_gradient_of_the_stored_energy`); what is left is the integrator's
    // error. The pull `c ℓ ∝ √δ` at the onset of a contact has an unbounded derivative, so the
    // step that straddles the onset errs by O(F(v Δt) · v Δt) = O(Δt^{3/2}): the energy error
    // of a cohesive impact converges at order 3/2, not Verlet's 2 (which the spring alone
    // keeps: `tests/area_law.rs`).
    for (name, shape) in [
        ("disks r = 1", Shape::Circle { r: 1.0 }),
        ("ellipses 1.5 × 1", Shape::Ellipse { a: 1.5, b: 1.0 }),
    ] {
        let dts = [4e-6, 2e-6, 1e-6];
        // Averaged over eight phases of the impact's onset within a step.
        let run = |dt: f64| {
            let (mut dk, mut de) = (0.0, 0.0);
            for k in 0..8 {
                let (k0, k1, worst) = collision(shape, NormalForce::Area, dt, k as f64 / 8.0);
                dk += (k1 / k0 - 1.0).abs() / 8.0;
                de += worst / 8.0;
            }
            (dk, de)
        };
        let got: Vec<(f64, f64)> = dts.iter().map(|&dt| run(dt)).collect();
        let order = |e: [f64; 3]| (e[0] / e[2]).log2() / 2.0;
        let (ok, oe) = (
            order([got[0].0, got[1].0, got[2].0]),
            order([got[0].1, got[1].1, got[2].1]),
        );
        eprintln!(
            "{name}: |K_after/K_before − 1| at Δt = 4e-6, 2e-6, 1e-6 s: {:.1e} {:.1e} {:.1e} \
             (order {ok:.2}); max |ΔE/E| {:.1e} {:.1e} {:.1e} (order {oe:.2})",
            got[0].0, got[1].0, got[2].0, got[0].1, got[1].1, got[2].1
        );
        assert!(got[2].0 < 1e-4 && got[2].1 < 1e-4, "{name}: {got:?}");
        assert!(ok > 1.4 && oe > 1.4, "{name}: orders {ok}, {oe}");
    }
}

/// Force and couple on the last body, and the stored energy, of a world of `bodies` and
/// `walls` under `s` (as the step computes them, at rest).
fn evaluated(
    bodies: &[dem2d::dynamics::BodyInit],
    walls: &[Wall],
    s: ContactSpec,
) -> (Vec2, f64, f64) {
    let walls = walls.iter().map(|&w| Boundary::new(w, s)).collect();
    let w = World::new(bodies, walls, Vec2::zeros(), s, 1e-6);
    assert_eq!(w.contacts.len(), 1, "one contact");
    let k = bodies.len() - 1;
    (w.bodies.force[k], w.bodies.torque[k], w.energies.elastic)
}

#[test]
fn force_is_minus_the_gradient_of_the_stored_energy() {
    // F = −∂E/∂x and M = −∂E/∂θ for the last body, E the stored energy (spring + −cA), by a
    // fourth-order central difference: the pull and −cA come from the kernels' chord and area,
    // computed apart. A rectangle on a wall is a Winkler contact (its force at the overlap's
    // centroid): the pull's lever from the chord midpoint goes with it as a couple.
    let fd4 = |f: &dyn Fn(f64) -> f64, h: f64| {
        (-f(2.0 * h) + 8.0 * f(h) - 8.0 * f(-h) + f(-2.0 * h)) / (12.0 * h)
    };
    let floor = Wall::new(Vec2::zeros(), Vec2::y()).unwrap();
    let e = Shape::Ellipse { a: 1.5, b: 1.0 };
    let rect = Shape::Rectangle { w: 2.0, h: 1.0 };
    let disk = Shape::Circle { r: 1.0 };
    type Placed = Vec<(Shape, Vec2, f64)>;
    let cases: Vec<(&str, Placed, Vec<Wall>, NormalForce)> = vec![
        (
            "disk–disk, depth law",
            vec![
                (disk, Vec2::zeros(), 0.0),
                (Shape::Circle { r: 0.8 }, Vec2::new(1.7, 0.2), 0.0),
            ],
            vec![],
            NormalForce::Depth,
        ),
        (
            "disk–wall, depth law",
            vec![(disk, Vec2::new(0.3, 0.93), 0.0)],
            vec![floor],
            NormalForce::Depth,
        ),
        (
            "ellipse–ellipse, area law",
            vec![
                (e, Vec2::zeros(), 0.3),
                (Shape::Ellipse { a: 1.2, b: 0.7 }, Vec2::new(2.2, 0.5), 1.1),
            ],
            vec![],
            NormalForce::Area,
        ),
        (
            "ellipse–wall, area law",
            vec![(e, Vec2::new(0.0, 1.05), 0.4)],
            vec![floor],
            NormalForce::Area,
        ),
        (
            "rectangle–ellipse, area law",
            vec![(rect, Vec2::zeros(), 0.2), (e, Vec2::new(0.6, 1.35), 0.7)],
            vec![],
            NormalForce::Area,
        ),
        (
            "rectangle–rectangle, area law",
            vec![(rect, Vec2::zeros(), 0.2), (rect, Vec2::new(0.4, 1.0), 0.9)],
            vec![],
            NormalForce::Area,
        ),
        (
            "rectangle–wall (Winkler), area law",
            vec![(rect, Vec2::new(0.0, 0.43), 0.05)],
            vec![floor],
            NormalForce::Area,
        ),
        (
            "rectangle–wall (Winkler), depth law",
            vec![(rect, Vec2::new(0.0, 0.43), 0.05)],
            vec![floor],
            NormalForce::Depth,
        ),
    ];
    for (name, placed, walls, nf) in cases {
        // k_n = 1, c = 0.3: the pull is of the spring's size at these overlaps.
        let s = ContactSpec::linear(
            Scaled::Absolute(1.0),
            Scaled::Absolute(1.0),
            LinearDamping::Dashpots {
                eta_n: Scaled::Absolute(0.0),
                eta_s: Scaled::Absolute(0.0),
            },
            0.0,
        )
        .with_normal_force(nf)
        .with_cohesion(Some(CohesionPart { cohesion: 0.3 }));
        let at = |dx: f64, dy: f64, dth: f64| {
            let mut bodies: Vec<_> = placed.iter().map(|&(sh, p, a)| body(sh, p, a)).collect();
            let last = bodies.last_mut().unwrap();
            last.position += Vec2::new(dx, dy);
            last.angle += dth;
            evaluated(&bodies, &walls, s)
        };
        let (f, m, _) = at(0.0, 0.0, 0.0);
        let h = 1e-5;
        let want = Vec2::new(
            -fd4(&|d| at(d, 0.0, 0.0).2, h),
            -fd4(&|d| at(0.0, d, 0.0).2, h),
        );
        let want_m = -fd4(&|d| at(0.0, 0.0, d).2, h);
        let err = ((f - want).norm() + (m - want_m).abs()) / (f.norm() + m.abs());
        eprintln!(
            "{name}: F = ({:.6e}, {:.6e}), M = {m:.6e}; −∇E = ({:.6e}, {:.6e}), {want_m:.6e}; rel {err:.1e}",
            f.x, f.y, want.x, want.y
        );
        assert!(err < 1e-7, "{name}: {err}");
    }
}

#[test]
fn a_law_with_cohesion_does_not_take_the_linear_fast_path() {
    // The same linear law with constant dashpots: of the fast path's kind without cohesion,
    // not with it (its copies never ask for the chord and would drop the pull).
    let plain = common::linear(KN, 10.0, 0.3);
    let law = plain.resolve(&plain, 1.0, G);
    assert!(LinearDashpots::of(&law).is_some());
    let cohesive = plain.with_cohesion(Some(CohesionPart { cohesion: C }));
    let law = cohesive.resolve(&cohesive, 1.0, G);
    assert!(LinearDashpots::of(&law).is_none());
    assert_eq!(law.cohesion, Some(CohesionPart { cohesion: C }));
    assert!(law.needs().cohesion);
    // And a run with such a law feels the pull: a disk released touching a floor without
    // gravity is drawn in, to the depth where k δ = c ℓ(δ) ((2) with W = 0).
    let b = body(Shape::Circle { r: 1.0 }, Vec2::new(0.0, 1.0 - 1e-9), 0.0);
    let s = common::linear(KN, 2000.0, 0.0).with_cohesion(Some(CohesionPart { cohesion: C }));
    let mut w = World::new(&[b], vec![floor(s)], Vec2::zeros(), s, 1e-5);
    Simulation::new(&mut w).until_time(0.2).run().unwrap();
    let (got, want) = (depth_of(&w, 1.0), rest_depth(KN, C, 1.0, 0.0));
    eprintln!("no gravity: drawn in to δ = {got:.9e} (closed form {want:.9e})");
    assert!((got / want - 1.0).abs() < 1e-6, "{got} vs {want}");
}

/// A case of a disk on a floor with `contact` as its contact object and `walls` its walls.
fn case_text(contact: &str, walls: &str, extra: &str) -> String {
    format!(
        r#"{{ "version": 1, "name": "cohesion", "units": "cm", "gravity": [0, -980],
  "dt": 1e-5, "duration": 0.001, {extra}
  "contact": {contact},
  "walls": {walls},
  "bodies": [ {{ "shape": {{ "type": "circle", "r": 1 }}, "position": [0, 1] }} ] }}"#
    )
}

#[test]
fn bad_cohesion_is_refused_naming_the_field() {
    let dir = scratch("bad");
    let floor = r#"[ { "point": [0, 0], "normal": [0, 1] } ]"#;
    let drum = r#"[ { "drum": { "center": [0, 1], "radius": 5 } } ]"#;
    let linear = r#"{ "model": "linear", "kn": 3.6e7, "restitution": 0.5, "friction": 0"#;
    for (name, text, want) in [
        (
            "negative",
            case_text(&format!(r#"{linear}, "cohesion": -1 }}"#), floor, ""),
            "field `contact.cohesion`: must be zero or positive, got -1",
        ),
        (
            "text",
            case_text(&format!(r#"{linear}, "cohesion": "strong" }}"#), floor, ""),
            "field `contact.cohesion`",
        ),
        (
            "drum",
            case_text(&format!(r#"{linear}, "cohesion": 1e5 }}"#), drum, "").replace(
                r#"{ "type": "circle", "r": 1 }"#,
                r#"{ "type": "ellipse", "a": 1, "b": 0.5 }"#,
            ),
            "field `contact.cohesion`: cohesion is not available against a drum (walls[0]) for \
             bodies[0], of shape `ellipse`",
        ),
    ] {
        let path = dir.join(format!("{name}.json"));
        std::fs::write(&path, text).unwrap();
        let (code, _, err) = dem2d(&["run", path.to_str().unwrap()]);
        eprintln!("{name}: exit {code}: {}", err.trim());
        assert_eq!(code, 2, "{name}: {err}");
        assert!(err.contains(want), "{name}: {err}");
    }
    // A drum wall may switch it off for itself (and a disk needs no switch).
    let path = dir.join("drum_off.json");
    let drum_off = r#"[ { "drum": { "center": [0, 1], "radius": 5 }, "cohesion": 0 } ]"#;
    std::fs::write(
        &path,
        case_text(&format!(r#"{linear}, "cohesion": 1e5 }}"#), drum_off, ""),
    )
    .unwrap();
    let (code, _, err) = dem2d(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn cohesion_is_read_per_material_and_per_pair() {
    use dem2d::scene::Case;
    let text = r#"{ "version": 1, "name": "m", "units": "cm", "gravity": [0, -980],
  "dt": 1e-5, "duration": 0.001,
  "contact": { "model": "linear", "kn": 3.6e7, "restitution": 0.5, "friction": 0,
               "cohesion": 4e5 },
  "materials": { "a": { "cohesion": 1e5 }, "b": { "cohesion": 9e4 }, "dry": { "cohesion": 0 } },
  "pairs": [ { "materials": ["a", "dry"], "cohesion": 7e3 } ],
  "bodies": [
    { "shape": { "type": "circle", "r": 1 }, "position": [0, 1], "material": "a" },
    { "shape": { "type": "circle", "r": 1 }, "position": [3, 1], "material": "b" },
    { "shape": { "type": "circle", "r": 1 }, "position": [6, 1], "material": "dry" },
    { "shape": { "type": "circle", "r": 1 }, "position": [9, 1] } ] }"#;
    let case = Case::from_json(text).unwrap();
    let w = case.build_world();
    let c = |a: u16, b: u16| w.pairs.body_pair(a, b).spec.cohesion.map(|c| c.cohesion);
    // Materials: 0 the scene's, then a, b, dry.
    assert_eq!(c(0, 0), Some(4e5));
    assert_eq!(c(1, 1), Some(1e5));
    assert_eq!(c(1, 2), Some((1e5f64 * 9e4).sqrt())); // the geometric mean: 94868.3…
    assert_eq!(c(0, 1), Some(2e5)); // √(4e5 × 1e5)
    assert_eq!(c(2, 3), None); // dry has none
    assert_eq!(c(1, 3), Some(7e3)); // the pair's own
}

// ---------------------------------------------------------------------------------------------
// Against a drum and a segment wall (disks and clumps).
//
// - **Drum** (centre c, radius R) and a disk (radius r, centre at distance d from c, depth
//   `δ = d + r − R`): the overlap is the disk's part beyond the circle, `A = πr² − lens(r, R,
//   d)`, and `dA/dd = ℓ`, the chord through the two circles' crossings, which lie at
//   `x = (d² + R² − r²)/(2d)` from c on the line of centres, `ℓ = 2√(R² − x²)`. At rest on the
//   bottom of a still drum under a weight W: `k δ − c ℓ(δ) = W`   (5), solved below by
//   bisection from these formulas (not the kernel's).
// - **Segment**: over the face the half-plane's cap at the depth `r − h`; at an end E the cap
//   at the depth `r − |p − E|`: one potential `−c cap(r − dist(p, segment))`, continuously
//   differentiable, so a disk sliding past an end keeps its energy to the integrator's error.

/// A world from a case with `walls` and `bodies` under the linear law (k_n = `KN`, frictionless,
/// cohesion `c`, its `restitution`), gravity `g` down, step `dt`.
fn cohesive_world(walls: &str, bodies: &str, c: f64, restitution: f64, g: f64, dt: f64) -> World {
    let text = format!(
        r#"{{ "version": 1, "name": "cohesion", "gravity": [0, {}], "dt": {dt}, "duration": 10,
        "contact": {{ "model": "linear", "kn": {KN}, "ks": {KN}, "restitution": {restitution},
                      "friction": 0, "cohesion": {c} }},
        "walls": {walls}, "bodies": {bodies} }}"#,
        -g
    );
    dem2d::scene::Case::from_json(&text)
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .build_world()
}

/// A disk of radius `r` at `p` as a case's body.
fn disk_at(r: f64, p: Vec2) -> String {
    format!(
        r#"[ {{ "shape": {{ "type": "circle", "r": {r} }}, "position": [{}, {}] }} ]"#,
        p.x, p.y
    )
}

#[test]
fn against_a_drum_and_a_segment_the_force_is_minus_the_gradient_of_the_stored_energy() {
    // F = −∂E/∂x (and M = −∂E/∂θ for a clump) by a fourth-order central difference, E the
    // stored energy (½kδ² − cA), the pull from the kernels' chord: the drum's A = πr² − lens,
    // the segment's face cap and end cap.
    let fd4 = |f: &dyn Fn(f64) -> f64, h: f64| {
        (-f(2.0 * h) + 8.0 * f(h) - 8.0 * f(-h) + f(-2.0 * h)) / (12.0 * h)
    };
    let drum = r#"[ { "drum": { "center": [0.3, -0.2], "radius": 5 } } ]"#;
    let segment = r#"[ { "segment": [[-2, 0], [2, 0]] } ]"#;
    let clump = |p: Vec2, th: f64| {
        format!(
            r#"[ {{ "shape": {{ "type": "clump", "disks": [ {{ "center": [-0.4, 0], "r": 0.6 }},
                {{ "center": [0.5, 0.1], "r": 0.8 }} ] }}, "position": [{}, {}], "angle": {th} }} ]"#,
            p.x, p.y
        )
    };
    // The drum's centre plus (R − r + δ) along a direction: δ = 0.02 (r = 1, d = 4.02).
    let u = Vec2::new(0.6, -0.8);
    let in_drum = Vec2::new(0.3, -0.2) + u * 4.02;
    type Bodies = Box<dyn Fn(Vec2, f64) -> String>;
    let cases: Vec<(&str, &str, Vec2, Bodies)> = vec![
        ("disk–drum", drum, in_drum, Box::new(|p, _| disk_at(1.0, p))),
        (
            "clump–drum (one member beyond the circle)",
            drum,
            // Its second member (r = 0.8 at (0.5, 0.1)) 0.03 beyond: √(0.25 + (y + 0.1)²) = 4.23.
            Vec2::new(0.3, -0.2) + Vec2::new(0.0, -0.1 - (4.23f64 * 4.23 - 0.25).sqrt()),
            Box::new(clump),
        ),
        (
            "disk–segment face",
            segment,
            Vec2::new(0.5, 0.95),
            Box::new(|p, _| disk_at(1.0, p)),
        ),
        (
            "disk–segment end",
            segment,
            Vec2::new(2.3, 0.85),
            Box::new(|p, _| disk_at(1.0, p)),
        ),
        (
            "clump–segment end",
            segment,
            // Its second member at (2.3, 0.72), 0.02 into the end (2, 0); the first clear.
            Vec2::new(1.8, 0.62),
            Box::new(clump),
        ),
    ];
    for (name, walls, p0, bodies) in cases {
        let at = |dx: f64, dy: f64, dth: f64| {
            let w = cohesive_world(
                walls,
                &bodies(p0 + Vec2::new(dx, dy), dth),
                C,
                1.0,
                0.0,
                1e-6,
            );
            assert!(!w.contacts.is_empty(), "{name}: a contact");
            (w.bodies.force[0], w.bodies.torque[0], w.energies.elastic)
        };
        let (f, m, e) = at(0.0, 0.0, 0.0);
        let h = 1e-6;
        let want = Vec2::new(
            -fd4(&|d| at(d, 0.0, 0.0).2, h),
            -fd4(&|d| at(0.0, d, 0.0).2, h),
        );
        let want_m = -fd4(&|d| at(0.0, 0.0, d).2, h);
        let err = ((f - want).norm() + (m - want_m).abs()) / (f.norm() + m.abs());
        eprintln!(
            "{name}: E = {e:.6e}, F = ({:.9e}, {:.9e}), M = {m:.6e}; −∇E = ({:.9e}, {:.9e}), \
             {want_m:.6e}; rel {err:.1e}",
            f.x, f.y, want.x, want.y
        );
        // (The difference's rounding, ε E/h ≈ 4e-5 dyn at most here, is below 1e-10 of F.)
        assert!(err < 2e-9, "{name}: {err}");
    }
}

/// (5)'s left side less W: the net push of a disk of radius r at depth δ in a drum of radius R.
fn drum_push(k: f64, c: f64, r: f64, big: f64, delta: f64) -> f64 {
    let d = big - r + delta;
    let x = (d * d + big * big - r * r) / (2.0 * d);
    k * delta - c * 2.0 * (big * big - x * x).sqrt()
}

#[test]
fn a_cohesive_disk_rests_in_a_drum_at_the_closed_form_overlap() {
    let (r, big) = (1.0, 5.0);
    let weight = PI * r * r * G;
    // (5) by bisection on [0, r]: the push is −cℓ < 0 near δ = 0 (below W) and kr − … > W at r.
    let (mut lo, mut hi) = (1e-12, r);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if drum_push(KN, C, r, big, mid) > weight {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let want = 0.5 * (lo + hi);
    let flat = rest_depth(KN, C, r, weight);
    // Released touching the bottom, at rest; damped (restitution 0.5).
    let walls = r#"[ { "drum": { "center": [0, 0], "radius": 5 } } ]"#;
    let mut w = cohesive_world(
        walls,
        &disk_at(r, Vec2::new(0.0, -(big - r))),
        C,
        0.5,
        G,
        1e-5,
    );
    Simulation::new(&mut w).until_time(0.2).run().unwrap();
    let got = w.bodies.state[0].pose.position.norm() + r - big;
    eprintln!(
        "drum: rest depth {got:.12e} cm, closed form (5) {want:.12e} (rel {:.1e}); \
         on a flat floor (2) {flat:.12e}",
        got / want - 1.0
    );
    assert!((got / want - 1.0).abs() < 1e-6, "{got} vs {want}");
    assert!(w.bodies.state[0].vel.norm() < 1e-9);
}

/// The worst relative energy error of a cohesive disk (r = 1, no gravity, frictionless,
/// undamped) that slides along the segment y = 0, x ∈ [−4, 0], at the no-gravity rest depth
/// with speed 20 cm/s, past the end x = 0 (and round it: the pull holds it), over 0.15 s at the
/// step `dt`; and the cohesive energy cA at the start, over |E₀|.
fn slide_past_an_end(dt: f64) -> (f64, f64) {
    let r = 1.0;
    let delta = rest_depth(KN, C, r, 0.0);
    let walls = r#"[ { "segment": [[-4, 0], [0, 0]] } ]"#;
    let bodies = format!(
        r#"[ {{ "shape": {{ "type": "circle", "r": {r} }}, "position": [-1, {}],
            "velocity": [20, 0] }} ]"#,
        r - delta
    );
    let mut w = cohesive_world(walls, &bodies, C, 1.0, 0.0, dt);
    let e0 = w.energies.total();
    // The cap of the rest overlap (the sagitta δ ≪ r): A = r² acos(1 − δ/r) − (r − δ)√(δ(2r−δ)).
    let area = r * r * (1.0 - delta / r).acos() - (r - delta) * (delta * (2.0 * r - delta)).sqrt();
    let sim = Simulation::new(&mut w).until_time(0.15);
    let worst = worst_energy_error(sim);
    let end = w.bodies.state[0].pose.position;
    eprintln!(
        "dt {dt:.1e}: worst |E − E₀|/|E₀| = {worst:.3e}; the body ends at ({:.4}, {:.4}), \
         {} contact(s)",
        end.x,
        end.y,
        w.contacts.len()
    );
    assert!(end.x > 0.0, "it went past the end");
    (worst, C * area / e0.abs())
}

#[test]
fn a_cohesive_disk_sliding_past_a_segments_end_keeps_its_energy() {
    // Velocity Verlet's energy error is O(Δt²) for a smooth potential: halving the step
    // quarters it. A jump in the potential where the contact goes from the face to the end
    // would not shrink with the step: it would be of the cohesive energy cA itself (the whole
    // of it if the end's pull were missing).
    let (coarse, jump) = slide_past_an_end(1e-5);
    let (fine, _) = slide_past_an_end(5e-6);
    eprintln!(
        "ratio {:.2} (Δt² gives 4); cA/|E₀| = {jump:.3e}",
        coarse / fine
    );
    assert!(
        coarse / fine > 3.5 && coarse / fine < 4.5,
        "{coarse} {fine}"
    );
    assert!(coarse < 1e-3 * jump, "{coarse} against {jump}");
}

#[test]
fn a_disks_overlap_with_a_drum_and_a_segments_end_is_the_closed_form_area() {
    // The records the pull and −cA read, against the textbook forms: a drum's A = πr² − lens
    // with lens(r, R, d) = r² acos((d² + r² − R²)/(2dr)) + R² acos((d² + R² − r²)/(2dR))
    // − ½√((−d + r + R)(d + r − R)(d − r + R)(d + r + R)), ℓ = 2√(R² − x²); a segment end's
    // cap A = r² acos(1 − δ/r) − (r − δ)√(δ(2r − δ)), ℓ = 2√(δ(2r − δ)).
    use dem2d::geometry::{Drum, Pose, Segment};
    use dem2d::narrow_phase::{Object, contact};
    let (r, big) = (1.0, 5.0);
    let drum = Drum::new(Vec2::new(0.3, -0.2), big).unwrap();
    let seg = Segment::new(Vec2::new(-2.0, 0.0), Vec2::new(2.0, 0.0)).unwrap();
    let u = Vec2::new(0.6, -0.8);
    for delta in [1e-3, 0.02, 0.3, 0.9] {
        let d = big - r + delta;
        let disk = Object::Body {
            shape: Shape::Circle { r },
            pose: Pose::new(drum.center + u * d, 0.0),
        };
        let c = contact(&Object::Drum(drum), &disk).unwrap();
        let a = c.area.expect("a disk's area against a drum");
        let lens = r * r * ((d * d + r * r - big * big) / (2.0 * d * r)).acos()
            + big * big * ((d * d + big * big - r * r) / (2.0 * d * big)).acos()
            - 0.5 * ((-d + r + big) * (d + r - big) * (d - r + big) * (d + r + big)).sqrt();
        let x = (d * d + big * big - r * r) / (2.0 * d);
        let (want_a, want_l) = (PI * r * r - lens, 2.0 * (big * big - x * x).sqrt());
        eprintln!(
            "drum δ = {delta}: A = {:.15e} (closed form {want_a:.15e}), ℓ = {:.15e} ({want_l:.15e})",
            a.area, a.length
        );
        // The textbook form subtracts terms of size R² whose acos arguments lie near ±1, which
        // amplifies their rounding by 1/sin ≈ R/(ℓ/2) (≈ 100 at δ = 1e-3): about
        // 25 × 100 × 1e-16 ≈ 3e-13 cm² of the reference's own error, hence the absolute bar.
        // (At δ = 1e-3 it errs by 1.5e-13 cm² (2.3e-9 relative); the same form in 40-digit
        // arithmetic, mpmath, gives 6.66511677354041e-5 cm², which the kernel's
        // 6.665116773543750e-5 meets to 5e-13.)
        assert!((a.area - want_a).abs() < 1e-12, "{delta}");
        assert!((a.length / want_l - 1.0).abs() < 1e-9, "{delta}");
        assert!((c.depth - delta).abs() < 1e-14);
        // The segment's end (2, 0), the centre beyond it on a slant.
        let v = Vec2::new(0.6, 0.8);
        let disk = Object::Body {
            shape: Shape::Circle { r },
            pose: Pose::new(seg.b + v * (r - delta), 0.0),
        };
        let c = contact(&Object::Segment(seg), &disk).unwrap();
        assert_eq!(c.point, seg.b, "an end contact");
        let a = c.area.expect("a disk's area at a segment's end");
        let want_a =
            r * r * (1.0 - delta / r).acos() - (r - delta) * (delta * (2.0 * r - delta)).sqrt();
        let want_l = 2.0 * (delta * (2.0 * r - delta)).sqrt();
        eprintln!(
            "segment end δ = {delta}: A = {:.15e} (closed form {want_a:.15e}), ℓ = {:.15e} \
             ({want_l:.15e})",
            a.area, a.length
        );
        assert!((a.area - want_a).abs() < 1e-14, "{delta}");
        assert!((a.length / want_l - 1.0).abs() < 1e-12, "{delta}");
    }
}

/// The pull-off force of two equal disks (the Bond number's force in `dem2d study
/// repose-cohesion`), against its closed form. Two disks of radius r at centre distance `2r − δ`
/// meet on the chord `ℓ = 2√((δ/2)(2r − δ/2))`, so with `u = δ/2` the net push apart
/// `F = kδ − cℓ = 2(k u − c√(u(2r − u)))` is twice (1) for a wall with cohesion c/2: its least
/// value gives `P = 2 r(√(k² + c²) − k)` (at `δ* = 2(r − kr/√(k² + c²))`), and a disk hanging
/// by W ≤ P rests at twice (4)'s depth for (c/2, W/2). The disk-disk chord is the lens's
/// (`narrow_phase::circle_circle`, Heron), not the wall's cap: this is not (3) again.
#[test]
fn a_disk_hanging_under_a_fixed_disk_leaves_at_the_two_disk_pull_off_force() {
    let r = 1.0;
    let m = PI * r * r;
    let s = (KN * KN + C * C).sqrt();
    let (d_star, p) = (2.0 * (r - KN * r / s), 2.0 * r * (s - KN));
    // The same from the wall's (3) with c/2, doubled.
    let (u_star, half) = pull_off(KN, C / 2.0, r);
    assert!((2.0 * u_star / d_star - 1.0).abs() < 1e-12 && (2.0 * half / p - 1.0).abs() < 1e-12);
    eprintln!(
        "two disks: pull-off P = {p:.6} dyn at δ* = {d_star:.6e} cm (a disk on a wall: {:.6})",
        pull_off(KN, C, r).1
    );
    let hanging = |weight: f64| {
        let spec = spec(NormalForce::Area, C, Some(0.5));
        let mut top = body(Shape::Circle { r }, Vec2::zeros(), 0.0);
        top.prescribed = true;
        let below = body(
            Shape::Circle { r },
            Vec2::new(0.0, -(2.0 * r - d_star)),
            0.0,
        );
        let mut w = World::new(
            &[top, below],
            vec![],
            Vec2::new(0.0, -weight / m),
            spec,
            1e-5,
        );
        Simulation::new(&mut w).until_time(0.3).run().unwrap();
        w.bodies.state[1].pose.position.y
    };
    // 0.1 % below P: it holds, at twice (4)'s depth for (c/2, W/2).
    let y = hanging(0.999 * p);
    let got = 2.0 * r + y;
    let want = 2.0 * hang_depth(KN, C / 2.0, r, 0.999 * p / 2.0);
    eprintln!(
        "W = 0.999 P: hangs at depth {got:.10e} cm, closed form {want:.10e} (rel {:.1e})",
        got / want - 1.0
    );
    assert!((got / want - 1.0).abs() < 1e-6, "{got} vs {want}");
    // 0.1 % above P: it leaves and falls free.
    let y = hanging(1.001 * p);
    eprintln!("W = 1.001 P: centre at y = {y:.4} cm after 0.3 s (it hung at y = -{r}·2)");
    assert!(y < -4.0 * r, "still hanging at y = {y}");
}

/// `dem2d study repose-cohesion`'s protocol on a small column (100 disks released from their
/// lattice, as `tests/rolling.rs`'s heap, EPSD μ_r = 0.1): with cohesion between the grains and
/// with the floor at Bo = 10 (the pull-off force of two disks of the mean radius, above, ten
/// weights: `c = √((k + Bo W/(2r))² − k²)`) the heap stands steeper, higher and shorter than
/// without. Cohesion is switched on at the release and only acts while grains overlap, so
/// nothing in the law itself makes a heap steeper: the grains must hold together in the flow.
#[test]
fn a_cohesive_heap_stands_steeper_than_a_cohesionless_one() {
    use dem2d::contact_law::{RollingModel, RollingPart};
    use dem2d::dynamics::analysis::heap_surface;
    use dem2d::run::Stop;
    use dem2d::scene::generate::{ColumnSpec, DENSITY, KN_OVER_RHO_G};
    let column = ColumnSpec {
        n: 100,
        width: 12.5,
        seed: 5,
        friction: 0.5,
    };
    let rolling = RollingPart {
        model: RollingModel::Epsd,
        friction: 0.1,
        damping: None,
    };
    let (k, weight) = (KN_OVER_RHO_G * DENSITY * G, DENSITY * G * PI);
    let bodies = column.lattice_bodies();
    let mut heaps = Vec::new();
    for bo in [0.0, 10.0] {
        let s = k + bo * weight / 2.0;
        let c = ((s - k) * (s + k)).sqrt();
        let text =
            column.cohesive_case_json("heap", &bodies, 100.0, &rolling.given(), c, "EPSD, 0.1.");
        let case = dem2d::scene::Case::from_json(&text).unwrap();
        let mut w = case.build_world();
        let stop = Simulation::new(&mut w)
            .until_time(3.0)
            .quiescence(case.quiescence_criterion())
            .run()
            .unwrap();
        let (angle, h, toe) = heap_surface(&w, 2.0);
        eprintln!(
            "Bo = {bo} (c = {c:.4e}): angle {angle:.1}°, height {h:.1} cm, toe {toe:.1} cm, {}",
            match stop {
                Stop::AtRest { since } => format!("at rest at t = {:.2} s", since as f64 * 1e-5),
                _ => "not at rest in 3 s".to_string(),
            }
        );
        heaps.push((angle, h, toe));
    }
    let ((a0, h0, t0), (a1, h1, t1)) = (heaps[0], heaps[1]);
    assert!(a1 > a0 + 4.0, "angle {a1} against {a0} without cohesion");
    assert!(h1 > h0 && t1 < t0, "height {h1} vs {h0}, toe {t1} vs {t0}");
}

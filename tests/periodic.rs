//! Periodic cells and Lees–Edwards shear (`dynamics::cell`), against independent answers: a
//! brute-force search over every image for the contact set, the same pair placed by hand at its
//! image for a pair across a seam, a linear shear profile and the imposed-pressure target for a
//! sheared cell, the conservation of momentum and of energy (with the boundary's work), and an
//! exact restart. Two classic faults of Lees–Edwards implementations are tested by name: a pair
//! listed twice when the shift is zero (the first ESPResSo implementation) and the velocity jump
//! left out at a crossing (once in LAMMPS).

use dem2d::contact_law::{ContactSpec, LinearDamping, Scaled};
use dem2d::dynamics::cell::{Cell, Periodic, Pressure};
use dem2d::dynamics::{BodyInit, World};
use dem2d::geometry::{Shape, Vec2};
use dem2d::narrow_phase::{Object, contact};
use dem2d::run::Simulation;
use dem2d::scene::Case;
use std::collections::BTreeSet;

mod common;
use common::Rng;

fn law(friction: f64, restitution: Option<f64>) -> ContactSpec {
    let damping = match restitution {
        Some(e) => LinearDamping::Restitution(e),
        None => LinearDamping::Dashpots {
            eta_n: Scaled::Absolute(0.0),
            eta_s: Scaled::Absolute(0.0),
        },
    };
    ContactSpec::linear(
        Scaled::Absolute(1e6),
        Scaled::Absolute(1e6),
        damping,
        friction,
    )
}

fn body(shape: Shape, position: Vec2, angle: f64, velocity: Vec2) -> BodyInit {
    BodyInit {
        velocity,
        ..common::body(shape, position, angle)
    }
}

fn world(bodies: Vec<BodyInit>, spec: ContactSpec, dt: f64, cell: Cell) -> World {
    Case::new(bodies, Vec::new(), Vec2::zeros(), spec, dt)
        .with_cell(cell)
        .build_world()
}

/// Every pair `(i, j)` that overlaps through some image of i (the lower index), by the narrow
/// phase on i placed at each of its images within two periods.
fn brute_force_pairs(w: &World, cell: &Cell) -> BTreeSet<(usize, usize)> {
    let b = &w.bodies;
    let mut out = BTreeSet::new();
    for i in 0..b.len() {
        for j in i + 1..b.len() {
            let mut touching = 0;
            for sy in -2..=2 {
                for sx in -2..=2 {
                    let offset = Vec2::new(
                        sx as f64 * cell.size.x + sy as f64 * cell.offset,
                        sy as f64 * cell.size.y,
                    );
                    let mut pose = b.state[i].pose;
                    pose.position += offset;
                    let oi = Object::Body {
                        shape: b.shape[i],
                        pose,
                    };
                    let oj = Object::Body {
                        shape: b.shape[j],
                        pose: b.state[j].pose,
                    };
                    if contact(&oi, &oj).is_some_and(|g| g.depth > 0.0) {
                        touching += 1;
                    }
                }
            }
            assert!(
                touching <= 1,
                "pair ({i}, {j}) touches through {touching} images"
            );
            if touching == 1 {
                out.insert((i, j));
            }
        }
    }
    out
}

/// A dense random packing of disks and ellipses in a cell, overlapping here and there, across
/// every seam.
fn packing(rng: &mut Rng, cell: &Cell) -> Vec<BodyInit> {
    let (lx, ly) = (cell.size.x, cell.size.y);
    (0..60)
        .map(|k| {
            let shape = if k % 3 == 0 {
                Shape::Ellipse {
                    a: 0.6 + 0.3 * rng.next(),
                    b: 0.35 + 0.1 * rng.next(),
                }
            } else {
                Shape::Circle {
                    r: 0.4 + 0.2 * rng.next(),
                }
            };
            body(
                shape,
                Vec2::new(lx * rng.next(), ly * rng.next()),
                6.3 * rng.next(),
                Vec2::zeros(),
            )
        })
        .collect()
}

/// An n × n square lattice of disks (radii 0.5 and 0.35 alternating, spacing 1.25 cm) in an "xy"
/// cell sheared at `rate` and held at the normal stress `p`, each disk with `velocity()`.
fn pressed_lattice(
    n: usize,
    rate: f64,
    p: f64,
    mut velocity: impl FnMut() -> Vec2,
) -> (Cell, Vec<BodyInit>) {
    let side = 1.25 * n as f64;
    let cell = Cell::new(
        Vec2::new(side, side),
        Periodic::XY,
        rate,
        Some(Pressure {
            target: p,
            gain: 0.1,
        }),
    );
    let bodies = (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            let r = if (i + j) % 2 == 0 { 0.5 } else { 0.35 };
            body(
                Shape::Circle { r },
                Vec2::new(1.25 * i as f64 + 0.6, 1.25 * j as f64 + 0.6),
                0.0,
                velocity(),
            )
        })
        .collect();
    (cell, bodies)
}

/// The contacts of the neighbour list equal those of a brute-force search over every image, at
/// Lees–Edwards offsets 0, L_x/2 and just below L_x — and no pair is listed twice (the first
/// ESPResSo implementation listed pairs twice at offset 0).
#[test]
fn the_contact_set_across_seams_equals_a_brute_force_image_search() {
    let mut rng = Rng(0x5EED_CE11);
    for offset_fraction in [0.0, 0.5, 1.0 - 1e-12] {
        for trial in 0..4 {
            let mut cell = Cell::new(Vec2::new(9.0, 7.5), Periodic::XY, 1.0, None);
            cell.offset = offset_fraction * cell.size.x;
            cell.shift = cell.offset + 3.0 * cell.size.x;
            let w = world(packing(&mut rng, &cell), law(0.0, None), 1e-5, cell);
            let listed: Vec<(usize, usize)> = w
                .contacts
                .slots
                .iter()
                .map(|s| (s.i as usize, s.j as usize))
                .collect();
            let unique: BTreeSet<_> = listed.iter().copied().collect();
            assert_eq!(unique.len(), listed.len(), "a pair listed twice");
            let active: BTreeSet<(usize, usize)> = w
                .contacts
                .active()
                .map(|c| (c.slot.i as usize, c.slot.j as usize))
                .collect();
            let want = brute_force_pairs(&w, &cell);
            assert!(!want.is_empty(), "no contact to test");
            assert_eq!(active, want, "offset {offset_fraction} L_x, trial {trial}");
        }
    }
}

/// A pair across a seam is computed as the same pair with the giver placed at its image by hand,
/// in a world without a cell: the same contact record and the same force and moment on the
/// receiver, bit for bit (coordinates that are sums of few powers of two make the image's
/// position exact), and the same moment on the giver to rounding.
#[test]
fn a_pair_across_a_seam_is_the_same_pair_away_from_it() {
    let ellipse = Shape::Ellipse { a: 1.0, b: 0.5 };
    let mut cell = Cell::new(Vec2::new(16.0, 8.0), Periodic::XY, 0.5, None);
    cell.offset = 3.25;
    cell.shift = 3.25;
    // Across the x seam; across the y seam (through the Lees–Edwards shift); across both.
    for (gx, gy, rx, ry) in [
        (15.5, 4.0, 0.375, 4.0),
        (6.0, 7.625, 2.75, 0.5),
        (2.75, 7.625, 0.25, 0.25),
    ] {
        let giver = body(ellipse, Vec2::new(gx, gy), 0.5, Vec2::new(1.0, -2.0));
        let receiver = body(ellipse, Vec2::new(rx, ry), 2.0, Vec2::new(-0.5, 0.25));
        let periodic = world(vec![giver, receiver], law(0.5, Some(0.5)), 1e-5, cell);
        let image = cell
            .nearest_image(giver.position, receiver.position)
            .expect("across a seam");
        let moved = BodyInit {
            position: giver.position + image.offset,
            velocity: giver.velocity + image.velocity,
            ..giver
        };
        let plain = Case::new(
            vec![moved, receiver],
            Vec::new(),
            Vec2::zeros(),
            law(0.5, Some(0.5)),
            1e-5,
        )
        .build_world();
        let (a, b) = (
            periodic.contacts.active().next().expect("in contact"),
            plain.contacts.active().next().expect("in contact"),
        );
        assert_eq!(a.data, b.data, "the contact record");
        assert_eq!(periodic.bodies.force[1], plain.bodies.force[1]);
        assert_eq!(periodic.bodies.torque[1], plain.bodies.torque[1]);
        assert_eq!(periodic.bodies.force[0], plain.bodies.force[0]);
        let (m, n) = (periodic.bodies.torque[0], plain.bodies.torque[0]);
        assert!((m - n).abs() <= 1e-12 * n.abs(), "{m} vs {n}");
    }
}

/// Two disks touching across the Lees–Edwards seam, each moving with the shear's mean flow
/// `v_x = γ̇ (y − L_y/2)`, against the same pair placed by hand with the giver at its image (with
/// the image's velocity, `v_x − γ̇ L_y`) in a world without a cell: the same contact force over
/// several steps. Left out, the image's velocity would make the pair slide by `γ̇ L_y` instead of
/// `γ̇` times its true height difference (a fault LAMMPS once had).
#[test]
fn a_pair_across_the_lees_edwards_seam_moves_as_the_same_pair_away_from_it() {
    let rate = 2.0;
    let mut cell = Cell::new(Vec2::new(12.0, 10.0), Periodic::XY, rate, None);
    cell.offset = 4.0;
    cell.shift = 4.0;
    let flow = |y: f64| Vec2::new(rate * (y - 5.0), 0.0);
    let disk = Shape::Circle { r: 0.5 };
    // The receiver just above the bottom; the giver just below the top, above the receiver in
    // the image below (shifted back by the offset).
    let (ry, gy) = (0.45, 9.58);
    let receiver = body(disk, Vec2::new(3.0, ry), 0.0, flow(ry));
    let giver = body(disk, Vec2::new(3.3 + 4.0, gy), 0.0, flow(gy));
    let spec = law(0.5, Some(0.5));
    let mut periodic = world(vec![giver, receiver], spec, 1e-6, cell);
    let image = cell
        .nearest_image(giver.position, receiver.position)
        .expect("across the seam");
    let moved = BodyInit {
        position: giver.position + image.offset,
        velocity: giver.velocity + image.velocity,
        ..giver
    };
    let mut plain =
        Case::new(vec![moved, receiver], Vec::new(), Vec2::zeros(), spec, 1e-6).build_world();
    for w in [&mut periodic, &mut plain] {
        Simulation::new(w).for_steps(200).run().unwrap();
    }
    let (a, b) = (
        periodic.contacts.active().next().expect("in contact"),
        plain.contacts.active().next().expect("in contact"),
    );
    let scale = b.data.force.norm();
    assert!(scale > 0.0);
    assert!(
        (a.data.force - b.data.force).norm() < 1e-9 * scale,
        "{:?} against {:?}",
        a.data.force,
        b.data.force
    );
    // The pair slides at γ̇ times its true height difference: a tangential force builds up.
    assert!(b.data.force.x.abs() > 1e-3 * scale);
}

/// A gas of elastic disks and ellipses (no dashpot, no friction) in a periodic cell, with
/// bodies crossing every seam: momentum is conserved to rounding, and energy to the scheme's
/// accuracy (a thousandth of the kinetic energy over several hundred collisions).
#[test]
fn momentum_and_energy_are_conserved_across_seams() {
    let cell = Cell::new(Vec2::new(14.0, 12.0), Periodic::XY, 0.0, None);
    let mut rng = Rng(99);
    let mut bodies = Vec::new();
    for k in 0..48 {
        let (i, j) = (k % 8, k / 8);
        let shape = if k % 2 == 0 {
            Shape::Circle { r: 0.5 }
        } else {
            Shape::Ellipse { a: 0.7, b: 0.4 }
        };
        bodies.push(body(
            shape,
            Vec2::new(1.75 * i as f64 + 0.5, 2.0 * j as f64 + 0.5),
            6.3 * rng.next(),
            Vec2::new(40.0 * (rng.next() - 0.5), 40.0 * (rng.next() - 0.5)),
        ));
    }
    let mut w = world(bodies, law(0.0, None), 2e-6, cell);
    let momentum0 = w.momentum();
    let e0 = w.energies.total();
    let mut contacts = 0;
    Simulation::new(&mut w)
        .for_steps(100_000)
        .run_each(|_, r| contacts += r.contacts)
        .unwrap();
    assert!(contacts > 10_000, "too few contacts to test: {contacts}");
    let crossed = w.bodies.image.iter().filter(|i| **i != [0, 0]).count();
    assert!(crossed > 10, "only {crossed} bodies crossed a seam");
    let dp = (w.momentum() - momentum0).norm();
    assert!(
        dp < 1e-9 * (1.0 + momentum0.norm()),
        "momentum changed by {dp}"
    );
    let de = (w.energies.total() - e0).abs();
    assert!(de < 1e-3 * e0, "energy changed by {de} of {e0}");
}

/// A dense, frictional, sheared cell at an imposed pressure: the cell holds the pressure, the
/// mean velocity profile is linear across the whole height with no kink at the seam, and the
/// energy account balances with the boundary's work.
#[test]
fn a_sheared_cell_at_an_imposed_pressure_flows_with_a_linear_profile() {
    let n = 12;
    let mut rng = Rng(7);
    let (rate, p) = (4.0, 1000.0);
    let (cell, bodies) =
        pressed_lattice(n, rate, p, || Vec2::new(rng.next() - 0.5, rng.next() - 0.5));
    let mut w = world(bodies, law(0.4, Some(0.5)), 5e-5, cell);
    let bins = 6;
    let (mut sum, mut count) = (vec![0.0; bins], vec![0usize; bins]);
    let (mut p_sum, mut p_n) = (0.0, 0);
    let steps = 60_000;
    let e0 = w.energies.total();
    Simulation::new(&mut w)
        .for_steps(steps)
        .run_each(|w, _| {
            // The second half: steady.
            if w.step > steps / 2 && w.step % 50 == 0 {
                let c = w.cell.expect("a cell");
                for s in &w.bodies.state {
                    let b = ((s.pose.position.y / c.size.y) * bins as f64) as usize;
                    sum[b.min(bins - 1)] += s.vel.x;
                    count[b.min(bins - 1)] += 1;
                }
                p_sum += c.normal_stress();
                p_n += 1;
            }
        })
        .unwrap();
    let c = w.cell.expect("a cell");
    let mean_p = p_sum / p_n as f64;
    assert!((mean_p - p).abs() < 0.05 * p, "σ_yy {mean_p} against {p}");
    // The profile against the shear's mean flow γ̇ (y − L_y/2), at each bin's centre: within a
    // tenth of the velocity across the cell, the bins at the seam (first and last) included.
    let across = rate * c.size.y;
    for b in 0..bins {
        let y = (b as f64 + 0.5) / bins as f64 * c.size.y;
        let v = sum[b] / count[b] as f64;
        let want = rate * (y - 0.5 * c.size.y);
        assert!(
            (v - want).abs() < 0.1 * across,
            "bin {b}: ⟨v_x⟩ {v:.3} against {want:.3} (γ̇ L_y = {across:.3})"
        );
    }
    // K + P + E_el + D = E₀ + W: what is left is the integration's error.
    let e = w.energies;
    let unaccounted = e.total() - e0 - e.boundary_work;
    assert!(
        unaccounted.abs() < 2e-3 * e.dissipated,
        "energy account off by {unaccounted} (dissipated {}, boundary work {})",
        e.dissipated,
        e.boundary_work
    );
}

/// A cell at rest under an imposed pressure shrinks until its grains touch: the stretch that
/// closes a contact does the work stored in it (the trapezoidal rule of `Cell::stretch`), so
/// the elastic, frictionless grains' energy equals the cell's work — and the blow-up watch,
/// which has no initial energy to allow for, does not take the stored energy for created
/// energy (it did when the stretch's work was taken with the stress before it alone).
#[test]
fn a_cell_at_rest_under_pressure_stores_what_its_stretch_works() {
    let n = 12;
    let (cell, bodies) = pressed_lattice(n, 0.0, 1000.0, Vec2::zeros);
    let mut w = world(bodies, law(0.0, None), 5e-5, cell);
    Simulation::new(&mut w)
        .for_steps(20_000)
        .run()
        .expect("no blow-up");
    let e = w.energies;
    assert!(e.elastic > 0.0 && e.boundary_work > 0.0, "{e:?}");
    // What is left is the step's error where a stretch closes a contact part-way through it:
    // at most half the spring's force over the approach of one step, ½ k (l_y |λ − 1|)² with
    // the branch vector l_y ≤ 1 cm (the largest diameter) and |λ − 1| ≤ MAX_STRETCH, once per
    // contact.
    let contacts = w.contacts.active().count() as f64;
    let bound = contacts * 0.5 * 1e6 * (1.0 * dem2d::dynamics::cell::MAX_STRETCH).powi(2);
    let unaccounted = e.total() - e.boundary_work;
    assert!(
        unaccounted.abs() < bound && bound < 0.02 * e.elastic,
        "energy account off by {unaccounted} (bound {bound}; boundary work {}, elastic {}, \
         kinetic {})",
        e.boundary_work,
        e.elastic,
        e.kinetic
    );
}

/// A sheared cell at an imposed pressure continued from its `state.json` ends in the same state,
/// bit for bit, as the run that was not interrupted (the cell's height, shift and stress and the
/// bodies' image counts are in the state).
#[test]
fn a_sheared_cell_continues_exactly_from_its_state() {
    let dir = common::scratch("restart");
    let mut rng = Rng(3);
    let bodies: Vec<String> = (0..36)
        .map(|k| {
            let (i, j) = (k % 6, k / 6);
            let shape = if k % 2 == 0 {
                r#"{"type": "circle", "r": 0.5}"#.to_string()
            } else {
                r#"{"type": "ellipse", "a": 0.7, "b": 0.4}"#.to_string()
            };
            format!(
                r#"{{"shape": {shape}, "position": [{}, {}], "angle": {}, "velocity": [{}, {}]}}"#,
                1.5 * i as f64 + 0.7,
                1.5 * j as f64 + 0.7,
                6.0 * rng.next(),
                rng.next() - 0.5,
                rng.next() - 0.5
            )
        })
        .collect();
    let case = format!(
        r#"{{"version": 1, "name": "restart_cell", "gravity": [0, 0], "dt": 5e-5, "duration": 1,
        "output_every": 100,
        "cell": {{"size": [9, 9], "periodic": "xy", "shear_rate": 3, "pressure": 500}},
        "contact": {{"model": "linear", "kn": 1e6, "restitution": 0.5, "friction": 0.4}},
        "bodies": [{}]}}"#,
        bodies.join(", ")
    );
    std::fs::write(dir.join("case.json"), case).unwrap();
    let run = |args: &[&str]| {
        let s = std::process::Command::new(common::bin())
            .args(args)
            .current_dir(&dir)
            .status()
            .unwrap();
        assert!(s.success(), "dem2d {args:?}");
    };
    run(&[
        "run",
        "case.json",
        "--out",
        "whole",
        "--max-steps",
        "3000",
        "--quiet",
    ]);
    run(&[
        "run",
        "case.json",
        "--out",
        "first",
        "--max-steps",
        "1700",
        "--quiet",
    ]);
    run(&[
        "run",
        "first/state.json",
        "--out",
        "second",
        "--max-steps",
        "1300",
        "--quiet",
    ]);
    let last_frame = |d: &str| {
        let text = std::fs::read_to_string(dir.join(d).join("trajectory.csv")).unwrap();
        let rows: Vec<&str> = text.lines().collect();
        rows[rows.len() - 36..].join("\n")
    };
    let whole = last_frame("whole");
    assert!(whole.starts_with("3000,"), "{whole}");
    assert_eq!(last_frame("second"), whole);
    let cell = |d: &str| {
        let text = std::fs::read_to_string(dir.join(d).join("cell.csv")).unwrap();
        text.lines().last().unwrap().to_string()
    };
    assert_eq!(cell("second"), cell("whole"));
}

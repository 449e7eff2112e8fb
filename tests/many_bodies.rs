//! Many bodies: the neighbour list never misses a contact (checked against every pair, step by
//! step, on random scenes with a 1:5 size spread and bodies leaving the populated region); the
//! trajectory is bit-identical for any number of threads; the generated piles are what their
//! description says, and the 10 000-body case files are exactly the generator's output.

use dem2d::contact_law::{ContactSpec, LinearDamping, Scaled};
use dem2d::dynamics::Partner;
use dem2d::dynamics::{BodyInit, Boundary, World};
use dem2d::geometry::{Shape, Vec2, Wall};
use dem2d::narrow_phase::{Object, contact};
use dem2d::run::Simulation;
use dem2d::scene::Case;
use dem2d::scene::generate::{PileShape, PileSpec, R_MAX, R_MIN};
use std::collections::BTreeSet;

/// A small deterministic generator for the scenes (independent of the one under test).
struct Lcg(u64);

impl Lcg {
    fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }
}

fn law(friction: f64) -> ContactSpec {
    ContactSpec::linear(
        Scaled::Absolute(2e5),
        Scaled::Absolute(2e5),
        LinearDamping::Dashpots {
            eta_n: Scaled::Absolute(20.0),
            eta_s: Scaled::Absolute(20.0),
        },
        friction,
    )
}

/// A random scene: circles, ellipses and rectangles with sizes spread 1:5, packed densely in a
/// box with fast random velocities; `escapees` bodies are flung out of the populated region.
fn random_scene(seed: u64, n: usize, escapees: usize) -> World {
    let mut rng = Lcg(seed);
    let mut bodies = Vec::new();
    let cols = (n as f64).sqrt().ceil() as usize;
    for k in 0..n {
        let size = rng.range(0.2, 1.0); // 1:5
        let shape = match k % 3 {
            0 => Shape::Circle { r: size },
            1 => Shape::Ellipse {
                a: size,
                b: size * rng.range(0.3, 1.0),
            },
            _ => Shape::Rectangle {
                w: 1.6 * size,
                h: 1.6 * size * rng.range(0.3, 1.0),
            },
        };
        let (row, col) = (k / cols, k % cols);
        // The last bodies (the top row) fly off up and to the right, out of the region.
        let escapes = k + escapees >= n;
        let speed = if escapes { 3000.0 } else { 30.0 };
        let dir = if escapes {
            rng.range(0.3, 1.2)
        } else {
            rng.range(0.0, std::f64::consts::TAU)
        };
        bodies.push(BodyInit {
            material: 0,
            prescribed: false,
            shape,
            position: Vec2::new(1.1 * col as f64 + 1.0, 1.1 * row as f64 + 1.0),
            angle: rng.range(0.0, 6.3),
            velocity: Vec2::new(dir.cos(), dir.sin()) * speed,
            omega: rng.range(-20.0, 20.0),
            density: 1.0,
        });
    }
    let walls = vec![
        Boundary::new(Wall::new(Vec2::zeros(), Vec2::y()).unwrap(), law(0.5)),
        Boundary::new(Wall::new(Vec2::zeros(), Vec2::x()).unwrap(), law(0.5)),
    ];
    World::new(&bodies, walls, Vec2::new(0.0, -980.0), law(0.3), 2e-5)
}

/// Every overlapping pair, by testing all pairs with the narrow phase (no broad phase).
fn all_pairs(w: &World) -> BTreeSet<(u32, u32)> {
    let b = &w.bodies;
    let body = |k: usize| Object::Body {
        shape: b.shape[k],
        pose: b.state[k].pose,
    };
    let mut out = BTreeSet::new();
    for i in 0..b.len() {
        for j in i + 1..b.len() {
            let c = contact(&body(i), &body(j));
            if c.is_some_and(|g| g.depth > 0.0) {
                out.insert((i as u32, j as u32));
            }
        }
        for (k, ws) in w.walls.iter().enumerate() {
            let c = contact(&Object::Wall(*ws.line()), &body(i));
            if c.is_some_and(|g| g.depth > 0.0) {
                out.insert((i as u32, Partner::Wall(k).key()));
            }
        }
    }
    out
}

#[test]
fn the_neighbour_list_finds_every_contact_the_all_pairs_check_finds() {
    for seed in 1..=3 {
        let mut w = random_scene(seed, 150, 10);
        let (mut checked, mut contacts) = (0, 0);
        // The scene is the list's stress test, not physics: its soft law lets fast bodies pass
        // deeper into each other than their size, which the blow-up watch would stop.
        Simulation::new(&mut w)
            .without_watch()
            .for_steps(600)
            .run_each(|w, _| {
                let step = w.step - 1;
                if step % 3 == 0 {
                    let expected = all_pairs(w);
                    let found: BTreeSet<(u32, u32)> =
                        w.contacts.active().map(|c| (c.slot.i, c.slot.j)).collect();
                    assert_eq!(found, expected, "seed {seed}, step {step}");
                    contacts += expected.len();
                    checked += 1;
                }
            })
            .expect("stable");
        // The scene must exercise the list: many contacts, several rebuilds, bodies far away.
        assert!(
            contacts > 50 * checked,
            "only {contacts} contacts in {checked} checks"
        );
        assert!(w.contacts.builds > 20, "{} builds", w.contacts.builds);
        let far = w
            .bodies
            .state
            .iter()
            .filter(|s| s.pose.position.norm() > 40.0)
            .count();
        assert!(far >= 5, "{far} bodies left the region");
    }
}

/// Runs `steps` steps of a dense random scene on a pool of `threads` threads; returns every
/// body's state bits, the energies' bits and the mean number of contacts per step.
fn run_on(threads: usize, steps: usize) -> (Vec<u64>, f64) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut w = random_scene(11, 1600, 0);
        let mut contacts = 0;
        // The random scene's overlaps run deep (see above): no watch.
        Simulation::new(&mut w)
            .without_watch()
            .for_steps(steps as u64)
            .run_each(|_, r| contacts += r.contacts)
            .unwrap();
        let b = &w.bodies;
        let bits = (0..b.len())
            .flat_map(|k| {
                [
                    b.state[k].pose.position.x,
                    b.state[k].pose.position.y,
                    b.state[k].pose.angle(),
                    b.state[k].vel.x,
                    b.state[k].vel.y,
                    b.state[k].omega,
                    b.force[k].x,
                    b.force[k].y,
                    b.torque[k],
                ]
            })
            .chain([
                w.energies.dissipated,
                w.energies.elastic,
                w.energies.kinetic,
            ])
            .map(f64::to_bits)
            .collect();
        (bits, contacts as f64 / steps as f64)
    })
}

#[test]
fn trajectories_are_bit_identical_for_any_number_of_threads() {
    // 1600 circles, ellipses and rectangles in a dense, agitated box: thousands of slots in
    // several parallel chunks, contacts opening and closing, list rebuilds.
    let (one, contacts) = run_on(1, 800);
    assert!(contacts > 1000.0, "only {contacts} contacts per step");
    for threads in [2, 3, 4] {
        let (many, _) = run_on(threads, 800);
        let differ = one.iter().zip(&many).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "{threads} threads: {differ} values differ");
    }
}

#[test]
fn generated_piles_start_without_overlap_inside_their_box() {
    // The piles of cases/, and bidisperse frictionless ones of several aspect ratios.
    let mut specs = vec![
        PileSpec::new(PileShape::Disks, 2000, 3),
        PileSpec::new(PileShape::Ellipses, 2000, 3),
    ];
    for aspect in [1.2, 3.0] {
        let mut s = PileSpec::new(PileShape::Ellipses, 2000, 3);
        s.aspect = aspect;
        s.sizes = dem2d::scene::generate::PileSizes::Bidisperse;
        s.friction = 0.0;
        specs.push(s);
    }
    for spec in specs {
        let case = Case::from_json(&spec.case_json()).unwrap();
        assert_eq!(case.bodies.len(), 2000);
        let w = World::new(
            &case.bodies,
            case.walls.clone(),
            case.gravity,
            case.contact,
            case.dt,
        );
        assert!(
            all_pairs(&w).is_empty(),
            "{}: overlaps at the start",
            spec.name()
        );
        let width = spec.width();
        for b in &case.bodies {
            let r_eq = match b.shape {
                Shape::Circle { r } => r,
                // Equal-area radius √(ab), and the asked a/b.
                Shape::Ellipse { a, b } => {
                    assert!((a / b - spec.aspect).abs() < 1e-12 * spec.aspect);
                    (a * b).sqrt()
                }
                Shape::Rectangle { .. } | Shape::Polygon(_) | Shape::Clump(_) => {
                    panic!("no rectangles, polygons or clumps in a pile")
                }
            };
            match spec.sizes {
                dem2d::scene::generate::PileSizes::Uniform => {
                    assert!((R_MIN..=R_MAX).contains(&r_eq), "radius {r_eq}")
                }
                dem2d::scene::generate::PileSizes::Bidisperse => {
                    let small = dem2d::scene::generate::R_SMALL;
                    assert!(
                        (r_eq - small).abs() < 1e-6 || (r_eq - 1.4 * small).abs() < 1e-6,
                        "radius {r_eq}"
                    )
                }
            }
            let bound = b.shape.bounding_radius();
            assert!(b.position.x - bound > 0.0 && b.position.x + bound < width);
            assert!(b.position.y - bound > 0.0);
            assert!(b.velocity.norm() <= 5.0 + 1e-6);
        }
    }
}

#[test]
fn the_10k_case_files_are_the_generators_output() {
    for (shape, file) in [
        (PileShape::Disks, "settle_disks_10k.json"),
        (PileShape::Ellipses, "settle_ellipses_10k.json"),
    ] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("cases")
            .join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        let spec = PileSpec::new(shape, 10_000, 1);
        assert!(
            text == spec.case_json(),
            "{file} differs from `dem2d generate`'s output: regenerate it"
        );
    }
}

/// A scene of disks under a linear law takes the step's disk path (each slot's geometry
/// straight from the circle kernels, the law compiled for its kind); one ellipse far above the
/// pile, touching nothing, sends every slot through the general path (the narrow phase's
/// dispatcher, a separate geometry pass) instead. The disks' trajectories must agree bit for
/// bit, as two implementations of the same arithmetic.
#[test]
fn the_disk_path_gives_the_general_paths_bits() {
    let spec = PileSpec::new(PileShape::Disks, 400, 7);
    let mut case = Case::from_json(&spec.case_json()).expect("pile");
    for b in &mut case.bodies {
        b.velocity.y -= 150.0; // into contact within a few hundred steps
    }
    let mut mixed = case.clone();
    let mut far = case.bodies[0];
    // Smaller than the largest disk (the same skin and grid), the pile's density (the same
    // laws), 10 m above it: it falls by well under a centimetre in the run.
    far.shape = Shape::Ellipse { a: 1.0, b: 0.5 };
    far.position = Vec2::new(far.position.x, far.position.y + 1000.0);
    far.velocity = Vec2::zeros();
    mixed.bodies.push(far);
    let run = |c: &Case| {
        let mut w = c.build_world();
        let mut contacts = 0;
        Simulation::new(&mut w)
            .for_steps(3000)
            .run_each(|_, r| contacts = r.contacts)
            .expect("no blow-up");
        (w, contacts)
    };
    let (disks, n_disks) = run(&case);
    let (general, n_general) = run(&mixed);
    assert!(n_disks > 100, "the pile is in contact ({n_disks} contacts)");
    assert_eq!(n_disks, n_general);
    for k in 0..case.bodies.len() {
        let (a, b) = (&disks.bodies.state[k], &general.bodies.state[k]);
        let bits = |s: &dem2d::dynamics::BodyState| {
            [
                s.pose.position.x,
                s.pose.position.y,
                s.vel.x,
                s.vel.y,
                s.omega,
            ]
            .map(f64::to_bits)
        };
        assert_eq!(bits(a), bits(b), "body {k}");
    }
    assert_eq!(
        disks.energies.elastic.to_bits(),
        general.energies.elastic.to_bits()
    );
}

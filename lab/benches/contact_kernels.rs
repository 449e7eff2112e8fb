//! Contact kernels per pair kind, in three regimes:
//! - `overlap`: the pair overlaps (two boundary crossings);
//! - `near`: separated, but the bounding circles overlap (the full test runs or a cheap axis
//!   test rejects it);
//! - `far`: rejected by the bounding circles;
//! - `grazing`: separated by 1e-3 of the smaller size along a direction other than the line of
//!   centres, so that no cheap axis test rejects it and the full test runs;
//! - `lasting` and `near, warm`: conic pairs (circle–ellipse, ellipse–ellipse) as the dynamics
//!   sees them, with the pair cache (its warm start) carried from a configuration one step of
//!   motion away (j moved by 1e-4 of its size and turned by 1e-4 rad): an overlap of 1e-4 to 1e-2 of the
//!   smaller size (a DEM contact's), and a grazing pair with its separating axis.
//!
//! Each measurement runs over a batch of 1024 random pairs of the regime (so branch prediction
//! sees realistic variety) and the table reports the median time per pair.
//! Also: the robust cubic solver against bare `roots::find_roots_cubic` on the same cubics.
//!
//! Run: `cargo bench -p dem2d-lab --bench contact_kernels` (prints a Markdown table at the end, writes it to
//! `figures/kernel_speed.md` and into the user guide's `kernel_speed` table (docs/src/performance.md);
//! `cargo bench -p dem2d-lab --bench contact_kernels -- --quick` for a faster, noisier run).

use criterion::{BenchmarkId, Criterion};
use dem2d::contact_law::{
    AreaKinematics, EquivalentOverlap, History, Kinematics, LinearDashpots, NormalForce,
    RollingKinematics,
};
use dem2d::geometry::cubic::{one_real_root, solve_cubic};
use dem2d::geometry::overlap_area::DiskLens;
use dem2d::geometry::support::support_local;
use dem2d::geometry::{Pose, Shape, Vec2, Wall};
use dem2d::narrow_phase::{ContactState, Object, PairCache, Request, contact, contact_with};
use dem2d_validation::rng::Rng;
use std::hint::black_box;
use std::time::Duration;

const BATCH: usize = 1024;

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Circle,
    Ellipse,
    Rectangle,
    Wall,
}

fn random_shape(rng: &mut Rng, kind: Kind) -> Shape {
    let a = rng.range(1.0, 2.0);
    match kind {
        Kind::Circle => Shape::Circle { r: a },
        Kind::Ellipse => Shape::Ellipse {
            a,
            b: a * rng.range(0.4, 0.9),
        },
        Kind::Rectangle => Shape::Rectangle {
            w: a,
            h: a * rng.range(0.5, 1.0),
        },
        Kind::Wall => unreachable!(),
    }
}

fn support(shape: &Shape, pose: &Pose, n: Vec2) -> f64 {
    let u = pose.to_body_vector(n);
    support_local(shape, u.x, u.y)
}

/// The point of the shape (centred at the origin) farthest along the unit direction `n`.
fn support_point(shape: &Shape, pose: &Pose, n: Vec2) -> Vec2 {
    let u = pose.to_body_vector(n);
    let p = match *shape {
        Shape::Circle { r } => u * r,
        Shape::Ellipse { a, b } => {
            let h = support_local(shape, u.x, u.y);
            Vec2::new(a * a * u.x / h, b * b * u.y / h)
        }
        Shape::Rectangle { w, h } => Vec2::new(0.5 * w * u.x.signum(), 0.5 * h * u.y.signum()),
        Shape::Polygon(p) => *p
            .vertices
            .iter()
            .max_by(|a, b| a.dot(&u).total_cmp(&b.dot(&u)))
            .expect("vertices"),
        Shape::Clump(_) => unreachable!("no clumps among the kernels"),
    };
    pose.to_world_vector(p)
}

#[derive(Clone, Copy, PartialEq)]
enum Regime {
    Overlap,
    /// A DEM contact's overlap: 1e-4 to 1e-2 of the smaller size.
    Shallow,
    Near,
    Far,
    Grazing,
}

/// One pair of the regime: j placed along a random direction at a chosen gap from i.
fn pair(rng: &mut Rng, ki: Kind, kj: Kind, regime: Regime) -> (Object, Object) {
    for _ in 0..100_000 {
        let sj = random_shape(rng, kj);
        let pj = Pose::new(
            Vec2::new(rng.range(-10.0, 10.0), rng.range(-10.0, 10.0)),
            rng.range(-3.2, 3.2),
        );
        let t = rng.range(-3.2, 3.2);
        let n = Vec2::new(t.cos(), t.sin());
        let (i, reach_i, sup_i) = if ki == Kind::Wall {
            (None, 0.0, 0.0)
        } else {
            let si = random_shape(rng, ki);
            (Some(si), si.bounding_radius(), 0.0)
        };
        let _ = sup_i;
        let rj = sj.bounding_radius();
        let gap = match regime {
            Regime::Overlap => -rng.range(0.01, 0.3) * sj.inscribed_radius(),
            Regime::Shallow => -10f64.powf(rng.range(-4.0, -2.0)) * sj.inscribed_radius(),
            Regime::Near => rng.range(0.01, 0.5) * sj.inscribed_radius(),
            Regime::Far => reach_i + rj + rng.range(0.1, 2.0),
            Regime::Grazing => 1e-3 * sj.inscribed_radius(),
        };
        let (oi, oj) = match i {
            None => {
                // Wall through a point below j along −n.
                let h = support(&sj, &pj, n) + gap;
                let w = Wall::new(pj.position - n * h, n).unwrap();
                (
                    Object::Wall(w),
                    Object::Body {
                        shape: sj,
                        pose: pj,
                    },
                )
            }
            Some(si) => {
                let pi0 = Pose::new(Vec2::zeros(), rng.range(-3.2, 3.2));
                let pi = match regime {
                    Regime::Far => Pose::new(pj.position - n * gap, pi0.angle()),
                    // Support points aligned: n is the separating axis, not the line of centres.
                    Regime::Grazing => Pose::new(
                        pj.position + support_point(&sj, &pj, -n)
                            - support_point(&si, &pi0, n)
                            - n * gap,
                        pi0.angle(),
                    ),
                    _ => Pose::new(
                        pj.position - n * (support(&si, &pi0, n) + support(&sj, &pj, n) + gap),
                        pi0.angle(),
                    ),
                };
                (
                    Object::Body {
                        shape: si,
                        pose: pi,
                    },
                    Object::Body {
                        shape: sj,
                        pose: pj,
                    },
                )
            }
        };
        let state = ContactState::of(contact(&oi, &oj).as_ref());
        let d_centres = match (oi, oj) {
            (Object::Body { pose: a, .. }, Object::Body { pose: b, .. }) => {
                (a.position - b.position).norm()
            }
            _ => 0.0,
        };
        let ok = match regime {
            Regime::Overlap | Regime::Shallow => state == ContactState::Overlap,
            Regime::Near => {
                state == ContactState::Separated && (ki == Kind::Wall || d_centres < reach_i + rj)
            }
            Regime::Grazing => {
                state == ContactState::Separated
                    && (ki == Kind::Wall || d_centres < reach_i + rj)
                    && !centre_line_separates(&oi, &oj)
            }
            Regime::Far => state == ContactState::Separated,
        };
        if ok {
            return (oi, oj);
        }
    }
    panic!("no pair of this kind in this regime");
}

/// Whether the separating-axis test along the line of centres alone rejects the pair.
fn centre_line_separates(i: &Object, j: &Object) -> bool {
    match (i, j) {
        (
            Object::Body {
                shape: si,
                pose: pi,
            },
            Object::Body {
                shape: sj,
                pose: pj,
            },
        ) => {
            let dv = pj.position - pi.position;
            let n = dv / dv.norm();
            support(si, pi, n) + support(sj, pj, n) < dv.norm()
        }
        _ => false,
    }
}

fn bench_kernels(c: &mut Criterion) {
    let kinds: [(&str, Kind, Kind); 9] = [
        ("circle-circle", Kind::Circle, Kind::Circle),
        ("circle-ellipse", Kind::Circle, Kind::Ellipse),
        ("ellipse-ellipse", Kind::Ellipse, Kind::Ellipse),
        ("wall-circle", Kind::Wall, Kind::Circle),
        ("wall-ellipse", Kind::Wall, Kind::Ellipse),
        ("wall-rectangle", Kind::Wall, Kind::Rectangle),
        ("rectangle-circle", Kind::Rectangle, Kind::Circle),
        ("rectangle-ellipse", Kind::Rectangle, Kind::Ellipse),
        ("rectangle-rectangle", Kind::Rectangle, Kind::Rectangle),
    ];
    let mut group = c.benchmark_group("contact");
    for (name, ki, kj) in kinds {
        for (regime, rname) in [
            (Regime::Overlap, "overlap"),
            (Regime::Near, "near"),
            (Regime::Far, "far"),
            (Regime::Grazing, "grazing"),
        ] {
            if name == "circle-circle" && matches!(regime, Regime::Near | Regime::Grazing) {
                continue; // separated circles never have overlapping bounding circles
            }
            let mut rng =
                Rng(0x9E37_79B9_7F4A_7C15 ^ (name.len() as u64 * 7919 + rname.len() as u64));
            let pairs: Vec<(Object, Object)> =
                (0..BATCH).map(|_| pair(&mut rng, ki, kj, regime)).collect();
            group.bench_function(BenchmarkId::new(name, rname), |b| {
                b.iter(|| {
                    let mut acc = 0.0;
                    for (i, j) in &pairs {
                        if let Some(g) = contact(black_box(i), black_box(j)) {
                            acc += g.depth;
                        }
                    }
                    acc
                })
            });
        }
    }
    // Conic pairs with the dynamics' warm start.
    for (name, ki, kj) in [
        ("circle-ellipse", Kind::Circle, Kind::Ellipse),
        ("ellipse-ellipse", Kind::Ellipse, Kind::Ellipse),
    ] {
        // (Near pairs that the centre-line test does not reject are the grazing ones.)
        for (regime, rname) in [(Regime::Shallow, "lasting"), (Regime::Grazing, "near-warm")] {
            let mut rng =
                Rng(0x9E37_79B9_7F4A_7C15 ^ (name.len() as u64 * 7919 + rname.len() as u64));
            let mut pairs = Vec::new();
            for _ in 0..100 * BATCH {
                if pairs.len() == BATCH {
                    break;
                }
                let (oi, oj) = pair(&mut rng, ki, kj, regime);
                let Object::Body {
                    shape: sj,
                    pose: pj,
                } = oj
                else {
                    unreachable!("body pairs")
                };
                // Last step: j a little elsewhere.
                let size = sj.bounding_radius();
                let before = Pose::new(
                    pj.position + Vec2::new(1e-4 * size, -0.7e-4 * size),
                    pj.angle() + 1e-4,
                );
                let mut cache = PairCache::default();
                let then = Object::Body {
                    shape: sj,
                    pose: before,
                };
                contact_with(&oi, &then, &mut cache, Request::CHORD);
                if !cache.is_empty() {
                    pairs.push((oi, oj, cache));
                }
            }
            assert_eq!(
                pairs.len(),
                BATCH,
                "{name} {rname}: too few pairs carry a warm start"
            );
            group.bench_function(BenchmarkId::new(name, rname), |b| {
                b.iter(|| {
                    let mut acc = 0.0;
                    for (i, j, cache) in &pairs {
                        // A copy of the cache: every iteration starts from last step's.
                        let mut cache = *cache;
                        let c = contact_with(
                            black_box(i),
                            black_box(j),
                            black_box(&mut cache),
                            Request::CHORD,
                        );
                        if let Some(g) = c {
                            acc += g.depth;
                        }
                    }
                    acc
                })
            });
            if rname == "lasting" {
                // Geometry and law together, as a step pays per lasting contact, under each
                // normal-force law (the area law adds the overlap area and the lens inverse).
                for nf in [NormalForce::Depth, NormalForce::Area] {
                    let id = format!("law-{}", nf.as_str());
                    group.bench_function(BenchmarkId::new(name, &id), |b| {
                        b.iter(|| {
                            let mut acc = 0.0;
                            for (i, j, cache) in &pairs {
                                acc += geometry_and_law(i, j, *cache, nf);
                            }
                            acc
                        })
                    });
                }
            }
        }
    }
    group.finish();
}

/// One lasting contact's geometry (from its pair cache) and linear law, at rest, under `nf`:
/// the normal force.
fn geometry_and_law(i: &Object, j: &Object, mut cache: PairCache, nf: NormalForce) -> f64 {
    let area = nf == NormalForce::Area;
    let request = Request {
        area,
        ..Request::CHORD
    };
    let c = contact_with(black_box(i), black_box(j), black_box(&mut cache), request);
    let Some(g) = c else {
        return 0.0;
    };
    let radius = |o: &Object| match o {
        Object::Body { shape, .. } => shape.equal_area_radius(),
        Object::Wall(_) | Object::Segment(_) | Object::Drum(_) => f64::INFINITY,
    };
    let law = LinearDashpots {
        kn: 3.6e7,
        eta_n: 1e4,
        eta_s: 1e4,
        ks: 3.6e7,
        friction: 0.3,
    }
    .law();
    let kin = Kinematics {
        depth: g.depth,
        energy_depth: g.depth,
        vn: 0.0,
        vt: 0.0,
        m_eff: 1.0,
        r_eff: f64::NAN,
        dt: 1e-5,
        area: g.area.filter(|_| area).map(|a| AreaKinematics {
            area: a.area,
            length: a.length,
            rate: 0.0,
            couple: a.couple,
            equivalent: EquivalentOverlap::Lens(DiskLens::new(radius(i), radius(j))),
        }),
        spin: 0.0,
        rolling: RollingKinematics {
            radius: f64::NAN,
            inertia: f64::NAN,
            spin_inertia: f64::NAN,
        },
        cohesion: None,
    };
    law.force(&kin, &mut History::default()).normal
}

fn bench_cubic(c: &mut Criterion) {
    // The cubics of real overlapping ellipse pairs would need the kernel's internals; a spread of
    // random cubics with one and with three real roots serves to compare the two solvers' cost.
    let mut rng = Rng(12345);
    let cubics: Vec<[f64; 4]> = (0..BATCH)
        .map(|_| {
            let (r1, r2, r3) = (
                rng.range(-3.0, 0.0),
                rng.range(-3.0, 3.0),
                rng.range(0.0, 3.0),
            );
            if rng.uniform() < 0.5 {
                // (λ − r1)(λ − r2)(λ − r3)
                [
                    1.0,
                    -(r1 + r2 + r3),
                    r1 * r2 + r1 * r3 + r2 * r3,
                    -r1 * r2 * r3,
                ]
            } else {
                // (λ − r1)(λ² + r2 λ + r3² + r2²)  — one real root
                let q = r3 * r3 + r2 * r2;
                [1.0, r2 - r1, q - r1 * r2, -r1 * q]
            }
        })
        .collect();
    let mut group = c.benchmark_group("cubic");
    group.bench_function("robust", |b| {
        b.iter(|| {
            cubics
                .iter()
                .map(|t| solve_cubic(t[0], t[1], t[2], t[3]).len())
                .sum::<usize>()
        })
    });
    group.bench_function("one-real-root", |b| {
        b.iter(|| {
            cubics
                .iter()
                .map(|t| one_real_root(t[0], t[1], t[2], t[3]).is_some() as usize)
                .sum::<usize>()
        })
    });
    group.bench_function("roots-bare", |b| {
        b.iter(|| {
            cubics
                .iter()
                .map(|t| {
                    roots::find_roots_cubic(t[0], t[1], t[2], t[3])
                        .as_ref()
                        .len()
                })
                .sum::<usize>()
        })
    });
    group.finish();
}

/// Reads criterion's median estimates written by this run (`since` its start), prints the ns/pair
/// table and, when every cell was measured, writes it to `figures/kernel_speed.md` and refreshes
/// the user guide's `kernel_speed` table (a filtered run prints only: it must neither blank the
/// published table nor mix in an earlier run's estimates).
fn print_table(since: std::time::SystemTime) {
    use std::fmt::Write as _;
    let mut md = String::new();
    // The workspace's target directory (this bench's package is lab/).
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/criterion");
    let missing = std::cell::Cell::new(0usize);
    let median = |group: &str, id: &str| -> Option<f64> {
        let p = dir.join(group).join(id).join("new/estimates.json");
        // No estimates at all: a cell no benchmark fills (a "–" of the table). Estimates older
        // than this run: a benchmark this run skipped (filtered), which must not be mixed in.
        let modified = std::fs::metadata(&p).and_then(|m| m.modified()).ok()?;
        let v = (modified >= since)
            .then(|| std::fs::read_to_string(&p).ok())
            .flatten()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            .and_then(|v| v["median"]["point_estimate"].as_f64());
        if v.is_none() {
            missing.set(missing.get() + 1);
        }
        v.map(|ns| ns / BATCH as f64)
    };
    let fmt = |x: Option<f64>| x.map_or("–".to_string(), |v| format!("{v:.1}"));
    writeln!(
        md,
        "| pair kind (ns/pair) | overlap | near: separated, bounding circles overlap | far: rejected by bounding circles | grazing: separated by 1e-3·b, the line of centres does not separate | lasting overlap (1e-4…1e-2 b), warm start | grazing, warm axis |"
    )
    .unwrap();
    writeln!(md, "|---|---:|---:|---:|---:|---:|---:|").unwrap();
    for name in [
        "circle-circle",
        "circle-ellipse",
        "ellipse-ellipse",
        "wall-circle",
        "wall-ellipse",
        "wall-rectangle",
        "rectangle-circle",
        "rectangle-ellipse",
        "rectangle-rectangle",
    ] {
        let dirname = |r: &str| format!("{name}/{r}");
        writeln!(
            md,
            "| {name} | {} | {} | {} | {} | {} | {} |",
            fmt(median("contact", &dirname("overlap"))),
            fmt(median("contact", &dirname("near"))),
            fmt(median("contact", &dirname("far"))),
            fmt(median("contact", &dirname("grazing"))),
            fmt(median("contact", &dirname("lasting"))),
            fmt(median("contact", &dirname("near-warm")))
        )
        .unwrap();
    }
    writeln!(
        md,
        "\nA lasting contact's geometry and linear law together (ns/contact), P's spring on the depth → the area law: circle–ellipse {} → {}, ellipse–ellipse {} → {}",
        fmt(median("contact", "circle-ellipse/law-depth")),
        fmt(median("contact", "circle-ellipse/law-area")),
        fmt(median("contact", "ellipse-ellipse/law-depth")),
        fmt(median("contact", "ellipse-ellipse/law-area"))
    )
    .unwrap();
    writeln!(
        md,
        "\nCubic solve (ns/cubic; half the cubics have one real root, half three): robust, all roots {} | fast single root (declines three-root cubics) {} | bare roots::find_roots_cubic {}",
        fmt(median("cubic", "robust")),
        fmt(median("cubic", "one-real-root")),
        fmt(median("cubic", "roots-bare"))
    )
    .unwrap();
    println!("\n{md}");
    if missing.get() > 0 {
        eprintln!(
            "{} entries not measured by this run (a filtered run?): figures/kernel_speed.md and the user guide left as they were",
            missing.get()
        );
        return;
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let root = root.as_path();
    let out = root.join("figures/kernel_speed.md");
    if let Err(e) = std::fs::write(&out, &md) {
        eprintln!("{}: {e}", out.display());
    }
    use dem2d::output::docs_tables::{Mode, refresh};
    if let Err(e) = refresh(root, &[("kernel_speed", md)], Mode::Write) {
        eprintln!("the user guide's kernel_speed table: {e}");
    }
}

fn main() {
    let start = std::time::SystemTime::now();
    let mut c = Criterion::default()
        .configure_from_args()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(30);
    bench_kernels(&mut c);
    bench_cubic(&mut c);
    c.final_summary();
    print_table(start);
}

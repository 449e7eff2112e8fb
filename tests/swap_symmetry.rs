//! Swap symmetry of the contact record, for every pair kind (issue 11, item 15).
//!
//! Exchanging i and j must give the same state and depth, the same point and chord, the normal
//! negated — and for the overlap area the same area, length and point, with the normal and the
//! couple negated. A seeded generator draws pairs of every kind — circle, ellipse, rectangle,
//! convex polygon (3 to 12 vertices on an ellipse, at any aspect) and wall, in every combination and both orders — coincident, concentric, contained (including
//! thin ellipses inside another body), touching, overlapping from 1e-12 to 0.3 of the smaller
//! size, deep (four crossings), separated, and any of those up to 1e6 sizes from the origin
//! with walls whose point is up to 1e6 sizes along the line from the body.
//!
//! The bar is **exact equality**: every pair is computed in one order only and the other order
//! is the same result swapped (`narrow_phase` documents the order: a wall before a body, a
//! circle before an ellipse, a polygon or rectangle before a conic, two ellipses or two
//! polygons (rectangles among them) in a canonical order,
//! circle pairs by a closed form symmetric term by term), so nothing may differ, not even in the
//! last bit. The one exception is a pair of two *identical* objects (same shape, same pose):
//! then i and j cannot be told apart, the two orders are the same computation, and the normal
//! cannot be both `n` and `−n`; everything else is still compared.

use dem2d::geometry::{Polygon, Pose, Shape, Vec2, Wall};
use dem2d::narrow_phase::ellipse_ellipse::Warm;
use dem2d::narrow_phase::{
    Contact, ContactState, Object, PairCache, Request, contact, contact_with,
};
use dem2d_validation::pairs::{support, support_point, unit};
use dem2d_validation::rng::Rng;

/// The kinds of object, in the order of the generator.
const KINDS: [&str; 5] = ["circle", "ellipse", "rectangle", "polygon", "wall"];

/// The wall's index in [`KINDS`].
const WALL: usize = 4;

/// A random convex polygon: 3 to 12 vertices on the ellipse `(a, a/aspect)`, one in each of
/// equal sectors of eccentric angle (so never two on a line), turned by a random angle.
fn polygon(a: f64, aspect: f64, rng: &mut Rng) -> Shape {
    let n = 3 + (rng.uniform() * 10.0) as usize;
    let turn = rng.angle();
    let sector = std::f64::consts::TAU / n as f64;
    let v: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let t = sector * (k as f64 + rng.range(0.1, 0.9));
            let (x, y) = (a * t.cos(), a / aspect * t.sin());
            let (s, c) = turn.sin_cos();
            [c * x - s * y, s * x + c * y]
        })
        .collect();
    Shape::Polygon(Polygon::new(&v).expect("points on an ellipse are in convex position"))
}

/// A random shape of `kind` (0 circle, 1 ellipse, 2 rectangle, 3 polygon) of size about `s`,
/// with an aspect ratio up to `max_aspect`.
fn shape(kind: usize, s: f64, max_aspect: f64, rng: &mut Rng) -> Shape {
    let aspect = (rng.uniform() * max_aspect.ln()).exp();
    match kind {
        0 => Shape::Circle {
            r: s * rng.range(0.5, 1.0),
        },
        1 => Shape::Ellipse {
            a: s,
            b: s / aspect,
        },
        2 => Shape::Rectangle {
            w: 2.0 * s,
            h: 2.0 * s / aspect,
        },
        _ => polygon(s, aspect, rng),
    }
}

/// How the pair is placed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Config {
    /// j an exact copy of i (same kinds only), or a wall through the body's centre.
    Identical,
    /// Same centre, different shapes or angles.
    Concentric,
    /// j well inside i (or i inside j).
    Contained,
    /// A thin ellipse (aspect 10 … 1e4) somewhere inside a body, possibly poking out.
    ThinInside,
    /// Supports along a random direction meeting, ±1e-14 of the size.
    Touching,
    /// Overlap 1e-12 … 0.3 of the smaller size along a random direction.
    Overlap,
    /// Two elongated bodies crossed at about a right angle near their centres.
    Deep,
    /// A gap 1e-12 … 0.3 of the smaller size.
    Separated,
}

const CONFIGS: [Config; 8] = [
    Config::Identical,
    Config::Concentric,
    Config::Contained,
    Config::ThinInside,
    Config::Touching,
    Config::Overlap,
    Config::Deep,
    Config::Separated,
];

/// One generated pair: i, j, and whether they are the same object.
struct Pair {
    i: Object,
    j: Object,
    identical: bool,
}

fn body(shape: Shape, p: [f64; 2], th: f64) -> Object {
    Object::Body {
        shape,
        pose: Pose::new(Vec2::new(p[0], p[1]), th),
    }
}

/// Draws a pair of kinds `(ki, kj)` (4 = wall) in configuration `cfg`, at `offset` from the
/// origin (a wall's point slid up to `offset` along its line), with sizes about `s`.
fn draw(ki: usize, kj: usize, cfg: Config, offset: f64, s: f64, rng: &mut Rng) -> Pair {
    let o = unit(rng.angle());
    let far = offset * rng.uniform();
    let origin = [far * o[0], far * o[1]];
    let (wall_i, wall_j) = (ki == WALL, kj == WALL);
    if wall_i || wall_j {
        // A body and a wall; the wall's depth into the body set by the configuration.
        let kb = if wall_i { kj } else { ki };
        let aspect = if cfg == Config::ThinInside { 1e4 } else { 10.0 };
        let sb = shape(kb, s, aspect, rng);
        let th = rng.angle();
        let n = unit(rng.angle());
        // The body's extent below its centre along the wall's normal (a polygon's support is
        // not symmetric).
        let h = support(&sb, th, [-n[0], -n[1]]);
        let small = s * 10f64.powf(rng.range(-12.0, -0.5));
        let nu = match cfg {
            Config::Identical => h, // the line through the centre
            Config::Concentric | Config::Contained | Config::Deep => 2.0 * h + small, // inside
            Config::ThinInside => h * rng.range(0.0, 2.5),
            Config::Touching => s * 1e-14 * rng.range(-1.0, 1.0),
            Config::Overlap => small,
            Config::Separated => -small,
        };
        let slide = offset * rng.range(-1.0, 1.0);
        let foot = [
            origin[0] - (h - nu) * n[0] - slide * n[1],
            origin[1] - (h - nu) * n[1] + slide * n[0],
        ];
        let w = Object::Wall(Wall::new(Vec2::from(foot), Vec2::from(n)).unwrap());
        let b = body(sb, origin, th);
        return if wall_i {
            Pair {
                i: w,
                j: b,
                identical: false,
            }
        } else {
            Pair {
                i: b,
                j: w,
                identical: false,
            }
        };
    }
    let (ti, tj) = (rng.angle(), rng.angle());
    let dir = unit(rng.angle());
    let at = |c: [f64; 2]| [origin[0] + c[0], origin[1] + c[1]];
    let (si, sj, ci, cj, ti, tj) = match cfg {
        Config::Identical if ki == kj => {
            let si = shape(ki, s, 10.0, rng);
            (si, si, [0.0; 2], [0.0; 2], ti, ti)
        }
        Config::Identical | Config::Concentric => (
            shape(ki, s, 10.0, rng),
            shape(kj, s * rng.range(0.3, 1.5), 10.0, rng),
            [0.0; 2],
            [0.0; 2],
            ti,
            tj,
        ),
        Config::Contained => {
            let si = shape(ki, s, 3.0, rng);
            let sj = shape(kj, s * rng.range(0.05, 0.25), 3.0, rng);
            let off = rng.range(0.0, 0.2) * s;
            (si, sj, [0.0; 2], [off * dir[0], off * dir[1]], ti, tj)
        }
        Config::ThinInside => {
            let si = shape(ki, s, 2.0, rng);
            // j thin: a thin ellipse (or, for kinds other than ellipses, a thin version of j).
            let thin = 10f64.powf(rng.range(1.0, 4.0));
            let len = s * rng.range(0.2, 0.9);
            let sj = match kj {
                0 => Shape::Circle { r: len / thin },
                1 => Shape::Ellipse {
                    a: len,
                    b: len / thin,
                },
                2 => Shape::Rectangle {
                    w: 2.0 * len,
                    h: 2.0 * len / thin,
                },
                _ => polygon(len, thin, rng),
            };
            let off = rng.range(0.0, 0.6) * s;
            (si, sj, [0.0; 2], [off * dir[0], off * dir[1]], ti, tj)
        }
        Config::Deep => {
            let thin = rng.range(3.0, 20.0);
            let si = shape(ki, s, 1.0, rng);
            let sj = shape(kj, s * rng.range(0.8, 1.2), 1.0, rng);
            let off = rng.range(0.0, 0.2) * s / thin;
            let tj = ti + std::f64::consts::FRAC_PI_2 + rng.range(-0.5, 0.5);
            let mut slim = |sh: Shape| match sh {
                Shape::Circle { r } => Shape::Circle { r },
                Shape::Ellipse { a, .. } => Shape::Ellipse { a, b: a / thin },
                Shape::Rectangle { w, .. } => Shape::Rectangle { w, h: w / thin },
                Shape::Polygon(p) => polygon(p.bounding_radius, thin, rng),
                Shape::Clump(_) => unreachable!("clumps: tests/clumps.rs"),
            };
            (
                slim(si),
                slim(sj),
                [0.0; 2],
                [off * dir[0], off * dir[1]],
                ti,
                tj,
            )
        }
        Config::Touching | Config::Overlap | Config::Separated => {
            let si = shape(ki, s, 10.0, rng);
            let sj = shape(kj, s * rng.range(0.3, 1.5), 10.0, rng);
            let smaller = si.inscribed_radius().min(sj.inscribed_radius());
            let nu = match cfg {
                Config::Touching => s * 1e-14 * rng.range(-1.0, 1.0),
                Config::Overlap => smaller * 10f64.powf(rng.range(-12.0, -0.5)),
                _ => -smaller * 10f64.powf(rng.range(-12.0, -0.5)),
            };
            // j's extreme point along −dir on i's extreme point along dir, then moved by nu
            // towards i.
            let (pi, pj) = (
                support_point(&si, ti, dir),
                support_point(&sj, tj, [-dir[0], -dir[1]]),
            );
            let cj = [pi[0] - pj[0] - nu * dir[0], pi[1] - pj[1] - nu * dir[1]];
            (si, sj, [0.0; 2], cj, ti, tj)
        }
    };
    let (i, j) = (body(si, at(ci), ti), body(sj, at(cj), tj));
    Pair {
        identical: i == j,
        i,
        j,
    }
}

/// Exact comparison of a contact with the same pair computed in the other order (`b`): all
/// equal but the normals, which must be opposite; `Err` names what differs.
fn compare(a: &Option<Contact>, b: &Option<Contact>, identical: bool) -> Result<(), String> {
    let (ga, gb) = match (a, b) {
        (None, None) => return Ok(()),
        (Some(ga), Some(gb)) => (ga, gb),
        (Some(_), None) | (None, Some(_)) => return Err("contact on one side only".into()),
    };
    if ga.state != gb.state {
        return Err(format!("state {:?} vs {:?}", ga.state, gb.state));
    }
    let finite = |v: Vec2| v.x.is_finite() && v.y.is_finite();
    if !(ga.depth.is_finite() && finite(ga.point) && finite(ga.normal)) {
        return Err(format!("non-finite geometry {ga:?}"));
    }
    if ga.depth != gb.depth {
        return Err(format!("depth {:e} vs {:e}", ga.depth, gb.depth));
    }
    if ga.point != gb.point {
        return Err(format!("point {:?} vs {:?}", ga.point, gb.point));
    }
    if !identical && ga.normal != -gb.normal {
        return Err(format!("normal {:?} vs −{:?}", ga.normal, gb.normal));
    }
    let (ca, cb) = (ga.chord(), gb.chord());
    let same_chord = ga.half_chord == gb.half_chord && (ca == cb || ca == (cb.1, cb.0));
    if !same_chord {
        return Err(format!("chord {ca:?} vs {cb:?}"));
    }
    if ga.flat != gb.flat {
        return Err(format!("flat overlap {:?} vs {:?}", ga.flat, gb.flat));
    }
    match (ga.area, gb.area) {
        (None, None) => {}
        (Some(x), Some(y)) => {
            if x.area != y.area || x.length != y.length || x.point != y.point {
                return Err(format!("overlap area {x:?} vs {y:?}"));
            }
            if !identical && (x.normal != -y.normal || x.couple != -y.couple) {
                return Err(format!(
                    "overlap area normal/couple {x:?} vs {y:?} (should be negated)"
                ));
            }
        }
        _ => return Err("overlap area on one side only".into()),
    }
    Ok(())
}

#[test]
fn every_pair_kind_is_swap_symmetric() {
    let mut rng = Rng(0x5EED_0015_u64);
    let mut failures = Vec::new();
    let mut seen = std::collections::BTreeMap::new();
    let mut total = 0;
    for (ki, name_i) in KINDS.iter().enumerate() {
        for (kj, name_j) in KINDS.iter().enumerate() {
            if ki == WALL && kj == WALL {
                continue;
            }
            for (c, &cfg) in CONFIGS.iter().enumerate() {
                for k in 0..60 {
                    // Half at the origin, the rest up to 1e3 and 1e6 sizes away.
                    let offset = [0.0, 0.0, 1e3, 1e6][k % 4];
                    let s = rng.range(0.5, 2.0);
                    let pair = draw(ki, kj, cfg, offset, s, &mut rng);
                    let (a, b) = (contact(&pair.i, &pair.j), contact(&pair.j, &pair.i));
                    total += 1;
                    let state = ContactState::of(a.as_ref()).as_str();
                    *seen.entry((name_i, name_j, state)).or_insert(0) += 1;
                    if let Err(e) = compare(&a, &b, pair.identical) {
                        failures.push(format!(
                            "{}–{} {cfg:?} (#{c}.{k}): {e}\n    i = {:?}\n    j = {:?}",
                            name_i, name_j, pair.i, pair.j
                        ));
                    }
                    // As the dynamics asks (no chord, no area: circle pairs skip the chord),
                    // through the dispatcher with a pair cache, both ways round.
                    let lean = |i: &Object, j: &Object| {
                        let request = Request {
                            area: false,
                            chord: false,
                            trace: None,
                        };
                        contact_with(i, j, &mut PairCache::default(), request)
                    };
                    let (x, y) = (lean(&pair.i, &pair.j), lean(&pair.j, &pair.i));
                    // What is asked changes only what is added: the state, point, normal and
                    // depth are the full query's, bit for bit.
                    let core =
                        |c: &Option<Contact>| c.map(|g| (g.state, g.point, g.normal, g.depth));
                    if core(&x) != core(&a) {
                        failures.push(format!(
                            "{}–{} {cfg:?}: without chord or area {:?}, with {:?}",
                            name_i,
                            name_j,
                            core(&x),
                            core(&a)
                        ));
                    }
                    if let Err(e) = compare(&x, &y, pair.identical) {
                        failures.push(format!(
                            "{}–{} {cfg:?} without chord or area (#{c}.{k}): {e}\n    i = {:?}\n    j = {:?}",
                            name_i, name_j, pair.i, pair.j
                        ));
                    }
                }
            }
        }
    }
    for ((i, j, s), n) in &seen {
        println!("{i:>9}–{j:<9} {s:<10} {n}");
    }
    println!("{total} pairs, each both ways round");
    // Every kind pair meets every state it can have (touching is a thin set for corners).
    for (ki, name_i) in KINDS.iter().enumerate() {
        for (kj, name_j) in KINDS.iter().enumerate() {
            if ki == WALL && kj == WALL {
                continue;
            }
            let mut wanted = vec!["separated", "overlap", "contained"];
            if (1..=3).contains(&ki) && (1..=3).contains(&kj) {
                wanted.push("deep");
            }
            for s in wanted {
                assert!(
                    seen.get(&(name_i, name_j, s)).copied().unwrap_or(0) > 0,
                    "{}–{} never {s}: the generator misses a state",
                    name_i,
                    name_j
                );
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {total} pairs are not swap-symmetric; first ones:\n{}",
        failures.len(),
        failures
            .iter()
            .take(8)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}

/// What a query is asked (the chord, the overlap area) changes only what is added: in both
/// orders, from a new pair and again from the warm start the first query left, the state,
/// point, normal and depth are bit for bit those of the full query, the area those of every
/// query that asks for it, the chord's half-length that of every query that asks for it, and
/// the warm start left in the pair cache is the same — so the dynamics, which asks for no chord
/// (and for the area only under the area law), gets the one-off query's contact.
#[test]
fn what_is_asked_changes_only_what_is_added() {
    let mut rng = Rng(0xC0_71C5_u64);
    let bits = |x: f64| x.to_bits();
    let (mut compared, mut warm) = (0, 0);
    let requests = [
        Request::LEAN,
        Request {
            area: true,
            ..Request::LEAN
        },
        Request::CHORD,
    ];
    for ki in 0..KINDS.len() {
        for kj in 0..KINDS.len() {
            if ki == WALL && kj == WALL {
                continue;
            }
            for &cfg in CONFIGS.iter() {
                for k in 0..20 {
                    let offset = [0.0, 0.0, 1e3, 1e6][k % 4];
                    let s = rng.range(0.5, 2.0);
                    let pair = draw(ki, kj, cfg, offset, s, &mut rng);
                    for (i, j) in [(&pair.i, &pair.j), (&pair.j, &pair.i)] {
                        for request in requests {
                            let (mut asked_cache, mut full_cache) =
                                (PairCache::default(), PairCache::default());
                            // A new pair, then the same pair from what the first query kept.
                            for _ in 0..2 {
                                let asked = contact_with(i, j, &mut asked_cache, request);
                                let full = contact_with(i, j, &mut full_cache, Request::FULL);
                                assert_eq!(asked_cache, full_cache, "{ki}–{kj} {cfg:?}");
                                warm += usize::from(!full_cache.is_empty());
                                compared += 1;
                                let (l, g) = match (asked, full) {
                                    (None, None) => continue,
                                    (Some(l), Some(g)) => (l, g),
                                    (l, g) => panic!("{ki}–{kj} {cfg:?}: {l:?}, full {g:?}"),
                                };
                                assert_eq!(l.state, g.state, "{ki}–{kj} {cfg:?}");
                                assert_eq!(l.flat, g.flat, "{ki}–{kj} {cfg:?}");
                                let mut pairs = vec![
                                    (l.point.x, g.point.x),
                                    (l.point.y, g.point.y),
                                    (l.normal.x, g.normal.x),
                                    (l.normal.y, g.normal.y),
                                    (l.depth, g.depth),
                                ];
                                if request.chord {
                                    pairs.push((l.half_chord, g.half_chord));
                                }
                                if request.area {
                                    let (la, ga) = (l.area, g.area);
                                    assert_eq!(la.is_some(), ga.is_some());
                                    if let (Some(la), Some(ga)) = (la, ga) {
                                        pairs.extend([
                                            (la.area, ga.area),
                                            (la.length, ga.length),
                                            (la.normal.x, ga.normal.x),
                                            (la.normal.y, ga.normal.y),
                                            (la.point.x, ga.point.x),
                                            (la.point.y, ga.point.y),
                                            (la.couple, ga.couple),
                                        ]);
                                    }
                                } else {
                                    assert!(l.area.is_none(), "{ki}–{kj} {cfg:?}: unasked area");
                                }
                                for (x, y) in pairs {
                                    assert_eq!(bits(x), bits(y), "{ki}–{kj} {cfg:?}");
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    // The comparison reached the conic pairs' warm starts.
    assert!(
        compared > 1000 && warm > 300,
        "{compared} compared, {warm} warm"
    );
}

/// The first case: a thin ellipse inside another was `contained` one way and
/// `overlap` the other, with a zero-length chord outside the thin ellipse (a line of the pencil
/// within rounding of tangency to the outer ellipse, where the thin one almost touches it from
/// inside, taken for an external tangency).
#[test]
fn thin_ellipse_inside_another_is_contained_both_ways() {
    let outer = body(
        Shape::Ellipse { a: 2.0, b: 1.0 },
        [0.0, 0.0],
        0.7073711808010344,
    );
    let thin = body(
        Shape::Ellipse {
            a: 0.9100772226449461,
            b: 9.100772226449461e-5,
        },
        [-0.45351194105852477, -0.3516833244330534],
        2.302016886087467,
    );
    for (i, j) in [(outer, thin), (thin, outer)] {
        let g = contact(&i, &j).unwrap();
        assert_eq!(g.state, ContactState::Contained, "{g:?}");
        // The contact point of containment is the inner body's centre.
        assert_eq!(
            g.point,
            Vec2::new(-0.45351194105852477, -0.3516833244330534)
        );
    }
    let (a, b) = (contact(&outer, &thin), contact(&thin, &outer));
    compare(&a, &b, false).unwrap();
}

/// The second case: concentric rectangles (here a 2 × 1 and a 1 × 2 turned by a right
/// angle, and two different rectangles) gave a different depth and the same normal each way:
/// the fallback normal was i's own x axis.
#[test]
fn concentric_rectangles_are_swap_symmetric() {
    let r = |w: f64, h: f64, th: f64| body(Shape::Rectangle { w, h }, [0.0, 0.0], th);
    let half_turn = std::f64::consts::FRAC_PI_2;
    for (i, j) in [
        (r(2.0, 1.0, 0.4), r(1.0, 2.0, 0.4 + half_turn)),
        (r(2.0, 1.0, 0.4), r(1.0, 0.3, 1.0)),
        (r(2.0, 1.0, 0.4), r(2.0, 1.0, 1.0)),
    ] {
        let (a, b) = (contact(&i, &j), contact(&j, &i));
        compare(&a, &b, false).unwrap_or_else(|e| panic!("{e}: {i:?} / {j:?}"));
    }
}

/// The warm start of a lasting contact survives the canonical order, also when that order flips
/// from one step to the next: a pair of equal ellipses is computed with the one of smaller x
/// first, so a pair stacked almost vertically flips its order as the upper one drifts across
/// the lower one's x. The crossings it carries to the next step are always handed back
/// relative to the caller's i (re-expressed when the pair was computed the other way round):
/// the next step takes them (the Newton refinement answers) and gives the cold result to
/// rounding, whichever order each step computes in.
#[test]
fn warm_start_survives_the_canonical_order_flipping_between_steps() {
    use dem2d::narrow_phase::computed_first;
    use std::cell::Cell;
    let s = Shape::Ellipse { a: 1.5, b: 1.0 };
    let body = |pose: &Pose| Object::Body {
        shape: s,
        pose: *pose,
    };
    let pa = Pose::new(Vec2::new(0.0, 0.0), 0.1);
    // B above A at a horizontal offset x, at the height where they first touch (bisection on
    // the state), then 1e-3 of b lower: a shallow, lasting contact the warm path takes.
    let above = |x: f64| {
        let at = |y: f64| Pose::new(Vec2::new(x, y), -0.2);
        let (mut lo, mut hi) = (0.0, 2.5);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if contact(&body(&pa), &body(&at(mid))).is_none() {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        at(hi - 1e-3)
    };
    let (before, after) = (above(1e-4), above(-1e-4));
    // A first before the step, B first after it.
    assert!(computed_first(&s, &pa, &s, &before) && !computed_first(&s, &pa, &s, &after));
    for (from, to) in [(before, after), (after, before)] {
        for swap in [false, true] {
            // The pair queried through the dispatcher, with B as i when `swap`; whether the
            // cache's warm start gave the result.
            let call = |pb: &Pose, cache: &mut PairCache| {
                let used = Cell::new(false);
                let request = Request {
                    trace: Some(&used),
                    ..Request::FULL
                };
                let (i, j) = if swap {
                    (body(pb), body(&pa))
                } else {
                    (body(&pa), body(pb))
                };
                (contact_with(&i, &j, cache, request).unwrap(), used.get())
            };
            let mut cache = PairCache::default();
            call(&from, &mut cache);
            assert!(
                matches!(cache.warm(), Some(Warm::Crossings(_))),
                "{cache:?}"
            );
            let (cold, _) = call(&to, &mut PairCache::default());
            let (again, used) = call(&to, &mut cache);
            assert_eq!(cold.state, ContactState::Overlap);
            assert!(used, "last step's crossings were not taken (swap {swap})");
            let (g, h) = (cold, again);
            assert!((g.depth - h.depth).abs() <= 1e-14, "{g:?} vs {h:?}");
            assert!((g.normal - h.normal).norm() <= 1e-12, "{g:?} vs {h:?}");
        }
    }
}

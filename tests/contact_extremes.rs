//! Every pair kind at the extremes of the accepted input ranges (issue 11, item 16; the ranges
//! are `dem2d::scene::ranges`: sizes 1e-40 … 1e40, sizes of a pair within a factor 1e6,
//! coordinates within 1e9 × the smaller size and within 1e40).
//!
//! Pairs of every kind (circle, ellipse, rectangle, wall; every combination, both orders) are
//! drawn concentric, one inside the other, overlapping, separated and touching, at size ratios
//! 1, 1e3 and 1e6, near the origin and as far out as the ranges allow (a wall's point as far
//! along its line), and then scaled by an exact power of two to the smallest accepted sizes
//! (the smaller body at ~1e-40), to sizes of one, and to the largest (the larger body at
//! ~5e39). Each is checked against the double-double reference (`dem2d_validation::reference`)
//! with the bars of the hard-case families: the right state whenever the true depth or gap is at
//! least 1e-12·a_max (deep and contained always), |depth error| ≤ 1e-12·a_max, normal within
//! 1e-8 rad, point within 1e-9·a_max plus two ulps of the coordinates; for containment the
//! depth along the fallback's own normal (within 1e-12·a_max plus two ulps of itself: a body
//! 1e9 sizes deep in a wall has a depth of 1e9 sizes). Swapping i and j must give the same
//! result exactly.
//!
//! The reference is evaluated at sizes of order one and its lengths scaled by the same power of
//! two: the scaling is exact on every input, so the true geometry scales exactly too, while the
//! reference's own double-double arithmetic is not made for 1e±40 (its quartic's coefficients
//! are products of up to eight lengths: at 2^-132 it loses ~1e-4 of the depth, at 2^132 it
//! misjudges a deep pair).

use dem2d::geometry::{Shape, Vec2};
use dem2d::narrow_phase::{Contact, ContactState, Object, contact};
use dem2d::scene::ranges::{MAX_EXTENT_RATIO, MAX_MAGNITUDE, MIN_SCALE, Placed, check_extent};
use dem2d_validation::pairs::{
    ANGLE_BAR, CLASS_BAR, DEPTH_BAR, POINT_BAR, Spec, angle_between, same_state, support_point,
    ulp, unit,
};
use dem2d_validation::reference::{RContact, RState, depth_along, reference_contact};
use dem2d_validation::rng::Rng;

/// A shape of `kind` (0 circle, 1 ellipse, 2 rectangle) with an aspect ratio up to 3 and its
/// sizes within `lo … hi` (its larger size `hi` when it is the large body, its smaller `lo`
/// when it is the small one): the sizes of a pair then spread by at most `hi / lo`.
fn shape(kind: usize, large: bool, lo: f64, hi: f64, rng: &mut Rng) -> Shape {
    let aspect = rng.range(1.0, 3.0).min(hi / lo);
    let (big, small) = if large {
        (hi, hi / aspect)
    } else {
        (lo * aspect, lo)
    };
    match kind {
        0 => Shape::Circle {
            r: if large { hi } else { lo },
        },
        1 => Shape::Ellipse { a: big, b: small },
        _ => Shape::Rectangle { w: big, h: small },
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Config {
    Concentric,
    Contained,
    Overlap,
    Separated,
    Touching,
}

/// A pair at sizes of order one: the larger body of size 1, the other `1/ratio` (or of size
/// 1 and `1/ratio`-thin ellipses are not drawn here: ratios are between bodies), placed by
/// `cfg` with overlap or gap `nu` (in units of the smaller size) along `dir`, and moved to
/// `at`. Returns the pair, the construction direction and whether the state is decisive by
/// construction.
fn unit_pair(
    ki: usize,
    kj: usize,
    cfg: Config,
    ratio: f64,
    nu: f64,
    at: [f64; 2],
    rng: &mut Rng,
) -> (Spec, Spec, [f64; 2]) {
    let dir = unit(rng.angle());
    let (ti, tj) = (rng.angle(), rng.angle());
    // Which body is the small one.
    let small_j = rng.uniform() < 0.5;
    let plus = |c: [f64; 2]| [at[0] + c[0], at[1] + c[1]];
    if ki == 3 || kj == 3 {
        let kb = if ki == 3 { kj } else { ki };
        // Against a wall, the body alone: sizes 1/ratio … 1 (at ratio 1, a circle of 1).
        let sb = shape(kb, true, 1.0 / ratio, 1.0, rng);
        let n = dir;
        let h = {
            let p = support_point(&sb, ti, n);
            p[0] * n[0] + p[1] * n[1]
        };
        let small = sb.inscribed_radius();
        let far = at[0].hypot(at[1]);
        // "Concentric" against a wall: the body deep in the wall's solid, as far from the line
        // as the ranges allow (`far`); "separated" as far on the free side every other time.
        let depth = match cfg {
            Config::Concentric => 2.0 * h + 1.0 / ratio + far,
            Config::Contained => 2.0 * h + small * 1e-6,
            Config::Overlap => nu * small,
            Config::Separated if rng.uniform() < 0.5 => -nu * small - far,
            Config::Separated => -nu * small,
            Config::Touching => 0.0,
        };
        // The wall's foot under the body, and either the pair at the far point `at` or the
        // wall's point slid along the line by that much (the body near the origin). Body and
        // foot straddle the chosen place, so that at the largest sizes no coordinate leaves the
        // range.
        let (centre, slide) = if (depth - h).abs() > far {
            ([0.0, 0.0], 0.0) // already far apart across the line
        } else if rng.uniform() < 0.5 {
            ([0.0, 0.0], far)
        } else {
            (at, 0.0)
        };
        let half = 0.5 * (h - depth);
        let body_at = [centre[0] + half * n[0], centre[1] + half * n[1]];
        let foot = [
            centre[0] - half * n[0] - slide * n[1],
            centre[1] - half * n[1] + slide * n[0],
        ];
        let w = Spec::Wall(foot, n);
        let b = Spec::Body(sb, body_at, ti);
        return if ki == 3 {
            (w, b, n)
        } else {
            (b, w, [-n[0], -n[1]])
        };
    }
    let lo = 1.0 / ratio;
    let (si, sj) = (
        shape(ki, !small_j, lo, 1.0, rng),
        shape(kj, small_j, lo, 1.0, rng),
    );
    let smaller = si.inscribed_radius().min(sj.inscribed_radius());
    let cj = match cfg {
        Config::Concentric => [0.0, 0.0],
        Config::Contained => {
            // The small one at up to a third of the large one's inscribed radius from its
            // centre (at ratio ≥ 10 it lies well inside).
            let big = si.inscribed_radius().max(sj.inscribed_radius());
            let off = big * rng.range(0.0, 0.3);
            [off * dir[0], off * dir[1]]
        }
        Config::Overlap | Config::Separated | Config::Touching => {
            let nu = match cfg {
                Config::Overlap => nu * smaller,
                Config::Separated => -nu * smaller,
                _ => 0.0,
            };
            let (pi, pj) = (
                support_point(&si, ti, dir),
                support_point(&sj, tj, [-dir[0], -dir[1]]),
            );
            [pi[0] - pj[0] - nu * dir[0], pi[1] - pj[1] - nu * dir[1]]
        }
    };
    // The two centres straddle `at` (so that at the largest sizes no coordinate leaves the
    // range); far out they are rounded, and the reference sees the same rounded numbers.
    let pi = plus([-0.5 * cj[0], -0.5 * cj[1]]);
    let pj = plus([0.5 * cj[0], 0.5 * cj[1]]);
    (Spec::Body(si, pi, ti), Spec::Body(sj, pj, tj), dir)
}

/// Checks the scaled pair against the unit-size reference scaled by `k`; returns what failed.
fn check(i: &Spec, j: &Spec, along: [f64; 2], k: f64) -> Result<ContactState, String> {
    let (ri, rj) = (i.reference(), j.reference());
    let r: RContact = reference_contact(&ri, &rj);
    let (si, sj) = (i.scaled(k), j.scaled(k));
    // Within the accepted ranges.
    let sizes: Vec<f64> = si.sizes().into_iter().chain(sj.sizes()).collect();
    for &s in &sizes {
        assert!(
            (MIN_SCALE..=MAX_MAGNITUDE).contains(&s),
            "size {s:e} outside the range"
        );
    }
    for s in [&si, &sj] {
        for c in s.coordinates() {
            assert!(c.abs() <= MAX_MAGNITUDE, "coordinate {c:e} beyond 1e40");
        }
    }
    let placed: Vec<Placed> = [(&si, "i"), (&sj, "j")]
        .iter()
        .map(|(s, name)| match s.object() {
            Object::Body { shape, pose } => Placed::Body {
                path: name.to_string(),
                shape: Box::leak(Box::new(shape)),
                position: pose.position,
            },
            Object::Wall(w) => Placed::Wall {
                path: name.to_string(),
                point: w.point,
            },
            Object::Segment(_) | Object::Drum(_) => {
                unreachable!("the generator makes no segment walls or drums")
            }
        })
        .collect();
    check_extent(&placed).map_err(|e| format!("generator left the ranges: {e:?}"))?;

    let (oi, oj) = (si.object(), sj.object());
    let kc: Option<Contact> = contact(&oi, &oj);
    let ks: Option<Contact> = contact(&oj, &oi);
    // Swap: exact (the normal only when i and j can be told apart: two equal circles with
    // one centre, or two equal shapes in one pose, are one object twice).
    let identical = match (oi, oj) {
        (
            Object::Body {
                shape: Shape::Circle { r: a },
                pose: p,
            },
            Object::Body {
                shape: Shape::Circle { r: b },
                pose: q,
            },
        ) => a == b && p.position == q.position,
        _ => oi == oj,
    };
    let swapped_ok = match (kc, ks) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.state == b.state
                && a.depth == b.depth
                && a.point == b.point
                && (identical || a.normal == -b.normal)
        }
        (Some(_), None) | (None, Some(_)) => false,
    };
    if !swapped_ok {
        return Err(format!("swap: {kc:?} vs {ks:?}"));
    }
    let a_max = i.size().max(j.size()); // at unit size
    let along_depth = depth_along(&ri, &rj, along);
    let decisive = match r.state {
        RState::Overlap => r.depth.unwrap() >= CLASS_BAR * a_max,
        RState::Separated => along_depth <= -CLASS_BAR * a_max,
        RState::Deep(_) | RState::Contained => true,
        RState::Touching => false,
    };
    let state = ContactState::of(kc.as_ref());
    if decisive && !same_state(state, r.state) {
        return Err(format!(
            "state {:?}, reference {:?} (depth {:?})",
            state, r.state, r.depth
        ));
    }
    let Some(g) = kc else {
        return Ok(state);
    };
    if !(g.depth.is_finite() && g.point.x.is_finite() && g.point.y.is_finite()) {
        return Err(format!("non-finite geometry {g:?}"));
    }
    let depth = g.depth / k; // back to unit size (exact)
    match state {
        ContactState::Overlap | ContactState::Touching => {
            let (Some(rd), Some(rn), Some(rp)) = (r.depth, r.normal, r.point_rel) else {
                return Ok(state); // reference touching without a normal (two corners)
            };
            let de = (depth - rd).abs() / a_max;
            let touching = state == ContactState::Touching || r.state == RState::Touching;
            let ae = angle_between(g.normal, rn);
            // Two rectangles corner on corner: their chord joins two intersections of edge lines
            // whose positions carry the rounding of the rotated half-sizes (ε·a_max), so its
            // normal is known to ~ε·a_max/(chord · sin θ), θ the angle between the edges (the
            // families' bar for that case; see docs/src/validation/geometry.md).
            let angle_bar = match (i, j) {
                (
                    Spec::Body(Shape::Rectangle { .. }, _, ti),
                    Spec::Body(Shape::Rectangle { .. }, _, tj),
                ) if r.crossings.len() == 2 => {
                    let [p, q] = [r.crossings[0], r.crossings[1]];
                    let chord = (q[0] - p[0]).hypot(q[1] - p[1]);
                    let sin_theta = (tj - ti).sin().abs().min((tj - ti).cos().abs());
                    ANGLE_BAR.max(2.0 * 16.0 * f64::EPSILON * a_max / (chord * sin_theta))
                }
                _ => ANGLE_BAR,
            };
            let point = (g.point / k) - Vec2::from(r.origin);
            let round = 2.0 * ulp(g.point.x / k).max(ulp(g.point.y / k));
            let pe = (((point - Vec2::from(rp)).norm()) - round).max(0.0) / a_max;
            if de > DEPTH_BAR || (!touching && (ae > angle_bar || pe > POINT_BAR)) {
                return Err(format!(
                    "depth err {de:.2e}, angle err {ae:.2e}, point err {pe:.2e} (state {:?}, \
                     reference {:?})",
                    state, r.state
                ));
            }
        }
        ContactState::Deep | ContactState::Contained => {
            let rd = depth_along(&ri, &rj, [g.normal.x, g.normal.y]);
            // A body 1e9 sizes deep in a wall has a depth of 1e9 sizes, which a double holds
            // only to its own last bits: the bar is 1e-12·a_max beyond two ulps of the depth.
            let de = ((depth - rd).abs() - 2.0 * ulp(rd)).max(0.0) / a_max;
            if de > DEPTH_BAR {
                return Err(format!("fallback depth err {de:.2e} ({:?})", state));
            }
        }
        ContactState::Separated => {}
    }
    Ok(state)
}

#[test]
fn every_pair_kind_is_right_at_the_extremes_of_the_accepted_ranges() {
    let names = ["circle", "ellipse", "rectangle", "wall"];
    let mut rng = Rng(0x0E57_0016);
    let mut failures = Vec::new();
    let mut counts = std::collections::BTreeMap::new();
    let mut total = 0;
    for ki in 0..4 {
        for kj in 0..4 {
            if ki == 3 && kj == 3 {
                continue;
            }
            for ratio in [1.0, 1e3, 1e6] {
                // The scales: the smaller size at ~1e-40 (the smallest accepted), sizes of
                // order one, the larger size at ~5e39 (below the largest, 1e40).
                let small = 2f64.powi((ratio * MIN_SCALE).log2().ceil() as i32);
                for k in [small, 1.0, 2f64.powi(132)] {
                    for cfg in [
                        Config::Concentric,
                        Config::Contained,
                        Config::Overlap,
                        Config::Separated,
                        Config::Touching,
                    ] {
                        if cfg == Config::Contained && ratio < 10.0 && ki != 3 && kj != 3 {
                            continue; // equal sizes cannot nest
                        }
                        for rep in 0..12 {
                            let nu = [1e-9, 1e-6, 1e-4, 1e-2, 0.1, 0.5][rep % 6];
                            // As far out as the ranges allow (1e9 × the smaller size, and
                            // within 1e40), in units of the unit-size pair; or at the origin.
                            let reach = (MAX_EXTENT_RATIO / ratio)
                                .min((0.5 * MAX_MAGNITUDE / k - 1.0).max(0.0));
                            let far = if rep % 2 == 0 {
                                0.0
                            } else {
                                reach * rng.range(0.5, 0.9)
                            };
                            let d = unit(rng.angle());
                            let at = [far * d[0], far * d[1]];
                            let (i, j, along) = unit_pair(ki, kj, cfg, ratio, nu, at, &mut rng);
                            total += 1;
                            match check(&i, &j, along, k) {
                                Ok(state) => {
                                    *counts
                                        .entry((names[ki], names[kj], state.as_str()))
                                        .or_insert(0) += 1
                                }
                                Err(e) => failures.push(format!(
                                    "{}–{} {cfg:?} ratio {ratio:e} scale {k:e} ν {nu:e} at {far:e}: \
                                     {e}\n    i = {:?}\n    j = {:?}",
                                    names[ki],
                                    names[kj],
                                    i.scaled(k),
                                    j.scaled(k)
                                )),
                            }
                        }
                    }
                }
            }
        }
    }
    for ((i, j, s), n) in &counts {
        println!("{i:>9}–{j:<9} {s:<10} {n}");
    }
    assert!(
        failures.is_empty(),
        "{} of {total} pairs wrong at the extremes; first ones:\n{}",
        failures.len(),
        failures
            .iter()
            .take(10)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}

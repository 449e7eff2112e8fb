//! The hard-case families of the contact kernel, checked against the independent reference
//! ([`super::reference`]: double-double, parametric boundary ∩ implicit form solved as a quartic,
//! no pencil, no cubic).
//!
//! Bars (from the kernel issue): |depth error| ≤ 1e-12·a_max; normal angle error ≤ 1e-8 rad;
//! contact point error ≤ 1e-9·a_max plus two ulps of the coordinates (far from the origin);
//! classification right whenever the true gap or depth is at least 1e-12·a_max; the same results
//! after a rigid motion of the pair and after swapping i and j. `tests/geometry_hard_cases.rs`
//! asserts them; `dem2d figures` tabulates the worst errors with the kernel's time per pair.

use super::pairs::{
    ANGLE_BAR, CLASS_BAR, DEPTH_BAR, POINT_BAR, Spec, angle_between, same_state, support,
    support_point, ulp, unit,
};
use super::reference::{RContact, RState, depth_along, reference_contact};
use crate::rng::Rng;
use dem2d::geometry::{Shape, Vec2};
use dem2d::narrow_phase::ellipse_ellipse::Warm;
use dem2d::narrow_phase::{
    Contact, ContactState, Object, PairCache, Request, contact, contact_with,
};

/// A pair with the direction it was built along (for the true gap along it).
struct Case {
    i: Spec,
    j: Spec,
    along: [f64; 2],
}

impl Case {
    /// The same pair with i and j exchanged (the build direction flips with them).
    fn swapped(self) -> Case {
        Case {
            i: self.j,
            j: self.i,
            along: [-self.along[0], -self.along[1]],
        }
    }
}

/// +1 for even `k`, −1 for odd: families alternate overlap and separation.
fn alternate(k: usize) -> f64 {
    if k.is_multiple_of(2) { 1.0 } else { -1.0 }
}

/// Body j of `sj` at angle `tj` placed against body i so that j's extreme point along −n sits on
/// i's extreme point along n (external tangency, common normal n), then moved by `nu` towards i
/// (`nu > 0` overlaps by ν along n, `nu < 0` leaves a gap |ν| along the separating axis n).
/// `origin` is i's position.
fn place(si: Shape, ti: f64, sj: Shape, tj: f64, n: [f64; 2], nu: f64, origin: [f64; 2]) -> Case {
    let pi = support_point(&si, ti, n);
    let pj = support_point(&sj, tj, [-n[0], -n[1]]);
    let c = [pi[0] - pj[0] - nu * n[0], pi[1] - pj[1] - nu * n[1]];
    Case {
        i: Spec::Body(si, origin, ti),
        j: Spec::Body(sj, [origin[0] + c[0], origin[1] + c[1]], tj),
        along: n,
    }
}

/// A wall (as i) under body j with overlap `nu` along the wall normal `n`.
fn place_wall(sj: Shape, tj: f64, n: [f64; 2], nu: f64, pos: [f64; 2]) -> Case {
    let h = support(&sj, tj, n) - nu;
    Case {
        i: Spec::Wall([pos[0] - h * n[0], pos[1] - h * n[1]], n),
        j: Spec::Body(sj, pos, tj),
        along: n,
    }
}

/// The same pair moved out to 1e5 … 1e6 from the origin in a random direction (both bodies; the
/// positions are rounded there, and the reference sees the same rounded numbers), and a wall's
/// point slid along its line by up to 1e6 either way, so that the wall's distance to the body is
/// taken across up to ~1.4e6.
fn far(c: Case, rng: &mut Rng) -> Case {
    let dir = unit(rng.angle());
    let r = rng.range(1e5, 1e6);
    let slide = rng.range(-1e6, 1e6);
    let shift = |s: Spec| match s {
        Spec::Body(shape, p, t) => Spec::Body(shape, [p[0] + r * dir[0], p[1] + r * dir[1]], t),
        Spec::Wall(p, n) => {
            let len = n[0].hypot(n[1]);
            let t = [-n[1] / len, n[0] / len];
            Spec::Wall(
                [
                    p[0] + r * dir[0] + slide * t[0],
                    p[1] + r * dir[1] + slide * t[1],
                ],
                n,
            )
        }
    };
    Case {
        i: shift(c.i),
        j: shift(c.j),
        along: c.along,
    }
}

/// What one family measured: worst errors (depth and point in units of a_max, normal in
/// radians; rigid motion and swap in units of the bars), misclassifications, the first
/// failures, and the pairs themselves (for timing).
#[derive(Clone, Debug, Default)]
pub struct FamilyReport {
    pub name: String,
    pub cases: usize,
    pub depth: f64,
    pub angle: f64,
    pub point: f64,
    pub class_errors: usize,
    pub class_checked: usize,
    pub motion: f64,
    pub swap: f64,
    /// Warm start (the dynamics' path for a lasting conic pair): pairs tried from a perturbed
    /// copy of what the kernel carries to the next step, how many the warm path answered, and
    /// the worst error of those answers in units of the bars.
    pub warm_checked: usize,
    pub warm_used: usize,
    pub warm: f64,
    pub failures: Vec<String>,
    pub pairs: Vec<(Object, Object)>,
}

/// The state of a query's result (`None`: apart).
fn state(c: &Option<Contact>) -> ContactState {
    ContactState::of(c.as_ref())
}

/// Differences between two kernel results of the same pair (for swap and rigid motion):
/// the largest of depth difference / a_max, point distance / a_max (beyond rounding), and
/// normal angle; `map` carries the second result's vectors back to the first's frame.
fn result_difference(
    a: &Option<Contact>,
    b: &Option<Contact>,
    scale: f64,
    flip: bool,
    map: impl Fn(Vec2) -> Vec2,
    round: f64,
    angle_bar: f64,
) -> f64 {
    if state(a) != state(b) {
        return f64::INFINITY;
    }
    let (Some(ga), Some(gb)) = (a, b) else {
        return 0.0;
    };
    let nb = if flip {
        -map(gb.normal)
    } else {
        map(gb.normal)
    };
    let pb = map(gb.point);
    let dd = (ga.depth - gb.depth).abs() / scale / DEPTH_BAR;
    let dn = angle_between(ga.normal, [nb.x, nb.y]) / angle_bar;
    let dp = ((ga.point - pb).norm() - round).max(0.0) / scale / POINT_BAR;
    dd.max(dn).max(dp)
}

/// Checks one case; returns nothing, records worst errors (in units of the bars for
/// motion/swap, absolute relative errors otherwise).
// clippy 1.95 would chain the warm-path `if let`s; left nested, as the narrow-phase rewrite has them.
#[allow(clippy::collapsible_if)]
fn check(case: &Case, rng: &mut Rng, st: &mut FamilyReport, label: &str, conditioned_normal: bool) {
    let (oi, oj) = (case.i.object(), case.j.object());
    let (ri, rj) = (case.i.reference(), case.j.reference());
    let scale = case.i.size().max(case.j.size());
    let k = contact(&oi, &oj);
    let r: RContact = reference_contact(&ri, &rj);
    st.cases += 1;
    if std::env::var("DEM2D_DEBUG_FAMILY").is_ok_and(|f| label.contains(&f)) {
        eprintln!(
            "{label}: kernel {:?} depth {:?}; reference {:?} depth {:?}",
            state(&k),
            k.map(|g| g.depth),
            r.state,
            r.depth
        );
    }
    // True penetration along the construction direction (DD), for the classification rule.
    let along = depth_along(&ri, &rj, case.along);
    let ref_depth = r.depth;
    let decisive = match r.state {
        RState::Overlap => ref_depth.unwrap() >= CLASS_BAR * scale,
        RState::Separated => along <= -CLASS_BAR * scale,
        RState::Deep(_) | RState::Contained => true,
        RState::Touching => false,
    };
    if decisive {
        st.class_checked += 1;
        if !same_state(state(&k), r.state) {
            st.class_errors += 1;
            st.failures.push(format!(
                "{label}: state {:?} vs reference {:?} ({case_i:?} / {case_j:?})",
                state(&k),
                r.state,
                case_i = case.i,
                case_j = case.j
            ));
            return;
        }
    }
    // The normal bar: 1e-8 rad, or for corner-to-corner rectangle contacts the conditioning of a
    // chord through two line intersections whose corners carry ε·L rounding: 32ε·L/|chord|.
    let chord_len = if r.crossings.len() == 2 {
        (r.crossings[1][0] - r.crossings[0][0]).hypot(r.crossings[1][1] - r.crossings[0][1])
    } else {
        0.0
    };
    // Each crossing is the intersection of an edge of i with an edge of j, which meet at an
    // angle θ with sin θ ≥ min(|sin φ|, |cos φ|) (φ the relative rotation of the rectangles), so
    // an error e in the position of an edge moves a crossing by e/sin θ.
    let sin_theta = match (case.i, case.j) {
        (Spec::Body(_, _, ti), Spec::Body(_, _, tj)) => {
            (tj - ti).sin().abs().min((tj - ti).cos().abs())
        }
        _ => 1.0,
    };
    let conditioned = |edge_error: f64| {
        if conditioned_normal && chord_len > 0.0 {
            ANGLE_BAR.max(2.0 * edge_error / (chord_len * sin_theta))
        } else {
            ANGLE_BAR
        }
    };
    let angle_bar = conditioned(16.0 * f64::EPSILON * scale);
    // Geometry against the reference where the chord definition applies: depth, normal and
    // point errors (depth and point over a_max) and whether only the depth is meaningful.
    let errors = |k: &Option<Contact>| -> Option<(f64, f64, f64, bool)> {
        let (g, rd, rn, rp) = ((*k)?, ref_depth?, r.normal?, r.point_rel?);
        if !matches!(g.state, ContactState::Overlap | ContactState::Touching) {
            return None;
        }
        let de = (g.depth - rd).abs() / scale;
        let ae = angle_between(g.normal, rn);
        let origin = Vec2::from(r.origin);
        let round = 2.0 * ulp(g.point.x).max(ulp(g.point.y));
        let pe = (((g.point - origin) - Vec2::from(rp)).norm() - round).max(0.0) / scale;
        // A touching result's point and normal are only meaningful to the order of the
        // crossings' own spread (they merge at tangency): compare depth only then.
        let touching = g.state == ContactState::Touching || r.state == RState::Touching;
        Some((de, ae, pe, touching))
    };
    if let Some((de, ae, pe, touching)) = errors(&k) {
        st.depth = st.depth.max(de);
        if !touching {
            st.angle = st.angle.max(ae);
            st.point = st.point.max(pe);
        }
        if de > DEPTH_BAR || (!touching && (ae > angle_bar || pe > POINT_BAR)) {
            st.failures.push(format!(
                "{label}: depth err {de:.2e}, angle err {ae:.2e}, point err {pe:.2e} ({:?} / {:?})",
                case.i, case.j
            ));
        }
    }
    // The warm path: the pair again, started from a perturbed copy of what the kernel carries
    // to the next step in its pair cache (crossings moved by up to 1e-4·a_max, an axis turned by
    // up to 0.02 rad: more than one step of motion), held to the same bars.
    if let (Object::Body { .. }, Object::Body { .. }) = (&oi, &oj) {
        let mut cache = PairCache::default();
        contact_with(&oi, &oj, &mut cache, Request::FULL);
        if let Some(carried) = cache.warm() {
            let mut jitter = || (rng.uniform() - 0.5) * 2e-4 * scale;
            let guess = match carried {
                Warm::Crossings([p, q]) => Warm::Crossings([
                    [p[0] + jitter(), p[1] + jitter()],
                    [q[0] + jitter(), q[1] + jitter()],
                ]),
                Warm::Axis([c, s]) => {
                    let t = (rng.uniform() - 0.5) * 0.04;
                    let (st_, ct) = t.sin_cos();
                    Warm::Axis([c * ct - s * st_, s * ct + c * st_])
                }
            };
            let used = std::cell::Cell::new(false);
            let traced = Request {
                trace: Some(&used),
                ..Request::FULL
            };
            let kw = contact_with(&oi, &oj, &mut PairCache::with_warm(Some(guess)), traced);
            let used = used.get();
            st.warm_checked += 1;
            st.warm_used += used as usize;
            if decisive && !same_state(state(&kw), r.state) {
                st.class_errors += 1;
                st.warm = f64::INFINITY;
                st.failures.push(format!(
                    "{label}: warm start gives state {:?} vs reference {:?} ({:?} / {:?})",
                    state(&kw),
                    r.state,
                    case.i,
                    case.j
                ));
            } else if let Some((de, ae, pe, touching)) = errors(&kw) {
                let bars = if touching {
                    de / DEPTH_BAR
                } else {
                    (de / DEPTH_BAR).max(ae / angle_bar).max(pe / POINT_BAR)
                };
                st.warm = st.warm.max(bars);
                if bars > 1.0 {
                    st.failures.push(format!(
                        "{label}: warm start: depth err {de:.2e}, angle err {ae:.2e}, point err {pe:.2e} ({:?} / {:?})",
                        case.i, case.j
                    ));
                }
            }
        }
    }
    if let Some(g) = k
        && matches!(g.state, ContactState::Deep | ContactState::Contained)
    {
        // The fallback's depth is the penetration along its own normal: check that against the
        // reference's depth along the same direction.
        let rd = depth_along(&ri, &rj, [g.normal.x, g.normal.y]);
        let de = (g.depth - rd).abs() / scale;
        st.depth = st.depth.max(de);
        if de > DEPTH_BAR {
            st.failures.push(format!(
                "{label}: fallback depth err {de:.2e} ({:?} / {:?})",
                case.i, case.j
            ));
        }
    }
    // Swap symmetry.
    let ks = contact(&oj, &oi);
    // A touching result's normal is arbitrary where both boundaries have corners.
    let sw = if !decisive
        && (state(&k) == ContactState::Touching || state(&ks) == ContactState::Touching)
    {
        0.0
    } else {
        result_difference(&k, &ks, scale, true, |v| v, 0.0, angle_bar)
    };
    st.swap = st.swap.max(sw);
    if sw > 1.0 {
        st.failures.push(format!(
            "{label}: swap differs by {sw:.2e} bars ({:?} / {:?})",
            case.i, case.j
        ));
    }
    // Rigid motion of the pair (rotation about the origin plus a translation).
    let psi = rng.angle();
    let t = [rng.range(-50.0, 50.0), rng.range(-50.0, 50.0)];
    let (mi, mj) = (case.i.moved(psi, t), case.j.moved(psi, t));
    let km = contact(&mi.object(), &mj.object());
    let (s, c) = psi.sin_cos();
    // Carry the moved result back: rotate by −ψ after removing the translation.
    let back = |v: Vec2, is_point: bool| {
        let w = if is_point { v - Vec2::from(t) } else { v };
        Vec2::new(c * w.x + s * w.y, -s * w.x + c * w.y)
    };
    let coord = |s: &Spec| match *s {
        Spec::Body(_, p, _) | Spec::Wall(p, _) => p[0].abs().max(p[1].abs()),
    };
    // Moving the inputs rounds each coordinate by half an ulp of its size: the true geometry of
    // the moved pair differs from the exact motion of the original by up to about that much.
    let far = coord(&case.i)
        .max(coord(&case.j))
        .max(coord(&mi))
        .max(coord(&mj));
    let round = 4.0 * ulp(far);
    let margin = match r.state {
        RState::Overlap => ref_depth.unwrap(),
        RState::Separated => -along,
        RState::Deep(_) | RState::Contained => f64::INFINITY,
        RState::Touching => 0.0,
    };
    if margin >= CLASS_BAR * scale + 4.0 * round {
        if state(&k) != state(&km) {
            st.failures.push(format!(
                "{label}: rigid motion changes the state {:?} → {:?} ({:?} / {:?})",
                state(&k),
                state(&km),
                case.i,
                case.j
            ));
            return;
        }
        // The contained fallback's normal follows the line of centres, which rounding of the
        // moved inputs turns by (rounding)/(distance of centres): compare its state only.
        if state(&k) == ContactState::Contained {
            return;
        }
        let mut kmb = km;
        if let Some(g) = &mut kmb {
            g.point = back(g.point, true);
            g.normal = back(g.normal, false);
        }
        // The moved inputs carry their own rounding: for a conditioned normal that adds
        // (rounding)/(chord·sin θ).
        let motion_bar = conditioned(16.0 * f64::EPSILON * scale + 2.0 * round);
        let mv = result_difference(&k, &kmb, scale, false, |v| v, 2.0 * round, motion_bar);
        // Depth moves with the inputs' rounding too: allow that on top of the bar.
        let mv = (mv - 2.0 * round / scale / DEPTH_BAR).max(0.0);
        st.motion = st.motion.max(mv);
        if mv > 1.0 {
            st.failures.push(format!(
                "{label}: rigid motion changes the result by {mv:.2e} bars ({:?} / {:?})",
                case.i, case.j
            ));
        }
    }
}

/// Runs a family and records its report.
fn family(
    name: &str,
    reports: &mut Vec<FamilyReport>,
    mut make: impl FnMut(&mut Rng, usize) -> Option<Case>,
    n: usize,
) {
    family_with(name, reports, &mut make, n, false)
}

fn family_with(
    name: &str,
    reports: &mut Vec<FamilyReport>,
    make: &mut dyn FnMut(&mut Rng, usize) -> Option<Case>,
    n: usize,
    conditioned_normal: bool,
) {
    let mut rng = Rng(0xD1B5_4A32_D192_ED03 ^ (name.len() as u64).wrapping_mul(0x9E37_79B9));
    let mut st = FamilyReport {
        name: name.to_string(),
        ..Default::default()
    };
    for k in 0..n {
        if let Some(case) = make(&mut rng, k) {
            st.pairs.push((case.i.object(), case.j.object()));
            check(&case, &mut rng, &mut st, name, conditioned_normal);
        }
    }
    reports.push(st);
}

/// The Markdown table of the reports; with `ns_per_pair`, a column of the kernel's median time.
pub fn markdown_table(reports: &[FamilyReport], ns_per_pair: Option<&[f64]>) -> String {
    let mut t = String::from(
        "| family | cases | worst depth err / a_max | worst normal err (rad) | worst point err / a_max | misclassified / checked | rigid motion (bars) | swap (bars) | warm start: answered / tried, worst (bars) |",
    );
    t.push_str(if ns_per_pair.is_some() {
        " ns/pair |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    } else {
        "\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    });
    for (k, r) in reports.iter().enumerate() {
        let warm = if r.warm_checked == 0 {
            "—".to_string()
        } else {
            format!("{}/{}, {:.2}", r.warm_used, r.warm_checked, r.warm)
        };
        t.push_str(&format!(
            "| {} | {} | {:.1e} | {:.1e} | {:.1e} | {}/{} | {:.2} | {:.2} | {warm} |",
            r.name,
            r.cases,
            r.depth,
            r.angle,
            r.point,
            r.class_errors,
            r.class_checked,
            r.motion,
            r.swap
        ));
        if let Some(ns) = ns_per_pair {
            t.push_str(&format!(" {:.0} |", ns[k]));
        }
        t.push('\n');
    }
    t
}

const DEPTHS: [f64; 9] = [1e-12, 1e-11, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2, 0.1, 0.3];
const ASPECTS: [f64; 5] = [1.0, 1.0 + 1e-9, 1.5, 10.0, 100.0];

/// Every family of hard cases, each checked against the reference.
pub fn run_families() -> Vec<FamilyReport> {
    let mut reports = Vec::new();

    // Ellipse pairs: every aspect ratio × every overlap depth, random orientations and sizes.
    for &aspect in &ASPECTS {
        let name = format!("ellipse–ellipse, a/b = {aspect}, overlap 1e-12…0.3 b");
        family(
            &name,
            &mut reports,
            |rng, k| {
                let a_i = 1.0;
                let a_j = rng.range(0.5, 2.0);
                let si = Shape::Ellipse {
                    a: a_i,
                    b: a_i / aspect,
                };
                let sj = Shape::Ellipse {
                    a: a_j,
                    b: a_j / aspect,
                };
                let b = (a_i / aspect).min(a_j / aspect);
                let nu = DEPTHS[k % DEPTHS.len()] * b;
                Some(place(
                    si,
                    rng.angle(),
                    sj,
                    rng.angle(),
                    unit(rng.angle()),
                    nu,
                    [0.0, 0.0],
                ))
            },
            9 * 40,
        );
    }
    family(
        "ellipse–ellipse separated by 1e-12…0.3 b",
        &mut reports,
        |rng, k| {
            let aspect = ASPECTS[k % ASPECTS.len()];
            let si = Shape::Ellipse {
                a: 1.0,
                b: 1.0 / aspect,
            };
            let sj = Shape::Ellipse {
                a: 1.3,
                b: 1.3 / aspect,
            };
            let nu = -DEPTHS[(k / 5) % DEPTHS.len()] / aspect;
            Some(place(
                si,
                rng.angle(),
                sj,
                rng.angle(),
                unit(rng.angle()),
                nu,
                [0.0, 0.0],
            ))
        },
        450,
    );
    family(
        "identical shapes, identical orientation",
        &mut reports,
        |rng, k| {
            let aspect = ASPECTS[k % ASPECTS.len()];
            let s = Shape::Ellipse {
                a: 1.5,
                b: 1.5 / aspect,
            };
            let th = rng.angle();
            let nu = DEPTHS[(k / 5) % DEPTHS.len()] * 1.5 / aspect * alternate(k);
            Some(place(s, th, s, th, unit(rng.angle()), nu, [0.0, 0.0]))
        },
        450,
    );
    let circle_ellipse = |rng: &mut Rng, k: usize| -> Option<Case> {
        let aspect = ASPECTS[(k / 9) % ASPECTS.len()];
        let sc = Shape::Circle {
            r: rng.range(0.3, 2.0),
        };
        let se = Shape::Ellipse {
            a: 1.0,
            b: 1.0 / aspect,
        };
        let nu = DEPTHS[k % DEPTHS.len()] / aspect;
        let c = place(sc, 0.0, se, rng.angle(), unit(rng.angle()), nu, [0.0, 0.0]);
        Some(if k.is_multiple_of(2) { c } else { c.swapped() })
    };
    family("circle–ellipse", &mut reports, &circle_ellipse, 450);
    let circle_circle = |rng: &mut Rng, k: usize| -> Option<Case> {
        let si = Shape::Circle {
            r: rng.range(0.3, 2.0),
        };
        let sj = Shape::Circle {
            r: rng.range(0.3, 2.0),
        };
        let nu = DEPTHS[k % DEPTHS.len()] * if k.is_multiple_of(2) { 0.3 } else { -0.3 };
        Some(place(si, 0.0, sj, 0.0, unit(rng.angle()), nu, [0.0, 0.0]))
    };
    family("circle–circle", &mut reports, &circle_circle, 360);
    family(
        "ellipse pairs 1e6 from the origin",
        &mut reports,
        |rng, k| {
            let aspect = ASPECTS[k % ASPECTS.len()];
            let si = Shape::Ellipse {
                a: 1.0,
                b: 1.0 / aspect,
            };
            let sj = Shape::Ellipse {
                a: 0.8,
                b: 0.8 / aspect,
            };
            let nu = DEPTHS[(k / 5) % DEPTHS.len()] * 0.8 / aspect;
            let o = unit(rng.angle());
            let r = rng.range(1e5, 1e6);
            Some(place(
                si,
                rng.angle(),
                sj,
                rng.angle(),
                unit(rng.angle()),
                nu,
                [r * o[0], r * o[1]],
            ))
        },
        450,
    );
    family(
        "exact tangency (ν = 0)",
        &mut reports,
        |rng, k| {
            let aspect = ASPECTS[k % ASPECTS.len()];
            let si = Shape::Ellipse {
                a: 1.0,
                b: 1.0 / aspect,
            };
            let sj = if k.is_multiple_of(3) {
                Shape::Circle { r: 0.7 }
            } else {
                Shape::Ellipse {
                    a: 0.7,
                    b: 0.7 / aspect,
                }
            };
            Some(place(
                si,
                rng.angle(),
                sj,
                rng.angle(),
                unit(rng.angle()),
                0.0,
                [0.0, 0.0],
            ))
        },
        300,
    );
    let crossed = |rng: &mut Rng, _: usize| -> Option<Case> {
        let aspect = rng.range(2.0, 20.0);
        let si = Shape::Ellipse {
            a: 1.0,
            b: 1.0 / aspect,
        };
        let sj = Shape::Ellipse {
            a: rng.range(0.8, 1.2),
            b: 1.0 / aspect,
        };
        let ti = rng.angle();
        let tj = ti + std::f64::consts::FRAC_PI_2 + rng.range(-0.6, 0.6);
        let off = rng.range(0.0, 0.3);
        let dir = unit(rng.angle());
        Some(Case {
            i: Spec::Body(si, [0.0, 0.0], ti),
            j: Spec::Body(sj, [off * dir[0], off * dir[1]], tj),
            along: dir,
        })
    };
    family(
        "four crossings (crossed ellipses)",
        &mut reports,
        &crossed,
        300,
    );
    let containment = |rng: &mut Rng, k: usize| -> Option<Case> {
        let aspect = ASPECTS[k % ASPECTS.len()].min(10.0);
        let si = Shape::Ellipse {
            a: 2.0,
            b: 2.0 / aspect,
        };
        let small = 0.2 / aspect;
        let sj = if k.is_multiple_of(2) {
            Shape::Circle { r: small }
        } else {
            Shape::Ellipse {
                a: small,
                b: small * 0.6,
            }
        };
        let ti = rng.angle();
        let dir = unit(rng.angle());
        let off = rng.range(0.0, 0.5) / aspect;
        let c = Case {
            i: Spec::Body(si, [0.0, 0.0], ti),
            j: Spec::Body(sj, [off * dir[0], off * dir[1]], rng.angle()),
            along: dir,
        };
        Some(if k % 4 == 1 {
            Case {
                i: c.j,
                j: c.i,
                along: dir,
            }
        } else {
            c
        })
    };
    family("containment", &mut reports, &containment, 200);
    // Walls and rectangles.
    let wall_conic = |rng: &mut Rng, k: usize| -> Option<Case> {
        let aspect = ASPECTS[k % ASPECTS.len()];
        let s = if k.is_multiple_of(4) {
            Shape::Circle { r: 1.0 }
        } else {
            Shape::Ellipse {
                a: 1.0,
                b: 1.0 / aspect,
            }
        };
        let nu = DEPTHS[(k / 5) % DEPTHS.len()] / aspect * alternate(k);
        let far = if k.is_multiple_of(3) { 1e6 } else { 0.0 };
        let c = place_wall(s, rng.angle(), unit(rng.angle()), nu, [far, -far]);
        Some(if k % 5 == 2 { c.swapped() } else { c })
    };
    family(
        "wall–ellipse/circle (incl. 1e6)",
        &mut reports,
        &wall_conic,
        450,
    );
    let wall_rectangle = |rng: &mut Rng, k: usize| -> Option<Case> {
        let s = Shape::Rectangle {
            w: 1.0,
            h: rng.range(0.1, 1.0),
        };
        let nu = DEPTHS[k % DEPTHS.len()] * 0.1 * alternate(k);
        let th = if k.is_multiple_of(7) {
            0.0
        } else {
            rng.angle()
        };
        Some(place_wall(s, th, unit(rng.angle()), nu, [0.0, 0.0]))
    };
    family("wall–rectangle", &mut reports, &wall_rectangle, 360);
    let rectangle_conic = |rng: &mut Rng, k: usize| -> Option<Case> {
        let sr = Shape::Rectangle {
            w: 1.0,
            h: rng.range(0.2, 1.0),
        };
        let aspect = ASPECTS[k % ASPECTS.len()].min(10.0);
        let se = if k.is_multiple_of(3) {
            Shape::Circle {
                r: rng.range(0.2, 1.0),
            }
        } else {
            Shape::Ellipse {
                a: 0.8,
                b: 0.8 / aspect,
            }
        };
        let nu = DEPTHS[(k / 5) % DEPTHS.len()] * 0.08 * alternate(k);
        let c = place(
            sr,
            rng.angle(),
            se,
            rng.angle(),
            unit(rng.angle()),
            nu,
            [0.0, 0.0],
        );
        Some(if k % 4 == 3 { c.swapped() } else { c })
    };
    family(
        "rectangle–ellipse/circle",
        &mut reports,
        &rectangle_conic,
        450,
    );
    let rectangle_face = |rng: &mut Rng, k: usize| -> Option<Case> {
        let si = Shape::Rectangle {
            w: 1.0,
            h: rng.range(0.2, 1.0),
        };
        let sj = Shape::Rectangle {
            w: rng.range(0.3, 1.5),
            h: rng.range(0.2, 1.0),
        };
        let nu = DEPTHS[k % DEPTHS.len()] * 0.1 * alternate(k);
        let ti = rng.angle();
        // Along a face normal of i: i's support there is a face, j's a corner (or an edge
        // when j is aligned, every fifth case: stacked boxes with collinear sides).
        let face = (k / 2 % 4) as f64 * std::f64::consts::FRAC_PI_2;
        let dir = unit(ti + face);
        let tj = if k.is_multiple_of(5) { ti } else { rng.angle() };
        let mut c = place(si, ti, sj, tj, dir, nu, [0.0, 0.0]);
        if let Spec::Body(s, p, t) = c.j {
            // Slide j along the face so that aligned boxes are offset (not corner on corner).
            let slide = rng.range(-0.3, 0.3);
            c.j = Spec::Body(s, [p[0] - slide * dir[1], p[1] + slide * dir[0]], t);
        }
        Some(if k % 3 == 1 {
            Case {
                i: c.j,
                j: c.i,
                along: [-dir[0], -dir[1]],
            }
        } else {
            c
        })
    };
    family(
        "rectangle–rectangle, corner or edge against a face",
        &mut reports,
        &rectangle_face,
        450,
    );
    let rectangle_corner = |rng: &mut Rng, k: usize| -> Option<Case> {
        let si = Shape::Rectangle {
            w: 1.0,
            h: rng.range(0.2, 1.0),
        };
        let sj = Shape::Rectangle {
            w: rng.range(0.3, 1.5),
            h: rng.range(0.2, 1.0),
        };
        let nu = DEPTHS[k % DEPTHS.len()] * 0.1 * alternate(k);
        Some(place(
            si,
            rng.angle(),
            sj,
            rng.angle(),
            unit(rng.angle()),
            nu,
            [0.0, 0.0],
        ))
    };
    family_with(
        "rectangle–rectangle, corner on corner",
        &mut reports,
        &mut |rng, k| rectangle_corner(rng, k),
        450,
        true,
    );

    // Every pair kind again, up to 1e6 sizes from the origin (a wall's point as far again along
    // its line): the same pairs moved, so the same bars (depth 1e-12·a_max: the relative position
    // of two bodies is exact out there, and so is, to rounding, a distance from a wall line).
    family(
        "circle–ellipse up to 1e6 from the origin",
        &mut reports,
        |rng, k| circle_ellipse(rng, k).map(|c| far(c, rng)),
        450,
    );
    family(
        "circle–circle up to 1e6 from the origin",
        &mut reports,
        |rng, k| circle_circle(rng, k).map(|c| far(c, rng)),
        360,
    );
    family(
        "four crossings up to 1e6 from the origin",
        &mut reports,
        |rng, k| crossed(rng, k).map(|c| far(c, rng)),
        300,
    );
    family(
        "containment up to 1e6 from the origin",
        &mut reports,
        |rng, k| containment(rng, k).map(|c| far(c, rng)),
        200,
    );
    family(
        "wall–ellipse/circle moved 1e5…1e6 out, wall point up to 1e6 along the wall",
        &mut reports,
        |rng, k| wall_conic(rng, k).map(|c| far(c, rng)),
        450,
    );
    family(
        "wall–rectangle moved 1e5…1e6 out, wall point up to 1e6 along the wall",
        &mut reports,
        |rng, k| wall_rectangle(rng, k).map(|c| far(c, rng)),
        360,
    );
    family(
        "rectangle–ellipse/circle up to 1e6 from the origin",
        &mut reports,
        |rng, k| rectangle_conic(rng, k).map(|c| far(c, rng)),
        450,
    );
    family(
        "rectangle–rectangle, corner or edge against a face, up to 1e6 from the origin",
        &mut reports,
        |rng, k| rectangle_face(rng, k).map(|c| far(c, rng)),
        450,
    );
    family_with(
        "rectangle–rectangle, corner on corner, up to 1e6 from the origin",
        &mut reports,
        &mut |rng, k| rectangle_corner(rng, k).map(|c| far(c, rng)),
        450,
        true,
    );
    reports
}

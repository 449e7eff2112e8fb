//! Issue 16, item 3: the ellipse as the exact conic against equal-area convex polygons of 8, 16,
//! 32, 64 and 128 vertices and equal-area clumps of 3, 5, 9 and 17 disks — error against cost.
//!
//! `dem2d study representation` writes `figures/representation_pareto.svg` (and a PNG into
//! `target/figure-png/`) and `figures/representation.md`, and prints the tables.
//!
//! **The polygon** ([`Polygon::equal_area_ellipse`]): n vertices on the ellipse
//! `x²/a² + y²/b² = 1` at equally spaced eccentric angles `u_k = φ₀ + 2πk/n`, i.e.
//! `(a cos u_k, b sin u_k)`, scaled about the centre by `s = √(π / (½ n sin(2π/n)))` so that the
//! polygon's area `s² · ½ n ab sin(2π/n)` equals the ellipse's `πab` (s = 1.054 at n = 8, 1.0008 at
//! 64). Its mass is therefore the ellipse's; its moment of inertia differs by O(1/n²).
//!
//! **The clump** ([`Clump::ellipse_fit`]): k disks centred on the major axis between the
//! centres of curvature of its ends, each the largest disk about its centre inside the ellipse,
//! all scaled about the centre so that the union's exact area is `πab`. Its mass is the
//! ellipse's; its contacts are its members' (several at once against the floor). It has no phase:
//! one run per case. It is in the drop and the settling, not in the pile (time).
//!
//! **Scenes**, all from the paper's cases in `cases/` with only the shapes replaced:
//! - P Fig. 2's drop (`drop_rebound_mu01.json`, `drop_rebound_mu05.json`: P's spring on the
//!   depth, e = 0.7, floor friction 0.1 and 0.5), the first [`WINDOW`] s (three bounces), at the
//!   case's Δt = 1e-5 s for every representation, for ellipses of a/b = 1.5, 2, 3 of the case's
//!   area (a = √(1.5 α), b = √(1.5/α) cm). Errors against the ellipse's run: the RMS over the
//!   window of the centroid's distance, over b; the RMS of the angle difference; the apex of the
//!   first rebound, over b. A polygon's errors are means over two phases, φ₀ = 0 (a vertex on
//!   the a axis, as `cases/drop_rebound_polygon64.json`) and φ₀ = π/n (an edge across it): where
//!   the vertices sit is arbitrary, and the error of one phase scatters. The ellipse's own error
//!   is its time-step error: the same run at Δt/4.
//! - P Fig. 4's settling (`settle3_dt1e-5.json`, α = 1.5 only: its layout is the one for a = 1.5,
//!   b = 1), φ₀ = π/n (an edge down: the bodies that lie flat lie on an edge, which starts within
//!   (1 − s cos(π/n)) b of the floor rather than a vertex overlapping it): steps to rest by P's
//!   criterion and the rest state (largest centroid distance over b, largest angle difference)
//!   against the ellipses'.
//! - A poured pile ([`super::packing`]'s: 300 bidisperse grains, α = 1.5, μ = 0.5 by default;
//!   `--grains` for another size), every ellipse replaced by its polygon at the same place and
//!   orientation: packing fraction and coordination in the packing study's window.
//!
//! **Cost**: ns per contact of the drop — the median wall time of the steps with a contact less
//! that of the free-flight steps (one body, one contact: the kernel and the law, not the loop);
//! for the pile, the wall time per step over the contacts per step, and particle-steps/s.
//! Bytes per body: the `Shape` each body holds (`size_of::<Shape>()`, the same for every
//! representation: a polygon is a reference into the shape table), plus the shape table's entry
//! (the vertex list, the edge normals and the derived data) divided among the bodies that share
//! it.

use super::packing;
use dem2d::geometry::clump::{Clump, ClumpData};
use dem2d::geometry::polygon::{Polygon, PolygonData};
use dem2d::geometry::{Shape, Vec2};
use dem2d::output::plot::{self, LinePanel, Series};
use dem2d::run::{RunError, Simulation, Stop};
use dem2d::scene::Case;
use serde_json::{Value, json};
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::time::Instant;

/// Aspect ratios of the drop.
pub const ALPHAS: [f64; 3] = [1.5, 2.0, 3.0];
/// Polygon vertex counts.
pub const NS: [usize; 5] = [8, 16, 32, 64, 128];
/// Polygon vertex counts of the pile (the 64- and 128-gon piles take too long for the shared
/// development machine: a 60-grain pile of 32-gons took 44 s against the ellipses' 3 s).
pub const PILE_NS: [usize; 3] = [8, 16, 32];
/// Clump member counts.
pub const KS: [usize; 4] = [3, 5, 9, 17];
/// The drop's window (s): release at 5 cm, first contact at 0.089 s, three bounces.
pub const WINDOW: f64 = 0.3;

/// A representation of an ellipse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rep {
    Ellipse,
    Polygon(usize),
    Clump(usize),
}

impl Rep {
    fn label(self) -> String {
        match self {
            Rep::Ellipse => "ellipse (exact conic)".into(),
            Rep::Polygon(n) => format!("{n}-gon"),
            Rep::Clump(k) => format!("{k}-disk clump"),
        }
    }
    fn shape(self, a: f64, b: f64, phase_half_step: bool) -> Shape {
        match self {
            Rep::Ellipse => Shape::Ellipse { a, b },
            Rep::Polygon(n) => {
                let phase = if phase_half_step { PI / n as f64 } else { 0.0 };
                Shape::Polygon(Polygon::equal_area_ellipse(n, a, b, phase).expect("convex"))
            }
            Rep::Clump(k) => Shape::Clump(Clump::new(&Clump::ellipse_fit(k, a, b)).expect("disks")),
        }
    }
    /// Bytes of the shape table's entry (zero for the ellipse, whose semi-axes live in the
    /// `Shape` itself).
    fn table_bytes(self) -> usize {
        match self {
            Rep::Ellipse => 0,
            Rep::Polygon(n) => {
                std::mem::size_of::<PolygonData>() + 2 * n * std::mem::size_of::<Vec2>()
            }
            Rep::Clump(k) => {
                std::mem::size_of::<ClumpData>()
                    + k * (std::mem::size_of::<Vec2>() + std::mem::size_of::<f64>())
            }
        }
    }
}

/// The case file `path` with every body's shape replaced by `shape`, and `edit` applied.
fn case_from(path: &str, shape: Shape, edit: impl Fn(&mut Value)) -> Case {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut v: Value = serde_json::from_str(&text).expect("JSON");
    for b in v["bodies"].as_array_mut().expect("bodies") {
        b["shape"] = dem2d::scene::generate::shape_json(&shape);
    }
    edit(&mut v);
    Case::from_json(&v.to_string()).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// One drop run, sampled every `every` steps.
struct Drop {
    pos: Vec<Vec2>,
    angle: Vec<f64>,
    apex: f64,
    ns_per_contact: f64,
}

fn drop_run(mu: &str, shape: Shape, dt_div: u32) -> Result<Drop, RunError> {
    let case = case_from(
        &format!("cases/drop_rebound_{mu}.json"),
        shape,
        |v: &mut Value| {
            v["duration"] = json!(WINDOW);
            let dt = v["dt"].as_f64().expect("dt");
            v["dt"] = json!(dt / dt_div as f64);
        },
    );
    let mut w = case.build_world();
    let (mut pos, mut angle) = (Vec::new(), Vec::new());
    let (mut with, mut without) = (Vec::new(), Vec::new());
    // First rebound: the highest centroid between the end of the first contact and the next.
    let (mut phase, mut apex) = (0, f64::NAN);
    // The time of each step (from the end of the last call to the end of the step).
    let mut clock = Instant::now();
    Simulation::new(&mut w)
        .until_step(case.steps())
        .run_each(|w, r| {
            let ns = clock.elapsed().as_nanos() as f64;
            if r.contacts > 0 {
                with.push(ns / r.contacts as f64);
            } else {
                without.push(ns);
            }
            let s = &w.bodies.state[0];
            match (phase, r.contacts > 0) {
                (0, true) => phase = 1,
                (1, false) => {
                    phase = 2;
                    apex = s.pose.position.y;
                }
                (2, false) => apex = apex.max(s.pose.position.y),
                (2, true) => phase = 3,
                _ => {}
            }
            if w.step.is_multiple_of(dt_div as u64) {
                pos.push(s.pose.position);
                angle.push(s.pose.angle());
            }
            clock = Instant::now();
        })?;
    Ok(Drop {
        pos,
        angle,
        apex,
        ns_per_contact: median(with) - median(without),
    })
}

/// Errors of `d` against `r`: RMS distance, RMS angle, apex.
fn drop_errors(d: &Drop, r: &Drop) -> [f64; 3] {
    let n = d.pos.len().min(r.pos.len()) as f64;
    let p = d
        .pos
        .iter()
        .zip(&r.pos)
        .map(|(a, b)| (a - b).norm_squared())
        .sum::<f64>();
    let q = d
        .angle
        .iter()
        .zip(&r.angle)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>();
    [(p / n).sqrt(), (q / n).sqrt(), (d.apex - r.apex).abs()]
}

/// One row of the drop table.
#[derive(Clone, Debug)]
pub struct DropRow {
    pub alpha: f64,
    pub mu: &'static str,
    pub rep: Rep,
    /// RMS centroid distance / b, RMS angle (rad), |apex − apex_ellipse| / b.
    pub errors: [f64; 3],
    pub ns_per_contact: f64,
    pub steps_per_second: f64,
}

/// One row of the settling table.
#[derive(Clone, Debug)]
pub struct SettleRow {
    pub rep: Rep,
    pub rest_step: Option<u64>,
    /// Largest centroid distance / b and largest angle difference (rad), at rest.
    pub errors: [f64; 2],
    pub ns_per_contact: f64,
}

type Settled = (Option<u64>, Vec<(Vec2, f64)>, f64);

fn settle_run(shape: Shape, dt_div: u32) -> Result<Settled, RunError> {
    let case = case_from("cases/settle3_dt1e-5.json", shape, |v: &mut Value| {
        let dt = v["dt"].as_f64().expect("dt");
        v["dt"] = json!(dt / dt_div as f64);
    });
    let mut w = case.build_world();
    let (start, mut contacts) = (Instant::now(), 0usize);
    let stop = Simulation::new(&mut w)
        .until_step(case.steps())
        .quiescence(Some(case.quiescence_criterion().expect("quiescence")))
        .run_each(|_, r| contacts += r.contacts)?;
    let rest = match stop {
        Stop::AtRest { since } => Some(since),
        _ => None,
    };
    let ns = start.elapsed().as_nanos() as f64 / contacts.max(1) as f64;
    let state = w
        .bodies
        .state
        .iter()
        .map(|s| (s.pose.position, s.pose.angle()))
        .collect();
    Ok((rest, state, ns))
}

/// One row of the pile table.
#[derive(Clone, Debug)]
pub struct PileRow {
    pub rep: Rep,
    pub pile: packing::Pile,
}

/// Least-squares slope of log y against log x.
fn slope(pts: &[(f64, f64)]) -> f64 {
    let n = pts.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = pts.iter().map(|&(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

fn e(v: f64) -> String {
    if v.is_nan() {
        "–".into()
    } else {
        format!("{v:.2e}")
    }
}

/// Runs the study; the pile has `grains` grains.
pub fn run(grains: usize) -> Result<String, RunError> {
    let reps: Vec<Rep> = std::iter::once(Rep::Ellipse)
        .chain(NS.iter().map(|&n| Rep::Polygon(n)))
        .chain(KS.iter().map(|&k| Rep::Clump(k)))
        .collect();
    let shape_slot = std::mem::size_of::<Shape>();
    let mut md = String::new();

    // --- The drop.
    let mut drops: Vec<DropRow> = Vec::new();
    for mu in ["mu01", "mu05"] {
        for &alpha in &ALPHAS {
            let (a, b) = ((1.5 * alpha).sqrt(), (1.5 / alpha).sqrt());
            let start = Instant::now();
            let reference = drop_run(mu, Shape::Ellipse { a, b }, 1)?;
            let wall = start.elapsed().as_secs_f64();
            let fine = drop_run(mu, Shape::Ellipse { a, b }, 4)?;
            let mut errors = drop_errors(&reference, &fine);
            errors[0] /= b;
            errors[2] /= b;
            drops.push(DropRow {
                alpha,
                mu,
                rep: Rep::Ellipse,
                errors,
                ns_per_contact: reference.ns_per_contact,
                steps_per_second: reference.pos.len() as f64 / wall,
            });
            for &rep in &reps[1..] {
                let (mut errors, mut ns, mut sps) = ([0.0; 3], 0.0, 0.0);
                // A clump has no phase: one run.
                let phases: &[bool] = match rep {
                    Rep::Clump(_) => &[false],
                    Rep::Ellipse | Rep::Polygon(_) => &[false, true],
                };
                let w = 1.0 / phases.len() as f64;
                for &half in phases {
                    let start = Instant::now();
                    let d = drop_run(mu, rep.shape(a, b, half), 1)?;
                    sps += w * d.pos.len() as f64 / start.elapsed().as_secs_f64();
                    let err = drop_errors(&d, &reference);
                    for k in 0..3 {
                        errors[k] += w * err[k] / if k == 1 { 1.0 } else { b };
                    }
                    ns += w * d.ns_per_contact;
                }
                drops.push(DropRow {
                    alpha,
                    mu,
                    rep,
                    errors,
                    ns_per_contact: ns,
                    steps_per_second: sps,
                });
            }
            eprintln!("drop {mu}, α = {alpha}: done");
        }
    }
    writeln!(
        md,
        "**P Fig. 2's drop**, first {WINDOW} s, Δt = 1e-5 s for every representation, ellipses \
         of the case's area πab = 1.5π cm² (a = √(1.5α), b = √(1.5/α) cm). Errors against the \
         ellipse's run at the same Δt (polygons: mean over the phases 0 and π/n; clumps: one run, \
         several member contacts with the floor at once, ns per contact per *body* contact, a \
         non-positive value is timing noise and is not drawn); the ellipse's \
         row gives its own time-step error (against Δt/4). ns per contact: median wall time of a \
         step with a contact less that of a free-flight step (machine-dependent: 2 shared \
         cores). Bytes per body: the `Shape` slot ({shape_slot} B for every representation) + \
         the shape table's entry, here held by the one body.\n"
    )
    .expect("string");
    md.push_str(
        "| floor μ | α | representation | RMS centroid error / b | RMS angle error (rad) | first-rebound apex error / b | ns per contact | steps/s | bytes per body |\n|---:|---:|---|---:|---:|---:|---:|---:|---:|\n",
    );
    for d in &drops {
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {:.0} | {:.2e} | {} |",
            if d.mu == "mu01" { "0.1" } else { "0.5" },
            d.alpha,
            if d.rep == Rep::Ellipse {
                "ellipse (its Δt error)".to_string()
            } else {
                d.rep.label()
            },
            e(d.errors[0]),
            e(d.errors[1]),
            e(d.errors[2]),
            d.ns_per_contact,
            d.steps_per_second,
            shape_slot + d.rep.table_bytes()
        )
        .expect("string");
    }
    // Order of convergence in n.
    md.push_str(
        "\nObserved order of the polygon's drop error in n (least-squares slope of log error \
         against log n, with a minus sign):\n\n| floor μ | α | RMS centroid, n = 8–128 | \
         n = 32–128 | RMS angle, n = 8–128 | n = 32–128 |\n|---:|---:|---:|---:|---:|---:|\n",
    );
    for mu in ["mu01", "mu05"] {
        for &alpha in &ALPHAS {
            let pts = |k: usize, lo: usize| -> Vec<(f64, f64)> {
                drops
                    .iter()
                    .filter_map(|d| match d.rep {
                        Rep::Polygon(n) if d.mu == mu && d.alpha == alpha && n >= lo => {
                            Some((n as f64, d.errors[k]))
                        }
                        _ => None,
                    })
                    .collect()
            };
            let o = [
                -slope(&pts(0, 8)),
                -slope(&pts(0, 32)),
                -slope(&pts(1, 8)),
                -slope(&pts(1, 32)),
            ];
            writeln!(
                md,
                "| {} | {alpha} | {:.2} | {:.2} | {:.2} | {:.2} |",
                if mu == "mu01" { "0.1" } else { "0.5" },
                o[0],
                o[1],
                o[2],
                o[3]
            )
            .expect("string");
        }
    }

    // --- The settling.
    let (a, b) = (1.5, 1.0);
    let (ell_rest, ell_state, ell_ns) = settle_run(Shape::Ellipse { a, b }, 1)?;
    let (_, fine_state, _) = settle_run(Shape::Ellipse { a, b }, 4)?;
    let rest_err = |s: &[(Vec2, f64)], r: &[(Vec2, f64)]| -> [f64; 2] {
        let mut m = [0.0f64; 2];
        for (p, q) in s.iter().zip(r) {
            m[0] = m[0].max((p.0 - q.0).norm() / b);
            m[1] = m[1].max((p.1 - q.1).abs());
        }
        m
    };
    let mut settles = vec![SettleRow {
        rep: Rep::Ellipse,
        rest_step: ell_rest,
        errors: rest_err(&ell_state, &fine_state),
        ns_per_contact: ell_ns,
    }];
    for &rep in &reps[1..] {
        let (rest, state, ns) = settle_run(rep.shape(a, b, true), 1)?;
        settles.push(SettleRow {
            rep,
            rest_step: rest,
            errors: rest_err(&state, &ell_state),
            ns_per_contact: ns,
        });
    }
    eprintln!("settling: done");
    md.push_str(
        "\n**P Fig. 4's settling** (`settle3_dt1e-5.json`, α = 1.5, Δt = 1e-5 s, P's rest \
         criterion; polygons with an edge down, φ₀ = π/n). Rest state against the ellipses' \
         (the ellipse's row: against its own run at Δt/4); ns per contact: the run's wall time \
         over the contacts it evaluated (whole step included).\n\n| representation | steps \
         to rest | largest centroid error at rest / b | largest angle error at rest (rad) | ns \
         per contact (whole step) |\n|---|---:|---:|---:|---:|\n",
    );
    for s in &settles {
        writeln!(
            md,
            "| {} | {} | {} | {} | {:.0} |",
            if s.rep == Rep::Ellipse {
                "ellipse (its Δt error)".to_string()
            } else {
                s.rep.label()
            },
            s.rest_step
                .map_or("never (0.5 s)".into(), |k| k.to_string()),
            e(s.errors[0]),
            e(s.errors[1]),
            s.ns_per_contact
        )
        .expect("string");
    }

    // The pile takes minutes: show the single-body tables first.
    eprint!("{md}");
    // --- The pile.
    let alpha = 1.5;
    let mut piles = Vec::new();
    for &rep in &reps[..=PILE_NS.len()] {
        let pile = packing::pour_shaped(alpha, 0.5, grains, false, packing::SEED, &|s| match s {
            Shape::Ellipse { a, b } => rep.shape(a, b, false),
            Shape::Circle { .. }
            | Shape::Rectangle { .. }
            | Shape::Polygon(_)
            | Shape::Clump(_) => s,
        })?;
        eprintln!(
            "pile {}: φ = {:.4}, Z = {:.2}, {:.0} s",
            rep.label(),
            pile.packing,
            pile.z_no_rattlers,
            pile.wall_seconds
        );
        piles.push(PileRow { rep, pile });
    }
    let ell = piles[0].pile;
    writeln!(
        md,
        "\n**A poured pile**: `dem2d study packing`'s pile of {grains} bidisperse grains \
         (α = 1.5, μ = 0.5; box {} cm wide), every ellipse replaced by its polygon (φ₀ = 0) at the \
         same place and orientation; the packing study's window, {} cm from the walls, the floor \
         and the surface. ns per contact: wall time per step over contacts per step (walls \
         included). Bytes per body: the `Shape` slot + the two shape-table entries (two sizes) \
         shared by the {grains} grains.\n\n| representation | φ | φ − φ_ellipse | Z (no \
         rattlers) | Z − Z_ellipse | at rest (t, s) | steps | contacts per step | ns per \
         contact | particle-steps/s | wall time (s) | bytes per body |\n|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|",
        packing::width_for(grains),
        packing::MARGIN
    )
    .expect("string");
    for p in &piles {
        let q = &p.pile;
        writeln!(
            md,
            "| {} | {:.4} | {:+.4} | {:.2} | {:+.2} | {} ({:.2}) | {} | {:.0} | {:.0} | {:.2e} | {:.0} | {:.1} |",
            p.rep.label(),
            q.packing,
            q.packing - ell.packing,
            q.z_no_rattlers,
            q.z_no_rattlers - ell.z_no_rattlers,
            if q.at_rest { "yes" } else { "no" },
            q.time,
            q.steps,
            q.contacts_per_step,
            1e9 * q.wall_seconds / (q.steps as f64 * q.contacts_per_step),
            q.particle_steps_per_second,
            q.wall_seconds,
            shape_slot as f64 + 2.0 * p.rep.table_bytes() as f64 / grains as f64
        )
        .expect("string");
    }
    writeln!(
        md,
        "\nWritten by `dem2d study representation{}`. The clumps (`Clump::ellipse_fit`) are in the \
         drop and the settling, not in the pile.",
        if grains == packing::N {
            String::new()
        } else {
            format!(" --grains {grains}")
        }
    )
    .expect("string");

    // --- The figure: error against cost, one curve per α (and the ellipse's own Δt error).
    // The drop rows of `mu` and α whose representation `rep` picks (and whose cost is drawable),
    // as a series of error against cost, each point labelled by `tag` of its representation.
    let drop_series = |mu: &str, alpha: f64, pick: fn(Rep) -> Option<String>, label: String| {
        let rows: Vec<&DropRow> = drops
            .iter()
            .filter(|d| d.mu == mu && d.alpha == alpha && pick(d.rep).is_some())
            .filter(|d| !matches!(d.rep, Rep::Clump(_)) || d.ns_per_contact > 0.0)
            .collect();
        Series {
            label,
            points: rows
                .iter()
                .map(|d| (d.ns_per_contact, d.errors[0]))
                .collect(),
            point_labels: rows.iter().filter_map(|d| pick(d.rep)).collect(),
            markers: true,
            ..Default::default()
        }
    };
    let drop_panel = |mu: &str, title: &str| -> LinePanel {
        let polygon = |r: Rep| match r {
            Rep::Polygon(n) => Some(format!("{n}")),
            Rep::Ellipse | Rep::Clump(_) => None,
        };
        let clump = |r: Rep| match r {
            Rep::Clump(k) => Some(format!("{k}d")),
            Rep::Ellipse | Rep::Polygon(_) => None,
        };
        let mut series: Vec<Series> = ALPHAS
            .iter()
            .enumerate()
            .map(|(c, &alpha)| Series {
                color: c,
                line: true,
                ..drop_series(mu, alpha, polygon, format!("n-gon, α = {alpha}"))
            })
            .collect();
        // Clumps: the same colour per α, hollow markers without lines (their cost is not
        // monotone in k), labelled "k d"; a non-positive cost (timing noise: a contact step
        // measured faster than a free-flight one) cannot be drawn on the log axis.
        for (c, &alpha) in ALPHAS.iter().enumerate() {
            series.push(Series {
                color: c,
                hollow: true,
                ..drop_series(mu, alpha, clump, format!("k-disk clump, α = {alpha}"))
            });
        }
        let ell: Vec<&DropRow> = drops
            .iter()
            .filter(|d| d.mu == mu && d.rep == Rep::Ellipse)
            .collect();
        series.push(Series {
            label: "exact conic (its own Δt error)".into(),
            points: ell
                .iter()
                .map(|d| (d.ns_per_contact, d.errors[0]))
                .collect(),
            point_labels: ell.iter().map(|d| format!("α={}", d.alpha)).collect(),
            color: 3,
            markers: true,
            hollow: true,
            ..Default::default()
        });
        LinePanel {
            title: title.into(),
            x_label: "cost: ns per contact (wall time)".into(),
            y_label: "RMS centroid error over 0.3 s / b (–)".into(),
            log_x: true,
            log_y: true,
            series,
            // Down to 1e-4: the legend (lower right) then sits below every point.
            y_range: Some((1e-4, 1e1)),
            legend: plot::Legend::LowerRight,
            ..Default::default()
        }
    };
    let poly: Vec<&PileRow> = piles.iter().skip(1).collect();
    let pile_panel = LinePanel {
        title: format!("Poured pile, {grains} grains, α = 1.5, μ = 0.5"),
        x_label: "cost: ns per contact (wall time)".into(),
        y_label: "|φ − φ_ellipse| (–)".into(),
        log_x: true,
        log_y: true,
        series: vec![Series {
            label: "n-gon".into(),
            points: poly
                .iter()
                .map(|p| {
                    let q = &p.pile;
                    (
                        1e9 * q.wall_seconds / (q.steps as f64 * q.contacts_per_step),
                        (q.packing - ell.packing).abs().max(1e-6),
                    )
                })
                .collect(),
            point_labels: poly
                .iter()
                .map(|p| match p.rep {
                    Rep::Polygon(n) => format!("{n}"),
                    Rep::Ellipse | Rep::Clump(_) => String::new(),
                })
                .collect(),
            color: 0,
            line: true,
            markers: true,
            ..Default::default()
        }],
        vlines: vec![(
            1e9 * ell.wall_seconds / (ell.steps as f64 * ell.contacts_per_step),
            "exact conic's cost".into(),
        )],
        legend: plot::Legend::UpperLeft,
        ..Default::default()
    };
    let panels = [
        drop_panel("mu01", "P Fig. 2 drop, floor μ = 0.1"),
        drop_panel("mu05", "P Fig. 2 drop, floor μ = 0.5"),
        pile_panel,
    ];
    super::write_figure("representation_pareto", (1500, 620), (1, 3), &panels)?;
    super::write_text("representation.md", &md)?;
    print!("{md}");
    Ok(md)
}

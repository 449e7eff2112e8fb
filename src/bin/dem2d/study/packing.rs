//! Packing fraction and coordination of bidisperse (1:1.4) grains poured under gravity into a
//! box, against the aspect ratio α (1, 1.2, 1.5, 2, 3), frictionless and with μ = 0.5.
//!
//! `dem2d study packing` writes `figures/packing.svg` and `figures/packing.md` and prints the
//! table. Each pile: [`N`] grains (equal areas: half of radius 0.833 cm, half 1.4 times it,
//! ellipses a = r√α, b = r/√α in random orientations) on a loose lattice in a box [`WIDTH`] cm
//! wide, released with random velocities ≤ 5 cm/s, settling under gravity with the laws of
//! `dem2d generate` (linear on the overlap area, P's stiffness, dashpots for e = 0.5) until at
//! rest (mean increment ≤ 1e-7 cm per step for 1000 steps) or [`DURATION`] s. Measured in a
//! window [`MARGIN`] cm away from the side walls, the floor and the surface (the lowest of the
//! tops of the grains in 5 cm bins, less the margin): the packing fraction from the exact areas
//! of the grains clipped by the window, the coordination number with and without rattlers of
//! the grains whose centre lies in it.
//!
//! With `--write-cases` each pile's case is also written to `cases/packing/` (e.g.
//! `cases/packing/packing_a1.5_mu0.5.json`): `dem2d run` on it followed by `dem2d analyze RUN_DIR
//! --window …` with the table's window gives the row again.

use super::Table;
use dem2d::analysis::statistics::mean_se;
use dem2d::analysis::{self, Frame, Window};
use dem2d::contact_law::NormalForce;
use dem2d::dynamics::BodyInit;
use dem2d::geometry::{Shape, Vec2};
use dem2d::output::plot::{self, LinePanel, Series};
use dem2d::output::progress::CommandProgress;
use dem2d::run::{RunError, Simulation, Stop};
use dem2d::scene::Case;
use dem2d::scene::generate::{DENSITY, PileShape, PileSizes, PileSpec, R_SMALL, Xorshift};
use std::time::Instant;

/// Grains per pile by default (`dem2d study packing --grains N` for others).
pub const N: usize = 300;
/// Box width for [`N`] grains; larger piles get a box wider by √(n/N) (in whole 5 cm bins), so
/// that the pile keeps its shape.
pub const WIDTH: f64 = 30.0;
pub const MARGIN: f64 = 4.0;
/// The seed of the first pile of each row (its grains' sizes, orientations and velocities).
pub const SEED: u64 = 5;
/// Pours per row by default: each number of the table is the mean over them ± its standard
/// error.
pub const POURS: usize = 3;
/// With `--precision`, pours are added until the se of φ is at most it, up to this many times
/// the pours asked for.
pub const PRECISION_CAP: usize = 10;
pub const DURATION: f64 = 3.0;

/// One pile.
#[derive(Clone, Copy, Debug)]
pub struct Pile {
    pub aspect: f64,
    pub friction: f64,
    pub packing: f64,
    pub z: f64,
    pub z_no_rattlers: f64,
    pub rattlers: f64,
    pub order: f64,
    pub window: Window,
    pub at_rest: bool,
    pub time: f64,
    pub wall_seconds: f64,
    pub particle_steps_per_second: f64,
    /// Steps run and the mean number of contacts per step (walls included).
    pub steps: u64,
    pub contacts_per_step: f64,
}

/// The box width for `n` grains (see [`WIDTH`]).
pub fn width_for(n: usize) -> f64 {
    (WIDTH / 5.0 * (n as f64 / N as f64).sqrt())
        .round()
        .max(WIDTH / 5.0)
        * 5.0
}

fn bodies(aspect: f64, seed: u64, spacing: f64, n: usize, width: f64) -> Vec<BodyInit> {
    let mut rng = Xorshift(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let mut uniform = move || rng.uniform();
    let cols = (width / spacing).floor() as usize;
    let x0 = 0.5 * (width - cols as f64 * spacing);
    let r6 = |x: f64| (x * 1e6).round() / 1e6;
    (0..n)
        .map(|k| {
            let r = if uniform() < 0.5 {
                R_SMALL
            } else {
                1.4 * R_SMALL
            };
            let angle = r6(std::f64::consts::PI * uniform());
            let (speed, dir) = (5.0 * uniform(), std::f64::consts::TAU * uniform());
            let shape = if aspect == 1.0 {
                Shape::Circle { r: r6(r) }
            } else {
                Shape::Ellipse {
                    a: r6(r * aspect.sqrt()),
                    b: r6(r / aspect.sqrt()),
                }
            };
            BodyInit {
                material: 0,
                prescribed: false,
                shape,
                position: Vec2::new(
                    r6(x0 + spacing * ((k % cols) as f64 + 0.5)),
                    r6(spacing * ((k / cols) as f64 + 0.5)),
                ),
                angle: if aspect == 1.0 { 0.0 } else { angle },
                velocity: Vec2::new(r6(speed * dir.cos()), r6(speed * dir.sin())),
                omega: 0.0,
                density: DENSITY,
            }
        })
        .collect()
}

/// Pours and measures one pile of `n` grains; with `write` its case file also goes to
/// `cases/packing/`.
pub fn pour(aspect: f64, friction: f64, n: usize, write: bool) -> Result<Pile, RunError> {
    pour_shaped(aspect, friction, n, write, SEED, &|s| s)
}

/// [`pour`] with each grain's shape passed through `shape` first (the representation study
/// turns the ellipses into polygons); the rest of the pile — positions, orientations,
/// velocities, laws, window — is [`pour`]'s.
pub fn pour_shaped(
    aspect: f64,
    friction: f64,
    n: usize,
    write: bool,
    seed: u64,
    shape: &dyn Fn(Shape) -> Shape,
) -> Result<Pile, RunError> {
    let start = Instant::now();
    let width = width_for(n);
    let mut spec = PileSpec::new(
        if aspect == 1.0 {
            PileShape::Disks
        } else {
            PileShape::Ellipses
        },
        n,
        1,
    );
    spec.aspect = aspect;
    spec.sizes = PileSizes::Bidisperse;
    spec.friction = friction;
    spec.normal_force = NormalForce::Area;
    spec.duration = DURATION;
    let spacing = ((2.0 * spec.max_bound() + 0.1) * 10.0).ceil() / 10.0;
    let text = spec.case_text(
        &format!("packing_a{aspect}_mu{friction}"),
        "packing study pile",
        width,
        &bodies(aspect, seed, spacing, n, width)
            .into_iter()
            .map(|b| BodyInit {
                shape: shape(b.shape),
                ..b
            })
            .collect::<Vec<_>>(),
    );
    if write {
        let path = format!("cases/packing/packing_a{aspect}_mu{friction}.json");
        super::put_case(std::path::Path::new(&path), &text);
    }
    let case = Case::from_json(&text).expect("valid case");
    let mut w = case.build_world();
    let mut contacts = 0usize;
    let mut lines = CommandProgress::new(case.name.clone());
    let stop = Simulation::new(&mut w)
        .observe(&mut lines)
        .until_step(case.steps())
        .quiescence(Some(case.quiescence_criterion().expect("a rest criterion")))
        .run_each(|_, r| contacts += r.contacts)?;
    let at_rest = matches!(stop, Stop::AtRest { .. });
    w.refresh_contact_extras();
    let frame = Frame::from_world(&w);
    // The surface: the lowest of the bins' highest grain tops.
    let bins = (width / 5.0).round() as usize;
    let mut tops = vec![0.0f64; bins];
    for b in &frame.bodies {
        let k = ((b.position.x / 5.0) as usize).min(bins - 1);
        tops[k] = tops[k].max(b.position.y + b.shape.bounding_radius());
    }
    let surface = tops.iter().copied().fold(f64::INFINITY, f64::min);
    let window = Window {
        x0: MARGIN,
        x1: width - MARGIN,
        y0: MARGIN,
        y1: surface - MARGIN,
    };
    let m = analysis::measure(&frame, Some(window));
    let wall = start.elapsed().as_secs_f64();
    Ok(Pile {
        aspect,
        friction,
        packing: m.packing_fraction,
        z: m.coordination,
        z_no_rattlers: m.coordination_no_rattlers,
        rattlers: m.rattler_fraction,
        order: m.orientation_order,
        window,
        at_rest,
        time: w.time,
        wall_seconds: wall,
        particle_steps_per_second: n as f64 * w.step as f64 / wall,
        steps: w.step,
        contacts_per_step: contacts as f64 / w.step.max(1) as f64,
    })
}

/// Runs the study with piles of `n` grains, `pours` per row (seeds [`SEED`] + `seed`, …; with
/// `precision`, more until the se of φ is at most it); `write` also writes their case files
/// (each row's first pile's).
pub fn run(
    n: usize,
    write: bool,
    pours: usize,
    seed: u64,
    precision: Option<f64>,
) -> Result<String, RunError> {
    let aspects = [1.0, 1.2, 1.5, 2.0, 3.0];
    let width = width_for(n);
    let pours = pours.max(1);
    let mut rows: Vec<Vec<Pile>> = Vec::new();
    for mu in [0.0, 0.5] {
        for &a in &aspects {
            let mut of: Vec<Pile> = Vec::new();
            while of.len() < pours
                || precision.is_some_and(|p| {
                    let e = mean_se(&of.iter().map(|q| q.packing).collect::<Vec<_>>());
                    !(e.converged && e.se <= p) && of.len() < PRECISION_CAP * pours
                })
            {
                let k = of.len() as u64;
                let p = pour_shaped(a, mu, n, write && k == 0, SEED + seed + k, &|s| s)?;
                eprintln!(
                    "α = {a}, μ = {mu}, pour {}: φ = {:.4}, {:.0} s",
                    k + 1,
                    p.packing,
                    p.wall_seconds
                );
                of.push(p);
            }
            rows.push(of);
        }
    }
    let mut table = Table::new(
        "| α | μ | pours | φ (window) | Z | Z (no rattlers) | rattlers (%) | orientation order | window of the first pour (cm) | at rest (t, s) | wall time (s) | particle-steps/s |\n|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---:|---:|",
    );
    let mut piles = Vec::new();
    for of in &rows {
        // Each number over the pours (independent seeds): mean ± s/√m.
        let over = |f: &dyn Fn(&Pile) -> f64| mean_se(&of.iter().map(f).collect::<Vec<_>>());
        let p = &of[0];
        let wall: f64 = of.iter().map(|q| q.wall_seconds).sum();
        let steps: f64 = of.iter().map(|q| q.steps as f64).sum();
        let order = over(&|q| q.order);
        table.row(format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | [{}, {}] × [{}, {:.1}] | {} of {} ({}) | {:.0} | {:.2e} |",
            p.aspect,
            p.friction,
            of.len(),
            over(&|q| q.packing).pm(4),
            over(&|q| q.z).pm(2),
            over(&|q| q.z_no_rattlers).pm(2),
            over(&|q| 100.0 * q.rattlers).pm(1),
            if order.mean.is_nan() { "–".into() } else { order.pm(2) },
            p.window.x0,
            p.window.x1,
            p.window.y0,
            p.window.y1,
            of.iter().filter(|q| q.at_rest).count(),
            of.len(),
            over(&|q| q.time).pm(2),
            wall,
            n as f64 * steps / wall
        ));
        piles.push(Pile {
            packing: over(&|q| q.packing).mean,
            z_no_rattlers: over(&|q| q.z_no_rattlers).mean,
            ..*p
        });
    }
    let errors: Vec<(f64, f64)> = rows
        .iter()
        .map(|of| {
            let over = |f: &dyn Fn(&Pile) -> f64| mean_se(&of.iter().map(f).collect::<Vec<_>>());
            (over(&|q| q.packing).se, over(&|q| q.z_no_rattlers).se)
        })
        .collect();
    let note = format!(
        "\n{n} bidisperse grains (1:1.4, equal numbers) per pile in a box {width} cm wide, poured \
         under gravity; window {MARGIN} cm from the walls, the floor and the surface. ± one \
         standard error over the pours (independent seeds from {}; \
         `analysis::statistics::mean_se`){}. Written by `dem2d study packing{}{}`.\n",
        SEED + seed,
        precision.map_or(String::new(), |p| format!(
            ", pours added until the se of φ is at most {p}"
        )),
        if n == N {
            String::new()
        } else {
            format!(" --grains {n}")
        },
        if pours == POURS {
            String::new()
        } else {
            format!(" --packings {pours}")
        }
    );
    print!("{note}");
    let md = table.text() + &note;
    let series = |k: usize| -> Vec<Series> {
        [0.0, 0.5]
            .iter()
            .enumerate()
            .map(|(c, &mu)| Series {
                label: format!("dem2d, poured, μ = {mu}"),
                points: piles
                    .iter()
                    .filter(|p| p.friction == mu)
                    .map(|p| (p.aspect, if k == 0 { p.packing } else { p.z_no_rattlers }))
                    .collect(),
                y_errors: piles
                    .iter()
                    .zip(&errors)
                    .filter(|(p, _)| p.friction == mu)
                    .map(|(_, e)| if k == 0 { e.0 } else { e.1 })
                    // (One pour has no error bar: none drawn.)
                    .map(|e| if e.is_finite() { e } else { 0.0 })
                    .collect(),
                color: c,
                line: true,
                markers: true,
                ..Default::default()
            })
            .collect()
    };
    let panels = [
        LinePanel {
            title: "Packing fraction".into(),
            x_label: "aspect ratio α = a/b (–)".into(),
            y_label: "φ (–)".into(),
            series: series(0),
            hlines: vec![(
                0.84,
                "bidisperse disks, isotropic jamming ≈ 0.84 (O'Hern 2003)".into(),
            )],
            // Room above the points for the legend.
            y_range: Some((0.78, 0.935)),
            legend: plot::Legend::UpperRight,
            ..Default::default()
        },
        LinePanel {
            title: "Coordination number".into(),
            x_label: "aspect ratio α = a/b (–)".into(),
            y_label: "Z without rattlers (–)".into(),
            series: series(1),
            ..Default::default()
        },
    ];
    super::write_figure("packing", (1200, 480), (1, 2), &panels)?;
    super::write_text("packing.md", &md)?;
    Ok(md)
}

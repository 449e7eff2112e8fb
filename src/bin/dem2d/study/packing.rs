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
    pour_shaped(aspect, friction, n, write, &|s| s)
}

/// [`pour`] with each grain's shape passed through `shape` first (the representation study
/// turns the ellipses into polygons); the rest of the pile — positions, orientations,
/// velocities, laws, window — is [`pour`]'s.
pub fn pour_shaped(
    aspect: f64,
    friction: f64,
    n: usize,
    write: bool,
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
        &bodies(aspect, 5, spacing, n, width)
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

/// Runs the study with piles of `n` grains; `write` also writes their case files.
pub fn run(n: usize, write: bool) -> Result<String, RunError> {
    let aspects = [1.0, 1.2, 1.5, 2.0, 3.0];
    let width = width_for(n);
    let mut piles = Vec::new();
    for mu in [0.0, 0.5] {
        for &a in &aspects {
            let p = pour(a, mu, n, write)?;
            eprintln!(
                "α = {a}, μ = {mu}: φ = {:.4}, {:.0} s",
                p.packing, p.wall_seconds
            );
            piles.push(p);
        }
    }
    let mut table = Table::new(
        "| α | μ | φ (window) | Z | Z (no rattlers) | rattlers | orientation order | window (cm) | at rest (t, s) | wall time (s) | particle-steps/s |\n|---:|---:|---:|---:|---:|---:|---:|---|---|---:|---:|",
    );
    for p in &piles {
        table.row(format!(
            "| {} | {} | {:.4} | {:.2} | {:.2} | {:.1} % | {} | [{}, {}] × [{}, {:.1}] | {} ({:.2}) | {:.0} | {:.2e} |",
            p.aspect,
            p.friction,
            p.packing,
            p.z,
            p.z_no_rattlers,
            100.0 * p.rattlers,
            if p.order.is_nan() { "–".into() } else { format!("{:.2}", p.order) },
            p.window.x0,
            p.window.x1,
            p.window.y0,
            p.window.y1,
            if p.at_rest { "yes" } else { "no" },
            p.time,
            p.wall_seconds,
            p.particle_steps_per_second
        ));
    }
    let note = format!(
        "\n{n} bidisperse grains (1:1.4, equal numbers) per pile in a box {width} cm wide, poured \
         under gravity; window {MARGIN} cm from the walls, the floor and the surface. Written by \
         `dem2d study packing{}`.\n",
        if n == N {
            String::new()
        } else {
            format!(" --grains {n}")
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

//! Generated scenes: piles of disks or ellipses on a jittered lattice in a box, for any number of
//! bodies (`dem2d generate`). The output is case-file text, so a generated pile is an ordinary
//! case: it can be saved, read, edited and run like any other.
//!
//! The 10 000-body piles of `cases/` are `generate --shape disks|ellipses --n 10000 --seed 1`.

use crate::contact_law::{Given, NormalForce, damping_ratio_linear};
use crate::dynamics::BodyInit;
use crate::geometry::{Shape, Vec2};
use serde_json::{Value, json};
use std::fmt::Write as _;

/// The grains of a pile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PileShape {
    /// Disks of radius r.
    Disks,
    /// Ellipses of aspect ratio α = a/b ([`PileSpec::aspect`]) of the same area as the disk of
    /// radius r: a = r√α, b = r/√α.
    Ellipses,
}

/// How the radii (equal-area radii for ellipses) are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PileSizes {
    /// Uniform in [`R_MIN`, `R_MAX`].
    Uniform,
    /// Bidisperse: half of radius [`R_SMALL`], half 1.4 times that (the jamming literature's
    /// 1:1.4 mixture), in random order.
    Bidisperse,
}

/// A pile: `n` bodies on a jittered square lattice in a box with a floor and two side walls,
/// with random initial velocities. The box is [`WIDTH_10K`] wide for 10 000 bodies and scales
/// with √n, so that piles of every size have the same aspect ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PileSpec {
    pub shape: PileShape,
    pub n: usize,
    pub seed: u64,
    /// Ellipses' aspect ratio a/b (ignored for disks).
    pub aspect: f64,
    pub sizes: PileSizes,
    /// Coulomb friction, between grains and with the walls.
    pub friction: f64,
    /// What the normal spring acts on.
    pub normal_force: NormalForce,
    /// The rest criterion (cm per step; the mean speed is this over Δt) and the longest run (s).
    pub quiescence: f64,
    pub duration: f64,
    /// Time step (s).
    pub dt: f64,
}

impl PileSpec {
    /// The piles of `cases/`: uniform radii, a/b = 1.5, friction 0.3, the area law.
    pub fn new(shape: PileShape, n: usize, seed: u64) -> Self {
        PileSpec {
            shape,
            n,
            seed,
            aspect: 1.5,
            sizes: PileSizes::Uniform,
            friction: FRICTION,
            normal_force: NormalForce::Area,
            quiescence: QUIESCENCE,
            duration: DURATION,
            dt: DT,
        }
    }
}

/// Radii (cm).
pub const R_MIN: f64 = 0.8;
pub const R_MAX: f64 = 1.2;
/// The small radius of a bidisperse pile (the large is 1.4 times it; mean radius 1 cm).
pub const R_SMALL: f64 = 1.0 / 1.2;
/// Box width for 10 000 bodies (cm).
pub const WIDTH_10K: f64 = 500.0;
/// Density (g/cm³, quartz).
pub const DENSITY: f64 = 2.65;
/// Largest initial speed (cm/s).
pub const V_MAX: f64 = 5.0;
/// Normal and shear stiffness over ρg (cm), as P's Fig. 4.
pub const KN_OVER_RHO_G: f64 = 36400.0;
/// Friction, everywhere (by default).
pub const FRICTION: f64 = 0.3;
/// Restitution of a mean body (r = 1 cm) against a wall, for which the dashpot is tuned.
pub const RESTITUTION: f64 = 0.5;
/// |g| (cm/s²), time step (s).
pub const G: f64 = 980.0;
pub const DT: f64 = 1e-5;
/// At rest: P's criterion with 1e-7 cm per step (a mean speed of 0.01 cm/s, 1e-4 of the speeds
/// of the fall) held for 1000 steps; or the end after 4 s.
pub const QUIESCENCE: f64 = 1e-7;
pub const QUIESCENCE_WINDOW: u64 = 1000;
pub const DURATION: f64 = 4.0;

/// SplitMix64: a small, fast, well-mixed generator; the same seed gives the same pile on every
/// machine (no dependency needed for this).
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) with 53 random bits.
    fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }
}

/// Marsaglia's xorshift generator (shifts 13, 7, 17; the state must not be 0), uniform in
/// [0, 1) with 53 bits: the servo box's lattice and the studies' scenes.
#[derive(Clone, Debug)]
pub struct Xorshift(pub u64);

impl Xorshift {
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Rounds to 1e-6 (the case file then holds exactly the values the run uses, in short text).
fn round6(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

impl PileSpec {
    /// Lattice spacing: the largest bounding diameter plus a margin, so that nothing overlaps
    /// at the start (the piles of `cases/`: disks 2.5 cm for diameters up to 2.4 cm; ellipses
    /// 3.0 cm for bounding diameters up to 2·1.2·√1.5 = 2.94 cm); other piles the largest
    /// bounding diameter plus 0.1 cm, rounded up to 0.1 cm.
    pub fn spacing(&self) -> f64 {
        match (self.shape, self.sizes, self.aspect == 1.5) {
            (PileShape::Disks, PileSizes::Uniform, _) => 2.5,
            (PileShape::Ellipses, PileSizes::Uniform, true) => 3.0,
            _ => ((2.0 * self.max_bound() + 0.1) * 10.0).ceil() / 10.0,
        }
    }

    /// The largest (equal-area) radius.
    pub fn max_radius(&self) -> f64 {
        match self.sizes {
            PileSizes::Uniform => R_MAX,
            PileSizes::Bidisperse => 1.4 * R_SMALL,
        }
    }

    /// Largest bounding radius of a grain.
    pub fn max_bound(&self) -> f64 {
        match self.shape {
            PileShape::Disks => self.max_radius(),
            PileShape::Ellipses => self.max_radius() * self.aspect.sqrt(),
        }
    }

    /// Box width (cm): 500 cm at 10 000 bodies, ∝ √n.
    pub fn width(&self) -> f64 {
        WIDTH_10K * (self.n as f64 / 1e4).sqrt()
    }

    /// Columns of the lattice (at least one).
    pub fn columns(&self) -> usize {
        ((self.width() / self.spacing()).floor() as usize).max(1)
    }

    /// The constant dashpot η (per unit thickness) that gives restitution 0.5 for a body of
    /// radius 1 cm (or its equal-area ellipse) against a wall: `η = 2ζ√(m k_n)` with ζ from e
    /// (T12) and m* = m for a wall.
    pub fn eta(&self) -> f64 {
        let m = DENSITY * std::f64::consts::PI;
        let kn = KN_OVER_RHO_G * DENSITY * G;
        2.0 * damping_ratio_linear(RESTITUTION) * (m * kn).sqrt() // T(12)
    }

    /// The bodies of the pile on the jittered lattice, with their random radii, orientations and
    /// velocities (values rounded to 1e-6, so that case-file text holds them exactly).
    pub fn lattice_bodies(&self) -> Vec<BodyInit> {
        let mut rng = SplitMix64(self.seed);
        let (s, cols, w) = (self.spacing(), self.columns(), self.width());
        let jitter = self.jitter();
        let x0 = 0.5 * (w - cols as f64 * s);
        (0..self.n)
            .map(|k| {
                let (row, col) = (k / cols, k % cols);
                let r = match self.sizes {
                    PileSizes::Uniform => round6(rng.range(R_MIN, R_MAX)),
                    PileSizes::Bidisperse if rng.uniform() < 0.5 => round6(R_SMALL),
                    PileSizes::Bidisperse => round6(1.4 * R_SMALL),
                };
                let x = round6(x0 + s * (col as f64 + 0.5) + rng.range(-jitter, jitter));
                let y = round6(s * (row as f64 + 0.5) + rng.range(-jitter, jitter));
                let (speed, dir) = (rng.range(0.0, V_MAX), rng.range(0.0, std::f64::consts::TAU));
                let velocity = Vec2::new(round6(speed * dir.cos()), round6(speed * dir.sin()));
                let (shape, angle) = match self.shape {
                    PileShape::Disks => (Shape::Circle { r }, 0.0),
                    PileShape::Ellipses => (
                        Shape::Ellipse {
                            a: r * self.aspect.sqrt(),
                            b: r / self.aspect.sqrt(),
                        },
                        round6(rng.range(0.0, std::f64::consts::PI)),
                    ),
                };
                BodyInit {
                    material: 0,
                    prescribed: false,
                    shape,
                    position: Vec2::new(x, y),
                    angle,
                    velocity,
                    omega: 0.0,
                    density: DENSITY,
                }
            })
            .collect()
    }

    /// Jitter of the lattice: up to 40 % of the gap left between the largest neighbours, each way.
    pub fn jitter(&self) -> f64 {
        0.4 * (self.spacing() - 2.0 * self.max_bound()) / 2.0
    }

    /// What differs from the piles of `cases/`, each as the name's suffix and the command's
    /// option (the run's quiescence, duration and Δt: the command's alone).
    fn departures(&self) -> Vec<(String, String)> {
        let mut d = Vec::new();
        if self.shape == PileShape::Ellipses && self.aspect != 1.5 {
            d.push((
                format!("_a{}", self.aspect),
                format!(" --aspect {}", self.aspect),
            ));
        }
        if self.sizes == PileSizes::Bidisperse {
            d.push(("_bi".into(), " --sizes bidisperse".into()));
        }
        if self.friction != FRICTION {
            let mu = self.friction;
            d.push((format!("_mu{mu}"), format!(" --friction {mu}")));
        }
        if self.normal_force != NormalForce::Area {
            let law = self.normal_force.as_str();
            d.push((format!("_{law}"), format!(" --normal-force {law}")));
        }
        for (key, given, default) in [
            ("quiescence", self.quiescence, QUIESCENCE),
            ("duration", self.duration, DURATION),
            ("dt", self.dt, DT),
        ] {
            if given != default {
                d.push((String::new(), format!(" --{key} {given}")));
            }
        }
        d
    }

    /// The shape's name in piles' names and on the command line.
    fn shape_name(&self) -> &'static str {
        match self.shape {
            PileShape::Disks => "disks",
            PileShape::Ellipses => "ellipses",
        }
    }

    /// The pile's name: `settle_disks_10k`, `settle_ellipses_1234`, …, with what differs from
    /// the piles of `cases/` (`_a2`, `_bi`, `_mu0`, `_depth`).
    pub fn name(&self) -> String {
        let count = match self.n {
            n if n >= 1000 && n % 1000 == 0 => format!("{}k", n / 1000),
            n => n.to_string(),
        };
        let suffixes: String = self.departures().into_iter().map(|d| d.0).collect();
        format!("settle_{}{suffixes}_{count}", self.shape_name())
    }

    /// The command line that writes this pile.
    pub fn command(&self) -> String {
        let options: String = self.departures().into_iter().map(|d| d.1).collect();
        format!(
            "dem2d generate --shape {} --n {} --seed {}{options}",
            self.shape_name(),
            self.n,
            self.seed
        )
    }

    /// The pile as case-file text (`"version": 1`), one body per line.
    pub fn case_json(&self) -> String {
        let (s, cols, w, jitter, eta) = (
            self.spacing(),
            self.columns(),
            self.width(),
            self.jitter(),
            self.eta(),
        );
        let label = match self.shape {
            PileShape::Disks => "disks".to_string(),
            PileShape::Ellipses => format!("ellipses (a/b = {}, random orientations)", self.aspect),
        };
        let (sizes, area) = match (self.sizes, self.shape) {
            (PileSizes::Uniform, _) => (format!("of radius uniform in [{R_MIN}, {R_MAX}] cm"), ""),
            (PileSizes::Bidisperse, _) => (
                format!(
                    "half of radius {:.6} cm and half 1.4 times that in random order",
                    round6(R_SMALL)
                ),
                "",
            ),
        };
        let area = match self.shape {
            PileShape::Disks => area,
            PileShape::Ellipses => " (the radius of the disk of equal area: a = r√α, b = r/√α)",
        };
        let command = self.command();
        let description = format!(
            "{n} {label} {sizes}{area} on a {s} cm square lattice jittered by up to ±{jitter:.3} cm, \
             {cols} columns, in a box {w:.1} cm wide (floor and two side walls), released with random \
             velocities of up to {V_MAX} cm/s, settling under gravity. Linear law on the {nf} \
             (normal_force): Kn/ρg = Ks/ρg = {KN_OVER_RHO_G} cm, ρ = {DENSITY} g/cm³, friction \
             {friction}, and a constant dashpot η_n = η_s = {eta:.1} (g/s per unit thickness) that \
             gives restitution {RESTITUTION} for a body of r = 1 cm against a wall (T12). Δt = {dt} s. \
             At rest when the mean increments per step stay below {q} cm (a mean speed of {v} cm/s) \
             for {QUIESCENCE_WINDOW} steps; at most {duration} s. Written by `{command}`.",
            q = self.quiescence,
            v = round6(self.quiescence / self.dt),
            dt = self.dt,
            duration = self.duration,
            n = self.n,
            nf = match self.normal_force {
                NormalForce::Area => "overlap area",
                NormalForce::Depth => "depth",
            },
            friction = self.friction,
        );
        self.case_text(&self.name(), &description, w, &self.lattice_bodies())
    }

    /// Case-file text for this pile's law, time step and box of width `width`, holding `bodies`.
    pub fn case_text(
        &self,
        name: &str,
        description: &str,
        width: f64,
        bodies: &[BodyInit],
    ) -> String {
        let eta = round6(self.eta());
        let contact = json!({
            "model": "linear",
            "normal_force": self.normal_force.as_str(),
            "kn_over_rho_g": KN_OVER_RHO_G,
            "ks_over_rho_g": KN_OVER_RHO_G,
            "eta_n": eta,
            "eta_s": eta,
            "friction": self.friction,
        });
        let right = json!({"point": [width, 0.0], "normal": [-1.0, 0.0]});
        let run = [self.dt, self.duration, self.quiescence];
        settling_case_text(
            name,
            description,
            run,
            contact,
            [left_wall(), right],
            bodies,
        )
    }
}

/// The left wall of a settling box, x = 0.
fn left_wall() -> Value {
    json!({"point": [0.0, 0.0], "normal": [1.0, 0.0]})
}

/// The text of a case settling under gravity in a box (a floor, the side walls `[left, right]`:
/// a left wall at x = 0, [`left_wall`], and a right wall; `dem2d generate`'s fields in their
/// order): `name`, `description`, the step, duration and rest criterion `run` (Δt, duration,
/// quiescence), the `contact` law, holding `bodies`.
fn settling_case_text(
    name: &str,
    description: &str,
    [dt, duration, quiescence]: [f64; 3],
    contact: Value,
    [left, right]: [Value; 2],
    bodies: &[BodyInit],
) -> String {
    let head: [(&str, Value); 12] = [
        ("version", json!(1)),
        ("name", json!(name)),
        ("description", json!(description)),
        ("units", json!("cm")),
        ("gravity", json!([0.0, -G])),
        ("dt", json!(dt)),
        ("duration", json!(duration)),
        ("quiescence", json!(quiescence)),
        ("quiescence_window", json!(QUIESCENCE_WINDOW)),
        ("output_every", json!(10000)),
        ("contact", contact),
        (
            "walls",
            json!([
                {"point": [0.0, 0.0], "normal": [0.0, 1.0]},
                left,
                right,
            ]),
        ),
    ];
    case_text_from(&head, bodies)
}

/// A shape as a case file gives it (`"shape"` of a body).
pub fn shape_json(shape: &Shape) -> Value {
    match *shape {
        Shape::Circle { r } => json!({"type": "circle", "r": r}),
        Shape::Ellipse { a, b } => json!({"type": "ellipse", "a": a, "b": b}),
        Shape::Rectangle { w, h } => json!({"type": "rectangle", "w": w, "h": h}),
        // The centred vertices: the body's position is the centroid's.
        Shape::Polygon(p) => json!({
            "type": "polygon",
            "vertices": p.vertices.iter().map(|v| [v.x, v.y]).collect::<Vec<_>>(),
        }),
        // The centred members: the body's position is the union's centroid.
        Shape::Clump(c) => json!({
            "type": "clump",
            "disks": c.centres.iter().zip(c.radii.iter())
                .map(|(v, r)| json!({"center": [v.x, v.y], "r": r}))
                .collect::<Vec<_>>(),
        }),
    }
}

/// Case-file text: the fields `head` in this order, one per line, then `bodies`, one per line.
pub fn case_text_from(head: &[(&str, Value)], bodies: &[BodyInit]) -> String {
    // Fields in reading order, one per line; bodies one per line.
    let mut text = String::from("{\n");
    for (key, value) in head {
        writeln!(text, "  \"{key}\": {value},").expect("string");
    }
    text.push_str("  \"bodies\": [\n");
    for (k, b) in bodies.iter().enumerate() {
        let shape = shape_json(&b.shape);
        let body = json!({
            "shape": shape,
            "position": [b.position.x, b.position.y],
            "angle": b.angle,
            "velocity": [b.velocity.x, b.velocity.y],
            "omega": b.omega,
            "density": b.density,
        });
        let sep = if k + 1 < bodies.len() { "," } else { "" };
        writeln!(text, "    {body}{sep}").expect("string");
    }
    text.push_str("  ]\n}\n");
    text
}

/// A column of disks for the angle of repose (a dam break): `n` disks, radii uniform in
/// [`R_MIN`, `R_MAX`], density [`DENSITY`], on a loose lattice of 8 columns (spacing 2.5 cm,
/// a little jitter) between a left wall at x = 0 and a right wall (the gate) at x = `width`,
/// on a floor y = 0; P's stiffness, dashpots for restitution 0.5 (as the piles), Coulomb
/// friction `friction`, the area law. See `dem2d study repose` for the protocol.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColumnSpec {
    pub n: usize,
    pub width: f64,
    pub seed: u64,
    pub friction: f64,
}

impl ColumnSpec {
    /// The bodies on their lattice, at rest.
    pub fn lattice_bodies(&self) -> Vec<BodyInit> {
        let mut rng = SplitMix64(self.seed);
        let (cols, spacing) = (((self.width / 2.5).floor() as usize).max(1), 2.5);
        let x0 = 0.5 * (self.width - cols as f64 * spacing);
        (0..self.n)
            .map(|k| {
                let (row, col) = (k / cols, k % cols);
                let r = round6(rng.range(R_MIN, R_MAX));
                let x = round6(x0 + spacing * (col as f64 + 0.5) + rng.range(-0.1, 0.1));
                BodyInit {
                    material: 0,
                    prescribed: false,
                    shape: Shape::Circle { r },
                    position: Vec2::new(x, round6(spacing * (row as f64 + 0.5))),
                    angle: 0.0,
                    velocity: Vec2::zeros(),
                    omega: 0.0,
                    density: DENSITY,
                }
            })
            .collect()
    }

    /// The case of `bodies` in the column, the gate withdrawing at `gate_speed` (cm/s; 0:
    /// fixed), with the further contact keys `extra` on every contact (a part's `given`) and a
    /// sentence on them for the description; P's quiescence criterion at 1e-7 cm per step held
    /// for 1000 steps, or 6 s.
    pub fn case_json(
        &self,
        name: &str,
        bodies: &[BodyInit],
        gate_speed: f64,
        extra: &[(&'static str, Given)],
        note: &str,
    ) -> String {
        self.column_case(name, bodies, gate_speed, extra, None, note)
    }

    /// The case of [`ColumnSpec::case_json`] with cohesion `cohesion` (dyn/cm², `contact.cohesion`)
    /// between the grains and with the floor, and none with the side walls (the left wall and
    /// the gate are given `"cohesion": 0`, so that the heap does not hang on the wall it leans
    /// against): `dem2d study repose-cohesion`'s runs.
    pub fn cohesive_case_json(
        &self,
        name: &str,
        bodies: &[BodyInit],
        gate_speed: f64,
        extra: &[(&'static str, Given)],
        cohesion: f64,
        note: &str,
    ) -> String {
        self.column_case(name, bodies, gate_speed, extra, Some(cohesion), note)
    }

    /// [`ColumnSpec::case_json`], and with `cohesion` [`ColumnSpec::cohesive_case_json`].
    fn column_case(
        &self,
        name: &str,
        bodies: &[BodyInit],
        gate_speed: f64,
        extra: &[(&'static str, Given)],
        cohesion: Option<f64>,
        note: &str,
    ) -> String {
        let eta = {
            let m = DENSITY * std::f64::consts::PI;
            let kn = KN_OVER_RHO_G * DENSITY * G;
            round6(2.0 * damping_ratio_linear(RESTITUTION) * (m * kn).sqrt()) // T(12)
        };
        let mut contact = json!({
            "model": "linear", "normal_force": "area", "kn_over_rho_g": KN_OVER_RHO_G,
            "eta_n": eta, "friction": self.friction,
        });
        for &(k, v) in extra {
            contact[k] = match v {
                Given::Number(x) => json!(x),
                Given::Text(t) => json!(t),
            };
        }
        let mut gate = json!({"point": [self.width, 0.0], "normal": [-1.0, 0.0]});
        if gate_speed != 0.0 {
            gate["velocity"] = json!([gate_speed, 0.0]);
        }
        let mut left = left_wall();
        let study = match cohesion {
            None => "repose",
            Some(c) => {
                contact["cohesion"] = json!(c);
                left["cohesion"] = json!(0.0);
                gate["cohesion"] = json!(0.0);
                "repose-cohesion"
            }
        };
        let description = format!(
            "Angle of repose (dem2d study {study}): {} disks in a column {} cm wide; the right \
             wall withdraws at {gate_speed} cm/s and the grains flow out over the floor until at \
             rest. {note}",
            bodies.len(),
            self.width
        );
        settling_case_text(
            name,
            &description,
            [DT, 6.0, QUIESCENCE],
            contact,
            [left, gate],
            bodies,
        )
    }
}

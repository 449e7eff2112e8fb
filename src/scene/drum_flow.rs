//! A bed of grains in a turning drum (issue 44, item 3): its free surface, its flowing layer and
//! its regime, measured over a chain of Froude numbers `Fr = ω²R/g`.
//!
//! The regimes are those of Mellmann (2001), "The transverse motion of solids in rotating
//! cylinders — forms of motion and transition behavior", Powder Technol. 118, 251–270: slumping
//! (intermittent avalanches), rolling (a steady flow down a plane surface), cascading (a curved,
//! kidney-shaped surface), cataracting (grains thrown off the bed into free flight) and
//! centrifuging (the bed turns with the drum as a ring). Here each is decided from measured
//! quantities ([`Regime::of`]), never from Fr itself.
//!
//! [`run`] builds one bed ([`DrumSpec::case_text`]: grains on a lattice in the lower part of the
//! drum, settled at rest), then turns the drum through the stages of a program, one Froude
//! number after the other, each stage continuing from the previous one's bed (the transient of
//! a stage is then one change of slope, not the whole rise of the bed from rest). Each stage
//! waits out a transient and then samples the bed every `sample` seconds ([`Meter`]).

use crate::dynamics::World;
use crate::geometry::{Shape, Vec2};
use crate::run::{RunError, Simulation};
use crate::scene::Case;
use crate::scene::generate::Xorshift;

/// Gravity (cm/s²).
pub const G: f64 = 980.0;

/// A drum study: the drum, the grains, the contact law and the chain of Froude numbers.
#[derive(Clone, Debug)]
pub struct DrumSpec {
    /// Drum radius R (cm).
    pub radius: f64,
    /// The grains' equal-area radii, uniform in `[r_min, r_max]` (cm).
    pub r_min: f64,
    pub r_max: f64,
    /// Aspect ratio a/b (1: disks, else ellipses of the same areas).
    pub aspect: f64,
    /// Grains: enough to fill half the drum at this packing fraction.
    pub fill_phi: f64,
    pub seed: u64,
    /// Coulomb friction (grains and the drum), restitution, k_n/(ρ g) (cm; k_t = k_n).
    pub friction: f64,
    pub restitution: f64,
    pub kn_over_rho_g: f64,
    /// Δt as a fraction of the a-priori critical step.
    pub dt_fraction: f64,
    /// Settling at rest before the first stage (s).
    pub settle: f64,
    /// The Froude numbers, in the order the stages run.
    pub froude: Vec<f64>,
    /// The first stage's transient (rad of the drum's turn: the bed rises from rest).
    pub first_turn: f64,
    /// Each later stage's transient and measurement, in rad of the drum's turn, and at least
    /// the given seconds.
    pub transient_turn: f64,
    pub transient_min: f64,
    pub measure_turn: f64,
    pub measure_min: f64,
    /// Sampling interval (s).
    pub sample: f64,
}

impl DrumSpec {
    /// The study's drum (R = 6 cm, radii 0.3–0.4 cm, about 120 grains).
    pub fn standard(aspect: f64, froude: Vec<f64>) -> DrumSpec {
        DrumSpec {
            radius: 6.0,
            r_min: 0.3,
            r_max: 0.4,
            aspect,
            fill_phi: 0.82,
            seed: 7,
            friction: 0.5,
            restitution: 0.5,
            kn_over_rho_g: 2000.0,
            dt_fraction: 0.2,
            settle: 0.4,
            froude,
            first_turn: 1.2,
            transient_turn: 0.25,
            transient_min: 0.5,
            measure_turn: 0.35,
            measure_min: 1.5,
            sample: 0.01,
        }
    }

    /// A small drum for tests (R = 4 cm, about 50 grains) and shorter measurements.
    pub fn quick(aspect: f64, froude: Vec<f64>) -> DrumSpec {
        DrumSpec {
            radius: 4.0,
            measure_min: 1.0,
            ..DrumSpec::standard(aspect, froude)
        }
    }

    /// The drum's angular velocity at `fr`, `ω = √(Fr g/R)` (rad/s).
    pub fn omega(&self, fr: f64) -> f64 {
        (fr * G / self.radius).sqrt()
    }

    /// The mean equal-area diameter of the grains (cm).
    pub fn diameter(&self) -> f64 {
        self.r_min + self.r_max
    }

    /// The stages' (start, end of transient, end) times (s).
    pub fn stages(&self) -> Vec<(f64, f64, f64)> {
        let mut t = self.settle;
        self.froude
            .iter()
            .enumerate()
            .map(|(k, &fr)| {
                let w = self.omega(fr);
                let tr = if k == 0 {
                    (self.first_turn / w).max(self.transient_min)
                } else {
                    (self.transient_turn / w).max(self.transient_min)
                };
                let me = (self.measure_turn / w).max(self.measure_min);
                let s = (t, t + tr, t + tr + me);
                t = s.2;
                s
            })
            .collect()
    }

    /// The grains: their shapes, on a lattice in the drum from its bottom up (ellipses lying
    /// flat, rows `2.1 b` apart and `2.1 a` between centres), enough to fill half the drum at
    /// `fill_phi`.
    fn bodies(&self) -> Vec<(Shape, Vec2)> {
        let mut rng = Xorshift(0x2545_F491_4F6C_DD1D ^ self.seed);
        let r2 = (self.r_max.powi(3) - self.r_min.powi(3)) / (3.0 * (self.r_max - self.r_min));
        let n = (self.fill_phi * 0.5 * self.radius * self.radius / r2).round() as usize;
        let (a, b) = (
            self.r_max * self.aspect.sqrt(),
            self.r_max / self.aspect.sqrt(),
        );
        let (sx, sy) = (2.1 * a, 2.1 * b);
        let mut out = Vec::with_capacity(n);
        let mut row = 0;
        while out.len() < n {
            let y = -self.radius + 1.05 * b + row as f64 * sy;
            assert!(y < self.radius, "the lattice does not hold {n} grains");
            let shift = if row % 2 == 0 { 0.0 } else { 0.5 * sx };
            let m = (self.radius / sx).ceil() as i64 + 1;
            for i in -m..=m {
                let x = i as f64 * sx + shift;
                // The grain's farthest reach, a from its centre, inside the circle.
                if x.hypot(y) + 1.02 * a < self.radius && out.len() < n {
                    let r = self.r_min + (self.r_max - self.r_min) * rng.uniform();
                    let shape = if self.aspect == 1.0 {
                        Shape::Circle { r }
                    } else {
                        Shape::Ellipse {
                            a: r * self.aspect.sqrt(),
                            b: r / self.aspect.sqrt(),
                        }
                    };
                    out.push((shape, Vec2::new(x, y)));
                }
            }
            row += 1;
        }
        out
    }

    /// The case: the drum at rest for `settle` s, then one stage per Froude number
    /// ([`DrumSpec::stages`]), the last one to the end. `dt` is written as given (see
    /// [`DrumSpec::case`] for the one it runs with).
    pub fn case_text(&self, dt: f64) -> String {
        let bodies: Vec<String> = self
            .bodies()
            .iter()
            .map(|(s, p)| {
                let shape = match *s {
                    Shape::Circle { r } => format!(r#"{{"type": "circle", "r": {r:.5}}}"#),
                    Shape::Ellipse { a, b } => {
                        format!(r#"{{"type": "ellipse", "a": {a:.5}, "b": {b:.5}}}"#)
                    }
                    _ => unreachable!(),
                };
                format!(
                    r#"{{ "shape": {shape}, "position": [{:.5}, {:.5}] }}"#,
                    p.x, p.y
                )
            })
            .collect();
        let stages = self.stages();
        let mut motion = vec![format!(
            r#"{{ "until": {}, "angular_velocity": 0 }}"#,
            self.settle
        )];
        for (k, (&fr, s)) in self.froude.iter().zip(&stages).enumerate() {
            let until = if k + 1 == stages.len() {
                String::new()
            } else {
                format!(r#""until": {:.6}, "#, s.2)
            };
            motion.push(format!(
                r#"{{ {until}"angular_velocity": {:.9} }}"#,
                self.omega(fr)
            ));
        }
        let end = stages.last().map_or(self.settle, |s| s.2);
        format!(
            r#"{{ "version": 1, "name": "drum_study_a{}", "units": "cm",
  "description": "dem2d study drum: a drum of radius {} cm half filled with {} grains (aspect {}), turned through Fr = {:?}",
  "gravity": [0, -{G}], "dt": {dt:e}, "duration": {end:.6},
  "contact": {{ "model": "linear", "kn_over_rho_g": {}, "ks_over_rho_g": {}, "restitution": {},
               "friction": {} }},
  "walls": [ {{ "drum": {{ "center": [0, 0], "radius": {} }}, "motion": [{}] }} ],
  "bodies": [{}] }}"#,
            self.aspect,
            self.radius,
            bodies.len(),
            self.aspect,
            self.froude,
            self.kn_over_rho_g,
            self.kn_over_rho_g,
            self.restitution,
            self.friction,
            self.radius,
            motion.join(", "),
            bodies.join(",\n  ")
        )
    }

    /// The case, stepped at `dt_fraction` of its a-priori critical step.
    pub fn case(&self) -> Case {
        let case = Case::from_json(&self.case_text(1e-5)).expect("the drum study's case");
        let dt = self.dt_fraction * case.critical_dt();
        case.with_dt(dt)
    }
}

/// Mellmann's (2001) forms of transverse motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Regime {
    Slumping,
    Rolling,
    Cascading,
    Cataracting,
    Centrifuging,
}

impl Regime {
    pub fn as_str(self) -> &'static str {
        match self {
            Regime::Slumping => "slumping",
            Regime::Rolling => "rolling",
            Regime::Cascading => "cascading",
            Regime::Cataracting => "cataracting",
            Regime::Centrifuging => "centrifuging",
        }
    }

    /// The regime of a measured stage, by the first that holds of:
    /// - centrifuging: the bed's centre of mass lies within [`CENTRED`] R of the axis (a ring
    ///   on the wall; a half-filled bed's lies 4R/(3π) ≈ 0.42 R off it) and at least
    ///   [`COROTATING`] of the grains turn with the drum (relative speed under a tenth of ωR);
    /// - cataracting: at least [`FLYING`] of the grains, on average, are in free flight: they
    ///   touch nothing and their centre lies more than a diameter above the surface's line;
    /// - slumping: the bed flows (at least [`FLOWING`] of its grains move faster than
    ///   [`FLOW_SPEED`] √(g d) relative to the drum's rotation) less than [`FLOW_TIME`] of the
    ///   time;
    /// - cascading: the mean free surface is not a plane: its cubic fit departs from its line
    ///   by a grain diameter or more ([`BULGE`]);
    /// - rolling: otherwise.
    pub fn of(p: &StagePoint) -> Regime {
        if p.corotating >= COROTATING && p.com < CENTRED {
            Regime::Centrifuging
        } else if p.flying >= FLYING {
            Regime::Cataracting
        } else if p.flow_time < FLOW_TIME {
            Regime::Slumping
        } else if p.bulge >= BULGE {
            Regime::Cascading
        } else {
            Regime::Rolling
        }
    }
}

/// The thresholds of [`Regime::of`].
pub const COROTATING: f64 = 0.5;
pub const CENTRED: f64 = 0.15;
pub const FLYING: f64 = 0.05;
pub const FLOWING: f64 = 0.02;
pub const FLOW_SPEED: f64 = 0.1;
pub const FLOW_TIME: f64 = 0.9;
pub const BULGE: f64 = 1.0;

/// What one stage measured.
#[derive(Clone, Debug)]
pub struct StagePoint {
    pub froude: f64,
    pub omega: f64,
    /// The angle (°) of the line through the mean free surface, and the standard deviation of
    /// the instantaneous surfaces' angles.
    pub angle: f64,
    pub angle_sd: f64,
    /// The mean surface's rms off its line and the largest departure of its cubic fit from
    /// the line, in mean diameters d.
    pub rms: f64,
    pub bulge: f64,
    /// The flowing layer's thickness at the drum's centre line, in d (NaN where the mean
    /// velocity does not change sign).
    pub thickness: f64,
    /// The fraction of samples in which the bed flows, and the avalanches (starts of flow).
    pub flow_time: f64,
    pub avalanches: usize,
    /// Mean fractions of grains in free flight, and turning with the drum.
    pub flying: f64,
    pub corotating: f64,
    /// Mean distance of the centre of mass from the axis, in R.
    pub com: f64,
    /// The largest reach of a grain beyond the drum's circle and the largest contact overlap,
    /// over the samples, in d.
    pub reach: f64,
    pub overlap: f64,
    /// The mean velocity profile at the centre line: (depth below the surface in d, mean
    /// velocity along the surface, up-slope positive, cm/s).
    pub profile: Vec<(f64, f64)>,
    pub samples: usize,
    /// Simulated time of the stage (s).
    pub duration: f64,
}

impl StagePoint {
    pub fn regime(&self) -> Regime {
        Regime::of(self)
    }
}

/// The top of a body, its centre's height plus its half extent in y.
fn top(shape: &Shape, y: f64, angle: f64, bound: f64) -> f64 {
    match *shape {
        Shape::Circle { r } => y + r,
        Shape::Ellipse { a, b } => {
            let (s, c) = angle.sin_cos();
            y + ((a * s).powi(2) + (b * c).powi(2)).sqrt()
        }
        _ => y + bound,
    }
}

/// The free surface of a bed in a drum centred at `center`: the top of the highest body in each
/// bin `[c_x + k bin, c_x + (k+1) bin)`, `k` in `-m..m` (bins without a body are left out),
/// as (bin centre, top) relative to the centre.
pub fn surface_tops(world: &World, center: Vec2, bin: f64, m: i64) -> Vec<(f64, f64)> {
    let b = &world.bodies;
    let mut tops = vec![f64::NEG_INFINITY; 2 * m as usize];
    for k in 0..b.len() {
        let s = &b.state[k];
        let p = s.pose.position - center;
        let i = (p.x / bin).floor() as i64;
        if (-m..m).contains(&i) {
            let t = top(&b.shape[k], p.y, s.pose.angle(), b.bound[k]);
            let slot = &mut tops[(i + m) as usize];
            *slot = slot.max(t);
        }
    }
    tops.iter()
        .enumerate()
        .filter(|(_, t)| t.is_finite())
        .map(|(i, &t)| ((i as f64 - m as f64 + 0.5) * bin, t))
        .collect()
}

/// The least-squares line `y = a + b x` through `pts` and its rms residual: (a, b, rms).
pub fn fit_line(pts: &[(f64, f64)]) -> (f64, f64, f64) {
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let slope = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
        / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>();
    let rms = (pts
        .iter()
        .map(|p| (p.1 - my - slope * (p.0 - mx)).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    (my - slope * mx, slope, rms)
}

/// The least-squares cubic through `pts` (x scaled by `scale`), by the normal equations:
/// its values at the points.
#[allow(clippy::needless_range_loop)] // a 4 × 5 augmented matrix, by its indices
fn fit_cubic(pts: &[(f64, f64)], scale: f64) -> Vec<f64> {
    let mut m = [[0.0f64; 5]; 4];
    for &(x, y) in pts {
        let u = x / scale;
        let p = [1.0, u, u * u, u * u * u];
        for i in 0..4 {
            for j in 0..4 {
                m[i][j] += p[i] * p[j];
            }
            m[i][4] += p[i] * y;
        }
    }
    // Gauss–Jordan with partial pivoting.
    for c in 0..4 {
        let piv = (c..4)
            .max_by(|&i, &j| m[i][c].abs().total_cmp(&m[j][c].abs()))
            .unwrap();
        m.swap(c, piv);
        for r in 0..4 {
            if r != c {
                let f = m[r][c] / m[c][c];
                for k in c..5 {
                    m[r][k] -= f * m[c][k];
                }
            }
        }
    }
    let coef: Vec<f64> = (0..4).map(|i| m[i][4] / m[i][i]).collect();
    pts.iter()
        .map(|&(x, _)| {
            let u = x / scale;
            coef[0] + u * (coef[1] + u * (coef[2] + u * coef[3]))
        })
        .collect()
}

/// Accumulates one stage's samples.
pub struct Meter {
    center: Vec2,
    radius: f64,
    omega: f64,
    d: f64,
    bin: f64,
    m: i64,
    /// Per surface bin: sum of tops, samples.
    tops: Vec<(f64, usize)>,
    angles: Vec<f64>,
    /// Per depth bin (d/2): sum of velocities, count.
    layer: Vec<(f64, usize)>,
    flowing: Vec<bool>,
    flying: f64,
    corotating: f64,
    com: f64,
    reach: f64,
    overlap: f64,
}

impl Meter {
    /// A meter for a drum of centre `center` and radius `radius` turning at `omega`, grains of
    /// mean diameter `d`. The surface is read in bins one diameter wide over the middle
    /// `1.5 R` of the chord.
    pub fn new(center: Vec2, radius: f64, omega: f64, d: f64) -> Meter {
        let m = (0.75 * radius / d).floor() as i64;
        Meter {
            center,
            radius,
            omega,
            d,
            bin: d,
            m,
            tops: vec![(0.0, 0); 2 * m as usize],
            angles: Vec::new(),
            layer: vec![(0.0, 0); (2.0 * radius / (0.5 * d)).ceil() as usize],
            flowing: Vec::new(),
            flying: 0.0,
            corotating: 0.0,
            com: 0.0,
            reach: 0.0,
            overlap: 0.0,
        }
    }

    /// One sample of the bed.
    #[allow(clippy::needless_range_loop)] // body k's state, mass, bound and contacts
    pub fn sample(&mut self, w: &mut World) {
        let n = w.bodies.len();
        let c = self.center;
        let tops = surface_tops(w, c, self.bin, self.m);
        for &(x, t) in &tops {
            let i = ((x / self.bin).floor() + self.m as f64) as usize;
            self.tops[i].0 += t;
            self.tops[i].1 += 1;
        }
        // This sample's surface line, its unit vector up the slope t and normal nrm.
        let (a, slope, _) = if tops.len() >= 2 {
            fit_line(&tops)
        } else {
            (0.0, 0.0, 0.0)
        };
        let theta = slope.atan();
        self.angles.push(theta.to_degrees());
        let t = Vec2::new(theta.cos(), theta.sin());
        let nrm = Vec2::new(-theta.sin(), theta.cos());
        // The line's distance from the centre along nrm (the point (0, a) is on it).
        let offset = a * theta.cos();
        let v_flow = FLOW_SPEED * (G * self.d).sqrt();
        let mut touching = vec![false; n];
        for (slot, _) in w.contacts.slots.iter().zip(&w.contacts.data) {
            if slot.active {
                touching[slot.i as usize] = true;
                if let crate::dynamics::Partner::Body(j) = slot.partner() {
                    touching[j] = true;
                }
            }
        }
        let (mut flowing, mut flying, mut co) = (0usize, 0usize, 0usize);
        let (mut mass, mut mx) = (0.0, Vec2::zeros());
        for k in 0..n {
            let s = &w.bodies.state[k];
            let r = s.pose.position - c;
            let rigid = Vec2::new(-r.y, r.x) * self.omega;
            let rel = (s.vel - rigid).norm();
            if rel > v_flow {
                flowing += 1;
            }
            if rel < 0.1 * self.omega * self.radius {
                co += 1;
            }
            // In free flight: touching nothing, its centre more than a diameter above this
            // sample's surface line (off the bed, not a grain hopping along its surface).
            if !touching[k] && r.dot(&nrm) - offset > self.d {
                flying += 1;
            }
            let m = w.bodies.mass[k];
            mass += m;
            mx += r * m;
            self.reach = self
                .reach
                .max((r.norm() + w.bodies.bound[k] - self.radius) / self.d);
            // The velocity profile along the centre line's normal.
            if r.dot(&t).abs() < self.d {
                let depth = offset - r.dot(&nrm);
                if depth >= 0.0 {
                    let i = (depth / (0.5 * self.d)) as usize;
                    if i < self.layer.len() {
                        self.layer[i].0 += s.vel.dot(&t);
                        self.layer[i].1 += 1;
                    }
                }
            }
        }
        self.flowing
            .push(flowing as f64 >= (FLOWING * n as f64).max(2.0));
        self.flying += flying as f64 / n as f64;
        self.corotating += co as f64 / n as f64;
        self.com += (mx / mass).norm() / self.radius;
        w.refresh_contact_extras();
        for (slot, e) in w.contacts.slots.iter().zip(&w.contacts.extra) {
            if slot.active {
                self.overlap = self.overlap.max(e.depth / self.d);
            }
        }
    }

    /// The stage's results.
    pub fn finish(&self, froude: f64, duration: f64) -> StagePoint {
        let k = self.angles.len().max(1) as f64;
        // The mean surface: the bins that held a body in at least half the samples.
        let mean: Vec<(f64, f64)> = self
            .tops
            .iter()
            .enumerate()
            .filter(|(_, t)| t.1 as f64 >= 0.5 * k)
            .map(|(i, t)| {
                (
                    (i as f64 - self.m as f64 + 0.5) * self.bin,
                    t.0 / t.1 as f64,
                )
            })
            .collect();
        let (angle, rms, bulge) = if mean.len() >= 4 {
            let (a, b, rms) = fit_line(&mean);
            let cubic = fit_cubic(&mean, self.radius);
            let bulge = mean
                .iter()
                .zip(&cubic)
                .map(|(p, q)| (q - a - b * p.0).abs())
                .fold(0.0, f64::max);
            (b.atan().to_degrees(), rms / self.d, bulge / self.d)
        } else {
            (f64::NAN, f64::NAN, f64::NAN)
        };
        let ma = self.angles.iter().sum::<f64>() / k;
        let angle_sd = (self.angles.iter().map(|x| (x - ma).powi(2)).sum::<f64>() / k).sqrt();
        let profile: Vec<(f64, f64)> = self
            .layer
            .iter()
            .enumerate()
            .filter(|(_, b)| b.1 as f64 >= 0.2 * k)
            .map(|(i, b)| ((i as f64 + 0.5) * 0.5, b.0 / b.1 as f64))
            .collect();
        // The first change of sign from down-slope (u < 0) to up-slope, from the surface down,
        // interpolated between the bins' centres.
        let mut thickness = f64::NAN;
        for pair in profile.windows(2) {
            let ((d0, u0), (d1, u1)) = (pair[0], pair[1]);
            if u0 < 0.0 && u1 >= 0.0 {
                thickness = d0 + (d1 - d0) * (-u0) / (u1 - u0);
                break;
            }
        }
        let flow_time =
            self.flowing.iter().filter(|&&f| f).count() as f64 / self.flowing.len().max(1) as f64;
        let avalanches = self.flowing.windows(2).filter(|p| !p[0] && p[1]).count();
        StagePoint {
            froude,
            omega: self.omega,
            angle,
            angle_sd,
            rms,
            bulge,
            thickness,
            flow_time,
            avalanches,
            flying: self.flying / k,
            corotating: self.corotating / k,
            com: self.com / k,
            reach: self.reach,
            overlap: self.overlap,
            profile,
            samples: self.angles.len(),
            duration,
        }
    }
}

/// The outcome of [`run`]: one point per stage, and the steps taken and Δt.
#[derive(Clone, Debug)]
pub struct DrumRun {
    pub points: Vec<StagePoint>,
    pub grains: usize,
    pub steps: u64,
    pub dt: f64,
}

/// Runs the chain of stages of `spec` and measures each.
pub fn run(spec: &DrumSpec) -> Result<DrumRun, RunError> {
    let case = spec.case();
    let mut w = case.build_world();
    let dt = w.dt;
    let stages = spec.stages();
    let d = spec.diameter();
    let every = ((spec.sample / dt).round() as u64).max(1);
    let end = stages.last().map_or(spec.settle, |s| s.2);
    let steps = (end / dt).ceil() as u64;
    let mut meters: Vec<Meter> = spec
        .froude
        .iter()
        .map(|&fr| Meter::new(Vec2::zeros(), spec.radius, spec.omega(fr), d))
        .collect();
    Simulation::new(&mut w).until_step(steps).run_each(|w, _| {
        if w.step % every != 0 {
            return;
        }
        let t = w.time;
        if let Some(k) = stages.iter().position(|s| t > s.1 && t <= s.2) {
            meters[k].sample(w);
        }
    })?;
    let points = meters
        .iter()
        .zip(&spec.froude)
        .zip(&stages)
        .map(|((m, &fr), s)| m.finish(fr, s.2 - s.0))
        .collect();
    Ok(DrumRun {
        points,
        grains: w.bodies.len(),
        steps,
        dt,
    })
}

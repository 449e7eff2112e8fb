//! Samples for biaxial tests: grains on a loose lattice in a box of four walls that are servos
//! holding a confining stress (isotropic compaction), and the case of the shear stage that
//! follows (two walls at a prescribed strain rate, two servos).
//!
//! Grains: radii uniform in [0.8, 1.2] cm (the radius of the disk of equal area), disks for
//! α = 1 or ellipses `a = r√α`, `b = r/√α` in random orientations; ρ = 2.65 g/cm³; the linear law
//! on the overlap area with P's stiffness `Kn/ρg = 36400 cm` (k_n ≈ 9.45e7 dyn/cm per cm), the
//! shear spring equal to it, a dashpot for restitution 0.5 of a mean disk against a wall; no
//! gravity; Δt = 1e-5 s. The walls are frictionless (as usual in biaxial tests: a wall's friction
//! adds the couples of its shear forces to the sample's mean stress, so that the wall's normal
//! load over its span is no longer the principal stress).

use super::generate::{Xorshift, case_text_from};
use crate::contact_law::damping_ratio_linear;
use crate::dynamics::BodyInit;
use crate::geometry::{Shape, Vec2};
use serde_json::{Value, json};

/// Grain density (g/cm³).
pub const DENSITY: f64 = 2.65;
/// k_n per unit thickness (dyn/cm per cm): P's `Kn/ρg = 36400 cm`.
pub const KN: f64 = 36400.0 * DENSITY * 980.0;
/// Time step (s).
pub const DT: f64 = 1e-5;

/// The four walls of the box `[x0, x1, y0, y1]` as case JSON — bottom, top, left, right, their
/// normals into the box — each given the extra fields of `motions` (`{"servo": …}`,
/// `{"velocity": …}`, or `null`).
pub fn box_walls([x0, x1, y0, y1]: [f64; 4], motions: [Value; 4]) -> Vec<Value> {
    let mut walls = vec![
        json!({"point": [0.0, y0], "normal": [0.0, 1.0]}),
        json!({"point": [0.0, y1], "normal": [0.0, -1.0]}),
        json!({"point": [x0, 0.0], "normal": [1.0, 0.0]}),
        json!({"point": [x1, 0.0], "normal": [-1.0, 0.0]}),
    ];
    for (w, m) in walls.iter_mut().zip(motions) {
        if let Value::Object(m) = m {
            for (k, v) in m {
                w[k] = v;
            }
        }
    }
    walls
}

fn round6(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

/// A sample for a biaxial test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ServoBox {
    /// Grains per side of the starting lattice (n_side² grains).
    pub n_side: usize,
    /// Aspect ratio a/b (1: disks).
    pub aspect: f64,
    pub friction: f64,
    /// Confining stress σ_c (dyn/cm²).
    pub sigma: f64,
    pub seed: u64,
}

impl ServoBox {
    /// The bodies on the starting lattice (spacing: the largest grain's length plus 10 %).
    pub fn bodies(&self) -> Vec<BodyInit> {
        let mut rng = Xorshift(self.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
        let mut uniform = move || rng.uniform();
        let s = self.spacing();
        let n = self.n_side;
        (0..n * n)
            .map(|k| {
                let r = round6(0.8 + 0.4 * uniform());
                let angle = round6(std::f64::consts::PI * uniform());
                let (shape, angle) = if self.aspect == 1.0 {
                    (Shape::Circle { r }, 0.0)
                } else {
                    let q = self.aspect.sqrt();
                    (
                        Shape::Ellipse {
                            a: round6(r * q),
                            b: round6(r / q),
                        },
                        angle,
                    )
                };
                BodyInit {
                    material: 0,
                    prescribed: false,
                    shape,
                    position: Vec2::new(
                        round6(s * ((k % n) as f64 + 0.5)),
                        round6(s * ((k / n) as f64 + 0.5)),
                    ),
                    angle,
                    velocity: Vec2::zeros(),
                    omega: 0.0,
                    density: DENSITY,
                }
            })
            .collect()
    }

    /// Lattice spacing (cm).
    pub fn spacing(&self) -> f64 {
        2.2 * 1.2 * self.aspect.sqrt()
    }

    /// The dashpot η (per unit thickness) for restitution 0.5 of a disk of radius 1 cm against a
    /// wall (T12).
    pub fn eta() -> f64 {
        2.0 * damping_ratio_linear(0.5) * (DENSITY * std::f64::consts::PI * KN).sqrt()
    }

    /// A servo wall holding σ_c over the span between walls a and b.
    pub fn servo(&self, a: usize, b: usize) -> Value {
        json!({"servo": {"stress": self.sigma, "span": [a, b], "max_speed": 20.0}})
    }

    /// The case: `bodies` in the box `[x0, x1, y0, y1]` of four walls (bottom, top, left,
    /// right), each given the extra fields of `motions` (`{"servo": …}`, `{"velocity": …}`).
    pub fn case_json(
        &self,
        name: &str,
        description: &str,
        bodies: &[BodyInit],
        [x0, x1, y0, y1]: [f64; 4],
        motions: [Value; 4],
        duration: f64,
    ) -> String {
        let mut walls = box_walls([x0, x1, y0, y1], motions);
        for w in walls.iter_mut().filter_map(Value::as_object_mut) {
            w.entry("friction").or_insert(json!(0.0));
        }
        let head: [(&str, Value); 10] = [
            ("version", json!(1)),
            ("name", json!(name)),
            ("description", json!(description)),
            ("units", json!("cm")),
            ("gravity", json!([0.0, 0.0])),
            ("dt", json!(DT)),
            ("duration", json!(duration)),
            ("output_every", json!(1000)),
            (
                "contact",
                json!({"model": "linear", "normal_force": "area", "kn": KN, "ks": KN,
                       "eta_n": round6(Self::eta()), "eta_s": round6(Self::eta()),
                       "friction": self.friction}),
            ),
            ("walls", Value::Array(walls)),
        ];
        let bodies: Vec<BodyInit> = bodies
            .iter()
            .map(|b| BodyInit {
                position: b.position.map(round6),
                angle: round6(b.angle),
                ..*b
            })
            .collect();
        case_text_from(&head, &bodies)
    }

    /// The compaction case: the lattice in its box, four servo walls.
    pub fn compaction_case(&self, duration: f64) -> String {
        let side = self.spacing() * self.n_side as f64;
        self.case_json(
            &format!("servo_box_a{}", self.aspect),
            &format!(
                "Isotropic compaction of {} grains (aspect ratio {}, friction {}) by four servo walls \
                 holding {:e} dyn/cm² (dem2d::scene::servo_box).",
                self.n_side * self.n_side,
                self.aspect,
                self.friction,
                self.sigma
            ),
            &self.bodies(),
            [0.0, side, 0.0, side],
            [
                self.servo(2, 3),
                self.servo(2, 3),
                self.servo(0, 1),
                self.servo(0, 1),
            ],
            duration,
        )
    }
}

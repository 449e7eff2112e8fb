//! Boundaries: walls (half-planes) with a pose that may move — at a given velocity, or under a
//! servo that holds a normal stress — and the contact parameters of contacts with them.
//!
//! # Moving walls
//! A wall's line translates with its velocity `v_w` (cm/s; it does not turn). It drifts with the
//! bodies, `p ← p + Δt v_w` at the step's drift, so its position has the bodies' time level; the
//! contact law sees the relative velocity of the body's material point and the wall,
//! `v_body − v_w`, so the dashpots and the shear spring act on the relative motion.
//!
//! **Work.** A wall moving at `v_w` does work `W = ∫ Σ_c F_c · v_w dt` on the bodies (F_c the
//! force of each of its contacts on its body), and the energy account reads
//! `K + P + E_el + D = E₀ + W`: per contact the kinetic power is `F·v_body`, the springs' and
//! the dissipation's are taken on the relative velocity `v_body − v_w`, and the difference is
//! `F·v_w`. The step integrates W with the forces of level n+1 and the velocity of the drift
//! that reached it.
//!
//! # Servo walls
//! A servo wall moves along its normal to hold a target normal stress σ_t on its loaded span:
//! - the **measured stress** is `σ = Σ_c (F_c · n_w) / S`, the total normal force its contacts
//!   push the bodies with (per unit thickness), divided by the **loaded span** S — a length
//!   given in the case (`"span": 10`), or `"span": [a, b]`: the length of this wall's line
//!   between the lines of walls a and b, measured from their current positions (the box's
//!   current width for the top of a box whose sides are walls a and b);
//! - the **control law**: `v_w = G (σ_t − σ) n_w`, capped at `max_speed` (σ below the target:
//!   the wall advances into the material); the velocity for the next step is set from the
//!   forces of this one.
//! - the **gain**: the wall's contacts resist its advance with the stiffness
//!   `K = Σ_c k_n,c (n_c·n_w)²` (force per unit of wall displacement, with the bodies held), so a
//!   step moves the stress by `ΔS = −(K/S) G (σ − σ_t) Δt`: the error is multiplied by
//!   `1 − λ` per step, `λ = G K Δt / S`. The loop is stable for `λ < 2` and without overshoot
//!   for `λ ≤ 1`. By default dem2d sets `G = α S/(K Δt)` each step with α =
//!   [`SERVO_RELAXATION`] = 0.5, i.e. λ = ½ (the servo of Itasca's PFC, whose `α` is the same
//!   relaxation factor): half the error is corrected per step against the contacts' own
//!   stiffness; the bodies behind them are softer, so the actual λ is smaller. With no
//!   contact (K = 0) the wall approaches at `max_speed`. A fixed `gain` may be given instead:
//!   then the case is responsible for `G K Δt/S < 2`.

use crate::contact_law::ContactSpec;
use crate::geometry::{Vec2, Wall};

/// The servo's relaxation factor α: the fraction of the stress error corrected per step against
/// the stiffness of the wall's own contacts.
pub const SERVO_RELAXATION: f64 = 0.5;

/// How a servo wall's loaded span is measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Span {
    /// A fixed length (cm).
    Length(f64),
    /// The length of this wall's line between the lines of walls a and b.
    Between(usize, usize),
}

/// A servo holding a normal stress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Servo {
    /// Target normal stress σ_t (dyn/cm²: force per unit length of the span, per unit
    /// thickness), > 0.
    pub stress: f64,
    pub span: Span,
    /// A fixed gain G (cm/s per dyn/cm²); `None`: `α S/(K Δt)` (see the module documentation).
    pub gain: Option<f64>,
    /// Largest speed of the wall (cm/s).
    pub max_speed: f64,
}

/// How a wall moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// At rest.
    Fixed,
    /// At a constant velocity.
    Velocity(Vec2),
    /// Under a servo.
    Servo(Servo),
}

/// What a wall's contacts did in the last force evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WallLoad {
    /// Σ of the forces on the bodies, and of their non-elastic parts.
    pub force: Vec2,
    pub force_non_elastic: Vec2,
    /// Σ of the contacts' normal stiffness (along the wall normal).
    pub stiffness: f64,
    /// Number of contacts.
    pub contacts: u32,
}

impl WallLoad {
    /// Adds another partial sum.
    #[inline]
    pub fn add(&mut self, o: &WallLoad) {
        self.force += o.force;
        self.force_non_elastic += o.force_non_elastic;
        self.stiffness += o.stiffness;
        self.contacts += o.contacts;
    }
}

/// A wall, the contact parameters of contacts with it (the scene's, or its own overrides), how
/// it moves, and its current velocity and load.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallSpec {
    /// The wall's line now.
    pub wall: Wall,
    pub spec: ContactSpec,
    pub motion: Motion,
    /// Velocity of the current step's drift (zero for a fixed wall).
    pub velocity: Vec2,
    /// Its contacts in the last force evaluation.
    pub load: WallLoad,
}

impl WallSpec {
    /// A fixed wall.
    pub fn new(wall: Wall, spec: ContactSpec) -> Self {
        Self::moving(wall, spec, Motion::Fixed)
    }

    /// A wall moving as `motion` says (its velocity: a constant one at once; a servo's from
    /// the first force evaluation).
    pub fn moving(wall: Wall, spec: ContactSpec, motion: Motion) -> Self {
        let velocity = match motion {
            Motion::Velocity(v) => v,
            _ => Vec2::zeros(),
        };
        WallSpec {
            wall,
            spec,
            motion,
            velocity,
            load: WallLoad::default(),
        }
    }

    /// True unless the wall is fixed.
    #[inline]
    pub fn moves(&self) -> bool {
        !matches!(self.motion, Motion::Fixed)
    }

    /// The normal stress its contacts carry over its loaded span (servo walls), with the
    /// span; `walls` the scene's walls (for a span between two of them).
    pub fn measured_stress(&self, walls: &[WallSpec]) -> Option<(f64, f64)> {
        let Motion::Servo(s) = self.motion else {
            return None;
        };
        let span = span_length(&self.wall, &s.span, walls);
        Some((self.load.force.dot(&self.wall.normal) / span, span))
    }
}

/// The loaded span of a wall (see the module documentation).
pub fn span_length(wall: &Wall, span: &Span, walls: &[WallSpec]) -> f64 {
    match *span {
        Span::Length(l) => l,
        Span::Between(a, b) => {
            let t = Vec2::new(-wall.normal.y, wall.normal.x);
            let along = |o: &Wall| o.normal.dot(&(o.point - wall.point)) / o.normal.dot(&t);
            (along(&walls[a].wall) - along(&walls[b].wall)).abs()
        }
    }
}

/// The servo's velocity for the next step, from the load of the last force evaluation
/// (see the module documentation); `dt` the step.
pub fn servo_velocity(wall: &WallSpec, servo: &Servo, walls: &[WallSpec], dt: f64) -> Vec2 {
    let span = span_length(&wall.wall, &servo.span, walls);
    let stress = wall.load.force.dot(&wall.wall.normal) / span;
    let error = servo.stress - stress;
    let speed = match servo.gain {
        Some(g) => g * error,
        None if wall.load.stiffness > 0.0 => {
            SERVO_RELAXATION * span / (wall.load.stiffness * dt) * error
        }
        None => servo.max_speed.copysign(error),
    };
    wall.wall.normal * speed.clamp(-servo.max_speed, servo.max_speed)
}

//! Boundaries: walls (half-planes) with a pose that may move — at a given velocity, or under a
//! servo that holds a normal stress — and the contact parameters of contacts with them.
//!
//! # Moving walls
//! A wall's line translates with its velocity `v_w` (cm/s; it does not turn). It drifts with the
//! bodies at the step's drift, so its position has the bodies' time level: at a constant
//! velocity `p = p₀ + (t − t₀) v_w` exactly (no rounding accumulates; t₀ = 0 but for a wall
//! given a velocity in a state file, which continues from its point there), under a servo
//! `p ← p + Δt v_w`. The
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
//! - the **control law**: `v_w = G (σ_t − σ_el) n_w`, capped at `max_speed` (below the target
//!   the wall advances into the material), set for the next step from the forces of this one.
//!   It acts on `σ_el`, the elastic part of σ (the springs' normal forces; at steady state the
//!   dashpots carry nothing on average, so σ_el = σ): a dashpot answers the wall's own speed at
//!   once, `C v/S` with `C = Σ_c η_n,c`, and fed back that makes the loop
//!   `e_{n+1} = (1 − a − c) e_n + c e_{n−1}` (`c = G C/S`), which needs `G < S/C` — a gain so
//!   small, with DEM dashpots (`C/Δt` is often ten times the contacts' stiffness K), that the
//!   wall lags 20–40 % behind a dilating sample in a biaxial test.
//! - the **gain**: the wall's contacts resist its displacement with the stiffness
//!   `K = Σ_c k_n,c` (with the bodies held), so a step moves σ_el by `K v Δt/S`: with
//!   `e = σ_t − σ_el`, `e_{n+1} = (1 − a) e_n`, `a = G K Δt/S`, stable for `a < 2` and without
//!   overshoot for `a ≤ 1`. dem2d sets, each step, `G = α S/(K Δt)` with α =
//!   [`SERVO_RELAXATION`] (the servo of Itasca's PFC, whose α is the same relaxation factor):
//!   the error is corrected by the fraction α per step against the contacts' own stiffness;
//!   the bodies behind them are softer, so the actual `a` is smaller. A wall that must follow a
//!   moving sample at speed `v` lags by `e = v/G = v K Δt/(α S)`. With no contact (K = 0) the
//!   wall approaches at `max_speed`. A fixed `gain` may be given instead: then the case is
//!   responsible for `a < 2`.
//!
//! # Wall programs
//! A wall's motion may be a list of stages ([`Program`]), each a constant velocity or a servo,
//! each lasting until a time (the last may last to the end; after a last stage that ends, the
//! wall is at rest): a delayed start, loading then unloading, a stress path. A stage ends at the
//! step nearest its end time, `n_s = round(until/Δt)` (stages closer than a step are refused
//! when the case is read), so a step lies in one stage. A velocity stage is anchored where the
//! wall is when it starts, `p = p_s + v (t − t_s)` with `t_s = n_{s−1} Δt` (no rounding
//! accumulates within it; the displacement over it is `v (n_s − n_{s−1}) Δt`); a servo stage
//! moves the wall as a servo wall. The stage, its anchor point and time are the wall's state
//! (a restart carries them).

use crate::contact_law::ContactSpec;
use crate::geometry::{Drum, Segment, Vec2, Wall};
use crate::narrow_phase::Side;

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
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    /// At rest.
    Fixed,
    /// At a constant velocity.
    Velocity(Vec2),
    /// Under a servo.
    Servo(Servo),
    /// A program of stages (see the module documentation).
    Program(Program),
}

/// What a wall does during one stage of its program.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StageMotion {
    /// A constant velocity (zero: at rest).
    Velocity(Vec2),
    /// A servo.
    Servo(Servo),
}

/// One stage of a wall's program: its motion, until `until` (s; `None`: to the end), and its
/// angular velocity about the wall's pivot (rad/s, counter-clockwise; 0 for one that does not
/// turn: see [`Turn`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stage {
    pub until: Option<f64>,
    pub motion: StageMotion,
    pub angular_velocity: f64,
}

/// A wall's program: its stages in time order.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    pub stages: Vec<Stage>,
}

impl Program {
    /// The step at which stage `s` ends, `round(until/Δt)` (`u64::MAX`: it lasts to the end).
    #[inline]
    pub fn end_step(&self, s: usize, dt: f64) -> u64 {
        match self.stages[s].until {
            Some(t) => (t / dt).round() as u64,
            None => u64::MAX,
        }
    }

    /// The stage that governs the step from step `n` to `n + 1`: the first that ends after
    /// step n; `stages.len()` after the last (at rest).
    pub fn stage_at(&self, n: u64, dt: f64) -> usize {
        (0..self.stages.len())
            .find(|&s| self.end_step(s, dt) > n)
            .unwrap_or(self.stages.len())
    }

    /// The angular velocity of stage `s` (0 after the last).
    #[inline]
    pub fn angular_velocity(&self, s: usize) -> f64 {
        self.stages.get(s).map_or(0.0, |st| st.angular_velocity)
    }

    /// The motion of stage `s` (at rest after the last).
    #[inline]
    pub fn motion(&self, s: usize) -> StageMotion {
        self.stages
            .get(s)
            .map_or(StageMotion::Velocity(Vec2::zeros()), |st| st.motion)
    }
}

/// What a wall's contacts did in the last force evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WallLoad {
    /// Σ of the forces on the bodies, and of their non-elastic parts.
    pub force: Vec2,
    pub force_non_elastic: Vec2,
    /// A turning boundary's Σ of the moments of the forces and couples on the bodies about its
    /// pivot (a drum's centre), `Σ ℓ_c × F_c + M_c` ([`Boundary::lever`]), and of their
    /// non-elastic parts: its power is `F·v + ω M` (see [`Turn`]); 0 for one that does not
    /// turn.
    pub torque: f64,
    pub torque_non_elastic: f64,
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
        self.torque += o.torque;
        self.torque_non_elastic += o.torque_non_elastic;
        self.stiffness += o.stiffness;
        self.contacts += o.contacts;
    }
}

/// What a boundary is, geometrically. Every use matches it exhaustively: a new kind (a segment,
/// a periodic cell's seam) is added here and wherever the compiler then asks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BoundaryKind {
    /// A half-plane: its line, and the normal pointing into the free side.
    Wall(Wall),
    /// A finite segment, both of whose sides are solid and whose ends are points (see
    /// [`Segment`] and `narrow_phase::segment`).
    Segment(Segment),
    /// A drum: a circle with the bodies inside (see [`Drum`] and `narrow_phase::drum`), and
    /// the line through its centre with the normal `(0, 1)` (what [`Boundary::line`] gives:
    /// a drum has no line of its own, and the readers of a line — servo spans, drawings of
    /// half-planes — are for half-planes and segments).
    Drum(Drum, Wall),
}

impl BoundaryKind {
    /// The drum `d` as a boundary kind.
    pub fn drum(d: Drum) -> Self {
        let line = Wall::new(d.center, Vec2::new(0.0, 1.0)).expect("a drum's centre is finite");
        BoundaryKind::Drum(d, line)
    }

    /// This geometry turned by `angle` (rad, counter-clockwise) about `origin` and then
    /// translated by `shift` (a segment's ends and a half-plane's point and normal; a drum's
    /// centre, its circle being the same at every angle).
    pub fn turned(&self, origin: Vec2, angle: f64, shift: Vec2) -> Self {
        let (s, c) = angle.sin_cos();
        let rot = |v: Vec2| Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y);
        let place = |x: Vec2| origin + shift + rot(x - origin);
        match self {
            BoundaryKind::Wall(w) => BoundaryKind::Wall(
                Wall::new(place(w.point), rot(w.normal)).expect("a turned wall stays a wall"),
            ),
            BoundaryKind::Segment(g) => BoundaryKind::Segment(
                Segment::new(place(g.a), place(g.b)).expect("a turned segment stays a segment"),
            ),
            BoundaryKind::Drum(d, _) => BoundaryKind::drum(Drum {
                center: d.center + shift,
                radius: d.radius,
            }),
        }
    }
}

/// How a boundary turns about its pivot `P` (a drum about its centre; a half-plane or a segment
/// given `angular_velocity` and `pivot`): its geometry now is the case's turned by `angle`
/// about the case's pivot, then carried by the translation of the pivot (which moves as the
/// boundary's reference point would: [`Boundary::anchor`]). The wall's velocity at a point x is
/// `v + ω ẑ × (x − P)`, which the contact law's relative velocity reads; its spin `ω` enters the
/// relative spin of rolling resistance; its power on the bodies is
/// `Σ_c F_c · (v + ω ẑ × (x_c − P)) = F·v + ω Σ_c (x_c − P) × F_c` (the energy account's wall
/// work). The angle at a constant angular velocity is `θ = θ_s + ω (t − t_s)` from the anchor
/// of the translation (no rounding accumulates).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Turn {
    /// The geometry at angle 0, and its pivot then.
    pub reference: BoundaryKind,
    pub origin: Vec2,
    /// The pivot now.
    pub pivot: Vec2,
    /// The angle turned from the reference (rad, counter-clockwise).
    pub angle: f64,
    /// The angle at the boundary's `start_time`.
    pub start_angle: f64,
    /// The angular velocity of a boundary without a program (rad/s).
    pub rate: f64,
    /// The angular velocity of the current step's drift (rad/s).
    pub omega: f64,
}

/// A boundary: its kind and pose, the contact parameters of contacts with it (the scene's, or
/// its own overrides), how it moves, and its current velocity and load.
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    /// The boundary where it is now.
    pub kind: BoundaryKind,
    /// Its reference point at `start_time` (the anchor of a constant velocity's motion, and of
    /// a program's current stage).
    pub start: Vec2,
    /// When it was at `start`: 0, or the time of a state file from which a wall given a new
    /// velocity continues from where it is (see `scene::state`), or when the program's
    /// current stage began.
    pub start_time: f64,
    /// A program's current stage (the stage of the last drift; 0 before the first).
    pub stage: usize,
    /// Its contact law when it has its own (`material` None), else its material's.
    pub spec: ContactSpec,
    /// Its material (`None`: its own law, `spec`, governs its contacts with every body; see
    /// [`super::materials`]).
    pub material: Option<u16>,
    pub motion: Motion,
    /// Velocity of the current step's drift (zero for a fixed boundary).
    pub velocity: Vec2,
    /// Its contacts in the last force evaluation.
    pub load: WallLoad,
    /// How it turns, if it may (a drum always has one, of rate 0 when it stands still).
    pub turn: Option<Turn>,
}

impl Boundary {
    /// A fixed wall.
    pub fn new(wall: Wall, spec: ContactSpec) -> Self {
        Self::moving(wall, spec, Motion::Fixed)
    }

    /// A wall moving as `motion` says (its velocity: a constant one at once; a servo's from
    /// the first force evaluation).
    pub fn moving(wall: Wall, spec: ContactSpec, motion: Motion) -> Self {
        Self::of_kind(BoundaryKind::Wall(wall), spec, motion)
    }

    /// A boundary of kind `kind` moving as `motion` says (a segment moves at a velocity or by
    /// a program of velocity stages; a servo is for half-plane walls).
    pub fn of_kind(kind: BoundaryKind, spec: ContactSpec, motion: Motion) -> Self {
        let velocity = match &motion {
            Motion::Velocity(v) => *v,
            Motion::Program(p) => match p.motion(0) {
                StageMotion::Velocity(v) => v,
                StageMotion::Servo(_) => Vec2::zeros(),
            },
            Motion::Fixed | Motion::Servo(_) => Vec2::zeros(),
        };
        let start = match &kind {
            BoundaryKind::Wall(w) => w.point,
            BoundaryKind::Segment(s) => s.a,
            BoundaryKind::Drum(d, _) => d.center,
        };
        let turn = match &kind {
            BoundaryKind::Drum(d, _) => Some(Turn::new(kind, d.center, 0.0)),
            BoundaryKind::Wall(_) | BoundaryKind::Segment(_) => None,
        };
        let mut b = Boundary {
            kind,
            start,
            start_time: 0.0,
            stage: 0,
            spec,
            material: None,
            motion,
            velocity,
            load: WallLoad::default(),
            turn,
        };
        let omega = b.angular_velocity_at_start();
        if let Some(t) = &mut b.turn {
            t.omega = omega;
        }
        b
    }

    /// The same boundary turning about `pivot` at the constant angular velocity `rate` (rad/s;
    /// with a program, its stages' `angular_velocity` instead): a drum about its centre
    /// whatever `pivot`.
    pub fn turning(mut self, pivot: Vec2, rate: f64) -> Self {
        let pivot = match &self.kind {
            BoundaryKind::Drum(d, _) => d.center,
            BoundaryKind::Wall(_) | BoundaryKind::Segment(_) => pivot,
        };
        let mut t = Turn::new(self.kind, pivot, rate);
        self.start = pivot;
        if let Motion::Fixed = self.motion
            && rate != 0.0
        {
            // Anchored as a constant velocity of zero is: θ = ω (t − t₀).
            self.motion = Motion::Velocity(Vec2::zeros());
        }
        self.turn = Some(t);
        t.omega = self.angular_velocity_at_start();
        self.turn = Some(t);
        self
    }

    /// The angular velocity of the first drift.
    fn angular_velocity_at_start(&self) -> f64 {
        match (&self.motion, &self.turn) {
            (Motion::Program(p), Some(_)) => p.angular_velocity(0),
            (Motion::Velocity(_), Some(t)) => t.rate,
            _ => 0.0,
        }
    }

    /// The point the boundary's translation carries: its pivot when it turns, else its
    /// reference point ([`Boundary::point`]).
    #[inline]
    pub fn anchor(&self) -> Vec2 {
        match &self.turn {
            Some(t) => t.pivot,
            None => self.point(),
        }
    }

    /// The pivot its moments are taken about ([`WallLoad::torque`]): a turning boundary's, or
    /// its reference point.
    #[inline]
    pub fn pivot(&self) -> Vec2 {
        self.anchor()
    }

    /// The angular velocity of the current step's drift (rad/s; 0 for a boundary that does not
    /// turn).
    #[inline]
    pub fn omega(&self) -> f64 {
        self.turn.map_or(0.0, |t| t.omega)
    }

    /// The angle the boundary has turned from the case's pose (rad).
    #[inline]
    pub fn angle(&self) -> f64 {
        self.turn.map_or(0.0, |t| t.angle)
    }

    /// The lever of a contact at `x` with normal `n` (from the boundary to the body) about the
    /// pivot: `x − P`, but for a drum `−R n`, the point of its circle on the normal's line
    /// (where a disk's or an ellipse's contact lies; a rectangle's force acts at its overlap's
    /// centroid, off that line, and a turning circle moves nothing along its own normals: taken
    /// at `x`, its normal force would do work that no spring stores).
    #[inline(always)]
    pub fn lever(&self, x: Vec2, n: Vec2) -> Vec2 {
        match (&self.kind, &self.turn) {
            (BoundaryKind::Drum(d, _), _) => -n * d.radius,
            (_, Some(t)) => x - t.pivot,
            (_, None) => x - self.point(),
        }
    }

    /// The velocity of the boundary's material point at the contact at `x` with normal `n`:
    /// `v + ω ẑ × lever` ([`Boundary::lever`]).
    #[inline(always)]
    pub fn velocity_at(&self, x: Vec2, n: Vec2) -> Vec2 {
        match &self.turn {
            None => self.velocity,
            Some(t) => {
                let r = self.lever(x, n);
                self.velocity + Vec2::new(-r.y, r.x) * t.omega
            }
        }
    }

    /// The drum, if the boundary is one.
    #[inline]
    pub fn drum(&self) -> Option<&Drum> {
        match &self.kind {
            BoundaryKind::Drum(d, _) => Some(d),
            BoundaryKind::Wall(_) | BoundaryKind::Segment(_) => None,
        }
    }

    /// True for a half-plane wall (not a segment, not a drum).
    #[inline]
    pub fn is_half_plane(&self) -> bool {
        matches!(self.kind, BoundaryKind::Wall(_))
    }

    /// Places the boundary with its reference point ([`Boundary::point`]: a segment's first
    /// end, a drum's centre) at `p`, turned by `angle` (a turning one; what `walls.csv` records).
    pub fn place_by_point(&mut self, p: Vec2, angle: f64) {
        match self.turn {
            None => self.move_to(p),
            Some(t) => {
                let at = t.reference.turned(t.origin, angle, Vec2::zeros());
                let point = match &at {
                    BoundaryKind::Wall(w) => w.point,
                    BoundaryKind::Segment(s) => s.a,
                    BoundaryKind::Drum(d, _) => d.center,
                };
                self.place(t.origin + (p - point), angle);
            }
        }
    }

    /// Places the boundary with its anchor at `p` and (a turning one) turned by `angle`.
    #[inline]
    pub fn place(&mut self, p: Vec2, angle: f64) {
        match &mut self.turn {
            None => self.move_to(p),
            Some(t) => {
                t.pivot = p;
                t.angle = angle;
                self.kind = t.reference.turned(t.origin, angle, p - t.origin);
            }
        }
    }

    /// The boundary's line: a wall's own (its point moves with the boundary, its normal points
    /// into the free side), a segment's front line (through its first end, normal to the left
    /// going from its first end to its second). Servo spans, loads along the normal and
    /// drawings read it.
    #[inline]
    pub fn line(&self) -> &Wall {
        match &self.kind {
            BoundaryKind::Wall(w) => w,
            BoundaryKind::Segment(s) => &s.front,
            BoundaryKind::Drum(_, l) => l,
        }
    }

    /// The segment, if the boundary is one.
    #[inline]
    pub fn segment(&self) -> Option<&Segment> {
        match &self.kind {
            BoundaryKind::Wall(_) | BoundaryKind::Drum(..) => None,
            BoundaryKind::Segment(s) => Some(s),
        }
    }

    /// The boundary's reference point now.
    #[inline]
    pub fn point(&self) -> Vec2 {
        self.line().point
    }

    /// The boundary as one side of a narrow-phase pair.
    #[inline(always)]
    pub fn side(&self) -> Side<'_> {
        match &self.kind {
            BoundaryKind::Wall(w) => Side::Wall(w),
            BoundaryKind::Segment(s) => Side::Segment(s),
            BoundaryKind::Drum(d, _) => Side::Drum(d),
        }
    }

    /// The signed distance of the point `x` from the boundary, positive on its free side (a
    /// segment: its distance, both sides being free): a body whose bounding circle of radius r
    /// about x has `signed_distance(x) > r` cannot touch it.
    #[inline]
    pub fn signed_distance(&self, x: Vec2) -> f64 {
        match &self.kind {
            BoundaryKind::Wall(w) => w.signed_distance(x),
            BoundaryKind::Segment(s) => s.distance(x),
            BoundaryKind::Drum(d, _) => d.signed_distance(x),
        }
    }

    /// Whether a body whose bounding circle about `x` has radius `reach` (its bounding radius
    /// plus a margin) can touch the boundary: within `reach` of a wall's line; inside a
    /// segment's bounding box grown by `reach` (the broad phase's test, four comparisons) and
    /// within `reach` of the segment. Returns the (signed) distance when it can.
    ///
    /// A turning segment: within `reach` of the disk its ends sweep about the pivot (the
    /// distance returned that disk's, a lower bound of the segment's at every angle); a turning
    /// half-plane: every body (−∞).
    #[inline]
    pub fn near(&self, x: Vec2, reach: f64) -> Option<f64> {
        if let Some(t) = &self.turn {
            match &self.kind {
                BoundaryKind::Drum(..) => {}
                BoundaryKind::Wall(_) => return Some(f64::NEG_INFINITY),
                BoundaryKind::Segment(s) => {
                    let swept = (s.a - t.pivot).norm().max((s.b - t.pivot).norm());
                    return Some((x - t.pivot).norm() - swept).filter(|&d| d <= reach);
                }
            }
        }
        self.near_now(x, reach)
    }

    /// [`Boundary::near`] for the boundary where it is now.
    #[inline]
    fn near_now(&self, x: Vec2, reach: f64) -> Option<f64> {
        match &self.kind {
            BoundaryKind::Wall(w) => Some(w.signed_distance(x)).filter(|&d| d <= reach),
            BoundaryKind::Segment(s) => {
                if !s.box_holds(x, reach) {
                    return None;
                }
                Some(s.distance(x)).filter(|&d| d <= reach)
            }
            BoundaryKind::Drum(d, _) => Some(d.signed_distance(x)).filter(|&h| h <= reach),
        }
    }

    /// How far the boundary has moved towards bodies since its anchor ([`Boundary::anchor`])
    /// was `at`: a wall's displacement along its normal, a segment's whole displacement (its
    /// ends move along its line too), a drum's centre's; a turning half-plane or segment, its
    /// pivot's (its rotation moves nothing out of [`Boundary::near`]'s reach, which holds every
    /// angle).
    #[inline]
    pub fn displacement_since(&self, at: Vec2) -> f64 {
        match (&self.kind, &self.turn) {
            (BoundaryKind::Drum(d, _), _) => (d.center - at).norm(),
            (BoundaryKind::Wall(w), None) => (w.point - at).dot(&w.normal).abs(),
            (BoundaryKind::Segment(s), None) => (s.a - at).norm(),
            (BoundaryKind::Wall(_) | BoundaryKind::Segment(_), Some(t)) => (t.pivot - at).norm(),
        }
    }

    /// Moves the boundary so that its reference point is `p`.
    #[inline]
    pub fn move_to(&mut self, p: Vec2) {
        match &mut self.kind {
            BoundaryKind::Wall(w) => w.point = p,
            BoundaryKind::Segment(s) => s.move_to(p),
            BoundaryKind::Drum(d, l) => {
                d.center = p;
                l.point = p;
            }
        }
    }

    /// Moves the boundary over the drift of step `step` (from step `step − 1`, at `step − 1`
    /// times `dt`, to `time` = `step` times `dt`).
    #[inline]
    pub fn drift(&mut self, step: u64, time: f64, dt: f64) {
        match &self.motion {
            Motion::Fixed => {}
            // (t − 0 is t: the uninterrupted run's bits.)
            Motion::Velocity(v) => {
                let since = time - self.start_time;
                let p = self.start + *v * since;
                match self.turn {
                    None => self.move_to(p),
                    Some(t) => self.place(p, t.start_angle + t.rate * since),
                }
            }
            Motion::Servo(_) => self.move_to(self.point() + self.velocity * dt),
            Motion::Program(p) => {
                let n = step - 1;
                let s = p.stage_at(n, dt);
                let motion = p.motion(s);
                let omega = p.angular_velocity(s);
                if s != self.stage {
                    // A new stage, anchored where the wall is as it begins.
                    self.stage = s;
                    self.start = self.anchor();
                    self.start_time = n as f64 * dt;
                    if let Some(t) = &mut self.turn {
                        t.start_angle = t.angle;
                    }
                }
                match motion {
                    StageMotion::Velocity(v) => {
                        self.velocity = v;
                        let since = time - self.start_time;
                        let p = self.start + v * since;
                        match &mut self.turn {
                            None => self.move_to(p),
                            Some(t) => {
                                t.omega = omega;
                                let angle = t.start_angle + omega * since;
                                self.place(p, angle);
                            }
                        }
                    }
                    StageMotion::Servo(_) => self.move_to(self.point() + self.velocity * dt),
                }
            }
        }
    }

    /// The servo that moves the wall over the step from step `n` (its own, or its program's
    /// stage's), if any.
    pub fn servo_at(&self, n: u64, dt: f64) -> Option<Servo> {
        match &self.motion {
            Motion::Servo(s) => Some(*s),
            Motion::Program(p) => match p.motion(p.stage_at(n, dt)) {
                StageMotion::Servo(s) => Some(s),
                StageMotion::Velocity(_) => None,
            },
            Motion::Fixed | Motion::Velocity(_) => None,
        }
    }

    /// The servo of the wall's current stage (its own, or its program's stage of the last
    /// drift), if any.
    pub fn servo(&self) -> Option<Servo> {
        match &self.motion {
            Motion::Servo(s) => Some(*s),
            Motion::Program(p) => match p.motion(self.stage) {
                StageMotion::Servo(s) => Some(s),
                StageMotion::Velocity(_) => None,
            },
            Motion::Fixed | Motion::Velocity(_) => None,
        }
    }

    /// The same boundary of material `m` (whose law is `spec`).
    pub fn of_material(mut self, m: u16, spec: ContactSpec) -> Self {
        self.material = Some(m);
        self.spec = spec;
        self
    }

    /// True unless the boundary is fixed.
    #[inline]
    pub fn moves(&self) -> bool {
        !matches!(self.motion, Motion::Fixed)
    }
}

impl Turn {
    /// The turn of `kind` about `pivot` at the rate `rate`, at angle 0.
    pub fn new(kind: BoundaryKind, pivot: Vec2, rate: f64) -> Self {
        Turn {
            reference: kind,
            origin: pivot,
            pivot,
            angle: 0.0,
            start_angle: 0.0,
            rate,
            omega: rate,
        }
    }
}

impl Boundary {
    /// The normal stress its contacts carry over its loaded span (servo walls), with the
    /// span; `walls` the scene's boundaries (for a span between two of them).
    pub fn measured_stress(&self, walls: &[Boundary]) -> Option<(f64, f64)> {
        let s = self.servo()?;
        let span = span_length(self.line(), &s.span, walls);
        Some((self.load.force.dot(&self.line().normal) / span, span))
    }
}

/// Sets the velocity for the step after step `step` of each wall a servo moves then (a servo
/// wall, or a program in a servo stage) from the load of the last force evaluation.
pub(crate) fn update_servos(walls: &mut [Boundary], step: u64, dt: f64) {
    for k in 0..walls.len() {
        if let Some(s) = walls[k].servo_at(step, dt) {
            walls[k].velocity = servo_velocity(&walls[k], &s, walls, dt);
        }
    }
}

/// Drifts the moving boundaries over step `step` (to `time`; see [`Boundary::drift`]); returns
/// the largest normal displacement of one since the neighbour list was built (`built_at`, each
/// boundary's point then), which counts like a body's towards the list's rebuild.
pub(crate) fn drift_walls(
    walls: &mut [Boundary],
    built_at: &[Vec2],
    step: u64,
    time: f64,
    dt: f64,
) -> f64 {
    let mut disp = 0.0f64;
    for (k, ws) in walls.iter_mut().enumerate() {
        if ws.moves() {
            ws.drift(step, time, dt);
            if let Some(at) = built_at.get(k) {
                disp = disp.max(ws.displacement_since(*at));
            }
        }
    }
    disp
}

/// The loaded span of a wall (see the module documentation).
pub fn span_length(wall: &Wall, span: &Span, walls: &[Boundary]) -> f64 {
    match *span {
        Span::Length(l) => l,
        Span::Between(a, b) => {
            let t = Vec2::new(-wall.normal.y, wall.normal.x);
            let along = |o: &Wall| o.normal.dot(&(o.point - wall.point)) / o.normal.dot(&t);
            (along(walls[a].line()) - along(walls[b].line())).abs()
        }
    }
}

/// The servo's velocity for the next step, from the load of the last force evaluation
/// (see the module documentation); `dt` the step.
pub fn servo_velocity(wall: &Boundary, servo: &Servo, walls: &[Boundary], dt: f64) -> Vec2 {
    let span = span_length(wall.line(), &servo.span, walls);
    let load = &wall.load;
    let elastic = (load.force - load.force_non_elastic).dot(&wall.line().normal) / span;
    let error = servo.stress - elastic;
    let speed = match servo.gain {
        Some(g) => g * error,
        None if load.stiffness > 0.0 => SERVO_RELAXATION * span / (load.stiffness * dt) * error,
        None => servo.max_speed.copysign(error),
    };
    wall.line().normal * speed.clamp(-servo.max_speed, servo.max_speed)
}

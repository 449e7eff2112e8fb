//! Bodies that come and go: insertion regions that pour bodies into the scene, and outflow
//! regions that take them out (LIGGGHTS' `fix insert/rate/region` and deletion regions,
//! MercuryDPM's insertion and deletion boundaries).
//!
//! # When
//! A run applies the flow between steps ([`crate::dynamics::World::apply_flow`]: at its start
//! and after every step), never inside one: the step is the same code with or without a flow.
//! At each application the outflow regions act first, then the insertion regions.
//!
//! # Outflow
//! Every free body (not prescribed) whose centroid lies in an outflow region is removed; each
//! removal is logged ([`Discharge`]: step, time, the body's identity, its mass) for
//! `discharge.csv`. The remaining bodies keep their order and their identities
//! ([`super::body::Bodies::id`]); their contacts keep their history.
//!
//! # Insertion
//! An inserter has a target, the number of bodies it should have inserted by time `t`:
//! - `rate` r (bodies/s) from `start`: `⌊r (t − start)⌋`, capped by `count` when given;
//! - `count` N alone: N at `start` (all at once, as fast as they can be placed);
//! - `keep` K: as many as make the scene's free bodies K (re-inserting what the outflow took:
//!   steady discharge), capped by `count` when given.
//!
//! While it is behind its target it draws a body (equal-area radius from `size`, aspect ratio
//! from `aspect`, orientation uniform in [0, 2π) unless given) and up to `attempts` positions
//! uniformly in its region (the body's bounding circle inside the region), and places the body
//! at the first position where its bounding circle is clear of every body's bounding circle
//! and of every wall (a conservative test: it never places a body in contact). A body that
//! finds no place is not inserted; the inserter tries again `retry` seconds later. So the
//! inserted count equals the target unless the region is full.
//!
//! Everything is drawn from the inserter's own generator (SplitMix64 from its `seed`), in a
//! fixed order: size, aspect, angle, then positions. Insertion happens between steps on one
//! thread, so a run with a flow gives the same bits on any number of threads; a restart saves
//! each generator's state, its count and when it tries next, so a continued run inserts exactly
//! the bodies the uninterrupted one does.
//!
//! # Energy
//! An inserted body brings its kinetic and potential energy into the scene, a removed one takes
//! its own out: both are booked in [`super::account::Energies::boundary_work`], the work of the
//! scene's boundaries, so that `E − E₀ − W` stays the energy the integration created. The
//! contact springs' energy of a removed body's contacts is the exception: its history springs'
//! energy counts as dissipated (as when a contact opens), its normal spring's leaves the
//! account unbooked — outflow regions belong where bodies fall freely.

use crate::geometry::{Shape, Vec2};

/// An axis-aligned rectangle `[x0, x1] × [y0, y1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    pub x0: f64,
    pub x1: f64,
    pub y0: f64,
    pub y1: f64,
}

impl Region {
    /// Whether `p` lies in the region (its boundary included).
    #[inline]
    pub fn contains(&self, p: Vec2) -> bool {
        p.x >= self.x0 && p.x <= self.x1 && p.y >= self.y0 && p.y <= self.y1
    }

    /// Whether `other` lies wholly in this region.
    pub fn covers(&self, other: &Region) -> bool {
        other.x0 >= self.x0 && other.x1 <= self.x1 && other.y0 >= self.y0 && other.y1 <= self.y1
    }

    pub fn width(&self) -> f64 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> f64 {
        self.y1 - self.y0
    }
}

/// A distribution a quantity is drawn from.
#[derive(Clone, Debug, PartialEq)]
pub enum Distribution {
    /// Always this value.
    Fixed(f64),
    /// Uniform in `[lo, hi]`.
    Uniform(f64, f64),
    /// One of `values`, value k with probability `weights[k] / Σ weights`.
    Choice { values: Vec<f64>, weights: Vec<f64> },
}

impl Distribution {
    /// A value (one draw from `rng` whatever the kind, so that the draws that follow do not
    /// depend on it).
    pub fn draw(&self, rng: &mut SplitMix64) -> f64 {
        let u = rng.uniform();
        match self {
            Distribution::Fixed(v) => *v,
            Distribution::Uniform(lo, hi) => lo + (hi - lo) * u,
            Distribution::Choice { values, weights } => {
                let total: f64 = weights.iter().sum();
                let mut at = u * total;
                for (v, w) in values.iter().zip(weights) {
                    if at < *w {
                        return *v;
                    }
                    at -= w;
                }
                *values.last().expect("a choice has values")
            }
        }
    }

    /// The smallest and largest value it can give.
    pub fn range(&self) -> (f64, f64) {
        match self {
            Distribution::Fixed(v) => (*v, *v),
            Distribution::Uniform(lo, hi) => (*lo, *hi),
            Distribution::Choice { values, .. } => values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                }),
        }
    }
}

/// The shapes an inserter makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InsertShape {
    Circle,
    Ellipse,
    Rectangle,
}

impl InsertShape {
    /// The shape of equal-area radius `r` and aspect ratio `alpha` (long over short side; a
    /// circle's is 1): an ellipse `a = r√α, b = r/√α`, a rectangle `w = r√(πα), h = r√(π/α)`.
    pub fn make(self, r: f64, alpha: f64) -> Shape {
        match self {
            InsertShape::Circle => Shape::Circle { r },
            InsertShape::Ellipse => Shape::Ellipse {
                a: r * alpha.sqrt(),
                b: r / alpha.sqrt(),
            },
            InsertShape::Rectangle => {
                let pi = std::f64::consts::PI;
                Shape::Rectangle {
                    w: r * (pi * alpha).sqrt(),
                    h: r * (pi / alpha).sqrt(),
                }
            }
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            InsertShape::Circle => "circle",
            InsertShape::Ellipse => "ellipse",
            InsertShape::Rectangle => "rectangle",
        }
    }
}

/// How many bodies an inserter aims at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// `⌊rate (t − start)⌋`, capped by the count.
    Rate { rate: f64, count: Option<u64> },
    /// The count at once.
    Count(u64),
    /// As many as make the scene's free bodies `keep`, capped by the count.
    Keep { keep: u64, count: Option<u64> },
}

/// An insertion region and what it pours (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Inserter {
    pub region: Region,
    pub target: Target,
    /// Time from which it inserts.
    pub start: f64,
    pub shape: InsertShape,
    /// Equal-area radius (cm).
    pub size: Distribution,
    /// Aspect ratio (≥ 1; ignored for circles, which still draw it).
    pub aspect: Distribution,
    /// Orientation (rad); `None`: uniform in [0, 2π).
    pub angle: Option<f64>,
    pub velocity: Vec2,
    pub omega: f64,
    pub density: f64,
    pub material: u16,
    /// Positions tried per body.
    pub attempts: u32,
    /// Wait (s) after a body found no place.
    pub retry: f64,
    pub seed: u64,
}

impl Inserter {
    /// The largest bounding radius of the bodies it can make.
    pub fn largest_bound(&self) -> f64 {
        let (_, r) = self.size.range();
        let (a0, a1) = self.aspect.range();
        [a0, a1]
            .iter()
            .map(|&a| self.shape.make(r, a).bounding_radius())
            .fold(0.0, f64::max)
    }

    /// The smallest bounding radius of the bodies it can make.
    pub fn smallest_bound(&self) -> f64 {
        let (r, _) = self.size.range();
        let (a0, a1) = self.aspect.range();
        // The bounding radius grows with the aspect ratio at a given area.
        let a = a0.min(a1).max(1.0);
        self.shape.make(r, a).bounding_radius()
    }
}

/// Where an inserter is: its generator, how many it inserted, and the time before which it
/// does not try again (after a body found no place).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InserterState {
    pub rng: u64,
    pub inserted: u64,
    pub next_try: f64,
}

/// A removed body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Discharge {
    pub step: u64,
    pub time: f64,
    /// Its identity ([`super::body::Bodies::id`]).
    pub id: u64,
    pub mass: f64,
}

/// An inserted body: what its inserter drew, so that a reader can make its shape again
/// ([`InsertShape::make`] of the inserter's shape with `r` and `aspect`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Insertion {
    pub step: u64,
    pub time: f64,
    /// Its identity ([`super::body::Bodies::id`]).
    pub id: u64,
    /// Its inserter (an index into the case's `insert`).
    pub inserter: usize,
    /// The equal-area radius and aspect ratio drawn.
    pub r: f64,
    pub aspect: f64,
}

/// A scene's insertion and outflow regions and where they are.
#[derive(Clone, Debug, PartialEq)]
pub struct Flow {
    pub inserters: Vec<Inserter>,
    pub outflows: Vec<Region>,
    pub state: Vec<InserterState>,
    /// The step of the last application (a run continued from a state written after it
    /// applies nothing again at that step).
    pub applied_step: Option<u64>,
    /// Bodies removed so far, and their mass.
    pub discharged: u64,
    pub discharged_mass: f64,
    /// The removals of the last application ([`World::apply_flow`] at step
    /// [`Flow::applied_step`]; emptied by the next): what a reader takes after each step.
    pub log: Vec<Discharge>,
    /// The insertions of the last application, likewise.
    pub inserted_log: Vec<Insertion>,
}

impl Flow {
    /// A flow at its start.
    pub fn new(inserters: Vec<Inserter>, outflows: Vec<Region>) -> Self {
        let state = inserters
            .iter()
            .map(|i| InserterState {
                rng: i.seed,
                inserted: 0,
                next_try: f64::NEG_INFINITY,
            })
            .collect();
        Flow {
            inserters,
            outflows,
            state,
            applied_step: None,
            discharged: 0,
            discharged_mass: 0.0,
            log: Vec::new(),
            inserted_log: Vec::new(),
        }
    }

    /// The inserters that placed no body although their target at time `t` asked for some:
    /// (inserter, bodies due). A region behind a wall, or filled by fixed bodies, finds no
    /// place for any body, and a run would otherwise end with exit 0 and none inserted (issue
    /// 41).
    pub fn starved(&self, t: f64) -> Vec<(usize, u64)> {
        self.inserters
            .iter()
            .zip(&self.state)
            .enumerate()
            .filter(|(_, (ins, st))| st.inserted == 0 && t >= ins.start)
            .filter_map(|(k, (ins, _))| {
                let due = match ins.target {
                    Target::Rate { rate, count } => {
                        let n = ((t - ins.start) * rate).floor() as u64;
                        count.map_or(n, |c| n.min(c))
                    }
                    Target::Count(c) => c,
                    Target::Keep { keep, count } => count.map_or(keep, |c| keep.min(c)),
                };
                (due > 0).then_some((k, due))
            })
            .collect()
    }

    /// Where the flow is, for a restart.
    pub fn restart(&self) -> FlowRestart {
        FlowRestart {
            inserters: self.state.clone(),
            applied_step: self.applied_step,
            discharged: self.discharged,
            discharged_mass: self.discharged_mass,
        }
    }

    /// The flow continued from `saved` (its inserters' count must match: checked by the
    /// reader of the state).
    pub fn resumed(mut self, saved: &FlowRestart) -> Self {
        self.state = saved.inserters.clone();
        self.applied_step = saved.applied_step;
        self.discharged = saved.discharged;
        self.discharged_mass = saved.discharged_mass;
        self
    }
}

/// A flow's part of a restart.
#[derive(Clone, Debug, PartialEq)]
pub struct FlowRestart {
    pub inserters: Vec<InserterState>,
    pub applied_step: Option<u64>,
    pub discharged: u64,
    pub discharged_mass: f64,
}

/// SplitMix64 (Steele, Lea and Flood 2014): a 64-bit state, well mixed, trivially saved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) (53 bits).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// A body to insert: shape, pose, and whether its bounding circle at `position` is clear.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Candidate {
    pub shape: Shape,
    pub angle: f64,
    /// The equal-area radius and aspect ratio it was made of.
    pub r: f64,
    pub aspect: f64,
}

/// Draws one body of `ins` (size, aspect, angle: three draws).
pub(crate) fn draw_body(ins: &Inserter, rng: &mut SplitMix64) -> Candidate {
    let r = ins.size.draw(rng);
    let alpha = ins.aspect.draw(rng);
    let u = rng.uniform();
    let angle = ins.angle.unwrap_or(u * std::f64::consts::TAU);
    Candidate {
        shape: ins.shape.make(r, alpha),
        angle,
        r,
        aspect: alpha,
    }
}

/// A position for a body of bounding radius `bound` in `region` (two draws), its bounding
/// circle inside the region.
pub(crate) fn draw_position(region: &Region, bound: f64, rng: &mut SplitMix64) -> Vec2 {
    let (u, v) = (rng.uniform(), rng.uniform());
    Vec2::new(
        region.x0 + bound + (region.width() - 2.0 * bound) * u,
        region.y0 + bound + (region.height() - 2.0 * bound) * v,
    )
}

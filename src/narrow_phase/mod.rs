//! Narrow phase: for a pair of objects, whether they touch and, if so, the contact record of the
//! chord definition. One file and one kernel per pair kind (`contact_<i>_<j>`), one record
//! ([`Contact`]) and one dispatcher, [`contact_with`], through which every caller goes (the
//! dynamics, the `contact` command, the reports, the tests and benchmarks):
//! - it takes the two sides ([`Object`]s or borrowed [`Side`]s), an opaque per-pair cache
//!   ([`PairCache`]: what the pair kind keeps from one query to the next, the conic pairs' warm
//!   start; parry keeps its contact workspace so) and a [`Request`] (whether the overlap area
//!   and the chord are wanted, and whether to report if the warm start gave the result);
//! - one exhaustive match over the pair's kinds picks the kernel and the order it computes the
//!   pair in, and turns the result round when that order is not the one given — the one place
//!   where the normal is flipped and the cache re-expressed.
//!
//! The kinds the kernels know: a wall, a circle, an ellipse (a conic), a convex polygon (a
//! polygon, or a rectangle as its four corners: [`Shape::vertices`]), a clump (its member
//! disks' contacts). The closed forms and the conic pairs (what a scene of disks or ellipses meets at
//! every step) are inlined into the caller; the polygon pairs and the clumps are computed out of
//! line ([`cold`]), so that they do not weigh on the hot pairs' code.
//!
//! [`contact`] is the one-off query (an empty cache, everything computed).
//!
//! # Conventions (for every pair kind)
//! - The unit `normal` points from i towards j. For a wall as i it is the wall's normal; for a
//!   wall as j it is minus the wall's normal.
//! - The chord: the two points where the boundaries cross, `point ± half_chord · t` with `t` the
//!   normal turned a quarter turn counter-clockwise ([`Contact::chord`]); `point` is its
//!   midpoint and `normal` is perpendicular to it.
//! - `depth` `δ = h_i(n) + h_j(−n)` with `h` the support function: the overlap measured along the
//!   normal, positive when penetrating. (`δ = h_i(n) − n·p1 + h_j(−n) + n·p1`: the `n·p1` cancel.)
//!   The sign of `n` is the one with the smaller depth (for bodies: `n·(c_j − c_i) ≥ 0`).
//! - Every pair is computed in a frame centred on a body (never in world coordinates), so the
//!   relative accuracy does not depend on where the pair sits. A wall's distance to a body is
//!   taken at world scale, but compensated ([`Wall::signed_distance`]): exact to rounding of the
//!   distance itself, however far the wall's point lies along the line.
//!
//! # Swap symmetry
//! Swapping i and j gives the same state, depth, point, chord (its ends exchanged) and flat
//! overlap, and the normal negated; for the overlap area ([`OverlapArea`]) the same area,
//! length and point, with the normal and the couple negated ([`Contact::swapped`]). This holds
//! **bit for bit**, by construction: every pair is computed in one order only, and the other
//! order is that result swapped —
//! - a wall and a body: the wall as i;
//! - a circle and an ellipse: the circle as i; a polygon (or rectangle) and a conic: the
//!   polygon as i;
//! - two ellipses, two polygons (rectangles among them): the order of [`computed_first`], a
//!   total order on (kind, sizes, position, orientation) that depends on the pair alone. The
//!   kernels compute in a frame centred on their first body and decide states on quantities
//!   rounded in that frame, so two orders could otherwise differ in the last bits — and at a
//!   decision's threshold in the state (a concentric pair's fallback normal was even i's own x
//!   axis);
//! - two circles: a closed form whose every term is exactly symmetric (`r_i + r_j`,
//!   `c_i + c_j`, `|c_j − c_i|`) or antisymmetric (`c_j − c_i`, `r_i − r_j`), so no order is
//!   chosen ([`circle_circle`]).
//!
//! The one exception is a pair of two *identical* objects (same shape in the same pose; two
//! equal circles with one centre): i and j cannot be told apart, both orders are the same
//! computation, and the normal cannot be both `n` and `−n`. `tests/swap_symmetry.rs` checks all
//! of this over every pair kind, state and place.
//!
//! Overlaps whose boundaries cross four times, or where one body contains the other, have no
//! single chord. They are never dropped: they get a defined fallback geometry and the state
//! [`ContactState::Deep`] or [`ContactState::Contained`], which later stages count and report.

use crate::geometry::{Drum, Pose, Segment, Shape, Vec2, Wall};
use std::cell::Cell;

pub use cache::PairCache;

pub mod cache;
mod circle_circle;
mod circle_wall;
pub mod clump;
pub mod drum;
pub mod ellipse_ellipse;
mod ellipse_wall;
mod polygon_conic;
mod polygon_polygon;
mod polygon_wall;
pub mod segment;
mod small;

/// How two objects relate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ContactState {
    /// No common point.
    Separated,
    /// Boundaries touch at one point (within rounding); depth ≈ 0.
    Touching,
    /// Boundaries cross at two points: the chord definition applies exactly.
    Overlap,
    /// Boundaries cross four (or more) times: fallback geometry, flagged.
    Deep,
    /// One solid lies inside the other (boundaries do not cross): fallback geometry, flagged.
    Contained,
}

impl ContactState {
    /// The name used in the JSON output.
    pub fn as_str(&self) -> &'static str {
        match self {
            ContactState::Separated => "separated",
            ContactState::Touching => "touching",
            ContactState::Overlap => "overlap",
            ContactState::Deep => "deep",
            ContactState::Contained => "contained",
        }
    }

    /// True for the fallback geometries ([`Deep`](Self::Deep), [`Contained`](Self::Contained)).
    pub fn is_deep(&self) -> bool {
        matches!(self, ContactState::Deep | ContactState::Contained)
    }

    /// The state of a query's result: [`Separated`](Self::Separated) for none.
    #[inline]
    pub fn of(c: Option<&Contact>) -> ContactState {
        c.map_or(ContactState::Separated, |c| c.state)
    }
}

/// The one contact record every pair kind produces (world coordinates), for two objects that
/// touch; a query's `None` is "apart".
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Relation of the pair (never [`ContactState::Separated`]).
    pub state: ContactState,
    /// Chord midpoint (contact point).
    pub point: Vec2,
    /// Unit normal from i towards j, perpendicular to the chord.
    pub normal: Vec2,
    /// Overlap along `normal` (positive when penetrating).
    pub depth: f64,
    /// Half the chord's length ([`Contact::chord`]): 0 for touching and for the fallbacks'
    /// degenerate chords, and when the [`Request`] did not ask for the chord (the dynamics
    /// reads none; two circles, say, would pay a square root for it).
    pub half_chord: f64,
    /// The overlap area and its gradient, when asked for (see [`OverlapArea`]); `None`
    /// otherwise, and for touching pairs.
    pub area: Option<OverlapArea>,
    /// The overlap polygon's area and centroid where both sides are flat (a flat-sided body —
    /// `Shape::is_flat_sided`, a rectangle — against a wall or another); `None` otherwise. See
    /// [`FlatOverlap`].
    pub flat: Option<FlatOverlap>,
}

impl Contact {
    /// The chord's two ends, `point ∓ half_chord · t` with `t = (−n_y, n_x)` (the same two
    /// points, exchanged, for the pair seen the other way round).
    #[inline]
    pub fn chord(&self) -> (Vec2, Vec2) {
        let t = Vec2::new(-self.normal.y, self.normal.x) * self.half_chord;
        (self.point - t, self.point + t)
    }

    /// The same contact seen from the other body (i ↔ j): normal flipped (and the area
    /// gradient's normal and couple), all else kept.
    #[inline(always)]
    pub fn swapped(mut self) -> Contact {
        self.turn();
        self
    }

    /// Turns this contact round in place ([`Contact::swapped`]).
    #[inline(always)]
    fn turn(&mut self) {
        self.normal = -self.normal;
        if let Some(a) = &mut self.area {
            // The other body's gradient: the opposite force and the opposite couple.
            a.normal = -a.normal;
            a.couple = -a.couple;
        }
    }
}

/// The overlap area `A` of a pair and how it changes with j's rigid motion: the geometry of the
/// energy-conserving normal force, which derives from a potential `W(A)` (Feng, Han & Owen
/// 2012). Moving j by `du` and turning it by `dθ` about its centroid `c_j` changes the area by
///
/// `dA = −length · n·du − (length · (point − c_j) × n + couple) dθ`,
///
/// so the force `W′(A) · length · n` at `point` plus the couple `W′(A) · couple` on j (their
/// opposites on i) is exactly `−∇W`. For two crossings (divergence theorem over the part of j
/// inside i) `length` is the chord length L, `n` and `point` are the chord's normal and
/// midpoint — P's chord, so only the magnitude differs from a spring on the depth — and the
/// couple is zero. For four or more crossings the gradient is the sum, over the arcs of j's
/// boundary inside i, of each arc's closing chord `L_k n_k` at its midpoint; `point` is then the
/// crossings' mean and `couple` what the sum leaves about it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlapArea {
    /// Area of the overlap.
    pub area: f64,
    /// `|∂A/∂x_j|`: the chord length for two crossings.
    pub length: f64,
    /// Unit vector along `−∂A/∂x_j` (from i towards j).
    pub normal: Vec2,
    /// Where the force acts (world coordinates).
    pub point: Vec2,
    /// The gradient's couple about `point`, see above (zero for two crossings).
    pub couple: f64,
}

/// The overlap of two flat-sided objects (a polygon), for a contact that acts like a Winkler
/// foundation: pressure `k′ × local penetration`, so a resultant `k′ A` at the overlap's
/// centroid (the centre of pressure) along the chord normal, and stored energy `k′ A ȳ` with ȳ
/// the centroid's distance from the chord — the area-based polygon contact of Tillemans &
/// Herrmann. Against a flat line this is exactly the gradient of that energy. With one contact
/// point, a spring on `depth` (the deepest corner's penetration) at the chord midpoint is not
/// the gradient of any potential when a face lies on a face: a rectangle resting on a floor then
/// rocks forever, fed by its own contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatOverlap {
    /// Area of the overlap polygon.
    pub area: f64,
    /// Its centroid (world coordinates).
    pub centroid: Vec2,
}

/// One side of a pair: a placed body, a wall (a half-plane) or a segment wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Object {
    Body {
        shape: Shape,
        pose: Pose,
    },
    Wall(Wall),
    Segment(Segment),
    /// A drum: a circle with the bodies inside it (see [`drum`]).
    Drum(Drum),
}

/// One side of a pair, borrowed: what a caller that keeps its bodies elsewhere (the dynamics)
/// hands the dispatcher, without copying shapes and poses into [`Object`]s.
#[derive(Clone, Copy, Debug)]
pub enum Side<'a> {
    Body(&'a Shape, &'a Pose),
    Wall(&'a Wall),
    Segment(&'a Segment),
    Drum(&'a Drum),
}

impl Object {
    /// True for a clump.
    #[inline]
    pub fn is_clump(&self) -> bool {
        matches!(
            self,
            Object::Body {
                shape: Shape::Clump(_),
                ..
            }
        )
    }
}

impl<'a> From<&'a Object> for Side<'a> {
    #[inline(always)]
    fn from(o: &'a Object) -> Self {
        match o {
            Object::Body { shape, pose } => Side::Body(shape, pose),
            Object::Wall(w) => Side::Wall(w),
            Object::Segment(s) => Side::Segment(s),
            Object::Drum(d) => Side::Drum(d),
        }
    }
}

/// What a query computes besides the contact's state, point, normal and depth (which it always
/// gives), and whether to report how it got them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Request<'a> {
    /// The overlap area and its gradient ([`Contact::area`]).
    pub area: bool,
    /// The chord's half-length ([`Contact::half_chord`]; 0 without it).
    pub chord: bool,
    /// Where to record whether the pair cache's warm start gave the result (rather than the
    /// computation from scratch): for the tests that hold the warm path to the same bars.
    pub trace: Option<&'a Cell<bool>>,
}

impl Request<'static> {
    /// Everything: the chord and the overlap area (one-off queries, the `contact` command).
    pub const FULL: Request<'static> = Request {
        area: true,
        chord: true,
        trace: None,
    };
    /// The chord geometry without the overlap area.
    pub const CHORD: Request<'static> = Request {
        area: false,
        chord: true,
        trace: None,
    };
    /// The state, point, normal and depth alone (what a spring on the depth reads).
    pub const LEAN: Request<'static> = Request {
        area: false,
        chord: false,
        trace: None,
    };
}

/// Contact between two objects from scratch (an empty [`PairCache`]), with everything
/// ([`Request::FULL`]); `None` when they are apart (or both walls). See [`contact_with`].
#[inline]
pub fn contact(i: &Object, j: &Object) -> Option<Contact> {
    contact_with(i, j, &mut PairCache::default(), Request::FULL)
}

/// The narrow-phase dispatcher: the contact between `i` and `j` (normal from i to j; `None`
/// when they are apart, or both walls: two walls are never a pair), computing what `request`
/// asks, starting from what `cache` kept from the last query of this pair and leaving in it
/// what the next query starts from.
///
/// One exhaustive match over the pair's kinds: a wall, a circle, an ellipse, a convex polygon
/// (a polygon, or a rectangle as its four corners: [`Shape::vertices`]), a clump. Every pair
/// kind is computed in one order only, its canonical order (see the module documentation), by
/// the kernel of its file; the other order is that result [`Contact::swapped`] — here, the one
/// place where a pair is turned round. The cache always speaks of the caller's i: it is
/// re-expressed for the kernel when the pair is computed the other way round, and back. Closed
/// forms where they exist (a circle pair never touches the conic machinery); the polygon and
/// clump pairs out of line ([`cold`]).
#[inline(always)]
pub fn contact_with<'a>(
    i: impl Into<Side<'a>>,
    j: impl Into<Side<'a>>,
    cache: &mut PairCache,
    request: Request,
) -> Option<Contact> {
    use Shape::{Circle, Clump, Ellipse, Polygon, Rectangle};
    let (i, j) = (i.into(), j.into());
    let r = &request;
    if let Some(t) = request.trace {
        t.set(false); // (the conic pairs' kernel records whether the warm start gave the result)
    }
    match (i, j) {
        (
            Side::Wall(_) | Side::Segment(_) | Side::Drum(_),
            Side::Wall(_) | Side::Segment(_) | Side::Drum(_),
        ) => None,
        // A drum as i; a clump through its members (circles).
        (Side::Drum(d), Side::Body(sj, pj)) => match sj {
            Circle { r: rj } => drum::contact_drum_circle(d, *rj, pj, r),
            Ellipse { a, b } => cold(|| drum::contact_drum_ellipse(d, *a, *b, pj, r)),
            Rectangle { .. } | Polygon(_) => cold(|| drum::contact_drum_polygon(d, sj, pj, r)),
            Clump(_) => cold(|| clump::contact_clump(i, j, r)),
        },
        (Side::Body(si, pi), Side::Drum(d)) => match si {
            Circle { r: ri } => turned(drum::contact_drum_circle(d, *ri, pi, r)),
            Ellipse { a, b } => turned(cold(|| drum::contact_drum_ellipse(d, *a, *b, pi, r))),
            Rectangle { .. } | Polygon(_) => {
                turned(cold(|| drum::contact_drum_polygon(d, si, pi, r)))
            }
            Clump(_) => cold(|| clump::contact_clump(i, j, r)),
        },
        // A segment as i; a clump through its members (circles).
        (Side::Segment(s), Side::Body(sj, pj)) => match sj {
            Clump(_) => cold(|| clump::contact_clump(i, j, r)),
            _ => cold(|| segment::contact_segment_body(s, sj, pj, r)),
        },
        (Side::Body(si, pi), Side::Segment(s)) => match si {
            Clump(_) => cold(|| clump::contact_clump(i, j, r)),
            _ => turned(cold(|| segment::contact_segment_body(s, si, pi, r))),
        },
        (Side::Wall(w), Side::Body(sj, pj)) => match sj {
            Circle { r: rj } => circle_wall::contact_wall_circle(w, *rj, pj, r),
            Ellipse { a, b } => ellipse_wall::contact_wall_ellipse(w, *a, *b, pj, r),
            Rectangle { .. } | Polygon(_) => {
                cold(|| polygon_wall::contact_wall_polygon(w, sj, pj, r))
            }
            // A clump's contacts are its members' (circles): the deepest, for one record.
            Clump(_) => cold(|| clump::contact_clump(i, j, r)),
        },
        (Side::Body(si, pi), Side::Wall(w)) => match si {
            Circle { r: ri } => turned(circle_wall::contact_wall_circle(w, *ri, pi, r)),
            Ellipse { a, b } => turned(ellipse_wall::contact_wall_ellipse(w, *a, *b, pi, r)),
            Rectangle { .. } | Polygon(_) => {
                turned(cold(|| polygon_wall::contact_wall_polygon(w, si, pi, r)))
            }
            Clump(_) => cold(|| clump::contact_clump(i, j, r)),
        },
        (Side::Body(si, pi), Side::Body(sj, pj)) => match (si, sj) {
            (Circle { r: ri }, Circle { r: rj }) => {
                circle_circle::contact_circle_circle(*ri, pi, *rj, pj, r)
            }
            (Circle { r: ri }, Ellipse { a, b }) => {
                conic(cache, (*ri, *ri, pi), (*a, *b, pj), true, r)
            }
            (Ellipse { a, b }, Circle { r: rj }) => {
                conic(cache, (*a, *b, pi), (*rj, *rj, pj), false, r)
            }
            (Ellipse { a: ai, b: bi }, Ellipse { a: aj, b: bj }) => {
                // [`computed_first`], whose first keys are the kind and `a`: two ellipses of
                // different `a` (most pairs of a polydisperse scene) are decided by `a` alone,
                // here where it inlines.
                let first = match ai.total_cmp(aj) {
                    std::cmp::Ordering::Less => true,
                    std::cmp::Ordering::Greater => false,
                    std::cmp::Ordering::Equal => computed_first(si, pi, sj, pj),
                };
                conic(cache, (*ai, *bi, pi), (*aj, *bj, pj), first, r)
            }
            (Rectangle { .. } | Polygon(_), Circle { r: rj }) => {
                cold(|| polygon_conic::contact_polygon_conic(si, pi, *rj, *rj, pj, r))
            }
            (Rectangle { .. } | Polygon(_), Ellipse { a, b }) => {
                cold(|| polygon_conic::contact_polygon_conic(si, pi, *a, *b, pj, r))
            }
            (Circle { r: ri }, Rectangle { .. } | Polygon(_)) => turned(cold(|| {
                polygon_conic::contact_polygon_conic(sj, pj, *ri, *ri, pi, r)
            })),
            (Ellipse { a, b }, Rectangle { .. } | Polygon(_)) => turned(cold(|| {
                polygon_conic::contact_polygon_conic(sj, pj, *a, *b, pi, r)
            })),
            (Rectangle { .. } | Polygon(_), Rectangle { .. } | Polygon(_)) => cold(|| {
                if computed_first(si, pi, sj, pj) {
                    polygon_polygon::contact_polygon_polygon(si, pi, sj, pj, r)
                } else {
                    turned(polygon_polygon::contact_polygon_polygon(sj, pj, si, pi, r))
                }
            }),
            (Clump(_), _) | (_, Clump(_)) => cold(|| clump::contact_clump(i, j, r)),
        },
    }
}

/// A pair computed the other way round, turned back ([`Contact::swapped`]).
#[inline(always)]
fn turned(mut c: Option<Contact>) -> Option<Contact> {
    if let Some(c) = &mut c {
        c.turn();
    }
    c
}

/// The dispatcher's out-of-line half: each pair kind that takes it gets its own copy of this
/// function (its kernel inlined into it), called from the dispatcher — so that the kernels of
/// the polygon and clump pairs, which a scene of disks or ellipses never meets, take no room
/// in the copies of the dispatcher inlined into the dynamics' per-slot code.
#[cold]
#[inline(never)]
fn cold(kernel: impl FnOnce() -> Option<Contact>) -> Option<Contact> {
    kernel()
}

/// A conic pair (circle–ellipse, ellipse–ellipse; a circle is the conic `a = b = r`) `(a_i,
/// b_i, pose_i)`, `(a_j, b_j, pose_j)`, computed in the given order when `in_order`, else as
/// `(j, i)` and turned round; the warm start read from and left in `cache` (relative to the
/// caller's i).
#[inline(always)]
fn conic(
    cache: &mut PairCache,
    (ai, bi, pi): (f64, f64, &Pose),
    (aj, bj, pj): (f64, f64, &Pose),
    in_order: bool,
    request: &Request,
) -> Option<Contact> {
    let guess = cache.warm();
    let mut next = None;
    let c = if in_order {
        ellipse_ellipse::conic_pair(ai, bi, pi, aj, bj, pj, guess, &mut next, request)
    } else {
        let back = guess.map(|w| w.seen_from(pi, pj));
        let mut c = ellipse_ellipse::conic_pair(aj, bj, pj, ai, bi, pi, back, &mut next, request);
        next = next.map(|w| w.seen_from(pj, pi));
        if let Some(c) = &mut c {
            c.turn();
        }
        c
    };
    cache.set_warm(next);
    c
}

/// Whether a pair of two bodies is computed in the order given (i first), rather than as
/// (j, i) and swapped, where the pair kind does not decide it (two ellipses, two polygons — a
/// rectangle among them): the canonical order, by the kind (a polygon before a rectangle),
/// the sizes (`a` then `b`, or `w` then `h`; a polygon's area then bounding radius), then the
/// position (x then y), then the orientation (cos then sin), then (two polygons only) the
/// vertex lists, i before j when its key is not greater. Every kernel computes in a frame
/// centred on its first body and decides on quantities rounded in that frame, so only one order
/// per pair makes the swap exact, in the state as in the last bit. The order depends on the
/// pair alone (never on how it was called); two bodies with equal keys are the same object in
/// the same place, and either order computes the same thing.
#[inline]
pub fn computed_first(si: &Shape, pi: &Pose, sj: &Shape, pj: &Pose) -> bool {
    let key = |s: &Shape, p: &Pose| {
        let (kind, u, v) = match *s {
            Shape::Circle { r } => (0.0, r, r),
            Shape::Ellipse { a, b } => (1.0, a, b),
            Shape::Polygon(q) => (2.0, q.area, q.bounding_radius),
            Shape::Rectangle { w, h } => (3.0, w, h),
            Shape::Clump(q) => (4.0, q.area, q.bounding_radius),
        };
        let (c, sn) = p.cos_sin();
        [kind, u, v, p.position.x, p.position.y, c, sn]
    };
    let (ki, kj) = (key(si, pi), key(sj, pj));
    for (x, y) in ki.iter().zip(&kj) {
        match x.total_cmp(y) {
            std::cmp::Ordering::Less => return true,
            std::cmp::Ordering::Greater => return false,
            std::cmp::Ordering::Equal => {}
        }
    }
    if let (Shape::Polygon(p), Shape::Polygon(q)) = (si, sj) {
        let flat = |v: &'static [Vec2]| v.iter().flat_map(|x| [x.x, x.y]);
        let (a, b) = (&p.data().vertices, &q.data().vertices);
        for (x, y) in flat(a).zip(flat(b)) {
            match x.total_cmp(&y) {
                std::cmp::Ordering::Less => return true,
                std::cmp::Ordering::Greater => return false,
                std::cmp::Ordering::Equal => {}
            }
        }
        return a.len() <= b.len();
    }
    true
}

/// Relative tolerance (of the pair's size) below which a depth counts as touching.
pub const TOUCH_TOL: f64 = 1e-14;

/// A frame centred on a body: `origin` in world coordinates, local x axis at `(cos, sin)`,
/// lengths divided by `scale` (an exact power of two, so rescaling adds no rounding).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LocalFrame {
    pub origin: Vec2,
    pub cos: f64,
    pub sin: f64,
    pub scale: f64,
}

impl LocalFrame {
    /// The frame of `pose` (its centroid and axes), lengths scaled by `scale`.
    #[inline]
    pub fn of(pose: &Pose, scale: f64) -> LocalFrame {
        let (cos, sin) = pose.cos_sin();
        LocalFrame {
            origin: pose.position,
            cos,
            sin,
            scale,
        }
    }

    #[inline]
    pub fn vector(&self, v: [f64; 2]) -> Vec2 {
        Vec2::new(
            self.cos * v[0] - self.sin * v[1],
            self.sin * v[0] + self.cos * v[1],
        )
    }

    #[inline]
    pub fn point(&self, p: [f64; 2]) -> Vec2 {
        self.origin + self.vector(p) * self.scale
    }

    /// A contact record in state `state` from local quantities (lengths in units of `scale`):
    /// the chord `p1 p2` (its half-length when `request` asks for the chord), the contact point
    /// `mid`, the unit normal `n` and the depth.
    #[allow(clippy::too_many_arguments)] // the record's local quantities and the request
    #[inline(always)]
    pub fn contact(
        &self,
        state: ContactState,
        p1: [f64; 2],
        p2: [f64; 2],
        mid: [f64; 2],
        n: [f64; 2],
        depth: f64,
        request: &Request,
    ) -> Contact {
        let half_chord = if request.chord {
            0.5 * (p2[0] - p1[0]).hypot(p2[1] - p1[1]) * self.scale
        } else {
            0.0
        };
        Contact {
            state,
            point: self.point(mid),
            normal: self.vector(n),
            depth: depth * self.scale,
            half_chord,
            area: None,
            flat: None,
        }
    }

    /// The record of a containment ([`ContactState::Contained`]): the chord collapsed onto the
    /// point `inner` (local), the unit normal `n` and the depth.
    #[inline]
    pub fn contained(
        &self,
        inner: [f64; 2],
        n: [f64; 2],
        depth: f64,
        request: &Request,
    ) -> Contact {
        self.contact(
            ContactState::Contained,
            inner,
            inner,
            inner,
            n,
            depth,
            request,
        )
    }

    /// An [`OverlapArea`] from local quantities (lengths in units of `scale`): `grad` is
    /// `∂A/∂x_j`, the others as in [`LocalOverlap`].
    #[inline(always)]
    pub fn overlap(&self, o: &LocalOverlap) -> OverlapArea {
        let s2 = self.scale * self.scale;
        let (length, normal) = match o.chord {
            // Two crossings: the chord's own length and normal, already at hand.
            Some((len, n)) => (len, self.vector(n)),
            None => {
                let len = (o.grad[0] * o.grad[0] + o.grad[1] * o.grad[1]).sqrt();
                let n = if len > 0.0 {
                    self.vector([-o.grad[0] / len, -o.grad[1] / len])
                } else {
                    self.vector([1.0, 0.0]) // a pure couple (only at an exactly symmetric crossing)
                };
                (len, n)
            }
        };
        OverlapArea {
            area: o.area * s2,
            length: length * self.scale,
            normal,
            point: self.point(o.point),
            couple: o.couple * s2,
        }
    }
}

/// An [`OverlapArea`] in a pair's local frame: the area, `∂A/∂x_j` (for two crossings
/// `−L n`), the point and the couple.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LocalOverlap {
    pub area: f64,
    pub grad: [f64; 2],
    pub point: [f64; 2],
    pub couple: f64,
    /// For two crossings, the chord's length and unit normal (so that they need not be
    /// recovered from `grad`).
    pub chord: Option<(f64, [f64; 2])>,
}

impl LocalOverlap {
    /// Two crossings: area `cap_i + cap_j`, gradient `−L n` at the chord midpoint.
    #[inline]
    pub fn chord(area: f64, p: [f64; 2], q: [f64; 2], n: [f64; 2]) -> Self {
        let len = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
        Self::chord_of_length(area, p, q, n, len)
    }

    /// [`LocalOverlap::chord`] for a caller that has the chord's length `len` (`|q − p|`).
    #[inline]
    pub fn chord_of_length(area: f64, p: [f64; 2], q: [f64; 2], n: [f64; 2], len: f64) -> Self {
        LocalOverlap {
            area,
            grad: [-len * n[0], -len * n[1]],
            point: midpoint(p, q),
            couple: 0.0,
            chord: Some((len, n)),
        }
    }
}

/// The overlap area and its gradient for four or more crossings (`points`, sorted
/// counter-clockwise about their mean, as [`deep_fallback`] leaves them). The overlap is the
/// convex polygon of the crossings plus, beyond each of its edges, the cap of whichever body's
/// boundary bounds the overlap there — the one that bulges less past the edge, since both
/// boundaries run between the same two crossings and the inner one lies inside the other body.
/// `height(k, u, m)` is `max over body k of u·(x − m)` (k = 0 for i, 1 for j; u unit) and
/// `cap(k, p, q, u)` the area of body k beyond the chord pq towards u. `c_j` is j's centroid.
pub(crate) fn deep_overlap(
    points: &[[f64; 2]],
    c_j: [f64; 2],
    height: impl Fn(usize, [f64; 2], [f64; 2]) -> f64,
    cap: impl Fn(usize, [f64; 2], [f64; 2], [f64; 2]) -> f64,
) -> LocalOverlap {
    let k = points.len();
    let n = k as f64;
    let centre = [
        points.iter().map(|p| p[0]).sum::<f64>() / n,
        points.iter().map(|p| p[1]).sum::<f64>() / n,
    ];
    let mut twice_polygon = 0.0;
    let mut area = 0.0;
    let mut grad = [0.0f64; 2];
    let mut turn = 0.0; // ∂A/∂θ_j about c_j
    for idx in 0..k {
        let (p, q) = (points[idx], points[(idx + 1) % k]);
        let (rp, rq) = (
            [p[0] - centre[0], p[1] - centre[1]],
            [q[0] - centre[0], q[1] - centre[1]],
        );
        twice_polygon += rp[0] * rq[1] - rp[1] * rq[0];
        let e = [q[0] - p[0], q[1] - p[1]];
        let len = (e[0] * e[0] + e[1] * e[1]).sqrt();
        if len == 0.0 {
            continue;
        }
        let u = [e[1] / len, -e[0] / len]; // outward normal of a counter-clockwise polygon
        let m = midpoint(p, q);
        let body = if height(1, u, m) < height(0, u, m) {
            1
        } else {
            0
        };
        area += cap(body, p, q, u);
        if body == 1 {
            // j's boundary: its outward normal integrates to L u over the arc.
            grad[0] += len * u[0];
            grad[1] += len * u[1];
            turn += len * ((m[0] - c_j[0]) * u[1] - (m[1] - c_j[1]) * u[0]);
        }
    }
    // ∂A/∂θ_j = (point − c_j) × grad + (the couple of the gradient, with the sign of dA).
    let lever = (centre[0] - c_j[0]) * grad[1] - (centre[1] - c_j[1]) * grad[0];
    LocalOverlap {
        area: area + 0.5 * twice_polygon.abs(),
        grad,
        point: centre,
        couple: -(turn - lever),
        chord: None,
    }
}

/// The largest power of two not above `x` (1 for zero, subnormal or non-finite `x`).
#[inline]
pub(crate) fn pow2_floor(x: f64) -> f64 {
    let p = f64::from_bits(x.to_bits() & 0x7FF0_0000_0000_0000);
    if p.is_normal() { p } else { 1.0 }
}

/// Orders up to eight points counter-clockwise about their mean (for the fallback chords).
pub(crate) fn sort_ccw(points: &mut [[f64; 2]]) {
    let n = points.len() as f64;
    let cx = points.iter().map(|p| p[0]).sum::<f64>() / n;
    let cy = points.iter().map(|p| p[1]).sum::<f64>() / n;
    points.sort_by(|p, q| {
        let ap = (p[1] - cy).atan2(p[0] - cx);
        let aq = (q[1] - cy).atan2(q[0] - cx);
        ap.total_cmp(&aq)
    });
}

/// Unit normal of the chord `p1 p2`, oriented so that `depth(n)` is the smaller of the two
/// orientations, with that depth. `depth(n)` must be the penetration along `n` (i → j).
#[inline]
pub(crate) fn chord_normal(
    p1: [f64; 2],
    p2: [f64; 2],
    depth: impl Fn([f64; 2]) -> f64,
) -> ([f64; 2], f64) {
    let (dx, dy) = (p2[0] - p1[0], p2[1] - p1[1]);
    let len = (dx * dx + dy * dy).sqrt();
    let n = [-dy / len, dx / len];
    orient(n, depth)
}

/// [`orient`] for two centrally symmetric shapes, whose supports add up to `supports` along
/// both `n` and `−n`: the depth is `supports ∓ n·d` with `n_dot_d = n·(c_j − c_i)`.
#[inline]
pub(crate) fn orient_symmetric(n: [f64; 2], supports: f64, n_dot_d: f64) -> ([f64; 2], f64) {
    if n_dot_d >= 0.0 {
        (n, supports - n_dot_d)
    } else {
        ([-n[0], -n[1]], supports + n_dot_d)
    }
}

/// Of `n` and `−n`, the orientation with the smaller penetration depth, and that depth.
#[inline]
pub(crate) fn orient(n: [f64; 2], depth: impl Fn([f64; 2]) -> f64) -> ([f64; 2], f64) {
    let dp = depth(n);
    let m = [-n[0], -n[1]];
    let dm = depth(m);
    if dm < dp { (m, dm) } else { (n, dp) }
}

/// The fallback for four or more crossings: of the chords joining consecutive crossings (taken
/// counter-clockwise), the one whose normal gives the least penetration, like the minimum
/// translation direction of a separating-axis test. Returns `(p1, p2, n, depth)`.
pub(crate) fn deep_fallback(
    points: &mut [[f64; 2]],
    depth: impl Fn([f64; 2]) -> f64,
) -> ([f64; 2], [f64; 2], [f64; 2], f64) {
    sort_ccw(points);
    let k = points.len();
    let mut best = (points[0], points[1 % k], [1.0, 0.0], f64::INFINITY);
    for idx in 0..k {
        let (p, q) = (points[idx], points[(idx + 1) % k]);
        if p == q {
            continue;
        }
        let (n, dpt) = chord_normal(p, q, &depth);
        if dpt < best.3 {
            best = (p, q, n, dpt);
        }
    }
    best
}

/// Area and centroid of a simple polygon (shoelace formulas); the mean of the vertices when
/// the area vanishes.
pub(crate) fn polygon_area_centroid(poly: &[[f64; 2]]) -> (f64, [f64; 2]) {
    let n = poly.len();
    let mean = || {
        let k = n.max(1) as f64;
        [
            poly.iter().map(|p| p[0]).sum::<f64>() / k,
            poly.iter().map(|p| p[1]).sum::<f64>() / k,
        ]
    };
    if n < 3 {
        return (0.0, mean());
    }
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let (p, q) = (poly[k], poly[(k + 1) % n]);
        let cr = p[0] * q[1] - q[0] * p[1];
        a += cr;
        cx += (p[0] + q[0]) * cr;
        cy += (p[1] + q[1]) * cr;
    }
    if a == 0.0 {
        return (0.0, mean());
    }
    (0.5 * a.abs(), [cx / (3.0 * a), cy / (3.0 * a)])
}

impl LocalFrame {
    /// The flat overlap of a local polygon.
    #[inline]
    pub fn flat(&self, poly: &[[f64; 2]]) -> FlatOverlap {
        let (area, c) = polygon_area_centroid(poly);
        FlatOverlap {
            area: area * self.scale * self.scale,
            centroid: self.point(c),
        }
    }
}

#[inline]
pub(crate) fn midpoint(p: [f64; 2], q: [f64; 2]) -> [f64; 2] {
    [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]
}

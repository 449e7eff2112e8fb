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

use crate::geometry::{Pose, Shape, Vec2};

pub use cache::PairCache;
pub use record::{
    Contact, ContactState, FlatOverlap, Object, OverlapArea, Request, Side, TOUCH_TOL,
};

pub mod cache;
mod circle_circle;
mod circle_wall;
pub mod clump;
pub mod drum;
pub mod ellipse_ellipse;
mod ellipse_wall;
mod local;
mod polygon_conic;
mod polygon_polygon;
mod polygon_wall;
mod record;
pub mod segment;
mod small;

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
            Clump(_) => cold(|| clump::contact_clump(i, j, r, fresh)),
        },
        (Side::Body(si, pi), Side::Drum(d)) => match si {
            Circle { r: ri } => turned(drum::contact_drum_circle(d, *ri, pi, r)),
            Ellipse { a, b } => turned(cold(|| drum::contact_drum_ellipse(d, *a, *b, pi, r))),
            Rectangle { .. } | Polygon(_) => {
                turned(cold(|| drum::contact_drum_polygon(d, si, pi, r)))
            }
            Clump(_) => cold(|| clump::contact_clump(i, j, r, fresh)),
        },
        // A segment as i; a clump through its members (circles).
        (Side::Segment(s), Side::Body(sj, pj)) => match sj {
            Clump(_) => cold(|| clump::contact_clump(i, j, r, fresh)),
            _ => cold(|| segment::contact_segment_body(s, sj, pj, r)),
        },
        (Side::Body(si, pi), Side::Segment(s)) => match si {
            Clump(_) => cold(|| clump::contact_clump(i, j, r, fresh)),
            _ => turned(cold(|| segment::contact_segment_body(s, si, pi, r))),
        },
        (Side::Wall(w), Side::Body(sj, pj)) => match sj {
            Circle { r: rj } => circle_wall::contact_wall_circle(w, *rj, pj, r),
            Ellipse { a, b } => ellipse_wall::contact_wall_ellipse(w, *a, *b, pj, r),
            Rectangle { .. } | Polygon(_) => {
                cold(|| polygon_wall::contact_wall_polygon(w, sj, pj, r))
            }
            // A clump's contacts are its members' (circles): the deepest, for one record.
            Clump(_) => cold(|| clump::contact_clump(i, j, r, fresh)),
        },
        (Side::Body(si, pi), Side::Wall(w)) => match si {
            Circle { r: ri } => turned(circle_wall::contact_wall_circle(w, *ri, pi, r)),
            Ellipse { a, b } => turned(ellipse_wall::contact_wall_ellipse(w, *a, *b, pi, r)),
            Rectangle { .. } | Polygon(_) => {
                turned(cold(|| polygon_wall::contact_wall_polygon(w, si, pi, r)))
            }
            Clump(_) => cold(|| clump::contact_clump(i, j, r, fresh)),
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
            (Clump(_), _) | (_, Clump(_)) => cold(|| clump::contact_clump(i, j, r, fresh)),
        },
    }
}

/// The contact of two sides from an empty cache (a clump's member pairs).
fn fresh(i: Side, j: Side, request: Request) -> Option<Contact> {
    contact_with(i, j, &mut PairCache::default(), request)
}

/// Every member pair's contact of a pair with a clump, `(member of i, member of j, contact)`
/// (member 0 for a side that is not a clump; `None`: that pair is apart), in member order,
/// normal from i to j, each from an empty cache (the `contact` command's `members`).
pub fn member_contacts(i: Side, j: Side, request: Request) -> Vec<(usize, usize, Option<Contact>)> {
    clump::member_contacts(i, j, request, fresh)
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

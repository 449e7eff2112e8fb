//! Clump pairs: a rigid clump's contacts are its member disks' contacts, each computed by the
//! circle's pair kind (circle–circle, circle–ellipse, circle–rectangle, circle–polygon,
//! circle–wall) with the member as a circle at its world centre. A clump pair may thus have
//! several simultaneous contacts; the dynamics keeps one neighbour-list slot per member pair
//! (see `dynamics::contacts`). For a caller that wants one record for the whole pair (the
//! dispatcher, [`super::contact_with`]), [`contact_clump`] gives the deepest member contact;
//! [`member_contacts`] gives them all.

use super::{
    Contact, Request, Side, circle_circle, circle_ellipse, circle_wall, polygon_circle,
    rectangle_conic,
};
use crate::geometry::{Clump, Pose, Shape};

/// Member `k` of a clump in pose `pose`, as a placed circle: its radius and its world pose
/// (centre `x + R c_k`, the clump's angle and frame).
#[inline]
pub fn member(c: &Clump, k: usize, pose: &Pose) -> (Shape, Pose) {
    let (ck, r) = c.member(k);
    (
        Shape::Circle { r },
        Pose::with_frame(
            pose.position + pose.to_world_vector(ck),
            pose.angle(),
            pose.cos_sin(),
        ),
    )
}

/// The member indices of one side: a clump's members, or `[0]` for any other side.
fn members(s: Side) -> usize {
    match s {
        Side::Body(Shape::Clump(c), _) => c.len(),
        Side::Body(..) | Side::Wall(_) => 1,
    }
}

/// One member of a side as a shape and pose (the side itself when it is not a clump).
fn resolve<'a>(s: Side<'a>, k: usize, store: &'a mut (Shape, Pose)) -> Side<'a> {
    match s {
        Side::Body(Shape::Clump(c), pose) => {
            *store = member(c, k, pose);
            Side::Body(&store.0, &store.1)
        }
        Side::Body(..) | Side::Wall(_) => s,
    }
}

/// Every member pair's contact `(member of i, member of j, contact)` (member 0 for a side that
/// is not a clump), in member order, normal from i to j, each from an empty cache.
pub fn member_contacts(i: Side, j: Side, request: Request) -> Vec<(usize, usize, Contact)> {
    let mut out = Vec::new();
    for a in 0..members(i) {
        for b in 0..members(j) {
            let (mut si, mut sj) = (
                (Shape::Circle { r: 1.0 }, Pose::new(Default::default(), 0.0)),
                (Shape::Circle { r: 1.0 }, Pose::new(Default::default(), 0.0)),
            );
            let mi = resolve(i, a, &mut si);
            let mj = resolve(j, b, &mut sj);
            if let Some(c) = Some(contact_member(mi, mj, &request)) {
                out.push((a, b, c));
            }
        }
    }
    out
}

/// The pair's deepest member contact (the first in member order among equals), or the
/// separated result when no member pair touches. Never inlined: it calls the dispatcher that
/// calls it (for the members), and must not weigh on the dispatcher's inlining.
#[inline(never)]
pub fn contact_clump(i: Side, j: Side, request: &Request) -> Contact {
    let mut best = Contact::SEPARATED;
    let mut depth = f64::NEG_INFINITY;
    for (_, _, c) in member_contacts(i, j, *request) {
        if let Some(g) = c.geometry
            && g.depth > depth
        {
            depth = g.depth;
            best = c;
        }
    }
    best
}

/// The contact of a pair one of whose sides is a circle (a clump's member), by the circle's
/// pair kernels in the dispatcher's canonical order and with its swap — the same computation,
/// bit for bit, as [`super::contact_sides`] from an empty cache, without going through it: the
/// step's copy of the dispatcher, with every kernel inlined into it, stays the only one
/// (another copy made the compiler take the ellipse kernel out of line: the 10⁴-ellipse pile
/// 12 % slower).
#[inline(never)]
pub fn contact_member(i: Side, j: Side, request: &Request) -> Contact {
    use Shape::*;
    match (i, j) {
        (Side::Wall(w), Side::Body(Circle { r }, p)) => {
            circle_wall::contact_wall_circle(w, *r, p, request)
        }
        (Side::Body(Circle { r }, p), Side::Wall(w)) => {
            circle_wall::contact_wall_circle(w, *r, p, request).swapped()
        }
        (Side::Body(si, pi), Side::Body(sj, pj)) => match (*si, *sj) {
            (Circle { r: ri }, Circle { r: rj }) => {
                circle_circle::contact_circle_circle(ri, pi, rj, pj, request)
            }
            (Circle { r }, Ellipse { a, b }) => {
                circle_ellipse::contact_circle_ellipse(r, pi, a, b, pj, None, request).0
            }
            (Ellipse { a, b }, Circle { r }) => {
                circle_ellipse::contact_circle_ellipse(r, pj, a, b, pi, None, request)
                    .0
                    .swapped()
            }
            (Rectangle { w, h }, Circle { .. }) => {
                rectangle_conic::contact_rectangle_conic(w, h, pi, sj, pj, request)
            }
            (Circle { .. }, Rectangle { w, h }) => {
                rectangle_conic::contact_rectangle_conic(w, h, pj, si, pi, request).swapped()
            }
            (Polygon(q), Circle { r }) => {
                polygon_circle::contact_polygon_circle(&q, pi, r, pj, request)
            }
            (Circle { r }, Polygon(q)) => {
                polygon_circle::contact_polygon_circle(&q, pj, r, pi, request).swapped()
            }
            _ => unreachable!("a member pair has a circle (a clump's member) on one side"),
        },
        _ => unreachable!("a member pair has a circle (a clump's member) on one side"),
    }
}

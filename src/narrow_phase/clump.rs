//! Clump pairs: a rigid clump's contacts are its member disks' contacts, each computed by the
//! dispatcher with the member as a circle at its world centre (circle–circle, circle–ellipse,
//! circle–polygon, circle–wall). A clump pair may thus have several simultaneous contacts; the
//! dynamics keeps one neighbour-list slot per member pair (see `dynamics::contacts`). For a
//! caller that wants one record for the whole pair (the dispatcher, [`super::contact_with`]),
//! [`contact_clump`] gives the deepest member contact; [`member_contacts`] gives them all.

use super::record::{Contact, Request, Side};

/// The contact of two sides from an empty cache: the dispatcher
/// ([`super::contact_with`], handed down by it), which each member pair goes through.
pub(super) type Pair = for<'a, 'b, 'c> fn(Side<'a>, Side<'b>, Request<'c>) -> Option<Contact>;
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
        Side::Body(..) | Side::Wall(_) | Side::Segment(_) | Side::Drum(_) => 1,
    }
}

/// One member of a side as a shape and pose (the side itself when it is not a clump).
fn resolve<'a>(s: Side<'a>, k: usize, store: &'a mut (Shape, Pose)) -> Side<'a> {
    match s {
        Side::Body(Shape::Clump(c), pose) => {
            *store = member(c, k, pose);
            Side::Body(&store.0, &store.1)
        }
        Side::Body(..) | Side::Wall(_) | Side::Segment(_) | Side::Drum(_) => s,
    }
}

/// Calls `f(member of i, member of j, contact)` for every member pair (member 0 for a side that
/// is not a clump), in member order, normal from i to j, each from an empty cache.
fn each_member_pair(
    i: Side,
    j: Side,
    request: &Request,
    pair: Pair,
    mut f: impl FnMut(usize, usize, Option<Contact>),
) {
    for a in 0..members(i) {
        for b in 0..members(j) {
            let unused = (Shape::Circle { r: 1.0 }, Pose::IDENTITY);
            let (mut si, mut sj) = (unused, unused);
            let mi = resolve(i, a, &mut si);
            let mj = resolve(j, b, &mut sj);
            f(a, b, pair(mi, mj, *request));
        }
    }
}

/// Every member pair's contact `(member of i, member of j, contact)` (member 0 for a side that
/// is not a clump; `None`: that pair is apart), in member order, normal from i to j, each from
/// an empty cache.
pub(super) fn member_contacts(
    i: Side,
    j: Side,
    request: Request,
    pair: Pair,
) -> Vec<(usize, usize, Option<Contact>)> {
    let mut out = Vec::new();
    each_member_pair(i, j, &request, pair, |a, b, c| out.push((a, b, c)));
    out
}

/// The pair's deepest member contact (the first in member order among equals), or `None` when
/// no member pair touches.
pub(super) fn contact_clump(i: Side, j: Side, request: &Request, pair: Pair) -> Option<Contact> {
    let mut best: Option<Contact> = None;
    each_member_pair(i, j, request, pair, |_, _, c| {
        if let Some(c) = c
            && best.is_none_or(|b| c.depth > b.depth)
        {
            best = Some(c);
        }
    });
    best
}

//! Clumps in the neighbour list: a clump's contacts are its member disks' (`geometry::clump`),
//! one slot per member pair (see [`super::contacts`]). This file is where the dynamics turns a
//! clump slot into a pair of placed circles (or a circle and another body, or a wall), and where
//! the neighbour list decides which member pairs get a slot.

use super::body::Bodies;
use super::boundary::Boundary;
use super::contacts::Slot;
use super::partner::{Partner, Sides};
use crate::geometry::{Clump, Pose, Shape};
use crate::narrow_phase::{Contact, PairCache, Request, Side, clump, contact_with};

/// A clump slot's member pair's contact, from the dispatcher on the member (a circle at its
/// world centre) and the other side, from an empty pair cache, computing what `request` asks
/// (nothing but in a cohesive scene, whose pull reads the chord and the area). The
/// contact pass takes it with the spring on its depth: a member is a disk, whose area potential
/// against a wall or a disk *is* that spring; against an ellipse, a rectangle or a polygon the
/// area law would take the lens potential, which clump members do not (a documented
/// limitation).
#[cold]
#[inline(never)]
pub(crate) fn lean_contact(
    b: &Bodies,
    walls: &[Boundary],
    slot: &Slot,
    sides: Sides,
    request: Request,
) -> Option<Contact> {
    let store = placed(b, slot, sides);
    let (i, j) = sides_of(b, walls, sides, &store);
    contact_with(i, j, &mut PairCache::default(), request)
}

/// The member circles of a clump slot's two sides, `[giver, receiver]`, each placed at its
/// world centre (a side that is not a clump: its pose, its image's for a giver seen through a
/// periodic seam).
type Placed = [(Shape, Pose); 2];

/// [`Placed`] for a clump slot.
#[inline(never)]
fn placed(b: &Bodies, slot: &Slot, sides: Sides) -> Placed {
    let (of_i, of_j) = slot.members();
    let unused = || (Shape::Circle { r: 0.0 }, Pose::IDENTITY);
    // A side that is not a clump keeps its own shape (read from the bodies) at this pose.
    let place = |k: usize, m: usize, pose: &Pose| match b.shape[k].clump() {
        Some(c) => clump::member(&c, m, pose),
        None => (Shape::Circle { r: 0.0 }, *pose),
    };
    match sides.giver {
        // The receiver is body i against a wall (its member `of_i`).
        Partner::Wall(_) => [
            unused(),
            place(sides.receiver, of_i, &b.state[sides.receiver].pose),
        ],
        Partner::Body(k) => [
            place(k, of_i, &giver_pose(b, k, sides)),
            place(sides.receiver, of_j, &b.state[sides.receiver].pose),
        ],
    }
}

/// Body `k`'s pose as the giver of `sides`: its own, or its periodic image's.
fn giver_pose(b: &Bodies, k: usize, sides: Sides) -> Pose {
    let mut pose = b.state[k].pose;
    if let Some(image) = sides.image {
        pose.position += image.offset;
    }
    pose
}

/// The sides of a clump slot as the narrow phase takes them (giver as i, receiver as j), each
/// clump replaced by the slot's member from `store` ([`placed`]): a circle at its world centre
/// (a giver that is not a clump: in `store` too when seen through a periodic image).
fn sides_of<'a>(
    b: &'a Bodies,
    walls: &'a [Boundary],
    sides: Sides,
    store: &'a Placed,
) -> (Side<'a>, Side<'a>) {
    let side = |k: usize, s: &'a (Shape, Pose)| {
        if b.shape[k].clump().is_some() {
            Side::Body(&s.0, &s.1)
        } else {
            Side::Body(&b.shape[k], &s.1)
        }
    };
    let i = match sides.giver {
        Partner::Wall(w) => walls[w].side(),
        Partner::Body(k) => side(k, &store[0]),
    };
    (i, side(sides.receiver, &store[1]))
}

/// The member-pair keys of the body pair `(i, j)` when either is a clump (every member pair
/// that can touch before the next build however the bodies turn: see `contacts`), else
/// `(i, j, 0)`.
pub(crate) fn pair_keys(b: &Bodies, i: u32, j: u32, skin: f64, keys: &mut Vec<(u32, u32, u32)>) {
    let (ci, cj) = (b.shape[i as usize].clump(), b.shape[j as usize].clump());
    if ci.is_none() && cj.is_none() {
        keys.push((i, j, 0));
        return;
    }
    let d = (b.state[i as usize].pose.position - b.state[j as usize].pose.position).norm();
    // A side's members: (reach from its centroid) per member; the whole body for a non-clump.
    let reach = |k: u32, c: Option<Clump>| -> Vec<f64> {
        match c {
            Some(c) => (0..c.len())
                .map(|m| {
                    let (cm, rm) = c.member(m);
                    cm.norm() + rm
                })
                .collect(),
            None => vec![b.bound[k as usize]],
        }
    };
    let (ri, rj) = (reach(i, ci), reach(j, cj));
    for (a, &ra) in ri.iter().enumerate() {
        for (bb, &rb) in rj.iter().enumerate() {
            if d <= ra + rb + skin {
                keys.push((i, j, Slot::sub_of(a, bb)));
            }
        }
    }
}

/// The member keys of body `i` against the boundary keyed `wj` at signed distance `d` from its
/// centroid: the members that can reach it however the clump turns.
pub(crate) fn boundary_keys(
    c: &Clump,
    i: u32,
    wj: u32,
    d: f64,
    skin: f64,
    keys: &mut Vec<(u32, u32, u32)>,
) {
    keys.extend((0..c.len()).filter_map(|k| {
        let (ck, rk) = c.member(k);
        (d <= ck.norm() + rk + skin).then(|| (i, wj, Slot::sub_of(k, 0)))
    }));
}

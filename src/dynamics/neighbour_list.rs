//! Upkeep of the neighbour list ([`super::contacts::ContactList`]): built from the broad
//! phase's grid when bodies have moved far enough that a pair outside it could touch, restored
//! from a restart, and what a scene keeps beside its slots.

use super::body::Bodies;
use super::boundary::Boundary;
use super::broad_phase::{Grid, in_body_chunks};
use super::cell::Cell;
use super::contacts::{ContactList, reserve_for};
use super::materials::PairTable;
use super::members;
use super::partner::Partner;
use super::restart::{Kept, RestartState};
use crate::narrow_phase::PairCache;

/// The skin of the neighbour list as a fraction of the largest bounding radius: larger means
/// fewer rebuilds and more candidate pairs to test each step.
pub const SKIN_FRACTION: f64 = 0.1;

/// The builder's scratch: the broad phase's grid and its pair list.
#[derive(Clone, Debug, Default)]
pub(crate) struct Builder {
    grid: Grid,
    /// The grid's body pairs.
    pairs: Vec<(u32, u32)>,
    /// Each chunk of bodies' slot keys (see [`in_body_chunks`]).
    key_parts: Vec<Vec<(u32, u32, u32)>>,
    /// The next build keeps the continuing slots' contact data (a list rebuilt between steps,
    /// whose data are read before the next step computes them: after an insertion).
    pub carry_data: bool,
}

impl Builder {
    /// Heap bytes of the grid, and of the build's scratch.
    pub fn heap_bytes(&self) -> (usize, usize) {
        let parts: usize = self.key_parts.iter().map(|p| p.capacity() * 12).sum();
        (self.grid.heap_bytes(), self.pairs.capacity() * 8 + parts)
    }

    /// Rebuilds `list` from the current positions (body pairs from the grid, then each body's
    /// walls after its body partners: key order), carrying histories over; `clumps`: some body
    /// is a clump (its pairs get a slot per member pair); `cell`: the periodic cell, whose
    /// pairs across its seams are found through their nearest images (with
    /// [`Builder::carry_data`], the continuing slots keep their contact data). Two prescribed
    /// bodies, or
    /// a prescribed body and a wall, get no slot: neither side can move the other (and their m*
    /// is infinite). Returns the history springs' energy of the contacts that dropped out of the
    /// list.
    pub fn rebuild(
        &mut self,
        bodies: &Bodies,
        walls: &[Boundary],
        pairs: &PairTable,
        clumps: bool,
        cell: Option<&Cell>,
        list: &mut ContactList,
    ) -> f64 {
        let n = bodies.len();
        let skin = skin(bodies);
        list.skin = skin;
        match cell {
            Some(cell) => self
                .grid
                .pairs_periodic(bodies, skin, cell, &mut self.pairs),
            None => self.grid.pairs(bodies, skin, &mut self.pairs),
        }
        list.keys.clear();
        let (held, pairs_of) = (!bodies.prescribed.is_empty(), &self.pairs[..]);
        in_body_chunks(n, &mut self.key_parts, &mut list.keys, |range, keys| {
            let mut next = pairs_of.partition_point(|p| (p.0 as usize) < range.start);
            for i in range {
                let held_i = held && bodies.is_prescribed(i);
                while next < pairs_of.len() && pairs_of[next].0 as usize == i {
                    let (a, b) = pairs_of[next];
                    if held_i && bodies.is_prescribed(b as usize) {
                        // (Neither moves.)
                    } else if clumps {
                        members::pair_keys(bodies, a, b, skin, keys);
                    } else {
                        keys.push((a, b, 0));
                    }
                    next += 1;
                }
                let (x, r) = (bodies.state[i].pose.position, bodies.bound[i]);
                let walls = if held_i { &[][..] } else { walls };
                for (w, ws) in walls.iter().enumerate() {
                    let wj = Partner::Wall(w).key();
                    if let Some(d) = ws.near(x, r + skin) {
                        match bodies.shape[i].clump() {
                            None => keys.push((i as u32, wj, 0)),
                            Some(c) => members::boundary_keys(&c, i as u32, wj, d, skin, keys),
                        }
                    }
                }
            }
        });
        let Kept { cached, history } = kept(&bodies.shape, pairs);
        let lost = list.rebuild_from_keys_with(n, cached, history - 1, self.carry_data);
        list.built_at.clear();
        reserve_for(&mut list.built_at, n);
        list.built_at
            .extend(bodies.state.iter().map(|s| s.pose.position));
        list.wall_built_at.clear();
        list.wall_built_at.extend(walls.iter().map(|w| w.anchor()));
        list.lattice_built_at = cell.map(Cell::lattice);
        lost
    }
}

/// The reach of a pair of bodies whose largest bounding radius is `max_bound`: two bounding
/// diameters and the skin. A periodic side must exceed twice it
/// ([`super::cell::Cell::check_size`]).
pub fn pair_reach(max_bound: f64) -> f64 {
    2.0 * max_bound + SKIN_FRACTION * max_bound
}

/// The skin for these bodies ([`SKIN_FRACTION`] of the largest bounding radius).
pub fn skin(bodies: &Bodies) -> f64 {
    let max_bound = bodies.bound.iter().copied().fold(0.0f64, f64::max);
    SKIN_FRACTION * max_bound
}

/// Restores the neighbour list of a restart: its slots with their histories, pair caches and
/// contacts, what it was built from and its number of builds (the state checked by
/// [`RestartState::check`]).
pub(crate) fn restore(
    bodies: &Bodies,
    pairs: &PairTable,
    saved: &RestartState,
    list: &mut ContactList,
) {
    let n = bodies.len();
    let Kept { cached, history } = kept(&bodies.shape, pairs);
    *list = ContactList::default();
    list.skin = skin(bodies);
    list.keys.extend(saved.slots.iter().map(|s| s.slot.key()));
    let stride = history - 1;
    list.rebuild_from_keys(n, cached, stride);
    for (k, s) in saved.slots.iter().enumerate() {
        list.slots[k] = s.slot;
        list.data[k] = s.data;
        if cached {
            list.cache[k] = s.cache;
        }
        list.history[k * stride..(k + 1) * stride].copy_from_slice(&s.more[..stride]);
    }
    list.built_at.extend_from_slice(&saved.built_at);
    list.wall_built_at.extend_from_slice(&saved.wall_built_at);
    list.builds = saved.builds;
    list.lattice_built_at = saved.lattice_built_at;
}

/// What a scene keeps beside its slots: pair caches where some pair keeps something in them
/// (conic pairs: warm starts), and as many history values as its most demanding law keeps.
pub(crate) fn kept(shapes: &[crate::geometry::Shape], pairs: &PairTable) -> Kept {
    Kept {
        cached: shapes.iter().any(PairCache::kept_with),
        history: pairs
            .all()
            .map(|p| p.spec.history_kept())
            .fold(1, usize::max),
    }
}

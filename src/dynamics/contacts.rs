//! Contacts, carried from step to step in a neighbour (Verlet) list.
//!
//! The list holds one **slot** per candidate pair: two bodies whose bounding circles were within
//! `skin` of each other, or a body within `skin` of a wall, when the list was last built. Each
//! step computes every slot's contact in place (independently, so in parallel and in a fixed
//! order); a slot whose pair overlaps is *active* and carries its history (T16) to the next
//! step; one that does not has its history dropped. The list is rebuilt when the bodies have
//! moved far enough that a pair outside it could have come into contact (the two largest
//! displacements since the last build add up to more than the skin), so no contact is ever
//! missed; between rebuilds nothing is allocated.
//!
//! A pair is keyed by `(i, j)`: two body indices `i < j`, or a body `i` and a wall `w` packed
//! into `j` ([`Partner::key`]), after every body. Slots are sorted by key, which fixes the order of every sum over
//! contacts: results do not depend on the number of threads. For each body the list also keeps
//! its slots in key order (`adjacency`), so that forces are gathered per body, in parallel,
//! without two threads writing to the same body.
//!
//! # Clumps: one slot per member pair
//! A clump's contacts are its member disks' (`geometry::clump`), and a clump pair can touch at
//! several places at once, each contact with its own shear spring. So a slot's key is
//! `(i, j, sub)`: `sub` packs the member of i (bits 16–30) and the member of j (low 16 bits;
//! 0 for a wall) with bit 31 set, and is 0 for a pair with no clump. A clump pair is then several slots with
//! the same `(i, j)`, each an ordinary contact between two circles (or a circle and the other
//! shape) whose force and moment go to the bodies with the lever arm from each body's
//! centroid to the contact point, as for any contact. Which member pairs get a slot is decided
//! at the build, rotation-invariantly (a clump turning in place between builds moves its
//! members, not its centroid, and the rebuild test watches only centroids): member `a` of i and
//! `b` of j get a slot when `|x_i − x_j| ≤ (|c_a| + r_a) + (|c_b| + r_b) + skin`, member `a` and
//! a wall when the wall is within `|c_a| + r_a + skin` of the centroid — every member pair that
//! can touch before the next build, however the bodies turn.

use super::body::Bodies;
use super::cell::Cell;
use super::partner::{Partner, Sides};
use crate::contact_law::History;
use crate::geometry::Vec2;
use crate::narrow_phase::{ContactState, PairCache};

/// Makes room for `needed` elements with 1/8 headroom instead of doubling: the lists are the bulk
/// of the memory, and they grow slowly, so that few builds reallocate.
pub(crate) fn reserve_for<T>(v: &mut Vec<T>, needed: usize) {
    if v.capacity() < needed {
        v.reserve_exact(needed + needed / 8 - v.len());
    }
}

/// Moves `v`'s elements up by `lead` places (in place), the vector's length becoming `total`
/// (`≥ lead + v.len()`; the places freed below, and any beyond, hold `filler`).
fn shift_up<T: Copy>(v: &mut Vec<T>, lead: usize, total: usize, filler: T) {
    let len = v.len();
    reserve_for(v, total);
    v.resize(total, filler);
    v.copy_within(0..len, lead);
}

/// A removed body's entry in the map [`ContactList::drop_bodies`] takes.
pub(crate) const REMOVED: u32 = u32::MAX;

/// One slot of the neighbour list: a candidate pair and what is carried from step to step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slot {
    /// First body.
    pub i: u32,
    /// Second body, or a wall ([`Partner::key`]; read it with [`Slot::partner`]).
    pub j: u32,
    /// The member pair of a clump pair ([`Slot::sub_of`]); 0 when neither body is a clump.
    pub sub: u32,
    /// The pair overlaps this step (its [`ContactData`] describes the contact).
    pub active: bool,
    /// Geometry state (overlap, deep, contained, …).
    pub state: ContactState,
    /// The contact's first history value ([`History`]: the tangential part's shear spring
    /// elongation δ_t along the current tangent, T16), dropped when the contact ends. The rest
    /// of the contact's history, where its law keeps any, is kept beside the slots
    /// ([`ContactList::history_of`]).
    pub shear: f64,
    /// Energy stored in the history springs (lost when the contact opens).
    pub history_energy: f64,
}

impl Slot {
    /// An inactive slot for pair `(i, j)` (no clump: `sub` 0).
    pub fn new(i: u32, j: u32) -> Self {
        Slot::with_sub(i, j, 0)
    }

    /// An inactive slot for member pair `sub` of pair `(i, j)`.
    pub fn with_sub(i: u32, j: u32, sub: u32) -> Self {
        Slot {
            i,
            j,
            sub,
            active: false,
            state: ContactState::Separated,
            shear: 0.0,
            history_energy: 0.0,
        }
    }

    /// True for a body–wall pair.
    #[inline]
    pub fn is_wall(&self) -> bool {
        matches!(self.partner(), Partner::Wall(_))
    }

    /// The partner of body `i`: body `j`, or a wall.
    #[inline]
    pub fn partner(&self) -> Partner {
        Partner::from_key(self.j)
    }

    /// Which side receives `+F` ([`Sides`]).
    #[inline]
    pub fn sides(&self) -> Sides {
        Sides::of_slot(self.i, self.j)
    }

    /// The slot's key: the pair and its member pair.
    #[inline]
    pub fn key(&self) -> (u32, u32, u32) {
        (self.i, self.j, self.sub)
    }

    /// `sub` for member `a` of body i and member `b` of body j (0 for a wall or a body that is
    /// not a clump) of a pair with a clump: [`Slot::CLUMP`] set, so that `sub != 0` exactly for
    /// the slots of clump pairs.
    #[inline]
    pub fn sub_of(a: usize, b: usize) -> u32 {
        Self::CLUMP | ((a as u32) << 16) | b as u32
    }

    /// The bit of `sub` set for every slot of a clump pair.
    pub const CLUMP: u32 = 1 << 31;

    /// The members `(of i, of j)` packed in `sub`.
    #[inline]
    pub fn members(&self) -> (usize, usize) {
        (
            ((self.sub >> 16) & 0x7FFF) as usize,
            (self.sub & 0xFFFF) as usize,
        )
    }
}

/// A slot's contact this step, as the force gather reads it (recomputed every step, all zero
/// while the slot is inactive). Kept to what the gather needs: at 10⁵ bodies the step is bound
/// by memory traffic, and this is written every step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactData {
    /// Contact point.
    pub point: Vec2,
    /// Force on j (the body, for a wall contact), world components.
    pub force: Vec2,
    /// For the energy account: the part of `force` that does not derive from the springs'
    /// energy — the normal force's non-elastic part (dashpot, or what the clamp `F_n ≥ 0`
    /// withholds) plus the whole shear force (whose spring's energy is accounted apart).
    pub force_non_elastic: Vec2,
    /// A couple on j (its opposite on i), and its non-elastic part: zero but for the area law's
    /// deep (four-crossing) overlaps.
    pub couple: f64,
    pub couple_non_elastic: f64,
}

/// The rest of a slot's contact, read only for reports (the depth) and the critical time step
/// (stiffness and damping, in single precision: an estimate needs no more). Filled on demand by
/// [`crate::dynamics::World::refresh_contact_extras`], not by the step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactExtra {
    /// Unit normal, from the wall or from i towards j, and depth.
    pub normal: Vec2,
    pub depth: f64,
    pub kn: f32,
    pub eta_n: f32,
    pub kt: f32,
    pub eta_t: f32,
    /// The spring and dashpot against the two bodies' relative rotation (zero for a law
    /// without one).
    pub kr: f32,
    pub cr: f32,
}

/// A contact of this step: its slot and its data (a copy, for reading).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    pub slot: Slot,
    pub data: ContactData,
    /// As of the last [`crate::dynamics::World::refresh_contact_extras`].
    pub extra: ContactExtra,
}

impl Contact {
    /// True for a body–wall contact.
    #[inline]
    pub fn is_wall(&self) -> bool {
        self.slot.is_wall()
    }

    /// Which side receives `+F` ([`Sides`]).
    #[inline]
    pub fn sides(&self) -> Sides {
        self.slot.sides()
    }
}

/// One entry of a body's adjacency: a slot and whether the body receives `+F` or `−F`
/// ([`Sides`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Adjacent {
    /// Slot index, with the top bit set when the body receives `−F`.
    packed: u32,
}

impl Adjacent {
    const GIVES: u32 = 1 << 31;

    /// The slot index.
    #[inline]
    pub fn slot(self) -> usize {
        (self.packed & !Self::GIVES) as usize
    }

    /// +1 when the body receives the slot's force, −1 when it receives its opposite.
    #[inline]
    pub fn sign(self) -> f64 {
        if self.packed & Self::GIVES != 0 {
            -1.0
        } else {
            1.0
        }
    }
}

/// The neighbour list: slots sorted by key, each body's slots, and what the list was built from.
#[derive(Clone, Debug, Default)]
pub struct ContactList {
    /// The slots, sorted by key.
    pub slots: Vec<Slot>,
    /// Each slot's contact this step (same index), and the rest of it.
    pub data: Vec<ContactData>,
    pub extra: Vec<ContactExtra>,
    /// Body k's slots are `adjacency[adjacency_start[k]..adjacency_start[k + 1]]`, in key order.
    pub(crate) adjacency_start: Vec<u32>,
    pub(crate) adjacency: Vec<Adjacent>,
    /// Body positions when the list was built.
    pub(crate) built_at: Vec<Vec2>,
    /// Wall points when the list was built (moving walls count towards the rebuild).
    pub(crate) wall_built_at: Vec<Vec2>,
    /// In a periodic cell, its lattice when the list was built (the images' motion counts
    /// towards the rebuild: [`super::cell::Cell::lattice_drift`]).
    pub(crate) lattice_built_at: Option<super::cell::LatticeMark>,
    /// In a periodic cell, whether each body lay near a seam when the list was built
    /// ([`ContactList::mark_near_seams`]); empty until marked.
    pub(crate) near_seam: Vec<bool>,
    /// Whether each slot's pair has a body near a seam (marked with `near_seam`): the contact
    /// pass reads these flags in slot order rather than two bodies' flags at random.
    pub(crate) near_slots: Vec<bool>,
    /// With rolling resistance, each body's contacts as the slots' flags stand (the last
    /// pass's: [`ContactList::count_touching`]); empty otherwise.
    pub(crate) touching: Vec<u32>,
    /// Margin added to the bounding circles at the build.
    pub skin: f64,
    /// Number of builds so far.
    pub builds: u64,
    /// Scratch of the build (kept to avoid allocating at every build).
    pub(crate) keys: Vec<(u32, u32, u32)>,
    /// Each slot's narrow-phase pair cache (same index; conic pairs keep their warm start
    /// there), or empty when no pair of the scene keeps anything ([`PairCache::kept_with`]): a
    /// disk pile neither stores nor streams them.
    pub(crate) cache: Vec<PairCache>,
    /// Each slot's further history values (beyond the first, which the slot holds), `stride`
    /// per slot in slot order ([`History`]: the values the scene's laws keep,
    /// [`crate::contact_law::ContactSpec::history_kept`]) — carried like the shear spring — or
    /// empty when no law of the scene keeps more than one (so that the slots, streamed every
    /// step, stay 32 bytes).
    pub(crate) history: Vec<f64>,
    /// Further history values per slot.
    pub(crate) stride: usize,
    pub(crate) adjacency_fill: Vec<u32>,
}

impl ContactList {
    /// Counts each of `n` bodies' contacts from the slots' flags (the last pass's contacts): the
    /// CDT limiter's share (`contact_law::rolling`), which a neighbour inside the skin that does
    /// not touch must not change.
    pub(crate) fn count_touching(&mut self, n: usize) {
        self.touching.clear();
        self.touching.resize(n, 0);
        for s in self.slots.iter().filter(|s| s.active) {
            self.touching[s.i as usize] += 1;
            if let Partner::Body(j) = s.partner() {
                self.touching[j] += 1;
            }
        }
    }

    /// Whether a pair outside the list could touch now: two bodies approach by at most the sum
    /// of their displacements since the build, which must stay within the skin (the step's
    /// rule, there taken from the drift's sums), with the drift of a periodic cell's lattice
    /// ([`ContactList::lattice_drift`]); also true for a list not built for these bodies.
    pub(crate) fn outgrown(&self, bodies: &super::Bodies, cell: Option<&Cell>) -> bool {
        if self.built_at.len() != bodies.len() {
            return true;
        }
        let mut top = [0.0f64; 2];
        for (s, at) in bodies.state.iter().zip(&self.built_at) {
            let d = (s.pose.position - at).norm();
            if d > top[0] {
                top = [d, top[0]];
            } else if d > top[1] {
                top[1] = d;
            }
        }
        top[0] + top[1] + self.lattice_drift(cell) > self.skin
    }

    /// How far the images of a periodic cell have moved since the list was built
    /// ([`Cell::lattice_drift`]; 0 outside a cell).
    #[inline]
    pub(crate) fn lattice_drift(&self, cell: Option<&Cell>) -> f64 {
        match (cell, &self.lattice_built_at) {
            (Some(c), Some(mark)) => c.lattice_drift(mark),
            _ => 0.0,
        }
    }

    /// Marks the bodies that lay near a seam of `cell` at the build (within a margin of twice
    /// the largest bounding radius of `bodies` and the skin), unless marked since: only a pair
    /// with such a body can meet through a
    /// periodic image before the next build. A body moves less than the skin between builds,
    /// so two bodies further from every seam stay in the cell and meet directly; their images
    /// lie at least `2 margin` less what they moved apart, beyond any contact. The contact
    /// pass and the gather look for images only at marked bodies; the others give the same
    /// bits without the search.
    pub(crate) fn mark_near_seams(&mut self, cell: &Cell, bodies: &Bodies) {
        if self.near_seam.len() == bodies.len() {
            return;
        }
        let max_bound = bodies.bound.iter().copied().fold(0.0f64, f64::max);
        let margin = 2.0 * (max_bound + self.skin);
        self.near_seam.clear();
        self.near_slots.clear();
        self.near_seam
            .extend(self.built_at.iter().map(|&p| cell.near_seam(p, margin)));
        let near = &self.near_seam;
        self.near_slots.clear();
        self.near_slots
            .extend(self.slots.iter().map(|s| match s.partner() {
                Partner::Body(k) => near[k] || near[s.i as usize],
                Partner::Wall(_) => false,
            }));
    }

    /// The contacts of this step (the active slots), in key order.
    pub fn active(&self) -> impl Iterator<Item = Contact> + '_ {
        self.slots
            .iter()
            .zip(&self.data)
            .zip(&self.extra)
            .filter(|((s, _), _)| s.active)
            .map(|((s, d), e)| Contact {
                slot: *s,
                data: *d,
                extra: *e,
            })
    }

    /// Slot `k`'s whole history (zero where the scene's laws keep nothing).
    pub fn history_of(&self, k: usize) -> History {
        let mut h = History::default();
        h.0[0] = self.slots[k].shear;
        let more = &self.history[k * self.stride..(k + 1) * self.stride];
        h.0[1..1 + more.len()].copy_from_slice(more);
        h
    }

    /// Number of contacts this step.
    pub fn len(&self) -> usize {
        self.slots.iter().filter(|c| c.active).count()
    }

    /// True when no pair is in contact.
    pub fn is_empty(&self) -> bool {
        !self.slots.iter().any(|c| c.active)
    }

    /// Takes removed bodies out of the list (between steps): `map[k]` is body k's new index,
    /// or [`REMOVED`]. The slots of the pairs of two remaining bodies, or of a remaining body
    /// and a wall, keep their history, cache and contact data, renumbered (a removal keeps the
    /// bodies' order, so the keys stay sorted); the others go, and the history springs' energy
    /// of the active ones among them is returned (lost, as when a contact opens). Each body's
    /// adjacency is made again for the `n` remaining bodies; what the list was built from
    /// keeps the remaining bodies' rows.
    pub(crate) fn drop_bodies(&mut self, map: &[u32], n: usize, cached: bool) -> f64 {
        let stride = self.stride;
        let cached = cached && self.cache.len() == self.slots.len();
        let mut lost = 0.0;
        let mut w = 0;
        for k in 0..self.slots.len() {
            let mut s = self.slots[k];
            let i = map[s.i as usize];
            let j = match s.partner() {
                Partner::Body(j) => map[j],
                Partner::Wall(_) => s.j,
            };
            if i == REMOVED || j == REMOVED {
                if s.active {
                    lost += s.history_energy;
                }
                continue;
            }
            s.i = i;
            s.j = j;
            self.slots[w] = s;
            self.data[w] = self.data[k];
            self.extra[w] = self.extra[k];
            if cached {
                self.cache[w] = self.cache[k];
            }
            self.history
                .copy_within(k * stride..(k + 1) * stride, w * stride);
            w += 1;
        }
        self.slots.truncate(w);
        self.data.truncate(w);
        self.extra.truncate(w);
        if cached {
            self.cache.truncate(w);
        }
        self.history.truncate(w * stride);
        let mut k = 0;
        self.built_at.retain(|_| {
            k += 1;
            map.get(k - 1).is_some_and(|&m| m != REMOVED)
        });
        self.near_seam.clear();
        self.near_slots.clear();
        self.touching.clear();
        // The same keys: every slot stays where it is; only the adjacency is made anew.
        self.keys.clear();
        self.keys.extend(self.slots.iter().map(Slot::key));
        let builds = self.builds;
        self.rebuild_from_keys_with(n, cached, stride, true);
        self.builds = builds;
        lost
    }

    /// Replaces the slots by `keys` (sorted, unique), carrying every continuing slot with its
    /// history (and its pair cache when `cached`, its further history values, `stride` of them
    /// per slot); rebuilds each body's adjacency for `n` bodies. Returns the history springs'
    /// energy of contacts that were active but are no longer candidates (lost, as when a contact
    /// opens).
    pub(crate) fn rebuild_from_keys(&mut self, n: usize, cached: bool, stride: usize) -> f64 {
        self.rebuild_from_keys_with(n, cached, stride, false)
    }

    /// [`ContactList::rebuild_from_keys`]; `carry_data`: each continuing slot keeps its contact
    /// data too (a new slot's are zero), for a list rebuilt between steps — when bodies are
    /// inserted ([`crate::dynamics::World::insert_bodies`]) — whose data are read before the
    /// next step computes them again.
    pub(crate) fn rebuild_from_keys_with(
        &mut self,
        n: usize,
        cached: bool,
        stride: usize,
        carry_data: bool,
    ) -> f64 {
        let (old_len, new_len) = (self.slots.len(), self.keys.len());
        let carry_data = carry_data && self.data.len() == old_len;
        self.near_seam.clear();
        self.near_slots.clear();
        let carry_cache = cached && self.cache.len() == old_len;
        let carry_history =
            stride > 0 && self.stride == stride && self.history.len() == old_len * stride;
        // The new list is the merge of the sorted keys with the old slots (sorted by key),
        // written over the old slots in place — no second list to carry them through (at 10⁴
        // ellipses that list and its caches held 146 of the 992 heap bytes per body) — once
        // the old ones have been moved up by `lead`, the most the merge's output ever runs
        // ahead of the old slots it has read. The first pass finds `lead`, and the history
        // energy of the slots that drop out, in the old list's order.
        let mut lost = 0.0;
        let mut lead = 0;
        let mut old = 0;
        for (k, &key) in self.keys.iter().enumerate() {
            while old < old_len && self.slots[old].key() < key {
                if self.slots[old].active {
                    lost += self.slots[old].history_energy;
                }
                old += 1;
            }
            if old < old_len && self.slots[old].key() == key {
                old += 1;
            }
            // Output k overwrites position k; the first unread old slot, `old`, sits at
            // `lead + old` and must lie beyond it.
            if old < old_len {
                lead = lead.max((k + 1).saturating_sub(old));
            }
        }
        for s in &self.slots[old..] {
            if s.active {
                lost += s.history_energy;
            }
        }
        let total = new_len.max(lead + old_len);
        shift_up(&mut self.slots, lead, total, Slot::with_sub(0, 0, 0));
        if carry_cache {
            shift_up(&mut self.cache, lead, total, PairCache::EMPTY);
        }
        if carry_history {
            shift_up(&mut self.history, lead * stride, total * stride, 0.0);
        }
        if carry_data {
            shift_up(&mut self.data, lead, total, ContactData::default());
        }
        let mut old = 0;
        for (k, &(i, j, sub)) in self.keys.iter().enumerate() {
            while old < old_len && self.slots[lead + old].key() < (i, j, sub) {
                old += 1;
            }
            if old < old_len && self.slots[lead + old].key() == (i, j, sub) {
                self.slots[k] = self.slots[lead + old];
                if carry_cache {
                    self.cache[k] = self.cache[lead + old];
                }
                if carry_history {
                    let from = (lead + old) * stride;
                    self.history.copy_within(from..from + stride, k * stride);
                }
                if carry_data {
                    self.data[k] = self.data[lead + old];
                }
                old += 1;
            } else {
                self.slots[k] = Slot::with_sub(i, j, sub);
                if carry_cache {
                    self.cache[k] = PairCache::EMPTY;
                }
                if carry_history {
                    self.history[k * stride..(k + 1) * stride].fill(0.0);
                }
                if carry_data {
                    self.data[k] = ContactData::default();
                }
            }
        }
        if carry_data {
            self.data.truncate(new_len);
        }
        self.slots.truncate(new_len);
        // Carried values are in place above (the resizes drop the shifted tail); a list that
        // kept none starts every slot empty, and a scene that keeps none has none.
        if !carry_cache {
            self.cache.clear();
        }
        if cached {
            reserve_for(&mut self.cache, new_len);
            self.cache.resize(new_len, PairCache::EMPTY);
        }
        if !carry_history {
            self.history.clear();
        }
        self.stride = stride;
        if stride > 0 {
            reserve_for(&mut self.history, new_len * stride);
            self.history.resize(new_len * stride, 0.0);
        }
        // The data are recomputed from the slots every step: only their number changes.
        reserve_for(&mut self.data, self.slots.len());
        self.data.resize(self.slots.len(), ContactData::default());
        reserve_for(&mut self.extra, self.slots.len());
        self.extra.resize(self.slots.len(), ContactExtra::default());
        // Adjacency (counting sort by body; each body's entries stay in slot order).
        self.adjacency_start.clear();
        reserve_for(&mut self.adjacency_start, n + 1);
        self.adjacency_start.resize(n + 1, 0);
        for s in &self.slots {
            self.adjacency_start[s.i as usize + 1] += 1;
            if !s.is_wall() {
                self.adjacency_start[s.j as usize + 1] += 1;
            }
        }
        for k in 0..n {
            self.adjacency_start[k + 1] += self.adjacency_start[k];
        }
        self.adjacency.clear();
        reserve_for(&mut self.adjacency, self.adjacency_start[n] as usize);
        self.adjacency
            .resize(self.adjacency_start[n] as usize, Adjacent { packed: 0 });
        // A cursor per body, from the starts.
        let mut fill: Vec<u32> = std::mem::take(&mut self.adjacency_fill);
        fill.clear();
        reserve_for(&mut fill, n);
        fill.extend_from_slice(&self.adjacency_start[..n]);
        for (idx, s) in self.slots.iter().enumerate() {
            let idx = idx as u32;
            let sides = Sides::of_slot(s.i, s.j);
            if let Some(k) = sides.giving_body() {
                self.adjacency[fill[k] as usize] = Adjacent {
                    packed: idx | Adjacent::GIVES,
                };
                fill[k] += 1;
            }
            let k = sides.receiver;
            self.adjacency[fill[k] as usize] = Adjacent { packed: idx };
            fill[k] += 1;
        }
        self.adjacency_fill = fill;
        self.builds += 1;
        lost
    }
}

/// One body's contact sums from its adjacency `adj` (its slots, in key order, with the sign of
/// each slot's force on it), its centroid `x` and its body force `f0`: the force `f0 + Σ F`
/// (T4), the moment `Σ r × F` (T22, `r` from the centroid to the contact point) plus the
/// contacts' couples, and the same two sums of the forces' non-elastic parts; `cell` the
/// periodic cell when some contact may lie across a seam. `COUPLES`
/// false leaves the couples out (a scene whose contacts have none): adding their ±0 would
/// change no bit, since a sum that starts at +0 is never −0.
#[inline(always)]
pub(crate) fn sum_contacts<const COUPLES: bool, const PERIODIC: bool>(
    adj: &[Adjacent],
    data: &[ContactData],
    x: Vec2,
    f0: Vec2,
    cell: Option<&Cell>,
) -> (Vec2, f64, Vec2, f64) {
    let (mut f, mut m) = (f0, 0.0);
    let (mut f_ne, mut m_ne) = (Vec2::zeros(), 0.0);
    // An inactive slot's data hold zero forces: no test needed.
    for a in adj {
        let d = &data[a.slot()];
        let r = match cell {
            // A contact of this body's periodic image: the lever to its point across the seam.
            Some(cell) if PERIODIC => cell.shortest(d.point - x),
            _ => d.point - x,
        };
        let sign = a.sign();
        let fs = d.force * sign;
        f += fs; // T(4)
        let fe = d.force_non_elastic * sign;
        f_ne += fe;
        if COUPLES {
            // The contact's couple is on j; its opposite on i.
            m += cross(r, fs) + d.couple * sign; // T(22)
            m_ne += cross(r, fe) + d.couple_non_elastic * sign;
        } else {
            m += cross(r, fs); // T(22)
            m_ne += cross(r, fe);
        }
    }
    (f, m, f_ne, m_ne)
}

/// The z component of `a × b`.
#[inline]
fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::narrow_phase::ellipse_ellipse::Warm;
    use std::collections::BTreeMap;

    /// A small deterministic generator (xorshift), so that the cases are reproducible.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn below(&mut self, n: u64) -> u64 {
            self.next() % n
        }
    }

    /// Sorted unique keys drawn from a small universe (so that old and new lists overlap).
    fn keys(rng: &mut Rng, count: usize) -> Vec<(u32, u32, u32)> {
        let mut k: Vec<_> = (0..count)
            .map(|_| {
                (
                    rng.below(12) as u32,
                    rng.below(12) as u32,
                    rng.below(2) as u32,
                )
            })
            .collect();
        k.sort_unstable();
        k.dedup();
        k
    }

    /// The in-place merge against a map from key to old slot: every new key keeps its old
    /// slot, pair cache and further history when it had one and starts empty otherwise, and the
    /// energy lost is that of the active old slots whose keys are gone — over lists that grow,
    /// shrink, and whose new keys come before, between and after the old ones.
    #[test]
    fn the_in_place_rebuild_carries_exactly_the_continuing_slots() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        for case in 0..2000 {
            let (old_count, new_count) = (rng.below(60) as usize, rng.below(60) as usize);
            let old_keys = keys(&mut rng, old_count);
            let new_keys = keys(&mut rng, new_count);
            let mut list = ContactList::default();
            let mut reference = BTreeMap::new();
            for (m, &(i, j, sub)) in old_keys.iter().enumerate() {
                let mut s = Slot::with_sub(i, j, sub);
                s.active = rng.below(2) == 0;
                s.shear = m as f64 + 0.5;
                s.history_energy = (m + 1) as f64; // small integers: every sum is exact
                let cache = PairCache::with_warm(Some(Warm::Axis([m as f64, 1.0])));
                let more = -(m as f64);
                list.slots.push(s);
                list.cache.push(cache);
                list.history.push(more);
                reference.insert((i, j, sub), (s, cache, more));
            }
            list.keys = new_keys.clone();
            list.stride = 1;
            let lost = list.rebuild_from_keys(12, true, 1);
            let expected_lost: f64 = reference
                .iter()
                .filter(|(k, (s, _, _))| s.active && new_keys.binary_search(k).is_err())
                .map(|(_, (s, _, _))| s.history_energy)
                .sum();
            assert_eq!(lost, expected_lost, "case {case}");
            assert_eq!(list.slots.len(), new_keys.len(), "case {case}");
            assert_eq!(list.cache.len(), new_keys.len(), "case {case}");
            assert_eq!(list.history.len(), new_keys.len(), "case {case}");
            for (k, &(i, j, sub)) in new_keys.iter().enumerate() {
                let (slot, cache, more) = match reference.get(&(i, j, sub)) {
                    Some(&(s, c, r)) => (s, c, r),
                    None => (Slot::with_sub(i, j, sub), PairCache::EMPTY, 0.0),
                };
                assert_eq!(list.slots[k], slot, "case {case}, slot {k}");
                assert_eq!(
                    list.cache[k].warm().map(|w| format!("{w:?}")),
                    cache.warm().map(|w| format!("{w:?}")),
                    "case {case}, slot {k}"
                );
                assert_eq!(list.history[k], more, "case {case}, slot {k}");
            }
        }
    }

    /// A list that kept no caches (a scene that had none) starts every slot's cache empty.
    #[test]
    fn a_list_without_caches_starts_them_empty() {
        let mut list = ContactList::default();
        list.slots.push(Slot::with_sub(0, 1, 0));
        list.keys = vec![(0, 1, 0), (0, 2, 0)];
        list.rebuild_from_keys(3, true, 0);
        assert_eq!(list.cache.len(), 2);
        assert!(list.cache.iter().all(|c| c.is_empty()));
        assert!(list.history.is_empty());
    }
}

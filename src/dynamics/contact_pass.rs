//! The contact pass: every slot's contact for the current positions and velocities, in
//! parallel, by one per-slot function ([`contact_slot`]).
//!
//! # One slot
//! 1. **Geometry**: where the contact is, along which normal and how deep, and what the normal
//!    spring acts on ([`SpringOn`], chosen in `contact_law`): from the narrow phase's dispatcher,
//!    the giver as i and the receiver as j ([`Sides`]: the normal points from the giver to the
//!    receiver, which gets +F).
//! 2. **Kinematics** at the contact point ([`super::kinematics`]): the relative velocity and
//!    spin, and what else the law asks for ([`Law::needs`]).
//! 3. **The law** ([`Law::force`]) with the slot's history.
//! 4. **The record**: the slot's history, its [`ContactData`] (read by the force gather), the
//!    wall's load, the pass's sums (contacts, elastic energy, the history springs' energy, the
//!    fallback geometries, the deepest overlap).
//!
//! # Compiled for what a scene needs
//! [`contact_slot`] is generic over where its geometry comes from ([`Geometry`]: the narrow
//! phase's dispatcher on circles of the bodies' radii in a scene of disks, a circle pair's
//! contact computed ahead for the chunk, or the dispatcher on the bodies' shapes with the slot's
//! pair cache), over its laws ([`LawSource`]:
//! all linear with constant dashpots — the law's kinds then known, so that nothing it does not
//! read is computed — or resolved), and over whether the slot pairs two
//! bodies (`PAIR`: no wall branch left). Each combination the pass takes is a copy of the same
//! source compiled for it: the same arithmetic, the same bits, in as few instructions as that
//! scene allows (10⁴ disks: ~40 % fewer per slot than the general copy).

use super::body::Bodies;
use super::boundary::{Boundary, WallLoad};
use super::cell::Cell;
use super::contacts::{ContactData, ContactExtra, ContactList, Slot};
use super::kinematics::{self, Contact};
use super::materials::PairTable;
use super::members;
use super::partner::{Partner, Sides};
use crate::contact_law::{CohesionKinematics, ContactSpec, History, Law, LinearDashpots};
use crate::contact_law::{HISTORY_LEN, Needs, PairFacts, SpringOn};
use crate::contact_law::{NormalForce, PairSpec};
use crate::geometry::overlap_area::DiskLens;
use crate::geometry::{Pose, Shape, Vec2};
use crate::narrow_phase::{self, ContactState, PairCache, Request, Side, contact_with};
use rayon::prelude::*;

/// Neighbour-list slots per parallel chunk. A fixed size: every sum is formed chunk by chunk
/// and then over the chunks in order, so that results are the same bit for bit whatever the
/// number of threads.
pub(crate) const SLOT_CHUNK: usize = 512;

/// How many slots ahead a loop asks for its second body's data. (10⁶ disks, one thread, three
/// interleaved pairs of `dem2d-lab bench --shapes disks --sizes 10000,1000000 --steps 100`:
/// 8 → 16 slots 13.15 → 13.44 M particle-steps/s at 10⁶, 10⁴ unchanged; 32 no better than 16.)
const PREFETCH_AHEAD: usize = 16;

/// Per-chunk results of the pass.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SlotPartial {
    pub contacts: usize,
    pub elastic: f64,
    /// History springs' energy of contacts that opened this step.
    pub lost_history: f64,
    pub deep: u64,
    pub contained: u64,
    pub max_depth_ratio: f64,
    /// Σ of the change of the history springs' energy.
    pub history_energy_change: f64,
    /// In a periodic cell, over the pairs of bodies: `Σ f ⊗ l` (xx, xy, yx, yy; f the force on
    /// the receiver, l the branch vector from the giver's image to the receiver: Love–Weber),
    /// and the contacts' affine stiffness against a stretch along x and along y, `Σ k_n (n_x
    /// l_x)²` and `Σ k_n (n_y l_y)²`.
    pub stress: [f64; 4],
    pub stiffness: [f64; 2],
    /// `Σ F_s n_x l_x` and `Σ F_s n_y l_y`, F_s the elastic part of the normal force: minus the
    /// rate at which the contacts' stored energy changes under an affine stretch along x, y.
    pub elastic_n: [f64; 2],
    /// In a Lees–Edwards cell, the power of the contacts across its y seam on the image's
    /// extra velocity u, `Σ f·u`, and of their non-elastic parts (the boundary's work: see
    /// `dynamics::cell`).
    pub image_power: f64,
    pub image_power_ne: f64,
}

impl SlotPartial {
    /// Adds another chunk's sums.
    fn add(&mut self, p: &SlotPartial) {
        self.contacts += p.contacts;
        self.elastic += p.elastic;
        self.lost_history += p.lost_history;
        self.deep += p.deep;
        self.contained += p.contained;
        self.max_depth_ratio = self.max_depth_ratio.max(p.max_depth_ratio);
        self.history_energy_change += p.history_energy_change;
        for (a, b) in self.stress.iter_mut().zip(p.stress) {
            *a += b;
        }
        for k in 0..2 {
            self.stiffness[k] += p.stiffness[k];
            self.elastic_n[k] += p.elastic_n[k];
        }
        self.image_power += p.image_power;
        self.image_power_ne += p.image_power_ne;
    }
}

/// The facts of a scene that decide which copy of the pass it takes, noted whenever the
/// neighbour list is made (built or restored from a restart: which pairs take the lean path
/// decides the last bits, so a restored list must note it too).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SceneFacts {
    /// The density of every body when they all have the same.
    pub uniform_density: Option<f64>,
    /// Some body is a circle or a clump (whose contacts are its member disks'): some pair may
    /// take the narrow phase's lean path.
    pub circles: bool,
    /// Some body is a clump: the list holds member-pair slots.
    pub clumps: bool,
    /// Every body is a circle.
    pub disks: bool,
    /// The largest bounding radius (the reach of a pair: [`super::neighbour_list::pair_reach`]).
    pub max_bound: f64,
}

impl SceneFacts {
    /// The facts of `bodies`.
    pub fn of(bodies: &Bodies) -> Self {
        let d0 = bodies.density.first().copied();
        let clumps = bodies.shape.iter().any(|s| s.clump().is_some());
        SceneFacts {
            uniform_density: d0.filter(|&d| bodies.density.iter().all(|&x| x == d)),
            circles: bodies.is_circle.iter().any(|&c| c) || clumps,
            clumps,
            disks: bodies.is_circle.iter().all(|&c| c),
            max_bound: bodies.bound.iter().copied().fold(0.0, f64::max),
        }
    }
}

/// The pass's scratch, reused from step to step: per-chunk sums, per chunk and wall the walls'
/// loads, and the laws resolved once per step.
#[derive(Clone, Debug, Default)]
pub(crate) struct ContactPass {
    partials: Vec<SlotPartial>,
    /// Per chunk of slots, per wall: the wall's contacts' sums.
    wall_partials: Vec<WallLoad>,
    /// Laws resolved once per step when every pair of a kind has the same: one material,
    /// `[0]` body pairs, `[1 + w]` wall w; M materials, as [`PairTable::all`] lists them.
    laws: Vec<Law>,
    /// The same laws' numbers when every one is linear with constant dashpots and nothing more
    /// ([`LinearDashpots`]; empty otherwise): the slots then take the copies compiled for
    /// such laws.
    linear: Vec<LinearDashpots>,
}

/// What a step's pass reads: the bodies, the walls, the scene's law, |g|, the step Δt, and the
/// neighbour list's per-body contact counts (the CDT limiter's share).
pub(crate) struct PassInput<'a> {
    pub bodies: &'a Bodies,
    pub walls: &'a mut [Boundary],
    pub spec: &'a ContactSpec,
    pub pairs: &'a PairTable,
    pub g: f64,
    pub dt: f64,
    pub facts: SceneFacts,
    pub cell: Option<&'a Cell>,
}

/// Runs `f` on each of `chunks` (chunks of [`SLOT_CHUNK`] slots, in order) with its chunk of
/// the pair caches and of the further history values, where the scene keeps them.
fn with_kept<T: Send>(
    chunks: impl IndexedParallelIterator<Item = T>,
    cache: &mut [PairCache],
    history: &mut [f64],
    stride: usize,
    f: impl Fn(T, Option<&mut [PairCache]>, Option<(&mut [f64], usize)>) + Sync + Send,
) {
    match (cache.is_empty(), history.is_empty()) {
        (true, true) => chunks.for_each(|c| f(c, None, None)),
        (false, true) => chunks
            .zip(cache.par_chunks_mut(SLOT_CHUNK))
            .for_each(|(c, cache)| f(c, Some(cache), None)),
        (true, false) => chunks
            .zip(history.par_chunks_mut(SLOT_CHUNK * stride))
            .for_each(|(c, more)| f(c, None, Some((more, stride)))),
        (false, false) => chunks
            .zip(cache.par_chunks_mut(SLOT_CHUNK))
            .zip(history.par_chunks_mut(SLOT_CHUNK * stride))
            .for_each(|((c, cache), more)| f(c, Some(cache), Some((more, stride)))),
    }
}

impl ContactPass {
    /// Heap bytes of the pass's scratch.
    pub fn heap_bytes(&self) -> usize {
        self.wall_partials.capacity() * std::mem::size_of::<WallLoad>()
    }

    /// One partial sum per chunk of `slots` slots (and per wall for each chunk: at least one,
    /// so that every chunk has its slice).
    pub fn size(&mut self, slots: usize, walls: usize) {
        let ns = slots.div_ceil(SLOT_CHUNK);
        if self.partials.len() != ns {
            self.partials.resize(ns, SlotPartial::default());
        }
        let nw = ns * walls.max(1);
        if self.wall_partials.len() != nw {
            self.wall_partials.resize(nw, WallLoad::default());
        }
    }

    /// Whether this step's laws are all linear with constant dashpots (after
    /// [`ContactPass::resolve`]): a disk scene's contacts then have no couples.
    pub fn linear(&self) -> bool {
        !self.linear.is_empty()
    }

    /// When every pair of a kind has the same law — one density for all bodies, and no law that
    /// depends on the pair's mass (restitution-tuned dashpots) — resolves the body–body law and
    /// each wall's once instead of at every contact: with one material, the body pairs' and each
    /// wall's; with several, every law of the table.
    fn resolve(&mut self, pairs: &PairTable, walls: &[Boundary], facts: &SceneFacts, g: f64) {
        self.laws.clear();
        self.linear.clear();
        let Some(rho) = facts.uniform_density else {
            return;
        };
        if pairs.all().any(|p| p.spec.depends_on_mass()) {
            return;
        }
        if pairs.count() > 1 {
            self.laws.extend(pairs.all().map(|p| p.resolve(rho, g)));
        } else {
            self.laws.push(pairs.body_pair(0, 0).resolve(rho, g));
            for w in 0..walls.len() {
                self.laws.push(pairs.wall(w, 0).resolve(rho, g));
            }
        }
        for law in &self.laws {
            match LinearDashpots::of(law) {
                Some(l) => self.linear.push(l),
                None => {
                    self.linear.clear();
                    break;
                }
            }
        }
    }

    /// Every slot's contact, in parallel; `input.dt` is the step just drifted over (0 at the
    /// start), over which the shear displacement is integrated (T16). Sets each wall's load and
    /// returns the sums.
    pub fn run(&mut self, input: PassInput, list: &mut ContactList) -> SlotPartial {
        let (pairs, facts, cell) = (input.pairs, input.facts, input.cell);
        self.resolve(pairs, input.walls, &facts, input.g);
        self.size(list.slots.len(), input.walls.len());
        let ContactList {
            slots,
            data,
            cache,
            history,
            stride,
            near_seam,
            near_slots,
            touching,
            ..
        } = list;
        let stride = *stride;
        let cx = PassContext::of(&input, input.dt, near_seam, touching);
        let nw = input.walls.len().max(1);
        let (linear, laws) = (&self.linear[..], &self.laws[..]);
        let chunk = Chunk {
            cx: &cx,
            linear,
            materials: pairs.count() > 1,
            resolved: Resolved::new(laws, pairs),
            circles: facts.circles,
            disks: facts.disks && !linear.is_empty(),
        };
        let chunks = slots
            .par_chunks_mut(SLOT_CHUNK)
            .zip(data.par_chunks_mut(SLOT_CHUNK))
            .zip(self.partials.par_iter_mut())
            .zip(self.wall_partials.par_chunks_mut(nw));
        // A periodic cell's copy of the pass shifts each giver to its nearest image and sums
        // the cell's stress: taken by every slot where the cell measures its stress, else by
        // the runs of slots with a body near a seam. The others meet no image: the
        // wall-bounded copy, the same bits (the sums run through the chunk in order either way).
        let measures = cell.is_some_and(Cell::measures_stress);
        if cell.is_none() || measures {
            with_kept(
                chunks,
                cache,
                history,
                stride,
                |(((s, d), p), l), cache, more| {
                    l.fill(WallLoad::default());
                    *p = SlotPartial::default();
                    match cell {
                        None => chunk.run::<false>(s, d, l, cache, more, p),
                        Some(_) => chunk.run::<true>(s, d, l, cache, more, p),
                    }
                },
            );
        } else {
            let near_slots = &near_slots[..];
            let chunks = chunks.enumerate();
            with_kept(chunks, cache, history, stride, |c, mut cache, mut more| {
                let (c, (((slots, data), p), loads)) = c;
                loads.fill(WallLoad::default());
                *p = SlotPartial::default();
                let near = &near_slots[c * SLOT_CHUNK..c * SLOT_CHUNK + slots.len()];
                let mut a = 0;
                while a < slots.len() {
                    let here = near[a];
                    let b = near[a..]
                        .iter()
                        .position(|&s| s != here)
                        .map_or(slots.len(), |k| a + k);
                    let cache = cache.as_deref_mut().map(|c| &mut c[a..b]);
                    let more = more
                        .as_mut()
                        .map(|(h, stride)| (&mut h[a * *stride..b * *stride], *stride));
                    let (s, d) = (&mut slots[a..b], &mut data[a..b]);
                    if here {
                        chunk.run::<true>(s, d, loads, cache, more, p);
                    } else {
                        chunk.run::<false>(s, d, loads, cache, more, p);
                    }
                    a = b;
                }
            });
        }
        let mut sum = SlotPartial::default();
        for p in &self.partials {
            sum.add(p);
        }
        // Each wall's load: its contacts' sums, chunk by chunk in order.
        for (w, ws) in input.walls.iter_mut().enumerate() {
            let mut load = WallLoad::default();
            for c in self.wall_partials.chunks(nw) {
                load.add(&c[w]);
            }
            ws.load = load;
        }
        sum
    }

    /// Fills each active slot's [`ContactExtra`] (depth, stiffness, damping) for the current
    /// state: every slot evaluated again on a copy — its history untouched, no time elapsing
    /// (Δt = 0) — keeping only the extras.
    pub fn refresh_extras(&mut self, input: PassInput, list: &mut ContactList) {
        self.resolve(input.pairs, input.walls, &input.facts, input.g);
        let ContactList {
            slots,
            extra,
            cache,
            history,
            stride,
            near_seam,
            touching,
            ..
        } = list;
        let stride = *stride;
        let cx = PassContext::of(&input, 0.0, near_seam, touching);
        let laws = Resolved::new(&self.laws, input.pairs);
        let (cache, history) = (&cache[..], &history[..]);
        slots
            .par_chunks(SLOT_CHUNK)
            .zip(extra.par_chunks_mut(SLOT_CHUNK))
            .enumerate()
            .for_each(|(c, (slots, extra))| {
                let mut p = SlotPartial::default();
                for (k, (slot, extra)) in slots.iter().zip(extra).enumerate() {
                    if !slot.active {
                        *extra = ContactExtra::default();
                        continue;
                    }
                    let (mut slot, mut data) = (*slot, ContactData::default());
                    let mut cache = cache.get(c * SLOT_CHUNK + k).copied();
                    let at = (c * SLOT_CHUNK + k) * stride;
                    let mut more = [0.0; HISTORY_LEN];
                    let more = match history.get(at..at + stride) {
                        Some(h) if stride > 0 => {
                            more[..stride].copy_from_slice(h);
                            Some(&mut more[..stride])
                        }
                        _ => None,
                    };
                    let to = SlotOut {
                        data: &mut data,
                        extra: Some(extra),
                        history: more,
                    };
                    // (Reports only: the periodic copy serves every scene.)
                    match lean_of::<true>(&slot, &cx) {
                        Some(l) => contact_slot::<_, _, false, true>(
                            &mut slot,
                            to,
                            Lean(l),
                            laws,
                            &cx,
                            &mut p,
                            &mut [],
                        ),
                        None => contact_slot::<_, _, false, true>(
                            &mut slot,
                            to,
                            Dispatch(cache.as_mut()),
                            laws,
                            &cx,
                            &mut p,
                            &mut [],
                        ),
                    }
                }
            });
    }
}

/// What every slot's contact is computed from: the bodies, the walls, the scene's law, |g|, the
/// step Δt and the neighbour list's per-body contact counts.
#[derive(Clone, Copy)]
pub(crate) struct PassContext<'a> {
    pub bodies: &'a Bodies,
    pub walls: &'a [Boundary],
    pub spec: &'a ContactSpec,
    pub pairs: &'a PairTable,
    pub g: f64,
    pub dt: f64,
    /// The periodic cell, if the scene has one.
    pub cell: Option<&'a Cell>,
    /// In a periodic cell, the bodies near a seam (the only ones whose pairs may meet through
    /// an image: [`ContactList::mark_near_seams`]).
    pub near_seam: &'a [bool],
    /// With rolling resistance, each body's contacts (the last pass's): the CDT limiter's share.
    pub touching: &'a [u32],
    /// Some pair's law has cohesion: the contacts ask the narrow phase for their chord and
    /// overlap area ([`CohesionKinematics`]).
    pub cohesive: bool,
}

impl<'a> PassContext<'a> {
    /// The context of a pass of `input` over the step `dt`, with the neighbour list's marks.
    fn of(input: &'a PassInput, dt: f64, near_seam: &'a [bool], touching: &'a [u32]) -> Self {
        PassContext {
            bodies: input.bodies,
            walls: input.walls,
            spec: input.spec,
            pairs: input.pairs,
            g: input.g,
            dt,
            cell: input.cell,
            near_seam,
            touching,
            cohesive: input.pairs.all().any(|p| p.spec.cohesion.is_some()),
        }
    }

    /// What a circle pair's or a clump member pair's query asks besides the depth: nothing, but
    /// in a cohesive scene the chord and the overlap area.
    #[inline(always)]
    fn lean_request(&self) -> Request<'static> {
        if self.cohesive {
            Request::FULL
        } else {
            Request::LEAN
        }
    }

    /// The cohesion's view of the contact `c` whose force acts at `point` along `normal` (in a
    /// cohesive scene; `None` otherwise).
    #[inline(always)]
    fn cohesion_of(
        &self,
        c: &narrow_phase::Contact,
        point: Vec2,
        normal: Vec2,
    ) -> Option<CohesionKinematics> {
        self.cohesive
            .then(|| CohesionKinematics::of(c, point, normal))
    }

    /// The sides of a slot's pair as the narrow phase takes them: the giver as i, the receiver
    /// as j; a giver seen through a periodic image is placed at the image, in `store`.
    #[inline(always)]
    fn sides<'s>(&'s self, sides: Sides, store: &'s mut Pose) -> (Side<'s>, Side<'s>) {
        let b = self.bodies;
        let i = match sides.giver {
            Partner::Wall(w) => self.walls[w].side(),
            Partner::Body(k) => Side::Body(&b.shape[k], self.giver_pose(k, sides, store)),
        };
        let recv = sides.receiver;
        (i, Side::Body(&b.shape[recv], &b.state[recv].pose))
    }

    /// Body `k`'s pose as the giver of `sides`: its own, or its periodic image's (in `store`).
    #[inline(always)]
    fn giver_pose<'s>(&'s self, k: usize, sides: Sides, store: &'s mut Pose) -> &'s Pose {
        match sides.image {
            None => &self.bodies.state[k].pose,
            Some(image) => {
                *store = self.bodies.state[k].pose;
                store.position += image.offset;
                store
            }
        }
    }

    /// `slot`'s sides (see [`sides_of_slot`]), with the giver's nearest periodic image in a
    /// periodic cell (`PERIODIC`).
    #[inline(always)]
    fn slot_sides<const PAIR: bool, const PERIODIC: bool>(&self, slot: &Slot) -> Sides {
        let mut sides = sides_of_slot::<PAIR>(slot);
        if PERIODIC
            && let (Some(cell), Partner::Body(k)) = (self.cell, sides.giver)
            && (self.near_seam[k] || self.near_seam[sides.receiver])
        {
            let b = &self.bodies.state;
            sides.image = cell.nearest_image(b[k].pose.position, b[sides.receiver].pose.position);
        }
        sides
    }

    /// What the normal spring of a pair acts on: a wall's own law's choice, or the scene's
    /// (a material cannot change it).
    #[inline(always)]
    fn normal_force(&self, sides: Sides) -> NormalForce {
        match sides.wall() {
            Some(w) => self.walls[w].spec.normal_force(),
            None => self.spec.normal_force(),
        }
    }

    /// The contact law of a pair: its materials', or a wall's with the body's material.
    #[inline(always)]
    fn pair(&self, sides: Sides) -> &PairSpec {
        let m = &self.bodies.material;
        let recv = m[sides.receiver];
        match sides.giver {
            Partner::Wall(w) => self.pairs.wall(w, recv),
            Partner::Body(k) => self.pairs.body_pair(m[k], recv),
        }
    }

    /// The index of a pair's law in [`PairTable::all`]'s order.
    #[inline(always)]
    fn pair_index(&self, sides: Sides) -> usize {
        let (m, count) = (&self.bodies.material, self.pairs.count());
        let recv = m[sides.receiver] as usize;
        match sides.giver {
            Partner::Wall(w) => count * count + w * count + recv,
            Partner::Body(k) => m[k] as usize * count + recv,
        }
    }
}

/// One chunk's pass: the copy of [`contact_slot`] each slot takes.
#[derive(Clone, Copy)]
struct Chunk<'a> {
    cx: &'a PassContext<'a>,
    /// The step's laws when all are linear with constant dashpots ([`Linear`]; empty
    /// otherwise).
    linear: &'a [LinearDashpots],
    /// Several materials: the laws as [`PairTable::all`] lists them.
    materials: bool,
    resolved: Resolved<'a>,
    /// Some pair may take the lean path.
    circles: bool,
    /// Every body is a circle and every law linear: [`Disks`].
    disks: bool,
}

impl Chunk<'_> {
    /// The chunk's slots (with their pair caches, and their further history values with their
    /// number per slot, when the scene keeps them), their sums added to `p` and their walls'
    /// loads to `loads`.
    fn run<const PERIODIC: bool>(
        &self,
        slots: &mut [Slot],
        data: &mut [ContactData],
        loads: &mut [WallLoad],
        cache: Option<&mut [PairCache]>,
        history: Option<(&mut [f64], usize)>,
        p: &mut SlotPartial,
    ) {
        // (A scene of several materials in copies of its own: one material's keep their code.)
        if self.materials {
            let linear = Linear::<true>(self.linear);
            self.run_with::<PERIODIC, true>(slots, data, loads, cache, history, p, linear);
        } else {
            let linear = Linear::<false>(self.linear);
            self.run_with::<PERIODIC, false>(slots, data, loads, cache, history, p, linear);
        }
    }

    /// [`Chunk::run`] with the linear laws `linear`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn run_with<const PERIODIC: bool, const MATERIALS: bool>(
        &self,
        slots: &mut [Slot],
        data: &mut [ContactData],
        loads: &mut [WallLoad],
        mut cache: Option<&mut [PairCache]>,
        mut history: Option<(&mut [f64], usize)>,
        p: &mut SlotPartial,
        linear: Linear<MATERIALS>,
    ) {
        let cx = self.cx;
        let is_linear = !linear.0.is_empty();
        if self.disks && MATERIALS {
            // Each body pair's law from the table.
            let data = &mut data[..slots.len()];
            for k in 0..slots.len() {
                if let Some(ahead) = slots.get(k + PREFETCH_AHEAD) {
                    prefetch_partner(cx.bodies, ahead, &cx.bodies.bound);
                }
                let (slot, to) = (&mut slots[k], SlotOut::data(&mut data[k]));
                if !slot.is_wall() {
                    contact_slot::<_, _, true, PERIODIC>(slot, to, Disks, linear, cx, p, loads);
                } else {
                    contact_slot_apart::<_, _, false, PERIODIC>(
                        slot, to, Disks, linear, cx, p, loads,
                    );
                }
            }
            return;
        }
        if self.disks {
            // The body pairs' law (the first) held here, where it stays in registers, rather
            // than read from the scene's list at every slot.
            let pair_law = [linear.0[0]];
            let data = &mut data[..slots.len()]; // (no bounds check on `data[k]`)
            for k in 0..slots.len() {
                if let Some(ahead) = slots.get(k + PREFETCH_AHEAD) {
                    prefetch_partner(cx.bodies, ahead, &cx.bodies.bound);
                }
                let (slot, to) = (&mut slots[k], SlotOut::data(&mut data[k]));
                // Body pairs in a copy compiled for them; wall slots (few) out of line, so that
                // the pair loop stays short.
                if !slot.is_wall() {
                    contact_slot::<_, _, true, PERIODIC>(
                        slot,
                        to,
                        Disks,
                        Linear::<false>(&pair_law),
                        cx,
                        p,
                        loads,
                    );
                } else {
                    contact_slot_apart::<_, _, false, PERIODIC>(
                        slot, to, Disks, linear, cx, p, loads,
                    );
                }
            }
            return;
        }
        // With circles in the scene, the circle pairs' geometry first, for the whole chunk: a
        // short loop whose square roots and divisions overlap from slot to slot (inside the
        // long per-slot pass each waited for its own; 10⁴ disks: 8 % faster). The same kernels
        // on the same inputs: the same bits. (Filled in place: returned from a closure, the
        // 28 KB array was copied.)
        let mut lean = [None; SLOT_CHUNK];
        if self.circles {
            for (k, (l, slot)) in lean.iter_mut().zip(slots.iter()).enumerate() {
                if let Some(ahead) = slots.get(k + PREFETCH_AHEAD) {
                    prefetch_partner(cx.bodies, ahead, &cx.bodies.shape);
                }
                *l = lean_of::<PERIODIC>(slot, cx);
            }
        }
        for (k, (slot, data)) in slots.iter_mut().zip(data).enumerate() {
            // (A linear law keeps no further history.)
            let r = history
                .as_mut()
                .map(|(h, stride)| &mut h[k * *stride..(k + 1) * *stride]);
            let cache = cache.as_deref_mut().map(|c| &mut c[k]);
            let (resolved, to) = (self.resolved, SlotOut::data(data));
            match lean[k] {
                Some(l) if is_linear => contact_slot_apart::<_, _, false, PERIODIC>(
                    slot,
                    to,
                    Lean(l),
                    linear,
                    cx,
                    p,
                    loads,
                ),
                Some(l) => contact_slot_apart::<_, _, false, PERIODIC>(
                    slot,
                    to.with_history(r),
                    Lean(l),
                    resolved,
                    cx,
                    p,
                    loads,
                ),
                None if !is_linear => contact_slot_apart::<_, _, false, PERIODIC>(
                    slot,
                    to.with_history(r),
                    Dispatch(cache),
                    resolved,
                    cx,
                    p,
                    loads,
                ),
                // Body pairs in a copy compiled for them (no wall branch left).
                None if !slot.is_wall() => contact_slot_apart::<_, _, true, PERIODIC>(
                    slot,
                    to,
                    Dispatch(cache),
                    linear,
                    cx,
                    p,
                    loads,
                ),
                None => contact_slot_apart::<_, _, false, PERIODIC>(
                    slot,
                    to,
                    Dispatch(cache),
                    linear,
                    cx,
                    p,
                    loads,
                ),
            }
        }
    }
}

/// Where a slot's contact goes: its data, its extras when asked (reports, the critical step),
/// and its further history values when the scene keeps them.
pub(crate) struct SlotOut<'a> {
    data: &'a mut ContactData,
    extra: Option<&'a mut ContactExtra>,
    history: Option<&'a mut [f64]>,
}

impl<'a> SlotOut<'a> {
    #[inline(always)]
    fn data(data: &'a mut ContactData) -> Self {
        SlotOut {
            data,
            extra: None,
            history: None,
        }
    }

    #[inline(always)]
    fn with_history(self, history: Option<&'a mut [f64]>) -> Self {
        SlotOut { history, ..self }
    }
}

/// A slot's contact as the geometry found it: state, point, normal, depth, what the spring
/// acts on, and in a cohesive scene the chord and area the pull reads.
type Found = (
    ContactState,
    Vec2,
    Vec2,
    f64,
    SpringOn,
    Option<CohesionKinematics>,
);

/// Where a slot's geometry comes from (see the module documentation).
pub(crate) trait Geometry {
    /// Every body is a circle: a body's inscribed radius is its bounding radius.
    const DISKS: bool;
    /// The slot's contact (`None`, or a depth ≤ 0: apart).
    fn find(self, sides: Sides, cx: &PassContext) -> Option<Found>;
}

/// A scene of disks: the dispatcher on circles of the bodies' bounding radii (their radii),
/// without their shapes (the wall is the giver, i, as [`PassContext::sides`] has it): the same
/// kernels on the same numbers as for the bodies' own shapes, the same bits. The spring on the
/// depth (a disk's area potential is that spring).
#[derive(Clone, Copy)]
struct Disks;

impl Disks {
    /// The slot's contact, from an empty pair cache (a circle pair keeps nothing), computing what
    /// `request` asks.
    #[inline(always)]
    fn contact(
        self,
        sides: Sides,
        cx: &PassContext,
        request: Request,
    ) -> Option<narrow_phase::Contact> {
        let b = cx.bodies;
        let recv = sides.receiver;
        let circle_j = Shape::Circle { r: b.bound[recv] };
        let j = Side::Body(&circle_j, &b.state[recv].pose);
        match sides.giver {
            Partner::Wall(w) => {
                contact_with(cx.walls[w].side(), j, &mut PairCache::default(), request)
            }
            Partner::Body(k) => {
                let circle_i = Shape::Circle { r: b.bound[k] };
                let mut store = Pose::IDENTITY;
                let i = Side::Body(&circle_i, cx.giver_pose(k, sides, &mut store));
                contact_with(i, j, &mut PairCache::default(), request)
            }
        }
    }
}

impl Geometry for Disks {
    const DISKS: bool = true;
    #[inline(always)]
    fn find(self, sides: Sides, cx: &PassContext) -> Option<Found> {
        // (Only in a scene whose laws are all linear with constant dashpots: no cohesion.)
        self.contact(sides, cx, Request::LEAN)
            .map(|c| (c.state, c.point, c.normal, c.depth, SpringOn::Depth, None))
    }
}

/// A pair's contact computed ahead for the chunk ([`lean_of`]: two circles, a circle and a
/// wall, a clump's member pair). The spring on the depth (a disk's area potential is that
/// spring).
#[derive(Clone, Copy)]
struct Lean(Option<narrow_phase::Contact>);

impl Geometry for Lean {
    const DISKS: bool = false;
    #[inline(always)]
    fn find(self, _: Sides, cx: &PassContext) -> Option<Found> {
        self.0.map(|c| {
            let cohesion = cx.cohesion_of(&c, c.point, c.normal);
            (
                c.state,
                c.point,
                c.normal,
                c.depth,
                SpringOn::Depth,
                cohesion,
            )
        })
    }
}

/// The narrow phase's dispatcher on the bodies' shapes with the slot's pair cache (conic pairs
/// start from the last step's crossings if the contact lasts, or a separating axis, and leave
/// the next step's there; `None`: a scene no pair of which keeps anything).
struct Dispatch<'a>(Option<&'a mut PairCache>);

impl Geometry for Dispatch<'_> {
    const DISKS: bool = false;
    #[inline(always)]
    fn find(self, sides: Sides, cx: &PassContext) -> Option<Found> {
        let area_law = cx.normal_force(sides) == NormalForce::Area;
        let facts = Facts {
            bodies: cx.bodies,
            sides,
        };
        let mut scratch = PairCache::EMPTY;
        let cache = match self.0 {
            Some(c) => c,
            None => &mut scratch,
        };
        let mut store = Pose::IDENTITY;
        let (i, j) = cx.sides(sides, &mut store);
        let request = Request {
            area: area_law || cx.cohesive,
            chord: cx.cohesive,
            trace: None,
        };
        // (Not `Option::map` with a closure: the compiler kept that closure out of line, and
        // the record went through memory to it — 4618 against 4379 instructions per body-step
        // on the settled 10⁴-ellipse pile under the area law, callgrind's count of
        // `World::step` over 50 steps as the lab notebook takes it.)
        let c = contact_with(i, j, cache, request)?;
        // Against a drum a disk's record carries its overlap area for cohesion alone: the
        // area law's spring stays on the depth there (as for the drum's other bodies).
        let area_spring = area_law
            && (c.area.is_none() || sides.wall().is_none_or(|w| cx.walls[w].drum().is_none()));
        let spring = SpringOn::of(&c, area_spring, &facts);
        let cohesion = if cx.cohesive {
            let (point, normal) = spring.point_normal(c.point, c.normal);
            Some(CohesionKinematics::of(&c, point, normal))
        } else {
            None
        };
        Some((c.state, c.point, c.normal, c.depth, spring, cohesion))
    }
}

/// The numbers about a slot's pair that decide what its spring acts on.
struct Facts<'a> {
    bodies: &'a Bodies,
    sides: Sides,
}

impl PairFacts for Facts<'_> {
    #[inline(always)]
    fn against_wall(&self) -> bool {
        self.sides.wall().is_some()
    }

    #[inline(always)]
    fn flat_pair(&self) -> bool {
        let b = self.bodies;
        self.sides.giving_body().is_some_and(|k| {
            b.shape[k].is_flat_sided() && b.shape[self.sides.receiver].is_flat_sided()
        })
    }

    #[inline(always)]
    fn face_length(&self) -> f64 {
        let (b, recv) = (self.bodies, self.sides.receiver);
        match self.sides.giving_body() {
            Some(k) => 0.5 * (b.shape[recv].face_length() + b.shape[k].face_length()),
            None => b.shape[recv].face_length(),
        }
    }

    #[inline(always)]
    fn lens(&self) -> DiskLens {
        let (b, recv) = (self.bodies, self.sides.receiver);
        let (far, inv_far) = self.sides.giving_body().map_or((f64::INFINITY, 0.0), |k| {
            (b.area_radius[k], b.inv_area_radius[k])
        });
        DiskLens::with_inverses(b.area_radius[recv], b.inv_area_radius[recv], far, inv_far)
    }
}

/// The laws a slot's contact takes.
pub(crate) trait LawSource: Copy {
    /// Every law of the step is linear with constant dashpots and nothing more
    /// ([`LinearDashpots`]): the copy is compiled with the law's kinds known, reads nothing the
    /// law does not need ([`Law::needs`]), keeps no further history and fills no extras.
    const LINEAR: bool;
    /// The law of the pair `sides` (`wall`: its wall) and the pair's m* where the law reads it
    /// (NaN otherwise).
    fn law(self, sides: Sides, cx: &PassContext) -> (Law, f64);
}

/// Laws all of [`LinearDashpots`]'s kind (one material: `[0]` body pairs, `[1 + w]` wall w;
/// `MATERIALS`, several: as [`PairTable::all`] lists them).
#[derive(Clone, Copy)]
struct Linear<'a, const MATERIALS: bool>(&'a [LinearDashpots]);

impl<const MATERIALS: bool> LawSource for Linear<'_, MATERIALS> {
    const LINEAR: bool = true;
    #[inline(always)]
    fn law(self, sides: Sides, cx: &PassContext) -> (Law, f64) {
        let at = if MATERIALS {
            cx.pair_index(sides)
        } else {
            sides.wall().map_or(0, |w| 1 + w)
        };
        (self.0[at].law(), f64::NAN)
    }
}

/// Laws resolved once for the step (`laws` not empty: indexed as [`Linear`] in a scene of one
/// material, else as [`PairTable::all`]) or at every contact (`laws` empty: several densities,
/// or a law that depends on the pair's mass).
#[derive(Clone, Copy)]
struct Resolved<'a> {
    laws: Option<&'a [Law]>,
    /// Several materials.
    materials: bool,
}

impl<'a> Resolved<'a> {
    fn new(laws: &'a [Law], pairs: &PairTable) -> Self {
        Resolved {
            laws: (!laws.is_empty()).then_some(laws),
            materials: pairs.count() > 1,
        }
    }
}

impl LawSource for Resolved<'_> {
    const LINEAR: bool = false;
    #[inline(always)]
    fn law(self, sides: Sides, cx: &PassContext) -> (Law, f64) {
        let m_eff = || 1.0 / kinematics::inv_mass(cx.bodies, sides); // T(13)
        match self.laws {
            Some(laws) => {
                let at = if self.materials {
                    cx.pair_index(sides)
                } else {
                    sides.wall().map_or(0, |w| 1 + w)
                };
                let law = laws[at];
                let m = if law.needs().m_eff { m_eff() } else { f64::NAN };
                (law, m)
            }
            None => {
                let m = m_eff();
                let rho = kinematics::density(cx.bodies, sides);
                (cx.pair(sides).resolve(rho, cx.g), m)
            }
        }
    }
}

/// The sides of `slot` ([`Sides::of_slot`]); `PAIR`: the caller knows the slot pairs two
/// bodies (not a wall), so that the copy compiled for body pairs has no wall branch left.
#[inline(always)]
fn sides_of_slot<const PAIR: bool>(slot: &Slot) -> Sides {
    debug_assert!(
        !PAIR || !slot.is_wall(),
        "a wall slot taken for a body pair"
    );
    if PAIR {
        Sides {
            receiver: slot.j as usize,
            giver: Partner::Body(slot.i as usize),
            image: None,
        }
    } else {
        slot.sides()
    }
}

/// [`contact_slot`] out of line (its own copy for each geometry, law source and `PAIR`).
#[allow(clippy::too_many_arguments)]
#[inline(never)]
fn contact_slot_apart<G: Geometry, L: LawSource, const PAIR: bool, const PERIODIC: bool>(
    slot: &mut Slot,
    to: SlotOut,
    geometry: G,
    laws: L,
    cx: &PassContext,
    p: &mut SlotPartial,
    loads: &mut [WallLoad],
) {
    contact_slot::<G, L, PAIR, PERIODIC>(slot, to, geometry, laws, cx, p, loads);
}

/// One slot's contact (see the module documentation): geometry, kinematics at the contact
/// point, the law and the history; an inactive slot drops its history (the shear spring, and
/// its further history values when the scene keeps them). `loads` (one per wall, or empty) receives the
/// sums of each wall's contacts.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn contact_slot<G: Geometry, L: LawSource, const PAIR: bool, const PERIODIC: bool>(
    slot: &mut Slot,
    to: SlotOut,
    geometry: G,
    laws: L,
    cx: &PassContext,
    p: &mut SlotPartial,
    loads: &mut [WallLoad],
) {
    // A linear law keeps no further history and fills no extras: constants in its copies.
    let SlotOut {
        data,
        extra,
        history: more,
    } = if L::LINEAR {
        SlotOut {
            history: None,
            extra: None,
            ..to
        }
    } else {
        to
    };
    let b = cx.bodies;
    let sides = cx.slot_sides::<PAIR, PERIODIC>(slot);
    let recv = sides.receiver;
    let (wall, giver) = (sides.wall(), sides.giving_body());
    let (state, geo_point, geo_normal, depth, spring, cohesion) = match geometry.find(sides, cx) {
        Some(l) if l.3 > 0.0 => l,
        // Separated, or touching without overlap: no force, no history.
        _ => {
            if slot.active {
                p.lost_history += slot.history_energy;
            }
            *slot = Slot::with_sub(slot.i, slot.j, slot.sub);
            if let Some(r) = more {
                r.fill(0.0);
            }
            *data = ContactData::default(); // zero forces: the gather adds them unconditionally
            if let Some(e) = extra {
                *e = ContactExtra::default();
            }
            return;
        }
    };
    match state {
        ContactState::Deep => p.deep += 1,
        ContactState::Contained => p.contained += 1,
        ContactState::Separated | ContactState::Touching | ContactState::Overlap => {}
    }
    let (point, n_) = spring.point_normal(geo_point, geo_normal);
    let t_ = Vec2::new(-n_.y, n_.x);
    let (law, m_eff) = laws.law(sides, cx);
    // What the law reads beyond the overlap and the velocities: nothing for a linear law.
    let needs = if L::LINEAR {
        Needs::default()
    } else {
        law.needs()
    };
    let kin = kinematics::of_contact(
        &Contact {
            bodies: b,
            walls: cx.walls,
            sides,
            point,
            normal: n_,
            depth,
            spring: &spring,
            cohesion,
        },
        m_eff,
        needs,
        cx.dt,
        |k| cx.touching.get(k).copied().unwrap_or(1),
    );
    let mut history = History::default();
    if slot.active {
        history.0[0] = slot.shear;
        if let Some(r) = more.as_deref() {
            history.0[1..1 + r.len()].copy_from_slice(r);
        }
    }
    debug_assert!(
        law.history_kept() <= 1 + more.as_deref().map_or(0, <[f64]>::len),
        "a contact whose law keeps more history than its slot has room for"
    );
    let cf = law.force(&kin, &mut history);
    let f = n_ * cf.normal + t_ * cf.tangential; // T(5): on the receiving body
    let f_ne = n_ * cf.normal_non_elastic + t_ * cf.tangential;
    p.contacts += 1;
    p.elastic += cf.elastic_energy;
    p.history_energy_change += cf.history_energy_change;
    // (A circle's inscribed radius is its radius, which a disk scene has at hand.)
    let inscribed = |k: usize| {
        if G::DISKS {
            b.bound[k]
        } else {
            b.shape[k].inscribed_radius()
        }
    };
    let scale = inscribed(recv).min(giver.map_or(f64::INFINITY, inscribed));
    if depth > p.max_depth_ratio * scale {
        p.max_depth_ratio = depth / scale; // divide only when the maximum grows
    }
    if PERIODIC
        && let Some(k) = giver
        && cx.cell.is_some_and(Cell::measures_stress)
    {
        // The cell's stress (Love–Weber) and its stiffness against a stretch of each side (only
        // an `"xy"` cell measures them: only there can a side move).
        let at = b.state[k].pose.position + sides.image.map_or(Vec2::zeros(), |i| i.offset);
        let l = b.state[recv].pose.position - at;
        p.stress[0] += f.x * l.x;
        p.stress[1] += f.x * l.y;
        p.stress[2] += f.y * l.x;
        p.stress[3] += f.y * l.y;
        let elastic = cf.normal - cf.normal_non_elastic;
        p.stiffness[0] += cf.kn * (n_.x * l.x) * (n_.x * l.x);
        p.stiffness[1] += cf.kn * (n_.y * l.y) * (n_.y * l.y);
        p.elastic_n[0] += elastic * n_.x * l.x;
        p.elastic_n[1] += elastic * n_.y * l.y;
        if let Some(image) = sides.image {
            // The relative velocity the law saw is the receiver's less the image's, which moves
            // at the giver's plus u: the bodies' power exceeds the contact's by f·u.
            p.image_power += f.dot(&image.velocity);
            p.image_power_ne += f_ne.dot(&image.velocity);
        }
    }
    if let Some(w) = wall
        && let Some(load) = loads.get_mut(w)
    {
        load.force += f;
        load.force_non_elastic += f_ne;
        // A turning boundary's moment about its pivot of the force and couple on the body.
        if cx.walls[w].turn.is_some() {
            let r = cx.walls[w].lever(point, n_);
            load.torque += r.perp(&f) + cf.couple;
            load.torque_non_elastic += r.perp(&f_ne) + cf.couple_non_elastic;
        }
        load.stiffness += cf.kn;
        load.contacts += 1;
    }
    *slot = Slot {
        i: slot.i,
        j: slot.j,
        sub: slot.sub,
        active: true,
        state,
        shear: history.0[0],
        history_energy: cf.history_energy,
    };
    if let Some(r) = more {
        r.copy_from_slice(&history.0[1..1 + r.len()]);
    }
    *data = ContactData {
        point,
        force: f,
        force_non_elastic: f_ne,
        couple: cf.couple,
        couple_non_elastic: cf.couple_non_elastic,
    };
    if let Some(e) = extra {
        *e = ContactExtra {
            normal: n_,
            depth,
            kn: cf.kn as f32,
            eta_n: cf.eta_n as f32,
            kt: cf.kt as f32,
            eta_t: cf.eta_t as f32,
            kr: cf.kr as f32,
            cr: cf.cr as f32,
        };
    }
}

/// A slot's pair computed ahead for the chunk: `Some` for two circles or a circle and a wall
/// ([`Disks`]' geometry: the bodies' radii are their bounding radii) and for a clump's member
/// pair ([`members::lean_contact`]); `None` for the other pair kinds.
#[inline(always)]
fn lean_of<const PERIODIC: bool>(
    slot: &Slot,
    cx: &PassContext,
) -> Option<Option<narrow_phase::Contact>> {
    let sides = cx.slot_sides::<false, PERIODIC>(slot);
    if slot.sub != 0 {
        return Some(members::lean_contact(
            cx.bodies,
            cx.walls,
            slot,
            sides,
            cx.lean_request(),
        ));
    }
    let b = cx.bodies;
    let circles = b.is_circle[sides.receiver] && sides.giving_body().is_none_or(|k| b.is_circle[k]);
    circles.then(|| Disks.contact(sides, cx, cx.lean_request()))
}

/// Asks the processor to fetch the state of slot `s`'s second body (`j`, not a wall) and its
/// entry of `other` (the shapes; a disk scene: the radii, all its pairs read) into the cache:
/// the first body's follow the slots' order, which the hardware prefetcher tracks, but `j`
/// jumps between neighbours in the row and rows above.
#[inline(always)]
fn prefetch_partner<T>(b: &Bodies, s: &Slot, other: &[T]) {
    let j = s.j as usize;
    if let (Some(state), Some(o)) = (b.state.get(j), other.get(j)) {
        prefetch(state);
        prefetch(o);
    }
}

/// A hint to load the cache line holding `r` (nothing on other targets than x86-64).
#[inline(always)]
fn prefetch<T>(r: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing into the program and cannot fault, whatever the address;
    // `r` is a valid reference anyway. (Only `unsafe` because of its `target_feature`, SSE,
    // which every x86-64 has.)
    unsafe {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        _mm_prefetch::<_MM_HINT_T0>((r as *const T).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = r;
}

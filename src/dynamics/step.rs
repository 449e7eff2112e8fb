//! The step function: velocity Verlet (kick–drift–kick) with contact forces from the chord
//! geometry and the contact law.
//!
//! # Stages of one step, and the time level of every quantity
//! 1. **Kick**: `v_{n+½} = v_n + ½Δt F_n/m`, `ω_{n+½} = ω_n + ½Δt M_n/I` (forces of the last
//!    evaluation, at time level n).
//! 2. **Drift**: `x_{n+1} = x_n + Δt v_{n+½}`, `θ_{n+1} = θ_n + Δt ω_{n+½}`; the increments
//!    `|Δx|, |Δy|, |Δθ|` averaged over bodies are P's quiescence measure. Non-finite state stops
//!    here with the step and the body. Moving walls drift to time level n+1 too
//!    ([`super::boundary`]).
//! 3. **Forces** `F_{n+1}, M_{n+1}` from the positions `x_{n+1}, θ_{n+1}` and, for the dashpots,
//!    the shear displacement and the rolling spring, the velocities `v_{n+½}, ω_{n+½}` (the
//!    latest available; as in LAMMPS and LIGGGHTS) and the walls' drift velocities: neighbour
//!    list → narrow phase → kinematics at the contact ([`super::kinematics`]) → contact law →
//!    `F`, `r × F` and the contact's couple on each body (T3, T4, T22; `r` from the centroid to
//!    the contact point, so the normal force has a moment on non-circular bodies), plus gravity
//!    (T3); each wall's load is summed.
//! 4. **Kick**: `v_{n+1} = v_{n+½} + ½Δt F_{n+1}/m`, `ω_{n+1} = ω_{n+½} + ½Δt M_{n+1}/I` (T1).
//! 5. **Account**: the dissipated energy and the walls' work over the step; the servo walls'
//!    velocities for the next drift, from their loads.
//!
//! For an undamped linear oscillator this scheme is stable for `ωΔt < 2`; with a dashpot of
//! damping ratio ζ evaluated at the half step, for `ωΔt < 2(√(1+ζ²) − ζ)`
//! (see [`super::timestep`]).
//!
//! # Many bodies, many threads
//! The pairs come from a neighbour list ([`super::contacts`]) rebuilt only when bodies have
//! moved far enough to matter. Each step is three parallel passes (rayon), each over
//! fixed-size chunks of bodies or slots: kick and drift (bodies); every slot's contact (slots,
//! each written by one thread only); gathering each body's forces from its own slots, in key
//! order, then the second kick and the dissipated power (bodies). Every sum (increments,
//! energies, counters) is formed per chunk and then over the chunks in order. Nothing depends
//! on how chunks are scheduled, so a run gives the same bits on one thread or many. Every
//! slot's geometry comes from the narrow phase's one dispatcher
//! ([`crate::narrow_phase::contact_sides`], the sides borrowed), asked for no chord and for the
//! overlap area only under the area law — circle pairs through its lean path
//! ([`crate::narrow_phase::overlap_lean`]); each slot keeps the pair's opaque
//! [`PairCache`] beside it (conic pairs start from the last step's crossings or separating
//! axis, see [`crate::narrow_phase::ellipse_ellipse`]) when some pair of the scene keeps
//! anything there. Circles skip their sine and cosine.

use super::account::{Diagnostics, Energies};
use super::body::Bodies;
use super::boundary::WallSpec;
use super::boundary::{Motion, WallLoad, servo_velocity};
use super::broad_phase::Grid;
use super::contacts::{
    Adjacent, ContactData, ContactExtra, ContactList, Slot, WALL_BASE, reserve_for,
};
use super::kinematics;
use super::partner::{Partner, Sides};
use super::restart::{Kept, RestartState};
use crate::contact_law::{
    AreaKinematics, ContactSpec, EquivalentOverlap, History, Kinematics, Law, LinearDashpots,
    NormalForce, RollingKinematics, RollingModel,
};
use crate::geometry::overlap_area::DiskLens;
use crate::geometry::{Pose, Shape, Vec2};
use crate::narrow_phase::{
    ContactState, LeanContact, OverlapArea, PairCache, Request, Side, conic_lean, contact_sides,
    overlap_lean,
};
use crate::narrow_phase::{circle_circle::overlap_circle_circle, circle_wall::overlap_wall_circle};
use rayon::prelude::*;
use std::fmt;

/// Bodies per parallel chunk, and neighbour-list slots per parallel chunk. Fixed sizes: every
/// sum is formed chunk by chunk and then over the chunks in order, so that results are the same
/// bit for bit whatever the number of threads.
pub(crate) const BODY_CHUNK: usize = 512;
pub(crate) const SLOT_CHUNK: usize = 512;

/// The skin of the neighbour list as a fraction of the largest bounding radius: larger means
/// fewer rebuilds and more candidate pairs to test each step.
pub const SKIN_FRACTION: f64 = 0.1;

/// A non-finite state: the step and the body where it was found.
#[derive(Clone, Debug, PartialEq)]
pub struct Blowup {
    pub step: u64,
    pub time: f64,
    pub body: usize,
    pub what: &'static str,
}

impl fmt::Display for Blowup {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "non-finite {} of body {} at step {} (t = {}): the simulation blew up (is dt far above dt_critical?)",
            self.what, self.body, self.step, self.time
        )
    }
}

impl std::error::Error for Blowup {}

/// What one step measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepReport {
    /// Mean over bodies of |Δx|, |Δy|, |Δθ| during the step (P's quiescence measure).
    pub increments: [f64; 3],
    /// Number of contacts after the step.
    pub contacts: usize,
}

/// Per-chunk results of the body passes.
#[derive(Clone, Copy, Debug, Default)]
struct BodyPartial {
    /// Σ|Δx|, Σ|Δy|, Σ|Δθ| (drift).
    inc: [f64; 3],
    /// The squares of the two largest displacements since the neighbour list was built
    /// (drift).
    disp: [f64; 2],
    /// First body with a non-finite state.
    bad: Option<usize>,
    /// Kinetic and potential energy, and the power of the contacts' non-elastic forces
    /// `F_ne·v + M_ne ω` at the new velocities (second kick).
    non_elastic_power: f64,
    kinetic: f64,
    potential: f64,
}

/// Per-chunk results of the slot passes.
#[derive(Clone, Copy, Debug, Default)]
struct SlotPartial {
    contacts: usize,
    elastic: f64,
    /// History springs' energy of contacts that opened this step.
    lost_history: f64,
    deep: u64,
    contained: u64,
    max_depth_ratio: f64,
    /// Σ of the change of the history springs' energy (shear and rolling).
    history_energy_change: f64,
}

/// What a step reads and writes of the world, borrowed from it by [`World::step`]: the stepper
/// never names the world, which owns it (no import cycle between the two).
pub(crate) struct Parts<'a> {
    pub bodies: &'a mut Bodies,
    pub walls: &'a mut [WallSpec],
    pub contacts: &'a mut ContactList,
    pub energies: &'a mut Energies,
    pub diagnostics: &'a mut Diagnostics,
    pub gravity: Vec2,
    pub spec: &'a ContactSpec,
    pub dt: f64,
    pub step: &'a mut u64,
    pub time: &'a mut f64,
    pub last_increments: &'a mut [f64; 3],
}

/// The stepper: the scratch the step reuses from step to step (the broad phase's grid and pair
/// list, the per-chunk partial sums of the parallel passes, the laws resolved once per step).
/// Nothing in it is state: a world rebuilt from its bodies and contacts steps the same.
#[derive(Clone, Debug, Default)]
pub struct Stepper {
    grid: Grid,
    /// Scratch of the neighbour-list build (the grid's body pairs).
    pair_scratch: Vec<(u32, u32)>,
    /// Per-chunk partial results of the parallel passes.
    body_partials: Vec<BodyPartial>,
    slot_partials: Vec<SlotPartial>,
    /// Per chunk of slots, per wall: the wall's contacts' sums.
    wall_partials: Vec<WallLoad>,
    /// The density of every body when they all have the same (checked at each list build).
    uniform_density: Option<f64>,
    /// Laws resolved once per step when every pair of a kind has the same.
    law_cache: Vec<Law>,
    /// The same laws' numbers when every one is linear with constant dashpots and no rolling
    /// part ([`LinearDashpots`]; empty otherwise): the slots then take the copies of the update
    /// compiled for such laws.
    linear_cache: Vec<LinearDashpots>,
    /// Some body is a circle (checked at each list build): some pair may take the narrow
    /// phase's lean path.
    circles: bool,
    /// Some body is a clump (checked at each list build): the list holds member-pair slots.
    clumps: bool,
    /// Every body is a circle (checked at each list build): with linear laws the slot pass
    /// takes [`update_disk_slot`].
    disks: bool,
}

impl Stepper {
    /// Heap bytes of the grid, and of the build's and the passes' scratch.
    pub(crate) fn heap_bytes(&self) -> (usize, usize) {
        let held = |cap: usize, size: usize| cap * size;
        (
            self.grid.heap_bytes(),
            held(self.pair_scratch.capacity(), 8)
                + held(
                    self.wall_partials.capacity(),
                    std::mem::size_of::<WallLoad>(),
                ),
        )
    }
}

/// Keeps the two largest of the values pushed.
#[inline]
fn top_two(t: &mut [f64; 2], d: f64) {
    if d > t[0] {
        t[1] = t[0];
        t[0] = d;
    } else if d > t[1] {
        t[1] = d;
    }
}

impl Stepper {
    /// Advances the world by one time step (see the module documentation for the stages).
    pub(crate) fn step(&mut self, wd: &mut Parts) -> Result<StepReport, Blowup> {
        let dt = wd.dt;
        let h = 0.5 * dt;
        let n = wd.bodies.len();
        let next_step = *wd.step + 1;
        let next_time = next_step as f64 * dt;
        self.size_partials(wd);
        // 1.–2. Kick to the half step and drift, chunk by chunk.
        {
            let Bodies {
                is_circle,
                state,
                force,
                torque,
                inv_mass,
                inv_inertia,
                ..
            } = &mut *wd.bodies;
            let built_at = &wd.contacts.built_at;
            let fresh = built_at.len() == n;
            state
                .par_chunks_mut(BODY_CHUNK)
                .zip(self.body_partials.par_iter_mut())
                .enumerate()
                .for_each(|(c, (state, part))| {
                    let base = c * BODY_CHUNK;
                    // The chunk's rows of the other arrays, cut to its length: indexed by `k`
                    // below with no bounds check left.
                    let rows = base..base + state.len();
                    let (force, torque) = (&force[rows.clone()], &torque[rows.clone()]);
                    let (inv_mass, inv_inertia) =
                        (&inv_mass[rows.clone()], &inv_inertia[rows.clone()]);
                    let is_circle = &is_circle[rows.clone()];
                    let built_at = if fresh { &built_at[rows] } else { &[][..] };
                    let mut p = BodyPartial::default();
                    for (k, s) in state.iter_mut().enumerate() {
                        let g = base + k;
                        s.vel += force[k] * (h * inv_mass[k]);
                        s.omega += torque[k] * h * inv_inertia[k];
                        let d = s.vel * dt;
                        let dth = s.omega * dt;
                        let pos = s.pose.position + d;
                        let angle = s.pose.angle() + dth;
                        if !(pos.x.is_finite() && pos.y.is_finite() && angle.is_finite()) {
                            p.bad.get_or_insert(g);
                            continue;
                        }
                        s.pose = if is_circle[k] {
                            // A circle's orientation enters no contact: skip its sine and cosine.
                            s.pose.moved(pos, angle)
                        } else {
                            Pose::new(pos, angle)
                        };
                        p.inc[0] += d.x.abs();
                        p.inc[1] += d.y.abs();
                        p.inc[2] += dth.abs();
                        if fresh {
                            // Squared: the same two largest, one square root per chunk
                            // instead of one per body (taken when the chunk is summed).
                            top_two(&mut p.disp, (pos - built_at[k]).norm_squared());
                        }
                    }
                    *part = p;
                });
        }
        let blowup = |body, what| Blowup {
            step: next_step,
            time: next_time,
            body,
            what,
        };
        let mut inc = [0.0f64; 3];
        let mut disp = [0.0f64; 2];
        for p in &self.body_partials {
            if let Some(body) = p.bad {
                return Err(blowup(body, "position"));
            }
            for (total, part) in inc.iter_mut().zip(p.inc) {
                *total += part;
            }
            top_two(&mut disp, p.disp[0].sqrt());
            top_two(&mut disp, p.disp[1].sqrt());
        }
        if n > 0 {
            for v in &mut inc {
                *v /= n as f64;
            }
        }
        *wd.last_increments = inc;
        // Moving walls drift with the bodies; a wall's normal displacement since the list was
        // built counts like a body's.
        let mut wall_disp = 0.0f64;
        for (k, ws) in wd.walls.iter_mut().enumerate() {
            if ws.moves() {
                ws.drift(next_time, dt);
                if let Some(at) = wd.contacts.wall_built_at.get(k) {
                    wall_disp = wall_disp.max((ws.wall.point - at).dot(&ws.wall.normal).abs());
                }
            }
        }
        // 3. Forces at the new positions (the neighbour list first, if a pair outside it could
        // now touch: two bodies approach by at most the sum of their displacements, a body and
        // a wall by the sum of theirs).
        if wd.contacts.built_at.len() != n || disp[0] + disp[1].max(wall_disp) > wd.contacts.skin {
            self.rebuild_neighbours(wd);
        }
        let slots = self.compute_slots(wd, dt);
        // 4. Kick to the full step, gathering each body's forces.
        let bodies_sum = self.gather_forces(wd, Some(h));
        if let Some(body) = bodies_sum.bad {
            return Err(blowup(body, "velocity"));
        }
        // Energy the contacts took out during this step. Verlet applies the forces of time level
        // n+1 over the interval centred on it, so their work is taken with the velocities at n+1
        // (after the second kick): the non-elastic forces' power, summed body by body
        // (Σ_c f·v_rel = Σ_k F_k·v_k + M_k ω_k − Σ_walls F_w·v_w), less the change of the
        // history springs' energy. A moving wall does the work F_w·v_w (see `boundary`).
        if wd.walls.iter().any(WallSpec::moves) {
            let (mut power, mut power_ne) = (0.0, 0.0);
            for ws in wd.walls.iter() {
                power += ws.load.force.dot(&ws.velocity);
                power_ne += ws.load.force_non_elastic.dot(&ws.velocity);
            }
            wd.energies.dissipated -=
                (bodies_sum.non_elastic_power - power_ne) * dt + slots.history_energy_change;
            wd.energies.boundary_work += power * dt;
            Self::update_servos(wd);
        } else {
            wd.energies.dissipated -=
                bodies_sum.non_elastic_power * dt + slots.history_energy_change;
        }
        *wd.step = next_step;
        *wd.time = next_time;
        wd.energies.kinetic = bodies_sum.kinetic;
        wd.energies.potential = bodies_sum.potential;
        Ok(StepReport {
            increments: inc,
            contacts: slots.contacts,
        })
    }

    /// Evaluates the forces of the current configuration without advancing (used at t = 0).
    pub(crate) fn evaluate_forces(&mut self, wd: &mut Parts) {
        self.size_partials(wd);
        self.rebuild_neighbours(wd);
        self.compute_slots(wd, 0.0);
        self.gather_forces(wd, None);
    }

    /// Sets each servo wall's velocity for the next step from the load of the last force
    /// evaluation (see [`super::boundary`]).
    pub(crate) fn update_servos(wd: &mut Parts) {
        for k in 0..wd.walls.len() {
            if let Motion::Servo(s) = wd.walls[k].motion {
                wd.walls[k].velocity = servo_velocity(&wd.walls[k], &s, wd.walls, wd.dt);
            }
        }
    }

    /// One partial result per chunk of bodies and of slots (and per wall for each chunk of
    /// slots: at least one, so that every chunk has its slice).
    fn size_partials(&mut self, wd: &Parts) {
        let nb = wd.bodies.len().div_ceil(BODY_CHUNK);
        if self.body_partials.len() != nb {
            self.body_partials.resize(nb, BodyPartial::default());
        }
        let ns = wd.contacts.slots.len().div_ceil(SLOT_CHUNK);
        if self.slot_partials.len() != ns {
            self.slot_partials.resize(ns, SlotPartial::default());
        }
        let nw = ns * wd.walls.len().max(1);
        if self.wall_partials.len() != nw {
            self.wall_partials.resize(nw, WallLoad::default());
        }
    }

    /// The facts of the scene that the slot pass relies on, noted whenever the neighbour list
    /// is made (built or restored from a restart): whether every body has one density, and
    /// whether any body is a circle (then circle pairs take the narrow phase's lean path —
    /// which pairs take it decides the last bits, so a restored list must note it too).
    fn note_scene(&mut self, wd: &Parts) {
        let d0 = wd.bodies.density.first().copied();
        self.uniform_density = d0.filter(|&d| wd.bodies.density.iter().all(|&x| x == d));
        self.circles = wd.bodies.is_circle.iter().any(|&c| c);
        self.disks = wd.bodies.is_circle.iter().all(|&c| c);
        // A clump's contacts are its members', circles: they take the lean path too.
        self.clumps = wd.bodies.shape.iter().any(|s| s.clump().is_some());
        self.circles |= self.clumps;
    }

    /// Rebuilds the neighbour list from the current positions (body pairs from the grid, then
    /// each body's walls after its body partners: key order), carrying histories over.
    pub(crate) fn rebuild_neighbours(&mut self, wd: &mut Parts) {
        let n = wd.bodies.len();
        let max_bound = wd.bodies.bound.iter().copied().fold(0.0f64, f64::max);
        let skin = SKIN_FRACTION * max_bound;
        self.note_scene(wd);
        let list = &mut *wd.contacts;
        list.skin = skin;
        self.grid.pairs(wd.bodies, skin, &mut self.pair_scratch);
        list.keys.clear();
        reserve_for(&mut list.keys, self.pair_scratch.len() + n);
        let mut next = 0;
        for i in 0..n {
            while next < self.pair_scratch.len() && self.pair_scratch[next].0 as usize == i {
                let (a, b) = self.pair_scratch[next];
                if self.clumps {
                    clump_keys(wd.bodies, a, b, skin, &mut list.keys);
                } else {
                    list.keys.push((a, b, 0));
                }
                next += 1;
            }
            let (x, r) = (wd.bodies.state[i].pose.position, wd.bodies.bound[i]);
            for (w, ws) in wd.walls.iter().enumerate() {
                let wj = super::contacts::WALL_BASE + w as u32;
                let d = ws.wall.signed_distance(x);
                if d <= r + skin {
                    match wd.bodies.shape[i].clump() {
                        None => list.keys.push((i as u32, wj, 0)),
                        // The members that can reach the wall however the clump turns.
                        Some(c) => list.keys.extend((0..c.len()).filter_map(|k| {
                            let (ck, rk) = c.member(k);
                            (d <= ck.norm() + rk + skin).then(|| (i as u32, wj, Slot::sub_of(k, 0)))
                        })),
                    }
                }
            }
        }
        let Kept { cached, rolling } = kept(&wd.bodies.shape, wd.spec, wd.walls);
        let lost = list.rebuild_from_keys(n, cached, rolling);
        wd.energies.dissipated += lost;
        list.built_at.clear();
        reserve_for(&mut list.built_at, n);
        list.built_at
            .extend(wd.bodies.state.iter().map(|s| s.pose.position));
        list.wall_built_at.clear();
        list.wall_built_at
            .extend(wd.walls.iter().map(|w| w.wall.point));
        self.size_partials(wd);
    }

    /// Restores the neighbour list of a restart: its slots with their histories, pair caches
    /// and contacts, what it was built from and its number of builds (the state checked by
    /// [`RestartState::check`]).
    pub(crate) fn restore_neighbours(&mut self, wd: &mut Parts, saved: &RestartState) {
        let n = wd.bodies.len();
        let max_bound = wd.bodies.bound.iter().copied().fold(0.0f64, f64::max);
        self.note_scene(wd);
        let Kept { cached, rolling } = kept(&wd.bodies.shape, wd.spec, wd.walls);
        let list = &mut *wd.contacts;
        *list = ContactList::default();
        list.skin = SKIN_FRACTION * max_bound;
        list.keys.extend(saved.slots.iter().map(|s| s.slot.key()));
        list.rebuild_from_keys(n, cached, rolling);
        for (k, s) in saved.slots.iter().enumerate() {
            list.slots[k] = s.slot;
            list.data[k] = s.data;
            if cached {
                list.cache[k] = s.cache;
            }
            if rolling {
                list.rolling[k] = s.rolling;
            }
        }
        list.built_at.extend_from_slice(&saved.built_at);
        list.wall_built_at.extend_from_slice(&saved.wall_built_at);
        list.builds = saved.builds;
        self.size_partials(wd);
    }

    /// Every slot's contact for the current positions and velocities, in parallel; `dt` is the
    /// step just drifted over (0 at the start), over which the shear displacement is integrated
    /// (T16). Adds the shear energy of contacts that opened to the dissipated energy and sets the
    /// elastic energy and the diagnostics; returns the sums.
    fn compute_slots(&mut self, wd: &mut Parts, dt: f64) -> SlotPartial {
        let g = wd.gravity.norm();
        self.resolve_uniform_laws(wd, g);
        let ContactList {
            slots,
            data,
            cache,
            rolling,
            adjacency_start,
            ..
        } = &mut *wd.contacts;
        let cx = SlotContext {
            bodies: &*wd.bodies,
            walls: &wd.walls[..],
            spec: wd.spec,
            laws: if self.law_cache.is_empty() {
                None
            } else {
                Some(&self.law_cache[..])
            },
            g,
            dt,
            adjacency_start,
        };
        let nw = wd.walls.len().max(1);
        let circles = self.circles;
        let linear = &self.linear_cache[..];
        let disks = self.disks && !linear.is_empty();
        let chunks = slots
            .par_chunks_mut(SLOT_CHUNK)
            .zip(data.par_chunks_mut(SLOT_CHUNK))
            .zip(self.slot_partials.par_iter_mut())
            .zip(self.wall_partials.par_chunks_mut(nw));
        // One chunk of slots, with its pair caches and rolling springs when the scene keeps them.
        let run = |slots: &mut [Slot],
                   data: &mut [ContactData],
                   part: &mut SlotPartial,
                   loads: &mut [WallLoad],
                   mut cache: Option<&mut [PairCache]>,
                   mut rolling: Option<&mut [f64]>| {
            let mut p = SlotPartial::default();
            loads.fill(WallLoad::default());
            // Disk scenes under linear laws: one loop (see [`update_disk_slot`]).
            if disks {
                // The body pairs' law (the first) held here, where it stays in registers,
                // rather than read from the scene's list at every slot.
                let pair_law = [linear[0]];
                let data = &mut data[..slots.len()]; // (no bounds check on `data[k]`)
                for k in 0..slots.len() {
                    if let Some(ahead) = slots.get(k + PREFETCH_AHEAD) {
                        prefetch_partner(cx.bodies, ahead, &cx.bodies.bound);
                    }
                    let (slot, data) = (&mut slots[k], &mut data[k]);
                    // Body pairs in a copy compiled for them (no wall branch left).
                    if slot.j < WALL_BASE {
                        update_disk_slot::<true>(slot, data, &cx, &mut p, loads, &pair_law);
                    } else {
                        update_disk_wall_slot(slot, data, &cx, &mut p, loads, linear);
                    }
                }
                *part = p;
                return;
            }
            // With circles in the scene, the circle pairs' geometry first, for the whole chunk:
            // a short loop whose square roots and divisions overlap from slot to slot (inside
            // the long per-slot pass each waited for its own; 10⁴ disks: 8 % faster). The same
            // kernels on the same inputs: the same bits. Without circles no pair is lean.
            // (Filled in place: returned from a closure, the 28 KB array was copied.)
            let mut lean = [None; SLOT_CHUNK];
            if circles {
                for (k, (l, slot)) in lean.iter_mut().zip(slots.iter()).enumerate() {
                    if let Some(ahead) = slots.get(k + PREFETCH_AHEAD) {
                        prefetch_partner(cx.bodies, ahead, &cx.bodies.shape);
                    }
                    *l = lean_of(slot, &cx);
                }
            }
            for (k, (slot, data)) in slots.iter_mut().zip(data).enumerate() {
                let r = rolling.as_deref_mut().map(|r| &mut r[k]);
                match lean[k] {
                    // A linear law has no rolling spring: `r` is `None`.
                    Some(l) if !linear.is_empty() => {
                        update_lean_slot::<true>(slot, data, None, &cx, &mut p, loads, l, linear)
                    }
                    Some(l) => update_lean_slot::<false>(slot, data, r, &cx, &mut p, loads, l, &[]),
                    None => {
                        let w = cache.as_deref_mut().map(|c| &mut c[k]);
                        if linear.is_empty() {
                            update_slot::<false, false>(
                                slot,
                                data,
                                None,
                                w,
                                r,
                                &cx,
                                &mut p,
                                loads,
                                None,
                                &[],
                            );
                        } else {
                            // A linear law has no rolling spring; body pairs in a copy
                            // compiled for them (no wall branch left).
                            if slot.j < WALL_BASE {
                                update_slot::<true, true>(
                                    slot, data, None, w, None, &cx, &mut p, loads, None, linear,
                                );
                            } else {
                                update_slot::<true, false>(
                                    slot, data, None, w, None, &cx, &mut p, loads, None, linear,
                                );
                            }
                        }
                    }
                }
            }
            *part = p;
        };
        match (cache.is_empty(), rolling.is_empty()) {
            (true, true) => chunks.for_each(|(((slots, data), part), loads)| {
                run(slots, data, part, loads, None, None)
            }),
            (false, true) => chunks.zip(cache.par_chunks_mut(SLOT_CHUNK)).for_each(
                |((((slots, data), part), loads), cache)| {
                    run(slots, data, part, loads, Some(cache), None)
                },
            ),
            (true, false) => chunks.zip(rolling.par_chunks_mut(SLOT_CHUNK)).for_each(
                |((((slots, data), part), loads), rolling)| {
                    run(slots, data, part, loads, None, Some(rolling))
                },
            ),
            (false, false) => chunks
                .zip(cache.par_chunks_mut(SLOT_CHUNK))
                .zip(rolling.par_chunks_mut(SLOT_CHUNK))
                .for_each(|(((((slots, data), part), loads), cache), rolling)| {
                    run(slots, data, part, loads, Some(cache), Some(rolling))
                }),
        }
        let mut sum = SlotPartial::default();
        for p in &self.slot_partials {
            sum.contacts += p.contacts;
            sum.elastic += p.elastic;
            sum.lost_history += p.lost_history;
            sum.deep += p.deep;
            sum.contained += p.contained;
            sum.max_depth_ratio = sum.max_depth_ratio.max(p.max_depth_ratio);
            sum.history_energy_change += p.history_energy_change;
        }
        // Each wall's load: its contacts' sums, chunk by chunk in order.
        for (w, ws) in wd.walls.iter_mut().enumerate() {
            let mut load = WallLoad::default();
            for c in self.wall_partials.chunks(nw) {
                load.add(&c[w]);
            }
            ws.load = load;
        }
        // A contact that opened took its history springs' energy with it.
        wd.energies.dissipated += sum.lost_history;
        wd.energies.elastic = sum.elastic;
        wd.diagnostics.deep_contacts += sum.deep;
        wd.diagnostics.contained_contacts += sum.contained;
        wd.diagnostics.max_depth_ratio = wd.diagnostics.max_depth_ratio.max(sum.max_depth_ratio);
        sum
    }

    /// Fills each active slot's [`ContactExtra`] (depth, stiffness, damping) for the current
    /// state. The step does not store them (it would stream them to memory every step for a
    /// report made every output interval): this evaluates every slot again on a copy — its
    /// history untouched, no time elapsing (Δt = 0) — and keeps only the extras.
    pub(crate) fn refresh_contact_extras(&mut self, wd: &mut Parts) {
        let g = wd.gravity.norm();
        self.resolve_uniform_laws(wd, g);
        let ContactList {
            slots,
            extra,
            cache,
            rolling,
            adjacency_start,
            ..
        } = &mut *wd.contacts;
        let cx = SlotContext {
            bodies: &*wd.bodies,
            walls: &wd.walls[..],
            spec: wd.spec,
            laws: if self.law_cache.is_empty() {
                None
            } else {
                Some(&self.law_cache[..])
            },
            g,
            dt: 0.0,
            adjacency_start,
        };
        let (cache, rolling) = (&cache[..], &rolling[..]);
        slots
            .par_chunks(SLOT_CHUNK)
            .zip(extra.par_chunks_mut(SLOT_CHUNK))
            .enumerate()
            .for_each(|(c, (slots, extra))| {
                let mut p = SlotPartial::default();
                for (k, (slot, extra)) in slots.iter().zip(extra).enumerate() {
                    let mut copy = (*slot, ContactData::default());
                    let mut cache_copy = cache.get(c * SLOT_CHUNK + k).copied();
                    let mut rolling_copy = rolling.get(c * SLOT_CHUNK + k).copied();
                    if slot.active {
                        update_slot::<false, false>(
                            &mut copy.0,
                            &mut copy.1,
                            Some(extra),
                            cache_copy.as_mut(),
                            rolling_copy.as_mut(),
                            &cx,
                            &mut p,
                            &mut [],
                            lean_of(slot, &cx),
                            &[],
                        );
                    } else {
                        *extra = ContactExtra::default();
                    }
                }
            });
    }

    /// When every pair of a kind has the same law — one density for all bodies, and no law that
    /// depends on the pair's mass (restitution-tuned dashpots) — resolves the body–body law and
    /// each wall's once (`law_cache[0]`, `law_cache[1 + w]`) instead of at every contact.
    fn resolve_uniform_laws(&mut self, wd: &Parts, g: f64) {
        self.law_cache.clear();
        self.linear_cache.clear();
        let Some(rho) = self.uniform_density else {
            return;
        };
        if wd.spec.depends_on_mass() || wd.walls.iter().any(|w| w.spec.depends_on_mass()) {
            return;
        }
        self.law_cache
            .push(wd.spec.resolve(wd.spec, rho, g, f64::NAN));
        for w in wd.walls.iter() {
            self.law_cache
                .push(w.spec.resolve(wd.spec, rho, g, f64::NAN));
        }
        for law in &self.law_cache {
            match LinearDashpots::of(law) {
                Some(l) => self.linear_cache.push(l),
                None => {
                    self.linear_cache.clear();
                    break;
                }
            }
        }
    }

    /// Each body's force and moment: gravity (T3) and its contacts' (T4, T22), gathered in key
    /// order. With `kick = Some(h)`, then `v += h F/m`, `ω += h M/I` (the second half-kick) and
    /// the sums of the body pass (net force and moment, energies, first non-finite body).
    fn gather_forces(&mut self, wd: &mut Parts, kick: Option<f64>) -> BodyPartial {
        let gravity = wd.gravity;
        // Disks under linear laws have no contact couples (no rolling part; a disk's area
        // potential is its depth spring).
        let couples = !self.disks || self.linear_cache.is_empty();
        let list = &*wd.contacts;
        let (data, start, adjacency) = (
            &list.data[..],
            &list.adjacency_start[..],
            &list.adjacency[..],
        );
        let Bodies {
            state,
            force,
            torque,
            mass,
            inertia,
            inv_mass,
            inv_inertia,
            ..
        } = &mut *wd.bodies;
        force
            .par_chunks_mut(BODY_CHUNK)
            .zip(torque.par_chunks_mut(BODY_CHUNK))
            .zip(state.par_chunks_mut(BODY_CHUNK))
            .zip(self.body_partials.par_iter_mut())
            .enumerate()
            .for_each(|(c, (((force, torque), state), part))| {
                let base = c * BODY_CHUNK;
                // The chunk's rows of the other arrays, cut to its length (and its slot ranges'
                // bounds, one more): indexed by `k` below with no bounds check left.
                let n = state.len();
                let rows = base..base + n;
                let (force, torque) = (&mut force[..n], &mut torque[..n]);
                let (mass, inertia) = (&mass[rows.clone()], &inertia[rows.clone()]);
                let (inv_mass, inv_inertia) = (&inv_mass[rows.clone()], &inv_inertia[rows]);
                let start = &start[base..base + n + 1];
                let mut p = BodyPartial::default();
                for (k, s) in state.iter_mut().enumerate() {
                    let g = base + k;
                    let x = s.pose.position;
                    let adj = &adjacency[start[k] as usize..start[k + 1] as usize];
                    let f0 = gravity * mass[k]; // T(3): body force
                    let (f, m, f_ne, m_ne) = if couples {
                        sum_contacts::<true>(adj, data, x, f0)
                    } else {
                        sum_contacts::<false>(adj, data, x, f0)
                    };
                    force[k] = f;
                    torque[k] = m;
                    if let Some(h) = kick {
                        s.vel += f * (h * inv_mass[k]);
                        s.omega += m * h * inv_inertia[k];
                        if !(s.vel.x.is_finite() && s.vel.y.is_finite() && s.omega.is_finite()) {
                            p.bad.get_or_insert(g);
                        }
                        p.non_elastic_power += f_ne.dot(&s.vel) + m_ne * s.omega;
                        p.kinetic += 0.5 * mass[k] * s.vel.norm_squared()
                            + 0.5 * inertia[k] * s.omega * s.omega;
                        p.potential -= mass[k] * gravity.dot(&x);
                    }
                }
                *part = p;
            });
        let mut sum = BodyPartial::default();
        for p in &self.body_partials {
            if sum.bad.is_none() {
                sum.bad = p.bad;
            }
            sum.kinetic += p.kinetic;
            sum.potential += p.potential;
            sum.non_elastic_power += p.non_elastic_power;
        }
        sum
    }
}

/// One body's contact sums from its adjacency `adj` (its slots, in key order, with the sign of
/// each slot's force on it), its centroid `x` and its body force `f0`: the force `f0 + Σ F`
/// (T4), the moment `Σ r × F` (T22, `r` from the centroid to the contact point) plus the
/// contacts' couples, and the same two sums of the forces' non-elastic parts. `COUPLES`
/// false leaves the couples out (a scene whose contacts have none): adding their ±0 would
/// change no bit, since a sum that starts at +0 is never −0.
#[inline(always)]
fn sum_contacts<const COUPLES: bool>(
    adj: &[Adjacent],
    data: &[ContactData],
    x: Vec2,
    f0: Vec2,
) -> (Vec2, f64, Vec2, f64) {
    let (mut f, mut m) = (f0, 0.0);
    let (mut f_ne, mut m_ne) = (Vec2::zeros(), 0.0);
    // An inactive slot's data hold zero forces: no test needed.
    for a in adj {
        let d = &data[a.slot()];
        let (sign, r) = (a.sign(), d.point - x);
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

/// What a scene keeps beside its slots: pair caches where some pair keeps something in them
/// (conic pairs: warm starts), rolling springs where a contact law has one (EPSD).
pub(crate) fn kept(
    shapes: &[crate::geometry::Shape],
    spec: &ContactSpec,
    walls: &[WallSpec],
) -> Kept {
    let epsd = |spec: &ContactSpec| {
        spec.rolling()
            .is_some_and(|r| r.model == RollingModel::Epsd)
    };
    Kept {
        cached: shapes.iter().any(PairCache::kept_with),
        rolling: epsd(spec) || walls.iter().any(|w| epsd(&w.spec)),
    }
}

/// What every slot's contact is computed from: the bodies, the walls, the scene's law, the laws
/// resolved once for the step (if uniform), |g| and the step Δt.
#[derive(Clone, Copy)]
struct SlotContext<'a> {
    bodies: &'a Bodies,
    walls: &'a [WallSpec],
    spec: &'a ContactSpec,
    laws: Option<&'a [Law]>,
    g: f64,
    dt: f64,
    /// The neighbour list's per-body slot ranges (a body's number of slots).
    adjacency_start: &'a [u32],
}

/// The sides of a slot's pair as the narrow phase takes them: the giver as i, the receiver as j
/// (the normal points from the giver to the receiver, which gets +F).
#[inline(always)]
fn sides_of<'a>(b: &'a Bodies, walls: &'a [WallSpec], sides: Sides) -> (Side<'a>, Side<'a>) {
    let i = match sides.giver {
        Partner::Wall(w) => Side::Wall(&walls[w].wall),
        Partner::Body(k) => Side::Body(&b.shape[k], &b.state[k].pose),
    };
    let recv = sides.receiver;
    (i, Side::Body(&b.shape[recv], &b.state[recv].pose))
}

/// How many slots ahead the lean pass asks for its second body's data.
const PREFETCH_AHEAD: usize = 8;

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

/// A slot's pair through the narrow phase's lean path ([`overlap_lean`]): `Some` for two
/// circles or a circle and a wall, `None` for the other pair kinds.
#[inline(always)]
fn lean_of(slot: &Slot, cx: &SlotContext) -> Option<Option<LeanContact>> {
    if slot.sub != 0 {
        return lean_of_members(slot, cx);
    }
    let (i, j) = sides_of(cx.bodies, cx.walls, Sides::of_slot(slot.i, slot.j));
    overlap_lean(i, j)
}

/// [`lean_of`] for a slot of a clump pair: its member pair's contact, always `Some` — the
/// lean path's when the member's partner is a circle or a wall (or another clump's member), the
/// full dispatcher's otherwise (a member against an ellipse, a rectangle or a polygon, from an
/// empty pair cache). So [`update_slot`] takes every clump slot's contact as given here, with
/// the spring on its depth (`Spring::Depth`): a member is a disk, whose area potential against
/// a wall or a disk *is* that spring; against an ellipse, a rectangle or a polygon the area law
/// would take the lens potential, which clump members do not (a documented limitation).
#[cold]
#[inline(never)]
fn lean_of_members(slot: &Slot, cx: &SlotContext) -> Option<Option<LeanContact>> {
    let store = placed_members(cx.bodies, slot);
    let (i, j) = member_sides(cx.bodies, cx.walls, slot, &store);
    if let Some(lean) = overlap_lean(i, j) {
        return Some(lean);
    }
    let request = Request {
        area: false,
        chord: false,
        trace: None,
    };
    let c = crate::narrow_phase::clump::contact_member(i, j, &request);
    Some(c.geometry.map(|g| LeanContact {
        state: c.state,
        point: g.point,
        normal: g.normal,
        depth: g.depth,
    }))
}

/// The member circles of a clump slot's two sides, `[giver, receiver]`, each placed at its
/// world centre (a side that is not a clump: unused).
type MemberStore = [(Shape, Pose); 2];

/// [`MemberStore`] for a clump slot.
#[inline(never)]
fn placed_members(b: &Bodies, slot: &Slot) -> MemberStore {
    let sides = Sides::of_slot(slot.i, slot.j);
    let (of_i, of_j) = slot.members();
    let place = |k: usize, m: usize| match b.shape[k].clump() {
        Some(c) => crate::narrow_phase::clump::member(&c, m, &b.state[k].pose),
        None => (Shape::Circle { r: 0.0 }, Pose::IDENTITY),
    };
    match sides.giver {
        // The receiver is body i against a wall (its member `of_i`).
        Partner::Wall(_) => [
            (Shape::Circle { r: 0.0 }, Pose::IDENTITY),
            place(sides.receiver, of_i),
        ],
        Partner::Body(k) => [place(k, of_i), place(sides.receiver, of_j)],
    }
}

/// The sides of a clump pair's slot as the narrow phase takes them (giver as i, receiver as j,
/// as [`sides_of`]), each clump replaced by the slot's member from `store`
/// ([`placed_members`]): a circle at its world centre.
fn member_sides<'a>(
    b: &'a Bodies,
    walls: &'a [WallSpec],
    slot: &Slot,
    store: &'a MemberStore,
) -> (Side<'a>, Side<'a>) {
    let sides = Sides::of_slot(slot.i, slot.j);
    let side = |k: usize, s: &'a (Shape, Pose)| {
        if b.shape[k].clump().is_some() {
            Side::Body(&s.0, &s.1)
        } else {
            Side::Body(&b.shape[k], &b.state[k].pose)
        }
    };
    let i = match sides.giver {
        Partner::Wall(w) => Side::Wall(&walls[w].wall),
        Partner::Body(k) => side(k, &store[0]),
    };
    (i, side(sides.receiver, &store[1]))
}

/// The member-pair keys of the body pair `(i, j)` when either is a clump (every member pair
/// that can touch before the next build however the bodies turn: see `contacts`), else
/// `(i, j, 0)`.
fn clump_keys(b: &Bodies, i: u32, j: u32, skin: f64, keys: &mut Vec<(u32, u32, u32)>) {
    let (ci, cj) = (b.shape[i as usize].clump(), b.shape[j as usize].clump());
    if ci.is_none() && cj.is_none() {
        keys.push((i, j, 0));
        return;
    }
    let d = (b.state[i as usize].pose.position - b.state[j as usize].pose.position).norm();
    // A side's members: (reach from its centroid) per member; the whole body for a non-clump.
    let reach = |k: u32, c: Option<crate::geometry::Clump>| -> Vec<f64> {
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

/// One slot's contact: geometry (narrow phase, from the slot's pair cache when it has one),
/// kinematics at the contact point, the law, and the history; an inactive slot drops its
/// history (the slot's shear spring, and the rolling spring `rolling_spring` when the scene
/// keeps them). `extra`, when given, receives the depth, normal and stiffness; `loads` (one per
/// wall, or empty) the sums of each wall's contacts; `lean` is the pair through the narrow
/// phase's lean path ([`lean_of`], computed by the caller; for a clump pair's slot always
/// `Some`: its member pair's contact, [`lean_of_members`]).
///
/// `LINEAR`: the step's laws are all of the kind [`LinearDashpots`] holds, their numbers in
/// `laws` (ignored otherwise): this copy is compiled with the law's kinds known (see
/// [`apply_found`]). `PAIR`: the slot pairs two bodies ([`sides_of_slot`]).
#[allow(clippy::too_many_arguments)]
#[inline(never)]
fn update_slot<const LINEAR: bool, const PAIR: bool>(
    slot: &mut Slot,
    data: &mut ContactData,
    extra: Option<&mut ContactExtra>,
    cache: Option<&mut PairCache>,
    rolling_spring: Option<&mut f64>,
    cx: &SlotContext,
    p: &mut SlotPartial,
    loads: &mut [WallLoad],
    lean: Option<Option<LeanContact>>,
    laws: &[LinearDashpots],
) {
    let linear = LINEAR.then_some(laws);
    // The linear copy serves the step alone: no extras asked, no lean pair (those take
    // [`update_lean_slot`]), no rolling spring (a linear law has none) — constants in it.
    let (extra, rolling_spring, lean) = if LINEAR {
        (None, None, None)
    } else {
        (extra, rolling_spring, lean)
    };
    let SlotContext {
        bodies: b,
        walls,
        spec,
        ..
    } = *cx;
    let sides = sides_of_slot::<PAIR>(slot);
    let governing = match sides.wall() {
        Some(w) => &walls[w].spec,
        None => spec,
    };
    let area_law = governing.normal_force() == NormalForce::Area;
    // The narrow phase, the giver as i and the receiver as j (the normal points from the giver
    // to the receiver, which gets +F). Under the area law two disks, or a disk and a wall, take
    // the spring on the depth — exactly their area potential (`contact_law::normal`) — so they
    // take the dispatcher's lean path ([`overlap_lean`]: the same kernels, without the chord and
    // without the full record, whose building made the 10⁴-disk pile's contacts 25–40 % dearer).
    // Nothing below reads the chord but a flat overlap's spring (rectangles, whose kernels give
    // it anyway). Conic pairs start from the slot's pair cache (last step's crossings if the
    // contact lasts, or a separating axis) and leave the next step's there.
    let found = match lean {
        Some(lean) => lean.map(|c| (c.state, c.point, c.normal, c.depth, Spring::Depth)),
        None => {
            let mut scratch = PairCache::EMPTY;
            let cache = match cache {
                Some(c) => c,
                None => &mut scratch, // a scene with no pair that keeps anything
            };
            let (i, j) = sides_of(b, walls, sides);
            // The conic pairs through the dispatcher's lean record ([`conic_lean`]: the same
            // kernel without the chord's world coordinates and the full record, whose copies
            // cost the 10⁴-ellipse pile ~5 % of its step); the other kinds through the full
            // dispatcher.
            match conic_lean(i, j, cache, area_law) {
                Some(c) => c.map(|c| {
                    let spring = match c.area {
                        // Two conics are never flat-sided: the area potential on the lens of
                        // their equal-area disks, as `spring_of` decides.
                        Some(a) if area_law => Spring::Area(a, lens_of(b, sides)),
                        _ => Spring::Depth,
                    };
                    (c.state, c.point, c.normal, c.depth, spring)
                }),
                None => {
                    let request = Request {
                        area: area_law,
                        chord: false,
                        trace: None,
                    };
                    let c = contact_sides(i, j, cache, request)
                        .expect("a slot pairs a body with a body or a wall");
                    c.geometry.map(|geo| {
                        let spring = spring_of(b, sides, c.state, &geo, area_law);
                        (c.state, geo.point, geo.normal, geo.depth, spring)
                    })
                }
            }
        }
    };
    apply_found::<PAIR>(
        slot,
        data,
        extra,
        rolling_spring,
        cx,
        p,
        loads,
        found,
        linear,
        false,
    );
}

/// [`update_slot`] for a pair through the narrow phase's lean path (two circles, a circle and a
/// wall: [`lean_of`]'s `Some`): the spring on the depth. The same code as [`update_slot`]'s
/// tail, compiled apart with the spring known, which drops the area law's and the other pair
/// kinds' branches and their register pressure from the hot loop of a disk scene; with
/// `LINEAR` (as [`update_slot`]) also with the law's kinds known: the same arithmetic and the
/// same bits in some 40 % fewer instructions (10⁴ disks, callgrind: 327 → 185 per slot).
#[allow(clippy::too_many_arguments)]
#[inline(never)]
fn update_lean_slot<const LINEAR: bool>(
    slot: &mut Slot,
    data: &mut ContactData,
    rolling_spring: Option<&mut f64>,
    cx: &SlotContext,
    p: &mut SlotPartial,
    loads: &mut [WallLoad],
    lean: Option<LeanContact>,
    laws: &[LinearDashpots],
) {
    let found = lean.map(|c| (c.state, c.point, c.normal, c.depth, Spring::Depth));
    let linear = LINEAR.then_some(laws);
    apply_found::<false>(
        slot,
        data,
        None,
        rolling_spring,
        cx,
        p,
        loads,
        found,
        linear,
        false,
    );
}

/// [`update_disk_slot`] for a disk and a wall, out of line (few slots: the pair loop stays short).
#[inline(never)]
fn update_disk_wall_slot(
    slot: &mut Slot,
    data: &mut ContactData,
    cx: &SlotContext,
    p: &mut SlotPartial,
    loads: &mut [WallLoad],
    laws: &[LinearDashpots],
) {
    update_disk_slot::<false>(slot, data, cx, p, loads, laws);
}

/// [`update_lean_slot`] under linear laws for a scene of circles alone (and walls): the
/// geometry straight from the circle kernels ([`overlap_circle_circle`],
/// [`overlap_wall_circle`]; the wall is the giver, i, as [`sides_of`] has it), with each body's
/// radius its bounding radius, rather than through the dispatcher's sides and a separate pass:
/// the same kernels on the same numbers, the same bits.
#[inline(always)]
fn update_disk_slot<const PAIR: bool>(
    slot: &mut Slot,
    data: &mut ContactData,
    cx: &SlotContext,
    p: &mut SlotPartial,
    loads: &mut [WallLoad],
    laws: &[LinearDashpots],
) {
    let b = cx.bodies;
    let sides = sides_of_slot::<PAIR>(slot);
    let recv = sides.receiver;
    let (rj, pj) = (b.bound[recv], &b.state[recv].pose);
    let found = match sides.giver {
        Partner::Wall(w) => overlap_wall_circle(&cx.walls[w].wall, rj, pj),
        Partner::Body(k) => overlap_circle_circle(b.bound[k], &b.state[k].pose, rj, pj),
    };
    let found =
        found.map(|(state, point, normal, depth)| (state, point, normal, depth, Spring::Depth));
    apply_found::<PAIR>(
        slot,
        data,
        None,
        None,
        cx,
        p,
        loads,
        found,
        Some(laws),
        true,
    );
}

/// The sides of `slot` ([`Sides::of_slot`]); `PAIR`: the caller knows the slot pairs two
/// bodies (not a wall), so that the copy compiled for body pairs has no wall branch left.
#[inline(always)]
fn sides_of_slot<const PAIR: bool>(slot: &Slot) -> Sides {
    debug_assert!(
        !PAIR || slot.j < WALL_BASE,
        "a wall slot taken for a body pair"
    );
    if PAIR {
        Sides {
            receiver: slot.j as usize,
            giver: Partner::Body(slot.i as usize),
        }
    } else {
        Sides::of_slot(slot.i, slot.j)
    }
}

/// What a slot's contact, as the narrow phase `found` it (state, point, normal, depth and what
/// the spring acts on; `None` or a depth ≤ 0: separated), does: the kinematics at the contact
/// point, the law, the history and the slot's record (see [`update_slot`]). `disks`: every
/// body is a circle. `PAIR`: the slot pairs two bodies, so this copy has no wall branch (10⁴
/// disks: 1005 → 826 instructions per body-step, the sides no longer decoded at every use).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn apply_found<const PAIR: bool>(
    slot: &mut Slot,
    data: &mut ContactData,
    extra: Option<&mut ContactExtra>,
    rolling_spring: Option<&mut f64>,
    cx: &SlotContext,
    p: &mut SlotPartial,
    loads: &mut [WallLoad],
    found: Option<(ContactState, Vec2, Vec2, f64, Spring)>,
    linear: Option<&[LinearDashpots]>,
    disks: bool,
) {
    let SlotContext {
        bodies: b,
        walls,
        spec,
        laws,
        g,
        dt,
        ..
    } = *cx;
    let sides = sides_of_slot::<PAIR>(slot);
    let recv = sides.receiver;
    let (wall, giver) = (sides.wall(), sides.giving_body());
    let governing = match wall {
        Some(w) => &walls[w].spec,
        None => spec,
    };
    let (state, geo_point, geo_normal, depth, spring) = match found {
        Some(l) if l.3 > 0.0 => l,
        // Separated, or touching without overlap: no force, no history.
        _ => {
            if slot.active {
                p.lost_history += slot.history_energy;
            }
            *slot = Slot::with_sub(slot.i, slot.j, slot.sub);
            if let Some(r) = rolling_spring {
                *r = 0.0;
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
    // Where the force acts and along which normal: the chord midpoint and normal (the area
    // gradient's for the area law, which equal them for two crossings); for a Winkler contact
    // the overlap's centroid.
    let (point, n_) = match spring {
        Spring::Winkler(_, _, centroid) => (centroid, geo_normal),
        Spring::Area(a, _) => (a.point, a.normal),
        Spring::Depth => (geo_point, geo_normal),
    };
    let t_ = Vec2::new(-n_.y, n_.x);
    let rel = kinematics::relative(b, walls, sides, point);
    let vn = rel.velocity.dot(&n_);
    // m* only matters to a Hertz dashpot, a rolling part and a law resolved here (T12–T14):
    // a law with constant dashpots and no rolling part (`linear`) never reads it.
    let m_eff = if linear.is_some() {
        f64::NAN
    } else {
        1.0 / kinematics::inv_mass(b, sides) // T(13)
    };
    let resolved;
    let law = match (linear, laws) {
        (Some(l), _) => {
            resolved = l[wall.map_or(0, |w| 1 + w)].law();
            &resolved
        }
        (None, Some(l)) => &l[wall.map_or(0, |w| 1 + w)],
        (None, None) => {
            resolved = governing.resolve(spec, kinematics::density(b, sides), g, m_eff);
            &resolved
        }
    };
    // R* only matters to Hertz–Mindlin (T11): a linear scene does not pay for curvatures. The
    // area law takes the equal-area disks' (so that its potential depends on A alone).
    let r_eff = match (governing, &spring) {
        _ if linear.is_some() => f64::NAN,
        (ContactSpec::HertzMindlin { .. }, Spring::Area(_, EquivalentOverlap::Lens(lens))) => {
            lens.effective_radius()
        }
        (ContactSpec::HertzMindlin { .. }, _) => kinematics::effective_radius(b, sides, n_),
        (ContactSpec::Linear { .. }, _) => f64::NAN,
    };
    let (spring_depth, energy_depth, area) = match spring {
        Spring::Winkler(ds, de, _) => (ds, de, None),
        Spring::Area(a, equivalent) => (
            depth,
            depth,
            Some(AreaKinematics {
                area: a.area,
                length: a.length,
                rate: -a.length * vn + a.couple * rel.spin,
                couple: a.couple,
                equivalent,
            }),
        ),
        Spring::Depth => (depth, depth, None),
    };
    let kin = Kinematics {
        depth: spring_depth,
        energy_depth,
        vn,
        vt: rel.velocity.dot(&t_),
        m_eff,
        r_eff,
        dt,
        area,
        spin: rel.spin,
        rolling: if law.rolling.is_some() {
            kinematics::rolling(b, sides, point, n_, |k| {
                cx.adjacency_start[k + 1] - cx.adjacency_start[k]
            })
        } else {
            RollingKinematics {
                radius: f64::NAN,
                inertia: f64::NAN,
                spin_inertia: f64::NAN,
            }
        },
    };
    let mut history = if slot.active {
        History {
            shear: slot.shear,
            rolling: rolling_spring.as_deref().copied().unwrap_or(0.0),
        }
    } else {
        History::default()
    };
    debug_assert!(
        rolling_spring.is_some() || law.rolling.is_none_or(|r| r.model == RollingModel::Cdt),
        "an EPSD contact without a rolling spring slot"
    );
    let cf = law.force(&kin, &mut history);
    let f = n_ * cf.normal + t_ * cf.tangential; // T(5): on the receiving body
    let f_ne = n_ * cf.normal_non_elastic + t_ * cf.tangential;
    p.contacts += 1;
    p.elastic += cf.elastic_energy;
    p.history_energy_change += cf.history_energy_change;
    // (A circle's inscribed radius is its radius, which the disk path has at hand.)
    let inscribed = |k: usize| {
        if disks {
            b.bound[k]
        } else {
            b.shape[k].inscribed_radius()
        }
    };
    let scale = inscribed(recv).min(giver.map_or(f64::INFINITY, inscribed));
    if depth > p.max_depth_ratio * scale {
        p.max_depth_ratio = depth / scale; // divide only when the maximum grows
    }
    if let Some(load) = wall.and_then(|w| loads.get_mut(w)) {
        load.force += f;
        load.force_non_elastic += f_ne;
        load.stiffness += cf.kn;
        load.contacts += 1;
    }
    *slot = Slot {
        i: slot.i,
        j: slot.j,
        sub: slot.sub,
        active: true,
        state,
        shear: history.shear,
        history_energy: cf.history_energy,
    };
    if let Some(r) = rolling_spring {
        *r = history.rolling;
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

/// What the normal spring of a contact acts on, from the geometry the narrow phase found (a
/// chord contact: not two circles).
fn spring_of(
    b: &Bodies,
    sides: Sides,
    state: ContactState,
    geo: &crate::narrow_phase::ContactGeometry,
    area_law: bool,
) -> Spring {
    let recv = sides.receiver;
    let wall = sides.wall().is_some();
    // The mean face length of a flat pair (a body and a wall: the body's).
    let face = || match sides.giving_body() {
        Some(k) => 0.5 * (b.shape[recv].face_length() + b.shape[k].face_length()),
        None => b.shape[recv].face_length(),
    };
    match (geo.flat, geo.area) {
        // Flat on flat against a wall: a Winkler foundation (see `FlatOverlap`), under either
        // law (against a straight line it is the gradient of its energy) — resultant k′A with
        // k′ = k_n/ℓ at the overlap centroid; energy k′Aȳ. The spring then acts on
        // δ_s = A/ℓ with energy ½k_n δ_s (2ȳ).
        (Some(f), _) if state == ContactState::Overlap && (wall || !area_law) => {
            let ybar = (f.centroid - geo.chord.0).dot(&geo.normal).abs();
            Spring::Winkler(f.area / face(), 2.0 * ybar, f.centroid)
        }
        // The area potential: between two rectangles, the flat-equivalent overlap; otherwise
        // the equal-area disks' lens.
        (_, Some(a)) if area_law => {
            let flat_pair = sides
                .giving_body()
                .is_some_and(|k| b.shape[k].is_flat_sided() && b.shape[recv].is_flat_sided());
            let equivalent = if flat_pair {
                EquivalentOverlap::Flat(face())
            } else {
                lens_of(b, sides)
            };
            Spring::Area(a, equivalent)
        }
        _ => Spring::Depth,
    }
}

/// The area potential's equivalent overlap for a pair that is not two flat-sided bodies: the
/// lens of the pair's equal-area disks (a wall: a disk of infinite radius).
#[inline(always)]
fn lens_of(b: &Bodies, sides: Sides) -> EquivalentOverlap {
    let recv = sides.receiver;
    let (far, inv_far) = sides.giving_body().map_or((f64::INFINITY, 0.0), |k| {
        (b.area_radius[k], b.inv_area_radius[k])
    });
    EquivalentOverlap::Lens(DiskLens::with_inverses(
        b.area_radius[recv],
        b.inv_area_radius[recv],
        far,
        inv_far,
    ))
}

/// What the normal spring of a slot acts on, as the geometry found it.
#[derive(Clone, Copy, Debug)]
enum Spring {
    /// The depth, at the chord midpoint.
    Depth,
    /// A Winkler foundation: `δ_s = A/ℓ`, twice the centroid's distance from the chord, and
    /// the overlap's centroid (where it acts).
    Winkler(f64, f64, Vec2),
    /// The area potential.
    Area(OverlapArea, EquivalentOverlap),
}

/// The z component of `a × b`.
#[inline]
fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

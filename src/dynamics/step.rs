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
//!    the contacts' history springs, the velocities `v_{n+½}, ω_{n+½}` (the
//!    latest available; as in LAMMPS and LIGGGHTS) and the walls' drift velocities: neighbour
//!    list → narrow phase → kinematics at the contact ([`super::kinematics`]) → contact law →
//!    `F`, `r × F` and the contact's couple on each body (T3, T4, T22; `r` from the centroid to
//!    the contact point, so the normal force has a moment on non-circular bodies), plus gravity
//!    (T3); each wall's load is summed.
//! 4. **Kick**: `v_{n+1} = v_{n+½} + ½Δt F_{n+1}/m`, `ω_{n+1} = ω_{n+½} + ½Δt M_{n+1}/I` (T1);
//!    with Cundall's local damping (`"damping": {"local": α}`), `F_{n+1}` and `M_{n+1}` first
//!    gain `−α |F| sign(v)` per component and `−α |M| sign(ω)` ([`super::local_damping`]).
//! 5. **Account**: the dissipated energy and the work of the walls and of the prescribed bodies
//!    over the step; the servo walls' velocities for the next drift, from their loads.
//!
//! A body whose motion is prescribed takes part in every stage with infinite mass and inertia
//! (see [`super::body::Bodies`]): the kicks leave its velocity as prescribed and the drift moves
//! it.
//!
//! For an undamped linear oscillator this scheme is stable for `ωΔt < 2`; with a dashpot of
//! damping ratio ζ evaluated at the half step, for `ωΔt < 2(√(1+ζ²) − ζ)`
//! (see [`super::timestep`]).
//!
//! # Many bodies, many threads
//! The pairs come from a neighbour list ([`super::contacts`], kept by
//! [`super::neighbour_list`]) rebuilt only when bodies have moved far enough to matter. Each
//! step is three parallel passes (rayon), each over fixed-size chunks of bodies or slots: kick
//! and drift (bodies); every slot's contact ([`super::contact_pass`]; slots, each written by
//! one thread only); gathering each body's forces from its own slots, in key order, then the
//! second kick and the dissipated power (bodies). Every sum (increments, energies, counters)
//! is formed per chunk and then over the chunks in order. Nothing depends on how chunks are
//! scheduled, so a run gives the same bits on one thread or many. Circles skip their sine and
//! cosine.

use super::account::{Blowup, Diagnostics, Energies, Lap, StageTimes, StepReport};
use super::body::Bodies;
use super::boundary::{Boundary, drift_walls, update_servos};
use super::cell::Cell;
use super::contact_pass::{ContactPass, PassInput, SceneFacts, SlotPartial};
use super::contacts::{ContactList, sum_contacts};
use super::local_damping::of_body;
use super::materials::PairTable;
use super::neighbour_list::{self, Builder};
use super::restart::RestartState;
use crate::contact_law::ContactSpec;
use crate::geometry::{Pose, Vec2};
use rayon::prelude::*;

/// Bodies per parallel chunk. A fixed size: every sum is formed chunk by chunk and then over the
/// chunks in order, so that results are the same bit for bit whatever the number of threads.
pub(crate) const BODY_CHUNK: usize = 512;

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
    /// In a periodic cell: `Σ m v′v′` (xx, xy, yy) with v′ the velocity about the shear's
    /// mean flow (second kick).
    kinetic_stress: [f64; 3],
}

/// What a step reads and writes of the world, borrowed from it by [`World::step`]: the stepper
/// never names the world, which owns it (no import cycle between the two).
pub(crate) struct Parts<'a> {
    pub bodies: &'a mut Bodies,
    pub walls: &'a mut [Boundary],
    pub contacts: &'a mut ContactList,
    pub energies: &'a mut Energies,
    pub diagnostics: &'a mut Diagnostics,
    pub gravity: Vec2,
    pub spec: &'a ContactSpec,
    pub pairs: &'a PairTable,
    pub dt: f64,
    pub step: &'a mut u64,
    pub time: &'a mut f64,
    pub last_increments: &'a mut [f64; 3],
    /// The periodic cell, if any.
    pub cell: Option<&'a mut Cell>,
    /// Cundall's local damping coefficient α (0: off; see stage 4).
    pub local_damping: f64,
}

/// The stepper: the scratch the step reuses from step to step (the neighbour list's builder, the
/// contact pass's, the per-chunk partial sums of the body passes) and the facts of the scene
/// noted at each list build. Nothing in it is state: a world rebuilt from its bodies and
/// contacts steps the same.
#[derive(Clone, Debug, Default)]
pub struct Stepper {
    builder: Builder,
    pass: ContactPass,
    /// Per-chunk partial results of the body passes.
    body_partials: Vec<BodyPartial>,
    /// Per chunk of bodies, the bodies that re-entered a periodic cell in the drift, with the
    /// image counts to add and the kinetic energy per unit mass they gained.
    crossings: Vec<Vec<(u32, [i32; 2], f64)>>,
    /// The scene's facts, noted whenever the neighbour list is made.
    facts: SceneFacts,
    /// Where the steps' time went.
    pub(crate) times: StageTimes,
}

impl Stepper {
    /// The largest bounding radius of the bodies, as of the last list build.
    pub(crate) fn max_bound(&self) -> f64 {
        self.facts.max_bound
    }

    /// Heap bytes of the grid, and of the build's and the passes' scratch.
    pub(crate) fn heap_bytes(&self) -> (usize, usize) {
        let (grid, build) = self.builder.heap_bytes();
        (grid, build + self.pass.heap_bytes())
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
        let mut lap = Lap::start();
        self.size_partials(wd);
        // 1.–2. Kick to the half step and drift, chunk by chunk (in a periodic cell: the cell
        // first — its height under an imposed pressure, the Lees–Edwards shift — to level n+1,
        // then each body drifted, stretched with the cell and brought back into it).
        match wd.cell.as_deref_mut() {
            Some(cell) => {
                let (stretch, work) = cell.stretch(dt);
                cell.advance(dt);
                let cell = *cell;
                wd.energies.boundary_work += work;
                let crossing = self.kick_drift::<true>(wd, Some(&cell), stretch);
                wd.energies.boundary_work += crossing;
            }
            None => {
                self.kick_drift::<false>(wd, None, Vec2::new(1.0, 1.0));
            }
        }
        lap.to(&mut self.times.drift);
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
        // The mean over the bodies that move by themselves (a prescribed body's motion is its
        // own: a fixed one adds nothing to the sums, a moving one keeps the scene from rest).
        let free = n - wd.bodies.prescribed.len();
        if free > 0 {
            for v in &mut inc {
                *v /= free as f64;
            }
        }
        *wd.last_increments = inc;
        // Moving walls drift with the bodies; a wall's normal displacement since the list was
        // built counts like a body's.
        let wall_disp = drift_walls(
            wd.walls,
            &wd.contacts.wall_built_at,
            next_step,
            next_time,
            dt,
        );
        // 3. Forces at the new positions (the neighbour list first, if a pair outside it could
        // now touch: two bodies approach by at most the sum of their displacements, a body and
        // a wall by the sum of theirs).
        // In a periodic cell the images move with its lattice too (the Lees–Edwards shift, a
        // side under an imposed stress).
        let drift = wd.contacts.lattice_drift(wd.cell.as_deref());
        if wd.contacts.built_at.len() != n
            || disp[0] + disp[1].max(wall_disp) + drift > wd.contacts.skin
        {
            lap.to(&mut self.times.rest);
            self.rebuild_neighbours(wd);
            lap.to(&mut self.times.list_builds);
        }
        let slots = self.compute_slots(wd, dt);
        lap.to(&mut self.times.contacts);
        // 4. Kick to the full step, gathering each body's forces.
        let bodies_sum = self.gather_forces(wd, Some(h));
        lap.to(&mut self.times.gather);
        if let Some(body) = bodies_sum.bad {
            return Err(blowup(body, "velocity"));
        }
        if let Some(cell) = wd.cell.as_deref_mut()
            && cell.measures_stress()
        {
            // (With the stretch's second half of work: see `Cell::stretch`.)
            wd.energies.boundary_work += cell.measure(&slots, &bodies_sum.kinetic_stress);
        }
        // 5. Account: the energy the contacts took out, the work of the walls and of the
        // prescribed bodies; the servos' next velocities.
        let power = bodies_sum.non_elastic_power;
        wd.energies
            .account_step(dt, wd.walls, wd.bodies, &slots, power);
        wd.energies.kinetic = bodies_sum.kinetic;
        wd.energies.potential = bodies_sum.potential;
        *wd.step = next_step;
        *wd.time = next_time;
        if wd.walls.iter().any(Boundary::moves) {
            update_servos(wd.walls, *wd.step, dt);
        }
        lap.to(&mut self.times.rest);
        Ok(StepReport {
            increments: inc,
            contacts: slots.contacts,
        })
    }

    /// Kick to the half step and drift (stages 1–2), chunk by chunk, into the body partials;
    /// `PERIODIC`: in `cell`, each body's x and y stretched by `stretch` (the cell's, where its
    /// sides follow a stress or a strain rate) and the body brought back into the cell, its image counts kept. Returns the
    /// kinetic energy the bodies gained re-entering a Lees–Edwards cell (the boundary's work:
    /// their velocity changes by the image's).
    fn kick_drift<const PERIODIC: bool>(
        &mut self,
        wd: &mut Parts,
        cell: Option<&Cell>,
        stretch: Vec2,
    ) -> f64 {
        let dt = wd.dt;
        let h = 0.5 * dt;
        let n = wd.bodies.len();
        let Bodies {
            is_circle,
            state,
            force,
            torque,
            inv_mass,
            inv_inertia,
            ..
        } = &mut *wd.bodies;
        let (built_at, near_seam) = (&wd.contacts.built_at, &wd.contacts.near_seam[..]);
        let fresh = built_at.len() == n;
        // A periodic cell's bodies re-enter it: their image counts change (rarely: gathered
        // per chunk and applied after the pass).
        state
            .par_chunks_mut(BODY_CHUNK)
            .zip(self.body_partials.par_iter_mut())
            .zip(self.crossings.par_iter_mut())
            .enumerate()
            .for_each(|(c, ((state, part), crossings))| {
                let base = c * BODY_CHUNK;
                // The chunk's rows of the other arrays, cut to its length: indexed by `k`
                // below with no bounds check left.
                let rows = base..base + state.len();
                let (force, torque) = (&force[rows.clone()], &torque[rows.clone()]);
                let (inv_mass, inv_inertia) = (&inv_mass[rows.clone()], &inv_inertia[rows.clone()]);
                let is_circle = &is_circle[rows.clone()];
                let built_at = if fresh { &built_at[rows] } else { &[][..] };
                let mut p = BodyPartial::default();
                if PERIODIC {
                    crossings.clear();
                }
                for (k, s) in state.iter_mut().enumerate() {
                    let g = base + k;
                    s.vel += force[k] * (h * inv_mass[k]);
                    s.omega += torque[k] * h * inv_inertia[k];
                    let d = s.vel * dt;
                    let dth = s.omega * dt;
                    #[allow(unused_mut)]
                    let mut pos = s.pose.position + d;
                    let angle = s.pose.angle() + dth;
                    if !(pos.x.is_finite() && pos.y.is_finite() && angle.is_finite()) {
                        p.bad.get_or_insert(g);
                        continue;
                    }
                    if PERIODIC && let Some(cell) = cell {
                        pos.x *= stretch.x;
                        pos.y *= stretch.y;
                        if let Some(w) = cell.wrap(pos, s.vel) {
                            pos = w.position;
                            let gained = 0.5 * (w.velocity.norm_squared() - s.vel.norm_squared());
                            s.vel = w.velocity;
                            crossings.push((g as u32, w.images, gained));
                        }
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
                        // instead of one per body (taken when the chunk is summed). In a
                        // periodic cell, the displacement's shortest image (a body that
                        // re-entered has not moved by a period).
                        let moved = match cell {
                            // (Only a body near a seam can have crossed one.)
                            Some(cell) if PERIODIC && near_seam.get(g) != Some(&false) => {
                                cell.shortest(pos - built_at[k])
                            }
                            _ => pos - built_at[k],
                        };
                        top_two(&mut p.disp, moved.norm_squared());
                    }
                }
                *part = p;
            });
        match PERIODIC {
            true => wd.bodies.re_enter(self.crossings.iter().flatten()),
            false => 0.0,
        }
    }

    /// Evaluates the forces of the current configuration without advancing (used at t = 0).
    pub(crate) fn evaluate_forces(&mut self, wd: &mut Parts, always_rebuild: bool) {
        self.size_partials(wd);
        if always_rebuild || wd.contacts.outgrown(wd.bodies, wd.cell.as_deref()) {
            self.rebuild_neighbours(wd);
        }
        let slots = self.compute_slots(wd, 0.0);
        self.gather_forces(wd, None);
        if let Some(cell) = wd.cell.as_deref_mut()
            && cell.measures_stress()
        {
            let _outside_a_step = cell.measure(&slots, &cell.kinetic_stress(wd.bodies));
        }
    }

    /// One partial result per chunk of bodies and of slots.
    fn size_partials(&mut self, wd: &Parts) {
        let nb = wd.bodies.len().div_ceil(BODY_CHUNK);
        if self.body_partials.len() != nb {
            self.body_partials.resize(nb, BodyPartial::default());
            self.crossings.resize(nb, Vec::new());
        }
        self.pass.size(wd.contacts.slots.len(), wd.walls.len());
    }

    /// Rebuilds the neighbour list from the current positions, carrying histories over (see
    /// [`neighbour_list`]); the history springs' energy of contacts that dropped out is
    /// dissipated.
    pub(crate) fn rebuild_neighbours(&mut self, wd: &mut Parts) {
        self.rebuild_neighbours_with(wd, false);
    }

    /// [`Stepper::rebuild_neighbours`]; `carry_data`: the continuing slots keep their contact
    /// data (a rebuild between steps, after bodies were inserted).
    pub(crate) fn rebuild_neighbours_with(&mut self, wd: &mut Parts, carry_data: bool) {
        self.facts = SceneFacts::of(wd.bodies);
        self.builder.carry_data = carry_data;
        let lost = self.builder.rebuild(
            wd.bodies,
            wd.walls,
            wd.pairs,
            self.facts.clumps,
            wd.cell.as_deref(),
            wd.contacts,
        );
        self.builder.carry_data = false;
        wd.energies.dissipated += lost;
        self.size_partials(wd);
    }

    /// Each body's force and moment gathered again from the contact data as they stand (no
    /// kick): after bodies were removed between steps, the others' forces without the removed
    /// bodies' contacts.
    pub(crate) fn regather_forces(&mut self, wd: &mut Parts) {
        self.size_partials(wd);
        self.gather_forces(wd, None);
    }

    /// Restores the neighbour list of a restart (see [`neighbour_list::restore`]).
    pub(crate) fn restore_neighbours(&mut self, wd: &mut Parts, saved: &RestartState) {
        self.facts = SceneFacts::of(wd.bodies);
        neighbour_list::restore(wd.bodies, wd.pairs, saved, wd.contacts);
        self.size_partials(wd);
    }

    /// The pass's input for the step just drifted over, `dt` (0 at the start).
    fn pass_input<'a>(&self, wd: &'a mut Parts, dt: f64) -> (PassInput<'a>, &'a mut ContactList) {
        let g = wd.gravity.norm();
        if let Some(cell) = wd.cell.as_deref() {
            wd.contacts.mark_near_seams(cell, wd.bodies);
        }
        if wd.pairs.all().any(|p| p.spec.counts_contacts()) {
            wd.contacts.count_touching(wd.bodies.len());
        }
        (
            PassInput {
                bodies: &*wd.bodies,
                walls: &mut *wd.walls,
                spec: wd.spec,
                pairs: wd.pairs,
                g,
                dt,
                facts: self.facts,
                cell: wd.cell.as_deref(),
            },
            &mut *wd.contacts,
        )
    }

    /// Every slot's contact ([`super::contact_pass`]); `dt` is the step just drifted over (0 at
    /// the start), over which the shear displacement is integrated (T16). Adds the shear energy
    /// of contacts that opened to the dissipated energy and sets the elastic energy and the
    /// diagnostics; returns the sums.
    fn compute_slots(&mut self, wd: &mut Parts, dt: f64) -> SlotPartial {
        let (input, list) = self.pass_input(wd, dt);
        let sum = self.pass.run(input, list);
        // A contact that opened took its history springs' energy with it.
        wd.energies.dissipated += sum.lost_history;
        wd.energies.elastic = sum.elastic;
        wd.diagnostics.deep_contacts += sum.deep;
        wd.diagnostics.contained_contacts += sum.contained;
        wd.diagnostics.max_depth_ratio = wd.diagnostics.max_depth_ratio.max(sum.max_depth_ratio);
        sum
    }

    /// Fills each active slot's [`super::contacts::ContactExtra`] (depth, stiffness, damping)
    /// for the current state (see [`ContactPass::refresh_extras`]).
    pub(crate) fn refresh_contact_extras(&mut self, wd: &mut Parts) {
        let (input, list) = self.pass_input(wd, 0.0);
        self.pass.refresh_extras(input, list);
    }

    /// Each body's force and moment: gravity (T3) and its contacts' (T4, T22), gathered in key
    /// order. With `kick = Some(h)`, then `v += h F/m`, `ω += h M/I` (the second half-kick) and
    /// the sums of the body pass (net force and moment, energies, first non-finite body).
    fn gather_forces(&mut self, wd: &mut Parts, kick: Option<f64>) -> BodyPartial {
        match wd.cell.as_deref() {
            Some(&cell) => self.gather::<true>(wd, kick, Some(&cell)),
            None => self.gather::<false>(wd, kick, None),
        }
    }

    /// [`Stepper::gather_forces`]; `PERIODIC`: in `cell`, each lever arm the shortest image of
    /// the centroid-to-contact vector (a contact of a body's periodic image lies across a
    /// seam), the potential energy from the unwrapped positions, and the kinetic stress summed.
    fn gather<const PERIODIC: bool>(
        &mut self,
        wd: &mut Parts,
        kick: Option<f64>,
        cell: Option<&Cell>,
    ) -> BodyPartial {
        let gravity = wd.gravity;
        let alpha = wd.local_damping;
        // Disks under linear laws have no contact couples (nothing but the spring, the dashpot
        // and the slider; a disk's area
        // potential is its depth spring).
        let couples = !self.facts.disks || !self.pass.linear();
        let list = &*wd.contacts;
        let (data, start, adjacency, near_seam) = (
            &list.data[..],
            &list.adjacency_start[..],
            &list.adjacency[..],
            &list.near_seam[..],
        );
        let Bodies {
            state,
            force,
            torque,
            mass,
            inertia,
            inv_mass,
            inv_inertia,
            image,
            ..
        } = &mut *wd.bodies;
        let image = &image[..];
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
                    // Only a body near a seam may have a contact through an image.
                    let (mut f, mut m, mut f_ne, mut m_ne) = match cell {
                        Some(cell) if PERIODIC && near_seam.get(g) != Some(&false) => {
                            if couples {
                                sum_contacts::<true, true>(adj, data, x, f0, Some(cell))
                            } else {
                                sum_contacts::<false, true>(adj, data, x, f0, Some(cell))
                            }
                        }
                        _ if couples => sum_contacts::<true, false>(adj, data, x, f0, None),
                        _ => sum_contacts::<false, false>(adj, data, x, f0, None),
                    };
                    if alpha > 0.0
                        && let Some(h) = kick
                    {
                        // Cundall's local damping (in a sheared cell, about the mean flow).
                        let flow = match cell {
                            Some(cell) if PERIODIC => Some(cell.mean_flow(x.y)),
                            _ => None,
                        };
                        let inv = (inv_mass[k], inv_inertia[k]);
                        let (fd, md) = of_body(alpha, (f, m), (s.vel, s.omega), h, inv, flow);
                        f += fd;
                        f_ne += fd;
                        m += md;
                        m_ne += md;
                    }
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
                        match cell {
                            Some(cell) if PERIODIC => {
                                // (From the unwrapped position: a body that crossed a seam
                                // has not moved against gravity by a period.)
                                p.potential -=
                                    mass[k] * gravity.dot(&cell.unwrapped_at(x, image[g]));
                                if cell.measures_stress() {
                                    cell.add_kinetic_stress(
                                        &mut p.kinetic_stress,
                                        mass[k],
                                        s.vel,
                                        x,
                                    );
                                }
                            }
                            _ => p.potential -= mass[k] * gravity.dot(&x),
                        }
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
            for (a, b) in sum.kinetic_stress.iter_mut().zip(p.kinetic_stress) {
                *a += b;
            }
        }
        sum
    }
}

//! The world: bodies, walls, gravity, the contact law, time, and the running energy account.

use super::account::{Blowup, StageTimes, StepReport};
pub use super::account::{Diagnostics, Energies};
use super::body::{Bodies, BodyInit};
pub use super::boundary::Boundary;
use super::boundary::{Motion, update_servos};
use super::cell::Cell;
use super::contacts::{ContactList, REMOVED};
use super::flow::{Discharge, Flow, Insertion, SplitMix64, draw_body, draw_position};
use super::flow::{FlowRestart, Target};
use super::materials::{Materials, PairTable};
use super::neighbour_list::kept;
use super::restart::{
    BodyRestart, ProgramRestart, RestartError, RestartState, SlotRestart, TurnRestart, WallRestart,
};
use super::step::{Parts, Stepper};
use crate::contact_law::{ContactSpec, HISTORY_LEN};
use crate::geometry::{Pose, Vec2};
use crate::narrow_phase::PairCache;

/// Everything the step function evolves.
#[derive(Clone, Debug)]
pub struct World {
    pub bodies: Bodies,
    pub walls: Vec<Boundary>,
    pub gravity: Vec2,
    /// The scene's contact law: material 0's (see [`super::materials`]).
    pub spec: ContactSpec,
    /// The scene's further materials and the pairs given their own law.
    pub materials: Materials,
    /// The contact law of every pair of materials, and of each wall with each material.
    pub pairs: PairTable,
    pub dt: f64,
    pub time: f64,
    pub step: u64,
    pub contacts: ContactList,
    pub energies: Energies,
    pub diagnostics: Diagnostics,
    /// Mean |Δx|, |Δy|, |Δθ| over bodies during the last step (P's quiescence measure).
    pub last_increments: [f64; 3],
    /// The periodic cell the scene repeats in, if any (see [`super::cell`]).
    pub cell: Option<Cell>,
    /// The scene's insertion and outflow regions, if any (see [`super::flow`]).
    pub flow: Option<Flow>,
    /// The identity the next inserted body gets ([`Bodies::id`]).
    pub next_id: u64,
    /// Cundall's local non-viscous damping coefficient α in [0, 1) (0: off; see
    /// [`super::step`]'s stage 4).
    pub local_damping: f64,
    /// The step's scratch (owned here, never read as state).
    stepper: Stepper,
}

/// What a world is made of: its bodies as they start, its walls, gravity, the contact law of
/// material 0 (the scene's) and the further materials, and the time step.
#[derive(Clone, Debug)]
pub struct Scene<'a> {
    pub bodies: &'a [BodyInit],
    pub walls: Vec<Boundary>,
    pub gravity: Vec2,
    pub spec: ContactSpec,
    pub materials: Materials,
    pub dt: f64,
}

impl World {
    /// A world at t = 0; the forces of the initial configuration are evaluated at once (the first
    /// half-kick needs them).
    pub fn new(
        bodies: &[BodyInit],
        walls: Vec<Boundary>,
        gravity: Vec2,
        spec: ContactSpec,
        dt: f64,
    ) -> Self {
        Self::of_scene(Scene {
            bodies,
            walls,
            gravity,
            spec,
            materials: Materials::default(),
            dt,
        })
    }

    /// The world of `scene` at t = 0, its forces evaluated.
    ///
    /// # Panics
    /// If a pair of materials has no law ([`PairTable::new`]).
    pub fn of_scene(scene: Scene) -> Self {
        let mut w = World::unevaluated(scene);
        w.start();
        w
    }

    /// The forces of the configuration as it stands, the servos' velocities for the first step
    /// and the energies: what a world starts from.
    fn start(&mut self) {
        self.evaluate_forces();
        update_servos(&mut self.walls, self.step, self.dt);
        self.energies.kinetic = self.kinetic_energy();
        self.energies.potential = self.potential_energy();
    }

    /// The scene at t = 0 with nothing evaluated: no contacts, no forces, no energies.
    fn unevaluated(scene: Scene) -> Self {
        let Scene {
            bodies,
            walls,
            gravity,
            spec,
            materials,
            dt,
        } = scene;
        World {
            bodies: Bodies::new(bodies),
            pairs: PairTable::new(&spec, &materials, &walls),
            walls,
            gravity,
            spec,
            materials,
            dt,
            time: 0.0,
            step: 0,
            contacts: ContactList::default(),
            energies: Energies::default(),
            diagnostics: Diagnostics {
                dt_critical_observed: f64::INFINITY,
                ..Default::default()
            },
            last_increments: [0.0; 3],
            cell: None,
            flow: None,
            next_id: bodies.len() as u64,
            local_damping: 0.0,
            stepper: Stepper::default(),
        }
    }

    /// A world resumed from a restart taken of a world of the same `scene` (as the case gives
    /// it; the bodies' poses and velocities are the restart's): it steps to the same bits as
    /// the world the restart was taken from ([`World::restart_state`]). Refused when the
    /// restart does not fit the scene.
    pub fn resume(scene: Scene, saved: &RestartState) -> Result<Self, RestartError> {
        let shapes: Vec<_> = scene.bodies.iter().map(|b| b.shape).collect();
        let pairs = PairTable::new(&scene.spec, &scene.materials, &scene.walls);
        saved.check(scene.bodies, &scene.walls, scene.dt, kept(&shapes, &pairs))?;
        let mut w = World {
            time: saved.time,
            step: saved.step,
            energies: saved.energies,
            diagnostics: saved.diagnostics,
            last_increments: saved.last_increments,
            cell: saved.cell,
            ..World::unevaluated(scene)
        };
        if saved.cell.is_some() {
            w.bodies.image = saved.bodies.iter().map(|r| r.image).collect();
        }
        w.bodies.id.clone_from(&saved.ids);
        w.next_id = saved.next_id;
        for (k, r) in saved.bodies.iter().enumerate() {
            let b = &mut w.bodies;
            b.state[k].pose = Pose::with_frame(r.position, r.angle, r.frame);
            b.state[k].vel = r.velocity;
            b.state[k].omega = r.omega;
            b.force[k] = r.force;
            b.torque[k] = r.torque;
        }
        for (ws, r) in w.walls.iter_mut().zip(&saved.walls) {
            ws.place(r.point, r.turn.map_or(0.0, |t| t.angle));
            if let (Some(t), Some(r)) = (&mut ws.turn, r.turn) {
                t.start_angle = r.start_angle;
                t.omega = r.omega;
            }
            ws.velocity = r.velocity;
            ws.load = r.load;
            if let Some(p) = r.program {
                ws.stage = p.stage;
                ws.start = p.start;
                ws.start_time = p.start_time;
            }
        }
        let (stepper, mut parts) = w.parts();
        stepper.restore_neighbours(&mut parts, saved);
        Ok(w)
    }

    /// The world's full state, from which [`World::resume`] continues exactly (see
    /// [`super::restart`]).
    pub fn restart_state(&self) -> RestartState {
        let b = &self.bodies;
        let c = &self.contacts;
        RestartState {
            step: self.step,
            time: self.time,
            bodies: (0..b.len())
                .map(|k| {
                    let s = &b.state[k];
                    BodyRestart {
                        position: s.pose.position,
                        angle: s.pose.angle(),
                        frame: s.pose.cos_sin(),
                        velocity: s.vel,
                        omega: s.omega,
                        force: b.force[k],
                        torque: b.torque[k],
                        image: b.image.get(k).copied().unwrap_or([0, 0]),
                    }
                })
                .collect(),
            walls: self
                .walls
                .iter()
                .map(|ws| WallRestart {
                    point: ws.anchor(),
                    turn: ws.turn.map(|t| TurnRestart {
                        angle: t.angle,
                        start_angle: t.start_angle,
                        omega: t.omega,
                    }),
                    velocity: ws.velocity,
                    load: ws.load,
                    program: matches!(ws.motion, Motion::Program(_)).then_some(ProgramRestart {
                        stage: ws.stage,
                        start: ws.start,
                        start_time: ws.start_time,
                    }),
                })
                .collect(),
            slots: (0..c.slots.len())
                .map(|k| SlotRestart {
                    slot: c.slots[k],
                    more: {
                        let h = c.history_of(k);
                        let mut more = [0.0; HISTORY_LEN - 1];
                        more.copy_from_slice(&h.0[1..]);
                        more
                    },
                    cache: c.cache.get(k).copied().unwrap_or(PairCache::EMPTY),
                    data: c.data[k],
                })
                .collect(),
            built_at: c.built_at.clone(),
            wall_built_at: c.wall_built_at.clone(),
            lattice_built_at: c.lattice_built_at,
            builds: c.builds,
            energies: self.energies,
            diagnostics: self.diagnostics,
            last_increments: self.last_increments,
            cell: self.cell,
            ids: b.id.clone(),
            next_id: self.next_id,
            flow: self.flow.as_ref().map(Flow::restart),
        }
    }

    /// The stepper and the state it steps, borrowed apart.
    fn parts(&mut self) -> (&mut Stepper, Parts<'_>) {
        (
            &mut self.stepper,
            Parts {
                bodies: &mut self.bodies,
                walls: &mut self.walls,
                contacts: &mut self.contacts,
                energies: &mut self.energies,
                diagnostics: &mut self.diagnostics,
                gravity: self.gravity,
                spec: &self.spec,
                pairs: &self.pairs,
                dt: self.dt,
                step: &mut self.step,
                time: &mut self.time,
                last_increments: &mut self.last_increments,
                cell: self.cell.as_mut(),
                local_damping: self.local_damping,
            },
        )
    }

    /// The world with its scene repeating in `cell`: every body brought into the cell (their
    /// number is returned: a case may place bodies outside it), the forces evaluated again with
    /// the pairs across the seams. (A cell checked by the case reader: its size against the
    /// bodies' reach, no wall across a periodic direction.)
    pub fn with_cell(mut self, cell: Cell) -> (Self, usize) {
        let b = &mut self.bodies;
        b.image = vec![[0, 0]; b.len()];
        let mut moved = 0;
        for k in 0..b.len() {
            let s = &mut b.state[k];
            if let Some(w) = cell.wrap(s.pose.position, s.vel) {
                s.pose = s.pose.moved(w.position, s.pose.angle());
                s.vel = w.velocity;
                b.image[k] = w.images;
                moved += 1;
            }
        }
        self.cell = Some(cell);
        self.contacts = ContactList::default();
        self.start();
        (self, moved)
    }

    /// In a periodic cell whose sides follow a stress, a side that has shrunk to twice the reach
    /// of a pair or below (the least the nearest-image model allows: [`Cell::check_size`], the
    /// case reader's rule): `(side, its size, the least)`. Below it a body meets two images of
    /// another, or its own, and the model misses all but the nearest: a run stops there rather
    /// than go on with contacts it cannot see (issue 41: one disk at P = 1000 ended in a cell
    /// 0.498 cm high with exit 0).
    pub fn cell_below_limit(&self) -> Option<(usize, f64, f64)> {
        let cell = self.cell.as_ref().filter(|c| c.deforms())?;
        let max_bound = self.stepper.max_bound();
        let sides = [cell.size.x, cell.size.y];
        cell.check_size(super::neighbour_list::pair_reach(max_bound))
            .err()
            .map(|(k, least)| (k, sides[k], least))
    }

    /// The world with insertion and outflow regions (see [`super::flow`]); `saved`: where the
    /// flow of the run this world was resumed from stood.
    pub fn with_flow(mut self, flow: Flow, saved: Option<&FlowRestart>) -> Self {
        self.flow = Some(match saved {
            Some(s) => flow.resumed(s),
            None => flow,
        });
        self
    }

    /// Applies the flow between steps, once per step (see [`super::flow`]): removes the free
    /// bodies whose centroids lie in an outflow region, logging them, then inserts the bodies
    /// the inserters are behind by. Nothing without a flow.
    pub fn apply_flow(&mut self) {
        let Some(mut flow) = self.flow.take() else {
            return;
        };
        if flow.applied_step != Some(self.step) {
            flow.applied_step = Some(self.step);
            flow.log.clear();
            flow.inserted_log.clear();
            self.outflow(&mut flow);
            self.inflow(&mut flow);
        }
        self.flow = Some(flow);
    }

    /// The outflow part of [`World::apply_flow`].
    fn outflow(&mut self, flow: &mut Flow) {
        if flow.outflows.is_empty() {
            return;
        }
        let b = &self.bodies;
        let out: Vec<usize> = (0..b.len())
            .filter(|&k| {
                !b.is_prescribed(k)
                    && flow
                        .outflows
                        .iter()
                        .any(|r| r.contains(b.state[k].pose.position))
            })
            .collect();
        if out.is_empty() {
            return;
        }
        for &k in &out {
            flow.log.push(Discharge {
                step: self.step,
                time: self.time,
                id: b.id[k],
                mass: b.mass[k],
            });
            flow.discharged += 1;
            flow.discharged_mass += b.mass[k];
        }
        self.remove_bodies(&out);
    }

    /// The insertion part of [`World::apply_flow`].
    fn inflow(&mut self, flow: &mut Flow) {
        let t = self.time;
        let free = self.bodies.len() - self.bodies.prescribed.len();
        let mut new: Vec<BodyInit> = Vec::new();
        for (which, (ins, st)) in flow.inserters.iter().zip(flow.state.iter_mut()).enumerate() {
            if t < ins.start || t < st.next_try {
                continue;
            }
            let target = match ins.target {
                Target::Rate { rate, count } => {
                    let n = ((t - ins.start) * rate).floor() as u64;
                    count.map_or(n, |c| n.min(c))
                }
                Target::Count(c) => c,
                Target::Keep { keep, count } => {
                    let now = (free + new.len()) as u64;
                    let want = st.inserted + keep.saturating_sub(now);
                    count.map_or(want, |c| want.min(c))
                }
            };
            let mut rng = SplitMix64(st.rng);
            while st.inserted < target {
                let c = draw_body(ins, &mut rng);
                let bound = c.shape.bounding_radius();
                let placed = (0..ins.attempts)
                    .map(|_| draw_position(&ins.region, bound, &mut rng))
                    .find(|&p| self.clear_of_all(p, bound, &new));
                match placed {
                    Some(p) => {
                        // (Its identity: the next after those inserted before it here.)
                        flow.inserted_log.push(Insertion {
                            step: self.step,
                            time: t,
                            id: self.next_id + new.len() as u64,
                            inserter: which,
                            r: c.r,
                            aspect: c.aspect,
                        });
                        new.push(BodyInit {
                            shape: c.shape,
                            position: p,
                            angle: c.angle,
                            velocity: ins.velocity,
                            omega: ins.omega,
                            density: ins.density,
                            material: ins.material,
                            prescribed: false,
                        });
                        st.inserted += 1;
                    }
                    None => {
                        st.next_try = t + ins.retry;
                        break;
                    }
                }
            }
            st.rng = rng.0;
        }
        if !new.is_empty() {
            self.insert_bodies(&new);
        }
    }

    /// Whether a bounding circle of radius `bound` about `p` is clear of every body's (those
    /// of the world and `more`) and of every wall: the bodies' distances by brute force (the
    /// nearest periodic image in a cell).
    fn clear_of_all(&self, p: Vec2, bound: f64, more: &[BodyInit]) -> bool {
        let apart = |x: Vec2, r: f64| {
            let d = match &self.cell {
                Some(c) => c.shortest(p - x),
                None => p - x,
            };
            d.norm_squared() > (bound + r) * (bound + r)
        };
        let b = &self.bodies;
        (0..b.len()).all(|k| apart(b.state[k].pose.position, b.bound[k]))
            && more
                .iter()
                .all(|m| apart(m.position, m.shape.bounding_radius()))
            && self.walls.iter().all(|w| w.signed_distance(p) > bound)
    }

    /// Adds bodies between steps, each with the next identity ([`World::next_id`]): their
    /// force is their weight (they touch nothing: the caller has placed them clear of every
    /// other body), their energy of motion and position is booked as work done on the scene
    /// (see [`super::flow`]), and the neighbour list is made again (carrying every contact).
    pub fn insert_bodies(&mut self, inits: &[BodyInit]) {
        for init in inits {
            let k = self.bodies.len();
            self.bodies.push(init, self.next_id);
            self.next_id += 1;
            if let Some(cell) = &self.cell {
                // A body placed outside the cell (an insertion region across a seam, or beyond
                // it) is brought into it, as a case's bodies are ([`World::with_cell`]), its
                // image counts keeping where it was placed (issue 41's fuzzing: inserted bodies
                // ran outside the cell, unwrapped).
                let s = &mut self.bodies.state[k];
                let mut images = [0, 0];
                if let Some(w) = cell.wrap(s.pose.position, s.vel) {
                    s.pose = s.pose.moved(w.position, s.pose.angle());
                    s.vel = w.velocity;
                    images = w.images;
                }
                self.bodies.image.push(images);
            }
            let b = &mut self.bodies;
            b.force[k] = self.gravity * b.mass[k];
            let s = &b.state[k];
            let kinetic =
                0.5 * b.mass[k] * s.vel.norm_squared() + 0.5 * b.inertia[k] * s.omega * s.omega;
            // (At the unwrapped position, as `remove_bodies` books it.)
            let x = match &self.cell {
                Some(c) => c.unwrapped(s.pose.position, b.image[k]),
                None => s.pose.position,
            };
            let potential = -b.mass[k] * self.gravity.dot(&x);
            self.energies.kinetic += kinetic;
            self.energies.potential += potential;
            self.energies.boundary_work += kinetic + potential;
        }
        let (stepper, mut parts) = self.parts();
        stepper.rebuild_neighbours_with(&mut parts, true);
    }

    /// Removes the bodies `out` (indices, increasing) between steps: the others keep their
    /// order, identities and contacts (renumbered), and their forces are gathered again
    /// without the removed bodies' contacts; the removed bodies' energy of motion and position
    /// is booked as work the scene did on its boundary (see [`super::flow`]).
    pub fn remove_bodies(&mut self, out: &[usize]) {
        let n = self.bodies.len();
        let mut keep = vec![true; n];
        for &k in out {
            keep[k] = false;
            let b = &self.bodies;
            let s = &b.state[k];
            let x = match &self.cell {
                Some(c) => c.unwrapped(s.pose.position, b.image[k]),
                None => s.pose.position,
            };
            let kinetic =
                0.5 * b.mass[k] * s.vel.norm_squared() + 0.5 * b.inertia[k] * s.omega * s.omega;
            let potential = -b.mass[k] * self.gravity.dot(&x);
            self.energies.kinetic -= kinetic;
            self.energies.potential -= potential;
            self.energies.boundary_work -= kinetic + potential;
        }
        let mut map = vec![REMOVED; n];
        let mut next = 0;
        for k in 0..n {
            if keep[k] {
                map[k] = next;
                next += 1;
            }
        }
        self.bodies.retain(&keep);
        let cached = !self.contacts.cache.is_empty();
        let lost = self.contacts.drop_bodies(&map, self.bodies.len(), cached);
        self.energies.dissipated += lost;
        let (stepper, mut parts) = self.parts();
        stepper.regather_forces(&mut parts);
    }

    /// Advances the world by one time step (see [`super::step`] for the stages). Never inlined
    /// into its caller (one call a step): its instructions are counted by name
    /// (`valgrind --tool=callgrind --toggle-collect='*World::step*'`), whatever runs it.
    #[inline(never)]
    pub fn step(&mut self) -> Result<StepReport, Blowup> {
        let (stepper, mut parts) = self.parts();
        stepper.step(&mut parts)
    }

    /// Wall-clock seconds this world's steps have spent in each stage so far (see
    /// [`StageTimes`]).
    pub fn stage_times(&self) -> StageTimes {
        self.stepper.times
    }

    /// Evaluates the forces of the current configuration without advancing (used at t = 0),
    /// the neighbour list built afresh.
    pub fn evaluate_forces(&mut self) {
        let (stepper, mut parts) = self.parts();
        stepper.evaluate_forces(&mut parts, true);
    }

    /// Evaluates the forces of the current configuration without advancing, keeping the
    /// neighbour list unless a body has moved far enough since it was built that a pair outside
    /// it could touch (the step's rule): for a sequence of nearby configurations, such as an
    /// energy minimisation's. The bodies must not have been moved in a way the list cannot see
    /// (a changed cell size, new bodies): call [`World::evaluate_forces`] after such a change.
    pub fn evaluate_forces_near(&mut self) {
        let (stepper, mut parts) = self.parts();
        stepper.evaluate_forces(&mut parts, false);
    }

    /// Fills each active slot's [`super::contacts::ContactExtra`] (depth, stiffness, damping)
    /// for the current state. The step does not store them (it would stream them to memory
    /// every step for a report made every output interval): this evaluates every slot again on
    /// a copy — its history untouched, no time elapsing (Δt = 0) — and keeps only the extras.
    pub fn refresh_contact_extras(&mut self) {
        let (stepper, mut parts) = self.parts();
        stepper.refresh_contact_extras(&mut parts);
    }

    /// The unbalanced-force ratio of PFC and Yade — mean |net force| over bodies divided by
    /// mean |contact force| over contacts — and the same for moments (contact force × the
    /// receiving body's bounding radius); 0 without contacts. Computed on demand from the last
    /// evaluation (it costs a square root per contact and per body).
    pub fn unbalanced_ratios(&self) -> (f64, f64) {
        let b = &self.bodies;
        let (mut sum_f, mut sum_m, mut count) = (0.0, 0.0, 0usize);
        for c in self.contacts.active() {
            let f = c.data.force.norm();
            sum_f += f;
            sum_m += f * b.bound[c.sides().receiver];
            count += 1;
        }
        if count == 0 || b.is_empty() {
            return (0.0, 0.0);
        }
        let n = b.len() as f64;
        let net_f = b.force.iter().map(|f| f.norm()).sum::<f64>() / n;
        let net_m = b.torque.iter().map(|m| m.abs()).sum::<f64>() / n;
        let (mean_f, mean_m) = (sum_f / count as f64, sum_m / count as f64);
        (
            if mean_f > 0.0 { net_f / mean_f } else { 0.0 },
            if mean_m > 0.0 { net_m / mean_m } else { 0.0 },
        )
    }

    /// `Σ ½ m v² + ½ I ω²`.
    pub fn kinetic_energy(&self) -> f64 {
        let b = &self.bodies;
        (0..b.len())
            .map(|k| {
                0.5 * b.mass[k] * b.state[k].vel.norm_squared()
                    + 0.5 * b.inertia[k] * b.state[k].omega * b.state[k].omega
            })
            .sum()
    }

    /// `Σ −m g·x`.
    pub fn potential_energy(&self) -> f64 {
        let b = &self.bodies;
        (0..b.len())
            .map(|k| {
                let x = match &self.cell {
                    Some(c) => c.unwrapped(b.state[k].pose.position, b.image[k]),
                    None => b.state[k].pose.position,
                };
                -b.mass[k] * self.gravity.dot(&x)
            })
            .sum()
    }

    /// Total linear momentum `Σ m v`.
    pub fn momentum(&self) -> Vec2 {
        let b = &self.bodies;
        (0..b.len()).map(|k| b.state[k].vel * b.mass[k]).sum()
    }

    /// Total angular momentum about the origin, `Σ (I ω + m x × v)`.
    pub fn angular_momentum(&self) -> f64 {
        let b = &self.bodies;
        (0..b.len())
            .map(|k| {
                let (x, v) = (b.state[k].pose.position, b.state[k].vel);
                b.inertia[k] * b.state[k].omega + b.mass[k] * (x.x * v.y - x.y * v.x)
            })
            .sum()
    }
}

/// Heap bytes held by a vector (its capacity, not its length).
fn held<T>(v: &Vec<T>) -> usize {
    v.capacity() * std::mem::size_of::<T>()
}

impl World {
    /// Heap bytes the world holds, by part (capacities): bodies, neighbour-list slots and their
    /// contact data, the per-body adjacency, the grid and the build's scratch.
    pub fn heap_breakdown(&self) -> [(&'static str, usize); 5] {
        let b = &self.bodies;
        let c = &self.contacts;
        let (grid, scratch) = self.stepper.heap_bytes();
        let bodies = held(&b.shape)
            + held(&b.density)
            + held(&b.mass)
            + held(&b.inv_mass)
            + held(&b.inertia)
            + held(&b.inv_inertia)
            + held(&b.bound)
            + held(&b.area_radius)
            + held(&b.inv_area_radius)
            + held(&b.state)
            + held(&b.is_circle)
            + held(&b.force)
            + held(&b.torque)
            + held(&b.id);
        [
            ("bodies", bodies),
            (
                "slots and contact data",
                held(&c.slots) + held(&c.data) + held(&c.extra) + held(&c.cache) + held(&c.history),
            ),
            (
                "adjacency",
                held(&c.adjacency) + held(&c.adjacency_start) + held(&c.adjacency_fill),
            ),
            ("grid", grid),
            (
                "build scratch",
                held(&c.keys) + scratch + held(&c.built_at) + held(&c.wall_built_at),
            ),
        ]
    }
}

//! The step function: velocity Verlet (kick–drift–kick) with contact forces from the chord
//! geometry and the contact law.
//!
//! # Stages of one step, and the time level of every quantity
//! 1. **Kick**: `v_{n+½} = v_n + ½Δt F_n/m`, `ω_{n+½} = ω_n + ½Δt M_n/I` (forces of the last
//!    evaluation, at time level n).
//! 2. **Drift**: `x_{n+1} = x_n + Δt v_{n+½}`, `θ_{n+1} = θ_n + Δt ω_{n+½}`; the increments
//!    `|Δx|, |Δy|, |Δθ|` averaged over bodies are P's quiescence measure. Non-finite state stops
//!    here with the step and the body.
//! 3. **Forces** `F_{n+1}, M_{n+1}` from the positions `x_{n+1}, θ_{n+1}` and, for the dashpots and
//!    the shear displacement, the velocities `v_{n+½}, ω_{n+½}` (the latest available; as in
//!    LAMMPS and LIGGGHTS): broad phase → narrow phase → contact law → `F` and `r × F` on each
//!    body (T3, T4; `r` from the centroid to the contact point, so the normal force has a moment
//!    on non-circular bodies), plus gravity (T3).
//! 4. **Kick**: `v_{n+1} = v_{n+½} + ½Δt F_{n+1}/m`, `ω_{n+1} = ω_{n+½} + ½Δt M_{n+1}/I` (T1).
//!
//! For an undamped linear oscillator this scheme is stable for `ωΔt < 2`; with a dashpot of
//! damping ratio ζ evaluated at the half step, for `ωΔt < 2(√(1+ζ²) − ζ)`
//! (see [`super::timestep`]).

use super::contacts::{Contact, WALL_BASE};
use super::world::World;
use crate::contact_law::Kinematics;
use crate::geometry::{Pose, Vec2};
use crate::narrow_phase::{ContactState, contact_bodies, contact_wall_body};
use std::fmt;

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
    /// Mean |net force| over bodies divided by mean |contact force| over contacts (the
    /// unbalanced-force ratio of PFC and Yade; 0 without contacts).
    pub unbalanced_force_ratio: f64,
    /// Mean |net moment| over bodies divided by mean |contact force × bounding radius|.
    pub unbalanced_moment_ratio: f64,
    /// Number of contacts after the step.
    pub contacts: usize,
}

impl World {
    /// Advances the world by one time step (see the module documentation for the stages).
    pub fn step(&mut self) -> Result<StepReport, Blowup> {
        let dt = self.dt;
        let h = 0.5 * dt;
        let n = self.bodies.len();
        let next_step = self.step + 1;
        let next_time = next_step as f64 * dt;
        // 1. Kick to the half step.
        {
            let b = &mut self.bodies;
            for k in 0..n {
                b.vel[k] += b.force[k] * (h * b.inv_mass[k]);
                b.omega[k] += b.torque[k] * h * b.inv_inertia[k];
            }
        }
        // 2. Drift.
        let mut inc = [0.0f64; 3];
        {
            let b = &mut self.bodies;
            for k in 0..n {
                let d = b.vel[k] * dt;
                let dth = b.omega[k] * dt;
                let p = b.pose[k];
                let pos = p.position + d;
                let angle = p.angle() + dth;
                if !(pos.x.is_finite() && pos.y.is_finite() && angle.is_finite()) {
                    return Err(Blowup {
                        step: next_step,
                        time: next_time,
                        body: k,
                        what: "position",
                    });
                }
                b.pose[k] = Pose::new(pos, angle);
                inc[0] += d.x.abs();
                inc[1] += d.y.abs();
                inc[2] += dth.abs();
            }
        }
        if n > 0 {
            for v in &mut inc {
                *v /= n as f64;
            }
        }
        self.last_increments = inc;
        // 3. Forces at the new positions.
        let (mean_contact_force, mean_contact_moment) = self.evaluate_forces_over(dt);
        // 4. Kick to the full step.
        let mut unbalanced = (0.0, 0.0);
        {
            let b = &mut self.bodies;
            for k in 0..n {
                b.vel[k] += b.force[k] * (h * b.inv_mass[k]);
                b.omega[k] += b.torque[k] * h * b.inv_inertia[k];
                if !(b.vel[k].x.is_finite() && b.vel[k].y.is_finite() && b.omega[k].is_finite()) {
                    return Err(Blowup {
                        step: next_step,
                        time: next_time,
                        body: k,
                        what: "velocity",
                    });
                }
                unbalanced.0 += b.force[k].norm();
                unbalanced.1 += b.torque[k].abs();
            }
        }
        self.account_dissipation(dt);
        self.step = next_step;
        self.time = next_time;
        self.energies.kinetic = self.kinetic_energy();
        self.energies.potential = self.potential_energy();
        let ratio = |num: f64, den: f64| if den > 0.0 { num / n as f64 / den } else { 0.0 };
        Ok(StepReport {
            increments: inc,
            unbalanced_force_ratio: ratio(unbalanced.0, mean_contact_force),
            unbalanced_moment_ratio: ratio(unbalanced.1, mean_contact_moment),
            contacts: self.contacts.current.len(),
        })
    }

    /// Evaluates the forces of the current configuration without advancing (used at t = 0).
    pub(crate) fn evaluate_forces(&mut self) {
        self.evaluate_forces_over(0.0);
    }

    /// Contact forces and gravity for the current positions and velocities; `dt` is the step
    /// just drifted over (0 at the start), over which the shear displacement is integrated (T16)
    /// and the dissipated energy is accounted. Returns the mean contact force magnitude and the
    /// mean contact moment scale (for the unbalanced ratios).
    fn evaluate_forces_over(&mut self, dt: f64) -> (f64, f64) {
        let n = self.bodies.len();
        for k in 0..n {
            self.bodies.force[k] = self.gravity * self.bodies.mass[k]; // T(3): body force
            self.bodies.torque[k] = 0.0;
        }
        // Candidate pairs: bodies from the grid, then every body against every wall; sorted, so
        // that histories are carried by a merge.
        self.grid.pairs(&self.bodies, &mut self.candidates);
        for (w, ws) in self.walls.iter().enumerate() {
            for k in 0..n {
                if ws.wall.signed_distance(self.bodies.pose[k].position) <= self.bodies.bound[k] {
                    self.candidates.push((k as u32, WALL_BASE + w as u32));
                }
            }
        }
        self.candidates.sort_unstable();
        self.contacts.begin_step();
        let g = self.gravity.norm();
        let (mut sum_f, mut sum_m, mut elastic) = (0.0, 0.0, 0.0);
        for idx in 0..self.candidates.len() {
            let (i, j) = self.candidates[idx];
            let (iu, ju) = (i as usize, j as usize);
            let b = &self.bodies;
            let wall = j >= WALL_BASE;
            let c = if wall {
                contact_wall_body(
                    &self.walls[(j - WALL_BASE) as usize].wall,
                    &b.shape[iu],
                    &b.pose[iu],
                )
            } else {
                contact_bodies(&b.shape[iu], &b.pose[iu], &b.shape[ju], &b.pose[ju])
            };
            let Some(geo) = c.geometry else { continue };
            if geo.depth <= 0.0 {
                continue; // touching without overlap: no force, no history
            }
            match c.state {
                ContactState::Deep => self.diagnostics.deep_contacts += 1,
                ContactState::Contained => self.diagnostics.contained_contacts += 1,
                _ => {}
            }
            // Flat on flat: a Winkler foundation (see `FlatOverlap`) — resultant k′A with
            // k′ = k_n/ℓ, ℓ the pair's face length, at the overlap centroid; energy k′Aȳ. The
            // spring then acts on δ_s = A/ℓ with energy ½k_n δ_s (2ȳ). Elsewhere: the depth, at the
            // chord midpoint.
            let (spring_depth, energy_depth, point) = match geo.flat {
                Some(f) if c.state == ContactState::Overlap => {
                    let ell = if wall {
                        face_length(&b.shape[iu])
                    } else {
                        0.5 * (face_length(&b.shape[iu]) + face_length(&b.shape[ju]))
                    };
                    let ybar = (f.centroid - geo.chord.0).dot(&geo.normal).abs();
                    (f.area / ell, 2.0 * ybar, f.centroid)
                }
                _ => (geo.depth, geo.depth, geo.point),
            };
            let n_ = geo.normal;
            let t_ = Vec2::new(-n_.y, n_.x);
            // The body that receives +F ("j" of the law) and the one that receives −F.
            let (recv, give) = if wall { (iu, None) } else { (ju, Some(iu)) };
            let r_recv = point - b.pose[recv].position;
            let mut v_rel = b.point_velocity(recv, r_recv);
            let mut inv_m = b.inv_mass[recv];
            let mut inv_r = 1.0 / b.curvature_radius(recv, -n_);
            let mut rho = b.density[recv];
            let r_give = give.map(|k| point - b.pose[k].position);
            if let (Some(k), Some(r)) = (give, r_give) {
                v_rel -= b.point_velocity(k, r);
                inv_m += b.inv_mass[k];
                inv_r += 1.0 / b.curvature_radius(k, n_);
                rho = 0.5 * (rho + b.density[k]);
            }
            let kin = Kinematics {
                depth: spring_depth,
                energy_depth,
                vn: v_rel.dot(&n_),
                vt: v_rel.dot(&t_),
                m_eff: 1.0 / inv_m, // T(13)
                r_eff: 1.0 / inv_r, // T(11)
                dt,
            };
            let law = if wall {
                self.walls[(j - WALL_BASE) as usize]
                    .spec
                    .resolve(&self.spec, rho, g, kin.m_eff)
            } else {
                self.spec.resolve(&self.spec, rho, g, kin.m_eff)
            };
            let mut history = self.contacts.carried(i, j).unwrap_or_default();
            let cf = law.force(&kin, &mut history);
            let f = n_ * cf.normal + t_ * cf.tangential; // T(5): on the receiving body
            let b = &mut self.bodies;
            b.force[recv] += f;
            b.torque[recv] += cross(r_recv, f); // T(22), r from the centroid to the contact point
            if let (Some(k), Some(r)) = (give, r_give) {
                b.force[k] -= f;
                b.torque[k] -= cross(r, f);
            }
            elastic += cf.elastic_energy;
            sum_f += f.norm();
            sum_m += f.norm() * b.bound[recv];
            let scale = b.shape[recv]
                .inscribed_radius()
                .min(give.map_or(f64::INFINITY, |k| b.shape[k].inscribed_radius()));
            self.diagnostics.max_depth_ratio =
                self.diagnostics.max_depth_ratio.max(geo.depth / scale);
            self.contacts.current.push(Contact {
                i,
                j,
                history,
                state: c.state,
                point,
                normal: n_,
                depth: geo.depth,
                force: f,
                elastic_energy: cf.elastic_energy,
                shear_energy: cf.shear_energy,
                normal_non_elastic: cf.normal_non_elastic,
                tangential: cf.tangential,
                shear_energy_change: cf.shear_energy_change,
                kn: cf.kn,
                eta_n: cf.eta_n,
                kt: cf.kt,
                eta_t: cf.eta_t,
            });
        }
        // A contact that opened took its shear spring's energy with it.
        if dt > 0.0 {
            self.energies.dissipated += self.contacts.opened_shear_energy();
        }
        self.energies.elastic = elastic;
        let nc = self.contacts.current.len().max(1) as f64;
        (sum_f / nc, sum_m / nc)
    }
}

impl World {
    /// Adds the energy the contacts took out during this step. Verlet applies the forces of time
    /// level n+1 over the interval centred on it, so their work is taken with the velocities at
    /// n+1 (after the second kick): the non-elastic normal part's and the shear force's, less the
    /// change of the shear spring's energy.
    fn account_dissipation(&mut self, dt: f64) {
        let b = &self.bodies;
        let mut d = 0.0;
        for c in &self.contacts.current {
            let (iu, ju) = (c.i as usize, c.j as usize);
            let (recv, give) = if c.is_wall() {
                (iu, None)
            } else {
                (ju, Some(iu))
            };
            let mut v = b.point_velocity(recv, c.point - b.pose[recv].position);
            if let Some(k) = give {
                v -= b.point_velocity(k, c.point - b.pose[k].position);
            }
            let t = Vec2::new(-c.normal.y, c.normal.x);
            d += -(c.normal_non_elastic * v.dot(&c.normal) + c.tangential * v.dot(&t)) * dt
                - c.shear_energy_change;
        }
        self.energies.dissipated += d;
    }
}

/// The face length ℓ of a flat-sided shape for the Winkler contact: the mean side, `(w + h)/2`,
/// so that a square pressed flat by δ feels exactly `k_n δ`.
fn face_length(shape: &crate::geometry::Shape) -> f64 {
    match *shape {
        crate::geometry::Shape::Rectangle { w, h } => 0.5 * (w + h),
        _ => shape.bounding_radius(),
    }
}

/// The z component of `a × b`.
#[inline]
fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

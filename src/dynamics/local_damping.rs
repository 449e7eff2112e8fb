//! Cundall's local non-viscous damping (Cundall, "Distinct element models of rock and soil
//! structure", in *Analytical and Computational Methods in Engineering Rock Mechanics*, 1987;
//! as PFC's `damp` and Yade's `NewtonIntegrator.damping`).
//!
//! Each component of a body's unbalanced force (its contacts' forces and its weight) and its
//! moment is opposed by a force proportional to its own magnitude, against the body's velocity
//! in that component:
//!
//! ```text
//! F_d,x = −α |F_x| sign(v_x),   F_d,y = −α |F_y| sign(v_y),   M_d = −α |M| sign(ω)
//! ```
//!
//! with α in [0, 1) (`"damping": {"local": α}` in a case) and sign(0) = 0. It is **not a
//! physical dissipation**: it acts on every body whether it touches anything or not (a body in
//! free fall is slowed), it has no relative velocity in it and it does not depend on the
//! contacts' stiffness; it damps each body's motion toward equilibrium, whatever its frequency,
//! which is what quasi-static preparation (settling a packing, bringing a sample to a
//! prescribed stress) wants, and what a dynamic result must not contain. For a linear
//! oscillator `m ẍ = −k x` it multiplies the restoring force by (1 − α) while the body moves
//! away from rest and by (1 + α) while it returns, so each half cycle keeps the fraction
//! (1 − α)/(1 + α) of the energy: the amplitude ratio per half cycle is √((1 − α)/(1 + α))
//! (the energy of the swing out, ½ (1−α) k A², equals that of the swing back, ½ (1+α) k A'²).
//!
//! **When it acts.** In the step's second kick (`super::step`, stage 4), on the force of time
//! level n+1 and against the velocity of that level, predicted as `v_{n+½} + ½Δt F/m` (Yade
//! predicts the same way); in a Lees–Edwards cell against the velocity about the shear's mean
//! flow `γ̇ (y − L_y/2)`, so the imposed shear is not damped. The force stored for the next
//! step's first half-kick is the damped one. The forces of t = 0 (evaluated before any step)
//! and those of an energy minimisation (`dem2d relax`) are not damped. A body whose motion is
//! prescribed is not damped. The damping force's power on the bodies is counted as dissipated
//! energy, with the contacts' non-elastic forces.

use crate::geometry::Vec2;

/// sign(x) with sign(0) = 0 (so that a body at rest is not pushed).
#[inline]
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The local damping force and moment on a body with unbalanced force `f` and moment `m`,
/// moving at `v` and `omega`: `(−α |F_x| sign(v_x), −α |F_y| sign(v_y))` and `−α |M| sign(ω)`.
#[inline]
pub fn local_damping(alpha: f64, f: Vec2, m: f64, v: Vec2, omega: f64) -> (Vec2, f64) {
    (
        Vec2::new(
            -alpha * f.x.abs() * sign(v.x),
            -alpha * f.y.abs() * sign(v.y),
        ),
        -alpha * m.abs() * sign(omega),
    )
}

/// Cundall's local damping of one body in the second kick: its force and moment `(f, m)` now,
/// its velocities `(v, ω)` at the half step, the half step `h`, its inverse mass and inertia
/// `inv` and, in a sheared cell, the mean flow's x velocity at its height: the damping force
/// and moment against the predicted `v_{n+1}`, `ω_{n+1}` (about the mean flow), none for a
/// prescribed body (zero inverse mass and inertia).
#[inline(always)]
pub(crate) fn of_body(
    alpha: f64,
    (f, m): (Vec2, f64),
    (vel, omega): (Vec2, f64),
    h: f64,
    (inv_mass, inv_inertia): (f64, f64),
    flow: Option<f64>,
) -> (Vec2, f64) {
    let mut v = vel + f * (h * inv_mass);
    if let Some(flow) = flow {
        v.x -= flow;
    }
    let w = omega + m * h * inv_inertia;
    let (fd, md) = local_damping(alpha, f, m, v, w);
    let fd = if inv_mass == 0.0 { Vec2::zeros() } else { fd };
    let md = if inv_inertia == 0.0 { 0.0 } else { md };
    (fd, md)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opposes_the_velocity_with_a_fraction_of_the_force() {
        // (α = 0.5: every product exact.)
        let (f, m) = local_damping(0.5, Vec2::new(-2.0, 3.0), -4.0, Vec2::new(1.0, -5.0), 2.0);
        assert_eq!(f, Vec2::new(-1.0, 1.5));
        assert_eq!(m, -2.0);
        // A body at rest in a component is not pushed in it.
        let (f, m) = local_damping(0.5, Vec2::new(-2.0, 3.0), -4.0, Vec2::new(0.0, 1.0), 0.0);
        assert_eq!(f, Vec2::new(0.0, -1.5));
        assert_eq!(m, 0.0);
    }
}

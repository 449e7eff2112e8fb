//! Contact forces of a frame read back from a run, for colouring pictures: the trace holds
//! positions, angles and velocities, from which the world is rebuilt and its contacts
//! evaluated once.

use super::run_data::Frame;
use crate::dynamics::{BodyInit, World};
use crate::geometry::Vec2;
use crate::scene::Case;

/// The normal contact force on each body of `frame`, `Σ F_n` over its contacts (dyn per unit
/// thickness), recomputed from the frame's positions and velocities with the case's law. The
/// normal force (spring and dashpot) depends only on the state, so it is the run's up to the
/// time level of the velocity (the run's dashpot sees the half-step velocity); the tangential
/// force needs the shear history, which the trace does not hold, and is left out.
pub fn normal_force_per_body(case: &Case, frame: &Frame) -> Vec<f64> {
    let bodies: Vec<BodyInit> = case
        .bodies
        .iter()
        .zip(&frame.bodies)
        .map(|(init, s)| BodyInit {
            position: Vec2::new(s.x, s.y),
            angle: s.angle,
            velocity: Vec2::new(s.vx, s.vy),
            omega: s.omega,
            ..*init
        })
        .collect();
    let mut world = World::new(
        &bodies,
        case.walls.clone(),
        case.gravity,
        case.contact,
        case.dt,
    );
    world.refresh_contact_extras();
    let mut sum = vec![0.0; bodies.len()];
    for c in world.contacts.active() {
        let fn_ = c.data.force.dot(&c.extra.normal);
        sum[c.slot.i as usize] += fn_;
        if !c.is_wall() {
            sum[c.slot.j as usize] += fn_;
        }
    }
    sum
}

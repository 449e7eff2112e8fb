//! Contact forces of a frame read back from a run, for colouring pictures: the forces the run
//! recorded (`contacts.csv`, written by `dem2d run --contacts`), or else recomputed from the
//! trace's positions and velocities with the walls where they were at that frame.

use super::analysis::ContactFrames;
use super::run_data::RunData;
use crate::dynamics::BodyInit;
use crate::geometry::Vec2;
use crate::scene::Case;

/// The normal contact force on each body at frame `k` of `run`, `Σ F_n` over its contacts (dyn
/// per unit thickness).
///
/// With `recorded` (the run's `contacts.csv`) holding the frame's step: the run's own forces.
/// Otherwise recomputed from the frame's positions and velocities with the case's law and the
/// walls placed where they were at that frame ([`RunData::walls_at`]: a moving wall drawn at its
/// starting point would push every grain past it with the force of an overlap of metres). The
/// normal force (spring and dashpot) depends only on the state, so it is the run's up to the
/// time level of the velocity (the run's dashpot sees the half-step velocity); the tangential
/// force needs the shear history, which the trace does not hold, and is left out.
pub fn normal_force_per_body(
    run: &RunData,
    k: usize,
    recorded: Option<&ContactFrames>,
) -> Vec<f64> {
    let frame = &run.frames[k];
    let n = frame.bodies.len();
    let mut sum = vec![0.0; n];
    let at = recorded.and_then(|r| {
        let i = r
            .contacts
            .binary_search_by_key(&frame.step, |(s, _)| *s)
            .ok()?;
        Some(&r.contacts[i].1)
    });
    if let Some(contacts) = at {
        for c in contacts {
            let fn_ = c.normal_force();
            if let Some(s) = sum.get_mut(c.j) {
                *s += fn_;
            }
            if let Some(s) = c.i.body().and_then(|i| sum.get_mut(i)) {
                *s += fn_;
            }
        }
        return sum;
    }
    let case = &run.case;
    let bodies: Vec<BodyInit> = run
        .inits(k)
        .zip(&frame.bodies)
        .map(|(init, s)| BodyInit {
            position: Vec2::new(s.x, s.y),
            angle: s.angle,
            velocity: Vec2::new(s.vx, s.vy),
            omega: s.omega,
            ..*init
        })
        .collect();
    let (walls, _) = run.walls_at(k);
    // (The frame's bodies as they are: no insertion or removal of the world's own.)
    let mut world = Case {
        bodies,
        walls,
        flow: None,
        ..case.clone()
    }
    .build_world();
    world.refresh_contact_extras();
    for c in world.contacts.active() {
        let fn_ = c.data.force.dot(&c.extra.normal);
        sum[c.slot.i as usize] += fn_;
        if !c.is_wall() {
            sum[c.slot.j as usize] += fn_;
        }
    }
    sum
}

//! The analysis measures on real runs: the Love–Weber stress of a servo-compacted sample against
//! the boundary stress from its wall forces (equal at static equilibrium, an identity of the
//! equilibrium equations — see `dem2d::analysis::stress`), and against the servo's target.

use dem2d::analysis::{self, Frame};
use dem2d::dynamics::World;
use dem2d::run::Simulation;
use dem2d::scene::Case;
use dem2d::scene::servo_box::ServoBox;

/// Steps `world` in chunks until the box area changes by less than `1e-6` of itself over a
/// chunk and the unbalanced force ratio is below 1e-3 (or `max_time` passes); returns whether
/// it got there.
fn settle(world: &mut World, chunk: u64, max_time: f64) -> bool {
    let area = |w: &World| Frame::from_world(w).wall_box.map_or(0.0, |b| b.area());
    let mut last = area(world);
    let mut sim = Simulation::new(world).for_steps(chunk);
    while sim.world().time < max_time {
        sim.run().unwrap();
        let w = sim.world();
        let a = area(w);
        if (a - last).abs() < 1e-6 * a && w.unbalanced_ratios().0 < 1e-3 {
            return true;
        }
        last = a;
    }
    false
}

#[test]
fn love_weber_stress_of_a_servo_compacted_sample_equals_its_boundary_stress() {
    let spec = ServoBox {
        n_side: 10,
        aspect: 1.0,
        friction: 0.5,
        sigma: 1e5,
        seed: 3,
    };
    let case = Case::from_json(&spec.compaction_case(5.0)).unwrap();
    let mut world = case.build_world();
    assert!(
        settle(&mut world, 2000, 5.0),
        "did not come to rest by t = 5 s"
    );
    world.refresh_contact_extras();
    let frame = Frame::from_world(&world);
    let m = analysis::measure(&frame, None);
    let p = 0.5 * (m.boundary_stress[0] + m.boundary_stress[1]);
    for k in 0..3 {
        assert!(
            (m.stress[k] - m.boundary_stress[k]).abs() < 0.01 * p,
            "component {k}: Love–Weber {:?} boundary {:?}",
            m.stress,
            m.boundary_stress
        );
    }
    // The servos hold σ_c on each wall: the boundary stress is isotropic at σ_c.
    for k in 0..2 {
        assert!(
            (m.boundary_stress[k] / spec.sigma - 1.0).abs() < 0.01,
            "{:?}",
            m.boundary_stress
        );
    }
    assert!(
        m.packing_fraction > 0.75 && m.packing_fraction < 0.9,
        "{}",
        m.packing_fraction
    );
    assert!(m.coordination_no_rattlers >= 3.0, "{m:?}");
}

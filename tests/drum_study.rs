//! `dem2d study drum --quick` (issue 44, item 3): a small drum (R = 4 cm) half filled with 53
//! disks, turned through Fr = 1e-3, 1e-2, 0.3, 1 and 2 in one run
//! ([`dem2d::scene::drum_flow`]). Facts that do not come from the code measured:
//! - geometry: no disk reaches beyond the drum's circle by more than a contact's overlap (a
//!   disk's reach |x − c| + r − R is its wall contact's depth);
//! - at Fr = 1e-3 the free surface is a plane (within a grain: its rms off its line under half a
//!   diameter, its cubic fit within a diameter of the line), at an angle between the grains'
//!   friction angle's neighbourhood bounds (15–40°);
//! - at Fr = 2 the bed centrifuges: a half-filled bed's innermost grains lie at R/√2 (the ring's
//!   inner radius for half the drum's area), held against the wall wherever ω² R/√2 > g, that is
//!   Fr > √2: its centre of mass comes to the axis (from 4R/(3π) = 0.42 R for the half-filled
//!   bed at rest) and most grains turn with the drum;
//! - the free surface steepens with Fr where the bed flows steadily (rolling, Fr = 1e-2 to 0.3):
//!   the flowing layer's inertia (GDR MiDi 2004, Eur. Phys. J. E 14, 341, rotating drums).

use dem2d::scene::drum_flow::{self, DrumSpec, Regime};

mod common;

#[test]
fn a_small_drum_rolls_with_a_plane_surface_at_low_fr_and_centrifuges_at_fr_2() {
    let t0 = std::time::Instant::now();
    let spec = DrumSpec::quick(1.0, vec![1e-3, 1e-2, 0.3, 1.0, 2.0]);
    let run = drum_flow::run(&spec).unwrap();
    println!(
        "{} grains, {} steps, dt {:e}, {:.1} s",
        run.grains,
        run.steps,
        run.dt,
        t0.elapsed().as_secs_f64()
    );
    for p in &run.points {
        println!(
            "Fr {:e}: {} angle {:.1}° (sd {:.1}) rms {:.2} d bulge {:.2} d layer {:.2} d \
             flowing {:.2} of the time, in flight {:.3}, co-rotating {:.2}, centre of mass \
             {:.2} R, reach {:.4} d, overlap {:.4} d",
            p.froude,
            p.regime().as_str(),
            p.angle,
            p.angle_sd,
            p.rms,
            p.bulge,
            p.thickness,
            p.flow_time,
            p.flying,
            p.corotating,
            p.com,
            p.reach,
            p.overlap
        );
    }
    let [low, mid, high, _, spin] = &run.points[..] else {
        panic!("five stages")
    };
    for p in &run.points {
        assert!(
            p.reach <= p.overlap + 1e-12,
            "Fr {}: a disk reaches {} d beyond the drum, its overlaps only {} d",
            p.froude,
            p.reach,
            p.overlap
        );
        assert!(p.overlap < 0.05, "overlap {} d", p.overlap);
    }
    assert!(low.rms < 0.5 && low.bulge < 1.0, "not a plane: {low:?}");
    assert!((15.0..40.0).contains(&low.angle), "angle {}", low.angle);
    assert!(
        low.com > 0.35,
        "a half-filled bed's centre of mass: {}",
        low.com
    );
    assert_eq!(spin.regime(), Regime::Centrifuging, "{spin:?}");
    assert!(spin.com < 0.1 && spin.corotating > 0.5, "{spin:?}");
    assert_eq!(high.regime(), Regime::Rolling, "{high:?}");
    assert!(high.flow_time == 1.0 && high.flying < 0.01, "{high:?}");
    assert!(
        high.angle > mid.angle + 2.0,
        "the surface steepens with Fr: {} at 1e-2, {} at 0.3",
        mid.angle,
        high.angle
    );
}

#[test]
fn the_drum_study_refuses_an_aspect_ratio_below_one_naming_the_option() {
    let dir = std::env::temp_dir().join(format!("dem2d_drum_study_{}", std::process::id()));
    for bad in ["0", "0.5", "nan", "7"] {
        let out = std::process::Command::new(common::bin())
            .args(["study", "drum", "--quick", "--aspects", bad, "--out"])
            .arg(&dir)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "--aspects {bad}: {err}");
        assert!(err.contains("--aspects"), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

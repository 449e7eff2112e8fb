//! Rolling resistance (Ai, Chen, Rotter & Ooi 2011) against closed forms.
//!
//! A disk of radius r, mass m, `I = ½mr²`, rolling without slip on a floor under a rolling
//! couple `M = μ_r R_r F_n` (R_r = r, F_n = mg): `m a = f`, `I α = −f r − M`, `a = α r` give
//! `a = −μ_r g/(1 + I/(mr²)) = −(2/3) μ_r g`, so it stops after `t = 3v₀/(2μ_r g)` and
//! `s = 3v₀²/(4μ_r g)` (literature notes §1.3). In the model the friction force acts at the
//! contact point, `ℓ = r − δ` below the centre (δ = mg/k_n), while `R_r = r`: then
//! `a = −μ_r g (r/ℓ)/(1 + r²/(2ℓ²)) = −(2/3)μ_r g (1 + δ/(3r) + O(δ²/r²))`. The tolerances below
//! are that bias's bound, `δ/r`, and no wider.
//!
//! On a slope β a disk held by EPSD's rolling spring needs the couple `m g r sin β`, at most
//! `μ_r r m g cos β`: it stays iff `tan β ≤ μ_r`; beyond, the spring sits at its cap and the
//! disk rolls down with `a = (2/3) g (sin β − μ_r cos β)` (§1.4).

use dem2d::contact_law::{
    ContactSpec, LinearDamping, NormalForce, RollingModel, RollingPart, Scaled,
};
use dem2d::dynamics::{BodyInit, World};
use dem2d::geometry::{Shape, Vec2};
use dem2d::run::{Simulation, Stop};
use std::f64::consts::PI;

mod common;
use common::floor;

const G: f64 = 980.0;
const KN: f64 = 36400.0 * G; // P's stiffness, ρ = 1

fn spec(friction: f64, rolling: Option<RollingPart>, damping: LinearDamping) -> ContactSpec {
    ContactSpec::linear(
        Scaled::Absolute(KN),
        Scaled::Absolute(KN),
        damping,
        friction,
    )
    .with_normal_force(NormalForce::Depth)
    .with_rolling(rolling)
}

fn rolling(model: RollingModel, mu_r: f64) -> Option<RollingPart> {
    Some(RollingPart {
        model,
        friction: mu_r,
        damping: None,
    })
}

/// A disk of radius `r` resting on the floor y = 0 (at its equilibrium overlap δ under g) with
/// velocity `v` along x, rolling without slip about its contact point (ω = −v/(r − δ));
/// gravity `gravity`.
fn disk_on_floor(r: f64, v: f64, gravity: Vec2, spec: ContactSpec, dt: f64) -> World {
    let m = PI * r * r;
    let delta = m * gravity.y.abs() / KN;
    let body = BodyInit {
        material: 0,
        prescribed: false,
        shape: Shape::Circle { r },
        position: Vec2::new(0.0, r - delta),
        angle: 0.0,
        velocity: Vec2::new(v, 0.0),
        omega: -v / (r - delta),
        density: 1.0,
    };
    let floor = floor(spec);
    World::new(&[body], vec![floor], gravity, spec, dt)
}

/// Least-squares slope of y against x.
fn slope(xs: &[f64], ys: &[f64]) -> f64 {
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

#[test]
fn cdt_disk_rolling_on_a_floor_decelerates_at_two_thirds_mu_r_g_and_stops_at_the_predicted_distance()
 {
    let (r, v0, dt) = (1.0, 20.0, 1e-5);
    let delta_over_r = PI * r * r * G / KN / r;
    for mu_r in [0.02, 0.05, 0.1] {
        let s = spec(
            0.5,
            rolling(RollingModel::Cdt, mu_r),
            LinearDamping::Restitution(0.5),
        );
        let mut w = disk_on_floor(r, v0, Vec2::new(0.0, -G), s, dt);
        let a_want = 2.0 / 3.0 * mu_r * G;
        let t_stop = 3.0 * v0 / (2.0 * mu_r * G);
        let s_want = 3.0 * v0 * v0 / (4.0 * mu_r * G);
        // Speed against time over the middle of the roll (away from the start's transient of
        // the shear spring loading up, and from the stop).
        let (mut ts, mut vs) = (Vec::new(), Vec::new());
        let mut stopped_at = None;
        Simulation::new(&mut w)
            .until_time(1.2 * t_stop)
            .run_each(|w, _| {
                let v = w.bodies.state[0].vel.x;
                if w.time > 0.1 * t_stop && w.time < 0.9 * t_stop && w.step.is_multiple_of(10) {
                    ts.push(w.time);
                    vs.push(v);
                }
                if stopped_at.is_none() && v <= 1e-9 * v0 {
                    stopped_at = Some((w.time, w.bodies.state[0].pose.position.x));
                }
            })
            .unwrap();
        let a = -slope(&ts, &vs);
        let (t, x) = stopped_at.expect("the disk stops");
        eprintln!(
            "CDT μ_r = {mu_r}: a = {a:.6} (want {a_want:.6}, rel {:.2e}), stop at t = {t:.5} s \
             (want {t_stop:.5}), x = {x:.5} cm (want {s_want:.5}, rel {:.2e}); δ/r = {delta_over_r:.2e}",
            a / a_want - 1.0,
            x / s_want - 1.0
        );
        assert!(
            (a / a_want - 1.0).abs() < delta_over_r,
            "deceleration {a} vs {a_want}"
        );
        assert!(
            (x / s_want - 1.0).abs() < delta_over_r,
            "stopping distance {x} vs {s_want}"
        );
        assert!((t / t_stop - 1.0).abs() < delta_over_r + dt / t_stop);
        // At rest it stays at rest: the limiter stops the chatter (|ω| would otherwise flip by
        // about μ_r r m g Δt/I_r every step, 2e-4 rad/s here).
        let s = &w.bodies.state[0];
        assert!(
            s.vel.norm() < 1e-7 && s.omega.abs() < 1e-7,
            "at rest after the stop: v = {:?}, ω = {}",
            s.vel,
            s.omega
        );
    }
}

/// A disk at rest on a slope of angle β (the floor y = 0 under gravity tilted by β), EPSD with
/// μ_r, for `time`: returns its displacement over the second half, its speed at the end, and its
/// acceleration (least squares over the second half: the first lets the springs load up).
fn on_slope(beta: f64, mu_r: f64, time: f64) -> (f64, f64, f64) {
    let gravity = Vec2::new(G * beta.sin(), -G * beta.cos());
    let s = spec(
        0.5,
        rolling(RollingModel::Epsd, mu_r),
        LinearDamping::Restitution(0.5),
    );
    let mut w = disk_on_floor(1.0, 0.0, gravity, s, 1e-5);
    let (mut ts, mut vs) = (Vec::new(), Vec::new());
    let mut x_half = None;
    Simulation::new(&mut w)
        .until_time(time)
        .run_each(|w, _| {
            if w.time >= 0.5 * time {
                x_half.get_or_insert(w.bodies.state[0].pose.position.x);
                if w.step.is_multiple_of(10) {
                    ts.push(w.time);
                    vs.push(w.bodies.state[0].vel.x);
                }
            }
        })
        .unwrap();
    let st = &w.bodies.state[0];
    (
        st.pose.position.x - x_half.unwrap(),
        st.vel.x,
        slope(&ts, &vs),
    )
}

#[test]
fn epsd_disk_on_a_slope_stays_iff_tan_beta_is_at_most_mu_r() {
    let mu_r: f64 = 0.1;
    let delta_over_r = PI * G / KN;
    // At and below the limit: held by the rolling spring — after the springs have loaded up
    // (a transient of a few ms), nothing moves.
    for ratio in [0.5, 0.98] {
        let beta = (ratio * mu_r).atan();
        let (dx, v, _) = on_slope(beta, mu_r, 0.4);
        eprintln!("tan β = {ratio} μ_r: moved {dx:.3e} cm over the last 0.2 s, v = {v:.3e} cm/s");
        assert!(
            dx.abs() < 1e-12 && v.abs() < 1e-12,
            "held: moved {dx}, v = {v}"
        );
    }
    // Above: the spring sits at its cap μ_r r F_n with the dashpot off, and the disk rolls
    // down with a = (2/3) g (sin β − μ_r cos β), to within δ/r of g sin β (the friction force's
    // lever is r − δ; see the module documentation).
    for ratio in [1.02, 1.5, 3.0] {
        let beta = (ratio * mu_r).atan();
        let (dx, _, a_got) = on_slope(beta, mu_r, 0.4);
        let a = 2.0 / 3.0 * G * (beta.sin() - mu_r * beta.cos());
        eprintln!(
            "tan β = {ratio} μ_r: rolls, a = {a_got:.6} cm/s² (want {a:.6}; error {:.2e} of g sin β)",
            (a_got - a) / (G * beta.sin())
        );
        assert!(dx > 0.0);
        assert!(
            (a_got - a).abs() < delta_over_r * G * beta.sin(),
            "{a_got} vs {a}"
        );
    }
}

/// The energy account `K + P + E_el + D` with a rolling part: an undamped elastic rolling
/// spring stores and returns what it takes (E_el carries it, D stays near 0); CDT dissipates
/// what the disk loses. A history spring's work is taken with the velocities at n+1 and its
/// energy change with those at n+½ (the shear spring's accounting, unchanged): the account of
/// an elastic history spring then oscillates, without drift, by about `Ω Δt` of the energy in
/// the oscillation (Ω its frequency) — the bound used.
#[test]
fn the_energy_account_closes_with_rolling_resistance() {
    let undamped = LinearDamping::Dashpots {
        eta_n: Scaled::Absolute(0.0),
        eta_s: Scaled::Absolute(0.0),
    };
    // EPSD, no dashpot anywhere, a spin small enough that the spring never reaches its cap:
    // the disk rocks about its contact point, elastically.
    let epsd = Some(RollingPart {
        model: RollingModel::Epsd,
        friction: 0.5,
        damping: Some(0.0),
    });
    let mut w = disk_on_floor(
        1.0,
        0.01,
        Vec2::new(0.0, -G),
        spec(0.5, epsd, undamped),
        1e-6,
    );
    let e0 = w.energies.total();
    let k0 = w.energies.kinetic;
    let (mut worst, mut most_stored) = (0.0f64, 0.0f64);
    Simulation::new(&mut w)
        .for_steps(20_000)
        .run_each(|w, _| {
            worst = worst.max((w.energies.total() - e0).abs());
            most_stored = most_stored.max(w.contacts.slots[0].history_energy);
            assert!(
                w.contacts.history_of(0).0[1].abs() < 0.5 * PI * G,
                "below the cap"
            );
        })
        .unwrap();
    eprintln!(
        "EPSD elastic: |ΔE| ≤ {worst:.3e} erg, initial kinetic {k0:.3e}, rolling spring held up to \
         {most_stored:.3e}, dissipated {:.3e}",
        w.energies.dissipated
    );
    // The stiffest rotation the rolling spring k_r = k_t r² drives: about the centroid,
    // Ω = √(k_r/I) = √(2k_t/m).
    let omega_dt = (2.0 * KN / PI).sqrt() * 1e-6;
    assert!(
        most_stored > 0.5 * k0,
        "the spring took the motion's energy: {most_stored}"
    );
    assert!(worst < omega_dt * k0, "energy error {worst} of {k0}");
    assert!(w.energies.dissipated.abs() < omega_dt * k0);
    // CDT: everything the disk had is dissipated, and the account closes.
    let s = spec(0.5, rolling(RollingModel::Cdt, 0.05), undamped);
    let mut w = disk_on_floor(1.0, 20.0, Vec2::new(0.0, -G), s, 1e-5);
    let e0 = w.energies.total();
    let k0 = w.energies.kinetic;
    Simulation::new(&mut w).until_time(0.8).run().unwrap();
    let e = w.energies;
    eprintln!(
        "CDT: kinetic {k0:.4e} → {:.3e}, dissipated {:.6e}, account error {:.2e}",
        e.kinetic,
        e.dissipated,
        e.total() - e0
    );
    assert!(e.kinetic < 1e-9 * k0);
    assert!(((e.total() - e0) / k0).abs() < 1e-4, "{}", e.total() - e0);
}

/// The rolling keys in a case: on the contact, and overridden per wall like any contact key (a
/// wall that changes the rolling model does not inherit the scene model's damping; μ_r = 0
/// switches the rolling part off).
#[test]
fn rolling_keys_are_read_and_walls_override_them() {
    let text = r#"{ "version": 1, "name": "t", "gravity": [0, -980], "dt": 1e-5, "duration": 0.1,
      "contact": { "model": "linear", "kn_over_rho_g": 36400, "restitution": 0.5, "friction": 0.3,
                   "rolling_model": "epsd", "rolling_friction": 0.05, "rolling_damping": 0.2 },
      "walls": [ { "point": [0, 0], "normal": [0, 1] },
                 { "point": [-5, 0], "normal": [1, 0], "rolling_model": "cdt" },
                 { "point": [5, 0], "normal": [-1, 0], "rolling_friction": 0 },
                 { "point": [0, 9], "normal": [0, -1], "rolling_friction": 0.2 } ],
      "bodies": [ { "shape": {"type": "circle", "r": 1}, "position": [0, 2] } ] }"#;
    let case = dem2d::scene::Case::from_json(text).unwrap();
    let epsd = RollingPart {
        model: RollingModel::Epsd,
        friction: 0.05,
        damping: Some(0.2),
    };
    assert_eq!(case.contact.rolling(), Some(epsd));
    assert_eq!(case.walls[0].spec.rolling(), Some(epsd));
    assert_eq!(
        case.walls[1].spec.rolling(),
        Some(RollingPart {
            model: RollingModel::Cdt,
            friction: 0.05,
            damping: None
        })
    );
    assert_eq!(case.walls[2].spec.rolling(), None);
    assert_eq!(
        case.walls[3].spec.rolling(),
        Some(RollingPart {
            friction: 0.2,
            ..epsd
        })
    );
}

/// Runs a case until P's criterion holds (the time at rest) or `limit` s.
fn rest_time(case: &dem2d::scene::Case, limit: f64) -> (World, Option<f64>) {
    let mut w = case.build_world();
    let stop = Simulation::new(&mut w)
        .until_time(limit)
        .quiescence(Some(case.quiescence_criterion().expect("quiescence")))
        .run()
        .unwrap();
    match stop {
        Stop::AtRest { since } => (w, Some(since as f64 * case.dt)),
        _ => (w, None),
    }
}

/// P Fig. 3: without rolling resistance the thrown circle rolls on and the ellipse rocks on for
/// ever (docs/src/results/paper-figures.md); with EPSD's μ_r = 0.05 both come to rest within the case's 3 s.
#[test]
fn the_thrown_circle_and_ellipse_of_p_fig_3_come_to_rest_with_rolling_resistance() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    for name in ["throw_circle", "throw_ellipse"] {
        let text = std::fs::read_to_string(root.join(format!("{name}.json"))).unwrap();
        let case = dem2d::scene::Case::from_json(&text).unwrap();
        let (_, never) = rest_time(&case, case.duration);
        assert_eq!(never, None, "{name} without rolling resistance");
        let rolling = case
            .clone()
            .map_contacts(|c| c.with_rolling(rolling(RollingModel::Epsd, 0.05)));
        let (w, at) = rest_time(&rolling, case.duration);
        eprintln!(
            "{name}, EPSD μ_r = 0.05: at rest at t = {at:?} s, x = {:.2} cm",
            w.bodies.state[0].pose.position.x
        );
        assert!(at.is_some(), "{name} comes to rest");
    }
}

/// The angle of repose of a small heap (100 disks released from a column by a withdrawing wall,
/// `dem2d study repose`'s protocol without the settling) rises with μ_r.
#[test]
fn the_angle_of_repose_of_a_heap_rises_with_rolling_friction() {
    use dem2d::dynamics::analysis::heap_surface;
    use dem2d::scene::generate::ColumnSpec;
    let column = ColumnSpec {
        n: 100,
        width: 12.5,
        seed: 5,
        friction: 0.5,
    };
    let bodies = column.lattice_bodies();
    let mut angles = Vec::new();
    for mu_r in [0.0, 0.1, 0.3] {
        let r = rolling(RollingModel::Epsd, mu_r);
        let text = column.case_json(
            "repose",
            &bodies,
            100.0,
            &r.map_or(vec![], |r| r.given()),
            "Rolling resistance: EPSD.",
        );
        let case = dem2d::scene::Case::from_json(&text).unwrap();
        let (w, at) = rest_time(&case, 2.5);
        let (angle, h, toe) = heap_surface(&w, 2.0);
        eprintln!(
            "μ_r = {mu_r}: angle {angle:.1}°, height {h:.1} cm, toe {toe:.1} cm, at rest {at:?}"
        );
        angles.push(angle);
    }
    assert!(
        angles[1] > angles[0] + 2.0 && angles[2] > angles[1] + 2.0,
        "{angles:?}"
    );
}

/// Issue 29, item 15 ("μ_r … whatever the shape"): the user guide said μ_r is the tangent of
/// the steepest slope a body holds whatever its shape, but a non-circular body holds itself by
/// its shape too. On a slope β, with ℓ the centroid's height above the slope and s how far
/// downhill of the centroid the contact point lies, the moments about the centroid balance with
/// a rolling couple `|m g (ℓ sin β − s cos β)| ≤ μ_r ℓ m g cos β`, i.e. `|tan β − s/ℓ| ≤ μ_r`
/// (R_r = ℓ on a wall). A disk has s = 0: `tan β ≤ μ_r`. An ellipse turned by θ from lying flat
/// has `s/ℓ = −(a² − b²) sin θ cos θ/(a² sin²θ + b² cos²θ)`, at most `(a² − b²)/(2ab)` (at
/// tan θ = −b/a): so it can rest iff `tan β ≤ μ_r + (a² − b²)/(2ab)` — 36.87° for a/b = 2
/// without rolling resistance, 43.53° with μ_r = 0.2. Each body is set down at rest in the
/// orientation of its equilibrium (or of the shape's limit where that is past reach) and must
/// stay there below the limit and roll away beyond it.
#[test]
fn an_ellipse_rests_on_slopes_up_to_mu_r_plus_its_shapes_own_limit() {
    let (a, b) = (2.0f64, 1.0f64);
    let ratio = |th: f64| {
        let (s, c) = th.sin_cos();
        -(a * a - b * b) * s * c / (a * a * s * s + b * b * c * c)
    };
    let th_max = -(b / a).atan();
    assert!((ratio(th_max) - (a * a - b * b) / (2.0 * a * b)).abs() < 1e-12);
    // The orientation whose contact point lies `target` ℓ downhill (bisection on the branch
    // from lying flat to the shape's limit, where the ratio rises monotonically).
    let orientation = |target: f64| {
        let (mut lo, mut hi) = (0.0, th_max);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if ratio(mid) < target {
                lo = mid
            } else {
                hi = mid
            }
        }
        lo
    };
    let limit = |mu_r: f64| (mu_r + (a * a - b * b) / (2.0 * a * b)).atan().to_degrees();
    assert!((limit(0.0) - 36.87).abs() < 0.01 && (limit(0.2) - 43.53).abs() < 0.01);
    for (beta_deg, mu_r, holds) in [
        (35.0, 0.0, true),
        (36.5, 0.0, true),
        (38.0, 0.0, false),
        (42.0, 0.2, true),
        (43.0, 0.2, true),
        (45.0, 0.2, false),
    ] {
        let beta = f64::to_radians(beta_deg);
        let th = if mu_r == 0.0 {
            orientation(beta.tan())
        } else {
            th_max
        };
        let (s, c) = th.sin_cos();
        let h = (a * a * s * s + b * b * c * c).sqrt();
        let law = spec(
            2.0,
            (mu_r > 0.0)
                .then(|| rolling(RollingModel::Epsd, mu_r))
                .flatten(),
            LinearDamping::Restitution(0.5),
        );
        let body = BodyInit {
            material: 0,
            prescribed: false,
            shape: Shape::Ellipse { a, b },
            position: Vec2::new(0.0, h),
            angle: th,
            velocity: Vec2::zeros(),
            omega: 0.0,
            density: 1.0,
        };
        let floor = floor(law);
        let gravity = Vec2::new(G * beta.sin(), -G * beta.cos());
        let mut w = World::new(&[body], vec![floor], gravity, law, 1e-5);
        Simulation::new(&mut w).for_steps(50_000).run().unwrap();
        let x = w.bodies.state[0].pose.position.x;
        let turned = (w.bodies.state[0].pose.angle() - th).abs();
        if holds {
            assert!(
                x.abs() < 1e-3 && turned < 1e-3,
                "{beta_deg}°, μ_r = {mu_r}: moved {x} cm, turned {turned} rad; should rest"
            );
        } else {
            assert!(
                x > 10.0,
                "{beta_deg}°, μ_r = {mu_r}: moved only {x} cm in 0.5 s; should roll away"
            );
        }
    }
}

//! `dem2d verify`'s ellipses under the area law (the default normal force), each against an
//! answer that does not come from dem2d:
//!
//! - **rocking**: an ellipse (a = 1.5, b = 1 cm) resting on its flat side, tilted by 0.03 rad
//!   and let go, rocks without slipping. A rigid body rolling on a plane, with its centroid at
//!   height h above the contact point where its outline's radius of curvature is R, rocks about
//!   the contact point with `ω² = m g (R − h) / (I + m h²)` for small angles; for the ellipse
//!   `h = b`, `R = a²/b`, `I = m (a² + b²)/4`: the period `T = 2π √((a² + b²)/4 + b²) /
//!   √(g (a²/b − b))` = 0.2417 s. Measured from the zero crossings of the angle.
//! - **tilted drop**: the same ellipse, tilted by θ, moving onto a frictionless floor at v with
//!   no gravity and no dashpot. A rigid impact at the lowest point (horizontal offset r from the
//!   centroid) with restitution 1 reverses the contact point's normal velocity: the impulse is
//!   `J = 2 m v / (1 + m r²/I)`, so `v' = −v + J/m` and `ω' = J r/I`. With a stiff contact the
//!   ellipse turns little while it touches, and the rebound approaches these values.
//! - **incline equilibrium**: an ellipse a/b = 2 laid on its flat side on an incline of angle β
//!   (friction 1: it cannot slide) rolls down until its centroid is above the contact point:
//!   where the outline's normal makes the angle β with the radius to the contact point,
//!   `cos β = ab / (|P| |N|)` for the point `P = (a cos t, b sin t)` with normal
//!   `N = (b cos t, a sin t)`; with `u = cos² t`: `u (1 − u) = a²b² tan²β / (a² − b²)²`, the
//!   smaller root stable. The centroid then rests at the height `ab/|N|` above the incline
//!   (1.0756 cm at β = 30°, against b = 1 lying flat). No such point exists beyond
//!   `tan β = (a² − b²)/(2ab)` (36.87° for a/b = 2): on a 40° incline it rolls away.
//! - **loop work**: the area law is the gradient of a potential, so the work of its force and
//!   moment around any closed loop of poses is zero; P's spring on the depth is not, and its
//!   loops gain work (the control: the check can fail).

use dem2d::contact_law::{ContactSpec, LinearDamping, NormalForce, Scaled};
use dem2d::dynamics::{BodyInit, Boundary, World};
use dem2d::geometry::{Shape, Vec2, Wall};
use dem2d::run::{RunError, Simulation};
use dem2d::scene::Case;

use crate::verify::Check;

const G: f64 = 980.0;

fn spec(kn: f64, damping: LinearDamping, friction: f64, nf: NormalForce) -> ContactSpec {
    ContactSpec::linear(
        Scaled::Absolute(kn),
        Scaled::Absolute(kn),
        damping,
        friction,
    )
    .with_normal_force(nf)
}

fn undamped() -> LinearDamping {
    LinearDamping::Dashpots {
        eta_n: Scaled::Absolute(0.0),
        eta_s: Scaled::Absolute(0.0),
    }
}

fn ellipse(a: f64, b: f64, x: Vec2, angle: f64, v: Vec2) -> BodyInit {
    BodyInit {
        material: 0,
        prescribed: false,
        shape: Shape::Ellipse { a, b },
        position: x,
        angle,
        velocity: v,
        omega: 0.0,
        density: 1.0,
    }
}

/// Height of the lowest point of an (a, b) ellipse at `angle` below its centroid, and that
/// point's horizontal offset from the centroid.
fn lowest(a: f64, b: f64, angle: f64) -> (f64, f64) {
    let (s, c) = angle.sin_cos();
    let h = (a * a * s * s + b * b * c * c).sqrt();
    // The support point in direction −y: −R diag(a², b²) Rᵀ ŷ / h.
    (h, -(a * a - b * b) * s * c / h)
}

/// The rocking period of the ellipse on a floor (see the module documentation).
fn rocking() -> Result<Vec<Check>, RunError> {
    let (a, b) = (1.5, 1.0);
    let theta0: f64 = 0.03;
    // P's stiffness (k_n = 36400 ρ g), a dashpot for the bounce of the first touch.
    let s = spec(
        36400.0 * G,
        LinearDamping::Restitution(0.3),
        1.0,
        NormalForce::Area,
    );
    let (h, _) = lowest(a, b, theta0);
    let floor = Boundary::new(Wall::new(Vec2::zeros(), Vec2::y()).expect("wall"), s);
    let mut w = Case::new(
        vec![ellipse(a, b, Vec2::new(0.0, h), theta0, Vec2::zeros())],
        vec![floor],
        Vec2::new(0.0, -G),
        s,
        1e-5,
    )
    .build_world();
    let angle = |w: &World| w.bodies.state[0].pose.angle();
    // Zero crossings of the angle, interpolated within the step.
    let mut crossings = Vec::new();
    let mut last = angle(&w);
    Simulation::new(&mut w).until_time(2.0).run_until(|w, _| {
        let now = angle(w);
        if (now < 0.0) != (last < 0.0) {
            crossings.push(w.time - w.dt * now / (now - last));
        }
        last = now;
        crossings.len() >= 9
    })?;
    let measured = if crossings.len() >= 9 {
        // Four whole periods from the first crossing to the ninth.
        (crossings[8] - crossings[0]) / 4.0
    } else {
        f64::NAN
    };
    let expected = 2.0
        * std::f64::consts::PI
        * (((a * a + b * b) / 4.0 + b * b) / (G * (a * a / b - b))).sqrt();
    let tol = 5e-3;
    Ok(vec![Check::relative(
        format!(
            "ellipse a = {a}, b = {b} rocking on a floor (area law, tilted {theta0} rad): period (s)"
        ),
        measured,
        expected,
        "rigid body rolling: 2π √((I + m b²)/(m g (a²/b − b)))",
        tol,
    )])
}

/// The rebound of the tilted ellipse from a frictionless floor (see the module documentation).
fn tilted_drop() -> Result<Vec<Check>, RunError> {
    let (a, b) = (1.5, 1.0);
    let (theta, v) = (0.5f64, 50.0);
    let kn = 1e10;
    let s = spec(kn, undamped(), 0.0, NormalForce::Area);
    let (h, r) = lowest(a, b, theta);
    let floor = Boundary::new(Wall::new(Vec2::zeros(), Vec2::y()).expect("wall"), s);
    let mut w = Case::new(
        vec![ellipse(
            a,
            b,
            Vec2::new(0.0, h + 1e-3),
            theta,
            Vec2::new(0.0, -v),
        )],
        vec![floor],
        Vec2::zeros(),
        s,
        2e-8,
    )
    .build_world();
    // Until the first step after the contact.
    let mut touched = false;
    Simulation::new(&mut w)
        .until_time(1e-3)
        .run_until(|_, report| {
            if report.contacts > 0 {
                touched = true;
                return false;
            }
            touched
        })?;
    let m = w.bodies.mass[0];
    let i = w.bodies.inertia[0];
    let j = 2.0 * m * v / (1.0 + m * r * r / i);
    let (vy, omega) = (-v + j / m, j * r / i);
    let st = w.bodies.state[0];
    let tol = 2e-3;
    Ok(vec![
        Check::relative(
            format!(
                "ellipse a = {a}, b = {b} tilted {theta} rad onto a frictionless floor at {v} cm/s, undamped (area law): v_y' (cm/s)"
            ),
            st.vel.y,
            vy,
            "rigid impact, e = 1: −v + J/m, J = 2mv/(1 + m r²/I)",
            tol,
        ),
        Check::relative(
            format!(
                "ellipse a = {a}, b = {b} tilted {theta} rad onto a frictionless floor: ω' (rad/s)"
            ),
            st.omega,
            omega,
            &format!("rigid impact: J r/I, r = {r:.4} cm"),
            tol,
        ),
    ])
}

/// The resting pose of an (a, b) ellipse on the incline through the origin with normal `n`
/// (angle β), its contact point at the parameter `t`: the body's angle and centroid such that
/// `P(t)` is at the origin and its outward normal points into the incline.
fn pose_on_incline(a: f64, b: f64, n: Vec2, t: f64) -> (f64, Vec2) {
    let (p, nb) = (
        Vec2::new(a * t.cos(), b * t.sin()),
        Vec2::new(b * t.cos(), a * t.sin()),
    );
    let phi = (-n.y).atan2(-n.x) - nb.y.atan2(nb.x);
    let (s, c) = phi.sin_cos();
    (phi, -Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y))
}

/// The ellipse on an incline (see the module documentation). Nothing damps a rolling rock (the
/// contact point is at rest), so the check is of the pose: placed at rest at the closed-form
/// resting pose it stays (turns by less than 1e-3 rad in 1 s); placed 0.02 (in `t`) beside it,
/// it rocks (the control); on a 40° incline, placed at the pose that comes closest to holding
/// (`u = ½`), it rolls away.
fn incline() -> Result<Vec<Check>, RunError> {
    let (a, b) = (2.0, 1.0);
    let (aa, bb) = (a * a, b * b);
    // Largest turn from the starting angle within 1 s, starting at rest at contact parameter t.
    let turn = |beta: f64, t: f64| -> Result<f64, RunError> {
        let n = Vec2::new(-beta.sin(), beta.cos());
        let s = spec(
            36400.0 * G,
            LinearDamping::Restitution(0.3),
            1.0,
            NormalForce::Area,
        );
        let incline = Boundary::new(Wall::new(Vec2::zeros(), n).expect("wall"), s);
        let (phi, x) = pose_on_incline(a, b, n, t);
        let mut w = Case::new(
            vec![ellipse(a, b, x, phi, Vec2::zeros())],
            vec![incline],
            Vec2::new(0.0, -G),
            s,
            1e-5,
        )
        .build_world();
        let mut most = 0.0f64;
        Simulation::new(&mut w)
            .until_time(1.0)
            .run_each(|w, _| most = most.max((w.bodies.state[0].pose.angle() - phi).abs()))?;
        Ok(most)
    };
    // The stable resting point at β: the root u₁ of u(1 − u) = c, as a contact parameter t
    // (of the two with cos²t = u₁, the one whose centroid is above the contact point).
    let resting = |beta: f64, u: f64| -> f64 {
        let n = Vec2::new(-beta.sin(), beta.cos());
        [-(u.sqrt()).acos(), -(-u.sqrt()).acos()]
            .into_iter()
            .min_by(|&p, &q| {
                let off = |t: f64| pose_on_incline(a, b, n, t).1.x.abs();
                off(p).total_cmp(&off(q))
            })
            .expect("two")
    };
    let beta = 30f64.to_radians();
    let c = aa * bb * beta.tan().powi(2) / (aa - bb).powi(2);
    let u = 0.5 * (1.0 - (1.0 - 4.0 * c).sqrt());
    let t = resting(beta, u);
    let height = a * b / (bb * u + aa * (1.0 - u)).sqrt();
    let stays = turn(beta, t)?;
    let beside = turn(beta, t + 0.02)?;
    let limit = ((aa - bb) / (2.0 * a * b)).atan().to_degrees();
    let beta40 = 40f64.to_radians();
    let away = turn(beta40, resting(beta40, 0.5))?;
    Ok(vec![
        Check {
            quantity: format!(
                "ellipse a/b = 2 at rest on a 30° incline at the closed-form resting pose \
                 (centroid {height:.4} cm above the incline; friction 1, no rolling resistance, \
                 area law): largest turn in 1 s (rad)"
            ),
            value: stays,
            reference:
                "0 (at rest: the centroid above the contact point, u(1 − u) = a²b² tan²β/(a² − b²)²)"
                    .into(),
            tolerance: "≤ 1e-3".into(),
            pass: stays <= 1e-3,
        },
        Check {
            quantity:
                "the same ellipse placed 0.02 beside it (in the contact's parameter): largest turn in \
                 1 s (rad)"
                    .into(),
            value: beside,
            reference: "> 0 (the control: it rocks about the resting pose)".into(),
            tolerance: "> 1e-2".into(),
            pass: beside > 1e-2,
        },
        Check {
            quantity:
                "ellipse a/b = 2 on a 40° incline, placed where it comes closest to holding: largest \
                 turn in 1 s (rad)"
                    .into(),
            value: away,
            reference: format!(
                "rolls away: no resting point beyond tan β = (a² − b²)/(2ab), β = {limit:.2}°"
            ),
            tolerance: "> 1".into(),
            pass: away > 1.0,
        },
    ])
}

/// Force and moment on body j (the second) from i — a body, or a wall when `i` is `None` — as
/// the step computes them, at rest.
fn force_on_j(i: Option<BodyInit>, j: BodyInit, nf: NormalForce) -> (Vec2, f64) {
    let s = spec(1.0, undamped(), 0.0, nf);
    let (bodies, walls, k) = match i {
        Some(i) => (vec![i, j], vec![], 1),
        None => (
            vec![j],
            vec![Boundary::new(
                Wall::new(Vec2::zeros(), Vec2::y()).expect("wall"),
                s,
            )],
            0,
        ),
    };
    let w = Case::new(bodies, walls, Vec2::zeros(), s, 1e-6).build_world();
    (w.bodies.force[k], w.bodies.torque[k])
}

/// Work of the force and moment on `j` around the closed loop through `corners` (offsets in
/// x, y, θ from j's pose), each leg by 16-point Gauss–Legendre quadrature; with the mean |F|.
fn loop_work(
    i: Option<BodyInit>,
    j: BodyInit,
    corners: [[f64; 3]; 4],
    nf: NormalForce,
) -> (f64, f64) {
    const X: [f64; 8] = [
        0.0950125098376374,
        0.2816035507792589,
        0.4580167776572274,
        0.6178762444026438,
        0.755404408355003,
        0.8656312023878318,
        0.9445750230732326,
        0.9894009349916499,
    ];
    const W: [f64; 8] = [
        0.1894506104550685,
        0.1826034150449236,
        0.1691565193950025,
        0.1495959888165767,
        0.1246289712555339,
        0.0951585116824928,
        0.0622535239386479,
        0.0271524594117541,
    ];
    let (mut work, mut mean) = (0.0, 0.0);
    for leg in 0..4 {
        let (a, z) = (corners[leg], corners[(leg + 1) % 4]);
        let d = [z[0] - a[0], z[1] - a[1], z[2] - a[2]];
        for (x, wt) in X
            .iter()
            .flat_map(|&x| [x, -x])
            .zip(W.iter().flat_map(|&w| [w, w]))
        {
            let s = 0.5 * (1.0 + x);
            let p = BodyInit {
                position: j.position + Vec2::new(a[0] + s * d[0], a[1] + s * d[1]),
                angle: j.angle + a[2] + s * d[2],
                ..j
            };
            let (f, m) = force_on_j(i, p, nf);
            mean += 0.125 * wt * f.norm();
            work += 0.5 * wt * (f.x * d[0] + f.y * d[1] + m * d[2]);
        }
    }
    (work, mean)
}

/// Loops in (x, θ) of an ellipse pair and in (y, θ) of an ellipse on a floor: the work per turn
/// in units of the mean |F| times the loop's extent.
fn loops() -> Vec<Check> {
    let e = |x: f64, y: f64, t: f64| ellipse(1.5, 1.0, Vec2::new(x, y), t, Vec2::zeros());
    let cases = [
        (
            "an ellipse pair, a loop in (x, θ) of ±0.03 cm, ±0.3 rad",
            Some(e(0.0, 0.0, 0.3)),
            e(2.45, 0.2, 0.9),
            [
                [-0.03, 0.0, -0.3],
                [0.03, 0.0, -0.3],
                [0.03, 0.0, 0.3],
                [-0.03, 0.0, 0.3],
            ],
            0.06,
        ),
        (
            "an ellipse on a floor, a loop in (y, θ) of ±0.02 cm, ±0.3 rad",
            None,
            e(0.0, 0.95, 0.6),
            [
                [0.0, -0.02, -0.3],
                [0.0, 0.02, -0.3],
                [0.0, 0.02, 0.3],
                [0.0, -0.02, 0.3],
            ],
            0.04,
        ),
    ];
    let mut rows = Vec::new();
    for (what, i, j, corners, size) in cases {
        let (w_area, f_area) = loop_work(i, j, corners, NormalForce::Area);
        let (w_depth, f_depth) = loop_work(i, j, corners, NormalForce::Depth);
        let (gain_area, gain_depth) = (
            w_area.abs() / (f_area * size),
            w_depth.abs() / (f_depth * size),
        );
        rows.push(Check {
            quantity: format!("{what}: work per turn / (mean force × extent), area law"),
            value: gain_area,
            reference: "0 (the force and moment are −∇ of the overlap-area potential)".into(),
            tolerance: "≤ 1e-9".into(),
            pass: gain_area <= 1e-9,
        });
        rows.push(Check {
            quantity: format!("{what}: the same, P's spring on the depth (the control)"),
            value: gain_depth,
            reference: "> 0 (not a gradient: its loops gain work)".into(),
            tolerance: "> 0.05".into(),
            pass: gain_depth > 0.05,
        });
    }
    rows
}

/// Every ellipse comparison (a second or two); a run that blows up is the error.
pub fn checks() -> Result<Vec<Check>, RunError> {
    let mut rows = rocking()?;
    rows.extend(tilted_drop()?);
    rows.extend(incline()?);
    rows.extend(loops());
    Ok(rows)
}

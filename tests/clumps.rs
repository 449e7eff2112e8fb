//! Rigid clumps of disks as a shape (issue 16, item 2), against independent references:
//!
//! - **the union's area, centroid and polar moment** (computed exactly by Green's theorem over
//!   the exposed arcs) against closed forms — two overlapping disks (the lens formula), disjoint
//!   disks (sums and the parallel-axis theorem), one disk inside another — and against a
//!   brute-force midpoint grid written here, whose error is bounded by the band of cells the
//!   boundary crosses and which converges to the exact values as the grid is refined;
//! - **member contacts**: a clump of one disk steps like the circle (to rounding); a two-disk
//!   clump pressed into a floor has the force and moment of two linear springs by hand;
//! - **swap symmetry** of a clump pair and the **work around a closed loop** in (x, y, θ) of a
//!   frictionless undamped clump pair (zero: central linear springs are conservative);
//! - a **dropped clump comes to rest** on a floor with the energy account closed;
//! - the **equal-area ellipse fit** has the ellipse's area.

use dem2d::contact_law::ContactSpec;
use dem2d::dynamics::{BodyInit, World};
use dem2d::geometry::{Clump, Shape, Vec2};
use dem2d::run::Simulation;
use std::f64::consts::PI;

mod common;
use common::{body, floor, linear, worst_energy_error};

fn clump(disks: &[([f64; 2], f64)]) -> Clump {
    Clump::new(disks).unwrap()
}

/// Area, centroid and polar moment about the centroid over area (`I/m`) of a union of disks by
/// the midpoint rule on an `n × n` grid over its bounding box: `(A, c̄, I/m)`.
fn grid_moments(disks: &[([f64; 2], f64)], n: usize) -> (f64, Vec2, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (c, r) in disks {
        x0 = x0.min(c[0] - r);
        x1 = x1.max(c[0] + r);
        y0 = y0.min(c[1] - r);
        y1 = y1.max(c[1] + r);
    }
    let (hx, hy) = ((x1 - x0) / n as f64, (y1 - y0) / n as f64);
    let (mut a, mut sx, mut sy, mut s2) = (0.0, 0.0, 0.0, 0.0);
    for ix in 0..n {
        let x = x0 + (ix as f64 + 0.5) * hx;
        for iy in 0..n {
            let y = y0 + (iy as f64 + 0.5) * hy;
            if disks
                .iter()
                .any(|(c, r)| (x - c[0]).powi(2) + (y - c[1]).powi(2) <= r * r)
            {
                a += 1.0;
                sx += x;
                sy += y;
                s2 += x * x + y * y;
            }
        }
    }
    let cell = hx * hy;
    let area = a * cell;
    let c = Vec2::new(sx / a, sy / a);
    (area, c, s2 / a - c.norm_squared())
}

#[test]
fn union_moments_match_the_closed_forms() {
    // Two overlapping disks: A = π r1² + π r2² − lens, the lens by its closed form.
    let (r1, r2, d) = (1.0f64, 0.7f64, 1.2f64);
    let lens = r1 * r1 * ((d * d + r1 * r1 - r2 * r2) / (2.0 * d * r1)).acos()
        + r2 * r2 * ((d * d + r2 * r2 - r1 * r1) / (2.0 * d * r2)).acos()
        - 0.5 * ((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2)).sqrt();
    let c = clump(&[([0.3, -0.2], r1), ([0.3 + d, -0.2], r2)]);
    let want = PI * (r1 * r1 + r2 * r2) - lens;
    assert!(
        (c.area - want).abs() < 4.0 * f64::EPSILON * want,
        "{} {want}",
        c.area
    );

    // Disjoint disks: sums, and I/m by the parallel-axis theorem.
    let disks = [([0.0, 0.0], 1.0), ([3.0, 1.0], 0.5), ([-1.0, 4.0], 0.8)];
    let c = clump(&disks);
    let m: Vec<f64> = disks.iter().map(|(_, r)| PI * r * r).collect();
    let total: f64 = m.iter().sum();
    let cbar = disks.iter().zip(&m).fold(Vec2::zeros(), |s, ((p, _), mk)| {
        s + Vec2::new(p[0], p[1]) * *mk
    }) / total;
    let j: f64 = disks
        .iter()
        .zip(&m)
        .map(|((p, r), mk)| mk * (0.5 * r * r + (Vec2::new(p[0], p[1]) - cbar).norm_squared()))
        .sum();
    assert!((c.area - total).abs() < 4.0 * f64::EPSILON * total);
    assert!((c.shift - cbar).norm() < 1e-15 * 4.0);
    assert!((c.inertia_per_mass - j / total).abs() < 1e-14 * (j / total));

    // One disk inside another: the outer disk alone.
    let c = clump(&[([0.5, 0.5], 1.0), ([0.9, 0.3], 0.3)]);
    assert_eq!(c.area, PI);
    assert!((c.shift - Vec2::new(0.5, 0.5)).norm() < 1e-15);
    assert!((c.inertia_per_mass - 0.5).abs() < 1e-15);
    // A member's centre is relative to the union's centroid: the body's pose is its centroid.
    assert!((c.member(1).0 - Vec2::new(0.4, -0.2)).norm() < 1e-15);
}

#[test]
fn union_moments_match_a_brute_force_grid() {
    // Three overlapping disks with a hole-free, non-convex union. The midpoint grid misclassifies
    // only cells the boundary crosses: their number is at most (perimeter / h + 4)·2 for cells of
    // side h, the perimeter at most Σ 2π r_k; so |A_grid − A| ≤ 2 (Σ 2π r_k + 4h) h. The grid
    // must come within that bound at every size (a bound that falls as 1/n: convergence).
    let disks = [([0.0, 0.0], 1.0), ([1.1, 0.4], 0.8), ([0.4, 1.2], 0.6)];
    let c = clump(&disks);
    let perimeter: f64 = disks.iter().map(|(_, r)| 2.0 * PI * r).sum();
    let mut last = f64::INFINITY;
    for n in [250usize, 500, 1000, 2000] {
        let (a, cbar, ipm) = grid_moments(&disks, n);
        let h = 3.0 / n as f64; // ≥ the cell's longer side (the box is under 3 × 3)
        let bound = 2.0 * (perimeter + 4.0 * h) * h;
        let err = (a - c.area).abs();
        println!(
            "n = {n}: |ΔA| = {err:.2e} (bound {bound:.2e}), |Δc̄| = {:.2e}, |Δ(I/m)| = {:.2e}",
            (cbar - c.shift).norm(),
            (ipm - c.inertia_per_mass).abs()
        );
        assert!(err <= bound, "n = {n}: {err} > {bound}");
        // The centroid and I/m are ratios of moments with the same band of error cells (lever
        // arms under 3): a relative error at most 3·bound/A (centroid) and 2·9·bound/A (I/m).
        assert!((cbar - c.shift).norm() <= 3.0 * bound / c.area * 2.0);
        assert!((ipm - c.inertia_per_mass).abs() <= 18.0 * bound / c.area * 2.0);
        last = err;
    }
    assert!(last < 2e-4 * c.area, "{last}");
}

#[test]
fn the_ellipse_fit_has_the_ellipse_area() {
    for (k, a, b) in [
        (3usize, 1.5f64, 1.0f64),
        (5, 2.0, 1.0),
        (9, 3.0, 1.0),
        (17, 3.0, 1.0),
    ] {
        let disks = Clump::ellipse_fit(k, a, b);
        assert_eq!(disks.len(), k);
        let c = clump(&disks);
        // Against the grid (independent of the arcs), within its band bound.
        let (ag, _, _) = grid_moments(&disks, 1500);
        let h = 2.0 * a * 1.2 / 1500.0;
        let perimeter: f64 = disks.iter().map(|(_, r)| 2.0 * PI * r).sum();
        assert!((ag - PI * a * b).abs() <= 2.0 * (perimeter + 4.0 * h) * h);
        assert!((c.area - PI * a * b).abs() < 1e-13 * PI * a * b, "{k} {a}");
        // Symmetric about the centre: centroid at the middle member.
        assert!(c.shift.norm() < 1e-13, "{:?}", c.shift);
        // Every member inside the ellipse's bounding box (scaled by at most the area factor).
        for (p, r) in &disks {
            assert!(p[0].abs() + r <= a * 1.2 && *r <= b * 1.2, "{k}: {p:?} {r}");
        }
    }
}

#[test]
fn a_clump_of_one_disk_steps_like_the_circle() {
    // Dropped tilted and spinning onto a rough floor with damping: the same run as a circle.
    let spec = linear(36400.0 * 980.0 * PI, 50.0, 0.4);
    let run = |shape: Shape| {
        let mut b = body(shape, Vec2::new(0.2, 1.5), 0.3);
        b.velocity = Vec2::new(20.0, 0.0);
        b.omega = 5.0;
        let mut w = World::new(&[b], vec![floor(spec)], Vec2::new(0.0, -980.0), spec, 1e-5);
        Simulation::new(&mut w).for_steps(20_000).run().unwrap();
        let s = w.bodies.state[0];
        (
            s.pose.position,
            s.pose.angle(),
            s.vel,
            s.omega,
            w.energies.total(),
        )
    };
    let one = Shape::Clump(clump(&[([3.0, -1.0], 1.0)]));
    let (pc, ac, vc, wc, ec) = run(Shape::Circle { r: 1.0 });
    let (pk, ak, vk, wk, ek) = run(one);
    println!("circle {pc:?} {ac} {vc:?} {wc}\nclump  {pk:?} {ak} {vk:?} {wk}");
    // Mass π r² and I/m = r²/2 come from the union's formulas, rounded differently from the
    // circle's (an ulp): equal to rounding, not bit for bit.
    assert!((pc - pk).norm() <= 1e-12 * pc.norm(), "{pc:?} {pk:?}");
    assert!((ac - ak).abs() <= 1e-12 * ac.abs().max(1.0));
    assert!((vc - vk).norm() <= 1e-12 * vc.norm().max(1.0));
    assert!((wc - wk).abs() <= 1e-12 * wc.abs().max(1.0));
    assert!((ec - ek).abs() <= 1e-12 * ec.abs());
}

#[test]
fn a_two_disk_clump_pressed_into_a_floor_has_the_hand_force_and_moment() {
    // Members r = 0.5 at (±0.6, 0) (disjoint: the centroid is the midpoint), the body turned by
    // θ and lowered so that both members overlap the floor: member k's centre is at height
    // y + sinθ x_k, its depth δ_k = r − y − sinθ x_k, its force k_n δ_k up at lever cosθ x_k.
    let kn = 1e5;
    let spec = linear(kn, 0.0, 0.0);
    let c = Shape::Clump(clump(&[([-0.6, 0.0], 0.5), ([0.6, 0.0], 0.5)]));
    let (y, th) = (0.45f64, 0.05f64);
    let w = World::new(
        &[body(c, Vec2::new(2.0, y), th)],
        vec![floor(spec)],
        Vec2::zeros(),
        spec,
        1e-6,
    );
    let (mut f, mut m) = (0.0, 0.0);
    for xk in [-0.6f64, 0.6] {
        let d = 0.5 - y - th.sin() * xk;
        assert!(d > 0.0);
        f += kn * d;
        m += th.cos() * xk * kn * d;
    }
    let (fw, mw) = (w.bodies.force[0], w.bodies.torque[0]);
    assert!(fw.x.abs() < 1e-12 * f, "{fw:?}");
    assert!((fw.y - f).abs() < 1e-12 * f, "{} {f}", fw.y);
    assert!((mw - m).abs() < 1e-12 * f, "{mw} {m}");
    assert_eq!(w.contacts.len(), 2, "one contact per member");
}

fn pair_forces(a: BodyInit, b: BodyInit, spec: ContactSpec) -> [(Vec2, f64); 2] {
    let w = World::new(&[a, b], vec![], Vec2::zeros(), spec, 1e-6);
    [0, 1].map(|k| (w.bodies.force[k], w.bodies.torque[k]))
}

fn three() -> Clump {
    clump(&[([0.0, 0.0], 0.6), ([0.7, 0.1], 0.45), ([-0.5, 0.4], 0.35)])
}

#[test]
fn a_clump_pair_is_swap_symmetric() {
    let spec = linear(1e5, 0.0, 0.5);
    let (p, q) = (
        Shape::Clump(three()),
        Shape::Clump(clump(&[([0.0, 0.0], 0.5), ([0.6, 0.0], 0.5)])),
    );
    let a = body(p, Vec2::new(0.1, 0.05), 0.4);
    let b = body(q, Vec2::new(1.25, 0.3), -0.7);
    let [(fa, ma), (fb, mb)] = pair_forces(a, b, spec);
    let [(gb, nb), (ga, na)] = pair_forces(b, a, spec);
    assert!(fa.norm() > 0.0, "the pair must touch");
    assert_eq!(
        (fa, ma),
        (ga, na),
        "swapping the bodies changes nothing for a"
    );
    assert_eq!((fb, mb), (gb, nb));
    assert!((fa + fb).norm() <= 1e-15 * fa.norm() * 4.0, "{fa:?} {fb:?}");
    // Angular momentum: the moments about the origin balance.
    let cross = |r: Vec2, f: Vec2| r.x * f.y - r.y * f.x;
    let l = ma + mb + cross(a.position, fa) + cross(b.position, fb);
    assert!(l.abs() < 1e-12 * fa.norm(), "{l}");
    // And a clump against a circle, an ellipse and a polygon: opposite forces either way.
    for other in [
        Shape::Circle { r: 0.5 },
        Shape::Ellipse { a: 0.8, b: 0.4 },
        Shape::Polygon(dem2d::geometry::Polygon::regular(5, 0.6, 0.1).unwrap()),
        Shape::Rectangle { w: 1.0, h: 0.6 },
    ] {
        let o = body(other, Vec2::new(1.0, 0.5), 0.3);
        let [(f1, m1), (f2, _)] = pair_forces(a, o, spec);
        let [(g2, _), (g1, n1)] = pair_forces(o, a, spec);
        assert!(f1.norm() > 0.0, "{other:?} must touch");
        assert!((f1 + f2).norm() <= 1e-14 * f1.norm(), "{other:?}");
        assert!(
            (f1 - g1).norm() <= 1e-14 * f1.norm(),
            "{other:?}: {f1:?} {g1:?}"
        );
        assert!((m1 - n1).abs() <= 1e-13 * f1.norm(), "{other:?}: {m1} {n1}");
        assert!((f2 - g2).norm() <= 1e-14 * f1.norm());
    }
}

#[test]
fn a_frictionless_clump_pair_does_no_work_around_a_closed_loop() {
    // j moves around a smooth closed loop in (x, y, θ) against a fixed i, with every member
    // pair that touches staying in contact (so the force is smooth along the loop and the
    // periodic trapezoid rule converges spectrally). W = ∮ F·dx + M dθ must vanish: the member
    // contacts are central linear springs on δ = r_a + r_b − |c_a − c_b|, with potential ½ k δ².
    let spec = linear(1e5, 0.0, 0.0);
    let ci = Shape::Clump(clump(&[([0.0, 0.0], 0.6), ([0.0, 1.2], 0.5)]));
    let cj = Shape::Clump(clump(&[([0.0, 0.0], 0.55), ([0.0, 1.2], 0.55)]));
    let a = body(ci, Vec2::zeros(), 0.0);
    let path = |s: f64| {
        let t = 2.0 * PI * s;
        (
            Vec2::new(0.9 + 0.04 * t.cos(), 0.1 + 0.06 * t.sin()),
            0.08 * (t.sin() + 0.5 * (2.0 * t).cos()),
        )
    };
    let dpath = |s: f64| {
        let t = 2.0 * PI * s;
        (
            Vec2::new(-0.04 * t.sin(), 0.06 * t.cos()) * (2.0 * PI),
            0.08 * (t.cos() - (2.0 * t).sin()) * (2.0 * PI),
        )
    };
    let n = 2000;
    let (mut work, mut scale) = (0.0, 0.0);
    let mut touching = usize::MAX;
    for k in 0..n {
        let s = k as f64 / n as f64;
        let (x, th) = path(s);
        let (dx, dth) = dpath(s);
        let w = World::new(&[a, body(cj, x, th)], vec![], Vec2::zeros(), spec, 1e-6);
        let c = w.contacts.len();
        if touching == usize::MAX {
            touching = c;
        }
        assert_eq!(
            c, touching,
            "the set of member contacts changes along the loop"
        );
        let (f, m) = (w.bodies.force[1], w.bodies.torque[1]);
        work += (f.dot(&dx) + m * dth) / n as f64;
        scale += (f.norm() * dx.norm() + m.abs() * dth.abs()) / n as f64;
    }
    println!("{touching} member contacts; W = {work:.3e}, ∮|F||dx| = {scale:.3e}");
    assert!(touching >= 2, "more than one member contact along the loop");
    assert!(work.abs() < 1e-12 * scale, "W = {work:e} against {scale:e}");
}

#[test]
fn a_dropped_clump_comes_to_rest_and_its_energy_account_closes() {
    // A 5-disk clump fitted to the 2:1 ellipse dropped tilted onto a floor.
    // (1) Undamped and frictionless: the account kinetic + potential + elastic stays at its
    //     initial value to velocity Verlet's O(Δt²): halving Δt twice must cut the largest
    //     drift by more than 8 (16 expected).
    // (2) Damped and rough, a dumbbell of two overlapping disks (the ellipse fit would roll
    //     freely on its middle member, centred at its centroid, for many seconds: no rolling
    //     resistance): it comes to rest on both members, and kinetic + potential + elastic +
    //     dissipated converges to its initial value as Δt → 0.
    let c = Shape::Clump(clump(&Clump::ellipse_fit(
        5,
        2.0f64.sqrt() * 1.2,
        1.2 / 2.0f64.sqrt(),
    )));
    let run = |spec: ContactSpec, dt: f64, until: f64, c: Shape| {
        let mut b = body(c, Vec2::new(0.0, 3.0), 0.6);
        b.omega = 2.0;
        let mut w = World::new(&[b], vec![floor(spec)], Vec2::new(0.0, -980.0), spec, dt);
        let worst = worst_energy_error(Simulation::new(&mut w).until_time(until));
        (worst, w)
    };
    let elastic = linear(36400.0 * 980.0, 0.0, 0.0);
    let drifts: Vec<f64> = [4e-6, 2e-6, 1e-6]
        .iter()
        .map(|&dt| run(elastic, dt, 0.4, c).0)
        .collect();
    println!("undamped drift at 4e-6, 2e-6, 1e-6 s: {drifts:?}");
    assert!(drifts[2] < drifts[0] / 8.0, "{drifts:?}");
    let damped = linear(36400.0 * 980.0, 5000.0, 0.5);
    let dumbbell = Shape::Clump(clump(&[([-0.5, 0.0], 0.7), ([0.5, 0.0], 0.7)]));
    let (d, w) = run(damped, 1e-5, 3.0, dumbbell);
    let (d4, _) = run(damped, 2.5e-6, 3.0, dumbbell);
    let (dc, _) = run(damped, 1e-5, 3.0, Shape::Circle { r: 0.7 });
    println!(
        "account drift: dumbbell {d:.2e} at 1e-5 s, {d4:.2e} at 2.5e-6 s; a disk {dc:.2e} at 1e-5 s"
    );
    let s = w.bodies.state[0];
    println!(
        "damped: drift {d:.2e}; rest: {s:?}, KE {:e}",
        w.energies.kinetic
    );
    assert!(w.energies.dissipated > 0.0);
    assert!(
        s.vel.norm() < 1e-3 && s.omega.abs() < 1e-3,
        "not at rest: {s:?}"
    );
    // At rest on both members: level, the centroid at a member's radius above the floor
    // (less the resting overlap m g / (2 k_n) ≈ 3e-5 cm).
    assert!(s.pose.angle().sin().abs() < 1e-4, "{s:?}");
    assert!((s.pose.position.y - 0.7).abs() < 1e-4, "{s:?}");
    assert_eq!(w.contacts.len(), 2);
    // The dashpots' dissipated energy is integrated to first order in Δt (a lone disk's account
    // drifts as much): the account must converge (Δt/4 cuts the drift by more than 3) and be
    // no worse than the disk's.
    assert!(d4 < d / 3.0, "{d} {d4}");
    assert!(d < 1.5 * dc, "{d} {dc}");
}

#[test]
fn a_slot_stays_32_bytes() {
    // The member pair rides in the padding: the slots, streamed every step, do not grow.
    assert_eq!(std::mem::size_of::<dem2d::dynamics::contacts::Slot>(), 32);
    assert_eq!(std::mem::size_of::<Shape>(), 24);
}

/// `cases/drop_rebound_clump9.json` is what its description says: P's ellipse (1.5, 1) as the
/// 9-disk equal-area fit, whose union's exact area is πab (against the closed form πab, not the
/// fit's own scaling).
#[test]
fn the_clump_drop_case_is_the_nine_disk_fit_of_p_s_ellipse() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/cases/drop_rebound_clump9.json"
    );
    let case = dem2d::scene::Case::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
    let Shape::Clump(c) = case.bodies[0].shape else {
        panic!("not a clump")
    };
    let fit = Clump::ellipse_fit(9, 1.5, 1.0);
    assert_eq!(c.len(), 9);
    for (k, (centre, r)) in fit.iter().enumerate() {
        let (ck, rk) = c.member(k);
        // Centres as given (the fit is symmetric about its centroid, so no shift).
        assert!(
            (ck.x - centre[0]).abs() <= 1e-15 && ck.y.abs() <= 1e-15,
            "{k}: {ck:?}"
        );
        assert!((rk - r).abs() <= 1e-15 * r, "{k}: {rk} {r}");
    }
    let (area, ..) = dem2d::geometry::clump::union_moments(&fit);
    assert!((area - PI * 1.5).abs() <= 1e-12 * area, "{area}");
}

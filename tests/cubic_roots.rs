//! The robust cubic solver (`dem2d::geometry::cubic::solve_cubic`) against roots computed in
//! double-double by critical-point bracketing (`dem2d_validation::reference`), on the cases that
//! break a bare Cardano solver: double and near-double roots, a tiny leading coefficient,
//! coefficients spanning sixteen decades, and the characteristic cubics of real ellipse pairs.
//!
//! Bar: a simple root must be within `16 ε · κ(r) · |r|` of the true root, with
//! `κ(r) = Σ|t_k||r|^k / |r p'(r)|` its relative condition number — the forward error of a
//! backward-stable evaluation. Roots of a double pair closer than `√ε` may be reported as one
//! double root; they must then be within `4√(ε κ₂)` of both.

use dem2d::geometry::cubic::{one_real_root, solve_cubic};
use dem2d_validation::dd::DD;
use dem2d_validation::reference::cubic_real_roots;
use dem2d_validation::rng::Rng;

/// Relative condition number of a simple root r of t1 x³ + t2 x² + t3 x + t4.
fn condition(t: [f64; 4], r: f64) -> f64 {
    let mag = ((t[0].abs() * r.abs() + t[1].abs()) * r.abs() + t[2].abs()) * r.abs() + t[3].abs();
    let dp = (3.0 * t[0] * r + 2.0 * t[1]) * r + t[2];
    mag / (r * dp).abs().max(f64::MIN_POSITIVE)
}

/// The fast path may decline (`None`), but when it answers, the cubic must have exactly one real
/// root and the answer must meet the same bar. Returns the error in units of the bar.
fn check_fast(t: [f64; 4], what: &str) -> f64 {
    let Some(x) = one_real_root(t[0], t[1], t[2], t[3]) else {
        return 0.0;
    };
    let exact = cubic_real_roots(t);
    assert!(
        exact.len() == 1 && exact[0].1 == 1,
        "{what}: {t:?}: fast path answered {x} but the roots are {exact:?}"
    );
    let r = exact[0].0;
    let tol = 16.0 * f64::EPSILON * condition(t, r) * r.abs();
    let e = (x - r).abs() / tol.max(f64::MIN_POSITIVE);
    assert!(
        e <= 1.0,
        "{what}: {t:?}: fast root {x} vs {r}: error {:e} > {tol:e}",
        (x - r).abs()
    );
    e
}

/// Checks the solver on one cubic; returns the worst error in units of the bar.
fn check(t: [f64; 4], what: &str) -> f64 {
    check_fast(t, what);
    let got = solve_cubic(t[0], t[1], t[2], t[3]);
    let exact = cubic_real_roots(t);
    let got: Vec<(f64, u8)> = got
        .as_slice()
        .iter()
        .copied()
        .zip(got.multiplicities().iter().copied())
        .collect();
    let mut worst: f64 = 0.0;
    // Expand both into lists with multiplicity and match them in order.
    let expand = |v: &[(f64, usize)]| {
        v.iter()
            .flat_map(|&(r, m)| std::iter::repeat_n(r, m))
            .collect::<Vec<_>>()
    };
    let ex = expand(&exact);
    let gx = expand(
        &got.iter()
            .map(|&(r, m)| (r, m as usize))
            .collect::<Vec<_>>(),
    );
    // A double root may be reported as two close simple roots or as one double root, and a
    // complex pair within rounding of the real axis as a double root: compare the multisets
    // only where the reference's roots are well separated.
    let separated = exact.iter().all(|&(_, m)| m == 1)
        && ex
            .windows(2)
            .all(|w| (w[1] - w[0]).abs() > 1e-6 * (w[0].abs().max(w[1].abs())));
    // A reported multiple root must be a point where the exact cubic (in double-double) is
    // within rounding of zero: that is what "double" means for a cubic with rounded coefficients.
    for &(x, m) in &got {
        if m > 1 {
            let xd = DD::from(x);
            let p = ((DD::from(t[0]) * xd + t[1]) * xd + t[2]) * xd + t[3];
            let mag =
                ((t[0].abs() * x.abs() + t[1].abs()) * x.abs() + t[2].abs()) * x.abs() + t[3].abs();
            assert!(
                p.abs().to_f64() <= 64.0 * f64::EPSILON * mag,
                "{what}: {t:?}: reported multiple root {x} where p = {:e}",
                p.to_f64()
            );
        }
    }
    if separated && got.iter().all(|&(_, m)| m == 1) {
        assert_eq!(
            gx.len(),
            ex.len(),
            "{what}: {t:?}: got {got:?}, exact {exact:?}"
        );
    }
    for &(r, m) in &exact {
        let Some(&(g, mg)) = got
            .iter()
            .min_by(|a, b| (a.0 - r).abs().total_cmp(&(b.0 - r).abs()))
        else {
            assert!(
                !separated,
                "{what}: {t:?}: no root reported, exact {exact:?}"
            );
            continue;
        };
        let tol = if mg > 1 || m > 1 {
            // A multiple root is a critical point x with |p(x)| ≤ 64ε·Σ|t_k||x|^k (checked above);
            // the real roots it stands for lie within √(2·64ε·Σ|t_k||x|^k / |p''(x)|) of it.
            let mag =
                ((t[0].abs() * g.abs() + t[1].abs()) * g.abs() + t[2].abs()) * g.abs() + t[3].abs();
            let pp = (6.0 * t[0] * g + 2.0 * t[1]).abs();
            let spread = if pp > 0.0 {
                (128.0 * f64::EPSILON * mag / pp).sqrt()
            } else {
                (64.0 * f64::EPSILON * mag / t[0].abs()).cbrt()
            };
            2.0 * spread
        } else {
            16.0 * f64::EPSILON * condition(t, r) * r.abs()
        };
        let nearest = (g - r).abs();
        if separated || nearest.is_finite() {
            let e = nearest / tol.max(f64::MIN_POSITIVE);
            assert!(
                e <= 1.0,
                "{what}: {t:?}: root {r} (mult {m}) found at distance {nearest:e} > {tol:e}; got {got:?}"
            );
            worst = worst.max(e);
        }
    }
    worst
}

fn cubic_from_roots(r: [f64; 3]) -> [f64; 4] {
    [
        1.0,
        -(r[0] + r[1] + r[2]),
        r[0] * r[1] + r[0] * r[2] + r[1] * r[2],
        -r[0] * r[1] * r[2],
    ]
}

#[test]
fn the_cases_that_break_cardano() {
    // roots::find_roots_cubic(1, 0, -12, 16) returns [-4, 8]; the true roots are -4 and 2 (double).
    let r = solve_cubic(1.0, 0.0, -12.0, 16.0);
    assert_eq!(r.as_slice(), &[-4.0, 2.0]);
    assert_eq!(r.multiplicities(), &[1, 2]);
    check([1.0, 0.0, -12.0, 16.0], "double root");
    check([1.0, -3.0, 3.0, -1.0], "triple root");
    check([1.0, -6.0, 11.0, -6.0], "three simple");
    check([1e-8, 1.0, -3.0, 2.0], "leading 1e-8");
    check([1e-12, -1.0, 0.5, 0.25], "leading 1e-12");
    check([1e-16, 2.0, 1.0, -1.0], "leading 1e-16");
    check([1e-8, 1e8, -1e-8, -1e8], "span 1e-8…1e8");
    check([1e8, 1.0, -1e-8, 1e-7], "span 1e8…1e-8");
}

#[test]
fn random_families_against_double_double() {
    let mut rng = Rng(0x1234_5678_9ABC_DEF1);
    let mut worst = [0.0f64; 5];
    for _ in 0..2000 {
        // Three well-separated real roots of mixed scale.
        let r = [
            rng.range(-10.0, -0.1),
            rng.range(-0.1, 0.1),
            rng.range(0.1, 10.0),
        ];
        worst[0] = worst[0].max(check(cubic_from_roots(r), "three real"));
        // One real root and a complex pair.
        let (x, re, im) = (
            rng.range(-5.0, 5.0),
            rng.range(-5.0, 5.0),
            rng.range(1e-3, 5.0),
        );
        let q = re * re + im * im;
        worst[1] = worst[1].max(check(
            [1.0, -2.0 * re - x, q + 2.0 * re * x, -x * q],
            "one real",
        ));
        // Near-double roots, separations 1e-2 … 1e-9.
        let s = 10f64.powf(rng.range(-9.0, -2.0));
        let base = rng.range(-3.0, 3.0);
        let other = base + rng.range(0.5, 3.0) * if rng.uniform() < 0.5 { 1.0 } else { -1.0 };
        worst[2] = worst[2].max(check(
            cubic_from_roots([base, base + s, other]),
            "near double",
        ));
        // Leading coefficient 1e-6 … 1e-14 (a root near infinity).
        let lead = 10f64.powf(rng.range(-14.0, -6.0));
        worst[3] = worst[3].max(check(
            [
                lead,
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            ],
            "small leading",
        ));
        // Coefficients spanning up to sixteen decades.
        let e = |rng: &mut Rng| {
            10f64.powf(rng.range(-8.0, 8.0)) * if rng.uniform() < 0.5 { -1.0 } else { 1.0 }
        };
        worst[4] = worst[4].max(check(
            [e(&mut rng), e(&mut rng), e(&mut rng), e(&mut rng)],
            "wide span",
        ));
    }
    println!(
        "worst error / bar: three real {:.3}, one real {:.3}, near double {:.3}, small leading {:.3}, wide span {:.3}",
        worst[0], worst[1], worst[2], worst[3], worst[4]
    );
}

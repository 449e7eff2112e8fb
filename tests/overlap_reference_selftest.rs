//! Self-tests of the double-double elementary functions (`validation::dd`) and of the
//! overlap-area reference (`validation::overlap_reference`), each against something
//! independent of the code under test:
//!
//! * DD functions: values computed with mpmath at 300 bits (constants below), identities
//!   (`sin² + cos² = 1`, `atan2(sin x, cos x) = x`, Machin's formula, `sin(π/6) = 1/2`, …);
//! * areas: closed forms evaluated in DD (circular lens, circular and elliptic segments,
//!   hand-clipped polygons), an `f64` polygon clipper, and an `f64` quadrature of the
//!   vertical extent of the intersection (a completely different method).

use dem2d::validation::dd::DD;

/// `|got − want|`, as an `f64`.
fn err(got: DD, want: DD) -> f64 {
    (got - want).abs().to_f64()
}

fn dd(hi: f64, lo: f64) -> DD {
    DD::new(hi, lo)
}

// ---------------------------------------------------------------------------
// DD elementary functions
// ---------------------------------------------------------------------------

/// Values from mpmath (300-bit), rounded to DD: `(argument, (hi, lo))`.
#[test]
fn dd_trig_against_mpmath() {
    // Tolerance 1e-31 absolute on values of order 1: two to three units of DD::EPS
    // (4.9e-32) plus the rounding of the mpmath value to DD (≤ 1 EPS/2).
    let tol = 1e-31;
    let mut worst = 0.0f64;
    let sins = [
        (1.0, dd(0.8414709848078965, 1.776845092935536e-18)),
        (10.0, dd(-0.5440211108893698, -3.8949898668223557e-17)),
        (0.5, dd(0.479425538604203, -5.103969860556013e-18)),
        (0.1, dd(0.09983341664682815, 3.08001512929492e-18)),
    ];
    for (x, want) in sins {
        let e = err(DD::from(x).sin(), want);
        worst = worst.max(e);
        assert!(e < tol, "sin({x}): error {e:e}");
    }
    let coss = [
        (1.0, dd(0.5403023058681398, -4.760954612604417e-17)),
        (-7.0, dd(0.7539022543433046, 3.728245359710072e-17)),
    ];
    for (x, want) in coss {
        let e = err(DD::from(x).cos(), want);
        worst = worst.max(e);
        assert!(e < tol, "cos({x}): error {e:e}");
    }
    let checks = [
        (
            "atan(0.3)",
            DD::from(0.3).atan(),
            dd(0.2914567944778671, -1.6448555435075034e-17),
        ),
        (
            "atan2(-2.5, -1.7)",
            DD::from(-2.5).atan2(DD::from(-1.7)),
            dd(-2.167972984887574, -2.0489901029157467e-16),
        ),
        (
            "asin(0.9)",
            DD::from(0.9).asin(),
            dd(1.1197695149986342, 4.092642558112641e-17),
        ),
        (
            "acos(-0.3)",
            DD::from(-0.3).acos(),
            dd(1.8754889808102941, -2.1748551325047183e-17),
        ),
        (
            "0.7 - sin(0.7)",
            DD::from(0.7).x_minus_sin(),
            dd(0.05578231276230894, -2.8740567927338755e-18),
        ),
        (
            "(1 − 2^-53) − sin(1 − 2^-53) (series branch)",
            DD::from(0.9999999999999999).x_minus_sin(),
            dd(0.15852901519210344, 2.6976096990938964e-18),
        ),
        (
            "1 − sin(1) (difference branch)",
            DD::ONE.x_minus_sin(),
            dd(0.1585290151921035, -1.776845092935536e-18),
        ),
        (
            "-2.5 - sin(-2.5)",
            DD::from(-2.5).x_minus_sin(),
            dd(-1.9015278558960436, 5.580826912169191e-17),
        ),
        (
            "3 - sin(3)",
            DD::from(3.0).x_minus_sin(),
            dd(2.8588799919401326, 1.3020060829112707e-16),
        ),
    ];
    for (what, got, want) in checks {
        let e = err(got, want);
        worst = worst.max(e);
        assert!(e < tol, "{what}: error {e:e}");
    }
    eprintln!("DD functions vs mpmath: worst absolute error {worst:e}");
    // Small argument: relative accuracy (x − sin x ≈ 1.7e-10 here).
    let got = DD::from(1e-3).x_minus_sin();
    let want = dd(1.6666665833333355e-10, -5.6979554413661525e-27);
    let rel = err(got, want) / want.to_f64();
    assert!(rel < 1e-30, "1e-3 - sin(1e-3): relative error {rel:e}");
}

#[test]
fn dd_trig_identities() {
    let pi = DD::PI;
    // Exact special values.
    let cases = [
        ("sin(π/6)", (pi / 6.0).sin(), DD::from(0.5)),
        ("cos(π/3)", (pi / 3.0).cos(), DD::from(0.5)),
        ("sin(π/4)", (pi / 4.0).sin(), DD::from(0.5).sqrt()),
        ("cos(-3π/4)", (pi * -0.75).cos(), -DD::from(0.5).sqrt()),
        ("sin(5π/6)", (pi * 5.0 / 6.0).sin(), DD::from(0.5)),
        ("sin(π/2)", DD::FRAC_PI_2.sin(), DD::ONE),
        ("cos(π)", pi.cos(), -DD::ONE),
        ("sin(π)", pi.sin(), DD::ZERO),
        ("4 atan(1)", DD::ONE.atan() * 4.0, pi),
        (
            "atan2(1, √3)·6",
            DD::ONE.atan2(DD::from(3.0).sqrt()) * 6.0,
            pi,
        ),
        ("asin(1/2)·6", DD::from(0.5).asin() * 6.0, pi),
        ("acos(-1)", DD::from(-1.0).acos(), pi),
        ("acos(1)", DD::ONE.acos(), DD::ZERO),
        ("asin(-1)", DD::from(-1.0).asin(), -DD::FRAC_PI_2),
        ("atan2(0, -1)", DD::ZERO.atan2(-DD::ONE), pi),
        ("atan2(-1, 0)", (-DD::ONE).atan2(DD::ZERO), -DD::FRAC_PI_2),
        // Machin: π/4 = 4 atan(1/5) − atan(1/239).
        (
            "Machin",
            ((DD::ONE / 5.0).atan() * 4.0 - (DD::ONE / 239.0).atan()) * 4.0,
            pi,
        ),
        ("τ", DD::TAU, pi * 2.0),
        ("π/2", DD::FRAC_PI_2 * 2.0, pi),
    ];
    // 2e-31: a few EPS on values ≤ π (the special arguments are themselves DD-rounded,
    // e.g. π/6, and the error of π/6 propagates with slope ≤ 1).
    let mut worst_special = 0.0f64;
    for (what, got, want) in cases {
        let e = err(got, want);
        worst_special = worst_special.max(e);
        assert!(e < 2e-31, "{what}: error {e:e}");
    }
    eprintln!("DD special values: worst absolute error {worst_special:e}");

    // sin² + cos² = 1, double angle, atan2 round trip, symmetry, on a spread of arguments
    // (including the range the overlap reference uses, [−2π, 4π]).
    let mut worst = [0.0f64; 5];
    for k in -400..=800 {
        let x = DD::from(k as f64 * 0.0157) + 1e-18 * k as f64;
        let (s, c) = x.sin_cos();
        worst[0] = worst[0].max(err(s.sqr() + c.sqr(), DD::ONE));
        let (s2, _) = (x * 2.0).sin_cos();
        worst[1] = worst[1].max(err(s2, s * c * 2.0));
        // atan2 returns (−π, π]: compare modulo 2π.
        let back = s.atan2(c);
        let turns = ((x - back) / DD::TAU).to_f64().round();
        worst[2] = worst[2].max(err(back + DD::TAU * turns, x));
        worst[3] = worst[3].max(err((-x).sin(), -s).max(err((-x).cos(), c)));
        worst[4] = worst[4].max(err((pi - x).sin(), s));
        // Scaling the point does not change the angle.
        assert!(err((s * 3.7).atan2(c * 3.7), back) < 4e-31, "k = {k}");
    }
    // sin²+cos² and the double angle: a few EPS; atan2 round trip: a few EPS times |x| ≤ 4π;
    // sin(π − x): the reduction of π − x is exact only to the DD rounding of π − x.
    eprintln!(
        "DD identities (sin²+cos², double angle, atan2 round trip, odd/even, sin(π−x)): {worst:?}"
    );
    let tols = [2e-31, 3e-31, 1e-30, 0.0, 1e-30];
    for (w, t) in worst.iter().zip(tols) {
        assert!(*w <= t, "identities: worst errors {worst:?}");
    }

    // Small arguments: sin x = x − x³/6 + x⁵/120 (next term ~1e-61 for x = 1e-10).
    let x = DD::from(1e-10);
    let series = x - x * x * x / 6.0;
    assert!(err(x.sin(), series) < 1e-40);
    assert!(err(x.cos(), DD::ONE - x * x / 2.0) < 1e-40);
    assert!(err(x.atan(), x - x * x * x / 3.0) < 1e-40);
    assert!(err(x.asin(), x + x * x * x / 6.0) < 1e-40);
    // x − sin x = x³/6 (1 − x²/20 + …): relative difference 5e-22 from the next term.
    let cube = x * x * x / 6.0;
    assert!(err(x.x_minus_sin(), cube) / cube.to_f64() < 1e-21);
    assert_eq!((-x).x_minus_sin(), -x.x_minus_sin());
}

//! Fabric: the anisotropies of the contact normals and of the mean contact forces (second-order
//! Fourier fits, Rothenburg & Bathurst, Géotechnique 39 (1989)), and the orientation order of
//! non-circular bodies.
//!
//! With θ the direction of a body–body contact normal (mod π):
//! - normals: `E(θ) = (1/2π)[1 + a_c cos 2(θ − θ_c)]`; `a_c e^{2iθ_c} = 2⟨e^{2iθ}⟩` over the
//!   contacts (the exact second-order Fourier coefficient of the sample, no binning; equivalent
//!   to the fabric tensor: `a_c = 2(φ₁ − φ₂)`);
//! - mean normal force in direction θ: `f_n(θ) = f_0[1 + a_n cos 2(θ − θ_n)]`;
//! - mean tangential force: `f_t(θ) = −f_0 a_t sin 2(θ − θ_t)`, `F_t = F·t`, `t = (−n_y, n_x)`.
//!
//! The force means are taken per angular bin ([`BINS`] over [0, π)) and the Fourier series fitted
//! to the bins' means by least squares, as Rothenburg & Bathurst did; a bin average of
//! `cos 2θ` over a bin of width π/M is `sinc(π/M)` times the value at its centre, so the fitted
//! second harmonics are divided by that factor. For coaxial directions the average stress obeys
//! `(σ₁ − σ₃)/(σ₁ + σ₃) ≈ ½(a_c + a_n + a_t)` (disks; non-circular bodies add a branch-length
//! term).
//!
//! Orientation order: `S = |⟨e^{2iφ}⟩|` over the non-circular bodies, φ the direction of a
//! body's long axis (0 for random orientations, 1 all aligned), with the director `½ arg`.

use super::frame::Frame;
use crate::geometry::Shape;
use std::f64::consts::PI;

/// Angular bins of the force fits over [0, π).
pub const BINS: usize = 36;

/// Anisotropies (dimensionless) and their directions (radians in [0, π)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Anisotropy {
    pub a_c: f64,
    pub theta_c: f64,
    pub a_n: f64,
    pub theta_n: f64,
    pub a_t: f64,
    pub theta_t: f64,
    /// Mean normal force `f_0` (dyn/cm).
    pub f0: f64,
    /// Body–body contacts used.
    pub contacts: usize,
}

fn wrap(theta: f64) -> f64 {
    theta.rem_euclid(PI)
}

/// Least-squares fit of `y = c₀ + c₁ cos 2θ + c₂ sin 2θ` to points `(θ, y)`.
fn fit(points: &[(f64, f64)]) -> Option<[f64; 3]> {
    let mut m = nalgebra::Matrix3::<f64>::zeros();
    let mut r = nalgebra::Vector3::<f64>::zeros();
    for &(t, y) in points {
        let g = nalgebra::Vector3::new(1.0, (2.0 * t).cos(), (2.0 * t).sin());
        m += g * g.transpose();
        r += g * y;
    }
    let c = m.lu().solve(&r)?;
    Some([c[0], c[1], c[2]])
}

/// The anisotropies of the body–body contacts with a body in the region (`inside`); NaN with
/// fewer than 3 populated bins.
pub fn anisotropy(frame: &Frame, inside: &[bool]) -> Anisotropy {
    let mut count = [0usize; BINS];
    let mut sum_n = [0.0; BINS];
    let mut sum_t = [0.0; BINS];
    let (mut c2, mut s2, mut n) = (0.0, 0.0, 0usize);
    for c in &frame.contacts {
        let Some(i) = c.giver_body() else { continue };
        if !(inside[i] || inside[c.j]) {
            continue;
        }
        let th = wrap(c.normal.y.atan2(c.normal.x));
        c2 += (2.0 * th).cos();
        s2 += (2.0 * th).sin();
        n += 1;
        let k = ((th / PI * BINS as f64) as usize).min(BINS - 1);
        count[k] += 1;
        sum_n[k] += c.normal_force();
        sum_t[k] += c.tangential_force();
    }
    let nan = Anisotropy {
        a_c: f64::NAN,
        theta_c: f64::NAN,
        a_n: f64::NAN,
        theta_n: f64::NAN,
        a_t: f64::NAN,
        theta_t: f64::NAN,
        f0: f64::NAN,
        contacts: n,
    };
    if n == 0 {
        return nan;
    }
    let (c2, s2) = (c2 / n as f64, s2 / n as f64);
    let a_c = 2.0 * c2.hypot(s2);
    let theta_c = wrap(0.5 * s2.atan2(c2));
    let centre = |k: usize| (k as f64 + 0.5) * PI / BINS as f64;
    let mean_n: Vec<(f64, f64)> = (0..BINS)
        .filter(|&k| count[k] > 0)
        .map(|k| (centre(k), sum_n[k] / count[k] as f64))
        .collect();
    let mean_t: Vec<(f64, f64)> = (0..BINS)
        .filter(|&k| count[k] > 0)
        .map(|k| (centre(k), sum_t[k] / count[k] as f64))
        .collect();
    if mean_n.len() < 3 {
        return Anisotropy {
            a_c,
            theta_c,
            ..nan
        };
    }
    let (Some(fn_), Some(ft)) = (fit(&mean_n), fit(&mean_t)) else {
        return Anisotropy {
            a_c,
            theta_c,
            ..nan
        };
    };
    let x = PI / BINS as f64;
    let sinc = x.sin() / x;
    let f0 = fn_[0];
    let (an_c, an_s) = (fn_[1] / sinc, fn_[2] / sinc);
    let (at_c, at_s) = (ft[1] / sinc, ft[2] / sinc);
    Anisotropy {
        a_c,
        theta_c,
        a_n: an_c.hypot(an_s) / f0,
        theta_n: wrap(0.5 * an_s.atan2(an_c)),
        // f_t = f0 a_t (sin 2θ_t cos 2θ − cos 2θ_t sin 2θ).
        a_t: at_c.hypot(at_s) / f0,
        theta_t: wrap(0.5 * at_c.atan2(-at_s)),
        f0,
        contacts: n,
    }
}

/// The direction of a body's long axis (radians), or `None` for a circle (and a square, and a
/// polygon whose second moments of area are equal about every axis, as a regular one's).
pub fn long_axis(shape: &Shape, angle: f64) -> Option<f64> {
    match *shape {
        Shape::Circle { .. } => None,
        Shape::Ellipse { a, b } if a != b => Some(if a > b { angle } else { angle + 0.5 * PI }),
        Shape::Rectangle { w, h } if w != h => Some(if w > h { angle } else { angle + 0.5 * PI }),
        Shape::Ellipse { .. } | Shape::Rectangle { .. } => None,
        // The principal axis of the larger second moment of area (none for a regular polygon).
        Shape::Polygon(p) => p.long_axis.map(|t| angle + t),
        // Likewise for the union of a clump's disks.
        Shape::Clump(c) => {
            (c.moment_ellipse[0] > c.moment_ellipse[1] * (1.0 + 1e-12)).then(|| angle + c.long_axis)
        }
    }
}

/// Orientation order `S` and director of the region's elongated bodies (NaN without any).
pub fn orientation_order(frame: &Frame, inside: &[bool]) -> (f64, f64) {
    let (mut c, mut s, mut n) = (0.0, 0.0, 0usize);
    for (b, _) in frame.bodies.iter().zip(inside).filter(|(_, i)| **i) {
        if let Some(phi) = long_axis(&b.shape, b.angle) {
            c += (2.0 * phi).cos();
            s += (2.0 * phi).sin();
            n += 1;
        }
    }
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let (c, s) = (c / n as f64, s / n as f64);
    (c.hypot(s), wrap(0.5 * s.atan2(c)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{FrameBody, FrameContact};
    use crate::dynamics::Partner;
    use crate::geometry::Vec2;
    use approx::assert_abs_diff_eq;

    /// Normals drawn from `E(θ) ∝ 1 + a cos 2(θ − θ₀)` by inverting its distribution function
    /// at the quantiles (k + ½)/N (a deterministic sample), each carrying the forces of given
    /// anisotropies: the fits must return them.
    #[test]
    fn a_synthetic_set_of_normals_and_forces_returns_its_anisotropies() {
        let (a_c, th_c) = (0.4, 0.5);
        let (a_n, th_n) = (0.3, 0.7);
        let (a_t, th_t) = (0.15, 0.2);
        let f0 = 7.0;
        let cdf = |t: f64| (t + 0.5 * a_c * ((2.0 * (t - th_c)).sin() + (2.0 * th_c).sin())) / PI;
        let n = 20_000;
        let mut contacts = Vec::new();
        for k in 0..n {
            let q = (k as f64 + 0.5) / n as f64;
            let (mut lo, mut hi) = (0.0, PI);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if cdf(mid) < q {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let t = 0.5 * (lo + hi);
            // Half the contacts written with the normal reversed (i and j swapped): the same
            // contact, so the same F_n and F_t.
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            let nrm = Vec2::new(t.cos(), t.sin()) * sign;
            let tan = Vec2::new(-nrm.y, nrm.x);
            let fn_ = f0 * (1.0 + a_n * (2.0 * (t - th_n)).cos());
            let ft = -f0 * a_t * (2.0 * (t - th_t)).sin();
            contacts.push(FrameContact {
                i: Partner::Body(0),
                j: 1,
                point: Vec2::zeros(),
                normal: nrm,
                force: nrm * fn_ + tan * ft,
                couple: 0.0,
                depth: 0.0,
                state: "overlap".into(),
            });
        }
        let body = FrameBody {
            shape: Shape::Circle { r: 1.0 },
            position: Vec2::zeros(),
            angle: 0.0,
            density: 1.0,
        };
        let frame = Frame {
            time: 0.0,
            bodies: vec![body; 2],
            contacts,
            wall_box: None,
            cell: None,
        };
        let a = anisotropy(&frame, &[true, true]);
        assert_abs_diff_eq!(a.a_c, a_c, epsilon = 1e-4);
        assert_abs_diff_eq!(a.theta_c, th_c, epsilon = 1e-4);
        assert_abs_diff_eq!(a.f0, f0, epsilon = 2e-2);
        assert_abs_diff_eq!(a.a_n, a_n, epsilon = 3e-3);
        assert_abs_diff_eq!(a.theta_n, th_n, epsilon = 1e-2);
        assert_abs_diff_eq!(a.a_t, a_t, epsilon = 3e-3);
        assert_abs_diff_eq!(a.theta_t, th_t, epsilon = 2e-2);
    }

    #[test]
    fn orientation_order_is_one_when_aligned_and_zero_for_evenly_spread_axes() {
        let mk = |angles: &[f64]| Frame {
            bodies: angles
                .iter()
                .map(|&a| FrameBody {
                    shape: Shape::Ellipse { a: 1.0, b: 2.0 },
                    position: Vec2::zeros(),
                    angle: a,
                    density: 1.0,
                })
                .collect(),
            ..Default::default()
        };
        let (s, d) = orientation_order(&mk(&[0.1, 0.1 + PI, 0.1 - PI]), &[true; 3]);
        assert_abs_diff_eq!(s, 1.0, epsilon = 1e-14);
        assert_abs_diff_eq!(d, 0.1 + 0.5 * PI, epsilon = 1e-14);
        let spread: Vec<f64> = (0..12).map(|k| k as f64 * PI / 12.0).collect();
        assert_abs_diff_eq!(
            orientation_order(&mk(&spread), &[true; 12]).0,
            0.0,
            epsilon = 1e-14
        );
    }
}

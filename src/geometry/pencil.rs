//! The pencil of two ellipses `f + λ g = 0` (P8), its characteristic cubic `D(λ)` (P10) and the
//! splitting of a degenerate member into two lines.
//!
//! Frame (P5–P7, Fig. 1): origin at the centroid of element i, x axis through the centroid of
//! element j at `(d, 0)`. Both ellipses are normalised so that their constant term is one
//! (P(7) divided by `D_n`), which only rescales λ.

use super::conic::{Conic, EllipseForm};

/// A homogeneous line `l[0] x + l[1] y + l[2] = 0`.
pub type Line = [f64; 3];

/// Element i at the origin and element j at `(d, 0)`, as in P(5) and P(6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pencil {
    /// Element i: `A_i x² + 2B_i xy + C_i y² = 1` (P5 over D_i).
    pub i: EllipseForm,
    /// Element j: `A_j (x−d)² + 2B_j (x−d) y + C_j y² = 1` (P6 over D_j).
    pub j: EllipseForm,
    /// Distance between the centroids.
    pub d: f64,
    /// The mixed invariant `X = A_i C_j + A_j C_i − 2 B_i B_j = tr(adj(Q_i) Q_j)`, evaluated
    /// without cancellation (see [`mixed_invariant`]).
    pub x_mixed: f64,
}

/// `X = tr(adj(Q_i) Q_j)` from the semi-axes and the angle φ from i's `a` axis to j's `a` axis.
///
/// Written in i's principal frame it is a sum of positive terms,
/// `X = (cos²φ/a_j² + sin²φ/b_j²)/b_i² + (sin²φ/a_j² + cos²φ/b_j²)/a_i²`, whereas the expression
/// from the P(7) coefficients, `A_iC_j + A_jC_i − 2B_iB_j`, cancels catastrophically for aligned
/// elongated ellipses (four digits lost at a/b = 100).
#[inline]
pub fn mixed_invariant(ai: f64, bi: f64, aj: f64, bj: f64, cos_phi: f64, sin_phi: f64) -> f64 {
    let inv = |x: f64| 1.0 / (x * x);
    mixed_invariant_from_inverse_squares([inv(ai), inv(bi)], [inv(aj), inv(bj)], cos_phi, sin_phi)
}

/// [`mixed_invariant`] from `[1/a², 1/b²]` of each ellipse.
#[inline]
pub fn mixed_invariant_from_inverse_squares(
    i: [f64; 2],
    j: [f64; 2],
    cos_phi: f64,
    sin_phi: f64,
) -> f64 {
    let (c2, s2) = (cos_phi * cos_phi, sin_phi * sin_phi);
    (c2 * j[0] + s2 * j[1]) * i[1] + (s2 * j[0] + c2 * j[1]) * i[0]
}

impl Pencil {
    /// The coefficients `[t1, t2, t3, t4]` of `D(λ) = det M(λ)` (P10), with `M(λ)` of P(9).
    ///
    /// Expanding the determinant of P(9) and using `A_j X − W = A_i K_j` (with `W` the form of
    /// `Q_i` at `(B_j, −A_j)`) leaves a form that is symmetric under i ↔ j, λ ↔ 1/λ:
    /// `t1 = −K_j`, `t2 = A_i K_j d² − X − K_j`, `t3 = A_j K_i d² − X − K_i`, `t4 = −K_i`,
    /// where `K_n = A_n C_n − B_n² = 1/(a_n² b_n²)`.
    #[inline]
    pub fn cubic(&self) -> [f64; 4] {
        let (ki, kj, x, d2) = (self.i.k, self.j.k, self.x_mixed, self.d * self.d);
        [
            -kj,                              // P(10) t1
            self.i.a_coef * kj * d2 - x - kj, // P(10) t2
            self.j.a_coef * ki * d2 - x - ki, // P(10) t3
            -ki,                              // P(10) t4
        ]
    }

    /// The member `f + λ g` of the pencil in the general form (P9).
    #[inline]
    pub fn member(&self, lambda: f64) -> Conic {
        let (i, j, d) = (&self.i, &self.j, self.d);
        Conic {
            a: lambda * j.a_coef + i.a_coef,            // P(9)
            h: lambda * j.b_coef + i.b_coef,            // P(9)
            b: lambda * j.c_coef + i.c_coef,            // P(9)
            g: -lambda * j.a_coef * d,                  // P(9)
            f: -lambda * j.b_coef * d,                  // P(9)
            c: lambda * (j.a_coef * d * d - 1.0) - 1.0, // P(9), with D_i = D_j = 1
        }
    }
}

/// The two real lines of a degenerate conic (`det M = 0`), or `None` when its lines are
/// imaginary (a point-ellipse, imaginary parallel lines) or it vanishes.
///
/// Method (projective splitting of a degenerate conic): for `M = g hᵀ + h gᵀ` (lines g, h),
/// `adj M = −p pᵀ` with `p = g × h` their common point, and `M − [p]ₓ = 2 g hᵀ` has rank one, so
/// one of its rows is h and one of its columns is g. Imaginary lines make the diagonal of
/// `adj M` positive instead. This covers every degenerate class of Table 1 at once: crossing
/// lines, parallel lines and one finite line plus the line at infinity (`p` at infinity), and a
/// double line (`adj M = 0`: any non-zero row of `M`).
pub fn split_degenerate(m: &Conic) -> Option<[Line; 2]> {
    let Conic { a, h, b, g, f, c } = *m;
    let scale = [a, h, b, g, f, c]
        .iter()
        .fold(0.0f64, |s, v| s.max(v.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return None;
    }
    // Cofactors of M (adj M is symmetric).
    let b11 = b * c - f * f;
    let b22 = a * c - g * g;
    let b33 = a * b - h * h; // = D0, P(3)
    let b12 = f * g - h * c;
    let b13 = h * f - b * g;
    let b23 = g * h - a * f;
    let diag = [-b11, -b22, -b33];
    let (k, &dk) = diag
        .iter()
        .enumerate()
        .max_by(|x, y| x.1.total_cmp(y.1))
        .expect("three entries");
    let tiny = 64.0 * f64::EPSILON * scale * scale;
    if dk <= tiny {
        let adj_max = [b11, b22, b33, b12, b13, b23]
            .iter()
            .fold(0.0f64, |s, v| s.max(v.abs()));
        if adj_max > tiny {
            return None; // imaginary lines: adj M is positive semi-definite
        }
        // Rank one: a double line, any row of M with the largest entry.
        let rows = m_rows(m);
        let r = (0..3)
            .max_by(|&x, &y| row_norm(&rows[x]).total_cmp(&row_norm(&rows[y])))
            .expect("three rows");
        return Some([rows[r], rows[r]]);
    }
    let col = match k {
        0 => [b11, b12, b13],
        1 => [b12, b22, b23],
        _ => [b13, b23, b33],
    };
    let s = 1.0 / dk.sqrt();
    let p = [col[0] * s, col[1] * s, col[2] * s];
    // C = M − [p]ₓ, with [p]ₓ x = p × x.
    let cm = [
        [a, h + p[2], g - p[1]],
        [h - p[2], b, f + p[0]],
        [g + p[1], f - p[0], c],
    ];
    let (mut r, mut q, mut best) = (0, 0, -1.0);
    for (ri, row) in cm.iter().enumerate() {
        for (qi, v) in row.iter().enumerate() {
            if v.abs() > best {
                (r, q, best) = (ri, qi, v.abs());
            }
        }
    }
    let row = cm[r];
    let column = [cm[0][q], cm[1][q], cm[2][q]];
    Some([row, column])
}

fn m_rows(m: &Conic) -> [Line; 3] {
    [[m.a, m.h, m.g], [m.h, m.b, m.f], [m.g, m.f, m.c]]
}

fn row_norm(r: &Line) -> f64 {
    r[0].abs().max(r[1].abs()).max(r[2].abs())
}

/// Where a line meets an ellipse centred at the origin (`A x² + 2B xy + C y² = 1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineCut {
    /// Unit normal of the line (its `(l0, l1)` normalised).
    pub normal: [f64; 2],
    /// Midpoint of the chord (the two crossings), or the tangent point.
    pub mid: [f64; 2],
    /// Unit direction of the line.
    pub dir: [f64; 2],
    /// Squared half-length of the chord; negative when the crossings are complex.
    pub half_sq: f64,
    /// Rounding bound on `half_sq`: within it the crossings coincide (tangency).
    pub half_sq_err: f64,
}

impl LineCut {
    /// The two crossings (only meaningful when `half_sq > 0`).
    pub fn points(&self) -> [[f64; 2]; 2] {
        let s = self.half_sq.max(0.0).sqrt();
        let [mx, my] = self.mid;
        let [tx, ty] = self.dir;
        [[mx - s * tx, my - s * ty], [mx + s * tx, my + s * ty]]
    }
}

/// Intersects the line `l` with the ellipse `form` centred at the origin; `None` when the line
/// misses the circle of radius `reach` about the origin (in particular the line at infinity).
///
/// Along `x = m + s t` (m the foot of the perpendicular from the origin, t the unit direction)
/// the ellipse reads `α s² + 2β s + γ = 0`. The midpoint `−β/α` is well conditioned even at
/// tangency; only the half-length `√(β² − αγ)/α` is not, and its rounding bound is returned.
#[inline]
pub fn cut_line(form: &EllipseForm, l: &Line, reach: f64) -> Option<LineCut> {
    // Member coefficients are of order one (lengths in units of the pair's size): no overflow
    // to guard against, so no `hypot`.
    let nu = (l[0] * l[0] + l[1] * l[1]).sqrt();
    let rho = -l[2] / nu;
    // Also rejects the line at infinity (ν = 0 makes ρ infinite or NaN).
    if rho.is_nan() || rho.abs() > reach {
        return None;
    }
    let (ux, uy) = (l[0] / nu, l[1] / nu);
    let (mx, my) = (rho * ux, rho * uy);
    let (tx, ty) = (-uy, ux);
    let (qa, qb, qc) = (form.a_coef, form.b_coef, form.c_coef);
    let alpha = (qa * tx + 2.0 * qb * ty) * tx + qc * ty * ty;
    let beta = (qa * mx + qb * my) * tx + (qb * mx + qc * my) * ty;
    let mqm = form.quad(mx, my);
    let gamma = mqm - 1.0;
    let disc = beta * beta - alpha * gamma;
    let err = 16.0 * f64::EPSILON * (beta * beta + alpha * (mqm + 1.0));
    let s_mid = -beta / alpha;
    Some(LineCut {
        normal: [ux, uy],
        mid: [mx + s_mid * tx, my + s_mid * ty],
        dir: [tx, ty],
        half_sq: disc / (alpha * alpha),
        half_sq_err: err / (alpha * alpha),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::conic::ConicClass;

    /// The conic `a x² + 2h xy + b y² + 2g x + 2f y + c = 0` from `[a, h, b, g, f, c]`.
    fn conic([a, h, b, g, f, c]: [f64; 6]) -> Conic {
        Conic { a, h, b, g, f, c }
    }

    /// det of the P(9) member by cofactors, to check P(10) against.
    fn det(m: &Conic) -> f64 {
        m.det()
    }

    #[test]
    fn cubic_coefficients_match_determinant() {
        let i = EllipseForm::new(1.5, 1.0, 0.3f64.cos(), 0.3f64.sin());
        let j = EllipseForm::new(0.7, 0.4, (-1.1f64).cos(), (-1.1f64).sin());
        let phi = -1.1 - 0.3f64;
        let p = Pencil {
            i,
            j,
            d: 1.9,
            x_mixed: mixed_invariant(1.5, 1.0, 0.7, 0.4, phi.cos(), phi.sin()),
        };
        let t = p.cubic();
        for &lambda in &[-3.0, -1.0, -0.25, 0.0, 0.5, 2.0, 7.0] {
            let poly = ((t[0] * lambda + t[1]) * lambda + t[2]) * lambda + t[3];
            let direct = det(&p.member(lambda));
            let scale = 1.0 + direct.abs() + (lambda * lambda * lambda).abs() * t[0].abs();
            assert!(
                (poly - direct).abs() <= 1e-13 * scale,
                "λ={lambda}: {poly} vs {direct}"
            );
        }
    }

    #[test]
    fn splits_every_real_degenerate_class() {
        // Crossing lines x = y and x = -y: x² − y² = 0.
        let m = conic([1.0, 0.0, -1.0, 0.0, 0.0, 0.0]);
        assert_eq!(m.classify(1e-12), ConicClass::CrossingLines);
        let [l1, l2] = split_degenerate(&m).unwrap();
        for l in [l1, l2] {
            assert!((l[0].abs() - l[1].abs()).abs() < 1e-15 && l[2] == 0.0);
        }
        // Parallel lines y = ±1: y² − 1 = 0.
        let m = conic([0.0, 0.0, 1.0, 0.0, 0.0, -1.0]);
        assert_eq!(m.classify(1e-12), ConicClass::ParallelLines);
        let [l1, l2] = split_degenerate(&m).unwrap();
        let mut offsets = [-l1[2] / l1[1], -l2[2] / l2[1]];
        offsets.sort_by(f64::total_cmp);
        assert_eq!(offsets, [-1.0, 1.0]);
        // Double line (y − 2)² = 0.
        let m = conic([0.0, 0.0, 1.0, 0.0, -2.0, 4.0]);
        assert_eq!(m.classify(1e-12), ConicClass::DoubleLine);
        let [l1, _] = split_degenerate(&m).unwrap();
        assert_eq!(-l1[2] / l1[1], 2.0);
        // One finite line plus the line at infinity: 2x − 3 = 0 (no quadratic part).
        let m = conic([0.0, 0.0, 0.0, 1.0, 0.0, -3.0]);
        let [l1, l2] = split_degenerate(&m).unwrap();
        let finite = if l1[0].abs() > 0.0 { l1 } else { l2 };
        let infinite = if l1[0].abs() > 0.0 { l2 } else { l1 };
        assert_eq!(-finite[2] / finite[0], 1.5);
        assert!(infinite[0] == 0.0 && infinite[1] == 0.0 && infinite[2] != 0.0);
        // Imaginary cases: point-ellipse x² + y² = 0, imaginary parallel lines y² + 1 = 0.
        let m = conic([1.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
        assert_eq!(m.classify(1e-12), ConicClass::PointEllipse);
        assert!(split_degenerate(&m).is_none());
        let m = conic([0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
        assert_eq!(m.classify(1e-12), ConicClass::ImaginaryParallelLines);
        assert!(split_degenerate(&m).is_none());
    }
}

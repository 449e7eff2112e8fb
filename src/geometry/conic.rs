//! Conics `a x² + 2h xy + b y² + 2g x + 2f y + c = 0` (P1), their invariants and classification
//! (P2–P4, Table 1), and the ellipse of a body in the paper's local frame (P5–P7).
//!
//! The letters are the paper's: `a, h, b, g, f, c` are the entries of the symmetric matrix
//! `M = [[a, h, g], [h, b, f], [g, f, c]]` with `Xᵀ M X = 0`, `X = (x, y, 1)`.

/// A conic in the general form of P(1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conic {
    pub a: f64,
    pub h: f64,
    pub b: f64,
    pub g: f64,
    pub f: f64,
    pub c: f64,
}

/// The classes of Table 1 of P.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConicClass {
    /// `D ≠ 0, D0 < 0`.
    Hyperbola,
    /// `D ≠ 0, D0 > 0, σD < 0`.
    RealEllipse,
    /// `D ≠ 0, D0 > 0, σD > 0` (no real point).
    ImaginaryEllipse,
    /// `D ≠ 0, D0 = 0`.
    Parabola,
    /// `D = 0, D0 < 0`: two real lines crossing at one point.
    CrossingLines,
    /// `D = 0, D0 > 0`: two imaginary lines meeting at one real point (a point-ellipse).
    PointEllipse,
    /// `D = 0, D0 = 0`, `g² − ac` or `f² − bc` positive: two real parallel lines.
    ParallelLines,
    /// `D = 0, D0 = 0`, negative: imaginary parallel lines (empty).
    ImaginaryParallelLines,
    /// `D = 0, D0 = 0, g² − ac = f² − bc = 0`: one double line.
    DoubleLine,
}

impl Conic {
    /// The symmetric 3×3 matrix `[[a, h, g], [h, b, f], [g, f, c]]`.
    pub fn matrix(&self) -> [[f64; 3]; 3] {
        [
            [self.a, self.h, self.g],
            [self.h, self.b, self.f],
            [self.g, self.f, self.c],
        ]
    }

    /// `D = det M` (P2).
    pub fn det(&self) -> f64 {
        let Conic { a, h, b, g, f, c } = *self;
        a * (b * c - f * f) - h * (h * c - f * g) + g * (h * f - b * g) // P(2)
    }

    /// `D0 = ab − h²` (P3).
    pub fn d0(&self) -> f64 {
        self.a * self.b - self.h * self.h // P(3)
    }

    /// `σ = a + b` (P4).
    pub fn sigma(&self) -> f64 {
        self.a + self.b // P(4)
    }

    /// Value of the left-hand side of P(1) at `(x, y)`.
    #[inline]
    pub fn value(&self, x: f64, y: f64) -> f64 {
        let Conic { a, h, b, g, f, c } = *self;
        (a * x + 2.0 * (h * y + g)) * x + (b * y + 2.0 * f) * y + c
    }

    /// Table 1 of P, deciding "= 0" with the relative tolerance `tol` (scaled by the size of the
    /// terms each invariant is made of).
    pub fn classify(&self, tol: f64) -> ConicClass {
        let Conic { a, h, b, g, f, c } = *self;
        let scale = [a, h, b, g, f, c]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let d = self.det();
        let d0 = self.d0();
        let d_zero = d.abs() <= tol * scale * scale * scale;
        let d0_zero = d0.abs() <= tol * scale * scale;
        match (d_zero, d0_zero) {
            (false, false) if d0 < 0.0 => ConicClass::Hyperbola,
            (false, false) if self.sigma() * d < 0.0 => ConicClass::RealEllipse,
            (false, false) => ConicClass::ImaginaryEllipse,
            (false, true) => ConicClass::Parabola,
            (true, false) if d0 < 0.0 => ConicClass::CrossingLines,
            (true, false) => ConicClass::PointEllipse,
            (true, true) => {
                // Table 1: g² − ac and f² − bc have the same sign or vanish.
                let p = g * g - a * c;
                let q = f * f - b * c;
                let z = tol * scale * scale;
                if p.abs() <= z && q.abs() <= z {
                    ConicClass::DoubleLine
                } else if p > 0.0 || q > 0.0 {
                    ConicClass::ParallelLines
                } else {
                    ConicClass::ImaginaryParallelLines
                }
            }
        }
    }
}

/// An ellipse's quadratic form in a frame whose x axis makes the angle θ with the ellipse's own
/// `a` axis: `A x² + 2B xy + C y² = 1`, i.e. P(7) divided by `D_n = a²b²` so that the constant
/// term is one (`A = cos²θ/a² + sin²θ/b²`, `B = (1/a² − 1/b²) cosθ sinθ`, `C = sin²θ/a² + cos²θ/b²`).
/// `K = AC − B² = 1/(a²b²)` is kept exactly rather than recomputed with cancellation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EllipseForm {
    pub a_coef: f64,
    pub b_coef: f64,
    pub c_coef: f64,
    pub k: f64,
}

impl EllipseForm {
    /// P(7) over `D_n`, for semi-axes `(a, b)` and `(cos θ, sin θ)`.
    #[inline]
    pub fn new(a: f64, b: f64, cos: f64, sin: f64) -> Self {
        Self::from_inverse_squares(1.0 / (a * a), 1.0 / (b * b), cos, sin)
    }

    /// [`EllipseForm::new`] from `1/a²` and `1/b²` (computed once per pair and reused).
    #[inline]
    pub fn from_inverse_squares(ia2: f64, ib2: f64, cos: f64, sin: f64) -> Self {
        if ia2 == ib2 {
            // A circle: the same in every frame, exactly (cos² + sin² is one only to rounding).
            return EllipseForm {
                a_coef: ia2,
                b_coef: 0.0,
                c_coef: ia2,
                k: ia2 * ib2,
            };
        }
        EllipseForm {
            a_coef: cos * cos * ia2 + sin * sin * ib2, // P(7) A_n / D_n
            b_coef: (ia2 - ib2) * cos * sin,           // P(7) B_n / D_n
            c_coef: sin * sin * ia2 + cos * cos * ib2, // P(7) C_n / D_n
            k: ia2 * ib2,
        }
    }

    /// `A x² + 2B xy + C y²` at `(x, y)` (centred form: subtract one for the implicit function).
    #[inline]
    pub fn quad(&self, x: f64, y: f64) -> f64 {
        (self.a_coef * x + 2.0 * self.b_coef * y) * x + self.c_coef * y * y
    }

    /// The general-form conic of the ellipse centred at `(cx, cy)`: P(5) for `(0, 0)`, P(6) for
    /// `(d, 0)`, both divided by `D_n`.
    pub fn conic_at(&self, cx: f64, cy: f64) -> Conic {
        let (a, h, b) = (self.a_coef, self.b_coef, self.c_coef);
        Conic {
            a,
            h,
            b,
            g: -(a * cx + h * cy),
            f: -(h * cx + b * cy),
            c: self.quad(cx, cy) - 1.0,
        }
    }
}

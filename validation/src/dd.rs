//! Minimal double-double ("DD") arithmetic for the test-suite reference implementation.
//!
//! A [`DD`] is the unevaluated sum `hi + lo` of two `f64` kept normalised
//! (`|lo| <= ulp(hi) / 2`), i.e. a number with about 106 significant bits
//! (~32 decimal digits). It is written from scratch on top of the three standard
//! error-free transformations:
//!
//! * [`two_sum`] (Knuth): `a + b == s + e` exactly, for any finite `a`, `b`;
//! * [`fast_two_sum`] (Dekker): the same in three flops when `|a| >= |b|`;
//! * [`two_prod`]: `a * b == p + e` exactly, `e` from one fused multiply-add.
//!
//! The operations are the usual accurate double-double algorithms (as in Hida,
//! Li & Bailey's QD library): the relative error of each operation is a small
//! multiple of [`DD::EPS`] = 2^-104 ≈ 4.9e-32. Results are *not* correctly rounded,
//! and overflow, underflow and non-finite values get no special treatment (none
//! of them occurs in the reference computations).
//!
//! # Elementary functions
//!
//! [`DD::sin`], [`DD::cos`], [`DD::sin_cos`], [`DD::x_minus_sin`], [`DD::atan2`],
//! [`DD::atan`], [`DD::asin`] and [`DD::acos`], for the overlap-area reference:
//!
//! * sine and cosine: argument reduction `r = x − k·π/2` in DD with the DD value
//!   [`DD::FRAC_PI_2`] (`k` the nearest integer), then the Taylor series of `sin r`
//!   and `cos r` on `|r| ≤ π/4` (15 terms each, truncation < 1e-37), summed by
//!   Horner's rule in DD. The absolute error is a few [`DD::EPS`] for `|x| ≲ 10`
//!   and grows like `|x|·1e-33` beyond (the error of `k` times the DD `π/2`);
//!   the reference only uses angles in `[−2π, 4π]`.
//! * `atan2(y, x)`: the `f64` `atan2` of the leading parts, `z`, corrected once by
//!   `z + (y cos z − x sin z)/(x cos z + y sin z)` (= `z + tan(θ − z)` for the true
//!   angle θ, so the remaining error is `(θ − z)³/3 ≈ 1e-48` plus rounding: a few
//!   `EPS` absolute). `atan`, `asin`, `acos` are reduced to `atan2`
//!   (`1 − x²` formed as `(1 − x)(1 + x)`).
//! * `x − sin x` without cancellation (the area of circular segments): its Taylor
//!   series for `|x| < 1`, the difference otherwise (where `x − sin x ≥ 0.15|x|`).

use std::cmp::Ordering;
use std::iter::Sum;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// Error-free sum: returns `(s, e)` with `s = fl(a + b)` and `a + b == s + e` exactly.
#[inline]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// Error-free sum for `|a| >= |b|` (or `a == 0`): `a + b == s + e` exactly.
#[inline]
pub fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let e = b - (s - a);
    (s, e)
}

/// Error-free product via FMA: `a * b == p + e` exactly (barring underflow).
#[inline]
pub fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let e = a.mul_add(b, -p);
    (p, e)
}

/// A double-double number `hi + lo` (normalised: `hi == fl(hi + lo)`).
///
/// The derived `PartialEq`/`PartialOrd` compare `hi` first, then `lo`, which is
/// the numeric order for normalised values.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct DD {
    /// Leading part: the `f64` nearest to the value.
    pub hi: f64,
    /// Trailing part: the rounding error of `hi`.
    pub lo: f64,
}

impl DD {
    /// Zero.
    pub const ZERO: DD = DD { hi: 0.0, lo: 0.0 };
    /// One.
    pub const ONE: DD = DD { hi: 1.0, lo: 0.0 };
    /// 2^-104 ≈ 4.93e-32: unit of the relative error of DD operations.
    pub const EPS: f64 = f64::EPSILON * f64::EPSILON;
    /// π to DD precision (error ≈ 3e-33).
    pub const PI: DD = DD {
        hi: std::f64::consts::PI,
        lo: 1.2246467991473532e-16,
    };
    /// π/2 to DD precision (exactly half of [`DD::PI`]).
    pub const FRAC_PI_2: DD = DD {
        hi: std::f64::consts::FRAC_PI_2,
        lo: 6.123233995736766e-17,
    };
    /// 2π to DD precision (exactly twice [`DD::PI`]).
    pub const TAU: DD = DD {
        hi: std::f64::consts::TAU,
        lo: 2.4492935982947064e-16,
    };

    /// The (renormalised) value `hi + lo`; both parts may be arbitrary.
    pub fn new(hi: f64, lo: f64) -> DD {
        let (hi, lo) = two_sum(hi, lo);
        DD { hi, lo }
    }

    /// The exact sum `a + b` of two `f64`.
    pub fn from_sum(a: f64, b: f64) -> DD {
        DD::new(a, b)
    }

    /// The exact product `a * b` of two `f64`.
    pub fn from_prod(a: f64, b: f64) -> DD {
        let (hi, lo) = two_prod(a, b);
        DD { hi, lo }
    }

    /// Nearest `f64` (up to the last-bit rounding of `hi + lo`).
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// `true` iff the value is exactly zero.
    pub fn is_zero(self) -> bool {
        self.hi == 0.0
    }

    /// `true` iff the value is strictly negative.
    pub fn is_negative(self) -> bool {
        self.hi < 0.0
    }

    /// `-1.0`, `0.0` or `1.0` according to the sign (0 for zero).
    pub fn signum(self) -> f64 {
        if self.hi > 0.0 {
            1.0
        } else if self.hi < 0.0 {
            -1.0
        } else {
            0.0
        }
    }

    /// Absolute value.
    pub fn abs(self) -> DD {
        if self.hi < 0.0 { -self } else { self }
    }

    /// `self * self`.
    pub fn sqr(self) -> DD {
        self * self
    }

    /// `1 / self`.
    pub fn recip(self) -> DD {
        DD::ONE / self
    }

    /// Multiplication by a power of two `k` (exact).
    pub fn mul_pow2(self, k: f64) -> DD {
        DD {
            hi: self.hi * k,
            lo: self.lo * k,
        }
    }

    /// Square root: the `f64` square root of `hi` plus one Newton correction
    /// computed in DD (`x + (a - x²) / (2x)`, with `x²` formed exactly).
    /// Returns 0 for 0 and NaN for negative input.
    pub fn sqrt(self) -> DD {
        if self.hi <= 0.0 {
            return if self.hi == 0.0 {
                DD::ZERO
            } else {
                DD {
                    hi: f64::NAN,
                    lo: f64::NAN,
                }
            };
        }
        let x = self.hi.sqrt();
        let r = self - DD::from_prod(x, x);
        let (hi, lo) = fast_two_sum(x, r.hi / (2.0 * x));
        DD { hi, lo }
    }

    /// The larger of two values.
    pub fn max(self, other: DD) -> DD {
        if other > self { other } else { self }
    }

    /// The smaller of two values.
    pub fn min(self, other: DD) -> DD {
        if other < self { other } else { self }
    }

    /// Total order for sorting (NaN compares equal to everything).
    pub fn cmp_total(&self, other: &DD) -> Ordering {
        self.partial_cmp(other).unwrap_or(Ordering::Equal)
    }
}

// ---------------------------------------------------------------------------
// Elementary functions (see the module documentation)
// ---------------------------------------------------------------------------

/// Number of Taylor terms of `sin`/`cos` on `|r| ≤ π/4`: `(π/4)^31/31! ≈ 7e-38`.
const TRIG_TERMS: usize = 15;

/// `sin r` and `cos r` for `|r| ≤ π/4 (+ a little)`, Taylor series by Horner's rule:
/// `sin r = r(1 − r²/(2·3)(1 − r²/(4·5)(1 − …)))`, `cos r = 1 − r²/(1·2)(1 − r²/(3·4)(1 − …))`.
fn sin_cos_taylor(r: DD) -> (DD, DD) {
    let r2 = r.sqr();
    let (mut s, mut c) = (DD::ONE, DD::ONE);
    for k in (1..=TRIG_TERMS).rev() {
        let k = k as f64;
        s = DD::ONE - s * r2 / ((2.0 * k) * (2.0 * k + 1.0));
        c = DD::ONE - c * r2 / ((2.0 * k - 1.0) * (2.0 * k));
    }
    (r * s, c)
}

impl DD {
    /// `(sin x, cos x)`; see the module documentation for the method and accuracy.
    pub fn sin_cos(self) -> (DD, DD) {
        let k = (self.hi / DD::FRAC_PI_2.hi).round();
        let r = self - DD::FRAC_PI_2 * k;
        let (s, c) = sin_cos_taylor(r);
        match (k.rem_euclid(4.0)) as u8 {
            0 => (s, c),
            1 => (c, -s),
            2 => (-s, -c),
            _ => (-c, s),
        }
    }

    /// `sin x`.
    pub fn sin(self) -> DD {
        self.sin_cos().0
    }

    /// `cos x`.
    pub fn cos(self) -> DD {
        self.sin_cos().1
    }

    /// `x − sin x`, accurate to a few `EPS` relative for all `x` (no cancellation for small `x`).
    pub fn x_minus_sin(self) -> DD {
        if self.hi.abs() >= 1.0 {
            return self - self.sin();
        }
        // x³/3! − x⁵/5! + … = x³/6 (1 − x²/(4·5)(1 − x²/(6·7)(1 − …))); x^33/33! < 1e-37.
        let x2 = self.sqr();
        let mut t = DD::ONE;
        for k in (2..=16).rev() {
            let k = k as f64;
            t = DD::ONE - t * x2 / ((2.0 * k) * (2.0 * k + 1.0));
        }
        self * x2 * t / 6.0
    }

    /// The angle of the point `(x, y)` (`self` is `y`), in `(−π, π]`; `atan2(0, 0) = 0`.
    /// Signed zeros are not distinguished beyond what `f64::atan2` does with the leading parts.
    pub fn atan2(self, x: DD) -> DD {
        let y = self;
        if x.is_zero() && y.is_zero() {
            return DD::ZERO;
        }
        let z = DD::from(y.hi.atan2(x.hi));
        let (s, c) = z.sin_cos();
        // tan(θ − z) with θ the true angle: r sin(θ − z) / (r cos(θ − z)).
        let num = y * c - x * s;
        let den = x * c + y * s;
        let out = z + num / den;
        // Keep the branch cut: the result stays in (−π, π].
        if out > DD::PI {
            out - DD::TAU
        } else if out <= -DD::PI {
            out + DD::TAU
        } else {
            out
        }
    }

    /// `atan x` in `(−π/2, π/2)`.
    pub fn atan(self) -> DD {
        self.atan2(DD::ONE)
    }

    /// `asin x` for `|x| ≤ 1`, in `[−π/2, π/2]`.
    pub fn asin(self) -> DD {
        let c = ((DD::ONE - self) * (DD::ONE + self)).sqrt();
        self.atan2(c)
    }

    /// `acos x` for `|x| ≤ 1`, in `[0, π]`.
    pub fn acos(self) -> DD {
        let s = ((DD::ONE - self) * (DD::ONE + self)).sqrt();
        s.atan2(self)
    }
}

impl From<f64> for DD {
    fn from(x: f64) -> DD {
        DD { hi: x, lo: 0.0 }
    }
}

impl PartialEq<f64> for DD {
    fn eq(&self, other: &f64) -> bool {
        *self == DD::from(*other)
    }
}

impl PartialOrd<f64> for DD {
    fn partial_cmp(&self, other: &f64) -> Option<Ordering> {
        self.partial_cmp(&DD::from(*other))
    }
}

impl Neg for DD {
    type Output = DD;
    #[inline]
    fn neg(self) -> DD {
        DD {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

/// Accurate DD addition (two TwoSums, two renormalisations).
#[inline]
fn dd_add(a: DD, b: DD) -> DD {
    let (s1, s2) = two_sum(a.hi, b.hi);
    let (t1, t2) = two_sum(a.lo, b.lo);
    let (s1, s2) = fast_two_sum(s1, s2 + t1);
    let (hi, lo) = fast_two_sum(s1, s2 + t2);
    DD { hi, lo }
}

#[inline]
fn dd_sub(a: DD, b: DD) -> DD {
    dd_add(a, -b)
}

/// DD multiplication: exact `hi * hi` plus the two cross terms.
#[inline]
fn dd_mul(a: DD, b: DD) -> DD {
    let (p, e) = two_prod(a.hi, b.hi);
    let e = e + (a.hi * b.lo + a.lo * b.hi);
    let (hi, lo) = fast_two_sum(p, e);
    DD { hi, lo }
}

/// DD division: three quotient digits, each from the exact-ish remainder.
#[inline]
fn dd_div(a: DD, b: DD) -> DD {
    let q1 = a.hi / b.hi;
    let r = a - b * q1;
    let q2 = r.hi / b.hi;
    let r = r - b * q2;
    let q3 = r.hi / b.hi;
    let (q1, q2) = fast_two_sum(q1, q2);
    DD { hi: q1, lo: q2 } + q3
}

macro_rules! dd_binop {
    ($tr:ident, $method:ident, $atr:ident, $amethod:ident, $f:ident) => {
        impl $tr for DD {
            type Output = DD;
            #[inline]
            fn $method(self, rhs: DD) -> DD {
                $f(self, rhs)
            }
        }
        impl $tr<f64> for DD {
            type Output = DD;
            #[inline]
            fn $method(self, rhs: f64) -> DD {
                $f(self, DD::from(rhs))
            }
        }
        impl $tr<DD> for f64 {
            type Output = DD;
            #[inline]
            fn $method(self, rhs: DD) -> DD {
                $f(DD::from(self), rhs)
            }
        }
        impl $atr for DD {
            #[inline]
            fn $amethod(&mut self, rhs: DD) {
                *self = $f(*self, rhs);
            }
        }
        impl $atr<f64> for DD {
            #[inline]
            fn $amethod(&mut self, rhs: f64) {
                *self = $f(*self, DD::from(rhs));
            }
        }
    };
}

dd_binop!(Add, add, AddAssign, add_assign, dd_add);
dd_binop!(Sub, sub, SubAssign, sub_assign, dd_sub);
dd_binop!(Mul, mul, MulAssign, mul_assign, dd_mul);
dd_binop!(Div, div, DivAssign, div_assign, dd_div);

impl Sum for DD {
    fn sum<I: Iterator<Item = DD>>(iter: I) -> DD {
        iter.fold(DD::ZERO, dd_add)
    }
}

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

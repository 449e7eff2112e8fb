//! Real roots of the pencil's characteristic cubic `D(λ) = t1 λ³ + t2 λ² + t3 λ + t4` (P10),
//! robust to the cases that break a bare closed-form (Cardano) solver.
//!
//! `roots::find_roots_cubic` alone is not reliable: it returns `[-4, 8]` for `λ³ − 12λ + 16`
//! (true: −4 and a double root 2), loses near-double roots, and gives order-one errors when the
//! leading coefficient is small or the coefficients span many decades. Contact detection lives on
//! exactly those cases (tangency is a double root; equal shapes give a root with a vanishing
//! quadratic part), so this solver does not trust any closed form. It
//!
//! 1. scales the coefficients and the variable by exact powers of two (no rounding), so that the
//!    leading and constant coefficients have comparable size;
//! 2. isolates every real root between the critical points of the cubic (the roots of its
//!    derivative, by the cancellation-free quadratic formula) and ±∞;
//! 3. evaluates the cubic at each critical point by compensated Horner (as accurate as Horner in
//!    twice the working precision), so that its sign is reliable; a critical value within a few ε
//!    of the size of the terms is a double root (both: a triple root) — the discriminant of the
//!    cubic vanishing to within a few ε;
//! 4. takes `roots::find_roots_cubic`'s values for the scaled cubic as candidates, keeps in each
//!    isolating bracket the candidate with the smallest residual (or, when Cardano missed or
//!    merged that root, a start from Taylor bounds at the critical point, on the side from which
//!    Newton converges monotonically), and polishes it by Newton's method guarded by bisection of
//!    the bracket, on the scaled polynomial itself — no deflation, so no error is carried from one
//!    root to the next.

/// Real roots of a polynomial of degree at most three, in ascending order, each with its
/// multiplicity (1, 2 or 3).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RealRoots {
    roots: [f64; 3],
    multiplicity: [u8; 3],
    len: u8,
}

impl RealRoots {
    /// The distinct real roots, ascending.
    #[inline]
    pub fn as_slice(&self) -> &[f64] {
        &self.roots[..self.len as usize]
    }

    /// Multiplicity of each root in [`as_slice`](Self::as_slice).
    #[inline]
    pub fn multiplicities(&self) -> &[u8] {
        &self.multiplicity[..self.len as usize]
    }

    /// Number of distinct real roots.
    #[inline]
    pub fn len(&self) -> usize {
        self.len as usize
    }

    /// True when there is no real root.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    #[inline]
    fn push(&mut self, x: f64, m: u8) {
        self.roots[self.len as usize] = x;
        self.multiplicity[self.len as usize] = m;
        self.len += 1;
    }

    #[inline]
    fn scaled(mut self, rho: f64) -> Self {
        for r in &mut self.roots[..self.len as usize] {
            *r *= rho;
        }
        self
    }

    #[inline]
    fn sorted(mut self) -> Self {
        let n = self.len as usize;
        for k in 1..n {
            let mut m = k;
            while m > 0 && self.roots[m - 1] > self.roots[m] {
                self.roots.swap(m - 1, m);
                self.multiplicity.swap(m - 1, m);
                m -= 1;
            }
        }
        self
    }
}

/// The largest power of two not above `x` (for positive, finite, normal `x`); 1 otherwise.
/// Multiplying by a power of two is exact, so scaling with it adds no rounding.
#[inline]
fn pow2_floor(x: f64) -> f64 {
    let p = f64::from_bits(x.to_bits() & 0x7FF0_0000_0000_0000);
    if p.is_normal() { p } else { 1.0 }
}

/// `1/pow2_floor(x)`, exactly (1 for zero, subnormal or non-finite `x`).
#[inline]
fn pow2_recip_floor(x: f64) -> f64 {
    // 1/2^e = 2^-e, built from the exponent bits: exact, and no division.
    let e = (x.to_bits() >> 52) & 0x7FF;
    if (1..=2045).contains(&e) {
        f64::from_bits((2046 - e) << 52)
    } else {
        1.0
    }
}

/// A power of two within a factor 2 of `(num/den)^(1/3)`, from the exponents alone (exact, and
/// far cheaper than a cube root). `num`, `den` positive and finite.
#[inline]
fn pow2_cube_root_ratio(num: f64, den: f64) -> f64 {
    let exp = |x: f64| ((x.to_bits() >> 52) & 0x7FF) as i64 - 1023;
    let e = (exp(num) - exp(den)).div_euclid(3).clamp(-300, 300);
    f64::from_bits(((e + 1023) as u64) << 52)
}

/// `c3 x³ + c2 x² + c1 x + c0` and its derivative, by Horner.
#[inline]
fn eval(c: &[f64; 4], x: f64) -> (f64, f64) {
    let [c3, c2, c1, c0] = *c;
    let p = ((c3 * x + c2) * x + c1) * x + c0;
    let dp = (3.0 * c3 * x + 2.0 * c2) * x + c1;
    (p, dp)
}

/// `c3 x³ + c2 x² + c1 x + c0` by compensated Horner (Graillat, Langlois & Louvet 2005): the
/// rounding errors of each product and sum are recovered exactly (`fma`, TwoSum) and added back,
/// so the result is as accurate as Horner in twice the working precision. Used for the critical
/// values, whose signs decide how many real roots there are.
#[inline]
fn eval_compensated(c: &[f64; 4], x: f64) -> f64 {
    let mut s = c[0];
    let mut r = 0.0;
    for &k in &c[1..] {
        let p = s * x;
        let pe = s.mul_add(x, -p); // exact error of the product
        let t = p + k;
        let z = t - p;
        let se = (p - (t - z)) + (k - z); // exact error of the sum (TwoSum)
        s = t;
        r = r * x + (pe + se);
    }
    s + r
}

/// The value of the cubic at a critical point, accurate enough to decide its sign: plain Horner
/// when that is clearly away from zero (its rounding error is at most about 6ε·Σ|c_k||x|^k), the
/// compensated evaluation otherwise.
#[inline]
fn critical_value(c: &[f64; 4], x: f64, mag: f64) -> f64 {
    let v = eval(c, x).0;
    if v.abs() > 16.0 * f64::EPSILON * mag {
        v
    } else {
        eval_compensated(c, x)
    }
}

/// Relative width of the band in which a critical value counts as zero (a double root): a few ε
/// of the size of the terms, now that the value itself is computed to about ε².
const DOUBLE_ROOT_BAND: f64 = 4.0 * f64::EPSILON;

/// `Σ|c_k||x|^k`, the scale against which a value of the cubic at `x` is small or not.
#[inline]
fn magnitude(c: &[f64; 4], x: f64) -> f64 {
    let ax = x.abs();
    ((c[0].abs() * ax + c[1].abs()) * ax + c[2].abs()) * ax + c[3].abs()
}

/// Real roots of `t1 λ³ + t2 λ² + t3 λ + t4`, ascending, with multiplicities.
///
/// Degree drops are handled (`t1 = 0` gives the quadratic's roots; a root at infinity is not
/// reported). A polynomial that is identically zero, or has a non-finite coefficient, has no
/// reported roots. Each simple root is accurate to a few ulps of its condition number; a root
/// whose critical value is within rounding of zero is reported once, as a double (or triple) root.
pub fn solve_cubic(t1: f64, t2: f64, t3: f64, t4: f64) -> RealRoots {
    let t = [t1, t2, t3, t4];
    if t.iter().any(|v| !v.is_finite()) {
        return RealRoots::default();
    }
    let m = t.iter().fold(0.0f64, |acc, v| acc.max(v.abs()));
    if m == 0.0 {
        return RealRoots::default();
    }
    let s = 1.0 / pow2_floor(m);
    let [c3, c2, c1, c0] = t.map(|v| v * s);
    if c3 == 0.0 {
        return solve_quadratic(c2, c1, c0);
    }
    if c0 == 0.0 {
        // λ = 0 is a root; the rest solve c3 λ² + c2 λ + c1 = 0.
        let q = solve_quadratic(c3, c2, c1);
        let mut out = RealRoots::default();
        let mut zero_mult = 1;
        for (&r, &k) in q.as_slice().iter().zip(q.multiplicities()) {
            if r == 0.0 {
                zero_mult += k;
            } else {
                out.push(r, k);
            }
        }
        out.push(0.0, zero_mult);
        return out.sorted();
    }
    // Balance the variable, λ = ρ μ with ρ a power of two near (|c0|/|c3|)^(1/3): then the
    // leading and constant coefficients are of comparable size and a small leading coefficient
    // (a root near infinity) is no longer small.
    let rho = pow2_cube_root_ratio(c0.abs(), c3.abs());
    let mut c = [c3 * rho * rho * rho, c2 * rho * rho, c1 * rho, c0];
    if c.iter().any(|v| !v.is_finite()) {
        return solve_quadratic(c2, c1, c0);
    }
    let m = c.iter().fold(0.0f64, |acc, v| acc.max(v.abs()));
    let s = 1.0 / pow2_floor(m);
    for v in &mut c {
        *v *= s;
    }
    if c[0] < 0.0 {
        // Same roots; make the cubic increasing at +∞.
        for v in &mut c {
            *v = -*v;
        }
    }
    // Cardano's values are usually right to a few ulps: starting points, never answers.
    let candidates = roots::find_roots_cubic(c[0], c[1], c[2], c[3]);
    solve_normalised(&c, candidates.as_ref())
        .scaled(rho)
        .sorted()
}

/// Cube root to about 1e-15 relative, from a bit-level first guess refined by two Halley steps
/// (no library call: `cbrt` is a software routine here and several times slower).
#[inline]
fn cbrt_fast(a: f64) -> f64 {
    let x = a.abs();
    if !(x.is_normal()) {
        return a.cbrt();
    }
    // Dividing the exponent by three via the bit pattern: x^(−1/3) within a few percent; then
    // Newton for the inverse cube root, z ← z (4 − x z³)/3, which needs no division.
    let mut z = f64::from_bits(0x553E_F0FF_289D_D796 - x.to_bits() / 3);
    for _ in 0..4 {
        z *= (4.0 - x * z * z * z) * (1.0 / 3.0);
    }
    (x * z * z).copysign(a)
}

/// A starting point for the single real root, by Cardano's formula in its cancellation-free
/// form about the inflection point x0 (value v0): with x = x0 + y the cubic is
/// `c3 (y³ + P y + Q)`, `P = −disc/(3c3²)`, `Q = v0/c3`, and `y = A − P/(3A)` with
/// `A = −∛(Q/2 + sign(Q)·√(Q²/4 + P³/27))`.
#[inline]
fn cardano_start(c3: f64, x0: f64, v0: f64, disc: f64) -> f64 {
    let p = -disc / (3.0 * c3 * c3);
    let q = v0 / c3;
    let d = (0.25 * q * q + p * p * p / 27.0).max(0.0);
    let a = -cbrt_fast(0.5 * q + d.sqrt().copysign(q));
    if a == 0.0 { x0 } else { x0 + a - p / (3.0 * a) }
}

/// One real root of `t1 λ³ + t2 λ² + t3 λ + t4` when the cubic has exactly one, fast: the
/// discriminant of the depressed cubic decides (only when its sign is certain beyond a bound on
/// its rounding), Cardano's formula starts and Halley's method finishes, verified by the residual
/// against its rounding bound. `None` whenever any of that is in doubt (three real roots, a
/// discriminant near zero, no convergence): then [`solve_cubic`] has the last word.
///
/// The pencil needs no more than this in the common case: two ellipses crossing at two points
/// have exactly one real root, and every real member of the pencil passes through every real
/// crossing.
pub fn one_real_root(t1: f64, t2: f64, t3: f64, t4: f64) -> Option<f64> {
    let m = t1.abs().max(t2.abs()).max(t3.abs()).max(t4.abs());
    if !(m.is_finite() && t1 != 0.0 && t4 != 0.0) {
        return None;
    }
    let s = pow2_recip_floor(m);
    let (c3, c0) = (t1 * s, t4 * s);
    let rho = pow2_cube_root_ratio(c0.abs(), c3.abs());
    let mut c = [c3 * rho * rho * rho, t2 * s * rho * rho, t3 * s * rho, c0];
    let m = c.iter().fold(0.0f64, |acc, v| acc.max(v.abs()));
    let s = if c[0] < 0.0 { -1.0 } else { 1.0 } * pow2_recip_floor(m);
    for v in &mut c {
        *v *= s;
    }
    let [c3, c2, c1, _] = c;
    let r3 = 1.0 / c3;
    let x0 = -c2 * r3 * (1.0 / 3.0);
    let disc = c2 * c2 - 3.0 * c3 * c1;
    let v0 = eval(&c, x0).0;
    // y³ + P y + Q about x0; D > 0: one real root. Bounds on the rounding of P, Q and D.
    let (p, q) = (-disc * r3 * r3 * (1.0 / 3.0), v0 * r3);
    let (q2, p3) = (0.25 * q * q, p * p * p * (1.0 / 27.0));
    let d = q2 + p3;
    let dq = 8.0 * f64::EPSILON * magnitude(&c, x0) * r3;
    let dp = 8.0 * f64::EPSILON * (c2 * c2 + (3.0 * c3 * c1).abs()) * r3 * r3;
    let d_err = 0.5 * q.abs() * dq + p * p * dp + 8.0 * f64::EPSILON * (q2 + p3.abs());
    // (Also declines a NaN discriminant.)
    if d.is_nan() || d <= 4.0 * d_err {
        return None;
    }
    let mut x = cardano_start(c3, x0, v0, disc);
    for _ in 0..6 {
        let (px, dpx) = eval(&c, x);
        if px.abs() <= 2.0 * f64::EPSILON * magnitude(&c, x)
            && px.abs() <= 4.0 * f64::EPSILON * (x * dpx).abs()
        {
            return Some(x * rho);
        }
        let ddp = 6.0 * c3 * x + 2.0 * c2;
        let next = x - 2.0 * px * dpx / (2.0 * dpx * dpx - px * ddp);
        if !next.is_finite() {
            return None;
        }
        let step = (next - x).abs();
        x = next;
        // Halley's error after a step is of the order of the step cubed.
        if step <= 1e-6 * x.abs() {
            return Some(x * rho);
        }
    }
    None
}

/// The roots of `c3 μ³ + c2 μ² + c1 μ + c0` with `c3 > 0`, coefficients of order one.
fn solve_normalised(c: &[f64; 4], candidates: &[f64]) -> RealRoots {
    let [c3, c2, c1, _] = *c;
    let mut out = RealRoots::default();
    // Inflection point and derivative's (quarter) discriminant.
    let x0 = -c2 / (3.0 * c3);
    let disc = c2 * c2 - 3.0 * c3 * c1;
    let disc_err = 4.0 * f64::EPSILON * (c2 * c2 + (3.0 * c3 * c1).abs());
    if disc <= disc_err {
        // Monotone (or a triple root at the inflection point).
        let m0 = magnitude(c, x0);
        let v0 = critical_value(c, x0, m0);
        if v0.abs() <= DOUBLE_ROOT_BAND * m0 && disc.abs() <= disc_err {
            out.push(x0, 3);
            return out;
        }
        if v0 == 0.0 {
            out.push(x0, 1);
            return out;
        }
        // Both |v0|/p'(x0) and (|v0|/c3)^(1/3) bound the distance to the root from above
        // (p(x0+h) − v0 = p'(x0) h + c3 h³ with both terms of one sign).
        let side = if v0 > 0.0 { -1.0 } else { 1.0 };
        out.push(
            root_beside(c, x0, v0, side, cardano_start(c3, x0, v0, disc)),
            1,
        );
        return out;
    }
    // Critical points x1 < x2 by the cancellation-free quadratic formula.
    let sq = disc.sqrt();
    let q = -(c2 + sq.copysign(c2));
    let (ra, rb) = (q / (3.0 * c3), c1 / q);
    let (x1, x2) = if ra < rb { (ra, rb) } else { (rb, ra) };
    let (m1, m2) = (magnitude(c, x1), magnitude(c, x2));
    let v1 = critical_value(c, x1, m1);
    let v2 = critical_value(c, x2, m2);
    let z1 = v1.abs() <= DOUBLE_ROOT_BAND * m1;
    let z2 = v2.abs() <= DOUBLE_ROOT_BAND * m2;
    // c3 > 0: local maximum v1 at x1, local minimum v2 at x2. Starting points from the Taylor
    // expansion at a critical point, p(x_k + h) ≈ v_k + p''(x_k) h²/2, are good exactly where
    // Cardano's are not (a root next to a near-double pair).
    let pp1 = 6.0 * c3 * x1 + 2.0 * c2;
    let pp2 = 6.0 * c3 * x2 + 2.0 * c2;
    let h1 = (-2.0 * v1 / pp1).abs().sqrt();
    let h2 = (-2.0 * v2 / pp2).abs().sqrt();
    let left = |out: &mut RealRoots| {
        let h = h1;
        let start = best_start(c, candidates, f64::NEG_INFINITY, x1, &[x1 - h]);
        out.push(root_beside(c, x1, v1, -1.0, start), 1);
    };
    let right = |out: &mut RealRoots| {
        let h = h2;
        let start = best_start(c, candidates, x2, f64::INFINITY, &[x2 + h]);
        out.push(root_beside(c, x2, v2, 1.0, start), 1);
    };
    match (z1, z2) {
        (true, true) => out.push(x0, 3),
        (true, false) => {
            out.push(x1, 2);
            right(&mut out);
        }
        (false, true) => {
            left(&mut out);
            out.push(x2, 2);
        }
        // A single real root beyond one critical point: Cardano's start (one real root is
        // exactly the case where its formula has no complex intermediate).
        (false, false) if v1 < 0.0 || v2 > 0.0 => {
            let v0 = eval(c, x0).0;
            let start = cardano_start(c3, x0, v0, disc);
            let (xc, vc, side) = if v1 < 0.0 {
                (x2, v2, 1.0)
            } else {
                (x1, v1, -1.0)
            };
            out.push(root_beside(c, xc, vc, side, start), 1);
        }
        (false, false) => {
            if v1 > 0.0 {
                left(&mut out);
            }
            if v1 > 0.0 && v2 < 0.0 {
                let start = best_start(c, candidates, x1, x2, &[x1 + h1, x2 - h2, x0]);
                out.push(polish(c, x1, x2, false, start, eval(c, start)), 1);
            }
            if v2 < 0.0 {
                right(&mut out);
            }
        }
    }
    out
}

/// Of the candidates inside `(lo, hi)` and the `extra` starting points, the one with the smallest
/// residual ("keep the best by residual").
#[inline]
fn best_start(c: &[f64; 4], candidates: &[f64], lo: f64, hi: f64, extra: &[f64]) -> f64 {
    if candidates.is_empty() && extra.len() == 1 {
        return extra[0];
    }
    let mut best = (extra[0], f64::INFINITY);
    for &x in candidates.iter().chain(extra) {
        if x > lo && x < hi {
            let r = eval(c, x).0.abs();
            if r < best.1 {
                best = (x, r);
            }
        }
    }
    best.0
}

/// The root on the `side` (±1) of the critical (or inflection) point `xc`, whose value `vc` is
/// non-zero, from the starting point `x`: the bracket is closed by stepping away from `xc`
/// (doubling the distance) until the sign differs from `vc`'s, then polished. Stepping only away
/// from `xc` keeps the bracket inside this root's interval.
fn root_beside(c: &[f64; 4], xc: f64, vc: f64, side: f64, x: f64) -> f64 {
    // A start on the wrong side of xc (an inaccurate formula) restarts just beside xc.
    let x = if (x - xc) * side > 0.0 {
        x
    } else {
        xc + side * f64::EPSILON * xc.abs().max(1.0)
    };
    let start = eval(c, x);
    if start.0 == 0.0 {
        return x;
    }
    // The sign at x tells whether the root lies between xc and x, or beyond x (then the
    // bracket stays open on that side until a step crosses the root).
    let beyond = (start.0 > 0.0) == (vc > 0.0);
    let far = if beyond { side * f64::INFINITY } else { x };
    let (lo, hi) = if side < 0.0 { (far, xc) } else { (xc, far) };
    // The cubic has vc's sign on xc's side of the root and the other sign beyond it.
    let lo_negative = if side < 0.0 { vc > 0.0 } else { vc < 0.0 };
    polish(c, lo, hi, lo_negative, x, start)
}

/// Halley's method (cubic convergence; `p''` costs two flops for a cubic) from `x`, where the
/// cubic is `(p, dp)`, on the bracket `[lo, hi]` across which it changes sign (`lo_negative`:
/// negative at `lo`), falling back to Newton and then to bisection whenever a step would leave
/// the bracket.
fn polish(
    c: &[f64; 4],
    mut lo: f64,
    mut hi: f64,
    lo_negative: bool,
    mut x: f64,
    (mut p, mut dp): (f64, f64),
) -> f64 {
    // The finite end of an open bracket: a step that cannot be trusted doubles the distance
    // from it instead.
    let anchor = if hi == f64::INFINITY { lo } else { hi };
    for _ in 0..200 {
        if p == 0.0 {
            return x;
        }
        if (p < 0.0) == lo_negative {
            lo = x;
        } else {
            hi = x;
        }
        let ddp = 6.0 * c[0] * x + 2.0 * c[1];
        let halley = x - 2.0 * p * dp / (2.0 * dp * dp - p * ddp);
        let (next, converged) = if halley > lo && halley < hi {
            // Halley's error after a step is of the order of the step cubed: a step below
            // 1e-6·|x| leaves an error far below an ulp, with no need to evaluate again.
            (halley, (halley - x).abs() <= 1e-6 * halley.abs())
        } else {
            let newton = x - p / dp;
            if newton > lo && newton < hi {
                (newton, false)
            } else {
                (split(lo, hi, x, anchor), false)
            }
        };
        let step = (next - x).abs();
        x = next;
        if converged
            || step < f64::EPSILON * x.abs() * 0.5
            || hi - lo <= 2.0 * f64::EPSILON * x.abs()
        {
            return x;
        }
        (p, dp) = eval(c, x);
        // A residual at the level of its own rounding with a correction of a few ulps: x is
        // within the root's conditioning, 2ε·Σ|c_k||x|^k / |p'|. (A small residual alone is
        // not enough: near a double root p is small on a wide flat stretch.)
        if p.abs() <= 4.0 * f64::EPSILON * (x * dp).abs()
            && p.abs() <= 2.0 * f64::EPSILON * magnitude(c, x)
        {
            return x;
        }
    }
    x
}

/// A point strictly inside `(lo, hi)`: beyond `x` at twice its distance from `anchor` (the
/// finite end it started from) when the bracket is open; halfway in the exponent when the ends differ by orders of magnitude
/// (so that a bracket like (1e-12, 1e15) takes tens, not hundreds, of steps); halfway otherwise.
#[inline]
fn split(lo: f64, hi: f64, x: f64, anchor: f64) -> f64 {
    if hi == f64::INFINITY || lo == f64::NEG_INFINITY {
        let step = (x - anchor)
            .abs()
            .max(f64::EPSILON * x.abs())
            .max(f64::MIN_POSITIVE);
        return if hi == f64::INFINITY {
            x + step
        } else {
            x - step
        };
    }
    if lo < 0.0 && hi > 0.0 {
        return 0.0;
    }
    let (a, b) = (lo.abs().min(hi.abs()), lo.abs().max(hi.abs()));
    if a > 0.0 && b > 16.0 * a {
        let g = (a * b).sqrt();
        return if lo > 0.0 { g } else { -g };
    }
    0.5 * (lo + hi)
}

/// Real roots of `c2 x² + c1 x + c0` (degree drops handled), ascending, by the
/// cancellation-free formula; a discriminant within rounding of zero gives a double root.
pub fn solve_quadratic(c2: f64, c1: f64, c0: f64) -> RealRoots {
    let mut out = RealRoots::default();
    if c2 == 0.0 {
        if c1 != 0.0 {
            out.push(-c0 / c1, 1);
        }
        return out;
    }
    let disc = c1 * c1 - 4.0 * c2 * c0;
    let err = 4.0 * f64::EPSILON * (c1 * c1 + (4.0 * c2 * c0).abs());
    if disc.abs() <= err {
        out.push(-c1 / (2.0 * c2), 2);
        return out;
    }
    if disc < 0.0 {
        return out;
    }
    let q = -0.5 * (c1 + disc.sqrt().copysign(c1));
    let (r1, r2) = (q / c2, c0 / q);
    out.push(r1, 1);
    out.push(r2, 1);
    out.sorted()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn roots(t: [f64; 4]) -> Vec<(f64, u8)> {
        let r = solve_cubic(t[0], t[1], t[2], t[3]);
        r.as_slice()
            .iter()
            .copied()
            .zip(r.multiplicities().iter().copied())
            .collect()
    }

    #[test]
    fn double_root_that_cardano_misses() {
        // roots::find_roots_cubic gives [-4, 8] here.
        assert_eq!(roots([1.0, 0.0, -12.0, 16.0]), vec![(-4.0, 1), (2.0, 2)]);
    }

    #[test]
    fn fast_cube_root_is_accurate_over_the_whole_range() {
        let mut x = 1e-300;
        while x < 1e300 {
            for v in [x, -x] {
                let (got, want) = (cbrt_fast(v), v.cbrt());
                assert!(
                    (got / want - 1.0).abs() <= 2e-15,
                    "cbrt({v}) = {got}, std gives {want}"
                );
            }
            x *= 1.37;
        }
        assert_eq!(cbrt_fast(0.0), 0.0);
        assert!((cbrt_fast(8.0) - 2.0).abs() <= 4.0 * f64::EPSILON);
    }

    #[test]
    fn triple_root() {
        assert_eq!(roots([1.0, -3.0, 3.0, -1.0]), vec![(1.0, 3)]);
        assert_eq!(roots([-2.0, 6.0, -6.0, 2.0]), vec![(1.0, 3)]);
    }

    #[test]
    fn three_simple_roots_to_a_few_ulps() {
        // Horner's rounding makes p vanish on a few floats around each root: a few ulps is the
        // floor of a double-precision evaluation.
        let r = roots([1.0, -6.0, 11.0, -6.0]);
        assert_eq!(r.len(), 3);
        for ((x, m), exact) in r.iter().zip([1.0, 2.0, 3.0]) {
            assert_eq!(*m, 1);
            assert!(
                (x - exact).abs() <= 4.0 * f64::EPSILON * exact,
                "{x} vs {exact}"
            );
        }
    }

    #[test]
    fn zero_constant_term_and_degree_drops() {
        assert_eq!(roots([1.0, -1.0, 0.0, 0.0]), vec![(0.0, 2), (1.0, 1)]);
        assert_eq!(roots([0.0, 1.0, -3.0, 2.0]), vec![(1.0, 1), (2.0, 1)]);
        assert_eq!(roots([0.0, 0.0, 2.0, -1.0]), vec![(0.5, 1)]);
        assert!(roots([0.0, 0.0, 0.0, 0.0]).is_empty());
        assert!(roots([f64::NAN, 1.0, 0.0, 0.0]).is_empty());
    }
}

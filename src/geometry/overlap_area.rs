//! Overlap areas for the energy-conserving normal force (Feng, Han & Owen 2012): the caps that a
//! chord cuts off circles, ellipses and polygons, and the lens of two disks with its inverse
//! (the overlap of two disks whose lens has a given area).
//!
//! Two convex bodies whose boundaries cross at two points overlap in a lens that P's chord
//! splits into two caps: the part of i beyond the chord (towards j) and the part of j beyond it
//! (towards i). So the overlap area is `A = cap_i + cap_j`, and each cap depends only on the
//! chord's two end points on that body's boundary.
//!
//! An ellipse `x²/a² + y²/b² ≤ 1` maps onto the unit disk by `(x, y) ↦ (x/a, y/b)`, which
//! scales areas by `1/(ab)`; a chord of image length `ℓ` subtends the central angle
//! `Δφ = 2 asin(ℓ/2)` there (Δφ is the difference of the end points' eccentric angles), so the
//! ellipse's minor cap is `½ab(Δφ − sin Δφ)`. `Δφ − sin Δφ` cancels catastrophically for small
//! chords (a DEM contact's chord is a few per cent of the body); it is evaluated here by series
//! where it cancels, to a few units in the last place everywhere.
//!
//! Everything is pure geometry: no mass, force or time.

use std::f64::consts::PI;
use wide::f64x2;

/// `φ − sin φ`, to a few ulps for every φ (its Taylor series below |φ| = 1, where the
/// difference cancels).
#[inline]
pub fn phi_minus_sin(phi: f64) -> f64 {
    if phi.abs() < 1.0 {
        // Σ_{k≥1} (−1)^{k+1} φ^{2k+1}/(2k+1)!, k ≤ 9: the first omitted term is below 2e-19 of
        // the first.
        let p = phi * phi;
        let s = 1.0 / 6.0
            - p * (1.0 / 120.0
                - p * (1.0 / 5040.0
                    - p * (1.0 / 362_880.0
                        - p * (1.0 / 39_916_800.0
                            - p * (1.0 / 6_227_020_800.0
                                - p * (1.0 / 1_307_674_368_000.0
                                    - p * (1.0 / 355_687_428_096_000.0
                                        - p * (1.0 / 121_645_100_408_832_000.0))))))));
        phi * p * s
    } else {
        phi - phi.sin()
    }
}

/// Taylor coefficients of `½(Δφ − sin Δφ)` in the chord length ℓ, `Δφ = 2 asin(ℓ/2)`: the
/// series is `ℓ³ Σ_k C[k] ℓ^{2k}` (all terms positive; exact rationals rounded once).
const UNIT_CAP_SERIES: [f64; 12] = [
    0.08333333333333333,
    0.00625,
    0.0008370535714285714,
    0.00013563368055555556,
    2.4275346235795453e-05,
    4.621652456430288e-06,
    9.179115295410156e-07,
    1.8801759271060719e-07,
    3.9428031366122395e-08,
    8.422787123847576e-09,
    1.8264630773995557e-09,
    4.009916665381752e-10,
];

/// Area of the minor cap of the unit disk cut off by a chord of length `l` (0 ≤ ℓ ≤ 2):
/// `½(Δφ − sin Δφ)` with `Δφ = 2 asin(ℓ/2)`. Accurate to a few ulps; for ℓ ≤ ½ a polynomial
/// (its truncation error is below 1.2e-16 relative), no elementary function.
#[inline]
pub fn unit_cap(l: f64) -> f64 {
    let x = l * l;
    match unit_cap_series(x) {
        Some(s) => x * l * s,
        None => unit_cap_by_asin(l),
    }
}

/// [`unit_cap`] from the chord's square `ℓ² = x`, as a caller that has it (an ellipse's cap:
/// the chord's image on the unit disk) holds it: the series runs on x itself, and the square
/// root ℓ, needed only for the last factor, is taken beside it rather than before it — the
/// cap waits on one square root less (and x is not rounded twice through √x²).
#[inline]
pub fn unit_cap_of_square(x: f64) -> f64 {
    let l = x.sqrt();
    match unit_cap_series(x) {
        Some(s) => x * l * s,
        None => unit_cap_by_asin(l),
    }
}

/// `Σ_k C[k] x^k` of [`UNIT_CAP_SERIES`] at `x = ℓ²` for ℓ ≤ 1 (the cap is `ℓ³` times it);
/// `None` beyond, where the series converges too slowly.
#[inline(always)]
fn unit_cap_series(x: f64) -> Option<f64> {
    let c = &UNIT_CAP_SERIES;
    // Estrin's scheme (independent products, short dependency chains); the terms fall like
    // (ℓ²/4)^k, so a DEM contact's short chord needs only the first eight.
    let x2 = x * x;
    let x4 = x2 * x2;
    let low = (c[0] + c[1] * x) + (c[2] + c[3] * x) * x2;
    let mid = (c[4] + c[5] * x) + (c[6] + c[7] * x) * x2;
    if x <= 1.0 / 64.0 {
        // ℓ ≤ 1/8: the next term is below 2e-17 of the first.
        Some(low + mid * x4)
    } else if x <= 0.25 {
        let high = (c[8] + c[9] * x) + (c[10] + c[11] * x) * x2;
        Some(low + (mid + high * x4) * x4)
    } else {
        None
    }
}

/// The sum of two minor caps of ellipses (a shallow lens: the two sides of one chord), each
/// `a_k b_k · unit_cap(ℓ_k)` for the chord's image on body k's unit disk of length² `l2[k]`
/// (`ab = [a_i b_i, a_j b_j]`), as [`unit_cap_of_square`] gives each: the two caps are the two
/// lanes of one SIMD register (each lane's arithmetic is IEEE's, the same bits as two scalar
/// calls), so they cost one series. Caller's promise: both caps are minor (`ℓ² ≤ 2`).
#[inline(always)]
pub fn minor_caps_sum(ab: [f64; 2], l2: [f64; 2]) -> f64 {
    if !(l2[0] <= 0.25 && l2[1] <= 0.25) {
        return minor_caps_sum_long(ab, l2);
    }
    let c = &UNIT_CAP_SERIES;
    let k = f64x2::splat;
    let x = f64x2::new(l2);
    // `unit_cap_series`, lane by lane, the same operations: both of its forms, each lane
    // taking its own (a select, not a branch).
    let (x2, l) = (x * x, x.sqrt());
    let x4 = x2 * x2;
    let low = (k(c[0]) + k(c[1]) * x) + (k(c[2]) + k(c[3]) * x) * x2;
    let mid = (k(c[4]) + k(c[5]) * x) + (k(c[6]) + k(c[7]) * x) * x2;
    let high = (k(c[8]) + k(c[9]) * x) + (k(c[10]) + k(c[11]) * x) * x2;
    let short = x.simd_le(k(1.0 / 64.0));
    let s = short.select(low + mid * x4, low + (mid + high * x4) * x4);
    let caps = (f64x2::new(ab) * ((x * l) * s)).to_array();
    caps[0] + caps[1]
}

/// [`minor_caps_sum`] where a chord is longer than ½ of the unit disk (its cap takes the closed
/// form): each cap on its own.
#[inline(never)]
fn minor_caps_sum_long(ab: [f64; 2], l2: [f64; 2]) -> f64 {
    ab[0] * unit_cap_of_square(l2[0]) + ab[1] * unit_cap_of_square(l2[1])
}

/// The unit cap of a long chord (ℓ > ½), by the closed form.
#[cold]
fn unit_cap_by_asin(l: f64) -> f64 {
    0.5 * phi_minus_sin(2.0 * (0.5 * l).min(1.0).asin())
}

/// Area of the minor cap of the unit disk cut off by a line at distance `s` (0 ≤ s ≤ 1) from
/// the centre: `½(Δφ − sin Δφ)` with `Δφ = 2 acos(s)`. Well conditioned for chords near the
/// centre (where [`unit_cap`]'s `asin` is not); for small caps use [`unit_cap`].
#[inline]
pub fn unit_cap_at_distance(s: f64) -> f64 {
    0.5 * phi_minus_sin(2.0 * s.clamp(0.0, 1.0).acos())
}

/// Area of the part of the ellipse `x²/a² + y²/b² ≤ 1` (its own frame) cut off by the chord
/// from `p` to `p + e`, both end points on the boundary: the minor cap, or with `major` the
/// rest of the ellipse. A circle is `a = b = r`.
///
/// `e` is passed apart from `p` so that a caller who has the chord vector more accurately than
/// the difference of two end points (`2·half·direction`) keeps that accuracy.
#[inline]
pub fn ellipse_cap(a: f64, b: f64, p: [f64; 2], e: [f64; 2], major: bool) -> f64 {
    ellipse_cap_with(a, b, || p, e, major)
}

/// [`ellipse_cap`] for a caller that already holds `inv2 = [1/a², 1/b²]` (the conic pair's
/// forms): the chord's image on the unit disk has length² `e_x²/a² + e_y²/b²` without a division,
/// and the end point `p` is computed only when needed (a chord near the centre).
#[inline(always)]
pub fn ellipse_cap_inverse(
    a: f64,
    b: f64,
    inv2: [f64; 2],
    p: impl FnOnce() -> [f64; 2],
    e: [f64; 2],
    major: bool,
) -> f64 {
    let l2 = e[0] * e[0] * inv2[0] + e[1] * e[1] * inv2[1];
    let minor = if l2 <= 2.0 {
        unit_cap_of_square(l2)
    } else {
        let p = p();
        let (ex, ey) = (e[0] / a, e[1] / b);
        let (px, py) = (p[0] / a, p[1] / b);
        unit_cap_at_distance((px * ey - py * ex).abs() / (ex * ex + ey * ey).sqrt())
    };
    a * b * if major { PI - minor } else { minor }
}

/// [`ellipse_cap`] with the end point `p` computed only when needed (a chord near the centre).
#[inline]
pub fn ellipse_cap_with(
    a: f64,
    b: f64,
    p: impl FnOnce() -> [f64; 2],
    e: [f64; 2],
    major: bool,
) -> f64 {
    let (ex, ey) = (e[0] / a, e[1] / b);
    let l2 = ex * ex + ey * ey;
    let minor = if l2 <= 2.0 {
        unit_cap_of_square(l2)
    } else {
        // The chord passes near the centre: its distance s = |p′ × e′| / ℓ decides.
        let p = p();
        let (px, py) = (p[0] / a, p[1] / b);
        unit_cap_at_distance((px * ey - py * ex).abs() / l2.sqrt())
    };
    a * b * if major { PI - minor } else { minor }
}

/// Area of the part of the ellipse `x²/a² + y²/b² ≤ 1` (its own frame) beyond a line that
/// penetrates it by `depth` along the line's unit normal `n` (pointing out of the part cut
/// off): `depth = S(n) − c` for the line `n·x = c`, with `S(n) = √(a²n_x² + b²n_y²)` the
/// support. From the depth alone, which a contact knows to rounding, rather than from the
/// line's two crossings, which a nearly tangent line places only to ε/sin(angle): the image of
/// the line on the unit disk is at distance `1 − δ/S`, so the cap's image has sagitta
/// `t = δ/S` and chord `2√(t(2 − t))`.
#[inline]
pub fn ellipse_cap_at_depth(a: f64, b: f64, n: [f64; 2], depth: f64) -> f64 {
    let support = ((a * n[0]) * (a * n[0]) + (b * n[1]) * (b * n[1])).sqrt();
    let t = (depth / support).clamp(0.0, 2.0);
    let u = t.min(2.0 - t); // the minor cap's sagitta
    let minor = if u <= 1.0 - std::f64::consts::FRAC_1_SQRT_2 {
        unit_cap_of_square(4.0 * (u * (2.0 - u)))
    } else {
        unit_cap_at_distance(1.0 - u)
    };
    a * b * if t > 1.0 { PI - minor } else { minor }
}

/// Area of the part of a convex polygon (vertices counter-clockwise) where `u·(x − m) ≥ 0`: the
/// cap a line through `m` with normal `u` (any length) cuts off it, towards `u`.
pub fn polygon_cap(vertices: &[[f64; 2]], m: [f64; 2], u: [f64; 2]) -> f64 {
    let n = vertices.len();
    let side = |p: [f64; 2]| u[0] * (p[0] - m[0]) + u[1] * (p[1] - m[1]);
    let mut twice = 0.0;
    // Shoelace over the clipped polygon, relative to m (small numbers, small rounding).
    let mut first: Option<[f64; 2]> = None;
    let mut last = [0.0; 2];
    let mut push = |p: [f64; 2]| {
        let q = [p[0] - m[0], p[1] - m[1]];
        match first {
            None => first = Some(q),
            Some(_) => twice += last[0] * q[1] - last[1] * q[0],
        }
        last = q;
    };
    for k in 0..n {
        let (p, q) = (vertices[k], vertices[(k + 1) % n]);
        let (sp, sq) = (side(p), side(q));
        if sp >= 0.0 {
            push(p);
        }
        if (sp >= 0.0) != (sq >= 0.0) {
            let t = sp / (sp - sq);
            push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    if let Some(f) = first {
        twice += last[0] * f[1] - last[1] * f[0];
    }
    0.5 * twice.abs()
}

/// Area of a simple polygon (shoelace about its first vertex, so that a small polygon far from
/// the frame's origin — a rectangle's corner just past a wall — keeps its relative accuracy).
pub fn polygon_area(vertices: &[[f64; 2]]) -> f64 {
    let Some(&o) = vertices.first() else {
        return 0.0;
    };
    let mut twice = 0.0;
    for k in 1..vertices.len().saturating_sub(1) {
        let (p, q) = (vertices[k], vertices[k + 1]);
        twice += (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]);
    }
    0.5 * twice.abs()
}

/// The lens in which two disks of radii `r1 ≤ r2` overlap (`r2 = ∞`: a disk against a
/// half-plane, whose lens is one circular segment). Parametrised by the overlap
/// `δ = r1 + r2 − d` (d the distance of the centres) or by the common chord `L`.
///
/// The radii are kept in the order given: what the dynamics asks for every contact
/// ([`DiskLens::equivalent_depth`], [`DiskLens::effective_radius`]) is symmetric in them, and
/// a contact meets its two radii in either order at random, so ordering them there would cost
/// a mispredicted branch half the time; the other methods order them ([`DiskLens::radii`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiskLens {
    ra: f64,
    rb: f64,
    /// `1/ra`, `1/rb` (0 for a half-plane): the series needs the inverses.
    ia: f64,
    ib: f64,
}

impl DiskLens {
    /// The lens of disks of radii `ra`, `rb` (either may be `f64::INFINITY`, not both).
    #[inline]
    pub fn new(ra: f64, rb: f64) -> Self {
        Self::with_inverses(ra, 1.0 / ra, rb, 1.0 / rb)
    }

    /// [`DiskLens::new`] from radii whose inverses are already known (`ia = 1/ra`, `ib = 1/rb`;
    /// 0 for ∞): a body can keep its own, sparing two divisions per contact.
    #[inline]
    pub fn with_inverses(ra: f64, ia: f64, rb: f64, ib: f64) -> Self {
        DiskLens { ra, rb, ia, ib }
    }

    /// The smaller radius and the larger (∞ for a half-plane).
    pub fn radii(&self) -> (f64, f64) {
        if self.ra <= self.rb {
            (self.ra, self.rb)
        } else {
            (self.rb, self.ra)
        }
    }

    /// The overlap the area law's spring acts on for the overlap area `area`, and its
    /// derivative `dδ_eq/dA = 1/L_eq` (the *compliance* of the map; `L_eq` is the equal-area
    /// disks' chord): the equal-area disks' lens overlap δ(A) (the inverse of
    /// [`DiskLens::at_depth`]) as the explicit series
    ///
    /// `δ = (S₁/8)u² + (S₃/640)u⁴ + ((25S₁S₅ − 14S₃²)/(179200 S₁))u⁶ + D₄u⁸ + D₅u¹⁰`,
    /// `u = (12A/S₁)^{1/3}`, `S_m = r₁^{−m} + r₂^{−m}`
    ///
    /// (the reversion of `A(L) = ½Σ g_k S_{2k−1} L^{2k+1}` composed with the lens's sagittas
    /// `δ(L) = Σ h_k S_{2k−1} L^{2k}`; D₄, D₅ in the code) and its exact derivative
    /// `dδ/dA = (dδ/du)/(dA/du) = 4 (Σ 2k D_k u^{2k−2}) / (S₁ u)`. One division (`1/S₁`, which
    /// does not wait for A) and no root: `1/u = (12A/S₁)^{−1/3}` comes from
    /// [`inv_cbrt`]'s multiplications, `u² = (12A/S₁)·(1/u)`. The series *is* the potential's
    /// definition (`W = ∫F_s dδ_eq`, exactly consistent with its compliance): every `D_k` is
    /// positive for any two radii (`25S₁S₅ ≥ 25S₃²` by Cauchy–Schwarz; D₄, D₅ checked over
    /// every radius ratio), so δ_eq grows smoothly with A everywhere. It equals the lens's
    /// exact inverse to 1e-14 at δ = 0.01 r₁, 1e-9 at 0.05 r₁, 3e-8 at 0.1 r₁, 1e-6 at 0.2 r₁
    /// and 1e-4 at 0.5 r₁ (for a disk on a wall, the least accurate pair). No overlap
    /// (`A ≤ 0`): `(0, 0)` — no spring and no dashpot.
    #[inline(always)]
    pub fn equivalent_depth(&self, area: f64) -> (f64, f64) {
        if area.is_nan() || area <= 0.0 {
            return (0.0, 0.0);
        }
        // Symmetric in the two radii: any order.
        let (i1, i2) = (self.ia, self.ib);
        let (q1, q2) = (i1 * i1, i2 * i2);
        let s1 = i1 + i2;
        let (p1, p2) = (i1 * q1, i2 * q2);
        let s3 = p1 + p2;
        let (p1, p2) = (p1 * q1, p2 * q2);
        let s5 = p1 + p2;
        let (p1, p2) = (p1 * q1, p2 * q2);
        let s7 = p1 + p2;
        let s9 = p1 * q1 + p2 * q2;
        let inv = 1.0 / s1;
        let x = 12.0 * area * inv;
        let y = inv_cbrt(x); // 1/u
        let d = self.series(s1, s3, s5, s7, s9, inv);
        let (delta, slope) = poly(&d, x * y);
        (delta, 4.0 * slope * inv * y)
    }

    /// The coefficients `D₁ … D₅` of δ(u) (see [`DiskLens::equivalent_depth`]); `inv` is `1/S₁`.
    /// With `w = S₃/S₁` and `v = S₅/S₁` (the numerators of D₃…D₅ divided by their `S₁` powers):
    /// `D₃ = (25S₅ − 14S₃w)/179200`, `D₄ = (4375S₇ − 5400S₅w + 1848S₃w²)/258048000`,
    /// `D₅ = (1929375S₉ − 2695000S₇w − 1113750S₅v + 2702700S₅w² − 672672S₃w³)/794787840000`.
    #[inline]
    fn series(&self, s1: f64, s3: f64, s5: f64, s7: f64, s9: f64, inv: f64) -> [f64; 5] {
        let (w, v) = (s3 * inv, s5 * inv);
        let w2 = w * w;
        const K3: f64 = 1.0 / 179_200.0;
        const K4: f64 = 1.0 / 258_048_000.0;
        const K5: f64 = 1.0 / 794_787_840_000.0;
        [
            s1 * (1.0 / 8.0),
            s3 * (1.0 / 640.0),
            (25.0 * K3) * s5 - (14.0 * K3) * (s3 * w),
            ((4375.0 * K4) * s7 - (5400.0 * K4) * (s5 * w)) + (1848.0 * K4) * (s3 * w2),
            (((1_929_375.0 * K5) * s9 - (2_695_000.0 * K5) * (s7 * w))
                - ((1_113_750.0 * K5) * (s5 * v) - (2_702_700.0 * K5) * (s5 * w2)))
                - (672_672.0 * K5) * (s3 * (w2 * w)),
        ]
    }

    /// The disks' effective radius `R* = r1 r2/(r1 + r2)` (T11; `r1` against a half-plane).
    #[inline]
    pub fn effective_radius(&self) -> f64 {
        let (ra, rb) = (self.ra, self.rb);
        if !rb.is_finite() {
            ra
        } else if !ra.is_finite() {
            rb
        } else {
            ra * rb / (ra + rb)
        }
    }

    /// The whole smaller disk: the largest area a lens can have.
    pub fn full_area(&self) -> f64 {
        let r1 = self.radii().0;
        PI * r1 * r1
    }

    /// Area and chord length of the lens at overlap `delta` (`0 ≤ δ ≤ 2 r1`), by the general
    /// formulas (angles from `atan2`); any depth, including those where the smaller disk's
    /// centre lies inside the other.
    pub fn at_depth(&self, delta: f64) -> (f64, f64) {
        let (r1, r2) = self.radii();
        let delta = delta.clamp(0.0, 2.0 * r1);
        // Sagittas of the two caps: h1 = δ(2r2 − δ)/(2d), h2 = δ(2r1 − δ)/(2d) (no
        // cancellation); a half-plane's cap is the whole overlap.
        let h1 = if r2.is_finite() {
            delta * (2.0 * r2 - delta) / (2.0 * (r1 + r2 - delta))
        } else {
            delta
        };
        let half = (h1 * (2.0 * r1 - h1)).max(0.0).sqrt();
        let cap = |r: f64, h: f64| 0.5 * r * r * phi_minus_sin(2.0 * half.atan2(r - h));
        let mut area = cap(r1, h1);
        if r2.is_finite() {
            let h2 = delta * (2.0 * r1 - delta) / (2.0 * (r1 + r2 - delta));
            area += cap(r2, h2);
        }
        (area, 2.0 * half)
    }

    /// Area, its derivative `dA/dL` and the overlap δ at chord `l`, on the branch where both
    /// caps are minor (`0 ≤ L ≤ 2 r1`).
    #[inline]
    fn at_chord(&self, l: f64) -> (f64, f64, f64) {
        let q = 0.25 * l * l;
        let term = |r: f64| {
            // A cap: ½r² · 2·unit_cap(L/r); dA/dL = (L²/4)/√(r² − L²/4); δ = (L²/4)/(r + √…)
            // (no cancellation), with one division for both quotients.
            let root = (r * r - q).max(0.0).sqrt();
            let inv = 1.0 / (root * (r + root));
            (
                r * r * unit_cap(l / r),
                q * (r + root) * inv,
                q * root * inv,
            )
        };
        let (r1, r2) = self.radii();
        let (a1, d1, h1) = term(r1);
        if r2.is_finite() {
            let (a2, d2, h2) = term(r2);
            (a1 + a2, d1 + d2, h1 + h2)
        } else {
            (a1, d1, h1)
        }
    }

    /// The overlap δ whose lens has area `area`, and the lens's chord: the inverse of
    /// [`DiskLens::at_depth`] (δ grows with A). Saturates at `(2 r1, 0)` for `area ≥ π r1²`.
    ///
    /// While both caps are minor and the chord short of the smaller disk's diameter (the usual
    /// case), Newton's method on the chord L, started from the series reversion of `A(L) = (S₁/12)L³ + (S₃/160)L⁵ + (3S₅/3584)L⁷ + …`
    /// (`S_m = r1^{−m} + r2^{−m}`), which is accurate to O(L⁸) so that one or two steps reach
    /// rounding; beyond, safeguarded Newton on δ with [`DiskLens::at_depth`].
    pub fn depth_for_area(&self, area: f64) -> (f64, f64) {
        let (r1, r2) = self.radii();
        if area.is_nan() || area <= 0.0 {
            return (0.0, 0.0);
        }
        if area >= self.full_area() {
            return (2.0 * r1, 0.0);
        }
        // The chord branch up to L = 1.9 r1, short of the smaller cap's half disk (where
        // dA/dL is infinite and δ(L) ill-conditioned); the depth branch beyond.
        let l_max = 1.9 * r1;
        let (i1, i2) = (1.0 / r1, if r2.is_finite() { 1.0 / r2 } else { 0.0 });
        let (q1, q2) = (i1 * i1, i2 * i2);
        let (s1, s3) = (i1 + i2, i1 * q1 + i2 * q2);
        let (s5, s7) = (
            i1 * q1 * q1 + i2 * q2 * q2,
            i1 * q1 * q1 * q1 + i2 * q2 * q2 * q2,
        );
        // (The start only has to be close: constants as products, one division.)
        let inv_s1 = 1.0 / s1;
        let x = 12.0 * area * inv_s1;
        let u = x * inv_cbrt(x).powi(2);
        let u2 = u * u;
        let c1 = -s3 * inv_s1 * (1.0 / 40.0);
        let c2 = -(75.0 * s1 * s5 - 56.0 * s3 * s3) * (inv_s1 * inv_s1) * (1.0 / 22400.0);
        let c3 = -(875.0 * s1 * s1 * s7 - 1350.0 * s1 * s3 * s5 + 546.0 * s3 * s3 * s3)
            * (inv_s1 * inv_s1 * inv_s1)
            * (1.0 / 1_612_800.0);
        let start = u * (1.0 + u2 * (c1 + u2 * (c2 + u2 * c3)));
        // The start is accurate to O(L⁸): one Newton step usually reaches rounding (A ∝ L³ to
        // leading order, so a relative error e becomes e² — below rounding from e ≤ 1e-8),
        // rarely two. The δ of the last step then follows to second order from the same
        // evaluation (dδ/dL = (dA/dL)/L, as dA/dδ = L).
        if start < 0.9 * l_max {
            let mut l = start;
            for _ in 0..3 {
                let (a, da, delta) = self.at_chord(l);
                let step = (area - a) / da;
                if step.abs() <= 1e-8 * l {
                    return (delta + step * da / l, l + step);
                }
                l += step;
                if !(l > 0.0 && l < l_max) {
                    break;
                }
            }
        }
        let (a_switch, _, _) = self.at_chord(l_max);
        if area < a_switch {
            let l = newton_in_bracket(area, start, l_max, |l| {
                let (a, da, _) = self.at_chord(l);
                (a, da)
            });
            let (_, _, delta) = self.at_chord(l);
            return (delta, l);
        }
        // Deeper than a half disk: Newton on δ (dA/dδ = L), kept in its bracket.
        let delta = newton_in_bracket(area, r1, 2.0 * r1, |d| self.at_depth(d));
        (delta, self.at_depth(delta).1)
    }
}

/// `Σ d_k u^{2k}` (k = 1…5) and its u-derivative over u, `Σ 2k d_k u^{2k−2}`, at `u2 = u²`.
/// Estrin's scheme (pairs of terms, then pairs of pairs): the force waits on four roundings'
/// depth of this rather than Horner's ten.
#[inline]
fn poly(d: &[f64; 5], u2: f64) -> (f64, f64) {
    let u4 = u2 * u2;
    let value = u2 * ((d[0] + u2 * d[1]) + u4 * ((d[2] + u2 * d[3]) + u4 * d[4]));
    let slope = (2.0 * d[0] + u2 * (4.0 * d[1]))
        + u4 * ((6.0 * d[2] + u2 * (8.0 * d[3])) + u4 * (10.0 * d[4]));
    (value, slope)
}

/// `x^{−1/3}` for a positive `x`, to about an ulp (the tests: within 4.5e-16 of libm's
/// `1/cbrt` over the whole normal range, 2.3e-16 of `1/k` at `k³`), with multiplications only,
/// in one step: a first guess `y` from the bits — the exponent divided by minus three, the
/// mantissa's leading bits along, 3.4 % off at worst, so that `r = 1 − x y³` is at most 0.106 —
/// then `x^{−1/3} = y (1 − r)^{−1/3} = y (1 + Σ_{k≥1} c_k r^k)`, `c_k = c_{k−1}(k − ⅔)/k`
/// (1/3, 2/9, 14/81, …), summed to k = 16 (the first term left out is below 2e-18 of the
/// sum) by Estrin's scheme. The area law's force waits on this root: one step's chain of
/// roughly twelve roundings rather than two steps of Horner's (the two-step form it replaces,
/// a cubic in r per step, took about 80 cycles of latency; this one about 50). No division:
/// the area law's compliance needs `1/u`, and `u² = x·x^{−1/3}`. Zero, subnormal, infinite and
/// NaN arguments take `1/cbrt`.
#[inline]
pub(crate) fn inv_cbrt(x: f64) -> f64 {
    if !x.is_normal() || x < 0.0 {
        return 1.0 / x.cbrt();
    }
    // x = 2^e (1 + f) has bits ≈ 2^52 (e + 1023 + f), so (4/3)·1023·2^52 − bits/3 approximates
    // the bits of x^{−1/3}; the constant is that, lowered by the shift that minimises the worst
    // error of the linear log over a period of three octaves.
    let y = f64::from_bits(0x553E_F000_0000_0000 - x.to_bits() / 3);
    let r = 1.0 - x * (y * y * y);
    let c = &INV_CBRT_SERIES;
    let (r2, e) = (r * r, |k: usize| c[k] + c[k + 1] * r);
    let r4 = r2 * r2;
    let f = |k: usize| e(k) + e(k + 2) * r2;
    let p = (f(0) + f(4) * r4) + (f(8) + f(12) * r4) * (r4 * r4);
    y + (y * r) * p
}

/// `c_1 … c_16` of `(1 − r)^{−1/3} = 1 + Σ c_k r^k` ([`inv_cbrt`]): `c_k = c_{k−1}(k − ⅔)/k`,
/// exact rationals rounded once.
const INV_CBRT_SERIES: [f64; 16] = [
    0.3333333333333333,
    0.2222222222222222,
    0.1728395061728395,
    0.1440329218106996,
    0.12482853223593965,
    0.11095869532083524,
    0.10039120052837473,
    0.09202526715101018,
    0.08520858069537979,
    0.07952800864902114,
    0.07470812933695925,
    0.07055767770712819,
    0.06693933526060879,
    0.06375174786724647,
    0.060918336850924404,
    0.05838007281546922,
];

/// The root in `[0, hi]` of `f(x) = target` for an increasing `f` (given as `x ↦ (f, f′)`), by
/// Newton's method from `start`, falling back to bisection whenever a step would leave the
/// bracket (or `f′` is infinite at the bracket's end).
fn newton_in_bracket(target: f64, start: f64, hi: f64, f: impl Fn(f64) -> (f64, f64)) -> f64 {
    let (mut lo, mut hi) = (0.0, hi);
    let mut x = if start > 0.0 && start < hi {
        start
    } else {
        0.5 * hi
    };
    for _ in 0..200 {
        let (v, dv) = f(x);
        if (v - target).abs() <= 2.0 * f64::EPSILON * target {
            break;
        }
        if v > target {
            hi = x;
        } else {
            lo = x;
        }
        let newton = x - (v - target) / dv;
        let bisect = !(newton > lo && newton < hi);
        let next = if bisect { 0.5 * (lo + hi) } else { newton };
        let step = (next - x).abs();
        x = next;
        // After a Newton step this small the error is below rounding (quadratic convergence,
        // with f″/f′ up to ~1e4 on the branches used).
        if (!bisect && step <= 1e-10 * x) || hi - lo <= 4.0 * f64::EPSILON * hi {
            break;
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    // Reference values from mpmath at 50 digits (the closed forms, not these series).
    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn series_match_high_precision_values() {
        for (l, want) in [
            (1e-3, 8.333333958333417e-11),
            (0.3, 0.0022653732770471125),
            (0.49, 0.00998653826898492),
            (0.5, 0.010618796004115099),
            (1.3, 0.21362720173430902),
            (1.99, 1.3713790660150516),
        ] {
            assert!(rel(unit_cap(l), want) < 4e-16, "unit_cap({l})");
            // From ℓ² (rounded: up to 1.7e-16 more of the cap, which goes as (ℓ²)^{3/2}).
            assert!(
                rel(unit_cap_of_square(l * l), want) < 6e-16,
                "unit_cap_of_square({l}²)"
            );
        }
        // Two caps at once, lane by lane: the same bits as two scalar calls, across the switch
        // between the series' two forms (ℓ = ⅛) and up to and beyond its reach (ℓ = ½).
        for k in 0..=300 {
            let (l, m) = (0.003 * f64::from(k), 0.9 - 0.003 * f64::from(k));
            let (x, y) = (l * l, m * m);
            let (ab, cd) = (0.7, 1.3);
            let want = ab * unit_cap_of_square(x) + cd * unit_cap_of_square(y);
            assert_eq!(
                minor_caps_sum([ab, cd], [x, y]).to_bits(),
                want.to_bits(),
                "ℓ = {l}, {m}"
            );
        }
        for (p, want) in [
            (1e-4, 1.6666666658333332e-13),
            (0.7, 0.055782312762308946),
            (0.99, 0.1539740213994795),
            (2.5, 1.9015278558960436),
        ] {
            assert!(rel(phi_minus_sin(p), want) < 4e-16, "φ − sin φ at {p}");
        }
    }

    #[test]
    fn lens_and_its_inverse_match_high_precision_values() {
        for (r1, r2, delta, a, l) in [
            (1.0, 2.0, 1e-6, 1.539600602368934e-09, 0.0023094007880833183),
            (1.0, 2.0, 0.3, 0.2470567369412955, 1.2146736593692282),
            (0.8, 1.2, 1e-2, 0.0013052502515054788, 0.19567299123022167),
            (1.0, 1.0, 1.5, 2.152109225029709, 1.9364916731037085),
            (1.0, 3.0, 1.9, 3.070880547033377, 1.0380406276592462),
            (
                1.0,
                f64::INFINITY,
                1e-8,
                1.8856180803356998e-12,
                0.0002828427117675122,
            ),
            (
                1.5,
                f64::INFINITY,
                0.2,
                0.20237742850238463,
                1.4966629547095767,
            ),
            (1.0, f64::INFINITY, 1.7, 2.846093813403649, 1.42828568570857),
        ] {
            let lens = DiskLens::new(r1, r2);
            let (ga, gl) = lens.at_depth(delta);
            assert!(rel(ga, a) < 1e-14, "area at δ = {delta}: {ga} vs {a}");
            assert!(rel(gl, l) < 1e-14, "chord at δ = {delta}");
            let (gd, gl2) = lens.depth_for_area(a);
            assert!(rel(gd, delta) < 1e-14, "δ for A = {a}: {gd} vs {delta}");
            assert!(rel(gl2, l) < 1e-12, "chord for A = {a}: {gl2} vs {l}");
        }
    }

    #[test]
    fn the_inverse_round_trips_over_every_area() {
        // The lens's area at the returned depth is the asked area, from a speck to the whole
        // smaller disk, for equal, unequal and half-plane pairs.
        for (r1, r2) in [(1.0, 1.0), (0.7, 1.05), (0.3, 2.0), (1.0, f64::INFINITY)] {
            let lens = DiskLens::new(r1, r2);
            let full = lens.full_area();
            for k in 1..400 {
                let area = full * (k as f64 / 400.0).powi(3);
                let (delta, _) = lens.depth_for_area(area);
                let (back, chord) = lens.at_depth(delta);
                // Near full overlap dA/dδ = L vanishes: δ's own rounding (ε r1) moves A by L ε r1.
                let tol = 1e-13 * area + 8.0 * f64::EPSILON * r1 * chord;
                assert!(
                    (back - area).abs() <= tol,
                    "r = ({r1}, {r2}), A = {area}: {back}"
                );
            }
        }
    }

    #[test]
    fn the_equivalent_depth_is_the_lens_inverse_and_its_own_derivative() {
        for (r1, r2) in [(1.0, 1.0), (0.8, 1.2), (0.3, 2.0), (1.0, f64::INFINITY)] {
            let lens = DiskLens::new(r1, r2);
            let mut worst = [0.0f64; 3];
            for k in 0..200 {
                let delta = r1 * 10f64.powf(-6.0 + 5.7 * k as f64 / 199.0); // 1e-6 … 0.5 r1
                let (area, _) = lens.at_depth(delta);
                let (d, compliance) = lens.equivalent_depth(area);
                // Against the exact inverse (the mpmath-checked at_depth): the series' error.
                let bin = if delta <= 0.01 * r1 {
                    0
                } else if delta <= 0.1 * r1 {
                    1
                } else {
                    2
                };
                worst[bin] = worst[bin].max(rel(d, delta));
                // The compliance is dδ_eq/dA of this very map (central difference in A).
                let h = 1e-4 * area;
                let (dp, _) = lens.equivalent_depth(area + h);
                let (dm, _) = lens.equivalent_depth(area - h);
                let fd = (dp - dm) / (2.0 * h);
                assert!(
                    rel(compliance, fd) < 1e-6,
                    "r = ({r1}, {r2}), δ = {delta}: dδ/dA {compliance} vs {fd}"
                );
            }
            // The series' truncation: below 1e-12 up to 0.01 r1, 1e-6 up to 0.1 r1 (3e-8 at a
            // wall), 1e-3 up to 0.5 r1.
            assert!(
                worst[0] < 1e-12 && worst[1] < 1e-6 && worst[2] < 1e-3,
                "{r1} {r2}: {worst:?}"
            );
        }
    }

    #[test]
    fn the_inverse_cube_root_is_good_to_two_ulps() {
        // Against libm's cube root (itself within an ulp) over the whole normal range, both
        // ends included, and exactly on perfect cubes (where 1/k is the one rounding).
        let mut x = f64::MIN_POSITIVE;
        while x < 1e308 {
            let y = inv_cbrt(x);
            assert!(rel(y, 1.0 / x.cbrt()) < 4.5e-16, "cbrt({x})⁻¹ = {y}");
            x *= 1.37;
        }
        for k in 1..2000u32 {
            let k = f64::from(k);
            assert!(rel(inv_cbrt(k * k * k), 1.0 / k) <= 2.3e-16, "{k}³");
        }
        assert_eq!(inv_cbrt(0.0), f64::INFINITY);
        assert!(inv_cbrt(5e-324) > 0.0 && inv_cbrt(f64::INFINITY) == 0.0);
    }

    #[test]
    fn caps_of_a_circle_and_a_square() {
        // A chord through the centre halves the disk; a quarter of a square on the diagonal.
        let r = 2.0;
        let half = ellipse_cap(r, r, [-r, 0.0], [2.0 * r, 0.0], false);
        assert!(rel(half, 0.5 * PI * r * r) < 1e-15);
        let sq = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        assert!(rel(polygon_cap(&sq, [0.0, 0.0], [1.0, 1.0]), 2.0) < 1e-15);
        assert!(rel(polygon_cap(&sq, [0.0, 0.5], [0.0, 1.0]), 1.0) < 1e-15);
    }
}

//! Rigid clumps of disks: the member list of a [`Shape::Clump`](super::Shape::Clump), checked
//! once, shifted to the union's centroid, with the union's area and polar moment computed once.
//!
//! # Sharing
//! As for [`Polygon`](super::Polygon): a [`Clump`] is a reference into a process-wide table
//! holding each distinct member list (as given, bit for bit) once, so that `Shape` stays `Copy`.
//!
//! # The body frame
//! The member centres as given may be anywhere: they are **shifted by minus the centroid of the
//! union of the disks** at load ([`ClumpData::shift`] keeps what was subtracted), so a body's
//! `position` is the union's centroid (its pose is its centroid, as for every body) and the
//! member centres are stored relative to it.
//!
//! # Mass and inertia of the union (exact)
//! Overlapping members count once. The union's area `A`, first moments and polar second moment
//! `J = ∫∫(x² + y²) dA` are computed **exactly** (closed forms, no quadrature) by Green's
//! theorem over the union's boundary, which is made of arcs of the member circles: for each
//! member, the arcs not covered by any other member (interval arithmetic on angles: member `m`
//! covers the arc `φ ± α` of member `k`, `φ` the direction from `c_k` to `c_m`,
//! `cos α = (r_k² + d² − r_m²)/(2 r_k d)`). Along an arc `x = c + r(cos t, sin t)`:
//! - `A = ½∮(x dy − y dx)`,
//! - `∫∫x dA = ½∮x² dy`, `∫∫y dA = −½∮y² dx`,
//! - `J_o = ⅓∮(x³ dy − y³ dx)`,
//!
//! each a trigonometric polynomial in `t` integrated in closed form (see [`arc_moments`]). Then
//! `I/m = J_o/A − |c̄|²` about the centroid `c̄`. A member inside another contributes no arc;
//! two identical members: the first given covers the later ones.

use super::pose::Vec2;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::fmt;
use std::sync::{Mutex, OnceLock};

/// The largest number of members (a slot packs a member index per side in 16 bits).
pub const MAX_MEMBERS: usize = 1 << 15;

/// A clump's data (body frame: union centroid at the origin).
#[derive(Debug, PartialEq)]
pub struct ClumpData {
    /// Member centres relative to the union's centroid.
    pub centres: Box<[Vec2]>,
    /// Member radii.
    pub radii: Box<[f64]>,
    /// The union's centroid in the frame of the centres as given (subtracted from them).
    pub shift: Vec2,
    /// The union's area.
    pub area: f64,
    /// The union's polar moment about its centroid divided by its area, `J/A`.
    pub inertia_per_mass: f64,
    /// Largest `|c_k| + r_k`.
    pub bounding_radius: f64,
    /// The smallest member radius (the size scale of a member contact).
    pub smallest_radius: f64,
    /// Semi-axes `(a, b)`, `a ≥ b`, of the ellipse with the union's second moments of area,
    /// and the long axis' angle (body frame) — for outputs that describe a body by an ellipse.
    pub moment_ellipse: [f64; 2],
    pub long_axis: f64,
}

/// A clump shape: a shared reference into the process-wide table (see the module docs). Two
/// `Clump`s are equal exactly when their member lists as given are.
#[derive(Clone, Copy)]
pub struct Clump(&'static ClumpData);

impl PartialEq for Clump {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self.0, other.0)
    }
}

impl fmt::Debug for Clump {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list()
            .entries(
                self.0
                    .centres
                    .iter()
                    .zip(self.0.radii.iter())
                    .map(|(c, r)| [c.x, c.y, *r]),
            )
            .finish()
    }
}

impl std::ops::Deref for Clump {
    type Target = ClumpData;
    fn deref(&self) -> &ClumpData {
        self.0
    }
}

/// Why a member list is not a usable clump (`disk` indices as given).
#[derive(Clone, Debug, PartialEq)]
pub enum ClumpError {
    /// No disks.
    Empty,
    /// More than [`MAX_MEMBERS`] disks.
    TooMany(usize),
    /// Disk `k`'s centre is not finite.
    NonFiniteCentre(usize),
    /// Disk `k`'s radius is not positive and finite.
    BadRadius(usize, f64),
}

impl fmt::Display for ClumpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ClumpError::Empty => write!(f, "a clump needs at least one disk, got none"),
            ClumpError::TooMany(n) => {
                write!(f, "a clump has at most {MAX_MEMBERS} disks, got {n}")
            }
            ClumpError::NonFiniteCentre(k) => write!(f, "disk {k}'s centre is not finite"),
            ClumpError::BadRadius(k, r) => {
                write!(f, "disk {k}'s `r` must be positive and finite, got {r}")
            }
        }
    }
}

impl std::error::Error for ClumpError {}

type Table = Mutex<HashMap<Vec<[u64; 3]>, &'static ClumpData>>;

fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| Mutex::new(HashMap::new()))
}

impl Clump {
    /// The clump of these disks `(centre, r)` (in any frame: shifted to the union's centroid),
    /// from the shape table; checked, see [`ClumpError`].
    pub fn new(disks: &[([f64; 2], f64)]) -> Result<Clump, ClumpError> {
        let key: Vec<[u64; 3]> = disks
            .iter()
            .map(|(c, r)| [c[0].to_bits(), c[1].to_bits(), r.to_bits()])
            .collect();
        if let Some(&d) = table().lock().expect("clump table").get(&key) {
            return Ok(Clump(d));
        }
        let data = ClumpData::new(disks)?;
        let mut t = table().lock().expect("clump table");
        let d: &'static ClumpData = t.entry(key).or_insert_with(|| Box::leak(Box::new(data)));
        Ok(Clump(d))
    }

    /// The data's address.
    pub fn data(&self) -> &'static ClumpData {
        self.0
    }

    /// Number of member disks.
    #[inline]
    pub fn len(&self) -> usize {
        self.0.radii.len()
    }

    /// Never true (a clump has at least one disk).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.0.radii.is_empty()
    }

    /// Member `k`: body-frame centre and radius.
    #[inline]
    pub fn member(&self, k: usize) -> (Vec2, f64) {
        (self.0.centres[k], self.0.radii[k])
    }

    /// Support `max over members of u·c_k + r_k|u|` (u in the body frame, any length). Not
    /// inlined: it must not weigh on the inlining of the support function's other arms.
    #[inline(never)]
    pub fn support(&self, u: Vec2) -> f64 {
        let n = u.norm();
        self.0
            .centres
            .iter()
            .zip(self.0.radii.iter())
            .map(|(c, r)| u.dot(c) + r * n)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// `k` disks fitted to the ellipse with semi-axes `a ≥ b` (along x, y) by an equal-area
    /// construction (not Ferellec & McDowell's): centres equally spaced on the major axis
    /// between the centres of curvature of its ends, `x_m = (a − b²/a)(2m/(k−1) − 1)` (one disk
    /// at the centre for `k = 1`); each radius that of the largest disk about `(x_m, 0)` inside
    /// the ellipse, `ρ(x) = b√(1 − x²/(a² − b²))` (the end disks are the osculating circles at
    /// the ends, `ρ = b²/a`); then every centre and radius scaled by one factor `s` about the
    /// centre so that the union's exact area is `πab` (`s = √(πab/A₁)`, the union's area growing
    /// as `s²`). Returns the member list `(centre, r)`.
    pub fn ellipse_fit(k: usize, a: f64, b: f64) -> Vec<([f64; 2], f64)> {
        assert!(k >= 1 && a >= b && b > 0.0);
        let end = b * b / a; // radius of curvature at the ends of the major axis
        let inscribed = |x: f64| -> f64 {
            // Largest disk about (x, 0) inside the ellipse: for |x| ≤ a − b²/a it touches
            // the ellipse at two symmetric points, r² = b²(1 − x²/(a² − b²)).
            let c2 = a * a - b * b;
            if c2 <= 0.0 {
                return b - x.abs();
            }
            let r2 = b * b * (1.0 - x * x / c2);
            r2.max(0.0).sqrt()
        };
        let base: Vec<([f64; 2], f64)> = if k == 1 {
            vec![([0.0, 0.0], b)]
        } else {
            let span = a - end;
            (0..k)
                .map(|m| {
                    let x = span * (2.0 * m as f64 / (k - 1) as f64 - 1.0);
                    ([x, 0.0], inscribed(x).max(end))
                })
                .collect()
        };
        let scaled = |s: f64| -> Vec<([f64; 2], f64)> {
            base.iter()
                .map(|(c, r)| ([c[0] * s, c[1] * s], r * s))
                .collect()
        };
        // The union of the scaled disks is the scaled union: its area is s² A(1).
        let s = (PI * a * b / union_moments(&base).0).sqrt();
        scaled(s)
    }
}

impl ClumpData {
    fn new(disks: &[([f64; 2], f64)]) -> Result<ClumpData, ClumpError> {
        if disks.is_empty() {
            return Err(ClumpError::Empty);
        }
        if disks.len() > MAX_MEMBERS {
            return Err(ClumpError::TooMany(disks.len()));
        }
        for (k, (c, r)) in disks.iter().enumerate() {
            if !(c[0].is_finite() && c[1].is_finite()) {
                return Err(ClumpError::NonFiniteCentre(k));
            }
            if !(r.is_finite() && *r > 0.0) {
                return Err(ClumpError::BadRadius(k, *r));
            }
        }
        // Moments about the first centre (small numbers for a clump far from the origin),
        // then about the centroid.
        let o = disks[0].0;
        let local: Vec<([f64; 2], f64)> = disks
            .iter()
            .map(|(c, r)| ([c[0] - o[0], c[1] - o[1]], *r))
            .collect();
        let (area, sx, sy, sxx, syy, sxy) = union_moments(&local);
        let cbar = Vec2::new(sx / area, sy / area);
        let shift = Vec2::new(o[0], o[1]) + cbar;
        let centres: Box<[Vec2]> = local
            .iter()
            .map(|(c, _)| Vec2::new(c[0], c[1]) - cbar)
            .collect();
        let radii: Box<[f64]> = disks.iter().map(|d| d.1).collect();
        let (ixx, iyy, ixy) = (
            sxx - area * cbar.x * cbar.x,
            syy - area * cbar.y * cbar.y,
            sxy - area * cbar.x * cbar.y,
        );
        let spread = (0.5 * (ixx - iyy)).hypot(ixy);
        let mean = 0.5 * (ixx + iyy);
        let bounding_radius = centres
            .iter()
            .zip(radii.iter())
            .map(|(c, r)| c.norm() + r)
            .fold(0.0, f64::max);
        Ok(ClumpData {
            shift,
            area,
            inertia_per_mass: (ixx + iyy) / area,
            bounding_radius,
            smallest_radius: radii.iter().copied().fold(f64::INFINITY, f64::min),
            moment_ellipse: [
                (4.0 * (mean + spread) / area).sqrt(),
                (4.0 * (mean - spread).max(0.0) / area).sqrt(),
            ],
            long_axis: 0.5 * (2.0 * ixy).atan2(ixx - iyy),
            centres,
            radii,
        })
    }
}

/// The union of disks `(centre, r)`: `(A, ∫∫x, ∫∫y, ∫∫x², ∫∫y², ∫∫xy)` about the frame's
/// origin, exactly (Green's theorem over the uncovered arcs: see the module documentation).
pub fn union_moments(disks: &[([f64; 2], f64)]) -> (f64, f64, f64, f64, f64, f64) {
    let mut m = [0.0f64; 6];
    for (k, t0, t1) in exposed_arcs(disks) {
        add(&mut m, arc_moments(disks[k].0, disks[k].1, t0, t1));
    }
    (m[0], m[1], m[2], m[3], m[4], m[5])
}

/// The arcs of the union's boundary: `(member, t0, t1)`, the arc `c + r(cos t, sin t)` for
/// `t ∈ [t0, t1] ⊂ [0, 2π]` covered by no other member, counter-clockwise about its member.
pub fn exposed_arcs(disks: &[([f64; 2], f64)]) -> Vec<(usize, f64, f64)> {
    let mut out = Vec::new();
    let mut covered: Vec<(f64, f64)> = Vec::new();
    'disks: for (k, &(ck, rk)) in disks.iter().enumerate() {
        covered.clear();
        for (l, &(cl, rl)) in disks.iter().enumerate() {
            if l == k {
                continue;
            }
            let (dx, dy) = (cl[0] - ck[0], cl[1] - ck[1]);
            let d = dx.hypot(dy);
            if d == 0.0 && rl == rk {
                if l < k {
                    continue 'disks; // identical: the first covers the later
                }
                continue;
            }
            if d + rk <= rl {
                continue 'disks; // k inside l
            }
            if d >= rk + rl || d + rl <= rk {
                continue; // apart, or l inside k
            }
            let cos_a = ((rk * rk + d * d - rl * rl) / (2.0 * rk * d)).clamp(-1.0, 1.0);
            let alpha = cos_a.acos();
            let phi = dy.atan2(dx);
            // The start in [0, 2π); an interval that wraps is split in two.
            let mut s = (phi - alpha).rem_euclid(2.0 * PI);
            if s >= 2.0 * PI {
                s = 0.0;
            }
            let e = s + 2.0 * alpha;
            if e > 2.0 * PI {
                covered.push((s, 2.0 * PI));
                covered.push((0.0, e - 2.0 * PI));
            } else {
                covered.push((s, e));
            }
        }
        covered.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut t = 0.0;
        for &(s, e) in &covered {
            if s > t {
                out.push((k, t, s));
            }
            t = t.max(e);
        }
        if t < 2.0 * PI {
            out.push((k, t, 2.0 * PI));
        }
    }
    out
}

impl Clump {
    /// The union's boundary as closed loops of body-frame points (for drawing): the exposed
    /// arcs, each sampled at most every `max_turn` radians, chained end to start (an arc that
    /// ends where another starts continues the loop; a loop closes when it comes back). One
    /// loop for a connected union without holes; a member apart from the rest, or a hole, gives
    /// another.
    pub fn boundary_loops(&self, max_turn: f64) -> Vec<Vec<Vec2>> {
        let disks: Vec<([f64; 2], f64)> = self
            .centres
            .iter()
            .zip(self.radii.iter())
            .map(|(c, r)| ([c.x, c.y], *r))
            .collect();
        let arcs = exposed_arcs(&disks);
        let at = |k: usize, t: f64| {
            let (c, r) = (self.centres[k], self.radii[k]);
            c + Vec2::new(r * t.cos(), r * t.sin())
        };
        // An arc that wraps through t = 0 on a member comes as two pieces: join them.
        let pieces = arcs;
        let mut joined: Vec<(usize, f64, f64)> = Vec::new();
        for (idx, &(k, t0, t1)) in pieces.iter().enumerate() {
            if t0 == 0.0 && t1 < 2.0 * PI {
                if let Some(&(_, y, _)) = pieces
                    .iter()
                    .skip(idx + 1)
                    .find(|p| p.0 == k && p.2 == 2.0 * PI && p.1 > 0.0)
                {
                    joined.push((k, y, 2.0 * PI + t1));
                    continue;
                }
            } else if t1 == 2.0 * PI
                && t0 > 0.0
                && pieces
                    .iter()
                    .any(|p| p.0 == k && p.1 == 0.0 && p.2 < 2.0 * PI)
            {
                continue;
            }
            joined.push((k, t0, t1));
        }
        let mut used = vec![false; joined.len()];
        let mut loops = Vec::new();
        while let Some(first) = used.iter().position(|u| !u) {
            let mut pts = Vec::new();
            let mut cur = first;
            loop {
                used[cur] = true;
                let (k, t0, t1) = joined[cur];
                let steps = (((t1 - t0) / max_turn).ceil() as usize).max(1);
                for s in 0..steps {
                    pts.push(at(k, t0 + (t1 - t0) * s as f64 / steps as f64));
                }
                let end = at(k, t1);
                // The unused arc starting nearest this one's end.
                let next = (0..joined.len())
                    .filter(|&m| !used[m])
                    .map(|m| (m, (at(joined[m].0, joined[m].1) - end).norm()))
                    .min_by(|a, b| a.1.total_cmp(&b.1));
                let back = (at(joined[first].0, joined[first].1) - end).norm();
                match next {
                    Some((m, d)) if d < back => cur = m,
                    _ => break,
                }
            }
            loops.push(pts);
        }
        loops
    }
}

fn add(m: &mut [f64; 6], a: [f64; 6]) {
    for (x, y) in m.iter_mut().zip(a) {
        *x += y;
    }
}

/// The contributions of the arc `t ∈ [t0, t1]` of the circle `c + r(cos t, sin t)`, traversed
/// counter-clockwise, to `(A, ∫∫x, ∫∫y, ∫∫x², ∫∫y², ∫∫xy)` by Green's theorem:
/// `A = ½∮(x dy − y dx)`, `∫∫x = ½∮x² dy`, `∫∫y = −½∮y² dx`, `∫∫x² = ⅓∮x³ dy`,
/// `∫∫y² = −⅓∮y³ dx`, `∫∫xy = ½∮x² y dy` — each expanded in powers of `cos t`, `sin t` and
/// integrated with the antiderivatives of `cⁿ sᵐ` below.
fn arc_moments(c: [f64; 2], r: f64, t0: f64, t1: f64) -> [f64; 6] {
    let (cx, cy) = (c[0], c[1]);
    // Antiderivatives F(t) of the monomials needed.
    let prim = |t: f64| -> [f64; 12] {
        let (s, co) = t.sin_cos();
        let s2 = (2.0 * t).sin();
        let s4 = (4.0 * t).sin();
        [
            s,                                 // 0: ∫c
            -co,                               // 1: ∫s
            0.5 * t + 0.25 * s2,               // 2: ∫c²
            0.5 * t - 0.25 * s2,               // 3: ∫s²
            s - s * s * s / 3.0,               // 4: ∫c³
            -co + co * co * co / 3.0,          // 5: ∫s³
            0.375 * t + 0.25 * s2 + s4 / 32.0, // 6: ∫c⁴
            0.375 * t - 0.25 * s2 + s4 / 32.0, // 7: ∫s⁴
            t,                                 // 8: ∫1
            0.5 * s * s,                       // 9: ∫cs
            -co * co * co / 3.0,               // 10: ∫c² s
            -co.powi(4) / 4.0,                 // 11: ∫c³ s
        ]
    };
    // A whole circle takes the exact integrals over a period (no rounding of sin 2π etc.):
    // a lone member's centroid is exactly its centre, and disjoint members sum exactly.
    const FULL: [f64; 12] = [
        0.0,
        0.0,
        PI,
        PI,
        0.0,
        0.0,
        0.75 * PI,
        0.75 * PI,
        2.0 * PI,
        0.0,
        0.0,
        0.0,
    ];
    let (p0, p1) = (prim(t0), prim(t1));
    let whole = t0 == 0.0 && t1 == 2.0 * PI;
    let i = |k: usize| if whole { FULL[k] } else { p1[k] - p0[k] };
    // A = ½ r ∫ (cx c + cy s + r) dt
    let area = 0.5 * r * (cx * i(0) + cy * i(1) + r * i(8));
    // ∫∫x = ½ r ∫ (cx + r c)² c dt
    let mx = 0.5 * r * (cx * cx * i(0) + 2.0 * cx * r * i(2) + r * r * i(4));
    // ∫∫y = ½ r ∫ (cy + r s)² s dt
    let my = 0.5 * r * (cy * cy * i(1) + 2.0 * cy * r * i(3) + r * r * i(5));
    // ∫∫x² = ⅓ r ∫ (cx + r c)³ c dt
    let mxx = r / 3.0
        * (cx.powi(3) * i(0)
            + 3.0 * cx * cx * r * i(2)
            + 3.0 * cx * r * r * i(4)
            + r.powi(3) * i(6));
    // ∫∫y² = ⅓ r ∫ (cy + r s)³ s dt
    let myy = r / 3.0
        * (cy.powi(3) * i(1)
            + 3.0 * cy * cy * r * i(3)
            + 3.0 * cy * r * r * i(5)
            + r.powi(3) * i(7));
    // ∫∫xy = ½ r ∫ (cx + r c)² (cy + r s) c dt
    //      = ½ r ∫ (cx² cy c + cx² r cs + 2cx r cy c² + 2cx r² c²s + r² cy c³ + r³ c³s) dt
    let mxy = 0.5
        * r
        * (cx * cx * cy * i(0)
            + cx * cx * r * i(9)
            + 2.0 * cx * r * cy * i(2)
            + 2.0 * cx * r * r * i(10)
            + r * r * cy * i(4)
            + r.powi(3) * i(11));
    [area, mx, my, mxx, myy, mxy]
}

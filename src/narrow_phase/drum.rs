//! Drum–body contact: a convex body touching the inside of a circle (centre `c`, radius `R`).
//!
//! The body's point farthest from `c`, at distance `ρ = max_{x ∈ body} |x − c|`, is the one
//! that reaches the circle; the depth is `δ = ρ − R` (positive when penetrating) and the normal,
//! from the drum (i) to the body (j), is `n = (c − x_far)/|c − x_far|`, towards the centre. The
//! contact point is where that line crosses the drum's circle, `c + R u` with `u = −n` (the
//! point of the drum's circle nearest the body's deepest point; for a disk the chord midpoint to
//! O(δ²/R)): a force along `n` there acts on the line through the deepest point and `c`, so a
//! spring on δ is the gradient of its energy (envelope theorem, `∂ρ/∂x = u` and
//! `∂ρ/∂θ = u × (x_far − x_body)`: conservative for disks and ellipses).
//!
//! - a **disk** of centre p and radius r: `ρ = |p − c| + r` (closed form);
//! - an **ellipse**: the farthest point of an ellipse from a point. With `x(t) = (a cos t,
//!   b sin t)` in the ellipse's frame and `q` the drum's centre there, `f(t) = |x(t) − q|²` has
//!   `f′/2 = g(t) = (b² − a²) sin t cos t + a q_x sin t − b q_y cos t`, whose zeros are the
//!   Lagrange conditions (a quartic in `tan(t/2)`: up to four critical points). Sixteen
//!   samples of f pick the discrete maxima, and each of the two best is refined by Newton on g
//!   safeguarded by bisection on a bracket where g goes from + to − (resampled when the
//!   samples' bracket is not one): robust, and exact to rounding;
//! - a **polygon** (a rectangle as its corners): ρ at the farthest vertex; as the half-plane
//!   wall does for polygons, the contact point is the midpoint of the chord between the outermost
//!   crossings of the drum's circle with the polygon's edges (a flat face resting on the drum
//!   then pushes at its middle, and a square lies on its face rather than a corner), the normal
//!   from that midpoint towards `c` (perpendicular to the chord, both of whose ends lie on the
//!   circle); the depth is the farthest vertex's `ρ − R`;
//! - a **clump**: its member disks (see [`super::clump`]).
//!
//! A disk's overlap area (the part of it beyond the circle, `πr² − lens(r, R, d)`) and chord
//! are given when asked (cohesion reads them: `contact_law::cohesion`; a disk's spring stays
//! on its depth). An ellipse and a polygon get no overlap area (the area law falls back to
//! the spring on the depth against a drum); a rectangle gets its flat overlap, as against a
//! half-plane (see [`contact_drum_polygon`]).

use super::local::pow2_floor;
use super::record::{Contact, ContactState, OverlapArea, Request, TOUCH_TOL};
use super::small::List;
use crate::geometry::overlap_area::ellipse_cap_at_depth;
use crate::geometry::{Drum, Pose, Shape, Vec2};

/// The record, from the world quantities.
#[inline]
fn record(state: ContactState, point: Vec2, normal: Vec2, depth: f64, half: f64) -> Contact {
    Contact {
        state,
        point,
        normal,
        depth,
        half_chord: half,
        area: None,
        flat: None,
    }
}

/// The state of a contact of depth `depth` (already ≥ −tol) for a body of size `size` whose
/// nearest point to the centre lies `inner` beyond the circle (> 0: wholly outside).
#[inline]
fn state_of(depth: f64, inner: f64, size: f64) -> ContactState {
    if inner >= 0.0 {
        ContactState::Contained
    } else if depth <= TOUCH_TOL * size {
        ContactState::Touching
    } else {
        ContactState::Overlap
    }
}

/// Contact between a drum (i) and a circle (j) of radius `r` at `pose` (closed form).
#[inline]
pub fn contact_drum_circle(drum: &Drum, r: f64, pose: &Pose, request: &Request) -> Option<Contact> {
    let v = pose.position - drum.center;
    let d = v.norm();
    let depth = d + r - drum.radius;
    if depth.is_nan() || depth < -TOUCH_TOL * r {
        return None;
    }
    // A disk centred on the drum's centre touches all round: any direction (down) will do.
    let u = if d > 0.0 { v / d } else { Vec2::new(0.0, -1.0) };
    let point = drum.center + u * drum.radius;
    let state = state_of(depth, d - r - drum.radius, r);
    let big = drum.radius;
    let mut c = record(state, point, -u, depth, 0.0);
    // The two circles cross (|r − R| < d): the chord and the overlap (the disk's part beyond
    // the drum's circle). Only cohesion reads the area (it asks for the chord too): the area
    // law's spring stays on the depth against a drum, and pays for no area it would not read.
    // (A touching disk, δ at rounding, takes its chord as against a half-plane.)
    if request.chord && state != ContactState::Contained && d > (r - big).abs() {
        let depth = depth.max(0.0);
        // The crossings lie at x = (d² + R² − r²)/(2d) from c along u; the drum's cap beyond
        // that line has sagitta h_D = R − x = (r² − (R − d)²)/(2d) = δ(2r − δ)/(2d) (written
        // with the depth δ = d + r − R: no cancellation at small overlaps), the disk's cap
        // beyond it h_d = d + r − x = δ + h_D, and the half chord is √(h_D(2R − h_D)).
        let h_drum = depth * (2.0 * r - depth) / (2.0 * d);
        let half = (h_drum * (2.0 * big - h_drum)).max(0.0).sqrt();
        c.half_chord = half;
        if request.area && state == ContactState::Overlap {
            // The disk's part outside the drum: its cap beyond the chord less the drum's cap
            // beyond it (which lies inside the disk), A = πr² − lens(r, R, d). Moving the disk
            // by dp changes A by ℓ u·dp (the chord sweeps out the lens's boundary on the drum's
            // side: d(lens)/dd = −ℓ for two circles), so |∂A/∂p| = ℓ = 2·half along u = −n, at
            // the contact point on the line of centres (no couple).
            let cap = |rad: f64, h: f64| ellipse_cap_at_depth(rad, rad, [1.0, 0.0], h);
            c.area = Some(OverlapArea {
                area: cap(r, depth + h_drum) - cap(big, h_drum),
                length: 2.0 * half,
                normal: -u,
                point,
                couple: 0.0,
            });
        }
    }
    Some(c)
}

/// `f(t) = |x(t) − q|²` and `g(t) = f′(t)/2` for the ellipse `x(t) = (a cos t, b sin t)`.
#[inline]
fn fg(a: f64, b: f64, q: [f64; 2], t: f64) -> (f64, f64, f64) {
    let (s, c) = t.sin_cos();
    let (dx, dy) = (a * c - q[0], b * s - q[1]);
    let g = (b * b - a * a) * s * c + a * q[0] * s - b * q[1] * c;
    let gp = (b * b - a * a) * (c * c - s * s) + a * q[0] * c + b * q[1] * s;
    (dx * dx + dy * dy, g, gp)
}

/// The parameter `t` of the point of the ellipse `(a cos t, b sin t)` farthest from `q`, and
/// the squared distance (see the module documentation).
pub fn ellipse_farthest(a: f64, b: f64, q: [f64; 2]) -> (f64, f64) {
    const N: usize = 16;
    let h = std::f64::consts::TAU / N as f64;
    let f: [f64; N] = std::array::from_fn(|k| fg(a, b, q, k as f64 * h).0);
    // The discrete local maxima, best first (two are refined).
    let mut best = [(f64::NEG_INFINITY, 0usize); 2];
    for k in 0..N {
        let (l, r) = (f[(k + N - 1) % N], f[(k + 1) % N]);
        if f[k] >= l && f[k] >= r {
            if f[k] > best[0].0 {
                best[1] = best[0];
                best[0] = (f[k], k);
            } else if f[k] > best[1].0 {
                best[1] = (f[k], k);
            }
        }
    }
    let mut out = (0.0, f64::NEG_INFINITY);
    for &(fk, k) in best.iter().filter(|b| b.0 > f64::NEG_INFINITY) {
        let t = refine(a, b, q, k as f64 * h, h);
        let ft = fg(a, b, q, t).0;
        let (t, ft) = if ft >= fk {
            (t, ft)
        } else {
            (k as f64 * h, fk)
        };
        if ft > out.1 {
            out = (t, ft);
        }
    }
    out
}

/// A local maximum of f near `t0` (within `h`): Newton on g, safeguarded by bisection on a
/// bracket `[lo, hi]` with `g(lo) ≥ 0 ≥ g(hi)` (found by resampling when `[t0 − h, t0 + h]`
/// is not one).
fn refine(a: f64, b: f64, q: [f64; 2], t0: f64, h: f64) -> f64 {
    let (mut lo, mut hi) = (t0 - h, t0 + h);
    let mut level = 0;
    while !(fg(a, b, q, lo).1 >= 0.0 && fg(a, b, q, hi).1 <= 0.0) {
        if level == 4 {
            return t0;
        }
        level += 1;
        // Sixteen subsamples: keep the best and its neighbours.
        let step = (hi - lo) / 16.0;
        let k = (0..=16)
            .max_by(|&i, &j| {
                let (fi, fj) = (
                    fg(a, b, q, lo + i as f64 * step).0,
                    fg(a, b, q, lo + j as f64 * step).0,
                );
                fi.total_cmp(&fj)
            })
            .unwrap_or(8);
        let centre = lo + k as f64 * step;
        (lo, hi) = (centre - step, centre + step);
    }
    let mut t = 0.5 * (lo + hi);
    for _ in 0..100 {
        let (_, g, gp) = fg(a, b, q, t);
        if g > 0.0 {
            lo = t;
        } else if g < 0.0 {
            hi = t;
        } else {
            return t;
        }
        let newton = t - g / gp;
        let next = if gp < 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - t).abs() <= 4.0 * f64::EPSILON * (1.0 + t.abs()) || hi - lo <= f64::EPSILON {
            return next;
        }
        t = next;
    }
    t
}

/// Contact between a drum (i) and an ellipse (j) of semi-axes `a`, `b` at `pose`.
pub fn contact_drum_ellipse(
    drum: &Drum,
    a: f64,
    b: f64,
    pose: &Pose,
    request: &Request,
) -> Option<Contact> {
    let scale = pow2_floor(a.max(b));
    let inv = 1.0 / scale;
    let qv = pose.to_body_vector(drum.center - pose.position) * inv;
    let q = [qv.x, qv.y];
    let (sa, sb) = (a * inv, b * inv);
    let big = drum.radius * inv;
    // A cheap bound first: the farthest point is at most |q| + a from q.
    if (qv.norm() + sa - big) < -TOUCH_TOL {
        return None;
    }
    let (t, f2) = ellipse_farthest(sa, sb, q);
    let rho = f2.sqrt();
    let depth = rho - big;
    if depth.is_nan() || depth < -TOUCH_TOL {
        return None;
    }
    let (s, c) = t.sin_cos();
    let far = [sa * c, sb * s];
    let u_local = Vec2::new(far[0] - q[0], far[1] - q[1]) / rho;
    let u = pose.to_world_vector(u_local);
    // The nearest point to q lies beyond the circle when q is outside the ellipse's reach: the
    // body wholly outside (contained in the solid) once its nearest distance exceeds R; the
    // nearest distance is at least |q| − a.
    let inner = if qv.norm() - sa > big { 1.0 } else { -1.0 };
    let state = state_of(depth, inner, 1.0);
    let _ = request; // (no chord or area: see the module documentation)
    Some(record(
        state,
        drum.center + u * drum.radius,
        -u,
        depth * scale,
        0.0,
    ))
}

/// Contact between a drum (i) and a convex polygon (j): a polygon, or a rectangle as its
/// corners.
///
/// For a flat-sided body (a rectangle) a Winkler foundation, as against a half-plane, but of
/// radial springs on the part of the polygon beyond the circle (see [`flat_overlap`]): a
/// rectangle lying on the drum has a lobe beyond it at each bottom corner, and the resultant
/// moves towards the deeper one when it tilts — the moment that keeps it on its face (with one
/// point at the chord's midpoint it would rock). Then the record's normal is the resultant's,
/// `flat.area` its magnitude over k′, `flat.centroid` where it acts (on the line through the
/// centre), and `point` that less ȳ along the normal, so that the Winkler energy `k′ A ȳ` is
/// the foundation's.
pub fn contact_drum_polygon(
    drum: &Drum,
    poly: &Shape,
    pose: &Pose,
    request: &Request,
) -> Option<Contact> {
    let scale = pow2_floor(poly.bounding_radius());
    let inv = 1.0 / scale;
    let qv = pose.to_body_vector(drum.center - pose.position) * inv;
    let big = drum.radius * inv;
    let mut corners = [Vec2::zeros(); 4];
    let verts = poly.vertices(&mut corners);
    let n = verts.len();
    let v: List<Vec2> = verts.iter().map(|x| *x * inv - qv).collect(); // relative to q
    let dist: List<f64> = v.iter().map(|x| x.norm()).collect();
    let (mut far, mut rho) = (0, f64::NEG_INFINITY);
    for (k, &d) in dist.iter().enumerate() {
        if d > rho {
            (far, rho) = (k, d);
        }
    }
    let depth = rho - big;
    if depth.is_nan() || depth < -TOUCH_TOL {
        return None;
    }
    let u = v[far] / rho;
    let world = |x: Vec2| drum.center + pose.to_world_vector(x) * scale;
    // The boundary walked counter-clockwise: the vertices outside the circle and the crossings
    // (`Some(true)`: leaving the circle, `Some(false)`: coming back), in order.
    let mut walk: List<(Vec2, Option<bool>)> = List::new();
    // The outermost crossings, by their angle from u.
    let (mut lo, mut hi) = (
        (f64::INFINITY, Vec2::zeros()),
        (f64::NEG_INFINITY, Vec2::zeros()),
    );
    let mut count = 0;
    for k in 0..n {
        let (p, e) = (v[k], v[(k + 1) % n] - v[k]);
        if dist[k] > big {
            walk.push((p, None));
        }
        // |p + s e|² = R²: e² s² + 2 (p·e) s + (|p|² − R²) = 0.
        let (aa, bb, cc) = (
            e.norm_squared(),
            p.dot(&e),
            (dist[k] - big) * (dist[k] + big),
        );
        let disc = bb * bb - aa * cc;
        // (A tangent line, disc = 0, crosses nothing.)
        if aa == 0.0 || disc <= 0.0 {
            continue;
        }
        let root = disc.sqrt();
        // Stable roots (no cancellation): s1 s2 = cc/aa.
        let big_root = if bb >= 0.0 { -bb - root } else { -bb + root };
        let (s1, s2) = if big_root == 0.0 {
            (0.0, 0.0)
        } else {
            (big_root / aa, cc / big_root)
        };
        let (s1, s2) = (s1.min(s2), s1.max(s2));
        for s in [s1, s2] {
            if (0.0..1.0).contains(&s) {
                let x = p + e * s;
                let ang = (u.x * x.y - u.y * x.x).atan2(u.dot(&x));
                count += 1;
                if ang < lo.0 {
                    lo = (ang, x);
                }
                if ang > hi.0 {
                    hi = (ang, x);
                }
                walk.push((x, Some(x.dot(&e) > 0.0)));
            }
        }
    }
    let outside = dist.iter().all(|&d| d > big);
    let (state, point, normal, half) = if count >= 2 && depth > TOUCH_TOL && !outside {
        let mid = (lo.1 + hi.1) * 0.5;
        let m = mid.norm();
        let normal = if m > 0.0 { -mid / m } else { -u };
        let half = if request.chord {
            0.5 * (hi.1 - lo.1).norm() * scale
        } else {
            0.0
        };
        (ContactState::Overlap, world(mid), normal, half)
    } else if outside {
        (ContactState::Contained, world(u * big), -u, 0.0)
    } else {
        (ContactState::Touching, world(u * big), -u, 0.0)
    };
    let mut c = record(
        state,
        point,
        pose.to_world_vector(normal),
        depth * scale,
        half,
    );
    if poly.is_flat_sided()
        && state == ContactState::Overlap
        && let Some((force, energy, centroid)) = flat_overlap(&walk, big)
    {
        // A bed of radial springs (pressure k′(ρ − R) along −r̂): its resultant −k′ ∫ r̂ dA
        // acts on the line through the centre (every element does), its energy is
        // k′ ∫ (ρ − R) dA — the gradient of that energy for any motion of the body, and no work
        // done by the drum turning under it. As a Winkler record: the area |∫ r̂ dA|, the normal
        // along −∫ r̂ dA, acting at the centroid's foot on that line (`flat.centroid`) with the
        // energy overlap 2ȳ, ȳ = ∫ (ρ − R) dA / |∫ r̂ dA| (the record's point ȳ along the normal
        // from there).
        let size = force.norm();
        if size > 0.0 {
            let u = force / size;
            let foot = u * centroid.dot(&u);
            let ybar = energy / size;
            c.normal = pose.to_world_vector(-u);
            c.point = world(foot - u * ybar);
            c.flat = Some(super::record::FlatOverlap {
                area: size * scale * scale,
                centroid: world(foot),
            });
        }
    }
    Some(c)
}

/// Gauss–Legendre nodes and weights on [−1, 1], eight points (exact to degree 15).
const GAUSS: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
];

/// The radial Winkler foundation of a polygon's part beyond the circle `|x| = big` (local,
/// the drum's centre at the origin), from its boundary's `walk` (see [`contact_drum_polygon`]):
/// `(∫ r̂ dA, ∫ (ρ − R) dA, ∫ x dA / ∫ dA)` over that part, `None` without a crossing.
///
/// Every ray from the centre through the part meets it on `R < ρ < ρ_b(θ)`, `ρ_b` the
/// polygon's far side (convex, the centre not in it), so with `s = ρ_b − R`:
/// `∫ r̂ dA = ∫ r̂ s (R + s/2) dθ`, `∫ (ρ − R) dA = ∫ s² (R/2 + s/3) dθ`, `∫ dA = ∫ s (R +
/// s/2) dθ` and `∫ x dA = ∫ r̂ s (R² + R s + s²/3) dθ`, each along the runs of the boundary
/// beyond the circle (θ increases along them), edge piece by edge piece; on a piece at distance
/// h from the centre, `ρ_b = h / cos α` with α the angle from the piece's foot, and eight
/// Gauss–Legendre points in α integrate it (s is small and smooth there: no cancellation).
type Radial = (Vec2, f64, Vec2);
fn flat_overlap(walk: &[(Vec2, Option<bool>)], big: f64) -> Option<Radial> {
    let m = walk.len();
    let start = walk.iter().position(|w| w.1 == Some(true))?;
    let (mut force, mut energy, mut area, mut moment) = (Vec2::zeros(), 0.0, 0.0, Vec2::zeros());
    let mut inside_run = false;
    for i in 0..m {
        let (p, kind) = walk[(start + i) % m];
        if kind == Some(true) {
            inside_run = true;
        }
        if !inside_run {
            continue;
        }
        if kind == Some(false) {
            inside_run = false;
            continue;
        }
        let q = walk[(start + i + 1) % m].0;
        let e = q - p;
        let len = e.norm();
        if len == 0.0 {
            continue;
        }
        // The piece's foot: f̂ along the normal from the centre to its line, h its distance.
        let t = e / len;
        let mut f = Vec2::new(t.y, -t.x);
        let mut h = f.dot(&p);
        if h < 0.0 {
            f = -f;
            h = -h;
        }
        let g = Vec2::new(-f.y, f.x);
        let angle = |x: Vec2| g.dot(&x).atan2(f.dot(&x));
        let (a0, a1) = (angle(p), angle(q));
        let (mid, half) = (0.5 * (a0 + a1), 0.5 * (a1 - a0));
        for (x, w) in GAUSS {
            let al = mid + half * x;
            let (sn, cs) = al.sin_cos();
            let sv = h / cs - big;
            let r = f * cs + g * sn;
            let dw = w * half;
            let a = sv * (big + 0.5 * sv);
            force += r * (a * dw);
            area += a * dw;
            energy += sv * sv * (0.5 * big + sv / 3.0) * dw;
            moment += r * (sv * (big * big + big * sv + sv * sv / 3.0) * dw);
        }
    }
    (area > 0.0).then(|| (force, energy, moment / area))
}

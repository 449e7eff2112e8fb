//! High-precision reference for the **overlap area** of a pair (and the boundary pieces it is
//! made of), for the tests of the overlap-area (energy-conserving) contact law.
//!
//! Everything is computed in double-double ([`DD`], ~106 bits) from the exact `f64` inputs and
//! rounded to `f64` only at the end, like [`reference_contact`](super::reference::reference_contact),
//! whose conventions it shares (shapes, poses, walls, the pair origin, crossings; see
//! [`super::reference`]). It uses no pencil of conics and nothing from the crate's geometry or
//! narrow phase.
//!
//! # What it computes
//!
//! * `area`: the area of the intersection of the two solids. For a wall the body's part in the
//!   wall's solid half-plane `{x : normal·(x − point) ≤ 0}`. 0 when separated (and for an
//!   external tangency); the area of the inner solid when one contains the other (a body wholly
//!   in a wall's solid: the body's area; an internal tangency counts as contained); the common
//!   area when the two boundaries coincide.
//! * The **crossings** of the two boundaries in counter-clockwise order along the boundary of the
//!   overlap region, relative to the pair origin (the position of the first body).
//! * The **pieces** of that boundary: `pieces[k]` runs counter-clockwise from `crossings[k]` to
//!   `crossings[k + 1]` (cyclically) along the boundary of its `owner` (`i` or `j`): the part of
//!   the owner's boundary that lies inside the other solid. `pieces[0]` is always one of `i`'s;
//!   for convex solids the owners alternate. Its closing chord is `(start, end)` and its `cap` is
//!   the area between the piece and that chord (≥ 0; 0 for a wall's piece).
//!
//! The area is `Σ caps + (area of the polygon of the crossings, in order)`: Green's theorem
//! `A = ½∮(x dy − y dx)` over the overlap boundary, with each piece's integral written as its
//! cap plus the integral along its chord; the chords close into the crossing polygon.
//!
//! # Method
//!
//! 1. Crossings: the reference's own search ([`super::reference`]: the tangent-half-angle
//!    quartic for two conics, the line–conic quadratic for walls, the segment walk for
//!    rectangles), the points `reference_contact` reports, then polished by up to three Newton
//!    steps on the two boundary functions evaluated at the point itself (conic
//!    `(ξ/a)² + (η/b)² − 1`, wall `n·(x − p)`, the nearest rectangle edge line). The search
//!    solves along a parametrisation whose coefficients can be far larger than the local
//!    geometry (a thin ellipse's tip seen from the foot of its centre on a wall lost 1e-20
//!    relative in the area); the polish removes that. It is skipped at rectangle corners and
//!    where the two boundaries are parallel (a shared segment's crossing, which is not an
//!    isolated point), and a step is kept only if it is tiny and does not raise the residual.
//!    Tangencies (even-multiplicity roots, touching runs) are not crossings and do not split
//!    the boundary.
//! 2. Each object's boundary is cut at the crossings, in its own counter-clockwise order:
//!    * ellipse/circle `c + a cos φ e1 + b sin φ e2`: by the eccentric angle
//!      `φ = atan2(a·η, b·ξ)` of the crossing (`(ξ, η)` its body coordinates);
//!    * rectangle: by the perimeter position `k + s` (edge `k` from corner `k` to corner
//!      `k + 1`, corners counter-clockwise from `(−w/2, −h/2)`, `s ∈ [0, 1]` along the edge);
//!    * wall: by the coordinate along `t = perp(normal)` (the direction that keeps the solid on
//!      the left); only the finite pieces between consecutive crossings exist.
//! 3. A piece between consecutive crossings belongs to the overlap boundary iff it lies inside
//!    the other solid: sample points on it (its middle first, then quarter points, corners) are
//!    classified with the other object's DD inside test; the first not *on* the other boundary
//!    decides. (*Decision*: a piece lying entirely on the other boundary is kept for `i` only.)
//!    Chaining the kept pieces end to start orders the crossings.
//! 4. Caps, in closed form in DD:
//!    * elliptic arc over the eccentric-angle span `Δφ ∈ (0, 2π)`: `½ab(Δφ − sin Δφ)` (the
//!      image of a circular segment under the map `diag(a, b)`; a full ellipse, `Δφ = 2π`,
//!      gives `πab`), with `Δφ − sin Δφ` from its series for small `Δφ`
//!      ([`DD::x_minus_sin`]), so a tiny cap keeps its full relative precision. `Δφ` is
//!      `atan2(w0 × w1, w0 · w1)` of the scaled vectors `w = (bξ, aη)` of the two crossings,
//!      taken modulo 2π to agree with the difference of their eccentric angles. (In the form
//!      the Green integral is usually written, the arc from `x0` to `x1` contributes
//!      `½ab Δφ + ½ c × (x1 − x0)`; minus the chord's `½ x0 × x1` this is the cap.)
//!    * rectangle polyline `x0, corners…, x1`: the shoelace sum `½ Σ (v_k − x0) × (v_{k+1} − x0)`;
//!    * wall segment: 0.
//!
//!    The crossing polygon is summed relative to its first vertex, so that for two crossings
//!    it is exactly 0 and a tiny lens is the sum of two small caps without cancellation.
//! 5. No crossings: one sample of each boundary not *on* the other decides containment
//!    (boundary samples of a conic at `φ = 2πk/16`, a rectangle's corners and edge midpoints).
//!
//! # Accuracy (measured by `tests/overlap_reference_selftest.rs`)
//!
//! Generic overlaps: relative error ≲ 1e-29 (lens closed form: 8e-30 worst down to
//! `δ/r = 1e-3`; rectangles against DD polygon clipping: 2e-32 of the area scale). The area is
//! limited by the crossings: their position relative to the pair origin carries an absolute
//! error ~EPS × the body size, which for a shallow overlap of depth δ is a relative error
//! ~EPS·r/δ in the sagitta, hence in the area (measured: ≤ 0.32 EPS·r/δ for circle pairs
//! with `δ/r` from 1e-6 to 1e-12, i.e. 3.6e-24 at `δ/r = 1e-9`; wall cuts ≤ 2.8 EPS/(1 ∓ D)
//! for a cut at scaled distance D from the centre). Overlaps shallower than the reference's
//! tangency tolerance (the two crossing roots merge, `δ/r ≲ 1e-28`) are reported as
//! `Separated` with area 0 (the true area is below ~1e-42 r²).
//!
//! Cost: ~10–100 µs per call (release build), a few times `reference_contact`.
//!
//! Panics for two walls, an odd number of crossings, or pieces that do not close into one loop
//! (only possible for degenerate, non-generic input).

use super::dd::DD;
use super::reference::{Cls, Conic, Geo, RObj, Rect, V, find, origin_of};

/// Which object of the pair `(i, j)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The first object of the pair.
    I,
    /// The second object of the pair.
    J,
}

/// Topological state of the overlap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OverlapState {
    /// No crossings, neither contains the other (includes an external tangency): area 0.
    Separated,
    /// Exactly two crossings.
    Overlap,
    /// `n ≥ 4` crossings (e.g. two crossed thin ellipses).
    Deep(usize),
    /// No crossings and this object's solid lies inside the other's (for a wall: the body lies
    /// in the wall's solid half-plane); the area is that object's area. Internal tangency
    /// counts as contained.
    Contained(Side),
    /// The two boundaries coincide; the area is the common area.
    Coincident,
}

/// One piece of the overlap region's boundary: the part of `owner`'s boundary, inside the
/// other solid, from `start` to `end` (counter-clockwise, i.e. with the overlap on the left).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RPiece {
    /// Whose boundary this is.
    pub owner: Side,
    /// First end (a crossing), relative to the pair origin.
    pub start: [f64; 2],
    /// Second end (the next crossing counter-clockwise), relative to the pair origin.
    pub end: [f64; 2],
    /// Area between the piece and its closing chord `start`–`end` (0 for a wall's piece).
    pub cap: f64,
}

/// Reference overlap of a pair.
#[derive(Clone, Debug, PartialEq)]
pub struct ROverlap {
    /// Topological state.
    pub state: OverlapState,
    /// Area of the intersection of the two solids (see the module documentation).
    pub area: f64,
    /// The same in DD, before the final rounding.
    pub area_dd: DD,
    /// Crossings, counter-clockwise along the overlap boundary, relative to `origin`
    /// (`crossings[0]` is the start of a piece of `i`). Empty without crossings.
    pub crossings: Vec<[f64; 2]>,
    /// `pieces[k]` runs from `crossings[k]` to `crossings[(k + 1) % n]`.
    pub pieces: Vec<RPiece>,
    /// Position of the first body of the pair (`i` if it is a body, else `j`).
    pub origin: [f64; 2],
}

impl ROverlap {
    /// The pieces of the overlap boundary owned by `side` (e.g. `Side::J`: every piece of
    /// `j`'s boundary inside `i`, with its closing chord `start`–`end`).
    pub fn pieces_of(&self, side: Side) -> impl Iterator<Item = &RPiece> {
        self.pieces.iter().filter(move |p| p.owner == side)
    }
}

/// Reference overlap area, crossings and boundary pieces of the pair `(i, j)`; see the module
/// documentation.
pub fn reference_overlap(i: &RObj, j: &RObj) -> ROverlap {
    let origin = origin_of(i, j);
    let gi = Geo::new(i, origin);
    let gj = Geo::new(j, origin);
    let found = find(&gi, &gj);
    let mut out = ROverlap {
        state: OverlapState::Separated,
        area: 0.0,
        area_dd: DD::ZERO,
        crossings: Vec::new(),
        pieces: Vec::new(),
        origin,
    };
    let xs: Vec<V> = found
        .crossings
        .iter()
        .map(|x| refine_crossing(*x, &gi, &gj))
        .collect();
    let contained = if found.coincident {
        Some((OverlapState::Coincident, &gi))
    } else if !xs.is_empty() {
        None
    } else if lies_inside(&gi, &gj) {
        Some((OverlapState::Contained(Side::I), &gi))
    } else if lies_inside(&gj, &gi) {
        Some((OverlapState::Contained(Side::J), &gj))
    } else {
        return out; // separated
    };
    if let Some((state, inner)) = contained {
        out.state = state;
        out.area_dd = body_area(inner);
        out.area = out.area_dd.to_f64();
        return out;
    }
    let n = xs.len();
    assert!(
        n.is_multiple_of(2),
        "reference_overlap: odd number of crossings ({n}) for {i:?} / {j:?}: degenerate input"
    );

    // Pieces of each boundary inside the other solid.
    let mut kept: Vec<Piece> = Vec::new();
    for (owner, g, other) in [(Side::I, &gi, &gj), (Side::J, &gj, &gi)] {
        for piece in boundary_pieces(g, owner, &xs) {
            let cls = piece
                .samples(&xs)
                .into_iter()
                .map(|x| classify(other, x))
                .find(|c| *c != Cls::On);
            let inside = match cls {
                Some(c) => c == Cls::In,
                None => owner == Side::I,
            };
            if inside {
                kept.push(piece);
            }
        }
    }

    // Chain them: exactly one kept piece starts at each crossing.
    let mut starting = vec![None; n];
    for (k, p) in kept.iter().enumerate() {
        assert!(
            starting[p.from].replace(k).is_none(),
            "reference_overlap: two pieces start at one crossing for {i:?} / {j:?}"
        );
    }
    let first = kept
        .iter()
        .enumerate()
        .filter(|(_, p)| p.owner == Side::I)
        .min_by_key(|(_, p)| p.from)
        .map(|(k, _)| k)
        .unwrap_or_else(|| panic!("reference_overlap: no piece of i for {i:?} / {j:?}"));
    let mut order = vec![first];
    loop {
        let next = starting[kept[*order.last().expect("non-empty")].to]
            .unwrap_or_else(|| panic!("reference_overlap: open boundary for {i:?} / {j:?}"));
        if next == first {
            break;
        }
        order.push(next);
        assert!(
            order.len() <= n,
            "reference_overlap: pieces do not close for {i:?} / {j:?}"
        );
    }
    assert_eq!(
        order.len(),
        n,
        "reference_overlap: pieces form more than one loop for {i:?} / {j:?}"
    );

    // Green's theorem: caps plus the polygon of the crossings (relative to its first vertex).
    let p0 = xs[kept[first].from];
    let mut area = DD::ZERO;
    for &k in &order {
        let piece = &kept[k];
        let cap = piece.cap(&xs);
        let (u, v) = (xs[piece.from] - p0, xs[piece.to] - p0);
        area += cap + cross(u, v).mul_pow2(0.5);
        out.crossings.push(xs[piece.from].to_f64());
        out.pieces.push(RPiece {
            owner: piece.owner,
            start: xs[piece.from].to_f64(),
            end: xs[piece.to].to_f64(),
            cap: cap.to_f64(),
        });
    }
    out.state = if n == 2 {
        OverlapState::Overlap
    } else {
        OverlapState::Deep(n)
    };
    out.area_dd = area;
    out.area = area.to_f64();
    out
}

// ---------------------------------------------------------------------------
// Boundary pieces
// ---------------------------------------------------------------------------

/// The geometric path of a piece between crossings `from` and `to`.
enum Path {
    /// Elliptic arc from eccentric angle `phi0` over `dphi ∈ [0, 2π)`.
    Arc { conic: Conic, phi0: DD, dphi: DD },
    /// Polyline through the rectangle corners strictly between the two crossings.
    Poly(Vec<V>),
    /// Straight segment (a wall's line).
    Segment,
}

struct Piece {
    owner: Side,
    /// Index (into the crossings) of the start.
    from: usize,
    /// Index of the end.
    to: usize,
    path: Path,
}

/// Fractions of a piece at which it is sampled, middle first.
const SAMPLE_FRACTIONS: [f64; 5] = [0.5, 0.25, 0.75, 0.125, 0.875];

impl Piece {
    /// Sample points on the piece (excluding its ends), most telling first.
    fn samples(&self, xs: &[V]) -> Vec<V> {
        let (a, b) = (xs[self.from], xs[self.to]);
        match &self.path {
            Path::Arc { conic, phi0, dphi } => SAMPLE_FRACTIONS
                .iter()
                .map(|&f| {
                    let (s, c) = (*phi0 + *dphi * f).sin_cos();
                    conic.point_at(c, s)
                })
                .collect(),
            Path::Poly(corners) => {
                let mut verts = vec![a];
                verts.extend(corners);
                verts.push(b);
                let mids = verts.windows(2).map(|w| w[0].mid(w[1]));
                mids.chain(corners.iter().copied()).collect()
            }
            Path::Segment => SAMPLE_FRACTIONS.iter().map(|&f| a + (b - a) * f).collect(),
        }
    }

    /// Area between the piece and its chord (see the module documentation).
    fn cap(&self, xs: &[V]) -> DD {
        let (a, b) = (xs[self.from], xs[self.to]);
        match &self.path {
            Path::Arc { conic, dphi, .. } => (conic.a * conic.b * dphi.x_minus_sin()).mul_pow2(0.5),
            Path::Poly(corners) => {
                let mut verts: Vec<V> = corners.iter().map(|v| *v - a).collect();
                verts.push(b - a);
                let twice: DD = verts.windows(2).map(|w| cross(w[0], w[1])).sum();
                twice.mul_pow2(0.5)
            }
            Path::Segment => DD::ZERO,
        }
    }
}

/// The pieces of `g`'s boundary between consecutive crossings, counter-clockwise.
fn boundary_pieces(g: &Geo, owner: Side, xs: &[V]) -> Vec<Piece> {
    let n = xs.len();
    let sorted_by = |key: &dyn Fn(V) -> DD| {
        let mut idx: Vec<(DD, usize)> = xs.iter().enumerate().map(|(k, x)| (key(*x), k)).collect();
        idx.sort_by(|p, q| p.0.cmp_total(&q.0));
        idx
    };
    match g {
        Geo::Conic(c) => {
            let order = sorted_by(&|x| ecc_angle(c, x));
            (0..n)
                .map(|k| {
                    let ((phi0, from), (phi1, to)) = (order[k], order[(k + 1) % n]);
                    Piece {
                        owner,
                        from,
                        to,
                        path: Path::Arc {
                            conic: *c,
                            phi0,
                            dphi: arc_span(c, xs[from], xs[to], phi1 - phi0),
                        },
                    }
                })
                .collect()
        }
        Geo::Rect(r) => {
            let order = sorted_by(&|x| rect_param(r, x));
            let corners = r.corners();
            (0..n)
                .map(|k| {
                    let ((t0, from), (t1, to)) = (order[k], order[(k + 1) % n]);
                    let t1 = if t1 > t0 { t1 } else { t1 + 4.0 };
                    let mut between = Vec::new();
                    let mut m = t0.hi.floor() + 1.0;
                    while DD::from(m) < t1 {
                        between.push(corners[(m as usize) % 4]);
                        m += 1.0;
                    }
                    Piece {
                        owner,
                        from,
                        to,
                        path: Path::Poly(between),
                    }
                })
                .collect()
        }
        Geo::Wall(w) => {
            let t = w.n.perp();
            let order = sorted_by(&|x| t.dot(x - w.p));
            order
                .windows(2)
                .map(|p| Piece {
                    owner,
                    from: p[0].1,
                    to: p[1].1,
                    path: Path::Segment,
                })
                .collect()
        }
    }
}

/// Eccentric angle of (a point near) the conic's boundary, in `[0, 2π)`.
fn ecc_angle(c: &Conic, x: V) -> DD {
    let (l1, l2) = c.local(x);
    let phi = (c.a * l2).atan2(c.b * l1);
    if phi.is_negative() {
        phi + DD::TAU
    } else {
        phi
    }
}

/// Eccentric-angle span from `x0` to `x1` counter-clockwise, in `[0, 2π)`: the angle between
/// the scaled vectors `(bξ, aη)` (no cancellation for close crossings), shifted by a multiple
/// of 2π to agree with `approx` (the difference of the eccentric angles).
fn arc_span(c: &Conic, x0: V, x1: V, approx: DD) -> DD {
    let scaled = |x: V| {
        let (l1, l2) = c.local(x);
        V::new(c.b * l1, c.a * l2)
    };
    let (w0, w1) = (scaled(x0), scaled(x1));
    let direct = cross(w0, w1).atan2(w0.dot(w1));
    let approx = if approx.is_negative() {
        approx + DD::TAU
    } else {
        approx
    };
    let turns = ((approx - direct) / DD::TAU).to_f64().round();
    direct + DD::TAU * turns
}

/// Perimeter position `k + s` of (a point near) the rectangle's boundary (see the module docs).
fn rect_param(r: &Rect, x: V) -> DD {
    let w = x - r.c;
    let (l1, l2) = (w.dot(r.e1), w.dot(r.e2));
    // Distances to the edge lines, edges in corner order: bottom, right, top, left.
    let dist = [
        (l2 + r.hh).abs(),
        (l1 - r.hw).abs(),
        (l2 - r.hh).abs(),
        (l1 + r.hw).abs(),
    ];
    let k = (0..4)
        .min_by(|&p, &q| dist[p].cmp_total(&dist[q]))
        .expect("four edges");
    let (w2, h2) = (r.hw.mul_pow2(2.0), r.hh.mul_pow2(2.0));
    let s = match k {
        0 => (l1 + r.hw) / w2,
        1 => (l2 + r.hh) / h2,
        2 => (r.hw - l1) / w2,
        _ => (r.hh - l2) / h2,
    };
    s.max(DD::ZERO).min(DD::ONE) + k as f64
}

// ---------------------------------------------------------------------------
// Crossing refinement
// ---------------------------------------------------------------------------

/// A boundary near `x` as a function `g` (zero on the boundary) and its gradient at `x`;
/// `None` for a rectangle corner (two edges within reach: the crossing is left alone).
fn boundary_fn(g: &Geo, x: V) -> Option<(DD, V)> {
    match g {
        Geo::Conic(c) => {
            // (ξ/a)² + (η/b)² − 1, gradient 2(ξ/a² e1 + η/b² e2).
            let (l1, l2) = c.local(x);
            let (u1, u2) = (l1 / c.a, l2 / c.b);
            let grad = c.e1 * (u1 / c.a).mul_pow2(2.0) + c.e2 * (u2 / c.b).mul_pow2(2.0);
            Some((u1.sqr() + u2.sqr() - 1.0, grad))
        }
        Geo::Wall(w) => Some((w.n.dot(x - w.p), w.n)),
        Geo::Rect(r) => {
            let w = x - r.c;
            let (l1, l2) = (w.dot(r.e1), w.dot(r.e2));
            // (value, outward normal) of the four edge lines.
            let mut edges = [
                (l1 - r.hw, r.e1),
                (-l1 - r.hw, -r.e1),
                (l2 - r.hh, r.e2),
                (-l2 - r.hh, -r.e2),
            ];
            edges.sort_by(|p, q| p.0.abs().cmp_total(&q.0.abs()));
            let near = CORNER_REL * (r.hw + r.hh).to_f64();
            (edges[1].0.abs().to_f64() > near).then_some(edges[0])
        }
    }
}

/// Relative distance (to the rectangle's size) within which a crossing counts as at a corner.
const CORNER_REL: f64 = 1e-20;
/// Newton steps accepted only below this size relative to the pair's scale.
const REFINE_MAX_STEP: f64 = 1e-10;

/// Polishes a crossing by Newton's method on the two boundary functions evaluated at the point
/// itself (at most 3 steps; a step is kept only if it is small and does not increase the
/// residual). The crossing search solves along a parametrisation whose coefficients can be
/// much larger than the local geometry (e.g. a thin ellipse's tip seen from the foot of its
/// centre on a wall), which costs accuracy for nearly tangent pairs; the boundary functions
/// at the point have errors at the DD level of their own size. Not applied at rectangle
/// corners nor where the boundaries are parallel (shared segments), where the crossing is
/// already exact or not an isolated point.
fn refine_crossing(x: V, gi: &Geo, gj: &Geo) -> V {
    let residual = |x: V| -> Option<(f64, DD, V, DD, V)> {
        let (f1, a) = boundary_fn(gi, x)?;
        let (f2, b) = boundary_fn(gj, x)?;
        let r = (f1.abs() / a.dot(a).sqrt())
            .max(f2.abs() / b.dot(b).sqrt())
            .to_f64();
        Some((r, f1, a, f2, b))
    };
    let scale = x.norm1() + size(gi) + size(gj);
    let mut x = x;
    for _ in 0..3 {
        let Some((r, f1, a, f2, b)) = residual(x) else {
            break;
        };
        if r == 0.0 {
            break;
        }
        let det = cross(a, b);
        let na = a.dot(a).sqrt() * b.dot(b).sqrt();
        if det.abs() <= na * 1e-24 {
            break;
        }
        // Solve a·Δ = −f1, b·Δ = −f2 (Cramer).
        let step = V::new((f2 * a.y - f1 * b.y) / det, (f1 * b.x - f2 * a.x) / det);
        if step.norm1() > REFINE_MAX_STEP * scale {
            break;
        }
        let y = x + step;
        match residual(y) {
            Some((ry, ..)) if ry <= r => x = y,
            _ => break,
        }
    }
    x
}

// ---------------------------------------------------------------------------
// Containment, areas, helpers
// ---------------------------------------------------------------------------

/// In/on/out of `x` with respect to the solid of `g`.
fn classify(g: &Geo, x: V) -> Cls {
    match g {
        Geo::Conic(c) => c.classify(x),
        Geo::Rect(r) => r.classify(x),
        Geo::Wall(w) => w.classify(x),
    }
}

/// Without crossings: whether `inner`'s solid lies in `outer`'s (decided by the first boundary
/// sample of `inner` that is not on `outer`'s boundary). A wall never lies in anything.
fn lies_inside(inner: &Geo, outer: &Geo) -> bool {
    let samples: Vec<V> = match inner {
        Geo::Conic(c) => (0..16)
            .map(|k| {
                let (s, c0) = (DD::TAU * (k as f64 / 16.0)).sin_cos();
                c.point_at(c0, s)
            })
            .collect(),
        Geo::Rect(r) => {
            let cs = r.corners();
            (0..4)
                .flat_map(|k| [cs[k], cs[k].mid(cs[(k + 1) % 4])])
                .collect()
        }
        Geo::Wall(_) => return false,
    };
    samples
        .into_iter()
        .map(|x| classify(outer, x))
        .find(|c| *c != Cls::On)
        == Some(Cls::In)
}

/// Size of a body (`a + b`, `(w + h)/2`; 0 for a wall), for relative thresholds.
fn size(g: &Geo) -> f64 {
    match g {
        Geo::Conic(c) => (c.a + c.b).to_f64(),
        Geo::Rect(r) => (r.hw + r.hh).to_f64(),
        Geo::Wall(_) => 0.0,
    }
}

/// Area of a body (`πab`, `wh`).
fn body_area(g: &Geo) -> DD {
    match g {
        Geo::Conic(c) => DD::PI * c.a * c.b,
        Geo::Rect(r) => (r.hw * r.hh).mul_pow2(4.0),
        Geo::Wall(_) => unreachable!("a wall is never the inner object"),
    }
}

/// 2D cross product `u × v = u_x v_y − u_y v_x`.
fn cross(u: V, v: V) -> DD {
    u.x * v.y - u.y * v.x
}

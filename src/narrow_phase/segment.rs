//! Segment–body contact: a finite line segment `a b` (a thin plate, both sides solid; see
//! [`Segment`]) against a circle, an ellipse or a convex polygon (a clump's members are
//! circles: [`super::clump`]).
//!
//! # Face or end
//! The body meets the side its centroid `c` is on ([`Segment::facing`]: the front when `c` lies
//! on the line). Its **deepest point** `d` towards that side — the point of the body that
//! reaches furthest across the line, its support point along the side's inward normal (a
//! circle's: below its centre; an ellipse's in closed form; a polygon's deepest vertex) — decides
//! what it touches:
//! - `τ(d) ∈ [0, L]` (it lies over the segment): the **face**. The contact is the half-plane
//!   wall's of that side's line, by the same kernel on the same numbers ([`super::circle_wall`],
//!   [`super::ellipse_wall`], [`super::polygon_wall`]): a body resting on a segment is, bit for
//!   bit, a body resting on the half-plane of its line. Its overlap area (the area law) and flat
//!   overlap are the half-plane's too: exact while the chord lies on the segment, and counting
//!   the part of the cut beyond the end when the chord runs past it (the body's deepest point
//!   still over the segment).
//! - otherwise the **end** on that side (`a` for `τ < 0`, `b` for `τ > L`), a point `E`: the
//!   depth is the distance from E to the body's boundary (positive with E inside the body), the
//!   normal the body's inward normal at its boundary point q closest to E (from E towards q
//!   when E is outside: for a circle the line of centres), the contact point E itself. A point
//!   has no overlap area (but a disk's, for cohesion: [`circle_end`]): under the area law a
//!   circle's end contact is a spring on this depth
//!   (for a disk that is the area law's own force); a polygon's is its least cut (below).
//!
//! An ellipse under the area law (`request.area`) takes its own rule instead, whose potential
//! is continuous from face to end ([`ellipse_area`]): the face while the face's chord midpoint
//! lies over the segment, else the end as the half-plane through it that cuts the least area.
//!
//! For a circle this is the segment's point closest to the centre — the disk's contact with the
//! segment as a closed set — and continuous as the disk rolls over an end. For an ellipse, at the
//! change from face to end the end lies straight above d at the face's depth, and d is its
//! closest boundary point while that depth is below the ellipse's radius of curvature there
//! (≥ b²/a): the depth, the normal and the spring's energy are continuous for any overlap a
//! DEM contact reaches.
//!
//! A polygon (a rectangle among them) takes its own rule ([`polygon`]). Under the area law, and a
//! flat-sided body (a rectangle: a Winkler foundation against a wall under either law) under
//! both ([`polygon_least_cut`]), it meets the face while the point where the face's force acts
//! (the chord midpoint; a rectangle's cut's centroid) lies over the segment, else the end as
//! the half-plane through it that cuts the least of the potential's measure off it — the area,
//! or a rectangle's Winkler energy ([`least_cut`]): conservative, and continuous from face to
//! end. A polygon under the depth law meets it along the axis of least penetration of the two
//! convex sets ([`polygon_depth`]): the face's (the deepest vertex's depth) or an edge's (the
//! depth of an end behind that edge's line): the depth is continuous from face to end, and an
//! end contact is the gradient of `½ k δ²`.
//!
//! The segment is i (the giver): the normal points from it into the body.

use super::local::{LocalFrame, pow2_floor};
use super::polygon_wall;
use super::record::{Contact, ContactState, Request, TOUCH_TOL};
use super::{circle_wall, ellipse_wall};
use crate::geometry::{Pose, Segment, Shape, Vec2, Wall};

/// Contact between a segment (i) and a body (j) that is not a clump.
#[inline]
pub fn contact_segment_body(
    seg: &Segment,
    shape: &Shape,
    pose: &Pose,
    request: &Request,
) -> Option<Contact> {
    let c = pose.position;
    let side = seg.facing(c);
    if let (Shape::Ellipse { a, b }, true) = (*shape, request.area) {
        return ellipse_area(seg, side, a, b, pose, request);
    }
    if let Shape::Rectangle { .. } | Shape::Polygon(_) = shape {
        return polygon(seg, side, shape, pose, request);
    }
    let deepest = deepest_point(shape, pose, side.normal);
    let tau = seg.along(deepest);
    if (0.0..=seg.length).contains(&tau) {
        return match *shape {
            Shape::Circle { r } => circle_wall::contact_wall_circle(side, r, pose, request),
            Shape::Ellipse { a, b } => {
                ellipse_wall::contact_wall_ellipse(side, a, b, pose, request)
            }
            Shape::Rectangle { .. } | Shape::Polygon(_) => {
                polygon_wall::contact_wall_polygon(side, shape, pose, request)
            }
            Shape::Clump(_) => unreachable!("a clump meets a segment through its members"),
        };
    }
    let end = if tau < 0.0 { seg.a } else { seg.b };
    contact_point_body(end, shape, pose, request)
}

/// The body's point that reaches furthest against `normal` (the support point along `−normal`).
#[inline]
pub fn deepest_point(shape: &Shape, pose: &Pose, normal: Vec2) -> Vec2 {
    let c = pose.position;
    match *shape {
        Shape::Circle { .. } => c,
        Shape::Ellipse { a, b } => {
            let u = pose.to_body_vector(-normal);
            let (ax, by) = (a * u.x, b * u.y);
            let s = ax.hypot(by);
            c + pose.to_world_vector(Vec2::new(a * ax / s, b * by / s))
        }
        Shape::Rectangle { .. } | Shape::Polygon(_) => {
            let mut corners = [Vec2::zeros(); 4];
            let u = pose.to_body_vector(normal);
            let v = shape
                .vertices(&mut corners)
                .iter()
                .copied()
                .min_by(|p, q| u.dot(p).total_cmp(&u.dot(q)))
                .unwrap_or(Vec2::zeros());
            c + pose.to_world_vector(v)
        }
        Shape::Clump(_) => c,
    }
}

/// Contact between the point `e` (i) and a body (j): the depth of `e` inside the body (negative
/// outside: `None` beyond the touching tolerance), the normal the body's inward normal at its
/// boundary point closest to `e`, the contact point `e`. No chord, no overlap area, but for a
/// disk ([`circle_end`]).
pub fn contact_point_body(
    e: Vec2,
    shape: &Shape,
    pose: &Pose,
    request: &Request,
) -> Option<Contact> {
    let _ = request;
    let scale = pow2_floor(shape.bounding_radius());
    let inv = 1.0 / scale;
    // The point in the body's frame, in units of `scale`.
    let p = pose.to_body_vector((e - pose.position) * inv);
    let (depth, n) = match *shape {
        Shape::Circle { r } => {
            let r = r * inv;
            let d = p.norm();
            let n = if d > 0.0 { -p / d } else { Vec2::new(0.0, 1.0) };
            (r - d, n)
        }
        Shape::Ellipse { a, b } => point_ellipse(a * inv, b * inv, p),
        Shape::Rectangle { .. } | Shape::Polygon(_) => {
            let mut corners = [Vec2::zeros(); 4];
            let v = shape.vertices(&mut corners);
            point_polygon(v, inv, p)
        }
        Shape::Clump(_) => unreachable!("a clump meets a point through its members"),
    };
    if depth < -TOUCH_TOL {
        return None;
    }
    let frame = LocalFrame::of(pose, scale);
    let state = if depth <= TOUCH_TOL {
        ContactState::Touching
    } else {
        ContactState::Overlap
    };
    let mut c = Contact {
        state,
        point: e,
        normal: frame.vector([n.x, n.y]),
        depth: depth * scale,
        half_chord: 0.0,
        area: None,
        flat: None,
    };
    // (Only cohesion reads them, and it asks for the chord: under the area law alone a disk's
    // end contact stays the spring on this depth, which its area potential is.)
    if let (Shape::Circle { r }, true) = (*shape, request.chord) {
        circle_end(&mut c, r, request);
    }
    Some(c)
}

/// A disk's contact with a segment's end E (`c`, of depth `δ = r − |p − E|`): the chord and
/// the overlap area of the cap that the half-plane through E normal to the contact's normal
/// cuts off it at that depth, `A = cap(r, δ)`, `ℓ = 2√(δ(2r − δ))`. The disk's distance to
/// the segment (a closed convex set) is continuously differentiable, the line's distance over
/// the face and `|p − E|` beyond it, so `A(r − dist)` is one C¹ potential over face and ends:
/// its gradient is `ℓ ∂δ/∂p = −ℓ n` (n from E towards the centre), the pull `c ℓ` on the line
/// of centres at E (no couple), and it equals the face's half-plane cap where the centre
/// projects on an end.
fn circle_end(c: &mut Contact, r: f64, request: &Request) {
    // (A touching disk, δ at rounding, takes its chord as against a half-plane, no area.)
    let depth = c.depth.max(0.0);
    let half = (depth * (2.0 * r - depth)).max(0.0).sqrt();
    c.half_chord = half;
    if request.area && c.state == ContactState::Overlap {
        c.area = Some(super::record::OverlapArea {
            area: crate::geometry::overlap_area::ellipse_cap_at_depth(r, r, [1.0, 0.0], depth),
            length: 2.0 * half,
            normal: c.normal,
            point: c.point,
            couple: 0.0,
        });
    }
}

/// The depth of the point `p` inside the ellipse `x²/a² + y²/b² = 1` (its distance to the
/// boundary; negative outside) and the ellipse's inward normal at the boundary point closest to
/// `p`, by Eberly's bisection ("Distance from a point to an ellipse", 2011): the closest point
/// `q = (a² p_x/(t + a²), b² p_y/(t + b²))` for the root t of
/// `(a p_x/(t + a²))² + (b p_y/(t + b²))² = 1` (t > 0 outside, t < 0 inside).
pub(crate) fn point_ellipse(a: f64, b: f64, p: Vec2) -> (f64, Vec2) {
    // In the first quadrant, the larger semi-axis first.
    let swap = a < b;
    let (e0, e1, y0, y1) = if swap {
        (b, a, p.y.abs(), p.x.abs())
    } else {
        (a, b, p.x.abs(), p.y.abs())
    };
    let (x0, x1) = closest_first_quadrant(e0, e1, y0, y1);
    let (qx, qy) = if swap { (x1, x0) } else { (x0, x1) };
    let q = Vec2::new(qx.copysign(p.x), qy.copysign(p.y));
    let inside = (p.x / a).powi(2) + (p.y / b).powi(2) < 1.0;
    let dist = (q - p).norm();
    // The outward normal at q: the gradient of x²/a² + y²/b².
    let g = Vec2::new(q.x / (a * a), q.y / (b * b));
    let n = -g / g.norm();
    (if inside { dist } else { -dist }, n)
}

/// Eberly's closest point of the ellipse with semi-axes `e0 ≥ e1` to `(y0, y1)`, both ≥ 0.
fn closest_first_quadrant(e0: f64, e1: f64, y0: f64, y1: f64) -> (f64, f64) {
    if y1 > 0.0 {
        if y0 > 0.0 {
            let (z0, z1) = (y0 / e0, y1 / e1);
            let g = z0 * z0 + z1 * z1 - 1.0;
            if g == 0.0 {
                return (y0, y1);
            }
            let r0 = (e0 / e1) * (e0 / e1);
            let s = root(r0, z0, z1, g);
            (r0 * y0 / (s + r0), y1 / (s + 1.0))
        } else {
            (0.0, e1)
        }
    } else {
        let (numer, denom) = (e0 * y0, e0 * e0 - e1 * e1);
        if numer < denom {
            let x = numer / denom;
            (e0 * x, e1 * (1.0 - x * x).max(0.0).sqrt())
        } else {
            (e0, 0.0)
        }
    }
}

/// The root of `(r0 z0/(s + r0))² + (z1/(s + 1))² = 1` by bisection to the last bit.
fn root(r0: f64, z0: f64, z1: f64, g: f64) -> f64 {
    let n0 = r0 * z0;
    let (mut s0, mut s1) = (z1 - 1.0, if g < 0.0 { 0.0 } else { n0.hypot(z1) - 1.0 });
    let mut s = 0.0;
    // (Each halving gains a bit; the loop ends when the midpoint rounds to an end.)
    for _ in 0..2200 {
        s = 0.5 * (s0 + s1);
        if s == s0 || s == s1 {
            break;
        }
        let (u, v) = (n0 / (s + r0), z1 / (s + 1.0));
        let g = u * u + v * v - 1.0;
        if g > 0.0 {
            s0 = s;
        } else if g < 0.0 {
            s1 = s;
        } else {
            break;
        }
    }
    s
}

/// The depth of the point `p` inside the convex polygon of vertices `v` (counter-clockwise,
/// scaled by `inv`) and its inward normal at the boundary point closest to `p`.
fn point_polygon(v: &[Vec2], inv: f64, p: Vec2) -> (f64, Vec2) {
    let k = v.len();
    // Inside: the nearest edge line. Outside: the nearest boundary point.
    let mut best_in = (f64::INFINITY, Vec2::zeros());
    let mut best_out = (f64::INFINITY, Vec2::zeros());
    let mut inside = true;
    for i in 0..k {
        let (a, b) = (v[i] * inv, v[(i + 1) % k] * inv);
        let e = b - a;
        let len = e.norm();
        let u = Vec2::new(e.y / len, -e.x / len); // outward
        let s = u.dot(&(p - a));
        if s > 0.0 {
            inside = false;
        }
        if -s < best_in.0 {
            best_in = (-s, -u);
        }
        let t = (e.dot(&(p - a)) / (len * len)).clamp(0.0, 1.0);
        let q = a + e * t;
        let d = (q - p).norm();
        if d < best_out.0 {
            let n = if d > 0.0 { (q - p) / d } else { -u };
            best_out = (d, n);
        }
    }
    if inside {
        best_in
    } else {
        (-best_out.0, best_out.1)
    }
}

/// An ellipse against a segment under the area law (`side` the line it meets): the face while
/// the midpoint of the chord the line cuts lies over the segment, else the end E on that side,
/// as the half-plane through E whose chord E bisects — the line through E that cuts the least
/// area off the ellipse, conjugate to the diameter through E (normal `∇(x²/a² + y²/b²)` at E,
/// in the body frame). By the envelope theorem the least cap's gradient is its chord's, at E:
/// the force `W′(A) L n` at E is the gradient of the potential `W(A_min)`. Where the face's
/// chord midpoint reaches the end, the bisected chord through the end is the face's own: the
/// area, the force and its point change continuously from face to end.
fn ellipse_area(
    seg: &Segment,
    side: &Wall,
    a: f64,
    b: f64,
    pose: &Pose,
    request: &Request,
) -> Option<Contact> {
    let face = ellipse_wall::contact_wall_ellipse(side, a, b, pose, request)?;
    let tau = seg.along(face.point);
    if (0.0..=seg.length).contains(&tau) {
        return Some(face);
    }
    let end = if tau < 0.0 { seg.a } else { seg.b };
    // (In units of the larger semi-axis, in the body frame.)
    let s = a.max(b);
    let p = pose.to_body_vector((end - pose.position) / s);
    let (ua, ub) = (a / s, b / s);
    let q = (p.x / ua).powi(2) + (p.y / ub).powi(2);
    if q >= 1.0 {
        // The end lies outside the ellipse, and so does the whole chord beyond it.
        return None;
    }
    let g = Vec2::new(p.x / (ua * ua), p.y / (ub * ub));
    // The half-plane's normal points into its free side, towards the centre (−∇Q; at the
    // centre itself, where every chord is bisected, the face's).
    let normal = if g.x == 0.0 && g.y == 0.0 {
        side.normal
    } else {
        -pose.to_world_vector(g)
    };
    let wall = Wall::new(end, normal)?;
    ellipse_wall::contact_wall_ellipse(&wall, a, b, pose, request)
}

/// A polygon (a rectangle among them) against a segment (`side` the line it meets). Under the
/// area law, and for a flat-sided body (a rectangle, a Winkler foundation against a wall under
/// either law) under both, [`polygon_least_cut`]. A polygon under the depth law meets the
/// segment along the axis of least penetration of the two as convex sets (the separating-axis
/// depth, [`polygon_depth`]).
fn polygon(
    seg: &Segment,
    side: &Wall,
    shape: &Shape,
    pose: &Pose,
    request: &Request,
) -> Option<Contact> {
    if request.area || shape.is_flat_sided() {
        return polygon_least_cut(seg, side, shape, pose, request);
    }
    polygon_depth(seg, side, shape, pose, request)
}

/// A polygon against a segment under the depth law: the least translation that parts them (the
/// penetration depth of two convex sets, by the separating-axis theorem). The Minkowski
/// difference of the polygon and the segment has the polygon's edges and the segment's line
/// for its edges, so the depth is the least over those normals of the overlap along them:
/// - the side's normal n: the deepest vertex's depth below the line, the **face** — the
///   half-plane's contact, bit for bit;
/// - an edge's outward normal m: `o − min(m·a, m·b)` (o the edge's offset), the depth of the
///   segment's end furthest behind that edge's line, the **end** E: the polygon is pushed
///   along −m, the force acts at E. This is the gradient of `½k δ²` with δ = `o − m·E`
///   (turning the edge about the centroid turns m, and the two terms cancel to E's lever).
///
/// The least of these is continuous in the pose: the contact changes from face to end where
/// the two depths are equal, and an end's depth is E's distance to the edge the polygon would
/// leave it by. (P's law on the face, the spring at the chord midpoint, is not the gradient of a
/// potential on a half-plane either.) `None` where an axis parts them by more than the touching
/// tolerance.
fn polygon_depth(
    seg: &Segment,
    side: &Wall,
    shape: &Shape,
    pose: &Pose,
    request: &Request,
) -> Option<Contact> {
    let face = polygon_wall::contact_wall_polygon(side, shape, pose, request)?;
    let scale = pow2_floor(shape.bounding_radius());
    let inv = 1.0 / scale;
    let mut corners = [Vec2::zeros(); 4];
    let v = shape.vertices(&mut corners);
    let k = v.len();
    // The ends in the body's frame, in units of `scale`.
    let ends = [seg.a, seg.b].map(|e| pose.to_body_vector((e - pose.position) * inv));
    // The edge of least overlap: (overlap, outward normal, which end).
    let mut best = (f64::INFINITY, Vec2::zeros(), 0);
    for i in 0..k {
        let (p, q) = (v[i] * inv, v[(i + 1) % k] * inv);
        let e = q - p;
        let m = Vec2::new(e.y, -e.x) / e.norm(); // outward (counter-clockwise vertices)
        let behind = ends.map(|x| m.dot(&(p - x)));
        let (overlap, end) = if behind[0] >= behind[1] {
            (behind[0], 0)
        } else {
            (behind[1], 1)
        };
        if overlap < best.0 {
            best = (overlap, m, end);
        }
    }
    let (overlap, m, end) = best;
    if overlap < -TOUCH_TOL {
        // An edge's line parts the polygon from the whole segment.
        return None;
    }
    // An edge parallel to the segment (m = −n) is the face: its overlap is the face's depth
    // but for rounding, at most a few units of the last place of the ends' coordinates.
    let margin = 1e-12 * (1.0 + ends[0].norm().max(ends[1].norm()));
    if face.depth <= (overlap + margin) * scale {
        return Some(face);
    }
    let state = if overlap <= TOUCH_TOL {
        ContactState::Touching
    } else {
        ContactState::Overlap
    };
    let frame = LocalFrame::of(pose, scale);
    Some(Contact {
        state,
        point: if end == 0 { seg.a } else { seg.b },
        normal: frame.vector([-m.x, -m.y]),
        depth: overlap * scale,
        half_chord: 0.0,
        area: None,
        flat: None,
    })
}

/// A polygon (a rectangle among them) against a segment under the area law, or a flat-sided body
/// under either (`side` the line it meets), continuous in its potential from face to end, as [`ellipse_area`] is for an ellipse.
/// Its potential against a half-plane is a function of the cut the line makes: `W(A)` of the
/// cut's area A for a polygon, the Winkler foundation's energy `k′M`, M the cut's first moment
/// about the line (`k′Aȳ`), for a flat-sided body (a rectangle; see `contact_law::overlap`).
/// The face while the point where the face's resultant acts — the chord's midpoint, a flat-sided
/// body's cut's centroid — lies over the segment: the half-plane's contact, the whole cut; else
/// the end E on that side, as the half-plane through E whose cut has the least of that measure
/// ([`least_cut`]). By the envelope theorem that least cut's gradient is its own line's (the
/// line held fixed): the half-plane's force through E is the gradient of `W(A_min)` (`k′M_min`),
/// so the end contact is conservative. At the least area E bisects the chord, so the area law's
/// force `W′(A) L n` acts at E; at the least moment the cut's centroid lies on the normal
/// through E, so the Winkler resultant `k′A` passes through E. Where the face's point reaches
/// the end, the face's own line is that least cut's (its derivative in the line's angle is zero
/// there): the potential, the force and its point are continuous from face to end.
fn polygon_least_cut(
    seg: &Segment,
    side: &Wall,
    shape: &Shape,
    pose: &Pose,
    request: &Request,
) -> Option<Contact> {
    let face = polygon_wall::contact_wall_polygon(side, shape, pose, request)?;
    let flat = shape.is_flat_sided();
    // Where the face's resultant acts.
    let at = match face.flat {
        Some(f) if face.state == ContactState::Overlap => f.centroid,
        _ => face.point,
    };
    let tau = seg.along(at);
    if (0.0..=seg.length).contains(&tau) {
        return Some(face);
    }
    let end = if tau < 0.0 { seg.a } else { seg.b };
    let normal = least_cut(end, shape, pose, flat)?;
    let wall = Wall::new(end, normal)?;
    polygon_wall::contact_wall_polygon(&wall, shape, pose, request)
}

/// The half-plane through the point `e` whose cut off the convex polygon `shape` (at `pose`)
/// is least — by area, or for a flat-sided body (`moment`) by its first moment about the line
/// (the Winkler foundation's energy over k′) — as the normal of its free side (world
/// coordinates); `None` when `e` does not lie inside the polygon (every line through it then
/// cuts nothing).
///
/// The cut of the line through e along `d = (cos θ, sin θ)` is the part of the polygon on the
/// side `u·(x − e) < 0`, `u = (−sin θ, cos θ)` (u the contact normal). Turning the line by dθ
/// about e sweeps the strip `t dθ` along its chord (t the place along d from e), so
/// - the area's derivative is `dA/dθ = ∫ t dt = (r₁² − r₂²)/2` over the chord, `r₁`, `r₂` the
///   distances from e to the chord's ends: it vanishes where e bisects the chord — the
///   classical characterisation of the least-area chords through a point of a convex region
///   (H. G. Eggleston, *Problems in Euclidean Space: Application of Convexity*, Pergamon 1957,
///   ch. 2; Yaglom & Boltyanskii, *Convex Figures*, 1961, problem 4-7: of the lines through a
///   point of a convex figure, the one cutting off the least area is bisected by it);
/// - the first moment `M = ∫ (−u·(x − e)) dA` (the depth vanishes on the chord) has
///   `dM/dθ = ∫ t dA = A t_c`, zero where the cut's centroid lies on the normal through e.
///
/// Both are C¹ in θ; their least value over the whole turn is found by sampling θ, then by
/// bisection on the derivative's sign about each sampled local least, to the last bit.
fn least_cut(e: Vec2, shape: &Shape, pose: &Pose, moment: bool) -> Option<Vec2> {
    let scale = pow2_floor(shape.bounding_radius());
    let inv = 1.0 / scale;
    let mut corners = [Vec2::zeros(); 4];
    // The vertices about e, in the body frame, in units of `scale`.
    let p = pose.to_body_vector((e - pose.position) * inv);
    let w: super::small::List<Vec2> = shape
        .vertices(&mut corners)
        .iter()
        .map(|v| v * inv - p)
        .collect();
    let k = w.len();
    // e inside: on the inner side of every edge (counter-clockwise).
    if (0..k).any(|i| w[i].perp(&w[(i + 1) % k]) <= 0.0) {
        return None;
    }
    // The cut's measure and its derivative in θ.
    let eval = |theta: f64| -> (f64, f64) {
        let (sn, cs) = theta.sin_cos();
        let (d, u) = (Vec2::new(cs, sn), Vec2::new(-sn, cs));
        let (mut area2, mut first, mut chord) = (0.0, Vec2::zeros(), [0.0f64; 2]);
        let mut nc = 0;
        // The cut as a fan from e (on its chord): the shoelace sum and the first moments of
        // its triangles (e, x, y).
        let mut prev: Option<Vec2> = None;
        let mut first_point: Option<Vec2> = None;
        let mut push = |x: Vec2| {
            if let Some(q) = prev {
                let c = q.perp(&x);
                area2 += c;
                first += (q + x) * c;
            } else {
                first_point = Some(x);
            }
            prev = Some(x);
        };
        for i in 0..k {
            let (a, b) = (w[i], w[(i + 1) % k]);
            let (sa, sb) = (u.dot(&a), u.dot(&b));
            if sa < 0.0 {
                push(a);
            }
            if (sa < 0.0) != (sb < 0.0) {
                let x = a + (b - a) * (sa / (sa - sb));
                if nc < 2 {
                    chord[nc] = d.dot(&x);
                }
                nc += 1;
                push(x);
            }
        }
        if let (Some(q), Some(x)) = (prev, first_point) {
            let c = q.perp(&x);
            area2 += c;
            first += (q + x) * c;
        }
        // Area A = area2/2, first moment about e ∫x dA = first/6.
        let area = 0.5 * area2;
        let m = first / 6.0;
        if moment {
            // M = −u·∫x dA; dM/dθ = d·∫x dA.
            (-u.dot(&m), d.dot(&m))
        } else {
            let (t1, t2) = (chord[0], chord[1]);
            // (The chord's ends lie on either side of e: their squares' difference, halved,
            // with the sign of the end ahead along d.)
            let (ahead, behind) = if t1 > t2 { (t1, t2) } else { (t2, t1) };
            (area, 0.5 * (ahead * ahead - behind * behind))
        }
    };
    const N: usize = 64;
    let step = std::f64::consts::TAU / N as f64;
    let samples: [f64; N] = std::array::from_fn(|i| eval(step * i as f64).0);
    let mut best = (f64::INFINITY, 0.0);
    for i in 0..N {
        let f = samples[i];
        if f > samples[(i + N - 1) % N] || f > samples[(i + 1) % N] {
            continue;
        }
        // A sampled local least: bisect on the derivative's sign between its neighbours.
        let (mut lo, mut hi) = (step * (i as f64 - 1.0), step * (i as f64 + 1.0));
        let mut theta = step * i as f64;
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if eval(mid).1 > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
            theta = mid;
        }
        let (g, _) = eval(theta);
        let (f, theta) = if g <= f {
            (g, theta)
        } else {
            (f, step * i as f64)
        };
        if f < best.0 {
            best = (f, theta);
        }
    }
    let (sn, cs) = best.1.sin_cos();
    Some(pose.to_world_vector(Vec2::new(-sn, cs)))
}

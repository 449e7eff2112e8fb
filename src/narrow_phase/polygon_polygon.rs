//! Polygon–polygon contact (rectangles among them, each as its four corners) by convex
//! clipping, in a frame centred on i.
//!
//! The overlap of two convex polygons is a convex polygon: j is clipped by i's edge lines
//! (Sutherland & Hodgman 1974), every edge of the result carrying the label of the body edge it
//! lies on — an edge of j that survived, or a piece of i's clipping line. Its area (shoelace) is
//! the exact overlap area, and the boundary crossings are the vertices where the labels change
//! from i to j: each is a clipped point, computed once from the two edges that meet there. A
//! run of edges where j's edge lies on i's (collinear faces, labelled both) counts as one
//! crossing at its midpoint, so two aligned stacked squares get the chord across the middle of
//! their overlap, the normal along the stack and the depth exactly.
//!
//! Separation and the touching depth come from the separating-axis test over both polygons'
//! edge normals (exact for convex polygons); the depth of any normal from the support
//! functions, `δ(n) = h_i(n) + h_j(−n)`.
//!
//! The gradient of the area for j's rigid motion is exact for any number of crossings: the
//! integral of j's outward normal over the part of its boundary inside i, i.e. the sum of
//! `L_e u_e` over the overlap's edges on j (halved on shared edges, where the one-sided
//! derivatives differ).

use super::local::{LocalFrame, LocalOverlap, deep_fallback, orient, pow2_floor};
use super::record::{Contact, ContactState, Request, TOUCH_TOL};
use super::small::List;
use crate::geometry::overlap_area::polygon_area;
use crate::geometry::{Pose, Shape, Vec2};

/// Which body's boundary an edge of the overlap lies on.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
enum Side {
    #[default]
    I,
    J,
    Both,
}

/// The label a clipped edge carries while clipping: the body edge it lies on, or the line
/// outside i that first cuts j down (which never survives i's faces).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
enum Label {
    I(usize),
    J(usize),
    #[default]
    Outside,
}

/// Contact between convex polygons i and j (polygons, or rectangles as their corners:
/// [`Shape::vertices`]); with `request.area`, the overlap area (the clipped polygon's, exactly)
/// and its gradient too; for two flat-sided bodies ([`Shape::is_flat_sided`]: rectangles), the
/// [`FlatOverlap`](super::FlatOverlap) of a two-crossing overlap.
pub fn contact_polygon_polygon(
    side_i: &Shape,
    pi: &Pose,
    side_j: &Shape,
    pj: &Pose,
    request: &Request,
) -> Option<Contact> {
    let flat = side_i.is_flat_sided() && side_j.is_flat_sided();
    let (mut corners_i, mut corners_j) = ([Vec2::zeros(); 4], [Vec2::zeros(); 4]);
    let (vi, bound_i) = (side_i.vertices(&mut corners_i), side_i.bounding_radius());
    let (vj, bound_j) = (side_j.vertices(&mut corners_j), side_j.bounding_radius());
    let area = request.area;
    let dv = pj.position - pi.position;
    if dv.norm_squared() > (bound_i + bound_j) * (bound_i + bound_j) {
        return None;
    }
    let scale = pow2_floor(bound_i.max(bound_j));
    let inv = 1.0 / scale;
    let c = pi.to_body_vector(dv) * inv; // j's centroid in i's frame
    let (ci, si) = pi.cos_sin();
    let (cj, sj) = pj.cos_sin();
    let (cr, sr) = (cj * ci + sj * si, sj * ci - cj * si); // j's axis in i's frame
    let qi: List<[f64; 2]> = vi.iter().map(|v| [v.x * inv, v.y * inv]).collect();
    // j's vertices relative to its centroid (rotated into i's frame), and placed.
    let rj: List<[f64; 2]> = vj
        .iter()
        .map(|v| {
            let (x, y) = (v.x * inv, v.y * inv);
            [cr * x - sr * y, sr * x + cr * y]
        })
        .collect();
    let qj: List<[f64; 2]> = rj.iter().map(|p| [c.x + p[0], c.y + p[1]]).collect();
    let (ni, nj) = (qi.len(), qj.len());
    let dot = |u: [f64; 2], p: [f64; 2]| u[0] * p[0] + u[1] * p[1];
    let max_dot = |u: [f64; 2], ps: &[[f64; 2]]| {
        ps.iter()
            .map(|&p| dot(u, p))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    // δ(n) = h_i(n) + h_j(−n), j's support about its centroid (the offset n·c apart).
    let depth = |n: [f64; 2]| max_dot(n, &qi) + max_dot([-n[0], -n[1]], &rj) - dot(n, [c.x, c.y]);
    // Face normals: i's as stored (its frame is the local one), j's turned into it.
    let ui: List<[f64; 2]> = side_i.edge_normals().iter().map(|u| [u.x, u.y]).collect();
    let uj: List<[f64; 2]> = side_j
        .edge_normals()
        .iter()
        .map(|u| [cr * u.x - sr * u.y, sr * u.x + cr * u.y])
        .collect();
    let di: List<f64> = (0..ni).map(|k| dot(ui[k], qi[k])).collect();
    // Separating axes: i's outward face normals (n = u) and j's (n = −u). Along i's face k the
    // depth is `d_k + h_j(−u_k) − u_k·c` (i's support along its own face normal is the face's
    // offset), along j's face `h_i(u_k) + e_k + u_k·c` likewise; the other body's support is
    // found by walking its vertices forward from the last axis's (the axes turn
    // counter-clockwise, and so does a convex polygon's support point): O(n_i + n_j) for all
    // axes rather than O((n_i + n_j)²).
    let mut sat = (f64::INFINITY, [1.0, 0.0]);
    let mut kj = argmax(&rj, [-ui[0][0], -ui[0][1]]);
    for (k, &u) in ui.iter().enumerate() {
        let (next, hj) = walk(&rj, [-u[0], -u[1]], kj);
        kj = next;
        let dpt = di[k] + hj - dot(u, [c.x, c.y]);
        if dpt < sat.0 {
            sat = (dpt, u);
        }
    }
    let mut ki = argmax(&qi, [-uj[0][0], -uj[0][1]]);
    for (k, &u) in uj.iter().enumerate() {
        let (next, hi) = walk(&qi, [-u[0], -u[1]], ki);
        ki = next;
        let dpt = hi + dot(u, rj[k]) + dot(u, [c.x, c.y]);
        if dpt < sat.0 {
            sat = (dpt, [-u[0], -u[1]]);
        }
    }
    let tol = TOUCH_TOL;
    if sat.0 < -tol {
        return None;
    }
    let frame = LocalFrame::of(pi, scale);
    // Only i's faces that j reaches past clip anything: the others' half-planes hold all of j
    // (and so every point clipping makes on j's edges). Which they are follows from j's support
    // along each face normal, walked as above; a margin keeps a face whose line j touches to
    // within rounding among the clipping ones.
    let mut active: List<bool> = (0..ni).map(|_| false).collect();
    let mut kj = argmax(&qj, ui[0]);
    for (k, &u) in ui.iter().enumerate() {
        let (next, h) = walk(&qj, u, kj);
        kj = next;
        active[k] = h > di[k] - 1e-12;
    }
    // The overlap lies in i, so on i's side of i's support line along the least-penetration
    // normal; j is cut there first (the line moved out by 1e-9 of the size, so that it lies
    // strictly outside i and none of it survives i's faces): of a many-sided j only the few
    // vertices within the overlap's depth of its extreme remain for the faces of i to clip.
    let slab = (sat.1, max_dot(sat.1, &qi) + 1e-9);
    let poly = clip(&qj, slab, &ui, &di, &active);
    // The face normals give the exact penetration depth of two convex polygons, so "touching"
    // is decided by it (an area test would scale with the square of a vertex's penetration).
    if poly.len() < 3 || sat.0 <= tol {
        let p = mean(&poly).unwrap_or([0.5 * c.x, 0.5 * c.y]);
        return Some(frame.contact(ContactState::Touching, p, p, p, sat.1, sat.0, request));
    }
    // j's edge k lies on i's edge line m (same outward normal, same offset): asked only of the
    // overlap's edges.
    let twins = |m: usize, k: usize| {
        dot(ui[m], uj[k]) >= 1.0 - 1e-12 && (dot(ui[m], qj[k]) - di[m]).abs() <= tol
    };
    let mut edges: List<Edge> = List::new();
    for k in 0..poly.len() {
        let (p, l) = poly[k];
        let q = poly[(k + 1) % poly.len()].0;
        if (q[0] - p[0]).abs() <= tol && (q[1] - p[1]).abs() <= tol {
            continue;
        }
        let (side, i_side, j_side) = match l {
            Label::I(m) => match (0..nj).find(|&kj| twins(m, kj)) {
                Some(kj) => (Side::Both, Some(m), Some(kj)),
                None => (Side::I, Some(m), None),
            },
            Label::J(kj) => match (0..ni).find(|&m| twins(m, kj)) {
                Some(m) => (Side::Both, Some(m), Some(kj)),
                None => (Side::J, None, Some(kj)),
            },
            // Outside i by construction: were a piece to survive (it cannot), it would lie on
            // i's boundary.
            Label::Outside => (Side::I, None, None),
        };
        edges.push(Edge {
            p,
            q,
            side,
            i_side,
            j_side,
        });
    }
    let has_i = edges.iter().any(|e| e.side == Side::I);
    let has_j = edges.iter().any(|e| e.side == Side::J);
    if !(has_i && has_j) {
        // The overlap is one polygon entirely: it lies inside the other.
        let inner = if has_j || !has_i {
            [c.x, c.y]
        } else {
            [0.0, 0.0]
        };
        let toward = if c.x == 0.0 && c.y == 0.0 {
            [1.0, 0.0]
        } else {
            [c.x, c.y]
        };
        let l = toward[0].hypot(toward[1]);
        let (n, dpt) = orient([toward[0] / l, toward[1] / l], depth);
        // No overlap area: it no longer changes, and the contact falls back to the spring on
        // the depth (as every pair kind's containment does).
        return Some(frame.contained(inner, n, dpt, request));
    }
    // Walk once around, starting on a non-shared edge; a change between I and J is a crossing,
    // at the midpoint of the shared run between them (the common vertex when there is none).
    let ne = edges.len();
    let start = edges
        .iter()
        .position(|e| e.side != Side::Both)
        .expect("has I and J edges");
    let mut cross: List<Cross> = List::new();
    let mut last = edges[start];
    let mut run: List<usize> = List::new();
    for step in 1..=ne {
        let k = (start + step) % ne;
        let e = edges[k];
        if e.side == Side::Both {
            run.push(k);
            continue;
        }
        if e.side != last.side {
            cross.push(if run.is_empty() {
                let (ei, ej) = if e.side == Side::I {
                    (e, last)
                } else {
                    (last, e)
                };
                Cross {
                    point: e.p,
                    i_side: ei.i_side,
                    j_side: ej.j_side,
                }
            } else {
                let r = edges[run[0]];
                Cross {
                    point: run_midpoint(&edges, &run),
                    i_side: r.i_side,
                    j_side: r.j_side,
                }
            });
        }
        last = e;
        run.clear();
    }
    match cross.len() {
        2 => {
            let (a, b) = (cross[0], cross[1]);
            // A chord along one face takes that face's normal exactly.
            let nrm = match (a.i_side, b.i_side, a.j_side, b.j_side) {
                (Some(x), Some(y), _, _) if x == y => ui[x],
                (_, _, Some(x), Some(y)) if x == y => uj[x],
                _ => {
                    let d = [b.point[0] - a.point[0], b.point[1] - a.point[1]];
                    let len = d[0].hypot(d[1]);
                    [-d[1] / len, d[0] / len]
                }
            };
            let (n, dpt) = orient(nrm, depth);
            let mid = super::local::midpoint(a.point, b.point);
            let mut g = frame.contact(
                ContactState::Overlap,
                a.point,
                b.point,
                mid,
                n,
                dpt,
                request,
            );
            if area || flat {
                let pts: List<[f64; 2]> = poly.iter().map(|p| p.0).collect();
                if flat {
                    g.flat = Some(frame.flat(&pts));
                }
                if area {
                    let a_poly = polygon_area(&pts);
                    g.area = Some(frame.overlap(&LocalOverlap::chord(a_poly, a.point, b.point, n)));
                }
            }
            Some(g)
        }
        nc => {
            let mut pts: List<[f64; 2]> = cross.iter().map(|c| c.point).collect();
            if pts.len() < 2 {
                pts.push(pts.first().copied().unwrap_or([0.5 * c.x, 0.5 * c.y]));
            }
            let (p, q, n, dpt) = deep_fallback(&mut pts, depth);
            let mid = super::local::midpoint(p, q);
            let mut g = frame.contact(ContactState::Deep, p, q, mid, n, dpt, request);
            if area && nc >= 2 {
                let m = pts
                    .iter()
                    .fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
                let centre = [m[0] / nc as f64, m[1] / nc as f64];
                g.area = Some(frame.overlap(&gradient(&edges, [c.x, c.y], centre)));
            }
            Some(g)
        }
    }
}

/// The overlap's area and its exact gradient for j's rigid motion (see the module
/// documentation), acting at `centre`; `c_j` is j's centroid.
fn gradient(edges: &[Edge], c_j: [f64; 2], centre: [f64; 2]) -> LocalOverlap {
    let mut pts: List<[f64; 2]> = edges.iter().map(|e| e.p).collect();
    if pts.is_empty() {
        pts.push(centre);
    }
    let area = polygon_area(&pts);
    let (mut grad, mut turn) = ([0.0f64; 2], 0.0);
    for e in edges {
        let w = match e.side {
            Side::J => 1.0,
            Side::Both => 0.5,
            Side::I => continue,
        };
        // L u with u the outward normal of a counter-clockwise edge: (e_y, −e_x).
        let lu = [w * (e.q[1] - e.p[1]), -w * (e.q[0] - e.p[0])];
        let m = super::local::midpoint(e.p, e.q);
        grad[0] += lu[0];
        grad[1] += lu[1];
        turn += (m[0] - c_j[0]) * lu[1] - (m[1] - c_j[1]) * lu[0];
    }
    let lever = (centre[0] - c_j[0]) * grad[1] - (centre[1] - c_j[1]) * grad[0];
    LocalOverlap {
        area,
        grad,
        point: centre,
        couple: -(turn - lever),
        chord: None,
    }
}

/// An edge of the intersection polygon and the sides of i and of j it lies on.
#[derive(Clone, Copy, Debug, Default)]
struct Edge {
    p: [f64; 2],
    q: [f64; 2],
    side: Side,
    i_side: Option<usize>,
    j_side: Option<usize>,
}

/// A boundary crossing and the sides of i and j it lies on.
#[derive(Clone, Copy, Debug, Default)]
struct Cross {
    point: [f64; 2],
    i_side: Option<usize>,
    j_side: Option<usize>,
}

/// The index of the point of `pts` farthest along `u`.
fn argmax(pts: &[[f64; 2]], u: [f64; 2]) -> usize {
    let mut best = (0, f64::NEG_INFINITY);
    for (k, p) in pts.iter().enumerate() {
        let v = u[0] * p[0] + u[1] * p[1];
        if v > best.1 {
            best = (k, v);
        }
    }
    best.0
}

/// The support of the convex polygon `pts` (counter-clockwise) along `u`, walking forward from
/// vertex `start` while `u·p` grows: `(index, u·p)`. Exact when `start` is the support of a
/// direction at most a half turn clockwise of `u` (the walk of [`contact_polygon_polygon`]'s
/// separating axes); a rounding-level plateau may stop it a vertex early, which changes the
/// value by rounding only.
fn walk(pts: &[[f64; 2]], u: [f64; 2], start: usize) -> (usize, f64) {
    let n = pts.len();
    let at = |k: usize| u[0] * pts[k][0] + u[1] * pts[k][1];
    let (mut k, mut best) = (start, at(start));
    for _ in 0..n {
        let next = if k + 1 == n { 0 } else { k + 1 };
        let v = at(next);
        if v > best {
            (k, best) = (next, v);
        } else {
            break;
        }
    }
    (k, best)
}

/// The point halfway (by length) along a chain of consecutive edges.
fn run_midpoint(edges: &[Edge], run: &[usize]) -> [f64; 2] {
    let len = |e: &Edge| (e.q[0] - e.p[0]).hypot(e.q[1] - e.p[1]);
    let total: f64 = run.iter().map(|&k| len(&edges[k])).sum();
    let mut left = 0.5 * total;
    for &k in run {
        let e = &edges[k];
        let l = len(e);
        if left <= l {
            let t = left / l;
            return [
                e.p[0] + t * (e.q[0] - e.p[0]),
                e.p[1] + t * (e.q[1] - e.p[1]),
            ];
        }
        left -= l;
    }
    edges[*run.last().expect("non-empty run")].q
}

/// Sutherland–Hodgman clipping of convex polygon `qj` (counter-clockwise) by the edge lines of
/// convex polygon i (outward normals `u`, offsets `d`: inside where `u·p ≤ d`) marked `active`
/// (the others would keep every point). Each vertex carries the label of the edge leaving it.
fn clip(
    qj: &[[f64; 2]],
    slab: ([f64; 2], f64),
    u: &[[f64; 2]],
    d: &[f64],
    active: &[bool],
) -> List<([f64; 2], Label)> {
    let mut buf: List<([f64; 2], Label)> = qj
        .iter()
        .enumerate()
        .map(|(k, &p)| (p, Label::J(k)))
        .collect();
    let mut out = List::new();
    // The slab's line first (labelled `Outside`: it lies outside i), then i's active faces.
    let planes = std::iter::once((slab.0, slab.1, Label::Outside)).chain(
        (0..u.len())
            .filter(|&m| active[m])
            .map(|m| (u[m], d[m], Label::I(m))),
    );
    for (um, dm, lm) in planes {
        out.clear();
        let len = buf.len();
        for k in 0..len {
            let ((p, l), (q, _)) = (buf[k], buf[(k + 1) % len]);
            let dp = um[0] * p[0] + um[1] * p[1] - dm;
            let dq = um[0] * q[0] + um[1] * q[1] - dm;
            let x = || {
                let t = dp / (dp - dq);
                [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
            };
            if dp <= 0.0 {
                if dq > 0.0 {
                    // Leaving: along this edge to the line, then along the line.
                    if dp < 0.0 {
                        out.push((p, l));
                        out.push((x(), lm));
                    } else {
                        out.push((p, lm));
                    }
                } else {
                    out.push((p, l));
                }
            } else if dq < 0.0 {
                // Entering: from the line's point on along this edge.
                out.push((x(), l));
            }
        }
        std::mem::swap(&mut buf, &mut out);
        if buf.is_empty() {
            break;
        }
    }
    buf
}

fn mean(poly: &[([f64; 2], Label)]) -> Option<[f64; 2]> {
    if poly.is_empty() {
        return None;
    }
    let n = poly.len() as f64;
    Some([
        poly.iter().map(|p| p.0[0]).sum::<f64>() / n,
        poly.iter().map(|p| p.0[1]).sum::<f64>() / n,
    ])
}

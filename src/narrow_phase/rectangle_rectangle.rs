//! Rectangle–rectangle contact by edge clipping.
//!
//! In i's frame, rectangle j is clipped by i's four side lines (Sutherland–Hodgman); every edge of
//! the intersection polygon lies on i's boundary, on j's, or on both (collinear edges). The
//! boundary crossings are where the polygon's boundary passes from i's boundary to j's; a run of
//! shared (collinear) edges between the two counts as one crossing at its midpoint, so two equal
//! aligned squares stacked with overlap δ get the chord across the middle of the overlap, the
//! normal along the stack and `δ` exactly.

use super::rectangle_wall::corners;
use super::{
    Contact, ContactState, LocalFrame, LocalOverlap, Request, TOUCH_TOL, deep_fallback,
    deep_overlap, orient, pow2_floor,
};
use crate::geometry::overlap_area::{polygon_area, polygon_cap};
use crate::geometry::support::support_local;
use crate::geometry::{Pose, Shape};

/// Room for the clipped polygon (at most 8 vertices) plus the transient one of a clipping pass.
const MAX_POLY: usize = 10;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Side {
    I,
    J,
    Both,
}

/// Contact between rectangle i (`wi × hi`) and rectangle j (`wj × hj`); with `request.area`,
/// the overlap area (the clipped polygon's, exactly) and its gradient too.
pub fn contact_rectangle_rectangle(
    wi: f64,
    hi: f64,
    pi: &Pose,
    wj: f64,
    hj: f64,
    pj: &Pose,
    request: &Request,
) -> Contact {
    let area = request.area;
    let dv = pj.position - pi.position;
    let (ri, rj) = (0.5 * wi.hypot(hi), 0.5 * wj.hypot(hj));
    if dv.norm_squared() > (ri + rj) * (ri + rj) {
        return Contact::SEPARATED;
    }
    let scale = pow2_floor(ri.max(rj));
    let inv = 1.0 / scale;
    let (wi, hi, wj, hj) = (wi * inv, hi * inv, wj * inv, hj * inv);
    let c = pi.to_body_vector(dv) * inv; // j's centre in i's frame
    let (ci, si) = pi.cos_sin();
    let (cj, sj) = pj.cos_sin();
    let (cr, sr) = (cj * ci + sj * si, sj * ci - cj * si); // j's axis in i's frame
    let shape_i = Shape::Rectangle { w: wi, h: hi };
    let shape_j = Shape::Rectangle { w: wj, h: hj };
    let depth_j_support =
        |n: [f64; 2]| support_local(&shape_j, cr * n[0] + sr * n[1], -sr * n[0] + cr * n[1]);
    let depth = |n: [f64; 2]| {
        support_local(&shape_i, n[0], n[1]) + depth_j_support(n) - n[0] * c.x - n[1] * c.y
    };
    // Separating axes: the four face normals decide separation of two rectangles exactly.
    let axes = [[1.0, 0.0], [0.0, 1.0], [cr, sr], [-sr, cr]];
    let mut sat = (f64::INFINITY, [1.0, 0.0]);
    for ax in axes {
        let (n, dpt) = orient(ax, depth);
        if dpt < sat.0 {
            sat = (dpt, n);
        }
    }
    let tol = TOUCH_TOL;
    if sat.0 < -tol {
        return Contact::SEPARATED;
    }
    let frame = LocalFrame {
        origin: pi.position,
        cos: ci,
        sin: si,
        scale,
    };
    let qj = corners(wj, hj).map(|p| [c.x + cr * p[0] - sr * p[1], c.y + sr * p[0] + cr * p[1]]);
    let (poly, len) = clip_to_box(&qj, 0.5 * wi, 0.5 * hi);
    let poly = &poly[..len];
    // The face normals give the exact penetration depth of two convex polygons, so "touching"
    // is decided by it (an area test would scale with the square of a corner's penetration).
    if len < 3 || sat.0 <= tol {
        // Touching along an edge or at a corner: the face normal of least penetration.
        let p = mean(poly).unwrap_or([0.5 * c.x, 0.5 * c.y]);
        return Contact {
            state: ContactState::Touching,
            geometry: Some(frame.geometry(p, p, p, sat.1, sat.0)),
        };
    }
    let on_i = |p: [f64; 2], side: usize| match side {
        0 => (p[0] - 0.5 * wi).abs() <= tol,
        1 => (p[1] - 0.5 * hi).abs() <= tol,
        2 => (p[0] + 0.5 * wi).abs() <= tol,
        _ => (p[1] + 0.5 * hi).abs() <= tol,
    };
    let to_j = |p: [f64; 2]| {
        let (x, y) = (p[0] - c.x, p[1] - c.y);
        [cr * x + sr * y, -sr * x + cr * y]
    };
    let on_j = |p: [f64; 2], side: usize| {
        let l = to_j(p);
        match side {
            0 => (l[0] - 0.5 * wj).abs() <= tol,
            1 => (l[1] - 0.5 * hj).abs() <= tol,
            2 => (l[0] + 0.5 * wj).abs() <= tol,
            _ => (l[1] + 0.5 * hj).abs() <= tol,
        }
    };
    // Label every (non-degenerate) edge of the intersection polygon with the sides it lies on.
    let mut edges = [Edge::default(); MAX_POLY];
    let mut ne = 0;
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        if (q[0] - p[0]).abs() <= tol && (q[1] - p[1]).abs() <= tol {
            continue;
        }
        let i_side = (0..4).find(|&s| on_i(p, s) && on_i(q, s));
        let j_side = (0..4).find(|&s| on_j(p, s) && on_j(q, s));
        let side = match (i_side, j_side) {
            (Some(_), Some(_)) => Side::Both,
            (Some(_), None) => Side::I,
            _ => Side::J,
        };
        edges[ne] = Edge {
            p,
            q,
            side,
            i_side,
            j_side,
        };
        ne += 1;
    }
    let edges = &edges[..ne];
    let has_i = edges.iter().any(|e| e.side == Side::I);
    let has_j = edges.iter().any(|e| e.side == Side::J);
    if !(has_i && has_j) {
        // The polygon is one rectangle entirely: it lies inside the other.
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
        return Contact {
            state: ContactState::Contained,
            geometry: Some(frame.geometry(inner, inner, inner, n, dpt)),
        };
    }
    // Walk once around, starting on a non-shared edge; a change between I and J is a crossing,
    // at the midpoint of the shared run between them (the common vertex when there is none).
    let start = edges
        .iter()
        .position(|e| e.side != Side::Both)
        .expect("has I and J edges");
    let mut cross = [Cross::default(); MAX_POLY];
    let mut nc = 0;
    let mut last = edges[start];
    let mut run: [usize; MAX_POLY] = [0; MAX_POLY];
    let mut run_len = 0;
    for step in 1..=ne {
        let k = (start + step) % ne;
        let e = edges[k];
        if e.side == Side::Both {
            run[run_len] = k;
            run_len += 1;
            continue;
        }
        if e.side != last.side {
            cross[nc] = if run_len == 0 {
                // A vertex between an edge of i and an edge of j.
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
                    point: run_midpoint(edges, &run[..run_len]),
                    i_side: r.i_side,
                    j_side: r.j_side,
                }
            };
            nc += 1;
        }
        last = e;
        run_len = 0;
    }
    // Face normals in i's frame, by side index (0: +x, 1: +y, 2: −x, 3: −y).
    let face_i = |s: usize| [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]][s];
    let face_j = |s: usize| {
        let [x, y] = face_i(s);
        [cr * x - sr * y, sr * x + cr * y]
    };
    match nc {
        2 => {
            let (a, b) = (cross[0], cross[1]);
            // A chord along one face takes that face's normal exactly; two crossings a few ulps
            // apart would give it only to (rounding)/(chord length).
            let nrm = match (a.i_side, b.i_side, a.j_side, b.j_side) {
                (Some(x), Some(y), _, _) if x == y => face_i(x),
                (_, _, Some(x), Some(y)) if x == y => face_j(x),
                _ => {
                    let d = [b.point[0] - a.point[0], b.point[1] - a.point[1]];
                    let len = d[0].hypot(d[1]);
                    [-d[1] / len, d[0] / len]
                }
            };
            let (n, dpt) = orient(nrm, depth);
            let mid = super::midpoint(a.point, b.point);
            let mut g = frame.geometry(a.point, b.point, mid, n, dpt);
            g.flat = Some(frame.flat(poly));
            if area {
                let a_poly = polygon_area(poly);
                g.area = Some(frame.overlap(&LocalOverlap::chord(a_poly, a.point, b.point, n)));
            }
            Contact {
                state: ContactState::Overlap,
                geometry: Some(g),
            }
        }
        _ => {
            let mut pts = [[0.0f64; 2]; MAX_POLY];
            for (dst, c) in pts.iter_mut().zip(&cross[..nc]) {
                *dst = c.point;
            }
            let (p, q, n, dpt) = deep_fallback(&mut pts[..nc.max(2)], depth);
            let mid = super::midpoint(p, q);
            let mut g = frame.geometry(p, q, mid, n, dpt);
            if area && nc >= 2 {
                let qi = corners(wi, hi);
                let height = |k: usize, u: [f64; 2], m: [f64; 2]| {
                    let su = u[0] * m[0] + u[1] * m[1];
                    if k == 0 {
                        support_local(&shape_i, u[0], u[1]) - su
                    } else {
                        depth_j_support(u) + u[0] * c.x + u[1] * c.y - su
                    }
                };
                let cap = |k: usize, p: [f64; 2], q: [f64; 2], u: [f64; 2]| {
                    polygon_cap(if k == 0 { &qi } else { &qj }, super::midpoint(p, q), u)
                };
                let o = deep_overlap(&pts[..nc], [c.x, c.y], height, cap);
                g.area = Some(frame.overlap(&o));
            }
            Contact {
                state: ContactState::Deep,
                geometry: Some(g),
            }
        }
    }
}

/// An edge of the intersection polygon and the sides of i and of j it lies on.
#[derive(Clone, Copy, Debug)]
struct Edge {
    p: [f64; 2],
    q: [f64; 2],
    side: Side,
    i_side: Option<usize>,
    j_side: Option<usize>,
}

impl Default for Edge {
    fn default() -> Self {
        Edge {
            p: [0.0; 2],
            q: [0.0; 2],
            side: Side::I,
            i_side: None,
            j_side: None,
        }
    }
}

/// A boundary crossing and the sides of i and j it lies on.
#[derive(Clone, Copy, Debug, Default)]
struct Cross {
    point: [f64; 2],
    i_side: Option<usize>,
    j_side: Option<usize>,
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

/// Sutherland–Hodgman clipping of a convex quadrilateral by the box `|x| ≤ hx, |y| ≤ hy`.
fn clip_to_box(quad: &[[f64; 2]; 4], hx: f64, hy: f64) -> ([[f64; 2]; MAX_POLY], usize) {
    let mut buf = [[0.0f64; 2]; MAX_POLY];
    buf[..4].copy_from_slice(quad);
    let mut len = 4;
    // Each plane: inside when `s·p[axis] ≤ bound`.
    for (axis, s, bound) in [(0, 1.0, hx), (0, -1.0, hx), (1, 1.0, hy), (1, -1.0, hy)] {
        let mut out = [[0.0f64; 2]; MAX_POLY];
        let mut n = 0;
        for k in 0..len {
            let (p, q) = (buf[k], buf[(k + 1) % len]);
            let (dp, dq) = (s * p[axis] - bound, s * q[axis] - bound);
            if dp <= 0.0 {
                out[n] = p;
                n += 1;
            }
            if (dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0) {
                let t = dp / (dp - dq);
                let mut x = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
                x[axis] = s * bound; // exactly on the clip line
                out[n] = x;
                n += 1;
            }
        }
        buf = out;
        len = n;
        if len == 0 {
            break;
        }
    }
    (buf, len)
}

fn mean(poly: &[[f64; 2]]) -> Option<[f64; 2]> {
    if poly.is_empty() {
        return None;
    }
    let n = poly.len() as f64;
    Some([
        poly.iter().map(|p| p[0]).sum::<f64>() / n,
        poly.iter().map(|p| p[1]).sum::<f64>() / n,
    ])
}

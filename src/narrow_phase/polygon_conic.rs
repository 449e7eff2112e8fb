//! Polygon–ellipse and polygon–circle contact (a rectangle as its four corners): the polygon's
//! edges ∩ the conic, in the conic's own frame (`x²/a² + y²/b² = 1`; a circle is `a = b = r`).
//!
//! The overlap area of two crossings is exact in closed form: the polygon's part beyond the
//! chord (a clipped polygon, shoelace) plus the conic's segment beyond it (`½ab(Δφ − sin Δφ)`,
//! [`ellipse_cap`]); for a chord on one face, the conic's segment at the face's depth.

use super::local::{LocalFrame, LocalOverlap, deep_fallback, deep_overlap, orient, pow2_floor};
use super::record::{Contact, ContactState, Request, TOUCH_TOL};
use super::small::List;
use crate::geometry::overlap_area::{ellipse_cap, ellipse_cap_at_depth, polygon_cap};
use crate::geometry::polygon::vertex_support;
use crate::geometry::{Pose, Shape, Vec2};

/// Contact between convex polygon i (a polygon, or a rectangle as its corners:
/// [`Shape::vertices`]) and ellipse j
/// (semi-axes `a`, `b`; a circle is `a = b`); with `request.area`, the overlap area too (the
/// polygon's cap beyond the chord plus the conic's).
pub fn contact_polygon_conic(
    poly: &Shape,
    pi: &Pose,
    a: f64,
    b: f64,
    pj: &Pose,
    request: &Request,
) -> Option<Contact> {
    let area = request.area;
    let dv = pi.position - pj.position; // polygon centroid relative to the conic
    let d = dv.norm();
    let rr = poly.bounding_radius();
    if d > rr + a.max(b) {
        return None;
    }
    let scale = pow2_floor(rr.max(a).max(b));
    let inv = 1.0 / scale;
    let (a, b) = (a * inv, b * inv);
    // Everything in the conic's frame: polygon centroid and axes.
    let c = pj.to_body_vector(dv) * inv;
    let (ci, si) = pi.cos_sin();
    let (cj, sj) = pj.cos_sin();
    let (cr, sr) = (ci * cj + si * sj, si * cj - ci * sj); // polygon axis in conic frame
    let mut corners = [Vec2::zeros(); 4];
    let verts = poly.vertices(&mut corners);
    let poly_support = |ux: f64, uy: f64| {
        vertex_support(verts, Vec2::new(cr * ux + sr * uy, -sr * ux + cr * uy)) * inv
    };
    let ell_support = |ux: f64, uy: f64| ((a * ux) * (a * ux) + (b * uy) * (b * uy)).sqrt();
    // Penetration along n (polygon i → conic j): s_i(n) + s_j(n) − n·(c_j − c_i).
    let depth =
        |n: [f64; 2]| poly_support(n[0], n[1]) + ell_support(n[0], n[1]) + n[0] * c.x + n[1] * c.y;
    if d > 0.0 && depth([-c.x / d * scale, -c.y / d * scale]) < 0.0 {
        return None; // separating axis along the line of centres
    }
    let q: List<[f64; 2]> = verts
        .iter()
        .map(|v| {
            let p = [v.x * inv, v.y * inv];
            [c.x + cr * p[0] - sr * p[1], c.y + sr * p[0] + cr * p[1]]
        })
        .collect();
    let nv = q.len();
    let (ia2, ib2) = (1.0 / (a * a), 1.0 / (b * b));
    let quad = |p: [f64; 2]| p[0] * p[0] * ia2 + p[1] * p[1] * ib2;
    // Implicit value Q(c) − 1 of each corner, shared by its two edges.
    let gamma: List<f64> = q.iter().map(|&p| quad(p) - 1.0).collect();
    let mut cross: List<Crossing> = List::new();
    let mut tangent: Option<([f64; 2], [f64; 2])> = None;
    // Along edge k, from corner k by `e` to corner k+1, the conic reads α s² + 2β s + γ_k = 0.
    // Which edges cross is decided by the corners' sides, each known to rounding (γ is the
    // corner's own implicit value): an edge whose ends lie on opposite sides crosses once; an
    // edge with both ends inside, never (the conic is convex); an edge with both ends outside,
    // twice or never, as the quadratic's minimum on the edge is below zero or not. The roots
    // themselves, from the far corner, are only located to ~ε of its implicit value, which
    // may not tell whether a crossing next to a corner falls before or after it: each is
    // re-solved from the nearer corner ([`crossing_on_edge`]).
    for k in 0..nv {
        let k1 = (k + 1) % nv;
        let (p0, p1) = (q[k], q[k1]);
        let e = [p1[0] - p0[0], p1[1] - p0[1]];
        let alpha = quad(e);
        let beta = p0[0] * e[0] * ia2 + p0[1] * e[1] * ib2;
        let disc = beta * beta - alpha * gamma[k];
        let err = 16.0 * f64::EPSILON * (beta * beta + alpha * (gamma[k].abs() + 2.0));
        let qq = -(beta + disc.max(0.0).sqrt().copysign(beta));
        let roots = if qq != 0.0 {
            [qq / alpha, gamma[k] / qq]
        } else {
            [-beta / alpha; 2]
        };
        let (in0, in1) = (gamma[k] < 0.0, gamma[k1] < 0.0);
        if in0 != in1 {
            // One crossing: the root on the edge, or the nearer to it when rounding has put it
            // just beyond an end.
            let off = |s: f64| (s - s.clamp(0.0, 1.0)).abs();
            let s = if off(roots[0]) <= off(roots[1]) {
                roots[0]
            } else {
                roots[1]
            };
            cross.push(crossing_on_edge(
                k,
                s.clamp(0.0, 1.0),
                &q,
                &gamma,
                e,
                alpha,
                [ia2, ib2],
            ));
        } else if !in0 {
            // Both ends outside: two crossings when the minimum, at s = −β/α, is on the edge
            // and certainly below zero.
            let s_min = -beta / alpha;
            if !(0.0..=1.0).contains(&s_min) {
                continue;
            }
            if disc > err {
                for s in roots {
                    let s = s.clamp(0.0, 1.0);
                    cross.push(crossing_on_edge(k, s, &q, &gamma, e, alpha, [ia2, ib2]));
                }
            } else if disc >= -err {
                // Outward normal of this edge (vertices run counter-clockwise).
                let len = e[0].hypot(e[1]);
                tangent = Some((
                    [p0[0] + s_min * e[0], p0[1] + s_min * e[1]],
                    [e[1] / len, -e[0] / len],
                ));
            }
        }
    }
    let frame = LocalFrame::of(pj, scale);
    // Caps beyond a chord through m towards u: the polygon's by clipping its vertices, the
    // conic's (centred at the origin here) in closed form.
    let poly_cap = |m: [f64; 2], u: [f64; 2]| polygon_cap(&q, m, u);
    let conic_cap = |p: [f64; 2], e: [f64; 2], u: [f64; 2]| {
        ellipse_cap(a, b, p, e, u[0] * p[0] + u[1] * p[1] < 0.0)
    };
    let n = cross.len();
    match n {
        2 => {
            let (p, qv) = (cross[0].point(), cross[1].point());
            // Two crossings that rounding cannot tell apart (a corner on the conic's boundary):
            // the chord's limit, the conic's tangent there.
            let nrm = chord_direction_normal(&cross[0], &cross[1]).unwrap_or_else(|| {
                let (gx, gy) = (p[0] * ia2, p[1] * ib2);
                let len = gx.hypot(gy);
                [gx / len, gy / len]
            });
            let (nrm, dpt) = orient(nrm, depth);
            if dpt <= TOUCH_TOL {
                // Crossings within rounding of each other and of tangency.
                let mid = super::local::midpoint(p, qv);
                return Some(frame.contact(ContactState::Touching, p, qv, mid, nrm, dpt, request));
            }
            let mid = super::local::midpoint(p, qv);
            let mut g = frame.contact(ContactState::Overlap, p, qv, mid, nrm, dpt, request);
            if area {
                let caps = if cross[0].edge == cross[1].edge {
                    // A face cuts the conic: the chord is on the face line (no cap of the
                    // polygon), and the conic's cap follows from the depth, where the
                    // crossings of a nearly tangent face are ill-conditioned.
                    ellipse_cap_at_depth(a, b, nrm, dpt)
                } else {
                    let e = [qv[0] - p[0], qv[1] - p[1]];
                    poly_cap(mid, nrm) + conic_cap(p, e, [-nrm[0], -nrm[1]])
                };
                g.area = Some(frame.overlap(&LocalOverlap::chord(caps, p, qv, nrm)));
            }
            Some(g)
        }
        3.. => {
            let mut pts: List<[f64; 2]> = cross.iter().map(Crossing::point).collect();
            let (p, qv, nrm, dpt) = deep_fallback(&mut pts[..n], depth);
            let mid = super::local::midpoint(p, qv);
            let mut g = frame.contact(ContactState::Deep, p, qv, mid, nrm, dpt, request);
            if area {
                let o = deep_overlap(
                    &pts[..n],
                    [0.0, 0.0],
                    |k, u, m| {
                        let (su, um) = (u[0] * m[0] + u[1] * m[1], u[0] * c.x + u[1] * c.y);
                        if k == 0 {
                            poly_support(u[0], u[1]) + um - su
                        } else {
                            ell_support(u[0], u[1]) - su
                        }
                    },
                    |k, p, qq, u| {
                        if k == 0 {
                            poly_cap(super::local::midpoint(p, qq), u)
                        } else {
                            conic_cap(p, [qq[0] - p[0], qq[1] - p[1]], u)
                        }
                    },
                );
                g.area = Some(frame.overlap(&o));
            }
            Some(g)
        }
        0 | 1 => {
            if let Some((t, face)) = tangent {
                // An edge within rounding of tangency: the half-chord cannot tell a tiny overlap
                // from a tiny gap where the conic is sharply curved, the depth through that face
                // can (exact, from the support functions) — unless, along that face's normal,
                // one body's extent lies within the other's: then the edge touches the conic
                // from inside (one body in the other), which the test below decides.
                let (nrm, dpt) = orient(face, depth);
                let s_min = poly_support(nrm[0], nrm[1]).min(ell_support(nrm[0], nrm[1]));
                let nested = dpt >= 2.0 * s_min - TOUCH_TOL;
                if !nested && dpt >= -TOUCH_TOL {
                    let state = if dpt <= TOUCH_TOL {
                        ContactState::Touching
                    } else {
                        ContactState::Overlap
                    };
                    return Some(frame.contact(state, t, t, t, nrm, dpt, request));
                }
            }
            // No crossing: nested or apart. The solids meet only if one lies inside the other,
            // and then the inner one's centre lies inside the outer one (by at least its own
            // inscribed radius: a robust test where a corner or a vertex of the inner one may
            // touch the outer boundary). The inner one is the smaller in area.
            let poly_centre_in = quad([c.x, c.y]) < 1.0;
            // The conic's centre (the origin) inside the polygon: left of every edge.
            let conic_centre_in = (0..nv).all(|k| {
                let (p, r) = (q[k], q[(k + 1) % nv]);
                (r[0] - p[0]) * (-p[1]) - (r[1] - p[1]) * (-p[0]) > 0.0
            });
            if !(poly_centre_in || conic_centre_in) {
                return None;
            }
            let toward = if d > 0.0 {
                [-c.x * scale / d, -c.y * scale / d]
            } else {
                [1.0, 0.0]
            };
            let (nrm, dpt) = orient(toward, depth);
            let poly_inner = poly.area() * inv * inv <= std::f64::consts::PI * a * b;
            let inner = if poly_inner { [c.x, c.y] } else { [0.0, 0.0] };
            Some(frame.contained(inner, nrm, dpt, request))
        }
    }
}

/// A boundary crossing on a polygon edge, stored relative to the nearer corner of that edge so
/// that two crossings next to one corner keep their small offsets exact (the corner's own
/// rounding is common to both and cancels from the chord's direction).
#[derive(Clone, Copy, Debug, Default)]
struct Crossing {
    corner: [f64; 2],
    offset: [f64; 2],
    corner_index: usize,
    edge: usize,
    edge_dir: [f64; 2],
}

impl Crossing {
    fn point(&self) -> [f64; 2] {
        [
            self.corner[0] + self.offset[0],
            self.corner[1] + self.offset[1],
        ]
    }
}

/// The crossing at parameter `s` of edge `k` (from corner k to corner k+1), re-solved from the
/// nearer corner: the roots of the quadratic about that corner are accurate relative to the
/// corner's implicit value `γ`, where `s` itself would lose it against 1.
fn crossing_on_edge(
    k: usize,
    s: f64,
    q: &[[f64; 2]],
    gamma: &[f64],
    e: [f64; 2],
    alpha: f64,
    inv2: [f64; 2],
) -> Crossing {
    let (ci, dir, t_est) = if s <= 0.5 {
        (k, e, s)
    } else {
        ((k + 1) % q.len(), [-e[0], -e[1]], 1.0 - s)
    };
    let c = q[ci];
    // α t² + 2β t + γ = 0 along c + t·dir.
    let beta = c[0] * dir[0] * inv2[0] + c[1] * dir[1] * inv2[1];
    let disc = (beta * beta - alpha * gamma[ci]).max(0.0);
    let qq = -(beta + disc.sqrt().copysign(beta));
    let t = if qq != 0.0 {
        let (r1, r2) = (qq / alpha, gamma[ci] / qq);
        if (r1 - t_est).abs() < (r2 - t_est).abs() {
            r1
        } else {
            r2
        }
    } else {
        t_est
    };
    Crossing {
        corner: c,
        offset: [t * dir[0], t * dir[1]],
        corner_index: ci,
        edge: k,
        edge_dir: e,
    }
}

/// Unit normal of the chord between two crossings, from the best-conditioned data: the edge's
/// own direction when both lie on one edge, the corner-relative offsets when they flank one
/// corner, the points otherwise. `None` when the two coincide.
fn chord_direction_normal(a: &Crossing, b: &Crossing) -> Option<[f64; 2]> {
    let d = if a.edge == b.edge {
        a.edge_dir
    } else if a.corner_index == b.corner_index {
        [b.offset[0] - a.offset[0], b.offset[1] - a.offset[1]]
    } else {
        let (p, q) = (a.point(), b.point());
        [q[0] - p[0], q[1] - p[1]]
    };
    let len = d[0].hypot(d[1]);
    (len > 0.0).then(|| [-d[1] / len, d[0] / len])
}

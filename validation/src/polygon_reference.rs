//! High-precision reference for contacts with **convex polygons**: the overlap area and the
//! boundary crossings of a polygon with a polygon, a wall, an ellipse or a circle, in
//! double-double ([`DD`], ~106 bits) from the exact `f64` inputs, rounded to `f64` at the end.
//! It shares nothing with the crate's geometry or narrow phase, and uses other methods than the
//! kernels:
//!
//! - **polygon–polygon**: j's vertices clipped by i's half-planes (Sutherland–Hodgman) for the
//!   area (shoelace); the crossings are the proper intersections of every edge of i with every
//!   edge of j (segment–segment, not the clipping's labels);
//! - **polygon–wall**: the polygon clipped by the half-plane; crossings edge ∩ line;
//! - **polygon–ellipse** (a circle is `a = b`): in the ellipse's frame scaled to the unit disk
//!   (`(x/a, y/b)`, areas × 1/(ab)), the area as the sum over the polygon's edges of the signed
//!   area of the unit disk ∩ the triangle (0, p_k, p_{k+1}) — each edge cut at its crossings with
//!   the circle, a piece inside contributing its triangle `½ p × q`, a piece outside its sector
//!   `½ atan2(p × q, p·q)` (Green's theorem; not the kernels' chord caps); the crossings are the
//!   roots in (0, 1) of `|p + t(q − p)|² = 1`.
//!
//! Poses are turned by the double-double sine and cosine of the given angle (the kernels use the
//! rounded `f64` ones: a difference of ~1e-16 of the size). Everything is relative to the first
//! object's position (a wall's point when i is a wall), exactly.

use super::dd::DD;

/// One side of a pair.
#[derive(Clone, Debug)]
pub enum PObj {
    /// Vertices in the body frame (counter-clockwise, centred on the centroid as the crate's
    /// polygons are), the centroid's position and the angle.
    Polygon {
        vertices: Vec<[f64; 2]>,
        pos: [f64; 2],
        angle: f64,
    },
    /// An ellipse (semi-axes a along its x axis, b), or a circle (a = b).
    Ellipse {
        a: f64,
        b: f64,
        pos: [f64; 2],
        angle: f64,
    },
    /// A half-plane `{x : normal·(x − point) ≤ 0}` (normal of any length).
    Wall { point: [f64; 2], normal: [f64; 2] },
}

/// The reference's answer.
#[derive(Clone, Debug, PartialEq)]
pub struct PRef {
    /// Area of the intersection of the two solids.
    pub area: f64,
    /// The boundary crossings (world coordinates), in no particular order.
    pub crossings: Vec<[f64; 2]>,
}

type V = [DD; 2];

fn sub(p: V, q: V) -> V {
    [p[0] - q[0], p[1] - q[1]]
}
fn cross(p: V, q: V) -> DD {
    p[0] * q[1] - p[1] * q[0]
}
fn dot(p: V, q: V) -> DD {
    p[0] * q[0] + p[1] * q[1]
}
fn lerp(p: V, q: V, t: DD) -> V {
    [p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t]
}

/// Vertices of a polygon relative to `origin`.
fn placed(vertices: &[[f64; 2]], pos: [f64; 2], angle: f64, origin: [f64; 2]) -> Vec<V> {
    let (s, c) = DD::from(angle).sin_cos();
    let o = [
        DD::from_sum(pos[0], -origin[0]),
        DD::from_sum(pos[1], -origin[1]),
    ];
    vertices
        .iter()
        .map(|v| {
            let (x, y) = (DD::from(v[0]), DD::from(v[1]));
            [o[0] + c * x - s * y, o[1] + s * x + c * y]
        })
        .collect()
}

fn shoelace(p: &[V]) -> DD {
    if p.len() < 3 {
        return DD::ZERO;
    }
    let mut twice = DD::ZERO;
    for k in 1..p.len() - 1 {
        twice += cross(sub(p[k], p[0]), sub(p[k + 1], p[0]));
    }
    twice * 0.5
}

/// Clips `poly` (counter-clockwise) by `{x : n·(x − a) ≤ 0}`.
fn clip_half_plane(poly: &[V], a: V, n: V) -> Vec<V> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    let len = poly.len();
    for k in 0..len {
        let (p, q) = (poly[k], poly[(k + 1) % len]);
        let (dp, dq) = (dot(n, sub(p, a)), dot(n, sub(q, a)));
        if dp.hi <= 0.0 {
            out.push(p);
        }
        if (dp.hi < 0.0 && dq.hi > 0.0) || (dp.hi > 0.0 && dq.hi < 0.0) {
            out.push(lerp(p, q, dp / (dp - dq)));
        }
    }
    out
}

/// Proper crossings of segment pq with segment rs.
fn segment_crossing(p: V, q: V, r: V, s: V) -> Option<V> {
    let (e, f) = (sub(q, p), sub(s, r));
    let den = cross(e, f);
    if den.is_zero() {
        return None;
    }
    let rp = sub(r, p);
    let t = cross(rp, f) / den;
    let u = cross(rp, e) / den;
    let inside = |x: DD| x.hi > 0.0 && x.hi < 1.0;
    (inside(t) && inside(u)).then(|| lerp(p, q, t))
}

/// Signed area of the unit disk ∩ the triangle (0, p, q), and the crossings of segment pq with
/// the unit circle (pushed to `cross_out`).
fn disk_triangle(p: V, q: V, cross_out: &mut Vec<V>) -> DD {
    let e = sub(q, p);
    let alpha = dot(e, e);
    let beta = dot(p, e);
    let gamma = dot(p, p) - 1.0;
    let disc = beta * beta - alpha * gamma;
    let mut ts = vec![DD::ZERO];
    if disc.hi > 0.0 {
        let root = disc.sqrt();
        for t in [(-beta - root) / alpha, (-beta + root) / alpha] {
            if t.hi > 0.0 && t.hi < 1.0 {
                ts.push(t);
                cross_out.push(lerp(p, q, t));
            }
        }
    }
    ts.push(DD::ONE);
    let mut area = DD::ZERO;
    for w in ts.windows(2) {
        let (u, v) = (lerp(p, q, w[0]), lerp(p, q, w[1]));
        let mid = lerp(p, q, (w[0] + w[1]) * 0.5);
        if dot(mid, mid).hi < 1.0 {
            area += cross(u, v) * 0.5;
        } else {
            area += cross(u, v).atan2(dot(u, v)) * 0.5;
        }
    }
    area
}

/// The reference overlap of two objects, at least one of them a polygon (else `None`).
pub fn polygon_overlap(i: &PObj, j: &PObj) -> Option<PRef> {
    let origin = match i {
        PObj::Polygon { pos, .. } | PObj::Ellipse { pos, .. } => *pos,
        PObj::Wall { point, .. } => *point,
    };
    let world = |p: V| [(p[0] + origin[0]).to_f64(), (p[1] + origin[1]).to_f64()];
    let (poly, other) = match (i, j) {
        (PObj::Polygon { .. }, _) => (i, j),
        (_, PObj::Polygon { .. }) => (j, i),
        _ => return None,
    };
    let PObj::Polygon {
        vertices,
        pos,
        angle,
    } = poly
    else {
        unreachable!()
    };
    let p = placed(vertices, *pos, *angle, origin);
    Some(match other {
        PObj::Polygon {
            vertices,
            pos,
            angle,
        } => {
            let q = placed(vertices, *pos, *angle, origin);
            let mut clipped = q.clone();
            for k in 0..p.len() {
                let (a, b) = (p[k], p[(k + 1) % p.len()]);
                let n = [b[1] - a[1], a[0] - b[0]];
                clipped = clip_half_plane(&clipped, a, n);
                if clipped.is_empty() {
                    break;
                }
            }
            let mut crossings = Vec::new();
            for k in 0..p.len() {
                for m in 0..q.len() {
                    if let Some(x) =
                        segment_crossing(p[k], p[(k + 1) % p.len()], q[m], q[(m + 1) % q.len()])
                    {
                        crossings.push(world(x));
                    }
                }
            }
            PRef {
                area: shoelace(&clipped).to_f64(),
                crossings,
            }
        }
        PObj::Wall { point, normal } => {
            let a = [
                DD::from_sum(point[0], -origin[0]),
                DD::from_sum(point[1], -origin[1]),
            ];
            let n = [DD::from(normal[0]), DD::from(normal[1])];
            let clipped = clip_half_plane(&p, a, n);
            let mut crossings = Vec::new();
            for k in 0..p.len() {
                let (x, y) = (p[k], p[(k + 1) % p.len()]);
                let (dx, dy) = (dot(n, sub(x, a)), dot(n, sub(y, a)));
                if (dx.hi < 0.0 && dy.hi > 0.0) || (dx.hi > 0.0 && dy.hi < 0.0) {
                    crossings.push(world(lerp(x, y, dx / (dx - dy))));
                }
            }
            PRef {
                area: shoelace(&clipped).to_f64(),
                crossings,
            }
        }
        PObj::Ellipse { a, b, pos, angle } => {
            // The polygon in the ellipse's frame, scaled to the unit disk.
            let (s, c) = DD::from(*angle).sin_cos();
            let o = [
                DD::from_sum(pos[0], -origin[0]),
                DD::from_sum(pos[1], -origin[1]),
            ];
            let unit: Vec<V> = p
                .iter()
                .map(|&x| {
                    let d = sub(x, o);
                    [(c * d[0] + s * d[1]) / *a, (c * d[1] - s * d[0]) / *b]
                })
                .collect();
            let mut area = DD::ZERO;
            let mut xs = Vec::new();
            for k in 0..unit.len() {
                area += disk_triangle(unit[k], unit[(k + 1) % unit.len()], &mut xs);
            }
            let crossings = xs
                .into_iter()
                .map(|u| {
                    let (x, y) = (u[0] * *a, u[1] * *b);
                    world([o[0] + c * x - s * y, o[1] + s * x + c * y])
                })
                .collect();
            PRef {
                area: (area * (*a) * (*b)).to_f64(),
                crossings,
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_forms() {
        let sq = vec![[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        // A square inside a disk of radius 2: the square's area; a unit disk in the square: π.
        let p = PObj::Polygon {
            vertices: sq.clone(),
            pos: [0.0, 0.0],
            angle: 0.3,
        };
        let big = PObj::Ellipse {
            a: 2.0,
            b: 2.0,
            pos: [0.1, 0.0],
            angle: 0.0,
        };
        assert!((polygon_overlap(&p, &big).unwrap().area - 4.0).abs() < 1e-15);
        let small = PObj::Ellipse {
            a: 1.0,
            b: 0.5,
            pos: [0.0, 0.0],
            angle: 0.0,
        };
        let r = polygon_overlap(&small, &p).unwrap();
        assert!((r.area - std::f64::consts::PI * 0.5).abs() < 1e-15, "{r:?}");
        // Half the square under a wall through its centre.
        let w = PObj::Wall {
            point: [0.0, 0.0],
            normal: [0.0, 1.0],
        };
        let r = polygon_overlap(&w, &p).unwrap();
        assert!((r.area - 2.0).abs() < 1e-15 && r.crossings.len() == 2);
        // Two squares offset by (1, 1): a unit square, two crossings.
        let q = PObj::Polygon {
            vertices: sq,
            pos: [1.0, 1.0],
            angle: 0.0,
        };
        let p0 = PObj::Polygon {
            vertices: vec![[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]],
            pos: [0.0, 0.0],
            angle: 0.0,
        };
        let r = polygon_overlap(&p0, &q).unwrap();
        assert!((r.area - 1.0).abs() < 1e-15, "{r:?}");
    }
}

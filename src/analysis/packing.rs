//! Packing fraction of a window (exact areas of the bodies clipped by it) and coordination
//! numbers with and without rattlers.
//!
//! # Exact clipped areas
//! - A disk ∩ a convex polygon: the sum over the polygon's edges of the signed area of the disk
//!   ∩ the triangle (centre, edge) — each edge split where it crosses the circle; a piece inside
//!   the circle adds its triangle, a piece outside adds the circular sector it subtends.
//! - An ellipse: the affine map `x ↦ diag(1/a, 1/b) Rᵀ (x − c)` takes it to the unit disk and the
//!   window to a parallelogram; areas scale by `ab`.
//! - A rectangle or a polygon: its outline clipped by the window (Sutherland–Hodgman), then the
//!   shoelace.

use super::frame::{Frame, FrameBody, Window};
use crate::geometry::{Shape, Vec2};

fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Signed area of the disk of radius `r` centred at the origin ∩ the triangle (0, a, b).
fn disk_triangle(a: Vec2, b: Vec2, r: f64) -> f64 {
    let d = b - a;
    let (qa, qb, qc) = (d.dot(&d), 2.0 * a.dot(&d), a.dot(&a) - r * r);
    let mut cuts = vec![0.0];
    let disc = qb * qb - 4.0 * qa * qc;
    if qa > 0.0 && disc > 0.0 {
        let s = disc.sqrt();
        for t in [(-qb - s) / (2.0 * qa), (-qb + s) / (2.0 * qa)] {
            if t > 0.0 && t < 1.0 {
                cuts.push(t);
            }
        }
    }
    cuts.push(1.0);
    let mut area = 0.0;
    for w in cuts.windows(2) {
        let (p, q) = (a + d * w[0], a + d * w[1]);
        let m = (p + q) * 0.5;
        // Strictly inside: a segment tangent to the circle (its midpoint on it) is outside.
        if m.norm_squared() < r * r {
            area += 0.5 * cross(p, q);
        } else {
            area += 0.5 * r * r * cross(p, q).atan2(p.dot(&q));
        }
    }
    area
}

/// Area of the disk of radius `r` at the origin ∩ the convex polygon `poly` (either winding).
fn disk_polygon(poly: &[Vec2], r: f64) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|k| disk_triangle(poly[k], poly[(k + 1) % n], r))
        .sum::<f64>()
        .abs()
}

/// Shoelace area of a polygon.
fn polygon_area(poly: &[Vec2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|k| cross(poly[k], poly[(k + 1) % n]))
        .sum::<f64>()
        .abs()
        * 0.5
}

/// `poly` clipped by the window (Sutherland–Hodgman).
fn clip(poly: &[Vec2], w: Window) -> Vec<Vec2> {
    let planes: [(Vec2, f64); 4] = [
        (Vec2::new(1.0, 0.0), w.x0),
        (Vec2::new(-1.0, 0.0), -w.x1),
        (Vec2::new(0.0, 1.0), w.y0),
        (Vec2::new(0.0, -1.0), -w.y1),
    ];
    let mut out = poly.to_vec();
    for (n, c) in planes {
        let input = std::mem::take(&mut out);
        let k = input.len();
        for e in 0..k {
            let (p, q) = (input[e], input[(e + 1) % k]);
            let (dp, dq) = (n.dot(&p) - c, n.dot(&q) - c);
            if dp >= 0.0 {
                out.push(p);
            }
            if (dp >= 0.0) != (dq >= 0.0) {
                out.push(p + (q - p) * (dp / (dp - dq)));
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// The area (cm²) of a body inside the window.
pub fn clipped_area(b: &FrameBody, w: Window) -> f64 {
    let corners = [
        Vec2::new(w.x0, w.y0),
        Vec2::new(w.x1, w.y0),
        Vec2::new(w.x1, w.y1),
        Vec2::new(w.x0, w.y1),
    ];
    let (c, s) = (b.angle.cos(), b.angle.sin());
    match b.shape {
        Shape::Circle { r } => {
            let poly: Vec<Vec2> = corners.iter().map(|&p| p - b.position).collect();
            disk_polygon(&poly, r)
        }
        Shape::Ellipse { a, b: bb } => {
            // Body frame, then scaled to the unit disk.
            let poly: Vec<Vec2> = corners
                .iter()
                .map(|&p| {
                    let d = p - b.position;
                    Vec2::new((c * d.x + s * d.y) / a, (-s * d.x + c * d.y) / bb)
                })
                .collect();
            a * bb * disk_polygon(&poly, 1.0)
        }
        Shape::Clump(cl) => {
            // Exact when the bounding circle is wholly inside or outside the window; otherwise
            // the midpoint rule on a 512 × 512 grid over the bounding square (an approximation:
            // the union of overlapping disks clipped to a rectangle has no closed form here).
            let rb = cl.bounding_radius;
            let p = b.position;
            if p.x - rb >= w.x0 && p.x + rb <= w.x1 && p.y - rb >= w.y0 && p.y + rb <= w.y1 {
                return cl.area;
            }
            if p.x + rb <= w.x0 || p.x - rb >= w.x1 || p.y + rb <= w.y0 || p.y - rb >= w.y1 {
                return 0.0;
            }
            let world: Vec<(Vec2, f64)> = cl
                .centres
                .iter()
                .zip(cl.radii.iter())
                .map(|(m, &r)| (p + Vec2::new(c * m.x - s * m.y, s * m.x + c * m.y), r))
                .collect();
            const N: usize = 512;
            let h = 2.0 * rb / N as f64;
            let mut hits = 0usize;
            for ix in 0..N {
                let x = p.x - rb + (ix as f64 + 0.5) * h;
                if x < w.x0 || x > w.x1 {
                    continue;
                }
                for iy in 0..N {
                    let y = p.y - rb + (iy as f64 + 0.5) * h;
                    if y < w.y0 || y > w.y1 {
                        continue;
                    }
                    let q = Vec2::new(x, y);
                    if world.iter().any(|(m, r)| (q - m).norm_squared() <= r * r) {
                        hits += 1;
                    }
                }
            }
            hits as f64 * h * h
        }
        Shape::Rectangle { .. } | Shape::Polygon(_) => {
            let outline: Vec<Vec2> = b
                .shape
                .corners()
                .expect("flat-faced shapes have corners")
                .iter()
                .map(|v| b.position + Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y))
                .collect();
            let clipped = clip(&outline, w);
            if clipped.len() < 3 {
                0.0
            } else {
                polygon_area(&clipped)
            }
        }
    }
}

/// The packing (solid area) fraction of the window: Σ of the bodies' areas inside it over its
/// area.
pub fn packing_fraction(bodies: &[FrameBody], w: Window) -> f64 {
    bodies.iter().map(|b| clipped_area(b, w)).sum::<f64>() / w.area()
}

/// The smallest axis-aligned window holding every body's bounding circle.
pub fn bounding_window(bodies: &[FrameBody]) -> Window {
    let mut w = Window {
        x0: f64::INFINITY,
        x1: f64::NEG_INFINITY,
        y0: f64::INFINITY,
        y1: f64::NEG_INFINITY,
    };
    for b in bodies {
        let r = b.shape.bounding_radius();
        w.x0 = w.x0.min(b.position.x - r);
        w.x1 = w.x1.max(b.position.x + r);
        w.y0 = w.y0.min(b.position.y - r);
        w.y1 = w.y1.max(b.position.y + r);
    }
    w
}

/// Coordination numbers of the bodies of a region.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Coordination {
    /// Mean number of contacts per body (walls included), over the region's bodies.
    pub with_rattlers: f64,
    /// The same after removing rattlers — bodies with fewer than 2 contacts — and their
    /// contacts, repeatedly until none is left (removing one can make a neighbour a rattler);
    /// over the remaining bodies (NaN if none remains).
    pub without_rattlers: f64,
    /// Fraction of the region's bodies that are rattlers.
    pub rattler_fraction: f64,
}

/// Contacts per body counts only contacts that carry a force (`F_n > 0`).
pub fn coordination(frame: &Frame, inside: &[bool]) -> Coordination {
    let n = frame.bodies.len();
    let carrying: Vec<_> = frame
        .contacts
        .iter()
        .filter(|c| c.normal_force() > 0.0)
        .collect();
    let mut z = vec![0usize; n];
    for c in &carrying {
        z[c.j] += 1;
        if let Some(i) = c.giver_body() {
            z[i] += 1;
        }
    }
    let count = inside.iter().filter(|&&b| b).count();
    if count == 0 {
        return Coordination {
            with_rattlers: f64::NAN,
            without_rattlers: f64::NAN,
            rattler_fraction: f64::NAN,
        };
    }
    let with = (0..n).filter(|&p| inside[p]).map(|p| z[p]).sum::<usize>() as f64 / count as f64;
    // Remove rattlers (of the whole frame) until none is left.
    let mut alive: Vec<bool> = vec![true; n];
    loop {
        let mut zz = vec![0usize; n];
        for c in &carrying {
            let i = c.giver_body();
            if !alive[c.j] || i.is_some_and(|i| !alive[i]) {
                continue;
            }
            zz[c.j] += 1;
            if let Some(i) = i {
                zz[i] += 1;
            }
        }
        let mut changed = false;
        for p in 0..n {
            if alive[p] && zz[p] < 2 {
                alive[p] = false;
                changed = true;
            }
        }
        if !changed {
            let kept: Vec<usize> = (0..n).filter(|&p| inside[p] && alive[p]).collect();
            let without = if kept.is_empty() {
                f64::NAN
            } else {
                kept.iter().map(|&p| zz[p]).sum::<usize>() as f64 / kept.len() as f64
            };
            return Coordination {
                with_rattlers: with,
                without_rattlers: without,
                rattler_fraction: (count - kept.len()) as f64 / count as f64,
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use std::f64::consts::PI;

    const W: Window = Window {
        x0: 0.0,
        x1: 10.0,
        y0: 0.0,
        y1: 6.0,
    };

    fn body(shape: Shape, x: f64, y: f64, angle: f64) -> FrameBody {
        FrameBody {
            shape,
            position: Vec2::new(x, y),
            angle,
            density: 1.0,
        }
    }

    #[test]
    fn a_disk_inside_on_an_edge_at_a_corner_and_at_a_distance_from_an_edge() {
        let c = Shape::Circle { r: 1.5 };
        assert_relative_eq!(
            clipped_area(&body(c, 5.0, 3.0, 0.0), W),
            PI * 2.25,
            max_relative = 1e-14
        );
        assert_relative_eq!(
            clipped_area(&body(c, 5.0, 0.0, 0.0), W),
            PI * 2.25 / 2.0,
            max_relative = 1e-14
        );
        assert_relative_eq!(
            clipped_area(&body(c, 10.0, 6.0, 0.0), W),
            PI * 2.25 / 4.0,
            max_relative = 1e-14
        );
        approx::assert_abs_diff_eq!(
            clipped_area(&body(c, 20.0, 3.0, 0.0), W),
            0.0,
            epsilon = 1e-14
        );
        // Centre at distance d outside the edge x = 10: the segment r² acos(d/r) − d√(r² − d²).
        let (r, d) = (1.5f64, 0.6f64);
        let segment = r * r * (d / r).acos() - d * (r * r - d * d).sqrt();
        assert_relative_eq!(
            clipped_area(&body(c, 10.6, 3.0, 0.0), W),
            segment,
            max_relative = 1e-13
        );
    }

    #[test]
    fn an_ellipse_or_a_rectangle_centred_on_an_edge_or_a_corner_at_any_angle() {
        for angle in [0.0, 0.3, 1.1, 2.5] {
            let e = Shape::Ellipse { a: 2.0, b: 0.7 };
            let area = PI * 1.4;
            assert_relative_eq!(
                clipped_area(&body(e, 4.0, 3.0, angle), W),
                area,
                max_relative = 1e-13
            );
            // An edge through the centre halves a centrally symmetric body; a corner quarters it
            // only for a body symmetric about both axes through the corner — a half-turn about
            // the centre maps the body onto itself, so opposite quadrants are equal, and the
            // window holds one quadrant: at angle 0 (axes aligned) exactly a quarter.
            assert_relative_eq!(
                clipped_area(&body(e, 0.0, 3.0, angle), W),
                area / 2.0,
                max_relative = 1e-13
            );
            let r = Shape::Rectangle { w: 3.0, h: 1.0 };
            assert_relative_eq!(
                clipped_area(&body(r, 4.0, 3.0, angle), W),
                3.0,
                max_relative = 1e-13
            );
            assert_relative_eq!(
                clipped_area(&body(r, 5.0, 6.0, angle), W),
                1.5,
                max_relative = 1e-13
            );
        }
        let e = Shape::Ellipse { a: 2.0, b: 0.7 };
        assert_relative_eq!(
            clipped_area(&body(e, 0.0, 0.0, 0.0), W),
            PI * 1.4 / 4.0,
            max_relative = 1e-13
        );
        let r = Shape::Rectangle { w: 3.0, h: 1.0 };
        assert_relative_eq!(
            clipped_area(&body(r, 10.0, 0.0, 0.0), W),
            0.75,
            max_relative = 1e-13
        );
    }

    #[test]
    fn a_square_lattice_of_touching_disks_packs_at_pi_over_4() {
        // Unit disks at the odd integers × 2: a window of whole cells holds π/4.
        let bodies: Vec<FrameBody> = (0..36)
            .map(|k| {
                body(
                    Shape::Circle { r: 1.0 },
                    2.0 * (k % 6) as f64 + 1.0,
                    2.0 * (k / 6) as f64 + 1.0,
                    0.0,
                )
            })
            .collect();
        // Whole cells; then a window cutting the disks anywhere, which still holds π/4 when it
        // spans whole periods.
        for [x0, x1, y0, y1] in [[2.0, 10.0, 2.0, 8.0], [1.3, 9.3, 0.7, 8.7]] {
            let w = Window { x0, x1, y0, y1 };
            assert_relative_eq!(packing_fraction(&bodies, w), PI / 4.0, max_relative = 1e-13);
        }
    }

    /// A triangle of three bodies in mutual contact, a fourth hanging on one of them by a
    /// single contact (a rattler), and a fifth touching only the rattler: removing the rattler
    /// leaves the fifth with no contact, so it is a rattler too (found on the second pass).
    #[test]
    fn rattlers_are_removed_with_their_contacts_until_none_is_left() {
        use crate::analysis::FrameContact;
        use crate::dynamics::Partner;
        let bodies: Vec<FrameBody> = (0..5)
            .map(|k| body(Shape::Circle { r: 1.0 }, k as f64, 0.0, 0.0))
            .collect();
        let c = |i: usize, j: usize| FrameContact {
            i: Partner::Body(i),
            j,
            point: Vec2::zeros(),
            normal: Vec2::new(1.0, 0.0),
            force: Vec2::new(1.0, 0.0),
            couple: 0.0,
            depth: 0.0,
            state: "overlap".into(),
        };
        let frame = Frame {
            time: 0.0,
            bodies,
            contacts: vec![c(0, 1), c(0, 2), c(1, 2), c(2, 3), c(3, 4)],
            wall_box: None,
            cell: None,
        };
        let z = coordination(&frame, &[true; 5]);
        // Contacts per body: 2, 2, 3, 2, 1 → 10/5; without rattlers (3, then 4): 2, 2, 2.
        assert_eq!(z.with_rattlers, 2.0);
        assert_eq!(z.without_rattlers, 2.0);
        assert_eq!(z.rattler_fraction, 0.4);
    }
}

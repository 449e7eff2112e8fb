//! Body outlines as polygons, for pictures (SVG, PNG) and ParaView (VTK): vertices on the true
//! boundary, as many as the boundary's curvature needs.
//!
//! # How many vertices
//! A chord spanning a turn `Δφ` of the outward normal of an arc with radius of curvature `ρ`
//! lies at most `s ≈ ρ Δφ²/8` (its sagitta) inside the arc. The vertices of an ellipse are
//! placed by the normal angle `φ` with a local spacing
//! `Δφ(φ) = min(TURN_MAX, √(8 ε b / ρ(φ)))`, `ε` = [`SAGITTA`], `b` the smaller semi-axis,
//! `ρ(φ) = a²b²/h(φ)³` and `h(φ) = √(a² cos²φ + b² sin²φ)` the support function. So every chord
//! lies within `ε·b` of the boundary (the flat sides, where ρ reaches `a²/b`, get dense
//! vertices) and no vertex turns the outline by more than `TURN_MAX` = 5° (the blunt tips,
//! where ρ falls to `b²/a`, are not drawn as corners). The count is the integral
//! `N = ∫₀^{2π} dφ / Δφ(φ)`, rounded up to a multiple of 4 so that the four tips are vertices:
//! 72 for a circle (the turn bound), 84 at a/b = 1.5, 128 at a/b = 10 (measured largest chord
//! distance: 0.95, 0.95 and 0.99 × ε·b). The vertices lie on the
//! ellipse, so the polygon is inscribed: its area is below the body's by at most `ε·b` times the
//! perimeter (each chord's segment lies in a strip `ε·b` wide).

use crate::geometry::Shape;
use std::f64::consts::TAU;

/// Largest distance of a chord from the boundary, relative to the smaller semi-axis.
pub const SAGITTA: f64 = 1e-3;

/// Largest turn of the outline at one vertex (rad): 5°, 72 vertices for a circle.
pub const TURN_MAX: f64 = TAU / 72.0;

/// The vertices of `shape` in its own frame (centroid at the origin, x along the body's axis),
/// counter-clockwise from the end of its x semi-axis (a rectangle: from its lower-left corner; a
/// polygon: its vertices as given, shifted to the centroid); not closed.
pub fn body_frame_vertices(shape: &Shape) -> Vec<(f64, f64)> {
    match *shape {
        Shape::Circle { r } => (0..72)
            .map(|k| k as f64 * TURN_MAX)
            .map(|t| (r * t.cos(), r * t.sin()))
            .collect(),
        Shape::Ellipse { a, b } => ellipse_vertices(a, b),
        Shape::Rectangle { w, h } => {
            let (u, v) = (0.5 * w, 0.5 * h);
            vec![(-u, -v), (u, -v), (u, v), (-u, v)]
        }
        Shape::Polygon(p) => p.vertices.iter().map(|v| (v.x, v.y)).collect(),
        // The union's boundary (its exposed arcs, a vertex at most every 5°); a clump whose
        // union is not one loop (a member apart, a hole) gives its loops one after another, so
        // the picture joins them by a segment.
        Shape::Clump(c) => c
            .boundary_loops(TURN_MAX)
            .into_iter()
            .flatten()
            .map(|v| (v.x, v.y))
            .collect(),
    }
}

/// The point of the ellipse whose outward normal has angle `phi`, with the radius of
/// curvature there.
fn ellipse_point(a: f64, b: f64, phi: f64) -> ((f64, f64), f64) {
    let (s, c) = phi.sin_cos();
    let h = (a * a * c * c + b * b * s * s).sqrt();
    (
        (a * a * c / h, b * b * s / h),
        (a * b).powi(2) / (h * h * h),
    )
}

/// Vertices of the ellipse `(a, b)` spaced as the module documentation says.
fn ellipse_vertices(a: f64, b: f64) -> Vec<(f64, f64)> {
    let small = a.min(b);
    // Vertex density (vertices per radian of normal angle) at φ.
    let density = |phi: f64| {
        let rho = ellipse_point(a, b, phi).1;
        (1.0 / TURN_MAX).max((rho / (8.0 * SAGITTA * small)).sqrt())
    };
    // Its running integral on a fine grid (trapezoids), inverted by linear interpolation.
    const M: usize = 4096;
    let mut cum = vec![0.0; M + 1];
    let mut prev = density(0.0);
    for k in 1..=M {
        let d = density(TAU * k as f64 / M as f64);
        cum[k] = cum[k - 1] + 0.5 * (prev + d) * TAU / M as f64;
        prev = d;
    }
    let total = cum[M];
    let n = ((total / 4.0).ceil() as usize).max(1) * 4;
    let mut out = Vec::with_capacity(n);
    let mut j = 0;
    for v in 0..n {
        let target = total * v as f64 / n as f64;
        while j + 1 < M && cum[j + 1] < target {
            j += 1;
        }
        let f = ((target - cum[j]) / (cum[j + 1] - cum[j])).clamp(0.0, 1.0);
        let phi = TAU * (j as f64 + f) / M as f64;
        out.push(ellipse_point(a, b, phi).0);
    }
    out
}

/// The outline of `shape` placed at `(x, y)` with angle `angle`, not closed.
pub fn polygon(shape: &Shape, x: f64, y: f64, angle: f64) -> Vec<(f64, f64)> {
    place(&body_frame_vertices(shape), x, y, angle)
}

/// Body-frame vertices placed at `(x, y)` with angle `angle`.
pub fn place(vertices: &[(f64, f64)], x: f64, y: f64, angle: f64) -> Vec<(f64, f64)> {
    let (s, c) = angle.sin_cos();
    vertices
        .iter()
        .map(|&(u, v)| (x + c * u - s * v, y + s * u + c * v))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Largest distance from the true ellipse to the polygon's chords, sampled finely by the
    /// parametric angle: for each boundary point, the distance to the chord whose normal-angle
    /// span holds it.
    fn worst_sagitta(a: f64, b: f64, vs: &[(f64, f64)]) -> f64 {
        let n = vs.len();
        let mut worst: f64 = 0.0;
        for k in 0..n {
            let (p, q) = (vs[k], vs[(k + 1) % n]);
            let (tp, mut tq) = ((p.1 / b).atan2(p.0 / a), (q.1 / b).atan2(q.0 / a));
            if tq <= tp {
                tq += TAU;
            }
            let (dx, dy) = (q.0 - p.0, q.1 - p.1);
            let len = dx.hypot(dy);
            for i in 1..64 {
                let t = tp + (tq - tp) * i as f64 / 64.0;
                let (x, y) = (a * t.cos(), b * t.sin());
                // Distance of (x, y) from the chord's line (the arc lies outside it).
                let d = ((x - p.0) * dy - (y - p.1) * dx).abs() / len;
                worst = worst.max(d);
            }
        }
        worst
    }

    #[test]
    fn ellipse_polygons_stay_within_the_sagitta_and_turn_bounds() {
        for (a, b, expect_n) in [
            (1.0, 1.0, 72),
            (1.5, 1.0, 84),
            (10.0, 1.0, 128),
            (1.0, 10.0, 128),
        ] {
            let vs = ellipse_vertices(a, b);
            assert_eq!(vs.len(), expect_n, "a/b = {a}/{b}");
            // On the ellipse.
            for &(x, y) in &vs {
                assert!(((x / a).powi(2) + (y / b).powi(2) - 1.0).abs() < 1e-14);
            }
            // The chord bound holds to first order in Δφ (the curvature varies along a chord):
            // 5 % is the second-order slack.
            let s = worst_sagitta(a, b, &vs);
            assert!(s <= 1.05 * SAGITTA * a.min(b), "a/b = {a}/{b}: {s}");
            // No vertex turns the outline by more than TURN_MAX (again to first order).
            let n = vs.len();
            for k in 0..n {
                let (p, q, r) = (vs[(k + n - 1) % n], vs[k], vs[(k + 1) % n]);
                let t1 = (q.1 - p.1).atan2(q.0 - p.0);
                let t2 = (r.1 - q.1).atan2(r.0 - q.0);
                let turn = (t2 - t1).rem_euclid(TAU);
                assert!(
                    turn > 0.0 && turn <= 1.05 * TURN_MAX,
                    "{a}/{b} vertex {k}: {turn}"
                );
            }
        }
    }
}

//! Area and polar moment of inertia of unit-thickness bodies (SEED_NOTES, T2 adapted to 2D).

use super::shape::Shape;
use std::f64::consts::PI;

/// Area of the shape (its mass per unit thickness and unit density).
pub fn area(shape: &Shape) -> f64 {
    match *shape {
        Shape::Circle { r } => PI * r * r,
        Shape::Ellipse { a, b } => PI * a * b,
        Shape::Rectangle { w, h } => w * h,
        Shape::Polygon(p) => p.area, // the shoelace formula (geometry::polygon)
        Shape::Clump(c) => c.area,   // the union's, exactly (geometry::clump)
    }
}

/// Moment of inertia about the centroid divided by mass: disk `r²/2`, ellipse `(a² + b²)/4`,
/// rectangle `(w² + h²)/12` (T2, in 2D), polygon `J/A` from its polar second moment of area
/// (Eberly's polygon moments, see `geometry::polygon`).
pub fn inertia_per_mass(shape: &Shape) -> f64 {
    match *shape {
        Shape::Circle { r } => 0.5 * r * r,
        Shape::Ellipse { a, b } => 0.25 * (a * a + b * b),
        Shape::Rectangle { w, h } => (w * w + h * h) / 12.0,
        Shape::Polygon(p) => p.inertia_per_mass,
        Shape::Clump(c) => c.inertia_per_mass,
    }
}

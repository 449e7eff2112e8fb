//! Area and polar moment of inertia of unit-thickness bodies (SEED_NOTES, T2 adapted to 2D).

use super::shape::Shape;

/// Area of the shape (its mass per unit thickness and unit density).
pub fn area(shape: &Shape) -> f64 {
    shape.area()
}

/// Moment of inertia about the centroid divided by mass: disk `r²/2`, ellipse `(a² + b²)/4`,
/// rectangle `(w² + h²)/12` (T2, in 2D), polygon `J/A` from its polar second moment of area
/// (Eberly's polygon moments, see `geometry::polygon`).
pub fn inertia_per_mass(shape: &Shape) -> f64 {
    shape.inertia_per_mass()
}

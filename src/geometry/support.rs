//! Support functions `h(u) = max over the shape of u·x` (the shape centred at the origin, in its
//! own orientation). The contact depth of the chord definition is `h_i(n) + h_j(−n)` for the
//! placed shapes, i.e. `s_i(n) + s_j(n) − n·(c_j − c_i)` with the centred `s` below
//! (all three shapes are centrally symmetric, so `s(−u) = s(u)`).

use super::shape::Shape;

/// Centred support function of `shape` for a direction given by its components `(ux, uy)` in
/// the shape's own frame (not necessarily unit: the result scales with |u|).
///
/// circle `r|u|`; ellipse `√(a²ux² + b²uy²)`; rectangle `(w|ux| + h|uy|)/2` (the farthest corner);
/// polygon `max_k u·v_k` over its vertices.
#[inline]
pub fn support_local(shape: &Shape, ux: f64, uy: f64) -> f64 {
    shape.support_xy(ux, uy)
}

/// Centred support function for a direction `(ux, uy)` in a frame in which the shape's own x axis
/// is at `(cos θ, sin θ)`.
#[inline]
pub fn support_rotated(shape: &Shape, cos: f64, sin: f64, ux: f64, uy: f64) -> f64 {
    support_local(shape, cos * ux + sin * uy, -sin * ux + cos * uy)
}

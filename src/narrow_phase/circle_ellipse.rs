//! Circle–ellipse contact: the pencil of conics with the circle as the conic `a = b = r`
//! (see [`super::ellipse_ellipse`]).

use super::Contact;
use super::ellipse_ellipse::conic_pair;
use crate::geometry::Pose;

/// Contact between circle i (radius `r`) and ellipse j (semi-axes `a` along its x axis, `b`).
#[inline]
pub fn contact_circle_ellipse(r: f64, pi: &Pose, a: f64, b: f64, pj: &Pose) -> Contact {
    conic_pair(r, r, pi, a, b, pj)
}

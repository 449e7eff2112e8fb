//! Polygon–circle contact: the polygon's edges ∩ the circle, by the polygon–conic kernel with
//! `a = b = r` ([`super::polygon_conic`]). The circle's pose gives only a frame (its
//! orientation enters no result: any orthonormal frame centred on the circle computes the same
//! crossings, to rounding).

use super::{Contact, Request};
use crate::geometry::{Polygon, Pose};

/// Contact between convex polygon i and circle j of radius `r`; with `request.area`, the
/// overlap area too (the polygon's cap beyond the chord plus the circle's segment).
#[inline]
pub fn contact_polygon_circle(
    poly: &Polygon,
    pi: &Pose,
    r: f64,
    pj: &Pose,
    request: &Request,
) -> Contact {
    super::polygon_conic::contact_polygon_ellipse(poly, pi, r, r, pj, request)
}

//! Circle–ellipse contact: the pencil of conics with the circle as the conic `a = b = r`
//! (see [`super::ellipse_ellipse`]). The circle is i (the pencil's frame is centred on it).

use super::ellipse_ellipse::{Warm, conic_pair};
use super::{Contact, Request};
use crate::geometry::Pose;

/// Contact between circle i (radius `r`) and ellipse j (semi-axes `a` along its x axis, `b`),
/// from the warm start `guess`: the contact, the next warm start and whether `guess` gave the
/// result (see [`super::ellipse_ellipse`]).
#[inline]
pub fn contact_circle_ellipse(
    r: f64,
    pi: &Pose,
    a: f64,
    b: f64,
    pj: &Pose,
    guess: Option<Warm>,
    request: &Request,
) -> (Contact, Option<Warm>, bool) {
    conic_pair(r, r, pi, a, b, pj, guess, request.area)
}

//! Ellipse–ellipse contact by the pencil of conics (P5–P10).
//!
//! 1. Cheap rejection: bounding circles, then the separating-axis test along the line of centres
//!    (two square roots).
//! 2. The paper's local frame (P5–P7): origin at the centroid of i, x axis through the centroid of
//!    j; lengths in units of a power of two near the larger semi-axis.
//! 3. The real roots of `D(λ) = 0` (P10) by the solvers of [`crate::geometry::cubic`]: the fast
//!    one when the cubic certainly has a single real root, the robust one otherwise.
//! 4. Each real root's member of the pencil (P9) is split into two lines; a line that meets
//!    ellipse i in real points meets ellipse j in the same points (on the line `f ≡ −λ g`), so
//!    the real crossings are read off line ∩ ellipse i alone.
//! 5. Two crossings: the chord definition. One tangent point: touching. Four: deep fallback.
//!    None: separated, or one inside the other (one boundary point tested against the other).
//!
//! Which roots give what (projective facts): two ellipses crossing at two points have one real
//! root, whose member is the chord line plus a line through the two complex crossings (which
//! meets ellipse i in complex points only); separated or nested ellipses have three real roots
//! and no member meets them in real points; four crossings give three real members, each through
//! all four points. At tangency two roots merge (a double root, a point-ellipse member).
//! Equal shapes with equal orientation give the root λ = −1 exactly, whose member is one finite
//! line (the chord) plus the line at infinity.

use super::{
    Contact, ContactState, LocalFrame, TOUCH_TOL, deep_fallback, orient_symmetric, pow2_floor,
};
use crate::geometry::Pose;
use crate::geometry::conic::EllipseForm;
use crate::geometry::cubic::{one_real_root, solve_cubic};
use crate::geometry::pencil::{
    LineCut, Pencil, cut_line, mixed_invariant_from_inverse_squares, split_degenerate,
};

/// Half-chords² (in units of the larger semi-axis squared) below which a line counts as nearly
/// tangent and is judged by the depth along its normal. The line itself carries the rounding of
/// λ and of the splitting (measured up to ~1e-14 at a/b = 100), which `half_sq_err` does not
/// include; a generous band costs nothing, since the depth decides.
const NEAR_TANGENT: f64 = 1e-10;

/// Contact between ellipse i (semi-axes `ai` along its x axis, `bi`) and ellipse j.
#[inline]
pub fn contact_ellipse_ellipse(
    ai: f64,
    bi: f64,
    pi: &Pose,
    aj: f64,
    bj: f64,
    pj: &Pose,
) -> Contact {
    conic_pair(ai, bi, pi, aj, bj, pj)
}

/// Centred support function of an ellipse along a direction `(ux, uy)` of a frame in which its
/// `a` axis is at `(cos, sin)`.
#[inline]
fn support(a: f64, b: f64, cos: f64, sin: f64, ux: f64, uy: f64) -> f64 {
    let (pa, pb) = (a * (cos * ux + sin * uy), b * (cos * uy - sin * ux));
    (pa * pa + pb * pb).sqrt()
}

/// The pencil computation shared by ellipse–ellipse and circle–ellipse (a circle is the conic
/// with `a = b = r`).
pub(crate) fn conic_pair(ai: f64, bi: f64, pi: &Pose, aj: f64, bj: f64, pj: &Pose) -> Contact {
    let dv = pj.position - pi.position;
    let d = dv.norm();
    let (ri, rj) = (ai.max(bi), aj.max(bj));
    if d > ri + rj {
        return Contact::SEPARATED; // bounding circles
    }
    // P's local frame: x axis from O_i through O_j (α of Fig. 1); any axis when concentric.
    let (ca, sa) = if d > 0.0 {
        (dv.x / d, dv.y / d)
    } else {
        (1.0, 0.0)
    };
    let (ci, si) = pi.cos_sin();
    let (cj, sj) = pj.cos_sin();
    // θ_n = (body angle) − α, by the angle-difference formulas.
    let (cti, sti) = (ci * ca + si * sa, si * ca - ci * sa);
    let (ctj, stj) = (cj * ca + sj * sa, sj * ca - cj * sa);
    // Separating axis along the line of centres.
    if support(ai, bi, cti, sti, 1.0, 0.0) + support(aj, bj, ctj, stj, 1.0, 0.0) < d {
        return Contact::SEPARATED;
    }
    let scale = pow2_floor(ri.max(rj));
    let inv = 1.0 / scale;
    let (ai, bi, aj, bj, d) = (ai * inv, bi * inv, aj * inv, bj * inv, d * inv);
    let frame = LocalFrame {
        origin: pi.position,
        cos: ca,
        sin: sa,
        scale,
    };

    // Relative angle φ from i's a axis to j's a axis (frame independent).
    let (cphi, sphi) = (cj * ci + sj * si, sj * ci - cj * si);
    let inv_i = [1.0 / (ai * ai), 1.0 / (bi * bi)];
    let inv_j = [1.0 / (aj * aj), 1.0 / (bj * bj)];
    let pencil = Pencil {
        i: EllipseForm::from_inverse_squares(inv_i[0], inv_i[1], cti, sti), // P(5), P(7)
        j: EllipseForm::from_inverse_squares(inv_j[0], inv_j[1], ctj, stj), // P(6), P(7)
        d,
        x_mixed: mixed_invariant_from_inverse_squares(inv_i, inv_j, cphi, sphi),
    };
    let [t1, t2, t3, t4] = pencil.cubic(); // P(10)
    // Every real root is tried in turn. When the cubic certainly has a single real root (every
    // two-crossing overlap) the fast solver finds it and there is nothing else to try; otherwise
    // the robust solver gives them all.
    let single = one_real_root(t1, t2, t3, t4);
    let all;
    let roots: &[f64] = match &single {
        Some(lambda) => std::slice::from_ref(lambda),
        None => {
            all = solve_cubic(t1, t2, t3, t4);
            all.as_slice()
        }
    };

    // Sum of the centred supports along n (both ellipses are symmetric, so the same along −n);
    // the depth along n (i → j) is that minus n·d.
    let supports =
        |n: [f64; 2]| support(ai, bi, cti, sti, n[0], n[1]) + support(aj, bj, ctj, stj, n[0], n[1]);
    let depth = |n: [f64; 2]| supports(n) - n[0] * d;
    let oriented = |n: [f64; 2]| orient_symmetric(n, supports(n), n[0] * d);

    let reach = ri * inv * (1.0 + 1e-9);
    let mut crossings = [[0.0f64; 2]; 4];
    let mut n_cross = 0;
    let mut chord: Option<LineCut> = None;
    // A line whose half-chord is within rounding of zero nearly touches both ellipses at one
    // point. Its half-length cannot tell a tiny overlap from a tiny gap where the curvature is
    // high (half² ≈ 2Rδ, R = b²/a at the tip of a thin ellipse), but its direction is accurate
    // and the depth along it is first-order insensitive to that direction: decide by δ(n).
    let mut near_tangent: Option<LineCut> = None;
    let mut coincident = false;
    for &lambda in roots {
        let member = pencil.member(lambda);
        let Some(lines) = split_degenerate(&member) else {
            // Imaginary lines (a point-ellipse member) — or no member at all: f + λg ≡ 0 means
            // the two conics are one and the same curve.
            let size = [member.a, member.h, member.b, member.g, member.f, member.c]
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            coincident |= size <= 1e-12 * (pencil.i.a_coef + pencil.i.c_coef);
            continue;
        };
        let mut found = 0;
        let distinct = if lines[0] == lines[1] { 1 } else { 2 }; // a double line counts once
        for line in &lines[..distinct] {
            let Some(cut) = cut_line(&pencil.i, line, reach) else {
                continue;
            };
            if cut.half_sq > cut.half_sq_err {
                let [p, q] = cut.points();
                crossings[found] = p;
                crossings[found + 1] = q;
                found += 2;
                chord = Some(cut);
                if single.is_some() {
                    break; // one real root: two crossings at most, and here they are
                }
            } else if cut.half_sq >= -NEAR_TANGENT.max(cut.half_sq_err) && near_tangent.is_none() {
                near_tangent = Some(cut);
            }
        }
        if found > 0 {
            n_cross = found;
            break;
        }
    }

    // The depth along a direction is exact to rounding (support functions), while a chord line
    // carries the rounding of λ and of the splitting: the depth's sign has the last word. A
    // negative depth along any direction proves separation (a separating axis).
    let tol = TOUCH_TOL;
    let candidate = match (n_cross, chord) {
        (2, Some(cut)) => Some(cut),
        (4, _) => {
            let (p, q, n, dpt) = deep_fallback(&mut crossings, depth);
            if dpt > tol {
                let mid = super::midpoint(p, q);
                return Contact {
                    state: ContactState::Deep,
                    geometry: Some(frame.geometry(p, q, mid, n, dpt)),
                };
            }
            None
        }
        _ => near_tangent,
    };
    if let Some(cut) = candidate {
        let (n, dpt) = oriented(cut.normal);
        if dpt >= -tol {
            let [p, q] = cut.points();
            let state = if dpt <= tol {
                ContactState::Touching
            } else {
                ContactState::Overlap
            };
            return Contact {
                state,
                geometry: Some(frame.geometry(p, q, cut.mid, n, dpt)),
            };
        }
        return Contact::SEPARATED;
    }
    // No crossing: nested or apart. Test one boundary point of each against the other.
    let j_point = [d + aj * ctj, aj * stj];
    let i_point = [ai * cti, ai * sti];
    let j_in_i = coincident || pencil.i.quad(j_point[0], j_point[1]) < 1.0;
    let i_in_j = pencil.j.quad(i_point[0] - d, i_point[1]) < 1.0;
    if !(j_in_i || i_in_j) {
        return Contact::SEPARATED;
    }
    let (n, dpt) = oriented([1.0, 0.0]);
    let inner = if j_in_i { [d, 0.0] } else { [0.0, 0.0] };
    Contact {
        state: ContactState::Contained,
        geometry: Some(frame.geometry(inner, inner, inner, n, dpt)),
    }
}

//! The critical time step of the explicit scheme.
//!
//! One contact seen along its normal (or its tangent) is a damped oscillator with stiffness k,
//! dashpot η and the pair's inverse effective mass along that direction at the contact point,
//! `w = 1/m_i + (r_i × n)²/I_i + 1/m_j + (r_j × n)²/I_j` — the rotational inertia and the lever
//! arm of a non-circular body enter through `(r × n)²/I` (for the tangent, `(r × t)²/I`, where
//! the lever is the full distance to the contact point). Then `ω² = k w`, `ζ = η w / (2ω)`, and
//! velocity Verlet with the dashpot at the half step is stable for
//! `Δt < 2(√(1+ζ²) − ζ)/ω` (from the eigenvalues of its amplification matrix). Heavy damping
//! lowers the limit: for ζ ≫ 1 it tends to `2/(η w)`, set by the dashpot alone.

use super::body::Bodies;
use super::cell::Cell;
use super::contacts::Contact;
use super::kinematics;
use super::materials::{Materials, PairTable};
use super::world::{Boundary, World};
use crate::contact_law::params::pair_density;
use crate::contact_law::{ContactSpec, NormalForce, PairSpec};
use crate::geometry::Shape;
use crate::geometry::overlap_area::DiskLens;

/// Stability limit of one damped contact mode (∞ without stiffness).
#[inline]
pub fn critical_dt(k: f64, eta: f64, w: f64) -> f64 {
    if k <= 0.0 || w <= 0.0 {
        return f64::INFINITY;
    }
    let omega = (k * w).sqrt();
    let zeta = eta * w / (2.0 * omega);
    2.0 * ((1.0 + zeta * zeta).sqrt() - zeta) / omega
}

/// The largest factor by which a contact of this scene can be stiffer (against its depth) than
/// the law's `k_n`: body pairs, or (with `wall`) a body against a wall, under `normal_force`.
///
/// - The area law on a smooth contact acts like a spring `k_n ρ²` with
///   `ρ² ≈ (R*_t/R*_eq)^{2/3}`, `R*_t` from the true radii of curvature and `R*_eq` from the
///   equal-area radii (see `contact_law`); a body's flattest point has `κ = R_max/R_eq`
///   (ellipse `(a/b)^{3/2}`), a pair's ratio is at most the larger κ, and a rectangle's face
///   against a conic gives `κ_c (1 + R_eq,c/R_eq,rect)`.
/// - Between flat faces: the Winkler contact (either law, against a wall; the depth law between
///   rectangles) is `k_n L/ℓ` for a face of length L; the area law's flat-equivalent potential
///   between rectangles `k_n (L/ℓ)²`.
/// - A polygon takes the area law of smooth bodies (the equal-area lens): a face of length L
///   pressed flat by δ has `A = Lδ`, and the force `k_n δ_eq L/L_eq` has a tangent stiffness of
///   at most `k_n ρ²`, `ρ = L/L_eq(Lδ)` — unbounded as δ → 0 (a face's force grows like
///   `δ^{1/3}` at first touch), so it is evaluated at an overlap of 1e-4 of the smallest
///   inscribed radius (about a resting overlap at P's stiffness, `Kn/ρg` = 36400 cm, for a body
///   of a centimetre: a drop of P's 64-gon on a floor observes 1.8e-4 s, the estimate gives
///   1.2e-4 s), for the longest face against a wall or against the same body. A heuristic:
///   at smaller overlaps such a face is stiffer still, but only over a vanishing range.
pub fn stiffness_factor(bodies: &Bodies, normal_force: NormalForce, wall: bool) -> f64 {
    let (mut kappa, mut r_eq_conic, mut r_eq_rect, mut side_ratio) =
        (0.0f64, 0.0f64, f64::INFINITY, 0.0f64);
    let (mut conics, mut rects) = (false, false);
    let delta = 1e-4
        * bodies
            .shape
            .iter()
            .map(Shape::inscribed_radius)
            .fold(f64::INFINITY, f64::min);
    let mut face: f64 = 1.0;
    for s in &bodies.shape {
        match *s {
            Shape::Polygon(p) => {
                if normal_force == NormalForce::Area {
                    let r = s.equal_area_radius();
                    let lens = DiskLens::new(r, if wall { f64::INFINITY } else { r });
                    let (_, compliance) = lens.equivalent_depth(p.longest_edge * delta);
                    face = face.max((p.longest_edge * compliance).powi(2));
                }
            }
            Shape::Rectangle { w, h } => {
                rects = true;
                r_eq_rect = r_eq_rect.min(s.equal_area_radius());
                side_ratio = side_ratio.max(w.max(h) / (0.5 * (w + h)));
            }
            Shape::Clump(c) => {
                // Every contact is a member disk's (κ = 1), but up to every member of a clump
                // can press on one wall or body at once: their springs act in parallel.
                conics = true;
                kappa = kappa.max(1.0);
                face = face.max(c.len() as f64);
            }
            Shape::Circle { .. } | Shape::Ellipse { .. } => {
                conics = true;
                kappa = kappa.max(s.max_curvature_radius() / s.equal_area_radius());
                r_eq_conic = r_eq_conic.max(s.equal_area_radius());
            }
        }
    }
    let mut factor: f64 = face;
    if rects {
        // Winkler against a wall; between rectangles, Winkler or the flat potential.
        factor = factor.max(side_ratio);
        if !wall && normal_force == NormalForce::Area {
            factor = factor.max(side_ratio * side_ratio);
        }
    }
    if normal_force == NormalForce::Area && conics {
        let mut ratio = kappa;
        if rects && !wall {
            ratio = ratio.max(kappa * (1.0 + r_eq_conic / r_eq_rect));
        }
        factor = factor.max(ratio.powf(2.0 / 3.0));
    }
    factor
}

/// An a-priori estimate of the critical time step of a scene, from the stiffest contact it can
/// have: the two bodies with the largest inverse effective masses (normal and tangential, with
/// the worst lever arms), or the lightest body against a wall, under every contact law of the
/// scene, with the stiffest geometry the scene's shapes allow ([`stiffness_factor`]). For
/// Hertz–Mindlin the stiffness grows with the overlap: it is evaluated at an overlap of 1 % of
/// the smallest body's inscribed radius (the observed value is reported separately).
pub fn estimate_critical_dt(
    bodies: &Bodies,
    spec: &ContactSpec,
    walls: &[Boundary],
    g: f64,
) -> f64 {
    let pairs = PairTable::new(spec, &Materials::default(), walls);
    estimate_critical_dt_of(bodies, &pairs, walls, g)
}

/// [`estimate_critical_dt`] for a scene of several materials: every law of `pairs` (each
/// material pair's for the two bodies of the largest inverse masses, each wall's with each
/// material for the lightest body).
pub fn estimate_critical_dt_of(
    bodies: &Bodies,
    pairs: &PairTable,
    walls: &[Boundary],
    g: f64,
) -> f64 {
    let n = bodies.len();
    if n == 0 {
        return f64::INFINITY;
    }
    // Per body: inverse masses along a worst-lever normal and tangent.
    let mut wn: Vec<(f64, usize)> = Vec::with_capacity(n);
    let mut wt: Vec<(f64, usize)> = Vec::with_capacity(n);
    for k in 0..n {
        let ln = bodies.shape[k].max_normal_lever();
        let lt = bodies.bound[k];
        wn.push((bodies.inv_mass[k] + ln * ln * bodies.inv_inertia[k], k));
        wt.push((bodies.inv_mass[k] + lt * lt * bodies.inv_inertia[k], k));
    }
    let top2 = |v: &mut Vec<(f64, usize)>| {
        v.sort_by(|a, b| b.0.total_cmp(&a.0));
        (v[0], v.get(1).copied())
    };
    let (n1, n2) = top2(&mut wn);
    let (t1, t2) = top2(&mut wt);
    let delta = 0.01
        * bodies
            .shape
            .iter()
            .map(Shape::inscribed_radius)
            .fold(f64::INFINITY, f64::min);
    let mut dt = f64::INFINITY;
    // A pair of bodies under the scene's law, and each wall's law against the lightest body.
    let m = pairs.count() as u16;
    let mut cases: Vec<(&PairSpec, f64, f64, usize, Option<usize>)> = Vec::new();
    if let (Some(n2), Some(t2)) = (n2, t2) {
        for a in 0..m {
            for b in a..m {
                let p = pairs.body_pair(a, b);
                cases.push((p, n1.0 + n2.0, t1.0 + t2.0, n1.1, Some(n2.1)));
            }
        }
    }
    for w in 0..walls.len() {
        for b in 0..m {
            cases.push((pairs.wall(w, b), n1.0, t1.0, n1.1, None));
        }
    }
    for (s, w_n, w_t, a, b) in cases {
        let rho = pair_density(bodies.density[a], b.map(|b| bodies.density[b]));
        // Each part's stiffness and dashpot (Hertz's at an overlap of 1 % of the smallest
        // inscribed radius), for the worst case's kinematics.
        let modes = s
            .resolve(rho, g)
            .modes(&kinematics::worst_case(bodies, a, b, delta));
        let (kn, eta_n) = modes.normal;
        let (kt, eta_t) = modes.tangential;
        // A couple's spring turns the bodies about their centroids: inverse inertia Σ 1/I.
        let w_r = bodies.inv_inertia[a] + b.map_or(0.0, |b| bodies.inv_inertia[b]);
        dt = dt.min(critical_dt(modes.rotation.0, modes.rotation.1, w_r));
        // A normal spring stiffer by the factor f: stiffness f k_n and dashpot √f η (the area
        // law's ρ η; more damping only lowers the limit).
        let f = stiffness_factor(bodies, s.spec.normal_force(), b.is_none());
        dt = dt
            .min(critical_dt(f * kn, f.sqrt() * eta_n, w_n))
            .min(critical_dt(kt, eta_t, w_t));
    }
    dt
}

impl World {
    /// The critical time step of the current contact network: its stiffest mode.
    ///
    /// In mass-normalised coordinates (`√m x`, `√m y`, `√I θ` per body) each contact adds
    /// `k J Jᵀ` along its normal and its tangent, `J` holding `±u/√m` and `(r × u)/√I` for the two
    /// bodies. Power iteration on `K = Σ k J Jᵀ` (matrix-free, over the contact list) gives the
    /// largest `ω²`; the mode's damping ratio is the Rayleigh quotient `ζ = vᵀCv / (2ω)` with
    /// `C = Σ η J Jᵀ`; then `Δt_crit = 2(√(1+ζ²) − ζ)/ω`. A body held by several contacts is
    /// stiffer than any one of them, which the single-contact a-priori estimate cannot see.
    /// Also records the smallest value in [`Diagnostics::dt_critical_observed`](super::world::Diagnostics).
    pub fn network_critical_dt(&mut self) -> f64 {
        self.refresh_contact_extras();
        let contacts: Vec<Contact> = self.contacts.active().collect();
        let dt = network_dt(&self.bodies, &contacts, self.cell.as_ref());
        self.diagnostics.dt_critical_observed = self.diagnostics.dt_critical_observed.min(dt);
        dt
    }
}

/// One contact direction: stiffness, damping, the mass-normalised Jacobian entries of its one or
/// two bodies, and whether the second side is a body (not a wall).
type JacobianRow = (f64, f64, [(usize, [f64; 3]); 2], bool);

fn network_dt(b: &Bodies, contacts: &[Contact], cell: Option<&Cell>) -> f64 {
    use crate::geometry::Vec2;
    if contacts.is_empty() {
        return f64::INFINITY;
    }
    let n = b.len();
    let scale: Vec<[f64; 3]> = (0..n)
        .map(|k| {
            let (sm, si) = (b.inv_mass[k].sqrt(), b.inv_inertia[k].sqrt());
            [sm, sm, si]
        })
        .collect();
    // One row of J per contact direction: (body, [jx, jy, jθ]) for each side.
    let cross = |a: Vec2, c: Vec2| a.x * c.y - a.y * c.x;
    let mut rows: Vec<JacobianRow> = Vec::with_capacity(2 * contacts.len());
    for c in contacts {
        let sides = c.sides();
        let (recv, give) = (sides.receiver, sides.giving_body());
        let (d, e) = (&c.data, &c.extra);
        // A couple's spring (`kr`, `cr`): a relative rotation, no translation.
        if e.kr > 0.0 {
            let a = (recv, [0.0, 0.0, scale[recv][2]]);
            let (g, two) = match give {
                Some(k) => ((k, [0.0, 0.0, -scale[k][2]]), true),
                None => ((recv, [0.0; 3]), false),
            };
            rows.push((e.kr as f64, e.cr as f64, [a, g], two));
        }
        let t = Vec2::new(-e.normal.y, e.normal.x);
        for (u, k, eta) in [
            (e.normal, e.kn as f64, e.eta_n as f64),
            (t, e.kt as f64, e.eta_t as f64),
        ] {
            if k <= 0.0 {
                continue;
            }
            let side = |body: usize, sign: f64| {
                // (In a periodic cell, to the contact point's nearest image.)
                let r = d.point - b.state[body].pose.position;
                let r = cell.map_or(r, |c| c.shortest(r));
                let s = scale[body];
                (
                    body,
                    [
                        sign * u.x * s[0],
                        sign * u.y * s[1],
                        sign * cross(r, u) * s[2],
                    ],
                )
            };
            let a = side(recv, 1.0);
            let (g, two) = match give {
                Some(k) => (side(k, -1.0), true),
                None => ((recv, [0.0; 3]), false),
            };
            rows.push((k, eta, [a, g], two));
        }
    }
    let apply = |v: &[f64], out: &mut [f64], use_eta: bool| {
        out.iter_mut().for_each(|o| *o = 0.0);
        for (k, eta, sides, two) in &rows {
            let coef = if use_eta { *eta } else { *k };
            let count = if *two { 2 } else { 1 };
            let mut dot = 0.0;
            for (body, j) in &sides[..count] {
                for d in 0..3 {
                    dot += j[d] * v[3 * body + d];
                }
            }
            for (body, j) in &sides[..count] {
                for d in 0..3 {
                    out[3 * body + d] += coef * dot * j[d];
                }
            }
        }
    };
    let mut v: Vec<f64> = (0..3 * n)
        .map(|k| 1.0 + 0.1 * ((k * 7919) % 13) as f64)
        .collect();
    let mut w = vec![0.0; 3 * n];
    let mut lambda = 0.0;
    for _ in 0..60 {
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            return f64::INFINITY;
        }
        v.iter_mut().for_each(|x| *x /= norm);
        apply(&v, &mut w, false);
        let next = v.iter().zip(&w).map(|(a, b)| a * b).sum::<f64>();
        std::mem::swap(&mut v, &mut w);
        if (next - lambda).abs() <= 1e-6 * next {
            lambda = next;
            break;
        }
        lambda = next;
    }
    // v holds K·v̂ of the last iterate: normalise and take the damping's Rayleigh quotient.
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.iter_mut().for_each(|x| *x /= norm);
    apply(&v, &mut w, true);
    let c = v.iter().zip(&w).map(|(a, b)| a * b).sum::<f64>();
    let omega = lambda.sqrt();
    let zeta = c / (2.0 * omega);
    2.0 * ((1.0 + zeta * zeta).sqrt() - zeta) / omega
}

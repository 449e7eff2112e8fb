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
use super::world::WallSpec;
use crate::contact_law::{ContactSpec, Law};
use crate::geometry::Shape;

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

/// The largest normal lever arm `|r × n|` a contact can have on this shape (the largest distance
/// from the centroid to a boundary normal line): circle 0, ellipse `|a − b|`, rectangle half its
/// diagonal (a corner can take any normal).
pub fn max_normal_lever(shape: &Shape) -> f64 {
    match *shape {
        Shape::Circle { .. } => 0.0,
        Shape::Ellipse { a, b } => (a - b).abs(),
        Shape::Rectangle { w, h } => 0.5 * w.hypot(h),
    }
}

/// An a-priori estimate of the critical time step of a scene, from the stiffest contact it can
/// have: the two bodies with the largest inverse effective masses (normal and tangential, with
/// the worst lever arms), or the lightest body against a wall, under every contact law of the
/// scene. For Hertz–Mindlin the stiffness grows with the overlap: it is evaluated at an overlap
/// of 1 % of the smallest body's inscribed radius (the observed value is reported separately).
pub fn estimate_critical_dt(
    bodies: &Bodies,
    spec: &ContactSpec,
    walls: &[WallSpec],
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
        let ln = max_normal_lever(&bodies.shape[k]);
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
    let mut cases: Vec<(&ContactSpec, f64, f64, usize, Option<usize>)> = Vec::new();
    if let (Some(n2), Some(t2)) = (n2, t2) {
        cases.push((spec, n1.0 + n2.0, t1.0 + t2.0, n1.1, Some(n2.1)));
    }
    for w in walls {
        cases.push((&w.spec, n1.0, t1.0, n1.1, None));
    }
    for (s, w_n, w_t, a, b) in cases {
        let m_eff = match b {
            Some(b) => 1.0 / (bodies.inv_mass[a] + bodies.inv_mass[b]),
            None => bodies.mass[a],
        };
        let rho = match b {
            Some(b) => 0.5 * (bodies.density[a] + bodies.density[b]),
            None => bodies.density[a],
        };
        let (kn, eta_n, kt, eta_t) = match s.resolve(spec, rho, g, m_eff) {
            Law::Linear(l) => (
                l.kn,
                l.eta_n,
                if l.friction > 0.0 { l.ks } else { 0.0 },
                l.eta_s,
            ),
            Law::HertzMindlin(h) => {
                // R* of two such bodies (or body and wall), with the body's bounding radius.
                let r = bodies.bound[a];
                let r_eff = if b.is_some() { 0.5 * r } else { r };
                let root = (r_eff * delta).sqrt();
                let kn = 2.0 * h.e_star * root; // dF/dδ = (3/2)(4/3)E*√(R*δ)
                let eta = h.beta * (m_eff * kn).sqrt();
                let kt = if h.friction > 0.0 {
                    8.0 * h.g_star * root
                } else {
                    0.0
                };
                (kn, eta, kt, eta)
            }
        };
        dt = dt
            .min(critical_dt(kn, eta_n, w_n))
            .min(critical_dt(kt, eta_t, w_t));
    }
    dt
}

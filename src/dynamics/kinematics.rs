//! The kinematic facts of a contact that the law needs and no shape-blind law can compute: the
//! relative velocity of the two material points at the contact point, the effective mass m*
//! (T13), the effective radius R* (T11), the pair's density (for parameters given per ρg), and
//! the rolling radius and inertia.
//!
//! # Rolling radius and inertia (dem2d's choice for non-round bodies)
//! Ai et al.'s rolling couple is `μ_r R_r F_n`, with `R_r = R*` for spheres: for a sphere R* is
//! the lever of the tangential (friction) force about the centre. dem2d takes, for every shape,
//! **each body's support distance along the contact normal** — the distance `ℓ` from its
//! centroid to the tangent line at the contact, the lever arm of the tangential force — and
//! combines them like R*: `1/R_r = 1/ℓ_i + 1/ℓ_j` (a wall: `ℓ = ∞`, so `R_r = ℓ` of the body).
//! - For disks `ℓ = r` exactly, so `R_r` is R* (LIGGGHTS, PFC).
//! - On a slope β the friction force `m g sin β` has the moment `m g sin β · ℓ` about the
//!   centroid and the rolling couple's cap is `μ_r ℓ m g cos β`, whatever the shape and where it
//!   touches. A disk (its contact straight below its centre) therefore rests iff
//!   `tan β ≤ μ_r`, Ai et al.'s meaning of μ_r; a non-circular body's normal force has a moment
//!   of its own, and it rests iff `tan β ≤ μ_r + k`, k the largest ratio of its contact point's
//!   downhill offset to its centroid's height (ellipse: `(a² − b²)/(2ab)`; `tests/rolling.rs`,
//!   `an_ellipse_rests_on_slopes_up_to_mu_r_plus_its_shapes_own_limit`).
//! - It is defined for every contact, bounded by the inscribed and circumscribed radii
//!   (ellipse: b on its flat side, a on its tip; rectangle: half a side on a face, up to half
//!   the diagonal on a corner).
//!
//! The alternative the issue suggested, the radius of curvature at the contact point
//! (`a²b²/h³` for an ellipse), fails both tests: it is infinite on a rectangle's face and zero
//! at its corner, and on an ellipse it is largest on the flat side (a²/b) and smallest at the
//! tip (b²/a) — the opposite of the lever, so a rolling couple from it would hold an a/b = 2
//! ellipse lying on its flat side on slopes up to `tan β = 4μ_r`, and standing on its tip only
//! up to `μ_r/4` (with ℓ: μ_r for both). Curvature sets the width of a Hertz contact patch (`∝ √(Rδ)`), not the lever
//! of the friction force, which is what Ai et al.'s `R_r` multiplies. (The Rocky DEM manual's
//! choice, the distance from the centroid to the contact point, is the same as ℓ at an
//! ellipse's axes and a rectangle's face centres, and larger elsewhere.)
//!
//! Polygons need no special case: a vertex has infinite curvature (R = 0), which no
//! curvature-based radius could use, but its support distance along any normal is finite — the
//! distance from the centroid to the tangent line through that vertex — and bounded by the
//! polygon's inscribed and bounding radii.
//!
//! The rolling inertia is the pair's equivalent moment of inertia for a rotation about the
//! contact point (Ai et al.; LIGGGHTS): `1/I_r = 1/(I_i + m_i d_i²) + 1/(I_j + m_j d_j²)` with
//! `d` the distance from each centroid to the contact point (parallel axes; a wall or a prescribed body: ∞);
//! for a disk on a wall `1.5 m r²` (LIGGGHTS' 2D value).

use super::body::Bodies;
use super::boundary::Boundary;
use super::partner::{Partner, Sides};
use crate::contact_law::params::pair_density;
use crate::contact_law::{CohesionKinematics, Kinematics, Needs, RollingKinematics, SpringOn};
use crate::geometry::Vec2;
use crate::geometry::overlap_area::DiskLens;

/// A contact as the kinematics sees it: the two sides, where the force acts, along which
/// normal (from the giver to the receiver), how deep, and what the spring acts on.
pub struct Contact<'a> {
    pub bodies: &'a Bodies,
    pub walls: &'a [Boundary],
    pub sides: Sides,
    pub point: Vec2,
    pub normal: Vec2,
    pub depth: f64,
    pub spring: &'a SpringOn,
    /// The overlap chord and area, where the pass asked for them (a cohesive scene).
    pub cohesion: Option<CohesionKinematics>,
}

/// What the law reads of the contact `c` (T5–T22: [`Kinematics`]): the overlap its spring acts
/// on, the relative velocity and spin at the contact point, and what the law `needs` beyond
/// them (NaN where it does not): R*, the rolling radius and inertias (`slots(k)`: body k's
/// number of contacts, the CDT limiter's share); `m_eff` m* (NaN unless the law
/// reads it), `dt` the step.
#[inline(always)]
pub fn of_contact(
    c: &Contact,
    m_eff: f64,
    needs: Needs,
    dt: f64,
    slots: impl Fn(usize) -> u32,
) -> Kinematics {
    let (b, sides, n) = (c.bodies, c.sides, c.normal);
    let t = Vec2::new(-n.y, n.x);
    let rel = relative(b, c.walls, sides, c.point, c.normal);
    let vn = rel.velocity.dot(&n);
    let (depth, energy_depth) = c.spring.depths(c.depth);
    Kinematics {
        depth,
        energy_depth,
        vn,
        vt: rel.velocity.dot(&t),
        m_eff,
        r_eff: if needs.r_eff {
            effective_radius_for(b, sides, n, c.spring.lens())
        } else {
            f64::NAN
        },
        dt,
        area: c.spring.area_kinematics(vn, rel.spin),
        spin: rel.spin,
        rolling: if needs.rolling {
            rolling(b, sides, c.point, n, slots)
        } else {
            RollingKinematics {
                radius: f64::NAN,
                inertia: f64::NAN,
                spin_inertia: f64::NAN,
            }
        },
        cohesion: if needs.cohesion { c.cohesion } else { None },
    }
}

/// The kinematics the a-priori critical step assumes ([`super::timestep`]) for a contact of body
/// `a` with body `b` (two bodies like `a`: R* = r/2), or with a wall (`b` `None`: R* = r), at
/// the overlap `depth` and at rest: R* and the rolling radius from `a`'s bounding radius r, the
/// rolling inertia about a point on its bounding circle (halved for two bodies), m* of the two.
pub fn worst_case(bodies: &Bodies, a: usize, b: Option<usize>, depth: f64) -> Kinematics {
    let m_eff = match b {
        Some(b) => 1.0 / (bodies.inv_mass[a] + bodies.inv_mass[b]),
        None => bodies.mass[a],
    };
    let r = bodies.bound[a];
    let r_eff = if b.is_some() { 0.5 * r } else { r };
    let pivot = bodies.inertia[a] + bodies.mass[a] * r * r;
    Kinematics {
        depth,
        energy_depth: depth,
        vn: 0.0,
        vt: 0.0,
        m_eff,
        r_eff,
        dt: 0.0,
        area: None,
        spin: 0.0,
        rolling: RollingKinematics {
            radius: r_eff,
            inertia: if b.is_some() { 0.5 * pivot } else { pivot },
            spin_inertia: bodies.inertia[a],
        },
        cohesion: None,
    }
}

/// The relative motion at a contact point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Relative {
    /// Velocity of the receiver's material point minus the giver's (a wall's: its velocity).
    pub velocity: Vec2,
    /// Relative spin `ω_receiver − ω_giver` (a wall's: its angular velocity, 0 unless it turns).
    pub spin: f64,
}

/// The relative motion of the two sides at `point` (`normal` the contact's: a drum's material
/// point there, see [`Boundary::lever`]).
#[inline(always)]
pub fn relative(
    b: &Bodies,
    walls: &[Boundary],
    sides: Sides,
    point: Vec2,
    normal: Vec2,
) -> Relative {
    let recv = sides.receiver;
    let mut velocity = b.point_velocity(recv, point - b.state[recv].pose.position);
    let mut spin = b.state[recv].omega;
    match sides.giver {
        Partner::Body(k) => {
            velocity -= b.point_velocity(k, point - centroid(b, k, sides));
            spin -= b.state[k].omega;
        }
        Partner::Wall(w) => {
            // A turning boundary's material point moves at v + ω ẑ × (x − P).
            velocity -= walls[w].velocity_at(point, normal);
            spin -= walls[w].omega();
        }
    }
    if let Some(image) = sides.image {
        // The giver's periodic image moves with the cell's shear as well as with the giver.
        velocity -= image.velocity;
    }
    Relative { velocity, spin }
}

/// Body `k`'s centroid as a side of `sides`: its own, or (the giver seen through a periodic
/// seam) its image's.
#[inline(always)]
fn centroid(b: &Bodies, k: usize, sides: Sides) -> Vec2 {
    match sides.image {
        Some(image) if sides.giving_body() == Some(k) => b.state[k].pose.position + image.offset,
        Some(_) | None => b.state[k].pose.position,
    }
}

/// The pair's `1/m* = Σ 1/m` (T13; a wall adds nothing).
#[inline(always)]
pub fn inv_mass(b: &Bodies, sides: Sides) -> f64 {
    let mut inv_mass = b.inv_mass[sides.receiver];
    if let Some(k) = sides.giving_body() {
        inv_mass += b.inv_mass[k];
    }
    inv_mass
}

/// The density the pair's per-ρg parameters are scaled by ([`pair_density`]).
#[inline]
pub fn density(b: &Bodies, sides: Sides) -> f64 {
    pair_density(
        b.density[sides.receiver],
        sides.giving_body().map(|k| b.density[k]),
    )
}

/// Hertz's effective radius `R* = (1/R_i + 1/R_j)⁻¹` (T11) from each body's radius of
/// curvature where it touches (`n` from the giver to the receiver; a wall has R = ∞).
#[inline]
pub fn effective_radius(b: &Bodies, sides: Sides, n: Vec2) -> f64 {
    let mut inv_r = 1.0 / b.curvature_radius(sides.receiver, -n);
    if let Some(k) = sides.giving_body() {
        inv_r += 1.0 / b.curvature_radius(k, n);
    }
    1.0 / inv_r // T(11)
}

/// R* as the law takes it: the area potential's lens (the equal-area disks', so that its
/// potential depends on A alone) when the spring acts on one, else [`effective_radius`].
#[inline]
pub fn effective_radius_for(b: &Bodies, sides: Sides, n: Vec2, lens: Option<DiskLens>) -> f64 {
    match lens {
        Some(lens) => lens.effective_radius(),
        None => effective_radius(b, sides, n),
    }
}

/// The rolling radius and inertias of a contact at `point` with normal `n` (from the giver to
/// the receiver): see the module documentation. `slots(k)` is the number of contacts of body k
/// (the CDT limiter's share, see `contact_law::rolling`; at least 1).
pub fn rolling(
    b: &Bodies,
    sides: Sides,
    point: Vec2,
    n: Vec2,
    slots: impl Fn(usize) -> u32,
) -> RollingKinematics {
    let side = |k: usize, outward: Vec2| {
        let lever = b.support_distance(k, outward);
        let d2 = (point - centroid(b, k, sides)).norm_squared();
        let share = slots(k).max(1) as f64 * b.inv_inertia[k];
        // A prescribed body turns about no point but as prescribed: infinite inertia.
        let pivot = if b.inv_inertia[k] == 0.0 {
            f64::INFINITY
        } else {
            b.inertia[k] + b.mass[k] * d2
        };
        (lever, pivot, share)
    };
    let (l_r, i_r, s_r) = side(sides.receiver, -n);
    match sides.giving_body() {
        Some(k) => {
            let (l_g, i_g, s_g) = side(k, n);
            RollingKinematics {
                radius: 1.0 / (1.0 / l_r + 1.0 / l_g),
                inertia: 1.0 / (1.0 / i_r + 1.0 / i_g),
                spin_inertia: 1.0 / (s_r + s_g),
            }
        }
        None => RollingKinematics {
            radius: l_r,
            inertia: i_r,
            spin_inertia: 1.0 / s_r,
        },
    }
}

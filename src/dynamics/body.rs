//! Bodies, stored as a structure of arrays (one vector per quantity) so that the step loops
//! touch only what they use.

use crate::geometry::mass::{area, inertia_per_mass};
use crate::geometry::{Pose, Shape, Vec2};

/// A body as a scene describes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyInit {
    pub shape: Shape,
    pub position: Vec2,
    pub angle: f64,
    pub velocity: Vec2,
    pub omega: f64,
    pub density: f64,
    /// Its material (0: the scene's contact law; see [`super::materials`]).
    pub material: u16,
    /// Its motion is prescribed: it moves at `velocity` and spins at `omega` throughout (at
    /// rest when both are zero: a fixed body), pushed by its contacts but never moved by them
    /// (see [`Bodies`]).
    pub prescribed: bool,
}

/// What changes every step of one body, in one cache line: the contact pass reads it for the
/// two bodies of every pair, in no particular order.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct BodyState {
    /// Position and orientation (with the orientation's cosine and sine).
    pub pose: Pose,
    /// Velocity of the centroid and angular velocity.
    pub vel: Vec2,
    pub omega: f64,
}

/// All bodies. Index `k` of every vector is body `k`.
///
/// # Bodies whose motion is prescribed
/// A prescribed body ([`BodyInit::prescribed`]) is held in the same vectors with infinite mass
/// and inertia against its contacts (`inv_mass = inv_inertia = 0`: the kicks leave its velocity
/// and spin as they are, the drift moves it, a pair's m* is the other body's) and no mass of its
/// own (`mass = inertia = 0`: gravity does not act on it, and its energy of motion and position
/// is not the scene's). Its force and moment are then its contacts' alone: the reaction the
/// scene exerts on it. The work it does on the scene is a boundary's (see `super::step`).
#[derive(Clone, Debug, Default)]
pub struct Bodies {
    pub shape: Vec<Shape>,
    pub density: Vec<f64>,
    /// Material (see [`super::materials`]).
    pub material: Vec<u16>,
    /// Mass per unit thickness, `m = ρ·area`.
    pub mass: Vec<f64>,
    pub inv_mass: Vec<f64>,
    /// Moment of inertia about the centroid (T2 in 2D).
    pub inertia: Vec<f64>,
    pub inv_inertia: Vec<f64>,
    /// Radius of the bounding circle about the centroid.
    pub bound: Vec<f64>,
    /// Radius of the disk of the same area (the area law's equivalent lens).
    pub area_radius: Vec<f64>,
    /// `1/area_radius` (the lens's series wants inverse radii: kept to spare two divisions per
    /// contact).
    pub inv_area_radius: Vec<f64>,
    /// Pose and velocities.
    pub state: Vec<BodyState>,
    /// The body is a circle (its orientation enters no contact; the drift reads this rather
    /// than the whole shape).
    pub is_circle: Vec<bool>,
    /// Force and moment of the last evaluation (contacts and gravity).
    pub force: Vec<Vec2>,
    pub torque: Vec<f64>,
    /// In a periodic cell, how often each body crossed its seams (`i_x`, `i_y`: see
    /// [`super::cell::Cell::unwrapped`]); empty otherwise.
    pub image: Vec<[i32; 2]>,
    /// The prescribed bodies, in order.
    pub prescribed: Vec<usize>,
    /// Each body's identity: its index in the case's `bodies`, or for a body inserted during
    /// the run the next number after every identity given before (see
    /// [`super::flow`]). Never reused: a removed body's number stays unused, so that the
    /// outputs of a run whose bodies come and go name each body by one number throughout. It
    /// equals the index until a body is removed.
    pub id: Vec<u64>,
}

impl Bodies {
    /// Adds the image counts of the bodies that re-entered a periodic cell (each crossing: the
    /// body, the counts to add, the kinetic energy per unit mass it gained); returns the kinetic
    /// energy they gained.
    pub(crate) fn re_enter<'a>(
        &mut self,
        crossings: impl Iterator<Item = &'a (u32, [i32; 2], f64)>,
    ) -> f64 {
        let mut gained = 0.0;
        for &(k, d, e) in crossings {
            let im = &mut self.image[k as usize];
            im[0] += d[0];
            im[1] += d[1];
            gained += self.mass[k as usize] * e;
        }
        gained
    }

    /// Bodies from their descriptions.
    pub fn new(inits: &[BodyInit]) -> Self {
        let n = inits.len();
        let mut b = Bodies {
            shape: Vec::with_capacity(n),
            density: Vec::with_capacity(n),
            material: Vec::with_capacity(n),
            mass: Vec::with_capacity(n),
            inv_mass: Vec::with_capacity(n),
            inertia: Vec::with_capacity(n),
            inv_inertia: Vec::with_capacity(n),
            bound: Vec::with_capacity(n),
            area_radius: Vec::with_capacity(n),
            inv_area_radius: Vec::with_capacity(n),
            state: Vec::with_capacity(n),
            is_circle: Vec::with_capacity(n),
            force: Vec::with_capacity(n),
            torque: Vec::with_capacity(n),
            image: Vec::new(),
            prescribed: Vec::new(),
            id: Vec::with_capacity(n),
        };
        for (k, init) in inits.iter().enumerate() {
            b.push(init, k as u64);
        }
        b
    }

    /// Appends the body `init` with identity `id` (its force and moment zero; in a periodic
    /// cell the caller gives it its image counts).
    pub fn push(&mut self, init: &BodyInit, id: u64) {
        let k = self.len();
        let m = init.density * area(&init.shape);
        let i = m * inertia_per_mass(&init.shape);
        self.shape.push(init.shape);
        self.density.push(init.density);
        self.material.push(init.material);
        if init.prescribed {
            self.prescribed.push(k);
            self.mass.push(0.0);
            self.inv_mass.push(0.0);
            self.inertia.push(0.0);
            self.inv_inertia.push(0.0);
        } else {
            self.mass.push(m);
            self.inv_mass.push(1.0 / m);
            self.inertia.push(i);
            self.inv_inertia.push(1.0 / i);
        }
        self.bound.push(init.shape.bounding_radius());
        let area_radius = (area(&init.shape) / std::f64::consts::PI).sqrt();
        self.area_radius.push(area_radius);
        self.inv_area_radius.push(1.0 / area_radius);
        self.is_circle.push(init.shape.is_circle());
        self.state.push(BodyState {
            pose: Pose::new(init.position, init.angle),
            vel: init.velocity,
            omega: init.omega,
        });
        self.force.push(Vec2::zeros());
        self.torque.push(0.0);
        self.id.push(id);
    }

    /// Keeps the bodies `k` with `keep[k]`, in their order (the others' rows removed from
    /// every vector; the prescribed bodies' indices renumbered).
    pub fn retain(&mut self, keep: &[bool]) {
        fn cut<T>(v: &mut Vec<T>, keep: &[bool]) {
            if v.is_empty() {
                return;
            }
            let mut k = 0;
            v.retain(|_| {
                k += 1;
                keep[k - 1]
            });
        }
        cut(&mut self.shape, keep);
        cut(&mut self.density, keep);
        cut(&mut self.material, keep);
        cut(&mut self.mass, keep);
        cut(&mut self.inv_mass, keep);
        cut(&mut self.inertia, keep);
        cut(&mut self.inv_inertia, keep);
        cut(&mut self.bound, keep);
        cut(&mut self.area_radius, keep);
        cut(&mut self.inv_area_radius, keep);
        cut(&mut self.state, keep);
        cut(&mut self.is_circle, keep);
        cut(&mut self.force, keep);
        cut(&mut self.torque, keep);
        cut(&mut self.image, keep);
        cut(&mut self.id, keep);
        self.prescribed = (0..self.len())
            .filter(|&k| self.inv_mass[k] == 0.0)
            .collect();
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.shape.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.shape.is_empty()
    }

    /// Whether body `k`'s motion is prescribed.
    #[inline]
    pub fn is_prescribed(&self, k: usize) -> bool {
        self.inv_mass[k] == 0.0
    }

    /// Velocity of body `k`'s material point at offset `r` from its centroid: `v + ω × r`.
    #[inline]
    pub fn point_velocity(&self, k: usize, r: Vec2) -> Vec2 {
        self.state[k].vel + Vec2::new(-r.y, r.x) * self.state[k].omega
    }

    /// Radius of curvature of body `k`'s boundary where its outward normal is `n` (world), for
    /// the Hertz radius R* (T11): see [`Shape::curvature_radius`].
    #[inline]
    pub fn curvature_radius(&self, k: usize, n: Vec2) -> f64 {
        self.shape[k].curvature_radius(self.state[k].pose.to_body_vector(n))
    }

    /// Distance from body `k`'s centroid to its tangent line whose outward normal is `n`
    /// (world, unit): its support along `n` ([`Shape::support`]).
    #[inline]
    pub fn support_distance(&self, k: usize, n: Vec2) -> f64 {
        self.shape[k].support(self.state[k].pose.to_body_vector(n))
    }
}

//! A periodic cell: the scene repeats in x (and in y), Lees–Edwards shear, and an imposed normal
//! stress.
//!
//! # The cell
//! The cell spans `[0, L_x) × [0, L_y)`. With `"periodic": "x"` the scene repeats every `L_x`
//! in x and the case's walls bound it in y; with `"xy"` it repeats in both directions and has
//! no walls. Every body's centroid is kept in the cell: a body that leaves it through a seam
//! re-enters through the opposite one, and its image count `(i_x, i_y)` records how often it
//! crossed (so that its unwrapped position can be rebuilt: see [`Cell::unwrapped`]). A pair of
//! bodies interacts through the nearest image of its giver ([`Cell::nearest_image`]): the
//! contact pass shifts the giver's pose by the image's offset (and its velocity by the image's
//! velocity) where the pair's sides are built, so the narrow phase and the law never know a
//! cell exists. For the nearest image to be the only one within reach, every side of the cell
//! must exceed twice the reach of a pair (two bounding diameters and the neighbour list's skin):
//! [`Cell::check_size`].
//!
//! # Lees–Edwards shear (Lees & Edwards, J. Phys. C 5 (1972) 1921)
//! With a shear rate γ̇ (`"shear_rate"`, periodic in x and y) the image of the cell above is
//! shifted in x by `s(t) = ∫ γ̇ L_y dt` (kept modulo `L_x`: [`Cell::offset`]) and moves at
//! `+γ̇ L_y` relative to the cell: a body leaving through the top re-enters at the bottom with
//! `x − s` and `v_x − γ̇ L_y`, and one leaving through the bottom re-enters at the top with
//! `x + s` and `v_x + γ̇ L_y`. A steady simple shear `v_x = γ̇ (y − L_y/2)` is then continuous
//! across the seam. The unwrapped position of a body is `x + i_x L_x + i_y S` with `S` the
//! total shift (not taken modulo `L_x`: [`Cell::shift`]), continuous in time across a crossing.
//!
//! # Imposed pressure
//! With `"pressure": P` the cell's height follows the normal stress σ_yy (the Love–Weber mean
//! stress over the cell with its kinetic part, compressive positive: [`Cell::stress`]): each
//! step `L_y ← λ L_y` and every body's `y ← λ y` (an affine stretch), with
//! `λ − 1 = α (σ_yy − P)/K_yy` — the error corrected by the fraction α (`"pressure_gain"`,
//! default [`PRESSURE_RELAXATION`]) against the contacts' affine stiffness K_yy, the rule of
//! the servo walls (`dynamics::boundary`); the bodies behind the contacts are softer than their
//! affine stiffness, so the actual correction is smaller and the control does not overshoot.
//! A cell pushed harder than P dilates; one below P contracts. See [`Cell::stretch`].
//!
//! # Stress and strain-rate control of each side
//! Each side of an `"xy"` cell can be controlled on its own ([`Cell::control`]): held at a
//! normal stress (`"stress": {"xx": S_xx, "yy": S_yy}`; `"pressure": P` is `{"yy": P}`), its
//! length following σ_xx or σ_yy by the rule above against that side's affine stiffness `K_xx =
//! (1/A) Σ_c k_n (n_x l_x)²` or `K_yy`; or strained at a true rate ε̇ (`"strain_rate": {"yy":
//! ε̇}`, 1/s, negative compresses): `L ← L exp(ε̇ Δt)` every step. Every body's coordinate along
//! a stretched side is stretched with it; a stretch of x stretches the Lees–Edwards shift too
//! (the image lattice deforms affinely, and a body's unwrapped position with it). The isotropic
//! compression of a sample to a stress and the biaxial test — one side strained, the other
//! held at its stress — run without walls (PFC's and Yade's `PeriTriaxController`, LAMMPS's
//! `fix press/berendsen` and `fix deform`). The stretch's work is booked side by side (see
//! [`Cell::stretch`]).

use super::partner::ImageShift;
use crate::geometry::Vec2;

/// The directions in which a cell repeats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Periodic {
    /// In x; walls bound the scene in y.
    X,
    /// In x and y.
    XY,
}

impl Periodic {
    /// The name used in case files.
    pub fn as_str(&self) -> &'static str {
        match self {
            Periodic::X => "x",
            Periodic::XY => "xy",
        }
    }
}

/// An imposed normal stress on a cell periodic in x and y (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pressure {
    /// The target σ_yy (dyn/cm² per unit thickness: force per unit length), > 0.
    pub target: f64,
    /// The fraction α of the stress error corrected per step ([`PRESSURE_RELAXATION`] by
    /// default; see [`Cell::stretch`]).
    pub gain: f64,
}

/// How one side of a cell moves (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SideControl {
    /// The side's length follows its normal stress towards a target.
    Stress(Pressure),
    /// The side is strained at a true rate ε̇ (1/s; negative compresses): `L ← L exp(ε̇ Δt)`.
    StrainRate(f64),
}

/// A periodic cell (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    /// `L_x`, `L_y` now (cm).
    pub size: Vec2,
    pub periodic: Periodic,
    /// γ̇ (1/s; 0: no shear).
    pub shear_rate: f64,
    /// The x shift of the image above, in `[0, L_x)`.
    pub offset: f64,
    /// The total x shift `S = ∫ γ̇ L_y dt` (not reduced modulo `L_x`).
    pub shift: f64,
    /// How each side (x, y) moves: `None` for a fixed side.
    pub control: [Option<SideControl>; 2],
    /// The cell's mean stress at the last force evaluation, compressive positive: `(1/A)(Σ_c
    /// f ⊗ l + Σ_k m v′ ⊗ v′)` (xx, xy, yx, yy; Love–Weber over the pairs of bodies, f the
    /// force on the receiver and l the branch vector to it from the giver's image; v′ the
    /// velocity about the shear's mean flow `γ̇ (y − L_y/2)`).
    pub stress: [f64; 4],
    /// `(1/A) Σ_c F_s n_x l_x` and `(1/A) Σ_c F_s n_y l_y` (F_s the elastic part of a
    /// contact's normal force): minus the rate at which the contacts' stored energy changes per
    /// unit affine strain along x and along y.
    pub elastic: [f64; 2],
    /// The contacts' affine stiffness against a stretch along x and along y, `(1/A) Σ_c k_n
    /// (n_x l_x)²` and `(1/A) Σ_c k_n (n_y l_y)²` (the change of σ_xx or σ_yy per unit strain
    /// along it, with the bodies moved affinely).
    pub stiffness: [f64; 2],
    /// `λ − 1` of each side's stretch in the step under way, whose work's second half waits for
    /// the forces at its end ([`Cell::measure`]); 0 between steps.
    pub strained: [f64; 2],
}

/// The relaxation factor of an imposed pressure: the fraction of the stress error the cell's
/// height corrects per step against the contacts' affine stiffness (see [`Cell::stretch`]).
pub const PRESSURE_RELAXATION: f64 = 0.1;

/// The largest relative change of a cell's height in one step under an imposed pressure.
pub const MAX_STRETCH: f64 = 1e-4;

/// The lattice of a cell's images when the neighbour list was built: the Lees–Edwards shift
/// and the sides. The images of a body move with the lattice, not only with the body: between
/// builds, a pair through an image approaches by at most the two bodies' displacements plus
/// the lattice's ([`Cell::lattice_drift`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LatticeMark {
    /// `S`, the total shift (not reduced modulo `L_x`).
    pub shift: f64,
    /// `L_x`, `L_y`.
    pub size: Vec2,
}

/// What a crossing did to a body: its new position and velocity, and the image counts to add.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wrapped {
    pub position: Vec2,
    pub velocity: Vec2,
    pub images: [i32; 2],
}

impl Cell {
    /// A cell of size `size` repeating in `periodic`, with shear rate `shear_rate` and an
    /// optional imposed normal stress; the image above starts unshifted.
    pub fn new(
        size: Vec2,
        periodic: Periodic,
        shear_rate: f64,
        pressure: Option<Pressure>,
    ) -> Self {
        Cell {
            size,
            periodic,
            shear_rate,
            offset: 0.0,
            shift: 0.0,
            control: [None, pressure.map(SideControl::Stress)],
            stress: [0.0; 4],
            elastic: [0.0; 2],
            stiffness: [0.0; 2],
            strained: [0.0; 2],
        }
    }

    /// Records the stress and stiffness of a force evaluation from its sums: `contact` the
    /// pass's `Σ f ⊗ l`, `stiffness` its `Σ k_n (n_y l_y)²`, `elastic` its `Σ F_s n_y l_y`
    /// (`slots`), `kinetic` the bodies' `Σ m v′v′` (xx, xy, yy); returns the second half of the
    /// work of the step's stretch (see [`Cell::stretch`]; 0 outside a step).
    pub(crate) fn measure(
        &mut self,
        slots: &super::contact_pass::SlotPartial,
        kinetic: &[f64; 3],
    ) -> f64 {
        let (contact, stiffness, elastic) = (&slots.stress, slots.stiffness, slots.elastic_n);
        let a = self.area();
        self.stress = [
            (contact[0] + kinetic[0]) / a,
            (contact[1] + kinetic[1]) / a,
            (contact[2] + kinetic[1]) / a,
            (contact[3] + kinetic[2]) / a,
        ];
        self.elastic = [elastic[0] / a, elastic[1] / a];
        self.stiffness = [stiffness[0] / a, stiffness[1] / a];
        let mut work = -0.5 * elastic[1] * self.strained[1];
        if self.strained[0] != 0.0 {
            work += -0.5 * elastic[0] * self.strained[0];
        }
        self.strained = [0.0; 2];
        work
    }

    /// The imposed normal stress on the horizontal faces (σ_yy's target), if y follows one:
    /// the case's `pressure`.
    pub fn pressure(&self) -> Option<Pressure> {
        match self.control[1] {
            Some(SideControl::Stress(p)) => Some(p),
            _ => None,
        }
    }

    /// Whether a side of the cell moves (follows a stress or a strain rate).
    pub fn deforms(&self) -> bool {
        self.control.iter().any(Option::is_some)
    }

    /// σ_xx (`side` 0) or σ_yy (1), compressive positive (NaN where the cell does not measure
    /// it).
    pub fn normal_stress_of(&self, side: usize) -> f64 {
        match (self.measures_stress(), side) {
            (false, _) => f64::NAN,
            (true, 0) => self.stress[0],
            (true, _) => self.stress[3],
        }
    }

    /// `Σ m v′v′` (xx, xy, yy) of `bodies` about the shear's mean flow.
    pub fn kinetic_stress(&self, bodies: &super::body::Bodies) -> [f64; 3] {
        let mut k = [0.0; 3];
        for (s, &m) in bodies.state.iter().zip(&bodies.mass) {
            self.add_kinetic_stress(&mut k, m, s.vel, s.pose.position);
        }
        k
    }

    /// Adds a body's `m v′v′` (xx, xy, yy) to `k`: mass `m`, velocity `vel`, at `position`.
    #[inline]
    pub fn add_kinetic_stress(&self, k: &mut [f64; 3], m: f64, vel: Vec2, position: Vec2) {
        let v = Vec2::new(vel.x - self.mean_flow(position.y), vel.y);
        k[0] += m * v.x * v.x;
        k[1] += m * v.x * v.y;
        k[2] += m * v.y * v.y;
    }

    /// Whether the cell measures its stress: a cell periodic in x and y (in an `"x"` cell the
    /// walls carry part of the load, and the packing's stress is `analysis`'s).
    #[inline]
    pub fn measures_stress(&self) -> bool {
        self.periodic_y()
    }

    /// σ_yy, the normal stress on the cell's horizontal faces (compressive positive; NaN where
    /// the cell does not measure it).
    pub fn normal_stress(&self) -> f64 {
        if self.measures_stress() {
            self.stress[3]
        } else {
            f64::NAN
        }
    }

    /// The shear stress `(σ_xy + σ_yx)/2` (NaN where the cell does not measure it).
    pub fn shear_stress(&self) -> f64 {
        if self.measures_stress() {
            0.5 * (self.stress[1] + self.stress[2])
        } else {
            f64::NAN
        }
    }

    /// The cell's sides for the next step, of length `dt`, from their controls and the stress of
    /// the last evaluation; returns the factors `λ = (λ_x, λ_y)` they (and every body's
    /// coordinates) are stretched by (1 for a fixed side) and the first half of the work the
    /// stretch does on the bodies: the change of the contacts' stored energy, `−Σ F_s n·δl =
    /// −(λ_x − 1) Σ F_s n_x l_x − (λ_y − 1) Σ F_s n_y l_y` (the affine stretch changes each
    /// branch vector by `δl = ((λ_x − 1) l_x, (λ_y − 1) l_y)` and no velocity; the shear springs,
    /// which integrate relative velocities, do not see it), taken by the trapezoidal rule: half
    /// with the sums before the stretch here, half with the sums after it when the step's forces
    /// are measured ([`Cell::measure`]) — exact for linear springs, so that a contact the stretch
    /// closes gets its stored energy from the account, not from nowhere. A side held at a
    /// stress corrects the relative error `σ − S` by the fraction α per step against its
    /// affine stiffness: `λ − 1 = α (σ − S)/K` (the servo walls' rule: `dynamics::boundary`), at
    /// most [`MAX_STRETCH`] either way (and that much, towards the target, without contacts); a
    /// side strained at a rate ε̇ takes `λ = exp(ε̇ Δt)`. A stretch of x stretches the
    /// Lees–Edwards shift with it.
    pub fn stretch(&mut self, dt: f64) -> (Vec2, f64) {
        let mut lambda = [1.0, 1.0];
        let mut work = 0.0;
        let a = self.area();
        // y first: its figures are those of the cell before x could move.
        for side in [1, 0] {
            let Some(control) = self.control[side] else {
                continue;
            };
            let l = match control {
                SideControl::Stress(p) => {
                    let error = self.normal_stress_of(side) - p.target;
                    let k = self.stiffness[side];
                    let strain = if k > 0.0 {
                        p.gain * error / k
                    } else {
                        MAX_STRETCH.copysign(error)
                    };
                    1.0 + strain.clamp(-MAX_STRETCH, MAX_STRETCH)
                }
                SideControl::StrainRate(rate) => (rate * dt).exp(),
            };
            work += -0.5 * a * self.elastic[side] * (l - 1.0);
            self.strained[side] = l - 1.0;
            lambda[side] = l;
        }
        self.size.y *= lambda[1];
        if self.control[0].is_some() {
            self.size.x *= lambda[0];
            self.shift *= lambda[0];
            self.offset = (self.offset * lambda[0]).rem_euclid(self.size.x);
        }
        (Vec2::new(lambda[0], lambda[1]), work)
    }

    /// Whether `p` (inside the cell) lies within `margin` of one of its seams.
    #[inline]
    pub fn near_seam(&self, p: Vec2, margin: f64) -> bool {
        p.x < margin
            || p.x > self.size.x - margin
            || (self.periodic_y() && (p.y < margin || p.y > self.size.y - margin))
    }

    /// Whether the cell repeats in y.
    #[inline]
    pub fn periodic_y(&self) -> bool {
        self.periodic == Periodic::XY
    }

    /// The smallest side a cell may have for pairs that reach `reach` (the largest bounding
    /// diameter plus the neighbour list's skin): more than twice that, so that a pair has at
    /// most one image within reach. Returns the side that is too small, if one is.
    pub fn check_size(&self, reach: f64) -> Result<(), (usize, f64)> {
        let least = 2.0 * reach;
        let sides = [self.size.x, self.size.y];
        let n = if self.periodic_y() { 2 } else { 1 };
        match (0..n).find(|&k| sides[k] <= least) {
            Some(k) => Err((k, least)),
            None => Ok(()),
        }
    }

    /// The image of the giver at `giver` nearest to the receiver at `receiver`: the offset to
    /// add to the giver's position (a multiple of the periods, with the Lees–Edwards shift across
    /// the y seam) and the image's velocity relative to the giver (`∓γ̇ L_y` in x across the y
    /// seam). `None` when the giver itself is the nearest. Exact for every pair whose nearest
    /// image lies within half a period of the receiver (every pair within reach, given
    /// [`Cell::check_size`]): the y image first (the one whose height is within half a period),
    /// then the x image.
    #[inline]
    pub fn nearest_image(&self, giver: Vec2, receiver: Vec2) -> Option<ImageShift> {
        let mut d = receiver - giver;
        let mut offset = Vec2::zeros();
        let mut velocity = Vec2::zeros();
        if self.periodic_y() {
            let sy = periods(d.y, self.size.y);
            if sy != 0.0 {
                // The giver's image `sy` cells above: shifted by sy·(s, L_y), moving at sy·γ̇L_y.
                offset = Vec2::new(sy * self.offset, sy * self.size.y);
                velocity.x = sy * self.shear_rate * self.size.y;
                d -= offset;
            }
        }
        let sx = periods(d.x, self.size.x);
        if sx != 0.0 {
            offset.x += sx * self.size.x;
        }
        (offset != Vec2::zeros()).then_some(ImageShift { offset, velocity })
    }

    /// The shortest vector equal to `d` modulo the cell's periods (a lever arm within a body's
    /// reach, measured from a centroid to a contact point that may lie across a seam).
    #[inline]
    pub fn shortest(&self, mut d: Vec2) -> Vec2 {
        if self.periodic_y() {
            let sy = periods(d.y, self.size.y);
            if sy != 0.0 {
                d.x -= sy * self.offset;
                d.y -= sy * self.size.y;
            }
        }
        let sx = periods(d.x, self.size.x);
        if sx != 0.0 {
            d.x -= sx * self.size.x;
        }
        d
    }

    /// A body at `position` with velocity `velocity` brought back into the cell (see the
    /// module documentation); `None` when it is inside.
    #[inline]
    pub fn wrap(&self, position: Vec2, velocity: Vec2) -> Option<Wrapped> {
        let (lx, ly) = (self.size.x, self.size.y);
        let inside_x = position.x >= 0.0 && position.x < lx;
        let inside_y = !self.periodic_y() || (position.y >= 0.0 && position.y < ly);
        if inside_x && inside_y {
            return None;
        }
        let (mut p, mut v) = (position, velocity);
        let mut images = [0i32; 2];
        if !inside_y {
            let mut iy = (p.y / ly).floor();
            p.y -= iy * ly;
            if p.y >= ly {
                p.y -= ly; // (a value just below 0 rounds to L_y)
                iy += 1.0;
            }
            // Re-entering `iy` cells down: back by `iy` shifts. The position takes the offset
            // (the shift modulo L_x, exact enough however long the shear has run); the image
            // count takes the whole periods the shift has run beyond it, so that
            // `x + i_x L_x + i_y S` does not jump.
            p.x -= iy * self.offset;
            v.x -= iy * self.shear_rate * ly;
            images[1] = iy as i32;
            let periods = ((self.shift - self.offset) / lx).round();
            images[0] = -(iy * periods) as i32;
        }
        let mut ix = (p.x / lx).floor();
        p.x -= ix * lx;
        if p.x >= lx {
            p.x -= lx;
            ix += 1.0;
        }
        images[0] += ix as i32;
        Some(Wrapped {
            position: p,
            velocity: v,
            images,
        })
    }

    /// The lattice now, to compare with later ([`Cell::lattice_drift`]).
    #[inline]
    pub fn lattice(&self) -> LatticeMark {
        LatticeMark {
            shift: self.shift,
            size: self.size,
        }
    }

    /// How far an image within reach has moved with the lattice since `mark`, at most: the
    /// shift's advance plus the change of each side (an image one period away moves by the
    /// change of the period; across the sheared seam, by the change of the shift, or by that
    /// less a period when the nearest image changes — no more). A neighbour list built at
    /// `mark` misses no pair while the bodies' displacements and this drift together stay
    /// within its skin. Without it, two bodies at rest on either side of a sheared seam never
    /// met while the shift swept their images through each other (issue 41).
    #[inline]
    pub fn lattice_drift(&self, mark: &LatticeMark) -> f64 {
        (self.shift - mark.shift).abs()
            + (self.size.x - mark.size.x).abs()
            + (self.size.y - mark.size.y).abs()
    }

    /// Advances the Lees–Edwards shift over a step `dt`.
    #[inline]
    pub fn advance(&mut self, dt: f64) {
        if self.shear_rate != 0.0 {
            let ds = self.shear_rate * self.size.y * dt;
            self.shift += ds;
            self.offset = (self.offset + ds).rem_euclid(self.size.x);
        }
    }

    /// [`Cell::unwrapped`], `position` itself for a body in the cell (`[0, 0]`).
    #[inline]
    pub fn unwrapped_at(&self, position: Vec2, images: [i32; 2]) -> Vec2 {
        match images {
            [0, 0] => position,
            images => self.unwrapped(position, images),
        }
    }

    /// The x velocity of the shear's mean flow at height `y`.
    #[inline]
    pub fn mean_flow(&self, y: f64) -> f64 {
        self.shear_rate * (y - 0.5 * self.size.y)
    }

    /// The unwrapped position of a body at `position` with image counts `images`.
    pub fn unwrapped(&self, position: Vec2, images: [i32; 2]) -> Vec2 {
        Vec2::new(
            position.x + images[0] as f64 * self.size.x + images[1] as f64 * self.shift,
            position.y + images[1] as f64 * self.size.y,
        )
    }

    /// The cell's area (per unit thickness).
    pub fn area(&self) -> f64 {
        self.size.x * self.size.y
    }
}

/// The whole number of periods `l` nearest to `d` (ties either way: both images are then equally
/// near). Pairs and lever arms lie within one and a half periods (positions are wrapped), decided
/// by comparisons; the division and rounding (a library call on x86-64's baseline) only beyond.
#[inline(always)]
fn periods(d: f64, l: f64) -> f64 {
    let a = d.abs();
    if a <= 0.5 * l {
        0.0
    } else if a <= 1.5 * l {
        1.0f64.copysign(d)
    } else {
        (d / l).round()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(shear: f64) -> Cell {
        let mut c = Cell::new(Vec2::new(10.0, 8.0), Periodic::XY, shear, None);
        c.offset = 3.0;
        c.shift = 23.0; // two periods and the offset
        c
    }

    /// Every image by brute force: the nearest of the giver's images within two periods.
    fn brute_nearest(c: &Cell, giver: Vec2, receiver: Vec2) -> Vec2 {
        let mut best = (f64::INFINITY, Vec2::zeros());
        for sy in -2..=2 {
            for sx in -3..=3 {
                let off = Vec2::new(
                    sy as f64 * c.offset + sx as f64 * c.size.x,
                    sy as f64 * c.size.y,
                );
                let d = (giver + off - receiver).norm();
                if d < best.0 {
                    best = (d, off);
                }
            }
        }
        best.1
    }

    #[test]
    fn the_nearest_image_is_the_nearest_of_all_images() {
        let c = cell(0.5);
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..10_000 {
            let g = Vec2::new(10.0 * next(), 8.0 * next());
            let r = Vec2::new(10.0 * next(), 8.0 * next());
            let off = c.nearest_image(g, r).map_or(Vec2::zeros(), |i| i.offset);
            let want = brute_nearest(&c, g, r);
            let want_d = (g + want - r).norm();
            // The regime the cell's size guarantees for a pair within reach.
            if want_d >= 0.5 * c.size.x.min(c.size.y) {
                continue;
            }
            assert_eq!(off, want, "{g:?} {r:?}");
        }
    }

    #[test]
    fn a_body_crossing_the_top_re_enters_shifted_and_slower() {
        let c = cell(0.5);
        let w = c
            .wrap(Vec2::new(1.0, 8.25), Vec2::new(2.0, 1.0))
            .expect("outside");
        // x − s = 1 − 3 = −2 → 8 (one more x image down).
        assert_eq!(w.position, Vec2::new(8.0, 0.25));
        assert_eq!(w.velocity, Vec2::new(2.0 - 0.5 * 8.0, 1.0));
        // Two periods of shift beyond the offset (S = 23 = 2·10 + 3): i_x = −1 − 2.
        assert_eq!(w.images, [-3, 1]);
        // The unwrapped position does not jump across the crossing.
        let before = Vec2::new(1.0, 8.25);
        assert_eq!(c.unwrapped(w.position, w.images), before);
    }

    #[test]
    fn a_body_inside_stays() {
        let c = cell(0.0);
        assert!(c.wrap(Vec2::new(0.0, 7.999), Vec2::zeros()).is_none());
    }

    #[test]
    fn a_cell_no_wider_than_twice_the_reach_is_refused() {
        let c = Cell::new(Vec2::new(4.0, 100.0), Periodic::X, 0.0, None);
        assert_eq!(c.check_size(2.0), Err((0, 4.0)));
        assert!(c.check_size(1.9).is_ok());
        // y is not periodic: its height does not count.
        let c = Cell::new(Vec2::new(100.0, 1.0), Periodic::X, 0.0, None);
        assert!(c.check_size(2.0).is_ok());
    }
}

//! The average stress of a granular sample, two ways.
//!
//! **Love–Weber**: `σ = −(1/V) Σ_p Σ_{c ∋ p} f_c^p ⊗ ℓ_c^p`, the sum over the bodies p of the
//! region and over each body's contacts c, with `f_c^p` the force on p at c and `ℓ_c^p = x_c − x_p`
//! its branch vector (centroid → contact point); V the region's area (per unit thickness, so
//! dyn/cm per cm = dyn/cm²). The minus sign makes compression positive. Both bodies of a contact
//! contribute (each with its own branch vector); a body–wall contact contributes its body's term.
//!
//! **Boundary**: for a sample at static equilibrium (no body force), `Σ_p f_c^p = 0` and the
//! contacts between bodies cancel in `Σ_p Σ_c f_c^p ⊗ x_c` (equal and opposite forces at the
//! same point), so `Σ_p Σ_c f ⊗ ℓ = Σ_{wall contacts} f ⊗ x_c`: the Love–Weber stress of the
//! whole sample equals `σ_b = −(1/V) Σ_{wall contacts} f_c ⊗ (x_c − x_0)` (x_0 the box centre;
//! at equilibrium the wall forces sum to zero and the origin drops out). For a box of four
//! walls this is the familiar "wall force over the span": σ_xx = F_side / H. The two agree only
//! in a quasi-static state; their difference measures how far the sample is from equilibrium.
//!
//! **Couples.** The area law's deep (four-crossing) overlaps act with a force at the crossings'
//! mean and a couple M (on j, −M on i). Both sums take such a force at its line of action
//! ([`super::FrameContact::action_point`]: the point nearest the crossings' mean where the force
//! alone has the moment of force and couple), so that each body's terms keep its moment
//! balance; a couple without a force enters the antisymmetric part only. Between two bodies
//! of the region the choice cancels (both take the same point); it matters for a body's contacts
//! with walls and with bodies outside the region.

use super::frame::{Frame, Window};
use crate::geometry::Vec2;

/// A 2×2 tensor `[[xx, xy], [yx, yy]]` (dyn/cm²).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stress {
    pub xx: f64,
    pub xy: f64,
    pub yx: f64,
    pub yy: f64,
}

impl Stress {
    fn add_outer(&mut self, f: Vec2, l: Vec2, w: f64) {
        self.xx += w * f.x * l.x;
        self.xy += w * f.x * l.y;
        self.yx += w * f.y * l.x;
        self.yy += w * f.y * l.y;
    }

    /// A couple `m` (weighted by `w`) as its antisymmetric part: `yx − xy` grows by `w m`.
    fn add_couple(&mut self, m: f64, w: f64) {
        self.xy -= 0.5 * w * m;
        self.yx += 0.5 * w * m;
    }

    /// `[σ_xx, σ_yy, σ_xy]` of the symmetric part.
    pub fn symmetric(&self) -> [f64; 3] {
        [self.xx, self.yy, 0.5 * (self.xy + self.yx)]
    }

    /// Principal stresses `(σ₁, σ₃)`, σ₁ ≥ σ₃, of the symmetric part, and the angle of σ₁'s
    /// direction (radians, in (−π/2, π/2]).
    pub fn principal(&self) -> (f64, f64, f64) {
        principal(self.symmetric())
    }
}

/// Principal values `(σ₁, σ₃)` and σ₁'s direction of `[σ_xx, σ_yy, σ_xy]`.
pub fn principal([xx, yy, xy]: [f64; 3]) -> (f64, f64, f64) {
    let c = 0.5 * (xx + yy);
    let r = (0.25 * (xx - yy) * (xx - yy) + xy * xy).sqrt();
    (c + r, c - r, 0.5 * (2.0 * xy).atan2(xx - yy))
}

/// The Love–Weber stress of the bodies with `inside[p]`, over an area `area` (see the module
/// documentation).
pub fn love_weber(frame: &Frame, inside: &[bool], area: f64) -> Stress {
    let mut s = Stress::default();
    let w = -1.0 / area;
    for c in &frame.contacts {
        let j = c.j;
        let p = c.action_point();
        // A couple no force carries: its moment in the antisymmetric part (yx − xy = M).
        let bare = if p == c.point { c.couple } else { 0.0 };
        // In a periodic cell, the lever to the contact point's nearest image (a contact of a
        // body's image lies across a seam).
        let lever = |k: usize| {
            let r = p - frame.bodies[k].position;
            frame.cell.map_or(r, |cell| cell.shortest(r))
        };
        if inside[j] {
            s.add_outer(c.force, lever(j), w);
            s.add_couple(bare, w);
        }
        if let Some(i) = c.giver_body()
            && inside[i]
        {
            s.add_outer(-c.force, lever(i), w);
            s.add_couple(-bare, w);
        }
    }
    s
}

/// The boundary stress from the wall contacts, over the box `bx` (see the module documentation).
pub fn boundary(frame: &Frame, bx: Window) -> Stress {
    let mut s = Stress::default();
    let w = -1.0 / bx.area();
    let x0 = bx.centre();
    for c in frame.contacts.iter().filter(|c| c.giver_body().is_none()) {
        s.add_outer(c.force, c.action_point() - x0, w);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{FrameBody, FrameContact};
    use crate::dynamics::Partner;
    use crate::geometry::Shape;

    fn disk(x: f64, y: f64) -> FrameBody {
        FrameBody {
            shape: Shape::Circle { r: 1.0 },
            position: Vec2::new(x, y),
            angle: 0.0,
            density: 1.0,
        }
    }

    fn contact(i: Partner, j: usize, point: Vec2, normal: Vec2, fn_: f64) -> FrameContact {
        FrameContact {
            i,
            j,
            point,
            normal,
            force: normal * fn_,
            couple: 0.0,
            depth: 0.0,
            state: "overlap".into(),
        }
    }

    /// Two unit disks side by side in a 4 × 2 box, squeezed by the left and right walls with a
    /// force P each and pressing on each other with P: by hand, σ_xx = P·(branch sum)/V. Each
    /// disk has two contacts at distance 1 from its centre along x, each pushing inwards with P:
    /// Σ f⊗ℓ = −4P in xx, so σ_xx = 4P/V = 4P/8 = P/2 = P/H (H = 2), σ_yy = σ_xy = 0. The
    /// boundary stress gives the same: F/H.
    #[test]
    fn two_disks_squeezed_between_walls_give_the_wall_force_over_the_height() {
        let p = 3.0;
        let frame = Frame {
            time: 0.0,
            bodies: vec![disk(1.0, 1.0), disk(3.0, 1.0)],
            contacts: vec![
                contact(
                    Partner::Wall(0),
                    0,
                    Vec2::new(0.0, 1.0),
                    Vec2::new(1.0, 0.0),
                    p,
                ),
                contact(
                    Partner::Body(0),
                    1,
                    Vec2::new(2.0, 1.0),
                    Vec2::new(1.0, 0.0),
                    p,
                ),
                contact(
                    Partner::Wall(1),
                    1,
                    Vec2::new(4.0, 1.0),
                    Vec2::new(-1.0, 0.0),
                    p,
                ),
            ],
            wall_box: None,
            cell: None,
        };
        let bx = Window {
            x0: 0.0,
            x1: 4.0,
            y0: 0.0,
            y1: 2.0,
        };
        let s = love_weber(&frame, &[true, true], bx.area());
        assert_eq!(s.symmetric(), [p / 2.0, 0.0, 0.0]);
        let b = boundary(&frame, bx);
        assert_eq!(b.symmetric(), [p / 2.0, 0.0, 0.0]);
    }

    /// A disk under two equal and opposite forces along a diameter at angle θ: σ is the
    /// uniaxial tensor F·2r/V n⊗n (compression positive), whose principal value 2rF/V lies
    /// along θ.
    #[test]
    fn a_disk_loaded_along_a_diameter_gives_a_uniaxial_stress_along_it() {
        let (f, th) = (5.0, 0.3f64);
        let n = Vec2::new(th.cos(), th.sin());
        let frame = Frame {
            time: 0.0,
            bodies: vec![disk(0.0, 0.0), disk(9.0, 9.0), disk(-9.0, -9.0)],
            contacts: vec![
                // Body 1 pushes body 0 at x = n (force on 0 is −f n, along −n).
                contact(Partner::Body(0), 1, n, n, f),
                contact(Partner::Body(0), 2, -n, -n, f),
            ],
            wall_box: None,
            cell: None,
        };
        let s = love_weber(&frame, &[true, false, false], 10.0);
        let (s1, s3, a) = s.principal();
        approx::assert_relative_eq!(s1, 2.0 * f / 10.0, epsilon = 1e-14);
        approx::assert_abs_diff_eq!(s3, 0.0, epsilon = 1e-14);
        approx::assert_abs_diff_eq!(a, th, epsilon = 1e-14);
    }
}

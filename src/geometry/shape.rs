//! Shapes: a body's outline in its own frame, and the facts the kernels and the dynamics ask of it.
//!
//! Conventions (see the crate docs): angles in radians, counter-clockwise; a body's angle is that
//! of its own x axis, which carries an ellipse's semi-axis `a` and a rectangle's width `w`.

use super::clump::Clump;
use super::polygon::Polygon;
use super::pose::Vec2;
use std::fmt;

/// The outline of a rigid body, in its own frame (centroid at the origin).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A disk of radius `r`.
    Circle { r: f64 },
    /// An ellipse with semi-axis `a` along the body's x axis and `b` along its y axis.
    Ellipse { a: f64, b: f64 },
    /// A rectangle of full width `w` (along the body's x axis) and full height `h`.
    Rectangle { w: f64, h: f64 },
    /// A convex polygon (vertices counter-clockwise about the centroid, shared by every body of
    /// this shape: see [`Polygon`]).
    Polygon(Polygon),
    /// A rigid clump of disks (member centres about the union's centroid: see [`Clump`]).
    /// Its contacts are its members' (each a circle), computed per member.
    Clump(Clump),
}

/// Why a shape is not usable.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeError {
    /// The offending field (`r`, `a`, `b`, `w` or `h`).
    pub field: &'static str,
    /// The value given.
    pub value: f64,
}

impl fmt::Display for ShapeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "`{}` must be positive and finite, got {}",
            self.field, self.value
        )
    }
}

impl std::error::Error for ShapeError {}

impl Shape {
    /// Checks that every size is positive and finite.
    pub fn validate(&self) -> Result<(), ShapeError> {
        let fields: &[(&'static str, f64)] = match *self {
            Shape::Circle { r } => &[("r", r)],
            Shape::Ellipse { a, b } => &[("a", a), ("b", b)],
            Shape::Rectangle { w, h } => &[("w", w), ("h", h)],
            // Checked when it was built (`Polygon::new`).
            Shape::Polygon(_) | Shape::Clump(_) => &[],
        };
        for &(field, value) in fields {
            if !(value.is_finite() && value > 0.0) {
                return Err(ShapeError { field, value });
            }
        }
        Ok(())
    }

    /// Radius of the smallest circle about the centroid that contains the shape.
    #[inline]
    pub fn bounding_radius(&self) -> f64 {
        match *self {
            Shape::Circle { r } => r,
            Shape::Ellipse { a, b } => a.max(b),
            Shape::Rectangle { w, h } => 0.5 * w.hypot(h),
            Shape::Polygon(p) => p.bounding_radius,
            Shape::Clump(c) => c.bounding_radius,
        }
    }

    /// Radius of the largest circle about the centroid inside the shape.
    #[inline]
    pub fn inscribed_radius(&self) -> f64 {
        match *self {
            Shape::Circle { r } => r,
            Shape::Ellipse { a, b } => a.min(b),
            Shape::Rectangle { w, h } => 0.5 * w.min(h),
            Shape::Polygon(p) => p.inscribed_radius,
            // Not the largest circle about the centroid inside the union (the centroid may lie
            // outside it): the smallest member, the size scale of a member contact's depth.
            Shape::Clump(c) => c.smallest_radius,
        }
    }

    /// Radius of the disk of the same area (the area law's equivalent lens).
    #[inline]
    pub fn equal_area_radius(&self) -> f64 {
        (self.area() / std::f64::consts::PI).sqrt()
    }

    /// The largest radius of curvature of the boundary: circle `r`, ellipse `a²/b` (a ≥ b, at
    /// the ends of the minor axis), rectangle and polygon ∞ (a face).
    pub fn max_curvature_radius(&self) -> f64 {
        match *self {
            Shape::Circle { r } => r,
            Shape::Ellipse { a, b } => a.max(b) * a.max(b) / a.min(b),
            Shape::Rectangle { .. } | Shape::Polygon(_) => f64::INFINITY,
            // Every contact is a member's: its largest member.
            Shape::Clump(c) => c.radii.iter().copied().fold(0.0, f64::max),
        }
    }

    /// Centred support function `h(u) = max over the shape of u·x` for a direction `u` in the
    /// shape's own frame (not necessarily unit: the result scales with |u|): circle `r|u|`,
    /// ellipse `√(a²u_x² + b²u_y²)`, rectangle `(w|u_x| + h|u_y|)/2`, polygon the largest `u·v`
    /// over its vertices (not centrally symmetric: `h(−u) ≠ h(u)` in general). For a unit `u` it is the
    /// distance from the centroid to the tangent line whose outward normal is `u`.
    #[inline]
    pub fn support(&self, u: Vec2) -> f64 {
        self.support_xy(u.x, u.y)
    }

    /// [`Shape::support`] for the direction `(ux, uy)` in the shape's own frame.
    #[inline]
    pub fn support_xy(&self, ux: f64, uy: f64) -> f64 {
        match *self {
            Shape::Circle { r } => r * ux.hypot(uy),
            Shape::Ellipse { a, b } => ((a * ux) * (a * ux) + (b * uy) * (b * uy)).sqrt(),
            Shape::Rectangle { w, h } => 0.5 * (w * ux.abs() + h * uy.abs()),
            Shape::Polygon(p) => p.support(Vec2::new(ux, uy)),
            Shape::Clump(c) => c.support(Vec2::new(ux, uy)),
        }
    }

    /// Radius of curvature of the boundary where its outward unit normal is `u` (own frame),
    /// for the Hertz radius R* (T11): circle `r`; ellipse `a²b²/h³` with `h` its support along
    /// `u` (closed form at the support point); rectangle: the radius of the circle of equal
    /// area (a corner has R = 0 and a face R = ∞, neither usable in √(R*δ): a documented
    /// choice); a polygon likewise (its vertices have R = 0, its faces R = ∞).
    #[inline]
    pub fn curvature_radius(&self, u: Vec2) -> f64 {
        match *self {
            Shape::Circle { r } => r,
            Shape::Ellipse { a, b } => {
                let h = ((a * u.x).powi(2) + (b * u.y).powi(2)).sqrt();
                (a * a * b * b) / (h * h * h)
            }
            Shape::Rectangle { w, h } => (w * h / std::f64::consts::PI).sqrt(),
            Shape::Polygon(p) => (p.area / std::f64::consts::PI).sqrt(),
            // A member contact takes its member's radius (the dynamics asks the member, a
            // circle); for the whole clump, the equal-area radius.
            Shape::Clump(c) => (c.area / std::f64::consts::PI).sqrt(),
        }
    }

    /// True for a circle (whose orientation does not matter: the dynamics skips its sine and
    /// cosine).
    #[inline]
    pub fn is_circle(&self) -> bool {
        match self {
            Shape::Circle { .. } => true,
            Shape::Ellipse { .. }
            | Shape::Rectangle { .. }
            | Shape::Polygon(_)
            | Shape::Clump(_) => false,
        }
    }

    /// True for a clump (whose contacts are its members').
    #[inline]
    pub fn clump(&self) -> Option<Clump> {
        match self {
            Shape::Clump(c) => Some(*c),
            Shape::Circle { .. }
            | Shape::Ellipse { .. }
            | Shape::Rectangle { .. }
            | Shape::Polygon(_) => None,
        }
    }

    /// True for a shape whose contacts take the flat-faced laws (a rectangle): against a wall a
    /// Winkler foundation, and between two such shapes the area law's flat-equivalent potential.
    /// A polygon is *not*: it takes the laws of smooth bodies (the equal-area lens), so that a
    /// many-sided polygon's contact converges to the smooth body's it approximates (see the
    /// user guide's polygon chapter, docs/src/physics/polygons.md).
    #[inline]
    pub fn is_flat_sided(&self) -> bool {
        match self {
            Shape::Rectangle { .. } => true,
            Shape::Circle { .. } | Shape::Ellipse { .. } | Shape::Polygon(_) | Shape::Clump(_) => {
                false
            }
        }
    }

    /// The face length ℓ of a flat-sided shape for the Winkler contact and the area law's flat
    /// equivalent: a rectangle's mean side `(w + h)/2`, so that a square pressed flat by δ
    /// feels exactly `k_n δ`. A conic has no face: its bounding radius (no contact asks).
    #[inline]
    pub fn face_length(&self) -> f64 {
        match *self {
            Shape::Rectangle { w, h } => 0.5 * (w + h),
            Shape::Circle { .. } | Shape::Ellipse { .. } | Shape::Polygon(_) | Shape::Clump(_) => {
                self.bounding_radius()
            }
        }
    }

    /// Area (the mass per unit thickness and unit density).
    #[inline]
    pub fn area(&self) -> f64 {
        use std::f64::consts::PI;
        match *self {
            Shape::Circle { r } => PI * r * r,
            Shape::Ellipse { a, b } => PI * a * b,
            Shape::Rectangle { w, h } => w * h,
            Shape::Polygon(p) => p.area, // the shoelace formula (geometry::polygon)
            Shape::Clump(c) => c.area,   // the union's, exactly (geometry::clump)
        }
    }

    /// Moment of inertia about the centroid divided by mass (T2 in 2D).
    #[inline]
    pub fn inertia_per_mass(&self) -> f64 {
        match *self {
            Shape::Circle { r } => 0.5 * r * r,
            Shape::Ellipse { a, b } => 0.25 * (a * a + b * b),
            Shape::Rectangle { w, h } => (w * w + h * h) / 12.0,
            Shape::Polygon(p) => p.inertia_per_mass,
            Shape::Clump(c) => c.inertia_per_mass,
        }
    }

    /// The largest normal lever arm `|r × n|` a contact can have on this shape (the largest
    /// distance from the centroid to a boundary normal line): circle 0, ellipse `|a − b|`,
    /// rectangle half its diagonal (a corner can take any normal), polygon its bounding radius
    /// (likewise).
    pub fn max_normal_lever(&self) -> f64 {
        match *self {
            Shape::Circle { .. } => 0.0,
            Shape::Ellipse { a, b } => (a - b).abs(),
            Shape::Rectangle { w, h } => 0.5 * w.hypot(h),
            Shape::Polygon(p) => p.bounding_radius,
            // A member's normal passes through its centre: the farthest member centre.
            Shape::Clump(c) => c.centres.iter().map(|x| x.norm()).fold(0.0, f64::max),
        }
    }

    /// The shape's type name as written in case files (`circle`, `ellipse`, `rectangle`,
    /// `polygon`).
    pub fn type_name(&self) -> &'static str {
        match self {
            Shape::Circle { .. } => "circle",
            Shape::Ellipse { .. } => "ellipse",
            Shape::Rectangle { .. } => "rectangle",
            Shape::Polygon(_) => "polygon",
            Shape::Clump(_) => "clump",
        }
    }

    /// The shape's kind as a number, as the VTK frames' `shape` array and the LAMMPS dump's
    /// `shape` column write it: 0 circle, 1 ellipse, 2 rectangle, 3 polygon, 4 clump.
    pub fn type_code(&self) -> u8 {
        match self {
            Shape::Circle { .. } => 0,
            Shape::Ellipse { .. } => 1,
            Shape::Rectangle { .. } => 2,
            Shape::Polygon(_) => 3,
            Shape::Clump(_) => 4,
        }
    }

    /// The semi-axes `(a, b)` of a shape that is an ellipse, `a` along the body's x axis:
    /// `(r, r)` for a circle; `None` for the others. Viewers that draw ellipses exactly (OVITO's
    /// aspherical particles, a canvas's `ellipse`) ask this.
    pub fn ellipse_semi_axes(&self) -> Option<(f64, f64)> {
        match *self {
            Shape::Circle { r } => Some((r, r)),
            Shape::Ellipse { a, b } => Some((a, b)),
            Shape::Rectangle { .. } | Shape::Polygon(_) | Shape::Clump(_) => None,
        }
    }

    /// The vertices of a shape with corners, counter-clockwise about the centroid (body
    /// frame): a polygon's, a rectangle's four corners (written into `corners`, from
    /// `(−w/2, −h/2)`, and read from there) — to the narrow phase a rectangle *is* a
    /// four-vertex polygon; none for a smooth shape (circle, ellipse) or a clump.
    #[inline]
    pub fn vertices<'a>(&'a self, corners: &'a mut [Vec2; 4]) -> &'a [Vec2] {
        match *self {
            Shape::Polygon(ref p) => &p.data().vertices,
            Shape::Rectangle { w, h } => {
                *corners = super::polygon::rectangle_corners(w, h);
                &corners[..]
            }
            Shape::Circle { .. } | Shape::Ellipse { .. } | Shape::Clump(_) => &[],
        }
    }

    /// The outward unit normals of the edges of [`Shape::vertices`] (edge k from vertex k to
    /// k + 1); none for a smooth shape or a clump.
    #[inline]
    pub fn edge_normals(&self) -> &'static [Vec2] {
        match *self {
            Shape::Polygon(p) => &p.data().normals,
            Shape::Rectangle { .. } => &super::polygon::RECTANGLE_NORMALS,
            Shape::Circle { .. } | Shape::Ellipse { .. } | Shape::Clump(_) => &[],
        }
    }

    /// The boundary as a closed list of body-frame points for drawing, where the shape has
    /// corners (rectangle, polygon): its vertices counter-clockwise; `None` for a conic.
    pub fn corners(&self) -> Option<Vec<Vec2>> {
        match *self {
            Shape::Circle { .. } | Shape::Ellipse { .. } | Shape::Clump(_) => None,
            Shape::Rectangle { w, h } => Some(super::polygon::rectangle_corners(w, h).to_vec()),
            Shape::Polygon(p) => Some(p.vertices.to_vec()),
        }
    }
}

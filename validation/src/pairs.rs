//! The building blocks of the test pairs the hard-case families ([`super::families`]) and the
//! tests draw (`tests/contact_extremes.rs`, `tests/swap_symmetry.rs`): one side of a pair as
//! both the kernel and the reference see it ([`Spec`]), the support function and point that
//! place a body against another, the bars the kernel is held to, and the comparisons.

use super::reference::{RObj, RShape, RState};
use dem2d::geometry::support::support_local;
use dem2d::geometry::{Polygon, Pose, Shape, Vec2, Wall};
use dem2d::narrow_phase::{ContactState, Object};

/// |depth error| ≤ `DEPTH_BAR`·a_max.
pub const DEPTH_BAR: f64 = 1e-12;
/// Normal angle error ≤ `ANGLE_BAR` rad.
pub const ANGLE_BAR: f64 = 1e-8;
/// Contact point error ≤ `POINT_BAR`·a_max (plus two ulps of the coordinates).
pub const POINT_BAR: f64 = 1e-9;
/// The state must be right whenever the true gap or depth is at least `CLASS_BAR`·a_max.
pub const CLASS_BAR: f64 = 1e-12;

/// One side of a test pair, convertible to both the kernel's and the reference's types.
#[derive(Clone, Copy, Debug)]
pub enum Spec {
    /// Shape, position, angle.
    Body(Shape, [f64; 2], f64),
    /// Point, normal.
    Wall([f64; 2], [f64; 2]),
}

impl Spec {
    pub fn object(&self) -> Object {
        match *self {
            Spec::Body(shape, p, th) => Object::Body {
                shape,
                pose: Pose::new(Vec2::from(p), th),
            },
            Spec::Wall(p, n) => Object::Wall(Wall::new(Vec2::from(p), Vec2::from(n)).unwrap()),
        }
    }

    /// The reference's object (circles, ellipses, rectangles and walls: the reference has no
    /// polygon or clump — a clump's contacts are circles').
    pub fn reference(&self) -> RObj {
        match *self {
            Spec::Body(shape, pos, angle) => RObj::Body {
                shape: match shape {
                    Shape::Circle { r } => RShape::Circle { r },
                    Shape::Ellipse { a, b } => RShape::Ellipse { a, b },
                    Shape::Rectangle { w, h } => RShape::Rectangle { w, h },
                    Shape::Polygon(_) | Shape::Clump(_) => unreachable!(
                        "no polygon or clump in the reference (a clump's contacts are circles')"
                    ),
                },
                pos,
                angle,
            },
            Spec::Wall(point, normal) => RObj::Wall { point, normal },
        }
    }

    /// A body's bounding radius (a wall's 0).
    pub fn size(&self) -> f64 {
        match self {
            Spec::Body(s, ..) => s.bounding_radius(),
            Spec::Wall(..) => 0.0,
        }
    }

    /// A body's characteristic lengths (a circle's radius, an ellipse's semi-axes, a
    /// rectangle's sides, a polygon's and a clump's smallest and largest diameters); a wall has
    /// none.
    pub fn sizes(&self) -> Vec<f64> {
        match *self {
            Spec::Body(Shape::Circle { r }, ..) => vec![r],
            Spec::Body(Shape::Ellipse { a, b }, ..) => vec![a, b],
            Spec::Body(Shape::Rectangle { w, h }, ..) => vec![w, h],
            Spec::Body(Shape::Polygon(p), ..) => {
                vec![2.0 * p.inscribed_radius, 2.0 * p.bounding_radius]
            }
            Spec::Body(Shape::Clump(c), ..) => {
                vec![2.0 * c.smallest_radius, 2.0 * c.bounding_radius]
            }
            Spec::Wall(..) => vec![],
        }
    }

    /// A body's position or a wall's point.
    pub fn coordinates(&self) -> [f64; 2] {
        match *self {
            Spec::Body(_, p, _) | Spec::Wall(p, _) => p,
        }
    }

    /// The same object after rotating the plane by ψ about the origin and translating by t.
    pub fn moved(&self, psi: f64, t: [f64; 2]) -> Spec {
        let (s, c) = psi.sin_cos();
        let rot = |p: [f64; 2]| [c * p[0] - s * p[1], s * p[0] + c * p[1]];
        match *self {
            Spec::Body(shape, p, th) => {
                let q = rot(p);
                Spec::Body(shape, [q[0] + t[0], q[1] + t[1]], th + psi)
            }
            Spec::Wall(p, n) => {
                let q = rot(p);
                Spec::Wall([q[0] + t[0], q[1] + t[1]], rot(n))
            }
        }
    }

    /// Lengths multiplied by `k` (a power of two: exact). No clumps.
    pub fn scaled(&self, k: f64) -> Spec {
        match *self {
            Spec::Body(s, p, t) => Spec::Body(
                match s {
                    Shape::Circle { r } => Shape::Circle { r: r * k },
                    Shape::Ellipse { a, b } => Shape::Ellipse { a: a * k, b: b * k },
                    Shape::Rectangle { w, h } => Shape::Rectangle { w: w * k, h: h * k },
                    Shape::Polygon(p) => Shape::Polygon(
                        Polygon::new(
                            &p.vertices
                                .iter()
                                .map(|v| [v.x * k, v.y * k])
                                .collect::<Vec<_>>(),
                        )
                        .unwrap(),
                    ),
                    Shape::Clump(_) => unreachable!("a clump is not scaled here"),
                },
                [p[0] * k, p[1] * k],
                t,
            ),
            Spec::Wall(p, n) => Spec::Wall([p[0] * k, p[1] * k], n),
        }
    }
}

/// The unit vector at angle `t`.
pub fn unit(t: f64) -> [f64; 2] {
    [t.cos(), t.sin()]
}

/// The support function of `shape` (centred at the origin, at `angle`) along the unit `n`.
pub fn support(shape: &Shape, angle: f64, n: [f64; 2]) -> f64 {
    let (s, c) = angle.sin_cos();
    support_local(shape, c * n[0] + s * n[1], -s * n[0] + c * n[1])
}

/// The point of `shape` (centred at the origin, at `angle`) farthest along the unit direction `n`.
pub fn support_point(shape: &Shape, angle: f64, n: [f64; 2]) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    let (ux, uy) = (c * n[0] + s * n[1], -s * n[0] + c * n[1]);
    let (px, py) = match *shape {
        Shape::Circle { r } => (r * ux, r * uy),
        Shape::Ellipse { a, b } => {
            let h = ((a * ux) * (a * ux) + (b * uy) * (b * uy)).sqrt();
            (a * a * ux / h, b * b * uy / h)
        }
        Shape::Rectangle { w, h } => (0.5 * w * ux.signum(), 0.5 * h * uy.signum()),
        Shape::Polygon(p) => {
            let v = p
                .vertices
                .iter()
                .max_by(|a, b| (a.x * ux + a.y * uy).total_cmp(&(b.x * ux + b.y * uy)))
                .expect("a polygon has vertices");
            (v.x, v.y)
        }
        Shape::Clump(cl) => {
            let n = ux.hypot(uy);
            let (m, r) = (0..cl.len())
                .map(|k| cl.member(k))
                .max_by(|a, b| {
                    (a.0.x * ux + a.0.y * uy + a.1 * n)
                        .total_cmp(&(b.0.x * ux + b.0.y * uy + b.1 * n))
                })
                .expect("a clump has members");
            (m.x + r * ux / n, m.y + r * uy / n)
        }
    };
    [c * px - s * py, s * px + c * py]
}

/// The spacing of the doubles at `x`.
pub fn ulp(x: f64) -> f64 {
    let x = x.abs().max(f64::MIN_POSITIVE);
    f64::from_bits(x.to_bits() + 1) - x
}

/// The angle between `a` and `b` (radians, ≥ 0).
pub fn angle_between(a: Vec2, b: [f64; 2]) -> f64 {
    (a.x * b[1] - a.y * b[0])
        .atan2(a.x * b[0] + a.y * b[1])
        .abs()
}

/// The kernel's state is the reference's.
pub fn same_state(k: ContactState, r: RState) -> bool {
    matches!(
        (k, r),
        (ContactState::Separated, RState::Separated)
            | (ContactState::Touching, RState::Touching)
            | (ContactState::Overlap, RState::Overlap)
            | (ContactState::Deep, RState::Deep(_))
            | (ContactState::Contained, RState::Contained)
    )
}

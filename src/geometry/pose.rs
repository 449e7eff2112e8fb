//! Vectors and poses: where a body is and which way it faces.
//!
//! Conventions (see the crate docs): angles in radians, counter-clockwise; a body's angle is that
//! of its own x axis.

/// A 2D vector (positions, directions, velocities).
pub type Vec2 = nalgebra::Vector2<f64>;

/// Position of a body's centroid and orientation of its own x axis.
///
/// The cosine and sine of the angle are computed once here, so that every contact of the body
/// reuses them (they are what the geometry needs, never the angle itself).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Centroid in world coordinates.
    pub position: Vec2,
    angle: f64,
    cos: f64,
    sin: f64,
}

impl Pose {
    /// The pose at the origin with angle 0.
    pub const IDENTITY: Pose = Pose {
        position: Vec2::new(0.0, 0.0),
        angle: 0.0,
        cos: 1.0,
        sin: 0.0,
    };

    /// A pose at `position` whose x axis is at `angle` (radians, counter-clockwise) from the world x axis.
    #[inline]
    pub fn new(position: Vec2, angle: f64) -> Self {
        let (sin, cos) = angle.sin_cos();
        Pose {
            position,
            angle,
            cos,
            sin,
        }
    }

    /// This pose translated to `position` with its angle set to `angle` but its frame (cosine
    /// and sine) kept: for a circle, whose contacts are the same in any orthonormal frame, this
    /// saves a sine and a cosine per step. `cos_sin` and the axes then give the frame, not the
    /// angle; nothing that depends on a body's orientation may use a pose moved this way.
    #[inline]
    pub fn moved(&self, position: Vec2, angle: f64) -> Self {
        Pose {
            position,
            angle,
            ..*self
        }
    }

    /// A pose at `position` and `angle` with the frame `(cos, sin)` as given (a restart gives
    /// back a circle's frame, which [`Pose::moved`] keeps from its first pose). Nothing checks
    /// that the frame is the angle's.
    #[inline]
    pub fn with_frame(position: Vec2, angle: f64, (cos, sin): (f64, f64)) -> Self {
        Pose {
            position,
            angle,
            cos,
            sin,
        }
    }

    /// The angle (radians, counter-clockwise), as given (not wrapped).
    #[inline]
    pub fn angle(&self) -> f64 {
        self.angle
    }

    /// `(cos θ, sin θ)` of the body angle θ.
    #[inline]
    pub fn cos_sin(&self) -> (f64, f64) {
        (self.cos, self.sin)
    }

    /// The body's x axis as a world unit vector.
    #[inline]
    pub fn axis_x(&self) -> Vec2 {
        Vec2::new(self.cos, self.sin)
    }

    /// The body's y axis as a world unit vector.
    #[inline]
    pub fn axis_y(&self) -> Vec2 {
        Vec2::new(-self.sin, self.cos)
    }

    /// World components of a vector given in the body frame.
    #[inline]
    pub fn to_world_vector(&self, v: Vec2) -> Vec2 {
        Vec2::new(
            self.cos * v.x - self.sin * v.y,
            self.sin * v.x + self.cos * v.y,
        )
    }

    /// Body-frame components of a world vector.
    #[inline]
    pub fn to_body_vector(&self, v: Vec2) -> Vec2 {
        Vec2::new(
            self.cos * v.x + self.sin * v.y,
            -self.sin * v.x + self.cos * v.y,
        )
    }
}

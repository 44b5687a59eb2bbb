use super::{ShapeError, check_finite};
use crate::geometry::{Rotation, Vec2};

/// Where a shape is: its centre `(x0, y0)` and its angle `theta` (radians, counter-clockwise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    center: Vec2,
    angle: f64,
    rotation: Rotation,
}

impl Pose {
    /// The identity: centre at the origin, angle 0.
    pub const ORIGIN: Pose = Pose {
        center: Vec2::ZERO,
        angle: 0.0,
        rotation: Rotation::IDENTITY,
    };

    /// A pose with a finite centre and angle.
    pub fn new(center: Vec2, angle: f64) -> Result<Self, ShapeError> {
        check_finite("center x", center.x)?;
        check_finite("center y", center.y)?;
        check_finite("angle", angle)?;
        Ok(Pose {
            center,
            angle,
            rotation: Rotation::new(angle),
        })
    }

    /// A pose from values already known to be finite (the solver's own state).
    pub(crate) fn from_parts(center: Vec2, angle: f64) -> Self {
        Pose {
            center,
            angle,
            rotation: Rotation::new(angle),
        }
    }

    /// A pose from its three parts as [`Self::relative`] made them (a rotation composed, not
    /// the sine and cosine of the angle), for state read back bit for bit.
    pub(crate) fn from_rotation(center: Vec2, angle: f64, rotation: Rotation) -> Self {
        Pose {
            center,
            angle,
            rotation,
        }
    }

    pub fn center(&self) -> Vec2 {
        self.center
    }

    pub fn angle(&self) -> f64 {
        self.angle
    }

    pub fn rotation(&self) -> Rotation {
        self.rotation
    }

    /// World point -> this pose's local frame: `R(-theta) (p - c)`.
    pub fn to_local(&self, p: Vec2) -> Vec2 {
        self.rotation.apply_inverse(p - self.center)
    }

    /// Local point -> world: `R(theta) p + c`.
    pub fn to_world(&self, p: Vec2) -> Vec2 {
        self.rotation.apply(p) + self.center
    }

    /// Local vector -> world.
    pub fn vector_to_world(&self, v: Vec2) -> Vec2 {
        self.rotation.apply(v)
    }

    /// The pose of the world frame seen from this one (`pos^-1`), with no new sine or cosine:
    /// `relative` the other way round, as `b.relative(a)` is `a.relative(b).inverse()`.
    pub fn inverse(&self) -> Pose {
        let r = self.rotation;
        Pose {
            center: -r.apply_inverse(self.center),
            angle: -self.angle,
            rotation: Rotation {
                cos: r.cos,
                sin: -r.sin,
            },
        }
    }

    /// Where `other` is, seen from this pose's local frame (`pos12 = pos1^-1 pos2`).
    /// The result is not re-validated: it is finite whenever both poses are. Its rotation is
    /// the two rotations composed (`R(-theta_1) R(theta_2)`), with no new sine or cosine: a
    /// contact test asks for one, and `sin_cos` cost a tenth of a circles step.
    pub fn relative(&self, other: &Pose) -> Pose {
        let (r1, r2) = (self.rotation, other.rotation);
        Pose {
            center: self.to_local(other.center),
            angle: other.angle - self.angle,
            rotation: Rotation {
                cos: r1.cos * r2.cos + r1.sin * r2.sin,
                sin: r1.cos * r2.sin - r1.sin * r2.cos,
            },
        }
    }
}

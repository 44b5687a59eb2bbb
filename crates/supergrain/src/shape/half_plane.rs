use super::{ShapeError, check_finite};
use crate::geometry::{Aabb, Vec2};

/// The shortest normal [`HalfPlane::new`] scales to length 1: far from any length a scene means,
/// and its reciprocal (1e300) far from overflowing.
pub const MIN_NORMAL: f64 = 1e-300;

/// A wall of the box (paper III-B): the half-plane `g(p) = n . p - d`, solid where `g < 0`,
/// with `n` a unit normal pointing out of the wall into the free space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfPlane {
    normal: Vec2,
    offset: f64,
}

impl HalfPlane {
    /// `g = n . p - d` with `n` normalised (its length is divided out of `d` as well). A normal
    /// shorter than [`MIN_NORMAL`] is refused: `1 / len` of a subnormal length overflows, and
    /// `[1e-310, 0]` was scaled to `[inf, NaN]` (written to dumps as `[null, null]`).
    pub fn new(normal: Vec2, offset: f64) -> Result<Self, ShapeError> {
        check_finite("wall offset", offset)?;
        let len = normal.norm();
        if !(len.is_finite() && len >= MIN_NORMAL) {
            return Err(ShapeError::BadDirection {
                name: "wall normal",
                x: normal.x,
                y: normal.y,
            });
        }
        let offset = check_finite("wall offset over the normal's length", offset / len)?;
        Ok(HalfPlane {
            normal: normal * (1.0 / len),
            offset,
        })
    }

    /// The left wall at `x = x_left`: `g = x - x_left`.
    pub fn left(x_left: f64) -> Result<Self, ShapeError> {
        Self::new(Vec2::new(1.0, 0.0), x_left)
    }

    /// The right wall at `x = x_right`: `g = x_right - x`.
    pub fn right(x_right: f64) -> Result<Self, ShapeError> {
        Self::new(Vec2::new(-1.0, 0.0), -x_right)
    }

    /// The floor at `y = y_floor`: `g = y - y_floor`.
    pub fn floor(y_floor: f64) -> Result<Self, ShapeError> {
        Self::new(Vec2::new(0.0, 1.0), y_floor)
    }

    pub fn normal(&self) -> Vec2 {
        self.normal
    }

    pub fn offset(&self) -> f64 {
        self.offset
    }

    /// `g(p)`: the signed distance to the wall's surface, negative inside the wall.
    pub fn value(&self, p: Vec2) -> f64 {
        self.normal.dot(p) - self.offset
    }

    /// The point of the wall's surface nearest to `p`.
    pub fn project(&self, p: Vec2) -> Vec2 {
        p - self.normal * self.value(p)
    }

    /// The smallest box holding the solid side: a half-infinite box for axis-aligned walls,
    /// the whole plane otherwise.
    pub fn bounding_box(&self) -> Aabb {
        let mut b = Aabb::EVERYWHERE;
        let n = self.normal;
        // Solid side: n . p < d. Pad by an ulp-sized margin so the box is never too small.
        if n.y == 0.0 {
            let x = self.offset / n.x;
            let x = if n.x > 0.0 {
                x.next_up()
            } else {
                x.next_down()
            };
            if n.x > 0.0 {
                b.max.x = x;
            } else {
                b.min.x = x;
            }
        } else if n.x == 0.0 {
            let y = self.offset / n.y;
            let y = if n.y > 0.0 {
                y.next_up()
            } else {
                y.next_down()
            };
            if n.y > 0.0 {
                b.max.y = y;
            } else {
                b.min.y = y;
            }
        }
        b
    }
}

//! The one trait the quadtree needs of a shape, and its implementations for our shapes.

use super::{Exponent, Interval};
use crate::geometry::{Aabb, Rotation, Vec2};
use crate::shape::{HalfPlane, Pose, Superellipse};

/// A closed shape given by an implicit function `f`, inside where `f < 0` (paper II).
///
/// The quadtree of [`crate::subdivision`] is written against this trait only, so walls, other
/// implicit shapes and, later, superquadrics reuse it.
pub trait ImplicitShape {
    /// A rigorous enclosure of the values of `f` over the box: every `f(p)`, `p` in `cell`,
    /// lies in the returned interval.
    fn enclose(&self, cell: &Aabb) -> Interval;

    /// A rigorous enclosure of `f(p)`: its sign, when the interval excludes 0, is a proof.
    fn enclose_point(&self, p: Vec2) -> Interval {
        self.enclose(&Aabb::point(p))
    }

    /// `f(p)` in plain floating point.
    fn value(&self, p: Vec2) -> f64;

    /// `grad f(p)` in plain floating point.
    fn gradient(&self, p: Vec2) -> Vec2;

    /// A box holding the whole inside (possibly infinite).
    fn bounding_box(&self) -> Aabb;

    /// Where `f` can have a local minimum. Unless [`Minima::Unknown`], the minimum of `f` over a
    /// closed region lies on the region's boundary or at that point, which lets the deepest-point
    /// search skip cells well inside the other shape.
    fn minima(&self) -> Minima {
        Minima::Unknown
    }
}

/// Where an implicit function can have local minima.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Minima {
    /// Nothing is known.
    Unknown,
    /// Nowhere (a linear function).
    Nowhere,
    /// Only at this point, about which `f` increases strictly along every ray.
    At(Vec2),
}

/// A superellipse placed in some frame: the implicit function `f(p) = h(R(-theta)(p - c)) - 1`.
#[derive(Clone, Copy, Debug)]
pub struct PlacedSuperellipse {
    shape: Superellipse,
    pose: Pose,
    exponents: [Exponent; 2],
    /// The centre is the frame's origin: no translation, and no rounding from it.
    at_origin: bool,
    /// The shape's axes are the frame's axes (or it is a circle): its enclosure is then exact
    /// up to rounding, with no rotated-box overestimation.
    aligned: bool,
}

impl PlacedSuperellipse {
    pub fn new(shape: Superellipse, pose: Pose) -> Self {
        let aligned = shape.is_circle() || pose.rotation() == Rotation::IDENTITY;
        let [ex, ey] = shape.exponents();
        PlacedSuperellipse {
            shape,
            pose,
            exponents: [Exponent::new(ex), Exponent::new(ey)],
            at_origin: pose.center() == Vec2::ZERO,
            aligned,
        }
    }

    pub fn shape(&self) -> &Superellipse {
        &self.shape
    }

    pub fn pose(&self) -> &Pose {
        &self.pose
    }
}

impl ImplicitShape for PlacedSuperellipse {
    /// Paper II-A: the box is moved to the shape's frame (for a rotated shape, the bounding box of
    /// the rotated cell), where `|t|^e` is monotone on each side of 0 and the sum separable.
    #[inline]
    fn enclose(&self, cell: &Aabb) -> Interval {
        let c = self.pose.center();
        let (mut dx, mut dy) = (
            Interval::new(cell.min.x, cell.max.x),
            Interval::new(cell.min.y, cell.max.y),
        );
        if !self.at_origin {
            dx = dx.sub_scalar(c.x);
            dy = dy.sub_scalar(c.y);
        }
        let (u, v) = if self.aligned {
            (dx, dy)
        } else {
            let r = self.pose.rotation();
            (
                dx.scale(r.cos).plus(dy.scale(r.sin)),
                dx.scale(-r.sin).plus(dy.scale(r.cos)),
            )
        };
        let s = self.shape.semi_axes();
        let [ex, ey] = self.exponents;
        let hx = u.div_positive(s.x).abs_pow(ex);
        let hy = v.div_positive(s.y).abs_pow(ey);
        hx.plus(hy).sub_scalar(1.0)
    }

    fn value(&self, p: Vec2) -> f64 {
        self.shape.value(&self.pose, p)
    }

    fn gradient(&self, p: Vec2) -> Vec2 {
        self.shape.gradient(&self.pose, p)
    }

    fn bounding_box(&self) -> Aabb {
        self.shape.bounding_box(&self.pose)
    }

    /// `h(t u, t v) = t^e_x |u|^e_x + t^e_y |v|^e_y` increases strictly with `t > 0`.
    fn minima(&self) -> Minima {
        Minima::At(self.pose.center())
    }
}

impl ImplicitShape for HalfPlane {
    /// `g = n . p - d` is linear: its range over a box is exact up to rounding.
    fn enclose(&self, cell: &Aabb) -> Interval {
        let n = self.normal();
        Interval::new(cell.min.x, cell.max.x)
            .scale(n.x)
            .plus(Interval::new(cell.min.y, cell.max.y).scale(n.y))
            .sub_scalar(self.offset())
    }

    fn value(&self, p: Vec2) -> f64 {
        HalfPlane::value(self, p)
    }

    fn gradient(&self, _p: Vec2) -> Vec2 {
        self.normal()
    }

    fn bounding_box(&self) -> Aabb {
        HalfPlane::bounding_box(self)
    }

    fn minima(&self) -> Minima {
        Minima::Nowhere
    }
}

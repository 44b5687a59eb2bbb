//! Plain 2D vectors, rotations and axis-aligned boxes: the vocabulary every layer speaks.

use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A point or a vector in the plane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec2 {
    pub x: f64,
    pub y: f64,
}

impl Vec2 {
    pub const ZERO: Vec2 = Vec2 { x: 0.0, y: 0.0 };

    pub const fn new(x: f64, y: f64) -> Self {
        Vec2 { x, y }
    }

    pub fn dot(self, o: Vec2) -> f64 {
        self.x * o.x + self.y * o.y
    }

    /// The 2D cross product `self x o` (the z component of the 3D one).
    pub fn cross(self, o: Vec2) -> f64 {
        self.x * o.y - self.y * o.x
    }

    /// `|self|`: the square root of the sum of squares, within an ulp or two of `hypot` and
    /// several times cheaper (`hypot` was a twelfth of a circles step); `hypot` only where the
    /// squares would overflow or underflow.
    pub fn norm(self) -> f64 {
        let s = self.x * self.x + self.y * self.y;
        if s.is_finite() && s >= f64::MIN_POSITIVE {
            s.sqrt()
        } else {
            self.x.hypot(self.y)
        }
    }

    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }

    /// The unit vector along `self`, or `None` for a zero or non-finite vector whose direction
    /// cannot be recovered. Infinite components (gradients of exponents below 1 near an axis)
    /// still give their direction.
    pub fn direction(self) -> Option<Vec2> {
        if self.x.is_nan() || self.y.is_nan() {
            return None;
        }
        let v = if self.x.is_infinite() || self.y.is_infinite() {
            let keep = |c: f64| if c.is_infinite() { c.signum() } else { 0.0 };
            Vec2::new(keep(self.x), keep(self.y))
        } else {
            // Scale first so that tiny or huge vectors normalise without under/overflow.
            let m = self.x.abs().max(self.y.abs());
            if m == 0.0 {
                return None;
            }
            Vec2::new(self.x / m, self.y / m)
        };
        let n = v.norm();
        (n > 0.0).then(|| Vec2::new(v.x / n, v.y / n))
    }

    pub fn to_array(self) -> [f64; 2] {
        [self.x, self.y]
    }
}

impl From<[f64; 2]> for Vec2 {
    fn from(a: [f64; 2]) -> Self {
        Vec2::new(a[0], a[1])
    }
}

impl Add for Vec2 {
    type Output = Vec2;
    fn add(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x + o.x, self.y + o.y)
    }
}

impl AddAssign for Vec2 {
    fn add_assign(&mut self, o: Vec2) {
        *self = *self + o;
    }
}

impl Sub for Vec2 {
    type Output = Vec2;
    fn sub(self, o: Vec2) -> Vec2 {
        Vec2::new(self.x - o.x, self.y - o.y)
    }
}

impl SubAssign for Vec2 {
    fn sub_assign(&mut self, o: Vec2) {
        *self = *self - o;
    }
}

impl Mul<f64> for Vec2 {
    type Output = Vec2;
    fn mul(self, k: f64) -> Vec2 {
        Vec2::new(self.x * k, self.y * k)
    }
}

impl Neg for Vec2 {
    type Output = Vec2;
    fn neg(self) -> Vec2 {
        Vec2::new(-self.x, -self.y)
    }
}

/// A rotation by an angle, stored as its cosine and sine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rotation {
    pub cos: f64,
    pub sin: f64,
}

impl Rotation {
    pub const IDENTITY: Rotation = Rotation { cos: 1.0, sin: 0.0 };

    pub fn new(angle: f64) -> Self {
        let (sin, cos) = angle.sin_cos();
        Rotation { cos, sin }
    }

    /// The rotation by a small angle, as a grain turns within a step: below 1/8 of a radian by
    /// the Taylor series of the sine and cosine (to the 11th and 12th powers: within 2.3e-16 of
    /// `sin_cos`, whose terms beyond are under 1e-17 there), otherwise [`Rotation::new`]. The
    /// soft step takes every grain's turn since the step began once a substep: `sin_cos` was 6%
    /// of a pour of disks (docs/performance.md).
    pub fn small(angle: f64) -> Self {
        if angle.abs() >= 0.125 {
            return Rotation::new(angle);
        }
        let x2 = angle * angle;
        // Horner's form, the smallest terms first.
        let sin = angle
            * (1.0
                - x2 / 6.0
                    * (1.0
                        - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0 * (1.0 - x2 / 110.0)))));
        let cos = 1.0
            - x2 / 2.0
                * (1.0
                    - x2 / 12.0
                        * (1.0
                            - x2 / 30.0
                                * (1.0 - x2 / 56.0 * (1.0 - x2 / 90.0 * (1.0 - x2 / 132.0)))));
        Rotation { cos, sin }
    }

    /// `R(theta) v`.
    pub fn apply(self, v: Vec2) -> Vec2 {
        Vec2::new(
            self.cos * v.x - self.sin * v.y,
            self.sin * v.x + self.cos * v.y,
        )
    }

    /// `R(-theta) v`.
    pub fn apply_inverse(self, v: Vec2) -> Vec2 {
        Vec2::new(
            self.cos * v.x + self.sin * v.y,
            -self.sin * v.x + self.cos * v.y,
        )
    }
}

/// An axis-aligned box `[min.x, max.x] x [min.y, max.y]`; sides may be infinite (half-planes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec2,
    pub max: Vec2,
}

impl Aabb {
    /// The whole plane.
    pub const EVERYWHERE: Aabb = Aabb {
        min: Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        max: Vec2::new(f64::INFINITY, f64::INFINITY),
    };

    pub const fn new(min: Vec2, max: Vec2) -> Self {
        Aabb { min, max }
    }

    pub fn point(p: Vec2) -> Self {
        Aabb { min: p, max: p }
    }

    pub fn center(&self) -> Vec2 {
        Vec2::new(
            0.5 * (self.min.x + self.max.x),
            0.5 * (self.min.y + self.max.y),
        )
    }

    pub fn width(&self) -> f64 {
        self.max.x - self.min.x
    }

    pub fn height(&self) -> f64 {
        self.max.y - self.min.y
    }

    /// The four corners, counter-clockwise from `min`.
    pub fn corners(&self) -> [Vec2; 4] {
        [
            self.min,
            Vec2::new(self.max.x, self.min.y),
            self.max,
            Vec2::new(self.min.x, self.max.y),
        ]
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        self.width().hypot(self.height())
    }

    /// The common part of two boxes, or `None` when they do not meet.
    pub fn intersection(&self, o: &Aabb) -> Option<Aabb> {
        let b = Aabb {
            min: Vec2::new(self.min.x.max(o.min.x), self.min.y.max(o.min.y)),
            max: Vec2::new(self.max.x.min(o.max.x), self.max.y.min(o.max.y)),
        };
        (b.min.x <= b.max.x && b.min.y <= b.max.y).then_some(b)
    }

    /// The box grown by `d` on every side.
    pub fn grown(&self, d: f64) -> Aabb {
        let d = Vec2::new(d, d);
        Aabb::new(self.min - d, self.max + d)
    }

    /// The smallest box holding both.
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: Vec2::new(self.min.x.min(o.min.x), self.min.y.min(o.min.y)),
            max: Vec2::new(self.max.x.max(o.max.x), self.max.y.max(o.max.y)),
        }
    }

    pub fn intersects(&self, o: &Aabb) -> bool {
        self.min.x <= o.max.x
            && o.min.x <= self.max.x
            && self.min.y <= o.max.y
            && o.min.y <= self.max.y
    }

    pub fn contains(&self, p: Vec2) -> bool {
        (self.min.x..=self.max.x).contains(&p.x) && (self.min.y..=self.max.y).contains(&p.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small turn's series agrees with the C library's `sin_cos` (the reference) within
    /// 2.3e-16 below 1/8 of a radian, and beyond it is `sin_cos` itself.
    #[test]
    fn a_small_turn_is_its_sine_and_cosine() {
        let mut worst = 0.0f64;
        for k in -20_000..=20_000 {
            let angle = f64::from(k) * 0.13 / 20_000.0;
            let r = Rotation::small(angle);
            let (sin, cos) = angle.sin_cos();
            worst = worst.max((r.sin - sin).abs()).max((r.cos - cos).abs());
            if angle.abs() >= 0.125 {
                assert_eq!((r.sin, r.cos), (sin, cos), "{angle}");
            }
        }
        assert!(worst <= 2.3e-16, "{worst}");
        assert_eq!(Rotation::small(0.0), Rotation::IDENTITY);
    }
}

//! The one trait the quadtree needs of a shape, and its implementations for our shapes.

use super::{Exponent, Interval, down, up};
use crate::geometry::{Aabb, Rotation, Vec2};
use crate::shape::{Boundary, HalfPlane, Pose, Superellipse};

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

    /// Where the box lies, proven: [`Side::Inside`] only if `f < 0` all over it,
    /// [`Side::Outside`] only if `f > 0` all over it. The default reads [`Self::enclose`];
    /// a shape may decide with less work (the renderer asks only this).
    fn classify(&self, cell: &Aabb) -> Side {
        Side::of(self.enclose(cell))
    }

    /// `f(p)` in plain floating point.
    fn value(&self, p: Vec2) -> f64;

    /// `grad f(p)` in plain floating point.
    fn gradient(&self, p: Vec2) -> Vec2;

    /// `f(p)` and `grad f(p)` together (shapes may share work between them).
    fn value_and_gradient(&self, p: Vec2) -> (f64, Vec2) {
        (self.value(p), self.gradient(p))
    }

    /// A box holding the whole inside (possibly infinite).
    fn bounding_box(&self) -> Aabb;

    /// Where `f` can have a local minimum. Unless [`Minima::Unknown`], the minimum of `f` over a
    /// closed region lies on the region's boundary or at that point, which lets the deepest-point
    /// search skip cells well inside the other shape.
    fn minima(&self) -> Minima {
        Minima::Unknown
    }
}

/// Where a box lies against a shape, as far as its enclosure can prove.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Every point is inside (`f < 0`).
    Inside,
    /// Every point is outside (`f > 0`).
    Outside,
    /// Neither could be proven.
    Boundary,
}

impl Side {
    /// The side an enclosure of `f` over a box proves.
    pub fn of(f: Interval) -> Side {
        if f.hi < 0.0 {
            Side::Inside
        } else if f.lo > 0.0 {
            Side::Outside
        } else {
            Side::Boundary
        }
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
    /// The scaled local coordinates as affine maps of the frame's: `u / s_x = U . (x, y, 1)` and
    /// `v / s_y = V . (x, y, 1)`, folded once so that an enclosure is two dot products.
    maps: [Affine; 2],
}

/// `a x + b y + k`, with the coefficients as rounded from their exact values.
#[derive(Clone, Copy, Debug)]
struct Affine {
    a: f64,
    b: f64,
    k: f64,
    /// The size of the terms `k` was summed from, which bounds its rounding error even when
    /// they cancel.
    k_terms: f64,
    /// For an axis-aligned shape: `(x - c) / s` along one axis, translated and scaled with
    /// directed rounding, whose error is relative to the result (tight near the shape's axes,
    /// which matters for exponents below 1).
    aligned: Option<Aligned>,
}

/// `(x - c) / s` along one axis (`axis` 0 for x, 1 for y), and `1 / s` rounded to nearest for
/// points.
#[derive(Clone, Copy, Debug)]
struct Aligned {
    axis: usize,
    c: f64,
    s: f64,
    inv_s: f64,
}

impl Affine {
    /// The exact map's partial derivatives, enclosed: each coefficient is within half an ulp of
    /// its exact value (the rotation's rounded `cos` and `sin` over the exact semi-axis).
    fn gradient(&self) -> (Interval, Interval) {
        let around = |x: f64| Interval::new(down(x), up(x));
        match self.aligned {
            Some(Aligned { axis: 0, inv_s, .. }) => (around(inv_s), Interval::point(0.0)),
            Some(Aligned { inv_s, .. }) => (Interval::point(0.0), around(inv_s)),
            None => (around(self.a), around(self.b)),
        }
    }
}

impl Affine {
    /// A rigorous enclosure of the exact map over the box. Each coefficient is within half an
    /// ulp of its exact value, each product and sum rounds by half an ulp, and every term is at
    /// most `M = |a| max|x| + |b| max|y| + |k|`; so the rounded result is within `4 eps M` of the
    /// exact one, and `8 eps M` is a safe widening (plus `MIN_POSITIVE` for underflow). One
    /// widening instead of one per operation keeps the hot loop short.
    #[inline(always)]
    fn enclose(&self, cell: &Aabb) -> Interval {
        if let Some(Aligned { axis, c, s, .. }) = self.aligned {
            let (lo, hi) = if axis == 0 {
                (cell.min.x, cell.max.x)
            } else {
                (cell.min.y, cell.max.y)
            };
            let t = Interval::new(lo, hi);
            let t = if c == 0.0 { t } else { t.sub_scalar(c) };
            return t.div_positive(s);
        }
        let (xl, xh) = if self.a >= 0.0 {
            (cell.min.x, cell.max.x)
        } else {
            (cell.max.x, cell.min.x)
        };
        let (yl, yh) = if self.b >= 0.0 {
            (cell.min.y, cell.max.y)
        } else {
            (cell.max.y, cell.min.y)
        };
        let lo = self.a * xl + self.b * yl + self.k;
        let hi = self.a * xh + self.b * yh + self.k;
        let m = self.a.abs() * cell.min.x.abs().max(cell.max.x.abs())
            + self.b.abs() * cell.min.y.abs().max(cell.max.y.abs())
            + self.k_terms;
        let err = 8.0 * f64::EPSILON * m + f64::MIN_POSITIVE;
        Interval::new(lo - err, hi + err)
    }
}

impl Affine {
    /// [`Affine::enclose`] of a single point. Axis-aligned, with one multiplication by the
    /// rounded `1 / s` instead of two directed divisions: the computed `q = fl(fl(x - c) fl(1/s))`
    /// carries three roundings of at most half an ulp each, so `|q - (x - c)/s| <= 1.5 eps |q|`
    /// (to first order), and `4 eps |q|` covers that and the rounding of the widening itself
    /// (`MIN_POSITIVE` covers underflow). For `s > 2^1022`, `1 / s` is subnormal and errs by up
    /// to `2 eps` relative: about `3.5 eps` in all, still covered. A `q` that is not finite (a
    /// subnormal `s`, whose reciprocal overflows) takes the directed divisions instead.
    #[inline(always)]
    fn enclose_point(&self, p: Vec2) -> Interval {
        if let Some(Aligned { axis, c, inv_s, .. }) = self.aligned {
            let x = if axis == 0 { p.x } else { p.y };
            let q = (x - c) * inv_s;
            if q.is_finite() {
                let err = 4.0 * f64::EPSILON * q.abs() + f64::MIN_POSITIVE;
                return Interval::new(q - err, q + err);
            }
        }
        self.enclose(&Aabb::point(p))
    }

    /// [`Affine::enclose`] of the box of half-width `r` about `p`, as cheap as
    /// [`Affine::enclose_point`] for an axis-aligned shape: the map moves the box's points by at
    /// most `r / s` from `p`'s image, and `r inv_s (1 + 4 eps)` is at least that (`inv_s` is
    /// within half an ulp of `1 / s`, a normal number for every valid semi-axis, and the
    /// product rounds by half an ulp). The ends are rounded outward, as the widening may be
    /// far larger than `q`.
    #[inline(always)]
    fn enclose_around(&self, p: Vec2, r: f64) -> Interval {
        if let Some(Aligned { axis, c, inv_s, .. }) = self.aligned {
            let x = if axis == 0 { p.x } else { p.y };
            let q = (x - c) * inv_s;
            let w = r * inv_s * (1.0 + 4.0 * f64::EPSILON);
            if q.is_finite() && w.is_finite() {
                let err = up(up(4.0 * f64::EPSILON * q.abs() + f64::MIN_POSITIVE) + up(w));
                return Interval::new(down(q - err), up(q + err));
            }
        }
        let d = Vec2::new(r, r);
        self.enclose(&Aabb::new(p - d, p + d))
    }
}

impl PlacedSuperellipse {
    pub fn new(shape: Superellipse, pose: Pose) -> Self {
        let [ex, ey] = shape.exponents();
        let s = shape.semi_axes();
        let c = pose.center();
        // A circle looks the same at any angle: skip the rotation, which keeps its enclosure
        // exact (up to rounding) with no rotated-box overestimation.
        let r = if shape.is_circle() {
            Rotation::IDENTITY
        } else {
            pose.rotation()
        };
        // u = cos (x - cx) + sin (y - cy), v = -sin (x - cx) + cos (y - cy).
        let aligned = r == Rotation::IDENTITY;
        let inv = shape.inv_semi_axes();
        let map = |a: f64, b: f64, s: f64, axis: usize| {
            if aligned {
                // Only `aligned` is read (see `Affine::enclose`): no division.
                return Affine {
                    a: 0.0,
                    b: 0.0,
                    k: 0.0,
                    k_terms: 0.0,
                    aligned: Some(Aligned {
                        axis,
                        c: if axis == 0 { c.x } else { c.y },
                        s,
                        inv_s: if axis == 0 { inv.x } else { inv.y },
                    }),
                };
            }
            Affine {
                a: a / s,
                b: b / s,
                k: -(a * c.x + b * c.y) / s,
                k_terms: ((a * c.x).abs() + (b * c.y).abs()) / s,
                aligned: None,
            }
        };
        PlacedSuperellipse {
            shape,
            pose,
            exponents: [Exponent::new(ex), Exponent::new(ey)],
            maps: [map(r.cos, r.sin, s.x, 0), map(-r.sin, r.cos, s.y, 1)],
        }
    }

    pub fn shape(&self) -> &Superellipse {
        &self.shape
    }

    /// [`ImplicitShape::enclose`] of the box of half-width `r` about `p` (a point proven inside over it
    /// stays inside when moved by rounding to world coordinates), without divisions for an
    /// axis-aligned shape, as [`ImplicitShape::enclose_point`].
    #[inline]
    pub(crate) fn enclose_around(&self, p: Vec2, r: f64) -> Interval {
        let [ex, ey] = self.exponents;
        let hx = self.maps[0].enclose_around(p, r).abs_pow(ex);
        let hy = self.maps[1].enclose_around(p, r).abs_pow(ey);
        hx.plus(hy).sub_scalar(1.0)
    }

    /// A lower bound of `f` over the box: [`ImplicitShape::enclose`]'s lower end alone, two
    /// powers at most, and none for a box beyond the shape's box along one axis (`|u| > 1`),
    /// where 0 is returned (the shape's `f` is positive there).
    ///
    /// This and the slopes and second derivatives below bound the boundary search's arcs
    /// ([`crate::contact`]), and take their powers in single precision
    /// ([`Exponent::pow_down_coarse`], a few millionths looser): the search's tolerances are
    /// a fraction of a cell, and its witnesses are proven by [`ImplicitShape::enclose`].
    #[inline]
    pub(crate) fn lower_bound(&self, cell: &Aabb) -> f64 {
        let [ex, ey] = self.exponents;
        let u = self.maps[0].enclose(cell).abs();
        let v = self.maps[1].enclose(cell).abs();
        if u.lo > 1.0 || v.lo > 1.0 {
            return 0.0;
        }
        down(down(ex.pow_down_coarse(u.lo) + ey.pow_down_coarse(v.lo)) - 1.0)
    }

    pub fn pose(&self) -> &Pose {
        &self.pose
    }

    /// An enclosure of `grad f` over the box, `None` where it is unbounded (a star's axis,
    /// where `|u|^e` with `e < 1` has an infinite slope, crosses the box). For an exponent of
    /// 1, where `|u|` has a kink at the axis, the slope there is enclosed by `[-1, 1]` (its
    /// generalised gradient), which is what the mean-value bounds built on it need.
    pub(crate) fn gradient_enclosure(&self, cell: &Aabb) -> Option<[Interval; 2]> {
        self.axis_slopes(cell).map(|s| self.gradient_from(s))
    }

    /// The slope of each term `|u|^e` in its own coordinate over the box,
    /// `e sgn(u) |u|^(e - 1)`, `None` where it is unbounded (a star's axis in the box): what
    /// [`Self::gradient_enclosure`] and [`Self::second_derivative_floor`] share.
    pub(crate) fn axis_slopes(&self, cell: &Aabb) -> Option<[Interval; 2]> {
        let exponents = self.shape.exponents();
        let t = [self.maps[0].enclose(cell), self.maps[1].enclose(cell)];
        // Unbounded before any power is spent: a star's axis in the box.
        let unbounded = |e: f64, t: Interval| e < 1.0 && t.lo <= 1e-300 && t.hi >= -1e-300;
        if unbounded(exponents[0], t[0]) || unbounded(exponents[1], t[1]) {
            return None;
        }
        // d/du |u|^e = e sgn(u) |u|^(e - 1).
        Some([
            signed_pow(t[0], exponents[0])?.scale(exponents[0]),
            signed_pow(t[1], exponents[1])?.scale(exponents[1]),
        ])
    }

    /// `grad f` from [`Self::axis_slopes`]: each slope times its coordinate's gradient.
    pub(crate) fn gradient_from(&self, slopes: [Interval; 2]) -> [Interval; 2] {
        let mut g = [Interval::point(0.0); 2];
        for (map, slope) in self.maps.iter().zip(slopes) {
            let (du_dx, du_dy) = map.gradient();
            g[0] = g[0].plus(slope.times(du_dx));
            g[1] = g[1].plus(slope.times(du_dy));
        }
        g
    }
}

impl PlacedSuperellipse {
    /// A lower bound of the second derivative of `f` along a curve over the box: `d1` and `d2`
    /// enclose the curve's velocity and acceleration (world axes) while it stays in the box,
    /// `slopes` are [`Self::axis_slopes`] over the box.
    /// `f = sum |u|^e - 1` with `u` affine in the point, so the second derivative is
    /// `sum e (e - 1) |u|^(e - 2) (u')^2 + e sgn(u) |u|^(e - 1) u''`, `u' = grad u . d1` and
    /// `u'' = grad u . d2`. The first term is never negative for `e >= 1` (for `1 < e < 2` it
    /// is unbounded at the axis, and bounded below by its value at the box's far side; the
    /// kink of `e = 1` only adds to it); for a star (`e < 1`) it is negative and unbounded at
    /// the axis, where [`Self::axis_slopes`] is already `None`. `None` where the sum is not
    /// finite. The boundary search's second-order bounds ([`crate::contact`]) rest on it.
    pub(crate) fn second_derivative_floor(
        &self,
        cell: &Aabb,
        slopes: [Interval; 2],
        d1: [Interval; 2],
        d2: [Interval; 2],
    ) -> Option<f64> {
        // Covers the rounding of `e - 2` and `e (e - 1)` (a relative 1e-15 or less on the
        // powers over `|u| >= 1e-300`, as [`signed_pow`]'s pad).
        const PAD: f64 = 1e-12;
        let exponents = self.shape.exponents();
        let mut total = 0.0;
        for (axis, map) in self.maps.iter().enumerate() {
            let e = exponents[axis];
            let t = map.enclose(cell);
            let slope = slopes[axis];
            let (gx, gy) = map.gradient();
            let v = gx.times(d1[0]).plus(gy.times(d1[1]));
            let acc = gx.times(d2[0]).plus(gy.times(d2[1]));
            // `(u')^2` enclosed: from 0 where `u'` may vanish.
            let v = v.abs();
            let square = Interval::new(
                if v.lo == 0.0 { 0.0 } else { down(v.lo * v.lo) },
                up(v.hi * v.hi),
            );
            let a = t.abs();
            let k = Exponent::new(e - 2.0);
            let first = if e == 1.0 {
                0.0
            } else if e == 2.0 {
                down(2.0 * square.lo)
            } else if e > 1.0 {
                // `|u|^(e - 2)` grows with `|u|` for `e > 2` (least at the box's near side) and
                // falls for `e < 2` (least at the far side, 0 there if the box is the axis).
                let least = if e > 2.0 {
                    down(k.pow_down_coarse(a.lo) * (1.0 - PAD))
                } else if a.hi > 0.0 {
                    down(k.pow_down_coarse(a.hi) * (1.0 - PAD))
                } else {
                    0.0
                };
                down(down(down(e * (e - 1.0)) * (1.0 - PAD) * least) * square.lo)
            } else {
                // A star: `e (e - 1) < 0`, most negative at the near side, which `signed_pow`
                // has kept off the axis.
                let most = up(k.pow_up_coarse(a.lo) * (1.0 + PAD));
                -up(up(up(e * (1.0 - e)) * (1.0 + PAD) * most) * square.hi)
            };
            let term = down(first + slope.times(acc).lo);
            if !term.is_finite() {
                return None;
            }
            total = down(total + term);
        }
        total.is_finite().then_some(total)
    }
}

/// An enclosure of `sgn(t) |t|^(e - 1)` over `t` (`e > 0`), `None` where it is unbounded.
fn signed_pow(t: Interval, e: f64) -> Option<Interval> {
    if e == 1.0 {
        return Some(if t.lo > 0.0 {
            Interval::point(1.0)
        } else if t.hi < 0.0 {
            Interval::point(-1.0)
        } else {
            Interval::new(-1.0, 1.0)
        });
    }
    // `e - 1` is exact for `e >= 1/2` (Sterbenz) and for `e >= 1` (a multiple of e's ulp
    // below it); below 1/2 its rounding moves `|t|^(e-1)` by a relative 1e-15 at most over
    // the `|t| >= 1e-300` the caller passes, which the pad covers.
    let k = Exponent::new(e - 1.0);
    let pad = if e < 0.5 { 1e-12 } else { 0.0 };
    let up_pad = |x: f64| up(x * (1.0 + pad));
    let down_pad = |x: f64| down(x * (1.0 - pad));
    if e > 1.0 {
        // Increasing in t, 0 at 0.
        let lo = if t.lo >= 0.0 {
            down_pad(k.pow_down_coarse(t.lo))
        } else {
            -up_pad(k.pow_up_coarse(-t.lo))
        };
        let hi = if t.hi >= 0.0 {
            up_pad(k.pow_up_coarse(t.hi))
        } else {
            -down_pad(k.pow_down_coarse(-t.hi))
        };
        return Some(Interval::new(lo, hi));
    }
    // 0 < e < 1: |t|^(e-1) decreases in |t| and is unbounded at 0.
    if t.lo > 1e-300 {
        Some(Interval::new(
            down_pad(k.pow_down_coarse(t.hi)),
            up_pad(k.pow_up_coarse(t.lo)),
        ))
    } else if t.hi < -1e-300 {
        Some(Interval::new(
            -up_pad(k.pow_up_coarse(-t.hi)),
            -down_pad(k.pow_down_coarse(-t.lo)),
        ))
    } else {
        None
    }
}

impl ImplicitShape for PlacedSuperellipse {
    /// Paper II-A: the box is moved to the shape's frame (for a rotated shape, the bounding box of
    /// the rotated cell), where `|t|^e` is monotone on each side of 0 and the sum separable.
    #[inline]
    fn enclose(&self, cell: &Aabb) -> Interval {
        let [ex, ey] = self.exponents;
        let hx = self.maps[0].enclose(cell).abs_pow(ex);
        let hy = self.maps[1].enclose(cell).abs_pow(ey);
        hx.plus(hy).sub_scalar(1.0)
    }

    /// [`Self::enclose`] of a point, without divisions for an axis-aligned shape (the contact
    /// certificates prove points inside dozens of times a test).
    #[inline]
    fn enclose_point(&self, p: Vec2) -> Interval {
        let [ex, ey] = self.exponents;
        let hx = self.maps[0].enclose_point(p).abs_pow(ex);
        let hy = self.maps[1].enclose_point(p).abs_pow(ey);
        hx.plus(hy).sub_scalar(1.0)
    }

    /// [`Self::enclose`]'s proof with the powers computed only as needed: the upper ends first
    /// (inside is decided by them alone), the lower ends only for a box not proven inside, and
    /// no power at all for a box beyond the shape's box along one axis (`|u| > 1`). Each end is
    /// rounded as in `enclose`, and the sums are compared with 1 rounded outward, so a side
    /// proven here is as certain as one read off the enclosure.
    #[inline]
    fn classify(&self, cell: &Aabb) -> Side {
        let [ex, ey] = self.exponents;
        let u = self.maps[0].enclose(cell).abs();
        let v = self.maps[1].enclose(cell).abs();
        if u.lo > 1.0 || v.lo > 1.0 {
            return Side::Outside;
        }
        let hi_u = ex.pow_up(u.hi);
        if hi_u < 1.0 && up(hi_u + ey.pow_up(v.hi)) < 1.0 {
            return Side::Inside;
        }
        if down(ex.pow_down(u.lo) + ey.pow_down(v.lo)) > 1.0 {
            Side::Outside
        } else {
            Side::Boundary
        }
    }

    fn value(&self, p: Vec2) -> f64 {
        self.shape.value(&self.pose, p)
    }

    fn gradient(&self, p: Vec2) -> Vec2 {
        self.shape.gradient(&self.pose, p)
    }

    fn value_and_gradient(&self, p: Vec2) -> (f64, Vec2) {
        self.shape.value_and_gradient(&self.pose, p)
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

impl ImplicitShape for Boundary {
    /// A half-plane's as above; the others' from their distances' extremes over the box
    /// ([`Boundary::enclose`]), widened by their rounding.
    fn enclose(&self, cell: &Aabb) -> Interval {
        if let Boundary::Plane(w) = self {
            return w.enclose(cell);
        }
        let (lo, hi) = Boundary::enclose(self, cell);
        Interval::new(lo, hi)
    }

    fn value(&self, p: Vec2) -> f64 {
        self.distance(p)
    }

    fn gradient(&self, p: Vec2) -> Vec2 {
        self.normal(p)
    }

    fn bounding_box(&self) -> Aabb {
        Boundary::bounding_box(self)
    }

    fn minima(&self) -> Minima {
        match self {
            // A half-plane's `g` is linear, and a drum's falls along every ray from its centre:
            // over a closed region both are least on its boundary. A disk's grows along every
            // ray from its centre; a segment's or an arc's minima are their whole core.
            Boundary::Plane(_) | Boundary::Circle { inside: true, .. } => Minima::Nowhere,
            Boundary::Circle { center, .. } => Minima::At(*center),
            _ => Minima::Unknown,
        }
    }
}

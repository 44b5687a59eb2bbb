use super::{Pose, ShapeError, check_positive, check_range};
use crate::geometry::{Aabb, Vec2};

/// A relative pad of a few ulps on bounds of the shape's extent (support, box, bounding
/// radius): a bound must never be smaller than the shape.
const BOUND_PAD: f64 = 1.0 + 8.0 * f64::EPSILON;

/// A superellipse centred at the origin, axis-aligned: `h(x, y) = |x/s_x|^e_x + |y/s_y|^e_y <= 1`
/// (paper I). `e = 2` is an ellipse, `e > 2` blocky, `1 <= e < 2` diamond-like, `e < 1` a
/// non-convex star.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Superellipse {
    semi_axes: Vec2,
    exponents: [f64; 2],
    /// `1 / s_x` and `1 / s_y`, so that plain evaluations multiply instead of dividing (a
    /// division costs several multiplications, and the contact tests evaluate `f` and its
    /// gradient dozens of times). Plain values only: enclosures divide with directed rounding.
    inv_semi_axes: Vec2,
    /// [`Superellipse::bounding_radius`], computed once (a square root per contact test
    /// otherwise).
    bounding_radius: f64,
}

/// The exponents accepted (issue 17): within them every certified answer has been checked
/// against dense boundary sampling at the range's edges (`tests/certificate_edges.rs`), both
/// orders of the pair. Beyond 100 the shapes are rectangles to within a percent of their size
/// and powers of coordinates near 1 lose their precision (at 400 the certified path once proved
/// overlapping blocks apart); below 0.25 a star is spikes a hair wide.
pub const EXPONENT_RANGE: std::ops::RangeInclusive<f64> = 0.25..=1000.0;

/// The semi-axes accepted: far inside what f64 holds for the shape's area (`s^2`), polar moment
/// (`s^4`) and the reciprocals the evaluations multiply by, whatever the unit of length (SI
/// grains of a micron to kilometre-long blocks).
pub const SEMI_AXIS_RANGE: std::ops::RangeInclusive<f64> = 1e-9..=1e9;

impl Superellipse {
    /// A superellipse with semi-axes `[s_x, s_y]` in [`SEMI_AXIS_RANGE`] and exponents
    /// `[e_x, e_y]` in [`EXPONENT_RANGE`]; anything else (or not a number) is an error naming
    /// the field.
    pub fn new(semi_axes: [f64; 2], exponents: [f64; 2]) -> Result<Self, ShapeError> {
        let semi_axis =
            |name, v| check_positive(name, v).and_then(|v| check_range(name, v, SEMI_AXIS_RANGE));
        let exponent =
            |name, v| check_positive(name, v).and_then(|v| check_range(name, v, EXPONENT_RANGE));
        let semi_axes = Vec2::new(
            semi_axis("semi-axis x", semi_axes[0])?,
            semi_axis("semi-axis y", semi_axes[1])?,
        );
        let exponents = [
            exponent("exponent x", exponents[0])?,
            exponent("exponent y", exponents[1])?,
        ];
        Ok(Superellipse {
            semi_axes,
            exponents,
            inv_semi_axes: Vec2::new(semi_axes.x.recip(), semi_axes.y.recip()),
            bounding_radius: bounding_radius(semi_axes, exponents),
        })
    }

    /// A circle of the given radius.
    pub fn circle(radius: f64) -> Result<Self, ShapeError> {
        Self::new([radius, radius], [2.0, 2.0])
    }

    pub fn semi_axes(&self) -> Vec2 {
        self.semi_axes
    }

    pub fn min_semi_axis(&self) -> f64 {
        self.semi_axes.x.min(self.semi_axes.y)
    }

    pub fn exponents(&self) -> [f64; 2] {
        self.exponents
    }

    /// `[1 / s_x, 1 / s_y]`, rounded to nearest.
    pub fn inv_semi_axes(&self) -> Vec2 {
        self.inv_semi_axes
    }

    /// Rotation changes nothing (a circle): contact can skip the rotated enclosure.
    pub fn is_circle(&self) -> bool {
        self.exponents == [2.0, 2.0] && self.semi_axes.x == self.semi_axes.y
    }

    /// The implicit function in the local frame: `h(p) - 1`, negative inside.
    pub fn local_value(&self, p: Vec2) -> f64 {
        let [ex, ey] = self.exponents;
        let inv = self.inv_semi_axes;
        abs_pow(p.x * inv.x, ex) + abs_pow(p.y * inv.y, ey) - 1.0
    }

    /// The gradient of [`local_value`](Self::local_value). Components may be infinite for
    /// exponents below 1 close to an axis; on the axis itself they are taken as 0.
    pub fn local_gradient(&self, p: Vec2) -> Vec2 {
        let [ex, ey] = self.exponents;
        let d = |c: f64, inv_s: f64, e: f64| {
            let t = c * inv_s;
            if t == 0.0 {
                0.0
            } else {
                e * abs_pow(t, e - 1.0) * t.signum() * inv_s
            }
        };
        let inv = self.inv_semi_axes;
        Vec2::new(d(p.x, inv.x, ex), d(p.y, inv.y, ey))
    }

    /// The implicit function `f(p) = h(R(-theta)(p - c)) - 1` of the placed shape (SPEC §1).
    pub fn value(&self, pose: &Pose, p: Vec2) -> f64 {
        self.local_value(pose.to_local(p))
    }

    /// The world-frame gradient of [`value`](Self::value).
    pub fn gradient(&self, pose: &Pose, p: Vec2) -> Vec2 {
        pose.vector_to_world(self.local_gradient(pose.to_local(p)))
    }

    /// [`value`](Self::value) and [`gradient`](Self::gradient) together, one power per axis
    /// (`d/dt |t|^e = e |t|^e / t`).
    pub fn value_and_gradient(&self, pose: &Pose, p: Vec2) -> (f64, Vec2) {
        let q = pose.to_local(p);
        let [ex, ey] = self.exponents;
        let term = |c: f64, inv_s: f64, e: f64| {
            let t = c * inv_s;
            let m = abs_pow(t, e);
            let g = if t == 0.0 {
                0.0
            } else if e == 2.0 {
                2.0 * t * inv_s
            } else {
                e * m / t * inv_s
            };
            (m, g)
        };
        let inv = self.inv_semi_axes;
        let (mx, gx) = term(q.x, inv.x, ex);
        let (my, gy) = term(q.y, inv.y, ey);
        (mx + my - 1.0, pose.vector_to_world(Vec2::new(gx, gy)))
    }

    /// The point of the boundary at parameter `t` (radians): the classic parametrisation
    /// `(s_x sgn(cos t) |cos t|^(2/e_x), s_y sgn(sin t) |sin t|^(2/e_y))`.
    pub fn boundary_point(&self, t: f64) -> Vec2 {
        let [ex, ey] = self.exponents;
        let (s, c) = t.sin_cos();
        let p = |v: f64, e: f64| v.signum() * v.abs().powf(2.0 / e);
        Vec2::new(self.semi_axes.x * p(c, ex), self.semi_axes.y * p(s, ey))
    }

    /// `n` boundary points at evenly spaced parameters, placed by `pose`: a polygon for
    /// outlines (pictures, and polygon fills to compare with).
    pub fn boundary_polygon(&self, pose: &Pose, n: u32) -> Vec<Vec2> {
        (0..n)
            .map(|i| {
                pose.to_world(
                    self.boundary_point(f64::from(i) * std::f64::consts::TAU / f64::from(n)),
                )
            })
            .collect()
    }

    /// An upper bound of the support function `max over the shape of d . p` for a local
    /// direction `d`: exact when `e_x = e_y`, and otherwise that of the superellipse with both
    /// exponents equal to the larger one, which contains this one.
    ///
    /// By Holder's inequality, `d . p <= ||(d_x s_x, d_y s_y)||_q` with `1/e + 1/q = 1`; for
    /// `e <= 1` the shape lies in the diamond `e = 1`, whose support is `max(|d_x| s_x, |d_y| s_y)`.
    pub fn local_support(&self, d: Vec2) -> f64 {
        support(self.semi_axes, self.exponents, d)
    }

    /// The axis-aligned bounding box of the placed shape (paper III-A, Fig. 4).
    pub fn bounding_box(&self, pose: &Pose) -> Aabb {
        let r = pose.rotation();
        let (hx, hy) = if self.is_circle() {
            // The same box at any angle.
            let r = self.semi_axes.x * BOUND_PAD;
            (r, r)
        } else {
            // World axes seen from the local frame: R(-theta) e_x and R(-theta) e_y.
            (
                self.local_support(Vec2::new(r.cos, -r.sin)),
                self.local_support(Vec2::new(r.sin, r.cos)),
            )
        };
        let c = pose.center();
        Aabb::new(Vec2::new(c.x - hx, c.y - hy), Vec2::new(c.x + hx, c.y + hy))
    }

    /// A radius about the centre that holds the whole shape: `max(s_x, s_y)` when both
    /// exponents are at most 2 (the shape lies in the ellipse), the half-diagonal otherwise.
    pub fn bounding_radius(&self) -> f64 {
        self.bounding_radius
    }

    /// The area, `4 s_x s_y G(1 + 1/e_x) G(1 + 1/e_y) / G(1 + 1/e_x + 1/e_y)` (G: gamma).
    pub fn area(&self) -> f64 {
        let [p, q] = self.exponents;
        4.0 * self.semi_axes.x * self.semi_axes.y * dirichlet(1.0, 1.0, p, q)
    }

    /// The polar second moment of area about the centre, `J = integral of (x^2 + y^2) dA`.
    pub fn polar_moment_of_area(&self) -> f64 {
        let [p, q] = self.exponents;
        let Vec2 { x: a, y: b } = self.semi_axes;
        4.0 * (a * a * a * b * dirichlet(3.0, 1.0, p, q)
            + a * b * b * b * dirichlet(1.0, 3.0, p, q))
    }

    /// The moment of inertia about the centre of a uniform grain of the given mass.
    pub fn moment_of_inertia(&self, mass: f64) -> f64 {
        mass * self.polar_moment_of_area() / self.area()
    }
}

/// [`Superellipse::bounding_radius`] from the shape's numbers.
fn bounding_radius(semi_axes: Vec2, exponents: [f64; 2]) -> f64 {
    let [ex, ey] = exponents;
    let Vec2 { x: sx, y: sy } = semi_axes;
    let r = if ex <= 2.0 && ey <= 2.0 {
        sx.max(sy)
    } else {
        sx.hypot(sy)
    };
    r * BOUND_PAD
}

/// [`Superellipse::local_support`] for any semi-axes and exponents (finite and positive), with
/// no shape built: the contact certificate asks it of grown copies of a shape.
pub(crate) fn support(semi_axes: Vec2, exponents: [f64; 2], d: Vec2) -> f64 {
    let e = exponents[0].max(exponents[1]);
    let a = (d.x * semi_axes.x).abs();
    let b = (d.y * semi_axes.y).abs();
    let m = a.max(b);
    if m == 0.0 {
        return 0.0;
    }
    let s = if e <= 1.0 || a.min(b) == 0.0 {
        // Along an axis (the first shape's frame of every contact test asks for its box)
        // the support is the semi-axis, for any exponent.
        m
    } else if e == 2.0 {
        // q = 2: no powf (the contact certificate asks for this often).
        let r = a.min(b) / m;
        m * (1.0 + r * r).sqrt()
    } else {
        let q = e / (e - 1.0);
        // Normalise by the larger term so that huge q neither overflows nor underflows.
        m * (1.0 + (a.min(b) / m).powf(q)).powf(1.0 / q)
    };
    s * BOUND_PAD
}

/// `|t|^e` in plain floating point, without `powf` for the common exponents (paper IV-A).
#[inline]
pub(crate) fn abs_pow(t: f64, e: f64) -> f64 {
    let a = t.abs();
    if e == 2.0 {
        a * a
    } else if e == 1.0 {
        a
    } else if e == 4.0 {
        (a * a) * (a * a)
    } else if e == 3.0 {
        a * a * a
    } else {
        a.powf(e)
    }
}

/// The Dirichlet integral over the quarter `u, v >= 0, u^p + v^q <= 1` of `u^(alpha-1) v^(beta-1)`:
/// `G(alpha/p) G(beta/q) / (p q G(1 + alpha/p + beta/q))`, computed with logarithms of gamma so
/// that large arguments (small exponents) do not overflow.
fn dirichlet(alpha: f64, beta: f64, p: f64, q: f64) -> f64 {
    let (a, b) = (alpha / p, beta / q);
    (libm::lgamma(a) + libm::lgamma(b) - libm::lgamma(1.0 + a + b)).exp() / (p * q)
}

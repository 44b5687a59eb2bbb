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

    /// A star: an exponent below 1, so the shape is not convex (its contacts can have several
    /// regions, and are answered to a cell rather than exactly).
    pub fn is_star(&self) -> bool {
        self.exponents.iter().any(|&e| e < 1.0)
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

    /// How deep the point `p` lies in the placed shape: its distance to the boundary (0 outside),
    /// from above and within about `tol` of it. The distance to the nearest of the boundary
    /// points sampled as the graphs `y(x)` and `x(y)` of a quadrant, each interval halved until
    /// its ends are at most `tol` apart (at most 2^16 points a graph): every sample is a point of
    /// the boundary, so the answer is never below the distance, and where one graph is steep
    /// (the sides of a block, a star's spikes: `y(x)` of exponent 1000 climbs from 0 to 0.98
    /// within 1e-10 of `x = s_x`) the other is flat and sampled finely. The shape is symmetric
    /// about both axes, so the nearest point of the boundary to a point of a quadrant is in that
    /// quadrant (reflecting a point into it brings it no further), and one quadrant is sampled.
    ///
    /// A penetration vector (`A1 -> B2`) is no such measure: it follows the gradient to where
    /// the ray leaves the shape, which for a star can be across a spike, far from `A1`.
    pub fn depth_of(&self, pose: &Pose, p: Vec2, tol: f64) -> f64 {
        let q = pose.to_local(p);
        // Not inside (or not a number): no depth.
        if self.local_value(q).partial_cmp(&0.0) != Some(std::cmp::Ordering::Less) {
            return 0.0;
        }
        let q = Vec2::new(q.x.abs(), q.y.abs());
        let [ex, ey] = self.exponents;
        let s = self.semi_axes;
        // `(1 - |t|^e)^(1 / e')`, the other coordinate's share, for t in [0, 1].
        let rest = |t: f64, e: f64, other: f64| (1.0 - abs_pow(t, e)).max(0.0).powf(1.0 / other);
        let over_x = |t: f64| Vec2::new(s.x * t, s.y * rest(t, ex, ey));
        let over_y = |t: f64| Vec2::new(s.x * rest(t, ey, ex), s.y * t);
        let tol = tol.max(self.min_semi_axis() * 1e-9);
        let mut best = f64::INFINITY;
        for graph in [&over_x as &dyn Fn(f64) -> Vec2, &over_y] {
            best = best.min(nearest_on(graph, q, tol));
        }
        best
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

/// The distance from `q` to the nearest of the points `graph(t)`, `t` in `[0, 1]`, sampled at 16
/// even steps and each interval halved (12 times at most) until its ends are within `tol`.
fn nearest_on(graph: &dyn Fn(f64) -> Vec2, q: Vec2, tol: f64) -> f64 {
    const FIRST: u32 = 16;
    const MAX_LEVEL: u32 = 12;
    let mut best = (graph(0.0) - q).norm();
    let mut stack: Vec<(f64, f64, Vec2, Vec2, u32)> = Vec::new();
    let mut last = (0.0, graph(0.0));
    for i in 1..=FIRST {
        let t = f64::from(i) / f64::from(FIRST);
        let b = graph(t);
        best = best.min((b - q).norm());
        stack.push((last.0, t, last.1, b, 0));
        last = (t, b);
    }
    while let Some((t0, t1, b0, b1, level)) = stack.pop() {
        if (b1 - b0).norm() <= tol || level >= MAX_LEVEL {
            continue;
        }
        let t = 0.5 * (t0 + t1);
        let b = graph(t);
        best = best.min((b - q).norm());
        stack.push((t0, t, b0, b, level + 1));
        stack.push((t, t1, b, b1, level + 1));
    }
    best
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
    support_by(semi_axes, exponents, d, f64::powf) * BOUND_PAD
}

/// [`support`]'s closed form with the powers of `pow` and without its pad: an estimate (the
/// flat grains' path takes [`pow32`]'s to choose an axis, where nothing rests on the bound).
pub(crate) fn support_by(
    semi_axes: Vec2,
    exponents: [f64; 2],
    d: Vec2,
    pow: fn(f64, f64) -> f64,
) -> f64 {
    let e = exponents[0].max(exponents[1]);
    let a = (d.x * semi_axes.x).abs();
    let b = (d.y * semi_axes.y).abs();
    let m = a.max(b);
    if m == 0.0 {
        return 0.0;
    }
    if e <= 1.0 || a.min(b) == 0.0 {
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
        m * pow(1.0 + pow(a.min(b) / m, q), 1.0 / q)
    }
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
    } else if is_small_integer(e) {
        // Blocky grains' exponents are often whole (8, 16): squarings, a few ulps off (no
        // certificate rests on these powers: the interval enclosures do their own), at a
        // fraction of `powf`'s cost (the tumbler's squares of exponent 16 spent 30% of their
        // step in `pow`).
        a.powi(e as i32)
    } else {
        a.powf(e)
    }
}

/// Whether `e` is a whole number from 5 to 24: a blocky grain's (a plank of exponent 50 keeps
/// `powf`, whose results the silo measurements of docs/silo.md were made with).
#[inline]
fn is_small_integer(e: f64) -> bool {
    (5.0..=24.0).contains(&e) && e.fract() == 0.0
}

/// `|t|^e` in single precision, for float solves whose answers no certificate rests on: a
/// manifold's points (where the solver pushes) and the starts and iterations of the certified
/// path's Newton solves, which the interval arithmetic then checks. A relative error of about
/// 1e-7 moves such points by a ten-millionth of a grain. Single precision's `powf` does two to
/// three times as many powers a second as double's (measured here: 4.8 against 12.3 ns); the
/// patch of a blocky contact needs about fifty (the profile of a settled mixed heap: a quarter
/// of its step was `pow`). Exponents 2 and 4 (exact products), and bases outside
/// `[1e-30, 1e30]`, where `f32` would flush or overflow, take [`abs_pow`].
#[inline]
pub(crate) fn pow32(t: f64, e: f64) -> f64 {
    let a = t.abs();
    if e != 2.0 && e != 4.0 && (1e-30..=1e30).contains(&a) {
        let a = a as f32;
        f64::from(if is_small_integer(e) {
            a.powi(e as i32)
        } else {
            a.powf(e as f32)
        })
    } else {
        abs_pow(t, e)
    }
}

/// The Dirichlet integral over the quarter `u, v >= 0, u^p + v^q <= 1` of `u^(alpha-1) v^(beta-1)`:
/// `G(alpha/p) G(beta/q) / (p q G(1 + alpha/p + beta/q))`, computed with logarithms of gamma so
/// that large arguments (small exponents) do not overflow.
fn dirichlet(alpha: f64, beta: f64, p: f64, q: f64) -> f64 {
    let (a, b) = (alpha / p, beta / q);
    (libm::lgamma(a) + libm::lgamma(b) - libm::lgamma(1.0 + a + b)).exp() / (p * q)
}

/// A tight upper bound of the support function `max over the shape of d . p` for unequal
/// exponents, where [`support`] takes the larger exponent for both axes (for exponents 1 and 4
/// that is a squircle about the diamond, far too loose for a contact certificate), and an
/// estimate of the point where it is reached. `None` for a direction that is zero or not finite.
///
/// By Lagrangian duality: with `A = |d_x| s_x`, `B = |d_y| s_y`, the support is the maximum of
/// `u A + v B` over `u^p + v^q <= 1`, `u, v` in `[0, 1]`, and for every `lambda > 0`
///
/// ```text
/// h <= g(lambda) = lambda + phi_p(A, lambda) + phi_q(B, lambda),
/// phi_p(A, lambda) = max over u in [0, 1] of (u A - lambda u^p)
/// ```
///
/// (weak duality: the bound holds for any `lambda`, so the `lambda` found below by Newton needs
/// no proof, only its evaluation is rounded up). `phi` has a closed form: `A - lambda` when
/// `A >= p lambda` (`u = 1`), else `(1 - 1/p) A u` with `u = (A / (p lambda))^(1/(p-1))` for
/// `p > 1`; `max(0, A - lambda)` for `p <= 1` (then `u A - lambda u^p` is convex in `u`). For
/// convex shapes `g`'s minimum is the support itself (no duality gap); for stars it is the
/// support of the shape with the exponents below 1 raised to 1, a convex set holding the star.
///
/// Written by hand: no closed form exists for unequal exponents, and the certificate needs an
/// upper bound, not an approximation.
pub(crate) fn support_dual(semi_axes: Vec2, exponents: [f64; 2], d: Vec2) -> Option<(f64, Vec2)> {
    // Exponents within 1e-6 above 1 are raised to that (a larger exponent, a larger shape: still
    // a bound), so that `1/(p-1)` and the rounding it multiplies stay bounded.
    let [p, q] = exponents.map(|e| if e > 1.0 { e.max(1.0 + 1e-6) } else { e });
    let (a, b) = ((d.x * semi_axes.x).abs(), (d.y * semi_axes.y).abs());
    if !(a.is_finite() && b.is_finite()) || a.max(b) == 0.0 {
        return None;
    }
    let sign = |v: f64| if v < 0.0 { -1.0 } else { 1.0 };
    let point = |u: f64, v: f64| {
        Vec2::new(
            sign(d.x) * semi_axes.x * u.min(1.0),
            sign(d.y) * semi_axes.y * v.min(1.0),
        )
    };
    if a.min(b) == 0.0 {
        // Along an axis: the semi-axis, for any exponents.
        let h = a.max(b) * BOUND_PAD;
        return Some(if a > b {
            (h, point(1.0, 0.0))
        } else {
            (h, point(0.0, 1.0))
        });
    }
    // The multiplier minimising g (its derivative `1 - u^p - v^q` is increasing).
    let lambda = match (p > 1.0, q > 1.0) {
        (false, false) => a.max(b),
        (false, true) => a,
        (true, false) => b,
        (true, true) => dual_multiplier(a, b, p, q)?,
    };
    // `u` maximising `u A - lambda u^p` on [0, 1], and that maximum rounded up: the ratio and
    // the power carry a few ulps, magnified by the exponent `1/(p-1)`.
    let phi = |a: f64, p: f64| -> (f64, f64) {
        if p <= 1.0 {
            return if a > lambda {
                (1.0, up_by(a - lambda, 4.0))
            } else {
                (0.0, 0.0)
            };
        }
        let r = a / (p * lambda);
        if r >= 1.0 {
            return (1.0, up_by(a - lambda, 4.0));
        }
        let k = 1.0 / (p - 1.0);
        let u = r.powf(k);
        (u, up_by((1.0 - 1.0 / p) * a * u, 16.0 + 8.0 * k))
    };
    let ((u, phi_a), (v, phi_b)) = (phi(a, p), phi(b, q));
    let h = up_by(lambda + phi_a + phi_b, 4.0);
    h.is_finite().then(|| (h, point(u, v)))
}

/// `x` raised by `ulps` relative units of rounding (and the smallest normal, for zero).
fn up_by(x: f64, ulps: f64) -> f64 {
    x + x.abs() * ulps * f64::EPSILON + f64::MIN_POSITIVE
}

/// The `lambda` of [`support_dual`] for exponents above 1: the root of
/// `psi(s) = (A s / p)^(p') + (B s / q)^(q') - 1` in `s = 1/lambda` (`p' = p/(p-1)`: there
/// the maximisers `u, v` of `phi` lie on the boundary). Solved in `z = ln s`, where
/// `ln(psi + 1)` is a log-sum-exp of two lines, convex, increasing and nearly straight (slopes
/// between `p'` and `q'`): Newton converges in a few steps from anywhere (from the left it
/// overshoots once, then descends). Only the bound's tightness rests on this solve: the bound
/// holds for any `lambda`, and `g` errs by the square of `lambda`'s error.
fn dual_multiplier(a: f64, b: f64, p: f64, q: f64) -> Option<f64> {
    let (pp, qp) = (p / (p - 1.0), q / (q - 1.0));
    let (la, lb) = ((a / p).ln(), (b / q).ln());
    // Where the larger term alone is 1: psi >= 0, the right of the root.
    let mut z = (-la).min(-lb);
    for _ in 0..30 {
        let (ta, tb) = ((pp * (z + la)).exp(), (qp * (z + lb)).exp());
        let sum = ta + tb;
        let step = sum.ln() * sum / (pp * ta + qp * tb);
        if !step.is_finite() {
            return None;
        }
        z -= step;
        if step.abs() <= 1e-7 {
            break;
        }
    }
    let lambda = (-z).exp();
    (lambda.is_finite() && lambda > 0.0).then_some(lambda)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// `u A + v B` along the boundary `u^p + v^q = 1` (first quadrant), as a function of `u`.
    fn along(a: f64, b: f64, p: f64, q: f64, u: f64) -> f64 {
        u * a + (1.0 - u.powf(p)).max(0.0).powf(1.0 / q) * b
    }

    /// The support by an independent route: the boundary sampled as a graph over each axis
    /// (so that neither a flat face nor a spike tip is skipped), and for convex shapes refined
    /// by ternary search (the function is concave along a convex boundary).
    fn reference(a: f64, b: f64, p: f64, q: f64) -> f64 {
        let n = 20_000;
        let mut best = a.max(b);
        for i in 0..=n {
            let t = i as f64 / n as f64;
            best = best.max(along(a, b, p, q, t)).max(along(b, a, q, p, t));
        }
        if p >= 1.0 && q >= 1.0 {
            let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
            for _ in 0..200 {
                let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
                if along(a, b, p, q, m1) < along(a, b, p, q, m2) {
                    lo = m1;
                } else {
                    hi = m2;
                }
            }
            best = best.max(along(a, b, p, q, 0.5 * (lo + hi)));
        }
        best
    }

    /// The dual bound is never below the support (any shape, exponents 0.25 to 1,000, flat
    /// faces and spikes), is the support itself for convex shapes, and its point is on the
    /// shape and reaches it.
    #[test]
    fn the_dual_support_bounds_and_for_convex_shapes_equals_the_sampled_support() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let exponent = |rng: &mut ChaCha8Rng| match rng.random_range(0..6) {
            0 => rng.random_range(0.25..1.0),
            1 => rng.random_range(1.0..1.1),
            2 => rng.random_range(1.0..4.0),
            3 => rng.random_range(4.0..40.0),
            4 => rng.random_range(40.0..1000.0),
            _ => 2.0,
        };
        let mut convex_cases = 0;
        for _ in 0..400 {
            let (p, q) = (exponent(&mut rng), exponent(&mut rng));
            let axes = Vec2::new(rng.random_range(0.1..2.0), rng.random_range(0.1..2.0));
            let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let d = Vec2::new(angle.cos(), angle.sin());
            let (h, point) = support_dual(axes, [p, q], d).unwrap();
            let (a, b) = ((d.x * axes.x).abs(), (d.y * axes.y).abs());
            let h_ref = reference(a, b, p, q);
            assert!(
                h >= h_ref,
                "{p} {q} {axes:?} {d:?}: bound {h} below the support {h_ref}"
            );
            let shape = Superellipse::new([axes.x, axes.y], [p, q]).unwrap();
            let loose = shape.local_support(d);
            assert!(
                h <= loose * (1.0 + 1e-12),
                "{p} {q}: {h} above the larger exponent's {loose}"
            );
            if p >= 1.0 && q >= 1.0 {
                convex_cases += 1;
                assert!(h - h_ref <= 1e-9 * h_ref, "{p} {q}: bound {h} over {h_ref}");
                assert!(
                    shape.local_value(point) <= 1e-6,
                    "{p} {q}: {point:?} outside"
                );
                let reach = d.dot(point);
                assert!(
                    h_ref - reach <= 1e-6 * h_ref,
                    "{p} {q}: point reaches {reach} of {h_ref}"
                );
            }
        }
        assert!(convex_cases > 150);
    }
}

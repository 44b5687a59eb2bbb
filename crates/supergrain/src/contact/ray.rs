use crate::geometry::Vec2;
use crate::interval::{ImplicitShape, PlacedSuperellipse};

/// `A1 -> B2` (paper III-A): from a point inside `other` along `grad f_other` to its boundary.
pub(crate) fn push_out(other: &PlacedSuperellipse, from: Vec2) -> Vec2 {
    push_out_by(other, from, false)
}

/// [`push_out`], and with `along_spikes` a point on a star's cusp (within [`CUSP`] of an axis of
/// exponent below 1) pushed along the spike ([`cusp_gradient`]) rather than out of its side: the
/// paper model's projection, whose push moves the grains. (Measured on the mixed preset, whose
/// deepest points lie on cusps since the boundary search crosses them: 3,000 steps in 4.4 s
/// against 15.3 with the plain gradient, which left a spike sideways and barely separated the
/// pair. The soft model takes only a depth from the pushes, and its spiky star heaps rested
/// later with the pushes along the spikes (steps 2,902, 1,243 and 3,986 against 803, 1,086
/// and 676, seeds 2-4), so it keeps the gradient.)
pub(crate) fn push_out_by(other: &PlacedSuperellipse, from: Vec2, along_spikes: bool) -> Vec2 {
    if other.shape().exponents() == [2.0, 2.0]
        && let Some(push) = ellipse_push(other, from)
    {
        return push;
    }
    let centre = other.pose().center();
    // From any point within the bounding circle, this far along is outside it.
    let t_far = ((from - centre).norm() + other.shape().bounding_radius()) * (1.0 + 1e-9)
        + f64::MIN_POSITIVE;
    // The gradient vanishes only at the centre of a symmetric shape; then any way out will do,
    // and straight away from the centre (or along x) is as good as any.
    let way_out = |g: Vec2| {
        g.direction()
            .or_else(|| (from - centre).direction())
            .unwrap_or(Vec2::new(1.0, 0.0))
    };
    let exit = if super::certified::convex(other.shape()) {
        // The value and gradient at `from` serve both the direction and Newton's first step.
        let (f, g) = other.value_and_gradient(from);
        convex_exit(other, from, way_out(g), t_far, f, g)
    } else {
        let g = if along_spikes {
            cusp_gradient(other, from)
        } else {
            other.gradient(from)
        };
        ray_to_boundary(other, from, way_out(g), t_far)
    };
    exit - from
}

/// A relative distance from a star's axis within which a point counts as on its cusp.
const CUSP: f64 = 1e-6;

/// `grad f` of a star, except next to an axis of exponent below 1 (within [`CUSP`] of the
/// semi-axis), where the term's slope, unbounded, points across the axis to one side or the
/// other: there the least of the one-sided gradients' combinations (the generalised gradient's
/// least element), without that term. A deepest point on a spike's axis is pushed along the
/// spike, not out of its side.
fn cusp_gradient(other: &PlacedSuperellipse, from: Vec2) -> Vec2 {
    let shape = other.shape();
    let pose = other.pose();
    let local = pose.to_local(from);
    let [ex, ey] = shape.exponents();
    let s = shape.semi_axes();
    let mut g = shape.local_gradient(local);
    if ex < 1.0 && local.x.abs() <= CUSP * s.x {
        g.x = 0.0;
    }
    if ey < 1.0 && local.y.abs() <= CUSP * s.y {
        g.y = 0.0;
    }
    pose.vector_to_world(g)
}

/// From a point inside `other` along the unit direction `way` to its boundary (for a star, the
/// first crossing the bracketed search finds): a push along a chosen normal
/// ([`super::push::separating`]).
pub(crate) fn exit_along(other: &PlacedSuperellipse, from: Vec2, way: Vec2) -> Vec2 {
    let centre = other.pose().center();
    let t_far = ((from - centre).norm() + other.shape().bounding_radius()) * (1.0 + 1e-9)
        + f64::MIN_POSITIVE;
    let exit = if super::certified::convex(other.shape()) {
        ray_to_convex_boundary(other, from, way, t_far)
    } else {
        ray_to_boundary(other, from, way, t_far)
    };
    exit - from
}

/// [`push_out`] of an ellipse (circles too) in closed form: along any ray its `f` is a quadratic
/// in the distance, `a t^2 + b t + f(from)`, with `b = |grad f| > 0` along the gradient, whose
/// positive root is `2 (-f) / (b + sqrt(b^2 - 4 a f))` (no cancellation: `f < 0`). `None` at the
/// centre (no gradient to follow) or for a value that is not a number.
fn ellipse_push(other: &PlacedSuperellipse, from: Vec2) -> Option<Vec2> {
    let pose = other.pose();
    let inv = other.shape().inv_semi_axes();
    let (ix2, iy2) = (inv.x * inv.x, inv.y * inv.y);
    let p = pose.to_local(from);
    let f = p.x * p.x * ix2 + p.y * p.y * iy2 - 1.0;
    if f.is_nan() {
        return None;
    }
    if f >= 0.0 {
        // Not inside: nowhere to go, as for the searches.
        return Some(Vec2::ZERO);
    }
    // Half the gradient, in the ellipse's frame: only its direction is used.
    let d = Vec2::new(p.x * ix2, p.y * iy2).direction()?;
    let a = d.x * d.x * ix2 + d.y * d.y * iy2;
    let b = 2.0 * (p.x * d.x * ix2 + p.y * d.y * iy2);
    let t = -2.0 * f / (b + (b * b - 4.0 * a * f).sqrt());
    t.is_finite().then(|| pose.vector_to_world(d * t))
}

/// Where the ray `from + t dir`, `t >= 0`, crosses the boundary of `shape` (paper III-A: `B2`),
/// for `from` inside the shape and `t_far` a distance at which the ray is surely outside.
///
/// The crossing is kept bracketed, `f < 0` at one end and `f >= 0` at the other, as in the
/// paper's bisection; steps are regula falsi with the Illinois modification, which converges in
/// a handful of evaluations on smooth boundaries, and a bisection step whenever a step fails to
/// halve the bracket, so it is never slower than bisection either.
pub fn ray_to_boundary<S: ImplicitShape + ?Sized>(
    shape: &S,
    from: Vec2,
    dir: Vec2,
    t_far: f64,
) -> Vec2 {
    let at = |t: f64| from + dir * t;
    let (mut t0, mut f0) = (0.0, shape.value(from));
    if f0.is_nan() || f0 >= 0.0 {
        return from;
    }
    // A Newton step from `from`, a little long so that it usually lands outside and closes the
    // bracket at once: the far end is often many times farther than the boundary, and is then
    // never evaluated.
    let mut outside = None;
    let slope = shape.gradient(from).dot(dir);
    if slope > 0.0 {
        let guess = -f0 / slope * 1.05;
        if guess > 0.0 && guess < t_far {
            let fg = shape.value(at(guess));
            if fg >= 0.0 {
                outside = Some((guess, fg));
            } else if !fg.is_nan() {
                (t0, f0) = (guess, fg);
            }
        }
    }
    let (t1, f1) = match outside {
        Some(end) => end,
        None => {
            let f_far = shape.value(at(t_far));
            if f_far.is_nan() || f_far < 0.0 {
                // Not outside after all (cannot happen with a true bound): the far point.
                return at(t_far);
            }
            (t_far, f_far)
        }
    };
    // Far below any quadtree cell: the push is exact to ~1e-10 of the shape's size; `|f|` of
    // 1e-14 is well within that of the boundary for any sane gradient.
    at(bracketed_root(
        (t0, f0),
        (t1, f1),
        t_far * 1e-10,
        1e-14,
        |t| shape.value(at(t)),
    ))
}

/// A root of `f` between `t0 < t1`, where `f0 = f(t0) < 0 <= f1 = f(t1)`: regula falsi with the
/// Illinois modification (a stale end's value halved), and a bisection step after two steps in a
/// row that failed to halve the bracket, so never slower than bisection. Returns a point where
/// `|f| <= small`, or the middle of the bracket once it is at most `tol` wide (or after 200
/// evaluations, or at a value that is not a number).
pub(crate) fn bracketed_root(
    (mut t0, mut f0): (f64, f64),
    (mut t1, mut f1): (f64, f64),
    tol: f64,
    small: f64,
    mut f: impl FnMut(f64) -> f64,
) -> f64 {
    let mut side = 0i8;
    let mut slow = 0u8;
    for _ in 0..200 {
        let width = t1 - t0;
        if width <= tol {
            break;
        }
        let secant = (t0 * f1 - t1 * f0) / (f1 - f0);
        let t = if slow >= 2 || !(secant > t0 && secant < t1) {
            slow = 0;
            0.5 * (t0 + t1)
        } else {
            secant
        };
        let ft = f(t);
        if ft.is_nan() {
            break;
        }
        if ft.abs() <= small {
            return t;
        }
        if ft < 0.0 {
            (t0, f0) = (t, ft);
            if side == -1 {
                f1 *= 0.5;
            }
            side = -1;
        } else {
            (t1, f1) = (t, ft);
            if side == 1 {
                f0 *= 0.5;
            }
            side = 1;
        }
        slow = if t1 - t0 > 0.5 * width { slow + 1 } else { 0 };
    }
    0.5 * (t0 + t1)
}

/// [`ray_to_boundary`] for a shape whose `f` is convex (a superellipse with every exponent at
/// least 1): Newton on `phi(t) = f(from + t dir)`. From inside, where `phi < 0` and
/// `phi' > 0`, the first step lands on or beyond the crossing (a convex `phi` lies above its
/// tangent), and from there every step moves back towards it without passing it (`phi` is
/// increasing and convex beyond the crossing): the same answer, to the same tolerance, in
/// three or four evaluations of value and gradient where the bracketed search needs five or
/// more. Anything unexpected (a slope that is not positive, a step beyond `t_far`, a value
/// that is not a number, rounding that stalls) hands over to [`ray_to_boundary`].
pub fn ray_to_convex_boundary<S: ImplicitShape + ?Sized>(
    shape: &S,
    from: Vec2,
    dir: Vec2,
    t_far: f64,
) -> Vec2 {
    let (f, g) = shape.value_and_gradient(from);
    convex_exit(shape, from, dir, t_far, f, g)
}

/// [`ray_to_convex_boundary`] with `f` and `grad f` at `from` known.
fn convex_exit<S: ImplicitShape + ?Sized>(
    shape: &S,
    from: Vec2,
    dir: Vec2,
    t_far: f64,
    mut f: f64,
    mut g: Vec2,
) -> Vec2 {
    let at = |t: f64| from + dir * t;
    if f.is_nan() || f >= 0.0 {
        return from;
    }
    // As the bracketed search's: far below any quadtree cell.
    let tol = t_far * 1e-10;
    let mut t = 0.0;
    for _ in 0..CONVEX_NEWTON_STEPS {
        let slope = g.dot(dir);
        if slope.is_nan() || slope <= 0.0 {
            break;
        }
        let next = t - f / slope;
        if !(0.0..=t_far).contains(&next) {
            break;
        }
        if (next - t).abs() <= tol {
            return at(next);
        }
        t = next;
        (f, g) = shape.value_and_gradient(at(t));
        if f.is_nan() {
            break;
        }
        if f == 0.0 {
            return at(t);
        }
    }
    ray_to_boundary(shape, from, dir, t_far)
}

/// Newton steps before [`ray_to_convex_boundary`] gives up: it converges quadratically, in
/// three or four.
const CONVEX_NEWTON_STEPS: usize = 12;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interval::PlacedSuperellipse;
    use crate::shape::{Pose, Superellipse};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A pose anywhere in [-5, 5]^2 at any angle.
    fn random_pose(rng: &mut ChaCha8Rng) -> Pose {
        Pose::new(
            Vec2::new(rng.random_range(-5.0..5.0), rng.random_range(-5.0..5.0)),
            rng.random_range(0.0..std::f64::consts::TAU),
        )
        .unwrap()
    }

    /// Where `inside(t)` turns false on `[0, hi]` (true at 0, false at `hi`), by 200 halvings:
    /// to the last bit.
    fn bisect(hi: f64, inside: impl Fn(f64) -> bool) -> f64 {
        let (mut lo, mut hi) = (0.0, hi);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if inside(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// Where the ray from `p` (inside) along the unit `d` leaves the ellipse with semi-axes
    /// `(a, b)` at the origin: the positive root of `(p + t d)^T D (p + t d) = 1`, a quadratic.
    fn ellipse_exit(a: f64, b: f64, p: Vec2, d: Vec2) -> f64 {
        let qa = d.x * d.x / (a * a) + d.y * d.y / (b * b);
        let qb = 2.0 * (p.x * d.x / (a * a) + p.y * d.y / (b * b));
        let qc = p.x * p.x / (a * a) + p.y * p.y / (b * b) - 1.0;
        (-qb + (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa)
    }

    /// Both searches land where the quadratic formula says the ray leaves an ellipse, from
    /// points deep inside to points a hair inside, along random directions and along the
    /// gradient (the push's direction).
    #[test]
    fn both_searches_find_where_a_ray_leaves_an_ellipse() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for case in 0..2000 {
            let (a, b) = (rng.random_range(0.1..2.0), rng.random_range(0.1..2.0));
            let shape = Superellipse::new([a, b], [2.0, 2.0]).unwrap();
            let placed = PlacedSuperellipse::new(shape, Pose::ORIGIN);
            let theta: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            // Scaled towards the boundary: depth from 1 down to 1e-12 of the way.
            let scale = 1.0 - 10f64.powf(-rng.random_range(0.0..12.0));
            let p = shape.boundary_point(theta) * scale;
            let d = if case % 2 == 0 {
                placed.gradient(p).direction().unwrap()
            } else {
                let phi: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                Vec2::new(phi.cos(), phi.sin())
            };
            let t_far = p.norm() + a.max(b) * 1.01;
            let exact = p + d * ellipse_exit(a, b, p, d);
            for (name, found) in [
                ("bracketed", ray_to_boundary(&placed, p, d, t_far)),
                ("convex", ray_to_convex_boundary(&placed, p, d, t_far)),
            ] {
                let err = (found - exact).norm();
                assert!(
                    err <= 1e-9 * a.max(b),
                    "{name}: case {case}, ellipse ({a}, {b}), from {p:?} along {d:?}: \
                     {found:?} is {err:e} from {exact:?}"
                );
            }
        }
    }

    /// On a star's cusp (a point of a spike's axis, a hair off it), the paper model's push
    /// runs along the spike to its tip (the closed form of where it leaves the spike), while the
    /// gradient's push leaves the spike through its side (the mixed preset took 2.3x the time
    /// with it). Off the axis by more than the cusp's width, the two are the same.
    #[test]
    fn the_papers_push_on_a_cusp_runs_along_the_spike() {
        let star = Superellipse::new([0.4, 0.3], [0.3, 0.5]).unwrap();
        let pose = Pose::new(Vec2::new(0.2, -0.1), 0.6).unwrap();
        let placed = PlacedSuperellipse::new(star, pose);
        for (u, off) in [(0.1, 1e-9), (0.25, -3e-8), (0.35, 1e-10)] {
            // The cusp of `|y|^0.5` is the local x axis: the spike along +x.
            let from = pose.to_world(Vec2::new(u, off));
            let along = push_out_by(&placed, from, true);
            // Where the line `y = off` leaves the spike: `|x / 0.4|^0.3 = 1 - |off / 0.3|^0.5`.
            let exit = 0.4 * (1.0 - (off.abs() / 0.3).sqrt()).powf(1.0 / 0.3);
            let want = pose.vector_to_world(Vec2::new(exit - u, 0.0));
            assert!(
                (along - want).norm() <= 1e-9,
                "{u}: {along:?} against {want:?}"
            );
            let side = pose.to_local(from + push_out_by(&placed, from, false)) - Vec2::new(u, off);
            assert!(
                side.y.abs() > side.x.abs(),
                "{u}: the gradient's push {side:?}"
            );
        }
        let from = pose.to_world(Vec2::new(0.2, 0.01));
        assert_eq!(push_out_by(&placed, from, true), push_out(&placed, from));
    }

    /// The push out of an ellipse (closed form) and of other convex shapes (Newton along the
    /// ray) ends on the boundary, along the gradient: against the quadratic formula for
    /// rotated, moved ellipses, and against bisection for exponents 1 to 6.
    #[test]
    fn push_out_ends_where_the_gradient_ray_leaves_the_shape() {
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        for case in 0..3000 {
            let ellipse = case % 2 == 0;
            let e = |rng: &mut ChaCha8Rng| {
                if ellipse {
                    2.0
                } else {
                    rng.random_range(1.0..6.0)
                }
            };
            let (a, b) = (rng.random_range(0.1..2.0), rng.random_range(0.1..2.0));
            let shape = Superellipse::new([a, b], [e(&mut rng), e(&mut rng)]).unwrap();
            let pose = random_pose(&mut rng);
            let placed = PlacedSuperellipse::new(shape, pose);
            let theta: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let scale = 1.0 - 10f64.powf(-rng.random_range(0.0..12.0));
            let local = shape.boundary_point(theta) * scale;
            let from = pose.to_world(local);
            let push = push_out(&placed, from);
            // Along the gradient (in the shape's frame: `(x e |x|^(e-2) / s^e, ...)`).
            let g = shape.local_gradient(local);
            let d = g.direction().unwrap();
            let along = pose.vector_to_world(d);
            assert!(
                push.cross(along).abs() <= 1e-12 * a.max(b),
                "case {case}: {push:?} not along {along:?}"
            );
            let exact = if ellipse {
                ellipse_exit(a, b, local, d)
            } else {
                bisect(4.0 * a.max(b), |t| shape.local_value(local + d * t) < 0.0)
            };
            let err = (push.norm() - exact).abs();
            assert!(
                err <= 1e-9 * a.max(b),
                "case {case}, {shape:?} at {pose:?}, from {from:?}: push {} against {exact} \
                 (error {err:e})",
                push.norm()
            );
        }
    }

    /// On blocky and diamond-like shapes (exponents 1 to 8, rotated, off the origin) the Newton
    /// search agrees with plain bisection run to the last bit.
    #[test]
    fn the_convex_search_agrees_with_bisection_on_superellipses() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        for case in 0..2000 {
            let shape = Superellipse::new(
                [rng.random_range(0.1..2.0), rng.random_range(0.1..2.0)],
                [rng.random_range(1.0..8.0), rng.random_range(1.0..8.0)],
            )
            .unwrap();
            let pose = random_pose(&mut rng);
            let placed = PlacedSuperellipse::new(shape, pose);
            let theta: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let scale = 1.0 - 10f64.powf(-rng.random_range(0.0..10.0));
            let p = pose.to_world(shape.boundary_point(theta) * scale);
            let phi: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let d = Vec2::new(phi.cos(), phi.sin());
            let r = shape.bounding_radius();
            let t_far = 2.0 * r * 1.01;
            let exact = p + d * bisect(t_far, |t| placed.value(p + d * t) < 0.0);
            let found = ray_to_convex_boundary(&placed, p, d, t_far);
            let err = (found - exact).norm();
            assert!(
                err <= 1e-9 * r,
                "case {case}, {shape:?} at {pose:?}, from {p:?} along {d:?}: {found:?} is \
                 {err:e} from {exact:?}"
            );
        }
    }
}

use crate::geometry::Vec2;
use crate::interval::ImplicitShape;

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
    let (mut t1, mut f1) = match outside {
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
    // Far below any quadtree cell: the push is exact to ~1e-10 of the shape's size.
    let tol = t_far * 1e-10;
    let mut side = 0i8;
    let mut slow = 0u8;
    for _ in 0..200 {
        let width = t1 - t0;
        if width <= tol {
            break;
        }
        let secant = (t0 * f1 - t1 * f0) / (f1 - f0);
        // Bisect after two steps in a row that failed to halve the bracket.
        let t = if slow >= 2 || !(secant > t0 && secant < t1) {
            slow = 0;
            0.5 * (t0 + t1)
        } else {
            secant
        };
        let ft = shape.value(at(t));
        if ft.is_nan() {
            break;
        }
        // |f| this small is well within `tol` of the boundary for any sane gradient.
        if ft.abs() <= 1e-14 {
            return at(t);
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
    at(0.5 * (t0 + t1))
}

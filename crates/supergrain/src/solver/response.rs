use super::Body;
use crate::geometry::Vec2;

/// The projection response of paper III-A (Fig. 7) for a grain whose deepest point `deepest`
/// should move by `push`: with `u = deepest -> centre`, the part of `push` along `u` moves the
/// centre and the rest turns the grain about it:
/// centre `+= share * d_par`, angle `+= sign * share * atan(|d_perp| / |u|)`, the sign being
/// that of `d_perp x d_par`. `share` is 0.5 between grains (each takes half) and 1 against a wall.
pub fn project(body: &mut Body, deepest: Vec2, push: Vec2, share: f64) {
    let u = body.center - deepest;
    let uu = u.dot(u);
    if uu.is_nan() || uu <= 0.0 || !push.is_finite() {
        // The deepest point is the centre itself: nothing to turn about, move straight.
        if push.is_finite() {
            body.center += push * share;
        }
        return;
    }
    let d_par = u * (push.dot(u) / uu);
    let d_perp = push - d_par;
    body.center += d_par * share;
    let turn = (d_perp.norm() / uu.sqrt()).atan();
    let sign = d_perp.cross(d_par).signum();
    if turn.is_finite() && sign != 0.0 {
        body.angle += sign * share * turn;
    }
}

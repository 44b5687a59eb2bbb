use crate::body::Body;
use crate::geometry::Vec2;

/// The projection response of paper III-A (Fig. 7) for a grain whose deepest point `deepest`
/// should move by `push`: with `u = deepest -> centre`, the part of `push` along `u` moves the
/// centre and the rest turns the grain about it:
/// centre `+= share * d_par`, angle `+= sign * share * atan(|d_perp| / |u|)`, the sign being
/// that of `d_perp x d_par`. `share` is 0.5 between grains (each takes half) and 1 against a wall.
/// Penetrations shallower than `slop` move the grain but do not turn it.
pub fn project(body: &mut Body, deepest: Vec2, push: Vec2, share: f64, slop: f64) {
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
    // Box2D's slop, applied to the paper's response: only the part of a penetration deeper than
    // `slop` moves the grain along `u` and turns it; a shallower one moves it straight along the
    // push. A resting grain sinks about g h^2 per step and is projected back; moving it along `u`
    // and turning it by that much every step makes it slide and roll for ever (on a flat face
    // the deepest point may be anywhere along the face), and heaps never rest.
    let depth = push.norm();
    let k = ((depth - slop) / depth).max(0.0);
    body.center += (d_par * k + push * (1.0 - k)) * share;
    let turn = (d_perp.norm() / uu.sqrt()).atan() * k;
    let sign = d_perp.cross(d_par).signum();
    if turn.is_finite() && sign != 0.0 {
        body.angle += sign * share * turn;
    }
}

/// The push actually applied to a grain, made safe (SPEC §4: "handle it gracefully"). Once a
/// centre has passed the other's, or spikes of stars interlock, the estimate can point into the
/// other grain: it is then turned to point straight away from the other's centre. And, as in
/// Box2D, no single correction moves a grain by more than `cap`: an impact is resolved over a
/// few passes instead of throwing a grain across the box.
pub fn safe_push(push: Vec2, away: Vec2, cap: f64) -> Vec2 {
    let push = if push.dot(away) < 0.0 {
        away.direction().map_or(push, |d| d * push.norm())
    } else {
        push
    };
    let length = push.norm();
    if length > cap {
        push * (cap / length)
    } else {
        push
    }
}

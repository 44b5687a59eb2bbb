//! Witnesses on the half-axes (issue 17): points of a shape's four half-axes, the segments
//! from its centre to its tips, proven inside the other shape.
//!
//! The quadtree proves an overlap only at a cell's midpoint, so a spike thinner than a final
//! cell can reach deep into the other shape between midpoints: a star (exponents 0.3) was
//! reported apart from a block it reached 1.4 cells into, and a star's spike 0.5 into a circle
//! was missed at depth 7. Every superellipse holds its half-axes (`f = t^e - 1 < 0` at `t` of
//! the way to a tip), and every spike lies along one. More: for a point `p` of a superellipse,
//! the segment from `p` straight to the nearer axis lies in it too (`f` grows with `|x|` and
//! with `|y|` in the shape's frame), so if `p` is deeper than `d` in the other shape and within
//! `d` of an axis, that axis's point beside `p` is inside both. Searching the half-axes of
//! both shapes with a final cell's resolution therefore finds every reach deeper than its
//! distance to an axis; any other reach holds a square of side `d / sqrt 2` in both shapes
//! (the corner of `p`'s box towards the centre), which the quadtree's midpoints find once it is
//! two final cells wide. So with both, "no overlap" means no point of one shape lies more than
//! three final cells inside the other, whatever the shapes.

use crate::geometry::{Aabb, Vec2};
use crate::interval::{ImplicitShape, PlacedSuperellipse};
use crate::subdivision::Deepest;

/// Halvings of a half-axis, at most, before its points are evaluated: 2^7 pieces, the paper's
/// depth, bound the work however fine the cell (with up to 2^12 and the search in the solver,
/// the mixed preset ran at 16 steps/s against 40 without it). With a finer quadtree the
/// guarantee is then four cells of depth 7 of the pair's box.
const MAX_LEVELS: u32 = 7;

/// The point of `own`'s half-axes deepest in `other` among those the search evaluates (a
/// final cell apart, within `region`), proven inside both, if any. `cell`: the final cell.
///
/// `slack`: each witness is proven inside both over the box of that half-width about it, not
/// at the point alone. A witness lies on a star's axis, where `f` rises like `|v|^e` across
/// it: the rounding of world coordinates (`1e-17` off the axis) would take a point proven
/// inside by `1e-10` to `1e-5` outside at exponent 0.25. The caller's slack covers a few ulps
/// of the world coordinates.
pub(crate) fn spike_witness<O: ImplicitShape + ?Sized>(
    own: &PlacedSuperellipse,
    other: &O,
    region: &Aabb,
    cell: f64,
    slack: f64,
) -> Option<Deepest> {
    let pose = own.pose();
    let centre = pose.center();
    let s = own.shape().semi_axes();
    let tips = [
        Vec2::new(s.x, 0.0),
        Vec2::new(-s.x, 0.0),
        Vec2::new(0.0, s.y),
        Vec2::new(0.0, -s.y),
    ];
    let mut best: Option<Deepest> = None;
    for tip in tips {
        // The tip itself is on the boundary: stop a hair short of it.
        let end = pose.to_world(tip * (1.0 - 1e-9));
        let Some((t0, t1)) = clip(centre, end, region) else {
            continue;
        };
        let length = (end - centre).norm() * (t1 - t0);
        let levels = if length > cell && cell > 0.0 {
            ((length / cell).log2().ceil() as u32).min(MAX_LEVELS)
        } else {
            0
        };
        search(own, other, centre, end, (t0, t1), levels, slack, &mut best);
    }
    best
}

/// The part `[t0, t1]` of the segment `a + t (b - a)`, `t` in `[0, 1]`, inside `region`.
fn clip(a: Vec2, b: Vec2, region: &Aabb) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, d, lo, hi) in [
        (a.x, b.x - a.x, region.min.x, region.max.x),
        (a.y, b.y - a.y, region.min.y, region.max.y),
    ] {
        if d == 0.0 {
            if p < lo || p > hi {
                return None;
            }
            continue;
        }
        let (u, v) = ((lo - p) / d, (hi - p) / d);
        let (u, v) = if u <= v { (u, v) } else { (v, u) };
        t0 = t0.max(u);
        t1 = t1.min(v);
    }
    (t0.is_finite() && t1.is_finite() && t0 <= t1).then_some((t0, t1))
}

/// Branch and bound along one half-axis: a piece whose box is proven outside `other` is
/// dropped; the rest are halved `levels` times and their midpoints tried.
#[allow(clippy::too_many_arguments)] // one recursion's state, passed down as it is
fn search<O: ImplicitShape + ?Sized>(
    own: &PlacedSuperellipse,
    other: &O,
    a: Vec2,
    b: Vec2,
    (t0, t1): (f64, f64),
    levels: u32,
    slack: f64,
    best: &mut Option<Deepest>,
) {
    let at = |t: f64| a + (b - a) * t;
    let (p, q) = (at(t0), at(t1));
    let piece = Aabb::new(
        Vec2::new(p.x.min(q.x), p.y.min(q.y)),
        Vec2::new(p.x.max(q.x), p.y.max(q.y)),
    );
    let bound = best.map_or(0.0, |d| d.other_value);
    if other.enclose(&piece).lo >= bound {
        return;
    }
    let tm = 0.5 * (t0 + t1);
    if levels == 0 {
        let m = at(tm);
        let around = Aabb::new(m - Vec2::new(slack, slack), m + Vec2::new(slack, slack));
        let inside_other = other.enclose(&around).hi;
        if inside_other < bound && own.enclose(&around).hi < 0.0 {
            *best = Some(Deepest {
                point: m,
                other_value: inside_other,
            });
        }
        return;
    }
    search(own, other, a, b, (t0, tm), levels - 1, slack, best);
    search(own, other, a, b, (tm, t1), levels - 1, slack, best);
}

//! Pushes that separate (issue 17): the paper's two penetration vectors, `A1 -> B2` along
//! `grad f_B` and `A2 -> B1` along `grad f_A`, made to act along one normal, `A`'s way and
//! `B`'s way opposite.
//!
//! The gradients alone can mislead in two ways, both measured:
//! - Where a deepest point is the other shape's centre (one shape holds the other's centre:
//!   nested shapes), the gradient there vanishes and its direction is arbitrary: a disk inside
//!   a disk, both at the origin, was pushed `[0.1, 0]` and `[1, 0]`, the same way.
//! - On stars the gradient near a spike's axis is nearly along the other axis: two identical
//!   stars side by side (exponents 0.5, centres 1 apart along x) were pushed `[-0.054, 0.259]`
//!   and `[0.054, 0.259]`, both up, a net lift of the pair that the projection turns into
//!   energy. Worse, the pushes of two stars can point into each other, or across each other in
//!   opposite ways: of 1,750 random overlapping pairs with a star (`tests/pushes.rs`), moving by
//!   them deepened 16 overlaps (0.09 to 0.13 for stars of size 0.45).
//!
//! So the pair gets a normal `n` (from A towards B); A's push must point along `-n` and B's
//! along `n`, and a push that does not is replaced by the exit from its deepest point along
//! its way.
//! - Between convex shapes `n` is the direction of the relative push `b_push - a_push`, and
//!   pushes that pass the check (every contact near touching) are the paper's, unchanged: each
//!   is the short way out of the other at its deepest point (two thin rods crossing are pushed
//!   across each other, both a little sideways, and rightly).
//! - When one shape holds the other's centre, the overlap is deep and the gradients at the
//!   centres say nothing: `n` is the line of the centres, or, for centres that coincide, the
//!   holder's shorter axis, the short way out.
//! - When either is a star, `n` is the line of the centres and each push keeps only its part
//!   along `n`. A superellipse, star or not, holds the segment from its centre to each of its
//!   points, so moving the centres apart is the way out that does not cross a spike. Measured
//!   on the same 1,750 pairs: no overlap deepened.

use super::certified::convex;
use super::ray::exit_along;
use crate::geometry::Vec2;
use crate::interval::{ImplicitShape, PlacedSuperellipse};

/// `(a_push, b_push)` made to separate, for `a1`, `a2` and the pushes in A's frame (`a` at the
/// origin of its frame, `b` placed in it), or `None` when the paper's pushes already do (they
/// are then kept bit for bit, and with them `B2` on B's boundary).
pub(crate) fn separating(
    a: &PlacedSuperellipse,
    b: &PlacedSuperellipse,
    a1: Vec2,
    a2: Vec2,
    a_push: Vec2,
    b_push: Vec2,
) -> Option<(Vec2, Vec2)> {
    let (ca, cb) = (a.pose().center(), b.pose().center());
    let holds = |own: &PlacedSuperellipse, c: Vec2| own.value(c) < 0.0;
    let deep = holds(a, cb) || holds(b, ca);
    let stars = !convex(a.shape()) || !convex(b.shape());
    let n = if deep || stars {
        (cb - ca).direction()
    } else {
        (b_push - a_push)
            .direction()
            .or_else(|| (cb - ca).direction())
    }
    .unwrap_or_else(|| {
        // Centres that coincide: out along the holder's shorter axis.
        let holder = if holds(a, cb) { a } else { b };
        let s = holder.shape().semi_axes();
        let local = if s.x <= s.y {
            Vec2::new(1.0, 0.0)
        } else {
            Vec2::new(0.0, 1.0)
        };
        holder.pose().vector_to_world(local)
    });
    let (ka, kb) = (a_push.dot(-n), b_push.dot(n));
    let wrong_way = |k: f64| !(k > 0.0 && k.is_finite());
    if !(wrong_way(ka) || wrong_way(kb) || stars) {
        return None;
    }
    // A deepest point at the other's very centre (the answer when a shape holds that centre)
    // has no gradient there to push along: its push went an arbitrary way (measured, a star
    // holding another's centre was pushed 0.0015 along the centres' line for an overlap 0.16
    // deep), and its exit along the normal is the way out.
    let keep = |push: Vec2, k: f64, way: Vec2, from: Vec2, out_of: &PlacedSuperellipse| {
        if wrong_way(k) || from == out_of.pose().center() {
            exit_along(out_of, from, way)
        } else if stars {
            way * k
        } else {
            push
        }
    };
    Some((keep(a_push, ka, -n, a1, b), keep(b_push, kb, n, a2, a)))
}

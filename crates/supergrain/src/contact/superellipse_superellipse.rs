use super::{Contact, Penetration, ray_to_boundary};
use crate::geometry::Vec2;
use crate::interval::{ImplicitShape, PlacedSuperellipse};
use crate::shape::{Pose, Superellipse};
use crate::subdivision::{CellSink, Precision, deepest_points};

/// The contact of two placed superellipses (paper II, III-A).
///
/// ```
/// use supergrain::{contact::contact, geometry::Vec2, shape::{Pose, Superellipse}, subdivision::Precision};
/// let disk = Superellipse::circle(1.0).unwrap();
/// let a = Pose::new(Vec2::new(0.0, 0.0), 0.0).unwrap();
/// let b = Pose::new(Vec2::new(1.9, 0.0), 0.0).unwrap();
/// let c = contact(&disk, &a, &disk, &b, &Precision::default());
/// let p = c.penetration.expect("the disks overlap by 0.1");
/// assert!(p.a_push.x < 0.0); // A is pushed away from B
/// ```
pub fn contact(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
) -> Contact {
    contact_with_cells(a, pose_a, b, pose_b, precision, &mut ())
}

/// [`contact`], handing every classified cell to `sink`. The quadtree runs in A's local frame,
/// where A's own classification is exact, and the cells are given in that frame.
pub fn contact_with_cells<S: CellSink + ?Sized>(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    sink: &mut S,
) -> Contact {
    // Cheap rejection by bounding circles before any box or interval.
    let reach = a.bounding_radius() + b.bounding_radius();
    let gap = (pose_b.center() - pose_a.center()).norm();
    if gap > reach || gap.is_nan() {
        return Contact {
            penetration: None,
            cells: 0,
        };
    }

    // Work in A's frame (parry's `pos12`): A is axis-aligned at the origin there.
    let origin = Pose::new(Vec2::ZERO, 0.0).expect("the origin is a valid pose");
    let local_a = PlacedSuperellipse::new(*a, origin);
    let local_b = PlacedSuperellipse::new(*b, pose_a.relative(pose_b));
    let Some(region) = local_a.bounding_box().intersection(&local_b.bounding_box()) else {
        return Contact {
            penetration: None,
            cells: 0,
        };
    };

    let found = deepest_points(&local_a, &local_b, &region, precision, true, sink);
    let penetration = match (found.in_a, found.in_b) {
        (Some(a1), Some(a2)) => {
            let a1 = polish(&local_a, &local_b, a1.point);
            let a2 = polish(&local_b, &local_a, a2.point);
            let a_push = push_out(&local_b, a1);
            let b_push = push_out(&local_a, a2);
            Some(Penetration {
                a_deepest: pose_a.to_world(a1),
                b_deepest: pose_a.to_world(a2),
                a_push: pose_a.vector_to_world(a_push),
                b_push: pose_a.vector_to_world(b_push),
            })
        }
        _ => None,
    };
    Contact {
        penetration,
        cells: found.cells,
    }
}

/// Unless `own` holds `other`'s centre, the deepest point of `own` in `other` lies on `own`'s
/// boundary (`f_other` grows along every ray from `other`'s centre, see
/// [`crate::subdivision`]), while the quadtree's is a cell midpoint up to half a cell inside. Moving it along `grad f_own` to the boundary removes that
/// error from the penetration estimate, which otherwise makes resting grains jitter by about a
/// cell per step. Kept only when the moved point is still proven inside `other`, and deeper.
fn polish(own: &PlacedSuperellipse, other: &PlacedSuperellipse, point: Vec2) -> Vec2 {
    if own.enclose_point(other.pose().center()).lo <= 0.0 {
        // `own` may hold `other`'s centre, which is then the deepest point: not on the boundary.
        return point;
    }
    let on_boundary = point + push_out(own, point);
    // A hair inside, so that the proof of being inside `own` survives rounding.
    let inside = point + (on_boundary - point) * (1.0 - 1e-9);
    // And only when it is at least as deep: on a thin shape the gradient may lead to the far
    // side, away from `other`'s centre.
    if own.enclose_point(inside).hi < 0.0
        && other.enclose_point(inside).hi < 0.0
        && other.value(inside) <= other.value(point)
    {
        inside
    } else {
        point
    }
}

/// `A1 -> B2`: from a point inside `other` along `grad f_other` to its boundary.
fn push_out(other: &PlacedSuperellipse, from: Vec2) -> Vec2 {
    let centre = other.pose().center();
    // The gradient vanishes only at the centre of a symmetric shape; then any way out will do,
    // and straight away from the centre (or along x) is as good as any.
    let dir = other
        .gradient(from)
        .direction()
        .or_else(|| (from - centre).direction())
        .unwrap_or(Vec2::new(1.0, 0.0));
    // From any point within the bounding circle, this far along is outside it.
    let t_far = ((from - centre).norm() + other.shape().bounding_radius()) * (1.0 + 1e-9)
        + f64::MIN_POSITIVE;
    ray_to_boundary(other, from, dir, t_far) - from
}

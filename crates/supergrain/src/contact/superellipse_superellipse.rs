use super::certified::{self, Certified, WarmStart};
use super::ray::push_out;
use super::{Contact, Penetration};
use crate::geometry::{Aabb, Vec2};
use crate::interval::{ImplicitShape, PlacedSuperellipse};
use crate::shape::{Pose, Superellipse};
use crate::subdivision::{CellSink, Precision, deepest_points};

/// The contact of two placed superellipses (paper II, III-A).
///
/// Convex pairs (every exponent at least 1) first try the certified Newton path
/// ([`super::certified`]): a Newton solve for each deepest point, kept only with a proof that it
/// lies inside both shapes and is deepest up to one final quadtree cell, or a proof that the
/// shapes are apart (within a cell). Without a proof, and for stars, the quadtree answers
/// ([`contact_quadtree`]).
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
    contact_warm(a, pose_a, b, pose_b, precision, &mut None)
}

/// [`contact`] for a persisting contact: `warm` holds where the last query of this pair found
/// its deepest points (`None` the first time), and is updated. It only starts the Newton
/// solves nearer their answers; every answer is certified afresh, so it is the same contact up
/// to the certificate's tolerance.
pub fn contact_warm(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    warm: &mut Option<WarmStart>,
) -> Contact {
    if !certified::eligible(a, b) {
        return contact_with_cells(a, pose_a, b, pose_b, precision, &mut ());
    }
    let Some((local_a, local_b, region)) = frame(a, pose_a, b, pose_b) else {
        return Contact {
            penetration: None,
            cells: 0,
        };
    };
    let cell = precision.cell_size(&region);
    match certified::certified_contact(&local_a, &local_b, cell, warm) {
        Some(Certified::Apart) => Contact {
            penetration: None,
            cells: 0,
        },
        Some(Certified::Overlap {
            a1,
            a2,
            a_push,
            b_push,
        }) => Contact {
            penetration: Some(Penetration {
                a_deepest: pose_a.to_world(a1),
                b_deepest: pose_b.to_world(a2),
                a_push: pose_a.vector_to_world(a_push),
                b_push: pose_b.vector_to_world(b_push),
            }),
            cells: 0,
        },
        None => quadtree(pose_a, &local_a, &local_b, &region, precision, &mut ()),
    }
}

/// The paper's quadtree alone, for every pair (the reference the certified path is tested
/// against, and `narrow_phase = "quadtree"`).
pub fn contact_quadtree(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
) -> Contact {
    contact_with_cells(a, pose_a, b, pose_b, precision, &mut ())
}

/// [`contact_quadtree`], handing every classified cell to `sink`. The quadtree runs in A's local
/// frame, where A's own classification is exact, and the cells are given in that frame.
pub fn contact_with_cells<S: CellSink + ?Sized>(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    sink: &mut S,
) -> Contact {
    match frame(a, pose_a, b, pose_b) {
        Some((local_a, local_b, region)) => {
            quadtree(pose_a, &local_a, &local_b, &region, precision, sink)
        }
        None => Contact {
            penetration: None,
            cells: 0,
        },
    }
}

/// Both shapes in A's frame (parry's `pos12`: A axis-aligned at the origin) and the
/// intersection of their boxes, or `None` when the bounding circles or boxes are apart.
// Inlined: the two placed shapes are then built where the caller keeps them, not copied out.
#[inline(always)]
fn frame(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
) -> Option<(PlacedSuperellipse, PlacedSuperellipse, Aabb)> {
    // Cheap rejection by bounding circles before any box or interval.
    let reach = a.bounding_radius() + b.bounding_radius();
    let gap = (pose_b.center() - pose_a.center()).norm();
    if gap > reach || gap.is_nan() {
        return None;
    }
    let local_a = PlacedSuperellipse::new(*a, Pose::ORIGIN);
    let local_b = PlacedSuperellipse::new(*b, pose_a.relative(pose_b));
    let region = local_a
        .bounding_box()
        .intersection(&local_b.bounding_box())?;
    Some((local_a, local_b, region))
}

fn quadtree<S: CellSink + ?Sized>(
    pose_a: &Pose,
    local_a: &PlacedSuperellipse,
    local_b: &PlacedSuperellipse,
    region: &Aabb,
    precision: &Precision,
    sink: &mut S,
) -> Contact {
    let found = deepest_points(local_a, local_b, region, precision, true, sink);
    let penetration = match (found.in_a, found.in_b) {
        (Some(a1), Some(a2)) => {
            let a1 = polish(local_a, local_b, a1.point);
            let a2 = polish(local_b, local_a, a2.point);
            let a_push = push_out(local_b, a1);
            let b_push = push_out(local_a, a2);
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

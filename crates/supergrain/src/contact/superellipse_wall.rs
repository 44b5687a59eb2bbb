use super::certified;
use super::{WallContact, WallPenetration};
use crate::geometry::Aabb;
use crate::interval::PlacedSuperellipse;
use crate::shape::{HalfPlane, Pose, Superellipse};
use crate::subdivision::{CellSink, Precision, deepest_points};

/// The contact of a placed superellipse with a wall (paper III-B).
///
/// Answered by the certified path ([`super::certified`]): the shape's support point towards the
/// wall (closed form, dual bound, a star's tip, or a search over the boundary), proven inside
/// both and deepest up to half a final cell, or the shape proven clear of the wall. When that
/// proof fails, the quadtree ([`contact_wall_quadtree`]).
pub fn contact_wall(
    shape: &Superellipse,
    pose: &Pose,
    wall: &HalfPlane,
    precision: &Precision,
) -> WallContact {
    let Some((placed, region)) = frame(shape, pose, wall) else {
        return WallContact {
            penetration: None,
            cells: 0,
        };
    };
    match certified::certified_wall(&placed, wall, precision.cell_size(&region)) {
        Some(deepest) => WallContact {
            penetration: deepest.map(|d| WallPenetration {
                deepest: d,
                push: wall.project(d) - d,
            }),
            cells: 0,
        },
        None => quadtree(&placed, wall, &region, precision, &mut ()),
    }
}

/// The paper's quadtree alone (paper III-B): the quadtree runs on `shape box ∩ wall
/// half-plane` (paper Fig. 8), in world coordinates, where that region is a thin axis-aligned
/// strip for the box's walls. `B` is the projection of the deepest point on the wall's
/// surface, with no bisection needed.
pub fn contact_wall_quadtree(
    shape: &Superellipse,
    pose: &Pose,
    wall: &HalfPlane,
    precision: &Precision,
) -> WallContact {
    contact_wall_with_cells(shape, pose, wall, precision, &mut ())
}

/// [`contact_wall`], handing every classified cell (world coordinates) to `sink`.
pub fn contact_wall_with_cells<S: CellSink + ?Sized>(
    shape: &Superellipse,
    pose: &Pose,
    wall: &HalfPlane,
    precision: &Precision,
    sink: &mut S,
) -> WallContact {
    match frame(shape, pose, wall) {
        Some((placed, region)) => quadtree(&placed, wall, &region, precision, sink),
        None => WallContact {
            penetration: None,
            cells: 0,
        },
    }
}

/// The placed shape and `shape box ∩ wall half-plane`, or `None` when they do not meet.
fn frame(
    shape: &Superellipse,
    pose: &Pose,
    wall: &HalfPlane,
) -> Option<(PlacedSuperellipse, Aabb)> {
    // The box first: most grains are far from most walls, and are then never placed.
    let region = shape
        .bounding_box(pose)
        .intersection(&wall.bounding_box())?;
    Some((PlacedSuperellipse::new(*shape, *pose), region))
}

fn quadtree<S: CellSink + ?Sized>(
    placed: &PlacedSuperellipse,
    wall: &HalfPlane,
    region: &Aabb,
    precision: &Precision,
    sink: &mut S,
) -> WallContact {
    let found = deepest_points(placed, wall, region, precision, false, sink);
    WallContact {
        penetration: found.in_a.map(|d| WallPenetration {
            deepest: d.point,
            push: wall.project(d.point) - d.point,
        }),
        cells: found.cells,
    }
}

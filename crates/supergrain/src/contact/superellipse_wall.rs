use super::certified;
use super::spikes::spike_witness;
use super::superellipse_superellipse::{deeper, world_slack};
use super::{WallContact, WallPenetration};
use crate::geometry::{Aabb, Vec2};
use crate::interval::PlacedSuperellipse;
use crate::shape::{Boundary, HalfPlane, Pose, Superellipse};
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

/// The contact of a placed superellipse with any boundary (issue 41), proven as the wall's is:
/// - a half-plane: [`contact_wall`] (or the quadtree alone, `quadtree_only`);
/// - any grain whose centre is farther from the solid than its bounding radius: apart, from
///   the signed distance, which is 1-Lipschitz (within its rounding, [`Boundary::pad`]);
/// - a disk: the closed form of a disk against a distance, `depth = r - g(centre)`, reported
///   when it exceeds the rounding (as [`super::disk_disk_certified`] does two disks);
/// - a grain on one face of a thick segment, away from its ends: that face's half-plane
///   ([`Boundary::face_for`]), answered by [`contact_wall`];
/// - otherwise the quadtree on `shape box ∩ boundary box`, whose deepest point is proven in
///   both. The push takes the deepest point to the nearest point of the boundary's surface.
pub fn contact_boundary(
    shape: &Superellipse,
    pose: &Pose,
    boundary: &Boundary,
    precision: &Precision,
    quadtree_only: bool,
) -> WallContact {
    let none = WallContact {
        penetration: None,
        cells: 0,
    };
    if let Some(wall) = boundary.as_plane() {
        return if quadtree_only {
            contact_wall_quadtree(shape, pose, wall, precision)
        } else {
            contact_wall(shape, pose, wall, precision)
        };
    }
    let c = pose.center();
    let (g, pad) = (boundary.distance(c), boundary.pad(c));
    if g > shape.bounding_radius() + pad {
        return none;
    }
    if !quadtree_only {
        if shape.is_circle() {
            let r = shape.semi_axes().x;
            let depth = r - g;
            if depth <= pad {
                return none;
            }
            // Where the disk reaches past a thick segment's or arc's middle line (`g + h` from
            // its centre), that line's point is its deepest (the whole half-thickness in), and
            // the push still takes the disk out on its centre's side.
            let n = boundary.normal(c);
            let reach = boundary.half_thickness().map_or(r, |h| r.min(g + h));
            return WallContact {
                penetration: Some(WallPenetration {
                    deepest: c - n * reach,
                    push: n * depth,
                }),
                cells: 0,
            };
        }
        let rotation = pose.rotation();
        let support = |d: Vec2| shape.local_support(rotation.apply_inverse(d));
        if let Some(face) = boundary.face_for(c, support) {
            return contact_wall(shape, pose, &face, precision);
        }
    }
    let Some(region) = shape
        .bounding_box(pose)
        .intersection(&boundary.bounding_box())
    else {
        return none;
    };
    let placed = PlacedSuperellipse::new(*shape, *pose);
    let found = deepest_points(&placed, boundary, &region, precision, false, &mut ());
    // Spikes thinner than a cell, along the half-axes, as for grain pairs
    // ([`super::spikes`]): "apart" then means no point more than four final cells in.
    let slack = world_slack(pose, &region);
    let cell = precision.cell_size(&region);
    let deepest = deeper(
        found.in_a,
        spike_witness(&placed, boundary, &region, cell, slack),
    );
    WallContact {
        penetration: deepest.map(|d| {
            // Past a thick segment's or arc's middle line the nearest surface is on the far
            // side; the grain goes back out on its centre's side.
            let past = boundary
                .half_thickness()
                .is_some_and(|h| -boundary.distance(d.point) > 0.5 * h);
            let push = if past {
                boundary.normal(c) * -boundary.distance(d.point)
            } else {
                boundary.project(d.point) - d.point
            };
            WallPenetration {
                deepest: d.point,
                push,
            }
        }),
        cells: found.cells,
    }
}

//! Diagrams of one collision test, as the paper's Figs. 2-9: the shapes painted by the interval
//! renderer, and on top, as asked, the quadtree's cells by class, the bounding boxes and their
//! intersection, the deepest points and the penetration vectors; and a shape against the floor.

use tiny_skia::{Color, Pixmap};

use super::pen::Pen;
use super::raster::{Antialias, Rgba, View, paint_shape_with};
use crate::contact::{Contact, WallContact, contact_wall_with_cells, contact_with_cells};
use crate::geometry::{Aabb, Vec2};
use crate::interval::{ImplicitShape, PlacedSuperellipse};
use crate::shape::{HalfPlane, Pose, Superellipse};
use crate::subdivision::{Class, Precision};

/// What a diagram shows besides the shapes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Show {
    /// The quadtree's cells: outside either shape grey outlines, inside both orange, boundary
    /// blue (filled at the last level).
    pub cells: bool,
    /// Both bounding boxes, and their intersection filled (the region the quadtree searches).
    pub boxes: bool,
    /// The deepest points and the penetration vectors.
    pub contact: bool,
}

const GREEN: Rgba = [0x2e, 0x7d, 0x32, 255];
const PURPLE: Rgba = [0x6a, 0x1b, 0x9a, 255];
const TINT_A: Rgba = [0x2e, 0x7d, 0x32, 70];
const TINT_B: Rgba = [0x6a, 0x1b, 0x9a, 70];

/// The view of a diagram: `region` with 15% around it, `width` pixels wide.
fn view_around(region: Aabb, width: u32) -> View {
    let pad = 0.15 * region.width().max(region.height());
    View::fit(region.grown(pad), width)
}

fn blank(view: &View) -> Pixmap {
    let mut pixmap = Pixmap::new(view.width, view.height).expect("a non-empty image");
    pixmap.fill(Color::WHITE);
    pixmap
}

/// How a quadtree cell is drawn, by its classes against the two shapes and whether it is at
/// the last level: its fill, if any, and its outline (colour, width in pixels), if any.
pub fn cell_style(a: Class, b: Class, last: bool) -> (Option<Rgba>, Option<(Rgba, f32)>) {
    if a == Class::Outside || b == Class::Outside {
        (None, Some(([0x9e, 0x9e, 0x9e, 255], 0.6)))
    } else if a == Class::Inside && b == Class::Inside {
        (
            Some([0xff, 0x98, 0x00, 200]),
            Some(([0xe6, 0x51, 0x00, 255], 0.6)),
        )
    } else if last {
        (
            Some([0x64, 0xb5, 0xf6, 170]),
            Some(([0x15, 0x65, 0xc0, 255], 0.6)),
        )
    } else {
        (None, Some(([0x15, 0x65, 0xc0, 255], 0.8)))
    }
}

/// Two shapes and their collision test.
pub fn collision_png(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    width: u32,
    show: Show,
) -> (Pixmap, Contact) {
    let mut cells: Vec<(Aabb, Class, Class, bool)> = Vec::new();
    let contact = contact_with_cells(a, pose_a, b, pose_b, precision, &mut cells);
    let (box_a, box_b) = (a.bounding_box(pose_a), b.bounding_box(pose_b));
    let both = Aabb::new(
        Vec2::new(box_a.min.x.min(box_b.min.x), box_a.min.y.min(box_b.min.y)),
        Vec2::new(box_a.max.x.max(box_b.max.x), box_a.max.y.max(box_b.max.y)),
    );
    let view = view_around(both, width);
    let mut pixmap = blank(&view);
    let shapes = [(a, pose_a, TINT_A), (b, pose_b, TINT_B)];
    for (shape, pose, tint) in shapes {
        let placed = PlacedSuperellipse::new(*shape, *pose);
        paint_shape_with(pixmap.data_mut(), &view, &placed, tint, Antialias::Gradient);
    }
    let mut pen = Pen::new(&view);
    for (shape, pose, colour) in [(a, pose_a, GREEN), (b, pose_b, PURPLE)] {
        pen.polygon(
            &mut pixmap,
            &outline(shape, pose),
            None,
            Some((colour, 1.5)),
        );
    }
    if show.boxes {
        if let Some(common) = box_a.intersection(&box_b) {
            pen.fill_box(&mut pixmap, &common, [0xff, 0xc1, 0x07, 120]);
        }
        pen.stroke_box(&mut pixmap, &box_a, GREEN, 1.2);
        pen.stroke_box(&mut pixmap, &box_b, PURPLE, 1.2);
    }
    if show.cells {
        // The cells are in A's local frame: their corners are placed in the plane.
        for (cell, ca, cb, last) in &cells {
            let corners = cell.corners().map(|p| pose_a.to_world(p));
            let (fill, line) = cell_style(*ca, *cb, *last);
            pen.polygon(&mut pixmap, &corners, fill, line);
        }
    }
    if show.contact
        && let Some(p) = contact.penetration
    {
        for (from, push, colour) in [
            (p.a_deepest, p.a_push, GREEN),
            (p.b_deepest, p.b_push, PURPLE),
        ] {
            pen.polyline(
                &mut pixmap,
                &[from, from + push],
                [0xd8, 0x1b, 0x60, 255],
                2.0,
            );
            pen.dot(&mut pixmap, from, colour, 3.5);
        }
    }
    (pixmap, contact)
}

/// A shape against the floor `y = floor` (paper Fig. 8): the wall, the region searched (the
/// shape's box below the floor), the quadtree's cells, the deepest point and the push.
pub fn wall_png(
    shape: &Superellipse,
    pose: &Pose,
    floor: f64,
    precision: &Precision,
    width: u32,
) -> (Pixmap, WallContact) {
    let wall = HalfPlane::floor(floor).expect("a finite floor");
    let mut cells: Vec<(Aabb, Class, Class, bool)> = Vec::new();
    let contact = contact_wall_with_cells(shape, pose, &wall, precision, &mut cells);
    let placed = PlacedSuperellipse::new(*shape, *pose);
    let bb = placed.bounding_box();
    let region = Aabb::new(
        Vec2::new(bb.min.x, bb.min.y.min(floor)),
        Vec2::new(bb.max.x, bb.max.y.max(floor)),
    );
    let view = view_around(region, width);
    let mut pixmap = blank(&view);
    let below = Aabb::new(view.region.min, Vec2::new(view.region.max.x, floor));
    let mut pen = Pen::new(&view);
    pen.fill_box(&mut pixmap, &below, [0x90, 0xa4, 0xae, 255]);
    paint_shape_with(
        pixmap.data_mut(),
        &view,
        &placed,
        TINT_A,
        Antialias::Gradient,
    );
    pen.polygon(&mut pixmap, &outline(shape, pose), None, Some((GREEN, 1.5)));
    pen.stroke_box(&mut pixmap, &bb, GREEN, 1.2);
    if let Some(common) = bb.intersection(&Aabb::new(below.min, below.max)) {
        pen.fill_box(&mut pixmap, &common, [0xff, 0xc1, 0x07, 120]);
    }
    // The wall test runs in the plane's frame.
    for (cell, ca, cb, last) in &cells {
        let (fill, line) = cell_style(*ca, *cb, *last);
        pen.polygon(&mut pixmap, &cell.corners(), fill, line);
    }
    if let Some(p) = contact.penetration {
        pen.polyline(
            &mut pixmap,
            &[p.deepest, p.deepest + p.push],
            [0xd8, 0x1b, 0x60, 255],
            2.0,
        );
        pen.dot(&mut pixmap, p.deepest, GREEN, 3.5);
    }
    (pixmap, contact)
}

/// The boundary as a polygon fine enough to outline a star's cusps.
fn outline(shape: &Superellipse, pose: &Pose) -> Vec<Vec2> {
    shape.boundary_polygon(pose, 720)
}

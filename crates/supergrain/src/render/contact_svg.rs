use std::fmt::Write;

use crate::contact::{Contact, contact_with_cells};
use crate::geometry::{Aabb, Vec2};
use crate::shape::{Pose, Superellipse};
use crate::subdivision::{Class, Precision};

/// The collision test of two shapes by the paper's quadtree as an SVG document `size` pixels
/// wide, and its answer.
///
/// Cells discarded (outside a shape) are outlined in grey, cells inside both are filled orange,
/// cells on a boundary are outlined in blue (filled when at the final precision). The deepest
/// points are dots and the penetration vectors arrows from them.
pub fn contact_svg(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    size: u32,
) -> (String, Contact) {
    let mut cells: Vec<(Aabb, Class, Class, bool)> = Vec::new();
    let contact = contact_with_cells(a, pose_a, b, pose_b, precision, &mut cells);
    let caption = format!(
        "overlap: {}, {} cells, depth {}",
        contact.overlap(),
        contact.cells,
        precision.depth()
    );
    let svg = draw([(a, pose_a), (b, pose_b)], &cells, &contact, &caption, size);
    (svg, contact)
}

/// An answer found without the quadtree (the certified path: `contact.cells` is 0) as an SVG
/// document `size` pixels wide: the shapes, the deepest points and the penetration vectors,
/// and no cell, since none was classified.
pub fn answer_svg(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    contact: &Contact,
    size: u32,
) -> String {
    let caption = format!(
        "overlap: {}, {} cells (answered by the certified path, not the quadtree)",
        contact.overlap(),
        contact.cells
    );
    draw([(a, pose_a), (b, pose_b)], &[], contact, &caption, size)
}

/// Two shapes, the quadtree's `cells` (in A's frame) and `contact`'s deepest points and
/// vectors, with `caption` at the top.
fn draw(
    [(a, pose_a), (b, pose_b)]: [(&Superellipse, &Pose); 2],
    cells: &[(Aabb, Class, Class, bool)],
    contact: &Contact,
    caption: &str,
    size: u32,
) -> String {
    // The view, y up: the quadtree's region with as much around it again on every side, or
    // both shapes when no cell was visited.
    let world_cells = cells
        .iter()
        .flat_map(|(c, ..)| [pose_a.to_world(c.min), pose_a.to_world(c.max)]);
    let (lo, hi, margin) = if cells.is_empty() {
        let (ba, bb) = (a.bounding_box(pose_a), b.bounding_box(pose_b));
        (
            Vec2::new(ba.min.x.min(bb.min.x), ba.min.y.min(bb.min.y)),
            Vec2::new(ba.max.x.max(bb.max.x), ba.max.y.max(bb.max.y)),
            1.1,
        )
    } else {
        world_cells.fold(
            (
                Vec2::new(f64::INFINITY, f64::INFINITY),
                Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
                2.2,
            ),
            |(lo, hi, m), p| {
                (
                    Vec2::new(lo.x.min(p.x), lo.y.min(p.y)),
                    Vec2::new(hi.x.max(p.x), hi.y.max(p.y)),
                    m,
                )
            },
        )
    };
    let span = (hi.x - lo.x).max(hi.y - lo.y) * margin;
    let mid = Vec2::new(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y));
    let scale = f64::from(size) / span;
    let px = |p: Vec2| {
        (
            (p.x - mid.x) * scale + 0.5 * f64::from(size),
            0.5 * f64::from(size) - (p.y - mid.y) * scale,
        )
    };
    let polygon = |pts: &[Vec2]| {
        pts.iter()
            .map(|&p| {
                let (x, y) = px(p);
                format!("{x:.2},{y:.2}")
            })
            .collect::<Vec<_>>()
            .join(" ")
    };

    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{size}" viewBox="0 0 {size} {size}"><clipPath id="view"><rect width="{size}" height="{size}"/></clipPath>"#
    );
    let _ = writeln!(
        svg,
        r##"<rect width="100%" height="100%" fill="#ffffff"/>"##
    );
    for (shape, pose, colour) in [(a, pose_a, "#2e7d32"), (b, pose_b, "#6a1b9a")] {
        let pts = shape.boundary_polygon(pose, 720);
        let _ = writeln!(
            svg,
            r#"<polygon points="{}" fill="{colour}" fill-opacity="0.18" stroke="{colour}" stroke-width="1.5"/>"#,
            polygon(&pts)
        );
    }
    // The cells are in A's local frame: place their corners in the world.
    for (cell, ca, cb, last) in cells {
        let corners = cell.corners().map(|p| pose_a.to_world(p));
        let style = if *ca == Class::Outside || *cb == Class::Outside {
            r##"fill="none" stroke="#9e9e9e" stroke-width="0.4""##
        } else if *ca == Class::Inside && *cb == Class::Inside {
            r##"fill="#ff9800" fill-opacity="0.7" stroke="#e65100" stroke-width="0.4""##
        } else if *last {
            r##"fill="#64b5f6" fill-opacity="0.6" stroke="#1565c0" stroke-width="0.4""##
        } else {
            r##"fill="none" stroke="#1565c0" stroke-width="0.5""##
        };
        let _ = writeln!(svg, r#"<polygon points="{}" {style}/>"#, polygon(&corners));
    }
    if let Some(p) = contact.penetration {
        for (from, push, colour) in [
            (p.a_deepest, p.a_push, "#1b5e20"),
            (p.b_deepest, p.b_push, "#4a148c"),
        ] {
            let (x1, y1) = px(from);
            let (x2, y2) = px(from + push);
            let _ = writeln!(
                svg,
                r#"<line x1="{x1:.2}" y1="{y1:.2}" x2="{x2:.2}" y2="{y2:.2}" stroke="{colour}" stroke-width="2"/><circle cx="{x1:.2}" cy="{y1:.2}" r="3.5" fill="{colour}"/><circle cx="{x2:.2}" cy="{y2:.2}" r="2" fill="none" stroke="{colour}"/>"#
            );
        }
    }
    let _ = writeln!(
        svg,
        r##"<text x="8" y="18" font-family="sans-serif" font-size="13" fill="#333">{caption}</text>"##
    );
    svg.push_str("</svg>\n");
    svg
}

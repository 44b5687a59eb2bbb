use std::fmt::Write;

use super::{exponent_colour, world_region};
use crate::world::World;

/// The world as an SVG picture `width` pixels wide: the box's walls and floor, and every grain
/// filled with a colour from its exponents (stars red, diamonds orange, ellipses green, blocks
/// blue). Vector outlines from the parametric boundary; [`super::render_world`] paints the
/// same with the paper's anti-aliased quadtree renderer.
pub fn world_svg(world: &World, width: u32) -> String {
    let w = world.walls;
    let region = world_region(world);
    let (x0, x1) = (w.left, w.right);
    let top = region.max.y;
    let (vx, vy) = (region.min.x, region.min.y);
    let (vw, vh) = (region.width(), region.height());
    let scale = f64::from(width) / vw;
    let height = (vh * scale).ceil() as u32;
    let px = |x: f64, y: f64| ((x - vx) * scale, (vy + vh - y) * scale);
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}">"#
    );
    let _ = writeln!(
        svg,
        r##"<rect width="100%" height="100%" fill="#fafafa"/>"##
    );
    for b in &world.bodies {
        let points: Vec<String> = b
            .shape
            .boundary_polygon(&b.pose(), 160)
            .into_iter()
            .map(|p| {
                let (x, y) = px(p.x, p.y);
                format!("{x:.1},{y:.1}")
            })
            .collect();
        let [r, g, bl, _] = exponent_colour(&b.shape);
        let colour = format!("#{r:02x}{g:02x}{bl:02x}");
        let _ = writeln!(
            svg,
            r##"<polygon points="{}" fill="{colour}" fill-opacity="0.85" stroke="#263238" stroke-width="0.8"/>"##,
            points.join(" ")
        );
    }
    let (lx, ly) = px(x0, top);
    let (fx, fy) = px(x0, w.floor);
    let (rx, ry) = px(x1, w.floor);
    let (tx, ty) = px(x1, top);
    let _ = writeln!(
        svg,
        r##"<polyline points="{lx:.1},{ly:.1} {fx:.1},{fy:.1} {rx:.1},{ry:.1} {tx:.1},{ty:.1}" fill="none" stroke="#37474f" stroke-width="3"/>"##
    );
    svg.push_str("</svg>\n");
    svg
}

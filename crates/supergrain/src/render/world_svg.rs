use std::fmt::Write;

use crate::world::World;

/// The world as an SVG picture `width` pixels wide: the box's walls and floor, and every grain
/// filled with a colour from its exponents (stars red, diamonds orange, ellipses green, blocks
/// blue). Vector outlines from the parametric boundary; the anti-aliased quadtree renderer of
/// paper II-B is the next step.
pub fn world_svg(world: &World, width: u32) -> String {
    let w = world.walls;
    // Up to the spawn height, or the highest grain if one reaches above it.
    let highest = world
        .bodies
        .iter()
        .map(|b| b.bounding_box().max.y)
        .fold(f64::NEG_INFINITY, f64::max);
    let top = world.top.max(highest).max(w.floor + 1.0);
    let (x0, x1) = (w.left, w.right);
    let margin = 0.04 * (x1 - x0);
    let (vx, vy) = (x0 - margin, w.floor - margin);
    let (vw, vh) = (x1 - x0 + 2.0 * margin, top - w.floor + 2.0 * margin);
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
        let pose = b.pose();
        let points: Vec<String> = (0..160)
            .map(|i| {
                let p = pose.to_world(
                    b.shape
                        .boundary_point(f64::from(i) * std::f64::consts::TAU / 160.0),
                );
                let (x, y) = px(p.x, p.y);
                format!("{x:.1},{y:.1}")
            })
            .collect();
        let e = b.shape.exponents()[0].min(b.shape.exponents()[1]);
        let colour = if e < 1.0 {
            "#e53935"
        } else if e < 2.0 {
            "#fb8c00"
        } else if e <= 2.0 {
            "#43a047"
        } else {
            "#1e88e5"
        };
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

//! The grains as a picture: anti-aliased polygons filled by tiny-skia on the CPU.

use eframe::egui::ColorImage;
use supergrain::geometry::Vec2;
use supergrain::render::exponent_colour;
use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Transform};

use crate::sim::Grain;

/// `grains` drawn `size` pixels large, `center` of the plane in the middle, `scale` pixels per
/// unit, `y` up; transparent where there is no grain. Sleeping grains are shaded darker and
/// the held one is amber.
pub fn grains(
    grains: &[Grain],
    held: Option<usize>,
    size: [usize; 2],
    center: Vec2,
    scale: f64,
) -> ColorImage {
    let (w, h) = (size[0].max(1) as u32, size[1].max(1) as u32);
    let Some(mut pixmap) = Pixmap::new(w, h) else {
        return ColorImage::new(size, vec![Default::default(); size[0] * size[1]]);
    };
    let (cx, cy) = (f64::from(w) / 2.0, f64::from(h) / 2.0);
    let to_px = |p: Vec2| {
        (
            (cx + (p.x - center.x) * scale) as f32,
            (cy - (p.y - center.y) * scale) as f32,
        )
    };
    let mut paint = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    for (i, g) in grains.iter().enumerate() {
        let radius_px = g.shape.bounding_radius() * scale;
        let (x, y) = to_px(g.pose.center());
        let r = radius_px as f32;
        if radius_px < 0.3 || x + r < 0.0 || y + r < 0.0 || x - r > w as f32 || y - r > h as f32 {
            continue;
        }
        let n = (radius_px * 1.5).clamp(12.0, 96.0) as u32;
        let mut pb = PathBuilder::new();
        for (k, p) in g.shape.boundary_polygon(&g.pose, n).into_iter().enumerate() {
            let (x, y) = to_px(p);
            if k == 0 {
                pb.move_to(x, y);
            } else {
                pb.line_to(x, y);
            }
        }
        pb.close();
        let Some(path) = pb.finish() else {
            continue;
        };
        let [r, g_, b, a] = if held == Some(i) {
            [0xff, 0xb3, 0x00, 0xff]
        } else {
            let [r, g_, b, a] = exponent_colour(&g.shape);
            if g.asleep {
                // Asleep: 80% of the colour.
                [r / 5 * 4, g_ / 5 * 4, b / 5 * 4, a]
            } else {
                [r, g_, b, a]
            }
        };
        paint.set_color(Color::from_rgba8(r, g_, b, a));
        pixmap.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
    }
    // tiny-skia's pixels are premultiplied RGBA, as egui's textures want them.
    ColorImage::from_rgba_premultiplied(size, pixmap.data())
}

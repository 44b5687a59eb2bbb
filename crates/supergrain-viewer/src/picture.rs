//! The grains as a picture: anti-aliased polygons filled by tiny-skia on the CPU.

use eframe::egui::{Color32, ColorImage};
use supergrain::geometry::Vec2;
use supergrain::render::exponent_colour;
use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Transform};

use crate::sim::Grain;

/// The canvas's background.
pub const BACKGROUND: Color32 = Color32::from_rgb(250, 250, 250);

/// `grains` drawn `size` pixels large, `center` of the plane in the middle, `scale` pixels per
/// unit, `y` up, on the canvas's background. Sleeping grains are shaded darker and the held
/// one is amber. `smooth`: anti-aliased edges (three times the time), else plain ones.
///
/// The background is in the picture, not a rectangle under it: where there is no GPU (Mesa's
/// software OpenGL) every layer over the canvas costs its pixels again, and a paused window
/// of the 1,000-grain pour kept 1.6 cores busy drawing 65 frames a second.
pub fn grains(
    grains: &[Grain],
    held: Option<usize>,
    size: [usize; 2],
    center: Vec2,
    scale: f64,
    smooth: bool,
) -> ColorImage {
    let (w, h) = (size[0].max(1) as u32, size[1].max(1) as u32);
    let Some(mut pixmap) = Pixmap::new(w, h) else {
        return ColorImage::new(size, vec![Default::default(); size[0] * size[1]]);
    };
    let [r, g, b, a] = BACKGROUND.to_array();
    pixmap.fill(Color::from_rgba8(r, g, b, a));
    let (cx, cy) = (f64::from(w) / 2.0, f64::from(h) / 2.0);
    let to_px = |p: Vec2| {
        (
            (cx + (p.x - center.x) * scale) as f32,
            (cy - (p.y - center.y) * scale) as f32,
        )
    };
    let mut paint = Paint {
        anti_alias: smooth,
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

#[cfg(test)]
mod tests {
    use super::*;
    use supergrain::shape::{Pose, Superellipse};

    /// A unit disk at the origin, 10 pixels per unit, in a 40 x 30 picture: its colour at the
    /// middle, the background in the corners, and its edge 10 pixels either side of the middle
    /// (pixels 10 to 29 have their centres inside: plain edges fill them; smooth ones blend
    /// the two partly covered end pixels).
    #[test]
    fn a_disk_is_drawn_where_it_is_on_the_background() {
        let disk = Grain {
            shape: Superellipse::new([1.0, 1.0], [2.0, 2.0]).unwrap(),
            pose: Pose::new(Vec2::ZERO, 0.0).unwrap(),
            group: 0,
            asleep: false,
        };
        let colour = exponent_colour(&disk.shape);
        for (smooth, ends) in [(true, (11, 28)), (false, (10, 29))] {
            let image = grains(&[disk], None, [40, 30], Vec2::ZERO, 10.0, smooth);
            let at = |x: usize, y: usize| image.pixels[y * 40 + x].to_array();
            assert_eq!(at(20, 15), colour, "smooth {smooth}");
            assert_eq!(at(0, 0), BACKGROUND.to_array());
            assert_eq!(at(39, 29), BACKGROUND.to_array());
            let inside: Vec<usize> = (0..40).filter(|&x| at(x, 15) == colour).collect();
            assert_eq!(inside.first(), Some(&ends.0), "smooth {smooth}: {inside:?}");
            assert_eq!(inside.last(), Some(&ends.1), "smooth {smooth}: {inside:?}");
        }
    }
}

//! Lines, boxes and dots in plane coordinates, stroked by tiny-skia: the overlays of frames and
//! diagrams.

use tiny_skia::{Color, FillRule, Paint, Path, PathBuilder, Pixmap, Rect, Stroke, Transform};

use super::raster::{Rgba, View};
use crate::geometry::{Aabb, Vec2};

/// Strokes and fills in plane coordinates.
pub(crate) struct Pen {
    view: View,
    paint: Paint<'static>,
}

impl Pen {
    pub(crate) fn new(view: &View) -> Pen {
        let paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        Pen { view: *view, paint }
    }

    pub(crate) fn colour(&mut self, c: Rgba) {
        self.paint
            .set_color(Color::from_rgba8(c[0], c[1], c[2], c[3]));
    }

    /// The path through `points` in pixel coordinates, closed or not.
    pub(crate) fn path(&self, points: &[Vec2], closed: bool) -> Option<Path> {
        let mut pb = PathBuilder::new();
        for (k, p) in points.iter().enumerate() {
            let (x, y) = self.view.to_pixel(*p);
            if k == 0 {
                pb.move_to(x, y);
            } else {
                pb.line_to(x, y);
            }
        }
        if closed {
            pb.close();
        }
        pb.finish()
    }

    pub(crate) fn stroke(&mut self, pixmap: &mut Pixmap, path: &Path, c: Rgba, width: f32) {
        self.colour(c);
        let stroke = Stroke {
            width,
            ..Stroke::default()
        };
        pixmap.stroke_path(path, &self.paint, &stroke, Transform::identity(), None);
    }

    pub(crate) fn fill(&mut self, pixmap: &mut Pixmap, path: &Path, c: Rgba) {
        self.colour(c);
        pixmap.fill_path(
            path,
            &self.paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
    }

    pub(crate) fn polyline(&mut self, pixmap: &mut Pixmap, points: &[Vec2], c: Rgba, width: f32) {
        if let Some(path) = self.path(points, false) {
            self.stroke(pixmap, &path, c, width);
        }
    }

    fn rect(&self, b: &Aabb) -> Option<Rect> {
        let (x0, y0) = self.view.to_pixel(Vec2::new(b.min.x, b.max.y));
        let (x1, y1) = self.view.to_pixel(Vec2::new(b.max.x, b.min.y));
        Rect::from_ltrb(x0, y0, x1.max(x0 + 0.5), y1.max(y0 + 0.5))
    }

    pub(crate) fn fill_box(&mut self, pixmap: &mut Pixmap, b: &Aabb, c: Rgba) {
        if let Some(r) = self.rect(b) {
            self.colour(c);
            pixmap.fill_rect(r, &self.paint, Transform::identity(), None);
        }
    }

    pub(crate) fn stroke_box(&mut self, pixmap: &mut Pixmap, b: &Aabb, c: Rgba, width: f32) {
        if let Some(r) = self.rect(b) {
            self.stroke(pixmap, &PathBuilder::from_rect(r), c, width);
        }
    }

    pub(crate) fn dot(&mut self, pixmap: &mut Pixmap, p: Vec2, c: Rgba, radius: f32) {
        let (x, y) = self.view.to_pixel(p);
        if let Some(path) = PathBuilder::from_circle(x, y, radius) {
            self.fill(pixmap, &path, c);
        }
    }

    /// A closed polygon, filled and/or outlined.
    pub(crate) fn polygon(
        &mut self,
        pixmap: &mut Pixmap,
        points: &[Vec2],
        fill: Option<Rgba>,
        outline: Option<(Rgba, f32)>,
    ) {
        let Some(path) = self.path(points, true) else {
            return;
        };
        if let Some(c) = fill {
            self.fill(pixmap, &path, c);
        }
        if let Some((c, width)) = outline {
            self.stroke(pixmap, &path, c, width);
        }
    }
}

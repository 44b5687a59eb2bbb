//! The paper's renderer (II-B, SPEC §6): the same interval classification that finds contacts
//! paints the grains. A quadtree over the pixels a grain's box covers: a block proven inside
//! takes the grain's colour whole, a block proven outside is skipped, and a boundary pixel is
//! split in four and its parts classified again (anti-aliasing), down to `aa_depth` levels;
//! a part still on the boundary at the last level counts by the sign at its centre.
//!
//! Written by hand because it is the heart of the paper's method: a polygon rasteriser would
//! need a boundary polyline, and for stars (exponent < 1) a fine one, while this needs only
//! the implicit function and costs a handful of enclosures per boundary pixel.

use crate::geometry::{Aabb, Vec2};
use crate::interval::{ImplicitShape, Side};

/// A rectangle of the plane mapped onto `width x height` pixels; pixel `(0, 0)` is the top-left
/// one, `y` grows upwards in the plane and downwards in the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    pub region: Aabb,
    pub width: u32,
    pub height: u32,
}

impl View {
    /// `region` drawn `width` pixels wide, the height following its aspect ratio.
    pub fn fit(region: Aabb, width: u32) -> View {
        let height = (region.height() / region.width() * f64::from(width))
            .round()
            .max(1.0) as u32;
        View {
            region,
            width: width.max(1),
            height,
        }
    }

    /// The size of a pixel in the plane.
    pub fn pixel(&self) -> Vec2 {
        Vec2::new(
            self.region.width() / f64::from(self.width),
            self.region.height() / f64::from(self.height),
        )
    }

    /// The plane's box of pixels `[x0, x1) x [y0, y1)`.
    pub fn cell(&self, x0: u32, y0: u32, x1: u32, y1: u32) -> Aabb {
        let p = self.pixel();
        let top = self.region.max.y;
        Aabb::new(
            Vec2::new(
                self.region.min.x + f64::from(x0) * p.x,
                top - f64::from(y1) * p.y,
            ),
            Vec2::new(
                self.region.min.x + f64::from(x1) * p.x,
                top - f64::from(y0) * p.y,
            ),
        )
    }

    /// Where a point of the plane falls in the image, in pixels (fractional).
    pub fn to_pixel(&self, q: Vec2) -> (f32, f32) {
        let p = self.pixel();
        (
            ((q.x - self.region.min.x) / p.x) as f32,
            ((self.region.max.y - q.y) / p.y) as f32,
        )
    }

    /// The pixels `[x0, x1) x [y0, y1)` a box of the plane touches, clipped to the image;
    /// `None` when it misses the image.
    pub fn pixels_of(&self, b: &Aabb) -> Option<(u32, u32, u32, u32)> {
        let b = b.intersection(&self.region)?;
        let p = self.pixel();
        let clamp_x = |v: f64| v.clamp(0.0, f64::from(self.width)) as u32;
        let clamp_y = |v: f64| v.clamp(0.0, f64::from(self.height)) as u32;
        let x0 = clamp_x(((b.min.x - self.region.min.x) / p.x).floor());
        let x1 = clamp_x(((b.max.x - self.region.min.x) / p.x).floor() + 1.0);
        let y0 = clamp_y(((self.region.max.y - b.max.y) / p.y).floor());
        let y1 = clamp_y(((self.region.max.y - b.min.y) / p.y).floor() + 1.0);
        (x0 < x1 && y0 < y1).then_some((x0, y0, x1, y1))
    }
}

/// The paper's anti-aliasing splits a boundary pixel once (four parts); two levels (sixteen)
/// is what [`Antialias::Gradient`] falls back to. At two levels a pixel's coverage is within
/// 1/8 of the exact one (edges parallel to the pixel's sides are the worst), 0.03 RMS.
pub const DEFAULT_AA_DEPTH: u32 = 2;

/// Deepest anti-aliasing accepted (4^8 parts per pixel).
pub const MAX_AA_DEPTH: u32 = 8;

/// How a boundary pixel's coverage is found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Antialias {
    /// The paper's: split in four and classify the parts, boundary parts again, this many
    /// levels; the last ones count by the sign at their centre.
    Split(u32),
    /// From the value and gradient at the pixel's centre: the boundary taken as a straight line
    /// at the first-order distance `f / |grad f|`, and the pixel's exact area on the inside of
    /// that line. One evaluation instead of up to `4 + 16` enclosures; for shapes many pixels
    /// across it is as close as `Split(3)`. Falls back to `Split(2)` where the gradient is not
    /// usable (zero, not finite, or the line missing the pixel the quadtree says is crossed).
    Gradient,
}

/// Calls `paint(x, y, coverage)` for every pixel of `view` the shape covers, with the fraction
/// of the pixel inside it (1 for pixels proven inside, `(0, 1]` on the boundary). Pixels
/// proven outside are not visited. Boundary pixels are split `aa_depth` times (the paper's
/// anti-aliasing, [`Antialias::Split`]).
pub fn cover<S: ImplicitShape>(
    shape: &S,
    view: &View,
    aa_depth: u32,
    paint: impl FnMut(u32, u32, f32),
) {
    cover_with(shape, view, Antialias::Split(aa_depth), paint);
}

/// [`cover`], with the anti-aliasing chosen.
pub fn cover_with<S: ImplicitShape>(
    shape: &S,
    view: &View,
    aa: Antialias,
    mut paint: impl FnMut(u32, u32, f32),
) {
    cover_spans(shape, view, aa, |x0, x1, y, c| {
        for x in x0..x1 {
            paint(x, y, c);
        }
    });
}

/// The walk behind [`cover_with`]: `paint(x0, x1, y, c)` for pixels `x0..x1` of row `y`, all
/// of coverage `c`: a row of a block proven inside (`c = 1`), or one boundary pixel. A painter
/// fills a proven row as one slice instead of pixel by pixel.
fn cover_spans<S: ImplicitShape>(
    shape: &S,
    view: &View,
    aa: Antialias,
    mut paint: impl FnMut(u32, u32, u32, f32),
) {
    let pixel = view.pixel();
    let Some(first) = view.pixels_of(&shape.bounding_box()) else {
        return;
    };
    // An explicit stack of pixel blocks; 4 per level of a tree at most 32 levels deep.
    let mut stack = Vec::with_capacity(128);
    stack.push(first);
    while let Some((x0, y0, x1, y1)) = stack.pop() {
        match shape.classify(&view.cell(x0, y0, x1, y1)) {
            Side::Outside => continue,
            Side::Inside => {
                for y in y0..y1 {
                    paint(x0, x1, y, 1.0);
                }
                continue;
            }
            Side::Boundary => {}
        }
        if x1 - x0 == 1 && y1 - y0 == 1 {
            let cell = view.cell(x0, y0, x1, y1);
            let c = match aa {
                Antialias::Split(depth) => coverage(shape, &cell, depth.min(MAX_AA_DEPTH)),
                Antialias::Gradient => gradient_coverage(shape, &cell, pixel)
                    .unwrap_or_else(|| coverage(shape, &cell, DEFAULT_AA_DEPTH)),
            };
            if c > 0.0 {
                paint(x0, x0 + 1, y0, c as f32);
            }
            continue;
        }
        if aa == Antialias::Gradient && x1 - x0 <= GRADIENT_BLOCK && y1 - y0 <= GRADIENT_BLOCK {
            // A small boundary block: one tangent line, from the value and gradient at the
            // block's centre, decides each of its pixels, inside and outside ones included.
            // That saves classifying each pixel first and evaluating `f` at each; over a
            // block two pixels wide the line strays from the boundary by about
            // `1 / (2 radius)` pixels (0.05 px for a grain 10 px across).
            let centre = view.cell(x0, y0, x1, y1).center();
            let (v, g) = shape.value_and_gradient(centre);
            for y in y0..y1 {
                for x in x0..x1 {
                    let cell = view.cell(x, y, x + 1, y + 1);
                    let vp = v + g.dot(cell.center() - centre);
                    let c = line_coverage(shape, &cell, vp, g, pixel)
                        .unwrap_or_else(|| coverage(shape, &cell, DEFAULT_AA_DEPTH));
                    if c > 0.0 {
                        paint(x, x + 1, y, c as f32);
                    }
                }
            }
            continue;
        }
        let (xm, ym) = (x0 + (x1 - x0).div_ceil(2), y0 + (y1 - y0).div_ceil(2));
        for (a0, a1) in [(x0, xm), (xm, x1)] {
            for (b0, b1) in [(y0, ym), (ym, y1)] {
                if a0 < a1 && b0 < b1 {
                    stack.push((a0, b0, a1, b1));
                }
            }
        }
    }
}

/// The fraction of `cell` inside the shape: four parts classified, boundary parts split again
/// down to `depth` levels, the last ones counted by the sign at their centre.
fn coverage<S: ImplicitShape>(shape: &S, cell: &Aabb, depth: u32) -> f64 {
    if depth == 0 {
        return if shape.value(cell.center()) <= 0.0 {
            1.0
        } else {
            0.0
        };
    }
    let m = cell.center();
    let mut sum = 0.0;
    for (x0, x1) in [(cell.min.x, m.x), (m.x, cell.max.x)] {
        for (y0, y1) in [(cell.min.y, m.y), (m.y, cell.max.y)] {
            let part = Aabb::new(Vec2::new(x0, y0), Vec2::new(x1, y1));
            sum += match shape.classify(&part) {
                Side::Inside => 1.0,
                Side::Outside => 0.0,
                Side::Boundary => coverage(shape, &part, depth - 1),
            };
        }
    }
    0.25 * sum
}

/// The pixel's area on the inside of the tangent line at the first-order boundary point, or
/// `None` when the gradient cannot be trusted.
fn gradient_coverage<S: ImplicitShape>(shape: &S, cell: &Aabb, pixel: Vec2) -> Option<f64> {
    let (v, g) = shape.value_and_gradient(cell.center());
    line_coverage(shape, cell, v, g, pixel)
}

/// The pixel's area on the inside of the line `v + g . (p - centre) = 0`, `v` and `g` the
/// (modelled) value and gradient at the pixel's centre, or `None` when they cannot be trusted.
fn line_coverage<S: ImplicitShape>(
    shape: &S,
    cell: &Aabb,
    v: f64,
    g: Vec2,
    pixel: Vec2,
) -> Option<f64> {
    // In pixel units: f(c + p x) ~ v + (g . p x), p the pixel size per axis.
    let (gx, gy) = (g.x * pixel.x, g.y * pixel.y);
    // Not `hypot`: a libm call per boundary pixel, and its overflow care is not needed here,
    // an infinite norm falls back below.
    let norm = (gx * gx + gy * gy).sqrt();
    if !(norm.is_finite() && norm > 0.0 && v.is_finite()) {
        return None;
    }
    // Inside: n . x < t, n the unit outward normal, x relative to the centre, |x_i| <= 1/2.
    let t = -v / norm;
    let (a, b) = {
        let (a, b) = ((gx / norm).abs(), (gy / norm).abs());
        if a >= b { (a, b) } else { (b, a) }
    };
    let w = a + b;
    if t.abs() > 0.5 * w + 1.0 {
        // The boundary is more than a pixel beyond the pixel at first order: only a curvature
        // radius under about a pixel could bring it back in.
        return Some(if t > 0.0 { 1.0 } else { 0.0 });
    }
    if t.abs() > 0.5 * w {
        // The line just misses the pixel: the pixel's own enclosure decides, and a boundary
        // pixel the line misses is too curved for a straight line.
        return match shape.classify(cell) {
            Side::Inside => Some(1.0),
            Side::Outside => Some(0.0),
            Side::Boundary => None,
        };
    }
    let u = (t + 0.5 * w).clamp(0.0, w);
    let area = if b < 1e-12 {
        u / a
    } else if u <= b {
        u * u / (2.0 * a * b)
    } else if u <= a {
        (u - 0.5 * b) / a
    } else {
        1.0 - (w - u) * (w - u) / (2.0 * a * b)
    };
    Some(area.clamp(0.0, 1.0))
}

/// An RGBA colour, not premultiplied.
pub type Rgba = [u8; 4];

/// Paints a shape onto a premultiplied RGBA8 pixel buffer (`tiny_skia::Pixmap`'s layout), its
/// coverage blended over what is there ("source over").
pub fn paint_shape<S: ImplicitShape>(
    pixels: &mut [u8],
    view: &View,
    shape: &S,
    colour: Rgba,
    aa_depth: u32,
) {
    paint_shape_with(pixels, view, shape, colour, Antialias::Split(aa_depth));
}

/// [`paint_shape`], with the anti-aliasing chosen.
pub fn paint_shape_with<S: ImplicitShape>(
    pixels: &mut [u8],
    view: &View,
    shape: &S,
    colour: Rgba,
    aa: Antialias,
) {
    let width = view.width as usize;
    let [r, g, b, a] = colour.map(|c| f32::from(c) / 255.0);
    // Source over, premultiplied, rounded to nearest (`+ 0.5` and truncation: the values are
    // never negative, and `f32::round` is a libm call on baseline x86-64).
    let blend = |px: &mut [u8], c: f32| {
        let alpha = a * c;
        let keep = 1.0 - alpha;
        for (d, s) in px.iter_mut().zip([r * alpha, g * alpha, b * alpha, alpha]) {
            *d = (s * 255.0 + f32::from(*d) * keep + 0.5).min(255.0) as u8;
        }
    };
    // An opaque colour over a proven-inside span is a plain copy.
    let opaque = colour[3] == 255;
    cover_spans(shape, view, aa, |x0, x1, y, c| {
        let row = y as usize * width;
        let span = &mut pixels[4 * (row + x0 as usize)..4 * (row + x1 as usize)];
        if opaque && c >= 1.0 {
            for px in span.chunks_exact_mut(4) {
                px.copy_from_slice(&colour);
            }
        } else {
            for px in span.chunks_exact_mut(4) {
                blend(px, c);
            }
        }
    });
}
/// Boundary blocks this many pixels wide or less are decided by one tangent line, pixel by pixel.
const GRADIENT_BLOCK: u32 = 2;

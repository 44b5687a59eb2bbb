//! The area fraction of disks in a window: each disk's area inside the window, exactly, summed,
//! over the window's area; and the overlaps of touching disks, which a soft contact keeps and
//! which count twice in that sum.

use super::Disk;
use crate::geometry::{Aabb, Vec2};
use crate::shape::{Pose, Superellipse};

/// The area of `disk` inside `window`, exactly: the vertical chord clipped to the window,
/// integrated in closed form piece by piece between the abscissae where the circle crosses the
/// window's top or bottom.
pub fn area_in(disk: &Disk, window: &Aabb) -> f64 {
    let r = disk.radius;
    let c = disk.center;
    // In the disk's frame.
    let (x0, x1) = ((window.min.x - c.x).max(-r), (window.max.x - c.x).min(r));
    let (y0, y1) = (window.min.y - c.y, window.max.y - c.y);
    if x0 >= x1 || y0 >= y1 {
        return 0.0;
    }
    let mut xs = vec![x0, x1];
    for y in [y0, y1] {
        if y.abs() < r {
            let x = (r * r - y * y).sqrt();
            xs.extend([-x, x].into_iter().filter(|&x| x > x0 && x < x1));
        }
    }
    xs.sort_by(f64::total_cmp);
    let half = |x: f64| (r * r - x * x).max(0.0).sqrt();
    // The integral of the upper arc, `sqrt(r^2 - x^2)`.
    let arc = |x: f64| 0.5 * (x * half(x) + r * r * (x / r).clamp(-1.0, 1.0).asin());
    let mut area = 0.0;
    for w in xs.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b <= a {
            continue;
        }
        // On each piece the chord's top is the window's top or the upper arc throughout, and
        // its bottom the window's bottom or the lower arc: the middle says which.
        let s = half(0.5 * (a + b));
        if y1.min(s) <= y0.max(-s) {
            continue;
        }
        let top = if y1 < s {
            y1 * (b - a)
        } else {
            arc(b) - arc(a)
        };
        let bottom = if y0 > -s {
            y0 * (b - a)
        } else {
            arc(a) - arc(b)
        };
        area += top - bottom;
    }
    area
}

/// The disks' areas inside `window`, summed, over the window's area. Where two disks overlap
/// (a soft contact keeps an overlap) the lens counts twice: see [`overlaps`].
pub fn area_fraction(disks: &[Disk], window: &Aabb) -> f64 {
    let inside: f64 = disks.iter().map(|d| area_in(d, window)).sum();
    inside / (window.width() * window.height())
}

/// How deep touching disks overlap: each pair whose centres are closer than the sum of their
/// radii, its overlap `r_i + r_j - |c_i - c_j|`. All pairs, so for a few thousand disks.
pub fn overlaps(disks: &[Disk]) -> Vec<f64> {
    let mut out = Vec::new();
    for (i, a) in disks.iter().enumerate() {
        for b in &disks[i + 1..] {
            let d = (a.center - b.center).norm();
            let overlap = a.radius + b.radius - d;
            if overlap > 0.0 {
                out.push(overlap);
            }
        }
    }
    out
}

/// The window inside a heap of disks in a box from `left` to `right` on a floor at `floor`: the
/// box less `margin` on each side and above the floor, and `margin` below the heap's surface
/// (the lowest of the highest disk tops in each tenth of the box's width, so that a sloping or
/// bumpy surface stays above it).
pub fn bulk_window(disks: &[Disk], left: f64, right: f64, floor: f64, margin: f64) -> Option<Aabb> {
    let tenth = (right - left) / 10.0;
    let mut tops = [f64::NEG_INFINITY; 10];
    for d in disks {
        let k = (((d.center.x - left) / tenth) as usize).min(9);
        tops[k] = tops[k].max(d.top());
    }
    let surface = tops.into_iter().fold(f64::INFINITY, f64::min);
    let window = Aabb::new(
        Vec2::new(left + margin, floor + margin),
        Vec2::new(right - margin, surface - margin),
    );
    (window.width() > 0.0 && window.height() > 0.0).then_some(window)
}

/// Sides of the polygon [`shape_area_in`] clips for a grain across a window's edge.
pub const CLIP_SIDES: u32 = 512;

/// The area of a placed superellipse inside `window`, for any grain: all of it (the closed
/// form) when its box is inside, none when its box misses the window, a disk's exactly
/// ([`area_in`]); otherwise its area times the fraction of its [`CLIP_SIDES`]-gon (the
/// boundary's points at even parameter steps) that the window holds (Sutherland-Hodgman
/// clipping), which takes the polygon's own shortfall out of the estimate.
pub fn shape_area_in(shape: &Superellipse, pose: &Pose, window: &Aabb) -> f64 {
    let bb = shape.bounding_box(pose);
    if bb.intersection(window).is_none() {
        return 0.0;
    }
    let inside = window.contains(bb.min) && window.contains(bb.max);
    if inside {
        return shape.area();
    }
    if shape.is_circle() {
        return area_in(
            &Disk::new(pose.center().x, pose.center().y, shape.semi_axes().x),
            window,
        );
    }
    let polygon = shape.boundary_polygon(pose, CLIP_SIDES);
    let whole = polygon_area(&polygon);
    if whole <= 0.0 {
        return 0.0;
    }
    shape.area() * polygon_area(&clip(polygon, window)) / whole
}

/// The shoelace area of a simple polygon (either orientation).
fn polygon_area(p: &[Vec2]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| p[i].cross(p[(i + 1) % n]))
        .sum::<f64>()
        .abs()
        * 0.5
}

/// The polygon clipped to the window, one side at a time. (A star's polygon is not convex, but
/// a rectangle's half-planes clip any simple polygon to one whose area is the part inside,
/// with only zero-width bridges along the window's edges.)
fn clip(mut poly: Vec<Vec2>, window: &Aabb) -> Vec<Vec2> {
    let sides: [(Vec2, f64); 4] = [
        (Vec2::new(1.0, 0.0), window.min.x),
        (Vec2::new(-1.0, 0.0), -window.max.x),
        (Vec2::new(0.0, 1.0), window.min.y),
        (Vec2::new(0.0, -1.0), -window.max.y),
    ];
    for (n, d) in sides {
        let inside = |p: Vec2| n.dot(p) >= d;
        let mut out = Vec::with_capacity(poly.len() + 4);
        for i in 0..poly.len() {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let (ia, ib) = (inside(a), inside(b));
            if ia {
                out.push(a);
            }
            if ia != ib {
                let t = (d - n.dot(a)) / n.dot(b - a);
                out.push(a + (b - a) * t);
            }
        }
        poly = out;
        if poly.is_empty() {
            break;
        }
    }
    poly
}

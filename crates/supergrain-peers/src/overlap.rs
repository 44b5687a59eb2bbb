//! Whether two peer shapes overlap: the spawner's "is this place free" for the peers, on their own
//! shapes, engine-neutral. Each shape is a convex core (a point, a segment, a box) swept by a
//! disk: two overlap when their cores come closer than the sum of the radii.

use crate::scene::{Grain, Shape};

type P = [f64; 2];

/// The core's vertices in the world (1, 2 or 4, counter-clockwise) and the sweeping radius.
fn core(g: &Grain) -> (Vec<P>, f64) {
    let (c, s) = (g.angle.cos(), g.angle.sin());
    let place = |x: f64, y: f64| [g.x + c * x - s * y, g.y + s * x + c * y];
    match g.shape {
        Shape::Circle { radius } => (vec![[g.x, g.y]], radius),
        Shape::Capsule {
            half_length: h,
            radius,
            along_y,
        } => {
            let ends = if along_y {
                [place(0.0, -h), place(0.0, h)]
            } else {
                [place(-h, 0.0), place(h, 0.0)]
            };
            (ends.to_vec(), radius)
        }
        Shape::RoundedBox {
            half_extents: [a, b],
            radius,
        } => {
            let (a, b) = (a - radius, b - radius);
            (
                vec![place(-a, -b), place(a, -b), place(a, b), place(-a, b)],
                radius,
            )
        }
    }
}

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1]]
}

fn cross(a: P, b: P) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Distance from `p` to the segment `ab`.
fn point_segment(p: P, a: P, b: P) -> f64 {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + t * ab[0], a[1] + t * ab[1]];
    let d = sub(p, q);
    dot(d, d).sqrt()
}

/// Whether the segments `ab` and `cd` cross.
fn segments_cross(a: P, b: P, c: P, d: P) -> bool {
    let side = |p: P, q: P, r: P| cross(sub(q, p), sub(r, p));
    let (d1, d2) = (side(c, d, a), side(c, d, b));
    let (d3, d4) = (side(a, b, c), side(a, b, d));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// Whether `p` lies in the convex counter-clockwise polygon `poly` (3 vertices or more).
fn inside(p: P, poly: &[P]) -> bool {
    poly.len() >= 3
        && (0..poly.len())
            .all(|i| cross(sub(poly[(i + 1) % poly.len()], poly[i]), sub(p, poly[i])) >= 0.0)
}

/// The edges of a core: none for a point (its vertex stands for itself), one for a segment.
fn edges(v: &[P]) -> Vec<(P, P)> {
    match v.len() {
        1 => vec![(v[0], v[0])],
        2 => vec![(v[0], v[1])],
        n => (0..n).map(|i| (v[i], v[(i + 1) % n])).collect(),
    }
}

/// The distance between two convex cores (0 when they meet).
fn core_distance(a: &[P], b: &[P]) -> f64 {
    let (ea, eb) = (edges(a), edges(b));
    let crossing = ea
        .iter()
        .any(|&(p, q)| eb.iter().any(|&(r, s)| segments_cross(p, q, r, s)));
    if crossing || a.iter().any(|&p| inside(p, b)) || b.iter().any(|&p| inside(p, a)) {
        return 0.0;
    }
    let from_a = a
        .iter()
        .flat_map(|&p| eb.iter().map(move |&(r, s)| point_segment(p, r, s)));
    let from_b = b
        .iter()
        .flat_map(|&p| ea.iter().map(move |&(r, s)| point_segment(p, r, s)));
    from_a.chain(from_b).fold(f64::INFINITY, f64::min)
}

/// Whether the two placed shapes overlap (touching is not overlapping).
pub fn overlap(a: &Grain, b: &Grain) -> bool {
    let reach = a.shape.bounding_radius() + b.shape.bounding_radius();
    if (a.x - b.x).hypot(a.y - b.y) >= reach {
        return false;
    }
    let ((ca, ra), (cb, rb)) = (core(a), core(b));
    core_distance(&ca, &cb) < ra + rb
}

//! Whether two peer shapes overlap: the spawner's "is this place free" for the peers, on their own
//! shapes, engine-neutral. Each shape is a convex core (a point, a segment, a box) swept by a
//! disk: two overlap when their cores come closer than the sum of the radii. And how deep the
//! disks of a settled heap overlap ([`resting`]), the same measure for every engine.

use supergrain::measure::{Disk, packing};

use crate::scene::{Grain, Shape, Walls};

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

/// How deep the contacts of a heap of disks overlap, measured on the grains' poses alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resting {
    /// Overlapping pairs and grains overlapping a wall or the floor.
    pub contacts: usize,
    /// The mean and the largest overlap of those contacts (0 when there are none).
    pub mean: f64,
    pub largest: f64,
    /// The grains' mean diameter, the scale the mean is read against.
    pub mean_diameter: f64,
}

impl Resting {
    /// The mean overlap in percent of the mean diameter.
    pub fn percent_of_diameter(&self) -> f64 {
        100.0 * self.mean / self.mean_diameter
    }
}

/// The overlaps of a heap of disks by exact disk geometry, whichever engine left it: each pair
/// with `r_a + r_b - |c_a - c_b| > 0` ([`packing::overlaps`], which shares no code with any
/// solver), and each disk with `r` beyond its distance to the floor or a wall. `None` when a
/// grain is not a circle (the other shapes have no exact measure here) or there is none.
pub fn resting(grains: &[Grain], walls: &Walls) -> Option<Resting> {
    let disks: Vec<Disk> = grains
        .iter()
        .map(|g| match g.shape {
            Shape::Circle { radius } => Some(Disk::new(g.x, g.y, radius)),
            _ => None,
        })
        .collect::<Option<_>>()?;
    if disks.is_empty() {
        return None;
    }
    let mut depths = packing::overlaps(&disks);
    for d in &disks {
        let (x, y) = (d.center.x, d.center.y);
        for gap in [y - walls.floor, x - walls.left, walls.right - x] {
            if d.radius > gap {
                depths.push(d.radius - gap);
            }
        }
    }
    let contacts = depths.len();
    Some(Resting {
        contacts,
        mean: depths.iter().sum::<f64>() / contacts.max(1) as f64,
        largest: depths.iter().copied().fold(0.0, f64::max),
        mean_diameter: 2.0 * disks.iter().map(|d| d.radius).sum::<f64>() / disks.len() as f64,
    })
}

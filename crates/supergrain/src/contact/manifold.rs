//! Contact manifolds (issue 18): the points at which a contact solver holds two overlapping
//! shapes apart, from the narrow phase's deepest points and pushes.
//!
//! A contact of two round shapes is one point: the middle of the overlap, between the two
//! deepest points, at the overlap's depth. Where flat faces meet (a block on a block, a block on
//! the floor) one point cannot hold the grain up: it rocks about it. Box2D clips polygon faces
//! and keeps two points; a superellipse has no faces to clip, but the overlap region has ends,
//! where the two boundaries cross. They are found by following one shape's boundary, in its
//! parameter, from its deepest point both ways until it leaves the other shape, and each is
//! added as a point at separation zero (on both boundaries). When the grain starts to tip, the
//! end that closes is held; while it rests, the middle point carries it.
//!
//! The ends are searched only when a shape is blocky (an exponent above 2): between round
//! shapes the overlap is a lens a few slops wide, and its middle is the contact. Pairs whose
//! overlap has several regions (stars) get the region of the deepest points here; issue 19
//! reports every region.

use super::{Penetration, WallPenetration};
use crate::geometry::Vec2;
use crate::shape::{HalfPlane, Pose, Superellipse};

/// At most this many points per manifold: the middle and the two ends.
pub const MAX_POINTS: usize = 3;

/// One point of a manifold, in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ManifoldPoint {
    pub point: Vec2,
    /// Negative: overlapping this deep along the normal.
    pub separation: f64,
    /// Which point this is (0 the middle, 1 and 2 the ends, in the order of A's boundary
    /// parameter), so that a persisting contact matches its points from step to step.
    pub id: u8,
}

/// The points of one contact region, with the normal from A towards B (for a wall: from the
/// wall into the grain).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Manifold {
    pub normal: Vec2,
    points: [ManifoldPoint; MAX_POINTS],
    len: usize,
}

impl Manifold {
    pub fn points(&self) -> &[ManifoldPoint] {
        &self.points[..self.len]
    }

    fn new(normal: Vec2, middle: Vec2, depth: f64) -> Self {
        let p = ManifoldPoint {
            point: middle,
            separation: -depth,
            id: 0,
        };
        Manifold {
            normal,
            points: [p; MAX_POINTS],
            len: 1,
        }
    }

    fn push(&mut self, point: Vec2, id: u8) {
        if self.len < MAX_POINTS {
            self.points[self.len] = ManifoldPoint {
                point,
                separation: 0.0,
                id,
            };
            self.len += 1;
        }
    }

    /// Adds the region's ends when they lie apart from the middle and from each other by more
    /// than `min_gap`: otherwise the middle alone holds the contact.
    fn add_ends(&mut self, ends: [Option<Vec2>; 2], min_gap: f64) {
        let middle = self.points[0].point;
        if let [Some(e1), Some(e2)] = ends
            && (e1 - e2).norm() > min_gap
        {
            for (e, id) in [(e1, 1), (e2, 2)] {
                if (e - middle).norm() > 0.5 * min_gap {
                    self.push(e, id);
                }
            }
        }
    }
}

/// Whether a shape has flat-ish faces, whose contacts need the region's ends.
fn blocky(s: &Superellipse) -> bool {
    s.exponents().iter().any(|&e| e > 2.0)
}

/// The manifold of two overlapping grains from their narrow-phase answer.
pub fn grain_manifold(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    p: &Penetration,
) -> Manifold {
    let (ca, cb) = (pose_a.center(), pose_b.center());
    let normal = (p.b_push - p.a_push)
        .direction()
        .or_else(|| (cb - ca).direction())
        .unwrap_or(Vec2::new(1.0, 0.0));
    // Each push alone separates the pair along the normal; their mean is the overlap's depth.
    let depth = (0.5 * (p.b_push.dot(normal) - p.a_push.dot(normal))).max(0.0);
    let middle = (p.a_deepest + p.b_deepest) * 0.5;
    let mut m = Manifold::new(normal, middle, depth);
    if blocky(a) || blocky(b) {
        let inside_b = |q: Vec2| b.value(pose_b, q) < 0.0;
        let ends = region_ends(a, pose_a, p.a_deepest, inside_b);
        m.add_ends(ends, min_gap(a, b));
    }
    m
}

/// The manifold of a grain overlapping a wall.
pub fn wall_manifold(
    shape: &Superellipse,
    pose: &Pose,
    wall: &HalfPlane,
    p: &WallPenetration,
) -> Manifold {
    let normal = wall.normal();
    let depth = (-wall.value(p.deepest)).max(0.0);
    let middle = p.deepest + p.push * 0.5;
    let mut m = Manifold::new(normal, middle, depth);
    if blocky(shape) {
        let inside = |q: Vec2| wall.value(q) < 0.0;
        let ends = region_ends(shape, pose, p.deepest, inside);
        m.add_ends(ends, min_gap(shape, shape));
    }
    m
}

/// Ends closer than this (a fifth of the smaller grain's shorter semi-axis) make no second
/// point: the region is a lens.
fn min_gap(a: &Superellipse, b: &Superellipse) -> f64 {
    0.2 * a.min_semi_axis().min(b.min_semi_axis())
}

/// The boundary parameter of a point of the shape (local coordinates), the inverse of
/// [`Superellipse::boundary_point`] along the ray through it.
fn parameter(s: &Superellipse, local: Vec2) -> f64 {
    let ax = s.semi_axes();
    let [ex, ey] = s.exponents();
    let c = (local.x / ax.x).abs().powf(0.5 * ex).copysign(local.x);
    let sn = (local.y / ax.y).abs().powf(0.5 * ey).copysign(local.y);
    sn.atan2(c)
}

/// Steps of the boundary walk per turn, and bisections of the last step.
const WALK_STEPS: u32 = 64;
const BISECTIONS: u32 = 14;

/// The two ends of the overlap region that holds `deepest`, on `shape`'s boundary: from the
/// deepest point's parameter both ways, the first boundary point outside the other (`inside`
/// false), refined by bisection. `None` for a way that stays inside for half a turn (one shape
/// deep in the other: there are no ends to hold).
fn region_ends(
    shape: &Superellipse,
    pose: &Pose,
    deepest: Vec2,
    inside: impl Fn(Vec2) -> bool,
) -> [Option<Vec2>; 2] {
    let t0 = parameter(shape, pose.to_local(deepest));
    let at = |t: f64| pose.to_world(shape.boundary_point(t));
    let step = std::f64::consts::TAU / f64::from(WALK_STEPS);
    let end = |way: f64| {
        let mut inner = t0;
        for k in 1..=WALK_STEPS / 2 {
            let t = t0 + way * step * f64::from(k);
            if !inside(at(t)) {
                let mut outer = t;
                for _ in 0..BISECTIONS {
                    let mid = 0.5 * (inner + outer);
                    if inside(at(mid)) {
                        inner = mid;
                    } else {
                        outer = mid;
                    }
                }
                return Some(at(0.5 * (inner + outer)));
            }
            inner = t;
        }
        None
    };
    [end(-1.0), end(1.0)]
}

//! Contact manifolds (issue 18): the points at which a contact solver holds two overlapping
//! shapes apart, from the narrow phase's deepest points and pushes.
//!
//! A contact of two round shapes is one point: the middle of the overlap, between the two
//! deepest points, at the overlap's depth. Where flat faces meet (a block on a block, a block on
//! the floor) one point cannot hold the grain up: it rocks about it, and the deepest point of a
//! face lying flat jumps from one end to the other as the grain tips (measured: a block on a
//! slope rocked at 0.4 radians per second and crept down it). Box2D clips polygon faces and
//! keeps two points; a superellipse has no faces to clip, but its contact has a patch: the
//! stretch of boundary within `margin` of the other shape. It is found by following A's
//! boundary, by the polar angle about its centre, from the deepest point both ways until the separation exceeds
//! the margin; when the patch is wider than a fifth of the smaller grain, the contact is two
//! points instead of the middle one, four fifths of the way from the middle to each end of the
//! patch, each with its own separation (exact against a wall, `f / |grad f|` against a grain).
//! As the grain tips, one point closes and the other opens, smoothly. When the middle is
//! deeper than both sides by more than the margin (a round grain pressed into a face), it stays as a
//! third point.
//!
//! The patch is searched only when a shape is blocky (an exponent above 2) and neither is an
//! ellipse: between round shapes the overlap is a lens a few slops wide, and its middle is the
//! contact; an ellipse (a disk too) touches a convex grain at one point, which moves smoothly as
//! it turns. Pairs whose overlap has several regions (stars) get the region of the deepest
//! points here; issue 19 reports every region.

use super::certified::{radial_to_boundary, ray32};
use super::{Penetration, WallPenetration};
use crate::geometry::{Aabb, Vec2};
use crate::shape::{Boundary, Pose, Superellipse, pow32};

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

    /// A manifold of given points (at most [`MAX_POINTS`]; more are dropped), for one carried
    /// from an earlier step (`solver::carry`). `None` for no point.
    pub fn from_points(normal: Vec2, points: &[ManifoldPoint]) -> Option<Manifold> {
        let first = *points.first()?;
        let mut m = Manifold {
            normal,
            points: [first; MAX_POINTS],
            len: points.len().min(MAX_POINTS),
        };
        m.points[..m.len].copy_from_slice(&points[..m.len]);
        Some(m)
    }

    pub(super) fn new(normal: Vec2, middle: Vec2, depth: f64) -> Self {
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

    /// A star's regions (points and separations, [`regions`]) with the middle: those farther
    /// than `apart` from each other, the deepest first, up to [`MAX_POINTS`], numbered in
    /// their order across the normal (so that a point keeps its number, and its warm start,
    /// as the regions deepen and ease in turn: numbered by depth, two spikes' points swapped
    /// their impulses whenever they swapped places, and the heap trembled). A star touching
    /// with two spikes, held by the deepest alone, rocks from spike to spike as the other
    /// closes.
    fn regions(&mut self, mut found: Vec<(Vec2, f64)>, apart: f64) {
        found.push((self.points[0].point, self.points[0].separation));
        found.sort_by(|x, y| x.1.total_cmp(&y.1));
        let mut kept: Vec<(Vec2, f64)> = Vec::with_capacity(MAX_POINTS);
        for (point, separation) in found {
            if kept.len() == MAX_POINTS {
                break;
            }
            if kept.iter().all(|p| (p.0 - point).norm() > apart) {
                kept.push((point, separation));
            }
        }
        let across = Vec2::new(self.normal.y, -self.normal.x);
        kept.sort_by(|x, y| x.0.dot(across).total_cmp(&y.0.dot(across)));
        // One point is the middle (0); two, the sides (1, 2); three, in order 1, 0, 2.
        let ids: &[u8] = match kept.len() {
            1 => &[0],
            2 => &[1, 2],
            _ => &[1, 0, 2],
        };
        for (k, ((point, separation), &id)) in kept.into_iter().zip(ids).enumerate() {
            self.points[k] = ManifoldPoint {
                point,
                separation,
                id,
            };
            self.len = k + 1;
        }
    }

    /// When the patch is wide, its two side points join the middle, and the middle counts as
    /// `tolerance` shallower than it is: it holds only a grain pressed into a face deeper than
    /// the sides by more than that (a round grain on a block's face: the sides alone would hold
    /// it at their depth, not the middle's; measured, a disk and a block stayed 0.12 deep),
    /// and never carries a grain lying flat (the deepest point of a flat face jumps from end to
    /// end as the grain tips). Keeping or dropping the middle by a threshold instead made a
    /// heap of blocks tremble at 0.2 units/s, as contacts crossed it.
    pub(super) fn sides(&mut self, patch: Option<[(Vec2, f64); 2]>, tolerance: f64) {
        if let Some(sides) = patch {
            self.points[0].separation += tolerance;
            for (k, (point, separation)) in sides.into_iter().enumerate() {
                self.points[1 + k] = ManifoldPoint {
                    point,
                    separation,
                    id: k as u8 + 1,
                };
            }
            self.len = 3;
        }
    }
}

/// The separation of `q` from a shape, to first order: `f / |grad f|`.
///
/// Except next to a star's axis, outside: its term `|t|^e`, `e < 1`, has a slope there that
/// grows without bound, so `f / |grad f|` is near 0 however far `q` lies beyond the spike. In
/// `pour-mixed.toml` (800 steps) 0.26% of the stars' regions were such points, 0.1 to 0.15
/// from the other grain (5 to 7 margins, half a grain), reported within the margin: contacts
/// where the grains did not touch. Where the first-order step to the boundary would cross such
/// an axis, the distance along the ray from the shape's centre replaces it (beyond a spike the
/// nearest boundary point is its tip, on that ray).
fn separation(s: &Superellipse, pose: &Pose, q: Vec2) -> f64 {
    let (f, g) = s.value_and_gradient(pose, q);
    let len = g.norm();
    if len.is_nan() || len <= 0.0 {
        return f64::INFINITY;
    }
    let [ex, ey] = s.exponents();
    if f > 0.0 && (ex < 1.0 || ey < 1.0) {
        let local = pose.to_local(q);
        let step = pose.rotation().apply_inverse(g) * (f / (len * len));
        let crosses = (ex < 1.0 && step.x.abs() >= local.x.abs())
            || (ey < 1.0 && step.y.abs() >= local.y.abs());
        if crosses && let Some(b) = radial_to_boundary(s, local) {
            return (local - b).norm();
        }
    }
    f / len
}

/// The separation of `q` from a convex shape, to first order, by its gauge: with
/// `F = |x/a|^ex + |y/b|^ey` and `e` the larger exponent, `G = F^(1/e)` grows along a face by
/// `1/a` a unit of distance whatever the exponent, so `(G - 1) / |grad G|` is the distance to a
/// face to second order, where `f / |grad f|` ([`separation`]) is off by the exponent times the
/// distance over the semi-axis: a point 0.01 inside a face of semi-axis 0.3 read 0.055 deep at
/// exponent 85, and 0.01 outside read 0.0034. Side points that read five times too deep rocked a
/// heap of blocks (exponents 50-200) from end to end every step, and it never rested
/// (docs/physics.md, "Overlap"). Powers by [`pow32`].
pub(super) fn separation32(s: &Superellipse, pose: &Pose, q: Vec2) -> f64 {
    let q = pose.to_local(q);
    let Some((first, along)) = gauge_step(s, q) else {
        return f64::INFINITY;
    };
    if s.exponents()[0] == s.exponents()[1] {
        return first;
    }
    // Unequal exponents: inside, where the other axis's term is not negligible, the gauge's
    // level curves are not parallel to the boundary (a point 0.01 inside the face of exponent 120
    // of a grain of exponents 8 and 120, three fifths of the way to the corner, read 0.035
    // deep). A second step from where the first one lands, along the gradient, corrects it.
    let landed = q - along * first;
    gauge_step(s, landed).map_or(first, |(second, _)| first + second)
}

/// [`separation32`]'s first-order step from `q` (in the grain's frame): the gauge's value over
/// its gradient's length, and the gradient's direction.
fn gauge_step(s: &Superellipse, q: Vec2) -> Option<(f64, Vec2)> {
    let [ex, ey] = s.exponents();
    let inv = s.inv_semi_axes();
    let term = |c: f64, inv_s: f64, e: f64| {
        let t = c * inv_s;
        let m = pow32(t, e);
        let g = if t == 0.0 { 0.0 } else { e * m / t * inv_s };
        (m, g)
    };
    let (mx, gx) = term(q.x, inv.x, ex);
    let (my, gy) = term(q.y, inv.y, ey);
    let f = mx + my;
    let grad = Vec2::new(gx, gy);
    let len = grad.norm();
    if !(f > 0.0 && len > 0.0 && f.is_finite() && len.is_finite()) {
        return None;
    }
    // grad G = G / (e F) grad F.
    let e = ex.max(ey);
    let gauge = pow32(f, 1.0 / e);
    Some(((gauge - 1.0) * e * f / (gauge * len), grad * (1.0 / len)))
}

/// Samples of a star's boundary searched for the other shape's regions.
const STAR_SAMPLES: u32 = 96;

/// The regions where `shape`'s boundary comes within `margin` of the other shape (by `gap`,
/// its separation from it): the deepest sample of each run of samples within the margin, with
/// its separation. A star's boundary sampled at evenly spaced classic parameters
/// ([`Superellipse::boundary_point`]): they crowd at the spikes' tips, which is where a star
/// touches.
///
/// `near`: where the other shape's samples can be within the margin (its box grown by the
/// margin), if known: a quadrant of the star whose box lies wholly outside it has no sample in
/// a region, and its samples are not computed (their gap would be infinite anyway).
fn regions(
    shape: &Superellipse,
    pose: &Pose,
    gap: impl Fn(Vec2) -> f64,
    margin: f64,
    near: Option<Aabb>,
) -> Vec<(Vec2, f64)> {
    // The parameter turned by a rotation per sample rather than a `sin_cos`, and the samples'
    // powers in single precision ([`pow32`]): a star's contact takes 192 samples a step, and
    // these two of each one's four double powers were a tenth of `pour-mixed.toml`'s run. The
    // samples depend on the shape alone, so their rounding is the same at every step; the
    // separations stay in double precision, which a star's steep ones near a spike need (in
    // single precision a region's deepest sample jittered and a star heap did not rest:
    // docs/performance.md, "Tried and not kept").
    let step = std::f64::consts::TAU / f64::from(STAR_SAMPLES);
    let (step_sin, step_cos) = step.sin_cos();
    let [ex, ey] = shape.exponents();
    let (kx, ky) = (2.0 / ex, 2.0 / ey);
    let axes = shape.semi_axes();
    // Whether each quadrant's box (by the signs of the sample's cosine and sine, which are
    // its point's) meets `near`, its corners in world coordinates padded over their rounding.
    let meets = |fx: f64, fy: f64| {
        let Some(near) = near else {
            return true;
        };
        let pad = 1e-9 * (axes.x + axes.y + pose.center().x.abs() + pose.center().y.abs());
        [(fx, 0.0), (0.0, fy), (fx, fy)]
            .map(|(u, v)| Aabb::point(pose.to_world(Vec2::new(u * axes.x, v * axes.y))))
            .iter()
            .fold(Aabb::point(pose.to_world(Vec2::ZERO)), |b, c| b.union(c))
            .grown(pad)
            .intersects(&near)
    };
    let quadrants = [
        [meets(1.0, 1.0), meets(1.0, -1.0)],
        [meets(-1.0, 1.0), meets(-1.0, -1.0)],
    ];
    let (mut sin, mut cos) = (0.0f64, 1.0f64);
    let mut samples = Vec::with_capacity(STAR_SAMPLES as usize);
    for _ in 0..STAR_SAMPLES {
        if quadrants[usize::from(cos.signum() < 0.0)][usize::from(sin.signum() < 0.0)] {
            let local = Vec2::new(
                axes.x * cos.signum() * pow32(cos, kx),
                axes.y * sin.signum() * pow32(sin, ky),
            );
            let q = pose.to_world(local);
            samples.push((q, gap(q)));
        } else {
            samples.push((Vec2::ZERO, f64::INFINITY));
        }
        (cos, sin) = (
            cos * step_cos - sin * step_sin,
            sin * step_cos + cos * step_sin,
        );
    }
    let n = samples.len();
    let Some(start) = (0..n).find(|&k| samples[k].1 >= margin) else {
        // Every sample within the margin: one region, its deepest sample.
        return samples
            .iter()
            .copied()
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .into_iter()
            .collect();
    };
    // Runs, starting after a sample beyond the margin so that none wraps around.
    let mut found = Vec::new();
    let mut run: Option<(Vec2, f64)> = None;
    for k in 1..=n {
        let (q, g) = samples[(start + k) % n];
        if g < margin {
            run = Some(match run {
                Some(r) if r.1 <= g => r,
                _ => (q, g),
            });
        } else if let Some(r) = run.take() {
            found.push(r);
        }
    }
    found
}

/// Whether a shape is an ellipse (a disk included): strictly convex, its curvature bounded.
fn ellipse(s: &Superellipse) -> bool {
    s.exponents() == [2.0, 2.0]
}

/// Whether the manifold of two grains is always their overlap's middle alone: no star (whose
/// regions make points of their own), and no patch walked (neither blocky, or an ellipse among
/// them).
fn one_point(a: &Superellipse, b: &Superellipse) -> bool {
    !a.is_star() && !b.is_star() && (!(blocky(a) || blocky(b)) || ellipse(a) || ellipse(b))
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
    margin: f64,
) -> Manifold {
    let (ca, cb) = (pose_a.center(), pose_b.center());
    // A disk's gradient is the distance's. The other grain's, read deep inside a long blocky
    // grain, points to the end its scaled coordinates favour, not to the nearest face: a disk
    // pressed 0.06 into a plank of exponent 50, 2 long and 0.2 thick, was pushed along it (a
    // normal of (0.99, 0.15), its push 0.4 long against the disk's 0.06) and fell through
    // (`tests/static_bodies.rs`). Where the other grain's push is more than twice the disk's,
    // the disk's alone gives the normal; resting contacts, whose pushes are alike, keep both.
    let misled = |disk: Vec2, other: Vec2| other.norm() > 2.0 * disk.norm();
    let pushes = match (a.is_circle(), b.is_circle()) {
        (true, false) if misled(p.b_push, p.a_push) => p.b_push,
        (false, true) if misled(p.a_push, p.b_push) => -p.a_push,
        _ => p.b_push - p.a_push,
    };
    let normal = pushes
        .direction()
        .or_else(|| (p.b_push - p.a_push).direction())
        .or_else(|| (cb - ca).direction())
        .unwrap_or(Vec2::new(1.0, 0.0));
    // Each push alone separates the pair along the normal; their mean is the overlap's depth.
    let depth = (0.5 * (p.b_push.dot(normal) - p.a_push.dot(normal))).max(0.0);
    let middle = (p.a_deepest + p.b_deepest) * 0.5;
    let mut m = Manifold::new(normal, middle, depth);
    if a.is_star() || b.is_star() {
        // A sample farther than the margin from the other grain's box is farther than that
        // from the grain, and in no region: its separation, two powers and more, is not
        // computed (most of a star's samples; the regions were a third of `pour-mixed.toml`'s
        // time). It also keeps such samples out of the regions where `f / |grad f|`, which
        // reads short of the distance away from a grain, would have let them in.
        // (And a quadrant of the star whose box is beyond it has no sample computed.)
        let (near_a, near_b) = (
            a.bounding_box(pose_a).grown(margin),
            b.bounding_box(pose_b).grown(margin),
        );
        let gap = |s: Superellipse, pose: Pose, near: Aabb| {
            move |q: Vec2| {
                if near.contains(q) {
                    separation(&s, &pose, q)
                } else {
                    f64::INFINITY
                }
            }
        };
        let mut found = regions(a, pose_a, gap(*b, *pose_b, near_b), margin, Some(near_b));
        found.extend(regions(
            b,
            pose_b,
            gap(*a, *pose_a, near_a),
            margin,
            Some(near_a),
        ));
        m.regions(found, min_gap(a, b));
        return m;
    }
    // An ellipse (a disk too) touches a convex grain at one point, which moves smoothly as it
    // turns (its curvature is bounded): the patch is not walked. Box2D's circles have one point
    // too. (The walks were half of a round grain's contact with a block in the settled mixed
    // heap; their sides held a grain of rice lying on a face as if it were flat.)
    if !one_point(a, b) {
        let gap = |q: Vec2| separation32(b, pose_b, q);
        let sides = if flat(a) && flat(b) {
            let reach = min_gap(a, b);
            face_patch(
                a,
                pose_a,
                p.a_deepest,
                normal,
                Some((b, pose_b)),
                gap,
                margin,
                reach,
            )
        } else {
            patch(a, pose_a, p.a_deepest, normal, gap, margin, min_gap(a, b))
        };
        m.sides(sides, margin);
    }
    m
}

/// The manifold of a grain overlapping a wall.
pub fn wall_manifold(
    shape: &Superellipse,
    pose: &Pose,
    wall: &Boundary,
    p: &WallPenetration,
    margin: f64,
) -> Manifold {
    // A half-plane's own normal; a curved or ended boundary's along the push, which is the
    // distance's gradient at the deepest point.
    let normal = match wall.as_plane() {
        Some(w) => w.normal(),
        None => p.push.direction().unwrap_or_else(|| wall.normal(p.deepest)),
    };
    let depth = (-wall.distance(p.deepest)).max(0.0);
    let middle = p.deepest + p.push * 0.5;
    let mut m = Manifold::new(normal, middle, depth);
    if shape.is_star() {
        let found = regions(shape, pose, |q: Vec2| wall.distance(q), margin, None);
        m.regions(found, min_gap(shape, shape));
        return m;
    }
    if blocky(shape) {
        let gap = |q: Vec2| wall.distance(q);
        let (deepest, reach) = (p.deepest, min_gap(shape, shape));
        let sides = if flat(shape) {
            face_patch(shape, pose, deepest, -normal, None, gap, margin, reach)
        } else {
            patch(shape, pose, deepest, normal, gap, margin, reach)
        };
        m.sides(sides, margin);
    }
    m
}

/// Exponents from which a grain's faces are flat enough for its patch to be found on the face
/// ([`face_patch`]) rather than walked ([`patch`]): at 8 a face's middle 60% lies within 0.1%
/// of its semi-axis of the straight line, and its ends are searched on the shape itself.
const FLAT: f64 = 8.0;

/// Whether both of a grain's exponents are at least [`FLAT`].
pub(super) fn flat(s: &Superellipse) -> bool {
    s.exponents().iter().all(|&e| e >= FLAT)
}

/// The middle of a flat grain's face whose outward normal is nearest `n` (world), in the
/// grain's frame: the semi-axis along that normal.
fn out_point(s: &Superellipse, pose: &Pose, n: Vec2) -> Vec2 {
    let l = pose.rotation().apply_inverse(n);
    let half = s.semi_axes();
    if l.x.abs() >= l.y.abs() {
        Vec2::new(l.x.signum() * half.x, 0.0)
    } else {
        Vec2::new(0.0, l.y.signum() * half.y)
    }
}

/// [`patch`] for a flat grain (both exponents at least [`FLAT`]), on its face whose outward
/// normal is nearest `out`: the patch is the stretch of that face within the other shape's
/// shadow on it (`clip`: its box's; `None` for a wall) and within `margin` of it by `gap`, each
/// end searched from the deepest point only where the face there is farther than the margin
/// ([`crossing`], on the face's coordinate). (Box2D clips one face of the other box against
/// it; the other grain's face alone cut a corner's patch at the corner, where the walk went on
/// along the corner's other face, and the heap of the tumbler sank twice as deep.) The side
/// points sit [`SIDE`] of the way from the patch's middle to its ends, on the shape, ordered
/// as [`patch`] orders them (by the polar angle). A face lying on a face costs five
/// separations where the walk took some thirty (a quarter turn of a 64-step walk and the
/// searches at its ends): the walks were a quarter of Box2D's tumbler's step.
#[allow(clippy::too_many_arguments)]
fn face_patch(
    shape: &Superellipse,
    pose: &Pose,
    deepest: Vec2,
    out: Vec2,
    clip: Option<(&Superellipse, &Pose)>,
    gap: impl Fn(Vec2) -> f64,
    margin: f64,
    min_gap: f64,
) -> Option<[(Vec2, f64); 2]> {
    let face = Face::new(shape, pose, out, clip, margin)?;
    face.patch(
        face.coord(deepest).clamp(face.lo, face.hi),
        gap,
        margin,
        min_gap,
    )
}

/// A flat grain's face whose outward normal is nearest a direction, as [`face_patch`] reads it:
/// a coordinate along it and the shape's point over each coordinate, and the stretch `lo..hi`
/// of it within the other grain's shadow.
pub(super) struct Face<'a> {
    pose: &'a Pose,
    /// The face's middle in the grain's frame (the semi-axis along its normal).
    middle: Vec2,
    /// Whether the face is y = +-b (its coordinate x), or x = +-a (its coordinate y).
    across: bool,
    /// The semi-axis along the face, its exponent, the other exponent.
    own: f64,
    e_own: f64,
    e_off: f64,
    /// Where the face ends, at its corners.
    pub(super) half: f64,
    pub(super) lo: f64,
    pub(super) hi: f64,
}

impl<'a> Face<'a> {
    /// The face of `shape` whose outward normal is nearest `out` (world), within the shadow
    /// of `clip` (its box's, grown by `margin`; `None` for a wall: the whole face). `None` when
    /// that stretch is empty.
    pub(super) fn new(
        shape: &Superellipse,
        pose: &'a Pose,
        out: Vec2,
        clip: Option<(&Superellipse, &Pose)>,
        margin: f64,
    ) -> Option<Self> {
        let middle = out_point(shape, pose, out);
        let across = middle.x == 0.0;
        // The face runs to its corners, where both terms of `f` are 1/2 (the diagonal of a
        // square superellipse): the face's coordinate `t` is the boundary's graph over it, `y =
        // b (1 - |t / a|^ex)^(1 / ey)` for the face y = +b, up to `t = a 2^(-1/ex)`. (Past the
        // corner the graph turns down the next face, steeply: a patch's end searched there by
        // two halvings and a secant landed a fifth of the face off.)
        let [ex, ey] = shape.exponents();
        let semi = shape.semi_axes();
        let (own, e_own, e_off) = if across {
            (semi.x, ex, ey)
        } else {
            (semi.y, ey, ex)
        };
        let half = own * pow32(0.5, 1.0 / e_own);
        let mut face = Face {
            pose,
            middle,
            across,
            own,
            e_own,
            e_off,
            half,
            lo: -half,
            hi: half,
        };
        if let Some((other, other_pose)) = clip {
            // The face's direction in the other grain's frame, and its box's half-extent along
            // it (and the margin: a point of the face beyond the shadow is still within the
            // margin of the other grain's corner).
            let way = if across {
                Vec2::new(1.0, 0.0)
            } else {
                Vec2::new(0.0, 1.0)
            };
            let way = other_pose
                .rotation()
                .apply_inverse(pose.rotation().apply(way));
            let box_half = other.semi_axes();
            let extent = (way.x * box_half.x).abs() + (way.y * box_half.y).abs() + margin;
            let centre = face.coord(other_pose.center());
            face.lo = (centre - extent).max(-half);
            face.hi = (centre + extent).min(half);
        }
        (face.hi > face.lo).then_some(face)
    }

    /// The face's coordinate of a world point.
    pub(super) fn coord(&self, q: Vec2) -> f64 {
        let l = self.pose.to_local(q);
        if self.across { l.x } else { l.y }
    }

    /// The shape's boundary point over the coordinate `t` (world).
    pub(super) fn on(&self, t: f64) -> Option<Vec2> {
        let t = t.clamp(-self.half, self.half);
        let rest = 1.0 - pow32(t / self.own, self.e_own);
        let height = if rest > 0.0 {
            pow32(rest, 1.0 / self.e_off)
        } else {
            0.0
        };
        let local = if self.across {
            Vec2::new(t, self.middle.y * height)
        } else {
            Vec2::new(self.middle.x * height, t)
        };
        local.is_finite().then(|| self.pose.to_world(local))
    }

    /// The two side points of the patch about the coordinate `from` (in it), with their
    /// separations by `gap` ([`face_patch`]).
    pub(super) fn patch(
        &self,
        from: f64,
        gap: impl Fn(Vec2) -> f64,
        margin: f64,
        min_gap: f64,
    ) -> Option<[(Vec2, f64); 2]> {
        let (lo, hi) = (self.lo, self.hi);
        if hi - lo <= min_gap || (hi - lo).is_nan() {
            return None;
        }
        let from_gap = gap(self.on(from)?);
        if from_gap >= margin || from_gap.is_nan() {
            return None;
        }
        let end = |t: f64| -> Option<f64> {
            let g = gap(self.on(t)?);
            if g < margin {
                return Some(t);
            }
            let value = |t: f64| self.on(t).map_or(f64::INFINITY, &gap);
            Some(crossing(
                (from, from_gap),
                (t, g),
                margin,
                FACE_HALVINGS,
                value,
            ))
        };
        let (e1, e2) = (end(lo)?, end(hi)?);
        if (self.on(e1)? - self.on(e2)?).norm() <= min_gap {
            return None;
        }
        let (middle, reach) = (0.5 * (e1 + e2), 0.5 * SIDE * (e2 - e1));
        let side = |t: f64| self.on(t).map(|q| (q, gap(q)));
        let (first, second) = (side(middle - reach)?, side(middle + reach)?);
        // The coordinate runs with the polar angle on the faces x = +a and y = -b, against it
        // on the other two.
        let with_angle = if self.across {
            self.middle.y < 0.0
        } else {
            self.middle.x > 0.0
        };
        Some(if with_angle {
            [first, second]
        } else {
            [second, first]
        })
    }
}

/// Ends closer than this (a fifth of the smaller grain's shorter semi-axis) make no second
/// point: the region is a lens.
pub(super) fn min_gap(a: &Superellipse, b: &Superellipse) -> f64 {
    0.2 * a.min_semi_axis().min(b.min_semi_axis())
}

/// Steps of the boundary walk per turn, and bisections of each search within a step.
const WALK_STEPS: u32 = 64;
const BISECTIONS: u32 = 2;

/// Halvings of a face's patch end search ([`face_patch`]) before its secant: the bracket from
/// the deepest point to the face's end is up to a face long, where the walk's is a 64th of a
/// turn, and the separation bends where the other grain's corner passes. Against dense
/// sampling of a face 0.6 long (`a_flat_grains_patch_is_where_dense_sampling_of_its_face_puts_it`),
/// two halvings put a side point 0.009 off, three 0.005, four within the test's 0.003.
const FACE_HALVINGS: u32 = 4;

/// Where the side points sit, from the middle of the patch to its ends.
const SIDE: f64 = 0.8;

/// A point of the boundary walk: its polar angle (local) and where it is (world).
#[derive(Clone, Copy)]
struct Sample {
    t: f64,
    point: Vec2,
}

/// The angle in `[lo, hi]` where `value` passes `want` (below it at `lo`, at or above at
/// `hi`, with the values `v_lo`, `v_hi` there): [`BISECTIONS`] halvings, then the secant in the
/// last bracket. The walk brackets every crossing within a 64th of a turn, where the boundary
/// and the separations are smooth, so the secant's error is second order in a bracket of
/// 1/256 turn, and the answer moves continuously with the shapes (two halvings pass the
/// block tests of `tests/mechanics.rs`, as four and six do, and took 15% off a settled mixed
/// heap's step against four). Before, fourteen halvings per search over the whole patch took
/// two thirds of a mixed heap's step (profiled).
fn crossing(
    (mut lo, mut v_lo): (f64, f64),
    (mut hi, mut v_hi): (f64, f64),
    want: f64,
    halvings: u32,
    value: impl Fn(f64) -> f64,
) -> f64 {
    for _ in 0..halvings {
        let mid = 0.5 * (lo + hi);
        let v = value(mid);
        if v < want {
            (lo, v_lo) = (mid, v);
        } else {
            (hi, v_hi) = (mid, v);
        }
    }
    let span = v_hi - v_lo;
    let f = if span > 0.0 {
        ((want - v_lo) / span).clamp(0.0, 1.0)
    } else {
        0.5
    };
    lo + f * (hi - lo)
}

/// The two side points of the contact patch of `shape` about `deepest` (module docs), with
/// their separations by `gap`, or `None` when the patch is narrower than `min_gap` or has no
/// end within half a turn either way (one shape deep in the other).
fn patch(
    shape: &Superellipse,
    pose: &Pose,
    deepest: Vec2,
    normal: Vec2,
    gap: impl Fn(Vec2) -> f64,
    margin: f64,
    min_gap: f64,
) -> Option<[(Vec2, f64); 2]> {
    // The boundary by the polar angle about the centre: along a flat face the classic
    // parameter `t` of [`Superellipse::boundary_point`] is useless (`x ~ |cos t|^(2/e)`: at
    // e = 8 a 64th of a turn from the face's middle is already 0.56 of the half-width, and a
    // bracket of 1e-4 radians still 0.1 of it), while the polar angle moves along a face as
    // its tangent. Searched in `t`, side points were off by a tenth of a block and jumped as
    // the bisections landed.
    let t0 = {
        let d = pose.to_local(deepest);
        d.y.atan2(d.x)
    };
    let on_ray = |c: f64, s: f64| {
        let local = ray32(shape, Vec2::new(c, s)).unwrap_or(Vec2::ZERO);
        pose.to_world(local)
    };
    let at = |t: f64| {
        let (s, c) = t.sin_cos();
        on_ray(c, s)
    };
    let step = std::f64::consts::TAU / f64::from(WALK_STEPS);
    let (step_sin, step_cos) = step.sin_cos();
    let (sin0, cos0) = t0.sin_cos();
    let first = Sample {
        t: t0,
        point: on_ray(cos0, sin0),
    };
    let first_gap = gap(first.point);
    // Walking `way` from `t0` (the direction turned by a rotation per step, not a `sin_cos`):
    // the samples in the patch, the deepest point first, then the first sample beyond it and
    // the separations at the last two.
    let walk = |way: f64| {
        let (mut s, mut c) = (sin0, cos0);
        let turn = way * step_sin;
        // Room for the whole walk and the end: grown one push at a time, it made 2,300
        // reallocations a step of the settled mixed heap.
        let mut samples = Vec::with_capacity(WALK_STEPS as usize / 2 + 2);
        samples.push(first);
        let mut inside_gap = first_gap;
        for k in 1..=WALK_STEPS / 2 {
            (c, s) = (c * step_cos - s * turn, s * step_cos + c * turn);
            let t = t0 + way * step * f64::from(k);
            let point = on_ray(c, s);
            let g = gap(point);
            if g >= margin {
                return Some((samples, Sample { t, point }, inside_gap, g));
            }
            inside_gap = g;
            samples.push(Sample { t, point });
        }
        None
    };
    let (mut left, left_out, left_in_gap, left_out_gap) = walk(-1.0)?;
    let (mut right, right_out, right_in_gap, right_out_gap) = walk(1.0)?;
    let (left_in, right_in) = (*left.last()?, *right.last()?);
    // Most patches are a round grain's lens on a face, a step or two wide: when the samples
    // either side of both ends are within `min_gap`, so are the ends, and their searches are
    // not needed.
    if (left_in.point - right_in.point).norm() <= min_gap
        && (left_out.point - right_out.point).norm() <= min_gap
    {
        return None;
    }
    let end = |inside: Sample, inside_gap: f64, outside: Sample, outside_gap: f64| {
        let t = crossing(
            (inside.t, inside_gap),
            (outside.t, outside_gap),
            margin,
            BISECTIONS,
            |t| gap(at(t)),
        );
        Sample { t, point: at(t) }
    };
    left.push(end(left_in, left_in_gap, left_out, left_out_gap));
    right.push(end(right_in, right_in_gap, right_out, right_out_gap));
    let (e1, e2) = (left.last()?.point, right.last()?.point);
    if (e1 - e2).norm() <= min_gap {
        return None;
    }
    // Along the patch, across the normal: the side point of each end is the boundary point
    // whose offset from the middle is `SIDE` of the end's, between the two samples of the walk
    // that bracket it (the offset grows from the deepest point to the end).
    let across = Vec2::new(normal.y, -normal.x);
    let middle = (e1 + e2) * 0.5;
    let side = |samples: &[Sample]| {
        let end = samples.last().expect("an end");
        let sign = (end.point - middle).dot(across).signum();
        let offset = |q: Vec2| sign * (q - middle).dot(across);
        let want = SIDE * offset(end.point);
        let k = samples
            .iter()
            .position(|s| offset(s.point) >= want)
            .unwrap_or(samples.len() - 1)
            .max(1);
        let (lo, hi) = (samples[k - 1].point, samples[k].point);
        // Between two samples a 64th of a turn apart the boundary is all but straight: the
        // point at the wanted offset on the chord, put back on the boundary along its ray from
        // the centre (one ray, where a search along the boundary took five; the chord's
        // distance from the boundary, second order in the step, moves the point along it
        // by less than that).
        let (o_lo, o_hi) = (offset(lo), offset(hi));
        let f = if o_hi > o_lo {
            ((want - o_lo) / (o_hi - o_lo)).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let on_chord = pose.to_local(lo + (hi - lo) * f);
        let q = on_ray(on_chord.x, on_chord.y);
        (q, gap(q))
    };
    // Each end's samples from the far end through the deepest point to it: where the deepest
    // point is at one end of the patch (a block tipped on a face, its corner deepest), the side
    // point of that end lies between the deepest point and the other end, on samples of the
    // other walk. Searched on its own walk alone, it stayed at the corner, and the two points
    // jumped by a fifth of the face each time the block tipped the other way.
    let through = |far: &[Sample], near: &[Sample]| -> Vec<Sample> {
        far.iter().rev().chain(&near[1..]).copied().collect()
    };
    Some([side(&through(&right, &left)), side(&through(&left, &right))])
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The distance from `q` to the boundary of the placed shape, by dense sampling: the
    /// independent reference.
    fn sampled_distance(s: &Superellipse, pose: &Pose, q: Vec2) -> f64 {
        s.boundary_polygon(pose, 200_000)
            .iter()
            .map(|&b| (b - q).norm())
            .fold(f64::INFINITY, f64::min)
    }

    /// Beyond a star's spike, next to its axis, the separation is the distance to the tip
    /// (sampled), where `f / |grad f|` alone reads nearly 0: the points of `pour-mixed.toml`
    /// that made contacts where grains did not touch (a star of its exponents, a point 0.15
    /// beyond its tip and 1e-4 off the axis, as measured there). Away from the axes, and for
    /// convex shapes, the first-order value as before.
    #[test]
    fn a_point_beyond_a_spike_is_as_far_as_the_tip() {
        let star = Superellipse::new([0.31, 0.22], [0.6, 0.84]).unwrap();
        let pose = Pose::new(Vec2::new(1.0, -2.0), 0.7).unwrap();
        for local in [
            Vec2::new(1e-4, 0.37),
            Vec2::new(-0.46, 5e-4),
            Vec2::new(0.0, -0.3),
        ] {
            let q = pose.to_world(local);
            let (f, g) = star.value_and_gradient(&pose, q);
            let first_order = f / g.norm();
            let d = sampled_distance(&star, &pose, q);
            assert!(
                first_order < 0.2 * d,
                "the premise: {first_order} against {d}"
            );
            let got = separation(&star, &pose, q);
            assert!(got >= d && got <= 1.02 * d, "{local:?}: {got} against {d}");
        }
        // Off the axes, and for a convex shape, nothing changes.
        let q = pose.to_world(Vec2::new(0.25, 0.2));
        let (f, g) = star.value_and_gradient(&pose, q);
        assert_eq!(separation(&star, &pose, q), f / g.norm());
        let block = Superellipse::new([0.31, 0.22], [4.0, 1.5]).unwrap();
        let q = pose.to_world(Vec2::new(1e-4, 0.37));
        let (f, g) = block.value_and_gradient(&pose, q);
        assert_eq!(separation(&block, &pose, q), f / g.norm());
    }

    /// A star pressed with two spikes into the middle of a long block's face, on each side of
    /// the block in turn: the manifold has a point at each spike's tip (tips that the block's
    /// own function places inside it). The block's samples are sparse along its faces (none
    /// within the margin of either tip here), so each region is found from the star's samples;
    /// those beyond the margin around the block's box are skipped, and skipping any on one
    /// side (the box narrowed there by 0.05) drops a region on that side.
    #[test]
    fn two_spikes_in_any_face_of_a_block_make_two_points() {
        use crate::contact::contact;
        use crate::geometry::Rotation;
        use crate::subdivision::Precision;
        let block = Superellipse::new([1.0, 0.5], [8.0, 8.0]).unwrap();
        let star = Superellipse::new([0.2, 0.2], [0.4, 0.4]).unwrap();
        let reach = 0.2 * std::f64::consts::FRAC_1_SQRT_2;
        for k in 0..4 {
            let angle = f64::from(k) * std::f64::consts::FRAC_PI_2;
            let turn = Rotation::new(angle);
            let pose_b = Pose::new(Vec2::ZERO, angle).unwrap();
            // The star left of the block, turned by 45 degrees (and a hair, so that one tip
            // is the deepest), its two right spikes 0.01 into the left face.
            let centre = Vec2::new(-1.0 - reach + 0.01, 0.0215);
            let tilt = std::f64::consts::FRAC_PI_4 + 0.01;
            let pose_s = Pose::new(turn.apply(centre), angle + tilt).unwrap();
            let tips = [tilt, tilt - std::f64::consts::FRAC_PI_2]
                .map(|t| turn.apply(centre + Vec2::new(t.cos(), t.sin()) * 0.2));
            for tip in tips {
                assert!(
                    block.value(&pose_b, tip) < 0.0,
                    "the tip {tip:?} is in the block"
                );
            }
            let p = contact(&star, &pose_s, &block, &pose_b, &Precision::default())
                .penetration
                .expect("the spikes are in the block");
            let m = grain_manifold(&star, &pose_s, &block, &pose_b, &p, 0.02);
            for tip in tips {
                assert!(
                    m.points().iter().any(|q| (q.point - tip).norm() < 0.03),
                    "side {k}: no point at the tip {tip:?}: {:?}",
                    m.points()
                );
            }
        }
    }

    /// A disk, and an ellipse lying flat, pressed into a block's face, in either order and at
    /// any angle of the block: one point, halfway into the overlap on the line through the
    /// round grain's centre along the face's normal (closed form: the face is flat there), at
    /// the overlap's depth. Walked as a blocky patch, their lenses (0.45 and 0.3 wide at
    /// these depths, more than `min_gap`) made two side points as well.
    #[test]
    fn a_disk_or_an_ellipse_on_a_block_is_one_point() {
        use crate::contact::contact;
        use crate::geometry::Rotation;
        use crate::subdivision::Precision;
        let block = Superellipse::new([1.0, 0.5], [8.0, 8.0]).unwrap();
        let disk = Superellipse::circle(0.3).unwrap();
        let rice = Superellipse::new([0.4, 0.14], [2.0, 2.0]).unwrap();
        // The round grain, its half-height over the face, its depth in it, its own angle.
        for (round, half, depth, own) in [(disk, 0.3, 0.1, 0.3), (rice, 0.14, 0.01, 0.0)] {
            for angle in [0.0, 0.4, 2.0] {
                let turn = Rotation::new(angle);
                let pose_b = Pose::new(Vec2::ZERO, angle).unwrap();
                // Above the top face's middle, `depth` into it.
                let centre = turn.apply(Vec2::new(0.05, 0.5 + half - depth));
                let pose_r = Pose::new(centre, angle + own).unwrap();
                let up = turn.apply(Vec2::new(0.0, 1.0));
                let middle = centre - up * (half - 0.5 * depth);
                for (a, pa, b, pb, normal) in [
                    (&round, &pose_r, &block, &pose_b, -up),
                    (&block, &pose_b, &round, &pose_r, up),
                ] {
                    let p = contact(a, pa, b, pb, &Precision::default())
                        .penetration
                        .expect("the grain is in the block");
                    let m = grain_manifold(a, pa, b, pb, &p, 0.02);
                    assert_eq!(m.points().len(), 1, "{angle}: {:?}", m.points());
                    let q = m.points()[0];
                    assert!((q.point - middle).norm() < 1e-3, "{angle}: {q:?}");
                    assert!((q.separation + depth).abs() < 1e-3, "{angle}: {q:?}");
                    assert!((m.normal - normal).norm() < 1e-3, "{angle}: {:?}", m.normal);
                }
            }
        }
    }

    proptest! {
        /// The single-precision rays agree with double precision's: the boundary point to a
        /// millionth of the grain (a bug in an exponent is off by far more). (The separation
        /// the patches read is checked against the sampled distance below.)
        #[test]
        fn single_precision_rays_agree_with_double(
            sx in 0.1f64..1.0, sy in 0.1f64..1.0, e in 1.0f64..10.0,
            dir in 0.0f64..6.3,
            ey in 1.0f64..10.0, length in 0.01f64..10.0,
        ) {
            let s = Superellipse::new([sx, sy], [e, e]).unwrap();
            let d = Vec2::new(dir.cos(), dir.sin());
            let (fast, exact) = (ray32(&s, d).unwrap(), radial_to_boundary(&s, d).unwrap());
            prop_assert!((fast - exact).norm() <= 1e-6 * sx.max(sy), "{fast:?} {exact:?}");
            // Unequal exponents (of the convex shapes whose patches take rays), from points
            // inside and outside: against double precision's Newton, and on the boundary by
            // the shape's own value.
            let u = Superellipse::new([sx, sy], [e, ey]).unwrap();
            let (fast, exact) = (
                ray32(&u, d * length).unwrap(),
                radial_to_boundary(&u, d * length).unwrap(),
            );
            prop_assert!((fast - exact).norm() <= 1e-6 * sx.max(sy), "{fast:?} {exact:?}");
            prop_assert!(u.local_value(fast).abs() <= 1e-5, "{}", u.local_value(fast));
        }

        /// Rays of very blocky grains (exponents 10 to the largest accepted, 1,000) reach the
        /// boundary from any distance: single precision against double's, and in double
        /// precision on the boundary by the shape's gauge, `max(|x/a|, |y/b|)` within a
        /// millionth of 1 for these exponents. Before 2026-12-06 an equal-exponent ray was not
        /// scaled first, and along a unit direction `4^e` overflowed single precision from
        /// `e = 64` (every ray of a block 0.5 across failed) and double from `e = 512`.
        #[test]
        fn rays_of_very_blocky_grains_reach_the_boundary(
            sx in 0.05f64..2.0, sy in 0.05f64..2.0, e in 10.0f64..1000.0,
            dir in 0.0f64..6.3, length in 0.01f64..10.0,
        ) {
            let s = Superellipse::new([sx, sy], [e, e]).unwrap();
            let d = Vec2::new(dir.cos(), dir.sin()) * length;
            let fast = ray32(&s, d);
            let exact = radial_to_boundary(&s, d);
            prop_assert!(fast.is_some() && exact.is_some(), "{fast:?} {exact:?}");
            let (fast, exact) = (fast.unwrap(), exact.unwrap());
            prop_assert!((fast - exact).norm() <= 1e-6 * sx.max(sy), "{fast:?} {exact:?}");
            // Along the ray, outward.
            prop_assert!(exact.cross(d).abs() <= 1e-9 * exact.norm() * length);
            prop_assert!(exact.dot(d) > 0.0);
            // For e >= 10, the boundary's `max(|x/a|, |y/b|)` lies in `[2^(-1/e), 1]`.
            let gauge = (exact.x / sx).abs().max((exact.y / sy).abs());
            prop_assert!(gauge <= 1.0 + 1e-9 && gauge >= 0.5f64.powf(1.0 / e) - 1e-9, "{gauge}");
        }
    }

    /// A block lying on the floor, tipped either way by a milliradian, is held at two side
    /// points placed symmetrically about its centre, four fifths of the way to its ends, for
    /// exponents from 8 to 1,000; and a block standing on a block the same, its normal the lower
    /// block's face's. Before 2026-12-06, from exponent 80 the side points were lost
    /// (the deepest corner alone, which changes ends as the block tips), and at 40-60 the side
    /// of the deepest end stayed at the corner.
    #[test]
    fn a_block_lying_flat_is_held_at_both_ends_whichever_way_it_tips() {
        use crate::contact::{contact, contact_wall};
        use crate::subdivision::Precision;
        use std::f64::consts::FRAC_PI_2;
        let plane = crate::shape::HalfPlane::floor(0.0).unwrap();
        let floor = Boundary::Plane(plane);
        let prec = Precision::default().deeper(3);
        for e in [8.0, 50.0, 100.0, 200.0, 1000.0] {
            let s = Superellipse::new([0.29, 0.228], [e, e]).unwrap();
            for tip in [-1e-3, 1e-3] {
                let pose = Pose::new(Vec2::new(-0.25, 0.2897), FRAC_PI_2 + tip).unwrap();
                let p = contact_wall(&s, &pose, &plane, &prec)
                    .penetration
                    .expect("on the floor");
                let m = wall_manifold(&s, &pose, &floor, &p, 0.02);
                let sides: Vec<f64> = m
                    .points()
                    .iter()
                    .filter(|q| q.id != 0)
                    .map(|q| q.point.x + 0.25)
                    .collect();
                assert_eq!(sides.len(), 2, "{e}, {tip}: {:?}", m.points());
                let (lo, hi) = (sides[0].min(sides[1]), sides[0].max(sides[1]));
                assert!(
                    (lo + hi).abs() < 0.01 && hi > 0.6 * 0.228,
                    "{e}, {tip}: sides at {lo} and {hi} from the centre"
                );
            }
        }
        let below = Superellipse::new([0.282, 0.32], [178.6, 178.6]).unwrap();
        let above = Superellipse::new([0.25, 0.23], [74.49, 74.49]).unwrap();
        let pose_below = Pose::new(Vec2::new(0.185, 0.8626), 1.55317).unwrap();
        let face = Vec2::new(1.55317f64.cos(), 1.55317f64.sin());
        for tilt in [1.5517, 1.55369, 1.556] {
            let pose_above = Pose::new(Vec2::new(0.202, 1.3914), tilt).unwrap();
            let p = contact(
                &below,
                &pose_below,
                &above,
                &pose_above,
                &Precision::default(),
            )
            .penetration
            .expect("standing on it");
            let m = grain_manifold(&below, &pose_below, &above, &pose_above, &p, 0.02);
            assert!((m.normal - face).norm() < 1e-3, "{tilt}: {:?}", m.normal);
            let across = Vec2::new(face.y, -face.x);
            let sides: Vec<f64> = m
                .points()
                .iter()
                .filter(|q| q.id != 0)
                .map(|q| (q.point - pose_above.center()).dot(across))
                .collect();
            assert_eq!(sides.len(), 2, "{tilt}: {:?}", m.points());
            let (lo, hi) = (sides[0].min(sides[1]), sides[0].max(sides[1]));
            assert!(
                (lo + hi).abs() < 0.02 && hi > 0.6 * 0.23,
                "{tilt}: sides at {lo} and {hi} from the upper block's centre"
            );
        }
    }

    /// A flat grain's patch is found on its face ([`face_patch`]) where dense sampling of its
    /// face finds it: the upper face of a block of exponent 16 (to its corners' diagonal) as the
    /// graph of `y(x)` in closed form, 20,000 samples; the patch the run of samples within the
    /// margin about the deepest point; its side points four fifths of the way from its middle to its ends. Faces
    /// lying on faces (tilts to 0.15 radians, the upper block overhanging either end) and a
    /// corner pressed into a face (45 degrees, where the patch runs along both sides of the
    /// corner: clipped by the corner's face alone, it stopped at the corner).
    #[test]
    fn a_flat_grains_patch_is_where_dense_sampling_of_its_face_puts_it() {
        use crate::contact::contact;
        use crate::subdivision::Precision;
        let a = Superellipse::new([0.3, 0.125], [16.0, 16.0]).unwrap();
        let b = Superellipse::new([0.125, 0.125], [16.0, 16.0]).unwrap();
        let margin = 0.02;
        let mut cases = Vec::new();
        for ta in [0.0, 0.06] {
            for tb in [-0.1, 0.0, 0.05, 0.15] {
                for dx in [-0.32, -0.1, 0.0, 0.2, 0.36] {
                    cases.push((ta, tb, dx, 0.25 - 0.004));
                }
            }
            cases.push((ta, std::f64::consts::FRAC_PI_4, 0.05, 0.125 + 0.125 * 1.28));
        }
        let y = |x: f64| 0.125 * (1.0 - (x / 0.3).abs().powi(16)).max(0.0).powf(1.0 / 16.0);
        let (total, mut checked) = (cases.len(), 0);
        for (ta, tb, dx, dy) in cases {
            let pa = Pose::new(Vec2::ZERO, ta).unwrap();
            let up = pa.to_world(Vec2::new(dx, dy));
            let pb = Pose::new(up, ta + tb).unwrap();
            // (A block tilted over the far end may miss the face.)
            let Some(p) = contact(&a, &pa, &b, &pb, &Precision::default()).penetration else {
                continue;
            };
            checked += 1;
            let m = grain_manifold(&a, &pa, &b, &pb, &p, margin);
            // The face, to its corners' diagonal (where `face_patch` ends it).
            let (n, corner) = (20_000, 0.3 * 0.5f64.powf(1.0 / 16.0));
            let xs: Vec<f64> = (0..=n)
                .map(|k| corner * (2.0 * k as f64 / n as f64 - 1.0))
                .collect();
            let at = |x: f64| pa.to_world(Vec2::new(x, y(x)));
            let gaps: Vec<f64> = xs.iter().map(|&x| separation32(&b, &pb, at(x))).collect();
            let deepest = pa.to_local(p.a_deepest).x;
            let k0 = xs.iter().position(|&x| x >= deepest).unwrap_or(n).min(n);
            assert!(
                gaps[k0] < margin,
                "{ta} {tb} {dx}: the deepest point is in the patch"
            );
            let (mut lo, mut hi) = (k0, k0);
            while lo > 0 && gaps[lo - 1] < margin {
                lo -= 1;
            }
            while hi < n && gaps[hi + 1] < margin {
                hi += 1;
            }
            let (x_lo, x_hi) = (xs[lo], xs[hi]);
            let mid = 0.5 * (x_lo + x_hi);
            let want = [
                at(mid - 0.8 * 0.5 * (x_hi - x_lo)),
                at(mid + 0.8 * 0.5 * (x_hi - x_lo)),
            ];
            let mut got: Vec<Vec2> = m
                .points()
                .iter()
                .filter(|q| q.id != 0)
                .map(|q| q.point)
                .collect();
            assert_eq!(got.len(), 2, "{ta} {tb} {dx}: {:?}", m.points());
            got.sort_by(|u, v| pa.to_local(*u).x.total_cmp(&pa.to_local(*v).x));
            for (g, w) in got.iter().zip(want) {
                assert!(
                    (*g - w).norm() < 3e-3,
                    "{ta} {tb} {dx}: side point {g:?}, sampled {w:?} (patch {x_lo} to {x_hi})"
                );
            }
        }
        assert!(checked + 4 >= total, "{checked} of {total} cases overlap");
    }

    /// Samples of the boundary of `s` at `pose` (in world coordinates) with their outward unit
    /// normals.
    fn boundary_with_normals(s: &Superellipse, pose: &Pose, n: u32) -> Vec<(Vec2, Vec2)> {
        (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / f64::from(n);
                let q = pose.to_world(s.boundary_point(t));
                let g = s.gradient(pose, q);
                (q, g * (1.0 / g.norm()))
            })
            .collect()
    }

    /// The separation a patch reads from a blocky grain is the distance, by dense sampling, to
    /// within a fifth of it (plus 1e-4), from 0.01 inside to 0.04 outside, off the corners (the
    /// faces' middle three fifths), for exponents 4 to 200, equal and unequal. `f / |grad f|`
    /// read a point 0.01 inside a face of exponent 85 as 0.055 deep and never read more than
    /// the grain's size over its exponent outside (0.004 at exponent 74): a patch never found
    /// its end, and blocky contacts had no side points (`tests/rest.rs`).
    #[test]
    fn a_blocky_grains_separation_is_its_distance_near_a_face() {
        let pose = Pose::new(Vec2::new(0.4, -0.3), 0.7).unwrap();
        let mut worst = 0.0f64;
        for exponents in [
            [4.0, 4.0],
            [20.0, 20.0],
            [85.0, 85.0],
            [200.0, 200.0],
            [8.0, 120.0],
        ] {
            let s = Superellipse::new([0.3, 0.22], exponents).unwrap();
            let dense = s.boundary_polygon(&pose, 100_000);
            for (q, n) in boundary_with_normals(&s, &pose, 400) {
                let local = pose.to_local(q);
                let off_corner = local.x.abs() <= 0.6 * 0.3 || local.y.abs() <= 0.6 * 0.22;
                if !off_corner {
                    continue;
                }
                for d in [-0.01, -0.003, 0.002, 0.01, 0.02, 0.04] {
                    let p = q + n * d;
                    let distance = dense
                        .iter()
                        .map(|&b| (b - p).norm())
                        .fold(f64::INFINITY, f64::min);
                    let signed = if s.value(&pose, p) < 0.0 {
                        -distance
                    } else {
                        distance
                    };
                    let got = separation32(&s, &pose, p);
                    let error = (got - signed).abs();
                    worst = worst.max(error / (signed.abs() + 1e-4));
                    assert!(
                        error <= 0.2 * signed.abs() + 1e-4,
                        "{exponents:?}, {local:?} moved {d}: read {got}, the distance is {signed}"
                    );
                }
            }
        }
        eprintln!("worst error relative to the distance: {worst:.3}");
    }
}

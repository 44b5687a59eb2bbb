//! Contact geometry carried across steps (issue 18): a grain pair that has hardly moved
//! against each other keeps its manifold, moved to first order with the pair, instead of a new
//! narrow-phase search and patch walk every step.
//!
//! In a settled heap every grain is awake and pressed on by its neighbours, yet a pair's
//! relative pose moves by about `1e-7` a step (median; `1e-5` for the 99th percentile,
//! docs/peers.md), and the narrow phase and the blocky grains' patches were two thirds of the
//! step, finding the same points again. Box2D's solver moves a contact's separation with the
//! bodies within a step (the substeps do the same here, [`super::soft`]); a carried manifold
//! does it across steps:
//! - its points and normal are kept in A's frame, with B's pose in that frame when they were
//!   found;
//! - each step, the point of B that sat on each point then has moved by `delta` in A's frame:
//!   the separation becomes `separation + n . delta`, and the point moves by `delta / 2` (it
//!   lies between the grains). For a smooth pair the separation is the narrow phase's answer
//!   up to the second order of the motion (the shapes' curvature times its square); the point
//!   only to the first: where one surface slides on the other it moves with neither half, and
//!   may be up to `reach / 2` from where a search would put it (a disk sliding 4e-4 along a
//!   block's face: carried 2e-4 along, searched 4e-4), a lever arm off by that much;
//! - the overlap itself stays proven every step: a point that was proven inside both grains
//!   (the middle of the two deepest points, or A's deepest point) is proven inside both again
//!   at the new poses by interval arithmetic, or the pair is searched afresh;
//! - once B's points have moved more than `reach` in A's frame (the centre's shift plus the
//!   turn times B's bounding radius: a bound on any point's motion), the pair is searched
//!   afresh. The reach is at most [`SIZE_REACH`] of the smaller grain's bounding radius, so
//!   that a pair turns at most that many radians between two searches whatever the grains'
//!   size. How far the carried points can then be from the fresh ones is set by `reach`:
//!   a patch's ends follow the sliding to first order, so they jump by up to `reach` when
//!   refreshed; the separations by its square times the curvature.
//!
//! What is not carried: disk pairs (their closed form is cheaper than this), wall contacts
//! (against a wall the narrow phase is a support point, and only blocky grains walk a patch),
//! and pairs that were apart (a new contact is always found by the narrow phase).

use crate::contact::Penetration;
use crate::contact::manifold::{MAX_POINTS, Manifold, ManifoldPoint};
use crate::geometry::{Rotation, Vec2};
use crate::interval::{ImplicitShape, PlacedSuperellipse};
use crate::shape::{Pose, Superellipse};

/// The most a pair may move between two searches, as a fraction of the smaller grain's
/// bounding radius, whatever `carry_reach` says: at most this many radians of turn. (A review
/// found that without it two grains 1e-3 across, at the default reach of 5e-4, could turn half
/// a radian between searches, their carried depth then off by 17% of their size, and that a
/// reach of 1e6 let a mixed heap sink 0.33 deep.) It binds for grains under 0.2 across at
/// the default reach; every built-in scene's grains are larger.
pub const SIZE_REACH: f64 = 2.5e-3;

/// A pair's manifold as found at some step, in A's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Carried {
    /// B's pose in A's frame when the manifold was found.
    rel: Pose,
    /// The normal, from A towards B, in A's frame.
    normal: Vec2,
    /// A point then proven inside both grains, in A's frame.
    witness: Vec2,
    points: [ManifoldPoint; MAX_POINTS],
    len: usize,
}

/// The frame a shape's points are carried in: its pose, except for a circle, whose turning
/// moves none of its boundary (a disk rolling on a block touches it at the same place of the
/// block, not of the disk): then its centre alone, so that a rolling disk's contacts are not
/// searched afresh for its turn.
fn frame(shape: &Superellipse, pose: &Pose) -> Pose {
    if shape.is_circle() {
        Pose::from_parts(pose.center(), 0.0)
    } else {
        *pose
    }
}

/// A slot past a manifold's points.
const UNUSED: ManifoldPoint = ManifoldPoint {
    point: Vec2::ZERO,
    separation: 0.0,
    id: 0,
};

/// Whether `w` (world) is proven inside both placed shapes.
fn proven_inside(a: &PlacedSuperellipse, b: &PlacedSuperellipse, w: Vec2) -> bool {
    w.is_finite() && a.enclose_point(w).hi < 0.0 && b.enclose_point(w).hi < 0.0
}

/// A carried manifold as numbers, for a dump (`contacts[].carried`): B's pose in A's frame
/// (`[x, y, angle, cos, sin]`, its rotation as it was composed), the normal and the witness
/// in A's frame, and each point `[x, y, separation, id]`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CarriedParts {
    pub pose: [f64; 5],
    pub normal: [f64; 2],
    pub witness: [f64; 2],
    pub points: Vec<[f64; 4]>,
}

impl Carried {
    pub fn to_parts(&self) -> CarriedParts {
        let (c, r) = (self.rel.center(), self.rel.rotation());
        CarriedParts {
            pose: [c.x, c.y, self.rel.angle(), r.cos, r.sin],
            normal: self.normal.to_array(),
            witness: self.witness.to_array(),
            points: self.points[..self.len]
                .iter()
                .map(|q| [q.point.x, q.point.y, q.separation, f64::from(q.id)])
                .collect(),
        }
    }

    /// Back from [`Self::to_parts`], or why not: every number finite, the rotation that of its
    /// angle, the normal of unit length, one to three points of distinct numbers 0, 1 or 2.
    pub fn from_parts(parts: &CarriedParts) -> Result<Carried, &'static str> {
        let CarriedParts {
            pose,
            normal,
            witness,
            points,
        } = parts;
        let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
        if !(finite(pose) && finite(normal) && finite(witness) && points.iter().all(|p| finite(p)))
        {
            return Err("carried numbers must be finite");
        }
        let [x, y, angle, cos, sin] = *pose;
        if ((cos * cos + sin * sin) - 1.0).abs() > 1e-9 {
            return Err("a carried pose's cos and sin must be of a rotation");
        }
        if points.is_empty() || points.len() > MAX_POINTS {
            return Err("a carried manifold holds one to three points");
        }
        let n = Vec2::from(*normal);
        if (n.norm() - 1.0).abs() > 1e-9 {
            return Err("a carried normal must be of length 1");
        }
        let r = Rotation::new(angle);
        if (r.cos - cos).abs() > 1e-9 || (r.sin - sin).abs() > 1e-9 {
            return Err("a carried pose's cos and sin must be those of its angle");
        }
        let mut out = [UNUSED; MAX_POINTS];
        for (k, (o, &[px, py, separation, id])) in out.iter_mut().zip(points).enumerate() {
            if !(id == 0.0 || id == 1.0 || id == 2.0) {
                return Err("a carried point's id is 0, 1 or 2");
            }
            if points[..k].iter().any(|q| q[3] == id) {
                return Err("a carried manifold's points have distinct ids");
            }
            *o = ManifoldPoint {
                point: Vec2::new(px, py),
                separation,
                id: id as u8,
            };
        }
        Ok(Carried {
            rel: Pose::from_rotation(Vec2::new(x, y), angle, Rotation { cos, sin }),
            normal: n,
            witness: Vec2::from(*witness),
            points: out,
            len: points.len(),
        })
    }

    /// Whether a carried manifold read from a dump fits grains of bounding radii `ra` and
    /// `rb`: the grains overlapped when it was found, so B's centre, the witness and every
    /// point lie within `ra + rb` of A's, and no separation is larger. (A hand-edited dump's
    /// separation of -1e300 launched grains; the overlap is proven again before any use, but
    /// the geometry is not.)
    pub fn fits(&self, ra: f64, rb: f64) -> Result<(), &'static str> {
        let reach = (ra + rb) * (1.0 + 1e-9);
        let near = |v: Vec2| v.norm() <= reach;
        let points = &self.points[..self.len];
        if !(near(self.rel.center())
            && near(self.witness)
            && points
                .iter()
                .all(|q| near(q.point) && q.separation.abs() <= reach))
        {
            return Err("a carried manifold must lie within the two grains' reach of A's centre");
        }
        Ok(())
    }

    /// The manifold `m` of the overlap `p` found at these poses, to carry, or `None` when no
    /// point of the overlap is proven inside both grains (nothing to re-prove it by).
    pub fn new(
        a: &Superellipse,
        pose_a: &Pose,
        b: &Superellipse,
        pose_b: &Pose,
        m: &Manifold,
        p: &Penetration,
    ) -> Option<Carried> {
        let (placed_a, placed_b) = (
            PlacedSuperellipse::new(*a, *pose_a),
            PlacedSuperellipse::new(*b, *pose_b),
        );
        let (pose_a, pose_b) = (&frame(a, pose_a), &frame(b, pose_b));
        let middle = (p.a_deepest + p.b_deepest) * 0.5;
        let witness = [middle, p.a_deepest, p.b_deepest]
            .into_iter()
            .find(|&w| proven_inside(&placed_a, &placed_b, w))?;
        let points = m.points();
        // (The slots past the points zero, as a dump reads them back.)
        let mut local = [UNUSED; MAX_POINTS];
        for (l, q) in local.iter_mut().zip(points) {
            *l = ManifoldPoint {
                point: pose_a.to_local(q.point),
                ..*q
            };
        }
        Some(Carried {
            rel: pose_a.relative(pose_b),
            normal: pose_a.rotation().apply_inverse(m.normal),
            witness: pose_a.to_local(witness),
            points: local,
            len: points.len(),
        })
    }

    /// The manifold at the poses `pose_a`, `pose_b`: carried, when B's points have moved by
    /// at most `reach` in A's frame since it was found and the overlap is proven again; `None`
    /// otherwise (the caller searches afresh).
    pub fn manifold(
        &self,
        a: &Superellipse,
        pose_a: &Pose,
        b: &Superellipse,
        pose_b: &Pose,
        reach: f64,
    ) -> Option<Manifold> {
        let (pose_a, pose_b) = (&frame(a, pose_a), &frame(b, pose_b));
        let rel = pose_a.relative(pose_b);
        let turn = rel.angle() - self.rel.angle();
        let motion = (rel.center() - self.rel.center()).norm() + turn.abs() * b.bounding_radius();
        let reach = reach.min(SIZE_REACH * a.bounding_radius().min(b.bounding_radius()));
        // (A motion that is not a number is no motion within reach.)
        if motion.is_nan() || motion > reach {
            return None;
        }
        let (placed_a, placed_b) = (
            PlacedSuperellipse::new(*a, *pose_a),
            PlacedSuperellipse::new(*b, *pose_b),
        );
        if !proven_inside(&placed_a, &placed_b, pose_a.to_world(self.witness)) {
            return None;
        }
        let mut points = [self.points[0]; MAX_POINTS];
        for (out, q) in points.iter_mut().zip(&self.points[..self.len]) {
            // B's material point that sat at `q` then, where it is now (A's frame).
            let delta = rel.to_world(self.rel.to_local(q.point)) - q.point;
            *out = ManifoldPoint {
                point: pose_a.to_world(q.point + delta * 0.5),
                separation: q.separation + self.normal.dot(delta),
                id: q.id,
            };
        }
        Manifold::from_points(pose_a.rotation().apply(self.normal), &points[..self.len])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::contact;
    use crate::contact::manifold::grain_manifold;
    use crate::subdivision::Precision;

    /// The patches' margin of the soft step (four slops).
    const MARGIN: f64 = 0.02;

    fn pose(x: f64, y: f64, angle: f64) -> Pose {
        Pose::new(Vec2::new(x, y), angle).unwrap()
    }

    /// The pair's manifold as the soft step finds it, carried.
    fn carried(a: &Superellipse, pa: &Pose, b: &Superellipse, pb: &Pose) -> Carried {
        let p = contact(a, pa, b, pb, &Precision::default())
            .penetration
            .expect("the pair overlaps");
        let m = grain_manifold(a, pa, b, pb, &p, MARGIN);
        Carried::new(a, pa, b, pb, &m, &p).expect("a point proven inside both")
    }

    /// Two disks: the overlap along the centre line is `ra + rb - d` in closed form. The carried
    /// separation follows B's motion to second order (its error over a motion `delta` is about
    /// `delta^2 / r`), across the line and along it; a first-order error (the separation not
    /// moved, or moved the wrong way) would be `delta` itself. The disks' own turning moves
    /// nothing: carried across a turn of a radian each, the manifold is the same.
    #[test]
    fn a_disk_pairs_carried_separation_is_the_closed_form_to_second_order() {
        let (ra, rb) = (0.3, 0.25);
        let (a, b) = (
            Superellipse::circle(ra).unwrap(),
            Superellipse::circle(rb).unwrap(),
        );
        let (pa, pb) = (pose(0.0, 0.0, 0.0), pose(0.52, 0.1, 0.0));
        let c = carried(&a, &pa, &b, &pb);
        // (Up to the reach the disks' size allows, `SIZE_REACH` of the smaller radius.)
        for delta in [1e-5, 1e-4, 6e-4] {
            for dir in [0.0, 1.0, 2.0, 3.0, 4.0, 5.0] {
                let d = Vec2::new(f64::cos(dir), f64::sin(dir)) * delta;
                let moved = pose(0.52 + d.x, 0.1 + d.y, 0.0);
                let m = c.manifold(&a, &pa, &b, &moved, 1.0).unwrap();
                let exact = moved.center().norm() - (ra + rb);
                let got = m.points()[0].separation;
                assert!(
                    (got - exact).abs() <= 2.0 * delta * delta / rb + 1e-12,
                    "moved {delta:e} along {dir}: carried {got}, closed form {exact}"
                );
            }
        }
        let turned = c
            .manifold(&a, &pose(0.0, 0.0, 1.0), &b, &pose(0.52, 0.1, -1.0), 1e-12)
            .expect("a disk's turn moves none of its boundary");
        let still = c.manifold(&a, &pa, &b, &pb, 1e-12).unwrap();
        assert_eq!(turned, still);
    }

    /// Blocks pressed face to face: carried while B moved less than the reach (a slide, a
    /// turn), searched afresh beyond it, where the turn counts by B's bounding radius.
    #[test]
    fn a_pair_that_moved_beyond_the_reach_is_searched_afresh() {
        let block = Superellipse::new([0.3, 0.2], [6.0, 6.0]).unwrap();
        let (pa, pb) = (pose(0.0, 0.0, 0.0), pose(0.1, 0.395, 0.0));
        let c = carried(&block, &pa, &block, &pb);
        let reach = 1e-3;
        let slide = |dx: f64| pose(0.1 + dx, 0.395, 0.0);
        assert!(
            c.manifold(&block, &pa, &block, &slide(0.9e-3), reach)
                .is_some()
        );
        assert!(
            c.manifold(&block, &pa, &block, &slide(1.1e-3), reach)
                .is_none()
        );
        let r = block.bounding_radius();
        let turn = |t: f64| pose(0.1, 0.395, t);
        assert!(
            c.manifold(&block, &pa, &block, &turn(0.9e-3 / r), reach)
                .is_some()
        );
        assert!(
            c.manifold(&block, &pa, &block, &turn(1.1e-3 / r), reach)
                .is_none()
        );
        // A turns: in its frame B moves round it, as far as B's centre is from A's.
        let far = 1.1e-3 / pb.center().norm();
        assert!(
            c.manifold(&block, &pose(0.0, 0.0, far), &block, &pb, reach)
                .is_none()
        );
        // The face contact keeps its two sides and the middle.
        assert_eq!(
            c.manifold(&block, &pa, &block, &pb, reach)
                .unwrap()
                .points()
                .len(),
            3
        );
    }

    /// The overlap is proven again at every step it is carried: a pair pulled apart (0.01
    /// between the faces) is not carried, however large the reach.
    #[test]
    fn a_pair_no_longer_proven_to_overlap_is_searched_afresh() {
        let block = Superellipse::new([0.3, 0.2], [6.0, 6.0]).unwrap();
        let (pa, pb) = (pose(0.0, 0.0, 0.0), pose(0.1, 0.395, 0.0));
        let c = carried(&block, &pa, &block, &pb);
        let apart = pose(0.1, 0.41, 0.0);
        assert!(
            contact(&block, &pa, &block, &apart, &Precision::default())
                .penetration
                .is_none()
        );
        assert!(c.manifold(&block, &pa, &block, &apart, 10.0).is_none());
    }

    #[test]
    fn a_carried_manifold_survives_its_numbers_bit_for_bit() {
        let block = Superellipse::new([0.3, 0.2], [6.0, 6.0]).unwrap();
        let ellipse = Superellipse::new([0.35, 0.12], [2.0, 2.0]).unwrap();
        let slab = Superellipse::new([0.35, 0.12], [2.0, 6.0]).unwrap();
        let (pa, pb) = (pose(0.3, -0.2, 0.7), pose(0.55, 0.1, 2.1));
        let c = carried(&block, &pa, &slab, &pb);
        assert_eq!(c.len, 3, "the premise: a manifold of three points");
        assert_eq!(Carried::from_parts(&c.to_parts()), Ok(c));
        let bad = |edit: fn(&mut CarriedParts)| {
            let mut p = c.to_parts();
            edit(&mut p);
            Carried::from_parts(&p).unwrap_err()
        };
        assert!(bad(|p| p.pose[3] = 2.0).contains("rotation"));
        assert!(bad(|p| p.normal[0] = f64::NAN).contains("finite"));
        assert!(bad(|p| p.points.clear()).contains("one to three"));
        assert!(bad(|p| p.points[0][3] = 3.0).contains("id"));
        assert!(bad(|p| p.pose[2] += 0.1).contains("of its angle"));
        assert!(bad(|p| p.normal = [0.0, 0.0]).contains("length 1"));
        assert!(bad(|p| p.points[1][3] = p.points[0][3]).contains("distinct"));
        // A one-point manifold comes back bit for bit too (its unused slots included).
        let round = carried(&ellipse, &pa, &ellipse, &pose(0.3, 0.02, 2.1));
        assert_eq!(round.len, 1);
        assert_eq!(Carried::from_parts(&round.to_parts()), Ok(round));
        // What a dump's grains make implausible: a separation of -1e300 (it launched grains).
        let (ra, rb) = (block.bounding_radius(), slab.bounding_radius());
        assert_eq!(c.fits(ra, rb), Ok(()));
        let mut far = c.to_parts();
        far.points[0][2] = -1e300;
        let far = Carried::from_parts(&far).unwrap();
        assert!(far.fits(ra, rb).unwrap_err().contains("reach"));
    }

    /// However large the reach asked, a pair is searched afresh once it has turned
    /// [`SIZE_REACH`] radians or moved that fraction of the smaller grain's radius: two grains
    /// a thousandth across, turned by a hundredth of a radian (B's points moved 1e-5, far
    /// below the default reach), are searched afresh.
    #[test]
    fn the_reach_shrinks_with_the_grains() {
        let tiny = Superellipse::new([1e-3, 0.6e-3], [2.0, 2.0]).unwrap();
        let (pa, pb) = (pose(0.0, 0.0, 0.0), pose(1.5e-3, 0.0, 0.3));
        let c = carried(&tiny, &pa, &tiny, &pb);
        let turned = pose(1.5e-3, 0.0, 0.31);
        assert!(c.manifold(&tiny, &pa, &tiny, &turned, 5e-4).is_none());
        let slightly = pose(1.5e-3, 0.0, 0.3 + 1e-3);
        assert!(c.manifold(&tiny, &pa, &tiny, &slightly, 5e-4).is_some());
    }
}

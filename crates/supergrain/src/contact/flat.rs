//! Flat grains' own path: two grains whose exponents are at least 8 and equal (squares,
//! planks, bricks) answered by their faces, as Box2D answers two boxes, with a proof of its own.
//!
//! Their faces are flat to a thousandth of a semi-axis over most of their length, and the
//! certified Newton path ([`super::certified`]) is at its slowest there: the Hessians of
//! `|x|^16` are all but singular along a face, and after the deepest points come the two pushes'
//! rays and the patch. In Box2D's tumbler (2,025 squares of exponent 16) that path was half of
//! the step. Here:
//!
//! - **The axis.** For each grain's two face normals (pointing at the other grain), the
//!   separation of the two along it, `n . (c_B - c_A) - h_A(n) - h_B(-n)` with `h` the support
//!   functions (exact along a grain's own axis, the semi-axis). The axis of the largest
//!   separation (the least overlap) is the contact's, its grain the reference: Box2D's choice
//!   of a reference face (separating axes).
//! - **Apart**, when an axis separates them: proven by the certified path's half-plane
//!   certificate ([`super::certified::proves_above`]) with that grain's half-plane `n . y <=
//!   h(n)` (which holds it exactly) and the other grain's level set at the touching level: no
//!   point of one lies deeper in the other than half a final cell, the certified path's
//!   "apart". (Not for a thinner overlap, which that proof would also call apart: as on the
//!   certified path, an overlap that can be proven is reported.)
//! - **Overlapping**: the reference face within the other grain's shadow ([`Face`]), its point
//!   deepest in the other grain: over the other grain's support point along the normal, its
//!   depth that point's below the face (as Box2D measures an incident point against the
//!   reference face); or, where the face rises towards its middle, the deepest by a search
//!   along it, if deeper. That point is proven inside both grains by interval enclosures over
//!   a box of a few ulps, moved a hair into the reference grain, as the certified path's
//!   points are. The manifold: the reference face's normal; the middle of the overlap there;
//!   and when the patch is wide its two side points ([`Face::patch`]), the middle then a
//!   margin shallower.
//! - Anything else (a separation near zero the certificate cannot settle, no point proven
//!   inside both) returns `None`, and the caller takes the certified path: an answer is
//!   never less proven than that path's.

use super::boundary::INWARD;
use super::certified::{proves_above, support_point_by, touch_level};
use super::manifold::{Face, Manifold, flat, min_gap, separation32};
use super::superellipse_superellipse::{frame, world_slack};
use crate::geometry::Vec2;
use crate::shape::{Pose, Superellipse, pow32, support_by};
use crate::subdivision::Precision;

/// Two flat grains' contact by their faces (module docs): `Some(None)` proven apart,
/// `Some(Some(manifold))` proven overlapping with its manifold (normal from A to B), `None`
/// not a pair of flat grains, or no proof: the caller's certified path answers.
pub(crate) fn flat_pair(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    margin: f64,
) -> Option<Option<Manifold>> {
    // (Equal exponents: their support points are in closed form. Unequal ones' come from a
    // bound's maximiser, a little off the corner, where the face read a needle's corner 24%
    // shallower than it is.)
    let square = |s: &Superellipse| flat(s) && s.exponents()[0] == s.exponents()[1];
    if !(square(a) && square(b)) {
        return None;
    }
    // Bounding circles or boxes apart: apart (as the certified path answers them).
    let Some((local_a, local_b, region)) = frame(a, pose_a, b, pose_b) else {
        return Some(None);
    };
    let cell = precision.cell_size(&region);
    let slack = world_slack(pose_a, &region);
    let rel_b = *local_b.pose();
    let rel_a = rel_b.inverse();
    let (sep_a, axis_a) = best_axis(a, b, &rel_b);
    let (sep_b, axis_b) = best_axis(b, a, &rel_a);
    // A's face unless B's is clearly the better axis (Box2D's tolerance, scaled to the
    // grains): two faces lying on each other are all but tied, and a reference that flipped
    // between them from step to step renumbered the side points and lost their warm starts.
    let tie = 0.01 * a.min_semi_axis().min(b.min_semi_axis());
    let a_ref = sep_b <= sep_a + tie;
    // Apart along either grain's axis, when one separates them: proven, or the certified path
    // answers. (Only then: a pair overlapping by less than half a final cell is "apart" to
    // that proof too, and resting blocks, whose contacts are that thin, lost them and sank
    // until they were not: a heap of exponents 50-200 never rested. The certified path, and
    // this one, report any overlap they can prove first.)
    if sep_a.max(sep_b) > 0.0 {
        let on_a = || {
            proves_above(
                (axis_a, own_support(a, axis_a)),
                b,
                &rel_b,
                -touch_level(b, cell),
            )
        };
        let on_b = || {
            proves_above(
                (axis_b, own_support(b, axis_b)),
                a,
                &rel_a,
                -touch_level(a, cell),
            )
        };
        // (The farther apart first: the other only where that proof fails.)
        let a_first = sep_a >= sep_b;
        let apart = [a_first, !a_first]
            .into_iter()
            .any(|on_a_axis| if on_a_axis { on_a() } else { on_b() });
        return apart.then_some(None);
    }
    // The reference face, the other grain (the incident one) and the normal from A to B.
    let (own, own_pose, other, other_pose, axis) = if a_ref {
        (a, pose_a, b, pose_b, axis_a)
    } else {
        (b, pose_b, a, pose_a, axis_b)
    };
    let out = own_pose.rotation().apply(axis);
    let face = Face::new(own, own_pose, out, Some((other, other_pose)), margin)?;
    // Where the other grain reaches deepest into the reference one: its support point along
    // the normal (a corner, or a point of a face lying on the face), over the face's stretch.
    let into = other_pose.rotation().apply_inverse(-out);
    let tip = other_pose.to_world(support_point_by(other, into, pow32)?);
    let at_tip = face.coord(tip);
    if at_tip < face.lo || at_tip > face.hi {
        // Beyond the face's stretch (past its corner, or outside the other grain's own shadow
        // by rounding): the certified path answers.
        return None;
    }
    // The overlap's depth there along the normal, as Box2D measures an incident point against
    // the reference face: the face's point over the tip less the tip. (The face point's own
    // separation, its distance to the other grain, reads a corner pressed into the face as
    // shallow as the corner is sharp: `d / sqrt 2` for a square's corner `d` deep.) But the
    // face curves away from flat towards its ends (3% of the semi-axis at 0.95 of it, at
    // exponent 16), and there the overlap is deepest beside the tip: so also the face point
    // most inside the other grain by its separation, searched along the stretch (a golden
    // section, [`GOLDEN`] steps), and the deeper of the two. (Under the tip alone, a hostile
    // test found contacts read 40 times too shallow, a small block lying near a big one's
    // corner, and 125 times for two of the tumbler's squares.) The gauge reads no distance
    // deep inside a grain: each reading is held to the overlap of the two grains' shadows on
    // the normal, which no depth along it exceeds.
    // The search only where the face rises above its height over the tip by more than 5% of
    // the depth there: the tip is the other grain's lowest point, so nowhere is the overlap
    // deeper than under the tip by more than that rise (most pairs of the tumbler lie on the
    // flat middle of a face, and skip it).
    let gap = |q: Vec2| separation32(other, other_pose, q);
    let most = -if a_ref { sep_a } else { sep_b };
    let over_tip = face.on(at_tip)?;
    let under_tip = (over_tip - tip).dot(out);
    let rise = (face.on(0.0f64.clamp(face.lo, face.hi))? - over_tip).dot(out);
    let (from, depth) = if rise > 0.05 * under_tip.max(0.0) {
        let sunk = |t: f64| {
            face.on(t)
                .map_or(f64::NEG_INFINITY, |q| (-gap(q)).min(most))
        };
        let (t, d) = golden(face.lo, face.hi, sunk);
        if d > under_tip {
            (t, d)
        } else {
            (at_tip, under_tip)
        }
    } else {
        (at_tip, under_tip)
    };
    let deep = if from == at_tip {
        over_tip
    } else {
        face.on(from)?
    };
    // Near the face's corner a corner pressed in is nearer the side face than the face it is
    // pressed into (two corners meeting), and it comes out sideways, not along the normal (the
    // face read it up to twice as deep as the certified pushes): the certified path answers.
    if depth.is_nan() || depth <= 0.0 || face.half - from.abs() < 2.0 * depth {
        return None;
    }
    // Proven inside both, in A's frame (as the certified path proves its points), moved a
    // hair towards the reference grain's centre.
    let q = pose_a.to_local(deep);
    let centre = if a_ref { Vec2::ZERO } else { rel_b.center() };
    let inside = INWARD.iter().any(|&k| {
        let x = centre + (q - centre) * (1.0 - k);
        local_a.enclose_around(x, slack).hi < 0.0 && local_b.enclose_around(x, slack).hi < 0.0
    });
    if !inside {
        return None;
    }
    let normal = if a_ref { out } else { -out };
    // The middle of the overlap halfway along the depth.
    let middle = deep - out * (0.5 * depth);
    let mut m = Manifold::new(normal, middle, depth);
    // The sides' separations are the other grain's gauge, good near its boundary only: deep
    // inside a needle it read 2.2 where no point is deeper than 0.031, and it fails (infinite)
    // on grains of exponent 1000. No side is deeper than the deepest point along the normal;
    // a side that is not a number leaves the middle alone.
    let sides = face
        .patch(from, gap, margin, min_gap(a, b))
        .filter(|sides| sides.iter().all(|(_, g)| g.is_finite()))
        .map(|sides| sides.map(|(q, g)| (q, g.max(-depth))));
    m.sides(sides, margin);
    Some(Some(m))
}

/// Steps of the golden-section search for the face point deepest in the other grain: the
/// stretch shrinks to 0.618^12, a three-hundredth of it.
const GOLDEN: u32 = 12;

/// The maximum of `f` over `[lo, hi]` by golden sections (`f` unimodal there, as the depth
/// of one convex grain's face in another is): where, and its value.
fn golden(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> f64) -> (f64, f64) {
    let k = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - k * (hi - lo), lo + k * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..GOLDEN {
        if f1 < f2 {
            (lo, x1, f1) = (x1, x2, f2);
            x2 = lo + k * (hi - lo);
            f2 = f(x2);
        } else {
            (hi, x2, f2) = (x2, x1, f1);
            x1 = hi - k * (hi - lo);
            f1 = f(x1);
        }
    }
    if f1 >= f2 { (x1, f1) } else { (x2, f2) }
}

/// The face normal of `own` (at the origin of its frame, `other` at `rel`) along which the two
/// are farthest apart, pointing at `other`, and that separation (estimated: it only chooses).
fn best_axis(own: &Superellipse, other: &Superellipse, rel: &Pose) -> (f64, Vec2) {
    let c = rel.center();
    let sign = |v: f64| if v < 0.0 { -1.0 } else { 1.0 };
    [Vec2::new(sign(c.x), 0.0), Vec2::new(0.0, sign(c.y))]
        .into_iter()
        .map(|n| {
            let toward = rel.rotation().apply_inverse(-n);
            // (An estimate with single precision's powers: it only chooses.)
            let h = support_by(other.semi_axes(), other.exponents(), toward, pow32);
            (n.dot(c) - own_support(own, n) - h, n)
        })
        .fold((f64::NEG_INFINITY, Vec2::new(1.0, 0.0)), |best, x| {
            if x.0 > best.0 { x } else { best }
        })
}

/// A grain's support along one of its own axes: the semi-axis (exactly: the grain lies in its
/// box).
fn own_support(own: &Superellipse, axis: Vec2) -> f64 {
    let s = own.semi_axes();
    if axis.x != 0.0 { s.x } else { s.y }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::contact;
    use crate::shape::support;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A block's corner pressed into a face, turned 10 to 45 degrees, and a block lying on a
    /// face tilted by 0.01 radians: the manifold's normal is the face's, and its deepest point
    /// as deep along it as the block's lowest point is below the face, that point sampled
    /// from 200,000 points of the block's boundary (they crowd at its corners). The certified
    /// path's pushes run along a gradient and read a corner shallower (0.0048 for a corner
    /// 0.0090 deep, found by sampling), so they are no reference here.
    #[test]
    fn a_corner_pressed_into_a_face_is_as_deep_as_it_is() {
        let floor = Superellipse::new([0.6, 0.125], [16.0, 16.0]).unwrap();
        let below = Pose::new(Vec2::new(0.1, -0.125), 0.0).unwrap();
        for e in [8.0, 16.0, 100.0] {
            let block = Superellipse::new([0.2, 0.1], [e, e]).unwrap();
            for turn in [0.01, 0.1745, 0.4, std::f64::consts::FRAC_PI_4] {
                for deep in [0.002, 0.01, 0.03] {
                    let lowest = |pose: &Pose| {
                        block
                            .boundary_polygon(pose, 200_000)
                            .iter()
                            .map(|q| q.y)
                            .fold(f64::INFINITY, f64::min)
                    };
                    let centre = Vec2::new(0.05, 0.0);
                    let height = -lowest(&Pose::new(centre, turn).unwrap()) - deep;
                    let pose = Pose::new(centre + Vec2::new(0.0, height), turn).unwrap();
                    let want = -lowest(&pose);
                    let Some(Some(m)) =
                        flat_pair(&floor, &below, &block, &pose, &Precision::default(), 0.02)
                    else {
                        panic!("{e} {turn} {deep}: no proven overlap by the faces");
                    };
                    assert!(
                        (m.normal - Vec2::new(0.0, 1.0)).norm() < 1e-12,
                        "{:?}",
                        m.normal
                    );
                    // The middle's (which counts a margin shallower beside two sides; the
                    // sides' separations are the gauge's, good to second order).
                    let middle = m.points().iter().find(|q| q.id == 0).expect("a middle");
                    let sides = if m.points().len() == 3 { 0.02 } else { 0.0 };
                    let got = sides - middle.separation;
                    assert!(
                        (got - want).abs() <= 0.01 * want + 2e-5,
                        "{e} {turn} {deep}: depth {got}, sampled {want}"
                    );
                }
            }
        }
    }

    /// The cases of a hostile test (2026-12-06, stop 47), their true depths found by an exact
    /// separating-axis search over 4,000 directions and cross-checked by sampling 80,000
    /// boundary points (agreeing to 1e-6): a small block lying near a big one's corner, where
    /// the face curves away (read 40 times too shallow under the tip alone); two of the
    /// tumbler's squares at 66 degrees (125 times); and side points whose gauge failed or
    /// read deep inside a needle (infinite, and 2.2 against a depth of 0.031). Each is answered
    /// by the faces with its deepest point at least 95% of the true depth (the least
    /// translation apart) and no point more than 15% deeper (the depth along the face's normal
    /// is at least that translation, and the gauge's reading is good to second order), or left
    /// to the certified path.
    #[test]
    fn a_hostile_tests_contacts_are_as_deep_as_they_are() {
        let at = |sx: f64, sy: f64, e: f64, x: f64, y: f64, angle: f64| {
            (
                Superellipse::new([sx, sy], [e, e]).unwrap(),
                Pose::new(Vec2::new(x, y), angle).unwrap(),
            )
        };
        let cases = [
            (
                at(1.0, 1.0, 16.0, 0.0, 0.0, 0.0),
                at(0.1, 0.1, 9.0, -0.95, -1.085, 0.001),
                6.37e-3,
            ),
            (
                at(1.0, 1.0, 16.0, 0.0, 0.0, 0.0),
                at(0.1, 0.1, 16.0, -0.95, -1.085, 0.001),
                8.11e-3,
            ),
            (
                at(0.125, 0.125, 16.0, 0.0, 0.0, 1.7297067191846256),
                at(
                    0.125,
                    0.125,
                    16.0,
                    -0.28715370679078306,
                    0.009220211552608026,
                    2.8882289458487738,
                ),
                2.73e-4,
            ),
            (
                at(33.333333333333336, 1000.0, 8.0, 0.0, 0.0, 4.71238898038469),
                at(
                    0.001,
                    1.0,
                    1000.0,
                    0.0,
                    -33.33413333,
                    std::f64::consts::FRAC_PI_2,
                ),
                2e-4,
            ),
            (
                at(0.001, 1.0, 1000.0, 0.0, 0.0, 0.0),
                at(0.03, 3.0, 9.0, 0.0, 0.0, 0.0),
                0.031,
            ),
        ];
        for ((a, pa), (b, pb), truth) in cases {
            let Some(found) = flat_pair(&a, &pa, &b, &pb, &Precision::default(), 0.02) else {
                continue;
            };
            let m = found.expect("they overlap");
            let sides = if m.points().len() == 3 { 0.02 } else { 0.0 };
            for q in m.points() {
                let deep = if q.id == 0 {
                    sides - q.separation
                } else {
                    -q.separation
                };
                assert!(
                    q.separation.is_finite() && deep <= 1.15 * truth,
                    "{a:?} {b:?}: a point {deep} deep, the truth {truth}: {:?}",
                    m.points()
                );
            }
            let middle = m.points().iter().find(|q| q.id == 0).expect("a middle");
            let deepest = sides - middle.separation;
            assert!(
                deepest >= 0.95 * truth,
                "{a:?} {b:?}: {deepest} deep, the truth {truth}: {:?}",
                m.points()
            );
        }
    }

    /// Flat pairs answered by their faces agree with the certified path on every decision:
    /// 3,000 pairs of blocks of exponents 8-200 (squares, planks and needles; unequal exponents
    /// are left to the certified path), turned every way, from a quarter of the smaller semi-axis deep to 6% of it
    /// apart along a random direction. Both answers are proven up to half a final cell, so they
    /// differ only where the overlap is thinner than a cell.
    #[test]
    fn flat_pairs_agree_with_the_certified_path() {
        let shapes = [
            Superellipse::new([0.125, 0.125], [16.0, 16.0]).unwrap(),
            Superellipse::new([0.3, 0.1], [8.0, 8.0]).unwrap(),
            Superellipse::new([0.2, 0.15], [200.0, 200.0]).unwrap(),
            Superellipse::new([0.4, 0.05], [12.0, 12.0]).unwrap(),
        ];
        let precision = Precision::default();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut rnd = || rng.random::<f64>();
        let (mut answered, mut overlaps, mut aparts) = (0, 0, 0);
        for _ in 0..3000 {
            let a = shapes[(rnd() * 4.0) as usize % 4];
            let b = shapes[(rnd() * 4.0) as usize % 4];
            let pa = Pose::new(Vec2::new(rnd() - 0.5, rnd() - 0.5), rnd() * 6.3).unwrap();
            // B's centre along a random direction from A's, at the distance where their
            // supports meet (farther than where they touch, unless face to face), moved in by
            // up to a quarter of the smaller semi-axis or out by 6%.
            let dir = rnd() * std::f64::consts::TAU;
            let n = Vec2::new(dir.cos(), dir.sin());
            let tb = rnd() * 6.3;
            let ha = support(a.semi_axes(), a.exponents(), pa.rotation().apply_inverse(n));
            let pb0 = Pose::new(Vec2::ZERO, tb).unwrap();
            let hb = support(
                b.semi_axes(),
                b.exponents(),
                pb0.rotation().apply_inverse(-n),
            );
            let small = a.min_semi_axis().min(b.min_semi_axis());
            let d = ha + hb + (rnd() - 0.8) * 0.3 * small;
            let pb = Pose::new(pa.center() + n * d, tb).unwrap();
            let Some(flat) = flat_pair(&a, &pa, &b, &pb, &precision, 0.02) else {
                continue;
            };
            answered += 1;
            let sound = contact(&a, &pa, &b, &pb, &precision);
            // Both answers hold up to half a final cell: where the overlap is thinner than a
            // cell, one may prove a point inside both and the other prove it that thin.
            let cell = frame(&a, &pa, &b, &pb).map_or(0.0, |(_, _, r)| precision.cell_size(&r));
            // The face's depth: its middle's, less the margin it counts shallower by when the
            // patch has sides.
            let depth = |m: &Manifold| {
                let middle = m.points().iter().find(|q| q.id == 0).expect("a middle");
                let sides = if m.points().len() == 3 { 0.02 } else { 0.0 };
                sides - middle.separation
            };
            match (flat, sound.penetration) {
                (None, None) => aparts += 1,
                (Some(m), Some(p)) => {
                    overlaps += 1;
                    // The certified path's depth is its longer push; the face's is along the
                    // normal, which a push along a corner's diagonal is shorter than.
                    // Within the pushes' reach (the certified path's depth is its longer push,
                    // along a gradient, which from a corner is not along the normal: a
                    // gross error only; `a_corner_pressed_into_a_face_is_as_deep_as_it_is`
                    // holds the depth to a sampled one).
                    let (face, certified) = (depth(&m), p.depth());
                    assert!(
                        face >= 0.5 * certified - 0.01 * small
                            && face <= 4.0 * certified + 0.01 * small,
                        "{a:?} {pa:?} {b:?} {pb:?}: face depth {face}, certified {certified}"
                    );
                }
                (None, Some(p)) => assert!(
                    p.depth() < cell,
                    "{a:?} {pa:?} {b:?} {pb:?}: apart by the faces, overlapping by {} (cell {cell})",
                    p.depth()
                ),
                (Some(m), None) => assert!(
                    depth(&m) < cell,
                    "{a:?} {pa:?} {b:?} {pb:?}: overlapping by the faces ({:?}), apart by the \
                     certified path (cell {cell})",
                    m.points()
                ),
            }
        }
        assert!(
            answered > 2000 && overlaps > 300 && aparts > 1000,
            "{answered} answered, {overlaps} overlapping, {aparts} apart"
        );
    }
}

use super::certified::{self, Certified, WarmStart};
use super::push::separating;
use super::ray::{push_out, push_out_by};
use super::spikes::spike_witness;
use super::{Contact, Penetration};
use crate::geometry::{Aabb, Vec2};
use crate::interval::{ImplicitShape, PlacedSuperellipse};
use crate::shape::{Pose, Superellipse};
use crate::subdivision::{CellSink, Deepest, Precision, deepest_points};

/// The contact of two placed superellipses (paper II, III-A).
///
/// Convex pairs (every exponent at least 1) first try the certified Newton path
/// ([`super::certified`]): a Newton solve for each deepest point, kept only with a proof that it
/// lies inside both shapes and is deepest up to one final quadtree cell, or a proof that the
/// shapes are apart (within a cell). Without a proof, and for stars, the quadtree answers
/// ([`contact_quadtree`]).
///
/// ```
/// use supergrain::{contact::contact, geometry::Vec2, shape::{Pose, Superellipse}, subdivision::Precision};
/// let disk = Superellipse::circle(1.0).unwrap();
/// let a = Pose::new(Vec2::new(0.0, 0.0), 0.0).unwrap();
/// let b = Pose::new(Vec2::new(1.9, 0.0), 0.0).unwrap();
/// let c = contact(&disk, &a, &disk, &b, &Precision::default());
/// let p = c.penetration.expect("the disks overlap by 0.1");
/// assert!(p.a_push.x < 0.0); // A is pushed away from B
/// ```
pub fn contact(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
) -> Contact {
    contact_warm(a, pose_a, b, pose_b, precision, &mut None)
}

/// [`contact`] for a persisting contact: `warm` holds where the last query of this pair found
/// its deepest points (`None` the first time), and is updated. It only starts the Newton
/// solves nearer their answers; every answer is certified afresh, so it is the same contact up
/// to the certificate's tolerance.
pub fn contact_warm(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    warm: &mut Option<WarmStart>,
) -> Contact {
    certified_or_quadtree(a, pose_a, b, pose_b, precision, warm, Answer::Sound)
}

/// [`contact_warm`] as the paper's projection uses it: when the quadtree answers, the paper's
/// answer, from its midpoints alone, with the paper's pushes (no half-axis search of
/// [`super::spikes`], no pushes made to separate by [`super::push`]). Those make every answer
/// of [`contact_warm`] sound, but the projection is not yet fit for them on stars: the mixed
/// preset (Fig. 13, grains every 5 steps) no longer rested within 4,000 steps (at about step
/// 10,000 with both, at 16 steps/s instead of 40; the pushes alone were enough to keep it
/// moving). Issue 19 rebuilds the star contacts. A pair this reports apart may have a spike
/// thinner than a cell reaching into the other.
pub fn contact_warm_midpoints(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    warm: &mut Option<WarmStart>,
) -> Contact {
    certified_or_quadtree(a, pose_a, b, pose_b, precision, warm, Answer::Paper)
}

/// What the quadtree's answer is made of.
#[derive(Clone, Copy, PartialEq)]
enum Answer {
    /// Sound for every shape: the half-axis search ([`super::spikes`]), pushes made to separate
    /// ([`super::push`]), moved points proven over a box of a few ulps.
    Sound,
    /// The paper's, for the projection ([`contact_warm_midpoints`]).
    Paper,
}

impl Answer {
    /// Whether a push from a star's cusp runs along the spike ([`super::ray::push_out_by`]):
    /// the paper's projection moves the grains by its pushes.
    fn along_spikes(self) -> bool {
        self == Answer::Paper
    }
}

fn certified_or_quadtree(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    warm: &mut Option<WarmStart>,
    answer: Answer,
) -> Contact {
    let Some((local_a, local_b, region)) = frame(a, pose_a, b, pose_b) else {
        return Contact {
            penetration: None,
            cells: 0,
        };
    };
    let cell = precision.cell_size(&region);
    match certified::certified_contact(
        &local_a,
        &local_b,
        cell,
        world_slack(pose_a, &region),
        warm,
        answer.along_spikes(),
    ) {
        Some(Certified::Apart) => Contact {
            penetration: None,
            cells: 0,
        },
        Some(Certified::Overlap {
            a1,
            a2,
            a_push,
            b_push,
        }) => {
            // A2 and its push come in B's frame: in A's, to check that they separate.
            let rel = local_b.pose();
            let (a_push, b_push) = match separating(
                &local_a,
                &local_b,
                a1,
                rel.to_world(a2),
                a_push,
                rel.vector_to_world(b_push),
            ) {
                Some((a_push, b_push)) => (
                    pose_a.vector_to_world(a_push),
                    pose_a.vector_to_world(b_push),
                ),
                None => (
                    pose_a.vector_to_world(a_push),
                    pose_b.vector_to_world(b_push),
                ),
            };
            Contact {
                penetration: Some(Penetration {
                    a_deepest: pose_a.to_world(a1),
                    b_deepest: pose_b.to_world(a2),
                    a_push,
                    b_push,
                }),
                cells: 0,
            }
        }
        None => quadtree(
            pose_a,
            &local_a,
            &local_b,
            &region,
            precision,
            &mut (),
            answer,
        ),
    }
}

/// The paper's quadtree alone, for every pair (the reference the certified path is tested
/// against, and `narrow_phase = "quadtree"`).
pub fn contact_quadtree(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
) -> Contact {
    contact_with_cells(a, pose_a, b, pose_b, precision, &mut ())
}

/// [`contact_quadtree`] without the half-axis search, as the paper's projection uses it (see
/// [`contact_warm_midpoints`]).
pub fn contact_quadtree_midpoints(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
) -> Contact {
    cells_and_contact(a, pose_a, b, pose_b, precision, &mut (), Answer::Paper)
}

/// [`contact_quadtree`], handing every classified cell to `sink`. The quadtree runs in A's local
/// frame, where A's own classification is exact, and the cells are given in that frame.
pub fn contact_with_cells<S: CellSink + ?Sized>(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    sink: &mut S,
) -> Contact {
    cells_and_contact(a, pose_a, b, pose_b, precision, sink, Answer::Sound)
}

fn cells_and_contact<S: CellSink + ?Sized>(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    sink: &mut S,
    answer: Answer,
) -> Contact {
    match frame(a, pose_a, b, pose_b) {
        Some((local_a, local_b, region)) => {
            quadtree(pose_a, &local_a, &local_b, &region, precision, sink, answer)
        }
        None => Contact {
            penetration: None,
            cells: 0,
        },
    }
}

/// The pair's final cell and the finest distance double precision resolves at its
/// coordinates, when the cell is the smaller: the stated tolerance (a few final cells) cannot
/// then be held, and a caller should refuse the pair. `None` for every other pair (and for
/// pairs whose bounding boxes are apart).
///
/// The resolution is `16 eps (|c_A| + |c_B| + R_A + R_B)`: the enclosures of the larger shape
/// err by several ulps of its size and of the coordinates. A hostile test found a grain of
/// radius `1e-9` centred on the boundary of one of radius `1e6` answered apart, half its size
/// deep, with a final cell of `1.6e-11` where the coordinates' ulps are `1.2e-10`.
pub fn unresolved(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
) -> Option<(f64, f64)> {
    let (_, _, region) = frame(a, pose_a, b, pose_b)?;
    let cell = precision.cell_size(&region);
    let scale =
        pose_a.center().norm() + pose_b.center().norm() + a.bounding_radius() + b.bounding_radius();
    let resolution = 16.0 * f64::EPSILON * scale;
    (cell < resolution).then_some((cell, resolution))
}

/// Both shapes in A's frame (parry's `pos12`: A axis-aligned at the origin) and the
/// intersection of their boxes, or `None` when the bounding circles or boxes are apart.
// Inlined: the two placed shapes are then built where the caller keeps them, not copied out.
#[inline(always)]
pub(super) fn frame(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
) -> Option<(PlacedSuperellipse, PlacedSuperellipse, Aabb)> {
    // Cheap rejection by bounding circles before any box or interval.
    let reach = a.bounding_radius() + b.bounding_radius();
    let gap = (pose_b.center() - pose_a.center()).norm();
    if gap > reach || gap.is_nan() {
        return None;
    }
    let local_a = PlacedSuperellipse::new(*a, Pose::ORIGIN);
    let local_b = PlacedSuperellipse::new(*b, pose_a.relative(pose_b));
    let region = local_a
        .bounding_box()
        .intersection(&local_b.bounding_box())?;
    Some((local_a, local_b, region))
}

fn quadtree<S: CellSink + ?Sized>(
    pose_a: &Pose,
    local_a: &PlacedSuperellipse,
    local_b: &PlacedSuperellipse,
    region: &Aabb,
    precision: &Precision,
    sink: &mut S,
    answer: Answer,
) -> Contact {
    let found = deepest_points(local_a, local_b, region, precision, true, sink);
    let (mut in_a, mut in_b) = (found.in_a, found.in_b);
    // A few ulps of the world coordinates the points are reported in: a point moved by the
    // searches is proven inside over a box this wide about it ([`spike_witness`]).
    let slack = if answer == Answer::Sound {
        world_slack(pose_a, region)
    } else {
        0.0
    };
    // Spikes thinner than a cell are searched along the half-axes ([`super::spikes`]), which
    // makes "no overlap" mean within four final cells of touching for every shape, and finds
    // a spike's tip that the midpoints passed by (a hostile test: at depth 10 a star's tip
    // was 60 times deeper in `f` than the deepest midpoint reported; the search had been run
    // only when the midpoints proved nothing).
    if answer == Answer::Sound {
        let cell = precision.cell_size(region);
        in_a = deeper(in_a, spike_witness(local_a, local_b, region, cell, slack));
        in_b = deeper(in_b, spike_witness(local_b, local_a, region, cell, slack));
    }
    // A point proven inside both is a point of either shape in the other: it stands in for a
    // deepest point the searches did not find.
    let (in_a, in_b) = match (in_a, in_b) {
        (Some(a1), None) => (Some(a1.point), Some(a1.point)),
        (None, Some(a2)) => (Some(a2.point), Some(a2.point)),
        (a1, a2) => (a1.map(|d| d.point), a2.map(|d| d.point)),
    };
    let penetration = match (in_a, in_b) {
        (Some(a1), Some(a2)) => {
            let a1 = polish(local_a, local_b, a1, slack);
            let a2 = polish(local_b, local_a, a2, slack);
            let (a_push, b_push) = (
                push_out_by(local_b, a1, answer.along_spikes()),
                push_out_by(local_a, a2, answer.along_spikes()),
            );
            let (a_push, b_push) = match answer {
                Answer::Sound => {
                    separating(local_a, local_b, a1, a2, a_push, b_push).unwrap_or((a_push, b_push))
                }
                Answer::Paper => (a_push, b_push),
            };
            Some(Penetration {
                a_deepest: pose_a.to_world(a1),
                b_deepest: pose_a.to_world(a2),
                a_push: pose_a.vector_to_world(a_push),
                b_push: pose_a.vector_to_world(b_push),
            })
        }
        _ => None,
    };
    Contact {
        penetration,
        cells: found.cells,
    }
}

/// A few ulps of the world coordinates a point of the pair's `region` (in A's frame) is
/// reported in: a point proven inside both over a box this wide about it stays inside when
/// moved to the world ([`spike_witness`]).
pub(super) fn world_slack(pose_a: &Pose, region: &Aabb) -> f64 {
    let scale = pose_a.center().norm() + region.min.norm().max(region.max.norm());
    8.0 * f64::EPSILON * scale
}

/// The deeper of two candidates for a deepest point (the smaller bound of the other's `f`).
pub(super) fn deeper(a: Option<Deepest>, b: Option<Deepest>) -> Option<Deepest> {
    match (a, b) {
        (Some(a), Some(b)) => Some(if b.other_value < a.other_value { b } else { a }),
        (a, b) => a.or(b),
    }
}

/// Unless `own` holds `other`'s centre, the deepest point of `own` in `other` lies on `own`'s
/// boundary (`f_other` grows along every ray from `other`'s centre, see
/// [`crate::subdivision`]), while the quadtree's is a cell midpoint up to half a cell inside. Moving it along `grad f_own` to the boundary removes that
/// error from the penetration estimate, which otherwise makes resting grains jitter by about a
/// cell per step. Kept only when the moved point is still proven inside `other`, and deeper.
///
/// `slack`: the moved point is proven inside over a box of that half-width about it, so that
/// it stays inside in world coordinates (a point moved to a star's spike tip, `1e-9` short
/// of it, came out `3e-9` outside after rounding to world coordinates, as for the half-axis
/// witnesses).
pub(super) fn polish(
    own: &PlacedSuperellipse,
    other: &PlacedSuperellipse,
    point: Vec2,
    slack: f64,
) -> Vec2 {
    if own.enclose_point(other.pose().center()).lo <= 0.0 {
        // `own` may hold `other`'s centre, which is then the deepest point: not on the boundary.
        return point;
    }
    let on_boundary = point + push_out(own, point);
    // A hair inside, so that the proof of being inside `own` survives rounding.
    let inside = point + (on_boundary - point) * (1.0 - 1e-9);
    // And only when it is at least as deep: on a thin shape the gradient may lead to the far
    // side, away from `other`'s centre.
    let proven_in = |shape: &PlacedSuperellipse| {
        if slack == 0.0 {
            shape.enclose_point(inside).hi < 0.0
        } else {
            let around = Aabb::new(
                inside - Vec2::new(slack, slack),
                inside + Vec2::new(slack, slack),
            );
            shape.enclose(&around).hi < 0.0
        }
    };
    if proven_in(own) && proven_in(other) && other.value(inside) <= other.value(point) {
        inside
    } else {
        point
    }
}

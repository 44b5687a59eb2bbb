//! Every overlap region of a pair (issue 19): two stars, or a star and a face, can touch in
//! several places at once, and [`super::contact`] reports only the deepest.
//!
//! The regions come from a cover of the overlap: the pair's box is subdivided, as the
//! quadtree does, but without its best-first pruning, and every cell not proven outside one of
//! the shapes is kept (a cell proven inside both is kept whole). Every point inside both shapes
//! lies in a kept cell, so each connected piece of the overlap lies in one connected group of
//! kept cells (cells touching at an edge or a corner). A group is a *proven* region when some
//! cell midpoint in it is proven inside both by interval arithmetic; its deepest points are the
//! proven midpoints deepest in the other shape, moved to the boundary where that stays proven
//! ([`polish`]). A group with no proven midpoint is touching within a final cell of the
//! cover, and is not reported. Two regions nearer each other than a final cell may come out
//! as one.
//!
//! The cover costs a full subdivision (all the boundary cells of the overlap, about
//! `2^depth` per region), so it answers `supergrain contact`, not the solver: the contact
//! solver's points per region come from [`super::manifold`]'s sampling of a star's boundary.

use super::Penetration;
use super::push::separating;
use super::ray::push_out;
use super::spikes::spike_witness;
use super::superellipse_superellipse::{deeper, frame, polish, world_slack};
use crate::geometry::{Aabb, Vec2};
use crate::interval::{ImplicitShape, PlacedSuperellipse};
use crate::shape::{Pose, Superellipse};
use crate::subdivision::{Deepest, Precision, splits};

/// The cover is never finer than this many levels: regions nearer each other than
/// `1/2^COVER_DEPTH` of the pair's box are counted as one (a depth of 20 would otherwise
/// keep millions of cells).
pub const COVER_DEPTH: u32 = 10;

/// A kept cell of the cover, with its midpoint's proof when it has one.
#[derive(Clone, Copy)]
struct Leaf {
    cell: Aabb,
    /// Upper bounds of `f_A` and `f_B` at the midpoint, when both are negative.
    proven: Option<(f64, f64)>,
}

/// Every proven overlap region of the pair, `first` (the pair's answer from
/// [`super::contact`] or [`super::contact_quadtree`]) first, the others deepest first. The
/// pushes of the other regions are along the gradients at their own deepest points (each
/// region its own normal), made to separate as `first`'s are. Empty when `first` is `None`.
pub fn overlap_regions(
    a: &Superellipse,
    pose_a: &Pose,
    b: &Superellipse,
    pose_b: &Pose,
    precision: &Precision,
    first: Option<&Penetration>,
) -> Vec<Penetration> {
    let Some(first) = first else {
        return Vec::new();
    };
    let Some((local_a, local_b, region)) = frame(a, pose_a, b, pose_b) else {
        return vec![*first];
    };
    let cover_precision = Precision::new(precision.depth().min(COVER_DEPTH), precision.eps())
        .expect("a valid precision stays valid shallower");
    let leaves = cover(&local_a, &local_b, &region, &cover_precision);
    let groups = components(&leaves);
    let slack = world_slack(pose_a, &region);
    let cell = cover_precision.cell_size(&region);

    // The group holding `first`'s deepest point of A (in A's frame), else the nearest.
    let at = pose_a.to_local(first.a_deepest);
    let distance = |g: &[usize]| {
        g.iter()
            .map(|&k| box_distance(&leaves[k].cell, at))
            .fold(f64::INFINITY, f64::min)
    };
    let first_group =
        (0..groups.len()).min_by(|&i, &j| distance(&groups[i]).total_cmp(&distance(&groups[j])));

    let mut others: Vec<(f64, Penetration)> = Vec::new();
    for (g, members) in groups.iter().enumerate() {
        if Some(g) == first_group {
            continue;
        }
        // The proven midpoints deepest in B (A1) and in A (A2).
        let mut a1: Option<Deepest> = None;
        let mut a2: Option<Deepest> = None;
        let mut bounds: Option<Aabb> = None;
        for &k in members {
            let leaf = &leaves[k];
            bounds = Some(bounds.map_or(leaf.cell, |b| b.union(&leaf.cell)));
            let Some((fa, fb)) = leaf.proven else {
                continue;
            };
            let point = leaf.cell.center();
            a1 = deeper(
                a1,
                Some(Deepest {
                    point,
                    other_value: fb,
                }),
            );
            a2 = deeper(
                a2,
                Some(Deepest {
                    point,
                    other_value: fa,
                }),
            );
        }
        // A spike thinner than a cell holds no proven midpoint: its half-axis, searched
        // within the group ([`spike_witness`]), may.
        let bounds = bounds.expect("a group has a leaf");
        let within = |d: Option<Deepest>| {
            d.filter(|d| {
                members
                    .iter()
                    .any(|&k| box_distance(&leaves[k].cell, d.point) == 0.0)
            })
        };
        a1 = deeper(
            a1,
            within(spike_witness(&local_a, &local_b, &bounds, cell, slack)),
        );
        a2 = deeper(
            a2,
            within(spike_witness(&local_b, &local_a, &bounds, cell, slack)),
        );
        // A point inside both stands in for the deepest point not found.
        let (a1, a2) = match (a1, a2) {
            (Some(a1), Some(a2)) => (a1.point, a2.point),
            (Some(d), None) | (None, Some(d)) => (d.point, d.point),
            (None, None) => continue,
        };
        let a1 = polish(&local_a, &local_b, a1, slack);
        let a2 = polish(&local_b, &local_a, a2, slack);
        let (a_push, b_push) = (push_out(&local_b, a1), push_out(&local_a, a2));
        let (a_push, b_push) =
            separating(&local_a, &local_b, a1, a2, a_push, b_push).unwrap_or((a_push, b_push));
        let p = Penetration {
            a_deepest: pose_a.to_world(a1),
            b_deepest: pose_a.to_world(a2),
            a_push: pose_a.vector_to_world(a_push),
            b_push: pose_a.vector_to_world(b_push),
        };
        others.push((-p.depth(), p));
    }
    others.sort_by(|x, y| x.0.total_cmp(&y.0));
    std::iter::once(*first)
        .chain(others.into_iter().map(|(_, p)| p))
        .collect()
}

/// The distance from `p` to a box (0 inside).
fn box_distance(cell: &Aabb, p: Vec2) -> f64 {
    let dx = (cell.min.x - p.x).max(p.x - cell.max.x).max(0.0);
    let dy = (cell.min.y - p.y).max(p.y - cell.max.y).max(0.0);
    dx.hypot(dy)
}

/// The cells of `region` not proven outside either shape, split to the final precision
/// except where proven inside both.
fn cover(
    a: &PlacedSuperellipse,
    b: &PlacedSuperellipse,
    region: &Aabb,
    precision: &Precision,
) -> Vec<Leaf> {
    let tol = precision.cell_size(region) * (1.0 + 1e-9);
    let mut leaves = Vec::new();
    let mut stack = vec![*region];
    while let Some(cell) = stack.pop() {
        let (fa, fb) = (a.enclose(&cell), b.enclose(&cell));
        if fa.lo > 0.0 || fb.lo > 0.0 {
            continue;
        }
        let (split_x, split_y) = splits(&cell, tol);
        let inside_both = fa.hi < 0.0 && fb.hi < 0.0;
        if inside_both || !(split_x || split_y) {
            let mid = cell.center();
            let (pa, pb) = (a.enclose_point(mid), b.enclose_point(mid));
            let proven = (pa.hi < 0.0 && pb.hi < 0.0).then_some((pa.hi, pb.hi));
            leaves.push(Leaf { cell, proven });
            continue;
        }
        let mid = cell.center();
        let xs: &[(f64, f64)] = if split_x {
            &[(cell.min.x, mid.x), (mid.x, cell.max.x)]
        } else {
            &[(cell.min.x, cell.max.x)]
        };
        let ys: &[(f64, f64)] = if split_y {
            &[(cell.min.y, mid.y), (mid.y, cell.max.y)]
        } else {
            &[(cell.min.y, cell.max.y)]
        };
        for &(x0, x1) in xs {
            for &(y0, y1) in ys {
                stack.push(Aabb::new(Vec2::new(x0, y0), Vec2::new(x1, y1)));
            }
        }
    }
    leaves
}

/// The groups of leaves whose closed boxes touch (at an edge or a corner), each as the
/// indices of its leaves, in the order of their first leaf. A sweep along x over the boxes
/// sorted by their left sides, joined in a union-find.
fn components(leaves: &[Leaf]) -> Vec<Vec<usize>> {
    let n = leaves.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| leaves[i].cell.min.x.total_cmp(&leaves[j].cell.min.x));
    for (pos, &i) in order.iter().enumerate() {
        let ci = leaves[i].cell;
        for &j in &order[pos + 1..] {
            let cj = leaves[j].cell;
            if cj.min.x > ci.max.x {
                break;
            }
            if cj.min.y <= ci.max.y && ci.min.y <= cj.max.y {
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                if ri != rj {
                    parent[ri.max(rj)] = ri.min(rj);
                }
            }
        }
    }
    let mut index_of_root = vec![usize::MAX; n];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for k in 0..n {
        let r = root(&mut parent, k);
        if index_of_root[r] == usize::MAX {
            index_of_root[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[index_of_root[r]].push(k);
    }
    groups
}

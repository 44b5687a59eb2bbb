//! Pairs kept from step to step, for the soft step: each body's fat box (its box grown by a
//! tenth of its size) and, per body, the bodies whose fat boxes meet it. A step's pairs are
//! then the kept neighbours whose boxes meet, one test each; only a body whose box has left its
//! fat box is looked up again (in a settled heap, a few a step), as in Box2D's broad phase,
//! which moves a proxy in its tree only when its box leaves the fat one. Before, the grid was
//! rebuilt and searched for every body at every step: a tenth of the settled mixed heap's step.
//!
//! The pairs are exactly those [`super::BroadPhase::later_candidates`] gives for the boxes,
//! in the same order: a box lies in its fat box, so boxes that meet have fat boxes that meet,
//! and the neighbours are kept in increasing order.

use super::grid::inside;
use super::{Any, BroadPhase, Kind};
use crate::geometry::Aabb;
use rayon::prelude::*;

/// The fat box's margin, as a fraction of the box's larger side.
const MARGIN: f64 = 0.1;

/// Bodies a task of the full search takes.
const CHUNK: usize = 1024;

/// See the module docs.
#[derive(Clone, Debug, Default)]
pub struct Near {
    /// The broad phase the fat boxes are filed in, and its kind.
    broad: Option<(Kind, Any)>,
    fat: Vec<Aabb>,
    /// Each body's neighbours (fat boxes that meet), increasing.
    lists: Vec<Vec<u32>>,
    escaped: Vec<usize>,
    scratch: Vec<usize>,
}

/// The fat box: `b` grown by a tenth of its larger side, or `b` itself where growing it does
/// not hold it (a box at infinity, whose margin is infinite or NaN: found by a review).
fn fatten(b: &Aabb) -> Aabb {
    let fat = b.grown(MARGIN * b.width().max(b.height()));
    if inside(b, &fat) { fat } else { *b }
}

impl Near {
    /// The fat boxes and neighbours for this step's `boxes`, looked up in a broad phase of
    /// `kind`: afresh for every body when the bodies or the kind changed or many boxes left
    /// their fat ones (a pour), else for those that left only.
    pub fn refresh(&mut self, boxes: &[Aabb], kind: Kind) {
        let n = boxes.len();
        let same = matches!(&self.broad, Some((k, _)) if *k == kind) && self.fat.len() == n;
        if same {
            self.escaped.clear();
            self.escaped
                .extend((0..n).filter(|&i| !inside(&boxes[i], &self.fat[i])));
            // Each lookup alone takes about twice a body's share of a search of all of them.
            if self.escaped.len() * 4 <= n {
                self.update(boxes);
                return;
            }
        }
        self.rebuild(boxes, kind);
    }

    /// Body `i`'s neighbours after it (`j > i`), increasing.
    pub fn later(&self, i: usize) -> &[u32] {
        let list = &self.lists[i];
        &list[list.partition_point(|&j| j as usize <= i)..]
    }

    fn rebuild(&mut self, boxes: &[Aabb], kind: Kind) {
        self.fat.clear();
        self.fat.extend(boxes.iter().map(fatten));
        let broad = match &mut self.broad {
            Some((k, b)) if *k == kind => b,
            slot => &mut slot.insert((kind, Any::new(kind))).1,
        };
        broad.rebuild(&self.fat);
        let (fat, broad) = (&self.fat, &*broad);
        // Each body's later neighbours on all cores, then both ways in the bodies' order: a
        // body's earlier neighbours come first, in order, then its later ones.
        let later: Vec<Vec<(u32, u32)>> = (0..boxes.len().div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let (mut out, mut found) = (Vec::new(), Vec::new());
                for i in c * CHUNK..((c + 1) * CHUNK).min(boxes.len()) {
                    found.clear();
                    broad.later_candidates(i, fat, &mut found);
                    out.extend(found.iter().map(|&j| (i as u32, j as u32)));
                }
                out
            })
            .collect();
        self.lists.resize_with(boxes.len(), Vec::new);
        for list in &mut self.lists {
            list.clear();
        }
        for &(i, j) in later.iter().flatten() {
            self.lists[i as usize].push(j);
            self.lists[j as usize].push(i);
        }
    }

    /// The escaped bodies' fat boxes afresh, and their neighbours looked up again.
    fn update(&mut self, boxes: &[Aabb]) {
        let Some((_, broad)) = &mut self.broad else {
            return;
        };
        for &k in &self.escaped {
            self.fat[k] = fatten(&boxes[k]);
            broad.update(k, &self.fat[k]);
        }
        for &k in &self.escaped {
            let mut list = std::mem::take(&mut self.lists[k]);
            for &j in &list {
                let theirs = &mut self.lists[j as usize];
                if let Ok(at) = theirs.binary_search(&(k as u32)) {
                    theirs.remove(at);
                }
            }
            self.scratch.clear();
            broad.candidates(k, &self.fat, &mut self.scratch);
            for &j in &self.scratch {
                let theirs = &mut self.lists[j];
                if let Err(at) = theirs.binary_search(&(k as u32)) {
                    theirs.insert(at, k as u32);
                }
            }
            list.clear();
            list.extend(self.scratch.iter().map(|&j| j as u32));
            self.lists[k] = list;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::broad_phase::AllPairs;
    use crate::geometry::Vec2;
    use proptest::prelude::*;

    /// The pairs the soft step wants: `j > i` whose boxes meet, by brute force.
    fn brute(boxes: &[Aabb]) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for i in 0..boxes.len() {
            let mut found = Vec::new();
            AllPairs.later_candidates(i, boxes, &mut found);
            out.extend(found.into_iter().map(|j| (i, j)));
        }
        out
    }

    fn kept(near: &Near, boxes: &[Aabb]) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for i in 0..boxes.len() {
            for &j in near.later(i) {
                if boxes[i].intersects(&boxes[j as usize]) {
                    out.push((i, j as usize));
                }
            }
        }
        out
    }

    proptest! {
        /// Over steps of small moves (most boxes stay in their fat ones, a few leave: the
        /// lookups of those alone), large ones (many leave: the search afresh), a body
        /// flung far, a NaN box and two boxes at one point at infinity, the kept pairs are every step exactly the brute force's,
        /// in its order, through the grid and through all pairs.
        #[test]
        fn the_kept_pairs_are_the_boxes_that_meet(
            start in prop::collection::vec((0.0f64..10.0, 0.0f64..10.0, 0.1f64..0.8), 2..60),
            moves in prop::collection::vec(
                prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0), 60), 1..8),
            scale in prop::sample::select(vec![0.002, 0.05, 0.5]),
            flung in 0usize..60,
            all_pairs in any::<bool>(),
        ) {
            let kind = if all_pairs { Kind::AllPairs } else { Kind::Grid };
            let mut centres: Vec<Vec2> = start.iter().map(|&(x, y, _)| Vec2::new(x, y)).collect();
            let boxes_at = |centres: &[Vec2]| -> Vec<Aabb> {
                centres
                    .iter()
                    .zip(&start)
                    .map(|(c, &(_, _, r))| Aabb::new(*c - Vec2::new(r, r), *c + Vec2::new(r, r)))
                    .collect()
            };
            let mut near = Near::default();
            for (step, m) in moves.iter().enumerate() {
                for (c, d) in centres.iter_mut().zip(m) {
                    *c += Vec2::new(d.0, d.1) * scale;
                }
                let mut boxes = boxes_at(&centres);
                let n = boxes.len();
                if step == 2 {
                    boxes[flung % n] = Aabb::point(Vec2::new(1e6, -1e6));
                }
                if step == 3 {
                    boxes[(flung + 1) % n] = Aabb::point(Vec2::new(f64::NAN, 0.0));
                }
                if step == 4 {
                    // Two boxes at the same point at infinity meet.
                    let far = Aabb::point(Vec2::new(f64::INFINITY, f64::INFINITY));
                    boxes[flung % n] = far;
                    boxes[(flung + 1) % n] = far;
                }
                near.refresh(&boxes, kind);
                prop_assert_eq!(kept(&near, &boxes), brute(&boxes), "step {}", step);
            }
        }
    }
}

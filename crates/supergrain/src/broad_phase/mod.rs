//! Broad phase: which pairs are worth a narrow-phase test (paper III-A, Figs. 4-5).
//!
//! The paper tests every pair whose bounding boxes overlap and leaves a real broad phase for
//! later; [`AllPairs`] is that, kept as the reference, and [`Grid`] finds the same pairs in time
//! linear in the number of grains. [`Near`] keeps the pairs of fat boxes from step to step
//! for the soft step, looking up again only the bodies that left them.

mod grid;
mod near;

pub use grid::Grid;
pub use near::Near;

use crate::geometry::Aabb;

/// Finds the bodies whose boxes may overlap a given body's box.
pub trait BroadPhase {
    /// Called once per step, before any query, with every body's box.
    fn rebuild(&mut self, boxes: &[Aabb]);

    /// Appends to `out` the indices `j != i` whose current box overlaps `boxes[i]`, in
    /// increasing order (the order fixes the order of corrections, so results are reproducible).
    fn candidates(&self, i: usize, boxes: &[Aabb], out: &mut Vec<usize>);

    /// [`Self::candidates`] after `i` only (`j > i`): each pair once, as the soft step asks.
    fn later_candidates(&self, i: usize, boxes: &[Aabb], out: &mut Vec<usize>) {
        let start = out.len();
        self.candidates(i, boxes, out);
        let later = out[start..].partition_point(|&j| j < i);
        out.drain(start..start + later);
    }

    /// Body `i`'s box changed within a step (it is `boxes[i]` at the next query).
    fn update(&mut self, _i: usize, _b: &Aabb) {}
}

/// Which broad phase a world uses; both give the same pairs in the same order, so the same
/// results bit for bit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    /// [`Grid`].
    #[default]
    Grid,
    /// [`AllPairs`], the paper's.
    AllPairs,
}

/// A broad phase of either kind.
#[derive(Clone, Debug)]
pub enum Any {
    Grid(Grid),
    AllPairs(AllPairs),
}

impl Any {
    pub fn new(kind: Kind) -> Self {
        match kind {
            Kind::Grid => Any::Grid(Grid::new()),
            Kind::AllPairs => Any::AllPairs(AllPairs),
        }
    }
}

impl BroadPhase for Any {
    fn rebuild(&mut self, boxes: &[Aabb]) {
        match self {
            Any::Grid(g) => g.rebuild(boxes),
            Any::AllPairs(a) => a.rebuild(boxes),
        }
    }

    fn candidates(&self, i: usize, boxes: &[Aabb], out: &mut Vec<usize>) {
        match self {
            Any::Grid(g) => g.candidates(i, boxes, out),
            Any::AllPairs(a) => a.candidates(i, boxes, out),
        }
    }

    fn later_candidates(&self, i: usize, boxes: &[Aabb], out: &mut Vec<usize>) {
        match self {
            Any::Grid(g) => g.later_candidates(i, boxes, out),
            Any::AllPairs(a) => a.later_candidates(i, boxes, out),
        }
    }

    fn update(&mut self, i: usize, b: &Aabb) {
        match self {
            Any::Grid(g) => g.update(i, b),
            Any::AllPairs(a) => a.update(i, b),
        }
    }
}

/// Every other body, filtered by its bounding box (the paper's method).
#[derive(Clone, Debug, Default)]
pub struct AllPairs;

impl BroadPhase for AllPairs {
    fn rebuild(&mut self, _boxes: &[Aabb]) {}

    fn candidates(&self, i: usize, boxes: &[Aabb], out: &mut Vec<usize>) {
        let bi = boxes[i];
        out.extend((0..boxes.len()).filter(|&j| j != i && bi.intersects(&boxes[j])));
    }
}

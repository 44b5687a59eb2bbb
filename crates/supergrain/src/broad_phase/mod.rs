//! Broad phase: which pairs are worth a narrow-phase test (paper III-A, Figs. 4-5).
//!
//! The paper tests every pair whose bounding boxes overlap and leaves a real broad phase for
//! later; [`AllPairs`] is that, and the [`BroadPhase`] trait is the seam a grid or
//! sweep-and-prune plugs into.

use crate::geometry::Aabb;

/// Finds the bodies whose boxes may overlap a given body's box.
pub trait BroadPhase {
    /// Called once per step, before any query, with every body's box.
    fn rebuild(&mut self, boxes: &[Aabb]);

    /// Appends to `out` the indices `j != i` whose current box overlaps `boxes[i]`, in
    /// increasing order (the order fixes the order of corrections, so results are reproducible).
    fn candidates(&self, i: usize, boxes: &[Aabb], out: &mut Vec<usize>);
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

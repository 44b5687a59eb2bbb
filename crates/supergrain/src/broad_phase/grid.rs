//! A uniform grid of fat boxes.
//!
//! Written here rather than taken from a crate: the solver needs the exact candidate list of
//! [`super::AllPairs`] (every body whose *current* box overlaps, in increasing order), so that
//! both give bit-identical runs, while boxes change many times within a step. Each body is
//! filed under every cell its fat box (its box grown by a margin, as Box2D's fat AABBs) overlaps;
//! it is refiled only when its box leaves the fat one. Cells are as large as the largest box, so
//! a body sits in at most four.

use super::BroadPhase;
use crate::geometry::{Aabb, Vec2};

/// The fat box margin, as a fraction of the cell size.
const MARGIN: f64 = 0.1;

/// The most cells per body (see `rebuild`).
const CELLS_PER_BODY: usize = 4;

/// The most cells along one side; beyond that, cells grow (a grain flung far away would
/// otherwise make the grid huge).
const MAX_CELLS: usize = 4096;

/// See the module docs.
#[derive(Clone, Debug, Default)]
pub struct Grid {
    origin: Vec2,
    cell: f64,
    nx: usize,
    ny: usize,
    /// Body indices per cell, row by row.
    cells: Vec<Vec<u32>>,
    /// Each body's fat box.
    fat: Vec<Aabb>,
    /// Whether every cell lists its bodies in increasing order (as `rebuild` files them,
    /// until `update` refiles one).
    sorted: bool,
}

impl Grid {
    pub fn new() -> Self {
        Grid::default()
    }

    /// The cell range `[x0, x1] x [y0, y1]` a box overlaps, clamped to the grid (a box beyond
    /// an edge counts as in the edge cells, for filing and queries alike, which keeps both
    /// conservative).
    fn range(&self, b: &Aabb) -> (usize, usize, usize, usize) {
        let index = |v: f64, o: f64, n: usize| -> usize {
            let k = ((v - o) / self.cell).floor();
            if k.is_nan() || k < 0.0 {
                0
            } else {
                (k as usize).min(n - 1)
            }
        };
        (
            index(b.min.x, self.origin.x, self.nx),
            index(b.min.y, self.origin.y, self.ny),
            index(b.max.x, self.origin.x, self.nx),
            index(b.max.y, self.origin.y, self.ny),
        )
    }

    fn fatten(&self, b: &Aabb) -> Aabb {
        b.grown(MARGIN * self.cell)
    }

    fn file(&mut self, i: usize) {
        let (x0, y0, x1, y1) = self.range(&self.fat[i]);
        for y in y0..=y1 {
            for x in x0..=x1 {
                self.cells[y * self.nx + x].push(i as u32);
            }
        }
    }

    fn unfile(&mut self, i: usize) {
        let (x0, y0, x1, y1) = self.range(&self.fat[i]);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let cell = &mut self.cells[y * self.nx + x];
                if let Some(k) = cell.iter().position(|&j| j as usize == i) {
                    cell.swap_remove(k);
                }
            }
        }
    }
}

/// Whether `inner` lies in `outer` (false for a NaN box).
pub(super) fn inside(inner: &Aabb, outer: &Aabb) -> bool {
    inner.min.x >= outer.min.x
        && inner.min.y >= outer.min.y
        && inner.max.x <= outer.max.x
        && inner.max.y <= outer.max.y
}

impl BroadPhase for Grid {
    fn rebuild(&mut self, boxes: &[Aabb]) {
        for c in &mut self.cells {
            c.clear();
        }
        self.fat.clear();
        let finite = || {
            boxes
                .iter()
                .filter(|b| b.min.is_finite() && b.max.is_finite())
        };
        let Some(first) = finite().next() else {
            // Nothing finite to file: one cell holds everything.
            self.origin = Vec2::ZERO;
            self.cell = 1.0;
            (self.nx, self.ny) = (1, 1);
            self.cells.resize(1, Vec::new());
            self.fat.extend(boxes.iter().copied());
            for i in 0..boxes.len() {
                self.cells[0].push(i as u32);
            }
            self.sorted = true;
            return;
        };
        let (mut lo, mut hi, mut largest) = (first.min, first.max, 0.0f64);
        for b in finite() {
            lo = Vec2::new(lo.x.min(b.min.x), lo.y.min(b.min.y));
            hi = Vec2::new(hi.x.max(b.max.x), hi.y.max(b.max.y));
            largest = largest.max(b.width()).max(b.height());
        }
        let span = (hi.x - lo.x).max(hi.y - lo.y);
        self.cell = (largest * (1.0 + 2.0 * MARGIN))
            .max(span / MAX_CELLS as f64)
            .max(f64::MIN_POSITIVE);
        self.origin = lo;
        let cells_along = |extent: f64, cell: f64| {
            ((extent / cell).floor() as usize)
                .saturating_add(1)
                .min(MAX_CELLS)
        };
        // At most CELLS_PER_BODY cells per body: tiny grains spread over a large box would
        // otherwise make millions of empty cells (5 grains of radius 1e-6 in an 8 x 10 box:
        // 4096 x 4096 cells, 150 MB, cleared at every rebuild). Larger cells change no
        // candidate list, which is exact.
        let most = CELLS_PER_BODY.saturating_mul(boxes.len()).max(1);
        loop {
            self.nx = cells_along(hi.x - lo.x, self.cell);
            self.ny = cells_along(hi.y - lo.y, self.cell);
            if self.nx.saturating_mul(self.ny) <= most {
                break;
            }
            self.cell *= 2.0;
        }
        self.cells.truncate(self.nx * self.ny);
        self.cells.shrink_to(4 * self.nx * self.ny);
        self.cells.resize(self.nx * self.ny, Vec::new());
        for (i, b) in boxes.iter().enumerate() {
            let fat = self.fatten(b);
            self.fat.push(fat);
            self.file(i);
        }
        self.sorted = true;
    }

    fn update(&mut self, i: usize, b: &Aabb) {
        if !inside(b, &self.fat[i]) {
            self.unfile(i);
            self.fat[i] = self.fatten(b);
            self.file(i);
            self.sorted = false;
        }
    }

    fn candidates(&self, i: usize, boxes: &[Aabb], out: &mut Vec<usize>) {
        self.gather(i, boxes, out, false);
    }

    /// Half the boxes tested and sorted, where the soft step asked for all and kept the later
    /// ones (the pairs' search was 5% of a settled heap's step).
    fn later_candidates(&self, i: usize, boxes: &[Aabb], out: &mut Vec<usize>) {
        self.gather(i, boxes, out, true);
    }
}

impl Grid {
    /// The bodies `j != i` (`j > i` if `later`) whose box overlaps body `i`'s, appended in
    /// increasing order, each once. Where the cells are sorted, the later ones are looked for
    /// from `i` on, found by bisection: the scan of the bodies before `i` and its unpredictable
    /// branch were most of the soft step's search for pairs.
    fn gather(&self, i: usize, boxes: &[Aabb], out: &mut Vec<usize>, later: bool) {
        let q = boxes[i];
        let start = out.len();
        let (x0, y0, x1, y1) = self.range(&q);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let cell = &self.cells[y * self.nx + x];
                let from = if later && self.sorted {
                    cell.partition_point(|&j| j as usize <= i)
                } else {
                    0
                };
                for &j in &cell[from..] {
                    let j = j as usize;
                    let wanted = if later { j > i } else { j != i };
                    if wanted && q.intersects(&boxes[j]) {
                        out.push(j);
                    }
                }
            }
        }
        // A body filed in several cells is met in each.
        out[start..].sort_unstable();
        let mut kept = start;
        for k in start..out.len() {
            if k == start || out[k] != out[kept - 1] {
                out[kept] = out[k];
                kept += 1;
            }
        }
        out.truncate(kept);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Five grains of radius 1e-6 spread over an 8 x 10 box (issue 17: 4096 x 4096 cells,
    /// 150 MB, 0.04 s a step): the cells stay a few per grain, and the candidates are still
    /// exactly the overlapping boxes.
    #[test]
    fn tiny_grains_in_a_large_box_make_few_cells() {
        let r = 1e-6;
        let at = |x: f64, y: f64| Aabb::new(Vec2::new(x - r, y - r), Vec2::new(x + r, y + r));
        let boxes = [
            at(-4.0, 0.0),
            at(4.0, 10.0),
            at(0.0, 5.0),
            at(0.0, 5.0 + r),
            at(3.0, 1.0),
        ];
        let mut grid = Grid::new();
        grid.rebuild(&boxes);
        assert!(
            grid.cells.len() <= CELLS_PER_BODY * boxes.len(),
            "{} cells for {} grains",
            grid.cells.len(),
            boxes.len()
        );
        let mut near = Vec::new();
        grid.candidates(2, &boxes, &mut near);
        assert_eq!(near, vec![3]);
        near.clear();
        grid.candidates(0, &boxes, &mut near);
        assert!(near.is_empty());
    }
}

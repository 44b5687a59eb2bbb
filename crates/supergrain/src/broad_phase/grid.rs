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
        let m = Vec2::new(MARGIN * self.cell, MARGIN * self.cell);
        Aabb::new(b.min - m, b.max + m)
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

fn inside(inner: &Aabb, outer: &Aabb) -> bool {
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
        self.nx = (((hi.x - lo.x) / self.cell).floor() as usize + 1).min(MAX_CELLS);
        self.ny = (((hi.y - lo.y) / self.cell).floor() as usize + 1).min(MAX_CELLS);
        self.cells.resize(self.nx * self.ny, Vec::new());
        for (i, b) in boxes.iter().enumerate() {
            let fat = self.fatten(b);
            self.fat.push(fat);
            self.file(i);
        }
    }

    fn update(&mut self, i: usize, b: &Aabb) {
        if !inside(b, &self.fat[i]) {
            self.unfile(i);
            self.fat[i] = self.fatten(b);
            self.file(i);
        }
    }

    fn candidates(&self, i: usize, boxes: &[Aabb], out: &mut Vec<usize>) {
        let q = boxes[i];
        let start = out.len();
        let (x0, y0, x1, y1) = self.range(&q);
        for y in y0..=y1 {
            for x in x0..=x1 {
                for &j in &self.cells[y * self.nx + x] {
                    let j = j as usize;
                    if j != i && q.intersects(&boxes[j]) {
                        out.push(j);
                    }
                }
            }
        }
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

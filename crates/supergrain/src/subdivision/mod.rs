//! The quadtree narrow phase (paper II, SPEC §3), generic over any [`ImplicitShape`].
//!
//! Cells of the region (the intersection of the two bounding boxes) are classified against
//! each shape from interval enclosures: outside either shape, a cell is discarded; otherwise it
//! is refined, splitting only the sides longer than the final cell size ("rectangular
//! subdivision", paper Fig. 9), until the precision is reached.
//!
//! Two additions keep the answer the paper's while doing much less work:
//! - **Certified witnesses.** A cell midpoint counts as a point of the collision only when the
//!   interval enclosure *at that point* proves it inside both shapes. `overlap` is therefore a
//!   proof, and "no overlap" means every cell was proven outside one shape or, at the final
//!   precision, no midpoint was proven inside both: the shapes are within one cell of touching.
//! - **Branch and bound** on the deepest points (paper III-A): `A1`, the point of shape A most
//!   interior to B, minimises `f_B` over A; a cell whose enclosure of `f_B` cannot beat the best
//!   midpoint found so far cannot hold a better one and is not refined (likewise for `A2`).
//!   `A1` is therefore the deepest of the final-level midpoints, as in the paper, without
//!   visiting them all.
//! - **Only boundaries hold deepest points.** `f_B` increases strictly along every ray from B's
//!   centre, so `min f_B` over A lies on A's boundary, or at B's centre when A holds it: the
//!   `A1` search does not refine cells strictly inside A that do not hold B's centre (the
//!   interior of the lens of overlap), though their midpoints still count, as the paper counts
//!   those of cells inside both; likewise for `A2`. Shapes declare this through
//!   [`ImplicitShape::minima`].
//!   (Pruning with a tolerance of one final cell's change of `f` was tried: 1.6x fewer cells, but
//!   on thin shapes the change of `f` varies so much along the boundary that the deepest point
//!   came out several cells off; the reference tests caught it.)

use crate::geometry::{Aabb, Vec2};
use crate::interval::{ImplicitShape, Interval, Minima};

/// The largest quadtree depth accepted; the traversal stack is sized from it.
///
/// 16 (issue 17): the final cell is then 1/65,536 of the pair's box, far finer than any
/// grain simulation resolves (the paper uses 7), while the quadtree's work doubles with each
/// level for a pair within a cell of touching: at 16 a step of a 300-grain heap already takes
/// seconds, and at the 32 once accepted a step never finished.
pub const MAX_DEPTH: u32 = 16;

/// How finely the quadtree refines: a maximum depth and a tolerance (SPEC §3).
///
/// The final cell size of a region is `max(eps, L / 2^depth)`, `L` the longest side of the
/// region; a cell side is split while it is longer than that.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Precision {
    depth: u32,
    eps: f64,
}

/// Why a precision is not valid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PrecisionError {
    #[error("depth must be between 0 and {MAX_DEPTH}, got {0}")]
    Depth(u32),
    #[error("eps must be a finite number >= 0, got {0}")]
    Eps(f64),
}

impl Default for Precision {
    /// The paper's level 7, no tolerance.
    fn default() -> Self {
        Precision { depth: 7, eps: 0.0 }
    }
}

impl Precision {
    pub fn new(depth: u32, eps: f64) -> Result<Self, PrecisionError> {
        if depth > MAX_DEPTH {
            return Err(PrecisionError::Depth(depth));
        }
        if !(eps.is_finite() && eps >= 0.0) {
            return Err(PrecisionError::Eps(eps));
        }
        Ok(Precision { depth, eps })
    }

    pub fn depth(&self) -> u32 {
        self.depth
    }

    pub fn eps(&self) -> f64 {
        self.eps
    }

    /// The same tolerance, `levels` deeper (at most [`MAX_DEPTH`]).
    pub fn deeper(&self, levels: u32) -> Precision {
        Precision {
            depth: (self.depth + levels).min(MAX_DEPTH),
            eps: self.eps,
        }
    }

    /// The final cell size for a region.
    pub fn cell_size(&self, region: &Aabb) -> f64 {
        let longest = region.width().max(region.height());
        // 0.5^depth is exact, so halving L depth times lands on this size exactly.
        self.eps.max(longest * 0.5f64.powi(self.depth as i32))
    }
}

/// A cell against one shape (paper II).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    /// `a > 0`: no point of the cell is in the shape.
    Outside,
    /// `b < 0`: every point of the cell is in the shape.
    Inside,
    /// Neither: the cell may hold part of the boundary.
    Boundary,
}

impl Class {
    pub fn of(f: Interval) -> Class {
        if f.lo > 0.0 {
            Class::Outside
        } else if f.hi < 0.0 {
            Class::Inside
        } else {
            Class::Boundary
        }
    }
}

/// Receives every classified cell, for drawing the tree (paper Figs. 2, 3, 9).
pub trait CellSink {
    /// `last`: the cell is at the final precision and will not be split.
    fn cell(&mut self, cell: &Aabb, a: Class, b: Class, last: bool);
}

/// A sink that keeps nothing; the traversal compiles to the same code as without one.
impl CellSink for () {
    #[inline]
    fn cell(&mut self, _: &Aabb, _: Class, _: Class, _: bool) {}
}

impl CellSink for Vec<(Aabb, Class, Class, bool)> {
    fn cell(&mut self, cell: &Aabb, a: Class, b: Class, last: bool) {
        self.push((*cell, a, b, last));
    }
}

/// A point of one shape proven inside the other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deepest {
    pub point: Vec2,
    /// An upper bound of the other shape's `f` at `point` (negative).
    pub other_value: f64,
}

/// What the quadtree found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeepestPoints {
    /// `A1`: the point of A most interior to B, if any point was proven inside both.
    pub in_a: Option<Deepest>,
    /// `A2`: the point of B most interior to A (only when asked for).
    pub in_b: Option<Deepest>,
    /// Cells classified.
    pub cells: u32,
}

#[derive(Clone, Copy)]
struct Node {
    cell: Aabb,
    fa: Interval,
    fb: Interval,
}

const STACK: usize = 3 * MAX_DEPTH as usize + 8;

/// Whether each side of `cell` is split: while longer than the final size `tol`, and only where
/// its midpoint falls strictly between its ends. A cell a few ulps wide (a tiny grain far from
/// the origin, or against a huge one) cannot be halved: split again and again, it overflowed
/// this module's stack and looped forever in the contact regions' cover (found by a hostile
/// test). It is then a final cell, wider than `tol`.
pub(crate) fn splits(cell: &Aabb, tol: f64) -> (bool, bool) {
    let m = cell.center();
    (
        cell.width() > tol && cell.min.x < m.x && m.x < cell.max.x,
        cell.height() > tol && cell.min.y < m.y && m.y < cell.max.y,
    )
}

/// Searches `region` for the deepest points of the collision of `a` and `b` (paper II and
/// III-A). `want_b`: also look for `A2` (not needed against a wall, which does not move).
pub fn deepest_points<A, B, S>(
    a: &A,
    b: &B,
    region: &Aabb,
    precision: &Precision,
    want_b: bool,
    sink: &mut S,
) -> DeepestPoints
where
    A: ImplicitShape + ?Sized,
    B: ImplicitShape + ?Sized,
    S: CellSink + ?Sized,
{
    // Midpoints are rounded, so a side may come out an ulp longer than the final size; the
    // slack keeps that from adding a level.
    let tol = precision.cell_size(region) * (1.0 + 1e-9);
    let mut found = DeepestPoints {
        in_a: None,
        in_b: None,
        cells: 1,
    };
    // Only points inside both count, so the bounds start at 0.
    let mut best_a = 0.0f64;
    let mut best_b = if want_b { 0.0f64 } else { f64::NEG_INFINITY };
    let (minima_a, minima_b) = (a.minima(), b.minima());
    let may_hold = |m: Minima, c: &Aabb| match m {
        Minima::Unknown => true,
        Minima::Nowhere => false,
        Minima::At(p) => c.contains(p),
    };

    let root = Node {
        cell: *region,
        fa: a.enclose(region),
        fb: b.enclose(region),
    };
    let (sx, sy) = splits(region, tol);
    sink.cell(region, Class::of(root.fa), Class::of(root.fb), !(sx || sy));

    // Depth first with the most promising child on top; each level pushes at most 3 siblings
    // besides the one it continues with, so a fixed array is enough and nothing is allocated.
    let mut stack = [root; STACK];
    let mut len = 1usize;
    while len > 0 {
        len -= 1;
        let Node { cell, fa, fb } = stack[len];
        // Could this cell still hold a better A1 (min f_B over A) or A2 (min f_A over B)?
        // Outside either shape (lower bound > 0) it cannot: the paper's discard rule.
        let improves_a = fa.lo <= 0.0 && fb.lo < best_a;
        let improves_b = fb.lo <= 0.0 && fa.lo < best_b;
        if !(improves_a || improves_b) {
            continue;
        }
        // Refined only where a deeper point can lie: on the boundary, or at the other's centre
        // (module docs). A cell strictly inside is not refined but its midpoint still counts,
        // the paper's rule for cells inside both.
        let refine = (improves_a && (fa.hi >= 0.0 || may_hold(minima_b, &cell)))
            || (improves_b && (fb.hi >= 0.0 || may_hold(minima_a, &cell)));

        // The midpoint is a candidate only when proven inside both. It is worth evaluating
        // where that is likely (a cell inside one shape, or at the final precision) and, until
        // some witness is found, everywhere: a star's centre may be the only point of the
        // overlap that a coarse tree ever visits.
        let mid = cell.center();
        let (split_x, split_y) = splits(&cell, tol);
        let last = !(split_x || split_y);
        let pa = if last || !refine || fa.hi < 0.0 || fb.hi < 0.0 || found.in_a.is_none() {
            a.enclose_point(mid)
        } else {
            Interval::point(f64::INFINITY)
        };
        if pa.hi < 0.0 {
            let pb = b.enclose_point(mid);
            if pb.hi < 0.0 {
                if pb.hi < best_a {
                    best_a = pb.hi;
                    found.in_a = Some(Deepest {
                        point: mid,
                        other_value: pb.hi,
                    });
                }
                if want_b && pa.hi < best_b {
                    best_b = pa.hi;
                    found.in_b = Some(Deepest {
                        point: mid,
                        other_value: pa.hi,
                    });
                }
            }
        }

        if last || !refine {
            continue;
        }
        let xs = if split_x {
            [cell.min.x, mid.x, cell.max.x]
        } else {
            [cell.min.x, cell.max.x, cell.max.x]
        };
        let ys = if split_y {
            [cell.min.y, mid.y, cell.max.y]
        } else {
            [cell.min.y, cell.max.y, cell.max.y]
        };
        let nx = 1 + usize::from(split_x);
        let ny = 1 + usize::from(split_y);

        let mut children = [stack[len]; 4];
        let mut keys = [0.0f64; 4];
        let mut n = 0;
        for i in 0..nx {
            for j in 0..ny {
                let c = Aabb::new(Vec2::new(xs[i], ys[j]), Vec2::new(xs[i + 1], ys[j + 1]));
                let fa = a.enclose(&c);
                let fb = b.enclose(&c);
                found.cells += 1;
                let (ca, cb) = (Class::of(fa), Class::of(fb));
                let (lx, ly) = splits(&c, tol);
                sink.cell(&c, ca, cb, !(lx || ly));
                if ca == Class::Outside || cb == Class::Outside {
                    continue;
                }
                children[n] = Node { cell: c, fa, fb };
                keys[n] = fa.lo + fb.lo;
                n += 1;
            }
        }
        // Push the least promising first so the most promising is popped next.
        let mut order = [0usize, 1, 2, 3];
        order[..n].sort_unstable_by(|&i, &j| keys[j].total_cmp(&keys[i]));
        for &k in &order[..n] {
            stack[len] = children[k];
            len += 1;
        }
    }
    found
}

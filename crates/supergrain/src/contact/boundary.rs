//! The boundary search (issue 19): the deepest point of one shape in another for any pair,
//! stars and unequal exponents included, by a branch and bound over the first shape's
//! boundary, one-dimensional where the quadtree is two.
//!
//! The deepest point of `own` in `other` minimises `f_other` over `own`. It lies on `own`'s
//! boundary unless `own` holds `other`'s centre: `f_other` grows along every ray from that
//! centre, so an interior point that is not the centre has a deeper neighbour towards it. A
//! superellipse's boundary has a closed form. In each quadrant, and on each side of the point
//! where `|x/s_x|^e_x = 1/2`, it is a graph over one scaled coordinate `p`: the other is
//! `(1 - p^e_p)^(1/e_q)`. Each half is taken over the coordinate along which it is flat
//! enough that halving `p` halves the arc: the one along the face for a blocky shape, the one
//! along the spike for a star. Within a quadrant both coordinates are monotone along the
//! boundary, so the arc between two parameters lies in the box of its two end points: an
//! interval enclosure of `f_other` over that box bounds it over the arc from below. Every
//! spike tip is the end of a half, an exact parameter, seen at once however thin the spike.
//!
//! The search splits the arc of the smallest lower bound at its middle, where it also tries a
//! witness: the boundary point moved a hair towards `own`'s centre, kept when interval
//! arithmetic proves it inside both shapes. It stops with
//! - "deepest up to `tau`": a witness whose upper bound is within `tau` (half a final
//!   quadtree cell times `|grad f_other|` there, as the Newton path's) of every arc's lower
//!   bound: no point of `own` is deeper in `other` by more than that;
//! - "beyond": every arc's lower bound above `-touch`, the level within half a final cell (a
//!   distance) of `other`'s boundary ([`touch_level`]), and `other`'s centre proven outside
//!   `own`: no point of `own` lies more than half a final cell inside `other`. And then no point
//!   of `other` lies more than that inside `own` either: from such a point, the way towards
//!   `other`'s centre reaches the level `-touch` within half a cell, at a point that cannot be
//!   in `own`.
//!
//! Anything else (a budget of splits spent, a centre on `own`'s boundary) is no answer: the
//! caller runs the quadtree, as for the Newton path.

use super::certified::{Deepest, touch_level};
use crate::geometry::{Aabb, Vec2};
use crate::interval::{
    Exponent, ImplicitShape, Interval, PlacedSuperellipse, down, pow_down, pow_up, up,
};
use crate::shape::Pose;

/// A relative pad over the rounding of `1 / e` and of the halves' ends (module docs).
const PAD: f64 = 1e-12;
/// Splits before giving up: a near-touching pair takes a few dozen.
const MAX_SPLITS: usize = 400;
/// Arcs kept at once before giving up.
const MAX_ARCS: usize = 96;
/// How far towards `own`'s centre a witness is moved, tried in turn: a hair first (as the
/// Newton path), then more for a spike's tip, where the rounding of the pose moves points
/// across the thin spike.
const INWARD: [f64; 3] = [1e-9, 1e-6, 1e-3];

/// One half of a quadrant, a graph over its parameter.
#[derive(Clone, Copy)]
struct Half {
    /// The signed semi-axes of the quadrant, the parameter's first.
    s_p: f64,
    s_q: f64,
    /// Whether the parameter is the scaled `y` (else `x`).
    by_y: bool,
    e_p: Exponent,
    e_p_float: f64,
    /// `1 / e_q`, rounded.
    inv_q: f64,
    lo: f64,
    hi: f64,
}

impl Half {
    /// The boundary point at `p`, enclosed: `(s_p p, s_q (1 - p^e_p)^(1/e_q))`, each end rounded
    /// outward, the root padded for the rounding of `1 / e_q`.
    fn enclose(&self, p: f64) -> Aabb {
        let pp = Interval::new(self.e_p.pow_down(p), self.e_p.pow_up(p));
        let w_lo = down(1.0 - pp.hi).max(0.0);
        let w_hi = up(1.0 - pp.lo).min(1.0);
        let q = Interval::new(
            pow_down(w_lo, self.inv_q) * (1.0 - PAD),
            (pow_up(w_hi, self.inv_q) * (1.0 + PAD)).min(1.0),
        );
        let a = Interval::point(p).scale(self.s_p);
        let b = q.scale(self.s_q);
        self.aabb(a, b)
    }

    /// The boundary point at `p` in floating point.
    fn point(&self, p: f64) -> Vec2 {
        let w = (1.0 - p.powf(self.e_p_float)).max(0.0);
        let (a, b) = (self.s_p * p, self.s_q * w.powf(self.inv_q));
        if self.by_y {
            Vec2::new(b, a)
        } else {
            Vec2::new(a, b)
        }
    }

    fn aabb(&self, a: Interval, b: Interval) -> Aabb {
        let (x, y) = if self.by_y { (b, a) } else { (a, b) };
        Aabb::new(Vec2::new(x.lo, y.lo), Vec2::new(x.hi, y.hi))
    }
}

/// The halves of a quadrant of `own` (axis-aligned at the origin), `sx`, `sy` signed.
fn halves(ex: f64, ey: f64, sx: f64, sy: f64) -> [Half; 2] {
    let (xm, ym) = (0.5f64.powf(1.0 / ex), 0.5f64.powf(1.0 / ey));
    let over_x = |lo: f64, hi: f64| Half {
        s_p: sx,
        s_q: sy,
        by_y: false,
        e_p: Exponent::new(ex),
        e_p_float: ex,
        inv_q: 1.0 / ey,
        lo,
        hi,
    };
    let over_y = |lo: f64, hi: f64| Half {
        s_p: sy,
        s_q: sx,
        by_y: true,
        e_p: Exponent::new(ey),
        e_p_float: ey,
        inv_q: 1.0 / ex,
        lo,
        hi,
    };
    // Next to the y tip (`|x/s_x|^e_x <= 1/2`), then next to the x tip; each reaching a
    // relative `PAD` past the middle, so that the rounded ends leave no gap.
    let near_y = if ex >= 1.0 {
        over_x(0.0, (xm * (1.0 + PAD)).min(1.0))
    } else {
        over_y(ym * (1.0 - PAD), 1.0)
    };
    let near_x = if ey > 1.0 {
        over_y(0.0, (ym * (1.0 + PAD)).min(1.0))
    } else {
        over_x(xm * (1.0 - PAD), 1.0)
    };
    [near_y, near_x]
}

/// An arc of one half between two parameters, with its ends' boxes and the lower bound of
/// `f_other` over their hull.
#[derive(Clone, Copy)]
struct Arc {
    half: u8,
    p0: f64,
    p1: f64,
    b0: Aabb,
    b1: Aabb,
    lower: f64,
}

/// A witness: a point proven inside both, the upper bound of `f_other` there, and the
/// tolerance of "deepest up to".
#[derive(Clone, Copy)]
struct Witness {
    point: Vec2,
    value: f64,
    tau: f64,
}

/// The deepest point of `own` (axis-aligned at the origin) in `other` by the boundary search
/// (module docs), and the point to start from next time, or `None` (no answer: the caller runs
/// the quadtree). `cell`: the final quadtree cell of the pair, which sets the tolerances;
/// `slack`: witnesses are proven inside over a box of that half-width about them, so that they
/// stay inside when moved to world coordinates.
pub(crate) fn deepest_on_boundary(
    placed_own: &PlacedSuperellipse,
    other: &PlacedSuperellipse,
    cell: f64,
    slack: f64,
) -> Option<(Deepest, Vec2)> {
    let own = placed_own.shape();
    debug_assert_eq!(*placed_own.pose(), Pose::ORIGIN);
    let centre = other.pose().center();
    let proven_in = |shape: &PlacedSuperellipse, q: Vec2| {
        if slack == 0.0 {
            shape.enclose_point(q).hi < 0.0
        } else {
            let d = Vec2::new(slack, slack);
            shape.enclose(&Aabb::new(q - d, q + d)).hi < 0.0
        }
    };
    // Does `own` hold `other`'s centre? Then it is the deepest point (`f_other = -1`). Beyond
    // `own`'s bounding circle (padded for the rounding of the test) it does not.
    let r = own.bounding_radius() * (1.0 + 1e-9);
    if centre.dot(centre) <= r * r {
        let f = placed_own.enclose_point(centre);
        if f.hi < 0.0 {
            return (proven_in(placed_own, centre) && proven_in(other, centre))
                .then_some((Deepest::At(centre), centre));
        }
        // Undecided (or NaN): the centre may be on `own`'s boundary.
        if f.lo.is_nan() || f.lo <= 0.0 {
            return None;
        }
    }
    let touch = touch_level(other.shape(), cell);
    let [ex, ey] = own.exponents();
    let s = own.semi_axes();
    let mut table = [halves(ex, ey, s.x, s.y)[0]; 8];
    let mut arcs: Vec<Arc> = Vec::with_capacity(16);
    for (k, (sx, sy)) in [(s.x, s.y), (-s.x, s.y), (-s.x, -s.y), (s.x, -s.y)]
        .into_iter()
        .enumerate()
    {
        // A quadrant whose box is clear of `other` costs one enclosure, usually no power.
        let quadrant = Aabb::new(
            Vec2::new(sx.min(0.0), sy.min(0.0)),
            Vec2::new(sx.max(0.0), sy.max(0.0)),
        );
        if other.lower_bound(&quadrant) >= 0.0 {
            continue;
        }
        for (m, half) in halves(ex, ey, sx, sy).into_iter().enumerate() {
            let index = 2 * k + m;
            table[index] = half;
            let (b0, b1) = (half.enclose(half.lo), half.enclose(half.hi));
            let lower = other.lower_bound(&b0.union(&b1));
            if lower < 0.0 {
                arcs.push(Arc {
                    half: index as u8,
                    p0: half.lo,
                    p1: half.hi,
                    b0,
                    b1,
                    lower,
                });
            }
        }
    }
    let mut best: Option<Witness> = None;
    for _ in 0..MAX_SPLITS {
        let Some(k) = (0..arcs.len()).min_by(|&i, &j| arcs[i].lower.total_cmp(&arcs[j].lower))
        else {
            // Every arc is outside `other`.
            return Some(match best {
                Some(w) => (Deepest::At(w.point), w.point),
                None => (Deepest::Beyond, Vec2::ZERO),
            });
        };
        let lower = arcs[k].lower;
        match best {
            Some(w) if lower >= w.value - w.tau => return Some((Deepest::At(w.point), w.point)),
            None if lower > -touch => {
                let near = arcs[k];
                let at = table[usize::from(near.half)].point(0.5 * (near.p0 + near.p1));
                return Some((Deepest::Beyond, at));
            }
            _ => {}
        }
        let arc = arcs.swap_remove(k);
        let half = table[usize::from(arc.half)];
        let mid = 0.5 * (arc.p0 + arc.p1);
        if !(mid > arc.p0 && mid < arc.p1 && lower.is_finite()) {
            return None;
        }
        let bm = half.enclose(mid);
        let q = half.point(mid);
        let value = other.value(q);
        if value < 0.0 && best.is_none_or(|w| value < w.value) {
            for k in INWARD {
                let w = q * (1.0 - k);
                if proven_in(placed_own, w) && proven_in(other, w) {
                    let v = if slack == 0.0 {
                        other.enclose_point(w).hi
                    } else {
                        let d = Vec2::new(slack, slack);
                        other.enclose(&Aabb::new(w - d, w + d)).hi
                    };
                    let tau = 0.5 * cell * other.gradient(w).norm();
                    if tau.is_finite() && best.is_none_or(|b| v < b.value) {
                        best = Some(Witness {
                            point: w,
                            value: v,
                            tau,
                        });
                    }
                    break;
                }
            }
        }
        for (p0, p1, b0, b1) in [(arc.p0, mid, arc.b0, bm), (mid, arc.p1, bm, arc.b1)] {
            let lower = other.lower_bound(&b0.union(&b1));
            // An arc outside `other` (`f >= 0`) holds no deeper point than any witness (`f < 0`)
            // and nothing within `touch` of its inside.
            if lower < 0.0 {
                if arcs.len() == MAX_ARCS {
                    return None;
                }
                arcs.push(Arc {
                    half: arc.half,
                    p0,
                    p1,
                    b0,
                    b1,
                    lower,
                });
            }
        }
    }
    None
}

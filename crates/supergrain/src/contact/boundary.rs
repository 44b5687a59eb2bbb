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
//! Where `other`'s gradient is bounded over the box, tighter bounds follow `f_other` along the
//! arc: by the mean-value theorem ([`slope_bound`], second order in the arc's length near a
//! minimum) and, on short arcs still open, by Taylor's theorem with a lower bound of the second
//! derivative ([`second_order_bound`], third order where `f_other` is convex along the arc).
//!
//! The search first tries `own`'s four tips as witnesses, then splits the arc of the smallest
//! lower bound at its middle, where it also tries a witness: the boundary point moved a hair
//! towards `own`'s centre, kept when interval arithmetic proves it inside both shapes. It stops
//! with
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
use super::ray::bracketed_root;
use crate::geometry::{Aabb, Vec2};
use crate::interval::{Exponent, ImplicitShape, Interval, PlacedSuperellipse, down, up};
use crate::shape::{Pose, Superellipse};

/// A relative pad over the rounding of `1 / e` and of the halves' ends (module docs).
const PAD: f64 = 1e-12;
/// A relative pad over the rounding of the tangent's factor `e_p / e_q` (from the rounded
/// `1 / e_q`): far above its few ulps. (Its powers come from the ends' enclosures, whose pad
/// covers the rounding of `1 / e_q`.)
const SLOPE_PAD: f64 = 1e-9;
/// The smallest exponent of `other` for which the mean-value bounds are tried.
const SLOPE_MIN_EXPONENT: f64 = 0.5;
/// Splits before giving up: a near-touching pair takes a few dozen.
const MAX_SPLITS: usize = 400;
/// Arcs kept at once before giving up. Faces pressed flat on each other keep many arcs open
/// at once: in the mixed pour (`examples/scenes/pour-mixed.toml`, 150 steps from step 1,000)
/// 96 sent 3,656 searches to the quadtree, 192 one, and the steps took 20% less time.
const MAX_ARCS: usize = 192;
/// How far towards `own`'s centre a witness is moved, tried in turn: a hair first (as the
/// Newton path), then more for a spike's tip, where the rounding of the pose moves points
/// across the thin spike.
pub(super) const INWARD: [f64; 3] = [1e-9, 1e-6, 1e-3];

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
    /// `1 / e_q`, rounded, and as an exponent.
    inv_q: f64,
    e_q: Exponent,
    /// Whether the ends' boxes take the single-precision powers
    /// ([`Exponent::pow_down_coarse`]): a relative `1e-5` wider, for the deepest point's
    /// search, whose tolerance is a fraction of a cell, not for the support's, which may be
    /// asked for `1e-6` of the size.
    coarse: bool,
    /// For the arc's tangent: `e_p / e_q` enclosed.
    ratio: Interval,
    lo: f64,
    hi: f64,
}

/// A boundary point of a half at the parameter `p`, enclosed: its box, and on the way there
/// `p^e_p`, `w = 1 - p^e_p` and `w^(1/e_q)`, kept for [`Half::tangent`] over the arcs it
/// ends, which then needs no power of its own (it took six, of about 35 a split).
#[derive(Clone, Copy, Debug, PartialEq)]
struct End {
    p: f64,
    pp: Interval,
    w: Interval,
    q: Interval,
    b: Aabb,
}

impl End {
    /// The same point in the quadrant of signs `(fx, fy)`: the box reflected, the powers
    /// (of the scaled coordinates' magnitudes) the same.
    fn mirrored(&self, fx: f64, fy: f64) -> End {
        End {
            b: mirrored(&self.b, fx, fy),
            ..*self
        }
    }
}

impl Half {
    /// The boundary point at `p`, enclosed: `(s_p p, s_q (1 - p^e_p)^(1/e_q))`, each end rounded
    /// outward, the root padded for the rounding of `1 / e_q`.
    fn enclose(&self, p: f64) -> End {
        let (lo, hi, _) = self.e_p.pow_all(p);
        self.enclose_from(p, Interval::new(lo, hi))
    }

    /// The same half in the quadrant of signs `(fx, fy)` (each 1 or -1) relative to this one's.
    fn mirrored(&self, fx: f64, fy: f64) -> Half {
        let (fp, fq) = if self.by_y { (fy, fx) } else { (fx, fy) };
        Half {
            s_p: fp * self.s_p,
            s_q: fq * self.s_q,
            ..*self
        }
    }

    /// [`Self::enclose`] and [`Self::point`] at once, sharing the power `p^e_p` (bit for bit
    /// the same answers; 2 of the 12 powers of a split saved).
    #[inline(always)]
    fn enclose_and_point(&self, p: f64) -> (End, Vec2) {
        let (lo, hi, pp) = self.e_p.pow_all(p);
        (
            self.enclose_from(p, Interval::new(lo, hi)),
            self.point_from(p, pp),
        )
    }

    /// [`Self::enclose`] given `p^e_p` enclosed.
    #[inline(always)]
    fn enclose_from(&self, p: f64, pp: Interval) -> End {
        let w_lo = down(1.0 - pp.hi).max(0.0);
        let w_hi = up(1.0 - pp.lo).min(1.0);
        let (q_lo, q_hi) = if self.coarse {
            (self.e_q.pow_down_coarse(w_lo), self.e_q.pow_up_coarse(w_hi))
        } else {
            (self.e_q.pow_down(w_lo), self.e_q.pow_up(w_hi))
        };
        let q = Interval::new(q_lo * (1.0 - PAD), (q_hi * (1.0 + PAD)).min(1.0));
        let a = Interval::point(p).scale(self.s_p);
        let b = q.scale(self.s_q);
        End {
            p,
            pp,
            w: Interval::new(w_lo, w_hi),
            q,
            b: self.aabb(a, b),
        }
    }

    /// The boundary point at `p` in floating point.
    fn point(&self, p: f64) -> Vec2 {
        self.point_from(p, p.powf(self.e_p_float))
    }

    /// [`Self::point`] given `p^e_p` in floating point.
    #[inline(always)]
    fn point_from(&self, p: f64, pp: f64) -> Vec2 {
        let w = (1.0 - pp).max(0.0);
        let (a, b) = (self.s_p * p, self.s_q * w.powf(self.inv_q));
        if self.by_y {
            Vec2::new(b, a)
        } else {
            Vec2::new(a, b)
        }
    }

    /// A pair in the half's `(p, q)` order in `(x, y)` order.
    fn xy<T>(&self, p: T, q: T) -> [T; 2] {
        if self.by_y { [q, p] } else { [p, q] }
    }

    fn aabb(&self, a: Interval, b: Interval) -> Aabb {
        let (x, y) = if self.by_y { (b, a) } else { (a, b) };
        Aabb::new(Vec2::new(x.lo, y.lo), Vec2::new(x.hi, y.hi))
    }
}

/// `e_p / e_q` from `e_p` and the rounded `1 / e_q`, enclosed.
fn ratio(e_p: f64, inv_q: f64) -> Interval {
    let r = e_p * inv_q;
    Interval::new(down(r) * (1.0 - SLOPE_PAD), up(r) * (1.0 + SLOPE_PAD))
}

impl Half {
    /// An enclosure of the derivative of the boundary point along the parameter, in the
    /// half's `(p, q)` order, over the arc between two ends: `(s_p, -s_q (e_p / e_q)
    /// p^(e_p - 1) w^(1/e_q - 1))` with `w = 1 - p^e_p`. Each factor is monotone in `p`, so it
    /// is enclosed by its values at the ends, and each of those is a quotient of the powers
    /// the ends hold: `p^(e_p - 1) = p^e_p / p` and `w^(1/e_q - 1) = w^(1/e_q) / w`, a bound
    /// of the numerator over the end's parameter rounded outward. The halves keep it bounded
    /// (`p` away from 0 where `e_p < 1`, `w >= 1/2` where `e_q > 1`), and `None` says it is
    /// not (a rounding at an end).
    fn tangent(&self, e0: &End, e1: &End) -> Option<(f64, Interval)> {
        self.tangent_factors(e0, e1).map(|t| (t.0, t.1))
    }

    /// [`Self::tangent`], and its factors `p^(e_p - 1)` and `w^(1/e_q - 1)` enclosed over the
    /// arc, for [`Self::curvature`].
    fn tangent_factors(&self, e0: &End, e1: &End) -> Option<(f64, Interval, [Interval; 2])> {
        let e_p = self.e_p_float;
        let (p0, p1) = (e0.p, e1.p);
        // (A single point at `p = 0` is an arc too, for [`second_order_bound`]'s slopes.)
        if p1.is_nan() || p1 < 0.0 || (p1 == 0.0 && e_p < 1.0) {
            return None;
        }
        let pp = if e_p >= 1.0 {
            // At `p = 0`: `0^(e_p - 1)` is 0, or 1 for `e_p = 1`.
            let lo = if p0 > 0.0 {
                down(e0.pp.lo / p0)
            } else if e_p > 1.0 {
                0.0
            } else {
                1.0
            };
            Interval::new(lo, if p1 > 0.0 { up(e1.pp.hi / p1) } else { lo })
        } else if p0 > 0.0 {
            Interval::new(down(e1.pp.lo / p1), up(e0.pp.hi / p0))
        } else {
            return None;
        };
        // `w` falls along the arc: from `e0.w.hi` down to `e1.w.lo` at most.
        let (w_lo, w_hi) = (e1.w.lo, e0.w.hi);
        let k = self.inv_q - 1.0;
        let ww = if k == 0.0 {
            Interval::point(1.0)
        } else if k > 0.0 {
            let lo = if w_lo > 0.0 {
                down(e1.q.lo / w_lo)
            } else {
                0.0
            };
            Interval::new(lo, up(e0.q.hi / w_hi))
        } else if w_lo > 0.0 {
            Interval::new(down(e0.q.lo / w_hi), up(e1.q.hi / w_lo))
        } else {
            return None;
        };
        let dq = pp.times(ww).times(self.ratio).scale(-self.s_q);
        let finite = dq.lo.is_finite() && dq.hi.is_finite() && dq.lo <= dq.hi;
        finite.then_some((self.s_p, dq, [pp, ww]))
    }
}

/// `a / b` for intervals with `b > 0`, rounded outward.
fn quotient(a: Interval, b: Interval) -> Interval {
    let lo = if a.lo >= 0.0 {
        a.lo / b.hi
    } else {
        a.lo / b.lo
    };
    let hi = if a.hi >= 0.0 {
        a.hi / b.lo
    } else {
        a.hi / b.hi
    };
    Interval::new(down(lo), up(hi))
}

impl Half {
    /// An enclosure of the second derivative of the boundary's `q` coordinate along the
    /// parameter over the arc between two ends (the first, `s_p`, is linear): with
    /// `w = 1 - p^e_p` and `k = 1/e_q - 1`,
    /// `q'' = -s_q (e_p / e_q) ((e_p - 1) p^(e_p - 2) w^k - k e_p p^(2 e_p - 2) w^(k - 1))`,
    /// each power a quotient of those [`Half::tangent`] encloses, no power of its own. `None`
    /// where it is unbounded over the arc (the end `p = 0` for `1 < e_p < 2`, a tip's `w = 0`
    /// for `k < 1`) or not finite.
    fn curvature(&self, e0: &End, e1: &End, [pp, wk]: [Interval; 2]) -> Option<Interval> {
        let e_p = self.e_p_float;
        let (p0, p1) = (e0.p, e1.p);
        let (w_lo, w_hi) = (e1.w.lo, e0.w.hi);
        if !(w_lo > 0.0 && p1 > 0.0) {
            return None;
        }
        let p = Interval::new(p0, p1);
        // `p^(e_p - 2) = p^(e_p - 1) / p`.
        let pp2 = if e_p == 1.0 {
            Interval::point(0.0)
        } else if p0 > 0.0 {
            quotient(pp, p)
        } else if e_p == 2.0 {
            Interval::point(1.0)
        } else if e_p > 2.0 {
            // Grows with `p`: from 0 at `p = 0` to its value at `p1`.
            Interval::new(0.0, up(pp.hi / p1))
        } else {
            return None;
        };
        let w = Interval::new(w_lo, w_hi);
        let k = self.inv_q - 1.0;
        // `e_p - 1` rounded, and `k` from the rounded `1 / e_q`: enclosed.
        let around = |x: f64, err: f64| Interval::new(down(x) - err, up(x) + err);
        let first = pp2.times(wk).times(around(e_p - 1.0, 0.0));
        let second = if k == 0.0 {
            Interval::point(0.0)
        } else {
            let k = around(k, 2.3e-16 * self.inv_q);
            pp.times(pp).times(quotient(wk, w)).times(k.scale(e_p))
        };
        let inner = Interval::new(down(first.lo - second.hi), up(first.hi - second.lo));
        let dqq = inner.times(self.ratio).scale(-self.s_q);
        (dqq.lo.is_finite() && dqq.hi.is_finite()).then_some(dqq)
    }
}

/// A lower bound of `a + b t + c t^2` over `t` in `[0, h]` (`c` finite).
fn quadratic_floor(a: f64, b: f64, c: f64, h: f64) -> f64 {
    if c > 0.0 {
        if b >= 0.0 {
            return a;
        }
        // Both are below the parabola over `[0, h]`: its vertex's value, and the chord `a + b t`.
        // (The vertex only where `4c` rounded down stays positive: for a subnormal `c` it
        // would not, and the quotient's sign would flip; found by a review, tested below.)
        let chord = down(a + down(b * h));
        let four_c = down(4.0 * c);
        if four_c > 0.0 {
            chord.max(down(a - up(up(b * b) / four_c)))
        } else {
            chord
        }
    } else {
        // Concave: least at an end.
        a.min(down(a + down(down(b * h) + down(c * up(h * h)))))
    }
}

/// The derivative of `f_other` along the boundary at an end: the gradient over the end's box
/// dotted with the tangent there. `None` where either is unbounded.
fn slope_at(half: &Half, other: &PlacedSuperellipse, e: &End) -> Option<Interval> {
    let (dp, dq) = half.tangent(e, e)?;
    let [gx, gy] = other.gradient_enclosure(&e.b)?;
    let [dx, dy] = half.xy(Interval::point(dp), dq);
    let s = gx.times(dx).plus(gy.times(dy));
    (s.lo.is_finite() && s.hi.is_finite()).then_some(s)
}

/// A second-order lower bound of `f_other` along an arc, by Taylor's theorem in the parameter
/// from each end: `f(p0 + t) >= f0 + f'(p0) t + C t^2 / 2` for `C` below the second derivative
/// over the arc ([`PlacedSuperellipse::second_derivative_floor`] along the boundary's velocity
/// and acceleration), and the same from the other end. Where `f` is convex along the arc (the
/// deepest point of a convex grain in another, a star's spike in a convex grain) it is within
/// a third-order term of the arc's minimum, where the first-order [`slope_bound`] is within a
/// second-order one: the arc by the deepest point closes a few halvings sooner. `slopes`:
/// [`PlacedSuperellipse::axis_slopes`] over the arc's box; `(s0, s1)`: [`slope_at`] the ends.
/// `None` where a factor is unbounded.
fn second_order_bound(
    half: &Half,
    other: &PlacedSuperellipse,
    (e0, e1): (&End, &End),
    (dp, dq, factors): (f64, Interval, [Interval; 2]),
    (hull, slopes): (&Aabb, [Interval; 2]),
    (f0, f1): (f64, f64),
    (s0, s1): (Interval, Interval),
) -> Option<f64> {
    let dqq = half.curvature(e0, e1, factors)?;
    let floor = other.second_derivative_floor(
        hull,
        slopes,
        half.xy(Interval::point(dp), dq),
        half.xy(Interval::point(0.0), dqq),
    )?;
    let c = 0.5 * floor;
    let h = up(e1.p - e0.p);
    Some(quadratic_floor(f0, s0.lo, c, h).max(quadratic_floor(f1, -s1.hi, c, h)))
}

/// A lower bound of `f_other` along an arc by the mean-value theorem in its parameter:
/// `f(p) >= f(p0) + min(0, D) (p1 - p0)` and `f(p) >= f(p1) - max(0, D) (p1 - p0)`, `D` an
/// enclosure of `d f(gamma(p)) / dp` over the arc (the gradient of `f_other` over the arc's box
/// dotted with the tangent's enclosure). Near the minimum `D` is small, so the bound is
/// second order in the arc's length where the box's is first: the arcs by the minimum need not
/// be split down to a cell, and along a flat face pressed on another (a derivative near 0 all
/// along) the whole face is bounded at once. `f0`, `f1`: lower bounds at the ends; `g`: the
/// gradient of `f_other` over the arc's box. `None` where the tangent is unbounded.
fn slope_bound(
    half: &Half,
    (e0, e1): (&End, &End),
    (dp, dq): (f64, Interval),
    g: [Interval; 2],
    (f0, f1): (f64, f64),
) -> Option<f64> {
    let (p0, p1) = (e0.p, e1.p);
    let (gp, gq) = if half.by_y {
        (g[1], g[0])
    } else {
        (g[0], g[1])
    };
    let d = gp.scale(dp).plus(gq.times(dq));
    if !(d.lo.is_finite() && d.hi.is_finite()) {
        return None;
    }
    let h = up(p1 - p0);
    let from_start = down(f0 + down(d.lo.min(0.0) * h));
    let from_end = down(f1 - up(d.hi.max(0.0) * h));
    Some(from_start.max(from_end))
}

/// The longest arc (in its half's parameter, of length at most 1) on which
/// [`second_order_bound`] is tried. On longer arcs it seldom closes one: replaying the
/// mixed preset's first 1,500 steps' tests (367k, recorded once), it closed 11% of the arcs
/// longer than 0.1 it was tried on and 33-43% of those between 0.01 and 0.1. The replay took
/// 1.44 s with this cap, 1.47 / 1.46 / 1.54 s with caps of 0.05 / 0.2 / 0.4, and 1.60 s without
/// the bound (splits 1.14M against 1.58M).
const SECOND_ORDER_MAX_ARC: f64 = 0.1;

/// The tightest bound of `f_other` along the arc between the nodes `i0` and `i1` that is worth
/// its cost: the box bound `lower`, [`slope_bound`] over it, and where that still leaves the
/// arc below `goal` (it would stay open), [`second_order_bound`] too. Caches the ends'
/// slopes in their nodes (each end is shared by two arcs).
fn tighter(
    half: &Half,
    other: &PlacedSuperellipse,
    nodes: &mut [Node],
    (i0, i1): (u32, u32),
    hull: &Aabb,
    (lower, goal): (f64, f64),
) -> f64 {
    let (n0, n1) = (nodes[i0 as usize], nodes[i1 as usize]);
    let ends = (&n0.end, &n1.end);
    let values = (n0.f, n1.f);
    // The tangent first: without it no power is spent.
    let Some(tangent) = half.tangent_factors(ends.0, ends.1) else {
        return lower;
    };
    let Some(slopes) = other.axis_slopes(hull) else {
        return lower;
    };
    let (dp, dq, _) = tangent;
    let first = slope_bound(half, ends, (dp, dq), other.gradient_from(slopes), values)
        .map_or(lower, |b| b.max(lower));
    if first >= goal || n1.end.p - n0.end.p > SECOND_ORDER_MAX_ARC {
        return first;
    }
    let mut end_slope = |i: u32| {
        let node = &mut nodes[i as usize];
        if node.slope.lo.is_nan() {
            node.slope = slope_at(half, other, &node.end)
                .unwrap_or(Interval::new(f64::NEG_INFINITY, f64::INFINITY));
        }
        Some(node.slope).filter(|s| s.lo.is_finite())
    };
    let (Some(s0), Some(s1)) = (end_slope(i0), end_slope(i1)) else {
        return first;
    };
    second_order_bound(half, other, ends, tangent, (hull, slopes), values, (s0, s1))
        .map_or(first, |b| b.max(first))
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
        e_q: Exponent::new(1.0 / ey),
        coarse: false,
        ratio: ratio(ex, 1.0 / ey),
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
        e_q: Exponent::new(1.0 / ex),
        coarse: false,
        ratio: ratio(ey, 1.0 / ex),
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

/// The ends of the first quadrant's halves of `own`, enclosed: a dozen powers, the same at
/// every test of the shape, so kept per thread for the shapes seen last (a table of 64 slots
/// indexed by a hash of the shape's bits; a shape found there is the same to the bit, so are
/// the answers). The mixed preset's tests replayed took 7% less time (1.34 s against 1.44).
fn first_quadrant_ends(own: &Superellipse, first: &[Half; 2]) -> [(End, End); 2] {
    type Entry = ([u64; 4], [(End, End); 2]);
    thread_local! {
        static ENDS: std::cell::RefCell<Vec<Option<Entry>>> =
            std::cell::RefCell::new(vec![None; 64]);
    }
    let [ex, ey] = own.exponents();
    let s = own.semi_axes();
    let key = [ex, ey, s.x, s.y].map(f64::to_bits);
    let hash = key.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &k| {
        (h ^ k).wrapping_mul(0x0100_0000_01b3)
    });
    let slot = (hash >> 58) as usize;
    ENDS.with_borrow_mut(|table| {
        if let Some((k, ends)) = &table[slot]
            && *k == key
        {
            return *ends;
        }
        let ends = first.map(|h| (h.enclose(h.lo), h.enclose(h.hi)));
        table[slot] = Some((key, ends));
        ends
    })
}

/// A box reflected through the axes where `fx`, `fy` are -1 (exactly: a change of sign).
fn mirrored(b: &Aabb, fx: f64, fy: f64) -> Aabb {
    let flip = |p: Vec2| Aabb::point(Vec2::new(fx * p.x, fy * p.y));
    flip(b.min).union(&flip(b.max))
}

/// An arc of one half between two parameters: its ends (indices into the search's list of
/// [`Node`]s, which neighbouring arcs share) and the lower bound of `f_other` over it. Small,
/// as the search picks the least bound over all of them at every split.
#[derive(Clone, Copy)]
struct Arc {
    half: u8,
    /// Whether a crossing of `other`'s cusps was searched for on this arc or one it was split
    /// from (see [`cusp_crossing`]).
    crossed: bool,
    e0: u32,
    e1: u32,
    lower: f64,
}

/// An end of arcs and the lower bound of `f_other` over its box.
#[derive(Clone, Copy)]
struct Node {
    end: End,
    f: f64,
    /// The end's boundary point in floating point, for the cusps' crossings (0 when `other`
    /// has none).
    point: Vec2,
    /// [`slope_at`] the end, once [`tighter`] wants it: NaN before, infinite where unbounded.
    slope: Interval,
}

impl Node {
    fn new(end: End, f: f64, point: Vec2) -> Node {
        Node {
            end,
            f,
            point,
            slope: Interval::new(f64::NAN, f64::NAN),
        }
    }
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
    // An upper bound of a shape's `f` over the box of half-width `slack` about `q`.
    let upper = |shape: &PlacedSuperellipse, q: Vec2| {
        if slack == 0.0 {
            shape.enclose_point(q).hi
        } else {
            let d = Vec2::new(slack, slack);
            shape.enclose(&Aabb::new(q - d, q + d)).hi
        }
    };
    let proven_in = |shape: &PlacedSuperellipse, q: Vec2| upper(shape, q) < 0.0;
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
    // The mean-value bounds ([`slope_bound`], [`second_order_bound`]) need `other`'s gradient
    // bounded over an arc's box; a star's is unbounded at its axes, where its contacts are, and
    // the bound then costs powers for nothing. Measured in instructions a near-touching pair
    // (callgrind): the mixed class (exponents in [0.5, 4]) 88k without the bounds, 76k with
    // them against convex shapes only, 69k also against stars of exponents from 1/2. For a
    // star `own` against such a star the bounds were left out at first (`bench contact`'s
    // stars class, exponents in [0.25, 0.9], 67k without, 77k with); but in the paper's mixed
    // preset, whose resting stars press on each other, those searches took 62 splits each
    // without them and 9 with them, and the preset's first 1,500 steps' tests, replayed, 17%
    // less time. For a star `own` below 1/2 (the thin spikes of `bench contact`'s stars class)
    // they still cost: with them the class ran 6.1-6.8 µs against 5.8-6.3 without, in
    // alternating runs, so against a star they wait for both shapes' exponents from 1/2
    // (against a convex `other` they apply to any `own`, as before).
    let least = |s: &Superellipse| s.exponents().into_iter().fold(f64::INFINITY, f64::min);
    let slopes = least(other.shape()) >= 1.0
        || (least(other.shape()) >= SLOPE_MIN_EXPONENT && least(own) >= SLOPE_MIN_EXPONENT);
    let [ex, ey] = own.exponents();
    let s = own.semi_axes();
    // The first quadrant's halves and their ends' boxes, once: the other quadrants' are their
    // mirror images, bit for bit (outward rounding is symmetric under a change of sign).
    // (The boxes only when a quadrant needs them: an apart pair often has none.)
    // `other`'s cusps: its axes of exponent below 1, where `f_other` has a sharp minimum
    // across the axis (see [`cusp_crossing`]). The ends' float points serve only those: without
    // a cusp, none is computed (two powers an end).
    let cusps = other.shape().exponents().map(|e| e < 1.0);
    let any_cusp = cusps.contains(&true);
    let end_point = |half: &Half, p: f64| {
        if any_cusp { half.point(p) } else { Vec2::ZERO }
    };
    let first = halves(ex, ey, s.x, s.y).map(|h| Half { coarse: true, ..h });
    let mut first_ends: Option<[(End, End); 2]> = None;
    let mut table = [first[0]; 8];
    let mut arcs: Vec<Arc> = Vec::with_capacity(16);
    let mut nodes: Vec<Node> = Vec::with_capacity(32);
    for (k, (fx, fy)) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)]
        .into_iter()
        .enumerate()
    {
        let (sx, sy) = (fx * s.x, fy * s.y);
        // A quadrant whose box is clear of `other` costs one enclosure, usually no power.
        let quadrant = Aabb::new(
            Vec2::new(sx.min(0.0), sy.min(0.0)),
            Vec2::new(sx.max(0.0), sy.max(0.0)),
        );
        if other.lower_bound(&quadrant) >= 0.0 {
            continue;
        }
        let ends = *first_ends.get_or_insert_with(|| first_quadrant_ends(own, &first));
        for (m, (base, ends)) in first.iter().zip(&ends).enumerate() {
            let index = 2 * k + m;
            let half = base.mirrored(fx, fy);
            table[index] = half;
            let (e0, e1) = (ends.0.mirrored(fx, fy), ends.1.mirrored(fx, fy));
            let hull = e0.b.union(&e1.b);
            let lower = other.lower_bound(&hull);
            if lower < 0.0 {
                let (f0, f1) = if slopes {
                    (other.lower_bound(&e0.b), other.lower_bound(&e1.b))
                } else {
                    (f64::NEG_INFINITY, f64::NEG_INFINITY)
                };
                let at = nodes.len() as u32;
                nodes.push(Node::new(e0, f0, end_point(&half, e0.p)));
                nodes.push(Node::new(e1, f1, end_point(&half, e1.p)));
                let lower = if slopes {
                    let (ends, bounds) = ((at, at + 1), (lower, -touch));
                    tighter(&half, other, &mut nodes, ends, &hull, bounds)
                } else {
                    lower
                };
                if lower >= 0.0 {
                    nodes.truncate(at as usize);
                    continue;
                }
                arcs.push(Arc {
                    half: index as u8,
                    crossed: false,
                    e0: at,
                    e1: at + 1,
                    lower,
                });
            }
        }
    }
    // A boundary point `q` as a witness: moved towards `own`'s centre until it is proven
    // inside both (a hair first, more at a spike's tip), kept if deeper than the best so far.
    let (other_axes, other_pose) = (other.shape().semi_axes(), other.pose());
    let try_witness = |best: &mut Option<Witness>, q: Vec2| {
        // Beyond `other`'s box in its frame a point is outside (a term alone is at least 1):
        // no power for most of the tips.
        let l = other_pose.to_local(q);
        if l.x.abs() >= other_axes.x || l.y.abs() >= other_axes.y {
            return;
        }
        let value = other.value(q);
        if !(value < 0.0 && best.is_none_or(|w| value < w.value)) {
            return;
        }
        for k in INWARD {
            let w = q * (1.0 - k);
            // The bound that proves `w` inside `other` is also the witness's value.
            if !proven_in(placed_own, w) {
                continue;
            }
            let v = upper(other, w);
            if v < 0.0 {
                let tau = 0.5 * cell * other.gradient(w).norm();
                if tau.is_finite() && best.is_none_or(|b| v < b.value) {
                    *best = Some(Witness {
                        point: w,
                        value: v,
                        tau,
                    });
                }
                return;
            }
        }
    };
    // The tips first: a star's deepest point is often one, where the middles of the arcs
    // next to it come near only one halving at a time (12.9 splits a search for the stars of
    // `bench contact` without them, 10.5 with them).
    let mut best: Option<Witness> = None;
    for tip in [
        Vec2::new(s.x, 0.0),
        Vec2::new(0.0, s.y),
        Vec2::new(-s.x, 0.0),
        Vec2::new(0.0, -s.y),
    ] {
        try_witness(&mut best, tip);
    }
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
                let (p0, p1) = (nodes[near.e0 as usize].end.p, nodes[near.e1 as usize].end.p);
                let at = table[usize::from(near.half)].point(0.5 * (p0 + p1));
                return Some((Deepest::Beyond, at));
            }
            _ => {}
        }
        let arc = arcs.swap_remove(k);
        let half = table[usize::from(arc.half)];
        let (n0, n1) = (nodes[arc.e0 as usize], nodes[arc.e1 as usize]);
        // Where the arc crosses one of `other`'s cusps, the crossing as a witness (once).
        let mut crossed = arc.crossed;
        if !crossed {
            for (axis, &cusp) in cusps.iter().enumerate() {
                if cusp
                    && let Some(q) =
                        cusp_crossing(&half, (&n0, &n1), |q| axis_of(other.pose(), q, axis))
                {
                    try_witness(&mut best, q);
                    crossed = true;
                }
            }
        }
        let mid = 0.5 * (n0.end.p + n1.end.p);
        if !(mid > n0.end.p && mid < n1.end.p && lower.is_finite()) {
            return None;
        }
        let (em, q) = half.enclose_and_point(mid);
        let fm = if slopes {
            other.lower_bound(&em.b)
        } else {
            f64::NEG_INFINITY
        };
        // (No witness where the middle's box is bounded above the best one, or outside.)
        if fm < best.map_or(0.0, |w| w.value) {
            try_witness(&mut best, q);
        }
        let m = nodes.len() as u32;
        let nm = Node::new(em, fm, q);
        nodes.push(nm);
        for (i0, i1, a, b) in [(arc.e0, m, &n0, &nm), (m, arc.e1, &nm, &n1)] {
            let hull = a.end.b.union(&b.end.b);
            let lower = other.lower_bound(&hull);
            // An arc outside `other` (`f >= 0`) holds no deeper point than any witness (`f < 0`)
            // and nothing within `touch` of its inside.
            if lower < 0.0 {
                // Only an arc that would stay open needs the finer bound.
                let goal = best.map_or(-touch, |w| w.value - w.tau);
                let lower = match best {
                    Some(_) if lower >= goal => lower,
                    _ if slopes => {
                        tighter(&half, other, &mut nodes, (i0, i1), &hull, (lower, goal))
                    }
                    _ => lower,
                };
                if lower >= 0.0 {
                    continue;
                }
                if arcs.len() == MAX_ARCS {
                    return None;
                }
                arcs.push(Arc {
                    half: arc.half,
                    crossed,
                    e0: i0,
                    e1: i1,
                    lower,
                });
            }
        }
    }
    None
}

/// The signed distance-like coordinate of `q` across `other`'s axis `axis` (0: the local `x`,
/// whose term has its cusp on the line `x = 0`).
fn axis_of(pose: &Pose, q: Vec2, axis: usize) -> f64 {
    let l = pose.to_local(q);
    if axis == 0 { l.x } else { l.y }
}

/// Where an arc crosses one of `other`'s cusps, in floating point, or `None` if its ends lie
/// on the same side. Across an axis of a star (`|t|^e`, `e < 1`) `f_other` along `own`'s
/// boundary has a sharp minimum, `f0 + a |p - p0|^e`: a split's middle a distance `d` from the
/// crossing is worse by `a d^e` (for `e = 0.3`, `d = 1e-3` costs `0.1 a`), so the search closed
/// in on it a halving at a time. Counted in `bench contact`'s stars class, such minima were 387
/// of its 955 overlapping searches and took 16.5 splits each, 56% of all. The crossing itself,
/// by the Illinois method on the parameter ([`bracketed_root`], as a push's ray), is a
/// witness within rounding of the minimum; its tolerance then reflects the steep slope there.
/// (Only a witness: it still has to be proven inside both shapes, and every arc bounded.)
fn cusp_crossing(half: &Half, (n0, n1): (&Node, &Node), g: impl Fn(Vec2) -> f64) -> Option<Vec2> {
    let (ga, gb) = (g(n0.point), g(n1.point));
    let product = ga * gb;
    if product.is_nan() || product >= 0.0 {
        return None;
    }
    // The search wants the value below 0 at the first end.
    let sign = if ga < 0.0 { 1.0 } else { -1.0 };
    let (a, b) = (n0.end.p, n1.end.p);
    let p = bracketed_root(
        (a, sign * ga),
        (b, sign * gb),
        4.0 * f64::EPSILON * b.abs(),
        0.0,
        |p| sign * g(half.point(p)),
    );
    Some(half.point(p))
}

/// The support of `shape` (in its frame) in the direction `m`, `max over the shape of m . y`,
/// for any exponents: a rigorous upper bound and a boundary point (in floating point) reaching
/// within `tol` of it, or `None` (a direction that is zero or not finite, or no answer within
/// the budget). A wall contact needs it where no closed form exists: one exponent below 1 and
/// the other above (the shape is not convex, and the dual bound of its convex hull is not
/// tight), or exactly 1 and above (convex, but the dual's point is not on the boundary).
///
/// The maximum lies in the quadrant of `m`'s signs (a reflection into it never lowers
/// `m . y`), on its two halves. A best-first branch and bound as [`deepest_on_boundary`]'s:
/// the bound of an arc is `m . y` at the best corner of the box of its two ends, which holds
/// the arc (both coordinates are monotone along it); candidates are the halves' ends (the tips
/// among them) and every split's middle.
pub(crate) fn support_on_boundary(shape: &Superellipse, m: Vec2, tol: f64) -> Option<(f64, Vec2)> {
    if !(m.x.is_finite() && m.y.is_finite()) || (m.x == 0.0 && m.y == 0.0) {
        return None;
    }
    let [ex, ey] = shape.exponents();
    let s = shape.semi_axes();
    let sign = |v: f64| if v < 0.0 { -1.0 } else { 1.0 };
    let table = halves(ex, ey, sign(m.x) * s.x, sign(m.y) * s.y);
    // (`f64::max` would drop a NaN product: a NaN end makes the bound NaN, and no answer.)
    let larger = |x: f64, y: f64| {
        if x.is_nan() || y.is_nan() {
            f64::NAN
        } else {
            x.max(y)
        }
    };
    let bound = |b: &Aabb| {
        up(up(larger(m.x * b.min.x, m.x * b.max.x)) + up(larger(m.y * b.min.y, m.y * b.max.y)))
    };
    // The mean-value bound along an arc, as [`slope_bound`]'s: `m . gamma(p)` is at most its
    // bound at an end plus the largest rise of its derivative towards the other end. Second
    // order by a smooth maximum, where the box's bound is first order: measured on shapes with
    // exponents 0.56 and 4.4, the box alone kept over 96 arcs open at a tolerance of 1e-4 of
    // the size.
    let tighter = |half: &Half, e0: &End, e1: &End, boxed: f64| {
        let Some((dp, dq)) = half.tangent(e0, e1) else {
            return boxed;
        };
        let (mp, mq) = if half.by_y { (m.y, m.x) } else { (m.x, m.y) };
        let d = Interval::point(dp).scale(mp).plus(dq.scale(mq));
        if !(d.lo.is_finite() && d.hi.is_finite()) {
            return boxed;
        }
        let w = up(e1.p - e0.p);
        let from_start = up(bound(&e0.b) + up(d.hi.max(0.0) * w));
        let from_end = up(bound(&e1.b) + up((-d.lo).max(0.0) * w));
        boxed.min(from_start).min(from_end)
    };
    let mut best = (f64::NEG_INFINITY, Vec2::ZERO);
    let consider = |best: &mut (f64, Vec2), q: Vec2| {
        let v = m.dot(q);
        if v > best.0 {
            *best = (v, q);
        }
    };
    // An arc of `table[half]` between two parameters, its ends' boxes and its bound.
    struct Open {
        half: usize,
        e0: End,
        e1: End,
        bound: f64,
    }
    let mut arcs: Vec<Open> = Vec::with_capacity(16);
    for (k, half) in table.iter().enumerate() {
        let (e0, q0) = half.enclose_and_point(half.lo);
        let (e1, q1) = half.enclose_and_point(half.hi);
        consider(&mut best, q0);
        consider(&mut best, q1);
        let boxed = bound(&e0.b.union(&e1.b));
        let b = tighter(half, &e0, &e1, boxed);
        if boxed.is_nan() || b.is_nan() {
            return None;
        }
        arcs.push(Open {
            half: k,
            e0,
            e1,
            bound: b,
        });
    }
    // The largest bound of the arcs dropped: still a bound of the support.
    let mut dropped = f64::NEG_INFINITY;
    for _ in 0..MAX_SPLITS {
        let Some(k) = (0..arcs.len()).max_by(|&i, &j| arcs[i].bound.total_cmp(&arcs[j].bound))
        else {
            return (dropped - best.0 <= tol).then_some((dropped, best.1));
        };
        let upper = arcs[k].bound.max(dropped);
        if !upper.is_finite() {
            return None;
        }
        if upper - best.0 <= tol {
            return Some((upper, best.1));
        }
        let Open {
            half: h, e0, e1, ..
        } = arcs.swap_remove(k);
        let mid = 0.5 * (e0.p + e1.p);
        if !(mid > e0.p && mid < e1.p) || arcs.len() + 2 > MAX_ARCS {
            return None;
        }
        let (em, q) = table[h].enclose_and_point(mid);
        consider(&mut best, q);
        // An arc whose bound is below the best candidate holds nothing better: dropped.
        for (lo, hi) in [(e0, em), (em, e1)] {
            let mut b = bound(&lo.b.union(&hi.b));
            if b.is_nan() {
                return None;
            }
            if b > best.0 {
                b = tighter(&table[h], &lo, &hi, b);
            }
            if b > best.0 {
                arcs.push(Open {
                    half: h,
                    e0: lo,
                    e1: hi,
                    bound: b,
                });
            } else {
                dropped = dropped.max(b);
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    //! The mean-value bound's parts against plain formulas written again: finite differences
    //! of the boundary's parametrisation and of `f`, and `f` sampled densely along the arc.
    use super::*;
    use crate::shape::Superellipse;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn exponent(rng: &mut ChaCha8Rng) -> f64 {
        match rng.random_range(0..4) {
            0 => 1.0,
            1 => 2.0,
            2 => rng.random_range(0.25..1.0),
            _ => rng.random_range(1.0..8.0),
        }
    }

    /// The boundary point of a half at `p`, `(s_p p, s_q (1 - p^e_p)^(1/e_q))` in (x, y).
    fn plain_point(h: &Half, e_q: f64, p: f64) -> [f64; 2] {
        let q = (1.0 - p.powf(h.e_p_float)).max(0.0).powf(1.0 / e_q);
        let (a, b) = (h.s_p * p, h.s_q * q);
        if h.by_y { [b, a] } else { [a, b] }
    }

    /// `f` of a placed superellipse, written again.
    fn plain_f(s: &Superellipse, pose: &Pose, x: [f64; 2]) -> f64 {
        let (c, t) = (pose.center(), pose.angle());
        let (dx, dy) = (x[0] - c.x, x[1] - c.y);
        let u = t.cos() * dx + t.sin() * dy;
        let v = -t.sin() * dx + t.cos() * dy;
        let [sx, sy] = [s.semi_axes().x, s.semi_axes().y];
        let [ex, ey] = s.exponents();
        (u / sx).abs().powf(ex) + (v / sy).abs().powf(ey) - 1.0
    }

    fn random_arc(rng: &mut ChaCha8Rng) -> (Half, f64, f64, f64) {
        let (ex, ey) = (exponent(rng), exponent(rng));
        let (sx, sy) = (rng.random_range(0.2..1.0), rng.random_range(0.2..1.0));
        let (kx, ky) = (
            if rng.random_bool(0.5) { 1.0 } else { -1.0 },
            if rng.random_bool(0.5) { 1.0 } else { -1.0 },
        );
        let h = halves(ex, ey, kx * sx, ky * sy)[rng.random_range(0..2)];
        let e_q = if h.by_y { ex } else { ey };
        let (a, b) = (rng.random_range(h.lo..h.hi), rng.random_range(h.lo..h.hi));
        (h, e_q, a.min(b), a.max(b))
    }

    /// A convex grain pierced by a star's spike: `f_star` along the grain's boundary has its
    /// minimum where the boundary crosses the spike's axis, a cusp. The search answers with
    /// that crossing (moved a hair inward), within a millionth of the star's size of the axis;
    /// a split's middle is seldom nearer than a thousandth. And the answer is the minimum of a
    /// dense sampling of the boundary, up to the hair, but for a few.
    #[test]
    fn a_spike_through_a_boundary_is_answered_on_its_axis() {
        let mut rng = ChaCha8Rng::seed_from_u64(19);
        let mut on_axis = 0;
        let (mut misses, mut worst) = (0, 0.0f64);
        for n in 0..200 {
            let own = Superellipse::new(
                [rng.random_range(0.3..0.6), rng.random_range(0.3..0.6)],
                [rng.random_range(1.0..4.0), rng.random_range(1.0..4.0)],
            )
            .unwrap();
            let star = Superellipse::new(
                [rng.random_range(0.3..0.5), rng.random_range(0.2..0.4)],
                [rng.random_range(0.25..2.0), rng.random_range(0.25..0.9)],
            )
            .unwrap();
            // The star's x axis (its cusp is across it: `e_y < 1`) points at `own`, offset a
            // little from `own`'s centre; the tip half a spike inside `own`'s boundary.
            let theta = rng.random_range(0.0..std::f64::consts::TAU);
            let (dir, across) = (
                Vec2::new(theta.cos(), theta.sin()),
                Vec2::new(-theta.sin(), theta.cos()),
            );
            let reach = super::super::certified::radial_to_boundary(&own, dir)
                .unwrap()
                .norm();
            let offset = rng.random_range(-0.05..0.05);
            let centre = dir * (reach + 0.5 * star.semi_axes().x) + across * offset;
            let pose = Pose::new(centre, theta + std::f64::consts::PI).unwrap();
            let other = PlacedSuperellipse::new(star, pose);
            let placed = PlacedSuperellipse::new(own, Pose::ORIGIN);
            let cell = 1.0 / 128.0;
            let (Deepest::At(w), _) = deepest_on_boundary(&placed, &other, cell, 0.0).unwrap()
            else {
                panic!("{n}: a spike inside, no overlap found");
            };
            if pose.to_local(w).y.abs() <= 1e-6 * star.semi_axes().y {
                on_axis += 1;
            }
            // The tolerance at a cusp is wide (the gradient there is steep), so compare with
            // the sampled minimum itself, which the answer should be up to the hair it was
            // moved inward (`a 1e-9^e`, below 0.01 for these exponents).
            let value = star.value(&pose, w);
            let least = (0..20_000)
                .map(|k| {
                    let t = k as f64 / 20_000.0 * std::f64::consts::TAU;
                    star.value(&pose, own.boundary_point(t))
                })
                .fold(f64::INFINITY, f64::min);
            if value > least + 0.01 {
                misses += 1;
                worst = f64::max(worst, value - least);
            }
        }
        // (A search may also stop earlier, on a middle whose steep slope gives it a wide
        // tolerance.)
        assert!(on_axis >= 150, "{on_axis} of 200 answers on the axis");
        // Without the crossing, 161 of the 200 answers were 0.01 to 0.15 above the sampled
        // minimum (the searches stopped on middles near the axis, whose steep slope widened
        // their tolerance); with it, one, by 0.017 (a second, deeper stretch of the boundary).
        assert!(
            misses <= 4 && worst < 0.05,
            "{misses} answers above the sampled minimum, by up to {worst}"
        );
    }

    /// A half and its ends' boxes mirrored from the first quadrant are those computed in the
    /// quadrant itself, bit for bit (the search computes them once and mirrors them).
    #[test]
    fn mirrored_halves_are_the_quadrants_own() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        for _ in 0..500 {
            let (ex, ey) = (exponent(&mut rng), exponent(&mut rng));
            let (sx, sy) = (rng.random_range(0.2..1.0), rng.random_range(0.2..1.0));
            let first = halves(ex, ey, sx, sy);
            for (fx, fy) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
                let own = halves(ex, ey, fx * sx, fy * sy);
                for m in 0..2 {
                    let (base, h) = (first[m].mirrored(fx, fy), own[m]);
                    assert_eq!((base.s_p, base.s_q), (h.s_p, h.s_q));
                    let p = rng.random_range(h.lo..=h.hi);
                    for p in [h.lo, h.hi, p] {
                        assert_eq!(first[m].enclose(p).mirrored(fx, fy), h.enclose(p));
                        assert_eq!(base.point(p), h.point(p));
                    }
                }
            }
        }
    }

    /// A random arc and a random other shape (exponents from 1/2) placed near its middle: what
    /// the bounds along an arc are checked on.
    #[derive(Clone, Copy)]
    struct ArcCase {
        h: Half,
        e_q: f64,
        p0: f64,
        p1: f64,
        other: Superellipse,
        pose: Pose,
        placed: PlacedSuperellipse,
        e0: End,
        e1: End,
        hull: Aabb,
        values: (f64, f64),
    }

    impl ArcCase {
        fn new(rng: &mut ChaCha8Rng) -> ArcCase {
            let (h, e_q, p0, p1) = random_arc(rng);
            let other = Superellipse::new(
                [rng.random_range(0.2..1.0), rng.random_range(0.2..1.0)],
                [exponent(rng).max(0.5), exponent(rng).max(0.5)],
            )
            .unwrap();
            let mid = plain_point(&h, e_q, 0.5 * (p0 + p1));
            let pose = Pose::new(
                Vec2::new(
                    mid[0] + rng.random_range(-0.8..0.8),
                    mid[1] + rng.random_range(-0.8..0.8),
                ),
                rng.random_range(0.0..6.3),
            )
            .unwrap();
            let placed = PlacedSuperellipse::new(other, pose);
            let (e0, e1) = (h.enclose(p0), h.enclose(p1));
            let values = (placed.lower_bound(&e0.b), placed.lower_bound(&e1.b));
            ArcCase {
                h,
                e_q,
                p0,
                p1,
                other,
                pose,
                placed,
                e0,
                e1,
                hull: e0.b.union(&e1.b),
                values,
            }
        }

        #[allow(clippy::type_complexity)]
        fn parts(&self) -> (Half, PlacedSuperellipse, (End, End), Aabb, (f64, f64)) {
            (
                self.h,
                self.placed,
                (self.e0, self.e1),
                self.hull,
                self.values,
            )
        }

        /// That `bound` is below the least of `f_other` at 2,001 points along the arc (by the
        /// formulas written again, up to their rounding), and that least.
        fn assert_below(&self, bound: f64) -> f64 {
            let least = (0..=2000)
                .map(|k| {
                    let p = self.p0 + (self.p1 - self.p0) * f64::from(k) / 2000.0;
                    plain_f(&self.other, &self.pose, plain_point(&self.h, self.e_q, p))
                })
                .fold(f64::INFINITY, f64::min);
            assert!(
                bound <= least + 1e-9 * (1.0 + least.abs()),
                "bound {bound} above the sampled minimum {least} on [{}, {}]",
                self.p0,
                self.p1
            );
            least
        }
    }

    /// The parabola's floor against its least over a fine grid, for random coefficients and
    /// for the edge a review found: a subnormal `c`, where `down(4c)` is negative (the floor
    /// came out at 5.5e303 for a least of -0.50001).
    #[test]
    fn the_quadratic_floor_is_below_the_parabola() {
        let mut rng = ChaCha8Rng::seed_from_u64(33);
        let mut cases: Vec<[f64; 4]> = vec![
            [-0.5, -1e-3, 1e-309, 0.01],
            [-0.5, -1e-300, 1e-309, 0.01],
            [-0.5, -1e-3, f64::MIN_POSITIVE, 0.01],
        ];
        for _ in 0..2000 {
            let c = match rng.random_range(0..3) {
                0 => rng.random_range(-10.0..10.0),
                1 => rng.random_range(0.0..1e-300),
                _ => 0.0,
            };
            cases.push([
                rng.random_range(-1.0..1.0),
                rng.random_range(-5.0..5.0),
                c,
                rng.random_range(0.0..1.0),
            ]);
        }
        for [a, b, c, h] in cases {
            let floor = quadratic_floor(a, b, c, h);
            let least = (0..=1000)
                .map(|k| {
                    let t = h * f64::from(k) / 1000.0;
                    a + b * t + c * t * t
                })
                .fold(f64::INFINITY, f64::min);
            assert!(
                floor <= least + 1e-12 * (1.0 + least.abs()),
                "floor {floor} above {least} for a {a}, b {b}, c {c}, h {h}"
            );
        }
    }

    /// The boundary's second derivative against central differences of the plain formula.
    #[test]
    fn the_curvature_encloses_finite_differences() {
        let mut rng = ChaCha8Rng::seed_from_u64(31);
        let mut checked = 0;
        while checked < 2000 {
            let (h, e_q, p0, p1) = random_arc(&mut rng);
            let (e0, e1) = (h.enclose(p0), h.enclose(p1));
            let Some(dqq) = h
                .tangent_factors(&e0, &e1)
                .and_then(|t| h.curvature(&e0, &e1, t.2))
            else {
                continue;
            };
            // Steps of 1e-4 (no finer: a second difference loses `eps / d^2`).
            let p = rng.random_range(p0..=p1);
            let d = 1e-4;
            if p - d < p0 || p + d > p1 {
                continue;
            }
            let q_axis = usize::from(!h.by_y);
            let at = |p: f64| plain_point(&h, e_q, p)[q_axis];
            let fd = (at(p + d) - 2.0 * at(p) + at(p - d)) / (d * d);
            let slack = 1e-3 * (1.0 + fd.abs());
            assert!(
                dqq.lo - slack <= fd && fd <= dqq.hi + slack,
                "q'' = {fd} outside {dqq:?} at p = {p} in [{p0}, {p1}] (e_p {}, e_q {e_q})",
                h.e_p_float
            );
            checked += 1;
        }
    }

    /// The second-order bound is below `f_other` at every sample of the arc, against every
    /// class of other shape (stars off their axes included); and it is the tighter of the two
    /// bounds on many arcs, and near the minimum of most (else it would not be worth its cost).
    #[test]
    fn the_second_order_bound_is_below_every_sample_of_the_arc() {
        let mut rng = ChaCha8Rng::seed_from_u64(32);
        let (mut checked, mut tighter_than_slope, mut closes) = (0, 0, 0);
        while checked < 1500 {
            let case = ArcCase::new(&mut rng);
            let (h, placed, (e0, e1), hull, values) = case.parts();
            let second = || {
                let slopes = placed.axis_slopes(&hull)?;
                let at_ends = (slope_at(&h, &placed, &e0)?, slope_at(&h, &placed, &e1)?);
                let t = h.tangent_factors(&e0, &e1)?;
                second_order_bound(&h, &placed, (&e0, &e1), t, (&hull, slopes), values, at_ends)
            };
            let Some(bound) = second() else {
                continue;
            };
            let least = case.assert_below(bound);
            let slope = placed
                .gradient_enclosure(&hull)
                .and_then(|g| slope_bound(&h, (&e0, &e1), h.tangent(&e0, &e1)?, g, values));
            if slope.is_none_or(|b| bound > b) {
                tighter_than_slope += 1;
            }
            if least - bound < 1e-3 * (case.p1 - case.p0) {
                closes += 1;
            }
            checked += 1;
        }
        assert!(
            tighter_than_slope > 300 && closes > 300,
            "tighter {tighter_than_slope}, within 1e-3 of the minimum {closes}"
        );
    }

    #[test]
    fn the_tangent_encloses_finite_differences() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut checked = 0;
        while checked < 2000 {
            let (h, e_q, p0, p1) = random_arc(&mut rng);
            let Some((dp, dq)) = h.tangent(&h.enclose(p0), &h.enclose(p1)) else {
                continue;
            };
            assert_eq!(dp, h.s_p);
            let p = rng.random_range(p0..=p1);
            let d = 1e-7 * (p1 - p0).max(1e-6);
            if p - d < p0 || p + d > p1 {
                continue;
            }
            let (a, b) = (plain_point(&h, e_q, p - d), plain_point(&h, e_q, p + d));
            let q_axis = usize::from(!h.by_y);
            let fd = (b[q_axis] - a[q_axis]) / (2.0 * d);
            let slack = 1e-5 * (1.0 + fd.abs());
            assert!(
                dq.lo - slack <= fd && fd <= dq.hi + slack,
                "d q/d p = {fd} outside {dq:?} at p = {p} in [{p0}, {p1}]"
            );
            checked += 1;
        }
    }

    #[test]
    fn the_gradient_encloses_finite_differences() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let mut checked = 0;
        while checked < 2000 {
            let s = Superellipse::new(
                [rng.random_range(0.2..1.0), rng.random_range(0.2..1.0)],
                [exponent(&mut rng), exponent(&mut rng)],
            )
            .unwrap();
            let angle = if rng.random_bool(0.3) {
                0.0
            } else {
                rng.random_range(0.0..6.3)
            };
            let pose = Pose::new(
                Vec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)),
                angle,
            )
            .unwrap();
            let placed = PlacedSuperellipse::new(s, pose);
            let lo = Vec2::new(rng.random_range(-1.5..1.5), rng.random_range(-1.5..1.5));
            let size = rng.random_range(1e-4..0.3);
            let cell = Aabb::new(lo, lo + Vec2::new(size, size));
            let Some(g) = placed.gradient_enclosure(&cell) else {
                continue;
            };
            let x = [
                rng.random_range(lo.x..lo.x + size),
                rng.random_range(lo.y..lo.y + size),
            ];
            let d = 1e-7;
            for axis in 0..2 {
                let (mut a, mut b) = (x, x);
                a[axis] -= d;
                b[axis] += d;
                let fd = (plain_f(&s, &pose, b) - plain_f(&s, &pose, a)) / (2.0 * d);
                let slack = 1e-4 * (1.0 + fd.abs());
                assert!(
                    g[axis].lo - slack <= fd && fd <= g[axis].hi + slack,
                    "df/dx{axis} = {fd} outside {:?} at {x:?}",
                    g[axis]
                );
            }
            checked += 1;
        }
    }

    /// The bound is below `f_other` all along the arc, sampled at 2,000 points.
    #[test]
    fn the_slope_bound_is_below_every_sample_of_the_arc() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let (mut checked, mut tighter_than_box) = (0, 0);
        while checked < 1000 {
            let case = ArcCase::new(&mut rng);
            let (h, placed, (e0, e1), hull, values) = case.parts();
            let Some(g) = placed.gradient_enclosure(&hull) else {
                continue;
            };
            let Some(t) = h.tangent(&e0, &e1) else {
                continue;
            };
            let Some(bound) = slope_bound(&h, (&e0, &e1), t, g, values) else {
                continue;
            };
            case.assert_below(bound);
            if bound > placed.lower_bound(&hull) {
                tighter_than_box += 1;
            }
            checked += 1;
        }
        assert!(
            tighter_than_box > 100,
            "the bound helped {tighter_than_box} times"
        );
    }

    /// The support by dense sampling of the boundary, written again: as a graph over each
    /// scaled axis (so that neither a flat face nor a spike's tip is skipped), 20,000 points
    /// each, in the quadrant of the direction.
    fn sampled_support(s: [f64; 2], e: [f64; 2], m: [f64; 2]) -> f64 {
        let n = 20_000;
        let mut best = f64::NEG_INFINITY;
        for i in 0..=n {
            let t = f64::from(i) / f64::from(n);
            let other = |t: f64, ep: f64, eq: f64| (1.0 - t.powf(ep)).max(0.0).powf(1.0 / eq);
            for (u, v) in [(t, other(t, e[0], e[1])), (other(t, e[1], e[0]), t)] {
                best = best.max(m[0].abs() * s[0] * u + m[1].abs() * s[1] * v);
            }
        }
        best
    }

    /// The support's bound is never below the sampled support, the point reaches within the
    /// tolerance of it and lies on the boundary, for shapes with one exponent up to 1 and the
    /// other above (what walls ask of it), and for stars and convex shapes too.
    #[test]
    fn the_support_search_bounds_the_sampled_support() {
        let mut rng = ChaCha8Rng::seed_from_u64(6);
        for case in 0..300 {
            // Exactly 1 now and then: the diamond's edge and a convex shape with a flat side.
            let low = if case % 7 == 0 {
                1.0
            } else {
                rng.random_range(0.25..1.0)
            };
            let high = rng.random_range(1.0..8.0);
            let e = match case % 4 {
                0 => [low, high],
                1 => [high, low],
                2 => [low, rng.random_range(0.25..1.0)],
                _ => [high, rng.random_range(1.0..8.0)],
            };
            let sa = [rng.random_range(0.1..2.0), rng.random_range(0.1..2.0)];
            let angle = rng.random_range(0.0..std::f64::consts::TAU);
            let m = [angle.cos(), angle.sin()];
            let shape = Superellipse::new(sa, e).unwrap();
            let tol = 1e-6 * sa[0].max(sa[1]);
            let (bound, point) = support_on_boundary(&shape, Vec2::new(m[0], m[1]), tol)
                .unwrap_or_else(|| panic!("no answer for {sa:?} {e:?} towards {m:?}"));
            let sampled = sampled_support(sa, e, m);
            let what = format!("{sa:?} {e:?} towards {m:?}");
            assert!(
                bound >= sampled - 1e-12,
                "{what}: bound {bound} below the sampled support {sampled}"
            );
            assert!(
                bound <= sampled + tol + 1e-9,
                "{what}: bound {bound} looser than {tol} over {sampled}"
            );
            let reached = m[0] * point.x + m[1] * point.y;
            assert!(
                reached >= bound - tol,
                "{what}: point reaches {reached} of {bound}"
            );
            let f = (point.x / sa[0]).abs().powf(e[0]) + (point.y / sa[1]).abs().powf(e[1]);
            assert!(
                (f - 1.0).abs() < 1e-9,
                "{what}: point {point:?} off the boundary ({f})"
            );
        }
    }
}

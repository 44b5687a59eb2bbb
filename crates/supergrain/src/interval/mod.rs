//! Rigorous interval enclosures (paper II-A, SPEC §2).
//!
//! A small interval type of our own: the narrow phase evaluates millions of enclosures per
//! second and needs only `+`, scaling by a constant and `|t|^e`. A general IEEE-1788 library
//! (inari) is ~80x slower for `pow` and switches the rounding mode; here every operation is
//! done in round-to-nearest and its result widened outward by at least one ulp ([`up`],
//! [`down`]), which encloses the exact result because round-to-nearest errs by at most half an
//! ulp.

mod implicit;
mod pow;

pub use implicit::{ImplicitShape, Minima, PlacedSuperellipse, Side};
pub use pow::{Exponent, pow_down, pow_up};

/// A number no smaller than `x + ulp(x)` (and so than the exact result `x` was rounded from):
/// `x + (|x| 2^-52 + MIN_POSITIVE)`. Branch-free, unlike `next_up`, which matters in the hot
/// loop. For finite `x` and `+inf`; the extra `MIN_POSITIVE` covers 0 and subnormals.
#[inline(always)]
pub fn up(x: f64) -> f64 {
    x + (x.abs() * f64::EPSILON + f64::MIN_POSITIVE)
}

/// A number no larger than `x - ulp(x)`; for finite `x` and `-inf` (see [`up`]).
#[inline(always)]
pub fn down(x: f64) -> f64 {
    x - (x.abs() * f64::EPSILON + f64::MIN_POSITIVE)
}

/// A closed interval `[lo, hi]` of reals, `lo <= hi`; the ends may be infinite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    pub lo: f64,
    pub hi: f64,
}

impl Interval {
    pub const fn new(lo: f64, hi: f64) -> Self {
        Interval { lo, hi }
    }

    /// The degenerate interval `[x, x]`.
    pub const fn point(x: f64) -> Self {
        Interval { lo: x, hi: x }
    }

    pub fn contains(&self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }

    pub fn width(&self) -> f64 {
        self.hi - self.lo
    }

    /// `[lo + a.lo, hi + a.hi]`, rounded outward.
    #[inline]
    pub fn plus(self, o: Interval) -> Interval {
        Interval::new(down(self.lo + o.lo), up(self.hi + o.hi))
    }

    /// `self - c` for an exact constant `c`, rounded outward.
    #[inline]
    pub fn sub_scalar(self, c: f64) -> Interval {
        Interval::new(down(self.lo - c), up(self.hi - c))
    }

    /// `k * self` for an exact constant `k`, rounded outward.
    #[inline]
    pub fn scale(self, k: f64) -> Interval {
        let (a, b) = if k >= 0.0 {
            (self.lo * k, self.hi * k)
        } else {
            (self.hi * k, self.lo * k)
        };
        Interval::new(down(a), up(b))
    }

    /// `self * o`, rounded outward (finite ends).
    #[inline]
    pub fn times(self, o: Interval) -> Interval {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        let lo = p[0].min(p[1]).min(p[2]).min(p[3]);
        let hi = p[0].max(p[1]).max(p[2]).max(p[3]);
        Interval::new(down(lo), up(hi))
    }

    /// `self / k` for an exact constant `k > 0`, rounded outward.
    #[inline]
    pub fn div_positive(self, k: f64) -> Interval {
        Interval::new(down(self.lo / k), up(self.hi / k))
    }

    /// The range of `|t|`: `[lo, hi]` if positive, `[-hi, -lo]` if negative,
    /// `[0, max(-lo, hi)]` if it straddles zero (paper II-A, step 2). Exact.
    #[inline(always)]
    pub fn abs(self) -> Interval {
        if self.lo > 0.0 {
            self
        } else if self.hi < 0.0 {
            Interval::new(-self.hi, -self.lo)
        } else {
            Interval::new(0.0, (-self.lo).max(self.hi))
        }
    }

    /// An enclosure of `|t|^e` for `e > 0` over this interval (paper II-A, step 3).
    #[inline(always)]
    pub fn abs_pow(self, e: Exponent) -> Interval {
        let a = self.abs();
        Interval::new(e.pow_down(a.lo), e.pow_up(a.hi))
    }
}

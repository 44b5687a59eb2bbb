//! Outward-rounded powers `x^e` for `x >= 0` (`e > 0` for the shapes' terms; the slopes and
//! curvatures take `e - 1` and `e - 2`, which may be negative or 0).
//!
//! The paper found `pow` to dominate the run time and special-cased `e = 1` and `e = 2`
//! (paper IV-A); we also do `e = 3`, `4` and `0.5` with exactly rounded operations, which each
//! err by at most half an ulp, so one outward step per operation encloses the truth. Any other
//! exponent goes through `powf`, which glibc computes to within one ulp; two outward steps each
//! way are safe.

use super::{down, up};

/// The exponent, sorted once so the hot loop does not compare floats to pick a method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Exponent {
    One,
    Two,
    Three,
    Four,
    Half,
    Other(f64),
}

impl Exponent {
    pub fn new(e: f64) -> Self {
        match e {
            1.0 => Exponent::One,
            2.0 => Exponent::Two,
            3.0 => Exponent::Three,
            4.0 => Exponent::Four,
            0.5 => Exponent::Half,
            _ => Exponent::Other(e),
        }
    }

    /// A lower bound of `x^e` for `x >= 0`; finite and never negative.
    #[inline(always)]
    pub fn pow_down(self, x: f64) -> f64 {
        let r = match self {
            Exponent::One => x,
            Exponent::Two => down(x * x),
            Exponent::Three => down(down(x * x) * x),
            Exponent::Four => {
                let s = down(x * x);
                down(s * s)
            }
            Exponent::Half => down(x.sqrt()),
            Exponent::Other(e) => down(down(x.powf(e))),
        };
        finite_lower(r)
    }

    /// An upper bound of `x^e` for `x >= 0`; at `x = 0`, `0` for `e > 0`, and `powf`'s `1`
    /// or `inf` (rounded up) for `e = 0` or `e < 0` (the slopes' and curvatures' exponents
    /// `e - 1`, `e - 2`; found by a review: 0 was returned for them too).
    #[inline(always)]
    pub fn pow_up(self, x: f64) -> f64 {
        if x == 0.0 && !matches!(self, Exponent::Other(e) if e <= 0.0) {
            return 0.0;
        }
        match self {
            Exponent::One => x,
            Exponent::Two => up(x * x),
            Exponent::Three => up(up(x * x) * x),
            Exponent::Four => {
                let s = up(x * x);
                up(s * s)
            }
            Exponent::Half => up(x.sqrt()),
            Exponent::Other(e) => up(up(x.powf(e))),
        }
    }

    /// `(pow_down(x), pow_up(x))` and the plain `x^e` they were rounded from, with one `powf`
    /// where two calls would make two: the same bits as [`Self::pow_down`] and
    /// [`Self::pow_up`], for the boundary search, which wants all three of one parameter.
    #[inline(always)]
    pub fn pow_all(self, x: f64) -> (f64, f64, f64) {
        let Exponent::Other(e) = self else {
            return (self.pow_down(x), self.pow_up(x), plain(self, x));
        };
        let r = x.powf(e);
        let lo = finite_lower(down(down(r)));
        let hi = if x == 0.0 && e > 0.0 { 0.0 } else { up(up(r)) };
        (lo, hi, r)
    }
}

/// Bases and powers within which [`Exponent::pow_down_coarse`] and
/// [`Exponent::pow_up_coarse`] use single precision: far inside `f32`'s normal range, so that
/// its relative error bounds hold (and `|ln b| <= 19` for a base `b` there).
const COARSE_RANGE: (f64, f64) = (1e-8, 1e8);
/// The largest `|e|` for a power in single precision: the pad grows with it.
const COARSE_MAX_EXPONENT: f64 = 16.0;

/// `x^e` in single precision and its relative error bound, or `None` outside
/// [`COARSE_RANGE`] and [`COARSE_MAX_EXPONENT`].
///
/// With `b` and `k` the base and the exponent rounded to `f32` (each within `2^-24` relative;
/// an exponent below `f32`'s normal range, `|e| < 1.2e-38`, within `2^-150`, which moves
/// `b^e` by less than `19 * 2^-150`, far inside the pad's constant)
/// and `r` glibc's `powf(b, k)` (within one ulp of `f32`, `2^-23` relative; its
/// implementation states 0.82 ulp): `x^e = b^k (x/b)^e b^(e-k)`, whose factors are within
/// `exp(|e| 2^-24)` and `exp(19 |e| 2^-24)` of 1. So `x^e` is within a relative
/// `2^-23 (4 + 11 |e|)` of `r`: 22 `|e|` halves of an `f32` ulp for the roundings of the
/// base and the exponent, and four ulps for `powf`, the second-order terms and the rounding
/// of the pad's product in `f64`. No branch on the rounding's direction: the pad covers
/// both (a branch per power cost more than single precision saved).
#[inline(always)]
fn coarse(x: f64, e: f64) -> Option<(f64, f64)> {
    // glibc's `powf` is the one whose error bound is on record (checked on x86_64 against
    // mpmath); any other C library takes the double-precision power.
    if !cfg!(all(target_os = "linux", target_env = "gnu")) {
        return None;
    }
    let (lo, hi) = COARSE_RANGE;
    if !(x >= lo && x <= hi && e.abs() <= COARSE_MAX_EXPONENT) {
        return None;
    }
    let r = f64::from((x as f32).powf(e as f32));
    if !(r >= lo && r <= hi) {
        return None;
    }
    Some((r, (4.0 + 11.0 * e.abs()) * f64::from(f32::EPSILON)))
}

impl Exponent {
    /// A lower bound of `x^e` for `x >= 0`, within a relative `2 (4 + 11 |e|) 2^-23` of it
    /// (`3.6e-6` for `e = 1`), by a power in single precision, about 2.5 times the throughput of
    /// `f64`'s here ([`coarse`]). For the boundary search's bounds of arcs, which need a bound,
    /// not a tight one (their tolerances are a fraction of a final cell); the witnesses'
    /// proofs keep [`Self::pow_down`]. Outside the single-precision range, and for the
    /// exponents with exact methods, [`Self::pow_down`].
    #[inline(always)]
    pub fn pow_down_coarse(self, x: f64) -> f64 {
        if let Exponent::Other(e) = self
            && let Some((r, pad)) = coarse(x, e)
        {
            return r * (1.0 - pad);
        }
        self.pow_down(x)
    }

    /// An upper bound of `x^e` for `x >= 0`, as [`Self::pow_down_coarse`].
    #[inline(always)]
    pub fn pow_up_coarse(self, x: f64) -> f64 {
        if let Exponent::Other(e) = self
            && let Some((r, pad)) = coarse(x, e)
        {
            return r * (1.0 + pad);
        }
        self.pow_up(x)
    }
}

/// A rounded-down power made finite and never negative: an overflowing power makes
/// `down(inf)` NaN, and the true value is then above `f64::MAX`.
#[inline(always)]
fn finite_lower(r: f64) -> f64 {
    if r.is_nan() {
        f64::MAX
    } else {
        r.clamp(0.0, f64::MAX)
    }
}

/// `x^e` in plain floating point, as `powf` would give it for the exponents with no method of
/// their own.
fn plain(e: Exponent, x: f64) -> f64 {
    match e {
        Exponent::One => x,
        Exponent::Two => x.powf(2.0),
        Exponent::Three => x.powf(3.0),
        Exponent::Four => x.powf(4.0),
        Exponent::Half => x.powf(0.5),
        Exponent::Other(e) => x.powf(e),
    }
}

/// A lower bound of `x^e` (`x >= 0`, `e > 0`).
pub fn pow_down(x: f64, e: f64) -> f64 {
    Exponent::new(e).pow_down(x)
}

/// An upper bound of `x^e` (`x >= 0`, `e > 0`).
pub fn pow_up(x: f64, e: f64) -> f64 {
    Exponent::new(e).pow_up(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At 0 a power of a negative exponent is infinite and of exponent 0 is 1: an upper bound
    /// of 0 there would be a wrong proof (`|u|^(e - 2)` of a star's curvature).
    #[test]
    fn powers_of_zero_are_bounded_above_for_every_exponent() {
        for e in [-1.7, -0.5, 0.0, 0.3, 1.0, 2.0, 2.5] {
            let k = Exponent::new(e);
            let truth = if e < 0.0 {
                f64::INFINITY
            } else if e == 0.0 {
                1.0
            } else {
                0.0
            };
            for hi in [k.pow_up(0.0), k.pow_up_coarse(0.0), k.pow_all(0.0).1] {
                assert!(hi >= truth, "0^{e}: upper bound {hi}");
            }
            for lo in [k.pow_down(0.0), k.pow_down_coarse(0.0), k.pow_all(0.0).0] {
                assert!(lo <= truth, "0^{e}: lower bound {lo}");
            }
        }
    }

    /// One `powf` gives the same bits as the two separate bounds and the plain power, for
    /// every kind of exponent, at 0, 1, tiny, huge and ordinary bases.
    #[test]
    fn pow_all_is_pow_down_pow_up_and_powf() {
        let bases = [0.0, 1e-300, 1e-9, 0.3, 0.5, 0.999_999, 1.0, 1.7, 1e9, 1e300];
        for e in [
            1.0, 2.0, 3.0, 4.0, 0.5, 0.25, 0.7, 1.3, 7.5, 400.0, 0.0, -0.5, -1.7,
        ] {
            let k = Exponent::new(e);
            for x in bases {
                let (lo, hi, r) = k.pow_all(x);
                assert_eq!(lo.to_bits(), k.pow_down(x).to_bits(), "{e} {x}");
                assert_eq!(hi.to_bits(), k.pow_up(x).to_bits(), "{e} {x}");
                assert_eq!(r.to_bits(), x.powf(e).to_bits(), "{e} {x}");
            }
        }
    }
}

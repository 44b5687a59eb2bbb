//! Outward-rounded powers `x^e` for `x >= 0`, `e > 0`.
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
        // An overflowing power makes `down(inf)` NaN: the true value is then above f64::MAX.
        if r.is_nan() {
            f64::MAX
        } else {
            r.clamp(0.0, f64::MAX)
        }
    }

    /// An upper bound of `x^e` for `x >= 0`.
    #[inline(always)]
    pub fn pow_up(self, x: f64) -> f64 {
        if x == 0.0 {
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
}

/// A lower bound of `x^e` (`x >= 0`, `e > 0`).
pub fn pow_down(x: f64, e: f64) -> f64 {
    Exponent::new(e).pow_down(x)
}

/// An upper bound of `x^e` (`x >= 0`, `e > 0`).
pub fn pow_up(x: f64, e: f64) -> f64 {
    Exponent::new(e).pow_up(x)
}

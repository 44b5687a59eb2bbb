//! Outward-rounded powers `x^e` for `x >= 0`, `e > 0`.
//!
//! The paper found `pow` to dominate the run time and special-cased `e = 1` and `e = 2`
//! (paper IV-A); we also do `e = 3`, `4` and `0.5` with exactly rounded operations, which each
//! err by at most half an ulp, so one outward step per operation encloses the truth.
//!
//! Any other exponent goes through [`pow_with_bound`], our own `2^(e log2 x)` with a proven
//! error bound, about three times faster than libm's `powf` (`docs/bench/pow.txt`): libm rounds
//! to within an ulp, which costs a long double-double evaluation, while an enclosure only needs
//! a bound, and a bound of a few hundred ulps costs a short series. Outside the range where
//! the bound is proven (subnormal or huge arguments, huge exponents) it falls back to `powf`,
//! which glibc computes to within one ulp, widened by two outward steps each way.

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
            Exponent::Other(e) => match pow_with_bound(x, e) {
                Some((r, w)) => down(r - r * w),
                // A cell straddling the shape's axis asks for 0^e: no call needed.
                None if x == 0.0 => 0.0,
                None => down(down(x.powf(e))),
            },
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
            Exponent::Other(e) => match pow_with_bound(x, e) {
                Some((r, w)) => up(r + r * w),
                None => up(up(x.powf(e))),
            },
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

/// The unit roundoff of round-to-nearest: every `+ - * /` errs by at most `U` of its result.
const U: f64 = f64::EPSILON / 2.0;

/// Index bits of the logarithm's table: `m` in `[1, 2)` is split into 128 slices.
const LOG_BITS: u32 = 7;
/// Index bits of the exponential's table: `2^(j / 64)`.
const EXP_BITS: u32 = 6;

/// `|r| = |m / c_i - 1|` with `c_i` a slice's midpoint is at most `2^-8 / 1`; with the rounding
/// of `1 / c_i`, below this.
pub const R_MAX: f64 = 0.003_907;

/// The absolute truncation error of `log2(1 + r) = (r - r^2/2 + ... - r^6/6) / ln 2`: the tail
/// is alternating-free bounded by `|r|^7 / (7 (1 - |r|) ln 2)` (`2.3e-18` at [`R_MAX`], rounded
/// up; a test recomputes it).
pub const LOG_TAIL: f64 = 3.0e-18;

/// `|t| = |d ln 2 / 64|` with `|d| <= 1/2`, rounded up.
pub const T_MAX: f64 = 0.005_416;

/// The relative truncation error of `e^t = 1 + t + ... + t^5 / 5!`: at most
/// `|t|^6 / 6! e^(2 |t|)` (`3.5e-17` at [`T_MAX`], rounded up; a test recomputes it).
pub const EXP_TAIL: f64 = 4.0e-17;

/// The tables: for each of the 128 slices of `[1, 2)`, `1 / c_i` rounded and `-log2` of that
/// rounded value; and `2^(j / 64)` for `j < 64`. Built once from libm's `log2` and `exp2`,
/// which glibc gives to within one ulp, the same trust the `powf` fallback places in libm.
struct Tables {
    inv: [f64; 1 << LOG_BITS],
    log: [f64; 1 << LOG_BITS],
    exp: [f64; 1 << EXP_BITS],
}

static TABLES: std::sync::LazyLock<Tables> = std::sync::LazyLock::new(|| {
    let n = (1 << LOG_BITS) as f64;
    let inv: [f64; 1 << LOG_BITS] = std::array::from_fn(|i| 1.0 / (1.0 + (i as f64 + 0.5) / n));
    Tables {
        inv,
        log: inv.map(|v| -v.log2()),
        exp: std::array::from_fn(|j| (j as f64 / (1 << EXP_BITS) as f64).exp2()),
    }
});

/// `x^e` for `x > 0` as `(r, w)` with the exact power within `r w` of `r`, or `None` where the
/// bound below is not proven (`x` subnormal, zero, infinite or NaN; `|e log2 x| > 1000`; or a
/// bound above `1e-6`, which only exponents beyond `1e8` reach).
///
/// Written by hand because this is the narrow phase's hottest loop (a third of a heap step went
/// to `powf`) and no crate gives a power with an error bound. It is glibc's method (a table
/// lookup, then short series) without the double-double arithmetic that buys libm its last
/// ulp: an enclosure needs a bound, not a correct rounding. The derivation, `U = 2^-53`:
///
/// 1. `x = 2^k m` exactly, `m` in `[1, 2)`, by reading the bits; the top 7 bits of `m` pick
///    a slice `i` with midpoint `c_i`, and `g = inv_i` is `1 / c_i` rounded.
/// 2. `log2 m = -log2 g + log2(1 + r)` exactly, `r = m g - 1`. The product rounds once, by at
///    most `1.004 U` absolutely (`m g < 1.004`), and the subtraction is exact (Sterbenz), so
///    the computed `r` is within `1.004 U` of the exact one and `|r| <= R_MAX`.
/// 3. `P = (r - r^2/2 + ... - r^6/6) / ln 2` (Estrin's scheme): the carried error of `r` moves
///    it by `1.004 U / ((1 - R_MAX) ln 2) <= 1.46 U`; the 13 roundings and the rounded
///    constants touch terms whose absolute values sum below `1.45 |r| < 0.006`, and no term
///    passes through more than 8 of them, so at most `0.1 U`; truncation adds [`LOG_TAIL`].
/// 4. `log2 m = table + P`: the table is within an ulp of `-log2 g`, at most `U` as
///    `|log2 g| < 1`, and the sum rounds by at most `U` (`|log2 m| <= 1`). So `log2 m` is within
///    `3.6 U + LOG_TAIL` absolutely. `y = e (k + log2 m)`: two more roundings, `U |y|` each,
///    once `|e| |k + log2 m|` is seen to be `|y|` to within a rounding. So
///    `|y - e log2 x| <= E_y = |e| (3.6 U + LOG_TAIL) + 2.01 U |y|`.
/// 5. `64 y` is exact; `N` is it rounded to an integer (adding and removing `1.5 2^52`, exact
///    for `|64 y| < 2^51`), `d = 64 y - N` exact with `|d| <= 1/2`; `N = 64 n + j`,
///    `0 <= j < 64`. `2^y = 2^n 2^(j/64) e^t`, `t = d ln 2 / 64`; the rounded constant and the
///    product put `t` within `2.01 U |t| < 0.02 U` of its value.
/// 6. `Q = 1 + t + ... + t^5/5!` (Estrin's scheme): no term passes through more than 10
///    roundings and a rounded coefficient, so at most `11 U e^|t| / e^-|t| <= 11.2 U`
///    relatively, plus [`EXP_TAIL`].
/// 7. `r = (2^(j/64) Q) 2^n`: the table within `2 U` relatively, one rounding of the product,
///    and the power of two exact (`|n| <= 1001`, `r` stays normal).
///
/// So `r = x^e 2^D (1 + d)` with `|D| <= E_y` and `|d| <= 14.3 U + EXP_TAIL`, and
/// `|r / x^e - 1| <= 1.001 ln 2 E_y + 15 U + EXP_TAIL` while `ln 2 E_y <= 1e-6`. The returned
/// `w` rounds `15 U` up to `20 U` and takes a factor 1.01 for its own rounding and cross terms.
#[inline(always)]
pub fn pow_with_bound(x: f64, e: f64) -> Option<(f64, f64)> {
    const MANTISSA: u64 = (1 << 52) - 1;
    const ONE_BITS: u64 = 1023 << 52;
    // Adding and subtracting this rounds to an integer, exactly, below 2^51 in magnitude;
    // faster than `round`, which is a libm call on baseline x86-64.
    const SHIFTER: f64 = 6_755_399_441_055_744.0; // 1.5 2^52
    if !(f64::MIN_POSITIVE..=f64::MAX).contains(&x) {
        return None;
    }
    let tables = &*TABLES;
    // 1-2. x = 2^k m, r = m g - 1.
    let bits = x.to_bits();
    let k = ((bits >> 52) as i64 - 1023) as f64;
    let m = f64::from_bits((bits & MANTISSA) | ONE_BITS);
    let i = ((bits & MANTISSA) >> (52 - LOG_BITS)) as usize;
    let r = m * tables.inv[i] - 1.0;
    // 3-4. log2 x = k + table + log2(1 + r).
    // Estrin's scheme: the same polynomial as Horner's with a third of the dependency chain.
    let r2 = r * r;
    let p = (r + r2 * (-1.0 / 2.0 + r * (1.0 / 3.0)))
        + (r2 * r2) * ((-1.0 / 4.0 + r * (1.0 / 5.0)) + r2 * (-1.0 / 6.0));
    let log2_m = tables.log[i] + p * std::f64::consts::LOG2_E;
    let y = e * (k + log2_m);
    let y_err = e * (3.6 * U + LOG_TAIL) + 2.01 * U * y.abs();
    if !(y.abs() <= 1000.0 && y_err <= 1e-6) {
        return None;
    }
    // 5. 64 y = N + d.
    let z = y * (1 << EXP_BITS) as f64;
    let shifted = z + SHIFTER;
    let big_n = shifted - SHIFTER;
    let d = z - big_n;
    // The low bits of `shifted` hold N in two's complement.
    let n_int = shifted.to_bits() as i64 as i32;
    let j = (n_int & ((1 << EXP_BITS) - 1)) as usize;
    let n = n_int >> EXP_BITS;
    let t = d * (std::f64::consts::LN_2 / (1 << EXP_BITS) as f64);
    // 6. e^t.
    let t2 = t * t;
    let q =
        (1.0 + t) + t2 * ((1.0 / 2.0 + t * (1.0 / 6.0)) + t2 * (1.0 / 24.0 + t * (1.0 / 120.0)));
    // 7. r = 2^(j/64) Q 2^n.
    let scale = f64::from_bits(((n + 1023) as u64) << 52);
    let w = 1.01 * (1.001 * std::f64::consts::LN_2 * y_err + 20.0 * U + EXP_TAIL);
    Some((tables.exp[j] * q * scale, w))
}

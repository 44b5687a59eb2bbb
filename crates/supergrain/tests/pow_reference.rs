//! The outward-rounded powers against an independent reference: `x^e` computed by mpmath at 60
//! digits from the exact binary `x` and `e` (`scripts/pow-reference.py`, 4,000 cases: bases in
//! (0, 1], near 1, at the mantissa's sqrt(2) cut, across the normal range; the shapes' exponents,
//! their inverses, and both less one, negative ones among them).
//!
//! The reference is read to the nearest float `r`; the true power lies within half an ulp of
//! it, so a bound below `r - ulp` and above `r + ulp` (what `down` and `up` give) holds it.
//! `powf` itself is not the reference: the bounds are built from it (glibc's `pow`, within one
//! ulp), and this checks that claim where it matters, at the shapes' bases and exponents.

use supergrain::interval::{Exponent, down, up};

fn cases() -> Vec<(f64, f64, f64)> {
    let text = include_str!("data/pow-reference.txt");
    text.lines()
        .map(|line| {
            let f: Vec<&str> = line.split_whitespace().collect();
            let bits = |s: &str| f64::from_bits(u64::from_str_radix(s, 16).expect("hex bits"));
            (bits(f[0]), bits(f[1]), f[2].parse().expect("a decimal"))
        })
        .collect()
}

#[test]
fn powers_enclose_the_reference() {
    let cases = cases();
    assert_eq!(cases.len(), 4000);
    let ulps = |a: f64, b: f64| a.to_bits().abs_diff(b.to_bits());
    for (x, e, r) in cases {
        let k = Exponent::new(e);
        let (lo, hi) = (k.pow_down(x), k.pow_up(x));
        assert!(
            lo <= down(r) && up(r) <= hi,
            "{x:e}^{e} = {r:e}: [{lo:e}, {hi:e}] misses it"
        );
        let (lo_all, hi_all, plain) = k.pow_all(x);
        assert_eq!((lo_all, hi_all), (lo, hi), "{x:e}^{e}");
        assert!(lo <= plain && plain <= hi, "{x:e}^{e}: {plain:e}");
        // And tight: two outward steps of 1-2 ulps each side (each step also moves by the
        // smallest normal, which tells below 1e-290).
        if r > 1e-290 {
            assert!(
                ulps(lo, r) <= 8 && ulps(hi, r) <= 8,
                "{x:e}^{e} = {r:e}: [{lo:e}, {hi:e}] wider than 8 ulps each side"
            );
        }
    }
}

/// The single-precision bounds of the boundary search's arcs
/// ([`Exponent::pow_down_coarse`]) hold the same reference, and are within their stated
/// relative width of it, `2 (4 + 11 |e|) 2^-23` (the single-precision power within its pad of
/// the truth, and the bound a pad beyond that), wherever they are in single precision (bases in
/// `[1e-8, 1e8]`, exponents up to 16 in size); elsewhere they are the double-precision bounds.
#[test]
fn coarse_powers_enclose_the_reference() {
    let mut single = 0;
    for (x, e, r) in cases() {
        let k = Exponent::new(e);
        let (lo, hi) = (k.pow_down_coarse(x), k.pow_up_coarse(x));
        assert!(
            lo <= down(r) && up(r) <= hi,
            "{x:e}^{e} = {r:e}: [{lo:e}, {hi:e}] misses it"
        );
        if (lo, hi) == (k.pow_down(x), k.pow_up(x)) {
            continue;
        }
        single += 1;
        let width = 2.0 * (4.0 + 11.0 * e.abs()) * f64::from(f32::EPSILON) * (1.0 + 1e-9);
        assert!(
            r - lo <= width * r && hi - r <= width * r,
            "{x:e}^{e} = {r:e}: [{lo:e}, {hi:e}] wider than {width:e} relative"
        );
    }
    // Most of the reference's cases are in the single-precision range.
    assert!(single > 1500, "only {single} cases in single precision");
}

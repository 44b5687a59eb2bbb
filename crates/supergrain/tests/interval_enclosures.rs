//! Interval enclosures (SPEC §2) against brute force: the implicit function written again here
//! and evaluated on dense grids of each box, exact rational values at dyadic points, and exact
//! powers of dyadic numbers.
//!
//! Rounding of the references: the sampled reference evaluates the real formula in
//! round-to-nearest, in the natural order of operations (translate, rotate, divide, power, sum,
//! subtract 1). Every step of a rigorous enclosure rounds outward, and rounding is monotone, so
//! the reference's float value at any point of the box must lie in the enclosure with no
//! tolerance at all. Where the real value itself can be computed exactly (dyadic inputs,
//! integer exponents) it is, in integers.

mod common;

use common::Rng;
use std::f64::consts::TAU;

use supergrain::geometry::{Aabb, Vec2};
use supergrain::interval::{
    Exponent, ImplicitShape, Interval, PlacedSuperellipse, Side, pow_down, pow_up,
};
use supergrain::shape::{HalfPlane, Pose, Superellipse};
use supergrain::subdivision::Precision;

/// `a + b = s + err` exactly (Knuth's TwoSum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a b = p + err` exactly (the error of a product is a fused multiply-add away).
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `a x + b y` for double-double `x`, `y`, to about 2^-100 relative to `|a x| + |b y|`.
fn dd_dot(a: f64, x: (f64, f64), b: f64, y: (f64, f64)) -> (f64, f64) {
    let (p1, e1) = two_prod(a, x.0);
    let (p2, e2) = two_prod(b, y.0);
    let (s, e) = two_sum(p1, p2);
    two_sum(s, e + e1 + e2 + a * x.1 + b * y.1)
}

/// `|t|^e` for a double-double `t`, to about an ulp: `powf` of the leading part and a
/// first-order correction for the trailing one.
fn dd_abs_pow(t: (f64, f64), e: f64) -> f64 {
    let (hi, lo) = if t.0 < 0.0 { (-t.0, -t.1) } else { t };
    if hi == 0.0 {
        return 0.0;
    }
    let p = hi.powf(e);
    p + p * e * (lo / hi)
}

/// `|t|^e` in round-to-nearest: exact products for the integer exponents, `sqrt` for 1/2.
fn ref_pow(t: f64, e: f64) -> f64 {
    let a = t.abs();
    match e {
        1.0 => a,
        2.0 => a * a,
        3.0 => a * a * a,
        4.0 => (a * a) * (a * a),
        0.5 => a.sqrt(),
        _ => a.powf(e),
    }
}

/// A placed superellipse as plain numbers.
#[derive(Clone, Copy, Debug)]
struct Shape {
    s: [f64; 2],
    e: [f64; 2],
    c: [f64; 2],
    angle: f64,
}

impl Shape {
    /// `f(p) = |u/sx|^ex + |v/sy|^ey - 1`, `(u, v) = R(-angle)(p - c)` (with `cos` and `sin`
    /// as `f64::sin_cos` gives them), evaluated in double-double up to the powers, and
    /// `err`, a bound of this value's own error: a few ulps of each term.
    fn f_and_err(&self, p: [f64; 2]) -> (f64, f64) {
        let dx = two_sum(p[0], -self.c[0]);
        let dy = two_sum(p[1], -self.c[1]);
        // A circle is the same function in every frame.
        let circle = self.s[0] == self.s[1] && self.e == [2.0, 2.0];
        let (u, v) = if self.angle == 0.0 || circle {
            (dx, dy)
        } else {
            let (sn, cs) = self.angle.sin_cos();
            (dd_dot(cs, dx, sn, dy), dd_dot(-sn, dx, cs, dy))
        };
        let div = |u: (f64, f64), s: f64| {
            let q = u.0 / s;
            let r = (-q).mul_add(s, u.0);
            (q, (r + u.1) / s)
        };
        let hx = dd_abs_pow(div(u, self.s[0]), self.e[0]);
        let hy = dd_abs_pow(div(v, self.s[1]), self.e[1]);
        (hx + hy - 1.0, 4.0 * f64::EPSILON * (1.0 + hx + hy))
    }

    fn placed(&self) -> PlacedSuperellipse {
        PlacedSuperellipse::new(
            Superellipse::new(self.s, self.e).unwrap(),
            Pose::new(Vec2::new(self.c[0], self.c[1]), self.angle).unwrap(),
        )
    }

    /// The largest value either term of `f` reaches on the box: the scale of its rounding.
    fn magnitude(&self, b: &Aabb) -> f64 {
        let r = (b.min.x - self.c[0])
            .abs()
            .max((b.max.x - self.c[0]).abs())
            .hypot((b.min.y - self.c[1]).abs().max((b.max.y - self.c[1]).abs()));
        1.0 + ref_pow(r / self.s[0], self.e[0]) + ref_pow(r / self.s[1], self.e[1])
    }
}

fn random_exponent(rng: &mut Rng) -> f64 {
    match rng.below(8) {
        0 => 0.5,
        1 => 1.0,
        2 => 2.0,
        3 => 3.0,
        4 => 4.0,
        5 => rng.range(0.3, 1.0),
        _ => rng.range(0.3, 10.0),
    }
}

fn random_shape(rng: &mut Rng, aligned: bool) -> Shape {
    let s = [rng.range(0.05, 3.0), rng.range(0.05, 3.0)];
    let e = [random_exponent(rng), random_exponent(rng)];
    let c = if rng.below(5) == 0 {
        [0.0, 0.0]
    } else {
        [rng.range(-20.0, 20.0), rng.range(-20.0, 20.0)]
    };
    let angle = if aligned { 0.0 } else { rng.range(-7.0, 7.0) };
    Shape { s, e, c, angle }
}

/// A random box near the shape: tiny or large, straddling the shape's axes or not, degenerate
/// (a point or a segment) sometimes.
fn random_box(rng: &mut Rng, sh: &Shape) -> Aabb {
    let size = sh.s[0].max(sh.s[1]);
    let centre = match rng.below(4) {
        // On the centre: the box straddles both axes.
        0 => [sh.c[0], sh.c[1]],
        // Near the shape's boundary.
        1 => {
            let t = rng.range(0.0, TAU);
            [sh.c[0] + sh.s[0] * t.cos(), sh.c[1] + sh.s[1] * t.sin()]
        }
        _ => [
            sh.c[0] + rng.range(-2.0, 2.0) * size,
            sh.c[1] + rng.range(-2.0, 2.0) * size,
        ],
    };
    let half = |rng: &mut Rng| match rng.below(6) {
        0 => 0.0,
        1 => size * 10f64.powf(rng.range(-9.0, -3.0)),
        2 => size * rng.range(0.001, 0.1),
        _ => size * rng.range(0.1, 3.0),
    };
    let (hx, hy) = if rng.below(8) == 0 {
        (0.0, 0.0)
    } else {
        (half(rng), half(rng))
    };
    Aabb::new(
        Vec2::new(centre[0] - hx, centre[1] - hy),
        Vec2::new(centre[0] + hx, centre[1] + hy),
    )
}

/// Grid coordinates over `[lo, hi]`: `n` evenly spaced including both ends, plus `extra`
/// (clamped into the interval).
fn coords(lo: f64, hi: f64, n: usize, extra: f64) -> Vec<f64> {
    let mut v: Vec<f64> = (0..n)
        .map(|i| {
            if i + 1 == n {
                hi
            } else {
                lo + (hi - lo) * i as f64 / (n - 1) as f64
            }
        })
        .collect();
    v.push(extra.clamp(lo, hi));
    v
}

/// The sampled range of `f` over the box, and the largest error bound of the samples.
fn sampled_range(sh: &Shape, b: &Aabb, n: usize) -> (f64, f64, f64) {
    // The shape's centre clamped into the box: for an aligned shape it holds the minimum.
    let xs = coords(b.min.x, b.max.x, n, sh.c[0]);
    let ys = coords(b.min.y, b.max.y, n, sh.c[1]);
    let (mut lo, mut hi, mut err) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for &x in &xs {
        for &y in &ys {
            let (v, e) = sh.f_and_err([x, y]);
            lo = lo.min(v);
            hi = hi.max(v);
            err = err.max(e);
        }
    }
    (lo, hi, err)
}

#[test]
fn superellipse_enclosure_contains_sampled_values() {
    let mut rng = Rng::new(31);
    for case in 0..1500 {
        let sh = random_shape(&mut rng, case % 3 == 0);
        let b = random_box(&mut rng, &sh);
        let en = sh.placed().enclose(&b);
        // Every sample's value lies in the enclosure, up to the reference's own error bound: a
        // few ulps of the terms, never an absolute allowance.
        for x in coords(b.min.x, b.max.x, 25, sh.c[0]) {
            for y in coords(b.min.y, b.max.y, 25, sh.c[1]) {
                let (v, err) = sh.f_and_err([x, y]);
                assert!(
                    en.lo <= v + err && v - err <= en.hi,
                    "{sh:?} over {b:?}: enclosure {en:?} misses f({x}, {y}) = {v} +- {err:e}"
                );
            }
        }
        // A point's enclosure holds the point's value.
        let p = b.center();
        let ep = sh.placed().enclose_point(p);
        let (v, err) = sh.f_and_err([p.x, p.y]);
        assert!(
            ep.lo <= v + err && v - err <= ep.hi,
            "{sh:?} at {p:?}: {ep:?} misses {v} +- {err:e}"
        );
    }
}

/// The renderer's classification proves a side only where every sample is on it (against the
/// reference's own error bound, no allowance), and proves at least what the enclosure proves:
/// it computes the same ends, only fewer of them.
#[test]
fn classify_proves_only_sides_the_samples_confirm() {
    let mut rng = Rng::new(47);
    let mut proven = [0usize; 2];
    for case in 0..3000 {
        let sh = random_shape(&mut rng, case % 3 == 0);
        let b = random_box(&mut rng, &sh);
        let placed = sh.placed();
        let side = placed.classify(&b);
        let by_enclosure = Side::of(placed.enclose(&b));
        if by_enclosure != Side::Boundary {
            assert_eq!(side, by_enclosure, "{sh:?} over {b:?}");
        }
        if side == Side::Boundary {
            continue;
        }
        proven[usize::from(side == Side::Outside)] += 1;
        for x in coords(b.min.x, b.max.x, 17, sh.c[0]) {
            for y in coords(b.min.y, b.max.y, 17, sh.c[1]) {
                let (v, err) = sh.f_and_err([x, y]);
                let holds = match side {
                    Side::Inside => v - err < 0.0,
                    _ => v + err > 0.0,
                };
                assert!(
                    holds,
                    "{sh:?} over {b:?}: {side:?}, but f({x}, {y}) = {v} +- {err:e}"
                );
            }
        }
    }
    // Both proofs were exercised, many times.
    assert!(proven[0] > 100 && proven[1] > 100, "{proven:?}");
}

#[test]
fn rotated_enclosure_holds_points_on_an_axis_through_the_frame_origin() {
    // The shape's u-axis (v = 0 line's normal) passes through the origin of the frame: at the
    // origin, u = -(cos cx + sin cy) cancels to ~1e-16 rho, not to 0, and |u|^0.5 ~ 1e-8.
    // That is what contact() meets when B's axis passes through A's centre.
    let mut rng = Rng::new(38);
    for _ in 0..200 {
        let th = rng.range(-3.0, 3.0);
        let rho = rng.range(0.5, 20.0);
        let (sn, cs) = th.sin_cos();
        let sh = Shape {
            s: [1.0, rho],
            e: [0.5, 2.0],
            c: [-rho * sn, rho * cs],
            angle: th,
        };
        let iv = sh.placed().enclose_point(Vec2::ZERO);
        let (v, err) = sh.f_and_err([0.0, 0.0]);
        assert!(
            iv.lo <= v + err && v - err <= iv.hi,
            "{sh:?} at the origin: enclosure {iv:?} misses f = {v} +- {err:e}"
        );
    }
}

/// The tightness check of an axis-aligned shape's enclosure: each term of `f` is monotone on
/// either side of the centre, so its range over the box is reached at the box's ends and at
/// the coordinate nearest the centre, which are all among the samples: the sampled range is
/// the exact range up to the reference's rounding.
fn check_aligned_tight(sh: &Shape, b: &Aabb) {
    let en = sh.placed().enclose(b);
    let (lo, hi, err) = sampled_range(sh, b, 9);
    let slack = 1e-9 * sh.magnitude(b);
    assert!(
        en.lo <= lo + err && hi - err <= en.hi,
        "{sh:?} over {b:?}: enclosure {en:?} misses sampled [{lo}, {hi}]"
    );
    assert!(
        lo - en.lo <= slack && en.hi - hi <= slack,
        "{sh:?} over {b:?}: enclosure {en:?} loose around sampled [{lo}, {hi}]"
    );
}

#[test]
fn aligned_enclosure_is_tight_for_exponents_from_one() {
    let mut rng = Rng::new(32);
    for _ in 0..1500 {
        let mut sh = random_shape(&mut rng, true);
        sh.e = sh.e.map(|e| if e < 1.0 { 1.0 / e } else { e });
        let b = random_box(&mut rng, &sh);
        check_aligned_tight(&sh, &b);
    }
}

#[test]
fn aligned_enclosure_is_tight_for_exponents_below_one() {
    let mut rng = Rng::new(39);
    for _ in 0..1500 {
        let mut sh = random_shape(&mut rng, true);
        sh.e = [rng.range(0.3, 1.0), rng.range(0.3, 1.0)];
        let b = random_box(&mut rng, &sh);
        check_aligned_tight(&sh, &b);
    }
}

/// `sum of k_i^e_i 2^(40 - 10 e_i) - 2^40`: the exact value of `f` times `2^40` for an aligned
/// shape with `t_i = k_i 2^-10` and integer exponents `e_i <= 4`.
fn exact_f_scaled(k: [i128; 2], e: [u32; 2]) -> i128 {
    let term = |k: i128, e: u32| k.abs().pow(e) << (40 - 10 * e);
    term(k[0], e[0]) + term(k[1], e[1]) - (1i128 << 40)
}

/// `lo <= n 2^-40 <= hi`, decided exactly (`x * 2^40` is exact for these magnitudes).
fn encloses_exact(iv: Interval, n: i128) -> bool {
    let lo = (iv.lo * (1u64 << 40) as f64).ceil();
    let hi = (iv.hi * (1u64 << 40) as f64).floor();
    lo.is_finite() && hi.is_finite() && (lo as i128) <= n && n <= (hi as i128)
}

#[test]
fn aligned_enclosure_holds_exact_values_at_dyadic_points() {
    // Coordinates are multiples of 2^-8 in [-8, 8], semi-axes 1/2, 1 or 2, exponents 1..=4:
    // t = (x - cx) / s is a multiple of 2^-10 with |t| < 2^5, and f is an exact rational.
    let mut rng = Rng::new(33);
    let grid = |rng: &mut Rng| (rng.below(4097) as i64 - 2048) as f64 / 256.0;
    for _ in 0..3000 {
        let ks = [rng.below(3) as i32 - 1, rng.below(3) as i32 - 1];
        let e = [1 + rng.below(4) as u32, 1 + rng.below(4) as u32];
        let c = [grid(&mut rng), grid(&mut rng)];
        let sh = Shape {
            s: [2f64.powi(ks[0]), 2f64.powi(ks[1])],
            e: [f64::from(e[0]), f64::from(e[1])],
            c,
            angle: 0.0,
        };
        let (x1, x2) = {
            let (a, b) = (grid(&mut rng), grid(&mut rng));
            (a.min(b), a.max(b))
        };
        let (y1, y2) = {
            let (a, b) = (grid(&mut rng), grid(&mut rng));
            (a.min(b), a.max(b))
        };
        // t * 2^10 as an integer.
        let k = |x: f64, axis: usize| ((x - c[axis]) / sh.s[axis] * 1024.0) as i128;
        let placed = sh.placed();

        // Every corner, as a point box: the enclosure holds the exact value.
        for (x, y) in [(x1, y1), (x1, y2), (x2, y1), (x2, y2)] {
            let n = exact_f_scaled([k(x, 0), k(y, 1)], e);
            let iv = placed.enclose_point(Vec2::new(x, y));
            assert!(
                encloses_exact(iv, n),
                "{sh:?} at ({x}, {y}): {iv:?} misses {n} 2^-40"
            );
        }

        // The box: exact range from the nearest point to the centre and the farthest corner.
        let b = Aabb::new(Vec2::new(x1, y1), Vec2::new(x2, y2));
        let near = [c[0].clamp(x1, x2), c[1].clamp(y1, y2)];
        let far = [
            if (x1 - c[0]).abs() > (x2 - c[0]).abs() {
                x1
            } else {
                x2
            },
            if (y1 - c[1]).abs() > (y2 - c[1]).abs() {
                y1
            } else {
                y2
            },
        ];
        let n_lo = exact_f_scaled([k(near[0], 0), k(near[1], 1)], e);
        let n_hi = exact_f_scaled([k(far[0], 0), k(far[1], 1)], e);
        let iv = placed.enclose(&b);
        assert!(
            encloses_exact(iv, n_lo) && encloses_exact(iv, n_hi),
            "{sh:?} over {b:?}: {iv:?} misses [{n_lo}, {n_hi}] 2^-40"
        );
        // Only rounding beyond the exact range.
        let scale = 1e-12 * (1.0 + (n_hi as f64 / (1u64 << 40) as f64).abs());
        assert!(
            n_lo as f64 / (1u64 << 40) as f64 - iv.lo <= scale
                && iv.hi - n_hi as f64 / (1u64 << 40) as f64 <= scale,
            "{sh:?} over {b:?}: {iv:?} loose around [{n_lo}, {n_hi}] 2^-40"
        );
    }
}

/// `x <= n / d` (`d > 0`), decided exactly in integers, or `None` when the integers would
/// overflow.
fn at_most_rational(x: f64, n: i128, d: i128) -> Option<bool> {
    if x == 0.0 {
        return Some(n >= 0);
    }
    // x = m 2^k exactly, m an integer below 2^53.
    let bits = x.abs().to_bits();
    let (exp, frac) = ((bits >> 52) as i32, (bits & ((1u64 << 52) - 1)) as i128);
    let (m, k) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1i128 << 52), exp - 1075)
    };
    let m = if x < 0.0 { -m } else { m };
    // m 2^k <= n / d  <=>  m d 2^k <= n.
    let lhs = m.checked_mul(d)?;
    if k >= 0 {
        Some(lhs.checked_mul(1i128.checked_shl(k as u32)?)? <= n)
    } else {
        let shift = u32::try_from(-k).ok().filter(|&s| s < 126)?;
        let rhs = n.checked_mul(1i128 << shift)?;
        Some(lhs <= rhs)
    }
}

/// A point's enclosure for an axis-aligned shape (one multiplication by the rounded `1 / s`,
/// no division) holds the exact value of `f` where `1 / s` is not a dyadic number: ellipses
/// with odd semi-axes `m 2^-10` at points and centres on the grid `2^-10`, where
/// `t = (x - c) / s = (k_x - k_c) / m` and `f` are exact rationals.
#[test]
fn aligned_point_enclosure_holds_exact_values_for_any_semi_axes() {
    let mut rng = Rng::new(34);
    let (mut decided, mut cases) = (0, 0);
    for _ in 0..20000 {
        let odd = |rng: &mut Rng| 2 * (256 + rng.below(768) as i128) + 1;
        let m = [odd(&mut rng), odd(&mut rng)];
        let kc = [
            rng.below(2048) as i128 - 1024,
            rng.below(2048) as i128 - 1024,
        ];
        // Points from the centre out to about twice the shape, many near its boundary.
        let n = [0, 1].map(|axis| {
            let reach = if rng.below(2) == 0 {
                m[axis]
            } else {
                2 * m[axis]
            };
            rng.below(2 * reach as u64 + 1) as i128 - reach
        });
        let to_f = |k: i128| k as f64 / 1024.0;
        let sh = Shape {
            s: [to_f(m[0]), to_f(m[1])],
            e: [2.0, 2.0],
            c: [to_f(kc[0]), to_f(kc[1])],
            angle: 0.0,
        };
        let p = Vec2::new(to_f(kc[0] + n[0]), to_f(kc[1] + n[1]));
        // f = n_x^2 / m_x^2 + n_y^2 / m_y^2 - 1 = num / den.
        let (mx2, my2) = (m[0] * m[0], m[1] * m[1]);
        let den = mx2 * my2;
        let num = n[0] * n[0] * my2 + n[1] * n[1] * mx2 - den;
        let iv = sh.placed().enclose_point(p);
        cases += 1;
        let lo_ok = at_most_rational(iv.lo, num, den);
        let hi_ok = at_most_rational(-iv.hi, -num, den);
        if let (Some(lo_ok), Some(hi_ok)) = (lo_ok, hi_ok) {
            decided += 1;
            assert!(
                lo_ok && hi_ok,
                "{sh:?} at {p:?}: {iv:?} misses {num} / {den}"
            );
        }
    }
    assert!(decided * 10 >= cases * 9, "{decided} of {cases} decided");
}

/// Distance in units in the last place between two finite non-negative floats.
fn ulps(a: f64, b: f64) -> u64 {
    a.to_bits().abs_diff(b.to_bits())
}

#[test]
fn pow_bounds_bracket_powf_within_a_few_ulps() {
    let mut rng = Rng::new(34);
    let specials = [0.5, 1.0, 2.0, 3.0, 4.0];
    for i in 0..20000 {
        let x = 2f64.powf(rng.range(-40.0, 40.0));
        let e = if i % 2 == 0 {
            specials[rng.below(5) as usize]
        } else {
            rng.range(0.2, 12.0)
        };
        let want = x.powf(e);
        let (lo, hi) = (pow_down(x, e), pow_up(x, e));
        assert!(lo <= want && want <= hi, "{x}^{e} = {want}: [{lo}, {hi}]");
        // Each outward step adds 1-2 ulps; the longest chain (x^4) takes two of them.
        assert!(
            ulps(lo, want) <= 8 && ulps(hi, want) <= 8,
            "{x}^{e} = {want}: [{lo}, {hi}] wider than 8 ulps each side"
        );
    }
}

#[test]
fn pow_bounds_bracket_exact_dyadic_powers() {
    // x = k^q 2^(-q m) with x^e = k^(q e) 2^(-q e m) exact in f64 (k^(qe) < 2^53).
    let cases: [(f64, i32); 9] = [
        // (exponent e, power q with q e an integer)
        (2.0, 1),
        (3.0, 1),
        (4.0, 1),
        (0.5, 2),
        (1.5, 2),
        (2.5, 2),
        (0.25, 4),
        (5.0, 1),
        (6.0, 1),
    ];
    for (e, q) in cases {
        let qe = (f64::from(q) * e) as i32;
        for k in 1..=60i64 {
            for m in [-3, 0, 5, 20] {
                let x = (k as f64).powi(q) * 2f64.powi(-q * m);
                let exact = (k as f64).powi(qe) * 2f64.powi(-qe * m);
                assert!((k as f64).powi(qe) < 2f64.powi(53));
                let (lo, hi) = (pow_down(x, e), pow_up(x, e));
                assert!(
                    lo <= exact && exact <= hi,
                    "{x}^{e} = {exact} exactly: [{lo}, {hi}]"
                );
                assert!(
                    lo < hi && ulps(lo, exact) <= 8 && ulps(hi, exact) <= 8,
                    "{x}^{e} = {exact}: [{lo}, {hi}] not a few ulps around it"
                );
            }
        }
    }
    // e = 1 is exact, and 0 to any power is 0.
    for x in [0.0, 1e-300, 0.75, 3.0, 1e300] {
        assert_eq!((pow_down(x, 1.0), pow_up(x, 1.0)), (x, x));
    }
    for e in [0.3, 0.5, 1.0, 2.0, 3.0, 4.0, 7.5] {
        assert_eq!((pow_down(0.0, e), pow_up(0.0, e)), (0.0, 0.0), "0^{e}");
    }
}

#[test]
fn pow_bounds_survive_underflow() {
    // The true power of a positive number is positive: the upper bound must be too, and the
    // lower bound must never be negative.
    for x in [1e-320, 1e-300, 1e-200, 1e-160, 1e-100] {
        for e in [0.5, 2.0, 3.0, 4.0, 2.7, 9.0] {
            let (lo, hi) = (pow_down(x, e), pow_up(x, e));
            assert!(
                lo >= 0.0 && hi > 0.0 && lo <= hi,
                "{x}^{e}: [{lo}, {hi}] (powf {})",
                x.powf(e)
            );
            assert!(lo <= x.powf(e) && x.powf(e) <= hi, "{x}^{e}: [{lo}, {hi}]");
        }
    }
}

#[test]
fn pow_bounds_survive_overflow() {
    // pow_down's contract: "a lower bound of x^e, finite and never negative". When x^e
    // overflows, the true value exceeds f64::MAX, so f64::MAX is a valid (and the best) lower
    // bound, and the upper bound must be +inf.
    for x in [1e160, 1e200, 1e300, f64::MAX] {
        for e in [2.0, 3.0, 4.0, 2.7, 9.0] {
            let (lo, hi) = (pow_down(x, e), pow_up(x, e));
            assert!(
                lo.is_finite() && lo >= 0.0,
                "{x}^{e}: lower bound {lo} not finite and >= 0"
            );
            assert!(hi == f64::INFINITY, "{x}^{e}: upper bound {hi}");
        }
    }
}

#[test]
fn interval_abs_and_abs_pow_match_brute_force() {
    let mut rng = Rng::new(35);
    let mut intervals = vec![
        Interval::new(-3.0, 2.0),
        Interval::new(-2.0, 3.0),
        Interval::new(0.0, 3.0),
        Interval::new(-2.0, 0.0),
        Interval::new(0.0, 0.0),
        Interval::new(-0.0, 0.0),
        Interval::new(1.5, 1.5),
        Interval::new(-1.5, -1.5),
        Interval::new(0.25, 4.0),
        Interval::new(-4.0, -0.25),
    ];
    for _ in 0..300 {
        let (a, b) = (
            rng.sign() * rng.range(0.0, 5.0),
            rng.sign() * rng.range(0.0, 5.0),
        );
        intervals.push(Interval::new(a.min(b), a.max(b)));
    }
    for iv in intervals {
        // Dense samples, both ends, and 0 when inside.
        let mut ts: Vec<f64> = (0..=200)
            .map(|i| (iv.lo + (iv.hi - iv.lo) * i as f64 / 200.0).clamp(iv.lo, iv.hi))
            .collect();
        ts.extend([iv.lo, iv.hi]);
        if iv.contains(0.0) {
            ts.push(0.0);
        }
        let abs_lo = ts.iter().map(|t| t.abs()).fold(f64::INFINITY, f64::min);
        let abs_hi = ts.iter().map(|t| t.abs()).fold(0.0f64, f64::max);
        let a = iv.abs();
        // The range of |t| is reached at the ends or at 0: exact.
        assert_eq!((a.lo, a.hi), (abs_lo, abs_hi), "|{iv:?}|");
        for e in [0.5, 1.0, 2.0, 3.0, 4.0, 0.7, 2.5, 7.0] {
            let p = iv.abs_pow(Exponent::new(e));
            let (plo, phi) = (ref_pow(abs_lo, e), ref_pow(abs_hi, e));
            for &t in &ts {
                let v = ref_pow(t, e);
                assert!(p.contains(v), "|{iv:?}|^{e} = {p:?} misses |{t}|^{e} = {v}");
            }
            assert!(
                plo - p.lo <= 1e-14 * plo.max(1e-300) + 1e-300
                    && p.hi - phi <= 1e-14 * phi.max(1e-300) + 1e-300,
                "|{iv:?}|^{e} = {p:?} loose around [{plo}, {phi}]"
            );
        }
    }
}

#[test]
fn half_plane_enclosure_contains_sampled_values() {
    let mut rng = Rng::new(36);
    for case in 0..600 {
        let wall = match case % 4 {
            0 => HalfPlane::floor(rng.range(-10.0, 10.0)).unwrap(),
            1 => HalfPlane::left(rng.range(-10.0, 10.0)).unwrap(),
            2 => HalfPlane::right(rng.range(-10.0, 10.0)).unwrap(),
            _ => HalfPlane::new(
                Vec2::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)),
                rng.range(-10.0, 10.0),
            )
            .unwrap(),
        };
        let (n, d) = (wall.normal(), wall.offset());
        assert!((n.norm() - 1.0).abs() <= 4.0 * f64::EPSILON, "{wall:?}");
        let c = [rng.range(-12.0, 12.0), rng.range(-12.0, 12.0)];
        let h = [
            rng.range(0.0, 3.0) * f64::from(u8::from(rng.below(6) != 0)),
            rng.range(0.0, 3.0) * f64::from(u8::from(rng.below(6) != 0)),
        ];
        let b = Aabb::new(
            Vec2::new(c[0] - h[0], c[1] - h[1]),
            Vec2::new(c[0] + h[0], c[1] + h[1]),
        );
        let en = wall.enclose(&b);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for x in coords(b.min.x, b.max.x, 17, c[0]) {
            for y in coords(b.min.y, b.max.y, 17, c[1]) {
                let g = n.x * x + n.y * y - d;
                lo = lo.min(g);
                hi = hi.max(g);
                assert!(en.contains(g), "{wall:?} over {b:?}: {en:?} misses g = {g}");
            }
        }
        // Linear: the range is reached at corners, all sampled; only rounding beyond it.
        let slack = 1e-12 * (1.0 + d.abs() + c[0].abs() + c[1].abs() + h[0] + h[1]);
        assert!(
            lo - en.lo <= slack && en.hi - hi <= slack,
            "{wall:?} over {b:?}: {en:?} loose around [{lo}, {hi}]"
        );
    }
}

#[test]
fn precision_validates_and_sizes_cells() {
    for depth in 0..=supergrain::subdivision::MAX_DEPTH {
        assert!(Precision::new(depth, 0.0).is_ok(), "depth {depth}");
    }
    for depth in [41, 64, 1000, u32::MAX] {
        let msg = Precision::new(depth, 0.0)
            .expect_err("too deep accepted")
            .to_string();
        assert!(msg.contains("depth"), "depth {depth}: {msg:?}");
    }
    for eps in [-1e-300, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let msg = Precision::new(7, eps)
            .expect_err("bad eps accepted")
            .to_string();
        assert!(msg.contains("eps"), "eps {eps}: {msg:?}");
    }
    assert!(Precision::new(7, 0.0).is_ok() && Precision::new(7, 1e-300).is_ok());

    let mut rng = Rng::new(37);
    for _ in 0..2000 {
        let depth = rng.below(u64::from(supergrain::subdivision::MAX_DEPTH) + 1) as u32;
        let eps = match rng.below(3) {
            0 => 0.0,
            1 => 10f64.powf(rng.range(-12.0, 0.0)),
            _ => rng.range(0.0, 2.0),
        };
        let (w, h) = (rng.range(0.0, 20.0), rng.range(0.0, 20.0));
        let x0 = rng.range(-50.0, 50.0);
        let y0 = rng.range(-50.0, 50.0);
        let region = Aabb::new(Vec2::new(x0, y0), Vec2::new(x0 + w, y0 + h));
        let p = Precision::new(depth, eps).unwrap();
        // L / 2^depth by repeated halving (exact: halving is exact far above the subnormals).
        let mut cell = (x0 + w - x0).max(y0 + h - y0);
        for _ in 0..depth {
            cell /= 2.0;
        }
        let want = eps.max(cell);
        assert_eq!(
            p.cell_size(&region),
            want,
            "depth {depth}, eps {eps}, {region:?}"
        );
    }
    assert_eq!(
        Precision::default().cell_size(&Aabb::point(Vec2::ZERO)),
        0.0
    );
}

/// A semi-axis so small that its reciprocal overflows (a subnormal) gave enclosures that had
/// to guard against NaN; such shapes, and every size or exponent outside the accepted ranges,
/// are now refused when built, with the field named.
#[test]
fn shapes_outside_the_accepted_ranges_are_refused_naming_the_field() {
    use supergrain::shape::{EXPONENT_RANGE, SEMI_AXIS_RANGE};
    let tiny = f64::MIN_POSITIVE / 8.0;
    for (axes, exps, field) in [
        ([tiny, 1.0], [2.0, 2.0], "semi-axis x"),
        ([1.0, 1e160], [2.0, 2.0], "semi-axis y"),
        ([1.0, 1.0], [0.2, 2.0], "exponent x"),
        ([1.0, 1.0], [2.0, 1001.0], "exponent y"),
        ([1.0, 1.0], [2.0, f64::NAN], "exponent y"),
    ] {
        let err = Superellipse::new(axes, exps).unwrap_err().to_string();
        assert!(err.contains(field), "{axes:?} {exps:?}: {err}");
    }
    // The ends themselves are accepted.
    for e in [*EXPONENT_RANGE.start(), *EXPONENT_RANGE.end()] {
        for s in [*SEMI_AXIS_RANGE.start(), *SEMI_AXIS_RANGE.end()] {
            Superellipse::new([s, s], [e, e]).unwrap();
        }
    }
}

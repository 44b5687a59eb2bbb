//! The interval-arithmetic renderer (`render::raster`, `render::render_world`) against references
//! written here from first principles: the exact coverage of a pixel by a disc (the chord length
//! integrated over the pixel), the closed-form area of a superellipse (with a gamma function
//! written here), point sampling of the implicit function written again (`common::Shape::f`),
//! and the positions and radii of the grains of a world. Nothing below takes the renderer's own
//! output as a reference, except where the point is that two runs agree.

mod common;

use common::Shape;
use std::f64::consts::{PI, SQRT_2};

use supergrain::geometry::{Aabb, Vec2};
use supergrain::interval::PlacedSuperellipse;
use supergrain::io::{to_rgba_image, write_png};
use supergrain::render::raster::{
    Antialias, DEFAULT_AA_DEPTH, MAX_AA_DEPTH, View, cover, cover_with, paint_shape,
    paint_shape_with,
};
use supergrain::render::{Colouring, Style, render_world, world_region};
use supergrain::world::{Scene, World};

// ---------------------------------------------------------------------------------------------
// References
// ---------------------------------------------------------------------------------------------

/// `ln Gamma(x)` for `x > 0` by Lanczos' approximation (g = 7, nine terms; relative error of
/// Gamma about 1e-15), with the reflection formula below 1/2.
fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Gamma(x) Gamma(1 - x) = pi / sin(pi x); x > 0 here, so sin(pi x) > 0.
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The area of `|u/sx|^ex + |v/sy|^ey <= 1`:
/// `4 sx sy Gamma(1 + 1/ex) Gamma(1 + 1/ey) / Gamma(1 + 1/ex + 1/ey)`.
fn superellipse_area(s: [f64; 2], e: [f64; 2]) -> f64 {
    let (a, b) = (1.0 / e[0], 1.0 / e[1]);
    4.0 * s[0] * s[1] * (ln_gamma(1.0 + a) + ln_gamma(1.0 + b) - ln_gamma(1.0 + a + b)).exp()
}

/// The area of the disc of radius `r` at the origin inside `[x0, x1] x [y0, y1]`: the length of
/// the chord inside the strip integrated over x, by the midpoint rule on `n` samples.
fn disc_in_box(r: f64, x0: f64, x1: f64, y0: f64, y1: f64, n: usize) -> f64 {
    let (a, b) = (x0.max(-r), x1.min(r));
    if a >= b {
        return 0.0;
    }
    let h = (b - a) / n as f64;
    let mut sum = 0.0;
    for i in 0..n {
        let x = a + (i as f64 + 0.5) * h;
        let half = (r * r - x * x).max(0.0).sqrt();
        sum += (y1.min(half) - y0.max(-half)).max(0.0);
    }
    sum * h
}

/// A pixel grid written independently of `View`: `w x h` square pixels of side `px`, pixel
/// `(0, 0)` at the top-left corner `(left, top)`, rows going down.
#[derive(Clone, Copy, Debug)]
struct Grid {
    left: f64,
    top: f64,
    px: f64,
    w: u32,
    h: u32,
}

impl Grid {
    /// Pixels of side `1/ppu` (a power of two, so every corner is exact) around `[lo, hi]`,
    /// with `margin` pixels on every side, the corners on the pixel lattice.
    fn around(lo: [f64; 2], hi: [f64; 2], ppu: f64, margin: f64) -> Grid {
        let x0 = (lo[0] * ppu - margin).floor();
        let x1 = (hi[0] * ppu + margin).ceil();
        let y0 = (lo[1] * ppu - margin).floor();
        let y1 = (hi[1] * ppu + margin).ceil();
        Grid {
            left: x0 / ppu,
            top: y1 / ppu,
            px: 1.0 / ppu,
            w: (x1 - x0) as u32,
            h: (y1 - y0) as u32,
        }
    }

    fn view(&self) -> View {
        View {
            region: Aabb::new(
                Vec2::new(self.left, self.top - f64::from(self.h) * self.px),
                Vec2::new(self.left + f64::from(self.w) * self.px, self.top),
            ),
            width: self.w,
            height: self.h,
        }
    }

    /// The plane's box of pixel `(x, y)`: `[x0, x1] x [y0, y1]`.
    fn pixel(&self, x: u32, y: u32) -> [f64; 4] {
        let x0 = self.left + f64::from(x) * self.px;
        let y1 = self.top - f64::from(y) * self.px;
        [x0, x0 + self.px, y1 - self.px, y1]
    }

    fn len(&self) -> usize {
        (self.w * self.h) as usize
    }
}

/// Per pixel, the fraction of `n x n` sample points (centres of an `n x n` split of the pixel)
/// where the shape's implicit function is `<= 0`, and whether some sample lies so near the
/// boundary (`|f| < 1e-9`) that rounding could decide its side.
fn sampled(shape: &Shape, grid: &Grid, n: u32) -> (Vec<f64>, Vec<bool>) {
    let mut cov = vec![0.0; grid.len()];
    let mut tie = vec![false; grid.len()];
    let reach = shape.s[0].hypot(shape.s[1]);
    for y in 0..grid.h {
        for x in 0..grid.w {
            let [x0, x1, y0, y1] = grid.pixel(x, y);
            // Pixels that cannot reach the shape: no sample inside.
            let nx = shape.c[0].clamp(x0, x1);
            let ny = shape.c[1].clamp(y0, y1);
            if (nx - shape.c[0]).hypot(ny - shape.c[1]) > reach {
                continue;
            }
            let mut inside = 0;
            let k = (y * grid.w + x) as usize;
            for j in 0..n {
                for i in 0..n {
                    let p = [
                        x0 + (f64::from(i) + 0.5) / f64::from(n) * grid.px,
                        y0 + (f64::from(j) + 0.5) / f64::from(n) * grid.px,
                    ];
                    let f = shape.f(p);
                    if f <= 0.0 {
                        inside += 1;
                    }
                    if f.abs() < 1e-9 {
                        tie[k] = true;
                    }
                }
            }
            cov[k] = f64::from(inside) / f64::from(n * n);
        }
    }
    (cov, tie)
}

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

fn placed(s: &Shape) -> PlacedSuperellipse {
    let (shape, pose) = common::to_lib(s);
    PlacedSuperellipse::new(shape, pose)
}

/// The bounding box of a shape, from its implicit function's definition: `|u| <= sx`,
/// `|v| <= sy`, so every point is within `hypot(sx, sy)` of the centre.
fn reach_box(s: &Shape) -> ([f64; 2], [f64; 2]) {
    let r = s.s[0].hypot(s.s[1]);
    ([s.c[0] - r, s.c[1] - r], [s.c[0] + r, s.c[1] + r])
}

/// Coverage per pixel from `cover`, checking on the way that every visited pixel is in the image,
/// visited once, with a coverage in (0, 1].
fn coverage_map(shape: &PlacedSuperellipse, view: &View, aa: u32) -> Vec<f64> {
    coverage_map_with(shape, view, Antialias::Split(aa))
}

fn coverage_map_with(shape: &PlacedSuperellipse, view: &View, aa: Antialias) -> Vec<f64> {
    let (w, h) = (view.width, view.height);
    let mut cov = vec![0.0; (w * h) as usize];
    let mut visits = vec![0u8; (w * h) as usize];
    cover_with(shape, view, aa, |x, y, c| {
        assert!(
            x < w && y < h,
            "pixel ({x}, {y}) outside the {w} x {h} image"
        );
        assert!(
            c > 0.0 && c <= 1.0,
            "coverage {c} at ({x}, {y}) not in (0, 1]"
        );
        let k = (y * w + x) as usize;
        visits[k] += 1;
        cov[k] = f64::from(c);
    });
    let twice = visits.iter().filter(|&&v| v > 1).count();
    assert_eq!(twice, 0, "{twice} pixels visited more than once");
    cov
}

/// The sum of the alpha channel of a premultiplied RGBA8 buffer, in pixels.
fn alpha_area(pixels: &[u8]) -> f64 {
    pixels
        .chunks_exact(4)
        .map(|p| f64::from(p[3]) / 255.0)
        .sum()
}

fn painted(shape: &PlacedSuperellipse, view: &View, colour: [u8; 4], aa: Antialias) -> Vec<u8> {
    let mut pixels = vec![0u8; 4 * (view.width * view.height) as usize];
    paint_shape_with(&mut pixels, view, shape, colour, aa);
    pixels
}

/// The shapes of the area tests: every class of exponent, rotated, off the pixel grid.
fn zoo() -> Vec<(&'static str, Shape)> {
    let shape = |c: [f64; 2], angle: f64, s: [f64; 2], e: [f64; 2]| Shape { c, angle, s, e };
    vec![
        (
            "circle",
            shape([0.0123, -0.0311], 0.0, [0.37, 0.37], [2.0, 2.0]),
        ),
        (
            "small circle",
            shape([0.517, 0.2], 0.9, [0.2, 0.2], [2.0, 2.0]),
        ),
        (
            "ellipse 3:1",
            shape([0.31, 0.07], 0.0, [0.6, 0.2], [2.0, 2.0]),
        ),
        (
            "ellipse 3:1 rotated",
            shape([-0.2, 0.13], 0.7, [0.6, 0.2], [2.0, 2.0]),
        ),
        (
            "squircle e=4",
            shape([0.011, 0.023], 0.0, [0.4, 0.4], [4.0, 4.0]),
        ),
        (
            "squircle e=4 rotated",
            shape([0.3, -0.1], 1.1, [0.45, 0.3], [4.0, 4.0]),
        ),
        (
            "blocky e=10",
            shape([0.05, 0.0017], 0.0, [0.5, 0.3], [10.0, 10.0]),
        ),
        (
            "blocky e=10 rotated",
            shape([0.05, 0.0017], 0.4, [0.5, 0.3], [10.0, 10.0]),
        ),
        (
            "diamond-like e=1.5",
            shape([-0.07, 0.4], 2.5, [0.35, 0.5], [1.5, 1.5]),
        ),
        (
            "diamond e=1",
            shape([0.1, 0.1], 0.0, [0.3, 0.3], [1.0, 1.0]),
        ),
        (
            "star e=0.6",
            shape([0.0071, -0.013], 0.0, [0.5, 0.5], [0.6, 0.6]),
        ),
        (
            "star e=0.6 rotated",
            shape([0.2, 0.3], 0.3, [0.55, 0.35], [0.6, 0.6]),
        ),
        (
            "mixed exponents",
            shape([-0.3, 0.0], 2.0, [0.3, 0.45], [0.8, 3.0]),
        ),
    ]
}

const PPU: f64 = 256.0;

// ---------------------------------------------------------------------------------------------
// The references themselves
// ---------------------------------------------------------------------------------------------

#[test]
fn gamma_reference_matches_known_values() {
    let sqrt_pi = PI.sqrt();
    for (x, want) in [
        (0.5, sqrt_pi),
        (1.0, 1.0),
        (1.5, 0.5 * sqrt_pi),
        (2.0, 1.0),
        (2.5, 0.75 * sqrt_pi),
        (5.0, 24.0),
        (1.0 / 3.0, 2.678_938_534_707_747_6),
        (0.25, 3.625_609_908_221_908),
        (3.7, 4.170_651_783_796_603),
    ] {
        let got = ln_gamma(x).exp();
        assert!(
            ((got - want) / want).abs() < 1e-12,
            "Gamma({x}) = {got}, want {want}"
        );
    }
}

#[test]
fn area_reference_matches_closed_forms_and_quadrature() {
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    // Closed forms: disc, ellipse, diamond.
    assert!(
        rel(
            superellipse_area([0.37, 0.37], [2.0, 2.0]),
            PI * 0.37 * 0.37
        ) < 1e-13
    );
    assert!(rel(superellipse_area([0.6, 0.2], [2.0, 2.0]), PI * 0.6 * 0.2) < 1e-13);
    assert!(rel(superellipse_area([0.3, 0.5], [1.0, 1.0]), 2.0 * 0.3 * 0.5) < 1e-13);
    // Quadrature of 4 sy integral_0^sx (1 - (u/sx)^ex)^(1/ey) du, for every exponent used.
    for (name, s) in zoo() {
        let n = 400_000;
        let mut sum = 0.0;
        for i in 0..n {
            let t = (f64::from(i) + 0.5) / f64::from(n);
            sum += (1.0 - t.powf(s.e[0])).max(0.0).powf(1.0 / s.e[1]);
        }
        let quad = 4.0 * s.s[0] * s.s[1] * sum / f64::from(n);
        let closed = superellipse_area(s.s, s.e);
        assert!(
            rel(quad, closed) < 1e-5,
            "{name}: quadrature {quad}, closed form {closed}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Per-pixel coverage
// ---------------------------------------------------------------------------------------------

/// A disc of radius 0.37 at 256 pixels per unit (94.7 pixels), its centre off the pixel grid:
/// every pixel's coverage against the exact area of the pixel inside the disc.
///
/// The bound: a part proven inside or outside counts exactly, and a part still on the boundary
/// after `d` splits counts by the sign at its centre, so the coverage is that of a `2^d x 2^d`
/// grid of point samples (see `coverage_is_point_sampling_at_every_depth`). For an edge that is
/// straight at the pixel's scale, such a grid is off by at most half a row of samples,
/// `2^-(d+1)` (1/8 at depth 2, reached by edges parallel to the pixel's sides); the curvature
/// of a 95-pixel radius adds well under 0.01.
#[test]
fn disc_coverage_per_pixel_matches_exact_areas() {
    // Point sampling on a 4 x 4 grid: up to 1/8 off where an edge runs along the pixel's sides.
    check_disc(
        Antialias::Split(DEFAULT_AA_DEPTH),
        0.5 / f64::from(1u32 << DEFAULT_AA_DEPTH) + 0.01,
    );
}

/// The default tangent-line coverage: exact for a straight edge, so on a disc 95 px across only
/// the curvature within a pixel is left (well under a hundredth).
#[test]
fn tangent_line_coverage_per_pixel_matches_exact_areas() {
    check_disc(Antialias::Gradient, 0.01);
}

fn check_disc(aa: Antialias, bound: f64) {
    let r = 0.37;
    let c = [0.0123, -0.0311];
    let disc = Shape {
        c,
        angle: 0.0,
        s: [r, r],
        e: [2.0, 2.0],
    };
    let (lo, hi) = reach_box(&disc);
    let grid = Grid::around(lo, hi, PPU, 3.0);
    let view = grid.view();
    let cov = coverage_map_with(&placed(&disc), &view, aa);

    let mut exact_sum = 0.0;
    let (mut max_err, mut worst) = (0.0f64, (0, 0, 0.0, 0.0));
    let (mut sq, mut signed, mut boundary) = (0.0, 0.0, 0usize);
    let (mut partial, mut partial_exact) = (0usize, 0usize);
    let mut inside_pixels = 0usize;
    for y in 0..grid.h {
        for x in 0..grid.w {
            let [x0, x1, y0, y1] = grid.pixel(x, y);
            let (x0, x1, y0, y1) = (x0 - c[0], x1 - c[0], y0 - c[1], y1 - c[1]);
            // Nearest and farthest distances from the centre to the pixel.
            let near = 0.0f64.clamp(x0, x1).hypot(0.0f64.clamp(y0, y1));
            let far = x0.abs().max(x1.abs()).hypot(y0.abs().max(y1.abs()));
            let k = (y * grid.w + x) as usize;
            let got = cov[k];
            let exact = if far < r - 1e-12 {
                inside_pixels += 1;
                assert_eq!(got, 1.0, "pixel ({x}, {y}) lies inside the disc");
                1.0
            } else if near > r {
                assert_eq!(got, 0.0, "pixel ({x}, {y}) lies outside the disc");
                0.0
            } else {
                let area = disc_in_box(r, x0, x1, y0, y1, 4000) / (grid.px * grid.px);
                boundary += 1;
                sq += (got - area).powi(2);
                signed += got - area;
                if area > 0.05 && area < 0.95 {
                    partial_exact += 1;
                }
                if got > 0.0 && got < 1.0 {
                    partial += 1;
                }
                area
            };
            exact_sum += exact;
            // Nothing painted outside the disc: a painted pixel has a sample or a part proven
            // inside, so it meets the disc (which is stronger than "within a pixel of it").
            if got > 0.0 {
                assert!(
                    near <= r * (1.0 + 1e-12),
                    "pixel ({x}, {y}) painted {got} but {near} from the centre"
                );
            }
            let err = (got - exact).abs();
            if err > max_err {
                max_err = err;
                worst = (x, y, got, exact);
            }
        }
    }
    // The reference itself: the exact coverages add up to the disc's area.
    let disc_px = PI * r * r / (grid.px * grid.px);
    assert!(
        ((exact_sum - disc_px) / disc_px).abs() < 1e-6,
        "reference sum {exact_sum} vs {disc_px}"
    );
    let rms = (sq / boundary as f64).sqrt();
    let bias = signed / boundary as f64;
    eprintln!(
        "disc r = {r} ({:.1} px): {boundary} boundary pixels, {inside_pixels} inside; max |error| \
         {max_err:.4} at {worst:?}, rms {rms:.4}, mean {bias:+.5}; {partial} pixels strictly \
         between 0 and 1 ({partial_exact} with exact coverage in (0.05, 0.95))",
        r * PPU
    );
    assert!(
        max_err <= bound,
        "max per-pixel error {max_err} > {bound} at {worst:?}"
    );
    assert!(rms < 0.05, "rms error {rms} over the boundary pixels");
    assert!(
        bias.abs() < 0.01,
        "coverage biased by {bias} per boundary pixel"
    );
    // Anti-aliased: the boundary takes intermediate values.
    assert!(
        partial as f64 >= 0.9 * partial_exact as f64 && partial > 500,
        "only {partial} pixels strictly between 0 and 1, {partial_exact} expected"
    );
}

/// The depth's point-sampling model, exactly: at depth `d` every pixel's coverage is the
/// fraction of the `2^d x 2^d` centres of its parts where the implicit function (written here
/// again) is `<= 0`, so that the intervals only save work and never change the answer. Also the
/// visited pixels are exactly those with some sample inside.
#[test]
fn coverage_is_point_sampling_at_every_depth() {
    let shapes = [
        (
            "rotated ellipse",
            [0.013, 0.021],
            0.7,
            [0.3, 0.1],
            [2.0, 2.0],
        ),
        (
            "rotated star",
            [-0.0123, 0.031],
            0.3,
            [0.25, 0.2],
            [0.6, 0.6],
        ),
        ("rotated blocky", [0.0, 0.0], 1.9, [0.2, 0.12], [10.0, 10.0]),
        ("tilted mixed", [0.1, 0.2], 2.2, [0.15, 0.25], [0.8, 3.0]),
    ];
    let mut checked = 0usize;
    for (name, c, angle, s, e) in shapes {
        let shape = Shape { c, angle, s, e };
        let (lo, hi) = reach_box(&shape);
        let grid = Grid::around(lo, hi, PPU, 2.0);
        let view = grid.view();
        let lib = placed(&shape);
        for depth in 0..=3 {
            let got = coverage_map(&lib, &view, depth);
            let (want, tie) = sampled(&shape, &grid, 1 << depth);
            let parts = f64::from(1u32 << (2 * depth));
            for k in 0..grid.len() {
                // Multiples of the smallest part.
                assert_eq!(
                    (got[k] * parts).fract(),
                    0.0,
                    "{name}, depth {depth}: coverage {} is no multiple of 1/{parts}",
                    got[k]
                );
                if tie[k] {
                    assert!((got[k] - want[k]).abs() <= 1.0 / parts + 1e-12);
                    continue;
                }
                let (x, y) = (k as u32 % grid.w, k as u32 / grid.w);
                assert_eq!(
                    got[k], want[k],
                    "{name}, depth {depth}: pixel ({x}, {y}) coverage {} but {} of its samples \
                     are inside",
                    got[k], want[k]
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 100_000);
}

/// Depth 0 paints whole pixels: every coverage is exactly 1. Depths beyond the maximum are
/// clamped to it (no endless recursion): the same picture as the maximum.
#[test]
fn depth_zero_is_binary_and_deep_requests_are_clamped() {
    let shape = Shape {
        c: [0.01, 0.02],
        angle: 0.5,
        s: [0.05, 0.03],
        e: [4.0, 4.0],
    };
    let (lo, hi) = reach_box(&shape);
    let grid = Grid::around(lo, hi, PPU, 2.0);
    let view = grid.view();
    let lib = placed(&shape);
    let zero = coverage_map(&lib, &view, 0);
    assert!(zero.iter().all(|&c| c == 0.0 || c == 1.0));
    assert!(zero.iter().filter(|&&c| c == 1.0).count() > 100);
    let deepest = coverage_map(&lib, &view, MAX_AA_DEPTH);
    let beyond = coverage_map(&lib, &view, MAX_AA_DEPTH + 20);
    assert_eq!(deepest, beyond);
    assert_eq!(
        painted(&lib, &view, [9, 8, 7, 255], Antialias::Split(MAX_AA_DEPTH)),
        painted(&lib, &view, [9, 8, 7, 255], Antialias::Split(u32::MAX))
    );
}

// ---------------------------------------------------------------------------------------------
// Areas
// ---------------------------------------------------------------------------------------------

/// The painted area of each shape (the sum of coverages, and the alpha of `paint_shape` on a
/// transparent buffer) against the closed-form area, at 256 pixels per unit.
fn check_areas(aa: Antialias, tol: f64) -> f64 {
    let mut worst = 0.0f64;
    for (name, shape) in zoo() {
        let (lo, hi) = reach_box(&shape);
        let grid = Grid::around(lo, hi, PPU, 2.0);
        let view = grid.view();
        let lib = placed(&shape);
        let want = superellipse_area(shape.s, shape.e) * PPU * PPU;
        let by_cover: f64 = coverage_map_with(&lib, &view, aa).iter().sum();
        let by_alpha = alpha_area(&painted(&lib, &view, [255, 255, 255, 255], aa));
        let by_half_alpha = alpha_area(&painted(&lib, &view, [10, 200, 30, 128], aa));
        for (how, got) in [("coverage", by_cover), ("alpha", by_alpha)] {
            let err = (got - want) / want;
            eprintln!(
                "aa {aa:?}, {name:22} by {how:8}: {got:10.1} px^2 vs {want:10.1}, error {:+.4}%",
                100.0 * err
            );
            worst = worst.max(err.abs());
            assert!(
                err.abs() < tol,
                "{name}, aa {aa:?}: area by {how} {got} px^2, closed form {want} (error {err:+e})"
            );
        }
        // A half-transparent colour lays half the alpha (to a rounding per pixel).
        let half = by_half_alpha / (128.0 / 255.0);
        assert!(
            ((half - want) / want).abs() < tol + 0.005,
            "{name}: alpha of a half-transparent paint {by_half_alpha}"
        );
    }
    worst
}

#[test]
fn areas_match_closed_form_with_tangent_line_coverage() {
    let worst = check_areas(Antialias::Gradient, 0.005);
    eprintln!("worst relative area error with tangent lines: {worst:.5}");
}

#[test]
fn areas_match_closed_form_at_default_depth() {
    let worst = check_areas(Antialias::Split(DEFAULT_AA_DEPTH), 0.005);
    eprintln!("worst relative area error at depth {DEFAULT_AA_DEPTH}: {worst:.5}");
}

#[test]
fn areas_match_closed_form_at_the_papers_depth_one() {
    let worst = check_areas(Antialias::Split(1), 0.01);
    eprintln!("worst relative area error at depth 1: {worst:.5}");
}

/// A disc of a third of a pixel anywhere: painted at most one pixel (or the few it touches),
/// never panics, and on average over positions its area comes out right.
#[test]
fn subpixel_disc_is_painted_in_proportion() {
    let grid = Grid {
        left: 0.0,
        top: 1.0,
        px: 1.0 / 64.0,
        w: 64,
        h: 64,
    };
    let view = grid.view();
    let r = grid.px / 3.0;
    let mut total = 0.0;
    let n = 400;
    for i in 0..n {
        let t = f64::from(i) / f64::from(n);
        let c = [
            0.3 + 2.0 * grid.px * t,
            0.4 + 1.7 * grid.px * (7.0 * t).fract(),
        ];
        let disc = Shape {
            c,
            angle: 0.0,
            s: [r, r],
            e: [2.0, 2.0],
        };
        let cov = coverage_map(&placed(&disc), &view, 3);
        let touched = cov.iter().filter(|&&c| c > 0.0).count();
        assert!(touched <= 4, "a subpixel disc touched {touched} pixels");
        total += cov.iter().sum::<f64>();
    }
    let want = f64::from(n) * PI / 9.0;
    assert!(
        ((total - want) / want).abs() < 0.05,
        "mean painted area {} px^2 vs {} px^2",
        total / f64::from(n),
        PI / 9.0
    );
}

// ---------------------------------------------------------------------------------------------
// Clipping, determinism, blending
// ---------------------------------------------------------------------------------------------

/// Shapes hanging over each side and corner of the image, and one covering it: no panic, only
/// in-image pixels visited (checked in `coverage_map`), and the visible area equal to an 8 x 8
/// point-sampled reference within 1%.
#[test]
fn shapes_partly_outside_the_image_are_clipped() {
    // The image: [0, 0.75] x [0, 0.5] at 256 px per unit, 192 x 128 pixels.
    let grid = Grid {
        left: 0.0,
        top: 0.5,
        px: 1.0 / PPU,
        w: 192,
        h: 128,
    };
    let view = grid.view();
    let cases = [
        (
            "over the left side",
            [0.05, 0.25],
            0.4,
            [0.3, 0.2],
            [2.0, 2.0],
        ),
        (
            "over the right side",
            [0.7, 0.2],
            1.2,
            [0.25, 0.15],
            [4.0, 4.0],
        ),
        ("over the top", [0.4, 0.45], 0.2, [0.2, 0.12], [0.6, 0.6]),
        (
            "over the bottom",
            [0.3, -0.05],
            0.0,
            [0.2, 0.15],
            [1.5, 1.5],
        ),
        (
            "over a corner",
            [0.72, 0.48],
            0.9,
            [0.2, 0.15],
            [10.0, 10.0],
        ),
        (
            "over the whole image",
            [0.37, 0.25],
            0.3,
            [0.9, 0.8],
            [2.0, 2.0],
        ),
    ];
    for (name, c, angle, s, e) in cases {
        let shape = Shape { c, angle, s, e };
        let lib = placed(&shape);
        let got: f64 = coverage_map(&lib, &view, DEFAULT_AA_DEPTH).iter().sum();
        let want: f64 = sampled(&shape, &grid, 8).0.iter().sum();
        eprintln!("{name}: visible area {got:.1} px^2, sampled reference {want:.1}");
        assert!(want > 500.0, "{name}: the case shows too little");
        assert!(
            ((got - want) / want).abs() < 0.01,
            "{name}: visible area {got} px^2, sampled reference {want}"
        );
        // paint_shape writes only inside the buffer (it would panic otherwise).
        let px = painted(
            &lib,
            &view,
            [1, 2, 3, 255],
            Antialias::Split(DEFAULT_AA_DEPTH),
        );
        assert_eq!(px.len(), grid.len() * 4);
    }
    // Covering the whole image: every pixel proven inside, coverage 1.
    let big = Shape {
        c: [0.37, 0.25],
        angle: 0.3,
        s: [0.9, 0.8],
        e: [2.0, 2.0],
    };
    let cov = coverage_map(&placed(&big), &view, DEFAULT_AA_DEPTH);
    assert!(cov.iter().all(|&c| c == 1.0));
}

#[test]
fn shapes_off_the_image_paint_nothing() {
    let grid = Grid {
        left: 0.0,
        top: 0.5,
        px: 1.0 / PPU,
        w: 192,
        h: 128,
    };
    let view = grid.view();
    for c in [
        [-0.5, 0.25],
        [1.3, 0.25],
        [0.3, 0.9],
        [0.3, -0.4],
        [5.0, 5.0],
    ] {
        let shape = Shape {
            c,
            angle: 0.5,
            s: [0.2, 0.1],
            e: [2.0, 2.0],
        };
        let mut visits = 0;
        cover(&placed(&shape), &view, DEFAULT_AA_DEPTH, |_, _, _| {
            visits += 1
        });
        assert_eq!(visits, 0, "a shape at {c:?} painted {visits} pixels");
    }
}

#[test]
fn rendering_is_deterministic() {
    let grid = Grid {
        left: -0.6,
        top: 0.6,
        px: 1.0 / PPU,
        w: 307,
        h: 307,
    };
    let view = grid.view();
    let paint_all = || {
        let mut pixels = vec![0u8; grid.len() * 4];
        for (i, (_, shape)) in zoo().iter().enumerate() {
            let colour = [(40 * i) as u8, 255 - (20 * i) as u8, 90, 200];
            paint_shape(&mut pixels, &view, &placed(shape), colour, DEFAULT_AA_DEPTH);
        }
        pixels
    };
    let first = paint_all();
    assert!(first.iter().any(|&b| b != 0));
    assert_eq!(first, paint_all());
    let mut log = Vec::new();
    let mut again = Vec::new();
    let star = placed(&zoo()[11].1);
    cover(&star, &view, 2, |x, y, c| log.push((x, y, c.to_bits())));
    cover(&star, &view, 2, |x, y, c| again.push((x, y, c.to_bits())));
    assert_eq!(log, again);
}

/// "Source over" on premultiplied pixels: an opaque colour replaces the inside, a translucent
/// one blends `a * colour + (1 - a) * below`, and boundary pixels lie between.
#[test]
fn paint_blends_source_over() {
    let shape = Shape {
        c: [0.101, 0.099],
        angle: 0.0,
        s: [0.08, 0.08],
        e: [2.0, 2.0],
    };
    let grid = Grid {
        left: 0.0,
        top: 0.2,
        px: 1.0 / PPU,
        w: 51,
        h: 51,
    };
    let view = grid.view();
    let lib = placed(&shape);
    let white = || vec![255u8; grid.len() * 4];
    let mut opaque = white();
    paint_shape(&mut opaque, &view, &lib, [200, 100, 50, 255], 2);
    let mut translucent = white();
    paint_shape(&mut translucent, &view, &lib, [200, 100, 50, 128], 2);
    let (mut inside, mut edge) = (0, 0);
    for y in 0..grid.h {
        for x in 0..grid.w {
            let [x0, x1, y0, y1] = grid.pixel(x, y);
            let corners = [[x0, y0], [x0, y1], [x1, y0], [x1, y1]];
            let k = 4 * (y * grid.w + x) as usize;
            let (o, t) = (&opaque[k..k + 4], &translucent[k..k + 4]);
            if corners.iter().all(|&p| shape.f(p) < 0.0) {
                inside += 1;
                assert_eq!(o, [200, 100, 50, 255]);
                // 200 * a + 255 * (1 - a) with a = 128/255, and so on; alpha stays opaque.
                let a = 128.0 / 255.0;
                let want = [200.0, 100.0, 50.0].map(|v| v * a + 255.0 * (1.0 - a));
                for ch in 0..3 {
                    assert!(
                        (f64::from(t[ch]) - want[ch]).abs() <= 1.0,
                        "{t:?} vs {want:?}"
                    );
                }
                assert_eq!(t[3], 255);
            } else if corners.iter().all(|&p| shape.f(p) > 0.0)
                && (shape.c[0].clamp(x0, x1) - shape.c[0])
                    .hypot(shape.c[1].clamp(y0, y1) - shape.c[1])
                    > shape.s[0]
            {
                assert_eq!(o, [255; 4]);
                assert_eq!(t, [255; 4]);
            } else {
                edge += 1;
                for ch in 0..3 {
                    let lo = [200, 100, 50][ch];
                    assert!(o[ch] >= lo, "edge pixel {o:?}");
                }
                assert_eq!(o[3], 255);
            }
        }
    }
    assert!(
        inside > 300 && edge > 50,
        "{inside} inside, {edge} on the edge"
    );
}

#[test]
fn view_maps_points_and_boxes_to_pixels() {
    let region = Aabb::new(Vec2::new(-1.0, 0.0), Vec2::new(3.0, 2.0));
    let view = View::fit(region, 200);
    assert_eq!((view.width, view.height), (200, 100));
    assert_eq!(View::fit(region, 3).height, 2); // 1.5 rounds up
    assert_eq!(View::fit(region, 1).height, 1); // never empty
    let (x, y) = view.to_pixel(Vec2::new(0.0, 1.5));
    assert!((x - 50.0).abs() < 1e-4 && (y - 25.0).abs() < 1e-4);
    let cell = view.cell(50, 25, 51, 26);
    assert!((cell.min.x - 0.0).abs() < 1e-12 && (cell.max.x - 0.02).abs() < 1e-12);
    assert!((cell.max.y - 1.5).abs() < 1e-12 && (cell.min.y - 1.48).abs() < 1e-12);
    // A box inside, one hanging over, one outside.
    let b = Aabb::new(Vec2::new(0.005, 1.005), Vec2::new(0.035, 1.495));
    assert_eq!(view.pixels_of(&b), Some((50, 25, 52, 50)));
    let over = Aabb::new(Vec2::new(-5.0, -5.0), Vec2::new(-0.99, 0.01));
    assert_eq!(view.pixels_of(&over), Some((0, 99, 1, 100)));
    let out = Aabb::new(Vec2::new(4.0, 0.0), Vec2::new(5.0, 1.0));
    assert_eq!(view.pixels_of(&out), None);
}

// ---------------------------------------------------------------------------------------------
// Whole worlds
// ---------------------------------------------------------------------------------------------

/// Distance from `p` to the segment `a b`.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

/// The circles preset after 400 steps (20 grains, falling and landing), drawn with one colour:
/// the image has the size of the world's region, pixels inside a grain have the grain colour,
/// pixels away from every grain and wall have the background colour, edge pixels lie between,
/// and the PNG decodes to the same picture.
#[test]
fn render_world_paints_grains_on_the_background() {
    let mut world = World::new(&Scene::preset("circles").expect("preset"));
    for _ in 0..400 {
        world.step();
    }
    assert!(world.bodies.len() >= 15, "{} grains", world.bodies.len());
    let grain = [200, 30, 40, 255];
    let background = [250, 250, 250, 255];
    let style = Style {
        width: 300,
        colouring: Colouring::Uniform(grain),
        background,
        ..Style::default()
    };
    let pixmap = render_world(&world, &style);

    // The region, written again from its definition: walls and floor with a 4% margin, up to the
    // spawn height plus the largest grain placed or that can still appear (circles: its radius;
    // the grains still to draw, by the largest of the preset's radii, 0.7), or the highest grain.
    let w = world.walls;
    let margin = 0.04 * (w.right - w.left);
    assert!(world.pending.generator().is_some(), "grains still to draw");
    let largest = world
        .bodies
        .iter()
        .map(|b| b.shape.semi_axes().x)
        .chain(
            world
                .pending
                .waiting()
                .iter()
                .map(|p| p.shape.semi_axes().x),
        )
        .fold(0.7, f64::max);
    let highest = world
        .bodies
        .iter()
        .map(|b| b.center.y + b.shape.semi_axes().y)
        .fold(world.top + largest, f64::max);
    let (left, right) = (w.left - margin, w.right + margin);
    let (bottom, top) = (w.floor - margin, highest + margin);
    let height = ((top - bottom) / (right - left) * 300.0).round() as u32;
    assert_eq!((pixmap.width(), pixmap.height()), (300, height));
    let view = View::fit(world_region(&world), 300);
    assert_eq!((pixmap.width(), pixmap.height()), (view.width, view.height));

    let image = to_rgba_image(&pixmap);
    let px = (right - left) / 300.0;
    let py = (top - bottom) / f64::from(height);
    let circles: Vec<Shape> = world
        .bodies
        .iter()
        .map(|b| {
            assert!(b.shape.is_circle());
            let r = b.shape.semi_axes().x;
            Shape {
                c: [b.center.x, b.center.y],
                angle: 0.0,
                s: [r, r],
                e: [2.0, 2.0],
            }
        })
        .collect();
    // Grain centres are painted the grain colour.
    for s in &circles {
        let x = ((s.c[0] - left) / px).floor() as u32;
        let y = ((top - s.c[1]) / py).floor() as u32;
        assert_eq!(image.get_pixel(x, y).0, grain, "centre {:?}", s.c);
    }
    // A pixel far above the heap, in the middle column, at least 8 pixels from every grain (a
    // falling one may be anywhere): the background.
    let clear = (0..height / 3).find(|&y| {
        let p = [left + 150.5 * px, top - (f64::from(y) + 0.5) * py];
        circles
            .iter()
            .all(|s| common::dist(p, s.c) > s.s[0] + 8.0 * px)
    });
    let y = clear.expect("some pixel high in the middle column is clear of every grain");
    assert_eq!(image.get_pixel(150, y).0, background);
    let wall_lines = [
        ([w.left, top], [w.left, w.floor]),
        ([w.left, w.floor], [w.right, w.floor]),
        ([w.right, w.floor], [w.right, top]),
    ];
    let (mut inside, mut outside, mut edge) = (0, 0, 0);
    for y in 0..height {
        for x in 0..300 {
            let x0 = left + f64::from(x) * px;
            let y1 = top - f64::from(y) * py;
            let (x1, y0) = (x0 + px, y1 - py);
            let centre = [x0 + 0.5 * px, y0 + 0.5 * py];
            let near_wall = wall_lines
                .iter()
                .any(|&(a, b)| to_segment(centre, a, b) < 4.0 * px);
            if near_wall {
                continue;
            }
            let pixel = image.get_pixel(x, y).0;
            let corners = [[x0, y0], [x0, y1], [x1, y0], [x1, y1]];
            let touching: Vec<&Shape> = circles
                .iter()
                .filter(|s| {
                    let n = [s.c[0].clamp(x0, x1), s.c[1].clamp(y0, y1)];
                    common::dist(n, s.c) <= s.s[0]
                })
                .collect();
            if touching
                .iter()
                .any(|s| corners.iter().all(|&p| s.f(p) < -1e-9))
            {
                inside += 1;
                assert_eq!(pixel, grain, "pixel ({x}, {y}) is inside a grain");
            } else if touching.is_empty() {
                outside += 1;
                assert_eq!(pixel, background, "pixel ({x}, {y}) touches no grain");
            } else if touching.len() == 1 {
                edge += 1;
                for ch in 0..3 {
                    let (lo, hi) = (grain[ch].min(background[ch]), grain[ch].max(background[ch]));
                    assert!(
                        pixel[ch] >= lo && pixel[ch] <= hi,
                        "edge pixel ({x}, {y}) is {pixel:?}"
                    );
                }
            }
        }
    }
    assert!(inside > 1000 && outside > 10_000 && edge > 300);

    // The PNG holds the same picture.
    let mut png = Vec::new();
    write_png(&pixmap, &mut png).expect("encode");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let decoded = image::load_from_memory(&png).expect("decode").to_rgba8();
    assert_eq!(decoded, image);
}

/// Colouring by exponent paints circles green; an explicit region sets the picture's size; the
/// same world drawn twice gives the same pixels.
#[test]
fn render_world_colours_regions_and_repeats() {
    let mut world = World::new(&Scene::preset("circles").expect("preset"));
    for _ in 0..100 {
        world.step();
    }
    let b = &world.bodies[0];
    let r = b.shape.semi_axes().x;
    // A region of 4r x 2r around the first grain, drawn 200 pixels wide.
    let region = Aabb::new(
        Vec2::new(b.center.x - 2.0 * r, b.center.y - r),
        Vec2::new(b.center.x + 2.0 * r, b.center.y + r),
    );
    let style = Style {
        width: 200,
        region: Some(region),
        walls: false,
        ..Style::default()
    };
    let pixmap = render_world(&world, &style);
    assert_eq!((pixmap.width(), pixmap.height()), (200, 100));
    let image = to_rgba_image(&pixmap);
    assert_eq!(image.get_pixel(100, 50).0, [0x43, 0xa0, 0x47, 255]);
    // Left and right of the grain, inside the region: background unless another grain is there.
    for x in [2, 197] {
        let px = b.center.x - 2.0 * r + (f64::from(x) + 0.5) * 4.0 * r / 200.0;
        let free = world.bodies.iter().all(|o| {
            let d = (o.center.x - px).hypot(o.center.y - b.center.y);
            d > o.shape.semi_axes().x.max(o.shape.semi_axes().y) * SQRT_2 + 4.0 * r / 100.0
        });
        if free {
            assert_eq!(image.get_pixel(x, 50).0, [250, 250, 250, 255]);
        }
    }
    assert_eq!(
        render_world(&world, &style).data(),
        pixmap.data(),
        "two renderings differ"
    );
}

/// A scene with three groups, poured and drawn `Colouring::Group`: the pixel at every grain's
/// centre has its group's documented colour (first blue, second red, third green), whatever
/// its shape, and each group keeps the shapes of its own ranges.
#[test]
fn colouring_by_group_follows_the_scene_groups() {
    let text = r#"
seed = 3
steps = 10
[box]
left = -4.0
right = 4.0
floor = 0.0
top = 6.0
[spawn]
interval = 10
[[group]]
name = "small circles"
count = 4
radius = [0.3, 0.35]
[[group]]
name = "large circles"
count = 4
radius = [0.6, 0.65]
[[group]]
name = "blocks"
count = 4
semi_axes = [[0.4, 0.45], [0.4, 0.45]]
exponent = 4.0
"#;
    let scene = Scene::from_toml(text).expect("scene");
    let mut world = World::new(&scene);
    while !world.all_spawned() {
        world.step();
    }
    // Which group a grain must be in, read off its shape alone.
    let group_of = |b: &supergrain::body::Body| {
        let s = b.shape.semi_axes();
        if b.shape.exponents()[0] == 4.0 {
            2
        } else if s.x < 0.5 {
            0
        } else {
            1
        }
    };
    assert_eq!(world.bodies.len(), 12);
    for b in &world.bodies {
        assert_eq!(b.group, group_of(b), "grain of shape {:?}", b.shape);
    }
    // A dump keeps the groups.
    let restarted = supergrain::io::Dump::of(&world)
        .to_world()
        .expect("restart");
    let groups = |w: &World| w.bodies.iter().map(|b| b.group).collect::<Vec<_>>();
    assert_eq!(groups(&restarted), groups(&world));
    let style = Style {
        width: 400,
        colouring: Colouring::Group,
        ..Style::default()
    };
    let image = to_rgba_image(&render_world(&world, &style));
    let view = View::fit(world_region(&world), 400);
    let colours = [
        [0x1e, 0x88, 0xe5, 255],
        [0xe5, 0x39, 0x35, 255],
        [0x43, 0xa0, 0x47, 255],
    ];
    for b in &world.bodies {
        let (px, py) = view.to_pixel(b.center);
        let pixel = image.get_pixel(px.floor() as u32, py.floor() as u32).0;
        assert_eq!(
            pixel, colours[b.group as usize],
            "grain of group {}",
            b.group
        );
    }
}

//! Shape properties (SPEC §1) against references written here from first principles: closed
//! forms for the circle, ellipse, diamond and rectangle, brute-force grid integration of the
//! implicit inequality, a parametric boundary sampled densely, and finite differences of the
//! implicit function. Nothing below builds a reference from the library's own output.

mod common;

use common::Rng;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

use supergrain::geometry::Vec2;
use supergrain::shape::{HalfPlane, Pose, Superellipse};

fn shape(s: [f64; 2], e: [f64; 2]) -> Superellipse {
    Superellipse::new(s, e).expect("valid shape")
}

fn pose(c: [f64; 2], angle: f64) -> Pose {
    Pose::new(Vec2::new(c[0], c[1]), angle).expect("valid pose")
}

fn assert_rel(got: f64, want: f64, tol: f64, what: &str) {
    let err = (got - want).abs() / want.abs();
    assert!(
        err <= tol,
        "{what}: got {got}, want {want} (relative error {err:e} > {tol:e})"
    );
}

/// The SPEC formula, written again: `f = |u/sx|^ex + |v/sy|^ey - 1`, `(u, v) = R(-theta)(p - c)`.
fn f_ref(s: [f64; 2], e: [f64; 2], c: [f64; 2], angle: f64, p: [f64; 2]) -> f64 {
    let (sn, cs) = angle.sin_cos();
    let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
    let u = cs * dx + sn * dy;
    let v = -sn * dx + cs * dy;
    (u / s[0]).abs().powf(e[0]) + (v / s[1]).abs().powf(e[1]) - 1.0
}

/// The boundary point at parameter `t`, in the shape's own frame:
/// `(sx sgn(cos t) |cos t|^(2/ex), sy sgn(sin t) |sin t|^(2/ey))` satisfies `h = cos^2 + sin^2 = 1`.
fn boundary_local(s: [f64; 2], e: [f64; 2], t: f64) -> [f64; 2] {
    let (sn, cs) = t.sin_cos();
    let g = |x: f64, e: f64| x.signum() * x.abs().powf(2.0 / e);
    [s[0] * g(cs, e[0]), s[1] * g(sn, e[1])]
}

/// The boundary point at parameter `t`, relative to the centre, in world axes.
fn boundary_offset(s: [f64; 2], e: [f64; 2], angle: f64, t: f64) -> [f64; 2] {
    let [u, v] = boundary_local(s, e, t);
    let (sn, cs) = angle.sin_cos();
    [cs * u - sn * v, sn * u + cs * v]
}

/// Brute-force midpoint-grid integration of `1` and `x^2 + y^2` over `h(x, y) <= 1`, on an
/// `n x n` grid of the quarter `[0, sx] x [0, sy]` (the shape is symmetric in both axes).
fn grid_area_and_polar_moment(s: [f64; 2], e: [f64; 2], n: usize) -> (f64, f64) {
    let (dx, dy) = (s[0] / n as f64, s[1] / n as f64);
    let xs: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5) * dx).collect();
    let ys: Vec<f64> = (0..n).map(|j| (j as f64 + 0.5) * dy).collect();
    // The inequality's two terms, one per column and one per row.
    let hx: Vec<f64> = xs.iter().map(|x| (x / s[0]).powf(e[0])).collect();
    let hy: Vec<f64> = ys.iter().map(|y| (y / s[1]).powf(e[1])).collect();
    let (mut count, mut second) = (0u64, 0.0f64);
    for (j, &y) in ys.iter().enumerate() {
        for (i, &x) in xs.iter().enumerate() {
            if hx[i] + hy[j] <= 1.0 {
                count += 1;
                second += x * x + y * y;
            }
        }
    }
    let da = dx * dy;
    (4.0 * da * count as f64, 4.0 * da * second)
}

#[test]
fn circle_area_and_polar_moment_match_closed_forms() {
    for r in [0.01, 0.3, 1.0, 2.5, 7.0] {
        let c = Superellipse::circle(r).unwrap();
        assert_rel(c.area(), PI * r * r, 1e-12, "circle area");
        assert_rel(
            c.polar_moment_of_area(),
            PI * r.powi(4) / 2.0,
            1e-12,
            "circle J",
        );
        // A uniform disk: I = m r^2 / 2.
        assert_rel(c.moment_of_inertia(3.0), 3.0 * r * r / 2.0, 1e-12, "disk I");
    }
}

#[test]
fn ellipse_area_and_polar_moment_match_closed_forms() {
    for (a, b) in [(1.0, 2.0), (0.1, 3.0), (2.5, 0.4), (7.0, 7.5)] {
        let s = shape([a, b], [2.0, 2.0]);
        assert_rel(s.area(), PI * a * b, 1e-12, "ellipse area");
        assert_rel(
            s.polar_moment_of_area(),
            PI * a * b * (a * a + b * b) / 4.0,
            1e-12,
            "ellipse J",
        );
        // A uniform elliptic plate: I = m (a^2 + b^2) / 4.
        assert_rel(
            s.moment_of_inertia(2.0),
            2.0 * (a * a + b * b) / 4.0,
            1e-12,
            "ellipse I",
        );
    }
}

#[test]
fn diamond_area_and_polar_moment_match_closed_forms() {
    // |x/a| + |y/b| <= 1 is a rhombus with half-diagonals a and b: area 2ab, and
    // integral of x^2 = 4 * integral_0^a x^2 b (1 - x/a) dx = a^3 b / 3, so J = ab(a^2 + b^2)/3.
    for (a, b) in [(1.0, 1.0), (0.2, 3.0), (2.0, 0.5)] {
        let s = shape([a, b], [1.0, 1.0]);
        assert_rel(s.area(), 2.0 * a * b, 1e-12, "diamond area");
        assert_rel(
            s.polar_moment_of_area(),
            a * b * (a * a + b * b) / 3.0,
            1e-12,
            "diamond J",
        );
    }
}

#[test]
fn large_exponents_approach_the_rectangle() {
    // From ln Gamma(1 + x) = -gamma x + (pi^2 / 12) x^2 + O(x^3), the relative deficits of
    // exponent n against the rectangle are about (pi^2 / 6) / n^2 for the area and
    // (pi^2 / 2) / n^2 for J: a hundredfold smaller per tenfold n.
    for (a, b) in [(1.0, 1.0), (0.3, 2.0)] {
        let rect_area = 4.0 * a * b;
        let rect_j = rect_area * (a * a + b * b) / 3.0;
        let mut prev = (f64::INFINITY, f64::INFINITY);
        for n in [10.0, 100.0, 1000.0] {
            let s = shape([a, b], [n, n]);
            let (da, dj) = (
                (rect_area - s.area()) / rect_area,
                (rect_j - s.polar_moment_of_area()) / rect_j,
            );
            // Always inside the rectangle, and closer as n grows.
            assert!(da > 0.0 && dj > 0.0, "n = {n}: deficits {da}, {dj}");
            assert!(da < prev.0 && dj < prev.1, "n = {n}: not converging");
            assert!(da < 2.0 / (n * n), "n = {n}: area deficit {da}");
            assert!(dj < 6.0 / (n * n), "n = {n}: J deficit {dj}");
            prev = (da, dj);
        }
        // The top of the accepted range.
        let s = shape([a, b], [1000.0, 1000.0]);
        assert_rel(s.area(), rect_area, 4e-6, "area at n = 1000");
        assert_rel(s.polar_moment_of_area(), rect_j, 8e-6, "J at n = 1000");
    }
}

#[test]
fn mass_properties_match_grid_integration() {
    let mut rng = Rng::new(11);
    for case in 0..30 {
        let s = [rng.range(0.1, 3.0), rng.range(0.1, 3.0)];
        let e = match case {
            // Mixed and extreme exponents first, then random ones.
            0 => [0.5, 6.0],
            1 => [0.5, 0.5],
            2 => [6.0, 6.0],
            3 => [1.0, 3.0],
            _ => [rng.range(0.5, 6.0), rng.range(0.5, 6.0)],
        };
        let sh = shape(s, e);
        let (area, j) = grid_area_and_polar_moment(s, e, 1200);
        let what = format!("s = {s:?}, e = {e:?}");
        assert_rel(sh.area(), area, 5e-3, &format!("area, {what}"));
        assert_rel(sh.polar_moment_of_area(), j, 5e-3, &format!("J, {what}"));
        let m = rng.range(0.1, 10.0);
        assert_rel(
            sh.moment_of_inertia(m),
            m * j / area,
            5e-3,
            &format!("I, {what}"),
        );
    }
}

/// The largest and smallest world offsets (x and y, relative to the centre) of `m` uniform
/// boundary samples, refined by golden-section search around the best sample. `m` is a
/// multiple of 4, so the vertices `t = k pi/2` are samples.
fn sampled_extent(s: [f64; 2], e: [f64; 2], angle: f64, m: usize) -> [[f64; 2]; 2] {
    let mut out = [[0.0; 2]; 2];
    for (axis, side) in out.iter_mut().enumerate() {
        for (k, sign) in [-1.0f64, 1.0].into_iter().enumerate() {
            let comp = |t: f64| sign * boundary_offset(s, e, angle, t)[axis];
            let dt = TAU / m as f64;
            let (mut best_t, mut best) = (0.0, f64::NEG_INFINITY);
            for i in 0..m {
                let t = i as f64 * dt;
                let v = comp(t);
                if v > best {
                    (best_t, best) = (t, v);
                }
            }
            let (mut lo, mut hi) = (best_t - dt, best_t + dt);
            let g = 0.618_033_988_749_895;
            for _ in 0..80 {
                let (t1, t2) = (hi - g * (hi - lo), lo + g * (hi - lo));
                if comp(t1) < comp(t2) {
                    lo = t1;
                } else {
                    hi = t2;
                }
            }
            best = best.max(comp(0.5 * (lo + hi)));
            side[k] = sign * best;
        }
    }
    out
}

fn random_exponent(rng: &mut Rng) -> f64 {
    match rng.next_u64() % 6 {
        0 => 1.0,
        1 => 2.0,
        2 => rng.range(0.3, 1.0),
        _ => rng.range(0.3, 8.0),
    }
}

#[test]
fn bounding_box_contains_every_boundary_sample() {
    let mut rng = Rng::new(21);
    for case in 0..200 {
        let s = [rng.range(0.05, 3.0), rng.range(0.05, 3.0)];
        let e = if case % 3 == 0 {
            let x = random_exponent(&mut rng);
            [x, x]
        } else {
            [random_exponent(&mut rng), random_exponent(&mut rng)]
        };
        let c = [rng.range(-50.0, 50.0), rng.range(-50.0, 50.0)];
        let angle = match case % 5 {
            0 => 0.0,
            1 => FRAC_PI_2 * (rng.next_u64() % 4) as f64,
            _ => rng.range(-10.0, 10.0),
        };
        let b = shape(s, e).bounding_box(&pose(c, angle));
        // Rounding of the samples' own world coordinates.
        let slack = 1e-13 * (c[0].abs() + c[1].abs() + s[0] + s[1]);
        for i in 0..4096 {
            let o = boundary_offset(s, e, angle, i as f64 * TAU / 4096.0);
            let p = [c[0] + o[0], c[1] + o[1]];
            assert!(
                b.min.x <= p[0] + slack
                    && p[0] <= b.max.x + slack
                    && b.min.y <= p[1] + slack
                    && p[1] <= b.max.y + slack,
                "s = {s:?}, e = {e:?}, c = {c:?}, angle = {angle}: {p:?} outside {b:?}"
            );
        }
    }
}

#[test]
fn bounding_box_is_tight_for_equal_exponents() {
    let mut rng = Rng::new(22);
    for case in 0..120 {
        let s = [rng.range(0.05, 3.0), rng.range(0.05, 3.0)];
        // Exponents >= 1: the Holder bound is the exact support; < 1: the diamond hull's,
        // whose extremes are the vertices, which the shape shares.
        let e = match case % 4 {
            0 => rng.range(0.3, 1.0),
            1 => 1.0,
            _ => rng.range(1.0, 8.0),
        };
        let c = [rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)];
        let angle = if case % 7 == 0 {
            0.0
        } else {
            rng.range(0.0, TAU)
        };
        let b = shape(s, [e, e]).bounding_box(&pose(c, angle));
        let ext = sampled_extent(s, [e, e], angle, 4096);
        let got = [
            [b.min.x - c[0], b.max.x - c[0]],
            [b.min.y - c[1], b.max.y - c[1]],
        ];
        let tol = 1e-6 * s[0].max(s[1]);
        for axis in 0..2 {
            for k in 0..2 {
                assert!(
                    (got[axis][k] - ext[axis][k]).abs() <= tol,
                    "s = {s:?}, e = {e}, angle = {angle}: box side {:?} vs sampled {:?}",
                    got[axis],
                    ext[axis]
                );
            }
        }
    }
}

#[test]
fn bounding_radius_holds_every_boundary_sample() {
    let mut rng = Rng::new(23);
    for _ in 0..200 {
        let s = [rng.range(0.05, 3.0), rng.range(0.05, 3.0)];
        let e = [random_exponent(&mut rng), random_exponent(&mut rng)];
        let r = shape(s, e).bounding_radius();
        let far = (0..4096)
            .map(|i| {
                let p = boundary_local(s, e, i as f64 * TAU / 4096.0);
                p[0].hypot(p[1])
            })
            .fold(0.0f64, f64::max);
        assert!(
            r >= far,
            "s = {s:?}, e = {e:?}: radius {r} < sample at {far}"
        );
        // The shape lies in its [-sx, sx] x [-sy, sy] rectangle; for exponents <= 2 it lies in
        // the ellipse, whose farthest point is the vertex at max(sx, sy), a sample (t = k pi/2).
        let bound = if e[0] <= 2.0 && e[1] <= 2.0 {
            s[0].max(s[1])
        } else {
            s[0].hypot(s[1])
        };
        assert!(
            r <= bound * (1.0 + 1e-12),
            "s = {s:?}, e = {e:?}: radius {r} looser than {bound}"
        );
    }
}

#[test]
fn value_and_gradient_match_the_formula_and_finite_differences() {
    let mut rng = Rng::new(24);
    for _ in 0..400 {
        let s = [rng.range(0.1, 3.0), rng.range(0.1, 3.0)];
        let e = [rng.range(0.5, 8.0), rng.range(0.5, 8.0)];
        let c = [rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)];
        let angle = rng.range(-4.0, 4.0);
        let sh = shape(s, e);
        let po = pose(c, angle);
        // A point away from the shape's axes, where f is smooth: |u| >= 0.1 sx, |v| >= 0.1 sy.
        let u = rng.sign() * rng.range(0.1, 1.3) * s[0];
        let v = rng.sign() * rng.range(0.1, 1.3) * s[1];
        let (sn, cs) = angle.sin_cos();
        let p = [c[0] + cs * u - sn * v, c[1] + sn * u + cs * v];
        let f = |p: [f64; 2]| f_ref(s, e, c, angle, p);

        let got = sh.value(&po, Vec2::new(p[0], p[1]));
        let want = f(p);
        assert!(
            (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
            "value at {p:?}: {got} vs {want}"
        );

        let h = 1e-5 * s[0].min(s[1]);
        let fd = [
            (f([p[0] + h, p[1]]) - f([p[0] - h, p[1]])) / (2.0 * h),
            (f([p[0], p[1] + h]) - f([p[0], p[1] - h])) / (2.0 * h),
        ];
        let g = sh.gradient(&po, Vec2::new(p[0], p[1]));
        let norm = fd[0].hypot(fd[1]);
        let err = (g.x - fd[0]).hypot(g.y - fd[1]);
        assert!(
            err <= 1e-6 * norm,
            "s = {s:?}, e = {e:?}, angle = {angle}, p = {p:?}: gradient {g:?} vs {fd:?}"
        );
    }
}

const BAD: [f64; 5] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.0, -1.5];

#[test]
fn superellipse_rejects_invalid_numbers_naming_the_field() {
    let names = ["semi-axis x", "semi-axis y", "exponent x", "exponent y"];
    for (slot, name) in names.iter().enumerate() {
        for bad in BAD {
            let mut v = [1.0, 2.0, 3.0, 0.5];
            v[slot] = bad;
            let err = Superellipse::new([v[0], v[1]], [v[2], v[3]])
                .expect_err(&format!("{name} = {bad} accepted"));
            let msg = err.to_string();
            assert!(msg.contains(name), "{name} = {bad}: message {msg:?}");
        }
    }
    for bad in BAD {
        assert!(Superellipse::circle(bad).is_err(), "radius {bad} accepted");
    }
    // The ends of the accepted ranges are valid; beyond them, an error naming the field.
    assert!(Superellipse::new([1e-9, 1e9], [0.25, 1e3]).is_ok());
    for (s, e, name) in [
        ([1e-300, 1.0], [2.0, 2.0], "semi-axis x"),
        ([1.0, 1e300], [2.0, 2.0], "semi-axis y"),
        ([1.0, 1.0], [1e-3, 2.0], "exponent x"),
        ([1.0, 1.0], [2.0, 1e4], "exponent y"),
    ] {
        let msg = Superellipse::new(s, e).unwrap_err().to_string();
        assert!(msg.contains(name) && msg.contains("between"), "{msg}");
    }
}

#[test]
fn pose_rejects_non_finite_numbers_naming_the_field() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for (slot, name) in ["center x", "center y", "angle"].iter().enumerate() {
            let mut v = [0.5, -2.0, 1.0];
            v[slot] = bad;
            let err = Pose::new(Vec2::new(v[0], v[1]), v[2])
                .expect_err(&format!("{name} = {bad} accepted"));
            let msg = err.to_string();
            assert!(msg.contains(name), "{name} = {bad}: message {msg:?}");
        }
    }
    // Zero and negative centres and angles are valid.
    assert!(Pose::new(Vec2::new(0.0, -3.0), -7.0).is_ok());
    assert!(Pose::new(Vec2::new(-1e300, 0.0), 0.0).is_ok());
}

#[test]
fn half_plane_rejects_invalid_numbers_naming_the_field() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for r in [
            HalfPlane::new(Vec2::new(0.0, 1.0), bad),
            HalfPlane::floor(bad),
            HalfPlane::left(bad),
            HalfPlane::right(bad),
        ] {
            let msg = r.expect_err("non-finite offset accepted").to_string();
            assert!(msg.contains("wall offset"), "offset {bad}: message {msg:?}");
        }
        for n in [Vec2::new(bad, 0.0), Vec2::new(1.0, bad)] {
            let msg = HalfPlane::new(n, 1.0)
                .expect_err("non-finite normal accepted")
                .to_string();
            assert!(msg.contains("wall normal"), "normal {n:?}: message {msg:?}");
        }
    }
    let msg = HalfPlane::new(Vec2::ZERO, 1.0)
        .expect_err("zero normal accepted")
        .to_string();
    assert!(msg.contains("wall normal"), "zero normal: message {msg:?}");
    // A valid wall is normalised: g(p) is the signed distance n.p/|n| - d/|n|.
    let w = HalfPlane::new(Vec2::new(3.0, 4.0), 10.0).unwrap();
    let p = Vec2::new(1.0, -2.0);
    let want = (3.0 * 1.0 + 4.0 * -2.0) / 5.0 - 10.0 / 5.0;
    assert!(
        (w.value(p) - want).abs() <= 1e-14,
        "{} vs {want}",
        w.value(p)
    );
}

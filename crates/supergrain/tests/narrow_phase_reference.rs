//! The narrow phase's overlap decisions and deepest points against references that share no
//! code with it: the Perram-Wertheim contact function for ellipses, and densely sampled
//! boundaries for every exponent (issue 2, "Correct"). Every pair is answered three ways: by
//! the certified Newton path (cold and warm-started) and by the quadtree alone.

mod common;

use common::*;
use supergrain::contact::{Contact, contact, contact_quadtree, contact_warm};
use supergrain::geometry::Vec2;
use supergrain::shape::Pose;
use supergrain::subdivision::Precision;

const DEPTH: u32 = 7;

/// The pair by each method: the certified Newton path (with its quadtree fallback), the same
/// warm-started from the pair's answer one small move earlier, and the quadtree alone.
fn run_all(a: &Shape, b: &Shape) -> [(&'static str, Contact); 3] {
    let (sa, pa) = to_lib(a);
    let (sb, pb) = to_lib(b);
    let precision = Precision::new(DEPTH, 0.0).unwrap();
    let size = b.max_axis();
    let earlier = Pose::new(
        pb.center() + Vec2::new(-0.7, 0.7) * (1e-3 * size),
        pb.angle() - 1e-3,
    )
    .unwrap();
    let mut warm = None;
    contact_warm(&sa, &pa, &sb, &earlier, &precision, &mut warm);
    [
        ("certified", contact(&sa, &pa, &sb, &pb, &precision)),
        (
            "certified, warm",
            contact_warm(&sa, &pa, &sb, &pb, &precision, &mut warm),
        ),
        ("quadtree", contact_quadtree(&sa, &pa, &sb, &pb, &precision)),
    ]
}

/// When the quadtree reports an overlap, `A1` is inside both shapes and `A1 + a_push` on B's
/// boundary (and likewise for B), by the reference implicit functions.
fn check_points(a: &Shape, b: &Shape, c: &Contact, what: &str) {
    let Some(p) = c.penetration else { return };
    let a1 = p.a_deepest.to_array();
    let a2 = p.b_deepest.to_array();
    assert!(
        a.f(a1) < 1e-9 && b.f(a1) < 1e-9,
        "{what}: A1 {a1:?} not in both"
    );
    assert!(
        a.f(a2) < 1e-9 && b.f(a2) < 1e-9,
        "{what}: A2 {a2:?} not in both"
    );
    // With a star the pushes may be cut to their part along the pair's normal (a drift of
    // both across it moves nothing apart, issue 17), and then end inside: tests/pushes.rs.
    if a.e.iter().chain(&b.e).any(|&e| e < 1.0) {
        return;
    }
    let b2 = [a1[0] + p.a_push.x, a1[1] + p.a_push.y];
    let b1 = [a2[0] + p.b_push.x, a2[1] + p.b_push.y];
    on_boundary(b, b2, p.a_push.to_array(), what);
    on_boundary(a, b1, p.b_push.to_array(), what);
}

/// `A1` is the deepest point of A in B to within the precision: `f_B(A1)` is no more than about
/// one final cell's change of `f_B` above the reference minimum of `f_B` over A. That minimum
/// lies on A's boundary, or is B's centre (-1) when A holds it: `f_B` has no other critical point.
fn check_deepest(a: &Shape, sa: &[[f64; 2]], b: &Shape, deepest: [f64; 2], cell: f64, what: &str) {
    let (mut best, mut at) = (f64::INFINITY, b.c);
    for &p in sa {
        let v = b.f(p);
        if v < best {
            (best, at) = (v, p);
        }
    }
    if a.f(b.c) < 0.0 {
        (best, at) = (-1.0, b.c);
    }
    // The largest gradient within a cell of the minimum: how much f may change over a cell there.
    let h = 1e-6 * b.min_axis();
    let grad_at = |p: [f64; 2]| {
        ((b.f([p[0] + h, p[1]]) - b.f([p[0] - h, p[1]])) / (2.0 * h))
            .hypot((b.f([p[0], p[1] + h]) - b.f([p[0], p[1] - h])) / (2.0 * h))
    };
    let grad = (0..16)
        .map(|k| {
            let t = f64::from(k) * TAU / 16.0;
            grad_at([at[0] + cell * t.cos(), at[1] + cell * t.sin()])
        })
        .fold(grad_at(at), f64::max);
    let got = b.f(deepest);
    assert!(
        got <= best + 2.0 * grad * cell + 1e-9,
        "{what}: deepest point has f = {got}, the reference minimum is {best} at {at:?} (gradient {grad})"
    );
}

/// The point is within 1e-7 of a sign change of `f`, looking along the axes and along the ray
/// it was found on (robust where the gradient is huge, as for exponents below 1 near the axes,
/// and at the tip of a star's spike, where the inside is a sliver along the ray).
fn on_boundary(s: &Shape, p: [f64; 2], ray: [f64; 2], what: &str) {
    let h = 1e-7 * s.max_axis();
    let n = ray[0].hypot(ray[1]);
    let r = if n > 0.0 {
        [ray[0] / n * h, ray[1] / n * h]
    } else {
        [0.0, 0.0]
    };
    let vals: Vec<f64> = [
        [-h, 0.0],
        [h, 0.0],
        [0.0, -h],
        [0.0, h],
        [0.0, 0.0],
        [-r[0], -r[1]],
        r,
    ]
    .iter()
    .map(|d| s.f([p[0] + d[0], p[1] + d[1]]))
    .collect();
    let has_in = vals.iter().any(|&v| v <= 1e-12);
    let has_out = vals.iter().any(|&v| v >= -1e-12);
    assert!(
        has_in && has_out,
        "{what}: {p:?} is not on the boundary: f nearby {vals:?}"
    );
}

#[test]
fn ellipses_agree_with_perram_wertheim() {
    let mut rng = Rng::new(7);
    let (mut checked_sep, mut checked_ov) = (0, 0);
    for i in 0..2000 {
        // Semi-axes up to an axis ratio of 20 and a size ratio of 20.
        let shape = |rng: &mut Rng| {
            let big = rng.range(0.1, 2.0);
            let ratio = if rng.unit() < 0.2 {
                20.0
            } else {
                rng.range(1.0, 5.0)
            };
            Shape {
                c: [0.0, 0.0],
                angle: rng.range(0.0, TAU),
                s: if rng.unit() < 0.5 {
                    [big, big / ratio]
                } else {
                    [big / ratio, big]
                },
                e: [2.0, 2.0],
            }
        };
        let mut a = shape(&mut rng);
        let mut b = shape(&mut rng);
        a.c = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)];
        let dir = rng.range(0.0, TAU);
        // F scales with the square of the centre distance: find the touching distance exactly.
        b.c = [a.c[0] + dir.cos(), a.c[1] + dir.sin()];
        let touching = 1.0 / perram_wertheim(&a, &b).sqrt();
        let t = touching * (1.0 + rng.range(-0.15, 0.15));
        b.c = [a.c[0] + t * dir.cos(), a.c[1] + t * dir.sin()];
        let mu = perram_wertheim(&a, &b).sqrt();
        let cell = cell_diagonal_bound(&a, &b, DEPTH);
        let (sa, sb) = (a.samples(0.25 * cell), b.samples(0.25 * cell));
        for (method, c) in run_all(&a, &b) {
            let what = format!("{method}, pair {i}: {a:?} {b:?} mu {mu}");
            // Scaling by mu makes them touch; a convex shape holding a disk of radius r about its
            // centre grows by at least (mu - 1) r when scaled by mu.
            if (mu - 1.0) * (a.min_axis() + b.min_axis()) > cell {
                assert!(
                    !c.overlap(),
                    "{what}: apart by more than a cell, reported overlapping"
                );
                checked_sep += 1;
            }
            if (1.0 - mu) * a.min_axis().min(b.min_axis()) > cell {
                assert!(
                    c.overlap(),
                    "{what}: overlapping by more than a cell, reported apart"
                );
                checked_ov += 1;
            }
            check_points(&a, &b, &c, &what);
            if let Some(p) = c.penetration {
                check_deepest(&a, &sa, &b, p.a_deepest.to_array(), cell, &what);
                check_deepest(&b, &sb, &a, p.b_deepest.to_array(), cell, &what);
            }
        }
    }
    assert!(
        checked_sep > 300 && checked_ov > 300,
        "too few decided pairs: {checked_sep} {checked_ov}"
    );
}

fn random_shape(rng: &mut Rng, kind: usize) -> Shape {
    let angle = rng.range(0.0, TAU);
    let (s, e) = match kind {
        0 => {
            let r = rng.range(0.3, 0.7);
            ([r, r], [2.0, 2.0])
        }
        1 => ([rng.range(0.1, 0.8), rng.range(0.1, 0.9)], [2.0, 2.0]),
        2 => ([rng.range(0.3, 0.4), rng.range(0.3, 0.7)], [4.0, 4.0]),
        3 => (
            [rng.range(0.3, 0.4), rng.range(0.3, 0.7)],
            [rng.range(0.5, 4.0), rng.range(0.5, 4.0)],
        ),
        // Non-convex stars.
        4 => (
            [rng.range(0.3, 0.7), rng.range(0.3, 0.7)],
            [rng.range(0.5, 1.0), rng.range(0.5, 1.0)],
        ),
        // Very thin.
        5 => {
            let l = rng.range(0.3, 1.0);
            ([l, l / 20.0], [rng.range(1.0, 4.0), rng.range(1.0, 4.0)])
        }
        // Very blocky.
        _ => (
            [rng.range(0.2, 0.6), rng.range(0.2, 0.6)],
            [rng.range(4.0, 12.0), rng.range(4.0, 12.0)],
        ),
    };
    Shape {
        c: [0.0, 0.0],
        angle,
        s,
        e,
    }
}

#[test]
fn every_exponent_agrees_with_dense_sampling() {
    let mut rng = Rng::new(11);
    let (mut checked_sep, mut checked_ov) = (0, 0);
    for i in 0..1000 {
        let mut a = random_shape(&mut rng, i % 7);
        let mut b = random_shape(&mut rng, (i / 7) % 7);
        if i % 10 == 0 {
            // Sizes in a ratio of 20.
            b.s = [b.s[0] / 20.0 * 2.0, b.s[1] / 20.0 * 2.0];
        }
        a.c = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)];
        let cell = cell_diagonal_bound(&a, &b, DEPTH);
        let h = 0.25 * cell;
        let sa = a.samples(h);
        let dir = rng.range(0.0, TAU);
        // Touching distance along `dir` by bisection on the sampled overlap.
        let place = |b: &mut Shape, t: f64| b.c = [a.c[0] + t * dir.cos(), a.c[1] + t * dir.sin()];
        let (mut lo, mut hi) = (0.0, a.s[0].hypot(a.s[1]) + b.s[0].hypot(b.s[1]));
        let coarse = a.samples(4.0 * h);
        for _ in 0..24 {
            let mid = 0.5 * (lo + hi);
            place(&mut b, mid);
            if sampled_overlap(&a, &coarse, &b, &b.samples(4.0 * h)) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let t = lo * (1.0 + rng.range(-0.1, 0.1));
        place(&mut b, t);
        let sb = b.samples(h);
        for (method, c) in run_all(&a, &b) {
            let what = format!("{method}, pair {i}: {a:?} {b:?}");
            if !sampled_overlap(&a, &sa, &b, &sb) {
                let gap = sampled_gap(&sa, &b, &sb, &a);
                if gap > cell + 2.0 * h {
                    assert!(
                        !c.overlap(),
                        "{what}: apart by {gap}, more than a cell, reported overlapping"
                    );
                    checked_sep += 1;
                }
            } else if !c.overlap() {
                // Reported apart: then no point may be a cell deep inside both. Look for one on a
                // grid over the common part of the boxes, deepest candidates first.
                let deep = deepest_sampled_point(&a, &sa, &b, &sb, cell);
                assert!(
                    deep < cell + h,
                    "{what}: a point {deep} deep in both, reported apart"
                );
            } else {
                checked_ov += 1;
            }
            check_points(&a, &b, &c, &what);
            // Where the exponents are at least 1 the gradient is bounded and the depth comparable.
            if let Some(p) = c
                .penetration
                .filter(|_| a.e.iter().chain(&b.e).all(|&e| e >= 1.0))
            {
                check_deepest(&a, &sa, &b, p.a_deepest.to_array(), cell, &what);
                check_deepest(&b, &sb, &a, p.b_deepest.to_array(), cell, &what);
            }
        }
    }
    eprintln!("decided: {checked_sep} apart, {checked_ov} overlapping");
    assert!(
        checked_sep > 200 && checked_ov > 200,
        "too few decided pairs: {checked_sep} {checked_ov}"
    );
}

/// The largest distance from a grid point inside both shapes to either boundary (sampled).
fn deepest_sampled_point(a: &Shape, sa: &[[f64; 2]], b: &Shape, sb: &[[f64; 2]], cell: f64) -> f64 {
    let lo = [
        sa.iter()
            .map(|p| p[0])
            .fold(f64::INFINITY, f64::min)
            .max(sb.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min)),
        sa.iter()
            .map(|p| p[1])
            .fold(f64::INFINITY, f64::min)
            .max(sb.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min)),
    ];
    let hi = [
        sa.iter()
            .map(|p| p[0])
            .fold(f64::NEG_INFINITY, f64::max)
            .min(sb.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max)),
        sa.iter()
            .map(|p| p[1])
            .fold(f64::NEG_INFINITY, f64::max)
            .min(sb.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max)),
    ];
    let step = 0.5 * cell;
    let mut inside = Vec::new();
    let mut x = lo[0];
    while x <= hi[0] {
        let mut y = lo[1];
        while y <= hi[1] {
            let p = [x, y];
            let (fa, fb) = (a.f(p), b.f(p));
            if fa < 0.0 && fb < 0.0 {
                inside.push((fa.max(fb), p));
            }
            y += step;
        }
        x += step;
    }
    inside.sort_by(|u, v| u.0.total_cmp(&v.0));
    inside
        .iter()
        .take(50)
        .map(|&(_, p)| {
            sa.iter()
                .chain(sb)
                .map(|&q| dist(p, q))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

use std::f64::consts::TAU;

/// The soft model's closed form for two disks (`disk_disk_certified`) against the certified
/// Newton path of the general narrow phase, which shares no code with it: over random pairs from
/// deep overlap to clear gaps, and pairs within 1e-12 of touching, the same decision wherever
/// the general path is certain (a depth beyond its tolerance of half a final cell), and the same
/// deepest points and pushes while neither disk holds the other's centre. A closed form with the reach or the normal wrong, or one that
/// decided the sign of a depth of 1e-13 wrongly, fails here.
#[test]
fn disk_closed_form_agrees_with_the_certified_path() {
    use supergrain::contact::disk_disk_certified;
    use supergrain::shape::Superellipse;
    let mut rng = Rng::new(18);
    let precision = Precision::new(DEPTH, 0.0).unwrap();
    let (mut overlaps, mut touching) = (0, 0);
    for k in 0..4000 {
        let (ra, rb) = (rng.range(0.1, 1.0), rng.range(0.1, 1.0));
        let angle = rng.range(0.0, std::f64::consts::TAU);
        let dir = Vec2::new(angle.cos(), angle.sin());
        let reach = ra + rb;
        let dist = if k % 4 == 0 {
            reach * (1.0 + rng.range(-1e-12, 1e-12))
        } else {
            rng.range(0.05, 1.2) * reach
        };
        let ca = Vec2::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0));
        let cb = ca + dir * dist;
        let (sa, sb) = (
            Superellipse::circle(ra).unwrap(),
            Superellipse::circle(rb).unwrap(),
        );
        let (pa, pb) = (Pose::new(ca, 0.3).unwrap(), Pose::new(cb, -1.1).unwrap());
        let general = contact(&sa, &pa, &sb, &pb, &precision);
        let closed = disk_disk_certified(ca, ra, cb, rb);
        let depth = reach - dist;
        let cell = cell_diagonal_bound(
            &Shape {
                c: [ca.x, ca.y],
                angle: 0.3,
                s: [ra, ra],
                e: [2.0, 2.0],
            },
            &Shape {
                c: [cb.x, cb.y],
                angle: -1.1,
                s: [rb, rb],
                e: [2.0, 2.0],
            },
            DEPTH,
        );
        if depth.abs() > cell {
            assert_eq!(
                general.overlap(),
                closed.overlap(),
                "pair {k}: radii {ra}, {rb}, distance {dist}"
            );
        }
        if depth.abs() < 1e-9 {
            touching += 1;
            // Beyond the rounding of the pair's own numbers (a few 1e-16), the decision is the
            // sign of the depth.
            if depth.abs() > 1e-13 {
                assert_eq!(closed.overlap(), depth > 0.0, "pair {k}: depth {depth:e}");
            }
        }
        // The points and pushes where neither disk holds the other's centre (deeper, either
        // push that separates is an answer, and the general path's is another one).
        if let (Some(g), Some(c), true) =
            (general.penetration, closed.penetration, dist > ra.max(rb))
        {
            overlaps += 1;
            let tol = 1e-6 * reach;
            for (what, x, y) in [
                ("A1", g.a_deepest, c.a_deepest),
                ("A2", g.b_deepest, c.b_deepest),
                ("A's push", g.a_push, c.a_push),
                ("B's push", g.b_push, c.b_push),
            ] {
                assert!(
                    (x - y).norm() < tol.max(cell),
                    "pair {k}: {what} {x:?} against {y:?} (radii {ra}, {rb}, distance {dist})"
                );
            }
        }
    }
    assert!(
        overlaps > 500 && touching > 500,
        "{overlaps} overlaps, {touching} touching"
    );
}

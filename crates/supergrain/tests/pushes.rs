//! The penetration vectors separate (issue 17, "pushes that do not separate"): moving A by
//! `a_push` and B by `b_push` never deepens the overlap, measured on densely sampled
//! boundaries that share no code with the narrow phase; nested shapes are pushed out the
//! short way, and a symmetric pair of stars along its line of symmetry.

mod common;

use std::f64::consts::TAU;

use common::*;
use supergrain::contact::{Contact, contact, contact_quadtree};
use supergrain::subdivision::Precision;

fn both(a: &Shape, b: &Shape) -> [(&'static str, Contact); 2] {
    let (sa, pa) = to_lib(a);
    let (sb, pb) = to_lib(b);
    let precision = Precision::default();
    [
        ("certified", contact(&sa, &pa, &sb, &pb, &precision)),
        ("quadtree", contact_quadtree(&sa, &pa, &sb, &pb, &precision)),
    ]
}

/// How deep one shape reaches into the other (the larger way), from boundary samples `h`
/// apart and the centres: the largest distance from a point of one inside the other to the
/// other's nearest boundary sample.
fn depth(a: &Shape, b: &Shape, h: f64) -> f64 {
    let (sa, sb) = (a.dense_boundary(h), b.dense_boundary(h));
    let reach = |own: &Shape, so: &[[f64; 2]], other: &Shape, sother: &[[f64; 2]]| {
        so.iter()
            .chain(std::iter::once(&own.c))
            .filter(|&&p| other.f(p) < 0.0)
            .map(|&p| {
                sother
                    .iter()
                    .map(|&q| dist(p, q))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    reach(a, &sa, b, &sb).max(reach(b, &sb, a, &sa))
}

fn moved(s: &Shape, d: supergrain::geometry::Vec2) -> Shape {
    Shape {
        c: [s.c[0] + d.x, s.c[1] + d.y],
        ..*s
    }
}

#[test]
fn a_shape_inside_another_is_pushed_out_the_short_way() {
    let big = Shape {
        c: [0.0, 0.0],
        angle: 0.0,
        s: [1.0, 1.0],
        e: [2.0, 2.0],
    };
    let small = Shape {
        s: [0.1, 0.1],
        ..big
    };
    for (what, c) in both(&big, &small) {
        let p = c.penetration.expect("nested shapes overlap");
        // Opposite ways, and between them out: B's centre moves 1.1 from A's, beyond A's
        // radius plus its own.
        let rel = p.b_push - p.a_push;
        assert!(
            p.a_push.dot(rel) < 0.0 && p.b_push.dot(rel) > 0.0,
            "{what}: {p:?} push the same way"
        );
        assert!(
            (rel.norm() - 1.1).abs() < 1e-6,
            "{what}: moved apart by {}, not out the short way (1.1)",
            rel.norm()
        );
    }
    // A block holding a small disk off its centre: out through the nearer face.
    let block = Shape {
        c: [0.0, 0.0],
        angle: 0.0,
        s: [1.0, 0.5],
        e: [8.0, 8.0],
    };
    let disk = Shape {
        c: [0.0, 0.2],
        angle: 0.0,
        s: [0.1, 0.1],
        e: [2.0, 2.0],
    };
    for (what, c) in both(&block, &disk) {
        let p = c.penetration.expect("overlap");
        let rel = p.b_push - p.a_push;
        assert!(rel.y > 0.0 && rel.x.abs() < 0.1 * rel.y, "{what}: {p:?}");
        assert!(
            depth(&moved(&block, p.a_push), &moved(&disk, p.b_push), 0.002) < 0.01,
            "{what}: not out: {p:?}"
        );
    }
}

#[test]
fn two_identical_stars_side_by_side_are_pushed_along_their_line() {
    let a = Shape {
        c: [0.0, 0.0],
        angle: 0.0,
        s: [1.0, 1.0],
        e: [0.5, 0.5],
    };
    let b = Shape { c: [1.0, 0.0], ..a };
    for (what, c) in both(&a, &b) {
        let p = c.penetration.expect("the spikes overlap");
        for push in [p.a_push, p.b_push] {
            assert!(
                push.y.abs() <= 1e-6 * push.x.abs(),
                "{what}: {push:?} is not along x ({p:?})"
            );
        }
        assert!(p.a_push.x < 0.0 && p.b_push.x > 0.0, "{what}: {p:?}");
    }
}

#[test]
fn moving_by_the_pushes_never_deepens_the_overlap() {
    let mut rng = Rng::new(5);
    let mut checked = 0;
    // `PUSH_PAIRS=4000` runs more (about a minute).
    let pairs: u64 = std::env::var("PUSH_PAIRS").map_or(800, |v| v.parse().expect("PUSH_PAIRS"));
    for i in 0..pairs {
        let shape = |rng: &mut Rng, k: u64| {
            let e = match k {
                0 => [2.0, 2.0],
                1 => [rng.range(2.0, 20.0), rng.range(2.0, 20.0)],
                2 => [rng.range(1.0, 2.0), rng.range(1.0, 2.0)],
                _ => {
                    let e = rng.range(0.3, 0.95);
                    [e, e]
                }
            };
            Shape {
                c: [0.0, 0.0],
                angle: rng.range(0.0, TAU),
                s: [rng.range(0.2, 0.5), rng.range(0.2, 0.5)],
                e,
            }
        };
        // Disks, blocks, near-ellipses and stars, every class against every class. Before the
        // stars' pushes kept to the line of the centres, 3 of the first 400 pairs deepened.
        let a = shape(&mut rng, i % 4);
        let mut b = shape(&mut rng, (i / 4) % 4);
        let dir = rng.range(0.0, TAU);
        // Overlaps up to a fraction of the grains' size, as in a heap (the deep and nested cases
        // are the test above: there the deepest reach is not what the pushes reduce first).
        let t = rng.range(0.6, 1.0) * (a.s[0].min(a.s[1]) + b.s[0].min(b.s[1]));
        b.c = [t * dir.cos(), t * dir.sin()];
        let h = 0.004;
        let before = depth(&a, &b, h);
        for (what, c) in both(&a, &b) {
            let Some(p) = c.penetration else { continue };
            let after = depth(&moved(&a, p.a_push), &moved(&b, p.b_push), h);
            assert!(
                after <= before + 2.0 * h,
                "pair {i} ({what}): the pushes deepen the overlap from {before} to {after}: \
                 {a:?} {b:?} {p:?}"
            );
            checked += 1;
        }
    }
    assert!(checked > pairs, "{checked} overlaps checked");
}

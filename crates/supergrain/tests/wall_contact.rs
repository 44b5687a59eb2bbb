//! Shape-wall contact (SPEC §4, paper III-B) against a densely sampled boundary.
//!
//! References, all written here:
//! - the boundary, sampled so that consecutive samples are at most `h` apart; within a quadrant
//!   the boundary is monotone in both local coordinates, so every boundary point lies within `h`
//!   of a sample and the true extreme towards the wall is within `h` of the sampled one;
//! - a disk certificate for "the quadtree must see this": a point `q` whose disk of radius
//!   `rho` (the half-diagonal of a final cell) lies inside both the shape and the wall. The
//!   final cell holding `q` then has its midpoint in that disk, inside both, so the quadtree
//!   (which returns the deepest such midpoint) must report an overlap at least as deep as
//!   `q` less `rho`. A bare "goes in by more than a cell" is not enough of a reference: a cusp
//!   (exponent < 1) or a thin tip can go into the wall by many cells with no final midpoint
//!   inside it.

mod common;

use common::{Rng, Shape, to_lib};
use std::f64::consts::{FRAC_PI_2, SQRT_2, TAU};

use supergrain::contact::{contact_wall, contact_wall_quadtree};
use supergrain::shape::HalfPlane;
use supergrain::subdivision::Precision;

/// What the wall tests need beyond the shared reference shape.
impl Shape {
    fn size(&self) -> f64 {
        self.s[0].max(self.s[1])
    }

    /// The longest side of the box of the rotated `[-sx, sx] x [-sy, sy]` rectangle, which holds
    /// the shape and every bounding box the library may compute for it.
    fn rect_box_longest(&self) -> f64 {
        let (sn, cs) = self.angle.sin_cos();
        let (sn, cs) = (sn.abs(), cs.abs());
        2.0 * (cs * self.s[0] + sn * self.s[1]).max(sn * self.s[0] + cs * self.s[1])
    }
}

#[derive(Clone, Copy, Debug)]
enum Side {
    Floor,
    Left,
    Right,
}

/// A wall as plain numbers: `g(p) = n . p - d`, solid where `g < 0`; `n` points out of it.
#[derive(Clone, Copy, Debug)]
struct Wall {
    n: [f64; 2],
    d: f64,
}

impl Wall {
    /// The wall of `side` whose surface is at `n . p = d`, and the library's.
    fn new(side: Side, d: f64) -> (Wall, HalfPlane) {
        match side {
            Side::Floor => (Wall { n: [0.0, 1.0], d }, HalfPlane::floor(d).unwrap()),
            Side::Left => (Wall { n: [1.0, 0.0], d }, HalfPlane::left(d).unwrap()),
            // x_R - x = (-1, 0) . p - (-x_R): x_R = -d, exact.
            Side::Right => (Wall { n: [-1.0, 0.0], d }, HalfPlane::right(-d).unwrap()),
        }
    }

    fn along(&self, p: [f64; 2]) -> f64 {
        self.n[0] * p[0] + self.n[1] * p[1]
    }

    fn g(&self, p: [f64; 2]) -> f64 {
        self.along(p) - self.d
    }

    /// The unit tangent `(n_y, -n_x)`.
    fn tangent(&self, p: [f64; 2]) -> f64 {
        self.n[1] * p[0] - self.n[0] * p[1]
    }

    /// The point at tangent coordinate `a` and depth `z` into the wall.
    fn point(&self, a: f64, z: f64) -> [f64; 2] {
        let w = self.d - z;
        [
            self.n[1] * a + self.n[0] * w,
            -self.n[0] * a + self.n[1] * w,
        ]
    }
}

/// The depth into the wall of the deepest grid point `q` whose disk of radius `r` lies inside
/// the shape and the wall, as far as the samples (spacing `h`) prove it. `step` is the grid's
/// spacing; `depth_max` is the sampled extreme's depth.
fn deepest_disk(
    sh: &Shape,
    wall: &Wall,
    samples: &[[f64; 2]],
    h: f64,
    r: f64,
    step: f64,
    depth_max: f64,
) -> Option<f64> {
    // Only samples in or near the wall can come within r + h of a point deeper than r.
    let mut near: Vec<(f64, [f64; 2])> = samples
        .iter()
        .filter(|&&p| wall.g(p) < h)
        .map(|&p| (wall.tangent(p), p))
        .collect();
    if near.is_empty() {
        return None;
    }
    near.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (a_lo, a_hi) = (near[0].0, near[near.len() - 1].0);
    let clear = r + h;
    let mut z = depth_max;
    while z > r {
        let mut a = a_lo;
        while a <= a_hi {
            let q = wall.point(a, z);
            if sh.f(q) < 0.0 {
                // The samples with tangent coordinate within `clear` of q's.
                let start = near.partition_point(|s| s.0 < a - clear);
                let free = near[start..]
                    .iter()
                    .take_while(|s| s.0 <= a + clear)
                    .all(|s| (s.1[0] - q[0]).hypot(s.1[1] - q[1]) > clear);
                if free {
                    return Some(z);
                }
            }
            a += step;
        }
        z -= step;
    }
    None
}

fn random_exponent(rng: &mut Rng) -> f64 {
    match rng.below(8) {
        0 => 0.5,
        1 => 1.0,
        2 => 2.0,
        3 => 4.0,
        4 => 8.0,
        _ => rng.range(0.5, 8.0),
    }
}

fn random_shape(rng: &mut Rng) -> Shape {
    let big = rng.range(0.05, 3.0);
    // Axis ratios up to 20: thin needles and slabs too.
    let ratio = match rng.below(4) {
        0 => 1.0,
        1 => rng.range(10.0, 20.0),
        _ => rng.range(1.0, 10.0),
    };
    let s = if rng.below(2) == 0 {
        [big, big / ratio]
    } else {
        [big / ratio, big]
    };
    let angle = match rng.below(6) {
        0 => 0.0,
        1 => FRAC_PI_2 * rng.below(4) as f64,
        _ => rng.range(-TAU, TAU),
    };
    Shape {
        s,
        e: if rng.below(3) == 0 {
            let e = random_exponent(rng);
            [e, e]
        } else {
            [random_exponent(rng), random_exponent(rng)]
        },
        c: [rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)],
        angle,
    }
}

/// How the cases came out, to check that each kind of assertion was exercised.
#[derive(Default, Debug)]
struct Tally {
    apart: u32,
    certified: u32,
    overlaps: u32,
    /// Overlaps answered by the certified path (no quadtree cell).
    newton: u32,
    /// Of those, shapes with an exponent up to 1 (stars, diamonds, and shapes convex along one
    /// axis only).
    not_convex: u32,
}

/// Shapes with an exponent up to 1: stars and diamonds (both exponents in [0.25, 1]), and shapes
/// with one exponent up to 1 and the other above (convex along one axis only).
fn not_convex_shape(rng: &mut Rng) -> Shape {
    let mut sh = random_shape(rng);
    // Exactly 1 now and then: a diamond, or a shape with a flat side.
    let low = if rng.below(6) == 0 {
        1.0
    } else {
        rng.range(0.25, 1.0)
    };
    sh.e = match rng.below(3) {
        0 => [low, rng.range(0.25, 1.0)],
        1 => [low, rng.range(1.0, 8.0)],
        _ => [rng.range(1.0, 8.0), low],
    };
    sh
}

fn run_side(side: Side, seed: u64, cases: u32) -> Tally {
    run_cases(side, seed, cases, random_shape, false)
}

/// `cases` shapes from `shapes` against the wall on `side`: the wall within two final cells of
/// touching the shape (`near`), or anywhere from clear to a third of its size in.
fn run_cases(
    side: Side,
    seed: u64,
    cases: u32,
    shapes: fn(&mut Rng) -> Shape,
    near: bool,
) -> Tally {
    let mut rng = Rng::new(seed);
    let precision = Precision::default();
    let mut tally = Tally::default();
    for case in 0..cases {
        let sh = shapes(&mut rng);
        let size = sh.size();
        let h = size / 3000.0;
        let samples = sh.samples(h);

        // Where the wall is: the sampled extreme into it plus a chosen penetration.
        let n = Wall::new(side, 0.0).0.n;
        let extreme = samples
            .iter()
            .map(|p| n[0] * p[0] + n[1] * p[1])
            .fold(f64::INFINITY, f64::min);
        let target = if near {
            rng.range(-2.0, 2.0) * sh.rect_box_longest() / f64::from(1u32 << precision.depth())
        } else if rng.below(5) == 0 {
            rng.range(-0.02, 0.02) * size
        } else {
            rng.range(-0.1, 0.35) * size
        };
        let (wall, lib_wall) = Wall::new(side, extreme + target);
        let depth_ref = wall.d - extreme;

        let (shape, pose) = to_lib(&sh);
        // Both ways: the certified path (with its quadtree fallback) and the quadtree alone.
        for (method, got) in [
            (
                "certified",
                contact_wall(&shape, &pose, &lib_wall, &precision),
            ),
            (
                "quadtree",
                contact_wall_quadtree(&shape, &pose, &lib_wall, &precision),
            ),
        ] {
            if method == "certified" && got.overlap() && got.cells == 0 {
                tally.newton += 1;
                if sh.e.iter().any(|&e| e <= 1.0) {
                    tally.not_convex += 1;
                }
            }

            // The final cells' half-diagonal: the region is inside the shape's box, whose longest
            // side is at most the rotated rectangle's.
            let cell = sh.rect_box_longest() / f64::from(1u32 << precision.depth()) * (1.0 + 1e-6);
            let rho = cell * SQRT_2 / 2.0;
            let what = format!("{method}, case {case}, {side:?} at {}: {sh:?}", wall.d);

            // Clear of the wall by more than the sampling error: no point of the shape is in the
            // wall, and the overlap the library reports is a proof, so there must be none.
            let tiny = 1e-12 * (1.0 + wall.d.abs() + size);
            if depth_ref < -(h + tiny) {
                tally.apart += 1;
                assert!(
                    !got.overlap(),
                    "{what}: clear by {} yet overlap {got:?}",
                    -depth_ref
                );
            }

            // A disk of radius rho (with a margin) inside both: the quadtree must see it.
            let certified = deepest_disk(&sh, &wall, &samples, h, 1.05 * rho, 0.5 * rho, depth_ref);
            if let Some(z) = certified {
                tally.certified += 1;
                assert!(
                    got.overlap(),
                    "{what}: a disk of radius {rho} at depth {z} is inside both, yet no overlap"
                );
            }

            // An answer of the certified path (no cell) is deepest up to half a final cell, and
            // its "apart" leaves no point more than half a cell into the wall.
            if method == "certified" && got.cells == 0 {
                let z = got
                    .penetration
                    .map_or(0.0, |pen| -wall.g(pen.deepest.to_array()));
                assert!(
                    z >= depth_ref - h - 0.5 * cell - tiny,
                    "{what}: certified depth {z}, the shape reaches {depth_ref}"
                );
            }

            let Some(pen) = got.penetration else {
                continue;
            };
            tally.overlaps += 1;
            let p = pen.deepest.to_array();
            let z = -wall.g(p);
            assert!(sh.f(p) <= 1e-12, "{what}: deepest {p:?} outside the shape");
            assert!(z > 0.0, "{what}: deepest {p:?} not in the wall");
            // No deeper than the shape goes, and as deep as any certified point less a cell.
            assert!(
                z <= depth_ref + h + tiny,
                "{what}: deepest at depth {z}, the shape only reaches {depth_ref}"
            );
            if let Some(zq) = certified {
                assert!(
                    z >= zq - rho,
                    "{what}: deepest at depth {z}, but a final midpoint at depth >= {} is inside both",
                    zq - rho
                );
            }

            // The push takes the deepest point exactly onto the wall's surface, along its normal.
            let push = pen.push.to_array();
            let landed = [p[0] + push[0], p[1] + push[1]];
            let ulp = 4.0 * f64::EPSILON * (wall.d.abs() + z + p[0].abs().max(p[1].abs()));
            assert!(
                wall.g(landed).abs() <= ulp,
                "{what}: deepest {p:?} + push {push:?} = {landed:?}, off the wall by {}",
                wall.g(landed)
            );
            assert_eq!(
                wall.tangent(push),
                0.0,
                "{what}: push {push:?} not perpendicular"
            );
            assert!(
                wall.along(push) > 0.0,
                "{what}: push {push:?} points into the wall"
            );
            assert!(
                (wall.along(push) - z).abs() <= ulp,
                "{what}: push {push:?} is not the depth {z}"
            );
        }
    }
    tally
}

fn check_tally(t: &Tally, cases: u32) {
    // Each kind of assertion ran on a fair share of the cases.
    assert!(
        t.apart >= cases / 10
            && t.certified >= cases / 3
            && t.overlaps >= cases / 3
            && t.newton >= cases / 10
            && t.not_convex >= cases / 20,
        "{t:?}"
    );
}

#[test]
fn floor_contact_matches_sampled_boundary() {
    let t = run_side(Side::Floor, 41, 200);
    check_tally(&t, 200);
}

#[test]
fn left_wall_contact_matches_sampled_boundary() {
    let t = run_side(Side::Left, 42, 200);
    check_tally(&t, 200);
}

#[test]
fn right_wall_contact_matches_sampled_boundary() {
    let t = run_side(Side::Right, 43, 200);
    check_tally(&t, 200);
}

/// Stars and shapes convex along one axis only, within two final cells of touching the wall:
/// where an error of the support's bound decides between "apart" and "in".
#[test]
fn not_convex_shapes_near_touching_match_sampled_boundary() {
    for (k, side) in [Side::Floor, Side::Left, Side::Right]
        .into_iter()
        .enumerate()
    {
        let t = run_cases(side, 50 + k as u64, 150, not_convex_shape, true);
        assert!(t.not_convex >= 30, "{t:?}");
    }
}

//! The narrow phase against the two references of the established codes, side by side, on the
//! same near-touching pairs of convex shapes (centres at the touching distance x (1 +- 2%)):
//!
//! - **Newton, midway point** (Podlozhnyuk, Pirker and Kloss 2017, as in LIGGGHTS/LAMMPS): solve
//!   `grad F_A(X) + mu^2 grad F_B(X) = 0`, `F_A(X) = F_B(X)` for the midway point `X`, then the
//!   overlap along the normal through it. Cold: started between the centres. Warm (a persisting
//!   contact): started from its answer for the pair one small move earlier.
//! - **parry2d** (f64): contact between 64-gon convex polygons on the same boundaries.
//!
//! Classes: circles, ellipses, squircles, and the convex pairs of `bench contact`'s mixed class
//! (every exponent in [1, 4], each axis its own), where every power is a `pow`. The Newton
//! reference takes one `pow` an axis for `F`, its gradient and Hessian (`t^(e-2)`, the others
//! by multiplying), as a careful implementation would; until 2026-12-05 it took three, which
//! made it about twice as slow and our certified path look faster than it is against the
//! method (docs/performance.md).
//!
//! Both references exist in this benchmark only. Neither handles exponents below 1 (a
//! superellipse is then not convex: Newton's Hessian is singular on the axes and a polygon would
//! need decomposing); the quadtree does, at the cost shown by `contact` in `benches/contact.rs`.
//! Before timing, the depths of the three are compared on the overlapping pairs and printed.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use parry2d_f64::math::{Pose as PPose, Vector};
use parry2d_f64::shape::ConvexPolygon;
use supergrain::bench::{Pair, ShapeClass, near_touching_pairs};
use supergrain::contact::{WarmStart, contact, contact_quadtree, contact_warm};
use supergrain::geometry::Vec2;
use supergrain::shape::{Pose, Superellipse};
use supergrain::subdivision::Precision;

const PAIRS: usize = 200;

/// `F = |u/a|^p + |v/b|^q - 1` in the shape's frame, its gradient and Hessian in the plane.
fn f_grad_hess(s: &Superellipse, pose: &Pose, x: Vec2) -> (f64, Vec2, [[f64; 2]; 2]) {
    let [p, q] = s.exponents();
    let ax = s.semi_axes();
    let l = pose.to_local(x);
    let (su, sv) = (l.x / ax.x, l.y / ax.y);
    let (au, av) = (su.abs(), sv.abs());
    // One `pow` an axis, `t^(e-2)`, and the others by multiplying (as a careful Newton code
    // would: `pow` is most of the cost), or the three powers where `t = 0`.
    let powers = |t: f64, e: f64| {
        if t > 0.0 {
            let h = t.powf(e - 2.0);
            (h * t * t, h * t, h)
        } else {
            (t.powf(e), t.powf(e - 1.0), t.powf(e - 2.0))
        }
    };
    let ((fu, gu1, hu2), (fv, gv1, hv2)) = (powers(au, p), powers(av, q));
    let f = fu + fv - 1.0;
    let gu = p / ax.x * gu1 * su.signum();
    let gv = q / ax.y * gv1 * sv.signum();
    let huu = p * (p - 1.0) / (ax.x * ax.x) * hu2;
    let hvv = q * (q - 1.0) / (ax.y * ax.y) * hv2;
    let r = pose.rotation();
    let (c, sn) = (r.cos, r.sin);
    // grad = R (gu, gv); H = R diag(huu, hvv) R^T.
    let g = Vec2::new(c * gu - sn * gv, sn * gu + c * gv);
    let h = [
        [c * c * huu + sn * sn * hvv, c * sn * (huu - hvv)],
        [c * sn * (huu - hvv), sn * sn * huu + c * c * hvv],
    ];
    (f, g, h)
}

/// The midway point `(X, mu)` by Newton from `start`, or `None` if it does not converge in 30
/// iterations.
fn midway(pair: &Pair, start: (Vec2, f64)) -> Option<(Vec2, f64, u32)> {
    let (mut x, mut mu) = start;
    for it in 1..=30 {
        let (fa, ga, ha) = f_grad_hess(&pair.a, &pair.pose_a, x);
        let (fb, gb, hb) = f_grad_hess(&pair.b, &pair.pose_b, x);
        let m2 = mu * mu;
        let r = [ga.x + m2 * gb.x, ga.y + m2 * gb.y, fa - fb];
        let j = [
            [
                ha[0][0] + m2 * hb[0][0],
                ha[0][1] + m2 * hb[0][1],
                2.0 * mu * gb.x,
            ],
            [
                ha[1][0] + m2 * hb[1][0],
                ha[1][1] + m2 * hb[1][1],
                2.0 * mu * gb.y,
            ],
            [ga.x - gb.x, ga.y - gb.y, 0.0],
        ];
        let d = solve3(j, r)?;
        x = Vec2::new(x.x - d[0], x.y - d[1]);
        mu -= d[2];
        if !(x.is_finite() && mu.is_finite()) {
            return None;
        }
        if d[0].abs() + d[1].abs() < 1e-12 && d[2].abs() < 1e-12 {
            return Some((x, mu, it));
        }
    }
    None
}

/// `J d = r` by Cramer's rule.
fn solve3(j: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(j);
    if d.abs() < 1e-300 {
        return None;
    }
    let mut out = [0.0; 3];
    for (k, o) in out.iter_mut().enumerate() {
        let mut m = j;
        for row in 0..3 {
            m[row][k] = r[row];
        }
        *o = det(m) / d;
    }
    Some(out)
}

/// The distance from `x` along `dir` to the shape's boundary (`F = 0`), by Newton in one
/// variable.
fn to_boundary(s: &Superellipse, pose: &Pose, x: Vec2, dir: Vec2) -> f64 {
    let mut t = 0.0;
    for _ in 0..30 {
        let (f, g, _) = f_grad_hess(s, pose, x + dir * t);
        let slope = g.dot(dir);
        if slope.abs() < 1e-300 {
            break;
        }
        let step = f / slope;
        t -= step;
        if step.abs() < 1e-13 {
            break;
        }
    }
    t
}

/// Newton's answer for a pair.
struct Answer {
    /// The midway point and `mu`: where a persisting contact's next search starts.
    midway: (Vec2, f64),
    /// The overlap depth along the normal through the midway point, if it is inside both.
    depth: Option<f64>,
    iterations: u32,
}

fn newton(pair: &Pair, start: (Vec2, f64)) -> Option<Answer> {
    let (x, mu, iterations) = midway(pair, start)?;
    let (fa, ga, _) = f_grad_hess(&pair.a, &pair.pose_a, x);
    let depth = (fa < 0.0).then(|| {
        let n = ga * (1.0 / ga.norm());
        to_boundary(&pair.a, &pair.pose_a, x, n) + to_boundary(&pair.b, &pair.pose_b, x, n * -1.0)
    });
    Some(Answer {
        midway: (x, mu),
        depth,
        iterations,
    })
}

fn cold_start(pair: &Pair) -> (Vec2, f64) {
    let (ca, cb) = (pair.pose_a.center(), pair.pose_b.center());
    let (ra, rb) = (pair.a.bounding_radius(), pair.b.bounding_radius());
    (ca + (cb - ca) * (ra / (ra + rb)), 1.0)
}

/// B moved a little: what a persisting contact sees one step later.
fn nudged(pair: &Pair) -> Pair {
    let c = pair.pose_b.center();
    let size = pair.b.bounding_radius();
    Pair {
        pose_b: Pose::new(
            c + Vec2::new(0.7, -0.7) * (1e-3 * size),
            pair.pose_b.angle() + 1e-3,
        )
        .expect("finite"),
        ..*pair
    }
}

fn polygon(s: &Superellipse) -> ConvexPolygon {
    let local = Pose::new(Vec2::ZERO, 0.0).expect("finite");
    let points = s
        .boundary_polygon(&local, 64)
        .into_iter()
        .map(|p| Vector::new(p.x, p.y))
        .collect();
    ConvexPolygon::from_convex_polyline(points).expect("a 64-gon")
}

fn ppose(p: &Pose) -> PPose {
    PPose::new(Vector::new(p.center().x, p.center().y), p.angle())
}

fn parry_depth(pa: &(PPose, ConvexPolygon), pb: &(PPose, ConvexPolygon)) -> Option<f64> {
    parry2d_f64::query::contact(&pa.0, &pa.1, &pb.0, &pb.1, 0.0)
        .expect("polygons are supported")
        .filter(|c| c.dist < 0.0)
        .map(|c| -c.dist)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

fn references(c: &mut Criterion) {
    let precision = Precision::default();
    // The mixed class's convex pairs (every exponent from 1): `bench contact`'s mixed class
    // without its stars, the general exponents the Newton codes take, with `pow` for every
    // power.
    let convex = |s: &Superellipse| s.exponents().iter().all(|&e| e >= 1.0);
    let mixed_convex: Vec<Pair> = near_touching_pairs(ShapeClass::Mixed, 20 * PAIRS, 0.02, 1)
        .into_iter()
        .filter(|p| convex(&p.a) && convex(&p.b))
        .take(PAIRS)
        .collect();
    for (name, pairs) in [
        ShapeClass::Circles,
        ShapeClass::Ellipses,
        ShapeClass::Squircles,
    ]
    .map(|class| (class.name(), near_touching_pairs(class, PAIRS, 0.02, 1)))
    .into_iter()
    .chain([("mixed convex (exponents in [1, 4])", mixed_convex)])
    {
        let starts: Vec<_> = pairs.iter().map(cold_start).collect();
        // Warm starts: each pair's answer before the nudge.
        let warm: Vec<_> = pairs
            .iter()
            .zip(&starts)
            .map(|(p, s)| newton(p, *s).map_or(*s, |a| a.midway))
            .collect();
        let nudged_pairs: Vec<Pair> = pairs.iter().map(nudged).collect();
        // Ours likewise: where the certified path found each pair's points before the nudge.
        let ours_warm: Vec<Option<WarmStart>> = pairs
            .iter()
            .map(|p| {
                let mut w = None;
                contact_warm(&p.a, &p.pose_a, &p.b, &p.pose_b, &precision, &mut w);
                w
            })
            .collect();
        let polys: Vec<_> = pairs
            .iter()
            .map(|p| {
                (
                    (ppose(&p.pose_a), polygon(&p.a)),
                    (ppose(&p.pose_b), polygon(&p.b)),
                )
            })
            .collect();

        // Accuracy, on the pairs all three call overlapping: each depth against the quadtree's
        // at depth 12 (ours, 32x finer than the timed depth 7).
        let fine = Precision::new(12, 0.0).expect("valid");
        let (mut ours_err, mut newton_err, mut parry_err) = (Vec::new(), Vec::new(), Vec::new());
        let mut tree_err = Vec::new();
        let mut certified = 0;
        let mut newton_failed = 0;
        let mut iterations = (0u32, 0u32);
        for ((p, s), (pa, pb)) in pairs.iter().zip(&starts).zip(&polys) {
            let depth_of = |prec: &Precision| {
                contact(&p.a, &p.pose_a, &p.b, &p.pose_b, prec)
                    .penetration
                    .map(|q| q.depth())
            };
            let tree_depth_of = |prec: &Precision| {
                contact_quadtree(&p.a, &p.pose_a, &p.b, &p.pose_b, prec)
                    .penetration
                    .map(|q| q.depth())
            };
            // No quadtree cell: the certified Newton path answered.
            if contact(&p.a, &p.pose_a, &p.b, &p.pose_b, &precision).cells == 0 {
                certified += 1;
            }
            let n = newton(p, *s);
            match &n {
                Some(a) => iterations.0 += a.iterations,
                None => newton_failed += 1,
            }
            if let Some(a) = &n
                && let Some(warm) = newton(&nudged(p), a.midway)
            {
                iterations.1 += warm.iterations;
            }
            if let (Some(r), Some(o), Some(t), Some(Some(nd)), Some(pd)) = (
                tree_depth_of(&fine),
                depth_of(&precision),
                tree_depth_of(&precision),
                n.map(|a| a.depth),
                parry_depth(pa, pb),
            ) {
                ours_err.push((o - r).abs() / r);
                tree_err.push((t - r).abs() / r);
                newton_err.push((nd - r).abs() / r);
                parry_err.push((pd - r).abs() / r);
            }
        }
        eprintln!(
            "{}: {} pairs overlapping by all three; median relative depth difference from the \
             depth-12 quadtree: ours {:.2e} (certified Newton on {} of {} pairs, else the \
             depth-7 quadtree), the depth-7 quadtree alone {:.2e}, Newton {:.2e}, parry 64-gons \
             {:.2e}; Newton failed on {} of {} pairs, mean iterations cold {:.1}, warm {:.1}",
            name,
            ours_err.len(),
            median(ours_err),
            certified,
            pairs.len(),
            median(tree_err),
            median(newton_err),
            median(parry_err),
            newton_failed,
            pairs.len(),
            f64::from(iterations.0) / pairs.len() as f64,
            f64::from(iterations.1) / pairs.len() as f64,
        );

        let mut group = c.benchmark_group(format!("references, {name}"));
        group.throughput(Throughput::Elements(PAIRS as u64));
        group.bench_function("ours (certified Newton, quadtree fallback; cold)", |b| {
            b.iter(|| {
                for p in &pairs {
                    black_box(contact(
                        black_box(&p.a),
                        &p.pose_a,
                        &p.b,
                        &p.pose_b,
                        &precision,
                    ));
                }
            })
        });
        group.bench_function("ours (certified Newton, warm (persisting))", |b| {
            b.iter(|| {
                for (p, w) in nudged_pairs.iter().zip(&ours_warm) {
                    let mut w = *w;
                    black_box(contact_warm(
                        black_box(&p.a),
                        &p.pose_a,
                        &p.b,
                        &p.pose_b,
                        &precision,
                        &mut w,
                    ));
                }
            })
        });
        group.bench_function("ours, quadtree alone (depth 7)", |b| {
            b.iter(|| {
                for p in &pairs {
                    black_box(contact_quadtree(
                        black_box(&p.a),
                        &p.pose_a,
                        &p.b,
                        &p.pose_b,
                        &precision,
                    ));
                }
            })
        });
        group.bench_function("Newton midway point, cold", |b| {
            b.iter(|| {
                for (p, s) in pairs.iter().zip(&starts) {
                    black_box(newton(black_box(p), *s));
                }
            })
        });
        group.bench_function("Newton midway point, warm (persisting)", |b| {
            b.iter(|| {
                for (p, s) in nudged_pairs.iter().zip(&warm) {
                    black_box(newton(black_box(p), *s));
                }
            })
        });
        group.bench_function("parry2d 64-gons", |b| {
            b.iter(|| {
                for (pa, pb) in &polys {
                    black_box(parry_depth(black_box(pa), pb));
                }
            })
        });
        group.finish();
    }
}

criterion_group!(benches, references);
criterion_main!(benches);

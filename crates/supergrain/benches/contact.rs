//! Criterion benchmark of the narrow phase: near-touching pairs of each shape class (centres at
//! the touching distance x (1 +- 2%)) at the paper's depth 7, and the centre-distance test for
//! circles as the floor. Throughput is per pair. `supergrain bench contact` runs the same cases.
//!
//! And the cost of one power, `f64::powf` and `f32::powf` (the C library's `pow` and `powf`)
//! on the bases and exponents of the mixed class (`[0, 1]`, `[0.5, 4]`), each call independent
//! of the last: a near-touching pair of that class takes about 130 of them (docs/performance.md,
//! "what a pair of the mixed class computes"), whose cost bounds what the class can reach.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use supergrain::bench::{ShapeClass, near_touching_pairs};
use supergrain::contact::contact;
use supergrain::contact::disk_disk;
use supergrain::subdivision::Precision;

const PAIRS: usize = 200;

fn narrow_phase(c: &mut Criterion) {
    let precision = Precision::default();
    let mut group = c.benchmark_group("contact");
    group.throughput(Throughput::Elements(PAIRS as u64));
    for class in ShapeClass::ALL {
        let pairs = near_touching_pairs(class, PAIRS, 0.02, 1);
        group.bench_function(class.name(), |b| {
            b.iter(|| {
                for p in &pairs {
                    black_box(contact(
                        black_box(&p.a),
                        black_box(&p.pose_a),
                        black_box(&p.b),
                        black_box(&p.pose_b),
                        &precision,
                    ));
                }
            })
        });
    }
    let disks: Vec<_> = near_touching_pairs(ShapeClass::Circles, PAIRS, 0.02, 1)
        .iter()
        .map(|p| {
            (
                p.pose_a.center(),
                p.a.semi_axes().x,
                p.pose_b.center(),
                p.b.semi_axes().x,
            )
        })
        .collect();
    group.bench_function("circles centre distance (floor)", |b| {
        b.iter(|| {
            for d in &disks {
                black_box(disk_disk(black_box(d.0), d.1, black_box(d.2), d.3));
            }
        })
    });
    group.finish();
}

/// One power per element, over 1,024 fixed bases in `[0, 1]` and exponents in `[0.5, 4]`.
fn powers(c: &mut Criterion) {
    const N: usize = 1024;
    // A fixed, spread sample (a multiplicative hash), so that no branch predictor learns it.
    let unit = |k: usize, salt: u64| {
        let h = (k as u64 ^ salt).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 11;
        h as f64 / (1u64 << 53) as f64
    };
    let inputs: Vec<(f64, f64)> = (0..N)
        .map(|k| (unit(k, 1), 0.5 + 3.5 * unit(k, 2)))
        .collect();
    let inputs32: Vec<(f32, f32)> = inputs.iter().map(|&(x, e)| (x as f32, e as f32)).collect();
    let mut group = c.benchmark_group("powers");
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("f64 pow", |b| {
        b.iter(|| {
            for &(x, e) in &inputs {
                black_box(black_box(x).powf(e));
            }
        })
    });
    group.bench_function("f32 powf", |b| {
        b.iter(|| {
            for &(x, e) in &inputs32 {
                black_box(black_box(x).powf(e));
            }
        })
    });
    group.bench_function("f64 multiply (floor)", |b| {
        b.iter(|| {
            for &(x, e) in &inputs {
                black_box(black_box(x) * e);
            }
        })
    });
    group.finish();
}

criterion_group!(benches, narrow_phase, powers);
criterion_main!(benches);

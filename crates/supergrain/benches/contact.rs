//! Criterion benchmark of the narrow phase: near-touching pairs of each shape class (centres at
//! the touching distance x (1 +- 2%)) at the paper's depth 7, and the centre-distance test for
//! circles as the floor. Throughput is per pair. `supergrain bench contact` runs the same cases.

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

criterion_group!(benches, narrow_phase);
criterion_main!(benches);

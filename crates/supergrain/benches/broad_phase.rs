//! Criterion benchmark of the broad phase: every grain's candidates in the settled 1,000-grain
//! pour tiled to 4,000 grains, by the grid (rebuilt, then queried) and by all pairs.
//! `supergrain bench scaling` measures whole steps at up to 100,000 grains.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use supergrain::broad_phase::{AllPairs, BroadPhase, Grid, Kind};
use supergrain::geometry::Aabb;
use supergrain::io::Dump;

fn broad_phase(c: &mut Criterion) {
    let dump: Dump =
        serde_json::from_str(include_str!("../../../docs/bench/pour-1000-rest.json")).unwrap();
    let heap = dump.to_world().unwrap();
    let world = supergrain::bench::tiled(&heap, 4, Kind::Grid);
    let boxes: Vec<Aabb> = world.bodies.iter().map(|b| b.bounding_box()).collect();
    let mut group = c.benchmark_group("broad phase, 4,000 grains");
    group.throughput(Throughput::Elements(boxes.len() as u64));
    group.sample_size(10);
    let mut out = Vec::new();
    let all = |broad: &mut dyn BroadPhase, out: &mut Vec<usize>| {
        broad.rebuild(&boxes);
        let mut n = 0;
        for i in 0..boxes.len() {
            out.clear();
            broad.candidates(i, &boxes, out);
            n += out.len();
        }
        black_box(n)
    };
    let mut grid = Grid::new();
    group.bench_function("grid", |b| b.iter(|| all(&mut grid, &mut out)));
    group.bench_function("all pairs", |b| b.iter(|| all(&mut AllPairs, &mut out)));
    group.finish();
}

criterion_group!(benches, broad_phase);
criterion_main!(benches);

//! Criterion benchmark of the certified power `x^e` for a non-integer exponent (the blocks'
//! 3.7): libm's `powf` widened two ulps each way (the old path) against our series with a
//! proven error bound, on the arguments the narrow phase meets (`|u| / s_x` in `[0, 1.5]`).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use supergrain::interval::{Exponent, down, up};

fn pow(c: &mut Criterion) {
    let xs: Vec<f64> = (0..1024).map(|i| 1e-3 + 1.5 * i as f64 / 1024.0).collect();
    let e = 3.7;
    let mut group = c.benchmark_group("certified x^3.7, 1,024 arguments");
    group.throughput(Throughput::Elements(xs.len() as u64));
    group.bench_function("powf, two ulps each way", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for &x in black_box(&xs) {
                // As `abs_pow` does: a lower bound at one end, an upper at the other.
                s += down(down(x.powf(e))) + up(up((x * 1.01).powf(e)));
            }
            s
        })
    });
    let ex = Exponent::new(e);
    group.bench_function("series with a bound (pow_down + pow_up)", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for &x in black_box(&xs) {
                s += ex.pow_down(x) + ex.pow_up(x * 1.01);
            }
            s
        })
    });
    group.finish();
}

criterion_group!(benches, pow);
criterion_main!(benches);

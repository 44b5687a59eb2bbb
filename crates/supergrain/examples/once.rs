use std::hint::black_box;
use supergrain::bench::{ShapeClass, near_touching_pairs};
use supergrain::contact::contact;
use supergrain::subdivision::Precision;
fn main() {
    let class = if std::env::args().nth(1).as_deref() == Some("stars") {
        ShapeClass::Stars
    } else {
        ShapeClass::Mixed
    };
    let precision = Precision::default();
    let set = near_touching_pairs(class, 300, 0.02, 1);
    for p in &set {
        black_box(run(p, &precision));
    }
}
#[inline(never)]
fn run(p: &supergrain::bench::Pair, precision: &Precision) -> bool {
    contact(black_box(&p.a), &p.pose_a, &p.b, &p.pose_b, precision).overlap()
}

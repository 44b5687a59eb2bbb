use std::hint::black_box;
use supergrain::bench::{ShapeClass, median_ns_per_item, near_touching_pairs};
use supergrain::contact::contact;
use supergrain::subdivision::Precision;
fn main() {
    let precision = Precision::default();
    for class in [ShapeClass::Mixed, ShapeClass::Stars] {
        let set = near_touching_pairs(class, 1000, 0.02, 1);
        let ns = median_ns_per_item(&set, 15, |p| {
            black_box(contact(
                black_box(&p.a),
                &p.pose_a,
                &p.b,
                &p.pose_b,
                &precision,
            ));
        });
        print!("{class:?} {ns:.0} ns  ");
    }
    println!();
}

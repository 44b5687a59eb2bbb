use std::hint::black_box;
use supergrain::bench::{ShapeClass, near_touching_pairs};
use supergrain::contact::contact;
use supergrain::subdivision::Precision;

fn main() {
    let which = std::env::args().nth(1).unwrap_or("convex".into());
    let precision = Precision::default();
    let set = near_touching_pairs(ShapeClass::Mixed, 1000, 0.02, 1);
    let star = |e: [f64; 2]| e.iter().any(|&x| x < 1.0);
    let g: Vec<_> = set
        .iter()
        .filter(|p| (star(p.a.exponents()) || star(p.b.exponents())) == (which == "star"))
        .copied()
        .collect();
    for _ in 0..3000 {
        for p in &g {
            black_box(contact(
                black_box(&p.a),
                &p.pose_a,
                &p.b,
                &p.pose_b,
                &precision,
            ));
        }
    }
}

use std::time::Instant;
use supergrain::bench::{ShapeClass, near_touching_pairs};
use supergrain::contact::contact;
use supergrain::subdivision::Precision;
fn main() {
    let prec = Precision::default();
    for (name, class) in [
        ("circles", ShapeClass::Circles),
        ("ellipses", ShapeClass::Ellipses),
        ("squircles", ShapeClass::Squircles),
    ] {
        let pairs = near_touching_pairs(class, 1000, 0.02, 3);
        let mut best = f64::INFINITY;
        let mut sink = 0.0;
        for _ in 0..60 {
            let t = Instant::now();
            for p in &pairs {
                let c = contact(&p.a, &p.pose_a, &p.b, &p.pose_b, &prec);
                if let Some(q) = c.penetration {
                    sink += q.a_push.x;
                }
            }
            best = best.min(t.elapsed().as_secs_f64());
        }
        print!("{name} {:.1}  ", best * 1e9 / 1000.0);
        std::hint::black_box(sink);
    }
    println!();
}

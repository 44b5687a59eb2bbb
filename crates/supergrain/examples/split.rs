use std::hint::black_box;
use supergrain::bench::{ShapeClass, median_ns_per_item, near_touching_pairs};
use supergrain::contact::contact;
use supergrain::subdivision::Precision;

fn main() {
    let precision = Precision::default();
    let set = near_touching_pairs(ShapeClass::Mixed, 1000, 0.02, 1);
    let star = |e: [f64; 2]| e.iter().any(|&x| x < 1.0);
    let equal = |p: &supergrain::bench::Pair| p.a.exponents() == p.b.exponents();
    let groups: Vec<(&str, Vec<_>)> = vec![
        (
            "star pairs",
            set.iter()
                .filter(|p| star(p.a.exponents()) || star(p.b.exponents()))
                .copied()
                .collect(),
        ),
        (
            "convex pairs",
            set.iter()
                .filter(|p| !star(p.a.exponents()) && !star(p.b.exponents()))
                .copied()
                .collect(),
        ),
        (
            "convex, both shapes' own exponents equal",
            set.iter()
                .filter(|p| {
                    !star(p.a.exponents())
                        && !star(p.b.exponents())
                        && p.a.exponents()[0] == p.a.exponents()[1]
                        && equal(p)
                })
                .copied()
                .collect(),
        ),
    ];
    for (name, g) in groups {
        let ns = median_ns_per_item(&g, 9, |p| {
            black_box(contact(
                black_box(&p.a),
                &p.pose_a,
                &p.b,
                &p.pose_b,
                &precision,
            ));
        });
        let over = g
            .iter()
            .filter(|p| contact(&p.a, &p.pose_a, &p.b, &p.pose_b, &precision).overlap())
            .count();
        println!(
            "{name}: {} pairs, {:.0} ns each, {over} overlap",
            g.len(),
            ns
        );
    }
}

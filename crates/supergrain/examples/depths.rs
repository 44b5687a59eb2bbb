//! The overlap depths of a dump's touching grains by dense sampling, beside the narrow phase's
//! push lengths: for each pair, the deepest of 720 boundary points of either grain inside the
//! other, by its distance to the other's sampled boundary (docs/physics.md, "Pushes along a
//! spike"). `cargo run --release -p supergrain --example depths -- DUMP.json`
use supergrain::geometry::Vec2;
use supergrain::io::Dump;
use supergrain::shape::Pose;
use supergrain::world::Touch;

fn main() {
    let path = std::env::args().nth(1).unwrap();
    let world = Dump::from_json(&std::fs::read_to_string(path).unwrap())
        .unwrap()
        .to_world()
        .unwrap();
    let mut rows = Vec::new();
    world.contacts(|t| {
        if let Touch::Grains(i, j, p) = t {
            rows.push((i, j, p.depth()));
        }
    });
    let n = 720;
    let mut sampled = Vec::new();
    for &(i, j, push) in &rows {
        let (a, b) = (&world.bodies[i], &world.bodies[j]);
        let pa = Pose::new(a.center, a.angle).unwrap();
        let pb = Pose::new(b.center, b.angle).unwrap();
        let poly_a = a.shape.boundary_polygon(&pa, n);
        let poly_b = b.shape.boundary_polygon(&pb, n);
        // Deepest point of each boundary inside the other: its distance to the other's polygon.
        let deep =
            |poly: &[Vec2], other: &supergrain::shape::Superellipse, po: &Pose, opoly: &[Vec2]| {
                poly.iter()
                    .filter(|&&q| other.value(po, q) < 0.0)
                    .map(|&q| {
                        opoly
                            .iter()
                            .map(|&o| (o - q).norm())
                            .fold(f64::INFINITY, f64::min)
                    })
                    .fold(0.0f64, f64::max)
            };
        let d = deep(&poly_a, &b.shape, &pb, &poly_b).max(deep(&poly_b, &a.shape, &pa, &poly_a));
        sampled.push((d, push));
    }
    let mut ds: Vec<f64> = sampled.iter().map(|x| x.0).collect();
    let mut ps: Vec<f64> = sampled.iter().map(|x| x.1).collect();
    ds.sort_by(f64::total_cmp);
    ps.sort_by(f64::total_cmp);
    let q = |v: &[f64], f: f64| v[((v.len() - 1) as f64 * f) as usize];
    println!(
        "{} contacts; sampled depth median {:.4} p90 {:.4} p99 {:.4} max {:.4}; push depth median {:.4} p90 {:.4} p99 {:.4} max {:.4}",
        rows.len(),
        q(&ds, 0.5),
        q(&ds, 0.9),
        q(&ds, 0.99),
        q(&ds, 1.0),
        q(&ps, 0.5),
        q(&ps, 0.9),
        q(&ps, 0.99),
        q(&ps, 1.0)
    );
}

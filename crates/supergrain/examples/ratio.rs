use std::time::Instant;
use supergrain::solver::NarrowPhase;
use supergrain::world::{Scene, World};
fn run(np: NarrowPhase, seed: u64) -> f64 {
    let mut scene = Scene::preset("circles").unwrap();
    scene.settings.narrow_phase = np;
    scene.seed = seed;
    let mut world = World::new(&scene);
    let t = Instant::now();
    for _ in 0..3000 {
        world.step();
    }
    t.elapsed().as_secs_f64()
}
fn main() {
    let seed: u64 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(1);
    let (mut c, mut a) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..7 {
        c = c.min(run(NarrowPhase::Interval, seed));
        a = a.min(run(NarrowPhase::Analytic, seed));
    }
    println!(
        "certified {:.1} ms, analytic {:.1} ms, ratio {:.2}",
        c * 1e3,
        a * 1e3,
        c / a
    );
}

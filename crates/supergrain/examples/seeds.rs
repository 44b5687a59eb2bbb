use supergrain::solver::NarrowPhase;
use supergrain::world::{Scene, World};
fn main() {
    for seed in 1..9 {
        for np in [NarrowPhase::Interval, NarrowPhase::Analytic] {
            let mut scene = Scene::preset("circles").unwrap();
            scene.settings.narrow_phase = np;
            scene.seed = seed;
            let mut world = World::new(&scene);
            let (mut tests, mut contacts, mut cells) = (0, 0, 0u64);
            let t = std::time::Instant::now();
            for _ in 0..3000 {
                let s = world.step();
                tests += s.tests;
                contacts += s.contacts;
            }
            let _ = cells;
            cells = 0;
            println!(
                "seed {seed} {np:?}: {:.0} ms tests {tests} contacts {contacts} asleep {} {}",
                t.elapsed().as_secs_f64() * 1e3,
                world.asleep(),
                cells
            );
        }
    }
}

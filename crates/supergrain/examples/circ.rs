use supergrain::solver::NarrowPhase;
use supergrain::world::{Scene, World};
fn main() {
    let mut scene = Scene::preset("circles").unwrap();
    scene.settings.narrow_phase = NarrowPhase::Interval;
    for seed in 1..6 {
        scene.seed = seed;
        let mut world = World::new(&scene);
        for _ in 0..3000 {
            world.step();
        }
    }
}

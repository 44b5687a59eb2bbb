//! The heap's mean stress (the run's summary with `--forces`) is the heap's: a grain in flight,
//! touching nothing, neither adds a force nor raises the height it is averaged over.

use supergrain::world::{Scene, World};

const HEAP: &str = "\
seed = 5
steps = 200

[box]
left = -1.0
right = 1.0
floor = 0.0
top = 1.0

[spawn]
interval = 1

[[group]]
name = \"discs\"
count = 6
radius = [0.2, 0.3]
";

#[test]
fn a_grain_in_flight_leaves_the_heaps_stress_as_it_is() {
    let scene = Scene::from_toml(HEAP).expect("a valid scene");
    let mut world = World::new(&scene);
    for _ in 0..200 {
        world.step();
    }
    let heap = world.stress().expect("the soft model's stress");
    assert!(heap[1][1] < 0.0, "the heap presses down: {heap:?}");
    // The same heap with a grain far above it, in flight: no contact of its own.
    let mut flying = *world.bodies.last().expect("grains");
    flying.center.y += 50.0;
    flying.previous_center.y += 50.0;
    world.bodies.push(flying);
    let with_flyer = world.stress().expect("the soft model's stress");
    for i in 0..2 {
        for j in 0..2 {
            let (a, b) = (heap[i][j], with_flyer[i][j]);
            assert!(
                (a - b).abs() <= 1e-12 * a.abs().max(1e-300),
                "sigma[{i}][{j}]: {a} for the heap, {b} with a grain in flight"
            );
        }
    }
}

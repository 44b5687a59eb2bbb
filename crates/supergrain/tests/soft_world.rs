//! The soft step in whole scenes (issue 18): the same result bit for bit on one thread and
//! two, and a run resumed from a dump goes on bit for bit; a pour with friction comes to rest.

use supergrain::io::Dump;
use supergrain::world::{Scene, World};

/// Disks, rice and blocks with friction and rolling resistance, one grain a step in a box 8
/// wide.
const SCENE: &str = r#"
seed = 3
[box]
left = -4.0
right = 4.0
floor = 0.0
top = 6.0
friction = 0.6
[spawn]
interval = 2
[solver]
model = "soft"
step = 0.008
[[group]]
count = 40
radius = [0.2, 0.3]
friction = 0.5
rolling_resistance = 0.1
restitution = 0.2
[[group]]
count = 30
semi_axes = [[0.25, 0.35], [0.1, 0.15]]
density = 2.0
[[group]]
count = 30
semi_axes = [[0.2, 0.3], [0.2, 0.3]]
exponent = [3.0, 6.0]
friction = 0.8
"#;

fn text(w: &World) -> String {
    serde_json::to_string(&Dump::of(w)).unwrap()
}

fn run(world: &mut World, steps: u64) {
    while world.step < steps {
        world.step();
    }
}

fn on_threads(threads: usize, steps: u64) -> String {
    let scene = Scene::from_toml(SCENE).unwrap();
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| {
            let mut w = World::new(&scene);
            run(&mut w, steps);
            text(&w)
        })
}

#[test]
fn one_thread_and_two_give_the_same_heap() {
    assert_eq!(on_threads(1, 300), on_threads(2, 300));
}

#[test]
fn a_run_resumed_from_its_dump_goes_on_bit_for_bit() {
    let scene = Scene::from_toml(SCENE).unwrap();
    let mut straight = World::new(&scene);
    run(&mut straight, 150);
    let saved = text(&straight);
    assert!(
        saved.contains("\"contacts\""),
        "the dump keeps the contacts"
    );
    let mut resumed = Dump::from_json(&saved).unwrap().to_world().unwrap();
    run(&mut straight, 300);
    run(&mut resumed, 300);
    assert_eq!(text(&straight), text(&resumed));
}

#[test]
fn a_pour_with_friction_comes_to_rest_in_the_box() {
    let scene = Scene::from_toml(SCENE).unwrap();
    let mut w = World::new(&scene);
    // 100 grains, one every two steps when their place is free; 9.6 s in all.
    run(&mut w, 1200);
    assert!(w.all_spawned(), "{} still to appear", w.pending.len());
    assert_eq!(w.first_outside(), None, "a grain left the box");
    let fastest = (0..w.bodies.len())
        .map(|i| w.velocity(i).norm())
        .fold(0.0, f64::max);
    assert!(fastest < 0.05, "the heap still moves: {fastest} units/s");
}

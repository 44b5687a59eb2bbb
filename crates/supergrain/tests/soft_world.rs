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
    run(&mut straight, 400);
    let saved = text(&straight);
    assert!(
        saved.contains("\"contacts\"") && saved.contains("\"carried\""),
        "the dump keeps the contacts and the manifolds carried"
    );
    let mut resumed = Dump::from_json(&saved).unwrap().to_world().unwrap();
    run(&mut straight, 550);
    run(&mut resumed, 550);
    assert_eq!(text(&straight), text(&resumed));
}

/// A dump's carried manifolds are checked as they are read: an error names the contact and
/// what is wrong, and nothing is resumed.
#[test]
fn a_dump_with_a_bad_carried_manifold_is_refused_naming_the_contact() {
    let scene = Scene::from_toml(SCENE).unwrap();
    let mut w = World::new(&scene);
    run(&mut w, 300);
    let mut dump: serde_json::Value = serde_json::from_str(&text(&w)).unwrap();
    let contacts = dump["contacts"].as_array_mut().unwrap();
    let k = contacts
        .iter()
        .position(|c| c.get("carried").is_some())
        .expect("a carried manifold");
    contacts[k]["carried"]["points"][0][3] = serde_json::json!(7.0);
    let err = Dump::from_json(&dump.to_string())
        .unwrap()
        .to_world()
        .expect_err("refused")
        .to_string();
    assert!(
        err.contains(&format!("contacts[{k}]")) && err.contains("id is 0, 1 or 2"),
        "{err}"
    );
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

/// Grains poured onto a slope across the box's left half, from `[[plane]]`.
const SLOPE: &str = r#"
seed = 5
[box]
left = -4.0
right = 4.0
floor = 0.0
top = 7.0
[spawn]
interval = 10
[solver]
model = "soft"
[[plane]]
normal = [0.5, 1.0]
point = [0.0, 2.0]
[[group]]
count = 12
radius = [0.2, 0.3]
[[group]]
count = 8
semi_axes = [[0.2, 0.3], [0.15, 0.2]]
exponent = 6.0
"#;

#[test]
fn grains_poured_on_a_plane_stay_above_it_and_resume_bit_for_bit() {
    let scene = Scene::from_toml(SLOPE).unwrap();
    assert_eq!(scene.boundaries.len(), 1);
    let plane = *scene.boundaries[0].as_plane().expect("a plane");
    let mut w = World::new(&scene);
    let mut deepest = 0.0f64;
    while w.step < 600 {
        w.step();
        for b in &w.bodies {
            // The grain's lowest point towards the plane: its support along -n.
            let n = plane.normal();
            let pose = b.pose();
            let local = pose.rotation().apply_inverse(-n);
            let reach = b.shape.local_support(local);
            deepest = deepest.max(-(plane.value(b.center) - reach));
        }
        if w.step == 300 {
            let saved = text(&w);
            assert!(saved.contains("\"boundaries\""));
            let mut resumed = Dump::from_json(&saved).unwrap().to_world().unwrap();
            run(&mut resumed, 600);
            let mut straight = Dump::from_json(&saved).unwrap().to_world().unwrap();
            run(&mut straight, 600);
            assert_eq!(text(&resumed), text(&straight));
        }
    }
    // A contact keeps about a slop (0.005) of overlap, and an impact presses a grain in for a
    // few steps: 0.027 by the queue rule; by the fair rule (the default, another heap) 0.035,
    // one step, a grain sliding on the plane struck by one falling at 5.6 units/s, pushed out
    // within 15 steps. A grain through the plane would be a grain's size deep.
    assert!(deepest < 0.04, "a grain sank {deepest} into the plane");
    assert_eq!(w.first_outside(), None);
}

#[test]
fn a_plane_needs_the_soft_model() {
    let paper = SLOPE.replace("model = \"soft\"", "model = \"paper\"");
    let err = Scene::from_toml(&paper).unwrap_err().to_string();
    assert!(
        err.contains("[[plane]] needs") && err.contains("line"),
        "{err}"
    );
}

#[test]
fn a_sleeping_heap_wakes_under_a_dropped_grain_and_holds_it() {
    let scene = Scene::from_toml(SCENE).unwrap();
    let mut w = World::new(&scene);
    // Asleep by islands, the heap falls asleep at once when all of it is calm, which on this
    // seed takes 1,200 to 3,000 steps (one grain creeping on the top keeps it awake: seeds 1-6
    // asleep by step 800 but this one; with the separations read before 2026-12-06, seed 5 not
    // by 3,000).
    while w.asleep() <= 90 {
        assert!(
            w.step < 4000,
            "only {} of 100 grains sleep by step 4,000",
            w.asleep()
        );
        w.step();
    }
    let sleeping = w.asleep();
    // A heavy disk dropped from above the middle of the heap.
    let top = w
        .bodies
        .iter()
        .map(|b| b.bounding_box().max.y)
        .fold(0.0, f64::max);
    let disk = supergrain::shape::Superellipse::circle(0.3).unwrap();
    let pose = supergrain::shape::Pose::new(supergrain::geometry::Vec2::new(0.0, top + 1.0), 0.0);
    let mut grain = supergrain::body::Body::at_rest(disk, &pose.unwrap());
    grain.group = 1;
    w.bodies.push(grain);
    let new = w.bodies.len() - 1;
    let mut woke = false;
    for _ in 0..400 {
        w.step();
        woke |= w.asleep() < sleeping;
    }
    assert!(woke, "no sleeper woke when the disk landed");
    // Resting on the heap, not in it: no overlap of the disk deeper than a few slops.
    let mut deepest = 0.0f64;
    w.contacts(|t| {
        if let supergrain::world::Touch::Grains(i, j, p) = t
            && (i == new || j == new)
        {
            deepest = deepest.max(p.depth());
        }
    });
    assert!(deepest < 0.03, "the disk is {deepest} deep in the heap");
    assert!(w.velocity(new).norm() < 0.05, "the disk still moves");
    assert_eq!(w.first_outside(), None);
}

/// Under the soft model a grain pushed into the floor (its centre a little below it, as a
/// grain of rice struck by a falling block was in `pour-100k.toml`) has not left the box: the
/// floor pushes it out. One beyond a wall by more than its diameter has.
#[test]
fn a_soft_grain_pushed_into_the_floor_has_not_left_the_box() {
    let scene = Scene::from_toml(SCENE).unwrap();
    let mut w = World::new(&scene);
    run(&mut w, 40);
    let n = w.bodies.len();
    assert!(n > 2);
    w.bodies[0].center.y = -0.01;
    w.bodies[0].previous_center = w.bodies[0].center;
    assert_eq!(w.first_outside(), None);
    run(&mut w, 70);
    assert!(w.bodies[0].center.y > 0.05, "{:?}", w.bodies[0].center);
    // Wholly beyond the right wall by more than its diameter.
    let r = w.bodies[1].shape.bounding_radius();
    w.bodies[1].center.x = 4.0 + 3.1 * r;
    assert_eq!(w.first_outside(), Some(1));
}

/// A dump tells a contact of the last step (kept impulses, zeros included: a sleeping island's
/// link) from a pair with only a warm start (tested and found apart). Read back, a warm-only
/// pair is no contact, and a contact with zero impulses still is one; written again, each is
/// as it was. (A warm-only pair read as a contact linked two sleepers that had not touched, and
/// a resumed run's next dump listed it where the straight run's did not.)
#[test]
fn a_dump_keeps_contacts_and_warm_starts_apart() {
    let scene = Scene::from_toml(SCENE).unwrap();
    let mut w = World::new(&scene);
    run(&mut w, 200);
    let mut d: serde_json::Value = serde_json::from_str(&text(&w)).unwrap();
    let contacts = d["contacts"].as_array_mut().unwrap();
    contacts.retain(|c| !(c["a"] == 0 && (c["b"] == 1 || c["b"] == 2)));
    contacts.push(serde_json::json!({"a": 0, "b": 1, "warm": [[0.1, 0.2]]}));
    contacts.push(serde_json::json!({"a": 0, "b": 2, "normal_impulse": [0.0, 0.0, 0.0]}));
    let back = Dump::from_json(&d.to_string()).unwrap().to_world().unwrap();
    assert!(
        !back.soft.kept.contains_key(&(0, 1)),
        "a warm start read as a contact"
    );
    assert!(back.soft.warm.contains_key(&(0, 1)));
    assert!(
        back.soft.kept.contains_key(&(0, 2)),
        "a contact of zero impulses lost"
    );
    let again: serde_json::Value = serde_json::from_str(&text(&back)).unwrap();
    let entry = |b: u64| {
        again["contacts"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["a"] == 0 && c["b"] == b)
            .cloned()
            .unwrap()
    };
    assert_eq!(
        entry(1),
        serde_json::json!({"a": 0, "b": 1, "warm": [[0.1, 0.2]]})
    );
    assert_eq!(
        entry(2),
        serde_json::json!({"a": 0, "b": 2, "normal_impulse": [0.0, 0.0, 0.0]})
    );
}

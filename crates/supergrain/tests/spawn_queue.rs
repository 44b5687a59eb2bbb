//! The spawn queue: grains still to appear cost memory and dump space only once drawn (issue 17,
//! section 5), every grain of every group comes, mixed, on the schedule; a run resumed from a
//! dump, while grains wait for their place and many are still to draw, is the uninterrupted one
//! bit for bit; dumps from before the queue (an explicit `pending` list) still resume.

use std::f64::consts::TAU;

use supergrain::io::Dump;
use supergrain::world::{Group, Range, Scene, World};

/// Ten million grains of sand (and a thousand pebbles) in a box that can hold them, 50 due at
/// every step; a step short enough for sand falling freely from 300 (issue 40: the soft model's
/// fall is not damped).
const TEN_MILLION: &str = r#"
seed = 3
[box]
left = -200.0
right = 200.0
floor = 0.0
top = 300.0

[spawn]
interval = 1
count = 50

[solver]
step = 0.001

[[group]]
name = "sand"
count = 10000000
radius = 0.05

[[group]]
name = "pebbles"
count = 1000
radius = [0.1, 0.2]
"#;

fn dump_text(world: &World) -> String {
    serde_json::to_string(&Dump::of(world)).unwrap()
}

/// The issue's case, `count = 10000000` for a 20-step run: on the code before the queue, this
/// test's run peaked at 2.6 GB and its dump was 1.1 GB (1,099,185,172 bytes, all but 246 kB
/// the grains still to appear), after 12 s. The queue now holds only the grains drawn and
/// waiting, and the dump is the grains that appeared plus a few hundred bytes.
#[test]
fn ten_million_grains_still_to_appear_cost_neither_memory_nor_dump() {
    let scene = Scene::from_toml(TEN_MILLION).expect("the box holds them");
    let mut world = World::new(&scene);
    assert_eq!(world.pending_count(), 10_001_000);
    for _ in 0..20 {
        world.step();
    }
    let appeared = world.bodies.len();
    // Of the 1,000 due, those whose place was free (one in four or so is near a grain that
    // appeared in the last ten steps, not yet fallen by its own size).
    assert!(appeared >= 500, "{appeared} grains appeared");
    assert_eq!(world.pending_count(), 10_001_000 - appeared as u64);
    // Held one by one: the grains due whose place was taken, at most the 1,000 due so far.
    let held = world.pending.waiting().len();
    assert!(held < 1000, "{held} grains held");
    assert_eq!(held as u64 + world.bodies.len() as u64, 1000);
    let dump = Dump::of(&world);
    let text = serde_json::to_string(&dump).unwrap();
    let grains = serde_json::to_string(&dump.particles).unwrap().len();
    assert!(
        text.len() < 100_000 + grains,
        "a dump of {} bytes, {grains} of them the grains that appeared",
        text.len()
    );
    // And it resumes where the run is.
    let mut resumed = Dump::from_json(&text).unwrap().to_world().unwrap();
    assert_eq!(resumed.pending_count(), world.pending_count());
    for _ in 0..3 {
        world.step();
        resumed.step();
    }
    assert_eq!(dump_text(&world), dump_text(&resumed));
}

/// Two groups of grains in the presets' box, eight due every ten steps: more than the top of
/// the box has room for, so that grains wait.
fn crowded() -> Scene {
    let mut scene = Scene::preset("circles").unwrap();
    scene.seed = 5;
    scene.spawn_interval = 10;
    scene.spawn_count = 8;
    scene.groups[0].count = 80;
    scene.groups[0].semi_axes = [Range::new(0.2, 0.4); 2];
    scene.groups.push(Group {
        name: "squircles".into(),
        count: 40,
        semi_axes: [Range::new(0.2, 0.3), Range::new(0.2, 0.4)],
        circles: false,
        exponents: [Range::fixed(4.0); 2],
        same_exponents: true,
        angle: Range::new(0.0, TAU),
        material: Default::default(),
    });
    scene.validate().expect("a valid scene");
    scene
}

#[test]
fn a_resume_while_grains_wait_and_many_are_still_to_draw_is_exact() {
    let scene = crowded();
    let mut whole = World::new(&scene);
    for _ in 0..100 {
        whole.step();
    }
    let mut first = World::new(&scene);
    for _ in 0..40 {
        first.step();
    }
    let waiting = first.pending.waiting().len();
    let to_draw = first.pending.generator().map_or(0, |g| g.remaining());
    assert!(waiting > 0, "no grain waits at the break");
    assert!(to_draw > 50, "only {to_draw} grains still to draw");
    assert!(
        first.pending.waiting().iter().all(|p| p.due <= first.step),
        "a grain drawn before it was due"
    );
    let text = dump_text(&first);
    let mut resumed = Dump::from_json(&text).unwrap().to_world().unwrap();
    assert_eq!(resumed.pending, first.pending);
    for _ in 0..60 {
        resumed.step();
    }
    assert_eq!(dump_text(&whole), dump_text(&resumed));
}

/// Every grain of every group is dealt, in the ranges, on the schedule, the groups mixed as a
/// shuffle mixes them (not one group after the other).
#[test]
fn the_queue_deals_every_grain_of_every_group_mixed_on_the_schedule() {
    let scene = crowded();
    let world = World::new(&scene);
    let grains: Vec<_> = world.pending.iter().collect();
    assert_eq!(grains.len(), 120);
    assert_eq!(world.pending_count(), 120);
    for (k, p) in grains.iter().enumerate() {
        assert_eq!(p.due, k as u64 / 8 * 10, "grain {k}");
        let g = &scene.groups[p.group as usize];
        let s = p.shape.semi_axes();
        let within = |r: Range, v: f64| r.lo <= v && v <= r.hi;
        assert!(within(g.semi_axes[0], s.x), "grain {k}: {s:?}");
        assert!(
            g.circles == (s.x == s.y) && within(g.semi_axes[1], s.y),
            "grain {k}: {s:?}"
        );
        assert!(within(g.angle, p.angle), "grain {k}");
        assert!(
            scene.walls.left < p.x && p.x < scene.walls.right,
            "grain {k}"
        );
    }
    let of = |group| grains.iter().filter(|p| p.group == group).count();
    assert_eq!((of(0), of(1)), (80, 40));
    // A shuffle of 80 and 40 changes group 2 x 80 x 40 / 120 = 53 times on average.
    let changes = grains
        .windows(2)
        .filter(|w| w[0].group != w[1].group)
        .count();
    assert!((35..=75).contains(&changes), "{changes} changes of group");
    // Drawing them changes nothing: the same grains again.
    assert_eq!(world.pending.iter().collect::<Vec<_>>(), grains);
}

/// A dump from before the queue lists every grain still to appear (`"pending": [...]`): it
/// resumes with those grains, in that order, then nothing more, and goes on exactly as the run
/// whose grains they are.
#[test]
fn a_dump_with_a_pending_list_resumes_those_grains_then_nothing_more() {
    let scene = crowded();
    let mut world = World::new(&scene);
    for _ in 0..40 {
        world.step();
    }
    // The old form of this state: the queue's grains written out one by one.
    let mut old: serde_json::Value = serde_json::from_str(&dump_text(&world)).unwrap();
    let list: Vec<serde_json::Value> = world
        .pending
        .iter()
        .map(|p| {
            serde_json::json!({
                "semi_axes": p.shape.semi_axes().to_array(),
                "exponents": p.shape.exponents(),
                "x": p.x,
                "angle": p.angle,
                "due": p.due,
                "group": p.group,
            })
        })
        .collect();
    let obj = old.as_object_mut().unwrap();
    obj.remove("queue");
    let listed = list.len();
    obj.insert("pending".into(), list.into());
    let old_text = old.to_string();
    let mut resumed = Dump::from_json(&old_text).unwrap().to_world().unwrap();
    assert_eq!(resumed.pending_count(), world.pending_count());
    assert!(resumed.pending.generator().is_none());
    // Written again, it has a queue of those grains, not the old list.
    let again = Dump::of(&resumed);
    assert!(again.pending.is_empty());
    let queue = again.queue.expect("grains still to appear");
    assert_eq!((queue.waiting.len(), queue.generator), (listed, None));
    for _ in 0..60 {
        world.step();
        resumed.step();
    }
    // The same grains, where the run has them, and the same still to come.
    let state = |w: &World| {
        let mut dump = Dump::of(w);
        dump.queue = None;
        (dump, w.pending.iter().collect::<Vec<_>>())
    };
    assert_eq!(state(&world), state(&resumed));
    while !resumed.all_spawned() && resumed.step < 3000 {
        resumed.step();
    }
    assert_eq!(
        resumed.bodies.len(),
        120,
        "the listed grains, then nothing more"
    );
    assert!(Dump::of(&resumed).queue.is_none());
}

/// Dumps written by the code before the queue (`supergrain run --preset circles --steps 100`,
/// then `--steps 300`, in `tests/data`): the first resumed for 200 steps is the second, its
/// grains where that run had them and the same grains still to appear, in the same order.
/// (No grain touches another before step 300: the run is free fall and spawning alone.)
#[test]
fn a_dump_written_before_the_queue_resumes_as_that_code_ran_on() {
    let at_100 = Dump::from_json(include_str!("data/pending-list-step-100.json")).unwrap();
    let at_300 = Dump::from_json(include_str!("data/pending-list-step-300.json")).unwrap();
    assert_eq!((at_100.particles.len(), at_100.pending.len()), (4, 31));
    let mut world = at_100.to_world().unwrap();
    assert_eq!(world.pending_count(), 31);
    while world.step < 300 {
        world.step();
    }
    let now = Dump::of(&world);
    assert_eq!(now.particles, at_300.particles);
    assert_eq!(now.step, at_300.step);
    let queue = now.queue.expect("grains still to appear");
    assert_eq!(queue.waiting, at_300.pending);
    assert_eq!(queue.generator, None);
}

//! The spawn rules (issue 18, item 7): the fair rule pours a mixture as it is queued, where the
//! queue rule sorts it; the fair rule keeps the queue's guarantees (grains in queue order, the
//! same run on one thread and two, a resume bit for bit while a grain is being offered places);
//! `[spawn] rule` is chosen by the solver model unless given.

use supergrain::io::Dump;
use supergrain::world::{Scene, SpawnRule, World};

/// Disks of radii 0.25 and 0.35, 200 of each, due one a step (faster than the top of a box 12
/// wide has room for, so that grains are blocked), soft model, friction and rolling resistance.
/// No `rule`: the soft model's default, the fair rule.
const POUR: &str = r#"
seed = 1
[box]
left = -6.0
right = 6.0
floor = 0.0
top = 16.0
friction = 0.5
[spawn]
interval = 1
[solver]
model = "soft"
[[group]]
name = "small"
count = 200
radius = 0.25
friction = 0.5
rolling_resistance = 0.1
[[group]]
name = "large"
count = 200
radius = 0.35
friction = 0.5
rolling_resistance = 0.1
"#;

fn pour(rule: SpawnRule) -> Scene {
    let mut scene = Scene::from_toml(POUR).unwrap();
    assert_eq!(
        scene.spawn_rule,
        SpawnRule::Fair,
        "the soft model's default"
    );
    scene.spawn_rule = rule;
    scene
}

fn text(w: &World) -> String {
    serde_json::to_string(&Dump::of(w)).unwrap()
}

/// What the bar measures of a pour: the share of small grains among the first 60% to appear,
/// and in the lowest and the highest third of the heap (the grains sorted by the height of
/// their centres).
#[derive(Debug)]
struct Shares {
    first: f64,
    bottom: f64,
    top: f64,
}

/// Runs `scene` until every grain has appeared and 300 steps more (3 s: the last grain has
/// landed and the heap has stopped moving): the shares, and the world.
fn poured(scene: &Scene) -> (Shares, World) {
    let mut w = World::new(scene);
    while !w.all_spawned() {
        assert!(w.step < 5000, "{} grains still to appear", w.pending.len());
        w.step();
    }
    let end = w.step + 300;
    while w.step < end {
        w.step();
    }
    let small = |groups: &mut dyn Iterator<Item = u32>| {
        let (mut n, mut small) = (0, 0);
        for g in groups {
            n += 1;
            small += usize::from(g == 0);
        }
        small as f64 / n as f64
    };
    let n = w.bodies.len();
    let mut heights: Vec<(f64, u32)> = w.bodies.iter().map(|b| (b.center.y, b.group)).collect();
    heights.sort_by(|a, b| a.0.total_cmp(&b.0));
    let third = n / 3;
    let shares = Shares {
        first: small(&mut w.bodies[..n * 6 / 10].iter().map(|b| b.group)),
        bottom: small(&mut heights[..third].iter().map(|h| h.1)),
        top: small(&mut heights[n - third..].iter().map(|h| h.1)),
    };
    (shares, w)
}

fn fair(s: &Shares) -> bool {
    [s.first, s.bottom, s.top]
        .iter()
        .all(|x| (0.4..=0.6).contains(x))
}

/// The issue's bar: a 50:50 pour keeps its mixture in the order the grains appear and in the
/// heap. Measured (the small share among the first 60% to appear; in the bottom third; in the
/// top third of the heap), seeds 1, 2, 3:
/// - fair rule: 0.496, 0.541, 0.504; 0.508, 0.466, 0.474; 0.521, 0.541, 0.474 (all 400
///   grains in by step 545-564; 300 steps later the fastest moves at 0.009-0.017).
/// - queue rule: 0.754, 0.759, 0.053; 0.758, 0.767, 0.053; 0.758, 0.752, 0.045 (the last 20%
///   to appear are 0-2.5% small; all in by step 1157-1388). It fails the bar (the next test).
///
/// The fair rule's grains also appear in exactly the order the queue deals them.
#[test]
fn the_fair_rule_pours_a_mixture_as_it_is_queued() {
    let scene = pour(SpawnRule::Fair);
    let dealt: Vec<_> = World::new(&scene)
        .pending
        .iter()
        .map(|p| (p.group, p.shape))
        .collect();
    let (shares, w) = poured(&scene);
    assert!(fair(&shares), "{shares:?}");
    let appeared: Vec<_> = w.bodies.iter().map(|b| (b.group, b.shape)).collect();
    assert_eq!(appeared.len(), dealt.len());
    for (k, (a, d)) in appeared.iter().zip(&dealt).enumerate() {
        assert_eq!(a, d, "grain {k} out of queue order");
    }
    assert_eq!(w.first_outside(), None);
}

/// The same pour by the queue rule (the paper's model's default) sorts it: blocked large
/// grains wait while small ones pass, so the small arrive first and the heap is layered.
#[test]
fn the_queue_rule_sorts_the_same_pour() {
    let (shares, _) = poured(&pour(SpawnRule::Queue));
    assert!(
        shares.first > 0.7 && shares.bottom > 0.7 && shares.top < 0.1,
        "{shares:?}"
    );
    assert!(!fair(&shares));
}

/// A state in the middle of the fair pour where the next grain has been offered places and
/// refused them all: the steps after it are where its retries come from.
fn while_a_grain_retries(scene: &Scene) -> World {
    let mut w = World::new(scene);
    loop {
        w.step();
        let retrying = w.pending.fair().is_some_and(|f| f.tries > 0);
        if w.step >= 100 && retrying && w.pending.waiting().len() == 1 {
            return w;
        }
        assert!(w.step < 1000, "no grain was blocked");
    }
}

#[test]
fn a_fair_pour_resumed_while_a_grain_retries_is_the_uninterrupted_one() {
    let scene = pour(SpawnRule::Fair);
    let first = while_a_grain_retries(&scene);
    let at = first.step;
    let saved = text(&first);
    assert!(
        saved.contains("\"fair\""),
        "the dump keeps the rule's state"
    );
    let mut resumed = Dump::from_json(&saved).unwrap().to_world().unwrap();
    // (The generator's groups carry no material in a dump: the world's `materials` do.)
    assert_eq!(resumed.pending.waiting(), first.pending.waiting());
    assert_eq!(resumed.pending.fair(), first.pending.fair());
    let mut whole = World::new(&scene);
    while whole.step < at + 300 {
        whole.step();
    }
    while resumed.step < at + 300 {
        resumed.step();
    }
    assert!(
        resumed.bodies.len() > first.bodies.len() + 50,
        "grains appeared after the resume"
    );
    assert_eq!(text(&whole), text(&resumed));
}

#[test]
fn a_fair_pour_is_the_same_on_one_thread_and_two() {
    let on = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let mut w = World::new(&pour(SpawnRule::Fair));
                while w.step < 400 {
                    w.step();
                }
                text(&w)
            })
    };
    assert_eq!(on(1), on(2));
}

/// The fair rule with the paper's model (chosen, not its default): every grain, due all at
/// once, appears in queue order, those placed under the top moving down as the paper's fall
/// does (at most its terminal `g h / delta` = 0.98), and all stay in the box.
#[test]
fn the_fair_rule_serves_the_paper_model_too() {
    let mut scene = Scene::preset("circles").unwrap();
    scene.spawn_rule = SpawnRule::Fair;
    scene.spawn_interval = 0;
    let dealt: Vec<_> = World::new(&scene).pending.iter().map(|p| p.shape).collect();
    let mut w = World::new(&scene);
    w.step();
    let below: Vec<_> = w
        .bodies
        .iter()
        .filter(|b| b.center.y < scene.top - 0.1)
        .collect();
    assert!(
        below.len() >= 5,
        "{} of {} under the top",
        below.len(),
        w.bodies.len()
    );
    for b in below {
        let per_step = b.previous_center.y - b.center.y;
        assert!(
            per_step > 0.0 && per_step <= 0.98 * 0.01 + 1e-3,
            "{per_step}"
        );
    }
    while !w.all_spawned() {
        assert!(w.step < 2000, "{} still to appear", w.pending.len());
        w.step();
    }
    let appeared: Vec<_> = w.bodies.iter().map(|b| b.shape).collect();
    assert_eq!(appeared, dealt);
    assert_eq!(w.first_outside(), None);
}

/// A scene with `[spawn]` lines `spawn` and `[solver]` lines `solver`.
fn scene(spawn: &str, solver: &str) -> Result<Scene, String> {
    Scene::from_toml(&format!(
        "[box]\nleft = -4.0\nright = 4.0\nfloor = 0.0\ntop = 10.0\n[spawn]\n{spawn}\n\
         [solver]\n{solver}\n[[group]]\ncount = 5\nradius = 0.3\n"
    ))
    .map_err(|e| e.to_string())
}

#[test]
fn the_rule_defaults_by_model_and_can_be_chosen() {
    let rule = |spawn: &str, solver: &str| scene(spawn, solver).unwrap().spawn_rule;
    // A scene file's model is the soft one unless it says.
    assert_eq!(rule("", ""), SpawnRule::Fair);
    assert_eq!(rule("", "model = \"paper\""), SpawnRule::Queue);
    assert_eq!(rule("", "model = \"soft\""), SpawnRule::Fair);
    assert_eq!(
        rule("rule = \"fair\"", "model = \"paper\""),
        SpawnRule::Fair
    );
    assert_eq!(
        rule("rule = \"queue\"", "model = \"soft\""),
        SpawnRule::Queue
    );
    // `interval` is optional with `rule`: 20, as without `[spawn]`.
    assert_eq!(scene("rule = \"fair\"", "").unwrap().spawn_interval, 20);
    for preset in supergrain::world::PRESETS {
        assert_eq!(
            Scene::preset(preset).unwrap().spawn_rule,
            SpawnRule::Queue,
            "{preset}"
        );
    }
    // The paper's model's dump carries no trace of the rule.
    let mut w = World::new(&scene("interval = 20", "model = \"paper\"").unwrap());
    w.step();
    let saved = text(&w);
    assert!(
        saved.contains("\"queue\"") && !saved.contains("fair"),
        "{saved}"
    );
}

#[test]
fn an_unknown_rule_is_an_error_naming_the_key_and_line() {
    let e = scene("rule = \"random\"", "").unwrap_err();
    assert!(e.contains("line 7"), "{e}");
    assert!(e.contains("spawn: rule"), "{e}");
    assert!(e.contains("\"fair\" or \"queue\""), "{e}");
    assert!(e.contains("\"random\""), "{e}");
}

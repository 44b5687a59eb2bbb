//! Sources narrower than the box (`[spawn] between`) and at a rate (`[spawn] rate`): grains
//! appear only across the source, at the rate asked (rounded to whole steps), and a dump keeps
//! the source.

use supergrain::io::Dump;
use supergrain::world::{Scene, World};

fn scene(spawn: &str) -> Scene {
    Scene::from_toml(&format!(
        "seed = 3\n[box]\nleft = -4.0\nright = 4.0\nfloor = 0.0\ntop = 6.0\n\
         [spawn]\n{spawn}\n[solver]\nmodel = \"soft\"\n\
         [[group]]\ncount = 120\nradius = [0.08, 0.12]\n"
    ))
    .unwrap()
}

#[test]
fn grains_appear_only_across_the_source() {
    let s = scene("between = [-1.0, 0.5]\ninterval = 1\ncount = 2");
    assert_eq!(s.spawn_between, Some([-1.0, 0.5]));
    let mut w = World::new(&s);
    let mut seen = 0;
    let mut text = String::new();
    while w.step < 300 {
        w.step();
        // Each grain where it appeared (its first step: it has fallen at most one step).
        for b in &w.bodies[seen..] {
            let r = b.shape.bounding_radius();
            assert!(
                -1.0 + r - 1e-9 <= b.center.x && b.center.x <= 0.5 - r + 1e-9,
                "a grain appeared at x = {}",
                b.center.x
            );
        }
        seen = w.bodies.len();
        if w.step == 20 {
            text = serde_json::to_string(&Dump::of(&w)).unwrap();
        }
    }
    assert!(seen > 100, "{seen} grains appeared");
    // The dump keeps the source: resumed, the grains appear where they did.
    assert!(text.contains("\"between\":[-1.0,0.5]"), "{text}");
    let back = Dump::from_json(&text).unwrap().to_world().unwrap();
    assert_eq!(back.pending.between(), Some([-1.0, 0.5]));
}

#[test]
fn a_rate_sets_how_many_grains_appear_a_second() {
    // 0.01 s steps: 30 grains a second is one every 3 steps (33.3 a second); 250 a second is
    // 2.5 a step, rounded to 3 (300 a second).
    for (rate, want) in [(30.0, 100.0 / 3.0), (250.0, 300.0)] {
        let s = Scene::from_toml(&format!(
            "seed = 3\n[box]\nleft = -8.0\nright = 8.0\nfloor = 0.0\ntop = 6.0\n\
             [spawn]\nrate = {rate}\n[solver]\nmodel = \"soft\"\nstep = 0.01\n\
             [[group]]\ncount = 1000\nradius = 0.06\n"
        ))
        .unwrap();
        let mut w = World::new(&s);
        while w.step < 100 {
            w.step();
        }
        let n = w.bodies.len() as f64;
        assert!(
            (n - want).abs() <= 1.0,
            "rate {rate}: {n} grains in 1 s, want {want}"
        );
    }
    let e = Scene::from_toml(
        "[box]\nleft = -1.0\nright = 1.0\nfloor = 0.0\ntop = 3.0\n[spawn]\nrate = 5.0\n\
         interval = 2\n[[group]]\ncount = 3\nradius = 0.1\n",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("rate, or interval and count"), "{e}");
    let e = Scene::from_toml(
        "[box]\nleft = -1.0\nright = 1.0\nfloor = 0.0\ntop = 3.0\n[spawn]\nbetween = [0.5, 2.0]\n\
         [[group]]\ncount = 3\nradius = 0.1\n",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("line 7") && e.contains("within the walls"),
        "{e}"
    );
}

//! Driven grains (issue 41, kinematic bodies): a `[[grain]]` with `turn` or `shake` moves as
//! its drive says, whatever it touches. Checked against closed forms written out here: the
//! paddle's pose at every step; a grain on a plank shaken below 1 g follows the plank, and
//! above 1 g leaves it; a grain in the paddle's way is swept along. A stirred heap resumed from
//! a dump ends bit for bit where the uninterrupted run ends, on one thread and two; driven
//! grains that cannot work are refused, naming the table or field.

mod common;

use common::resume::{dump_text, resumed};
use std::f64::consts::TAU;
use supergrain::body::BodyKind;
use supergrain::io::Dump;
use supergrain::world::{Scene, World};

fn scene(body: &str) -> String {
    format!(
        "seed = 4\n[box]\nleft = -3.0\nright = 3.0\nfloor = 0.0\ntop = 5.0\nfriction = 0.5\n\
         [spawn]\ninterval = 2\n\
         [solver]\nmodel = \"soft\"\nstep = 0.005\n\
         [[group]]\nname = \"grains\"\ncount = 0\nradius = 0.1\nfriction = 0.5\n{body}"
    )
}

fn world(body: &str) -> World {
    World::new(&Scene::from_toml(&scene(body)).unwrap())
}

/// A plank 3 long and 0.2 thick, turning about its centre at (0, 1.2) at 60 degrees a second.
const PADDLE: &str = "[[grain]]\ncenter = [0.0, 1.2]\nsemi_axes = [1.5, 0.1]\nexponent = 10.0\n\
                      turn = { about = [0.0, 1.2], rate = 60.0 }\n";

#[test]
fn a_turning_paddle_is_where_its_closed_form_says_whatever_it_stirs() {
    let body = format!(
        "{PADDLE}[[group]]\nname = \"poured\"\ncount = 60\nradius = [0.08, 0.12]\nfriction = 0.5\n"
    );
    let mut w = world(&body);
    assert_eq!(w.bodies[0].kind, BodyKind::Kinematic);
    let mut touched = false;
    while w.step < 1200 {
        w.step();
        let t = w.time();
        let p = &w.bodies[0];
        // Turned about its own centre: the centre stays, the angle is the rate times the time.
        assert_eq!(p.center.x, 0.0);
        assert_eq!(p.center.y, 1.2);
        let want = (60.0 * t).to_radians();
        assert!(
            (p.angle - want).abs() < 1e-12,
            "at t = {t}: angle {} against {want}",
            p.angle
        );
        let w_want = 60f64.to_radians();
        assert!((p.angular_velocity - w_want).abs() < 1e-9 * w_want);
        touched |= w.bodies[1..]
            .iter()
            .any(|b| (b.center - p.center).norm() < 1.5 && b.velocity.norm() > 1.0);
    }
    assert!(
        touched,
        "the paddle swept no grain at more than 1 unit/s within its reach"
    );
    // It is not a grain of the heap: not counted asleep, not taken by the rest test.
    assert!(w.max_speed() < 20.0);
}

/// A grain on a plank shaken up and down: at peak acceleration `A (2 pi f)^2` below g it stays
/// on the plank (its height the plank's, up to the contact's give); above g it leaves.
#[test]
fn a_grain_on_a_shaken_plank_follows_it_below_one_g_and_leaves_above() {
    let run = |a: f64, f: f64| {
        let mut w = world(&format!(
            "[[grain]]\ncenter = [0.0, 1.0]\nsemi_axes = [1.5, 0.1]\nexponent = 10.0\n\
             shake = {{ amplitude = [0.0, {a}], frequency = {f} }}\n\
             [[grain]]\ncenter = [0.0, 1.2]\nradius = 0.1\n"
        ));
        let mut worst = 0.0f64;
        while w.step < 800 {
            w.step();
            let t = w.time();
            let plank = 1.0 + a * (TAU * f * t).sin();
            assert!(
                (w.bodies[0].center.y - plank).abs() < 1e-12,
                "the plank at {} against {plank}",
                w.bodies[0].center.y
            );
            assert_eq!(w.bodies[0].center.x, 0.0);
            if w.step > 100 {
                worst = worst.max((w.bodies[1].center.y - 0.2 - plank).abs());
            }
        }
        worst
    };
    // 0.02 at 3 Hz: 7.1 units/s^2 at the peak, below g.
    let below = run(0.02, 3.0);
    assert!(
        below < 0.1 * 0.02,
        "strayed {below} from the plank (amplitude 0.02)"
    );
    // 0.05 at 4 Hz: 31.6 units/s^2, above g: the grain is thrown off at every cycle's top.
    let above = run(0.05, 4.0);
    assert!(
        above > 0.5 * 0.05,
        "stayed within {above} of a plank shaken at 3 g"
    );
}

#[test]
fn a_stirred_heap_resumes_bit_for_bit_on_one_thread_and_two() {
    let body = format!("{PADDLE}[[group]]\nname = \"poured\"\ncount = 80\nradius = [0.08, 0.12]\n");
    let mut w = world(&body);
    while w.step < 300 {
        w.step();
    }
    let saved = dump_text(&w);
    assert!(saved.contains("\"drivers\"") && saved.contains("\"kinematic\""));
    while w.step < 600 {
        w.step();
    }
    let straight = dump_text(&w);
    for threads in [1, 2] {
        assert_eq!(
            resumed(&saved, 600, threads),
            straight,
            "resumed on {threads} threads"
        );
    }
}

#[test]
fn driven_grains_that_cannot_work_are_refused() {
    let refused = |body: &str, text: &str| {
        let e = match Scene::from_toml(&scene(body)) {
            Ok(_) => panic!("accepted: {body}"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(text), "{body}: {e}");
    };
    refused(
        &format!("{PADDLE}fixed = true\n"),
        "give it no `fixed`, velocity or angular_velocity",
    );
    refused(
        &format!("{PADDLE}velocity = [1.0, 0.0]\n"),
        "give it no `fixed`, velocity or angular_velocity",
    );
    refused(
        "[[grain]]\ncenter = [0.0, 1.2]\nradius = 0.2\nturn = { about = [0.0], rate = 1.0 }\n",
        "turn's about needs two finite numbers",
    );
    // A drive faster than a grain may move in a step, as a placed grain's velocity is checked.
    refused(
        "[[grain]]\ncenter = [0.0, 1.2]\nsemi_axes = [0.5, 0.1]\nexponent = 10.0\n\
         turn = { about = [0.0, 1.2], rate = 36000.0 }\n",
        "in one step",
    );
    refused(
        "[[grain]]\ncenter = [0.0, 1.2]\nradius = 0.2\n\
         shake = { amplitude = [1.0, 0.0], frequency = 16.0 }\n",
        "in one step",
    );
    let paper = scene(PADDLE)
        .replace("model = \"soft\"", "model = \"paper\"")
        .replace("friction = 0.5\n", "");
    let e = Scene::from_toml(&paper)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("needs [solver] model = \"soft\""), "{e}");
    // Dumps: a kinematic particle without its drive, a drive of no particle, a dynamic one.
    let w = world(PADDLE);
    let good: serde_json::Value = serde_json::to_value(Dump::of(&w)).unwrap();
    let resume = |d: &serde_json::Value| {
        Dump::from_json(&d.to_string())
            .unwrap()
            .to_world()
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    resume(&good).unwrap();
    // A driven grain removed (`World::remove`) takes its drive: the dump still resumes.
    let mut gone = world(PADDLE);
    let removed = gone.remove(|b| b.kind == BodyKind::Kinematic);
    assert_eq!(removed.len(), 1);
    assert!(gone.drivers.is_empty());
    resume(&serde_json::to_value(Dump::of(&gone)).unwrap()).unwrap();
    let mut d = good.clone();
    d["drivers"] = serde_json::json!([]);
    assert!(
        resume(&d)
            .unwrap_err()
            .contains("needs its drive in \"drivers\"")
    );
    let mut d = good.clone();
    d["drivers"][0].as_object_mut().unwrap().remove("turn");
    assert!(resume(&d).unwrap_err().contains("needs `turn` or `shake`"));
    let mut d = good.clone();
    d["drivers"][0]["center"] = serde_json::json!([0.3, 1.2]);
    assert!(resume(&d).unwrap_err().contains("but the particle is"));
    let mut d = good.clone();
    d["drivers"][0]["id"] = serde_json::json!(7);
    assert!(resume(&d).unwrap_err().contains("no particle has id 7"));
    let mut d = good.clone();
    d["particles"][0].as_object_mut().unwrap().remove("kind");
    assert!(
        resume(&d)
            .unwrap_err()
            .contains("is not \"kind\": \"kinematic\"")
    );
}

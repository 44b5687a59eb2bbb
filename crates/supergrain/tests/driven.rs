//! Driven boundaries (issue 41) against closed forms: a block on a conveyor belt reaches the
//! belt's speed; a grain on a floor shaken below 1 g follows the floor; a block in a turning drum
//! is carried up to its friction angle (`tan theta = mu`) and slides there; a tumbler resumed
//! from a dump ends bit for bit where the uninterrupted run ends, on one thread and two.

mod common;

use common::resume::{dump_text, resumed};
use std::f64::consts::TAU;
use supergrain::io::Dump;
use supergrain::world::{Scene, World};

fn scene(body: &str) -> Scene {
    Scene::from_toml(&format!(
        "[box]\nleft = -6.0\nright = 6.0\nfloor = -6.0\ntop = 5.0\nfriction = 0.5\n\
         [solver]\nmodel = \"soft\"\nstep = 0.005\nsleep_radius = 0.0\n\
         [[group]]\nname = \"grains\"\ncount = 0\nradius = 0.1\nfriction = 0.5\n{body}"
    ))
    .unwrap()
}

#[test]
fn a_block_on_a_conveyor_reaches_the_belts_speed() {
    // A belt 0.2 thick, its top at y = 0, moving +x at 1.5 units/s; a block set on it at rest.
    let s = scene(
        "[[boundary]]\nsegment = [[-5.0, -0.1], [5.0, -0.1]]\nthickness = 0.2\nbelt = 1.5\n\
         [[grain]]\ncenter = [-3.0, 0.1]\nsemi_axes = [0.2, 0.1]\nexponent = 8.0\n",
    );
    let mut w = World::new(&s);
    let mut speeds = Vec::new();
    while w.step < 400 {
        w.step();
        speeds.push(w.bodies[0].velocity.x);
    }
    // Friction accelerates it at mu g = 4.9: at the belt's speed within a third of a second.
    let last = speeds[300..].iter().copied();
    for v in last {
        assert!(
            (v - 1.5).abs() < 0.02 * 1.5,
            "moves at {v}, the belt at 1.5"
        );
    }
    // And it got there at about mu g (from 0.3 s in: 1.47 from rest; allow the first contact).
    let early = speeds[20];
    assert!(
        early > 0.2 && early < 1.0,
        "at 0.1 s it moves at {early} (mu g t = 0.49)"
    );
}

#[test]
fn a_grain_on_a_floor_shaken_below_one_g_follows_the_floor() {
    // Amplitude 0.02 at 3 Hz: peak acceleration 0.02 (6 pi)^2 = 7.1 < 9.8.
    let (a, f) = (0.02, 3.0);
    let s = scene(&format!(
        "[[boundary]]\nsegment = [[-5.0, -0.1], [5.0, -0.1]]\nthickness = 0.2\n\
         shake = {{ amplitude = [0.0, {a}], frequency = {f} }}\n\
         [[grain]]\ncenter = [0.0, 0.1]\nradius = 0.1\n"
    ));
    let mut w = World::new(&s);
    let mut worst = 0.0f64;
    // Settled after half a second; then the grain's height is the floor's, up to the contact's
    // give (constant under a steady load, it varies with the floor's acceleration).
    while w.step < 800 {
        w.step();
        let t = w.time();
        let floor = a * (TAU * f * t).sin();
        if w.step > 100 {
            worst = worst.max((w.bodies[0].center.y - 0.1 - floor).abs());
        }
    }
    assert!(
        worst < 0.1 * a,
        "strayed {worst} from the floor's motion (amplitude {a})"
    );
}

#[test]
fn a_block_in_a_turning_drum_rides_up_to_its_friction_angle() {
    // A drum of radius 3 turning counter-clockwise at 2 degrees/s; a small block set on it 22
    // degrees up from the bottom, friction 0.5 with the drum. The drum carries it up until
    // gravity's pull along the surface beats friction, at atan(0.5) = 26.57 degrees; there it
    // slides and, still slower than the surface, oscillates about that angle (Coulomb
    // friction with one coefficient damps nothing) by omega / sqrt(g (cos + mu sin) / R), 1.0
    // degree at this rate (10.5 at 20 degrees/s, as measured: 18-38).
    let (x, y) = (
        2.88 * 22f64.to_radians().sin(),
        -2.88 * 22f64.to_radians().cos(),
    );
    let s = scene(&format!(
        "[[boundary]]\ncircle = {{ center = [0.0, 0.0], radius = 3.0 }}\ninside = true\n\
         turn = {{ about = [0.0, 0.0], rate = 2.0 }}\n\
         [[grain]]\ncenter = [{x}, {y}]\nangle = {}\nsemi_axes = [0.05, 0.05]\nexponent = 6.0\n\
         group = \"grains\"\n",
        22f64.to_radians()
    ));
    let mut w = World::new(&s);
    let mut angles = Vec::new();
    while w.step < 2400 {
        w.step();
        let c = w.bodies[0].center;
        // From the bottom, counter-clockwise: the drum carries it to +x.
        angles.push(c.x.atan2(-c.y).to_degrees());
    }
    let want = 0.5f64.atan().to_degrees();
    let late = &angles[1100..];
    let mean = late.iter().sum::<f64>() / late.len() as f64;
    let (lo, hi) = late
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    let delta = (0.05f64 / 2.94).atan().to_degrees();
    assert!(
        (mean - want).abs() < delta,
        "rides at {mean} degrees on average, atan(mu) = {want} (within {delta})"
    );
    assert!(
        hi - want < 1.0 + delta && want - lo < 1.0 + delta,
        "swings over {lo}..{hi} degrees about {want}"
    );
}

/// A square tumbler 4 wide turning at 25 degrees per second, 64 blocks placed in a grid.
fn tumbler() -> Scene {
    let mut text = String::from(
        "seed = 2\n[box]\nleft = -3.5\nright = 3.5\nfloor = -3.5\ntop = 3.0\n\
         [solver]\nmodel = \"soft\"\nstep = 0.005\n\
         [[boundary]]\npolyline = [[-2.0, -2.0], [2.0, -2.0], [2.0, 2.0], [-2.0, 2.0]]\n\
         closed = true\nthickness = 0.2\nturn = { about = [0.0, 0.0], rate = 25.0 }\n\
         [[group]]\ncount = 0\nsemi_axes = [0.1, 0.1]\nexponent = 8.0\n",
    );
    for i in 0..8 {
        for j in 0..8 {
            let (x, y) = (-1.5 + 0.3 * f64::from(i), -1.75 + 0.25 * f64::from(j));
            text += &format!(
                "[[grain]]\ncenter = [{x}, {y}]\nsemi_axes = [0.1, 0.1]\nexponent = 8.0\n"
            );
        }
    }
    Scene::from_toml(&text).unwrap()
}

#[test]
fn a_tumbler_resumes_bit_for_bit_on_one_thread_and_two() {
    let s = tumbler();
    assert_eq!(s.boundaries.len(), 4);
    let text = dump_text;
    let mut w = World::new(&s);
    while w.step < 300 {
        w.step();
    }
    let saved = text(&w);
    assert!(saved.contains("\"turn\""));
    while w.step < 600 {
        w.step();
    }
    // Turned 600 x 0.005 x 25 = 75 degrees: every grain still inside the box it turns.
    for b in &w.bodies {
        let p = b.center;
        let (s, c) = 75f64.to_radians().sin_cos();
        let (u, v) = (c * p.x + s * p.y, -s * p.x + c * p.y);
        assert!(
            u.abs() < 1.9 && v.abs() < 1.9,
            "a grain at {p:?} left the tumbler"
        );
    }
    let straight = text(&w);
    for threads in [1, 2] {
        assert_eq!(
            resumed(&saved, 600, threads),
            straight,
            "resumed on {threads} threads"
        );
    }
}

/// A new time step mid-run (the viewer's slider) keeps the clock running: a shaken floor goes
/// on from where it is, and a dump written after keeps the clock, resuming bit for bit.
#[test]
fn a_new_time_step_keeps_the_clock_and_the_boundaries_where_they_are() {
    let s = scene(
        "[[boundary]]\nsegment = [[-5.0, -0.1], [5.0, -0.1]]\nthickness = 0.2\n\
         shake = { amplitude = [0.0, 0.05], frequency = 1.3 }\n\
         [[grain]]\ncenter = [0.0, 0.2]\nradius = 0.1\n",
    );
    let mut w = World::new(&s);
    while w.step < 77 {
        w.step();
    }
    let (t, y) = (
        w.time(),
        w.boundaries[0].distance(supergrain::geometry::Vec2::ZERO),
    );
    w.set_step(0.003);
    w.place_boundaries();
    assert_eq!(w.time(), t, "the clock jumped");
    let y2 = w.boundaries[0].distance(supergrain::geometry::Vec2::ZERO);
    assert!((y2 - y).abs() < 1e-12, "the floor jumped from {y} to {y2}");
    w.step();
    assert!((w.time() - (t + 0.003)).abs() < 1e-12);
    let text = |w: &World| serde_json::to_string(&Dump::of(w)).unwrap();
    let saved = text(&w);
    assert!(saved.contains("\"clock\""));
    let mut resumed = Dump::from_json(&saved).unwrap().to_world().unwrap();
    assert_eq!(resumed.time(), w.time());
    for _ in 0..50 {
        w.step();
        resumed.step();
    }
    assert_eq!(text(&resumed), text(&w));
}

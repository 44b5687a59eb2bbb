//! Every dump a run writes resumes (issue 40, section 4, "the run's own dumps refused"): the
//! check that refuses grains deep in each other measures how deep they are, not how long a
//! penetration vector is, and holds sleepers of the soft model to what its step leaves.
//!
//! Before: a heap of 60 stars at rest was refused, "particles 33 and 38 overlap 1.463e-1 deep"
//! (a vector along the gradient that crossed a spike; the pair is 0.012 deep), from step 600 on;
//! 60 needles slept 0.56-0.79 of their smallest semi-axis in each other, and most of their
//! checkpoints were refused.

use serde_json::json;
use supergrain::io::Dump;
use supergrain::world::{Scene, Touch, World, checks};

/// The box (6 wide, top 6, a grain every 4 steps), 60 grains of `group`, seed 4.
fn pour(solver: &str, group: &str) -> World {
    let text = format!(
        "seed = 4\n[box]\nleft = -3.0\nright = 3.0\nfloor = 0.0\ntop = 6.0\n[spawn]\ninterval = 4\n\
         [solver]\n{solver}\n[[group]]\ncount = 60\n{group}\n"
    );
    World::new(&Scene::from_toml(&text).expect("a valid scene"))
}

const STARS: &str = "semi_axes = [[0.25, 0.4], [0.25, 0.4]]\nexponents = [[0.3, 0.6], [0.3, 0.6]]";
const NEEDLES: &str = "semi_axes = [[0.5, 0.6], [0.025, 0.03]]";

fn text(w: &World) -> String {
    serde_json::to_string(&Dump::of(w)).unwrap()
}

fn resume(saved: &str) -> World {
    Dump::from_json(saved)
        .unwrap()
        .to_world()
        .unwrap_or_else(|e| panic!("the run's own dump refused: {e}"))
}

/// Runs `w` for `steps` steps, a checkpoint every 100, each resumed; resuming the middle one and
/// running to the end gives the uninterrupted run's end, byte for byte. Returns the number of
/// sleepers at the end.
fn every_checkpoint_resumes(mut w: World, steps: u64) -> usize {
    let middle = steps / 200 * 100;
    let mut kept = None;
    while w.step < steps {
        w.step();
        if w.step.is_multiple_of(100) {
            let saved = text(&w);
            resume(&saved);
            if w.step == middle {
                kept = Some(saved);
            }
        }
    }
    let mut resumed = resume(&kept.expect("a checkpoint in the middle"));
    while resumed.step < steps {
        resumed.step();
    }
    assert!(text(&resumed) == text(&w), "the resumed run ends elsewhere");
    w.asleep()
}

#[test]
fn every_checkpoint_of_a_heap_of_stars_resumes() {
    // At rest from step 616 (a pour of 60 stars, as the run), grain by grain as the
    // issue's run slept (by islands, the soft model's default since, its trembling stars keep
    // the heap awake to step 3,701): the sleepers' overlaps are what the check refused.
    let asleep = every_checkpoint_resumes(pour("sleep_islands = false", STARS), 800);
    assert!(asleep > 50, "only {asleep} of 60 stars asleep");
}

#[test]
fn every_checkpoint_of_a_heap_of_needles_resumes() {
    // At the step the soft model's check allows them (the default, 0.01, lets a needle falling
    // from the top pass through another: 4.3 x its smallest semi-axis a step).
    let asleep =
        every_checkpoint_resumes(pour("step = 0.004\nsleep_islands = false", NEEDLES), 1200);
    assert!(asleep > 50, "only {asleep} of 60 needles asleep");
}

/// Two stars of the heap at rest, as the run left them (particles 33 and 38 at step 600), in a
/// dump of the paper's model, which holds every pair to the depth limit: the penetration vector
/// of one crosses a spike (0.146 long), the pair is 0.012 deep.
#[test]
fn a_pair_whose_penetration_vector_crosses_a_spike_is_measured_by_its_depth() {
    let star = |center: [f64; 2], angle: f64, semi_axes: [f64; 2], exponents: [f64; 2]| {
        json!({
            "center": center, "angle": angle, "semi_axes": semi_axes, "exponents": exponents,
            "velocity": [0.0, 0.0]
        })
    };
    let d = json!({
        "walls": {"left": -3.0, "right": 3.0, "floor": 0.0},
        "top": 6.0,
        "particles": [
            star(
                [-2.428947211266798, 0.7897052927680542],
                6.225162173252675,
                [0.33701332450288535, 0.36237523480934425],
                [0.41131722568024254, 0.305331345547092],
            ),
            star(
                [-2.6410707160864346, 0.992527784642544],
                5.994358020626379,
                [0.284832968467388, 0.2876417746211872],
                [0.46259630956081865, 0.4297197463287139],
            ),
        ],
    });
    let w = resume(&d.to_string());
    let mut seen = None;
    w.contacts(|t| {
        if let Touch::Grains(i, j, p) = t {
            let (a, b) = (&w.bodies[i], &w.bodies[j]);
            seen = Some((p.depth(), checks::overlap_depth(a, b, &p, 1e-4)));
        }
    });
    let (push, depth) = seen.expect("the two stars touch");
    let thin = 0.284832968467388;
    assert!(
        push > checks::DEPTH_FRACTION * thin,
        "the vector is {push} long: no longer the case this test is about"
    );
    assert!(depth < 0.05 * thin, "{depth} deep");
}

#[test]
fn the_depth_of_a_point_is_its_distance_to_the_boundary() {
    use supergrain::geometry::Vec2;
    use supergrain::shape::{Pose, Superellipse};
    // An ellipse 2 x 1 turned by 0.3, and points along its minor axis: distance 1 - t from the
    // centre's side of the boundary (the nearest boundary point of a point on the minor axis
    // within the evolute is the minor axis's end).
    let e = Superellipse::new([2.0, 1.0], [2.0, 2.0]).unwrap();
    let pose = Pose::new(Vec2::new(1.0, -2.0), 0.3).unwrap();
    let minor = Vec2::new(-(0.3f64).sin(), 0.3f64.cos());
    for t in [0.0, 0.3, 0.9, 0.99] {
        let p = pose.center() + minor * t;
        let d = e.depth_of(&pose, p, 1e-6);
        assert!(d >= 1.0 - t - 1e-12 && d <= 1.0 - t + 1e-5, "t = {t}: {d}");
    }
    // Outside: 0.
    assert_eq!(e.depth_of(&pose, pose.center() + minor * 1.01, 1e-6), 0.0);
    // A square (exponent 1000) 1 x 1 from (0.9, 0.2): 0.1 to the right side.
    let square = Superellipse::new([1.0, 1.0], [1000.0, 1000.0]).unwrap();
    let at = Pose::new(Vec2::ZERO, 0.0).unwrap();
    let d = square.depth_of(&at, Vec2::new(0.9, 0.2), 1e-6);
    assert!((d - 0.1).abs() < 1e-3, "{d}");
    // A star (exponent 0.3): from its centre the boundary is nearest along a diagonal, at
    // (s/2^(1/0.3)) (1, 1), far closer than a semi-axis.
    let star = Superellipse::new([1.0, 1.0], [0.3, 0.3]).unwrap();
    let d = star.depth_of(&at, Vec2::new(1e-9, 1e-9), 1e-6);
    let diagonal = 2f64.powf(-1.0 / 0.3) * 2f64.sqrt();
    assert!(
        d <= diagonal + 1e-9 && d > 0.5 * diagonal,
        "{d} against {diagonal}"
    );
}

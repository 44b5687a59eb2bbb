//! Boundaries in whole scenes (issue 41): a hopper of thick segments, an arc and an obstacle
//! hold every grain out of their solids; a run resumes from its dump bit for bit, on one
//! thread and two; bad `[[boundary]]` tables are refused with their line.

mod common;

use common::resume::{dump_text, resumed};
use supergrain::geometry::Vec2;
use supergrain::io::Dump;
use supergrain::shape::Boundary;
use supergrain::world::{Scene, World};

/// A V hopper (a polyline of two thick segments, open at the bottom), an arc under it catching
/// the flow, and a disk obstacle; 90 disks, ellipses and blocks poured in from the top.
const HOPPER: &str = r#"
seed = 5
[box]
left = -4.0
right = 4.0
floor = 0.0
top = 9.0
friction = 0.5
[spawn]
interval = 2
[solver]
model = "soft"
step = 0.005
[[boundary]]
polyline = [[-3.5, 7.0], [-0.45, 4.0], [-0.45, 3.6]]
thickness = 0.2
[[boundary]]
polyline = [[3.5, 7.0], [0.45, 4.0], [0.45, 3.6]]
thickness = 0.2
[[boundary]]
arc = { center = [0.0, 3.0], radius = 2.5, from = 200, to = 340 }
thickness = 0.15
[[boundary]]
circle = { center = [2.6, 1.0], radius = 0.5 }
inside = false
[[group]]
count = 40
radius = [0.1, 0.15]
[[group]]
count = 30
semi_axes = [[0.12, 0.18], [0.06, 0.09]]
[[group]]
count = 20
semi_axes = [[0.1, 0.14], [0.1, 0.14]]
exponent = 6.0
"#;

#[test]
fn a_hopper_holds_its_grains_and_resumes_bit_for_bit() {
    let scene = Scene::from_toml(HOPPER).unwrap();
    // Two polylines of two segments, an arc, a circle.
    assert_eq!(scene.boundaries.len(), 6);
    assert_eq!(scene.boundary_names[1], "boundary 1, segment 2");
    let mut w = World::new(&scene);
    let mut deepest = 0.0f64;
    let mut saved = None;
    while w.step < 700 {
        w.step();
        for b in &w.bodies {
            // No grain's centre ever inside a solid, and no grain deeper in one than a few
            // hundredths of its size (the contacts' give).
            for boundary in &w.boundaries {
                let g = boundary.distance(b.center);
                assert!(g > 0.0, "step {}: a centre in {boundary:?}", w.step);
                let reach = b.shape.bounding_radius();
                if g < reach {
                    let c = b.wall_contact(boundary, &w.settings.narrow());
                    if let Some(p) = c.penetration {
                        deepest = deepest.max(p.push.norm() / b.shape.min_semi_axis());
                    }
                }
            }
        }
        if w.step == 350 {
            saved = Some(dump_text(&w));
        }
    }
    assert!(
        deepest < 0.25,
        "a grain {deepest} of its thickness into a boundary"
    );
    // Grains reached the arc under the hopper's mouth: the flow went through.
    let below = w.bodies.iter().filter(|b| b.center.y < 3.6).count();
    assert!(below > 10, "{below} grains under the hopper");
    let saved = saved.unwrap();
    assert!(saved.contains("\"boundaries\""));
    let straight = dump_text(&w);
    for threads in [1, 2] {
        assert_eq!(
            resumed(&saved, 700, threads),
            straight,
            "resumed on {threads} threads"
        );
    }
}

#[test]
fn a_dump_keeps_every_boundary_bit_for_bit() {
    let scene = Scene::from_toml(HOPPER).unwrap();
    let w = World::new(&scene);
    let back = Dump::from_json(&dump_text(&w)).unwrap().to_world().unwrap();
    assert_eq!(back.boundaries, w.boundaries);
    // An arc given by `to` is kept as its sweep: 340 - 200.
    match w.boundaries[4] {
        Boundary::Arc { from, sweep, .. } => assert_eq!((from, sweep), (200.0, 140.0)),
        other => panic!("not an arc: {other:?}"),
    }
    assert!(w.boundaries[5].distance(Vec2::new(2.6, 1.0)) < 0.0);
}

fn refused(table: &str) -> String {
    let text = format!(
        "[box]\nleft = -2.0\nright = 2.0\nfloor = 0.0\ntop = 5.0\n[solver]\nmodel = \"soft\"\n\
         [[group]]\ncount = 3\nradius = 0.1\n{table}"
    );
    Scene::from_toml(&text).unwrap_err().to_string()
}

#[test]
fn bad_boundaries_are_refused_with_their_line() {
    let e = refused("[[boundary]]\nsegment = [[0.0, 1.0], [1.0, 1.0]]\n");
    assert!(
        e.contains("line 11") && e.contains("needs a thickness"),
        "{e}"
    );
    let e = refused(
        "[[boundary]]\nsegment = [[0.0, 1.0], [1.0, 1.0]]\narc = { center = [0.0, 0.0], radius = 1.0, from = 0, to = 90 }\nthickness = 0.1\n",
    );
    assert!(e.contains("segment and arc"), "{e}");
    let e = refused("[[boundary]]\ncircle = { center = [0.0, 0.0], radius = 1.0 }\n");
    assert!(e.contains("inside = true"), "{e}");
    let e = refused("[[boundary]]\npolyline = [[0.0, 1.0]]\nthickness = 0.1\n");
    assert!(e.contains("at least 2 points"), "{e}");
    let e = refused("[[boundary]]\nsegment = [[0.0, 1.0], [1.0, 1.0, 2.0]]\nthickness = 0.1\n");
    assert!(e.contains("two numbers"), "{e}");
    let e = refused("[[boundary]]\nsegment = [[0.0, 1.0], [1.0, 1.0]]\nthickness = -0.1\n");
    assert!(e.contains("thickness"), "{e}");
    // A segment across the line where grains appear, by the queue's rule.
    let e = refused(
        "[spawn]\nrule = \"queue\"\n[[boundary]]\nsegment = [[-1.0, 5.0], [1.0, 5.0]]\nthickness = 0.1\n",
    );
    assert!(e.contains("boundary 1 reaches within"), "{e}");
    // The paper's projection has the box alone.
    let text = "[box]\nleft = -2.0\nright = 2.0\nfloor = 0.0\ntop = 5.0\n[solver]\nmodel = \"paper\"\n\
                [[group]]\ncount = 3\n\
                radius = 0.1\n[[boundary]]\ncircle = { center = [0.0, 2.0], radius = 0.5 }\n\
                inside = false\n";
    let e = Scene::from_toml(text).unwrap_err().to_string();
    assert!(e.contains("[[boundary]] needs [solver] model"), "{e}");
}

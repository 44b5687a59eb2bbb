//! Grains placed by the scene file (`[[grain]]`, issue 41): a state set up without editing a
//! dump, checked against closed forms that share nothing with the solver.

use supergrain::body::BodyId;
use supergrain::world::{Scene, SceneError, World};

const G: f64 = 9.8;

/// A box 10 wide with `grains` placed and no group drawn, `model = "soft"`.
fn scene(extra: &str) -> Result<Scene, SceneError> {
    Scene::from_toml(&format!(
        "[box]\nleft = -5.0\nright = 5.0\nfloor = 0.0\ntop = 4.0\nfriction = 0.5\n\
         [solver]\nmodel = \"soft\"\n{extra}"
    ))
}

/// A block (exponent 20, 0.4 by 0.2) launched along the floor at 2 units/s, friction 0.5 on
/// both sides (mixed: 0.5): it decelerates at `mu g` and stops after `v^2 / (2 mu g)`.
#[test]
fn a_placed_block_launched_along_the_floor_stops_where_friction_says() {
    let s = scene(
        "[[group]]\nname = \"blocks\"\ncount = 0\nradius = 0.1\nfriction = 0.5\n\
         [[grain]]\ncenter = [-2.0, 0.1]\nsemi_axes = [0.2, 0.1]\nexponent = 20.0\n\
         velocity = [2.0, 0.0]\ngroup = \"blocks\"\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let mut w = World::new(&s);
    assert_eq!(w.bodies.len(), 1);
    assert_eq!(w.bodies[0].id, BodyId(0));
    let start = w.bodies[0].center.x;
    while w.step < 200 {
        w.step();
    }
    let (v, mu) = (2.0, 0.5);
    let expected = v * v / (2.0 * mu * G);
    let slid = w.bodies[0].center.x - start;
    assert!(
        (slid - expected).abs() < 0.02 * expected,
        "slid {slid}, closed form {expected}"
    );
    assert!(w.bodies[0].velocity.norm() < 1e-6, "still moving");
}

/// A disk placed at rest `h` above the floor lands after `sqrt(2 h / g)`, and one thrown
/// sideways keeps its horizontal speed in flight.
#[test]
fn placed_disks_fall_as_a_free_fall_says() {
    let s = scene(
        "[[grain]]\ncenter = [0.0, 2.3]\nradius = 0.3\n\
         [[grain]]\ncenter = [-3.0, 3.0]\nradius = 0.2\nvelocity = [1.5, 0.0]\n",
    )
    .expect("a valid scene");
    let mut w = World::new(&s);
    let h = 2.0;
    let landing = (2.0 * h / G).sqrt();
    let mut landed = None;
    while landed.is_none() && w.step < 200 {
        w.step();
        if w.bodies[0].center.y <= 0.3 + 1e-3 {
            landed = Some(w.step as f64 * 0.01);
        }
    }
    let t = landed.expect("it lands");
    assert!(
        (t - landing).abs() <= 0.011,
        "landed at {t}, free fall {landing}"
    );
    let vx = w.bodies[1].velocity.x;
    assert!((vx - 1.5).abs() < 1e-12, "the thrown disk's speed {vx}");
}

/// Each refusal names the grain, its line and what is wrong.
#[test]
fn placed_grains_that_cannot_be_there_are_refused_with_their_line() {
    let cases = [
        (
            "[[grain]]\ncenter = [4.9, 1.0]\nradius = 0.3\n",
            "line 9: grain 1: reaches 0.2 beyond the box",
        ),
        (
            "[[grain]]\ncenter = [0.0, 1.0]\nradius = 0.3\n\
             [[grain]]\ncenter = [0.5, 1.0]\nsemi_axes = [0.3, 0.1]\n",
            "line 12: grain 2: overlaps grain 1 (line 9)",
        ),
        (
            "[[grain]]\ncenter = [0.0, 1.0]\nradius = 0.3\ngroup = \"sand\"\n",
            "grain 1: no [[group]] is named `sand` (the groups: none)",
        ),
        (
            "[[grain]]\ncenter = [0.0, 1.0]\nradius = 0.3\nsemi_axes = [0.3, 0.2]\n",
            "line 9: grain 1: give either `radius`",
        ),
        (
            "[[grain]]\ncenter = [0.0, 1.0, 2.0]\nradius = 0.3\n",
            "grain 1: center needs two numbers [x, y], got 3",
        ),
        (
            "[[grain]]\ncenter = [0.0, 1.0]\nradius = 0.05\nvelocity = [50.0, 0.0]\n",
            "grain 1: its velocity moves it 0.5 in one step",
        ),
    ];
    for (grains, wanted) in cases {
        let e = scene(grains).expect_err("refused").to_string();
        assert!(e.contains(wanted), "wanted {wanted:?}, got {e:?}");
    }
}

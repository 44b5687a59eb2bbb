//! Static bodies (issue 41, "one body model"): a grain placed with `fixed = true` never moves,
//! holds what rests on it as a wall does, joins no island, and stays out of the sinks. Two of
//! them, blocky planks with a gap between, make a silo's floor with an orifice, through which a
//! poured heap discharges into a sink.

use supergrain::body::BodyKind;
use supergrain::io::Dump;
use supergrain::world::{Scene, World};

/// A silo 4 wide: planks (exponent 50, 1.7 by 0.2) from either wall to an orifice `gap` wide at
/// height 1, disks of radius 0.1-0.14 poured onto them, a sink under the orifice; `solver`
/// added to `[solver]`.
fn silo(gap: f64, solver: &str) -> World {
    let half = 0.5 * (4.0 - gap) / 2.0;
    let text = format!(
        "seed = 1\n[box]\nleft = -2.0\nright = 2.0\nfloor = 0.0\ntop = 6.0\n\
         [spawn]\ninterval = 3\n[solver]\nmodel = \"soft\"\n{solver}\n\
         [[group]]\ncount = 120\nradius = [0.1, 0.14]\n\
         [[grain]]\ncenter = [{l}, 1.0]\nsemi_axes = [{half}, 0.1]\nexponent = 50.0\nfixed = true\n\
         [[grain]]\ncenter = [{r}, 1.0]\nsemi_axes = [{half}, 0.1]\nexponent = 50.0\nfixed = true\n\
         [[sink]]\nregion = [[-2.0, 2.0], [0.0, 0.6]]\n",
        l = -2.0 + half,
        r = 2.0 - half,
    );
    World::new(&Scene::from_toml(&text).unwrap_or_else(|e| panic!("{e}")))
}

/// Whether `p` lies inside plank `k` (its shape's implicit function, independently evaluated
/// here: `|x/a|^e + |y/b|^e < 1`).
fn in_plank(w: &World, k: usize, p: supergrain::geometry::Vec2) -> bool {
    let b = &w.bodies[k];
    let [a, h] = [b.shape.semi_axes().x, b.shape.semi_axes().y];
    let d = p - b.center;
    (d.x / a).abs().powf(50.0) + (d.y / h).abs().powf(50.0) < 1.0
}

#[test]
fn a_silo_of_fixed_planks_discharges_through_its_orifice_and_the_planks_never_move() {
    let mut w = silo(0.8, "");
    let planks: Vec<_> = w.bodies[..2].to_vec();
    assert!(planks.iter().all(|b| b.kind == BodyKind::Static));
    let mut through = 0;
    while w.step < 2500 {
        w.step();
        assert_eq!(
            &w.bodies[..2],
            &planks[..],
            "step {}: a plank moved",
            w.step
        );
        for b in &w.bodies[2..] {
            for k in 0..2 {
                assert!(
                    !in_plank(&w, k, b.center),
                    "step {}: grain {} is inside plank {k}",
                    w.step,
                    b.id
                );
            }
        }
        through = w.sinks[0].grains;
        assert_eq!(
            w.next_id().0,
            w.bodies.len() as u64 + through,
            "grains conserved"
        );
    }
    // Most of the grains went through the orifice (7 grain diameters wide) into the sink.
    assert!(through >= 100, "{through} of 120 discharged");
}

/// A heap resting on fixed planks with no orifice falls asleep by islands: a static body in
/// an island would keep it awake for good (its calm count never runs).
#[test]
fn a_heap_on_fixed_planks_falls_asleep_by_islands() {
    let mut w = silo(0.0, "");
    while !(w.all_spawned() && w.asleep() == w.bodies.len() - 2) {
        assert!(
            w.step < 4000,
            "not asleep by step 4000: {} of {} grains",
            w.asleep(),
            w.bodies.len() - 2
        );
        w.step();
        let inside = w.bodies[2..]
            .iter()
            .any(|b| in_plank(&w, 0, b.center) || in_plank(&w, 1, b.center));
        assert!(!inside, "step {}: a grain is inside a plank", w.step);
    }
    assert_eq!(w.sinks[0].grains, 0, "nothing passes a closed floor");
}

/// With sleeping off a fixed body still never moves, and a dump keeps it static: resumed, the
/// run ends where the uninterrupted one ends.
#[test]
fn a_fixed_body_holds_with_sleep_off_and_resumes_static() {
    let mut w = silo(0.8, "sleep_radius = 0.0");
    let planks: Vec<_> = w.bodies[..2].to_vec();
    while w.step < 400 {
        w.step();
    }
    assert_eq!(&w.bodies[..2], &planks[..]);
    let saved = serde_json::to_string(&Dump::of(&w)).unwrap();
    assert_eq!(saved.matches("\"kind\":\"static\"").count(), 2);
    let mut resumed = Dump::from_json(&saved).unwrap().to_world().unwrap();
    for world in [&mut w, &mut resumed] {
        while world.step < 700 {
            world.step();
        }
    }
    let end = |w: &World| serde_json::to_string(&Dump::of(w)).unwrap();
    assert!(end(&w) == end(&resumed), "the resumed run ends elsewhere");
    assert_eq!(&resumed.bodies[..2], &planks[..]);
}

/// A fixed grain given a velocity is refused, naming the grain.
#[test]
fn a_fixed_grain_with_a_velocity_is_refused() {
    let e = Scene::from_toml(
        "[box]\nleft = -2.0\nright = 2.0\nfloor = 0.0\ntop = 6.0\n\
         [[grain]]\ncenter = [0.0, 1.0]\nradius = 0.3\nfixed = true\nvelocity = [1.0, 0.0]\n",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("grain 1: a fixed grain never moves"), "{e}");
}

/// Pictures draw the fixed bodies in the walls' colour and each sink's outline in its own.
#[test]
fn pictures_draw_fixed_bodies_as_walls_and_the_sinks() {
    use supergrain::render::{SINK_COLOUR, Style, WALL_COLOUR, render_world};
    let count = |w: &World, colour: [u8; 4]| {
        let style = Style {
            width: 200,
            ..Style::default()
        };
        render_world(w, &style)
            .pixels()
            .iter()
            .filter(|p| [p.red(), p.green(), p.blue()] == colour[..3])
            .count()
    };
    let w = silo(0.8, "");
    let mut plain = silo(0.8, "");
    for b in &mut plain.bodies {
        b.kind = BodyKind::Dynamic;
    }
    plain.sinks.clear();
    // Two planks 1.6 x 0.2 in a picture 200 px across 8.4 units: about 24 px each at least.
    let (walls, walls_plain) = (count(&w, WALL_COLOUR), count(&plain, WALL_COLOUR));
    assert!(
        walls >= walls_plain + 2 * 24 * 4,
        "{walls} against {walls_plain}"
    );
    assert!(count(&w, SINK_COLOUR) > 100, "the sink's outline");
    assert_eq!(count(&plain, SINK_COLOUR), 0);
}

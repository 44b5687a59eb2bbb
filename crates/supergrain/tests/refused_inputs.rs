//! Scenes and dumps that would run wrong physics, or none, are refused before any work, with an
//! error naming the key and where (issue 40, section 4, "wrong or silent physics", and section
//! 5's first item). Each of these was accepted before, and went wrong later: NaN, grains
//! through the floor or asleep in the air, a plane dumped as `[null, null]`, settings that did
//! nothing.

use serde_json::{Value, json};
use supergrain::io::Dump;
use supergrain::world::{Scene, World};

/// A box 6 wide, top 6, and `extra` lines (tables after `[solver]`'s keys).
fn scene(solver: &str, extra: &str) -> String {
    format!(
        "seed = 2\n[box]\nleft = -3.0\nright = 3.0\nfloor = 0.0\ntop = 6.0\n[solver]\n{solver}\n\
         {extra}\n[[group]]\nname = \"stones\"\ncount = 8\nradius = 0.3\n"
    )
}

fn refused(text: &str) -> String {
    match Scene::from_toml(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

fn accepted(text: &str) -> Scene {
    Scene::from_toml(text).unwrap_or_else(|e| panic!("refused: {e}\n{text}"))
}

/// A soft-model heap of 8 disks after 150 steps (contacts kept, a queue still to appear), as
/// JSON.
fn soft_dump() -> Value {
    let text = "seed = 3\n[box]\nleft = -2.0\nright = 2.0\nfloor = 0.0\ntop = 4.0\n[spawn]\n\
                interval = 15\n[[group]]\ncount = 12\nradius = 0.3\n";
    let mut w = World::new(&Scene::from_toml(text).unwrap());
    for _ in 0..150 {
        w.step();
    }
    let d = serde_json::to_value(Dump::of(&w)).unwrap();
    assert!(
        !d["contacts"].as_array().unwrap().is_empty(),
        "no contact kept"
    );
    assert!(!d["queue"].is_null(), "nothing still to appear");
    d
}

fn to_world(d: &Value) -> Result<World, String> {
    serde_json::from_value::<Dump>(d.clone())
        .map_err(|e| e.to_string())?
        .to_world()
        .map_err(|e| e.to_string())
}

fn refused_dump(d: &Value) -> String {
    match to_world(d) {
        Ok(_) => panic!("dump accepted"),
        Err(e) => e,
    }
}

#[test]
fn a_plane_normal_too_short_to_scale_is_refused() {
    // [1e-310, 0]: 1 / 1e-310 overflows, and the normal was dumped as [null, null].
    let e = refused(&scene(
        "",
        "[[plane]]\nnormal = [1e-310, 0.0]\npoint = [0.0, 1.0]",
    ));
    assert!(
        e.contains("line 10") && e.contains("plane 1") && e.contains("normal"),
        "{e}"
    );
    // Short but scalable is a plane like any other.
    accepted(&scene(
        "",
        "[[plane]]\nnormal = [1e-200, 2e-200]\npoint = [0.0, 1.0]",
    ));
    let mut d = soft_dump();
    d["planes"] = json!([{"normal": [1e-310, 0.0], "offset": 0.0}]);
    let e = refused_dump(&d);
    assert!(e.contains("planes[0]") && e.contains("wall normal"), "{e}");
}

#[test]
fn a_plane_vector_of_three_numbers_is_refused_naming_the_key() {
    // [0, 1, 2] dropped its third number.
    let e = refused(&scene(
        "",
        "[[plane]]\nnormal = [0.0, 1.0, 2.0]\npoint = [0.0, 1.0]",
    ));
    assert!(
        e.contains("line 10")
            && e.contains("plane 1: normal needs two numbers")
            && e.contains("got 3"),
        "{e}"
    );
    let e = refused(&scene("", "[[plane]]\nnormal = [0.0, 1.0]\npoint = [0.0]"));
    assert!(e.contains("plane 1: point needs two numbers"), "{e}");
}

#[test]
fn a_plane_over_the_places_grains_appear_is_refused() {
    // Solid above y = 5 (normal down): the whole band under the top, by either rule.
    let ceiling = "[[plane]]\nnormal = [0.0, -1.0]\npoint = [0.0, 5.0]";
    for rule in ["fair", "queue"] {
        let e = refused(&scene(
            "",
            &format!("[spawn]\nrule = \"{rule}\"\n{ceiling}"),
        ));
        assert!(
            e.contains("plane 1") && e.contains("grains appear"),
            "{rule}: {e}"
        );
    }
    // Solid below y = 8: the whole box.
    let e = refused(&scene(
        "",
        "[[plane]]\nnormal = [0.0, 1.0]\npoint = [0.0, 8.0]",
    ));
    assert!(e.contains("plane 1 covers every place"), "{e}");
    // A slope reaching the top at the left wall: grains appear in it by the queue rule; the
    // fair rule offers them other places.
    let slope = "[[plane]]\nnormal = [1.0, 1.0]\npoint = [-2.0, 6.0]";
    let e = refused(&scene("", &format!("[spawn]\nrule = \"queue\"\n{slope}")));
    assert!(
        e.contains("plane 1 reaches") && e.contains("rule = \"fair\""),
        "{e}"
    );
    accepted(&scene("", &format!("[spawn]\nrule = \"fair\"\n{slope}")));
    // A floor raised to y = 2 leaves the top free.
    accepted(&scene(
        "",
        "[[plane]]\nnormal = [0.0, 1.0]\npoint = [0.0, 2.0]",
    ));
    // And in a dump with grains still to appear.
    let mut d = soft_dump();
    d["planes"] = json!([{"normal": [0.0, 1.0], "offset": 8.0}]);
    let e = refused_dump(&d);
    assert!(
        e.contains("planes[0]") && e.contains("covers every place"),
        "{e}"
    );
}

#[test]
fn a_dump_that_does_not_say_its_model_is_refused_or_read_as_the_papers() {
    let mut d = soft_dump();
    assert_eq!(d["solver"]["model"], "soft");
    d["solver"].as_object_mut().unwrap().remove("model");
    let e = refused_dump(&d);
    assert!(
        e.contains("model is missing") && e.contains("`sleep_islands`, which only model \"soft\""),
        "{e}"
    );
    // The paper's dumps say so now; one from before the key still reads as the paper's.
    let mut w = World::new(&Scene::preset("circles").unwrap());
    for _ in 0..50 {
        w.step();
    }
    let mut d = serde_json::to_value(Dump::of(&w)).unwrap();
    assert_eq!(d["solver"]["model"], "paper");
    d["solver"].as_object_mut().unwrap().remove("model");
    assert_eq!(
        to_world(&d).unwrap().settings.model,
        supergrain::settings::Model::Paper
    );
}

#[test]
fn a_density_whose_mass_is_not_a_workable_number_is_refused() {
    for density in ["1e308", "1e-306", "1e150"] {
        let text = scene("", "").replace(
            "radius = 0.3",
            &format!("radius = 0.3\ndensity = {density}"),
        );
        let e = refused(&text);
        assert!(
            e.contains("group `stones`") && e.contains("density") && e.contains("mass"),
            "{density}: {e}"
        );
    }
    accepted(&scene("", "").replace("radius = 0.3", "radius = 0.3\ndensity = 1e20"));
    let mut d = soft_dump();
    d["materials"][0]["density"] = json!(1e308);
    let e = refused_dump(&d);
    assert!(e.contains("particle 0") && e.contains("mass"), "{e}");
}

#[test]
fn a_dump_with_gravity_upwards_is_refused_as_a_scene_is() {
    let e = refused(&scene("gravity = -9.8", ""));
    assert!(
        e.contains("gravity") || e.contains("expected a finite number >= 0"),
        "{e}"
    );
    let mut d = soft_dump();
    d["solver"]["gravity"] = json!(-9.8);
    let e = refused_dump(&d);
    assert!(
        e.contains("gravity must be a finite number, 0 or more, got -9.8"),
        "{e}"
    );
    d["solver"]["gravity"] = json!(0.0);
    to_world(&d).unwrap();
}

#[test]
fn impulses_no_heap_could_give_are_refused() {
    let mut d = soft_dump();
    d["contacts"][0]["normal_impulse"] = json!([1e300, 0.0, 0.0]);
    let e = refused_dump(&d);
    assert!(
        e.contains("contacts[0]") && e.contains("impulse of 1.000e300"),
        "{e}"
    );
    let mut d = soft_dump();
    d["contacts"][0]["rolling_impulse"] = json!(-1e300);
    assert!(refused_dump(&d).contains("contacts[0]"));
    // The run's own are far below the limit (the dump resumes, as every other here).
    to_world(&soft_dump()).unwrap();
}

#[test]
fn a_contact_listed_twice_is_refused() {
    let mut d = soft_dump();
    let contacts = d["contacts"].as_array_mut().unwrap();
    let first = contacts[0].clone();
    contacts.push(first);
    let n = contacts.len() - 1;
    let e = refused_dump(&d);
    assert!(
        e.contains(&format!("contacts[{n}]")) && e.contains("the same contact as contacts[0]"),
        "{e}"
    );
}

#[test]
fn a_quadtree_tolerance_coarser_than_the_grains_is_refused() {
    // eps = 1e308: every pair's region was one cell, and grains fell through each other.
    for eps in ["1e308", "0.04"] {
        let e = refused(&scene(&format!("eps = {eps}"), ""));
        assert!(
            e.contains("eps") && e.contains("smallest semi-axis (0.3)"),
            "{e}"
        );
    }
    accepted(&scene("eps = 0.03", ""));
    let mut d = soft_dump();
    d["solver"]["eps"] = json!(1e308);
    assert!(refused_dump(&d).contains("eps"));
}

#[test]
fn a_sleep_radius_wider_than_a_grain_is_refused() {
    // 1e308 put grains to sleep in the air.
    for r in ["1e308", "0.31"] {
        let e = refused(&scene(&format!("sleep_radius = {r}"), ""));
        assert!(
            e.contains("sleep_radius") && e.contains("smallest semi-axis"),
            "{r}: {e}"
        );
    }
    accepted(&scene("sleep_radius = 0.3", ""));
    // In a dump (where `run --resume --sleep-radius` puts the flag's value).
    let mut d = soft_dump();
    d["solver"]["sleep_radius"] = json!(1e308);
    assert!(refused_dump(&d).contains("sleep_radius"));
}

#[test]
fn the_soft_models_time_step_takes_no_damping() {
    // The soft step ignores `damping` (the paper's): step 0.07 with damping 0.99 was accepted,
    // and a falling plate went through resting disks and the floor.
    let e = refused(&scene("step = 0.07\ndamping = 0.99", ""));
    assert!(
        e.contains("step = 0.07") && e.contains("model = \"soft\""),
        "{e}"
    );
    // The paper's Verlet fall is damped: there it is slow enough.
    accepted(&scene("model = \"paper\"\nstep = 0.07\ndamping = 0.99", ""));
    // A free fall from 6 moves 0.109 a step at 0.01, under twice the radius: accepted.
    accepted(&scene("", ""));
    let mut d = soft_dump();
    d["solver"]["step"] = json!(0.07);
    d["solver"]["damping"] = json!(0.99);
    assert!(refused_dump(&d).contains("step = 0.07"));
}

#[test]
fn a_material_key_the_papers_model_ignores_is_refused_naming_it() {
    for key in [
        "friction = 0.5",
        "restitution = 0.5",
        "rolling_resistance = 0.1",
        "density = 2.0",
    ] {
        let name = key.split(' ').next().unwrap();
        let in_group =
            scene("model = \"paper\"", "").replace("radius = 0.3", &format!("radius = 0.3\n{key}"));
        let e = refused(&in_group);
        assert!(
            e.contains("line 14")
                && e.contains("group `stones`")
                && e.contains(&format!("`{name}`"))
                && e.contains("model = \"paper\""),
            "{key}: {e}"
        );
        let in_box =
            scene("model = \"paper\"", "").replace("top = 6.0", &format!("top = 6.0\n{key}"));
        let e = refused(&in_box);
        assert!(
            e.contains("line 7") && e.contains("box") && e.contains(&format!("`{name}`")),
            "{key}: {e}"
        );
        // The soft model uses them.
        accepted(&in_group.replace("model = \"paper\"", "model = \"soft\""));
    }
}

/// Issue 40: `slop = 1` was accepted, and contacts held the grains a unit deep in each other and
/// in the floor. A slop deeper than half the smallest semi-axis is refused, naming the key, in
/// scenes and in dumps (the paper model's slop and the soft model's alike).
#[test]
fn a_slop_deeper_than_half_a_grain_is_refused() {
    for s in ["1", "0.16"] {
        let e = refused(&scene(&format!("slop = {s}"), ""));
        assert!(
            e.contains("slop") && e.contains("smallest semi-axis"),
            "{s}: {e}"
        );
    }
    accepted(&scene("slop = 0.15", ""));
    let mut d = soft_dump();
    d["solver"]["slop"] = json!(1.0);
    assert!(refused_dump(&d).contains("slop"));
}

/// Boundaries are the soft model's: a dump of the paper's model that holds one is refused, not
/// run with the boundary silently left out; a bad boundary in a dump is refused naming it.
#[test]
fn a_dumps_boundaries_are_checked_and_the_paper_model_refuses_them() {
    let mut d = soft_dump();
    d["boundaries"] = json!([{"segment": [[-1.0, 1.0], [1.0, 1.5]], "thickness": 0.1}]);
    assert!(to_world(&d).is_ok());
    let mut paper = d.clone();
    paper["solver"]["model"] = json!("paper");
    // The soft step's other parts out, so that the boundary is what is refused.
    let solver = paper["solver"].as_object_mut().unwrap();
    for key in supergrain::settings::SOFT_KEYS {
        solver.remove(*key);
    }
    for key in ["materials", "wall_material", "contacts"] {
        paper.as_object_mut().unwrap().remove(key);
    }
    let e = refused_dump(&paper);
    assert!(
        e.contains("boundaries[0]") && e.contains("soft model"),
        "{e}"
    );
    d["boundaries"] = json!([{"segment": [[-1.0, 1.0], [1.0, 1.5]]}]);
    let e = refused_dump(&d);
    assert!(
        e.contains("boundaries[0]") && e.contains("needs a thickness"),
        "{e}"
    );
    d["boundaries"] = json!([{"segment": [[-1.0, 1.0], [1.0, 1.5]], "thickness": 0.1, "clock": 3}]);
    let e = refused_dump(&d);
    assert!(e.contains("clock"), "{e}");
}

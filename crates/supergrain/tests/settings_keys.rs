//! The solver settings are one type (issue 41, "Settings as one type"): a scene's `[solver]`,
//! a dump's `solver`, the viewer's sliders and `run --set` read them through one table of keys.
//! Checked here against ranges and fields written out again by hand, sharing nothing with that
//! table: every key out of its range is refused by the scene (at its line), by the dump and by
//! `Settings::validate`; every key reaches its own field; a dump gives back every key; dumps
//! of the old form (the soft step's keys in a `soft` table of their own) still resume; and the
//! README's scene reference shows every key.

use supergrain::broad_phase::Kind as BroadPhase;
use supergrain::contact::NarrowPhase;
use supergrain::io::Dump;
use supergrain::settings::{Model, Rotation, Settings, SolverTable};
use supergrain::subdivision::Precision;
use supergrain::world::{Scene, World};

/// Every key, a value out of its documented range (README, scene reference), and a value in it
/// other than the default.
const KEYS: &[(&str, &str, &str)] = &[
    ("step", "-0.01", "0.005"),
    ("damping", "1.0", "0.25"),
    ("gravity", "-9.8", "4.5"),
    ("max_iterations", "-1", "7"),
    ("slop", "-0.001", "0.002"),
    ("sleep_radius", "nan", "0.003"),
    ("sleep_steps", "-5", "77"),
    ("sleep_islands", "1", "false"),
    ("shock_propagation", "\"yes\"", "true"),
    ("strip_width", "-1.0", "3.5"),
    ("depth", "17", "9"),
    ("eps", "-0.1", "0.001"),
    ("rotation", "\"spin\"", "\"inertia\""),
    ("narrow_phase", "\"newton\"", "\"quadtree\""),
    ("broad_phase", "\"tree\"", "\"all-pairs\""),
    ("model", "\"rigid\"", "\"soft\""),
    ("substeps", "65", "6"),
    ("contact_hertz", "0.0", "45.0"),
    ("damping_ratio", "-1.0", "2.5"),
    ("push_out", "0.0", "1.5"),
    ("restitution_threshold", "-0.5", "0.75"),
    ("linear_damping", "inf", "0.2"),
    ("angular_damping", "-0.2", "0.3"),
    ("carry_reach", "-1e-4", "2e-4"),
    ("max_overlap", "1.5", "0.02"),
];

/// A box 8 wide, 20 circles, and `[solver]` with `lines` from line 9 on.
fn scene(lines: &str) -> String {
    format!(
        "seed = 1\nsteps = 20\n[box]\nleft = -4.0\nright = 4.0\nfloor = 0.0\ntop = 12.0\n\
         [solver]\n{lines}\n[[group]]\ncount = 20\nradius = [0.2, 0.3]\n"
    )
}

#[test]
fn the_table_here_names_every_key() {
    let here: Vec<&str> = KEYS.iter().map(|k| k.0).collect();
    assert_eq!(
        here,
        SolverTable::KEYS,
        "a key was added or renamed: give it a bad and a good value here"
    );
}

#[test]
fn a_key_out_of_its_range_is_refused_by_the_scene_at_its_line() {
    for (key, bad, _) in KEYS {
        // `model` first: the other keys are read under the soft model, where all of them work.
        let text = scene(&format!("model = \"soft\"\n{key} = {bad}"));
        let text = if *key == "model" {
            scene(&format!("{key} = {bad}"))
        } else {
            text
        };
        let e = match Scene::from_toml(&text) {
            Ok(_) => panic!("{key} = {bad} accepted"),
            Err(e) => e.to_string(),
        };
        let line = if *key == "model" { 9 } else { 10 };
        assert!(
            e.contains(&format!("line {line}")) || e.contains(&format!("\n{line} | ")),
            "{key} = {bad}: the error does not point at line {line}:\n{e}"
        );
        assert!(e.contains(key), "{key} = {bad}: not named:\n{e}");
    }
}

#[test]
fn a_key_out_of_its_range_is_refused_by_the_dump_and_by_validate() {
    let world = World::new(&Scene::from_toml(&scene("model = \"soft\"")).unwrap());
    let good: serde_json::Value = serde_json::to_value(Dump::of(&world)).unwrap();
    for (key, bad, _) in KEYS {
        if *key == "max_overlap" {
            continue; // a scene's alone: see below
        }
        let mut d = good.clone();
        // JSON has no nan or inf: those are written as the numbers serde_json reads them as.
        let bad_json: serde_json::Value = match *bad {
            "nan" | "inf" => serde_json::json!(null),
            v => serde_json::from_str(&v.replace('\'', "\"")).unwrap(),
        };
        d["solver"][key] = bad_json;
        let refused = Dump::from_json(&d.to_string())
            .map_err(|e| e.to_string())
            .and_then(|dump| dump.to_world().map(|_| ()).map_err(|e| e.to_string()));
        let e = refused.expect_err(&format!("a dump with {key} = {bad} resumed"));
        assert!(e.contains(key), "{key} = {bad}: not named: {e}");
    }
    // Built in a program, the same nonsense is refused by validate, naming the key.
    let s = Settings::soft();
    for (bad, key) in [
        (
            Settings {
                step: f64::NAN,
                ..s
            },
            "step",
        ),
        (Settings { damping: 1.0, ..s }, "damping"),
        (Settings { gravity: -1.0, ..s }, "gravity"),
        (Settings { slop: -1e-3, ..s }, "slop"),
        (
            Settings {
                sleep_radius: f64::INFINITY,
                ..s
            },
            "sleep_radius",
        ),
        (
            Settings {
                strip_width: -1.0,
                ..s
            },
            "strip_width",
        ),
        (
            Settings {
                sleep_islands: true,
                model: Model::Paper,
                ..s
            },
            "sleep_islands",
        ),
    ] {
        let e = bad.validate().expect_err(key);
        assert!(e.contains(key), "{key}: {e}");
    }
    let soft = |f: fn(&mut supergrain::settings::SoftSettings)| {
        let mut t = s;
        f(&mut t.soft);
        t.validate()
    };
    assert!(soft(|k| k.substeps = 0).unwrap_err().contains("substeps"));
    assert!(soft(|k| k.substeps = 65).unwrap_err().contains("substeps"));
    assert!(
        soft(|k| k.contact_hertz = 0.0)
            .unwrap_err()
            .contains("contact_hertz")
    );
    assert!(
        soft(|k| k.push_out = -1.0)
            .unwrap_err()
            .contains("push_out")
    );
    assert!(
        soft(|k| k.damping_ratio = f64::NAN)
            .unwrap_err()
            .contains("damping_ratio")
    );
    assert!(
        soft(|k| k.restitution_threshold = -1.0)
            .unwrap_err()
            .contains("restitution_threshold")
    );
    assert!(
        soft(|k| k.linear_damping = -1.0)
            .unwrap_err()
            .contains("linear_damping")
    );
    assert!(
        soft(|k| k.angular_damping = -1.0)
            .unwrap_err()
            .contains("angular_damping")
    );
    assert!(
        soft(|k| k.carry_reach = -1.0)
            .unwrap_err()
            .contains("carry_reach")
    );
    assert!(Settings::soft().validate().is_ok());
    assert!(Settings::default().validate().is_ok());
}

/// Every key but `max_overlap` at its good value, read by the scene, lands in the field the
/// README says (mapped here by hand), and a dump gives every one back.
#[test]
fn every_key_reaches_its_field_and_a_dump_gives_it_back() {
    let lines: Vec<String> = KEYS
        .iter()
        .filter(|k| k.0 != "max_overlap")
        .map(|(k, _, good)| format!("{k} = {good}"))
        .collect();
    let s = Scene::from_toml(&scene(&lines.join("\n")))
        .unwrap()
        .settings;
    let want = Settings {
        step: 0.005,
        damping: 0.25,
        gravity: 4.5,
        max_iterations: 7,
        slop: 0.002,
        sleep_radius: 0.003,
        sleep_steps: 77,
        sleep_islands: false,
        shock_propagation: true,
        strip_width: 3.5,
        precision: Precision::new(9, 0.001).unwrap(),
        rotation: Rotation::Inertia,
        narrow_phase: NarrowPhase::Quadtree,
        broad_phase: BroadPhase::AllPairs,
        model: Model::Soft,
        soft: supergrain::settings::SoftSettings {
            substeps: 6,
            contact_hertz: 45.0,
            damping_ratio: 2.5,
            push_out: 1.5,
            restitution_threshold: 0.75,
            linear_damping: 0.2,
            angular_damping: 0.3,
            carry_reach: 2e-4,
        },
    };
    assert_eq!(s, want);
    let mut read = Scene::from_toml(&scene(&lines.join("\n"))).unwrap();
    read.settings = want;
    let world = World::new(&read);
    let back = Dump::from_json(&serde_json::to_string(&Dump::of(&world)).unwrap())
        .unwrap()
        .to_world()
        .unwrap();
    assert_eq!(back.settings, want);
    // `max_overlap` sets the stiffness (and is not a field of its own).
    let asked = Scene::from_toml(&scene("max_overlap = 0.02"))
        .unwrap()
        .settings;
    assert_ne!(
        asked.soft.contact_hertz,
        Settings::soft().soft.contact_hertz
    );
}

/// `Settings::set`, as `run --set` uses it: a key from its TOML text, checked, and nothing
/// changed on an error.
#[test]
fn one_key_is_set_from_its_text_and_nonsense_changes_nothing() {
    let mut s = Settings::soft();
    s.set("contact_hertz", "30").unwrap();
    assert_eq!(s.soft.contact_hertz, 30.0);
    s.set("narrow_phase", "\"quadtree\"").unwrap();
    assert_eq!(s.narrow_phase, NarrowPhase::Quadtree);
    // As a shell leaves `--set rotation="inertia"`: the bare word.
    s.set("rotation", "inertia").unwrap();
    assert_eq!(s.rotation, Rotation::Inertia);
    let before = s;
    for (key, value, says) in [
        // A line break must not set a second key (the hostile tester's `model` injection).
        (
            "sleep_islands",
            "false\nmodel = \"paper\"",
            "one key per setting",
        ),
        ("step", "0.005\nmax_overlap = 0.001", "one key per setting"),
        ("contact_hertz", "-3", "contact_hertz"),
        ("substeps", "0", "substeps"),
        ("contact_herz", "30", "no solver key"),
        ("model", "\"paper\"", "model is the scene's"),
        ("max_overlap", "0.01", "max_overlap"),
        ("narrow_phase", "newton", "narrow_phase"),
        ("rotation", "\"spin\"", "rotation"),
        ("step", "fast", "step"),
    ] {
        let e = s.set(key, value).expect_err(key);
        assert!(e.contains(says), "{key} = {value}: {e}");
        assert_eq!(s, before, "{key} = {value} changed the settings");
    }
}

/// A dump of the form before the keys were one table, the soft step's in `"soft": {...}`
/// with its own `slop` over the paper's, and no `carry_reach` (dumps before contacts were
/// carried), resumes with the soft step's slop and no contact carried.
#[test]
fn a_dump_of_the_old_form_resumes_with_its_soft_table() {
    let world = World::new(&Scene::from_toml(&scene("model = \"soft\"")).unwrap());
    let mut d: serde_json::Value = serde_json::to_value(Dump::of(&world)).unwrap();
    let solver = d["solver"].as_object_mut().unwrap();
    for key in supergrain::settings::SOFT_KEYS {
        solver.remove(*key);
    }
    solver.insert("slop".into(), serde_json::json!(0.005));
    solver.insert(
        "soft".into(),
        serde_json::json!({
            "substeps": 5, "contact_hertz": 33.0, "damping_ratio": 9.0, "push_out": 2.0,
            "restitution_threshold": 0.5, "slop": 0.001, "linear_damping": 0.1,
            "angular_damping": 0.05
        }),
    );
    let s = Dump::from_json(&d.to_string())
        .unwrap()
        .to_world()
        .unwrap()
        .settings;
    assert_eq!(s.slop, 0.001, "the soft table's slop, not the paper's");
    assert_eq!(
        (s.soft.substeps, s.soft.contact_hertz, s.soft.damping_ratio),
        (5, 33.0, 9.0)
    );
    assert_eq!((s.soft.push_out, s.soft.restitution_threshold), (2.0, 0.5));
    assert_eq!((s.soft.linear_damping, s.soft.angular_damping), (0.1, 0.05));
    assert_eq!(
        s.soft.carry_reach, 0.0,
        "no contact carried, as that code ran"
    );
    assert!(!s.sleep_islands, "grain by grain, as that code slept");
    // Without `model`, the soft table makes it the soft step's, and is refused.
    d["solver"].as_object_mut().unwrap().remove("model");
    let e = Dump::from_json(&d.to_string())
        .unwrap()
        .to_world()
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("model is missing") && e.contains("soft"), "{e}");
}

/// The README's scene reference shows every key (a key added to the table is documented).
#[test]
fn the_readme_shows_every_key() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    // The scene reference's table: from its `[solver]` line to the `[[group]]` line after it.
    let reference = &readme[readme.find("\n[solver]").expect("a [solver] reference")..];
    let reference = &reference[..reference.find("\n[[group]]").unwrap()];
    for key in SolverTable::KEYS {
        assert!(
            reference.contains(&format!("{key} ")) || reference.contains(&format!("# {key}")),
            "the README's [solver] reference does not show `{key}`"
        );
    }
}

/// Keys that say nothing where they are are refused, not ignored: the soft step's keys under the
/// paper's model (scene and dump), a scene's `soft` table (a dump's old form), the old table
/// beside the flat keys it would override, and `max_overlap` in a dump.
#[test]
fn keys_that_would_be_ignored_or_override_unseen_are_refused() {
    for key in [
        "substeps = 4",
        "contact_hertz = 5.0",
        "carry_reach = 0.0",
        "push_out = 2.0",
    ] {
        let e = Scene::from_toml(&scene(&format!("model = \"paper\"\n{key}")))
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(e.contains("is the soft model's"), "{key}: {e}");
    }
    let legacy = "soft = { substeps = 7, contact_hertz = 5.0, damping_ratio = 1.0, push_out = 1.0, \
                  restitution_threshold = 1.0, linear_damping = 0.0, angular_damping = 0.0, slop = 0.0 }";
    let e = Scene::from_toml(&scene(&format!("model = \"soft\"\n{legacy}")))
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("unknown key `soft`"), "{e}");
    let world = World::new(&Scene::from_toml(&scene("model = \"soft\"")).unwrap());
    let good: serde_json::Value = serde_json::to_value(Dump::of(&world)).unwrap();
    let refused = |d: &serde_json::Value| {
        Dump::from_json(&d.to_string())
            .unwrap()
            .to_world()
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let mut d = good.clone();
    d["solver"]["soft"] = serde_json::json!({
        "substeps": 5, "contact_hertz": 33.0, "damping_ratio": 9.0, "push_out": 2.0,
        "restitution_threshold": 0.5, "slop": 0.001, "linear_damping": 0.1, "angular_damping": 0.05
    });
    assert!(refused(&d).contains("are both given"), "{}", refused(&d));
    let mut d = good.clone();
    d["solver"]["max_overlap"] = serde_json::json!(0.01);
    assert!(refused(&d).contains("max_overlap is a scene's"));
    let mut d = good;
    d["solver"]["model"] = serde_json::json!("paper");
    assert!(refused(&d).contains("is the soft model's"));
}

//! The viewer's logic without a window: the controls as commands, checked against the library
//! driven directly, brute force, and closed forms.

use supergrain::body::Material;
use supergrain::contact::contact;
use supergrain::geometry::Vec2;
use supergrain::io::Dump;
use supergrain::settings::{Model, Settings, SoftSettings};
use supergrain::shape::{Pose, Superellipse};
use supergrain::subdivision::Precision;
use supergrain::world::{MaterialOf, Scene, World};
use supergrain_viewer::driver::Meter;
use supergrain_viewer::explorer::{Explorer, Params};
use supergrain_viewer::sim::{DropShape, Overlays};
use supergrain_viewer::{Command, Sim};

/// A scene with no grains of its own: only what the tests drop.
const EMPTY: &str = r#"
seed = 1
steps = 100
[box]
left = -2.0
right = 2.0
floor = 0.0
top = 6.0
"#;

fn empty() -> Sim {
    let mut sim = Sim::open("empty.toml", EMPTY).expect("the empty scene is valid");
    sim.apply(Command::Pause);
    sim
}

#[test]
fn play_steps_pause_stops_and_step_steps_once() {
    let mut sim = Sim::preset("mixed").unwrap();
    assert!(sim.playing());
    sim.apply(Command::Speed(3));
    assert_eq!(sim.frame(), 3);
    assert_eq!(sim.world.step, 3);
    sim.apply(Command::Pause);
    assert_eq!(sim.frame(), 0);
    assert_eq!(sim.world.step, 3);
    sim.apply(Command::Step);
    assert_eq!(sim.world.step, 4);
    assert!(!sim.playing());
    // Speeds outside the slider's range are clamped, not obeyed.
    sim.apply(Command::Speed(0));
    assert_eq!(sim.speed(), 1);
    sim.apply(Command::Speed(1_000_000));
    assert_eq!(sim.speed(), supergrain_viewer::sim::MAX_SPEED);
}

#[test]
fn the_viewer_runs_the_same_simulation_as_the_library_and_reset_replays_it() {
    // The reference: the library's world of the same preset, stepped directly.
    let mut reference = World::new(&Scene::preset("ellipses").unwrap());
    for _ in 0..300 {
        reference.step();
    }
    let mut sim = Sim::preset("ellipses").unwrap();
    sim.apply(Command::Speed(10));
    for _ in 0..30 {
        sim.frame();
    }
    let centres = |w: &World| -> Vec<(u64, u64)> {
        w.bodies
            .iter()
            .map(|b| (b.center.x.to_bits(), b.center.y.to_bits()))
            .collect()
    };
    assert!(!reference.bodies.is_empty());
    assert_eq!(centres(&sim.world), centres(&reference));
    sim.apply(Command::Reset);
    assert_eq!(sim.world.step, 0);
    assert!(sim.world.bodies.is_empty());
    for _ in 0..30 {
        sim.frame();
    }
    assert_eq!(
        centres(&sim.world),
        centres(&reference),
        "reset replays bit for bit"
    );
}

#[test]
fn a_dropped_grain_appears_where_clicked_and_falls_to_rest_on_the_floor() {
    let mut sim = empty();
    let d = DropShape {
        semi_axes: [0.3, 0.2],
        exponents: [2.0, 2.0],
        angle: 0.0,
    };
    sim.apply(Command::DropShape(d));
    sim.apply(Command::Drop(Vec2::new(0.5, 3.0)));
    assert_eq!(sim.world.bodies.len(), 1);
    let b = sim.world.bodies[0];
    assert_eq!((b.center.x, b.center.y), (0.5, 3.0));
    assert_eq!(b.shape.semi_axes(), Vec2::new(0.3, 0.2));

    // On top of it, or across a wall: refused, with a reason, nothing added.
    sim.apply(Command::Drop(Vec2::new(0.6, 3.1)));
    assert!(
        sim.message().unwrap().contains("overlap"),
        "{:?}",
        sim.message()
    );
    sim.apply(Command::Drop(Vec2::new(1.9, 3.0)));
    assert!(
        sim.message().unwrap().contains("wall"),
        "{:?}",
        sim.message()
    );
    assert_eq!(sim.world.bodies.len(), 1);

    // Falling from rest, it lands flat: an ellipse at angle 0 rests with its centre one
    // semi-axis (0.2) above the floor.
    sim.apply(Command::Play);
    sim.apply(Command::Speed(50));
    for _ in 0..20 {
        sim.frame();
    }
    let b = sim.world.bodies[0];
    assert!(
        (b.center.y - 0.2).abs() < 0.01,
        "rests at y = {}",
        b.center.y
    );
    assert!(
        (b.center.x - 0.5).abs() < 0.01 && b.angle.abs() < 0.05,
        "{b:?}"
    );
}

#[test]
fn a_dragged_grain_follows_the_point_it_was_grabbed_by() {
    let mut sim = empty();
    sim.apply(Command::DropShape(DropShape {
        semi_axes: [0.4, 0.25],
        exponents: [4.0, 4.0],
        angle: 0.0,
    }));
    sim.apply(Command::Drop(Vec2::new(0.0, 3.0)));
    // Outside every grain: nothing is held, and dragging moves nothing.
    sim.apply(Command::Grab(Vec2::new(1.0, 1.0)));
    sim.apply(Command::DragTo(Vec2::new(1.5, 1.5)));
    assert_eq!(sim.world.bodies[0].center, Vec2::new(0.0, 3.0));
    // Grabbed 0.1 right of and 0.05 above the centre, the grain's centre stays that far from
    // the mouse.
    sim.apply(Command::Grab(Vec2::new(0.1, 3.05)));
    assert_eq!(sim.snapshot().held, Some(0));
    sim.apply(Command::DragTo(Vec2::new(1.0, 5.0)));
    let c = sim.world.bodies[0].center;
    assert!(
        (c.x - 0.9).abs() < 1e-12 && (c.y - 4.95).abs() < 1e-12,
        "{c:?}"
    );
    // Held, it stays put while time runs; released, it falls.
    sim.apply(Command::Play);
    for _ in 0..10 {
        sim.frame();
    }
    let held = sim.world.bodies[0].center;
    assert!((held.y - 4.95).abs() < 1e-12, "{held:?}");
    sim.apply(Command::Release);
    for _ in 0..10 {
        sim.frame();
    }
    assert!(sim.world.bodies[0].center.y < 4.9);
}

#[test]
fn a_bad_scene_keeps_the_current_one_and_names_the_line() {
    let mut sim = Sim::preset("circles").unwrap();
    sim.frame();
    let before = sim.world.step;
    sim.apply(Command::Open {
        name: "broken.toml".into(),
        text: "seed = 1\n[box]\nleft = \"wide\"\n".into(),
    });
    let msg = sim.message().unwrap().to_string();
    assert!(
        msg.contains("broken.toml") && msg.contains("line 3"),
        "{msg}"
    );
    assert_eq!(sim.source().label(), "preset circles");
    assert_eq!(sim.world.step, before);
    // An unknown preset, likewise.
    sim.apply(Command::Preset("sand".into()));
    assert!(sim.message().unwrap().contains("unknown preset"));
    assert_eq!(sim.source().label(), "preset circles");
    // A good one replaces it, keeping the speed.
    sim.apply(Command::Speed(7));
    sim.apply(Command::Preset("squircles".into()));
    assert_eq!(sim.source().label(), "preset squircles");
    assert_eq!((sim.world.step, sim.speed()), (0, 7));
}

#[test]
fn solver_sliders_apply_at_once_and_nonsense_is_refused() {
    let mut sim = Sim::preset("mixed").unwrap();
    let t = Settings {
        step: 0.005,
        damping: 0.4,
        max_iterations: 4,
        precision: Precision::new(9, 0.001).unwrap(),
        ..sim.world.settings
    };
    sim.apply(Command::Tune(t));
    assert_eq!(sim.world.settings, t);
    for bad in [
        Settings {
            max_iterations: 0,
            ..t
        },
        Settings { damping: 1.5, ..t },
        Settings {
            step: f64::NAN,
            ..t
        },
        Settings { step: 0.5, ..t },
        Settings { gravity: -1.0, ..t },
        Settings { slop: -1.0, ..t },
        Settings {
            model: Model::Soft,
            ..t
        },
        Settings {
            sleep_islands: true,
            ..t
        },
    ] {
        sim.apply(Command::Tune(bad));
        assert_eq!(sim.world.settings, t, "{bad:?} was applied");
        assert!(sim.message().is_some());
    }
    // Settings survive a reset.
    sim.apply(Command::Reset);
    assert_eq!(sim.world.settings, t);
}

#[test]
fn the_spawn_rule_applies_from_the_next_reset() {
    let mut sim = Sim::preset("circles").unwrap();
    sim.apply(Command::Spawn(supergrain_viewer::sim::Spawn {
        interval: 5,
        top: 8.0,
    }));
    assert!(sim.message().unwrap().contains("next reset"));
    sim.apply(Command::Reset);
    sim.apply(Command::Speed(1));
    // Grains now appear every 5 steps at height 8: two of them after 6 steps.
    for _ in 0..6 {
        sim.frame();
    }
    assert_eq!(sim.world.bodies.len(), 2);
    assert!(
        sim.world
            .bodies
            .iter()
            .all(|b| b.center.y <= 8.0 && b.center.y > 7.5)
    );
}

#[test]
fn the_overlays_show_every_overlapping_pair_found_by_brute_force() {
    // Two rows of grains pressed into each other and into the floor.
    let mut sim = empty();
    let shapes = [
        Superellipse::new([0.3, 0.2], [4.0, 4.0]).unwrap(),
        Superellipse::new([0.28, 0.18], [0.7, 1.5]).unwrap(),
        Superellipse::new([0.25, 0.25], [2.0, 2.0]).unwrap(),
    ];
    for k in 0..14 {
        let (row, col) = (k / 7, k % 7);
        let centre = Vec2::new(-1.5 + 0.5 * f64::from(col), 0.15 + 0.33 * f64::from(row));
        let pose = Pose::new(centre, 0.37 * f64::from(k)).unwrap();
        sim.world.bodies.push(supergrain::body::Body::at_rest(
            shapes[k as usize % 3],
            &pose,
        ));
    }
    sim.apply(Command::Overlays(Overlays {
        boxes: true,
        cells: true,
        vectors: true,
    }));
    let snap = sim.snapshot();
    let bodies = &sim.world.bodies;
    let precision = sim.world.settings.precision;
    let mut pairs = 0;
    for i in 0..bodies.len() {
        for j in i + 1..bodies.len() {
            let (a, b) = (&bodies[i], &bodies[j]);
            if contact(&a.shape, &a.pose(), &b.shape, &b.pose(), &precision).overlap() {
                pairs += 1;
            }
        }
    }
    assert!(pairs >= 5, "the rows overlap: {pairs} pairs");
    assert_eq!(snap.contacts.len(), pairs);
    // The bottom row reaches below the floor.
    assert!(!snap.wall_contacts.is_empty());
    assert!(!snap.cells.is_empty());
    // Off, nothing is computed.
    sim.apply(Command::Overlays(Overlays::default()));
    let snap = sim.snapshot();
    assert!(snap.contacts.is_empty() && snap.cells.is_empty());
}

#[test]
fn saved_state_and_picture_are_a_dump_and_a_png_of_the_world() {
    let mut sim = Sim::preset("squircles").unwrap();
    sim.apply(Command::Speed(20));
    for _ in 0..30 {
        sim.frame();
    }
    let dump: Dump = serde_json::from_str(&sim.state_json()).expect("a dump");
    let world = dump.to_world().expect("a valid dump");
    assert_eq!(world.step, sim.world.step);
    assert_eq!(world.bodies.len(), sim.world.bodies.len());
    for (a, b) in world.bodies.iter().zip(&sim.world.bodies) {
        assert_eq!(a.center, b.center);
    }
    let png = sim.screenshot_png(300).unwrap();
    let img = image::load_from_memory(&png).expect("a PNG").to_rgba8();
    assert_eq!(img.width(), 300);
    // The pixel under a grain's centre is painted, not the background.
    let b = &sim.world.bodies[0];
    let region = supergrain::render::world_region(&sim.world);
    let view = supergrain::render::raster::View::fit(region, 300);
    let (px, py) = view.to_pixel(b.center);
    let p = img.get_pixel(px as u32, py as u32);
    assert_ne!(p.0, [250, 250, 250, 255], "background under a grain");
}

#[test]
fn the_files_are_written_whole_or_not_at_all() {
    let dir = std::env::temp_dir().join(format!("sg-viewer-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let target = dir.join("state.json");
    supergrain::io::write_atomically(&target, b"{}").unwrap();
    assert_eq!(std::fs::read(&target).unwrap(), b"{}");
    // A folder that does not exist: an error naming the path, nothing left behind.
    let bad = dir.join("missing").join("state.json");
    let e = supergrain::io::write_atomically(&bad, b"{}").unwrap_err();
    assert!(e.contains("missing"), "{e}");
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("state.json")]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_explorer_matches_two_circles_closed_form() {
    // Two unit-radius... circles of radius 0.5 at distance d overlap by 1 - d.
    let circle = Params {
        semi_axes: [0.5, 0.5],
        exponents: [2.0, 2.0],
        angle: 0.0,
    };
    for d in [0.6, 0.8, 0.95] {
        let e = Explorer {
            a: circle,
            b: circle,
            b_center: Vec2::new(d * 0.6, d * 0.8),
            depth: 10,
            eps: 0.0,
        };
        let eval = e.evaluate().unwrap();
        let p = eval.contact.penetration.expect("overlap");
        let depth = p.a_push.norm().max(p.b_push.norm());
        assert!((depth - (1.0 - d)).abs() < 0.01, "d {d}: depth {depth}");
        assert!(!eval.cells.is_empty());
    }
    let apart = Explorer {
        a: circle,
        b: circle,
        b_center: Vec2::new(1.05, 0.0),
        depth: 10,
        eps: 0.0,
    };
    assert!(apart.evaluate().unwrap().contact.penetration.is_none());
    // A shape the library refuses is reported, not drawn.
    let bad = Explorer {
        a: Params {
            exponents: [0.0, 2.0],
            ..circle
        },
        ..apart
    };
    assert!(bad.evaluate().is_err());
}

#[test]
fn the_meter_counts_steps_per_second() {
    let mut m = Meter::default();
    for k in 0..=120 {
        m.count(2, f64::from(k) / 60.0);
    }
    assert!((m.rate() - 120.0).abs() < 3.0, "{}", m.rate());
}

#[test]
fn grains_under_the_mouse_are_found_by_their_inside() {
    let mut sim = empty();
    sim.apply(Command::DropShape(DropShape {
        semi_axes: [0.5, 0.1],
        exponents: [2.0, 2.0],
        angle: std::f64::consts::FRAC_PI_2,
    }));
    sim.apply(Command::Drop(Vec2::new(0.0, 2.0)));
    // Turned upright: 0.4 above the centre is inside, 0.4 to the side is not.
    assert_eq!(sim.grain_at(Vec2::new(0.0, 2.4)), Some(0));
    assert_eq!(sim.grain_at(Vec2::new(0.4, 2.0)), None);
    let shape = Superellipse::new([0.5, 0.1], [2.0, 2.0]).unwrap();
    let pose = Pose::new(Vec2::new(0.0, 2.0), std::f64::consts::FRAC_PI_2).unwrap();
    assert!(shape.value(&pose, Vec2::new(0.0, 2.4)) < 0.0);
}

#[test]
fn a_saved_state_opens_and_reset_returns_to_it() {
    let mut sim = Sim::preset("circles").unwrap();
    sim.apply(Command::Speed(20));
    for _ in 0..40 {
        sim.frame();
    }
    let text = sim.state_json();
    let saved: Vec<Vec2> = sim.world.bodies.iter().map(|b| b.center).collect();
    let mut opened = Sim::state("heap.json", &text).unwrap();
    assert_eq!(opened.source().label(), "heap.json");
    let centres = |s: &Sim| s.world.bodies.iter().map(|b| b.center).collect::<Vec<_>>();
    assert_eq!(centres(&opened), saved);
    // It goes on from there exactly as the original does.
    sim.frame();
    opened.apply(Command::Speed(20));
    opened.frame();
    assert_eq!(centres(&opened), centres(&sim));
    opened.apply(Command::Reset);
    assert_eq!(centres(&opened), saved);
    // Not a dump: the error names the file.
    let e = Sim::state("notes.json", "{\"grains\": 3}").err().unwrap();
    assert!(e.starts_with("notes.json: not a supergrain state"), "{e}");
}

#[test]
fn a_new_time_step_keeps_every_grain_velocity() {
    let mut sim = empty();
    sim.apply(Command::Drop(Vec2::new(0.0, 4.0)));
    sim.apply(Command::Play);
    for _ in 0..5 {
        sim.frame();
    }
    let h = sim.world.settings.step;
    let b = sim.world.bodies[0];
    let v = (b.center - b.previous_center) * (1.0 / h);
    assert!(v.y < -0.1, "falling: {v:?}");
    let t = Settings {
        step: h / 4.0,
        ..sim.world.settings
    };
    sim.apply(Command::Tune(t));
    let b = sim.world.bodies[0];
    let v2 = (b.center - b.previous_center) * (1.0 / t.step);
    assert!((v2 - v).norm() < 1e-9 * v.norm(), "{v:?} became {v2:?}");
}

#[test]
fn refusals_are_counted_said_and_change_nothing() {
    let mut sim = empty();
    let before = sim.snapshot().commands;
    // Damping 1 would stop nothing and cannot be saved (dumps need [0, 1)).
    let t = Settings {
        damping: 1.0,
        ..sim.world.settings
    };
    sim.apply(Command::Tune(t));
    assert!(sim.message().unwrap().contains("damping"));
    assert!(sim.world.settings.damping < 1.0);
    sim.apply(Command::Notice("cannot read x.toml: gone".into()));
    assert_eq!(sim.message(), Some("cannot read x.toml: gone"));
    assert_eq!(sim.snapshot().commands, before + 2);
    // A saved state has no spawn rule to change.
    let mut state = Sim::state("s.json", &sim.state_json()).unwrap();
    state.apply(Command::Spawn(supergrain_viewer::sim::Spawn {
        interval: 3,
        top: 5.0,
    }));
    assert!(state.message().unwrap().contains("no spawn rule"));
}

#[test]
fn a_dragged_grain_stays_inside_the_box() {
    let mut sim = empty();
    sim.apply(Command::DropShape(DropShape {
        semi_axes: [0.4, 0.2],
        exponents: [2.0, 2.0],
        angle: 0.0,
    }));
    sim.apply(Command::Drop(Vec2::new(0.0, 3.0)));
    sim.apply(Command::Grab(Vec2::new(0.0, 3.0)));
    // Far past the right wall (at 2) and below the floor (at 0).
    sim.apply(Command::DragTo(Vec2::new(9.0, -5.0)));
    let b = sim.world.bodies[0];
    let bb = b.bounding_box();
    assert!(bb.max.x <= 2.0 + 1e-12 && bb.min.y >= -1e-12, "{bb:?}");
    assert!(
        (bb.max.x - 2.0).abs() < 1e-9 && bb.min.y.abs() < 1e-9,
        "{bb:?}"
    );
}

// ---- Materials (the soft model's sliders) ----

/// The soft model in an empty box, a step of 1/240 s, no sleeping; one group, `balls`, with
/// no grains of its own (the tests drop theirs, which are of group 0) and Box2D's default
/// material: friction 0.6, no restitution.
const SOFT: &str = r#"
seed = 1
steps = 100
[box]
left = -2.0
right = 2.0
floor = 0.0
top = 6.0
[solver]
model = "soft"
step = 0.004166666666666667
sleep_radius = 0.0
[[group]]
name = "balls"
count = 0
radius = 0.25
"#;

const G: f64 = 9.8;

fn soft_with(shape: DropShape, at: Vec2) -> Sim {
    let mut sim = Sim::open("soft.toml", SOFT).expect("the soft scene is valid");
    sim.apply(Command::Pause);
    sim.apply(Command::DropShape(shape));
    sim.apply(Command::Drop(at));
    assert_eq!(sim.world.bodies.len(), 1, "{:?}", sim.message());
    sim
}

const BALL: DropShape = DropShape {
    semi_axes: [0.25, 0.25],
    exponents: [2.0, 2.0],
    angle: 0.0,
};

/// A ball of radius 0.25 let go 2 above the floor, its material changed after `change_at`
/// steps (in flight): the height of the top of its first rebound (0 without one).
fn rebound(change_at: usize, change: Option<(MaterialOf, Material)>) -> f64 {
    let (r, h0) = (0.25, 2.0);
    let mut sim = soft_with(BALL, Vec2::new(0.0, r + h0));
    let (mut bounced, mut top) = (false, 0.0f64);
    for k in 0..1000 {
        if k == change_at
            && let Some((of, m)) = change
        {
            sim.apply(Command::Material(of, m));
            assert_eq!(sim.message(), None);
        }
        sim.step();
        let b = &sim.world.bodies[0];
        if b.velocity.y > 0.0 && b.center.y - r > 0.01 {
            bounced = true;
        }
        if bounced {
            top = top.max(b.center.y - r);
            if b.velocity.y < 0.0 {
                break;
            }
        }
    }
    top
}

#[test]
fn a_restitution_slider_makes_a_falling_ball_bounce_to_e_squared_of_its_height() {
    let bouncy = Material {
        restitution: 0.9,
        ..Material::default()
    };
    // Without a change, no rebound (restitution 0 for the ball and the floor).
    let dead = rebound(0, None);
    assert!(dead < 0.01, "rebounded to {dead} without restitution");
    // Changed in mid-air (the impact is at step 153): the ball's group, or the walls (the
    // larger restitution of the two counts). Each rebounds to e^2 h = 1.62.
    for of in [MaterialOf::Group(0), MaterialOf::Walls] {
        let top = rebound(60, Some((of, bouncy)));
        let want = 0.81 * 2.0;
        assert!(
            (top - want).abs() <= 0.05 * want,
            "{of:?}: rebounded to {top}, e^2 h = {want}"
        );
    }
}

#[test]
fn a_material_command_changes_the_worlds_table_and_the_panel() {
    let mut sim = soft_with(BALL, Vec2::new(0.0, 3.0));
    let m = Material {
        density: 2.0,
        friction: 0.1,
        restitution: 0.3,
        rolling_resistance: 0.2,
    };
    let walls = Material {
        friction: 1.5,
        ..Material::default()
    };
    sim.apply(Command::Material(MaterialOf::Group(0), m));
    sim.apply(Command::Material(MaterialOf::Walls, walls));
    assert_eq!(sim.world.materials, vec![m]);
    assert_eq!(sim.world.wall_material, walls);
    let shown = sim
        .snapshot()
        .materials
        .expect("the soft model has materials");
    assert_eq!(shown.groups, vec![("balls".to_string(), m)]);
    assert_eq!(shown.walls, walls);
    // Out of range: refused, said, nothing changed.
    for bad in [
        Material { density: 0.0, ..m },
        Material {
            restitution: 1.5,
            ..m
        },
        Material {
            friction: f64::NAN,
            ..m
        },
    ] {
        sim.apply(Command::Material(MaterialOf::Group(0), bad));
        assert!(sim.message().is_some_and(|e| e.contains("out of range")));
        assert_eq!(sim.world.materials, vec![m]);
    }
    // Materials survive a reset, as the solver settings do.
    sim.apply(Command::Reset);
    assert_eq!(
        (sim.world.materials.clone(), sim.world.wall_material),
        (vec![m], walls)
    );
    // The paper's model has none: no panel, and the command is refused.
    let mut paper = Sim::preset("circles").unwrap();
    assert!(paper.snapshot().materials.is_none());
    paper.apply(Command::Material(MaterialOf::Walls, walls));
    assert!(paper.message().is_some_and(|e| e.contains("soft model")));
    assert_eq!(paper.world.wall_material, Material::default());
}

/// The floor's upward push on the grains over the last step.
fn floor_force(sim: &Sim) -> f64 {
    sim.world
        .soft
        .forces
        .iter()
        .filter(|f| f.wall == Some(2))
        .map(|f| f.normal.y * f.normal_force)
        .sum()
}

#[test]
fn a_new_density_gives_a_resting_ball_its_new_weight() {
    let r: f64 = 0.25;
    let mut sim = soft_with(BALL, Vec2::new(0.0, r + 0.001));
    let area = std::f64::consts::PI * r * r;
    for _ in 0..240 {
        sim.step();
    }
    let weight = area * G;
    let f = floor_force(&sim);
    assert!((f - weight).abs() <= 0.01 * weight, "{f} against {weight}");
    // Three times as dense: the floor carries three times the weight (the solver's mass is
    // recomputed, not the one it kept).
    sim.apply(Command::Material(
        MaterialOf::Group(0),
        Material {
            density: 3.0,
            ..Material::default()
        },
    ));
    for _ in 0..120 {
        sim.step();
    }
    let f = floor_force(&sim);
    assert!(
        (f - 3.0 * weight).abs() <= 0.01 * 3.0 * weight,
        "{f} against {}",
        3.0 * weight
    );
}

#[test]
fn a_friction_slider_sets_how_far_a_pushed_block_slides() {
    let block = DropShape {
        semi_axes: [0.3, 0.2],
        exponents: [8.0, 8.0],
        angle: 0.0,
    };
    // Pushed along the floor at 2 units/s: how far it goes in a second.
    let slide = |friction: f64| {
        let mut sim = soft_with(block, Vec2::new(-1.5, 0.201));
        sim.apply(Command::Material(
            MaterialOf::Group(0),
            Material {
                friction,
                ..Material::default()
            },
        ));
        for _ in 0..60 {
            sim.step();
        }
        let x0 = sim.world.bodies[0].center.x;
        sim.world.bodies[0].velocity = Vec2::new(2.0, 0.0);
        for _ in 0..240 {
            sim.step();
        }
        sim.world.bodies[0].center.x - x0
    };
    // Friction 0 (the mix with the floor's 0.6 is their geometric mean, 0): no braking.
    let free = slide(0.0);
    assert!(
        (free - 2.0).abs() <= 0.02,
        "slid {free} in 1 s without friction"
    );
    // Friction 1: mu = sqrt(0.6) with the floor, it stops after v^2 / (2 mu g).
    let braked = slide(1.0);
    let want = 4.0 / (2.0 * 0.6f64.sqrt() * G);
    assert!(
        (braked - want).abs() <= 0.05 * want,
        "slid {braked}, v^2 / (2 mu g) = {want}"
    );
}

/// Under the soft model the panel shows the soft step's settings: a drag slider makes a
/// falling ball reach `g / c (1 - e^(-c t))` (the substeps' drag is `1 / (1 + c h)` a substep),
/// and nonsense is refused, changing nothing.
#[test]
fn the_soft_panel_sets_the_soft_steps_settings() {
    let mut sim = soft_with(BALL, Vec2::new(0.0, 5.0));
    let now = sim.snapshot().settings.expect("the solver panel");
    assert_eq!(
        now.model,
        Model::Soft,
        "the panel shows the soft step's settings"
    );
    let soft = now.soft;
    let c = 2.0;
    let t = Settings {
        soft: SoftSettings {
            linear_damping: c,
            contact_hertz: 45.0,
            ..soft
        },
        ..now
    };
    sim.apply(Command::Tune(t));
    assert_eq!(sim.message(), None);
    assert_eq!(sim.world.settings.soft.contact_hertz, 45.0);
    let h = sim.world.settings.step;
    let steps = (0.4 / h).round() as usize;
    for _ in 0..steps {
        sim.step();
    }
    let time = steps as f64 * h;
    let want = G / c * (1.0 - (-c * time).exp());
    let v = -sim.world.bodies[0].velocity.y;
    assert!(
        (v - want).abs() <= 0.02 * want,
        "falls at {v}, drag's closed form {want}"
    );
    for bad in [
        SoftSettings {
            substeps: 0,
            ..soft
        },
        SoftSettings {
            contact_hertz: f64::NAN,
            ..soft
        },
        SoftSettings {
            linear_damping: -1.0,
            ..soft
        },
    ] {
        sim.apply(Command::Tune(Settings { soft: bad, ..now }));
        assert!(sim.message().is_some(), "{bad:?} was taken");
        assert_eq!(sim.world.settings.soft.contact_hertz, 45.0);
    }
}

/// The window follows a scene's boundaries where they are now, its sinks, and its measures
/// live: a paddle turning about the origin is drawn where a quarter turn takes it, and the
/// energy chart's last value is the grains' kinetic energy summed here by hand
/// (`m v^2 / 2 + I w^2 / 2`).
#[test]
fn the_window_shows_moving_boundaries_sinks_and_live_measures() {
    let scene = r#"
seed = 3
steps = 200
[box]
left = -3.0
right = 3.0
floor = 0.0
top = 6.0
[spawn]
interval = 2
[solver]
model = "soft"
[[boundary]]
segment = [[-1.0, 2.0], [1.0, 2.0]]
thickness = 0.1
turn = { about = [0.0, 2.0], rate = 90.0 }
[[sink]]
region = [[-3.0, 3.0], [0.0, 0.3]]
recycle = true
[[group]]
count = 12
radius = 0.2
[[measure]]
kind = "energy"
every = 5
[[measure]]
kind = "discharge"
every = 5
"#;
    let mut sim = Sim::open("paddle.toml", scene).unwrap();
    sim.apply(Command::Pause);
    let snap = sim.snapshot();
    assert_eq!(snap.boundaries.len(), 1);
    assert_eq!(snap.sinks.len(), 1);
    assert_eq!(snap.measures.len(), 2);
    assert_eq!(
        (snap.measures[0].kind, snap.measures[1].kind),
        ("energy", "discharge")
    );
    // One second at 90 degrees a second: the paddle stands upright.
    let steps = (1.0 / sim.world.settings.step).round() as usize;
    for _ in 0..steps {
        sim.step();
    }
    let snap = sim.snapshot();
    let supergrain::shape::Boundary::Segment { a, b, .. } = snap.boundaries[0] else {
        panic!("a segment: {:?}", snap.boundaries[0]);
    };
    assert!(
        (a.x.abs() < 1e-9 && (a.y - 1.0).abs() < 1e-9 && (b.y - 3.0).abs() < 1e-9)
            || (b.x.abs() < 1e-9 && (b.y - 1.0).abs() < 1e-9 && (a.y - 3.0).abs() < 1e-9),
        "a quarter turn about (0, 2): {a:?} {b:?}"
    );
    let energy = &snap.measures[0];
    assert_eq!(energy.what, "kinetic energy");
    assert_eq!(
        energy.points.len(),
        steps / 5 + 1,
        "a point a row, and step 0's"
    );
    let w = &sim.world;
    let by_hand: f64 = w
        .bodies
        .iter()
        .filter(|b| !b.is_static())
        .map(|b| {
            let m = &w.materials[b.group as usize];
            let (mass, inertia) = m.mass_and_inertia(&b.shape);
            0.5 * mass * b.velocity.norm().powi(2) + 0.5 * inertia * b.angular_velocity.powi(2)
        })
        .sum();
    let last = energy.points.last().unwrap();
    assert!(
        (last[0] - w.time()).abs() < 1e-9,
        "{last:?} at t = {}",
        w.time()
    );
    assert!(
        (last[1] - by_hand).abs() <= 1e-9 * by_hand.max(1e-12),
        "chart {} against {by_hand}",
        last[1]
    );
    assert!(
        energy.summary.contains("kinetic energy"),
        "{}",
        energy.summary
    );
    // A reset starts the charts again.
    sim.apply(Command::Reset);
    assert_eq!(sim.snapshot().measures[0].points.len(), 1);
}

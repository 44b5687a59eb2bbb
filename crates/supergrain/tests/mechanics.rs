//! The soft step against textbook mechanics (issue 18): free fall, a bounce, a head-on
//! collision, a block on an incline that holds or slides, a disk that rolls without slipping,
//! a column and a pyramid of blocks that stand. Each compares with a closed form, not with the
//! code's own output.

use supergrain::body::{Body, Material, Walls};
use supergrain::contact::NarrowPhase;
use supergrain::geometry::Vec2;
use supergrain::settings::Settings;
use supergrain::shape::{Boundary, HalfPlane, Pose, Superellipse};
use supergrain::world::{Queue, World};

const G: f64 = 9.8;

/// A world of the soft model with the given grains, materials by group, a box far wider than
/// the test needs unless `walls` say otherwise.
fn world(bodies: Vec<Body>, walls: Walls, materials: Vec<Material>, settings: Settings) -> World {
    let mut w = World::from_parts(bodies, walls, settings, 0, 50.0, Queue::default());
    w.materials = materials;
    w
}

fn soft() -> Settings {
    Settings {
        step: 1.0 / 60.0,
        sleep_radius: 0.0,
        ..Settings::soft()
    }
}

fn far_walls() -> Walls {
    Walls {
        left: -100.0,
        right: 100.0,
        floor: 0.0,
    }
}

fn grain(shape: Superellipse, x: f64, y: f64, angle: f64) -> Body {
    Body::at_rest(shape, &Pose::new(Vec2::new(x, y), angle).unwrap())
}

fn disk(r: f64) -> Superellipse {
    Superellipse::circle(r).unwrap()
}

#[test]
fn a_grain_released_in_the_air_falls_as_g_t2_over_2() {
    for shape in [
        disk(0.3),
        Superellipse::new([0.4, 0.2], [6.0, 6.0]).unwrap(),
    ] {
        let mut w = world(
            vec![grain(shape, 0.0, 20.0, 0.3)],
            far_walls(),
            vec![Material::default()],
            soft(),
        );
        let steps = 60;
        for _ in 0..steps {
            w.step();
        }
        let t = steps as f64 * w.settings.step;
        let fell = 20.0 - w.bodies[0].center.y;
        let exact = 0.5 * G * t * t;
        assert!(
            (fell - exact).abs() <= 0.01 * exact,
            "fell {fell} in {t} s, g t^2 / 2 = {exact}"
        );
        let v = w.velocity(0);
        assert!(
            (v.y + G * t).abs() <= 1e-9 * G * t,
            "speed {v:?}, g t = {}",
            G * t
        );
        assert_eq!(w.bodies[0].angle, 0.3, "nothing turned it");
    }
}

/// How high a disk of radius 0.25 dropped `h0` onto the floor (both of restitution `e`, no
/// friction) rebounds, stepped at `step`: the top of its first rebound above the floor.
fn rebound(e: f64, h0: f64, step: f64) -> f64 {
    let r = 0.25;
    let material = Material {
        restitution: e,
        friction: 0.0,
        ..Material::default()
    };
    let mut w = world(
        vec![grain(disk(r), 0.0, r + h0, 0.0)],
        far_walls(),
        vec![material],
        Settings { step, ..soft() },
    );
    w.wall_material = material;
    // Down, the bounce, and up to the top of the rebound.
    let mut bounced = false;
    let mut top = 0.0f64;
    for _ in 0..2000 {
        w.step();
        let v = w.velocity(0).y;
        bounced |= v > 0.0;
        if bounced {
            top = top.max(w.bodies[0].center.y - r);
            if v < 0.0 {
                break;
            }
        }
    }
    assert!(bounced, "e = {e}: no bounce");
    top
}

#[test]
fn a_ball_dropped_with_restitution_e_rebounds_to_e_squared_of_its_height() {
    for e in [0.5, 0.8] {
        let (top, want) = (rebound(e, 2.0, 1.0 / 240.0), e * e * 2.0);
        assert!(
            (top - want).abs() <= 0.02 * want,
            "e = {e}: rebounded to {top}, e^2 h = {want}"
        );
    }
}

/// Issue 40's bar: at the default step (`h = 0.01`, not 1/240 as above), drops of 2 and 5
/// units with `e` 0.5 and 0.9 rebound within 2% of `e^2 h`. The bounce takes the speed at the
/// substep where the contact closes: taken at the step's start, as until 2026-12-06, it missed
/// up to `g h` of the fall (contacts are found a step ahead) and rebounded 2.4-4.5% low (3.5%
/// low here for `e` 0.5 and 2 units, checked).
#[test]
fn a_ball_dropped_at_the_default_step_rebounds_to_e_squared_of_its_height() {
    for (e, h0) in [(0.5, 2.0), (0.9, 2.0), (0.5, 5.0), (0.9, 5.0)] {
        let (top, want) = (rebound(e, h0, 0.01), e * e * h0);
        eprintln!(
            "e = {e}, h = {h0}: rebounded to {top:.4}, {:+.2}% of e^2 h",
            100.0 * (top / want - 1.0)
        );
        assert!(
            (top - want).abs() <= 0.02 * want,
            "e = {e}, h = {h0}: rebounded to {top}, e^2 h = {want}"
        );
    }
}

#[test]
fn a_head_on_elastic_collision_keeps_momentum_and_energy() {
    let (ra, rb) = (0.3, 0.5);
    let mut a = grain(disk(ra), -2.0, 5.0, 0.0);
    let mut b = grain(disk(rb), 1.0, 5.0, 0.0);
    a.velocity = Vec2::new(3.0, 0.0);
    b.velocity = Vec2::new(-1.0, 0.0);
    b.group = 1;
    let elastic = Material {
        restitution: 1.0,
        friction: 0.0,
        ..Material::default()
    };
    let heavy = Material {
        density: 3.0,
        ..elastic
    };
    let mut w = world(
        vec![a, b],
        far_walls(),
        vec![elastic, heavy],
        Settings {
            gravity: 0.0,
            ..soft()
        },
    );
    let mass = |w: &World, i: usize| {
        w.materials[w.bodies[i].group as usize].density * w.bodies[i].shape.area()
    };
    let (ma, mb) = (mass(&w, 0), mass(&w, 1));
    let momentum = |w: &World| ma * w.velocity(0).x + mb * w.velocity(1).x;
    let energy = |w: &World| {
        0.5 * ma * w.velocity(0).norm().powi(2) + 0.5 * mb * w.velocity(1).norm().powi(2)
    };
    let (p0, e0) = (ma * 3.0 - mb, 0.5 * ma * 9.0 + 0.5 * mb);
    for _ in 0..120 {
        w.step();
    }
    assert!(
        w.velocity(0).x < 0.0 && w.velocity(0).x < w.velocity(1).x,
        "they did not collide: {:?} {:?}",
        w.velocity(0),
        w.velocity(1)
    );
    let (p, e) = (momentum(&w), energy(&w));
    assert!((p - p0).abs() <= 0.01 * p0.abs(), "momentum {p0} -> {p}");
    assert!((e - e0).abs() <= 0.01 * e0, "energy {e0} -> {e}");
    // The closed form of a 1D elastic collision.
    let va = ((ma - mb) * 3.0 - 2.0 * mb) / (ma + mb);
    assert!(
        (w.velocity(0).x - va).abs() <= 0.02 * 3.0,
        "A leaves at {}, the closed form says {va}",
        w.velocity(0).x
    );
}

/// An incline through the origin at `theta` (rising to the right), its surface normal, and a
/// point at distance `along` up the slope lifted `height` off it.
fn incline(theta: f64) -> (HalfPlane, Vec2, Vec2) {
    let n = Vec2::new(-theta.sin(), theta.cos());
    let t = Vec2::new(theta.cos(), theta.sin());
    (HalfPlane::new(n, 0.0).unwrap(), n, t)
}

/// What the incline is: a half-plane, or a thick segment (issue 41's boundaries) whose top face
/// is the same line.
#[derive(Clone, Copy, Debug)]
enum Surface {
    Plane,
    Segment,
}

const SURFACES: [Surface; 2] = [Surface::Plane, Surface::Segment];

/// A grain resting on an incline: returns how far it moved along the slope (down positive) in
/// `seconds`, and its distance down the slope at each step.
fn on_incline(
    surface: Surface,
    shape: Superellipse,
    theta: f64,
    mu: f64,
    seconds: f64,
) -> Vec<f64> {
    let (plane, n, t) = incline(theta);
    let boundary = match surface {
        Surface::Plane => Boundary::Plane(plane),
        // 0.2 thick, its top face through the origin, from 20 down the slope to 20 up it.
        Surface::Segment => {
            Boundary::segment(n * -0.1 - t * 20.0, n * -0.1 + t * 20.0, 0.2).unwrap()
        }
    };
    // Resting on its flat face (the semi-axis y across the slope): the grain's x axis along it.
    let lift = shape.semi_axes().y;
    let start = t * 5.0 + n * (lift - 0.002);
    let material = Material {
        friction: mu,
        ..Material::default()
    };
    let mut w = world(
        vec![grain(shape, start.x, start.y, theta)],
        Walls {
            left: -100.0,
            right: 100.0,
            floor: -100.0,
        },
        vec![material],
        soft(),
    );
    w.wall_material = material;
    w.boundaries.push(boundary);
    let steps = (seconds / w.settings.step).round() as usize;
    let mut down = Vec::with_capacity(steps);
    for _ in 0..steps {
        w.step();
        down.push((start - w.bodies[0].center).dot(t));
    }
    down
}

#[test]
fn a_block_on_an_incline_below_its_friction_angle_stays_put() {
    let block = Superellipse::new([0.3, 0.2], [8.0, 8.0]).unwrap();
    let mu: f64 = 0.6;
    let theta = 0.8 * mu.atan();
    for surface in SURFACES {
        let down = on_incline(surface, block, theta, mu, 10.0);
        // Settling onto the slope takes a moment; after it, no creep.
        let settled = down[60];
        let drift = (down.last().unwrap() - settled).abs();
        assert!(
            drift < 1e-3,
            "{surface:?}: drifted {drift} down the slope in 9 s (tan theta {} < mu {mu})",
            theta.tan()
        );
    }
}

#[test]
fn a_block_above_its_friction_angle_slides_at_g_sin_minus_mu_cos() {
    let block = Superellipse::new([0.3, 0.2], [8.0, 8.0]).unwrap();
    let mu: f64 = 0.3;
    let theta: f64 = 0.5;
    for surface in SURFACES {
        let down = on_incline(surface, block, theta, mu, 1.5);
        // From 0.5 s to 1.5 s: s(t) = s0 + v0 t + a t^2 / 2, fitted from three samples.
        let h = 1.0 / 60.0;
        let (i0, i1, i2) = (20, 50, 80);
        let dt = (i1 - i0) as f64 * h;
        let a = (down[i2] - 2.0 * down[i1] + down[i0]) / (dt * dt);
        let want = G * (theta.sin() - mu * theta.cos());
        assert!(
            (a - want).abs() <= 0.02 * want,
            "{surface:?}: slid at {a}, g (sin - mu cos) = {want}"
        );
    }
}

#[test]
fn a_disk_rolls_down_an_incline_without_slipping_at_two_thirds_g_sin() {
    let theta: f64 = 0.4;
    let r = 0.3;
    for surface in SURFACES {
        let down = on_incline(surface, disk(r), theta, 0.8, 1.5);
        let h = 1.0 / 60.0;
        let (i0, i1, i2) = (20, 50, 80);
        let dt = (i1 - i0) as f64 * h;
        let a = (down[i2] - 2.0 * down[i1] + down[i0]) / (dt * dt);
        let want = 2.0 / 3.0 * G * theta.sin();
        assert!(
            (a - want).abs() <= 0.02 * want,
            "{surface:?}: rolled at {a}, (2/3) g sin theta = {want}"
        );
    }
}

/// Runs `w` for `seconds` and returns the largest distance any grain moved from its place
/// after the first two seconds (the stack, built touching, settling onto its contacts: each
/// block-block contact comes to overlap about 0.012, the slop and the faces' bulge at the
/// manifold's side points).
fn largest_motion(w: &mut World, seconds: f64) -> (usize, f64) {
    let settle = (2.0 / w.settings.step) as usize;
    for _ in 0..settle {
        w.step();
    }
    let start: Vec<Vec2> = w.bodies.iter().map(|b| b.center).collect();
    let steps = (seconds / w.settings.step) as usize;
    for _ in 0..steps {
        w.step();
    }
    w.bodies
        .iter()
        .zip(&start)
        .map(|(b, s)| (b.center - *s).norm())
        .enumerate()
        .fold((0, 0.0), |m, (i, d)| if d > m.1 { (i, d) } else { m })
}

#[test]
fn a_column_of_ten_blocks_stands() {
    let (hx, hy) = (0.3, 0.2);
    let block = Superellipse::new([hx, hy], [8.0, 8.0]).unwrap();
    let bodies = (0..10)
        .map(|k| grain(block, 0.0, hy + 2.0 * hy * k as f64, 0.0))
        .collect();
    let mut w = world(bodies, far_walls(), vec![Material::default()], soft());
    let (i, moved) = largest_motion(&mut w, 10.0);
    assert!(
        moved < 0.01 * 2.0 * hy,
        "block {i} moved {moved} in 10 s (1% of its size is {})",
        0.02 * hy
    );
}

/// Awake throughout (sleeping off): the manifolds alone must hold it. Before the patch search
/// walked the boundary by the polar angle (`contact/manifold.rs`), the side points jumped by
/// up to a tenth of a block between steps and the top rows crept sideways, 0.0096 in 10 s,
/// and the pyramid stood only because its grains fell asleep; now the largest motion is about
/// 1e-7. With sleeping on it stands too.
#[test]
fn a_pyramid_of_twenty_blocks_stands() {
    let (hx, hy) = (0.3, 0.2);
    let block = Superellipse::new([hx, hy], [8.0, 8.0]).unwrap();
    let mut bodies = Vec::new();
    // Rows of 6, 5, 4, 3, 2 (20 blocks), each on the gaps of the row below.
    for (row, n) in [6, 5, 4, 3, 2].into_iter().enumerate() {
        for k in 0..n {
            let x = (k as f64 - (n - 1) as f64 / 2.0) * 2.0 * hx * 1.02;
            bodies.push(grain(block, x, hy + 2.0 * hy * row as f64, 0.0));
        }
    }
    assert_eq!(bodies.len(), 20);
    let sleeping = Settings {
        sleep_radius: Settings::soft().sleep_radius,
        ..soft()
    };
    for settings in [soft(), sleeping] {
        let mut w = world(
            bodies.clone(),
            far_walls(),
            vec![Material::default()],
            settings,
        );
        let (i, moved) = largest_motion(&mut w, 10.0);
        assert!(
            moved < 0.01 * 2.0 * hy,
            "block {i} moved {moved} in 10 s (1% of its size is {}), sleeping {}",
            0.02 * hy,
            settings.sleep_radius > 0.0
        );
    }
}

#[test]
fn circles_by_the_analytic_narrow_phase_and_the_certified_one_agree() {
    // A small pile of disks: the two narrow phases find the same contacts, so the runs agree
    // to far below the grains' size.
    let run = |narrow_phase| {
        let bodies = (0..12)
            .map(|k| {
                grain(
                    disk(0.25),
                    -1.0 + 0.55 * (k % 4) as f64,
                    0.3 + 0.6 * (k / 4) as f64,
                    0.0,
                )
            })
            .collect();
        let mut w = world(
            bodies,
            Walls {
                left: -1.5,
                right: 1.5,
                floor: 0.0,
            },
            vec![Material::default()],
            Settings {
                narrow_phase,
                ..soft()
            },
        );
        for _ in 0..120 {
            w.step();
        }
        w.bodies.iter().map(|b| b.center).collect::<Vec<_>>()
    };
    let (a, b) = (run(NarrowPhase::Analytic), run(NarrowPhase::Interval));
    for (k, (p, q)) in a.iter().zip(&b).enumerate() {
        assert!((*p - *q).norm() < 0.02, "disk {k}: {p:?} vs {q:?}");
    }
}

#[test]
fn the_stress_of_a_column_at_rest_is_its_weight_on_its_contacts() {
    // Five blocks in a box as wide as they are: each contact carries the weight above it, so
    // sigma_yy = -(1/A) (sum over contacts of that weight times the branch vector's height).
    let (hx, hy) = (0.3, 0.2);
    let block = Superellipse::new([hx, hy], [8.0, 8.0]).unwrap();
    let n = 5;
    let bodies = (0..n)
        .map(|k| grain(block, 0.0, hy + 2.0 * hy * k as f64, 0.0))
        .collect();
    let walls = Walls {
        left: -1.0,
        right: 1.0,
        floor: 0.0,
    };
    // Asleep by islands, as the soft model's scenes sleep, so that the forces are settled.
    let settings = Settings {
        step: 1.0 / 60.0,
        ..Settings::soft()
    };
    let mut w = world(bodies, walls, vec![Material::default()], settings);
    while w.bodies.iter().any(|b| b.calm < settings.sleep_steps) {
        assert!(w.step < 2000, "the column is not asleep by step 2,000");
        w.step();
    }
    let [[sxx, sxy], [syx, syy]] = w.stress().expect("the soft model has forces");
    let weight = block.area() * G;
    let y: Vec<f64> = w.bodies.iter().map(|b| b.center.y).collect();
    // The floor's contact point is at the floor, up to the slop.
    let mut sum = n as f64 * weight * y[0];
    for k in 1..n {
        sum += (n - k) as f64 * weight * (y[k] - y[k - 1]);
    }
    let top = w.bodies[n - 1].bounding_box().max.y;
    let want = -sum / (2.0 * top);
    assert!(
        (syy - want).abs() <= 0.02 * want.abs(),
        "sigma_yy {syy}, the statics say {want}"
    );
    // (Awake, sleeping off, as this test ran until 2026-12-06, the column trembles at a few
    // thousandths of a unit a second and its shear swings between -0.018 and 0.018, 0.6% of
    // sigma_yy, from step to step: a step's impulses are not an equilibrium. Asleep by
    // islands, its forces are settled.)
    for s in [sxx, sxy, syx] {
        assert!(
            s.abs() <= 1e-3 * want.abs(),
            "a column has no shear or side stress: {s} (sigma_yy {syy}, want {want})"
        );
    }
    assert!(w.stress().is_some());
    let paper = World::from_parts(
        Vec::new(),
        walls,
        Settings::default(),
        0,
        5.0,
        Queue::default(),
    );
    assert_eq!(paper.stress(), None);
}

/// Sleeping by the soft model's radius (0.005, [`Settings::soft`]) holds nothing up: a disk
/// asleep in the hollow of two sleeping disks wakes and sinks when the left one creeps away,
/// by less than the radius a step (0.003). The top disk is frictionless against the two (its
/// friction is 0, and friction mixes by the geometric mean), so that nothing but their surfaces
/// can hold it: resting on them, its centre is at most `r + sqrt(4 r^2 - (d / 2)^2)` high for
/// their final distance `d`; a sleeper left in the air would stay 0.3 above that. The two
/// below hold to the floor (friction 0.6, rolling resistance 1).
#[test]
fn a_soft_sleeper_wakes_when_its_support_creeps_away() {
    let r: f64 = 0.5;
    // A hair apart, so that the two below rest without pushing on each other.
    let x = r + 0.005;
    let top = r + (4.0 * r * r - x * x).sqrt();
    let rough = Material {
        friction: 0.6,
        rolling_resistance: 1.0,
        ..Material::default()
    };
    let smooth = Material {
        friction: 0.0,
        restitution: 0.0,
        rolling_resistance: 0.0,
        ..Material::default()
    };
    let settings = Settings::soft();
    assert_eq!(settings.sleep_radius, 0.005);
    let mut w = world(
        vec![grain(disk(r), -x, r, 0.0), grain(disk(r), x, r, 0.0)],
        far_walls(),
        vec![rough, smooth],
        settings,
    );
    w.wall_material = rough;
    for _ in 0..settings.sleep_steps + 50 {
        w.step();
    }
    let mut above = grain(disk(r), 0.0, top, 0.0);
    above.group = 1;
    w.bodies.push(above);
    for _ in 0..settings.sleep_steps + 50 {
        w.step();
    }
    assert_eq!(w.asleep(), 3, "all three should sleep first");
    let start = w.bodies[2].center;
    assert!((start.y - top).abs() < 0.02, "top disk at {start:?}");
    let creep = 0.003;
    assert!(creep < settings.sleep_radius);
    w.bodies[0].calm = 0;
    for _ in 0..300 {
        w.bodies[0].velocity = Vec2::new(-creep / settings.step, 0.0);
        w.step();
    }
    for _ in 0..300 {
        w.step();
    }
    let d = (w.bodies[1].center - w.bodies[0].center).norm();
    assert!(d > 2.0 * x + 0.5, "the left disk crept {d}");
    let highest = r + (4.0 * r * r - 0.25 * d * d).max(0.0).sqrt();
    let y = w.bodies[2].center.y;
    assert!(
        y <= highest + 0.02,
        "the top disk stayed at {y}, above the {highest} the two below can hold it at (apart by {d})"
    );
}

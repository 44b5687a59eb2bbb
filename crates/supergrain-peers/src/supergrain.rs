//! The supergrain side: whatever `supergrain::world::World` stepping gives (the soft model, and
//! the paper's projection model as a baseline), on the same heap and the same pour as the peers. One thread runs the
//! scene's own settings; more cut the box into strips of the default width
//! ([`supergrain::solver::strips`]) projected in a rayon pool of that size.

use std::time::Instant;

use supergrain::body::{Body, Material};
use supergrain::geometry::Vec2;
use supergrain::settings::{Model, Settings, SoftSettings};
use supergrain::solver::strips::WIDTH_IN_RADII;
use supergrain::world::{RestCounter, Scene, SpawnRule, World};

use crate::overlap::{self, Resting};
use crate::run::{HeapTiming, PourTiming, median};
use crate::scene::{Grain, Rest, Shape};

pub const NAME: &str = "supergrain";
pub const SOFT: &str = "supergrain-soft";
pub const SOFT_STIFF: &str = "supergrain-soft-stiff";

/// The `max_overlap` (in `[solver]`, a fraction of the thinnest grain's thickness) that
/// [`SOFT_STIFF`] asks for: the documented setting for issue 40's bar (docs/physics.md,
/// "Overlap").
pub const MAX_OVERLAP: f64 = 0.01;

/// The soft step's settings in place of the paper's: Box2D's defaults (4 substeps, friction 0.6,
/// density 1, no damping), the same time step, and the soft model's sleep radius (the built-in
/// scenes set none; a radius a scene set would be replaced).
fn soft_settings(s: &mut Settings) {
    s.model = Model::Soft;
    s.soft = SoftSettings::default();
    s.sleep_radius = Settings::soft().sleep_radius;
}

/// A heap stepped by the soft model (the grains at rest, with the default material).
pub fn soft_world(heap: &World) -> World {
    let mut settings = heap.settings;
    soft_settings(&mut settings);
    let bodies = heap
        .bodies
        .iter()
        .map(|b| Body {
            velocity: Vec2::ZERO,
            angular_velocity: 0.0,
            ..*b
        })
        .collect();
    let mut w = World::from_parts(
        bodies,
        heap.walls,
        settings,
        0,
        heap.top,
        Default::default(),
    );
    w.materials = vec![Material::default()];
    w
}

/// A heap stepped by the paper's model, whatever model settled it (the built-in heaps were
/// poured by the soft one): the paper's sleep radius, as [`paper_scene`].
pub fn paper_world(heap: &World) -> World {
    let mut settings = heap.settings;
    settings.model = Model::Paper;
    settings.sleep_radius = Settings::default().sleep_radius;
    World::from_parts(
        heap.bodies.clone(),
        heap.walls,
        settings,
        0,
        heap.top,
        Default::default(),
    )
}

/// A scene poured by the paper's model (scene files now default to the soft one), by the spawn
/// rule the peers follow (`overlap.rs`: a blocked grain waits while later ones pass it).
pub fn paper_scene(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.settings.model = Model::Paper;
    // The built-in files say no model, so they were read with the soft model's defaults; the
    // paper's radius replaces the soft one (a radius a scene set would be replaced too).
    s.settings.sleep_radius = Settings::default().sleep_radius;
    s.spawn_rule = SpawnRule::Queue;
    s
}

/// [`soft_scene`] with the contact stiffness and substeps of the scene's own `[solver]` (as
/// its `max_overlap` set them) kept.
pub fn stiff_scene(scene: &Scene) -> Scene {
    let mut s = soft_scene(scene);
    s.settings.soft = scene.settings.soft;
    s
}

/// A scene poured by the soft model, with the default material everywhere, by the spawn rule
/// the peers follow (the soft model's own default, the fair rule, is not replicated on the
/// peers' side yet).
pub fn soft_scene(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.spawn_rule = SpawnRule::Queue;
    soft_settings(&mut s.settings);
    for g in &mut s.groups {
        g.material = Material::default();
    }
    s.wall_material = Material::default();
    s
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
        .expect("a thread pool")
}

/// Cut into strips for more than one thread.
fn threaded(world: &mut World, threads: usize) {
    if threads > 1 {
        let widest = world
            .bodies
            .iter()
            .map(|b| b.shape.bounding_radius())
            .chain(world.pending.iter().map(|p| p.shape.bounding_radius()))
            .fold(0.0, f64::max);
        world.settings.strip_width = WIDTH_IN_RADII * widest;
    }
}

/// A settled heap (a dump's world), every grain awake and sleeping off, stepped `warmup` steps
/// untimed and then `steps` timed, `reps` times from the heap: the median ms per step.
pub fn heap(heap: &World, threads: usize, warmup: u64, steps: u64, reps: usize) -> HeapTiming {
    let pool = pool(threads);
    let runs: Vec<f64> = (0..reps.max(1))
        .map(|_| {
            let mut world = supergrain::bench::tiled(heap, 1, heap.settings.broad_phase);
            threaded(&mut world, threads);
            pool.install(|| {
                for _ in 0..warmup {
                    world.step();
                }
                let start = Instant::now();
                for _ in 0..steps {
                    world.step();
                }
                start.elapsed().as_secs_f64() * 1e3 / steps.max(1) as f64
            })
        })
        .collect();
    HeapTiming {
        grains: heap.bodies.len(),
        ms_per_step: median(&runs),
        runs,
    }
}

/// A scene's pour from its empty box until rest ([`Rest`], measured as `run --until-rest`
/// does), timed whole.
pub fn pour(scene: &Scene, threads: usize, rest: &Rest) -> PourTiming {
    let mut world = World::new(scene);
    threaded(&mut world, threads);
    let grains = world.pending.len() as usize;
    let mut calm = RestCounter::default();
    pool(threads).install(|| {
        let start = Instant::now();
        let mut engine = std::time::Duration::ZERO;
        let mut steps = 0;
        let mut at_rest = false;
        while steps < rest.max_steps && !at_rest {
            let stepping = Instant::now();
            world.step();
            engine += stepping.elapsed();
            steps += 1;
            at_rest = calm.after_step(&rest.criterion(), &world);
        }
        PourTiming {
            grains,
            seconds: start.elapsed().as_secs_f64(),
            engine_seconds: engine.as_secs_f64(),
            steps,
            at_rest,
            overlap: resting(&world),
        }
    })
}

/// [`overlap::resting`] of a world's grains, as the peers' are measured.
fn resting(world: &World) -> Option<Resting> {
    let grains: Vec<Grain> = world
        .bodies
        .iter()
        .map(|b| {
            Some(Grain {
                shape: Shape::of(&b.shape).ok()?,
                x: b.center.x,
                y: b.center.y,
                angle: b.angle,
            })
        })
        .collect::<Option<_>>()?;
    overlap::resting(&grains, &world.walls.into())
}

//! `bench peers --scene drum` and `--scene tumbler`: grains in a turning container, in
//! supergrain's soft step (a `[[boundary]]` with `turn`) and in Box2D v3 (a kinematic body
//! with the container's shapes, turning at the same rate).
//!
//! **The drum** (issue 41's bar): a circle of radius 1, half filled with 160 disks of radii
//! 0.045-0.055 placed in a triangular lattice from its bottom up (the same places in both
//! engines), turning counter-clockwise. After `settle` seconds, the free surface's angle
//! ([`supergrain::measure::series::surface_line`]: the highest grain of each bin across the
//! middle 60% of the grains' width, a least-squares line) every 6 steps for `measure`
//! seconds; the drum's dynamic angle is their mean. In Box2D the circle is 120 capsules
//! around it, their inner surface on the circle (a chord's sag is 3e-4 of the radius).
//! Friction on grains and drum alike, restitution 0, no rolling resistance, density 1, 60 Hz,
//! 4 substeps, sleeping off.
//!
//! **The tumbler** (Box2D's benchmark app's scene, `CreateTumbler`): a box of walls 1 thick
//! whose inner faces are 19 apart, about `(0, 10)`, turning at 25 degrees per second, and 45 x
//! 45 = 2,025 squares of side 0.25 on a grid 0.4 apart; 60 Hz, 4 substeps, Box2D's materials
//! (friction 0.6, density 1). Box2D's app turns the box with a motor joint on a dynamic body of
//! density 50; here both engines turn it kinematically at the same rate. supergrain's squares
//! are superellipses of exponent [`TUMBLER_EXPONENT`], its walls four thick segments (a closed
//! polyline). Timed: the mean time per step over `steps` steps from the start, median of
//! `reps`.

use std::time::Instant;

use boxdd::{
    BodyBuilder, BodyType, Foundation, Position, ShapeDef, SurfaceMaterial, Vec2 as BVec2,
    WorkerCount, WorldBuilder, shapes,
};
use supergrain::body::{Body, Drive, Material, Walls};
use supergrain::geometry::{Aabb, Vec2};
use supergrain::measure::series::surface_line;
use supergrain::settings::{Model, Settings, SoftSettings, SolverTable};
use supergrain::shape::{Boundary, Pose, Superellipse};
use supergrain::world::World;

use crate::peer::Error;
use crate::run::{HeapTiming, median};

fn err(e: boxdd::Error) -> Error {
    Error(format!("Box2D: {e}"))
}

/// 60 Hz and 4 substeps, as Box2D's samples and benchmarks run.
pub const STEP: f64 = 1.0 / 60.0;
pub const SUBSTEPS: u32 = 4;

/// The drum's rates (degrees per second: Froude numbers `w^2 R / g` of 0.001, 0.01 and 0.09,
/// the rolling regime to the cascading one) and frictions.
pub const DRUM_RATES: [f64; 3] = [6.0, 18.0, 54.0];
pub const DRUM_FRICTIONS: [f64; 2] = [0.3, 0.6];

/// The tumbler's squares' exponent in supergrain: blocky enough that a square's area is 98%
/// of the box's (exponent 10: 0.97; 20: 0.99).
pub const TUMBLER_EXPONENT: f64 = 16.0;

/// The drum: where and how big, its grains, and how long to run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drum {
    pub radius: f64,
    pub grain_radius: [f64; 2],
    /// Disks: 160 of mean radius 0.05 fill half a drum of radius 1 at a packing of 0.8.
    pub count: usize,
    pub seed: u64,
    /// Seconds before the surface is measured, and seconds measured.
    pub settle: f64,
    pub measure: f64,
}

impl Default for Drum {
    fn default() -> Self {
        Drum {
            radius: 1.0,
            grain_radius: [0.045, 0.055],
            count: 160,
            seed: 1,
            settle: 4.0,
            measure: 10.0,
        }
    }
}

/// A small deterministic generator for the radii (the engines must get the same grains).
fn radii(seed: u64, n: usize, [lo, hi]: [f64; 2]) -> Vec<f64> {
    let mut s = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            lo + (hi - lo) * ((s >> 11) as f64 / (1u64 << 53) as f64)
        })
        .collect()
}

impl Drum {
    /// The grains' centres and radii: [`Drum::count`] places of a triangular lattice of the
    /// largest diameter (and a hair), filled row by row from the drum's bottom, one diameter
    /// off its wall. Settled, they fill about half the drum.
    pub fn grains(&self) -> Vec<(Vec2, f64)> {
        let d = 2.0 * self.grain_radius[1] * 1.01;
        let mut places = Vec::new();
        let mut j = 0;
        while places.len() < self.count {
            let y = -self.radius + d + f64::from(j) * d * 0.866;
            if y > self.radius - d {
                break;
            }
            let shift = if j % 2 == 0 { 0.0 } else { 0.5 * d };
            j += 1;
            let reach = (self.radius - d).powi(2) - y * y;
            if reach <= 0.0 {
                continue;
            }
            // On the lattice's columns, so that every neighbour is a diameter away.
            let half = reach.sqrt();
            let mut x = shift - d * ((half + shift) / d).floor();
            while x <= half && places.len() < self.count {
                places.push(Vec2::new(x, y));
                x += d;
            }
        }
        let r = radii(self.seed, places.len(), self.grain_radius);
        places.into_iter().zip(r).collect()
    }

    fn steps(&self) -> (u64, u64) {
        (
            (self.settle / STEP).round() as u64,
            (self.measure / STEP).round() as u64,
        )
    }
}

/// One engine's drum: stepped, and its grains' boxes read.
trait Turning {
    fn step(&mut self) -> Result<(), Error>;
    fn boxes(&mut self) -> Result<Vec<Aabb>, Error>;
}

/// Runs a drum and returns the mean surface angle (degrees) and the number of samples.
fn measure_drum(drum: &Drum, engine: &mut dyn Turning) -> Result<(f64, usize), Error> {
    let (settle, measured) = drum.steps();
    for _ in 0..settle {
        engine.step()?;
    }
    let mut angles = Vec::new();
    for k in 0..measured {
        engine.step()?;
        if k % 6 == 0
            && let Some((deg, _)) = surface_line(&engine.boxes()?)
        {
            angles.push(deg);
        }
    }
    if angles.is_empty() {
        return Err(Error("the drum's surface could not be fitted".into()));
    }
    Ok((
        angles.iter().sum::<f64>() / angles.len() as f64,
        angles.len(),
    ))
}

struct Ours(World);

impl Turning for Ours {
    fn step(&mut self) -> Result<(), Error> {
        self.0.step();
        Ok(())
    }

    fn boxes(&mut self) -> Result<Vec<Aabb>, Error> {
        Ok(self.0.bodies.iter().map(Body::bounding_box).collect())
    }
}

fn soft_settings() -> Settings {
    Settings {
        model: Model::Soft,
        step: STEP,
        sleep_radius: 0.0,
        soft: SoftSettings {
            substeps: SUBSTEPS,
            ..SoftSettings::default()
        },
        ..Settings::soft()
    }
}

/// supergrain's world for a turning container: `bodies`, the boundaries turning about `pivot`
/// at `rate` degrees per second, `material` for grains and boundaries, the box far away.
fn ours(
    bodies: Vec<Body>,
    boundaries: Vec<Boundary>,
    pivot: Vec2,
    rate: f64,
    material: Material,
    far: f64,
    settings: Settings,
) -> World {
    let walls = Walls {
        left: pivot.x - far,
        right: pivot.x + far,
        floor: pivot.y - far,
    };
    let mut w = World::from_parts(
        bodies,
        walls,
        settings,
        0,
        pivot.y + far,
        Default::default(),
    );
    w.materials = vec![material];
    w.wall_material = material;
    w.drives = vec![
        Drive {
            turn: Some((pivot, rate)),
            ..Drive::default()
        };
        boundaries.len()
    ];
    w.bases.clone_from(&boundaries);
    w.boundaries = boundaries;
    w
}

/// supergrain's dynamic drum angle for friction `mu` at `rate` degrees per second, its soft
/// step's settings the bench's with `overrides` over them (`bench peers --set`).
pub fn drum_supergrain(
    drum: &Drum,
    mu: f64,
    rate: f64,
    overrides: &SolverTable,
) -> Result<(f64, usize), Error> {
    let mut settings = soft_settings();
    overrides
        .apply(&mut settings)
        .and_then(|()| settings.validate())
        .map_err(Error)?;
    let bodies = drum
        .grains()
        .into_iter()
        .map(|(c, r)| {
            let shape = Superellipse::circle(r).map_err(|e| Error(e.to_string()))?;
            Ok(Body::at_rest(
                shape,
                &Pose::new(c, 0.0).map_err(|e| Error(e.to_string()))?,
            ))
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let drum_shape =
        Boundary::circle(Vec2::ZERO, drum.radius, true).map_err(|e| Error(e.to_string()))?;
    let material = Material {
        friction: mu,
        ..Material::default()
    };
    let world = ours(
        bodies,
        vec![drum_shape],
        Vec2::ZERO,
        rate,
        material,
        2.0 * drum.radius,
        settings,
    );
    measure_drum(drum, &mut Ours(world))
}

/// Box2D's world and its grains.
struct Theirs {
    world: boxdd::World,
    grains: Vec<(boxdd::BodyId, f64)>,
}

impl Turning for Theirs {
    fn step(&mut self) -> Result<(), Error> {
        let done = self.world.step(STEP as f32, SUBSTEPS as i32).map_err(err)?;
        match done.post_step_error() {
            Some(e) => Err(err(e)),
            None => Ok(()),
        }
    }

    fn boxes(&mut self) -> Result<Vec<Aabb>, Error> {
        let mut out = Vec::with_capacity(self.grains.len());
        for &(id, r) in &self.grains {
            let p = self.world.body(id).map_err(err)?.position().map_err(err)?;
            let c = Vec2::new(f64::from(p.x), f64::from(p.y));
            out.push(Aabb::point(c).grown(r));
        }
        Ok(out)
    }
}

/// Box2D's world with gravity, on `threads` workers, sleeping off, and a shape definition of
/// `mu` (density 1, restitution 0).
fn box2d_world(
    threads: usize,
    mu: f64,
    sleep: bool,
) -> Result<(&'static Foundation, boxdd::World, ShapeDef), Error> {
    let foundation = Foundation::initialize_default().map_err(err)?;
    let workers = WorkerCount::new(u32::try_from(threads).unwrap_or(u32::MAX)).map_err(err)?;
    let def = WorldBuilder::from(foundation.world_def())
        .gravity(BVec2::new(0.0, -9.8))
        .enable_sleep(sleep)
        .worker_count(workers)
        .build()
        .map_err(err)?;
    let world = foundation.create_world(def).map_err(err)?;
    let material = SurfaceMaterial::new()
        .with_friction(mu as f32)
        .and_then(|m| m.with_restitution(0.0))
        .map_err(err)?;
    let shape_def = ShapeDef::builder()
        .material(material)
        .density(1.0)
        .build()
        .map_err(err)?;
    Ok((foundation, world, shape_def))
}

/// A kinematic body at `pivot` turning at `rate` degrees per second.
fn turning_body(
    foundation: &Foundation,
    world: &mut boxdd::World,
    pivot: Vec2,
    rate: f64,
) -> Result<boxdd::BodyId, Error> {
    let def = BodyBuilder::from(foundation.body_def())
        .body_type(BodyType::Kinematic)
        .position(Position::new(pivot.x as f32, pivot.y as f32))
        .angular_velocity(rate.to_radians() as f32)
        .build()
        .map_err(err)?;
    world.create_body(def).map_err(err)
}

/// Capsules around the drum.
pub const DRUM_CAPSULES: usize = 120;

/// Box2D's dynamic drum angle for friction `mu` at `rate` degrees per second.
pub fn drum_box2d(drum: &Drum, mu: f64, rate: f64) -> Result<(f64, usize), Error> {
    let (foundation, mut world, shape_def) = box2d_world(1, mu, false)?;
    let body = turning_body(foundation, &mut world, Vec2::ZERO, rate)?;
    // Capsules of radius `t` whose inner surface touches the circle at each chord's middle.
    let t = 0.05 * drum.radius;
    let n = DRUM_CAPSULES;
    let half = std::f64::consts::PI / n as f64;
    let core = (drum.radius + t) / half.cos();
    for k in 0..n {
        let (a0, a1) = (2.0 * half * k as f64, 2.0 * half * (k + 1) as f64);
        let p = |a: f64| [(core * a.cos()) as f32, (core * a.sin()) as f32];
        let capsule = shapes::capsule(p(a0), p(a1), t as f32).map_err(err)?;
        world
            .body(body)
            .map_err(err)?
            .create_capsule(&shape_def, &capsule)
            .map_err(err)?;
    }
    let mut grains = Vec::new();
    for (c, r) in drum.grains() {
        let def = BodyBuilder::from(foundation.body_def())
            .body_type(BodyType::Dynamic)
            .position(Position::new(c.x as f32, c.y as f32))
            .build()
            .map_err(err)?;
        let id = world.create_body(def).map_err(err)?;
        let circle = shapes::circle([0.0, 0.0], r as f32).map_err(err)?;
        world
            .body(id)
            .map_err(err)?
            .create_circle(&shape_def, &circle)
            .map_err(err)?;
        grains.push((id, r));
    }
    measure_drum(drum, &mut Theirs { world, grains })
}

/// The tumbler's grid of square centres (Box2D's `CreateTumbler`).
pub fn tumbler_grid() -> Vec<Vec2> {
    let n = 45;
    let mut out = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            out.push(Vec2::new(
                -0.2 * n as f64 + 0.4 * j as f64,
                -0.2 * n as f64 + 10.0 + 0.4 * i as f64,
            ));
        }
    }
    out
}

/// The tumbler's centre, its walls' half thickness and the middle of its walls from the
/// centre, and its rate.
const TUMBLER_CENTRE: Vec2 = Vec2::new(0.0, 10.0);
const TUMBLER_WALL: f64 = 0.5;
const TUMBLER_HALF: f64 = 10.0;
const TUMBLER_RATE: f64 = 25.0;

/// supergrain's tumbler (squares of [`TUMBLER_EXPONENT`]), stepped `steps` times `reps` times.
pub fn tumbler_supergrain(threads: usize, steps: u64, reps: usize) -> Result<HeapTiming, Error> {
    let square = Superellipse::new([0.125, 0.125], [TUMBLER_EXPONENT; 2])
        .map_err(|e| Error(e.to_string()))?;
    let (c, h) = (TUMBLER_CENTRE, TUMBLER_HALF);
    let corners = [
        Vec2::new(c.x - h, c.y - h),
        Vec2::new(c.x + h, c.y - h),
        Vec2::new(c.x + h, c.y + h),
        Vec2::new(c.x - h, c.y + h),
    ];
    let walls = (0..4)
        .map(|k| Boundary::segment(corners[k], corners[(k + 1) % 4], 2.0 * TUMBLER_WALL))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| Error(e.to_string()))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
        .map_err(|e| Error(e.to_string()))?;
    let mut runs = Vec::new();
    for _ in 0..reps.max(1) {
        let bodies = tumbler_grid()
            .into_iter()
            .map(|p| Body::at_rest(square, &Pose::new(p, 0.0).expect("a finite place")))
            .collect();
        let mut world = ours(
            bodies,
            walls.clone(),
            c,
            TUMBLER_RATE,
            Material::default(),
            1.5 * h * std::f64::consts::SQRT_2,
            soft_settings(),
        );
        world.settings.sleep_radius = Settings::soft().sleep_radius;
        runs.push(pool.install(|| {
            let start = Instant::now();
            for _ in 0..steps {
                world.step();
            }
            start.elapsed().as_secs_f64() * 1e3 / steps.max(1) as f64
        }));
    }
    Ok(HeapTiming {
        grains: 45 * 45,
        ms_per_step: median(&runs),
        runs,
    })
}

/// Box2D's tumbler, stepped `steps` times `reps` times.
pub fn tumbler_box2d(threads: usize, steps: u64, reps: usize) -> Result<HeapTiming, Error> {
    let mut runs = Vec::new();
    for _ in 0..reps.max(1) {
        // Sleeping on, as in Box2D's app (and in supergrain's run): in a turning box nothing
        // sleeps for long.
        let (foundation, mut world, shape_def) = box2d_world(threads, 0.6, true)?;
        let body = turning_body(foundation, &mut world, TUMBLER_CENTRE, TUMBLER_RATE)?;
        let (h, t) = (TUMBLER_HALF as f32, TUMBLER_WALL as f32);
        for (cx, cy, hx, hy) in [
            (h, 0.0, t, h),
            (-h, 0.0, t, h),
            (0.0, h, h, t),
            (0.0, -h, h, t),
        ] {
            let polygon = shapes::polygon_from_points(
                [
                    [cx - hx, cy - hy],
                    [cx + hx, cy - hy],
                    [cx + hx, cy + hy],
                    [cx - hx, cy + hy],
                ],
                0.0,
            )
            .map_err(err)?;
            world
                .body(body)
                .map_err(err)?
                .create_polygon(&shape_def, &polygon)
                .map_err(err)?;
        }
        let square = shapes::box_polygon(0.125, 0.125).map_err(err)?;
        for p in tumbler_grid() {
            let def = BodyBuilder::from(foundation.body_def())
                .body_type(BodyType::Dynamic)
                .position(Position::new(p.x as f32, p.y as f32))
                .build()
                .map_err(err)?;
            let id = world.create_body(def).map_err(err)?;
            world
                .body(id)
                .map_err(err)?
                .create_polygon(&shape_def, &square)
                .map_err(err)?;
        }
        let mut theirs = Theirs {
            world,
            grains: Vec::new(),
        };
        let start = Instant::now();
        for _ in 0..steps {
            theirs.step()?;
        }
        runs.push(start.elapsed().as_secs_f64() * 1e3 / steps.max(1) as f64);
    }
    Ok(HeapTiming {
        grains: 45 * 45,
        ms_per_step: median(&runs),
        runs,
    })
}

//! Box2D v3 (the boxdd crate, built from source): the neutral scene as static boxes for the walls
//! and the floor and one dynamic body per grain, stepped with `b2World_Step` and its substeps.
//! Threads are Box2D's own scheduler (`workerCount` in the world definition).

use boxdd::{
    BodyBuilder, BodyId, BodyType, Foundation, Position, ShapeDef, ShapeId, SurfaceMaterial, Vec2,
    WorkerCount, World, WorldBuilder, shapes,
};

use crate::peer::{Error, Peer, wall_boxes};
use crate::scene::{Grain, Scene, Shape};

/// Box2D's `B2_SPECULATIVE_DISTANCE`, four linear slops of 0.005 (one length unit per metre).
const SPECULATIVE_DISTANCE: f32 = 4.0 * 0.005;

fn err(e: boxdd::Error) -> Error {
    Error(format!("Box2D: {e}"))
}

pub struct Box2d {
    foundation: &'static Foundation,
    world: World,
    shape_def: ShapeDef,
    time_step: f32,
    substeps: i32,
    grains: Vec<(BodyId, ShapeId, Shape)>,
}

impl Peer for Box2d {
    const NAME: &'static str = "box2d-v3";

    fn new(scene: &Scene, threads: usize, sleep: bool) -> Result<Self, Error> {
        let foundation = Foundation::initialize_default().map_err(err)?;
        let workers = WorkerCount::new(u32::try_from(threads).unwrap_or(u32::MAX)).map_err(err)?;
        let def = WorldBuilder::from(foundation.world_def())
            .gravity(Vec2::new(0.0, -scene.gravity as f32))
            .enable_sleep(sleep)
            .worker_count(workers)
            .build()
            .map_err(err)?;
        let mut world = foundation.create_world(def).map_err(err)?;
        let shape_def = |friction: f64, rolling_resistance: f64| {
            let material = SurfaceMaterial::new()
                .with_friction(friction as f32)
                .and_then(|m| m.with_restitution(scene.restitution as f32))
                .and_then(|m| m.with_rolling_resistance(rolling_resistance as f32))
                .map_err(err)?;
            ShapeDef::builder()
                .material(material)
                .density(scene.density as f32)
                .build()
                .map_err(err)
        };
        let wall_def = shape_def(scene.wall_friction, scene.wall_rolling_resistance)?;
        let shape_def = shape_def(scene.friction, scene.rolling_resistance)?;
        for (c, h) in wall_boxes(scene) {
            let body = world
                .create_body(
                    BodyBuilder::from(foundation.body_def())
                        .position(Position::new(c[0] as f32, c[1] as f32))
                        .build()
                        .map_err(err)?,
                )
                .map_err(err)?;
            let polygon = shapes::box_polygon(h[0] as f32, h[1] as f32).map_err(err)?;
            world
                .body(body)
                .map_err(err)?
                .create_polygon(&wall_def, &polygon)
                .map_err(err)?;
        }
        let mut peer = Box2d {
            foundation,
            world,
            shape_def,
            time_step: scene.time_step as f32,
            substeps: scene.substeps as i32,
            grains: Vec::with_capacity(scene.grain_count()),
        };
        for g in &scene.grains {
            peer.add(g)?;
        }
        Ok(peer)
    }

    fn add(&mut self, g: &Grain) -> Result<(), Error> {
        let def = BodyBuilder::from(self.foundation.body_def())
            .body_type(BodyType::Dynamic)
            .position(Position::new(g.x as f32, g.y as f32))
            .angle(g.angle as f32)
            .build()
            .map_err(err)?;
        let id = self.world.create_body(def).map_err(err)?;
        let mut body = self.world.body(id).map_err(err)?;
        let shape = match g.shape {
            Shape::Circle { radius } => {
                let circle = shapes::circle([0.0, 0.0], radius as f32).map_err(err)?;
                body.create_circle(&self.shape_def, &circle).map_err(err)?
            }
            Shape::Capsule {
                half_length: h,
                radius,
                along_y,
            } => {
                let h = h as f32;
                let (a, b) = if along_y {
                    ([0.0, -h], [0.0, h])
                } else {
                    ([-h, 0.0], [h, 0.0])
                };
                let capsule = shapes::capsule(a, b, radius as f32).map_err(err)?;
                body.create_capsule(&self.shape_def, &capsule)
                    .map_err(err)?
            }
            Shape::RoundedBox {
                half_extents: [a, b],
                radius,
            } => {
                // Box2D's rounded box adds the radius around the box it is given.
                let polygon = shapes::rounded_box_polygon(
                    (a - radius) as f32,
                    (b - radius) as f32,
                    radius as f32,
                )
                .map_err(err)?;
                body.create_polygon(&self.shape_def, &polygon)
                    .map_err(err)?
            }
        };
        self.grains.push((id, shape, g.shape));
        Ok(())
    }

    fn step(&mut self) -> Result<(), Error> {
        let done = self
            .world
            .step(self.time_step, self.substeps)
            .map_err(err)?;
        match done.post_step_error() {
            Some(e) => Err(err(e)),
            None => Ok(()),
        }
    }

    fn grains(&mut self, out: &mut Vec<Grain>) -> Result<(), Error> {
        out.clear();
        for &(id, _, shape) in &self.grains {
            let body = self.world.body(id).map_err(err)?;
            let p = body.position().map_err(err)?;
            let angle = body.rotation().map_err(err)?.angle();
            out.push(Grain {
                shape,
                x: f64::from(p.x),
                y: f64::from(p.y),
                angle: f64::from(angle),
            });
        }
        Ok(())
    }

    fn fastest(&mut self) -> Result<f64, Error> {
        if self.world.awake_body_count().map_err(err)? == 0 {
            return Ok(0.0);
        }
        let mut fastest = 0.0f64;
        for &(id, _, _) in &self.grains {
            let v = self
                .world
                .body(id)
                .map_err(err)?
                .linear_velocity()
                .map_err(err)?;
            fastest = fastest.max(f64::from(v.x).hypot(f64::from(v.y)));
        }
        Ok(fastest)
    }

    fn area(&mut self) -> Result<f64, Error> {
        let density = f64::from(self.shape_def_density());
        let mut mass = 0.0;
        for &(id, _, _) in &self.grains {
            mass += f64::from(self.world.body(id).map_err(err)?.mass().map_err(err)?);
        }
        Ok(mass / density)
    }

    fn bounds(&mut self, i: usize) -> Result<[f64; 4], Error> {
        // The shape's box, which Box2D widens by its speculative distance on every side.
        let (_, shape, _) = self.grains[i];
        let aabb = self.world.shape(shape).map_err(err)?.aabb().map_err(err)?;
        let (lo, hi) = (aabb.lower(), aabb.upper());
        let s = SPECULATIVE_DISTANCE;
        Ok([lo.x + s, lo.y + s, hi.x - s, hi.y - s].map(f64::from))
    }

    fn len(&self) -> usize {
        self.grains.len()
    }
}

impl Box2d {
    fn shape_def_density(&self) -> f32 {
        self.shape_def.density()
    }
}

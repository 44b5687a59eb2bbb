//! rapier2d: the neutral scene as fixed cuboids for the walls and the floor and one dynamic body
//! per grain, in a `PhysicsWorld`; its solver iterations are its substeps. Threads: rapier's
//! `parallel` feature, in a pool of the given size.

use rapier2d::prelude::*;

use crate::peer::{Error, Peer, wall_boxes};
use crate::scene::{Grain, Scene, Shape};

pub struct Rapier {
    world: PhysicsWorld,
    friction: f32,
    restitution: f32,
    density: f32,
    sleep: bool,
    grains: Vec<(RigidBodyHandle, Shape)>,
}

impl Peer for Rapier {
    const NAME: &'static str = "rapier2d";

    fn new(scene: &Scene, threads: usize, sleep: bool) -> Result<Self, Error> {
        if scene.rolling_resistance > 0.0 || scene.wall_rolling_resistance > 0.0 {
            return Err(Error(
                "rapier2d has no rolling resistance (the scene asks for it)".into(),
            ));
        }
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, -scene.gravity as f32);
        world.integration_parameters.dt = scene.time_step as f32;
        world.integration_parameters.num_solver_iterations = scene.substeps as usize;
        world
            .physics_pipeline
            .configure_thread_pool(threads)
            .map_err(|e| Error(format!("rapier: a pool of {threads} threads: {e}")))?;
        let mut peer = Rapier {
            world,
            friction: scene.friction as f32,
            restitution: scene.restitution as f32,
            density: scene.density as f32,
            sleep,
            grains: Vec::with_capacity(scene.grain_count()),
        };
        for (c, h) in wall_boxes(scene) {
            let body = RigidBodyBuilder::fixed().translation(Vector::new(c[0] as f32, c[1] as f32));
            let collider = ColliderBuilder::cuboid(h[0] as f32, h[1] as f32)
                .friction(scene.wall_friction as f32)
                .restitution(peer.restitution);
            peer.world.insert(body, collider);
        }
        for g in &scene.grains {
            peer.add(g)?;
        }
        Ok(peer)
    }

    fn add(&mut self, g: &Grain) -> Result<(), Error> {
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(g.x as f32, g.y as f32))
            .rotation(g.angle as f32)
            .can_sleep(self.sleep);
        let collider = match g.shape {
            Shape::Circle { radius } => ColliderBuilder::ball(radius as f32),
            Shape::Capsule {
                half_length,
                radius,
                along_y,
            } => {
                if along_y {
                    ColliderBuilder::capsule_y(half_length as f32, radius as f32)
                } else {
                    ColliderBuilder::capsule_x(half_length as f32, radius as f32)
                }
            }
            // The round cuboid, like Box2D's rounded box, adds the radius around its cuboid.
            Shape::RoundedBox {
                half_extents: [a, b],
                radius,
            } => ColliderBuilder::round_cuboid(
                (a - radius) as f32,
                (b - radius) as f32,
                radius as f32,
            ),
        }
        .density(self.density)
        .friction(self.friction)
        .restitution(self.restitution);
        let (handle, _) = self.world.insert(body, collider);
        self.grains.push((handle, g.shape));
        Ok(())
    }

    fn step(&mut self) -> Result<(), Error> {
        self.world.step();
        Ok(())
    }

    fn grains(&mut self, out: &mut Vec<Grain>) -> Result<(), Error> {
        out.clear();
        out.extend(self.grains.iter().map(|&(h, shape)| {
            let b = &self.world.bodies[h];
            let p = b.translation();
            Grain {
                shape,
                x: f64::from(p.x),
                y: f64::from(p.y),
                angle: f64::from(b.rotation().angle()),
            }
        }));
        Ok(())
    }

    fn fastest(&mut self) -> Result<f64, Error> {
        Ok(self
            .grains
            .iter()
            .map(|&(h, _)| f64::from(self.world.bodies[h].linvel().length()))
            .fold(0.0, f64::max))
    }

    fn area(&mut self) -> Result<f64, Error> {
        let mass: f64 = self
            .grains
            .iter()
            .map(|&(h, _)| f64::from(self.world.bodies[h].mass()))
            .sum();
        Ok(mass / f64::from(self.density))
    }

    fn bounds(&mut self, i: usize) -> Result<[f64; 4], Error> {
        let (h, _) = self.grains[i];
        let collider = self.world.bodies[h].colliders()[0];
        let aabb = self.world.colliders[collider].compute_aabb();
        Ok([aabb.mins.x, aabb.mins.y, aabb.maxs.x, aabb.maxs.y].map(f64::from))
    }

    fn len(&self) -> usize {
        self.grains.len()
    }
}

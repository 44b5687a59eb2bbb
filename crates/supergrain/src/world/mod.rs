//! The world: grains in an open box, grains appearing at the top over time (paper III), and the
//! solver stepping them. It knows nothing of pixels or files.

pub mod checks;
mod rest;
mod scene;
mod sink;
mod spawn;

use std::sync::atomic::{AtomicBool, Ordering};

pub use rest::{Rest, RestCounter};
pub use scene::{Group, PRESETS, Placed, Range, Scene, SceneError};
pub use sink::Sink;
pub use spawn::{
    BAND_IN_RADII, Fair, Generator, Pending, Queue, SpawnRule, TRIES_PER_STEP, narrowed,
};

use crate::body::{Body, BodyId, Drive, Driver, Material, WallMotion, Walls};
use crate::broad_phase::{Any as AnyBroadPhase, BroadPhase, Grid};
use crate::contact::{Penetration, WallPenetration};
use crate::geometry::{Aabb, Vec2};
use crate::measure::series::Series;
use crate::settings::{Model, Settings};
use crate::shape::{Boundary, Pose};
use crate::solver::soft::{self, SoftWorkspace};
use crate::solver::{self, StepStats, Stopped, Workspace};

/// Grains, walls, settings and the spawn queue.
#[derive(Debug)]
pub struct World {
    pub bodies: Vec<Body>,
    pub walls: Walls,
    pub settings: Settings,
    /// Steps done.
    pub step: u64,
    /// Height at which grains appear.
    pub top: f64,
    /// The grains still to appear.
    pub pending: Queue,
    /// Each scene group's material, by [`Body::group`] (the soft step's; see
    /// [`Material`]).
    pub materials: Vec<Material>,
    pub wall_material: Material,
    /// Boundaries besides the box's three walls (planes at any angle, thick segments, arcs,
    /// drums; a polyline is one per segment), of the wall material; the soft step's (the
    /// paper's projection has the box alone).
    pub boundaries: Vec<Boundary>,
    /// How each boundary is driven (still for most), and where it was at step 0: where it is
    /// at any step is a closed form of that ([`Drive::place`]).
    pub drives: Vec<Drive>,
    pub bases: Vec<Boundary>,
    /// The driven grains ([`BodyKind::Kinematic`]): each one's place at step 0 and drive; where
    /// it is at any step is a closed form of that ([`Drive::pose_at`]).
    pub drivers: Vec<Driver>,
    /// The time at step `.0` was `.1`: the clock restarts there when the time step changes
    /// ([`World::set_step`]), so that time runs on without a jump. `(0, 0.0)` until then.
    pub clock: (u64, f64),
    /// The soft step's contacts kept from step to step, and its buffers.
    pub soft: SoftWorkspace,
    /// The id the next body to join gets ([`BodyId`]: never given twice).
    next_id: BodyId,
    /// Where grains leave, and how many have (`[[sink]]`).
    pub sinks: Vec<Sink>,
    /// Measures taken as the run goes (`[[measure]]`), kept here so that dumps carry them.
    pub measures: Vec<Series>,
    /// Where each grain was when the last step began (see [`World::velocity`]).
    step_start: Vec<Vec2>,
    broad: AnyBroadPhase,
    work: Workspace,
    undo: Undo,
}

/// What a step changes in the world, kept by [`World::step_or_stop`] to put it back when the
/// step is abandoned (the broad phase and the workspace are rebuilt by every step).
#[derive(Debug, Default)]
struct Undo {
    bodies: Vec<Body>,
    next_id: BodyId,
    step_start: Vec<Vec2>,
    /// What the step's spawn changed in the queue.
    spawned: spawn::Taken,
}

impl World {
    /// The world of a scene at step 0: no grain yet, every grain of the scene still to draw
    /// (from the scene's seed, each when it is due, see [`Queue`]).
    pub fn new(scene: &Scene) -> World {
        let mut world = World {
            bodies: Vec::new(),
            walls: scene.walls,
            settings: scene.settings,
            step: 0,
            top: scene.top,
            pending: Queue::new(scene),
            materials: scene.groups.iter().map(|g| g.material).collect(),
            wall_material: scene.wall_material,
            boundaries: scene.boundaries.clone(),
            drives: scene.drives.clone(),
            bases: scene.boundaries.clone(),
            drivers: Vec::new(),
            clock: (0, 0.0),
            soft: SoftWorkspace::default(),
            next_id: BodyId(0),
            sinks: scene.sinks.clone(),
            measures: scene.measures.clone(),
            step_start: Vec::new(),
            broad: AnyBroadPhase::new(scene.settings.broad_phase),
            work: Workspace::default(),
            undo: Undo::default(),
        };
        // The placed grains, in the file's order: ids 0, 1, ...
        for g in &scene.grains {
            let mut body = g.body();
            if scene.settings.model == Model::Paper {
                // Verlet's velocity is the step's displacement.
                let h = scene.settings.step;
                body.previous_center = body.center - g.velocity * h;
                body.previous_angle = body.angle - g.angular_velocity * h;
                (body.velocity, body.angular_velocity) = (Vec2::ZERO, 0.0);
            }
            let id = world.add(body);
            if let Some(drive) = g.drive {
                world.drivers.push(Driver {
                    id,
                    base: body.pose(),
                    drive,
                });
            }
        }
        world
    }

    /// A world from its parts (a restart from a dump). Bodies keep their ids; those not yet
    /// named ([`BodyId::NEW`]) are named in order, after the largest id given.
    pub fn from_parts(
        bodies: Vec<Body>,
        walls: Walls,
        settings: Settings,
        step: u64,
        top: f64,
        pending: Queue,
    ) -> World {
        let next_id = BodyId::after(bodies.iter().map(|b| b.id));
        let mut world = World {
            step_start: bodies.iter().map(|b| b.center).collect(),
            bodies,
            walls,
            settings,
            step,
            top,
            pending,
            materials: Vec::new(),
            wall_material: Material::default(),
            boundaries: Vec::new(),
            drives: Vec::new(),
            bases: Vec::new(),
            drivers: Vec::new(),
            clock: (0, 0.0),
            soft: SoftWorkspace::default(),
            next_id,
            sinks: Vec::new(),
            measures: Vec::new(),
            broad: AnyBroadPhase::new(settings.broad_phase),
            work: Workspace::default(),
            undo: Undo::default(),
        };
        world.name_new();
        world
    }

    /// The id the next body to join will get.
    pub fn next_id(&self) -> BodyId {
        self.next_id
    }

    /// Ids from `next` on for the bodies still to join (a dump's `next_id`: the ids of bodies
    /// that left stay given). Panics below an id already given.
    pub(crate) fn name_from(&mut self, next: BodyId) {
        assert!(next >= self.next_id, "an id is never given twice");
        self.next_id = next;
    }

    /// Names the bodies not yet named, in their order.
    fn name_new(&mut self) {
        for b in self.bodies.iter_mut().filter(|b| b.id == BodyId::NEW) {
            b.id = self.next_id;
            self.next_id = BodyId(self.next_id.0 + 1);
        }
    }

    /// Adds `body` (a grain placed by hand), named with the next id, which it returns.
    pub fn add(&mut self, body: Body) -> BodyId {
        let id = self.next_id;
        self.bodies.push(Body { id, ..body });
        self.next_id = BodyId(id.0 + 1);
        id
    }

    /// Removes the grains for which `leaves` says so, between steps, and returns them in their
    /// order. The others keep their ids, their order and their contacts: the soft step's kept
    /// impulses, warm starts and carried manifolds follow them to their new places, so a run
    /// goes on as if the removed grains had vanished at the step's end (and a dump written now
    /// resumes bit for bit). Ids are never given again.
    pub fn remove(&mut self, leaves: impl FnMut(&Body) -> bool) -> Vec<Body> {
        let marked: Vec<bool> = self.bodies.iter().map(leaves).collect();
        self.remove_marked(&marked)
    }

    /// [`World::remove`] of the grains `marked` by index.
    fn remove_marked(&mut self, marked: &[bool]) -> Vec<Body> {
        let gone: Vec<Body> = self
            .bodies
            .iter()
            .zip(marked)
            .filter(|(_, m)| **m)
            .map(|(b, _)| *b)
            .collect();
        if gone.is_empty() {
            return gone;
        }
        // Each grain's new index, or `None` for one that leaves.
        let mut kept = 0;
        let to: Vec<Option<usize>> = marked
            .iter()
            .map(|&m| {
                (!m).then(|| {
                    kept += 1;
                    kept - 1
                })
            })
            .collect();
        let mut stays = marked.iter().map(|&m| !m);
        self.bodies.retain(|_| stays.next().unwrap_or(true));
        // (`step_start` is as long as `bodies` was at the step's start: no longer.)
        let mut stays = marked.iter().map(|&m| !m);
        self.step_start.retain(|_| stays.next().unwrap_or(true));
        self.soft.reindex(&to);
        self.work = Workspace::default();
        // A driven grain that leaves takes its drive with it.
        self.drivers.retain(|d| !gone.iter().any(|b| b.id == d.id));
        gone
    }

    /// One step: due grains appear if their place is free, then the solver runs.
    pub fn step(&mut self) -> StepStats {
        let never = AtomicBool::new(false);
        match self.advance(&never) {
            Ok(stats) => stats,
            Err(Stopped) => unreachable!("nothing raises a flag no one else sees"),
        }
    }

    /// [`World::step`], unless `stop` is raised before the step ends: the step is then
    /// abandoned within one contact test and the world is put back exactly as it was at the
    /// step's start, so that what is written afterwards is the last whole step. Not raised, the
    /// step is [`World::step`]'s bit for bit. The price is a copy of the grains per step, about
    /// 140 bytes each (measured in docs/robustness.md: within the noise of `bench presets`).
    pub fn step_or_stop(&mut self, stop: &AtomicBool) -> Result<StepStats, Stopped> {
        if stop.load(Ordering::Relaxed) {
            return Err(Stopped);
        }
        let mut undo = std::mem::take(&mut self.undo);
        undo.bodies.clone_from(&self.bodies);
        undo.next_id = self.next_id;
        undo.step_start.clone_from(&self.step_start);
        self.undo = undo;
        let done = self.advance(stop);
        if done.is_err() {
            let undo = &mut self.undo;
            std::mem::swap(&mut self.bodies, &mut undo.bodies);
            std::mem::swap(&mut self.step_start, &mut undo.step_start);
            self.next_id = undo.next_id;
            self.pending.undo(&undo.spawned);
            self.place_boundaries();
        }
        done
    }

    /// One step, abandoned (leaving the world half stepped) if `stop` rises.
    fn advance(&mut self, stop: &AtomicBool) -> Result<StepStats, Stopped> {
        // Grains pushed onto `bodies` by hand since the last step, then those that appear now.
        self.name_new();
        self.spawn();
        self.name_new();
        self.step_start.clear();
        self.step_start.extend(self.bodies.iter().map(|b| b.center));
        let motions = match self.settings.model {
            Model::Soft => {
                self.drive_grains();
                self.motions()
            }
            Model::Paper => Vec::new(),
        };
        let stats = match self.settings.model {
            Model::Paper => solver::step_or_stop(
                &mut self.bodies,
                &self.walls,
                &self.settings,
                &mut self.broad,
                &mut self.work,
                self.step,
                stop,
            )?,
            Model::Soft => soft::step_or_stop(
                &mut self.bodies,
                &self.walls,
                &self.boundaries,
                &motions,
                &self.materials,
                &self.wall_material,
                &self.settings,
                &mut self.soft,
                stop,
            )?,
        };
        self.step += 1;
        self.place_boundaries();
        self.place_driven();
        self.drain();
        Ok(stats)
    }

    /// Each driven boundary's motion over the next step, and its place at the step's end (in
    /// `boundaries` for the step; [`Self::place_boundaries`] keeps it). Empty when none moves.
    fn motions(&mut self) -> Vec<WallMotion> {
        if self.drives.iter().all(Drive::is_still) {
            return Vec::new();
        }
        let (h, t) = (self.settings.step, self.time());
        self.boundaries
            .iter_mut()
            .zip(&self.bases)
            .zip(&self.drives)
            .map(|((now, base), drive)| {
                *now = drive.place(base, t + h);
                drive.motion(now, t, h)
            })
            .collect()
    }

    /// The driven grains' velocities over the next step: the chord between their places at
    /// the step's start and end ([`Drive::pose_at`]), so that the substeps end where the drive
    /// puts them.
    fn drive_grains(&mut self) {
        let (h, t) = (self.settings.step, self.time());
        for d in &self.drivers {
            let Some(b) = self.bodies.iter_mut().find(|b| b.id == d.id) else {
                continue;
            };
            let (from, to) = (d.drive.pose_at(&d.base, t), d.drive.pose_at(&d.base, t + h));
            b.velocity = (to.center() - from.center()) * (1.0 / h);
            b.angular_velocity = (to.angle() - from.angle()) / h;
        }
    }

    /// The driven grains where their drives have them now (the closed form's bits, not the
    /// substeps' sum).
    pub fn place_driven(&mut self) {
        let t = self.time();
        for d in &self.drivers {
            if let Some(b) = self.bodies.iter_mut().find(|b| b.id == d.id) {
                let p = d.drive.pose_at(&d.base, t);
                (b.center, b.angle) = (p.center(), p.angle());
            }
        }
    }

    /// The boundaries where their drives have them now.
    pub fn place_boundaries(&mut self) {
        let t = self.time();
        for ((now, base), drive) in self
            .boundaries
            .iter_mut()
            .zip(&self.bases)
            .zip(&self.drives)
        {
            *now = drive.place(base, t);
        }
    }

    /// A new time step, every grain keeping its velocity: the paper model's Verlet keeps a
    /// velocity as `(x - x_prev) / h`, so each previous pose is moved to match the new step;
    /// the soft model keeps velocities as they are. The clock goes on from the time reached
    /// ([`World::clock`]), so driven boundaries go on from where they are.
    pub fn set_step(&mut self, step: f64) {
        // The same step changes nothing (a restarted clock would round the time differently).
        if step == self.settings.step {
            return;
        }
        self.clock = (self.step, self.time());
        let ratio = step / self.settings.step;
        if ratio != 1.0 {
            for b in &mut self.bodies {
                b.previous_center = b.center - (b.center - b.previous_center) * ratio;
                b.previous_angle = b.angle - (b.angle - b.previous_angle) * ratio;
            }
        }
        self.settings.step = step;
    }

    /// Every wall in the order contacts name them: the box's left, right and floor, then the
    /// boundaries.
    pub fn all_walls(&self) -> Vec<Boundary> {
        let mut walls = self.walls.boundaries().to_vec();
        walls.extend_from_slice(&self.boundaries);
        walls
    }

    /// The simulated time: the clock's time, and the steps done since times the step.
    pub fn time(&self) -> f64 {
        let (at, time) = self.clock;
        time + self.step.saturating_sub(at) as f64 * self.settings.step
    }

    /// The grains in a sink leave (the first sink in order that holds a grain's centre counts
    /// it), those of a recycling sink queued to come back; the grains whose boxes reach a
    /// leaving grain's wake, so that nothing sleeps on a support that is gone.
    fn drain(&mut self) {
        if self.sinks.is_empty() {
            return;
        }
        // Each grain's sink (a static or driven body stays: it is part of the container).
        let sink_of: Vec<Option<usize>> = self
            .bodies
            .iter()
            .map(|b| {
                b.kind
                    .is_dynamic()
                    .then(|| self.sinks.iter().position(|s| s.region.contains(b.center)))
                    .flatten()
            })
            .collect();
        if sink_of.iter().all(Option::is_none) {
            return;
        }
        let reach = self.settings.sleep_radius;
        let mut wake = Vec::new();
        for (i, k) in sink_of.iter().enumerate() {
            let Some(k) = *k else { continue };
            let b = self.bodies[i];
            let (mass, _) = self.material(i).mass_and_inertia(&b.shape);
            let sink = &mut self.sinks[k];
            sink.grains += 1;
            sink.mass += mass;
            if sink.recycle {
                // Back at the top where it left, or the source's nearest place to it.
                let r = b.shape.bounding_radius();
                let source = spawn::narrowed(&self.walls, self.pending.between());
                let (lo, hi) = (source.left + r, source.right - r);
                let x = if lo < hi {
                    b.center.x.clamp(lo, hi)
                } else {
                    0.5 * (source.left + source.right)
                };
                self.pending.push_back(Pending {
                    shape: b.shape,
                    x,
                    angle: b.angle,
                    due: self.step,
                    group: b.group,
                });
            }
            wake.push(b.bounding_box().grown(reach));
        }
        for o in self.bodies.iter_mut() {
            let bb = o.bounding_box();
            if wake.iter().any(|w| w.intersects(&bb)) {
                o.calm = 0;
            }
        }
        let marked: Vec<bool> = sink_of.iter().map(Option::is_some).collect();
        self.remove_marked(&marked);
    }

    /// A new grain never appears inside another, by the queue's rule (see [`SpawnRule`]). A grain
    /// placed under the top (the fair rule's band) comes with the speed of a fall from the top,
    /// as LAMMPS's `fix pour` gives it: the flow below the top is the same whatever the height
    /// a grain was placed at, and none is placed at rest under a grain falling onto it. Under
    /// the fair rule a place inside a boundary is taken too.
    fn spawn(&mut self) {
        let (bodies, settings, boundaries, top) =
            (&mut self.bodies, &self.settings, &self.boundaries, self.top);
        let fair = self.pending.rule() == SpawnRule::Fair;
        let place = |p: &Pending, at: Vec2| {
            let mut body = Body {
                group: p.group,
                ..Body::at_rest(p.shape, &Pose::from_parts(at, p.angle))
            };
            if at.y < top {
                let v = fall_speed(settings, top - at.y);
                match settings.model {
                    Model::Soft => body.velocity = Vec2::new(0.0, -v),
                    // Verlet's velocity is the step's displacement.
                    Model::Paper => body.previous_center.y += v * settings.step,
                }
            }
            let bb = body.bounding_box();
            if overlaps_any(settings, bodies, &body, &bb)
                || (fair
                    && boundaries
                        .iter()
                        .any(|w| body.wall_contact(w, &settings.narrow()).overlap()))
            {
                return false;
            }
            bodies.push(body);
            true
        };
        self.pending
            .spawn(self.step, &self.walls, top, place, &mut self.undo.spawned);
    }

    /// Whether `body` would overlap a grain of the world (the rule that keeps spawned grains
    /// from appearing inside another).
    pub fn overlaps_a_grain(&self, body: &Body) -> bool {
        overlaps_any(&self.settings, &self.bodies, body, &body.bounding_box())
    }

    /// The first grain whose state (pose, previous pose or velocity) is not finite: a run gone
    /// wrong, whose state must not be written (nothing can resume or draw it).
    pub fn first_not_finite(&self) -> Option<usize> {
        (0..self.bodies.len())
            .find(|&i| !self.bodies[i].is_finite() || !self.velocity(i).is_finite())
    }

    /// The first grain that has left the box (a run gone wrong: the walls no longer hold it).
    /// Under the paper's model, a grain whose centre is left of the left wall, right of the
    /// right one or below the floor. Under the soft model, one beyond a wall by more than its
    /// diameter: a grain struck while lying on the floor can have its centre below it for a
    /// step or two, and the floor pushes it out (docs/physics.md, "The soft step"); the same
    /// limit as a dump's (`checks::SOFT_OUTSIDE_FRACTION`).
    pub fn first_outside(&self) -> Option<usize> {
        let w = self.walls;
        let soft = self.settings.model == Model::Soft;
        self.bodies.iter().position(|b| {
            if soft {
                return checks::depth_outside(&w, &b.bounding_box())
                    > checks::soft_outside_limit(&b.shape);
            }
            let c = b.center;
            !(c.x >= w.left && c.x <= w.right && c.y >= w.floor)
        })
    }

    /// All grains have appeared.
    pub fn all_spawned(&self) -> bool {
        self.pending.is_empty()
    }

    /// The mean stress tensor of the heap over the last step (the soft model's; `None` for the
    /// paper's, whose projection has no forces): `sigma = (1/A) sum over contacts of f (x) l`,
    /// `f` the force on one side, `l` the branch vector from the other side's centre to that
    /// side's (for a wall, from the contact point to the grain's centre), `A` the box's width
    /// times the height of the heap's top above the floor: the highest top of a grain in a
    /// contact (a grain in flight touches nothing and is not of the heap). Compression is
    /// negative.
    pub fn stress(&self) -> Option<[[f64; 2]; 2]> {
        if self.settings.model != Model::Soft || self.bodies.is_empty() {
            return None;
        }
        let mut touching = vec![false; self.bodies.len()];
        for f in &self.soft.forces {
            if f.a != soft::STATIC {
                touching[f.a] = true;
            }
            touching[f.b] = true;
        }
        let top = self
            .bodies
            .iter()
            .zip(&touching)
            .filter(|&(_, &t)| t)
            .map(|(b, _)| b.bounding_box().max.y)
            .fold(self.walls.floor, f64::max);
        let area = (self.walls.right - self.walls.left) * (top - self.walls.floor);
        let mut sigma = [[0.0; 2]; 2];
        for f in &self.soft.forces {
            let t = Vec2::new(f.normal.y, -f.normal.x);
            let on_b = f.normal * f.normal_force + t * f.tangent_force;
            let from = if f.a == soft::STATIC {
                f.point
            } else {
                self.bodies[f.a].center
            };
            let l = self.bodies[f.b].center - from;
            let (fv, lv) = ([on_b.x, on_b.y], [l.x, l.y]);
            for (i, row) in sigma.iter_mut().enumerate() {
                for (j, s) in row.iter_mut().enumerate() {
                    // Tension positive: a contact pushes its grains apart, a compression.
                    *s -= fv[i] * lv[j] / area;
                }
            }
        }
        Some(sigma)
    }

    /// How many groups the world knows of: its material table's, and every group a grain or
    /// a grain still to appear comes from.
    pub fn group_count(&self) -> usize {
        let of = |g: u32| g as usize + 1;
        let generated = self.pending.generator().map_or(0, |g| g.groups().len());
        let waiting = self.pending.waiting().iter().map(|p| of(p.group));
        let grains = self.bodies.iter().map(|b| of(b.group));
        waiting
            .chain(grains)
            .fold(self.materials.len().max(generated), usize::max)
    }

    /// The material of grain `i` (its group's, see [`soft::material_of`]).
    pub fn material(&self, i: usize) -> Material {
        crate::body::material_of(&self.materials, self.bodies[i].group)
    }

    /// Changes a group's material, or the walls', from the next step on (the soft step's;
    /// the paper's model ignores materials). A new density gives the grains of the group
    /// their new mass and moment of inertia; every grain wakes, since a sleeper is not solved
    /// and would not feel the change. A group past the end of the table first fills the table
    /// up to it with the materials its grains had (so that no other group's changes). The error
    /// names the number out of range.
    pub fn set_material(&mut self, of: MaterialOf, m: Material) -> Result<(), String> {
        m.validate()?;
        let density_changed = match of {
            MaterialOf::Walls => {
                // The walls do not move: their density is never used.
                self.wall_material = m;
                false
            }
            MaterialOf::Group(g) => {
                let g = g as usize;
                let len = self.group_count().max(g + 1);
                while self.materials.len() < len {
                    let next =
                        crate::body::material_of(&self.materials, self.materials.len() as u32);
                    self.materials.push(next);
                }
                let old = std::mem::replace(&mut self.materials[g], m);
                old.density != m.density
            }
        };
        if density_changed {
            self.soft.forget_masses();
        }
        for b in &mut self.bodies {
            b.calm = 0;
            b.anchor = b.center;
        }
        Ok(())
    }

    /// How many grains are still to appear.
    pub fn pending_count(&self) -> u64 {
        self.pending.len()
    }

    /// The velocity of grain `i` over the last step: its displacement from where the step began.
    ///
    /// Not the solver's `center - previous_center`: grains are handled one after another, so a
    /// grain resting in a heap is pushed down by those handled before it and back up after its
    /// own update, and that internal back-and-forth would read as motion.
    pub fn velocity(&self, i: usize) -> Vec2 {
        if self.settings.model == Model::Soft {
            // The soft step's velocity is state.
            return self.bodies[i].velocity;
        }
        let start = self
            .step_start
            .get(i)
            .copied()
            .unwrap_or(self.bodies[i].center);
        (self.bodies[i].center - start) * (1.0 / self.settings.step)
    }

    /// Sets the velocities [`World::velocity`] reports until the next step (a restart).
    pub fn set_velocities(&mut self, velocities: &[Vec2]) {
        let h = self.settings.step;
        self.step_start = self
            .bodies
            .iter()
            .zip(velocities)
            .map(|(b, v)| b.center - *v * h)
            .collect();
    }

    /// How many grains sleep (see [`Settings::sleep_radius`]).
    pub fn asleep(&self) -> usize {
        self.bodies
            .iter()
            .filter(|b| b.kind.is_dynamic() && b.asleep(&self.settings))
            .count()
    }

    /// The largest grain speed over the last step (a driven grain moves as its drive says, and
    /// does not count).
    pub fn max_speed(&self) -> f64 {
        (0..self.bodies.len())
            .filter(|&i| self.bodies[i].kind.is_dynamic())
            .map(|i| self.velocity(i).norm())
            .fold(0.0, f64::max)
    }

    /// Every grain-grain and grain-wall contact of the current state, as the solver sees it: for
    /// each grain `i` in turn, its contacts with the grains `j > i`, in increasing `j`, then with
    /// the walls. Pairs come from a grid, so this takes time linear in the number of grains.
    pub fn contacts(&self, mut f: impl FnMut(Touch)) {
        let walls = self.all_walls();
        let narrow = self.settings.narrow();
        let boxes: Vec<Aabb> = self.bodies.iter().map(Body::bounding_box).collect();
        let mut grid = Grid::new();
        grid.rebuild(&boxes);
        let mut near = Vec::new();
        for (i, a) in self.bodies.iter().enumerate() {
            near.clear();
            grid.candidates(i, &boxes, &mut near);
            for &j in near.iter().filter(|&&j| j > i) {
                if let Some(p) = a.contact(&self.bodies[j], &narrow).penetration {
                    f(Touch::Grains(i, j, p));
                }
            }
            for w in &walls {
                if let Some(p) = a.wall_contact(w, &narrow).penetration {
                    f(Touch::Wall(i, p));
                }
            }
        }
    }

    /// How deep the grains overlap, over the contacts that touch: the soft model's as its
    /// solver left them at the end of the last step (a contact's deepest point; sleepers'
    /// contacts as they fell asleep), the paper model's by the narrow phase's penetration
    /// vectors ([`World::contacts`]). `None` when nothing touches.
    pub fn overlaps(&self) -> Option<Overlaps> {
        // A grain's size here: its thickness, twice its smallest semi-axis.
        let size = |i: usize| 2.0 * self.bodies[i].shape.min_semi_axis();
        let mut all: Vec<(f64, f64)> = Vec::new();
        match self.settings.model {
            Model::Soft => {
                for f in &self.soft.forces {
                    if f.overlap > 0.0 && f.b < self.bodies.len() {
                        let thinner = if f.a == soft::STATIC {
                            size(f.b)
                        } else {
                            size(f.a).min(size(f.b))
                        };
                        all.push((f.overlap, thinner));
                    }
                }
            }
            Model::Paper => self.contacts(|t| {
                all.push(match t {
                    Touch::Grains(i, j, p) => (p.depth(), size(i).min(size(j))),
                    Touch::Wall(i, p) => (p.push.norm(), size(i)),
                })
            }),
        }
        if all.is_empty() {
            return None;
        }
        let n = all.len() as f64;
        Some(Overlaps {
            contacts: all.len(),
            mean: all.iter().map(|o| o.0).sum::<f64>() / n,
            max: all.iter().map(|o| o.0).fold(0.0, f64::max),
            mean_relative: all.iter().map(|o| o.0 / o.1).sum::<f64>() / n,
            max_relative: all.iter().map(|o| o.0 / o.1).fold(0.0, f64::max),
        })
    }

    /// The longest penetration vector among all overlapping pairs and grain-wall contacts.
    pub fn deepest_penetration(&self) -> f64 {
        let mut deepest = 0.0f64;
        self.contacts(|t| {
            deepest = deepest.max(match t {
                Touch::Grains(_, _, p) => p.depth(),
                Touch::Wall(_, p) => p.push.norm(),
            })
        });
        deepest
    }
}

/// How deep the contacts of a state overlap ([`World::overlaps`]): in units, and relative to
/// the thinner grain of each contact (its thickness, twice its smallest semi-axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlaps {
    /// The contacts that overlap.
    pub contacts: usize,
    pub mean: f64,
    pub max: f64,
    pub mean_relative: f64,
    pub max_relative: f64,
}

/// The speed of a grain fallen `height` from rest: `sqrt(2 g height)` for the soft model
/// (without its optional air drag); for the paper's, whose damping caps a fall at
/// `g h / delta` (0.98 with its settings), the smaller of the two.
fn fall_speed(settings: &Settings, height: f64) -> f64 {
    let free = (2.0 * settings.gravity * height.max(0.0)).sqrt();
    match settings.model {
        Model::Soft => free,
        Model::Paper if settings.damping > 0.0 => {
            free.min(settings.gravity * settings.step / settings.damping)
        }
        Model::Paper => free,
    }
}

/// Whether `body` (its box `bb`) overlaps one of `bodies`: their bounding circles first, then
/// their boxes, then the narrow phase. (The boxes of every grain were made for each grain due:
/// with the scan, 5% of a pour of 1,000 disks. A pair whose circles or boxes are apart has no
/// point in both, so the answer is the same.)
fn overlaps_any(settings: &Settings, bodies: &[Body], body: &Body, bb: &Aabb) -> bool {
    let (c, r) = (body.center, body.shape.bounding_radius());
    bodies.iter().any(|o| {
        let reach = r + o.shape.bounding_radius();
        let d = o.center - c;
        d.dot(d) <= reach * reach
            && o.bounding_box().intersects(bb)
            && body.contact(o, &settings.narrow()).overlap()
    })
}

/// Whose material [`World::set_material`] changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaterialOf {
    /// A scene group's, by [`Body::group`].
    Group(u32),
    /// The walls' (the box's and the boundaries').
    Walls,
}

/// A contact found by [`World::contacts`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Touch {
    /// Grains `i < j` overlap.
    Grains(usize, usize, Penetration),
    /// Grain `i` is in a wall.
    Wall(usize, WallPenetration),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::NarrowPhase;
    use crate::subdivision::Precision;

    /// The mixed preset with slow steps (the quadtree at depth 12), so that a flag raised at
    /// any moment almost surely lands in the middle of one.
    fn slow_world() -> World {
        let mut scene = Scene::preset("mixed").expect("a preset");
        scene.spawn_interval = 1;
        scene.settings.narrow_phase = NarrowPhase::Quadtree;
        scene.settings.precision = Precision::new(12, 0.0).expect("a valid precision");
        World::new(&scene)
    }

    /// What a dump would hold of a world.
    fn state(w: &World) -> (Vec<Body>, Queue, u64, Vec<Vec2>) {
        (
            w.bodies.clone(),
            w.pending.clone(),
            w.step,
            (0..w.bodies.len()).map(|i| w.velocity(i)).collect(),
        )
    }

    /// A stop raised while the world steps: the step under way is abandoned and the world is
    /// exactly that of an unstopped run of the steps done (grains, spawn queue, step count,
    /// velocities), from which it goes on as that run does.
    #[test]
    fn a_stopped_step_leaves_the_last_whole_step() {
        let mut world = slow_world();
        for _ in 0..30 {
            world.step();
        }
        let stop = AtomicBool::new(false);
        let mut stopped = 0;
        for delay in [3, 11, 29] {
            stop.store(false, Ordering::SeqCst);
            std::thread::scope(|s| {
                s.spawn(|| {
                    std::thread::sleep(std::time::Duration::from_millis(delay));
                    stop.store(true, Ordering::SeqCst);
                });
                while world.step_or_stop(&stop).is_ok() {}
            });
            stopped += 1;
            let mut reference = slow_world();
            while reference.step < world.step {
                reference.step();
            }
            assert_eq!(
                state(&world),
                state(&reference),
                "stop {stopped}, after {delay} ms, at step {}",
                world.step
            );
            world.step();
            reference.step();
            assert_eq!(state(&world), state(&reference), "after the stop {stopped}");
        }
    }

    /// A group past the end of the material table: the groups between keep the material
    /// they had (the table's last), and so does every group after it.
    #[test]
    fn setting_a_group_past_the_tables_end_changes_no_other_group() {
        let shape = crate::shape::Superellipse::circle(0.2).expect("a circle");
        let bodies = (0..4)
            .map(|g| Body {
                group: g,
                ..Body::at_rest(shape, &Pose::from_parts(Vec2::new(g as f64, 1.0), 0.0))
            })
            .collect();
        let walls = Walls {
            left: -5.0,
            right: 5.0,
            floor: 0.0,
        };
        let settings = Settings::default();
        let mut world = World::from_parts(bodies, walls, settings, 0, 5.0, Queue::default());
        let a = Material {
            friction: 0.2,
            ..Material::default()
        };
        let m = Material {
            density: 2.0,
            ..Material::default()
        };
        world.materials = vec![a];
        world.set_material(MaterialOf::Group(2), m).expect("valid");
        assert_eq!(world.materials, vec![a, a, m, a]);
        assert_eq!(
            (0..4).map(|i| world.material(i)).collect::<Vec<_>>(),
            vec![a, a, m, a]
        );
        let bad = Material {
            restitution: 2.0,
            ..m
        };
        assert!(world.set_material(MaterialOf::Walls, bad).is_err());
        assert_eq!(world.wall_material, Material::default());
    }

    #[test]
    fn a_step_asked_to_stop_before_it_starts_changes_nothing() {
        let mut world = slow_world();
        world.step();
        let before = state(&world);
        assert_eq!(world.step_or_stop(&AtomicBool::new(true)), Err(Stopped));
        assert_eq!(state(&world), before);
    }
}

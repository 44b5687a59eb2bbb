//! The rigid-body contact solver (issue 18), `model = "soft"`: grains with mass and moment of
//! inertia, velocities as state, Coulomb friction, restitution and rolling resistance, contacts
//! found once per step by the certified narrow phase and solved with substeps as soft
//! constraints, after Box2D v3's "soft step" (Catto, "Solver2D", 2024). Written for this
//! project from the published description of the method: the solver is the heart of the
//! engine, and its contacts come from our narrow phase, not from polygon clipping.
//!
//! One step of length `h`, in named stages:
//! 1. [`find_contacts`]: every pair whose boxes overlap at the poses the grains would reach
//!    in free flight (`x + h (v + h g)`, `theta + h omega`) is tested there, by the certified
//!    narrow phase, except a pair that has hardly moved against the other since it was last
//!    searched, whose contact is carried, moved to first order and its overlap proven again
//!    ([`super::carry`]). Testing where the grains are going is the speculative margin: a
//!    grain that would reach another within the step gets its contact before it gets there. Each overlap
//!    becomes a [`Manifold`] (the middle of the overlap, and the region's ends where flat faces
//!    meet), its points anchored in the bodies and its separation carried back to the step's
//!    start.
//! 2. [`prepare`]: effective masses along the normal and the tangent, the soft-constraint
//!    coefficients, the relative normal velocity (for restitution), friction and restitution
//!    mixed from the two materials.
//! 3. `substeps` times: gravity and damping on the velocities, [`warm_one`] (the impulses the
//!    contact kept from the last step, then those of the last substep), [`solve_one`] with the
//!    soft push-out, positions integrated, [`solve_one`] again without it (the "relax" that
//!    takes the push-out's velocity back out). Both run over the contacts in colour batches,
//!    four independent contacts side by side ([`batch`]).
//! 4. [`restitution`] on the points that were closing faster than the threshold.
//! 5. The impulses are kept by pair and point for the next step.
//!
//! The separation of a point within the step is updated from the bodies' motion since the
//! step's start (the anchors turn with the bodies); the narrow phase runs once per step.

mod batch;

use rustc_hash::FxHashMap;
use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::carry::Carried;
use super::{StepStats, Stopped};
use crate::body::{Body, BodyKind, Material, WallMotion, Walls, material_of, mix};
use crate::broad_phase::Near;
use crate::contact::manifold::{Manifold, ManifoldPoint, grain_manifold, wall_manifold};
use crate::contact::{NarrowPhase, WarmStart};
use crate::geometry::{Aabb, Rotation, Vec2};
use crate::settings::{Settings, SoftSettings};
use crate::shape::{Boundary, Pose};

/// The coefficients of a soft constraint of frequency `hertz` and damping ratio `zeta`, for a
/// substep `h` (Catto's "soft step": a spring-damper solved implicitly, expressed as a bias
/// rate and two scales of the impulse).
#[derive(Clone, Copy, Debug)]
struct Softness {
    bias_rate: f64,
    mass_scale: f64,
    impulse_scale: f64,
}

impl Softness {
    fn new(hertz: f64, zeta: f64, h: f64) -> Self {
        let omega = std::f64::consts::TAU * hertz;
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Softness {
            bias_rate: omega / a1,
            mass_scale: a2 * a3,
            impulse_scale: a3,
        }
    }
}

/// How far apart a contact's patch (see [`crate::contact::manifold`]) reaches, in units: Box2D's
/// speculative distance (four of its linear slops of 0.005). A length of its own since the slop
/// became 0 (2026-12-06): the manifolds are those of before.
const PATCH_REACH: f64 = 0.02;

/// The overlap a contact with a star keeps at rest, on top of the settings' `slop`. A star's
/// contacts are answered to half a final cell (the boundary search, the quadtree), not exactly,
/// and a star rocks from spike to spike: solved to zero separation, the 60-star heap of issue 40
/// (exponents 0.3-0.6) trembled on (not at rest by step 8,000; 616 steps with the old slop of
/// 0.005 for every pair). With it, it rests as before: docs/physics.md ("Overlap").
const STAR_SLOP: f64 = 0.005;

/// The stiffest a contact with a star is (Hz): the default until 2026-12-06. A star's contacts
/// have no speculative point (its narrow phase answers "apart" without a distance), so spikes
/// that meet within a step are pushed apart from an overlap no contact held, and the stiffer the
/// contact the more energy that gives: at 60 Hz a heap of 30 stars of exponents 0.3-0.7 (seed 2
/// of `tests/star_heap.rs`) kept a grain at 0.14-0.45 units/s for good, by islands; at 30 Hz it
/// rests.
const STAR_HERTZ: f64 = 30.0;

/// How far apart two disks (or a disk and a wall) at the poses of free flight still get a
/// contact, with its positive separation: Box2D's speculative distance (`PATCH_REACH`).
const SPECULATIVE: f64 = 0.02;

/// A speculative contact between two disks whose gap at the predicted poses is below
/// [`SPECULATIVE`] ([`gap_contact`], which a disk against a wall takes directly): one point in
/// the middle of the gap, the gap its separation. It is no claim of overlap (its separation is not
/// negative); it only keeps the two from closing faster than the gap within a substep.
fn speculative(ca: Vec2, ra: f64, cb: Vec2, rb: f64) -> Option<Manifold> {
    let d = cb - ca;
    let dist = d.norm();
    // (Not `dist <= 0.0`: a NaN distance has no contact either.)
    if dist.is_nan() || dist <= 0.0 {
        return None;
    }
    let n = d * (1.0 / dist);
    let gap = dist - ra - rb;
    gap_contact(n, gap, ca, ra + 0.5 * gap)
}

/// The speculative contact across a `gap` (below [`SPECULATIVE`]) along `n`: one point in the
/// gap's middle, `from + n * along`, separated by the gap (never less than 0).
fn gap_contact(n: Vec2, gap: f64, from: Vec2, along: f64) -> Option<Manifold> {
    if gap.is_nan() || gap >= SPECULATIVE {
        return None;
    }
    Manifold::from_points(
        n,
        &[ManifoldPoint {
            point: from + n * along,
            separation: gap.max(0.0),
            id: 0,
        }],
    )
}

/// No body: the wall side of a grain-wall contact.
pub const STATIC: usize = usize::MAX;

/// The most walls a world can have: the box's three and the boundaries (see
/// [`crate::world::World::boundaries`]; a polyline is one per segment).
pub const MAX_WALLS: usize = 1 << 16;

/// The key a contact persists under: the two grains (`j` is `STATIC - w` for wall `w`: 0, 1,
/// 2 the box's left, right and floor, then the boundaries in order).
pub type PairKey = (usize, usize);

/// The impulses a point carried at the end of a step, kept for the next one.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kept {
    pub normal: [f64; 3],
    pub tangent: [f64; 3],
    pub rolling: f64,
}

#[derive(Clone, Copy, Debug)]
struct Point {
    /// From each body's centre at the step's start to the point (world orientation of the
    /// start; for a wall, the point itself).
    ra: Vec2,
    rb: Vec2,
    /// The separation at the step's start.
    base: f64,
    normal_mass: f64,
    tangent_mass: f64,
    normal_impulse: f64,
    tangent_impulse: f64,
    max_normal_impulse: f64,
    /// The normal velocity at impact (negative: closing), for restitution: before the step,
    /// then, while the point is apart, at the start of each substep (after its gravity), so
    /// that a grain found a step before it lands bounces with the speed it lands with.
    closing: f64,
    id: u8,
}

impl Point {
    /// An unused slot.
    const ZERO: Point = Point {
        ra: Vec2::ZERO,
        rb: Vec2::ZERO,
        base: 0.0,
        normal_mass: 0.0,
        tangent_mass: 0.0,
        normal_impulse: 0.0,
        tangent_impulse: 0.0,
        max_normal_impulse: 0.0,
        closing: 0.0,
        id: 0,
    };
}

#[derive(Clone, Copy, Debug)]
struct Constraint {
    a: usize,
    b: usize,
    /// The record of side A in [`State::solids`]: grain `a`'s, or its wall's for [`STATIC`].
    slot_a: usize,
    key: PairKey,
    normal: Vec2,
    friction: f64,
    restitution: f64,
    rolling_resistance: f64,
    /// The mean lever arm, for rolling resistance.
    lever: f64,
    /// The overlap this contact keeps at rest: the settings' `slop`, and [`STAR_SLOP`] more
    /// where a star is in the pair.
    slop: f64,
    /// Whether a star is in the pair (its stiffness is then at most [`STAR_HERTZ`]).
    star: bool,
    rolling_mass: f64,
    rolling_impulse: f64,
    softness: Softness,
    points: [Point; 3],
    len: usize,
}

/// The force at one contact over the last step: the impulses of its last substep divided by
/// the substep (a contact's force, as a DEM code reports it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactForce {
    /// The grains; `b` is the grain and `a` [`STATIC`] for a wall, whose index is `wall`.
    pub a: usize,
    pub b: usize,
    pub wall: Option<usize>,
    /// Where the force acts (the impulse-weighted mean of the contact's points), and the normal
    /// from A towards B (from the wall into the grain).
    pub point: Vec2,
    pub normal: Vec2,
    /// On B, along the normal (>= 0) and along `(n.y, -n.x)`; A feels the opposite.
    pub normal_force: f64,
    pub tangent_force: f64,
    /// How deep the contact's deepest point overlaps at the end of the step (the solver's
    /// separation, negated; 0 or less: touching or apart).
    pub overlap: f64,
}

/// What the soft step keeps between steps and reuses within one.
#[derive(Debug, Default)]
pub struct SoftWorkspace {
    /// Inverse mass and inverse moment of inertia of each grain (computed once per grain: the
    /// closed forms take gamma functions).
    inverse: Vec<(f64, f64)>,
    /// The impulses of each contact at the end of the last step (warm start).
    /// (Keyed by rustc's Fx hash, not SipHash: these three maps are looked up and filled for
    /// every contact of every step, and SipHash took 2% of a settled heap's step. No result
    /// depends on their order.)
    pub kept: FxHashMap<PairKey, Kept>,
    /// Where each pair's last narrow-phase test found its deepest points (`next_warm`: this
    /// step's, kept when the step is whole).
    pub warm: FxHashMap<PairKey, WarmStart>,
    next_warm: FxHashMap<PairKey, WarmStart>,
    /// Each overlapping pair's manifold as last searched ([`super::carry`]).
    pub carried: FxHashMap<PairKey, Carried>,
    next_carried: FxHashMap<PairKey, Carried>,
    predicted: Vec<Pose>,
    /// Each grain's rotation from its pose to its predicted one.
    turns: Vec<Rotation>,
    boxes: Vec<Aabb>,
    /// The pairs of fat boxes, kept from step to step.
    near: Near,
    pairs: Vec<PairEntry>,
    constraints: Vec<Constraint>,
    start: Vec<(Vec2, f64)>,
    solids: Vec<Solid>,
    walls: Vec<Boundary>,
    /// Each wall's motion this step (the box's three first).
    motions: Vec<WallMotion>,
    /// Whether each grain is awake this step, and its inverse masses as the solver sees them
    /// (a sleeper's are 0: it holds its neighbours as a wall does).
    awake: Vec<bool>,
    active: Vec<(f64, f64)>,
    /// The contacts in colour batches, for the substeps.
    batches: batch::Batches,
    /// Every contact's force over the last step, in the order of the contacts.
    pub forces: Vec<ContactForce>,
    /// The sleepers woken this step (sleeping grain by grain), for [`keep`].
    woken: Vec<usize>,
}

impl SoftWorkspace {
    /// Forget the masses (a grain's shape or material changed) and the kept contacts.
    pub fn reset(&mut self) {
        *self = SoftWorkspace::default();
    }

    /// Grains have left: grain `i` is now grain `to[i]`, or gone for `None` (the order kept).
    /// The kept impulses, warm starts, carried manifolds and the last step's forces follow
    /// their grains, those of a grain gone are dropped; the pairs of fat boxes are searched
    /// afresh.
    pub fn reindex(&mut self, to: &[Option<usize>]) {
        let mut k = 0;
        self.inverse.retain(|_| {
            k += 1;
            to.get(k - 1).is_none_or(Option::is_some)
        });
        // A pair's second index is a grain's, or `STATIC - k` for wall `k`.
        let pair = |(a, b): PairKey| -> Option<PairKey> {
            let a = to.get(a).copied().flatten()?;
            let b = if b > STATIC - MAX_WALLS {
                b
            } else {
                to.get(b).copied().flatten()?
            };
            Some((a, b))
        };
        fn moved<V>(map: &mut FxHashMap<PairKey, V>, pair: impl Fn(PairKey) -> Option<PairKey>) {
            *map = map
                .drain()
                .filter_map(|(key, v)| pair(key).map(|key| (key, v)))
                .collect();
        }
        moved(&mut self.kept, pair);
        moved(&mut self.warm, pair);
        moved(&mut self.carried, pair);
        self.next_warm.clear();
        self.next_carried.clear();
        self.near = Near::default();
        let grain = |i: usize| to.get(i).copied().flatten();
        self.forces.retain_mut(|f| {
            // `a` is STATIC for a wall's force.
            let a = if f.a == STATIC {
                Some(STATIC)
            } else {
                grain(f.a)
            };
            match (a, grain(f.b)) {
                (Some(a), Some(b)) => {
                    (f.a, f.b) = (a, b);
                    true
                }
                _ => false,
            }
        });
        self.woken.clear();
    }

    /// Forget the masses only (a density changed): the next step computes every grain's
    /// again. The kept impulses stay, as a first guess the solver corrects within the step.
    pub fn forget_masses(&mut self) {
        self.inverse.clear();
    }
}

/// One soft step of `bodies` (see the module docs). `materials[g]` is the material of group
/// `g` (grains of a group past its end take the last one, or the default), `wall` the walls'.
#[allow(clippy::too_many_arguments)]
pub fn step_or_stop(
    bodies: &mut [Body],
    walls: &Walls,
    boundaries: &[Boundary],
    motions: &[WallMotion],
    materials: &[Material],
    wall: &Material,
    settings: &Settings,
    work: &mut SoftWorkspace,
    stop: &AtomicBool,
) -> Result<StepStats, Stopped> {
    let soft = &settings.soft;
    let h = settings.step;
    let n = soft.substeps.max(1);
    let hs = h / f64::from(n);
    let material = |b: &Body| material_of(materials, b.group);
    wake_at_moving_walls(bodies, boundaries, motions);
    masses(bodies, &material, work);
    let sleeps = settings.sleep_radius > 0.0;
    work.awake.clear();
    work.awake
        .extend(bodies.iter().map(|b| !b.asleep(settings)));
    work.active.clear();
    work.active.extend(
        work.inverse
            .iter()
            .zip(&work.awake)
            .map(|(&m, &awake)| if awake { m } else { (0.0, 0.0) }),
    );
    let gravity = Vec2::new(0.0, -settings.gravity);
    let mut all = std::mem::take(&mut work.walls);
    all.clear();
    all.extend(walls.boundaries());
    all.extend_from_slice(boundaries);
    // The box's walls are still; the boundaries move as `motions` says (still where it ends).
    work.motions.clear();
    work.motions.resize(3, WallMotion::default());
    work.motions.extend_from_slice(motions);
    work.motions.resize(all.len(), WallMotion::default());
    let found = find_contacts(bodies, &all, settings, work, stop);
    work.walls = all;
    let mut stats = found?;
    prepare(bodies, &material, wall, settings, hs, work);
    stats.contacts = work.constraints.len();

    let SoftWorkspace {
        active,
        awake,
        constraints,
        start,
        solids,
        kept,
        batches,
        ..
    } = work;
    batches.build(constraints, bodies.len());
    start.clear();
    start.extend(bodies.iter().map(|b| (b.center, b.angle)));
    solids.clear();
    solids.extend(bodies.iter().zip(active.iter()).map(|(b, &(m, i))| Solid {
        v: b.velocity,
        w: b.angular_velocity,
        inv_mass: m,
        inv_inertia: i,
        ..Solid::WALL
    }));
    // One record per wall, after the grains': its motion, no mass.
    solids.extend(work.motions.iter().map(|m| Solid {
        v: m.v,
        w: m.w,
        ..Solid::WALL
    }));
    let moving: Vec<usize> = (0..work.motions.len())
        .filter(|&k| work.motions[k].moves())
        .map(|k| bodies.len() + k)
        .collect();
    let (lin, ang) = (
        1.0 / (1.0 + hs * soft.linear_damping),
        1.0 / (1.0 + hs * soft.angular_damping),
    );
    let mut state = State { solids };
    for substep in 0..n {
        if stop.load(Ordering::Relaxed) {
            return Err(Stopped);
        }
        // (A driven grain keeps the velocity its drive gives it.)
        for ((s, _), _) in state
            .solids
            .iter_mut()
            .zip(awake.iter())
            .zip(bodies.iter())
            .filter(|((_, a), b)| **a && b.kind.is_dynamic())
        {
            s.v = (s.v + gravity * hs) * lin;
            s.w *= ang;
        }
        batches.warm_start(constraints, &mut state);
        batches.solve(constraints, &mut state, hs, soft, true);
        for (i, b) in bodies.iter_mut().enumerate().filter(|&(i, _)| awake[i]) {
            let s = &mut state.solids[i];
            b.center += s.v * hs;
            b.angle += s.w * hs;
            s.shift = b.center - start[i].0;
            s.turn = Rotation::small(b.angle - start[i].1);
        }
        // A moving wall's motion since the step's start, at its own velocity.
        let elapsed = hs * f64::from(substep + 1);
        for &k in &moving {
            let s = &mut state.solids[k];
            s.shift = s.v * elapsed;
            s.turn = Rotation::new(s.w * elapsed);
        }
        batches.solve(constraints, &mut state, hs, soft, false);
    }
    batches.write_back(constraints);
    restitution(constraints, &mut state, soft);
    for (i, b) in bodies.iter_mut().enumerate() {
        b.previous_center = start[i].0;
        b.previous_angle = start[i].1;
        b.velocity = state.solids[i].v;
        b.angular_velocity = state.solids[i].w;
    }
    work.woken.clear();
    if sleeps && settings.sleep_islands {
        let falling = update_sleep_islands(bodies, constraints, awake, kept, settings);
        settle(constraints, &mut state, &falling, gravity, hs, soft);
    } else if sleeps {
        update_sleep(bodies, constraints, awake, settings, &mut work.woken);
    }
    forces(bodies, hs, work);
    keep(work);
    Ok(stats)
}

/// Grains within reach of a moving wall or a moving driven grain do not sleep: a sleeper holds
/// still as a wall does, and a moving wall would go through it.
fn wake_at_moving_walls(bodies: &mut [Body], boundaries: &[Boundary], motions: &[WallMotion]) {
    for (wall, m) in boundaries.iter().zip(motions) {
        if !m.moves() {
            continue;
        }
        for b in bodies.iter_mut().filter(|b| b.kind.is_dynamic()) {
            if wall.distance(b.center) < b.shape.bounding_radius() + 2.0 * SPECULATIVE {
                b.calm = 0;
            }
        }
    }
    let driven: Vec<(Vec2, f64)> = bodies
        .iter()
        .filter(|b| {
            b.kind == BodyKind::Kinematic && (b.velocity != Vec2::ZERO || b.angular_velocity != 0.0)
        })
        .map(|b| (b.center, b.shape.bounding_radius()))
        .collect();
    for (c, r) in driven {
        for b in bodies.iter_mut().filter(|b| b.kind.is_dynamic()) {
            if (b.center - c).norm() < r + b.shape.bounding_radius() + 2.0 * SPECULATIVE {
                b.calm = 0;
            }
        }
    }
}

/// The inverse masses of grains not seen before (grains only ever join the end of the list).
fn masses(bodies: &[Body], material: &impl Fn(&Body) -> Material, work: &mut SoftWorkspace) {
    if work.inverse.len() > bodies.len() {
        work.inverse.clear();
    }
    for b in &bodies[work.inverse.len()..] {
        if !b.kind.is_dynamic() {
            work.inverse.push((0.0, 0.0));
            continue;
        }
        let (mass, inertia) = material(b).mass_and_inertia(&b.shape);
        let inv = |x: f64| {
            if x > 0.0 && x.is_finite() {
                1.0 / x
            } else {
                0.0
            }
        };
        work.inverse.push((inv(mass), inv(inertia)));
    }
}

/// A grain as the substeps see it: one record per grain, so that a contact reads two records
/// (six arrays before); the last one stands for the walls, no mass and no motion, so that the
/// hot loops need no branch for them and give the same bits as with one. The solve's
/// instructions fell by 30% (callgrind, settled mixed heap), its time hardly (the passes now
/// run in colour batches, [`batch`]).
#[derive(Clone, Copy, Debug)]
struct Solid {
    v: Vec2,
    w: f64,
    /// Its motion since the step's start: the centre's shift and the rotation.
    shift: Vec2,
    turn: Rotation,
    /// As the solver sees them (a sleeper's are 0: it holds its neighbours as a wall does).
    inv_mass: f64,
    inv_inertia: f64,
}

impl Solid {
    const WALL: Solid = Solid {
        v: Vec2::ZERO,
        w: 0.0,
        shift: Vec2::ZERO,
        turn: Rotation::IDENTITY,
        inv_mass: 0.0,
        inv_inertia: 0.0,
    };
}

/// The grains' velocities and motion during the substeps: from `solids[wall]` on, the walls'.
struct State<'a> {
    solids: &'a mut [Solid],
}

/// Record `i` is a grain's, or a wall's past them ([`Constraint::slot_a`]).
impl State<'_> {
    #[inline(always)]
    fn velocity(&self, i: usize) -> (Vec2, f64) {
        let s = &self.solids[i];
        (s.v, s.w)
    }

    /// How far the point `r` (from grain `i`'s start centre) has moved since the step's start.
    #[inline(always)]
    fn moved(&self, i: usize, r: Vec2) -> Vec2 {
        let s = &self.solids[i];
        s.shift + s.turn.apply(r) - r
    }

    #[inline(always)]
    fn apply(&mut self, i: usize, r: Vec2, impulse: Vec2, sign: f64) {
        let s = &mut self.solids[i];
        s.v += impulse * (sign * s.inv_mass);
        s.w += sign * s.inv_inertia * r.cross(impulse);
    }

    #[inline(always)]
    fn apply_angular(&mut self, i: usize, impulse: f64) {
        let s = &mut self.solids[i];
        s.w += s.inv_inertia * impulse;
    }
}

/// `omega x r` in 2D.
fn spin(w: f64, r: Vec2) -> Vec2 {
    Vec2::new(-w * r.y, w * r.x)
}

/// The relative velocity of B's point to A's.
fn relative(s: &State, c: &Constraint, p: &Point) -> Vec2 {
    let (va, wa) = s.velocity(c.slot_a);
    let (vb, wb) = s.velocity(c.b);
    (vb + spin(wb, p.rb)) - (va + spin(wa, p.ra))
}

/// A pair to test: the grains and the warm start of their last contact.
type PairEntry = (usize, usize, Option<WarmStart>);

/// Grains per task of the pairs' search.
const PAIR_CHUNK: usize = 1024;

/// Stage 1: the contacts of the step, tested at the poses of free flight, as manifolds with
/// their points anchored (module docs). Grain pairs are tested on all cores, in a fixed order
/// of pairs, so the result does not depend on the number of threads.
fn find_contacts(
    bodies: &[Body],
    walls: &[Boundary],
    settings: &Settings,
    work: &mut SoftWorkspace,
    stop: &AtomicBool,
) -> Result<StepStats, Stopped> {
    let h = settings.step;
    let narrow = settings.narrow();
    let fall = Vec2::new(0.0, -settings.gravity * h);
    work.predicted.clear();
    // A driven grain does not fall: it is where its drive puts it. (A fixed grain's predicted
    // pose still falls `g h^2`, as it always has, though it never moves: without that fall the
    // silo of tests/beverloo.rs, on fixed planks, discharged at rates that fit Beverloo's
    // exponent 1.77 instead of 1.60, the six widths' fit being that sensitive (docs/silo.md).)
    work.predicted.extend(bodies.iter().map(|b| {
        let fall = if b.kind == BodyKind::Kinematic {
            Vec2::ZERO
        } else {
            fall
        };
        Pose::from_parts(
            b.center + (b.velocity + fall) * h,
            b.angle + b.angular_velocity * h,
        )
    }));
    // The boxes and the pairs on all cores too, in the grains' order (the same pairs in the
    // same order): these passes go over every grain, awake or asleep, and on one core they
    // kept the 100,000-grain pour at 1.23 cores; on all, it rests in 17% less time.
    work.boxes.clear();
    work.boxes.par_extend(
        bodies
            .par_iter()
            .zip(&work.predicted)
            .map(|(b, p)| b.shape.bounding_box(p)),
    );
    // The pairs of fat boxes kept from the last step, looked up again only for the grains whose
    // boxes left theirs ([`Near`]): the same pairs as the broad phase's, in the same order.
    work.near.refresh(&work.boxes, settings.broad_phase);
    let disks: Vec<bool> = bodies
        .iter()
        .map(|b| settings.narrow_phase == NarrowPhase::Interval && b.shape.is_circle())
        .collect();
    let disks = &disks;
    let (boxes, awake, warm, near) = (&work.boxes, &work.awake, &work.warm, &work.near);
    // A pair is tested when one of its grains moves under its contacts: awake and dynamic (a
    // driven grain against a sleeper, a fixed grain or a wall has no mass on either side; the
    // sleepers near a moving driven grain were woken).
    let free = |i: usize| awake[i] && bodies[i].kind.is_dynamic();
    work.pairs.clear();
    work.pairs.par_extend(
        (0..bodies.len().div_ceil(PAIR_CHUNK))
            .into_par_iter()
            .flat_map_iter(|c| {
                let mut out = Vec::new();
                for i in c * PAIR_CHUNK..((c + 1) * PAIR_CHUNK).min(bodies.len()) {
                    for &j in near.later(i) {
                        let j = j as usize;
                        if (free(i) || free(j))
                            && (if disks[i] && disks[j] {
                                boxes[i].grown(SPECULATIVE).intersects(&boxes[j])
                            } else {
                                boxes[i].intersects(&boxes[j])
                            })
                        {
                            out.push((i, j, warm.get(&(i, j)).copied()));
                        }
                    }
                }
                out
            }),
    );
    // Once a grain, not once a point's lever (a sine and a cosine each: 4% of a settled heap's
    // step went to them).
    work.turns.clear();
    work.turns.extend(
        bodies
            .iter()
            .zip(&work.predicted)
            .map(|(b, p)| Rotation::small(p.angle() - b.angle)),
    );
    let (predicted, turns, carried) = (&work.predicted, &work.turns, &work.carried);
    let reach = settings.soft.carry_reach;
    let carrying = reach > 0.0 && settings.narrow_phase == NarrowPhase::Interval;
    // Each pair's manifold, anchored below: a constraint is four times a manifold's size, and
    // moving constraints out of the parallel answers was 2-3% of a settled heap's step.
    type Found = (Option<Manifold>, Option<WarmStart>, Option<Carried>);
    let found: Vec<Option<Found>> = work
        .pairs
        .par_iter()
        .map(|&(i, j, warm)| {
            if stop.load(Ordering::Relaxed) {
                return None;
            }
            let (a, b) = (&bodies[i], &bodies[j]);
            let (pa, pb) = (&predicted[i], &predicted[j]);
            let carry = carrying && !(a.shape.is_circle() && b.shape.is_circle());
            if carry
                && let Some(c) = carried.get(&(i, j))
                && let Some(m) = c.manifold(&a.shape, pa, &b.shape, pb, reach)
            {
                return Some((Some(m), warm, Some(*c)));
            }
            // Flat grains by their faces, where those prove the answer (no warm start kept:
            // no Newton solve ran).
            if let Some(m) = narrow.flat(&a.shape, pa, &b.shape, pb, PATCH_REACH) {
                return Some((m, None, None));
            }
            let mut warm = warm;
            let c = narrow.pair(&a.shape, pa, &b.shape, pb, &mut warm);
            // The manifold here too, on all cores: a blocky pair's patch search costs more than
            // its narrow phase.
            let Some(p) = c.penetration else {
                let m = (disks[i] && disks[j])
                    .then(|| {
                        speculative(
                            pa.center(),
                            a.shape.semi_axes().x,
                            pb.center(),
                            b.shape.semi_axes().x,
                        )
                    })
                    .flatten();
                return Some((m, warm, None));
            };
            let m = grain_manifold(&a.shape, pa, &b.shape, pb, &p, PATCH_REACH);
            let kept = carry
                .then(|| Carried::new(&a.shape, pa, &b.shape, pb, &m, &p))
                .flatten();
            Some((Some(m), warm, kept))
        })
        .collect();
    if stop.load(Ordering::Relaxed) {
        return Err(Stopped);
    }
    let mut stats = StepStats {
        tests: work.pairs.len(),
        ..StepStats::default()
    };
    work.next_warm.clear();
    work.next_carried.clear();
    work.constraints.clear();
    // In the pairs' order; the manifolds anchored here, one constraint each.
    for (&(i, j, _), answer) in work.pairs.iter().zip(&found) {
        let (manifold, warm, kept) = answer.as_ref().expect("not stopped");
        if let Some(w) = warm {
            work.next_warm.insert((i, j), *w);
        }
        if let Some(c) = kept {
            work.next_carried.insert((i, j), *c);
        }
        if let Some(m) = manifold {
            work.constraints.push(anchored(
                i,
                j,
                (i, j),
                m,
                bodies,
                predicted,
                turns,
                settings.slop,
                &work.motions,
                h,
            ));
        }
    }
    let wall_boxes: Vec<Aabb> = walls.iter().map(Boundary::bounding_box).collect();
    let (boxes, motions) = (&work.boxes, &work.motions);
    // Each awake grain against each wall whose box it meets, on all cores, collected in the
    // order of the grains and walls.
    let at_walls: Vec<(usize, Vec<Constraint>)> = (0..bodies.len())
        .into_par_iter()
        .filter(|&i| free(i))
        .map(|i| {
            let b = &bodies[i];
            let pose = &predicted[i];
            let mut tests = 0;
            let mut found = Vec::new();
            for (k, wall) in walls.iter().enumerate() {
                let reach = if disks[i] { SPECULATIVE } else { 0.0 };
                if !boxes[i].grown(reach).intersects(&wall_boxes[k]) {
                    continue;
                }
                tests += 1;
                let c = narrow.wall(&b.shape, pose, wall);
                let m = match c.penetration {
                    Some(p) => Some(wall_manifold(&b.shape, pose, wall, &p, PATCH_REACH)),
                    None if disks[i] => {
                        // The normal from the wall (A) into the disk (B).
                        let r = b.shape.semi_axes().x;
                        let c = pose.center();
                        let (n, gap) = (wall.normal(c), wall.distance(c) - r);
                        gap_contact(n, gap, pose.center(), -(r + 0.5 * gap))
                    }
                    None => None,
                };
                if let Some(m) = m {
                    found.push(anchored(
                        STATIC,
                        i,
                        (i, STATIC - k),
                        &m,
                        bodies,
                        predicted,
                        turns,
                        settings.slop,
                        motions,
                        h,
                    ));
                }
            }
            (tests, found)
        })
        .filter(|(tests, _)| *tests > 0)
        .collect();
    for (tests, found) in at_walls {
        stats.tests += tests;
        work.constraints.extend(found);
    }
    Ok(stats)
}

/// A manifold found at the predicted poses, as a constraint between `a` and `b`. Each point's
/// lever is its offset from the grain's predicted centre: where the contact is, not the
/// material point that will be there (turned back to the step's start, a rolling disk's lever
/// tilts by its turn in one step, and the normal impulse then brakes the rolling like a
/// rolling resistance of that angle: measured, 25% slow at 3 radians per second). The
/// separation is carried back to the step's start along the motion the substeps will measure
/// ([`separation`]), so that at the predicted poses it is the narrow phase's.
#[allow(clippy::too_many_arguments)]
fn anchored(
    a: usize,
    b: usize,
    key: PairKey,
    m: &Manifold,
    bodies: &[Body],
    predicted: &[Pose],
    turns: &[Rotation],
    slop: f64,
    motions: &[WallMotion],
    step: f64,
) -> Constraint {
    let star = |i: usize| i != STATIC && bodies[i].shape.is_star();
    // A wall's motion (zero for a still one, whose points keep no lever and do not move).
    let wall = (a == STATIC).then(|| motions[STATIC - key.1]);
    let lever = |i: usize, c: Vec2| {
        if i == STATIC {
            match wall {
                Some(m) if m.moves() => c - m.pivot,
                _ => Vec2::ZERO,
            }
        } else {
            c - predicted[i].center()
        }
    };
    // How far the point at offset `r` moves from the start to the predicted pose (a moving
    // wall's, over the step at its velocity).
    let moved = |i: usize, r: Vec2| {
        if i == STATIC {
            match wall {
                Some(m) if m.moves() => m.v * step + Rotation::new(m.w * step).apply(r) - r,
                _ => Vec2::ZERO,
            }
        } else {
            predicted[i].center() - bodies[i].center + turns[i].apply(r) - r
        }
    };
    let mut points = [Point::ZERO; 3];
    let mp = m.points();
    for (q, p) in points.iter_mut().zip(mp) {
        let (ra, rb) = (lever(a, p.point), lever(b, p.point));
        q.ra = ra;
        q.rb = rb;
        q.base = p.separation - m.normal.dot(moved(b, rb) - moved(a, ra));
        q.id = p.id;
    }
    Constraint {
        a,
        b,
        slot_a: match wall {
            Some(_) => bodies.len() + (STATIC - key.1),
            None => a,
        },
        key,
        normal: m.normal,
        friction: 0.0,
        restitution: 0.0,
        rolling_resistance: 0.0,
        lever: 0.0,
        slop: slop + if star(a) || star(b) { STAR_SLOP } else { 0.0 },
        star: star(a) || star(b),
        rolling_mass: 0.0,
        rolling_impulse: 0.0,
        softness: Softness {
            bias_rate: 0.0,
            mass_scale: 1.0,
            impulse_scale: 0.0,
        },
        points,
        len: mp.len(),
    }
}

/// Stage 2: masses, materials, softness and the impulses kept from the last step.
fn prepare(
    bodies: &[Body],
    material: &impl Fn(&Body) -> Material,
    wall: &Material,
    settings: &Settings,
    hs: f64,
    work: &mut SoftWorkspace,
) {
    let soft = &settings.soft;
    let hertz = soft.contact_hertz.min(0.25 / hs);
    let grains = Softness::new(hertz, soft.damping_ratio, hs);
    let walls = Softness::new(2.0 * hertz, soft.damping_ratio, hs);
    let star_hertz = hertz.min(STAR_HERTZ);
    let star_grains = Softness::new(star_hertz, soft.damping_ratio, hs);
    let star_walls = Softness::new(2.0 * star_hertz, soft.damping_ratio, hs);
    let inverse = &work.active;
    let inv = |i: usize| {
        if i == STATIC { (0.0, 0.0) } else { inverse[i] }
    };
    let motions = &work.motions;
    let vel = |c: &Constraint, i: usize| {
        if i == STATIC {
            let m = motions[STATIC - c.key.1];
            (m.v, m.w)
        } else {
            (bodies[i].velocity, bodies[i].angular_velocity)
        }
    };
    for c in &mut work.constraints {
        let ma = if c.a == STATIC {
            *wall
        } else {
            material(&bodies[c.a])
        };
        let mb = material(&bodies[c.b]);
        (c.friction, c.restitution, c.rolling_resistance) = mix(&ma, &mb);
        c.softness = match (c.a == STATIC, c.star) {
            (true, false) => walls,
            (false, false) => grains,
            (true, true) => star_walls,
            (false, true) => star_grains,
        };
        let ((ma, ia), (mb, ib)) = (inv(c.a), inv(c.b));
        let (n, t) = (c.normal, Vec2::new(c.normal.y, -c.normal.x));
        let kept = work.kept.get(&c.key).copied().unwrap_or_default();
        let ((va, wa), (vb, wb)) = (vel(c, c.a), vel(c, c.b));
        let mut lever = 0.0;
        for p in &mut c.points[..c.len] {
            let k = |d: Vec2| {
                let (ca, cb) = (p.ra.cross(d), p.rb.cross(d));
                ma + mb + ia * ca * ca + ib * cb * cb
            };
            p.normal_mass = 1.0 / k(n);
            p.tangent_mass = 1.0 / k(t);
            let dv = (vb + spin(wb, p.rb)) - (va + spin(wa, p.ra));
            p.closing = dv.dot(n);
            let slot = usize::from(p.id);
            p.normal_impulse = kept.normal[slot];
            p.tangent_impulse = kept.tangent[slot];
            p.max_normal_impulse = 0.0;
            // Against a wall, the grain's own arm.
            lever += if c.a == STATIC {
                p.rb.norm()
            } else {
                0.5 * (p.ra.norm() + p.rb.norm())
            };
        }
        c.lever = lever / c.len as f64;
        let k = ia + ib;
        c.rolling_mass = if k > 0.0 { 1.0 / k } else { 0.0 };
        c.rolling_impulse = kept.rolling;
    }
}

/// The current separation of a point: its start value moved by the bodies' motion since.
fn separation(s: &State, c: &Constraint, p: &Point) -> f64 {
    p.base + c.normal.dot(s.moved(c.b, p.rb) - s.moved(c.slot_a, p.ra))
}

/// Applies the impulses one contact accumulated so far (from the last step, then the last
/// substep). The substeps run it for the contacts batch by batch ([`batch`]).
fn warm_one(c: &Constraint, s: &mut State) {
    let t = Vec2::new(c.normal.y, -c.normal.x);
    for p in &c.points[..c.len] {
        let impulse = c.normal * p.normal_impulse + t * p.tangent_impulse;
        s.apply(c.slot_a, p.ra, impulse, -1.0);
        s.apply(c.b, p.rb, impulse, 1.0);
    }
    s.apply_angular(c.slot_a, -c.rolling_impulse);
    s.apply_angular(c.b, c.rolling_impulse);
}

/// One pass over one contact: the normal impulses, then friction and rolling resistance,
/// each clamped by the normal impulses just found (solved the other way round, the normal
/// pass that follows can lower them below what the friction used: measured, a block sliding
/// down a slope with `mu = 0.3` was held back as if by 0.4). With `bias`, overlaps deeper than
/// the slop are pushed out softly; without, only the velocities are made to agree (the
/// relax). The substeps run it for the contacts batch by batch ([`batch`]).
fn solve_one(c: &mut Constraint, s: &mut State, hs: f64, soft: &SoftSettings, bias: bool) {
    let n = c.normal;
    let t = Vec2::new(n.y, -n.x);
    for k in 0..c.len {
        let p = c.points[k];
        let sep = separation(s, c, &p) + c.slop;
        let (push, mass_scale, impulse_scale) = if sep > 0.0 {
            // Apart: the grains may close the gap within the substep, no more.
            (sep / hs, 1.0, 0.0)
        } else if bias {
            (
                max(c.softness.bias_rate * sep, -soft.push_out),
                c.softness.mass_scale,
                c.softness.impulse_scale,
            )
        } else {
            (0.0, 1.0, 0.0)
        };
        let vn = relative(s, c, &p).dot(n);
        let raw = -p.normal_mass * mass_scale * (vn + push) - impulse_scale * p.normal_impulse;
        let next = max(p.normal_impulse + raw, 0.0);
        let d = next - p.normal_impulse;
        let q = &mut c.points[k];
        // Closing in from apart, not yet pushed this step: the speed at impact so far (once
        // pushed, a separation rounded a hair above 0 must not read the resting speed).
        if bias && sep > 0.0 && p.max_normal_impulse == 0.0 {
            q.closing = vn;
        }
        q.normal_impulse = next;
        q.max_normal_impulse = max(q.max_normal_impulse, next);
        s.apply(c.slot_a, p.ra, n * d, -1.0);
        s.apply(c.b, p.rb, n * d, 1.0);
    }
    for k in 0..c.len {
        let p = c.points[k];
        let vt = relative(s, c, &p).dot(t);
        let most = c.friction * p.normal_impulse;
        let next = clamp(p.tangent_impulse - p.tangent_mass * vt, -most, most);
        let d = next - p.tangent_impulse;
        c.points[k].tangent_impulse = next;
        s.apply(c.slot_a, p.ra, t * d, -1.0);
        s.apply(c.b, p.rb, t * d, 1.0);
    }
    if c.rolling_resistance > 0.0 {
        let total = c.points[..c.len]
            .iter()
            .fold(0.0, |sum, p| sum + p.normal_impulse);
        let (_, wa) = s.velocity(c.slot_a);
        let (_, wb) = s.velocity(c.b);
        let most = c.rolling_resistance * c.lever * total;
        let old = c.rolling_impulse;
        c.rolling_impulse = clamp(old - c.rolling_mass * (wb - wa), -most, most);
        let d = c.rolling_impulse - old;
        s.apply_angular(c.slot_a, -d);
        s.apply_angular(c.b, d);
    }
}

/// `a` if it is greater than `b`, else `b`: written out rather than `f64::max`, which leaves
/// its answer on signed zeros open, so that the lanes of [`batch`] give the same bits.
#[inline(always)]
fn max(a: f64, b: f64) -> f64 {
    if a > b { a } else { b }
}

/// `x` within `[lo, hi]`, `lo` tried first (`f64::clamp`'s order, without its checks).
#[inline(always)]
fn clamp(x: f64, lo: f64, hi: f64) -> f64 {
    let y = if x < lo { lo } else { x };
    if y > hi { hi } else { y }
}

/// Stage 4: points that closed faster than the threshold and were pushed get the normal
/// velocity `-e` times their closing one: the speed at impact, taken at the substep where the
/// point closed. (Taken at the step's start until 2026-12-06, it missed up to `g h` of a
/// fall: contacts are found a step ahead, at the poses of free flight, and a ball dropped 2
/// units at `h = 0.01` rebounded 2.4-4.5% below `e^2 h`.)
fn restitution(constraints: &mut [Constraint], s: &mut State, soft: &SoftSettings) {
    for c in constraints.iter_mut() {
        if c.restitution == 0.0 {
            continue;
        }
        let n = c.normal;
        for k in 0..c.len {
            let p = c.points[k];
            if p.closing > -soft.restitution_threshold || p.max_normal_impulse == 0.0 {
                continue;
            }
            let vn = relative(s, c, &p).dot(n);
            let raw = -p.normal_mass * (vn + c.restitution * p.closing);
            let next = (p.normal_impulse + raw).max(0.0);
            let d = next - p.normal_impulse;
            c.points[k].normal_impulse = next;
            s.apply(c.slot_a, p.ra, n * d, -1.0);
            s.apply(c.b, p.rb, n * d, 1.0);
        }
    }
}

/// Sleeping, by the paper model's rule (see [`Settings::sleep_radius`]): a grain that stays
/// within `sleep_radius` of one point for `sleep_steps` steps in a row stops, and the solver
/// holds it still (its inverse masses are 0) until a grain that moved this step touches it.
/// Per grain, not by islands: a sleeper under a moving grain holds it up as the floor would.
/// Without it, a pyramid of twenty blocks crept 0.5 mm/s (the sequential solve leaves a little
/// tangential velocity at every substep; `tests/mechanics.rs`).
///
/// The sleepers it wakes are listed in `woken`.
fn update_sleep(
    bodies: &mut [Body],
    constraints: &[Constraint],
    awake: &[bool],
    s: &Settings,
    woken: &mut Vec<usize>,
) {
    count_calm(bodies, awake, s);
    for (b, _) in bodies
        .iter_mut()
        .zip(awake)
        .filter(|(b, a)| **a && b.kind.is_dynamic())
    {
        if b.calm >= s.sleep_steps {
            b.velocity = Vec2::ZERO;
            b.angular_velocity = 0.0;
        }
    }
    // A sleeper touched by a grain that moved wakes (and wakes its own neighbours in turn if
    // it moves).
    for c in constraints {
        for (me, other) in [(c.a, c.b), (c.b, c.a)] {
            if me == STATIC || awake[me] || !bodies[me].kind.is_dynamic() {
                continue;
            }
            if other != STATIC && awake[other] && bodies[other].calm == 0 {
                let b = &mut bodies[me];
                if b.calm != 0 {
                    woken.push(me);
                }
                b.calm = 0;
                b.anchor = b.center;
            }
        }
    }
}

/// Each awake grain's calm count: one more step within `sleep_radius` of its anchor, or 0 and a
/// new anchor where it is.
fn count_calm(bodies: &mut [Body], awake: &[bool], s: &Settings) {
    // (A driven grain is never calm: it moves as its drive says, whatever touches it.)
    for (b, _) in bodies
        .iter_mut()
        .zip(awake)
        .filter(|(b, a)| **a && b.kind.is_dynamic())
    {
        if (b.center - b.anchor).norm() > s.sleep_radius {
            b.anchor = b.center;
            b.calm = 0;
        } else {
            b.calm = b.calm.saturating_add(1);
        }
    }
}

/// Sleeping by islands (`sleep_islands`, as Box2D): grains that touch form an island, which
/// falls asleep only when every grain of it has stayed within `sleep_radius` of one point for
/// `sleep_steps` steps, all at the same step; a sleeping island that an awake grain touches
/// wakes whole. No awake grain then ever leans on a sleeper, and the contacts of a sleeping
/// island keep the forces of one and the same step, which balance: per grain, a sleeper under an
/// awake grain holds it as a wall would and is squeezed (measured: a contact's force rose from
/// 26 to 162 in 30 steps while neither grain moved), and neighbours fall asleep at different
/// steps, so the forces of a heap asleep grain by grain need not balance (docs/physics.md).
///
/// `kept`: the contacts of the step before (the pairs it tested, and those between sleepers,
/// which are not tested while they sleep; kept in dumps, so a resumed run goes on the same):
/// the sleeping islands' links, and links that a contact apart for a step does not break.
fn update_sleep_islands(
    bodies: &mut [Body],
    constraints: &[Constraint],
    awake: &[bool],
    kept: &FxHashMap<PairKey, Kept>,
    s: &Settings,
) -> Vec<bool> {
    let n = bodies.len();
    count_calm(bodies, awake, s);
    // The grain pairs in contact at the step before (walls' keys are past every grain), in
    // order (the map's own order depends on its history, which a resumed run does not share),
    // then this step's.
    // A static or driven body is in no island: it holds its neighbours as a wall does.
    let grains = |i: usize, j: usize| bodies[i].kind.is_dynamic() && bodies[j].kind.is_dynamic();
    let mut pairs: Vec<PairKey> = kept
        .keys()
        .filter(|&&(i, j)| i < n && j < n && grains(i, j))
        .copied()
        .collect();
    pairs.sort_unstable();
    pairs.extend(
        constraints
            .iter()
            .filter(|c| c.a != STATIC && grains(c.a, c.b))
            .map(|c| (c.a, c.b)),
    );
    // A sleeping island touched by an awake grain wakes whole: through the links between
    // sleepers, from every sleeper an awake grain touches now or touched at the step before (a
    // grain woken from outside, as the viewer's drag does, has left its island's contacts).
    let mut links: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut seeds: Vec<usize> = Vec::new();
    for &(i, j) in &pairs {
        match (awake[i], awake[j]) {
            (false, false) => {
                links[i].push(j);
                links[j].push(i);
            }
            (false, true) => seeds.push(i),
            (true, false) => seeds.push(j),
            (true, true) => {}
        }
    }
    let mut woken = vec![false; n];
    let mut queue: Vec<usize> = Vec::new();
    for i in seeds {
        if !woken[i] {
            woken[i] = true;
            queue.push(i);
        }
    }
    while let Some(i) = queue.pop() {
        let b = &mut bodies[i];
        b.calm = 0;
        b.anchor = b.center;
        for &j in &links[i] {
            if !woken[j] {
                woken[j] = true;
                queue.push(j);
            }
        }
    }
    // The awake islands (grains joined by the contacts of this step and the step before), and
    // whether each is calm throughout: its grains fall asleep together, or none does.
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let active = |i: usize| awake[i] || woken[i];
    for &(a, b) in &pairs {
        if active(a) && active(b) {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            // The smaller index as the root: the same islands whatever the order.
            parent[ra.max(rb)] = ra.min(rb);
        }
    }
    let mut calm = vec![true; n];
    for i in (0..n).filter(|&i| active(i)) {
        let r = root(&mut parent, i);
        calm[r] &= bodies[i].calm >= s.sleep_steps;
    }
    let mut falling = vec![false; n];
    for i in (0..n).filter(|&i| active(i)) {
        let r = root(&mut parent, i);
        let b = &mut bodies[i];
        if calm[r] {
            b.velocity = Vec2::ZERO;
            b.angular_velocity = 0.0;
            falling[i] = awake[i];
        } else if b.calm >= s.sleep_steps {
            // Calm enough, but its island is not: it waits, awake, for the rest.
            b.calm = s.sleep_steps - 1;
        }
    }
    falling
}

/// The most passes [`settle`] makes over an island's contacts.
const SETTLE_PASSES: usize = 2000;

/// How far from equilibrium [`settle`] stops: each grain's velocity after a pass within this
/// fraction of what gravity gives it in a substep (its net force within this fraction of its
/// weight), and its spin at its bounding radius likewise (its net torque).
const SETTLE_TOLERANCE: f64 = 1e-4;

/// The forces of an island falling asleep (`falling`), put in equilibrium before they are kept:
/// Gauss-Seidel passes over the island's contacts, the grains held where they are, each pass a
/// substep's gravity, the impulses kept so far and one pass without the push-out, until no grain
/// moves (its net force and torque within [`SETTLE_TOLERANCE`] of its weight). The substeps leave
/// a heap's forces off equilibrium by a few percent (one pass a substep: in the bidisperse heap of
/// docs/physics.md ("Heaps at rest"), the median grain 0.3%, 166 grains of 1,000 above 1%, the
/// worst 6%); a sleeping island keeps its forces (for `--forces`, the stress, and its warm start
/// when it wakes), so they are settled once, here. Apart points carry nothing (their push lets
/// them close only to the gap), friction stays within its cone and rolling resistance within
/// its bound: the equilibrium found is one the contacts can hold.
fn settle(
    constraints: &mut [Constraint],
    s: &mut State,
    falling: &[bool],
    gravity: Vec2,
    hs: f64,
    soft: &SoftSettings,
) {
    let mine = |i: usize| i != STATIC && falling.get(i).copied().unwrap_or(false);
    let island: Vec<usize> = (0..constraints.len())
        .filter(|&k| {
            let c = &constraints[k];
            mine(c.b) && (c.a == STATIC || mine(c.a))
        })
        .collect();
    if island.is_empty() {
        return;
    }
    let grains: Vec<usize> = (0..falling.len()).filter(|&i| falling[i]).collect();
    let kick = (gravity * hs).norm();
    for _ in 0..SETTLE_PASSES {
        for &i in &grains {
            s.solids[i].v = gravity * hs;
            s.solids[i].w = 0.0;
        }
        for &k in &island {
            warm_one(&constraints[k], s);
        }
        for &k in &island {
            solve_one(&mut constraints[k], s, hs, soft, false);
        }
        let still = grains.iter().all(|&i| {
            let d = &s.solids[i];
            d.v.norm() <= SETTLE_TOLERANCE * kick
                && (d.inv_inertia == 0.0 || d.inv_mass == 0.0 || {
                    // The spin a substep's torque of `SETTLE_TOLERANCE` weights at the grain's
                    // reach would give: `w = tau I^-1 hs`, `tau = tol m g r` (r = sqrt(I/m) as
                    // the reach, close enough for a bound on an imbalance).
                    let r2 = d.inv_mass / d.inv_inertia;
                    d.w.abs() * r2.sqrt() <= SETTLE_TOLERANCE * kick
                })
        });
        if still {
            break;
        }
    }
    for &i in &grains {
        s.solids[i].v = Vec2::ZERO;
        s.solids[i].w = 0.0;
    }
}

/// Each contact's force, from its last substep's impulses.
///
/// A contact between sleepers is not tested or solved; it keeps the force it had when they fell
/// asleep (so a sleeping heap still reports its weight on the floor).
fn forces(bodies: &[Body], hs: f64, work: &mut SoftWorkspace) {
    let awake = &work.awake;
    let asleep = |i: usize| i == STATIC || !awake.get(i).copied().unwrap_or(true);
    let mut previous = std::mem::take(&mut work.forces);
    previous.retain(|f| asleep(f.a) && asleep(f.b) && f.b < bodies.len());
    work.forces = previous;
    // The grains' motion over the step, as the substeps left it in their records.
    let state = State {
        solids: &mut work.solids,
    };
    for c in &work.constraints {
        let points = &c.points[..c.len];
        let overlap = points.iter().fold(f64::NEG_INFINITY, |deepest, p| {
            deepest.max(-separation(&state, c, p))
        });
        let normal: f64 = points.iter().map(|p| p.normal_impulse).sum();
        let tangent: f64 = points.iter().map(|p| p.tangent_impulse).sum();
        let at = |p: &Point| bodies[c.b].center + p.rb;
        let point = if normal > 0.0 {
            points.iter().fold(Vec2::ZERO, |sum, p| {
                sum + at(p) * (p.normal_impulse / normal)
            })
        } else {
            points.iter().fold(Vec2::ZERO, |sum, p| sum + at(p)) * (1.0 / c.len as f64)
        };
        work.forces.push(ContactForce {
            a: c.a,
            b: c.b,
            wall: (c.a == STATIC).then(|| STATIC - c.key.1),
            point,
            normal: c.normal,
            normal_force: normal / hs,
            tangent_force: tangent / hs,
            overlap,
        });
    }
}

/// Stage 5: each contact's impulses, by pair and point, for the next step's warm start.
fn keep(work: &mut SoftWorkspace) {
    std::mem::swap(&mut work.warm, &mut work.next_warm);
    std::mem::swap(&mut work.carried, &mut work.next_carried);
    // Contacts between sleepers were not solved: they keep what they had.
    let awake = &work.awake;
    let asleep = |i: usize| !awake.get(i).copied().unwrap_or(true);
    work.kept
        .retain(|&(i, j), _| asleep(i) && (j > STATIC - MAX_WALLS || asleep(j)));
    for c in &work.constraints {
        let mut k = Kept {
            rolling: c.rolling_impulse,
            ..Kept::default()
        };
        for p in &c.points[..c.len] {
            k.normal[usize::from(p.id)] = p.normal_impulse;
            k.tangent[usize::from(p.id)] = p.tangent_impulse;
        }
        work.kept.insert(c.key, k);
    }
    // A sleeper woken keeps no impulse against another grain: each was found with one of the
    // two held still, and a sleeper holds up an awake grain as a wall does, so the impulse can
    // carry the other's weight, which its warm start would throw at the woken grain (a disk of
    // radius 0.04 under one of 0.8, 400 times its mass, left at 95 units/s, and at 288 when only
    // its contacts with other sleepers were forgotten: docs/physics.md, "Heaps at rest"). Its
    // contacts start from nothing, as new ones do; those with the walls keep theirs.
    if !work.woken.is_empty() {
        let mut woken = vec![false; work.awake.len()];
        for &i in &work.woken {
            woken[i] = true;
        }
        let grain = |k: usize| k < woken.len();
        work.kept
            .retain(|&(i, j), _| !(grain(j) && (woken[i] || woken[j])));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn of_friction(friction: f64) -> Material {
        Material {
            friction,
            ..Material::default()
        }
    }

    /// Friction mixes by the geometric mean (0.36 and 0.64: 0.48), and the largest frictions a
    /// material may have stay finite when mixed: two of 1e200 mixed to infinity, and a point
    /// with no normal impulse then had its friction bounded by `inf * 0`, not a number (no
    /// bound at all).
    #[test]
    fn frictions_mix_by_their_geometric_mean_and_stay_finite() {
        let (mu, _, _) = mix(&of_friction(0.36), &of_friction(0.64));
        assert!((mu - 0.48).abs() < 1e-15, "{mu}");
        let (mu, _, _) = mix(&of_friction(1e200), &of_friction(1e200));
        assert!(mu.is_finite() && (mu / 1e200 - 1.0).abs() < 1e-12, "{mu}");
        assert_eq!(mu * 0.0, 0.0);
    }
}

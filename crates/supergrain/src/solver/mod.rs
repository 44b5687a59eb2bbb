//! The solver (paper III, SPEC §5): Verlet integration with damping, then, grain by grain,
//! projection of its collisions with the other grains and the walls, repeated until none is
//! left or `max_iterations` is reached (Jakobsen, "Advanced character physics").
//!
//! Our additions, each needed for heaps to come to rest and each measured (docs/physics.md,
//! "Where we depart from the paper"): a slop below which contacts move a grain straight out without
//! turning it, pushes that never point into the other grain and are capped, two closing sweeps
//! over all grains (or, for deep heaps, one shock-propagation sweep from the floor up), and
//! deeper quadtrees for walls and for pairs with a star.
pub mod carry;
mod response;
pub mod soft;
pub mod strips;

pub use response::{project, safe_push};

use crate::body::{Body, Walls};
use crate::broad_phase::BroadPhase;
use crate::contact::{Contact, WarmStart};
use crate::geometry::{Aabb, Vec2};
use crate::settings::{Rotation, Settings};
use crate::shape::{Boundary, Pose};
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::sync::atomic::{AtomicBool, Ordering};

/// What one step did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// Grain-grain and grain-wall contacts found in the first projection pass of each grain.
    pub contacts: usize,
    /// Narrow-phase tests run.
    pub tests: usize,
}

/// A step abandoned half-way because a stop was requested (see [`step_or_stop`]): the grains are
/// then in no meaningful state, and the caller puts back those of the step's start.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the step was abandoned: a stop was requested")]
pub struct Stopped;

/// Reusable buffers, so a step allocates nothing once warm.
#[derive(Debug, Default)]
pub struct Workspace {
    /// Every grain's pose and bounding box, kept up to date as grains move (see
    /// [`Workspace::moved`]): the sine and cosine of a grain's angle once per move, not once
    /// per contact test.
    poses: Vec<Pose>,
    boxes: Vec<Aabb>,
    start: Vec<Vec2>,
    candidates: Vec<usize>,
    order: Vec<usize>,
    rank: Vec<usize>,
    /// Where each pair tested in this step (`(i, j)`, `i` the grain taking its turn) last found
    /// its deepest points: the next pass starts Newton there ([`warm_pair`]). Emptied at every
    /// step, so no run depends on it beyond the step: dumps and resumed runs are unchanged.
    /// Only pairs the certified path answered have one (not those its bounding circles parted).
    warm: HashMap<(usize, usize), WarmStart>,
}

/// One step of the paper's loop: for each grain in turn, Verlet, then projection of its
/// collisions until none is left or `max_iterations` passes are done. In a box wide enough for
/// [`Settings::strip_width`], the grains go strip by strip, strips far apart at once on all cores
/// ([`strips`]); `number` is the step's number, whose parity places the strips' cuts.
pub fn step<B: BroadPhase>(
    bodies: &mut [Body],
    walls: &Walls,
    settings: &Settings,
    broad: &mut B,
    work: &mut Workspace,
    number: u64,
) -> StepStats {
    let never = AtomicBool::new(false);
    match step_or_stop(bodies, walls, settings, broad, work, number, &never) {
        Ok(stats) => stats,
        Err(Stopped) => unreachable!("nothing raises a flag no one else sees"),
    }
}

/// [`step`], abandoned within one contact test once `stop` is raised: a step of a scene whose
/// tests are slow (a deep quadtree, many overlapping grains) can take minutes, and a stop
/// request must not wait for it. Abandoned, it returns [`Stopped`] and leaves `bodies` half
/// done: the caller restores them ([`crate::world::World::step_or_stop`] does). Not raised,
/// the step is [`step`]'s, bit for bit: the flag is only read.
pub fn step_or_stop<B: BroadPhase>(
    bodies: &mut [Body],
    walls: &Walls,
    settings: &Settings,
    broad: &mut B,
    work: &mut Workspace,
    number: u64,
    stop: &AtomicBool,
) -> Result<StepStats, Stopped> {
    let mut stats = StepStats::default();
    let boundaries = walls.boundaries();
    let ctx = Context {
        walls: &boundaries,
        wall_boxes: boundaries.map(|w| w.bounding_box()),
        settings,
        stop,
    };
    work.start.clear();
    work.start.extend(bodies.iter().map(|b| b.center));
    work.warm.clear();
    if let Some(strips) = strips::Strips::new(bodies, walls, settings, number) {
        strips.step(bodies, &ctx, &mut stats);
        // Each strip kept its own boxes; sleeping reads the final ones.
        rebuild_boxes(bodies, broad, work);
    } else {
        rebuild_boxes(bodies, broad, work);
        for i in 0..bodies.len() {
            if ctx.stopped() {
                break;
            }
            settle(i, bodies, &ctx, broad, work, &mut stats);
        }
        if settings.shock_propagation {
            let mut order = std::mem::take(&mut work.order);
            let mut rank = std::mem::take(&mut work.rank);
            shock_order(bodies, &mut order, &mut rank);
            for &i in &order {
                if ctx.stopped() {
                    break;
                }
                shock_grain(i, bodies, &ctx, broad, work, &mut stats, &rank);
            }
            work.order = order;
            work.rank = rank;
        } else {
            // The closing sweeps this replaces: grains handled late in the step push earlier
            // ones back into their neighbours; sweeping everything once or twice more leaves the
            // step with (nearly) no overlap instead of the last pushes'.
            for _ in 0..CLOSING_SWEEPS {
                let mut hit = 0;
                for i in 0..bodies.len() {
                    if ctx.stopped() {
                        break;
                    }
                    hit += sweep_grain(i, bodies, &ctx, broad, work, &mut stats);
                }
                if hit == 0 || ctx.stopped() {
                    break;
                }
            }
        }
    }
    if ctx.stopped() {
        return Err(Stopped);
    }
    if settings.sleep_radius > 0.0 {
        update_sleep(bodies, settings, broad, work);
    }
    Ok(stats)
}

/// Every grain's box, and the broad phase filed with them.
fn rebuild_boxes<B: BroadPhase>(bodies: &[Body], broad: &mut B, work: &mut Workspace) {
    work.poses.clear();
    work.poses.extend(bodies.iter().map(Body::pose));
    work.boxes.clear();
    work.boxes.extend(
        bodies
            .iter()
            .zip(&work.poses)
            .map(|(b, pose)| b.shape.bounding_box(pose)),
    );
    broad.rebuild(&work.boxes);
}

impl Workspace {
    /// Grain `i` has moved: its pose and box afresh, and the broad phase told.
    fn moved<B: BroadPhase>(&mut self, i: usize, body: &Body, broad: &mut B) {
        let pose = body.pose();
        self.poses[i] = pose;
        self.boxes[i] = body.shape.bounding_box(&pose);
        broad.update(i, &self.boxes[i]);
    }
}

/// Grain `i`'s turn in the step: Verlet, then projection passes until none finds a contact.
fn settle<B: BroadPhase>(
    i: usize,
    bodies: &mut [Body],
    ctx: &Context,
    broad: &mut B,
    work: &mut Workspace,
    stats: &mut StepStats,
) {
    if bodies[i].asleep(ctx.settings) {
        return;
    }
    verlet(&mut bodies[i], ctx.settings);
    work.moved(i, &bodies[i], broad);
    for pass in 0..ctx.settings.max_iterations {
        if ctx.stopped() {
            return;
        }
        let hit = resolve(i, bodies, ctx, broad, work, stats, None);
        if pass == 0 {
            stats.contacts += hit;
        }
        if hit == 0 {
            break;
        }
    }
}

/// Grain `i`'s pass in a closing sweep; how many contacts it corrected.
fn sweep_grain<B: BroadPhase>(
    i: usize,
    bodies: &mut [Body],
    ctx: &Context,
    broad: &mut B,
    work: &mut Workspace,
    stats: &mut StepStats,
) -> usize {
    if bodies[i].asleep(ctx.settings) {
        0
    } else {
        resolve(i, bodies, ctx, broad, work, stats, None)
    }
}

/// Counts calm steps, and wakes the sleepers near a grain that moved far this step (the grain
/// under them may have gone). A grain calm for `sleep_steps - 1` steps is ready; it falls
/// asleep at once, or, with shock propagation (deep heaps), once every grain whose box touches
/// its box is ready or asleep too (a local form of Box2D's islands), or after waiting
/// `sleep_steps` more steps for them. In a deep heap, put to sleep alone, a
/// grain becomes a wall to a neighbour still settling against it, which can then be squeezed
/// out of its place, move and wake it, every `sleep_steps` steps for ever (seen in the
/// 1,000-grain pour: a grain of rice wedged between two blocks at the wall). The wait is
/// bounded because a star's neighbours would otherwise never sleep: its spikes flicker in and
/// out of contact and it is seldom ready. The paper's small scenes do without waiting: with it
/// the mixed preset ran 2.8x slower, for no gain there.
fn update_sleep<B: BroadPhase>(
    bodies: &mut [Body],
    settings: &Settings,
    broad: &mut B,
    work: &mut Workspace,
) {
    let radius = settings.sleep_radius;
    let ready = settings.sleep_steps.saturating_sub(1);
    // Each grain on its own falls asleep as soon as it is calm. With shock propagation the calm
    // count stops at `ready`, and grains are put to sleep below, after all the wakes of the step.
    // (Doing that always made the mixed preset 2.4x slower: a grain woken by a neighbour's move
    // in the same step loses its calm there.)
    let together = settings.shock_propagation;
    for i in 0..bodies.len() {
        let b = &mut bodies[i];
        if b.asleep(settings) {
            continue;
        }
        // Drift: far from where it last woke its neighbours, however slowly it went.
        let drifted = (b.center - b.drift_anchor).norm() > DRIFT_WAKE * radius;
        if drifted {
            b.drift_anchor = b.center;
        }
        if (b.center - b.anchor).norm() <= radius {
            b.calm = b.calm.saturating_add(1);
            if together {
                b.calm = b.calm.min(ready);
            } else if b.calm == settings.sleep_steps {
                stop(b);
            }
        } else {
            b.anchor = b.center;
            b.calm = 0;
            b.waiting = 0;
        }
        wake_neighbours(i, drifted, bodies, settings, broad, work);
    }
    if !together {
        return;
    }
    for i in 0..bodies.len() {
        if bodies[i].calm != ready || bodies[i].asleep(settings) {
            continue;
        }
        work.candidates.clear();
        broad.candidates(i, &work.boxes, &mut work.candidates);
        bodies[i].waiting += 1;
        if bodies[i].waiting > settings.sleep_steps
            || work.candidates.iter().all(|&j| bodies[j].calm >= ready)
        {
            let b = &mut bodies[i];
            b.calm = settings.sleep_steps;
            b.waiting = 0;
            stop(b);
        }
    }
}

/// A grain falling asleep stops where it is: when woken, it starts from zero velocity.
fn stop(b: &mut Body) {
    b.previous_center = b.center;
    b.previous_angle = b.angle;
}

/// How far, in sleep radii, a grain may drift, however slowly, before it wakes the sleepers by
/// it. Without this, a grain creeping away by less than `sleep_radius` a step left its sleeping
/// neighbour in the air: in a 160-grain heap a block slept against the wall with a gap of 0.07
/// under it, and fell 0.24 when woken. At 1 (every time a grain leaves its calm anchor) the
/// circles preset kept 23.5 contacts a step awake instead of 13 and ran 1.9x slower; at 5 it
/// costs 15%, at 20 nothing, and a sleeper is left at most 5 radii (0.01 by default) above a gap.
pub const DRIFT_WAKE: f64 = 5.0;

/// Wakes the sleepers whose boxes touch grain `i`'s if it moved more than `sleep_radius` this
/// step, or has `drifted` [`DRIFT_WAKE`] radii since it last woke them (the grain under them may
/// have gone).
fn wake_neighbours<B: BroadPhase>(
    i: usize,
    drifted: bool,
    bodies: &mut [Body],
    settings: &Settings,
    broad: &mut B,
    work: &mut Workspace,
) {
    if drifted || (bodies[i].center - work.start[i]).norm() > settings.sleep_radius {
        work.candidates.clear();
        broad.candidates(i, &work.boxes, &mut work.candidates);
        for &j in &work.candidates {
            if bodies[j].asleep(settings) {
                bodies[j].calm = 0;
            }
        }
    }
}

/// What every projection pass of a step reads.
struct Context<'a> {
    walls: &'a [Boundary; 3],
    /// The walls' boxes: a grain whose box misses a wall's is not tested against it (the narrow
    /// phase would find the same from the same box, after computing it again).
    wall_boxes: [Aabb; 3],
    settings: &'a Settings,
    /// Raised when the step is to be abandoned ([`step_or_stop`]).
    stop: &'a AtomicBool,
}

impl Context<'_> {
    /// Whether a stop was requested: read before every contact test, so a step of slow tests
    /// ends within one of them. A relaxed load, as cheap as a plain one: it orders nothing, the
    /// abandoned work is thrown away.
    fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// The shock sweep's order, lowest centre first (ties by index), and each grain's rank in it.
fn shock_order(bodies: &[Body], order: &mut Vec<usize>, rank: &mut Vec<usize>) {
    order.clear();
    order.extend(0..bodies.len());
    order.sort_unstable_by(|&a, &b| {
        bodies[a]
            .center
            .y
            .total_cmp(&bodies[b].center.y)
            .then(a.cmp(&b))
    });
    rank.clear();
    rank.resize(bodies.len(), 0);
    for (r, &i) in order.iter().enumerate() {
        rank[i] = r;
    }
}

/// Shock propagation (Guendelman, Bridson and Fedkiw, "Nonconvex rigid bodies with stacking",
/// 2003), in the projection setting: the grains, lowest centre first, are each moved out of the
/// walls and of every grain below them, which no longer move. A step thus ends with every
/// contact resolved once, the upper grain taking the whole correction, so the weight of a deep
/// heap no longer squeezes its bottom layers: the grain-by-grain passes alone leave twenty
/// layers overlapping and trembling for ever.
///
/// And, as in XPBD's velocity pass, this correction is inelastic: it cancels the grain's
/// velocity into its supports but creates none away from them. Otherwise a grain the sweep lifts
/// by `d` leaves with speed `d / h`, rises, falls back and is lifted again.
///
/// A grain ranked below but met at the side (the push less than 30 degrees above horizontal)
/// is not a support: the two share that correction, as in the passes ([`SIDE_SINE`]).
///
/// This is grain `i`'s turn in it: out of the walls and of every grain ranked below it.
fn shock_grain<B: BroadPhase>(
    i: usize,
    bodies: &mut [Body],
    ctx: &Context,
    broad: &mut B,
    work: &mut Workspace,
    stats: &mut StepStats,
    rank: &[usize],
) {
    if bodies[i].asleep(ctx.settings) {
        return;
    }
    let before = bodies[i].center;
    for _ in 0..ctx.settings.max_iterations {
        if ctx.stopped() || resolve(i, bodies, ctx, broad, work, stats, Some(rank)) == 0 {
            break;
        }
    }
    let b = &mut bodies[i];
    if let Some(n) = (b.center - before).direction() {
        let v = before - b.previous_center;
        let kept = v - n * v.dot(n).min(0.0);
        b.previous_center = b.center - kept;
    }
}

/// Relaxation sweeps over all grains at the end of a step.
const CLOSING_SWEEPS: usize = 2;

/// In the shock sweep, a grain ranked below (lower centre) is met at the side when the push on
/// the upper one rises less than this sine above horizontal (30 degrees), or points down. It is
/// no support then: taking the whole correction lifted the taller of two grains side by side,
/// and clusters on the 100,000-grain heap rose slowly and collapsed again and again, never at
/// rest.
const SIDE_SINE: f64 = 0.5;

/// One projection pass for grain `i` against the walls and its broad-phase candidates; returns
/// how many of its contacts it corrected. With `rank` (shock propagation), only grains ranked
/// below `i` count and they do not move.
fn resolve<B: BroadPhase>(
    i: usize,
    bodies: &mut [Body],
    ctx: &Context,
    broad: &mut B,
    work: &mut Workspace,
    stats: &mut StepStats,
    rank: Option<&[usize]>,
) -> usize {
    let settings = ctx.settings;
    let mut hit = 0usize;
    for (wall, wall_box) in ctx.walls.iter().zip(&ctx.wall_boxes) {
        if ctx.stopped() {
            return hit;
        }
        if !work.boxes[i].intersects(wall_box) {
            continue;
        }
        stats.tests += 1;
        let contact = settings
            .narrow()
            .wall(&bodies[i].shape, &work.poses[i], wall);
        if let Some(p) = contact.penetration {
            // Walls do not move: the grain takes the whole correction.
            let push = safe_push(p.push, wall.normal(p.deepest), cap(&bodies[i]));
            project(&mut bodies[i], p.deepest, push, 1.0, settings.slop);
            work.moved(i, &bodies[i], broad);
            hit += 1;
        }
    }
    work.candidates.clear();
    broad.candidates(i, &work.boxes, &mut work.candidates);
    for k in 0..work.candidates.len() {
        let j = work.candidates[k];
        if !work.boxes[i].intersects(&work.boxes[j]) {
            continue;
        }
        if ctx.stopped() {
            return hit;
        }
        let sleeper = bodies[j].asleep(settings);
        if rank.is_some_and(|r| r[j] > r[i]) && !sleeper {
            // Seen from `j` when its turn comes (a sleeper's never comes).
            continue;
        }
        stats.tests += 1;
        let (a, b) = (&bodies[i], &bodies[j]);
        let (pose_a, pose_b) = (&work.poses[i], &work.poses[j]);
        let narrow = settings.narrow();
        let found = if narrow.starts_warm(&a.shape, &b.shape) {
            with_warm_start(&mut work.warm, (i, j), |warm| {
                narrow.pair_midpoints(&a.shape, pose_a, &b.shape, pose_b, warm)
            })
        } else {
            narrow.pair_midpoints(&a.shape, pose_a, &b.shape, pose_b, &mut None)
        };
        if let Some(p) = found.penetration {
            let away = bodies[i].center - bodies[j].center;
            let a_push = safe_push(p.a_push, away, cap(&bodies[i]));
            // Whether `j` holds like a wall, `i` taking the whole correction: in the shock
            // sweep a sleeper, or a grain below unless met at the side ([`SIDE_SINE`]); in the
            // passes a sleeper pushed into no deeper than the slop. Otherwise the two share it.
            let holds = match rank {
                Some(_) => {
                    let side = a_push.y < SIDE_SINE * a_push.norm();
                    sleeper || !side
                }
                None => sleeper && a_push.norm() <= settings.slop,
            };
            if holds {
                project(&mut bodies[i], p.a_deepest, a_push, 1.0, settings.slop);
            } else {
                if sleeper {
                    bodies[j].calm = 0;
                }
                let b_push = safe_push(p.b_push, -away, cap(&bodies[j]));
                project(&mut bodies[i], p.a_deepest, a_push, 0.5, settings.slop);
                project(&mut bodies[j], p.b_deepest, b_push, 0.5, settings.slop);
                work.moved(j, &bodies[j], broad);
            }
            work.moved(i, &bodies[i], broad);
            hit += 1;
        }
    }
    hit
}

/// Runs `test` from the pair's warm start, if it has one, and keeps what the test leaves: the
/// new start, or none when the certified path found nothing to start from (a quadtree answer),
/// as for a new pair. One lookup either way.
fn with_warm_start(
    warm: &mut HashMap<(usize, usize), WarmStart>,
    pair: (usize, usize),
    test: impl FnOnce(&mut Option<WarmStart>) -> Contact,
) -> Contact {
    match warm.entry(pair) {
        Entry::Occupied(mut kept) => {
            let mut start = Some(*kept.get());
            let found = test(&mut start);
            match start {
                Some(w) => *kept.get_mut() = w,
                None => {
                    kept.remove();
                }
            }
            found
        }
        Entry::Vacant(slot) => {
            let mut start = None;
            let found = test(&mut start);
            if let Some(w) = start {
                slot.insert(w);
            }
            found
        }
    }
}

/// The largest single correction of a grain: a quarter of its smaller semi-axis.
fn cap(b: &Body) -> f64 {
    0.25 * b.shape.min_semi_axis()
}

/// `x_{i+1} = x_i + (1 - delta)(x_i - x_{i-1}) + h^2 f / m`, with gravity only (`f / m = (0, -g)`).
fn verlet(b: &mut Body, s: &Settings) {
    let keep = 1.0 - s.damping;
    let next = b.center
        + (b.center - b.previous_center) * keep
        + Vec2::new(0.0, -s.gravity * s.step * s.step);
    b.previous_center = b.center;
    b.center = next;
    match s.rotation {
        Rotation::Projection => b.previous_angle = b.angle,
        Rotation::Inertia => {
            let next = b.angle + (b.angle - b.previous_angle) * keep;
            b.previous_angle = b.angle;
            b.angle = next;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::broad_phase::{Any, Kind};
    use crate::shape::Superellipse;

    /// Two ellipses resting against each other on the floor: their pair is warm-started within a
    /// step, and nothing of one step's warm starts survives into the next (a resumed run starts
    /// with none, so a run that kept them would not resume bit for bit).
    #[test]
    fn warm_starts_last_one_step() {
        let shape = Superellipse::new([0.5, 0.3], [2.0, 2.0]).unwrap();
        let mut bodies = vec![
            Body::at_rest(shape, &Pose::new(Vec2::new(-0.45, 0.3), 0.0).unwrap()),
            Body::at_rest(shape, &Pose::new(Vec2::new(0.45, 0.3), 0.2).unwrap()),
        ];
        let walls = Walls {
            left: -5.0,
            right: 5.0,
            floor: 0.0,
        };
        let settings = Settings::default();
        let mut broad = Any::new(Kind::Grid);
        let mut work = Workspace::default();
        step(&mut bodies, &walls, &settings, &mut broad, &mut work, 0);
        assert!(
            !work.warm.is_empty(),
            "the overlapping pair kept no warm start"
        );
        let stale = (usize::MAX, usize::MAX);
        let kept = *work.warm.values().next().unwrap();
        work.warm.insert(stale, kept);
        step(&mut bodies, &walls, &settings, &mut broad, &mut work, 0);
        assert!(
            !work.warm.contains_key(&stale),
            "a warm start outlived its step"
        );
    }
}

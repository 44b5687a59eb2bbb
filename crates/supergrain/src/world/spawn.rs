//! The spawn queue: the grains still to appear, and the rule by which they appear (paper III:
//! grains appear at the top over time).
//!
//! A grain is drawn only when its due step has come. Until then it is a count in its group: the
//! queue's memory, and its part of a dump, are the groups' ranges and counts, the index of the
//! next grain and the seed, whatever the number still to come. Grain `k` of the queue draws
//! from its own stream of the seeded generator (stream `k`), so which grains came before it
//! changes none of its numbers, and a dump needs no generator position. The only grains held one
//! by one are those drawn and waiting for their place.
//!
//! Grain `k` is due at step `k / spawn_count * spawn_interval`, and due grains are offered a
//! place in queue order, by one of two rules ([`SpawnRule`]):
//! - `queue` (the paper's model's default): a grain is offered its drawn `x` at the top; one
//!   whose place is taken waits, and the grains due after it whose places are free appear
//!   meanwhile. Large grains are blocked more often than small ones, so a mixture arrives
//!   sorted, small first.
//! - `fair` (the soft model's default), after LAMMPS's `fix pour`: grains appear strictly in
//!   queue order. The next grain is offered its drawn `x` at the top, then other places drawn
//!   at random in the insertion band under the top ([`BAND_IN_RADII`] of its bounding radii
//!   deep), up to [`TRIES_PER_STEP`] a step, as if it had fallen there from the top; until one
//!   is free, the grains after it wait undrawn. Each group's share of the grains that appear
//!   is then its share of the queue at every moment. The places tried come from the grain's
//!   own stream `k` too, far past its draw, so a dump needs only the count of places tried.

use std::collections::VecDeque;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::scene::{Group, Range, Scene};
use crate::body::Walls;
use crate::geometry::Vec2;
use crate::shape::{Pose, Superellipse};

/// How due grains appear (see the module's doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpawnRule {
    /// A blocked grain waits and the grains after it may appear first (the paper's model's
    /// default: its presets' runs stay what they were).
    #[default]
    Queue,
    /// Grains appear in queue order; a blocked one is offered other places in the insertion
    /// band (the soft model's default).
    Fair,
}

/// The depth of the fair rule's band under the top, in the grain's bounding radii: two
/// diameters, room for a few rows of places besides the top's.
pub const BAND_IN_RADII: f64 = 4.0;

/// The most places the fair rule offers the next grain in one step. A place costs one pass over
/// the grains' boxes; with a share `f` of the band's places taken, eight find a free one within
/// the step with probability `1 - f^8` (96% at two thirds taken).
pub const TRIES_PER_STEP: u64 = 8;

/// The box's walls, or where grains appear across when a source is narrower (`between`).
pub fn narrowed(walls: &Walls, between: Option<[f64; 2]>) -> Walls {
    match between {
        Some([left, right]) => Walls {
            left,
            right,
            floor: walls.floor,
        },
        None => *walls,
    }
}

/// Where the fair rule stands: the next grain to appear and the places it has been offered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fair {
    /// The scene's seed (kept when the generator is done with it).
    pub seed: u64,
    /// The queue index of the next grain to appear.
    pub head: u64,
    /// The places it has been offered so far (0: none yet).
    pub tries: u64,
}

impl Fair {
    /// Where grain `head` (`p`) is offered its place number `tries`: its drawn `x` at the top
    /// first, then uniform in the band between the walls, its box inside them and above the
    /// floor. Drawn from stream `head` of the seeded generator at word `tries << 32`, past the
    /// few words its draw took.
    fn place(&self, p: &Pending, walls: &Walls, top: f64) -> Vec2 {
        if self.tries == 0 {
            return Vec2::new(p.x, top);
        }
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        rng.set_stream(self.head);
        rng.set_word_pos(u128::from(self.tries) << 32);
        let bb = p.shape.bounding_box(&Pose::from_parts(Vec2::ZERO, p.angle));
        let (half_width, half_height) = (0.5 * bb.width(), 0.5 * bb.height());
        let (lo, hi) = (walls.left + half_width, walls.right - half_width);
        let x = if lo < hi {
            rng.random_range(lo..=hi)
        } else {
            0.5 * (walls.left + walls.right)
        };
        let depth = BAND_IN_RADII * p.shape.bounding_radius();
        let low = (top - depth).max(walls.floor + half_height);
        let y = if low < top {
            rng.random_range(low..=top)
        } else {
            top
        };
        Vec2::new(x, y)
    }
}

/// A grain drawn, waiting to appear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pending {
    pub shape: Superellipse,
    pub x: f64,
    pub angle: f64,
    /// The first step at which it may appear.
    pub due: u64,
    /// Its scene group (see [`crate::body::Body::group`]).
    pub group: u32,
}

/// The grains not drawn yet: the scene's groups, each with the number of its grains still to
/// draw, and where the draws stand. Never empty (a [`Queue`] drops it when its last grain is
/// drawn).
#[derive(Clone, Debug, PartialEq)]
pub struct Generator {
    seed: u64,
    /// The queue index of the next grain to draw.
    next: u64,
    spawn_interval: u32,
    spawn_count: u32,
    /// Where x is drawn (between the walls).
    walls: Walls,
    /// The scene's groups, in its order, each `count` being the grains still to draw.
    groups: Vec<Group>,
    /// The sum of the groups' counts.
    remaining: u64,
}

impl Generator {
    /// The grains of `groups` still to draw (each group's `count`), the next one being grain
    /// `next` of the queue; `None` if there are none. The ranges must have been checked (as
    /// [`Scene::validate`] and [`crate::io::Dump::to_world`] do): every corner makes a valid
    /// shape, every range is finite with `lo <= hi`.
    pub fn new(
        seed: u64,
        next: u64,
        spawn_interval: u32,
        spawn_count: u32,
        walls: Walls,
        groups: Vec<Group>,
    ) -> Option<Generator> {
        let remaining = groups.iter().map(|g| u64::from(g.count)).sum();
        (remaining > 0).then_some(Generator {
            seed,
            next,
            spawn_interval,
            spawn_count,
            walls,
            groups,
            remaining,
        })
    }

    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The queue index of the next grain to draw, counted from 0 over the whole run.
    pub fn next(&self) -> u64 {
        self.next
    }

    pub fn spawn_interval(&self) -> u32 {
        self.spawn_interval
    }

    pub fn spawn_count(&self) -> u32 {
        self.spawn_count
    }

    /// The scene's groups, each `count` being the grains still to draw.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// How many grains are still to draw.
    pub fn remaining(&self) -> u64 {
        self.remaining
    }

    /// The step at which the next grain is due.
    pub fn next_due(&self) -> u64 {
        (self.next / u64::from(self.spawn_count.max(1)))
            .saturating_mul(u64::from(self.spawn_interval))
    }

    /// The groups that still have grains to draw.
    fn live(&self) -> impl Iterator<Item = &Group> {
        self.groups.iter().filter(|g| g.count > 0)
    }

    /// Draws the next grain. Its group comes first, with probability its share of the grains
    /// still to draw: the groups then come in the order of a uniform shuffle of all their grains.
    /// Then its shape, angle and x, from the ranges.
    fn draw(&mut self) -> Pending {
        let due = self.next_due();
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        rng.set_stream(self.next);
        let mut r = rng.random_range(0..self.remaining);
        let mut index = 0;
        for (i, g) in self.groups.iter().enumerate() {
            let count = u64::from(g.count);
            if r < count {
                index = i;
                break;
            }
            r -= count;
        }
        let g = &mut self.groups[index];
        g.count -= 1;
        self.remaining -= 1;
        self.next += 1;
        let pick = |rng: &mut ChaCha8Rng, r: Range| {
            if r.lo < r.hi {
                rng.random_range(r.lo..=r.hi)
            } else {
                r.lo
            }
        };
        let sx = pick(&mut rng, g.semi_axes[0]);
        let sy = if g.circles {
            sx
        } else {
            pick(&mut rng, g.semi_axes[1])
        };
        let ex = pick(&mut rng, g.exponents[0]);
        let ey = if g.same_exponents {
            ex
        } else {
            pick(&mut rng, g.exponents[1])
        };
        let angle = pick(&mut rng, g.angle);
        let shape = Superellipse::new([sx, sy], [ex, ey]).expect("the ranges are checked");
        // x uniform between the walls, the grain's box kept inside them.
        let w = self.walls;
        let half = 0.5
            * shape
                .bounding_box(&Pose::from_parts(Vec2::ZERO, angle))
                .width();
        let (lo, hi) = (w.left + half, w.right - half);
        let x = if lo < hi {
            rng.random_range(lo..=hi)
        } else {
            0.5 * (w.left + w.right)
        };
        Pending {
            shape,
            x,
            angle,
            due,
            group: u32::try_from(index).unwrap_or(u32::MAX),
        }
    }
}

/// The grains still to appear, in queue order: those drawn and waiting, then the generator's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Queue {
    /// Drawn and not yet appeared, in queue order: grains whose place was taken when they were
    /// due (or a dump's list from before the generator, due steps and all). Under the fair rule,
    /// at most the next grain to appear.
    waiting: VecDeque<Pending>,
    generator: Option<Generator>,
    /// The fair rule's state; `None`: the queue rule.
    fair: Option<Fair>,
    /// Where grains appear across (`[spawn] between`, a source narrower than the box: over a
    /// drum, a tumbler, a hopper's mouth); `None`: between the walls.
    between: Option<[f64; 2]>,
}

/// What [`Queue::spawn`] changed, for [`Queue::undo`].
#[derive(Debug, Default)]
pub(crate) struct Taken {
    /// The waiting grains that appeared, each with its index when taken, in the order taken.
    waiting: Vec<(usize, Pending)>,
    /// How many grains were drawn and left waiting (at the back).
    left_waiting: usize,
    /// The generator before the first draw, when one was drawn.
    generator: Option<Option<Generator>>,
    /// The fair rule's state before.
    fair: Option<Fair>,
}

impl Queue {
    /// Every grain of a scene, none drawn yet, to appear by the scene's rule.
    pub fn new(scene: &Scene) -> Queue {
        Queue {
            waiting: VecDeque::new(),
            generator: Generator::new(
                scene.seed,
                0,
                scene.spawn_interval,
                scene.spawn_count,
                narrowed(&scene.walls, scene.spawn_between),
                scene.groups.clone(),
            ),
            between: scene.spawn_between,
            fair: (scene.spawn_rule == SpawnRule::Fair).then_some(Fair {
                seed: scene.seed,
                head: 0,
                tries: 0,
            }),
        }
    }

    /// A queue of grains already drawn (in queue order) and those still to draw (a restart),
    /// with the fair rule's state, or `None` for the queue rule.
    pub fn from_parts(
        waiting: VecDeque<Pending>,
        generator: Option<Generator>,
        fair: Option<Fair>,
        between: Option<[f64; 2]>,
    ) -> Queue {
        Queue {
            waiting,
            generator,
            fair,
            between,
        }
    }

    /// Where grains appear across, when narrower than the box (`[spawn] between`).
    pub fn between(&self) -> Option<[f64; 2]> {
        self.between
    }

    /// The rule by which the grains appear.
    pub fn rule(&self) -> SpawnRule {
        if self.fair.is_some() {
            SpawnRule::Fair
        } else {
            SpawnRule::Queue
        }
    }

    /// The fair rule's state, under that rule.
    pub fn fair(&self) -> Option<&Fair> {
        self.fair.as_ref()
    }

    /// The grains drawn and waiting, in queue order.
    pub fn waiting(&self) -> &VecDeque<Pending> {
        &self.waiting
    }

    /// The grains still to draw, if any.
    pub fn generator(&self) -> Option<&Generator> {
        self.generator.as_ref()
    }

    /// How many grains are still to appear.
    pub fn len(&self) -> u64 {
        self.waiting.len() as u64 + self.generator.as_ref().map_or(0, Generator::remaining)
    }

    pub fn is_empty(&self) -> bool {
        self.waiting.is_empty() && self.generator.is_none()
    }

    /// Every grain still to appear, in queue order, each drawn as it comes (the queue is left
    /// as it is): time in the number of grains, memory in the number of groups.
    pub fn iter(&self) -> impl Iterator<Item = Pending> + '_ {
        let mut generator = self.generator.clone();
        self.waiting
            .iter()
            .copied()
            .chain(std::iter::from_fn(move || {
                let g = generator.as_mut()?;
                let p = g.draw();
                if g.remaining == 0 {
                    generator = None;
                }
                Some(p)
            }))
    }

    /// The extreme shapes of the groups still drawn from (their ranges' corners bound every
    /// draw, see [`Group::extreme_shapes`]), and the waiting grains' shapes.
    fn shapes(&self) -> impl Iterator<Item = Superellipse> + '_ {
        let extremes = self
            .generator
            .iter()
            .flat_map(Generator::live)
            .flat_map(|g| {
                let (least, largest) = g.extreme_shapes().expect("the ranges are checked");
                [least, largest]
            });
        self.waiting.iter().map(|p| p.shape).chain(extremes)
    }

    /// The largest bounding radius a grain still to appear can have (0 for none).
    pub fn largest_bounding_radius(&self) -> f64 {
        self.shapes()
            .map(|s| s.bounding_radius())
            .fold(0.0, f64::max)
    }

    /// The smallest bounding radius a grain still to appear can have (infinite for none).
    pub fn smallest_bounding_radius(&self) -> f64 {
        self.shapes()
            .map(|s| s.bounding_radius())
            .fold(f64::INFINITY, f64::min)
    }

    /// The smallest semi-axis a grain still to appear can have (infinite for none).
    pub fn smallest_semi_axis(&self) -> f64 {
        self.shapes()
            .map(|s| s.min_semi_axis())
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether every grain still to appear is a circle.
    pub fn all_circles(&self) -> bool {
        let circles = |g: &Group| g.circles && g.exponents == [Range::fixed(2.0); 2];
        self.waiting.iter().all(|p| p.shape.is_circle())
            && self.generator.iter().flat_map(Generator::live).all(circles)
    }

    /// Offers the grains due at `step` a place in the box `walls` under `top`, in queue order:
    /// `place` makes a grain appear with its centre at the point given and says so, or says that
    /// place is taken. By the queue rule each grain is offered its drawn `x` at `top`: the
    /// waiting grains come first, up to the first not yet due; then the grains due are drawn,
    /// and those that did not appear wait. By the fair rule see [`Queue::spawn_fair`]. `taken`
    /// records the changes for [`Queue::undo`].
    /// Queues `p` after the grains drawn and waiting, before those still to draw: a grain put
    /// back by a recycling sink ([`super::Sink`]).
    pub(crate) fn push_back(&mut self, p: Pending) {
        self.waiting.push_back(p);
    }

    pub(crate) fn spawn(
        &mut self,
        step: u64,
        walls: &Walls,
        top: f64,
        mut place: impl FnMut(&Pending, Vec2) -> bool,
        taken: &mut Taken,
    ) {
        taken.waiting.clear();
        taken.left_waiting = 0;
        taken.generator = None;
        taken.fair = self.fair;
        let walls = &narrowed(walls, self.between);
        if self.fair.is_some() {
            return self.spawn_fair(step, walls, top, place, taken);
        }
        let mut place = |p: &Pending| place(p, Vec2::new(p.x, top));
        let mut k = 0;
        while k < self.waiting.len() {
            let p = self.waiting[k];
            if p.due > step {
                return;
            }
            if place(&p) {
                self.waiting.remove(k);
                taken.waiting.push((k, p));
            } else {
                k += 1;
            }
        }
        while let Some(g) = self.generator.as_mut()
            && g.next_due() <= step
        {
            if taken.generator.is_none() {
                taken.generator = Some(Some(g.clone()));
            }
            let p = g.draw();
            if g.remaining == 0 {
                self.generator = None;
            }
            if !place(&p) {
                self.waiting.push_back(p);
                taken.left_waiting += 1;
            }
        }
    }

    /// The fair rule: the next grain, once due, is offered its places one after another (see
    /// [`Fair::place`]), at most [`TRIES_PER_STEP`] this step; if none is free it waits, and so
    /// do all the grains after it, undrawn. Once it appears, the next one is drawn and offered
    /// its places in turn.
    fn spawn_fair(
        &mut self,
        step: u64,
        walls: &Walls,
        top: f64,
        mut place: impl FnMut(&Pending, Vec2) -> bool,
        taken: &mut Taken,
    ) {
        let Some(mut fair) = self.fair else { return };
        loop {
            let (p, drawn) = match self.waiting.front() {
                Some(&p) if p.due <= step => (p, false),
                Some(_) => break,
                None => match self.generator.as_mut() {
                    Some(g) if g.next_due() <= step => {
                        if taken.generator.is_none() {
                            taken.generator = Some(Some(g.clone()));
                        }
                        let p = g.draw();
                        if g.remaining == 0 {
                            self.generator = None;
                        }
                        (p, true)
                    }
                    _ => break,
                },
            };
            let mut appeared = false;
            for _ in 0..TRIES_PER_STEP {
                appeared = place(&p, fair.place(&p, walls, top));
                fair.tries = fair.tries.saturating_add(1);
                if appeared {
                    break;
                }
            }
            if !appeared {
                if drawn {
                    self.waiting.push_back(p);
                    taken.left_waiting += 1;
                }
                break;
            }
            if !drawn {
                self.waiting.pop_front();
                taken.waiting.push((0, p));
            }
            fair.head += 1;
            fair.tries = 0;
        }
        self.fair = Some(fair);
    }

    /// Puts the queue back as it was before the [`Queue::spawn`] that recorded `taken`.
    pub(crate) fn undo(&mut self, taken: &Taken) {
        for _ in 0..taken.left_waiting {
            self.waiting.pop_back();
        }
        for &(k, p) in taken.waiting.iter().rev() {
            self.waiting.insert(k, p);
        }
        if let Some(g) = &taken.generator {
            self.generator.clone_from(g);
        }
        self.fair = taken.fair;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Spawns the circles preset by the fair rule, every grain due at step 0, a place in every
    /// `free_every` offered being free, round after round; undoes each round and checks the
    /// queue is as it was, then redoes it. The first place offered a grain is its drawn `x` at
    /// the top, the others in the band between the walls; grains appear in queue order, and
    /// a blocked one waits alone.
    #[test]
    fn the_fair_rule_offers_places_in_order_and_a_spawn_undoes_exactly() {
        let mut scene = Scene::preset("circles").expect("a preset");
        scene.spawn_rule = SpawnRule::Fair;
        scene.spawn_interval = 0;
        let mut queue = Queue::new(&scene);
        let dealt: Vec<Pending> = queue.iter().collect();
        let (walls, top) = (scene.walls, scene.top);
        let (mut appeared, mut offered, mut last) = (Vec::new(), 0u64, None);
        let mut taken = Taken::default();
        for free_every in [1, 3, 20, 2, 9, 1] {
            let before = queue.clone();
            let place = |p: &Pending, at: Vec2| {
                offered += 1;
                if last != Some(*p) {
                    assert_eq!(at, Vec2::new(p.x, top), "a grain's first place");
                    last = Some(*p);
                }
                let r = p.shape.bounding_radius();
                assert!(walls.left <= at.x - r && at.x + r <= walls.right);
                assert!(top - BAND_IN_RADII * r <= at.y && at.y <= top);
                let free = offered % free_every == 0;
                if free {
                    appeared.push(*p);
                }
                free
            };
            queue.spawn(0, &walls, top, place, &mut taken);
            let after = queue.clone();
            queue.undo(&taken);
            assert_eq!(queue, before, "undone, free every {free_every}");
            queue = after;
            assert!(queue.waiting().len() <= 1);
        }
        assert!(appeared.len() > 5);
        assert_eq!(appeared[..], dealt[..appeared.len()], "queue order");
        let fair = queue.fair().expect("the fair rule");
        assert_eq!(fair.head, appeared.len() as u64);
    }
}

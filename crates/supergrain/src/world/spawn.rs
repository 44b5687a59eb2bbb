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
//! The rule (another may replace it, behind [`Queue::spawn`]): grain `k` is due at step
//! `k / spawn_count * spawn_interval`; due grains are offered a place in queue order; one whose
//! place is taken waits, and the grains due after it whose places are free appear meanwhile.

use std::collections::VecDeque;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::scene::{Group, Range, Scene};
use crate::geometry::Vec2;
use crate::shape::{Pose, Superellipse};
use crate::solver::Walls;

/// A grain drawn, waiting to appear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pending {
    pub shape: Superellipse,
    pub x: f64,
    pub angle: f64,
    /// The first step at which it may appear.
    pub due: u64,
    /// Its scene group (see [`crate::solver::Body::group`]).
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
    /// due (or a dump's list from before the generator, due steps and all).
    waiting: VecDeque<Pending>,
    generator: Option<Generator>,
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
}

impl Queue {
    /// Every grain of a scene, none drawn yet.
    pub fn new(scene: &Scene) -> Queue {
        Queue {
            waiting: VecDeque::new(),
            generator: Generator::new(
                scene.seed,
                0,
                scene.spawn_interval,
                scene.spawn_count,
                scene.walls,
                scene.groups.clone(),
            ),
        }
    }

    /// A queue of grains already drawn (in queue order) and those still to draw (a restart).
    pub fn from_parts(waiting: VecDeque<Pending>, generator: Option<Generator>) -> Queue {
        Queue { waiting, generator }
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

    /// Offers the grains due at `step` their place, in queue order: `place` makes a grain
    /// appear and says so, or says its place is taken. The waiting grains come first, up to the
    /// first not yet due; then the grains due are drawn, and those that did not appear wait.
    /// `taken` records the changes for [`Queue::undo`].
    pub(crate) fn spawn(
        &mut self,
        step: u64,
        mut place: impl FnMut(&Pending) -> bool,
        taken: &mut Taken,
    ) {
        taken.waiting.clear();
        taken.left_waiting = 0;
        taken.generator = None;
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
    }
}

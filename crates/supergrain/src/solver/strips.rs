//! All cores, with results that do not depend on how many there are.
//!
//! The paper's projection is Gauss-Seidel: grain by grain, each seeing the moves of the ones
//! before it. Computing contacts in parallel and applying them in order would need the poses
//! they were computed from, which the earlier grains keep changing. So we parallelise the order
//! instead: a wide box is cut into vertical strips at least [`crate::settings::Settings::strip_width`]
//! wide (by default eight times the largest grain's bounding radius, set by the scene), each
//! grain belonging, for the whole step, to the strip of its centre at the step's start. Strip
//! `k`'s grains are projected one after another, in index order, in a world made of strips
//! `k - 1`, `k` and `k + 1` only; they may push grains of the two neighbouring strips, never
//! further. Strips three apart share no grain, so the strips `k = p mod 3` are done at once for
//! `p = 0, 1, 2` in turn, each on whichever thread is free: every strip sees exactly the same
//! grains whatever the number of threads, and the step's result is the same bit for bit on one
//! thread or many (tested). It is still Gauss-Seidel, in another order than index order, and
//! the same order on every machine.
//!
//! A grain whose box reaches past the neighbouring strips (a strip is four grains wide, so only
//! a grain flung sideways faster than that in one step) does not see what is there until the
//! next step; the step's end (sleep) and the next step's strips see everything again.
//!
//! Narrow boxes (fewer than [`MIN_STRIPS`] strips) keep the paper's order: with one or two
//! strips per phase there is nothing to share between two cores.

use rayon::prelude::*;

use super::{
    CLOSING_SWEEPS, Context, StepStats, Workspace, rebuild_boxes, settle, shock_grain, shock_order,
    sweep_grain,
};
use crate::body::{Body, Walls};
use crate::broad_phase::Any;
use crate::settings::Settings;

/// Fewer strips than this and a box keeps the paper's order: two strips per phase at least.
pub const MIN_STRIPS: usize = 6;

/// The default strip width, in bounding radii of the largest grain: four grains across, so a
/// strip's grains never reach past its neighbours.
pub const WIDTH_IN_RADII: f64 = 8.0;

/// A step's grains sorted into strips.
#[derive(Debug)]
pub struct Strips {
    /// Each strip's grains, in increasing index order.
    members: Vec<Vec<usize>>,
}

/// What a strip's turn does to each of its own grains.
#[derive(Clone, Copy)]
enum Turn<'a> {
    /// Verlet and projection passes ([`settle`]).
    Settle,
    /// One closing-sweep pass ([`sweep_grain`]).
    Sweep,
    /// The shock sweep, in this global order's ranks ([`shock_grain`]).
    Shock(&'a [usize]),
}

/// One strip's world for one phase: the grains of strips `k - 1 ..= k + 1`, copied out.
struct Local {
    /// Global index of each local grain, increasing (so that local candidate lists come in the
    /// same order as global ones).
    global: Vec<usize>,
    bodies: Vec<Body>,
    /// Local indices of strip `k`'s own grains, in the order they take their turn.
    own: Vec<usize>,
}

impl Strips {
    /// The strips of step number `step`, or `None` for the paper's order (strips off, or too
    /// few). On odd steps the cuts move by half a strip (one strip more, the two end ones half
    /// wide): with fixed cuts, two grains either side of one are projected in the same order,
    /// phase after phase, step after step, and some such pairs among sleepers settle into a
    /// cycle that never ends (the 100,000-grain pour: 700 grains in two dozen places, for 40,000
    /// steps; grain by grain, the first one traced sat 0.23 from a cut). Every interior strip
    /// keeps its width, so the strips' guarantee holds, and the shift depends only on the step's
    /// number: runs stay the same on any number of threads, and resumed runs the same.
    pub fn new(bodies: &[Body], walls: &Walls, settings: &Settings, step: u64) -> Option<Strips> {
        let width = walls.right - walls.left;
        if !(settings.strip_width > 0.0 && width.is_finite()) {
            return None;
        }
        // Capped so that a huge box cannot ask for more strips than it could ever hold grains.
        let count = (width / settings.strip_width)
            .floor()
            .min((bodies.len().max(1) * 3) as f64);
        if count < MIN_STRIPS as f64 {
            return None;
        }
        let strip = width / count;
        let (count, shift) = if step % 2 == 1 {
            (count as usize + 1, 0.5)
        } else {
            (count as usize, 0.0)
        };
        let mut members = vec![Vec::new(); count];
        for (i, b) in bodies.iter().enumerate() {
            let k = ((b.center.x - walls.left) / strip + shift).floor();
            // Outside the box (or NaN): the nearest strip.
            let k = if k >= 0.0 {
                (k as usize).min(count - 1)
            } else {
                0
            };
            members[k].push(i);
        }
        Some(Strips { members })
    }

    /// How many strips.
    pub fn count(&self) -> usize {
        self.members.len()
    }

    /// Strip `k`'s grains, in increasing index order.
    pub fn members(&self, k: usize) -> &[usize] {
        &self.members[k]
    }

    /// The step's projection, strip by strip (the caller handles sleep).
    pub(super) fn step(&self, bodies: &mut [Body], ctx: &Context, stats: &mut StepStats) {
        self.phases(bodies, ctx, stats, Turn::Settle);
        if ctx.settings.shock_propagation {
            let (mut order, mut rank) = (Vec::new(), Vec::new());
            shock_order(bodies, &mut order, &mut rank);
            self.phases(bodies, ctx, stats, Turn::Shock(&rank));
        } else {
            for _ in 0..CLOSING_SWEEPS {
                if self.phases(bodies, ctx, stats, Turn::Sweep) == 0 {
                    break;
                }
            }
        }
    }

    /// Every strip's turn, in three phases of strips three apart, each phase's strips in
    /// parallel; the contacts corrected (closing sweeps only).
    fn phases(
        &self,
        bodies: &mut [Body],
        ctx: &Context,
        stats: &mut StepStats,
        turn: Turn,
    ) -> usize {
        let mut hit = 0;
        for phase in 0..3 {
            let locals: Vec<Local> = (phase..self.count())
                .step_by(3)
                // Every turn starts by passing over a sleeping grain, and no other strip of the
                // phase touches this one's grains: a strip whose own grains all sleep would do
                // nothing, so it is not copied out (most of a settling heap's strips).
                .filter(|&k| {
                    self.members[k]
                        .iter()
                        .any(|&g| !bodies[g].asleep(ctx.settings))
                })
                .map(|k| self.local(k, bodies, turn))
                .collect();
            debug_assert!(
                {
                    let mut seen = vec![false; bodies.len()];
                    locals
                        .iter()
                        .flat_map(|l| &l.global)
                        .all(|&g| !std::mem::replace(&mut seen[g], true))
                },
                "strips of one phase share a grain"
            );
            let done: Vec<(Local, StepStats, usize)> = locals
                .into_par_iter()
                .map(|mut local| {
                    let (s, h) = local.run(ctx, turn);
                    (local, s, h)
                })
                .collect();
            for (local, s, h) in done {
                for (&g, b) in local.global.iter().zip(&local.bodies) {
                    bodies[g] = *b;
                }
                stats.contacts += s.contacts;
                stats.tests += s.tests;
                hit += h;
            }
        }
        hit
    }

    /// Strip `k`'s world: its grains and its neighbours'.
    fn local(&self, k: usize, bodies: &[Body], turn: Turn) -> Local {
        let lo = k.saturating_sub(1);
        let hi = (k + 1).min(self.count() - 1);
        let mut global: Vec<usize> = self.members[lo..=hi].concat();
        global.sort_unstable();
        let local_bodies = global.iter().map(|&g| bodies[g]).collect();
        let mut own: Vec<usize> = (0..global.len())
            .filter(|&l| self.members[k].binary_search(&global[l]).is_ok())
            .collect();
        if let Turn::Shock(rank) = turn {
            own.sort_unstable_by_key(|&l| rank[global[l]]);
        }
        Local {
            global,
            bodies: local_bodies,
            own,
        }
    }
}

impl Local {
    /// The strip's own grains take their turn, in order; what they did, and the contacts
    /// corrected by a closing sweep.
    fn run(&mut self, ctx: &Context, turn: Turn) -> (StepStats, usize) {
        let mut stats = StepStats::default();
        let mut work = Workspace::default();
        let mut broad = Any::new(ctx.settings.broad_phase);
        rebuild_boxes(&self.bodies, &mut broad, &mut work);
        let rank: Vec<usize> = match turn {
            Turn::Shock(rank) => self.global.iter().map(|&g| rank[g]).collect(),
            _ => Vec::new(),
        };
        let mut hit = 0;
        for &i in &self.own {
            if ctx.stopped() {
                break;
            }
            match turn {
                Turn::Settle => settle(i, &mut self.bodies, ctx, &mut broad, &mut work, &mut stats),
                Turn::Sweep => {
                    hit += sweep_grain(i, &mut self.bodies, ctx, &mut broad, &mut work, &mut stats)
                }
                Turn::Shock(_) => shock_grain(
                    i,
                    &mut self.bodies,
                    ctx,
                    &mut broad,
                    &mut work,
                    &mut stats,
                    &rank,
                ),
            }
        }
        (stats, hit)
    }
}

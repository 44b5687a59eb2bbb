//! The angle of repose of disks poured from a narrow source onto a wide floor: the pour, written
//! once for any engine ([`Pile`], [`pour`]), and the measure of the heap's two flanks
//! ([`angle`]).
//!
//! **The pour.** Disks of radii drawn uniformly from `radius` (a spread of 10% either way keeps
//! them from stacking as a crystal, whose facets would set the angle), one every `interval`
//! steps, each at rest at an `x` drawn uniformly across the source (`source` wide, over `x = 0`),
//! `gap` above the highest disk top within its own width (the apex, or the grain before it
//! still falling): a funnel kept just above the apex, so that grains land gently and the heap
//! grows by avalanches down its flanks. (Dropped from half a diameter instead, the landing
//! grains splash the apex flat, and in Box2D the three seeds' angles at `mu = 0.5` spread over
//! 19 degrees, against 6.) Then steps until rest: every grain in and none faster than
//! `rest_speed` for `rest_steps` steps in a row, or `max_steps`.
//!
//! **The floor** is rough ([`floor`]): a grain meets it with friction and rolling resistance 1,
//! so it neither slides nor rolls once landed, as on a floor of glued grains. On a floor of the
//! grains' own material the heap's base spreads: 300 disks dropped from half a diameter left,
//! at `mu = 0.1`, a layer one or two grains deep across the whole floor in both engines (1
//! degree), and at `mu = 0.3` a mound of 6-8 degrees.
//!
//! **The measure.** After rest, the heap's surface: the box cut into bins one mean diameter
//! wide, and in each the disk whose top is highest (its centre's `x`, its top's height above
//! the floor). A flank is the surface on one side of the source whose height lies in the middle
//! 60% of the highest point's (from 0.2 to 0.8 of it: neither the rounded top nor the toe);
//! a least-squares line through it, and the flank's angle `atan |slope|`. The heap's angle is
//! the mean of its two flanks'.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::Disk;
use crate::body::{Body, Material, Walls};
use crate::geometry::Vec2;
use crate::settings::Settings;
use crate::shape::{Pose, Superellipse};
use crate::world::{Queue, Rest, RestCounter, World};

/// The pour's parameters (see the module docs). The floor is at `y = 0`, the source over
/// `x = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pour {
    pub grains: usize,
    /// Radii drawn uniformly from `[radius[0], radius[1]]`.
    pub radius: [f64; 2],
    /// Width of the source: each grain's `x` is drawn uniformly from `[-source / 2, source / 2]`.
    pub source: f64,
    /// Drop above the highest disk under the new one.
    pub gap: f64,
    /// Steps between grains.
    pub interval: u64,
    /// The floor reaches `half_width` either side of the source, where the walls stand.
    pub half_width: f64,
    pub seed: u64,
    pub rest_speed: f64,
    pub rest_steps: u32,
    pub max_steps: u64,
    /// Gravity (downwards) and time step.
    pub gravity: f64,
    pub time_step: f64,
}

impl Default for Pour {
    /// 600 disks of radius 0.225-0.275 (a mean diameter of 0.5, as Box2D's bodies are sized:
    /// tenths of a metre to metres), a source two diameters wide, dropped from a tenth of a
    /// diameter above the heap, one every 8 steps of 0.01 s; a floor 40 either side (the heaps
    /// reach about 15). Rest as `run --until-rest`: none faster than 0.05 for 100 steps.
    fn default() -> Self {
        Pour {
            grains: 600,
            radius: [0.225, 0.275],
            source: 1.0,
            gap: 0.05,
            interval: 8,
            half_width: 40.0,
            seed: 1,
            rest_speed: 0.05,
            rest_steps: 100,
            max_steps: 20_000,
            gravity: 9.8,
            time_step: 0.01,
        }
    }
}

impl Pour {
    /// Each grain's radius and `x`, in order, from the seed.
    pub fn draws(&self) -> Vec<(f64, f64)> {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let [lo, hi] = self.radius;
        let half = 0.5 * self.source;
        (0..self.grains)
            .map(|_| {
                let r = if hi > lo {
                    rng.random_range(lo..=hi)
                } else {
                    lo
                };
                let x = if half > 0.0 {
                    rng.random_range(-half..=half)
                } else {
                    0.0
                };
                (r, x)
            })
            .collect()
    }

    /// The mean diameter of the grains drawn.
    pub fn mean_diameter(&self) -> f64 {
        self.radius[0] + self.radius[1]
    }

    /// The angle of repose of the heap this pour left (see [`angle`]): flanks either side of
    /// the source, bins one mean diameter wide.
    pub fn angle(&self, disks: &[Disk]) -> Option<Repose> {
        angle(disks, self.walls().floor, 0.0, self.mean_diameter())
    }

    /// The box: walls at `-half_width` and `half_width`, the floor at 0.
    pub fn walls(&self) -> Walls {
        Walls {
            left: -self.half_width,
            right: self.half_width,
            floor: 0.0,
        }
    }
}

/// An engine's world of disks, as the pour drives it.
pub trait Pile {
    type Error;
    /// A disk of `radius` at rest at `(x, y)`, of the pour's material.
    fn add(&mut self, x: f64, y: f64, radius: f64) -> Result<(), Self::Error>;
    fn step(&mut self) -> Result<(), Self::Error>;
    /// The disks, in the order added.
    fn disks(&mut self, out: &mut Vec<Disk>) -> Result<(), Self::Error>;
    /// The largest linear speed of a disk.
    fn fastest(&mut self) -> Result<f64, Self::Error>;
}

/// A pour, done.
#[derive(Clone, Debug, PartialEq)]
pub struct Poured {
    pub disks: Vec<Disk>,
    pub steps: u64,
    pub at_rest: bool,
    /// Wall time of the whole pour.
    pub seconds: f64,
}

/// Pours `pour`'s grains into `pile` (its box and material already made) until rest.
pub fn pour<P: Pile>(pile: &mut P, pour: &Pour) -> Result<Poured, P::Error> {
    let start = std::time::Instant::now();
    let draws = pour.draws();
    let mut disks = Vec::with_capacity(draws.len());
    let mut next = 0;
    let mut steps = 0;
    let rest = Rest {
        speed: pour.rest_speed,
        steps: pour.rest_steps,
    };
    let mut calm = RestCounter::default();
    while steps < pour.max_steps {
        if next < draws.len() && steps % pour.interval.max(1) == 0 {
            let (r, x) = draws[next];
            pile.disks(&mut disks)?;
            let under = disks
                .iter()
                .filter(|d| (d.center.x - x).abs() < d.radius + r)
                .map(Disk::top)
                .fold(0.0, f64::max);
            pile.add(x, under + pour.gap + r, r)?;
            next += 1;
        }
        pile.step()?;
        steps += 1;
        // (The fastest grain asked for only once all are in, as each engine's query costs.)
        let all_in = next == draws.len();
        let fastest = if all_in {
            pile.fastest()?
        } else {
            f64::INFINITY
        };
        if calm.update(&rest, all_in, fastest) {
            break;
        }
    }
    pile.disks(&mut disks)?;
    Ok(Poured {
        disks,
        steps,
        at_rest: calm.at_rest(&rest),
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// One flank's straight line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flank {
    /// `atan |slope|`, in degrees.
    pub degrees: f64,
    /// Height over `x` (positive on the left flank, negative on the right).
    pub slope: f64,
    /// Surface points fitted.
    pub points: usize,
}

/// A heap's two flanks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Repose {
    pub left: Flank,
    pub right: Flank,
    /// The apex: the highest surface point.
    pub apex: Vec2,
}

impl Repose {
    /// The mean of the two flanks' angles, in degrees.
    pub fn degrees(&self) -> f64 {
        0.5 * (self.left.degrees + self.right.degrees)
    }
}

/// The surface of a heap on a floor at `floor`: in each bin `bin` wide (from the leftmost disk),
/// the disk whose top is highest, as `(x of its centre, height of its top above the floor)`,
/// left to right.
pub fn surface(disks: &[Disk], floor: f64, bin: f64) -> Vec<Vec2> {
    let left = disks
        .iter()
        .map(|d| d.center.x)
        .fold(f64::INFINITY, f64::min);
    let mut bins: Vec<Option<Disk>> = Vec::new();
    for d in disks {
        let k = ((d.center.x - left) / bin) as usize;
        if bins.len() <= k {
            bins.resize(k + 1, None);
        }
        if bins[k].is_none_or(|o| d.top() > o.top()) {
            bins[k] = Some(*d);
        }
    }
    bins.into_iter()
        .flatten()
        .map(|d| Vec2::new(d.center.x, d.top() - floor))
        .collect()
}

/// The least-squares slope of `y` over `x`.
pub(crate) fn slope(points: &[Vec2]) -> f64 {
    let n = points.len() as f64;
    let (mx, my) = (
        points.iter().map(|p| p.x).sum::<f64>() / n,
        points.iter().map(|p| p.y).sum::<f64>() / n,
    );
    let sxy: f64 = points.iter().map(|p| (p.x - mx) * (p.y - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.x - mx) * (p.x - mx)).sum();
    sxy / sxx
}

/// The fraction of the apex's height below which a surface point is the toe, and above which
/// (one minus it) the top: the flanks are fitted between.
pub const TRIM: f64 = 0.2;

/// The angle of repose of the heap of `disks` on a floor at `floor`, poured over `x = axis`
/// (see the module docs), with bins `bin` wide (one mean diameter); `None` when a flank has
/// fewer than three points to fit.
pub fn angle(disks: &[Disk], floor: f64, axis: f64, bin: f64) -> Option<Repose> {
    let surface = surface(disks, floor, bin);
    let apex = surface.iter().copied().max_by(|a, b| a.y.total_cmp(&b.y))?;
    let band = TRIM * apex.y..=(1.0 - TRIM) * apex.y;
    let fit = |left: bool| {
        let points: Vec<Vec2> = surface
            .iter()
            .filter(|p| (p.x < axis) == left && band.contains(&p.y))
            .copied()
            .collect();
        (points.len() >= 3).then(|| {
            let s = slope(&points);
            Flank {
                degrees: s.abs().atan().to_degrees(),
                slope: s,
                points: points.len(),
            }
        })
    };
    Some(Repose {
        left: fit(true)?,
        right: fit(false)?,
        apex: Vec2::new(apex.x, apex.y + floor),
    })
}

/// A world of the soft step for `pour`: its box, gravity and time step, Box2D's settings
/// otherwise (4 substeps, the soft contact's defaults, sleeping as the soft model's scenes have it), and
/// `material` for the grains and the walls alike.
pub fn world(pour: &Pour, material: Material) -> World {
    let settings = Settings {
        step: pour.time_step,
        gravity: pour.gravity,
        ..Settings::soft()
    };
    let mut w = World::from_parts(Vec::new(), pour.walls(), settings, 0, 0.0, Queue::default());
    w.materials = vec![material];
    w.wall_material = floor(&material);
    w
}

/// The friction and the rolling resistance a grain meets on the floor (and the far walls):
/// a rough floor, on which a grain neither slides nor rolls once it has landed (as on a floor of
/// glued grains), so that the heap's base cannot spread.
pub const FLOOR_FRICTION: f64 = 1.0;
pub const FLOOR_ROLLING_RESISTANCE: f64 = 1.0;

/// The floor's material that, mixed with `grain`'s by the soft step's and Box2D's rules
/// (friction the geometric mean, rolling resistance the larger), gives [`FLOOR_FRICTION`] and
/// [`FLOOR_ROLLING_RESISTANCE`]; the grain's restitution and density.
pub fn floor(grain: &Material) -> Material {
    Material {
        friction: if grain.friction > 0.0 {
            FLOOR_FRICTION * FLOOR_FRICTION / grain.friction
        } else {
            0.0
        },
        rolling_resistance: FLOOR_ROLLING_RESISTANCE,
        ..*grain
    }
}

impl Pile for World {
    type Error = std::convert::Infallible;

    fn add(&mut self, x: f64, y: f64, radius: f64) -> Result<(), Self::Error> {
        let disk = Superellipse::circle(radius).expect("a positive, finite radius");
        let pose = Pose::new(Vec2::new(x, y), 0.0).expect("a finite place");
        self.bodies.push(Body::at_rest(disk, &pose));
        Ok(())
    }

    fn step(&mut self) -> Result<(), Self::Error> {
        World::step(self);
        Ok(())
    }

    fn disks(&mut self, out: &mut Vec<Disk>) -> Result<(), Self::Error> {
        out.clear();
        out.extend(self.bodies.iter().map(|b| Disk {
            center: b.center,
            radius: b.shape.semi_axes().x,
        }));
        Ok(())
    }

    fn fastest(&mut self) -> Result<f64, Self::Error> {
        Ok(self.max_speed())
    }
}

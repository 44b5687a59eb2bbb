//! The two measurements, written once for every peer: a settled heap stepped with every grain
//! awake (ms per step), and a pour from the empty box until rest (wall time, steps, and how
//! deep the rested disks overlap).

use std::time::Instant;

use crate::overlap::{self, Resting};
use crate::peer::{Error, Peer};
use crate::scene::{Rest, Scene, Spawner};
use supergrain::world::RestCounter;

/// A heap's steps, measured.
#[derive(Clone, Debug, PartialEq)]
pub struct HeapTiming {
    pub grains: usize,
    /// The median of `runs`.
    pub ms_per_step: f64,
    /// Each repetition's mean ms per timed step.
    pub runs: Vec<f64>,
}

/// A pour, measured.
#[derive(Clone, Debug, PartialEq)]
pub struct PourTiming {
    pub grains: usize,
    /// Wall time from the first step to rest (or to the step cap), spawning and the rest test
    /// included.
    pub seconds: f64,
    /// Of `seconds`, the engine's steps alone (supergrain's include its own spawner, which is
    /// part of its step; the harness's copies of the grains for the peers' spawner, its
    /// overlap tests and the fastest-grain query are the rest).
    pub engine_seconds: f64,
    pub steps: u64,
    pub at_rest: bool,
    /// How deep the grains overlap where the pour ended (untimed; disks only:
    /// [`overlap::resting`]).
    pub overlap: Option<Resting>,
}

impl PourTiming {
    /// The pours of several seeds as one: the median wall time, steps, mean and largest
    /// overlap (each taken alone), at rest only if every pour was.
    pub fn median_of(runs: &[PourTiming]) -> PourTiming {
        let seconds: Vec<f64> = runs.iter().map(|r| r.seconds).collect();
        let engine: Vec<f64> = runs.iter().map(|r| r.engine_seconds).collect();
        let steps: Vec<f64> = runs.iter().map(|r| r.steps as f64).collect();
        let overlaps: Option<Vec<Resting>> = runs.iter().map(|r| r.overlap).collect();
        PourTiming {
            grains: runs.first().map_or(0, |r| r.grains),
            seconds: median(&seconds),
            engine_seconds: median(&engine),
            steps: median(&steps).round() as u64,
            at_rest: runs.iter().all(|r| r.at_rest),
            overlap: overlaps.filter(|o| !o.is_empty()).map(|o| {
                let of = |f: fn(&Resting) -> f64| median(&o.iter().map(f).collect::<Vec<_>>());
                Resting {
                    contacts: of(|r| r.contacts as f64).round() as usize,
                    mean: of(|r| r.mean),
                    largest: of(|r| r.largest),
                    mean_diameter: of(|r| r.mean_diameter),
                }
            }),
        }
    }
}

/// The median (the mean of the two middle values for an even count).
pub fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// `scene`'s placed grains in a new `P` world with sleeping off, `warmup` steps untimed (the
/// peers' shapes are not all supergrain's, so the heap first settles to them), then `steps`
/// timed; `reps` times from the heap.
pub fn heap<P: Peer>(
    scene: &Scene,
    threads: usize,
    warmup: u64,
    steps: u64,
    reps: usize,
) -> Result<HeapTiming, Error> {
    let mut runs = Vec::with_capacity(reps.max(1));
    for _ in 0..reps.max(1) {
        let mut peer = P::new(scene, threads, false)?;
        for _ in 0..warmup {
            peer.step()?;
        }
        let start = Instant::now();
        for _ in 0..steps {
            peer.step()?;
        }
        runs.push(start.elapsed().as_secs_f64() * 1e3 / steps.max(1) as f64);
    }
    Ok(HeapTiming {
        grains: scene.grains.len(),
        ms_per_step: median(&runs),
        runs,
    })
}

/// `scene`'s spawn queue poured into its empty box with sleeping on (each engine's own), until
/// rest.
pub fn pour<P: Peer>(scene: &Scene, threads: usize, rest: &Rest) -> Result<PourTiming, Error> {
    let mut peer = P::new(scene, threads, true)?;
    let mut spawner = Spawner::new(&scene.spawns);
    let mut placed = Vec::with_capacity(scene.grain_count());
    let mut calm = RestCounter::default();
    let start = Instant::now();
    let mut engine = std::time::Duration::ZERO;
    let mut steps = 0;
    let mut at_rest = false;
    while steps < rest.max_steps && !at_rest {
        if !spawner.is_empty() {
            peer.grains(&mut placed)?;
            for g in spawner.due(steps, scene.top, &placed) {
                peer.add(&g)?;
            }
        }
        let stepping = Instant::now();
        peer.step()?;
        engine += stepping.elapsed();
        steps += 1;
        at_rest = calm.update(&rest.criterion(), spawner.is_empty(), peer.fastest()?);
    }
    let seconds = start.elapsed().as_secs_f64();
    peer.grains(&mut placed)?;
    Ok(PourTiming {
        grains: peer.len(),
        seconds,
        engine_seconds: engine.as_secs_f64(),
        steps,
        at_rest,
        overlap: overlap::resting(&placed, &scene.walls),
    })
}

//! `bench peers --scene repose`: the angle of repose of disks with rolling resistance, poured
//! from a narrow source onto a wide floor, for several frictions, in supergrain's soft step and
//! in Box2D v3. The pour and the measure are supergrain's own
//! ([`supergrain::measure::repose`]), written once for any engine; here each peer is driven
//! through them.
//!
//! Materials match: friction `mu` and rolling resistance `mu_r` on grains and walls alike,
//! restitution 0, density 1, mixed by the same rules (friction the geometric mean, restitution
//! and rolling resistance the larger). One difference remains: Box2D's rolling torque is at most
//! `mu_r` times the *larger* radius of the pair times the normal force, supergrain's soft step
//! takes the contact's mean lever (about the mean radius): with radii within 10% of their mean,
//! the two differ by at most 10% on a pair, 3% on average. Against the floor both take the
//! grain's radius. rapier2d has no rolling resistance and the paper's model no friction: neither
//! runs this scene.

use supergrain::body::Material;
use supergrain::measure::Disk;
use supergrain::measure::repose::{self, Pile, Pour, Repose};
use supergrain::settings::SolverTable;

use crate::bench::Engine;
use crate::box2d::Box2d;
use crate::peer::{Error, Peer};
use crate::scene::{DENSITY, Grain, SUBSTEPS, Scene, Shape, Walls};

/// The frictions of issue 18's bar.
pub const FRICTIONS: [f64; 4] = [0.1, 0.3, 0.5, 0.8];

/// The rolling resistance every pour takes: enough that disks hold a slope as real grains do
/// (without it a frictional disk rolls down any slope), in the middle of what DEM studies of
/// disks use (0.05-0.2) and of Box2D's own range.
pub const ROLLING_RESISTANCE: f64 = 0.1;

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    pub frictions: Vec<f64>,
    pub rolling_resistance: f64,
    /// Each pour's seed (the radii and the source's draws).
    pub seeds: Vec<u64>,
    /// Everything else of the pour (its seed is replaced by each of `seeds`).
    pub pour: Pour,
    pub engines: Vec<Engine>,
    pub threads: usize,
    /// Our `[solver]` keys changed from the bench's (`bench peers --set`); Box2D keeps its.
    pub overrides: SolverTable,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            frictions: FRICTIONS.to_vec(),
            rolling_resistance: ROLLING_RESISTANCE,
            seeds: vec![1, 2, 3],
            pour: Pour::default(),
            engines: vec![Engine::Soft, Engine::Box2d],
            threads: 1,
            overrides: SolverTable::default(),
        }
    }
}

/// One pour, measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    pub engine: Engine,
    pub friction: f64,
    pub seed: u64,
    pub grains: usize,
    pub steps: u64,
    pub at_rest: bool,
    pub seconds: f64,
    /// `None` when a flank had too few surface points to fit.
    pub repose: Option<Repose>,
}

/// The runs of one engine and one friction, over the seeds.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    pub engine: Engine,
    pub friction: f64,
    /// The mean of the seeds' angles (each the mean of its two flanks), in degrees.
    pub degrees: f64,
    pub min: f64,
    pub max: f64,
    /// Seeds measured (a pour whose flanks could not be fitted is left out).
    pub seeds: usize,
}

/// The neutral scene of a pour: its box, gravity and time step, Box2D's substeps, and the
/// material.
pub fn scene(pour: &Pour, friction: f64, rolling_resistance: f64) -> Scene {
    let w = pour.walls();
    let floor = repose::floor(&material(friction, rolling_resistance));
    Scene {
        walls: Walls {
            left: w.left,
            right: w.right,
            floor: w.floor,
        },
        gravity: pour.gravity,
        time_step: pour.time_step,
        substeps: SUBSTEPS,
        friction,
        restitution: 0.0,
        density: DENSITY,
        rolling_resistance,
        wall_friction: floor.friction,
        wall_rolling_resistance: floor.rolling_resistance,
        grains: Vec::new(),
        spawns: Vec::new(),
        // The walls stand far from the heap; this only sets their height.
        top: 0.5 * pour.half_width,
    }
}

/// The grains' material: restitution 0, density 1.
pub fn material(friction: f64, rolling_resistance: f64) -> Material {
    Material {
        friction,
        rolling_resistance,
        restitution: 0.0,
        density: DENSITY,
    }
}

/// A peer driven by the pour.
pub struct Piled<P: Peer> {
    pub peer: P,
    grains: Vec<Grain>,
}

impl<P: Peer> Piled<P> {
    pub fn new(peer: P) -> Self {
        Piled {
            peer,
            grains: Vec::new(),
        }
    }
}

impl<P: Peer> Pile for Piled<P> {
    type Error = Error;

    fn add(&mut self, x: f64, y: f64, radius: f64) -> Result<(), Error> {
        self.peer.add(&Grain {
            shape: Shape::Circle { radius },
            x,
            y,
            angle: 0.0,
        })
    }

    fn step(&mut self) -> Result<(), Error> {
        self.peer.step()
    }

    fn disks(&mut self, out: &mut Vec<Disk>) -> Result<(), Error> {
        self.peer.grains(&mut self.grains)?;
        out.clear();
        for g in &self.grains {
            let Shape::Circle { radius } = g.shape else {
                return Err(Error("the pour adds disks only".into()));
            };
            out.push(Disk::new(g.x, g.y, radius));
        }
        Ok(())
    }

    fn fastest(&mut self) -> Result<f64, Error> {
        self.peer.fastest()
    }
}

/// One pour of `engine` with `friction`, measured.
pub fn run(
    engine: Engine,
    pour: &Pour,
    friction: f64,
    rolling_resistance: f64,
    threads: usize,
    overrides: &SolverTable,
) -> Result<Run, Error> {
    let poured = match engine {
        Engine::Soft => {
            let mut world = repose::world(pour, material(friction, rolling_resistance));
            overrides
                .apply(&mut world.settings)
                .and_then(|()| world.settings.validate())
                .map_err(Error)?;
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads.max(1))
                .build()
                .map_err(|e| Error(format!("a pool of {threads} threads: {e}")))?;
            pool.install(|| repose::pour(&mut world, pour))
                .unwrap_or_else(|never| match never {})
        }
        Engine::Box2d => {
            let scene = scene(pour, friction, rolling_resistance);
            let mut pile = Piled::new(Box2d::new(&scene, threads, true)?);
            repose::pour(&mut pile, pour)?
        }
        Engine::Supergrain | Engine::Rapier | Engine::SoftStiff => {
            return Err(Error(format!(
                "{} has no {}: the repose scene runs soft and box2d",
                engine.name(),
                match engine {
                    Engine::Rapier => "rolling resistance",
                    Engine::Supergrain => "friction (the paper's projection model)",
                    _ => "scene file to set max_overlap in",
                }
            )));
        }
    };
    Ok(Run {
        engine,
        friction,
        seed: pour.seed,
        grains: poured.disks.len(),
        steps: poured.steps,
        at_rest: poured.at_rest,
        seconds: poured.seconds,
        repose: pour.angle(&poured.disks),
    })
}

/// Every run of `options`: friction by friction, engine by engine, seed by seed; `progress`
/// hears each before it starts.
pub fn runs(options: &Options, progress: &mut dyn FnMut(&str)) -> Result<Vec<Run>, Error> {
    let mut out = Vec::new();
    for &friction in &options.frictions {
        for &engine in &options.engines {
            for &seed in &options.seeds {
                progress(&format!(
                    "repose mu = {friction} mu_r = {} {} seed {seed}",
                    options.rolling_resistance,
                    engine.name()
                ));
                let pour = Pour {
                    seed,
                    ..options.pour
                };
                out.push(run(
                    engine,
                    &pour,
                    friction,
                    options.rolling_resistance,
                    options.threads,
                    &options.overrides,
                )?);
            }
        }
    }
    Ok(out)
}

/// The runs summed up by engine and friction, in the order they came.
pub fn summaries(runs: &[Run]) -> Vec<Summary> {
    let mut out: Vec<Summary> = Vec::new();
    for r in runs {
        if out
            .iter()
            .any(|s| s.engine == r.engine && s.friction == r.friction)
        {
            continue;
        }
        let angles: Vec<f64> = runs
            .iter()
            .filter(|o| o.engine == r.engine && o.friction == r.friction)
            .filter_map(|o| o.repose.map(|a| a.degrees()))
            .collect();
        let n = angles.len();
        out.push(Summary {
            engine: r.engine,
            friction: r.friction,
            degrees: if n > 0 {
                angles.iter().sum::<f64>() / n as f64
            } else {
                f64::NAN
            },
            min: angles.iter().copied().fold(f64::NAN, f64::min),
            max: angles.iter().copied().fold(f64::NAN, f64::max),
            seeds: n,
        });
    }
    out
}

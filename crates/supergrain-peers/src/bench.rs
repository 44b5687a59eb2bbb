//! The cases of `supergrain bench peers`: which scene, which shapes, which engine, how many
//! threads, and each case's ratio to Box2D v3 on the same scene and threads.

use std::fmt;

use supergrain::io::Dump;
use supergrain::world::{Scene as SupergrainScene, World};

use crate::box2d::Box2d;
use crate::peer::Error;
use crate::rapier::Rapier;
use crate::run::{self, HeapTiming, PourTiming};
use crate::scene::{Rest, Scene};

/// The settled 1,000-grain pour of pebbles, rice and blocks: `data/pour-1000-mix.toml` poured
/// to rest by the soft model (the command that made it is in that file).
pub const HEAP_MIX: &str = include_str!("../data/heap-mix.json");
/// The settled 1,000 pebbles of `data/pour-1000-circles.toml` (the command that made it is in
/// that file).
pub const HEAP_CIRCLES: &str = include_str!("../data/heap-circles.json");
/// `examples/scenes/pour-1000.toml` with the default narrow phase (the file says why).
pub const POUR_1000_MIX: &str = include_str!("../data/pour-1000-mix.toml");
pub const POUR_1000_CIRCLES: &str = include_str!("../data/pour-1000-circles.toml");
pub const POUR_10K_MIX: &str = include_str!("../../../examples/scenes/pour-10k.toml");
pub const POUR_10K_CIRCLES: &str = include_str!("../data/pour-10k-circles.toml");
/// Issue 40's pour of 500 + 500 disks of radii 0.25 and 0.35 (the file says more).
pub const POUR_BIDISPERSE: &str = include_str!("../data/pour-bidisperse.toml");

/// The scenes of Box2D's benchmark app's kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneKind {
    /// The settled 1,000-grain heap, every grain awake: ms per step.
    Heap,
    /// The 1,000-grain pour until rest: wall time and steps.
    Pour1000,
    /// The 10,000-grain pour until rest (or the step cap).
    Pour10k,
    /// Issue 40's bidisperse pour of 1,000 disks until rest, for how deep they overlap at rest
    /// (circles alone).
    Bidisperse,
}

impl SceneKind {
    pub const ALL: [SceneKind; 3] = [SceneKind::Heap, SceneKind::Pour1000, SceneKind::Pour10k];

    pub fn name(self) -> &'static str {
        match self {
            SceneKind::Heap => "heap",
            SceneKind::Pour1000 => "pour-1000",
            SceneKind::Pour10k => "pour-10k",
            SceneKind::Bidisperse => "bidisperse",
        }
    }
}

/// The grains: circles alone (the same radii in every engine), or the mix of pebbles, rice and
/// blocks (rice as capsules, blocks as rounded boxes for the peers).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shapes {
    Circles,
    Mix,
}

impl Shapes {
    pub fn name(self) -> &'static str {
        match self {
            Shapes::Circles => "circles",
            Shapes::Mix => "mix",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Engine {
    Supergrain,
    /// supergrain with the soft step (`model = "soft"`): Box2D's defaults for materials
    /// (friction 0.6, density 1), 4 substeps, the same time step.
    Soft,
    /// The soft step as the scene asks for `max_overlap =`
    /// [`MAX_OVERLAP`](crate::supergrain::MAX_OVERLAP) in `[solver]`: the stiffness and
    /// substeps follow from it (pours only).
    SoftStiff,
    Box2d,
    Rapier,
}

impl Engine {
    pub const ALL: [Engine; 4] = [
        Engine::Supergrain,
        Engine::Soft,
        Engine::Box2d,
        Engine::Rapier,
    ];

    pub fn name(self) -> &'static str {
        use crate::peer::Peer;
        match self {
            Engine::Supergrain => crate::supergrain::NAME,
            Engine::Soft => crate::supergrain::SOFT,
            Engine::SoftStiff => crate::supergrain::SOFT_STIFF,
            Engine::Box2d => Box2d::NAME,
            Engine::Rapier => Rapier::NAME,
        }
    }
}

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    pub scenes: Vec<SceneKind>,
    pub shapes: Vec<Shapes>,
    pub engines: Vec<Engine>,
    pub threads: Vec<usize>,
    /// Heap: untimed steps before the timed ones.
    pub warmup: u64,
    /// Heap: timed steps per repetition.
    pub steps: u64,
    /// Heap: repetitions, each from the heap; the median is reported.
    pub reps: usize,
    /// Pours: when at rest, and the step cap.
    pub rest: Rest,
    /// Pours: one pour per seed (the scene's draws of grains and places), the median reported;
    /// empty: the scene's own seed alone.
    pub seeds: Vec<u64>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            scenes: vec![SceneKind::Heap, SceneKind::Pour1000],
            shapes: vec![Shapes::Circles, Shapes::Mix],
            engines: Engine::ALL.to_vec(),
            threads: vec![1, 2],
            warmup: 300,
            steps: 100,
            reps: 3,
            rest: Rest::default(),
            seeds: Vec::new(),
        }
    }
}

/// One measured case.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub scene: SceneKind,
    pub shapes: Shapes,
    pub engine: Engine,
    pub threads: usize,
    pub grains: usize,
    pub result: Measured,
    /// This case's time over Box2D's on the same scene, shapes and threads.
    pub x_box2d: Option<f64>,
    /// A pour's run per seed, in the order run (`result` is their median).
    pub seeds: Vec<(u64, PourTiming)>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Measured {
    Heap(HeapTiming),
    Pour(PourTiming),
}

impl Case {
    /// The time compared: ms per step of a heap, seconds of a pour.
    pub fn time(&self) -> f64 {
        match &self.result {
            Measured::Heap(h) => h.ms_per_step,
            Measured::Pour(p) => p.seconds,
        }
    }
}

impl fmt::Display for Case {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} {} {} {} thread{}",
            self.scene.name(),
            self.shapes.name(),
            self.engine.name(),
            self.threads,
            if self.threads == 1 { "" } else { "s" }
        )
    }
}

fn heap_world(shapes: Shapes) -> Result<World, Error> {
    let text = match shapes {
        Shapes::Circles => HEAP_CIRCLES,
        Shapes::Mix => HEAP_MIX,
    };
    let dump = Dump::from_json(text).map_err(|e| Error(format!("the built-in heap: {e}")))?;
    dump.to_world()
        .map_err(|e| Error(format!("the built-in heap: {e}")))
}

fn pour_text(kind: SceneKind, shapes: Shapes) -> Result<&'static str, Error> {
    Ok(match (kind, shapes) {
        (SceneKind::Bidisperse, Shapes::Circles) => POUR_BIDISPERSE,
        (SceneKind::Bidisperse, Shapes::Mix) => {
            return Err(Error("the bidisperse pour is of circles alone".into()));
        }
        (SceneKind::Pour10k, Shapes::Circles) => POUR_10K_CIRCLES,
        (SceneKind::Pour10k, Shapes::Mix) => POUR_10K_MIX,
        (_, Shapes::Circles) => POUR_1000_CIRCLES,
        (_, Shapes::Mix) => POUR_1000_MIX,
    })
}

fn pour_scene(kind: SceneKind, shapes: Shapes) -> Result<SupergrainScene, Error> {
    SupergrainScene::from_toml(pour_text(kind, shapes)?)
        .map_err(|e| Error(format!("the built-in scene: {e}")))
}

/// The built-in scene with `max_overlap =` [`MAX_OVERLAP`](crate::supergrain::MAX_OVERLAP)
/// added to its `[solver]`, read as a user's file is (so the stiffness and substeps are the
/// ones that setting documents), with `seed`.
pub fn stiff_pour(kind: SceneKind, shapes: Shapes, seed: u64) -> Result<SupergrainScene, Error> {
    let text = pour_text(kind, shapes)?;
    let line = format!(
        "[solver]\nmax_overlap = {}\n",
        crate::supergrain::MAX_OVERLAP
    );
    if !text.contains("[solver]\n") {
        return Err(Error(
            "the built-in scene has no [solver] for max_overlap".into(),
        ));
    }
    let mut scene = SupergrainScene::from_toml(&text.replacen("[solver]\n", &line, 1))
        .map_err(|e| Error(format!("the built-in scene with max_overlap: {e}")))?;
    scene.seed = seed;
    Ok(crate::supergrain::stiff_scene(&scene))
}

/// The neutral heap of a built-in settled heap.
pub fn heap_scene(shapes: Shapes) -> Result<(World, Scene), Error> {
    let world = heap_world(shapes)?;
    let scene = Scene::heap(&world).map_err(|e| Error(e.to_string()))?;
    Ok((world, scene))
}

/// The neutral pour of a built-in scene, with `seed` in place of its own if given.
pub fn pour(
    kind: SceneKind,
    shapes: Shapes,
    seed: Option<u64>,
) -> Result<(SupergrainScene, Scene), Error> {
    let mut scene = pour_scene(kind, shapes)?;
    if let Some(seed) = seed {
        scene.seed = seed;
    }
    let neutral = Scene::pour(&scene).map_err(|e| Error(e.to_string()))?;
    Ok((scene, neutral))
}

/// Runs every case of `options`, scene by scene, shapes, threads, then engines in turn;
/// `progress` hears each case before it starts.
pub fn cases(options: &Options, progress: &mut dyn FnMut(&str)) -> Result<Vec<Case>, Error> {
    let mut out = Vec::new();
    for &kind in &options.scenes {
        for &shapes in &options.shapes {
            // A pour per seed (the scene's own when none is asked).
            let seeds: Vec<Option<u64>> = if options.seeds.is_empty() {
                vec![None]
            } else {
                options.seeds.iter().copied().map(Some).collect()
            };
            let (heap, pours) = match kind {
                SceneKind::Heap => (Some(heap_scene(shapes)?), Vec::new()),
                _ => (
                    None,
                    seeds
                        .iter()
                        .map(|&s| pour(kind, shapes, s))
                        .collect::<Result<Vec<_>, _>>()?,
                ),
            };
            for &threads in &options.threads {
                for &engine in &options.engines {
                    let mut case = Case {
                        scene: kind,
                        shapes,
                        engine,
                        threads,
                        grains: 0,
                        result: Measured::Heap(HeapTiming {
                            grains: 0,
                            ms_per_step: f64::NAN,
                            runs: Vec::new(),
                        }),
                        x_box2d: None,
                        seeds: Vec::new(),
                    };
                    let o = options;
                    if heap.is_some() {
                        progress(&case.to_string());
                    }
                    case.result = match &heap {
                        Some((world, scene)) => Measured::Heap(match engine {
                            Engine::Supergrain => crate::supergrain::heap(
                                &crate::supergrain::paper_world(world),
                                threads,
                                o.warmup,
                                o.steps,
                                o.reps,
                            ),
                            Engine::Soft => crate::supergrain::heap(
                                &crate::supergrain::soft_world(world),
                                threads,
                                o.warmup,
                                o.steps,
                                o.reps,
                            ),
                            Engine::SoftStiff => {
                                return Err(Error(format!(
                                    "{}: the heap is a dump, with no scene to set max_overlap \
                                     in; it runs the pours",
                                    engine.name()
                                )));
                            }
                            Engine::Box2d => {
                                run::heap::<Box2d>(scene, threads, o.warmup, o.steps, o.reps)?
                            }
                            Engine::Rapier => {
                                run::heap::<Rapier>(scene, threads, o.warmup, o.steps, o.reps)?
                            }
                        }),
                        None => {
                            for (scene, neutral) in &pours {
                                progress(&if pours.len() > 1 {
                                    format!("{case} seed {}", scene.seed)
                                } else {
                                    case.to_string()
                                });
                                let timing = match engine {
                                    Engine::Supergrain => crate::supergrain::pour(
                                        &crate::supergrain::paper_scene(scene),
                                        threads,
                                        &o.rest,
                                    ),
                                    Engine::Soft => crate::supergrain::pour(
                                        &crate::supergrain::soft_scene(scene),
                                        threads,
                                        &o.rest,
                                    ),
                                    Engine::SoftStiff => crate::supergrain::pour(
                                        &stiff_pour(kind, shapes, scene.seed)?,
                                        threads,
                                        &o.rest,
                                    ),
                                    Engine::Box2d => run::pour::<Box2d>(neutral, threads, &o.rest)?,
                                    Engine::Rapier => {
                                        run::pour::<Rapier>(neutral, threads, &o.rest)?
                                    }
                                };
                                case.seeds.push((scene.seed, timing));
                            }
                            let runs: Vec<PourTiming> =
                                case.seeds.iter().map(|(_, t)| t.clone()).collect();
                            Measured::Pour(PourTiming::median_of(&runs))
                        }
                    };
                    case.grains = match &case.result {
                        Measured::Heap(h) => h.grains,
                        Measured::Pour(p) => p.grains,
                    };
                    out.push(case);
                }
            }
        }
    }
    let ratios: Vec<Option<f64>> = out
        .iter()
        .map(|c| {
            out.iter()
                .find(|b| {
                    b.engine == Engine::Box2d
                        && b.scene == c.scene
                        && b.shapes == c.shapes
                        && b.threads == c.threads
                })
                .map(|b| c.time() / b.time())
        })
        .collect();
    for (c, r) in out.iter_mut().zip(ratios) {
        c.x_box2d = r;
    }
    Ok(out)
}

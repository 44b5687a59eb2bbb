//! `supergrain bench peers`: the same scenes through supergrain, Box2D v3 and rapier2d (the
//! `supergrain-peers` crate), printed as a table, JSON or CSV. Built only with the `peers`
//! feature: the peers are bench-only dependencies, and Box2D builds from C source.

use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, ValueEnum};

/// How to build the command with the peers.
#[cfg(not(feature = "peers"))]
pub const BUILD_WITH_PEERS: &str =
    "cargo run --release -p supergrain-cli --features peers -- bench peers";

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SceneArg {
    /// The settled 1,000-grain heap, every grain awake and sleeping off: ms per step.
    Heap,
    /// The 1,000-grain pour from the empty box until rest: wall time and steps.
    #[value(name = "pour-1000")]
    Pour1000,
    /// The 10,000-grain pour until rest (or --max-steps).
    #[value(name = "pour-10k")]
    Pour10k,
    /// All three timed scenes (not bidisperse or repose).
    All,
    /// Issue 40's pour of 500 + 500 disks of radii 0.25 and 0.35 (friction 0.6, a box 20 wide)
    /// until rest: how deep the rested disks overlap in each engine, measured alike.
    Bidisperse,
    /// The angle of repose of disks with rolling resistance poured onto a floor, for each
    /// --frictions: supergrain's soft step next to Box2D (a measure of the physics, not of time).
    Repose,
    /// A half-filled drum of disks turning at each --rates, for each --frictions: the free
    /// surface's dynamic angle, supergrain's soft step next to Box2D (physics, not time).
    Drum,
    /// Box2D's benchmark tumbler: 2,025 squares in a box 20 wide turning at 25 degrees per
    /// second, 60 Hz, 4 substeps: ms per step over --steps from the start (default 600),
    /// supergrain's soft step (squares of exponent 16) next to Box2D.
    Tumbler,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ShapesArg {
    /// Circles alone: the same radii in every engine.
    Circles,
    /// Pebbles, rice and blocks (rice as capsules, blocks as rounded boxes for the peers).
    Mix,
    /// Circles, then the mix.
    Both,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EngineArg {
    /// supergrain with the paper's model (the scenes' own until scene files defaulted to the soft one).
    Supergrain,
    /// supergrain with the rigid-body soft step (`model = "soft"`, Box2D's materials).
    Soft,
    /// The soft step with `max_overlap = 0.01` added to the pour's `[solver]` (pours only).
    SoftStiff,
    Box2d,
    Rapier,
}

#[derive(Parser)]
pub struct Args {
    /// Which scene.
    #[arg(long, value_enum, default_value = "heap")]
    scene: SceneArg,
    /// Circles alone or the mix of pebbles, rice and blocks (bidisperse: circles alone).
    #[arg(long, value_enum, default_value = "both")]
    shapes: ShapesArg,
    /// Engines, each run in turn [default: supergrain,soft,box2d,rapier; bidisperse:
    /// soft,soft-stiff,box2d,rapier; repose: soft,box2d, the two with rolling resistance;
    /// drum and tumbler: always soft and box2d, not to be changed].
    #[arg(long, value_enum, value_delimiter = ',')]
    engines: Option<Vec<EngineArg>>,
    /// Heap: timed steps per repetition [default: 100; tumbler: 600, from the start].
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    steps: Option<u64>,
    /// Heap: untimed steps first, for every engine to settle the heap to its own shapes (the
    /// peers' hold about 6% more area; Box2D's mixed heap moves for some 250 steps).
    #[arg(long, default_value_t = 300)]
    warmup: u64,
    /// Heap: repetitions, each from the heap; the median is reported.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..))]
    reps: u64,
    /// Pours: speed under which a grain counts as at rest (as `run --until-rest`).
    #[arg(long, default_value_t = 0.05, value_name = "SPEED")]
    rest_speed: f64,
    /// Pours: at rest after this many steps in a row with every grain in and none faster.
    #[arg(long, default_value_t = 100)]
    rest_steps: u32,
    /// Pours: the most steps run (a pour not at rest by then says so).
    #[arg(long, default_value_t = 20_000, value_parser = clap::value_parser!(u64).range(1..))]
    max_steps: u64,
    /// Repose and drum: the grains' friction coefficients, one run each (per engine and seed)
    /// [default: repose 0.1,0.3,0.5,0.8; drum 0.3,0.6].
    #[arg(long, value_delimiter = ',', value_name = "MU")]
    frictions: Option<Vec<f64>>,
    /// Drum: its rates in degrees per second, one run each [default: 6,18,54, Froude numbers
    /// 0.001, 0.01 and 0.09].
    #[arg(long, value_delimiter = ',', value_name = "DEG_PER_S")]
    rates: Option<Vec<f64>>,
    /// Repose: the grains' rolling resistance (Box2D's `rollingResistance`).
    #[arg(long, default_value_t = 0.1, value_name = "MU_R")]
    rolling_resistance: f64,
    /// Pours: each pour with seeds 1, 2, ..., N (the scene's draws of grains and places), the
    /// median wall time and steps reported and each seed's in --json [default: the scene's own
    /// seed alone]. Repose: pours per friction and engine, seeds 1 to N, the angles' mean and
    /// spread reported [default: 3]. Drum: runs per rate and friction, seeds 1 to N (the radii), the
    /// mean reported [default: 3].
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    seeds: Option<u64>,
    /// Repose: disks per pour.
    #[arg(long, default_value_t = 600, value_parser = clap::value_parser!(u64).range(10..))]
    grains: u64,
    /// Drum and repose: override one of supergrain's `[solver]` keys in its runs, as `run
    /// --set` does (repeatable): --set contact_hertz=30. Box2D's settings stay its defaults.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Print {"cases": [...]} instead of a table.
    #[arg(long)]
    json: bool,
    /// Print CSV instead of a table: a header, then one row per case.
    #[arg(long, conflicts_with = "json")]
    csv: bool,
}

/// Thread counts when `--threads` (the command's global option) is not given: each engine on one
/// thread, then on two (supergrain: a rayon pool, the box cut into strips above one thread;
/// Box2D: its own scheduler's workers; rapier: its `parallel` pool).
#[cfg(feature = "peers")]
pub const DEFAULT_THREADS: [usize; 2] = [1, 2];

#[cfg(not(feature = "peers"))]
pub fn run(_args: Args, _threads: Option<u16>) -> Result<ExitCode> {
    anyhow::bail!(
        "`bench peers` needs the peers (Box2D v3, built from source, and rapier2d), which this \
         build left out: they are behind the `peers` feature, off by default. Build and run it \
         with\n  {BUILD_WITH_PEERS}"
    )
}

/// `threads`: the global `--threads`, one count; without it [`DEFAULT_THREADS`].
#[cfg(feature = "peers")]
pub fn run(args: Args, threads: Option<u16>) -> Result<ExitCode> {
    use supergrain_peers::bench::{self, Engine, Measured, SceneKind, Shapes};
    use supergrain_peers::scene::Rest;

    if !(args.rest_speed.is_finite() && args.rest_speed > 0.0) {
        anyhow::bail!(
            "--rest-speed: expected a positive number, got {}",
            args.rest_speed
        );
    }
    let engines = args.engines.as_ref().map(|engines| {
        engines
            .iter()
            .map(|e| match e {
                EngineArg::Supergrain => Engine::Supergrain,
                EngineArg::Soft => Engine::Soft,
                EngineArg::SoftStiff => Engine::SoftStiff,
                EngineArg::Box2d => Engine::Box2d,
                EngineArg::Rapier => Engine::Rapier,
            })
            .collect::<Vec<_>>()
    });
    if !args.set.is_empty() && !matches!(args.scene, SceneArg::Drum | SceneArg::Repose) {
        anyhow::bail!(
            "--set: only --scene drum and --scene repose take supergrain's settings from the \
             command line (the timed scenes keep the settings their figures were measured with)"
        );
    }
    if args.scene == SceneArg::Repose {
        return repose(&args, engines, threads);
    }
    if matches!(args.scene, SceneArg::Drum | SceneArg::Tumbler) && args.engines.is_some() {
        anyhow::bail!(
            "--engines: --scene drum and --scene tumbler always run supergrain's soft step and \
             Box2D side by side (a gap or a ratio needs both)"
        );
    }
    if args.scene == SceneArg::Drum {
        return drum(&args);
    }
    if args.scene == SceneArg::Tumbler {
        return tumbler(&args, threads);
    }
    if args.scene == SceneArg::Heap && args.seeds.is_some() {
        anyhow::bail!(
            "--seeds: the heap is a settled dump and draws nothing; seeds apply to the pours \
             (--scene pour-1000, pour-10k or all) and to --scene repose"
        );
    }
    let options = bench::Options {
        scenes: match args.scene {
            SceneArg::Heap => vec![SceneKind::Heap],
            SceneArg::Pour1000 => vec![SceneKind::Pour1000],
            SceneArg::Pour10k => vec![SceneKind::Pour10k],
            SceneArg::All => SceneKind::ALL.to_vec(),
            SceneArg::Bidisperse => vec![SceneKind::Bidisperse],
            SceneArg::Repose | SceneArg::Drum | SceneArg::Tumbler => {
                unreachable!("handled above")
            }
        },
        shapes: match (args.scene, args.shapes) {
            (SceneArg::Bidisperse, ShapesArg::Mix) => {
                anyhow::bail!("--shapes mix: the bidisperse pour is of circles alone")
            }
            (SceneArg::Bidisperse, _) | (_, ShapesArg::Circles) => vec![Shapes::Circles],
            (_, ShapesArg::Mix) => vec![Shapes::Mix],
            (_, ShapesArg::Both) => vec![Shapes::Circles, Shapes::Mix],
        },
        engines: engines.unwrap_or_else(|| match args.scene {
            SceneArg::Bidisperse => {
                vec![
                    Engine::Soft,
                    Engine::SoftStiff,
                    Engine::Box2d,
                    Engine::Rapier,
                ]
            }
            _ => Engine::ALL.to_vec(),
        }),
        threads: threads.map_or(DEFAULT_THREADS.to_vec(), |n| vec![usize::from(n)]),
        warmup: args.warmup,
        steps: args.steps.unwrap_or(100),
        reps: args.reps as usize,
        rest: Rest {
            speed: args.rest_speed,
            steps: args.rest_steps,
            max_steps: args.max_steps,
        },
        seeds: args.seeds.map_or(Vec::new(), |n| (1..=n).collect()),
    };
    let cases = bench::cases(&options, &mut |case| eprintln!("running {case}"))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    if args.json || args.csv {
        let rows: Vec<_> = cases
            .iter()
            .map(|c| {
                let (ms, runs, seconds, steps, at_rest, overlap) = match &c.result {
                    Measured::Heap(h) => {
                        (Some(h.ms_per_step), Some(&h.runs), None, None, None, None)
                    }
                    Measured::Pour(p) => (
                        None,
                        None,
                        Some(p.seconds),
                        Some(p.steps),
                        Some(p.at_rest),
                        p.overlap,
                    ),
                };
                let seeds: Option<Vec<_>> = (!c.seeds.is_empty()).then(|| {
                    c.seeds
                        .iter()
                        .map(|(seed, t)| {
                            serde_json::json!({
                                "seed": seed, "seconds": t.seconds, "steps": t.steps,
                                "at_rest": t.at_rest, "overlap_mean": t.overlap.map(|o| o.mean),
                                "overlap_largest": t.overlap.map(|o| o.largest),
                            })
                        })
                        .collect()
                });
                let engine_ms = match &c.result {
                    Measured::Pour(p) => Some(p.engine_seconds * 1e3 / p.steps.max(1) as f64),
                    Measured::Heap(_) => None,
                };
                serde_json::json!({
                    "scene": c.scene.name(), "shapes": c.shapes.name(), "engine": c.engine.name(),
                    "threads": c.threads, "grains": c.grains, "ms_per_step": ms,
                    "engine_ms_per_step": engine_ms,
                    "harness_ms_per_step": match &c.result {
                        Measured::Pour(p) => Some((p.seconds - p.engine_seconds) * 1e3 / p.steps.max(1) as f64),
                        Measured::Heap(_) => None,
                    },
                    "runs_ms_per_step": runs, "seconds": seconds, "steps": steps,
                    "at_rest": at_rest, "x_box2d": c.x_box2d,
                    "overlap_mean": overlap.map(|o| o.mean),
                    "overlap_percent_of_diameter": overlap.map(|o| o.percent_of_diameter()),
                    "overlap_largest": overlap.map(|o| o.largest),
                    "overlap_contacts": overlap.map(|o| o.contacts),
                    "seeds": seeds,
                })
            })
            .collect();
        if args.csv {
            // One value per cell: the repetitions and the seeds' pours are in the JSON.
            let rows: Vec<_> = rows
                .into_iter()
                .map(|mut r| {
                    if let Some(o) = r.as_object_mut() {
                        o.remove("runs_ms_per_step");
                        o.remove("seeds");
                    }
                    r
                })
                .collect();
            return crate::bench::print_csv(&rows);
        }
        let o = &options;
        outln!(
            "{}",
            serde_json::json!({
                "cases": rows,
                "heap": { "warmup": o.warmup, "steps": o.steps, "reps": o.reps },
                "rest": { "speed": o.rest.speed, "steps": o.rest.steps, "max_steps": o.rest.max_steps },
            })
        );
        return Ok(ExitCode::SUCCESS);
    }
    outln!(
        "{:<10} {:<8} {:<21} {:>7} {:>7} {:>10} {:>10} {:>7} {:>8} {:>8} {:>9} {:>7} {:>8}",
        "scene",
        "shapes",
        "engine",
        "threads",
        "grains",
        "ms/step",
        "seconds",
        "steps",
        "at rest",
        "x box2d",
        "overlap",
        "% diam",
        "largest"
    );
    let cell = |v: Option<String>| v.unwrap_or_else(|| "-".into());
    for c in &cases {
        let (ms, seconds, steps, rest, overlap) = match &c.result {
            Measured::Heap(h) => (
                Some(format!("{:.3}", h.ms_per_step)),
                None,
                None,
                None,
                None,
            ),
            Measured::Pour(p) => (
                None,
                Some(format!("{:.2}", p.seconds)),
                Some(p.steps.to_string()),
                Some(if p.at_rest { "yes" } else { "no" }.to_string()),
                p.overlap,
            ),
        };
        outln!(
            "{:<10} {:<8} {:<21} {:>7} {:>7} {:>10} {:>10} {:>7} {:>8} {:>8} {:>9} {:>7} {:>8}",
            c.scene.name(),
            c.shapes.name(),
            c.engine.name(),
            c.threads,
            c.grains,
            cell(ms),
            cell(seconds),
            cell(steps),
            cell(rest),
            cell(c.x_box2d.map(|x| format!("{x:.2}"))),
            cell(overlap.map(|o| format!("{:.5}", o.mean))),
            cell(overlap.map(|o| format!("{:.3}%", o.percent_of_diameter()))),
            cell(overlap.map(|o| format!("{:.4}", o.largest)))
        );
    }
    let o = &options;
    if o.scenes.contains(&SceneKind::Heap) {
        outln!(
            "heap: {} untimed steps, then the median of {} repetitions of {} steps, every grain \
             awake",
            o.warmup,
            o.reps,
            o.steps
        );
    }
    // The pours' engines alone, per step, and the harness's own work on a line of its own.
    let pours: Vec<_> = cases
        .iter()
        .filter_map(|c| match &c.result {
            Measured::Pour(p) => Some((c, p)),
            Measured::Heap(_) => None,
        })
        .collect();
    if !pours.is_empty() {
        outln!();
        outln!(
            "{:<10} {:<8} {:<21} {:>7} {:>15} {:>16} {:>15}",
            "scene",
            "shapes",
            "engine",
            "threads",
            "engine ms/step",
            "harness ms/step",
            "engine x box2d"
        );
        let per_step =
            |p: &supergrain_peers::run::PourTiming| p.engine_seconds * 1e3 / p.steps.max(1) as f64;
        for (c, p) in &pours {
            let box2d = pours.iter().find(|(b, _)| {
                b.engine == Engine::Box2d
                    && b.scene == c.scene
                    && b.shapes == c.shapes
                    && b.threads == c.threads
            });
            outln!(
                "{:<10} {:<8} {:<21} {:>7} {:>15.3} {:>16.3} {:>15}",
                c.scene.name(),
                c.shapes.name(),
                c.engine.name(),
                c.threads,
                per_step(p),
                (p.seconds - p.engine_seconds) * 1e3 / p.steps.max(1) as f64,
                box2d.map_or("-".to_string(), |(_, b)| format!(
                    "{:.2}",
                    per_step(p) / per_step(b)
                ))
            );
        }
        outln!(
            "engine: the time inside the engine's step calls alone (supergrain's own spawner is \
             part of its step); harness: the rest of the pour loop (the peers' spawner, its copies \
             of every grain and overlap tests, the fastest-grain query for the rest test)"
        );
    }
    if o.scenes.iter().any(|&s| s != SceneKind::Heap) {
        outln!(
            "pours: wall time until every grain is in and none faster than {} for {} steps (at \
             most {} steps){}",
            o.rest.speed,
            o.rest.steps,
            o.rest.max_steps,
            if o.seeds.is_empty() {
                "; the scene's own seed".to_string()
            } else {
                format!(
                    "; the median of seeds 1 to {} (each seed's in --json)",
                    o.seeds.len()
                )
            }
        );
        if cases
            .iter()
            .any(|c| matches!(&c.result, Measured::Pour(p) if p.overlap.is_some()))
        {
            outln!(
                "overlap: where the pour ended, the mean of every overlap of two disks (r_a + r_b \
                 - |c_a - c_b| > 0) or of a disk and a wall or the floor, exact disk geometry on \
                 the grains' poses, the same code for every engine; % diam: of the grains' mean \
                 diameter; largest: the deepest{}",
                if o.engines.contains(&Engine::SoftStiff) {
                    format!(
                        "; {}: max_overlap = {} in [solver]",
                        Engine::SoftStiff.name(),
                        supergrain_peers::supergrain::MAX_OVERLAP
                    )
                } else {
                    String::new()
                }
            );
        }
        // Each seed's pour, where there are several.
        for c in cases.iter().filter(|c| c.seeds.len() > 1) {
            let runs: Vec<String> = c
                .seeds
                .iter()
                .map(|(seed, t)| {
                    format!(
                        "{seed}: {:.2} s, {}{}",
                        t.seconds,
                        t.steps,
                        if t.at_rest { "" } else { " (not at rest)" }
                    )
                })
                .collect();
            outln!("  {c}: {}", runs.join("; "));
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// `--scene repose`: a table of the mean angle (and the seeds' spread) per friction and engine,
/// or every pour as JSON or CSV. One thread unless `--threads` says otherwise (the angles do not
/// depend on it: both engines give the same result on any number of threads).
#[cfg(feature = "peers")]
fn repose(
    args: &Args,
    engines: Option<Vec<supergrain_peers::bench::Engine>>,
    threads: Option<u16>,
) -> Result<ExitCode> {
    use supergrain::measure::repose::Pour;
    use supergrain_peers::repose::{self, Options};

    if let Some(bad) = args
        .frictions
        .iter()
        .flatten()
        .find(|mu| !(mu.is_finite() && **mu > 0.0))
    {
        anyhow::bail!("--frictions: expected positive numbers, got {bad}");
    }
    if !(args.rolling_resistance.is_finite() && args.rolling_resistance >= 0.0) {
        anyhow::bail!(
            "--rolling-resistance: expected a number >= 0, got {}",
            args.rolling_resistance
        );
    }
    let defaults = Options::default();
    let options = Options {
        frictions: args
            .frictions
            .clone()
            .unwrap_or_else(|| supergrain_peers::repose::FRICTIONS.to_vec()),
        rolling_resistance: args.rolling_resistance,
        seeds: (1..=args.seeds.unwrap_or(3)).collect(),
        pour: Pour {
            grains: args.grains as usize,
            rest_speed: args.rest_speed,
            rest_steps: args.rest_steps,
            max_steps: args.max_steps,
            ..defaults.pour
        },
        engines: engines.unwrap_or(defaults.engines),
        threads: threads.map_or(1, usize::from),
        overrides: overrides(args)?,
    };
    let runs = repose::runs(&options, &mut |run| eprintln!("running {run}"))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let summaries = repose::summaries(&runs);
    let pour = &options.pour;
    if args.json || args.csv {
        let rows: Vec<_> = runs
            .iter()
            .map(|r| {
                let a = r.repose.as_ref();
                serde_json::json!({
                    "engine": r.engine.name(), "friction": r.friction,
                    "rolling_resistance": options.rolling_resistance, "seed": r.seed,
                    "grains": r.grains, "degrees": a.map(|a| a.degrees()),
                    "left_degrees": a.map(|a| a.left.degrees),
                    "right_degrees": a.map(|a| a.right.degrees),
                    "left_points": a.map(|a| a.left.points),
                    "right_points": a.map(|a| a.right.points),
                    "apex_height": a.map(|a| a.apex.y), "steps": r.steps,
                    "at_rest": r.at_rest, "seconds": r.seconds,
                })
            })
            .collect();
        if args.csv {
            return crate::bench::print_csv(&rows);
        }
        let summary: Vec<_> = summaries
            .iter()
            .map(|s| {
                serde_json::json!({
                    "engine": s.engine.name(), "friction": s.friction, "degrees": s.degrees,
                    "min": s.min, "max": s.max, "seeds": s.seeds,
                })
            })
            .collect();
        outln!(
            "{}",
            serde_json::json!({
                "runs": rows,
                "summary": summary,
                "pour": {
                    "grains": pour.grains, "radius": pour.radius, "source": pour.source,
                    "gap": pour.gap, "interval": pour.interval, "half_width": pour.half_width,
                    "rolling_resistance": options.rolling_resistance,
                    "rest": { "speed": pour.rest_speed, "steps": pour.rest_steps, "max_steps": pour.max_steps },
                },
            })
        );
        return Ok(ExitCode::SUCCESS);
    }
    out!("{:>6}", "mu");
    for e in &options.engines {
        out!(" {:>24}", e.name());
    }
    outln!();
    for &mu in &options.frictions {
        out!("{mu:>6}");
        for &e in &options.engines {
            let cell = summaries
                .iter()
                .find(|s| s.engine == e && s.friction == mu)
                .filter(|s| s.seeds > 0)
                .map_or("-".to_string(), |s| {
                    format!("{:.1} ({:.1}-{:.1})", s.degrees, s.min, s.max)
                });
            out!(" {cell:>24}");
        }
        outln!();
    }
    let resting = runs.iter().filter(|r| r.at_rest).count();
    outln!(
        "angle of repose in degrees: the mean over {} seeds (their range), each the mean of the \
         heap's two flanks; {} disks of radius {}-{}, rolling resistance {}, on a rough floor; \
         {resting} of {} pours at rest",
        options.seeds.len(),
        pour.grains,
        pour.radius[0],
        pour.radius[1],
        options.rolling_resistance,
        runs.len()
    );
    Ok(ExitCode::SUCCESS)
}

/// `--set`: our `[solver]` keys changed for the drum and the repose pours.
#[cfg(feature = "peers")]
fn overrides(args: &Args) -> Result<supergrain::settings::SolverTable> {
    let mut table = supergrain::settings::SolverTable::default();
    for kv in &args.set {
        let Some((key, value)) = kv.split_once('=') else {
            anyhow::bail!("--set {kv}: expected KEY=VALUE (for example --set contact_hertz=30)");
        };
        let one = supergrain::settings::SolverTable::one(key.trim(), value.trim())
            .map_err(|e| anyhow::anyhow!("--set {kv}: {e}"))?;
        table.merge(&one);
    }
    Ok(table)
}

/// `--scene drum`: the dynamic angle per rate and friction, supergrain's soft step and Box2D.
#[cfg(feature = "peers")]
fn drum(args: &Args) -> Result<ExitCode> {
    use supergrain_peers::turning::{
        DRUM_CAPSULES, DRUM_FRICTIONS, DRUM_RATES, Drum, drum_box2d, drum_supergrain,
    };
    let frictions = args.frictions.clone().unwrap_or(DRUM_FRICTIONS.to_vec());
    let rates = args.rates.clone().unwrap_or(DRUM_RATES.to_vec());
    if let Some(bad) = frictions.iter().find(|mu| !(mu.is_finite() && **mu > 0.0)) {
        anyhow::bail!("--frictions: expected positive numbers, got {bad}");
    }
    if let Some(bad) = rates.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
        anyhow::bail!("--rates: expected positive numbers of degrees per second, got {bad}");
    }
    let overrides = overrides(args)?;
    let drum = Drum::default();
    let seeds: Vec<u64> = (1..=args.seeds.unwrap_or(3)).collect();
    // Each cell the mean over the seeds (the radii's draws), with each seed's angle.
    let mut rows = Vec::new();
    for &rate in &rates {
        for &mu in &frictions {
            let (mut ours, mut theirs) = (Vec::new(), Vec::new());
            for &seed in &seeds {
                let drum = Drum { seed, ..drum };
                eprintln!("running drum at {rate} degrees/s, friction {mu}, seed {seed}");
                ours.push(
                    drum_supergrain(&drum, mu, rate, &overrides)
                        .map_err(|e| anyhow::anyhow!("{e}"))?,
                );
                theirs.push(drum_box2d(&drum, mu, rate).map_err(|e| anyhow::anyhow!("{e}"))?);
            }
            let mean = |v: &[(f64, usize)]| {
                let a: Vec<f64> = v.iter().map(|x| x.0).collect();
                (a.iter().sum::<f64>() / a.len() as f64, v[0].1, a)
            };
            rows.push((rate, mu, mean(&ours), mean(&theirs)));
        }
    }
    if args.json || args.csv {
        let rows: Vec<_> = rows
            .iter()
            .map(|(rate, mu, ours, theirs)| {
                serde_json::json!({
                    "rate": rate, "friction": mu, "supergrain_soft_degrees": ours.0,
                    "box2d_degrees": theirs.0, "samples": ours.1,
                    "supergrain_soft_seeds": ours.2, "box2d_seeds": theirs.2,
                    "seeds": seeds, "grains": drum.grains().len(),
                })
            })
            .collect();
        return print_runs(args, &rows);
    }
    outln!(
        "{:>10} {:>6} {:>16} {:>10} {:>6}",
        "deg/s",
        "mu",
        "supergrain-soft",
        "box2d-v3",
        "gap"
    );
    for (rate, mu, ours, theirs) in &rows {
        outln!(
            "{rate:>10} {mu:>6} {:>16.1} {:>10.1} {:>6.1}",
            ours.0,
            theirs.0,
            ours.0 - theirs.0
        );
    }
    outln!(
        "dynamic angle of the free surface in degrees: the mean over {} seeds of the mean of {} \
         fits (every 6 steps over {} s, after {} s); {} disks of radius {}-{} in a drum of \
         radius {} (Box2D: {} capsules around it), 60 Hz, 4 substeps",
        seeds.len(),
        rows.first().map_or(0, |r| r.2.1),
        drum.measure,
        drum.settle,
        drum.grains().len(),
        drum.grain_radius[0],
        drum.grain_radius[1],
        drum.radius,
        DRUM_CAPSULES
    );
    Ok(ExitCode::SUCCESS)
}

/// `--scene tumbler`: ms per step of Box2D's tumbler, supergrain's soft step and Box2D.
#[cfg(feature = "peers")]
fn tumbler(args: &Args, threads: Option<u16>) -> Result<ExitCode> {
    use supergrain_peers::turning::{TUMBLER_EXPONENT, tumbler_box2d, tumbler_supergrain};
    let steps = args.steps.unwrap_or(600);
    let reps = args.reps as usize;
    let threads: Vec<usize> = match threads {
        Some(t) => vec![usize::from(t)],
        None => DEFAULT_THREADS.to_vec(),
    };
    let mut rows = Vec::new();
    for &t in &threads {
        eprintln!("running tumbler supergrain-soft {t} thread(s)");
        let ours = tumbler_supergrain(t, steps, reps).map_err(|e| anyhow::anyhow!("{e}"))?;
        eprintln!("running tumbler box2d-v3 {t} thread(s)");
        let theirs = tumbler_box2d(t, steps, reps).map_err(|e| anyhow::anyhow!("{e}"))?;
        rows.push((t, ours, theirs));
    }
    if args.json || args.csv {
        let rows: Vec<_> = rows
            .iter()
            .map(|(t, ours, theirs)| {
                serde_json::json!({
                    "threads": t, "steps": steps, "grains": ours.grains,
                    "supergrain_soft_ms_per_step": ours.ms_per_step,
                    "box2d_ms_per_step": theirs.ms_per_step,
                    "x_box2d": ours.ms_per_step / theirs.ms_per_step,
                    "supergrain_soft_runs": ours.runs, "box2d_runs": theirs.runs,
                })
            })
            .collect();
        return print_runs(args, &rows);
    }
    outln!(
        "{:>8} {:>22} {:>16} {:>8}",
        "threads",
        "supergrain-soft ms",
        "box2d-v3 ms",
        "x box2d"
    );
    for (t, ours, theirs) in &rows {
        outln!(
            "{t:>8} {:>22.3} {:>16.3} {:>8.2}",
            ours.ms_per_step,
            theirs.ms_per_step,
            ours.ms_per_step / theirs.ms_per_step
        );
    }
    outln!(
        "ms per step over {steps} steps from the start, median of {reps}; 2,025 squares of side \
         0.25 (supergrain: superellipses of exponent {TUMBLER_EXPONENT}), a box 19 wide inside \
         turning at 25 degrees per second, 60 Hz, 4 substeps"
    );
    Ok(ExitCode::SUCCESS)
}

/// `--csv` or `--json` of a drum's or a tumbler's rows: CSV, or `{"runs": [...]}`.
#[cfg(feature = "peers")]
fn print_runs(args: &Args, rows: &[serde_json::Value]) -> Result<ExitCode> {
    if args.csv {
        return crate::bench::print_csv(rows);
    }
    outln!("{}", serde_json::json!({ "runs": rows }));
    Ok(ExitCode::SUCCESS)
}

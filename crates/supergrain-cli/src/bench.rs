//! `supergrain bench`: the project's own benchmarks, printed as a table or JSON.

use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use supergrain::bench::contact_cases;
use supergrain::subdivision::{MAX_DEPTH, Precision};

#[derive(Subcommand)]
pub enum Bench {
    /// Narrow phase: ns per near-touching pair (centres at the touching distance x (1 +- 2%))
    /// for circles, ellipses, exponent-4 shapes, mixed exponents in [0.5, 4] and stars (exponents
    /// in [0.25, 0.9]), by the certified path and by the quadtree alone, and the
    /// centre-distance test for circles as the floor, all in one run.
    Contact(ContactArgs),
    /// Whole simulation: the paper's four scenes through the interval narrow phase and the
    /// circles through the centre-distance test (the paper's comparison), in one run, each the
    /// fastest of --runs rounds; the ratio column is each time over the analytic circles'.
    Presets(PresetArgs),
    /// Rendering: a frame of the 1,000-grain example (its grains laid out in rows) by the
    /// paper's interval quadtree renderer and by tiny-skia filling 64-gons, interleaved in one
    /// run; the ratio column is each time over the prebuilt polygon fill's.
    Render(RenderArgs),
    /// Scaling: a step of the 1,000-grain pour's settled heap (docs/bench/pour-1000-rest.json)
    /// tiled side by side to 1,000, 10,000 and 100,000 grains, every grain awake and sleeping
    /// off, with the grid broad phase and (up to --all-pairs-max grains) all pairs; the first
    /// steps untimed, then the median step. Reports the process's peak memory at the end.
    Scaling(ScalingArgs),
    /// Peers: the same scenes through supergrain, Box2D v3 and rapier2d, modelled on Box2D's
    /// benchmark app: the settled 1,000-grain heap with every grain awake (ms per step), the
    /// 1,000- and 10,000-grain pours until rest (wall time, steps); circles alone and the mix
    /// (rice as capsules, blocks as rounded boxes for the peers); each against Box2D. Needs the
    /// `peers` feature (cargo run --release -p supergrain-cli --features peers -- bench peers).
    /// Runs one and two threads, or the global --threads alone.
    Peers(crate::peers::Args),
}

#[derive(Parser)]
pub struct ScalingArgs {
    /// Copies of the heap, side by side (1,000 grains each).
    #[arg(long, value_delimiter = ',', default_value = "1,10,100")]
    copies: Vec<usize>,
    /// Untimed steps first.
    #[arg(long, default_value_t = 2)]
    warmup: usize,
    /// Timed steps; the median is reported.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..))]
    steps: u64,
    /// Thread counts for the strip-parallel runs (each scene also runs in the paper's order on
    /// one thread); default: 1 and every core. (Not `--threads`: that is the command's global
    /// option, and a second one on the subcommand made clap panic.)
    #[arg(long, value_name = "N,N", value_delimiter = ',')]
    thread_counts: Vec<usize>,
    /// The largest scene also run with all pairs (their cost grows with the square).
    #[arg(long, default_value_t = 10_000)]
    all_pairs_max: usize,
    /// Print {"cases": [...], "peak_rss_kib"} instead of a table.
    #[arg(long)]
    json: bool,
    /// Print CSV instead of a table: a header, then one row per case.
    #[arg(long, conflicts_with = "json")]
    csv: bool,
}

/// The settled 1,000-grain pour, built in so the benchmark runs from anywhere.
const POUR_1000_REST: &str = include_str!("../../../docs/bench/pour-1000-rest.json");

/// The process's peak resident memory in KiB (Linux), if known.
fn peak_rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn scaling(args: ScalingArgs) -> Result<ExitCode> {
    use supergrain::broad_phase::Kind;
    let dump: supergrain::io::Dump =
        serde_json::from_str(POUR_1000_REST).context("the built-in settled heap")?;
    let heap = dump
        .to_world()
        .map_err(|e| anyhow::anyhow!("the built-in settled heap: {e}"))?;
    let threads = if args.thread_counts.is_empty() {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        if cores > 1 { vec![1, cores] } else { vec![1] }
    } else {
        args.thread_counts.clone()
    };
    if threads.contains(&0) {
        anyhow::bail!("--thread-counts: a thread count must be at least 1");
    }
    let mut cases = Vec::new();
    for &n in &args.copies {
        let mut kinds = vec![Kind::Grid];
        if n * heap.bodies.len() <= args.all_pairs_max {
            kinds.push(Kind::AllPairs);
        }
        cases.extend(supergrain::bench::scaling_cases(
            &heap,
            &[n],
            &kinds,
            &threads,
            args.warmup,
            args.steps as usize,
        ));
    }
    let peak = peak_rss_kib();
    if args.json || args.csv {
        let cases: Vec<_> = cases
            .iter()
            .map(|c| {
                serde_json::json!({
                    "grains": c.grains, "broad_phase": c.broad_phase, "threads": c.threads,
                    "strips": c.strips, "ms_per_step": c.ms_per_step,
                    "us_per_grain_step": c.us_per_grain_step, "tests_per_step": c.tests_per_step,
                    "peak_rss_kib": peak,
                })
            })
            .collect();
        if args.csv {
            return print_csv(&cases);
        }
        outln!(
            "{}",
            serde_json::json!({ "cases": cases, "peak_rss_kib": peak })
        );
        return Ok(ExitCode::SUCCESS);
    }
    // Each case against the smallest scene run the same way.
    let base = |c: &supergrain::bench::ScalingResult| {
        cases
            .iter()
            .find(|b| {
                b.broad_phase == c.broad_phase
                    && b.threads == c.threads
                    && (b.strips == 0) == (c.strips == 0)
            })
            .map_or(f64::NAN, |b| c.us_per_grain_step / b.us_per_grain_step)
    };
    outln!(
        "{:>8} {:<10} {:>7} {:>7} {:>12} {:>16} {:>14} {:>10}",
        "grains",
        "broad",
        "strips",
        "threads",
        "ms/step",
        "us/grain-step",
        "tests/step",
        "x smallest"
    );
    for c in &cases {
        outln!(
            "{:>8} {:<10} {:>7} {:>7} {:>12.1} {:>16.2} {:>14.0} {:>10.2}",
            c.grains,
            c.broad_phase,
            c.strips,
            c.threads,
            c.ms_per_step,
            c.us_per_grain_step,
            c.tests_per_step,
            base(c)
        );
    }
    if let Some(kib) = peak {
        let grains = cases.iter().map(|c| c.grains).max().unwrap_or(1);
        outln!(
            "peak memory {:.1} MiB, {:.0} bytes per grain of the largest scene",
            kib as f64 / 1024.0,
            kib as f64 * 1024.0 / grains as f64
        );
    }
    Ok(ExitCode::SUCCESS)
}

#[derive(Parser)]
pub struct RenderArgs {
    /// Frame width in pixels (the height follows the box).
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(16..=8192))]
    width: u32,
    /// Timed frames per renderer; the median is reported (at least 1).
    #[arg(long, default_value_t = 15, value_parser = at_least_one)]
    reps: usize,
    /// Print {"cases": [{"name", "ms"}]} instead of a table.
    #[arg(long)]
    json: bool,
    /// Print CSV instead of a table: a header, then one row per case.
    #[arg(long, conflicts_with = "json")]
    csv: bool,
}

/// The 1,000-grain example scene, built in so the benchmark runs from anywhere.
const POUR_1000: &str = include_str!("../../../examples/scenes/pour-1000.toml");

fn render(args: RenderArgs) -> Result<ExitCode> {
    let scene = supergrain::world::Scene::from_toml(POUR_1000)
        .map_err(|e| anyhow::anyhow!("the built-in scene: {e}"))?;
    let world = supergrain::bench::laid_out(&scene);
    let cases = supergrain::bench::render_cases(&world, args.width, args.reps);
    if args.json || args.csv {
        let cases: Vec<_> = cases
            .iter()
            .map(|c| serde_json::json!({ "name": c.name, "ms": c.ms }))
            .collect();
        if args.csv {
            return print_csv(&cases);
        }
        outln!(
            "{}",
            serde_json::json!({ "grains": world.bodies.len(), "width": args.width, "cases": cases })
        );
        return Ok(ExitCode::SUCCESS);
    }
    let floor = cases.last().map_or(f64::NAN, |c| c.ms);
    outln!(
        "{} grains, {} px wide, median of {} frames",
        world.bodies.len(),
        args.width,
        args.reps
    );
    outln!("{:<36} {:>10} {:>12}", "renderer", "ms/frame", "x polygons");
    for c in &cases {
        outln!("{:<36} {:>10.2} {:>12.2}", c.name, c.ms, c.ms / floor);
    }
    Ok(ExitCode::SUCCESS)
}

#[derive(Parser)]
pub struct PresetArgs {
    /// Steps per scene (the presets pour and settle in about 3000).
    #[arg(long, default_value_t = 3000)]
    steps: u64,
    /// Rounds of all five scenes in turn; each scene reports its fastest.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..))]
    runs: u64,
    /// Seed of every scene instead of each preset's own (the ratio moves with the trajectory:
    /// try a few).
    #[arg(long)]
    seed: Option<u64>,
    /// Print {"cases": [...]} instead of a table.
    #[arg(long)]
    json: bool,
    /// Print CSV instead of a table: a header, then one row per case.
    #[arg(long, conflicts_with = "json")]
    csv: bool,
}

#[derive(Parser)]
pub struct ContactArgs {
    /// Pairs per shape class (1 to 1,000,000).
    #[arg(long, default_value_t = 1000, value_parser = pair_count)]
    pairs: usize,
    /// Timed passes over the pairs; the median is reported (at least 1).
    #[arg(long, default_value_t = 15, value_parser = at_least_one)]
    reps: usize,
    /// Quadtree depth.
    #[arg(long, default_value_t = 7, value_parser = clap::value_parser!(u32).range(0..=i64::from(MAX_DEPTH)))]
    depth: u32,
    /// Seed of the random pairs.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Print {"cases": [{"name", "ns_per_pair", "pairs", ...}]} instead of a table.
    #[arg(long)]
    json: bool,
    /// Print CSV instead of a table: a header, then one row per case.
    #[arg(long, conflicts_with = "json")]
    csv: bool,
}

/// `threads`: the command's global `--threads`, if given.
pub fn run(b: Bench, threads: Option<u16>) -> Result<ExitCode> {
    match b {
        Bench::Contact(args) => contact(args),
        Bench::Presets(args) => presets(args),
        Bench::Render(args) => render(args),
        Bench::Scaling(args) => scaling(args),
        Bench::Peers(args) => crate::peers::run(args, threads),
    }
}

fn presets(args: PresetArgs) -> Result<ExitCode> {
    let cases = supergrain::bench::preset_cases(args.steps, args.runs as usize, args.seed);
    if args.json || args.csv {
        let cases: Vec<_> = cases
            .iter()
            .map(|c| {
                serde_json::json!({
                    "name": c.name, "steps": c.steps, "grains": c.grains, "seconds": c.seconds,
                    "steps_per_second": c.steps_per_second, "contacts_per_step": c.contacts_per_step,
                })
            })
            .collect();
        if args.csv {
            return print_csv(&cases);
        }
        outln!("{}", serde_json::json!({ "cases": cases }));
        return Ok(ExitCode::SUCCESS);
    }
    let floor = cases.last().map_or(f64::NAN, |c| c.seconds);
    outln!(
        "{:<28} {:>7} {:>7} {:>10} {:>10} {:>14} {:>10}",
        "scene",
        "grains",
        "steps",
        "seconds",
        "steps/s",
        "contacts/step",
        "x analytic"
    );
    for c in &cases {
        outln!(
            "{:<28} {:>7} {:>7} {:>10.2} {:>10.1} {:>14.1} {:>10.1}",
            c.name,
            c.grains,
            c.steps,
            c.seconds,
            c.steps_per_second,
            c.contacts_per_step,
            c.seconds / floor
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn contact(args: ContactArgs) -> Result<ExitCode> {
    let precision = Precision::new(args.depth, 0.0).context("invalid --depth")?;
    let cases = contact_cases(args.pairs, args.reps, &precision, args.seed);
    if args.json || args.csv {
        let cases: Vec<_> = cases
            .iter()
            .map(|c| {
                serde_json::json!({
                    "name": c.name,
                    "ns_per_pair": c.ns_per_pair,
                    "pairs": c.pairs,
                    "overlap_fraction": c.overlap_fraction,
                    "cells_per_pair": c.cells_per_pair,
                })
            })
            .collect();
        if args.csv {
            return print_csv(&cases);
        }
        outln!("{}", serde_json::json!({ "cases": cases }));
    } else {
        let floor = cases.last().map_or(f64::NAN, |c| c.ns_per_pair);
        outln!(
            "{:<38} {:>12} {:>9} {:>8} {:>10} {:>10}",
            "case",
            "ns/pair",
            "x floor",
            "pairs",
            "overlap",
            "cells"
        );
        for c in &cases {
            outln!(
                "{:<38} {:>12.1} {:>9.1} {:>8} {:>9.0}% {:>10.1}",
                c.name,
                c.ns_per_pair,
                c.ns_per_pair / floor,
                c.pairs,
                100.0 * c.overlap_fraction,
                c.cells_per_pair
            );
        }
        outln!(
            "(median of {} timed passes after one untimed pass)",
            args.reps
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The cases as CSV on standard output: the first case's fields (alphabetical) as the header,
/// then one row per case; names with commas are quoted.
pub(crate) fn print_csv(cases: &[serde_json::Value]) -> Result<ExitCode> {
    let mut out = csv::Writer::from_writer(std::io::stdout().lock());
    let keys: Vec<String> = cases
        .first()
        .and_then(|c| c.as_object())
        .map(|o| o.keys().cloned().collect())
        .unwrap_or_default();
    out.write_record(&keys)
        .context("cannot write to standard output")?;
    for c in cases {
        let row = keys.iter().map(|k| match &c[k] {
            serde_json::Value::String(s) => s.clone(),
            serde_json::Value::Null => String::new(),
            v => v.to_string(),
        });
        out.write_record(row)
            .context("cannot write to standard output")?;
    }
    out.flush().context("cannot write to standard output")?;
    Ok(ExitCode::SUCCESS)
}

/// A count of at least 1: a timing over no pair or no pass means nothing.
fn at_least_one(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("expected a whole number >= 1, got {s}")),
    }
}

/// The most pairs per class `bench contact` holds: a million take some 250 MB, and a pass
/// over them by the quadtree alone a minute or more.
const MAX_PAIRS: usize = 1_000_000;

/// A pair count for `bench contact`: at least 1, at most [`MAX_PAIRS`] (4,000,000,000 asked for
/// more memory than there is, and panicked).
fn pair_count(s: &str) -> Result<usize, String> {
    match at_least_one(s)? {
        n if n <= MAX_PAIRS => Ok(n),
        _ => Err(format!(
            "expected a whole number from 1 to {MAX_PAIRS} (a million pairs a class take some \
             250 MB, and a pass over them by the quadtree a minute or more), got {s}"
        )),
    }
}

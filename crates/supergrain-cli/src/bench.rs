//! `supergrain bench`: the project's own benchmarks, printed as a table or JSON.

use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use supergrain::bench::contact_cases;
use supergrain::subdivision::{MAX_DEPTH, Precision};

#[derive(Subcommand)]
pub enum Bench {
    /// Narrow phase: ns per near-touching pair (centres at the touching distance x (1 +- 2%))
    /// for circles, ellipses, exponent-4 shapes and mixed exponents in [0.5, 4], and the
    /// centre-distance test for circles as the floor, all in one run.
    Contact(ContactArgs),
    /// Whole simulation: the paper's four scenes through the interval narrow phase and the
    /// circles through the centre-distance test (the paper's comparison), in one run; the
    /// ratio column is each run's time over the analytic circles'.
    Presets(PresetArgs),
    /// Rendering: a frame of the 1,000-grain example (its grains laid out in rows) by the
    /// paper's interval quadtree renderer and by tiny-skia filling 64-gons, interleaved in one
    /// run; the ratio column is each time over the prebuilt polygon fill's.
    Render(RenderArgs),
}

#[derive(Parser)]
pub struct RenderArgs {
    /// Frame width in pixels (the height follows the box).
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(16..=8192))]
    width: u32,
    /// Timed frames per renderer; the median is reported.
    #[arg(long, default_value_t = 15)]
    reps: usize,
    /// Print {"cases": [{"name", "ms"}]} instead of a table.
    #[arg(long)]
    json: bool,
}

/// The 1,000-grain example scene, built in so the benchmark runs from anywhere.
const POUR_1000: &str = include_str!("../../../examples/scenes/pour-1000.toml");

fn render(args: RenderArgs) -> Result<ExitCode> {
    let scene = supergrain::world::Scene::from_toml(POUR_1000)
        .map_err(|e| anyhow::anyhow!("the built-in scene: {e}"))?;
    let world = supergrain::bench::laid_out(&scene);
    let cases = supergrain::bench::render_cases(&world, args.width, args.reps);
    if args.json {
        let cases: Vec<_> = cases
            .iter()
            .map(|c| serde_json::json!({ "name": c.name, "ms": c.ms }))
            .collect();
        println!(
            "{}",
            serde_json::json!({ "grains": world.bodies.len(), "width": args.width, "cases": cases })
        );
        return Ok(ExitCode::SUCCESS);
    }
    let floor = cases.last().map_or(f64::NAN, |c| c.ms);
    println!(
        "{} grains, {} px wide, median of {} frames",
        world.bodies.len(),
        args.width,
        args.reps
    );
    println!("{:<36} {:>10} {:>12}", "renderer", "ms/frame", "x polygons");
    for c in &cases {
        println!("{:<36} {:>10.2} {:>12.2}", c.name, c.ms, c.ms / floor);
    }
    Ok(ExitCode::SUCCESS)
}

#[derive(Parser)]
pub struct PresetArgs {
    /// Steps per scene (the presets pour and settle in about 3000).
    #[arg(long, default_value_t = 3000)]
    steps: u64,
    /// Print {"cases": [...]} instead of a table.
    #[arg(long)]
    json: bool,
}

#[derive(Parser)]
pub struct ContactArgs {
    /// Pairs per shape class.
    #[arg(long, default_value_t = 1000)]
    pairs: usize,
    /// Timed passes over the pairs; the median is reported.
    #[arg(long, default_value_t = 15)]
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
}

pub fn run(b: Bench) -> Result<ExitCode> {
    match b {
        Bench::Contact(args) => contact(args),
        Bench::Presets(args) => presets(args),
        Bench::Render(args) => render(args),
    }
}

fn presets(args: PresetArgs) -> Result<ExitCode> {
    let cases = supergrain::bench::preset_cases(args.steps);
    if args.json {
        let cases: Vec<_> = cases
            .iter()
            .map(|c| {
                serde_json::json!({
                    "name": c.name, "steps": c.steps, "grains": c.grains, "seconds": c.seconds,
                    "steps_per_second": c.steps_per_second, "contacts_per_step": c.contacts_per_step,
                })
            })
            .collect();
        println!("{}", serde_json::json!({ "cases": cases }));
        return Ok(ExitCode::SUCCESS);
    }
    let floor = cases.last().map_or(f64::NAN, |c| c.seconds);
    println!(
        "{:<28} {:>7} {:>7} {:>10} {:>10} {:>14} {:>10}",
        "scene", "grains", "steps", "seconds", "steps/s", "contacts/step", "x analytic"
    );
    for c in &cases {
        println!(
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
    if args.json {
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
        println!("{}", serde_json::json!({ "cases": cases }));
    } else {
        let floor = cases.last().map_or(f64::NAN, |c| c.ns_per_pair);
        println!(
            "{:<38} {:>12} {:>9} {:>8} {:>10} {:>10}",
            "case", "ns/pair", "x floor", "pairs", "overlap", "cells"
        );
        for c in &cases {
            println!(
                "{:<38} {:>12.1} {:>9.1} {:>8} {:>9.0}% {:>10.1}",
                c.name,
                c.ns_per_pair,
                c.ns_per_pair / floor,
                c.pairs,
                100.0 * c.overlap_fraction,
                c.cells_per_pair
            );
        }
        println!(
            "(median of {} timed passes after one untimed pass)",
            args.reps
        );
    }
    Ok(ExitCode::SUCCESS)
}

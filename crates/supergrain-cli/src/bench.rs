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

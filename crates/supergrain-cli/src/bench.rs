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
    }
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

//! The `supergrain` command: a thin layer over the library. It parses, reports errors with
//! context, and writes output atomically; the physics lives in the library.

mod bench;
mod contact;
mod figures;
mod output;
mod peers;
mod picture;
mod render;
mod run;
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "supergrain",
    version,
    about = "Granular simulation of superellipses with certified collision detection",
    long_about = "Granular simulation of superellipses with certified collision detection.\n\n\
        Collision tests use a quadtree driven by interval arithmetic (Figueiredo & Celes): an \
        overlap is reported only when a point is proven inside both shapes."
)]
struct Cli {
    /// Threads for the simulation (default: every core, or RAYON_NUM_THREADS). Results are the
    /// same bit for bit whatever the number: a wide box is cut into strips, and strips far
    /// enough apart are projected at once.
    #[arg(long, global = true, value_parser = clap::value_parser!(u16).range(1..))]
    threads: Option<u16>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Pour grains into the box: a scene file, one of the paper's presets, or a dump to resume.
    Run(run::Args),
    /// Draw a state written by `run --dump` as a PNG, with optional overlays.
    Render(render::Args),
    /// Write every figure of the paper (2-13), redrawn, with captions, into a folder.
    Figures(figures::Args),
    /// Test two superellipses for contact: deepest points and penetration vectors.
    Contact(contact::Args),
    /// Watch a scene live in a window: play, pause, step, tune the solver, drop and drag grains,
    /// and explore a collision test (needs a display; see the README for the browser version).
    View(view::Args),
    /// Measure performance and print a table (or JSON).
    #[command(subcommand)]
    Bench(bench::Bench),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Some(n) = cli.threads
        && let Err(e) = rayon::ThreadPoolBuilder::new()
            .num_threads(usize::from(n))
            .build_global()
    {
        eprintln!("error: --threads {n}: {e}");
        return ExitCode::FAILURE;
    }
    let result = match cli.command {
        Command::Run(args) => run::run(args),
        Command::Render(args) => render::run(args),
        Command::Figures(args) => figures::run(args),
        Command::Contact(args) => contact::run(args),
        Command::View(args) => view::run(args),
        Command::Bench(b) => bench::run(b, cli.threads),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

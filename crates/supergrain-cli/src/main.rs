//! The `supergrain` command: a thin layer over the library. It parses, reports errors with
//! context, and writes output atomically; the physics lives in the library.

/// `println!` that returns its error instead of panicking (standard output closed by a reader
/// that has read enough, `supergrain bench contact --csv | head -4`): the command then ends
/// quietly ([`is_broken_pipe`]).
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)
            .map_err(|e| anyhow::Error::new(e).context("cannot write to standard output"))?
    }};
}

/// `print!`, as [`outln!`] (used by `bench peers`, built with the `peers` feature).
#[cfg_attr(not(feature = "peers"), allow(unused_macros))]
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        write!(std::io::stdout().lock(), $($arg)*)
            .map_err(|e| anyhow::Error::new(e).context("cannot write to standard output"))?
    }};
}

mod bench;
mod contact;
mod figures;
mod output;
mod peers;
mod picture;
mod plot;
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
    /// Threads for stepping a simulation: `run`, `view` and `bench` (default: every core, or
    /// RAYON_NUM_THREADS); `contact`, `render` and `figures` work on one thread whatever the
    /// number. A run's results are the same bit for bit on any number of threads.
    #[arg(long, global = true, value_parser = clap::value_parser!(u16).range(1..))]
    threads: Option<u16>,
    #[command(subcommand)]
    command: Command,
}

// Parsed once per process: the size of `run`'s many options costs nothing.
#[allow(clippy::large_enum_variant)]
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
    // The main thread is one of the pool's: a parallel pass started from it runs there too
    // instead of being handed to a worker while it waits. On one thread the handing over was a
    // context switch per pass: a 1,000-disk pour ran 1.5 times as long, a ninth of it in system
    // calls (docs/performance.md).
    let mut pool = rayon::ThreadPoolBuilder::new().use_current_thread();
    if let Some(n) = cli.threads {
        pool = pool.num_threads(usize::from(n));
    }
    if let Err(e) = pool.build_global() {
        match cli.threads {
            Some(n) => eprintln!("error: --threads {n}: {e}"),
            None => eprintln!("error: cannot start the worker threads: {e}"),
        }
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
        // The reader of standard output has gone (`| head`): what it read is whole, and the
        // shell's pipeline carries on. Quietly, as `cat` ends by SIGPIPE, with exit code 0.
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// Whether `e` comes from writing to a pipe whose reader has gone.
pub(crate) fn is_broken_pipe(e: &anyhow::Error) -> bool {
    use std::io::ErrorKind::BrokenPipe;
    e.chain().any(|cause| {
        cause
            .downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == BrokenPipe)
            || cause
                .downcast_ref::<serde_json::Error>()
                .is_some_and(|j| j.io_error_kind() == Some(BrokenPipe))
            || cause.downcast_ref::<csv::Error>().is_some_and(
                |c| matches!(c.kind(), csv::ErrorKind::Io(io) if io.kind() == BrokenPipe),
            )
    })
}

/// A number for a message, as the user would write it: the shortest form that reads back as
/// the same number, in exponent form when large or small (`1e308`, not 309 digits).
pub(crate) fn number(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e9).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

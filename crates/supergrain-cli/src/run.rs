//! `supergrain run`: pour grains into the box from a scene file, a preset or a dump.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::{Parser, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use supergrain::contact::NarrowPhase;
use supergrain::io::{
    Dump, FORCES_HEADER, GifWriter, trajectory_header, write_forces_frame, write_trajectory_frame,
    write_vtk_frame,
};
use supergrain::measure::series::{Series, SeriesKind};
use supergrain::render::{Style, render_world, world_region, world_svg};
use supergrain::settings::{Model, Settings, SolverTable};
use supergrain::world::checks::short;
use supergrain::world::{PRESETS, Rest, RestCounter, Scene, World};

use crate::output::{Folder, Output, Plans, Target};
use crate::picture::{PictureArgs, check_size, save_frame, save_png};

/// A measure from the command line (`--measure`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum MeasureArg {
    /// Per sink: the grains and mass taken so far, the grains in the box and all that appeared.
    Discharge,
    /// The grains' kinetic energy, translational and rotational.
    Energy,
    /// The angle of one straight free surface (a drum's): a line through the highest grain of
    /// each bin across the middle 60% of the grains' width.
    Surface,
}

#[derive(Parser)]
#[command(after_help = "\
Examples:
  supergrain run --preset circles --dump circles.json --png circles.png
  supergrain run --preset mixed --gif mixed.gif --every 20 --width 400
  supergrain run examples/scenes/mixed.toml --steps 2000 --trajectory mixed.csv --every 20
  supergrain run --resume circles.json --steps 1000 --dump circles-later.json
  supergrain run --preset circles --narrow-phase analytic
  supergrain run examples/scenes/pour-1000.toml --until-rest --steps 20000 --svg pour.svg

The presets are the paper's four scenes (Figs. 10-13): circles, ellipses, squircles, mixed.
A scene's [spawn] rule says what happens to a grain whose place is taken. \"fair\", the
default with [solver] model = \"soft\": it is tried at other places in a band under the top,
and grains appear in queue order, so a mixture arrives mixed. \"queue\", the default with the
paper's model: it waits while later grains pass it, so large grains arrive last.
A progress bar shows on a terminal, elsewhere (a log file) a progress line every 30 s;\na summary is printed at the end. Ctrl-C (or SIGTERM) stops within a second, even in the\nmiddle of a slow step, and still writes every output with the last whole step (exit code\n130); a second Ctrl-C quits at once.")]
pub struct Args {
    /// A scene file (TOML; see examples/scenes/).
    #[arg(value_name = "SCENE.toml", conflicts_with_all = ["preset", "resume"])]
    scene: Option<PathBuf>,
    /// One of the paper's scenes: circles, ellipses, squircles, mixed.
    #[arg(long, value_name = "NAME", conflicts_with = "resume")]
    preset: Option<String>,
    /// Go on from a dump written by --dump.
    #[arg(long, value_name = "FILE.json")]
    resume: Option<PathBuf>,
    /// Steps to run [default: the scene's `steps`, or 1000 after --resume].
    #[arg(long)]
    steps: Option<u64>,
    /// Seed of the random draws (shapes, angles, where grains appear) [default: the scene's].
    #[arg(long, conflicts_with = "resume")]
    seed: Option<u64>,
    /// Override the scene's (or the dump's) narrow phase: interval (certified, any
    /// superellipse: Newton with a proof for convex pairs, a search of one shape's boundary for
    /// stars, the quadtree where neither proves anything), quadtree (the paper's certified
    /// quadtree alone, for every pair) or analytic (centre distance, circles only: the paper's
    /// comparison). The same as --set narrow_phase=NAME.
    #[arg(long, value_name = "NAME")]
    narrow_phase: Option<String>,
    /// Override the scene's (or the dump's) sleep radius; 0 turns sleeping off and wakes every
    /// sleeper. A radius other than the dump's starts every grain's calm count afresh. The soft
    /// model sleeps by islands (touching grains together, their forces put in equilibrium as
    /// they fall asleep); grain by grain (`sleep_islands = false`, and the paper's model) a
    /// sleeper's contacts keep the forces they had when it fell asleep, which need not balance:
    /// for `--forces` or the mean stress at equilibrium, resume the rested dump with
    /// `--sleep-radius 0` for a few hundred steps.
    #[arg(long, value_name = "R", allow_negative_numbers = true, value_parser = non_negative_number)]
    sleep_radius: Option<f64>,
    /// Soft model: override the scene's (or the dump's) `carry_reach`, how far a pair of
    /// grains may move against each other before its contact, carried from step to step, is
    /// searched afresh (default 0.0005); 0 searches every pair every step, as before contacts
    /// were carried (docs/physics.md).
    #[arg(long, value_name = "R", allow_negative_numbers = true, value_parser = non_negative_number)]
    carry_reach: Option<f64>,
    /// Override one of the scene's (or the dump's) [solver] keys, as the scene would write it
    /// (repeatable): --set contact_hertz=30 --set substeps=8 --set narrow_phase=quadtree.
    /// Checked as the scene's are; the keys are listed in the README's scene reference. Not
    /// `model` (a run's grains are built for it) nor `max_overlap` (set it in the scene).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Write the final state as JSON (restartable with --resume).
    #[arg(long, value_name = "FILE.json")]
    dump: Option<PathBuf>,
    /// Also write the --dump file every STEPS steps (replaced whole each time), so that a long
    /// run killed without Ctrl-C (a machine going down) can --resume from its last checkpoint.
    #[arg(
        long,
        value_name = "STEPS",
        requires = "dump",
        value_parser = clap::value_parser!(u64).range(1..)
    )]
    checkpoint: Option<u64>,
    /// Draw the final state as an SVG picture.
    #[arg(long, value_name = "FILE.svg")]
    svg: Option<PathBuf>,
    /// Draw the final state as a PNG (the paper's anti-aliased quadtree renderer).
    #[arg(long, value_name = "FILE.png")]
    png: Option<PathBuf>,
    /// Write an animated GIF, a frame every --gif-every steps.
    #[arg(long, value_name = "FILE.gif")]
    gif: Option<PathBuf>,
    /// Write a PNG per frame (every --frames-every steps) into DIR.
    #[arg(long, value_name = "DIR")]
    frames: Option<PathBuf>,
    /// Frames per second of the GIF, from 0.1 to 50 (a GIF's frame delay is whole hundredths
    /// of a second, and browsers play delays under 2 hundredths slowly; a rate between two
    /// delays is played at the nearest, and the run says so).
    #[arg(long, default_value_t = 25.0, allow_negative_numbers = true, value_parser = gif_fps)]
    fps: f64,
    #[command(flatten)]
    picture: PictureArgs,
    /// Write a CSV row per grain every --trajectory-every steps (model = "soft": with its
    /// material, mass and moment of inertia).
    #[arg(long, value_name = "FILE.csv")]
    trajectory: Option<PathBuf>,
    /// Write a CSV row per contact every --forces-every steps: its grains (or grain and wall),
    /// point, normal (from the first grain to the second, or out of the wall), and normal and
    /// tangential force (model = "soft" only; the tangent is the normal turned a quarter turn
    /// clockwise, (n_y, -n_x); both forces act on the second grain). With --forces the summary
    /// also gives the heap's mean stress.
    #[arg(long, value_name = "FILE.csv")]
    forces: Option<PathBuf>,
    /// Write each measure (the scene's [[measure]] tables, the dump's, and --measure) as a CSV
    /// into DIR, DIR/KIND.csv, a row every its own `every` steps: discharge (per sink: step,
    /// time, sink, grains, mass, in_box, appeared) and energy (step, time, grains,
    /// translational, rotational, total).
    #[arg(long, value_name = "DIR")]
    measures: Option<PathBuf>,
    /// Add a measure, every --every steps (repeatable): discharge (needs a [[sink]]) or energy.
    #[arg(long, value_name = "KIND")]
    measure: Vec<MeasureArg>,
    /// Write a VTK point file per frame (every --vtk-every steps) into DIR: each grain's
    /// centre, with its id, group, shape, angle and velocity as point data.
    #[arg(long, value_name = "DIR")]
    vtk: Option<PathBuf>,
    /// Stop once every grain has appeared and none has moved faster than --rest-speed for 100
    /// steps in a row; --steps is then the most it runs.
    #[arg(long)]
    until_rest: bool,
    /// Speed under which a grain counts as at rest (5% of a falling grain's terminal speed
    /// g h / delta with the paper's settings).
    #[arg(long, default_value_t = 0.05, value_name = "SPEED", allow_negative_numbers = true, value_parser = positive_number)]
    rest_speed: f64,
    /// Steps between frames of every stream: --trajectory, --forces, --vtk, --gif and
    /// --frames, unless its own interval is given.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..))]
    every: u64,
    /// Steps between rows of --trajectory [default: --every].
    #[arg(long, value_name = "STEPS", value_parser = clap::value_parser!(u64).range(1..))]
    trajectory_every: Option<u64>,
    /// Steps between rows of --forces [default: --every].
    #[arg(long, value_name = "STEPS", value_parser = clap::value_parser!(u64).range(1..))]
    forces_every: Option<u64>,
    /// Steps between files of --vtk [default: --every].
    #[arg(long, value_name = "STEPS", value_parser = clap::value_parser!(u64).range(1..))]
    vtk_every: Option<u64>,
    /// Steps between frames of --gif [default: --every].
    #[arg(long, value_name = "STEPS", value_parser = clap::value_parser!(u64).range(1..))]
    gif_every: Option<u64>,
    /// Steps between pictures of --frames [default: --every].
    #[arg(long, value_name = "STEPS", value_parser = clap::value_parser!(u64).range(1..))]
    frames_every: Option<u64>,
    /// No summary.
    #[arg(long, short)]
    quiet: bool,
}

/// The dump of `world` into `out`, finished (renamed into place).
fn write_dump(mut out: Output, world: &World) -> Result<()> {
    serde_json::to_writer(&mut out, &Dump::of(world))?;
    out.write_all(b"\n")?;
    out.finish()
}

/// The outputs that failed, each with its error: the run writes every other one, and ends in
/// error naming each.
#[derive(Default)]
struct Failures(Vec<anyhow::Error>);

impl Failures {
    /// Keeps `result`'s error, if any; whether it succeeded.
    fn keep(&mut self, result: Result<()>) -> bool {
        match result {
            Ok(()) => true,
            // A stream to standard output whose reader has read enough (`| head`): it ends,
            // quietly, and the run and the other outputs go on.
            Err(e) if crate::is_broken_pipe(&e) => false,
            Err(e) => {
                self.0.push(e);
                false
            }
        }
    }
}

pub fn run(args: Args) -> Result<ExitCode> {
    let (mut world, default_steps) = load(&args)?;
    let steps = args.steps.unwrap_or(default_steps);
    // A run that would pass step 2^53 has no exact step time past it (a dump of it could not
    // be resumed): refused before any work.
    let last = supergrain::world::checks::MAX_STEP;
    if world.step.checked_add(steps).is_none_or(|end| end > last) {
        bail!(
            "--steps {steps} from step {} goes past step {last} (2^53), beyond which step times \
             are not exact; run at most {} steps",
            world.step,
            last.saturating_sub(world.step)
        );
    }

    // Every output is planned before any work, so a bad path, or two outputs on one path, costs
    // nothing; the files written at the end are only opened then.
    let mut plans = Plans::default();
    let dump = plans.file("--dump", args.dump.as_deref())?;
    let svg = plans.file("--svg", args.svg.as_deref())?;
    let png = plans.file("--png", args.png.as_deref())?;
    let trajectory_to = plans.file("--trajectory", args.trajectory.as_deref())?;
    if args.forces.is_some() && world.settings.model != Model::Soft {
        bail!(
            "--forces needs the soft model ([solver] model = \"soft\"): the paper's projection \
             has no forces"
        );
    }
    let forces_to = plans.file("--forces", args.forces.as_deref())?;
    for m in &args.measure {
        let kind = match m {
            MeasureArg::Discharge => SeriesKind::Discharge,
            MeasureArg::Energy => SeriesKind::Energy,
            MeasureArg::Surface => SeriesKind::Surface,
        };
        if kind == SeriesKind::Discharge && world.sinks.is_empty() {
            bail!("--measure discharge needs a [[sink]] in the scene to measure");
        }
        if !world.measures.iter().any(|s| s.kind == kind) {
            world.measures.push(Series::new(kind, args.every));
        }
    }
    if args.measures.is_none() && !world.measures.is_empty() && !args.quiet {
        eprintln!(
            "note: the measures ({}) are given in the summary; --measures DIR writes them as CSV",
            world
                .measures
                .iter()
                .map(|m| m.kind.name())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let measures_dir = args
        .measures
        .as_deref()
        .map(|dir| plans.folder("--measures", dir))
        .transpose()?;
    let gif_to = plans.file("--gif", args.gif.as_deref())?;
    let vtk = args
        .vtk
        .as_deref()
        .map(|dir| plans.folder("--vtk", dir))
        .transpose()?;
    let frames = args
        .frames
        .as_deref()
        .map(|dir| plans.folder("--frames", dir))
        .transpose()?;
    // The streams are written as the run goes.
    let mut trajectory = trajectory_to.as_ref().map(Target::open).transpose()?;
    if let Some(t) = trajectory.as_mut() {
        writeln!(t, "{}", trajectory_header(&world))?;
    }
    let mut forces = forces_to.as_ref().map(Target::open).transpose()?;
    if let Some(f) = forces.as_mut() {
        writeln!(f, "{FORCES_HEADER}")?;
    }
    // Frames of an animation share one view: the box up to where grains appear. A picture too
    // large to draw is refused now, before any work (it would abort the run at its end).
    let style = Style {
        region: Some(world_region(&world)),
        ..args.picture.style()
    };
    for (flag, wanted) in [
        ("--png", png.is_some()),
        ("--gif", gif_to.is_some()),
        ("--frames", frames.is_some()),
    ] {
        if wanted {
            check_size(&world, &style, flag)?;
        }
    }
    let vtk = vtk.map(Folder::make).transpose()?;
    let frames = frames.map(Folder::make).transpose()?;
    // Each measure's CSV, its header now and a row at the start, then as it is due.
    // Each with its CSV's path and its plot's (drawn from the CSV at the end).
    let mut series: Vec<(Series, Output, PathBuf, Target)> = Vec::new();
    if let Some(dir) = measures_dir.map(Folder::make).transpose()? {
        for (k, m) in world.measures.iter().enumerate() {
            let twice = world.measures.iter().filter(|o| o.kind == m.kind).count() > 1;
            let name = if twice {
                format!("{}-{}", m.kind.name(), k + 1)
            } else {
                m.kind.name().to_string()
            };
            let csv = dir.join(format!("{name}.csv"));
            let mut out = Target::resolve(Some(&csv))?.open()?;
            writeln!(out, "{}", m.header())?;
            m.write_rows(&world, &mut out)?;
            let png = Target::resolve(Some(&dir.join(format!("{name}.png"))))?;
            series.push((*m, out, csv, png));
        }
    }
    let mut gif_out = gif_to.as_ref().map(Target::open).transpose()?;
    let mut gif = match gif_out.as_mut() {
        Some(out) => {
            let played = played_fps(args.fps);
            if (played - args.fps).abs() > 1e-9 * args.fps && !args.quiet {
                eprintln!(
                    "note: --fps {} is played at {} (a GIF's frame delay is whole hundredths of \
                     a second)",
                    crate::number(args.fps),
                    short(played)
                );
            }
            Some(GifWriter::new(out, args.fps, 10).context("cannot start the GIF")?)
        }
        None => None,
    };

    let bar = ProgressBar::new(steps).with_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} steps, {per_sec}, eta {eta} {msg}")
            .expect("a valid template"),
    );
    let log_lines = !std::io::stderr().is_terminal();
    let start = Instant::now();
    let (mut last_shown, mut last_logged) = (start, start);
    let mut contacts = 0u64;
    let rest = Rest {
        speed: args.rest_speed,
        steps: REST_STEPS,
    };
    let mut calm = RestCounter::default();
    let mut done = 0u64;
    // A stream that fails (its folder removed, a full disk) is dropped with its error; the run
    // and the other outputs go on.
    let mut failures = Failures::default();
    let (mut vtk, mut frames) = (vtk, frames);
    // Each stream's own interval.
    let every = Every {
        trajectory: args.trajectory_every.unwrap_or(args.every),
        forces: args.forces_every.unwrap_or(args.every),
        vtk: args.vtk_every.unwrap_or(args.every),
        gif: args.gif_every.unwrap_or(args.every),
        frames: args.frames_every.unwrap_or(args.every),
    };
    // Writes the frame of each stream that `due` says is due, given its interval.
    let mut frame = |world: &World,
                     trajectory: &mut Option<Output>,
                     failures: &mut Failures,
                     due: &dyn Fn(u64) -> bool| {
        if let Some(t) = trajectory.as_mut()
            && due(every.trajectory)
            && !failures.keep(
                write_trajectory_frame(world, t)
                    .with_context(|| format!("--trajectory at step {}", world.step)),
            )
        {
            *trajectory = None;
        }
        if let Some(f) = forces.as_mut()
            && due(every.forces)
            && !failures.keep(
                write_forces_frame(world, f)
                    .with_context(|| format!("--forces at step {}", world.step)),
            )
        {
            forces = None;
        }
        if let Some(dir) = &vtk
            && due(every.vtk)
            && !failures.keep(write_vtk(world, dir))
        {
            vtk = None;
        }
        if let Some(dir) = &frames
            && due(every.frames)
            && !failures.keep(save_frame(world, &style, dir))
        {
            frames = None;
        }
        if let Some(g) = gif.as_mut()
            && due(every.gif)
            && !failures.keep(
                g.push(&render_world(world, &style))
                    .with_context(|| format!("cannot write the GIF at step {}", world.step)),
            )
        {
            gif = None;
        }
    };
    frame(&world, &mut trajectory, &mut failures, &|_| true);
    let stop = stop_on_interrupt();
    let mut interrupted = false;
    // The first grain to leave the box, and the step: the run goes on, and says so.
    let mut escaped: Option<(usize, u64)> = None;
    for k in 1..=steps {
        // A stop request abandons the step under way: the world is then the last whole step's.
        let Ok(stats) = world.step_or_stop(&stop) else {
            interrupted = true;
            break;
        };
        done = k;
        if let Some(i) = world.first_not_finite() {
            bail!(
                "grain {i} left the computable range at step {}: its position is not finite \
                 (no output written from this state)",
                world.step
            );
        }
        if escaped.is_none()
            && let Some(i) = world.first_outside()
        {
            let c = world.bodies[i].center;
            eprintln!(
                "warning: grain {i} left the box at step {} (centre at ({}, {}))",
                world.step,
                short(c.x),
                short(c.y)
            );
            escaped = Some((i, world.step));
        }
        contacts += stats.contacts as u64;
        frame(&world, &mut trajectory, &mut failures, &|n| k % n == 0);
        series.retain_mut(|(m, out, _, _)| {
            !m.due(world.step)
                || failures.keep(
                    m.write_rows(&world, out)
                        .with_context(|| format!("--measures at step {}", world.step)),
                )
        });
        if let (Some(every), Some(target)) = (args.checkpoint, dump.as_ref())
            && k % every == 0
            && k < steps
            && let Err(e) = target
                .open_tagged(Some("checkpoint"))
                .and_then(|out| write_dump(out, &world))
        {
            // The run goes on: its final outputs may still be written.
            eprintln!("warning: checkpoint at step {}: {e:#}", world.step);
        }
        let fastest = world.max_speed();
        let at_rest = calm.update(&rest, world.all_spawned(), fastest);
        if k % 50 == 0 || last_shown.elapsed().as_secs_f64() >= 1.0 {
            last_shown = Instant::now();
            let state = format!(
                "{} grains, {} asleep, fastest {}",
                world.bodies.len(),
                world.asleep(),
                speed(fastest)
            );
            if !log_lines {
                bar.set_position(k);
                bar.set_message(state);
            } else if last_logged.elapsed().as_secs_f64() >= LOG_SECONDS && !args.quiet {
                // No terminal (a log file, a batch job): a line now and then instead of a bar.
                last_logged = Instant::now();
                let t = start.elapsed().as_secs_f64();
                eprintln!(
                    "step {k}/{steps} at {t:.0} s ({:.1} steps/s): {state}",
                    k as f64 / t.max(1e-9)
                );
            }
        }
        if args.until_rest && at_rest {
            break;
        }
    }
    if args.until_rest || interrupted {
        // The last state, in each stream that has not just written it.
        frame(&world, &mut trajectory, &mut failures, &|n| {
            !done.is_multiple_of(n)
        });
    }
    bar.finish_and_clear();
    let elapsed = start.elapsed().as_secs_f64();

    // Every output is written that can be, whatever happens to the others.
    if let Some(t) = trajectory {
        failures.keep(t.finish());
    }
    if let Some(f) = forces {
        failures.keep(f.finish());
    }
    for (m, mut out, csv, png) in series {
        // The last state, where its row was not just written.
        if !m.due(world.step) {
            failures.keep(m.write_rows(&world, &mut out).map_err(Into::into));
        }
        // The plot from the CSV, once the CSV is whole.
        let whole = out.finish();
        let written = whole.is_ok();
        failures.keep(whole);
        if written {
            failures.keep(
                png.open()
                    .and_then(|out| crate::plot::plot(m.kind, &csv, out)),
            );
        }
    }
    // A GIF that failed during the run is not renamed into place (dropped, its temporary goes).
    let gif_whole = gif.is_some();
    drop(gif);
    if let Some(g) = gif_out
        && gif_whole
    {
        failures.keep(g.finish());
    }
    // The dump first: it is the run's work, and a picture can still fail.
    if let Some(to) = dump {
        failures.keep(to.open().and_then(|out| write_dump(out, &world)));
    }
    if let Some(to) = png {
        failures.keep(to.open().and_then(|out| save_png(&world, &style, out)));
    }
    if let Some(to) = svg {
        failures.keep(to.open().and_then(|mut picture| {
            picture.write_all(world_svg(&world, 800).as_bytes())?;
            picture.finish()
        }));
    }
    if !args.quiet {
        eprintln!(
            "{} grains ({} still to appear), {} steps in {:.2} s: {:.1} steps/s, {:.1} contacts/step, \
             deepest remaining penetration {:.2e}, fastest grain {}",
            world.bodies.len(),
            world.pending_count(),
            done,
            elapsed,
            done as f64 / elapsed.max(1e-9),
            contacts as f64 / done.max(1) as f64,
            world.deepest_penetration(),
            speed(world.max_speed()),
        );
        for m in &world.measures {
            eprintln!("{}", m.summary(&world));
        }
        let time = world.time();
        for (k, s) in world.sinks.iter().enumerate() {
            eprintln!(
                "sink {}: {} grains have left (mass {}){}, {} per second over the run's {} s",
                k + 1,
                s.grains,
                short(s.mass),
                if s.recycle {
                    ", each put back at the top"
                } else {
                    ""
                },
                short(s.grains as f64 / time.max(f64::MIN_POSITIVE)),
                short(time),
            );
        }
        if let Some(o) = world.overlaps() {
            eprintln!(
                "overlap of the {} touching contacts: mean {:.2e} ({:.3}% of the thinner grain's \
                 thickness), largest {:.2e} ({:.2}%)",
                o.contacts,
                o.mean,
                100.0 * o.mean_relative,
                o.max,
                100.0 * o.max_relative,
            );
        }
        // The mean stress goes with the forces it sums (--forces), and only when some contact
        // carries one.
        if let Some([[sxx, sxy], [_, syy]]) = world.stress().filter(|_| {
            args.forces.is_some() && world.soft.forces.iter().any(|f| f.normal_force != 0.0)
        }) {
            eprintln!(
                "mean stress of the heap: xx {sxx:.4e}, yy {syy:.4e}, xy {sxy:.4e} (pressure \
                 {:.4e}; compression negative)",
                -(sxx + syy) / 2.0
            );
            let asleep = world.asleep();
            if asleep > 0 && world.settings.sleep_islands && args.resume.is_some() {
                eprintln!(
                    "  ({asleep} of {} grains asleep: a dump does not keep the forces of the \
                     contacts that slept through it, so the stress leaves out those that have \
                     not woken since; run from the scene, or resume with --sleep-radius 0 for a \
                     few hundred steps)",
                    world.bodies.len()
                );
            } else if asleep > 0 && !world.settings.sleep_islands {
                eprintln!(
                    "  ({asleep} of {} grains asleep, grain by grain: their contacts keep the \
                     forces they had when they fell asleep, which need not balance; for the \
                     forces at equilibrium, resume with --sleep-radius 0 for a few hundred \
                     steps, or sleep by islands: sleep_islands = true)",
                    world.bodies.len()
                );
            }
        }
        if let Some((i, at)) = escaped {
            eprintln!(
                "the run went wrong: grain {i} left the box at step {at} (a time step too long, \
                 or grains placed by hand deep in each other or in a wall)"
            );
        }
        if interrupted {
            eprintln!(
                "interrupted after step {}: the outputs hold that state (--resume a dump to go on)",
                world.step
            );
        } else if args.until_rest {
            if calm.at_rest(&rest) {
                eprintln!(
                    "at rest at step {}: no grain faster than {} for {REST_STEPS} steps",
                    world.step,
                    crate::number(args.rest_speed)
                );
            } else {
                eprintln!(
                    "not at rest after {done} steps (raise --steps to go on, or --resume a dump)"
                );
            }
        }
    }
    // Each failed output is named, the last in the error the command ends with.
    let count = failures.0.len();
    if let Some(last) = failures.0.pop() {
        for e in &failures.0 {
            eprintln!("error: {e:#}");
        }
        if count == 1 {
            return Err(last);
        }
        return Err(last.context(format!("{count} outputs not written (every other one is)")));
    }
    // The shell's code for a run stopped by SIGINT, so that scripts see it did not finish.
    Ok(if interrupted {
        ExitCode::from(130)
    } else {
        ExitCode::SUCCESS
    })
}

/// A flag raised by Ctrl-C (or SIGTERM, SIGHUP): the step under way is abandoned at once (the
/// world put back as it was before it, [`World::step_or_stop`]) and the run writes its outputs,
/// so hours of a long run are not lost and a slow step does not keep `timeout` waiting. A
/// second signal ends the process at once, removing the temporaries of unfinished outputs. Without a handler (one could not be installed) the flag simply never rises.
fn stop_on_interrupt() -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    let raised = Arc::clone(&stop);
    let installed = ctrlc::set_handler(move || {
        if raised.swap(true, Ordering::SeqCst) {
            // No destructor runs on exit: the temporaries go by hand.
            crate::output::remove_temporaries();
            std::process::exit(130);
        }
        eprintln!(
            "\nstopping: the outputs will hold the last whole step (press Ctrl-C again to quit at once)"
        );
    });
    if let Err(e) = installed {
        eprintln!("warning: Ctrl-C will end the run without writing its outputs ({e})");
    }
    stop
}

/// Seconds between two progress lines when stderr is not a terminal.
const LOG_SECONDS: f64 = 30.0;

/// Steps in a row under --rest-speed that count as rest.
const REST_STEPS: u32 = 100;

fn non_negative_number(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("expected a finite number >= 0, got {}", shown(s))),
    }
}

fn positive_number(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("expected a finite number > 0, got {}", shown(s))),
    }
}

/// A speed for the progress line and the summary: three decimals, in exponent form when huge (a
/// run gone wrong).
fn speed(x: f64) -> String {
    if x.abs() < 1e6 {
        format!("{x:.3}")
    } else {
        format!("{x:.3e}")
    }
}

/// A value the user gave, for a message: at most 40 characters of it.
fn shown(s: &str) -> String {
    match s.char_indices().nth(40) {
        Some((end, _)) => format!("{}... ({} characters)", &s[..end], s.chars().count()),
        None => s.to_string(),
    }
}

/// The slowest and fastest GIF rates: a frame delay of at most 10 s and at least 2 hundredths
/// (browsers play shorter delays at 10 frames per second).
const GIF_FPS: (f64, f64) = (0.1, 50.0);

fn gif_fps(s: &str) -> Result<f64, String> {
    match positive_number(s)? {
        v if (GIF_FPS.0..=GIF_FPS.1).contains(&v) => Ok(v),
        _ => Err(format!(
            "expected frames per second from {} to {} (a GIF's frame delay is whole hundredths \
             of a second; browsers play delays under 2 hundredths at 10 frames per second), \
             got {}",
            GIF_FPS.0,
            GIF_FPS.1,
            shown(s)
        )),
    }
}

/// The rate a GIF of `fps` plays at: its delay is whole hundredths of a second, the
/// milliseconds [`GifWriter`] asks for cut to them by the encoder.
fn played_fps(fps: f64) -> f64 {
    let ms = (1000.0 / fps).round();
    100.0 / (ms / 10.0).floor()
}

/// Each stream's interval, in steps.
#[derive(Clone, Copy)]
struct Every {
    trajectory: u64,
    forces: u64,
    vtk: u64,
    gif: u64,
    frames: u64,
}

/// The [solver] keys the command line overrides: `--set`, and the flags that are short for one
/// key (`--narrow-phase`, `--sleep-radius`, `--carry-reach`), each checked as a scene's.
fn overrides(args: &Args) -> Result<SolverTable> {
    let mut table = SolverTable::default();
    for kv in &args.set {
        let Some((key, value)) = kv.split_once('=') else {
            bail!("--set {kv}: expected KEY=VALUE (for example --set contact_hertz=30)");
        };
        let t = SolverTable::one(key.trim(), value.trim())
            .map_err(|e| anyhow::anyhow!("--set {kv}: {e}"))?;
        table.merge(&t);
    }
    // `+ 0.0`: -0 is 0 (and is written so in dumps).
    let flags = [
        (
            "--narrow-phase",
            "narrow_phase",
            args.narrow_phase.as_ref().map(|n| format!("{n:?}")),
        ),
        (
            "--sleep-radius",
            "sleep_radius",
            args.sleep_radius.map(|r| (r + 0.0).to_string()),
        ),
        (
            "--carry-reach",
            "carry_reach",
            args.carry_reach.map(|r| (r + 0.0).to_string()),
        ),
    ];
    for (flag, key, value) in flags {
        let Some(value) = value else { continue };
        // A key given by `--set` and by its own flag: which was meant is not clear.
        if table.given(key) {
            bail!("{flag} and --set {key}=... both set `{key}`: give one");
        }
        let t = SolverTable::one(key, &value).map_err(|e| anyhow::anyhow!("{flag}: {e}"))?;
        table.merge(&t);
    }
    Ok(table)
}

fn load(args: &Args) -> Result<(World, u64)> {
    let table = overrides(args)?;
    // The soft step's keys mean nothing to the paper's projection: refused, as a flag would be.
    let soft_only = |model: Model| match table.soft_key() {
        Some(key) if model != Model::Soft => {
            let flag = if key == "carry_reach" && args.carry_reach.is_some() {
                "--carry-reach".to_string()
            } else {
                format!("--set {key}")
            };
            Err(anyhow::anyhow!(
                "{flag} needs the soft model ([solver] model = \"soft\"): this run's model is \
                 the paper's, whose projection has no such setting"
            ))
        }
        _ => Ok(()),
    };
    if let Some(path) = &args.resume {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read dump {}", path.display()))?;
        let mut dump = Dump::from_json(&text)
            .with_context(|| format!("{} is not a supergrain dump", path.display()))?;
        // The keys are overridden before the dump is checked, so that `--sleep-radius 0` turns
        // off the sleeping of a dump whose `sleep_steps` is 0.
        let before = dump.solver.as_ref().and_then(|s| s.sleep_radius);
        if table != SolverTable::default() {
            let solver = dump
                .solver
                .get_or_insert_with(|| SolverTable::of(&Settings::default()));
            // (A dump that does not say is the paper's.)
            soft_only(solver.model.unwrap_or(Model::Paper))?;
            if let Some(r) = table.sleep_radius
                && r > 0.0
                && table.sleep_steps.or(solver.sleep_steps).unwrap_or(0) == 0
            {
                bail!(
                    "--sleep-radius {}: the dump's sleep_steps is 0 (grains would freeze where \
                     they are); give --sleep-radius 0 or a dump with sleep_steps >= 1",
                    crate::number(r)
                );
            }
            // A new step keeps the clock going on from where it stands (`World::set_step`).
            let step = table.step;
            let mut given = table.clone();
            given.step = None;
            solver.merge(&given);
            let mut world = dump.to_world().with_context(|| {
                format!(
                    "cannot resume from {} with the command line's solver settings",
                    path.display()
                )
            })?;
            if let Some(h) = step {
                world.set_step(h);
                // Checked as a dump of the new step would be (one too long for the grains).
                Dump::of(&world).to_world().with_context(|| {
                    format!("--set step={h}: cannot resume from {}", path.display())
                })?;
            }
            // A new radius starts every grain's calm afresh: the counts and anchors of the
            // old rule would put grains back to sleep at once, falling or not.
            if let Some(r) = table.sleep_radius
                && before != Some(r)
            {
                for b in &mut world.bodies {
                    b.calm = 0;
                    b.anchor = b.center;
                }
            }
            check_analytic(&world)?;
            return Ok((world, 1000));
        }
        let world = dump
            .to_world()
            .with_context(|| format!("cannot resume from {}", path.display()))?;
        check_analytic(&world)?;
        return Ok((world, 1000));
    }
    let mut scene = match (&args.scene, &args.preset) {
        (Some(path), None) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read scene {}", path.display()))?;
            if text.trim_start().starts_with('{') && Dump::from_json(&text).is_ok() {
                bail!(
                    "{} is a dump (a state written by --dump), not a scene: use --resume {0}",
                    path.display()
                );
            }
            Scene::from_toml(&text)
                .map_err(|e| anyhow::anyhow!(clip_lines(&e.to_string())))
                .with_context(|| format!("invalid scene {}", path.display()))?
        }
        (None, Some(name)) => Scene::preset(name)?,
        (None, None) => bail!(
            "give a scene file, --preset NAME ({}) or --resume FILE.json",
            PRESETS.join(", ")
        ),
        (Some(_), Some(_)) => unreachable!("clap rejects a scene with --preset"),
    };
    if let Some(seed) = args.seed {
        scene.seed = seed;
    }
    if let Some(r) = table.sleep_radius
        && r > 0.0
        && table.sleep_steps.unwrap_or(scene.settings.sleep_steps) == 0
    {
        bail!(
            "--sleep-radius {}: the scene's sleep_steps is 0 (grains would freeze where they \
             appear); give --sleep-radius 0 or set sleep_steps >= 1 in the scene",
            crate::number(r)
        );
    }
    soft_only(scene.settings.model)?;
    table
        .apply(&mut scene.settings)
        .and_then(|()| scene.settings.validate())
        .map_err(|e| anyhow::anyhow!("the command line's solver settings: {e}"))?;
    scene.validate()?;
    let steps = scene.steps;
    Ok((World::new(&scene), steps))
}

/// `message` with each line longer than a screenful cut short: a parser's error quotes the line
/// it failed on, and a file of one long line (a dump, minified JSON) would fill the screen.
fn clip_lines(message: &str) -> String {
    const MOST: usize = 600;
    message
        .lines()
        .map(|line| match line.char_indices().nth(MOST) {
            Some((end, _)) => format!(
                "{}... ({} characters more)",
                &line[..end],
                line[end..].chars().count()
            ),
            None => line.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn check_analytic(world: &World) -> Result<()> {
    if world.settings.narrow_phase == NarrowPhase::Analytic {
        if let Some(i) = world.bodies.iter().position(|b| !b.shape.is_circle()) {
            bail!("--narrow-phase analytic needs circles only, but grain {i} is not a circle");
        }
        if !world.pending.all_circles() {
            bail!(
                "--narrow-phase analytic needs circles only, but grains still to appear are not all circles"
            );
        }
    }
    Ok(())
}

/// Writes one frame of the VTK series into `dir`.
fn write_vtk(world: &World, dir: &Path) -> Result<()> {
    let path = dir.join(format!("frame_{:08}.vtk", world.step));
    let mut out = Target::resolve(Some(&path))?.open()?;
    write_vtk_frame(world, &mut out)?;
    out.finish()
}

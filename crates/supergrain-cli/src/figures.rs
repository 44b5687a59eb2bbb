//! `supergrain figures DIR`: every figure of the paper, redrawn by us, with captions.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use supergrain::geometry::Vec2;
use supergrain::io::write_png;
use supergrain::render::{Colouring, Show, Style, collision_png, render_world, wall_png};
use supergrain::shape::{Pose, Superellipse};
use supergrain::subdivision::Precision;
use supergrain::world::{Rest, RestCounter, Scene, World};
use tiny_skia::Pixmap;

use crate::output::Output;

#[derive(Parser)]
#[command(after_help = "\
Example:
  supergrain figures figures/

Writes fig02.png ... fig13.png and captions.md: the quadtree of a collision test (Figs. 2, 3, 9),
bounding boxes (4, 5), deepest points and penetration vectors (6, 7), a wall contact (8), and the
paper's four scenes poured and settled (10-13, about a minute).")]
pub struct Args {
    /// Folder to write into (created if missing).
    #[arg(value_name = "DIR")]
    dir: PathBuf,
    /// Only the diagrams (Figs. 2-9), not the four settled scenes (the slow part).
    #[arg(long)]
    only_diagrams: bool,
    /// Width of each picture in pixels.
    #[arg(long, default_value_t = 600, value_parser = clap::value_parser!(u32).range(64..=4096))]
    width: u32,
}

fn shape(sx: f64, sy: f64, e: f64) -> Superellipse {
    Superellipse::new([sx, sy], [e, e]).expect("a valid figure shape")
}

fn pose(x: f64, y: f64, angle: f64) -> Pose {
    Pose::new(Vec2::new(x, y), angle).expect("a valid figure pose")
}

fn save(dir: &Path, name: &str, pixmap: &Pixmap) -> Result<()> {
    let mut out = Output::open(Some(&dir.join(name)))?;
    write_png(pixmap, &mut out).context("cannot encode the PNG")?;
    out.finish()
}

/// Steps a preset until every grain has appeared and none has moved faster than 0.05 for 100
/// steps (or 8,000 steps).
fn settle(name: &str) -> World {
    let scene = Scene::preset(name).expect("a preset");
    let mut world = World::new(&scene);
    let mut calm = RestCounter::default();
    while world.step < 8000 {
        world.step();
        if calm.after_step(&Rest::default(), &world) {
            break;
        }
    }
    world
}

pub fn run(args: Args) -> Result<ExitCode> {
    let dir = &args.dir;
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create output folder {}", dir.display()))?;
    let captions_out = Output::open(Some(&dir.join("captions.md")))?;
    let w = args.width;
    let coarse = Precision::new(5, 0.0).expect("a valid precision");
    let fine = Precision::default();

    let ellipse = shape(0.6, 0.3, 2.0);
    let squircle = shape(0.4, 0.4, 4.0);
    let at_origin = pose(0.0, 0.0, 0.3);
    let apart = pose(1.0, 0.42, 0.5);
    let touching = pose(0.78, 0.3, 0.5);
    let far = pose(1.7, 0.7, 0.5);
    let cells = Show {
        cells: true,
        ..Show::default()
    };
    let boxes = Show {
        boxes: true,
        ..Show::default()
    };
    let contact = Show {
        contact: true,
        ..Show::default()
    };

    let mut captions = vec!["# The paper's figures, redrawn by supergrain\n".to_string()];
    let mut figure = |file: &str, caption: String, pixmap: &Pixmap| -> Result<()> {
        save(dir, file, pixmap)?;
        captions.push(format!("- **{file}**: {caption}"));
        Ok(())
    };

    let (p, c) = collision_png(&ellipse, &at_origin, &squircle, &apart, &coarse, w, cells);
    figure(
        "fig02.png",
        format!(
            "Fig. 2, no collision: the quadtree (depth 5) over the intersection of the boxes; every \
             cell is proven outside one shape (grey) before the last level. Overlap: {}.",
            c.overlap()
        ),
        &p,
    )?;
    let (p, c) = collision_png(
        &ellipse, &at_origin, &squircle, &touching, &coarse, w, cells,
    );
    figure(
        "fig03.png",
        format!(
            "Fig. 3, collision: cells inside both shapes (orange) prove the overlap; boundary \
             cells (blue) are split down to the last level. Overlap: {}.",
            c.overlap()
        ),
        &p,
    )?;
    let (p, _) = collision_png(&ellipse, &at_origin, &squircle, &far, &coarse, w, boxes);
    figure(
        "fig04.png",
        "Fig. 4, bounding boxes apart: no quadtree is needed.".into(),
        &p,
    )?;
    let (p, _) = collision_png(
        &ellipse, &at_origin, &squircle, &touching, &coarse, w, boxes,
    );
    figure(
        "fig05.png",
        "Fig. 5, bounding boxes overlap: their intersection (yellow) is the quadtree's region."
            .into(),
        &p,
    )?;
    let (p, _) = collision_png(
        &ellipse, &at_origin, &squircle, &touching, &fine, w, contact,
    );
    figure(
        "fig06.png",
        "Fig. 6, deepest points (depth 7): the point of each shape most interior to the other."
            .into(),
        &p,
    )?;
    let all = Show {
        cells: true,
        boxes: false,
        contact: true,
    };
    let (p, c) = collision_png(&ellipse, &at_origin, &squircle, &touching, &fine, w, all);
    let depth = c.penetration.map_or(0.0, |p| p.depth());
    figure(
        "fig07.png",
        format!(
            "Fig. 7, penetration vectors: from each deepest point along the other's gradient to \
             its boundary (longest {depth:.4}); the solver moves each shape by half of its \
             vector's component towards its centre and turns it by the rest."
        ),
        &p,
    )?;
    let block = shape(0.5, 0.3, 4.0);
    let (p, c) = wall_png(&block, &pose(0.0, 0.22, 0.35), 0.0, &fine.deeper(3), w);
    figure(
        "fig08.png",
        format!(
            "Fig. 8, a wall: the region searched is the shape's box below the floor; the deepest \
             point goes straight up to the floor (push {:.4}).",
            c.penetration.map_or(0.0, |p| p.push.norm())
        ),
        &p,
    )?;
    let star_a = shape(0.5, 0.5, 0.6);
    let star_b = shape(0.45, 0.4, 0.7);
    let deep = Precision::new(6, 0.0).expect("a valid precision");
    let (p, c) = collision_png(
        &star_a,
        &pose(0.0, 0.0, 0.1),
        &star_b,
        &pose(0.55, 0.35, 0.6),
        &deep,
        w,
        all,
    );
    figure(
        "fig09.png",
        format!(
            "Fig. 9, non-convex shapes (exponents 0.6 and 0.7): the same quadtree, depth 6, \
             certifies where spikes meet. Overlap: {}.",
            c.overlap()
        ),
        &p,
    )?;

    let scenes: &[_] = if args.only_diagrams {
        &[]
    } else {
        &[
            ("fig10.png", "circles", "Fig. 10"),
            ("fig11.png", "ellipses", "Fig. 11"),
            ("fig12.png", "squircles", "Fig. 12"),
            ("fig13.png", "mixed", "Fig. 13"),
        ]
    };
    let bar = ProgressBar::new(scenes.len() as u64).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} scenes settled {msg}")
            .expect("a valid template"),
    );
    for &(file, preset, fig) in scenes {
        bar.set_message(preset);
        let world = settle(preset);
        let style = Style {
            width: w,
            colouring: if preset == "mixed" {
                Colouring::Exponent
            } else {
                Colouring::Palette
            },
            ..Style::default()
        };
        figure(
            file,
            format!(
                "{fig}, the `{preset}` preset: {} grains poured and settled after {} steps.",
                world.bodies.len(),
                world.step
            ),
            &render_world(&world, &style),
        )?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mut out = captions_out;
    let written = captions.len() - 1;
    writeln!(out, "{}", captions.join("\n"))?;
    out.finish()?;
    eprintln!(
        "wrote {written} figures and captions.md into {}",
        dir.display()
    );
    Ok(ExitCode::SUCCESS)
}

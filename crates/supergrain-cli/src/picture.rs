//! Picture options shared by `run` and `render`.

use std::path::Path;

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use supergrain::io::write_png;
use supergrain::render::raster::{Antialias, MAX_AA_DEPTH};
use supergrain::render::{Colouring, Style, render_world};
use supergrain::world::World;

use crate::output::{Output, Target};

#[derive(Clone, Copy, ValueEnum)]
pub enum ColourArg {
    /// By shape class: stars red, diamond-like orange, ellipses green, blocky blue.
    Exponent,
    /// A palette cycled by grain, so neighbours differ.
    Palette,
    /// By the scene's [[group]]: the first blue, then red, green, orange, purple, cyan, brown,
    /// lime.
    Group,
}

#[derive(Args, Clone)]
pub struct PictureArgs {
    /// Width of PNG and GIF pictures in pixels (the height follows the box).
    #[arg(long, default_value_t = 800, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub width: u32,
    /// How grains are coloured.
    #[arg(long, value_enum, default_value = "exponent")]
    pub colour: ColourArg,
    /// Anti-aliasing by the paper's method: boundary pixels split in four this many times and
    /// the parts classified (the paper: 1) [default: the coverage of the tangent line at each
    /// boundary pixel, from the value and gradient there].
    #[arg(long, value_name = "LEVELS", value_parser = clap::value_parser!(u32).range(0..=MAX_AA_DEPTH as i64))]
    pub aa: Option<u32>,
    /// Overlay bounding boxes and, filled, where they overlap (paper Figs. 4, 5).
    #[arg(long)]
    pub boxes: bool,
    /// Overlay deepest points and penetration vectors of every contact (paper Figs. 6-8).
    #[arg(long)]
    pub contacts: bool,
}

impl PictureArgs {
    pub fn style(&self) -> Style {
        Style {
            width: self.width,
            colouring: match self.colour {
                ColourArg::Exponent => Colouring::Exponent,
                ColourArg::Palette => Colouring::Palette,
                ColourArg::Group => Colouring::Group,
            },
            antialias: self.aa.map_or(Antialias::Gradient, Antialias::Split),
            boxes: self.boxes,
            contacts: self.contacts,
            ..Style::default()
        }
    }
}

/// Renders a world into an opened output, as PNG, and renames it into place.
pub fn save_png(world: &World, style: &Style, mut out: Output) -> Result<()> {
    write_png(&render_world(world, style), &mut out).context("cannot encode the PNG")?;
    out.finish()
}

/// Writes one PNG into a folder of frames (planned by [`crate::output::Plans::folder`]), named
/// by step.
pub fn save_frame(world: &World, style: &Style, dir: &Path) -> Result<()> {
    let path = dir.join(format!("frame_{:08}.png", world.step));
    save_png(world, style, Target::resolve(Some(&path))?.open()?)
}

//! Picture options shared by `run` and `render`.

use std::path::Path;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use supergrain::io::write_png;
use supergrain::render::raster::{Antialias, MAX_AA_DEPTH};
use supergrain::render::{Colouring, Style, render_world, world_region};
use supergrain::world::World;
use supergrain::world::checks::short;

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

/// The longest side a picture may have, in pixels.
const MAX_SIDE: f64 = 32_768.0;
/// The most pixels a picture may have: 8192 x 16384, 512 MiB of RGBA.
const MAX_PIXELS: f64 = 8192.0 * 16384.0;

/// Refuses, before any work, a picture of `world` (by `style`) too large to draw: a box much
/// taller than wide (`top = 1e6` in a box 2 wide asked for 1.2 TB and aborted the run, its
/// dump unwritten). `flag` names the output in the message.
pub fn check_size(world: &World, style: &Style, flag: &str) -> Result<()> {
    let region = style.region.unwrap_or_else(|| world_region(world));
    let aspect = region.height() / region.width();
    let fits = |width: f64| {
        let height = (aspect * width).round().max(1.0);
        height <= MAX_SIDE && width * height <= MAX_PIXELS
    };
    let width = f64::from(style.width);
    if fits(width) {
        return Ok(());
    }
    // The widest picture within both bounds (its height rounds: step down to the one that fits).
    let mut widest = (MAX_SIDE / aspect)
        .min((MAX_PIXELS / aspect).sqrt())
        .min(8192.0)
        .floor();
    while widest >= 16.0 && !fits(widest) {
        widest -= 1.0;
    }
    let height = (aspect * width).round().max(1.0);
    let fix = if widest >= 16.0 {
        format!("give --width {widest} or less")
    } else if flag == "--output" {
        "no --width fits (16 is the least): the box's top is too high for a picture".to_string()
    } else {
        "no --width fits (16 is the least): lower the box's top (`top` in the scene), or draw \
         the state with --svg"
            .to_string()
    };
    bail!(
        "{flag}: the picture would be {} x {} pixels (the region drawn, the box up to where \
         grains appear, is {} wide and {} tall), more than {MAX_SIDE} pixels on a side or \
         8192 x 16384 in all; {fix}",
        style.width,
        pixels(height),
        short(region.width()),
        short(region.height()),
    )
}

/// A pixel count for a message: whole, in exponent form when huge.
fn pixels(x: f64) -> String {
    if x < 1e9 {
        format!("{x:.0}")
    } else {
        format!("{x:.2e}")
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

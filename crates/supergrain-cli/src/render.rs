//! `supergrain render`: a picture of a dump.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::Parser;
use supergrain::io::Dump;

use crate::output::Output;
use crate::picture::{PictureArgs, check_size, save_png};

#[derive(Parser)]
#[command(after_help = "\
Examples:
  supergrain run --preset mixed --dump mixed.json
  supergrain render mixed.json -o mixed.png
  supergrain render mixed.json -o boxes.png --width 1200 --boxes --contacts --colour palette
  supergrain render heap.json -o chains.png --forces

Grains are painted by the paper's renderer: the interval quadtree classifies pixel blocks, and
boundary pixels are anti-aliased by classifying their parts (--aa levels).")]
pub struct Args {
    /// A state written by `supergrain run --dump`.
    #[arg(value_name = "STATE.json")]
    state: PathBuf,
    /// The PNG to write.
    #[arg(long, short, value_name = "FILE.png")]
    output: PathBuf,
    #[command(flatten)]
    picture: PictureArgs,
    /// Overlay force chains: a line through each contact, centre to centre (or to the wall), as
    /// wide as its normal force is of the largest; from the forces the dump's contacts kept
    /// (model = "soft" dumps; others have none and draw none).
    #[arg(long)]
    forces: bool,
}

pub fn run(args: Args) -> Result<ExitCode> {
    let text = std::fs::read_to_string(&args.state)
        .with_context(|| format!("cannot read {}", args.state.display()))?;
    let dump = Dump::from_json(&text)
        .with_context(|| format!("{} is not a supergrain dump", args.state.display()))?;
    let world = dump
        .to_world()
        .with_context(|| format!("invalid state in {}", args.state.display()))?;
    let out = Output::open(Some(&args.output))?;
    if args.forces && world.settings.model != supergrain::settings::Model::Soft {
        anyhow::bail!(
            "--forces needs a dump of the soft model ([solver] model = \"soft\"): {} has no \
             forces",
            args.state.display()
        );
    }
    let style = supergrain::render::Style {
        forces: args.forces,
        ..args.picture.style()
    };
    check_size(&world, &style, "--output")?;
    save_png(&world, &style, out)?;
    Ok(ExitCode::SUCCESS)
}

//! `supergrain view`: the interactive viewer (crate `supergrain-viewer`) on a scene file or a
//! preset.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::Args as ClapArgs;
use supergrain_viewer::{Launch, Sim};

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// A scene file (TOML). Without one, the preset given by --preset.
    pub scene: Option<PathBuf>,
    /// One of the paper's scenes: circles, ellipses, squircles, mixed.
    #[arg(long, default_value = "mixed", conflicts_with_all = ["scene", "state"])]
    pub preset: String,
    /// A state written by `supergrain run --dump` (or the viewer's Save) instead of a scene;
    /// Reset returns to it.
    #[arg(long, value_name = "STATE.json", conflicts_with = "scene")]
    pub state: Option<PathBuf>,
    /// Start paused.
    #[arg(long)]
    pub paused: bool,
    /// Steps per frame (60 frames per second) to start with; the window's slider changes it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=200))]
    pub speed: Option<u32>,
    /// Open on the collision explorer instead of the simulation.
    #[arg(long)]
    pub explorer: bool,
    /// Print the frame rate and steps per second once a second (for measuring).
    #[arg(long)]
    pub log_fps: bool,
    /// Close the window by itself after this many seconds (for scripts).
    #[arg(long, value_name = "SECONDS")]
    pub quit_after: Option<f64>,
}

pub fn run(args: Args) -> Result<ExitCode> {
    let sim = match (&args.scene, &args.state) {
        (_, Some(path)) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read state file {}", path.display()))?;
            Sim::state(&path.display().to_string(), &text).map_err(anyhow::Error::msg)?
        }
        (Some(path), None) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read scene file {}", path.display()))?;
            Sim::open(&path.display().to_string(), &text).map_err(anyhow::Error::msg)?
        }
        (None, None) => Sim::preset(&args.preset).map_err(anyhow::Error::msg)?,
    };
    if let Some(t) = args.quit_after
        && !(t.is_finite() && t > 0.0)
    {
        anyhow::bail!(
            "--quit-after must be a positive number of seconds, got {}",
            crate::number(t)
        );
    }
    let launch = Launch {
        log_fps: args.log_fps,
        quit_after: args.quit_after,
        paused: args.paused,
        speed: args.speed,
        explorer: args.explorer,
    };
    supergrain_viewer::run_native(sim, launch)?;
    Ok(ExitCode::SUCCESS)
}

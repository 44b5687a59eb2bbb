//! What each peer engine offers the drivers: build the box, add a grain, step, read the grains
//! back. The drivers ([`crate::run`]) are written once over it.

use crate::scene::{Grain, Scene};

/// A peer's failure (the engine refused a shape, a setting or a step), with its own words.
#[derive(Clone, Debug, PartialEq)]
pub struct Error(pub String);

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}

/// One engine's world holding one scene.
pub trait Peer: Sized {
    /// The engine's name in tables.
    const NAME: &'static str;

    /// The box (static walls and floor) of `scene` and its placed grains, gravity, time step and
    /// substeps, on `threads` threads; with sleeping on or off.
    fn new(scene: &Scene, threads: usize, sleep: bool) -> Result<Self, Error>;

    /// A grain of `scene`'s materials at rest at its pose.
    fn add(&mut self, grain: &Grain) -> Result<(), Error>;

    /// One time step.
    fn step(&mut self) -> Result<(), Error>;

    /// The grains in the order added, at their current poses.
    fn grains(&mut self, out: &mut Vec<Grain>) -> Result<(), Error>;

    /// The largest linear speed of a grain.
    fn fastest(&mut self) -> Result<f64, Error>;

    /// The grains' total area as the engine holds it: their mass over the density.
    fn area(&mut self) -> Result<f64, Error>;

    /// The engine's bounding box of grain `i`: `[min x, min y, max x, max y]`.
    fn bounds(&mut self, i: usize) -> Result<[f64; 4], Error>;

    /// Grains added.
    fn len(&self) -> usize;

    fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The static boxes the peers build for the walls and the floor: `(centre, half extents)`, each a
/// unit thick, outside the box, the walls as high as [`Scene::wall_height`].
pub fn wall_boxes(scene: &Scene) -> [([f64; 2], [f64; 2]); 3] {
    let w = scene.walls;
    let t = 0.5;
    let h = 0.5 * scene.wall_height();
    let half_width = 0.5 * (w.right - w.left) + 2.0 * t;
    [
        ([0.5 * (w.left + w.right), w.floor - t], [half_width, t]),
        ([w.left - t, w.floor + h], [t, h]),
        ([w.right + t, w.floor + h], [t, h]),
    ]
}

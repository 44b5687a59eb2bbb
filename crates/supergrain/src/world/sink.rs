//! Sinks: where grains leave the world (issue 41, "inflow and outflow"). A sink is a rectangle;
//! a grain whose centre is in it at the end of a step leaves, counted with its mass, and may be
//! put back at the top as a new grain (a steady state: a chute or a silo that never empties).

use crate::geometry::Aabb;

/// A sink and what has left through it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sink {
    /// Grains whose centre lies in it (edges included) at the end of a step leave.
    pub region: Aabb,
    /// Each grain that leaves comes back as a new grain of its group, its shape and angle
    /// kept, queued to appear at the top by the scene's spawn rule from the next step (first
    /// offered where it left, across the box), with a new id.
    pub recycle: bool,
    /// The grains that have left through it, and their mass (density times area; the paper's
    /// model, which has no materials, counts density 1).
    pub grains: u64,
    pub mass: f64,
}

impl Sink {
    /// A sink over `region` that has taken nothing yet.
    pub fn new(region: Aabb, recycle: bool) -> Sink {
        Sink {
            region,
            recycle,
            grains: 0,
            mass: 0.0,
        }
    }
}

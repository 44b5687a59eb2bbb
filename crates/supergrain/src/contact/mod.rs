//! Contact (paper III-A, III-B; SPEC §4): the deepest points and the penetration vectors.
//!
//! `A1` is the point of A most interior to B; following `grad f_B(A1)` from `A1` to B's boundary
//! gives `B2`, and `A1 -> B2` estimates the penetration of A into B (`a_push`, the way A should
//! move to get out). `A2`, `B1` and `b_push` likewise for B.

mod boundary;
mod certified;
mod disk_disk;
mod flat;
pub mod manifold;
mod narrow;
mod push;
mod ray;
mod regions;
mod spikes;
mod superellipse_superellipse;
mod superellipse_wall;

pub use certified::WarmStart;
pub use disk_disk::{disk_disk, disk_disk_certified};
pub use narrow::{Narrow, NarrowPhase};
pub use ray::{ray_to_boundary, ray_to_convex_boundary};
pub use regions::{COVER_DEPTH, overlap_regions};
pub use superellipse_superellipse::{
    contact, contact_quadtree, contact_quadtree_midpoints, contact_warm, contact_warm_midpoints,
    contact_with_cells, unresolved,
};
pub use superellipse_wall::{
    contact_boundary, contact_wall, contact_wall_quadtree, contact_wall_with_cells,
};

use crate::geometry::Vec2;

/// What two shapes do to each other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// `None`: no point was proven inside both shapes, and no point of one lies deeper in the
    /// other than the tolerance: half a final cell when the certified path answered (`cells`
    /// 0), four final cells from the quadtree (see `contact/spikes.rs`).
    pub penetration: Option<Penetration>,
    /// Quadtree cells classified to reach the answer.
    pub cells: u32,
}

/// The deepest points and penetration vectors of an overlap, in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Penetration {
    /// `A1`: the point of A most interior to B.
    pub a_deepest: Vec2,
    /// `A2`: the point of B most interior to A.
    pub b_deepest: Vec2,
    /// `A1 -> B2`: from `A1` along `grad f_B(A1)` to B's boundary.
    pub a_push: Vec2,
    /// `A2 -> B1`: from `A2` along `grad f_A(A2)` to A's boundary.
    pub b_push: Vec2,
}

impl Penetration {
    /// How deep the overlap is: the longer of the two penetration vectors.
    pub fn depth(&self) -> f64 {
        self.a_push.norm().max(self.b_push.norm())
    }
}

impl Contact {
    pub fn overlap(&self) -> bool {
        self.penetration.is_some()
    }
}

/// A shape against a wall (paper III-B).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallContact {
    pub penetration: Option<WallPenetration>,
    pub cells: u32,
}

/// The shape's point deepest in the wall and the vector that takes it back to the wall's
/// surface. Walls do not move: the shape takes the whole correction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallPenetration {
    pub deepest: Vec2,
    pub push: Vec2,
}

impl WallContact {
    pub fn overlap(&self) -> bool {
        self.penetration.is_some()
    }
}

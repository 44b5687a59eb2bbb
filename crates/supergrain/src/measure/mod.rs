//! Measures of a settled heap of disks, with the pours that make them: the angle of repose
//! ([`repose`]) and the area fraction in a window ([`packing`]) (issue 18's granular bars).
//!
//! They see disks as plain centres and radii ([`Disk`]), so that the same measure reads our
//! heaps and another engine's (`supergrain bench peers --scene repose` measures Box2D's with
//! it).

pub mod packing;
pub mod repose;
pub mod series;

use crate::geometry::Vec2;

/// A disk as the measures see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disk {
    pub center: Vec2,
    pub radius: f64,
}

impl Disk {
    pub fn new(x: f64, y: f64, radius: f64) -> Disk {
        Disk {
            center: Vec2::new(x, y),
            radius,
        }
    }

    /// The disk's highest point.
    pub fn top(&self) -> f64 {
        self.center.y + self.radius
    }
}

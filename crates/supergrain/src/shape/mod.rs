//! Shapes (paper I, SPEC §1): the superellipse, its pose, and the box walls as half-planes.
//!
//! A shape knows its implicit function, gradient, bounding box and mass properties; it knows
//! nothing of intervals, trees or simulation.

mod boundary;
mod half_plane;
mod pose;
mod superellipse;

pub use boundary::{ArcSpec, Boundary, BoundarySpec, CircleSpec, PlaneSpec, ShakeSpec, TurnSpec};
pub use half_plane::HalfPlane;
pub use pose::Pose;
pub use superellipse::{EXPONENT_RANGE, SEMI_AXIS_RANGE, Superellipse};
pub(crate) use superellipse::{abs_pow, pow32, support, support_by, support_dual};

/// Why a shape, pose or wall could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShapeError {
    #[error("{name} must be a finite number greater than 0, got {value}")]
    NotPositive { name: &'static str, value: f64 },
    #[error("{name} must be a finite number, got {value}")]
    NotFinite { name: &'static str, value: f64 },
    #[error("{name} must be between {lo} and {hi}, got {value}")]
    OutOfRange {
        name: &'static str,
        value: f64,
        lo: f64,
        hi: f64,
    },
    #[error(
        "{name} must be a finite vector long enough to scale to length 1 (its length at least \
         1e-300), got ({x:e}, {y:e})"
    )]
    BadDirection { name: &'static str, x: f64, y: f64 },
}

pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<f64, ShapeError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ShapeError::NotPositive { name, value })
    }
}

pub(crate) fn check_finite(name: &'static str, value: f64) -> Result<f64, ShapeError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ShapeError::NotFinite { name, value })
    }
}

/// `value` within `[lo, hi]` (`range`), or an error naming it.
pub(crate) fn check_range(
    name: &'static str,
    value: f64,
    range: std::ops::RangeInclusive<f64>,
) -> Result<f64, ShapeError> {
    if range.contains(&value) {
        Ok(value)
    } else {
        Err(ShapeError::OutOfRange {
            name,
            value,
            lo: *range.start(),
            hi: *range.end(),
        })
    }
}

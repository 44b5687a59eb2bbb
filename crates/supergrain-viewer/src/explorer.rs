//! The collision explorer: two shapes, A fixed at the origin and B following the mouse, and
//! their collision test as the quadtree sees it (the paper's Figs. 2, 3 and 6, live). No window
//! here either: [`Explorer::evaluate`] gives what to draw.

use supergrain::contact::{Contact, contact_with_cells};
use supergrain::geometry::{Aabb, Vec2};
use supergrain::shape::{Pose, Superellipse};
use supergrain::subdivision::{Class, Precision};

/// One shape's editable parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    pub semi_axes: [f64; 2],
    pub exponents: [f64; 2],
    pub angle: f64,
}

impl Params {
    pub fn shape(&self) -> Result<Superellipse, String> {
        Superellipse::new(self.semi_axes, self.exponents).map_err(|e| e.to_string())
    }
}

/// The explorer's state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Explorer {
    pub a: Params,
    pub b: Params,
    /// B's centre (A's is the origin).
    pub b_center: Vec2,
    pub depth: u32,
    pub eps: f64,
}

impl Default for Explorer {
    fn default() -> Self {
        Explorer {
            a: Params {
                semi_axes: [1.2, 0.6],
                exponents: [4.0, 4.0],
                angle: 0.4,
            },
            b: Params {
                semi_axes: [0.8, 0.5],
                exponents: [0.7, 0.7],
                angle: -0.3,
            },
            b_center: Vec2::new(1.3, 0.6),
            depth: 7,
            eps: 0.0,
        }
    }
}

/// A classified cell, in the plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClassedCell {
    pub corners: [Vec2; 4],
    pub a: Class,
    pub b: Class,
    pub last: bool,
}

/// The cells a collision test handed its sink (`contact_with_cells`), in A's frame, placed in
/// the plane by A's pose.
pub fn classed_cells(
    raw: Vec<(Aabb, Class, Class, bool)>,
    pose_a: &Pose,
) -> impl Iterator<Item = ClassedCell> + '_ {
    raw.into_iter().map(move |(cell, a, b, last)| ClassedCell {
        corners: cell.corners().map(|p| pose_a.to_world(p)),
        a,
        b,
        last,
    })
}

/// What the explorer draws.
#[derive(Clone, Debug)]
pub struct Evaluation {
    pub shapes: [(Superellipse, Pose); 2],
    pub boxes: [Aabb; 2],
    pub cells: Vec<ClassedCell>,
    pub contact: Contact,
}

impl Explorer {
    /// The region the explorer's view starts on.
    pub fn region() -> Aabb {
        Aabb::new(Vec2::new(-3.0, -2.0), Vec2::new(3.0, 2.0))
    }

    pub fn evaluate(&self) -> Result<Evaluation, String> {
        let (a, b) = (self.a.shape()?, self.b.shape()?);
        let precision = Precision::new(self.depth, self.eps).map_err(|e| e.to_string())?;
        let pa = Pose::new(Vec2::ZERO, self.a.angle).map_err(|e| e.to_string())?;
        let pb = Pose::new(self.b_center, self.b.angle).map_err(|e| e.to_string())?;
        let mut raw = Vec::new();
        let contact = contact_with_cells(&a, &pa, &b, &pb, &precision, &mut raw);
        let cells = classed_cells(raw, &pa).collect();
        Ok(Evaluation {
            shapes: [(a, pa), (b, pb)],
            boxes: [a.bounding_box(&pa), b.bounding_box(&pb)],
            cells,
            contact,
        })
    }
}

//! Which path answers a pair: the one place that decides it. A solver says which narrow phase
//! its scene asked for and how fine its quadtree is ([`Narrow`]), and gets contacts back; the
//! pair's shapes choose the rest (the analytic answer for two disks, the quadtree two levels
//! deeper for a star, three for a wall).

use super::flat::flat_pair;
use super::manifold::Manifold;
use super::{
    Contact, Penetration, WallContact, WallPenetration, WarmStart, contact_boundary,
    contact_quadtree, contact_quadtree_midpoints, contact_warm, contact_warm_midpoints, disk_disk,
    disk_disk_certified,
};
use crate::shape::{Boundary, Pose, Superellipse};
use crate::subdivision::Precision;

/// Which narrow phase answers grain-grain and grain-wall contact (a scene's `narrow_phase`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NarrowPhase {
    /// Certified, for any superellipse: the certified Newton path for convex pairs, the
    /// quadtree whenever that path has no proof, and for stars.
    Interval,
    /// The paper's certified quadtree alone, for every pair.
    Quadtree,
    /// Centre distance, for circles only: the paper's comparison (IV-A).
    Analytic,
}

/// What a solver asks of the narrow phase: the path its scene chose and the quadtree's
/// precision for a pair of convex grains.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Narrow {
    pub phase: NarrowPhase,
    pub precision: Precision,
}

impl Narrow {
    /// Pairs with a star (an exponent below 1) are tested two levels deeper: a spike thinner
    /// than a final cell can otherwise sink unseen into a neighbour, and such contacts flicker
    /// on and off as grains move, which keeps stars jittering.
    pub fn pair_precision(&self, a: &Superellipse, b: &Superellipse) -> Precision {
        if a.is_star() || b.is_star() {
            self.precision.deeper(2)
        } else {
            self.precision
        }
    }

    /// Walls are tested three levels deeper than grains: their enclosure is exact and cheap,
    /// and the spike of a star (exponent < 1) narrower than a final cell can otherwise sink
    /// unseen into the floor.
    pub fn wall_precision(&self) -> Precision {
        self.precision.deeper(3)
    }

    /// Whether a pair's Newton solves should start where its last test in the step ended: a
    /// persisting contact is tested again at every pass of the paper's projection (seven times
    /// a step on average in the circles preset), after small moves, and Newton then needs about
    /// half the iterations (3 against 6 for ellipses, `cargo bench --bench references`). Not
    /// for two circles: from the line between their centres Newton starts on the answer, which
    /// a warm start, moved with the grains, is not.
    pub fn starts_warm(&self, a: &Superellipse, b: &Superellipse) -> bool {
        self.phase == NarrowPhase::Interval && !(a.is_circle() && b.is_circle())
    }

    /// Two grains' contact with their deepest points (the soft step's): two disks by their
    /// certified analytic answer, any other pair by the certified path started from `warm`
    /// (updated), or the quadtree or the centre distance where the scene asked for them.
    pub fn pair(
        &self,
        a: &Superellipse,
        pa: &Pose,
        b: &Superellipse,
        pb: &Pose,
        warm: &mut Option<WarmStart>,
    ) -> Contact {
        match self.phase {
            NarrowPhase::Interval if a.is_circle() && b.is_circle() => {
                disk_disk_certified(pa.center(), a.semi_axes().x, pb.center(), b.semi_axes().x)
            }
            NarrowPhase::Interval => contact_warm(a, pa, b, pb, &self.pair_precision(a, b), warm),
            NarrowPhase::Quadtree => contact_quadtree(a, pa, b, pb, &self.pair_precision(a, b)),
            NarrowPhase::Analytic => analytic(a, pa, b, pb),
        }
    }

    /// Two flat grains (every exponent at least 8) by their faces, under the certified path:
    /// `Some(None)` proven apart, `Some(Some(manifold))` proven overlapping, with the manifold
    /// the soft step holds them by; `None` for any other pair or phase, or where the faces
    /// prove nothing (then [`Narrow::pair`] and the manifold of its deepest points).
    /// `contact/flat.rs`.
    pub fn flat(
        &self,
        a: &Superellipse,
        pa: &Pose,
        b: &Superellipse,
        pb: &Pose,
        margin: f64,
    ) -> Option<Option<Manifold>> {
        if self.phase != NarrowPhase::Interval {
            return None;
        }
        flat_pair(a, pa, b, pb, &self.pair_precision(a, b), margin)
    }

    /// Two grains' contact as the paper's projection reads it: the deepest points of the
    /// overlap's middle ([`contact_warm_midpoints`]), for every pair by the chosen path.
    pub fn pair_midpoints(
        &self,
        a: &Superellipse,
        pa: &Pose,
        b: &Superellipse,
        pb: &Pose,
        warm: &mut Option<WarmStart>,
    ) -> Contact {
        match self.phase {
            NarrowPhase::Interval => {
                contact_warm_midpoints(a, pa, b, pb, &self.pair_precision(a, b), warm)
            }
            NarrowPhase::Quadtree => {
                contact_quadtree_midpoints(a, pa, b, pb, &self.pair_precision(a, b))
            }
            NarrowPhase::Analytic => analytic(a, pa, b, pb),
        }
    }

    /// A grain against a boundary: certified (by the quadtree alone where the scene asked for
    /// it), or for a disk under the analytic path its centre's distance.
    pub fn wall(&self, a: &Superellipse, pa: &Pose, wall: &Boundary) -> WallContact {
        match self.phase {
            NarrowPhase::Interval => contact_boundary(a, pa, wall, &self.wall_precision(), false),
            NarrowPhase::Quadtree => contact_boundary(a, pa, wall, &self.wall_precision(), true),
            NarrowPhase::Analytic => {
                let r = a.semi_axes().x;
                let n = wall.normal(pa.center());
                let deepest = pa.center() - n * r;
                // A half-plane's as it always was (the same bits); the others' by the centre.
                let g = match wall.as_plane() {
                    Some(w) => w.value(deepest),
                    None => wall.distance(pa.center()) - r,
                };
                WallContact {
                    penetration: (g < 0.0).then(|| WallPenetration {
                        deepest,
                        push: n * -g,
                    }),
                    cells: 0,
                }
            }
        }
    }
}

/// Two disks by their centres' distance (the paper's comparison; not certified).
fn analytic(a: &Superellipse, pa: &Pose, b: &Superellipse, pb: &Pose) -> Contact {
    let (ra, rb) = (a.semi_axes().x, b.semi_axes().x);
    let (ca, cb) = (pa.center(), pb.center());
    Contact {
        penetration: disk_disk(ca, ra, cb, rb).map(|(n, depth)| Penetration {
            a_deepest: ca + n * ra,
            b_deepest: cb - n * rb,
            a_push: n * -depth,
            b_push: n * depth,
        }),
        cells: 0,
    }
}

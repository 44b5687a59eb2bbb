//! Boundaries (issue 41): the solids that hold grains in, each given by its signed distance.
//!
//! A boundary is a solid region, like a grain, but fixed in the scene: a half-plane (the box's
//! walls, an incline), a thick segment (a capsule: a silo's plank, a hopper's side, a piece of
//! a polyline), a thick circular arc, or a circle with the grains inside (a drum: the solid is
//! everything outside it) or outside (an obstacle). Each is described by `g(p)`, the signed
//! distance to its surface, negative inside the solid: exact and 1-Lipschitz for all four, which
//! gives the narrow phase a closed form for disks and a cheap proof of "apart" for any grain
//! (`g(centre)` beyond the grain's bounding radius), and the quadtree an enclosure over a box
//! ([`crate::interval::ImplicitShape`]).
//!
//! Segments and arcs have a thickness: a zero-thickness wall holds no point, so no overlap with
//! it could ever be proven, and a grain that passes its middle line within a step is pushed out
//! on the far side. A thickness of a grain's radius or more keeps that from happening at any
//! speed the time-step check allows.

use super::{HalfPlane, ShapeError, check_finite, check_positive};
use crate::geometry::{Aabb, Vec2};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// A solid grains are kept out of. See the module docs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Boundary {
    /// `g(p) = n . p - d`.
    Plane(HalfPlane),
    /// The points within `radius` of the segment from `a` to `b` (`a = b`: a disk).
    Segment { a: Vec2, b: Vec2, radius: f64 },
    /// The points within `radius` of the arc of the circle about `center` of radius `r`, from
    /// the angle `from` counter-clockwise through `sweep` (degrees, as a scene gives them, so
    /// that a dump writes them back bit for bit: `0 <= from < 360`, `0 < sweep <= 360`).
    Arc {
        center: Vec2,
        r: f64,
        from: f64,
        sweep: f64,
        radius: f64,
    },
    /// The circle about `center` of radius `r`: with the grains `inside` (a drum), the solid is
    /// all outside it; otherwise the solid is the disk (an obstacle).
    Circle { center: Vec2, r: f64, inside: bool },
}

fn point(name: &'static str, p: Vec2) -> Result<Vec2, ShapeError> {
    check_finite(name, p.x)?;
    check_finite(name, p.y)?;
    Ok(p)
}

/// The angle of the direction `d` in `[0, 2 pi)`.
fn angle_of(d: Vec2) -> f64 {
    let t = d.y.atan2(d.x);
    if t < 0.0 { t + TAU } else { t }
}

/// `x` reduced into `[0, 2 pi)`.
fn wrap(x: f64) -> f64 {
    let t = x.rem_euclid(TAU);
    if t >= TAU { 0.0 } else { t }
}

/// The point of the segment `a..b` nearest to `p`.
fn nearest_on_segment(a: Vec2, b: Vec2, p: Vec2) -> Vec2 {
    let d = b - a;
    let len2 = d.dot(d);
    if len2 > 0.0 {
        a + d * ((p - a).dot(d) / len2).clamp(0.0, 1.0)
    } else {
        a
    }
}

/// The distance from `p` to the box (0 inside it).
fn point_box_distance(p: Vec2, b: &Aabb) -> f64 {
    let dx = (b.min.x - p.x).max(p.x - b.max.x).max(0.0);
    let dy = (b.min.y - p.y).max(p.y - b.max.y).max(0.0);
    dx.hypot(dy)
}

/// Whether the segment `a..b` meets the closed box (Liang-Barsky clipping).
fn segment_meets_box(a: Vec2, b: Vec2, bx: &Aabb) -> bool {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x - bx.min.x),
        (d.x, bx.max.x - a.x),
        (-d.y, a.y - bx.min.y),
        (d.y, bx.max.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    t0 <= t1
}

/// The smallest distance between the segment `a..b` and the box: for two convex polygons it is
/// reached at a vertex of one of them, unless they meet.
fn segment_box_distance(a: Vec2, b: Vec2, bx: &Aabb) -> f64 {
    if segment_meets_box(a, b, bx) {
        return 0.0;
    }
    let corners = bx.corners();
    let mut best = point_box_distance(a, bx).min(point_box_distance(b, bx));
    for c in corners {
        best = best.min((c - nearest_on_segment(a, b, c)).norm());
    }
    best
}

/// The largest distance from `c` to a point of the box: at a corner.
fn farthest_corner(c: Vec2, bx: &Aabb) -> f64 {
    bx.corners()
        .iter()
        .map(|&q| (q - c).norm())
        .fold(0.0, f64::max)
}

impl Boundary {
    /// A thick segment from `a` to `b`, `thickness` wide (`a = b`: a disk of that diameter).
    pub fn segment(a: Vec2, b: Vec2, thickness: f64) -> Result<Boundary, ShapeError> {
        Ok(Boundary::Segment {
            a: point("segment end", a)?,
            b: point("segment end", b)?,
            radius: check_positive("thickness", thickness)? * 0.5,
        })
    }

    /// A thick arc of the circle about `center` of radius `r`, from the angle `from`
    /// counter-clockwise through `sweep` (degrees, `0 < sweep <= 360`), `thickness` wide.
    pub fn arc(
        center: Vec2,
        r: f64,
        from: f64,
        sweep: f64,
        thickness: f64,
    ) -> Result<Boundary, ShapeError> {
        let from = check_finite("arc's from", from)?.rem_euclid(360.0);
        let from = if from >= 360.0 { 0.0 } else { from };
        let sweep = super::check_range("arc's sweep", sweep, 0.0..=360.0)?;
        check_positive("arc's sweep", sweep)?;
        let radius = check_positive("thickness", thickness)? * 0.5;
        let r = check_positive("arc's radius", r)?;
        if radius >= r {
            return Err(ShapeError::OutOfRange {
                name: "thickness",
                value: thickness,
                lo: 0.0,
                hi: 2.0 * r,
            });
        }
        Ok(Boundary::Arc {
            center: point("arc's centre", center)?,
            r,
            from,
            sweep,
            radius,
        })
    }

    /// A circle about `center` of radius `r`, the grains `inside` (a drum) or outside it.
    pub fn circle(center: Vec2, r: f64, inside: bool) -> Result<Boundary, ShapeError> {
        Ok(Boundary::Circle {
            center: point("circle's centre", center)?,
            r: check_positive("circle's radius", r)?,
            inside,
        })
    }

    /// The nearest point of a segment's or an arc's middle line (its core) to `p`.
    fn core_point(&self, p: Vec2) -> Vec2 {
        match *self {
            Boundary::Segment { a, b, .. } => nearest_on_segment(a, b, p),
            Boundary::Arc {
                center,
                r,
                from,
                sweep,
                ..
            } => {
                let d = p - center;
                if d.x == 0.0 && d.y == 0.0 {
                    return self.arc_end(0);
                }
                if wrap(angle_of(d) - from.to_radians()) <= sweep.to_radians() {
                    center + d * (r / d.norm())
                } else {
                    let (e0, e1) = (self.arc_end(0), self.arc_end(1));
                    if (p - e0).norm() <= (p - e1).norm() {
                        e0
                    } else {
                        e1
                    }
                }
            }
            _ => p,
        }
    }

    /// An arc's first (`0`) or last (`1`) end on its middle line.
    fn arc_end(&self, k: usize) -> Vec2 {
        match *self {
            Boundary::Arc {
                center,
                r,
                from,
                sweep,
                ..
            } => {
                let t = if k == 0 { from } else { from + sweep }.to_radians();
                center + Vec2::new(t.cos(), t.sin()) * r
            }
            _ => Vec2::ZERO,
        }
    }

    /// `g(p)`: the signed distance to the surface, negative inside the solid.
    pub fn distance(&self, p: Vec2) -> f64 {
        match *self {
            Boundary::Plane(w) => w.value(p),
            Boundary::Segment { radius, .. } | Boundary::Arc { radius, .. } => {
                (p - self.core_point(p)).norm() - radius
            }
            Boundary::Circle { center, r, inside } => {
                let d = (p - center).norm();
                if inside { r - d } else { d - r }
            }
        }
    }

    /// The unit gradient of [`Self::distance`] at `p`: out of the solid, into the free space.
    /// Where it is not defined (on a core, at a circle's centre) a fixed choice.
    pub fn normal(&self, p: Vec2) -> Vec2 {
        match *self {
            Boundary::Plane(w) => w.normal(),
            Boundary::Segment { a, b, .. } => {
                (p - self.core_point(p)).direction().unwrap_or_else(|| {
                    let d = (b - a).direction().unwrap_or(Vec2::new(1.0, 0.0));
                    Vec2::new(-d.y, d.x)
                })
            }
            Boundary::Arc { center, .. } => (p - self.core_point(p))
                .direction()
                .or_else(|| (center - p).direction())
                .unwrap_or(Vec2::new(0.0, 1.0)),
            Boundary::Circle { center, inside, .. } => {
                let u = (p - center).direction().unwrap_or(Vec2::new(0.0, 1.0));
                if inside { u * -1.0 } else { u }
            }
        }
    }

    /// The point of the surface nearest to `p`.
    pub fn project(&self, p: Vec2) -> Vec2 {
        match self {
            Boundary::Plane(w) => w.project(p),
            _ => p - self.normal(p) * self.distance(p),
        }
    }

    /// A box holding the whole solid (infinite for a half-plane at an angle and for a drum).
    pub fn bounding_box(&self) -> Aabb {
        let grown = |b: Aabb, r: f64| b.grown(r + self.pad(b.center()));
        match *self {
            Boundary::Plane(w) => w.bounding_box(),
            Boundary::Segment { a, b, radius } => grown(
                Aabb::new(
                    Vec2::new(a.x.min(b.x), a.y.min(b.y)),
                    Vec2::new(a.x.max(b.x), a.y.max(b.y)),
                ),
                radius,
            ),
            Boundary::Arc {
                center,
                r,
                from,
                sweep,
                radius,
            } => {
                let (e0, e1) = (self.arc_end(0), self.arc_end(1));
                let mut bx = Aabb::new(
                    Vec2::new(e0.x.min(e1.x), e0.y.min(e1.y)),
                    Vec2::new(e0.x.max(e1.x), e0.y.max(e1.y)),
                );
                // The circle's extreme points the arc passes (with a margin on the angles).
                for (k, q) in [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)]
                    .into_iter()
                    .enumerate()
                {
                    let t = wrap(k as f64 * std::f64::consts::FRAC_PI_2 - from.to_radians());
                    if t <= sweep.to_radians() + 1e-9 || t >= TAU - 1e-9 {
                        bx = bx.union(&Aabb::point(center + Vec2::new(q.0, q.1) * r));
                    }
                }
                grown(bx, radius)
            }
            Boundary::Circle { center, r, inside } => {
                if inside {
                    Aabb::EVERYWHERE
                } else {
                    grown(Aabb::point(center), r)
                }
            }
        }
    }

    /// How far off the rounding of [`Self::distance`] and of the enclosures can be near `p`,
    /// with room: each distance is a handful of correctly rounded operations on numbers no
    /// larger than the coordinates and radii involved, so `1e-13` of their size (about 450
    /// roundings' worth) bounds the error.
    pub fn pad(&self, p: Vec2) -> f64 {
        let size = |q: Vec2| q.x.abs().max(q.y.abs());
        let own = match *self {
            Boundary::Plane(w) => w.offset().abs(),
            Boundary::Segment { a, b, radius } => size(a).max(size(b)) + radius,
            Boundary::Arc {
                center, r, radius, ..
            } => size(center) + r + radius,
            Boundary::Circle { center, r, .. } => size(center) + r,
        };
        1e-13 * (own + size(p))
    }

    /// A rigorous enclosure `[lo, hi]` of `g` over the box.
    pub fn enclose(&self, bx: &Aabb) -> (f64, f64) {
        let pad = self.pad(bx.min).max(self.pad(bx.max));
        let (lo, hi) = match *self {
            Boundary::Plane(w) => {
                // Linear: the extremes are at corners.
                let v = bx.corners().map(|q| w.value(q));
                (
                    v.iter().copied().fold(f64::INFINITY, f64::min),
                    v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                )
            }
            Boundary::Segment { a, b, radius } => {
                // Distance to a convex set is convex: its largest value over the box is at a
                // corner.
                let far = bx
                    .corners()
                    .iter()
                    .map(|&q| (q - nearest_on_segment(a, b, q)).norm())
                    .fold(0.0, f64::max);
                (segment_box_distance(a, b, bx) - radius, far - radius)
            }
            Boundary::Arc {
                center,
                r,
                from,
                sweep,
                radius,
            } => {
                // The distance to the whole circle bounds the arc's from below; where every
                // point of the box lies outside the arc's angles, the nearest point of the arc
                // is an end.
                let (near, far) = (point_box_distance(center, bx), farthest_corner(center, bx));
                let ring_lo = (r - far).max(near - r).max(0.0);
                let (e0, e1) = (self.arc_end(0), self.arc_end(1));
                let ends_lo = point_box_distance(e0, bx).min(point_box_distance(e1, bx));
                let ends_hi = farthest_corner(e0, bx).min(farthest_corner(e1, bx));
                let half = 0.5 * bx.diagonal();
                let mid = bx.center();
                let lipschitz_hi = (mid - self.core_point(mid)).norm() + half;
                let (lo, mut hi) = (ring_lo, ends_hi.min(lipschitz_hi));
                let lo = match self.angles_of(bx, center) {
                    Some((start, width)) => {
                        let (from, sweep) = (from.to_radians(), sweep.to_radians());
                        let s = wrap(start - from);
                        if s > sweep && s + width < TAU {
                            lo.max(ends_lo)
                        } else {
                            if s + width <= sweep {
                                hi = hi.min((r - near).abs().max((far - r).abs()));
                            }
                            lo
                        }
                    }
                    None => lo,
                };
                (lo - radius, hi - radius)
            }
            Boundary::Circle { center, r, inside } => {
                let (near, far) = (point_box_distance(center, bx), farthest_corner(center, bx));
                if inside {
                    (r - far, r - near)
                } else {
                    (near - r, far - r)
                }
            }
        };
        (lo - pad, hi + pad)
    }

    /// The angles under which the box is seen from `c`, as a start and a width (both padded),
    /// or `None` when `c` is in the box or too near it to tell.
    fn angles_of(&self, bx: &Aabb, c: Vec2) -> Option<(f64, f64)> {
        if point_box_distance(c, bx) <= 1e-9 * bx.diagonal().max(f64::MIN_POSITIVE) {
            return None;
        }
        let mid = angle_of(bx.center() - c);
        let mut lo = 0.0f64;
        let mut hi = 0.0f64;
        for q in bx.corners() {
            let mut d = angle_of(q - c) - mid;
            if d > std::f64::consts::PI {
                d -= TAU;
            } else if d < -std::f64::consts::PI {
                d += TAU;
            }
            lo = lo.min(d);
            hi = hi.max(d);
        }
        // atan2 is good to an ulp or two; a micro-radian is far beyond that.
        const ANGLE_PAD: f64 = 1e-6;
        let width = hi - lo + 2.0 * ANGLE_PAD;
        (width < std::f64::consts::PI).then_some((mid + lo - ANGLE_PAD, width))
    }

    /// A box holding its surface, for pictures: `None` for a half-plane; a drum's circle.
    pub fn extent(&self) -> Option<Aabb> {
        match *self {
            Boundary::Plane(_) => None,
            Boundary::Circle { center, r, .. } => Some(Aabb::point(center).grown(r)),
            _ => Some(self.bounding_box()),
        }
    }

    /// Turned by `angle` (radians, counter-clockwise) about `pivot`, then moved by `shift`.
    pub fn moved(&self, pivot: Vec2, angle: f64, shift: Vec2) -> Boundary {
        let r = crate::geometry::Rotation::new(angle);
        let at = |p: Vec2| pivot + r.apply(p - pivot) + shift;
        match *self {
            Boundary::Plane(w) => {
                let n = r.apply(w.normal());
                let on = at(w.normal() * w.offset());
                // A unit normal turned stays one within rounding, which `new` divides out.
                Boundary::Plane(HalfPlane::new(n, n.dot(on)).unwrap_or(w))
            }
            Boundary::Segment { a, b, radius } => Boundary::Segment {
                a: at(a),
                b: at(b),
                radius,
            },
            Boundary::Arc {
                center,
                r: big,
                from,
                sweep,
                radius,
            } => {
                let from = (from + angle.to_degrees()).rem_euclid(360.0);
                Boundary::Arc {
                    center: at(center),
                    r: big,
                    from: if from >= 360.0 { 0.0 } else { from },
                    sweep,
                    radius,
                }
            }
            Boundary::Circle {
                center,
                r: big,
                inside,
            } => Boundary::Circle {
                center: at(center),
                r: big,
                inside,
            },
        }
    }

    /// A thick segment's or arc's half-thickness (how deep its middle line is).
    pub fn half_thickness(&self) -> Option<f64> {
        match *self {
            Boundary::Segment { radius, .. } | Boundary::Arc { radius, .. } => Some(radius),
            _ => None,
        }
    }

    /// Whether this is the box's kind of wall, a half-plane.
    pub fn as_plane(&self) -> Option<&HalfPlane> {
        match self {
            Boundary::Plane(w) => Some(w),
            _ => None,
        }
    }

    /// Where a grain of bounding radius `reach` about `center` meets a thick segment only on
    /// one face, away from both ends: that face's half-plane, on which the contact is the
    /// half-plane's (the grain lies on this side of the middle line and within the segment's
    /// length, where the capsule is the slab `0 <= n . (p - a) < radius`). `support(d)` is an
    /// upper bound of the grain's extent from its centre in the world direction `d`.
    pub fn face_for(&self, center: Vec2, support: impl Fn(Vec2) -> f64) -> Option<HalfPlane> {
        let Boundary::Segment { a, b, radius } = *self else {
            return None;
        };
        let len = (b - a).norm();
        let t = (b - a).direction()?;
        // The normal of the face the centre looks at.
        let left = Vec2::new(-t.y, t.x);
        let n = if left.dot(center - a) >= 0.0 {
            left
        } else {
            left * -1.0
        };
        let pad = self.pad(center) + 1e-12 * support(n * -1.0);
        let above_core = n.dot(center - a) - support(n * -1.0) > pad;
        let along = t.dot(center - a);
        let within = along - support(t * -1.0) > pad && along + support(t) < len - pad;
        (above_core && within)
            .then(|| HalfPlane::new(n, n.dot(a) + radius).ok())
            .flatten()
    }
}

/// A boundary as a scene's `[[boundary]]` table and a dump's `boundaries` entry give it: exactly
/// one of `plane`, `segment`, `polyline`, `arc`, `circle`, with `thickness` for the thick ones,
/// `closed` for a polyline and `inside` for a circle. One type for both, read and written by
/// serde, checked once by [`BoundarySpec::pieces`]. (Lists, not arrays, for points: a third
/// number must be an error, not dropped.)
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<PlaneSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub segment: Option<Vec<Vec<f64>>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polyline: Option<Vec<Vec<f64>>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub closed: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arc: Option<ArcSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub circle: Option<CircleSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inside: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f64>,
    /// Driven: turned about a point (see `crate::body::Drive`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn: Option<TurnSpec>,
    /// Driven: shaken along a line.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shake: Option<ShakeSpec>,
    /// Driven: its surface moving along it at this speed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub belt: Option<f64>,
}

/// A turn: about the point `about`, at `rate` degrees per second (counter-clockwise).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TurnSpec {
    pub about: Vec<f64>,
    pub rate: f64,
}

/// A shake: displaced by `amplitude sin(2 pi frequency t)`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShakeSpec {
    pub amplitude: Vec<f64>,
    pub frequency: f64,
}

/// A half-plane: the line through `point` (or at `offset` along the normal) across `normal`,
/// solid on the side away from the normal.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneSpec {
    pub normal: Vec<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<Vec<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<f64>,
}

/// An arc: its circle's `center` and `radius`, from the angle `from` counter-clockwise to `to`
/// or through `sweep` (degrees; `to` below `from` goes round through 360).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArcSpec {
    pub center: Vec<f64>,
    pub radius: f64,
    pub from: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<f64>,
}

/// A circle: `center` and `radius`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CircleSpec {
    pub center: Vec<f64>,
    pub radius: f64,
}

fn xy(what: &str, v: &[f64]) -> Result<Vec2, String> {
    match v {
        [x, y] if x.is_finite() && y.is_finite() => Ok(Vec2::new(*x, *y)),
        [_, _] => Err(format!("{what} must be two finite numbers, got {v:?}")),
        _ => Err(format!("{what} needs two numbers [x, y], got {}", v.len())),
    }
}

impl BoundarySpec {
    /// The boundaries it stands for (a polyline's segments, in order), or what is wrong.
    pub fn pieces(&self) -> Result<Vec<Boundary>, String> {
        let kinds = [
            ("plane", self.plane.is_some()),
            ("segment", self.segment.is_some()),
            ("polyline", self.polyline.is_some()),
            ("arc", self.arc.is_some()),
            ("circle", self.circle.is_some()),
        ];
        let given: Vec<&str> = kinds.iter().filter(|k| k.1).map(|k| k.0).collect();
        let kind = match given[..] {
            [one] => one,
            [] => {
                return Err("needs one of plane, segment, polyline, arc or circle".into());
            }
            _ => {
                return Err(format!(
                    "has {}: give one shape per [[boundary]]",
                    given.join(" and ")
                ));
            }
        };
        let allowed: &[&str] = match kind {
            "plane" => &[],
            "segment" | "arc" => &["thickness"],
            "polyline" => &["thickness", "closed"],
            _ => &["inside"],
        };
        for (key, set) in [
            ("thickness", self.thickness.is_some()),
            ("closed", self.closed.is_some()),
            ("inside", self.inside.is_some()),
        ] {
            if set && !allowed.contains(&key) {
                return Err(format!("a {kind} takes no {key}"));
            }
        }
        let thickness = || {
            self.thickness.ok_or_else(|| {
                format!(
                    "a {kind} needs a thickness (its full width: a wall with none holds no point, \
                     and a grain crossing its middle within a step comes out the far side)"
                )
            })
        };
        let shape = |e: ShapeError| format!("{kind}: {e}");
        match kind {
            "plane" => {
                let p = self.plane.as_ref().expect("given");
                let n = xy("plane's normal", &p.normal)?;
                let offset = match (&p.point, p.offset) {
                    (Some(at), None) => n.dot(xy("plane's point", at)?),
                    (None, Some(d)) => d,
                    _ => return Err("a plane needs one of point or offset".into()),
                };
                Ok(vec![Boundary::Plane(
                    HalfPlane::new(n, offset).map_err(shape)?,
                )])
            }
            "segment" => {
                let ends = self.segment.as_ref().expect("given");
                let [a, b] = &ends[..] else {
                    return Err(format!("a segment needs two points, got {}", ends.len()));
                };
                let (a, b) = (xy("segment's end", a)?, xy("segment's end", b)?);
                Ok(vec![Boundary::segment(a, b, thickness()?).map_err(shape)?])
            }
            "polyline" => {
                let points = self.polyline.as_ref().expect("given");
                let closed = self.closed.unwrap_or(false);
                if points.len() < 2 || (closed && points.len() < 3) {
                    return Err(format!(
                        "a{} polyline needs at least {} points, got {}",
                        if closed { " closed" } else { "n open" },
                        if closed { 3 } else { 2 },
                        points.len()
                    ));
                }
                let points = points
                    .iter()
                    .enumerate()
                    .map(|(k, p)| xy(&format!("polyline's point {}", k + 1), p))
                    .collect::<Result<Vec<_>, _>>()?;
                let t = thickness()?;
                let mut pieces = Vec::new();
                let n = points.len();
                for k in 0..if closed { n } else { n - 1 } {
                    let (a, b) = (points[k], points[(k + 1) % n]);
                    pieces.push(
                        Boundary::segment(a, b, t)
                            .map_err(|e| format!("polyline's segment {}: {e}", k + 1))?,
                    );
                }
                Ok(pieces)
            }
            "arc" => {
                let a = self.arc.as_ref().expect("given");
                let sweep = match (a.to, a.sweep) {
                    (Some(to), None) if to.is_finite() && a.from.is_finite() => {
                        let s = (to - a.from).rem_euclid(360.0);
                        if s == 0.0 { 360.0 } else { s }
                    }
                    (None, Some(s)) => s,
                    (Some(to), None) => return Err(format!("arc's to must be finite, got {to}")),
                    _ => return Err("an arc needs one of to or sweep".into()),
                };
                let center = xy("arc's center", &a.center)?;
                Ok(vec![
                    Boundary::arc(center, a.radius, a.from, sweep, thickness()?).map_err(shape)?,
                ])
            }
            _ => {
                let c = self.circle.as_ref().expect("given");
                let inside = self.inside.ok_or(
                    "a circle needs inside = true (the grains inside it, a drum) or false (an \
                     obstacle)",
                )?;
                let center = xy("circle's center", &c.center)?;
                Ok(vec![
                    Boundary::circle(center, c.radius, inside).map_err(shape)?,
                ])
            }
        }
    }

    /// The spec of one boundary, as a dump writes it (read back, the same bits).
    pub fn of(b: &Boundary) -> BoundarySpec {
        let pair = |p: Vec2| vec![p.x, p.y];
        match *b {
            Boundary::Plane(w) => BoundarySpec {
                plane: Some(PlaneSpec {
                    normal: pair(w.normal()),
                    point: None,
                    offset: Some(w.offset()),
                }),
                ..BoundarySpec::default()
            },
            Boundary::Segment { a, b, radius } => BoundarySpec {
                segment: Some(vec![pair(a), pair(b)]),
                thickness: Some(2.0 * radius),
                ..BoundarySpec::default()
            },
            Boundary::Arc {
                center,
                r,
                from,
                sweep,
                radius,
            } => BoundarySpec {
                arc: Some(ArcSpec {
                    center: pair(center),
                    radius: r,
                    from,
                    to: None,
                    sweep: Some(sweep),
                }),
                thickness: Some(2.0 * radius),
                ..BoundarySpec::default()
            },
            Boundary::Circle { center, r, inside } => BoundarySpec {
                circle: Some(CircleSpec {
                    center: pair(center),
                    radius: r,
                }),
                inside: Some(inside),
                ..BoundarySpec::default()
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_enclosure_holds(bd: &Boundary, bx: &Aabb) {
        let (lo, hi) = bd.enclose(bx);
        for i in 0..=40 {
            for j in 0..=40 {
                let p = Vec2::new(
                    bx.min.x + bx.width() * f64::from(i) / 40.0,
                    bx.min.y + bx.height() * f64::from(j) / 40.0,
                );
                let g = bd.distance(p);
                assert!(lo <= g && g <= hi, "{bd:?} {bx:?}: {g} not in [{lo}, {hi}]");
            }
        }
    }

    #[test]
    fn enclosures_hold_every_sampled_value() {
        let shapes = [
            Boundary::segment(Vec2::new(-1.0, 0.2), Vec2::new(2.0, 0.7), 0.1).unwrap(),
            Boundary::segment(Vec2::new(0.5, 0.5), Vec2::new(0.5, 0.5), 0.4).unwrap(),
            Boundary::arc(Vec2::new(0.1, -0.3), 1.5, 200.0, 145.0, 0.2).unwrap(),
            Boundary::arc(Vec2::new(0.0, 0.0), 1.0, 0.0, 360.0, 0.1).unwrap(),
            Boundary::arc(Vec2::new(0.0, 0.0), 1.0, 300.0, 120.0, 0.1).unwrap(),
            Boundary::circle(Vec2::new(0.3, 0.1), 1.2, true).unwrap(),
            Boundary::circle(Vec2::new(0.3, 0.1), 0.7, false).unwrap(),
        ];
        let mut s = 7u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for bd in &shapes {
            for _ in 0..300 {
                let (x, y) = (next() * 5.0 - 2.5, next() * 5.0 - 2.5);
                let (w, h) = (next() * next() * 2.0, next() * next() * 2.0);
                brute_enclosure_holds(bd, &Aabb::new(Vec2::new(x, y), Vec2::new(x + w, y + h)));
            }
        }
    }

    #[test]
    fn distances_are_the_closed_forms() {
        let s = Boundary::segment(Vec2::new(0.0, 0.0), Vec2::new(2.0, 0.0), 0.2).unwrap();
        assert!((s.distance(Vec2::new(1.0, 0.5)) - 0.4).abs() < 1e-15);
        assert!((s.distance(Vec2::new(3.0, 0.0)) - 0.9).abs() < 1e-15);
        let a = Boundary::arc(Vec2::ZERO, 1.0, 0.0, 180.0, 0.2).unwrap();
        // Below the arc's ends: the nearest point is the end (1, 0).
        assert!((a.distance(Vec2::new(1.0, -1.0)) - 0.9).abs() < 1e-15);
        assert!((a.distance(Vec2::new(0.0, 2.0)) - 0.9).abs() < 1e-15);
        let d = Boundary::circle(Vec2::ZERO, 2.0, true).unwrap();
        assert!((d.distance(Vec2::new(0.0, 1.5)) - 0.5).abs() < 1e-15);
        assert!((d.normal(Vec2::new(0.0, 1.5)) - Vec2::new(0.0, -1.0)).norm() < 1e-15);
    }
}

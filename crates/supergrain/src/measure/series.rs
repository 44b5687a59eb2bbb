//! Measures taken as a run goes (issue 41, "measurements"): each a CSV row (or a row per sink)
//! every `every` steps, declared in a scene (`[[measure]]`) or on the command line, kept in
//! dumps. The first two: the discharge through the sinks, and the kinetic energy.

use std::io::{self, Write};

use serde::{Deserialize, Serialize};

use crate::geometry::{Aabb, Vec2};
use crate::settings::Model;
use crate::world::World;

/// What a series measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SeriesKind {
    /// Per sink: the grains and the mass it has taken so far, with the grains in the box and
    /// all that have appeared (appeared = in the box + taken by every sink, at every row).
    Discharge,
    /// The grains' kinetic energy: translational `sum m v^2 / 2` and rotational
    /// `sum I w^2 / 2` (the soft model's masses; the paper's model, which has none, counts
    /// density 1 and no rotation).
    Energy,
    /// The angle of one straight free surface (a drum's, a chute's): [`surface_angle`].
    Surface,
    /// In a region: the grains whose centres it holds, the area fraction (every grain's area
    /// inside it, any shape: [`super::packing::shape_area_in`]) and the mean contact number of
    /// those grains ([`packing_in`]).
    Packing,
    /// Across a region cut into `bins` horizontal slices: each slice's grains and their mean
    /// velocity ([`profile_in`]), a row per slice.
    Profile,
}

impl SeriesKind {
    pub fn name(&self) -> &'static str {
        match self {
            SeriesKind::Discharge => "discharge",
            SeriesKind::Energy => "energy",
            SeriesKind::Surface => "surface",
            SeriesKind::Packing => "packing",
            SeriesKind::Profile => "profile",
        }
    }
}

/// A measure and how often it is taken.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Series {
    pub kind: SeriesKind,
    /// Steps between rows (at least 1).
    pub every: u64,
    /// Where a packing or a profile is measured: `[[x0, x1], [y0, y1]]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<[[f64; 2]; 2]>,
    /// A profile's slices (default [`PROFILE_BINS`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bins: Option<u32>,
}

/// A profile's slices when the measure does not say.
pub const PROFILE_BINS: u32 = 10;

impl Series {
    /// A measure of `kind` every `every` steps, with no region.
    pub fn new(kind: SeriesKind, every: u64) -> Series {
        Series {
            kind,
            every,
            region: None,
            bins: None,
        }
    }

    /// Its region as a box (the whole plane when it has none).
    pub fn window(&self) -> Aabb {
        match self.region {
            Some([[x0, x1], [y0, y1]]) => Aabb::new(Vec2::new(x0, y0), Vec2::new(x1, y1)),
            None => Aabb::EVERYWHERE,
        }
    }
}

impl Series {
    /// The CSV header.
    pub fn header(&self) -> &'static str {
        match self.kind {
            SeriesKind::Discharge => "step,time,sink,grains,mass,in_box,appeared",
            SeriesKind::Energy => "step,time,grains,translational,rotational,total",
            SeriesKind::Surface => "step,time,degrees,points",
            SeriesKind::Packing => "step,time,grains,area_fraction,contact_number",
            SeriesKind::Profile => "step,time,y,grains,vx,vy",
        }
    }

    /// Whether a row is due after step `step`.
    pub fn due(&self, step: u64) -> bool {
        step.is_multiple_of(self.every.max(1))
    }

    /// The rows of `world` now.
    pub fn write_rows(&self, world: &World, out: &mut impl Write) -> io::Result<()> {
        let (step, time) = (world.step, world.time());
        match self.kind {
            SeriesKind::Discharge => {
                let in_box = world.bodies.iter().filter(|b| b.kind.is_dynamic()).count();
                let fixed = (world.bodies.len() - in_box) as u64;
                // Ids are given in order of appearance, fixed bodies first: every grain that
                // has appeared has one.
                let appeared = world.next_id().0 - fixed;
                for (k, s) in world.sinks.iter().enumerate() {
                    writeln!(
                        out,
                        "{step},{time},{},{},{},{in_box},{appeared}",
                        k + 1,
                        s.grains,
                        s.mass
                    )?;
                }
            }
            SeriesKind::Energy => {
                let (n, translational, rotational) = energy(world);
                writeln!(
                    out,
                    "{step},{time},{n},{translational},{rotational},{}",
                    translational + rotational
                )?;
            }
            SeriesKind::Surface => match surface_angle(world) {
                Some((degrees, points)) => writeln!(out, "{step},{time},{degrees},{points}")?,
                None => writeln!(out, "{step},{time},,0")?,
            },
            SeriesKind::Packing => {
                let p = packing_in(world, &self.window());
                writeln!(
                    out,
                    "{step},{time},{},{},{}",
                    p.grains, p.area_fraction, p.contact_number
                )?;
            }
            SeriesKind::Profile => {
                for s in profile_in(world, &self.window(), self.bins.unwrap_or(PROFILE_BINS)) {
                    writeln!(
                        out,
                        "{step},{time},{},{},{},{}",
                        s.y, s.grains, s.v.x, s.v.y
                    )?;
                }
            }
        }
        Ok(())
    }

    /// A line for the run's summary.
    pub fn summary(&self, world: &World) -> String {
        self.reading(world).0
    }

    /// The summary line, and the one number a live chart follows (the viewer's) with its name:
    /// the grains taken by every sink, the total kinetic energy, the surface's angle, the
    /// region's area fraction; `None` for a profile (many numbers) and a surface too small to
    /// fit. One measurement gives both.
    pub fn reading(&self, world: &World) -> (String, Option<(&'static str, f64)>) {
        match self.kind {
            SeriesKind::Discharge => {
                let taken: u64 = world.sinks.iter().map(|s| s.grains).sum();
                (
                    format!(
                        "discharge: {taken} grains taken by {} sinks",
                        world.sinks.len()
                    ),
                    Some(("grains taken", taken as f64)),
                )
            }
            SeriesKind::Energy => {
                let (n, t, r) = energy(world);
                (
                    format!(
                        "kinetic energy of the {n} grains: {t:.4e} translational, {r:.4e} \
                         rotational"
                    ),
                    Some(("kinetic energy", t + r)),
                )
            }
            SeriesKind::Surface => match surface_angle(world) {
                Some((degrees, points)) => (
                    format!("free surface: {degrees:.2} degrees (a line through {points} bins)"),
                    Some(("degrees", degrees)),
                ),
                None => ("free surface: too few grains to fit".into(), None),
            },
            SeriesKind::Packing => {
                let p = packing_in(world, &self.window());
                (
                    format!(
                        "packing: {} grains in the region, area fraction {:.4}, mean contact \
                         number {:.3}",
                        p.grains, p.area_fraction, p.contact_number
                    ),
                    Some(("area fraction", p.area_fraction)),
                )
            }
            SeriesKind::Profile => {
                let slices = profile_in(world, &self.window(), self.bins.unwrap_or(PROFILE_BINS));
                let text: Vec<String> = slices
                    .iter()
                    .filter(|s| s.grains > 0)
                    .map(|s| format!("{:.3}: {:.3}", s.y, s.v.x))
                    .collect();
                (
                    format!("velocity profile (y: mean vx): {}", text.join(", ")),
                    None,
                )
            }
        }
    }
}

/// A region's packing ([`SeriesKind::Packing`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Packing {
    /// Dynamic grains whose centres the region holds.
    pub grains: usize,
    /// Every dynamic grain's area inside the region, over the region's area.
    pub area_fraction: f64,
    /// The mean number of contacts of those grains (walls and fixed bodies count): the soft
    /// model's contacts carrying a force at the last step, the paper model's overlaps.
    pub contact_number: f64,
}

/// The packing of the grains in `window` (see [`Packing`]).
pub fn packing_in(world: &World, window: &Aabb) -> Packing {
    let area: f64 = world
        .bodies
        .iter()
        .filter(|b| b.kind.is_dynamic())
        .map(|b| super::packing::shape_area_in(&b.shape, &b.pose(), window))
        .sum::<f64>()
        // (A sum of nothing is -0 in Rust, written "-0": 0.)
        + 0.0;
    let inside: Vec<bool> = world
        .bodies
        .iter()
        .map(|b| b.kind.is_dynamic() && window.contains(b.center))
        .collect();
    let grains = inside.iter().filter(|&&i| i).count();
    let mut contacts = 0usize;
    let mut count = |i: usize| {
        if inside.get(i).copied().unwrap_or(false) {
            contacts += 1;
        }
    };
    match world.settings.model {
        Model::Soft => {
            for f in world.soft.forces.iter().filter(|f| f.normal_force > 0.0) {
                count(f.a);
                count(f.b);
            }
        }
        Model::Paper => world.contacts(|t| match t {
            crate::world::Touch::Grains(i, j, _) => {
                count(i);
                count(j);
            }
            crate::world::Touch::Wall(i, _) => count(i),
        }),
    }
    Packing {
        grains,
        area_fraction: area / (window.width() * window.height()),
        contact_number: if grains > 0 {
            contacts as f64 / grains as f64
        } else {
            0.0
        },
    }
}

/// One slice of a velocity profile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slice {
    /// The slice's middle height.
    pub y: f64,
    /// Dynamic grains whose centres it holds, and their mean velocity (zero for none).
    pub grains: usize,
    pub v: Vec2,
}

/// The velocity profile across `window` in `bins` horizontal slices, bottom to top.
pub fn profile_in(world: &World, window: &Aabb, bins: u32) -> Vec<Slice> {
    let bins = bins.max(1);
    let h = window.height() / f64::from(bins);
    let mut slices: Vec<Slice> = (0..bins)
        .map(|k| Slice {
            y: window.min.y + (f64::from(k) + 0.5) * h,
            grains: 0,
            v: Vec2::ZERO,
        })
        .collect();
    for (i, b) in world.bodies.iter().enumerate() {
        if !b.kind.is_dynamic() || !window.contains(b.center) {
            continue;
        }
        let k = (((b.center.y - window.min.y) / h) as usize).min(slices.len() - 1);
        slices[k].grains += 1;
        slices[k].v += world.velocity(i);
    }
    for s in &mut slices {
        if s.grains > 0 {
            s.v = s.v * (1.0 / s.grains as f64);
        }
    }
    slices
}

/// The fraction of the grains' width trimmed at each end before the surface is fitted: the
/// walls' rise and the toe.
pub const SURFACE_TRIM: f64 = 0.2;

/// The angle of the grains' free surface, in degrees (positive: rising to the right), and the
/// bins fitted: the dynamic grains cut into vertical bins one mean bounding diameter wide, in
/// each the highest top of a grain's box; a least-squares line through the bins of the middle
/// 60% of the grains' width ([`SURFACE_TRIM`] off each end, where the surface bends up to a
/// drum's wall). `None` with fewer than three bins. One straight surface: a drum's or a chute's
/// (a heap's two flanks are [`super::repose`]'s).
pub fn surface_angle(world: &World) -> Option<(f64, usize)> {
    let boxes: Vec<Aabb> = world
        .bodies
        .iter()
        .filter(|b| b.kind.is_dynamic())
        .map(|b| b.bounding_box())
        .collect();
    surface_line(&boxes)
}

/// [`surface_angle`] of grains given by their boxes (another engine's too).
pub fn surface_line(boxes: &[Aabb]) -> Option<(f64, usize)> {
    if boxes.is_empty() {
        return None;
    }
    let bin = boxes.iter().map(|b| b.width()).sum::<f64>() / boxes.len() as f64;
    let left = boxes.iter().map(|b| b.min.x).fold(f64::INFINITY, f64::min);
    let right = boxes
        .iter()
        .map(|b| b.max.x)
        .fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = (
        left + SURFACE_TRIM * (right - left),
        right - SURFACE_TRIM * (right - left),
    );
    let bins = ((hi - lo) / bin).floor().max(0.0) as usize;
    // Fewer than three bins fit no line (a grain or two: narrower than a bin, none).
    if bins < 3 {
        return None;
    }
    let mut tops = vec![f64::NEG_INFINITY; bins];
    for b in boxes {
        let x = 0.5 * (b.min.x + b.max.x);
        if x < lo || x >= hi {
            continue;
        }
        let k = (((x - lo) / bin) as usize).min(bins.saturating_sub(1));
        tops[k] = tops[k].max(b.max.y);
    }
    let points: Vec<Vec2> = tops
        .iter()
        .enumerate()
        .filter(|(_, t)| t.is_finite())
        .map(|(k, &t)| Vec2::new(lo + (k as f64 + 0.5) * bin, t))
        .collect();
    if points.len() < 3 {
        return None;
    }
    let slope = super::repose::slope(&points);
    Some((slope.atan().to_degrees(), points.len()))
}

/// The dynamic grains, and their translational and rotational kinetic energies.
fn energy(world: &World) -> (usize, f64, f64) {
    let soft = world.settings.model == Model::Soft;
    let (mut n, mut translational, mut rotational) = (0, 0.0, 0.0);
    for (i, b) in world.bodies.iter().enumerate() {
        if !b.kind.is_dynamic() {
            continue;
        }
        n += 1;
        let (mass, inertia) = world.material(i).mass_and_inertia(&b.shape);
        let v = world.velocity(i);
        translational += 0.5 * mass * v.dot(v);
        if soft {
            rotational += 0.5 * inertia * b.angular_velocity * b.angular_velocity;
        }
    }
    (n, translational, rotational)
}

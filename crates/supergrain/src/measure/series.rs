//! Measures taken as a run goes (issue 41, "measurements"): each a CSV row (or a row per sink)
//! every `every` steps, declared in a scene (`[[measure]]`) or on the command line, kept in
//! dumps. The first two: the discharge through the sinks, and the kinetic energy.

use std::io::{self, Write};

use serde::{Deserialize, Serialize};

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
}

impl SeriesKind {
    pub fn name(&self) -> &'static str {
        match self {
            SeriesKind::Discharge => "discharge",
            SeriesKind::Energy => "energy",
        }
    }
}

/// A measure and how often it is taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Series {
    pub kind: SeriesKind,
    /// Steps between rows (at least 1).
    pub every: u64,
}

impl Series {
    /// The CSV header.
    pub fn header(&self) -> &'static str {
        match self.kind {
            SeriesKind::Discharge => "step,time,sink,grains,mass,in_box,appeared",
            SeriesKind::Energy => "step,time,grains,translational,rotational,total",
        }
    }

    /// Whether a row is due after step `step`.
    pub fn due(&self, step: u64) -> bool {
        step.is_multiple_of(self.every.max(1))
    }

    /// The rows of `world` now.
    pub fn write_rows(&self, world: &World, out: &mut impl Write) -> io::Result<()> {
        let (step, time) = (world.step, world.step as f64 * world.settings.step);
        match self.kind {
            SeriesKind::Discharge => {
                let in_box = world.bodies.iter().filter(|b| !b.is_static()).count();
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
        }
        Ok(())
    }

    /// A line for the run's summary.
    pub fn summary(&self, world: &World) -> String {
        match self.kind {
            SeriesKind::Discharge => {
                let taken: u64 = world.sinks.iter().map(|s| s.grains).sum();
                format!(
                    "discharge: {taken} grains taken by {} sinks",
                    world.sinks.len()
                )
            }
            SeriesKind::Energy => {
                let (n, t, r) = energy(world);
                format!(
                    "kinetic energy of the {n} grains: {t:.4e} translational, {r:.4e} \
                     rotational"
                )
            }
        }
    }
}

/// The dynamic grains, and their translational and rotational kinetic energies.
fn energy(world: &World) -> (usize, f64, f64) {
    let soft = world.settings.model == Model::Soft;
    let (mut n, mut translational, mut rotational) = (0, 0.0, 0.0);
    for (i, b) in world.bodies.iter().enumerate() {
        if b.is_static() {
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

//! The state dump: `{"walls": {...}, "particles": [...]}` with each particle in the SHAPE form
//! plus its velocity, and, for exact restarts, the solver state the velocity cannot carry
//! (previous pose, step, settings, the spawn queue of the grains still to appear).

use std::collections::VecDeque;

use serde::{Deserialize, Serialize};

use super::ShapeJson;
use crate::body::{Body, BodyId, BodyKind, Drive, Driver, Material, Walls, material_of};
use crate::broad_phase::Kind as BroadPhaseKind;
use crate::contact::WarmStart;
use crate::geometry::{Aabb, Vec2};
use crate::measure::series::Series;
use crate::settings::{Model, Settings, SoftSettings, SolverTable};
use crate::shape::{
    Boundary, BoundarySpec, HalfPlane, Pose, ShakeSpec, ShapeError, Superellipse, TurnSpec,
};
use crate::solver::carry::{Carried, CarriedParts};
use crate::solver::soft::{Kept, MAX_WALLS, STATIC};
use crate::world::{Fair, Generator, Group, Pending, Queue, Range, Sink, Touch, World, checks};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallsJson {
    pub left: f64,
    pub right: f64,
    pub floor: f64,
}

/// One grain of a dump.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleJson {
    /// Its [`BodyId`]; absent: its index in `particles` (every dump written before grains
    /// could leave, and any grain whose id is its index).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<u64>,
    /// `"static"` for a body that never moves; absent: `"dynamic"`.
    #[serde(default, skip_serializing_if = "BodyKind::is_dynamic")]
    pub kind: BodyKind,
    pub center: [f64; 2],
    pub angle: f64,
    pub semi_axes: [f64; 2],
    pub exponents: [f64; 2],
    pub velocity: [f64; 2],
    /// Verlet's previous position; when absent, `center - velocity * step`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub previous_center: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub previous_angle: Option<f64>,
    /// Calm steps in a row near `anchor` (sleeping, see the solver's `sleep_radius`);
    /// absent: 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub calm: u32,
    /// Absent: `center`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub anchor: Option<[f64; 2]>,
    /// Where the grain last woke its neighbours for drifting; absent: `center`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drift_anchor: Option<[f64; 2]>,
    /// Steps ready to sleep while a neighbour was not; absent: 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub waiting: u32,
    /// The scene group, counted from 0 in the scene's order; absent: 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub group: u32,
    /// Radians per second (the soft step's state); absent: 0.
    #[serde(default, skip_serializing_if = "is_zero_f64")]
    pub angular_velocity: f64,
}

fn is_zero(n: &u32) -> bool {
    *n == 0
}

fn is_zero_f64(x: &f64) -> bool {
    *x == 0.0
}

/// A material (see [`Material`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialJson {
    pub density: f64,
    pub friction: f64,
    pub restitution: f64,
    pub rolling_resistance: f64,
}

impl From<&Material> for MaterialJson {
    fn from(m: &Material) -> Self {
        MaterialJson {
            density: m.density,
            friction: m.friction,
            restitution: m.restitution,
            rolling_resistance: m.rolling_resistance,
        }
    }
}

impl MaterialJson {
    fn to_material(&self, what: &str) -> Result<Material, DumpError> {
        let m = Material {
            density: self.density,
            friction: self.friction,
            restitution: self.restitution,
            rolling_resistance: self.rolling_resistance,
        };
        m.validate()
            .map_err(|e| DumpError::Solver(format!("{what}: {e}")))?;
        Ok(m)
    }
}

/// A sink and what has left through it (see [`Sink`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SinkJson {
    /// `[[x0, x1], [y0, y1]]`.
    pub region: [[f64; 2]; 2],
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub recycle: bool,
    #[serde(default, skip_serializing_if = "is_zero_u64")]
    pub grains: u64,
    #[serde(default, skip_serializing_if = "is_zero_f64")]
    pub mass: f64,
}

fn is_zero_u64(n: &u64) -> bool {
    *n == 0
}

/// A wall at any angle (see [`HalfPlane`]), as dumps before `boundaries` wrote them: read,
/// never written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneJson {
    pub normal: [f64; 2],
    pub offset: f64,
}

/// A contact the soft step keeps from one step to the next: its impulses (the next step's
/// warm start) and where the narrow phase found its deepest points, so that a resumed run goes
/// on bit for bit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactJson {
    /// The grains, or a grain and `wall` (0 left, 1 right, 2 floor, then the planes).
    pub a: usize,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub b: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_impulse: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangent_impulse: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "is_zero_f64")]
    pub rolling_impulse: f64,
    /// Newton's last points for the pair, in A's frame: `[A1]` or `[A1, A2]`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warm: Vec<[f64; 2]>,
    /// The pair's manifold carried from the step it was last searched.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub carried: Option<CarriedParts>,
}

/// A grain drawn that has not appeared yet.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PendingJson {
    pub semi_axes: [f64; 2],
    pub exponents: [f64; 2],
    pub x: f64,
    pub angle: f64,
    pub due: u64,
    /// Absent: 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub group: u32,
}

/// The spawn queue (see [`Queue`]): the grains drawn and waiting for their place, then those
/// still to draw.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QueueJson {
    /// In queue order; absent: none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub waiting: Vec<PendingJson>,
    /// Absent: nothing more to draw.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generator: Option<GeneratorJson>,
    /// The fair rule's state (`[spawn] rule = "fair"`); absent: the queue rule (and every dump
    /// from before the rule).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fair: Option<FairJson>,
    /// Where grains appear across (`[spawn] between`); absent: between the walls.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub between: Option<[f64; 2]>,
}

/// Where the fair rule stands (see [`Fair`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FairJson {
    /// The scene's seed: the places offered are drawn from its streams.
    pub seed: u64,
    /// The queue index of the next grain to appear.
    pub head: u64,
    /// The places it has been offered so far.
    pub tries: u64,
}

/// The grains still to draw (see [`Generator`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeneratorJson {
    /// The scene's seed.
    pub seed: u64,
    /// The queue index of the next grain to draw: it draws from that stream of the seeded
    /// generator, and is due at step `next / spawn_count * spawn_interval`.
    pub next: u64,
    pub spawn_interval: u32,
    pub spawn_count: u32,
    /// The scene's groups, in its order (a grain's `group` counts in it).
    pub groups: Vec<GroupJson>,
}

/// A scene group and how many of its grains are still to draw. Ranges are `[lo, hi]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupJson {
    pub name: String,
    pub remaining: u32,
    pub semi_axes: [[f64; 2]; 2],
    /// Both semi-axes from one draw.
    pub circles: bool,
    pub exponents: [[f64; 2]; 2],
    /// Both exponents from one draw.
    pub same_exponents: bool,
    pub angle: [f64; 2],
}

/// A whole dump.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dump {
    pub walls: WallsJson,
    pub particles: Vec<ParticleJson>,
    /// Steps done (absent in a hand-written state: 0).
    #[serde(default)]
    pub step: u64,
    /// Height at which grains appear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub top: Option<f64>,
    /// The solver settings, as a scene's `[solver]` ([`SolverTable::of`]). Keys absent in
    /// dumps older than them: sleeping off (`sleep_radius`, `sleep_steps` 0), by grain, no
    /// shock propagation, no strips, the grid broad phase, contacts not carried; `model`
    /// absent: the paper's, unless the dump holds the soft step's parts, when it is refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<SolverTable>,
    /// The grains still to appear; absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub queue: Option<QueueJson>,
    /// Dumps from before the queue: every grain still to appear, drawn, in queue order. Read,
    /// never written.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pending: Vec<PendingJson>,
    /// Each group's material (the soft step's), by group; absent: the default material.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub materials: Vec<MaterialJson>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_material: Option<MaterialJson>,
    /// Dumps before `boundaries`: walls at any angle, `g = normal . p - offset`, solid where
    /// `g < 0`. Read, never written.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub planes: Vec<PlaneJson>,
    /// The boundaries besides the box's walls, in order (a polyline as its segments).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub boundaries: Vec<BoundarySpec>,
    /// The driven grains: each one's id, where it was at step 0 and its drive (where it is now
    /// follows from the time); absent: none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub drivers: Vec<DriverJson>,
    /// Where the clock restarted when the time step changed, `[step, time]`
    /// ([`World::clock`]); absent: never, the time is the steps times the step.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clock: Option<(u64, f64)>,
    /// The soft step's contacts kept for the next step.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contacts: Vec<ContactJson>,
    /// The id the next body to join gets; absent: one past the largest id of `particles` (0
    /// for none): written only once a body has left with the largest id, which no later body
    /// may take.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub next_id: Option<u64>,
    /// Where grains leave, and how many have.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sinks: Vec<SinkJson>,
    /// Measures taken as the run goes: `{"kind", "every"}`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub measures: Vec<Series>,
}

/// A driven grain ([`Driver`]): the particle's `id`, its place at step 0, and its drive's
/// `turn` and `shake`, as a `[[grain]]` table writes them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriverJson {
    pub id: u64,
    pub center: [f64; 2],
    pub angle: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn: Option<TurnSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shake: Option<ShakeSpec>,
}

/// Why a dump cannot be resumed.
#[derive(Debug, thiserror::Error)]
pub enum DumpError {
    #[error("particle {index}: {error}")]
    Particle { index: usize, error: ShapeError },
    #[error("pending grain {index}: {error}")]
    Pending { index: usize, error: ShapeError },
    #[error("queue: waiting grain {index}: {error}")]
    Waiting { index: usize, error: ShapeError },
    /// A spawn queue that cannot be drawn from; the message names the field.
    #[error("queue: {0}")]
    Queue(String),
    #[error("walls: {0}")]
    Walls(String),
    #[error("solver: {0}")]
    Solver(String),
    #[error("particle {0}: a number is not finite")]
    NotFinite(usize),
    #[error(
        "step: {0} leaves no exact step to go on to: a dump holds steps below {max} (2^53, past \
         which a step's time is not exact)",
        max = checks::MAX_STEP
    )]
    Step(u64),
    /// A state the solver cannot go on from: a grain outside the box or deep in another, a
    /// grain that cannot fit or appear, a time step too long for the grains.
    #[error("{0}")]
    Unworkable(String),
}

impl Dump {
    /// A dump from the text of a JSON file. A UTF-8 byte-order mark before it (some editors
    /// save one) is skipped: JSON forbids it, but it says nothing about the content.
    pub fn from_json(text: &str) -> Result<Dump, serde_json::Error> {
        serde_json::from_str(text.strip_prefix('\u{feff}').unwrap_or(text))
    }

    /// The state of a world.
    pub fn of(world: &World) -> Dump {
        let s = &world.settings;
        Dump {
            walls: WallsJson {
                left: world.walls.left,
                right: world.walls.right,
                floor: world.walls.floor,
            },
            particles: world
                .bodies
                .iter()
                .enumerate()
                .map(|(i, b)| {
                    let shape = ShapeJson::from_shape(&b.shape, &b.pose());
                    ParticleJson {
                        id: (b.id != BodyId(i as u64)).then_some(b.id.0),
                        kind: b.kind,
                        center: shape.center,
                        angle: shape.angle,
                        semi_axes: shape.semi_axes,
                        exponents: shape.exponents,
                        velocity: world.velocity(i).to_array(),
                        previous_center: Some(b.previous_center.to_array()),
                        previous_angle: Some(b.previous_angle),
                        calm: b.calm,
                        anchor: (b.anchor != b.center).then(|| b.anchor.to_array()),
                        drift_anchor: (b.drift_anchor != b.center)
                            .then(|| b.drift_anchor.to_array()),
                        waiting: b.waiting,
                        group: b.group,
                        angular_velocity: b.angular_velocity,
                    }
                })
                .collect(),
            step: world.step,
            top: Some(world.top),
            solver: Some(SolverTable::of(s)),
            // Written empty too where a sink puts grains back: they appear by its rule.
            queue: (!world.pending.is_empty() || world.sinks.iter().any(|s| s.recycle))
                .then(|| queue_json(&world.pending)),
            pending: Vec::new(),
            materials: if s.model == Model::Soft {
                world.materials.iter().map(MaterialJson::from).collect()
            } else {
                Vec::new()
            },
            wall_material: (s.model == Model::Soft).then(|| (&world.wall_material).into()),
            planes: Vec::new(),
            // Each at step 0, with its drive: where it is now follows from the step.
            clock: (world.clock != (0, 0.0)).then_some(world.clock),
            drivers: world
                .drivers
                .iter()
                .map(|d| {
                    let (turn, shake) = d.drive.keys();
                    DriverJson {
                        id: d.id.0,
                        center: d.base.center().to_array(),
                        angle: d.base.angle(),
                        turn,
                        shake,
                    }
                })
                .collect(),
            boundaries: world
                .bases
                .iter()
                .zip(&world.drives)
                .map(|(b, d)| {
                    let mut spec = BoundarySpec::of(b);
                    d.write(&mut spec);
                    spec
                })
                .collect(),
            contacts: if s.model == Model::Soft {
                kept_contacts(world)
            } else {
                Vec::new()
            },
            next_id: (world.next_id() != BodyId::after(world.bodies.iter().map(|b| b.id)))
                .then_some(world.next_id().0),
            sinks: world
                .sinks
                .iter()
                .map(|s| SinkJson {
                    region: [
                        [s.region.min.x, s.region.max.x],
                        [s.region.min.y, s.region.max.y],
                    ],
                    recycle: s.recycle,
                    grains: s.grains,
                    mass: s.mass,
                })
                .collect(),
            measures: world.measures.clone(),
        }
    }

    /// The first of the soft step's parts the dump holds, by its key.
    fn soft_part(&self) -> Option<&'static str> {
        let solver = self.solver.as_ref().and_then(SolverTable::soft_key);
        [
            (solver.unwrap_or(""), solver.is_some()),
            ("materials", !self.materials.is_empty()),
            ("wall_material", self.wall_material.is_some()),
            ("planes", !self.planes.is_empty()),
            ("boundaries", !self.boundaries.is_empty()),
            ("contacts", !self.contacts.is_empty()),
        ]
        .into_iter()
        .find_map(|(key, held)| held.then_some(key))
    }

    /// The world this dump describes, ready to go on.
    ///
    /// Refused before any work (see [`checks`]), as a scene's settings are: a non-finite number,
    /// a `step` not below [`checks::MAX_STEP`], a grain deeper than [`checks::DEPTH_FRACTION`]
    /// of its smallest semi-axis beyond a wall or inside another grain (its depth measured by
    /// [`checks::overlap_depth`]; under the soft model: an awake grain beyond a wall by more
    /// than [`checks::SOFT_OUTSIDE_FRACTION`] of its bounding radius, a sleeper beyond a wall
    /// by the paper's limit, two sleepers one of which holds the other's centre), a grain still
    /// to appear that cannot fit between the walls, would appear in the floor or (drawn) beyond
    /// a wall, a time step too long for the grains, a queue whose groups cannot be drawn from
    /// (as a scene's), negative gravity, an `eps` or sleep radius too coarse for the grains, a
    /// mass or moment of inertia out of [`checks::MASS_RANGE`], a plane over the places grains
    /// appear, a contact listed twice or with impulses no heap could give, and a dump without
    /// `model` that holds the soft step's parts. A dump from before the queue, with every grain
    /// still to appear in `pending`, resumes with those grains and nothing more.
    pub fn to_world(&self) -> Result<World, DumpError> {
        if self.step >= checks::MAX_STEP {
            return Err(DumpError::Step(self.step));
        }
        let w = &self.walls;
        if !(w.left.is_finite() && w.right.is_finite() && w.floor.is_finite() && w.left < w.right) {
            return Err(DumpError::Walls(format!(
                "left ({}) must be left of right ({}), all finite",
                w.left, w.right
            )));
        }
        let settings = match &self.solver {
            None => Settings::default(),
            Some(t) => {
                if t.model.is_none()
                    && let Some(part) = self.soft_part()
                {
                    return Err(DumpError::Solver(format!(
                        "model is missing, and the dump holds `{part}`, which only model \
                         \"soft\" has: add \"model\": \"soft\" to \"solver\" (or \"paper\" \
                         without the soft step's parts)"
                    )));
                }
                if t.max_overlap.is_some() {
                    return Err(DumpError::Solver(
                        "max_overlap is a scene's (its stiffness follows from the scene's \
                         grains); a dump holds the contact_hertz and substeps it gave"
                            .into(),
                    ));
                }
                t.settings(Model::Paper, legacy_settings)
                    .map_err(DumpError::Solver)?
            }
        };
        let walls = Walls {
            left: w.left,
            right: w.right,
            floor: w.floor,
        };
        let mut bodies = Vec::with_capacity(self.particles.len());
        let mut velocities = Vec::with_capacity(self.particles.len());
        for (index, p) in self.particles.iter().enumerate() {
            let shape = Superellipse::new(p.semi_axes, p.exponents)
                .map_err(|error| DumpError::Particle { index, error })?;
            let pose = Pose::new(Vec2::from(p.center), p.angle)
                .map_err(|error| DumpError::Particle { index, error })?;
            let v = Vec2::from(p.velocity);
            let body = Body {
                id: BodyId(p.id.unwrap_or(index as u64)),
                kind: p.kind,
                shape,
                center: pose.center(),
                angle: pose.angle(),
                previous_center: p
                    .previous_center
                    .map_or(pose.center() - v * settings.step, Vec2::from),
                previous_angle: p.previous_angle.unwrap_or(pose.angle()),
                calm: p.calm,
                anchor: p.anchor.map_or(pose.center(), Vec2::from),
                drift_anchor: p.drift_anchor.map_or(pose.center(), Vec2::from),
                waiting: p.waiting,
                group: p.group,
                velocity: if settings.model == Model::Soft {
                    v
                } else {
                    Vec2::ZERO
                },
                angular_velocity: if settings.model == Model::Soft {
                    p.angular_velocity
                } else {
                    0.0
                },
            };
            if !body.is_finite() || !v.is_finite() {
                return Err(DumpError::NotFinite(index));
            }
            if body.is_static() && (v != Vec2::ZERO || p.angular_velocity != 0.0) {
                return Err(DumpError::Unworkable(format!(
                    "particle {index}: a static body never moves, but has velocity ({}, {}) \
                     and angular velocity {}",
                    v.x, v.y, p.angular_velocity
                )));
            }
            let outside = checks::depth_outside(&walls, &body.bounding_box());
            // Under the soft model a grain struck while lying on the floor can be pushed into
            // it by more than its thickness for a step or two (measured: a grain of rice 0.1
            // thick, 0.104 into the floor of `pour-100k.toml` at step 260), and the wall pushes
            // it out at a bounded speed: an awake grain is refused only beyond a wall by more
            // than twice its bounding radius. A sleeper is held to the paper's limit: the soft
            // step does not move it, so it would stay where the dump put it (found by a review).
            let (limit, fraction, of) = if settings.model == Model::Soft && !body.asleep(&settings)
            {
                let limit = checks::soft_outside_limit(&shape);
                (limit, checks::SOFT_OUTSIDE_FRACTION, "its bounding radius")
            } else {
                let limit = checks::DEPTH_FRACTION * shape.min_semi_axis();
                (limit, checks::DEPTH_FRACTION, "its smallest semi-axis")
            };
            if outside > limit {
                return Err(DumpError::Unworkable(format!(
                    "particle {index}: centre ({}, {}) puts it {outside:.3e} beyond the walls \
                     (left {}, right {}, floor {}), more than {fraction} x {of}",
                    p.center[0], p.center[1], w.left, w.right, w.floor,
                )));
            }
            // A grain that would cross the box a thousand times in one step (a hand-edited
            // previous position or velocity) is no state a run leaves: a previous centre at
            // x = 1e13 flung the grain out and overflowed the quadtree's stack at the first
            // step. Faster, but less absurd, grains are let run: the run then says which grain
            // left the box, or which position stopped being finite.
            let per_step = (body.center - body.previous_center)
                .norm()
                .max(body.velocity.norm() * settings.step)
                .max(v.norm() * settings.step);
            let width = w.right - w.left;
            if per_step.is_finite() && per_step > MAX_BOX_CROSSINGS * width {
                return Err(DumpError::Unworkable(format!(
                    "particle {index}: its previous centre or velocity moves it {per_step:.3e} \
                     in one step, more than {MAX_BOX_CROSSINGS} x the box's width ({width})"
                )));
            }
            bodies.push(body);
            velocities.push(v);
        }
        // The grains drawn: a dump's queue's waiting grains, or the whole list of an older dump.
        let (listed, old) = match &self.queue {
            Some(_) if !self.pending.is_empty() => {
                return Err(DumpError::Queue(
                    "a dump holds `queue` or, as dumps before the queue did, `pending`, not both"
                        .into(),
                ));
            }
            Some(q) => (&q.waiting, false),
            None => (&self.pending, true),
        };
        let mut waiting = VecDeque::with_capacity(listed.len());
        for (index, p) in listed.iter().enumerate() {
            let error = |error| {
                if old {
                    DumpError::Pending { index, error }
                } else {
                    DumpError::Waiting { index, error }
                }
            };
            let shape = Superellipse::new(p.semi_axes, p.exponents).map_err(error)?;
            Pose::new(Vec2::new(p.x, 0.0), p.angle).map_err(error)?;
            waiting.push_back(Pending {
                shape,
                x: p.x,
                angle: p.angle,
                due: p.due,
                group: p.group,
            });
        }
        let top = self.top.unwrap_or_else(|| {
            bodies
                .iter()
                .map(|b| b.bounding_box().max.y)
                .fold(w.floor + 1.0, f64::max)
        });
        if !top.is_finite() {
            return Err(DumpError::Walls(format!("top must be finite, got {top}")));
        }
        checks::check_box(&walls, top).map_err(DumpError::Walls)?;
        let between = self.queue.as_ref().and_then(|q| q.between);
        if let Some([x0, x1]) = between
            && !(walls.left <= x0 && x0 < x1 && x1 <= walls.right)
        {
            return Err(DumpError::Walls(format!(
                "queue: between = [{x0}, {x1}] must lie within the walls ({} to {}), its first \
                 number below its second",
                walls.left, walls.right
            )));
        }
        // Where the queue's grains appear across.
        let source = crate::world::narrowed(&walls, between);
        for (index, p) in waiting.iter().enumerate() {
            let what = if old {
                format!("pending grain {index}")
            } else {
                format!("queue: waiting grain {index}")
            };
            checks::check_fits(&source, top, p.shape.bounding_radius(), &what)
                .map_err(DumpError::Unworkable)?;
            // Drawn, its box is between the walls; as a particle's, a little beyond is let be.
            let pose = Pose::new(Vec2::new(p.x, top), p.angle)
                .map_err(|e| DumpError::Unworkable(format!("{what}: {e}")))?;
            let outside = checks::depth_outside(&source, &p.shape.bounding_box(&pose));
            if outside > checks::DEPTH_FRACTION * p.shape.min_semi_axis() {
                return Err(DumpError::Unworkable(format!(
                    "{what}: x = {} puts it {outside:.3e} beyond the walls (left {}, right {}), \
                     more than {} x its smallest semi-axis",
                    p.x,
                    w.left,
                    w.right,
                    checks::DEPTH_FRACTION
                )));
            }
        }
        let generator = match self.queue.as_ref().and_then(|q| q.generator.as_ref()) {
            Some(g) => generator_of(g, &source, top)?,
            None => None,
        };
        let fair = self
            .queue
            .as_ref()
            .and_then(|q| q.fair.as_ref())
            .map(|f| Fair {
                seed: f.seed,
                head: f.head,
                tries: f.tries,
            });
        let pending = Queue::from_parts(waiting, generator, fair, between);
        let smallest = bodies
            .iter()
            .map(|b| b.shape.min_semi_axis())
            .fold(pending.smallest_semi_axis(), f64::min);
        checks::check_sleep(&settings, smallest).map_err(DumpError::Unworkable)?;
        checks::check_slop(&settings, smallest).map_err(DumpError::Unworkable)?;
        if smallest.is_finite() {
            checks::check_time_step(&settings, top - w.floor, smallest)
                .map_err(DumpError::Unworkable)?;
            checks::check_eps(&settings, smallest).map_err(DumpError::Unworkable)?;
        }
        let materials = self
            .materials
            .iter()
            .enumerate()
            .map(|(g, m)| m.to_material(&format!("materials[{g}]")))
            .collect::<Result<Vec<_>, _>>()?;
        check_masses(&bodies, &pending, &materials)?;
        let wall_material = match &self.wall_material {
            None => Material::default(),
            Some(m) => m.to_material("wall_material")?,
        };
        let n = bodies.len();
        let mut ids = std::collections::HashSet::with_capacity(n);
        for (index, b) in bodies.iter().enumerate() {
            if b.id == BodyId::NEW {
                return Err(DumpError::Unworkable(format!(
                    "particle {index}: id {} is reserved (a body not yet in a world)",
                    b.id
                )));
            }
            if !ids.insert(b.id) {
                return Err(DumpError::Unworkable(format!(
                    "particle {index}: id {} is taken by an earlier particle",
                    b.id
                )));
            }
        }
        let implied = BodyId::after(bodies.iter().map(|b| b.id));
        let next_id = match self.next_id {
            None => implied,
            Some(n) if n >= implied.0 && n < BodyId::NEW.0 => BodyId(n),
            Some(n) => {
                return Err(DumpError::Unworkable(format!(
                    "next_id {n} must be above every particle's id (at least {implied}) and \
                     below {}",
                    BodyId::NEW
                )));
            }
        };
        let mut world = World::from_parts(bodies, walls, settings, self.step, top, pending);
        world.name_from(next_id);
        for (k, s) in self.sinks.iter().enumerate() {
            let [[x0, x1], [y0, y1]] = s.region;
            if !([x0, x1, y0, y1].iter().all(|v| v.is_finite()) && x0 < x1 && y0 < y1) {
                return Err(DumpError::Walls(format!(
                    "sinks[{k}]: region [[{x0}, {x1}], [{y0}, {y1}]] must be finite, each \
                     range's start below its end"
                )));
            }
            if !(s.mass.is_finite() && s.mass >= 0.0) {
                return Err(DumpError::Walls(format!(
                    "sinks[{k}]: mass must be finite and not negative, got {}",
                    s.mass
                )));
            }
            world.sinks.push(Sink {
                region: Aabb {
                    min: Vec2::new(x0, y0),
                    max: Vec2::new(x1, y1),
                },
                recycle: s.recycle,
                grains: s.grains,
                mass: s.mass,
            });
        }
        world.materials = materials;
        world.wall_material = wall_material;
        if !self.planes.is_empty() && !self.boundaries.is_empty() {
            return Err(DumpError::Walls(
                "planes and boundaries: a dump holds one or the other (planes only before \
                 boundaries)"
                    .into(),
            ));
        }
        let mut boundaries = Vec::new();
        for (k, p) in self.planes.iter().enumerate() {
            let plane = HalfPlane::new(Vec2::from(p.normal), p.offset)
                .map_err(|e| DumpError::Walls(format!("planes[{k}]: {e}")))?;
            boundaries.push((
                format!("planes[{k}]"),
                Boundary::Plane(plane),
                Drive::default(),
            ));
        }
        for (k, spec) in self.boundaries.iter().enumerate() {
            let name = format!("boundaries[{k}]");
            let pieces = spec
                .pieces()
                .map_err(|e| DumpError::Walls(format!("{name}: {e}")))?;
            let drive =
                Drive::from_spec(spec).map_err(|e| DumpError::Walls(format!("{name}: {e}")))?;
            boundaries.extend(pieces.into_iter().map(|b| (name.clone(), b, drive)));
        }
        if !boundaries.is_empty() && world.settings.model != Model::Soft {
            return Err(DumpError::Walls(format!(
                "{}: boundaries are the soft model's (\"model\": \"soft\"); the paper's \
                 projection has the box alone",
                boundaries[0].0
            )));
        }
        if boundaries.len() + 3 > MAX_WALLS {
            return Err(DumpError::Walls(format!(
                "at most {} boundaries, got {}",
                MAX_WALLS - 3,
                boundaries.len()
            )));
        }
        for (name, boundary, drive) in boundaries {
            if !world.pending.is_empty() {
                let radii = [
                    world.pending.smallest_bounding_radius(),
                    world.pending.largest_bounding_radius(),
                ];
                let (rule, thinnest) = (world.pending.rule(), world.pending.smallest_semi_axis());
                let walls = crate::world::narrowed(&world.walls, world.pending.between());
                checks::check_boundary(&boundary, &name, &walls, top, rule, radii, thinnest)
                    .map_err(DumpError::Walls)?;
            }
            world.bases.push(boundary);
            world.drives.push(drive);
            world.boundaries.push(boundary);
        }
        if let Some((at, time)) = self.clock {
            if at > self.step || !time.is_finite() || time < 0.0 {
                return Err(DumpError::Solver(format!(
                    "clock: [{at}, {time}] must be a step no later than the dump's ({}) and a \
                     finite time, 0 or more",
                    self.step
                )));
            }
            world.clock = (at, time);
        }
        world.place_boundaries();
        for (k, d) in self.drivers.iter().enumerate() {
            let bad = |why: String| DumpError::Unworkable(format!("drivers[{k}]: {why}"));
            let Some(body) = world.bodies.iter().find(|b| b.id == BodyId(d.id)) else {
                return Err(bad(format!("no particle has id {}", d.id)));
            };
            if body.kind != BodyKind::Kinematic {
                return Err(bad(format!(
                    "particle {} is not \"kind\": \"kinematic\"",
                    d.id
                )));
            }
            if world.drivers.iter().any(|o| o.id == body.id) {
                return Err(bad(format!("particle {} is driven twice", d.id)));
            }
            let drive = Drive::from_keys(d.turn.as_ref(), d.shake.as_ref(), None).map_err(bad)?;
            if drive.is_still() {
                return Err(bad("needs `turn` or `shake`".into()));
            }
            let base = Pose::new(Vec2::from(d.center), d.angle).map_err(|e| bad(e.to_string()))?;
            // Where the drive has it now is where the particle is (the run wrote both).
            let now = drive.pose_at(&base, world.time());
            let off = (now.center() - body.center).norm() + (now.angle() - body.angle).abs();
            let close = off <= 1e-9 * (1.0 + body.center.norm() + body.angle.abs());
            if !close {
                return Err(bad(format!(
                    "its drive has particle {} at ({}, {}) turned {} now, but the particle is \
                     at ({}, {}) turned {}",
                    d.id,
                    now.center().x,
                    now.center().y,
                    now.angle(),
                    body.center.x,
                    body.center.y,
                    body.angle
                )));
            }
            world.drivers.push(Driver {
                id: body.id,
                base,
                drive,
            });
        }
        if let Some(b) = world
            .bodies
            .iter()
            .find(|b| b.kind == BodyKind::Kinematic && !world.drivers.iter().any(|d| d.id == b.id))
        {
            return Err(DumpError::Unworkable(format!(
                "particle {}: \"kind\": \"kinematic\" needs its drive in \"drivers\"",
                b.id.0
            )));
        }
        if !world.drivers.is_empty() && world.settings.model != Model::Soft {
            return Err(DumpError::Unworkable(
                "drivers: driven grains are the soft model's (\"model\": \"soft\")".into(),
            ));
        }
        for (k, m) in self.measures.iter().enumerate() {
            if m.every == 0 {
                return Err(DumpError::Unworkable(format!(
                    "measures[{k}]: every must be at least 1"
                )));
            }
        }
        world.measures.clone_from(&self.measures);
        let (most, most_rolling) = impulse_limits(&world, &velocities);
        let mut seen = std::collections::HashMap::new();
        for (index, c) in self.contacts.iter().enumerate() {
            let bad = |why: &str| DumpError::Solver(format!("contacts[{index}]: {why}"));
            let key = match (c.b, c.wall) {
                (Some(b), None) if c.a < b && b < n => (c.a, b),
                (None, Some(w)) if c.a < n && w < 3 + world.boundaries.len() => (c.a, STATIC - w),
                _ => {
                    return Err(bad(
                        "needs grains a < b, or a grain a and a wall of the world",
                    ));
                }
            };
            // A dump writes each pair once (`kept_contacts`); a second entry would replace
            // the first's impulses unseen.
            if let Some(first) = seen.insert(key, index) {
                return Err(bad(&format!(
                    "the same contact as contacts[{first}] (a = {}, {})",
                    c.a,
                    match (c.b, c.wall) {
                        (Some(b), _) => format!("b = {b}"),
                        (_, w) => format!("wall = {}", w.unwrap_or_default()),
                    }
                )));
            }
            let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
            let normal = c.normal_impulse.unwrap_or_default();
            let tangent = c.tangent_impulse.unwrap_or_default();
            if !(finite(&normal) && finite(&tangent) && c.rolling_impulse.is_finite())
                || normal.iter().any(|&x| x < 0.0)
            {
                return Err(bad("impulses must be finite, normal ones >= 0"));
            }
            let largest = normal
                .iter()
                .chain(&tangent)
                .fold(0.0f64, |m, x| m.max(x.abs()));
            if largest > most || c.rolling_impulse.abs() > most_rolling {
                return Err(bad(&format!(
                    "an impulse of {} is more than the whole heap's momentum could give \
                     ({IMPULSE_MARGIN} x its mass x the fastest speed a step can reach: {} \
                     for a push, {} for rolling)",
                    checks::short(largest.max(c.rolling_impulse.abs())),
                    checks::short(most),
                    checks::short(most_rolling)
                )));
            }
            // A contact of the last step has its impulses written (`kept_contacts`); an entry
            // with nothing at all is one too (dumps before 2026-12-05 left zero impulses out).
            // An entry with only a warm start or a carried manifold is none: made one on
            // reading, it linked two sleepers that had not touched.
            let empty = c.warm.is_empty() && c.carried.is_none();
            if c.normal_impulse.is_some()
                || c.tangent_impulse.is_some()
                || c.rolling_impulse != 0.0
                || empty
            {
                world.soft.kept.insert(
                    key,
                    Kept {
                        normal,
                        tangent,
                        rolling: c.rolling_impulse,
                    },
                );
            }
            let point = |p: &[f64; 2]| {
                let v = Vec2::from(*p);
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(bad("warm points must be finite"))
                }
            };
            match c.warm.as_slice() {
                [] => {}
                [a1] => {
                    world
                        .soft
                        .warm
                        .insert(key, WarmStart::from_parts(point(a1)?, None));
                }
                [a1, a2] => {
                    world
                        .soft
                        .warm
                        .insert(key, WarmStart::from_parts(point(a1)?, Some(point(a2)?)));
                }
                _ => return Err(bad("warm holds one or two points")),
            }
            if let Some(k) = &c.carried {
                if c.b.is_none() {
                    return Err(bad("only a pair of grains carries a manifold"));
                }
                let carried = Carried::from_parts(k).map_err(bad)?;
                let radius = |i: usize| world.bodies[i].shape.bounding_radius();
                carried.fits(radius(key.0), radius(key.1)).map_err(bad)?;
                world.soft.carried.insert(key, carried);
            }
        }
        // The velocities the dump reports stay the world's until its next step.
        world.set_velocities(&velocities);
        // Grains deep in each other: put there by hand under the paper's model, whose
        // projection would fling them out. Under the soft model only between two sleepers,
        // which its step does not move: each contact's push-out is bounded (`push_out`, 3
        // units/s, though a grain pushed by many at once goes faster), and a fast grain's
        // impact leaves deeper overlaps for a step or two (measured: `pour-100k.toml` at step
        // 250, a disk 0.08 deep in a grain of rice whose smaller semi-axis is 0.115), so the
        // check refused dumps the run had written itself, its checkpoints among them.
        let soft = world.settings.model == Model::Soft;
        if soft && !world.bodies.iter().any(|b| b.asleep(&world.settings)) {
            // No pair of sleepers: nothing to test (the scan runs every pair's narrow phase).
            return Ok(world);
        }
        let mut deep = None;
        world.contacts(|t| {
            let Touch::Grains(i, j, p) = t else { return };
            if deep.is_some() {
                return;
            }
            let (a, b) = (&world.bodies[i], &world.bodies[j]);
            if soft {
                // Sleepers rest deeper in each other than the paper's limit: contacts keep the
                // solver's slop and give under load, and a needle is thin (60 needles of smallest
                // semi-axis 0.025-0.03 slept 0.56-0.79 of it deep, by `checks::overlap_depth`:
                // 9 of their 15 checkpoints were refused). No contact leaves a grain's centre
                // inside another, and a pair of sleepers is refused only then.
                if a.asleep(&world.settings) && b.asleep(&world.settings) {
                    let holds = |o: &Body, c: Vec2| o.shape.value(&o.pose(), c) < 0.0;
                    if holds(a, b.center) || holds(b, a.center) {
                        deep = Some(format!(
                            "particles {i} and {j} overlap so deep that one holds the other's \
                             centre, both asleep: not a state the solver leaves"
                        ));
                    }
                }
                return;
            }
            let thin = a.shape.min_semi_axis().min(b.shape.min_semi_axis());
            let limit = checks::DEPTH_FRACTION * thin;
            // The penetration vectors bound the depth from above; only a pair they do not
            // clear is measured (see `checks::overlap_depth`).
            if p.depth() <= limit {
                return;
            }
            let depth = checks::overlap_depth(a, b, &p, checks::DEPTH_TOLERANCE * thin);
            if depth > limit {
                deep = Some(format!(
                    "particles {i} and {j} overlap {depth:.3e} deep, more than {} x the smaller \
                     smallest semi-axis ({thin}): not a state the solver leaves",
                    checks::DEPTH_FRACTION
                ));
            }
        });
        if let Some(message) = deep {
            return Err(DumpError::Unworkable(message));
        }
        Ok(world)
    }
}

/// The soft step's kept contacts, in the order of their pairs (a dump is the same for the same
/// state).
fn kept_contacts(world: &World) -> Vec<ContactJson> {
    let soft = &world.soft;
    let mut keys: Vec<_> = soft
        .kept
        .keys()
        .chain(soft.warm.keys())
        .chain(soft.carried.keys())
        .copied()
        .collect();
    keys.sort_unstable();
    keys.dedup();
    keys.into_iter()
        .map(|key| {
            let (a, j) = key;
            let (b, wall) = if j > STATIC - MAX_WALLS {
                (None, Some(STATIC - j))
            } else {
                (Some(j), None)
            };
            let kept = soft.kept.get(&key);
            let nonzero = |x: [f64; 3]| (x != [0.0; 3]).then_some(x);
            ContactJson {
                a,
                b,
                wall,
                // Whenever the pair is kept, zeros too: a kept pair is a contact of the last
                // step (a sleeping island's link), which a pair with only a warm start is not.
                normal_impulse: kept.map(|k| k.normal),
                tangent_impulse: kept.and_then(|k| nonzero(k.tangent)),
                rolling_impulse: kept.map_or(0.0, |k| k.rolling),
                warm: soft.warm.get(&key).map_or(Vec::new(), |w| {
                    let (a1, a2) = w.to_parts();
                    std::iter::once(a1.to_array())
                        .chain(a2.map(Vec2::to_array))
                        .collect()
                }),
                carried: soft.carried.get(&key).map(Carried::to_parts),
            }
        })
        .collect()
}

/// How many times the whole heap's momentum a kept contact's impulse may be (see
/// [`impulse_limits`]).
const IMPULSE_MARGIN: f64 = 1000.0;

/// The largest impulses a kept contact of `world` may hold, a push and a rolling one:
/// [`IMPULSE_MARGIN`] times the grains' total mass times the fastest speed a step can bring
/// (a fall from the top, the fastest grain of the dump, a step's gravity and the contacts'
/// push-out), and for rolling times the largest bounding radius too. A contact's impulse over a
/// step is at most the weight it carries over the step plus the momentum it stops, both far
/// below this; `1e300` was accepted, and the first step flung the grains out.
fn impulse_limits(world: &World, velocities: &[Vec2]) -> (f64, f64) {
    let s = &world.settings;
    let mass: f64 = (0..world.bodies.len())
        .map(|i| world.material(i).mass_and_inertia(&world.bodies[i].shape).0)
        .sum();
    let fastest = velocities.iter().map(|v| v.norm()).fold(0.0, f64::max);
    let fall = (2.0 * s.gravity * (world.top - world.walls.floor).max(0.0)).sqrt();
    let speed = fall + fastest + s.gravity * s.step + s.soft.push_out;
    let reach = world
        .bodies
        .iter()
        .map(|b| b.shape.bounding_radius())
        .fold(0.0, f64::max);
    let most = IMPULSE_MARGIN * mass * speed;
    (most, most * reach)
}

/// Refuses a grain (a particle, a waiting grain, the extremes of a group still to draw) whose
/// material gives it a mass or moment of inertia out of [`checks::MASS_RANGE`].
fn check_masses(bodies: &[Body], pending: &Queue, materials: &[Material]) -> Result<(), DumpError> {
    let material = |group: u32| material_of(materials, group);
    for (index, b) in bodies.iter().enumerate() {
        checks::check_mass(&material(b.group), &b.shape)
            .map_err(|e| DumpError::Unworkable(format!("particle {index}: {e}")))?;
    }
    for (index, p) in pending.waiting().iter().enumerate() {
        checks::check_mass(&material(p.group), &p.shape)
            .map_err(|e| DumpError::Unworkable(format!("queue: waiting grain {index}: {e}")))?;
    }
    for (index, g) in pending
        .generator()
        .map_or(&[][..], |g| g.groups())
        .iter()
        .enumerate()
    {
        if g.count == 0 {
            continue;
        }
        let (least, largest) = g
            .extreme_shapes()
            .map_err(|e| DumpError::Queue(format!("generator: group {index}: {e}")))?;
        for shape in [least, largest] {
            checks::check_mass(&material(index as u32), &shape).map_err(|e| {
                DumpError::Unworkable(format!("queue: generator: group {index}: {e}"))
            })?;
        }
    }
    Ok(())
}

/// How many box widths a grain of a dump may move in one step (see [`Dump::to_world`]).
const MAX_BOX_CROSSINGS: f64 = 1000.0;

/// What a dump's absent solver key means: the model's default where the dump format always
/// wrote the key, and how the code ran before the key was written where it did not
/// (see [`Dump::solver`]).
fn legacy_settings(model: Model) -> Settings {
    let s = Settings::of_model(model);
    Settings {
        sleep_radius: 0.0,
        sleep_steps: 0,
        sleep_islands: false,
        shock_propagation: false,
        strip_width: 0.0,
        broad_phase: BroadPhaseKind::Grid,
        soft: SoftSettings {
            carry_reach: 0.0,
            ..s.soft
        },
        ..s
    }
}

/// The queue of a world, as JSON.
fn queue_json(queue: &Queue) -> QueueJson {
    let pair = |r: Range| [r.lo, r.hi];
    QueueJson {
        waiting: queue
            .waiting()
            .iter()
            .map(|p| PendingJson {
                semi_axes: p.shape.semi_axes().to_array(),
                exponents: p.shape.exponents(),
                x: p.x,
                angle: p.angle,
                due: p.due,
                group: p.group,
            })
            .collect(),
        generator: queue.generator().map(|g| GeneratorJson {
            seed: g.seed(),
            next: g.next(),
            spawn_interval: g.spawn_interval(),
            spawn_count: g.spawn_count(),
            groups: g
                .groups()
                .iter()
                .map(|group| GroupJson {
                    name: group.name.clone(),
                    remaining: group.count,
                    semi_axes: group.semi_axes.map(pair),
                    circles: group.circles,
                    exponents: group.exponents.map(pair),
                    same_exponents: group.same_exponents,
                    angle: pair(group.angle),
                })
                .collect(),
        }),
        fair: queue.fair().map(|f| FairJson {
            seed: f.seed,
            head: f.head,
            tries: f.tries,
        }),
        between: queue.between(),
    }
}

/// The grains a dump still has to draw, checked as a scene's groups are (see
/// [`crate::world::Scene::validate`]): ranges that can be drawn from, whose corners make valid
/// shapes that fit between the walls and appear above the floor, no more grains than the box
/// holds; and a count that cannot overflow the queue's index. Errors name the field.
fn generator_of(
    g: &GeneratorJson,
    walls: &Walls,
    top: f64,
) -> Result<Option<Generator>, DumpError> {
    let fail = |message: String| DumpError::Queue(format!("generator: {message}"));
    if g.spawn_count == 0 {
        return Err(fail("spawn_count must be at least 1".into()));
    }
    let mut groups = Vec::with_capacity(g.groups.len());
    let (mut remaining, mut area) = (0u64, 0.0);
    for (i, j) in g.groups.iter().enumerate() {
        let group_fail = |message: String| fail(format!("group {i} (`{}`): {message}", j.name));
        let range = |field: &str, [lo, hi]: [f64; 2]| {
            let r = Range::new(lo, hi);
            checks::check_range(r, field)
                .map(|()| r)
                .map_err(group_fail)
        };
        let group = Group {
            name: j.name.clone(),
            count: j.remaining,
            semi_axes: [
                range("semi_axes", j.semi_axes[0])?,
                range("semi_axes", j.semi_axes[1])?,
            ],
            circles: j.circles,
            exponents: [
                range("exponents", j.exponents[0])?,
                range("exponents", j.exponents[1])?,
            ],
            same_exponents: j.same_exponents,
            angle: range("angle", j.angle)?,
            // The queue draws shapes only; the groups' materials are the dump's `materials`.
            material: Material::default(),
        };
        // Fields named as the dump writes them (`semi_axes`, `exponents`), whatever the flags.
        let (least, largest) = group
            .extremes(|e| checks::shape_field(e, false, false))
            .map_err(group_fail)?;
        if group.count > 0 {
            checks::check_fits(walls, top, largest.bounding_radius(), "semi_axes")
                .map_err(group_fail)?;
            area += f64::from(group.count) * least.area();
        }
        remaining += u64::from(group.count);
        groups.push(group);
    }
    if g.next.checked_add(remaining).is_none() {
        return Err(fail(format!(
            "next ({}) plus the {remaining} grains still to draw overflows the queue's index",
            g.next
        )));
    }
    // The grains still to draw alone, as a scene's: a run's dump always passes.
    checks::check_capacity(walls, top, remaining, area).map_err(fail)?;
    Ok(Generator::new(
        g.seed,
        g.next,
        g.spawn_interval,
        g.spawn_count,
        *walls,
        groups,
    ))
}

//! Bodies: what a grain is (its shape, pose, velocity and scene group), what it is made of
//! ([`Material`], and how two materials mix in a contact), and the open box it is poured into.
//! The layer below the solvers: the world, the dumps, the pictures and the measures read these
//! without knowing how a step moves them.

use crate::contact::{Contact, Narrow, WallContact};
use crate::geometry::{Aabb, Vec2};
use crate::settings::Settings;
use crate::shape::{Boundary, BoundarySpec, HalfPlane, Pose, ShakeSpec, Superellipse, TurnSpec};

/// A body's name for as long as the world lives: given in the order bodies join it (the first
/// grain to appear is 0), never given again when a body leaves, kept in dumps. Trajectories,
/// VTK frames and the forces name grains by it, so a grain can be followed across frames and
/// across grains that leave.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct BodyId(pub u64);

impl BodyId {
    /// A body not yet in a world: the world names it when it joins ([`crate::world::World::add`],
    /// or the next step for one pushed onto `bodies`).
    pub const NEW: BodyId = BodyId(u64::MAX);

    /// The id after all of `ids` (those not [`BodyId::NEW`]): one past the largest, 0 for none.
    pub fn after(ids: impl Iterator<Item = BodyId>) -> BodyId {
        BodyId(
            ids.filter(|&id| id != BodyId::NEW)
                .map(|id| id.0 + 1)
                .max()
                .unwrap_or(0),
        )
    }
}

impl std::fmt::Display for BodyId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

/// How a body moves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyKind {
    /// Moved by gravity and its contacts.
    #[default]
    Dynamic,
    /// Never moves: held where it was placed, as a wall holds (an obstacle, a silo's floor
    /// either side of its orifice, a hopper's sides). The solvers treat it as a sleeper that
    /// nothing wakes: no gravity, no mass, in no island.
    Static,
    /// Moved by its drive ([`Driver`]): a paddle turning, a piston shaken. Its place at every
    /// step is a closed form of its place at step 0, and the soft step sees its velocity with no
    /// mass and no gravity: it pushes and drags the grains it meets, which do not push it back.
    /// Never asleep, in no island; grains near it while it moves stay awake.
    Kinematic,
}

impl BodyKind {
    pub fn is_dynamic(&self) -> bool {
        *self == BodyKind::Dynamic
    }
}

/// A grain: its shape, where it is and where it was one step ago (Verlet keeps velocity
/// implicit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    /// Its stable name ([`BodyId`]); [`BodyId::NEW`] until it joins a world.
    pub id: BodyId,
    pub kind: BodyKind,
    pub shape: Superellipse,
    pub center: Vec2,
    pub angle: f64,
    pub previous_center: Vec2,
    pub previous_angle: f64,
    /// Steps in a row the grain has stayed within [`Settings::sleep_radius`] of `anchor`; at
    /// [`Settings::sleep_steps`] it is asleep.
    pub calm: u32,
    pub anchor: Vec2,
    /// Where the grain was when it last woke the sleepers by it for drifting: once it is
    /// [`crate::solver::DRIFT_WAKE`] sleep radii away, however slowly it went, it wakes them again.
    pub drift_anchor: Vec2,
    /// Steps the grain has been ready to sleep while a neighbour was not (see `update_sleep`).
    pub waiting: u32,
    /// The scene group the grain came from, counted from 0 in the scene's order (0 for grains
    /// made otherwise). The paper's solver ignores it; the soft step takes the group's
    /// material; pictures can colour by it.
    pub group: u32,
    /// Linear and angular velocity: state of the soft step ([`crate::settings::Model::Soft`]); the paper's
    /// Verlet keeps velocity implicit and leaves these at 0.
    pub velocity: Vec2,
    pub angular_velocity: f64,
}

impl Body {
    /// A body at rest.
    pub fn at_rest(shape: Superellipse, pose: &Pose) -> Self {
        Body {
            id: BodyId::NEW,
            kind: BodyKind::Dynamic,
            shape,
            center: pose.center(),
            angle: pose.angle(),
            previous_center: pose.center(),
            previous_angle: pose.angle(),
            calm: 0,
            anchor: pose.center(),
            drift_anchor: pose.center(),
            waiting: 0,
            group: 0,
            velocity: Vec2::ZERO,
            angular_velocity: 0.0,
        }
    }

    /// Whether the solvers hold the grain still: a static body always, a dynamic one when it
    /// sleeps under these settings.
    pub fn asleep(&self, settings: &Settings) -> bool {
        match self.kind {
            BodyKind::Static => true,
            BodyKind::Kinematic => false,
            BodyKind::Dynamic => settings.sleep_radius > 0.0 && self.calm >= settings.sleep_steps,
        }
    }

    pub fn is_static(&self) -> bool {
        self.kind == BodyKind::Static
    }

    pub fn pose(&self) -> Pose {
        Pose::from_parts(self.center, self.angle)
    }

    pub fn bounding_box(&self) -> Aabb {
        self.shape.bounding_box(&self.pose())
    }

    /// Its contact with `other` at their poses, as `narrow` answers it (the overlap's middle,
    /// as the paper's projection reads it): what the checks of a state and the pictures use.
    pub fn contact(&self, other: &Body, narrow: &Narrow) -> Contact {
        narrow.pair_midpoints(
            &self.shape,
            &self.pose(),
            &other.shape,
            &other.pose(),
            &mut None,
        )
    }

    /// Its contact with `wall` at its pose, as `narrow` answers it.
    pub fn wall_contact(&self, wall: &Boundary, narrow: &Narrow) -> WallContact {
        narrow.wall(&self.shape, &self.pose(), wall)
    }

    pub fn is_finite(&self) -> bool {
        self.center.is_finite()
            && self.angle.is_finite()
            && self.previous_center.is_finite()
            && self.previous_angle.is_finite()
            && self.velocity.is_finite()
            && self.angular_velocity.is_finite()
    }
}

/// The open box (paper III-B, Fig. 8).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walls {
    pub left: f64,
    pub right: f64,
    pub floor: f64,
}

impl Walls {
    /// The three walls as boundaries: left, right, floor.
    pub fn boundaries(&self) -> [Boundary; 3] {
        [
            HalfPlane::left(self.left),
            HalfPlane::right(self.right),
            HalfPlane::floor(self.floor),
        ]
        .map(|w| Boundary::Plane(w.expect("finite walls")))
    }
}

/// What a grain (or a wall) is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Mass per unit area.
    pub density: f64,
    /// Coulomb's coefficient: the tangential impulse at a point is at most `friction` times
    /// the normal one.
    pub friction: f64,
    /// The ratio of the speeds apart and together along the normal after an impact faster
    /// than [`crate::settings::SoftSettings::restitution_threshold`].
    pub restitution: f64,
    /// The rolling-friction coefficient `mu_r`: the torque resisting the relative rolling of
    /// two grains is at most `mu_r R F_n`, `R` the contact's mean lever arm (DEM's "type A"
    /// rolling resistance, as Box2D v3's `rollingResistance`). Without it poured disks roll
    /// flat.
    pub rolling_resistance: f64,
}

impl Default for Material {
    /// Density 1, friction 0.6 and no restitution or rolling resistance: Box2D's defaults.
    fn default() -> Self {
        Material {
            density: 1.0,
            friction: 0.6,
            restitution: 0.0,
            rolling_resistance: 0.0,
        }
    }
}

impl Material {
    /// The mass (`density` times the area) and the moment of inertia about the centre of a
    /// grain of `shape` made of this material: what the soft step uses, and what the
    /// trajectory reports.
    pub fn mass_and_inertia(&self, shape: &Superellipse) -> (f64, f64) {
        let mass = self.density * shape.area();
        (mass, shape.moment_of_inertia(mass))
    }

    /// Whether every number is in its range (the scene file's: density finite and positive,
    /// friction and rolling resistance finite and not negative, restitution in `[0, 1]`); the
    /// error names the first that is not.
    pub fn validate(&self) -> Result<(), String> {
        let bad = |field: &str, v: f64| Err(format!("{field} is out of range, got {v}"));
        if !(self.density.is_finite() && self.density > 0.0) {
            return bad("density", self.density);
        }
        if !(self.friction.is_finite() && self.friction >= 0.0) {
            return bad("friction", self.friction);
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return bad("restitution", self.restitution);
        }
        if !(self.rolling_resistance.is_finite() && self.rolling_resistance >= 0.0) {
            return bad("rolling_resistance", self.rolling_resistance);
        }
        Ok(())
    }
}

/// The material of a grain of `group`: `materials[group]`, or past the table's end its last
/// entry, or the default for an empty table.
pub fn material_of(materials: &[Material], group: u32) -> Material {
    materials
        .get(group as usize)
        .or(materials.last())
        .copied()
        .unwrap_or_default()
}

/// Two materials in contact: friction is the geometric mean, restitution and rolling
/// resistance the larger (Box2D's rules: a frictionless grain slides on anything, a bouncy one
/// bounces on anything).
pub(crate) fn mix(a: &Material, b: &Material) -> (f64, f64, f64) {
    // (Each root taken alone where the product overflows: two frictions of 1e200 mixed to
    // infinity, and infinity times a point's zero normal impulse bounded its friction by NaN.)
    let product = a.friction * b.friction;
    (
        if product.is_finite() {
            product.sqrt()
        } else {
            a.friction.sqrt() * b.friction.sqrt()
        },
        a.restitution.max(b.restitution),
        a.rolling_resistance.max(b.rolling_resistance),
    )
}

/// How a wall moves over a step (issue 41's driven boundaries): the velocity of its point `p`
/// is `v + w x (p - pivot)`, `pivot` where it is at the step's end. A still wall's is zero.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WallMotion {
    pub v: Vec2,
    pub w: f64,
    pub pivot: Vec2,
}

impl WallMotion {
    /// Whether it moves at all.
    pub fn moves(&self) -> bool {
        self.v != Vec2::ZERO || self.w != 0.0
    }
}

/// How a boundary is driven (issue 41): turned about a point at a rate (a drum, a tumbler),
/// shaken along a line (a vibrated floor), its surface moving along it (a conveyor belt), or
/// any of these together; none: still. Its place at time `t` is a closed form of its place at
/// `t = 0` ([`Drive::place`]), so a run resumed from a dump at step `k` puts it where the
/// uninterrupted run has it, bit for bit.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Drive {
    /// About `.0`, at `.1` degrees per second, counter-clockwise.
    pub turn: Option<(Vec2, f64)>,
    /// Displaced by `.0 sin(2 pi .1 t)` (`.1` in hertz).
    pub shake: Option<(Vec2, f64)>,
    /// The surface's speed along it (from a segment's first end to its second; counter-clockwise
    /// round an arc or a circle); the shape does not move for it.
    pub belt: f64,
}

impl Drive {
    /// From a `[[boundary]]` table's `turn`, `shake` and `belt`, checked.
    pub fn from_spec(spec: &BoundarySpec) -> Result<Drive, String> {
        Drive::from_keys(spec.turn.as_ref(), spec.shake.as_ref(), spec.belt)
    }

    /// From the keys `turn`, `shake` and `belt` (a boundary's or a driven grain's), checked.
    pub fn from_keys(
        turn: Option<&TurnSpec>,
        shake: Option<&ShakeSpec>,
        belt: Option<f64>,
    ) -> Result<Drive, String> {
        let two = |what: &str, v: &[f64]| match v {
            [x, y] if x.is_finite() && y.is_finite() => Ok(Vec2::new(*x, *y)),
            _ => Err(format!("{what} needs two finite numbers [x, y], got {v:?}")),
        };
        let turn = match turn {
            Some(t) if t.rate.is_finite() => Some((two("turn's about", &t.about)?, t.rate)),
            Some(t) => return Err(format!("turn's rate must be finite, got {}", t.rate)),
            None => None,
        };
        let shake = match shake {
            Some(s) if s.frequency.is_finite() && s.frequency >= 0.0 => {
                Some((two("shake's amplitude", &s.amplitude)?, s.frequency))
            }
            Some(s) => {
                return Err(format!(
                    "shake's frequency must be a finite number >= 0, got {}",
                    s.frequency
                ));
            }
            None => None,
        };
        let belt = belt.unwrap_or(0.0);
        if !belt.is_finite() {
            return Err(format!("belt must be a finite speed, got {belt}"));
        }
        Ok(Drive { turn, shake, belt })
    }

    /// Writes its keys into a boundary's table.
    pub fn write(&self, spec: &mut BoundarySpec) {
        spec.turn = self.turn.map(|(about, rate)| TurnSpec {
            about: vec![about.x, about.y],
            rate,
        });
        spec.shake = self.shake.map(|(amplitude, frequency)| ShakeSpec {
            amplitude: vec![amplitude.x, amplitude.y],
            frequency,
        });
        spec.belt = (self.belt != 0.0).then_some(self.belt);
    }

    pub fn is_still(&self) -> bool {
        self.turn.is_none() && self.shake.is_none() && self.belt == 0.0
    }

    /// The shake's displacement at time `t`.
    fn offset(&self, t: f64) -> Vec2 {
        match self.shake {
            Some((a, f)) => a * (std::f64::consts::TAU * f * t).sin(),
            None => Vec2::ZERO,
        }
    }

    /// Where `base` (its place at `t = 0`) is at time `t`: turned about the pivot, then
    /// shaken. Unmoved (the same bits) when neither.
    pub fn place(&self, base: &Boundary, t: f64) -> Boundary {
        if self.turn.is_none() && self.shake.is_none() {
            return *base;
        }
        let (pivot, angle) = self
            .turn
            .map_or((Vec2::ZERO, 0.0), |(p, rate)| (p, (rate * t).to_radians()));
        base.moved(pivot, angle, self.offset(t))
    }

    /// Where a driven grain placed at `base` at `t = 0` is at time `t`: its centre turned about
    /// the pivot and its angle by the same turn, then shaken ([`Self::place`]'s motion).
    pub fn pose_at(&self, base: &Pose, t: f64) -> Pose {
        if self.turn.is_none() && self.shake.is_none() {
            return *base;
        }
        let (pivot, angle) = self
            .turn
            .map_or((Vec2::ZERO, 0.0), |(p, rate)| (p, (rate * t).to_radians()));
        let turned = pivot + crate::geometry::Rotation::new(angle).apply(base.center() - pivot);
        Pose::from_parts(turned + self.offset(t), base.angle() + angle)
    }

    /// The fastest a point of a driven grain centred at `center`, reaching `reach` from it, ever
    /// moves: its turn's rate times its farthest point's distance from the pivot, plus the
    /// shake's peak speed `2 pi f |A|`.
    pub fn peak_speed(&self, center: Vec2, reach: f64) -> f64 {
        let turn = self.turn.map_or(0.0, |(pivot, rate)| {
            rate.to_radians().abs() * ((center - pivot).norm() + reach)
        });
        let shake = self
            .shake
            .map_or(0.0, |(a, f)| std::f64::consts::TAU * f * a.norm());
        turn + shake
    }

    /// Writes its keys into a driven grain's record (a dump's `drivers`).
    pub fn keys(&self) -> (Option<TurnSpec>, Option<ShakeSpec>) {
        let mut spec = BoundarySpec::default();
        self.write(&mut spec);
        (spec.turn, spec.shake)
    }

    /// Its motion over the step from `t` to `t + h`, for the solver: the shake's mean velocity
    /// (so that the substeps end where [`Self::place`] puts it), the turn's rate, and the
    /// belt's speed as a velocity of the surface ([`WallMotion`], about the pivot at `t + h`).
    /// `now`: the boundary where [`Self::place`] puts it at `t + h`.
    pub fn motion(&self, now: &Boundary, t: f64, h: f64) -> WallMotion {
        if self.is_still() {
            return WallMotion::default();
        }
        let mut v = (self.offset(t + h) - self.offset(t)) * (1.0 / h);
        let mut w = self.turn.map_or(0.0, |(_, rate)| rate.to_radians());
        let pivot = self.turn.map_or(Vec2::ZERO, |(p, _)| p) + self.offset(t + h);
        match *now {
            Boundary::Segment { a, b, .. } => {
                v += (b - a).direction().unwrap_or(Vec2::ZERO) * self.belt;
            }
            Boundary::Arc { center, r, .. } | Boundary::Circle { center, r, .. } => {
                // A surface speed round a circle is a turn about its centre:
                // (belt / r) x (p - centre) = (belt / r) x (p - pivot) + (belt / r) x (pivot - centre).
                let spin = self.belt / r;
                w += spin;
                let d = pivot - center;
                v += Vec2::new(-spin * d.y, spin * d.x);
            }
            Boundary::Plane(plane) => {
                let n = plane.normal();
                v += Vec2::new(n.y, -n.x) * self.belt;
            }
        }
        WallMotion { v, w, pivot }
    }
}

/// A driven grain ([`BodyKind::Kinematic`]): its id, where it was at step 0, and its drive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Driver {
    pub id: BodyId,
    pub base: Pose,
    pub drive: Drive,
}

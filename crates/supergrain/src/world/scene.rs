//! Scenes: the box, the spawn rule, groups of grains, the solver settings, the seed and the
//! number of steps; from a TOML file or one of the paper's four presets (paper IV, Figs. 10-13).

use std::f64::consts::TAU;
use std::fmt;

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};

use super::Sink;
use super::checks;
use super::spawn::{BAND_IN_RADII, SpawnRule};
use crate::body::{Body, BodyKind, Drive, Material, Walls, material_of};
use crate::contact::NarrowPhase;
use crate::geometry::{Aabb, Vec2};
use crate::measure::series::{Series, SeriesKind};
use crate::settings::{Model, Settings, SoftSettings, SolverTable};
use crate::shape::{Boundary, BoundarySpec, HalfPlane, Pose, ShapeError, Superellipse};

/// A closed range `[lo, hi]` of values drawn uniformly, or one fixed value (`lo == hi`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Range {
    pub lo: f64,
    pub hi: f64,
}

impl Range {
    pub const fn fixed(v: f64) -> Self {
        Range { lo: v, hi: v }
    }

    pub const fn new(lo: f64, hi: f64) -> Self {
        Range { lo, hi }
    }
}

/// A group of grains drawn from the same ranges.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    pub name: String,
    pub count: u32,
    /// Semi-axes; for circles both come from one draw.
    pub semi_axes: [Range; 2],
    pub circles: bool,
    pub exponents: [Range; 2],
    /// Both exponents from one draw (squircles), or independent (the mixed preset).
    pub same_exponents: bool,
    pub angle: Range,
    /// What the grains are made of (the soft step's; the paper's model ignores it).
    pub material: Material,
}

impl Group {
    /// The smallest and the largest shapes the group can draw (every range at its low end, and
    /// at its high end), after checking that every corner of the ranges makes a valid shape: the
    /// shape's limits are monotone in each number, so the corners bound every draw. An error
    /// names the field (`radius`, `semi_axes`, `exponent`, `exponents`).
    pub fn extreme_shapes(&self) -> Result<(Superellipse, Superellipse), String> {
        self.extremes(|err| checks::shape_field(err, self.circles, self.same_exponents))
    }

    /// [`Group::extreme_shapes`], its errors naming the field `field` gives for the shape error.
    pub(crate) fn extremes(
        &self,
        field: impl Fn(&ShapeError) -> &'static str,
    ) -> Result<(Superellipse, Superellipse), String> {
        let [sx, sy] = self.semi_axes;
        let [ex, ey] = self.exponents;
        let ends = |r: Range| [r.lo, r.hi];
        let make = |s: [f64; 2], e: [f64; 2]| {
            Superellipse::new(s, e).map_err(|err| {
                let field = field(&err);
                format!(
                    "{field}: the range's extreme semi-axes {s:?} with exponents {e:?} make no \
                     valid shape: {err}"
                )
            })
        };
        for a in ends(sx) {
            for b in if self.circles { [a, a] } else { ends(sy) } {
                for p in ends(ex) {
                    for q in if self.same_exponents {
                        [p, p]
                    } else {
                        ends(ey)
                    } {
                        make([a, b], [p, q])?;
                    }
                }
            }
        }
        let sy_lo = if self.circles { sx.lo } else { sy.lo };
        let sy_hi = if self.circles { sx.hi } else { sy.hi };
        let ey_lo = if self.same_exponents { ex.lo } else { ey.lo };
        let ey_hi = if self.same_exponents { ex.hi } else { ey.hi };
        Ok((
            make([sx.lo, sy_lo], [ex.lo, ey_lo])?,
            make([sx.hi, sy_hi], [ex.hi, ey_hi])?,
        ))
    }
}

/// A whole scene, validated.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub seed: u64,
    pub steps: u64,
    pub walls: Walls,
    /// Height at which grains appear.
    pub top: f64,
    /// Steps between two spawns.
    pub spawn_interval: u32,
    /// Grains due at each spawn (each at its own random place; one whose place is taken waits).
    pub spawn_count: u32,
    /// How due grains appear when their place is taken (`[spawn] rule`; see [`SpawnRule`]).
    pub spawn_rule: SpawnRule,
    /// Where grains appear across, `[x0, x1]` within the walls (`[spawn] between`); `None`:
    /// between the walls.
    pub spawn_between: Option<[f64; 2]>,
    pub settings: Settings,
    pub groups: Vec<Group>,
    /// What the walls are made of (the soft step's).
    pub wall_material: Material,
    /// Boundaries besides the box's walls (`[[plane]]`, then `[[boundary]]`, a polyline one per
    /// segment; the soft step's), of the walls' material.
    pub boundaries: Vec<Boundary>,
    /// Each boundary's name in messages: `plane 2`, `boundary 3`, `boundary 4, segment 2`.
    pub boundary_names: Vec<String>,
    /// How each boundary is driven (`turn`, `shake`, `belt`; still by default).
    pub drives: Vec<Drive>,
    /// Grains placed by the file (`[[grain]]`), there from step 0, before any of the groups'.
    pub grains: Vec<Placed>,
    /// Where grains leave (`[[sink]]`).
    pub sinks: Vec<Sink>,
    /// Measures taken as the run goes (`[[measure]]`).
    pub measures: Vec<Series>,
}

/// How deep a placed grain may be in a wall or another placed grain, as a fraction of its
/// smallest semi-axis (of the thinner of a pair): grains placed touching, as computed by hand,
/// are not refused for their rounding.
pub const PLACED_TOLERANCE: f64 = 1e-6;

/// A grain placed by a scene file (`[[grain]]`): its shape, pose and velocity, and the
/// `[[group]]` whose material and colour it takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placed {
    pub shape: Superellipse,
    pub pose: Pose,
    /// Units per second; under the paper's model, the first step's displacement over the step.
    pub velocity: Vec2,
    /// Radians per second (the soft model's; the paper's projection keeps none).
    pub angular_velocity: f64,
    /// Its group, counted from 0 in the scene's order (0 when the table names none).
    pub group: u32,
    /// The line of its `[[grain]]` table (0 for a grain made otherwise), for errors.
    pub line: usize,
    /// Held where it is for good (`fixed = true`): a [`BodyKind::Static`] body.
    pub fixed: bool,
    /// Moved by a drive (`turn`, `shake`): a [`BodyKind::Kinematic`] body.
    pub drive: Option<Drive>,
}

/// The paper's four scenes.
pub const PRESETS: [&str; 4] = ["circles", "ellipses", "squircles", "mixed"];

/// Why a scene cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{0}")]
    Toml(String),
    #[error("line {line}: {message}")]
    Invalid { line: usize, message: String },
    #[error("the analytic narrow phase needs circles only, but group `{0}` is not circles")]
    NotCircles(String),
    #[error("unknown preset `{0}`; the presets are circles, ellipses, squircles and mixed")]
    UnknownPreset(String),
    /// A group whose ranges draw grains that cannot be made or cannot work in the box.
    #[error("group `{group}`: {message}")]
    Group { group: String, message: String },
    /// Settings, box or spawn rule that cannot work together.
    #[error("{0}")]
    Unworkable(String),
    /// A placed grain (`[[grain]]`, counted from 1) that cannot be where it is.
    #[error("line {line}: grain {grain}: {message}")]
    Grain {
        line: usize,
        grain: usize,
        message: String,
    },
}

impl Placed {
    /// The grain as a body (not yet named: the world names it when it joins), with its
    /// velocity as the soft model keeps it (the world gives the paper's Verlet its previous
    /// pose instead: [`super::World::new`]).
    pub fn body(&self) -> Body {
        Body {
            group: self.group,
            kind: if self.fixed {
                BodyKind::Static
            } else if self.drive.is_some() {
                BodyKind::Kinematic
            } else {
                BodyKind::Dynamic
            },
            velocity: self.velocity,
            angular_velocity: self.angular_velocity,
            ..Body::at_rest(self.shape, &self.pose)
        }
    }
}

impl Scene {
    /// One of the paper's scenes (SPEC §5 table) in an 8 x 10 box, 3,000 steps.
    pub fn preset(name: &str) -> Result<Scene, SceneError> {
        let angle = Range::new(0.0, TAU);
        let group = |count, semi_axes, circles, exponents, same_exponents| Group {
            name: name.to_string(),
            count,
            semi_axes,
            circles,
            exponents,
            same_exponents,
            angle,
            material: Material::default(),
        };
        let two = [Range::fixed(2.0); 2];
        let g = match name {
            "circles" => group(35, [Range::new(0.3, 0.7); 2], true, two, true),
            "ellipses" => group(
                35,
                [Range::new(0.1, 0.8), Range::new(0.1, 0.9)],
                false,
                two,
                true,
            ),
            "squircles" => group(
                40,
                [Range::new(0.3, 0.4), Range::new(0.3, 0.7)],
                false,
                [Range::fixed(4.0); 2],
                true,
            ),
            "mixed" => group(
                40,
                [Range::new(0.3, 0.4), Range::new(0.3, 0.7)],
                false,
                [Range::new(0.5, 4.0); 2],
                false,
            ),
            other => return Err(SceneError::UnknownPreset(other.to_string())),
        };
        Ok(Scene {
            seed: 1,
            steps: 3000,
            walls: Walls {
                left: -4.0,
                right: 4.0,
                floor: 0.0,
            },
            top: 10.0,
            spawn_interval: 20,
            spawn_count: 1,
            spawn_between: None,
            spawn_rule: SpawnRule::Queue,
            settings: Settings {
                strip_width: auto_strip_width(std::slice::from_ref(&g)),
                ..Settings::default()
            },
            groups: vec![g],
            grains: Vec::new(),
            sinks: Vec::new(),
            measures: Vec::new(),
            wall_material: Material::default(),
            boundaries: Vec::new(),
            boundary_names: Vec::new(),
            drives: Vec::new(),
        })
    }

    /// A scene from the text of a TOML file; errors name the line and the key.
    pub fn from_toml(text: &str) -> Result<Scene, SceneError> {
        let file: SceneFile = toml::from_str(text)
            .map_err(|e| SceneError::Toml(e.to_string().trim_end().to_string()))?;
        // (Counted by line ends before the span: a table's span starts at the head of its
        // line, where counting the lines before it named the line above.)
        let line_of = |span: std::ops::Range<usize>| {
            text.as_bytes()[..span.start.min(text.len())]
                .iter()
                .filter(|&&c| c == b'\n')
                .count()
                + 1
        };
        let invalid = |span: std::ops::Range<usize>, message: String| SceneError::Invalid {
            line: line_of(span),
            message,
        };
        let b = &file.bounds;
        if b.left.get_ref().0 >= b.right.get_ref().0 {
            return Err(invalid(
                b.right.span(),
                format!(
                    "box: right ({}) must be greater than left ({})",
                    b.right.get_ref().0,
                    b.left.get_ref().0
                ),
            ));
        }
        if b.floor.get_ref().0 >= b.top.get_ref().0 {
            return Err(invalid(
                b.top.span(),
                format!(
                    "box: top ({}) must be above floor ({})",
                    b.top.get_ref().0,
                    b.floor.get_ref().0
                ),
            ));
        }
        // A scene file that does not say gets the rigid-body solver (issue 18); the presets,
        // and `Settings::default()` for programs, keep the paper's.
        let solver_line = file.solver.as_ref().map_or(0..0, |t| t.span());
        let s = file
            .solver
            .as_ref()
            .map(|t| t.get_ref().clone())
            .unwrap_or_default();
        if s.has_legacy_soft() {
            return Err(invalid(
                solver_line.clone(),
                "solver: unknown key `soft` (a dump's old form): write the soft step's keys in \
                 [solver] itself"
                    .into(),
            ));
        }
        let mut settings = s
            .settings(Model::Soft, Settings::of_model)
            .map_err(|e| invalid(solver_line.clone(), format!("solver: {e}")))?;
        let model = settings.model;
        // The paper's projection moves grains by geometry alone, with no masses, friction or
        // bounce: a material key under it would be accepted and do nothing (issue 40).
        if model == Model::Paper {
            let tables = file
                .groups
                .iter()
                .enumerate()
                .map(|(k, g)| {
                    let name = g.name.clone().unwrap_or_else(|| format!("group {}", k + 1));
                    (format!("group `{name}`"), g.material_spec())
                })
                .chain(std::iter::once(("box".to_string(), b.material_spec())));
            for (table, spec) in tables {
                if let Some((key, span)) = spec.first_key() {
                    return Err(invalid(
                        span,
                        format!(
                            "{table}: `{key}` does nothing under [solver] model = \"paper\" (the \
                             paper's projection has no masses, friction or bounce): remove it, \
                             or use model = \"soft\", whose step uses it"
                        ),
                    ));
                }
            }
        }
        let mut groups = Vec::new();
        for (k, g) in file.groups.iter().enumerate() {
            let name = g.name.clone().unwrap_or_else(|| format!("group {}", k + 1));
            let pair = |field: &str, v: &toml::Spanned<Vec<PositiveRange>>| match v.get_ref()[..] {
                [x, y] => Ok([x.0, y.0]),
                _ => Err(invalid(
                    v.span(),
                    format!(
                        "group `{name}`: {field} needs two entries [x, y] (each a number or a \
                         range [lo, hi]), got {}",
                        v.get_ref().len()
                    ),
                )),
            };
            let (semi_axes, circles) = match (&g.radius, &g.semi_axes) {
                (Some(r), None) => ([r.0; 2], true),
                (None, Some(s)) => (pair("semi_axes", s)?, false),
                _ => {
                    return Err(invalid(
                        g.count.span(),
                        format!(
                            "group `{name}`: give either `radius` (circles) or `semi_axes`, not both or neither"
                        ),
                    ));
                }
            };
            let (exponents, same_exponents) = match (&g.exponent, &g.exponents) {
                (Some(e), None) => ([e.0; 2], true),
                (None, Some(e)) => (pair("exponents", e)?, false),
                (None, None) => ([Range::fixed(2.0); 2], true),
                _ => {
                    return Err(invalid(
                        g.count.span(),
                        format!(
                            "group `{name}`: give `exponent` (both the same) or `exponents`, not both"
                        ),
                    ));
                }
            };
            groups.push(Group {
                name,
                count: *g.count.get_ref(),
                semi_axes,
                circles,
                exponents,
                same_exponents,
                angle: g.angle.map_or(Range::new(0.0, TAU), |a| a.0),
                material: g.material_spec().material(),
            });
        }
        if let Some(f) = s.max_overlap {
            let width = b.right.get_ref().0 - b.left.get_ref().0;
            settings.soft = stiffness_for(f, &s, &settings, &groups, width)
                .map_err(|message| invalid(solver_line.clone(), message))?;
        }
        let spawn_count = match file.spawn.as_ref().and_then(|s| s.count.as_ref()) {
            None => 1,
            Some(c) if *c.get_ref() == 0 => {
                return Err(invalid(c.span(), "spawn: count must be at least 1".into()));
            }
            Some(c) => *c.get_ref(),
        };
        let mut spawn_interval = file
            .spawn
            .as_ref()
            .and_then(|s| s.interval.as_ref())
            .map_or(20, |i| *i.get_ref());
        let mut spawn_count = spawn_count;
        if let Some(r) = file.spawn.as_ref().and_then(|s| s.rate.as_ref()) {
            let spec = file.spawn.as_ref().expect("a [spawn] table");
            if spec.interval.is_some() || spec.count.is_some() {
                return Err(invalid(
                    r.span(),
                    "spawn: give rate, or interval and count, not both".into(),
                ));
            }
            let rate = *r.get_ref();
            // Grains per step: a whole number a step from one a step up, one every so many
            // steps below (the rate is then `1 / (interval step)`, rounded to whole steps).
            let per_step = rate * settings.step;
            if !(rate.is_finite() && rate > 0.0 && per_step <= f64::from(u32::MAX)) {
                return Err(invalid(
                    r.span(),
                    format!(
                        "spawn: rate must be a positive number of grains per second, got {rate}"
                    ),
                ));
            }
            (spawn_interval, spawn_count) = if per_step >= 1.0 {
                (1, per_step.round() as u32)
            } else {
                ((1.0 / per_step).round().min(f64::from(u32::MAX)) as u32, 1)
            };
        }
        let spawn_between = match file.spawn.as_ref().and_then(|s| s.between.as_ref()) {
            None => None,
            Some(v) => {
                let (left, right) = (b.left.get_ref().0, b.right.get_ref().0);
                match v.get_ref()[..] {
                    [x0, x1] if left <= x0.0 && x0.0 < x1.0 && x1.0 <= right => Some([x0.0, x1.0]),
                    [x0, x1] => {
                        return Err(invalid(
                            v.span(),
                            format!(
                                "spawn: between = [{}, {}] must lie within the walls ({left} to \
                                 {right}), its first number below its second",
                                x0.0, x1.0
                            ),
                        ));
                    }
                    _ => {
                        return Err(invalid(
                            v.span(),
                            format!(
                                "spawn: between needs two numbers [x0, x1], got {}",
                                v.get_ref().len()
                            ),
                        ));
                    }
                }
            }
        };
        // The fair rule with the soft model; the paper's keeps the rule its runs were made with.
        let spawn_rule = match file.spawn.as_ref().and_then(|s| s.rule.as_ref()) {
            None if settings.model == Model::Soft => SpawnRule::Fair,
            None => SpawnRule::Queue,
            Some(r) => match r.get_ref().as_str() {
                "fair" => SpawnRule::Fair,
                "queue" => SpawnRule::Queue,
                other => {
                    return Err(invalid(
                        r.span(),
                        format!("spawn: rule must be \"fair\" or \"queue\", got {other:?}"),
                    ));
                }
            },
        };
        if s.strip_width.is_none() {
            settings.strip_width = auto_strip_width(&groups);
        }
        let (mut boundaries, mut boundary_names, mut drives) = (Vec::new(), Vec::new(), Vec::new());
        for (k, p) in file.planes.iter().enumerate() {
            let spec = p.get_ref();
            let vector = |key: &str, v: &toml::Spanned<Vec<Finite>>| match v.get_ref()[..] {
                [x, y] => Ok(Vec2::new(x.0, y.0)),
                _ => Err(invalid(
                    v.span(),
                    format!(
                        "plane {}: {key} needs two numbers [x, y], got {}",
                        k + 1,
                        v.get_ref().len()
                    ),
                )),
            };
            let n = vector("normal", &spec.normal)?;
            let at = vector("point", &spec.point)?;
            let plane = HalfPlane::new(n, n.dot(at))
                .map_err(|e| invalid(spec.normal.span(), format!("plane {}: {e}", k + 1)))?;
            boundaries.push(Boundary::Plane(plane));
            boundary_names.push(format!("plane {}", k + 1));
            drives.push(Drive::default());
        }
        for (k, spec) in file.boundaries.iter().enumerate() {
            let pieces = spec
                .get_ref()
                .pieces()
                .map_err(|e| invalid(spec.span(), format!("boundary {}: {e}", k + 1)))?;
            let drive = Drive::from_spec(spec.get_ref())
                .map_err(|e| invalid(spec.span(), format!("boundary {}: {e}", k + 1)))?;
            let several = pieces.len() > 1;
            for (j, piece) in pieces.into_iter().enumerate() {
                boundaries.push(piece);
                drives.push(drive);
                boundary_names.push(if several {
                    format!("boundary {}, segment {}", k + 1, j + 1)
                } else {
                    format!("boundary {}", k + 1)
                });
            }
        }
        let first = file
            .planes
            .first()
            .map(|p| (p.span(), "[[plane]]"))
            .or_else(|| file.boundaries.first().map(|b| (b.span(), "[[boundary]]")));
        if let Some((span, table)) = first.clone()
            && settings.model != Model::Soft
        {
            return Err(invalid(
                span,
                format!(
                    "{table} needs [solver] model = \"soft\" (the paper's projection has the \
                     box alone)"
                ),
            ));
        }
        if let Some((span, _)) = first
            && boundaries.len() + 3 > crate::solver::soft::MAX_WALLS
        {
            return Err(invalid(
                span,
                format!(
                    "at most {} boundaries (a polyline's segments each count), got {}",
                    crate::solver::soft::MAX_WALLS - 3,
                    boundaries.len()
                ),
            ));
        }
        let mut grains = Vec::new();
        for (k, spanned) in file.grains.iter().enumerate() {
            let g = spanned.get_ref();
            let at = |span: std::ops::Range<usize>, message: String| SceneError::Grain {
                line: line_of(span),
                grain: k + 1,
                message,
            };
            let two = |key: &str, v: &toml::Spanned<Vec<f64>>| match v.get_ref()[..] {
                [x, y] => Ok([x, y]),
                _ => Err(at(
                    v.span(),
                    format!("{key} needs two numbers [x, y], got {}", v.get_ref().len()),
                )),
            };
            let numbers = |v: &toml::Spanned<Vec<Finite>>| {
                toml::Spanned::new(v.span(), v.get_ref().iter().map(|x| x.0).collect())
            };
            let positives = |v: &toml::Spanned<Vec<Positive>>| {
                toml::Spanned::new(v.span(), v.get_ref().iter().map(|x| x.0).collect())
            };
            let semi_axes = match (&g.radius, &g.semi_axes) {
                (Some(r), None) => [r.0; 2],
                (None, Some(s)) => two("semi_axes", &positives(s))?,
                _ => {
                    return Err(at(
                        spanned.span(),
                        "give either `radius` (a circle) or `semi_axes`, not both or neither"
                            .into(),
                    ));
                }
            };
            let exponents = match (&g.exponent, &g.exponents) {
                (Some(e), None) => [e.0; 2],
                (None, Some(e)) => two("exponents", &positives(e))?,
                (None, None) => [2.0; 2],
                _ => {
                    return Err(at(
                        spanned.span(),
                        "give `exponent` (both the same) or `exponents`, not both".into(),
                    ));
                }
            };
            let shape = Superellipse::new(semi_axes, exponents)
                .map_err(|e| at(spanned.span(), e.to_string()))?;
            let center = two("center", &numbers(&g.center))?;
            let pose = Pose::new(Vec2::from(center), g.angle.map_or(0.0, |a| a.0))
                .map_err(|e| at(g.center.span(), e.to_string()))?;
            let velocity = match &g.velocity {
                None => Vec2::ZERO,
                Some(v) => Vec2::from(two("velocity", &numbers(v))?),
            };
            if g.fixed && (velocity != Vec2::ZERO || g.angular_velocity.is_some_and(|w| w.0 != 0.0))
            {
                return Err(at(
                    spanned.span(),
                    "a fixed grain never moves: give it no velocity or angular_velocity".into(),
                ));
            }
            let drive = if g.turn.is_some() || g.shake.is_some() {
                if g.fixed || velocity != Vec2::ZERO || g.angular_velocity.is_some() {
                    return Err(at(
                        spanned.span(),
                        "a driven grain (turn, shake) moves as its drive says: give it no \
                         `fixed`, velocity or angular_velocity"
                            .into(),
                    ));
                }
                if settings.model != Model::Soft {
                    return Err(at(
                        spanned.span(),
                        "a driven grain (turn, shake) needs [solver] model = \"soft\" (the \
                         paper's projection moves grains by their overlaps alone)"
                            .into(),
                    ));
                }
                Some(
                    Drive::from_keys(g.turn.as_ref(), g.shake.as_ref(), None)
                        .map_err(|e| at(spanned.span(), e))?,
                )
            } else {
                None
            };
            let group = match &g.group {
                None => 0,
                Some(name) => groups
                    .iter()
                    .position(|gr| gr.name == *name.get_ref())
                    .ok_or_else(|| {
                        at(
                            name.span(),
                            format!(
                                "no [[group]] is named `{}` (the groups: {})",
                                name.get_ref(),
                                if groups.is_empty() {
                                    "none".to_string()
                                } else {
                                    groups
                                        .iter()
                                        .map(|gr| format!("`{}`", gr.name))
                                        .collect::<Vec<_>>()
                                        .join(", ")
                                }
                            ),
                        )
                    })? as u32,
            };
            grains.push(Placed {
                shape,
                pose,
                velocity,
                angular_velocity: g.angular_velocity.map_or(0.0, |w| w.0),
                group,
                line: line_of(spanned.span()),
                fixed: g.fixed,
                drive,
            });
        }
        // A `region = [[x0, x1], [y0, y1]]` of a sink or a measure (`what`), checked.
        let region_of = |region: &toml::Spanned<Vec<Vec<Finite>>>, what: String| {
            let bad = |message: String| invalid(region.span(), format!("{what}: region {message}"));
            let [x, y] = match &region.get_ref()[..] {
                [x, y] => [x, y],
                _ => return Err(bad("needs [[x0, x1], [y0, y1]]".into())),
            };
            let (&[x0, x1], &[y0, y1]) = (&x[..], &y[..]) else {
                return Err(bad("needs [[x0, x1], [y0, y1]]".into()));
            };
            if !(x0.0 < x1.0 && y0.0 < y1.0) {
                return Err(bad(format!(
                    "[[{}, {}], [{}, {}]] is empty: each range's start below its end",
                    x0.0, x1.0, y0.0, y1.0
                )));
            }
            Ok(Aabb {
                min: Vec2::new(x0.0, y0.0),
                max: Vec2::new(x1.0, y1.0),
            })
        };
        let mut sinks = Vec::new();
        for (k, spanned) in file.sinks.iter().enumerate() {
            let region = region_of(&spanned.get_ref().region, format!("sink {}", k + 1))?;
            sinks.push(Sink::new(region, spanned.get_ref().recycle));
        }
        let mut measures = Vec::new();
        for (k, spanned) in file.measures.iter().enumerate() {
            let m = spanned.get_ref();
            let every = match &m.every {
                None => 10,
                Some(e) if *e.get_ref() == 0 => {
                    return Err(invalid(
                        e.span(),
                        format!("measure {}: every must be at least 1", k + 1),
                    ));
                }
                Some(e) => *e.get_ref(),
            };
            if m.kind == SeriesKind::Discharge && sinks.is_empty() {
                return Err(invalid(
                    spanned.span(),
                    format!(
                        "measure {}: kind = \"discharge\" needs a [[sink]] to measure",
                        k + 1
                    ),
                ));
            }
            let what = format!("measure {}", k + 1);
            let region = m
                .region
                .as_ref()
                .map(|r| region_of(r, what.clone()))
                .transpose()?
                .map(|b| [[b.min.x, b.max.x], [b.min.y, b.max.y]]);
            let regional = matches!(m.kind, SeriesKind::Packing | SeriesKind::Profile);
            if regional && region.is_none() {
                return Err(invalid(
                    spanned.span(),
                    format!(
                        "{what}: kind = \"{}\" needs a region = [[x0, x1], [y0, y1]]",
                        m.kind.name()
                    ),
                ));
            }
            if !regional && (region.is_some() || m.bins.is_some()) {
                return Err(invalid(
                    spanned.span(),
                    format!(
                        "{what}: kind = \"{}\" takes no region or bins",
                        m.kind.name()
                    ),
                ));
            }
            if let Some(b) = &m.bins
                && (*b.get_ref() == 0 || m.kind != SeriesKind::Profile)
            {
                return Err(invalid(
                    b.span(),
                    format!("{what}: bins is a profile's, at least 1"),
                ));
            }
            measures.push(Series {
                region,
                bins: m.bins.as_ref().map(|b| *b.get_ref()),
                ..Series::new(m.kind, every)
            });
        }
        let scene = Scene {
            seed: file.seed.unwrap_or(1),
            steps: file.steps.unwrap_or(3000),
            walls: Walls {
                left: b.left.get_ref().0,
                right: b.right.get_ref().0,
                floor: b.floor.get_ref().0,
            },
            top: b.top.get_ref().0,
            spawn_interval,
            spawn_count,
            spawn_between,
            spawn_rule,
            settings,
            groups,
            wall_material: b.material_spec().material(),
            boundaries,
            boundary_names,
            drives,
            grains,
            sinks,
            measures,
        };
        scene.validate()?;
        Ok(scene)
    }

    /// Checks what the parts cannot check alone, before any work (see [`checks`]): the analytic
    /// narrow phase needs circles only; every range can be drawn from; the extremes of every
    /// drawn range make a valid shape that fits between the walls and appears above the floor;
    /// the box holds all the grains; their masses and moments of inertia are in
    /// [`checks::MASS_RANGE`]; a falling grain moves less than [`checks::STEP_FRACTION`] of the
    /// smallest semi-axis per step; the quadtree's `eps` is at most [`checks::EPS_FRACTION`] of
    /// it and the sleep radius at most it; sleeping needs at least one calm step; no plane
    /// covers where grains appear.
    pub fn validate(&self) -> Result<(), SceneError> {
        if self.settings.narrow_phase == NarrowPhase::Analytic
            && let Some(g) = self
                .groups
                .iter()
                .find(|g| !g.circles || g.exponents != [Range::fixed(2.0); 2])
        {
            return Err(SceneError::NotCircles(g.name.clone()));
        }
        checks::check_box(&self.walls, self.top).map_err(SceneError::Unworkable)?;
        let mut smallest = f64::INFINITY;
        let mut radii = [f64::INFINITY, 0.0f64];
        let mut area = 0.0;
        for g in &self.groups {
            let group_error = |message: String| SceneError::Group {
                group: g.name.clone(),
                message,
            };
            let radius = if g.circles { "radius" } else { "semi_axes" };
            let exponent = if g.same_exponents {
                "exponent"
            } else {
                "exponents"
            };
            for (r, field) in [
                (g.semi_axes[0], radius),
                (g.semi_axes[1], radius),
                (g.exponents[0], exponent),
                (g.exponents[1], exponent),
                (g.angle, "angle"),
            ] {
                checks::check_range(r, field).map_err(group_error)?;
            }
            let (least, largest) = g.extreme_shapes().map_err(group_error)?;
            if g.count == 0 {
                continue;
            }
            let field = if g.circles { "radius" } else { "semi_axes" };
            let spawn_walls = super::spawn::narrowed(&self.walls, self.spawn_between);
            checks::check_fits(&spawn_walls, self.top, largest.bounding_radius(), field)
                .map_err(group_error)?;
            // Mass and moment of inertia grow with each semi-axis and exponent.
            for shape in [least, largest] {
                checks::check_mass(&g.material, &shape).map_err(group_error)?;
            }
            smallest = smallest.min(least.min_semi_axis());
            radii[0] = radii[0].min(least.bounding_radius());
            radii[1] = radii[1].max(largest.bounding_radius());
            area += f64::from(g.count) * least.area();
        }
        let materials: Vec<Material> = self.groups.iter().map(|g| g.material).collect();
        let placed: Vec<Body> = self.grains.iter().map(Placed::body).collect();
        let boxes: Vec<Aabb> = placed.iter().map(Body::bounding_box).collect();
        let narrow = self.settings.narrow();
        for (k, (g, body)) in self.grains.iter().zip(&placed).enumerate() {
            let error = |message: String| SceneError::Grain {
                line: g.line,
                grain: k + 1,
                message,
            };
            if self.settings.narrow_phase == NarrowPhase::Analytic && !g.shape.is_circle() {
                return Err(error(
                    "the analytic narrow phase needs circles only, and this grain is not one"
                        .into(),
                ));
            }
            checks::check_mass(&material_of(&materials, g.group), &g.shape).map_err(error)?;
            // Placed grains may touch the walls and each other: each is refused deeper than
            // `PLACED_TOLERANCE` of its smallest semi-axis (a grain set on the floor by hand,
            // `y = b`, reaches 1.8e-16 below it by its rounded box).
            let thin = g.shape.min_semi_axis();
            let bb = boxes[k];
            let outside = checks::depth_outside(&self.walls, &bb);
            if outside > PLACED_TOLERANCE * thin {
                return Err(error(format!(
                    "reaches {} beyond the box's walls or floor (its box is x {}..{}, y {}..; the \
                     walls at {} and {}, the floor at {})",
                    checks::short(outside),
                    checks::short(bb.min.x),
                    checks::short(bb.max.x),
                    checks::short(bb.min.y),
                    checks::short(self.walls.left),
                    checks::short(self.walls.right),
                    checks::short(self.walls.floor),
                )));
            }
            if let Some(p) = self.boundaries.iter().position(|w| {
                body.wall_contact(w, &narrow)
                    .penetration
                    .is_some_and(|p| p.push.norm() > PLACED_TOLERANCE * thin)
            }) {
                return Err(error(format!("lies in {}", self.boundary_names[p])));
            }
            if let Some(j) = placed[..k].iter().zip(&boxes).position(|(o, ob)| {
                // Fixed grains may overlap each other (the joint of a hopper's sides): they
                // never meet.
                if !body.kind.is_dynamic() && !o.kind.is_dynamic() {
                    return false;
                }
                let limit = PLACED_TOLERANCE * thin.min(o.shape.min_semi_axis());
                ob.intersects(&bb)
                    && body
                        .contact(o, &narrow)
                        .penetration
                        .is_some_and(|p| checks::overlap_depth(body, o, &p, 0.1 * limit) > limit)
            }) {
                return Err(error(format!(
                    "overlaps grain {} (line {})",
                    j + 1,
                    self.grains[j].line
                )));
            }
            // (A driven grain: the fastest its drive moves any point of it.)
            let speed = g.velocity.norm()
                + g.drive.map_or(0.0, |d| {
                    d.peak_speed(g.pose.center(), g.shape.bounding_radius())
                });
            checks::check_speed(&self.settings, speed, g.shape.min_semi_axis()).map_err(error)?;
            smallest = smallest.min(g.shape.min_semi_axis());
            radii[0] = radii[0].min(g.shape.bounding_radius());
            radii[1] = radii[1].max(g.shape.bounding_radius());
            area += g.shape.area();
        }
        checks::check_capacity(&self.walls, self.top, self.grain_count(), area)
            .map_err(SceneError::Unworkable)?;
        // Grains appear in a band under `top` (the fair rule's, [`BAND_IN_RADII`] bounding
        // radii deep): a sink reaching into it would take them as they appear.
        let band = self.top - BAND_IN_RADII * radii[1].max(0.0);
        for (k, s) in self.sinks.iter().enumerate() {
            if s.region.max.y >= band {
                return Err(SceneError::Unworkable(format!(
                    "sink {}: its region reaches y = {}, into the band where grains appear \
                     (from y = {} up to top = {}): keep it below",
                    k + 1,
                    checks::short(s.region.max.y),
                    checks::short(band),
                    checks::short(self.top)
                )));
            }
        }
        checks::check_sleep(&self.settings, smallest).map_err(SceneError::Unworkable)?;
        checks::check_slop(&self.settings, smallest).map_err(SceneError::Unworkable)?;
        if smallest.is_finite() {
            checks::check_time_step(&self.settings, self.top - self.walls.floor, smallest)
                .map_err(SceneError::Unworkable)?;
            checks::check_eps(&self.settings, smallest).map_err(SceneError::Unworkable)?;
            // (Only where grains are to appear at all.)
            if self.groups.iter().any(|g| g.count > 0) {
                let walls = &super::spawn::narrowed(&self.walls, self.spawn_between);
                let rule = self.spawn_rule;
                for (boundary, name) in self.boundaries.iter().zip(&self.boundary_names) {
                    checks::check_boundary(boundary, name, walls, self.top, rule, radii, smallest)
                        .map_err(SceneError::Unworkable)?;
                }
            }
        }
        Ok(())
    }

    /// The number of grains the scene will hold: those placed and those the groups draw.
    pub fn grain_count(&self) -> u64 {
        self.grains.len() as u64 + self.groups.iter().map(|g| u64::from(g.count)).sum::<u64>()
    }
}

/// The default [`Settings::strip_width`]: [`crate::solver::strips::WIDTH_IN_RADII`] times the
/// largest bounding radius the groups can draw (the corner of the largest semi-axes' box).
pub fn auto_strip_width(groups: &[Group]) -> f64 {
    let radius = groups
        .iter()
        .map(|g| g.semi_axes[0].hi.hypot(g.semi_axes[1].hi))
        .fold(0.0, f64::max);
    crate::solver::strips::WIDTH_IN_RADII * radius
}

// ---- The file format ----

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    seed: Option<u64>,
    steps: Option<u64>,
    #[serde(rename = "box")]
    bounds: BoxSpec,
    spawn: Option<SpawnSpec>,
    solver: Option<toml::Spanned<SolverTable>>,
    #[serde(rename = "group", default)]
    groups: Vec<GroupSpec>,
    #[serde(rename = "plane", default)]
    planes: Vec<toml::Spanned<PlaneSpec>>,
    #[serde(rename = "boundary", default)]
    boundaries: Vec<toml::Spanned<BoundarySpec>>,
    #[serde(rename = "grain", default)]
    grains: Vec<toml::Spanned<GrainSpec>>,
    #[serde(rename = "sink", default)]
    sinks: Vec<toml::Spanned<SinkSpec>>,
    #[serde(rename = "measure", default)]
    measures: Vec<toml::Spanned<MeasureSpec>>,
}

/// A measure: `kind` (`"discharge"`, `"energy"`, `"surface"`, `"packing"` or `"profile"`),
/// `every` (steps between rows, 10), and a packing's or profile's `region` and `bins`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeasureSpec {
    kind: SeriesKind,
    every: Option<toml::Spanned<u64>>,
    region: Option<toml::Spanned<Vec<Vec<Finite>>>>,
    bins: Option<toml::Spanned<u32>>,
}

/// A sink: `region = [[x0, x1], [y0, y1]]`, and whether its grains come back (`recycle`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SinkSpec {
    region: toml::Spanned<Vec<Vec<Finite>>>,
    #[serde(default)]
    recycle: bool,
}

/// A grain placed by hand: `center` and a shape as a group's (`radius` or `semi_axes`,
/// `exponent` or `exponents`, single numbers), `angle`, `velocity`, `angular_velocity`, and the
/// `group` (by name) whose material it takes.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GrainSpec {
    // Vectors, not arrays: a third number must be an error, not dropped.
    center: toml::Spanned<Vec<Finite>>,
    radius: Option<Positive>,
    semi_axes: Option<toml::Spanned<Vec<Positive>>>,
    exponent: Option<Positive>,
    exponents: Option<toml::Spanned<Vec<Positive>>>,
    angle: Option<Finite>,
    velocity: Option<toml::Spanned<Vec<Finite>>>,
    angular_velocity: Option<Finite>,
    group: Option<toml::Spanned<String>>,
    #[serde(default)]
    fixed: bool,
    /// Driven, as a boundary is: `turn = { about, rate }`, `shake = { amplitude, frequency }`.
    turn: Option<crate::shape::TurnSpec>,
    shake: Option<crate::shape::ShakeSpec>,
}

/// A wall at any angle: the line through `point` across `normal`, solid on the side away from
/// the normal.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlaneSpec {
    // Vectors, not arrays: a third number must be an error, not dropped.
    normal: toml::Spanned<Vec<Finite>>,
    point: toml::Spanned<Vec<Finite>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BoxSpec {
    left: toml::Spanned<Finite>,
    right: toml::Spanned<Finite>,
    floor: toml::Spanned<Finite>,
    top: toml::Spanned<Finite>,
    // The material's keys (see [`MaterialSpec`]).
    density: Option<toml::Spanned<Positive>>,
    friction: Option<toml::Spanned<NonNegative>>,
    restitution: Option<toml::Spanned<UnitInterval>>,
    rolling_resistance: Option<toml::Spanned<NonNegative>>,
}

#[derive(Deserialize, Clone)]
#[serde(deny_unknown_fields)]
struct SpawnSpec {
    interval: Option<toml::Spanned<u32>>,
    count: Option<toml::Spanned<u32>>,
    /// Grains per second, instead of `interval` and `count`.
    rate: Option<toml::Spanned<f64>>,
    /// Where grains appear across: `[x0, x1]` within the walls.
    between: Option<toml::Spanned<Vec<Finite>>>,
    /// "fair" or "queue" (see [`SpawnRule`]); checked by hand, so that the error names the key.
    rule: Option<toml::Spanned<String>>,
}

/// The soft settings a scene's `max_overlap` asks for ([`SoftSettings::for_max_overlap`]): the
/// load of every grain of the groups (each group's count at the mean of its smallest and
/// largest grains' masses) over the box's `width`, on its thinnest grains.
fn stiffness_for(
    v: f64,
    s: &SolverTable,
    settings: &Settings,
    groups: &[Group],
    width: f64,
) -> Result<SoftSettings, String> {
    if settings.model != Model::Soft {
        return Err(
            "solver: max_overlap needs model = \"soft\" (the paper's projection has no contact \
             stiffness)"
                .into(),
        );
    }
    if s.contact_hertz.is_some() {
        return Err(
            "solver: give max_overlap or contact_hertz, not both (max_overlap sets the contact \
             stiffness)"
                .into(),
        );
    }
    let mut load = crate::settings::Load {
        mass: 0.0,
        width,
        thin_mass: 0.0,
        gravity: settings.gravity,
    };
    let mut thinnest = f64::INFINITY;
    for g in groups {
        // (Invalid shapes are refused by `validate`, after this: skip them here.)
        let Ok((small, large)) = g.extreme_shapes() else {
            continue;
        };
        let (m_small, _) = g.material.mass_and_inertia(&small);
        let (m_large, _) = g.material.mass_and_inertia(&large);
        load.mass += f64::from(g.count) * 0.5 * (m_small + m_large);
        let thickness = 2.0 * small.min_semi_axis();
        if thickness < thinnest {
            thinnest = thickness;
            load.thin_mass = m_small;
        }
    }
    settings
        .soft
        .for_max_overlap(v, &load, settings.step)
        .map_err(|e| format!("solver: {e}"))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GroupSpec {
    name: Option<String>,
    count: toml::Spanned<u32>,
    radius: Option<PositiveRange>,
    // Vectors, not arrays: a third number must be an error, not dropped.
    semi_axes: Option<toml::Spanned<Vec<PositiveRange>>>,
    exponent: Option<PositiveRange>,
    exponents: Option<toml::Spanned<Vec<PositiveRange>>>,
    angle: Option<FiniteRange>,
    // The material's keys (see [`MaterialSpec`]).
    density: Option<toml::Spanned<Positive>>,
    friction: Option<toml::Spanned<NonNegative>>,
    restitution: Option<toml::Spanned<UnitInterval>>,
    rolling_resistance: Option<toml::Spanned<NonNegative>>,
}

/// The [`MaterialSpec`] of a `[[group]]` or of `[box]`.
macro_rules! impl_material_spec {
    ($($spec:ty),*) => {$(
        impl $spec {
            fn material_spec(&self) -> MaterialSpec {
                MaterialSpec {
                    density: self.density.clone(),
                    friction: self.friction.clone(),
                    restitution: self.restitution.clone(),
                    rolling_resistance: self.rolling_resistance.clone(),
                }
            }
        }
    )*};
}

impl_material_spec!(GroupSpec, BoxSpec);

/// A material's keys in a `[[group]]` or in `[box]` (the walls'), where they were written.
struct MaterialSpec {
    density: Option<toml::Spanned<Positive>>,
    friction: Option<toml::Spanned<NonNegative>>,
    restitution: Option<toml::Spanned<UnitInterval>>,
    rolling_resistance: Option<toml::Spanned<NonNegative>>,
}

impl MaterialSpec {
    /// The material; absent keys take [`Material::default`]'s values.
    fn material(&self) -> Material {
        let d = Material::default();
        Material {
            density: self.density.as_ref().map_or(d.density, |v| v.get_ref().0),
            friction: self.friction.as_ref().map_or(d.friction, |v| v.get_ref().0),
            restitution: self
                .restitution
                .as_ref()
                .map_or(d.restitution, |v| v.get_ref().0),
            rolling_resistance: self
                .rolling_resistance
                .as_ref()
                .map_or(d.rolling_resistance, |v| v.get_ref().0),
        }
    }

    /// The first key given, by name, and where.
    fn first_key(&self) -> Option<(&'static str, std::ops::Range<usize>)> {
        [
            ("density", self.density.as_ref().map(|v| v.span())),
            ("friction", self.friction.as_ref().map(|v| v.span())),
            ("restitution", self.restitution.as_ref().map(|v| v.span())),
            (
                "rolling_resistance",
                self.rolling_resistance.as_ref().map(|v| v.span()),
            ),
        ]
        .into_iter()
        .filter_map(|(key, span)| span.map(|s| (key, s)))
        .min_by_key(|(_, s)| s.start)
    }
}

/// Numbers checked while parsing, so that the TOML error points at the offending value.
macro_rules! checked_number {
    ($name:ident, $what:literal, $ok:expr) => {
        #[derive(Clone, Copy, Debug)]
        struct $name(f64);

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let v = f64::deserialize(d)?;
                let ok: fn(f64) -> bool = $ok;
                if ok(v) {
                    Ok($name(v))
                } else {
                    Err(de::Error::custom(format!(
                        concat!("expected ", $what, ", got {}"),
                        v
                    )))
                }
            }
        }
    };
}

checked_number!(Positive, "a finite number > 0", |v| v.is_finite()
    && v > 0.0);
checked_number!(NonNegative, "a finite number >= 0", |v| v.is_finite()
    && v >= 0.0);
checked_number!(Finite, "a finite number", |v| v.is_finite());
checked_number!(UnitInterval, "a number in [0, 1]", |v| (0.0..=1.0)
    .contains(&v));

/// A number or `[lo, hi]`, each end checked.
macro_rules! checked_range {
    ($name:ident, $what:literal, $ok:expr) => {
        #[derive(Clone, Copy, Debug)]
        struct $name(Range);

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                struct V;
                impl<'de> Visitor<'de> for V {
                    type Value = Range;
                    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                        write!(f, concat!($what, ", or a range [lo, hi] of them"))
                    }
                    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Range, E> {
                        check::<E>(v).map(Range::fixed)
                    }
                    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Range, E> {
                        self.visit_f64(v as f64)
                    }
                    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Range, A::Error> {
                        let lo: f64 = seq.next_element()?.ok_or_else(|| {
                            de::Error::custom("a range needs two numbers [lo, hi]")
                        })?;
                        let hi: f64 = seq.next_element()?.ok_or_else(|| {
                            de::Error::custom("a range needs two numbers [lo, hi]")
                        })?;
                        if seq.next_element::<f64>()?.is_some() {
                            return Err(de::Error::custom(
                                "a range has exactly two numbers [lo, hi]",
                            ));
                        }
                        let (lo, hi) = (check::<A::Error>(lo)?, check::<A::Error>(hi)?);
                        if lo > hi {
                            return Err(de::Error::custom(format!(
                                "range [{lo}, {hi}] is empty: lo > hi"
                            )));
                        }
                        Ok(Range::new(lo, hi))
                    }
                }
                fn check<E: de::Error>(v: f64) -> Result<f64, E> {
                    let ok: fn(f64) -> bool = $ok;
                    if ok(v) {
                        Ok(v)
                    } else {
                        Err(E::custom(format!(
                            concat!("expected ", $what, ", got {}"),
                            v
                        )))
                    }
                }
                d.deserialize_any(V).map($name)
            }
        }
    };
}

checked_range!(PositiveRange, "a finite number > 0", |v| v.is_finite()
    && v > 0.0);
checked_range!(FiniteRange, "a finite number", |v| v.is_finite());

//! The neutral scene every engine runs: an open box, gravity, a time step, materials, and grains
//! as plain shapes (circle, capsule, rounded box) with poses, either all placed (a settled heap)
//! or appearing over time at the top (a pour). Made from supergrain's own scenes and dumps, so
//! that the peers run exactly the grains supergrain runs.

use std::fmt;

use supergrain::shape::Superellipse;
use supergrain::world::{Scene as SupergrainScene, World};

/// A grain's shape in the peers' vocabulary. Lengths in the scene's units (metres for the peers).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Circle {
        radius: f64,
    },
    /// The segment between `(-h, 0)` and `(h, 0)` (along local x) or `(0, -h)` and `(0, h)`
    /// (along local y), swept by a disk of `radius`: `half_extents` are `[h + radius, radius]`
    /// or `[radius, h + radius]`.
    Capsule {
        half_length: f64,
        radius: f64,
        along_y: bool,
    },
    /// The box of half extents `half_extents`, its corners rounded with `radius`: the straight
    /// part is `half_extents - radius` on each side (Box2D's rounded box and rapier's round
    /// cuboid take that inner box and the radius).
    RoundedBox {
        half_extents: [f64; 2],
        radius: f64,
    },
}

/// The rounding radius of a block's box, as a fraction of its smaller half extent: small, so
/// that the box keeps the superellipse's flat sides and its size (Box2D's own samples round
/// boxes by about a tenth). A superellipse of exponent 3 is rounder than that at its corners: its
/// area is 0.88 of its box's, at exponent 6 0.96 (`docs/peers.md`).
pub const BOX_ROUNDING: f64 = 0.1;

/// Why a superellipse has no shape among the peers'.
#[derive(Clone, Debug, PartialEq)]
pub struct Unsupported {
    pub semi_axes: [f64; 2],
    pub exponents: [f64; 2],
}

impl fmt::Display for Unsupported {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "no peer shape for the superellipse of semi-axes {:?} and exponents {:?}: the peers \
             take circles and ellipses (exponents 2, 2) and blocks (equal exponents above 2)",
            self.semi_axes, self.exponents
        )
    }
}

impl std::error::Error for Unsupported {}

impl Shape {
    /// The peer shape of a superellipse: a circle of the same radius, an ellipse (exponents 2)
    /// as the capsule of the same length and width, a blocky superellipse (equal exponents above
    /// 2) as the rounded box of the same half extents ([`BOX_ROUNDING`]). Anything else
    /// (diamonds, stars, unequal exponents) has none.
    pub fn of(shape: &Superellipse) -> Result<Shape, Unsupported> {
        let s = shape.semi_axes();
        let [ex, ey] = shape.exponents();
        let unsupported = || Unsupported {
            semi_axes: [s.x, s.y],
            exponents: [ex, ey],
        };
        if ex != ey {
            return Err(unsupported());
        }
        if ex == 2.0 {
            if s.x == s.y {
                return Ok(Shape::Circle { radius: s.x });
            }
            let (long, short) = (s.x.max(s.y), s.x.min(s.y));
            return Ok(Shape::Capsule {
                half_length: long - short,
                radius: short,
                along_y: s.y > s.x,
            });
        }
        if ex > 2.0 {
            return Ok(Shape::RoundedBox {
                half_extents: [s.x, s.y],
                radius: BOX_ROUNDING * s.x.min(s.y),
            });
        }
        Err(unsupported())
    }

    /// Half extents of the shape's local box (the superellipse's semi-axes it was made from).
    pub fn half_extents(&self) -> [f64; 2] {
        match *self {
            Shape::Circle { radius } => [radius, radius],
            Shape::Capsule {
                half_length,
                radius,
                along_y,
            } => {
                if along_y {
                    [radius, half_length + radius]
                } else {
                    [half_length + radius, radius]
                }
            }
            Shape::RoundedBox { half_extents, .. } => half_extents,
        }
    }

    /// The area, in closed form.
    pub fn area(&self) -> f64 {
        use std::f64::consts::PI;
        match *self {
            Shape::Circle { radius } => PI * radius * radius,
            Shape::Capsule {
                half_length,
                radius,
                ..
            } => PI * radius * radius + 4.0 * half_length * radius,
            Shape::RoundedBox {
                half_extents: [a, b],
                radius,
            } => 4.0 * a * b - (4.0 - PI) * radius * radius,
        }
    }

    /// The radius of the smallest disk about the centre that holds the shape.
    pub fn bounding_radius(&self) -> f64 {
        match *self {
            Shape::Circle { radius } => radius,
            Shape::Capsule {
                half_length,
                radius,
                ..
            } => half_length + radius,
            Shape::RoundedBox {
                half_extents: [a, b],
                radius,
            } => (a - radius).hypot(b - radius) + radius,
        }
    }
}

/// A placed grain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grain {
    pub shape: Shape,
    pub x: f64,
    pub y: f64,
    pub angle: f64,
}

/// A grain waiting to appear at `(x, top)` from step `due` on, as supergrain's spawner makes it:
/// a due grain whose place is taken waits, and those due after it whose places are free appear
/// meanwhile, in queue order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spawn {
    pub shape: Shape,
    pub x: f64,
    pub angle: f64,
    pub due: u64,
}

/// The open box: two walls and a floor, as supergrain's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walls {
    pub left: f64,
    pub right: f64,
    pub floor: f64,
}

impl From<supergrain::body::Walls> for Walls {
    fn from(w: supergrain::body::Walls) -> Walls {
        Walls {
            left: w.left,
            right: w.right,
            floor: w.floor,
        }
    }
}

/// What every engine is given.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub walls: Walls,
    /// Downwards.
    pub gravity: f64,
    /// Seconds per step.
    pub time_step: f64,
    /// Substeps (Box2D) or solver iterations (rapier, whose iterations are substeps) per step.
    pub substeps: u32,
    /// Coulomb friction of grains and walls alike.
    pub friction: f64,
    pub restitution: f64,
    pub density: f64,
    /// The rolling-resistance coefficient `mu_r` of grains and walls alike (Box2D's
    /// `rollingResistance`: the torque resisting rolling is at most `mu_r` times the larger
    /// radius of the two shapes times the normal force; supergrain's soft step takes the
    /// contact's mean lever instead). rapier2d has none, and refuses a scene with it.
    pub rolling_resistance: f64,
    /// The walls' and the floor's friction and rolling resistance (mixed with a grain's by the
    /// engine's rules): the grains' own in the timed scenes.
    pub wall_friction: f64,
    pub wall_rolling_resistance: f64,
    /// Grains in place at the start.
    pub grains: Vec<Grain>,
    /// Grains to appear, in queue order.
    pub spawns: Vec<Spawn>,
    /// Height at which spawned grains appear.
    pub top: f64,
}

/// Materials and substeps where supergrain's projection has none: Box2D's defaults (friction
/// 0.6, restitution 0, density 1, four substeps), which both peers take alike.
pub const FRICTION: f64 = 0.6;
pub const RESTITUTION: f64 = 0.0;
pub const DENSITY: f64 = 1.0;
pub const SUBSTEPS: u32 = 4;

/// When a pour has come to rest: every grain has appeared and none has been faster than `speed`
/// for `steps` steps in a row (supergrain's `run --until-rest`: 0.05, 5% of a falling grain's
/// terminal speed under the paper's damping, for 100 steps), or `max_steps` have passed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rest {
    pub speed: f64,
    pub steps: u32,
    pub max_steps: u64,
}

impl Default for Rest {
    fn default() -> Self {
        Rest {
            speed: 0.05,
            steps: 100,
            max_steps: 20_000,
        }
    }
}

impl Rest {
    /// The criterion alone, as supergrain's [`supergrain::world::RestCounter`] counts it for every engine.
    pub fn criterion(&self) -> supergrain::world::Rest {
        supergrain::world::Rest {
            speed: self.speed,
            steps: self.steps,
        }
    }
}

impl Scene {
    /// The box, gravity and time step of a supergrain world, and the peers' materials
    /// ([`FRICTION`], ...), with no grain.
    fn empty(world: &World) -> Scene {
        Scene {
            walls: world.walls.into(),
            gravity: world.settings.gravity,
            time_step: world.settings.step,
            substeps: SUBSTEPS,
            friction: FRICTION,
            restitution: RESTITUTION,
            density: DENSITY,
            rolling_resistance: 0.0,
            wall_friction: FRICTION,
            wall_rolling_resistance: 0.0,
            grains: Vec::new(),
            spawns: Vec::new(),
            top: world.top,
        }
    }

    /// The grains of a supergrain world where they are (a settled heap), none to appear.
    pub fn heap(world: &World) -> Result<Scene, Unsupported> {
        let mut scene = Scene::empty(world);
        scene.grains = world
            .bodies
            .iter()
            .map(|b| {
                Ok(Grain {
                    shape: Shape::of(&b.shape)?,
                    x: b.center.x,
                    y: b.center.y,
                    angle: b.angle,
                })
            })
            .collect::<Result<_, _>>()?;
        Ok(scene)
    }

    /// A supergrain scene's pour: its spawn queue as its world draws it from the seed (the same
    /// shapes, places, angles and due steps), the box empty.
    pub fn pour(scene: &SupergrainScene) -> Result<Scene, Unsupported> {
        let world = World::new(scene);
        let mut out = Scene::empty(&world);
        out.spawns = world
            .pending
            .iter()
            .map(|p| {
                Ok(Spawn {
                    shape: Shape::of(&p.shape)?,
                    x: p.x,
                    angle: p.angle,
                    due: p.due,
                })
            })
            .collect::<Result<_, _>>()?;
        Ok(out)
    }

    /// Grains placed and to appear.
    pub fn grain_count(&self) -> usize {
        self.grains.len() + self.spawns.len()
    }

    /// The total area of the grains placed.
    pub fn area(&self) -> f64 {
        self.grains.iter().map(|g| g.shape.area()).sum()
    }

    /// The largest bounding radius of any grain, placed or to appear.
    pub fn largest_radius(&self) -> f64 {
        let placed = self.grains.iter().map(|g| g.shape.bounding_radius());
        let spawned = self.spawns.iter().map(|s| s.shape.bounding_radius());
        placed.chain(spawned).fold(0.0, f64::max)
    }

    /// Height of the side walls the peers build: the box holds the heap and the spawn height
    /// with room above (supergrain's walls are half-planes, endless).
    pub fn wall_height(&self) -> f64 {
        let w = self.walls;
        let heap = self
            .grains
            .iter()
            .map(|g| g.y + g.shape.bounding_radius())
            .fold(w.floor, f64::max);
        heap.max(self.top) - w.floor + (w.right - w.left).min(50.0)
    }
}

/// The queue of a pour as an engine runs it: which grains appear at a step.
#[derive(Clone, Debug)]
pub struct Spawner {
    pending: std::collections::VecDeque<Spawn>,
}

impl Spawner {
    pub fn new(spawns: &[Spawn]) -> Spawner {
        Spawner {
            pending: spawns.iter().copied().collect(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.pending.is_empty()
    }

    /// At step `step`, the grains that appear, in queue order: those due whose place at `top`
    /// is free of the grains `placed` (poses of the grains already in) and of those appearing
    /// before them; a due grain whose place is taken waits (supergrain's rule).
    pub fn due(&mut self, step: u64, top: f64, placed: &[Grain]) -> Vec<Grain> {
        let mut out: Vec<Grain> = Vec::new();
        let mut k = 0;
        while k < self.pending.len() {
            let p = self.pending[k];
            if p.due > step {
                break;
            }
            let g = Grain {
                shape: p.shape,
                x: p.x,
                y: top,
                angle: p.angle,
            };
            let taken = placed
                .iter()
                .chain(&out)
                .any(|o| crate::overlap::overlap(&g, o));
            if taken {
                k += 1;
            } else {
                out.push(g);
                self.pending.remove(k);
            }
        }
        out
    }
}

//! The viewer's simulation, apart from any window: a scene, its world, the controls that act
//! on it ([`Command`]) and what a frame draws of it ([`Snapshot`]). Everything here runs and is
//! tested without a display; the window only sends commands and draws snapshots.

use supergrain::body::{Body, Material};
use supergrain::contact::{Penetration, WallPenetration};
use supergrain::geometry::{Aabb, Vec2};
use supergrain::io::Dump;
use supergrain::render::{Colouring, Style, render_world};
use supergrain::settings::{Model, Settings};
use supergrain::shape::{Pose, Superellipse};
use supergrain::world::{MaterialOf, PRESETS, Scene, Touch, World};

use crate::explorer::{ClassedCell, classed_cells};

/// Where the scene came from, shown in the title and used by reset.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    Preset(String),
    /// A scene file: its name and its text.
    File {
        name: String,
        text: String,
    },
    /// A state written by `supergrain run --dump` or the viewer's Save: its name and its text.
    State {
        name: String,
        text: String,
    },
}

impl Source {
    pub fn label(&self) -> String {
        match self {
            Source::Preset(name) => format!("preset {name}"),
            Source::File { name, .. } | Source::State { name, .. } => name.clone(),
        }
    }
}

/// The spawn rule a user can change; it applies from the next reset, since a world's spawn
/// queue takes the rule when the world is made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spawn {
    /// Steps between two grains.
    pub interval: u32,
    /// Height at which grains appear.
    pub top: f64,
}

/// The materials a user can change (the soft model's), applied from the next step: each
/// group's, by [`Body::group`], named as in the scene, and the walls'.
#[derive(Clone, Debug, PartialEq)]
pub struct Materials {
    pub groups: Vec<(String, Material)>,
    pub walls: Material,
}

/// The shape dropped by a click.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DropShape {
    pub semi_axes: [f64; 2],
    pub exponents: [f64; 2],
    pub angle: f64,
}

impl Default for DropShape {
    fn default() -> Self {
        DropShape {
            semi_axes: [0.4, 0.25],
            exponents: [4.0, 4.0],
            angle: 0.3,
        }
    }
}

/// What the overlays show (each computed only when on).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Overlays {
    /// Every grain's bounding box.
    pub boxes: bool,
    /// The quadtree cells of every current grain-grain contact.
    pub cells: bool,
    /// Deepest points and penetration vectors.
    pub vectors: bool,
}

/// Everything the window can ask of the simulation.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    Play,
    Pause,
    /// One step, when paused.
    Step,
    /// Back to step 0 of the current scene (with the current spawn rule).
    Reset,
    /// Steps per frame (at 60 frames per second).
    Speed(u32),
    Preset(String),
    /// A scene file's name and text.
    Open {
        name: String,
        text: String,
    },
    /// New solver settings (the scene's model kept), applied at once.
    Tune(Settings),
    /// A group's material or the walls' (the soft model's), from the next step.
    Material(MaterialOf, Material),
    Spawn(Spawn),
    Overlays(Overlays),
    DropShape(DropShape),
    /// Drop a grain of the chosen shape, at rest, centred here.
    Drop(Vec2),
    /// Take hold of the grain under this point.
    Grab(Vec2),
    /// Move the held grain (its grabbed point follows).
    DragTo(Vec2),
    Release,
    /// Show a message (a file that could not be read, say).
    Notice(String),
}

/// A grain as drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grain {
    pub shape: Superellipse,
    pub pose: Pose,
    pub group: u32,
    pub asleep: bool,
}

/// What one frame draws.
/// A scene's measure as the window follows it: its latest summary line and its headline
/// number over time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Measured {
    /// The measure's kind (`discharge`, `energy`, ...).
    pub kind: &'static str,
    /// What the chart shows (`grains taken`, `degrees`, ...); empty for none.
    pub what: &'static str,
    /// The run's summary line, as at the measure's last row.
    pub summary: String,
    /// `[time, value]`, one a row, the last [`MEASURE_POINTS`].
    pub points: Vec<[f64; 2]>,
}

/// The most points a live chart keeps.
pub const MEASURE_POINTS: usize = 600;

#[derive(Clone, Debug, Default)]
pub struct Snapshot {
    pub label: String,
    /// The boundaries where they are now (a drum turned, a floor shaken).
    pub boundaries: Vec<supergrain::shape::Boundary>,
    /// The sinks' regions.
    pub sinks: Vec<Aabb>,
    /// The scene's measures, live.
    pub measures: Vec<Measured>,
    pub grains: Vec<Grain>,
    pub walls: [f64; 3],
    pub top: f64,
    pub step: u64,
    pub playing: bool,
    pub speed: u32,
    /// The solver settings the sliders show.
    pub settings: Option<Settings>,
    /// `None` for the paper's model, which has no materials.
    pub materials: Option<Materials>,
    pub spawn: Option<Spawn>,
    pub overlays: Overlays,
    pub drop_shape: DropShape,
    pub pending: u64,
    pub asleep: usize,
    /// Grain-grain contacts: the pair's penetration.
    pub contacts: Vec<Penetration>,
    pub wall_contacts: Vec<WallPenetration>,
    /// The quadtree cells of those contacts that lie in both shapes' boxes and in neither's
    /// outside.
    pub cells: Vec<ClassedCell>,
    /// The last problem or notice, for the status line.
    pub message: Option<String>,
    /// Which grain is held.
    pub held: Option<usize>,
    /// Commands carried out so far (applied or refused): the window knows from it which of
    /// its edits the simulation has seen.
    pub commands: u64,
}

/// The simulation behind the window.
pub struct Sim {
    source: Source,
    scene: Scene,
    pub world: World,
    playing: bool,
    speed: u32,
    overlays: Overlays,
    drop_shape: DropShape,
    /// The held grain and the grabbed point in its own frame.
    held: Option<(usize, Vec2)>,
    message: Option<String>,
    commands: u64,
    /// The scene's measures as taken so far (one per `world.measures`).
    measured: Vec<Measured>,
}

/// Upper bounds the sliders and commands keep to, so a slip of the mouse cannot stall the
/// window for minutes.
pub const MAX_SPEED: u32 = 200;
pub const MAX_ITERATIONS: u32 = 50;
pub const MAX_DEPTH: u32 = 16;

impl Sim {
    pub fn preset(name: &str) -> Result<Sim, String> {
        let scene = Scene::preset(name).map_err(|e| e.to_string())?;
        Ok(Sim::new(Source::Preset(name.to_string()), scene))
    }

    /// A scene file's text; errors name the file and the line.
    pub fn open(name: &str, text: &str) -> Result<Sim, String> {
        let scene = Scene::from_toml(text).map_err(|e| format!("{name}: {e}"))?;
        Ok(Sim::new(
            Source::File {
                name: name.to_string(),
                text: text.to_string(),
            },
            scene,
        ))
    }

    /// A dump (`supergrain run --dump`, or Save in the viewer); reset returns to it. Errors
    /// name the file.
    pub fn state(name: &str, text: &str) -> Result<Sim, String> {
        let world = world_of_dump(text).map_err(|e| format!("{name}: {e}"))?;
        // The scene behind a dump is not kept in it: an empty one in the same box.
        let scene = Scene {
            seed: 0,
            steps: 0,
            walls: world.walls,
            top: world.top,
            spawn_interval: 1,
            spawn_count: 1,
            spawn_rule: world.pending.rule(),
            spawn_between: world.pending.between(),
            settings: world.settings,
            groups: Vec::new(),
            wall_material: world.wall_material,
            boundaries: world.bases.clone(),
            drives: world.drives.clone(),
            boundary_names: (1..=world.boundaries.len())
                .map(|k| format!("boundary {k}"))
                .collect(),
            grains: Vec::new(),
            sinks: world.sinks.clone(),
            measures: world.measures.clone(),
        };
        let mut sim = Sim::new(
            Source::State {
                name: name.to_string(),
                text: text.to_string(),
            },
            scene,
        );
        sim.world = world;
        Ok(sim)
    }

    fn new(source: Source, scene: Scene) -> Sim {
        let mut sim = Sim {
            world: World::new(&scene),
            source,
            scene,
            playing: true,
            // About real time: two steps of 0.01 per sixtieth of a second.
            speed: 2,
            overlays: Overlays::default(),
            drop_shape: DropShape::default(),
            held: None,
            message: None,
            commands: 0,
            measured: Vec::new(),
        };
        sim.measure();
        sim
    }

    pub fn source(&self) -> &Source {
        &self.source
    }

    pub fn playing(&self) -> bool {
        self.playing
    }

    pub fn speed(&self) -> u32 {
        self.speed
    }

    pub fn message(&self) -> Option<&str> {
        self.message.as_deref()
    }

    /// Shows the outcome of something done outside the simulation (a file saved).
    pub fn notice(&mut self, outcome: Result<String, String>) {
        self.message = Some(outcome.unwrap_or_else(|e| e));
    }

    /// Carries out one command. A command that cannot be carried out leaves everything as it
    /// was and says why in [`Sim::message`].
    pub fn apply(&mut self, command: Command) {
        let commands = self.commands + 1;
        if let Err(e) = self.try_apply(command) {
            self.message = Some(e);
        }
        self.commands = commands;
    }

    fn try_apply(&mut self, command: Command) -> Result<(), String> {
        match command {
            Command::Play => self.playing = true,
            Command::Pause => self.playing = false,
            Command::Step => {
                self.playing = false;
                self.step();
            }
            Command::Reset => self.reset(),
            Command::Speed(n) => self.speed = n.clamp(1, MAX_SPEED),
            Command::Preset(name) => {
                let other = Sim::preset(&name)?;
                self.replace(other);
            }
            Command::Open { name, text } => {
                let other = Sim::open(&name, &text)?;
                self.replace(other);
            }
            Command::Tune(t) => self.tune(t)?,
            Command::Material(of, m) => self.set_material(of, m)?,
            Command::Spawn(s) => {
                if matches!(self.source, Source::State { .. }) {
                    return Err(
                        "a saved state has no spawn rule: its grains are all there (open a scene to pour)"
                            .into(),
                    );
                }
                if s.interval == 0 || !(s.top.is_finite() && s.top > self.scene.walls.floor) {
                    return Err(format!(
                        "spawn: interval must be at least 1 and the top above the floor, got {} and {}",
                        s.interval, s.top
                    ));
                }
                self.scene.spawn_interval = s.interval;
                self.scene.top = s.top;
                self.message = Some("spawn rule set: it applies from the next reset".into());
            }
            Command::Overlays(o) => self.overlays = o,
            Command::DropShape(d) => {
                Superellipse::new(d.semi_axes, d.exponents).map_err(|e| e.to_string())?;
                self.drop_shape = d;
            }
            Command::Drop(at) => self.drop_grain(at)?,
            Command::Grab(at) => {
                self.held = self.grain_at(at).map(|i| {
                    let b = &self.world.bodies[i];
                    (i, b.pose().to_local(at))
                });
            }
            Command::DragTo(at) => self.drag_to(at),
            Command::Release => self.held = None,
            Command::Notice(m) => self.message = Some(m),
        }
        Ok(())
    }

    fn replace(&mut self, other: Sim) {
        let (speed, overlays, drop_shape) = (self.speed, self.overlays, self.drop_shape);
        let commands = self.commands;
        *self = other;
        self.commands = commands;
        self.speed = speed;
        self.overlays = overlays;
        self.drop_shape = drop_shape;
    }

    /// Step 0 of the current scene, with the current settings, materials and spawn rule.
    pub fn reset(&mut self) {
        self.scene.settings = self.world.settings;
        let materials = std::mem::take(&mut self.world.materials);
        let walls = self.world.wall_material;
        self.world = match &self.source {
            // The text was a valid dump when it was opened.
            Source::State { text, .. } => {
                let mut world = world_of_dump(text).expect("a dump that opened reopens");
                world.settings = self.scene.settings;
                world
            }
            _ => World::new(&self.scene),
        };
        self.world.materials = materials;
        self.world.wall_material = walls;
        self.held = None;
        self.message = None;
        self.measured.clear();
        self.measure();
    }

    /// A row of every measure due at this step: its summary, and its headline on the chart.
    fn measure(&mut self) {
        let world = &self.world;
        self.measured
            .resize_with(world.measures.len(), Measured::default);
        for (series, m) in world.measures.iter().zip(&mut self.measured) {
            if !series.due(world.step) && !m.summary.is_empty() {
                continue;
            }
            m.kind = series.kind.name();
            let (summary, headline) = series.reading(world);
            m.summary = summary;
            if let Some((what, v)) = headline {
                m.what = what;
                if m.points.len() == MEASURE_POINTS {
                    m.points.remove(0);
                }
                m.points.push([world.time(), v]);
            }
        }
    }

    fn tune(&mut self, t: Settings) -> Result<(), String> {
        if t.model != self.world.settings.model {
            return Err(
                "settings: the model is the scene's; open a scene of the other model".into(),
            );
        }
        let ok = t.step <= 0.1
            && (1..=MAX_ITERATIONS).contains(&t.max_iterations)
            && t.precision.depth() <= MAX_DEPTH;
        if !ok {
            return Err(format!(
                "settings: the window keeps step to 0.1, iterations to 1..={MAX_ITERATIONS}, \
                 depth to {MAX_DEPTH}; got step {}, iterations {}, depth {}",
                t.step,
                t.max_iterations,
                t.precision.depth()
            ));
        }
        t.validate().map_err(|e| format!("settings: {e}"))?;
        self.world.set_step(t.step);
        self.world.settings = t;
        Ok(())
    }

    /// A group's material or the walls', from the next step on (see
    /// [`World::set_material`]: a new density gives the group's grains their new mass and
    /// moment of inertia). The paper's model has no materials: refused.
    pub fn set_material(&mut self, of: MaterialOf, m: Material) -> Result<(), String> {
        if self.world.settings.model != Model::Soft {
            return Err(
                "materials are the soft model's ([solver] model = \"soft\"); the paper's model has none"
                    .into(),
            );
        }
        let whose = match of {
            MaterialOf::Group(g) => format!("`{}`", self.group_name(g as usize)),
            MaterialOf::Walls => "the walls".into(),
        };
        self.world
            .set_material(of, m)
            .map_err(|e| format!("material of {whose}: {e}"))
    }

    /// A group's name in the scene (as a scene file names a group without one, from 1).
    fn group_name(&self, g: usize) -> String {
        self.scene
            .groups
            .get(g)
            .map_or_else(|| format!("group {}", g + 1), |group| group.name.clone())
    }

    /// The materials the panel shows: `None` for the paper's model.
    pub fn materials(&self) -> Option<Materials> {
        let world = &self.world;
        (world.settings.model == Model::Soft).then(|| Materials {
            groups: (0..world.group_count())
                .map(|g| {
                    let m = supergrain::body::material_of(&world.materials, g as u32);
                    (self.group_name(g), m)
                })
                .collect(),
            walls: world.wall_material,
        })
    }

    /// Steps of the world when playing: `speed` of them. While a grain is held it is kept at
    /// the mouse, at rest.
    pub fn frame(&mut self) -> u32 {
        if !self.playing {
            return 0;
        }
        for _ in 0..self.speed {
            self.step();
        }
        self.speed
    }

    /// One step, whether playing or not (the browser's frame loop counts its own).
    pub fn step(&mut self) {
        let held = self.held.map(|(i, _)| (i, self.world.bodies[i]));
        self.world.step();
        // The held grain stays where the hand put it; it still pushes its neighbours.
        if let Some((i, before)) = held {
            let b = &mut self.world.bodies[i];
            b.center = before.center;
            b.angle = before.angle;
            b.previous_center = before.center;
            b.previous_angle = before.angle;
        }
        self.measure();
    }

    /// The grain whose inside holds `p` (the topmost drawn, i.e. the last).
    pub fn grain_at(&self, p: Vec2) -> Option<usize> {
        self.world
            .bodies
            .iter()
            .rposition(|b| b.shape.value(&b.pose(), p) <= 0.0)
    }

    fn drag_to(&mut self, at: Vec2) {
        let Some((i, grip)) = self.held else {
            return;
        };
        let w = self.world.walls;
        let b = &mut self.world.bodies[i];
        // The grabbed point goes to the mouse; the box's walls still hold the grain.
        let offset = b.pose().to_world(grip) - b.center;
        let mut c = at - offset;
        if !c.is_finite() {
            return;
        }
        // The whole box stays inside the walls and above the floor.
        let bb = b.bounding_box();
        let (half_w, below) = (0.5 * bb.width(), b.center.y - bb.min.y);
        c.x = if w.right - w.left > 2.0 * half_w {
            c.x.clamp(w.left + half_w, w.right - half_w)
        } else {
            0.5 * (w.left + w.right)
        };
        c.y = c.y.max(w.floor + below);
        b.center = c;
        b.previous_center = c;
        b.previous_angle = b.angle;
        b.anchor = c;
        b.calm = 0;
        b.waiting = 0;
    }

    fn drop_grain(&mut self, at: Vec2) -> Result<(), String> {
        let d = self.drop_shape;
        let shape = Superellipse::new(d.semi_axes, d.exponents).map_err(|e| e.to_string())?;
        let pose = Pose::new(at, d.angle).map_err(|e| e.to_string())?;
        let body = Body::at_rest(shape, &pose);
        let w = self.world.walls;
        let bb = body.bounding_box();
        if bb.min.x < w.left || bb.max.x > w.right || bb.min.y < w.floor {
            return Err(format!(
                "no room at ({:.2}, {:.2}): the grain would cross a wall",
                at.x, at.y
            ));
        }
        if self.world.overlaps_a_grain(&body) {
            return Err(format!(
                "no room at ({:.2}, {:.2}): the grain would overlap another",
                at.x, at.y
            ));
        }
        self.world.bodies.push(body);
        self.message = None;
        Ok(())
    }

    /// What a frame draws of the current state.
    pub fn snapshot(&self) -> Snapshot {
        let world = &self.world;
        let settings = &world.settings;
        let mut snap = Snapshot {
            label: self.source.label(),
            grains: world
                .bodies
                .iter()
                .map(|b| Grain {
                    shape: b.shape,
                    pose: b.pose(),
                    group: b.group,
                    asleep: b.asleep(settings),
                })
                .collect(),
            walls: [world.walls.left, world.walls.right, world.walls.floor],
            top: world.top,
            step: world.step,
            playing: self.playing,
            speed: self.speed,
            settings: Some(*settings),
            materials: self.materials(),
            spawn: Some(Spawn {
                interval: self.scene.spawn_interval,
                top: self.scene.top,
            }),
            overlays: self.overlays,
            drop_shape: self.drop_shape,
            pending: world.pending_count(),
            asleep: world.asleep(),
            message: self.message.clone(),
            held: self.held.map(|(i, _)| i),
            commands: self.commands,
            boundaries: world.boundaries.clone(),
            sinks: world.sinks.iter().map(|s| s.region).collect(),
            measures: self.measured.clone(),
            ..Snapshot::default()
        };
        if self.overlays.vectors || self.overlays.cells {
            world.contacts(|t| match t {
                Touch::Grains(i, j, p) => {
                    snap.contacts.push(p);
                    if self.overlays.cells {
                        cells_of(world, i, j, &mut snap.cells);
                    }
                }
                Touch::Wall(_, p) => snap.wall_contacts.push(p),
            });
        }
        snap
    }

    /// The current state in the dump format (`supergrain run --resume` and `render` read it).
    pub fn state_json(&self) -> String {
        serde_json::to_string_pretty(&Dump::of(&self.world)).expect("a dump serialises")
    }

    /// The current state drawn by the library's interval renderer, as PNG bytes.
    pub fn screenshot_png(&self, width: u32) -> Result<Vec<u8>, String> {
        let style = Style {
            width,
            colouring: Colouring::Exponent,
            boxes: self.overlays.boxes,
            contacts: self.overlays.vectors,
            ..Style::default()
        };
        let pixmap = render_world(&self.world, &style);
        let mut out = Vec::new();
        supergrain::io::write_png(&pixmap, &mut out).map_err(|e| e.to_string())?;
        Ok(out)
    }
}

/// The world a dump's text describes.
fn world_of_dump(text: &str) -> Result<World, String> {
    let dump: Dump = serde_json::from_str(text)
        .map_err(|e| format!("not a supergrain state (JSON dump): {e}"))?;
    dump.to_world().map_err(|e| e.to_string())
}

/// The quadtree cells of the test between grains `i` and `j` outside neither grain, in the
/// plane.
fn cells_of(world: &World, i: usize, j: usize, out: &mut Vec<ClassedCell>) {
    use supergrain::subdivision::Class;
    let (a, b) = (&world.bodies[i], &world.bodies[j]);
    let mut cells = Vec::new();
    let pa = a.pose();
    supergrain::contact::contact_with_cells(
        &a.shape,
        &pa,
        &b.shape,
        &b.pose(),
        &world.settings.precision,
        &mut cells,
    );
    out.extend(
        classed_cells(cells, &pa).filter(|c| c.a != Class::Outside && c.b != Class::Outside),
    );
}

/// The names a preset menu offers.
pub fn presets() -> &'static [&'static str] {
    &PRESETS
}

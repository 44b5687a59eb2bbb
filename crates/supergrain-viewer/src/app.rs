//! The window: egui panels around a canvas. It holds no simulation state of its own beyond the
//! camera and the widgets' values; every change goes to the driver as a [`Command`].

use std::sync::Arc;

use eframe::egui::{
    self, Color32, Mesh, PointerButton, Pos2, Rect, Sense, Shape, Stroke, Vec2 as EVec2,
};
use supergrain::body::Material;
use supergrain::geometry::{Aabb, Vec2};
use supergrain::render::cell_style;
use supergrain::settings::Model;
use supergrain::shape::{Boundary, Pose, Superellipse};
use supergrain::subdivision::Precision;
use supergrain::world::MaterialOf;

use crate::driver::{Driver, Meter};
use crate::explorer::{ClassedCell, Explorer};
use crate::sim::{Command, DropShape, MAX_DEPTH, MAX_ITERATIONS, MAX_SPEED, Sim, Snapshot};

/// How the window was asked to behave (the `supergrain view` options).
#[derive(Clone, Debug, Default)]
pub struct Launch {
    /// Print `fps ... steps/s ...` once a second on standard output.
    pub log_fps: bool,
    /// Close by itself after this many seconds.
    pub quit_after: Option<f64>,
    /// Start paused.
    pub paused: bool,
    /// Steps per frame to start with (the speed slider).
    pub speed: Option<u32>,
    /// Open on the collision explorer.
    pub explorer: bool,
}

/// A line for whoever watches the output: standard output natively, the console in a browser.
fn log_line(line: &str) {
    #[cfg(not(target_arch = "wasm32"))]
    println!("{line}");
    #[cfg(target_arch = "wasm32")]
    web_sys::console::log_1(&line.into());
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Simulation,
    Explorer,
}

/// The plane's view on the canvas: a point in the plane at the canvas's centre and pixels per
/// unit; `y` grows upwards in the plane and downwards on screen.
#[derive(Clone, Copy, Debug)]
struct Camera {
    center: Vec2,
    scale: f64,
}

impl Camera {
    /// `None` for a canvas too small to fit anything into (a window shrunk to nothing).
    fn fit(region: Aabb, rect: Rect) -> Option<Camera> {
        let empty = region.width().is_nan() || region.width() <= 0.0;
        if rect.width() < 2.0 || rect.height() < 2.0 || empty {
            return None;
        }
        let sx = f64::from(rect.width()) / region.width();
        let sy = f64::from(rect.height()) / region.height();
        Some(Camera {
            center: region.center(),
            scale: 0.92 * sx.min(sy),
        })
    }

    fn to_screen(self, rect: Rect, p: Vec2) -> Pos2 {
        let c = rect.center();
        Pos2::new(
            c.x + ((p.x - self.center.x) * self.scale) as f32,
            c.y - ((p.y - self.center.y) * self.scale) as f32,
        )
    }

    fn to_plane(self, rect: Rect, q: Pos2) -> Vec2 {
        let c = rect.center();
        Vec2::new(
            self.center.x + f64::from(q.x - c.x) / self.scale,
            self.center.y - f64::from(q.y - c.y) / self.scale,
        )
    }

    /// Zoom by `factor` about the screen point `at`, which keeps its place in the plane.
    fn zoom(&mut self, rect: Rect, at: Pos2, factor: f64) {
        if !factor.is_finite() || factor <= 0.0 {
            return;
        }
        let before = self.to_plane(rect, at);
        self.scale = (self.scale * factor).clamp(1.0, 1e5);
        let after = self.to_plane(rect, at);
        if (before - after).is_finite() {
            self.center += before - after;
        }
    }
}

/// The viewer application.
pub struct App {
    driver: Driver,
    launch: Launch,
    mode: Mode,
    camera: Option<Camera>,
    explorer_camera: Option<Camera>,
    explorer: Explorer,
    fps: Meter,
    started: Option<f64>,
    last_log: f64,
    /// Widget values that are only sent on a press (file paths: native only).
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    open_path: String,
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    save_path: String,
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    shot_path: String,
    last_label: String,
    /// Commands sent so far; a snapshot says how many the simulation has carried out.
    sent: u64,
    /// Values edited in the panel that the simulation has not seen yet.
    edits: Edits,
    /// The grains drawn on the CPU into a picture, shown as one texture, and what it shows.
    grains_picture: Option<(egui::TextureHandle, PictureKey)>,
    /// While the grains move, draw them with plain edges: set when an anti-aliased picture
    /// takes longer than [`SMOOTH_BUDGET`], cleared when a plain one takes less than
    /// [`PLAIN_BUDGET`]. Anti-aliasing triples tiny-skia's time (the 1,000-grain pour at
    /// 919 x 758 pixels: 9.2 ms against 2.8, medians), and under software OpenGL on two cores
    /// the smooth pictures held the window at 40 frames a second. A picture that stops
    /// changing (paused, or the grains at rest) is redrawn smooth.
    plain_while_playing: bool,
}

/// See [`App::plain_while_playing`] (seconds).
const SMOOTH_BUDGET: f64 = 0.005;
const PLAIN_BUDGET: f64 = 0.0015;

/// A value edited in the window, and the number of the command that carries it: until a
/// snapshot shows that command done, the panel shows the edit, not the snapshot's older value
/// (a slow step can hold the next snapshot back for seconds).
type Edit<T> = Option<(T, u64)>;

#[derive(Default)]
struct Edits {
    settings: Edit<supergrain::settings::Settings>,
    materials: Edit<crate::sim::Materials>,
    spawn: Edit<crate::sim::Spawn>,
    overlays: Edit<crate::sim::Overlays>,
    drop_shape: Edit<DropShape>,
}

/// The value to show: the edit while the simulation has not seen it, else the snapshot's.
fn shown<T: Clone>(edit: &Edit<T>, done: u64, current: T) -> T {
    match edit {
        Some((v, n)) if done < *n => v.clone(),
        _ => current,
    }
}

/// What a grains picture was drawn from: redrawn only when one of these changes.
#[derive(Clone, Debug)]
struct PictureKey {
    /// Held, so its address cannot be reused by a later snapshot.
    snapshot: Arc<Snapshot>,
    center: (f64, f64),
    scale: f64,
    size: [usize; 2],
    /// Anti-aliased (else plain edges: [`App::plain_while_playing`]).
    smooth: bool,
}

impl App {
    pub fn new(sim: Sim, launch: Launch) -> App {
        let mut driver = Driver::new(sim);
        let mut sent = 0;
        if launch.paused {
            driver.send(Command::Pause);
            sent += 1;
        }
        if let Some(n) = launch.speed {
            driver.send(Command::Speed(n));
            sent += 1;
        }
        let mode = if launch.explorer {
            Mode::Explorer
        } else {
            Mode::Simulation
        };
        App {
            driver,
            launch,
            mode,
            camera: None,
            explorer_camera: None,
            explorer: Explorer::default(),
            fps: Meter::default(),
            started: None,
            last_log: 0.0,
            open_path: String::new(),
            save_path: "supergrain-state.json".into(),
            shot_path: "supergrain-screenshot.png".into(),
            last_label: String::new(),
            grains_picture: None,
            plain_while_playing: false,
            sent,
            edits: Edits::default(),
        }
    }

    /// Called once the window exists: the worker asks for a repaint on each new snapshot.
    pub fn attach(self, ctx: &egui::Context) -> App {
        let ctx = ctx.clone();
        self.driver.on_snapshot(move || ctx.request_repaint());
        self
    }
}

fn darker(c: Color32) -> Color32 {
    Color32::from_rgb(c.r() / 2, c.g() / 2, c.b() / 2)
}

/// A superellipse as a filled fan about its centre (every superellipse is star-shaped about
/// it, so the fan is right for exponents below 1 too); the explorer draws an anti-aliased
/// outline on top.
fn add_grain(
    mesh: &mut Mesh,
    cam: Camera,
    rect: Rect,
    shape: &Superellipse,
    pose: &Pose,
    fill: Color32,
) {
    let radius_px = shape.bounding_radius() * cam.scale;
    let n = (radius_px * 1.5).clamp(12.0, 256.0) as u32;
    let base = mesh.vertices.len() as u32;
    mesh.colored_vertex(cam.to_screen(rect, pose.center()), fill);
    for p in shape.boundary_polygon(pose, n) {
        mesh.colored_vertex(cam.to_screen(rect, p), fill);
    }
    for i in 0..n {
        mesh.add_triangle(base, base + 1 + i, base + 1 + (i + 1) % n);
    }
}

/// A closed outline through `points` (a boundary polygon, its first point on the x axis) that
/// stays near the shape: drawn as an open line that begins and ends mid-side, an eighth of the
/// way round, since egui joins the corners of a closed line by miters alone, and a star's
/// sharp tip then drew a spike many times the star's size, out of its own bounding box; an
/// open line's corners sharper than a right angle are cut off.
fn outline(mut points: Vec<Pos2>, stroke: Stroke) -> Shape {
    let eighth = points.len() / 8;
    points.rotate_left(eighth);
    if let Some(&first) = points.first() {
        points.push(first);
    }
    Shape::line(points, stroke)
}

/// A boundary in its solid's colour: a segment or an arc as a thick stroke with round ends, a
/// drum as a ring outside its circle, an obstacle as a disk, a half-plane as its part of the
/// canvas.
fn paint_boundary(painter: &egui::Painter, cam: Camera, rect: Rect, b: &Boundary, fill: Color32) {
    let to = |p: Vec2| cam.to_screen(rect, p);
    let px = |d: f64| (d * cam.scale) as f32;
    let rounded = |points: Vec<Pos2>, radius: f64| {
        let w = (2.0 * px(radius)).max(1.0);
        if let (Some(&first), Some(&last)) = (points.first(), points.last()) {
            painter.circle_filled(first, w / 2.0, fill);
            painter.circle_filled(last, w / 2.0, fill);
        }
        painter.line(points, Stroke::new(w, fill));
    };
    match *b {
        Boundary::Segment { a, b, radius } => rounded(vec![to(a), to(b)], radius),
        Boundary::Arc {
            center,
            r,
            from,
            sweep,
            radius,
        } => {
            let n = 96;
            let points = (0..=n)
                .map(|k| {
                    let t = (from + sweep * f64::from(k) / f64::from(n)).to_radians();
                    to(center + Vec2::new(t.cos(), t.sin()) * r)
                })
                .collect();
            rounded(points, radius);
        }
        Boundary::Circle {
            center,
            r,
            inside: true,
        } => {
            let w = 6.0;
            painter.circle_stroke(to(center), px(r) + w / 2.0, Stroke::new(w, fill));
        }
        Boundary::Circle {
            center,
            r,
            inside: false,
        } => {
            painter.circle_filled(to(center), px(r), fill);
        }
        Boundary::Plane(h) => {
            // The canvas's corners in the plane, clipped to the solid side (`g <= 0`).
            let corners = [
                rect.left_top(),
                rect.right_top(),
                rect.right_bottom(),
                rect.left_bottom(),
            ]
            .map(|q| cam.to_plane(rect, q));
            let g = |p: Vec2| h.value(p);
            let mut solid = Vec::new();
            for k in 0..4 {
                let (p, q) = (corners[k], corners[(k + 1) % 4]);
                let (gp, gq) = (g(p), g(q));
                if gp <= 0.0 {
                    solid.push(to(p));
                }
                if (gp < 0.0) != (gq < 0.0) && gp != gq {
                    solid.push(to(p + (q - p) * (gp / (gp - gq))));
                }
            }
            if solid.len() >= 3 {
                painter.add(egui::Shape::convex_polygon(solid, fill, Stroke::NONE));
            }
        }
    }
}

/// A measure's headline over time, as a line in a small chart with its range.
fn measure_chart(ui: &mut egui::Ui, m: &crate::sim::Measured) {
    ui.label(egui::RichText::new(&m.summary).small());
    if m.points.len() < 2 {
        return;
    }
    let (lo, hi) = m
        .points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p[1]), hi.max(p[1]))
        });
    let (t0, t1) = (m.points[0][0], m.points[m.points.len() - 1][0]);
    let (response, painter) =
        ui.allocate_painter(egui::vec2(ui.available_width(), 60.0), Sense::hover());
    let r = response.rect.shrink(2.0);
    painter.rect_stroke(
        response.rect,
        2.0,
        Stroke::new(1.0, Color32::from_gray(90)),
        egui::StrokeKind::Inside,
    );
    let span = if hi > lo { hi - lo } else { 1.0 };
    let dt = if t1 > t0 { t1 - t0 } else { 1.0 };
    let points = m
        .points
        .iter()
        .map(|p| {
            Pos2::new(
                r.left() + ((p[0] - t0) / dt) as f32 * r.width(),
                r.bottom() - ((p[1] - lo) / span) as f32 * r.height(),
            )
        })
        .collect();
    painter.line(points, Stroke::new(1.5, Color32::from_rgb(0, 150, 150)));
    ui.label(
        egui::RichText::new(format!(
            "{}: {} to {} over t = {t0:.2} to {t1:.2}",
            m.what,
            short(lo),
            short(hi)
        ))
        .small(),
    );
}

/// A number in a few characters.
fn short(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e5) {
        format!("{v:.3e}")
    } else {
        format!("{v:.4}")
    }
}

fn paint_box(painter: &egui::Painter, cam: Camera, rect: Rect, b: &Aabb, stroke: Stroke) {
    let r = Rect::from_two_pos(cam.to_screen(rect, b.min), cam.to_screen(rect, b.max));
    painter.rect_stroke(r, 0.0, stroke, egui::StrokeKind::Middle);
}

/// A quadtree cell in the colours of the paper's figures (`supergrain figures`).
fn paint_cell(painter: &egui::Painter, cam: Camera, rect: Rect, c: &ClassedCell) {
    let rgba = |[r, g, b, a]: [u8; 4]| Color32::from_rgba_unmultiplied(r, g, b, a);
    let (fill, line) = cell_style(c.a, c.b, c.last);
    let stroke = line.map_or(Stroke::NONE, |(colour, width)| {
        Stroke::new(width, rgba(colour))
    });
    let pts = c.corners.map(|p| cam.to_screen(rect, p)).to_vec();
    painter.add(Shape::convex_polygon(
        pts,
        fill.map_or(Color32::TRANSPARENT, rgba),
        stroke,
    ));
}

fn paint_arrow(painter: &egui::Painter, cam: Camera, rect: Rect, from: Vec2, push: Vec2) {
    let (a, b) = (cam.to_screen(rect, from), cam.to_screen(rect, from + push));
    let red = Color32::from_rgb(0xd8, 0x1b, 0x60);
    painter.line_segment([a, b], Stroke::new(2.0, red));
    painter.circle_filled(a, 3.0, Color32::from_rgb(0x1a, 0x23, 0x7e));
}

impl App {
    /// Sends a command; returns its number.
    fn send(&mut self, c: Command) -> u64 {
        self.driver.send(c);
        self.sent += 1;
        self.sent
    }

    fn top_bar(&mut self, ui: &mut egui::Ui, snap: &Snapshot, sps: f64) {
        ui.horizontal_wrapped(|ui| {
            ui.selectable_value(&mut self.mode, Mode::Simulation, "Simulation");
            ui.selectable_value(&mut self.mode, Mode::Explorer, "Collision explorer");
            ui.separator();
            if snap.playing {
                if ui.button("⏸ Pause").clicked() {
                    self.send(Command::Pause);
                }
            } else if ui.button("▶ Play").clicked() {
                self.send(Command::Play);
            }
            if ui.button("Step").clicked() {
                self.send(Command::Step);
            }
            if ui.button("Reset").clicked() {
                self.send(Command::Reset);
            }
            let mut speed = snap.speed;
            if ui
                .add(
                    egui::Slider::new(&mut speed, 1..=MAX_SPEED)
                        .clamping(egui::SliderClamping::Edits)
                        .text("steps/frame"),
                )
                .changed()
            {
                self.send(Command::Speed(speed));
            }
            ui.separator();
            ui.label(format!(
                "{:.0} fps · {:.0} steps/s · step {} · {} grains ({} asleep, {} to come)",
                self.fps.rate(),
                sps,
                snap.step,
                snap.grains.len(),
                snap.asleep,
                snap.pending
            ));
        });
    }

    fn side_panel(&mut self, ui: &mut egui::Ui, snap: &Snapshot) {
        ui.heading("Scene");
        ui.label(&snap.label);
        egui::ComboBox::from_label("preset")
            .selected_text("choose…")
            .show_ui(ui, |ui| {
                for name in crate::sim::presets() {
                    if ui.selectable_label(false, *name).clicked() {
                        self.send(Command::Preset((*name).to_string()));
                    }
                }
            });
        #[cfg(not(target_arch = "wasm32"))]
        ui.horizontal(|ui| {
            ui.text_edit_singleline(&mut self.open_path)
                .on_hover_text("a scene file (TOML); or drop one on the window");
            if ui.button("Open").clicked() {
                let command = match std::fs::read_to_string(&self.open_path) {
                    Ok(text) => Command::Open {
                        name: self.open_path.clone(),
                        text,
                    },
                    Err(e) => {
                        Command::Notice(format!("cannot read scene file {}: {e}", self.open_path))
                    }
                };
                self.send(command);
            }
        });
        #[cfg(target_arch = "wasm32")]
        ui.label("Drop a scene file (TOML) on the page to open it.");

        ui.separator();
        ui.heading("Solver");
        if let Some(current) = snap.settings {
            let mut t = shown(&self.edits.settings, snap.commands, current);
            let before = t;
            ui.add(
                egui::Slider::new(&mut t.step, 0.001..=0.05)
                    .clamping(egui::SliderClamping::Edits)
                    .logarithmic(true)
                    .text("time step"),
            );
            // The panel follows the scene's model: the soft step's substeps, contact and drag;
            // the paper's projection's damping and passes.
            match t.model {
                Model::Soft => soft_sliders(ui, &mut t.soft),
                Model::Paper => {
                    ui.add(
                        egui::Slider::new(&mut t.damping, 0.0..=0.99)
                            .clamping(egui::SliderClamping::Edits)
                            .text("damping"),
                    );
                    ui.add(
                        egui::Slider::new(&mut t.max_iterations, 1..=MAX_ITERATIONS)
                            .clamping(egui::SliderClamping::Edits)
                            .text("iterations"),
                    );
                }
            }
            let (mut depth, mut eps) = (t.precision.depth(), t.precision.eps());
            ui.add(
                egui::Slider::new(&mut depth, 1..=MAX_DEPTH)
                    .clamping(egui::SliderClamping::Edits)
                    .text("quadtree depth"),
            );
            ui.add(
                egui::Slider::new(&mut eps, 0.0..=0.1)
                    .clamping(egui::SliderClamping::Edits)
                    .logarithmic(true)
                    .text("quadtree eps"),
            );
            // (A slider's value is in range: the window's command refuses anything else.)
            if let Ok(p) = Precision::new(depth, eps) {
                t.precision = p;
            }
            if t != before {
                let n = self.send(Command::Tune(t));
                self.edits.settings = Some((t, n));
            }
        }
        if let Some(current) = &snap.materials {
            self.materials_panel(ui, snap.commands, current);
        }
        if !snap.measures.is_empty() {
            ui.separator();
            ui.heading("Measures");
            for m in &snap.measures {
                egui::CollapsingHeader::new(m.kind)
                    .default_open(true)
                    .show(ui, |ui| measure_chart(ui, m));
            }
        }
        ui.heading("Spawn rule");
        if let Some(current) = snap.spawn {
            let mut s = shown(&self.edits.spawn, snap.commands, current);
            let before = s;
            ui.add(
                egui::Slider::new(&mut s.interval, 1..=200)
                    .clamping(egui::SliderClamping::Edits)
                    .text("steps between grains"),
            );
            ui.add(
                egui::Slider::new(&mut s.top, 1.0..=40.0)
                    .clamping(egui::SliderClamping::Edits)
                    .text("height"),
            );
            if s != before {
                let n = self.send(Command::Spawn(s));
                self.edits.spawn = Some((s, n));
            }
            ui.small("applies from the next reset");
        }

        ui.separator();
        ui.heading("Overlays");
        let before = shown(&self.edits.overlays, snap.commands, snap.overlays);
        let mut o = before;
        ui.checkbox(&mut o.boxes, "bounding boxes");
        ui.checkbox(&mut o.cells, "quadtree cells of contacts");
        ui.checkbox(&mut o.vectors, "penetration vectors");
        if o != before {
            let n = self.send(Command::Overlays(o));
            self.edits.overlays = Some((o, n));
        }

        ui.separator();
        ui.heading("Click to drop");
        let before = shown(&self.edits.drop_shape, snap.commands, snap.drop_shape);
        let mut d = before;
        shape_sliders(ui, &mut d.semi_axes, &mut d.exponents, &mut d.angle);
        if d != before {
            let n = self.send(Command::DropShape(d));
            self.edits.drop_shape = Some((d, n));
        }
        ui.small(
            "left click: drop · left drag on a grain: move it · right drag: pan · wheel: zoom",
        );

        #[cfg(not(target_arch = "wasm32"))]
        {
            ui.separator();
            ui.heading("Save");
            ui.horizontal(|ui| {
                ui.text_edit_singleline(&mut self.shot_path);
                if ui.button("Picture").clicked() {
                    self.driver
                        .screenshot(std::path::PathBuf::from(&self.shot_path), 1200);
                }
            });
            ui.horizontal(|ui| {
                ui.text_edit_singleline(&mut self.save_path);
                if ui.button("State").clicked() {
                    self.driver
                        .save_state(std::path::PathBuf::from(&self.save_path));
                }
            });
        }
        #[cfg(target_arch = "wasm32")]
        {
            ui.separator();
            ui.heading("Save");
            ui.horizontal(|ui| {
                if ui.button("Picture").clicked() {
                    self.driver.screenshot("supergrain-screenshot.png", 1200);
                }
                if ui.button("State").clicked() {
                    self.driver.save_state("supergrain-state.json");
                }
            });
            ui.small(
                "downloads: the picture as PNG, the state as a dump (supergrain view --state)",
            );
        }
    }

    /// The soft model's materials: a group's or the walls' changes from the next step.
    fn materials_panel(&mut self, ui: &mut egui::Ui, done: u64, current: &crate::sim::Materials) {
        ui.heading("Materials");
        let before = shown(&self.edits.materials, done, current.clone());
        let mut m = before.clone();
        for (k, (name, material)) in m.groups.iter_mut().enumerate() {
            egui::CollapsingHeader::new(name.as_str())
                .id_salt(("material", k))
                .default_open(true)
                .show(ui, |ui| material_sliders(ui, material, true));
        }
        egui::CollapsingHeader::new("walls")
            .id_salt("walls material")
            .default_open(true)
            .show(ui, |ui| material_sliders(ui, &mut m.walls, false));
        let mut last = None;
        for (k, ((_, now), (_, was))) in m.groups.iter().zip(&before.groups).enumerate() {
            if now != was {
                last = Some(self.send(Command::Material(MaterialOf::Group(k as u32), *now)));
            }
        }
        if m.walls != before.walls {
            last = Some(self.send(Command::Material(MaterialOf::Walls, m.walls)));
        }
        if let Some(n) = last {
            self.edits.materials = Some((m, n));
        }
        ui.small("applies from the next step; a new density gives the grains their new mass");
    }

    fn canvas(&mut self, ui: &mut egui::Ui, snap: &Arc<Snapshot>) {
        let (response, painter) = ui.allocate_painter(ui.available_size(), Sense::click_and_drag());
        let rect = response.rect;
        let [left, right, floor] = snap.walls;
        // The box, and the boundaries wherever they reach (a drum above the top).
        let region = snap.boundaries.iter().filter_map(Boundary::extent).fold(
            Aabb::new(
                Vec2::new(left, floor),
                Vec2::new(right, snap.top.max(floor + 1.0)),
            ),
            |r, e| r.union(&e),
        );
        if self.last_label != snap.label {
            self.camera = None;
            self.last_label = snap.label.clone();
        }
        if self.camera.is_none() {
            self.camera = Camera::fit(region, rect);
        }
        let Some(cam) = self.camera.as_mut() else {
            return;
        };
        pan_and_zoom(ui, &response, rect, cam);
        let cam = *cam;

        // The grains' picture, on the canvas's background, covers only the box and the grains
        // (wherever they are): the rest of the canvas is the window's clear colour, the same
        // grey ([`App::clear_color`]). Over the whole canvas, the 1,000-grain pour's picture
        // was twice the pixels to fill, upload and draw (software OpenGL drew a paused window
        // at 65 frames a second on 0.9 cores).
        let occupied = snap
            .grains
            .iter()
            .fold(region, |r, g| r.union(&g.shape.bounding_box(&g.pose)));
        let (a, b) = (
            cam.to_screen(rect, occupied.min),
            cam.to_screen(rect, occupied.max),
        );
        let picture = Rect::from_two_pos(a, b).expand(1.0).intersect(rect);
        let picture = Rect::from_min_max(picture.min.floor(), picture.max.ceil());
        if picture.is_positive() {
            let at = Camera {
                center: cam.to_plane(rect, picture.center()),
                scale: cam.scale,
            };
            self.paint_grains(ui, &painter, picture, at, snap);
        }
        // The box: floor and walls up to where grains appear.
        let wall = Stroke::new(2.0, Color32::from_gray(60));
        let (bl, br) = (Vec2::new(left, floor), Vec2::new(right, floor));
        let (tl, tr) = (Vec2::new(left, snap.top), Vec2::new(right, snap.top));
        painter.line(
            [tl, bl, br, tr].map(|p| cam.to_screen(rect, p)).to_vec(),
            wall,
        );
        for b in &snap.boundaries {
            paint_boundary(&painter, cam, rect, b, Color32::from_gray(60));
        }
        for sink in &snap.sinks {
            paint_box(
                &painter,
                cam,
                rect,
                sink,
                Stroke::new(1.5, Color32::from_rgb(0, 128, 128)),
            );
        }
        if snap.overlays.boxes {
            for g in &snap.grains {
                let b = g.shape.bounding_box(&g.pose);
                paint_box(
                    &painter,
                    cam,
                    rect,
                    &b,
                    Stroke::new(1.0, Color32::from_gray(90)),
                );
            }
        }
        for c in &snap.cells {
            paint_cell(&painter, cam, rect, c);
        }
        if snap.overlays.vectors {
            for p in &snap.contacts {
                paint_arrow(&painter, cam, rect, p.a_deepest, p.a_push);
                paint_arrow(&painter, cam, rect, p.b_deepest, p.b_push);
            }
            for p in &snap.wall_contacts {
                paint_arrow(&painter, cam, rect, p.deepest, p.push);
            }
        }

        // The hand: click to drop, drag a grain to move it.
        if response.drag_started_by(PointerButton::Primary)
            && let Some(q) = response.interact_pointer_pos()
        {
            self.send(Command::Grab(cam.to_plane(rect, q)));
        }
        if response.dragged_by(PointerButton::Primary)
            && let Some(q) = response.interact_pointer_pos()
        {
            self.send(Command::DragTo(cam.to_plane(rect, q)));
        }
        if response.drag_stopped() {
            self.send(Command::Release);
        }
        if response.clicked_by(PointerButton::Primary)
            && let Some(q) = response.interact_pointer_pos()
        {
            self.send(Command::Drop(cam.to_plane(rect, q)));
        }
    }

    /// The grains, anti-aliased polygons filled by tiny-skia into one picture shown as one
    /// texture. Drawing them as meshes would be simpler, but a thousand grains make tens of
    /// thousands of small triangles, and where there is no GPU (software OpenGL) each costs a
    /// setup: 31 fps against 60 here for the settled 1,000-grain pour.
    fn paint_grains(
        &mut self,
        ui: &egui::Ui,
        painter: &egui::Painter,
        rect: Rect,
        cam: Camera,
        snap: &Arc<Snapshot>,
    ) {
        // No larger than the GPU takes in one texture: past that, fewer pixels per point.
        let max_side = ui.ctx().input(|i| i.max_texture_side) as f64;
        let longest = f64::from(rect.width().max(rect.height())).max(1.0);
        let ppp = f64::from(ui.ctx().pixels_per_point()).min(max_side / longest);
        let size = [
            (f64::from(rect.width()) * ppp).round().max(1.0) as usize,
            (f64::from(rect.height()) * ppp).round().max(1.0) as usize,
        ];
        let clock = seconds();
        let smooth = clock.is_none() || !(snap.playing && self.plain_while_playing);
        let key = PictureKey {
            snapshot: Arc::clone(snap),
            center: (cam.center.x, cam.center.y),
            scale: cam.scale,
            size,
            smooth,
        };
        // The same picture, or a smooth one where a plain one would do.
        let same = |k: &PictureKey| {
            Arc::ptr_eq(&k.snapshot, &key.snapshot)
                && k.center == key.center
                && k.scale == key.scale
                && k.size == key.size
                && k.smooth >= key.smooth
        };
        if !self.grains_picture.as_ref().is_some_and(|(_, k)| same(k)) {
            let image = crate::picture::grains(
                &snap.grains,
                snap.held,
                size,
                cam.center,
                cam.scale * ppp,
                smooth,
            );
            if let (Some(start), Some(end)) = (clock, seconds()) {
                let took = end - start;
                if smooth && snap.playing && took > SMOOTH_BUDGET {
                    self.plain_while_playing = true;
                } else if !smooth && took < PLAIN_BUDGET {
                    self.plain_while_playing = false;
                }
            }
            match &mut self.grains_picture {
                Some((texture, k)) => {
                    texture.set(image, egui::TextureOptions::NEAREST);
                    *k = key;
                }
                None => {
                    let texture =
                        ui.ctx()
                            .load_texture("grains", image, egui::TextureOptions::NEAREST);
                    self.grains_picture = Some((texture, key));
                }
            }
        }
        if let Some((texture, _)) = &self.grains_picture {
            let uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
            painter.image(texture.id(), rect, uv, Color32::WHITE);
        }
    }

    fn explorer_panel(&mut self, ui: &mut egui::Ui) {
        ui.heading("Shape A (fixed)");
        let a = &mut self.explorer.a;
        shape_sliders(ui, &mut a.semi_axes, &mut a.exponents, &mut a.angle);
        ui.heading("Shape B (follows the mouse)");
        let b = &mut self.explorer.b;
        shape_sliders(ui, &mut b.semi_axes, &mut b.exponents, &mut b.angle);
        ui.heading("Quadtree");
        ui.add(
            egui::Slider::new(&mut self.explorer.depth, 1..=MAX_DEPTH)
                .clamping(egui::SliderClamping::Edits)
                .text("depth"),
        );
        ui.small("Cells: grey outside either shape, orange inside both, blue on a boundary (filled at the last level). Dots: the deepest points; red: the penetration vectors.");
    }

    fn explorer_canvas(&mut self, ui: &mut egui::Ui) {
        let (response, painter) = ui.allocate_painter(ui.available_size(), Sense::click_and_drag());
        let rect = response.rect;
        painter.rect_filled(rect, 0.0, Color32::WHITE);
        if self.explorer_camera.is_none() {
            self.explorer_camera = Camera::fit(Explorer::region(), rect);
        }
        let Some(cam) = self.explorer_camera.as_mut() else {
            return;
        };
        pan_and_zoom(ui, &response, rect, cam);
        let cam = *cam;
        if let Some(q) = response.hover_pos() {
            self.explorer.b_center = cam.to_plane(rect, q);
        }
        let eval = match self.explorer.evaluate() {
            Ok(e) => e,
            Err(e) => {
                painter.text(
                    rect.center(),
                    egui::Align2::CENTER_CENTER,
                    e,
                    egui::FontId::proportional(16.0),
                    Color32::RED,
                );
                return;
            }
        };
        let tints = [
            Color32::from_rgba_unmultiplied(0x2e, 0x7d, 0x32, 70),
            Color32::from_rgba_unmultiplied(0x6a, 0x1b, 0x9a, 70),
        ];
        let mut mesh = Mesh::default();
        for ((shape, pose), tint) in eval.shapes.iter().zip(tints) {
            add_grain(&mut mesh, cam, rect, shape, pose, tint);
        }
        painter.add(Shape::mesh(mesh));
        for ((shape, pose), tint) in eval.shapes.iter().zip(tints) {
            let points: Vec<Pos2> = shape
                .boundary_polygon(pose, 256)
                .into_iter()
                .map(|p| cam.to_screen(rect, p))
                .collect();
            painter.add(outline(points, Stroke::new(1.5, darker(tint.to_opaque()))));
        }
        for c in &eval.cells {
            paint_cell(&painter, cam, rect, c);
        }
        let common = eval.boxes[0].intersection(&eval.boxes[1]);
        for b in eval.boxes.iter().chain(common.iter()) {
            paint_box(
                &painter,
                cam,
                rect,
                b,
                Stroke::new(1.0, Color32::from_gray(100)),
            );
        }
        let text = match eval.contact.penetration {
            Some(p) => {
                paint_arrow(&painter, cam, rect, p.a_deepest, p.a_push);
                paint_arrow(&painter, cam, rect, p.b_deepest, p.b_push);
                format!(
                    "overlap · penetration {:.4} · {} cells",
                    p.depth(),
                    eval.contact.cells
                )
            }
            None => format!(
                "apart (or within a final cell) · {} cells",
                eval.contact.cells
            ),
        };
        painter.text(
            rect.left_top() + EVec2::new(8.0, 8.0),
            egui::Align2::LEFT_TOP,
            text,
            egui::FontId::proportional(15.0),
            Color32::BLACK,
        );
    }

    fn dropped_files(&mut self, ctx: &egui::Context) {
        let dropped = ctx.input(|i| i.raw.dropped_files.clone());
        for f in dropped {
            let text = if let Some(bytes) = &f.bytes {
                String::from_utf8(bytes.to_vec()).map_err(|_| "not UTF-8 text".to_string())
            } else if let Some(path) = &f.path {
                std::fs::read_to_string(path).map_err(|e| e.to_string())
            } else {
                Err("nothing to read".to_string())
            };
            let name = if f.name.is_empty() {
                f.path
                    .as_ref()
                    .map(|p| p.display().to_string())
                    .unwrap_or_default()
            } else {
                f.name.clone()
            };
            let command = match text {
                Ok(text) => Command::Open { name, text },
                Err(e) => Command::Notice(format!("cannot read {name}: {e}")),
            };
            self.send(command);
        }
    }
}

/// The soft step's settings (docs/reference.md, `[solver]`), each in its scene key's range.
fn soft_sliders(ui: &mut egui::Ui, s: &mut supergrain::settings::SoftSettings) {
    ui.add(egui::Slider::new(&mut s.substeps, 1..=64).text("substeps"));
    ui.add(
        egui::Slider::new(&mut s.contact_hertz, 1.0..=1000.0)
            .clamping(egui::SliderClamping::Edits)
            .logarithmic(true)
            .text("contact stiffness (Hz)"),
    );
    ui.add(
        egui::Slider::new(&mut s.damping_ratio, 0.0..=20.0)
            .clamping(egui::SliderClamping::Edits)
            .text("contact damping ratio"),
    );
    ui.add(
        egui::Slider::new(&mut s.push_out, 0.1..=20.0)
            .clamping(egui::SliderClamping::Edits)
            .logarithmic(true)
            .text("push-out speed"),
    );
    ui.add(
        egui::Slider::new(&mut s.restitution_threshold, 0.0..=5.0)
            .clamping(egui::SliderClamping::Edits)
            .text("restitution threshold"),
    );
    ui.add(
        egui::Slider::new(&mut s.linear_damping, 0.0..=5.0)
            .clamping(egui::SliderClamping::Edits)
            .text("air drag"),
    );
    ui.add(
        egui::Slider::new(&mut s.angular_damping, 0.0..=5.0)
            .clamping(egui::SliderClamping::Edits)
            .text("angular drag"),
    );
}

fn shape_sliders(
    ui: &mut egui::Ui,
    semi_axes: &mut [f64; 2],
    exponents: &mut [f64; 2],
    angle: &mut f64,
) {
    ui.add(
        egui::Slider::new(&mut semi_axes[0], 0.05..=2.0)
            .clamping(egui::SliderClamping::Edits)
            .text("semi-axis x"),
    );
    ui.add(
        egui::Slider::new(&mut semi_axes[1], 0.05..=2.0)
            .clamping(egui::SliderClamping::Edits)
            .text("semi-axis y"),
    );
    ui.add(
        egui::Slider::new(&mut exponents[0], 0.3..=10.0)
            .clamping(egui::SliderClamping::Edits)
            .logarithmic(true)
            .text("exponent x"),
    );
    ui.add(
        egui::Slider::new(&mut exponents[1], 0.3..=10.0)
            .clamping(egui::SliderClamping::Edits)
            .logarithmic(true)
            .text("exponent y"),
    );
    ui.add(
        egui::Slider::new(angle, -3.2..=3.2)
            .clamping(egui::SliderClamping::Edits)
            .text("angle"),
    );
}

/// A material's sliders; the walls do not move, so their density is never used.
fn material_sliders(ui: &mut egui::Ui, m: &mut Material, density: bool) {
    if density {
        ui.add(
            egui::Slider::new(&mut m.density, 0.1..=10.0)
                .clamping(egui::SliderClamping::Edits)
                .logarithmic(true)
                .text("density"),
        );
    }
    ui.add(
        egui::Slider::new(&mut m.friction, 0.0..=2.0)
            .clamping(egui::SliderClamping::Edits)
            .text("friction"),
    );
    ui.add(
        egui::Slider::new(&mut m.restitution, 0.0..=1.0)
            .clamping(egui::SliderClamping::Edits)
            .text("restitution"),
    );
    ui.add(
        egui::Slider::new(&mut m.rolling_resistance, 0.0..=1.0)
            .clamping(egui::SliderClamping::Edits)
            .text("rolling resistance"),
    );
}

/// Seconds on a monotonic clock, natively (the browser's build has no `Instant`: its
/// pictures are always smooth).
fn seconds() -> Option<f64> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        static CLOCK: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
        Some(
            CLOCK
                .get_or_init(std::time::Instant::now)
                .elapsed()
                .as_secs_f64(),
        )
    }
    #[cfg(target_arch = "wasm32")]
    None
}

/// The time to the next tick of a 60 Hz clock started with the first frame.
#[cfg(not(target_arch = "wasm32"))]
fn until_next_tick() -> std::time::Duration {
    let t = seconds().unwrap_or(0.0);
    let tick = 1.0 / 60.0;
    std::time::Duration::from_secs_f64(((t / tick).floor() + 1.0) * tick - t)
}

fn pan_and_zoom(ui: &egui::Ui, response: &egui::Response, rect: Rect, cam: &mut Camera) {
    if response.dragged_by(PointerButton::Secondary) || response.dragged_by(PointerButton::Middle) {
        let d = response.drag_delta();
        cam.center -= Vec2::new(f64::from(d.x) / cam.scale, -f64::from(d.y) / cam.scale);
    }
    if let Some(at) = response.hover_pos() {
        let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
        let factor = f64::from(zoom) * (f64::from(scroll) * 0.002).exp();
        if factor != 1.0 {
            cam.zoom(rect, at, factor);
        }
    }
}

impl eframe::App for App {
    /// The canvas's background, around the grains' picture.
    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        crate::picture::BACKGROUND.to_normalized_gamma_f32()
    }

    fn update(&mut self, ctx: &egui::Context, _frame: &mut eframe::Frame) {
        let now = ctx.input(|i| i.time);
        let started = *self.started.get_or_insert(now);
        self.fps.count(1, now);
        self.dropped_files(ctx);
        let frame = self.driver.frame(now);
        let snap: Arc<Snapshot> = frame.snapshot;

        if self.launch.log_fps && now - self.last_log >= 1.0 {
            self.last_log = now;
            log_line(&format!(
                "fps {:.1} steps/s {:.1} step {} grains {} t {:.1}",
                self.fps.rate(),
                frame.steps_per_second,
                snap.step,
                snap.grains.len(),
                now - started
            ));
        }
        if let Some(t) = self.launch.quit_after
            && now - started >= t
        {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }

        egui::TopBottomPanel::top("controls")
            .show(ctx, |ui| self.top_bar(ui, &snap, frame.steps_per_second));
        egui::TopBottomPanel::bottom("status").show(ctx, |ui| {
            ui.label(
                snap.message
                    .as_deref()
                    .unwrap_or("Drop a scene file on the window to open it."),
            );
        });
        match self.mode {
            Mode::Simulation => {
                egui::SidePanel::left("settings")
                    .resizable(false)
                    .show(ctx, |ui| {
                        egui::ScrollArea::vertical().show(ui, |ui| self.side_panel(ui, &snap))
                    });
                egui::CentralPanel::default()
                    .frame(egui::Frame::NONE)
                    .show(ctx, |ui| self.canvas(ui, &snap));
            }
            Mode::Explorer => {
                egui::SidePanel::left("explorer")
                    .resizable(false)
                    .show(ctx, |ui| {
                        egui::ScrollArea::vertical().show(ui, |ui| self.explorer_panel(ui))
                    });
                egui::CentralPanel::default()
                    .frame(egui::Frame::NONE)
                    .show(ctx, |ui| self.explorer_canvas(ui));
            }
        }
        // Natively the worker asks for a repaint with each snapshot, and frames are drawn on
        // the ticks of a 60 Hz clock: a repaint asked for a sixtieth of a second after each
        // frame's end made every period that much longer than the frame (50-59 frames a second
        // measured for the 1,000-grain pour under software OpenGL). A browser paces frames
        // itself.
        if snap.playing || self.launch.quit_after.is_some() || self.launch.log_fps {
            #[cfg(not(target_arch = "wasm32"))]
            ctx.request_repaint_after(until_next_tick());
            #[cfg(target_arch = "wasm32")]
            ctx.request_repaint();
        }
    }
}

#[cfg(test)]
mod tests {
    use eframe::egui::epaint::{Mesh, TessellationOptions, Tessellator};
    use eframe::egui::{Color32, Pos2, Stroke};
    use supergrain::geometry::Vec2;
    use supergrain::shape::{Pose, Superellipse};

    use super::outline;

    /// The explorer's outline of a star stays within the star's bounding box, grown by the
    /// line's width: drawn as a closed line, its tips were miter spikes reaching far out.
    #[test]
    fn a_stars_outline_stays_in_its_bounding_box() {
        for exponent in [0.3, 0.5, 0.7] {
            let star = Superellipse::new([1.0, 0.6], [exponent, exponent]).expect("a star");
            let pose = Pose::new(Vec2::new(0.3, -0.2), 0.4).expect("a pose");
            // 100 pixels a unit, y down, as the explorer's camera.
            let to_screen = |p: Vec2| Pos2::new((100.0 * p.x) as f32, (-100.0 * p.y) as f32);
            let points: Vec<Pos2> = star
                .boundary_polygon(&pose, 256)
                .into_iter()
                .map(to_screen)
                .collect();
            let width = 1.5;
            let options = TessellationOptions {
                feathering: false,
                ..TessellationOptions::default()
            };
            let mut tessellator = Tessellator::new(1.0, options, [1, 1], Vec::new());
            let mut mesh = Mesh::default();
            tessellator.tessellate_shape(
                outline(points, Stroke::new(width, Color32::BLACK)),
                &mut mesh,
            );
            assert!(!mesh.vertices.is_empty());
            let bb = star.bounding_box(&pose);
            let (lo, hi) = (to_screen(bb.min), to_screen(bb.max));
            let reach = 2.0 * width;
            for v in &mesh.vertices {
                let p = v.pos;
                assert!(
                    p.x >= lo.x - reach
                        && p.x <= hi.x + reach
                        && p.y <= lo.y + reach
                        && p.y >= hi.y - reach,
                    "exponent {exponent}: outline vertex {p:?} outside the star's box \
                     ({lo:?}, {hi:?}) grown by {reach} px"
                );
            }
        }
    }
}

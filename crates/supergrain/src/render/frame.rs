//! A whole world as a picture: grains painted by the interval renderer ([`super::raster`]),
//! walls and overlays stroked with tiny-skia (lines and rectangles are what a vector
//! rasteriser does well).

use tiny_skia::{Color, Pixmap};

use super::pen::Pen;
use super::raster::{Antialias, Rgba, View, paint_shape_with};
use crate::geometry::{Aabb, Vec2};
use crate::interval::PlacedSuperellipse;
use crate::shape::Superellipse;
use crate::solver::soft;
use crate::world::{Touch, World};

/// How grains are coloured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Colouring {
    /// By shape class, from the smaller exponent: stars red, diamond-like orange, ellipses
    /// green, blocky blue (as the README's pictures).
    Exponent,
    /// A fixed palette cycled by grain index, so neighbours differ.
    Palette,
    /// The same palette by scene group: the scene's first `[[group]]` blue, the second red,
    /// then green, orange, purple, cyan, brown, lime (and round again).
    Group,
    /// One colour for all.
    Uniform(Rgba),
}

/// What a frame shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Image width in pixels; the height follows the region's aspect ratio.
    pub width: u32,
    /// The part of the plane shown; `None`: the box up to where grains appear (or the highest
    /// grain), with a small margin.
    pub region: Option<Aabb>,
    pub background: Rgba,
    pub colouring: Colouring,
    /// How boundary pixels are anti-aliased (the paper's: `Split(1)`).
    pub antialias: Antialias,
    /// Draw the box's walls and floor.
    pub walls: bool,
    /// Overlay every grain's bounding box and, filled, the intersections of overlapping boxes
    /// (paper Figs. 4, 5).
    pub boxes: bool,
    /// Overlay the deepest points and penetration vectors of every contact (paper Figs. 6-8).
    pub contacts: bool,
    /// Overlay force chains (the soft model's): a line through each contact from centre to
    /// centre (or to the wall), its width growing with the normal force.
    pub forces: bool,
}

impl Default for Style {
    fn default() -> Self {
        Style {
            width: 800,
            region: None,
            background: [250, 250, 250, 255],
            colouring: Colouring::Exponent,
            antialias: Antialias::Gradient,
            walls: true,
            boxes: false,
            contacts: false,
            forces: false,
        }
    }
}

/// The colour of a shape by class (see [`Colouring::Exponent`]).
pub fn exponent_colour(shape: &Superellipse) -> Rgba {
    let e = shape.exponents()[0].min(shape.exponents()[1]);
    if e < 1.0 {
        [0xe5, 0x39, 0x35, 255]
    } else if e < 2.0 {
        [0xfb, 0x8c, 0x00, 255]
    } else if e <= 2.0 {
        [0x43, 0xa0, 0x47, 255]
    } else {
        [0x1e, 0x88, 0xe5, 255]
    }
}

const PALETTE: [Rgba; 8] = [
    [0x1e, 0x88, 0xe5, 255],
    [0xe5, 0x39, 0x35, 255],
    [0x43, 0xa0, 0x47, 255],
    [0xfb, 0x8c, 0x00, 255],
    [0x8e, 0x24, 0xaa, 255],
    [0x00, 0xac, 0xc1, 255],
    [0x6d, 0x4c, 0x41, 255],
    [0xc0, 0xca, 0x33, 255],
];

/// The default region of a world: the box up to where grains appear plus the largest grain,
/// placed or that can still appear (so a grain appearing is whole), or up to the highest grain
/// if one is above that.
pub fn world_region(world: &World) -> Aabb {
    let w = world.walls;
    let highest = world
        .bodies
        .iter()
        .map(|b| b.bounding_box().max.y)
        .fold(f64::NEG_INFINITY, f64::max);
    let largest = world
        .bodies
        .iter()
        .map(|b| b.shape.bounding_radius())
        .fold(world.pending.largest_bounding_radius(), f64::max);
    let top = (world.top + largest).max(highest).max(w.floor + 1.0);
    let margin = 0.04 * (w.right - w.left);
    let mut region = Aabb::new(
        Vec2::new(w.left - margin, w.floor - margin),
        Vec2::new(w.right + margin, top + margin),
    );
    // Boundaries beyond the box (a drum's circle) are in the picture too.
    for b in world.boundaries.iter().filter_map(|b| b.extent()) {
        region = region.union(&b.grown(margin));
    }
    region
}

/// The walls', the planes' and the fixed bodies' colour.
pub const WALL_COLOUR: [u8; 4] = [0x37, 0x47, 0x4f, 255];

/// The outline of a sink's region.
pub const SINK_COLOUR: [u8; 4] = [0x00, 0x96, 0x88, 255];

/// Draws a world.
pub fn render_world(world: &World, style: &Style) -> Pixmap {
    let view = View::fit(
        style.region.unwrap_or_else(|| world_region(world)),
        style.width,
    );
    let mut pixmap = Pixmap::new(view.width, view.height).expect("a non-empty image");
    let [r, g, b, a] = style.background;
    pixmap.fill(Color::from_rgba8(r, g, b, a));
    for (i, body) in world.bodies.iter().enumerate() {
        let colour = match style.colouring {
            // A fixed or driven body is part of the container: in the walls' colour.
            _ if !body.kind.is_dynamic() && style.walls => WALL_COLOUR,
            Colouring::Exponent => exponent_colour(&body.shape),
            Colouring::Palette => PALETTE[i % PALETTE.len()],
            Colouring::Group => PALETTE[body.group as usize % PALETTE.len()],
            Colouring::Uniform(c) => c,
        };
        let placed = PlacedSuperellipse::new(body.shape, body.pose());
        paint_shape_with(pixmap.data_mut(), &view, &placed, colour, style.antialias);
    }
    let mut pen = Pen::new(&view);
    if style.walls {
        let w = world.walls;
        let top = view.region.max.y;
        pen.polyline(
            &mut pixmap,
            &[
                Vec2::new(w.left, top),
                Vec2::new(w.left, w.floor),
                Vec2::new(w.right, w.floor),
                Vec2::new(w.right, top),
            ],
            WALL_COLOUR,
            3.0,
        );
        // Sinks: their rectangles, in a colour of their own.
        for s in &world.sinks {
            pen.stroke_box(&mut pixmap, &s.region, SINK_COLOUR, 1.5);
        }
        // Planes: the part of each line across the picture; the other boundaries' solids
        // painted as the grains are.
        let region = view.region;
        let reach = region.diagonal();
        for boundary in &world.boundaries {
            match boundary.as_plane() {
                Some(plane) => {
                    let n = plane.normal();
                    let foot = plane.project(region.center());
                    let along = Vec2::new(-n.y, n.x) * reach;
                    pen.polyline(&mut pixmap, &[foot - along, foot + along], WALL_COLOUR, 3.0);
                }
                None => paint_shape_with(
                    pixmap.data_mut(),
                    &view,
                    boundary,
                    WALL_COLOUR,
                    style.antialias,
                ),
            }
        }
    }
    if style.boxes {
        let boxes: Vec<Aabb> = world.bodies.iter().map(|b| b.bounding_box()).collect();
        for (i, bi) in boxes.iter().enumerate() {
            for bj in &boxes[i + 1..] {
                if let Some(common) = bi.intersection(bj) {
                    pen.fill_box(&mut pixmap, &common, [0xff, 0xc1, 0x07, 110]);
                }
            }
        }
        for bb in &boxes {
            pen.stroke_box(&mut pixmap, bb, [0x26, 0x32, 0x38, 200], 1.0);
        }
    }
    if style.contacts {
        draw_contacts(world, &mut pixmap, &mut pen);
    }
    if style.forces {
        draw_forces(world, &mut pixmap, &mut pen);
    }
    pixmap
}

/// The widest force-chain line, in pixels, for the largest normal force in the picture.
const FORCE_WIDTH: f32 = 7.0;

/// Force chains, as photoelastic disks show them: each contact a line from centre to centre
/// (to the wall's surface for a wall), as wide as its normal force is of the largest. From the
/// last step's forces, or, for a world read from a dump, from the impulses its contacts kept.
fn draw_forces(world: &World, pixmap: &mut Pixmap, pen: &mut Pen) {
    let colour = [0xb7, 0x1c, 0x1c, 230];
    let walls = world.all_walls();
    let mut chains: Vec<(Vec2, Vec2, f64)> = Vec::new();
    let line = |i: usize, j: usize, f: f64, chains: &mut Vec<(Vec2, Vec2, f64)>| {
        let from = world.bodies[i].center;
        let to = if j > soft::STATIC - soft::MAX_WALLS {
            match walls.get(soft::STATIC - j) {
                Some(w) => w.project(from),
                None => return,
            }
        } else {
            world.bodies[j].center
        };
        chains.push((from, to, f));
    };
    if world.soft.forces.is_empty() {
        let hs = world.settings.step / f64::from(world.settings.soft.substeps.max(1));
        for (&(i, j), k) in &world.soft.kept {
            if i < world.bodies.len()
                && (j < world.bodies.len() || j > soft::STATIC - soft::MAX_WALLS)
            {
                line(i, j, k.normal.iter().sum::<f64>() / hs, &mut chains);
            }
        }
        // The kept contacts come in no particular order: drawn in one, so pictures repeat.
        chains.sort_by(|a, b| a.2.total_cmp(&b.2));
    } else {
        for f in &world.soft.forces {
            match f.wall {
                Some(w) => line(f.b, soft::STATIC - w, f.normal_force, &mut chains),
                None => line(f.a, f.b, f.normal_force, &mut chains),
            }
        }
    }
    let largest = chains.iter().map(|c| c.2).fold(0.0, f64::max);
    if largest <= 0.0 {
        return;
    }
    for (from, to, f) in chains {
        let width = FORCE_WIDTH * (f / largest) as f32;
        if width >= 0.3 {
            pen.polyline(pixmap, &[from, to], colour, width);
        }
    }
}

/// Deepest points (dots) and penetration vectors (lines) of every grain-grain and grain-wall
/// contact, as the solver sees them.
fn draw_contacts(world: &World, pixmap: &mut Pixmap, pen: &mut Pen) {
    let vector = [0xd8, 0x1b, 0x60, 255];
    let point = [0x21, 0x21, 0x21, 255];
    world.contacts(|t| {
        let ends = match t {
            Touch::Grains(_, _, p) => {
                [Some((p.a_deepest, p.a_push)), Some((p.b_deepest, p.b_push))]
            }
            Touch::Wall(_, p) => [Some((p.deepest, p.push)), None],
        };
        for (from, push) in ends.into_iter().flatten() {
            pen.polyline(pixmap, &[from, from + push], vector, 1.5);
            pen.dot(pixmap, from, point, 2.0);
        }
    });
}

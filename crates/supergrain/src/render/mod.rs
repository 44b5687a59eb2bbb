//! Pictures: the paper's anti-aliased quadtree renderer ([`raster`]) and whole frames with
//! overlays ([`render_world`]), plus SVG diagrams of a collision test with its quadtree cells by
//! class, deepest points and penetration vectors (paper Figs. 2, 3, 6) and of a whole world.

mod contact_svg;
mod diagram;
mod frame;
mod pen;
pub mod raster;
mod world_svg;

pub use contact_svg::{answer_svg, contact_svg};
pub use diagram::{Show, cell_style, collision_png, wall_png};
pub use frame::{
    Colouring, SINK_COLOUR, Style, WALL_COLOUR, exponent_colour, render_world, world_region,
};
pub(crate) use pen::Pen;
pub use world_svg::world_svg;

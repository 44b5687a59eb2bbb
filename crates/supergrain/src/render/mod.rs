//! Pictures, as SVG for now: a collision test with its quadtree cells by class, deepest points
//! and penetration vectors (paper Figs. 2, 3, 6), and a whole world (paper Figs. 10-13).

mod contact_svg;
mod world_svg;

pub use contact_svg::contact_svg;
pub use world_svg::world_svg;

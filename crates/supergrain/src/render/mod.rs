//! Pictures. For now one diagram: a collision test drawn as SVG, with the quadtree cells by
//! class, the two shapes, the deepest points and the penetration vectors (paper Figs. 2, 3, 6).

mod contact_svg;

pub use contact_svg::contact_svg;

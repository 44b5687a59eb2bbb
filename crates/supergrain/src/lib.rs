//! supergrain: granular material made of superellipses, with collision detection certified by
//! interval arithmetic on a quadtree (Figueiredo & Celes, "Detecção de colisão para simulação
//! entre partículas representadas como superelipses").
//!
//! The library is a pipeline in layers, each knowing only those below it:
//!
//! | layer | module | paper |
//! |---|---|---|
//! | vectors, boxes | [`geometry`] | |
//! | shapes | [`shape`] | I |
//! | interval enclosures | [`interval`] | II-A |
//! | quadtree narrow phase | [`subdivision`] | II |
//! | deepest points, penetration | [`contact`] | III-A, III-B |
//! | broad phase | [`broad_phase`] | III-A |
//! | solver settings | [`settings`] | III |
//! | grains, materials, the box | [`body`] | I, III |
//! | Verlet + projection, the soft step | [`solver`] | III |
//! | world, scenes, spawning | [`world`] | III, IV |
//! | a heap's angle of repose and packing | [`measure`] | |
//! | pictures | [`render`] | II-B |
//! | JSON forms | [`io`] | |
//! | benchmark scenes | [`bench`] | IV-A |

pub mod bench;
pub mod body;
pub mod broad_phase;
pub mod contact;
pub mod geometry;
pub mod interval;
pub mod io;
pub mod measure;
pub mod render;
pub mod settings;
pub mod shape;
pub mod solver;
pub mod subdivision;
pub mod world;

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;

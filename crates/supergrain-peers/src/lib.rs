//! `supergrain bench peers`: the same scenes through supergrain, Box2D v3 (the boxdd crate, which
//! builds it from source) and rapier2d, as Box2D's benchmark app runs its own scenes.
//!
//! - [`scene`]: the neutral scene every engine is given (an open box, gravity, time step,
//!   materials, grains as circles, capsules and rounded boxes), made from supergrain's own
//!   scenes and dumps, so that the peers run the grains supergrain runs.
//! - [`peer`]: what an engine offers; [`box2d`] and [`rapier`] implement it, and
//!   [`supergrain`] runs our own `World`.
//! - [`run`]: the two measurements, a settled heap stepped awake and a pour until rest.
//! - [`bench`]: the cases of `bench peers` and their ratios to Box2D.
//! - [`repose`]: the angle of repose of poured disks against friction, in supergrain's soft step
//!   and Box2D (`--scene repose`): a measure of the physics, not of time.
//! - [`turning`]: grains in a turning container: a drum's dynamic angle (`--scene drum`) and
//!   Box2D's tumbler timed (`--scene tumbler`).
//!
//! This crate has its own workspace, so that the main workspace's tests build neither engine;
//! see `docs/peers.md`.

pub mod bench;
pub mod box2d;
pub mod overlap;
pub mod peer;
pub mod rapier;
pub mod repose;
pub mod run;
pub mod scene;
pub mod supergrain;
pub mod turning;

//! The solvers' settings: the paper's projection and the soft step alike ([`Settings`], with
//! the soft step's own in [`SoftSettings`]), their defaults and what follows from them (the
//! substeps a wanted overlap takes, the quadtree's depth for stars and walls). Below the bodies
//! and the solvers, so that the scene, the dump and the viewer read them without the solver.

use crate::contact::{Narrow, NarrowPhase};
use crate::subdivision::Precision;

/// How the angle evolves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rotation {
    /// The paper's: only projection turns a grain; it keeps no angular velocity.
    Projection,
    /// Verlet on the angle too: a grain turned by a collision keeps turning, damped.
    Inertia,
}

/// Which dynamics steps the grains.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Model {
    /// The paper's: Verlet with damping, unit masses, projection of the overlaps (this module).
    #[default]
    Paper,
    /// Rigid grains with mass, friction, restitution and rolling resistance, contacts found once
    /// per step and solved with substeps as soft constraints ([`crate::solver::soft`]).
    Soft,
}

/// Solver settings; the defaults are the paper's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Time step `h`.
    pub step: f64,
    /// Damping `delta` of the Verlet update.
    pub damping: f64,
    /// Gravity `g` (downwards).
    pub gravity: f64,
    /// Projection passes per grain per step.
    pub max_iterations: u32,
    /// Penetrations shallower than this move a grain but do not turn it (our addition, as
    /// Box2D's linear slop; 0 is the paper's projection).
    pub slop: f64,
    /// Sleeping, as in Box2D (our addition; 0 turns it off): a grain that stays within this
    /// distance of one point for [`Settings::sleep_steps`] steps in a row stops moving, until an
    /// awake grain pushes into it deeper than `slop` or a grain whose box touches its box moves
    /// more than this in one step. Projection alone leaves heaps trembling in place for ever
    /// (a contact within a final cell of touching flickers between found and not found, so a
    /// grain sinks `g h^2` and is pushed back, about every other step; with stars' spikes
    /// thinner than a cell this never stops). A sleeper holds its neighbours as a wall does,
    /// and is neither moved nor tested itself. The paper model's default is 0.002; the soft
    /// model's, [`SOFT_SLEEP_RADIUS`] (0.005): build its settings with [`Settings::soft`], not
    /// `Settings { model: Model::Soft, ..Settings::default() }`, which keeps the paper's.
    pub sleep_radius: f64,
    pub sleep_steps: u32,
    /// Sleep by islands (soft model only): touching grains fall asleep together, when all are
    /// calm, and wake together (see the soft step's `update_sleep_islands`), their forces put in
    /// equilibrium as they fall asleep. The soft model's default ([`Settings::soft`]); off, grain
    /// by grain, as the paper's model sleeps.
    pub sleep_islands: bool,
    /// End each step with a shock-propagation sweep from the floor up (our addition; the
    /// solver's `shock_grain`) instead of two closing relaxation sweeps over all grains. Off by default:
    /// the paper's small scenes rest without it; deep heaps (the 1,000-grain pour, twenty layers)
    /// only rest with it.
    pub shock_propagation: bool,
    pub precision: Precision,
    pub rotation: Rotation,
    pub narrow_phase: NarrowPhase,
    /// Which pairs are tested: a grid or all pairs (same pairs, same results; see
    /// [`crate::broad_phase`]).
    pub broad_phase: crate::broad_phase::Kind,
    /// Width of the vertical strips a wide box is cut into so that all cores project at once
    /// (see [`crate::solver::strips`]); 0, or a box narrower than [`crate::solver::strips::MIN_STRIPS`] strips, keeps the
    /// paper's order, one grain after another. Results never depend on the number of threads.
    pub strip_width: f64,
    /// Which dynamics: the paper's projection or the soft step.
    pub model: Model,
    /// The soft step's settings (unused by the paper's model).
    pub soft: SoftSettings,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            step: 0.01,
            damping: 0.1,
            gravity: 9.8,
            max_iterations: 10,
            slop: 0.005,
            sleep_radius: 0.002,
            sleep_steps: 100,
            sleep_islands: false,
            // (The soft model's default is true: [`Settings::soft`].)
            shock_propagation: false,
            precision: Precision::default(),
            rotation: Rotation::Projection,
            narrow_phase: NarrowPhase::Interval,
            broad_phase: crate::broad_phase::Kind::Grid,
            strip_width: 0.0,
            model: Model::Paper,
            soft: SoftSettings::default(),
        }
    }
}

/// The soft model's default sleep radius: its slop, 2.5 times the paper model's 0.002. A grain
/// that drifts less than the overlap every contact keeps (`slop`) in `sleep_steps` steps is at
/// rest. Measured on the mixed 1,000-grain pour with Box2D's materials (docs/physics.md, "The
/// soft model's sleep radius"): at 0.002, 115 of 996 grains slept at step 1,200 though 813 were
/// slower than the rest bar, the late steps cost as much as a heap with every grain awake, and
/// six seeds rested after 1,905-3,832 steps (5.7-10.3 s); at 0.005 after 1,540-1,746 steps
/// (3.0-3.2 s), and the scene's own seed in 2.84 s against 4.52.
pub const SOFT_SLEEP_RADIUS: f64 = 0.005;

impl Settings {
    /// The defaults with the soft model ([`Model::Soft`]), whose sleep radius is
    /// [`SOFT_SLEEP_RADIUS`].
    pub fn soft() -> Self {
        Settings {
            model: Model::Soft,
            sleep_radius: SOFT_SLEEP_RADIUS,
            // By islands since 2026-12-06 (issue 40): a heap asleep grain by grain kept forces
            // that did not balance (a median grain 4.3 weights off) and sank 2.7% of a grain's
            // size when woken; by islands, settled as they fall asleep, every grain balances
            // and a woken heap moves by 1e-4 of a size (docs/physics.md, "Heaps at rest").
            sleep_islands: true,
            ..Settings::default()
        }
    }

    /// What the solvers ask of the narrow phase: the scene's path and precision.
    pub fn narrow(&self) -> Narrow {
        Narrow {
            phase: self.narrow_phase,
            precision: self.precision,
        }
    }
}

/// The soft step's settings (Box2D v3's defaults, in its units: our grains are tenths of a
/// unit to a unit across, as Box2D's bodies are in metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoftSettings {
    /// Substeps per step.
    pub substeps: u32,
    /// The contacts' stiffness, as a frequency (Hz); at most a quarter of the substep rate is
    /// used. Against walls, twice this. 60 since 2026-12-06 (Box2D's 30 at its 60 steps a
    /// second is half its step rate; ours, at 100 steps a second, was 30 until then): with
    /// the slop gone, the bidisperse heap of docs/physics.md ("Overlap") rests with a mean
    /// overlap of 0.27% of its thinner grains' thickness (0.99% at 30 Hz), and its
    /// frictionless twin rests (at 30 Hz it crept on). A scene can ask for an overlap instead
    /// ([`SoftSettings::for_max_overlap`]).
    pub contact_hertz: f64,
    /// The contacts' damping ratio (above 1: overdamped, no bounce from the push-out).
    pub damping_ratio: f64,
    /// The fastest an overlap is pushed out (units per second).
    pub push_out: f64,
    /// Impacts slower than this (units per second) do not bounce.
    pub restitution_threshold: f64,
    /// The overlap a resting contact keeps on top of its give under load; 0 (the default, as
    /// Box2D v3's solver): contacts are solved to zero separation. Until 2026-12-06 it was
    /// 0.005, half of the mean overlap of a heap of disks 0.5-0.7 across (docs/physics.md,
    /// "Overlap"); contacts are found at the poses of free flight, `g h^2` deeper than at rest
    /// (0.001 at the default step), so a resting contact does not flicker without it.
    pub slop: f64,
    /// Air drag on the linear and angular velocities (per second); 0: none.
    pub linear_damping: f64,
    pub angular_damping: f64,
    /// How far a pair's points may move against each other (in A's frame, units) before
    /// its carried manifold is searched afresh ([`crate::solver::carry`]); 0: every pair searched
    /// every step.
    pub carry_reach: f64,
}

impl SoftSettings {
    /// The ranges a scene's `[solver]` keys are read in (substeps 1 to 64; stiffness and
    /// push-out above 0; damping ratio, restitution threshold, slop, drag and carry reach 0 or
    /// more, all finite), for settings changed elsewhere (the viewer's sliders).
    pub fn validate(&self) -> Result<(), String> {
        if !(1..=64).contains(&self.substeps) {
            return Err(format!("substeps must be 1 to 64, got {}", self.substeps));
        }
        for (name, v) in [
            ("contact_hertz", self.contact_hertz),
            ("push_out", self.push_out),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} must be a finite number above 0, got {v}"));
            }
        }
        for (name, v) in [
            ("damping_ratio", self.damping_ratio),
            ("restitution_threshold", self.restitution_threshold),
            ("slop", self.slop),
            ("linear_damping", self.linear_damping),
            ("angular_damping", self.angular_damping),
            ("carry_reach", self.carry_reach),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!(
                    "{name} must be a finite number, 0 or more, got {v}"
                ));
            }
        }
        Ok(())
    }
}

impl Default for SoftSettings {
    fn default() -> Self {
        SoftSettings {
            substeps: 4,
            contact_hertz: 60.0,
            damping_ratio: 10.0,
            push_out: 3.0,
            restitution_threshold: 1.0,
            slop: 0.0,
            linear_damping: 0.0,
            angular_damping: 0.0,
            carry_reach: 5e-4,
        }
    }
}

/// Force chains carry up to about three times a heap's mean contact force (the exponential
/// tail of the force distribution; Radjai, Jean, Moreau & Roux, PRL 77, 274, 1996), and the
/// deepest overlap of the bidisperse heap of docs/physics.md came out 2.5 times the hydrostatic
/// estimate's: [`SoftSettings::for_max_overlap`] takes the load three times that estimate.
pub const FORCE_CHAIN_FACTOR: f64 = 3.0;

/// The most substeps a step may have.
pub const MAX_SUBSTEPS: u32 = 64;

/// What the weight of a heap asks of its contacts, for [`SoftSettings::for_max_overlap`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Load {
    /// The mass of all the grains, and the width they are spread over.
    pub mass: f64,
    pub width: f64,
    /// The mass of the thinnest grain (the one of smallest thickness, twice its smallest
    /// semi-axis).
    pub thin_mass: f64,
    pub gravity: f64,
}

impl SoftSettings {
    /// The contact stiffness (and, when a quarter of the substep rate is below it, the
    /// substeps) at which the deepest contact of a heap keeps an overlap of `max_overlap` times
    /// the thinnest grain's thickness `d`, by a hydrostatic estimate: every grain's weight
    /// spread over the width, `p = M g / W`, a contact at the floor carries `p d`, and
    /// [`FORCE_CHAIN_FACTOR`] times that in a force chain; the thinnest grains' contact, of
    /// effective mass `m_d / 2`, gives way by `F / (m_d / 2 omega^2)`. So
    /// `omega^2 = 2 FORCE_CHAIN_FACTOR M g / (W m_d max_overlap)`. The substeps become at least
    /// `4 hertz h` (the stiffness used is at most a quarter of the substep rate); the contacts
    /// are still found once a step, so the narrow phase costs the same and the solve grows
    /// with the substeps. `Err` with the substeps it would take when more than
    /// [`MAX_SUBSTEPS`].
    pub fn for_max_overlap(
        self,
        max_overlap: f64,
        load: &Load,
        step: f64,
    ) -> Result<SoftSettings, String> {
        let omega2 = 2.0 * FORCE_CHAIN_FACTOR * load.mass * load.gravity
            / (load.width * load.thin_mass * max_overlap);
        let hertz = omega2.sqrt() / std::f64::consts::TAU;
        if !(hertz.is_finite() && hertz > 0.0) {
            return Err(format!(
                "max_overlap = {max_overlap:e} gives no contact stiffness (nothing to carry?)"
            ));
        }
        let needed = (4.0 * hertz * step).ceil();
        if needed > f64::from(MAX_SUBSTEPS) {
            return Err(format!(
                "max_overlap = {max_overlap:e} needs contacts of {hertz:.0} Hz, {needed} substeps \
                 at step = {step:e} (at most {MAX_SUBSTEPS}): ask for a larger overlap or a \
                 shorter step"
            ));
        }
        Ok(SoftSettings {
            contact_hertz: hertz,
            substeps: self.substeps.max(needed as u32),
            ..self
        })
    }
}

//! The solvers' settings: the paper's projection and the soft step alike ([`Settings`], with
//! the soft step's own in [`SoftSettings`]), their defaults and what follows from them (the
//! substeps a wanted overlap takes, the quadtree's depth for stars and walls). Below the bodies
//! and the solvers, so that the scene, the dump and the viewer read them without the solver.
//!
//! Every key is listed once, in [`solver_keys!`]'s table below: its name, its type, the range
//! it is read in and where it lives in [`Settings`]. From that one list come the serde form
//! that a scene's `[solver]` and a dump's `solver` are read and written in ([`SolverTable`]),
//! the one check of a whole [`Settings`] ([`Settings::validate`], also run on what the viewer's
//! sliders and `run --set` change) and `run --set KEY=VALUE` ([`Settings::set`]).

use std::fmt;
use std::marker::PhantomData;

use serde::de::{self, DeserializeSeed, MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::contact::{Narrow, NarrowPhase};
use crate::subdivision::{MAX_DEPTH, Precision};

/// How the angle evolves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Rotation {
    /// The paper's: only projection turns a grain; it keeps no angular velocity.
    Projection,
    /// Verlet on the angle too: a grain turned by a collision keeps turning, damped.
    Inertia,
}

/// Which dynamics steps the grains.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
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
    /// The paper's model: penetrations shallower than this move a grain but do not turn it
    /// (our addition, as Box2D's linear slop; 0 is the paper's projection); 0.005.
    /// The soft model: the overlap a resting contact keeps on top of its give under load; 0
    /// (its default, as Box2D v3's solver): contacts are solved to zero separation. Until
    /// 2026-12-06 it was 0.005, half of the mean overlap of a heap of disks 0.5-0.7 across
    /// (docs/physics.md, "Overlap"); contacts are found at the poses of free flight, `g h^2`
    /// deeper than at rest (0.001 at the default step), so a resting contact does not flicker
    /// without it.
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
    /// `Settings { model: Model::Soft, ..Settings::default() }`, which keeps the paper's (and
    /// the paper's slop, 0.005, where the soft model's is 0).
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
            slop: 0.0,
            ..Settings::default()
        }
    }

    /// A model's defaults: [`Settings::default`] (the paper's) or [`Settings::soft`].
    pub fn of_model(model: Model) -> Self {
        match model {
            Model::Paper => Settings::default(),
            Model::Soft => Settings::soft(),
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
    /// Air drag on the linear and angular velocities (per second); 0: none.
    pub linear_damping: f64,
    pub angular_damping: f64,
    /// How far a pair's points may move against each other (in A's frame, units) before
    /// its carried manifold is searched afresh ([`crate::solver::carry`]); 0: every pair searched
    /// every step.
    pub carry_reach: f64,
}

impl Default for SoftSettings {
    fn default() -> Self {
        SoftSettings {
            substeps: 4,
            contact_hertz: 60.0,
            damping_ratio: 10.0,
            push_out: 3.0,
            restitution_threshold: 1.0,
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

// ---- The keys ----

/// The range a key is read in.
#[derive(Clone, Copy, Debug)]
enum Rule {
    /// Any value of its type.
    Any,
    /// A finite number above 0.
    Positive,
    /// A finite number, 0 or more.
    NonNegative,
    /// A number in `[0, 1)`.
    Below1,
    /// A number in `(0, 1)`.
    Fraction,
    /// A whole number from `lo` to `hi`.
    Between(u32, u32),
}

/// A value checked against its key's [`Rule`].
trait Check {
    fn check(&self, _rule: Rule) -> Result<(), String> {
        Ok(())
    }
}

impl Check for f64 {
    fn check(&self, rule: Rule) -> Result<(), String> {
        let v = *self;
        let (ok, what) = match rule {
            Rule::Any => (true, ""),
            Rule::Positive => (v.is_finite() && v > 0.0, "a finite number above 0"),
            Rule::NonNegative => (v.is_finite() && v >= 0.0, "a finite number, 0 or more"),
            Rule::Below1 => ((0.0..1.0).contains(&v), "in [0, 1)"),
            Rule::Fraction => (v > 0.0 && v < 1.0, "in (0, 1)"),
            Rule::Between(..) => unreachable!("a whole number's rule"),
        };
        if ok {
            Ok(())
        } else {
            Err(format!("must be {what}, got {v}"))
        }
    }
}

impl Check for u32 {
    fn check(&self, rule: Rule) -> Result<(), String> {
        match rule {
            Rule::Between(lo, hi) if !(lo..=hi).contains(self) => {
                Err(format!("must be {lo} to {hi}, got {self}"))
            }
            _ => Ok(()),
        }
    }
}

impl Check for bool {}
impl Check for Model {}
impl Check for Rotation {}
impl Check for NarrowPhase {}
impl Check for crate::broad_phase::Kind {}

/// A key's value read and checked in one go, so that a scene's error points at the value.
struct Checked<T> {
    key: &'static str,
    rule: Rule,
    value: PhantomData<T>,
}

impl<'de, T: Deserialize<'de> + Check> DeserializeSeed<'de> for Checked<T> {
    type Value = T;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<T, D::Error> {
        let v = T::deserialize(d).map_err(|e| de::Error::custom(format!("{}: {e}", self.key)))?;
        v.check(self.rule)
            .map_err(|e| de::Error::custom(format!("{} {e}", self.key)))?;
        Ok(v)
    }
}

/// A key's setter: a plain field takes the value; a key with its own setter checks more.
macro_rules! set_key {
    ($settings:ident, $value:ident, |$s:ident| $get:expr) => {{
        let $s = &mut *$settings;
        $get = $value;
        Ok::<(), String>(())
    }};
    ($settings:ident, $value:ident, |$s:ident| $get:expr, |$t:ident, $v:ident| $set:expr) => {{
        let ($t, $v) = (&mut *$settings, $value);
        $set
    }};
}

/// The table of keys (see the module's head). Each row: the key, its type, its [`Rule`],
/// where its value is in a [`Settings`] `s`, and, where that is not a plain field, how it is
/// set (checking what its rule cannot).
macro_rules! solver_keys {
    ($(
        $(#[$doc:meta])*
        $key:ident: $ty:ty, $rule:expr, |$s:ident| $get:expr $(, set |$t:ident, $v:ident| $set:expr)?;
    )*) => {
        /// A scene's `[solver]` and a dump's `solver` as written: each key given or not. Read
        /// it with serde (each value checked as it is read, so that an error names the key and
        /// its place), then [`SolverTable::settings`] puts the given keys over a model's
        /// defaults. [`SolverTable::of`] writes a whole [`Settings`].
        #[derive(Clone, Debug, Default, PartialEq)]
        pub struct SolverTable {
            $( $(#[$doc])* pub $key: Option<$ty>, )*
            /// A scene's wanted overlap, a fraction of the thinnest grain's thickness in
            /// (0, 1): the scene sets `contact_hertz` and `substeps` from it
            /// ([`SoftSettings::for_max_overlap`]). Never written.
            pub max_overlap: Option<f64>,
            /// Dumps before the soft step's keys were flat kept them in their own table
            /// (with their own `slop`, over the paper's). Read, never written.
            legacy_soft: Option<LegacySoft>,
        }

        impl SolverTable {
            /// Every key's name, in the order they are written.
            pub const KEYS: &'static [&'static str] = &[$(stringify!($key),)* "max_overlap"];

            /// Every key of `settings`.
            fn every(settings: &Settings) -> SolverTable {
                SolverTable {
                    $( $key: Some({ let $s = settings; $get }), )*
                    max_overlap: None,
                    legacy_soft: None,
                }
            }

            /// The given keys over `settings` (ranges are [`Settings::validate`]'s, which every
            /// caller runs after).
            pub fn apply(&self, settings: &mut Settings) -> Result<(), String> {
                $(
                    if let Some(value) = self.$key {
                        set_key!(settings, value, |$s| $get $(, |$t, $v| $set)?)?;
                    }
                )*
                if let Some(k) = &self.legacy_soft {
                    k.apply(settings);
                }
                Ok(())
            }

            /// Whether `key` is given.
            pub fn given(&self, key: &str) -> bool {
                match key {
                    $( stringify!($key) => self.$key.is_some(), )*
                    _ => false,
                }
            }

            /// `other`'s given keys over these.
            pub fn merge(&mut self, other: &SolverTable) {
                $( if other.$key.is_some() { self.$key = other.$key; } )*
                if other.max_overlap.is_some() {
                    self.max_overlap = other.max_overlap;
                }
            }

            /// `key` not given.
            fn forget(&mut self, key: &str) {
                match key {
                    $( stringify!($key) => self.$key = None, )*
                    _ => {}
                }
            }

            fn serialize_keys<M: SerializeMap>(&self, m: &mut M) -> Result<(), M::Error> {
                $( if let Some(v) = &self.$key { m.serialize_entry(stringify!($key), v)?; } )*
                Ok(())
            }

            fn read_key<'de, A: MapAccess<'de>>(
                &mut self,
                key: &str,
                map: &mut A,
            ) -> Result<(), A::Error> {
                match key {
                    $(
                        stringify!($key) => {
                            if self.$key.is_some() {
                                return Err(de::Error::duplicate_field(stringify!($key)));
                            }
                            self.$key = Some(map.next_value_seed(Checked {
                                key: stringify!($key),
                                rule: $rule,
                                value: PhantomData,
                            })?);
                        }
                    )*
                    "max_overlap" => {
                        self.max_overlap = Some(map.next_value_seed(Checked {
                            key: "max_overlap",
                            rule: Rule::Fraction,
                            value: PhantomData,
                        })?);
                    }
                    "soft" => self.legacy_soft = Some(map.next_value()?),
                    other => return Err(de::Error::unknown_field(other, Self::KEYS)),
                }
                Ok(())
            }
        }

        impl Settings {
            /// Every key in its range, and the keys that go together: what a scene and a dump
            /// are checked against as they are read, for settings changed elsewhere (the
            /// viewer's sliders, `run --set`).
            pub fn validate(&self) -> Result<(), String> {
                $({
                    let $s = self;
                    $get.check($rule).map_err(|e| format!("{} {e}", stringify!($key)))?;
                })*
                if self.sleep_islands && self.model != Model::Soft {
                    return Err(
                        "sleep_islands needs model = \"soft\" (the paper's model sleeps grain \
                         by grain)"
                            .into(),
                    );
                }
                Ok(())
            }
        }
    };
}

solver_keys! {
    step: f64, Rule::Positive, |s| s.step;
    damping: f64, Rule::Below1, |s| s.damping;
    /// Down or none (a negative one pulled grains through the top).
    gravity: f64, Rule::NonNegative, |s| s.gravity;
    max_iterations: u32, Rule::Any, |s| s.max_iterations;
    slop: f64, Rule::NonNegative, |s| s.slop;
    sleep_radius: f64, Rule::NonNegative, |s| s.sleep_radius;
    sleep_steps: u32, Rule::Any, |s| s.sleep_steps;
    sleep_islands: bool, Rule::Any, |s| s.sleep_islands;
    shock_propagation: bool, Rule::Any, |s| s.shock_propagation;
    strip_width: f64, Rule::NonNegative, |s| s.strip_width;
    depth: u32, Rule::Between(0, MAX_DEPTH), |s| s.precision.depth(),
        set |s, v| Precision::new(v, s.precision.eps())
            .map(|p| s.precision = p)
            .map_err(|e| e.to_string());
    eps: f64, Rule::NonNegative, |s| s.precision.eps(),
        set |s, v| Precision::new(s.precision.depth(), v)
            .map(|p| s.precision = p)
            .map_err(|e| e.to_string());
    rotation: Rotation, Rule::Any, |s| s.rotation;
    narrow_phase: NarrowPhase, Rule::Any, |s| s.narrow_phase;
    broad_phase: crate::broad_phase::Kind, Rule::Any, |s| s.broad_phase;
    model: Model, Rule::Any, |s| s.model;
    substeps: u32, Rule::Between(1, MAX_SUBSTEPS), |s| s.soft.substeps;
    contact_hertz: f64, Rule::Positive, |s| s.soft.contact_hertz;
    damping_ratio: f64, Rule::NonNegative, |s| s.soft.damping_ratio;
    push_out: f64, Rule::Positive, |s| s.soft.push_out;
    restitution_threshold: f64, Rule::NonNegative, |s| s.soft.restitution_threshold;
    linear_damping: f64, Rule::NonNegative, |s| s.soft.linear_damping;
    angular_damping: f64, Rule::NonNegative, |s| s.soft.angular_damping;
    carry_reach: f64, Rule::NonNegative, |s| s.soft.carry_reach;
}

/// The keys only the soft step reads: not written for the paper's model.
pub const SOFT_KEYS: &[&str] = &[
    "sleep_islands",
    "substeps",
    "contact_hertz",
    "damping_ratio",
    "push_out",
    "restitution_threshold",
    "linear_damping",
    "angular_damping",
    "carry_reach",
];

impl SolverTable {
    /// Every key of `settings` that its model reads (the soft step's only under
    /// [`Model::Soft`]), for a dump.
    pub fn of(settings: &Settings) -> SolverTable {
        let mut t = SolverTable::every(settings);
        if settings.model != Model::Soft {
            for k in SOFT_KEYS {
                t.forget(k);
            }
        }
        t
    }

    /// The settings: the given keys over `base(model)`, the model the given one or
    /// `default_model`, then [`Settings::validate`]d. `max_overlap` is left to the scene.
    pub fn settings(
        &self,
        default_model: Model,
        base: impl Fn(Model) -> Settings,
    ) -> Result<Settings, String> {
        let model = self.model.unwrap_or(default_model);
        // The old form's soft table (a dump's) alone: beside the flat keys it would override
        // them unseen. (`sleep_islands` stood flat beside it in those dumps.)
        if self.legacy_soft.is_some()
            && let Some(key) = SOFT_KEYS
                .iter()
                .copied()
                .find(|&k| k != "sleep_islands" && self.given(k))
        {
            return Err(format!(
                "`soft` (the old form of the soft step's keys) and `{key}` are both given: \
                 give the keys flat, without `soft`"
            ));
        }
        if model == Model::Paper
            && let Some(key) = self.soft_key()
        {
            return Err(format!(
                "`{key}` is the soft model's (model = \"soft\"): the paper's projection has no \
                 such setting; remove it, or use the soft model"
            ));
        }
        let mut s = base(model);
        self.apply(&mut s)?;
        s.validate()?;
        Ok(s)
    }

    /// Whether the old form's soft table is given (dumps only: a scene refuses it).
    pub fn has_legacy_soft(&self) -> bool {
        self.legacy_soft.is_some()
    }

    /// The first key given that only the soft step reads.
    pub fn soft_key(&self) -> Option<&'static str> {
        SOFT_KEYS
            .iter()
            .copied()
            .find(|k| self.given(k))
            .or(self.legacy_soft.as_ref().map(|_| "soft"))
    }
}

impl Serialize for SolverTable {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        self.serialize_keys(&mut m)?;
        m.end()
    }
}

/// A key's name, refused as it is read when it is none of [`SolverTable::KEYS`] (so that a
/// scene's error points at the key).
struct KeyName;

impl<'de> DeserializeSeed<'de> for KeyName {
    type Value = String;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<String, D::Error> {
        let key = String::deserialize(d)?;
        if SolverTable::KEYS.contains(&key.as_str()) || key == "soft" {
            Ok(key)
        } else {
            Err(de::Error::unknown_field(&key, SolverTable::KEYS))
        }
    }
}

impl<'de> Deserialize<'de> for SolverTable {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = SolverTable;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "a table of solver settings")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<SolverTable, A::Error> {
                let mut t = SolverTable::default();
                while let Some(key) = map.next_key_seed(KeyName)? {
                    t.read_key(&key, &mut map)?;
                }
                Ok(t)
            }
        }
        d.deserialize_map(V)
    }
}

impl SolverTable {
    /// One key from its value as TOML writes it (`contact_hertz`, `30`; `narrow_phase`,
    /// `"quadtree"`, or the bare word), checked, for `run --set KEY=VALUE`. `model` and `max_overlap` are the
    /// scene's alone: a run's grains are built for its model, and an overlap's stiffness
    /// follows from the scene's grains.
    pub fn one(key: &str, value: &str) -> Result<SolverTable, String> {
        match key {
            "model" => {
                return Err(
                    "model is the scene's, not a run's (its grains are built for it): \
                            set it in the scene's [solver]"
                        .into(),
                );
            }
            "max_overlap" => {
                return Err(
                    "max_overlap is the scene's (its stiffness follows from the \
                            scene's grains): set it in [solver], or contact_hertz and substeps \
                            here"
                        .into(),
                );
            }
            _ if !SolverTable::KEYS.contains(&key) => {
                return Err(format!(
                    "no solver key `{key}`: the keys are {}",
                    SolverTable::KEYS.join(", ")
                ));
            }
            _ => {}
        }
        let read = |value: &str| {
            toml::from_str::<SolverTable>(&format!("{key} = {value}"))
                .map_err(|e| format!("`{key} = {value}`: {}", e.message()))
        };
        // A shell drops the quotes of `--set narrow_phase="quadtree"`: a bare word is read as
        // the string it names (and refused as one, where the key takes a number).
        let bare = value
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic())
            && value
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
        let literal = ["true", "false", "nan", "inf"].contains(&value);
        let t = if bare && !literal {
            read(&format!("{value:?}"))?
        } else {
            read(value)?
        };
        // One key: a value with a line break in it must not set a second one (`model`).
        let mut rest = t.clone();
        rest.forget(key);
        if rest != SolverTable::default() {
            return Err(format!(
                "`{key} = {value}` sets more than `{key}`: one key per setting"
            ));
        }
        Ok(t)
    }
}

impl Settings {
    /// One key set as [`SolverTable::one`] reads it, checked with the rest
    /// ([`Settings::validate`]); unchanged on an error.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), String> {
        let mut s = *self;
        SolverTable::one(key, value)?.apply(&mut s)?;
        s.validate()?;
        *self = s;
        Ok(())
    }
}

/// The soft step's keys as dumps before the flat keys wrote them (`"soft": {...}`).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct LegacySoft {
    substeps: u32,
    contact_hertz: f64,
    damping_ratio: f64,
    push_out: f64,
    restitution_threshold: f64,
    slop: f64,
    linear_damping: f64,
    angular_damping: f64,
    /// Absent (a dump written before contacts were carried): 0, none carried, as that code
    /// ran.
    #[serde(default)]
    carry_reach: f64,
}

impl LegacySoft {
    fn apply(&self, s: &mut Settings) {
        s.slop = self.slop;
        s.soft.substeps = self.substeps;
        s.soft.contact_hertz = self.contact_hertz;
        s.soft.damping_ratio = self.damping_ratio;
        s.soft.push_out = self.push_out;
        s.soft.restitution_threshold = self.restitution_threshold;
        s.soft.linear_damping = self.linear_damping;
        s.soft.angular_damping = self.angular_damping;
        s.soft.carry_reach = self.carry_reach;
    }
}

//! What makes a scene or a dump workable, checked once before any work: shapes that exist,
//! grains that fit between the walls and appear above the floor, a box that can hold them all, a
//! time step at which a falling grain cannot jump through another, a state inside the box.
//! The scene ([`super::Scene::validate`]) and the dump ([`crate::io::Dump::to_world`]) share
//! these, so both refuse the same things with the same words.

use super::Range;
use crate::geometry::Aabb;
use crate::shape::{ShapeError, Superellipse};
use crate::solver::{Settings, Walls};

/// The most a falling grain may move in one step, as a fraction of the smallest semi-axis of
/// the scene: two such grains closing on each other then move together by at most one smallest
/// semi-axis per step, half the thickness of the thinnest grain, so the projection always sees
/// them overlap before they pass through each other (or a grain through the floor).
pub const STEP_FRACTION: f64 = 0.5;

/// The part of the box up to the spawn height grains can cover: about the densest packing of
/// equal disks (pi / sqrt(12) = 0.9069). A heap that needs more reaches the spawn height, where
/// the grains still due wait for ever for a free place.
pub const PACKING: f64 = 0.9;

/// How deep a grain of a dump may be in a wall or in another grain, as a fraction of its
/// smallest semi-axis (of the smaller one for a pair). A run keeps penetrations near the solver's
/// `slop` (0.005); a grain deeper than half its own thickness was put there by hand, and the
/// projection would fling it out.
pub const DEPTH_FRACTION: f64 = 0.5;

/// How far a grain of a soft-model dump may reach beyond a wall, as a fraction of its bounding
/// radius: beyond that, its whole diameter, it was put there by hand (a struck grain's
/// transient overlaps with the floor stay within its thickness; see `io::dump`).
pub const SOFT_OUTSIDE_FRACTION: f64 = 2.0;

/// How far an awake grain of the soft model may reach beyond a wall before it has left the
/// box: [`SOFT_OUTSIDE_FRACTION`] of its bounding radius (a dump's limit, and a run's).
pub fn soft_outside_limit(shape: &Superellipse) -> f64 {
    SOFT_OUTSIDE_FRACTION * shape.bounding_radius()
}

/// The largest `step` count a dump may hold: past 2^53 steps are no longer exact as `f64` times
/// (and `u64::MAX` wraps at the next step).
pub const MAX_STEP: u64 = 1 << 53;

/// An upper bound on how far a grain falling from rest `height` above the floor moves in one
/// step, for the damped Verlet update `d' = (1 - delta) d + g h^2` (SPEC §5): its displacement
/// per step grows towards the terminal `g h^2 / delta`, and cannot exceed what an undamped fall
/// from `height` reaches, `h sqrt(2 g height)` (plus one kick `g h^2` for the discrete steps).
pub fn fall_per_step(settings: &Settings, height: f64) -> f64 {
    let (g, h, delta) = (settings.gravity, settings.step, settings.damping);
    let kick = g * h * h;
    let terminal = if delta > 0.0 {
        kick / delta
    } else {
        f64::INFINITY
    };
    let fall = h * (2.0 * g * height.max(0.0)).sqrt() + kick;
    terminal.min(fall)
}

/// The largest time step at which [`fall_per_step`] stays within `limit`: the larger of the
/// steps solving `g h^2 / delta = limit` and `g h^2 + h sqrt(2 g height) = limit` (the bound is
/// the smaller of the two, each increasing in `h`).
fn largest_step(settings: &Settings, height: f64, limit: f64) -> f64 {
    let (g, delta) = (settings.gravity, settings.damping);
    if g <= 0.0 {
        return f64::INFINITY;
    }
    let terminal = if delta > 0.0 {
        (limit * delta / g).sqrt()
    } else {
        0.0
    };
    let b = (2.0 * g * height.max(0.0)).sqrt();
    let fall = (-b + (b * b + 4.0 * g * limit).sqrt()) / (2.0 * g);
    terminal.max(fall)
}

/// Refuses a time step (with its gravity and damping) at which a grain falling from `height`
/// moves more than [`STEP_FRACTION`] of `smallest` (the smallest semi-axis) in one step.
pub fn check_time_step(settings: &Settings, height: f64, smallest: f64) -> Result<(), String> {
    let moved = fall_per_step(settings, height);
    let limit = STEP_FRACTION * smallest;
    if moved.is_finite() && moved <= limit {
        return Ok(());
    }
    Err(format!(
        "solver: step = {} with gravity = {} and damping = {} lets a falling grain move {moved:.3e} \
         in one step, more than {STEP_FRACTION} x the smallest semi-axis ({smallest}) = {limit:.3e}, \
         so grains would pass through each other and the floor; use step <= {:.3e}",
        settings.step,
        settings.gravity,
        settings.damping,
        largest_step(settings, height, limit),
    ))
}

/// Refuses a box whose width or height up to `top` overflows (the spawn draws x between the
/// walls, and cannot draw from an infinite range).
pub fn check_box(walls: &Walls, top: f64) -> Result<(), String> {
    let (width, height) = (walls.right - walls.left, top - walls.floor);
    if width.is_finite() && height.is_finite() && width > 0.0 && height > 0.0 {
        return Ok(());
    }
    Err(format!(
        "box: its width ({}) and its height up to top ({}) must be finite numbers > 0",
        short(width),
        short(height)
    ))
}

/// Refuses sleeping after 0 calm steps (grains would freeze where they appear).
pub fn check_sleep(settings: &Settings) -> Result<(), String> {
    if settings.sleep_radius > 0.0 && settings.sleep_steps == 0 {
        return Err(
            "solver: sleep_steps must be at least 1 (0 freezes grains where they appear); \
             turn sleeping off with sleep_radius = 0"
                .into(),
        );
    }
    Ok(())
}

/// Refuses a grain (of bounding radius `radius`, named by `what`) that cannot turn between the
/// walls, or that would appear with its lowest point below the floor when its centre is at `top`.
pub fn check_fits(walls: &Walls, top: f64, radius: f64, what: &str) -> Result<(), String> {
    let width = walls.right - walls.left;
    let fits = 2.0 * radius < width;
    if !fits {
        return Err(format!(
            "{what}: a grain of bounding radius {} cannot fit between the walls \
             (the box is {} wide, the grain up to {} across)",
            short(radius),
            short(width),
            short(2.0 * radius)
        ));
    }
    let above = top - radius > walls.floor;
    if !above {
        return Err(format!(
            "{what}: a grain of bounding radius {} appearing at top = {} would reach into \
             the floor at {}; raise top above {}",
            short(radius),
            short(top),
            short(walls.floor),
            short(walls.floor + radius)
        ));
    }
    Ok(())
}

/// A number for a message: 4 significant digits, in exponent form when very large or small.
pub fn short(x: f64) -> String {
    if x != 0.0 && !(1e-3..1e6).contains(&x.abs()) {
        format!("{x:.3e}")
    } else {
        let s = format!("{x:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// Refuses a range (of the field `what`) that cannot be drawn from uniformly: an end not
/// finite, `lo > hi`, or ends so far apart that the width overflows (the draw would fail).
pub fn check_range(r: Range, what: &str) -> Result<(), String> {
    let (lo, hi) = (r.lo, r.hi);
    // Exact, in exponent form when large (1e308 has 309 digits).
    let exact = |x: f64| {
        if x.abs() >= 1e6 && x.is_finite() {
            format!("{x:e}")
        } else {
            format!("{x}")
        }
    };
    let range = format!("[{}, {}]", exact(lo), exact(hi));
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(format!("{what}: the range {range} needs finite ends"));
    }
    if lo > hi {
        return Err(format!("{what}: the range {range} is empty: lo > hi"));
    }
    if !(hi - lo).is_finite() {
        return Err(format!(
            "{what}: the range {range} is too wide to draw from (hi - lo overflows)"
        ));
    }
    Ok(())
}

/// Refuses more grain area than the box can hold up to `top` (at [`PACKING`]); `area` is the
/// least total area of the grains.
pub fn check_capacity(walls: &Walls, top: f64, count: u64, area: f64) -> Result<(), String> {
    let room = (walls.right - walls.left) * (top - walls.floor);
    if area <= PACKING * room {
        return Ok(());
    }
    let each = area / count.max(1) as f64;
    Err(format!(
        "the box cannot hold {count} grains: they cover at least {area:.4e} \
         ({each:.4e} each), more than {PACKING} of the box's area up to top ({room:.4e}); \
         it holds about {:.0} such grains",
        (PACKING * room / each).floor()
    ))
}

/// How deep a grain's box is beyond a wall or below the floor (0 inside).
pub fn depth_outside(walls: &Walls, b: &Aabb) -> f64 {
    let d = (walls.left - b.min.x)
        .max(b.max.x - walls.right)
        .max(walls.floor - b.min.y)
        .max(0.0);
    if d.is_nan() { f64::INFINITY } else { d }
}

/// Names the scene field a [`ShapeError`] is about.
pub fn shape_field(error: &ShapeError, circles: bool, same_exponents: bool) -> &'static str {
    let name = match error {
        ShapeError::NotPositive { name, .. }
        | ShapeError::NotFinite { name, .. }
        | ShapeError::OutOfRange { name, .. } => *name,
        ShapeError::BadDirection { name, .. } => name,
    };
    let exponent = name.contains("exponent");
    match (exponent, circles, same_exponents) {
        (true, _, true) => "exponent",
        (true, _, false) => "exponents",
        (false, true, _) => "radius",
        (false, false, _) => "semi_axes",
    }
}

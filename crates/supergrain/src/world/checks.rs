//! What makes a scene or a dump workable, checked once before any work: shapes that exist,
//! grains that fit between the walls and appear above the floor, a box that can hold them all, a
//! time step at which a falling grain cannot jump through another, a state inside the box.
//! The scene ([`super::Scene::validate`]) and the dump ([`crate::io::Dump::to_world`]) share
//! these, so both refuse the same things with the same words.

use super::Range;
use super::spawn::{BAND_IN_RADII, SpawnRule};
use crate::body::{Body, Material, Walls};
use crate::contact::Penetration;
use crate::geometry::{Aabb, Vec2};
use crate::settings::{Model, Settings};
use crate::shape::{Boundary, ShapeError, Superellipse};

/// The most a falling grain may move in one step, as a fraction of the smallest semi-axis of
/// the scene: two such grains closing on each other then move together by at most one smallest
/// semi-axis per step, half the thickness of the thinnest grain, so the projection always sees
/// them overlap before they pass through each other (or a grain through the floor).
pub const STEP_FRACTION: f64 = 0.5;

/// [`STEP_FRACTION`] under the soft model, whose grains fall freely (no Verlet damping slows
/// them). Its step finds a contact where the grains will be at the step's end, so a grain
/// falling onto a resting one is caught as long as it has not passed the pair's middle, its
/// two half-thicknesses, at least twice the smallest semi-axis. Measured with 60 needles
/// (smallest semi-axes 0.025-0.03) poured from 6 high: at the default step (4.3 x) two pairs
/// had crossed by step 300, each grain's centre inside the other; at 1.96 x and 0.98 x none in
/// 15 checkpoints. The 1,000-grain pour (`pour-1000.toml`) falls 1.66 x its rice's.
pub const SOFT_STEP_FRACTION: f64 = 2.0;

/// The part of the box up to the spawn height grains can cover: about the densest packing of
/// equal disks (pi / sqrt(12) = 0.9069). A heap that needs more reaches the spawn height, where
/// the grains still due wait for ever for a free place.
pub const PACKING: f64 = 0.9;

/// How deep a grain of a dump may be in a wall or in another grain, as a fraction of its
/// smallest semi-axis (of the smaller one for a pair). A run keeps penetrations near the solver's
/// `slop` (0.005); a grain deeper than half its own thickness was put there by hand, and the
/// projection would fling it out.
pub const DEPTH_FRACTION: f64 = 0.5;

/// How deep two overlapping grains `a` and `b` are in each other, to within `tol` from above:
/// the deeper of their deepest points' depths in the other grain, each its distance to the
/// other's boundary ([`Superellipse::depth_of`]), and never more than its penetration vector.
///
/// The vectors themselves are no depths: `A1 -> B2` follows the gradient of B at `A1` to where
/// it leaves B, and for a star that can be across a spike. In a 60-star heap at rest a vector of
/// 0.146 (more than half the thinner star's semi-axis, so the dump was refused) measured a pair
/// 0.012 deep by this measure (0.005-0.012 by the issue's).
pub fn overlap_depth(a: &Body, b: &Body, p: &Penetration, tol: f64) -> f64 {
    let a_in_b = p
        .a_push
        .norm()
        .min(b.shape.depth_of(&b.pose(), p.a_deepest, tol));
    let b_in_a = p
        .b_push
        .norm()
        .min(a.shape.depth_of(&a.pose(), p.b_deepest, tol));
    a_in_b.max(b_in_a)
}

/// How finely [`overlap_depth`] measures a pair's depth for the dump's check, as a fraction of
/// the thinner grain's smallest semi-axis: a fiftieth of [`DEPTH_FRACTION`]'s limit.
pub const DEPTH_TOLERANCE: f64 = 0.01;

/// How far a grain of a soft-model dump may reach beyond a wall, as a fraction of its bounding
/// radius: beyond that, its whole diameter, it was put there by hand (a struck grain's
/// transient overlaps with the floor stay within its thickness; see `io::dump`).
pub const SOFT_OUTSIDE_FRACTION: f64 = 2.0;

/// How far an awake grain of the soft model may reach beyond a wall before it has left the
/// box: [`SOFT_OUTSIDE_FRACTION`] of its bounding radius (a dump's limit, and a run's).
pub fn soft_outside_limit(shape: &Superellipse) -> f64 {
    SOFT_OUTSIDE_FRACTION * shape.bounding_radius()
}

/// The `step` count a dump must stay below: past 2^53 steps are no longer exact as `f64` times
/// (and `u64::MAX` wraps at the next step), and a run goes on at least one step from its dump.
pub const MAX_STEP: u64 = 1 << 53;

/// An upper bound on how far a grain falling from rest `height` above the floor moves in one
/// step, for the damped Verlet update `d' = (1 - delta) d + g h^2` (SPEC §5): its displacement
/// per step grows towards the terminal `g h^2 / delta`, and cannot exceed what an undamped fall
/// from `height` reaches, `h sqrt(2 g height)` (plus one kick `g h^2` for the discrete steps).
/// The soft model has no such damping (`damping` is the paper's; its air drag,
/// `linear_damping`, is off by default): its grains fall freely, and only the undamped bound
/// holds (with the paper's `damping = 0.99`, `step = 0.07` was accepted and a falling plate went
/// through resting disks and the floor).
pub fn fall_per_step(settings: &Settings, height: f64) -> f64 {
    let (g, h, delta) = (settings.gravity, settings.step, damping(settings));
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
    let (g, delta) = (settings.gravity, damping(settings));
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

/// The Verlet damping a fall is slowed by: the paper's `damping`, none under the soft model.
fn damping(settings: &Settings) -> f64 {
    match settings.model {
        Model::Paper => settings.damping,
        Model::Soft => 0.0,
    }
}

/// Refuses a time step (with its gravity and, under the paper's model, damping) at which a
/// grain falling from `height` moves more than [`STEP_FRACTION`] of `smallest` (the smallest
/// semi-axis) in one step, [`SOFT_STEP_FRACTION`] under the soft model.
pub fn check_time_step(settings: &Settings, height: f64, smallest: f64) -> Result<(), String> {
    let moved = fall_per_step(settings, height);
    let fraction = match settings.model {
        Model::Paper => STEP_FRACTION,
        Model::Soft => SOFT_STEP_FRACTION,
    };
    let limit = fraction * smallest;
    if moved.is_finite() && moved <= limit {
        return Ok(());
    }
    let slowed = match settings.model {
        Model::Paper => format!(" and damping = {}", settings.damping),
        // Named, since a scene may set it: the soft step ignores it.
        Model::Soft => " (model = \"soft\": a free fall, `damping` is the paper's)".into(),
    };
    Err(format!(
        "solver: step = {} with gravity = {}{slowed} lets a falling grain from the top move \
         {moved:.3e} in one step, more than {fraction} x the smallest semi-axis \
         ({smallest}) = {limit:.3e}, so grains would pass through each other and the floor; \
         use step <= {:.3e}",
        settings.step,
        settings.gravity,
        largest_step(settings, height, limit),
    ))
}

/// Refuses a grain's given `speed` at which it would move more than the time step's share of
/// its smallest semi-axis `smallest` in one step ([`STEP_FRACTION`], [`SOFT_STEP_FRACTION`]
/// under the soft model): it would pass through what it meets.
pub fn check_speed(settings: &Settings, speed: f64, smallest: f64) -> Result<(), String> {
    let fraction = match settings.model {
        Model::Paper => STEP_FRACTION,
        Model::Soft => SOFT_STEP_FRACTION,
    };
    let (moved, limit) = (speed * settings.step, fraction * smallest);
    if moved <= limit {
        return Ok(());
    }
    Err(format!(
        "its velocity moves it {} in one step of {}, more than {fraction} x its smallest \
         semi-axis ({}): slower, or a shorter step (at most {})",
        short(moved),
        short(settings.step),
        short(smallest),
        short(limit / speed)
    ))
}

/// The most the quadtree's tolerance `eps` may be, as a fraction of the smallest semi-axis: an
/// overlap is missed up to four final cells deep (the quadtree's spikes, `contact/spikes.rs`;
/// half a cell by the certified path), at most [`DEPTH_FRACTION`] of the thinnest grain.
pub const EPS_FRACTION: f64 = 0.125;

/// Refuses a quadtree tolerance `eps` coarser than [`EPS_FRACTION`] of `smallest` (the smallest
/// semi-axis): with `eps = 1e308` every pair's region was one cell, overlaps went unseen and
/// grains fell through each other.
pub fn check_eps(settings: &Settings, smallest: f64) -> Result<(), String> {
    let eps = settings.precision.eps();
    let limit = EPS_FRACTION * smallest;
    if eps <= limit {
        return Ok(());
    }
    Err(format!(
        "solver: eps = {} is coarser than {EPS_FRACTION} x the smallest semi-axis ({}): overlaps \
         up to four final cells deep would go unseen and grains pass through each other; use \
         eps <= {} (0: the depth alone sets the final cell)",
        short(eps),
        short(smallest),
        short(limit)
    ))
}

/// Refuses a sleep radius that is not a finite number >= 0, or wider than `smallest` (the
/// smallest semi-axis): a grain that moves less than its own thickness in `sleep_steps` steps
/// may be at rest, one that moves more is not (with `sleep_radius = 1e308` grains slept in the
/// air). Sleeping after 0 calm steps is refused too (grains would freeze where they appear).
pub fn check_sleep(settings: &Settings, smallest: f64) -> Result<(), String> {
    let r = settings.sleep_radius;
    if !(r.is_finite() && r >= 0.0) {
        return Err(format!(
            "solver: sleep_radius must be a finite number >= 0, got {}",
            short(r)
        ));
    }
    if r > smallest {
        return Err(format!(
            "solver: sleep_radius = {} is wider than the smallest semi-axis of the grains ({}): \
             a grain moving by its own thickness is not at rest, and would be put to sleep (in \
             the air); use sleep_radius <= {}, or 0 to turn sleeping off",
            short(r),
            short(smallest),
            short(smallest)
        ));
    }
    if r > 0.0 && settings.sleep_steps == 0 {
        return Err(
            "solver: sleep_steps must be at least 1 (0 freezes grains where they appear); \
             turn sleeping off with sleep_radius = 0"
                .into(),
        );
    }
    Ok(())
}

/// The deepest overlap a `slop` may ask contacts to keep, as a fraction of the smallest
/// semi-axis: half a thin grain's half-thickness.
pub const SLOP_FRACTION: f64 = 0.5;

/// Refuses a `slop` (the paper model's, or the soft model's) deeper than [`SLOP_FRACTION`] of
/// `smallest` (the smallest semi-axis): with `slop = 1` a heap's contacts were held a unit deep
/// in each other and grains sank through the floor (issue 40).
pub fn check_slop(settings: &Settings, smallest: f64) -> Result<(), String> {
    let limit = SLOP_FRACTION * smallest;
    // (Finite and 0 or more: `Settings::validate`.)
    let slop = settings.slop;
    if slop > limit {
        return Err(format!(
            "solver: slop = {} is deeper than {SLOP_FRACTION} x the smallest semi-axis of \
             the grains ({}): contacts would hold grains that deep in each other and in the \
             walls; use slop <= {} (the soft model's default is 0)",
            short(slop),
            short(smallest),
            short(limit)
        ));
    }
    Ok(())
}

/// The masses and moments of inertia the soft step works with: a product or quotient of up to
/// three of them stays a finite, normal number (`1e100^3` is far below `f64::MAX`).
pub const MASS_RANGE: std::ops::RangeInclusive<f64> = 1e-100..=1e100;

/// Refuses a material whose density gives `shape` a mass or moment of inertia outside
/// [`MASS_RANGE`]: with density 1e308 the mass overflowed, with 1e-306 the moment of inertia
/// was subnormal, and the soft step divided by it into infinities and NaN.
pub fn check_mass(material: &Material, shape: &Superellipse) -> Result<(), String> {
    let (mass, inertia) = material.mass_and_inertia(shape);
    let ok = |x: f64| MASS_RANGE.contains(&x);
    if ok(mass) && ok(inertia) {
        return Ok(());
    }
    let s = shape.semi_axes();
    let [ex, ey] = shape.exponents();
    Err(format!(
        "density = {} gives a grain of semi-axes [{}, {}] and exponents [{}, {}] a mass of {} \
         and a moment of inertia of {}: both must be between {:e} and {:e}",
        short(material.density),
        short(s.x),
        short(s.y),
        short(ex),
        short(ey),
        short(mass),
        short(inertia),
        MASS_RANGE.start(),
        MASS_RANGE.end()
    ))
}

/// Refuses a boundary (named `name`) that leaves grains no place to appear. By the queue's rule
/// grains appear on the line `y = top` between the walls and wait until their place is free:
/// a boundary must keep its solid at least `largest` (the largest bounding radius) from that
/// line, or grains may wait inside it for ever. By the fair rule a place inside a boundary is
/// taken and another is offered in the band under the top: the boundary must leave a place
/// free for the smallest grain, whose band is the shallowest ([`BAND_IN_RADII`] of `smallest`,
/// its bounding radius). A grain is surely in the boundary when its centre is nearer than
/// `thinnest` (the smallest semi-axis) over `sqrt(2)`: every grain reaches that far in every
/// direction (it holds the diamond of its spikes' tips). The boundary's distance is bounded
/// over the line or band by its enclosure, exact for planes and segments.
pub fn check_boundary(
    boundary: &Boundary,
    name: &str,
    walls: &Walls,
    top: f64,
    rule: SpawnRule,
    [smallest, largest]: [f64; 2],
    thinnest: f64,
) -> Result<(), String> {
    let (left, right) = (walls.left, walls.right);
    let over = |low: f64| boundary.enclose(&Aabb::new(Vec2::new(left, low), Vec2::new(right, top)));
    match rule {
        SpawnRule::Queue => {
            if over(top).0 < largest {
                return Err(format!(
                    "{name} reaches within a grain's bounding radius ({}) of the line y = {} \
                     between the walls, where grains appear by [spawn] rule = \"queue\": they \
                     would appear inside it; keep it lower, or use rule = \"fair\"",
                    short(largest),
                    short(top)
                ));
            }
        }
        SpawnRule::Fair => {
            let low = (top - BAND_IN_RADII * smallest).max(walls.floor);
            if over(low).1 < thinnest * std::f64::consts::FRAC_1_SQRT_2 {
                return Err(format!(
                    "{name} covers every place where grains appear (the band from y = {} to \
                     top = {} between the walls): no grain would ever appear; keep it lower",
                    short(low),
                    short(top)
                ));
            }
        }
    }
    Ok(())
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

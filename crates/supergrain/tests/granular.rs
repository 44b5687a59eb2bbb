//! Issue 18's granular bars for the soft step: the angle of repose of poured disks rises with
//! their friction and lies where published heaps of disks with rolling resistance lie, and a
//! frictionless bidisperse heap packs near random close packing. The measures
//! (`supergrain::measure`) are checked here against closed forms first.

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use supergrain::body::Material;
use supergrain::geometry::{Aabb, Vec2};
use supergrain::measure::repose::{self, Pour};
use supergrain::measure::{Disk, packing};
use supergrain::world::{Rest, RestCounter, World};

fn window(x0: f64, y0: f64, x1: f64, y1: f64) -> Aabb {
    Aabb::new(Vec2::new(x0, y0), Vec2::new(x1, y1))
}

/// A disk's area inside a window: whole, halved and quartered by the window's sides, a strip
/// through it (closed form: `2 (r^2 asin(h/r) + h sqrt(r^2 - h^2))` for `|y| < h`), none; and
/// for windows at random, against counting the points of a fine grid (a million points).
#[test]
fn a_disk_is_clipped_to_a_window_exactly() {
    let d = Disk::new(1.0, 2.0, 0.5);
    let full = PI * 0.25;
    let cases = [
        (window(0.0, 0.0, 3.0, 3.0), full),
        (window(1.0, 0.0, 3.0, 3.0), full / 2.0),
        (window(0.0, 2.0, 3.0, 3.0), full / 2.0),
        (window(1.0, 2.0, 3.0, 3.0), full / 4.0),
        (window(-1.0, 1.8, 3.0, 2.2), {
            let (r, h): (f64, f64) = (0.5, 0.2);
            2.0 * (r * r * (h / r).asin() + h * (r * r - h * h).sqrt())
        }),
        (window(1.6, 0.0, 3.0, 3.0), 0.0),
    ];
    for (w, want) in cases {
        let got = packing::area_in(&d, &w);
        assert!((got - want).abs() < 1e-12, "{w:?}: {got}, want {want}");
    }
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..20 {
        let (x0, y0) = (rng.random_range(0.3..1.4), rng.random_range(1.3..2.4));
        let w = window(
            x0,
            y0,
            x0 + rng.random_range(0.05..1.0),
            y0 + rng.random_range(0.05..1.0),
        );
        let n = 1000;
        let cell = 1.2 / n as f64;
        let mut count = 0u32;
        for i in 0..n {
            for j in 0..n {
                let p = Vec2::new(0.4 + (i as f64 + 0.5) * cell, 1.4 + (j as f64 + 0.5) * cell);
                if w.contains(p) && (p - d.center).norm() <= d.radius {
                    count += 1;
                }
            }
        }
        let sampled = f64::from(count) * cell * cell;
        let got = packing::area_in(&d, &w);
        // The grid moves each side of the window by up to half a cell: at most the window's
        // half perimeter (under 2) times a cell.
        let tolerance = 2.0 * cell;
        assert!(
            (got - sampled).abs() < tolerance,
            "{w:?}: {got}, sampled {sampled}"
        );
    }
}

/// The angle of a heap poured with friction `mu` (rolling resistance 0.1), the mean over two
/// seeds: 300 disks (a heap about 12 diameters high), the pour and the measure of
/// `measure::repose`.
fn repose_angle(mu: f64) -> f64 {
    let grain = Material {
        friction: mu,
        rolling_resistance: 0.1,
        restitution: 0.0,
        density: 1.0,
    };
    let angles: Vec<f64> = [1, 2]
        .into_iter()
        .map(|seed| {
            let pour = Pour {
                grains: 300,
                seed,
                ..Pour::default()
            };
            let mut world = repose::world(&pour, grain);
            let Ok(poured) = repose::pour(&mut world, &pour);
            assert!(poured.at_rest, "mu = {mu}, seed {seed}: not at rest");
            let a = pour
                .angle(&poured.disks)
                .unwrap_or_else(|| panic!("mu = {mu}, seed {seed}: no flank to fit"));
            a.degrees()
        })
        .collect();
    angles.iter().sum::<f64>() / angles.len() as f64
}

/// The angle of repose rises with friction: disks with rolling resistance 0.1 poured onto a
/// rough floor, `mu = 0.1` against `mu = 0.5`.
///
/// The range: DEM heaps of disks or spheres with rolling resistance and the usual frictions
/// (0.3-0.8) stand at about 15-35 degrees, and the angle rises with both the sliding and the
/// rolling friction and levels off at high sliding friction (Zhou, Xu, Yu & Zulli, "Numerical
/// investigation of the angle of repose of monosized spheres", Phys. Rev. E 64, 021301, 2001;
/// the range itself is issue 18's). At `mu = 0.1` the heap is far lower (a lone disk slides on
/// a slope steeper than `atan 0.1`, 5.7 degrees): we ask only that it stands at all, below
/// 15. Measured here (seeds 1 and 2) with the soft model's sleep radius 0.005: 9.0 and 25.9
/// degrees (7.6 and 31.2 with the paper's 0.002, before 2026-12-04; then seeds 1-4 gave
/// 7.3-10.7 and 21.7-34.8 one by one). With 600 disks and three seeds (`bench peers --scene
/// repose`, docs/physics.md) ours gives 8.8 and 30.6, Box2D v3 on the same pours 12.0 and 34.6.
/// At this size the seeds of 0.3 and 0.5, and of 0.5 and 0.8, overlap, so only 0.1 and 0.5 are
/// asserted.
///
/// 2026-12-06 (issue 40: no slop, 60 Hz, sleeping by islands) the heaps stand lower: 9.1 and
/// 16.4 degrees. Each change lowers the angle at `mu = 0.5`: 25.9 before, 22.7 without the slop,
/// 20.5 at 60 Hz, 16.4 by islands (a flank grain asleep on its own held up those above it as a
/// wall does; by islands the flank creeps on until the whole heap is calm; Box2D's looser sleep,
/// 0.05 units/s for half a second, gives 13.1 here). The margin is 5 degrees, not 8; the gap to
/// Box2D's 34.6 is open (docs/physics.md, "Overlap").
///
/// Can fail: with `mu = 0.5` on both sides the two angles are the same, and the margin of 5
/// degrees fails (checked when this was written).
#[test]
fn the_angle_of_repose_rises_with_friction() {
    let low = repose_angle(0.1);
    let high = repose_angle(0.5);
    eprintln!("angle of repose: {low:.1} degrees at mu = 0.1, {high:.1} at mu = 0.5");
    assert!(
        high > low + 5.0,
        "mu = 0.5 stands at {high:.1} degrees, mu = 0.1 at {low:.1}"
    );
    assert!(
        (15.0..=35.0).contains(&high),
        "mu = 0.5: {high:.1} degrees, outside 15-35"
    );
    assert!(
        (3.0..15.0).contains(&low),
        "mu = 0.1: {low:.1} degrees, not a heap or steeper than mu = 0.5 should be"
    );
}

/// The bidisperse pour of issue 40: 500 disks of radius 0.25 and 500 of 0.35 (ratio 1.4, which
/// keeps them from crystallising) poured one a step into a box 20 wide, `[solver]` lines added
/// to the scene, run until every grain has appeared and none has been faster than 0.05 for 100
/// steps (the CLI's `--until-rest`). Returns the settled disks and the step it rested at.
fn bidisperse_pour(friction: f64, solver: &str) -> (Vec<Disk>, u64) {
    let text = format!(
        "seed = 1\n[box]\nleft = -10.0\nright = 10.0\nfloor = 0.0\ntop = 26.0\n\
         friction = {friction}\n[spawn]\ninterval = 1\n[solver]\n{solver}\n\
         [[group]]\ncount = 500\nradius = 0.25\nfriction = {friction}\n\
         [[group]]\ncount = 500\nradius = 0.35\nfriction = {friction}\n"
    );
    let scene = supergrain::world::Scene::from_toml(&text).expect("a valid scene");
    let mut w = World::new(&scene);
    let mut calm = RestCounter::default();
    while !calm.at_rest(&Rest::default()) {
        assert!(
            w.step < 6000,
            "friction {friction}, {solver:?}: not at rest by step 6000"
        );
        w.step();
        calm.after_step(&Rest::default(), &w);
    }
    let disks = w
        .bodies
        .iter()
        .map(|b| Disk {
            center: b.center,
            radius: b.shape.semi_axes().x,
        })
        .collect();
    (disks, w.step)
}

/// The mean overlap of touching disks (exact disk geometry, no solver code), the packing
/// fraction of the bulk (three mean diameters from the walls, the floor and the surface) as the
/// areas are, and as disks shrunk by half the mean overlap, which touch.
fn overlap_and_packing(disks: &[Disk]) -> (f64, f64, f64) {
    let overlaps = packing::overlaps(disks);
    let mean = overlaps.iter().sum::<f64>() / overlaps.len() as f64;
    let window = packing::bulk_window(disks, -10.0, 10.0, 0.0, 1.8).expect("a window");
    assert!(
        window.width() > 14.0 && window.height() > 10.0,
        "the window is {window:?}"
    );
    let raw = packing::area_fraction(disks, &window);
    let hard: Vec<Disk> = disks
        .iter()
        .map(|d| Disk {
            radius: d.radius - 0.5 * mean,
            ..*d
        })
        .collect();
    (mean, raw, packing::area_fraction(&hard, &window))
}

/// A frictionless bidisperse heap comes to rest and packs near random close packing, as the
/// areas are. The published 2D random close packing of such mixtures is 0.84 (O'Hern, Silbert,
/// Liu & Nagel, "Jamming at zero temperature and zero applied stress", Phys. Rev. E 68,
/// 011306, 2003: 0.842 for 50:50 disks of ratio 1.4); issue 40 asks 0.84 +- 0.02.
///
/// Until 2026-12-06 this heap never rested (fastest grain 0.063 after 3,000 steps) and packed
/// at 0.874-0.881 as the areas are: its contacts kept the slop, 0.005, on top of their give at
/// 30 Hz, a mean overlap of 0.0097, and each contact was found only once it overlapped, so
/// the stiffer contacts were not allowed: two disks that met within a step were pushed apart
/// from an overlap no constraint had held, which pumped energy in (at 100 Hz the frictionless
/// heap kept a kinetic energy of 10-20 for good). With the slop gone, speculative contacts for
/// disks and 60 Hz, it rests at step 1,448, 0.851 (0.846 as disks that touch).
///
/// Can fail (checked when this was written): with the slop back at 0.005, or without the
/// speculative contacts, it is not at rest by step 6,000.
#[test]
fn a_frictionless_bidisperse_pour_rests_and_packs_near_random_close_packing() {
    let (disks, rested) = bidisperse_pour(0.0, "");
    let (mean, raw, touching) = overlap_and_packing(&disks);
    eprintln!(
        "at rest at step {rested}: area fraction {raw:.4} as the grains are, {touching:.4} as \
         disks that touch (mean overlap {mean:.5})"
    );
    assert!(
        (0.82..=0.86).contains(&raw),
        "area fraction {raw:.4} (as disks that touch: {touching:.4}; mean overlap {mean:.5})"
    );
}

/// Overlap the user controls (issue 40): the frictional (0.6) bidisperse heap at rest, with
/// `max_overlap = 0.01`, has a mean overlap under 0.2% of the mean diameter (0.6), its packing
/// fraction as the areas are within 0.005 of the one as disks that touch, and its deepest
/// overlap under 1% of the thinner grain's thickness; with the defaults the mean stays under 1%.
/// Measured when this was written (sleeping by islands): 0.12% of the mean diameter (the
/// deepest 0.0040, 0.81% of a small disk), fractions 0.8309 and 0.8289; the defaults 0.32%.
/// Until 2026-12-06: 1.69%, 0.859 and 0.831.
#[test]
fn a_heap_keeps_the_overlap_its_scene_asks_for() {
    let (disks, _) = bidisperse_pour(0.6, "max_overlap = 0.01");
    let (mean, raw, touching) = overlap_and_packing(&disks);
    let deepest = packing::overlaps(&disks).into_iter().fold(0.0, f64::max);
    eprintln!(
        "max_overlap = 0.01: mean overlap {mean:.5}, deepest {deepest:.5}; area fraction \
         {raw:.4}, {touching:.4} as disks that touch"
    );
    assert!(mean < 0.002 * 0.6, "mean overlap {mean}");
    assert!(deepest < 0.01 * 0.5, "deepest overlap {deepest}");
    assert!((raw - touching).abs() < 0.005, "{raw} against {touching}");
    let (disks, _) = bidisperse_pour(0.6, "");
    let (mean, _, _) = overlap_and_packing(&disks);
    eprintln!("the defaults: mean overlap {mean:.5}");
    assert!(mean < 0.01 * 0.6, "the defaults: mean overlap {mean}");
}

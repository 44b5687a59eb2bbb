//! Issue 18's granular bars for the soft step: the angle of repose of poured disks rises with
//! their friction and lies where published heaps of disks with rolling resistance lie, and a
//! frictionless bidisperse heap packs near random close packing. The measures
//! (`supergrain::measure`) are checked here against closed forms first.

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use supergrain::geometry::{Aabb, Vec2};
use supergrain::measure::repose::{self, Pour};
use supergrain::measure::{Disk, packing};
use supergrain::shape::{Pose, Superellipse};
use supergrain::solver::soft::Material;
use supergrain::solver::{Body, Settings, Walls};
use supergrain::world::{Queue, World};

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
/// Can fail: with `mu = 0.5` on both sides the two angles are the same, and the margin of 8
/// degrees fails (checked when this was written).
#[test]
fn the_angle_of_repose_rises_with_friction() {
    let low = repose_angle(0.1);
    let high = repose_angle(0.5);
    eprintln!("angle of repose: {low:.1} degrees at mu = 0.1, {high:.1} at mu = 0.5");
    assert!(
        high > low + 8.0,
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

/// A frictionless bidisperse heap packs near random close packing: 400 disks, half of radius
/// 0.25 and half 0.35 (ratio 1.4, which keeps them from crystallising), released at rest from
/// random places that overlap nothing in a box 12 wide, settled under gravity for 10 s (the
/// fraction is steady from 5 s on) with the soft step's defaults, no friction, rolling
/// resistance or restitution. The window keeps three mean diameters (1.8) from the walls, the
/// floor and the surface (the lowest of the tops in each tenth of the box); the grains' areas
/// are clipped to it exactly.
///
/// The published 2D random close packing of such mixtures is 0.84 (O'Hern, Silbert, Liu &
/// Nagel, "Jamming at zero temperature and zero applied stress", Phys. Rev. E 68, 011306, 2003:
/// 0.842 for 50:50 disks of ratio 1.4). **The raw fraction lands above [0.82, 0.86]**: 0.874
/// (seeds 2 and 3: 0.878, 0.880). The reason is the soft contacts' overlap: the sum of areas
/// counts every grain whole, and touching grains here overlap by 0.0097 on average (the slop,
/// 0.005, plus the 30 Hz contact's give under the weight above: 0.03-0.04 at the bottom), so
/// the grains are packed as disks about half an overlap smaller would be. With those disks
/// (each radius less half the mean overlap) the fraction is 0.847 (0.851, 0.853), which is
/// what this test asserts, with the overlap itself. With contacts at 100 Hz (the stiffest four
/// substeps allow) the mean overlap falls to the slop (0.0054) and the raw fraction to
/// 0.857-0.860, the overlap-corrected one to 0.842-0.845: the correction, not the stiffness,
/// is what brings it to 0.84.
///
/// Can fail (checked when this was written): with friction 0.5 the heap jams looser, 0.812 as
/// disks that touch; with one radius (0.3) it crystallises denser, 0.874.
#[test]
fn a_frictionless_bidisperse_heap_packs_near_random_close_packing() {
    let half = 6.0;
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut disks: Vec<Disk> = Vec::new();
    // Spread over a column about three times the heap's height.
    let height = 400.0 * 0.29 / (2.0 * half) / 0.35;
    while disks.len() < 400 {
        let r = if disks.len().is_multiple_of(2) {
            0.25
        } else {
            0.35
        };
        let d = Disk::new(
            rng.random_range(-half + r..half - r),
            rng.random_range(r..height),
            r,
        );
        if disks
            .iter()
            .all(|o| (o.center - d.center).norm() > o.radius + d.radius)
        {
            disks.push(d);
        }
    }
    let bodies = disks
        .iter()
        .map(|d| {
            let shape = Superellipse::circle(d.radius).unwrap();
            Body::at_rest(shape, &Pose::new(d.center, 0.0).unwrap())
        })
        .collect();
    let settings = Settings::soft();
    let walls = Walls {
        left: -half,
        right: half,
        floor: 0.0,
    };
    let mut w = World::from_parts(bodies, walls, settings, 0, 0.0, Queue::default());
    let frictionless = Material {
        friction: 0.0,
        restitution: 0.0,
        rolling_resistance: 0.0,
        density: 1.0,
    };
    w.materials = vec![frictionless];
    w.wall_material = frictionless;
    for _ in 0..1000 {
        w.step();
    }
    let settled: Vec<Disk> = w
        .bodies
        .iter()
        .map(|b| Disk {
            center: b.center,
            radius: b.shape.semi_axes().x,
        })
        .collect();
    let window = packing::bulk_window(&settled, -half, half, 0.0, 1.8).expect("a window");
    assert!(
        window.width() > 8.0 && window.height() > 6.0,
        "the window is {window:?}"
    );
    let raw = packing::area_fraction(&settled, &window);
    let overlaps = packing::overlaps(&settled);
    let mean = overlaps.iter().sum::<f64>() / overlaps.len() as f64;
    let slop = w.settings.soft.slop;
    assert!(
        (slop..3.0 * slop).contains(&mean),
        "touching grains overlap by {mean} on average"
    );
    let hard: Vec<Disk> = settled
        .iter()
        .map(|d| Disk {
            radius: d.radius - 0.5 * mean,
            ..*d
        })
        .collect();
    let fraction = packing::area_fraction(&hard, &window);
    eprintln!("area fraction {raw:.4} as the grains overlap, {fraction:.4} as disks that touch");
    assert!(
        (0.82..=0.86).contains(&fraction),
        "area fraction {fraction:.4} (as the grains overlap: {raw:.4}; mean overlap {mean:.4})"
    );
}

//! The region measures (issue 41) against closed forms: a packing's area fraction of tiled
//! grains of every class (disks, blocks, stars) in a window that cuts through them; a column's
//! mean contact number; a velocity profile of a sheared layer.

use std::f64::consts::PI;

use supergrain::body::{Body, Material, Walls};
use supergrain::geometry::{Aabb, Vec2};
use supergrain::measure::packing::shape_area_in;
use supergrain::measure::series::{packing_in, profile_in};
use supergrain::settings::Settings;
use supergrain::shape::{Pose, Superellipse};
use supergrain::world::{Queue, World};

/// The area of `shape` inside windows that cut it, against a dense grid count written here.
#[test]
fn a_grains_area_in_a_window_matches_a_dense_count() {
    let shapes = [
        Superellipse::circle(0.5).unwrap(),
        Superellipse::new([0.6, 0.3], [2.0, 2.0]).unwrap(),
        Superellipse::new([0.5, 0.5], [16.0, 16.0]).unwrap(),
        Superellipse::new([0.6, 0.4], [0.5, 0.5]).unwrap(),
        Superellipse::new([0.5, 0.2], [4.0, 1.0]).unwrap(),
    ];
    let pose = Pose::new(Vec2::new(0.1, -0.2), 0.7).unwrap();
    let windows = [
        Aabb::new(Vec2::new(-0.1, -2.0), Vec2::new(2.0, 2.0)),
        Aabb::new(Vec2::new(-1.0, -0.5), Vec2::new(0.3, 0.0)),
        Aabb::new(Vec2::new(-2.0, -2.0), Vec2::new(2.0, 2.0)),
    ];
    let n = 1500;
    for s in &shapes {
        for w in &windows {
            // Cell midpoints inside both, counted: the grid's error is about the boundary's
            // length times a cell.
            let (lo, hi) = (Vec2::new(-1.0, -1.2), Vec2::new(1.2, 0.8));
            let (dx, dy) = ((hi.x - lo.x) / n as f64, (hi.y - lo.y) / n as f64);
            let mut count = 0usize;
            for i in 0..n {
                for j in 0..n {
                    let p = Vec2::new(lo.x + (i as f64 + 0.5) * dx, lo.y + (j as f64 + 0.5) * dy);
                    if w.contains(p) && s.value(&pose, p) < 0.0 {
                        count += 1;
                    }
                }
            }
            let grid = count as f64 * dx * dy;
            let ours = shape_area_in(s, &pose, w);
            assert!(
                (ours - grid).abs() <= 0.01 * s.area() + 4e-3,
                "{s:?} in {w:?}: {ours}, counted {grid}"
            );
        }
    }
}

fn world(bodies: Vec<Body>) -> World {
    let mut w = World::from_parts(
        bodies,
        Walls {
            left: -10.0,
            right: 10.0,
            floor: 0.0,
        },
        Settings::soft(),
        0,
        20.0,
        Queue::default(),
    );
    w.materials = vec![Material::default()];
    w
}

#[test]
fn a_square_lattice_of_disks_packs_at_pi_over_four() {
    // Disks of radius 0.5 at the integers: any window of whole cells holds pi / 4, cut
    // through the disks' middles.
    let disk = Superellipse::circle(0.5).unwrap();
    let bodies = (-5..5)
        .flat_map(|i| (1..10).map(move |j| (i, j)))
        .map(|(i, j)| {
            Body::at_rest(
                disk,
                &Pose::new(Vec2::new(f64::from(i), f64::from(j)), 0.0).unwrap(),
            )
        })
        .collect();
    let w = world(bodies);
    let window = Aabb::new(Vec2::new(-3.0, 2.0), Vec2::new(2.0, 6.0));
    let p = packing_in(&w, &window);
    assert!(
        (p.area_fraction - PI / 4.0).abs() < 1e-12,
        "{}",
        p.area_fraction
    );
    // Centres strictly inside a window from -3 to 2 and 2 to 6: x -3..2 (6), y 2..6 (5).
    assert_eq!(p.grains, 30);
}

#[test]
fn a_column_of_three_disks_has_five_thirds_contacts_each() {
    // Three disks stacked on the floor: 1 + 2 + 2 contacts (the top one, the middle one above
    // and below, the bottom one above and on the floor).
    let disk = Superellipse::circle(0.5).unwrap();
    let bodies = (0..3)
        .map(|k| {
            Body::at_rest(
                disk,
                &Pose::new(Vec2::new(0.0, 0.5 + f64::from(k)), 0.0).unwrap(),
            )
        })
        .collect();
    let mut w = world(bodies);
    for _ in 0..120 {
        w.step();
    }
    let p = packing_in(&w, &Aabb::new(Vec2::new(-1.0, 0.0), Vec2::new(1.0, 4.0)));
    assert_eq!(p.grains, 3);
    assert!(
        (p.contact_number - 5.0 / 3.0).abs() < 1e-12,
        "{}",
        p.contact_number
    );
}

#[test]
fn a_profile_reads_each_slices_mean_velocity() {
    // Disks in flight, a linear shear: vx = y, each slice's mean the slice's centres' mean.
    let disk = Superellipse::circle(0.1).unwrap();
    let bodies = (0..40)
        .map(|k| {
            let y = 1.0 + 0.1 * f64::from(k);
            Body {
                velocity: Vec2::new(y, 0.0),
                ..Body::at_rest(disk, &Pose::new(Vec2::new(0.0, y), 0.0).unwrap())
            }
        })
        .collect();
    let w = world(bodies);
    let slices = profile_in(&w, &Aabb::new(Vec2::new(-1.0, 1.0), Vec2::new(1.0, 5.0)), 4);
    assert_eq!(slices.len(), 4);
    for s in &slices {
        assert_eq!(s.grains, 10);
        // Centres 1.0, 1.1, ..., 1.9 in the first slice: mean 1.45.
        assert!((s.v.x - (s.y - 0.05)).abs() < 1e-9, "{s:?}");
    }
}

/// An empty region packs at 0, written "0" in the CSV (a sum of nothing is -0 in Rust).
#[test]
fn an_empty_region_packs_at_zero_not_minus_zero() {
    let w = world(Vec::new());
    let p = packing_in(&w, &Aabb::new(Vec2::new(-1.0, 0.0), Vec2::new(1.0, 1.0)));
    assert_eq!(p.grains, 0);
    assert_eq!(p.area_fraction.to_string(), "0");
}

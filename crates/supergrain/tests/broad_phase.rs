//! The grid broad phase against the reference: brute force over every pair, and whole runs.

use proptest::prelude::*;
use supergrain::broad_phase::{AllPairs, BroadPhase, Grid, Kind};
use supergrain::geometry::{Aabb, Vec2};
use supergrain::io::Dump;
use supergrain::world::{Scene, World};

/// Every `j != i` whose box overlaps `boxes[i]`, in increasing order, by brute force.
fn brute(i: usize, boxes: &[Aabb]) -> Vec<usize> {
    (0..boxes.len())
        .filter(|&j| {
            j != i
                && boxes[i].min.x <= boxes[j].max.x
                && boxes[j].min.x <= boxes[i].max.x
                && boxes[i].min.y <= boxes[j].max.y
                && boxes[j].min.y <= boxes[i].max.y
        })
        .collect()
}

fn boxes_of(raw: &[(f64, f64, f64, f64)]) -> Vec<Aabb> {
    raw.iter()
        .map(|&(x, y, w, h)| Aabb::new(Vec2::new(x, y), Vec2::new(x + w, y + h)))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Boxes of mixed sizes, some far apart, then moved one by one (small moves, and jumps
    /// across the grid and beyond its edges) as the solver moves grains within a step: after
    /// every move, every body's candidates are exactly the brute-force list.
    #[test]
    fn grid_candidates_are_the_overlapping_boxes(
        raw in prop::collection::vec((-20.0f64..20.0, -5.0f64..30.0, 0.01f64..1.5, 0.01f64..1.5), 1..60),
        moves in prop::collection::vec((0usize..60, -3.0f64..3.0, -3.0f64..3.0, prop::bool::ANY), 0..40),
    ) {
        let mut boxes = boxes_of(&raw);
        let mut grid = Grid::new();
        grid.rebuild(&boxes);
        let mut out = Vec::new();
        let check = |grid: &Grid, boxes: &[Aabb], out: &mut Vec<usize>| {
            for i in 0..boxes.len() {
                out.clear();
                grid.candidates(i, boxes, out);
                assert_eq!(*out, brute(i, boxes), "body {i}");
                out.clear();
                grid.later_candidates(i, boxes, out);
                let later: Vec<usize> = brute(i, boxes).into_iter().filter(|&j| j > i).collect();
                assert_eq!(*out, later, "body {i}, later ones");
            }
        };
        check(&grid, &boxes, &mut out);
        for (k, dx, dy, far) in moves {
            let i = k % boxes.len();
            let d = if far { Vec2::new(dx * 20.0, dy * 20.0) } else { Vec2::new(dx * 0.05, dy * 0.05) };
            boxes[i] = Aabb::new(boxes[i].min + d, boxes[i].max + d);
            grid.update(i, &boxes[i]);
            check(&grid, &boxes, &mut out);
        }
    }
}

/// The candidates are appended: what `out` held before is kept.
#[test]
fn candidates_append() {
    let boxes = boxes_of(&[(0.0, 0.0, 1.0, 1.0), (0.5, 0.5, 1.0, 1.0)]);
    let mut grid = Grid::new();
    grid.rebuild(&boxes);
    let mut out = vec![7];
    grid.candidates(0, &boxes, &mut out);
    assert_eq!(out, vec![7, 1]);
    for broad in [&grid as &dyn BroadPhase, &AllPairs] {
        let mut out = vec![7];
        broad.later_candidates(1, &boxes, &mut out);
        assert_eq!(out, vec![7], "nothing after the last body");
        broad.later_candidates(0, &boxes, &mut out);
        assert_eq!(out, vec![7, 1]);
    }
}

fn particles(world: &World) -> String {
    serde_json::to_string(&Dump::of(world).particles).unwrap()
}

/// The grid and all pairs give the same run bit for bit (the mixed preset, stars included,
/// grains falling and landing; and the deep pour's shock sweep).
#[test]
fn grid_and_all_pairs_give_identical_runs() {
    for (name, steps, shock) in [("mixed", 900, false), ("ellipses", 900, true)] {
        let mut scene = Scene::preset(name).unwrap();
        scene.spawn_interval = 5;
        scene.settings.shock_propagation = shock;
        let run = |kind| {
            let mut s = scene.clone();
            s.settings.broad_phase = kind;
            let mut world = World::new(&s);
            for _ in 0..steps {
                world.step();
            }
            world
        };
        let (grid, all) = (run(Kind::Grid), run(Kind::AllPairs));
        assert!(
            grid.bodies.len() >= 30,
            "{name}: {} grains",
            grid.bodies.len()
        );
        assert_eq!(particles(&grid), particles(&all), "{name}");
    }
}

/// `broad_phase` in a scene file, and a bad value named with its line.
#[test]
fn scene_files_choose_the_broad_phase() {
    let text = |v: &str| {
        format!(
            "[box]\nleft = -1.0\nright = 1.0\nfloor = 0.0\ntop = 3.0\n[solver]\nbroad_phase = \"{v}\"\n[[group]]\ncount = 1\nradius = 0.2\n"
        )
    };
    let all = Scene::from_toml(&text("all-pairs")).unwrap();
    assert_eq!(all.settings.broad_phase, Kind::AllPairs);
    let grid = Scene::from_toml(&text("grid")).unwrap();
    assert_eq!(grid.settings.broad_phase, Kind::Grid);
    let err = Scene::from_toml(&text("octree")).unwrap_err().to_string();
    assert!(err.contains("line 7") && err.contains("octree"), "{err}");
}

/// The scaling benchmark's scenes: `tiled(heap, k)` is `k` copies of the heap side by side, in a
/// box `k` times as wide, all awake with sleeping off; a step of it finds the same pairs per
/// copy (so the tests per step grow `k` times, give or take the grains at the seams).
#[test]
fn tiled_heaps_are_side_by_side_copies() {
    let mut scene = Scene::preset("circles").unwrap();
    scene.spawn_interval = 2;
    let mut heap = World::new(&scene);
    for _ in 0..400 {
        heap.step();
    }
    let width = heap.walls.right - heap.walls.left;
    let three = supergrain::bench::tiled(&heap, 3, Kind::Grid);
    assert_eq!(three.bodies.len(), 3 * heap.bodies.len());
    assert_eq!(three.walls.right, heap.walls.left + 3.0 * width);
    assert_eq!(three.settings.sleep_radius, 0.0);
    for (k, b) in three.bodies.iter().enumerate() {
        let original = &heap.bodies[k % heap.bodies.len()];
        let copy = (k / heap.bodies.len()) as f64;
        assert_eq!(b.center.x, original.center.x + copy * width);
        assert_eq!(b.center.y, original.center.y);
        assert!(!b.asleep(&three.settings));
    }
    let (mut one, mut three) = (supergrain::bench::tiled(&heap, 1, Kind::Grid), three);
    let (a, b) = (one.step().tests, three.step().tests);
    assert!(
        (2.5 * a as f64..=3.5 * a as f64).contains(&(b as f64)),
        "{a} tests for one copy, {b} for three"
    );
}

//! Benchmark scenes: near-touching random pairs of the paper's shape classes for the narrow
//! phase (paper IV), shared by the criterion benches and `supergrain bench contact`, and the
//! paper's four scenes for the whole simulation (`supergrain bench presets`).

use std::hint::black_box;
use std::time::Instant;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::contact::{Contact, contact, contact_quadtree, disk_disk};
use crate::geometry::Vec2;
use crate::shape::{Pose, Superellipse};
use crate::subdivision::Precision;

/// The shape classes of the paper's scenes (Figs. 10-13).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeClass {
    /// Radius in [0.3, 0.7].
    Circles,
    /// Semi-axes in [0.1, 0.8] and [0.1, 0.9].
    Ellipses,
    /// Exponents 4, semi-axes in [0.3, 0.4] and [0.3, 0.7].
    Squircles,
    /// Exponents each in [0.5, 4], semi-axes as squircles.
    Mixed,
    /// Stars: exponents each in [0.25, 0.9], semi-axes as squircles.
    Stars,
}

impl ShapeClass {
    pub const ALL: [ShapeClass; 5] = [
        ShapeClass::Circles,
        ShapeClass::Ellipses,
        ShapeClass::Squircles,
        ShapeClass::Mixed,
        ShapeClass::Stars,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ShapeClass::Circles => "circles",
            ShapeClass::Ellipses => "ellipses",
            ShapeClass::Squircles => "squircles",
            ShapeClass::Mixed => "mixed",
            ShapeClass::Stars => "stars",
        }
    }

    /// A random shape of this class.
    pub fn sample(self, rng: &mut impl Rng) -> Superellipse {
        let (axes, exps) = match self {
            ShapeClass::Circles => {
                let r = rng.random_range(0.3..=0.7);
                ([r, r], [2.0, 2.0])
            }
            ShapeClass::Ellipses => (
                [rng.random_range(0.1..=0.8), rng.random_range(0.1..=0.9)],
                [2.0, 2.0],
            ),
            ShapeClass::Squircles => (
                [rng.random_range(0.3..=0.4), rng.random_range(0.3..=0.7)],
                [4.0, 4.0],
            ),
            ShapeClass::Mixed => (
                [rng.random_range(0.3..=0.4), rng.random_range(0.3..=0.7)],
                [rng.random_range(0.5..=4.0), rng.random_range(0.5..=4.0)],
            ),
            ShapeClass::Stars => (
                [rng.random_range(0.3..=0.4), rng.random_range(0.3..=0.7)],
                [rng.random_range(0.25..=0.9), rng.random_range(0.25..=0.9)],
            ),
        };
        Superellipse::new(axes, exps).expect("class ranges are valid")
    }
}

/// Two placed shapes.
#[derive(Clone, Copy, Debug)]
pub struct Pair {
    pub a: Superellipse,
    pub pose_a: Pose,
    pub b: Superellipse,
    pub pose_b: Pose,
}

/// `n` pairs of the class, B's centre along a random direction from A's at the touching
/// distance times `1 +- spread` (uniform), random angles. Deterministic in `seed`.
///
/// The touching distance is found by bisection on an overlap test of densely sampled
/// boundaries, not by the quadtree, so the benchmark does not tune itself to the code it times.
pub fn near_touching_pairs(class: ShapeClass, n: usize, spread: f64, seed: u64) -> Vec<Pair> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let a = class.sample(&mut rng);
            let b = class.sample(&mut rng);
            let pose_a = Pose::new(Vec2::ZERO, rng.random_range(0.0..std::f64::consts::TAU))
                .expect("finite");
            let angle_b = rng.random_range(0.0..std::f64::consts::TAU);
            let dir_angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let dir = Vec2::new(dir_angle.cos(), dir_angle.sin());
            let touching = touching_distance(&a, &pose_a, &b, angle_b, dir);
            let t = touching * (1.0 + rng.random_range(-spread..=spread));
            let pose_b = Pose::new(dir * t, angle_b).expect("finite");
            Pair {
                a,
                pose_a,
                b,
                pose_b,
            }
        })
        .collect()
}

fn sampled_overlap(a: &Superellipse, pa: &Pose, b: &Superellipse, pb: &Pose) -> bool {
    const N: usize = 512;
    let inside = |s: &Superellipse, ps: &Pose, o: &Superellipse, po: &Pose| {
        (0..N).any(|i| {
            let t = i as f64 * std::f64::consts::TAU / N as f64;
            o.value(po, ps.to_world(s.boundary_point(t))) < 0.0
        })
    };
    inside(a, pa, b, pb) || inside(b, pb, a, pa)
}

/// The largest centre distance along `dir` at which the sampled boundaries still overlap.
fn touching_distance(
    a: &Superellipse,
    pa: &Pose,
    b: &Superellipse,
    angle_b: f64,
    dir: Vec2,
) -> f64 {
    let (mut lo, mut hi) = (0.0, a.bounding_radius() + b.bounding_radius());
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        let pb = Pose::new(dir * mid, angle_b).expect("finite");
        if sampled_overlap(a, pa, b, &pb) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// One measured case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseResult {
    pub name: String,
    /// Median over the repetitions of the time per pair.
    pub ns_per_pair: f64,
    pub pairs: usize,
    /// Fraction of pairs found overlapping.
    pub overlap_fraction: f64,
    /// Mean quadtree cells per pair.
    pub cells_per_pair: f64,
}

/// Median over `reps` timed passes of `f` over all items, in ns per item; one untimed pass first.
pub fn median_ns_per_item<T>(items: &[T], reps: usize, mut f: impl FnMut(&T)) -> f64 {
    for it in items {
        f(it);
    }
    let mut times: Vec<f64> = (0..reps.max(1))
        .map(|_| {
            let start = Instant::now();
            for it in items {
                f(it);
            }
            start.elapsed().as_nanos() as f64 / items.len().max(1) as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// The narrow-phase benchmark: every shape class at the given precision, by the certified
/// path (Newton for convex pairs, the boundary search for the others, the quadtree as the
/// fallback of both) and by the quadtree alone, then the disk-disk floor
/// on the circle pairs, all in one run.
pub fn contact_cases(
    pairs: usize,
    reps: usize,
    precision: &Precision,
    seed: u64,
) -> Vec<CaseResult> {
    let mut out = Vec::new();
    let mut circle_pairs = Vec::new();
    for class in ShapeClass::ALL {
        let set = near_touching_pairs(class, pairs, 0.02, seed);
        type Method = fn(&Superellipse, &Pose, &Superellipse, &Pose, &Precision) -> Contact;
        let methods: [(String, Method); 2] = [
            ("certified".to_string(), contact),
            (
                format!("quadtree depth {}", precision.depth()),
                contact_quadtree,
            ),
        ];
        for (method, run) in methods {
            let (mut overlaps, mut cells) = (0usize, 0u64);
            for p in &set {
                let c = run(&p.a, &p.pose_a, &p.b, &p.pose_b, precision);
                overlaps += usize::from(c.overlap());
                cells += u64::from(c.cells);
            }
            let ns = median_ns_per_item(&set, reps, |p| {
                black_box(run(
                    black_box(&p.a),
                    black_box(&p.pose_a),
                    black_box(&p.b),
                    black_box(&p.pose_b),
                    precision,
                ));
            });
            out.push(CaseResult {
                name: format!("{} ({method})", class.name()),
                ns_per_pair: ns,
                pairs: set.len(),
                overlap_fraction: overlaps as f64 / set.len().max(1) as f64,
                cells_per_pair: cells as f64 / set.len().max(1) as f64,
            });
        }
        if class == ShapeClass::Circles {
            circle_pairs = set;
        }
    }
    let disks: Vec<(Vec2, f64, Vec2, f64)> = circle_pairs
        .iter()
        .map(|p| {
            (
                p.pose_a.center(),
                p.a.semi_axes().x,
                p.pose_b.center(),
                p.b.semi_axes().x,
            )
        })
        .collect();
    let overlaps = disks
        .iter()
        .filter(|d| disk_disk(d.0, d.1, d.2, d.3).is_some())
        .count();
    let ns = median_ns_per_item(&disks, reps, |d| {
        black_box(disk_disk(black_box(d.0), d.1, black_box(d.2), d.3));
    });
    out.push(CaseResult {
        name: "circles (centre distance, floor)".into(),
        ns_per_pair: ns,
        pairs: disks.len(),
        overlap_fraction: overlaps as f64 / disks.len().max(1) as f64,
        cells_per_pair: 0.0,
    });
    out
}

/// One preset run.
#[derive(Clone, Debug, PartialEq)]
pub struct PresetResult {
    pub name: String,
    pub steps: u64,
    pub grains: usize,
    pub seconds: f64,
    pub steps_per_second: f64,
    pub contacts_per_step: f64,
}

/// The paper's four scenes through the interval narrow phase, then the circles through the
/// centre-distance test (the paper's comparison, IV-A), `steps` steps each; `runs` rounds of all
/// five in turn (side by side, so that a busy spell of the machine touches every scene alike),
/// and for each scene its fastest run. Runs are identical bit for bit, so only the time varies.
/// `seed`: instead of each preset's own.
pub fn preset_cases(steps: u64, runs: usize, seed: Option<u64>) -> Vec<PresetResult> {
    use crate::contact::NarrowPhase;
    use crate::world::{Scene, World};
    let mut scenes: Vec<(String, Scene)> = crate::world::PRESETS
        .iter()
        .map(|name| (name.to_string(), Scene::preset(name).expect("a preset")))
        .collect();
    let mut analytic = Scene::preset("circles").expect("a preset");
    analytic.settings.narrow_phase = NarrowPhase::Analytic;
    scenes.push(("circles (analytic, floor)".into(), analytic));
    if let Some(seed) = seed {
        for (_, scene) in &mut scenes {
            scene.seed = seed;
        }
    }
    let mut best: Vec<Option<PresetResult>> = vec![None; scenes.len()];
    for _ in 0..runs.max(1) {
        for ((name, scene), best) in scenes.iter().zip(&mut best) {
            let mut world = World::new(scene);
            let start = Instant::now();
            let contacts: usize = (0..steps).map(|_| world.step().contacts).sum();
            let seconds = start.elapsed().as_secs_f64();
            if best.as_ref().is_none_or(|b| seconds < b.seconds) {
                *best = Some(PresetResult {
                    name: name.clone(),
                    steps,
                    grains: world.bodies.len(),
                    seconds,
                    steps_per_second: steps as f64 / seconds.max(1e-9),
                    contacts_per_step: contacts as f64 / steps.max(1) as f64,
                });
            }
        }
    }
    best.into_iter().flatten().collect()
}

/// A scene's grains laid out without simulating: in rows from the floor up, left to right, each
/// grain in a cell as wide as the largest box, at its drawn angle (a frame to draw, for the
/// renderer's benchmark).
pub fn laid_out(scene: &crate::world::Scene) -> crate::world::World {
    use crate::body::Body;
    let world = crate::world::World::new(scene);
    let w = scene.walls;
    let cell = world
        .pending
        .iter()
        .map(|p| p.shape.bounding_radius())
        .fold(0.0, f64::max)
        * 2.0;
    let per_row = (((w.right - w.left) / cell).floor() as usize).max(1);
    let bodies = world
        .pending
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let (col, row) = ((k % per_row) as f64, (k / per_row) as f64);
            let c = Vec2::new(w.left + (col + 0.5) * cell, w.floor + (row + 0.5) * cell);
            Body::at_rest(p.shape, &Pose::from_parts(c, p.angle))
        })
        .collect();
    crate::world::World::from_parts(bodies, w, scene.settings, 0, scene.top, Default::default())
}

/// One way of drawing a frame, measured.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderResult {
    pub name: &'static str,
    /// Median milliseconds per frame.
    pub ms: f64,
}

/// Draws the grains of `world` on a `width`-pixel frame of its region, every way, interleaved
/// `reps` times: the interval renderer with tangent-line, two-level and the paper's one-level
/// anti-aliasing, and tiny-skia filling anti-aliased 64-gons (with the polygons built each frame from the
/// parametric boundary, and prebuilt).
pub fn render_cases(world: &crate::world::World, width: u32, reps: usize) -> Vec<RenderResult> {
    use crate::interval::PlacedSuperellipse;
    use crate::render::Pen;
    use crate::render::raster::{Antialias, View, paint_shape_with};
    use crate::render::{exponent_colour, world_region};
    use tiny_skia::{Color, Path, Pixmap};

    let view = View::fit(world_region(world), width);
    let mut pixmap = Pixmap::new(view.width, view.height).expect("a non-empty frame");
    // The same anti-aliased solid fill the overlays use.
    let mut pen = Pen::new(&view);
    let polygon = |pen: &Pen, b: &crate::body::Body| -> Option<Path> {
        pen.path(&b.shape.boundary_polygon(&b.pose(), 64), true)
    };
    let prebuilt: Vec<Option<Path>> = world.bodies.iter().map(|b| polygon(&pen, b)).collect();
    let names = [
        "interval quadtree, tangent-line aa",
        "interval quadtree, split aa 2",
        "interval quadtree, split aa 1 (paper)",
        "tiny-skia 64-gons, built per frame",
        "tiny-skia 64-gons, prebuilt",
    ];
    let mut times = vec![Vec::with_capacity(reps); names.len()];
    for rep in 0..=reps.max(1) {
        for (case, t) in times.iter_mut().enumerate() {
            pixmap.fill(Color::WHITE);
            let start = Instant::now();
            for (b, pre) in world.bodies.iter().zip(&prebuilt) {
                let colour = exponent_colour(&b.shape);
                match case {
                    0..=2 => {
                        let placed = PlacedSuperellipse::new(b.shape, b.pose());
                        let aa = [
                            Antialias::Gradient,
                            Antialias::Split(2),
                            Antialias::Split(1),
                        ][case];
                        paint_shape_with(pixmap.data_mut(), &view, &placed, colour, aa);
                    }
                    3 => {
                        if let Some(path) = polygon(&pen, b) {
                            pen.fill(&mut pixmap, &path, colour);
                        }
                    }
                    _ => {
                        if let Some(path) = pre {
                            pen.fill(&mut pixmap, path, colour);
                        }
                    }
                }
            }
            black_box(pixmap.data());
            // The first round warms up and is not counted.
            if rep > 0 {
                t.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    names
        .iter()
        .zip(times)
        .map(|(name, mut t)| {
            t.sort_by(f64::total_cmp);
            RenderResult {
                name,
                ms: t[t.len() / 2],
            }
        })
        .collect()
}

/// One whole-simulation step measured at one size.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingResult {
    pub grains: usize,
    pub broad_phase: &'static str,
    /// Threads in the pool the step ran in.
    pub threads: usize,
    /// Strips the box was cut into ([`crate::solver::strips`]); 0 for the paper's order.
    pub strips: usize,
    /// Median milliseconds per step.
    pub ms_per_step: f64,
    /// `ms_per_step` per grain, in microseconds.
    pub us_per_grain_step: f64,
    /// Narrow-phase tests per step.
    pub tests_per_step: f64,
}

/// `copies` side-by-side copies of a settled heap (a dump's world), in one box `copies` times as
/// wide, every grain awake and sleeping off, so that each step does a settling heap's full work.
pub fn tiled(
    heap: &crate::world::World,
    copies: usize,
    broad_phase: crate::broad_phase::Kind,
) -> crate::world::World {
    use crate::body::Body;
    let w = heap.walls;
    let width = w.right - w.left;
    let mut bodies = Vec::with_capacity(heap.bodies.len() * copies);
    for c in 0..copies {
        let shift = Vec2::new(width * c as f64, 0.0);
        bodies.extend(heap.bodies.iter().map(|b| Body {
            center: b.center + shift,
            previous_center: b.previous_center + shift,
            anchor: b.anchor + shift,
            drift_anchor: b.drift_anchor + shift,
            calm: 0,
            ..*b
        }));
    }
    let mut settings = heap.settings;
    settings.sleep_radius = 0.0;
    settings.broad_phase = broad_phase;
    let walls = crate::body::Walls {
        right: w.left + width * copies as f64,
        ..w
    };
    crate::world::World::from_parts(bodies, walls, settings, 0, heap.top, Default::default())
}

/// The cost of a step of `heap` tiled to each size in `copies`, with each broad phase in
/// `kinds`: `warmup` steps untimed, then the median of `steps` timed ones. Each scene runs in
/// the paper's order on one thread, and, with the grid, cut into strips
/// ([`crate::solver::strips`], the default width for its grains) in a pool of each size in
/// `threads`. The strip runs give the same steps whatever the pool, so their times compare.
pub fn scaling_cases(
    heap: &crate::world::World,
    copies: &[usize],
    kinds: &[crate::broad_phase::Kind],
    threads: &[usize],
    warmup: usize,
    steps: usize,
) -> Vec<ScalingResult> {
    use crate::broad_phase::Kind;
    let strip_width = crate::solver::strips::WIDTH_IN_RADII
        * heap
            .bodies
            .iter()
            .map(|b| b.shape.bounding_radius())
            .fold(0.0, f64::max);
    let mut out = Vec::new();
    for &n in copies {
        for &kind in kinds {
            let mut runs = vec![(1, 0.0)];
            if kind == Kind::Grid {
                runs.extend(threads.iter().map(|&t| (t, strip_width)));
            }
            for (t, width) in runs {
                let mut world = tiled(heap, n, kind);
                world.settings.strip_width = width;
                let strips = crate::solver::strips::Strips::new(
                    &world.bodies,
                    &world.walls,
                    &world.settings,
                    0,
                )
                .map_or(0, |s| s.count());
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(t.max(1))
                    .build()
                    .expect("a thread pool");
                let (times, tests) = pool.install(|| {
                    for _ in 0..warmup {
                        world.step();
                    }
                    let mut times = Vec::with_capacity(steps);
                    let mut tests = 0usize;
                    for _ in 0..steps {
                        let start = Instant::now();
                        tests += world.step().tests;
                        times.push(start.elapsed().as_secs_f64() * 1e3);
                    }
                    (times, tests)
                });
                let mut times = times;
                times.sort_by(f64::total_cmp);
                let ms = times.get(times.len() / 2).copied().unwrap_or(f64::NAN);
                out.push(ScalingResult {
                    grains: world.bodies.len(),
                    broad_phase: match kind {
                        Kind::Grid => "grid",
                        Kind::AllPairs => "all-pairs",
                    },
                    threads: t.max(1),
                    strips,
                    ms_per_step: ms,
                    us_per_grain_step: ms * 1e3 / world.bodies.len().max(1) as f64,
                    tests_per_step: tests as f64 / steps.max(1) as f64,
                });
            }
        }
    }
    out
}

//! Every overlap region (issue 19): a star touching a disk or a face with two spikes at once
//! has two regions; over random pairs of stars every region's points are inside both shapes
//! and no piece of the overlap found by dense sampling (an independent reference: plain `f` on
//! a grid and on the half-axes, joined by neighbours) is reported twice.

mod common;

use common::*;
use supergrain::contact::{contact, overlap_regions};
use supergrain::subdivision::Precision;

/// The overlap sampled on a grid of spacing `h` over the pair's reach, and along both shapes'
/// half-axes (a spike thinner than `h` holds its axis, which the grid may miss), the samples
/// inside both labelled by connected piece: grid samples joined to their 8 neighbours, axis
/// samples to the next along the axis and to the grid samples within `h`.
struct Sampled {
    h: f64,
    points: Vec<[f64; 2]>,
    /// The piece of each point, -1 outside.
    label: Vec<i32>,
    pieces: usize,
}

fn root(parent: &mut [usize], mut k: usize) -> usize {
    while parent[k] != k {
        parent[k] = parent[parent[k]];
        k = parent[k];
    }
    k
}

fn join(parent: &mut [usize], i: usize, j: usize) {
    let (ri, rj) = (root(parent, i), root(parent, j));
    if ri != rj {
        parent[ri.max(rj)] = ri.min(rj);
    }
}

impl Sampled {
    fn new(a: &Shape, b: &Shape, h: f64) -> Self {
        let ra = a.max_axis();
        let rb = b.max_axis();
        let x0 = (a.c[0] - ra).max(b.c[0] - rb);
        let x1 = (a.c[0] + ra).min(b.c[0] + rb);
        let y0 = (a.c[1] - ra).max(b.c[1] - rb);
        let y1 = (a.c[1] + ra).min(b.c[1] + rb);
        let nx = ((x1 - x0) / h).ceil().max(0.0) as usize + 1;
        let ny = ((y1 - y0) / h).ceil().max(0.0) as usize + 1;
        let mut points = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                points.push([x0 + i as f64 * h, y0 + j as f64 * h]);
            }
        }
        // Each half-axis from the centre to the tip, at a tenth of `h`.
        let mut axes = Vec::new();
        for shape in [a, b] {
            for (u, v) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)] {
                let reach = if u != 0.0 { shape.s[0] } else { shape.s[1] };
                let n = (reach / (0.1 * h)).ceil() as usize;
                let (sn, cs) = shape.angle.sin_cos();
                let start = points.len();
                for k in 0..n {
                    let t = reach * k as f64 / n as f64;
                    let (lu, lv) = (u * t, v * t);
                    points.push([
                        shape.c[0] + cs * lu - sn * lv,
                        shape.c[1] + sn * lu + cs * lv,
                    ]);
                }
                axes.push(start..points.len());
            }
        }
        let inside: Vec<bool> = points
            .iter()
            .map(|&p| a.f(p) < 0.0 && b.f(p) < 0.0)
            .collect();
        let mut parent: Vec<usize> = (0..points.len()).collect();
        for j in 0..ny {
            for i in 0..nx {
                let k = j * nx + i;
                if !inside[k] {
                    continue;
                }
                for (di, dj) in [(1, 0), (0, 1), (1, 1), (-1, 1)] {
                    let (ii, jj) = (i as i64 + di, j as i64 + dj);
                    if ii >= 0 && (ii as usize) < nx && (jj as usize) < ny {
                        let n = jj as usize * nx + ii as usize;
                        if inside[n] {
                            join(&mut parent, k, n);
                        }
                    }
                }
            }
        }
        for axis in axes {
            for k in axis.clone() {
                if !inside[k] {
                    continue;
                }
                if k + 1 < axis.end && inside[k + 1] {
                    join(&mut parent, k, k + 1);
                }
                let p = points[k];
                let (ci, cj) = (
                    ((p[0] - x0) / h).floor() as i64,
                    ((p[1] - y0) / h).floor() as i64,
                );
                for jj in cj..=cj + 1 {
                    for ii in ci..=ci + 1 {
                        if ii < 0 || jj < 0 || ii >= nx as i64 || jj >= ny as i64 {
                            continue;
                        }
                        let n = jj as usize * nx + ii as usize;
                        if inside[n] && dist(points[n], p) <= h {
                            join(&mut parent, k, n);
                        }
                    }
                }
            }
        }
        let mut label = vec![-1; points.len()];
        let mut of_root = vec![-1; points.len()];
        let mut pieces = 0;
        for k in 0..points.len() {
            if !inside[k] {
                continue;
            }
            let r = root(&mut parent, k);
            if of_root[r] < 0 {
                of_root[r] = pieces as i32;
                pieces += 1;
            }
            label[k] = of_root[r];
        }
        Sampled {
            h,
            points,
            label,
            pieces,
        }
    }

    /// The piece of the nearest labelled sample within `reach` of `p`.
    fn piece_near(&self, p: [f64; 2], reach: f64) -> Option<i32> {
        (0..self.points.len())
            .filter(|&k| self.label[k] >= 0)
            .map(|k| (dist(self.points[k], p), self.label[k]))
            .filter(|&(d, _)| d <= reach)
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .map(|x| x.1)
    }
}

fn regions(a: &Shape, b: &Shape) -> Vec<supergrain::contact::Penetration> {
    let ((sa, pa), (sb, pb)) = (to_lib(a), to_lib(b));
    let precision = Precision::default();
    let found = contact(&sa, &pa, &sb, &pb, &precision);
    let all = overlap_regions(&sa, &pa, &sb, &pb, &precision, found.penetration.as_ref());
    if let Some(p) = found.penetration {
        assert_eq!(all[0], p, "the first region is the contact's own answer");
    } else {
        assert!(all.is_empty());
    }
    all
}

/// Every reported deepest point is inside both shapes, and the regions fall in distinct
/// sampled pieces.
fn check_distinct(a: &Shape, b: &Shape, found: &[supergrain::contact::Penetration], s: &Sampled) {
    let mut seen = Vec::new();
    for (k, p) in found.iter().enumerate() {
        for q in [p.a_deepest, p.b_deepest] {
            let q = [q.x, q.y];
            assert!(
                a.inside_up_to(q, 1e-9) && b.inside_up_to(q, 1e-9),
                "region {k}: {q:?} is not inside both ({a:?}, {b:?})"
            );
        }
        if k == 0 {
            // The contact's own answer may be a spike tip thinner than the samples.
            continue;
        }
        // A spike thinner than the samples holds none: its point was checked above.
        let Some(piece) = s.piece_near([p.a_deepest.x, p.a_deepest.y], 3.0 * s.h) else {
            continue;
        };
        assert!(
            !seen.contains(&piece),
            "two regions in one sampled piece {piece} ({a:?}, {b:?})"
        );
        seen.push(piece);
    }
}

#[test]
fn a_star_touching_a_disk_with_two_spikes_has_two_regions() {
    let star = Shape {
        c: [0.0, 0.0],
        angle: 0.0,
        s: [1.0, 1.0],
        e: [0.7, 0.7],
    };
    // 0.03 from both tips, (1, 0) and (0, 1), and 0.04 short of the star between them.
    let r = 5f64.sqrt() + 0.03;
    let disk = Shape {
        c: [2.0, 2.0],
        angle: 0.0,
        s: [r, r],
        e: [2.0, 2.0],
    };
    let s = Sampled::new(&star, &disk, 0.0005);
    assert_eq!(s.pieces, 2, "the reference sees the two spike tips");
    for (a, b) in [(star, disk), (disk, star)] {
        let found = regions(&a, &b);
        assert_eq!(found.len(), 2, "{found:?}");
        check_distinct(&a, &b, &found, &s);
        // Each region's point of A is near one of the tips, (1, 0) and (0, 1) (the disk's
        // crosses the spike's axis 0.065 inside the tip): the regions
        // are told apart by it (the tips are equally deep, so the pair's own answer may find
        // A's deepest point at one and B's at the other).
        let mut tips: Vec<[f64; 2]> = found
            .iter()
            .map(|p| [p.a_deepest.x, p.a_deepest.y])
            .collect();
        tips.sort_by(|x, y| x[0].total_cmp(&y[0]));
        assert!(dist(tips[0], [0.0, 1.0]) < 0.08, "{tips:?}");
        assert!(dist(tips[1], [1.0, 0.0]) < 0.08, "{tips:?}");
    }
}

#[test]
fn a_star_on_a_face_with_two_spikes_has_two_regions() {
    // Spikes on the diagonals: the lower two reach 0.03 into the block's top face (and the
    // star between them stays 0.06 above it).
    let star = Shape {
        c: [0.0, 0.0],
        angle: std::f64::consts::FRAC_PI_4,
        s: [0.5, 0.5],
        e: [0.7, 0.7],
    };
    let tip = 0.5 * std::f64::consts::FRAC_1_SQRT_2;
    let block = Shape {
        c: [0.0, -tip + 0.03 - 0.5],
        angle: 0.0,
        s: [2.0, 0.5],
        e: [8.0, 8.0],
    };
    let s = Sampled::new(&star, &block, 0.001);
    assert_eq!(s.pieces, 2);
    for (a, b) in [(star, block), (block, star)] {
        let found = regions(&a, &b);
        assert_eq!(found.len(), 2, "{found:?}");
        check_distinct(&a, &b, &found, &s);
        for p in &found {
            assert!(
                (p.depth() - 0.03).abs() < 0.01,
                "each spike 0.03 deep: {p:?}"
            );
        }
    }
}

#[test]
fn regions_of_random_stars_match_dense_sampling() {
    let mut rng = Rng::new(19);
    let (mut pairs, mut several) = (0, 0);
    while pairs < 150 {
        let star = |rng: &mut Rng| Shape {
            c: [0.0, 0.0],
            angle: rng.range(0.0, std::f64::consts::TAU),
            s: [rng.range(0.25, 0.4), rng.range(0.25, 0.4)],
            e: [rng.range(0.3, 0.9), rng.range(0.3, 0.9)],
        };
        let a = star(&mut rng);
        let mut b = star(&mut rng);
        if rng.below(3) == 0 {
            b.e = [rng.range(1.0, 8.0), rng.range(1.0, 8.0)];
        }
        let t = rng.range(0.0, std::f64::consts::TAU);
        let d = rng.range(0.5, 0.95) * (a.max_axis() + b.max_axis());
        b.c = [d * t.cos(), d * t.sin()];
        let found = regions(&a, &b);
        if found.is_empty() {
            continue;
        }
        pairs += 1;
        let cell = cell_diagonal_bound(&a, &b, 7);
        let s = Sampled::new(&a, &b, cell / 6.0);
        check_distinct(&a, &b, &found, &s);
        if found.len() > 1 {
            several += 1;
        }
    }
    assert!(several >= 3, "only {several} pairs with several regions");
}

//! Independent references for the narrow-phase tests. Nothing here calls the library's
//! geometry, intervals or quadtree: shapes are plain numbers and every formula is written again.
#![allow(dead_code)]

use std::f64::consts::TAU;

pub mod resume;

/// A placed superellipse as plain numbers.
#[derive(Clone, Copy, Debug)]
pub struct Shape {
    pub c: [f64; 2],
    pub angle: f64,
    pub s: [f64; 2],
    pub e: [f64; 2],
}

impl Shape {
    /// `f(p) = |u/sx|^ex + |v/sy|^ey - 1` with `(u, v)` = `p` in the shape's frame.
    pub fn f(&self, p: [f64; 2]) -> f64 {
        let (sn, cs) = self.angle.sin_cos();
        let (dx, dy) = (p[0] - self.c[0], p[1] - self.c[1]);
        let u = cs * dx + sn * dy;
        let v = -sn * dx + cs * dy;
        (u / self.s[0]).abs().powf(self.e[0]) + (v / self.s[1]).abs().powf(self.e[1]) - 1.0
    }

    /// `p` is inside, or within `eps` of an inside point across one of the shape's axes: a
    /// star's `f` rises like `|v|^e` across its axis, so a point proven inside on the axis in
    /// the shape's frame may come out `1e-5` outside after the rounding of world coordinates
    /// (`1e-17` off the axis at exponent 0.25).
    pub fn inside_up_to(&self, p: [f64; 2], eps: f64) -> bool {
        let (sn, cs) = self.angle.sin_cos();
        let (dx, dy) = (p[0] - self.c[0], p[1] - self.c[1]);
        let u = cs * dx + sn * dy;
        let v = -sn * dx + cs * dy;
        let f = |u: f64, v: f64| {
            (u / self.s[0]).abs().powf(self.e[0]) + (v / self.s[1]).abs().powf(self.e[1]) - 1.0
        };
        f(u, v) < 0.0 || (v.abs() <= eps && f(u, 0.0) < 0.0) || (u.abs() <= eps && f(0.0, v) < 0.0)
    }

    fn local_to_world(&self, u: f64, v: f64) -> [f64; 2] {
        let (sn, cs) = self.angle.sin_cos();
        [self.c[0] + cs * u - sn * v, self.c[1] + sn * u + cs * v]
    }

    /// The boundary point at parameter `t`.
    pub fn boundary(&self, t: f64) -> [f64; 2] {
        let (sn, cs) = t.sin_cos();
        let g = |x: f64, e: f64| x.signum() * x.abs().powf(2.0 / e);
        self.local_to_world(self.s[0] * g(cs, self.e[0]), self.s[1] * g(sn, self.e[1]))
    }

    pub fn max_axis(&self) -> f64 {
        self.s[0].max(self.s[1])
    }

    pub fn min_axis(&self) -> f64 {
        self.s[0].min(self.s[1])
    }

    /// Boundary samples no farther apart than `h`, refining the parameter where needed.
    pub fn samples(&self, h: f64) -> Vec<[f64; 2]> {
        let mut out = Vec::new();
        let n = 256;
        for i in 0..n {
            let (t0, t1) = (i as f64 * TAU / n as f64, (i + 1) as f64 * TAU / n as f64);
            let curve = |t| self.boundary(t);
            let ends = ((t0, self.boundary(t0)), (t1, self.boundary(t1)));
            refine_by_chord(&curve, ends, h, 41, &mut out);
        }
        out
    }
}

impl Shape {
    /// Boundary samples no farther apart than `h` along the whole boundary, for any exponent
    /// in the accepted range. The angle parametrisation of [`Shape::samples`] cannot reach the
    /// middle of a blocky shape's faces (at exponent 40, `|cos t|^(2/40)` is still 0.15 at the
    /// smallest `cos t` that f64 holds away from 0), so each quadrant is sampled as two graphs
    /// instead, `y(x)` and `x(y)`, each refined by chord length: where one is steep the other
    /// is flat.
    pub fn dense_boundary(&self, h: f64) -> Vec<[f64; 2]> {
        let [ex, ey] = self.e;
        let [sx, sy] = self.s;
        let across = |t: f64, e_t: f64, e_o: f64| (1.0 - t.powf(e_t)).max(0.0).powf(1.0 / e_o);
        let graph_y = |u: f64| [sx * u, sy * across(u, ex, ey)];
        let graph_x = |v: f64| [sx * across(v, ey, ex), sy * v];
        let mut quarter = Vec::new();
        for graph in [&graph_y as &dyn Fn(f64) -> [f64; 2], &graph_x] {
            let n = 64;
            for i in 0..n {
                let (t0, t1) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
                refine_by_chord(
                    graph,
                    ((t0, graph(t0)), (t1, graph(t1))),
                    h,
                    61,
                    &mut quarter,
                );
            }
            quarter.push(graph(1.0));
        }
        let mut out = Vec::with_capacity(4 * quarter.len());
        for [x, y] in quarter {
            for (kx, ky) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
                out.push(self.local_to_world(kx * x, ky * y));
            }
        }
        out
    }
}

/// Two parameters of a curve and its points there.
type Ends = ((f64, [f64; 2]), (f64, [f64; 2]));

/// Points of `curve` from `t0` towards `t1` (`t1` excluded), halving the parameter where the
/// chord between neighbours is longer than `h`, at most `levels` times.
fn refine_by_chord(
    curve: &dyn Fn(f64) -> [f64; 2],
    ((t0, p0), (t1, p1)): Ends,
    h: f64,
    levels: u32,
    out: &mut Vec<[f64; 2]>,
) {
    if dist(p0, p1) <= h || levels == 0 {
        out.push(p0);
        return;
    }
    let tm = 0.5 * (t0 + t1);
    let pm = curve(tm);
    refine_by_chord(curve, ((t0, p0), (tm, pm)), h, levels - 1, out);
    refine_by_chord(curve, ((tm, pm), (t1, p1)), h, levels - 1, out);
}

pub fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Some boundary sample of one shape lies inside the other.
pub fn sampled_overlap(a: &Shape, sa: &[[f64; 2]], b: &Shape, sb: &[[f64; 2]]) -> bool {
    sb.iter().any(|&p| a.f(p) < 0.0) || sa.iter().any(|&p| b.f(p) < 0.0)
}

/// The smallest distance between the two sample sets (only samples near the other shape's
/// reach are compared, which does not change the minimum).
pub fn sampled_gap(sa: &[[f64; 2]], b: &Shape, sb: &[[f64; 2]], a: &Shape) -> f64 {
    let near = |s: &[[f64; 2]], o: &Shape| -> Vec<[f64; 2]> {
        let r = o.s[0].hypot(o.s[1]) * 1.01;
        s.iter()
            .copied()
            .filter(|&p| dist(p, o.c) <= r + 0.5)
            .collect()
    };
    let (na, nb) = (near(sa, b), near(sb, a));
    let mut best = f64::INFINITY;
    for p in &na {
        for q in &nb {
            best = best.min(dist(*p, *q));
        }
    }
    best
}

/// The Perram-Wertheim contact function of two ellipses:
/// `F = max over l in [0, 1] of l (1 - l) r^T ((1 - l) A^-1 + l B^-1)^-1 r`, `A = R diag(1/a^2) R^T`.
/// `F < 1`: overlap; `F = 1`: touching; `F > 1`: apart. Scaling both ellipses about their
/// centres by `sqrt(F)` makes them touch.
pub fn perram_wertheim(a: &Shape, b: &Shape) -> f64 {
    // A^-1 = R diag(a^2) R^T.
    let inv = |s: &Shape| {
        let (sn, cs) = s.angle.sin_cos();
        let (p, q) = (s.s[0] * s.s[0], s.s[1] * s.s[1]);
        [
            cs * cs * p + sn * sn * q,
            cs * sn * (p - q),
            sn * sn * p + cs * cs * q,
        ]
    };
    let (ia, ib) = (inv(a), inv(b));
    let r = [b.c[0] - a.c[0], b.c[1] - a.c[1]];
    let s = |l: f64| {
        let m = [
            (1.0 - l) * ia[0] + l * ib[0],
            (1.0 - l) * ia[1] + l * ib[1],
            (1.0 - l) * ia[2] + l * ib[2],
        ];
        let det = m[0] * m[2] - m[1] * m[1];
        // r^T M^-1 r with M^-1 = [m2, -m1; -m1, m0] / det.
        let q = (m[2] * r[0] * r[0] - 2.0 * m[1] * r[0] * r[1] + m[0] * r[1] * r[1]) / det;
        l * (1.0 - l) * q
    };
    // The function is concave in l: golden-section search.
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let g = 0.618_033_988_749_895;
    for _ in 0..200 {
        let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if s(x1) < s(x2) {
            lo = x1;
        } else {
            hi = x2;
        }
    }
    s(0.5 * (lo + hi))
}

/// SplitMix64: a small deterministic generator, so the references need no crate of the
/// library's.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    pub fn sign(&mut self) -> f64 {
        if self.next_u64() & 1 == 0 { 1.0 } else { -1.0 }
    }
}

/// The library's view of a reference shape.
pub fn to_lib(s: &Shape) -> (supergrain::shape::Superellipse, supergrain::shape::Pose) {
    (
        supergrain::shape::Superellipse::new(s.s, s.e).unwrap(),
        supergrain::shape::Pose::new(supergrain::geometry::Vec2::new(s.c[0], s.c[1]), s.angle)
            .unwrap(),
    )
}

/// An upper bound of the diagonal of a final quadtree cell for the pair at depth `depth`: the
/// region is at most the smaller shape's box, whose longest side is at most twice the larger
/// of its semi-axes, rotated.
pub fn cell_diagonal_bound(a: &Shape, b: &Shape, depth: u32) -> f64 {
    let reach = |s: &Shape| 2.0 * s.s[0].hypot(s.s[1]);
    let longest = reach(a).min(reach(b));
    longest / f64::from(1u32 << depth) * std::f64::consts::SQRT_2
}

//! The certified Newton path: the deepest points of a convex pair at the cost of a Newton solve,
//! each answer carrying a proof, with the quadtree as the fallback whenever the proof fails.
//!
//! `A1`, the point of A most interior to B, minimises `f_B` over A (paper III-A). For convex
//! shapes it is the point of A's boundary where the outward normals of A and of B's level set
//! are opposite (Karush-Kuhn-Tucker), unless A holds B's centre, which is then the answer. A
//! Newton solve of those conditions in A's frame (A axis-aligned at the origin, one power per
//! axis and no `powf` for the exponents 1, 2, 3, 4) finds it in a handful of iterations.
//!
//! Newton alone proves nothing: it may stop at the far side of A, or not converge. The answer is
//! kept only with a certificate built from half-planes and support functions:
//! - A lies in a half-plane `n . y <= s`, `n` A's normal at the Newton point: below its tangent
//!   there, for a convex A (`f_A` is convex), and for any shape below `h_A(n)`
//!   ([`Superellipse::local_support`] is a rigorous upper bound of the support function).
//! - B's sublevel set `{f_B <= c}` is the superellipse with semi-axes `s_i (1 + c)^(1/e_i)`. If
//!   it lies strictly beyond that line, then `f_B > c` on the half-plane and so on all of A.
//! - With `c = f_B(A1) - tau`, this proves that no point of A is deeper in B than `A1` by more
//!   than `tau`, half a final quadtree cell times `|grad f_B(A1)|`: about the quadtree's own
//!   accuracy. With `c` just below 0 it proves that A reaches less than half a final cell into
//!   B: apart, or touching within the quadtree's precision (its "no overlap").
//! - `A1` itself counts only when an interval evaluation proves it inside both shapes, as for
//!   the quadtree's midpoints.
//!
//! Every rounded quantity in the certificate is padded outward (a relative `1e-12`, far above the
//! few ulps of error of these short formulas, far below any quadtree cell), so a certificate is a
//! proof. When it fails, the caller runs the quadtree: the answer is never less certain than
//! the paper's, only faster when Newton has found the point.

use super::boundary::{INWARD, deepest_on_boundary, support_on_boundary};
use super::ray::push_out_by;
use crate::geometry::{Rotation, Vec2};
use crate::interval::{ImplicitShape, PlacedSuperellipse, up};
use crate::shape::{HalfPlane, Pose, Superellipse, abs_pow, pow32, support, support_dual};

/// A relative pad over the rounding of the certificate's formulas (module docs).
const PAD: f64 = 1e-12;
/// Newton iterations before giving up on convergence and trying the certificate anyway.
const MAX_ITERATIONS: u32 = 16;

/// What the certified path can prove about a pair.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Certified {
    /// No point of A lies in B deeper than half a final cell: apart, or touching within the
    /// quadtree's precision.
    Apart,
    /// `A1` and `A2`, each in its own shape's frame, proven inside both shapes and deepest up to
    /// the tolerance, and the pushes `A1 -> B2` (in A's frame) and `A2 -> B1` (in B's).
    Overlap {
        a1: Vec2,
        a2: Vec2,
        a_push: Vec2,
        b_push: Vec2,
    },
}

/// Whether both shapes are convex: the only pairs worth a Newton solve. (The certificate itself
/// holds for any shapes.)
pub(crate) fn eligible(a: &Superellipse, b: &Superellipse) -> bool {
    convex(a) && convex(b)
}

/// Every exponent at least 1: the shape, and its `f`, are convex.
pub(crate) fn convex(s: &Superellipse) -> bool {
    s.exponents().iter().all(|&e| e >= 1.0)
}

/// The certified answer for `a` and `b` placed at `rel_ab` in `a`'s frame, or `None` when no
/// certificate could be had (the caller then runs the quadtree). `cell`: the quadtree's final
/// cell size for this pair, which sets the tolerance.
///
/// `warm`: where the last query of this pair found its points (a persisting contact), updated
/// with this query's. `along_spikes`: the pushes of points on a star's cusp along the spike
/// ([`super::ray::push_out_by`]), for the paper model.
///
/// Convex pairs are solved by Newton; the others, and convex pairs Newton could not certify, by
/// the boundary search ([`super::boundary`]), whose witnesses are proven inside over a box of
/// half-width `slack` (a few ulps of the world coordinates they are reported in).
pub(crate) fn certified_contact(
    local_a: &PlacedSuperellipse,
    local_b: &PlacedSuperellipse,
    cell: f64,
    slack: f64,
    warm: &mut Option<WarmStart>,
    along_spikes: bool,
) -> Option<Certified> {
    let newton = eligible(local_a.shape(), local_b.shape());
    let deepest = |own: &PlacedSuperellipse, other: &PlacedSuperellipse, start: Option<Vec2>| {
        if newton && let Some(found) = deepest(own, other, cell, slack, start) {
            return Some(found);
        }
        deepest_on_boundary(own, other, cell, slack)
    };
    let last = warm.take();
    let a1 = match deepest(local_a, local_b, last.map(|w| w.a1))? {
        (Deepest::Beyond, x) => {
            *warm = Some(WarmStart { a1: x, a2: None });
            return Some(Certified::Apart);
        }
        (Deepest::At(p), _) => p,
    };
    // A1 is inside both: the shapes overlap, so A2 exists; failing to certify it is possible
    // (Newton may fail on B's side) and sends the pair to the quadtree.
    let rel_ba = local_b.pose().inverse();
    let b_local = PlacedSuperellipse::new(*local_b.shape(), Pose::ORIGIN);
    let a_in_b = PlacedSuperellipse::new(*local_a.shape(), rel_ba);
    // A2 is near A1 unless the overlap is deep: start there, seen from B, unless known.
    let a1_in_b = rel_ba.to_world(a1);
    let start = last.and_then(|w| w.a2).unwrap_or(a1_in_b);
    let a2 = match deepest(&b_local, &a_in_b, Some(start))? {
        (Deepest::At(a2), _) => a2,
        // No point of B is deeper in A than half a final cell ([`touch_level`]), yet A1 is
        // proven inside both: an overlap within rounding of touching (resting grains). A1 is
        // in both, so it is as deep in A as B's deepest point up to that distance, and serves
        // as A2.
        (Deepest::Beyond, _) => a1_in_b,
    };
    *warm = Some(WarmStart { a1, a2: Some(a2) });
    Some(Certified::Overlap {
        a1,
        a2,
        a_push: push_out_by(local_b, a1, along_spikes),
        b_push: push_out_by(&a_in_b, a2, along_spikes),
    })
}

/// Where the certified path last found a pair's deepest points, each in its own shape's frame
/// (so that it survives the pair's motion): the start of the next Newton solve for a persisting
/// contact. Only a start: every answer is certified afresh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WarmStart {
    a1: Vec2,
    a2: Option<Vec2>,
}

impl WarmStart {
    /// Its points (in A's frame): where Newton found `A1` and, if it got there, `A2`. For a
    /// dump: a run resumed with them goes on bit for bit.
    pub fn to_parts(&self) -> (Vec2, Option<Vec2>) {
        (self.a1, self.a2)
    }

    pub fn from_parts(a1: Vec2, a2: Option<Vec2>) -> Self {
        WarmStart { a1, a2 }
    }
}

pub(crate) enum Deepest {
    /// No point of `own` lies in `other` deeper than half a final cell.
    Beyond,
    /// The point of `own` most interior to `other` (up to `tau`), proven inside both.
    At(Vec2),
}

/// The deepest point of `own` in `other`, in `own`'s frame (`placed_own` at the origin,
/// `placed_other` where `other` is in that frame), and Newton's point (a warm start).
/// `start`: a point near the answer, if known. `slack`: the point is proven inside both over
/// the box of that half-width about it (a few ulps of the world coordinates it is reported in,
/// as the boundary search's witnesses), so that it stays inside when moved to the world.
fn deepest(
    placed_own: &PlacedSuperellipse,
    placed_other: &PlacedSuperellipse,
    cell: f64,
    slack: f64,
    start: Option<Vec2>,
) -> Option<(Deepest, Vec2)> {
    let (own, other, rel) = (
        placed_own.shape(),
        placed_other.shape(),
        placed_other.pose(),
    );
    debug_assert_eq!(*placed_own.pose(), Pose::ORIGIN);
    let centre = rel.center();
    // An enclosure of a shape's `f` over the box of half-width `slack` about `q`.
    let around = |shape: &PlacedSuperellipse, q: Vec2| shape.enclose_around(q, slack);

    // `own` holds `other`'s centre: that centre is the answer (`f_other >= -1` everywhere).
    // (Its plain value first: an enclosure cannot prove inside a point whose value is > 0.)
    // (And a centre beyond own's bounding circle first: no power for the usual, distant pair.)
    let r = own.bounding_radius();
    if centre.dot(centre) <= r * r
        && own.local_value(centre) < 1e-9
        && placed_own.enclose_point(centre).hi < 0.0
    {
        return (around(placed_own, centre).hi < 0.0 && around(placed_other, centre).hi < 0.0)
            .then_some((Deepest::At(centre), centre));
    }

    let (found, gradient) = newton(own, other, rel, start)?;
    // The tolerance's scale only (any `tau` gives a proof, of "deepest up to `tau`"): Newton's
    // last gradient, when it converged, is that at `x` to about 1e-6 relative.
    let gradient = gradient.unwrap_or_else(|| other.gradient(rel, found));
    let tau = 0.5 * cell * len(gradient);
    if !tau.is_finite() {
        return None;
    }
    // A hair towards own's centre, so that being inside own survives rounding (own is
    // star-shaped about its centre); more where the slack of the world's coordinates asks it
    // (grains far from the origin, or small against their coordinates: at 1e8 a point a hair
    // inside was reported on the boundary, found by a hostile test).
    let inward = |k: f64| {
        let x = found * (1.0 - k);
        (x, around(placed_own, x))
    };
    let (first, first_own) = inward(INWARD[0]);
    let moves = INWARD[1..].iter().map(|&k| inward(k));
    for (x, f_own) in std::iter::once((first, first_own)).chain(moves) {
        let f_other = around(placed_other, x);
        if f_own.hi < 0.0 && f_other.hi < 0.0 {
            let plane = half_plane(own, x, f_own.lo)?;
            return proves_above(plane, other, rel, f_other.hi - tau)
                .then_some((Deepest::At(x), x));
        }
        if f_other.lo >= 0.0 || f_other.lo.is_nan() {
            // Proven outside other (or NaN): further in does not help.
            break;
        }
    }
    let (x, plane) = (first, half_plane(own, first, first_own.lo)?);
    // No overlap to report: a proof that no point of own is deeper in other than half a
    // final cell. Resting grains touch to within rounding, and this keeps them off the quadtree.
    proves_above(plane, other, rel, -touch_level(other, cell)).then_some((Deepest::Beyond, x))
}

/// The level `-touch` of `f_other` above which a point of `other` is within half a final cell
/// (`cell / 2`, a distance) of its boundary, on any shape: "touching" in the quadtree's sense.
///
/// Euler's identity for the homogeneous `h = f + 1` gives, for `y` in other with
/// `f(y) >= -touch` and `t >= 1`, `h(t y) >= t^e_min (1 - touch)`: `y` scaled by
/// `t = (1 - touch)^(-1/e_min)` about other's centre is outside, a distance at most `(t - 1) R`
/// away (`R` other's bounding radius). That is `cell / 2` for
/// `touch = 1 - (1 + cell / (2 R))^(-e_min)`, computed here without cancellation and shrunk by
/// a relative `1e-9` over its few ulps of rounding (a smaller `touch` claims less).
///
/// Its first order, `cell e_min / (2 R)`, was used before: for blocky shapes (`e_min` in the
/// hundreds) it exceeds 1, a level every point of `other` is above, so two shapes a tenth of
/// their size deep in each other were "proven" apart (`supergrain contact --a
/// 0,0,0.183,0.387,0.423,400,400 --b 0.86,-0.44,2.933,0.439,0.483,400,400`).
pub(crate) fn touch_level(other: &Superellipse, cell: f64) -> f64 {
    let e_min = other.exponents()[0].min(other.exponents()[1]);
    let x = 0.5 * cell / other.bounding_radius();
    let touch = -(-e_min * x.ln_1p()).exp_m1();
    touch * (1.0 - 1e-9)
}

/// `|v|` by a square root: `hypot`, which guards against overflow these magnitudes never
/// reach, cost an eighth of the certified path's time.
#[inline]
fn len(v: Vec2) -> f64 {
    (v.x * v.x + v.y * v.y).sqrt()
}

/// `x^(1/e)` for `x >= 0`, without `powf` for the common exponents 2 and 4 (correctly rounded
/// square roots; the callers pad for a few ulps either way).
#[inline]
fn root(x: f64, e: f64) -> f64 {
    if e == 2.0 {
        x.sqrt()
    } else if e == 4.0 {
        x.sqrt().sqrt()
    } else {
        x.powf(1.0 / e)
    }
}

/// A shape against a wall by the certified path: the point of the shape deepest in the wall is
/// its support point in the direction into the wall: in closed form (Hölder) for a convex shape
/// with equal exponents, the dual bound's maximiser ([`support_dual`]) for unequal ones, a tip
/// for a star (both exponents up to 1), and by a branch and bound over the boundary
/// ([`support_on_boundary`]) for one exponent up to 1 and the other above. Kept only when
/// proven inside the shape and the wall, and deepest up to half a final cell by the support
/// function's upper bound; proven apart by the same bound. `None`: no proof, the caller runs
/// the quadtree.
pub(crate) fn certified_wall(
    placed: &PlacedSuperellipse,
    wall: &HalfPlane,
    cell: f64,
) -> Option<Option<Vec2>> {
    let (shape, pose) = (placed.shape(), placed.pose());
    let [e, ey] = shape.exponents();
    let n = wall.normal();
    let c = pose.center();
    let d = wall.offset();
    // Into the wall, in the shape's frame.
    let m = pose.rotation().apply_inverse(-n);
    let s = shape.semi_axes();
    // (Both exponents above 1: the closed forms' domain. An exponent of exactly 1 with the other
    // above is convex too, but takes the search below.)
    let smooth = e > 1.0 && ey > 1.0;
    // The support's bound and the point reaching it, from one solve, except for a convex shape
    // with equal exponents (closed form, the point only when needed).
    let solved = if smooth && e == ey {
        None
    } else if smooth {
        Some(support_dual(s, [e, ey], m)?)
    } else if e <= 1.0 && ey <= 1.0 {
        // A star (or a diamond) lies in the diamond of its tips, so its support is a tip's.
        let (a, b) = ((m.x * s.x).abs(), (m.y * s.y).abs());
        let sign = |v: f64| if v < 0.0 { -1.0 } else { 1.0 };
        Some(if a >= b {
            (a, Vec2::new(sign(m.x) * s.x, 0.0))
        } else {
            (b, Vec2::new(0.0, sign(m.y) * s.y))
        })
    } else {
        Some(support_on_boundary(shape, m, 0.25 * cell)?)
    };
    let h = match solved {
        Some((h, _)) => up(h * (1.0 + PAD)),
        None => support_up(s, [e, e], m)?,
    };
    let h_up = h + PAD * (s.x + s.y);
    let (tx, ty) = (n.x * c.x, n.y * c.y);
    // A lower bound of min g = n . c - d - h(-n) over the shape.
    let min_lo = tx + ty - d - h_up - PAD * (tx.abs() + ty.abs() + d.abs() + h_up);
    // No point deeper in the wall than half a final cell: apart, or touching within the
    // quadtree's precision (as for grains in [`deepest`]). Resting grains touch the floor to
    // within rounding, and this keeps them off the quadtree.
    if min_lo > -0.5 * cell {
        return Some(None);
    }
    // The point is on the boundary up to its solve's precision: moved a hair towards the
    // centre, and for a shape that is not convex (a spike's tip, thinner than the rounding of
    // the pose) further, until proven inside.
    let on_boundary = match solved {
        Some((_, point)) => point,
        None => support_point(shape, m)?,
    };
    let inward: &[f64] = if smooth { &[1e-9] } else { &[1e-9, 1e-6, 1e-3] };
    for &k in inward {
        let x = pose.to_world(on_boundary * (1.0 - k));
        // (A NaN bound proves nothing either.)
        let hi = placed.enclose_point(x).hi;
        if !x.is_finite() || hi.is_nan() {
            return None;
        }
        if hi >= 0.0 {
            continue;
        }
        let (gx, gy) = (n.x * x.x, n.y * x.y);
        let g_hi = gx + gy - d + PAD * (gx.abs() + gy.abs() + d.abs()) + f64::MIN_POSITIVE;
        return (g_hi < 0.0 && g_hi - min_lo <= 0.5 * cell).then_some(Some(x));
    }
    None
}

/// The point of `shape` (in its frame) farthest along the local direction `m`, in closed form
/// (Hölder) for equal exponents above 1: `(s_x u, s_y v)` with
/// `(u, v) = sgn (|A|, |B|)^(q-1) / ||(A, B)||_q^(q-1)`, `A = m_x s_x`, `B = m_y s_y`,
/// `1/e + 1/q = 1`. `None` for other shapes or a direction that is zero or not finite.
fn support_point(shape: &Superellipse, m: Vec2) -> Option<Vec2> {
    support_point_by(shape, m, f64::powf)
}

/// [`support_point`] with the powers of `pow` (the flat grains' path takes [`pow32`]'s: its
/// point only places a contact).
pub(super) fn support_point_by(
    shape: &Superellipse,
    m: Vec2,
    pow: fn(f64, f64) -> f64,
) -> Option<Vec2> {
    let [e, ey] = shape.exponents();
    if e != ey || e <= 1.0 {
        return None;
    }
    let s = shape.semi_axes();
    let (a, b) = (m.x * s.x, m.y * s.y);
    let q = e / (e - 1.0);
    let big = a.abs().max(b.abs());
    if !(big > 0.0 && big.is_finite()) {
        return None;
    }
    let (ra, rb) = (a.abs() / big, b.abs() / big);
    let power = |r: f64, k: f64| {
        if e == 2.0 {
            r.powi(k as i32)
        } else {
            pow(r, k)
        }
    };
    let norm = pow(power(ra, q) + power(rb, q), 1.0 / q);
    let u = a.signum() * power(ra / norm, q - 1.0);
    let v = b.signum() * power(rb / norm, q - 1.0);
    Some(Vec2::new(s.x * u, s.y * v))
}

/// `f`, its gradient and the diagonal of its Hessian for one axis term `|c / s|^e`, with no
/// division by `t` and no `powf` for the common exponents 2 and 4 (`inv_s = 1 / s`). `pow`:
/// [`abs_pow`], or [`pow32`] for Newton's iterations before its last.
#[inline]
fn axis_term(c: f64, inv_s: f64, e: f64, pow: fn(f64, f64) -> f64) -> (f64, f64, f64) {
    let t = c * inv_s;
    if e == 2.0 {
        return (t * t, 2.0 * t * inv_s, 2.0 * inv_s * inv_s);
    }
    if e == 4.0 {
        let t2 = t * t;
        return (t2 * t2, 4.0 * t2 * t * inv_s, 12.0 * t2 * inv_s * inv_s);
    }
    let m = pow(t, e);
    if t == 0.0 {
        let h = if e > 2.0 { 0.0 } else { f64::INFINITY };
        return (m, 0.0, h);
    }
    let g = e * m / t * inv_s;
    let h = (e - 1.0) * g / t * inv_s;
    (m, g, h)
}

/// `f`, gradient and Hessian `[xx, xy, yy]` of `shape` placed at `rotation`, `centre`, at `p`.
#[inline]
fn value_gradient_hessian(
    shape: &Superellipse,
    rotation: Rotation,
    centre: Vec2,
    p: Vec2,
    pow: fn(f64, f64) -> f64,
) -> (f64, Vec2, [f64; 3]) {
    let q = rotation.apply_inverse(p - centre);
    let [ex, ey] = shape.exponents();
    let inv = shape.inv_semi_axes();
    let (mu, gu, hu) = axis_term(q.x, inv.x, ex, pow);
    let (mv, gv, hv) = axis_term(q.y, inv.y, ey, pow);
    let (c, sn) = (rotation.cos, rotation.sin);
    let g = Vec2::new(c * gu - sn * gv, sn * gu + c * gv);
    let h = [
        c * c * hu + sn * sn * hv,
        c * sn * (hu - hv),
        sn * sn * hu + c * c * hv,
    ];
    (mu + mv - 1.0, g, h)
}

/// Where the ray from `own`'s centre through `p` meets `own`'s boundary (own in its frame).
pub(crate) fn radial_to_boundary(own: &Superellipse, p: Vec2) -> Option<Vec2> {
    radial(own, p, false)
}

/// [`radial_to_boundary`] in double precision, or with [`pow32`]'s powers to their own
/// accuracy (`coarse`). For equal exponents the closed form; for unequal ones Newton on the scale `t` of `p`,
/// `phi(t) = a t^ex + b t^ey - 1`, increasing and convex for `t > 0`, from the right of its
/// root, where it converges monotonically. `p` is first scaled so that its larger term is 1:
/// then the root is in `[2^(-1/e_min), 1]` and no power overflows. (Unscaled, where the sum
/// `a + b` is below 1, the start was `(a + b)^(-1/e_min)`, for a ray along an axis of exponent
/// 1 some 1e15 too far out, where single precision's powers overflow: a property test found
/// it.)
fn radial(own: &Superellipse, p: Vec2, coarse: bool) -> Option<Vec2> {
    let [ex, ey] = own.exponents();
    let inv = own.inv_semi_axes();
    let pow = if coarse { pow32 } else { abs_pow };
    // (Where `h` is far from 1 its powers lose bits: single precision's underflow to
    // subnormals, whose few digits put a ray of exponent 165 off by 4e-5.)
    let on_ray = |p: Vec2| {
        let h = pow(p.x * inv.x, ex) + pow(p.y * inv.y, ey);
        (h > 1e-30 && h < 1e30).then(|| {
            if coarse {
                p * pow32(h, -1.0 / ex)
            } else {
                p * root(h, ex).recip()
            }
        })
    };
    let k = (p.x * inv.x).abs().max((p.y * inv.y).abs());
    if !(k > 0.0 && k.is_finite()) {
        return None;
    }
    if ex == ey {
        // Scaled where the powers overflow (or vanish): the patches' walks ask along unit directions,
        // four semi-axes out for a grain 0.5 across, and `4^e` overflows single precision from
        // `e = 64`. Unscaled, every such ray failed, and the contacts of blocks of exponent 80
        // or more lost their side points and rocked from corner to corner every step: a heap of
        // exponents 50-200 never rested. (Unscaled where it can be, so that every other answer
        // keeps its bits.)
        return on_ray(p).or_else(|| on_ray(p * k.recip()));
    }
    let p = p * k.recip();
    let (a, b) = (pow(p.x * inv.x, ex), pow(p.y * inv.y, ey));
    let stop = if coarse { 1e-6 } else { 1e-15 };
    // Where the sum alone would reach 1 with the larger exponent: right of the root, as
    // `t <= 1` there (the sum is at least 1) and `t^e >= t^e_max`.
    let mut t = pow(a + b, -1.0 / ex.max(ey)).min(1.0);
    for _ in 0..30 {
        let (pa, pb) = (a * pow(t, ex), b * pow(t, ey));
        let step = (pa + pb - 1.0) * t / (ex * pa + ey * pb);
        t -= step;
        if !(t > 0.0 && t.is_finite()) {
            return None;
        }
        if step.abs() <= stop * t {
            break;
        }
    }
    Some(p * t)
}

/// [`radial_to_boundary`] with [`pow32`]'s powers, to their own accuracy (a step of a
/// millionth, the next one's size being about its square or the powers' rounding, 1e-7). The
/// patches' walks take thousands of rays a step for a pour of unequal exponents (in
/// `pour-mixed.toml`, 6,700 a step at step 1,000, when double precision's Newton took eleven
/// powers a ray); also the start of [`newton`].
pub(crate) fn ray32(shape: &Superellipse, p: Vec2) -> Option<Vec2> {
    radial(shape, p, true)
}

/// Newton on the conditions for `argmin f_other` over `own`'s boundary: `grad f_other + l grad
/// f_own = 0`, `f_own = 0`, in `own`'s frame, started where the line between the centres leaves
/// `own` (or from `start`, projected on the boundary). Returns the last iterate, projected on
/// the boundary unless converged there (convergence is not required: the certificate decides),
/// and, once converged, `grad f_other` at the last iterate (at most `1e-6` of the size from
/// the answer: about `1e-6` relative).
fn newton(
    own: &Superellipse,
    other: &Superellipse,
    rel: &Pose,
    start: Option<Vec2>,
) -> Option<(Vec2, Option<Vec2>)> {
    let (rot, c) = (rel.rotation(), rel.center());
    // The start and the iterations but the last in single precision ([`pow32`]): Newton's
    // answer only has to be near the minimum for the certificate, which is computed in double
    // precision's intervals, and the last iteration, in double precision, takes an iterate
    // within 1e-7 of the answer to within its square.
    // (Exponents 2 and 4 have exact powers, and keep double precision throughout.)
    let exact = |s: &Superellipse| s.exponents().iter().all(|&e| e == 2.0 || e == 4.0);
    let coarse = !(exact(own) && exact(other));
    let project = if coarse { ray32 } else { radial_to_boundary };
    // A warm start (where the last query of the pair found its point, on `own`'s boundary but
    // for the hair it was moved in) needs no projection: two powers to see that, against the
    // projection's ten or so.
    let on_boundary = |s: Vec2| {
        let inv = own.inv_semi_axes();
        let [ex, ey] = own.exponents();
        (pow32(s.x * inv.x, ex) + pow32(s.y * inv.y, ey) - 1.0).abs() <= 1e-6
    };
    let mut x = start
        .and_then(|s| {
            if coarse && on_boundary(s) {
                Some(s)
            } else {
                project(own, s)
            }
        })
        .or_else(|| project(own, c))?;
    let size = own.min_semi_axis();
    let mut max_step = 0.25 * size;
    let mut last_dx = Vec2::ZERO;
    // (Only where an exponent is below 2; circles, ellipses and squircles never cycle so.)
    let kinked = [own, other]
        .iter()
        .any(|s| s.exponents().iter().any(|&e| e < 2.0));
    let converged_step2 = (1e-6 * size) * (1e-6 * size);
    // Close enough for the last iteration: the next step is then about the square of this
    // one's (times the curvature's scale) or the single-precision powers' rounding, 1e-7.
    let near_step2 = (1e-4 * size) * (1e-4 * size);
    let id = Rotation::IDENTITY;
    let mut fine = !coarse;
    // The multiplier starts from the gradients at the start, as the first iteration finds them.
    let mut l = f64::NAN;
    for _ in 0..MAX_ITERATIONS {
        let pow: fn(f64, f64) -> f64 = if fine { abs_pow } else { pow32 };
        let (fa, ga, ha) = value_gradient_hessian(own, id, Vec2::ZERO, x, pow);
        let (_, gb, hb) = value_gradient_hessian(other, rot, c, x, pow);
        let first = l.is_nan();
        if first {
            // The multiplier that best cancels `gb + l ga`: one division, no square root (the
            // ratio of the lengths cost an eighth of a circles step). Should the gradients not
            // point apart, the ratio of lengths.
            let gaga = ga.dot(ga);
            l = -gb.dot(ga) / gaga;
            if l.is_nan() || l <= 0.0 {
                l = (gb.dot(gb) / gaga).sqrt();
            }
            if !l.is_finite() {
                return None;
            }
        }
        let r = [gb.x + l * ga.x, gb.y + l * ga.y, fa];
        if first && fine {
            // The start solves the conditions already (two circles, or a warm start that has
            // not moved): on the boundary, with opposite normals to within 1e-10, which puts
            // Newton's step below the convergence threshold. The start is on the boundary, so
            // there is nothing to solve or project.
            let opposite = r[0] * r[0] + r[1] * r[1] <= 1e-20 * gb.dot(gb);
            if opposite && fa.abs() <= 1e-10 && ga.dot(gb) < 0.0 {
                return Some((x, Some(gb)));
            }
        }
        let j = [
            [hb[0] + l * ha[0], hb[1] + l * ha[1], ga.x],
            [hb[1] + l * ha[1], hb[2] + l * ha[2], ga.y],
            [ga.x, ga.y, 0.0],
        ];
        let Some(d) = solve3(j, [-r[0], -r[1], -r[2]]) else {
            break;
        };
        let mut dx = Vec2::new(d[0], d[1]);
        let mut dl = d[2];
        // Squared lengths: a square root only for a step to cut.
        let step2 = dx.dot(dx);
        // A step back the way the last one came, not much shorter: Newton cycling about a
        // point where a Hessian is unbounded (next to the tip of an axis of exponent below 2
        // of either shape, `|t|^(e-2)`). Each such step is cut to half the last one's length,
        // so the iterates close in on where the direction turns.
        if kinked && dx.dot(last_dx) < 0.0 && step2 > 0.25 * last_dx.dot(last_dx) {
            max_step = 0.5 * last_dx.dot(last_dx).sqrt();
        }
        if step2 > max_step * max_step {
            let k = max_step / step2.sqrt();
            dx = dx * k;
            dl *= k;
        }
        x += dx;
        last_dx = dx;
        l = if l + dl > 0.0 { l + dl } else { 0.5 * l };
        // Quadratic convergence: after a step of `1e-6` of the size the error is about the
        // square of it, `1e-12` (one more iteration only confirmed that); and even where
        // convergence is slow (flat faces) `1e-6` is far below any tolerance the certificate
        // needs (half a final cell, about `2e-3` of the size at depth 7). 5% off a step of the
        // 100,000-grain heap.
        if fine && step2 <= converged_step2 {
            // The last step solved `f_own + grad f_own . dx = 0`, so `f_own` is now of the
            // order of the step squared (1e-12 of the size away from the boundary at most, far
            // inside the 1e-9 the caller moves the point in): no projection, and its three
            // powers, needed.
            return x.is_finite().then_some((x, Some(gb)));
        }
        if step2 <= near_step2 {
            fine = true;
        }
    }
    if !x.is_finite() {
        return None;
    }
    Some((radial_to_boundary(own, x)?, None))
}

/// `J d = r` by Cramer's rule, `None` when `J` is (nearly) singular or anything is not finite.
fn solve3(j: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let det = det3(j);
    if !(det.is_finite() && det != 0.0) {
        return None;
    }
    let inv = det.recip();
    let mut out = [0.0; 3];
    for (k, o) in out.iter_mut().enumerate() {
        let mut m = j;
        for row in 0..3 {
            m[row][k] = r[row];
        }
        *o = det3(m) * inv;
    }
    out.iter().all(|v| v.is_finite()).then_some(out)
}

/// An upper bound of the support function, about its centre, of the superellipse with these
/// semi-axes and exponents, in the local direction `d`: [`Superellipse::local_support`] for
/// equal exponents (exact), the dual bound [`support_dual`] for unequal ones, where the larger
/// exponent's support is too loose for any certificate (measured on the mixed class of `bench
/// contact`, the first deepest point of 512 of its 539 convex pairs is certified with the dual
/// bound, of 177 with the larger exponent's; 3.5 us a convex pair instead of 10.9).
fn support_up(semi_axes: Vec2, exponents: [f64; 2], d: Vec2) -> Option<f64> {
    // Grown axes may overflow: no bound then. (Exponents come from valid shapes.)
    let valid = |s: f64| s > 0.0 && s.is_finite();
    if !(valid(semi_axes.x) && valid(semi_axes.y)) {
        return None;
    }
    let h = if exponents[0] == exponents[1] {
        support(semi_axes, exponents, d)
    } else {
        // Unequal exponents: the dual bound, tight where `support`'s larger exponent is not.
        support_dual(semi_axes, exponents, d)?.0
    };
    Some(up(h * (1.0 + PAD)))
}

/// A half-plane `n . y <= bound` that holds `own` (in its frame), with `n = grad f_own(x)`.
///
/// For a convex `own`, `f_own` is a convex function, so for every `y` in `own`
/// `0 >= f_own(y) >= f_own(x) + n . (y - x)`: the bound is `n . x - f_own(x)`, no power needed
/// (`f_own_lo` is a lower bound of `f_own(x)`). The computed `n` errs from the exact gradient by a
/// few ulps, which over `|y - x| <= 2 R` the pad covers. For a star, the support function's
/// upper bound ([`Superellipse::local_support`]).
fn half_plane(own: &Superellipse, x: Vec2, f_own_lo: f64) -> Option<(Vec2, f64)> {
    let n = own.local_gradient(x);
    if !n.is_finite() || n == Vec2::ZERO {
        return None;
    }
    if !convex(own) {
        return Some((n, support_up(own.semi_axes(), own.exponents(), n)?));
    }
    let (tx, ty) = (n.x * x.x, n.y * x.y);
    let norm1 = n.x.abs() + n.y.abs();
    // `n`'s own error grows with the exponent (`|t|^(e-1)` multiplies `t`'s relative error by
    // `e - 1`): about `(e + 2) eps`, which `PAD` alone would not cover beyond e ~ 1,000.
    let [ex, ey] = own.exponents();
    let n_pad = PAD + 8.0 * f64::EPSILON * ex.max(ey);
    let bound = tx + ty - f_own_lo
        + PAD * (tx.abs() + ty.abs() + f_own_lo.abs())
        + n_pad * norm1 * 2.0 * own.bounding_radius()
        + f64::MIN_POSITIVE;
    bound.is_finite().then_some((n, bound))
}

/// A proof that `f_other > level` at every point of `own` (own at the origin of its frame,
/// other at `rel`), given a half-plane `n . y <= s_own` that holds own: other's sublevel set at
/// `level` lies strictly beyond its line. The proof is as tight as `n` is close to the normal
/// of the common tangent.
pub(super) fn proves_above(
    plane: (Vec2, f64),
    other: &Superellipse,
    rel: &Pose,
    level: f64,
) -> bool {
    let (n, s_own) = plane;
    if !(n.is_finite() && level.is_finite() && s_own.is_finite()) || n == Vec2::ZERO {
        return false;
    }
    // `f_other >= -1` everywhere: a level at or below -1 needs no proof ("at least" suffices
    // there, the only point at -1 being other's centre, not in own, or the caller's first case).
    let k = up(1.0 + level) * (1.0 + PAD);
    if k <= 0.0 {
        return true;
    }
    let c = rel.center();
    let (tx, ty) = (n.x * c.x, n.y * c.y);
    // n . c - s_own, rounded down with a pad over every term it was summed from.
    let gap = tx + ty - s_own - PAD * (tx.abs() + ty.abs() + s_own) - f64::MIN_POSITIVE;
    // (NaN fails too.)
    if gap.is_nan() || gap <= 0.0 {
        return false;
    }
    // -n in other's frame; its rounding moves the support by at most |error| x the radius of the
    // level set, covered by the relative pad on that radius.
    let m = rel.rotation().apply_inverse(-n);
    let [ex, ey] = other.exponents();
    let s = other.semi_axes();
    let grow = |e: f64| root(k, e) * (1.0 + PAD);
    let gx = grow(ex);
    let gy = if ey == ex { gx } else { grow(ey) };
    let axes = Vec2::new(s.x * gx, s.y * gy);
    let Some(h) = support_up(axes, [ex, ey], m) else {
        return false;
    };
    let radius = (axes.x + axes.y) * (n.x.abs() + n.y.abs());
    h + PAD * radius < gap
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_shape(rng: &mut ChaCha8Rng, convex: bool) -> Superellipse {
        random_shape_with(rng, convex, false)
    }

    fn random_shape_with(rng: &mut ChaCha8Rng, convex: bool, same: bool) -> Superellipse {
        let lo = if convex { 1.0 } else { 0.4 };
        let e = |rng: &mut ChaCha8Rng| match rng.random_range(0..4) {
            0 => 2.0,
            1 => 4.0,
            _ => rng.random_range(lo..5.0),
        };
        let ex = e(rng);
        let ey = if same || rng.random_bool(0.5) {
            ex
        } else {
            e(rng)
        };
        Superellipse::new(
            [rng.random_range(0.1..1.0), rng.random_range(0.1..1.0)],
            [ex, ey],
        )
        .unwrap()
    }

    /// Points of `own` (its frame) where `min f_other` may lie: its boundary densely, inner
    /// copies of it, and `other`'s centre if `own` holds it.
    fn samples(own: &Superellipse, rel: &Pose) -> Vec<Vec2> {
        let n = 4000;
        let mut out: Vec<Vec2> = (0..n)
            .flat_map(|i| {
                let p = own.boundary_point(i as f64 * std::f64::consts::TAU / n as f64);
                [p, p * 0.5]
            })
            .collect();
        if own.local_value(rel.center()) <= 0.0 {
            out.push(rel.center());
        }
        out
    }

    /// The certificate never proves `f_other > level` over `own` when a sampled point of `own`
    /// has `f_other <= level`: on any shapes (stars too, for which it still must hold), along
    /// the Newton normal and along random directions, at levels around the sampled minimum.
    #[test]
    fn the_certificate_never_proves_what_sampling_refutes() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (mut proofs, mut tight) = (0, 0);
        for case in 0..600 {
            let convex = case % 2 == 0;
            let own = random_shape(&mut rng, convex);
            let other = random_shape(&mut rng, convex);
            let dir: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let dist =
                rng.random_range(0.3..1.0) * (own.bounding_radius() + other.bounding_radius());
            let rel = Pose::new(
                Vec2::new(dir.cos(), dir.sin()) * dist,
                rng.random_range(0.0..std::f64::consts::TAU),
            )
            .unwrap();
            let pts = samples(&own, &rel);
            let sampled_min = pts
                .iter()
                .map(|&p| other.value(&rel, p))
                .fold(f64::INFINITY, f64::min);
            // Along a random direction, by the support function; at Newton's point, by the
            // tangent (convex) or the support function (stars).
            let n = Vec2::new(dir.cos(), dir.sin());
            let mut planes = vec![(n, support_up(own.semi_axes(), own.exponents(), n).unwrap())];
            if let Some((x, _)) = newton(&own, &other, &rel, None)
                && let Some(plane) = half_plane(
                    &own,
                    x,
                    PlacedSuperellipse::new(own, Pose::ORIGIN)
                        .enclose_point(x)
                        .lo,
                )
            {
                planes.push(plane);
            }
            for plane in planes {
                let n = plane.0;
                for k in 0..8 {
                    let level = sampled_min + (k as f64 - 5.0) * 0.02 * sampled_min.abs().max(0.05);
                    if !proves_above(plane, &other, &rel, level) {
                        continue;
                    }
                    proofs += 1;
                    if level > sampled_min - 0.05 * sampled_min.abs().max(0.05) {
                        tight += 1;
                    }
                    for &p in &pts {
                        let f = other.value(&rel, p);
                        assert!(
                            f > level - 1e-12,
                            "case {case}: proven f > {level} over {own:?}, but f = {f} at {p:?} \
                             ({other:?} at {rel:?}, n = {n:?})"
                        );
                    }
                }
            }
        }
        // The proofs are exercised, and some within a few percent of the true minimum.
        assert!(
            proofs > 500 && tight > 100,
            "{proofs} proofs, {tight} tight"
        );
    }

    /// Newton converges where a shape has an exponent just above 1, whose Hessian is
    /// unbounded at its axes' tips: there it cycled about the tip (16 iterations, then the
    /// boundary search; 42 of the 46 fallbacks of `bench contact`'s mixed class). Its point is
    /// then the minimum of `f_other` over `own`'s boundary, against dense sampling.
    #[test]
    fn newton_converges_next_to_the_tips_of_exponents_near_one() {
        let mut rng = ChaCha8Rng::seed_from_u64(23);
        let (mut converged, mut total) = (0, 0);
        for case in 0..400 {
            let near_one = |rng: &mut ChaCha8Rng| rng.random_range(1.02..1.4);
            let own = Superellipse::new(
                [rng.random_range(0.3..0.7), rng.random_range(0.3..0.7)],
                [near_one(&mut rng), rng.random_range(1.0..4.0)],
            )
            .unwrap();
            let other = Superellipse::new(
                [rng.random_range(0.3..0.7), rng.random_range(0.3..0.7)],
                [rng.random_range(1.0..4.0), rng.random_range(1.0..4.0)],
            )
            .unwrap();
            // Near touching: the centre distance about the sum of the bounding radii' halves.
            let dir: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let dist = rng.random_range(0.8..1.1)
                * 0.5
                * (own.bounding_radius() + other.bounding_radius());
            let rel = Pose::new(
                Vec2::new(dir.cos(), dir.sin()) * (dist + 0.3 * own.min_semi_axis()),
                rng.random_range(0.0..std::f64::consts::TAU),
            )
            .unwrap();
            if own.local_value(rel.center()) <= 0.0 {
                continue;
            }
            total += 1;
            let Some((x, Some(_))) = newton(&own, &other, &rel, None) else {
                continue;
            };
            converged += 1;
            let sampled_min = (0..20_000)
                .map(|i| {
                    let p = own.boundary_point(i as f64 * std::f64::consts::TAU / 20_000.0);
                    other.value(&rel, p)
                })
                .fold(f64::INFINITY, f64::min);
            let f = other.value(&rel, x);
            assert!(
                f <= sampled_min + 1e-6 * (1.0 + sampled_min.abs()),
                "case {case}: Newton's f_other {f} above the sampled minimum {sampled_min}"
            );
        }
        // 375 of 400 converge; 347 without the cut steps.
        assert!(
            converged * 10 >= 9 * total,
            "{converged} of {total} converged"
        );
    }

    /// Newton's point, when certified, is the sampled minimum of `f_other` over `own` up to
    /// the tolerance; and convex pairs are certified nearly always, with equal exponents and
    /// with unequal ones (whose certificate needs the dual support bound: with the larger
    /// exponent's support, 70% of these were; now 98%).
    #[test]
    fn certified_deepest_points_match_the_sampled_minimum() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (mut certified, mut overlaps, mut total) = (0, 0, 0);
        let (mut unequal, mut unequal_certified) = (0, 0);
        for case in 0..800 {
            let same = case % 2 == 0;
            let own = random_shape_with(&mut rng, true, same);
            let other = random_shape_with(&mut rng, true, same);
            let uneven = |s: &Superellipse| s.exponents()[0] != s.exponents()[1];
            let counted = uneven(&own) || uneven(&other);
            unequal += usize::from(counted);
            let dir: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let dist = rng.random_range(0.2..0.9) * (own.min_semi_axis() + other.bounding_radius());
            let rel = Pose::new(
                Vec2::new(dir.cos(), dir.sin()) * dist,
                rng.random_range(0.0..std::f64::consts::TAU),
            )
            .unwrap();
            total += 1;
            let cell = 1e-3;
            let placed_own = PlacedSuperellipse::new(own, Pose::ORIGIN);
            let placed_other = PlacedSuperellipse::new(other, rel);
            let Some((answer, _)) = deepest(&placed_own, &placed_other, cell, 0.0, None) else {
                continue;
            };
            certified += 1;
            unequal_certified += usize::from(counted);
            let pts = samples(&own, &rel);
            let sampled_min = pts
                .iter()
                .map(|&p| other.value(&rel, p))
                .fold(f64::INFINITY, f64::min);
            match answer {
                Deepest::Beyond => {
                    // No sampled point of own is more than half a cell inside other, measured
                    // along the ray from other's centre.
                    for &p in &pts {
                        let f = other.value(&rel, p);
                        if f < 0.0 {
                            let q = rel.to_local(p);
                            let exit = radial_to_boundary(&other, q).unwrap();
                            let depth = len(exit - q);
                            assert!(
                                depth <= 0.5 * cell * (1.0 + 1e-6) + 1e-12,
                                "case {case}: apart, but {p:?} is {depth} deep"
                            );
                        }
                    }
                }
                Deepest::At(p) => {
                    overlaps += 1;
                    assert!(
                        own.local_value(p) < 0.0 && other.value(&rel, p) < 0.0,
                        "case {case}"
                    );
                    let f = other.value(&rel, p);
                    // No sample deeper than the answer by more than the tolerance (plus the
                    // hair the point is moved inside by).
                    let tau = 0.5 * cell * other.gradient(&rel, p).norm() + 1e-6;
                    assert!(
                        f <= sampled_min + tau,
                        "case {case}: f = {f}, sampled min {sampled_min}"
                    );
                }
            }
        }
        assert!(overlaps > 200, "{overlaps} overlaps");
        assert!(
            certified * 100 >= total * 95,
            "{certified} of {total} certified"
        );
        assert!(unequal > 250);
        assert!(
            unequal_certified * 100 >= unequal * 90,
            "{unequal_certified} of {unequal} with unequal exponents certified"
        );
    }

    /// Grains at rest touch to within rounding. Disks overlapping by `delta` from 1e-13 to 1e-4,
    /// at any angle, and a disk sunk `delta` into the floor: all answered by the certified path
    /// (no quadtree cell), with the analytic depth (`ra + rb - distance`, `r - height`) when an
    /// overlap is reported, and "no overlap" only for depths under half a final cell.
    #[test]
    fn touching_disks_are_certified_with_their_analytic_depth() {
        use crate::contact::{contact, contact_wall};
        use crate::geometry::Aabb;
        use crate::subdivision::Precision;
        let precision = Precision::default();
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let floor = HalfPlane::new(Vec2::new(0.0, 1.0), 0.0).unwrap();
        for case in 0..200 {
            let (ra, rb) = (rng.random_range(0.2..0.5), rng.random_range(0.2..0.5));
            // Half of them where the projection leaves resting grains: a few 1e-10 deep, about
            // the hair (1e-9 of a radius) a Newton point is moved in to be proven inside.
            let decades = if case % 2 == 0 {
                -13.0..-4.0
            } else {
                -10.5..-8.5
            };
            let delta = 10f64.powf(rng.random_range(decades));
            let dir: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let u = Vec2::new(dir.cos(), dir.sin());
            let c = Vec2::new(rng.random_range(-3.0..3.0), rng.random_range(0.0..3.0));
            let (a, b) = (
                Superellipse::circle(ra).unwrap(),
                Superellipse::circle(rb).unwrap(),
            );
            let pa = Pose::new(c, rng.random_range(0.0..6.0)).unwrap();
            let pb = Pose::new(c + u * (ra + rb - delta), rng.random_range(0.0..6.0)).unwrap();
            let got = contact(&a, &pa, &b, &pb, &precision);
            assert_eq!(
                got.cells, 0,
                "case {case}: delta {delta:e} went to the quadtree"
            );
            // At least the final cell of the pair's region or the floor's (each within a box
            // of side 2 max(ra, rb)).
            let side = Aabb::new(Vec2::ZERO, Vec2::new(2.0 * ra.max(rb), 0.0));
            let cell = precision.cell_size(&side);
            match got.penetration {
                Some(p) => {
                    // A1 lies `delta` deep in B, and B's deepest point as deep in A.
                    for push in [p.a_push, p.b_push] {
                        let depth = push.norm();
                        assert!(
                            (depth - delta).abs() <= 1e-7,
                            "case {case}: a push of {depth:e} for an overlap of {delta:e}"
                        );
                    }
                }
                None => assert!(delta < 0.5 * cell, "case {case}: {delta:e} missed"),
            }
            let pose = Pose::new(Vec2::new(c.x, ra - delta), 0.3).unwrap();
            let wall = contact_wall(&a, &pose, &floor, &precision);
            assert_eq!(wall.cells, 0, "case {case}: the floor went to the quadtree");
            match wall.penetration {
                Some(p) => assert!((p.push.y - delta).abs() <= 1e-7),
                None => assert!(delta < 0.5 * cell, "case {case}: floor {delta:e} missed"),
            }
        }
    }
}

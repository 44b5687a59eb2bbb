//! The substeps' passes over the contacts in colour batches, after Box2D v3's graph colouring
//! (Catto, "Solver2D", 2024): contacts are coloured so that no two of a colour share a grain,
//! and each colour is cut into batches of [`LANES`] contacts held lane by lane (one array per
//! quantity, one lane per contact). A batch's contacts are independent, so the pass computes
//! the four side by side, in lanes the compiler turns into vector instructions.
//!
//! Written by hand: the solver is the heart of the engine. The lanes are plain `[f64; 4]`
//! with the scalar operations of [`super::solve_one`] in the same order, not a SIMD crate's
//! vectors, so each lane gives the bits the one-contact code gives (a crate's `max` and
//! `clamp` differ from `f64`'s on signed zeros): solving the batches is solving the contacts
//! one by one in the batches' order, which `tests` checks bit for bit, up to the sign of a
//! zero velocity (a contact with fewer points than its batch's others runs the missing ones
//! with zero masses and levers, which add `+0` to its grains' velocities: a `-0.0` turns
//! `+0.0`, and nothing else changes).
//!
//! Why: on the settled 1,000-grain mixed heap the solve was 38% of the step, 1.2 ms, more
//! than Box2D's whole step. Neither fewer instructions (one record per grain: 30% fewer, the
//! same time) nor independent lanes computed one after another paid; vector lanes without
//! masks took the step 11% down (`docs/peers.md`).

use super::{Constraint, STATIC, SoftSettings, Solid, State, clamp, max, solve_one, warm_one};

/// Contacts solved side by side.
pub(super) const LANES: usize = 4;

/// Colours before a contact goes to the overflow, solved one by one after the batches (a
/// grain touching more than this many others: a boulder among sand).
const COLOURS: usize = 64;

/// One value per lane. Each operation is the scalar one lane by lane, written out so that
/// the compiler emits it as vector instructions (two lanes to an SSE2 register).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
struct W([f64; LANES]);

/// One condition per lane.
#[derive(Clone, Copy, Debug, Default)]
struct M([bool; LANES]);

impl W {
    #[inline(always)]
    fn splat(x: f64) -> W {
        W([x; LANES])
    }

    #[inline(always)]
    fn zip(self, o: W, f: impl Fn(f64, f64) -> f64) -> W {
        W([
            f(self.0[0], o.0[0]),
            f(self.0[1], o.0[1]),
            f(self.0[2], o.0[2]),
            f(self.0[3], o.0[3]),
        ])
    }

    #[inline(always)]
    fn gt(self, o: W) -> M {
        M([
            self.0[0] > o.0[0],
            self.0[1] > o.0[1],
            self.0[2] > o.0[2],
            self.0[3] > o.0[3],
        ])
    }

    /// [`max`] lane by lane.
    #[inline(always)]
    fn max(self, o: W) -> W {
        self.zip(o, max)
    }

    /// [`clamp`] lane by lane.
    #[inline(always)]
    fn clamp(self, lo: W, hi: W) -> W {
        W([
            clamp(self.0[0], lo.0[0], hi.0[0]),
            clamp(self.0[1], lo.0[1], hi.0[1]),
            clamp(self.0[2], lo.0[2], hi.0[2]),
            clamp(self.0[3], lo.0[3], hi.0[3]),
        ])
    }
}

impl M {
    /// `t` where the condition holds, else `f`.
    #[inline(always)]
    fn select(self, t: W, f: W) -> W {
        W([
            if self.0[0] { t.0[0] } else { f.0[0] },
            if self.0[1] { t.0[1] } else { f.0[1] },
            if self.0[2] { t.0[2] } else { f.0[2] },
            if self.0[3] { t.0[3] } else { f.0[3] },
        ])
    }
}

macro_rules! lanes {
    ($op:ident, $f:ident) => {
        impl std::ops::$op for W {
            type Output = W;
            #[inline(always)]
            fn $f(self, o: W) -> W {
                self.zip(o, |x, y| std::ops::$op::$f(x, y))
            }
        }
    };
}
lanes!(Add, add);
lanes!(Sub, sub);
lanes!(Mul, mul);
lanes!(Div, div);

impl std::ops::Neg for W {
    type Output = W;
    #[inline(always)]
    fn neg(self) -> W {
        W(self.0.map(|x| -x))
    }
}

/// One contact point in each lane.
#[derive(Clone, Copy, Debug, Default)]
struct PointLanes {
    rax: W,
    ray: W,
    rbx: W,
    rby: W,
    base: W,
    normal_mass: W,
    tangent_mass: W,
    normal_impulse: W,
    tangent_impulse: W,
    max_normal_impulse: W,
    closing: W,
}

/// [`LANES`] contacts of one colour.
#[derive(Clone, Debug, Default)]
struct Batch {
    /// Each lane's contact, and the slots of its two solids in [`State::solids`] (the walls'
    /// for [`STATIC`] and for an empty lane).
    constraint: [usize; LANES],
    a: [usize; LANES],
    b: [usize; LANES],
    /// The first wall's slot: the walls' records follow the grains'.
    walls: usize,
    /// Lanes in use, and the most points a lane has.
    lanes: usize,
    most: usize,
    nx: W,
    ny: W,
    friction: W,
    rolling_resistance: W,
    lever: W,
    slop: W,
    rolling_mass: W,
    rolling_impulse: W,
    bias_rate: W,
    mass_scale: W,
    impulse_scale: W,
    points: [PointLanes; 3],
}

impl Batch {
    /// Lane `l` from a contact (its index and itself), or emptied: the walls' slot on both
    /// sides and zeros, which add `+0` to that slot. Points past the batch's `most` are left
    /// as they were: nothing reads them.
    #[inline(always)]
    fn fill(&mut self, l: usize, contact: Option<(usize, &Constraint)>, wall: usize) {
        self.walls = wall;
        let Some((i, c)) = contact else {
            self.constraint[l] = 0;
            self.a[l] = wall;
            self.b[l] = wall;
            for w in [
                &mut self.nx,
                &mut self.ny,
                &mut self.friction,
                &mut self.rolling_resistance,
                &mut self.lever,
                &mut self.slop,
                &mut self.rolling_mass,
                &mut self.rolling_impulse,
                &mut self.bias_rate,
                &mut self.mass_scale,
                &mut self.impulse_scale,
            ] {
                w.0[l] = 0.0;
            }
            for q in &mut self.points[..self.most] {
                q.clear(l);
            }
            return;
        };
        self.constraint[l] = i;
        self.a[l] = c.slot_a;
        self.b[l] = c.b;
        self.nx.0[l] = c.normal.x;
        self.ny.0[l] = c.normal.y;
        self.friction.0[l] = c.friction;
        self.rolling_resistance.0[l] = c.rolling_resistance;
        self.lever.0[l] = c.lever;
        self.slop.0[l] = c.slop;
        self.rolling_mass.0[l] = c.rolling_mass;
        self.rolling_impulse.0[l] = c.rolling_impulse;
        self.bias_rate.0[l] = c.softness.bias_rate;
        self.mass_scale.0[l] = c.softness.mass_scale;
        self.impulse_scale.0[l] = c.softness.impulse_scale;
        for (k, q) in self.points[..self.most].iter_mut().enumerate() {
            let Some(p) = c.points[..c.len].get(k) else {
                q.clear(l);
                continue;
            };
            q.rax.0[l] = p.ra.x;
            q.ray.0[l] = p.ra.y;
            q.rbx.0[l] = p.rb.x;
            q.rby.0[l] = p.rb.y;
            q.base.0[l] = p.base;
            q.normal_mass.0[l] = p.normal_mass;
            q.tangent_mass.0[l] = p.tangent_mass;
            q.normal_impulse.0[l] = p.normal_impulse;
            q.tangent_impulse.0[l] = p.tangent_impulse;
            q.max_normal_impulse.0[l] = p.max_normal_impulse;
            q.closing.0[l] = p.closing;
        }
    }
}

impl PointLanes {
    /// Lane `l` of a point no contact has: zeros.
    #[inline(always)]
    fn clear(&mut self, l: usize) {
        for w in [
            &mut self.rax,
            &mut self.ray,
            &mut self.rbx,
            &mut self.rby,
            &mut self.base,
            &mut self.normal_mass,
            &mut self.tangent_mass,
            &mut self.normal_impulse,
            &mut self.tangent_impulse,
            &mut self.max_normal_impulse,
            &mut self.closing,
        ] {
            w.0[l] = 0.0;
        }
    }
}

/// The contacts of a step in colour batches, and those past the last colour.
#[derive(Debug, Default)]
pub(super) struct Batches {
    batches: Vec<Batch>,
    overflow: Vec<usize>,
    /// Scratch: the colours each grain has, and each colour's contacts.
    used: Vec<u64>,
    colours: Vec<Vec<usize>>,
}

impl Batches {
    /// Colours `constraints` (greedily, in their order: each takes the first colour neither of
    /// its grains has; walls are no grain) and packs each colour's contacts into batches.
    pub(super) fn build(&mut self, constraints: &[Constraint], bodies: usize) {
        self.overflow.clear();
        self.used.clear();
        self.used.resize(bodies, 0);
        for c in &mut self.colours {
            c.clear();
        }
        self.colours.resize_with(COLOURS, Vec::new);
        for (i, c) in constraints.iter().enumerate() {
            // (A lane scatters both its grains: one grain on both sides would lose an update.)
            debug_assert!(c.a != c.b, "a contact of grain {} with itself", c.b);
            let mask = |k: usize| if k == STATIC { 0 } else { self.used[k] };
            let taken = mask(c.a) | mask(c.b);
            let colour = (!taken).trailing_zeros() as usize;
            if colour >= COLOURS {
                self.overflow.push(i);
                continue;
            }
            for k in [c.a, c.b] {
                if k != STATIC {
                    self.used[k] |= 1 << colour;
                }
            }
            self.colours[colour].push(i);
        }
        let wall = bodies;
        // The batches written over last step's in place, every lane and every point a lane's
        // batch reads (its `most`), unused ones as zeros: a batch built afresh and pushed was a
        // memset and a memmove of 1.4 kB each, a tenth of the settled mixed heap's step.
        let count = self.colours.iter().map(|c| c.len().div_ceil(LANES)).sum();
        self.batches.resize_with(count, Batch::default);
        let mut batches = self.batches.iter_mut();
        for colour in &mut self.colours {
            // Contacts of as many points side by side (a stable sort: the order stays the
            // contacts' within a count).
            colour.sort_by_key(|&i| constraints[i].len);
            for chunk in colour.chunks(LANES) {
                let bt = batches.next().expect("counted");
                bt.lanes = chunk.len();
                bt.most = chunk.iter().map(|&i| constraints[i].len).max().unwrap_or(0);
                for l in 0..LANES {
                    bt.fill(l, chunk.get(l).map(|&i| (i, &constraints[i])), wall);
                }
            }
        }
    }

    /// Applies the impulses accumulated so far ([`super::warm_one`], batch by batch).
    pub(super) fn warm_start(&self, constraints: &[Constraint], s: &mut State) {
        for bt in &self.batches {
            warm_batch(bt, s.solids);
        }
        for &i in &self.overflow {
            warm_one(&constraints[i], s);
        }
    }

    /// One pass ([`super::solve_one`]), batch by batch, then the overflow one by one.
    pub(super) fn solve(
        &mut self,
        constraints: &mut [Constraint],
        s: &mut State,
        hs: f64,
        soft: &SoftSettings,
        bias: bool,
    ) {
        for bt in &mut self.batches {
            solve_batch(bt, s.solids, hs, soft, bias);
        }
        for &i in &self.overflow {
            solve_one(&mut constraints[i], s, hs, soft, bias);
        }
    }

    /// The batches' impulses back into their contacts (for restitution, the forces and the
    /// next step's warm start).
    pub(super) fn write_back(&self, constraints: &mut [Constraint]) {
        for bt in &self.batches {
            for l in 0..bt.lanes {
                let c = &mut constraints[bt.constraint[l]];
                c.rolling_impulse = bt.rolling_impulse.0[l];
                for (p, q) in c.points[..c.len].iter_mut().zip(&bt.points) {
                    p.normal_impulse = q.normal_impulse.0[l];
                    p.tangent_impulse = q.tangent_impulse.0[l];
                    p.max_normal_impulse = q.max_normal_impulse.0[l];
                    p.closing = q.closing.0[l];
                }
            }
        }
    }
}

/// One side of each lane's contact, read from its solid.
#[derive(Clone, Copy, Default)]
struct Side {
    vx: W,
    vy: W,
    w: W,
    sx: W,
    sy: W,
    cos: W,
    sin: W,
    m: W,
    i: W,
}

impl Side {
    #[inline(always)]
    fn gather(slots: &[usize; LANES], solids: &[Solid]) -> Side {
        let mut g = Side::default();
        for (l, &k) in slots.iter().enumerate() {
            let s = &solids[k];
            g.vx.0[l] = s.v.x;
            g.vy.0[l] = s.v.y;
            g.w.0[l] = s.w;
            g.sx.0[l] = s.shift.x;
            g.sy.0[l] = s.shift.y;
            g.cos.0[l] = s.turn.cos;
            g.sin.0[l] = s.turn.sin;
            g.m.0[l] = s.inv_mass;
            g.i.0[l] = s.inv_inertia;
        }
        g
    }

    /// How far the point at `(rx, ry)` has moved since the step's start ([`State::moved`]).
    #[inline(always)]
    fn moved(&self, rx: W, ry: W) -> (W, W) {
        (
            (self.sx + (self.cos * rx - self.sin * ry)) - rx,
            (self.sy + (self.sin * rx + self.cos * ry)) - ry,
        )
    }

    /// The velocity of the point at `(rx, ry)` (`v + omega x r`).
    #[inline(always)]
    fn velocity(&self, rx: W, ry: W) -> (W, W) {
        (self.vx + -self.w * ry, self.vy + self.w * rx)
    }

    /// [`State::apply`].
    #[inline(always)]
    fn apply(&mut self, rx: W, ry: W, ix: W, iy: W, sign: f64) {
        let sign = W::splat(sign);
        let k = sign * self.m;
        self.vx = self.vx + ix * k;
        self.vy = self.vy + iy * k;
        self.w = self.w + sign * self.i * (rx * iy - ry * ix);
    }
}

/// Both sides of a batch.
struct Gathered {
    a: Side,
    b: Side,
}

impl Gathered {
    #[inline(always)]
    fn new(bt: &Batch, solids: &[Solid]) -> Self {
        Gathered {
            a: Side::gather(&bt.a, solids),
            b: Side::gather(&bt.b, solids),
        }
    }

    /// The impulse `(ix, iy)` at point `p`: minus on A, plus on B.
    #[inline(always)]
    fn apply(&mut self, p: &PointLanes, ix: W, iy: W) {
        self.a.apply(p.rax, p.ray, ix, iy, -1.0);
        self.b.apply(p.rbx, p.rby, ix, iy, 1.0);
    }

    /// The relative velocity of B's point to A's.
    #[inline(always)]
    fn relative(&self, p: &PointLanes) -> (W, W) {
        let (bx, by) = self.b.velocity(p.rbx, p.rby);
        let (ax, ay) = self.a.velocity(p.rax, p.ray);
        (bx - ax, by - ay)
    }

    /// The velocities back into the solids (the walls' are never written: no lane moves them).
    #[inline(always)]
    fn scatter(&self, bt: &Batch, solids: &mut [Solid]) {
        for l in 0..bt.lanes {
            for (k, side) in [(bt.a[l], &self.a), (bt.b[l], &self.b)] {
                if k < bt.walls {
                    let s = &mut solids[k];
                    s.v.x = side.vx.0[l];
                    s.v.y = side.vy.0[l];
                    s.w = side.w.0[l];
                }
            }
        }
    }
}

/// [`super::warm_one`] for the lanes of a batch.
fn warm_batch(bt: &Batch, solids: &mut [Solid]) {
    let mut g = Gathered::new(bt, solids);
    let (nx, ny) = (bt.nx, bt.ny);
    for p in &bt.points[..bt.most] {
        // `c.normal * ni + t * ti`, t = (n.y, -n.x).
        let ix = nx * p.normal_impulse + ny * p.tangent_impulse;
        let iy = ny * p.normal_impulse + -nx * p.tangent_impulse;
        g.apply(p, ix, iy);
    }
    g.a.w = g.a.w + g.a.i * -bt.rolling_impulse;
    g.b.w = g.b.w + g.b.i * bt.rolling_impulse;
    g.scatter(bt, solids);
}

/// [`super::solve_one`] for the lanes of a batch.
fn solve_batch(bt: &mut Batch, solids: &mut [Solid], hs: f64, soft: &SoftSettings, bias: bool) {
    let mut g = Gathered::new(bt, solids);
    let (nx, ny) = (bt.nx, bt.ny);
    let (zero, one) = (W::splat(0.0), W::splat(1.0));
    let slop = bt.slop;
    for p in &mut bt.points[..bt.most] {
        let (max_, may) = g.a.moved(p.rax, p.ray);
        let (mbx, mby) = g.b.moved(p.rbx, p.rby);
        let sep = (p.base + (nx * (mbx - max_) + ny * (mby - may))) + slop;
        // Apart: the grains may close the gap within the substep, no more; else the soft
        // push-out with `bias`, nothing without.
        let apart = sep.gt(zero);
        let (push, mass_scale, impulse_scale) = if bias {
            (
                apart.select(
                    sep / W::splat(hs),
                    (bt.bias_rate * sep).max(W::splat(-soft.push_out)),
                ),
                apart.select(one, bt.mass_scale),
                apart.select(zero, bt.impulse_scale),
            )
        } else {
            (apart.select(sep / W::splat(hs), zero), one, zero)
        };
        let (rx, ry) = g.relative(p);
        let vn = rx * nx + ry * ny;
        let old = p.normal_impulse;
        let raw = -p.normal_mass * mass_scale * (vn + push) - impulse_scale * old;
        let next = (old + raw).max(zero);
        let d = next - old;
        if bias {
            let pushed = p.max_normal_impulse.gt(zero);
            p.closing = apart.select(pushed.select(p.closing, vn), p.closing);
        }
        p.normal_impulse = next;
        p.max_normal_impulse = p.max_normal_impulse.max(next);
        g.apply(p, nx * d, ny * d);
    }
    let (tx, ty) = (ny, -nx);
    for p in &mut bt.points[..bt.most] {
        let (rx, ry) = g.relative(p);
        let vt = rx * tx + ry * ty;
        let most = bt.friction * p.normal_impulse;
        let old = p.tangent_impulse;
        let next = (old - p.tangent_mass * vt).clamp(-most, most);
        let d = next - old;
        p.tangent_impulse = next;
        g.apply(p, tx * d, ty * d);
    }
    let rolls = bt.rolling_resistance.gt(zero);
    // The sum over each lane's own points (a missing point's impulse stays +0, and adding
    // +0 to a sum of impulses, never -0, changes no bit).
    let total = bt.points[..bt.most]
        .iter()
        .fold(zero, |sum, p| sum + p.normal_impulse);
    let most = bt.rolling_resistance * bt.lever * total;
    let old = bt.rolling_impulse;
    let next = (old - bt.rolling_mass * (g.b.w - g.a.w)).clamp(-most, most);
    let d = next - old;
    bt.rolling_impulse = rolls.select(next, old);
    g.a.w = rolls.select(g.a.w + g.a.i * -d, g.a.w);
    g.b.w = rolls.select(g.b.w + g.b.i * d, g.b.w);
    g.scatter(bt, solids);
}

#[cfg(test)]
mod tests {
    use super::super::{Point, Softness};
    use super::*;
    use crate::geometry::{Rotation, Vec2};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Random contacts among `grains` grains and the walls, each grain with a random motion;
    /// grain 0 touches everything (more contacts than colours: the overflow).
    fn scene(seed: u64, grains: usize, contacts: usize) -> (Vec<Constraint>, Vec<Solid>) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut u = |lo: f64, hi: f64| rng.random_range(lo..hi);
        let mut solids: Vec<Solid> = (0..grains)
            .map(|_| Solid {
                v: Vec2::new(u(-1.0, 1.0), u(-1.0, 1.0)),
                w: u(-3.0, 3.0),
                shift: Vec2::new(u(-1e-3, 1e-3), u(-1e-3, 1e-3)),
                turn: Rotation::new(u(-1e-2, 1e-2)),
                inv_mass: u(0.5, 2.0),
                inv_inertia: u(1.0, 20.0),
            })
            .collect();
        solids.push(Solid::WALL);
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
        let constraints = (0..contacts)
            .map(|i| {
                let a = if i < 70 {
                    0
                } else if rng.random_bool(0.15) {
                    STATIC
                } else {
                    rng.random_range(0..grains)
                };
                let b = loop {
                    let b = rng.random_range(0..grains);
                    if b != a {
                        break b;
                    }
                };
                let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                let mut f = |lo: f64, hi: f64| rng.random_range(lo..hi);
                let mut points = [Point::ZERO; 3];
                let len = 1 + i % 3;
                for (k, p) in points[..len].iter_mut().enumerate() {
                    p.ra = if a == STATIC {
                        Vec2::ZERO
                    } else {
                        Vec2::new(f(-0.3, 0.3), f(-0.3, 0.3))
                    };
                    p.rb = Vec2::new(f(-0.3, 0.3), f(-0.3, 0.3));
                    p.base = f(-0.02, 0.01);
                    p.normal_mass = f(0.1, 1.0);
                    p.tangent_mass = f(0.1, 1.0);
                    p.normal_impulse = f(0.0, 0.05);
                    p.tangent_impulse = f(-0.01, 0.01);
                    p.closing = f(-3.0, 1.0);
                    p.id = k as u8;
                }
                Constraint {
                    a,
                    b,
                    slot_a: a.min(grains),
                    key: (a, b),
                    normal: Vec2::new(angle.cos(), angle.sin()),
                    friction: f(0.0, 1.0),
                    restitution: 0.0,
                    rolling_resistance: if i % 2 == 0 { f(0.0, 0.3) } else { 0.0 },
                    lever: f(0.1, 0.3),
                    slop: if i % 3 == 0 { 0.005 } else { 0.0 },
                    star: i % 3 == 0,
                    rolling_mass: f(0.01, 0.1),
                    rolling_impulse: f(-1e-3, 1e-3),
                    softness: Softness::new(30.0, 10.0, 1.0 / 240.0),
                    points,
                    len,
                }
            })
            .collect();
        (constraints, solids)
    }

    /// The batches give, bit for bit, what the one-contact code gives solving the contacts in
    /// the batches' order: velocities, every impulse and the speeds at impact, through warm
    /// starts and passes with and without the push-out, the overflow included.
    #[test]
    fn batches_solve_as_the_contacts_one_by_one_in_their_order() {
        let soft = SoftSettings::default();
        let hs = 1.0 / 240.0;
        for seed in 0..20 {
            let grains = 40;
            let (mut batched, mut solids) = scene(seed, grains, 300);
            let mut batches = Batches::default();
            batches.build(&batched, grains);
            assert!(
                !batches.overflow.is_empty() && batches.batches.len() > 20,
                "the scene exercises both paths"
            );
            // The reference: the same contacts, reordered as the batches hold them.
            let order: Vec<usize> = batches
                .batches
                .iter()
                .flat_map(|bt| bt.constraint[..bt.lanes].to_vec())
                .chain(batches.overflow.iter().copied())
                .collect();
            assert_eq!(order.len(), batched.len());
            let mut one: Vec<Constraint> = order.iter().map(|&i| batched[i]).collect();
            let mut reference = solids.clone();
            for _ in 0..3 {
                let mut s = State {
                    solids: &mut reference,
                };
                for c in &one {
                    warm_one(c, &mut s);
                }
                for bias in [true, false] {
                    for c in one.iter_mut() {
                        solve_one(c, &mut s, hs, &soft, bias);
                    }
                }
                let mut s = State {
                    solids: &mut solids,
                };
                batches.warm_start(&batched, &mut s);
                for bias in [true, false] {
                    batches.solve(&mut batched, &mut s, hs, &soft, bias);
                }
            }
            batches.write_back(&mut batched);
            for (x, y) in solids.iter().zip(&reference) {
                assert_eq!(
                    (x.v.x.to_bits(), x.v.y.to_bits(), x.w.to_bits()),
                    (y.v.x.to_bits(), y.v.y.to_bits(), y.w.to_bits()),
                    "seed {seed}"
                );
            }
            for (&i, r) in order.iter().zip(&one) {
                let c = &batched[i];
                assert_eq!(c.rolling_impulse.to_bits(), r.rolling_impulse.to_bits());
                for (p, q) in c.points.iter().zip(&r.points) {
                    assert_eq!(
                        (
                            p.normal_impulse.to_bits(),
                            p.tangent_impulse.to_bits(),
                            p.max_normal_impulse.to_bits(),
                            p.closing.to_bits()
                        ),
                        (
                            q.normal_impulse.to_bits(),
                            q.tangent_impulse.to_bits(),
                            q.max_normal_impulse.to_bits(),
                            q.closing.to_bits()
                        ),
                        "seed {seed}"
                    );
                }
            }
        }
    }

    /// No colour holds two contacts of one grain.
    #[test]
    fn a_colour_never_holds_a_grain_twice() {
        let (constraints, _) = scene(3, 40, 300);
        let mut batches = Batches::default();
        batches.build(&constraints, 40);
        for colour in batches.colours.iter() {
            let mut seen = [false; 40];
            for &i in colour {
                for k in [constraints[i].a, constraints[i].b] {
                    if k != STATIC {
                        assert!(!seen[k], "grain {k} twice in a colour");
                        seen[k] = true;
                    }
                }
            }
        }
    }
}

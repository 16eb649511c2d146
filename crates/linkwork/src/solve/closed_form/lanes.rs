//! The closed-form groups of many designs at once, in lanes: a plan of driven cranks on the
//! ground and RRR dyads (a four-bar, a chain of dyads on it) stepped for `LANES` designs of
//! one structure side by side, every body's numbers a lane array. Each lane is its design's
//! step as the scalar engine takes it, operation for operation: `step_positions` as
//! `closed_form::step_guarded` (positions, the closeness checks and trends, the guard from
//! positions; the sweeps use lanes only where positions alone are asked). So its figures
//! are the scalar engine's bit for bit: the lane arithmetic is the same IEEE additions,
//! products, quotients and square roots, and what branches per design (cos and sin turned or in full, an angle by its
//! series or atan2, a missed step) is done per lane by the scalar helpers. Each lane keeps
//! its own branch sign, its own trends and its own first failing step (`sweep::lanes`).
//! The arithmetic runs under the best instruction set the machine has (`pulp`'s runtime
//! dispatch: AVX2 on x86-64, the plain build elsewhere).

use super::guard;
use super::lane_ops::Ops;
pub use super::lane_ops::{LANES, V};
use super::NEAR_SINGULAR;
use crate::constraints::Constraint;
use crate::input::motion::MotionLaw;
use crate::math::angle::{angle_of, turned, SMALL_TURN};
use crate::model::data::Data;
use crate::model::plan::{Block, Link, Plan};
use crate::model::Model;

/// One body's pose in every lane (q and its frame's cos, sin), and each lane's base for
/// turning its cos and sin (`Data::frame_base`).
#[derive(Debug, Clone, Default)]
pub struct BodyLanes {
    pub x: V,
    pub y: V,
    pub th: V,
    pub c: V,
    pub s: V,
    pub base: [[f64; 3]; LANES],
}

/// A body's `guard::Travel` in every lane: its reference point, path and turn bounds.
#[derive(Debug, Clone, Copy, Default)]
struct TravelLanes {
    r: [V; 2],
    len: V,
    turn: V,
}

/// A crank on the ground (its pin's known side and its angle's base the ground), per lane.
#[derive(Debug, Clone, Default)]
struct CrankLanes {
    body: usize,
    sign: V,
    u_body: [V; 2],
    fixed: [V; 2],
}

/// One link of an RRR dyad, per lane: its known side (the same in every lane) and numbers.
#[derive(Debug, Clone, Default)]
struct LinkLanes {
    body: usize,
    known: Option<usize>,
    u_known: [V; 2],
    u_outer: [V; 2],
    u_middle: [V; 2],
    length: V,
    inv_length: V,
    dir: [V; 2],
    fixed: [V; 2],
}

// a few blocks a plan, made once per LANES designs: their sizes do not matter
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
enum BlockLanes {
    Crank(CrankLanes),
    Rrr(LinkLanes, LinkLanes),
}

/// Whether `plan` is one the lanes step: cranks on the ground and RRR dyads of two bodies
/// (no tie rod), at least one dyad, every coordinate a body's.
pub fn fits(model: &Model, plan: &Plan) -> bool {
    model.n_coords == 3 * model.n_bodies
        && plan.blocks.iter().any(|b| matches!(b, Block::Rrr(_)))
        && plan.blocks.iter().all(|b| match b {
            Block::Crank(c) => c.known.is_none() && c.base.is_none(),
            Block::Rrr(r) => !r.rod,
            _ => false,
        })
}

/// The plans' common shape: the same blocks on the same bodies and known sides.
fn same_shape(a: &Plan, b: &Plan) -> bool {
    a.blocks.len() == b.blocks.len()
        && a.blocks.iter().zip(&b.blocks).all(|(x, y)| match (x, y) {
            (Block::Crank(x), Block::Crank(y)) => x.body == y.body,
            (Block::Rrr(x), Block::Rrr(y)) => {
                (x.l1.body, x.l1.known, x.l2.body, x.l2.known)
                    == (y.l1.body, y.l1.known, y.l2.body, y.l2.known)
            }
            _ => false,
        })
}

/// `LANES` designs of one plan shape stepped together: their numbers, state and laws.
#[derive(Debug, Clone)]
pub struct Lanes<'m> {
    blocks: Vec<BlockLanes>,
    /// per block, per lane: the branch sign and closeness trend (`Work::sign`, `close`)
    sign: Vec<V>,
    close: Vec<[V; 2]>,
    pub bodies: Vec<BodyLanes>,
    /// each lane's crank laws, in block order (one per crank)
    laws: Vec<[&'m MotionLaw; LANES]>,
    /// whether every lane's laws are the first lane's (evaluated once a step)
    same_laws: bool,
    inv_l: V,
    /// each coordinate's inverse scale (body-major x, y, theta), per lane
    pub inv_scale: Vec<V>,
    /// per lane: the step's smallest closeness (the pivot ratio the scalar step reports)
    pub ratio: V,
    /// per body: the guard's bounds on its motion over the step (`guard`), per lane
    travel: Vec<TravelLanes>,
    /// per body: whether `step_positions` forms its angle (`keep_angles`; all at first)
    angles: Vec<bool>,
    /// per block: whether a later group reads its bodies' bounds (`closed_form::guard_reads`;
    /// where none does, the dyad's guard is its test alone, as the scalar step's)
    reads: Vec<bool>,
}

impl<'m> Lanes<'m> {
    /// The lanes of `models` (LANES of them; their plans `fits` and of one shape), each
    /// started from its `data` at a solved step (q, frames, the plan's state as
    /// `closed_form::resync` or a step leaves them). None where the plans differ in shape.
    pub fn new(models: [&'m Model; LANES], data: [&Data; LANES]) -> Option<Lanes<'m>> {
        let plans: Vec<&Plan> = models.iter().map(|m| m.plan.as_ref().ok()).collect::<Option<_>>()?;
        if !fits(models[0], plans[0]) || !plans.iter().all(|p| same_shape(plans[0], p)) {
            return None;
        }
        let lane = |f: &dyn Fn(usize) -> f64| -> V { std::array::from_fn(f) };
        let link = |pick: &dyn Fn(usize) -> &'m Link| {
            let l0 = pick(0);
            LinkLanes {
                body: l0.body,
                known: l0.known,
                u_known: [lane(&|j| pick(j).u_known[0]), lane(&|j| pick(j).u_known[1])],
                u_outer: [lane(&|j| pick(j).u_outer[0]), lane(&|j| pick(j).u_outer[1])],
                u_middle: [lane(&|j| pick(j).u_middle[0]), lane(&|j| pick(j).u_middle[1])],
                length: lane(&|j| pick(j).length),
                inv_length: lane(&|j| pick(j).inv_length),
                dir: [lane(&|j| pick(j).dir[0]), lane(&|j| pick(j).dir[1])],
                fixed: [lane(&|j| pick(j).fixed[0]), lane(&|j| pick(j).fixed[1])],
            }
        };
        let mut blocks = Vec::with_capacity(plans[0].blocks.len());
        let mut laws = Vec::new();
        for (i, block) in plans[0].blocks.iter().enumerate() {
            match block {
                Block::Crank(c0) => {
                    let crank = |j: usize| match &plans[j].blocks[i] {
                        Block::Crank(c) => c,
                        _ => unreachable!("the plans are of one shape"),
                    };
                    let law = |j: usize| models[j].constraints[crank(j).driver].kind.law();
                    if (0..LANES).any(|j| law(j).is_none()) {
                        return None;
                    }
                    laws.push(std::array::from_fn(|j| law(j).expect("checked")));
                    blocks.push(BlockLanes::Crank(CrankLanes {
                        body: c0.body,
                        sign: lane(&|j| crank(j).sign),
                        u_body: [lane(&|j| crank(j).u_body[0]), lane(&|j| crank(j).u_body[1])],
                        fixed: [lane(&|j| crank(j).fixed[0]), lane(&|j| crank(j).fixed[1])],
                    }));
                }
                Block::Rrr(_) => {
                    let rrr = |j: usize| match &plans[j].blocks[i] {
                        Block::Rrr(r) => r,
                        _ => unreachable!("the plans are of one shape"),
                    };
                    blocks.push(BlockLanes::Rrr(link(&|j| &rrr(j).l1), link(&|j| &rrr(j).l2)));
                }
                _ => return None,
            }
        }
        let same_laws = laws.iter().all(|l: &[&MotionLaw; LANES]| l.iter().all(|x| *x == l[0]));
        let n_blocks = blocks.len();
        let n_bodies = models[0].n_bodies;
        let bodies = (0..n_bodies)
            .map(|b| {
                let q = |k: usize| lane(&|j| data[j].q[3 * b + k]);
                BodyLanes {
                    x: q(0),
                    y: q(1),
                    th: q(2),
                    c: lane(&|j| data[j].frames[b].c),
                    s: lane(&|j| data[j].frames[b].s),
                    base: std::array::from_fn(|j| data[j].frame_base[b]),
                }
            })
            .collect();
        Some(Lanes {
            blocks,
            sign: (0..n_blocks).map(|i| lane(&|j| data[j].blocks.sign[i])).collect(),
            close: (0..n_blocks)
                .map(|i| [lane(&|j| data[j].blocks.close[i][0]), lane(&|j| data[j].blocks.close[i][1])])
                .collect(),
            bodies,
            laws,
            same_laws,
            inv_l: lane(&|j| 1.0 / models[j].length_scale),
            inv_scale: (0..models[0].n_coords).map(|i| lane(&|j| data[j].inv_col_scale[i])).collect(),
            ratio: [1.0; LANES],
            travel: vec![TravelLanes::default(); n_bodies],
            angles: vec![true; n_bodies],
            reads: super::guard_reads(plans[0], n_bodies),
        })
    }

    /// Only the angles of the bodies whose theta is among `kept` (coordinates, body-major)
    /// formed by `step_positions` from now on: the others' theta is then stale, their cos
    /// and sin (and so their points) still set.
    pub fn keep_angles(&mut self, kept: &[usize]) {
        for (b, angle) in self.angles.iter_mut().enumerate() {
            *angle = kept.contains(&(3 * b + 2));
        }
    }

    /// Step k (time t, h from the last) of positions only in every lane, as
    /// `closed_form::step_guarded`: each group's closeness checks and its guard (`guard`)
    /// in place of rates and the two-way check, on `o`'s registers. Per lane, whether the
    /// step was taken (its figures then the scalar guarded step's, bit for bit: the same
    /// operations). `turns`: the crank's cos and sin of earlier lanes at this step.
    #[inline(always)]
    pub fn step_positions<O: Ops>(
        &mut self,
        o: O,
        t: f64,
        h: f64,
        k: usize,
        turns: &mut Turns,
    ) -> [bool; LANES] {
        let mut bad = o.mask([false; LANES]);
        let mut closeness_min = o.splat(1.0);
        let mut residual = o.splat(0.0);
        let mut crank_index = 0;
        let (hv, quarter, near) = (o.splat(h), o.splat(0.25), o.splat(NEAR_SINGULAR));
        for i in 0..self.blocks.len() {
            let (closeness, res) = match &self.blocks[i] {
                BlockLanes::Crank(c) => {
                    let laws = self.laws[crank_index];
                    let (f, turn): ([f64; LANES], [Option<f64>; LANES]) = if self.same_laws {
                        ([laws[0].eval(t)[0]; LANES], [guard::law_travel(laws[0], h); LANES])
                    } else {
                        (
                            std::array::from_fn(|j| laws[j].eval(t)[0]),
                            std::array::from_fn(|j| guard::law_travel(laws[j], h)),
                        )
                    };
                    let mut missed = [false; LANES];
                    for j in 0..LANES {
                        missed[j] = turn[j].is_none() || !f[j].is_finite();
                    }
                    self.travel[c.body] =
                        TravelLanes { r: c.fixed, len: [0.0; LANES], turn: turn.map(|x| x.unwrap_or(0.0)) };
                    let memo = turns.slot(crank_index, k);
                    crank_index += 1;
                    let (cl, res) = crank_positions(o, c, &mut self.bodies, &f, memo);
                    bad = o.or(bad, o.mask(missed));
                    (cl, res)
                }
                BlockLanes::Rrr(l1, l2) => {
                    let (angles, read) = (&self.angles, self.reads[i]);
                    let travel = &mut self.travel;
                    let (cl, res, b) =
                        rrr_positions(o, l1, l2, &mut self.bodies, travel, &self.sign[i], angles, read);
                    bad = o.or(bad, b);
                    (cl, res)
                }
            };
            let [c1, rate] = self.close[i];
            let (c1, rate) = (o.load(&c1), o.load(&rate));
            let quarter_c1 = o.mul(quarter, c1);
            // the scalar step's checks, in its order: NaN, near singular, the trend
            let b = o.or(
                o.or(o.is_nan(closeness), o.lt(closeness, near)),
                o.or(o.lt(o.add(c1, o.mul(rate, hv)), quarter_c1), o.lt(closeness, quarter_c1)),
            );
            bad = o.or(bad, b);
            self.close[i][1] = o.store(o.div(o.sub(closeness, c1), hv));
            self.close[i][0] = o.store(closeness);
            closeness_min = o.min(closeness_min, closeness);
            residual = o.max(residual, o.mul(res, o.load(&self.inv_l)));
        }
        // not finite: NaN, or at least infinity (|x| >= inf)
        let abs_r = o.abs(residual);
        bad = o.or(bad, o.or(o.is_nan(residual), o.le(o.splat(f64::INFINITY), abs_r)));
        self.ratio = o.store(closeness_min);
        o.bits(bad).map(|b| !b)
    }

    /// Every coordinate (body-major x, y, theta) in every lane, into `q`.
    #[inline(always)]
    pub fn coords(&self, q: &mut [V]) {
        for (b, body) in self.bodies.iter().enumerate() {
            q[3 * b] = body.x;
            q[3 * b + 1] = body.y;
            q[3 * b + 2] = body.th;
        }
    }

    /// A body's frame's cos and sin in every lane (as the groups set them).
    #[inline(always)]
    pub fn cos_sin(&self, b: usize) -> (&V, &V) {
        (&self.bodies[b].c, &self.bodies[b].s)
    }
}

/// The crank's cos and sin at each step, as `turned` gave them to the first lane of the
/// last lanes that took the step: (the angle and the turning base it started from, the
/// cos and sin, the base it left). Designs whose crank turns by one law from one start
/// (an atlas's) take the same angles from the same bases, so each lane after the first
/// four reads `turned`'s result instead of computing it again: the same bits.
#[derive(Debug, Clone, Default)]
pub struct Turns {
    /// per crank (in plan order), per step
    memo: Vec<Vec<Turn>>,
    /// how many steps' cos and sin were read here
    pub hits: usize,
}

/// One step's `turned`: its arguments' bits (angle, base) and its results.
#[derive(Debug, Clone, Copy)]
pub struct Turn {
    key: [u64; 4],
    cs: (f64, f64),
    base: [f64; 3],
}

impl Turns {
    /// The memo of crank `crank` at step k (made as needed; an empty one has a key no
    /// angle's bits match).
    #[inline(always)]
    fn slot(&mut self, crank: usize, k: usize) -> (&mut Turn, &mut usize) {
        if self.memo.len() <= crank {
            self.memo.resize(crank + 1, Vec::new());
        }
        let steps = &mut self.memo[crank];
        if steps.len() <= k {
            steps.resize(k + 1, Turn { key: [u64::MAX; 4], cs: (0.0, 0.0), base: [0.0; 3] });
        }
        (&mut steps[k], &mut self.hits)
    }
}

/// `turned` by way of `memo`: its result where the arguments are the memo's bits, else
/// computed and kept there.
#[inline(always)]
fn turned_memo(theta: f64, base: &mut [f64; 3], memo: &mut Turn, hits: &mut usize) -> (f64, f64) {
    let key = [theta.to_bits(), base[0].to_bits(), base[1].to_bits(), base[2].to_bits()];
    if key == memo.key {
        *base = memo.base;
        *hits += 1;
        return memo.cs;
    }
    let cs = turned(theta, base);
    *memo = Turn { key, cs, base: *base };
    cs
}

/// A crank on the ground in every lane, positions only (`Crank::solve_on::<false, false>`
/// without rates), `f` each lane's law's value at t: (closeness 1, pin residual).
#[inline(always)]
fn crank_positions<O: Ops>(
    o: O,
    c: &CrankLanes,
    bodies: &mut [BodyLanes],
    f: &[f64; LANES],
    (memo, hits): (&mut Turn, &mut usize),
) -> (O::F, O::F) {
    let body = &mut bodies[c.body];
    let theta: V = std::array::from_fn(|j| 0.0 + c.sign[j] * f[j]);
    let (mut cs, mut sn) = ([0.0; LANES], [0.0; LANES]);
    let base0 = body.base[0];
    for j in 0..LANES {
        if j > 0 && theta[j].to_bits() == theta[0].to_bits() && same_bits(&body.base[j], &base0) {
            (cs[j], sn[j]) = (cs[0], sn[0]);
            body.base[j] = body.base[0];
        } else if j == 0 {
            (cs[j], sn[j]) = turned_memo(theta[j], &mut body.base[j], memo, hits);
        } else {
            (cs[j], sn[j]) = turned(theta[j], &mut body.base[j]);
        }
    }
    let (cj, sj) = (o.load(&cs), o.load(&sn));
    let u = [o.load(&c.u_body[0]), o.load(&c.u_body[1])];
    let p = [o.load(&c.fixed[0]), o.load(&c.fixed[1])];
    let arm = [o.sub(o.mul(cj, u[0]), o.mul(sj, u[1])), o.add(o.mul(sj, u[0]), o.mul(cj, u[1]))];
    let r = [o.sub(p[0], arm[0]), o.sub(p[1], arm[1])];
    body.x = o.store(r[0]);
    body.y = o.store(r[1]);
    body.th = theta;
    body.c = cs;
    body.s = sn;
    let back = [o.add(r[0], arm[0]), o.add(r[1], arm[1])];
    let res = o.max(o.abs(o.sub(back[0], p[0])), o.abs(o.sub(back[1], p[1])));
    (o.splat(1.0), res)
}

/// The known side's pin of a link in every lane (`outer`'s position only).
#[inline(always)]
fn outer_p<O: Ops>(o: O, l: &LinkLanes, bodies: &[BodyLanes]) -> [O::F; 2] {
    let Some(kb) = l.known else { return [o.load(&l.fixed[0]), o.load(&l.fixed[1])] };
    let k = &bodies[kb];
    let (u0, u1) = (o.load(&l.u_known[0]), o.load(&l.u_known[1]));
    let (c, s) = (o.load(&k.c), o.load(&k.s));
    let px = o.add(o.load(&k.x), o.sub(o.mul(c, u0), o.mul(s, u1)));
    let py = o.add(o.load(&k.y), o.add(o.mul(s, u0), o.mul(c, u1)));
    [px, py]
}

/// `guard::rrr_margin` in every lane (the same operations): D's distance to the nearer of
/// the dyad's limits, and the links' lengths in order (lo, hi).
#[inline(always)]
fn rrr_margin<O: Ops>(o: O, r1: O::F, r2: O::F, dd: O::F) -> (O::F, O::F, O::F) {
    let d = o.sqrt(dd);
    let (lo, hi) = (o.min(r1, r2), o.max(r1, r2));
    (o.min(o.sub(o.add(r1, r2), d), o.sub(d, o.sub(hi, lo))), lo, hi)
}

/// `guard::rrr_shown` in every lane: whether the step is not shown (a mask).
#[inline(always)]
fn rrr_not_shown<O: Ops>(o: O, r1: O::F, r2: O::F, dd: O::F, l: O::F) -> O::M {
    let (margin, _, _) = rrr_margin(o, r1, r2, dd);
    // NaN fails the comparison: not shown
    o.not(o.le(l, o.mul(o.splat(guard::GUARD), margin)))
}

/// `guard::rrr_turns` in every lane (the same operations): whether the step is not shown
/// (a mask), and the bodies' turn bounds.
#[inline(always)]
fn rrr_turns<O: Ops>(o: O, r1: O::F, r2: O::F, dd: O::F, l: O::F) -> (O::M, O::F, O::F) {
    let two = o.splat(2.0);
    let (margin, lo, hi) = rrr_margin(o, r1, r2, dd);
    // NaN fails the comparison: not shown
    let shown = o.le(l, o.mul(o.splat(guard::GUARD), margin));
    let m = o.sub(margin, l);
    let prod =
        o.mul(o.mul(o.mul(m, o.sub(o.mul(two, lo), m)), o.mul(two, hi)), o.add(o.mul(two, o.sub(hi, lo)), m));
    let sin = o.div(o.sqrt(prod), o.mul(o.mul(two, r1), r2));
    (o.not(shown), o.div(l, o.mul(r1, sin)), o.div(l, o.mul(r2, sin)))
}

/// A bound on the path of the pins at `p` of a body moving within `t` (`Travel::pin`).
#[inline(always)]
fn pin<O: Ops>(o: O, t: &TravelLanes, p: &[O::F; 2]) -> O::F {
    let d = [o.sub(p[0], o.load(&t.r[0])), o.sub(p[1], o.load(&t.r[1]))];
    o.add(o.load(&t.len), o.mul(o.sqrt(o.add(o.mul(d[0], d[0]), o.mul(d[1], d[1]))), o.load(&t.turn)))
}

/// An RRR dyad's positions in every lane (`Rrr::solve_on` without rates) and its guard
/// (`Rrr::solve_guarded`: its bodies' bounds only where a later group reads them, `read`),
/// each lane's failing guard a miss: (closeness, residual, the lanes missed).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn rrr_positions<O: Ops>(
    o: O,
    l1: &LinkLanes,
    l2: &LinkLanes,
    bodies: &mut [BodyLanes],
    travel: &mut [TravelLanes],
    sign: &V,
    angles: &[bool],
    read: bool,
) -> (O::F, O::F, O::M) {
    let (pa, pc) = (outer_p(o, l1, bodies), outer_p(o, l2, bodies));
    let (r1, r2) = (o.load(&l1.length), o.load(&l2.length));
    let d = [o.sub(pc[0], pa[0]), o.sub(pc[1], pa[1])];
    let dd = o.add(o.mul(d[0], d[0]), o.mul(d[1], d[1]));
    let zero = o.splat(0.0);
    let mut bad = o.or(o.is_nan(dd), o.le(dd, zero));
    let inv_dd = o.div(o.splat(1.0), dd);
    let along = o.mul(o.mul(o.splat(0.5), o.sub(o.add(dd, o.mul(r1, r1)), o.mul(r2, r2))), inv_dd);
    let h2 = o.sub(o.mul(o.mul(r1, r1), inv_dd), o.mul(along, along));
    bad = o.or(bad, o.or(o.is_nan(h2), o.lt(h2, zero)));
    let height = o.mul(o.load(sign), o.sqrt(h2));
    let b = [
        o.sub(o.add(pa[0], o.mul(along, d[0])), o.mul(height, d[1])),
        o.add(o.add(pa[1], o.mul(along, d[1])), o.mul(height, d[0])),
    ];
    let closeness = o.mul(o.mul(o.mul(o.abs(height), dd), o.load(&l1.inv_length)), o.load(&l2.inv_length));
    // the guard, from the known sides' bounds (read before this dyad's bodies are written)
    let la = l1.known.map_or(zero, |k| pin(o, &travel[k], &pa));
    let lc = l2.known.map_or(zero, |k| pin(o, &travel[k], &pc));
    if read {
        let (not_shown, t1, t2) = rrr_turns(o, r1, r2, dd, o.add(la, lc));
        bad = o.or(bad, not_shown);
        travel[l1.body] =
            TravelLanes { r: [o.store(pa[0]), o.store(pa[1])], len: o.store(la), turn: o.store(t1) };
        travel[l2.body] =
            TravelLanes { r: [o.store(pc[0]), o.store(pc[1])], len: o.store(lc), turn: o.store(t2) };
    } else {
        bad = o.or(bad, rrr_not_shown(o, r1, r2, dd, o.add(la, lc)));
    }
    let res1 = place_with(o, l1, &mut bodies[l1.body], &pa, &b, angles[l1.body]);
    let res2 = place_with(o, l2, &mut bodies[l2.body], &pc, &b, angles[l2.body]);
    (closeness, o.max(res1, res2), bad)
}

/// Whether two turning bases are the same bits (then the same angle turns the same).
#[inline(always)]
fn same_bits(a: &[f64; 3], b: &[f64; 3]) -> bool {
    a.map(f64::to_bits) == b.map(f64::to_bits)
}

/// A link's body from its outer pin at `a` and middle pin at `b` in every lane
/// (`Link::place`), the body's angle formed only with `angle` (else theta is left as it was: a
/// positions-only sweep that keeps no angle of the body needs only its cos and sin).
#[inline(always)]
fn place_with<O: Ops>(
    o: O,
    l: &LinkLanes,
    body: &mut BodyLanes,
    a: &[O::F; 2],
    b: &[O::F; 2],
    angle: bool,
) -> O::F {
    let inv = o.load(&l.inv_length);
    let w = [o.mul(o.sub(b[0], a[0]), inv), o.mul(o.sub(b[1], a[1]), inv)];
    let dir = [o.load(&l.dir[0]), o.load(&l.dir[1])];
    let c = o.add(o.mul(dir[0], w[0]), o.mul(dir[1], w[1]));
    let s = o.sub(o.mul(dir[0], w[1]), o.mul(dir[1], w[0]));
    let (uo, um) =
        ([o.load(&l.u_outer[0]), o.load(&l.u_outer[1])], [o.load(&l.u_middle[0]), o.load(&l.u_middle[1])]);
    let arm = [o.sub(o.mul(c, uo[0]), o.mul(s, uo[1])), o.add(o.mul(s, uo[0]), o.mul(c, uo[1]))];
    let r = [o.sub(a[0], arm[0]), o.sub(a[1], arm[1])];
    let (cs, sn) = (o.store(c), o.store(s));
    if angle {
        body_angle(body, &cs, &sn);
    }
    body.x = o.store(r[0]);
    body.y = o.store(r[1]);
    body.c = cs;
    body.s = sn;
    let rot = [o.sub(o.mul(c, um[0]), o.mul(s, um[1])), o.add(o.mul(s, um[0]), o.mul(c, um[1]))];
    let m = [o.add(r[0], rot[0]), o.add(r[1], rot[1])];
    o.max(o.abs(o.sub(m[0], b[0])), o.abs(o.sub(m[1], b[1])))
}

/// A body's angle in every lane from its cos and sin, continued from its last (`angle_of`).
#[inline(always)]
fn body_angle(body: &mut BodyLanes, cs: &V, sn: &V) {
    // the angle per lane: `angle_of`'s series from the base in every lane at once (the same
    // operations), and `angle_of` itself (atan2) in a lane the series does not serve
    let mut series = [0.0; LANES];
    let mut served = [false; LANES];
    for j in 0..LANES {
        let [theta0, c0, s0] = body.base[j];
        let (c, s) = (cs[j], sn[j]);
        let (cd, sd) = (c0 * c + s0 * s, c0 * s - s0 * c);
        let x = sd / cd;
        let (x2, x4) = (x * x, x * x * (x * x));
        let d = x * ((1.0 - x2 * (1.0 / 3.0)) + x4 * ((1.0 / 5.0 - x2 * (1.0 / 7.0)) + x4 * (1.0 / 9.0)));
        series[j] = theta0 + d;
        served[j] =
            cd > 0.0 && sd.abs() < SMALL_TURN * cd && (series[j] - body.th[j]).abs() <= std::f64::consts::PI;
    }
    for j in 0..LANES {
        body.th[j] =
            if served[j] { series[j] } else { angle_of(cs[j], sn[j], body.th[j], &mut body.base[j]) };
    }
}

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

use super::guard::{self, Travel};
use super::NEAR_SINGULAR;
use crate::constraints::Constraint;
use crate::input::motion::MotionLaw;
use crate::math::angle::{angle_of, turned, SMALL_TURN};
use crate::model::data::Data;
use crate::model::plan::{Block, Link, Plan};
use crate::model::Model;

/// Designs stepped side by side (AVX2 holds four f64).
pub const LANES: usize = 4;
/// One number in every lane.
pub type V = [f64; LANES];

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
    /// per body, per lane: the guard's bounds on its motion over the step (`guard`)
    travel: Vec<[Travel; LANES]>,
    /// per body: whether `step_positions` forms its angle (`keep_angles`; all at first)
    angles: Vec<bool>,
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
            travel: vec![[Travel::default(); LANES]; n_bodies],
            angles: vec![true; n_bodies],
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

    /// Step t of positions only in every lane, as `closed_form::step_guarded`: each group's
    /// closeness checks and its guard (`guard`) in place of rates and the two-way check.
    /// Per lane, whether the step was taken (its figures then the scalar guarded step's,
    /// bit for bit: the same operations).
    #[inline(always)]
    pub fn step_positions(&mut self, t: f64, h: f64) -> [bool; LANES] {
        let mut ok = [true; LANES];
        let mut closeness_min = [1.0f64; LANES];
        let mut residual = [0.0f64; LANES];
        let mut crank_index = 0;
        for i in 0..self.blocks.len() {
            let (closeness, res) = match &self.blocks[i] {
                BlockLanes::Crank(c) => {
                    let laws = self.laws[crank_index];
                    crank_index += 1;
                    let (f, turn): ([f64; LANES], [Option<f64>; LANES]) = if self.same_laws {
                        ([laws[0].eval(t)[0]; LANES], [guard::law_travel(laws[0], h); LANES])
                    } else {
                        (
                            std::array::from_fn(|j| laws[j].eval(t)[0]),
                            std::array::from_fn(|j| guard::law_travel(laws[j], h)),
                        )
                    };
                    for j in 0..LANES {
                        ok[j] &= turn[j].is_some();
                        let r = [c.fixed[0][j], c.fixed[1][j]];
                        self.travel[c.body][j] = Travel { r, len: 0.0, turn: turn[j].unwrap_or(0.0) };
                    }
                    crank_positions(c, &mut self.bodies, &f, &mut ok)
                }
                BlockLanes::Rrr(l1, l2) => {
                    let angles = &self.angles;
                    rrr_positions(l1, l2, &mut self.bodies, &mut self.travel, &self.sign[i], angles, &mut ok)
                }
            };
            let [c1, rate] = self.close[i];
            for j in 0..LANES {
                let cl = closeness[j];
                ok[j] &= !(cl.is_nan()
                    || cl < NEAR_SINGULAR
                    || c1[j] + rate[j] * h < 0.25 * c1[j]
                    || cl < 0.25 * c1[j]);
                self.close[i][1][j] = (cl - c1[j]) / h;
                self.close[i][0][j] = cl;
                closeness_min[j] = closeness_min[j].min(cl);
                residual[j] = residual[j].max(res[j] * self.inv_l[j]);
            }
        }
        for j in 0..LANES {
            ok[j] &= residual[j].is_finite();
        }
        self.ratio = closeness_min;
        ok
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

/// A crank on the ground in every lane, positions only (`Crank::solve_on::<false, false>`
/// without rates), `f` each lane's law's value at t: (closeness 1, pin residual).
#[inline(always)]
fn crank_positions(
    c: &CrankLanes,
    bodies: &mut [BodyLanes],
    f: &[f64; LANES],
    ok: &mut [bool; LANES],
) -> (V, V) {
    let body = &mut bodies[c.body];
    let mut theta = [0.0; LANES];
    for j in 0..LANES {
        ok[j] &= f[j].is_finite();
        theta[j] = 0.0 + c.sign[j] * f[j];
    }
    let (mut cs, mut sn) = ([0.0; LANES], [0.0; LANES]);
    let base0 = body.base[0];
    for j in 0..LANES {
        if j > 0 && theta[j].to_bits() == theta[0].to_bits() && same_bits(&body.base[j], &base0) {
            (cs[j], sn[j]) = (cs[0], sn[0]);
            body.base[j] = body.base[0];
        } else {
            (cs[j], sn[j]) = turned(theta[j], &mut body.base[j]);
        }
    }
    let mut res = [0.0; LANES];
    for j in 0..LANES {
        let (cj, sj, u) = (cs[j], sn[j], [c.u_body[0][j], c.u_body[1][j]]);
        let p = [c.fixed[0][j], c.fixed[1][j]];
        let arm = [cj * u[0] - sj * u[1], sj * u[0] + cj * u[1]];
        let r = [p[0] - arm[0], p[1] - arm[1]];
        body.x[j] = r[0];
        body.y[j] = r[1];
        body.th[j] = theta[j];
        body.c[j] = cj;
        body.s[j] = sj;
        let back = [r[0] + arm[0], r[1] + arm[1]];
        res[j] = (back[0] - p[0]).abs().max((back[1] - p[1]).abs());
    }
    ([1.0; LANES], res)
}

/// The known side's pin of a link in every lane (`outer`'s position only).
#[inline(always)]
fn outer_p(l: &LinkLanes, bodies: &[BodyLanes]) -> [V; 2] {
    let Some(kb) = l.known else { return l.fixed };
    let k = &bodies[kb];
    let u = &l.u_known;
    let px: V = std::array::from_fn(|j| k.x[j] + (k.c[j] * u[0][j] - k.s[j] * u[1][j]));
    let py: V = std::array::from_fn(|j| k.y[j] + (k.s[j] * u[0][j] + k.c[j] * u[1][j]));
    [px, py]
}

/// An RRR dyad's positions in every lane (`Rrr::solve_on` without rates) and its guard
/// (`closed_form::guard_block`), each lane's failing guard a miss: (closeness, residual).
#[inline(always)]
fn rrr_positions(
    l1: &LinkLanes,
    l2: &LinkLanes,
    bodies: &mut [BodyLanes],
    travel: &mut [[Travel; LANES]],
    sign: &V,
    angles: &[bool],
    ok: &mut [bool; LANES],
) -> (V, V) {
    let (pa, pc) = (outer_p(l1, bodies), outer_p(l2, bodies));
    let mut b = [[0.0; LANES]; 2];
    let (mut closeness, mut dds) = ([0.0; LANES], [0.0; LANES]);
    for j in 0..LANES {
        let (a, c) = ([pa[0][j], pa[1][j]], [pc[0][j], pc[1][j]]);
        let (r1, r2) = (l1.length[j], l2.length[j]);
        let d = [c[0] - a[0], c[1] - a[1]];
        let dd = d[0] * d[0] + d[1] * d[1];
        ok[j] &= !(dd.is_nan() || dd <= 0.0);
        let inv_dd = 1.0 / dd;
        let along = 0.5 * (dd + r1 * r1 - r2 * r2) * inv_dd;
        let h2 = r1 * r1 * inv_dd - along * along;
        ok[j] &= !(h2.is_nan() || h2 < 0.0);
        let height = sign[j] * h2.sqrt();
        b[0][j] = a[0] + along * d[0] - height * d[1];
        b[1][j] = a[1] + along * d[1] + height * d[0];
        closeness[j] = height.abs() * dd * l1.inv_length[j] * l2.inv_length[j];
        dds[j] = dd;
    }
    // the guard, from the known sides' bounds (read before this dyad's bodies are written)
    for j in 0..LANES {
        let (a, c) = ([pa[0][j], pa[1][j]], [pc[0][j], pc[1][j]]);
        let la = l1.known.map_or(0.0, |k| travel[k][j].pin(a));
        let lc = l2.known.map_or(0.0, |k| travel[k][j].pin(c));
        let (shown, t1, t2) = guard::rrr_turns(l1.length[j], l2.length[j], dds[j], la + lc);
        ok[j] &= shown;
        travel[l1.body][j] = Travel { r: a, len: la, turn: t1 };
        travel[l2.body][j] = Travel { r: c, len: lc, turn: t2 };
    }
    let res1 = place_with(l1, &mut bodies[l1.body], &pa, &b, angles[l1.body]);
    let res2 = place_with(l2, &mut bodies[l2.body], &pc, &b, angles[l2.body]);
    let mut res = [0.0; LANES];
    for j in 0..LANES {
        res[j] = res1[j].max(res2[j]);
    }
    (closeness, res)
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
fn place_with(l: &LinkLanes, body: &mut BodyLanes, a: &[V; 2], b: &[V; 2], angle: bool) -> V {
    let (mut cs, mut sn) = ([0.0; LANES], [0.0; LANES]);
    for j in 0..LANES {
        let w = [(b[0][j] - a[0][j]) * l.inv_length[j], (b[1][j] - a[1][j]) * l.inv_length[j]];
        cs[j] = l.dir[0][j] * w[0] + l.dir[1][j] * w[1];
        sn[j] = l.dir[0][j] * w[1] - l.dir[1][j] * w[0];
    }
    if angle {
        body_angle(body, &cs, &sn);
    }
    let mut res = [0.0; LANES];
    for j in 0..LANES {
        let (c, s) = (cs[j], sn[j]);
        let (uo, um) = ([l.u_outer[0][j], l.u_outer[1][j]], [l.u_middle[0][j], l.u_middle[1][j]]);
        let arm = [c * uo[0] - s * uo[1], s * uo[0] + c * uo[1]];
        let r = [a[0][j] - arm[0], a[1][j] - arm[1]];
        body.x[j] = r[0];
        body.y[j] = r[1];
        body.c[j] = c;
        body.s[j] = s;
        let rot = [c * um[0] - s * um[1], s * um[0] + c * um[1]];
        let m = [r[0] + rot[0], r[1] + rot[1]];
        res[j] = (m[0] - b[0][j]).abs().max((m[1] - b[1][j]).abs());
    }
    res
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

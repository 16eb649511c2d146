//! The sensitivities at one step, from the factorization of Phi_q there.
//!
//! With S = dq/dp, differentiating Phi(q(t, p), p, t) = 0 in p gives
//! psi(t) = Phi_q S + Phi_p = 0 at every t, hence psi' = psi'' = 0 too:
//!   Phi_q S   = -Phi_p
//!   Phi_q S'  = -(Phi_q' S + Phi_p')
//!   Phi_q S'' = -(2 Phi_q' S' + Phi_q'' S + Phi_p'')
//! (' the time derivative along the motion). Each joint's rows over jets (`phi_jet`) give
//! these exactly, once per step: in its coordinates' directions, the blocks of Phi_q'
//! and Phi_q'' / 2 (n_rows x 7 per joint: side a's x, y, theta, side b's, the extra
//! coordinate); in the parameters' directions (W at a time, only the joints they move),
//! Phi_p, Phi_p' and Phi_p'' / 2. Each parameter then costs three solves with the one
//! factorization and two sparse products.

use super::jet::{Jet, JetFrame};
use crate::constraints::{Constraint, MAX_ROWS};
use crate::model::data::Data;
use crate::model::params::{values, Parameter};
use crate::model::{ConstraintEntry, Model};

/// Parameter directions carried by one pass of jets.
pub const W: usize = 4;
/// Coordinate directions of one joint: side a's x, y, theta, side b's, the extra one.
const WC: usize = 7;

/// A body point whose position sensitivities are wanted: its body (None: the ground),
/// its local coordinates, and the named point it is, if it is one (a parameter may move
/// a named point's local coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointRequest {
    pub body: Option<usize>,
    pub local: [f64; 2],
    pub named: Option<usize>,
}

/// W parameters (the last chunk may have fewer): the constraints' numbers as jets, each
/// perturbed along the chunk's directions.
struct Chunk {
    first: usize,
    len: usize,
    /// per constraint moved by a parameter of the chunk: (its index, its numbers as jets)
    moved: Vec<(usize, Vec<Jet<W>>)>,
}

/// A constraint's numbers as constant jets, one lane per coordinate direction it has.
pub(super) enum Consts {
    W3(Vec<Jet<3>>),
    W4(Vec<Jet<4>>),
    W6(Vec<Jet<6>>),
    W7(Vec<Jet<WC>>),
}

impl Consts {
    /// Per constraint: its numbers `vals` as constant jets as wide as its columns `cols`.
    pub(super) fn of(vals: &[Vec<f64>], cols: &[Vec<usize>]) -> Vec<Consts> {
        fn jets<const WL: usize>(v: &[f64]) -> Vec<Jet<WL>> {
            v.iter().map(|&x| Jet::cst(x)).collect()
        }
        vals.iter()
            .zip(cols)
            .map(|(v, cols)| match cols.len() {
                3 => Consts::W3(jets(v)),
                4 => Consts::W4(jets(v)),
                6 => Consts::W6(jets(v)),
                _ => Consts::W7(jets(v)),
            })
            .collect()
    }
}

/// Per constraint: the column of each of its coordinate directions, in lane order (side
/// a's x, y, theta if it moves, side b's, its extra coordinate).
pub(super) fn coordinate_columns(model: &Model) -> Vec<Vec<usize>> {
    model
        .constraints
        .iter()
        .map(|c| {
            let side = |b: Option<usize>| b.into_iter().flat_map(|b| [3 * b, 3 * b + 1, 3 * b + 2]);
            side(c.body_a).chain(side(c.body_b)).chain(c.extra).collect()
        })
        .collect()
}

/// What one step needs, prepared once for a model, parameters and points; with the
/// per-step scratch, so a sweep allocates nothing per step.
pub struct Sensitivity {
    pub n_params: usize,
    pub points: Vec<PointRequest>,
    chunks: Vec<Chunk>,
    /// per constraint: its numbers as constant jets as wide as its coordinate directions
    /// (3 per moving side, 1 for an extra coordinate), for its Phi_q' and Phi_q''
    consts: Vec<Consts>,
    /// per constraint: the column of each of its coordinate directions, in lane order
    cols: Vec<Vec<usize>>,
    /// per point request, d local / d parameter (n_params)
    point_seeds: Vec<Vec<[f64; 2]>>,
    /// n_bodies: the bodies' motions, in their own coordinates' directions
    frames: Vec<JetFrame<3>>,
    /// n_rows x n_params: Phi_p, Phi_p', Phi_p'' / 2
    p0: Vec<f64>,
    p1: Vec<f64>,
    p2: Vec<f64>,
    /// the nonzero entries (row, column, value) of Phi_q' and Phi_q'' / 2 at the step
    m1_entries: Vec<(u32, u32, f64)>,
    m2_entries: Vec<(u32, u32, f64)>,
    /// n_rows x n_params: right-hand sides, solved in place; and the solver's scratch
    rhs: Vec<f64>,
    scratch: Vec<f64>,
    /// n_coords x n_params: S, S', S''
    s: Vec<f64>,
    sd: Vec<f64>,
    sdd: Vec<f64>,
}

/// Row-major outputs of one step: (n_coords x n_params) each, and the points'
/// (n_points x 2 x n_params) position, velocity and acceleration sensitivities.
pub struct StepOut<'a> {
    pub dq: &'a mut [f64],
    pub dqd: &'a mut [f64],
    pub dqdd: &'a mut [f64],
    pub points: &'a mut [f64],
    pub points_d: &'a mut [f64],
    pub points_dd: &'a mut [f64],
}

/// A jet frame of `f`'s lanes placed at lanes `at..at + 3` of a wider one.
#[inline(always)]
pub(super) fn widen<const WL: usize>(f: &JetFrame<3>, at: usize) -> JetFrame<WL> {
    let w = |x: &Jet<3>| {
        let mut y = Jet::<WL> { v: x.v, e: [[0.0; 3]; WL] };
        y.e[at..at + 3].copy_from_slice(&x.e);
        y
    };
    JetFrame { r: [w(&f.r[0]), w(&f.r[1])], theta: w(&f.theta), c: w(&f.c), s: w(&f.s) }
}

/// The frame of `f` without perturbations, W lanes wide.
#[inline(always)]
fn plain(f: &JetFrame<3>) -> JetFrame<W> {
    let w = |x: &Jet<3>| Jet::<W> { v: x.v, e: [[0.0; 3]; W] };
    JetFrame { r: [w(&f.r[0]), w(&f.r[1])], theta: w(&f.theta), c: w(&f.c), s: w(&f.s) }
}

/// One entry of Phi_q' or Phi_q''/2: row, column, value.
type JacobianEntry = (u32, u32, f64);

impl Sensitivity {
    pub fn new(model: &Model, params: &[Parameter], points: &[PointRequest]) -> Sensitivity {
        let vals = values(model);
        let mut chunks = Vec::new();
        for first in (0..params.len()).step_by(W) {
            let len = W.min(params.len() - first);
            let mut moved: Vec<(usize, Vec<Jet<W>>)> = Vec::new();
            for k in 0..len {
                for &(c, i, d) in &params[first + k].seeds {
                    let at = match moved.iter().position(|(m, _)| *m == c) {
                        Some(at) => at,
                        None => {
                            moved.push((c, vals[c].iter().map(|&x| Jet::cst(x)).collect()));
                            moved.len() - 1
                        }
                    };
                    moved[at].1[i].e[k][0] += d;
                }
            }
            chunks.push(Chunk { first, len, moved });
        }
        let cols = coordinate_columns(model);
        let consts = Consts::of(&vals, &cols);
        let point_seeds = points
            .iter()
            .map(|r| {
                params
                    .iter()
                    .map(|p| {
                        p.points
                            .iter()
                            .filter(|(k, _)| r.named == Some(*k))
                            .fold([0.0; 2], |a, (_, d)| [a[0] + d[0], a[1] + d[1]])
                    })
                    .collect()
            })
            .collect();
        let (nc, nr, n) = (model.n_coords, model.n_rows, params.len());
        Sensitivity {
            n_params: n,
            points: points.to_vec(),
            chunks,
            consts,
            cols,
            point_seeds,
            frames: vec![JetFrame::ground(); model.n_bodies],
            p0: vec![0.0; n * nr],
            p1: vec![0.0; n * nr],
            p2: vec![0.0; n * nr],
            m1_entries: Vec::with_capacity(model.n_rows * WC),
            m2_entries: Vec::with_capacity(model.n_rows * WC),
            rhs: vec![0.0; n * nr],
            scratch: vec![0.0; n * nr],
            s: vec![0.0; n * nc],
            sd: vec![0.0; n * nc],
            sdd: vec![0.0; n * nc],
        }
    }

    /// The bodies' motions (data's q, qd, qdd) as jets in their own coordinates.
    fn update_frames(&mut self, data: &Data) {
        for (i, frame) in self.frames.iter_mut().enumerate() {
            let x = [0, 1, 2].map(|j| {
                let k = 3 * i + j;
                let mut x = Jet::<3> { v: [data.q[k], data.qd[k], 0.5 * data.qdd[k]], e: [[0.0; 3]; 3] };
                x.e[j][0] = 1.0;
                x
            });
            // cos and sin as the position solve left them (data.frames, at data.q)
            let f = &data.frames[i];
            *frame = JetFrame::with_cos_sin(x, f.c, f.s);
        }
    }

    /// Phi_q' and Phi_q'' / 2, joint by joint, each in its own coordinates' directions.
    fn rates_of_phi_q(&mut self, model: &Model, data: &Data, t: f64) {
        self.m1_entries.clear();
        self.m2_entries.clear();
        for (ci, c) in model.constraints.iter().enumerate() {
            let (f, cols) = (&self.frames, &self.cols[ci]);
            let (m1, m2) = (&mut self.m1_entries, &mut self.m2_entries);
            match &self.consts[ci] {
                Consts::W3(p) => rates_one(c, f, data, t, p, cols, m1, m2),
                Consts::W4(p) => rates_one(c, f, data, t, p, cols, m1, m2),
                Consts::W6(p) => rates_one(c, f, data, t, p, cols, m1, m2),
                Consts::W7(p) => rates_one(c, f, data, t, p, cols, m1, m2),
            }
        }
    }

    /// Phi_p, Phi_p' and Phi_p'' / 2 of every parameter, from the joints it moves.
    fn rates_of_phi_p(&mut self, model: &Model, data: &Data, t: f64) {
        let n = self.n_params;
        self.p0.fill(0.0);
        self.p1.fill(0.0);
        self.p2.fill(0.0);
        for chunk in &self.chunks {
            for (ci, p) in &chunk.moved {
                let c = &model.constraints[*ci];
                let a = c.body_a.map_or_else(JetFrame::ground, |i| plain(&self.frames[i]));
                let b = c.body_b.map_or_else(JetFrame::ground, |i| plain(&self.frames[i]));
                let s = match c.extra {
                    Some(k) => Jet::<W> { v: [data.q[k], data.qd[k], 0.5 * data.qdd[k]], e: [[0.0; 3]; W] },
                    None => Jet::ZERO,
                };
                let mut out = [Jet::ZERO; MAX_ROWS];
                c.kind.phi_jet(&a, &b, s, t, p, &mut out);
                for i in 0..c.n_rows {
                    for d in 0..chunk.len {
                        let at = (c.row0 + i) * n + chunk.first + d;
                        self.p0[at] += out[i].e[d][0];
                        self.p1[at] += out[i].e[d][1];
                        self.p2[at] += out[i].e[d][2];
                    }
                }
            }
        }
    }

    /// For every parameter k at once: x_k = -factor Phi_q^-1 (p_k + the products of
    /// Phi_q' and Phi_q'' / 2 with what the earlier levels solved), the rows scaled for the
    /// solver and the solution unscaled.
    fn stage(&mut self, model: &Model, data: &mut Data, level: usize, factor: f64) {
        let n = self.n_params;
        let p = [&self.p0, &self.p1, &self.p2][level];
        self.rhs.copy_from_slice(p);
        let terms: &[(&[JacobianEntry], &[f64])] = match level {
            0 => &[],
            1 => &[(&self.m1_entries, &self.s)],
            _ => &[(&self.m2_entries, &self.s), (&self.m1_entries, &self.sd)],
        };
        for (entries, v) in terms {
            for &(row, col, m) in entries.iter() {
                let (row, col) = (row as usize * n, col as usize * n);
                for (r, x) in self.rhs[row..row + n].iter_mut().zip(&v[col..col + n]) {
                    *r += m * x;
                }
            }
        }
        for c in &model.constraints {
            for i in 0..c.n_rows {
                let scale = -factor * c.row_scale[i];
                let row = (c.row0 + i) * n;
                for r in &mut self.rhs[row..row + n] {
                    *r *= scale;
                }
            }
        }
        data.factor.solve_many(&model.symbolic, &mut self.rhs, n, &mut self.scratch);
        let x = match level {
            0 => &mut self.s,
            1 => &mut self.sd,
            _ => &mut self.sdd,
        };
        for ((x, r), s) in x.chunks_exact_mut(n).zip(self.rhs.chunks_exact(n)).zip(&model.col_scale) {
            for (x, r) in x.iter_mut().zip(r) {
                *x = r * s;
            }
        }
    }

    /// S, S', S'' (and the points') at the step data holds: data.q, qd, qdd solved at t
    /// and Phi_q factored at data.q (in data.factor).
    pub fn step(&mut self, model: &Model, data: &mut Data, t: f64, out: StepOut) {
        self.step_to(model, data, t, 2, out);
    }

    /// `step` up to the derivative `derivatives`: 0 S (out.dq, out.points), 1 and S'
    /// (out.dqd, out.points_d), 2 and S''; the outputs of the others are not touched
    /// (they may be empty), nor are data.qd (data.qdd) read below 1 (2).
    pub fn step_to(&mut self, model: &Model, data: &mut Data, t: f64, derivatives: u8, out: StepOut) {
        let n = self.n_params;
        if n == 0 {
            return;
        }
        self.update_frames(data);
        if derivatives >= 1 {
            self.rates_of_phi_q(model, data, t);
        }
        self.rates_of_phi_p(model, data, t);
        self.stage(model, data, 0, 1.0);
        out.dq.copy_from_slice(&self.s);
        if derivatives >= 1 {
            self.stage(model, data, 1, 1.0);
            out.dqd.copy_from_slice(&self.sd);
        }
        if derivatives >= 2 {
            self.stage(model, data, 2, 2.0);
            out.dqdd.copy_from_slice(&self.sdd);
        }
        for (r, req) in self.points.iter().enumerate() {
            for k in 0..n {
                let du = self.point_seeds[r][k];
                let (d, dd, ddd) = point_sensitivity(req, data, du, k, n, &self.s, &self.sd, &self.sdd);
                for axis in 0..2 {
                    let at = (r * 2 + axis) * n + k;
                    out.points[at] = d[axis];
                    if derivatives >= 1 {
                        out.points_d[at] = dd[axis];
                    }
                    if derivatives >= 2 {
                        out.points_dd[at] = ddd[axis];
                    }
                }
            }
        }
    }

    /// The points' position sensitivities (n_points x 2 x n_params) from S = `dq` (n_coords
    /// x n_params) at data.q (its frames current): dr = dR + B u dtheta + A du.
    pub fn points_of(&self, data: &Data, dq: &[f64], points: &mut [f64]) {
        let n = self.n_params;
        for (r, req) in self.points.iter().enumerate() {
            for k in 0..n {
                let du = self.point_seeds[r][k];
                let d = match req.body {
                    None => du,
                    Some(b) => {
                        let f = &data.frames[b];
                        let dth = dq[(3 * b + 2) * n + k];
                        let (bu, adu) = (f.rot_d(req.local), f.rot(du));
                        [0, 1].map(|i| dq[(3 * b + i) * n + k] + bu[i] * dth + adu[i])
                    }
                };
                points[r * 2 * n + k] = d[0];
                points[(r * 2 + 1) * n + k] = d[1];
            }
        }
    }
}

/// One constraint's rows on jets in the WL directions of its coordinates (side a's x,
/// y, theta if it moves, side b's, its extra coordinate), their entries of Phi_q' and
/// Phi_q'' / 2 pushed as (row, column, value).
#[allow(clippy::too_many_arguments)]
#[inline]
fn rates_one<const WL: usize>(
    c: &ConstraintEntry,
    frames: &[JetFrame<3>],
    data: &Data,
    t: f64,
    consts: &[Jet<WL>],
    cols: &[usize],
    m1: &mut Vec<(u32, u32, f64)>,
    m2: &mut Vec<(u32, u32, f64)>,
) {
    let b_at = if c.body_a.is_some() { 3 } else { 0 };
    let a = c.body_a.map_or_else(JetFrame::ground, |i| widen(&frames[i], 0));
    let b = c.body_b.map_or_else(JetFrame::ground, |i| widen(&frames[i], b_at));
    let s = match c.extra {
        Some(k) => {
            let mut s = Jet::<WL> { v: [data.q[k], data.qd[k], 0.5 * data.qdd[k]], e: [[0.0; 3]; WL] };
            s.e[WL - 1][0] = 1.0;
            s
        }
        None => Jet::ZERO,
    };
    let mut out = [Jet::ZERO; MAX_ROWS];
    c.kind.phi_jet(&a, &b, s, t, consts, &mut out);
    for i in 0..c.n_rows {
        let row = (c.row0 + i) as u32;
        for (lane, &col) in cols.iter().enumerate() {
            let (d1, d2) = (out[i].e[lane][1], out[i].e[lane][2]);
            if d1 != 0.0 {
                m1.push((row, col as u32, d1));
            }
            if d2 != 0.0 {
                m2.push((row, col as u32, d2));
            }
        }
    }
}

/// The change of a body point's world position, velocity and acceleration with its
/// body's motion changed by (s, sd, sdd) and its local coordinates by du:
/// r = R + A u, r' = R' + B u th', r'' = R'' + B u th'' - A u th'^2, differentiated.
#[allow(clippy::too_many_arguments)]
fn point_sensitivity(
    req: &PointRequest,
    data: &Data,
    du: [f64; 2],
    k: usize,
    n: usize,
    s: &[f64],
    sd: &[f64],
    sdd: &[f64],
) -> ([f64; 2], [f64; 2], [f64; 2]) {
    // parameter k's column of the (n_coords x n_params) arrays
    let (s, sd, sdd) = (|c: usize| s[c * n + k], |c: usize| sd[c * n + k], |c: usize| sdd[c * n + k]);
    let Some(b) = req.body else {
        return (du, [0.0; 2], [0.0; 2]);
    };
    let f = &data.frames[b];
    let (w, al) = (data.qd[3 * b + 2], data.qdd[3 * b + 2]);
    let (dth, dw, dal) = (s(3 * b + 2), sd(3 * b + 2), sdd(3 * b + 2));
    let (au, bu) = (f.rot(req.local), f.rot_d(req.local));
    let (adu, bdu) = (f.rot(du), f.rot_d(du));
    let mut out = ([0.0; 2], [0.0; 2], [0.0; 2]);
    for i in 0..2 {
        out.0[i] = s(3 * b + i) + bu[i] * dth + adu[i];
        out.1[i] = sd(3 * b + i) + bu[i] * dw - au[i] * w * dth + bdu[i] * w;
        out.2[i] =
            sdd(3 * b + i) + bu[i] * dal - au[i] * al * dth - 2.0 * au[i] * w * dw - bu[i] * w * w * dth
                + bdu[i] * al
                - adu[i] * w * w;
    }
    out
}

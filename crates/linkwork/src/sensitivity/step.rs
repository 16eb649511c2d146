//! The sensitivities at one step, from the factorization of Phi_q there.
//!
//! With S = dq/dp, differentiating Phi(q(t, p), p, t) = 0 in p gives
//! psi(t) = Phi_q S + Phi_p = 0 at every t, hence psi' = psi'' = 0 too:
//!   Phi_q S   = -Phi_p
//!   Phi_q S'  = -(Phi_q' S + Phi_p')
//!   Phi_q S'' = -(2 Phi_q' S' + Phi_q'' S + Phi_p'')
//! (' the time derivative along the motion). psi is the eps-part of phi along the
//! perturbed motion q + eps (S + S' tau + S'' tau^2 / 2), p + eps e: each joint's
//! `phi_jet` gives its tau coefficients exactly, so three passes over the joints, each
//! with what the last one solved, give the right-hand sides, and the three solves reuse
//! one factorization (multiple right-hand sides: W parameter directions per pass).

use super::jet::{Jet, JetFrame};
use super::params::{values, Parameter};
use crate::data::Data;
use crate::joints::{Constraint, MAX_ROWS};
use crate::model::Model;

/// Parameter directions carried by one pass of jets.
pub const W: usize = 4;

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
/// perturbed along the chunk's directions, and the points' local coordinates likewise.
struct Chunk {
    first: usize,
    len: usize,
    /// per constraint, its numbers as jets
    p: Vec<Vec<Jet<W>>>,
    /// per constraint: whether a parameter of the chunk moves one of its numbers
    moves: Vec<bool>,
    /// per point request, its local coordinates as jets
    local: Vec<[Jet<W>; 2]>,
}

/// What one step needs, prepared once for a model, parameters and points; with the
/// per-step scratch, so a sweep allocates nothing per step.
pub struct Sensitivity {
    pub n_params: usize,
    pub points: Vec<PointRequest>,
    chunks: Vec<Chunk>,
    /// n_bodies
    frames: Vec<JetFrame<W>>,
    /// W x n_rows
    rhs: [Vec<f64>; W],
    /// n_coords x W: the chunk's S, S', S''
    dq: Vec<[f64; W]>,
    dqd: Vec<[f64; W]>,
    dqdd: Vec<[f64; W]>,
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

impl Sensitivity {
    pub fn new(model: &Model, params: &[Parameter], points: &[PointRequest]) -> Sensitivity {
        let vals = values(model);
        let mut chunks = Vec::new();
        for first in (0..params.len()).step_by(W) {
            let len = W.min(params.len() - first);
            let mut p: Vec<Vec<Jet<W>>> =
                vals.iter().map(|v| v.iter().map(|&x| Jet::cst(x)).collect()).collect();
            let mut moves = vec![false; model.constraints.len()];
            let mut local: Vec<[Jet<W>; 2]> = points.iter().map(|r| r.local.map(Jet::cst)).collect();
            for k in 0..len {
                let par = &params[first + k];
                for &(c, i, d) in &par.seeds {
                    p[c][i].e[k][0] += d;
                    moves[c] = true;
                }
                for &(named, d) in &par.points {
                    for (r, req) in points.iter().enumerate() {
                        if req.named == Some(named) {
                            local[r][0].e[k][0] += d[0];
                            local[r][1].e[k][0] += d[1];
                        }
                    }
                }
            }
            chunks.push(Chunk { first, len, p, moves, local });
        }
        Sensitivity {
            n_params: params.len(),
            points: points.to_vec(),
            chunks,
            frames: vec![JetFrame::ground(); model.n_bodies],
            rhs: std::array::from_fn(|_| vec![0.0; model.n_rows]),
            dq: vec![[0.0; W]; model.n_coords],
            dqd: vec![[0.0; W]; model.n_coords],
            dqdd: vec![[0.0; W]; model.n_coords],
        }
    }

    /// The jet of coordinate k: data's motion, perturbed by S (and S', S''/2 where the
    /// pass has them: `order` 0, 1, 2, 3 for none, S, S and S', all three).
    #[inline(always)]
    fn coordinate(&self, data: &Data, k: usize, order: usize) -> Jet<W> {
        let mut x = Jet { v: [data.q[k], data.qd[k], 0.5 * data.qdd[k]], e: [[0.0; 3]; W] };
        for d in 0..W {
            if order >= 1 {
                x.e[d][0] = self.dq[k][d];
            }
            if order >= 2 {
                x.e[d][1] = self.dqd[k][d];
            }
            if order >= 3 {
                x.e[d][2] = 0.5 * self.dqdd[k][d];
            }
        }
        x
    }

    fn update_frames(&mut self, data: &Data, order: usize) {
        for i in 0..self.frames.len() {
            let x = [0, 1, 2].map(|j| self.coordinate(data, 3 * i + j, order));
            // cos and sin as the position solve left them (data.frames, at data.q)
            let f = &data.frames[i];
            self.frames[i] = JetFrame::with_cos_sin(x, f.c, f.s);
        }
    }

    /// One pass over the constraints: the tau^`level` coefficient of each row's eps part,
    /// times -`factor`, scaled, into rhs; then solved, into `target` (S, S' or S'').
    fn pass(&mut self, model: &Model, data: &mut Data, t: f64, chunk: usize, level: usize, factor: f64) {
        let ground = JetFrame::ground();
        for r in &mut self.rhs {
            r.fill(0.0);
        }
        for (ci, c) in model.constraints.iter().enumerate() {
            // Phi_p alone: only the constraints the parameters move
            if level == 0 && !self.chunks[chunk].moves[ci] {
                continue;
            }
            let a = c.body_a.map_or(&ground, |i| &self.frames[i]);
            let b = c.body_b.map_or(&ground, |i| &self.frames[i]);
            let s = match c.extra {
                Some(k) => self.coordinate(data, k, level),
                None => Jet::ZERO,
            };
            let mut out = [Jet::ZERO; MAX_ROWS];
            c.kind.phi_jet(a, b, s, t, &self.chunks[chunk].p[ci], &mut out);
            for i in 0..c.n_rows {
                let scale = -factor * c.row_scale[i];
                for d in 0..W {
                    self.rhs[d][c.row0 + i] = out[i].e[d][level] * scale;
                }
            }
        }
        let len = self.chunks[chunk].len;
        for d in 0..len {
            data.factor.solve(&model.symbolic, &mut self.rhs[d]);
            let target = match level {
                0 => &mut self.dq,
                1 => &mut self.dqd,
                _ => &mut self.dqdd,
            };
            for ((x, col), s) in self.rhs[d].iter().zip(target.iter_mut()).zip(&model.col_scale) {
                col[d] = x * s;
            }
        }
    }

    /// S, S', S'' (and the points') at the step data holds: data.q, qd, qdd solved at t
    /// and Phi_q factored at data.q (in data.factor).
    pub fn step(&mut self, model: &Model, data: &mut Data, t: f64, out: StepOut) {
        let n = self.n_params;
        let ground = JetFrame::ground();
        for chunk in 0..self.chunks.len() {
            self.update_frames(data, 0);
            self.pass(model, data, t, chunk, 0, 1.0);
            self.update_frames(data, 1);
            self.pass(model, data, t, chunk, 1, 1.0);
            self.update_frames(data, 2);
            self.pass(model, data, t, chunk, 2, 2.0);
            let (first, len) = (self.chunks[chunk].first, self.chunks[chunk].len);
            for k in 0..model.n_coords {
                for d in 0..len {
                    out.dq[k * n + first + d] = self.dq[k][d];
                    out.dqd[k * n + first + d] = self.dqd[k][d];
                    out.dqdd[k * n + first + d] = self.dqdd[k][d];
                }
            }
            if self.points.is_empty() {
                continue;
            }
            // the points move with their bodies' perturbed motion, and with their own
            // local coordinates where a parameter moves them
            self.update_frames(data, 3);
            for (r, req) in self.points.iter().enumerate() {
                let frame = req.body.map_or(&ground, |i| &self.frames[i]);
                let p = frame.point(self.chunks[chunk].local[r]);
                for (axis, x) in p.iter().enumerate() {
                    for d in 0..len {
                        let at = (r * 2 + axis) * n + first + d;
                        out.points[at] = x.e[d][0];
                        out.points_d[at] = x.e[d][1];
                        out.points_dd[at] = 2.0 * x.e[d][2];
                    }
                }
            }
        }
    }
}

//! The sensitivities of the Lagrange multipliers, hence of the driver efforts, at one step.
//!
//! The inverse dynamics is Phi_q^T lambda = Q(q, qd, qdd, p) (`forces`: Q = -M qdd + the
//! velocity terms + gravity + the applied loads). Differentiated in p along the solved
//! motion (S = dq/dp, S', S''):
//!   Phi_q^T dlambda/dp = dQ/dp - (dPhi_q/dp)^T lambda,
//!   dQ/dp = Q_q S + Q_qd S' + Q_qdd S'' + Q_p,   dPhi_q/dp = Phi_qq S + Phi_qp.
//! dQ/dp comes from the bodies' and loads' forces over jets (`Inertia::force_jet`,
//! `LoadEntry::add_jet`): the motion perturbed by (S, S', S''), the mass properties,
//! gravity and the loads' numbers by the parameters (W directions at a time). For
//! (dPhi_q/dp)^T lambda the roles of the jets swap: the tau direction carries parameter
//! k's change (the coordinates' S_k and the constraints' seeds), the lanes each joint's
//! own coordinates, so the tau part of lane j of row i is d(dphi_i/dq_j)/dp_k. Then one
//! transpose solve per parameter with the step's factorization.

use super::jet::{Jet, JetFrame};
use super::step::{coordinate_columns, widen, Consts, W};
use crate::constraints::loads::Inertia;
use crate::constraints::{Constraint, MAX_ROWS};
use crate::model::data::Data;
use crate::model::params::{values, Dynamics, Parameter};
use crate::model::{ConstraintEntry, Model};

/// What the effort sensitivities of one step need, prepared once for a model and its
/// parameters; with the per-step scratch, so a sweep allocates nothing per step.
pub struct Efforts {
    n_params: usize,
    /// per chunk of W parameters: the inverse dynamics' numbers (`Dynamics`) as jets,
    /// perturbed along the chunk's directions
    dynamics: Vec<Vec<Jet<W>>>,
    /// where gravity and each load's numbers sit in `dynamics` (`Dynamics`)
    layout: Dynamics,
    /// per parameter: the constraints' numbers it moves (constraint, number, d / dp)
    seeds: Vec<Vec<(usize, usize, f64)>>,
    /// per constraint: its numbers as jets as wide as its coordinate directions
    consts: Vec<Consts>,
    /// per constraint: the column of each of its coordinate directions, in lane order
    cols: Vec<Vec<usize>>,
    /// n_bodies: the motion perturbed along a chunk; the direction of one parameter
    motion: Vec<JetFrame<W>>,
    along: Vec<JetFrame<3>>,
    /// n_coords: the generalized force over jets
    force: Vec<Jet<W>>,
    /// n_coords x n_params: dQ/dp - (dPhi_q/dp)^T lambda
    rhs: Vec<f64>,
    /// n_rows: one parameter's column, solved in place
    column: Vec<f64>,
}

impl Efforts {
    pub fn new(model: &Model, params: &[Parameter]) -> Efforts {
        let n = params.len();
        let layout = Dynamics::new(model);
        let dynamics = (0..n)
            .step_by(W)
            .map(|first| {
                let mut jets: Vec<Jet<W>> = layout.values.iter().map(|&x| Jet::cst(x)).collect();
                for (k, p) in params[first..n.min(first + W)].iter().enumerate() {
                    for &(i, d) in &p.dynamics {
                        jets[i].e[k][0] += d;
                    }
                }
                jets
            })
            .collect();
        let cols = coordinate_columns(model);
        Efforts {
            n_params: n,
            dynamics,
            layout,
            seeds: params.iter().map(|p| p.seeds.clone()).collect(),
            consts: Consts::of(&values(model), &cols),
            cols,
            motion: vec![JetFrame::ground(); model.n_bodies],
            along: vec![JetFrame::ground(); model.n_bodies],
            force: vec![Jet::ZERO; model.n_coords],
            rhs: vec![0.0; model.n_coords * n],
            column: vec![0.0; model.n_rows.max(model.n_coords)],
        }
    }

    /// dlambda/dp (n_rows x n_params) at the step data holds: q, qd, qdd and lambda solved
    /// at t, Phi_q factored at q; `s`, `sd`, `sdd` the step's S, S', S'' (n_coords x
    /// n_params).
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        model: &Model,
        data: &mut Data,
        t: f64,
        s: &[f64],
        sd: &[f64],
        sdd: &[f64],
        dlambda: &mut [f64],
    ) {
        let n = self.n_params;
        if n == 0 {
            return;
        }
        self.rhs.fill(0.0);
        self.force_rates(model, data, t, s, sd, sdd);
        for k in 0..n {
            self.phi_q_rates(model, data, t, s, k);
        }
        // Phi_q^T x = b, scaled as `forces::solve_forces`: J_s^T (D_r^-1 x) = D_c b
        for k in 0..n {
            self.column.fill(0.0);
            for (j, sc) in model.col_scale.iter().enumerate() {
                self.column[j] = self.rhs[j * n + k] * sc;
            }
            data.factor.solve_transpose(&model.symbolic, &mut self.column[..model.n_rows]);
            for c in &model.constraints {
                for i in 0..c.n_rows {
                    dlambda[(c.row0 + i) * n + k] = self.column[c.row0 + i] * c.row_scale[i];
                }
            }
        }
    }

    /// dQ/dp into `rhs`, W parameters at a time.
    fn force_rates(&mut self, model: &Model, data: &Data, t: f64, s: &[f64], sd: &[f64], sdd: &[f64]) {
        let n = self.n_params;
        for (chunk, p) in self.dynamics.iter().enumerate() {
            let first = chunk * W;
            let len = W.min(n - first);
            for (i, frame) in self.motion.iter_mut().enumerate() {
                let x = [0, 1, 2].map(|j| {
                    let c = 3 * i + j;
                    let at = |v: &[f64], k: usize| if k < len { v[c * n + first + k] } else { 0.0 };
                    Jet::<W> {
                        v: [data.q[c], data.qd[c], 0.5 * data.qdd[c]],
                        e: std::array::from_fn(|k| [at(s, k), at(sd, k), 0.5 * at(sdd, k)]),
                    }
                });
                *frame = JetFrame::with_cos_sin(x, data.frames[i].c, data.frames[i].s);
            }
            self.force.fill(Jet::ZERO);
            let g = [p[self.layout.gravity], p[self.layout.gravity + 1]];
            for (i, frame) in self.motion.iter().enumerate() {
                let at = Dynamics::body(i, 0);
                let f = Inertia::force_jet(frame, &p[at..at + Inertia::NAMES.len()], g);
                for j in 0..3 {
                    self.force[3 * i + j] = self.force[3 * i + j] + f[j];
                }
            }
            for (l, load) in model.loads.iter().enumerate() {
                let from = self.layout.loads[l];
                let to = self.layout.loads.get(l + 1).copied().unwrap_or(p.len());
                load.add_jet(&self.motion, t, &p[from..to], &mut self.force);
            }
            for (c, f) in self.force.iter().enumerate() {
                for k in 0..len {
                    self.rhs[c * n + first + k] += f.e[k][0];
                }
            }
        }
    }

    /// -(dPhi_q/dp_k)^T lambda into column k of `rhs`, joint by joint.
    fn phi_q_rates(&mut self, model: &Model, data: &Data, t: f64, s: &[f64], k: usize) {
        let n = self.n_params;
        let dir = |c: usize| s[c * n + k];
        for (i, frame) in self.along.iter_mut().enumerate() {
            let x = [0, 1, 2].map(|j| {
                let c = 3 * i + j;
                let mut x = Jet::<3> { v: [data.q[c], dir(c), 0.0], e: [[0.0; 3]; 3] };
                x.e[j][0] = 1.0;
                x
            });
            *frame = JetFrame::with_cos_sin(x, data.frames[i].c, data.frames[i].s);
        }
        for (ci, c) in model.constraints.iter().enumerate() {
            let seeds = &self.seeds[k];
            let moved = seeds.iter().any(|&(sc, _, _)| sc == ci);
            if !moved && self.cols[ci].iter().all(|&col| dir(col) == 0.0) {
                continue;
            }
            let lambda = &data.lambda[c.row0..c.row0 + c.n_rows];
            let (frames, cols, rhs) = (&self.along, &self.cols[ci], &mut self.rhs);
            let extra = c.extra.map(|e| (data.q[e], dir(e)));
            let seeds = seeds.iter().filter(|s| s.0 == ci).map(|&(_, i, d)| (i, d));
            match &mut self.consts[ci] {
                Consts::W3(p) => along_one(c, frames, extra, t, p, seeds, cols, lambda, rhs, n, k),
                Consts::W4(p) => along_one(c, frames, extra, t, p, seeds, cols, lambda, rhs, n, k),
                Consts::W6(p) => along_one(c, frames, extra, t, p, seeds, cols, lambda, rhs, n, k),
                Consts::W7(p) => along_one(c, frames, extra, t, p, seeds, cols, lambda, rhs, n, k),
            }
        }
    }
}

/// One constraint's rows on jets whose lanes are its coordinate directions and whose tau
/// direction is parameter k's change (`frames`, `extra`: its value and change; `seeds`:
/// its numbers' changes); subtracts lambda_i times the tau part of lane j of row i from
/// rhs (column `cols[j]`, parameter k).
#[allow(clippy::too_many_arguments)]
#[inline]
fn along_one<const WL: usize>(
    c: &ConstraintEntry,
    frames: &[JetFrame<3>],
    extra: Option<(f64, f64)>,
    t: f64,
    consts: &mut [Jet<WL>],
    seeds: impl Iterator<Item = (usize, f64)> + Clone,
    cols: &[usize],
    lambda: &[f64],
    rhs: &mut [f64],
    n: usize,
    k: usize,
) {
    let b_at = if c.body_a.is_some() { 3 } else { 0 };
    let a = c.body_a.map_or_else(JetFrame::ground, |i| widen(&frames[i], 0));
    let b = c.body_b.map_or_else(JetFrame::ground, |i| widen(&frames[i], b_at));
    let s = match extra {
        Some((x, dx)) => {
            let mut s = Jet::<WL> { v: [x, dx, 0.0], e: [[0.0; 3]; WL] };
            s.e[WL - 1][0] = 1.0;
            s
        }
        None => Jet::ZERO,
    };
    for (i, d) in seeds.clone() {
        consts[i].v[1] += d;
    }
    let mut out = [Jet::ZERO; MAX_ROWS];
    c.kind.phi_jet(&a, &b, s, t, consts, &mut out);
    for (i, _) in seeds {
        consts[i].v[1] = 0.0;
    }
    for (i, l) in lambda.iter().enumerate() {
        for (lane, &col) in cols.iter().enumerate() {
            rhs[col * n + k] -= l * out[i].e[lane][1];
        }
    }
}

//! A group with no closed form (a triad, a cam contact, gears in a loop, a user
//! expression): Newton on its own rows and coordinates only, the coordinates of earlier
//! groups held fixed, with a dense LU of the block (`small_lu`). Velocities and
//! accelerations: the same block with the known coordinates' terms moved to the right.

use super::StepMiss;
use crate::constraints::{Constraint, Frame, Rows, MAX_ROWS};
use crate::math::angle::turned;
use crate::math::small_lu;
use crate::model::data::Data;
use crate::model::plan::{NewtonBlock, NewtonWork};
use crate::model::structure::Group;
use crate::model::Model;

const KNOWN: usize = usize::MAX;

/// Diagnostics of one block solve.
#[derive(Debug, Clone, Copy)]
pub struct NewtonInfo {
    pub iterations: usize,
    /// scaled residual of the block's rows (in units of L: `step` scales by 1/L)
    pub residual: f64,
    pub pivot_ratio: f64,
    pub det_sign: f64,
    pub correction: f64,
}

impl NewtonBlock {
    pub fn new(model: &Model, g: &Group) -> NewtonBlock {
        let local_of = |col: usize| g.coords.iter().position(|&c| c == col).unwrap_or(KNOWN);
        let mut local = Vec::with_capacity(g.constraints.len());
        let mut row0 = Vec::with_capacity(g.constraints.len());
        let mut rows = 0;
        for &k in &g.constraints {
            let c = &model.constraints[k];
            let mut l = [KNOWN; 7];
            for (side, body) in [c.body_a, c.body_b].into_iter().enumerate() {
                if let Some(b) = body {
                    for j in 0..3 {
                        l[3 * side + j] = local_of(3 * b + j);
                    }
                }
            }
            if let Some(e) = c.extra {
                l[6] = local_of(e);
            }
            local.push(l);
            row0.push(rows);
            rows += c.n_rows;
        }
        let mut bodies: Vec<usize> =
            g.coords.iter().filter(|&&c| c < 3 * model.n_bodies).map(|&c| c / 3).collect();
        bodies.dedup();
        NewtonBlock {
            cols: g.coords.clone(),
            constraints: g.constraints.clone(),
            local,
            row0,
            bodies,
            n: g.coords.len(),
        }
    }

    /// Frames of the block's bodies from q (and qd).
    fn refresh(&self, data: &mut Data) {
        for &b in &self.bodies {
            let (c, s) = turned(data.q[3 * b + 2], &mut data.frame_base[b]);
            let q = &data.q[3 * b..3 * b + 3];
            let qd = &data.qd[3 * b..3 * b + 3];
            data.frames[b] = Frame { r: [q[0], q[1]], theta: q[2], c, s, rd: [qd[0], qd[1]], thetad: qd[2] };
        }
    }

    /// The rows of constraint i at the frames (and q, qd for the extra coordinate).
    #[inline]
    fn rows(&self, model: &Model, q: &[f64], qd: &[f64], frames: &[Frame], i: usize, t: f64) -> Rows {
        let c = &model.constraints[self.constraints[i]];
        let f = |b: Option<usize>| b.map_or(Frame::GROUND, |b| frames[b]);
        let mut rows = Rows::default();
        c.kind.position(&f(c.body_a), &f(c.body_b), &c.extra(q, qd), t, &mut rows);
        rows
    }

    /// Writes the scaled block of Phi_q into work.jac and -phi (scaled) into work.rhs;
    /// returns the residual's inf-norm.
    fn assemble(&self, model: &Model, q: &[f64], frames: &[Frame], work: &mut NewtonWork, t: f64) -> f64 {
        let n = self.n;
        let l = model.length_scale;
        let col = [l, l, 1.0];
        work.jac.fill(0.0);
        let mut norm = 0.0f64;
        for (i, &k) in self.constraints.iter().enumerate() {
            let c = &model.constraints[k];
            let rows = self.rows(model, q, &[], frames, i, t);
            let loc = &self.local[i];
            for r in 0..c.n_rows {
                let rs = c.row_scale[r];
                let row = self.row0[i] + r;
                let p = rows.phi[r] * rs;
                work.rhs[row] = -p;
                norm = if p.abs() > norm || p.is_nan() { p.abs() } else { norm };
                for j in 0..3 {
                    if loc[j] != KNOWN {
                        work.jac[loc[j] * n + row] += rows.jac_a[r][j] * rs * col[j];
                    }
                    if loc[3 + j] != KNOWN {
                        work.jac[loc[3 + j] * n + row] += rows.jac_b[r][j] * rs * col[j];
                    }
                }
                if loc[6] != KNOWN {
                    work.jac[loc[6] * n + row] += rows.jac_s[r] * rs;
                }
            }
        }
        norm
    }

    /// LU of work.jac: (pivot ratio, det sign).
    fn factor(&self, work: &mut NewtonWork) -> (f64, f64) {
        let n = self.n;
        small_lu::factor(&mut work.jac, n, &mut work.piv, &mut work.inv);
        let (mut lo, mut hi, mut det) = (f64::INFINITY, 0.0f64, 1.0f64);
        for k in 0..n {
            let u = work.jac[k * n + k];
            lo = lo.min(u.abs());
            hi = hi.max(u.abs());
            det *= u.signum() * if work.piv[k] != k { -1.0 } else { 1.0 };
        }
        let ratio = if hi > 0.0 { lo / hi } else { 0.0 };
        (ratio, if lo == 0.0 { 0.0 } else { det })
    }

    /// The block factored at the configuration in q and frames: (det sign, pivot ratio).
    pub fn pivots_at(
        &self,
        model: &Model,
        q: &[f64],
        frames: &[Frame],
        work: &mut NewtonWork,
        t: f64,
    ) -> (f64, f64) {
        self.assemble(model, q, frames, work, t);
        let (ratio, det) = self.factor(work);
        (det, ratio)
    }

    /// Newton on the block from data.q, then its rates.
    pub fn solve(
        &self,
        model: &Model,
        data: &mut Data,
        work: &mut NewtonWork,
        t: f64,
        derivatives: u8,
    ) -> Result<NewtonInfo, StepMiss> {
        let opts = &model.options;
        let mut prev_step = f64::INFINITY;
        let mut correction = 0.0;
        let mut info = None;
        for it in 1..=opts.max_iter {
            self.refresh(data);
            let residual = self.assemble(model, &data.q, &data.frames, work, t);
            if !residual.is_finite() {
                return Err(StepMiss::Failed);
            }
            let (ratio, det) = self.factor(work);
            if ratio.is_nan() || ratio < opts.singular_tol {
                return Err(StepMiss::NearSingular);
            }
            small_lu::solve(&work.jac, self.n, &work.piv, &work.inv, &mut work.rhs);
            let step = work.rhs.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            if !step.is_finite() {
                return Err(StepMiss::Failed);
            }
            // as the general Newton (position.rs): the step's floor is round-off over the ratio
            let floor = opts.tol_step.max(8.0 * f64::EPSILON / ratio);
            let converged = residual <= opts.tol_residual && step <= floor;
            let stalled = !converged && residual <= opts.tol_residual && step >= 0.9 * prev_step;
            prev_step = step;
            if !stalled {
                for (j, &c) in self.cols.iter().enumerate() {
                    data.q[c] += work.rhs[j] * model.col_scale[c];
                }
                correction += step;
            }
            if converged || stalled {
                info = Some(NewtonInfo {
                    iterations: it,
                    residual: residual * model.length_scale,
                    pivot_ratio: ratio,
                    det_sign: det,
                    correction,
                });
                break;
            }
        }
        let info = info.ok_or(StepMiss::Failed)?;
        if work.det_sign != 0.0 && info.det_sign != work.det_sign {
            return Err(StepMiss::NearSingular); // the block's det changed sign: a crossing
        }
        work.det_sign = info.det_sign;
        self.refresh(data);
        if derivatives >= 1 {
            self.rates(model, data, work, t, false)?;
            self.refresh(data);
            if derivatives >= 2 {
                self.rates(model, data, work, t, true)?;
            }
        }
        Ok(info)
    }

    /// Velocities (or accelerations): the block's rows of Phi_q x = nu (gamma), the known
    /// columns' terms on the right, solved with the last factorization.
    fn rates(
        &self,
        model: &Model,
        data: &mut Data,
        work: &mut NewtonWork,
        t: f64,
        second: bool,
    ) -> Result<(), StepMiss> {
        for (i, &k) in self.constraints.iter().enumerate() {
            let c = &model.constraints[k];
            let mut v = [0.0; MAX_ROWS];
            let f = |b: Option<usize>| b.map_or(Frame::GROUND, |b| data.frames[b]);
            if second {
                c.kind.gamma(&f(c.body_a), &f(c.body_b), &c.extra(&data.q, &data.qd), t, &mut v);
            } else {
                c.kind.nu(t, &mut v);
            }
            let rows = self.rows(model, &data.q, &data.qd, &data.frames, i, t);
            let x = if second { &data.qdd } else { &data.qd };
            let loc = &self.local[i];
            for (r, &vr) in v.iter().enumerate().take(c.n_rows) {
                let mut known = 0.0;
                for (side, body) in [c.body_a, c.body_b].into_iter().enumerate() {
                    if let Some(b) = body {
                        let jac = if side == 0 { &rows.jac_a[r] } else { &rows.jac_b[r] };
                        for j in 0..3 {
                            if loc[3 * side + j] == KNOWN {
                                known += jac[j] * x[3 * b + j];
                            }
                        }
                    }
                }
                if let (Some(e), KNOWN) = (c.extra, loc[6]) {
                    known += rows.jac_s[r] * x[e];
                }
                work.rhs[self.row0[i] + r] = (vr - known) * c.row_scale[r];
            }
        }
        small_lu::solve(&work.jac, self.n, &work.piv, &work.inv, &mut work.rhs);
        if !work.rhs.iter().all(|v| v.is_finite()) {
            return Err(StepMiss::Failed); // the general path names the row
        }
        let x = if second { &mut data.qdd } else { &mut data.qd };
        for (j, &c) in self.cols.iter().enumerate() {
            x[c] = work.rhs[j] * model.col_scale[c];
        }
        Ok(())
    }
}

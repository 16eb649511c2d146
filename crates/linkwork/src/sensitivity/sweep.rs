//! A sweep with its sensitivities: the ordinary sweep (`crate::sweep::sweep`, every
//! coordinate, velocities and accelerations), then, step by step, Phi_q assembled and
//! factored at the solved q (the structured path has no factorization of its own; the
//! general path's last one is at the Newton iterate before the last update) and the
//! sensitivities solved with it (`step`); with efforts, the sweep solves the inverse
//! dynamics too and the multipliers' sensitivities follow (`efforts`).

use super::efforts::Efforts;
use super::params::Parameter;
use super::step::{PointRequest, Sensitivity, StepOut};
use crate::data::Data;
use crate::error::SolveError;
use crate::model::Model;
use crate::sweep::{Request, SweepOutput};

/// A sweep and its sensitivities: row-major arrays, the first `n_done` steps valid.
#[derive(Debug, Clone, Default)]
pub struct SensitivityOutput {
    /// the sweep itself (every coordinate; velocities and accelerations)
    pub sweep: SweepOutput,
    pub names: Vec<String>,
    pub n_params: usize,
    pub n_points: usize,
    /// steps whose sensitivities are solved
    pub n_done: usize,
    /// n_steps x n_coords x n_params: dq/dp, dqd/dp, dqdd/dp
    pub dq: Vec<f64>,
    pub dqd: Vec<f64>,
    pub dqdd: Vec<f64>,
    /// n_steps x n_points x 2 x n_params: the points' world position, velocity and
    /// acceleration, differentiated
    pub points: Vec<f64>,
    pub points_d: Vec<f64>,
    pub points_dd: Vec<f64>,
    /// whether the sweep solves the inverse dynamics and dlambda/dp is solved
    pub efforts: bool,
    /// n_steps x n_rows x n_params: dlambda/dp (empty without efforts); a driver's
    /// effort is -lambda of its row
    pub dlambda: Vec<f64>,
}

impl SensitivityOutput {
    /// Preallocated outputs of a sweep over `times` with the sensitivities to `params`
    /// and of `n_points` body points.
    pub fn new(model: &Model, times: &[f64], params: &[Parameter], n_points: usize) -> SensitivityOutput {
        let (n_steps, n, nc) = (times.len(), params.len(), model.n_coords);
        SensitivityOutput {
            sweep: SweepOutput::with_request(model, times, Request::default()),
            names: params.iter().map(|p| p.name.clone()).collect(),
            n_params: n,
            n_points,
            n_done: 0,
            dq: vec![0.0; n_steps * nc * n],
            dqd: vec![0.0; n_steps * nc * n],
            dqdd: vec![0.0; n_steps * nc * n],
            points: vec![0.0; n_steps * n_points * 2 * n],
            points_d: vec![0.0; n_steps * n_points * 2 * n],
            points_dd: vec![0.0; n_steps * n_points * 2 * n],
            efforts: false,
            dlambda: Vec::new(),
        }
    }

    /// `new`, with the inverse dynamics in the sweep (`Request::forces`) and the
    /// sensitivities of its multipliers, dlambda/dp.
    pub fn with_efforts(
        model: &Model,
        times: &[f64],
        params: &[Parameter],
        n_points: usize,
    ) -> SensitivityOutput {
        let mut out = SensitivityOutput::new(model, times, params, n_points);
        out.sweep = SweepOutput::with_request(model, times, Request { forces: true, ..Request::default() });
        out.efforts = true;
        out.dlambda = vec![0.0; times.len() * model.n_rows * params.len()];
        out
    }
}

/// Sweeps `times` from data.q (as `crate::sweep::sweep`) and solves the sensitivities
/// of every step to `params`, and of the body points `points`, into `out` (made by
/// `SensitivityOutput::new`, or `with_efforts` for dlambda/dp too, for the same times,
/// parameters and points). On error the steps before the one at fault are kept
/// (`out.n_done`, and the sweep's own).
#[allow(clippy::too_many_arguments)]
pub fn sensitivity_sweep(
    model: &Model,
    data: &mut Data,
    times: &[f64],
    params: &[Parameter],
    points: &[PointRequest],
    out: &mut SensitivityOutput,
    progress_every: usize,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<(), SolveError> {
    let (n, nc, np, nr) = (params.len(), model.n_coords, points.len(), model.n_rows);
    assert!(
        out.n_params == n && out.n_points == np && out.dq.len() == times.len() * nc * n,
        "outputs made for other times, parameters or points"
    );
    out.n_done = 0;
    let result = crate::sweep::sweep(model, data, times, &mut out.sweep, progress_every, progress);
    let mut sens = Sensitivity::new(model, params, points);
    let mut efforts = out.efforts.then(|| Efforts::new(model, params));
    for k in 0..out.sweep.n_done {
        let t = times[k];
        let row = k * nc..(k + 1) * nc;
        data.q.copy_from_slice(&out.sweep.q[row.clone()]);
        data.qd.copy_from_slice(&out.sweep.qd[row.clone()]);
        data.qdd.copy_from_slice(&out.sweep.qdd[row]);
        crate::assembly::position(model, data, t);
        crate::position::factor(model, data, t, k)?;
        let (s, p) = (k * nc * n..(k + 1) * nc * n, k * np * 2 * n..(k + 1) * np * 2 * n);
        sens.step(
            model,
            data,
            t,
            StepOut {
                dq: &mut out.dq[s.clone()],
                dqd: &mut out.dqd[s.clone()],
                dqdd: &mut out.dqdd[s],
                points: &mut out.points[p.clone()],
                points_d: &mut out.points_d[p.clone()],
                points_dd: &mut out.points_dd[p],
            },
        );
        if let Some(efforts) = &mut efforts {
            data.lambda.copy_from_slice(&out.sweep.lambda[k * nr..(k + 1) * nr]);
            let s = k * nc * n..(k + 1) * nc * n;
            let (dq, dqd, dqdd) = (&out.dq[s.clone()], &out.dqd[s.clone()], &out.dqdd[s]);
            let dlambda = &mut out.dlambda[k * nr * n..(k + 1) * nr * n];
            efforts.step(model, data, t, dq, dqd, dqdd, dlambda);
        }
        out.n_done = k + 1;
    }
    result
}

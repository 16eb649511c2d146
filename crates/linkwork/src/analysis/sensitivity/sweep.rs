//! A sweep with its sensitivities: the ordinary sweep (`crate::sweep::time_loop::sweep`, every
//! coordinate, and the velocities and accelerations the sensitivities need) and, step by
//! step, the sensitivities at the solved q. On the structured path (`structured`: dq/dp
//! only, a plan of cranks and dyads) each group's closed form differentiated, as the sweep
//! leaves each step (its frames current); on the general path, after the sweep, Phi_q
//! assembled and factored at the solved q (the structured sweep has no factorization of
//! its own; the general sweep's last one is at the Newton iterate before the last update)
//! and the sensitivities solved with it (`step`); with efforts (the general path), the
//! sweep solves the inverse dynamics too and the multipliers' sensitivities follow
//! (`efforts`).

use std::ops::Range;

use super::efforts::Efforts;
use super::step::{PointRequest, Sensitivity, StepOut};
use super::structured::{choose, SensitivityPath};
use crate::error::SolveError;
use crate::model::data::Data;
use crate::model::params::Parameter;
use crate::model::Model;
use crate::sweep::outputs::{Request, SweepOutput};

/// What a sensitivity sweep solves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SensitivityRequest {
    /// 0: dq/dp only; 1: and dqd/dp; 2: and dqdd/dp (the sweep solves as many)
    pub derivatives: u8,
    /// the general path even where the structured one applies (a cross-check)
    pub general: bool,
}

impl Default for SensitivityRequest {
    fn default() -> Self {
        SensitivityRequest { derivatives: 2, general: false }
    }
}

/// A sweep and its sensitivities: row-major arrays, the first `n_done` steps valid.
#[derive(Debug, Clone, Default)]
pub struct SensitivityOutput {
    /// the sweep itself (every coordinate; the velocities and accelerations asked for)
    pub sweep: SweepOutput,
    pub names: Vec<String>,
    pub n_params: usize,
    pub n_points: usize,
    pub request: SensitivityRequest,
    /// steps whose sensitivities are solved
    pub n_done: usize,
    /// the path that solved them (`structured::choose`), and why that one
    pub path: SensitivityPath,
    pub path_reason: String,
    /// on the structured path: the steps next to a singular configuration that the
    /// general path solved
    pub general_steps: usize,
    /// n_steps x n_coords x n_params: dq/dp, dqd/dp, dqdd/dp (the last two empty unless
    /// asked for)
    pub dq: Vec<f64>,
    pub dqd: Vec<f64>,
    pub dqdd: Vec<f64>,
    /// n_steps x n_points x 2 x n_params: the points' world position, velocity and
    /// acceleration, differentiated (as the derivatives asked for)
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
    /// and of `n_points` body points: dq/dp, dqd/dp and dqdd/dp.
    pub fn new(model: &Model, times: &[f64], params: &[Parameter], n_points: usize) -> SensitivityOutput {
        SensitivityOutput::with_request(model, times, params, n_points, SensitivityRequest::default())
    }

    /// As `new`, of the derivatives `request` asks for.
    pub fn with_request(
        model: &Model,
        times: &[f64],
        params: &[Parameter],
        n_points: usize,
        request: SensitivityRequest,
    ) -> SensitivityOutput {
        let d = request.derivatives.min(2);
        let request = SensitivityRequest { derivatives: d, ..request };
        let (n_steps, n, nc) = (times.len(), params.len(), model.n_coords);
        let sized = |on: bool, len: usize| if on { vec![0.0; len] } else { Vec::new() };
        SensitivityOutput {
            sweep: SweepOutput::with_request(model, times, Request { derivatives: d, ..Request::default() }),
            names: params.iter().map(|p| p.name.clone()).collect(),
            n_params: n,
            n_points,
            request,
            n_done: 0,
            path: SensitivityPath::General,
            path_reason: String::new(),
            general_steps: 0,
            dq: vec![0.0; n_steps * nc * n],
            dqd: sized(d >= 1, n_steps * nc * n),
            dqdd: sized(d >= 2, n_steps * nc * n),
            points: vec![0.0; n_steps * n_points * 2 * n],
            points_d: sized(d >= 1, n_steps * n_points * 2 * n),
            points_dd: sized(d >= 2, n_steps * n_points * 2 * n),
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

/// `v[r]`, or `v` itself where it is empty (an output not asked for).
fn rows(v: &mut [f64], r: Range<usize>) -> &mut [f64] {
    if v.is_empty() {
        v
    } else {
        &mut v[r]
    }
}

/// Sweeps `times` from data.q (as `crate::sweep::time_loop::sweep`) and solves the sensitivities
/// of every step to `params`, and of the body points `points`, into `out` (made by
/// `SensitivityOutput::new`, `with_request` (its request says which derivatives) or
/// `with_efforts` (dlambda/dp too), for the same times, parameters and points). On error
/// the steps before the one at fault are kept (`out.n_done`, and the sweep's own).
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
    let d = out.request.derivatives;
    out.n_done = 0;
    out.general_steps = 0;
    let structured = choose(model, params, d, out.request.general);
    (out.path, out.path_reason) = match &structured {
        Ok(_) => (
            SensitivityPath::Structured,
            "every group is a crank or a dyad, whose closed form is differentiated".into(),
        ),
        Err(why) => (SensitivityPath::General, why.clone()),
    };
    let mut sens = Sensitivity::new(model, params, points);
    let mut efforts = out.efforts.then(|| Efforts::new(model, params));
    // the steps the general path solves after the sweep: all of them, or on the structured
    // path those next to a singular configuration
    let mut general = vec![structured.is_err(); times.len()];
    let result = match &structured {
        Ok(st) => {
            let (dq, dr, sens) = (&mut out.dq, &mut out.points, &sens);
            let mut each = |data: &Data, t: f64, k: usize| {
                let (s, p) = (k * nc * n..(k + 1) * nc * n, k * np * 2 * n..(k + 1) * np * 2 * n);
                match st.step(model, data, t, &mut dq[s.clone()]) {
                    Ok(()) => sens.points_of(data, &dq[s], &mut dr[p]),
                    Err(_) => general[k] = true,
                }
                Ok(())
            };
            crate::sweep::time_loop::sweep_observed(
                model,
                data,
                times,
                &mut out.sweep,
                progress_every,
                progress,
                &mut each,
            )
        }
        Err(_) => {
            crate::sweep::time_loop::sweep(model, data, times, &mut out.sweep, progress_every, progress)
        }
    };
    for k in 0..out.sweep.n_done {
        if !general[k] {
            out.n_done = k + 1;
            continue;
        }
        let t = times[k];
        let row = k * nc..(k + 1) * nc;
        data.q.copy_from_slice(&out.sweep.q[row.clone()]);
        // the general path's jets read the rates solved; none below the derivatives asked for
        match d {
            0 => data.qd.fill(0.0),
            _ => data.qd.copy_from_slice(&out.sweep.qd[row.clone()]),
        }
        match d {
            0 | 1 => data.qdd.fill(0.0),
            _ => data.qdd.copy_from_slice(&out.sweep.qdd[row]),
        }
        let (s, p) = (k * nc * n..(k + 1) * nc * n, k * np * 2 * n..(k + 1) * np * 2 * n);
        out.general_steps += structured.is_ok() as usize;
        crate::solve::assembly::position(model, data, t);
        crate::solve::position::factor(model, data, t, k)?;
        sens.step_to(
            model,
            data,
            t,
            d,
            StepOut {
                dq: &mut out.dq[s.clone()],
                dqd: rows(&mut out.dqd, s.clone()),
                dqdd: rows(&mut out.dqdd, s),
                points: &mut out.points[p.clone()],
                points_d: rows(&mut out.points_d, p.clone()),
                points_dd: rows(&mut out.points_dd, p),
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

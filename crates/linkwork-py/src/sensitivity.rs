//! Exact sensitivities of a sweep to design parameters, as NumPy arrays.

use linkwork::sensitivity::{
    sensitivity_sweep, Parameter, PointRequest, SensitivityOutput, SensitivityRequest,
};
use linkwork::Data;
use numpy::ndarray::{Array3, Array4};
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::{guard, laws, output_dict, poll_progress, run_error, InputError, PyModel};

pyo3::import_exception!(linkwork.errors, ParameterError);

/// Sweeps `times` and solves, at every step, dq/dp (and with `derivatives` 1 dqd/dp, 2
/// dqdd/dp too) for each named parameter (description paths or engine names), and the
/// world position (velocity, acceleration) sensitivities of `points` ((body index, -1 the
/// ground; u_x, u_y; named point index or -1)). With `efforts` (derivatives 2), the sweep
/// solves the inverse dynamics too and dlambda/dp follows. The GIL is released meanwhile.
/// Returns (dict, error or None): the sweep's outputs (its forces with `efforts`) and
/// "names", "nominal", "dq", "dqd", "dqdd" (n_steps x n_coords x n_params; None where not
/// asked for), "sens_points", "sens_points_d", "sens_points_dd" (n_steps x n_points x 2 x
/// n_params; None likewise), with `efforts` "dlambda" (n_steps x n_rows x n_params),
/// "derivatives", the "path" that solved them ("structured" or "general"), "path_reason"
/// and "general_steps", the steps before a failure kept.
#[pyfunction]
#[pyo3(signature = (model, times, parameters, q_guess=None, points=None, progress=None, progress_every=0,
                    derivatives=2, efforts=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn sensitivities<'py>(
    py: Python<'py>,
    model: PyRef<'py, PyModel>,
    times: PyReadonlyArray1<'py, f64>,
    parameters: Vec<String>,
    q_guess: Option<PyReadonlyArray1<'py, f64>>,
    points: Option<Vec<(i64, f64, f64, i64)>>,
    progress: Option<Py<PyAny>>,
    progress_every: usize,
    derivatives: u8,
    efforts: bool,
) -> PyResult<(Bound<'py, PyDict>, Option<PyErr>)> {
    if derivatives > 2 {
        return Err(InputError::new_err(format!("derivatives must be 0, 1 or 2, not {derivatives}")));
    }
    let m = std::sync::Arc::clone(&model.model);
    let params = parameters
        .iter()
        .map(|name| Parameter::resolve(&m, name).map_err(|e| ParameterError::new_err(e.to_string())))
        .collect::<PyResult<Vec<_>>>()?;
    let index = |i: i64, what: &str, n: usize| -> PyResult<Option<usize>> {
        match i {
            -1 => Ok(None),
            i if i >= 0 && (i as usize) < n => Ok(Some(i as usize)),
            i => Err(InputError::new_err(format!("a point's {what} index {i} does not exist"))),
        }
    };
    let requests = points
        .unwrap_or_default()
        .into_iter()
        .map(|(b, ux, uy, named)| {
            Ok(PointRequest {
                body: index(b, "body", m.n_bodies)?,
                local: [ux, uy],
                named: index(named, "named point", m.points.len())?,
            })
        })
        .collect::<PyResult<Vec<_>>>()?;
    let times = times.as_slice()?;
    let mut data = Data::new(&m);
    data.q = model.start_q(py, q_guess, times)?;
    if efforts && derivatives != 2 {
        return Err(InputError::new_err(format!(
            "the efforts' sensitivities need dqdd/dp: derivatives=2 with efforts=True, not {derivatives}"
        )));
    }
    let request = SensitivityRequest { derivatives, ..SensitivityRequest::default() };
    let mut out = if efforts {
        SensitivityOutput::with_efforts(&m, times, &params, requests.len())
    } else {
        SensitivityOutput::with_request(&m, times, &params, requests.len(), request)
    };
    let total = times.len();
    laws::clear(&model.failures);
    let (result, interrupt) = py.detach(|| {
        let mut interrupt: Option<PyErr> = None;
        let mut on_progress = |k: usize| poll_progress(&progress, total, k, &mut interrupt);
        let r = guard("solving sensitivities", || {
            sensitivity_sweep(
                &m,
                &mut data,
                times,
                &params,
                &requests,
                &mut out,
                progress_every,
                &mut on_progress,
            )
        });
        (r, interrupt)
    });
    let error = run_error(result, interrupt, |e| model.solve_err(py, e));
    let SensitivityOutput {
        mut sweep,
        names,
        n_params,
        n_points,
        request,
        n_done,
        path,
        path_reason,
        general_steps,
        dq,
        dqd,
        dqdd,
        points,
        points_d,
        points_dd,
        dlambda,
        ..
    } = out;
    sweep.truncate();
    let nc = m.n_coords;
    let d = output_dict(py, sweep)?;
    // an array of a derivative not asked for is empty: None
    let per_step = |mut v: Vec<f64>, order: u8| {
        (request.derivatives >= order).then(|| {
            v.truncate(n_done * nc * n_params);
            Array3::from_shape_vec((n_done, nc, n_params), v)
                .expect("steps x coords x params")
                .into_pyarray(py)
        })
    };
    let per_point = |mut v: Vec<f64>, order: u8| {
        (request.derivatives >= order).then(|| {
            v.truncate(n_done * n_points * 2 * n_params);
            Array4::from_shape_vec((n_done, n_points, 2, n_params), v)
                .expect("steps x points x 2 x params")
                .into_pyarray(py)
        })
    };
    d.set_item("names", names)?;
    d.set_item("nominal", params.iter().map(|p| p.nominal).collect::<Vec<f64>>())?;
    d.set_item("dq", per_step(dq, 0))?;
    d.set_item("dqd", per_step(dqd, 1))?;
    d.set_item("dqdd", per_step(dqdd, 2))?;
    d.set_item("sens_points", per_point(points, 0))?;
    d.set_item("sens_points_d", per_point(points_d, 1))?;
    d.set_item("sens_points_dd", per_point(points_dd, 2))?;
    d.set_item("derivatives", request.derivatives)?;
    d.set_item("path", path.label())?;
    d.set_item("path_reason", path_reason)?;
    d.set_item("general_steps", general_steps)?;
    if efforts {
        let nr = m.n_rows;
        let mut v = dlambda;
        v.truncate(n_done * nr * n_params);
        let a = Array3::from_shape_vec((n_done, nr, n_params), v).expect("steps x rows x params");
        d.set_item("dlambda", a.into_pyarray(py))?;
    }
    Ok((d, error))
}

//! Forward dynamics: a free model simulated over times, the GIL released, progress and
//! Ctrl-C polled every few steps, the rows done kept on failure.

use std::sync::Arc;

use linkwork::dynamics::record::solve_rows;
use linkwork::dynamics::{Method, SimOptions, SimOutput};
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::{guard, laws, poll_progress, rows_to_array, run_error, InputError, PyModel};

fn optional(a: Option<PyReadonlyArray1<'_, f64>>) -> PyResult<Option<Vec<f64>>> {
    a.map(|a| Ok(a.as_slice()?.to_vec())).transpose()
}

/// Simulates `model` (compiled with free=True) over `times` from q0, qd0 (default: the
/// drawing at rest), made consistent first. Returns (dict of arrays, error or None):
/// "times", "q", "qd" (n x n_coords), "drift", "drift_d", "kinetic", "potential",
/// "work", "step", "iterations" (n), "n_steps", "n_rejected", "n_evaluations",
/// "moved_q", "moved_qd", "events" (dicts as a sweep's). `progress(done, total)` counts the asked times reached.
/// `at_travel_end`: "stop" (the run ends where a slider reaches an end of its travel, the
/// rows before it kept) or "continue" (reported, the motion goes on).
#[pyfunction]
#[pyo3(signature = (model, times, q0=None, qd0=None, method="rk8", rtol=1e-8, atol=1e-8, rho_inf=0.9,
                    h0=None, h_max=None, max_steps=None, ic_tol=1e-6, progress=None, at_travel_end="stop"))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn simulate<'py>(
    py: Python<'py>,
    model: PyRef<'py, PyModel>,
    times: PyReadonlyArray1<'py, f64>,
    q0: Option<PyReadonlyArray1<'py, f64>>,
    qd0: Option<PyReadonlyArray1<'py, f64>>,
    method: &str,
    rtol: f64,
    atol: f64,
    rho_inf: f64,
    h0: Option<f64>,
    h_max: Option<f64>,
    max_steps: Option<usize>,
    ic_tol: f64,
    progress: Option<Py<PyAny>>,
    at_travel_end: &str,
) -> PyResult<(Bound<'py, PyDict>, Option<PyErr>)> {
    let method = Method::from_name(method).ok_or_else(|| {
        InputError::new_err(format!("method must be \"rk8\" or \"gen-alpha\", not {method:?}"))
    })?;
    let stop_at_travel_end = match at_travel_end {
        "stop" => true,
        "continue" => false,
        _ => {
            return Err(InputError::new_err(format!(
                "at_travel_end must be \"stop\" or \"continue\", not {at_travel_end:?}"
            )))
        }
    };
    let d = SimOptions::default();
    let opts = SimOptions {
        method,
        rtol,
        atol,
        rho_inf,
        h0,
        h_max: h_max.unwrap_or(d.h_max),
        max_steps: max_steps.unwrap_or(d.max_steps),
        ic_tol,
        // qdd, the multipliers and reactions are solved when asked (`simulation_rows`)
        accelerations: false,
        stop_at_travel_end,
    };
    opts.check().map_err(InputError::new_err)?;
    let m = Arc::clone(&model.model);
    let times = times.as_slice()?.to_vec();
    let (q0, qd0) = (optional(q0)?, optional(qd0)?);
    let total = times.len();
    laws::clear(&model.failures);
    let mut out = SimOutput::new(&m, &times);
    let (result, interrupt) = py.detach(|| {
        let mut interrupt: Option<PyErr> = None;
        let mut poll = |k: usize| poll_progress(&progress, total, k, &mut interrupt);
        let r = guard("simulating", || {
            linkwork::dynamics::simulate(
                &m,
                &times,
                q0.as_deref(),
                qd0.as_deref(),
                &opts,
                &mut out,
                &mut poll,
            )
        });
        (r, interrupt)
    });
    if matches!(result, Ok(Ok(()))) {
        if let Some(cb) = &progress {
            cb.call1(py, (total, total))?;
        }
    }
    let error = run_error(result, interrupt, |e| model.solve_err(py, e));
    out.truncate();
    let (k, n) = (out.n_done, out.n_coords);
    let d = PyDict::new(py);
    d.set_item(intern!(py, "times"), out.times.into_pyarray(py))?;
    d.set_item(intern!(py, "q"), rows_to_array(py, out.q, k, n))?;
    d.set_item(intern!(py, "qd"), rows_to_array(py, out.qd, k, n))?;
    for (name, v) in [
        (intern!(py, "drift"), out.drift),
        (intern!(py, "drift_d"), out.drift_d),
        (intern!(py, "kinetic"), out.kinetic),
        (intern!(py, "potential"), out.potential),
        (intern!(py, "work"), out.work),
        (intern!(py, "step"), out.step),
    ] {
        d.set_item(name, v.into_pyarray(py))?;
    }
    d.set_item(intern!(py, "iterations"), out.iterations.into_pyarray(py))?;
    d.set_item(intern!(py, "n_steps"), out.n_steps)?;
    d.set_item(intern!(py, "n_rejected"), out.n_rejected)?;
    d.set_item(intern!(py, "n_evaluations"), out.n_evaluations)?;
    d.set_item(intern!(py, "moved_q"), out.moved.q)?;
    d.set_item(intern!(py, "moved_qd"), out.moved.qd)?;
    let events = out.events.iter().map(|e| crate::events::event_dict(py, e)).collect::<PyResult<Vec<_>>>()?;
    d.set_item(intern!(py, "events"), events)?;
    Ok((d, error))
}

/// The index-1 solve at every row of a simulation (its times, projected q and qd): a
/// dict of "qdd" (n x n_coords), "lambda" (n x n_rows, in the rows' units),
/// "reactions" (n x n_constraints x 4) and "pivot_ratio" (n).
#[pyfunction]
pub(crate) fn simulation_rows<'py>(
    py: Python<'py>,
    model: PyRef<'py, PyModel>,
    times: PyReadonlyArray1<'py, f64>,
    q: PyReadonlyArray2<'py, f64>,
    qd: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let m = Arc::clone(&model.model);
    let (times, q, qd) = (times.as_slice()?.to_vec(), q.as_array(), qd.as_array());
    let (k, n, r, nc) = (times.len(), m.n_coords, m.n_rows, m.constraints.len());
    if q.shape() != [k, n] || qd.shape() != [k, n] {
        return Err(InputError::new_err(format!(
            "q and qd must be {k} x {n} (a row per time, a column per coordinate), not {:?} and {:?}",
            q.shape(),
            qd.shape()
        )));
    }
    let mut out = SimOutput::new(&m, &times);
    out.q = q.iter().copied().collect();
    out.qd = qd.iter().copied().collect();
    out.n_done = k;
    laws::clear(&model.failures);
    let result = py.detach(|| guard("solving the rows of a simulation", || solve_rows(&m, &mut out)));
    if let Some(e) = run_error(result, None, |e| model.solve_err(py, e)) {
        return Err(e);
    }
    let d = PyDict::new(py);
    d.set_item("qdd", rows_to_array(py, out.qdd, k, n))?;
    d.set_item("lambda", rows_to_array(py, out.lambda, k, r))?;
    let reactions = Array3::from_shape_vec((k, nc, linkwork::REACTION_COLUMNS), out.reactions)
        .expect("n x constraints x 4 buffer");
    d.set_item("reactions", reactions.into_pyarray(py))?;
    d.set_item("pivot_ratio", out.pivot_ratio.into_pyarray(py))?;
    Ok(d)
}

//! A design study's designs as variants of one compiled model, built and swept on the
//! engine's threads, their kept figures returned stacked.

use linkwork::sensitivity::Parameter;
use linkwork::{Outputs, SolveError, VariantFigures, Variation};
use numpy::ndarray::{Array3, Array4};
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::sensitivity::ParameterError;
use crate::{batch_watch, guard, parse_request, solve_err, InputError, PyModel};

/// Sweeps the designs `deltas` (n x len(parameters): each row a design's changes of the
/// engine parameters, named as for `sensitivities`) of `model` over `times` on `threads`
/// threads, the GIL released, keeping the coordinates `coords` and the body `points`
/// ((body index, -1 the ground; u_x, u_y; named point index or -1: a named point moves
/// with its parameters)). Returns a dict: "q" (n x steps x len(coords)), "points" (n x
/// steps x len(points) x 2), NaN past a design's last step; "pivot_min", "events",
/// "n_done" (n); "errors": [(design, exception)]. `progress(done, total)` counts designs.
#[pyfunction]
#[pyo3(signature = (model, parameters, deltas, times, coords, points, derivatives=0,
                    on_singular="continue", threads=0, progress=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn sweep_variants<'py>(
    py: Python<'py>,
    model: PyRef<'py, PyModel>,
    parameters: Vec<String>,
    deltas: PyReadonlyArray2<'py, f64>,
    times: PyReadonlyArray1<'py, f64>,
    coords: Vec<usize>,
    points: Vec<(i64, f64, f64, i64)>,
    derivatives: u8,
    on_singular: &str,
    threads: usize,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let m = std::sync::Arc::clone(&model.model);
    let params = parameters
        .iter()
        .map(|name| Parameter::resolve(&m, name).map_err(|e| ParameterError::new_err(e.to_string())))
        .collect::<PyResult<Vec<_>>>()?;
    let request = parse_request(derivatives, false, 1, on_singular, false)?;
    let shape = deltas.shape();
    if shape[1] != params.len() {
        return Err(InputError::new_err(format!(
            "deltas has {} columns for {} parameters",
            shape[1],
            params.len()
        )));
    }
    let n = shape[0];
    let deltas = deltas.as_array().iter().copied().collect::<Vec<f64>>();
    if let Some(i) = deltas.iter().position(|d| !d.is_finite()) {
        return Err(InputError::new_err(format!(
            "design {}: the change of parameter {:?} is not finite",
            i / params.len().max(1),
            parameters[i % params.len().max(1)]
        )));
    }
    let mut named = Vec::with_capacity(points.len());
    let mut kept = Vec::with_capacity(points.len());
    for (b, ux, uy, k) in points {
        let body = match b {
            -1 => None,
            b if b >= 0 && (b as usize) < m.n_bodies => Some(b as usize),
            b => return Err(InputError::new_err(format!("a point's body index {b} does not exist"))),
        };
        named.push(match k {
            k if k >= 0 && (k as usize) < m.points.len() => Some(k as usize),
            _ => None,
        });
        kept.push((body, [ux, uy]));
    }
    let outputs = Outputs { coords: Some(coords), points: kept };
    outputs.check(&m).map_err(|e| solve_err(py, &e))?;
    let times = times.as_slice()?;
    let bytes = VariantFigures::bytes(&m, n, times.len(), &outputs);
    let available = linkwork::available_memory();
    if available.is_some_and(|a| bytes > a) {
        let e = SolveError::TooLarge {
            bytes,
            available,
            steps: times.len(),
            n_coords: outputs.n_kept(&m) + 2 * outputs.points.len(),
            what: format!(": the kept figures of {n} designs"),
        };
        return Err(solve_err(py, &e));
    }
    let (figures, interrupt) = py.detach(|| {
        let variation = Variation::new(&m, params);
        let mut interrupt: Option<PyErr> = None;
        let mut watch = batch_watch(&progress, n, &mut interrupt);
        let figures = guard("sweeping a study's designs", || {
            linkwork::sweep_variants(
                &m, &variation, n, &deltas, times, request, &outputs, &named, threads, &mut watch,
            )
        });
        drop(watch);
        (figures, interrupt)
    });
    let figures = figures?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    if let Some(cb) = &progress {
        cb.call1(py, (n, n))?;
    }
    let VariantFigures { n_steps, q, points, pivot_min, events, n_done, errors, .. } = figures;
    let d = PyDict::new(py);
    let np = outputs.points.len();
    d.set_item(
        "q",
        Array3::from_shape_vec((n, n_steps, outputs.n_kept(&m)), q)
            .expect("designs x steps x kept")
            .into_pyarray(py),
    )?;
    d.set_item(
        "points",
        Array4::from_shape_vec((n, n_steps, np, 2), points)
            .expect("designs x steps x points x 2")
            .into_pyarray(py),
    )?;
    d.set_item("pivot_min", pivot_min.into_pyarray(py))?;
    d.set_item("events", events.into_pyarray(py))?;
    d.set_item("n_done", n_done.into_pyarray(py))?;
    let errors = errors
        .iter()
        .enumerate()
        .filter_map(|(i, e)| e.as_ref().map(|e| (i, solve_err(py, e))))
        .collect::<Vec<_>>();
    d.set_item("errors", errors)?;
    Ok(d)
}

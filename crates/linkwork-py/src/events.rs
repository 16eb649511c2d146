//! Sweep events and limits of motion as Python dicts.

use linkwork::analysis::limits::{motion_limits as engine_limits, LimitsError};
use linkwork::stepping::singular::Event;
use linkwork::stepping::tracking::OnSingular;
use linkwork::Data;
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::{guard, model_err, solve_err, InputError, PyModel};

pub(crate) fn parse_on_singular(s: &str) -> PyResult<OnSingular> {
    match s {
        "continue" => Ok(OnSingular::Continue),
        "stop" => Ok(OnSingular::Stop),
        "switch" => Ok(OnSingular::Switch),
        other => Err(InputError::new_err(format!(
            "on_singular must be 'continue', 'stop' or 'switch', not {other:?}"
        ))),
    }
}

/// One event: kind, step, time, q, sigma_min, constraints, coordinates, output, drivers,
/// message, pivot_ratio.
pub(crate) fn event_dict<'py>(py: Python<'py>, e: &Event) -> PyResult<Bound<'py, PyDict>> {
    // the keys made Python strings once (a simulation returns an event per lock met)
    let d = PyDict::new(py);
    d.set_item(intern!(py, "kind"), e.kind.name())?;
    d.set_item(intern!(py, "step"), e.step)?;
    d.set_item(intern!(py, "time"), e.time)?;
    d.set_item(intern!(py, "q"), e.q.clone().into_pyarray(py))?;
    d.set_item(intern!(py, "sigma_min"), e.sigma_min)?;
    d.set_item(intern!(py, "constraints"), e.constraints.clone())?;
    d.set_item(intern!(py, "coordinates"), e.coordinates.clone())?;
    d.set_item(intern!(py, "output"), e.output.clone())?;
    d.set_item(intern!(py, "drivers"), e.drivers.clone())?;
    d.set_item(intern!(py, "message"), e.message.clone())?;
    d.set_item(intern!(py, "pivot_ratio"), e.pivot_ratio)?;
    Ok(d)
}

/// The range of a driver's input over which the mechanism assembles, on the branch of
/// q_guess at time t. Returns a dict: driver, angle, start, lower, upper (None: no limit
/// within `range`), full_rotation, range, events.
#[pyfunction]
#[pyo3(signature = (model, driver, t=0.0, q_guess=None, range=None, steps=None))]
pub(crate) fn motion_limits<'py>(
    py: Python<'py>,
    model: PyRef<'py, PyModel>,
    driver: &str,
    t: f64,
    q_guess: Option<PyReadonlyArray1<'py, f64>>,
    range: Option<f64>,
    steps: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let m = std::sync::Arc::clone(&model.model);
    let mut data = Data::new(&m);
    data.q = crate::assembled(py, &m, t, crate::guess(&m, q_guess)?, true)?;
    let q = data.q;
    if let Some(r) = range {
        if !(r.is_finite() && r > 0.0) {
            return Err(InputError::new_err(format!("range must be finite and > 0, not {r}")));
        }
    }
    let lim =
        py.detach(|| guard("finding the motion limits", || engine_limits(&m, driver, t, &q, range, steps)))?;
    let lim = lim.map_err(|e| match e {
        LimitsError::Model(e) => model_err(e),
        LimitsError::Solve(e) => solve_err(py, &e),
        LimitsError::NotADriver(_) => InputError::new_err(e.to_string()),
    })?;
    let d = PyDict::new(py);
    d.set_item("driver", lim.driver)?;
    d.set_item("angle", lim.angle)?;
    d.set_item("start", lim.start)?;
    d.set_item("lower", lim.lower)?;
    d.set_item("upper", lim.upper)?;
    d.set_item("full_rotation", lim.full_rotation)?;
    d.set_item("range", lim.range)?;
    let events = lim.events.iter().map(|e| event_dict(py, e)).collect::<PyResult<Vec<_>>>()?;
    d.set_item("events", events)?;
    Ok(d)
}

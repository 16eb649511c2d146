//! Motion laws from Python: callables bound to the description's `{"type": "python"}`
//! laws, their exceptions kept for the error report, and the expression parser and law
//! evaluation exposed for checking and plotting.

use std::sync::{Arc, Mutex};

use linkwork::description::LoadDesc;
use linkwork::{Description, ExprError, Expression, ExternalFn, MotionLaw};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray1};
use pyo3::exceptions::{PyException, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

pyo3::import_exception!(linkwork.errors, ExpressionError);

/// The last exception raised by a model's Python laws, waiting for the error report of
/// the solve that met it (`chain_failure`).
pub(crate) type Failures = Arc<Mutex<Option<PyErr>>>;

/// A Python callable f(t) -> (f, f', f'') as an engine law function. The GIL is taken
/// for each call (solves and sweeps run with it released).
fn external(name: String, func: Py<PyAny>, failures: Failures) -> ExternalFn {
    Arc::new(move |t: f64| {
        Python::attach(|py| {
            let result = func.call1(py, (t,)).and_then(|r| {
                let r = r.bind(py);
                r.extract::<[f64; 3]>().map_err(|_| {
                    let shown = r.repr().map_or_else(|_| "?".to_string(), |s| s.to_string());
                    PyTypeError::new_err(format!(
                        "python law '{name}' must return 3 numbers (value, first derivative, second \
                         derivative), got {shown}"
                    ))
                })
            });
            result.map_err(|e| {
                let why = e.to_string();
                if let Ok(mut slot) = failures.lock() {
                    *slot = Some(e);
                }
                why
            })
        })
    })
}

/// Binds the callables of `python_laws` (name -> callable) to the python laws of every
/// driver and load of `desc`; a law left without one is refused when compiling.
pub(crate) fn bind(
    desc: &mut Description,
    python_laws: Option<&Bound<'_, PyDict>>,
    failures: &Failures,
) -> PyResult<()> {
    let Some(funcs) = python_laws else { return Ok(()) };
    let mut table: Vec<(String, Py<PyAny>)> = Vec::with_capacity(funcs.len());
    for (k, v) in funcs.iter() {
        let name: String = k.extract()?;
        if !v.is_callable() {
            return Err(PyTypeError::new_err(format!("python_laws['{name}'] is not callable")));
        }
        table.push((name, v.unbind()));
    }
    let attach = |law: &mut MotionLaw| {
        law.for_each_mut(&mut |l| {
            if let MotionLaw::Python(x) = l {
                if let Some((_, f)) = table.iter().find(|(n, _)| *n == x.name) {
                    let func = Python::attach(|py| f.clone_ref(py));
                    x.bind(external(x.name.clone(), func, Arc::clone(failures)));
                }
            }
        })
    };
    for d in desc.drivers.iter_mut() {
        attach(d.law_mut());
    }
    for l in desc.loads.iter_mut() {
        if let LoadDesc::Force { law, .. } | LoadDesc::Torque { law, .. } | LoadDesc::JointForce { law, .. } =
            l
        {
            attach(law);
        }
    }
    Ok(())
}

/// Gives `err` (the error of a solve) the Python exception that made the law fail as
/// its `__cause__`; an interrupt (KeyboardInterrupt, SystemExit) raised in the callable
/// is returned as it is.
pub(crate) fn chain_failure(py: Python<'_>, err: PyErr, failures: &Failures) -> PyErr {
    let cause = failures.lock().ok().and_then(|mut slot| slot.take());
    match cause {
        Some(cause) if !cause.is_instance_of::<PyException>(py) => cause,
        Some(cause) => {
            err.set_cause(py, Some(cause));
            err
        }
        None => err,
    }
}

/// Forgets an exception left by an earlier solve (one rescued by a sub-step, say).
pub(crate) fn clear(failures: &Failures) {
    if let Ok(mut slot) = failures.lock() {
        slot.take();
    }
}

fn expr_err(text: &str, e: ExprError) -> PyErr {
    let err = ExpressionError::new_err(e.to_string());
    Python::attach(|py| {
        let value = err.value(py);
        // attributes of an exception we created ourselves: setting them cannot fail in practice
        let _ = value.setattr("column", e.column);
        let _ = value.setattr("text", text);
        let _ = value.setattr("hint", e.hint.clone());
    });
    err
}

/// Parses `text` as an expression of `variable`; raises ExpressionError (with `.column`)
/// if it is not one.
#[pyfunction]
#[pyo3(signature = (text, variable="t"))]
fn parse_expression(text: &str, variable: &str) -> PyResult<()> {
    crate::guard("parsing an expression", || Expression::parse(text, variable))?
        .map(|_| ())
        .map_err(|e| expr_err(text, e))
}

/// (f, f', f'') of a motion law (a description's law as JSON) at each time: n x 3.
#[pyfunction]
#[pyo3(signature = (law_json, times, python_laws=None))]
fn evaluate_law<'py>(
    py: Python<'py>,
    law_json: &str,
    times: PyReadonlyArray1<'py, f64>,
    python_laws: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let model_err = |m: String| crate::py_errors::ModelError::new_err(format!("motion law: {m}"));
    let mut law = MotionLaw::from_json(law_json).map_err(model_err)?;
    let failures: Failures = Arc::default();
    if let Some(funcs) = python_laws {
        law.for_each_mut(&mut |l| {
            if let MotionLaw::Python(x) = l {
                if let Ok(Some(f)) = funcs.get_item(&x.name) {
                    x.bind(external(x.name.clone(), f.unbind(), Arc::clone(&failures)));
                }
            }
        });
    }
    crate::guard("preparing a motion law", || law.prepare())?.map_err(model_err)?;
    let times = times.as_slice()?;
    if let Some((lo, hi)) = law.domain() {
        if let Some(t) = times.iter().find(|&&t| !(t >= lo && t <= hi)) {
            return Err(crate::InputError::new_err(format!(
                "t = {t} is outside the law's table [{lo}, {hi}]"
            )));
        }
    }
    let mut out = Vec::with_capacity(3 * times.len());
    for &t in times {
        let v = crate::guard("evaluating a motion law", || law.eval(t))?;
        if let Some(e) = failures.lock().ok().and_then(|mut s| s.take()) {
            return Err(e);
        }
        out.extend_from_slice(&v);
    }
    let array = Array2::from_shape_vec((times.len(), 3), out).expect("n x 3 buffer");
    Ok(array.into_pyarray(py))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(parse_expression, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate_law, m)?)?;
    Ok(())
}

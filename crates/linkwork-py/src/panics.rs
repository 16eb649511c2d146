//! Panics stop here. A panic in the engine is a bug in linkwork; where Python calls in it
//! becomes `linkwork.errors.InternalError`, an ordinary exception that names the
//! operation, rather than PyO3's PanicException, which `except Exception` does not catch.

use std::any::Any;
use std::panic::{catch_unwind, AssertUnwindSafe};

use pyo3::prelude::*;

pyo3::import_exception!(linkwork.errors, InternalError);

/// Runs `f` (engine work: `what` says which, in the error), catching a panic.
pub(crate) fn guard<T>(what: &str, f: impl FnOnce() -> T) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|payload| internal_err(what, payload.as_ref()))
}

/// The InternalError for a caught panic's payload.
pub(crate) fn internal_err(what: &str, payload: &(dyn Any + Send)) -> PyErr {
    let msg = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "no message".to_string());
    InternalError::new_err(format!(
        "internal error in linkwork while {what}: {msg} (a bug in linkwork: please report it with the model)"
    ))
}

/// Panics inside `guard`: the test that a panic reaches Python as InternalError.
#[pyfunction]
pub(crate) fn _check_panic_guard() -> PyResult<()> {
    guard("checking the panic guard", || -> () { panic!("deliberate panic") })
}

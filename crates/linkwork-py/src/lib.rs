//! PyO3 bindings of the linkwork engine: conversion, errors and GIL release only.
//! The public Python API is the plain-Python package `linkwork` on top of this.

use std::sync::Arc;

use linkwork::memory::{Block, Column};
use linkwork::model::OnRedundant;
use linkwork::stepping::singular::Event;
use linkwork::{Data, Description, LinearKind, Model, ModelError, Options, SolveError, SweepOutput};
use numpy::ndarray::{Array2, ArrayView, Dimension, IntoDimension, Ix1};
use numpy::{IntoPyArray, PyArray, PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

mod dynamics;
mod equilibrium;
mod events;
mod laws;
mod linkages;
mod load_power;
mod mobility;
mod panics;
mod screw;
mod sensitivity;
mod synthesis;
mod variants;

use panics::guard;

mod py_errors {
    pyo3::import_exception!(linkwork.errors, ModelError);
}
use py_errors::ModelError as PyModelError;
pyo3::import_exception!(linkwork.errors, InputError);
pyo3::import_exception!(linkwork.errors, ClosureError);
pyo3::import_exception!(linkwork.errors, AssemblyError);
pyo3::import_exception!(linkwork.errors, ConvergenceError);
pyo3::import_exception!(linkwork.errors, SingularError);
pyo3::import_exception!(linkwork.errors, NonFiniteError);
pyo3::import_exception!(linkwork.errors, CancelledError);
pyo3::import_exception!(linkwork.errors, FreeModelError);
pyo3::import_exception!(linkwork.errors, InitialConditionError);
pyo3::import_exception!(linkwork.errors, MasslessError);
pyo3::import_exception!(linkwork.errors, IntegrationError);
pyo3::import_exception!(linkwork.errors, StiffnessError);

fn model_err(e: ModelError) -> PyErr {
    let inner = match &e {
        ModelError::Located { error, .. } => error.as_ref(),
        other => other,
    };
    let err = match inner {
        ModelError::NotClosed { .. } => ClosureError::new_err(e.to_string()),
        _ => PyModelError::new_err(e.to_string()),
    };
    // (kind, name) of the element at fault, so that a file's reader can add its line
    Python::attach(|py| {
        let element = e.element().map(|(kind, name)| (kind.to_string(), name.to_string()));
        let value = err.value(py);
        let _ = value.setattr("element", element);
        if let ModelError::NotClosed { joint, miss, .. } = inner {
            let _ = value.setattr("joint", joint);
            let _ = value.setattr("miss", *miss);
        }
    });
    err
}

fn parse_format(format: &str) -> PyResult<linkwork::Format> {
    linkwork::Format::from_name(format)
        .ok_or_else(|| PyValueError::new_err(format!("format must be 'toml' or 'json', not {format:?}")))
}

/// Reads a model file's text (`format` "toml" or "json"; `file` names it in errors).
/// Returns the flat description as JSON, keys and numbers as written, and the
/// (kind, name, line) of every named element.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn read_model(text: &str, format: &str, file: &str) -> PyResult<(String, Vec<(String, String, usize)>)> {
    let format = parse_format(format)?;
    let read =
        guard("reading a model file", || linkwork::files::read(text, format, file))?.map_err(model_err)?;
    let lines = read.source.elements.into_iter().map(|(k, n, l)| (k.to_string(), n, l)).collect();
    Ok((linkwork::files::flat_json(&read.flat), lines))
}

/// Writes a flat description (JSON) as a model file's text (`format` "toml" or "json").
#[pyfunction]
fn write_model(description_json: &str, format: &str) -> PyResult<String> {
    let format = parse_format(format)?;
    guard("writing a model file", || linkwork::files::write(description_json, format))?.map_err(model_err)
}

/// The one place where engine solve errors become Python exceptions; each carries
/// `.step` (the time step at fault, or None) and `.time` where known.
fn solve_err(py: Python<'_>, e: &SolveError) -> PyErr {
    let msg = e.to_string();
    let (err, time) = match e {
        SolveError::Assembly { time, .. } | SolveError::AssemblyBranch { time, .. } => {
            (AssemblyError::new_err(msg), Some(*time))
        }
        SolveError::NoConvergence { time, .. } => (ConvergenceError::new_err(msg), Some(*time)),
        SolveError::Singular { time, .. } => (SingularError::new_err(msg), Some(*time)),
        SolveError::NonFinite { time, .. } => (NonFiniteError::new_err(msg), Some(*time)),
        SolveError::Times { .. } => (InputError::new_err(msg), None),
        SolveError::OutOfRange { time, .. } => (InputError::new_err(msg), Some(*time)),
        SolveError::TooLarge { .. } | SolveError::Outputs { .. } | SolveError::Settings { .. } => {
            (InputError::new_err(msg), None)
        }
        SolveError::Cancelled { .. } => (CancelledError::new_err(msg), None),
        SolveError::Event { time, .. } => (SingularError::new_err(msg), Some(*time)),
        SolveError::Free { .. } => (FreeModelError::new_err(msg), None),
        SolveError::Inconsistent { .. } => (InitialConditionError::new_err(msg), None),
        SolveError::Massless { time, .. } => (MasslessError::new_err(msg), Some(*time)),
        SolveError::Step { time, .. } => (IntegrationError::new_err(msg), Some(*time)),
        SolveError::Stiff { time, .. } => (StiffnessError::new_err(msg), Some(*time)),
    };
    let value = err.value(py);
    // attributes of an exception we created ourselves: setting them cannot fail in practice
    let _ = value.setattr("step", e.step());
    let _ = value.setattr("time", time);
    err
}

fn parse_linear(s: &str) -> PyResult<LinearKind> {
    match s {
        "auto" => Ok(LinearKind::Auto),
        "small" => Ok(LinearKind::Small),
        "dense" => Ok(LinearKind::Dense),
        "sparse" => Ok(LinearKind::Sparse),
        "refactor" => Ok(LinearKind::Refactor),
        other => Err(PyValueError::new_err(format!(
            "linear must be 'auto', 'refactor', 'small', 'dense' or 'sparse', not {other:?}"
        ))),
    }
}

fn linear_name(k: LinearKind) -> &'static str {
    match k {
        LinearKind::Auto => "auto",
        LinearKind::Small => "small",
        LinearKind::Dense => "dense",
        LinearKind::Sparse => "sparse",
        LinearKind::Refactor => "refactor",
        LinearKind::LeastSquares => "least_squares",
    }
}

/// A compiled mechanism (immutable; every solve gets its own workspace).
#[pyclass(frozen, module = "linkwork._core", name = "Model")]
struct PyModel {
    model: Arc<Model>,
    /// the last exception of its Python laws, for the error report
    failures: laws::Failures,
    /// as the description declared them (the compiled model holds angles in radians)
    units: linkwork::Units,
}

/// q at t: assembled from the guess (with `assemble`; else as given), or without a
/// guess, the drawing's branch followed to t (`along`).
fn assembled(
    py: Python<'_>,
    m: &Arc<Model>,
    t: f64,
    q_guess: Option<Vec<f64>>,
    assemble: bool,
) -> PyResult<Vec<f64>> {
    match (q_guess, assemble) {
        (None, true) => Ok(along(py, m, t)?.0.q),
        (q, _) => {
            let mut data = Data::new(m);
            data.q = q.unwrap_or_else(|| m.q_start.clone());
            if assemble {
                linkwork::check_times(m, &[t]).map_err(|e| solve_err(py, &e))?;
                guard("assembling", || linkwork::solve_position(m, &mut data, t, 0, true))?
                    .map_err(|e| solve_err(py, &e))?;
            }
            Ok(data.q)
        }
    }
}

/// The drawing's configuration followed along the drivers to t (`linkwork::solve_along`),
/// with the GIL released and Ctrl-C noticed on the way: the solved workspace, its
/// diagnostics and the events met.
fn along(py: Python<'_>, m: &Arc<Model>, t: f64) -> PyResult<(Data, linkwork::PositionInfo, Vec<Event>)> {
    let model = Arc::clone(m);
    let (result, interrupt) = py.detach(|| {
        let mut data = Data::new(&model);
        let mut interrupt: Option<PyErr> = None;
        let mut poll = || -> bool {
            Python::attach(|py| match py.check_signals() {
                Ok(()) => true,
                Err(e) => {
                    interrupt = Some(e);
                    false
                }
            })
        };
        let r = guard("solving", || linkwork::solve_along(&model, &mut data, t, &mut poll));
        (r.map(|r| r.map(|(info, events)| (data, info, events))), interrupt)
    });
    match (result?, interrupt) {
        (Ok(r), _) => Ok(r),
        (Err(_), Some(e)) => Err(e),
        (Err(e), None) => Err(solve_err(py, &e)),
    }
}

/// q_guess checked (length, finite), or None.
fn guess(model: &Model, q_guess: Option<PyReadonlyArray1<'_, f64>>) -> PyResult<Option<Vec<f64>>> {
    q_guess.map(|g| start_guess(model, Some(g))).transpose()
}

fn start_guess(model: &Model, q_guess: Option<PyReadonlyArray1<'_, f64>>) -> PyResult<Vec<f64>> {
    match q_guess {
        None => Ok(model.q_start.clone()),
        Some(a) => {
            let q = a.as_slice()?.to_vec();
            if q.len() != model.n_coords {
                return Err(InputError::new_err(format!(
                    "q_guess has {} entries; the model has {} coordinates",
                    q.len(),
                    model.n_coords
                )));
            }
            if let Some(i) = q.iter().position(|v| !v.is_finite()) {
                return Err(InputError::new_err(format!(
                    "q_guess[{i}] ({}) is not finite",
                    model.columns[i]
                )));
            }
            Ok(q)
        }
    }
}

fn rows_to_array<'py>(py: Python<'py>, v: Vec<f64>, n: usize, m: usize) -> Bound<'py, PyAny> {
    // moves the buffer into NumPy: no copy
    Array2::from_shape_vec((n, m), v).expect("n x m buffer").into_pyarray(py).into_any()
}

/// Keeps a sweep's output memory (the `Block` its columns share) alive while a NumPy
/// array over it lives: the arrays' base.
#[pyclass(frozen, module = "linkwork._core")]
struct OutputMemory(#[allow(dead_code)] Arc<Block>);

/// The base objects of a sweep's arrays: one per Block (a sweep's columns share one).
#[derive(Default)]
struct Owners<'py> {
    last: Option<(Arc<Block>, Bound<'py, PyAny>)>,
}

impl<'py> Owners<'py> {
    /// A sweep's output column moved into NumPy, no copy: an array of `shape` over its
    /// elements, whose base keeps their Block.
    fn array<T, D>(&mut self, py: Python<'py>, column: Column<T>, shape: D) -> PyResult<Bound<'py, PyAny>>
    where
        T: numpy::Element + Copy,
        D: IntoDimension,
    {
        let shape = shape.into_dimension();
        assert_eq!(shape.size(), column.len(), "an output column of the shape asked");
        let Some(block) = column.block() else {
            // no elements, no memory
            return Ok(PyArray::<T, _>::zeros(py, shape, false).into_any());
        };
        let owner = match &self.last {
            Some((b, owner)) if Arc::ptr_eq(b, block) => owner.clone(),
            _ => {
                let owner = Bound::new(py, OutputMemory(Arc::clone(block)))?.into_any();
                self.last = Some((Arc::clone(block), owner.clone()));
                owner
            }
        };
        // SAFETY: the column's elements, shape.size() of them, initialised, contiguous,
        // row-major, lie in the Block that `owner` (the array's base, kept as long as the
        // array is) keeps alive and never moves; no other column covers them
        let array = unsafe {
            let view = ArrayView::from_shape_ptr(shape, column.as_ptr());
            PyArray::borrow_from_array(&view, owner)
        };
        Ok(array.into_any())
    }

    /// `array` of one dimension.
    fn array_1d<T>(&mut self, py: Python<'py>, column: Column<T>) -> PyResult<Bound<'py, PyAny>>
    where
        T: numpy::Element + Copy,
    {
        let n = column.len();
        self.array(py, column, Ix1(n))
    }
}

fn parse_request(
    derivatives: u8,
    forces: bool,
    every: usize,
    on_singular: &str,
    locks: bool,
) -> PyResult<linkwork::Request> {
    if derivatives > 2 || (forces && derivatives < 2) {
        return Err(InputError::new_err(format!(
            "derivatives must be 0, 1 or 2 (2 with forces=True), not {derivatives}"
        )));
    }
    if every == 0 {
        return Err(InputError::new_err("every must be at least 1"));
    }
    let on_singular = events::parse_on_singular(on_singular)?;
    Ok(linkwork::Request { derivatives, forces, every, on_singular, locks })
}

/// The coordinates (None: all) and body points ((body index, -1 the ground; u_x, u_y))
/// a sweep keeps.
/// One model's kept coordinates and points, as Python passes them (`parse_outputs`).
type KeptArg = (Option<Vec<usize>>, Option<Vec<(i64, f64, f64)>>);

fn parse_outputs(
    coords: Option<Vec<usize>>,
    points: Option<Vec<(i64, f64, f64)>>,
) -> PyResult<linkwork::Outputs> {
    let points = points
        .unwrap_or_default()
        .into_iter()
        .map(|(b, ux, uy)| {
            let body = match b {
                -1 => None,
                b if b >= 0 => Some(b as usize),
                b => {
                    return Err(InputError::new_err(format!(
                        "a point's body index must be -1 or more, not {b}"
                    )))
                }
            };
            Ok((body, [ux, uy]))
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok(linkwork::Outputs { coords, points })
}

/// A sweep's outputs as a dict of NumPy arrays (moved, not copied); qd and qdd are None
/// when not solved, the inverse dynamics arrays absent when not asked for.
fn output_dict<'py>(py: Python<'py>, out: SweepOutput) -> PyResult<Bound<'py, PyDict>> {
    let (n, m, np) = (out.n_done, out.n_kept, out.outputs.points.len());
    let d = PyDict::new(py);
    let derivatives = out.request.derivatives;
    let mut o = Owners::default();
    d.set_item("q", o.array(py, out.q, (n, m))?)?;
    d.set_item("qd", if derivatives >= 1 { Some(o.array(py, out.qd, (n, m))?) } else { None })?;
    d.set_item("qdd", if derivatives >= 2 { Some(o.array(py, out.qdd, (n, m))?) } else { None })?;
    if np > 0 {
        let shape = (n, np, 2);
        d.set_item("points", o.array(py, out.points, shape)?)?;
        d.set_item(
            "points_d",
            if derivatives >= 1 { Some(o.array(py, out.points_d, shape)?) } else { None },
        )?;
        d.set_item(
            "points_dd",
            if derivatives >= 2 { Some(o.array(py, out.points_dd, shape)?) } else { None },
        )?;
    }
    d.set_item("iterations", o.array_1d(py, out.iterations)?)?;
    d.set_item("residual", o.array_1d(py, out.residual)?)?;
    d.set_item("pivot_ratio", o.array_1d(py, out.pivot_ratio)?)?;
    d.set_item("times", o.array_1d(py, out.times)?)?;
    d.set_item("det_sign", o.array_1d(py, out.det_sign)?)?;
    let events = out.events.iter().map(|e| events::event_dict(py, e)).collect::<PyResult<Vec<_>>>()?;
    d.set_item("events", events)?;
    if out.request.forces {
        let (r, nc) = (out.n_rows, out.n_constraints);
        d.set_item("lambda", o.array(py, out.lambda, (n, r))?)?;
        let [pi, pg, pl] = out.lambda_parts;
        d.set_item("lambda_inertia", o.array(py, pi, (n, r))?)?;
        d.set_item("lambda_gravity", o.array(py, pg, (n, r))?)?;
        d.set_item("lambda_loads", o.array(py, pl, (n, r))?)?;
        d.set_item("reactions", o.array(py, out.reactions, (n, nc, linkwork::REACTION_COLUMNS))?)?;
        d.set_item("load_power", o.array_1d(py, out.load_power)?)?;
    }
    Ok(d)
}

/// Sweeps many models over the same times on worker threads with the GIL released.
/// Returns one (results dict, error or None) per model, in order. `progress(done, total)`
/// is called with the number of finished models; Ctrl-C cancels every running sweep.
/// `branches_of`: the model whose branches at the first time each model starts on.
#[pyfunction]
#[pyo3(signature = (models, times, threads=0, derivatives=2, forces=false, progress=None, every=1,
                    on_singular="continue", locks=false, branches_of=None, outputs=None))]
#[allow(clippy::too_many_arguments)]
fn sweep_batch<'py>(
    py: Python<'py>,
    models: Vec<PyRef<'py, PyModel>>,
    times: PyReadonlyArray1<'py, f64>,
    threads: usize,
    derivatives: u8,
    forces: bool,
    progress: Option<Py<PyAny>>,
    every: usize,
    on_singular: &str,
    locks: bool,
    branches_of: Option<PyRef<'py, PyModel>>,
    outputs: Option<Vec<KeptArg>>,
) -> PyResult<Vec<(Bound<'py, PyDict>, Option<PyErr>)>> {
    let request = parse_request(derivatives, forces, every, on_singular, locks)?;
    let arcs: Vec<Arc<Model>> = models.iter().map(|m| Arc::clone(&m.model)).collect();
    let refs: Vec<&Model> = arcs.iter().map(|m| m.as_ref()).collect();
    // each model's kept coordinates and points (None: all of every model's coordinates)
    let kept: Option<Vec<linkwork::Outputs>> = match outputs {
        Some(o) if o.len() != refs.len() => {
            return Err(InputError::new_err(format!(
                "outputs: one entry per model ({} models, {} entries)",
                refs.len(),
                o.len()
            )))
        }
        Some(o) => Some(
            o.into_iter()
                .zip(&refs)
                .map(|((coords, points), m)| {
                    let out = parse_outputs(coords, points)?;
                    out.check(m).map_err(|e| solve_err(py, &e))?;
                    Ok(out)
                })
                .collect::<PyResult<_>>()?,
        ),
        None => None,
    };
    let asked: Option<Arc<Model>> = branches_of.map(|m| Arc::clone(&m.model));
    let times = times.as_slice()?;
    let total = refs.len();
    // every model's outputs are kept until all are returned: refused up front if they
    // cannot all fit
    let all = linkwork::Outputs::all();
    let (bytes, what) = refs.iter().enumerate().fold((0usize, String::new()), |(b, _), (i, m)| {
        let o = kept.as_ref().map_or(&all, |k| &k[i]);
        let (mb, what) = SweepOutput::bytes(m, times.len(), request, o);
        (b.saturating_add(mb), what)
    });
    let available = linkwork::available_memory();
    if available.is_some_and(|a| bytes > a) {
        let e = SolveError::TooLarge {
            bytes,
            available,
            steps: times.len().div_ceil(request.every.max(1)),
            n_coords: refs.iter().map(|m| m.n_coords).max().unwrap_or(0),
            what: format!("{what}, for {total} models"),
        };
        return Err(solve_err(py, &e));
    }
    let (items, interrupt) = py.detach(|| {
        let mut interrupt: Option<PyErr> = None;
        let mut watch = batch_watch(&progress, total, &mut interrupt);
        let items = guard("sweeping a batch", || {
            linkwork::sweep_batch_kept(
                &refs,
                times,
                request,
                kept.as_deref(),
                asked.as_deref(),
                threads,
                &mut watch,
            )
        });
        drop(watch);
        (items, interrupt)
    });
    let items = items?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    if let Some(cb) = &progress {
        cb.call1(py, (total, total))?;
    }
    items
        .into_iter()
        .zip(&models)
        .map(|((out, err), m)| {
            let err = err.map(|e| laws::chain_failure(py, solve_err(py, &e), &m.failures));
            Ok((output_dict(py, out)?, err))
        })
        .collect()
}

/// A batch's watch, called without the GIL about every 5 ms with the items done: Ctrl-C
/// and `progress(done, total)` (when done moved); an exception of either cancels the
/// batch and is kept in `interrupt`.
pub(crate) fn batch_watch<'a>(
    progress: &'a Option<Py<PyAny>>,
    total: usize,
    interrupt: &'a mut Option<PyErr>,
) -> impl FnMut(usize) -> bool + 'a {
    let mut last = usize::MAX;
    move |done: usize| {
        Python::attach(|py| {
            let r = py.check_signals().and_then(|_| match (progress, done != last) {
                (Some(cb), true) => cb.call1(py, (done, total)).map(|_| ()),
                _ => Ok(()),
            });
            last = done;
            r.map_err(|e| *interrupt = Some(e)).is_ok()
        })
    }
}

impl PyModel {
    /// `solve_err`, with the exception of a failed Python law as the cause.
    fn solve_err(&self, py: Python<'_>, e: &SolveError) -> PyErr {
        laws::chain_failure(py, solve_err(py, e), &self.failures)
    }

    /// A Python exception, with the exception of a failed Python law as the cause.
    fn law_failure(&self, py: Python<'_>, e: PyErr) -> PyErr {
        laws::chain_failure(py, e, &self.failures)
    }
}

impl PyModel {
    /// The configuration a sweep over `times` starts from: the guess, else the drawing
    /// followed by its drivers to the first time (the drawing's branch, however far).
    fn start_q(
        &self,
        py: Python<'_>,
        q_guess: Option<PyReadonlyArray1<'_, f64>>,
        times: &[f64],
    ) -> PyResult<Vec<f64>> {
        let model = &self.model;
        Ok(match (guess(model, q_guess)?, times.first()) {
            (Some(q), _) => q,
            (None, Some(&t0)) if t0.is_finite() && t0 != linkwork::drawing_time(model) => {
                laws::clear(&self.failures);
                along(py, model, t0).map_err(|e| self.law_failure(py, e))?.0.q
            }
            (None, _) => model.q_start.clone(),
        })
    }
}

/// A long solve's progress poll, from its thread without the GIL: Ctrl-C and the
/// callback `progress(k, total)`; false (stop) with the exception kept in `interrupt`.
pub(crate) fn poll_progress(
    progress: &Option<Py<PyAny>>,
    total: usize,
    k: usize,
    interrupt: &mut Option<PyErr>,
) -> bool {
    Python::attach(|py| {
        let r = py.check_signals().and_then(|_| match progress {
            Some(cb) => cb.call1(py, (k, total)).map(|_| ()),
            None => Ok(()),
        });
        r.map_err(|e| *interrupt = Some(e)).is_ok()
    })
}

/// The error of a long solve run by `guard` with `poll_progress`: its panic, else the
/// exception that stopped it from the poll (Ctrl-C, the progress callback's own), else the
/// engine's error made a Python one by `solve_err`; None when it finished.
pub(crate) fn run_error(
    result: PyResult<Result<(), SolveError>>,
    interrupt: Option<PyErr>,
    solve_err: impl FnOnce(&SolveError) -> PyErr,
) -> Option<PyErr> {
    match (result, interrupt) {
        (Err(panic), _) => Some(panic),
        (Ok(Ok(())), _) => None,
        (Ok(Err(_)), Some(py_err)) => Some(py_err),
        (Ok(Err(e)), None) => Some(solve_err(&e)),
    }
}

#[pymethods]
impl PyModel {
    #[new]
    #[pyo3(signature = (description_json, *, tol_residual=None, tol_step=None, max_iter=None,
                        max_iter_assembly=None, singular_tol=None, linear="auto", dense_max=None,
                        redundant="error", solver="auto", free=false, python_laws=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        description_json: &str,
        tol_residual: Option<f64>,
        tol_step: Option<f64>,
        max_iter: Option<usize>,
        max_iter_assembly: Option<usize>,
        singular_tol: Option<f64>,
        linear: &str,
        dense_max: Option<usize>,
        redundant: &str,
        solver: &str,
        free: bool,
        python_laws: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let solver = match solver {
            "auto" => linkwork::SolverKind::Auto,
            "general" => linkwork::SolverKind::General,
            other => {
                return Err(InputError::new_err(format!(
                    "solver must be \"auto\" or \"general\", not {other:?}"
                )))
            }
        };
        let redundant = match redundant {
            "error" => OnRedundant::Error,
            "solve" => OnRedundant::Solve,
            other => {
                return Err(InputError::new_err(format!(
                    "redundant must be \"error\" or \"solve\", not {other:?}"
                )))
            }
        };
        let d = Options::default();
        let options = Options {
            tol_residual: tol_residual.unwrap_or(d.tol_residual),
            tol_step: tol_step.unwrap_or(d.tol_step),
            max_iter: max_iter.unwrap_or(d.max_iter),
            max_iter_assembly: max_iter_assembly.unwrap_or(d.max_iter_assembly),
            singular_tol: singular_tol.unwrap_or(d.singular_tol),
            linear: parse_linear(linear)?,
            dense_max: dense_max.unwrap_or(d.dense_max),
            redundant,
            solver,
            free,
        };
        let mut desc = guard("reading a description", || Description::from_json(description_json))?
            .map_err(model_err)?;
        let units = desc.units;
        let failures = laws::Failures::default();
        laws::bind(&mut desc, python_laws, &failures)?;
        let model =
            guard("compiling the model", || Model::with_options(desc, options))?.map_err(model_err)?;
        Ok(PyModel { model: Arc::new(model), failures, units })
    }

    #[getter]
    fn name(&self) -> &str {
        &self.model.name
    }
    #[getter]
    fn n_bodies(&self) -> usize {
        self.model.n_bodies
    }
    #[getter]
    fn n_coords(&self) -> usize {
        self.model.n_coords
    }
    #[getter]
    fn n_rows(&self) -> usize {
        self.model.n_rows
    }
    /// Degrees of freedom left free (`free=True`); 0 for a kinematic model.
    #[getter]
    fn dof(&self) -> usize {
        self.model.dof()
    }
    #[getter]
    fn nnz(&self) -> usize {
        self.model.nnz()
    }
    #[getter]
    fn columns(&self) -> Vec<String> {
        self.model.columns.clone()
    }
    #[getter]
    fn body_names(&self) -> Vec<String> {
        self.model.body_names.clone()
    }
    #[getter]
    fn length_scale(&self) -> f64 {
        self.model.length_scale
    }
    /// "structured" (the groups one after another) or "general" (one sparse system).
    #[getter]
    fn solver(&self) -> &'static str {
        if self.model.plan.is_ok() {
            "structured"
        } else {
            "general"
        }
    }
    /// Why the general path solves the whole model (None when it is structured).
    #[getter]
    fn fallback(&self) -> Option<String> {
        self.model.plan.as_ref().err().cloned()
    }
    #[getter]
    fn linear(&self) -> &'static str {
        linear_name(self.model.linear_kind())
    }
    #[getter]
    fn q_start<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.model.q_start.clone().into_pyarray(py)
    }
    /// (name, role, type, n_rows, first row) of every joint and driver, in row order.
    #[getter]
    fn constraints(&self) -> Vec<(String, &'static str, &'static str, usize, usize)> {
        self.model
            .constraints
            .iter()
            .map(|c| (c.name.clone(), c.role, c.kind.label(), c.n_rows, c.row0))
            .collect()
    }
    /// How a drawing that did not close was closed (the description's `close`), or None:
    /// {"keep": "given" | "drawn", "misses": [(joint, body, pin, miss, given, drawn)],
    /// "moved": [(body, distance, turn)]}.
    #[getter]
    fn closing<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(c) = &self.model.closing else { return Ok(None) };
        let d = PyDict::new(py);
        d.set_item("keep", c.keep.name())?;
        let misses: Vec<_> = c
            .misses
            .iter()
            .map(|m| (m.joint.clone(), m.body.clone(), m.pin, m.miss, m.given, m.drawn))
            .collect();
        d.set_item("misses", misses)?;
        d.set_item("moved", c.moved.clone())?;
        Ok(Some(d))
    }
    /// Joints whose reactions kinematics does not determine (redundant rows).
    #[getter]
    fn indeterminate(&self) -> Vec<String> {
        self.model.indeterminate.clone()
    }
    /// (name, body index or -1 for the ground, local x, local y) of every named point.
    #[getter]
    fn points(&self) -> Vec<(String, i64, f64, f64)> {
        self.model
            .points
            .iter()
            .map(|p| (p.name.clone(), p.body.map_or(-1, |b| b as i64), p.local[0], p.local[1]))
            .collect()
    }

    /// Position, velocity and acceleration at time t, assembled from q_guess; without
    /// one, the drawing's branch followed along the drivers to t. Returns (q, qd, qdd,
    /// iterations, residual, pivot_ratio, events met on the way).
    #[pyo3(signature = (t, q_guess=None))]
    #[allow(clippy::type_complexity)]
    fn solve<'py>(
        &self,
        py: Python<'py>,
        t: f64,
        q_guess: Option<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        usize,
        f64,
        f64,
        Vec<Bound<'py, PyDict>>,
    )> {
        let model = &self.model;
        laws::clear(&self.failures);
        let (data, info, events) = match guess(model, q_guess)? {
            None => along(py, model, t).map_err(|e| self.law_failure(py, e))?,
            Some(q) => {
                let mut data = Data::new(model);
                data.q = q;
                let info = guard("solving", || linkwork::solve(model, &mut data, t))?
                    .map_err(|e| self.solve_err(py, &e))?;
                (data, info, Vec::new())
            }
        };
        let events = events.iter().map(|e| events::event_dict(py, e)).collect::<PyResult<Vec<_>>>()?;
        Ok((
            data.q.into_pyarray(py),
            data.qd.into_pyarray(py),
            data.qdd.into_pyarray(py),
            info.iterations,
            info.residual,
            info.pivot_ratio,
            events,
        ))
    }

    /// Sweeps the times with the GIL released. Returns (results dict, error or None):
    /// on failure at step k the dict holds the k good steps and the error says why.
    /// `progress(done, total)` is called every `progress_every` steps (0: never);
    /// Ctrl-C is noticed at the same points.
    #[pyo3(signature = (times, q_guess=None, progress=None, progress_every=16384, forces=false, derivatives=2,
                        every=1, on_singular="continue", locks=false, coords=None, points=None))]
    #[allow(clippy::too_many_arguments)]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        times: PyReadonlyArray1<'py, f64>,
        q_guess: Option<PyReadonlyArray1<'py, f64>>,
        progress: Option<Py<PyAny>>,
        progress_every: usize,
        forces: bool,
        derivatives: u8,
        every: usize,
        on_singular: &str,
        locks: bool,
        coords: Option<Vec<usize>>,
        points: Option<Vec<(i64, f64, f64)>>,
    ) -> PyResult<(Bound<'py, PyDict>, Option<PyErr>)> {
        let request = parse_request(derivatives, forces, every, on_singular, locks)?;
        let outputs = parse_outputs(coords, points)?;
        let model = Arc::clone(&self.model);
        let times = times.as_slice()?;
        let mut data = Data::new(&model);
        data.q = self.start_q(py, q_guess, times)?;
        let mut out =
            SweepOutput::try_with_outputs(&model, times, request, outputs, linkwork::available_memory())
                .map_err(|e| solve_err(py, &e))?;
        let total = times.len();
        laws::clear(&self.failures);
        let (result, interrupt) = py.detach(|| {
            let mut interrupt: Option<PyErr> = None;
            let mut on_progress = |k: usize| poll_progress(&progress, total, k, &mut interrupt);
            let r = guard("sweeping", || {
                linkwork::sweep(&model, &mut data, times, &mut out, progress_every, &mut on_progress)
            });
            (r, interrupt)
        });
        if matches!(result, Ok(Ok(()))) {
            if let Some(cb) = &progress {
                cb.call1(py, (total, total))?;
            }
        }
        // a panic keeps the steps stored before it, as a solve error does
        let error = run_error(result, interrupt, |e| self.solve_err(py, e));
        out.truncate();
        Ok((output_dict(py, out)?, error))
    }

    /// Inverse dynamics at one configuration at rest (qd = qdd = 0): the driver efforts
    /// and joint reactions that hold it against gravity and the loads at time t.
    /// Returns (q, lambda, reactions n_constraints x 4).
    #[pyo3(signature = (t, q_guess=None))]
    #[allow(clippy::type_complexity)]
    fn statics<'py>(
        &self,
        py: Python<'py>,
        t: f64,
        q_guess: Option<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, Bound<'py, PyAny>)> {
        let model = &self.model;
        laws::clear(&self.failures);
        let mut data = Data::new(model);
        data.q =
            assembled(py, model, t, guess(model, q_guess)?, true).map_err(|e| self.law_failure(py, e))?;
        // solved again from there (one iteration) for the factorization the forces use
        guard("assembling", || linkwork::solve_position(model, &mut data, t, 0, true))?
            .map_err(|e| self.solve_err(py, &e))?;
        data.qd.fill(0.0);
        data.qdd.fill(0.0);
        // solve_forces refreshes the frames from q and qd = 0, so reactions see rest
        guard("solving for the forces", || linkwork::solve_forces(model, &mut data, t, 0))?
            .map_err(|e| self.solve_err(py, &e))?;
        let mut reactions = vec![0.0; linkwork::REACTION_COLUMNS * model.constraints.len()];
        guard("computing the reactions", || linkwork::reactions(model, &data, t, &mut reactions))?;
        let reactions = rows_to_array(py, reactions, model.constraints.len(), linkwork::REACTION_COLUMNS);
        Ok((data.q.into_pyarray(py), data.lambda.into_pyarray(py), reactions))
    }

    /// (name, type, body_a index, body_b index; -1 for the ground) of every load.
    #[getter]
    fn loads(&self) -> Vec<(String, &'static str, i64, i64)> {
        let idx = |b: Option<usize>| b.map_or(-1, |i| i as i64);
        self.model
            .loads
            .iter()
            .map(|l| {
                let kind = match l.load {
                    linkwork::loads::Load::Force { .. } => "force",
                    linkwork::loads::Load::Torque { .. } => "torque",
                    linkwork::loads::Load::Spring { .. } => "spring",
                    linkwork::loads::Load::TorsionSpring { .. } => "torsion_spring",
                    linkwork::loads::Load::JointForce { .. } => "joint_force",
                    linkwork::loads::Load::Friction { .. } => "friction",
                };
                (l.name.clone(), kind, idx(l.body_a), idx(l.body_b))
            })
            .collect()
    }

    /// (mass, inertia about the centre of mass, local com x, local com y) of every body.
    #[getter]
    fn inertias(&self) -> Vec<(f64, f64, f64, f64)> {
        self.model.inertias.iter().map(|i| (i.mass, i.inertia, i.com[0], i.com[1])).collect()
    }

    /// (name, role, body_a index, body_b index, local anchor x, local anchor y) of every
    /// joint and driver: where its reaction on side b is reported.
    #[getter]
    fn anchors(&self) -> Vec<(String, &'static str, i64, i64, f64, f64)> {
        use linkwork::constraints::Constraint;
        let idx = |b: Option<usize>| b.map_or(-1, |i| i as i64);
        self.model
            .constraints
            .iter()
            .map(|c| {
                let p = c.kind.anchor_b();
                (c.name.clone(), c.role, idx(c.body_a), idx(c.body_b), p[0], p[1])
            })
            .collect()
    }

    /// (quantity, unit) of everything in and out of the model: lengths in the declared
    /// unit, angles in rad (the declared input angle unit as "input_angle"), forces ...
    #[getter]
    fn units(&self) -> Vec<(&'static str, &'static str)> {
        self.units.table()
    }

    #[getter]
    fn gravity(&self) -> (f64, f64) {
        (self.model.gravity[0], self.model.gravity[1])
    }

    fn __repr__(&self) -> String {
        let m = &self.model;
        format!(
            "<linkwork Model '{}': {} bodies, {} coordinates, {} rows, {} LU>",
            m.name,
            m.n_bodies,
            m.n_coords,
            m.n_rows,
            linear_name(m.linear_kind())
        )
    }
}

/// Every joint and driver type of the engine with the description forms it compiles
/// from and the role of each field (`linkwork::constraints::Role`), in the kind list's order:
/// [{"kind", "group", "type", "fields": [{"name", "role", "bodies", "choices", "input", "unit"}]}].
#[pyfunction]
fn constraint_roles(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    let mut out = Vec::new();
    for (kind, forms) in linkwork::constraints::roles() {
        for form in forms {
            let mut fields = Vec::with_capacity(form.fields.len());
            for (name, role) in form.fields {
                let f = PyDict::new(py);
                f.set_item("name", name)?;
                f.set_item("role", role.name())?;
                f.set_item("bodies", role.bodies())?;
                let choices: &[&str] = match role {
                    linkwork::constraints::Role::Choice(c) => c,
                    _ => &[],
                };
                f.set_item("choices", choices.to_vec())?;
                let input = match role {
                    linkwork::constraints::Role::Law(i) => Some(i.name()),
                    _ => None,
                };
                f.set_item("input", input)?;
                f.set_item("unit", role.unit())?;
                fields.push(f);
            }
            let d = PyDict::new(py);
            d.set_item("kind", kind)?;
            d.set_item("group", form.group)?;
            d.set_item("type", form.type_)?;
            d.set_item("fields", fields)?;
            out.push(d);
        }
    }
    Ok(out)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyModel>()?;
    screw::register(m)?;
    m.add_function(wrap_pyfunction!(synthesis::synth_dyads, m)?)?;
    m.add_function(wrap_pyfunction!(synthesis::synth_motion, m)?)?;
    m.add_function(wrap_pyfunction!(synthesis::synth_freudenstein, m)?)?;
    m.add_function(wrap_pyfunction!(synthesis::synth_chebyshev, m)?)?;
    m.add_function(wrap_pyfunction!(synthesis::synth_start_set, m)?)?;
    m.add_function(wrap_pyfunction!(synthesis::synth_alt, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_batch, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics::simulation_rows, m)?)?;
    m.add_function(wrap_pyfunction!(load_power::load_powers, m)?)?;
    m.add_function(wrap_pyfunction!(equilibrium::equilibrium, m)?)?;
    m.add_function(wrap_pyfunction!(sensitivity::sensitivities, m)?)?;
    m.add_function(wrap_pyfunction!(variants::sweep_variants, m)?)?;
    m.add_function(wrap_pyfunction!(panics::_check_panic_guard, m)?)?;
    m.add_function(wrap_pyfunction!(read_model, m)?)?;
    m.add_function(wrap_pyfunction!(write_model, m)?)?;
    m.add_function(wrap_pyfunction!(constraint_roles, m)?)?;
    m.add_function(wrap_pyfunction!(events::motion_limits, m)?)?;
    m.add_function(wrap_pyfunction!(mobility::mobility, m)?)?;
    m.add_function(wrap_pyfunction!(mobility::structure, m)?)?;
    m.add_function(wrap_pyfunction!(linkages::linkages, m)?)?;
    m.add_function(wrap_pyfunction!(linkages::assembly_modes, m)?)?;
    laws::register(m)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

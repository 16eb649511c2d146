//! Static equilibrium: the rest configuration of a model under its loads, its stability
//! and its linearized vibration modes, the GIL released.

use linkwork::dynamics::equilibrium::{equilibrium as solve_equilibrium, EqOptions, NotConverged};
use linkwork::dynamics::modes::{modes, stability};
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::{guard, rows_to_array, InputError, PyModel};

pyo3::import_exception!(linkwork.errors, EquilibriumError);

fn not_converged(py: Python<'_>, e: NotConverged) -> PyErr {
    let err = EquilibriumError::new_err(e.to_string());
    let value = err.value(py);
    // attributes of an exception we created ourselves: setting them cannot fail in practice
    let _ = value.setattr("time", e.time);
    let _ = value.setattr("step", 0);
    let _ = value.setattr("iterations", e.iterations);
    let _ = value.setattr("force", e.force);
    let _ = value.setattr("phi", e.phi);
    let _ = value.setattr("coordinate", e.coordinate);
    let _ = value.setattr("q", e.q.into_pyarray(py));
    err
}

/// The rest configuration of `model` at time t from q_guess (default: the drawing).
/// Returns a dict: "q", "lambda" (rows' units), "reactions" (n_constraints x 4),
/// "iterations", "force", "phi", "force_scale", "eigenvalues", "directions" (dof x n),
/// "dominant" (column indices), "tol", "stable", "asymmetry", "omega2", "shapes"
/// (dof x n) and "modes_error" (an exception where the modes cannot be computed, else
/// None). Raises EquilibriumError (with the last iterate, `q`) when Newton does not converge.
#[pyfunction]
#[pyo3(signature = (model, t=0.0, q_guess=None, max_iter=100, tol_force=1e-12, max_step=0.5))]
pub(crate) fn equilibrium<'py>(
    py: Python<'py>,
    model: PyRef<'py, PyModel>,
    t: f64,
    q_guess: Option<PyReadonlyArray1<'py, f64>>,
    max_iter: usize,
    tol_force: f64,
    max_step: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = EqOptions { max_iter, tol_force, max_step };
    opts.check().map_err(InputError::new_err)?;
    let m = &model.model;
    let guess = q_guess.map(|g| g.as_slice().map(|s| s.to_vec())).transpose()?;
    if let Some(g) = &guess {
        if g.len() != m.n_coords || !g.iter().all(|v| v.is_finite()) {
            return Err(InputError::new_err(format!(
                "q_guess must be {} finite numbers (one per column), not {} values",
                m.n_coords,
                g.len()
            )));
        }
    }
    let (n, nc) = (m.n_coords, m.constraints.len());
    let solved = py.detach(|| {
        guard("solving for the equilibrium", || {
            let eq = solve_equilibrium(m, t, guess.as_deref(), &opts)?;
            let st = stability(m, &eq);
            let md = modes(m, &eq);
            let (lambda, reactions) = eq.reactions(m);
            Ok((eq, st, md, lambda, reactions))
        })
    })?;
    let (eq, st, md, lambda, reactions) = solved.map_err(|e| not_converged(py, e))?;
    let d = PyDict::new(py);
    let flat = |rows: Vec<Vec<f64>>| {
        let k = rows.len();
        rows_to_array(py, rows.into_iter().flatten().collect(), k, n)
    };
    d.set_item("q", eq.q.into_pyarray(py))?;
    d.set_item("lambda", lambda.into_pyarray(py))?;
    d.set_item("reactions", rows_to_array(py, reactions, nc, linkwork::REACTION_COLUMNS))?;
    d.set_item("iterations", eq.iterations)?;
    d.set_item("force", eq.force)?;
    d.set_item("phi", eq.phi)?;
    d.set_item("force_scale", eq.force_scale)?;
    d.set_item("eigenvalues", st.eigenvalues.into_pyarray(py))?;
    d.set_item("directions", flat(st.directions))?;
    d.set_item("dominant", st.dominant)?;
    d.set_item("tol", st.tol)?;
    d.set_item("stable", st.stable)?;
    d.set_item("asymmetry", st.asymmetry)?;
    match md {
        Ok(md) => {
            d.set_item("omega2", md.omega2.into_pyarray(py))?;
            d.set_item("shapes", flat(md.shapes))?;
            d.set_item("modes_error", py.None())?;
        }
        Err(e) => {
            d.set_item("omega2", py.None())?;
            d.set_item("shapes", py.None())?;
            d.set_item("modes_error", model.solve_err(py, &e))?;
        }
    }
    Ok(d)
}

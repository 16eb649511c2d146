//! Mobility (degrees of freedom two ways, redundant rows) as a Python dict.

use linkwork::analysis::mobility::mobility as engine_mobility;
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::{assembled, guard, guess, InputError, PyModel};

/// Degrees of freedom and dependencies at q_guess (default: the starting configuration)
/// and time t; with `assemble`, at the configuration assembled from it first.
#[pyfunction]
#[pyo3(signature = (model, t=0.0, q_guess=None, assemble=true))]
pub(crate) fn mobility<'py>(
    py: Python<'py>,
    model: PyRef<'py, PyModel>,
    t: f64,
    q_guess: Option<PyReadonlyArray1<'py, f64>>,
    assemble: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let m = std::sync::Arc::clone(&model.model);
    let q = assembled(py, &m, t, guess(&m, q_guess)?, assemble)?;
    let mob = py.detach(|| guard("counting the degrees of freedom", || engine_mobility(&m, &q, t)))?;
    let mob = mob.map_err(|e| InputError::new_err(e.to_string()))?;
    let d = PyDict::new(py);
    d.set_item("q", q.into_pyarray(py))?;
    d.set_item("n_bodies", mob.n_bodies)?;
    d.set_item("n_coords", mob.n_coords)?;
    d.set_item("joint_rows", mob.joint_rows)?;
    d.set_item("driver_rows", mob.driver_rows)?;
    d.set_item("gruebler_dof", mob.gruebler_dof)?;
    d.set_item("gruebler_dof_driven", mob.gruebler_dof_driven)?;
    d.set_item("rank_joints", mob.rank_joints)?;
    d.set_item("rank", mob.rank)?;
    d.set_item("dof", mob.dof)?;
    d.set_item("dof_driven", mob.dof_driven)?;
    d.set_item("singular_values", mob.singular_values.into_pyarray(py))?;
    let deps = |v: &[linkwork::analysis::mobility::Dependency]| -> Vec<(f64, Vec<(String, f64)>)> {
        v.iter().map(|d| (d.sigma, d.constraints.clone())).collect()
    };
    d.set_item("redundancies", deps(&mob.redundancies))?;
    d.set_item("nearest", mob.nearest.as_ref().map(|n| (n.sigma, n.constraints.clone())))?;
    d.set_item("free_motions", mob.free_motions)?;
    d.set_item("explanation", mob.explanation)?;
    Ok(d)
}

/// The mechanism's structure from Phi_q's pattern: groups of coordinates solved together,
/// in solving order, each with its kind, bodies, constraints (names) and coordinates
/// (column names); the structurally redundant rows (as constraint names) and the
/// coordinates no row determines.
#[pyfunction]
pub(crate) fn structure<'py>(py: Python<'py>, model: PyRef<'py, PyModel>) -> PyResult<Bound<'py, PyDict>> {
    use linkwork::analysis::structure::structure as engine_structure;
    let m = std::sync::Arc::clone(&model.model);
    let s = py.detach(|| guard("finding the mechanism's structure", || engine_structure(&m)))?;
    let constraint_of = |row: usize| {
        m.constraints
            .iter()
            .find(|c| (c.row0..c.row0 + c.n_rows).contains(&row))
            .map(|c| c.name.clone())
            .unwrap_or_default()
    };
    let plan = m.plan.as_ref().ok();
    let groups = pyo3::types::PyList::empty(py);
    for (i, g) in s.groups.iter().enumerate() {
        let d = PyDict::new(py);
        d.set_item("kind", &g.kind)?;
        // the plan's blocks are the structure's groups, in the same order
        let method = plan.and_then(|p| p.blocks.get(i)).map(|b| b.describe());
        d.set_item("method", method.unwrap_or_else(|| "general path".into()))?;
        d.set_item("bodies", g.bodies.iter().map(|&b| m.body_names[b].clone()).collect::<Vec<_>>())?;
        d.set_item(
            "constraints",
            g.constraints.iter().map(|&k| m.constraints[k].name.clone()).collect::<Vec<_>>(),
        )?;
        d.set_item(
            "types",
            g.constraints.iter().map(|&k| m.constraints[k].kind.label()).collect::<Vec<_>>(),
        )?;
        d.set_item("coordinates", g.coords.iter().map(|&c| m.columns[c].clone()).collect::<Vec<_>>())?;
        d.set_item("rows", g.rows.clone())?;
        groups.append(d)?;
    }
    let d = PyDict::new(py);
    d.set_item("groups", groups)?;
    d.set_item("redundant", s.redundant_rows.iter().map(|&r| constraint_of(r)).collect::<Vec<_>>())?;
    d.set_item("free", s.free_coords.iter().map(|&c| m.columns[c].clone()).collect::<Vec<_>>())?;
    d.set_item("fallback", m.plan.as_ref().err().cloned())?;
    Ok(d)
}

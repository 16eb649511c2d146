//! The classical linkages of a model (four-bar loops, slider-cranks) and its assembly
//! modes, as Python dicts.

use linkwork::analysis::linkages::{linkages as find_linkages, FourBarLoop, Linkages, SliderCrankLoop};
use linkwork::analysis::modes::assembly_modes as find_modes;
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::{assembled, guard, guess, solve_err, start_guess, PyModel};

fn four_bar<'py>(py: Python<'py>, l: &FourBarLoop) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("kind", "four-bar")?;
    d.set_item("name", &l.name)?;
    d.set_item("bodies", l.bodies.to_vec())?;
    d.set_item("joints", l.joints.to_vec())?;
    d.set_item("lengths", l.lengths.to_vec())?;
    d.set_item("class", l.class.name())?;
    d.set_item("input_turns", l.class.input_turns())?;
    d.set_item("sums", l.sums.to_vec())?;
    d.set_item("driven", l.driven)?;
    d.set_item("input_limits", l.input_limits.map(|v| v.to_vec()))?;
    d.set_item("circuit", l.circuit)?;
    d.set_item("transmission_angle", l.transmission_angle)?;
    d.set_item("a_on_crank", l.a_on_crank.to_vec())?;
    d.set_item("a_on_coupler", l.a_on_coupler.to_vec())?;
    d.set_item("b_on_coupler", l.b_on_coupler.to_vec())?;
    d.set_item("b_on_rocker", l.b_on_rocker.to_vec())?;
    d.set_item("o2", l.o2.to_vec())?;
    d.set_item("o4", l.o4.to_vec())?;
    Ok(d)
}

fn slider_crank<'py>(py: Python<'py>, l: &SliderCrankLoop) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("kind", "slider-crank")?;
    d.set_item("name", &l.name)?;
    d.set_item("bodies", l.bodies.to_vec())?;
    d.set_item("joints", l.joints.to_vec())?;
    d.set_item("lengths", vec![l.crank, l.rod, l.offset])?;
    d.set_item("crank_turns", l.crank_turns)?;
    d.set_item("change_point", l.change_point)?;
    d.set_item("driven", l.driven)?;
    d.set_item("input_limits", l.input_limits.map(|v| v.to_vec()))?;
    d.set_item("stroke", l.stroke.map(|v| v.to_vec()))?;
    d.set_item("circuit", l.circuit)?;
    d.set_item("transmission_angle", l.transmission_angle)?;
    d.set_item("axis", l.axis.to_vec())?;
    d.set_item("o", l.o.to_vec())?;
    d.set_item("a_on_crank", l.a_on_crank.to_vec())?;
    d.set_item("a_on_rod", l.a_on_rod.to_vec())?;
    d.set_item("b_on_rod", l.b_on_rod.to_vec())?;
    d.set_item("b_on_slider", l.b_on_slider.to_vec())?;
    Ok(d)
}

fn loops<'py>(py: Python<'py>, found: &Linkages) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for l in &found.four_bars {
        list.append(four_bar(py, l)?)?;
    }
    for l in &found.slider_cranks {
        list.append(slider_crank(py, l)?)?;
    }
    Ok(list)
}

/// The four-bar loops and slider-cranks at the configuration assembled at t from
/// q_guess (default: as described). Returns (q, [loop dicts]).
#[pyfunction]
#[pyo3(signature = (model, t=0.0, q_guess=None, assemble=true))]
pub(crate) fn linkages<'py>(
    py: Python<'py>,
    model: PyRef<'py, PyModel>,
    t: f64,
    q_guess: Option<PyReadonlyArray1<'py, f64>>,
    assemble: bool,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyList>)> {
    let m = std::sync::Arc::clone(&model.model);
    let q = assembled(py, &m, t, guess(&m, q_guess)?, assemble)?;
    let found = guard("finding the linkages", || find_linkages(&m, &q))?;
    Ok((q.into_pyarray(py).into_any(), loops(py, &found)?))
}

/// The assembly modes at time t found from `tries` guesses around q_guess. Returns
/// (tries, converged, [(q, det_sign, pivot_ratio, [loop dicts])]).
#[pyfunction]
#[pyo3(signature = (model, t=0.0, q_guess=None, tries=200))]
#[allow(clippy::type_complexity)]
pub(crate) fn assembly_modes<'py>(
    py: Python<'py>,
    model: PyRef<'py, PyModel>,
    t: f64,
    q_guess: Option<PyReadonlyArray1<'py, f64>>,
    tries: usize,
) -> PyResult<(usize, usize, Vec<(Bound<'py, PyAny>, f64, f64, Bound<'py, PyList>)>)> {
    let m = std::sync::Arc::clone(&model.model);
    let q_ref = start_guess(&m, q_guess)?;
    let found = py.detach(|| guard("finding the assembly modes", || find_modes(&m, &q_ref, t, tries)))?;
    let found = found.map_err(|e| solve_err(py, &e))?;
    let mut out = Vec::new();
    for mode in found.modes {
        let l = guard("finding the linkages", || find_linkages(&m, &mode.q))?;
        out.push((mode.q.into_pyarray(py).into_any(), mode.det_sign, mode.pivot_ratio, loops(py, &l)?));
    }
    Ok((found.tries, found.converged, out))
}

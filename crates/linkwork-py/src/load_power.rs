//! The power of each applied load along a motion already computed (a simulation's rows):
//! its generalized force, as the engine assembles it into Q_A, dotted with qd.

use linkwork::constraints::Frame;
use linkwork::dynamics::mass::frames_of;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::{guard, laws, rows_to_array, InputError, PyModel};

/// (n x n_loads): Q_l(q, qd, t) . qd for every load l of `model.loads` at each row of
/// `times`, `q`, `qd` (n x n_coords): F . v of a force's point, torque x rate, -(spring
/// tension) x elongation rate (and likewise for torsion springs); negative where a load
/// takes energy out of the mechanism.
#[pyfunction]
pub(crate) fn load_powers<'py>(
    py: Python<'py>,
    model: PyRef<'py, PyModel>,
    times: PyReadonlyArray1<'py, f64>,
    q: PyReadonlyArray2<'py, f64>,
    qd: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let m = &model.model;
    let (times, q, qd) = (times.as_slice()?, q.as_array(), qd.as_array());
    let (n, nc, nl) = (times.len(), m.n_coords, m.loads.len());
    if q.shape() != [n, nc] || qd.shape() != [n, nc] {
        return Err(InputError::new_err(format!(
            "q and qd must be {n} x {nc} (a row per time, a column per coordinate), not {:?} and {:?}",
            q.shape(),
            qd.shape()
        )));
    }
    laws::clear(&model.failures);
    let out = guard("computing the loads' power", || {
        let mut frames = vec![Frame::GROUND; m.inertias.len()];
        let mut force = vec![0.0; nc];
        let mut out: Vec<f64> = Vec::with_capacity(n * nl);
        for (k, &t) in times.iter().enumerate() {
            let (qk, qdk) = (q.row(k).to_vec(), qd.row(k).to_vec());
            frames_of(&qk, &qdk, &mut frames);
            for l in &m.loads {
                force.fill(0.0);
                l.add_to(&frames, t, &mut force);
                out.push(force.iter().zip(&qdk).map(|(f, v)| f * v).sum());
            }
        }
        out
    })?;
    if let Some(e) = model.failures.lock().ok().and_then(|mut slot| slot.take()) {
        return Err(e);
    }
    Ok(rows_to_array(py, out, n, nl))
}

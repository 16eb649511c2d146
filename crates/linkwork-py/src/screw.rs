//! Bindings of the screw toolkit (`linkwork::screw`): serial arms and their states,
//! join, meet, transport, instant centres and loop singularities. Conversion and the one
//! mapping of `ScrewError` only; the public API is `linkwork.screw`.

use linkwork::screw::{self as sc, Gauge, Point, Pose, Twist, Wrench};
use linkwork::Description;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

type Arr1<'py> = Bound<'py, PyArray1<f64>>;
type Arr2<'py> = Bound<'py, PyArray2<f64>>;
/// pairs (j, k) and one homogeneous point per pair (m x 3)
type PairArrays<'py> = (Vec<(usize, usize)>, Arr2<'py>);

mod py_errors {
    pyo3::import_exception!(linkwork.errors, ScrewError);
}

/// The one place where screw errors become Python exceptions.
fn err(e: sc::ScrewError) -> PyErr {
    py_errors::ScrewError::new_err(e.to_string())
}

fn description(json: &str) -> PyResult<Description> {
    // screws work in radians, whatever angle unit the description declares
    Description::from_json(json)
        .map(|d| linkwork::units::internal(&d))
        .map_err(|e| err(sc::ScrewError::Mechanism(e.to_string())))
}

fn slice<'a>(a: &'a PyReadonlyArray1<'_, f64>) -> PyResult<&'a [f64]> {
    Ok(a.as_slice()?)
}

fn rows<'py>(py: Python<'py>, v: Vec<[f64; 3]>) -> Bound<'py, PyArray2<f64>> {
    let n = v.len();
    Array2::from_shape_vec((n, 3), v.into_iter().flatten().collect()).expect("n x 3").into_pyarray(py)
}

fn rows2<'py>(py: Python<'py>, v: &[[f64; 2]]) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_vec((v.len(), 2), v.iter().flatten().copied().collect())
        .expect("n x 2")
        .into_pyarray(py)
}

fn pairs_out<'py>(py: Python<'py>, p: sc::PairPoints) -> PairArrays<'py> {
    let (idx, pts): (Vec<_>, Vec<_>) = p.into_iter().map(|(ij, x)| (ij, x.0)).unzip();
    (idx, rows(py, pts))
}

/// A serial planar arm of revolute and prismatic joints (see `linkwork.screw.SerialArm`).
#[pyclass(frozen, module = "linkwork._core", name = "SerialArm")]
struct PySerialArm {
    arm: sc::SerialArm,
}

#[pymethods]
impl PySerialArm {
    /// joints: (name, "R" or "P", home position, slide direction) each; end: home pose.
    #[new]
    fn new(joints: Vec<(String, String, [f64; 2], [f64; 2])>, end: [f64; 3]) -> PyResult<Self> {
        let mut js = Vec::with_capacity(joints.len());
        for (name, kind, at, axis) in joints {
            js.push(match kind.as_str() {
                "R" => sc::ArmJoint::revolute(name, at),
                "P" => sc::ArmJoint::prismatic(name, at, axis).map_err(err)?,
                other => {
                    return Err(err(sc::ScrewError::Input(format!(
                        "joint {name}: kind must be 'R' or 'P', not {other:?}"
                    ))))
                }
            });
        }
        let arm = sc::SerialArm::new(js, Pose::new(end[0], end[1], end[2])).map_err(err)?;
        Ok(PySerialArm { arm })
    }

    /// An arm from link lengths; kinds is a string of 'R' and 'P', one per link.
    #[staticmethod]
    fn from_links(kinds: &str, lengths: Vec<f64>) -> PyResult<Self> {
        let ks = kinds
            .chars()
            .map(|c| {
                sc::JointKind::from_letter(c).ok_or_else(|| {
                    err(sc::ScrewError::Input(format!("joint kinds are 'R' or 'P', not {c:?}")))
                })
            })
            .collect::<PyResult<Vec<_>>>()?;
        Ok(PySerialArm { arm: sc::SerialArm::from_links(&ks, &lengths).map_err(err)? })
    }

    /// The serial chain of a model description (JSON); end_point: a named point on the last body.
    #[staticmethod]
    #[pyo3(signature = (description_json, end_point=None))]
    fn from_description(description_json: &str, end_point: Option<&str>) -> PyResult<Self> {
        let d = description(description_json)?;
        let arm = crate::guard("reading an arm", || sc::SerialArm::from_description(&d, end_point))?;
        Ok(PySerialArm { arm: arm.map_err(err)? })
    }

    #[getter]
    fn names(&self) -> Vec<String> {
        self.arm.joints().iter().map(|j| j.name.clone()).collect()
    }
    #[getter]
    fn kinds(&self) -> String {
        self.arm.joints().iter().map(|j| j.kind.letter()).collect()
    }
    #[getter]
    fn home_positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows2(py, &self.arm.joints().iter().map(|j| j.at).collect::<Vec<_>>())
    }
    #[getter]
    fn home_axes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows2(py, &self.arm.joints().iter().map(|j| j.axis).collect::<Vec<_>>())
    }
    #[getter]
    fn end_home(&self) -> (f64, f64, f64) {
        let e = self.arm.end_home();
        (e.x, e.y, e.theta)
    }
    #[getter]
    fn end_body(&self) -> Option<usize> {
        self.arm.end_body()
    }
    #[getter]
    fn gauge(&self) -> ((f64, f64), f64) {
        let g = self.arm.gauge();
        ((g.centre[0], g.centre[1]), g.scale)
    }

    /// (q, w) of the arm from a model's coordinates and velocities.
    fn joint_values<'py>(
        &self,
        py: Python<'py>,
        q: PyReadonlyArray1<'py, f64>,
        qd: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(Arr1<'py>, Arr1<'py>)> {
        let (a, b) = self.arm.joint_values(slice(&q)?, slice(&qd)?).map_err(err)?;
        Ok((a.into_pyarray(py), b.into_pyarray(py)))
    }

    /// The end frame's pose and twist from a model's own coordinates and velocities.
    fn model_end<'py>(
        &self,
        py: Python<'py>,
        q: PyReadonlyArray1<'py, f64>,
        qd: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<((f64, f64, f64), Arr1<'py>)> {
        let (p, t) = self.arm.model_end(slice(&q)?, slice(&qd)?).map_err(err)?;
        Ok(((p.x, p.y, p.theta), t.to_array().to_vec().into_pyarray(py)))
    }

    /// Forward kinematics at joint values q.
    fn forward(&self, q: PyReadonlyArray1<'_, f64>) -> PyResult<PyArmState> {
        let q = slice(&q)?;
        Ok(PyArmState { st: crate::guard("forward kinematics", || self.arm.forward(q))?.map_err(err)? })
    }

    fn __repr__(&self) -> String {
        format!("<linkwork SerialArm {}: joints {}>", self.kinds(), self.names().join(", "))
    }
}

/// An arm at one configuration (see `linkwork.screw.ArmState`).
#[pyclass(frozen, module = "linkwork._core", name = "ArmState")]
struct PyArmState {
    st: sc::ArmState,
}

fn given(g: Option<Vec<(usize, f64)>>) -> Vec<(usize, f64)> {
    g.unwrap_or_default()
}

#[pymethods]
impl PyArmState {
    #[getter]
    fn names(&self) -> Vec<String> {
        self.st.names.clone()
    }
    #[getter]
    fn kinds(&self) -> String {
        self.st.kinds.iter().map(|k| k.letter()).collect()
    }
    #[getter]
    fn q<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.st.q.clone().into_pyarray(py)
    }
    /// joint axes as homogeneous points (n x 3)
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows(py, self.st.points.iter().map(|p| p.0).collect())
    }
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows2(py, &self.st.positions)
    }
    #[getter]
    fn axes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows2(py, &self.st.axes)
    }
    #[getter]
    fn end(&self) -> (f64, f64, f64) {
        (self.st.end.x, self.st.end.y, self.st.end.theta)
    }
    /// J = [$_1 ... $_n] (3 x n)
    #[getter]
    fn jacobian<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let n = self.st.n_joints();
        Array2::from_shape_vec((3, n), self.st.jacobian()).expect("3 x n").into_pyarray(py)
    }
    #[getter]
    fn gauge(&self) -> ((f64, f64), f64) {
        ((self.st.gauge.centre[0], self.st.gauge.centre[1]), self.st.gauge.scale)
    }

    fn twist(&self, w: PyReadonlyArray1<'_, f64>) -> PyResult<[f64; 3]> {
        Ok(self.st.twist(slice(&w)?).map_err(err)?.to_array())
    }
    fn pole(&self, w: PyReadonlyArray1<'_, f64>) -> PyResult<[f64; 3]> {
        Ok(self.st.pole(slice(&w)?).map_err(err)?.0)
    }
    fn end_velocity(&self, w: PyReadonlyArray1<'_, f64>) -> PyResult<[f64; 2]> {
        self.st.end_velocity(slice(&w)?).map_err(err)
    }
    fn velocity_centres<'py>(
        &self,
        py: Python<'py>,
        w: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<PairArrays<'py>> {
        Ok(pairs_out(py, self.st.velocity_centres(slice(&w)?).map_err(err)?))
    }
    fn torque_centres<'py>(
        &self,
        py: Python<'py>,
        tau: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<PairArrays<'py>> {
        Ok(pairs_out(py, self.st.torque_centres(slice(&tau)?).map_err(err)?))
    }
    #[pyo3(signature = (twist, given=None))]
    fn inverse_velocity<'py>(
        &self,
        py: Python<'py>,
        twist: [f64; 3],
        given: Option<Vec<(usize, f64)>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let w = self.st.inverse_velocity(&Twist::from_array(twist), &self::given(given)).map_err(err)?;
        Ok(w.into_pyarray(py))
    }
    /// (rates, pole, vertex or None, foot or None)
    #[pyo3(signature = (twist, given=None))]
    #[allow(clippy::type_complexity)] // the tuple is the Python return value
    fn inverse_velocity_barycentre<'py>(
        &self,
        py: Python<'py>,
        twist: [f64; 3],
        given: Option<Vec<(usize, f64)>>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, [f64; 3], Option<usize>, Option<[f64; 3]>)> {
        let b = self
            .st
            .inverse_velocity_barycentre(&Twist::from_array(twist), &self::given(given))
            .map_err(err)?;
        Ok((b.rates.into_pyarray(py), b.pole.0, b.vertex, b.foot.map(|p| p.0)))
    }
    /// the unit line screws (3 x 3, one wrench a row) of the line-screw formula
    fn line_screws<'py>(&self, py: Python<'py>, unknown: [usize; 3]) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = self.st.line_screws(unknown).map_err(err)?;
        Ok(rows(py, s.iter().map(|w| w.to_array()).collect()))
    }
    fn torques<'py>(&self, py: Python<'py>, wrench: [f64; 3]) -> Bound<'py, PyArray1<f64>> {
        self.st.torques(&Wrench::from_array(wrench)).into_pyarray(py)
    }
    fn lever_arms<'py>(&self, py: Python<'py>, wrench: [f64; 3]) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(self.st.lever_arms(&Wrench::from_array(wrench)).map_err(err)?.into_pyarray(py))
    }
    #[pyo3(signature = (tau, through=None))]
    fn force(&self, tau: PyReadonlyArray1<'_, f64>, through: Option<[f64; 2]>) -> PyResult<[f64; 3]> {
        Ok(self.st.force(slice(&tau)?, through).map_err(err)?.to_array())
    }
    fn dependencies(&self) -> Vec<Vec<usize>> {
        self.st.dependencies()
    }
}

fn gauge_of(centre: (f64, f64), scale: f64) -> PyResult<Gauge> {
    if !(scale > 0.0 && scale.is_finite() && centre.0.is_finite() && centre.1.is_finite()) {
        return Err(err(sc::ScrewError::Input(format!(
            "the gauge needs a finite centre and a positive length scale, not {centre:?} and {scale}"
        ))));
    }
    Ok(Gauge { centre: [centre.0, centre.1], scale })
}

/// The line p x q through two homogeneous points.
#[pyfunction]
#[pyo3(signature = (p, q, centre=(0.0, 0.0), scale=1.0))]
fn screw_join(p: [f64; 3], q: [f64; 3], centre: (f64, f64), scale: f64) -> PyResult<[f64; 3]> {
    Ok(gauge_of(centre, scale)?.join(&Point(p), &Point(q)).map_err(err)?.0)
}

/// The point l x k where two homogeneous lines meet, normalised ((x, y, 1) or a unit
/// direction at infinity).
#[pyfunction]
#[pyo3(signature = (l, k, centre=(0.0, 0.0), scale=1.0))]
fn screw_meet(l: [f64; 3], k: [f64; 3], centre: (f64, f64), scale: f64) -> PyResult<[f64; 3]> {
    let g = gauge_of(centre, scale)?;
    let p = g.meet(&sc::Line(l), &sc::Line(k)).map_err(err)?;
    Ok(g.normalize(&p).0)
}

/// A homogeneous point normalised: (x, y, 1), or a unit direction (dx, dy, 0) when the
/// gauge cannot tell it from a point at infinity.
#[pyfunction]
#[pyo3(signature = (p, centre=(0.0, 0.0), scale=1.0))]
fn screw_normalize(p: [f64; 3], centre: (f64, f64), scale: f64) -> PyResult<[f64; 3]> {
    Ok(gauge_of(centre, scale)?.normalize(&Point(p)).0)
}

/// Transports a twist or wrench ("twist"/"wrench") to the world ("world") or into the
/// frame at `pose` ("local").
#[pyfunction]
fn screw_transport(kind: &str, to: &str, pose: [f64; 3], v: [f64; 3]) -> PyResult<[f64; 3]> {
    let f = Pose::new(pose[0], pose[1], pose[2]);
    Ok(match (kind, to) {
        ("twist", "world") => f.twist_to_world(&Twist::from_array(v)).to_array(),
        ("twist", "local") => f.twist_to_local(&Twist::from_array(v)).to_array(),
        ("wrench", "world") => f.wrench_to_world(&Wrench::from_array(v)).to_array(),
        ("wrench", "local") => f.wrench_to_local(&Wrench::from_array(v)).to_array(),
        _ => {
            return Err(err(sc::ScrewError::Input(format!(
                "transport of {kind:?} to {to:?}: kind is 'twist' or 'wrench', to is 'world' or 'local'"
            ))))
        }
    })
}

fn centres_dict<'py>(py: Python<'py>, c: &sc::InstantCentres) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("bodies", c.body_names.clone())?;
    let pairs: Vec<(usize, usize, Option<[f64; 3]>)> =
        c.pairs().into_iter().map(|(i, j, p)| (i, j, p.map(|p| p.0))).collect();
    d.set_item("pairs", pairs)?;
    d.set_item("kennedy", c.kennedy_worst().map(|(r, t)| (r, (t[0], t[1], t[2]))))?;
    d.set_item("gauge", ((c.gauge.centre[0], c.gauge.centre[1]), c.gauge.scale))?;
    Ok(d)
}

/// Instant centres of every pair of bodies from the bodies' velocities.
#[pyfunction]
fn screw_centres_from_velocities<'py>(
    py: Python<'py>,
    description_json: &str,
    q: PyReadonlyArray1<'py, f64>,
    qd: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let mech = sc::MechanismJoints::from_description(&description(description_json)?).map_err(err)?;
    let (q, qd) = (slice(&q)?, slice(&qd)?);
    let c = crate::guard("finding instant centres", || sc::centres_from_velocities(&mech, q, qd))?
        .map_err(err)?;
    centres_dict(py, &c)
}

/// Instant centres from the joints and Kennedy's theorem (positions only).
#[pyfunction]
fn screw_centres_by_kennedy<'py>(
    py: Python<'py>,
    description_json: &str,
    q: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let mech = sc::MechanismJoints::from_description(&description(description_json)?).map_err(err)?;
    let q = slice(&q)?;
    let c = crate::guard("finding instant centres", || sc::centres_by_kennedy(&mech, q))?.map_err(err)?;
    centres_dict(py, &c)
}

/// The loop screws of a mechanism at q and whether they have collapsed.
#[pyfunction]
#[pyo3(signature = (description_json, q, tol=1e-9))]
fn screw_loop_singularity<'py>(
    py: Python<'py>,
    description_json: &str,
    q: PyReadonlyArray1<'py, f64>,
    tol: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let (d, q) = (description(description_json)?, slice(&q)?);
    let s = crate::guard("checking the loops", || sc::loop_singularity(&d, q, tol))?.map_err(err)?;
    let d = PyDict::new(py);
    d.set_item("joints", s.joints)?;
    d.set_item("locked", s.locked)?;
    d.set_item("loops", s.loops)?;
    d.set_item("singular_values", s.singular_values.into_pyarray(py))?;
    d.set_item("rank", s.rank)?;
    d.set_item("singular", s.singular)?;
    d.set_item("involved", s.involved)?;
    d.set_item("dependent", s.dependent)?;
    Ok(d)
}

/// Adds the screw classes and functions to `_core`.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PySerialArm>()?;
    m.add_class::<PyArmState>()?;
    m.add_function(wrap_pyfunction!(screw_join, m)?)?;
    m.add_function(wrap_pyfunction!(screw_meet, m)?)?;
    m.add_function(wrap_pyfunction!(screw_normalize, m)?)?;
    m.add_function(wrap_pyfunction!(screw_transport, m)?)?;
    m.add_function(wrap_pyfunction!(screw_centres_from_velocities, m)?)?;
    m.add_function(wrap_pyfunction!(screw_centres_by_kennedy, m)?)?;
    m.add_function(wrap_pyfunction!(screw_loop_singularity, m)?)?;
    Ok(())
}

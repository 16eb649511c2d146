//! Bindings of `linkwork::synthesis`: arrays in, dicts of lists out; one mapping of
//! `SynthesisError`. The public API (solution objects, models, screening) is
//! `linkwork.synthesis`.

use linkwork::synthesis::{self as syn, function as fg, motion, path, sixbar, Dyad, DyadSet, SynthesisError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::guard;

mod py_errors {
    pyo3::import_exception!(linkwork.errors, SynthesisError);
}

fn err(e: SynthesisError) -> PyErr {
    py_errors::SynthesisError::new_err(e.to_string())
}

fn dyads_dict<'py>(py: Python<'py>, dyads: &[Dyad], set: Option<&DyadSet>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("ground", dyads.iter().map(|x| x.ground.to_vec()).collect::<Vec<_>>())?;
    d.set_item("moving", dyads.iter().map(|x| x.moving.to_vec()).collect::<Vec<_>>())?;
    d.set_item("ground_imag", dyads.iter().map(|x| x.ground_imag.to_vec()).collect::<Vec<_>>())?;
    d.set_item("moving_imag", dyads.iter().map(|x| x.moving_imag.to_vec()).collect::<Vec<_>>())?;
    d.set_item("real", dyads.iter().map(|x| x.real).collect::<Vec<_>>())?;
    d.set_item("certified", dyads.iter().map(|x| x.certified).collect::<Vec<_>>())?;
    d.set_item("residual", dyads.iter().map(|x| x.residual).collect::<Vec<_>>())?;
    d.set_item("backward_error", dyads.iter().map(|x| x.backward_error).collect::<Vec<_>>())?;
    d.set_item("condition", dyads.iter().map(|x| x.condition).collect::<Vec<_>>())?;
    d.set_item("radius", dyads.iter().map(|x| x.radius).collect::<Vec<_>>())?;
    if let Some(s) = set {
        d.set_item("paths", s.paths)?;
        d.set_item("at_infinity", s.at_infinity)?;
        d.set_item("failed", s.failed)?;
        d.set_item("singular", s.singular)?;
        d.set_item("distinct", s.distinct)?;
    }
    Ok(d)
}

fn pairs(v: &[f64]) -> Vec<[f64; 2]> {
    v.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
}

fn poses(v: &[f64]) -> Vec<motion::Pose> {
    v.chunks_exact(3).map(|c| motion::Pose { x: c[0], y: c[1], angle: c[2] }).collect()
}

/// Every dyad of a problem. `problem`: "burmester" (poses n x 3), "timed" (points n x 2,
/// then n input angles), "chain1" (points, phi, theta; `point` = the input pivot Q),
/// "chain2" (points, phi, theta; `point` = the output pivot O); `method`: "homotopy" or "resultant" (real dyads only).
#[pyfunction]
#[pyo3(signature = (problem, method, poses_or_points, angles_a=vec![], angles_b=vec![], point=vec![]))]
pub(crate) fn synth_dyads<'py>(
    py: Python<'py>,
    problem: &str,
    method: &str,
    poses_or_points: Vec<f64>,
    angles_a: Vec<f64>,
    angles_b: Vec<f64>,
    point: Vec<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let homotopy = match method {
        "homotopy" => true,
        "resultant" => false,
        other => {
            return Err(err(SynthesisError::Degenerate(format!(
                "unknown method {other:?}: 'homotopy' or 'resultant'"
            ))))
        }
    };
    let what = format!("solving the {problem} synthesis");
    // the chained six-bar's pivot: Q (chain1, the input link's) or O (chain2, the output's)
    let pivot = match (problem, point.as_slice()) {
        ("chain1" | "chain2", [x, y]) => [*x, *y],
        ("chain1" | "chain2", _) => {
            let which = if problem == "chain1" { "the input pivot Q" } else { "the output pivot O" };
            return Err(err(SynthesisError::Count {
                problem: "the chained six-bar's dyads",
                got: point.len(),
                want: format!("{which} as a point (x, y)"),
            }));
        }
        _ => [0.0, 0.0],
    };
    let out: Result<(Vec<Dyad>, Option<DyadSet>), SynthesisError> = py.detach(|| {
        guard(&what, || match (problem, homotopy) {
            ("burmester", true) => {
                motion::burmester(&poses(&poses_or_points)).map(|s| (s.dyads.clone(), Some(s)))
            }
            ("burmester", false) => {
                motion::burmester_by_resultant(&poses(&poses_or_points)).map(|s| (s.dyads.clone(), Some(s)))
            }
            ("timed", true) => {
                path::timed_dyads(&pairs(&poses_or_points), &angles_a).map(|s| (s.dyads.clone(), Some(s)))
            }
            ("timed", false) => path::timed_dyads_by_resultant(&pairs(&poses_or_points), &angles_a)
                .map(|s| (s.dyads.clone(), Some(s))),
            ("chain1", true) => sixbar::dyad_1(&pairs(&poses_or_points), pivot, &angles_a, &angles_b)
                .map(|s| (s.dyads.clone(), Some(s))),
            ("chain2", true) => sixbar::dyad_2(&pairs(&poses_or_points), pivot, &angles_a, &angles_b)
                .map(|s| (s.dyads.clone(), Some(s))),
            ("chain1", false) => {
                sixbar::dyad_1_by_resultant(&pairs(&poses_or_points), pivot, &angles_a, &angles_b)
                    .map(|s| (s.dyads.clone(), Some(s)))
            }
            ("chain2", false) => {
                sixbar::dyad_2_by_resultant(&pairs(&poses_or_points), pivot, &angles_a, &angles_b)
                    .map(|s| (s.dyads.clone(), Some(s)))
            }
            _ => Err(SynthesisError::Degenerate(format!("unknown problem {problem:?}"))),
        })
    })?;
    let (dyads, set) = out.map_err(err)?;
    dyads_dict(py, &dyads, set.as_ref())
}

/// Closed forms: "three_ground" / "three_moving" (poses 3 x 3, the chosen point),
/// "two_ground" (poses 2 x 3, moving point, `along`), "four_curves" (poses 4 x 3,
/// `samples` rays).
#[pyfunction]
#[pyo3(signature = (problem, poses_flat, point=vec![], along=0.0, samples=360))]
pub(crate) fn synth_motion<'py>(
    py: Python<'py>,
    problem: &str,
    poses_flat: Vec<f64>,
    point: Vec<f64>,
    along: f64,
    samples: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let p = poses(&poses_flat);
    let pt = if point.len() == 2 { [point[0], point[1]] } else { [f64::NAN, f64::NAN] };
    if problem != "four_curves" && !(pt[0].is_finite() && pt[1].is_finite()) {
        return Err(err(SynthesisError::NotFinite { what: "the chosen point".into() }));
    }
    let what = format!("solving the {problem} motion synthesis");
    let out = py.detach(|| {
        guard(&what, || match problem {
            "three_ground" => motion::three_pose_ground(&p, pt).map(|d| vec![d]),
            "three_moving" => motion::three_pose_moving(&p, pt).map(|d| vec![d]),
            "two_ground" => motion::two_pose_ground(&p, pt, along).map(|d| vec![d]),
            "four_curves" => motion::four_pose_curves(&p, samples),
            _ => Err(SynthesisError::Degenerate(format!("unknown problem {problem:?}"))),
        })
    })?;
    dyads_dict(py, &out.map_err(err)?, None)
}

/// Freudenstein: "four_bar" -> (a, b, c, d), "slider_crank" -> (a, b, e).
#[pyfunction]
pub(crate) fn synth_freudenstein(
    kind: &str,
    input: Vec<f64>,
    output: Vec<f64>,
    ground: f64,
) -> PyResult<Vec<f64>> {
    match kind {
        "four_bar" => fg::four_bar(&input, &output, ground).map(|f| vec![f.a, f.b, f.c, f.d]).map_err(err),
        "slider_crank" => fg::slider_crank(&input, &output).map(|s| vec![s.a, s.b, s.e]).map_err(err),
        other => Err(err(SynthesisError::Degenerate(format!("unknown kind {other:?}")))),
    }
}

/// Chebyshev spacing of n points on [lo, hi].
#[pyfunction]
pub(crate) fn synth_chebyshev(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    fg::chebyshev(lo, hi, n)
}

/// The generic root count the dyad problems track, and how it was found.
#[pyfunction]
pub(crate) fn synth_start_set() -> (usize, usize, usize) {
    let s = syn::dyad::start_set();
    (s.roots.len(), s.total_degree.paths, s.total_degree.at_infinity)
}

/// Alt's nine-point problem: every class of four-bars through the points (flat 9 x 2),
/// by parameter homotopy from the shipped start set; the real four-bars with their
/// coupler rotations. `hatted` (flat 9 x 2, each pair a complex number) replaces the
/// points' conjugates: a complex instance, whose roots are counted but none is a
/// four-bar. `seconds`: the wall-time budget; paths still running then count as failed
/// and over budget.
#[pyfunction]
#[pyo3(signature = (points, hatted=None, seconds=30.0))]
pub(crate) fn synth_alt<'py>(
    py: Python<'py>,
    points: Vec<f64>,
    hatted: Option<Vec<f64>>,
    seconds: f64,
) -> PyResult<Bound<'py, PyDict>> {
    use linkwork::synthesis::alt;
    use num_complex::Complex64 as C64;
    let complex = |v: &[f64]| -> Vec<C64> { v.chunks_exact(2).map(|c| C64::new(c[0], c[1])).collect() };
    if points.len() != 18 || hatted.as_ref().is_some_and(|h| h.len() != 18) {
        return Err(err(SynthesisError::Count {
            problem: "Alt's nine-point path synthesis",
            got: points.len() / 2,
            want: "exactly 9 points".into(),
        }));
    }
    let listed = complex(&points);
    let frame = alt::check_points(&listed).map_err(err)?;
    let pts: [C64; 9] = std::array::from_fn(|k| listed[k]);
    let hat = match &hatted {
        Some(h) => {
            let hat = complex(h);
            syn::check_scale("the hatted points", &hat).map_err(err)?;
            Some(hat)
        }
        None => None,
    };
    if !(seconds > 0.0 && seconds <= 1e9) {
        return Err(err(SynthesisError::Degenerate(format!(
            "the time budget must be positive seconds, not {seconds}"
        ))));
    }
    let budget = std::time::Duration::from_secs_f64(seconds);
    let started = std::time::Instant::now();
    let out = py.detach(|| {
        guard("solving Alt's nine-point problem", || match &hat {
            None => alt::four_bars(&pts, alt::shipped(), budget),
            Some(hat) => {
                // the complex instance in the points' local units (roots are only counted)
                let p1: Vec<C64> = (1..9)
                    .map(|j| (pts[j] - pts[0]) / frame.scale)
                    .chain((1..9).map(|j| (hat[j] - hat[0]) / frame.scale))
                    .collect();
                let solutions = alt::solve_params(&p1, alt::shipped(), budget)?;
                Ok(alt::AltResult { solutions, physical_classes: 0, four_bars: vec![] })
            }
        })
    })?;
    let out = out.map_err(err)?;
    let seconds = started.elapsed().as_secs_f64();
    let d = PyDict::new(py);
    let s = &out.solutions;
    d.set_item("paths", s.paths)?;
    d.set_item("roots", s.roots.len())?;
    d.set_item("certified", s.roots.iter().filter(|r| r.certified).count())?;
    d.set_item("distinct", s.distinct)?;
    d.set_item("failed", s.failed)?;
    d.set_item("over_budget", s.over_budget)?;
    d.set_item("at_infinity", s.at_infinity)?;
    d.set_item("singular", s.singular.len())?;
    d.set_item("duplicates", s.duplicates)?;
    d.set_item("max_residual", s.roots.iter().map(|r| r.backward_error).fold(0.0, f64::max))?;
    d.set_item("physical_classes", out.physical_classes)?;
    d.set_item("seconds", seconds)?;
    let c = |z: C64| vec![z.re, z.im];
    d.set_item("ground_a", out.four_bars.iter().map(|f| c(f.ground_a)).collect::<Vec<_>>())?;
    d.set_item("moving_a", out.four_bars.iter().map(|f| c(f.moving_a)).collect::<Vec<_>>())?;
    d.set_item("ground_b", out.four_bars.iter().map(|f| c(f.ground_b)).collect::<Vec<_>>())?;
    d.set_item("moving_b", out.four_bars.iter().map(|f| c(f.moving_b)).collect::<Vec<_>>())?;
    d.set_item(
        "coupler_angles",
        out.four_bars.iter().map(|f| f.coupler_angles.to_vec()).collect::<Vec<_>>(),
    )?;
    d.set_item("class", out.four_bars.iter().map(|f| f.class).collect::<Vec<_>>())?;
    d.set_item("cognate", out.four_bars.iter().map(|f| f.cognate).collect::<Vec<_>>())?;
    Ok(d)
}

//! Outputs that would not fit are refused before a sweep starts, with what they need.

use crate::common;
use common::*;
use linkwork::{Model, Outputs, Request, SolveError, SweepOutput};

#[test]
fn outputs_larger_than_the_memory_available_are_refused() {
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let model = Model::new(four_bar(&m, 0.0, 5.0)).unwrap();
    let times: Vec<f64> = (0..1000).map(|k| k as f64 * 1e-3).collect();
    // 1000 steps x 9 coordinates x (q, qd, qdd) x 8 bytes, plus times and diagnostics
    let (bytes, what) = SweepOutput::bytes(&model, times.len(), Request::default(), &Outputs::all());
    assert_eq!(bytes, 1000 * (9 * 3 * 8 + 3 * 8 + 4 + 8));
    assert!(what.contains("qdd"));
    let err = SweepOutput::try_with_request(&model, &times, Request::default(), Some(bytes - 1)).unwrap_err();
    assert!(matches!(err, SolveError::TooLarge { .. }), "{err}");
    assert!(err.to_string().contains("every=k"), "{err}");
    let fewer = Request { derivatives: 0, every: 10, ..Request::default() };
    let out = SweepOutput::try_with_request(&model, &times, fewer, Some(bytes - 1)).unwrap();
    assert_eq!(out.n_steps, 100);
}

#[test]
fn outputs_kept_are_what_is_allocated_and_counted() {
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let model = Model::new(four_bar(&m, 0.0, 5.0)).unwrap();
    let times: Vec<f64> = (0..1000).map(|k| k as f64 * 1e-3).collect();
    // the rocker's angle and one coupler point: 1 + 2 values per step and derivative
    let outputs = Outputs { coords: Some(vec![8]), points: vec![(Some(1), [0.1, 0.05])] };
    let (bytes, _) = SweepOutput::bytes(&model, times.len(), Request::default(), &outputs);
    assert_eq!(bytes, 1000 * (3 * 3 * 8 + 3 * 8 + 4 + 8));
    let out =
        SweepOutput::try_with_outputs(&model, &times, Request::default(), outputs, Some(bytes)).unwrap();
    assert_eq!((out.q.len(), out.qdd.len(), out.points.len(), out.points_dd.len()), (1000, 1000, 2000, 2000));
    // a refusal names what to ask for instead
    let err = SweepOutput::try_with_request(&model, &times, Request::default(), Some(bytes)).unwrap_err();
    assert!(err.to_string().contains("outputs=[...]"), "{err}");
    // coordinates and bodies that do not exist are named
    for bad in [
        Outputs { coords: Some(vec![9]), points: vec![] },
        Outputs { coords: None, points: vec![(Some(3), [0.0, 0.0])] },
        Outputs { coords: None, points: vec![(None, [f64::NAN, 0.0])] },
    ] {
        let err = SweepOutput::try_with_outputs(&model, &times, Request::default(), bad, None).unwrap_err();
        assert!(matches!(err, SolveError::Outputs { .. }), "{err}");
    }
}

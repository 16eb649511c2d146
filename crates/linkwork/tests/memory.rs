//! Outputs that would not fit are refused before a sweep starts, with what they need.

mod common;
use common::*;
use linkwork::{Model, Request, SolveError, SweepOutput};

#[test]
fn outputs_larger_than_the_memory_available_are_refused() {
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let model = Model::new(four_bar(&m, 0.0, 5.0)).unwrap();
    let times: Vec<f64> = (0..1000).map(|k| k as f64 * 1e-3).collect();
    // 1000 steps x 9 coordinates x (q, qd, qdd) x 8 bytes, plus times and diagnostics
    let (bytes, what) = SweepOutput::bytes(&model, times.len(), Request::default());
    assert_eq!(bytes, 1000 * (9 * 3 * 8 + 3 * 8 + 4 + 8));
    assert!(what.contains("qdd"));
    let err = SweepOutput::try_with_request(&model, &times, Request::default(), Some(bytes - 1)).unwrap_err();
    assert!(matches!(err, SolveError::TooLarge { .. }), "{err}");
    assert!(err.to_string().contains("every=k"), "{err}");
    let fewer = Request { derivatives: 0, every: 10, ..Request::default() };
    let out = SweepOutput::try_with_request(&model, &times, fewer, Some(bytes - 1)).unwrap();
    assert_eq!(out.n_steps, 100);
}

//! A sweep told what to keep (`Outputs`) solves exactly as the full sweep: the kept
//! columns are the full sweep's, bit for bit, and the kept points are the body points of
//! the full sweep's poses, on the structured and on the general path.

use crate::common;
use common::*;
use linkwork::{sweep, Data, Model, Options, Outputs, Request, SolverKind, SweepOutput};

fn swept(model: &Model, times: &[f64], request: Request, outputs: Outputs) -> SweepOutput {
    let mut data = Data::new(model);
    let mut out = SweepOutput::try_with_outputs(model, times, request, outputs, None).unwrap();
    sweep(model, &mut data, times, &mut out, 0, &mut |_| true).unwrap();
    out
}

/// World position, velocity and acceleration of body point u from a full sweep's row.
fn point_of(out: &SweepOutput, row: usize, b: usize, u: [f64; 2]) -> [[f64; 2]; 3] {
    let m = out.n_coords;
    let at = |v: &[f64], i: usize| v[row * m + 3 * b + i];
    let (s, c) = at(&out.q, 2).sin_cos();
    let au = [c * u[0] - s * u[1], s * u[0] + c * u[1]];
    let (w, al) = (at(&out.qd, 2), at(&out.qdd, 2));
    [
        [at(&out.q, 0) + au[0], at(&out.q, 1) + au[1]],
        [at(&out.qd, 0) - w * au[1], at(&out.qd, 1) + w * au[0]],
        [at(&out.qdd, 0) - al * au[1] - w * w * au[0], at(&out.qdd, 1) + al * au[0] - w * w * au[1]],
    ]
}

#[test]
fn kept_outputs_are_the_full_sweeps() {
    let cases = [
        ("four-bar", four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0)),
        ("slider-crank", slider_crank(&SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 }, 0.0, 5.0)),
        ("Stephenson six-bar", six_bar_stephenson(0.0, 5.0)),
    ];
    let times: Vec<f64> = (0..2000).map(|k| k as f64 * 1e-3).collect();
    for (name, desc) in cases {
        for solver in [SolverKind::Auto, SolverKind::General] {
            let model = Model::with_options(desc.clone(), Options { solver, ..Options::default() }).unwrap();
            let last = model.n_bodies - 1;
            let points = vec![(Some(1), [0.03, -0.07]), (Some(last), [0.1, 0.02]), (None, [0.5, 0.25])];
            let coords = vec![3 * last + 2, 0, 3 * last + 2];
            for request in [Request::default(), Request { every: 7, ..Request::default() }] {
                let full = swept(&model, &times, request, Outputs::all());
                let outputs = Outputs { coords: Some(coords.clone()), points: points.clone() };
                let kept = swept(&model, &times, request, outputs);
                assert_eq!(kept.n_done, full.n_done, "{name}");
                assert_eq!(kept.events.len(), full.events.len(), "{name}");
                let m = full.n_coords;
                for row in 0..full.n_done {
                    for (k, &c) in coords.iter().enumerate() {
                        // the same solve: the same bits
                        assert_eq!(kept.q[row * 3 + k], full.q[row * m + c], "{name} row {row}");
                        assert_eq!(kept.qd[row * 3 + k], full.qd[row * m + c], "{name} row {row}");
                        assert_eq!(kept.qdd[row * 3 + k], full.qdd[row * m + c], "{name} row {row}");
                    }
                    for (i, &(body, u)) in points.iter().enumerate() {
                        let want = match body {
                            Some(b) => point_of(&full, row, b, u),
                            None => [u, [0.0; 2], [0.0; 2]],
                        };
                        let at = row * 2 * points.len() + 2 * i;
                        for (got, (want, tol)) in [&kept.points, &kept.points_d, &kept.points_dd]
                            .iter()
                            .zip(want.iter().zip([1e-15, 1e-14, 1e-13]))
                        {
                            for a in 0..2 {
                                // cos, sin from the pins (structured) or from theta: round-off apart
                                assert!((got[at + a] - want[a]).abs() <= tol, "{name} row {row} point {i}");
                            }
                        }
                    }
                    assert_eq!(kept.pivot_ratio[row], full.pivot_ratio[row]);
                }
            }
        }
    }
}

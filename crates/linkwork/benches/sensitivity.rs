//! Sensitivity benchmark (criterion): the textbook four-bar over 100,000 steps (one crank
//! revolution, as the sweep benchmark), side by side for each solver (`structured`, the
//! default, and `general`):
//! - `sweep`: positions, velocities and accelerations, against `sweep_and_10_sensitivities`:
//!   the same with dq/dp, dqd/dp, dqdd/dp to 10 parameters (the pins O2, A and B in their
//!   bodies), which the general path solves;
//! - `sweep_positions` (`Request::derivatives` 0), against `sweep_positions_and_10_dq`:
//!   the same with dq/dp alone to the same 10 parameters, which the structured model
//!   solves group by group (`SensitivityPath::Structured`).
//!
//! Then the same four-bar with masses and gravity: its sweep with forces against the same
//! sweep with the 10 parameters' sensitivities and their efforts' (dlambda/dp).
//!
//! Outputs are allocated outside the timing, as in the sweep benchmark. The issue's
//! target: dq/dp cost at most 2x the sweep. Run:
//!
//!     cargo bench -p linkwork --bench sensitivity

#[path = "../tests/common/mod.rs"]
mod common;

use common::*;
use criterion::{criterion_group, criterion_main, BatchSize, Bencher, BenchmarkId, Criterion, Throughput};
use linkwork::sensitivity::{
    sensitivity_sweep, Parameter, SensitivityOutput, SensitivityPath, SensitivityRequest,
};
use linkwork::{sweep, Data, Description, Model, Options, Request, SolverKind, SweepOutput};
use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Duration;

const STEPS: usize = 100_000;
const N_PARAMS: usize = 10;

/// Times a plain sweep into `out`, reading `last` of it.
fn time_sweep(
    b: &mut Bencher,
    model: &Model,
    times: &[f64],
    out: &mut SweepOutput,
    last: fn(&SweepOutput) -> f64,
) {
    b.iter_batched_ref(
        || Data::new(model),
        |data| {
            sweep(model, data, black_box(times), out, 0, &mut |_| true).unwrap();
            black_box(last(out))
        },
        BatchSize::LargeInput,
    )
}

/// Times a sweep with its sensitivities to `params` into `out`, reading `last` of it.
fn time_sensitivities(
    b: &mut Bencher,
    model: &Model,
    times: &[f64],
    params: &[Parameter],
    out: &mut SensitivityOutput,
    last: fn(&SensitivityOutput) -> f64,
) {
    b.iter_batched_ref(
        || Data::new(model),
        |data| {
            sensitivity_sweep(model, data, black_box(times), params, &[], out, 0, &mut |_| true).unwrap();
            black_box(last(out))
        },
        BatchSize::LargeInput,
    )
}

fn sensitivities(c: &mut Criterion) {
    let desc = four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0);
    let h = 2.0 * PI / 5.0 / STEPS as f64;
    let times: Vec<f64> = (0..STEPS).map(|k| k as f64 * h).collect();
    let mut g = c.benchmark_group("four_bar_sensitivities");
    g.throughput(Throughput::Elements(STEPS as u64));
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    for (name, solver) in [("structured", SolverKind::Auto), ("general", SolverKind::General)] {
        let model = Model::with_options(desc.clone(), Options { solver, ..Options::default() }).unwrap();
        let params: Vec<Parameter> = Parameter::all(&model).into_iter().take(N_PARAMS).collect();
        for (what, derivatives) in [("sweep", 2), ("sweep_positions", 0)] {
            let mut out =
                SweepOutput::with_request(&model, &times, Request { derivatives, ..Request::default() });
            g.bench_function(BenchmarkId::new(name, what), |b| {
                time_sweep(b, &model, &times, &mut out, |o| o.q[o.q.len() - 1])
            });
        }
        for (what, derivatives) in [("sweep_and_10_sensitivities", 2), ("sweep_positions_and_10_dq", 0)] {
            let request = SensitivityRequest { derivatives, ..SensitivityRequest::default() };
            let mut out = SensitivityOutput::with_request(&model, &times, &params, 0, request);
            g.bench_function(BenchmarkId::new(name, what), |b| {
                time_sensitivities(b, &model, &times, &params, &mut out, |o| o.dq[o.dq.len() - 1])
            });
            // the path measured is the one the table names
            let structured = solver == SolverKind::Auto && derivatives == 0;
            let want = if structured { SensitivityPath::Structured } else { SensitivityPath::General };
            assert_eq!((out.path, out.general_steps), (want, 0), "{name} {what}: {}", out.path_reason);
        }
    }
    g.finish();
}

fn efforts(c: &mut Criterion) {
    let mut desc: Description = four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0);
    for b in &mut desc.bodies {
        (b.mass, b.inertia) = (1.5, 0.01);
    }
    desc.gravity = [0.0, -9.81];
    let h = 2.0 * PI / 5.0 / STEPS as f64;
    let times: Vec<f64> = (0..STEPS).map(|k| k as f64 * h).collect();
    let mut g = c.benchmark_group("four_bar_effort_sensitivities");
    g.throughput(Throughput::Elements(STEPS as u64));
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    for (name, solver) in [("structured", SolverKind::Auto), ("general", SolverKind::General)] {
        let model = Model::with_options(desc.clone(), Options { solver, ..Options::default() }).unwrap();
        let mut out = SweepOutput::with_forces(&model, &times);
        g.bench_function(BenchmarkId::new(name, "sweep_with_forces"), |b| {
            time_sweep(b, &model, &times, &mut out, |o| o.lambda[o.lambda.len() - 1])
        });
        let params: Vec<Parameter> = Parameter::all(&model).into_iter().take(N_PARAMS).collect();
        let mut out = SensitivityOutput::with_efforts(&model, &times, &params, 0);
        g.bench_function(BenchmarkId::new(name, "sweep_and_10_sensitivities_with_efforts"), |b| {
            time_sensitivities(b, &model, &times, &params, &mut out, |o| o.dlambda[o.dlambda.len() - 1])
        });
    }
    g.finish();
}

criterion_group!(benches, sensitivities, efforts);
criterion_main!(benches);

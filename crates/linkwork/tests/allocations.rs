//! The per-step loop allocates nothing: a sweep of 2,000 steps makes exactly as many
//! heap allocations as a sweep of 20 (all of them before the loop or at the first
//! factorization), counted by a global allocator, per thread; the fixed-sequence LU keeps
//! its first pivot sequence through them. Likewise a sweep with its sensitivities, on
//! either path.

mod common;
use common::*;
use linkwork::sensitivity::{
    sensitivity_sweep, Parameter, SensitivityOutput, SensitivityPath, SensitivityRequest,
};
use linkwork::{sweep, Data, LinearKind, Model, Options, SweepOutput};

#[path = "common/counting.rs"]
mod counting;
use counting::allocations;

fn allocations_of_sweep(model: &Model, n: usize) -> usize {
    allocations_and_pivot_choices(model, n).0
}

/// Allocations of a sweep of n steps of 1 ms, and how many times the fixed-sequence LU
/// chose its pivots in it.
fn allocations_and_pivot_choices(model: &Model, n: usize) -> (usize, usize) {
    let times: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
    let mut data = Data::new(model);
    let mut out = SweepOutput::new(model, &times);
    let before = allocations();
    sweep(model, &mut data, &times, &mut out, 0, &mut |_| true).unwrap();
    (allocations() - before, data.pivot_choices())
}

#[test]
fn the_sweep_loop_allocates_nothing_per_step() {
    let desc = four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0);
    for linear in [LinearKind::Refactor, LinearKind::Small, LinearKind::Dense, LinearKind::Sparse] {
        let model = Model::with_options(desc.clone(), Options { linear, ..Options::default() }).unwrap();
        let few = allocations_of_sweep(&model, 20);
        let many = allocations_of_sweep(&model, 2_000);
        assert_eq!(few, many, "{linear:?}: {few} allocations for 20 steps, {many} for 2000");
    }
}

#[test]
fn the_fixed_pivot_sequence_replays_without_allocating() {
    // the pivots are chosen (and the program allocated) once, at the first factorization;
    // 2,000 steps (1.6 crank turns) replay it: no re-pivoting, no allocation
    let textbook = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let cases = [
        ("four_bar", four_bar(&textbook, 0.0, 5.0)),
        ("slider_crank", slider_crank(&SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 }, 0.0, 5.0)),
        ("six_bar_stephenson", six_bar_stephenson(0.0, 5.0)),
        ("chain_30", chain(&textbook, 30, 0.0, 5.0, -0.8644, 0.0)),
    ];
    for (name, desc) in cases {
        let model = Model::with_options(desc, Options { linear: LinearKind::Refactor, ..Options::default() })
            .unwrap();
        let (few, choices_few) = allocations_and_pivot_choices(&model, 20);
        let (many, choices_many) = allocations_and_pivot_choices(&model, 2_000);
        assert_eq!((choices_few, choices_many), (1, 1), "{name}: pivots chosen more than once");
        assert_eq!(few, many, "{name}: {few} allocations for 20 steps, {many} for 2000");
    }
}

/// Allocations of a sweep of n steps of 1 ms with the sensitivities `request` asks for, to
/// every engine parameter, and the path that solved them.
fn allocations_of_sensitivities(
    model: &Model,
    request: SensitivityRequest,
    n: usize,
) -> (usize, SensitivityPath) {
    let times: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
    let params = Parameter::all(model);
    let mut data = Data::new(model);
    let mut out = SensitivityOutput::with_request(model, &times, &params, 0, request);
    let before = allocations();
    sensitivity_sweep(model, &mut data, &times, &params, &[], &mut out, 0, &mut |_| true).unwrap();
    (allocations() - before, out.path)
}

#[test]
fn the_sensitivity_loop_allocates_nothing_per_step() {
    let desc = four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0);
    let model = Model::new(desc).unwrap();
    let structured = SensitivityRequest { derivatives: 0, general: false };
    for (request, path) in
        [(structured, SensitivityPath::Structured), (SensitivityRequest::default(), SensitivityPath::General)]
    {
        let (few, p) = allocations_of_sensitivities(&model, request, 20);
        let (many, _) = allocations_of_sensitivities(&model, request, 2_000);
        assert_eq!(p, path);
        assert_eq!(few, many, "{path:?}: {few} allocations for 20 steps, {many} for 2000");
    }
}

//! Sweep benchmarks (criterion): time per step of the engine alone, no Python.
//!
//! - `four_bar`, `slider_crank`, `six_bar_stephenson`: positions + velocities +
//!   accelerations with each linear solver (small: linkwork's own dense LU; dense: faer's
//!   dense LU; sparse: faer's sparse LU), and the four-bar's positions only.
//! - `chain`: K four-bar loops in series (3K bodies, stacked on the same pivots, tie angle
//!   `CHAIN_OFFSET`), K = 1, 10, 100, 1000; sparse LU at every K, the dense paths up to
//!   K = 10 (90 coordinates).
//! - `batch`: 8 four-bar designs on 1 and 2 threads (`sweep_batch`).
//!
//! Every sweep steps at h = one crank revolution / 100,000 (as `benches/compare.py`), so
//! the Newton work per step is the same at every K. Run:
//!     cargo bench -p linkwork --bench sweep
//!     python benches/criterion_report.py --write    # the table in docs/performance.md

#[path = "../tests/common/mod.rs"]
mod common;

use common::*;
use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion, Throughput};
use linkwork::{sweep, sweep_batch, Data, Description, LinearKind, Model, Options, Request, SweepOutput};
use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Duration;

/// One crank revolution (5 rad/s) in 100,000 steps.
const H: f64 = 2.0 * PI / 5.0 / 100_000.0;
const KINDS: [LinearKind; 3] = [LinearKind::Small, LinearKind::Dense, LinearKind::Sparse];
/// The chain's tie angle, as `benches/compare.py` computes it (`chain_offset`): the loops
/// settle where a loop's gain d theta4 / d theta2 is -0.97, so every loop keeps moving
/// and no rate underflows into subnormal numbers along the chain.
const CHAIN_OFFSET: f64 = -0.8644;

fn times(steps: usize) -> Vec<f64> {
    (0..steps).map(|k| k as f64 * H).collect()
}

fn textbook() -> FourBar {
    FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }
}

fn kind_name(linear: LinearKind) -> String {
    format!("{linear:?}").to_lowercase()
}

/// One benchmark: a whole sweep of `steps` steps from the described configuration. The
/// model, outputs and workspace are made outside the timing, and only when the benchmark
/// is selected (criterion calls the closure only then), so a filtered run, or a profile
/// of one, does only that benchmark's work.
fn bench_sweep(
    c: &mut Criterion,
    group: &str,
    id: BenchmarkId,
    desc: &Description,
    linear: LinearKind,
    steps: usize,
    derivatives: u8,
) {
    let times = times(steps);
    let mut g = c.benchmark_group(group);
    g.throughput(Throughput::Elements(steps as u64));
    g.bench_function(id, |b| {
        let model = Model::with_options(desc.clone(), Options { linear, ..Options::default() }).unwrap();
        let mut out = SweepOutput::with_derivatives(&model, &times, derivatives);
        b.iter_batched_ref(
            || Data::new(&model),
            |data| {
                sweep(&model, data, black_box(&times), &mut out, 0, &mut |_| true).unwrap();
                black_box(out.q[out.q.len() - 1])
            },
            BatchSize::LargeInput,
        )
    });
    g.finish();
}

fn mechanisms(c: &mut Criterion) {
    const STEPS: usize = 10_000;
    let cases = [
        ("four_bar", four_bar(&textbook(), 0.0, 5.0)),
        ("slider_crank", slider_crank(&SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 }, 0.0, 5.0)),
        ("six_bar_stephenson", six_bar_stephenson(0.0, 5.0)),
    ];
    for (name, desc) in &cases {
        for linear in KINDS {
            bench_sweep(c, name, BenchmarkId::new(kind_name(linear), "pva"), desc, linear, STEPS, 2);
        }
    }
    let desc = &cases[0].1;
    for linear in KINDS {
        bench_sweep(c, "four_bar", BenchmarkId::new(kind_name(linear), "p"), desc, linear, STEPS, 0);
    }
}

fn chains(c: &mut Criterion) {
    for loops in [1usize, 10, 100, 1000] {
        let desc = chain(&textbook(), loops, 0.0, 5.0, CHAIN_OFFSET, 0.0);
        let steps = (10_000 / loops).max(50);
        for linear in KINDS {
            if linear != LinearKind::Sparse && loops > 10 {
                continue; // dense LU of 900+ coordinates: cubic, and not what "auto" picks
            }
            bench_sweep(c, "chain", BenchmarkId::new(kind_name(linear), loops), &desc, linear, steps, 2);
        }
    }
}

fn batch(c: &mut Criterion) {
    const DESIGNS: usize = 8;
    const STEPS: usize = 10_000;
    let times = times(STEPS);
    let mut g = c.benchmark_group("batch");
    g.throughput(Throughput::Elements((DESIGNS * STEPS) as u64));
    for threads in [1usize, 2] {
        g.bench_function(BenchmarkId::new("threads", threads), |b| {
            let models: Vec<Model> = (0..DESIGNS)
                .map(|i| {
                    let crank = 0.15 + 0.07 * i as f64 / (DESIGNS - 1) as f64;
                    Model::new(four_bar(&FourBar { r2: crank, ..textbook() }, 0.0, 5.0)).unwrap()
                })
                .collect();
            let refs: Vec<&Model> = models.iter().collect();
            b.iter(|| {
                let items = sweep_batch(&refs, black_box(&times), Request::default(), threads, &mut |_| true);
                black_box(items.len())
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = sweep_benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = mechanisms, chains, batch
}
criterion_main!(sweep_benches);

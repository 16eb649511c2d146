//! Sweep benchmarks: time per step of position + velocity + acceleration analysis, for
//! the dense and the sparse LU on the same mechanisms (the seam's choice is made by
//! these figures). Run: cargo bench -p linkwork --bench sweep

#[path = "../tests/common/mod.rs"]
mod common;

use common::*;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linkwork::{sweep, Data, Description, LinearKind, Model, Options, SweepOutput};
use std::f64::consts::PI;
use std::hint::black_box;

const STEPS: usize = 10_000;

fn bench_mechanism(c: &mut Criterion, name: &str, desc: Description) {
    let times: Vec<f64> = (0..STEPS).map(|k| k as f64 * 2.0 * PI / 5.0 / (STEPS - 1) as f64).collect();
    let mut group = c.benchmark_group(name);
    group.throughput(Throughput::Elements(STEPS as u64));
    for linear in [LinearKind::Dense, LinearKind::Sparse] {
        let model = Model::with_options(desc.clone(), Options { linear, ..Options::default() }).unwrap();
        let mut out = SweepOutput::new(&model, &times);
        group.bench_with_input(
            BenchmarkId::new(format!("{linear:?}").to_lowercase(), STEPS),
            &times,
            |b, times| {
                b.iter(|| {
                    let mut data = Data::new(&model);
                    sweep(&model, &mut data, black_box(times), &mut out, 0, &mut |_| true).unwrap();
                    black_box(out.qdd[out.qdd.len() - 1])
                })
            },
        );
    }
    group.finish();
}

fn benches(c: &mut Criterion) {
    bench_mechanism(c, "four_bar", four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0));
    bench_mechanism(c, "slider_crank", slider_crank(&SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 }, 0.0, 5.0));
}

criterion_group! {
    name = sweep_benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = benches
}
criterion_main!(sweep_benches);

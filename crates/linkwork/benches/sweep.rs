//! Sweep benchmarks (criterion): time per step of the engine alone, no Python.
//!
//! - `four_bar`, `slider_crank`, `six_bar_stephenson`: positions + velocities +
//!   accelerations with each linear solver (refactor: linkwork's sparse LU with a fixed
//!   pivot sequence, the default; small: linkwork's own dense LU; dense: faer's dense LU;
//!   sparse: faer's sparse LU), and the four-bar's (and, default LU only, the
//!   slider-crank's) positions only.
//! - `chain`: K four-bar loops in series (3K bodies, stacked on the same pivots, tie angle
//!   `CHAIN_OFFSET`), K = 1, 10, 100, 1000; the sparse LUs at every K, the dense paths up
//!   to K = 10 (90 coordinates); at least 500 steps, so the first step's assembly is
//!   spread as over a sweep.
//! - `lu`: one factorization and three solves (Newton step, velocity, acceleration) of
//!   the four-bar's and the 100-loop chain's Phi_q at a solved configuration, by
//!   `sparse_lu` replaying its program and by `small_lu`.
//! - `batch`: 8 four-bar designs on 1 and 2 threads (`sweep_batch`).
//! - `.../structured/point_path`: one coupler point's path only (positions, no
//!   coordinates kept), against `.../structured/pva`, the full output.
//! - `floor`: the four-bar and the slider-crank by a hand-written closed-form loop that
//!   computes and stores what the engine's sweep stores (every body's x, y, theta and,
//!   for "pva", their first and second derivatives, row-major per step): the floor a
//!   structure-aware engine is measured against.
//!
//! Every sweep steps at h = one crank revolution / 100,000 (as `benches/compare.py`), so
//! the Newton work per step is the same at every K. Run:
//!     cargo bench -p linkwork --bench sweep
//!     python benches/criterion_report.py --write    # the table in docs/performance.md

#[path = "../tests/common/mod.rs"]
mod common;

use common::*;
use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion, Throughput};
use linkwork::{
    sweep, sweep_batch, Data, Description, LinearKind, Model, Options, Outputs, Request, SolverKind,
    SweepOutput,
};
use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Duration;

/// One crank revolution (5 rad/s) in 100,000 steps.
const H: f64 = 2.0 * PI / 5.0 / 100_000.0;
const KINDS: [LinearKind; 4] =
    [LinearKind::Refactor, LinearKind::Small, LinearKind::Dense, LinearKind::Sparse];
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
    bench_outputs(c, group, id, desc, linear, SolverKind::General, steps, derivatives, Outputs::all())
}

/// `bench_sweep` with the solver chosen (`Auto` is the structure-aware path, the groups one
/// after another; `General` the whole model as one sparse system with `linear`), keeping
/// only `outputs`.
#[allow(clippy::too_many_arguments)]
fn bench_outputs(
    c: &mut Criterion,
    group: &str,
    id: BenchmarkId,
    desc: &Description,
    linear: LinearKind,
    solver: SolverKind,
    steps: usize,
    derivatives: u8,
    outputs: Outputs,
) {
    let times = times(steps);
    let mut g = c.benchmark_group(group);
    g.throughput(Throughput::Elements(steps as u64));
    g.bench_function(id, |b| {
        let model =
            Model::with_options(desc.clone(), Options { linear, solver, ..Options::default() }).unwrap();
        let request = Request { derivatives, ..Request::default() };
        let mut out = SweepOutput::with_outputs(&model, &times, request, outputs.clone());
        b.iter_batched_ref(
            || Data::new(&model),
            |data| {
                sweep(&model, data, black_box(&times), &mut out, 0, &mut |_| true).unwrap();
                black_box((out.q.last().copied(), out.points.last().copied()))
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
    let auto = LinearKind::Auto;
    for (name, desc) in &cases {
        for linear in KINDS {
            bench_sweep(c, name, BenchmarkId::new(kind_name(linear), "pva"), desc, linear, STEPS, 2);
        }
        for (what, d) in [("pva", 2), ("p", 0)] {
            let id = BenchmarkId::new("structured", what);
            bench_outputs(c, name, id, desc, auto, SolverKind::Auto, STEPS, d, Outputs::all());
        }
        // one coupler point's path and nothing else (the coupler is body 1 in each)
        let path = Outputs { coords: Some(Vec::new()), points: vec![(Some(1), [0.05, 0.04])] };
        let id = BenchmarkId::new("structured", "point_path");
        bench_outputs(c, name, id, desc, auto, SolverKind::Auto, STEPS, 0, path);
    }
    let desc = &cases[0].1;
    for linear in KINDS {
        bench_sweep(c, "four_bar", BenchmarkId::new(kind_name(linear), "p"), desc, linear, STEPS, 0);
    }
    // the slider-crank's positions, for the closed-form floor's table
    let refactor = BenchmarkId::new(kind_name(LinearKind::Refactor), "p");
    bench_sweep(c, "slider_crank", refactor, &cases[1].1, LinearKind::Refactor, STEPS, 0);
}

fn chains(c: &mut Criterion) {
    for loops in [1usize, 10, 100, 1000] {
        let desc = chain(&textbook(), loops, 0.0, 5.0, CHAIN_OFFSET, 0.0);
        // at least 500 steps: the first step assembles the whole chain by the general path
        // (a sparse LU of 9,000 coordinates at 1,000 loops), a cost of the sweep, not of
        // its steps; at 50 steps it was a fifth of the time measured
        let steps = (10_000 / loops).max(500);
        for linear in KINDS {
            if matches!(linear, LinearKind::Small | LinearKind::Dense) && loops > 10 {
                continue; // dense LU of 900+ coordinates: cubic, and not what "auto" picks
            }
            bench_sweep(c, "chain", BenchmarkId::new(kind_name(linear), loops), &desc, linear, steps, 2);
        }
        let id = BenchmarkId::new("structured", loops);
        bench_outputs(c, "chain", id, &desc, LinearKind::Auto, SolverKind::Auto, steps, 2, Outputs::all());
    }
}

fn lu(c: &mut Criterion) {
    let mut g = c.benchmark_group("lu");
    let cases = [
        ("four_bar", four_bar(&textbook(), 0.3, 5.0)),
        ("chain_100", chain(&textbook(), 100, 0.3, 5.0, CHAIN_OFFSET, 0.0)),
    ];
    for (name, desc) in &cases {
        // Phi_q at a solved configuration, in compressed columns
        let model =
            Model::with_options(desc.clone(), Options { linear: LinearKind::Refactor, ..Options::default() })
                .unwrap();
        let mut data = Data::new(&model);
        linkwork::solve(&model, &mut data, 0.0).unwrap();
        let (ptr, rows) = model.sparsity().unwrap();
        let (n, values) = (model.n_coords, data.jacobian().to_vec());
        let order = linkwork::sparse_lu::colamd_order(n, ptr, rows);
        let b: Vec<f64> = (0..n).map(|i| 1.0 + i as f64 / n as f64).collect();
        g.bench_function(BenchmarkId::new("refactor", name), |bench| {
            let mut lu = linkwork::sparse_lu::SparseLu::new(n, ptr, rows, &order);
            lu.factor(&values);
            let mut x = b.clone();
            bench.iter(|| {
                let piv = lu.factor(black_box(&values));
                for _ in 0..3 {
                    x.copy_from_slice(&b);
                    lu.solve(&mut x);
                }
                black_box((piv.ratio, x[0]))
            })
        });
        if n > 48 {
            continue;
        }
        let mut dense = vec![0.0; n * n];
        for col in 0..n {
            for p in ptr[col]..ptr[col + 1] {
                dense[col * n + rows[p]] = values[p];
            }
        }
        g.bench_function(BenchmarkId::new("small", name), |bench| {
            let (mut a, mut piv, mut inv) = (dense.clone(), vec![0; n], vec![0.0; n]);
            let mut x = b.clone();
            bench.iter(|| {
                a.copy_from_slice(black_box(&dense));
                linkwork::small_lu::factor(&mut a, n, &mut piv, &mut inv);
                for _ in 0..3 {
                    x.copy_from_slice(&b);
                    linkwork::small_lu::solve(&a, n, &piv, &inv, &mut x);
                }
                black_box(x[0])
            })
        });
    }
    g.finish();
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

/// The closed-form floor: per step, the crank angle from its law, the loop's angles, rates
/// and accelerations (tests/common's closed forms), the body frames' poses and their
/// derivatives, stored row-major into preallocated q, qd, qdd (n_steps x 9).
fn floor(c: &mut Criterion) {
    const STEPS: usize = 10_000;
    const OMEGA: f64 = 5.0;
    let times = times(STEPS);
    let mut g = c.benchmark_group("floor");
    g.throughput(Throughput::Elements(STEPS as u64));
    for derivatives in [2u8, 0] {
        let id = if derivatives == 2 { "pva" } else { "p" };
        let fb = textbook();
        g.bench_function(BenchmarkId::new("four_bar", id), |b| {
            let (mut q, mut qd, mut qdd) = (vec![0.0; 9 * STEPS], vec![0.0; 9 * STEPS], vec![0.0; 9 * STEPS]);
            b.iter(|| {
                for (k, &t) in black_box(&times).iter().enumerate() {
                    let th2 = OMEGA * t;
                    let ([th3, th4], [w3, w4], [a3, a4]) = four_bar_closed(&fb, th2, OMEGA, 0.0);
                    let (s2, c2) = th2.sin_cos();
                    let row = 9 * k;
                    q[row..row + 9].copy_from_slice(&[
                        0.0,
                        0.0,
                        th2,
                        fb.r2 * c2,
                        fb.r2 * s2,
                        th3,
                        fb.r1,
                        0.0,
                        th4,
                    ]);
                    if derivatives == 2 {
                        let (v, a) = (fb.r2 * OMEGA, -fb.r2 * OMEGA * OMEGA);
                        qd[row..row + 9].copy_from_slice(&[
                            0.0,
                            0.0,
                            OMEGA,
                            -v * s2,
                            v * c2,
                            w3,
                            0.0,
                            0.0,
                            w4,
                        ]);
                        qdd[row..row + 9].copy_from_slice(&[0.0, 0.0, 0.0, a * c2, a * s2, a3, 0.0, 0.0, a4]);
                    }
                }
                black_box((q[9 * STEPS - 1], qd[9 * STEPS - 1], qdd[9 * STEPS - 1]))
            })
        });
        let sc = SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 };
        g.bench_function(BenchmarkId::new("slider_crank", id), |b| {
            let (mut q, mut qd, mut qdd) = (vec![0.0; 9 * STEPS], vec![0.0; 9 * STEPS], vec![0.0; 9 * STEPS]);
            b.iter(|| {
                for (k, &t) in black_box(&times).iter().enumerate() {
                    let th2 = OMEGA * t;
                    let ([th3, x], [w3, v], [a3, acc]) = slider_crank_closed(&sc, th2, OMEGA, 0.0);
                    let (s2, c2) = th2.sin_cos();
                    let row = 9 * k;
                    q[row..row + 9].copy_from_slice(&[
                        0.0,
                        0.0,
                        th2,
                        sc.r2 * c2,
                        sc.r2 * s2,
                        th3,
                        x,
                        sc.e,
                        0.0,
                    ]);
                    if derivatives == 2 {
                        let (u, a) = (sc.r2 * OMEGA, -sc.r2 * OMEGA * OMEGA);
                        qd[row..row + 9].copy_from_slice(&[
                            0.0,
                            0.0,
                            OMEGA,
                            -u * s2,
                            u * c2,
                            w3,
                            v,
                            0.0,
                            0.0,
                        ]);
                        qdd[row..row + 9].copy_from_slice(&[
                            0.0,
                            0.0,
                            0.0,
                            a * c2,
                            a * s2,
                            a3,
                            acc,
                            0.0,
                            0.0,
                        ]);
                    }
                }
                black_box((q[9 * STEPS - 1], qd[9 * STEPS - 1], qdd[9 * STEPS - 1]))
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
    targets = mechanisms, chains, lu, batch, floor
}
criterion_main!(sweep_benches);

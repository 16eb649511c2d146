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
//!   for "pva", their first and second derivatives, row-major per step), as such a loop
//!   is written (one sine and cosine of the crank, one square root, the angles by atan2
//!   or asin): the floor a structure-aware engine is measured against. `pva_guarded`: the
//!   same with what the engine checks and keeps at every step (`Guard`), the price of
//!   "every step right or an explicit event" written by hand. `pva_continued`,
//!   `p_continued` (four-bar): the guarded loop with its angles continued as the engine
//!   continues them (`turned`, `angle_of`), every coordinate's rates solved for the check
//!   and kept (pva) or not (p): the least a step that keeps the promise costs.
//!
//! Every sweep steps at h = one crank revolution / 100,000 (as `benches/compare.py`), so
//! the Newton work per step is the same at every K. Run:
//!     cargo bench -p linkwork --bench sweep
//!     python benches/criterion_report.py --write    # the table in docs/performance.md

#[path = "../tests/common/mod.rs"]
mod common;

use common::*;
use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion, Throughput};
use linkwork::constraints::Frame;
use linkwork::math::angle::{angle_of, turned};
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

/// The four-bar's pins at crank angle theta2 (its sine and cosine), as a hand-written
/// loop finds them: A; B where the circles about A (coupler) and O4 (rocker) meet, one
/// square root; B - A, B - O4; |O4 - A|^2 and B's height over A -> O4 in its units. The
/// same branch as `four_bar_closed` (checked in `floor`).
struct Pins {
    a: [f64; 2],
    b: [f64; 2],
    rab: [f64; 2],
    rcb: [f64; 2],
    dd: f64,
    height: f64,
}

#[inline(always)]
fn four_bar_pins(fb: &FourBar, s2: f64, c2: f64) -> Pins {
    let a = [fb.r2 * c2, fb.r2 * s2];
    let d = [fb.r1 - a[0], -a[1]];
    let dd = d[0] * d[0] + d[1] * d[1];
    let along = 0.5 * (dd + fb.r3 * fb.r3 - fb.r4 * fb.r4) / dd;
    let height = (fb.r3 * fb.r3 / dd - along * along).sqrt();
    let b = [a[0] + along * d[0] - height * d[1], a[1] + along * d[1] + height * d[0]];
    Pins { a, b, rab: [b[0] - a[0], b[1] - a[1]], rcb: [b[0] - fb.r1, b[1]], dd, height }
}

/// The coupler's and the rocker's rates and accelerations, the crank turning steadily at
/// `w2`: Cramer's rule on B's velocity (acceleration) seen from both links.
#[inline(always)]
fn four_bar_rates(p: &Pins, w2: f64) -> ([f64; 2], [f64; 2]) {
    let (a, rab, rcb) = (p.a, p.rab, p.rcb);
    // w3 perp(rab) - w4 perp(rcb) = -vA, vA = w2 perp(A)
    let inv_det = 1.0 / (rab[0] * rcb[1] - rab[1] * rcb[0]);
    let solve =
        |r: [f64; 2]| ((r[1] * rcb[1] + r[0] * rcb[0]) * inv_det, (r[1] * rab[1] + r[0] * rab[0]) * inv_det);
    let (w3, w4) = solve([w2 * a[1], -w2 * a[0]]);
    // a3 perp(rab) - a4 perp(rcb) = -aA + w3^2 rab - w4^2 rcb, aA = -w2^2 A
    let rhs = [
        w2 * w2 * a[0] + w3 * w3 * rab[0] - w4 * w4 * rcb[0],
        w2 * w2 * a[1] + w3 * w3 * rab[1] - w4 * w4 * rcb[1],
    ];
    let (a3, a4) = solve(rhs);
    ([w3, w4], [a3, a4])
}

/// The four-bar's loop at crank angle theta2 as a hand-written loop would do it: the pins,
/// the two angles by atan2, and with `derivatives` 2 the rates and accelerations.
#[inline(always)]
fn four_bar_floor(
    fb: &FourBar,
    s2: f64,
    c2: f64,
    w2: f64,
    derivatives: u8,
) -> ([f64; 2], [f64; 2], [f64; 2]) {
    let p = four_bar_pins(fb, s2, c2);
    let angles = [p.rab[1].atan2(p.rab[0]), p.rcb[1].atan2(p.rcb[0])];
    if derivatives == 0 {
        return (angles, [0.0; 2], [0.0; 2]);
    }
    let (omega, alpha) = four_bar_rates(&p, w2);
    (angles, omega, alpha)
}

/// A loop's two unknown angles (or an angle and a slide), their rates and accelerations,
/// with what the engine checks: the closeness to singular and the largest pin residual of
/// the bodies placed from their pins.
struct Guarded {
    theta: [f64; 2],
    omega: [f64; 2],
    alpha: [f64; 2],
    closeness: f64,
    residual: f64,
}

/// `four_bar_floor` (p+v+a) with the closeness (|sin| of the angle at B) and the coupler's
/// and the rocker's far pins placed back from their poses. The angles by atan2, or with
/// `bases` (the last angles and the bases of their series) continued as the engine
/// continues them (`angle_of`).
#[inline(always)]
fn four_bar_guarded(fb: &FourBar, s2: f64, c2: f64, w2: f64, bases: Option<&mut Bases>) -> Guarded {
    let p = four_bar_pins(fb, s2, c2);
    let (a, b, rab, rcb) = (p.a, p.b, p.rab, p.rcb);
    let theta = match bases {
        None => [rab[1].atan2(rab[0]), rcb[1].atan2(rcb[0])],
        Some(Bases { theta, base, .. }) => {
            *theta = [
                angle_of(rab[0], rab[1], theta[0], &mut base[0]),
                angle_of(rcb[0], rcb[1], theta[1], &mut base[1]),
            ];
            *theta
        }
    };
    let (u3, u4) = ([rab[0] / fb.r3, rab[1] / fb.r3], [rcb[0] / fb.r4, rcb[1] / fb.r4]);
    let back3 = [a[0] + fb.r3 * u3[0], a[1] + fb.r3 * u3[1]];
    let back4 = [fb.r1 + fb.r4 * u4[0], fb.r4 * u4[1]];
    let residual = (back3[0] - b[0])
        .abs()
        .max((back3[1] - b[1]).abs())
        .max((back4[0] - b[0]).abs())
        .max((back4[1] - b[1]).abs());
    let closeness = p.height.abs() * p.dd / (fb.r3 * fb.r4);
    let (omega, alpha) = four_bar_rates(&p, w2);
    Guarded { theta, omega, alpha, closeness, residual }
}

/// What a loop that continues its angles as the engine does keeps from step to step: the
/// coupler's and the rocker's last angles, and the crank's and their series' bases
/// (angle, cos, sin of the last angle computed in full; `turned`, `angle_of`).
struct Bases {
    theta: [f64; 2],
    base: [[f64; 3]; 2],
    crank: [f64; 3],
}

impl Bases {
    /// Nothing computed yet: the first step computes every angle in full.
    fn new() -> Bases {
        Bases { theta: [0.0; 2], base: [[f64::NAN; 3]; 2], crank: [f64::NAN; 3] }
    }
}

/// The slider-crank as a hand-written loop with what the engine checks: B where the rod's
/// circle about A meets the slide's line y = e, the rod's direction (c3, s3) from its
/// pins and its angle by asin; the rates and accelerations of `slider_crank_closed`;
/// the closeness (cos of the rod's angle to the line) and the rod's pin residual.
/// Returns A and (rod angle, slider x), their rates, accelerations.
#[inline(always)]
fn slider_crank_guarded(sc: &SliderCrank, s2: f64, c2: f64, w2: f64) -> ([f64; 2], Guarded) {
    let a = [sc.r2 * c2, sc.r2 * s2];
    let off = sc.e - a[1];
    let along = (sc.r3 * sc.r3 - off * off).sqrt();
    let (c3, s3) = (along / sc.r3, off / sc.r3);
    let bx = a[0] + along;
    let back = [a[0] + sc.r3 * c3, a[1] + sc.r3 * s3];
    let residual = (back[0] - bx).abs().max((back[1] - sc.e).abs());
    let w3 = -sc.r2 * w2 * c2 / (sc.r3 * c3);
    let vx = -sc.r2 * w2 * s2 - sc.r3 * w3 * s3;
    let a3 = (sc.r2 * w2 * w2 * s2 + sc.r3 * w3 * w3 * s3) / (sc.r3 * c3);
    let ax = -sc.r2 * w2 * w2 * c2 - sc.r3 * a3 * s3 - sc.r3 * w3 * w3 * c3;
    let g = Guarded { theta: [s3.asin(), bx], omega: [w3, vx], alpha: [a3, ax], closeness: c3, residual };
    (a, g)
}

/// What the engine checks and keeps at every step of a closed-form sweep, for a
/// hand-written loop of 3 bodies: the closeness to singular against the near-singular
/// threshold and its trend reaching zero within the step; the two-way check of every
/// coordinate (q - h (qd - h qdd / 2) back at the last step's q, scaled by the model's
/// length for x and y); q, qd, qdd and the residual and closeness stored per row.
struct Guard {
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    residual: Vec<f64>,
    closeness: Vec<f64>,
    scale: [f64; 9],
    inv_l: f64,
    prev: [f64; 9],
    close: [f64; 2],
}

impl Guard {
    fn new(steps: usize, length: f64) -> Guard {
        let inv_l = 1.0 / length;
        Guard {
            q: vec![0.0; 9 * steps],
            qd: vec![0.0; 9 * steps],
            qdd: vec![0.0; 9 * steps],
            residual: vec![0.0; steps],
            closeness: vec![0.0; steps],
            scale: [inv_l, inv_l, 1.0, inv_l, inv_l, 1.0, inv_l, inv_l, 1.0],
            inv_l,
            prev: [0.0; 9],
            close: [0.0; 2],
        }
    }

    fn start(&mut self) {
        (self.prev, self.close) = ([0.0; 9], [0.0; 2]);
    }

    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn step(
        &mut self,
        k: usize,
        times: &[f64],
        q: [f64; 9],
        qd: [f64; 9],
        qdd: [f64; 9],
        closeness: f64,
        residual: f64,
        rates: bool,
    ) {
        if k == 0 {
            self.close = [closeness, 0.0]; // the start's, as the engine reads it there
        } else {
            let h = times[k] - times[k - 1];
            let [c1, rate] = self.close;
            // the engine hands such a step to its careful path: these loops never come near
            assert!(
                closeness >= 1e-3 && c1 + rate * h >= 0.25 * c1 && closeness >= 0.25 * c1,
                "near singular at step {k}"
            );
            self.close = [closeness, (closeness - c1) / h];
            let (mut motion, mut misfit) = (0.0f64, 0.0f64);
            for i in 0..9 {
                let back = q[i] - h * (qd[i] - 0.5 * h * qdd[i]);
                motion = motion.max((q[i] - self.prev[i]).abs() * self.scale[i]);
                misfit = misfit.max((self.prev[i] - back).abs() * self.scale[i]);
            }
            assert!(misfit <= 0.1 * motion + 1e-9, "the two-way check at step {k}");
        }
        self.prev = q;
        let row = 9 * k;
        self.q[row..row + 9].copy_from_slice(&q);
        if rates {
            self.qd[row..row + 9].copy_from_slice(&qd);
            self.qdd[row..row + 9].copy_from_slice(&qdd);
        }
        self.residual[k] = residual * self.inv_l;
        self.closeness[k] = closeness;
    }

    fn last(&self) -> (f64, f64, f64, f64, f64) {
        let n = self.q.len() - 1;
        (self.q[n], self.qd[n], self.qdd[n], self.residual[n / 9], self.closeness[0])
    }
}

/// The closed-form floor: per step, the crank angle from its law, the loop's angles, rates
/// and accelerations (tests/common's closed forms), the body frames' poses and their
/// derivatives, stored row-major into preallocated q, qd, qdd (n_steps x 9).
fn floor(c: &mut Criterion) {
    let times = times(FLOOR_STEPS);
    // the floor's four-bar is the closed form's, on its branch, over a revolution
    for i in 0..720 {
        let th2 = i as f64 * PI / 360.0;
        let (s2, c2) = th2.sin_cos();
        let (p, v, a) = four_bar_floor(&textbook(), s2, c2, OMEGA, 2);
        let (pe, ve, ae) = four_bar_closed(&textbook(), th2, OMEGA, 0.0);
        for j in 0..2 {
            let turn = (p[j] - pe[j]) / (2.0 * PI);
            assert!((turn - turn.round()).abs() * 2.0 * PI < 1e-12, "floor theta at {th2}");
            assert!((v[j] - ve[j]).abs() < 1e-11 && (a[j] - ae[j]).abs() < 1e-9, "floor rates at {th2}");
        }
    }
    for i in 0..720 {
        let th2 = i as f64 * PI / 360.0;
        let (s2, c2) = th2.sin_cos();
        let (_, g) = slider_crank_guarded(&SLIDER_CRANK, s2, c2, OMEGA);
        let (pe, ve, ae) = slider_crank_closed(&SLIDER_CRANK, th2, OMEGA, 0.0);
        for j in 0..2 {
            assert!((g.theta[j] - pe[j]).abs() < 1e-12 && (g.omega[j] - ve[j]).abs() < 1e-11, "at {th2}");
            assert!((g.alpha[j] - ae[j]).abs() < 1e-9, "slider-crank accelerations at {th2}");
        }
    }
    // the continued angles are atan2's to round-off: the loop against the closed form
    let mut guard = Guard::new(FLOOR_STEPS, textbook().r1);
    continued_four_bar(&times, &mut guard, true);
    for (k, &t) in times.iter().enumerate() {
        let (pe, ve, ae) = four_bar_closed(&textbook(), OMEGA * t, OMEGA, 0.0);
        let row = 9 * k;
        for (j, i) in [5, 8].into_iter().enumerate() {
            let turn = (guard.q[row + i] - pe[j]) / (2.0 * PI);
            assert!((turn - turn.round()).abs() * 2.0 * PI < 1e-12, "continued theta at step {k}");
            assert!((guard.qd[row + i] - ve[j]).abs() < 1e-11, "continued omega at step {k}");
            assert!((guard.qdd[row + i] - ae[j]).abs() < 1e-9, "continued alpha at step {k}");
        }
    }
    // and the general loop's (its origins at pins: the same q as the continued loop's)
    let mut general = Guard::new(FLOOR_STEPS, textbook().r1);
    general_four_bar(&times, &mut general, &General::textbook());
    for (i, (x, e)) in general.q.iter().zip(&guard.q).enumerate() {
        assert!((x - e).abs() < 1e-12, "general q[{i}]: {x} against {e}");
    }
    for (i, (x, e)) in general.qd.iter().zip(&guard.qd).enumerate() {
        assert!((x - e).abs() < 1e-11, "general qd[{i}]: {x} against {e}");
    }
    for (i, (x, e)) in general.qdd.iter().zip(&guard.qdd).enumerate() {
        assert!((x - e).abs() < 1e-9, "general qdd[{i}]: {x} against {e}");
    }
    let mut g = c.benchmark_group("floor");
    g.throughput(Throughput::Elements(FLOOR_STEPS as u64));
    let rows = || (vec![0.0; 9 * FLOOR_STEPS], vec![0.0; 9 * FLOOR_STEPS], vec![0.0; 9 * FLOOR_STEPS]);
    for derivatives in [2u8, 0] {
        let id = if derivatives == 2 { "pva" } else { "p" };
        g.bench_function(BenchmarkId::new("four_bar", id), |b| {
            let (mut q, mut qd, mut qdd) = rows();
            b.iter(|| {
                floor_four_bar(black_box(&times), derivatives, &mut q, &mut qd, &mut qdd);
                black_box((q[9 * FLOOR_STEPS - 1], qd[9 * FLOOR_STEPS - 1], qdd[9 * FLOOR_STEPS - 1]))
            })
        });
        g.bench_function(BenchmarkId::new("slider_crank", id), |b| {
            let (mut q, mut qd, mut qdd) = rows();
            b.iter(|| {
                floor_slider_crank(black_box(&times), derivatives, &mut q, &mut qd, &mut qdd);
                black_box((q[9 * FLOOR_STEPS - 1], qd[9 * FLOOR_STEPS - 1], qdd[9 * FLOOR_STEPS - 1]))
            })
        });
    }
    // the same loops with the checks the engine makes at every step, by hand (`Guard`)
    g.bench_function(BenchmarkId::new("four_bar", "pva_guarded"), |b| {
        let mut guard = Guard::new(FLOOR_STEPS, textbook().r1);
        b.iter(|| {
            guarded_four_bar(black_box(&times), &mut guard);
            guard.last()
        })
    });
    // and with the angles continued as the engine continues them, p+v+a and p kept
    for (rates, id) in [(true, "pva_continued"), (false, "p_continued")] {
        g.bench_function(BenchmarkId::new("four_bar", id), |b| {
            let mut guard = Guard::new(FLOOR_STEPS, textbook().r1);
            b.iter(|| {
                continued_four_bar(black_box(&times), &mut guard, rates);
                guard.last()
            })
        });
    }
    // and the engine's general arithmetic for its two groups, in one function
    g.bench_function(BenchmarkId::new("four_bar", "pva_general"), |b| {
        let mut guard = Guard::new(FLOOR_STEPS, textbook().r1);
        let geometry = black_box(General::textbook());
        b.iter(|| {
            general_four_bar(black_box(&times), &mut guard, &geometry);
            guard.last()
        })
    });
    g.bench_function(BenchmarkId::new("slider_crank", "pva_guarded"), |b| {
        let mut guard = Guard::new(FLOOR_STEPS, SLIDER_CRANK.r2 + SLIDER_CRANK.r3);
        b.iter(|| {
            guarded_slider_crank(black_box(&times), &mut guard);
            guard.last()
        })
    });
    g.finish();
}

/// Steps of a floor benchmark, and the crank's steady rate.
const FLOOR_STEPS: usize = 10_000;
const OMEGA: f64 = 5.0;
/// The floor's slider-crank (the engine's bench sweeps the same).
const SLIDER_CRANK: SliderCrank = SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 };

// The floor's loops, each a function of its own (never inlined) so that an instruction
// count of the benchmark can divide by its calls (`benches/profile.py`).

/// The four-bar's floor over `times`: q (and with `derivatives` 2, qd, qdd) row-major.
#[inline(never)]
fn floor_four_bar(times: &[f64], derivatives: u8, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
    let fb = textbook();
    for (k, &t) in times.iter().enumerate() {
        let th2 = OMEGA * t;
        let (s2, c2) = th2.sin_cos();
        let ([th3, th4], [w3, w4], [a3, a4]) = four_bar_floor(&fb, s2, c2, OMEGA, derivatives);
        let row = 9 * k;
        q[row..row + 9].copy_from_slice(&[0.0, 0.0, th2, fb.r2 * c2, fb.r2 * s2, th3, fb.r1, 0.0, th4]);
        if derivatives == 2 {
            let (v, a) = (fb.r2 * OMEGA, -fb.r2 * OMEGA * OMEGA);
            qd[row..row + 9].copy_from_slice(&[0.0, 0.0, OMEGA, -v * s2, v * c2, w3, 0.0, 0.0, w4]);
            qdd[row..row + 9].copy_from_slice(&[0.0, 0.0, 0.0, a * c2, a * s2, a3, 0.0, 0.0, a4]);
        }
    }
}

/// The slider-crank's floor over `times` (`slider_crank_closed`: its rod by asin).
#[inline(never)]
fn floor_slider_crank(times: &[f64], derivatives: u8, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
    let sc = SLIDER_CRANK;
    for (k, &t) in times.iter().enumerate() {
        let th2 = OMEGA * t;
        let ([th3, x], [w3, v], [a3, acc]) = slider_crank_closed(&sc, th2, OMEGA, 0.0);
        let (s2, c2) = th2.sin_cos();
        let row = 9 * k;
        q[row..row + 9].copy_from_slice(&[0.0, 0.0, th2, sc.r2 * c2, sc.r2 * s2, th3, x, sc.e, 0.0]);
        if derivatives == 2 {
            let (u, a) = (sc.r2 * OMEGA, -sc.r2 * OMEGA * OMEGA);
            qd[row..row + 9].copy_from_slice(&[0.0, 0.0, OMEGA, -u * s2, u * c2, w3, v, 0.0, 0.0]);
            qdd[row..row + 9].copy_from_slice(&[0.0, 0.0, 0.0, a * c2, a * s2, a3, acc, 0.0, 0.0]);
        }
    }
}

/// The four-bar's floor with the engine's per-step checks (`Guard`), p+v+a.
#[inline(never)]
fn guarded_four_bar(times: &[f64], guard: &mut Guard) {
    let fb = textbook();
    guard.start();
    for (k, &t) in times.iter().enumerate() {
        let th2 = OMEGA * t;
        let (s2, c2) = th2.sin_cos();
        let g = four_bar_guarded(&fb, s2, c2, OMEGA, None);
        four_bar_rows(&fb, k, times, th2, s2, c2, &g, guard, true);
    }
}

/// `guarded_four_bar` with the angles continued as the engine continues them (the crank's
/// cos and sin by `turned`, the coupler's and the rocker's angles by `angle_of`): the least
/// a loop pays for the engine's promise with its arithmetic. `rates`: velocities and
/// accelerations kept (else solved for the check and not kept, as a positions-only sweep).
#[inline(never)]
fn continued_four_bar(times: &[f64], guard: &mut Guard, rates: bool) {
    let fb = textbook();
    guard.start();
    let mut bases = Bases::new();
    for (k, &t) in times.iter().enumerate() {
        let th2 = OMEGA * t;
        let (c2, s2) = turned(th2, &mut bases.crank);
        let g = four_bar_guarded(&fb, s2, c2, OMEGA, Some(&mut bases));
        four_bar_rows(&fb, k, times, th2, s2, c2, &g, guard, rates);
    }
}

/// One link of the general loop's dyad, as the engine holds it (`blocks::rrr::Link`): the
/// outer pin on the known side and on the body, the middle pin on the body, the length.
struct GeneralLink {
    u_known: [f64; 2],
    u_outer: [f64; 2],
    u_middle: [f64; 2],
    length: f64,
    inv_length: f64,
    dir: [f64; 2],
}

impl GeneralLink {
    fn new(u_known: [f64; 2], u_outer: [f64; 2], u_middle: [f64; 2]) -> GeneralLink {
        let d = [u_middle[0] - u_outer[0], u_middle[1] - u_outer[1]];
        let length = d[0].hypot(d[1]);
        GeneralLink {
            u_known,
            u_outer,
            u_middle,
            length,
            inv_length: 1.0 / length,
            dir: [d[0] / length, d[1] / length],
        }
    }

    /// The body's frame with its outer pin at `a` and middle pin at `b` (the engine's
    /// `Link::place`), its angle continued; and the middle pin's residual.
    #[inline(always)]
    fn place(&self, a: [f64; 2], b: [f64; 2], theta: &mut f64, base: &mut [f64; 3]) -> (Frame, f64) {
        let w = [(b[0] - a[0]) * self.inv_length, (b[1] - a[1]) * self.inv_length];
        let c = self.dir[0] * w[0] + self.dir[1] * w[1];
        let s = self.dir[0] * w[1] - self.dir[1] * w[0];
        *theta = angle_of(c, s, *theta, base);
        let arm = [c * self.u_outer[0] - s * self.u_outer[1], s * self.u_outer[0] + c * self.u_outer[1]];
        let f = Frame { r: [a[0] - arm[0], a[1] - arm[1]], theta: *theta, c, s, rd: [0.0; 2], thetad: 0.0 };
        let m = f.point(self.u_middle);
        (f, (m[0] - b[0]).abs().max((m[1] - b[1]).abs()))
    }
}

/// The four-bar as the engine's groups hold it, for `general_four_bar`: the crank's pin on
/// it and the ground pivots, each dyad link's pins in its body's frame (the built-in
/// example's: every origin at a pin, x along the bar).
struct General {
    o2: [f64; 2],
    o4: [f64; 2],
    u_crank: [f64; 2],
    l1: GeneralLink,
    l2: GeneralLink,
}

impl General {
    fn textbook() -> General {
        let fb = textbook();
        General {
            o2: [0.0, 0.0],
            o4: [fb.r1, 0.0],
            u_crank: [0.0, 0.0],
            l1: GeneralLink::new([fb.r2, 0.0], [0.0, 0.0], [fb.r3, 0.0]),
            l2: GeneralLink::new([0.0, 0.0], [0.0, 0.0], [fb.r4, 0.0]),
        }
    }
}

/// A point's acceleration on a body turning at `w` with angular acceleration `alpha`,
/// `r` from the origin, whose origin accelerates at `rdd` (the engine's `point_acc`).
#[inline(always)]
fn point_acceleration(rdd: [f64; 2], w: f64, alpha: f64, r: [f64; 2]) -> [f64; 2] {
    [rdd[0] - alpha * r[1] - w * w * r[0], rdd[1] + alpha * r[0] - w * w * r[1]]
}

/// The engine's arithmetic for the four-bar's two groups (`Crank::solve_on`,
/// `Rrr::solve_on`, both known sides of the dyad as the four-bar has them), body by body
/// with every origin wherever its body's pins put it, and the engine's checks (`Guard`),
/// in one function whose values stay local: no frames kept for later groups, no dispatch
/// among group kinds, no predictor's history, no row of diagnostics. The difference to
/// `continued_four_bar` is the general geometry; the difference to the engine, what the
/// engine does around its arithmetic.
#[inline(never)]
fn general_four_bar(times: &[f64], guard: &mut Guard, g: &General) {
    guard.start();
    let (mut crank_base, mut bases, mut theta) = ([f64::NAN; 3], [[f64::NAN; 3]; 2], [0.0f64; 2]);
    for (k, &t) in times.iter().enumerate() {
        // the crank: its angle from the driver's law, its origin from its ground pin
        let th2 = OMEGA * t;
        let (c, s) = turned(th2, &mut crank_base);
        let arm = [c * g.u_crank[0] - s * g.u_crank[1], s * g.u_crank[0] + c * g.u_crank[1]];
        let mut f2 =
            Frame { r: [g.o2[0] - arm[0], g.o2[1] - arm[1]], theta: th2, c, s, rd: [0.0; 2], thetad: 0.0 };
        let back = f2.point(g.u_crank);
        let mut residual = (back[0] - g.o2[0]).abs().max((back[1] - g.o2[1]).abs());
        (f2.rd, f2.thetad) = ([arm[1] * OMEGA, -arm[0] * OMEGA], OMEGA);
        let own = point_acceleration([0.0; 2], OMEGA, 0.0, arm);
        let rdd2 = [-own[0], -own[1]];
        // the dyad: A on the crank, C on the ground
        let a = f2.point(g.l1.u_known);
        let c4 = g.o4;
        let (r1, r2) = (g.l1.length, g.l2.length);
        let d = [c4[0] - a[0], c4[1] - a[1]];
        let dd = d[0] * d[0] + d[1] * d[1];
        let inv_dd = 1.0 / dd;
        let along = 0.5 * (dd + r1 * r1 - r2 * r2) * inv_dd;
        let height = (r1 * r1 * inv_dd - along * along).sqrt();
        let b = [a[0] + along * d[0] - height * d[1], a[1] + along * d[1] + height * d[0]];
        let (f3, res3) = g.l1.place(a, b, &mut theta[0], &mut bases[0]);
        let (f4, res4) = g.l2.place(c4, b, &mut theta[1], &mut bases[1]);
        residual = residual.max(res3).max(res4);
        let closeness = height.abs() * dd * g.l1.inv_length * g.l2.inv_length;
        let (rab, rcb) = ([b[0] - a[0], b[1] - a[1]], [b[0] - c4[0], b[1] - c4[1]]);
        let (pab, pcb) = ([-rab[1], rab[0]], [-rcb[1], rcb[0]]);
        let inv_det = 1.0 / (pcb[0] * pab[1] - pcb[1] * pab[0]);
        let va = f2.point_velocity(g.l1.u_known);
        let rhs = [-va[0], -va[1]];
        let w3 = (pcb[0] * rhs[1] - pcb[1] * rhs[0]) * inv_det;
        let w4 = (pab[0] * rhs[1] - pab[1] * rhs[0]) * inv_det;
        let (o3, o4) = ([f3.r[0] - a[0], f3.r[1] - a[1]], [f4.r[0] - c4[0], f4.r[1] - c4[1]]);
        let rd3 = [va[0] - w3 * o3[1], va[1] + w3 * o3[0]];
        let rd4 = [-w4 * o4[1], w4 * o4[0]];
        let aa = point_acceleration(rdd2, OMEGA, 0.0, [a[0] - f2.r[0], a[1] - f2.r[1]]);
        let rhs =
            [-aa[0] - w4 * w4 * rcb[0] + w3 * w3 * rab[0], -aa[1] - w4 * w4 * rcb[1] + w3 * w3 * rab[1]];
        let a3 = (pcb[0] * rhs[1] - pcb[1] * rhs[0]) * inv_det;
        let a4 = (pab[0] * rhs[1] - pab[1] * rhs[0]) * inv_det;
        let rdd3 = point_acceleration(aa, w3, a3, o3);
        let rdd4 = point_acceleration([0.0; 2], w4, a4, o4);
        let q = [f2.r[0], f2.r[1], th2, f3.r[0], f3.r[1], theta[0], f4.r[0], f4.r[1], theta[1]];
        let qd = [f2.rd[0], f2.rd[1], OMEGA, rd3[0], rd3[1], w3, rd4[0], rd4[1], w4];
        let qdd = [rdd2[0], rdd2[1], 0.0, rdd3[0], rdd3[1], a3, rdd4[0], rdd4[1], a4];
        guard.step(k, times, q, qd, qdd, closeness, residual, true);
    }
}

/// The four-bar's q, qd, qdd at step k (the crank at th2 turning steadily) through `guard`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn four_bar_rows(
    fb: &FourBar,
    k: usize,
    times: &[f64],
    th2: f64,
    s2: f64,
    c2: f64,
    g: &Guarded,
    guard: &mut Guard,
    rates: bool,
) {
    let (u, v) = (fb.r2 * OMEGA, -fb.r2 * OMEGA * OMEGA);
    let q = [0.0, 0.0, th2, fb.r2 * c2, fb.r2 * s2, g.theta[0], fb.r1, 0.0, g.theta[1]];
    let qd = [0.0, 0.0, OMEGA, -u * s2, u * c2, g.omega[0], 0.0, 0.0, g.omega[1]];
    let qdd = [0.0, 0.0, 0.0, v * c2, v * s2, g.alpha[0], 0.0, 0.0, g.alpha[1]];
    guard.step(k, times, q, qd, qdd, g.closeness, g.residual, rates);
}

/// The slider-crank's floor with the engine's per-step checks (`Guard`), p+v+a.
#[inline(never)]
fn guarded_slider_crank(times: &[f64], guard: &mut Guard) {
    let sc = SLIDER_CRANK;
    guard.start();
    for (k, &t) in times.iter().enumerate() {
        let th2 = OMEGA * t;
        let (s2, c2) = th2.sin_cos();
        let (a, g) = slider_crank_guarded(&sc, s2, c2, OMEGA);
        let (u, v) = (sc.r2 * OMEGA, -sc.r2 * OMEGA * OMEGA);
        let q = [0.0, 0.0, th2, a[0], a[1], g.theta[0], g.theta[1], sc.e, 0.0];
        let qd = [0.0, 0.0, OMEGA, -u * s2, u * c2, g.omega[0], g.omega[1], 0.0, 0.0];
        let qdd = [0.0, 0.0, 0.0, v * c2, v * s2, g.alpha[0], g.alpha[1], 0.0, 0.0];
        guard.step(k, times, q, qd, qdd, g.closeness, g.residual, true);
    }
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

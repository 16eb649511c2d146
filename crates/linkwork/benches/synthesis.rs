//! Synthesis benchmarks (criterion): one exact problem, all roots, certified.
//!
//! - `burmester`: five-pose Burmester dyads by parameter homotopy (5 paths) and by the
//!   elimination (resultant.rs), on the generator of tests/engine/synthesis.rs; either way every
//!   root is polished and alpha-certified.
//! - `timed`: the five-point timed path dyad, both ways.
//!
//! Run: cargo bench -p linkwork --bench synthesis

use criterion::{criterion_group, criterion_main, Criterion};
use linkwork::synthesis::motion::{burmester, burmester_by_resultant, Pose};
use linkwork::synthesis::path::{timed_dyads, timed_dyads_by_resultant};
use num_complex::Complex64 as C64;
use std::hint::black_box;

fn generator(phi: f64) -> (f64, C64) {
    let (a0, b0, ra, l, rb, p) = (C64::new(0.0, 0.0), C64::new(4.0, 0.5), 1.5, 4.0, 3.0, C64::new(1.7, 1.1));
    let a = a0 + C64::from_polar(ra, phi);
    let d = b0 - a;
    let dist = d.norm();
    let along = (l * l - rb * rb + dist * dist) / (2.0 * dist);
    let b = a + d / dist * C64::new(along, (l * l - along * along).sqrt());
    let angle = (b - a).arg();
    (angle, a + p * C64::from_polar(1.0, angle))
}

const PHIS: [f64; 5] = [0.3, 0.7, 1.2, 1.8, 2.3];

fn bench(c: &mut Criterion) {
    let poses: Vec<Pose> = PHIS
        .iter()
        .map(|&phi| {
            let (angle, p) = generator(phi);
            Pose { x: p.re, y: p.im, angle }
        })
        .collect();
    let points: Vec<[f64; 2]> = poses.iter().map(|p| [p.x, p.y]).collect();
    let input: Vec<f64> = PHIS.iter().map(|p| p - PHIS[0]).collect();
    // the start set is computed once per process, outside the timing
    let _ = burmester(&poses).unwrap();
    let mut g = c.benchmark_group("synthesis");
    g.bench_function("burmester/homotopy", |b| b.iter(|| black_box(burmester(black_box(&poses)).unwrap())));
    g.bench_function("burmester/resultant", |b| {
        b.iter(|| black_box(burmester_by_resultant(black_box(&poses)).unwrap()))
    });
    g.bench_function("timed/homotopy", |b| {
        b.iter(|| black_box(timed_dyads(black_box(&points), &input).unwrap()))
    });
    g.bench_function("timed/resultant", |b| {
        b.iter(|| black_box(timed_dyads_by_resultant(black_box(&points), &input).unwrap()))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

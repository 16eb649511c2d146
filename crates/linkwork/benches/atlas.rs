//! The coupler-curve atlas workload, side by side in one process: N Grashof crank-rockers,
//! 360 steps of one crank turn each, the coupler point's path. linkwork's variants
//! (`sweep_variants`: the designs as one compiled four-bar with its numbers moved,
//! positions and the point asked) against four-bar-rs's closed form, one step at a time,
//! as a plain scalar loop (`fourbar_rs_step`, from KmolYuan/four-bar-rs v7.0.5,
//! four-bar/src/mech/fb.rs, `curve_interval`). Every path is checked against the closed
//! form to 1e-13.
//!
//! `cargo bench -p linkwork --bench atlas -- [designs] [rounds] [steps]` (defaults 10000, 3,
//! 360).
//! Prints M design-steps/s for each, on one thread and on two, alternating in rounds.

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Instant;

use common::{four_bar, FourBar};
use linkwork::sensitivity::Parameter;
use linkwork::{sweep_batch_kept, sweep_variants, Model, Outputs, PointDesc, Request, Variation};

const OMEGA: f64 = 5.0;
/// Steps of one turn (the atlas's 360; a third argument sets another).
/// The base drawing: a crank-rocker drawn at crank angle 0.
const BASE: FourBar = FourBar { r1: 0.38, r2: 0.2, r3: 0.35, r4: 0.25 };
/// The coupler point of the base, in the world at the drawing.
const BASE_P: [f64; 2] = [0.3, 0.12];

/// One design: link lengths and the coupler point (its distance from A and its angle from
/// A -> B), as four-bar-rs names them.
#[derive(Clone, Copy, Debug)]
struct Design {
    l1: f64,
    l2: f64,
    l3: f64,
    l4: f64,
    l5: f64,
    g: f64,
}

/// Deterministic designs: Grashof crank-rockers (the crank the shortest link, s + l below
/// p + q by 2 % of l), lengths drawn around the base's.
fn designs(n: usize) -> Vec<Design> {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut uniform = |lo: f64, hi: f64| {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((state >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let (l1, l2, l3, l4) =
            (uniform(0.3, 0.5), uniform(0.08, 0.2), uniform(0.25, 0.5), uniform(0.2, 0.45));
        let s = l2;
        let l = l1.max(l3).max(l4);
        if s >= l1.min(l3).min(l4) || s + l > l1 + l3 + l4 - l - 0.02 * l {
            continue;
        }
        out.push(Design { l1, l2, l3, l4, l5: uniform(0.05, 0.3), g: uniform(-1.5, 1.5) });
    }
    out
}

/// B at crank angle 0 on the open circuit (above the ground line), for the drawing.
fn b_at_zero(d: &Design) -> [f64; 2] {
    let (a, c) = ([d.l2, 0.0], [d.l1, 0.0]);
    let dx = c[0] - a[0];
    let along = (dx * dx + d.l3 * d.l3 - d.l4 * d.l4) / (2.0 * dx);
    [a[0] + along, (d.l3 * d.l3 - along * along).sqrt()]
}

/// The design's drawing at crank angle 0: A, B, O4 and P in the world.
fn drawing(d: &Design) -> [[f64; 2]; 4] {
    let a = [d.l2, 0.0];
    let b = b_at_zero(d);
    let phi = (b[1] - a[1]).atan2(b[0] - a[0]) + d.g;
    let p = [a[0] + d.l5 * phi.cos(), a[1] + d.l5 * phi.sin()];
    [a, b, [d.l1, 0.0], p]
}

/// four-bar-rs's closed form of one step (`curve_interval` in four-bar/src/mech/fb.rs of
/// KmolYuan/four-bar-rs v7.0.5), for p1 at the origin and ground angle a = 0, written over
/// plain arrays instead of nalgebra's points (the same operations): the coupler point p5 at
/// crank angle `b`, on the circuit `inv`; None where the linkage does not close.
#[inline(always)]
fn fourbar_rs_step(d: &Design, b: f64, inv: bool) -> Option<[f64; 2]> {
    let (p1x, p1y, a) = (0.0f64, 0.0f64, 0.0f64);
    let angle = |p: [f64; 2], l: f64, a: f64| [p[0] + l * a.cos(), p[1] + l * a.sin()];
    let p1 = [p1x, p1y];
    let p2 = angle(p1, d.l1, a);
    let p3 = angle(p1, d.l2, a + b);
    let p4 = if (d.l1 - d.l3).abs() < f64::EPSILON && (d.l2 - d.l4).abs() < f64::EPSILON {
        [p2[0] + (p3[0] - p1[0]), p2[1] + (p3[1] - p1[1])]
    } else {
        let p23 = [p2[0] - p3[0], p2[1] - p3[1]];
        let r_2 = p23[0] * p23[0] + p23[1] * p23[1];
        let r = r_2.sqrt();
        if r > d.l3 + d.l4 || r < (d.l3 - d.l4).abs() || r < f64::EPSILON {
            [f64::NAN; 2]
        } else {
            let l3_2 = d.l3 * d.l3;
            let c = (l3_2 - d.l4 * d.l4 + r_2) / (2. * r);
            let s = (l3_2 - c * c).sqrt();
            let s = if inv { -s } else { s };
            let u = [p23[0] / r, p23[1] / r];
            [p3[0] + (c * u[0] - s * u[1]), p3[1] + (s * u[0] + c * u[1])]
        }
    };
    let p43 = [p4[0] - p3[0], p4[1] - p3[1]];
    let p5 = angle(p3, d.l5, d.g + p43[1].atan2(p43[0]));
    let js = [p1, p2, p3, p4, p5];
    js.iter().flatten().all(|x| x.is_finite()).then_some(p5)
}

/// The closed form's path of every design (n x steps x 2), each on the circuit `inv[i]`.
fn fourbar_rs_atlas(designs: &[Design], inv: &[bool], angles: &[f64], out: &mut [f64]) -> usize {
    let mut failed = 0;
    for (i, d) in designs.iter().enumerate() {
        let row = &mut out[i * angles.len() * 2..(i + 1) * angles.len() * 2];
        for (k, &b) in angles.iter().enumerate() {
            match fourbar_rs_step(d, b, inv[i]) {
                Some(p) => row[2 * k..2 * k + 2].copy_from_slice(&p),
                None => failed += 1,
            }
        }
    }
    failed
}

/// The process's CPU time (every thread's), seconds: on a shared machine the work's own
/// time, where the wall clock also counts the other processes' turns.
fn cpu_time() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes the timespec it is given
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + 1e-9 * ts.tv_nsec as f64
}

/// Runs `f`, returning its wall and CPU seconds.
fn timed<T>(f: impl FnOnce() -> T) -> (f64, f64) {
    let (w0, c0) = (Instant::now(), cpu_time());
    std::hint::black_box(f());
    (w0.elapsed().as_secs_f64(), cpu_time() - c0)
}

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let n = args.first().copied().unwrap_or(10_000);
    let rounds = args.get(1).copied().unwrap_or(3);
    let steps = args.get(2).copied().unwrap_or(360);
    let designs = designs(n);
    let turn = std::f64::consts::TAU / OMEGA;
    let times: Vec<f64> = (0..steps).map(|k| turn * k as f64 / steps as f64).collect();
    let angles: Vec<f64> = times.iter().map(|t| OMEGA * t).collect();

    // the base model with its coupler point P; the designs move the pins' and P's places
    let mut desc = four_bar(&BASE, 0.0, OMEGA);
    desc.points.push(PointDesc { name: "P".into(), body: "coupler".into(), at: BASE_P });
    let model = Model::new(desc).expect("the base four-bar compiles");
    let names = [
        "joints.A.at.0",
        "joints.B.at.0",
        "joints.B.at.1",
        "joints.O4.at.0",
        "points.P.at.0",
        "points.P.at.1",
    ];
    let params = names.iter().map(|p| Parameter::resolve(&model, p).expect("a parameter")).collect();
    let variation = Variation::new(&model, params);
    let base = drawing(&Design { l1: BASE.r1, l2: BASE.r2, l3: BASE.r3, l4: BASE.r4, l5: 0.0, g: 0.0 });
    let deltas: Vec<f64> = designs
        .iter()
        .flat_map(|d| {
            let [a, b, o4, p] = drawing(d);
            [
                a[0] - base[0][0],
                b[0] - base[1][0],
                b[1] - base[1][1],
                o4[0] - base[2][0],
                p[0] - BASE_P[0],
                p[1] - BASE_P[1],
            ]
        })
        .collect();
    let coupler = model.description.bodies.iter().position(|b| b.name == "coupler").expect("a coupler");
    let p_index = model.points.iter().position(|p| p.name == "P").expect("the point P");
    let outputs =
        Outputs { coords: Some(vec![]), points: vec![(Some(coupler), model.points[p_index].local)] };
    let request = Request { derivatives: 0, ..Request::default() };
    let run_linkwork = |threads: usize| {
        sweep_variants(
            &model,
            &variation,
            n,
            &deltas,
            &times,
            request,
            &outputs,
            &[Some(p_index)],
            threads,
            &mut |_| true,
        )
    };

    // the circuit of each design in four-bar-rs's terms: the one its first point matches
    let figures = run_linkwork(2);
    let failed: Vec<usize> = (0..n).filter(|&i| figures.errors[i].is_some()).collect();
    let inv: Vec<bool> = (0..n)
        .map(|i| {
            let p = &figures.points[i * steps * 2..i * steps * 2 + 2];
            let q = fourbar_rs_step(&designs[i], angles[0], false).expect("closes at 0");
            (p[0] - q[0]).abs() + (p[1] - q[1]).abs() > 1e-9
        })
        .collect();
    let mut reference = vec![f64::NAN; n * steps * 2];
    let rs_failed = fourbar_rs_atlas(&designs, &inv, &angles, &mut reference);
    let worst = figures.points.iter().zip(&reference).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    println!(
        "{n} designs x {steps} steps: linkwork errors {}, four-bar-rs failed steps {rs_failed}, \
         open circuit (four-bar-rs inv = false) {}; worst |linkwork - closed form| {worst:.2e} (<= 1e-13: {})",
        failed.len(),
        inv.iter().filter(|&&x| !x).count(),
        worst <= 1e-13
    );

    let per = (n * steps) as f64 * 1e-6;
    let mut out = vec![0.0; n * steps * 2];
    // the per-design path, for comparison: every design a model of its own (built
    // beforehand), swept one by one (`sweep_batch_kept`), the same point kept
    let mut built = Vec::new();
    let (build_w, build_c) = timed(|| {
        built = (0..n).map(|i| variation.model(&model, &deltas[i * 6..(i + 1) * 6])).collect::<Vec<Model>>();
    });
    println!("building the {n} designs from their numbers (Variation::model): {build_w:.3} s wall, {build_c:.3} s cpu");
    let refs: Vec<&Model> = built.iter().collect();
    let kept: Vec<Outputs> = built
        .iter()
        .map(|m| Outputs { coords: Some(vec![]), points: vec![(Some(coupler), m.points[p_index].local)] })
        .collect();
    let (alone_w, alone_c) =
        timed(|| sweep_batch_kept(&refs, &times, request, Some(&kept), Some(&model), 1, &mut |_| true));
    println!(
        "linkwork one design at a time (sweep_batch_kept, 1 thread): {:.2} M/s wall, {:.2} cpu",
        per / alone_w,
        per / alone_c
    );
    drop(built);
    println!("M design-steps/s: by wall time, and by CPU time (per core: the work's own time)");
    for round in 0..rounds {
        let (rs_w, rs_c) = timed(|| fourbar_rs_atlas(&designs, &inv, &angles, &mut out));
        let (one_w, one_c) = timed(|| run_linkwork(1));
        let (two_w, two_c) = timed(|| run_linkwork(2));
        println!(
            "round {round}: four-bar-rs loop {:.2} wall, {:.2} cpu | linkwork 1 thread {:.2} wall, {:.2} cpu \
             ({:.2}x, {:.2}x per core) | 2 threads {:.2} wall, {:.2} cpu per core ({:.2}x the 1-thread wall)",
            per / rs_w,
            per / rs_c,
            per / one_w,
            per / one_c,
            rs_w / one_w,
            rs_c / one_c,
            per / two_w,
            per / two_c,
            one_w / two_w,
        );
    }
}

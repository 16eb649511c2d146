//! Positions-only and velocity-only sweeps, and batches of models on threads, against
//! the plain full sweep.

use crate::common;
use common::*;
use linkwork::{sweep, sweep_batch, Data, Model, Request, SolveError, SweepOutput};
use std::f64::consts::PI;

fn times(n: usize) -> Vec<f64> {
    (0..n).map(|k| k as f64 * 2.0 * PI / 5.0 / (n - 1) as f64).collect()
}

fn full(model: &Model, t: &[f64]) -> SweepOutput {
    let mut out = SweepOutput::new(model, t);
    sweep(model, &mut Data::new(model), t, &mut out, 0, &mut |_| true).unwrap();
    out
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

#[test]
fn fewer_derivatives_give_the_same_positions_and_no_more() {
    let model = Model::new(four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0)).unwrap();
    let t = times(2001);
    let reference = full(&model, &t);
    for d in [0u8, 1] {
        let mut out = SweepOutput::with_derivatives(&model, &t, d);
        sweep(&model, &mut Data::new(&model), &t, &mut out, 0, &mut |_| true).unwrap();
        // each converges to the same solution within the Newton tolerance (1e-12 scaled)
        assert!(max_diff(&out.q, &reference.q) < 1e-11, "derivatives {d}: q differs");
        assert_eq!(out.qdd.len(), 0);
        if d == 1 {
            assert!(max_diff(&out.qd, &reference.qd) < 1e-10);
        } else {
            assert_eq!(out.qd.len(), 0);
        }
        // the history-based predictors are as good as the Taylor one: no more iterations
        let mean = |it: &[u32]| it.iter().map(|&i| i as f64).sum::<f64>() / it.len() as f64;
        let (mine, theirs) = (mean(&out.iterations), mean(&reference.iterations));
        assert!(
            mine <= theirs + 0.05,
            "derivatives {d}: {mine} Newton iterations per step, full sweep {theirs}"
        );
    }
}

#[test]
fn a_batch_gives_what_the_sweeps_give_one_by_one() {
    let designs: Vec<Model> = (0..6)
        .map(|k| {
            Model::new(four_bar(
                &FourBar { r1: 0.35, r2: 0.18 + 0.01 * k as f64, r3: 0.35, r4: 0.25 },
                0.0,
                5.0,
            ))
            .unwrap()
        })
        .collect();
    let refs: Vec<&Model> = designs.iter().collect();
    let t = times(501);
    for threads in [1, 2] {
        let batch = sweep_batch(&refs, &t, Request::default(), threads, &mut |_| true);
        assert_eq!(batch.len(), designs.len());
        for (model, (out, err)) in designs.iter().zip(&batch) {
            assert!(err.is_none());
            let one = full(model, &t);
            assert_eq!(out.q, one.q, "threads {threads}: a batch sweep is the same computation");
            assert_eq!(out.qdd, one.qdd);
        }
    }
}

#[test]
fn a_failing_design_does_not_stop_the_others() {
    let good = Model::new(four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0)).unwrap();
    // drive the slider-crank's slider by a crank angle law far beyond one revolution: fine;
    // but a four-bar whose crank cannot turn fully (non-Grashof) fails part-way
    let bad = Model::new(four_bar(&FourBar { r1: 0.35, r2: 0.30, r3: 0.20, r4: 0.25 }, 0.6, 5.0)).unwrap();
    let t = times(721);
    let batch = sweep_batch(&[&good, &bad, &good], &t, Request::default(), 2, &mut |_| true);
    assert!(batch[0].1.is_none() && batch[2].1.is_none());
    let (out, err) = &batch[1];
    let k = err.as_ref().and_then(|e| e.step()).expect("the non-Grashof design fails at a step");
    assert!(k > 0 && out.n_done == k && out.q.len() == k * out.n_coords);
}

#[test]
fn a_batch_can_be_cancelled() {
    let model = Model::new(four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0)).unwrap();
    let refs: Vec<&Model> = (0..4).map(|_| &model).collect();
    let t = times(400_000);
    let batch = sweep_batch(&refs, &t, Request::default(), 2, &mut |_| false);
    assert!(batch.iter().all(|(_, e)| matches!(e, Some(SolveError::Cancelled { .. }))));
    assert!(batch.iter().all(|(o, _)| o.n_done < t.len()));
}

#[test]
fn keeping_every_kth_step_keeps_those_steps_and_the_worst_diagnostics() {
    let model = Model::new(four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.0, 5.0)).unwrap();
    let t = times(1001);
    let all = full(&model, &t);
    let mut out = SweepOutput::with_request(&model, &t, Request { every: 10, ..Request::default() });
    sweep(&model, &mut Data::new(&model), &t, &mut out, 0, &mut |_| true).unwrap();
    assert_eq!(out.n_done, 101);
    let m = model.n_coords;
    for row in 0..out.n_done {
        let k = 10 * row;
        assert_eq!(out.times[row], t[k]);
        assert_eq!(&out.q[row * m..(row + 1) * m], &all.q[k * m..(k + 1) * m]);
        let stride = k.saturating_sub(9)..=k;
        let worst = stride.clone().map(|j| all.pivot_ratio[j]).fold(f64::INFINITY, f64::min);
        assert_eq!(out.pivot_ratio[row], worst);
        assert_eq!(out.iterations[row], stride.map(|j| all.iterations[j]).max().unwrap());
    }
}

/// `sweep_batch_on` with a base whose groups are not the models' (another mechanism): the
/// models are swept from their own drawings, to the bit as `sweep_batch` sweeps them; the
/// base's branches are enforced only on designs of the same mechanism.
#[test]
fn another_mechanism_as_the_base_leaves_each_model_to_its_drawing() {
    let four_bar =
        Model::new(four_bar(&FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 }, 0.3, 5.0)).unwrap();
    let six_bar = Model::new(six_bar_stephenson(0.3, 5.0)).unwrap();
    let t = times(101);
    let own = sweep_batch(&[&four_bar], &t, Request::default(), 1, &mut |_| true);
    let based =
        linkwork::sweep_batch_on(&[&four_bar], &t, Request::default(), Some(&six_bar), 1, &mut |_| true);
    assert!(own[0].1.is_none() && based[0].1.is_none(), "{:?}", based[0].1);
    assert_eq!(own[0].0.n_done, based[0].0.n_done);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&own[0].0.q), bits(&based[0].0.q));
    assert_eq!(bits(&own[0].0.qdd), bits(&based[0].0.qdd));
}

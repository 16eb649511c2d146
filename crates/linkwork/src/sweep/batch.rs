//! Many sweeps at once (a design study: one model per parameter set) on worker threads.
//! Each model is swept by one thread with its own `Data`; threads take the next model
//! as they finish one. The calling thread watches: it reports progress and may cancel,
//! which stops every running sweep at its next progress point.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

use crate::error::SolveError;
use crate::model::data::Data;
use crate::model::Model;
use crate::sweep::branches::{asked_branches, sweep_on};
use crate::sweep::outputs::{Outputs, Request, SweepOutput};

/// One model's sweep: its outputs (the completed steps) and its error, if any.
pub type BatchItem = (SweepOutput, Option<SolveError>);

/// Sweeps every model over `times`, computing what `request` asks, on `threads` threads
/// (0: as many as the machine has cores). `watch(done)` is called on the calling thread
/// about every 5 ms with the number of finished models, and may return false to cancel.
pub fn sweep_batch(
    models: &[&Model],
    times: &[f64],
    request: Request,
    threads: usize,
    watch: &mut dyn FnMut(usize) -> bool,
) -> Vec<BatchItem> {
    sweep_batch_on(models, times, request, None, threads, watch)
}

/// `sweep_batch` of designs of one mechanism, each started on the branches `asked` takes at
/// times[0] (`branches::asked_branches`: the base of a design study), not wherever Newton
/// from its own drawing lands; a design that has no configuration there is its error.
pub fn sweep_batch_on(
    models: &[&Model],
    times: &[f64],
    request: Request,
    asked: Option<&Model>,
    threads: usize,
    watch: &mut dyn FnMut(usize) -> bool,
) -> Vec<BatchItem> {
    sweep_batch_kept(models, times, request, None, asked, threads, watch)
}

/// `sweep_batch_on` keeping, of model i, only `outputs[i]` (its coordinates and points, as
/// `SweepOutput::with_outputs` keeps them; None: every coordinate of every model): what is
/// not kept is neither stored nor allocated.
pub fn sweep_batch_kept(
    models: &[&Model],
    times: &[f64],
    request: Request,
    outputs: Option<&[Outputs]>,
    asked: Option<&Model>,
    threads: usize,
    watch: &mut dyn FnMut(usize) -> bool,
) -> Vec<BatchItem> {
    if let Some(o) = outputs {
        assert_eq!(o.len(), models.len(), "one set of outputs per model");
    }
    let asked = asked.zip(times.first()).and_then(|(m, &t)| asked_branches(m, t));
    let items = on_threads(
        models.len(),
        threads,
        watch,
        || (),
        |_, i, cancel| {
            let model = models[i];
            let mut data = Data::new(model);
            let mut out = match outputs {
                Some(o) => SweepOutput::with_outputs(model, times, request, o[i].clone()),
                None => SweepOutput::with_request(model, times, request),
            };
            let mut keep_going = |_: usize| !cancel.load(Ordering::Relaxed);
            let err = if cancel.load(Ordering::Relaxed) {
                Some(SolveError::Cancelled { step: 0 })
            } else {
                sweep_on(model, &mut data, times, &mut out, 4096, &mut keep_going, asked.as_ref()).err()
            };
            out.truncate();
            (out, err)
        },
    );
    items.into_iter().map(|r| r.expect("every model was swept")).collect()
}

/// Runs `work(state, i, cancel)` for i in 0..n on `threads` threads (0: one per core),
/// each thread with its own `state` (made by `init` on it), and returns the results in
/// order. The calling thread polls `watch(done)` about every 5 ms; false sets `cancel`,
/// which the work reads to stop early.
pub(crate) fn on_threads<S, T: Send>(
    n: usize,
    threads: usize,
    watch: &mut dyn FnMut(usize) -> bool,
    init: impl Fn() -> S + Sync,
    work: impl Fn(&mut S, usize, &AtomicBool) -> T + Sync,
) -> Vec<Option<T>> {
    let threads =
        if threads == 0 { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { threads };
    let threads = threads.min(n).max(1);
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let cancel = AtomicBool::new(false);
    let mut results: Vec<Option<T>> = (0..n).map(|_| None).collect();
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut state = init();
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= n {
                            break;
                        }
                        mine.push((i, work(&mut state, i, &cancel)));
                        done.fetch_add(1, Ordering::Relaxed);
                    }
                    mine
                })
            })
            .collect();
        while done.load(Ordering::Relaxed) < n && !workers.iter().all(|w| w.is_finished()) {
            if !watch(done.load(Ordering::Relaxed)) {
                cancel.store(true, Ordering::Relaxed);
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        for w in workers {
            for (i, item) in w.join().expect("a sweep worker panicked") {
                results[i] = Some(item);
            }
        }
    });
    results
}

//! The per-step loop allocates nothing: a sweep of 2,000 steps makes exactly as many
//! heap allocations as a sweep of 20 (all of them before the loop or at the first
//! factorization), counted by a global allocator.

mod common;
use common::*;
use linkwork::{sweep, Data, LinearKind, Model, Options, SweepOutput};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_of_sweep(model: &Model, n: usize) -> usize {
    let times: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
    let mut data = Data::new(model);
    let mut out = SweepOutput::new(model, &times);
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    sweep(model, &mut data, &times, &mut out, 0, &mut |_| true).unwrap();
    ALLOCATIONS.load(Ordering::Relaxed) - before
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

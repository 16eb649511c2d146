//! Makes data/alt_start.bin, the start set of Alt's nine-point problem: one root per
//! class (1442) at generic complex parameters, by monodromy (linkwork::synthesis::alt).
//!
//!     cargo run --release -p linkwork --example alt_start_set -- [SEED] [OUT] [RESUME]
//!
//! With RESUME (a start-set file), the loops continue from its classes and parameters.
//!
//!     cargo run --release -p linkwork --example alt_start_set -- reanchor SEED OUT FROM
//!
//! carries the start set FROM to random complex parameters (complex normal, seed SEED) by
//! parameter homotopy, completes it there by monodromy, and reports its worst root.
//! Stops at 1442 classes, or after 12 loops in a row that find no new class (then the set
//! is incomplete and the program says so, exit status 1).

use linkwork::synthesis::alt::{
    decode, encode, monodromy, monodromy_from, reanchor, start_quality, CLASSES, N_PARAMS,
};
use linkwork_homotopy::random::Rng;
use linkwork_homotopy::C64;
use std::time::Instant;

fn main() {
    let mut args: Vec<String> = std::env::args().collect();
    let reanchoring = args.get(1).is_some_and(|a| a == "reanchor");
    if reanchoring {
        args.remove(1);
    }
    let seed: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1442);
    let out = args.get(2).cloned().unwrap_or_else(|| "crates/linkwork/data/alt_start.bin".into());
    let started = Instant::now();
    let mut report = |lap: usize, n: usize, tracked: usize, back: usize| {
        eprintln!(
            "loop {lap}: {n} classes; {back} of {tracked} paths came back; {:.1} s",
            started.elapsed().as_secs_f64()
        );
    };
    let set = match args.get(3) {
        Some(path) if reanchoring => {
            let from = decode(&std::fs::read(path).expect("read the start set")).expect("a start-set file");
            let mut rng = Rng::new(seed);
            let p1: Vec<C64> = (0..N_PARAMS).map(|_| rng.complex_normal()).collect();
            let moved = reanchor(&from, &p1);
            eprintln!(
                "carried to seed {seed}'s parameters: {} classes; {:.1} s",
                moved.classes.len(),
                started.elapsed().as_secs_f64()
            );
            monodromy_from(moved, &mut rng, CLASSES, 12, 400, &mut report)
        }
        Some(path) => {
            let partial =
                decode(&std::fs::read(path).expect("read the start set")).expect("a start-set file");
            monodromy_from(partial, &mut Rng::new(seed ^ 0x5eed), CLASSES, 12, 400, &mut report)
        }
        None => monodromy(seed, CLASSES, 12, 400, &mut report),
    };
    std::fs::write(&out, encode(&set)).expect("write the start set");
    let (certified, alpha, condition) = start_quality(&set);
    eprintln!("{certified} roots certified; worst alpha {alpha:.2e}, worst condition {condition:.2e}");
    eprintln!(
        "seed {seed}: {} classes in {:.1} s -> {out}",
        set.classes.len(),
        started.elapsed().as_secs_f64()
    );
    if set.classes.len() != CLASSES {
        eprintln!("incomplete: {} of {CLASSES} classes", set.classes.len());
        std::process::exit(1);
    }
}

//! Makes data/alt_start.bin, the start set of Alt's nine-point problem: one root per
//! class (1442) at generic complex parameters, by monodromy (linkwork::synthesis::alt).
//!
//!     cargo run --release -p linkwork --example alt_start_set -- [SEED] [OUT] [RESUME]
//!
//! With RESUME (a start-set file), the loops continue from its classes and parameters.
//! Stops at 1442 classes, or after 12 loops in a row that find no new class (then the set
//! is incomplete and the program says so, exit status 1).

use linkwork::synthesis::alt::{decode, encode, monodromy, monodromy_from, CLASSES};
use linkwork_homotopy::random::Rng;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
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
        Some(path) => {
            let partial =
                decode(&std::fs::read(path).expect("read the start set")).expect("a start-set file");
            monodromy_from(partial, &mut Rng::new(seed ^ 0x5eed), CLASSES, 12, 400, &mut report)
        }
        None => monodromy(seed, CLASSES, 12, 400, &mut report),
    };
    std::fs::write(&out, encode(&set)).expect("write the start set");
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

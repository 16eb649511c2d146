//! Alt's nine-point problem at random complex parameters (d and d^ independent): how many
//! of the 1442 shipped classes end at finite, certified roots, and how fast.
//!
//! Run: cargo run --release -p linkwork --example alt_complex -- [seed ...]
//! (ALT_START=file: another start set than the shipped one)

use linkwork::synthesis::alt;
use linkwork_homotopy::random::Rng;
use linkwork_homotopy::C64;

fn main() {
    let seeds: Vec<u64> = std::env::args().skip(1).filter_map(|s| s.parse().ok()).collect();
    let seeds = if seeds.is_empty() { vec![1, 2, 3] } else { seeds };
    let other = std::env::var("ALT_START")
        .ok()
        .map(|path| alt::decode(&std::fs::read(path).expect("read the start set")).expect("a start set"));
    let start = other.as_ref().unwrap_or_else(|| alt::shipped());
    for seed in seeds {
        let mut rng = Rng::new(seed);
        let p1: Vec<C64> = (0..alt::N_PARAMS).map(|_| rng.complex_normal()).collect();
        let t = std::time::Instant::now();
        let s = alt::solve_params(&p1, start, alt::WALL_BUDGET).expect("random finite parameters");
        let elapsed = t.elapsed().as_secs_f64();
        let certified = s.roots.iter().filter(|r| r.certified).count();
        println!(
            "seed {seed}: {:.2} s, {} paths ({:.0} paths/s), {} finite roots ({} certified), {} failed, {} at infinity, {} singular, {} duplicates, in distinct orbits {}, {:.0} steps + {:.0} rejected per path",
            elapsed,
            s.paths,
            s.paths as f64 / elapsed,
            s.roots.len(),
            certified,
            s.failed,
            s.at_infinity,
            s.singular.len(),
            s.duplicates,
            s.distinct,
            s.steps as f64 / s.paths as f64,
            s.rejected as f64 / s.paths as f64,
        );
    }
}

//! A four-bar sweep for profiling (valgrind --tool=callgrind): the textbook four-bar,
//! one revolution in `steps` steps, positions, velocities and accelerations.
//!     cargo run --release -p linkwork --example profile_sweep -- 100000 dense

use linkwork::{sweep, Data, Description, LinearKind, Model, Options, SweepOutput};

fn main() {
    let mut args = std::env::args().skip(1);
    let steps: usize = args.next().map_or(100_000, |s| s.parse().expect("steps"));
    let linear = match args.next().as_deref() {
        Some("sparse") => LinearKind::Sparse,
        Some("small") => LinearKind::Small,
        Some("refactor") => LinearKind::Refactor,
        _ => LinearKind::Dense,
    };
    // open branch at crank angle 0: the rocker stands at 60 degrees
    let th4 = std::f64::consts::FRAC_PI_3;
    let b = [0.35 + 0.25 * th4.cos(), 0.25 * th4.sin()];
    let th3 = (b[1]).atan2(b[0] - 0.2);
    let json = format!(
        r#"{{"name": "four-bar", "bodies": [
            {{"name": "crank", "x": 0, "y": 0, "theta": 0}},
            {{"name": "coupler", "x": 0.2, "y": 0, "theta": {th3}}},
            {{"name": "rocker", "x": 0.35, "y": 0, "theta": {th4}}}],
          "joints": [
            {{"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [0, 0]}},
            {{"type": "revolute", "name": "A", "body_a": "crank", "body_b": "coupler", "at": [0.2, 0]}},
            {{"type": "revolute", "name": "B", "body_a": "coupler", "body_b": "rocker", "at": [{}, {}]}},
            {{"type": "revolute", "name": "O4", "body_a": "rocker", "body_b": "ground", "at": [0.35, 0]}}],
          "drivers": [{{"type": "angle", "name": "crank_angle", "body": "crank",
                        "law": {{"type": "linear", "value": 0, "rate": 5}}}}]}}"#,
        b[0], b[1]
    );
    let desc = Description::from_json(&json).expect("description");
    let model = Model::with_options(desc, Options { linear, ..Options::default() }).expect("model");
    let times: Vec<f64> =
        (0..steps).map(|k| k as f64 * 2.0 * std::f64::consts::PI / 5.0 / (steps - 1) as f64).collect();
    let mut data = Data::new(&model);
    let mut out = SweepOutput::new(&model, &times);
    let start = std::time::Instant::now();
    sweep(&model, &mut data, &times, &mut out, 0, &mut |_| true).expect("sweep");
    let secs = start.elapsed().as_secs_f64();
    let mean_iter = out.iterations.iter().map(|&i| i as f64).sum::<f64>() / steps as f64;
    println!(
        "{steps} steps, {:.3} us/step, {mean_iter:.2} Newton iterations per step",
        secs / steps as f64 * 1e6
    );
}

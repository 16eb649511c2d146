//! A block on a slide held by a spring-damper: m x'' + c x' + k x = 0 has a closed form,
//! so the forward-dynamics tests measure their errors against it.

use linkwork::{Description, Model, Options};

pub const K: f64 = 50.0;
pub const MASS: f64 = 2.0;
pub const C: f64 = 0.8;

/// A block of `mass` on a slide along x, a spring (k = K, free length 1, `damping`) from
/// the ground point (-1, 0): the spring's length is 1 + x. Released at rest 0.3 from its
/// rest position; gravity acts across the slide.
pub fn oscillator(mass: f64, damping: f64) -> Model {
    oscillator_on_travel(mass, damping, None)
}

/// `oscillator`, its slide given a `travel` (the slide's range from the start, x = 0.3).
pub fn oscillator_on_travel(mass: f64, damping: f64, travel: Option<[f64; 2]>) -> Model {
    let travel = travel.map_or(String::new(), |[lo, hi]| format!(r#", "travel": [{lo:?}, {hi:?}]"#));
    let json = format!(
        r#"{{"name": "oscillator", "gravity": [0, -9.81],
            "bodies": [{{"name": "block", "x": 0.3, "y": 0.0, "mass": {mass}, "inertia": 0.1}}],
            "joints": [{{"type": "prismatic", "name": "slide", "body_a": "ground", "body_b": "block",
                         "at": [0.3, 0.0], "axis": [1.0, 0.0]{travel}}}],
            "loads": [{{"type": "spring", "name": "s", "body_a": "ground", "at_a": [-1.0, 0.0],
                        "body_b": "block", "at_b": [0.3, 0.0], "stiffness": {K}, "free_length": 1.0,
                        "damping": {damping}}}]}}"#
    );
    Model::with_options(Description::from_json(&json).unwrap(), Options { free: true, ..Options::default() })
        .unwrap()
}

/// x(t) of MASS x'' + c x' + K x = 0 from x0, v0 (underdamped).
pub fn exact(t: f64, c: f64, x0: f64, v0: f64) -> f64 {
    let w0 = (K / MASS).sqrt();
    let zeta = c / (2.0 * (K * MASS).sqrt());
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    (-zeta * w0 * t).exp() * (x0 * (wd * t).cos() + (v0 + zeta * w0 * x0) / wd * (wd * t).sin())
}

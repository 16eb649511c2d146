//! Cam motion: normalised rise profiles s(u) (u and s in [0, 1]), a single rise (or fall),
//! and a cam program of dwells, rises and falls.
//!
//! Every profile has s(0) = 0, s(1) = 1 and s'(0) = s'(1) = 0, so rises and dwells join
//! with continuous velocity. All but the simple harmonic also have s''(0) = s''(1) = 0
//! (continuous acceleration); the simple harmonic's acceleration jumps at both ends.
//! Peak coefficients for unit lift over unit time (Norton, Design of Machinery, tables
//! 8-2 and 8-3), max |s'| and max |s''|:
//!
//! | profile            | Cv     | Ca     | continuous |
//! |--------------------|--------|--------|------------|
//! | cycloidal          | 2.0000 | 6.2832 | C2         |
//! | modified trapezoid | 2.0000 | 4.8881 | C2         |
//! | modified sine      | 1.7596 | 5.5280 | C2         |
//! | 3-4-5 polynomial   | 1.8750 | 5.7735 | C2         |
//! | 4-5-6-7 polynomial | 2.1875 | 7.5107 | C3         |
//! | simple harmonic    | 1.5708 | 4.9348 | C1         |

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

/// A normalised rise s(u): s(0) = 0, s(1) = 1, at rest at both ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Profile {
    /// s = u - sin(2 pi u) / (2 pi): sine acceleration.
    Cycloidal,
    /// Constant acceleration plateaus joined by sine ramps (eighths of the rise).
    ModifiedTrapezoid,
    /// Sine acceleration with a short first and last quarter-wave (eighths of the rise).
    ModifiedSine,
    /// s = 10 u^3 - 15 u^4 + 6 u^5.
    #[serde(rename = "polynomial_345")]
    Polynomial345,
    /// s = 35 u^4 - 84 u^5 + 70 u^6 - 20 u^7.
    #[serde(rename = "polynomial_4567")]
    Polynomial4567,
    /// s = (1 - cos(pi u)) / 2: the acceleration jumps at both ends.
    Harmonic,
}

impl Profile {
    /// Every profile, for tests and documentation.
    pub const ALL: [Profile; 6] = [
        Profile::Cycloidal,
        Profile::ModifiedTrapezoid,
        Profile::ModifiedSine,
        Profile::Polynomial345,
        Profile::Polynomial4567,
        Profile::Harmonic,
    ];

    /// The name used in model descriptions.
    pub fn name(self) -> &'static str {
        match self {
            Profile::Cycloidal => "cycloidal",
            Profile::ModifiedTrapezoid => "modified_trapezoid",
            Profile::ModifiedSine => "modified_sine",
            Profile::Polynomial345 => "polynomial_345",
            Profile::Polynomial4567 => "polynomial_4567",
            Profile::Harmonic => "harmonic",
        }
    }

    /// Whether the acceleration is continuous where the rise meets a dwell.
    pub fn continuous_acceleration(self) -> bool {
        self != Profile::Harmonic
    }

    /// (s, ds/du, d2s/du2) at u, clamped to [0, 1].
    #[inline]
    pub fn eval(self, u: f64) -> [f64; 3] {
        let u = u.clamp(0.0, 1.0);
        match self {
            Profile::Cycloidal => {
                let (s, c) = (2.0 * PI * u).sin_cos();
                [u - s / (2.0 * PI), 1.0 - c, 2.0 * PI * s]
            }
            Profile::Harmonic => {
                let (s, c) = (PI * u).sin_cos();
                [0.5 * (1.0 - c), 0.5 * PI * s, 0.5 * PI * PI * c]
            }
            Profile::Polynomial345 => {
                let u2 = u * u;
                [
                    u2 * u * (10.0 + u * (-15.0 + 6.0 * u)),
                    u2 * (30.0 + u * (-60.0 + 30.0 * u)),
                    u * (60.0 + u * (-180.0 + 120.0 * u)),
                ]
            }
            Profile::Polynomial4567 => {
                let u2 = u * u;
                [
                    u2 * u2 * (35.0 + u * (-84.0 + u * (70.0 - 20.0 * u))),
                    u2 * u * (140.0 + u * (-420.0 + u * (420.0 - 140.0 * u))),
                    u2 * (420.0 + u * (-1680.0 + u * (2100.0 - 840.0 * u))),
                ]
            }
            // antisymmetric about u = 1/2: s(u) = 1 - s(1 - u)
            Profile::ModifiedTrapezoid | Profile::ModifiedSine if u > 0.5 => {
                let [s, v, a] = self.first_half(1.0 - u);
                [1.0 - s, v, -a]
            }
            Profile::ModifiedTrapezoid | Profile::ModifiedSine => self.first_half(u),
        }
    }

    /// The modified trapezoid and modified sine on u in [0, 1/2], from their acceleration
    /// integrated piece by piece (k = 4 pi: the first eighth is a quarter sine wave).
    fn first_half(self, u: f64) -> [f64; 3] {
        let k = 4.0 * PI;
        // the first eighth, common to both: a = C sin(k u)
        let ramp = |c: f64, u: f64| {
            let (s, co) = (k * u).sin_cos();
            [c * (u / k - s / (k * k)), c * (1.0 - co) / k, c * s]
        };
        let (c, [s1, v1, _]) = match self {
            // C = 8 pi / (2 + pi) makes s(1) = 1
            Profile::ModifiedTrapezoid => {
                let c = 8.0 * PI / (2.0 + PI);
                (c, ramp(c, 0.125))
            }
            // C = 4 pi^2 / (4 + pi)
            _ => {
                let c = 4.0 * PI * PI / (4.0 + PI);
                (c, ramp(c, 0.125))
            }
        };
        if u <= 0.125 {
            return ramp(c, u);
        }
        match self {
            Profile::ModifiedTrapezoid if u <= 0.375 => {
                // constant acceleration C
                let w = u - 0.125;
                [s1 + v1 * w + 0.5 * c * w * w, v1 + c * w, c]
            }
            Profile::ModifiedTrapezoid => {
                // a = C cos(k (u - 3/8)), from the end of the plateau
                let (s2, v2) = (s1 + v1 * 0.25 + 0.5 * c * 0.0625, v1 + c * 0.25);
                let w = u - 0.375;
                let (s, co) = (k * w).sin_cos();
                [s2 + v2 * w + c * (1.0 - co) / (k * k), v2 + c * s / k, c * co]
            }
            _ => {
                // a = C cos(k2 (u - 1/8)) with k2 = 4 pi / 3: zero at u = 1/2
                let k2 = k / 3.0;
                let w = u - 0.125;
                let (s, co) = (k2 * w).sin_cos();
                [s1 + v1 * w + c * (1.0 - co) / (k2 * k2), v1 + c * s / k2, c * co]
            }
        }
    }
}

/// One rise (or fall, with a negative lift) from `start` at `t0`, `duration` long:
/// f = start before t0, start + lift s((t - t0) / duration) during, start + lift after.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rise {
    #[serde(default)]
    pub start: f64,
    pub lift: f64,
    #[serde(default)]
    pub t0: f64,
    pub duration: f64,
    pub profile: Profile,
}

impl Rise {
    #[inline]
    pub(crate) fn eval(&self, t: f64) -> [f64; 3] {
        rise(self.profile, self.start, self.lift, self.duration, t - self.t0)
    }

    pub(crate) fn check(&self) -> Result<(), String> {
        finite("rise start", self.start)?;
        finite("rise lift", self.lift)?;
        finite("rise t0", self.t0)?;
        positive("rise duration", self.duration)
    }
}

/// start + lift s(tau / duration) and its time derivatives; constant outside the rise.
/// Right-continuous: where the acceleration jumps (simple harmonic ends), the value just
/// after the instant is taken.
#[inline(always)]
fn rise(profile: Profile, start: f64, lift: f64, duration: f64, tau: f64) -> [f64; 3] {
    if tau < 0.0 {
        return [start, 0.0, 0.0];
    }
    if tau >= duration {
        return [start + lift, 0.0, 0.0];
    }
    let [s, v, a] = profile.eval(tau / duration);
    [start + lift * s, lift * v / duration, lift * a / (duration * duration)]
}

/// A segment of a cam program.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum CamSegment {
    /// At rest.
    Dwell { duration: f64 },
    /// Up by `lift` (down if negative).
    Rise { duration: f64, lift: f64, profile: Profile },
    /// Down by `lift` (up if negative).
    Fall { duration: f64, lift: f64, profile: Profile },
}

impl CamSegment {
    fn duration(&self) -> f64 {
        match self {
            CamSegment::Dwell { duration }
            | CamSegment::Rise { duration, .. }
            | CamSegment::Fall { duration, .. } => *duration,
        }
    }

    /// The signed change of value over the segment, and its profile.
    fn change(&self) -> (f64, Profile) {
        match self {
            CamSegment::Dwell { .. } => (0.0, Profile::Cycloidal),
            CamSegment::Rise { lift, profile, .. } => (*lift, *profile),
            CamSegment::Fall { lift, profile, .. } => (-*lift, *profile),
        }
    }
}

/// Dwells, rises and falls one after the other from `start` at time `t0`: each segment
/// starts where the previous one ended, so the value is continuous by construction (and
/// the velocity too, every profile being at rest at its ends). Before t0 the value is
/// `start`; after the last segment, its end value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CamProgram {
    #[serde(default)]
    pub start: f64,
    #[serde(default)]
    pub t0: f64,
    pub segments: Vec<CamSegment>,
    /// n_segments + 1: when each segment starts (and the last ends); set by `prepare`
    #[serde(skip)]
    times: Vec<f64>,
    /// n_segments + 1: the value at each of those times; set by `prepare`
    #[serde(skip)]
    values: Vec<f64>,
}

impl CamProgram {
    /// A program (which `check` must accept), prepared.
    pub fn new(start: f64, t0: f64, segments: Vec<CamSegment>) -> Result<Self, String> {
        let mut c = CamProgram { start, t0, segments, times: Vec::new(), values: Vec::new() };
        c.check()?;
        c.prepare();
        Ok(c)
    }

    /// The time the last segment ends.
    pub fn end(&self) -> f64 {
        self.t0 + self.segments.iter().map(CamSegment::duration).sum::<f64>()
    }

    pub(crate) fn check(&self) -> Result<(), String> {
        finite("cam program start", self.start)?;
        finite("cam program t0", self.t0)?;
        if self.segments.is_empty() {
            return Err("cam program has no segments".into());
        }
        for (i, s) in self.segments.iter().enumerate() {
            positive(&format!("cam segment {i} duration"), s.duration())?;
            finite(&format!("cam segment {i} lift"), s.change().0)?;
        }
        Ok(())
    }

    pub(crate) fn prepare(&mut self) {
        let n = self.segments.len();
        self.times = Vec::with_capacity(n + 1);
        self.values = Vec::with_capacity(n + 1);
        let (mut t, mut v) = (self.t0, self.start);
        for s in &self.segments {
            self.times.push(t);
            self.values.push(v);
            t += s.duration();
            v += s.change().0;
        }
        self.times.push(t);
        self.values.push(v);
    }

    #[inline]
    pub(crate) fn eval(&self, t: f64) -> [f64; 3] {
        let n = self.segments.len();
        // segment k with times[k] <= t < times[k+1]
        let k = self.times.partition_point(|&tk| tk <= t);
        if k == 0 {
            return [self.start, 0.0, 0.0];
        }
        if k > n {
            return [self.values[n], 0.0, 0.0];
        }
        let k = k - 1;
        let (lift, profile) = self.segments[k].change();
        let duration = self.times[k + 1] - self.times[k];
        rise(profile, self.values[k], lift, duration, t - self.times[k])
    }
}

pub(crate) fn finite(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(format!("{name} is {v}, not a finite number"))
    }
}

pub(crate) fn positive(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(format!("{name} is {v}; it must be finite and > 0"))
    }
}

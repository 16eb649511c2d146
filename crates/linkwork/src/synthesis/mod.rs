//! Synthesis: link dimensions from precision points, every isolated solution found by
//! homotopy continuation (linkwork-homotopy), certified, and cross-checked by an
//! independent elimination.
//!
//! Pipeline: a problem (motion.rs, path.rs, sixbar.rs) becomes rows of the standard
//! dyad equation (dyad.rs) in local units (Frame); the rows are solved by parameter
//! homotopy (every root, alpha-certified) or by elimination (resultant.rs); roots come
//! back as `Dyad`s in the caller's units. function.rs holds the linear Freudenstein
//! problems.

#![allow(clippy::needless_range_loop)] // dense kernels index several arrays by one index

pub mod alt;
pub mod dyad;
pub mod function;
pub mod motion;
pub mod path;
pub mod resultant;
pub mod sixbar;
pub mod univariate;

use num_complex::Complex64 as C64;

use dyad::{residuals, DyadRow};
use linkwork_homotopy::Solutions;

/// Why a synthesis problem was refused.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SynthesisError {
    #[error("{problem} takes {want}; got {got}")]
    Count { problem: &'static str, got: usize, want: String },
    #[error("{what} is not finite")]
    NotFinite { what: String },
    #[error("{what} {i} and {j} coincide: they add no condition")]
    Coincident { what: &'static str, i: usize, j: usize },
    #[error("{what} are collinear: no circle passes through them")]
    Collinear { what: &'static str },
    #[error("{what} cannot be scaled to unit size: {why}")]
    Unscalable { what: &'static str, why: String },
    #[error("{0}")]
    Degenerate(String),
    #[error("the polynomial system was refused: {0}")]
    System(#[from] linkwork_homotopy::SystemError),
}

/// Largest coordinate (absolute) and smallest spread of a problem's data: the designs
/// are mechanisms in the caller's units, and their lengths squared must stay within
/// floating point's range (about 1e-308 to 1e308) with room to spare.
pub const LARGEST: f64 = 1e150;
pub const SMALLEST: f64 = 1e-150;

/// The data's frame; refuses data that no frame brings to unit size: a coordinate beyond
/// `LARGEST`, or points spread over less than `SMALLEST` but not all at one place (which
/// the problems judge themselves: coincident points, or poses differing only in angle).
pub fn check_scale(what: &'static str, points: &[C64]) -> Result<Frame, SynthesisError> {
    if points.iter().any(|p| !(p.re.is_finite() && p.im.is_finite())) {
        return Err(SynthesisError::NotFinite { what: what.into() });
    }
    let largest = points.iter().map(|p| p.re.abs().max(p.im.abs())).fold(0.0, f64::max);
    if largest > LARGEST {
        return Err(SynthesisError::Unscalable {
            what,
            why: format!(
                "a coordinate reaches {largest:.3e}, beyond {LARGEST:.0e} (lengths squared would overflow)"
            ),
        });
    }
    let frame = Frame::fit(points.iter().copied());
    let spread = points.iter().map(|p| (p - frame.centre).norm()).fold(0.0, f64::max);
    if spread > 0.0 && spread < SMALLEST {
        return Err(SynthesisError::Unscalable {
            what,
            why: format!("they span {spread:.3e}, below {SMALLEST:.0e} (lengths squared would underflow)"),
        });
    }
    Ok(frame)
}

/// Whether two data points are one (to 1e-9 of the data's size or of their own size).
pub fn coincide(a: C64, b: C64, frame: &Frame) -> bool {
    (a - b).norm() <= 1e-9 * (frame.scale + a.norm().max(b.norm()))
}

/// Local units: problems are solved centred and scaled to unit size, so tolerances mean
/// the same at any scale; results go back through `to_world`.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub centre: C64,
    pub scale: f64,
}

impl Frame {
    /// Centre and rms radius, computed without squaring a coordinate (no overflow for
    /// data up to f64::MAX / 2, no underflow down to subnormal spreads).
    pub fn fit(points: impl Iterator<Item = C64> + Clone) -> Self {
        let n = points.clone().count().max(1) as f64;
        let centre = points.clone().map(|p| p / n).sum::<C64>();
        let big = points.clone().map(|p| (p - centre).norm()).fold(0.0, f64::max);
        let rms = if big > 0.0 && big.is_finite() {
            big * (points.map(|p| ((p - centre) / big).norm_sqr()).sum::<f64>() / n).sqrt()
        } else {
            big
        };
        let scale = if rms > 0.0 && rms.is_finite() { rms } else { 1.0 };
        Frame { centre, scale }
    }

    pub fn to_local(&self, p: C64) -> C64 {
        (p - self.centre) / self.scale
    }

    pub fn to_world(&self, p: C64) -> C64 {
        self.centre + p * self.scale
    }
}

/// One RR dyad: its ground pivot (or the pivot fixed in the guiding link) and its moving
/// pivot, both at position 1 in world coordinates. Complex solutions keep their
/// imaginary parts (`*_imag`), which are zero for real ones.
#[derive(Clone, Debug, PartialEq)]
pub struct Dyad {
    pub ground: [f64; 2],
    pub moving: [f64; 2],
    pub ground_imag: [f64; 2],
    pub moving_imag: [f64; 2],
    /// Certified real (a real root lies within `radius` of it).
    pub real: bool,
    /// Passed the alpha test.
    pub certified: bool,
    /// Largest change of the link length over the positions, world length units.
    pub residual: f64,
    /// Normwise backward error of the polynomial system (scale-free).
    pub backward_error: f64,
    /// Condition number of the system's Jacobian at the root.
    pub condition: f64,
    /// Distance (world length units) within which the certified root lies.
    pub radius: f64,
}

impl Dyad {
    /// A dyad from a closed form (exact up to rounding, nothing to certify).
    pub fn exact(ground: C64, moving: C64) -> Self {
        Dyad {
            ground: [ground.re, ground.im],
            moving: [moving.re, moving.im],
            ground_imag: [0.0; 2],
            moving_imag: [0.0; 2],
            real: true,
            certified: true,
            residual: 0.0,
            backward_error: 0.0,
            condition: 1.0,
            radius: 0.0,
        }
    }
}

/// Largest | |V_j + sigma_j y| - |y| | over the rows (local units).
fn length_residual(rows: &[DyadRow; 4], x: C64, y: C64) -> f64 {
    let r = residuals(rows, x, y);
    // |a|^2 - |b|^2 = (|a| - |b|)(|a| + |b|)
    r.iter().map(|v| v.abs() / (2.0 * y.norm()).max(f64::MIN_POSITIVE)).fold(0.0, f64::max)
}

/// Every dyad of one problem, with what the paths did.
#[derive(Clone, Debug, Default)]
pub struct DyadSet {
    pub dyads: Vec<Dyad>,
    pub paths: usize,
    pub at_infinity: usize,
    pub failed: usize,
    pub singular: usize,
    /// Certified roots are pairwise distinct (disjoint certification balls).
    pub distinct: bool,
}

impl DyadSet {
    /// Dyads from homotopy roots in local units; `map(x, y)` gives (ground, moving) in
    /// local coordinates and must be affine.
    fn from_solutions(
        sol: &Solutions,
        rows: &[DyadRow; 4],
        frame: &Frame,
        map: impl Fn(C64, C64) -> (C64, C64),
    ) -> Self {
        let origin = map(C64::default(), C64::default());
        let dyads = sol
            .roots
            .iter()
            .map(|r| {
                let x_re = C64::new(r.x[0].re, r.x[1].re);
                let y_re = C64::new(r.x[2].re, r.x[3].re);
                let x_im = C64::new(r.x[0].im, r.x[1].im);
                let y_im = C64::new(r.x[2].im, r.x[3].im);
                let (g, m) = map(x_re, y_re);
                let (gi, mi) = map(x_im, y_im);
                let (gi, mi) = ((gi - origin.0) * frame.scale, (mi - origin.1) * frame.scale);
                let (g, m) = (frame.to_world(g), frame.to_world(m));
                Dyad {
                    ground: [g.re, g.im],
                    moving: [m.re, m.im],
                    ground_imag: [gi.re, gi.im],
                    moving_imag: [mi.re, mi.im],
                    real: r.real,
                    certified: r.certified,
                    // complex roots: the polynomial residual, scaled to length units
                    residual: if r.real {
                        length_residual(rows, x_re, y_re) * frame.scale
                    } else {
                        r.residual * frame.scale
                    },
                    backward_error: r.backward_error,
                    condition: r.condition,
                    radius: r.radius * frame.scale,
                }
            })
            .collect();
        DyadSet {
            dyads,
            paths: sol.paths,
            at_infinity: sol.at_infinity,
            failed: sol.failed,
            singular: sol.singular.len(),
            distinct: sol.distinct,
        }
    }

    pub fn real(&self) -> impl Iterator<Item = &Dyad> {
        self.dyads.iter().filter(|d| d.real)
    }
}

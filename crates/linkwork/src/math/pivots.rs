//! The pivots of a factorization: how close Phi_q is to singular, and the bound that
//! marks a step as near a singular configuration.

/// The pivots of a factorization: their spread says how close Phi_q is to singular.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pivots {
    /// smallest |pivot| / largest |pivot| of the scaled Phi_q (0 if singular, NaN if not finite)
    pub ratio: f64,
    /// the coordinate (column of Phi_q) of the smallest pivot
    pub column: usize,
    /// sign of det Phi_q (+1 or -1; 0 if a pivot is zero): it flips where a sweep crosses
    /// a singular configuration
    pub det_sign: f64,
}

impl Pivots {
    /// Before any factorization.
    pub const NONE: Pivots = Pivots { ratio: f64::NAN, column: 0, det_sign: 0.0 };
}

/// A pivot ratio below this marks a step next to a singular configuration: the next
/// prediction does not use its rates: solved to round-off, q is off by about eps / ratio
/// along the near-singular direction, and the rates solved at that q are off by that over
/// the ratio again.
pub const NEAR_SINGULAR: f64 = 1e-6;

/// Ratio of the smallest to the largest |pivot|, where the smallest is, and the sign of
/// det Phi_q (`sign`: that of the permutations and of L).
pub(crate) fn pivots(diag: impl Iterator<Item = (usize, f64)>, mut sign: f64) -> Pivots {
    let (mut lo, mut hi, mut column) = (f64::INFINITY, 0.0f64, 0);
    for (col, d) in diag {
        if d < 0.0 {
            sign = -sign;
        }
        let d = d.abs();
        if !d.is_finite() {
            return Pivots { ratio: f64::NAN, column: col, det_sign: 0.0 };
        }
        if d < lo {
            lo = d;
            column = col;
        }
        hi = hi.max(d);
    }
    let ratio = if hi > 0.0 { lo / hi } else { 0.0 };
    let det_sign = if lo > 0.0 { sign } else { 0.0 };
    Pivots { ratio, column, det_sign }
}

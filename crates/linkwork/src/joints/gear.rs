//! Spur gear pair between bodies a and b, rolling without slipping at the pitch circles
//! (radii r_a, r_b). 1 row, an angle:
//! k_a (theta_a - theta_c) + k_b (theta_b - theta_c) - value = 0,
//! where theta_c is the carrier's angle (the arm of a planetary train that holds both
//! centres; a coordinate borrowed from a third body) or 0 without a carrier (both centres
//! fixed in the ground), and value is the drawing's (the row is 0 at the start).
//!
//! k_a = r_a / r_max and k_b = +-r_b / r_max, r_max = max(r_a, r_b), so the row is
//! dimensionless with coefficients of at most 1. Signs: external gears turn opposite ways
//! (k_b = +r_b / r_max: r_a dtheta_a = -r_b dtheta_b); an internal gear and its pinion
//! turn the same way (k_b = -r_b / r_max). Relative to the carrier, the speed of b is
//! -+ (r_a / r_b) times that of a. Belts and chains (`belt`) use the same row.

use super::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};

#[derive(Debug, Clone, PartialEq)]
pub struct Gear {
    /// coefficient of theta_a - theta_c
    pub k_a: f64,
    /// coefficient of theta_b - theta_c
    pub k_b: f64,
    /// the row's constant, from the drawing
    pub value: f64,
    /// whether the row is relative to a carrier (the extra coordinate is its angle)
    pub carrier: bool,
}

impl Gear {
    /// The coefficients of a pair with pitch radii r_a, r_b (> 0), turning the same way
    /// (`same_sense`: internal gears, open belts) or opposite ways.
    pub fn coefficients(r_a: f64, r_b: f64, same_sense: bool) -> (f64, f64) {
        let r_max = r_a.max(r_b);
        let sign = if same_sense { -1.0 } else { 1.0 };
        (r_a / r_max, sign * r_b / r_max)
    }
}

impl Constraint for Gear {
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Angle]
    }
    fn has_extra(&self) -> bool {
        self.carrier
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, x: &Extra, _t: f64, out: &mut Rows) {
        let theta_c = if self.carrier { x.s } else { 0.0 };
        out.phi[0] = self.k_a * (a.theta - theta_c) + self.k_b * (b.theta - theta_c) - self.value;
        out.jac_a[0] = [0.0, 0.0, self.k_a];
        out.jac_b[0] = [0.0, 0.0, self.k_b];
        if self.carrier {
            out.jac_s[0] = -(self.k_a + self.k_b);
        }
    }
    #[inline]
    fn gamma(&self, _a: &Frame, _b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        // linear in the angles
        g[0] = 0.0;
    }
}

impl Sample for Gear {
    fn sample() -> Self {
        let (k_a, k_b) = Gear::coefficients(0.05, 0.12, false);
        Gear { k_a, k_b, value: 0.3, carrier: true }
    }
}

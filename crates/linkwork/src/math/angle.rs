//! Angles along a sweep: cos and sin turned from the last ones computed in full, an
//! angle from its direction continued from a nearby one, atan2 continued.

/// An angle change below this turns cos and sin from the last ones computed in full, by
/// their Taylor series to d^7: the first term left out, d^8 / 8!, is below 2^-70.
pub(crate) const SMALL_TURN: f64 = 1.0 / 64.0;

/// cos and sin of `theta`: turned from `base` (theta0, cos theta0, sin theta0) when
/// theta is within `SMALL_TURN` of theta0, else in full, and then `base` becomes theta's.
#[inline(always)]
pub fn turned(theta: f64, base: &mut [f64; 3]) -> (f64, f64) {
    let [theta0, c0, s0] = *base;
    let d = theta - theta0;
    if d.abs() < SMALL_TURN {
        let (d2, d4) = (d * d, d * d * (d * d));
        // cos d - 1 and sin d; added to c0, s0 last, so the result keeps their accuracy.
        // Estrin's order (the powers side by side): the sweep's chain of dependent
        // operations is what a step waits on, and Horner's is twice as long
        let cm = d2 * (d2 * (1.0 / 24.0) - 0.5) - d4 * d2 * (1.0 / 720.0);
        let sd = d * ((1.0 - d2 * (1.0 / 6.0)) + d4 * (1.0 / 120.0 - d2 * (1.0 / 5040.0)));
        (c0 + (c0 * cm - s0 * sd), s0 + (s0 * cm + c0 * sd))
    } else {
        let (s, c) = theta.sin_cos();
        *base = [theta, c, s];
        (c, s)
    }
}

/// The angle of the direction (c, s) (not necessarily of unit length), continued from
/// `near`: `turned`'s inverse. Within `SMALL_TURN` of `base`'s direction it is theta0 plus
/// atan of the turn's tangent by its series to x^9 (the first term left out, x^11 / 11,
/// is below 2^-69 of x), never added onto a turned angle, so errors cannot accumulate;
/// else atan2 in full, which becomes the base. Saves the atan2 of nearly every step of a
/// dyad's two bodies.
#[inline(always)]
pub fn angle_of(c: f64, s: f64, near: f64, base: &mut [f64; 3]) -> f64 {
    let [theta0, c0, s0] = *base;
    // the turn from the base: |base| |(c, s)| (cos d, sin d); their ratio is tan d whatever the norms
    let (cd, sd) = (c0 * c + s0 * s, c0 * s - s0 * c);
    if cd > 0.0 && sd.abs() < SMALL_TURN * cd {
        let x = sd / cd;
        let (x2, x4) = (x * x, x * x * (x * x));
        // Estrin's order, as in `turned`
        let d = x * ((1.0 - x2 * (1.0 / 3.0)) + x4 * ((1.0 / 5.0 - x2 * (1.0 / 7.0)) + x4 * (1.0 / 9.0)));
        let theta = theta0 + d;
        // the base may be a turn (or more) away from where the body went since (NaN: none yet)
        if (theta - near).abs() <= std::f64::consts::PI {
            return theta;
        }
    }
    let theta = continued(s.atan2(c), near);
    *base = [theta, c, s];
    theta
}

/// theta near `near` (2 pi multiples added): atan2's principal value continued.
#[inline(always)]
pub(crate) fn continued(raw: f64, near: f64) -> f64 {
    use std::f64::consts::TAU;
    let d = raw - near;
    if d.abs() <= std::f64::consts::PI {
        raw
    } else {
        raw - TAU * (d / TAU).round()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Turned cos and sin agree with sin_cos to round-off over the whole turn range, at
    /// small and large angles (a sweep's angles grow with its revolutions).
    #[test]
    fn turned_cos_and_sin_are_within_round_off() {
        let mut worst = 0.0f64;
        let mut rebased = 0;
        for i in 0..2000 {
            let theta0 = -70.0 + 140.0 * (i as f64 / 1999.0);
            let (s0, c0) = theta0.sin_cos();
            for j in 0..=200 {
                let d = SMALL_TURN * (2.0 * j as f64 / 200.0 - 1.0) * 0.9999 * (1.0 - 1e-9 * (j % 3) as f64);
                let theta = theta0 + d;
                let mut base = [theta0, c0, s0];
                let (c, s) = turned(theta, &mut base);
                rebased += (base[0] != theta0) as usize;
                let (se, ce) = theta.sin_cos();
                worst = worst.max((c - ce).abs()).max((s - se).abs());
            }
        }
        assert_eq!(rebased, 0, "every turn was below SMALL_TURN");
        // one ulp of 1 (measured: 1.1e-16, half of it); sin_cos itself is within half an ulp
        assert!(worst <= 2.3e-16, "worst error {worst:e}");
        // beyond SMALL_TURN the base moves to theta, in full
        let mut base = [0.0, 1.0, 0.0];
        assert_eq!(turned(0.5, &mut base), (0.5f64.cos(), 0.5f64.sin()));
        assert_eq!(base, [0.5, 0.5f64.cos(), 0.5f64.sin()]);
    }

    /// `angle_of` agrees with atan2 (continued) to round-off for turns within SMALL_TURN of
    /// its base, from directions of any length, and rebases beyond it or a turn away.
    #[test]
    fn angle_of_is_atan2_within_round_off() {
        let mut worst = 0.0f64;
        for i in 0..2000 {
            let theta0 = -70.0 + 140.0 * (i as f64 / 1999.0);
            let (s0, c0) = theta0.sin_cos();
            for j in 0..=200 {
                let d = SMALL_TURN * (2.0 * j as f64 / 200.0 - 1.0) * 0.9999;
                let theta = theta0 + d;
                let (se, ce) = theta.sin_cos();
                let scale = 1.0 + 1e-3 * (j % 7) as f64;
                let mut base = [theta0, c0, s0];
                let got = angle_of(scale * ce, scale * se, theta0, &mut base);
                assert_eq!(base[0], theta0, "within SMALL_TURN: no rebase");
                let exact = continued((scale * se).atan2(scale * ce), theta0);
                worst = worst.max((got - exact).abs() / theta.abs().max(1.0));
            }
        }
        // a few ulps of the angle (atan2 itself is within one)
        assert!(worst <= 4.5e-16, "worst relative error {worst:e}");
        // a turn away from the base: atan2 continued from `near`, which becomes the base
        let tau = std::f64::consts::TAU;
        let mut base = [0.1, 0.1f64.cos(), 0.1f64.sin()];
        let got = angle_of(0.1f64.cos(), 0.1f64.sin(), 0.1 + tau, &mut base);
        assert!((got - (0.1 + tau)).abs() < 1e-15 && (base[0] - got).abs() == 0.0);
        // no base yet (NaN): atan2
        let mut base = [f64::NAN, 1.0, 0.0];
        assert_eq!(angle_of(0.0, 2.0, 0.0, &mut base), std::f64::consts::FRAC_PI_2);
    }
}

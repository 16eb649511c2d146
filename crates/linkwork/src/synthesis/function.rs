//! Function generation by Freudenstein's equation: three precision pairs give a linear
//! 3 x 3 system (nalgebra), for four-bars (input and output angles) and slider-cranks
//! (input angle and slider position). Chebyshev spacing places the pairs where the
//! structural error of the interpolation is least.

use nalgebra::{Matrix3, Vector3};

use num_complex::Complex64 as C64;

use super::{check_scale, SynthesisError, LARGEST, SMALLEST};

/// A four-bar with ground pivots (0, 0) and (d, 0): crank a, coupler b, rocker c;
/// angles from the ground line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FourBar {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
}

/// A slider-crank: crank a about (0, 0), coupler b, slider on the line y = e, position s
/// along x.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliderCrank {
    pub a: f64,
    pub b: f64,
    pub e: f64,
}

/// Chebyshev spacing of n precision points on [lo, hi].
pub fn chebyshev(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (1..=n)
        .map(|j| {
            0.5 * (lo + hi)
                - 0.5 * (hi - lo) * ((2 * j - 1) as f64 * std::f64::consts::PI / (2 * n) as f64).cos()
        })
        .collect()
}

fn solve3(m: Matrix3<f64>, r: Vector3<f64>, what: &str) -> Result<Vector3<f64>, SynthesisError> {
    let k = m.lu().solve(&r).ok_or_else(|| {
        SynthesisError::Degenerate(format!(
            "the three {what} give a singular Freudenstein system (repeated or dependent pairs)"
        ))
    })?;
    if k.iter().all(|v| v.is_finite()) {
        Ok(k)
    } else {
        Err(SynthesisError::Degenerate(format!("the three {what} give a singular Freudenstein system")))
    }
}

fn check3(input: &[f64], output: &[f64], what: &'static str) -> Result<(), SynthesisError> {
    let n = input.len().min(output.len());
    if n != 3 || input.len() != output.len() {
        return Err(SynthesisError::Count {
            problem: what,
            got: n,
            want: "exactly 3 precision pairs for the linear Freudenstein solve".into(),
        });
    }
    if input.iter().chain(output).any(|v| !v.is_finite()) {
        return Err(SynthesisError::NotFinite { what: "a precision pair".into() });
    }
    Ok(())
}

/// A length of the result, refused when not finite or beyond the range `check_scale`
/// allows the data (a nearly singular system gives links of any size).
fn length(name: &str, v: f64) -> Result<f64, SynthesisError> {
    if v.is_finite() && v.abs() <= LARGEST && v.abs() >= SMALLEST {
        Ok(v)
    } else {
        Err(SynthesisError::Degenerate(format!(
            "the pairs give a {name} of length {v:.3e}: the Freudenstein system is nearly singular"
        )))
    }
}

/// Four-bar through three (input, output) angle pairs, ground length d:
/// K1 cos psi - K2 cos phi + K3 = cos(phi - psi), K1 = d/a, K2 = d/c,
/// K3 = (a^2 - b^2 + c^2 + d^2) / (2 a c).
pub fn four_bar(input: &[f64], output: &[f64], d: f64) -> Result<FourBar, SynthesisError> {
    check3(input, output, "Freudenstein four-bar function generation")?;
    if !(d.is_finite() && d.abs() <= LARGEST && d.abs() >= SMALLEST) {
        return Err(SynthesisError::Unscalable {
            what: "the ground length",
            why: format!("{d:.3e} is not a length between {SMALLEST:.0e} and {LARGEST:.0e}"),
        });
    }
    let m = Matrix3::from_fn(|i, j| match j {
        0 => output[i].cos(),
        1 => -input[i].cos(),
        _ => 1.0,
    });
    let r = Vector3::from_fn(|i, _| (input[i] - output[i]).cos());
    let k = solve3(m, r, "angle pairs")?;
    let a = length("crank", d / k[0])?;
    let c = length("rocker", d / k[1])?;
    let b2 = a * a + c * c + d * d - 2.0 * a * c * k[2];
    if b2 <= 0.0 {
        return Err(SynthesisError::Degenerate(format!("no real coupler: b^2 = {b2:.3e}")));
    }
    // a negative a or c is a crank pointing the other way: the lengths are the magnitudes
    Ok(FourBar { a, b: length("coupler", b2.sqrt())?, c, d })
}

/// Output angle of the four-bar at input phi on the branch `sign` (+1 or -1).
pub fn four_bar_output(fb: &FourBar, phi: f64, sign: f64) -> Option<f64> {
    // Freudenstein in the form A cos psi + B sin psi = C
    let k1 = fb.d / fb.a;
    let k2 = fb.d / fb.c;
    let k3 = (fb.a * fb.a - fb.b * fb.b + fb.c * fb.c + fb.d * fb.d) / (2.0 * fb.a * fb.c);
    let aa = k1 - phi.cos();
    let bb = -phi.sin();
    let cc = k2 * phi.cos() - k3;
    // aa cos psi + bb sin psi = cc  with cos(phi - psi) = cos phi cos psi + sin phi sin psi
    let r = (aa * aa + bb * bb).sqrt();
    if r == 0.0 || (cc / r).abs() > 1.0 {
        return None;
    }
    let base = bb.atan2(aa);
    Some(base + sign * (cc / r).acos())
}

/// Slider-crank through three (input angle, slider position) pairs:
/// K1 s cos phi + K2 sin phi - K3 = s^2, K1 = 2a, K2 = 2ae, K3 = a^2 + e^2 - b^2.
pub fn slider_crank(input: &[f64], position: &[f64]) -> Result<SliderCrank, SynthesisError> {
    check3(input, position, "Freudenstein slider-crank function generation")?;
    let spots: Vec<C64> = position.iter().map(|&s| C64::new(s, 0.0)).collect();
    check_scale("the slider positions", &spots)?;
    let m = Matrix3::from_fn(|i, j| match j {
        0 => position[i] * input[i].cos(),
        1 => input[i].sin(),
        _ => -1.0,
    });
    let r = Vector3::from_fn(|i, _| position[i] * position[i]);
    let k = solve3(m, r, "(angle, position) pairs")?;
    let a = length("crank", k[0] / 2.0)?;
    let e = k[1] / k[0];
    if !(e.is_finite() && e.abs() <= LARGEST) {
        return Err(SynthesisError::Degenerate(format!("the pairs give an offset of {e:.3e}")));
    }
    let b2 = a * a + e * e - k[2];
    if b2 <= 0.0 {
        return Err(SynthesisError::Degenerate(format!("no real coupler: b^2 = {b2:.3e}")));
    }
    Ok(SliderCrank { a, b: length("coupler", b2.sqrt())?, e })
}

/// Slider position at input phi on the branch `sign`.
pub fn slider_position(sc: &SliderCrank, phi: f64, sign: f64) -> Option<f64> {
    let dy = sc.e - sc.a * phi.sin();
    let h = sc.b * sc.b - dy * dy;
    (h >= 0.0).then(|| sc.a * phi.cos() + sign * h.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_bar_recovers_its_generator() {
        let fb = FourBar { a: 1.0, b: 3.2, c: 2.5, d: 3.0 };
        let phis = chebyshev(0.4, 1.6, 3);
        let psis: Vec<f64> = phis.iter().map(|&p| four_bar_output(&fb, p, 1.0).unwrap()).collect();
        let got = four_bar(&phis, &psis, 3.0).unwrap();
        for (g, w) in [got.a, got.b, got.c].iter().zip([1.0, 3.2, 2.5]) {
            assert!((g - w).abs() < 1e-12 * w, "{got:?}");
        }
    }

    #[test]
    fn slider_crank_recovers_its_generator() {
        let sc = SliderCrank { a: 0.8, b: 2.1, e: 0.3 };
        let phis = chebyshev(0.2, 2.0, 3);
        let s: Vec<f64> = phis.iter().map(|&p| slider_position(&sc, p, 1.0).unwrap()).collect();
        let got = slider_crank(&phis, &s).unwrap();
        assert!(
            (got.a - 0.8).abs() < 1e-12 && (got.b - 2.1).abs() < 1e-12 && (got.e - 0.3).abs() < 1e-12,
            "{got:?}"
        );
    }
}

//! Scalar roots: a bracketed root by the Illinois variant of regula falsi.

/// A root of f in [a, b] (f(a), f(b) of opposite signs) by the Illinois variant of
/// regula falsi: superlinear on simple roots, never leaves the bracket. None if f cannot
/// be evaluated at the ends. The caller has seen f change sign between a and b.
///
/// How precise the root is depends on f: a signed sigma_min is known only to about
/// sqrt(eps) near a bifurcation (the residual is quadratic in the distance to the
/// crossing branches, so Newton's solutions wander by sqrt(eps) there), while a rate's
/// zero (a lock) is found to round-off.
pub(crate) fn illinois(mut a: f64, mut b: f64, mut f: impl FnMut(f64) -> Option<f64>) -> Option<f64> {
    let mut fa = f(a)?;
    let mut fb = f(b)?;
    if fa == 0.0 {
        return Some(a);
    }
    if fb == 0.0 {
        return Some(b);
    }
    if fa * fb > 0.0 {
        // the caller saw a sign change between a and b; re-evaluated, one end is so close
        // to the root that its sign is round-off: that end is the root
        return Some(if fa.abs() < fb.abs() { a } else { b });
    }
    let tol = 4.0 * f64::EPSILON * a.abs().max(b.abs()).max((b - a).abs());
    for _ in 0..100 {
        let mut m = (a * fb - b * fa) / (fb - fa);
        if !m.is_finite() || (m - a) * (m - b) > 0.0 {
            m = 0.5 * (a + b);
        }
        let fm = match f(m) {
            Some(v) => v,
            // singular to round-off right at m: that is the root
            None => return Some(m),
        };
        if fm == 0.0 {
            return Some(m);
        }
        if fm * fb < 0.0 {
            a = b;
            fa = fb;
        } else {
            fa *= 0.5;
        }
        b = m;
        fb = fm;
        if (b - a).abs() <= tol {
            break;
        }
    }
    Some(b)
}

#[cfg(test)]
mod tests {
    use super::illinois;

    /// A double root: the caller's sign change was round-off, and the ends re-evaluated
    /// have one sign. The end nearer the root (the smaller |f|) is returned, on either
    /// side of the bracket; the far end is a bracket's length away.
    #[test]
    fn ends_of_one_sign_give_the_end_with_the_smaller_residual() {
        let square = |t: f64| Some(t * t);
        assert_eq!(illinois(-1e-9, 2.0, square), Some(-1e-9));
        assert_eq!(illinois(-2.0, 1e-9, square), Some(1e-9));
    }
}

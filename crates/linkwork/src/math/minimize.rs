//! A scalar minimum: Brent's method (golden section with parabolic steps).

const GOLDEN: f64 = 0.381_966_011_250_105_1; // (3 - sqrt 5) / 2

/// A local minimum of f on [a, b] from x inside it (f(x) = fx known, no higher than at
/// the ends), by Brent's method (R. P. Brent, Algorithms for Minimization without
/// Derivatives, 1973, ch. 5): parabolic steps through the best three points where they
/// fall well inside the bracket, golden-section steps otherwise. Stops when the bracket
/// is within 2 tol of the best point (tol absolute, in x's units). Returns (x, f(x)).
pub(crate) fn brent(
    mut a: f64,
    mut b: f64,
    x: f64,
    fx: f64,
    tol: f64,
    max_iter: usize,
    mut f: impl FnMut(f64) -> f64,
) -> (f64, f64) {
    let (mut x, mut fx) = (x, fx);
    let (mut w, mut fw, mut v, mut fv) = (x, fx, x, fx);
    let (mut d, mut e) = (0.0f64, 0.0f64);
    for _ in 0..max_iter {
        let m = 0.5 * (a + b);
        let tol1 = tol + 1e-12 * x.abs();
        let tol2 = 2.0 * tol1;
        if (x - m).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol1 {
            // the parabola through (v, w, x)
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            let e_prev = e;
            e = d;
            // accepted if inside the bracket and less than half the step before last
            if p.abs() < (0.5 * q * e_prev).abs() && p > q * (a - x) && p < q * (b - x) {
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = if m > x { tol1 } else { -tol1 };
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= m { a - x } else { b - x };
            d = GOLDEN * e;
        }
        let u = if d.abs() >= tol1 { x + d } else { x + tol1.copysign(d) };
        let fu = f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, fx)
}

#[cfg(test)]
mod tests {
    use super::brent;

    #[test]
    fn finds_the_vertex_of_a_parabola_in_few_steps() {
        // no offset: a minimum value of 1 would hide the argmin below sqrt(eps)
        let mut calls = 0;
        let (x, fx) = brent(0.0, 3.0, 2.5, 0.75f64 * 0.75, 1e-10, 100, |t| {
            calls += 1;
            (t - 1.75f64).powi(2)
        });
        assert!((x - 1.75).abs() < 1e-9, "{x}");
        assert!(fx < 1e-18, "{fx}");
        assert!(calls < 12, "{calls} evaluations");
    }

    #[test]
    fn finds_the_bottom_of_a_v_by_its_square() {
        // |t - t*| squared: the square of a V is smooth
        let v = |t: f64| (t - 0.8125f64).powi(2);
        let (x, _) = brent(-1.0, 2.0, 0.9, v(0.9), 1e-12, 100, v);
        assert!((x - 0.8125).abs() < 1e-8, "{x}");
    }

    #[test]
    fn finds_a_minimum_that_is_not_a_parabola() {
        // cos has its minimum at pi on [2, 4]
        let (x, _) = brent(2.0, 4.0, 3.5, 3.5f64.cos(), 1e-10, 100, f64::cos);
        assert!((x - std::f64::consts::PI).abs() < 1e-8, "{x}");
    }
}

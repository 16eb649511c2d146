//! An independent route to the roots of a dyad system (dyad.rs), by elimination in
//! isotropic coordinates: x and its conjugate as independent unknowns z, w, and y as u, v.
//! Row j reads V_j W_j + conj(sigma_j) V_j v + sigma_j W_j u = 0 with V_j = alpha_j z + beta_j
//! and W_j = conj(alpha_j) w + conj(beta_j): linear in (u, v) for fixed (z, w). Rows 1, 2, k
//! are consistent only where C_k(z, w) = det[r_1; r_2; r_k] = 0, with
//! r_j = (sigma_j W_j, conj(sigma_j) V_j, V_j W_j): a curve of bidegree (2, 2), k = 3, 4.
//! Their resultant in w is a polynomial R(z) of degree <= 8: the family's 5 roots (4 when
//! every |sigma_j| = 1, the fifth then at infinity) and 3 spurious ones (r_1 = 0, r_2 = 0,
//! or r_1 parallel to r_2, where rows 1 and 2 fix nothing). R is sampled on a circle and
//! interpolated (inverse DFT), its roots are a companion eigenproblem (nalgebra); at each,
//! w is the common root of C_3 and C_4 and (u, v) the least-squares solution of the four
//! rows; a spurious root leaves the rows inconsistent and is dropped. The candidates are
//! then polished, alpha-certified and merged on the dyad system itself (`certify_points`).

use linkwork_homotopy::{certify_points, Solutions, C64};
use nalgebra::{Matrix2, Vector2};

use super::dyad::{family, params, DyadRow};
use super::univariate;
use super::SynthesisError;

/// Samples of R on each circle: twice its degree, so the interpolated coefficients above
/// 8 measure the rounding.
const SAMPLES: usize = 16;
/// Circles of interpolation: R's coefficients are accurate for roots near the circle, so
/// roots up to `SPLIT` are taken from the unit circle and larger ones from the outer one.
const RADII: [f64; 2] = [1.0, 16.0];
const SPLIT: f64 = 4.0;

/// Row j at (z, w): (coefficient of u, coefficient of v, constant).
fn row(r: &DyadRow, z: C64, w: C64) -> [C64; 3] {
    let v = r.alpha * z + r.beta;
    let wb = r.alpha.conj() * w + r.beta.conj();
    [r.sigma * wb, r.sigma.conj() * v, v * wb]
}

fn det3(a: [C64; 3], b: [C64; 3], c: [C64; 3]) -> C64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// C_3 and C_4 at (z, w).
fn curves(rows: &[DyadRow; 4], z: C64, w: C64) -> [C64; 2] {
    let (r1, r2) = (row(&rows[0], z, w), row(&rows[1], z, w));
    [det3(r1, r2, row(&rows[2], z, w)), det3(r1, r2, row(&rows[3], z, w))]
}

/// Coefficients (a, b, c) in w of C_3 and C_4 at fixed z, from w = 0, 1, -1 (exact for a
/// quadratic).
fn quadratics(rows: &[DyadRow; 4], z: C64) -> [[C64; 3]; 2] {
    let one = C64::new(1.0, 0.0);
    let (c0, cp, cm) = (curves(rows, z, C64::default()), curves(rows, z, one), curves(rows, z, -one));
    std::array::from_fn(|k| [(cp[k] + cm[k]) / 2.0 - c0[k], (cp[k] - cm[k]) / 2.0, c0[k]])
}

/// Res_w(C_3, C_4)(z) = (a3 c4 - a4 c3)^2 - (a3 b4 - a4 b3)(b3 c4 - b4 c3).
fn resultant(rows: &[DyadRow; 4], z: C64) -> C64 {
    let [[a3, b3, c3], [a4, b4, c4]] = quadratics(rows, z);
    let ac = a3 * c4 - a4 * c3;
    ac * ac - (a3 * b4 - a4 * b3) * (b3 * c4 - b4 * c3)
}

/// Inverse DFT of samples on the unit circle: polynomial coefficients, lowest first.
fn idft(v: &[C64; SAMPLES]) -> Vec<C64> {
    let unit: [C64; SAMPLES] =
        std::array::from_fn(|k| C64::from_polar(1.0, -std::f64::consts::TAU * k as f64 / SAMPLES as f64));
    (0..SAMPLES)
        .map(|m| {
            v.iter().enumerate().map(|(k, vk)| vk * unit[(k * m) % SAMPLES]).sum::<C64>() / SAMPLES as f64
        })
        .collect()
}

/// The roots of R, each taken from the circle it is accurate on (the outer circle only
/// when the unit circle's interpolant has roots beyond `SPLIT`).
fn z_roots(rows: &[DyadRow; 4]) -> Vec<C64> {
    let roots_on = |radius: f64| {
        let values: [C64; SAMPLES] = std::array::from_fn(|k| {
            resultant(rows, C64::from_polar(radius, std::f64::consts::TAU * k as f64 / SAMPLES as f64))
        });
        univariate::roots(&idft(&values), 1e-11).into_iter().map(move |zeta| zeta * radius)
    };
    let (mut out, outer): (Vec<C64>, Vec<C64>) = roots_on(RADII[0]).partition(|z| z.norm() <= SPLIT);
    if !outer.is_empty() {
        out.extend(roots_on(RADII[1]).filter(|z| z.norm() > SPLIT));
    }
    out
}

/// Roots of a w^2 + b w + c, without cancellation; one when a is negligible.
fn quadratic_roots(a: C64, b: C64, c: C64) -> [Option<C64>; 2] {
    let scale = a.norm().max(b.norm()).max(c.norm());
    if scale == 0.0 {
        return [None, None];
    }
    if a.norm() <= 1e-14 * scale {
        return [(b.norm() > 0.0).then(|| -c / b), None];
    }
    let sq = (b * b - 4.0 * a * c).sqrt();
    // q = -(b + sign sqrt(disc)) / 2 with the sign that avoids cancellation
    let q = if (b.conj() * sq).re >= 0.0 { -(b + sq) / 2.0 } else { -(b - sq) / 2.0 };
    if q.norm() == 0.0 {
        return [Some(C64::default()), Some(C64::default())];
    }
    [Some(q / a), Some(c / q)]
}

/// (u, v) from the four rows, least squares (the rows are consistent at a root).
fn least_squares_y(rows: &[DyadRow; 4], z: C64, w: C64) -> Option<[C64; 2]> {
    let mut a = Matrix2::<C64>::zeros();
    let mut b = Vector2::<C64>::zeros();
    for r in rows {
        let row = row(r, z, w);
        for i in 0..2 {
            for j in 0..2 {
                a[(i, j)] += row[i].conj() * row[j];
            }
            b[i] -= row[i].conj() * row[2];
        }
    }
    let y = a.lu().solve(&b)?;
    Some([y[0], y[1]])
}

/// Candidate roots (x1, x2, y1, y2) of the dyad system, before polishing.
fn candidates(rows: &[DyadRow; 4]) -> Vec<Vec<C64>> {
    let half_i = C64::new(0.0, -0.5);
    z_roots(rows)
        .into_iter()
        .filter_map(|z| {
            let [[a3, b3, c3], [a4, b4, c4]] = quadratics(rows, z);
            // the root of C_3 (a quadratic in w) on which C_4 is smallest
            let w = quadratic_roots(a3, b3, c3).into_iter().flatten().min_by(|p, q| {
                let f = |w: &C64| (a4 * w * w + b4 * w + c4).norm() / (1.0 + w.norm_sqr());
                f(p).total_cmp(&f(q))
            })?;
            let [u, v] = least_squares_y(rows, z, w)?;
            // the spurious roots leave rows 3 and 4 inconsistent: drop them before Newton
            let inconsistent = rows.iter().any(|r| {
                let [a, b, c] = row(r, z, w);
                let (p, q) = (a * u, b * v);
                (p + q + c).norm() > 1e-3 * (p.norm() + q.norm() + c.norm())
            });
            if inconsistent {
                return None;
            }
            Some(vec![(z + w) / 2.0, (z - w) * half_i, (u + v) / 2.0, (u - v) * half_i])
        })
        .collect()
}

/// Every root of the dyad system by elimination, polished and certified.
pub fn solve_by_resultant(rows: &[DyadRow; 4]) -> Result<Solutions, SynthesisError> {
    let system = family().specialize(&params(rows))?;
    Ok(certify_points(&system, candidates(rows)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quadratic whose leading coefficient is negligible against the others is the line
    /// b z + c: its one root -c / b; a proper quadratic gives both roots.
    #[test]
    fn quadratic_roots_of_a_negligible_leading_coefficient_are_the_line_root() {
        let (b, c) = (C64::new(2.0, -1.0), C64::new(-3.0, 0.5));
        for a in [C64::new(0.0, 0.0), C64::new(1e-15, 0.0)] {
            let [r0, r1] = quadratic_roots(a, b, c);
            let r0 = r0.expect("the line's root");
            assert!((b * r0 + c).norm() < 1e-14, "{r0}");
            assert!(r1.is_none());
        }
        // (z - 1)(z - 2i): both roots
        let [r0, r1] = quadratic_roots(C64::new(1.0, 0.0), C64::new(-1.0, -2.0), C64::new(0.0, 2.0));
        let mut roots = [r0.unwrap(), r1.unwrap()];
        roots.sort_by(|x, y| x.re.total_cmp(&y.re));
        assert!(
            (roots[0] - C64::new(0.0, 2.0)).norm() < 1e-14 && (roots[1] - C64::new(1.0, 0.0)).norm() < 1e-14
        );
    }
}

//! An independent route to the roots of a dyad system (dyad.rs), by elimination:
//! for fixed x the rows are linear in y, so consistency of rows (1, 2, k) is
//! det[l_1 q_1; l_2 q_2; l_k q_k](x) = 0, a quartic curve, k = 3, 4. The two curves'
//! Sylvester resultant in x2 is a polynomial in x1 of degree <= 16, found by sampling on
//! the unit circle and an inverse DFT; its roots (companion matrix), the common roots in
//! x2, y by least squares, then Newton on the full system. Points where rows 1 and 2 are
//! dependent satisfy both curves without being roots; Newton and the residual reject them.

use linkwork_homotopy::{Affine, C64};
use nalgebra::{DMatrix, Matrix2, Vector2};

use super::dyad::{family, params, DyadRow};
use super::univariate;

/// A fixed, generic rotation of the (x1, x2) plane, so that no two roots share x1.
const TURN: f64 = 0.618_033_988_749_895;

fn rows_at(rows: &[DyadRow; 4], x: [C64; 2]) -> [[C64; 3]; 4] {
    let mut out = [[C64::default(); 3]; 4];
    for (o, r) in out.iter_mut().zip(rows) {
        let vr = r.alpha.re * x[0] - r.alpha.im * x[1] + r.beta.re;
        let vi = r.alpha.im * x[0] + r.alpha.re * x[1] + r.beta.im;
        *o = [
            2.0 * (vr * r.sigma.re + vi * r.sigma.im),
            2.0 * (vi * r.sigma.re - vr * r.sigma.im),
            vr * vr + vi * vi,
        ];
    }
    out
}

fn det3(a: [C64; 3], b: [C64; 3], c: [C64; 3]) -> C64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// x in the original plane from turned coordinates (u1, u2).
fn unturn(u: [C64; 2]) -> [C64; 2] {
    let (s, c) = TURN.sin_cos();
    [c * u[0] - s * u[1], s * u[0] + c * u[1]]
}

/// Coefficients in u2 (degree <= 4) of the two consistency conditions at fixed u1.
fn quartics(rows: &[DyadRow; 4], u1: C64) -> [Vec<C64>; 2] {
    const N: usize = 5;
    let mut vals = [[C64::default(); N]; 2];
    for k in 0..N {
        let w = C64::from_polar(1.0, std::f64::consts::TAU * k as f64 / N as f64);
        let r = rows_at(rows, unturn([u1, w]));
        vals[0][k] = det3(r[0], r[1], r[2]);
        vals[1][k] = det3(r[0], r[1], r[3]);
    }
    vals.map(|v| trim(idft(&v)))
}

/// Drop leading coefficients at rounding level: the curves' degree in u2 is below 4 in
/// most problems (Burmester's quadratic terms cancel), and a zero leading coefficient
/// would make the Sylvester determinant vanish identically.
fn trim(mut p: Vec<C64>) -> Vec<C64> {
    let scale = p.iter().map(|c| c.norm()).fold(0.0, f64::max);
    while p.len() > 1 && p[p.len() - 1].norm() <= 1e-11 * scale {
        p.pop();
    }
    p
}

fn idft(v: &[C64]) -> Vec<C64> {
    let n = v.len();
    (0..n)
        .map(|m| {
            let mut s = C64::default();
            for (k, vk) in v.iter().enumerate() {
                s += vk * C64::from_polar(1.0, -std::f64::consts::TAU * (k * m) as f64 / n as f64);
            }
            s / n as f64
        })
        .collect()
}

fn sylvester(p: &[C64], q: &[C64]) -> C64 {
    let (m, n) = (p.len() - 1, q.len() - 1);
    if m + n == 0 {
        return C64::new(1.0, 0.0);
    }
    let size = m + n;
    let mut s = DMatrix::<C64>::zeros(size, size);
    for i in 0..n {
        for (k, c) in p.iter().rev().enumerate() {
            s[(i, i + k)] = *c;
        }
    }
    for i in 0..m {
        for (k, c) in q.iter().rev().enumerate() {
            s[(n + i, i + k)] = *c;
        }
    }
    s.lu().determinant()
}

/// Candidate roots (x1, x2, y1, y2), polished by Newton and deduplicated.
pub fn solve_by_resultant(rows: &[DyadRow; 4]) -> Vec<[C64; 4]> {
    const SAMPLES: usize = 32;
    // the interpolated coefficients are accurate for roots near the sampling circle: one
    // circle per decade and a half of |x1|, candidates merged
    let mut candidates = Vec::new();
    for radius in [1.0, 8.0, 64.0] {
        let values: Vec<C64> = (0..SAMPLES)
            .map(|k| {
                let u1 = C64::from_polar(radius, std::f64::consts::TAU * k as f64 / SAMPLES as f64);
                let [p, q] = quartics(rows, u1);
                sylvester(&p, &q)
            })
            .collect();
        // coefficients of R(radius w) in w
        let resultant = idft(&values);
        candidates.extend(univariate::roots(&resultant, 1e-11).into_iter().map(|w| w * radius));
    }
    let affine = Affine::new(family().specialize(&params(rows)).expect("parameter count"));
    let mut found: Vec<[C64; 4]> = Vec::new();
    for u1 in candidates {
        let [p, q] = quartics(rows, u1);
        let q_scale = q.iter().map(|c| c.norm()).fold(0.0, f64::max);
        for u2 in univariate::roots(&p, 1e-11) {
            let size = u2.norm().max(1.0).powi(4);
            if univariate::eval(&q, u2).norm() > 1e-6 * q_scale * size {
                continue;
            }
            let x = unturn([u1, u2]);
            let Some(y) = least_squares_y(rows, x) else { continue };
            let mut z = vec![x[0], x[1], y[0], y[1]];
            if !affine.newton(&mut z, 12) {
                continue;
            }
            let (_, backward) = affine.residual(&z);
            if backward > 1e-12 || !affine.alpha(&z).certified {
                continue;
            }
            let scale = z.iter().map(|v| v.norm()).fold(1.0, f64::max);
            let new = !found
                .iter()
                .any(|f| f.iter().zip(&z).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max) < 1e-8 * scale);
            if new {
                found.push([z[0], z[1], z[2], z[3]]);
            }
        }
    }
    found
}

/// y from the four rows l_j . y = -q_j (consistent at a root): normal equations.
fn least_squares_y(rows: &[DyadRow; 4], x: [C64; 2]) -> Option<[C64; 2]> {
    let r = rows_at(rows, x);
    let mut a = Matrix2::<C64>::zeros();
    let mut b = Vector2::<C64>::zeros();
    for row in &r {
        for i in 0..2 {
            for j in 0..2 {
                a[(i, j)] += row[i] * row[j];
            }
            b[i] -= row[i] * row[2];
        }
    }
    let y = a.lu().solve(&b)?;
    Some([y[0], y[1]])
}

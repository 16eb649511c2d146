//! Jets: numbers along a perturbed motion, for exact sensitivities.
//!
//! A jet is a truncated Taylor polynomial in time tau (about the step's time) and in a
//! perturbation epsilon of the design parameters (first order in epsilon, W directions at
//! once):
//!   x(tau, eps) = v0 + v1 tau + v2 tau^2 + sum_k eps_k (e_k0 + e_k1 tau + e_k2 tau^2).
//! Evaluating a joint's phi on jets of the bodies' perturbed motion gives, exactly (to
//! round-off), phi's time derivatives along the motion (v1 = phi', v2 = phi'' / 2) and their
//! derivatives in each parameter direction (e_k0, e_k1, e_k2): forward-mode automatic
//! differentiation, with no difference quotient anywhere. Products drop tau^3 and eps^2.
#![allow(clippy::needless_range_loop)] // jets index their W slots and several arrays by one index

use std::ops::{Add, Mul, Neg, Sub};

/// A number along a perturbed motion (see the module notes): `v` the Taylor coefficients in
/// tau, `e[k]` those of its derivative in parameter direction k.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jet<const W: usize> {
    pub v: [f64; 3],
    pub e: [[f64; 3]; W],
}

impl<const W: usize> Jet<W> {
    pub const ZERO: Jet<W> = Jet { v: [0.0; 3], e: [[0.0; 3]; W] };

    /// A constant: no rate, no parameter in it.
    #[inline(always)]
    pub fn cst(x: f64) -> Jet<W> {
        Jet { v: [x, 0.0, 0.0], e: [[0.0; 3]; W] }
    }

    /// A coordinate along a motion: value x, rate xd, acceleration xdd, perturbed in
    /// direction k by dx[k] + dxd[k] tau (its change and the change of its rate).
    #[inline(always)]
    pub fn motion(x: f64, xd: f64, xdd: f64, dx: [f64; W], dxd: [f64; W]) -> Jet<W> {
        Jet { v: [x, xd, 0.5 * xdd], e: std::array::from_fn(|k| [dx[k], dxd[k], 0.0]) }
    }

    /// f(x) from f and its first three derivatives at v0: f0 + f1 d + f2 d^2 / 2 + f3 d^3 / 6
    /// with d = x - v0 (d^4 and beyond are below the truncation).
    #[inline(always)]
    pub fn compose(self, f: [f64; 4]) -> Jet<W> {
        let mut d = self;
        d.v[0] = 0.0;
        let d2 = d * d;
        let d3 = d2 * d;
        let mut out = d * f[1] + d2 * (0.5 * f[2]) + d3 * (f[3] / 6.0);
        out.v[0] += f[0];
        out
    }

    /// (sin x, cos x).
    #[inline(always)]
    pub fn sin_cos(self) -> (Jet<W>, Jet<W>) {
        let (s, c) = self.v[0].sin_cos();
        (self.compose([s, c, -s, -c]), self.compose([c, -s, -c, s]))
    }

    /// 1 / x.
    #[inline(always)]
    pub fn recip(self) -> Jet<W> {
        let r = 1.0 / self.v[0];
        let r2 = r * r;
        self.compose([r, -r2, 2.0 * r2 * r, -6.0 * r2 * r2])
    }

    /// sqrt(x), x > 0.
    #[inline(always)]
    pub fn sqrt(self) -> Jet<W> {
        let s = self.v[0].sqrt();
        let x = self.v[0];
        self.compose([s, 0.5 / s, -0.25 / (s * x), 0.375 / (s * x * x)])
    }

    /// atan2(y, x) on the branch of atan2(y.v0, x.v0): the angle of (x0, y0) plus the
    /// atan of the turn from it (zero at tau = eps = 0): atan z = z - z^3 / 3 + ...
    #[inline(always)]
    pub fn atan2(y: Jet<W>, x: Jet<W>) -> Jet<W> {
        let (x0, y0) = (x.v[0], y.v[0]);
        let across = x * y0;
        let z = (y * x0 - across) * (x * x0 + y * y0).recip();
        let mut out = z.compose([0.0, 1.0, 0.0, -2.0]);
        out.v[0] = y0.atan2(x0);
        out
    }

    /// The value at the step, tau = eps = 0.
    #[inline(always)]
    pub fn value(&self) -> f64 {
        self.v[0]
    }

    /// The tau^i part as a jet of its own, constant in tau: its value and its change in
    /// each direction (i = 1: the rate along the motion; i = 2: half the acceleration).
    #[inline(always)]
    pub fn coefficient(&self, i: usize) -> Jet<W> {
        Jet { v: [self.v[i], 0.0, 0.0], e: std::array::from_fn(|k| [self.e[k][i], 0.0, 0.0]) }
    }
}

impl<const W: usize> Add for Jet<W> {
    type Output = Jet<W>;
    #[inline(always)]
    fn add(mut self, o: Jet<W>) -> Jet<W> {
        for i in 0..3 {
            self.v[i] += o.v[i];
        }
        for k in 0..W {
            for i in 0..3 {
                self.e[k][i] += o.e[k][i];
            }
        }
        self
    }
}

impl<const W: usize> Sub for Jet<W> {
    type Output = Jet<W>;
    #[inline(always)]
    fn sub(mut self, o: Jet<W>) -> Jet<W> {
        for i in 0..3 {
            self.v[i] -= o.v[i];
        }
        for k in 0..W {
            for i in 0..3 {
                self.e[k][i] -= o.e[k][i];
            }
        }
        self
    }
}

impl<const W: usize> Neg for Jet<W> {
    type Output = Jet<W>;
    #[inline(always)]
    fn neg(self) -> Jet<W> {
        self * -1.0
    }
}

impl<const W: usize> Mul<f64> for Jet<W> {
    type Output = Jet<W>;
    #[inline(always)]
    fn mul(mut self, c: f64) -> Jet<W> {
        for i in 0..3 {
            self.v[i] *= c;
        }
        for k in 0..W {
            for i in 0..3 {
                self.e[k][i] *= c;
            }
        }
        self
    }
}

impl<const W: usize> Add<f64> for Jet<W> {
    type Output = Jet<W>;
    #[inline(always)]
    fn add(mut self, c: f64) -> Jet<W> {
        self.v[0] += c;
        self
    }
}

impl<const W: usize> Sub<f64> for Jet<W> {
    type Output = Jet<W>;
    #[inline(always)]
    fn sub(mut self, c: f64) -> Jet<W> {
        self.v[0] -= c;
        self
    }
}

/// Truncated product of two polynomials of degree 2 in tau.
#[inline(always)]
fn times(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] * b[0], a[0] * b[1] + a[1] * b[0], a[0] * b[2] + a[1] * b[1] + a[2] * b[0]]
}

impl<const W: usize> Mul for Jet<W> {
    type Output = Jet<W>;
    #[inline(always)]
    fn mul(self, o: Jet<W>) -> Jet<W> {
        let mut e = [[0.0; 3]; W];
        for k in 0..W {
            let (x, y) = (times(self.v, o.e[k]), times(self.e[k], o.v));
            e[k] = [x[0] + y[0], x[1] + y[1], x[2] + y[2]];
        }
        Jet { v: times(self.v, o.v), e }
    }
}

/// A point or vector: two jets.
pub type Vec2<const W: usize> = [Jet<W>; 2];

#[inline(always)]
pub fn dot<const W: usize>(a: Vec2<W>, b: Vec2<W>) -> Jet<W> {
    a[0] * b[0] + a[1] * b[1]
}

#[inline(always)]
pub fn cross<const W: usize>(a: Vec2<W>, b: Vec2<W>) -> Jet<W> {
    a[0] * b[1] - a[1] * b[0]
}

#[inline(always)]
pub fn sub<const W: usize>(a: Vec2<W>, b: Vec2<W>) -> Vec2<W> {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline(always)]
pub fn perp<const W: usize>(a: Vec2<W>) -> Vec2<W> {
    [-a[1], a[0]]
}

/// A body's perturbed motion as jets: origin, angle, cos and sin. The ground is constant.
#[derive(Debug, Clone, Copy)]
pub struct JetFrame<const W: usize> {
    pub r: Vec2<W>,
    pub theta: Jet<W>,
    pub c: Jet<W>,
    pub s: Jet<W>,
}

impl<const W: usize> JetFrame<W> {
    pub fn ground() -> JetFrame<W> {
        JetFrame { r: [Jet::ZERO; 2], theta: Jet::ZERO, c: Jet::cst(1.0), s: Jet::ZERO }
    }

    /// The frame of the coordinates (x, y, theta) moving as `motion` (per coordinate: the
    /// value, rate and acceleration) and perturbed as `dq`, `dqd` (per coordinate, per
    /// direction).
    pub fn new(x: [Jet<W>; 3]) -> JetFrame<W> {
        let (s, c) = x[2].v[0].sin_cos();
        JetFrame::with_cos_sin(x, c, s)
    }

    /// `new` with cos and sin of the angle's value already known.
    #[inline(always)]
    pub fn with_cos_sin(x: [Jet<W>; 3], c: f64, s: f64) -> JetFrame<W> {
        JetFrame {
            r: [x[0], x[1]],
            theta: x[2],
            c: x[2].compose([c, -s, -c, s]),
            s: x[2].compose([s, c, -s, -c]),
        }
    }

    /// A(theta) u.
    #[inline(always)]
    pub fn rot(&self, u: Vec2<W>) -> Vec2<W> {
        [self.c * u[0] - self.s * u[1], self.s * u[0] + self.c * u[1]]
    }

    /// R + A(theta) u.
    #[inline(always)]
    pub fn point(&self, u: Vec2<W>) -> Vec2<W> {
        let p = self.rot(u);
        [self.r[0] + p[0], self.r[1] + p[1]]
    }
}

/// A jet vector from the parameters p[i], p[i + 1].
#[inline(always)]
pub fn pair<const W: usize>(p: &[Jet<W>], i: usize) -> Vec2<W> {
    [p[i], p[i + 1]]
}

/// A constant vector as jets.
#[inline(always)]
pub fn cst2<const W: usize>(u: [f64; 2]) -> Vec2<W> {
    [Jet::cst(u[0]), Jet::cst(u[1])]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Jet<1>, b: Jet<1>, what: &str) {
        for i in 0..3 {
            assert!((a.v[i] - b.v[i]).abs() < 1e-14, "{what} v{i}: {:?} vs {:?}", a, b);
            assert!((a.e[0][i] - b.e[0][i]).abs() < 1e-14, "{what} e{i}: {:?} vs {:?}", a, b);
        }
    }

    /// Every coefficient, through identities that hold exactly in truncated arithmetic
    /// (a product of jets is the jet of the product); the first-order ones against
    /// central differences too.
    #[test]
    fn elementary_functions_satisfy_their_identities() {
        let x = Jet { v: [0.7, 0.3, -0.2], e: [[0.5, 0.1, 0.05]] };
        let y = Jet { v: [-0.4, 0.2, 0.05], e: [[-0.3, 0.25, -0.1]] };
        let one = Jet::cst(1.0);
        let (s, c) = x.sin_cos();
        close(s * s + c * c, one, "sin^2 + cos^2");
        close(x * x.recip(), one, "x / x");
        close(x.sqrt() * x.sqrt(), x, "sqrt^2");
        // theta = atan2(y, x): cos(theta) y - sin(theta) x = 0, and theta's value
        let theta = Jet::atan2(y, x);
        let (st, ct) = theta.sin_cos();
        close(ct * y - st * x, Jet::ZERO, "atan2");
        assert_eq!(theta.v[0], (-0.4f64).atan2(0.7));
        // the chain rule in compose: sin(x)' = cos(x) x' (first order, differences)
        let h = 1e-6;
        let at = |tau: f64, eps: f64| {
            x.v[0]
                + x.v[1] * tau
                + x.v[2] * tau * tau
                + eps * (x.e[0][0] + x.e[0][1] * tau + x.e[0][2] * tau * tau)
        };
        let d_tau = (at(h, 0.0).sin() - at(-h, 0.0).sin()) / (2.0 * h);
        let d_eps = (at(0.0, h).sin() - at(0.0, -h).sin()) / (2.0 * h);
        assert!((s.v[1] - d_tau).abs() < 1e-9 && (s.e[0][0] - d_eps).abs() < 1e-9);
    }
}

//! An input: a body pinned to a known body (or the ground) and turned by an angle driver.
//! Its angle is the driver's value (theta = theta_base + sign f(t)), its origin follows
//! from the pin: one angle, no equations.

use super::{body_qdd, moved, pair, point_acc, seed_of, set_acc, set_body, set_rates, set_tangent, side};
use super::{Miss, Numbers, Seed};
use crate::assembly::turned;
use crate::data::Data;
use crate::joints::{perp, sub, Constraint, ConstraintKind};
use crate::model::Model;
use crate::structure::Group;

#[derive(Debug, Clone)]
pub struct Crank {
    pub body: usize,
    /// the driver (index into model.constraints)
    pub driver: usize,
    /// theta = theta_base + sign f(t)
    base: Option<usize>,
    sign: f64,
    /// the pin: the known side and the pin in its frame, the pin in the body's frame
    known: Option<usize>,
    u_known: [f64; 2],
    u_body: [f64; 2],
    /// the pin (constraint index) and where u_known and u_body start in its numbers
    pin: (usize, usize, usize),
}

impl Crank {
    pub fn new(model: &Model, g: &Group) -> Option<Crank> {
        if g.bodies.len() != 1 || g.constraints.len() != 2 {
            return None;
        }
        let body = g.bodies[0];
        let mut driver = None;
        let mut pin = None;
        for &k in &g.constraints {
            let c = &model.constraints[k];
            match &c.kind {
                ConstraintKind::AngleDriver(_) if c.body_b == Some(body) && c.body_a.is_none() => {
                    driver = Some((k, None, 1.0))
                }
                ConstraintKind::RelativeAngleDriver(_) if c.body_b == Some(body) => {
                    driver = Some((k, c.body_a, 1.0))
                }
                ConstraintKind::RelativeAngleDriver(_) if c.body_a == Some(body) => {
                    driver = Some((k, c.body_b, -1.0))
                }
                // a revolute's numbers: u_a at 0, 1 and u_b at 2, 3
                ConstraintKind::Revolute(j) if c.body_b == Some(body) => {
                    pin = Some((c.body_a, j.u_a, j.u_b, (k, 0, 2)))
                }
                ConstraintKind::Revolute(j) if c.body_a == Some(body) => {
                    pin = Some((c.body_b, j.u_b, j.u_a, (k, 2, 0)))
                }
                _ => return None,
            }
        }
        let (driver, base, sign) = driver?;
        let (known, u_known, u_body, pin) = pin?;
        Some(Crank { body, driver, base, sign, known, u_known, u_body, pin })
    }

    /// Solves the body; returns (closeness 1, pin residual).
    #[inline]
    pub fn solve(&self, model: &Model, data: &mut Data, t: f64, derivatives: u8) -> Result<(f64, f64), Miss> {
        let Some(law) = model.constraints[self.driver].kind.law() else { return Err(Miss::Failed) };
        let f = law.eval(t);
        // a law outside its domain: the general path names it (value, nu or gamma)
        if !f[..=derivatives.min(2) as usize].iter().all(|v| v.is_finite()) {
            return Err(Miss::Failed);
        }
        let b = self.body;
        let base = side(data, self.base);
        let theta = base.theta + self.sign * f[0];
        let (c, s) = turned(theta, &mut data.frame_base[b]);
        let k = side(data, self.known);
        let p = k.point(self.u_known);
        let arm = [c * self.u_body[0] - s * self.u_body[1], s * self.u_body[0] + c * self.u_body[1]];
        let r = sub(p, arm);
        set_body(data, b, r, theta, c, s);
        let residual = {
            let back = data.frames[b].point(self.u_body);
            (back[0] - p[0]).abs().max((back[1] - p[1]).abs())
        };
        if derivatives >= 1 {
            let thetad = base.thetad + self.sign * f[1];
            let vp = k.point_velocity(self.u_known);
            let ba = perp(arm);
            set_rates(data, b, [vp[0] - ba[0] * thetad, vp[1] - ba[1] * thetad], thetad);
            if derivatives >= 2 {
                let base_qdd = body_qdd(data, self.base);
                let thetadd = base_qdd[2] + self.sign * f[2];
                let ap = point_acc(&k, body_qdd(data, self.known), sub(p, k.r));
                // the pin's acceleration seen from the body: a_p = Rdd + thetadd B u - thetad^2 A u
                let own = point_acc(&data.frames[b], [0.0, 0.0, thetadd], arm);
                set_acc(data, b, [ap[0] - own[0], ap[1] - own[1]], thetadd);
            }
        }
        Ok((1.0, residual))
    }

    /// Its numbers: u_known in slots 0, 1, u_body in 2, 3; the driver's are its law's.
    pub fn numbers(&self) -> Numbers {
        let (c, known, own) = self.pin;
        Numbers {
            slots: vec![(c, known, 0), (c, known + 1, 1), (c, own, 2), (c, own + 1, 3)],
            law: Some(self.driver),
        }
    }

    /// dq/dp of the body (`super::tangents`), `solve` differentiated: theta = theta_base +
    /// sign f(t; p) gives dtheta = dtheta_base + sign df/dp, and R = P - A(theta) u_body
    /// with P = R_k + A_k u_known gives dR = dP - perp(A u_body) dtheta - A du_body.
    #[inline]
    pub fn tangents(&self, model: &Model, data: &Data, t: f64, seeds: &[Seed], s: &mut [f64], n: usize) {
        let law = model.constraints[self.driver].kind.law();
        let k = side(data, self.known);
        let f = &data.frames[self.body];
        let (rk, arm) = (k.rot(self.u_known), f.rot(self.u_body));
        let mut at = 0;
        for j in 0..n {
            let (mut dp, _) = moved(s, n, self.known, rk, j);
            let (_, mut dth) = moved(s, n, self.base, [0.0; 2], j);
            let mut du = [0.0; 2];
            if let Some(seed) = seed_of(seeds, &mut at, j) {
                let dk = k.rot(pair(&seed.slots, 0));
                dp = [dp[0] + dk[0], dp[1] + dk[1]];
                du = f.rot(pair(&seed.slots, 2));
                if let Some(law) = law {
                    for &(i, w) in &seed.law {
                        dth += self.sign * w * law.param_derivative(i, t)[0];
                    }
                }
            }
            set_tangent(
                s,
                n,
                self.body,
                j,
                [dp[0] + arm[1] * dth - du[0], dp[1] - arm[0] * dth - du[1]],
                dth,
            );
        }
    }
}

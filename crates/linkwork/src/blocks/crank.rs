//! An input: a body pinned to a known body (or the ground) and turned by an angle driver.
//! Its angle is the driver's value (theta = theta_base + sign f(t)), its origin follows
//! from the pin: one angle, no equations.

use super::Miss;
use super::{body_qdd, point_acc, set_acc, set_body, set_rates, side};
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
                ConstraintKind::Revolute(j) if c.body_b == Some(body) => pin = Some((c.body_a, j.u_a, j.u_b)),
                ConstraintKind::Revolute(j) if c.body_a == Some(body) => pin = Some((c.body_b, j.u_b, j.u_a)),
                _ => return None,
            }
        }
        let (driver, base, sign) = driver?;
        let (known, u_known, u_body) = pin?;
        Some(Crank { body, driver, base, sign, known, u_known, u_body })
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
}

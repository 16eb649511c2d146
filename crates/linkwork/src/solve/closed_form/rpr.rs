//! The RPR dyad: two bodies on a prismatic joint (the line fixed in body L = the joint's
//! side a, the sliding point in body S = side b, theta_S = theta_L + theta0), each pinned
//! to a known body at its outer pin (P_L, P_S). The inverted slider-crank's block and
//! rocker. With D = P_S - P_L and v = A(theta_L) e_a the line's direction, the line's
//! offset row is cross(v, D) + k = 0, k = cross(e_a, A(theta0)(u_b - u_S) - (u_a - u_L))
//! a constant of the dyad: v is D turned by the angle whose sine is -k/|D| (two
//! directions, one per branch: the sign of v . D). Velocities and accelerations: that row
//! differentiated, one unknown rate shared by both bodies.
//!
//! The same with the slider massless: a pinned body whose slot (a point-on-line joint's
//! line) runs through a known point P_S, the lever of a quick-return.

use super::{body_qdd, pinned_accelerations, pinned_rates, point_acc, set_body, side, StepMiss};
use crate::constraints::{cross, dot, kinds::ConstraintKind, perp, sub, Frame};
use crate::math::angle::angle_of;
use crate::model::data::Data;
use crate::model::plan::{Pin, Rpr};
use crate::model::structure::Group;
use crate::model::Model;

impl Pin {
    /// Reads the pin `k` (a revolute) holding `body`.
    fn new(model: &Model, body: usize, k: usize) -> Option<Pin> {
        let c = &model.constraints[k];
        let ConstraintKind::Revolute(j) = &c.kind else { return None };
        if c.body_b == Some(body) {
            Some(Pin { body, known: c.body_a, u_known: j.u_a, u_body: j.u_b })
        } else if c.body_a == Some(body) {
            Some(Pin { body, known: c.body_b, u_known: j.u_b, u_body: j.u_a })
        } else {
            None
        }
    }

    /// The known frame and the pin's world position there.
    #[inline(always)]
    fn outer(&self, data: &Data) -> (Frame, [f64; 2]) {
        let k = side(data, self.known);
        let p = k.point(self.u_known);
        (k, p)
    }

    /// The body's origin with its pin at p and cos, sin of its angle.
    #[inline(always)]
    fn origin(&self, p: [f64; 2], c: f64, s: f64) -> [f64; 2] {
        let u = self.u_body;
        [p[0] - (c * u[0] - s * u[1]), p[1] - (s * u[0] + c * u[1])]
    }
}

impl Rpr {
    pub fn new(model: &Model, g: &Group) -> Option<Rpr> {
        if g.bodies.len() != 2 || g.constraints.len() != 3 {
            return None;
        }
        let inside = |b: Option<usize>| b.is_some_and(|b| g.bodies.contains(&b));
        let (mut prismatic, mut pins) = (None, Vec::new());
        for &k in &g.constraints {
            let c = &model.constraints[k];
            match &c.kind {
                ConstraintKind::Prismatic(p) if inside(c.body_a) && inside(c.body_b) => {
                    prismatic = Some((c.body_a?, c.body_b?, p.clone()))
                }
                ConstraintKind::Revolute(_) if inside(c.body_a) != inside(c.body_b) => pins.push(k),
                _ => return None,
            }
        }
        let (a, b, p) = prismatic?;
        if a == b || pins.len() != 2 {
            return None;
        }
        let holder = |k: usize| {
            let c = &model.constraints[k];
            if inside(c.body_a) {
                c.body_a
            } else {
                c.body_b
            }
        };
        let (k_line, k_slider) = match (holder(pins[0])?, holder(pins[1])?) {
            (x, y) if x == a && y == b => (pins[0], pins[1]),
            (x, y) if x == b && y == a => (pins[1], pins[0]),
            _ => return None,
        };
        let line = Pin::new(model, a, k_line)?;
        let slider = Pin::new(model, b, k_slider)?;
        let (s0, c0) = p.theta0.sin_cos();
        let d = sub(p.u_b, slider.u_body);
        let w = sub([c0 * d[0] - s0 * d[1], s0 * d[0] + c0 * d[1]], sub(p.u_a, line.u_body));
        let k = cross(p.e_a, w);
        let point = (slider.known, slider.u_known);
        Some(Rpr { line, point, slider: Some(slider), e_a: p.e_a, theta0: p.theta0, c0, s0, k })
    }

    /// A pinned body whose slot runs through a known point: a "one body" group of a
    /// revolute to a known body and a point-on-line joint whose line is in the body.
    pub fn slot(model: &Model, g: &Group) -> Option<Rpr> {
        if g.bodies.len() != 1 || g.constraints.len() != 2 {
            return None;
        }
        let body = g.bodies[0];
        let (mut pin, mut slot) = (None, None);
        for &k in &g.constraints {
            let c = &model.constraints[k];
            match &c.kind {
                ConstraintKind::Revolute(_) => pin = Pin::new(model, body, k),
                // the line in the body (side b), the point on the known side a
                ConstraintKind::PointOnLine(j) if c.body_b == Some(body) && c.body_a != Some(body) => {
                    slot = Some((c.body_a, j.clone()))
                }
                _ => return None,
            }
        }
        let (line, (known, j)) = (pin?, slot?);
        // n . (K - r_b(u_b)) - offset = 0, r_b(u_b) = P_L + A (u_b - u_L), n = A perp(e_b)
        let k = -cross(j.e_b, sub(j.u_b, line.u_body)) - j.offset;
        Some(Rpr { line, point: (known, j.u_a), slider: None, e_a: j.e_b, theta0: 0.0, c0: 1.0, s0: 0.0, k })
    }

    /// Both bodies on the branch `sign` (of v . D); returns (closeness, residual).
    #[inline]
    pub fn solve(&self, data: &mut Data, sign: f64, derivatives: u8) -> Result<(f64, f64), StepMiss> {
        let (kl, pl) = self.line.outer(data);
        let (ks, ps) = self.point(data);
        let d = sub(ps, pl);
        let dd = dot(d, d);
        let m2 = dd - self.k * self.k;
        if m2.is_nan() || m2 < 0.0 || dd <= 0.0 {
            return Err(StepMiss::NoAssembly);
        }
        let m = sign * m2.sqrt();
        // v: D turned by the angle whose cosine is m / |D| and sine -k / |D|, made unit
        let inv_dd = 1.0 / dd;
        let v = [(m * d[0] - self.k * d[1]) * inv_dd, (self.k * d[0] + m * d[1]) * inv_dd];
        // the rotation taking e_a to v: body L's angle
        let (c, s) = (dot(self.e_a, v), cross(self.e_a, v));
        let theta = angle_of(c, s, data.q[3 * self.line.body + 2], &mut data.frame_base[self.line.body]);
        set_body(data, self.line.body, self.line.origin(pl, c, s), theta, c, s);
        if let Some(slider) = &self.slider {
            let (cs, ss) = (c * self.c0 - s * self.s0, s * self.c0 + c * self.s0);
            set_body(data, slider.body, slider.origin(ps, cs, ss), theta + self.theta0, cs, ss);
        }
        // the line's offset row at the solution
        let residual = (cross(v, d) + self.k).abs();
        let closeness = m.abs() * inv_dd.sqrt();
        if derivatives >= 1 {
            let (vl, vs) = (kl.point_velocity(self.line.u_known), ks.point_velocity(self.point.1));
            let d_dot = sub(vs, vl);
            let along = dot(v, d);
            let w = cross(v, d_dot) / along;
            pinned_rates(data, self.line.body, pl, vl, w);
            if let Some(slider) = &self.slider {
                pinned_rates(data, slider.body, ps, vs, w);
            }
            if derivatives >= 2 {
                let al = point_acc(&kl, body_qdd(data, self.line.known), sub(pl, kl.r));
                let as_ = point_acc(&ks, body_qdd(data, self.point.0), sub(ps, ks.r));
                let d_ddot = sub(as_, al);
                let alpha = (cross(v, d_ddot) - 2.0 * w * dot(v, d_dot) + w * w * self.k) / along;
                pinned_accelerations(data, self.line.body, pl, al, w, alpha);
                if let Some(slider) = &self.slider {
                    pinned_accelerations(data, slider.body, ps, as_, w, alpha);
                }
            }
        }
        Ok((closeness, residual))
    }

    /// P_S's known frame and world position.
    #[inline(always)]
    fn point(&self, data: &Data) -> (Frame, [f64; 2]) {
        let k = side(data, self.point.0);
        let p = k.point(self.point.1);
        (k, p)
    }

    /// The branch sign, closeness and its rate (with `rates`, else 0) of the configuration
    /// in data (frames current).
    pub fn branch(&self, data: &Data, rates: bool) -> (f64, f64, f64) {
        let (kl, pl) = self.line.outer(data);
        let (ks, ps) = self.point(data);
        let d = sub(ps, pl);
        let v = data.frames[self.line.body].rot(self.e_a);
        let along = dot(v, d);
        let sign = if along < 0.0 { -1.0 } else { 1.0 };
        let norm = dot(d, d).sqrt();
        let closeness = along.abs() / norm;
        let rate = if rates {
            // d/dt (v . D / |D|), v turning at the body's rate
            let w = data.frames[self.line.body].thetad;
            let d_dot = sub(ks.point_velocity(self.point.1), kl.point_velocity(self.line.u_known));
            let along_dot = w * dot(perp(v), d) + dot(v, d_dot);
            sign * (along_dot / norm - along * dot(d, d_dot) / (norm * norm * norm))
        } else {
            0.0
        };
        (sign, closeness, rate)
    }
}

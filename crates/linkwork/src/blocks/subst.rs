//! A body whose angle one row gives outright and whose position a pin then gives: the
//! partner of a gear or belt with fixed centres, a linear coupling of angles, a fixed
//! orientation, a body fixed to a known one. The angle row is affine in the body's angle
//! with a constant slope alpha (its Jacobian in the body is [0, 0, alpha]), so one
//! evaluation of the joint's own row gives theta exactly (theta - phi / alpha), its rate
//! and acceleration by the same division: substitutions, not equations.

use super::{body_qdd, point_acc, set_acc, set_body, set_rates, side, Miss};
use crate::assembly::turned;
use crate::data::Data;
use crate::joints::{perp, sub, Constraint, ConstraintKind, Rows, MAX_ROWS};
use crate::model::Model;
use crate::structure::Group;

#[derive(Debug, Clone)]
pub struct Subst {
    body: usize,
    /// the angle row: its constraint, the row, whether the body is the constraint's side b
    constraint: usize,
    row: usize,
    body_is_b: bool,
    /// the pin (a revolute, or a fixed joint's point): the known side and the pin in its
    /// frame, the pin in the body's frame
    known: Option<usize>,
    u_known: [f64; 2],
    u_body: [f64; 2],
}

/// Whether a constraint's angle row is affine in each side's angle with a constant slope
/// and free of the sides' positions (on the side `b` or a): the substitutions' rows.
fn affine_angle_row(kind: &ConstraintKind, body_is_b: bool) -> Option<usize> {
    match kind {
        ConstraintKind::FixedOrientation(_) => Some(0),
        ConstraintKind::Fixed(_) => Some(2),
        ConstraintKind::Gear(g) if g.mesh.is_none() => Some(0),
        ConstraintKind::Belt(b) if b.0.mesh.is_none() => Some(0),
        ConstraintKind::LinearCoupling(c) => {
            let own = if body_is_b { c.c_b } else { c.c_a };
            (own[0] == 0.0 && own[1] == 0.0 && own[2] != 0.0).then_some(0)
        }
        _ => None,
    }
}

impl Subst {
    pub fn new(model: &Model, g: &Group) -> Option<Subst> {
        if g.bodies.len() != 1 {
            return None;
        }
        let body = g.bodies[0];
        let (mut angle, mut pin) = (None, None);
        for &k in &g.constraints {
            let c = &model.constraints[k];
            let body_is_b = c.body_b == Some(body);
            if !body_is_b && c.body_a != Some(body) {
                return None;
            }
            let other = if body_is_b { c.body_a } else { c.body_b };
            match &c.kind {
                ConstraintKind::Revolute(j) if pin.is_none() => {
                    pin = Some(if body_is_b { (other, j.u_a, j.u_b) } else { (other, j.u_b, j.u_a) })
                }
                ConstraintKind::Fixed(f) if pin.is_none() && angle.is_none() => {
                    // its point u_a of side a is side b's origin
                    pin = Some(if body_is_b { (other, f.u_a, [0.0; 2]) } else { (other, [0.0; 2], f.u_a) });
                    angle = Some((k, 2, body_is_b));
                }
                kind => match affine_angle_row(kind, body_is_b) {
                    Some(row) if angle.is_none() && kind.n_rows() == 1 => angle = Some((k, row, body_is_b)),
                    _ => return None,
                },
            }
        }
        let ((constraint, row, body_is_b), (known, u_known, u_body)) = (angle?, pin?);
        Some(Subst { body, constraint, row, body_is_b, known, u_known, u_body })
    }

    /// The angle row at the frames in data: (phi, slope alpha, the known side's Jacobian,
    /// d phi / d s and the extra coordinate's column).
    #[inline(always)]
    fn angle_row(&self, model: &Model, data: &Data, t: f64) -> (f64, f64, [f64; 3], f64) {
        let c = &model.constraints[self.constraint];
        let f = |b: Option<usize>| side(data, b);
        let mut rows = Rows::default();
        c.kind.position(&f(c.body_a), &f(c.body_b), &c.extra(&data.q, &data.qd), t, &mut rows);
        let (own, other) = if self.body_is_b {
            (rows.jac_b[self.row], rows.jac_a[self.row])
        } else {
            (rows.jac_a[self.row], rows.jac_b[self.row])
        };
        (rows.phi[self.row], own[2], other, rows.jac_s[self.row])
    }

    /// The known side's rates (or accelerations) dotted with its Jacobian row, and the
    /// extra coordinate's.
    #[inline(always)]
    fn known_part(&self, model: &Model, v: &[f64], jac: [f64; 3], jac_s: f64) -> f64 {
        let c = &model.constraints[self.constraint];
        let other = if self.body_is_b { c.body_a } else { c.body_b };
        let mut sum = match other {
            Some(o) => jac[0] * v[3 * o] + jac[1] * v[3 * o + 1] + jac[2] * v[3 * o + 2],
            None => 0.0,
        };
        if let Some(e) = c.extra {
            sum += jac_s * v[e];
        }
        sum
    }

    /// Solves the body; returns (closeness 1, the angle row's residual).
    #[inline]
    pub fn solve(&self, model: &Model, data: &mut Data, t: f64, derivatives: u8) -> Result<(f64, f64), Miss> {
        let b = self.body;
        let (phi, alpha, jac, jac_s) = self.angle_row(model, data, t);
        if alpha == 0.0 || !phi.is_finite() {
            return Err(Miss::Failed);
        }
        // from the angle phi was evaluated at (the frame's: q may hold a prediction)
        let theta = data.frames[b].theta - phi / alpha;
        let (c, s) = turned(theta, &mut data.frame_base[b]);
        let k = side(data, self.known);
        let p = k.point(self.u_known);
        let arm = [c * self.u_body[0] - s * self.u_body[1], s * self.u_body[0] + c * self.u_body[1]];
        set_body(data, b, sub(p, arm), theta, c, s);
        // the row again at the solution: round-off for an affine row
        let residual = self.angle_row(model, data, t).0.abs();
        if derivatives >= 1 {
            let mut nu = [0.0; MAX_ROWS];
            model.constraints[self.constraint].kind.nu(t, &mut nu);
            let thetad = (nu[self.row] - self.known_part(model, &data.qd, jac, jac_s)) / alpha;
            let vp = k.point_velocity(self.u_known);
            let ba = perp(arm);
            set_rates(data, b, [vp[0] - ba[0] * thetad, vp[1] - ba[1] * thetad], thetad);
            if derivatives >= 2 {
                let c = &model.constraints[self.constraint];
                let mut gamma = [0.0; MAX_ROWS];
                let f = |x: Option<usize>| side(data, x);
                c.kind.gamma(&f(c.body_a), &f(c.body_b), &c.extra(&data.q, &data.qd), t, &mut gamma);
                let thetadd = (gamma[self.row] - self.known_part(model, &data.qdd, jac, jac_s)) / alpha;
                let ap = point_acc(&k, body_qdd(data, self.known), sub(p, k.r));
                let own = point_acc(&data.frames[b], [0.0, 0.0, thetadd], arm);
                set_acc(data, b, [ap[0] - own[0], ap[1] - own[1]], thetadd);
            }
        }
        Ok((1.0, residual))
    }
}

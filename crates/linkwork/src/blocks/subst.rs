//! A body that its joints give outright, one coordinate after another: one row fixes its
//! angle and is affine in it with a constant slope (a gear or belt partner with fixed
//! centres, a linear coupling of angles, a fixed orientation, a weld's or a prismatic
//! joint's angle row, an angle driver), and two rows are affine in its x, y once the
//! angle is known (a pin, a weld's point, a slot or a slide's line, a rack's mesh, a
//! coordinate or translation driver, a linear coupling of positions). Each is solved from
//! the joints' own rows: theta - phi / alpha, then (x, y) - J^-1 phi with J the 2 x 2 of
//! the two rows in x, y, exact for such rows; rates and accelerations by the same two
//! solves. Substitutions, not equations.

use nalgebra::{Matrix2, Vector2};

use super::{set_acc, set_body, set_rates, side, Miss, NEAR_SINGULAR};
use crate::assembly::turned;
use crate::data::Data;
use crate::joints::{Constraint, ConstraintKind, Rows, MAX_ROWS};
use crate::model::Model;
use crate::structure::Group;

/// What a row is to the body: its angle's, or one of its position's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    Angle,
    Position,
}

/// The role of row `row` of a constraint for the body on side b (`body_is_b`) or a, for
/// the joints whose rows have one (None: the row is neither, and the group is not a
/// substitution).
fn role(kind: &ConstraintKind, row: usize, body_is_b: bool) -> Option<Role> {
    use ConstraintKind as K;
    use Role::{Angle, Position};
    match (kind, row) {
        (K::Revolute(_), _) | (K::Fixed(_), 0 | 1) | (K::Prismatic(_), 1) => Some(Position),
        (K::PointOnLine(_) | K::RackPinion(_) | K::TranslationDriver(_) | K::CoordinateDriver(_), 0) => {
            Some(Position)
        }
        (K::Fixed(_), 2) | (K::Prismatic(_), 0) | (K::FixedOrientation(_), 0) => Some(Angle),
        (K::AngleDriver(_) | K::RelativeAngleDriver(_), 0) => Some(Angle),
        (K::Gear(g), 0) if g.mesh.is_none() => Some(Angle),
        (K::Belt(b), 0) if b.0.mesh.is_none() => Some(Angle),
        (K::LinearCoupling(c), 0) => {
            let own = if body_is_b { c.c_b } else { c.c_a };
            if own[0] != 0.0 || own[1] != 0.0 {
                Some(Position)
            } else {
                (own[2] != 0.0).then_some(Angle)
            }
        }
        _ => None,
    }
}

#[derive(Debug, Clone)]
pub struct Subst {
    body: usize,
    /// the group's constraints: (index, the body is its side b)
    constraints: Vec<(usize, bool)>,
    /// the angle row and the two position rows: (index into `constraints`, row)
    angle: (usize, usize),
    position: [(usize, usize); 2],
}

impl Subst {
    pub fn new(model: &Model, g: &Group) -> Option<Subst> {
        if g.bodies.len() != 1 {
            return None;
        }
        let body = g.bodies[0];
        let (mut constraints, mut angle, mut position) = (Vec::new(), Vec::new(), Vec::new());
        for &k in &g.constraints {
            let c = &model.constraints[k];
            let body_is_b = c.body_b == Some(body);
            if c.body_a == c.body_b || (!body_is_b && c.body_a != Some(body)) {
                return None;
            }
            for row in 0..c.kind.n_rows() {
                match role(&c.kind, row, body_is_b)? {
                    Role::Angle => angle.push((constraints.len(), row)),
                    Role::Position => position.push((constraints.len(), row)),
                }
            }
            constraints.push((k, body_is_b));
        }
        if angle.len() != 1 || position.len() != 2 {
            return None;
        }
        Some(Subst { body, constraints, angle: angle[0], position: [position[0], position[1]] })
    }

    /// Every constraint's rows at the frames in data.
    #[inline(always)]
    fn rows(&self, model: &Model, data: &Data, t: f64, out: &mut [Rows; 3]) {
        for (o, &(k, _)) in out.iter_mut().zip(&self.constraints) {
            let c = &model.constraints[k];
            let f = |b: Option<usize>| side(data, b);
            c.kind.position(&f(c.body_a), &f(c.body_b), &c.extra(&data.q, &data.qd), t, o);
        }
    }

    /// Row (i, r): its value, its Jacobian in the body's (x, y, theta), and the rest of
    /// phi_q v (the known side's and the extra coordinate's columns) for v = qd or qdd.
    #[inline(always)]
    fn row(
        &self,
        model: &Model,
        rows: &[Rows; 3],
        (i, r): (usize, usize),
        v: &[f64],
    ) -> (f64, [f64; 3], f64) {
        let (k, body_is_b) = self.constraints[i];
        let c = &model.constraints[k];
        let (own, other, other_body) = if body_is_b {
            (rows[i].jac_b[r], rows[i].jac_a[r], c.body_a)
        } else {
            (rows[i].jac_a[r], rows[i].jac_b[r], c.body_b)
        };
        let mut known = match other_body {
            Some(o) => other[0] * v[3 * o] + other[1] * v[3 * o + 1] + other[2] * v[3 * o + 2],
            None => 0.0,
        };
        if let Some(e) = c.extra {
            known += rows[i].jac_s[r] * v[e];
        }
        (rows[i].phi[r], own, known)
    }

    /// The right-hand sides of the constraints' velocity (nu) or acceleration (gamma) rows.
    #[inline(always)]
    fn rhs(&self, model: &Model, data: &Data, t: f64, gamma: bool) -> [[f64; MAX_ROWS]; 3] {
        let mut out = [[0.0; MAX_ROWS]; 3];
        for (o, &(k, _)) in out.iter_mut().zip(&self.constraints) {
            let c = &model.constraints[k];
            if gamma {
                let f = |b: Option<usize>| side(data, b);
                c.kind.gamma(&f(c.body_a), &f(c.body_b), &c.extra(&data.q, &data.qd), t, o);
            } else {
                c.kind.nu(t, o);
            }
        }
        out
    }

    /// The body's rates (`gamma` false: qd from nu) or accelerations (qdd from gamma)
    /// from the rows at the solution: the angle's first, then x, y by the 2 x 2.
    #[inline(always)]
    fn derivative(
        &self,
        model: &Model,
        data: &Data,
        t: f64,
        rows: &[Rows; 3],
        jac: &Matrix2<f64>,
        gamma: bool,
    ) -> Option<[f64; 3]> {
        let rhs = self.rhs(model, data, t, gamma);
        let v = if gamma { &data.qdd } else { &data.qd };
        let (_, own, known) = self.row(model, rows, self.angle, v);
        let w = (rhs[self.angle.0][self.angle.1] - known) / own[2];
        let mut b = Vector2::zeros();
        for (j, &p) in self.position.iter().enumerate() {
            let (_, own, known) = self.row(model, rows, p, v);
            b[j] = rhs[p.0][p.1] - known - own[2] * w;
        }
        let xy = jac.lu().solve(&b)?;
        Some([xy[0], xy[1], w])
    }

    /// Solves the body; returns (closeness: |sin| of the angle between the position rows'
    /// normals, the rows' largest residual).
    #[inline]
    pub fn solve(&self, model: &Model, data: &mut Data, t: f64, derivatives: u8) -> Result<(f64, f64), Miss> {
        let b = self.body;
        let mut rows = [Rows::default(); 3];
        // the angle, from the angle the row is evaluated at (q may hold a prediction)
        self.rows(model, data, t, &mut rows);
        let (phi, own, _) = self.row(model, &rows, self.angle, &data.qd);
        if own[2] == 0.0 || !phi.is_finite() {
            return Err(Miss::Failed);
        }
        let theta = data.frames[b].theta - phi / own[2];
        let (c, s) = turned(theta, &mut data.frame_base[b]);
        let r = data.frames[b].r;
        set_body(data, b, r, theta, c, s);
        // then x, y: one step of the two rows, affine in them
        self.rows(model, data, t, &mut rows);
        let mut jac = Matrix2::zeros();
        let mut phi = Vector2::zeros();
        for (j, &p) in self.position.iter().enumerate() {
            let (value, own, _) = self.row(model, &rows, p, &data.qd);
            phi[j] = value;
            jac[(j, 0)] = own[0];
            jac[(j, 1)] = own[1];
        }
        let norms = jac.row(0).norm() * jac.row(1).norm();
        let closeness = if norms > 0.0 { jac.determinant().abs() / norms } else { 0.0 };
        if closeness.is_nan() || closeness < NEAR_SINGULAR {
            return Err(Miss::NearSingular);
        }
        let step = jac.lu().solve(&phi).ok_or(Miss::NearSingular)?;
        set_body(data, b, [r[0] - step[0], r[1] - step[1]], theta, c, s);
        // the rows at the solution: their residual, and the Jacobians of the rates
        self.rows(model, data, t, &mut rows);
        let residual = [self.angle, self.position[0], self.position[1]]
            .iter()
            .fold(0.0f64, |m, &p| m.max(self.row(model, &rows, p, &data.qd).0.abs()));
        if derivatives >= 1 {
            for (j, &p) in self.position.iter().enumerate() {
                let (_, own, _) = self.row(model, &rows, p, &data.qd);
                jac[(j, 0)] = own[0];
                jac[(j, 1)] = own[1];
            }
            let qd = self.derivative(model, data, t, &rows, &jac, false).ok_or(Miss::NearSingular)?;
            set_rates(data, b, [qd[0], qd[1]], qd[2]);
            if derivatives >= 2 {
                let qdd = self.derivative(model, data, t, &rows, &jac, true).ok_or(Miss::NearSingular)?;
                set_acc(data, b, [qdd[0], qdd[1]], qdd[2]);
            }
        }
        Ok((closeness, residual))
    }
}

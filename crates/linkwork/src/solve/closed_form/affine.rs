//! Bodies that their joints give outright, one kind of coordinate after another: each
//! body's angle from a row affine in it with a constant slope (a gear or belt partner with
//! fixed centres, a linear coupling of angles, a fixed orientation, a weld's or a prismatic
//! joint's angle row, an angle driver), taken in an order where each row has one angle
//! left to give; then every x, y from the rows affine in them once the angles are known
//! (a pin, a weld's point, a slot's or a slide's line, a rack's mesh, a coordinate or
//! translation driver, a linear coupling of positions). One body (a rack, a gear) or two
//! (the PRP and RPP dyads: sliders pinned together, a slider on a pinned slide). Each is
//! solved from the joints' own rows: theta - phi / alpha, then (x, y) - J^-1 phi with J
//! the rows' Jacobian in the x, y (2 x 2 or 4 x 4, on nalgebra), exact for such rows;
//! rates and accelerations by the same solves. Substitutions, not equations.

use nalgebra::{SMatrix, SVector};

use super::{set_acc, set_body, set_rates, side, StepMiss, NEAR_SINGULAR};
use crate::constraints::{kinds::ConstraintKind, Constraint, Rows, MAX_ROWS};
use crate::math::angle::turned;
use crate::model::data::Data;
use crate::model::plan::{Affine, Member};
use crate::model::structure::Group;
use crate::model::Model;

/// The most bodies a substitution gives (its position system is 2 per body).
const MAX_BODIES: usize = 2;

/// What a row is to the group: an angle's, or a position's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    Angle,
    Position,
}

/// The role of row `row` of a constraint, for the joints whose rows have one (None: the
/// row is neither, and the group is not a substitution). `a_in`, `b_in`: which sides are
/// the group's bodies (their coefficients decide a linear coupling's role).
fn role(kind: &ConstraintKind, row: usize, a_in: bool, b_in: bool) -> Option<Role> {
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
            let sides = [(a_in, c.c_a), (b_in, c.c_b)];
            let own = sides.iter().filter(|(inside, _)| *inside).map(|(_, k)| k);
            if own.clone().any(|k| k[0] != 0.0 || k[1] != 0.0) {
                Some(Position)
            } else {
                own.clone().any(|k| k[2] != 0.0).then_some(Angle)
            }
        }
        _ => None,
    }
}

/// Rows' values and Jacobians, one per member.
type AllRows = [Rows; 3 * MAX_BODIES];
/// A row's Jacobian in each of the group's bodies' (x, y, theta).
type BodyJacs = [[f64; 3]; MAX_BODIES];
/// The position rows' Jacobian in the x, y (padded to 4 x 4), values, Jacobians in every
/// coordinate of the bodies, and known parts.
type PositionSystem = (SMatrix<f64, 4, 4>, SVector<f64, 4>, [BodyJacs; 2 * MAX_BODIES], [f64; 4]);

impl Affine {
    pub fn new(model: &Model, g: &Group) -> Option<Affine> {
        let k = g.bodies.len();
        if k == 0 || k > MAX_BODIES || g.constraints.len() > 3 * MAX_BODIES {
            return None;
        }
        let local = |b: Option<usize>| b.and_then(|b| g.bodies.iter().position(|&x| x == b));
        let (mut members, mut angle_rows, mut positions) = (Vec::new(), Vec::new(), Vec::new());
        for &ci in &g.constraints {
            let c = &model.constraints[ci];
            let m = Member { constraint: ci, side_a: local(c.body_a), side_b: local(c.body_b) };
            if m.side_a.is_none() && m.side_b.is_none() || c.body_a == c.body_b {
                return None;
            }
            for row in 0..c.kind.n_rows() {
                match role(&c.kind, row, m.side_a.is_some(), m.side_b.is_some())? {
                    Role::Angle => angle_rows.push((members.len(), row)),
                    Role::Position => positions.push((members.len(), row)),
                }
            }
            members.push(m);
        }
        if angle_rows.len() != k || positions.len() != 2 * k {
            return None;
        }
        // solving order: a row whose unknown angles are all given but one gives that one
        let mut given = vec![false; k];
        let mut angles = Vec::with_capacity(k);
        while angles.len() < k {
            let next = angle_rows.iter().enumerate().find_map(|(i, &(mi, row))| {
                let m: &Member = &members[mi];
                let open: Vec<usize> =
                    [m.side_a, m.side_b].into_iter().flatten().filter(|&b| !given[b]).collect();
                (open.len() == 1).then_some((i, mi, row, open[0]))
            });
            let (i, mi, row, body) = next?;
            angle_rows.remove(i);
            given[body] = true;
            angles.push((mi, row, body));
        }
        Some(Affine { bodies: g.bodies.clone(), members, angles, positions })
    }

    /// Every member's rows at the frames in data.
    #[inline(always)]
    fn rows(&self, model: &Model, data: &Data, t: f64, out: &mut AllRows) {
        for (o, m) in out.iter_mut().zip(&self.members) {
            let c = &model.constraints[m.constraint];
            let f = |b: Option<usize>| side(data, b);
            c.kind.position(&f(c.body_a), &f(c.body_b), &c.extra(&data.q, &data.qd), t, o);
        }
    }

    /// Row (mi, r): its value, its Jacobian in each of the group's bodies (zero where a
    /// side is not one), and the known part of phi_q v for v = qd or qdd (the columns of
    /// known bodies and of the extra coordinate).
    #[inline(always)]
    fn row(&self, model: &Model, rows: &AllRows, (mi, r): (usize, usize), v: &[f64]) -> (f64, BodyJacs, f64) {
        let m = &self.members[mi];
        let c = &model.constraints[m.constraint];
        let mut own = [[0.0; 3]; MAX_BODIES];
        let mut known = 0.0;
        for (local, body, jac) in
            [(m.side_a, c.body_a, rows[mi].jac_a[r]), (m.side_b, c.body_b, rows[mi].jac_b[r])]
        {
            match (local, body) {
                (Some(l), _) => own[l] = jac,
                (None, Some(o)) => known += jac[0] * v[3 * o] + jac[1] * v[3 * o + 1] + jac[2] * v[3 * o + 2],
                (None, None) => {}
            }
        }
        if let Some(e) = c.extra {
            known += rows[mi].jac_s[r] * v[e];
        }
        (rows[mi].phi[r], own, known)
    }

    /// The right-hand sides of the members' velocity (nu) or acceleration (gamma) rows.
    #[inline(always)]
    fn rhs(&self, model: &Model, data: &Data, t: f64, gamma: bool) -> [[f64; MAX_ROWS]; 3 * MAX_BODIES] {
        let mut out = [[0.0; MAX_ROWS]; 3 * MAX_BODIES];
        for (o, m) in out.iter_mut().zip(&self.members) {
            let c = &model.constraints[m.constraint];
            if gamma {
                let f = |b: Option<usize>| side(data, b);
                c.kind.gamma(&f(c.body_a), &f(c.body_b), &c.extra(&data.q, &data.qd), t, o);
            } else {
                c.kind.nu(t, o);
            }
        }
        out
    }

    /// The position rows' Jacobian in the bodies' x, y (2k x 2k, padded with the identity
    /// to 4 x 4 for one body) and their values.
    fn position_system(&self, model: &Model, rows: &AllRows, v: &[f64]) -> PositionSystem {
        let mut jac = SMatrix::<f64, 4, 4>::identity();
        let mut phi = SVector::<f64, 4>::zeros();
        let mut own_all = [[[0.0; 3]; MAX_BODIES]; 2 * MAX_BODIES];
        let mut known_all = [0.0; 4];
        for (j, &p) in self.positions.iter().enumerate() {
            let (value, own, known) = self.row(model, rows, p, v);
            phi[j] = value;
            for (l, o) in own.iter().enumerate().take(self.bodies.len()) {
                jac[(j, 2 * l)] = o[0];
                jac[(j, 2 * l + 1)] = o[1];
            }
            own_all[j] = own;
            known_all[j] = known;
        }
        (jac, phi, own_all, known_all)
    }

    /// Rates (`gamma` false: from nu) or accelerations (from gamma) of the bodies, from the
    /// rows at the solution: the angles in order, then every x, y at once.
    fn derivative(
        &self,
        model: &Model,
        data: &Data,
        t: f64,
        rows: &AllRows,
        lu: &nalgebra::LU<f64, nalgebra::Const<4>, nalgebra::Const<4>>,
        gamma: bool,
    ) -> Option<BodyJacs> {
        let rhs = self.rhs(model, data, t, gamma);
        let v = if gamma { &data.qdd } else { &data.qd };
        let mut out = [[0.0; 3]; MAX_BODIES];
        for &(mi, r, body) in &self.angles {
            let (_, own, known) = self.row(model, rows, (mi, r), v);
            // the angle rows have no x, y terms: the other bodies' angles given before
            let others: f64 =
                (0..self.bodies.len()).filter(|&l| l != body).map(|l| own[l][2] * out[l][2]).sum();
            out[body][2] = (rhs[mi][r] - known - others) / own[body][2];
        }
        let mut b = SVector::<f64, 4>::zeros();
        let (_, _, own_all, known_all) = self.position_system(model, rows, v);
        for (j, &(mi, r)) in self.positions.iter().enumerate() {
            let turning: f64 = (0..self.bodies.len()).map(|l| own_all[j][l][2] * out[l][2]).sum();
            b[j] = rhs[mi][r] - known_all[j] - turning;
        }
        let xy = lu.solve(&b)?;
        for (l, o) in out.iter_mut().enumerate().take(self.bodies.len()) {
            o[0] = xy[2 * l];
            o[1] = xy[2 * l + 1];
        }
        Some(out)
    }

    /// The sign of the position rows' Jacobian's det and the closeness to singular (|det|
    /// over the product of its rows' norms).
    fn conditioning(jac: &SMatrix<f64, 4, 4>) -> (f64, f64) {
        let norms: f64 = jac.row_iter().map(|r| r.norm()).product();
        let det = jac.determinant();
        let closeness = if norms > 0.0 { det.abs() / norms } else { 0.0 };
        (if det < 0.0 { -1.0 } else { 1.0 }, closeness)
    }

    /// The det sign and closeness of the configuration in data (frames current), the rate
    /// not known (0): what the sweep keeps after a general step.
    pub fn branch(&self, model: &Model, data: &Data, t: f64) -> (f64, f64, f64) {
        let mut rows = [Rows::default(); 3 * MAX_BODIES];
        self.rows(model, data, t, &mut rows);
        let (sign, closeness) = Affine::conditioning(&self.position_system(model, &rows, &data.qd).0);
        (sign, closeness, 0.0)
    }

    /// Solves the bodies, the position rows' det keeping the sign `sign` (a change is a
    /// singular configuration crossed, for the general path to locate); returns
    /// (closeness, the rows' largest residual).
    #[inline]
    pub fn solve(
        &self,
        model: &Model,
        data: &mut Data,
        t: f64,
        derivatives: u8,
        sign: f64,
    ) -> Result<(f64, f64), StepMiss> {
        let mut rows = [Rows::default(); 3 * MAX_BODIES];
        // the angles in order, each from the angle its row is evaluated at (q may hold a
        // prediction; the frames hold what the rows see)
        for &(mi, r, body) in &self.angles {
            self.rows(model, data, t, &mut rows);
            let (phi, own, _) = self.row(model, &rows, (mi, r), &data.qd);
            let alpha = own[body][2];
            if alpha == 0.0 || !phi.is_finite() {
                return Err(StepMiss::Failed);
            }
            let b = self.bodies[body];
            let theta = data.frames[b].theta - phi / alpha;
            let (c, s) = turned(theta, &mut data.frame_base[b]);
            let r0 = data.frames[b].r;
            set_body(data, b, r0, theta, c, s);
        }
        // then every x, y: one step of the position rows, affine in them
        self.rows(model, data, t, &mut rows);
        let (jac, phi, _, _) = self.position_system(model, &rows, &data.qd);
        let (det_sign, closeness) = Affine::conditioning(&jac);
        if closeness.is_nan() || closeness < NEAR_SINGULAR || det_sign != sign {
            return Err(StepMiss::NearSingular);
        }
        let step = jac.lu().solve(&phi).ok_or(StepMiss::NearSingular)?;
        for (l, &b) in self.bodies.iter().enumerate() {
            let f = data.frames[b];
            set_body(data, b, [f.r[0] - step[2 * l], f.r[1] - step[2 * l + 1]], f.theta, f.c, f.s);
        }
        // the rows at the solution: their residual, and the Jacobians of the rates
        self.rows(model, data, t, &mut rows);
        let residual = self
            .angles
            .iter()
            .map(|&(mi, r, _)| (mi, r))
            .chain(self.positions.iter().copied())
            .fold(0.0f64, |m, p| m.max(self.row(model, &rows, p, &data.qd).0.abs()));
        if derivatives >= 1 {
            let lu = self.position_system(model, &rows, &data.qd).0.lu();
            let qd = self.derivative(model, data, t, &rows, &lu, false).ok_or(StepMiss::NearSingular)?;
            for (l, &b) in self.bodies.iter().enumerate() {
                set_rates(data, b, [qd[l][0], qd[l][1]], qd[l][2]);
            }
            if derivatives >= 2 {
                let qdd = self.derivative(model, data, t, &rows, &lu, true).ok_or(StepMiss::NearSingular)?;
                for (l, &b) in self.bodies.iter().enumerate() {
                    set_acc(data, b, [qdd[l][0], qdd[l][1]], qdd[l][2]);
                }
            }
        }
        Ok((closeness, residual))
    }
}

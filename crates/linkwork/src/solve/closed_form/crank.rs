//! An input: a body pinned to a known body (or the ground) and turned by an angle driver.
//! Its angle is the driver's value (theta = theta_base + sign f(t)), its origin follows
//! from the pin: one angle, no equations.

use super::guard::{self, Travel};
use super::{add_move, body_qdd, column, point_acc, set_acc, set_body, set_rates, side, split};
use super::{NumberMove, Numbers, StepMiss};
use crate::constraints::{kinds::ConstraintKind, perp, sub, Constraint, Frame};
use crate::input::motion::MotionLaw;
use crate::math::angle::turned;
use crate::model::data::Data;
use crate::model::plan::Crank;
use crate::model::structure::Group;
use crate::model::Model;

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
        let fixed = Frame::GROUND.point(u_known);
        Some(Crank { body, driver, base, sign, known, u_known, u_body, fixed, pin })
    }

    /// Solves the body; returns (closeness 1, pin residual).
    #[inline]
    pub fn solve(
        &self,
        model: &Model,
        data: &mut Data,
        t: f64,
        derivatives: u8,
    ) -> Result<(f64, f64), StepMiss> {
        self.solve_inline(model, data, t, derivatives)
    }

    /// `solve` inlined into its caller (a sweep's step of the plan).
    #[inline(always)]
    pub(crate) fn solve_inline(
        &self,
        model: &Model,
        data: &mut Data,
        t: f64,
        derivatives: u8,
    ) -> Result<(f64, f64), StepMiss> {
        // a known side or base on the ground folded in: fixed, at rest
        match (self.known.is_some(), self.base.is_some()) {
            (true, true) => self.solve_on::<true, true>(model, data, t, derivatives),
            (true, false) => self.solve_on::<true, false>(model, data, t, derivatives),
            (false, true) => self.solve_on::<false, true>(model, data, t, derivatives),
            (false, false) => self.solve_on::<false, false>(model, data, t, derivatives),
        }
    }

    /// `solve` of positions only for a crank on the ground, with the guard's bound on its
    /// turn over a step of `h` (`guard::law_travel`) written into `travel`: (closeness 1,
    /// residual), or the miss (`NearSingular` where the driver's law has no bound). Only
    /// for a crank pinned to the ground with its angle from the ground (`closed_form::guarded`).
    #[inline(always)]
    pub fn solve_guarded(
        &self,
        model: &Model,
        data: &mut Data,
        t: f64,
        h: f64,
        travel: &mut [Travel],
    ) -> Result<(f64, f64), StepMiss> {
        if self.known.is_some() || self.base.is_some() {
            return Err(StepMiss::Failed);
        }
        // the law looked up once, for the angle and its bound
        let law = model.constraints[self.driver].kind.law().ok_or(StepMiss::Failed)?;
        let solved = self.solve_law::<false, false>(law, data, t, 0)?;
        let turn = guard::law_travel(law, h).ok_or(StepMiss::NearSingular)?;
        travel[self.body] = Travel { r: self.fixed, len: 0.0, turn };
        Ok(solved)
    }

    /// `solve` with `K`, `B`: whether the pin's known side, the angle's base is a body.
    /// The ground's pin is `fixed` and at rest (the bits `Frame::GROUND` gives).
    #[inline(always)]
    fn solve_on<const K: bool, const B: bool>(
        &self,
        model: &Model,
        data: &mut Data,
        t: f64,
        derivatives: u8,
    ) -> Result<(f64, f64), StepMiss> {
        let Some(law) = model.constraints[self.driver].kind.law() else { return Err(StepMiss::Failed) };
        self.solve_law::<K, B>(law, data, t, derivatives)
    }

    /// `solve_on` with the driver's law given.
    #[inline(always)]
    fn solve_law<const K: bool, const B: bool>(
        &self,
        law: &MotionLaw,
        data: &mut Data,
        t: f64,
        derivatives: u8,
    ) -> Result<(f64, f64), StepMiss> {
        let f = law.eval(t);
        // a law outside its domain: the general path names it (value, nu or gamma)
        if !f[..=derivatives.min(2) as usize].iter().all(|v| v.is_finite()) {
            return Err(StepMiss::Failed);
        }
        let b = self.body;
        let base = if B { side(data, self.base) } else { Frame::GROUND };
        let theta = base.theta + self.sign * f[0];
        let (c, s) = turned(theta, &mut data.frame_base[b]);
        let k = if K { side(data, self.known) } else { Frame::GROUND };
        let p = if K { k.point(self.u_known) } else { self.fixed };
        let arm = [c * self.u_body[0] - s * self.u_body[1], s * self.u_body[0] + c * self.u_body[1]];
        let r = sub(p, arm);
        let back = set_body(data, b, r, theta, c, s).point(self.u_body);
        let residual = (back[0] - p[0]).abs().max((back[1] - p[1]).abs());
        if derivatives >= 1 {
            let thetad = base.thetad + self.sign * f[1];
            let vp = if K { k.point_velocity(self.u_known) } else { [0.0; 2] };
            let ba = perp(arm);
            set_rates(data, b, [vp[0] - ba[0] * thetad, vp[1] - ba[1] * thetad], thetad);
            if derivatives >= 2 {
                let base_qdd = if B { body_qdd(data, self.base) } else { [0.0; 3] };
                let thetadd = base_qdd[2] + self.sign * f[2];
                let ap = if K { point_acc(&k, body_qdd(data, self.known), sub(p, k.r)) } else { [0.0; 2] };
                // the pin's acceleration seen from the body: a_p = Rdd + thetadd B u - thetad^2 A u
                let own = point_acc(&data.frames[b], [0.0, 0.0, thetadd], arm);
                set_acc(data, b, [ap[0] - own[0], ap[1] - own[1]], thetadd);
            }
        }
        Ok((1.0, residual))
    }

    /// Its numbers: u_known in slots 0, 1, u_body in 2, 3; the driver's are its law's, law
    /// number i in slot 4 + i.
    pub fn numbers(&self) -> Numbers {
        let (c, known, own) = self.pin;
        Numbers {
            slots: vec![(c, known, 0), (c, known + 1, 1), (c, own, 2), (c, own + 1, 3)],
            law: Some((self.driver, 4)),
        }
    }

    /// dq/dp of the body (`super::tangents`), `solve` differentiated: theta = theta_base +
    /// sign f(t; p) gives dtheta = dtheta_base + sign df/dp, and R = P - A(theta) u_body
    /// with P = R_k + A_k u_known gives dR = dP - perp(A u_body) dtheta - A du_body.
    /// `zeros`: the ground's rows (n zeros).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn tangents(
        &self,
        model: &Model,
        data: &Data,
        t: f64,
        entries: &[NumberMove],
        s: &mut [f64],
        n: usize,
        zeros: &[f64],
    ) {
        let law = model.constraints[self.driver].kind.law();
        let k = side(data, self.known);
        let f = &data.frames[self.body];
        let (rk, arm) = (k.rot(self.u_known), f.rot(self.u_body));
        // the body's move for a move dP of the pin and dtheta
        let respond = |dp: [f64; 2], dth: f64| [dp[0] + arm[1] * dth, dp[1] - arm[0] * dth, dth];
        let (mut body, _, rest) = split(s, n, self.body, None);
        // the known sides' moves, for every parameter (a side on the ground moves nothing)
        let (k_rows, b_rows) = (rest.known(self.known, zeros), rest.known(self.base, zeros));
        let [x, y, th] = &mut body;
        let (x, y, th) = (&mut x[..n], &mut y[..n], &mut th[..n]);
        match (self.known.is_some(), self.base.is_some()) {
            (true, true) => known::<true, true>(k_rows, b_rows, (rk, arm), x, y, th),
            (true, false) => known::<true, false>(k_rows, b_rows, (rk, arm), x, y, th),
            (false, true) => known::<false, true>(k_rows, b_rows, (rk, arm), x, y, th),
            // nothing moves the crank's known sides
            (false, false) => {
                for row in [x, y, th] {
                    row.fill(0.0);
                }
            }
        }
        // each parameter's own moves of the pin (u_known, u_body) and of the law
        for e in entries {
            let d = match e.slot {
                0 | 1 => respond(column(&k, e.slot), 0.0),
                2 | 3 => {
                    let c = column(f, e.slot - 2);
                    [-c[0], -c[1], 0.0]
                }
                i => respond([0.0; 2], law.map_or(0.0, |l| self.sign * l.param_derivative(i - 4, t)[0])),
            };
            add_move(&mut body, e.param, e.w, d);
        }
    }
}

/// The crank's rows for its known sides' moves (`k`: the pin's side, `b`: the angle's
/// base; `K`, `B`: whether they move, else they are the ground and are not read), every
/// parameter at once; `rk` the pin about the known side's origin, `arm` about the body's.
/// Each output row a reference of its own (an argument by itself), which the compiler then
/// knows not to overlap the others: it may take several parameters at once.
#[inline(never)]
fn known<const K: bool, const B: bool>(
    k: [&[f64]; 3],
    b: [&[f64]; 3],
    (rk, arm): ([f64; 2], [f64; 2]),
    x: &mut [f64],
    y: &mut [f64],
    th: &mut [f64],
) {
    let n = x.len();
    // rows cut to n: no bounds checks in the loop
    let ([kx, ky, kt], bt) = (k.map(|r| &r[..n]), &b[2][..n]);
    let (y, th) = (&mut y[..n], &mut th[..n]);
    for j in 0..n {
        // the terms of a side that does not move left out (a product with 0 is not 0)
        let (mut dx, mut dy, mut dth) = (0.0, 0.0, 0.0);
        if K {
            (dx, dy) = (kx[j] - rk[1] * kt[j], ky[j] + rk[0] * kt[j]);
        }
        if B {
            (dx, dy, dth) = (dx + arm[1] * bt[j], dy - arm[0] * bt[j], bt[j]);
        }
        [x[j], y[j], th[j]] = [dx, dy, dth];
    }
}

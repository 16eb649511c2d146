//! Roller follower: a roller of radius rho, centred at u_b of the follower b, rolls on the
//! cam profile c(s) fixed in the cam a. With C = R_a + A_a c(s) the contact point,
//! P = r_b(u_b) the roller centre, d = P - C and T = A_a c'(s) the profile's tangent,
//! 2 rows and one own coordinate s (where on the profile the contact is):
//!   (d . d - rho^2) / (2 rho) = 0   the centre is rho from the contact point,
//!   d . T / rho = 0                 along the profile's normal there.
//! Both are lengths. The first row's derivative in s, -d . T / rho, vanishes on the
//! solution, so the follower's motion does not depend on c''' (only s'' does).

use super::cam_follower;
use super::point_on_curve::to_local;
use crate::constraints::compile_context::{CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{dot, sub, Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::curves::Curve;
use crate::input::curves::CurveDesc;
use crate::input::description::JointDesc;
use crate::math::jet::{self, pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct RollerFollower {
    /// the cam profile in a's frame
    pub curve: Curve,
    /// the roller centre in b's frame
    pub u_b: [f64; 2],
    /// the roller radius (> 0)
    pub radius: f64,
}

impl RollerFollower {
    /// A roller checked against the profile at the starting poses: the radius is positive
    /// and the roller fits every hollow of the profile on its side (a sampled check: a
    /// roller larger than the radius of curvature there would cut into the cam, its
    /// centre's path having a cusp).
    pub fn new(curve: Curve, u_b: [f64; 2], radius: f64, a: &Frame, b: &Frame) -> Result<Self, String> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(format!("roller radius {radius} must be finite and > 0"));
        }
        let roller = RollerFollower { curve, u_b, radius };
        let s0 = roller.own_start(a, b);
        let k = roller.curve.eval(s0);
        let d = sub(to_local(a, b.point(u_b)), k.c);
        // outward normal of the profile: right of the tangent on a counter-clockwise curve
        let orient = roller.curve.orientation();
        let side = if orient * (d[0] * k.d1[1] - d[1] * k.d1[0]) >= 0.0 { 1.0 } else { -1.0 };
        for s in roller.curve.samples() {
            let kappa = roller.curve.curvature(s);
            if side * orient * kappa < 0.0 && radius * kappa.abs() > 1.0 {
                return Err(format!(
                    "roller radius {radius} exceeds the profile's radius of curvature {:.6e} at s = {s:.6}, \
                     where the profile is hollow on the roller's side: the roller cannot follow it",
                    1.0 / kappa.abs()
                ));
            }
        }
        Ok(roller)
    }
}

impl Constraint for RollerFollower {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p: Vec<(String, &mut f64)> =
            crate::constraints::xy("u_b", &mut self.u_b).into_iter().collect();
        p.push(("radius".into(), &mut self.radius));
        p
    }
    #[inline]
    fn phi_jet<const W: usize>(
        &self,
        a: &JetFrame<W>,
        b: &JetFrame<W>,
        s: Jet<W>,
        _t: f64,
        p: &[Jet<W>],
        out: &mut [Jet<W>; MAX_ROWS],
    ) {
        let (c, c1) = crate::input::curves::at_jet(&self.curve, s);
        let d = jet::sub(b.point(pair(p, 0)), a.point(c));
        let tangent = a.rot(c1);
        let inv = p[2].recip();
        out[0] = (jet::dot(d, d) - p[2] * p[2]) * (inv * 0.5);
        out[1] = jet::dot(d, tangent) * inv;
    }
    fn n_rows(&self) -> usize {
        2
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Length, RowKind::Length]
    }
    fn n_own(&self) -> usize {
        1
    }
    /// The profile point nearest the roller centre (the normal there passes through it).
    fn own_start(&self, a: &Frame, b: &Frame) -> f64 {
        self.curve.nearest(to_local(a, b.point(self.u_b)))
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, x: &Extra, _t: f64, out: &mut Rows) {
        let rho = self.radius;
        let k = self.curve.eval(x.s);
        let d = sub(b.point(self.u_b), a.point(k.c));
        let tangent = a.rot(k.d1);
        let (bc, bt, bu) = (a.rot_d(k.c), a.rot_d(k.d1), b.rot_d(self.u_b));
        out.phi[0] = (dot(d, d) - rho * rho) / (2.0 * rho);
        out.jac_a[0] = [-d[0] / rho, -d[1] / rho, -dot(d, bc) / rho];
        out.jac_b[0] = [d[0] / rho, d[1] / rho, dot(d, bu) / rho];
        out.jac_s[0] = -dot(d, tangent) / rho;
        out.phi[1] = dot(d, tangent) / rho;
        out.jac_a[1] = [-tangent[0] / rho, -tangent[1] / rho, (dot(d, bt) - dot(bc, tangent)) / rho];
        out.jac_b[1] = [tangent[0] / rho, tangent[1] / rho, dot(bu, tangent) / rho];
        out.jac_s[1] = (dot(d, a.rot(k.d2)) - dot(tangent, tangent)) / rho;
    }
    /// With dd, dq the rate of d and the velocity-squared part of its second derivative,
    /// and Td, Tq the same for T: gamma = -(dd . dd + d . dq) / rho and
    /// -(dq . T + 2 dd . Td + d . Tq) / rho, where
    /// dq = -A_b u_b thd_b^2 + A_a c thd_a^2 - 2 B_a c' thd_a sd - A_a c'' sd^2,
    /// Tq = -A_a c' thd_a^2 + 2 B_a c'' thd_a sd + A_a c''' sd^2.
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        let rho = self.radius;
        let (w, sd) = (a.thetad, x.sd);
        let k = self.curve.eval(x.s);
        let d = sub(b.point(self.u_b), a.point(k.c));
        let tangent = a.rot(k.d1);
        let (bt, at2) = (a.rot_d(k.d1), a.rot(k.d2));
        let contact_rate = a.point_velocity(k.c);
        let dd = sub(
            b.point_velocity(self.u_b),
            [contact_rate[0] + tangent[0] * sd, contact_rate[1] + tangent[1] * sd],
        );
        let (ca, cb) = (a.point_centripetal(k.c), b.point_centripetal(self.u_b));
        let dq: [f64; 2] = std::array::from_fn(|i| cb[i] - ca[i] - 2.0 * w * sd * bt[i] - sd * sd * at2[i]);
        let (bt2, at3) = (a.rot_d(k.d2), a.rot(k.d3));
        let td: [f64; 2] = std::array::from_fn(|i| w * bt[i] + sd * at2[i]);
        let tq: [f64; 2] =
            std::array::from_fn(|i| -w * w * tangent[i] + 2.0 * w * sd * bt2[i] + sd * sd * at3[i]);
        g[0] = -(dot(dd, dd) + dot(d, dq)) / rho;
        g[1] = -(dot(dq, tangent) + 2.0 * dot(dd, td) + dot(d, tq)) / rho;
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u_b
    }
}

impl Sample for RollerFollower {
    fn sample() -> Self {
        let points = vec![[0.5, 0.0], [0.2, 0.4], [-0.4, 0.3], [-0.5, -0.2], [0.1, -0.45]];
        let curve = Curve::spline(points).expect("valid spline points");
        RollerFollower { curve, u_b: [-0.1, 0.2], radius: 0.08 }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for RollerFollower {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "cam_follower",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("body_b", Body),
                ("follower", Choice(&["roller"])),
                ("at", Point(&["body_b"])),
                ("curve", Curve("body_a")),
                ("radius", Length),
            ],
        }]
    };
}

/// Compiles a cam-follower description with a roller: its radius, the contact found.
#[allow(clippy::too_many_arguments)]
fn compile(
    body_a: &str,
    body_b: &str,
    follower: &str,
    at: [f64; 2],
    curve: &CurveDesc,
    radius: Option<f64>,
    face: Option<[f64; 2]>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<RollerFollower>, String> {
    let (curve, u_b, a, b) = cam_follower::start(body_a, body_b, follower, at, curve, radius, face, cx)?;
    let frame = |b: Option<usize>| cx.pose(b).map_or(Frame::GROUND, |p| Frame::new(p, [0.0; 3]));
    let radius = radius.ok_or_else(|| "a roller follower needs a radius".to_string())?;
    Ok(Compiled::new(RollerFollower::new(curve, u_b, radius, &frame(a), &frame(b))?, a, b))
}

impl FromDescription for RollerFollower {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::CamFollower { body_a, body_b, follower, at, curve, radius, face, .. }) =
            desc
        else {
            return None;
        };
        if follower != "roller" {
            return None;
        }
        Some(compile(body_a, body_b, follower, *at, curve, *radius, *face, cx))
    }
}

//! Flat-faced follower: the face of the follower b, the line through u_b with unit normal
//! n_b (b's frame), touches the cam profile c(s) fixed in the cam a. With
//! C = R_a + A_a c(s) the contact point, n = A_b n_b, P = r_b(u_b) and T = A_a c'(s),
//! 2 rows and one own coordinate s (where on the profile the contact is):
//!   n . (C - P) = 0   the contact point is on the face line,
//!   n . T = 0         the face is tangent to the profile there.
//! Both are lengths (c' is a length per radian). The first row's derivative in s,
//! n . T, vanishes on the solution, so the follower's motion does not depend on c'''.

use super::cam_follower;
use super::point_on_curve::{to_local, to_local_dir};
use crate::constraints::compile_context::{CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{dot, perp, sub, Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::curves::Curve;
use crate::input::curves::CurveDesc;
use crate::input::description::JointDesc;
use crate::math::jet::{self, pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct FlatFollower {
    /// the cam profile in a's frame
    pub curve: Curve,
    /// a point of the face in b's frame
    pub u_b: [f64; 2],
    /// the face's unit normal in b's frame
    pub n_b: [f64; 2],
}

impl FlatFollower {
    /// A face through u_b along the direction `face_b` (b's frame, non-zero), on a convex
    /// profile (a sampled check: a flat face would bridge a hollow, not follow it).
    pub fn new(curve: Curve, u_b: [f64; 2], face_b: [f64; 2]) -> Result<Self, String> {
        let norm = face_b[0].hypot(face_b[1]);
        if !(norm.is_finite() && norm > 0.0) {
            return Err(format!("face direction {face_b:?} must be finite and non-zero"));
        }
        let orient = curve.orientation();
        for s in curve.samples() {
            let d1 = curve.eval(s).d1;
            // curvature times |c'|: the turn of the tangent per radian of s, dimensionless
            if orient * curve.curvature(s) * d1[0].hypot(d1[1]) < -1e-9 {
                return Err(format!(
                    "the profile is hollow at s = {s:.6} (radius of curvature {:.6e}): a flat face would \
                     bridge the hollow; a flat-faced follower needs a convex profile",
                    1.0 / curve.curvature(s).abs()
                ));
            }
        }
        Ok(FlatFollower { curve, u_b, n_b: perp([face_b[0] / norm, face_b[1] / norm]) })
    }
}

impl Constraint for FlatFollower {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p = Vec::new();
        p.extend(crate::constraints::xy("u_b", &mut self.u_b));
        p.extend(crate::constraints::xy("n_b", &mut self.n_b));
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
        let n = b.rot(pair(p, 2));
        let e = jet::sub(a.point(c), b.point(pair(p, 0)));
        out[0] = jet::dot(n, e);
        out[1] = jet::dot(n, a.rot(c1));
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
    /// Of the profile points where the tangent is along the face, the one nearer the face.
    fn own_start(&self, a: &Frame, b: &Frame) -> f64 {
        let n = to_local_dir(a, b.rot(self.n_b));
        self.curve.tangent_to_line(n, to_local(a, b.point(self.u_b)))
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, x: &Extra, _t: f64, out: &mut Rows) {
        let k = self.curve.eval(x.s);
        let (n, n_theta) = (b.rot(self.n_b), b.rot_d(self.n_b));
        let e = sub(a.point(k.c), b.point(self.u_b));
        let tangent = a.rot(k.d1);
        out.phi[0] = dot(n, e);
        out.jac_a[0] = [n[0], n[1], dot(n, a.rot_d(k.c))];
        out.jac_b[0] = [-n[0], -n[1], dot(n_theta, e) - dot(n, b.rot_d(self.u_b))];
        out.jac_s[0] = dot(n, tangent);
        out.phi[1] = dot(n, tangent);
        out.jac_a[1] = [0.0, 0.0, dot(n, a.rot_d(k.d1))];
        out.jac_b[1] = [0.0, 0.0, dot(n_theta, tangent)];
        out.jac_s[1] = dot(n, a.rot(k.d2));
    }
    /// With e = C - P, n's rate thd_b B_b n_b and velocity-squared part -n thd_b^2:
    /// gamma = -(-thd_b^2 n . e + 2 thd_b (B_b n_b) . ed + n . eq) and the same with T, Td,
    /// Tq in place of e, ed, eq, where
    /// eq = -A_a c thd_a^2 + 2 B_a c' thd_a sd + A_a c'' sd^2 + A_b u_b thd_b^2,
    /// Tq = -A_a c' thd_a^2 + 2 B_a c'' thd_a sd + A_a c''' sd^2.
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        let (wa, wb, sd) = (a.thetad, b.thetad, x.sd);
        let k = self.curve.eval(x.s);
        let (n, n_theta) = (b.rot(self.n_b), b.rot_d(self.n_b));
        let e = sub(a.point(k.c), b.point(self.u_b));
        let tangent = a.rot(k.d1);
        let (bt, at2, bt2, at3) = (a.rot_d(k.d1), a.rot(k.d2), a.rot_d(k.d2), a.rot(k.d3));
        let (va, vb) = (a.point_velocity(k.c), b.point_velocity(self.u_b));
        let ed: [f64; 2] = std::array::from_fn(|i| va[i] + tangent[i] * sd - vb[i]);
        let (ca, cb) = (a.point_centripetal(k.c), b.point_centripetal(self.u_b));
        let eq: [f64; 2] = std::array::from_fn(|i| ca[i] + 2.0 * wa * sd * bt[i] + sd * sd * at2[i] - cb[i]);
        let td: [f64; 2] = std::array::from_fn(|i| wa * bt[i] + sd * at2[i]);
        let tq: [f64; 2] =
            std::array::from_fn(|i| -wa * wa * tangent[i] + 2.0 * wa * sd * bt2[i] + sd * sd * at3[i]);
        g[0] = wb * wb * dot(n, e) - 2.0 * wb * dot(n_theta, ed) - dot(n, eq);
        g[1] = wb * wb * dot(n, tangent) - 2.0 * wb * dot(n_theta, td) - dot(n, tq);
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u_b
    }
}

impl Sample for FlatFollower {
    fn sample() -> Self {
        let curve = Curve::circle([0.15, -0.1], 0.3, 0.4).expect("a valid circle");
        FlatFollower::new(curve, [0.05, 0.3], [1.0, -0.3]).expect("a valid face")
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for FlatFollower {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "cam_follower",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("body_b", Body),
                ("follower", Choice(&["flat"])),
                ("at", Point(&["body_b"])),
                ("curve", Curve("body_a")),
                ("face", Direction("body_b")),
            ],
        }]
    };
}

/// Compiles a cam-follower description with a flat face: its direction in b.
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
) -> Result<Compiled<FlatFollower>, String> {
    let (curve, u_b, a, b) = cam_follower::start(body_a, body_b, follower, at, curve, radius, face, cx)?;
    let face = face.ok_or_else(|| "a flat-faced follower needs its face direction".to_string())?;
    Ok(Compiled::new(FlatFollower::new(curve, u_b, cx.local_dir(b, face))?, a, b))
}

impl FromDescription for FlatFollower {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::CamFollower { body_a, body_b, follower, at, curve, radius, face, .. }) =
            desc
        else {
            return None;
        };
        if follower != "flat" {
            return None;
        }
        Some(compile(body_a, body_b, follower, *at, curve, *radius, *face, cx))
    }
}

//! Point on a curve: the point u_b of body b stays on the curve c(s) fixed in body a: a
//! pin of b in a curved slot of a, or a knife-edge follower's tip on a cam profile. 2
//! rows, r_b(u_b) - (R_a + A_a c(s)) = 0, and one own coordinate: the curve parameter s.

use super::cam_follower;
use crate::constraints::compile_context::{finite2, CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::curves::Curve;
use crate::input::curves::CurveDesc;
use crate::input::description::JointDesc;
use crate::math::jet::{self, pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct PointOnCurve {
    /// the slot or profile in a's frame
    pub curve: Curve,
    /// the pin or tip in b's frame
    pub u_b: [f64; 2],
}

/// A world point p in the frame of `a`: A_a^T (p - R_a).
#[inline]
pub(crate) fn to_local(a: &Frame, p: [f64; 2]) -> [f64; 2] {
    let d = [p[0] - a.r[0], p[1] - a.r[1]];
    [a.c * d[0] + a.s * d[1], -a.s * d[0] + a.c * d[1]]
}

/// A world direction v in the frame of `a`: A_a^T v.
#[inline]
pub(crate) fn to_local_dir(a: &Frame, v: [f64; 2]) -> [f64; 2] {
    [a.c * v[0] + a.s * v[1], -a.s * v[0] + a.c * v[1]]
}

impl Constraint for PointOnCurve {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        crate::constraints::xy("u_b", &mut self.u_b).into_iter().collect()
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
        let (c, _) = crate::input::curves::at_jet(&self.curve, s);
        let d = jet::sub(b.point(pair(p, 0)), a.point(c));
        out[0] = d[0];
        out[1] = d[1];
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
    fn own_start(&self, a: &Frame, b: &Frame) -> f64 {
        self.curve.nearest(to_local(a, b.point(self.u_b)))
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, x: &Extra, _t: f64, out: &mut Rows) {
        let k = self.curve.eval(x.s);
        let (pa, pb) = (a.point(k.c), b.point(self.u_b));
        let (ba, bb) = (a.rot_d(k.c), b.rot_d(self.u_b));
        let tangent = a.rot(k.d1);
        for i in 0..2 {
            out.phi[i] = pb[i] - pa[i];
            out.jac_a[i] = [0.0, 0.0, -ba[i]];
            out.jac_a[i][i] = -1.0;
            out.jac_b[i] = [0.0, 0.0, bb[i]];
            out.jac_b[i][i] = 1.0;
            out.jac_s[i] = -tangent[i];
        }
    }
    /// gamma = A_b u_b thd_b^2 - A_a c thd_a^2 + 2 B_a c' thd_a sd + A_a c'' sd^2.
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        let k = self.curve.eval(x.s);
        let (ca, cb) = (a.point_centripetal(k.c), b.point_centripetal(self.u_b));
        let (coriolis, along) = (a.rot_d(k.d1), a.rot(k.d2));
        for i in 0..2 {
            g[i] = ca[i] - cb[i] + 2.0 * a.thetad * x.sd * coriolis[i] + x.sd * x.sd * along[i];
        }
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u_b
    }
}

impl Sample for PointOnCurve {
    fn sample() -> Self {
        let angles = vec![0.0, 1.2, 2.0, 3.5, 5.0, std::f64::consts::TAU];
        let radii = vec![0.4, 0.5, 0.35, 0.45, 0.38, 0.4];
        let curve = Curve::polar([0.1, -0.05], 0.3, angles, radii).expect("a valid polar table");
        PointOnCurve { curve, u_b: [0.2, 0.1] }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for PointOnCurve {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[
            super::Form {
                group: "joints",
                type_: "pin_in_slot",
                fields: &[
                    ("name", Name),
                    ("body_a", Body),
                    ("body_b", Body),
                    ("at", Point(&["body_b"])),
                    ("curve", Curve("body_a")),
                ],
            },
            super::Form {
                group: "joints",
                type_: "cam_follower",
                fields: &[
                    ("name", Name),
                    ("body_a", Body),
                    ("body_b", Body),
                    ("follower", Choice(&["knife"])),
                    ("at", Point(&["body_b"])),
                    ("curve", Curve("body_a")),
                ],
            },
        ]
    };
}

/// Compiles a pin-in-slot description: the slot's curve in a, the pin in b.
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    at: [f64; 2],
    curve: &CurveDesc,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<PointOnCurve>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    if !finite2(at) {
        return Err(format!("position {at:?} is not finite"));
    }
    let curve = curve.to_body(cx.pose(a))?;
    Ok(Compiled::new(PointOnCurve { curve, u_b: cx.local(b, at) }, a, b))
}

impl FromDescription for PointOnCurve {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        match desc {
            Desc::Joint(JointDesc::PinInSlot { body_a, body_b, at, curve, .. }) => {
                Some(compile(body_a, body_b, *at, curve, cx))
            }
            // a knife edge: its tip on the profile (a follower no other type takes, checked)
            Desc::Joint(JointDesc::CamFollower {
                body_a, body_b, follower, at, curve, radius, face, ..
            }) if follower != "roller" && follower != "flat" => Some(
                cam_follower::start(body_a, body_b, follower, *at, curve, *radius, *face, cx)
                    .map(|(curve, u_b, a, b)| Compiled::new(PointOnCurve { curve, u_b }, a, b)),
            ),
            _ => None,
        }
    }
}

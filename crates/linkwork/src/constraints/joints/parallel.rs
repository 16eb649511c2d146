//! Parallel axes: a line of body a (unit direction e_a in a's frame) stays parallel to a
//! line of body b (e_b in b's frame). 1 row, an angle: the cross product
//! (A_a e_a) x (A_b e_b) = sin(angle between them) = 0. Its zeros are the parallel and
//! the anti-parallel lines; Newton keeps the one nearest the drawing, where the Jacobian
//! (the cosine, +-1) is far from singular.

use crate::constraints::compile_context::{unit, CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{dot, Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::JointDesc;
use crate::math::jet::{self, pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct Parallel {
    /// unit direction of a's line, in a's frame
    pub e_a: [f64; 2],
    /// unit direction of b's line, in b's frame
    pub e_b: [f64; 2],
}

#[inline(always)]
fn cross(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[1] - u[1] * v[0]
}

impl Constraint for Parallel {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p = Vec::new();
        p.extend(crate::constraints::xy("e_a", &mut self.e_a));
        p.extend(crate::constraints::xy("e_b", &mut self.e_b));
        p
    }
    #[inline]
    fn phi_jet<const W: usize>(
        &self,
        a: &JetFrame<W>,
        b: &JetFrame<W>,
        _s: Jet<W>,
        _t: f64,
        p: &[Jet<W>],
        out: &mut [Jet<W>; MAX_ROWS],
    ) {
        out[0] = jet::cross(a.rot(pair(p, 0)), b.rot(pair(p, 2)));
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Angle]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, out: &mut Rows) {
        let (u, v) = (a.rot(self.e_a), b.rot(self.e_b));
        out.phi[0] = cross(u, v);
        // d/dtheta_a: perp(u) x v = -u . v; d/dtheta_b: u x perp(v) = u . v
        let c = dot(u, v);
        out.jac_a[0] = [0.0, 0.0, -c];
        out.jac_b[0] = [0.0, 0.0, c];
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        // phi = sin(delta), delta = angle from u to v: phi'' = cos(delta) delta'' - phi delta'^2
        let w = b.thetad - a.thetad;
        g[0] = cross(a.rot(self.e_a), b.rot(self.e_b)) * w * w;
    }
}

impl Sample for Parallel {
    fn sample() -> Self {
        let ((sa, ca), (sb, cb)) = (0.3f64.sin_cos(), (-1.1f64).sin_cos());
        Parallel { e_a: [ca, sa], e_b: [cb, sb] }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for Parallel {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "parallel",
            fields: &[
                ("name", Name),
                ("body_a", Body),
                ("body_b", Body),
                ("axis_a", Direction("body_a")),
                ("axis_b", Direction("body_b")),
            ],
        }]
    };
}

/// Compiles a parallel description: each line's direction in its body.
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    axis_a: [f64; 2],
    axis_b: [f64; 2],
    cx: &mut dyn CompileContext,
) -> Result<Compiled<Parallel>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    let (e_a, e_b) = (unit("axis_a", axis_a)?, unit("axis_b", axis_b)?);
    // the row's Jacobian is the cosine between the lines: zero when perpendicular
    if (e_a[0] * e_b[0] + e_a[1] * e_b[1]).abs() <= 1e-6 {
        return Err("its two lines are perpendicular at the start; draw them (nearly) parallel".into());
    }
    Ok(Compiled::new(Parallel { e_a: cx.local_dir(a, e_a), e_b: cx.local_dir(b, e_b) }, a, b))
}

impl FromDescription for Parallel {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::Parallel { body_a, body_b, axis_a, axis_b, .. }) = desc else {
            return None;
        };
        Some(compile(body_a, body_b, *axis_a, *axis_b, cx))
    }
}

//! Fixed joint (weld): body b keeps its pose relative to body a. 3 rows: b's origin
//! stays at the point u_a of a, and the relative angle stays theta0.

use super::revolute::{coincidence, coincidence_gamma};
use crate::constraints::compile_context::{CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::JointDesc;
use crate::math::jet::{pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct Fixed {
    /// b's origin in a's frame
    pub u_a: [f64; 2],
    /// theta_b - theta_a, constant
    pub theta0: f64,
}

impl Constraint for Fixed {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p = Vec::new();
        p.extend(crate::constraints::xy("u_a", &mut self.u_a));
        p.push(("theta0".into(), &mut self.theta0));
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
        let pa = a.point(pair(p, 0));
        out[0] = b.r[0] - pa[0];
        out[1] = b.r[1] - pa[1];
        out[2] = b.theta - a.theta - p[2];
    }
    fn n_rows(&self) -> usize {
        3
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Length, RowKind::Length, RowKind::Angle]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, out: &mut Rows) {
        coincidence(self.u_a, [0.0, 0.0], a, b, 0, out);
        out.phi[2] = b.theta - a.theta - self.theta0;
        out.jac_a[2] = [0.0, 0.0, -1.0];
        out.jac_b[2] = [0.0, 0.0, 1.0];
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        coincidence_gamma(self.u_a, [0.0, 0.0], a, b, 0, g);
        g[2] = 0.0;
    }
}

impl Sample for Fixed {
    fn sample() -> Self {
        Fixed { u_a: [0.25, 0.1], theta0: 0.7 }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for Fixed {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "fixed",
            fields: &[("name", Name), ("body_a", Body), ("body_b", Body)],
        }]
    };
}

/// Compiles a weld description: b's origin in a's frame and the drawn relative angle.
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<Fixed>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    let joint = Fixed { u_a: cx.local(a, cx.origin(b)), theta0: cx.theta(b) - cx.theta(a) };
    Ok(Compiled::new(joint, a, b))
}

impl FromDescription for Fixed {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::Fixed { body_a, body_b, .. }) = desc else {
            return None;
        };
        Some(compile(body_a, body_b, cx))
    }
}

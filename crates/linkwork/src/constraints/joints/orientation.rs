//! Fixed orientation: body b keeps its angle relative to body a, while both translate
//! freely. 1 row, an angle: theta_b - theta_a - angle = 0 (the drawing's angle unless
//! given).

use crate::constraints::compile_context::{CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::JointDesc;
use crate::math::jet::{Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct FixedOrientation {
    /// theta_b - theta_a, constant
    pub angle: f64,
}

impl Constraint for FixedOrientation {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        vec![("angle".into(), &mut self.angle)]
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
        out[0] = b.theta - a.theta - p[0];
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Angle]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, _t: f64, out: &mut Rows) {
        out.phi[0] = b.theta - a.theta - self.angle;
        out.jac_a[0] = [0.0, 0.0, -1.0];
        out.jac_b[0] = [0.0, 0.0, 1.0];
    }
    #[inline]
    fn gamma(&self, _a: &Frame, _b: &Frame, _x: &Extra, _t: f64, g: &mut [f64; MAX_ROWS]) {
        g[0] = 0.0;
    }
}

impl Sample for FixedOrientation {
    fn sample() -> Self {
        FixedOrientation { angle: -0.8 }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for FixedOrientation {
    const FORMS: &'static [super::Form] = {
        use super::Role::*;
        &[super::Form {
            group: "joints",
            type_: "fixed_orientation",
            fields: &[("name", Name), ("body_a", Body), ("body_b", Body), ("angle", Angle)],
        }]
    };
}

/// Compiles a fixed-orientation description: the angle given or drawn.
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    angle: Option<f64>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<FixedOrientation>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    let angle = match angle {
        None => cx.theta(b) - cx.theta(a),
        Some(v) if v.is_finite() => v,
        Some(v) => return Err(format!("angle {v} is not finite")),
    };
    Ok(Compiled::new(FixedOrientation { angle }, a, b))
}

impl FromDescription for FixedOrientation {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Joint(JointDesc::FixedOrientation { body_a, body_b, angle, .. }) = desc else {
            return None;
        };
        Some(compile(body_a, body_b, *angle, cx))
    }
}

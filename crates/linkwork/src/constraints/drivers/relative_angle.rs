//! Relative angle driver: theta_b - theta_a - f(t) = 0.

use crate::constraints::compile_context::{CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::DriverDesc;
use crate::input::motion::MotionLaw;
use crate::math::jet::{Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct RelativeAngleDriver {
    pub law: MotionLaw,
}

impl Constraint for RelativeAngleDriver {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        self.law.params_mut()
    }
    #[inline]
    fn phi_jet<const W: usize>(
        &self,
        a: &JetFrame<W>,
        b: &JetFrame<W>,
        _s: Jet<W>,
        t: f64,
        p: &[Jet<W>],
        out: &mut [Jet<W>; MAX_ROWS],
    ) {
        out[0] = b.theta - a.theta - self.law.jet(t, p);
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Angle]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, t: f64, out: &mut Rows) {
        out.phi[0] = b.theta - a.theta - self.law.eval(t)[0];
        out.jac_a[0] = [0.0, 0.0, -1.0];
        out.jac_b[0] = [0.0, 0.0, 1.0];
    }
    #[inline]
    fn nu(&self, t: f64, nu: &mut [f64; MAX_ROWS]) {
        nu[0] = self.law.eval(t)[1];
    }
    #[inline]
    fn gamma(&self, _a: &Frame, _b: &Frame, _x: &Extra, t: f64, g: &mut [f64; MAX_ROWS]) {
        g[0] = self.law.eval(t)[2];
    }
    fn law(&self) -> Option<&MotionLaw> {
        Some(&self.law)
    }
}

impl Sample for RelativeAngleDriver {
    fn sample() -> Self {
        RelativeAngleDriver { law: super::sample_law() }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for RelativeAngleDriver {
    const FORMS: &'static [super::Form] = {
        use super::Input;
        use super::Role::*;
        &[super::Form {
            group: "drivers",
            type_: "relative_angle",
            fields: &[("name", Name), ("body_a", Body), ("body_b", Body), ("law", Law(Input::RelativeAngle))],
        }]
    };
}

/// Compiles a relative-angle-driver description: its two bodies.
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    law: MotionLaw,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<RelativeAngleDriver>, String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    Ok(Compiled::new(RelativeAngleDriver { law }, a, b))
}

impl FromDescription for RelativeAngleDriver {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Driver(DriverDesc::RelativeAngle { body_a, body_b, .. }, law) = desc else {
            return None;
        };
        Some(compile(body_a, body_b, (*law).clone(), cx))
    }
}

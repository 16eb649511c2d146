//! Absolute angle driver: theta_b - f(t) = 0 (side a is the ground).

use crate::constraints::compile_context::{CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::DriverDesc;
use crate::input::motion::MotionLaw;
use crate::math::jet::{Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct AngleDriver {
    pub law: MotionLaw,
}

impl Constraint for AngleDriver {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        self.law.params_mut()
    }
    #[inline]
    fn phi_jet<const W: usize>(
        &self,
        _a: &JetFrame<W>,
        b: &JetFrame<W>,
        _s: Jet<W>,
        t: f64,
        p: &[Jet<W>],
        out: &mut [Jet<W>; MAX_ROWS],
    ) {
        out[0] = b.theta - self.law.jet(t, p);
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Angle]
    }
    #[inline]
    fn position(&self, _a: &Frame, b: &Frame, _x: &Extra, t: f64, out: &mut Rows) {
        out.phi[0] = b.theta - self.law.eval(t)[0];
        out.jac_a[0] = [0.0; 3];
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

impl Sample for AngleDriver {
    fn sample() -> Self {
        AngleDriver { law: super::sample_law() }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for AngleDriver {
    const FORMS: &'static [super::Form] = {
        use super::Input;
        use super::Role::*;
        &[super::Form {
            group: "drivers",
            type_: "angle",
            fields: &[("name", Name), ("body", Body), ("law", Law(Input::Angle))],
        }]
    };
}

/// Compiles an angle-driver description: the body driven (not the ground).
pub(crate) fn compile(
    body: &str,
    law: MotionLaw,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<AngleDriver>, String> {
    let b = cx.find(body)?;
    if b.is_none() {
        return Err("drives the ground, which cannot move".into());
    }
    Ok(Compiled::new(AngleDriver { law }, None, b))
}

impl FromDescription for AngleDriver {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Driver(DriverDesc::Angle { body, .. }, law) = desc else {
            return None;
        };
        Some(compile(body, (*law).clone(), cx))
    }
}

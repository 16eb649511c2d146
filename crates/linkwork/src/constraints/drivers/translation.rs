//! Translation driver of a prismatic joint: the slide e . d - f(t) = 0, with e the
//! joint's axis (fixed in a) and d = r_b(u_b) - r_a(u_a); the slide is 0 at the start.

use crate::constraints::compile_context::{CompileContext, Compiled, Desc, FromDescription};
use crate::constraints::joints::prismatic::{line_gamma, line_row};
use crate::constraints::{Constraint, Extra, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::description::DriverDesc;
use crate::input::motion::MotionLaw;
use crate::math::jet::{pair, Jet, JetFrame};

#[derive(Debug, Clone, PartialEq)]
pub struct TranslationDriver {
    pub u_a: [f64; 2],
    pub u_b: [f64; 2],
    /// unit axis in a's frame
    pub e_a: [f64; 2],
    pub law: MotionLaw,
}

impl Constraint for TranslationDriver {
    fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
        let mut p = Vec::new();
        p.extend(crate::constraints::xy("u_a", &mut self.u_a));
        p.extend(crate::constraints::xy("u_b", &mut self.u_b));
        p.extend(crate::constraints::xy("e_a", &mut self.e_a));
        p.extend(self.law.params_mut());
        p
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
        let line = crate::constraints::joints::prismatic::line_jet(pair(p, 4), pair(p, 0), pair(p, 2), a, b);
        out[0] = line - self.law.jet(t, &p[6..]);
    }
    fn n_rows(&self) -> usize {
        1
    }
    fn row_kinds(&self) -> &'static [RowKind] {
        &[RowKind::Length]
    }
    #[inline]
    fn position(&self, a: &Frame, b: &Frame, _x: &Extra, t: f64, out: &mut Rows) {
        line_row(self.e_a, self.u_a, self.u_b, a, b, 0, out);
        out.phi[0] -= self.law.eval(t)[0];
    }
    #[inline]
    fn nu(&self, t: f64, nu: &mut [f64; MAX_ROWS]) {
        nu[0] = self.law.eval(t)[1];
    }
    #[inline]
    fn gamma(&self, a: &Frame, b: &Frame, _x: &Extra, t: f64, g: &mut [f64; MAX_ROWS]) {
        g[0] = line_gamma(self.e_a, self.u_a, self.u_b, a, b) + self.law.eval(t)[2];
    }
    fn law(&self) -> Option<&MotionLaw> {
        Some(&self.law)
    }
    fn anchor_b(&self) -> [f64; 2] {
        self.u_b
    }
}

impl Sample for TranslationDriver {
    fn sample() -> Self {
        let (s, c) = (-0.6f64).sin_cos();
        TranslationDriver { u_a: [0.1, 0.0], u_b: [0.0, 0.2], e_a: [c, s], law: super::sample_law() }
    }
}

/// The description's fields and their roles (`Described`).
impl super::Described for TranslationDriver {
    const FORMS: &'static [super::Form] = {
        use super::Input;
        use super::Role::*;
        &[super::Form {
            group: "drivers",
            type_: "translation",
            fields: &[("name", Name), ("joint", Joint), ("law", Law(Input::Slide))],
        }]
    };
}

/// Compiles a translation-driver description: the slide of the prismatic joint it rides on.
pub(crate) fn compile(
    joint: &str,
    law: MotionLaw,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<TranslationDriver>, String> {
    let Some(s) = cx.slide(joint) else {
        return Err(format!("refers to '{joint}', which is not a prismatic joint of the model"));
    };
    Ok(s.map(|s| TranslationDriver { u_a: s.u_a, u_b: s.u_b, e_a: s.e_a, law }))
}

impl FromDescription for TranslationDriver {
    fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Option<Result<Compiled<Self>, String>> {
        let Desc::Driver(DriverDesc::Translation { joint, .. }, law) = desc else {
            return None;
        };
        Some(compile(joint, (*law).clone(), cx))
    }
}

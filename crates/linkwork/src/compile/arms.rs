//! The joints and drivers compiled in order, each description by the type the kind list
//! finds for it (`ConstraintKind::compile`), and the compiler's answers to what a type
//! asks while it compiles (`CompileContext`): bodies by name, drawn poses, pins checked
//! against the drawing (`Closer`), the model's size, the slides compiled before.

use std::collections::HashMap;

use crate::compile::close_drawing::{Closer, Side};
use crate::constraints::compile_context::{local, CompileContext, Compiled, Desc, Slide};
use crate::constraints::kinds::ConstraintKind;
use crate::error::ModelError;
use crate::input::description::{Description, GROUND};

use super::{Bodies, ConstraintDraft};

/// The compiler's side of `CompileContext`: the bodies, the closer collecting the misses,
/// and the prismatic joints' slides kept for the translation drivers that ride on them.
pub(super) struct Context<'a> {
    desc: &'a Description,
    bodies: &'a Bodies<'a>,
    length_scale: f64,
    pub closer: Closer,
    slides: HashMap<&'a str, Compiled<Slide>>,
}

impl<'a> Context<'a> {
    pub fn new(desc: &'a Description, bodies: &'a Bodies<'a>, length_scale: f64, closer: Closer) -> Self {
        Context { desc, bodies, length_scale, closer, slides: HashMap::new() }
    }
}

impl CompileContext for Context<'_> {
    fn find(&self, name: &str) -> Result<Option<usize>, String> {
        self.bodies.find(name)
    }
    fn pose(&self, body: Option<usize>) -> Option<[f64; 3]> {
        self.bodies.pose(body)
    }
    fn length_scale(&self) -> f64 {
        self.length_scale
    }
    fn pin(
        &mut self,
        joint: &str,
        body: Option<usize>,
        key: &'static str,
        pin: Option<[f64; 2]>,
        at: Option<[f64; 2]>,
        normal: Option<[f64; 2]>,
    ) -> [f64; 2] {
        let pose = self.bodies.pose(body);
        let body_name = body.map_or(GROUND, |i| self.desc.bodies[i].name.as_str());
        let drawn = at.map(|at| (at, local(pose, at)));
        self.closer.side(Side { joint, body: body_name, pin: key }, pin, drawn, pose, normal)
    }
    fn slide(&self, joint: &str) -> Option<Compiled<Slide>> {
        self.slides.get(joint).cloned()
    }
}

/// The joints in the description's order, each compiled by its type.
pub(super) fn joint_entries<'a>(
    desc: &'a Description,
    cx: &mut Context<'a>,
) -> Result<Vec<ConstraintDraft>, ModelError> {
    let mut entries = Vec::new();
    for j in &desc.joints {
        let fail = |problem: String| ModelError::Constraint { kind: "joint", name: j.name().into(), problem };
        let c = ConstraintKind::compile(&Desc::Joint(j), cx).map_err(fail)?;
        if let Some(slide) = c.joint.slide() {
            cx.slides.insert(j.name(), Compiled::new(slide, c.a, c.b));
        }
        let name = j.name().to_string();
        let Compiled { joint: kind, a, b, borrowed } = c;
        entries.push(ConstraintDraft { name, role: "joint", kind, body_a: a, body_b: b, borrowed });
    }
    Ok(entries)
}

/// The drivers, after the joints (a translation driver reads its prismatic joint).
pub(super) fn driver_entries(
    desc: &Description,
    cx: &mut Context<'_>,
    entries: &mut Vec<ConstraintDraft>,
) -> Result<(), ModelError> {
    for d in &desc.drivers {
        let fail =
            |problem: String| ModelError::Constraint { kind: "driver", name: d.name().into(), problem };
        let mut law = d.law().clone();
        law.prepare().map_err(fail)?;
        let Compiled { joint: kind, a, b, .. } =
            ConstraintKind::compile(&Desc::Driver(d, &law), cx).map_err(fail)?;
        let name = d.name().to_string();
        entries.push(ConstraintDraft { name, role: "driver", kind, body_a: a, body_b: b, borrowed: None });
    }
    Ok(())
}

//! Each joint's and driver's description sent to its own file's `compile`, and the
//! compiler's answers to what it asks there (`CompileContext`): bodies by name, drawn
//! poses, pins checked against the drawing (`Closer`), the model's size.

use std::collections::HashMap;

use crate::compile::close_drawing::{Closer, Side};
use crate::constraints::compile_context::{local, CompileContext, Compiled, Slide};
use crate::constraints::drivers::{angle, coordinate, distance, relative_angle, translation};
use crate::constraints::joints::cam_follower::{self, CamFollower};
use crate::constraints::joints::{
    belt, coupler, coupling, fixed, gear, orientation, parallel, point_line, point_on_curve, prismatic,
    rack_pinion, revolute,
};
use crate::constraints::kinds::ConstraintKind as K;
use crate::error::ModelError;
use crate::input::description::{Description, DriverDesc, JointDesc, GROUND};

use super::{Bodies, ConstraintDraft};

/// The compiler's side of `CompileContext`: the bodies, the closer collecting the misses,
/// and the prismatic joints' slides kept for the translation drivers that ride on them.
pub(super) struct Context<'a> {
    desc: &'a Description,
    bodies: &'a Bodies<'a>,
    length_scale: f64,
    pub closer: Closer,
    slides: HashMap<&'a str, Slide>,
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
    fn slide(&self, joint: &str) -> Option<Slide> {
        self.slides.get(joint).copied()
    }
}

/// The joints, each compiled by its file, in the description's order.
pub(super) fn joint_entries<'a>(
    desc: &'a Description,
    cx: &mut Context<'a>,
) -> Result<Vec<ConstraintDraft>, ModelError> {
    let mut entries = Vec::new();
    for j in &desc.joints {
        let fail = |problem: String| ModelError::Constraint { kind: "joint", name: j.name().into(), problem };
        let c = joint(j, cx).map_err(fail)?;
        if let (JointDesc::Prismatic { name, .. }, K::Prismatic(p)) = (j, &c.joint) {
            cx.slides.insert(name, Slide { u_a: p.u_a, u_b: p.u_b, e_a: p.e_a, a: c.a, b: c.b });
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
        let Compiled { joint: kind, a, b, .. } = driver(d, law, cx).map_err(fail)?;
        let name = d.name().to_string();
        entries.push(ConstraintDraft { name, role: "driver", kind, body_a: a, body_b: b, borrowed: None });
    }
    Ok(())
}

/// A joint description to its file's `compile`, its type wrapped in its kind.
fn joint(j: &JointDesc, cx: &mut dyn CompileContext) -> Result<Compiled<K>, String> {
    Ok(match j {
        JointDesc::Revolute { name, body_a, body_b, at, pin_a, pin_b } => {
            revolute::compile(name, body_a, body_b, *at, *pin_a, *pin_b, cx)?.map(K::Revolute)
        }
        JointDesc::Prismatic { name, body_a, body_b, at, axis, pin_a, pin_b, axis_a, angle } => {
            prismatic::compile(name, body_a, body_b, *at, *axis, *pin_a, *pin_b, *axis_a, *angle, cx)?
                .map(K::Prismatic)
        }
        JointDesc::Fixed { body_a, body_b, .. } => fixed::compile(body_a, body_b, cx)?.map(K::Fixed),
        JointDesc::Distance { body_a, at_a, body_b, at_b, length, .. } => {
            coupler::compile(body_a, *at_a, body_b, *at_b, *length, cx)?.map(K::Distance)
        }
        JointDesc::PointOnLine { body_a, body_b, at, axis, through, offset, .. } => {
            point_line::compile(body_a, body_b, *at, *axis, *through, *offset, cx)?.map(K::PointOnLine)
        }
        JointDesc::Gear {
            body_a,
            body_b,
            radius_a,
            radius_b,
            ratio,
            centre_a,
            centre_b,
            internal,
            carrier,
            ..
        } => gear::compile(
            body_a, body_b, *radius_a, *radius_b, *ratio, *centre_a, *centre_b, *internal, carrier, cx,
        )?
        .map(K::Gear),
        JointDesc::RackPinion { body_a, body_b, radius, axis, centre, .. } => {
            rack_pinion::compile(body_a, body_b, *radius, *axis, *centre, cx)?.map(K::RackPinion)
        }
        JointDesc::Belt { body_a, body_b, radius_a, radius_b, ratio, crossed, carrier, .. } => {
            belt::compile(body_a, body_b, *radius_a, *radius_b, *ratio, *crossed, carrier, cx)?.map(K::Belt)
        }
        JointDesc::FixedOrientation { body_a, body_b, angle, .. } => {
            orientation::compile(body_a, body_b, *angle, cx)?.map(K::FixedOrientation)
        }
        JointDesc::Parallel { body_a, body_b, axis_a, axis_b, .. } => {
            parallel::compile(body_a, body_b, *axis_a, *axis_b, cx)?.map(K::Parallel)
        }
        JointDesc::LinearCoupling { body_a, body_b, coefficients_a, coefficients_b, value, .. } => {
            coupling::compile(body_a, body_b, coefficients_a, coefficients_b, *value, cx)?
                .map(K::LinearCoupling)
        }
        JointDesc::PinInSlot { body_a, body_b, at, curve, .. } => {
            point_on_curve::compile(body_a, body_b, *at, curve, cx)?.map(K::PointOnCurve)
        }
        JointDesc::CamFollower { body_a, body_b, follower, at, curve, radius, face, .. } => {
            cam_follower::compile(body_a, body_b, follower, *at, curve, *radius, *face, cx)?.map(
                |f| match f {
                    CamFollower::Knife(j) => K::PointOnCurve(j),
                    CamFollower::Roller(j) => K::RollerFollower(j),
                    CamFollower::Flat(j) => K::FlatFollower(j),
                },
            )
        }
    })
}

/// A driver description to its file's `compile`, its type wrapped in its kind.
fn driver(
    d: &DriverDesc,
    law: crate::input::motion::MotionLaw,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<K>, String> {
    Ok(match d {
        DriverDesc::Angle { body, .. } => angle::compile(body, law, cx)?.map(K::AngleDriver),
        DriverDesc::RelativeAngle { body_a, body_b, .. } => {
            relative_angle::compile(body_a, body_b, law, cx)?.map(K::RelativeAngleDriver)
        }
        DriverDesc::Distance { body_a, at_a, body_b, at_b, .. } => {
            distance::compile(body_a, *at_a, body_b, *at_b, law, cx)?.map(K::DistanceDriver)
        }
        DriverDesc::Coordinate { body, at, axis, .. } => {
            coordinate::compile(body, *at, axis, law, cx)?.map(K::CoordinateDriver)
        }
        DriverDesc::Translation { joint, .. } => {
            translation::compile(joint, law, cx)?.map(K::TranslationDriver)
        }
    })
}

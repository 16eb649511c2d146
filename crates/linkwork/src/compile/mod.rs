//! Compiling: a description becomes an immutable `Model`. Names, each joint's and
//! driver's compile arm, the closing of the drawing, redundancy, the symbolic
//! factorization and the plan.

pub mod closing;
pub mod layout;

use std::collections::HashMap;
use std::sync::Arc;

use crate::compile::closing::{close_given, not_closed, world, Closer, Side, CLOSE_TOL};
use crate::constraints::drivers::{
    angle::AngleDriver, coordinate::CoordinateDriver, distance::DistanceDriver,
    relative_angle::RelativeAngleDriver, translation::TranslationDriver,
};
use crate::constraints::joints::{
    belt::Belt,
    coupler::Coupler,
    coupling::LinearCoupling,
    gear::{Gear, Mesh},
    orientation::FixedOrientation,
    parallel::Parallel,
    point_line::PointOnLine,
    rack_pinion::RackPinion,
};
use crate::constraints::loads::{Inertia, Load, LoadEntry};
use crate::constraints::{
    joints::fixed::Fixed, joints::prismatic::Prismatic, joints::revolute::Revolute, kinds::ConstraintKind,
    Constraint, Frame, RowKind, MAX_ROWS,
};
use crate::constraints::{
    joints::flat_follower::FlatFollower, joints::point_on_curve::PointOnCurve,
    joints::roller_follower::RollerFollower,
};
use crate::error::ModelError;
use crate::input::description::{Description, DriverDesc, JointDesc, LoadDesc, GROUND};
use crate::input::files::ModelFile;
use crate::math::linear::LinearKind;
use crate::model::closing::{Closing, Keep};
use crate::model::rank::analyse;

use crate::model::{ConstraintEntry, Model, NamedPoint, OnRedundant, Options};

fn finite2(p: [f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

fn local(q0: Option<[f64; 3]>, p: [f64; 2]) -> [f64; 2] {
    match q0 {
        None => p,
        Some([x, y, th]) => {
            let (s, c) = th.sin_cos();
            let d = [p[0] - x, p[1] - y];
            [c * d[0] + s * d[1], -s * d[0] + c * d[1]]
        }
    }
}

/// A constraint before its rows are laid out: name, role, kind, sides.
struct Entry {
    name: String,
    role: &'static str,
    kind: ConstraintKind,
    body_a: Option<usize>,
    body_b: Option<usize>,
    /// a coordinate of another body the rows involve (a gear pair's carrier angle)
    borrowed: Option<usize>,
}

struct Bodies<'a> {
    index: HashMap<&'a str, usize>,
    poses: Vec<[f64; 3]>,
}

impl Bodies<'_> {
    /// Ok(None) for the ground, Ok(Some(i)) for body i.
    fn find(&self, name: &str) -> Result<Option<usize>, String> {
        if name == GROUND {
            return Ok(None);
        }
        self.index
            .get(name)
            .map(|&i| Some(i))
            .ok_or_else(|| format!("refers to body '{name}', which is not in the model"))
    }
    fn pose(&self, b: Option<usize>) -> Option<[f64; 3]> {
        b.map(|i| self.poses[i])
    }
    fn theta(&self, b: Option<usize>) -> f64 {
        b.map_or(0.0, |i| self.poses[i][2])
    }
    /// The body's origin at the start (the ground's: (0, 0)).
    fn origin(&self, b: Option<usize>) -> [f64; 2] {
        self.pose(b).map_or([0.0, 0.0], |p| [p[0], p[1]])
    }
    fn pair(&self, a: &str, b: &str) -> Result<(Option<usize>, Option<usize>), String> {
        let (ia, ib) = (self.find(a)?, self.find(b)?);
        if ia == ib {
            return Err(format!("connects '{a}' to itself; its two sides must be different bodies"));
        }
        Ok((ia, ib))
    }
}

impl Model {
    /// Compiles a description with default options.
    pub fn new(description: Description) -> Result<Model, ModelError> {
        Model::with_options(description, Options::default())
    }

    /// Compiles a description read from JSON.
    pub fn from_json(text: &str, options: Options) -> Result<Model, ModelError> {
        Model::with_options(Description::from_json(text)?, options)
    }

    /// Validates the description and compiles it.
    pub fn with_options(description: Description, options: Options) -> Result<Model, ModelError> {
        // every angle in radians from here on (the one place units are converted)
        let description = crate::input::units::internal(&description);
        check_options(&options)?;
        let desc = &description;

        // bodies: unique names, finite poses
        let mut names: HashMap<String, &'static str> = HashMap::new();
        let mut claim = |name: &str, what: &'static str| -> Result<(), ModelError> {
            if name.is_empty() {
                return Err(ModelError::Description(format!("a {what} has an empty name")));
            }
            if let Some(first) = names.insert(name.to_string(), what) {
                return Err(ModelError::DuplicateName { name: name.to_string(), first, second: what });
            }
            Ok(())
        };
        claim(GROUND, "the ground")?;
        let mut bodies = Bodies { index: HashMap::new(), poses: Vec::new() };
        for (i, b) in desc.bodies.iter().enumerate() {
            claim(&b.name, "a body")?;
            if !(b.x.is_finite() && b.y.is_finite() && b.theta.is_finite()) {
                return Err(ModelError::Body {
                    name: b.name.clone(),
                    problem: format!("starting pose ({}, {}, {}) is not finite", b.x, b.y, b.theta),
                });
            }
            bodies.index.insert(&b.name, i);
            bodies.poses.push([b.x, b.y, b.theta]);
        }
        for j in &desc.joints {
            claim(j.name(), "a joint")?;
        }
        for d in &desc.drivers {
            claim(d.name(), "a driver")?;
        }
        for l in &desc.loads {
            claim(l.name(), "a load")?;
        }
        let mut point_names: HashMap<&str, ()> = HashMap::new();
        for p in &desc.points {
            if point_names.insert(&p.name, ()).is_some() {
                return Err(ModelError::Point { name: p.name.clone(), problem: "is defined twice".into() });
            }
        }

        let length_scale = length_scale(desc);
        let close = match desc.close.as_deref() {
            None => None,
            Some("given") => Some(Keep::Given),
            Some("drawn") => Some(Keep::Drawn),
            Some(other) => {
                return Err(ModelError::Description(format!(
                    "close must be \"given\" (keep the pins given, close the drawing by least squares) \
                     or \"drawn\" (keep the drawing's points), not {other:?}"
                )))
            }
        };
        // where a joint gives a drawn point and its pins, how far apart they are
        let mut closer = Closer { keep: close, tol: CLOSE_TOL * length_scale, misses: Vec::new() };
        let mut entries: Vec<Entry> = Vec::new();
        let mut prismatic_of: HashMap<&str, (Prismatic, Option<usize>, Option<usize>)> = HashMap::new();
        for j in &desc.joints {
            let fail =
                |problem: String| ModelError::Constraint { kind: "joint", name: j.name().into(), problem };
            // set by a joint whose rows involve another body's coordinate
            let mut borrowed: Option<usize> = None;
            let (kind, a, b) = match j {
                JointDesc::Revolute { name, body_a, body_b, at, pin_a, pin_b } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    if let Some(p) = [*at, *pin_a, *pin_b].into_iter().flatten().find(|p| !finite2(*p)) {
                        return Err(fail(format!("position {p:?} is not finite")));
                    }
                    if at.is_none() && (pin_a.is_none() || pin_b.is_none()) {
                        return Err(fail(
                            "needs its position `at`, or its pin in each body (pin_a and pin_b)".into(),
                        ));
                    }
                    // each side's pin in its frame: given (checked against the drawing's
                    // point where both are), or the drawing's point there
                    let mut side = |pin: Option<[f64; 2]>, body: Option<usize>, key: &'static str| {
                        let pose = bodies.pose(body);
                        let body_name = body.map_or(GROUND, |i| desc.bodies[i].name.as_str());
                        let drawn = at.map(|at| (at, local(pose, at)));
                        closer.side(Side { joint: name, body: body_name, pin: key }, pin, drawn, pose, None)
                    };
                    let joint = Revolute { u_a: side(*pin_a, a, "pin_a"), u_b: side(*pin_b, b, "pin_b") };
                    (ConstraintKind::Revolute(joint), a, b)
                }
                JointDesc::Prismatic { name, body_a, body_b, at, axis, pin_a, pin_b, axis_a, angle } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    let points = [*at, *axis, *pin_a, *pin_b, *axis_a];
                    if let Some(p) = points.into_iter().flatten().find(|p| !finite2(*p)) {
                        return Err(fail(format!("point or axis {p:?} is not finite")));
                    }
                    if at.is_none() && (pin_a.is_none() || pin_b.is_none()) {
                        return Err(fail(
                            "needs its point `at` (world), or its pin in each body (pin_a and pin_b)".into(),
                        ));
                    }
                    // the axis in a's frame: given there, or the world one turned into a's
                    let a_turn = Some([0.0, 0.0, bodies.theta(a)]);
                    if axis_a.or(*axis).is_some_and(|e| e[0].hypot(e[1]) == 0.0) {
                        return Err(fail("has a zero-length axis; give the sliding direction".into()));
                    }
                    let e =
                        match (axis_a, axis) {
                            (Some(e), _) => unit("axis_a", *e).map_err(fail)?,
                            (None, Some(e)) => local(a_turn, unit("axis", *e).map_err(fail)?),
                            (None, None) => return Err(fail(
                                "needs its sliding direction: `axis` (world) or `axis_a` (in body_a's frame)"
                                    .into(),
                            )),
                        };
                    // a pin need only be on the slide line: the miss is across it
                    let normal = Some(world(a_turn, [-e[1], e[0]]));
                    let mut side = |pin: Option<[f64; 2]>, body: Option<usize>, key: &'static str| {
                        let pose = bodies.pose(body);
                        let body_name = body.map_or(GROUND, |i| desc.bodies[i].name.as_str());
                        let drawn = at.map(|at| (at, local(pose, at)));
                        closer.side(Side { joint: name, body: body_name, pin: key }, pin, drawn, pose, normal)
                    };
                    let (u_a, u_b) = (side(*pin_a, a, "pin_a"), side(*pin_b, b, "pin_b"));
                    let lengths_first = pin_a.is_some() || pin_b.is_some();
                    let drawn_angle = bodies.theta(b) - bodies.theta(a);
                    let theta0 = match angle {
                        Some(v) if v.is_finite() => *v,
                        Some(v) => return Err(fail(format!("angle {v} is not finite"))),
                        None if lengths_first => 0.0,
                        None => drawn_angle,
                    };
                    let joint = Prismatic { u_a, u_b, e_a: e, theta0 };
                    prismatic_of.insert(name, (joint.clone(), a, b));
                    (ConstraintKind::Prismatic(joint), a, b)
                }
                JointDesc::Fixed { body_a, body_b, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    let origin_b = bodies.pose(b).map_or([0.0, 0.0], |p| [p[0], p[1]]);
                    let joint = Fixed {
                        u_a: local(bodies.pose(a), origin_b),
                        theta0: bodies.theta(b) - bodies.theta(a),
                    };
                    (ConstraintKind::Fixed(joint), a, b)
                }
                JointDesc::Distance { body_a, at_a, body_b, at_b, length, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    if !finite2(*at_a) || !finite2(*at_b) {
                        return Err(fail(format!("points {at_a:?}, {at_b:?} are not finite")));
                    }
                    let drawn = (at_b[0] - at_a[0]).hypot(at_b[1] - at_a[1]);
                    if drawn <= 1e-12 * length_scale {
                        return Err(fail(
                            "its two points coincide at the start; a distance joint needs them apart".into(),
                        ));
                    }
                    let length = positive_or("length", *length, drawn).map_err(fail)?;
                    let joint = Coupler {
                        u_a: local(bodies.pose(a), *at_a),
                        u_b: local(bodies.pose(b), *at_b),
                        length,
                    };
                    (ConstraintKind::Distance(joint), a, b)
                }
                JointDesc::PointOnLine { body_a, body_b, at, axis, through, offset, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    let q = through.unwrap_or(*at);
                    if !finite2(*at) || !finite2(q) {
                        return Err(fail(format!("point {at:?} or line point {q:?} is not finite")));
                    }
                    let e = unit("axis", *axis).map_err(fail)?;
                    let drawn = -e[1] * (at[0] - q[0]) + e[0] * (at[1] - q[1]);
                    let offset = match offset {
                        None => drawn,
                        Some(o) if o.is_finite() => *o,
                        Some(o) => return Err(fail(format!("offset {o} is not finite"))),
                    };
                    let joint = PointOnLine {
                        u_a: local(bodies.pose(a), *at),
                        u_b: local(bodies.pose(b), q),
                        e_b: local(Some([0.0, 0.0, bodies.theta(b)]), e),
                        offset,
                    };
                    (ConstraintKind::PointOnLine(joint), a, b)
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
                } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    let c_a = centre_a.unwrap_or(bodies.origin(a));
                    let c_b = centre_b.unwrap_or(bodies.origin(b));
                    if !finite2(c_a) || !finite2(c_b) {
                        return Err(fail(format!("centres {c_a:?}, {c_b:?} are not finite")));
                    }
                    let distance = (c_b[0] - c_a[0]).hypot(c_b[1] - c_a[1]);
                    let (r_a, r_b) = match (radius_a, radius_b, ratio) {
                        (None, None, Some(k)) => {
                            gear_radii(*k, distance, *internal, 1e-12 * length_scale).map_err(fail)?
                        }
                        _ => radii(*radius_a, *radius_b, *ratio).map_err(fail)?,
                    };
                    if *internal && r_a == r_b {
                        return Err(fail("an internal gear and its pinion need different radii".into()));
                    }
                    let (k_a, k_b) = Gear::coefficients(r_a, r_b, *internal);
                    let (column, theta_c) = carrier_of(&bodies, carrier, a, b).map_err(fail)?;
                    borrowed = column;
                    // on a carrier, rolling against the line of centres (joints/gear.rs)
                    let mesh = column.map(|_| Mesh {
                        u_a: local(bodies.pose(a), c_a),
                        u_b: local(bodies.pose(b), c_b),
                        delta: (c_b[1] - c_a[1]).atan2(c_b[0] - c_a[0]) - theta_c,
                    });
                    let phi0 = mesh.as_ref().map_or(0.0, |m| theta_c + m.delta);
                    if mesh.is_some() && distance <= 1e-12 * length_scale {
                        return Err(fail("its centres coincide, so they have no line of centres".into()));
                    }
                    let value = k_a * (bodies.theta(a) - phi0) + k_b * (bodies.theta(b) - phi0);
                    let gear = Gear { k_a, k_b, value, carrier: column.is_some(), mesh };
                    (ConstraintKind::Gear(gear), a, b)
                }
                JointDesc::RackPinion { body_a, body_b, radius, axis, centre, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    if a.is_none() {
                        return Err(fail(
                            "its pinion (body_a) is the ground, which cannot turn; the rack may be".into(),
                        ));
                    }
                    let radius = positive_or("radius", Some(*radius), 0.0).map_err(fail)?;
                    let c = centre.unwrap_or(bodies.origin(a));
                    if !finite2(c) {
                        return Err(fail(format!("centre {c:?} is not finite")));
                    }
                    let e = unit("axis", *axis).map_err(fail)?;
                    let joint = RackPinion {
                        u_a: local(bodies.pose(a), c),
                        u_b: local(bodies.pose(b), c),
                        e_b: local(Some([0.0, 0.0, bodies.theta(b)]), e),
                        radius,
                        delta0: bodies.theta(a) - bodies.theta(b),
                    };
                    (ConstraintKind::RackPinion(joint), a, b)
                }
                JointDesc::Belt { body_a, body_b, radius_a, radius_b, ratio, crossed, carrier, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    let (r_a, r_b) = radii(*radius_a, *radius_b, *ratio).map_err(fail)?;
                    let (k_a, k_b) = Gear::coefficients(r_a, r_b, !*crossed);
                    let (column, theta_c) = carrier_of(&bodies, carrier, a, b).map_err(fail)?;
                    borrowed = column;
                    let value = k_a * (bodies.theta(a) - theta_c) + k_b * (bodies.theta(b) - theta_c);
                    (
                        ConstraintKind::Belt(Belt(Gear {
                            k_a,
                            k_b,
                            value,
                            carrier: column.is_some(),
                            mesh: None,
                        })),
                        a,
                        b,
                    )
                }
                JointDesc::FixedOrientation { body_a, body_b, angle, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    let angle = match angle {
                        None => bodies.theta(b) - bodies.theta(a),
                        Some(v) if v.is_finite() => *v,
                        Some(v) => return Err(fail(format!("angle {v} is not finite"))),
                    };
                    (ConstraintKind::FixedOrientation(FixedOrientation { angle }), a, b)
                }
                JointDesc::Parallel { body_a, body_b, axis_a, axis_b, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    let (e_a, e_b) =
                        (unit("axis_a", *axis_a).map_err(fail)?, unit("axis_b", *axis_b).map_err(fail)?);
                    // the row's Jacobian is the cosine between the lines: zero when perpendicular
                    if (e_a[0] * e_b[0] + e_a[1] * e_b[1]).abs() <= 1e-6 {
                        return Err(fail(
                            "its two lines are perpendicular at the start; draw them (nearly) parallel"
                                .into(),
                        ));
                    }
                    let joint = Parallel {
                        e_a: local(Some([0.0, 0.0, bodies.theta(a)]), e_a),
                        e_b: local(Some([0.0, 0.0, bodies.theta(b)]), e_b),
                    };
                    (ConstraintKind::Parallel(joint), a, b)
                }
                JointDesc::LinearCoupling {
                    body_a, body_b, coefficients_a, coefficients_b, value, ..
                } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    let c_a = [coefficients_a.x, coefficients_a.y, coefficients_a.theta];
                    let c_b = [coefficients_b.x, coefficients_b.y, coefficients_b.theta];
                    if !c_a.iter().chain(&c_b).all(|c| c.is_finite()) {
                        return Err(fail(format!("coefficients {c_a:?}, {c_b:?} are not finite")));
                    }
                    for (side, body, c) in [("a", a, c_a), ("b", b, c_b)] {
                        if body.is_none() && c.iter().any(|c| *c != 0.0) {
                            return Err(fail(format!(
                                "has coefficients_{side} on the ground, whose coordinates are fixed"
                            )));
                        }
                    }
                    if c_a.iter().chain(&c_b).all(|c| *c == 0.0) {
                        return Err(fail("has no non-zero coefficient".into()));
                    }
                    let (q_a, q_b) = (bodies.pose(a).unwrap_or([0.0; 3]), bodies.pose(b).unwrap_or([0.0; 3]));
                    let value = match value {
                        None => (0..3).map(|k| c_a[k] * q_a[k] + c_b[k] * q_b[k]).sum(),
                        Some(v) if v.is_finite() => *v,
                        Some(v) => return Err(fail(format!("value {v} is not finite"))),
                    };
                    (ConstraintKind::LinearCoupling(LinearCoupling { c_a, c_b, value }), a, b)
                }
                JointDesc::PinInSlot { body_a, body_b, at, curve, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    if !finite2(*at) {
                        return Err(fail(format!("position {at:?} is not finite")));
                    }
                    let curve = curve.to_body(bodies.pose(a)).map_err(fail)?;
                    let joint = PointOnCurve { curve, u_b: local(bodies.pose(b), *at) };
                    (ConstraintKind::PointOnCurve(joint), a, b)
                }
                JointDesc::CamFollower { body_a, body_b, follower, at, curve, radius, face, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    if !finite2(*at) {
                        return Err(fail(format!("position {at:?} is not finite")));
                    }
                    if !["knife", "roller", "flat"].contains(&follower.as_str()) {
                        return Err(fail(format!(
                            "follower must be \"knife\", \"roller\" or \"flat\", not {follower:?}"
                        )));
                    }
                    if radius.is_some() && follower != "roller" {
                        return Err(fail("gives a radius, which only a roller follower has".into()));
                    }
                    if face.is_some() && follower != "flat" {
                        return Err(fail(
                            "gives a face direction, which only a flat-faced follower has".into(),
                        ));
                    }
                    let curve = curve.to_body(bodies.pose(a)).map_err(fail)?;
                    let u_b = local(bodies.pose(b), *at);
                    let frame =
                        |b: Option<usize>| bodies.pose(b).map_or(Frame::GROUND, |p| Frame::new(p, [0.0; 3]));
                    let kind = match follower.as_str() {
                        "roller" => {
                            let radius =
                                radius.ok_or_else(|| fail("a roller follower needs a radius".into()))?;
                            let joint = RollerFollower::new(curve, u_b, radius, &frame(a), &frame(b));
                            ConstraintKind::RollerFollower(joint.map_err(fail)?)
                        }
                        "flat" => {
                            let face = face.ok_or_else(|| {
                                fail("a flat-faced follower needs its face direction".into())
                            })?;
                            let face_b = local(Some([0.0, 0.0, bodies.theta(b)]), face);
                            ConstraintKind::FlatFollower(FlatFollower::new(curve, u_b, face_b).map_err(fail)?)
                        }
                        // a knife edge: its tip on the profile
                        _ => ConstraintKind::PointOnCurve(PointOnCurve { curve, u_b }),
                    };
                    (kind, a, b)
                }
            };
            let name = j.name().to_string();
            entries.push(Entry { name, role: "joint", kind, body_a: a, body_b: b, borrowed });
        }
        if close.is_none() && !closer.misses.is_empty() {
            return Err(not_closed(&closer.misses));
        }
        for d in &desc.drivers {
            let fail =
                |problem: String| ModelError::Constraint { kind: "driver", name: d.name().into(), problem };
            let mut law = d.law().clone();
            law.prepare().map_err(fail)?;
            let (kind, a, b) = match d {
                DriverDesc::Angle { body, .. } => {
                    let b = bodies.find(body).map_err(fail)?;
                    if b.is_none() {
                        return Err(fail("drives the ground, which cannot move".into()));
                    }
                    (ConstraintKind::AngleDriver(AngleDriver { law }), None, b)
                }
                DriverDesc::RelativeAngle { body_a, body_b, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    (ConstraintKind::RelativeAngleDriver(RelativeAngleDriver { law }), a, b)
                }
                DriverDesc::Distance { body_a, at_a, body_b, at_b, .. } => {
                    let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                    if !finite2(*at_a) || !finite2(*at_b) {
                        return Err(fail(format!("points {at_a:?}, {at_b:?} are not finite")));
                    }
                    if (at_b[0] - at_a[0]).hypot(at_b[1] - at_a[1]) <= 1e-12 * length_scale {
                        return Err(fail(
                            "its two points coincide at the start; a distance driver needs them apart".into(),
                        ));
                    }
                    let drv = DistanceDriver {
                        u_a: local(bodies.pose(a), *at_a),
                        u_b: local(bodies.pose(b), *at_b),
                        law,
                    };
                    (ConstraintKind::DistanceDriver(drv), a, b)
                }
                DriverDesc::Coordinate { body, at, axis, .. } => {
                    let b = bodies.find(body).map_err(fail)?;
                    if b.is_none() {
                        return Err(fail("drives a point of the ground, which cannot move".into()));
                    }
                    if !finite2(*at) {
                        return Err(fail(format!("point {at:?} is not finite")));
                    }
                    let axis = match axis.as_str() {
                        "x" => 0,
                        "y" => 1,
                        other => return Err(fail(format!("axis must be \"x\" or \"y\", not {other:?}"))),
                    };
                    let drv = CoordinateDriver { u: local(bodies.pose(b), *at), axis, law };
                    (ConstraintKind::CoordinateDriver(drv), None, b)
                }
                DriverDesc::Translation { joint, .. } => {
                    let Some((p, a, b)) = prismatic_of.get(joint.as_str()) else {
                        return Err(fail(format!(
                            "refers to '{joint}', which is not a prismatic joint of the model"
                        )));
                    };
                    let drv = TranslationDriver { u_a: p.u_a, u_b: p.u_b, e_a: p.e_a, law };
                    (ConstraintKind::TranslationDriver(drv), *a, *b)
                }
            };
            let name = d.name().to_string();
            entries.push(Entry { name, role: "driver", kind, body_a: a, body_b: b, borrowed: None });
        }

        // rows against coordinates: 3 per body, then one per joint with its own coordinate
        let n_bodies = desc.bodies.len();
        let n_own: usize = entries.iter().map(|e| e.kind.n_own()).sum();
        let n_coords = 3 * n_bodies + n_own;
        let n_rows: usize = entries.iter().map(|e| e.kind.n_rows()).sum();
        if n_bodies == 0 {
            return Err(ModelError::Description("the model has no moving body".into()));
        }
        // a body that no row touches can never be solved for
        let mut touched = vec![false; n_bodies];
        for e in &entries {
            for i in [e.body_a, e.body_b].iter().flatten() {
                touched[*i] = true;
            }
        }
        if let Some(i) = touched.iter().position(|t| !t) {
            return Err(ModelError::Body {
                name: desc.bodies[i].name.clone(),
                problem: "is not connected by any joint or driver".into(),
            });
        }

        let mut points = Vec::new();
        for p in &desc.points {
            let body = bodies
                .find(&p.body)
                .map_err(|problem| ModelError::Point { name: p.name.clone(), problem })?;
            if !finite2(p.at) {
                return Err(ModelError::Point {
                    name: p.name.clone(),
                    problem: format!("{:?} is not finite", p.at),
                });
            }
            points.push(NamedPoint { name: p.name.clone(), body, local: local(bodies.pose(body), p.at) });
        }

        // rows, scales and the pattern of Phi_q
        let mut constraints = Vec::with_capacity(entries.len());
        let mut row0 = 0;
        let mut own_cols = Vec::new();
        for Entry { name, role, kind, body_a, body_b, borrowed } in entries {
            let extra = if kind.n_own() > 0 {
                let pose =
                    |b: Option<usize>| bodies.pose(b).map_or(Frame::GROUND, |p| Frame::new(p, [0.0; 3]));
                own_cols.push((format!("{name}.s"), kind.own_start(&pose(body_a), &pose(body_b))));
                Some(3 * n_bodies + own_cols.len() - 1)
            } else {
                borrowed
            };
            debug_assert_eq!(extra.is_some(), kind.has_extra(), "'{name}': extra coordinate");
            let n = kind.n_rows();
            let mut row_scale = [1.0; MAX_ROWS];
            for (k, rk) in kind.row_kinds().iter().enumerate() {
                row_scale[k] = if *rk == RowKind::Length { 1.0 / length_scale } else { 1.0 };
            }
            constraints.push(ConstraintEntry {
                name,
                role,
                kind,
                body_a,
                body_b,
                row0,
                n_rows: n,
                row_scale,
                extra,
                slots_a: [[u32::MAX; 3]; MAX_ROWS],
                slots_b: [[u32::MAX; 3]; MAX_ROWS],
                slots_s: [u32::MAX; MAX_ROWS],
            });
            row0 += n;
        }
        let mut columns = Vec::with_capacity(n_coords);
        let mut q_start = Vec::with_capacity(n_coords);
        let mut col_scale = Vec::with_capacity(n_coords);
        for (b, pose) in desc.bodies.iter().zip(&bodies.poses) {
            for (k, axis) in ["x", "y", "theta"].iter().enumerate() {
                columns.push(format!("{}.{}", b.name, axis));
                q_start.push(pose[k]);
                col_scale.push(if k < 2 { length_scale } else { 1.0 });
            }
        }
        // own coordinates are dimensionless (curve parameters)
        for (column, start) in own_cols {
            columns.push(column);
            q_start.push(start);
            col_scale.push(1.0);
        }

        // a drawing that did not close, closed as asked (the drawing's points are already
        // the pins where it keeps them)
        let closing = match close {
            Some(keep) if !closer.misses.is_empty() => {
                let drawn = q_start.clone();
                if keep == Keep::Given {
                    close_given(&constraints, &col_scale, length_scale, &mut q_start)?;
                }
                let moved = (0..n_bodies)
                    .map(|i| {
                        let (d, p) = (&drawn[3 * i..3 * i + 3], &q_start[3 * i..3 * i + 3]);
                        (desc.bodies[i].name.clone(), (p[0] - d[0]).hypot(p[1] - d[1]), p[2] - d[2])
                    })
                    .filter(|(_, d, turn)| *d > 0.0 || *turn != 0.0)
                    .collect();
                Some(Closing { keep, misses: closer.misses, moved })
            }
            _ => None,
        };

        let mut indeterminate = Vec::new();
        if n_rows != n_coords {
            // with rows to spare, say which are dependent (or that none is: a structure);
            // the dense SVD is cheap at these sizes
            if n_rows > n_coords && n_coords <= 600 {
                if let Ok(m) = analyse(&constraints, &columns, length_scale, &q_start, 0.0) {
                    let only_redundant = m.rank == n_coords && m.redundancies.len() == n_rows - n_coords;
                    if options.redundant == OnRedundant::Solve && only_redundant {
                        for d in &m.redundancies {
                            indeterminate.extend(d.constraints.iter().map(|(n, _)| n.clone()));
                        }
                        indeterminate.sort();
                        indeterminate.dedup();
                    } else {
                        let hint = if only_redundant {
                            "; or solve anyway in the least-squares sense (Options::redundant = Solve, \
                             Python: compile(redundant=\"solve\"))"
                        } else {
                            ""
                        };
                        return Err(ModelError::Redundant {
                            n_rows,
                            n_coords,
                            explanation: m.explanation.join("; ") + hint,
                        });
                    }
                }
            }
        }
        if n_rows != n_coords && indeterminate.is_empty() {
            let dof = n_coords as i64 - n_rows as i64;
            let advice = if dof > 0 {
                "add drivers (or joints) until none is left"
            } else {
                "remove drivers or redundant joints (kinematic analysis needs exactly as many rows as coordinates)"
            };
            return Err(ModelError::RowCount { n_rows, n_coords, n_bodies, n_own, dof, advice });
        }
        let linear = match options.linear {
            // a redundant model solved anyway: dense QR, least squares (small by nature)
            _ if n_rows > n_coords => LinearKind::LeastSquares,
            LinearKind::Auto => LinearKind::Refactor,
            k => k,
        };
        let symbolic = layout::symbolic_factor(linear, n_rows, n_coords, &mut constraints);

        let inertias = compile_inertias(desc, &bodies)?;
        if !finite2(desc.gravity) {
            return Err(ModelError::Description(format!("gravity {:?} is not finite", desc.gravity)));
        }
        let loads = compile_loads(desc, &bodies, length_scale)?;

        let mut time_domain = (f64::NEG_INFINITY, f64::INFINITY);
        let laws =
            constraints.iter().filter_map(|c| c.kind.law()).chain(loads.iter().filter_map(|l| l.law()));
        for (t0, t1) in laws.filter_map(|l| l.domain()) {
            time_domain = (time_domain.0.max(t0), time_domain.1.min(t1));
        }

        let mut model = Model {
            name: desc.name.clone(),
            body_names: desc.bodies.iter().map(|b| b.name.clone()).collect(),
            columns,
            q_start,
            constraints,
            points,
            n_bodies,
            n_coords,
            n_rows,
            indeterminate,
            length_scale,
            col_scale,
            options,
            symbolic: Arc::new(symbolic),
            time_domain,
            inertias,
            gravity: desc.gravity,
            loads,
            description,
            plan: Err(String::new()),
            closing,
        };
        model.plan = crate::solve::blocks::Plan::new(&model);
        Ok(model)
    }
}

impl ModelFile {
    /// Compiles the description; an error that names an element gets its line.
    pub fn compile(&self, options: Options) -> Result<Model, ModelError> {
        Model::with_options(self.description.clone(), options).map_err(|e| self.source.locate(e))
    }
}

fn compile_inertias(desc: &Description, bodies: &Bodies) -> Result<Vec<Inertia>, ModelError> {
    let mut out = Vec::with_capacity(desc.bodies.len());
    for (i, b) in desc.bodies.iter().enumerate() {
        let fail = |problem: String| ModelError::Body { name: b.name.clone(), problem };
        if !(b.mass.is_finite() && b.mass >= 0.0) {
            return Err(fail(format!("mass {} must be finite and >= 0", b.mass)));
        }
        if !(b.inertia.is_finite() && b.inertia >= 0.0) {
            return Err(fail(format!("moment of inertia {} must be finite and >= 0", b.inertia)));
        }
        let com = b.com.unwrap_or([b.x, b.y]);
        if !finite2(com) {
            return Err(fail(format!("centre of mass {com:?} is not finite")));
        }
        out.push(Inertia { mass: b.mass, inertia: b.inertia, com: local(Some(bodies.poses[i]), com) });
    }
    Ok(out)
}

fn compile_loads(
    desc: &Description,
    bodies: &Bodies,
    length_scale: f64,
) -> Result<Vec<LoadEntry>, ModelError> {
    let mut out = Vec::with_capacity(desc.loads.len());
    for l in &desc.loads {
        let fail = |problem: String| ModelError::Constraint { kind: "load", name: l.name().into(), problem };
        let non_negative = |what: &str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(fail(format!("{what} {v} must be finite and >= 0")))
            }
        };
        let (load, a, b) = match l {
            LoadDesc::Force { body, at, direction, law, .. } => {
                let b = bodies.find(body).map_err(fail)?;
                let norm = direction[0].hypot(direction[1]);
                if !finite2(*at) || !norm.is_finite() || norm == 0.0 {
                    return Err(fail(format!(
                        "point {at:?} and direction {direction:?} must be finite, the direction non-zero"
                    )));
                }
                let mut law = law.clone();
                law.prepare().map_err(fail)?;
                let dir = [direction[0] / norm, direction[1] / norm];
                (Load::Force { u: local(bodies.pose(b), *at), dir, law }, None, b)
            }
            LoadDesc::Torque { body, law, .. } => {
                let b = bodies.find(body).map_err(fail)?;
                let mut law = law.clone();
                law.prepare().map_err(fail)?;
                (Load::Torque { law }, None, b)
            }
            LoadDesc::Spring { body_a, at_a, body_b, at_b, stiffness, free_length, damping, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                non_negative("stiffness", *stiffness)?;
                non_negative("free length", *free_length)?;
                non_negative("damping", *damping)?;
                if !finite2(*at_a) || !finite2(*at_b) {
                    return Err(fail(format!("points {at_a:?}, {at_b:?} are not finite")));
                }
                if (at_b[0] - at_a[0]).hypot(at_b[1] - at_a[1]) <= 1e-12 * length_scale {
                    return Err(fail(
                        "its two points coincide at the start; a spring needs them apart".into(),
                    ));
                }
                let load = Load::Spring {
                    u_a: local(bodies.pose(a), *at_a),
                    u_b: local(bodies.pose(b), *at_b),
                    stiffness: *stiffness,
                    free_length: *free_length,
                    damping: *damping,
                };
                (load, a, b)
            }
            LoadDesc::TorsionSpring { body_a, body_b, stiffness, free_angle, damping, .. } => {
                let (a, b) = bodies.pair(body_a, body_b).map_err(fail)?;
                non_negative("stiffness", *stiffness)?;
                non_negative("damping", *damping)?;
                if !free_angle.is_finite() {
                    return Err(fail(format!("free angle {free_angle} is not finite")));
                }
                (
                    Load::TorsionSpring { stiffness: *stiffness, free_angle: *free_angle, damping: *damping },
                    a,
                    b,
                )
            }
        };
        if b.is_none() && a.is_none() {
            return Err(fail("acts on the ground only, which cannot move".into()));
        }
        out.push(LoadEntry { name: l.name().to_string(), load, body_a: a, body_b: b });
    }
    Ok(out)
}

/// A given value (finite and > 0, else an error naming `what`), or the default.
fn positive_or(what: &str, given: Option<f64>, default: f64) -> Result<f64, String> {
    match given {
        None => Ok(default),
        Some(v) if v.is_finite() && v > 0.0 => Ok(v),
        Some(v) => Err(format!("{what} {v} must be finite and > 0")),
    }
}

/// The unit vector along a finite, non-zero direction `what`.
fn unit(what: &str, v: [f64; 2]) -> Result<[f64; 2], String> {
    let norm = v[0].hypot(v[1]);
    if !finite2(v) || norm == 0.0 {
        return Err(format!("{what} {v:?} must be a finite, non-zero direction"));
    }
    Ok([v[0] / norm, v[1] / norm])
}

/// Pitch radii of a gear pair or pulleys given by radii, or by the speed ratio r_a / r_b
/// alone (radii k and 1: only their ratio matters).
fn radii(radius_a: Option<f64>, radius_b: Option<f64>, ratio: Option<f64>) -> Result<(f64, f64), String> {
    match (radius_a, radius_b, ratio) {
        (Some(r_a), Some(r_b), None) => {
            Ok((positive_or("radius_a", Some(r_a), 0.0)?, positive_or("radius_b", Some(r_b), 0.0)?))
        }
        (None, None, Some(k)) => Ok((positive_or("ratio", Some(k), 0.0)?, 1.0)),
        _ => Err("needs either radius_a and radius_b, or ratio (one of the two, not both)".into()),
    }
}

/// Pitch radii of a gear pair from the speed ratio k = r_a / r_b and the distance between
/// the centres: r_a + r_b = distance (external), |r_a - r_b| = distance (internal).
fn gear_radii(k: f64, distance: f64, internal: bool, min_distance: f64) -> Result<(f64, f64), String> {
    let k = positive_or("ratio", Some(k), 0.0)?;
    if distance <= min_distance {
        return Err("its centres coincide at the start, so a ratio does not give the radii; \
                    give radius_a and radius_b or draw the centres apart"
            .into());
    }
    if internal && (k - 1.0).abs() <= 1e-12 {
        return Err("an internal gear pair cannot have ratio 1".into());
    }
    let r_b = if internal { distance / (k - 1.0).abs() } else { distance / (k + 1.0) };
    Ok((k * r_b, r_b))
}

/// The carrier of a gear pair or belt: its theta column and starting angle; no carrier
/// (or the ground) gives (None, 0). The carrier must be a third body.
fn carrier_of(
    bodies: &Bodies,
    carrier: &Option<String>,
    a: Option<usize>,
    b: Option<usize>,
) -> Result<(Option<usize>, f64), String> {
    let Some(name) = carrier else {
        return Ok((None, 0.0));
    };
    let c = bodies.find(name)?;
    if c == a || c == b {
        return Err(format!(
            "its carrier '{name}' is one of its own two bodies; the carrier must be a third body"
        ));
    }
    Ok((c.map(|i| 3 * i + 2), bodies.theta(c)))
}

fn check_options(o: &Options) -> Result<(), ModelError> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    if !(positive(o.tol_residual) && positive(o.tol_step) && positive(o.singular_tol))
        || o.max_iter == 0
        || o.max_iter_assembly == 0
    {
        return Err(ModelError::Description(format!(
            "solver options must be positive (tolerances finite and > 0, iteration caps >= 1): {o:?}"
        )));
    }
    Ok(())
}

/// L: the largest distance between any two described points (body origins, joint and
/// driver points, named points); 1 if they all coincide.
fn length_scale(desc: &Description) -> f64 {
    let mut pts: Vec<[f64; 2]> = desc.bodies.iter().map(|b| [b.x, b.y]).collect();
    for j in &desc.joints {
        match j {
            JointDesc::Revolute { at, pin_a, pin_b, .. } => {
                pts.extend([*at, *pin_a, *pin_b].into_iter().flatten())
            }
            JointDesc::Prismatic { at, pin_a, pin_b, .. } => {
                pts.extend([*at, *pin_a, *pin_b].into_iter().flatten())
            }
            JointDesc::Fixed { .. } => {}
            JointDesc::Distance { at_a, at_b, .. } => pts.extend([*at_a, *at_b]),
            JointDesc::PointOnLine { at, through, .. } => {
                pts.extend([Some(*at), *through].into_iter().flatten())
            }
            JointDesc::Gear { centre_a, centre_b, .. } => {
                pts.extend([*centre_a, *centre_b].into_iter().flatten())
            }
            JointDesc::RackPinion { centre, .. } => pts.extend(*centre),
            JointDesc::Belt { .. }
            | JointDesc::FixedOrientation { .. }
            | JointDesc::Parallel { .. }
            | JointDesc::LinearCoupling { .. } => {}
            JointDesc::PinInSlot { at, curve, .. } | JointDesc::CamFollower { at, curve, .. } => {
                pts.push(*at);
                pts.extend(curve.world_points());
            }
        }
    }
    for d in &desc.drivers {
        match d {
            DriverDesc::Distance { at_a, at_b, .. } => pts.extend([*at_a, *at_b]),
            DriverDesc::Coordinate { at, .. } => pts.push(*at),
            _ => {}
        }
    }
    pts.extend(desc.points.iter().map(|p| p.at));
    pts.retain(|p| finite2(*p));
    // bounding-box diagonal: within a factor sqrt(2) of the diameter, and O(n)
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &pts {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let diag = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    if diag.is_finite() && diag > 0.0 {
        diag
    } else {
        1.0
    }
}

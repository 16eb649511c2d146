//! Compiling: a description becomes an immutable `Model`. Names, each joint's and
//! driver's compile arm, the closing of the drawing, redundancy, the symbolic
//! factorization and the plan.

mod arms;
pub mod close_drawing;
pub mod layout;

use std::collections::HashMap;
use std::sync::Arc;

use crate::compile::close_drawing::{close_given, not_closed, Closer, CLOSE_TOL};
use crate::constraints::compile_context::{finite2, local};
use crate::constraints::loads::{Inertia, JointAxis, Load, LoadEntry, ReadJoint};
use crate::constraints::{kinds::ConstraintKind, Constraint, Frame, RowKind, MAX_ROWS};
use crate::error::ModelError;
use crate::input::description::{Description, DriverDesc, JointArgument, JointDesc, LoadDesc, GROUND};
use crate::input::files::ModelFile;
use crate::input::motion::{MotionLaw, Sequence};
use crate::math::linear::LinearKind;
use crate::model::closing::{Closing, Keep, PinMiss};
use crate::model::rank::analyse;

use crate::model::{ConstraintEntry, Model, NamedPoint, OnRedundant, Options};

/// A constraint before its rows are laid out: name, role, kind, sides.
struct ConstraintDraft {
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
        // a description that says `free = true` compiles free whatever the options say
        let options = Options { free: options.free || description.free, ..options };
        // the radians in the file's angle unit, for the joint loads (`compile_loads`)
        let angle_unit = description.units.angle.to_radians();
        // every angle in radians from here on (the one place units are converted)
        let description = crate::input::units::internal(&description);
        check_options(&options)?;
        let desc = &description;

        let bodies = names(desc)?;

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
        let closer = Closer { keep: close, tol: CLOSE_TOL * length_scale, misses: Vec::new() };
        let mut cx = arms::Context::new(desc, &bodies, length_scale, closer);
        let mut entries = arms::joint_entries(desc, &mut cx)?;
        if close.is_none() && !cx.closer.misses.is_empty() {
            return Err(not_closed(&cx.closer.misses));
        }
        arms::driver_entries(desc, &mut cx, &mut entries)?;
        let closer = cx.closer;

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
        for ConstraintDraft { name, role, kind, body_a, body_b, borrowed } in entries {
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
        let closing =
            close_drawing(desc, close, closer.misses, &constraints, &col_scale, length_scale, &mut q_start)?;

        let indeterminate =
            redundancy(&constraints, &columns, length_scale, &q_start, &options, n_bodies, n_own)?;
        let linear = match options.linear {
            // a redundant model solved anyway: dense QR, least squares (small by nature)
            _ if n_rows > n_coords => LinearKind::LeastSquares,
            // a free model: never factored by kinematics (refused); the dense layout
            // (n x n, rows m < n) keeps Data::new valid, dynamics builds its own pattern
            _ if n_rows < n_coords => LinearKind::Small,
            LinearKind::Auto => LinearKind::Refactor,
            k => k,
        };
        let symbolic = layout::symbolic_factor(linear, n_rows, n_coords, &mut constraints);

        let inertias = compile_inertias(desc, &bodies)?;
        if !finite2(desc.gravity) {
            return Err(ModelError::Description(format!("gravity {:?} is not finite", desc.gravity)));
        }
        let loads = compile_loads(desc, &bodies, &constraints, length_scale, angle_unit)?;

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
        model.plan = if model.dof() > 0 {
            Err("free model".into())
        } else {
            crate::solve::closed_form::Plan::new(&model)
        };
        Ok(model)
    }
}

/// Every name claimed once (bodies, joints, drivers, loads; points apart), and the bodies'
/// starting poses, finite.
fn names(desc: &Description) -> Result<Bodies<'_>, ModelError> {
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
    Ok(bodies)
}

/// A drawing that did not close, closed as asked (the drawing's points are already the
/// pins where it keeps them): keeping the pins given, the bodies moved by least squares.
fn close_drawing(
    desc: &Description,
    close: Option<Keep>,
    misses: Vec<PinMiss>,
    constraints: &[ConstraintEntry],
    col_scale: &[f64],
    length_scale: f64,
    q_start: &mut [f64],
) -> Result<Option<Closing>, ModelError> {
    let n_bodies = desc.bodies.len();
    Ok(match close {
        Some(keep) if !misses.is_empty() => {
            let drawn = q_start.to_vec();
            if keep == Keep::Given {
                close_given(constraints, col_scale, length_scale, q_start)?;
            }
            let moved = (0..n_bodies)
                .map(|i| {
                    let (d, p) = (&drawn[3 * i..3 * i + 3], &q_start[3 * i..3 * i + 3]);
                    (desc.bodies[i].name.clone(), (p[0] - d[0]).hypot(p[1] - d[1]), p[2] - d[2])
                })
                .filter(|(_, d, turn)| *d > 0.0 || *turn != 0.0)
                .collect();
            Some(Closing { keep, misses, moved })
        }
        _ => None,
    })
}

/// Rows against coordinates: with rows to spare, which are dependent (solved anyway in the
/// least-squares sense where asked: the constraints whose reactions are indeterminate),
/// else an error that says what to add or remove.
fn redundancy(
    constraints: &[ConstraintEntry],
    columns: &[String],
    length_scale: f64,
    q_start: &[f64],
    options: &Options,
    n_bodies: usize,
    n_own: usize,
) -> Result<Vec<String>, ModelError> {
    let (n_rows, n_coords) = (constraints.iter().map(|c| c.n_rows).sum::<usize>(), columns.len());
    let mut indeterminate = Vec::new();
    if n_rows != n_coords {
        // with rows to spare, say which are dependent (or that none is: a structure);
        // the dense SVD is cheap at these sizes
        if n_rows > n_coords && n_coords <= 600 {
            if let Ok(m) = analyse(constraints, columns, length_scale, q_start, 0.0) {
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
    // free coordinates kept on purpose: their motion follows from forces
    let free = options.free && n_rows < n_coords;
    if n_rows != n_coords && indeterminate.is_empty() && !free {
        let dof = n_coords as i64 - n_rows as i64;
        let advice = if dof > 0 {
            "add drivers (or joints) until none is left for a kinematic analysis; or keep them free and \
             simulate the motion under forces (Options::free, Python: compile(free=True), then \
             model.simulate)"
        } else {
            "remove drivers or redundant joints (kinematic analysis needs exactly as many rows as coordinates)"
        };
        return Err(ModelError::RowCount { n_rows, n_coords, n_bodies, n_own, dof, advice });
    }
    Ok(indeterminate)
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

/// The axis of the joint named `joint` a joint load acts at, its sides and the factor from
/// its coordinate to the unit of the file (1 / angle_unit for a revolute: the angles of
/// a file in degrees; a slide keeps its length unit).
fn joint_axis(
    verb: &str,
    joint: &str,
    constraints: &[ConstraintEntry],
    angle_unit: f64,
) -> Result<(JointAxis, Option<usize>, Option<usize>, f64), String> {
    let Some(c) = constraints.iter().find(|c| c.role == "joint" && c.name == joint) else {
        return Err(format!("{verb} '{joint}', which is not a joint of the model"));
    };
    match &c.kind {
        ConstraintKind::Revolute(_) => Ok((JointAxis::Turn, c.body_a, c.body_b, 1.0 / angle_unit)),
        ConstraintKind::Prismatic(p) => {
            Ok((JointAxis::Slide { u_a: p.u_a, u_b: p.u_b, e_a: p.e_a }, c.body_a, c.body_b, 1.0))
        }
        _ => Err(format!(
            "{verb} '{joint}', a {} joint; joint loads act at and read revolute or prismatic joints",
            c.kind.label()
        )),
    }
}

/// A motor's torque-speed line stall (1 - w / w_nl); clipped, stall torque at and against
/// zero speed and none at and beyond the no-load speed (in the direction of w_nl).
fn motor_curve(stall: f64, no_load_speed: f64, clip: bool) -> MotionLaw {
    let line = MotionLaw::Linear { value: stall, rate: -stall / no_load_speed };
    if !clip {
        return line;
    }
    let (held, idle) = (MotionLaw::Constant { value: stall }, MotionLaw::Constant { value: 0.0 });
    let (breakpoints, laws) = if no_load_speed > 0.0 {
        (vec![0.0, no_load_speed], vec![held, line, idle])
    } else {
        (vec![no_load_speed, 0.0], vec![idle, line, held])
    };
    MotionLaw::Sequence(Sequence { breakpoints, laws })
}

fn compile_loads(
    desc: &Description,
    bodies: &Bodies,
    constraints: &[ConstraintEntry],
    length_scale: f64,
    angle_unit: f64,
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
            // laws of the coordinate x of the joint read, in the file's unit: f(scale x),
            // scale = 180 / pi for a revolute joint of a file in degrees
            LoadDesc::JointForce { joint, of, of_joint, law, .. } => {
                let (axis, a, b, own_scale) =
                    joint_axis("acts at", joint, constraints, angle_unit).map_err(fail)?;
                let (reads, scale) = match of_joint {
                    Some(other) if other != joint => {
                        let (axis, body_a, body_b, scale) =
                            joint_axis("reads the coordinate of", other, constraints, angle_unit)
                                .map_err(fail)?;
                        (Some(ReadJoint { axis, body_a, body_b }), scale)
                    }
                    _ => (None, own_scale),
                };
                let mut law = law.clone();
                law.prepare().map_err(fail)?;
                (Load::JointForce { axis, law, rate: *of == JointArgument::Rate, scale, reads }, a, b)
            }
            LoadDesc::Motor { joint, stall, no_load_speed, clip, .. } => {
                let (axis, a, b, scale) =
                    joint_axis("acts at", joint, constraints, angle_unit).map_err(fail)?;
                if !(stall.is_finite() && no_load_speed.is_finite() && *no_load_speed != 0.0) {
                    return Err(fail(format!(
                        "stall {stall} and no-load speed {no_load_speed} must be finite, the speed non-zero"
                    )));
                }
                let mut law = motor_curve(*stall, *no_load_speed, *clip);
                law.prepare().map_err(fail)?;
                (Load::JointForce { axis, law, rate: true, scale, reads: None }, a, b)
            }
            LoadDesc::Friction { joint, viscous, coulomb, smoothing, .. } => {
                let (axis, a, b, scale) =
                    joint_axis("acts at", joint, constraints, angle_unit).map_err(fail)?;
                non_negative("viscous coefficient", *viscous)?;
                non_negative("Coulomb friction", *coulomb)?;
                let smoothing = match smoothing {
                    Some(v) if v.is_finite() && *v > 0.0 => *v,
                    None if *coulomb == 0.0 => 1.0,
                    Some(v) => return Err(fail(format!("smoothing rate {v} must be finite and > 0"))),
                    None => {
                        return Err(fail(
                            "Coulomb friction needs a smoothing rate (tanh(rate / smoothing))".into(),
                        ))
                    }
                };
                // per unit rate of the file -> per unit rate of x (c scale), smoothing likewise
                let load = Load::Friction {
                    axis,
                    viscous: viscous * scale,
                    coulomb: *coulomb,
                    smoothing: smoothing / scale,
                };
                (load, a, b)
            }
        };
        if b.is_none() && a.is_none() {
            return Err(fail("acts on the ground only, which cannot move".into()));
        }
        out.push(LoadEntry { name: l.name().to_string(), load, body_a: a, body_b: b });
    }
    Ok(out)
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

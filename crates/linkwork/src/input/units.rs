//! Units of a description, declared once per model: length "m" or "mm", angle "rad" or
//! "deg". The description keeps its numbers as written; `internal` (called at the start
//! of compiling) turns every angle into radians, in this one place. Lengths are never
//! converted: the engine is scale-aware, so the declared length unit is the unit of every
//! length in and out. Mass is kg and time s, so forces come out in kg L/s^2 and torques
//! in kg L^2/s^2 (L the length unit): `Units::table` names them.

use crate::input::curves::CurveDesc;
pub use crate::input::description::{AngleUnit, LengthUnit, Units};
use crate::input::description::{
    BodyDesc, Coefficients, Description, DriverDesc, JointDesc, LoadDesc, PointDesc,
};

/// The description as the engine compiles it: every angle in radians (laws of angle
/// drivers wrapped in a scale), lengths as declared; its units say angles are radians,
/// so converting it again changes nothing.
///
/// Every struct is taken apart field by field and every enum matched variant by
/// variant (no `..`, no `_`): a new field or type with an angle cannot be forgotten here.
pub fn internal(desc: &Description) -> Description {
    let k = desc.units.angle.to_radians();
    let Description {
        name,
        units,
        bodies,
        joints,
        drivers,
        points,
        gravity,
        loads,
        outputs,
        branch,
        close,
        free,
        initial_rates,
    } = desc;
    let bodies = bodies
        .iter()
        .map(|b| {
            let BodyDesc { name, x, y, theta, mass, inertia, com } = b;
            BodyDesc {
                name: name.clone(),
                x: *x,
                y: *y,
                theta: k * theta,
                mass: *mass,
                inertia: *inertia,
                com: *com,
            }
        })
        .collect();
    // joints with an angle: a fixed orientation's angle, a linear coupling's theta
    // coefficients (per degree -> per radian), a polar cam table's angles
    let joints = joints
        .iter()
        .map(|j| match j {
            JointDesc::Revolute { name, body_a, body_b, at, pin_a, pin_b } => JointDesc::Revolute {
                name: name.clone(),
                body_a: body_a.clone(),
                body_b: body_b.clone(),
                at: *at,
                pin_a: *pin_a,
                pin_b: *pin_b,
            },
            JointDesc::Prismatic { name, body_a, body_b, at, axis, pin_a, pin_b, axis_a, angle, travel } => {
                JointDesc::Prismatic {
                    name: name.clone(),
                    body_a: body_a.clone(),
                    body_b: body_b.clone(),
                    at: *at,
                    axis: *axis,
                    pin_a: *pin_a,
                    pin_b: *pin_b,
                    axis_a: *axis_a,
                    angle: angle.map(|a| k * a),
                    travel: *travel,
                }
            }
            JointDesc::Fixed { name, body_a, body_b } => {
                JointDesc::Fixed { name: name.clone(), body_a: body_a.clone(), body_b: body_b.clone() }
            }
            JointDesc::Distance { name, body_a, at_a, body_b, at_b, length } => JointDesc::Distance {
                name: name.clone(),
                body_a: body_a.clone(),
                at_a: *at_a,
                body_b: body_b.clone(),
                at_b: *at_b,
                length: *length,
            },
            JointDesc::PointOnLine { name, body_a, body_b, at, axis, through, offset } => {
                JointDesc::PointOnLine {
                    name: name.clone(),
                    body_a: body_a.clone(),
                    body_b: body_b.clone(),
                    at: *at,
                    axis: *axis,
                    through: *through,
                    offset: *offset,
                }
            }
            JointDesc::Gear {
                name,
                body_a,
                body_b,
                radius_a,
                radius_b,
                ratio,
                centre_a,
                centre_b,
                internal,
                carrier,
            } => JointDesc::Gear {
                name: name.clone(),
                body_a: body_a.clone(),
                body_b: body_b.clone(),
                radius_a: *radius_a,
                radius_b: *radius_b,
                ratio: *ratio,
                centre_a: *centre_a,
                centre_b: *centre_b,
                internal: *internal,
                carrier: carrier.clone(),
            },
            JointDesc::RackPinion { name, body_a, body_b, radius, axis, centre } => JointDesc::RackPinion {
                name: name.clone(),
                body_a: body_a.clone(),
                body_b: body_b.clone(),
                radius: *radius,
                axis: *axis,
                centre: *centre,
            },
            JointDesc::Belt { name, body_a, body_b, radius_a, radius_b, ratio, crossed, carrier } => {
                JointDesc::Belt {
                    name: name.clone(),
                    body_a: body_a.clone(),
                    body_b: body_b.clone(),
                    radius_a: *radius_a,
                    radius_b: *radius_b,
                    ratio: *ratio,
                    crossed: *crossed,
                    carrier: carrier.clone(),
                }
            }
            JointDesc::FixedOrientation { name, body_a, body_b, angle } => JointDesc::FixedOrientation {
                name: name.clone(),
                body_a: body_a.clone(),
                body_b: body_b.clone(),
                angle: angle.map(|a| k * a),
            },
            JointDesc::Parallel { name, body_a, body_b, axis_a, axis_b } => JointDesc::Parallel {
                name: name.clone(),
                body_a: body_a.clone(),
                body_b: body_b.clone(),
                axis_a: *axis_a,
                axis_b: *axis_b,
            },
            JointDesc::LinearCoupling { name, body_a, body_b, coefficients_a, coefficients_b, value } => {
                JointDesc::LinearCoupling {
                    name: name.clone(),
                    body_a: body_a.clone(),
                    body_b: body_b.clone(),
                    coefficients_a: per_radian(coefficients_a, k),
                    coefficients_b: per_radian(coefficients_b, k),
                    value: *value,
                }
            }
            JointDesc::PinInSlot { name, body_a, body_b, at, curve } => JointDesc::PinInSlot {
                name: name.clone(),
                body_a: body_a.clone(),
                body_b: body_b.clone(),
                at: *at,
                curve: curve_in_radians(curve, k),
            },
            JointDesc::CamFollower { name, body_a, body_b, follower, at, curve, radius, face } => {
                JointDesc::CamFollower {
                    name: name.clone(),
                    body_a: body_a.clone(),
                    body_b: body_b.clone(),
                    follower: follower.clone(),
                    at: *at,
                    curve: curve_in_radians(curve, k),
                    radius: *radius,
                    face: *face,
                }
            }
        })
        .collect();
    let drivers = drivers
        .iter()
        .map(|d| match d {
            DriverDesc::Angle { name, body, law } => {
                DriverDesc::Angle { name: name.clone(), body: body.clone(), law: law.clone().scaled(k) }
            }
            DriverDesc::RelativeAngle { name, body_a, body_b, law } => DriverDesc::RelativeAngle {
                name: name.clone(),
                body_a: body_a.clone(),
                body_b: body_b.clone(),
                law: law.clone().scaled(k),
            },
            DriverDesc::Distance { name, body_a, at_a, body_b, at_b, law } => DriverDesc::Distance {
                name: name.clone(),
                body_a: body_a.clone(),
                at_a: *at_a,
                body_b: body_b.clone(),
                at_b: *at_b,
                law: law.clone(),
            },
            DriverDesc::Coordinate { name, body, at, axis, law } => DriverDesc::Coordinate {
                name: name.clone(),
                body: body.clone(),
                at: *at,
                axis: axis.clone(),
                law: law.clone(),
            },
            DriverDesc::Translation { name, joint, law } => {
                DriverDesc::Translation { name: name.clone(), joint: joint.clone(), law: law.clone() }
            }
        })
        .collect();
    let points = points
        .iter()
        .map(|p| {
            let PointDesc { name, body, at } = p;
            PointDesc { name: name.clone(), body: body.clone(), at: *at }
        })
        .collect();
    let loads = loads
        .iter()
        .map(|l| match l {
            // forces and torques do not depend on the angle unit (a torque is N m, not per angle)
            LoadDesc::Force { name, body, at, direction, law } => LoadDesc::Force {
                name: name.clone(),
                body: body.clone(),
                at: *at,
                direction: *direction,
                law: law.clone(),
            },
            LoadDesc::Torque { name, body, law } => {
                LoadDesc::Torque { name: name.clone(), body: body.clone(), law: law.clone() }
            }
            LoadDesc::Spring { name, body_a, at_a, body_b, at_b, stiffness, free_length, damping } => {
                LoadDesc::Spring {
                    name: name.clone(),
                    body_a: body_a.clone(),
                    at_a: *at_a,
                    body_b: body_b.clone(),
                    at_b: *at_b,
                    stiffness: *stiffness,
                    free_length: *free_length,
                    damping: *damping,
                }
            }
            // their angle units depend on the joint's kind (a revolute's angle, a prismatic's
            // slide), known once the joints compile: `compile_loads` converts them
            LoadDesc::JointForce { name, joint, of, of_joint, law } => LoadDesc::JointForce {
                name: name.clone(),
                joint: joint.clone(),
                of: *of,
                of_joint: of_joint.clone(),
                law: law.clone(),
            },
            LoadDesc::Motor { name, joint, stall, no_load_speed, clip } => LoadDesc::Motor {
                name: name.clone(),
                joint: joint.clone(),
                stall: *stall,
                no_load_speed: *no_load_speed,
                clip: *clip,
            },
            LoadDesc::Friction { name, joint, viscous, coulomb, smoothing } => LoadDesc::Friction {
                name: name.clone(),
                joint: joint.clone(),
                viscous: *viscous,
                coulomb: *coulomb,
                smoothing: *smoothing,
            },
            // torque per degree -> per radian: divide by the radians in a degree
            LoadDesc::TorsionSpring { name, body_a, body_b, stiffness, free_angle, damping } => {
                LoadDesc::TorsionSpring {
                    name: name.clone(),
                    body_a: body_a.clone(),
                    body_b: body_b.clone(),
                    stiffness: stiffness / k,
                    free_angle: k * free_angle,
                    damping: damping / k,
                }
            }
        })
        .collect();
    Description {
        name: name.clone(),
        units: Units { length: units.length, angle: AngleUnit::Radian },
        bodies,
        joints,
        drivers,
        points,
        gravity: *gravity,
        loads,
        outputs: outputs.clone(),
        branch: branch.clone(),
        close: close.clone(),
        free: *free,
        // rates in the file's units: resolved as drivers' rates (the Python package)
        initial_rates: initial_rates.iter().map(|(c, v)| (c.clone(), *v)).collect(),
    }
}

/// A linear coupling's coefficients with theta per radian (the file's are per degree:
/// c theta_deg = (c / k) theta_rad, so the value side keeps its number).
fn per_radian(c: &Coefficients, k: f64) -> Coefficients {
    let Coefficients { x, y, theta } = c;
    Coefficients { x: *x, y: *y, theta: theta / k }
}

/// A curve with its angles in radians (a polar table's angles).
fn curve_in_radians(curve: &CurveDesc, k: f64) -> CurveDesc {
    match curve {
        CurveDesc::Circle { centre, radius } => CurveDesc::Circle { centre: *centre, radius: *radius },
        CurveDesc::Spline { points } => CurveDesc::Spline { points: points.clone() },
        CurveDesc::Polar { centre, angles, radii } => CurveDesc::Polar {
            centre: *centre,
            angles: angles.iter().map(|a| k * a).collect(),
            radii: radii.clone(),
        },
        // phi is in radians whatever the declared unit, like a harmonic law's omega
        CurveDesc::PolarExpression { centre, r } => {
            CurveDesc::PolarExpression { centre: *centre, r: r.clone() }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::motion::MotionLaw;

    fn pendulum(units: Units) -> Description {
        Description {
            name: "p".into(),
            units,
            bodies: vec![BodyDesc {
                name: "bob".into(),
                x: 0.0,
                y: 0.0,
                theta: 90.0,
                mass: 1.0,
                inertia: 0.5,
                com: None,
            }],
            joints: vec![],
            drivers: vec![DriverDesc::Angle {
                name: "d".into(),
                body: "bob".into(),
                law: MotionLaw::Linear { value: 90.0, rate: 180.0 },
            }],
            points: vec![],
            gravity: [0.0, -9.81],
            loads: vec![LoadDesc::TorsionSpring {
                name: "s".into(),
                body_a: "ground".into(),
                body_b: "bob".into(),
                stiffness: 2.0,
                free_angle: 45.0,
                damping: 3.0,
            }],
            outputs: Vec::new(),
            branch: None,
            close: None,
            free: false,
            initial_rates: Default::default(),
        }
    }

    #[test]
    fn degrees_become_radians_and_only_angles_change() {
        let deg = Units { length: LengthUnit::Millimetre, angle: AngleUnit::Degree };
        let d = internal(&pendulum(deg));
        let k = std::f64::consts::PI / 180.0;
        assert_eq!(d.units, Units { length: LengthUnit::Millimetre, angle: AngleUnit::Radian });
        assert_eq!(d.bodies[0].theta, 90.0 * k);
        assert_eq!(d.bodies[0].mass, 1.0);
        let mut law = d.drivers[0].law().clone();
        law.prepare().unwrap();
        let [f, fd, fdd] = law.eval(0.5);
        assert_eq!([f, fd, fdd], [k * 180.0, k * 180.0, 0.0]);
        let LoadDesc::TorsionSpring { stiffness, free_angle, damping, .. } = d.loads[0] else {
            panic!("a torsion spring")
        };
        // 2 per degree is 2 * 180 / pi per radian
        assert_eq!((stiffness, free_angle, damping), (2.0 / k, 45.0 * k, 3.0 / k));
        // converting twice changes nothing: the result says radians
        assert_eq!(internal(&d), d);
    }

    #[test]
    fn radians_are_left_alone() {
        let d = pendulum(Units::default());
        assert_eq!(internal(&d), d);
    }
}

//! The model description: bodies placed in an approximate starting configuration,
//! joints and drivers at world points. Plain data, read from TOML or JSON model files
//! (`files`) with the numbers exactly as written, in the declared `units`;
//! `model::compile` validates it and turns it into a `Model`.

use serde::{Deserialize, Serialize};

use crate::input::curves::CurveDesc;
use crate::input::motion::MotionLaw;

/// The name of the fixed frame; it has no coordinates.
pub const GROUND: &str = "ground";

/// A whole mechanism as the user described it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Description {
    #[serde(default)]
    pub name: String,
    /// the units every number of the description is written in (default m, rad)
    #[serde(default, skip_serializing_if = "Units::is_default")]
    pub units: Units,
    #[serde(default)]
    pub bodies: Vec<BodyDesc>,
    #[serde(default, deserialize_with = "wire::joints")]
    pub joints: Vec<JointDesc>,
    #[serde(default, deserialize_with = "wire::drivers")]
    pub drivers: Vec<DriverDesc>,
    #[serde(default)]
    pub points: Vec<PointDesc>,
    /// gravitational acceleration (world), for inverse dynamics
    #[serde(default)]
    pub gravity: [f64; 2],
    /// applied forces, torques, springs and dampers, for inverse dynamics
    #[serde(default, deserialize_with = "wire::loads")]
    pub loads: Vec<LoadDesc>,
    /// what a sweep keeps unless told otherwise (bodies, columns, points, joints); empty:
    /// every coordinate. Names are resolved where sweeps are asked for (the Python package).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub outputs: Vec<String>,
    /// the assembly branch to draw a mechanism given by its pins on ("open", "crossed", or
    /// a table linkage -> circuit); resolved where it is assembled (the Python package)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub branch: Option<serde_json::Value>,
    /// what to do where a joint gives both a drawn point and its pins and they disagree:
    /// none (an error naming the joint), "given" (keep the pins, close the drawing by least
    /// squares) or "drawn" (keep the drawing's points, the pins given ignored)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub close: Option<String>,
    /// compile with the undriven coordinates free (for forward dynamics and equilibrium);
    /// read where a model is compiled (the Python package)
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub free: bool,
    /// initial rates of named coordinates ("crank.theta") for a simulation; the others
    /// follow from the constraints (resolved where a simulation starts: the Python package)
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub initial_rates: std::collections::BTreeMap<String, f64>,
}

/// A moving body and its approximate starting pose (world origin and angle).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyDesc {
    pub name: String,
    /// the starting pose; a rough one (or none: 0) where the joints give pins in the
    /// bodies' frames and the engine assembles the drawing
    #[serde(default)]
    pub x: f64,
    #[serde(default)]
    pub y: f64,
    #[serde(default)]
    pub theta: f64,
    /// mass (0: massless)
    #[serde(default)]
    pub mass: f64,
    /// moment of inertia about the centre of mass
    #[serde(default)]
    pub inertia: f64,
    /// centre of mass, a world point at the start (default: the body's origin)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub com: Option<[f64; 2]>,
}

/// A load for inverse dynamics; forces and torques follow motion laws of time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum LoadDesc {
    /// A force of magnitude f(t) along a fixed world direction, at a point of a body.
    Force { name: String, body: String, at: [f64; 2], direction: [f64; 2], law: MotionLaw },
    /// A torque f(t) on a body (counter-clockwise positive).
    Torque { name: String, body: String, law: MotionLaw },
    /// A linear spring and damper between two points: tension k (L - free_length) + c dL/dt.
    Spring {
        name: String,
        body_a: String,
        at_a: [f64; 2],
        body_b: String,
        at_b: [f64; 2],
        stiffness: f64,
        free_length: f64,
        #[serde(default)]
        damping: f64,
    },
    /// A torsional spring and damper: torque on b k (theta_b - theta_a - free_angle) + c (w_b - w_a), resisting.
    TorsionSpring {
        name: String,
        body_a: String,
        body_b: String,
        stiffness: f64,
        free_angle: f64,
        #[serde(default)]
        damping: f64,
    },
    /// A torque (revolute joint) or a force along the axis (prismatic joint) between the
    /// joint's two bodies, +f on body_b and its reaction on body_a, of magnitude f = law(x):
    /// x the coordinate (theta_b - theta_a; the slide from the start) or the rate of the
    /// joint `of_joint` (default: the joint it acts at).
    JointForce {
        name: String,
        joint: String,
        #[serde(default)]
        of: JointArgument,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        of_joint: Option<String>,
        law: MotionLaw,
    },
    /// A motor at a joint with the linear torque-speed curve f = stall (1 - rate / no_load_speed);
    /// `clip`: held between 0 and stall (no torque beyond the no-load speed, stall torque
    /// against it).
    Motor {
        name: String,
        joint: String,
        stall: f64,
        no_load_speed: f64,
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        clip: bool,
    },
    /// Friction at a joint: f = -viscous rate - coulomb tanh(rate / smoothing) (Coulomb
    /// friction of constant magnitude, smoothed over rates of about `smoothing`).
    Friction {
        name: String,
        joint: String,
        #[serde(default)]
        viscous: f64,
        #[serde(default)]
        coulomb: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        smoothing: Option<f64>,
    },
}

/// What a joint force's law is a function of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JointArgument {
    /// the joint's angle or slide
    #[default]
    Coordinate,
    /// its rate
    Rate,
}

impl LoadDesc {
    pub fn name(&self) -> &str {
        match self {
            LoadDesc::Force { name, .. }
            | LoadDesc::Torque { name, .. }
            | LoadDesc::Spring { name, .. }
            | LoadDesc::TorsionSpring { name, .. }
            | LoadDesc::JointForce { name, .. }
            | LoadDesc::Motor { name, .. }
            | LoadDesc::Friction { name, .. } => name,
        }
    }
}

/// A joint between two bodies (either may be the ground), placed at world points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum JointDesc {
    /// Pin at `at`, a world point of the drawing; or, lengths first, at `pin_a` of body_a
    /// and `pin_b` of body_b, points in each body's own frame (the ground's is the world),
    /// the drawing then assembled (`at` may be left out where both are given).
    Revolute {
        name: String,
        body_a: String,
        body_b: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        at: Option<[f64; 2]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pin_a: Option<[f64; 2]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pin_b: Option<[f64; 2]>,
    },
    /// `body_b` slides on `body_a` along `axis` through `at` (world, in the drawing); or,
    /// lengths first, along `axis_a` (or `axis`) through `pin_a`, in body_a's frame, with
    /// body_b's point `pin_b` (in its frame) on that line, `angle` = theta_b - theta_a
    /// (default: the drawing's, or 0 with pins); `travel` = [min, max], the slide's range
    /// from the start (a simulation reports its ends).
    Prismatic {
        name: String,
        body_a: String,
        body_b: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        at: Option<[f64; 2]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        axis: Option<[f64; 2]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pin_a: Option<[f64; 2]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pin_b: Option<[f64; 2]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        axis_a: Option<[f64; 2]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        angle: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        travel: Option<[f64; 2]>,
    },
    /// Weld: `body_b` keeps its starting pose relative to `body_a`.
    Fixed { name: String, body_a: String, body_b: String },
    /// A massless coupler between `at_a` (a point of `body_a`) and `at_b` (of `body_b`):
    /// their distance stays `length` (default: the distance in the drawing).
    Distance {
        name: String,
        body_a: String,
        at_a: [f64; 2],
        body_b: String,
        at_b: [f64; 2],
        #[serde(default, skip_serializing_if = "Option::is_none")]
        length: Option<f64>,
    },
    /// The point `at` of `body_a` stays at `offset` (default: the drawing's) from the line
    /// of `body_b` through `through` (default: `at`) along `axis`, measured along the
    /// axis turned by +90 degrees: a pin in a slot, or a slider block pinned to `body_a`.
    PointOnLine {
        name: String,
        body_a: String,
        body_b: String,
        at: [f64; 2],
        axis: [f64; 2],
        #[serde(default, skip_serializing_if = "Option::is_none")]
        through: Option<[f64; 2]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        offset: Option<f64>,
    },
    /// Spur gears rolling without slipping, by pitch radii or by the speed ratio
    /// r_a / r_b (radii then from the centre distance); external gears turn opposite
    /// ways, internal ones the same way; with a `carrier`, relative to it.
    Gear {
        name: String,
        body_a: String,
        body_b: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radius_a: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radius_b: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        ratio: Option<f64>,
        /// gear centres, world points at the start (default: the bodies' origins)
        #[serde(default, skip_serializing_if = "Option::is_none")]
        centre_a: Option<[f64; 2]>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        centre_b: Option<[f64; 2]>,
        #[serde(default)]
        internal: bool,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        carrier: Option<String>,
    },
    /// A pinion (`body_a`, pitch `radius`, centre `centre`, default its origin) drives a
    /// rack (`body_b`, or the ground) along `axis`: a counter-clockwise turn dtheta moves
    /// the rack by radius * dtheta along `axis`.
    RackPinion {
        name: String,
        body_a: String,
        body_b: String,
        radius: f64,
        axis: [f64; 2],
        #[serde(default, skip_serializing_if = "Option::is_none")]
        centre: Option<[f64; 2]>,
    },
    /// Belt or chain between pulleys, by pitch radii or by the ratio r_a / r_b: open
    /// belts turn both the same way, `crossed` ones opposite ways; with a `carrier`,
    /// relative to it.
    Belt {
        name: String,
        body_a: String,
        body_b: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radius_a: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radius_b: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        ratio: Option<f64>,
        #[serde(default)]
        crossed: bool,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        carrier: Option<String>,
    },
    /// theta_b - theta_a stays `angle` (default: the drawing's).
    FixedOrientation {
        name: String,
        body_a: String,
        body_b: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        angle: Option<f64>,
    },
    /// The line of `body_a` along `axis_a` stays parallel to the line of `body_b` along
    /// `axis_b` (world directions at the start).
    Parallel { name: String, body_a: String, body_b: String, axis_a: [f64; 2], axis_b: [f64; 2] },
    /// c_a . (x_a, y_a, theta_a) + c_b . (x_b, y_b, theta_b) = `value` (default: the
    /// drawing's); couples at most two bodies (either may be the ground).
    LinearCoupling {
        name: String,
        body_a: String,
        body_b: String,
        #[serde(default)]
        coefficients_a: Coefficients,
        #[serde(default)]
        coefficients_b: Coefficients,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        value: Option<f64>,
    },
    /// The point `at` of `body_b` stays on `curve`, fixed in `body_a`: a pin in a curved
    /// slot. Adds the curve parameter "<name>.s" to the coordinates.
    PinInSlot { name: String, body_a: String, body_b: String, at: [f64; 2], curve: CurveDesc },
    /// A cam `body_a` with its profile `curve` and a follower `body_b`: a knife edge (the
    /// tip `at` on the profile), a roller (of `radius`, centred at `at`) or a flat face
    /// (the line through `at` along `face`). Adds the contact's curve parameter "<name>.s".
    CamFollower {
        name: String,
        body_a: String,
        body_b: String,
        /// "knife", "roller" or "flat"
        follower: String,
        at: [f64; 2],
        curve: CurveDesc,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        radius: Option<f64>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        face: Option<[f64; 2]>,
    },
}

/// Coefficients of one body's coordinates in a linear coupling (absent ones are 0).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Coefficients {
    #[serde(default)]
    pub x: f64,
    #[serde(default)]
    pub y: f64,
    #[serde(default)]
    pub theta: f64,
}

/// A driver: one row g(q) - f(t) = 0 with a motion law f.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum DriverDesc {
    /// theta_body = f(t).
    Angle { name: String, body: String, law: MotionLaw },
    /// theta_b - theta_a = f(t).
    RelativeAngle { name: String, body_a: String, body_b: String, law: MotionLaw },
    /// |r_Pb - r_Pa| = f(t).
    Distance { name: String, body_a: String, at_a: [f64; 2], body_b: String, at_b: [f64; 2], law: MotionLaw },
    /// x or y of a point of `body` = f(t).
    Coordinate { name: String, body: String, at: [f64; 2], axis: String, law: MotionLaw },
    /// The slide of a prismatic joint = f(t).
    Translation { name: String, joint: String, law: MotionLaw },
}

/// A named point fixed in a body, given at its world position at the start.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointDesc {
    pub name: String,
    pub body: String,
    pub at: [f64; 2],
}

impl JointDesc {
    pub fn name(&self) -> &str {
        match self {
            JointDesc::Revolute { name, .. }
            | JointDesc::Prismatic { name, .. }
            | JointDesc::Fixed { name, .. }
            | JointDesc::Distance { name, .. }
            | JointDesc::PointOnLine { name, .. }
            | JointDesc::Gear { name, .. }
            | JointDesc::RackPinion { name, .. }
            | JointDesc::Belt { name, .. }
            | JointDesc::FixedOrientation { name, .. }
            | JointDesc::Parallel { name, .. }
            | JointDesc::LinearCoupling { name, .. } => name,
            JointDesc::PinInSlot { name, .. } | JointDesc::CamFollower { name, .. } => name,
        }
    }
}

impl DriverDesc {
    pub fn name(&self) -> &str {
        match self {
            DriverDesc::Angle { name, .. }
            | DriverDesc::RelativeAngle { name, .. }
            | DriverDesc::Distance { name, .. }
            | DriverDesc::Coordinate { name, .. }
            | DriverDesc::Translation { name, .. } => name,
        }
    }

    pub fn law(&self) -> &MotionLaw {
        match self {
            DriverDesc::Angle { law, .. }
            | DriverDesc::RelativeAngle { law, .. }
            | DriverDesc::Distance { law, .. }
            | DriverDesc::Coordinate { law, .. }
            | DriverDesc::Translation { law, .. } => law,
        }
    }

    pub fn law_mut(&mut self) -> &mut MotionLaw {
        match self {
            DriverDesc::Angle { law, .. }
            | DriverDesc::RelativeAngle { law, .. }
            | DriverDesc::Distance { law, .. }
            | DriverDesc::Coordinate { law, .. }
            | DriverDesc::Translation { law, .. } => law,
        }
    }

    /// Whether the driver sets an angle (rad) rather than a length.
    pub fn is_angle(&self) -> bool {
        matches!(self, DriverDesc::Angle { .. } | DriverDesc::RelativeAngle { .. })
    }
}

/// The model-file form of the tagged element lists. A file writes an element's kind as
/// its `type` key, among its fields; reading it as an externally tagged enum (the file
/// reader hands `type` over as the variant) keeps every field's own position for error
/// messages, which serde's internally tagged enums lose by buffering the whole table.
/// The `remote` mirrors are checked against the enums by the compiler both ways: a
/// variant or field missing here fails to build.
mod wire {
    use serde::{Deserialize, Deserializer, Serialize};

    use super::{Coefficients, DriverDesc, JointArgument, JointDesc, LoadDesc};
    use crate::input::curves::CurveDesc;
    use crate::input::motion::MotionLaw;

    // serialize is generated only for its exhaustive match over the real enum
    #[allow(dead_code)]
    #[derive(Serialize, Deserialize)]
    #[serde(remote = "JointDesc", rename_all = "snake_case", deny_unknown_fields)]
    enum JointWire {
        Revolute {
            name: String,
            body_a: String,
            body_b: String,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            at: Option<[f64; 2]>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pin_a: Option<[f64; 2]>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pin_b: Option<[f64; 2]>,
        },
        Prismatic {
            name: String,
            body_a: String,
            body_b: String,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            at: Option<[f64; 2]>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            axis: Option<[f64; 2]>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pin_a: Option<[f64; 2]>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pin_b: Option<[f64; 2]>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            axis_a: Option<[f64; 2]>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            angle: Option<f64>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            travel: Option<[f64; 2]>,
        },
        Fixed {
            name: String,
            body_a: String,
            body_b: String,
        },
        Distance {
            name: String,
            body_a: String,
            at_a: [f64; 2],
            body_b: String,
            at_b: [f64; 2],
            #[serde(default, skip_serializing_if = "Option::is_none")]
            length: Option<f64>,
        },
        PointOnLine {
            name: String,
            body_a: String,
            body_b: String,
            at: [f64; 2],
            axis: [f64; 2],
            #[serde(default, skip_serializing_if = "Option::is_none")]
            through: Option<[f64; 2]>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            offset: Option<f64>,
        },
        Gear {
            name: String,
            body_a: String,
            body_b: String,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            radius_a: Option<f64>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            radius_b: Option<f64>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            ratio: Option<f64>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            centre_a: Option<[f64; 2]>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            centre_b: Option<[f64; 2]>,
            #[serde(default)]
            internal: bool,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            carrier: Option<String>,
        },
        RackPinion {
            name: String,
            body_a: String,
            body_b: String,
            radius: f64,
            axis: [f64; 2],
            #[serde(default, skip_serializing_if = "Option::is_none")]
            centre: Option<[f64; 2]>,
        },
        Belt {
            name: String,
            body_a: String,
            body_b: String,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            radius_a: Option<f64>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            radius_b: Option<f64>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            ratio: Option<f64>,
            #[serde(default)]
            crossed: bool,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            carrier: Option<String>,
        },
        FixedOrientation {
            name: String,
            body_a: String,
            body_b: String,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            angle: Option<f64>,
        },
        Parallel {
            name: String,
            body_a: String,
            body_b: String,
            axis_a: [f64; 2],
            axis_b: [f64; 2],
        },
        LinearCoupling {
            name: String,
            body_a: String,
            body_b: String,
            #[serde(default)]
            coefficients_a: Coefficients,
            #[serde(default)]
            coefficients_b: Coefficients,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            value: Option<f64>,
        },
        PinInSlot {
            name: String,
            body_a: String,
            body_b: String,
            at: [f64; 2],
            curve: CurveDesc,
        },
        CamFollower {
            name: String,
            body_a: String,
            body_b: String,
            follower: String,
            at: [f64; 2],
            curve: CurveDesc,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            radius: Option<f64>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            face: Option<[f64; 2]>,
        },
    }

    #[allow(dead_code)]
    #[derive(Serialize, Deserialize)]
    #[serde(remote = "DriverDesc", rename_all = "snake_case", deny_unknown_fields)]
    enum DriverWire {
        Angle {
            name: String,
            body: String,
            law: MotionLaw,
        },
        RelativeAngle {
            name: String,
            body_a: String,
            body_b: String,
            law: MotionLaw,
        },
        Distance {
            name: String,
            body_a: String,
            at_a: [f64; 2],
            body_b: String,
            at_b: [f64; 2],
            law: MotionLaw,
        },
        Coordinate {
            name: String,
            body: String,
            at: [f64; 2],
            axis: String,
            law: MotionLaw,
        },
        Translation {
            name: String,
            joint: String,
            law: MotionLaw,
        },
    }

    #[allow(dead_code)]
    #[derive(Serialize, Deserialize)]
    #[serde(remote = "LoadDesc", rename_all = "snake_case", deny_unknown_fields)]
    enum LoadWire {
        Force {
            name: String,
            body: String,
            at: [f64; 2],
            direction: [f64; 2],
            law: MotionLaw,
        },
        Torque {
            name: String,
            body: String,
            law: MotionLaw,
        },
        Spring {
            name: String,
            body_a: String,
            at_a: [f64; 2],
            body_b: String,
            at_b: [f64; 2],
            stiffness: f64,
            free_length: f64,
            #[serde(default)]
            damping: f64,
        },
        TorsionSpring {
            name: String,
            body_a: String,
            body_b: String,
            stiffness: f64,
            free_angle: f64,
            #[serde(default)]
            damping: f64,
        },
        JointForce {
            name: String,
            joint: String,
            #[serde(default)]
            of: JointArgument,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            of_joint: Option<String>,
            law: MotionLaw,
        },
        Motor {
            name: String,
            joint: String,
            stall: f64,
            no_load_speed: f64,
            #[serde(default, skip_serializing_if = "std::ops::Not::not")]
            clip: bool,
        },
        Friction {
            name: String,
            joint: String,
            #[serde(default)]
            viscous: f64,
            #[serde(default)]
            coulomb: f64,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            smoothing: Option<f64>,
        },
    }

    #[derive(Deserialize)]
    struct Joint(#[serde(with = "JointWire")] JointDesc);
    #[derive(Deserialize)]
    struct Driver(#[serde(with = "DriverWire")] DriverDesc);
    #[derive(Deserialize)]
    struct Load(#[serde(with = "LoadWire")] LoadDesc);

    pub fn joints<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<JointDesc>, D::Error> {
        Ok(Vec::<Joint>::deserialize(d)?.into_iter().map(|j| j.0).collect())
    }
    pub fn drivers<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<DriverDesc>, D::Error> {
        Ok(Vec::<Driver>::deserialize(d)?.into_iter().map(|j| j.0).collect())
    }
    pub fn loads<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<LoadDesc>, D::Error> {
        Ok(Vec::<Load>::deserialize(d)?.into_iter().map(|j| j.0).collect())
    }
}

/// The length unit of every length of a description (and of the results).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum LengthUnit {
    #[default]
    #[serde(rename = "m")]
    Metre,
    #[serde(rename = "mm")]
    Millimetre,
}

/// The angle unit of the description's angles (results are always in radians).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum AngleUnit {
    #[default]
    #[serde(rename = "rad")]
    Radian,
    #[serde(rename = "deg")]
    Degree,
}

/// The units a description is written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Units {
    #[serde(default)]
    pub length: LengthUnit,
    #[serde(default)]
    pub angle: AngleUnit,
}

impl LengthUnit {
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Metre => "m",
            LengthUnit::Millimetre => "mm",
        }
    }
}

impl AngleUnit {
    pub fn symbol(self) -> &'static str {
        match self {
            AngleUnit::Radian => "rad",
            AngleUnit::Degree => "deg",
        }
    }

    /// Radians per unit.
    pub fn to_radians(self) -> f64 {
        match self {
            AngleUnit::Radian => 1.0,
            AngleUnit::Degree => std::f64::consts::PI / 180.0,
        }
    }
}

impl Units {
    pub fn is_default(&self) -> bool {
        *self == Units::default()
    }

    /// The unit of every quantity in and out of a model with these units, as
    /// (quantity, symbol): results give angles in rad whatever the declared angle unit.
    pub fn table(&self) -> Vec<(&'static str, &'static str)> {
        // kg L/s^2 and kg L^2/s^2: N and N m for metres, mN and mN mm (uN m) for millimetres
        let (force, torque, power, energy, stiffness) = match self.length {
            LengthUnit::Metre => ("N", "N m", "W", "J", "N/m"),
            LengthUnit::Millimetre => ("mN", "mN mm", "uW", "uJ", "mN/mm"),
        };
        vec![
            ("length", self.length.symbol()),
            ("angle", "rad"),
            ("input_angle", self.angle.symbol()),
            ("time", "s"),
            ("mass", "kg"),
            ("inertia", if self.length == LengthUnit::Metre { "kg m^2" } else { "kg mm^2" }),
            ("force", force),
            ("torque", torque),
            ("power", power),
            ("energy", energy),
            ("stiffness", stiffness),
        ]
    }
}

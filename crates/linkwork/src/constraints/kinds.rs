//! The one list of constraint kinds: every joint and driver type, its variant and label.

use crate::constraints::compile_context::{CompileContext, Compiled, Desc, FromDescription, Slide};
use crate::constraints::drivers::angle;
use crate::constraints::drivers::coordinate;
use crate::constraints::drivers::distance;
use crate::constraints::drivers::relative_angle;
use crate::constraints::drivers::translation;
use crate::constraints::joints::belt;
use crate::constraints::joints::fixed;
use crate::constraints::joints::fixed_distance;
use crate::constraints::joints::flat_follower;
use crate::constraints::joints::gear;
use crate::constraints::joints::linear_coupling;
use crate::constraints::joints::orientation;
use crate::constraints::joints::parallel;
use crate::constraints::joints::point_line;
use crate::constraints::joints::point_on_curve;
use crate::constraints::joints::prismatic;
use crate::constraints::joints::rack_pinion;
use crate::constraints::joints::revolute;
use crate::constraints::joints::roller_follower;
use crate::constraints::{Constraint, Described, Extra, Form, Frame, RowKind, Rows, Sample, MAX_ROWS};
use crate::input::motion::MotionLaw;
use crate::math::jet::{Jet, JetFrame};

macro_rules! constraint_list {
    ($($variant:ident($ty:ty) = $label:literal),* $(,)?) => {
        /// Every joint and driver type, dispatched statically.
        #[derive(Debug, Clone, PartialEq)]
        pub enum ConstraintKind {
            $($variant($ty)),*
        }

        impl ConstraintKind {
            /// The type's name as it appears in model descriptions.
            pub fn label(&self) -> &'static str {
                match self { $(ConstraintKind::$variant(_) => $label),* }
            }
        }

        impl Constraint for ConstraintKind {
            #[inline]
            fn n_rows(&self) -> usize {
                match self { $(ConstraintKind::$variant(j) => j.n_rows()),* }
            }
            #[inline]
            fn row_kinds(&self) -> &'static [RowKind] {
                match self { $(ConstraintKind::$variant(j) => j.row_kinds()),* }
            }
            #[inline]
            fn n_own(&self) -> usize {
                match self { $(ConstraintKind::$variant(j) => j.n_own()),* }
            }
            #[inline]
            fn has_extra(&self) -> bool {
                match self { $(ConstraintKind::$variant(j) => j.has_extra()),* }
            }
            fn own_start(&self, a: &Frame, b: &Frame) -> f64 {
                match self { $(ConstraintKind::$variant(j) => j.own_start(a, b)),* }
            }
            #[inline]
            fn position(&self, a: &Frame, b: &Frame, x: &Extra, t: f64, out: &mut Rows) {
                match self { $(ConstraintKind::$variant(j) => j.position(a, b, x, t, out)),* }
            }
            #[inline]
            fn nu(&self, t: f64, nu: &mut [f64; MAX_ROWS]) {
                match self { $(ConstraintKind::$variant(j) => j.nu(t, nu)),* }
            }
            #[inline]
            fn gamma(&self, a: &Frame, b: &Frame, x: &Extra, t: f64, gamma: &mut [f64; MAX_ROWS]) {
                match self { $(ConstraintKind::$variant(j) => j.gamma(a, b, x, t, gamma)),* }
            }
            fn law(&self) -> Option<&MotionLaw> {
                match self { $(ConstraintKind::$variant(j) => j.law()),* }
            }
            fn anchor_b(&self) -> [f64; 2] {
                match self { $(ConstraintKind::$variant(j) => j.anchor_b()),* }
            }
            fn params_mut(&mut self) -> Vec<(String, &mut f64)> {
                match self { $(ConstraintKind::$variant(j) => j.params_mut()),* }
            }
            #[inline]
            fn phi_jet<const W: usize>(
                &self,
                a: &JetFrame<W>,
                b: &JetFrame<W>,
                s: Jet<W>,
                t: f64,
                p: &[Jet<W>],
                out: &mut [Jet<W>; MAX_ROWS],
            ) {
                match self { $(ConstraintKind::$variant(j) => j.phi_jet(a, b, s, t, p, out)),* }
            }
        }

        impl ConstraintKind {
            /// Compiles a joint or driver description with the type whose it is.
            pub(crate) fn compile(desc: &Desc, cx: &mut dyn CompileContext) -> Result<Compiled<ConstraintKind>, String> {
                $(if let Some(c) = <$ty as FromDescription>::compile(desc, cx) {
                    return Ok(c?.map(ConstraintKind::$variant));
                })*
                Err("has a description no joint or driver type compiles".into())
            }

            /// A prismatic joint's slide, for the translation drivers that ride on it.
            pub(crate) fn slide(&self) -> Option<Slide> {
                match self { $(ConstraintKind::$variant(j) => j.slide()),* }
            }
        }

        /// One valid instance of every joint and driver type.
        pub fn samples() -> Vec<ConstraintKind> {
            vec![$(ConstraintKind::$variant(<$ty as Sample>::sample())),*]
        }

        /// Every joint and driver type's label with the description forms it compiles
        /// from, the roles of their fields: a type without `Described` does not build.
        pub fn roles() -> Vec<(&'static str, &'static [Form])> {
            vec![$(($label, <$ty as Described>::FORMS)),*]
        }
    };
}

constraint_list! {
    Revolute(revolute::Revolute) = "revolute",
    Prismatic(prismatic::Prismatic) = "prismatic",
    Fixed(fixed::Fixed) = "fixed",
    AngleDriver(angle::AngleDriver) = "angle driver",
    RelativeAngleDriver(relative_angle::RelativeAngleDriver) = "relative angle driver",
    DistanceDriver(distance::DistanceDriver) = "distance driver",
    CoordinateDriver(coordinate::CoordinateDriver) = "coordinate driver",
    TranslationDriver(translation::TranslationDriver) = "translation driver",
    Distance(fixed_distance::FixedDistance) = "distance",
    PointOnLine(point_line::PointOnLine) = "point on line",
    Gear(gear::Gear) = "gear",
    RackPinion(rack_pinion::RackPinion) = "rack and pinion",
    Belt(belt::Belt) = "belt",
    FixedOrientation(orientation::FixedOrientation) = "fixed orientation",
    Parallel(parallel::Parallel) = "parallel",
    LinearCoupling(linear_coupling::LinearCoupling) = "linear coupling",
    PointOnCurve(point_on_curve::PointOnCurve) = "point on curve",
    RollerFollower(roller_follower::RollerFollower) = "roller follower",
    FlatFollower(flat_follower::FlatFollower) = "flat follower",
}

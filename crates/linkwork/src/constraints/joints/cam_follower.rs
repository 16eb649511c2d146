//! The cam-follower description, shared by its three types (by its follower: a knife
//! edge is a point on the profile, `point_on_curve`; a roller, `roller_follower`; a flat
//! face, `flat_follower`): its checks, the profile in the cam's frame, the follower's point.

use crate::constraints::compile_context::{finite2, CompileContext};
use crate::input::curves::{Curve, CurveDesc};

/// A cam follower's checks, its profile in a's frame and its point in b's, its sides.
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
pub(crate) fn start(
    body_a: &str,
    body_b: &str,
    follower: &str,
    at: [f64; 2],
    curve: &CurveDesc,
    radius: Option<f64>,
    face: Option<[f64; 2]>,
    cx: &dyn CompileContext,
) -> Result<(Curve, [f64; 2], Option<usize>, Option<usize>), String> {
    let (a, b) = cx.pair(body_a, body_b)?;
    if !finite2(at) {
        return Err(format!("position {at:?} is not finite"));
    }
    if !["knife", "roller", "flat"].contains(&follower) {
        return Err(format!("follower must be \"knife\", \"roller\" or \"flat\", not {follower:?}"));
    }
    if radius.is_some() && follower != "roller" {
        return Err("gives a radius, which only a roller follower has".into());
    }
    if face.is_some() && follower != "flat" {
        return Err("gives a face direction, which only a flat-faced follower has".into());
    }
    let curve = curve.to_body(cx.pose(a))?;
    Ok((curve, cx.local(b, at), a, b))
}

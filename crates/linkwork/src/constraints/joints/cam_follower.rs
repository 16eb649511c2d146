//! The cam-follower description: one description, three joint types by its follower (a
//! knife edge is a point on the profile, a roller and a flat face have their own files).

use super::flat_follower::FlatFollower;
use super::point_on_curve::PointOnCurve;
use super::roller_follower::RollerFollower;
use crate::constraints::compile_context::{finite2, CompileContext, Compiled};
use crate::constraints::Frame;
use crate::input::curves::CurveDesc;

/// A compiled cam follower, by its follower.
pub(crate) enum CamFollower {
    Knife(PointOnCurve),
    Roller(RollerFollower),
    Flat(FlatFollower),
}

/// Compiles a cam-follower description: the profile in a, the follower's point in b, the
/// radius of a roller or the face of a flat follower.
#[allow(clippy::too_many_arguments)]
pub(crate) fn compile(
    body_a: &str,
    body_b: &str,
    follower: &str,
    at: [f64; 2],
    curve: &CurveDesc,
    radius: Option<f64>,
    face: Option<[f64; 2]>,
    cx: &mut dyn CompileContext,
) -> Result<Compiled<CamFollower>, String> {
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
    let u_b = cx.local(b, at);
    let frame = |b: Option<usize>| cx.pose(b).map_or(Frame::GROUND, |p| Frame::new(p, [0.0; 3]));
    let joint = match follower {
        "roller" => {
            let radius = radius.ok_or_else(|| "a roller follower needs a radius".to_string())?;
            CamFollower::Roller(RollerFollower::new(curve, u_b, radius, &frame(a), &frame(b))?)
        }
        "flat" => {
            let face = face.ok_or_else(|| "a flat-faced follower needs its face direction".to_string())?;
            CamFollower::Flat(FlatFollower::new(curve, u_b, cx.local_dir(b, face))?)
        }
        // a knife edge: its tip on the profile
        _ => CamFollower::Knife(PointOnCurve { curve, u_b }),
    };
    Ok(Compiled::new(joint, a, b))
}

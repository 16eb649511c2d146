//! Closing a drawing. Where a joint gives both a drawn point (`at`, world) and its pins in
//! the bodies' own frames, the two must agree: a drawing typed with rounded coordinates
//! would otherwise change the lengths silently. Where they do not, compiling fails with an
//! error that names the joint and the miss, unless the description asks the engine to
//! close it (`close`): keeping the pins given (the bodies moved to a closed configuration
//! near the drawing, by least squares) or keeping the drawing's points (the pins ignored).

use crate::constraints::compile_context::world;
use crate::constraints::{Constraint, Frame, RowKind, Rows};
use crate::model::closing::{Keep, PinMiss};
use crate::model::rank::{dense_jacobian, RANK_TOL};
use crate::model::ConstraintEntry;
use crate::ModelError;

/// A pin more than this times L (the model's size) from its drawn point misses: a drawing
/// computed in floating point closes to ~1e-15 L, one typed to 9 digits or fewer does not.
pub const CLOSE_TOL: f64 = 1e-9;

/// One side of a joint, for the report.
pub(crate) struct Side<'a> {
    pub joint: &'a str,
    pub body: &'a str,
    pub pin: &'static str,
}

/// Collects the misses while the joints are compiled and picks each side's pin.
pub(crate) struct Closer {
    pub keep: Option<Keep>,
    /// CLOSE_TOL L
    pub tol: f64,
    pub misses: Vec<PinMiss>,
}

impl Closer {
    /// The pin of one side of a joint in its body's frame: the one given, the drawing's
    /// (`drawn`: the world point and its place in the body's frame), or, where both are
    /// there and disagree, the one `keep` says. `pose` is the body's drawn pose (None:
    /// the ground); `normal`, for a slide, the world normal of its line (a pin need only
    /// be on the line). One of `pin` and `drawn` is always given (checked by the caller).
    pub(crate) fn side(
        &mut self,
        side: Side,
        pin: Option<[f64; 2]>,
        drawn: Option<([f64; 2], [f64; 2])>,
        pose: Option<[f64; 3]>,
        normal: Option<[f64; 2]>,
    ) -> [f64; 2] {
        match (pin, drawn) {
            (Some(p), Some((at, u))) => {
                let w = world(pose, p);
                let d = [w[0] - at[0], w[1] - at[1]];
                let miss = match normal {
                    Some(n) => (n[0] * d[0] + n[1] * d[1]).abs(),
                    None => d[0].hypot(d[1]),
                };
                if miss <= self.tol {
                    return p;
                }
                self.misses.push(PinMiss {
                    joint: side.joint.to_string(),
                    body: side.body.to_string(),
                    pin: side.pin,
                    miss,
                    given: p,
                    drawn: u,
                });
                if self.keep == Some(Keep::Drawn) {
                    u
                } else {
                    p
                }
            }
            (Some(p), None) => p,
            (None, Some((_, u))) => u,
            // excluded by the caller, which names the joint
            (None, None) => [0.0, 0.0],
        }
    }
}

/// The error for a drawing that does not close: the worst miss named, the others counted.
pub(crate) fn not_closed(misses: &[PinMiss]) -> ModelError {
    let worst = misses.iter().max_by(|a, b| a.miss.total_cmp(&b.miss)).expect("at least one miss");
    let others: Vec<String> = misses
        .iter()
        .filter(|m| !std::ptr::eq(*m, worst))
        .map(|m| format!("'{}' ({} of '{}') by {:.3e}", m.joint, m.pin, m.body, m.miss))
        .collect();
    let more = if others.is_empty() { String::new() } else { format!("; also {}", others.join(", ")) };
    ModelError::NotClosed {
        joint: worst.joint.clone(),
        miss: worst.miss,
        detail: format!(
            "its {} in '{}' {:?}, placed by the body's drawn pose, misses the drawn point by {:.3e} \
             (the drawing puts it at {:?} in the body's frame){more}. Fix the drawing or the pins, or let \
             the engine close it: close = \"given\" (keeps the pins, moves the bodies by least squares) or \
             close = \"drawn\" (keeps the drawing's points) in the model header; Python: Mechanism.close",
            worst.pin, worst.body, worst.given, worst.miss, worst.drawn
        ),
    }
}

/// Moves `q` (the drawing) to a configuration where every joint holds with the pins
/// given: Gauss-Newton with minimum-norm steps (the SVD's pseudo-inverse) on the joints'
/// rows alone, scaled as the solver scales them, so each step is the least-squares one
/// and the result is near the drawing. Fails, naming the joint that misses most, where
/// the joints cannot all hold with those pins (the least-squares residual is not 0).
pub(crate) fn close_given(
    constraints: &[ConstraintEntry],
    col_scale: &[f64],
    length_scale: f64,
    q: &mut [f64],
) -> Result<(), ModelError> {
    let n_coords = col_scale.len();
    let joints: Vec<&ConstraintEntry> = constraints.iter().filter(|c| c.role == "joint").collect();
    for _ in 0..50 {
        let (phi, _) = residual(&joints, length_scale, q);
        let norm = phi.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if norm <= 1e-14 {
            return Ok(());
        }
        let jac = dense_jacobian(&joints, n_coords, length_scale, q, 0.0);
        let d =
            jac.svd().map_err(|_| ModelError::Description("closing the drawing: the SVD failed".into()))?;
        let (s, u, v) = (d.S().column_vector(), d.U(), d.V());
        let top = s.iter().copied().fold(0.0f64, f64::max);
        let mut step = vec![0.0; n_coords];
        for k in 0..s.nrows() {
            if s[k] <= RANK_TOL * top {
                continue;
            }
            let coef = (0..phi.len()).map(|i| u[(i, k)] * phi[i]).sum::<f64>() / s[k];
            for (j, st) in step.iter_mut().enumerate() {
                *st -= coef * v[(j, k)];
            }
        }
        let size = step.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for ((qj, st), cs) in q.iter_mut().zip(&step).zip(col_scale) {
            *qj += cs * st;
        }
        if size <= 1e-15 {
            break;
        }
    }
    let (phi, (miss, joint)) = residual(&joints, length_scale, q);
    if phi.iter().fold(0.0f64, |m, v| m.max(v.abs())) <= CLOSE_TOL {
        return Ok(());
    }
    Err(ModelError::NotClosed {
        joint: joint.clone(),
        miss,
        detail: format!(
            "with the pins given the joints cannot all hold: the closest configuration (least squares) \
             leaves '{joint}' missing by {miss:.3e}; the lengths given do not assemble"
        ),
    })
}

/// The joints' scaled residual at q, and (how far, which joint) misses most, in the
/// model's length unit (an angle row's miss as the arc it makes at L).
fn residual(joints: &[&ConstraintEntry], length_scale: f64, q: &[f64]) -> (Vec<f64>, (f64, String)) {
    let frame = |b: Option<usize>| match b {
        Some(i) => Frame::new([q[3 * i], q[3 * i + 1], q[3 * i + 2]], [0.0; 3]),
        None => Frame::GROUND,
    };
    let mut phi = Vec::new();
    let mut worst = (0.0, String::new());
    for c in joints {
        let mut rows = Rows::default();
        c.kind.position(&frame(c.body_a), &frame(c.body_b), &c.extra(q, &[]), 0.0, &mut rows);
        for (i, kind) in c.kind.row_kinds().iter().enumerate().take(c.n_rows) {
            phi.push(rows.phi[i] * c.row_scale[i]);
            let size =
                if *kind == RowKind::Length { rows.phi[i].abs() } else { rows.phi[i].abs() * length_scale };
            if size > worst.0 {
                worst = (size, c.name.clone());
            }
        }
    }
    (phi, worst)
}

#[cfg(test)]
mod tests {
    use crate::{Description, Model, ModelError};

    /// The textbook four-bar drawn, joint B also giving its pins, B's drawn point moved by
    /// `shift` along x and the coupler's pose by `turn`; closed as `close` says.
    fn four_bar(shift: f64, turn: f64, close: &str) -> Result<Model, ModelError> {
        let close = if close.is_empty() { String::new() } else { format!(r#""close": "{close}","#) };
        let text = format!(
            r#"{{"name": "four-bar", {close}
            "bodies": [{{"name": "crank"}},
                       {{"name": "coupler", "x": 0.2, "theta": {}}},
                       {{"name": "rocker", "x": 0.35, "theta": 1.0471975511965974}}],
            "joints": [
              {{"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [0, 0]}},
              {{"type": "revolute", "name": "A", "body_a": "crank", "body_b": "coupler", "at": [0.2, 0]}},
              {{"type": "revolute", "name": "B", "body_a": "coupler", "body_b": "rocker",
                "at": [{}, 0.2165063509461096], "pin_a": [0.35, 0], "pin_b": [0.25, 0]}},
              {{"type": "revolute", "name": "O4", "body_a": "ground", "body_b": "rocker", "at": [0.35, 0]}}],
            "drivers": [{{"type": "angle", "name": "crank_angle", "body": "crank",
                          "law": {{"type": "linear", "value": 0, "rate": 5}}}}]}}"#,
            0.6669463445036641 + turn,
            0.47500000000000003 + shift
        );
        Model::new(Description::from_json(&text)?)
    }

    #[test]
    fn a_miss_names_the_joint_unless_closed() {
        // exact to round-off: nothing to report
        assert!(four_bar(0.0, 0.0, "").unwrap().closing.is_none());
        match four_bar(1e-3, 0.0, "") {
            Err(ModelError::NotClosed { joint, miss, .. }) => {
                assert_eq!(joint, "B");
                assert!((miss - 1e-3).abs() < 1e-15, "{miss}");
            }
            other => panic!("expected NotClosed, got {other:?}"),
        }
        // the coupler turned by 1e-4 rad: keeping the pins, the bodies move until B holds
        let model = four_bar(0.0, 1e-4, "given").unwrap();
        let closing = model.closing.as_ref().unwrap();
        assert_eq!(closing.misses[0].joint, "B");
        let q = &model.q_start;
        let (c, r) = (&q[3..6], &q[6..9]);
        let on_coupler = [c[0] + 0.35 * c[2].cos(), c[1] + 0.35 * c[2].sin()];
        let on_rocker = [r[0] + 0.25 * r[2].cos(), r[1] + 0.25 * r[2].sin()];
        let miss = (on_coupler[0] - on_rocker[0]).hypot(on_coupler[1] - on_rocker[1]);
        assert!(miss < 1e-14, "{miss}");
        assert!(closing.moved.iter().all(|(_, d, t)| *d < 1e-4 && t.abs() < 1e-4));
        // keeping the drawing: the bodies stay, the coupler's pin is the drawing's
        let model = four_bar(0.0, 1e-4, "drawn").unwrap();
        assert!(model.closing.as_ref().unwrap().moved.is_empty());
        assert!(matches!(four_bar(0.0, 0.0, "nearest"), Err(ModelError::Description(_))));
    }
}

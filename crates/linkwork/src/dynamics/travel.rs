//! Limits of a slider's motion in a simulation, found from the accepted steps and located
//! between them on the interpolant of the steps' ends (`events`):
//! - the end of the travel a prismatic joint is given (`travel = [min, max]`, its slide from
//!   the start, as a translation driver's): where the slide crosses min or max, an
//!   "end_of_travel" event; the simulation stops there (`SimOptions::stop_at_travel_end`,
//!   the rows up to it kept) or goes on through it (no stop is modelled), reporting it;
//! - a slider's geometric limit (the end of a slider-crank's stroke): where its rate changes
//!   sign while the mechanism moves on and its slide is stationary along every motion the
//!   joints allow there, a "lock" of that slider (as a sweep reports an output's).
#![allow(clippy::needless_range_loop)] // numeric kernels: one index runs over several arrays

use nalgebra::DMatrix;

use crate::constraints::joints::prismatic::line_row;
use crate::constraints::kinds::ConstraintKind;
use crate::constraints::loads::JointAxis;
use crate::constraints::{Frame, Rows};
use crate::dynamics::output::SimOutput;
use crate::error::SolveError;
use crate::model::Model;

/// A slide reversal is the slider's geometric limit when the part of its gradient along
/// the motions the joints allow is below this fraction of the whole: zero at a stroke's
/// end up to the interpolant's error (1e-6 and less on the tests), of order one where
/// forces turn a slider that could go on.
pub const GEOMETRIC_BELOW: f64 = 1e-2;

/// A prismatic joint of the model: its slide and the travel it is given.
#[derive(Debug, Clone)]
pub struct Slider {
    pub name: String,
    e_a: [f64; 2],
    u_a: [f64; 2],
    u_b: [f64; 2],
    body_a: Option<usize>,
    body_b: Option<usize>,
    pub travel: Option<[f64; 2]>,
}

/// The model's prismatic joints.
pub fn sliders(model: &Model) -> Vec<Slider> {
    model
        .constraints
        .iter()
        .filter(|c| c.role == "joint")
        .filter_map(|c| match &c.kind {
            ConstraintKind::Prismatic(p) => Some(Slider {
                name: c.name.clone(),
                e_a: p.e_a,
                u_a: p.u_a,
                u_b: p.u_b,
                body_a: c.body_a,
                body_b: c.body_b,
                travel: p.travel,
            }),
            _ => None,
        })
        .collect()
}

fn frame(q: &[f64], qd: &[f64], body: Option<usize>) -> Frame {
    body.map_or(Frame::GROUND, |i| {
        Frame::new([q[3 * i], q[3 * i + 1], q[3 * i + 2]], [qd[3 * i], qd[3 * i + 1], qd[3 * i + 2]])
    })
}

impl Slider {
    /// The slide from the start and its rate at (q, qd).
    pub fn slide(&self, q: &[f64], qd: &[f64]) -> (f64, f64) {
        let axis = JointAxis::Slide { u_a: self.u_a, u_b: self.u_b, e_a: self.e_a };
        axis.coordinate(&frame(q, qd, self.body_a), &frame(q, qd, self.body_b))
    }

    /// d(slide)/dq at q, per scaled coordinate (q_i / col_scale_i).
    pub fn gradient(&self, model: &Model, q: &[f64]) -> Vec<f64> {
        let zero = vec![0.0; q.len()];
        let (a, b) = (frame(q, &zero, self.body_a), frame(q, &zero, self.body_b));
        let mut rows = Rows::default();
        line_row(self.e_a, self.u_a, self.u_b, &a, &b, 0, &mut rows);
        let mut g = vec![0.0; model.n_coords];
        for j in 0..3 {
            if let Some(i) = self.body_a {
                g[3 * i + j] += rows.jac_a[0][j];
            }
            if let Some(i) = self.body_b {
                g[3 * i + j] += rows.jac_b[0][j];
            }
        }
        g.iter_mut().zip(&model.col_scale).for_each(|(v, s)| *v *= s);
        g
    }

    /// The fraction of the slide's gradient along the motions the joints allow at q
    /// (`basis`: their rows, in scaled coordinates): 0 where the slide is stationary
    /// whichever way the mechanism moves, a stroke's end.
    pub fn free_share(&self, model: &Model, q: &[f64], basis: &DMatrix<f64>) -> f64 {
        let g = nalgebra::DVector::from_vec(self.gradient(model, q));
        let norm = g.norm();
        if norm == 0.0 {
            return 0.0;
        }
        let qr = basis.transpose().qr();
        (qr.q().transpose() * &g).norm() / norm
    }
}

/// Refuses a start outside a slider's travel.
pub fn check_start(model: &Model, q: &[f64], qd: &[f64]) -> Result<(), SolveError> {
    for s in sliders(model) {
        let Some([lo, hi]) = s.travel else { continue };
        let (x, _) = s.slide(q, qd);
        if x < lo || x > hi {
            return Err(SolveError::Settings {
                problem: format!(
                    "prismatic joint '{}' starts at slide {x:.6e}, outside its travel [{lo}, {hi}] \
                     (the slide from the drawing)",
                    s.name
                ),
            });
        }
    }
    Ok(())
}

/// A simulation stopped at t by a travel's end: the rows asked after it are dropped.
pub fn stop_at(out: &mut SimOutput, t: f64) {
    out.n_done = out.n_done.min(out.times.partition_point(|&x| x <= t));
    out.events.sort_by(|a, b| a.time.total_cmp(&b.time));
}

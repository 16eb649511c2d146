//! A model's sliders: each prismatic joint's slide from the start (as a translation
//! driver's coordinate) and the travel it is given (`travel = [min, max]`), read by a
//! simulation (`dynamics::travel`) and a sweep (`sweep::stepping::travel`) alike.
#![allow(clippy::needless_range_loop)] // numeric kernels: one index runs over several arrays

use nalgebra::DMatrix;

use crate::constraints::joints::prismatic::line_row;
use crate::constraints::kinds::ConstraintKind;
use crate::constraints::loads::JointAxis;
use crate::constraints::{Frame, Rows};
use crate::model::Model;

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

    /// The translation driver that sets this slide (on the same two bodies), if any.
    pub fn driver<'m>(&self, model: &'m Model) -> Option<&'m str> {
        slide_driver(model, self.body_a, self.body_b)
    }
}

/// The translation driver between bodies a and b (a prismatic joint's slide it sets), if any.
pub fn slide_driver(model: &Model, body_a: Option<usize>, body_b: Option<usize>) -> Option<&str> {
    model
        .constraints
        .iter()
        .find(|d| {
            matches!(d.kind, ConstraintKind::TranslationDriver(_)) && d.body_a == body_a && d.body_b == body_b
        })
        .map(|d| d.name.as_str())
}

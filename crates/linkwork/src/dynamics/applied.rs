//! The generalized applied force Q_A(q, qd, t) of M qdd + Phi_q^T lambda = Q_A: gravity,
//! the applied loads (forces, torques, spring-dampers) and each body's quadratic-velocity
//! inertia term (an off-centre centre of mass: m A u_c w^2). Its exact tangents come from
//! the jets the loads and bodies already have (forward-mode differentiation in the
//! directions of every coordinate and rate of the bodies involved): no differences.
#![allow(clippy::needless_range_loop)] // numeric kernels: one index runs over several arrays

use crate::constraints::loads::{Inertia, LoadEntry};
use crate::constraints::Frame;
use crate::math::jet::{Jet, JetFrame};
use crate::model::Model;

#[inline(always)]
fn side(frames: &[Frame], body: Option<usize>) -> &Frame {
    match body {
        Some(i) => &frames[i],
        None => &Frame::GROUND,
    }
}

/// Writes Q_A (n_coords) at the frames' poses and velocities, time t.
pub fn applied_force(model: &Model, frames: &[Frame], t: f64, q_out: &mut [f64]) {
    q_out.fill(0.0);
    for (i, body) in model.inertias.iter().enumerate() {
        let f = &frames[i];
        // -M qdd + Q_v at qdd = 0 is Q_v: m A u_c w^2 on the translations, none on theta
        let qv = body.inertia_force(f, &[0.0; 3]);
        let qg = body.gravity_force(f, model.gravity);
        for j in 0..3 {
            q_out[3 * i + j] = qv[j] + qg[j];
        }
    }
    for l in &model.loads {
        l.add_to(side(frames, l.body_a), side(frames, l.body_b), t, q_out);
    }
}

/// One 3 x 3 block of the tangents: K = dr/dq and C = dr/dqd of r = M qdd - Q_A between
/// the coordinates of body `row` (r's entries) and body `col`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentBlock {
    pub row: usize,
    pub col: usize,
    pub k: [[f64; 3]; 3],
    pub c: [[f64; 3]; 3],
}

/// The coordinates (value, rate, acceleration) of one body as jets differentiated in six
/// directions starting at `d0`: its three values, then its three rates.
fn body_jets<const W: usize>(q: &[f64], qd: &[f64], qdd: &[f64], d0: usize) -> [Jet<W>; 3] {
    std::array::from_fn(|j| {
        let unit = |k: usize| std::array::from_fn(|d| if d == k { 1.0 } else { 0.0 });
        Jet::motion(q[j], qd[j], qdd[j], unit(d0 + j), unit(d0 + 3 + j))
    })
}

/// The per-load data `tangents` needs: the load with its sides renumbered 0 (a) and 1
/// (b) so that its jets write six entries, and its numbers.
#[derive(Debug, Clone)]
pub struct LoadJet {
    local: LoadEntry,
    params: Vec<f64>,
}

impl LoadJet {
    pub fn new(l: &LoadEntry) -> LoadJet {
        let local = LoadEntry {
            name: l.name.clone(),
            load: l.load.clone(),
            body_a: l.body_a.map(|_| 0),
            body_b: l.body_b.map(|_| 1),
        };
        let params = local.load.clone().params_mut().into_iter().map(|(_, v)| *v).collect();
        LoadJet { local, params }
    }
}

/// The tangents of r(q, qd, qdd) = M(q) qdd - Q_A(q, qd, t) at (q, qd, qdd): per body
/// (inertia, gravity, quadratic velocity) and per load, blocks of dr/dq and dr/dqd
/// (a load between two bodies gives four). With qdd = 0, K = -dQ_A/dq and C = -dQ_A/dqd.
/// Calls `out` with each block (blocks of one pair of bodies may repeat: they add).
pub fn tangents(
    model: &Model,
    loads: &[LoadJet],
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    t: f64,
    out: &mut dyn FnMut(TangentBlock),
) {
    let g = [Jet::<6>::cst(model.gravity[0]), Jet::cst(model.gravity[1])];
    for (i, body) in model.inertias.iter().enumerate() {
        let s = 3 * i..3 * i + 3;
        let f = JetFrame::new(body_jets::<6>(&q[s.clone()], &qd[s.clone()], &qdd[s], 0));
        let p = [body.mass, body.inertia, body.com[0], body.com[1]].map(Jet::<6>::cst);
        // force_jet is Q_A's inertial and gravity part minus M qdd: r = -it
        let r = Inertia::force_jet(&f, &p, g);
        let mut b = TangentBlock { row: i, col: i, k: [[0.0; 3]; 3], c: [[0.0; 3]; 3] };
        for j in 0..3 {
            for k in 0..3 {
                b.k[j][k] = -r[j].e[k][0];
                b.c[j][k] = -r[j].e[3 + k][0];
            }
        }
        out(b);
    }
    for (lj, l) in loads.iter().zip(&model.loads) {
        let frame = |body: Option<usize>, d0: usize| match body {
            Some(i) => {
                let s = 3 * i..3 * i + 3;
                JetFrame::new(body_jets::<12>(&q[s.clone()], &qd[s.clone()], &[0.0; 3], d0))
            }
            None => JetFrame::ground(),
        };
        let (fa, fb) = (frame(l.body_a, 0), frame(l.body_b, 6));
        let p: Vec<Jet<12>> = lj.params.iter().map(|&v| Jet::cst(v)).collect();
        let mut qj = [Jet::<12>::ZERO; 6];
        lj.local.add_jet(&fa, &fb, t, &p, &mut qj);
        let sides = [(l.body_a, 0usize), (l.body_b, 1usize)];
        for &(row, rs) in &sides {
            let Some(row) = row else { continue };
            for &(col, cs) in &sides {
                let Some(col) = col else { continue };
                let mut b = TangentBlock { row, col, k: [[0.0; 3]; 3], c: [[0.0; 3]; 3] };
                for j in 0..3 {
                    for k in 0..3 {
                        b.k[j][k] = -qj[3 * rs + j].e[6 * cs + k][0];
                        b.c[j][k] = -qj[3 * rs + j].e[6 * cs + 3 + k][0];
                    }
                }
                out(b);
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::input::description::Description;
    use crate::model::Options;

    /// Two bodies with off-centre masses, gravity, a spring-damper between them, a
    /// torsion spring-damper to ground, a force and a torque; a double pendulum (free).
    pub(crate) fn loaded_pair() -> Model {
        let json = r#"{
          "name": "pair", "gravity": [0.3, -9.81],
          "bodies": [
            {"name": "a", "x": 0.1, "y": 0.2, "theta": 0.3, "mass": 1.5, "inertia": 0.02, "com": [0.35, 0.1]},
            {"name": "b", "x": 0.8, "y": -0.1, "theta": -0.4, "mass": 0.7, "inertia": 0.01, "com": [0.9, 0.05]}
          ],
          "joints": [
            {"type": "revolute", "name": "A", "body_a": "ground", "body_b": "a", "at": [0.0, 0.0]},
            {"type": "revolute", "name": "B", "body_a": "a", "body_b": "b", "at": [0.8, -0.1]}
          ],
          "loads": [
            {"type": "spring", "name": "s", "body_a": "a", "at_a": [0.5, 0.3], "body_b": "b", "at_b": [1.1, -0.2],
             "stiffness": 40.0, "free_length": 0.2, "damping": 1.5},
            {"type": "torsion_spring", "name": "ts", "body_a": "ground", "body_b": "b", "stiffness": 3.0,
             "free_angle": 0.1, "damping": 0.4},
            {"type": "force", "name": "f", "body": "b", "at": [1.0, 0.0], "direction": [0.6, 0.8],
             "law": {"type": "linear", "value": 2.0, "rate": 1.0}},
            {"type": "torque", "name": "tq", "body": "a", "law": {"type": "constant", "value": 0.5}},
            {"type": "joint_force", "name": "jf", "joint": "B", "of": "coordinate",
             "law": {"type": "spline", "times": [-2.0, -0.5, 0.0, 1.0], "values": [3.0, -1.0, 2.0, 0.5]}},
            {"type": "motor", "name": "m", "joint": "A", "stall": 4.0, "no_load_speed": 6.0},
            {"type": "friction", "name": "fr", "joint": "B", "viscous": 0.3, "coulomb": 0.8, "smoothing": 2.0}
          ]
        }"#;
        let options = Options { free: true, ..Options::default() };
        Model::with_options(Description::from_json(json).unwrap(), options).unwrap()
    }

    /// A body pinned to the ground and a slider on it (the prismatic's axis turns with its
    /// body), with a force law of the slide, a linear motor and friction along it.
    pub(crate) fn loaded_slider() -> Model {
        let json = r#"{
          "name": "slider", "gravity": [0.0, -9.81],
          "bodies": [
            {"name": "arm", "x": 0.0, "y": 0.0, "theta": 0.4, "mass": 2.0, "inertia": 0.1, "com": [0.3, 0.1]},
            {"name": "block", "x": 0.5, "y": 0.2, "theta": 0.4, "mass": 0.6, "inertia": 0.005}
          ],
          "joints": [
            {"type": "revolute", "name": "A", "body_a": "ground", "body_b": "arm", "at": [0.0, 0.0]},
            {"type": "prismatic", "name": "P", "body_a": "arm", "body_b": "block", "at": [0.5, 0.2],
             "axis": [0.92, 0.39]}
          ],
          "loads": [
            {"type": "joint_force", "name": "gas", "joint": "P",
             "law": {"type": "spline", "times": [-0.5, 0.0, 0.2, 0.6], "values": [10.0, 40.0, 5.0, 1.0]}},
            {"type": "motor", "name": "m", "joint": "P", "stall": 3.0, "no_load_speed": -2.0},
            {"type": "friction", "name": "fr", "joint": "P", "viscous": 0.7, "coulomb": 1.5, "smoothing": 0.3},
            {"type": "joint_force", "name": "damper", "joint": "A", "of": "rate",
             "law": {"type": "polynomial", "coefficients": [0.2, -0.5, 0.3]}}
          ]
        }"#;
        let options = Options { free: true, ..Options::default() };
        Model::with_options(Description::from_json(json).unwrap(), options).unwrap()
    }

    fn residual(model: &Model, q: &[f64], qd: &[f64], qdd: &[f64], t: f64) -> Vec<f64> {
        let frames: Vec<Frame> = (0..model.n_bodies)
            .map(|i| {
                Frame::new([q[3 * i], q[3 * i + 1], q[3 * i + 2]], [qd[3 * i], qd[3 * i + 1], qd[3 * i + 2]])
            })
            .collect();
        let mut qa = vec![0.0; model.n_coords];
        applied_force(model, &frames, t, &mut qa);
        let mut r: Vec<f64> = qa.iter().map(|v| -v).collect();
        for (i, body) in model.inertias.iter().enumerate() {
            let m = crate::dynamics::mass::mass_block(body, &frames[i]);
            for j in 0..3 {
                r[3 * i + j] += (0..3).map(|k| m[j][k] * qdd[3 * i + k]).sum::<f64>();
            }
        }
        r
    }

    /// K and C from the jets against central differences of r = M qdd - Q_A, with and
    /// without accelerations (differences of step 1e-6: error ~1e-9 of entries ~10-100).
    #[test]
    fn tangents_match_finite_differences() {
        for model in [loaded_pair(), loaded_slider()] {
            tangents_match_finite_differences_of(&model);
        }
    }

    fn tangents_match_finite_differences_of(model: &Model) {
        let n = model.n_coords;
        let loads: Vec<LoadJet> = model.loads.iter().map(LoadJet::new).collect();
        let q = vec![0.1, 0.2, 0.3, 0.8, -0.1, -0.4];
        let qd = vec![0.4, -0.3, 1.7, -0.2, 0.5, -2.1];
        let t = 0.6;
        for qdd in [vec![0.0; 6], vec![1.0, -2.0, 3.0, 0.5, 0.7, -4.0]] {
            let (mut k, mut c) = (vec![0.0; n * n], vec![0.0; n * n]);
            tangents(model, &loads, &q, &qd, &qdd, t, &mut |b| {
                for j in 0..3 {
                    for l in 0..3 {
                        k[(3 * b.row + j) * n + 3 * b.col + l] += b.k[j][l];
                        c[(3 * b.row + j) * n + 3 * b.col + l] += b.c[j][l];
                    }
                }
            });
            let h = 1e-6;
            for col in 0..n {
                for (which, m) in [(0, &k), (1, &c)] {
                    let (mut up, mut down) = ((q.clone(), qd.clone()), (q.clone(), qd.clone()));
                    if which == 0 {
                        up.0[col] += h;
                        down.0[col] -= h;
                    } else {
                        up.1[col] += h;
                        down.1[col] -= h;
                    }
                    let (ru, rd) =
                        (residual(model, &up.0, &up.1, &qdd, t), residual(model, &down.0, &down.1, &qdd, t));
                    for row in 0..n {
                        let fd = (ru[row] - rd[row]) / (2.0 * h);
                        let got = m[row * n + col];
                        assert!(
                            (got - fd).abs() < 1e-7 * (1.0 + fd.abs()),
                            "{} ({row}, {col}): jets {got} vs differences {fd}",
                            ["K", "C"][which]
                        );
                    }
                }
            }
            // not all zero: the test can fail
            assert!(k.iter().any(|v| v.abs() > 1.0) && c.iter().any(|v| v.abs() > 0.1));
        }
    }
}

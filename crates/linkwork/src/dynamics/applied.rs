//! The generalized applied force Q_A(q, qd, t) of M qdd + Phi_q^T lambda = Q_A: gravity,
//! the applied loads (forces, torques, spring-dampers) and each body's quadratic-velocity
//! inertia term (an off-centre centre of mass: m A u_c w^2). Its exact tangents come from
//! the jets the loads and bodies already have (forward-mode differentiation in the
//! directions of every coordinate and rate of the bodies involved): no differences.
#![allow(clippy::needless_range_loop)] // numeric kernels: one index runs over several arrays

use crate::constraints::loads::{Inertia, Load, LoadEntry, ReadJoint};
use crate::constraints::Frame;
use crate::math::jet::{Jet, JetFrame};
use crate::model::Model;

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
        l.add_to(frames, t, q_out);
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
/// (b), and a joint force's joint read 2 and 3, so that its jets write six (twelve)
/// entries; the bodies they stand for, and its numbers.
#[derive(Debug, Clone)]
pub struct LoadJet {
    local: LoadEntry,
    sides: [Option<usize>; 4],
    params: Vec<f64>,
}

impl LoadJet {
    pub fn new(l: &LoadEntry) -> LoadJet {
        let mut load = l.load.clone();
        let mut sides = [l.body_a, l.body_b, None, None];
        if let Load::JointForce { reads: Some(r), .. } = &mut load {
            sides[2..].copy_from_slice(&[r.body_a, r.body_b]);
            *r = ReadJoint { axis: r.axis, body_a: r.body_a.map(|_| 2), body_b: r.body_b.map(|_| 3) };
        }
        let local = LoadEntry {
            name: l.name.clone(),
            load,
            body_a: l.body_a.map(|_| 0),
            body_b: l.body_b.map(|_| 1),
        };
        let params = local.load.clone().params_mut().into_iter().map(|(_, v)| *v).collect();
        LoadJet { local, sides, params }
    }

    /// Sides 0 and 1, or all four (a joint force reading another joint).
    fn n_sides(&self) -> usize {
        if matches!(self.local.load, Load::JointForce { reads: Some(_), .. }) {
            4
        } else {
            2
        }
    }

    /// The blocks of one load, W = 6 x its sides: each side's coordinates and rates are
    /// directions of the jets; a body that is two sides gets the sum of their blocks.
    fn blocks<const W: usize>(&self, q: &[f64], qd: &[f64], t: f64, out: &mut dyn FnMut(TangentBlock)) {
        let n = W / 6;
        let frames: [JetFrame<W>; 4] = std::array::from_fn(|s| match self.sides[s] {
            Some(i) if s < n => {
                let at = 3 * i..3 * i + 3;
                JetFrame::new(body_jets::<W>(&q[at.clone()], &qd[at], &[0.0; 3], 6 * s))
            }
            _ => JetFrame::ground(),
        });
        let p: Vec<Jet<W>> = self.params.iter().map(|&v| Jet::cst(v)).collect();
        let mut qj = [Jet::<W>::ZERO; 12];
        self.local.add_jet(&frames[..n], t, &p, &mut qj[..3 * n]);
        for (rs, &row) in self.sides[..n].iter().enumerate() {
            let Some(row) = row else { continue };
            for (cs, &col) in self.sides[..n].iter().enumerate() {
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
    for lj in loads {
        if lj.n_sides() == 4 {
            lj.blocks::<24>(q, qd, t, out);
        } else {
            lj.blocks::<12>(q, qd, t, out);
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

    /// A slider-crank whose piston carries a force of the crank's angle (a gas force of the
    /// cycle), whose crank carries a torque of the piston's rate, and whose rod carries a
    /// torque at the crank pin of the slide (the loads and the joints read share no body).
    pub(crate) fn loaded_crossed() -> Model {
        let json = r#"{
          "name": "crossed", "gravity": [0.0, -9.81],
          "bodies": [
            {"name": "crank", "x": 0.0, "y": 0.0, "theta": 0.5, "mass": 1.0, "inertia": 0.05, "com": [0.02, 0.01]},
            {"name": "rod", "x": 0.0877, "y": 0.0479, "theta": -0.2, "mass": 0.4, "inertia": 0.002},
            {"name": "piston", "x": 0.33, "y": 0.0, "theta": 0.0, "mass": 0.3, "inertia": 1e-4}
          ],
          "joints": [
            {"type": "revolute", "name": "main", "body_a": "ground", "body_b": "crank", "at": [0.0, 0.0]},
            {"type": "revolute", "name": "pin", "body_a": "crank", "body_b": "rod", "at": [0.0877, 0.0479]},
            {"type": "revolute", "name": "wrist", "body_a": "rod", "body_b": "piston", "at": [0.33, 0.0]},
            {"type": "prismatic", "name": "cyl", "body_a": "ground", "body_b": "piston", "at": [0.33, 0.0],
             "axis": [0.96, 0.28]}
          ],
          "loads": [
            {"type": "joint_force", "name": "gas", "joint": "cyl", "of_joint": "main",
             "law": {"type": "harmonic", "mean": -40.0, "amplitude": 90.0, "omega": 1.0, "phase": 0.4}},
            {"type": "joint_force", "name": "drag", "joint": "main", "of_joint": "cyl", "of": "rate",
             "law": {"type": "polynomial", "coefficients": [0.5, -3.0, 2.0]}},
            {"type": "joint_force", "name": "twist", "joint": "pin", "of_joint": "cyl",
             "law": {"type": "polynomial", "coefficients": [1.0, 20.0, -50.0]}}
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
        for model in [loaded_pair(), loaded_slider(), loaded_crossed()] {
            tangents_match_finite_differences_of(&model);
        }
    }

    /// K and C as dense n x n matrices, row-major.
    fn dense_tangents(
        model: &Model,
        loads: &[LoadJet],
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        t: f64,
    ) -> (Vec<f64>, Vec<f64>) {
        let n = model.n_coords;
        let (mut k, mut c) = (vec![0.0; n * n], vec![0.0; n * n]);
        tangents(model, loads, q, qd, qdd, t, &mut |b| {
            for j in 0..3 {
                for l in 0..3 {
                    k[(3 * b.row + j) * n + 3 * b.col + l] += b.k[j][l];
                    c[(3 * b.row + j) * n + 3 * b.col + l] += b.c[j][l];
                }
            }
        });
        (k, c)
    }

    /// A force at one joint of another joint's coordinate or rate couples bodies that
    /// share no joint or load otherwise: the piston's force moves with the crank's angle
    /// (K), the crank's torque with the piston's rate (C). Their values are checked by
    /// `tangents_match_finite_differences`; here, that they are there (the augmented
    /// matrix's pattern holds them: gen-alpha on such a model, tests/test_dynamics_loads.py).
    #[test]
    fn loads_of_another_joint_couple_its_bodies() {
        let model = loaded_crossed();
        let n = model.n_coords;
        let loads: Vec<LoadJet> = model.loads.iter().map(LoadJet::new).collect();
        let q = model.q_start.clone();
        let qd: Vec<f64> = (0..n).map(|i| 0.3 + 0.1 * i as f64).collect();
        let (k, c) = dense_tangents(&model, &loads, &q, &qd, &vec![0.0; n], 0.0);
        let (crank_theta, piston_x) = (2, 6);
        assert!(k[piston_x * n + crank_theta].abs() > 1.0, "{}", k[piston_x * n + crank_theta]);
        assert!(c[crank_theta * n + piston_x].abs() > 0.1, "{}", c[crank_theta * n + piston_x]);
    }

    fn tangents_match_finite_differences_of(model: &Model) {
        let n = model.n_coords;
        let loads: Vec<LoadJet> = model.loads.iter().map(LoadJet::new).collect();
        // a state off the constraints (Q_A does not need them), every entry non-trivial
        let wave = |k: f64, i: usize| ((i + 1) as f64 * k).sin();
        let q: Vec<f64> = (0..n).map(|i| 0.1 + 0.4 * wave(1.3, i)).collect();
        let qd: Vec<f64> = (0..n).map(|i| 2.0 * wave(2.1, i)).collect();
        let t = 0.6;
        for qdd in [vec![0.0; n], (0..n).map(|i| 4.0 * wave(0.7, i)).collect()] {
            let (k, c) = dense_tangents(model, &loads, &q, &qd, &qdd, t);
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

//! The screw toolkit: every geometric answer against an algebraic one. The screw Jacobian
//! against finite differences of the forward kinematics and against the engine's own
//! velocities; inverse velocity (line screws, barycentres) against a linear solve; joint
//! torques against virtual work; forward force through torque centres against J^T W = tau;
//! instant centres from velocities against Kennedy's construction; loop singularities
//! against the engine's singular Jacobian. Random arms of 2 to 8 joints come from a
//! deterministic xorshift generator.
//!
//! Tolerances: 1e-12 (relative) where the two answers are the same algebra in a different
//! order; 1e-9 for solves of random arms whose conditioning is bounded by the test; 1e-7 for
//! central differences (step 1e-6: truncation ~1e-12, rounding ~1e-10 relative).

// index loops read like the formulas they check
#![allow(clippy::needless_range_loop)]

use std::f64::consts::PI;

use linkwork::screw::{
    centres_by_kennedy, centres_from_velocities, join, loop_singularity, meet, ArmJoint, JointKind,
    MechanismJoints, Point, Pose, ScrewError, SerialArm, Twist, Wrench,
};
use linkwork::{Data, Description, Model, SolveError};

struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol * (1.0 + a.abs().max(b.abs())), "{what}: {a} vs {b} (tol {tol})");
}

fn close3(a: [f64; 3], b: [f64; 3], tol: f64, what: &str) {
    let scale = 1.0 + a.iter().chain(&b).fold(0.0f64, |m, v| m.max(v.abs()));
    for k in 0..3 {
        assert!((a[k] - b[k]).abs() <= tol * scale, "{what}[{k}]: {a:?} vs {b:?} (tol {tol})");
    }
}

/// A random arm: n joints, about a third prismatic, home axes in the unit square.
fn random_arm(rng: &mut XorShift, n: usize) -> SerialArm {
    let joints = (0..n)
        .map(|i| {
            let at = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)];
            if rng.next() < 0.3 {
                let t = rng.range(0.0, 2.0 * PI);
                ArmJoint::prismatic(format!("{}", i + 1), at, [t.cos(), t.sin()]).unwrap()
            } else {
                ArmJoint::revolute(format!("{}", i + 1), at)
            }
        })
        .collect();
    let end = Pose::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-PI, PI));
    SerialArm::new(joints, end).unwrap()
}

fn random_q(rng: &mut XorShift, arm: &SerialArm) -> Vec<f64> {
    arm.joints()
        .iter()
        .map(|j| match j.kind {
            JointKind::Revolute => rng.range(-PI, PI),
            JointKind::Prismatic => rng.range(-0.5, 0.5),
        })
        .collect()
}

/// Gaussian elimination with partial pivoting (the algebraic answer).
fn linear_solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs())).unwrap();
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            for k in c..n {
                a[r][k] -= f * a[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x
}

fn det3(a: [[f64; 3]; 3]) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// The end frame's twist from central differences of the forward kinematics along dq.
fn fd_twist(arm: &SerialArm, q: &[f64], dq: &[f64]) -> Twist {
    let h = 1e-6;
    let at = |s: f64| {
        let qs: Vec<f64> = q.iter().zip(dq).map(|(a, d)| a + s * d).collect();
        arm.forward(&qs).unwrap().end
    };
    let (p, m, e) = (at(h), at(-h), at(0.0));
    let rate = [(p.x - m.x) / (2.0 * h), (p.y - m.y) / (2.0 * h), (p.theta - m.theta) / (2.0 * h)];
    Twist::of_body([e.x, e.y, e.theta], rate)
}

// -- conventions: twists, wrenches, join, meet, transport ------------------------------

#[test]
fn conventions_of_twists_wrenches_points_and_lines() {
    let mut rng = XorShift(0x9e3779b97f4a7c15);
    for _ in 0..200 {
        let p = [rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)];
        let s = Twist::revolute(p);
        assert_eq!(s.to_array(), [p[1], -p[0], 1.0]);
        // a pivot's own point does not move; its pole is the pivot
        assert_eq!(s.velocity_at(p), [0.0, 0.0]);
        assert_eq!(s.pole().xy().unwrap(), p);
        let t = rng.range(-PI, PI);
        let l = Wrench::line_screw(t, p);
        close3(l.to_array(), [t.cos(), t.sin(), p[0] * t.sin() - p[1] * t.cos()], 1e-15, "line screw");
        close(l.moment_about(p), 0.0, 1e-14, "a line screw has no moment about its own points");
        // reciprocal product = line . pole = the power of the force on the motion
        let tw = Twist::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
        let w = Wrench::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
        close(w.power(&tw), w.line().dot(&tw.pole()), 1e-14, "W.T = line.pole");
        let f = [rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)];
        let v = tw.velocity_at(p);
        close(Wrench::force_at(f, p).power(&tw), f[0] * v[0] + f[1] * v[1], 1e-13, "power of a force = f.v");
        // join: the line through both points, as the force q - p through p
        let q = [rng.range(-3.0, 3.0), rng.range(-3.0, 3.0)];
        let lpq = join(&Point::finite(p), &Point::finite(q)).unwrap();
        close(lpq.at(p), 0.0, 1e-13, "p on join");
        close(lpq.at(q), 0.0, 1e-13, "q on join");
        let wpq = lpq.wrench();
        close3(
            wpq.to_array(),
            Wrench::force_at([q[0] - p[0], q[1] - p[1]], p).to_array(),
            1e-13,
            "join as force",
        );
        // meet: on both lines
        let k = Wrench::line_screw(rng.range(-PI, PI), q).line();
        let x = meet(&lpq, &k).unwrap().xy().unwrap();
        let scale = 1.0 + x[0].abs().max(x[1].abs());
        assert!(lpq.at(x).abs() <= 1e-10 * scale * 10.0 && k.at(x).abs() <= 1e-10 * scale * 10.0);
    }
    // parallel lines meet at infinity, in their direction
    let a = Wrench::line_screw(0.3, [0.0, 0.0]).line();
    let b = Wrench::line_screw(0.3, [0.0, 1.0]).line();
    let x = meet(&a, &b).unwrap();
    assert_eq!(x.0[2], 0.0);
    close(x.0[1].atan2(x.0[0]).rem_euclid(PI), 0.3, 1e-14, "direction of the point at infinity");
    // a point at infinity joins a finite point along its direction
    let l = join(&Point::finite([1.0, 2.0]), &Point::at_infinity([0.0, 1.0])).unwrap();
    close(l.at([1.0, 7.0]), 0.0, 1e-15, "vertical line through (1, 2)");
    // degenerate: the same point, the same line
    assert_eq!(join(&Point::finite([1.0, 2.0]), &Point([2.0, 4.0, 2.0])), Err(ScrewError::SamePoint));
    assert_eq!(meet(&a, &a.scaled(-3.0)), Err(ScrewError::SameLine));
    assert!(Twist::prismatic([0.0, 0.0]).is_err());
}

#[test]
fn transport_between_frames_keeps_the_power() {
    let mut rng = XorShift(7);
    for _ in 0..200 {
        let f = Pose::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-PI, PI));
        let t = Twist::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
        let w = Wrench::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
        let (tl, wl) = (f.twist_to_local(&t), f.wrench_to_local(&w));
        close(wl.power(&tl), w.power(&t), 1e-13, "W.T in both frames");
        close3(f.twist_to_world(&tl).to_array(), t.to_array(), 1e-13, "twist round trip");
        close3(f.wrench_to_world(&wl).to_array(), w.to_array(), 1e-13, "wrench round trip");
        // the local twist's (vx, vy) is the velocity of the frame origin, in frame axes
        let v = f.rotate([tl.vx, tl.vy]);
        close3(
            [v[0], v[1], 0.0],
            [t.velocity_at([f.x, f.y])[0], t.velocity_at([f.x, f.y])[1], 0.0],
            1e-13,
            "v",
        );
        // a body's twist from its pose and rates
        let rate = [rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)];
        let body = Twist::of_body([f.x, f.y, f.theta], rate);
        let origin_v = body.velocity_at([f.x, f.y]);
        close3(
            [origin_v[0], origin_v[1], body.w],
            rate,
            1e-13,
            "body twist moves the body origin at (xd, yd)",
        );
        // the moment about the frame origin
        close(wl.m, w.moment_about([f.x, f.y]), 1e-13, "local moment");
        // compose / inverse
        let g = Pose::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-PI, PI));
        let p = [rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)];
        let a = f.compose(&g).apply(p);
        let b = f.apply(g.apply(p));
        close3([a[0], a[1], 0.0], [b[0], b[1], 0.0], 1e-13, "compose");
        let c = f.inverse().apply(f.apply(p));
        close3([c[0], c[1], 0.0], [p[0], p[1], 0.0], 1e-13, "inverse");
    }
}

// -- serial arms -----------------------------------------------------------------------

#[test]
fn screw_jacobian_is_the_jacobian_of_the_forward_kinematics() {
    let mut rng = XorShift(0x1234_5678);
    for n in 2..=8 {
        for _ in 0..20 {
            let arm = random_arm(&mut rng, n);
            let q = random_q(&mut rng, &arm);
            let st = arm.forward(&q).unwrap();
            let screws = st.screws();
            for i in 0..n {
                let mut dq = vec![0.0; n];
                dq[i] = 1.0;
                close3(screws[i].to_array(), fd_twist(&arm, &q, &dq).to_array(), 1e-7, "J column vs FD");
            }
            // forward velocity: T = J w against the derivative along w
            let w: Vec<f64> = (0..n).map(|_| rng.range(-2.0, 2.0)).collect();
            let t = st.twist(&w).unwrap();
            close3(t.to_array(), fd_twist(&arm, &q, &w).to_array(), 1e-7, "J w vs FD");
            // the row-major Jacobian holds the same screws
            let jac = st.jacobian();
            for (i, s) in screws.iter().enumerate() {
                assert_eq!([jac[i], jac[n + i], jac[2 * n + i]], s.to_array());
            }
        }
    }
}

#[test]
fn velocity_pole_is_the_barycentre_of_the_joints() {
    let mut rng = XorShift(99);
    for n in 2..=8 {
        for _ in 0..20 {
            let arm =
                SerialArm::from_lengths(&(0..n).map(|_| rng.range(0.2, 1.0)).collect::<Vec<_>>()).unwrap();
            let q: Vec<f64> = (0..n).map(|_| rng.range(-PI, PI)).collect();
            let w: Vec<f64> = (0..n).map(|_| rng.range(-2.0, 2.0)).collect();
            let st = arm.forward(&q).unwrap();
            // the weighted mean of the pivots, written out
            let sw: f64 = w.iter().sum();
            let bx = st.positions.iter().zip(&w).map(|(p, wi)| wi * p[0]).sum::<f64>() / sw;
            let by = st.positions.iter().zip(&w).map(|(p, wi)| wi * p[1]).sum::<f64>() / sw;
            let pole = st.pole(&w).unwrap();
            close(pole.0[2], sw, 1e-14, "pole weight = end link rate");
            let xy = pole.xy().unwrap();
            close3([xy[0], xy[1], 0.0], [bx, by, 0.0], 1e-10, "pole = barycentre");
            // the end point's velocity turns about the pole: Omega k x (E - pole), vs FD
            let e = st.end_point();
            let v_geo = [-sw * (e[1] - by), sw * (e[0] - bx)];
            let t = fd_twist(&arm, &q, &w);
            let v_fd = t.velocity_at(e);
            close3([v_geo[0], v_geo[1], 0.0], [v_fd[0], v_fd[1], 0.0], 1e-7, "end velocity about the pole");
            close3(
                [v_geo[0], v_geo[1], 0.0],
                [st.end_velocity(&w).unwrap()[0], st.end_velocity(&w).unwrap()[1], 0.0],
                1e-9,
                "end velocity",
            );
        }
    }
}

#[test]
fn inverse_velocity_matches_a_linear_solve() {
    let mut rng = XorShift(2024);
    let mut checked = 0;
    for n in 2..=8 {
        for _ in 0..40 {
            let arm = random_arm(&mut rng, n);
            let q = random_q(&mut rng, &arm);
            let st = arm.forward(&q).unwrap();
            let s = st.screws();
            if n == 2 {
                // a twist the two joints can produce comes back; one they cannot is refused
                let w_true = [rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)];
                let t = st.twist(&w_true).unwrap();
                let g = st.gauge;
                if g.collinearity(&st.points[0], &st.points[1], &Point([1.0, 0.0, 0.0])) < 1e-3 {
                    continue;
                }
                let w = st.inverse_velocity(&t, &[]).unwrap();
                let b = st.inverse_velocity_barycentre(&t, &[]).unwrap().rates;
                for i in 0..2 {
                    close(w[i], w_true[i], 1e-9, "2 joints: line screws");
                    close(b[i], w_true[i], 1e-9, "2 joints: barycentre");
                }
                let off = t + Twist::revolute([st.gauge.centre[0] + 5.0, st.gauge.centre[1] + 3.0]) * 0.5;
                if g.collinearity(&off.pole(), &st.points[0], &st.points[1]) > 1e-6 {
                    assert!(matches!(st.inverse_velocity(&off, &[]), Err(ScrewError::Unreachable { .. })));
                }
                checked += 1;
                continue;
            }
            // the last three joints are unknown, the others given
            let unknown = [n - 3, n - 2, n - 1];
            let cols: Vec<[f64; 3]> = unknown.iter().map(|&i| st.gauge.point(&st.points[i])).collect();
            if det3([cols[0], cols[1], cols[2]]).abs() < 1e-2 {
                continue; // too close to singular for a 1e-9 comparison
            }
            let given: Vec<(usize, f64)> = (0..n - 3).map(|i| (i, rng.range(-2.0, 2.0))).collect();
            let t = Twist::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
            // algebra: [$a $b $c] w = T - sum given
            let mut rest = t;
            for &(k, wk) in &given {
                rest = rest - s[k] * wk;
            }
            let a: Vec<Vec<f64>> =
                (0..3).map(|r| unknown.iter().map(|&i| s[i].to_array()[r]).collect()).collect();
            let x = linear_solve(a, rest.to_array().to_vec());
            let w = st.inverse_velocity(&t, &given).unwrap();
            let bary = st.inverse_velocity_barycentre(&t, &given).unwrap();
            let scale = 1.0 + x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (slot, &i) in unknown.iter().enumerate() {
                assert!(
                    (w[i] - x[slot]).abs() <= 1e-9 * scale,
                    "line screws vs solve: {} vs {}",
                    w[i],
                    x[slot]
                );
                assert!((bary.rates[i] - x[slot]).abs() <= 1e-9 * scale, "barycentre vs solve");
            }
            for &(k, wk) in &given {
                assert_eq!(w[k], wk);
            }
            close3(st.twist(&w).unwrap().to_array(), t.to_array(), 1e-9, "J w = T");
            // the line screws are reciprocal to the other two unknown joints
            let lines = st.line_screws(unknown).unwrap();
            for (slot, l) in lines.iter().enumerate() {
                for other in 1..3 {
                    close(l.power(&s[unknown[(slot + other) % 3]]), 0.0, 1e-12, "S_jk . $_j = 0");
                }
            }
            // the barycentre construction's foot lies on the opposite side and on the vertex-pole line
            if let (Some(a), Some(d)) = (bary.vertex, bary.foot) {
                let others: Vec<usize> = unknown.iter().copied().filter(|&i| i != a).collect();
                let g = st.gauge;
                assert!(g.collinearity(&d, &st.points[others[0]], &st.points[others[1]]) < 1e-10);
                assert!(g.collinearity(&d, &st.points[a], &bary.pole) < 1e-10);
            }
            checked += 1;
        }
    }
    assert!(checked > 150, "only {checked} arms were well enough conditioned");
}

#[test]
fn torques_are_virtual_work_and_lever_arms_are_distances() {
    let mut rng = XorShift(31337);
    for n in 2..=8 {
        for _ in 0..20 {
            let arm = random_arm(&mut rng, n);
            let q = random_q(&mut rng, &arm);
            let st = arm.forward(&q).unwrap();
            let wr = Wrench::force_at(
                [rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)],
                [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)],
            ) + Wrench::couple(rng.range(-1.0, 1.0));
            let tau = st.torques(&wr);
            // virtual work: tau . dq = W . (twist of the end frame for dq), by FD
            for i in 0..n {
                let mut dq = vec![0.0; n];
                dq[i] = 1.0;
                close(tau[i], wr.power(&fd_twist(&arm, &q, &dq)), 1e-7, "tau_i vs virtual work");
            }
            let w: Vec<f64> = (0..n).map(|_| rng.range(-2.0, 2.0)).collect();
            let work: f64 = tau.iter().zip(&w).map(|(a, b)| a * b).sum();
            close(work, wr.power(&st.twist(&w).unwrap()), 1e-12, "tau . w = W . J w");
            // lever arms: the perpendicular distance from each pivot to the force line
            let p = st.lever_arms(&wr).unwrap();
            let f = wr.fx.hypot(wr.fy);
            for i in 0..n {
                match st.kinds[i] {
                    JointKind::Revolute => {
                        let [x, y] = st.positions[i];
                        // the foot of the perpendicular from the pivot onto the force line
                        let l = wr.line();
                        let d = l.at([x, y]) / l.0[0].hypot(l.0[1]);
                        close(p[i], d, 1e-12, "lever arm = distance");
                    }
                    JointKind::Prismatic => {
                        let u = st.axes[i];
                        close(p[i], (wr.fx * u[0] + wr.fy * u[1]) / f, 1e-12, "slide: direction cosine")
                    }
                }
                close(tau[i], f * p[i], 1e-12, "tau = |f| p");
            }
        }
    }
}

#[test]
fn forward_force_passes_through_the_torque_centres() {
    let mut rng = XorShift(4242);
    let mut checked = 0;
    for n in 2..=8 {
        for _ in 0..30 {
            let arm = random_arm(&mut rng, n);
            let q = random_q(&mut rng, &arm);
            let st = arm.forward(&q).unwrap();
            let e = st.end_point();
            let truth = if n == 2 {
                Wrench::force_at([rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)], e)
            } else {
                Wrench::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0), rng.range(-5.0, 5.0))
            };
            let tau = st.torques(&truth);
            let got = match st.force(&tau, None) {
                Ok(w) => w,
                Err(ScrewError::Dependent { .. }) => continue,
                Err(e) => panic!("{e}"),
            };
            // the algebra: J^T W = tau is what the answer must satisfy
            let back = st.torques(&got);
            let tmax = tau.iter().fold(0.0f64, |m, t| m.max(t.abs()));
            for i in 0..n {
                assert!((back[i] - tau[i]).abs() <= 1e-9 * tmax, "J^T W = tau");
            }
            if n == 3 || n == 2 {
                let a = st.points.iter().map(|p| st.gauge.point(p)).collect::<Vec<_>>();
                if n == 2 || det3([a[0], a[1], a[2]]).abs() > 1e-2 {
                    close3(got.to_array(), truth.to_array(), 1e-8, "recovered wrench");
                }
            }
            // every torque centre lies on the force line
            let l = got.line();
            for ((j, k), x) in st.torque_centres(&tau).unwrap() {
                let xn = st.gauge.point(&x);
                let ln = st.gauge.line(&l);
                let ll = (ln[0] * ln[0] + ln[1] * ln[1] + ln[2] * ln[2]).sqrt();
                assert!(
                    (xn[0] * ln[0] + xn[1] * ln[1] + xn[2] * ln[2]).abs() <= 1e-9 * ll,
                    "centre {j}{k} on the line"
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 150, "{checked}");
    // torques no wrench can give: a four-joint arm whose torques disagree
    let arm = SerialArm::from_lengths(&[1.0, 0.8, 0.5, 0.3]).unwrap();
    let st = arm.forward(&[0.3, 0.5, -0.4, 0.9]).unwrap();
    let mut tau = st.torques(&Wrench::new(1.0, 2.0, 0.3));
    tau[3] += 0.5;
    assert!(matches!(st.force(&tau, None), Err(ScrewError::Unbalanced { .. })));
}

#[test]
fn torque_centres_are_velocity_centres_of_motions_that_do_no_work() {
    let mut rng = XorShift(5);
    for n in 3..=6 {
        let arm = random_arm(&mut rng, n);
        let q = random_q(&mut rng, &arm);
        let st = arm.forward(&q).unwrap();
        let wr = Wrench::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0), rng.range(-5.0, 5.0));
        let tau = st.torques(&wr);
        for ((j, k), x) in st.torque_centres(&tau).unwrap() {
            let mut w = vec![0.0; n];
            w[j] = tau[k];
            w[k] = -tau[j];
            let v = st.velocity_centres(&w).unwrap().into_iter().find(|(p, _)| *p == (j, k)).unwrap().1;
            close3(v.0, x.0, 1e-14, "torque centre = velocity centre of rates (tau_k, -tau_j)");
            close(wr.power(&st.twist(&w).unwrap()), 0.0, 1e-12, "that motion does no work against W");
        }
    }
}

/// The documented three-link arm (docs/screw.md): lengths 1.0, 0.8, 0.5 m at relative
/// angles 30, 45, -60 degrees, rates 1.0, -0.5, 2.0 rad/s, end force (0, -10) N.
#[test]
fn three_link_arm_against_closed_forms() {
    let l = [1.0, 0.8, 0.5];
    let q = [30f64.to_radians(), 45f64.to_radians(), -60f64.to_radians()];
    let w = [1.0, -0.5, 2.0];
    let arm = SerialArm::from_lengths(&l).unwrap();
    let st = arm.forward(&q).unwrap();
    // closed form: cumulative angles
    let phi = [q[0], q[0] + q[1], q[0] + q[1] + q[2]];
    let rates = [w[0], w[0] + w[1], w[0] + w[1] + w[2]];
    let mut p = [[0.0; 2]; 4];
    for i in 0..3 {
        p[i + 1] = [p[i][0] + l[i] * phi[i].cos(), p[i][1] + l[i] * phi[i].sin()];
    }
    for i in 0..3 {
        close3(
            [st.positions[i][0], st.positions[i][1], 0.0],
            [p[i][0], p[i][1], 0.0],
            1e-15,
            "joint position",
        );
    }
    close3([st.end.x, st.end.y, st.end.theta], [p[3][0], p[3][1], phi[2]], 1e-15, "end pose");
    let v: [f64; 2] = [
        -(0..3).map(|i| l[i] * rates[i] * phi[i].sin()).sum::<f64>(),
        (0..3).map(|i| l[i] * rates[i] * phi[i].cos()).sum::<f64>(),
    ];
    let ve = st.end_velocity(&w).unwrap();
    close3([ve[0], ve[1], 0.0], [v[0], v[1], 0.0], 1e-14, "end velocity");
    // each joint's share of the end velocity: w_i k x (E - P_i)
    let share: Vec<[f64; 2]> =
        (0..3).map(|i| [-w[i] * (p[3][1] - p[i][1]), w[i] * (p[3][0] - p[i][0])]).collect();
    close(share.iter().map(|s| s[0]).sum(), v[0], 1e-14, "sum of shares x");
    close(share.iter().map(|s| s[1]).sum(), v[1], 1e-14, "sum of shares y");
    // inverse velocity
    let t = st.twist(&w).unwrap();
    let back = st.inverse_velocity(&t, &[]).unwrap();
    let bary = st.inverse_velocity_barycentre(&t, &[]).unwrap();
    for i in 0..3 {
        close(back[i], w[i], 1e-13, "line screws");
        close(bary.rates[i], w[i], 1e-13, "barycentre");
    }
    // inverse force: tau_i = (E - P_i) x F
    let f = [0.0, -10.0];
    let wr = Wrench::force_at(f, p[3]);
    let tau = st.torques(&wr);
    for i in 0..3 {
        close(tau[i], (p[3][0] - p[i][0]) * f[1] - (p[3][1] - p[i][1]) * f[0], 1e-14, "tau closed form");
    }
    close3(st.force(&tau, None).unwrap().to_array(), wr.to_array(), 1e-12, "forward force");
}

// -- arms read from linkwork descriptions, against the engine --------------------------

/// A chain ground -R- b1 -P- b2 -R- b3 with drivers on every joint, and a point "E".
fn rpr_description() -> Description {
    let json = r#"{
      "name": "rpr",
      "bodies": [
        {"name": "b1", "x": 0.1, "y": 0.2, "theta": 0.4},
        {"name": "b2", "x": 0.7, "y": 0.5, "theta": 0.4},
        {"name": "b3", "x": 1.2, "y": 0.6, "theta": -0.3}
      ],
      "joints": [
        {"type": "revolute", "name": "O", "body_a": "ground", "body_b": "b1", "at": [0.1, 0.2]},
        {"type": "prismatic", "name": "S", "body_a": "b1", "body_b": "b2", "at": [0.6, 0.4],
         "axis": [0.9210609940028851, 0.3894183423086505]},
        {"type": "revolute", "name": "K", "body_a": "b3", "body_b": "b2", "at": [1.1, 0.55]}
      ],
      "drivers": [
        {"type": "angle", "name": "d1", "body": "b1", "law": {"type": "linear", "value": 0.4, "rate": 1.3}},
        {"type": "translation", "name": "d2", "joint": "S", "law": {"type": "linear", "value": 0.0, "rate": 0.2}},
        {"type": "relative_angle", "name": "d3", "body_a": "b1", "body_b": "b3",
         "law": {"type": "linear", "value": -0.7, "rate": -0.8}}
      ],
      "points": [{"name": "E", "body": "b3", "at": [1.5, 0.4]}]
    }"#;
    Description::from_json(json).unwrap()
}

#[test]
fn arm_from_a_description_matches_the_engine() {
    let desc = rpr_description();
    let model = Model::new(desc.clone()).unwrap();
    let arm = SerialArm::from_description(&desc, Some("E")).unwrap();
    let names: Vec<&str> = arm.joints().iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["O", "S", "K"]);
    assert_eq!(arm.end_body(), Some(2));
    for t in [0.0, 0.3, 0.9, 1.7] {
        let mut data = Data::new(&model);
        linkwork::solve(&model, &mut data, t).unwrap();
        let (q, w) = arm.joint_values(&data.q, &data.qd).unwrap();
        // the driven values, read back through the chain: theta1 - 0.4, s, theta3 - theta2 - start
        close(q[0], 1.3 * t, 1e-12, "revolute O");
        close(q[1], 0.2 * t, 1e-12, "slide S");
        close3([w[0], w[1], w[2]], [1.3, 0.2, -0.8], 1e-12, "joint rates");
        let (pose, twist) = arm.model_end(&data.q, &data.qd).unwrap();
        let st = arm.forward(&q).unwrap();
        close3([st.end.x, st.end.y, st.end.theta], [pose.x, pose.y, pose.theta], 1e-12, "FK = engine pose");
        close3(st.twist(&w).unwrap().to_array(), twist.to_array(), 1e-12, "J w = engine twist");
    }
}

#[test]
fn serial_chains_only() {
    let mut desc = rpr_description();
    // a loop: tie b3 back to the ground
    let extra = r#"{"type": "revolute", "name": "X", "body_a": "b3", "body_b": "ground", "at": [1.6, 0.0]}"#;
    desc.joints.push(serde_json::from_str(extra).unwrap());
    let err = SerialArm::from_description(&desc, None).unwrap_err();
    assert!(err.to_string().contains("'X'"), "{err}");
    let err = SerialArm::from_description(&rpr_description(), Some("nowhere")).unwrap_err();
    assert!(err.to_string().contains("nowhere"), "{err}");
}

// -- degenerate input ------------------------------------------------------------------

#[test]
fn degenerate_arms_get_clear_errors() {
    // a zero-length link: joints 2 and 3 coincide
    let arm = SerialArm::from_lengths(&[1.0, 0.0, 0.5]).unwrap();
    let st = arm.forward(&[0.3, 0.2, 0.1]).unwrap();
    let err = st.inverse_velocity(&Twist::new(0.1, 0.2, 0.3), &[]).unwrap_err();
    assert_eq!(err.to_string(), "joints 2 and 3 coincide");
    assert_eq!(st.dependencies(), vec![vec![1, 2]]);
    assert!(st.inverse_velocity_barycentre(&Twist::new(0.1, 0.2, 0.3), &[]).is_err());
    // a straight arm: joints 1, 2 and 3 are collinear
    let arm = SerialArm::from_lengths(&[1.0, 0.8, 0.5]).unwrap();
    let st = arm.forward(&[0.4, 0.0, 0.0]).unwrap();
    let err = st.inverse_velocity(&Twist::new(0.1, 0.2, 0.3), &[]).unwrap_err();
    assert_eq!(err.to_string(), "joints 1, 2 and 3 are collinear");
    assert!(st.line_screws([0, 1, 2]).is_err());
    // a wrench through every joint needs no torque; the torques then do not fix the force
    let through_all = Wrench::line_screw(0.4, [0.0, 0.0]) * 7.0;
    assert!(st.torques(&through_all).iter().all(|t| t.abs() < 1e-14));
    let err = st.force(&[0.0, 0.0, 0.0], None).unwrap_err();
    assert!(err.to_string().starts_with("joints 1, 2 and 3 have dependent axes"), "{err}");
    // a pure couple has no lever arms
    assert!(st.lever_arms(&Wrench::couple(2.0)).is_err());
    // parallel slides
    let arm = SerialArm::new(
        vec![
            ArmJoint::prismatic("a", [0.0, 0.0], [1.0, 0.0]).unwrap(),
            ArmJoint::prismatic("b", [0.0, 1.0], [-2.0, 0.0]).unwrap(),
            ArmJoint::revolute("c", [1.0, 1.0]),
        ],
        Pose::new(2.0, 1.0, 0.0),
    )
    .unwrap();
    let st = arm.forward(&[0.1, 0.2, 0.3]).unwrap();
    assert_eq!(
        st.inverse_velocity(&Twist::new(1.0, 0.0, 0.0), &[]).unwrap_err().to_string(),
        "joints a and b slide in parallel directions"
    );
    // pivots on a line perpendicular to a slide
    let arm = SerialArm::new(
        vec![
            ArmJoint::revolute("a", [0.0, 0.0]),
            ArmJoint::revolute("b", [1.0, 0.0]),
            ArmJoint::prismatic("c", [2.0, 0.0], [0.0, 1.0]).unwrap(),
        ],
        Pose::new(2.0, 1.0, 0.0),
    )
    .unwrap();
    let err =
        arm.forward(&[0.0, 0.0, 0.0]).unwrap().inverse_velocity(&Twist::new(1.0, 0.0, 0.0), &[]).unwrap_err();
    assert!(err.to_string().contains("perpendicular to the slide of c"), "{err}");
    // too many unknowns, bad sizes, non-finite input
    let arm = SerialArm::from_lengths(&[1.0, 0.8, 0.5, 0.3]).unwrap();
    let st = arm.forward(&[0.1, 0.2, 0.3, 0.4]).unwrap();
    assert_eq!(
        st.inverse_velocity(&Twist::new(1.0, 0.0, 0.0), &[]),
        Err(ScrewError::Redundant { unknown: 4 })
    );
    assert!(st.inverse_velocity(&Twist::new(1.0, 0.0, 0.0), &[(0, 1.0), (0, 2.0)]).is_err());
    assert!(st.inverse_velocity(&Twist::new(f64::NAN, 0.0, 0.0), &[(0, 1.0)]).is_err());
    assert!(arm.forward(&[0.1, 0.2]).is_err());
    assert!(arm.forward(&[0.1, 0.2, f64::INFINITY, 0.0]).is_err());
    assert!(st.twist(&[1.0]).is_err());
    assert!(SerialArm::from_lengths(&[1.0, -0.5]).is_err());
    assert!(SerialArm::from_lengths(&[]).is_err());
    // a one-joint arm cannot fix a force
    let one = SerialArm::from_lengths(&[1.0]).unwrap().forward(&[0.2]).unwrap();
    assert!(one.force(&[1.0], None).is_err());
    // a two-joint arm stretched straight: the end point is in line with both joints
    let two = SerialArm::from_lengths(&[1.0, 1.0]).unwrap().forward(&[0.5, 0.0]).unwrap();
    assert!(matches!(two.force(&[1.0, 2.0], None), Err(ScrewError::Dependent { .. })));
}

// -- closed loops: instant centres and singularities -----------------------------------

fn four_bar(theta2: f64, branch: f64) -> (Description, [[f64; 2]; 4]) {
    let (r1, r2, r3, r4) = (0.35, 0.20, 0.35, 0.25);
    let o2 = [0.0, 0.0];
    let o4 = [r1, 0.0];
    let a = [r2 * theta2.cos(), r2 * theta2.sin()];
    // B: circles (A, r3) and (O4, r4)
    let (dx, dy) = (o4[0] - a[0], o4[1] - a[1]);
    let d = dx.hypot(dy);
    let along = (r3 * r3 - r4 * r4 + d * d) / (2.0 * d);
    let h = (r3 * r3 - along * along).max(0.0).sqrt() * branch;
    let b = [a[0] + (along * dx - h * dy) / d, a[1] + (along * dy + h * dx) / d];
    (four_bar_at(o2, a, b, o4), [o2, a, b, o4])
}

fn four_bar_at(o2: [f64; 2], a: [f64; 2], b: [f64; 2], o4: [f64; 2]) -> Description {
    let ang = |p: [f64; 2], q: [f64; 2]| (q[1] - p[1]).atan2(q[0] - p[0]);
    let json = format!(
        r#"{{"name": "four-bar",
        "bodies": [
          {{"name": "crank", "x": {}, "y": {}, "theta": {}}},
          {{"name": "coupler", "x": {}, "y": {}, "theta": {}}},
          {{"name": "rocker", "x": {}, "y": {}, "theta": {}}}],
        "joints": [
          {{"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [{}, {}]}},
          {{"type": "revolute", "name": "A", "body_a": "crank", "body_b": "coupler", "at": [{}, {}]}},
          {{"type": "revolute", "name": "B", "body_a": "coupler", "body_b": "rocker", "at": [{}, {}]}},
          {{"type": "revolute", "name": "O4", "body_a": "ground", "body_b": "rocker", "at": [{}, {}]}}],
        "drivers": [{{"type": "angle", "name": "crank_angle", "body": "crank",
                      "law": {{"type": "linear", "value": {}, "rate": 5.0}}}}]}}"#,
        o2[0],
        o2[1],
        ang(o2, a),
        a[0],
        a[1],
        ang(a, b),
        o4[0],
        o4[1],
        ang(o4, b),
        o2[0],
        o2[1],
        a[0],
        a[1],
        b[0],
        b[1],
        o4[0],
        o4[1],
        ang(o2, a)
    );
    Description::from_json(&json).unwrap()
}

fn slider_crank(theta2: f64) -> Description {
    let (r2, r3, e) = (0.10, 0.35, 0.02);
    let a = [r2 * theta2.cos(), r2 * theta2.sin()];
    let bx = a[0] + (r3 * r3 - (e - a[1]) * (e - a[1])).sqrt();
    let json = format!(
        r#"{{"name": "slider-crank",
        "bodies": [
          {{"name": "crank", "x": 0, "y": 0, "theta": {theta2}}},
          {{"name": "rod", "x": {}, "y": {}, "theta": {}}},
          {{"name": "slider", "x": {bx}, "y": {e}, "theta": 0}}],
        "joints": [
          {{"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [0, 0]}},
          {{"type": "revolute", "name": "A", "body_a": "crank", "body_b": "rod", "at": [{}, {}]}},
          {{"type": "revolute", "name": "B", "body_a": "rod", "body_b": "slider", "at": [{bx}, {e}]}},
          {{"type": "prismatic", "name": "S", "body_a": "ground", "body_b": "slider", "at": [{bx}, {e}],
            "axis": [1, 0]}}],
        "drivers": [{{"type": "angle", "name": "crank_angle", "body": "crank",
                      "law": {{"type": "linear", "value": {theta2}, "rate": 5.0}}}}]}}"#,
        a[0],
        a[1],
        (e - a[1]).atan2(bx - a[0]),
        a[0],
        a[1],
    );
    Description::from_json(&json).unwrap()
}

/// Centres from the engine's velocities against Kennedy's construction from the joints,
/// and Kennedy's theorem (collinear triples) on the velocity centres.
fn check_centres(desc: &Description, times: &[f64]) -> usize {
    let model = Model::new(desc.clone()).unwrap();
    let mech = MechanismJoints::from_description(desc).unwrap();
    let mut at_infinity = 0;
    for &t in times {
        let mut data = Data::new(&model);
        linkwork::solve(&model, &mut data, t).unwrap();
        let vel = centres_from_velocities(&mech, &data.q, &data.qd).unwrap();
        let geo = centres_by_kennedy(&mech, &data.q).unwrap();
        for (i, j, p) in vel.pairs() {
            let p = p.unwrap_or_else(|| panic!("no centre for bodies {i} and {j} at t = {t}"));
            let g = geo.get(i, j).unwrap_or_else(|| panic!("Kennedy did not reach {i}{j}"));
            // the same point: normalised homogeneous vectors parallel
            let (a, b) = (vel.gauge.point(&p), vel.gauge.point(&g));
            let c = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
            assert!(c.iter().all(|v| v.abs() < 1e-9), "centre {i}{j} at t = {t}: {p:?} vs {g:?}");
            if vel.gauge.is_at_infinity(&p) {
                at_infinity += 1;
            }
        }
        let (worst, triple) = vel.kennedy_worst().unwrap();
        assert!(worst < 1e-12, "Kennedy: bodies {triple:?} off line by {worst}");
    }
    at_infinity
}

#[test]
fn instant_centres_of_a_four_bar_from_velocities_and_by_kennedy() {
    let (desc, _) = four_bar(0.3, 1.0);
    let times: Vec<f64> = (0..24).map(|k| k as f64 * 2.0 * PI / 5.0 / 24.0).collect();
    check_centres(&desc, &times);
}

#[test]
fn instant_centres_of_a_slider_crank_include_points_at_infinity() {
    let desc = slider_crank(0.3);
    let times: Vec<f64> = (0..24).map(|k| 0.013 + k as f64 * 2.0 * PI / 5.0 / 24.0).collect();
    // the slider's centre with the ground is at infinity at every step
    let inf = check_centres(&desc, &times);
    assert!(inf >= times.len(), "{inf}");
    // and it lies across the slide (vertical)
    let model = Model::new(desc.clone()).unwrap();
    let mut data = Data::new(&model);
    linkwork::solve(&model, &mut data, 0.1).unwrap();
    let mech = MechanismJoints::from_description(&desc).unwrap();
    let c = centres_from_velocities(&mech, &data.q, &data.qd).unwrap().get(0, 3).unwrap();
    assert_eq!(c.0[2], 0.0);
    assert!(c.0[0].abs() < 1e-12 && (c.0[1].abs() - 1.0).abs() < 1e-12, "{c:?}");
}

#[test]
fn a_dead_point_is_a_collapse_of_the_loop_screws() {
    // regular configuration: the passive joints A, B, O4 span the plane's twists
    let (desc, _) = four_bar(0.3, 1.0);
    let q0: Vec<f64> = desc.bodies.iter().flat_map(|b| [b.x, b.y, b.theta]).collect();
    let ok = loop_singularity(&desc, &q0, 1e-9).unwrap();
    assert_eq!(ok.joints, ["A", "B", "O4"]);
    assert_eq!(ok.locked, ["O2"]);
    assert_eq!(ok.loops.len(), 1);
    assert!(!ok.singular && ok.rank == 3 && ok.involved.is_empty() && ok.dependent.is_empty());
    // dead point: B on the line A-O4 (coupler and rocker aligned)
    let a = [0.2 * 1.1f64.cos(), 0.2 * 1.1f64.sin()];
    let o4 = [0.35, 0.0];
    let b = [a[0] + 0.6 * (o4[0] - a[0]), a[1] + 0.6 * (o4[1] - a[1])];
    let dead = four_bar_at([0.0, 0.0], a, b, o4);
    let q: Vec<f64> = dead.bodies.iter().flat_map(|b| [b.x, b.y, b.theta]).collect();
    let s = loop_singularity(&dead, &q, 1e-9).unwrap();
    assert!(s.singular, "{s:?}");
    assert_eq!(s.rank, 2);
    assert_eq!(s.involved, ["A", "B", "O4"]);
    assert_eq!(s.dependent, vec![vec!["A".to_string(), "B".into(), "O4".into()]]);
    // the algebra agrees: the engine finds Phi_q singular there
    let model = Model::new(dead).unwrap();
    let mut data = Data::new(&model);
    let err = linkwork::solve(&model, &mut data, 0.0).unwrap_err();
    assert!(matches!(err, SolveError::Singular { .. }), "{err}");
}

#[test]
fn welds_and_loose_drivers_get_clear_errors() {
    let (mut desc, _) = four_bar(0.3, 1.0);
    desc.drivers.push(
        serde_json::from_str(
            r#"{"type": "coordinate", "name": "dx", "body": "coupler", "at": [0.1, 0.1], "axis": "x",
                "law": {"type": "constant", "value": 0.1}}"#,
        )
        .unwrap(),
    );
    let q: Vec<f64> = desc.bodies.iter().flat_map(|b| [b.x, b.y, b.theta]).collect();
    let err = loop_singularity(&desc, &q, 1e-9).unwrap_err();
    assert!(err.to_string().contains("driver 'dx'"), "{err}");
    let (mut desc, _) = four_bar(0.3, 1.0);
    desc.joints.push(
        serde_json::from_str(r#"{"type": "fixed", "name": "W", "body_a": "crank", "body_b": "coupler"}"#)
            .unwrap(),
    );
    let mech = MechanismJoints::from_description(&desc).unwrap();
    let err = centres_by_kennedy(&mech, &q).unwrap_err();
    assert!(err.to_string().contains("'W' is a weld"), "{err}");
    assert!(centres_from_velocities(&mech, &q[..3], &q).is_err());
}

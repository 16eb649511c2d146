//! The joints without coordinates of their own (distance, point on line, gear, rack and
//! pinion, belt, fixed orientation, parallel, linear coupling) in whole mechanisms, over
//! whole revolutions, against closed forms: positions, velocities and accelerations to
//! 1e-10 relative (Newton stops at 1e-12 scaled on well-conditioned Jacobians, so the
//! engine sits near machine precision; 1e-10 leaves room for the closed forms' rounding).
//! Then the variants `samples()` does not reach against finite differences, and every
//! refusal of bad input, named.

use crate::common;
use common::{four_bar_closed, rel_err, FourBar};
use linkwork::constraints::{Constraint, ConstraintKind, Extra, Frame, Rows, MAX_ROWS};
use linkwork::joints::gear::Gear;
use linkwork::joints::{
    belt::Belt, linear_coupling::LinearCoupling, point_line::PointOnLine, rack_pinion::RackPinion,
};
use linkwork::{sweep, Data, Model, ModelError, Options, SweepOutput};
use serde_json::{json, Value};
use std::f64::consts::PI;

const TOL: f64 = 1e-10;

struct Run {
    model: Model,
    out: SweepOutput,
}

impl Run {
    fn new(desc: Value, times: &[f64]) -> Run {
        let model = Model::from_json(&desc.to_string(), Options::default()).unwrap();
        let mut data = Data::new(&model);
        let mut out = SweepOutput::new(&model, times);
        sweep(&model, &mut data, times, &mut out, 0, &mut |_| true).unwrap();
        assert_eq!(out.n_done, times.len());
        Run { model, out }
    }
    /// (q, qd, qdd) of the named column over the sweep.
    fn column(&self, name: &str) -> [Vec<f64>; 3] {
        let j = self.model.columns.iter().position(|c| c == name).unwrap_or_else(|| panic!("{name}"));
        let n = self.out.n_coords;
        let pick = |v: &[f64]| (0..self.out.n_done).map(|k| v[k * n + j]).collect::<Vec<f64>>();
        [pick(&self.out.q), pick(&self.out.qd), pick(&self.out.qdd)]
    }
}

/// One revolution at `omega`, n steps.
fn revolution(omega: f64, n: usize) -> Vec<f64> {
    (0..n).map(|k| k as f64 * 2.0 * PI / omega / (n - 1) as f64).collect()
}

/// Largest absolute error (for quantities that are exactly zero or O(1) angles).
fn abs_err(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

fn body(name: &str, x: f64, y: f64, theta: f64) -> Value {
    json!({"name": name, "x": x, "y": y, "theta": theta})
}

fn pin(name: &str, a: &str, b: &str, at: [f64; 2]) -> Value {
    json!({"type": "revolute", "name": name, "body_a": a, "body_b": b, "at": at})
}

fn drive(body: &str, theta0: f64, omega: f64) -> Value {
    json!({"type": "angle", "name": "input", "body": body, "law": {"type": "linear", "value": theta0, "rate": omega}})
}

#[test]
fn four_bar_with_a_distance_joint_as_coupler_matches_closed_form() {
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };
    let (th0, w) = (0.3, 5.0);
    let ([_, th4], _, _) = four_bar_closed(&m, th0, w, 0.0);
    let a = [m.r2 * th0.cos(), m.r2 * th0.sin()];
    let b = [m.r1 + m.r4 * th4.cos(), m.r4 * th4.sin()];
    let desc = json!({
        "bodies": [body("crank", 0.0, 0.0, th0), body("rocker", m.r1, 0.0, th4)],
        "joints": [
            pin("O2", "ground", "crank", [0.0, 0.0]),
            pin("O4", "ground", "rocker", [m.r1, 0.0]),
            {"type": "distance", "name": "AB", "body_a": "crank", "at_a": a, "body_b": "rocker", "at_b": b},
        ],
        "drivers": [drive("crank", th0, w)],
    });
    let times = revolution(w, 721);
    let run = Run::new(desc, &times);
    assert_eq!(run.model.n_coords, 6);
    let mut want = [vec![], vec![], vec![]];
    for t in &times {
        let (th, om, al) = four_bar_closed(&m, th0 + w * t, w, 0.0);
        want[0].push(th[1]);
        want[1].push(om[1]);
        want[2].push(al[1]);
    }
    let got = run.column("rocker.theta");
    assert!(abs_err(&got[0], &want[0]) <= TOL, "theta4 {}", abs_err(&got[0], &want[0]));
    assert!(rel_err(&got[1], &want[1]) <= TOL, "omega4 {}", rel_err(&got[1], &want[1]));
    assert!(rel_err(&got[2], &want[2]) <= TOL, "alpha4 {}", rel_err(&got[2], &want[2]));
}

#[test]
fn scotch_yoke_pin_in_slot_gives_x_equal_r_cos_theta() {
    // crank of radius r about the origin; its pin in a vertical slot of the yoke, which
    // slides along x: yoke.x = r cos(theta) + (the yoke's origin offset from the slot)
    let (r, w, th0, off): (f64, f64, f64, f64) = (0.12, 4.0, 0.2, 0.05);
    let pin_at = [r * th0.cos(), r * th0.sin()];
    let desc = json!({
        "bodies": [body("crank", 0.0, 0.0, th0), body("yoke", pin_at[0] - off, 0.0, 0.0)],
        "joints": [
            pin("O", "ground", "crank", [0.0, 0.0]),
            {"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "yoke",
             "at": [pin_at[0] - off, 0.0], "axis": [1.0, 0.0]},
            {"type": "point_on_line", "name": "slot", "body_a": "crank", "body_b": "yoke",
             "at": pin_at, "axis": [0.0, 1.0]},
        ],
        "drivers": [drive("crank", th0, w)],
    });
    let times = revolution(w, 721);
    let run = Run::new(desc, &times);
    let th: Vec<f64> = times.iter().map(|t| th0 + w * t).collect();
    let x: Vec<f64> = th.iter().map(|th| r * th.cos() - off).collect();
    let v: Vec<f64> = th.iter().map(|th| -r * w * th.sin()).collect();
    let a: Vec<f64> = th.iter().map(|th| -r * w * w * th.cos()).collect();
    let [gx, gv, ga] = run.column("yoke.x");
    assert!(rel_err(&gx, &x) <= TOL, "x {}", rel_err(&gx, &x));
    assert!(rel_err(&gv, &v) <= TOL, "v {}", rel_err(&gv, &v));
    assert!(rel_err(&ga, &a) <= TOL, "a {}", rel_err(&ga, &a));
}

#[test]
fn gear_pair_output_is_minus_ratio_times_input() {
    // pinion about (0, 0) and gear about (0.2, 0), by ratio from the centre distance:
    // r_a + r_b = 0.2 and r_a / r_b = 0.6; external gears turn opposite ways
    for (internal, sign) in [(false, -1.0), (true, 1.0)] {
        let (ratio, w, th_a0, th_b0) = (0.6, 3.0, 0.4, -1.3);
        let desc = json!({
            "bodies": [body("pinion", 0.0, 0.0, th_a0), body("gear", 0.2, 0.0, th_b0)],
            "joints": [
                pin("Oa", "ground", "pinion", [0.0, 0.0]),
                pin("Ob", "ground", "gear", [0.2, 0.0]),
                {"type": "gear", "name": "mesh", "body_a": "pinion", "body_b": "gear",
                 "ratio": ratio, "internal": internal},
            ],
            "drivers": [drive("pinion", th_a0, w)],
        });
        let times = revolution(w, 181);
        let run = Run::new(desc, &times);
        // the gear is an affine group (its angle from the mesh row, its x, y from its pin):
        // every step after the first is solved by that substitution, 0 Newton iterations (a
        // group that fails it or reads itself singular leaves them to the general path, to
        // the same values)
        let general = (1..run.out.n_done).filter(|&k| run.out.iterations[k] != 0).count();
        assert_eq!(general, 0, "{general} steps left to the general path");
        let [q, qd, qdd] = run.column("gear.theta");
        for (k, t) in times.iter().enumerate() {
            assert!((q[k] - (th_b0 + sign * ratio * w * t)).abs() <= 1e-12 * (1.0 + w * t));
            assert!((qd[k] - sign * ratio * w).abs() <= 1e-12 * w);
            assert!(qdd[k].abs() <= 1e-12);
        }
    }
}

/// Sun (radius r_s) about the origin, a carrier arm about the origin, a planet (r_p)
/// pinned to the arm at r_s + r_p, and a ring (r_r = r_s + 2 r_p) about the origin:
/// driven (sun, ring), or the ring held by the ground.
fn planetary(ring_fixed: bool, w_s: f64, w_r: f64) -> Value {
    let (r_s, r_p) = (0.05, 0.03);
    let r_r = r_s + 2.0 * r_p;
    let ring = if ring_fixed { "ground" } else { "ring" };
    let mut bodies = vec![
        body("sun", 0.0, 0.0, 0.2),
        body("carrier", 0.0, 0.0, 0.0),
        body("planet", r_s + r_p, 0.0, -0.4),
    ];
    let mut joints = vec![
        pin("Os", "ground", "sun", [0.0, 0.0]),
        pin("Oc", "ground", "carrier", [0.0, 0.0]),
        pin("Op", "carrier", "planet", [r_s + r_p, 0.0]),
        json!({"type": "gear", "name": "sun_planet", "body_a": "sun", "body_b": "planet",
               "radius_a": r_s, "radius_b": r_p, "carrier": "carrier"}),
        json!({"type": "gear", "name": "planet_ring", "body_a": ring, "body_b": "planet",
               "radius_a": r_r, "radius_b": r_p, "internal": true, "carrier": "carrier"}),
    ];
    let mut drivers = vec![drive("sun", 0.2, w_s)];
    if !ring_fixed {
        bodies.push(body("ring", 0.0, 0.0, 0.7));
        joints.push(pin("Or", "ground", "ring", [0.0, 0.0]));
        drivers.push(json!({"type": "angle", "name": "ring_input", "body": "ring",
                            "law": {"type": "linear", "value": 0.7, "rate": w_r}}));
    }
    json!({"bodies": bodies, "joints": joints, "drivers": drivers})
}

#[test]
fn planetary_train_obeys_willis_formula() {
    // Willis: (w_s - w_c) / (w_r - w_c) = -z_r / z_s, so w_c = (z_s w_s + z_r w_r) / (z_s + z_r);
    // the planet relative to the carrier: (w_p - w_c) = -(z_s / z_p) (w_s - w_c)
    let (z_s, z_p, z_r) = (0.05, 0.03, 0.11);
    for (ring_fixed, w_s, w_r) in [(true, 6.0, 0.0), (false, 6.0, -2.5)] {
        let times = revolution(w_s, 361);
        let run = Run::new(planetary(ring_fixed, w_s, w_r), &times);
        let w_c = (z_s * w_s + z_r * w_r) / (z_s + z_r);
        let w_p = w_c - z_s / z_p * (w_s - w_c);
        let [qc, qdc, qddc] = run.column("carrier.theta");
        let [qp, qdp, qddp] = run.column("planet.theta");
        for (k, t) in times.iter().enumerate() {
            let scale = 1.0 + w_s.abs() * t;
            assert!((qc[k] - w_c * t).abs() <= 1e-12 * scale, "carrier angle at {t}");
            assert!((qp[k] - (-0.4 + w_p * t)).abs() <= 1e-12 * scale, "planet angle at {t}");
            assert!((qdc[k] - w_c).abs() <= 1e-12 * w_s.abs(), "carrier rate {} vs {w_c}", qdc[k]);
            assert!((qdp[k] - w_p).abs() <= 1e-12 * w_s.abs(), "planet rate {} vs {w_p}", qdp[k]);
            assert!(qddc[k].abs() <= 1e-12 && qddp[k].abs() <= 1e-10, "accelerations vanish");
            let willis =
                if ring_fixed { (w_s - qdc[k]) / (0.0 - qdc[k]) } else { (w_s - qdc[k]) / (w_r - qdc[k]) };
            assert!((willis + z_r / z_s).abs() <= 1e-10, "Willis ratio {willis}");
        }
        // the planet's centre stays on its circle about the sun: the pins hold it there
        let [px, _, _] = run.column("planet.x");
        let [py, _, _] = run.column("planet.y");
        for k in 0..times.len() {
            assert!((px[k].hypot(py[k]) - (z_s + z_p)).abs() <= 1e-12);
        }
    }
}

#[test]
fn rack_travel_is_radius_times_pinion_turn() {
    // pinion about a fixed pivot drives a rack guided along x: x = x0 + r (theta - theta0)
    let (r, w, th0) = (0.04, 2.0, 0.3);
    let desc = json!({
        "bodies": [body("pinion", 0.0, 0.0, th0), body("rack", 0.1, -r, 0.0)],
        "joints": [
            pin("O", "ground", "pinion", [0.0, 0.0]),
            {"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "rack",
             "at": [0.1, -r], "axis": [1.0, 0.0]},
            {"type": "rack_pinion", "name": "mesh", "body_a": "pinion", "body_b": "rack",
             "radius": r, "axis": [1.0, 0.0]},
        ],
        "drivers": [drive("pinion", th0, w)],
    });
    let times = revolution(w, 181);
    let run = Run::new(desc, &times);
    let [x, xd, xdd] = run.column("rack.x");
    for (k, t) in times.iter().enumerate() {
        assert!((x[k] - (0.1 + r * w * t)).abs() <= 1e-12 * (0.1 + r * w * t), "x at {t}");
        assert!((xd[k] - r * w).abs() <= 1e-12 * r * w);
        assert!(xdd[k].abs() <= 1e-12);
    }
}

#[test]
fn wheel_rolling_on_a_ground_rack_and_a_line() {
    // a wheel of radius r rolls on the ground (the rack, along +x), its centre held on the
    // line y = r by a point-on-line joint: a counter-clockwise turn rolls it to the left,
    // x = x0 - r (theta - theta0), and a rim point traces a cycloid
    let (r, w, x0) = (0.05, 3.0, 0.2);
    let desc = json!({
        "bodies": [body("wheel", x0, r, 0.0)],
        "joints": [
            {"type": "point_on_line", "name": "axle", "body_a": "wheel", "body_b": "ground",
             "at": [x0, r], "axis": [1.0, 0.0]},
            {"type": "rack_pinion", "name": "road", "body_a": "wheel", "body_b": "ground",
             "radius": r, "axis": [1.0, 0.0]},
        ],
        "drivers": [drive("wheel", 0.0, w)],
    });
    let times = revolution(w, 181);
    let run = Run::new(desc, &times);
    let [x, xd, xdd] = run.column("wheel.x");
    let [y, yd, _] = run.column("wheel.y");
    for (k, t) in times.iter().enumerate() {
        assert!((x[k] - (x0 - r * w * t)).abs() <= 1e-12, "x at {t}");
        assert!((xd[k] + r * w).abs() <= 1e-12 && xdd[k].abs() <= 1e-12);
        assert!((y[k] - r).abs() <= 1e-13 && yd[k].abs() <= 1e-13);
    }
}

#[test]
fn belts_turn_pulleys_the_same_way_and_crossed_belts_the_other() {
    for (crossed, sign) in [(false, 1.0), (true, -1.0)] {
        let (r_a, r_b, w) = (0.03, 0.075, 5.0);
        let desc = json!({
            "bodies": [body("a", 0.0, 0.0, 0.1), body("b", 0.4, 0.1, 2.0)],
            "joints": [
                pin("Oa", "ground", "a", [0.0, 0.0]),
                pin("Ob", "ground", "b", [0.4, 0.1]),
                {"type": "belt", "name": "belt", "body_a": "a", "body_b": "b",
                 "radius_a": r_a, "radius_b": r_b, "crossed": crossed},
            ],
            "drivers": [drive("a", 0.1, w)],
        });
        let times = revolution(w, 91);
        let run = Run::new(desc, &times);
        let [q, qd, qdd] = run.column("b.theta");
        for (k, t) in times.iter().enumerate() {
            assert!((q[k] - (2.0 + sign * r_a / r_b * w * t)).abs() <= 1e-12 * (1.0 + w * t));
            assert!((qd[k] - sign * r_a / r_b * w).abs() <= 1e-12 * w && qdd[k].abs() <= 1e-12);
        }
    }
}

#[test]
fn belt_on_a_carrier_turns_relative_to_it() {
    // pulley a held by the ground, pulley b on an arm about a's centre: driving the arm
    // turns b relative to the arm by (r_a / r_b) times a's turn relative to the arm
    let (ratio, w) = (2.0, 1.5);
    let desc = json!({
        "bodies": [body("arm", 0.0, 0.0, 0.0), body("b", 0.3, 0.0, 0.0)],
        "joints": [
            pin("Oc", "ground", "arm", [0.0, 0.0]),
            pin("Ob", "arm", "b", [0.3, 0.0]),
            {"type": "belt", "name": "chain", "body_a": "ground", "body_b": "b", "ratio": ratio,
             "carrier": "arm"},
        ],
        "drivers": [drive("arm", 0.0, w)],
    });
    let times = revolution(w, 91);
    let run = Run::new(desc, &times);
    let [q, qd, _] = run.column("b.theta");
    for (k, t) in times.iter().enumerate() {
        // theta_b - theta_c = ratio (theta_a - theta_c), theta_a = 0, theta_c = w t
        assert!((q[k] - (1.0 - ratio) * w * t).abs() <= 1e-12 * (1.0 + w * t));
        assert!((qd[k] - (1.0 - ratio) * w).abs() <= 1e-12 * w);
    }
}

#[test]
fn fixed_orientation_and_parallel_make_a_translating_coupler() {
    // a plate pinned to a crank's end, kept at its angle to the ground: it translates on
    // the crank circle, origin = pin + (its offset), theta constant
    for kind in ["fixed_orientation", "parallel"] {
        let (r, w, th0, phi): (f64, f64, f64, f64) = (0.1, 4.0, 0.5, 0.35);
        let pin_at = [r * th0.cos(), r * th0.sin()];
        let keep = if kind == "parallel" {
            json!({"type": "parallel", "name": "keep", "body_a": "ground", "body_b": "plate",
                   "axis_a": [phi.cos(), phi.sin()], "axis_b": [-phi.cos(), -phi.sin()]})
        } else {
            json!({"type": "fixed_orientation", "name": "keep", "body_a": "ground", "body_b": "plate"})
        };
        let desc = json!({
            "bodies": [body("crank", 0.0, 0.0, th0), body("plate", pin_at[0] + 0.2, pin_at[1], phi)],
            "joints": [pin("O", "ground", "crank", [0.0, 0.0]), pin("A", "crank", "plate", pin_at), keep],
            "drivers": [drive("crank", th0, w)],
        });
        let times = revolution(w, 181);
        let run = Run::new(desc, &times);
        let th: Vec<f64> = times.iter().map(|t| th0 + w * t).collect();
        let x: Vec<f64> = th.iter().map(|th| r * th.cos() + 0.2).collect();
        let yd: Vec<f64> = th.iter().map(|th| r * w * th.cos()).collect();
        let ydd: Vec<f64> = th.iter().map(|th| -r * w * w * th.sin()).collect();
        let [gx, _, _] = run.column("plate.x");
        let [_, gyd, gydd] = run.column("plate.y");
        let [gth, gthd, gthdd] = run.column("plate.theta");
        assert!(
            rel_err(&gx, &x) <= TOL && rel_err(&gyd, &yd) <= TOL && rel_err(&gydd, &ydd) <= TOL,
            "{kind}"
        );
        let max_dev = gth.iter().fold(0.0f64, |m, v| m.max((v - phi).abs()));
        assert!(max_dev <= 1e-13, "{kind}: theta drifts {max_dev}");
        assert!(gthd.iter().chain(&gthdd).all(|v| v.abs() <= 1e-12), "{kind}");
    }
}

#[test]
fn linear_coupling_ties_a_slide_to_a_turn() {
    // a slider on x coupled to a crank's angle: x - 0.05 theta = value (from the drawing)
    let (w, th0) = (2.0, 0.25);
    let desc = json!({
        "bodies": [body("crank", 0.0, 0.0, th0), body("slider", 0.3, 0.2, 0.0)],
        "joints": [
            pin("O", "ground", "crank", [0.0, 0.0]),
            {"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "slider",
             "at": [0.3, 0.2], "axis": [1.0, 0.0]},
            {"type": "linear_coupling", "name": "screw", "body_a": "crank", "body_b": "slider",
             "coefficients_a": {"theta": -0.05}, "coefficients_b": {"x": 1.0}},
        ],
        "drivers": [drive("crank", th0, w)],
    });
    let times = revolution(w, 91);
    let run = Run::new(desc, &times);
    let [x, xd, xdd] = run.column("slider.x");
    for (k, t) in times.iter().enumerate() {
        assert!((x[k] - (0.3 + 0.05 * w * t)).abs() <= 1e-13);
        assert!((xd[k] - 0.05 * w).abs() <= 1e-13 && xdd[k].abs() <= 1e-13);
    }
}

// --- finite differences for the variants `samples()` does not reach ----------------------------

fn phi(c: &ConstraintKind, qa: [f64; 3], qb: [f64; 3], s: f64) -> [f64; MAX_ROWS] {
    let mut r = Rows::default();
    c.position(&Frame::new(qa, [0.0; 3]), &Frame::new(qb, [0.0; 3]), &Extra { s, sd: 0.0 }, 0.0, &mut r);
    r.phi
}

fn shift(q: [f64; 3], h: f64, d: [f64; 3]) -> [f64; 3] {
    [q[0] + h * d[0], q[1] + h * d[1], q[2] + h * d[2]]
}

#[test]
fn variants_match_finite_differences() {
    let (k_a, k_b) = Gear::coefficients(0.11, 0.03, true);
    let variants = [
        ConstraintKind::Gear(Gear { k_a, k_b, value: 0.4, carrier: false, mesh: None }),
        ConstraintKind::Belt(Belt(Gear { k_a: 1.0, k_b: 0.25, value: -0.1, carrier: false, mesh: None })),
        ConstraintKind::PointOnLine(PointOnLine {
            u_a: [0.1, 0.2],
            u_b: [0.0, 0.0],
            e_b: [0.6, 0.8],
            offset: 0.0,
        }),
        ConstraintKind::RackPinion(RackPinion {
            u_a: [0.0, 0.0],
            u_b: [0.2, 0.1],
            e_b: [1.0, 0.0],
            radius: 0.3,
            delta0: 0.0,
        }),
        ConstraintKind::LinearCoupling(LinearCoupling {
            c_a: [0.0, 0.0, 1.5],
            c_b: [0.0, 0.0, -0.5],
            value: 0.2,
        }),
    ];
    let (qa, qb) = ([0.3, -0.2, 0.9], [-0.1, 0.4, -2.1]);
    let (qda, qdb) = ([1.1, -0.7, 2.3], [0.4, 0.9, -1.6]);
    for c in &variants {
        let extra = Extra { s: 0.7, sd: -1.2 };
        let mut rows = Rows::default();
        c.position(&Frame::new(qa, qda), &Frame::new(qb, qdb), &extra, 0.0, &mut rows);
        let h = 1e-6;
        for j in 0..3 {
            let mut e = [0.0; 3];
            e[j] = 1.0;
            let fd_a = (phi(c, shift(qa, h, e), qb, extra.s)[0] - phi(c, shift(qa, -h, e), qb, extra.s)[0])
                / (2.0 * h);
            let fd_b = (phi(c, qa, shift(qb, h, e), extra.s)[0] - phi(c, qa, shift(qb, -h, e), extra.s)[0])
                / (2.0 * h);
            assert!((fd_a - rows.jac_a[0][j]).abs() < 1e-8, "{} d/dq_a[{j}]", c.label());
            assert!((fd_b - rows.jac_b[0][j]).abs() < 1e-8, "{} d/dq_b[{j}]", c.label());
        }
        // without a carrier the rows must not depend on the extra coordinate
        assert!(!c.has_extra(), "{}", c.label());
        assert_eq!(phi(c, qa, qb, 5.0), phi(c, qa, qb, -3.0), "{}", c.label());
        assert_eq!(rows.jac_s, [0.0; MAX_ROWS], "{}", c.label());
        let mut gamma = [0.0; MAX_ROWS];
        c.gamma(&Frame::new(qa, qda), &Frame::new(qb, qdb), &extra, 0.0, &mut gamma);
        let h = 1e-4;
        let fd = -(phi(c, shift(qa, h, qda), shift(qb, h, qdb), 0.0)[0] - 2.0 * phi(c, qa, qb, 0.0)[0]
            + phi(c, shift(qa, -h, qda), shift(qb, -h, qdb), 0.0)[0])
            / (h * h);
        assert!(
            (fd - gamma[0]).abs() < 1e-5 * (1.0 + gamma[0].abs()),
            "{} gamma {fd} vs {}",
            c.label(),
            gamma[0]
        );
    }
}

// --- bad input ------------------------------------------------------------------------------------

/// Compiles two bodies a (at the origin) and b (at (0.3, 0)) with the given joint; returns
/// the error's message.
fn refusal(joint: Value) -> String {
    let desc = json!({
        "bodies": [body("a", 0.0, 0.0, 0.0), body("b", 0.3, 0.0, 0.0), body("c", 0.1, 0.1, 0.0)],
        "joints": [joint],
    });
    match Model::from_json(&desc.to_string(), Options::default()) {
        Err(e @ ModelError::Constraint { .. }) => e.to_string(),
        other => panic!("expected a refusal naming the joint, got {other:?}"),
    }
}

#[test]
fn bad_joints_are_refused_naming_the_joint() {
    let cases = [
        (
            json!({"type": "distance", "name": "J", "body_a": "a", "at_a": [0.0, 0.0], "body_b": "nobody", "at_b": [0.3, 0.0]}),
            "nobody",
        ),
        (
            json!({"type": "distance", "name": "J", "body_a": "a", "at_a": [0.1, 0.0], "body_b": "b", "at_b": [0.1, 0.0]}),
            "coincide",
        ),
        (
            json!({"type": "distance", "name": "J", "body_a": "a", "at_a": [0.0, 0.0], "body_b": "b", "at_b": [0.3, 0.0], "length": -1.0}),
            "length -1 must be finite and > 0",
        ),
        (
            json!({"type": "point_on_line", "name": "J", "body_a": "a", "body_b": "b", "at": [0.0, 0.0], "axis": [0.0, 0.0]}),
            "axis [0.0, 0.0] must be a finite, non-zero direction",
        ),
        (
            json!({"type": "point_on_line", "name": "J", "body_a": "a", "body_b": "a", "at": [0.0, 0.0], "axis": [1.0, 0.0]}),
            "itself",
        ),
        (
            json!({"type": "gear", "name": "J", "body_a": "a", "body_b": "b", "radius_a": 0.1, "radius_b": 0.0}),
            "radius_b 0 must be finite and > 0",
        ),
        (
            json!({"type": "gear", "name": "J", "body_a": "a", "body_b": "b", "ratio": -2.0}),
            "ratio -2 must be finite and > 0",
        ),
        (
            json!({"type": "gear", "name": "J", "body_a": "a", "body_b": "b", "radius_a": 0.1, "radius_b": 0.2, "ratio": 0.5}),
            "either radius_a and radius_b, or ratio",
        ),
        (
            json!({"type": "gear", "name": "J", "body_a": "a", "body_b": "b"}),
            "either radius_a and radius_b, or ratio",
        ),
        (
            json!({"type": "gear", "name": "J", "body_a": "a", "body_b": "b", "ratio": 1.0, "internal": true}),
            "cannot have ratio 1",
        ),
        (
            json!({"type": "gear", "name": "J", "body_a": "a", "body_b": "b", "ratio": 2.0, "centre_b": [0.0, 0.0]}),
            "centres coincide",
        ),
        (
            json!({"type": "gear", "name": "J", "body_a": "a", "body_b": "b", "radius_a": 0.1, "radius_b": 0.1, "internal": true}),
            "different radii",
        ),
        (
            json!({"type": "gear", "name": "J", "body_a": "a", "body_b": "b", "ratio": 2.0, "carrier": "b"}),
            "carrier 'b' is one of its own two bodies",
        ),
        (
            json!({"type": "gear", "name": "J", "body_a": "a", "body_b": "b", "ratio": 2.0, "carrier": "arm"}),
            "'arm', which is not in the model",
        ),
        (
            json!({"type": "rack_pinion", "name": "J", "body_a": "a", "body_b": "b", "radius": 0.0, "axis": [1.0, 0.0]}),
            "radius 0 must be finite and > 0",
        ),
        (
            json!({"type": "rack_pinion", "name": "J", "body_a": "ground", "body_b": "b", "radius": 0.1, "axis": [1.0, 0.0]}),
            "pinion (body_a) is the ground",
        ),
        (
            json!({"type": "rack_pinion", "name": "J", "body_a": "a", "body_b": "b", "radius": 0.1, "axis": [0.0, 0.0]}),
            "axis",
        ),
        (
            json!({"type": "belt", "name": "J", "body_a": "a", "body_b": "b", "radius_a": -0.1, "radius_b": 0.1}),
            "radius_a -0.1 must be finite and > 0",
        ),
        (
            json!({"type": "belt", "name": "J", "body_a": "a", "body_b": "b", "ratio": 2.0, "carrier": "a"}),
            "carrier 'a' is one of its own two bodies",
        ),
        (
            json!({"type": "parallel", "name": "J", "body_a": "a", "body_b": "b", "axis_a": [1.0, 0.0], "axis_b": [0.0, 2.0]}),
            "perpendicular",
        ),
        (
            json!({"type": "parallel", "name": "J", "body_a": "a", "body_b": "b", "axis_a": [0.0, 0.0], "axis_b": [1.0, 0.0]}),
            "axis_a",
        ),
        (json!({"type": "fixed_orientation", "name": "J", "body_a": "a", "body_b": "ghost"}), "ghost"),
        (
            json!({"type": "linear_coupling", "name": "J", "body_a": "a", "body_b": "b"}),
            "no non-zero coefficient",
        ),
        (
            json!({"type": "linear_coupling", "name": "J", "body_a": "a", "body_b": "ground", "coefficients_a": {"x": 1.0}, "coefficients_b": {"theta": 1.0}}),
            "coefficients_b on the ground",
        ),
    ];
    for (joint, fragment) in cases {
        let message = refusal(joint.clone());
        assert!(message.starts_with("joint 'J'"), "{message}");
        assert!(message.contains(fragment), "{joint}: {message}");
    }
}

#[test]
fn unknown_coefficient_names_are_refused_when_read() {
    let desc = json!({
        "bodies": [body("a", 0.0, 0.0, 0.0)],
        "joints": [{"type": "linear_coupling", "name": "J", "body_a": "a", "body_b": "ground",
                    "coefficients_a": {"phi": 1.0}}],
    });
    let err = Model::from_json(&desc.to_string(), Options::default()).unwrap_err().to_string();
    assert!(err.contains("unknown field `phi`"), "{err}");
}

#[test]
fn screw_analysis_refuses_the_library_joints_by_name() {
    use linkwork::screw::MechanismJoints;
    let desc = json!({
        "bodies": [body("a", 0.0, 0.0, 0.0), body("b", 0.3, 0.0, 0.0)],
        "joints": [
            pin("O", "ground", "a", [0.0, 0.0]),
            {"type": "gear", "name": "mesh", "body_a": "a", "body_b": "b", "ratio": 2.0},
        ],
    });
    let desc = linkwork::Description::from_json(&desc.to_string()).unwrap();
    let err = MechanismJoints::from_description(&desc).unwrap_err().to_string();
    assert!(err.contains("joint 'mesh' is a gear joint"), "{err}");
    assert!(err.contains("revolute, prismatic and fixed"), "{err}");
}

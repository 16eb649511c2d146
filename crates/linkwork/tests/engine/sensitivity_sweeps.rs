//! Exact sensitivities of whole sweeps (dq/dp, dqd/dp, dqdd/dp and the points') against
//! differences of whole sweeps with the parameter moved, on mechanisms that hold every
//! joint type and every driver kind, for every engine parameter they have
//! (`Parameter::all`), and for the description paths a study names; and dq/dp alone (the
//! positions' sensitivities, on the structured path where the model's groups allow it).
//!
//! The differences are the fourth-order central ones, (f(-2h) - 8 f(-h) + 8 f(h) -
//! f(2h)) / 12h, with h = 1e-4 (1e-4 of the model's size for lengths): truncation
//! ~h^4 |f^(5)| / 30, below 1e-12 here, and round-off ~|q| eps / h ~ 1e-12, the sweeps
//! converging Newton to ~1e-15 (the general solver for every moved design). Relative
//! agreement 1e-8 is then asked of every array (against its largest entry, with an
//! absolute floor of 1e-9 for the sensitivities that vanish).

use crate::common;

use common::with_number;
use linkwork::constraints::Constraint;
use linkwork::sensitivity::{
    sensitivity_sweep, Parameter, PointRequest, SensitivityOutput, SensitivityPath, SensitivityRequest,
};
use linkwork::{Data, Model, Options, SolverKind};
use serde_json::{json, Value};

fn body(name: &str, x: f64, y: f64, theta: f64) -> Value {
    json!({"name": name, "x": x, "y": y, "theta": theta})
}

fn pin(name: &str, a: &str, b: &str, at: [f64; 2]) -> Value {
    json!({"type": "revolute", "name": name, "body_a": a, "body_b": b, "at": at})
}

fn angle(name: &str, body: &str, law: Value) -> Value {
    json!({"type": "angle", "name": name, "body": body, "law": law})
}

fn linear(value: f64, rate: f64) -> Value {
    json!({"type": "linear", "value": value, "rate": rate})
}

fn general(desc: &Value) -> Model {
    let options = Options { solver: SolverKind::General, ..Options::default() };
    Model::from_json(&desc.to_string(), options).unwrap()
}

/// The sweep of `model` (plain q, qd, qdd and the named points' r, rd, rdd per step).
fn plain(model: &Model, times: &[f64]) -> Vec<[Vec<f64>; 6]> {
    let mut data = Data::new(model);
    let points: Vec<PointRequest> = points(model);
    let mut out = SensitivityOutput::new(model, times, &[], points.len());
    sensitivity_sweep(model, &mut data, times, &[], &points, &mut out, 0, &mut |_| true).unwrap();
    let (n, np) = (model.n_coords, points.len());
    (0..times.len())
        .map(|k| {
            let row = |v: &[f64]| v[k * n..(k + 1) * n].to_vec();
            let (q, qd, qdd) = (row(&out.sweep.q), row(&out.sweep.qd), row(&out.sweep.qdd));
            let mut pts = [vec![], vec![], vec![]];
            for req in &points[..np] {
                let b = req.body.unwrap();
                let (th, w, al) = (q[3 * b + 2], qd[3 * b + 2], qdd[3 * b + 2]);
                let (s, c) = th.sin_cos();
                let u = req.local;
                let au = [c * u[0] - s * u[1], s * u[0] + c * u[1]];
                let bu = [-au[1], au[0]];
                for i in 0..2 {
                    pts[0].push(q[3 * b + i] + au[i]);
                    pts[1].push(qd[3 * b + i] + bu[i] * w);
                    pts[2].push(qdd[3 * b + i] + bu[i] * al - au[i] * w * w);
                }
            }
            let [p, pd, pdd] = pts;
            [q, qd, qdd, p, pd, pdd]
        })
        .collect()
}

fn points(model: &Model) -> Vec<PointRequest> {
    model
        .points
        .iter()
        .enumerate()
        .map(|(k, p)| PointRequest { body: p.body, local: p.local, named: Some(k) })
        .collect()
}

/// The fourth-order central difference of the sweeps of `moved(d)`.
fn differences(moved: &dyn Fn(f64) -> Model, h: f64, times: &[f64]) -> Vec<[Vec<f64>; 6]> {
    let runs: Vec<Vec<[Vec<f64>; 6]>> =
        [-2.0, -1.0, 1.0, 2.0].iter().map(|k| plain(&moved(k * h), times)).collect();
    (0..times.len())
        .map(|k| {
            std::array::from_fn(|a| {
                (0..runs[0][k][a].len())
                    .map(|j| {
                        (runs[0][k][a][j] - 8.0 * runs[1][k][a][j] + 8.0 * runs[2][k][a][j]
                            - runs[3][k][a][j])
                            / (12.0 * h)
                    })
                    .collect()
            })
        })
        .collect()
}

/// Compares parameter `j` of `out` with the differences; returns the worst relative error.
fn compare(
    what: &str,
    out: &SensitivityOutput,
    j: usize,
    fd: &[Vec<f64>; 6],
    k: usize,
    worst: &mut [f64; 6],
) {
    let n = out.n_params;
    let nc = out.sweep.n_coords;
    let np2 = 2 * out.n_points;
    let arrays: [(&[f64], usize); 6] = [
        (&out.dq, nc),
        (&out.dqd, nc),
        (&out.dqdd, nc),
        (&out.points, np2),
        (&out.points_d, np2),
        (&out.points_dd, np2),
    ];
    for (a, (v, m)) in arrays.iter().enumerate() {
        // a derivative not asked for
        if v.is_empty() {
            continue;
        }
        for i in 0..*m {
            let got = v[(k * m + i) * n + j];
            let want = fd[a][i];
            worst[a] = worst[a].max((got - want).abs());
            if !(got - want).abs().is_finite() {
                panic!("{what}: array {a}, step {k}, entry {i}: {got} vs {want}");
            }
        }
    }
}

/// Every engine parameter of `desc` (or the description paths `paths`, moved in the
/// description itself) against differences of whole sweeps.
fn check(label: &str, desc: Value, times: &[f64], paths: &[&str]) {
    let model = Model::from_json(&desc.to_string(), Options::default()).unwrap();
    let params: Vec<Parameter> = if paths.is_empty() {
        Parameter::all(&model)
    } else {
        paths.iter().map(|p| Parameter::resolve(&model, p).unwrap()).collect()
    };
    assert!(!params.is_empty(), "{label}: no parameters");
    let mut data = Data::new(&model);
    let pts = points(&model);
    let mut out = SensitivityOutput::new(&model, times, &params, pts.len());
    sensitivity_sweep(&model, &mut data, times, &params, &pts, &mut out, 0, &mut |_| true).unwrap();
    assert_eq!(out.n_done, times.len());
    assert_eq!(out.path, SensitivityPath::General, "{label}: {}", out.path_reason);
    // dq/dp alone: the structured path where every group is a crank or a dyad
    let mut data = Data::new(&model);
    let request = SensitivityRequest { derivatives: 0, ..SensitivityRequest::default() };
    let mut out0 = SensitivityOutput::with_request(&model, times, &params, pts.len(), request);
    sensitivity_sweep(&model, &mut data, times, &params, &pts, &mut out0, 0, &mut |_| true).unwrap();
    assert_eq!(out0.n_done, times.len());
    assert!(out0.dqd.is_empty() && out0.points_dd.is_empty(), "{label}: rates solved unasked");
    let size = model.length_scale;
    for (j, p) in params.iter().enumerate() {
        let h = 1e-4 * if p.nominal.abs() > 0.0 { p.nominal.abs().max(0.1 * size) } else { size };
        let moved = |d: f64| -> Model {
            if paths.is_empty() {
                let mut m = general(&desc);
                let &(c, i, _) = &p.seeds[0];
                *m.constraints[c].kind.params_mut()[i].1 += d;
                m
            } else {
                general(&with_number(&desc, &p.name, |_| p.nominal + d))
            }
        };
        let fd = differences(&moved, h, times);
        let (mut worst, mut worst0) = ([0.0f64; 6], [0.0f64; 6]);
        let mut scale = [0.0f64; 6];
        for (k, row) in fd.iter().enumerate() {
            compare(&format!("{label} {}", p.name), &out, j, row, k, &mut worst);
            compare(&format!("{label} {}, positions only", p.name), &out0, j, row, k, &mut worst0);
            for a in 0..6 {
                scale[a] = scale[a].max(row[a].iter().fold(0.0f64, |m, x| m.max(x.abs())));
            }
        }
        for a in 0..6 {
            let what = ["dq", "dqd", "dqdd", "dr", "drd", "drdd"][a];
            assert!(
                worst[a] <= 1e-8 * scale[a] + 1e-9,
                "{label}: d{what}/d{}: worst error {:e} against differences as large as {:e}",
                p.name,
                worst[a],
                scale[a]
            );
            assert!(
                worst0[a] <= 1e-8 * scale[a] + 1e-9,
                "{label}: d{what}/d{} alone ({} path): worst error {:e} against differences as large as {:e}",
                p.name,
                out0.path.label(),
                worst0[a],
                scale[a]
            );
        }
    }
}

fn steps(t_end: f64, n: usize) -> Vec<f64> {
    (0..n).map(|k| t_end * k as f64 / (n - 1) as f64).collect()
}

fn four_bar(law: Value) -> Value {
    // O2 (0, 0), O4 (0.35, 0); crank 0.2, coupler 0.35, rocker 0.25; a coupler point P
    let (a, b) = ([0.2 * 0.3f64.cos(), 0.2 * 0.3f64.sin()], [0.517365536421962, 0.1857115430397069]);
    json!({
        "bodies": [body("crank", 0.0, 0.0, 0.3), body("coupler", a[0], a[1], 0.0), body("rocker", 0.35, 0.0, 2.2)],
        "joints": [
            pin("O2", "ground", "crank", [0.0, 0.0]),
            pin("A", "crank", "coupler", a),
            pin("B", "coupler", "rocker", b),
            pin("O4", "ground", "rocker", [0.35, 0.0]),
        ],
        "drivers": [angle("input", "crank", law)],
        "points": [{"name": "P", "body": "coupler", "at": [0.2, 0.15]}],
    })
}

#[test]
fn four_bar_revolutes_and_angle_driver_laws() {
    check("four-bar, linear law", four_bar(linear(0.3, 5.0)), &steps(0.6, 13), &[]);
    let harmonic = json!({"type": "harmonic", "mean": 0.8, "amplitude": 0.5, "omega": 4.0, "phase": 0.2});
    check("four-bar, harmonic law", four_bar(harmonic), &steps(1.0, 11), &[]);
    let poly = json!({"type": "polynomial", "coefficients": [0.3, 2.0, 1.5, -0.4]});
    check("four-bar, polynomial law", four_bar(poly), &steps(0.8, 9), &[]);
    let constant = json!({"type": "constant", "value": 0.45});
    check("four-bar, constant law", four_bar(constant), &steps(0.1, 3), &[]);
}

#[test]
fn four_bar_description_paths() {
    let paths = [
        "joints.B.at.0",
        "joints.B.at.1",
        "joints.O4.at.0",
        "joints.A.at.1",
        "drivers.input.law.rate",
        "points.P.at.1",
    ];
    check("four-bar paths", four_bar(linear(0.3, 5.0)), &steps(0.6, 13), &paths);
}

#[test]
fn distance_joint_and_relative_angle_driver() {
    let (a, b) = ([0.2 * 0.3f64.cos(), 0.2 * 0.3f64.sin()], [0.517365536421962, 0.1857115430397069]);
    let desc = json!({
        "bodies": [body("crank", 0.0, 0.0, 0.3), body("rocker", 0.35, 0.0, 2.2)],
        "joints": [
            pin("O2", "ground", "crank", [0.0, 0.0]),
            pin("O4", "ground", "rocker", [0.35, 0.0]),
            {"type": "distance", "name": "AB", "body_a": "crank", "at_a": a, "body_b": "rocker", "at_b": b},
        ],
        "drivers": [{"type": "relative_angle", "name": "input", "body_a": "ground", "body_b": "crank",
                     "law": linear(0.3, 4.0)}],
    });
    check("distance joint", desc.clone(), &steps(0.6, 11), &[]);
    check("distance joint paths", desc, &steps(0.6, 11), &["joints.AB.at_a.0", "joints.AB.at_b.1"]);
}

#[test]
fn slider_crank_prismatic_and_translation_driver() {
    // crank 0.1 about the origin, rod 0.3 to a slider on y = 0.02
    let th: f64 = 0.5;
    let a = [0.1 * th.cos(), 0.1 * th.sin()];
    let bx = a[0] + (0.3f64 * 0.3 - (a[1] - 0.02).powi(2)).sqrt();
    let desc = json!({
        "bodies": [body("crank", 0.0, 0.0, th), body("rod", a[0], a[1], 0.0), body("slider", bx, 0.02, 0.1)],
        "joints": [
            pin("O", "ground", "crank", [0.0, 0.0]),
            pin("A", "crank", "rod", a),
            pin("B", "rod", "slider", [bx, 0.02]),
            {"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "slider", "at": [bx, 0.02], "axis": [1.0, 0.0]},
        ],
        "drivers": [angle("input", "crank", json!({"type": "polynomial", "coefficients": [th, 3.0, 1.0]}))],
    });
    check("slider-crank", desc.clone(), &steps(0.5, 11), &[]);
    check("slider-crank paths", desc, &steps(0.5, 11), &["joints.guide.at.1", "joints.B.at.0"]);
    // the slider driven along the guide; a crank follows
    let desc = json!({
        "bodies": [body("crank", 0.0, 0.0, th), body("rod", a[0], a[1], 0.0), body("slider", bx, 0.02, 0.1)],
        "joints": [
            pin("O", "ground", "crank", [0.0, 0.0]),
            pin("A", "crank", "rod", a),
            pin("B", "rod", "slider", [bx, 0.02]),
            {"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "slider", "at": [bx, 0.02], "axis": [1.0, 0.1]},
        ],
        "drivers": [{"type": "translation", "name": "push", "joint": "guide", "law": linear(0.0, -0.1)}],
    });
    check("translation driver", desc.clone(), &steps(0.5, 11), &[]);
    check("translation driver paths", desc, &steps(0.5, 11), &["joints.guide.at.0", "drivers.push.law.rate"]);
}

#[test]
fn scotch_yoke_point_on_line() {
    let (r, th0, off): (f64, f64, f64) = (0.12, 0.2, 0.05);
    let p = [r * th0.cos(), r * th0.sin()];
    let desc = json!({
        "bodies": [body("crank", 0.0, 0.0, th0), body("yoke", p[0] - off, 0.0, 0.0)],
        "joints": [
            pin("O", "ground", "crank", [0.0, 0.0]),
            {"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "yoke", "at": [p[0] - off, 0.0], "axis": [1.0, 0.0]},
            {"type": "point_on_line", "name": "slot", "body_a": "crank", "body_b": "yoke", "at": p, "axis": [0.1, 1.0],
             "offset": 0.01},
        ],
        "drivers": [angle("input", "crank", linear(th0, 4.0))],
    });
    check("point on line", desc.clone(), &steps(0.5, 11), &[]);
    check("point on line paths", desc, &steps(0.5, 11), &["joints.slot.at.0", "joints.slot.offset"]);
}

#[test]
fn gears_on_the_ground_and_on_a_carrier() {
    let desc = json!({
        "bodies": [body("pinion", 0.0, 0.0, 0.4), body("gear", 0.2, 0.0, -1.3)],
        "joints": [
            pin("Oa", "ground", "pinion", [0.0, 0.0]),
            pin("Ob", "ground", "gear", [0.2, 0.0]),
            {"type": "gear", "name": "mesh", "body_a": "pinion", "body_b": "gear", "ratio": 0.6},
        ],
        "drivers": [angle("input", "pinion", linear(0.4, 3.0))],
    });
    check("gear pair", desc.clone(), &steps(0.5, 9), &[]);
    // ratio < 1: k_a = ratio moves, and the drawing's row constant with it
    check("gear pair ratio", desc.clone(), &steps(0.5, 9), &["joints.mesh.ratio"]);
    let mut desc = desc;
    desc["joints"][2]["ratio"] = json!(1.7);
    check("gear pair ratio > 1", desc, &steps(0.5, 9), &["joints.mesh.ratio"]);
    let (r_s, r_p) = (0.05, 0.03);
    let op = [(r_s + r_p) * 0.5f64.cos(), (r_s + r_p) * 0.5f64.sin()];
    let desc = json!({
        // the carrier drawn at 0.5 rad: the line of centres, and the rows' constants, too
        "bodies": [body("sun", 0.0, 0.0, 0.2), body("carrier", 0.0, 0.0, 0.5), body("planet", op[0], op[1], -0.4),
                   body("ring", 0.0, 0.0, 0.7)],
        "joints": [
            pin("Os", "ground", "sun", [0.0, 0.0]),
            pin("Oc", "ground", "carrier", [0.0, 0.0]),
            pin("Op", "carrier", "planet", op),
            pin("Or", "ground", "ring", [0.0, 0.0]),
            {"type": "gear", "name": "sun_planet", "body_a": "sun", "body_b": "planet", "radius_a": r_s, "radius_b": r_p, "carrier": "carrier"},
            {"type": "gear", "name": "planet_ring", "body_a": "ring", "body_b": "planet", "radius_a": r_s + 2.0 * r_p,
             "radius_b": r_p, "internal": true, "carrier": "carrier"},
        ],
        "drivers": [angle("input", "sun", linear(0.2, 6.0)), angle("ring_input", "ring", linear(0.7, -2.5))],
    });
    check("planetary", desc.clone(), &steps(0.4, 9), &[]);
    // on a carrier: the row constant is measured from the line of centres
    let radii = [
        "joints.sun_planet.radius_a",
        "joints.sun_planet.radius_b",
        "joints.planet_ring.radius_a",
        "joints.planet_ring.radius_b",
    ];
    check("planetary radii", desc, &steps(0.4, 9), &radii);
}

#[test]
fn belts_rack_and_pinion() {
    let desc = json!({
        "bodies": [body("arm", 0.0, 0.0, 0.0), body("b", 0.3, 0.0, 0.0), body("c", 0.4, 0.1, 2.0)],
        "joints": [
            pin("Oc", "ground", "arm", [0.0, 0.0]),
            pin("Ob", "arm", "b", [0.3, 0.0]),
            pin("Oc2", "ground", "c", [0.4, 0.1]),
            {"type": "belt", "name": "chain", "body_a": "ground", "body_b": "b", "ratio": 2.0, "carrier": "arm"},
            {"type": "belt", "name": "belt", "body_a": "arm", "body_b": "c", "radius_a": 0.03, "radius_b": 0.075, "crossed": true},
        ],
        "drivers": [angle("input", "arm", linear(0.0, 1.5))],
    });
    check("belts", desc.clone(), &steps(0.5, 9), &[]);
    check(
        "belt ratio and radii",
        desc.clone(),
        &steps(0.5, 9),
        &["joints.chain.ratio", "joints.belt.radius_a", "joints.belt.radius_b"],
    );
    // r_a > r_b: k_b moves, and with c drawn at 2 rad the row constant with it
    let mut desc = desc;
    desc["joints"][4]["radius_a"] = json!(0.075);
    desc["joints"][4]["radius_b"] = json!(0.03);
    check("belt radii, r_a > r_b", desc, &steps(0.5, 9), &["joints.belt.radius_a", "joints.belt.radius_b"]);
    let r = 0.04;
    let desc = json!({
        "bodies": [body("pinion", 0.0, 0.0, 0.3), body("rack", 0.1, -r, 0.0)],
        "joints": [
            pin("O", "ground", "pinion", [0.0, 0.0]),
            {"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "rack", "at": [0.1, -r], "axis": [1.0, 0.0]},
            {"type": "rack_pinion", "name": "mesh", "body_a": "pinion", "body_b": "rack", "radius": r, "axis": [1.0, 0.0]},
        ],
        "drivers": [angle("input", "pinion", linear(0.3, 2.0))],
    });
    check("rack and pinion", desc.clone(), &steps(0.5, 9), &[]);
    check("rack and pinion paths", desc, &steps(0.5, 9), &["joints.mesh.radius"]);
}

#[test]
fn orientation_parallel_coupling_and_weld() {
    let (r, th0, phi): (f64, f64, f64) = (0.1, 0.5, 0.35);
    let p = [r * th0.cos(), r * th0.sin()];
    for keep in [
        json!({"type": "parallel", "name": "keep", "body_a": "ground", "body_b": "plate",
               "axis_a": [phi.cos(), phi.sin()], "axis_b": [-phi.cos(), -phi.sin()]}),
        json!({"type": "fixed_orientation", "name": "keep", "body_a": "ground", "body_b": "plate"}),
    ] {
        let desc = json!({
            "bodies": [body("crank", 0.0, 0.0, th0), body("plate", p[0] + 0.2, p[1], phi), body("tab", p[0] + 0.3, p[1] + 0.1, 1.0)],
            "joints": [pin("O", "ground", "crank", [0.0, 0.0]), pin("A", "crank", "plate", p), keep,
                       {"type": "fixed", "name": "weld", "body_a": "plate", "body_b": "tab"}],
            "drivers": [angle("input", "crank", linear(th0, 4.0))],
        });
        check("orientation, weld", desc, &steps(0.5, 9), &[]);
    }
    // a slider on x tied to a crank's turn: x_s = x_0 + 0.05 (theta - theta0)
    let desc = json!({
        "bodies": [body("crank", 0.0, 0.0, th0), body("slider", 0.3, 0.0, 0.0)],
        "joints": [
            pin("O", "ground", "crank", [0.0, 0.0]),
            {"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "slider", "at": [0.3, 0.0], "axis": [1.0, 0.0]},
            {"type": "linear_coupling", "name": "tie", "body_a": "crank", "body_b": "slider",
             "coefficients_a": {"theta": -0.05}, "coefficients_b": {"x": 1.0}},
        ],
        "drivers": [angle("input", "crank", linear(th0, 4.0))],
    });
    check("linear coupling", desc, &steps(0.5, 9), &[]);
}

#[test]
fn distance_and_coordinate_drivers() {
    // a rocker about the ground moved by a linear actuator from a ground point
    let desc = json!({
        "bodies": [body("rocker", 0.0, 0.0, 0.5)],
        "joints": [pin("O", "ground", "rocker", [0.0, 0.0])],
        "drivers": [{"type": "distance", "name": "ram", "body_a": "ground", "at_a": [0.3, -0.1], "body_b": "rocker",
                     "at_b": [0.2 * 0.5f64.cos(), 0.2 * 0.5f64.sin()], "law": linear(0.28, 0.1)}],
    });
    check("distance driver", desc.clone(), &steps(0.5, 9), &[]);
    check(
        "distance driver paths",
        desc,
        &steps(0.5, 9),
        &["drivers.ram.at_a.0", "drivers.ram.at_b.1", "drivers.ram.law.value"],
    );
    // a crank whose pin's x follows a law
    let desc = json!({
        "bodies": [body("crank", 0.0, 0.0, 0.5)],
        "joints": [pin("O", "ground", "crank", [0.0, 0.0])],
        "drivers": [{"type": "coordinate", "name": "x", "body": "crank", "at": [0.2 * 0.5f64.cos(), 0.2 * 0.5f64.sin()],
                     "axis": "x", "law": linear(0.2 * 0.5f64.cos(), -0.05)}],
    });
    check("coordinate driver", desc.clone(), &steps(0.5, 9), &[]);
    check("coordinate driver paths", desc, &steps(0.5, 9), &["drivers.x.at.1"]);
}

#[test]
fn pin_in_slot_and_cam_followers() {
    let (e, big_r, rho) = (0.02, 0.05, 0.015);
    let circle = json!({"type": "circle", "centre": [e, 0.0], "radius": big_r});
    let polar = json!({"type": "polar", "centre": [0.0, 0.0], "angles": [0.0, 1.2, 2.0, 3.5, 5.0, std::f64::consts::TAU],
                       "radii": [0.05, 0.06, 0.048, 0.055, 0.05, 0.05]});
    for (follower, curve) in
        [("knife", circle.clone()), ("roller", circle.clone()), ("flat", circle), ("roller", polar)]
    {
        let top = 0.075;
        let (at, y) = match follower {
            "roller" => ([0.0, top], top),
            _ => ([0.0, 0.06], 0.06),
        };
        let mut joint = json!({"type": "cam_follower", "name": "F", "body_a": "cam", "body_b": "follower",
                               "follower": follower, "at": at, "curve": curve});
        if follower == "roller" {
            joint["radius"] = json!(rho);
        }
        if follower == "flat" {
            joint["face"] = json!([1.0, 0.0]);
        }
        let desc = json!({
            "bodies": [body("cam", 0.0, 0.0, 0.0), body("follower", 0.0, y, 0.0)],
            "joints": [
                pin("O", "ground", "cam", [0.0, 0.0]),
                {"type": "prismatic", "name": "guide", "body_a": "ground", "body_b": "follower", "at": [0.0, y], "axis": [0.0, 1.0]},
                joint,
            ],
            "drivers": [angle("input", "cam", json!({"type": "polynomial", "coefficients": [0.3, 10.0, 2.5]}))],
        });
        // the roller's contact curve needs the curve's fourth derivative: a polar table's
        // and a circle's are exact, so these agree to the same 1e-8
        let model = Model::from_json(&desc.to_string(), Options::default());
        if let Err(e) = model {
            panic!("{follower}: {e}");
        }
        check(&format!("{follower} follower"), desc.clone(), &steps(0.3, 9), &[]);
        check(&format!("{follower} follower paths"), desc, &steps(0.3, 9), &["joints.F.at.0"]);
    }
}

#[test]
fn unknown_and_unmapped_parameters_are_refused_by_name() {
    let model = Model::from_json(&four_bar(linear(0.3, 5.0)).to_string(), Options::default()).unwrap();
    for (name, says) in [
        ("joints.Z.at.0", "no joint 'Z'"),
        ("joints.B.at.2", ".0 (x) or .1 (y)"),
        ("drivers.input.law.omega", "law has law.value, law.rate"),
        ("bodies.crank.theta", "its drawn pose only names its frame"),
        ("constraints.B.length", "no engine number 'length'"),
        ("joints.B", "a parameter is a path"),
    ] {
        let e = Parameter::resolve(&model, name).unwrap_err();
        assert_eq!(e.name, name);
        assert!(e.to_string().contains(says), "{name}: {e}");
    }
}

#[test]
fn equal_gear_radii_are_refused_where_the_derivative_is_one_sided() {
    // k_a = r_a / max(r_a, r_b): at r_a = r_b the two sides' derivatives differ
    let desc = json!({
        "bodies": [body("a", 0.0, 0.0, 0.0), body("b", 0.1, 0.0, 0.0), body("c", 0.0, 0.3, 0.0)],
        "joints": [
            pin("Oa", "ground", "a", [0.0, 0.0]),
            pin("Ob", "ground", "b", [0.1, 0.0]),
            pin("Oc", "ground", "c", [0.0, 0.3]),
            {"type": "gear", "name": "mesh", "body_a": "a", "body_b": "b", "radius_a": 0.05, "radius_b": 0.05},
            {"type": "belt", "name": "belt", "body_a": "a", "body_b": "c", "ratio": 1.0},
        ],
        "drivers": [angle("input", "a", linear(0.0, 3.0))],
    });
    let model = Model::from_json(&desc.to_string(), Options::default()).unwrap();
    for name in ["joints.mesh.radius_a", "joints.mesh.radius_b", "joints.belt.ratio"] {
        let e = Parameter::resolve(&model, name).unwrap_err();
        assert!(e.to_string().contains("two radii are equal") && e.to_string().contains("one-sided"), "{e}");
    }
    let e = Parameter::resolve(&model, "joints.mesh.ratio").unwrap_err();
    assert!(e.to_string().contains("not mapped"), "{e}");
}

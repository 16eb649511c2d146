//! dq/dp on the structured path (each group's closed form differentiated, group by group)
//! against today's general path (Phi_q factored at every step, every joint's rows over
//! jets) at the same solved configurations, on the textbook mechanisms of cranks and
//! dyads, for every engine parameter (`Parameter::all`) and for description paths; the
//! rule that chooses the path; and the general path taking the steps next to a singular
//! configuration. (Against differences of whole sweeps: `sensitivity_sweeps.rs`, whose
//! every check also runs dq/dp alone.)

use crate::common;
use common::*;

use linkwork::files::read_path;
use linkwork::sensitivity::{
    sensitivity_sweep, Parameter, PointRequest, SensitivityOutput, SensitivityPath, SensitivityRequest,
};
use linkwork::{Data, Description, Model, Options, PointDesc, SolverKind};
use serde_json::{json, Value};
use std::f64::consts::TAU;

const TEXTBOOK: FourBar = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.25 };

fn example(name: &str) -> Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(name);
    read_path(&path).unwrap().compile(Options::default()).unwrap()
}

fn from_json(desc: &Value) -> Model {
    Model::from_json(&desc.to_string(), Options::default()).unwrap()
}

fn points(model: &Model) -> Vec<PointRequest> {
    let named = model.points.iter().enumerate();
    named.map(|(k, p)| PointRequest { body: p.body, local: p.local, named: Some(k) }).collect()
}

/// `n` times over one crank turn at 5 rad/s.
fn turn(n: usize) -> Vec<f64> {
    (0..n).map(|k| TAU / 5.0 * k as f64 / (n - 1) as f64).collect()
}

fn run(model: &Model, times: &[f64], params: &[Parameter], request: SensitivityRequest) -> SensitivityOutput {
    let pts = points(model);
    let mut data = Data::new(model);
    let mut out = SensitivityOutput::with_request(model, times, params, pts.len(), request);
    sensitivity_sweep(model, &mut data, times, params, &pts, &mut out, 0, &mut |_| true).unwrap();
    assert_eq!(out.n_done, times.len());
    out
}

/// The worst error of `got` against `want` (n_steps x m x n_params) per parameter, over
/// the largest |want| of that parameter, or 1e-3 of the largest of any where that is less:
/// a parameter that moves the array only to round-off (a pin moved across its link, a
/// slide's axis stretched along itself, a named point's place for the coordinates) is
/// held to the array's size.
fn relative_errors(got: &[f64], want: &[f64], n: usize) -> Vec<f64> {
    let largest = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(largest > 0.0, "no parameter moves anything");
    (0..n)
        .map(|j| {
            let column = |v: &[f64]| v.iter().skip(j).step_by(n).copied().collect::<Vec<f64>>();
            let (g, w) = (column(got), column(want));
            let scale = w.iter().fold(1e-3 * largest, |m, x| m.max(x.abs()));
            g.iter().zip(&w).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / scale
        })
        .collect()
}

/// dq/dp alone on the structured path against today's sensitivities (`new`: the general
/// path, every derivative) of the same sweep; returns the worst relative error.
fn agree(label: &str, model: &Model, times: &[f64], params: &[Parameter], tol: f64) -> f64 {
    let request = SensitivityRequest { derivatives: 0, general: false };
    let structured = run(model, times, params, request);
    assert_eq!(structured.path, SensitivityPath::Structured, "{label}: {}", structured.path_reason);
    assert_eq!(structured.general_steps, 0, "{label}: no step is near singular");
    let general = run(model, times, params, SensitivityRequest::default());
    assert_eq!(general.path, SensitivityPath::General, "{label}");
    // the same configurations: a plan with dyads solves every derivative whatever is kept
    assert_eq!(structured.sweep.q, general.sweep.q, "{label}: the sweeps differ");
    let n = params.len();
    let mut worst = 0.0f64;
    for (what, got, want) in
        [("dq", &structured.dq, &general.dq), ("points", &structured.points, &general.points)]
    {
        if want.is_empty() {
            continue;
        }
        for (j, e) in relative_errors(got, want, n).into_iter().enumerate() {
            assert!(e <= tol, "{label}: d{what}/d{}: relative error {e:e}", params[j].name);
            worst = worst.max(e);
        }
    }
    worst
}

fn with_point(mut d: Description, body: &str, at: [f64; 2]) -> Description {
    d.points.push(PointDesc { name: "P".into(), body: body.into(), at });
    d
}

// Tolerance: both paths solve the same linear equations at the same q, the general one
// by a pivoted LU of the scaled Phi_q, the structured one by 2 x 2 Cramer's rule group by
// group, so they differ by round-off times the conditioning, which these sweeps keep
// moderate (no step within NEAR_SINGULAR: `general_steps` is 0). Measured: 9e-15 of each
// parameter's largest entry; 5e-13 for the columns that are round-off alone (1e-16 held
// to 1e-3 of the array's largest entry). A wrong term in any block is off by O(1).
const TOL: f64 = 1e-12;

#[test]
fn four_bar_every_engine_parameter_and_description_paths() {
    let model = Model::new(with_point(four_bar(&TEXTBOOK, 0.0, 5.0), "coupler", [0.2, 0.15])).unwrap();
    let times = turn(181);
    agree("four-bar", &model, &times, &Parameter::all(&model), TOL);
    let paths = [
        "joints.O2.at.0",
        "joints.A.at.1",
        "joints.B.at.0",
        "joints.B.at.1",
        "joints.O4.at.0",
        "drivers.crank_angle.law.value",
        "drivers.crank_angle.law.rate",
        "points.P.at.1",
    ];
    let params: Vec<Parameter> = paths.iter().map(|p| Parameter::resolve(&model, p).unwrap()).collect();
    agree("four-bar paths", &model, &times, &params, TOL);
}

#[test]
fn one_parameter_moving_numbers_of_several_groups() {
    // a direction across the crank's pin, the dyad's middle pin and the law: one seed per
    // group it moves, summed where two numbers of one group move
    let model = Model::new(four_bar(&TEXTBOOK, 0.3, 5.0)).unwrap();
    let all = Parameter::all(&model);
    let named = |n: &str| all.iter().find(|p| p.name == n).unwrap().seeds[0];
    let mixed = Parameter {
        name: "mixed".into(),
        seeds: vec![
            (named("constraints.O2.u_b.x").0, named("constraints.O2.u_b.x").1, 0.7),
            (named("constraints.B.u_a.y").0, named("constraints.B.u_a.y").1, -1.3),
            (named("constraints.crank_angle.law.rate").0, named("constraints.crank_angle.law.rate").1, 0.2),
            (named("constraints.B.u_b.x").0, named("constraints.B.u_b.x").1, 0.4),
            (named("constraints.O4.u_a.x").0, named("constraints.O4.u_a.x").1, 2.0),
        ],
        points: Vec::new(),
        dynamics: Vec::new(),
        nominal: 0.0,
    };
    let params = vec![all[0].clone(), mixed, all[5].clone()];
    agree("mixed parameter", &model, &turn(91), &params, TOL);
}

#[test]
fn slider_crank_and_inverted_sliders() {
    let model = Model::new(slider_crank(&SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 }, 0.0, 5.0)).unwrap();
    let times = turn(181);
    agree("slider-crank", &model, &times, &Parameter::all(&model), TOL);
    let params: Vec<Parameter> =
        ["joints.S.at.1", "joints.B.at.0"].iter().map(|p| Parameter::resolve(&model, p).unwrap()).collect();
    agree("slider-crank paths", &model, &times, &params, TOL);
    // a slider on the turning crank, pinned to a rod about the ground pivot G: the line
    // turns with the known body; the prismatic joint both ways round (the line in the
    // crank, and in the slider)
    let (th, g, rod): (f64, [f64; 2], f64) = (0.4, [0.3, 0.1], 0.25);
    let e = [th.cos(), th.sin()];
    let along = e[0] * g[0] + e[1] * g[1];
    let s = along + (rod * rod - (g[0] * e[1] - g[1] * e[0]).powi(2)).sqrt();
    let b = [s * e[0], s * e[1]];
    for (side_a, side_b) in [("crank", "slider"), ("slider", "crank")] {
        let desc = json!({
            "bodies": [
                {"name": "crank", "x": 0.0, "y": 0.0, "theta": th},
                {"name": "rod", "x": g[0], "y": g[1], "theta": 0.3},
                {"name": "slider", "x": b[0], "y": b[1], "theta": th + 0.2},
            ],
            "joints": [
                {"type": "revolute", "name": "O", "body_a": "ground", "body_b": "crank", "at": [0.0, 0.0]},
                {"type": "revolute", "name": "G", "body_a": "ground", "body_b": "rod", "at": g},
                {"type": "revolute", "name": "B", "body_a": "rod", "body_b": "slider", "at": b},
                {"type": "prismatic", "name": "slide", "body_a": side_a, "body_b": side_b, "at": b, "axis": e},
            ],
            "drivers": [{"type": "angle", "name": "input", "body": "crank",
                         "law": {"type": "linear", "value": th, "rate": 1.0}}],
            "points": [{"name": "P", "body": "slider", "at": [b[0] + 0.05, b[1]]}],
        });
        let model = from_json(&desc);
        let times: Vec<f64> = (0..61).map(|k| 0.4 * k as f64 / 60.0).collect();
        let label = format!("slider on the crank, line in {side_a}");
        agree(&label, &model, &times, &Parameter::all(&model), TOL);
        let off = from_json(&off_pins_json(desc.clone()));
        agree(&format!("{label}, frames off the pins"), &off, &times, &Parameter::all(&off), TOL);
        // (the slide's own place moves nothing: its line and its sliding point move together)
        let params: Vec<Parameter> = ["joints.B.at.0", "joints.G.at.1"]
            .iter()
            .map(|p| Parameter::resolve(&model, p).unwrap())
            .collect();
        agree(&format!("{label}, paths"), &model, &times, &params, TOL);
    }
}

#[test]
fn six_bars_five_bar_and_a_chain() {
    let times = turn(121);
    let stephenson = Model::new(six_bar_stephenson(0.0, 5.0)).unwrap();
    agree("Stephenson six-bar", &stephenson, &times, &Parameter::all(&stephenson), TOL);
    let params: Vec<Parameter> = ["joints.C.at.0", "joints.D.at.1", "joints.O6.at.0"]
        .iter()
        .map(|p| Parameter::resolve(&stephenson, p).unwrap())
        .collect();
    agree("Stephenson six-bar paths", &stephenson, &times, &params, TOL);
    let watt = example("six_bar_watt.toml");
    agree("Watt six-bar", &watt, &times, &Parameter::all(&watt), TOL);
    // both known sides of the dyad move (two cranks)
    let five = example("five_bar_two_inputs.toml");
    let five_times: Vec<f64> = (0..101).map(|k| k as f64 / 100.0).collect();
    agree("five-bar", &five, &five_times, &Parameter::all(&five), TOL);
    // relative-angle drivers: each loop's crank turned from the last loop's rocker
    let chain = Model::new(chain(&TEXTBOOK, 4, 0.0, 5.0, -0.8644, 0.5)).unwrap();
    agree("chain", &chain, &times, &Parameter::all(&chain), TOL);
    let params: Vec<Parameter> = ["drivers.tie3.law.value", "joints.B2.at.0", "joints.O4_4.at.1"]
        .iter()
        .map(|p| Parameter::resolve(&chain, p).unwrap())
        .collect();
    agree("chain paths", &chain, &times, &params, TOL);
}

#[test]
fn a_groups_known_side_numbered_between_its_two_bodies() {
    // each group reads its known sides' rows of dq/dp from around its own two bodies' rows:
    // the Stephenson six-bar's bodies reordered so that a dyad's known side (the coupler,
    // the crank) lies between the dyad's bodies, the first of them not the model's first
    let times = turn(61);
    for order in
        [["crank", "link5", "coupler", "rocker", "output"], ["rocker", "crank", "link5", "coupler", "output"]]
    {
        let mut desc = six_bar_stephenson(0.0, 5.0);
        desc.bodies.sort_by_key(|b| order.iter().position(|name| *name == b.name).unwrap());
        let model = Model::new(desc).unwrap();
        agree(&format!("Stephenson six-bar {order:?}"), &model, &times, &Parameter::all(&model), TOL);
    }
}

#[test]
fn a_tie_rod_as_the_dyads_second_link() {
    // a distance joint (a massless rod) from the crank to a rocker: a "one body" group
    let (a, b) = ([0.2 * 0.3f64.cos(), 0.2 * 0.3f64.sin()], [0.517365536421962, 0.1857115430397069]);
    let desc = json!({
        "bodies": [{"name": "crank", "x": 0.0, "y": 0.0, "theta": 0.3},
                   {"name": "rocker", "x": 0.35, "y": 0.0, "theta": 2.2}],
        "joints": [
            {"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [0.0, 0.0]},
            {"type": "revolute", "name": "O4", "body_a": "ground", "body_b": "rocker", "at": [0.35, 0.0]},
            {"type": "distance", "name": "AB", "body_a": "crank", "at_a": a, "body_b": "rocker", "at_b": b},
        ],
        "drivers": [{"type": "relative_angle", "name": "input", "body_a": "ground", "body_b": "crank",
                     "law": {"type": "linear", "value": 0.3, "rate": 5.0}}],
    });
    let model = from_json(&desc);
    let times = turn(121);
    agree("tie rod", &model, &times, &Parameter::all(&model), TOL);
    let params = vec![Parameter::resolve(&model, "joints.AB.at_a.0").unwrap()];
    agree("tie rod paths", &model, &times, &params, TOL);
    // the driver the other way round: theta_ground - theta_crank = f, the crank's angle -f
    let mut desc = desc;
    desc["drivers"][0] = json!({"type": "relative_angle", "name": "input", "body_a": "crank", "body_b": "ground",
                                "law": {"type": "linear", "value": -0.3, "rate": -5.0}});
    let model = from_json(&desc);
    agree("tie rod, driver reversed", &model, &times, &Parameter::all(&model), TOL);
}

#[test]
fn the_path_is_chosen_by_a_stated_rule() {
    let model = Model::new(four_bar(&TEXTBOOK, 0.0, 5.0)).unwrap();
    let params = Parameter::all(&model);
    let times = turn(5);
    let path = |model: &Model, derivatives: u8, general: bool| {
        let out = run(model, &times, &Parameter::all(model), SensitivityRequest { derivatives, general });
        (out.path, out.path_reason)
    };
    assert_eq!(path(&model, 0, false).0, SensitivityPath::Structured);
    for (derivatives, general, says) in [(1, false, "dqd/dp"), (2, false, "dqd/dp"), (0, true, "asked for")] {
        let (p, why) = path(&model, derivatives, general);
        assert_eq!(p, SensitivityPath::General, "derivatives {derivatives}, general {general}");
        assert!(why.contains(says), "{why}");
    }
    // the general solver has no plan
    let general = Model::with_options(
        four_bar(&TEXTBOOK, 0.0, 5.0),
        Options { solver: SolverKind::General, ..Options::default() },
    )
    .unwrap();
    let (p, why) = path(&general, 0, false);
    assert!(p == SensitivityPath::General && why.contains("no structured plan"), "{why}");
    // a group without structured sensitivities (the steering's rack is a substitution)
    let steering = example("steering.toml");
    let (p, why) = path(&steering, 0, false);
    assert!(p == SensitivityPath::General && why.contains("no structured sensitivities"), "{why}");
    // positions only on the general path: dq/dp as with every derivative
    let d0 = run(&model, &times, &params, SensitivityRequest { derivatives: 0, general: true });
    let d2 = run(&model, &times, &params, SensitivityRequest::default());
    assert_eq!(d0.dq, d2.dq, "the same solves for dq/dp");
    assert!(d0.dqd.is_empty() && d0.dqdd.is_empty() && d0.sweep.qd.is_empty());
}

#[test]
fn steps_next_to_a_singular_configuration_go_to_the_general_path() {
    // a parallelogram four-bar (ground = coupler 0.35, crank = rocker 0.2) through its
    // change point at crank angle pi, where the dyad lies stretched out: there the |sin|
    // at B is |theta - pi|; one step lands 2e-7 past it, below the sweep's NEAR_SINGULAR
    // (1e-6)
    let m = FourBar { r1: 0.35, r2: 0.20, r3: 0.35, r4: 0.20 };
    let (th0, delta) = (2.0, 2e-7);
    let model = Model::new(four_bar(&m, th0, 1.0)).unwrap();
    let h = (std::f64::consts::PI + delta - th0) / 20.0;
    let times: Vec<f64> = (0..31).map(|k| k as f64 * h).collect();
    let params = Parameter::all(&model);
    let request = SensitivityRequest { derivatives: 0, general: false };
    let structured = run(&model, &times, &params, request);
    let general = run(&model, &times, &params, SensitivityRequest::default());
    assert_eq!(structured.path, SensitivityPath::Structured);
    assert_eq!(structured.general_steps, 1, "the step at the change point only");
    assert_eq!(structured.sweep.q, general.sweep.q);
    // that step is the general path's own; the others agree to the conditioning of each
    let row = model.n_coords * params.len();
    let at = 20 * row..21 * row;
    assert_eq!(structured.dq[at.clone()], general.dq[at.clone()]);
    let (mut got, mut want) = (structured.dq.clone(), general.dq.clone());
    got.drain(at.clone());
    want.drain(at);
    let worst = relative_errors(&got, &want, params.len()).into_iter().fold(0.0f64, f64::max);
    assert!(worst <= TOL, "worst relative error {worst:e}");
}

#[test]
fn a_crank_on_a_moving_arm() {
    // an arm turned about the origin carries a crank at its tip, turned relative to the arm
    // (or absolutely); an RRR dyad closes the crank's tip to the ground pivot O4: the crank's
    // pin and, in the first case, its angle's base move with the arm
    let (tha, phi, arm, crank, coupler, rocker, o4) = (0.3f64, 0.5f64, 0.1, 0.08, 0.35, 0.3, [0.35, 0.0]);
    let p = [arm * tha.cos(), arm * tha.sin()];
    let q = [p[0] + crank * (tha + phi).cos(), p[1] + crank * (tha + phi).sin()];
    // B: circles (Q, coupler) and (O4, rocker), left of Q -> O4
    let (dx, dy) = (o4[0] - q[0], o4[1] - q[1]);
    let d = dx.hypot(dy);
    let along = (coupler * coupler - rocker * rocker + d * d) / (2.0 * d);
    let up = (coupler * coupler - along * along).sqrt();
    let b = [q[0] + (along * dx - up * dy) / d, q[1] + (along * dy + up * dx) / d];
    let angle = |from: [f64; 2], to: [f64; 2]| (to[1] - from[1]).atan2(to[0] - from[0]);
    let linear = |value: f64, rate: f64| json!({"type": "linear", "value": value, "rate": rate});
    for relative in [true, false] {
        let crank_driver = if relative {
            json!({"type": "relative_angle", "name": "turn", "body_a": "arm", "body_b": "crank", "law": linear(phi, 3.0)})
        } else {
            json!({"type": "angle", "name": "turn", "body": "crank", "law": linear(tha + phi, 4.0)})
        };
        let desc = json!({
            "bodies": [
                {"name": "arm", "x": 0.0, "y": 0.0, "theta": tha},
                // the crank's origin at its tip, away from its pin: its pin's arm turns too
                {"name": "crank", "x": q[0], "y": q[1], "theta": tha + phi},
                {"name": "coupler", "x": q[0], "y": q[1], "theta": angle(q, b)},
                {"name": "rocker", "x": o4[0], "y": o4[1], "theta": angle(o4, b)},
            ],
            "joints": [
                {"type": "revolute", "name": "O", "body_a": "ground", "body_b": "arm", "at": [0.0, 0.0]},
                {"type": "revolute", "name": "P", "body_a": "arm", "body_b": "crank", "at": p},
                {"type": "revolute", "name": "Q", "body_a": "crank", "body_b": "coupler", "at": q},
                {"type": "revolute", "name": "B", "body_a": "coupler", "body_b": "rocker", "at": b},
                {"type": "revolute", "name": "O4", "body_a": "rocker", "body_b": "ground", "at": o4},
            ],
            "drivers": [{"type": "angle", "name": "swing", "body": "arm", "law": linear(tha, 1.0)}, crank_driver],
        });
        let model = from_json(&desc);
        let times: Vec<f64> = (0..61).map(|k| 1.5 * k as f64 / 60.0).collect();
        let label = if relative { "crank turned relative to its arm" } else { "crank on an arm" };
        agree(label, &model, &times, &Parameter::all(&model), TOL);
    }
}

/// The description with every body's frame drawn away from its pins (shifted and turned):
/// the same mechanism, whose pins now have arms in their bodies.
fn off_pins(mut d: Description) -> Description {
    for (k, b) in d.bodies.iter_mut().enumerate() {
        let k = k as f64 + 1.0;
        (b.x, b.y, b.theta) = (b.x + 0.03 * k, b.y - 0.02 * k, b.theta + 0.4 * k);
    }
    d
}

fn off_pins_json(mut d: Value) -> Value {
    for (k, b) in d["bodies"].as_array_mut().unwrap().iter_mut().enumerate() {
        let k = k as f64 + 1.0;
        for (key, by) in [("x", 0.03 * k), ("y", -0.02 * k), ("theta", 0.4 * k)] {
            b[key] = json!(b[key].as_f64().unwrap() + by);
        }
    }
    d
}

#[test]
fn bodies_drawn_away_from_their_pins() {
    // every pin then has an arm in its body, which each block's derivative turns
    let times = turn(91);
    for (label, desc) in [
        ("four-bar", four_bar(&TEXTBOOK, 0.0, 5.0)),
        ("slider-crank", slider_crank(&SliderCrank { r2: 0.10, r3: 0.35, e: 0.02 }, 0.0, 5.0)),
        ("Stephenson six-bar", six_bar_stephenson(0.0, 5.0)),
        ("chain", chain(&TEXTBOOK, 3, 0.0, 5.0, -0.8644, 0.5)),
    ] {
        let model = Model::new(off_pins(desc)).unwrap();
        agree(&format!("{label}, frames off the pins"), &model, &times, &Parameter::all(&model), TOL);
    }
    let (a, b) = ([0.2 * 0.3f64.cos(), 0.2 * 0.3f64.sin()], [0.517365536421962, 0.1857115430397069]);
    let tie_rod = json!({
        "bodies": [{"name": "crank", "x": 0.0, "y": 0.0, "theta": 0.3},
                   {"name": "rocker", "x": 0.35, "y": 0.0, "theta": 2.2}],
        "joints": [
            {"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [0.0, 0.0]},
            {"type": "revolute", "name": "O4", "body_a": "ground", "body_b": "rocker", "at": [0.35, 0.0]},
            {"type": "distance", "name": "AB", "body_a": "crank", "at_a": a, "body_b": "rocker", "at_b": b},
        ],
        "drivers": [{"type": "angle", "name": "input", "body": "crank",
                     "law": {"type": "linear", "value": 0.3, "rate": 5.0}}],
    });
    let model = from_json(&off_pins_json(tie_rod));
    agree("tie rod, frames off the pins", &model, &times, &Parameter::all(&model), TOL);
}

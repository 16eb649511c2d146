//! Textbook mechanisms and their closed forms, shared by the integration tests.
#![allow(dead_code)]

use linkwork::{BodyDesc, Description, DriverDesc, JointDesc, MotionLaw};

pub fn body(name: &str, x: f64, y: f64, theta: f64) -> BodyDesc {
    BodyDesc { name: name.into(), x, y, theta, mass: 0.0, inertia: 0.0, com: None }
}

pub fn pin(name: &str, a: &str, b: &str, at: [f64; 2]) -> JointDesc {
    JointDesc::Revolute {
        name: name.into(),
        body_a: a.into(),
        body_b: b.into(),
        at: Some(at),
        pin_a: None,
        pin_b: None,
    }
}

pub fn crank_driver(theta0: f64, omega: f64) -> DriverDesc {
    DriverDesc::Angle {
        name: "crank_angle".into(),
        body: "crank".into(),
        law: MotionLaw::Linear { value: theta0, rate: omega },
    }
}

/// Four-bar: ground O2 = (0, 0), O4 = (r1, 0); crank O2-A (r2), coupler A-B (r3), rocker
/// O4-B (r4). Open branch: B to the left of the vector A -> O4.
pub struct FourBar {
    pub r1: f64,
    pub r2: f64,
    pub r3: f64,
    pub r4: f64,
}

/// (theta3, theta4), (omega3, omega4), (alpha3, alpha4) from the loop equations.
pub fn four_bar_closed(m: &FourBar, th2: f64, w2: f64, a2: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
    let a = [m.r2 * th2.cos(), m.r2 * th2.sin()];
    let e = [m.r1 - a[0], -a[1]];
    let s = e[0].hypot(e[1]);
    let beta = ((m.r3 * m.r3 + s * s - m.r4 * m.r4) / (2.0 * m.r3 * s)).acos();
    let th3 = e[1].atan2(e[0]) + beta;
    let b = [a[0] + m.r3 * th3.cos(), a[1] + m.r3 * th3.sin()];
    let th4 = b[1].atan2(b[0] - m.r1);
    // r2 w2 i e^{i th2} + r3 w3 i e^{i th3} = r4 w4 i e^{i th4}, by Cramer's rule
    let w3 = m.r2 * w2 * (th4 - th2).sin() / (m.r3 * (th3 - th4).sin());
    let w4 = m.r2 * w2 * (th2 - th3).sin() / (m.r4 * (th4 - th3).sin());
    // r3 a3 i e3 - r4 a4 i e4 = r2 w2^2 e2 - r2 a2 i e2 + r3 w3^2 e3 - r4 w4^2 e4 =: c
    let c = [
        m.r2 * w2 * w2 * th2.cos() + m.r2 * a2 * th2.sin() + m.r3 * w3 * w3 * th3.cos()
            - m.r4 * w4 * w4 * th4.cos(),
        m.r2 * w2 * w2 * th2.sin() - m.r2 * a2 * th2.cos() + m.r3 * w3 * w3 * th3.sin()
            - m.r4 * w4 * w4 * th4.sin(),
    ];
    // [-r3 s3, r4 s4; r3 c3, -r4 c4] [a3, a4] = c
    let (m11, m12, m21, m22) = (-m.r3 * th3.sin(), m.r4 * th4.sin(), m.r3 * th3.cos(), -m.r4 * th4.cos());
    let det = m11 * m22 - m12 * m21;
    let a3 = (c[0] * m22 - m12 * c[1]) / det;
    let a4 = (m11 * c[1] - m21 * c[0]) / det;
    ([th3, th4], [w3, w4], [a3, a4])
}

/// Drawn (exactly) at crank angle `th_drawn`; the driver starts at `th2`, so assembly
/// has to move the linkage to the driver's first value on the drawn branch.
pub fn four_bar_drawn(m: &FourBar, th_drawn: f64, th2: f64, omega: f64) -> Description {
    let mut d = four_bar(m, th_drawn, omega);
    d.drivers = vec![crank_driver(th2, omega)];
    d
}

pub fn four_bar(m: &FourBar, th2: f64, omega: f64) -> Description {
    let ([th3, th4], _, _) = four_bar_closed(m, th2, omega, 0.0);
    let a = [m.r2 * th2.cos(), m.r2 * th2.sin()];
    let b = [a[0] + m.r3 * th3.cos(), a[1] + m.r3 * th3.sin()];
    Description {
        name: "four-bar".into(),
        units: Default::default(),
        bodies: vec![
            body("crank", 0.0, 0.0, th2),
            body("coupler", a[0], a[1], th3),
            body("rocker", m.r1, 0.0, th4),
        ],
        joints: vec![
            pin("O2", "ground", "crank", [0.0, 0.0]),
            pin("A", "crank", "coupler", a),
            pin("B", "coupler", "rocker", b),
            pin("O4", "rocker", "ground", [m.r1, 0.0]),
        ],
        drivers: vec![crank_driver(th2, omega)],
        points: vec![],
        gravity: [0.0, 0.0],
        loads: vec![],
        outputs: Vec::new(),
        branch: None,
        close: None,
        free: false,
        initial_rates: Default::default(),
    }
}

/// Offset slider-crank: crank O2-A (r2), rod A-B (r3), slider pin B on y = e.
pub struct SliderCrank {
    pub r2: f64,
    pub r3: f64,
    pub e: f64,
}

/// (theta3, x), (omega3, v), (alpha3, a).
pub fn slider_crank_closed(m: &SliderCrank, th2: f64, w2: f64, a2: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
    let th3 = ((m.e - m.r2 * th2.sin()) / m.r3).asin();
    let x = m.r2 * th2.cos() + m.r3 * th3.cos();
    let w3 = -m.r2 * w2 * th2.cos() / (m.r3 * th3.cos());
    let v = -m.r2 * w2 * th2.sin() - m.r3 * w3 * th3.sin();
    let a3 = (m.r2 * w2 * w2 * th2.sin() - m.r2 * a2 * th2.cos() + m.r3 * w3 * w3 * th3.sin())
        / (m.r3 * th3.cos());
    let acc = -m.r2 * a2 * th2.sin()
        - m.r2 * w2 * w2 * th2.cos()
        - m.r3 * a3 * th3.sin()
        - m.r3 * w3 * w3 * th3.cos();
    ([th3, x], [w3, v], [a3, acc])
}

pub fn slider_crank(m: &SliderCrank, th2: f64, omega: f64) -> Description {
    let ([th3, x], _, _) = slider_crank_closed(m, th2, omega, 0.0);
    let a = [m.r2 * th2.cos(), m.r2 * th2.sin()];
    Description {
        name: "slider-crank".into(),
        units: Default::default(),
        bodies: vec![body("crank", 0.0, 0.0, th2), body("rod", a[0], a[1], th3), body("slider", x, m.e, 0.0)],
        joints: vec![
            pin("O2", "ground", "crank", [0.0, 0.0]),
            pin("A", "crank", "rod", a),
            pin("B", "rod", "slider", [x, m.e]),
            JointDesc::Prismatic {
                name: "S".into(),
                body_a: "ground".into(),
                body_b: "slider".into(),
                at: Some([x, m.e]),
                axis: Some([1.0, 0.0]),
                pin_a: None,
                pin_b: None,
                axis_a: None,
                angle: None,
                travel: None,
            },
        ],
        drivers: vec![crank_driver(th2, omega)],
        points: vec![],
        gravity: [0.0, 0.0],
        loads: vec![],
        outputs: Vec::new(),
        branch: None,
        close: None,
        free: false,
        initial_rates: Default::default(),
    }
}

/// Largest |a - b| over the largest |b|: the error relative to the quantity's scale.
pub fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

/// Stephenson III six-bar, the same as Python's `examples.six_bar("stephenson")`: the
/// crank-rocker O2-A-B-O4 (crank 0.10, coupler 0.35, rocker 0.30, ground 0.35) whose
/// coupler is the ternary link A-B-C (|AC| = 0.25, 0.3 rad clockwise of A->B), and the
/// dyad C-D (link5, 0.25) and O6-D (output, 0.15), O6 = (0.20, -0.15), D on the right of
/// the directed line C -> O6. Bodies crank, coupler, rocker, link5, output; revolutes
/// O2, A, B, O4, C, D, O6; the crank driven at theta2 + omega t.
pub fn six_bar_stephenson(th2: f64, omega: f64) -> Description {
    let fb = FourBar { r1: 0.35, r2: 0.10, r3: 0.35, r4: 0.30 };
    let ([th3, th4], _, _) = four_bar_closed(&fb, th2, omega, 0.0);
    let polar = |p: [f64; 2], r: f64, a: f64| [p[0] + r * a.cos(), p[1] + r * a.sin()];
    let (o6, link5, output) = ([0.20, -0.15], 0.25, 0.15);
    let a = polar([0.0, 0.0], fb.r2, th2);
    let b = polar(a, fb.r3, th3);
    let c = polar(a, 0.25, th3 - 0.3);
    // D: circles (C, link5) and (O6, output), the intersection right of C -> O6
    let (dx, dy) = (o6[0] - c[0], o6[1] - c[1]);
    let dist = dx.hypot(dy);
    let along = (link5 * link5 - output * output + dist * dist) / (2.0 * dist);
    let across = -(link5 * link5 - along * along).sqrt();
    let (ex, ey) = (dx / dist, dy / dist);
    let d = [c[0] + along * ex - across * ey, c[1] + along * ey + across * ex];
    let angle = |p: [f64; 2], q: [f64; 2]| (q[1] - p[1]).atan2(q[0] - p[0]);
    Description {
        name: "six-bar (Stephenson III)".into(),
        units: Default::default(),
        bodies: vec![
            body("crank", 0.0, 0.0, th2),
            body("coupler", a[0], a[1], th3),
            body("rocker", fb.r1, 0.0, th4),
            body("link5", c[0], c[1], angle(c, d)),
            body("output", o6[0], o6[1], angle(o6, d)),
        ],
        joints: vec![
            pin("O2", "ground", "crank", [0.0, 0.0]),
            pin("A", "crank", "coupler", a),
            pin("B", "coupler", "rocker", b),
            pin("O4", "rocker", "ground", [fb.r1, 0.0]),
            pin("C", "coupler", "link5", c),
            pin("D", "link5", "output", d),
            pin("O6", "output", "ground", o6),
        ],
        drivers: vec![crank_driver(th2, omega)],
        points: vec![],
        gravity: [0.0, 0.0],
        loads: vec![],
        outputs: Vec::new(),
        branch: None,
        close: None,
        free: false,
        initial_rates: Default::default(),
    }
}

/// A closed chain of `loops` four-bar loops in series, the same as Python's
/// `examples.chain(loops, offset=offset, spacing=spacing)`: loop k (1-based) is the
/// four-bar `m` with its ground pivots at ((k - 1) spacing, 0) and ((k - 1) spacing + r1,
/// 0), bodies crank{k}, coupler{k}, rocker{k}, revolutes O2_{k}, A{k}, B{k}, O4_{k}; loop
/// 1's crank is driven at th2 + omega t, loop k+1's crank tied to loop k's rocker by a
/// relative-angle driver tie{k+1}: theta_crank{k+1} - theta_rocker{k} = offset (a
/// constant law). `m` must be a Grashof crank-rocker (it then assembles at every input
/// angle).
pub fn chain(m: &FourBar, loops: usize, th2: f64, omega: f64, offset: f64, spacing: f64) -> Description {
    let mut d = Description {
        name: format!("chain of {loops} four-bar loops"),
        units: Default::default(),
        bodies: vec![],
        joints: vec![],
        drivers: vec![],
        points: vec![],
        gravity: [0.0, 0.0],
        loads: vec![],
        outputs: Vec::new(),
        branch: None,
        close: None,
        free: false,
        initial_rates: Default::default(),
    };
    let mut input = th2;
    for k in 1..=loops {
        let ([th3, th4], _, _) = four_bar_closed(m, input, omega, 0.0);
        let x0 = (k - 1) as f64 * spacing;
        let a = [x0 + m.r2 * input.cos(), m.r2 * input.sin()];
        let b = [a[0] + m.r3 * th3.cos(), a[1] + m.r3 * th3.sin()];
        let (crank, coupler, rocker) = (format!("crank{k}"), format!("coupler{k}"), format!("rocker{k}"));
        d.bodies.push(body(&crank, x0, 0.0, input));
        d.bodies.push(body(&coupler, a[0], a[1], th3));
        d.bodies.push(body(&rocker, x0 + m.r1, 0.0, th4));
        d.joints.push(pin(&format!("O2_{k}"), "ground", &crank, [x0, 0.0]));
        d.joints.push(pin(&format!("A{k}"), &crank, &coupler, a));
        d.joints.push(pin(&format!("B{k}"), &coupler, &rocker, b));
        d.joints.push(pin(&format!("O4_{k}"), &rocker, "ground", [x0 + m.r1, 0.0]));
        d.drivers.push(if k == 1 {
            DriverDesc::Angle {
                name: "crank_angle".into(),
                body: crank,
                law: MotionLaw::Linear { value: th2, rate: omega },
            }
        } else {
            DriverDesc::RelativeAngle {
                name: format!("tie{k}"),
                body_a: format!("rocker{}", k - 1),
                body_b: crank,
                law: MotionLaw::Constant { value: offset },
            }
        });
        input = th4 + offset;
    }
    d
}

/// Deterministic pseudo-random numbers (xorshift), so failures reproduce.
pub struct Rng(pub u64);

impl Rng {
    /// uniform in [-1, 1)
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    /// uniform in 0 .. n
    pub fn below(&mut self, n: usize) -> usize {
        (((self.next() + 1.0) * 0.5 * n as f64) as usize).min(n - 1)
    }
}

/// A model compiled from `desc` and swept over `times` (every step must succeed).
pub fn sweep_all(desc: Description, times: &[f64]) -> (linkwork::Model, linkwork::SweepOutput) {
    let model = linkwork::Model::new(desc).unwrap();
    let mut data = linkwork::Data::new(&model);
    let mut out = linkwork::SweepOutput::new(&model, times);
    linkwork::sweep(&model, &mut data, times, &mut out, 0, &mut |_| true).unwrap();
    assert_eq!(out.n_done, times.len());
    (model, out)
}

/// The column `name` of a sweep's rows `v` (q, qd or qdd).
pub fn column_named(model: &linkwork::Model, v: &[f64], name: &str) -> Vec<f64> {
    let j = model.columns.iter().position(|c| c == name).unwrap_or_else(|| panic!("no column {name}"));
    v.chunks(model.n_coords).map(|row| row[j]).collect()
}

/// A cam pinned at the origin, turned by theta = the polynomial `coefficients` in t, under
/// a follower ("knife", "roller" of `roller_radius`, or "flat" facing along x) that
/// translates along the y axis, drawn at height `y_drawn`; the joint is named "F", the
/// curve parameter column "F.s".
pub fn translating_cam(
    kind: &str,
    curve: linkwork::curves::CurveDesc,
    y_drawn: f64,
    roller_radius: f64,
    coefficients: Vec<f64>,
) -> Description {
    let (radius, face) = match kind {
        "roller" => (Some(roller_radius), None),
        "flat" => (None, Some([1.0, 0.0])),
        _ => (None, None),
    };
    Description {
        units: Default::default(),
        name: "eccentric cam".into(),
        bodies: vec![body("cam", 0.0, 0.0, 0.0), body("follower", 0.0, y_drawn, 0.0)],
        joints: vec![
            pin("O", "ground", "cam", [0.0, 0.0]),
            JointDesc::Prismatic {
                name: "slide".into(),
                body_a: "ground".into(),
                body_b: "follower".into(),
                at: Some([0.0, y_drawn]),
                axis: Some([0.0, 1.0]),
                pin_a: None,
                pin_b: None,
                axis_a: None,
                angle: None,
                travel: None,
            },
            JointDesc::CamFollower {
                name: "F".into(),
                body_a: "cam".into(),
                body_b: "follower".into(),
                follower: kind.into(),
                at: [0.0, y_drawn],
                curve,
                radius,
                face,
            },
        ],
        drivers: vec![DriverDesc::Angle {
            name: "turn".into(),
            body: "cam".into(),
            law: MotionLaw::Polynomial { coefficients },
        }],
        points: vec![],
        gravity: [0.0, 0.0],
        loads: vec![],
        outputs: Vec::new(),
        branch: None,
        close: None,
        free: false,
        initial_rates: Default::default(),
    }
}

/// The description (as JSON) with the number at `path` (keys and list indices; items of
/// `bodies`, `joints`, ... by name; `gravity.1`) replaced by `f` of it.
pub fn with_number(desc: &serde_json::Value, path: &str, f: impl FnOnce(f64) -> f64) -> serde_json::Value {
    let mut out = desc.clone();
    let keys: Vec<&str> = path.split('.').collect();
    let mut node = &mut out;
    for (k, key) in keys.iter().enumerate() {
        node = if k == 1 && keys[0] != "gravity" {
            node.as_array_mut().unwrap().iter_mut().find(|i| i["name"] == *key).unwrap()
        } else if let Ok(i) = key.parse::<usize>() {
            &mut node[i]
        } else {
            &mut node[*key]
        };
    }
    *node = serde_json::json!(f(node.as_f64().unwrap()));
    out
}

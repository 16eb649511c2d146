//! Textbook mechanisms and their closed forms, shared by the integration tests.
#![allow(dead_code)]

use linkwork::{BodyDesc, Description, DriverDesc, JointDesc, MotionLaw};

pub fn body(name: &str, x: f64, y: f64, theta: f64) -> BodyDesc {
    BodyDesc { name: name.into(), x, y, theta, mass: 0.0, inertia: 0.0, com: None }
}

pub fn pin(name: &str, a: &str, b: &str, at: [f64; 2]) -> JointDesc {
    JointDesc::Revolute { name: name.into(), body_a: a.into(), body_b: b.into(), at }
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
        bodies: vec![body("crank", 0.0, 0.0, th2), body("rod", a[0], a[1], th3), body("slider", x, m.e, 0.0)],
        joints: vec![
            pin("O2", "ground", "crank", [0.0, 0.0]),
            pin("A", "crank", "rod", a),
            pin("B", "rod", "slider", [x, m.e]),
            JointDesc::Prismatic {
                name: "S".into(),
                body_a: "ground".into(),
                body_b: "slider".into(),
                at: [x, m.e],
                axis: [1.0, 0.0],
            },
        ],
        drivers: vec![crank_driver(th2, omega)],
        points: vec![],
        gravity: [0.0, 0.0],
        loads: vec![],
    }
}

/// Largest |a - b| over the largest |b|: the error relative to the quantity's scale.
pub fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

//! Curves fixed in a body, followed by the joints that own a coordinate: a pin in a
//! curved slot, a cam profile under its follower. Every curve is closed, parameterised
//! by an angle-like s of period 2 pi (so the joint's coordinate "<joint>.s" needs no
//! length scale), and gives c(s) and its first three derivatives exactly, in the body's
//! frame. The third derivative is needed by the followers whose rows hold the tangent
//! c'(s) (roller, flat face): their gamma has a term c''' sd^2.
//!
//! A curve is described (`CurveDesc`) in world coordinates at the start, like every other
//! point of a model; `CurveDesc::to_body` expresses it in a body's frame (`Curve`).
//!
//! Parameterisations (s in rad):
//! - circle: s is the polar angle about the centre, from the world x axis at the start;
//! - polar profile r(phi) (a periodic cubic spline through a table of (phi, r)): s = phi,
//!   the polar angle about the centre, from the world x axis at the start;
//! - polar expression r(phi) (a formula of phi in rad, exact to c''' through third-order
//!   jets, read on [0, 2 pi) and repeated): s = phi, as for the polar profile;
//! - closed spline through points: s = 2 pi times the fraction of the closed polygon's
//!   length (chordal knots), so |c'(s)| stays near perimeter / 2 pi.

use std::f64::consts::TAU;

use serde::{Deserialize, Serialize};

use crate::input::expr::Expression;
use crate::math::jet::{Jet, Vec2};

/// A curve as a model description gives it: world points at the start.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum CurveDesc {
    /// A circle: s is the polar angle about `centre`.
    Circle { centre: [f64; 2], radius: f64 },
    /// A closed (periodic) cubic spline through `points` (at least 3, the first not
    /// repeated at the end): s = 2 pi times the fraction of the polygon's length.
    Spline { points: Vec<[f64; 2]> },
    /// A polar profile r(phi) about `centre`: a periodic cubic spline through the table
    /// (`angles`, `radii`), angles in rad increasing over exactly one turn, the last row
    /// closing the table (angles[n] = angles[0] + 2 pi, radii[n] = radii[0]); s = phi.
    Polar { centre: [f64; 2], angles: Vec<f64>, radii: Vec<f64> },
    /// A polar profile about `centre` written as an expression `r` of `phi` (rad, from the
    /// world x axis at the start, whatever the model's angle unit), e.g.
    /// "0.05 + 0.01*(1 - cos(phi))": read on one turn, phi in [0, 2 pi), and repeated, so
    /// r must join itself at 2 pi to its second derivative; s = phi.
    PolarExpression { centre: [f64; 2], r: String },
}

/// c(s) and its derivatives d^k c / ds^k, k = 1, 2, 3 (body frame).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CurvePoint {
    pub c: [f64; 2],
    pub d1: [f64; 2],
    pub d2: [f64; 2],
    pub d3: [f64; 2],
}

/// A closed curve in a body's frame, period 2 pi in s.
#[derive(Debug, Clone, PartialEq)]
pub enum Curve {
    Circle(Circle),
    Spline(ClosedSpline),
    Polar(PolarProfile),
    PolarExpression(ExpressionProfile),
}

/// c(s) = centre + radius e(s + angle), e(phi) = (cos phi, sin phi).
#[derive(Debug, Clone, PartialEq)]
pub struct Circle {
    pub centre: [f64; 2],
    pub radius: f64,
    /// the body-frame direction of s = 0 (minus the body's starting angle)
    pub angle: f64,
}

/// c(s) = (x(s), y(s)), two periodic cubic splines on the same knots.
#[derive(Debug, Clone, PartialEq)]
pub struct ClosedSpline {
    x: PeriodicSpline,
    y: PeriodicSpline,
    /// +1 if the points run counter-clockwise, -1 if clockwise
    orientation: f64,
}

/// c(s) = centre + r(s) e(s + angle), r a periodic cubic spline.
#[derive(Debug, Clone, PartialEq)]
pub struct PolarProfile {
    pub centre: [f64; 2],
    pub angle: f64,
    r: PeriodicSpline,
}

/// c(s) = centre + r(phi) e(s + angle) with phi = s mod 2 pi, r an expression of phi.
#[derive(Debug, Clone, PartialEq)]
pub struct ExpressionProfile {
    pub centre: [f64; 2],
    pub angle: f64,
    r: Expression,
}

/// Parameters at which a polar expression is checked when a model compiles (r finite and
/// > 0 with finite derivatives): 4096 steps of a turn, every 0.088 degrees.
pub const EXPRESSION_CHECKS: usize = 4096;
/// Parameters over a turn at which a polar expression is searched for a starting contact
/// and its curvature checked against the followers (every half degree): an expression
/// has no knots to say where its features are.
const EXPRESSION_SAMPLES: usize = 720;
/// How closely r, r' and r'' of a polar expression must meet at phi = 0 and 2 pi,
/// relative to the profile's size (max |r| over the turn, or max |r^(k)| if larger). A
/// periodic formula meets to rounding (2 pi is 2.4e-16 off in floating point, and the
/// terms round at 1e-16 relative: about 1e-15 in all), a formula that is not periodic
/// misses by its own scale; 1e-9 lies between, and it is what the polar table's closing
/// row is held to.
pub const EXPRESSION_SEAM_TOL: f64 = 1e-9;

/// A periodic cubic spline (C2) of period 2 pi.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicSpline {
    /// n + 1 knots, knots[n] = knots[0] + 2 pi
    knots: Vec<f64>,
    /// n + 1 values, values[n] = values[0]
    values: Vec<f64>,
    /// n + 1 second derivatives at the knots, second[n] = second[0]
    second: Vec<f64>,
}

impl CurveDesc {
    /// The curve in the frame of a body whose starting pose is `pose` (None: the ground).
    /// The error says which field is wrong.
    pub fn to_body(&self, pose: Option<[f64; 3]>) -> Result<Curve, String> {
        let [x0, y0, th0] = pose.unwrap_or([0.0; 3]);
        let (s, c) = th0.sin_cos();
        let local = |p: [f64; 2]| {
            let d = [p[0] - x0, p[1] - y0];
            [c * d[0] + s * d[1], -s * d[0] + c * d[1]]
        };
        match self {
            CurveDesc::Circle { centre, radius } => {
                finite("centre", centre)?;
                Curve::circle(local(*centre), *radius, -th0)
            }
            CurveDesc::Spline { points } => {
                points.iter().try_for_each(|p| finite("points", p))?;
                Curve::spline(points.iter().map(|p| local(*p)).collect())
            }
            CurveDesc::Polar { centre, angles, radii } => {
                finite("centre", centre)?;
                Curve::polar(local(*centre), -th0, angles.clone(), radii.clone())
            }
            CurveDesc::PolarExpression { centre, r } => {
                finite("centre", centre)?;
                Curve::polar_expression(local(*centre), -th0, r)
            }
        }
    }

    /// World points that show the curve's extent at the start (for the model's length
    /// scale): the circle's bounding box corners, the spline's points, the polar table's
    /// points, a polar expression at 64 equal steps of phi (its centre alone if it does
    /// not parse: compiling refuses it later, naming the joint).
    pub fn world_points(&self) -> Vec<[f64; 2]> {
        match self {
            CurveDesc::Circle { centre, radius } => {
                let r = radius.abs();
                vec![[centre[0] - r, centre[1] - r], [centre[0] + r, centre[1] + r]]
            }
            CurveDesc::Spline { points } => points.clone(),
            CurveDesc::Polar { centre, angles, radii } => angles
                .iter()
                .zip(radii)
                .map(|(phi, r)| [centre[0] + r * phi.cos(), centre[1] + r * phi.sin()])
                .collect(),
            CurveDesc::PolarExpression { centre, r } => match Expression::parse(r, "phi") {
                Ok(r) => (0..64)
                    .map(|k| TAU * k as f64 / 64.0)
                    .map(|phi| (phi, r.eval(phi)[0]))
                    .filter(|(_, r)| r.is_finite())
                    .map(|(phi, r)| [centre[0] + r * phi.cos(), centre[1] + r * phi.sin()])
                    .collect(),
                Err(_) => vec![*centre],
            },
        }
    }
}

fn finite(field: &str, p: &[f64; 2]) -> Result<(), String> {
    if p[0].is_finite() && p[1].is_finite() {
        Ok(())
    } else {
        Err(format!("curve {field} {p:?} is not finite"))
    }
}

impl Curve {
    /// A circle in the body frame; s = 0 points along `angle`.
    pub fn circle(centre: [f64; 2], radius: f64, angle: f64) -> Result<Curve, String> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(format!("curve radius {radius} must be finite and > 0"));
        }
        if !angle.is_finite() {
            return Err(format!("curve angle {angle} is not finite"));
        }
        Ok(Curve::Circle(Circle { centre, radius, angle }))
    }

    /// A closed spline through body-frame points (at least 3; consecutive points
    /// distinct, the first not repeated at the end).
    pub fn spline(points: Vec<[f64; 2]>) -> Result<Curve, String> {
        let n = points.len();
        if n < 3 {
            return Err(format!("a closed spline needs at least 3 points, got {n}"));
        }
        let chord = |k: usize| {
            let (p, q) = (points[k], points[(k + 1) % n]);
            (q[0] - p[0]).hypot(q[1] - p[1])
        };
        let perimeter: f64 = (0..n).map(chord).sum();
        if !(perimeter.is_finite() && perimeter > 0.0) {
            return Err(format!("the spline's points {points:?} do not span a curve"));
        }
        if let Some(k) = (0..n).find(|&k| chord(k) <= 1e-12 * perimeter) {
            return Err(if k == n - 1 {
                "the spline's last point repeats its first: a closed spline closes by itself, \
                 leave the repeat out"
                    .to_string()
            } else {
                format!("spline points {k} and {} coincide", k + 1)
            });
        }
        // chordal knots scaled to one turn
        let mut knots = Vec::with_capacity(n + 1);
        let mut run = 0.0;
        for k in 0..n {
            knots.push(TAU * run / perimeter);
            run += chord(k);
        }
        knots.push(TAU);
        let coord = |i: usize| points.iter().chain([&points[0]]).map(|p| p[i]).collect::<Vec<f64>>();
        let x = PeriodicSpline::new(knots.clone(), coord(0))?;
        let y = PeriodicSpline::new(knots, coord(1))?;
        // shoelace: the sign of the polygon's area is the curve's sense
        let area2: f64 = (0..n)
            .map(|k| {
                let (p, q) = (points[k], points[(k + 1) % n]);
                p[0] * q[1] - q[0] * p[1]
            })
            .sum();
        Ok(Curve::Spline(ClosedSpline { x, y, orientation: if area2 < 0.0 { -1.0 } else { 1.0 } }))
    }

    /// A polar profile about the body-frame `centre`, phi measured from `angle`: the
    /// table (angles, radii) closes one turn (angles[n] = angles[0] + 2 pi, radii[n] =
    /// radii[0]) with at least 3 distinct rows; radii > 0.
    pub fn polar(centre: [f64; 2], angle: f64, angles: Vec<f64>, radii: Vec<f64>) -> Result<Curve, String> {
        let n = angles.len();
        if radii.len() != n {
            return Err(format!("polar table has {n} angles but {} radii", radii.len()));
        }
        if n < 4 {
            return Err(format!(
                "polar table needs at least 4 rows (3 distinct angles and the closing row), got {n}"
            ));
        }
        if let Some(v) = angles.iter().chain(&radii).find(|v| !v.is_finite()) {
            return Err(format!("polar table holds {v}, not a finite number"));
        }
        if let Some(k) = (0..n).find(|&k| radii[k] <= 0.0) {
            return Err(format!("polar table radius {} (row {k}) must be > 0", radii[k]));
        }
        if let Some(k) = (1..n).find(|&k| angles[k] <= angles[k - 1]) {
            return Err(format!(
                "polar table angles must increase strictly (row {k}: {} follows {})",
                angles[k],
                angles[k - 1]
            ));
        }
        let span = angles[n - 1] - angles[0];
        if (span - TAU).abs() > 1e-9 * TAU || (radii[n - 1] - radii[0]).abs() > 1e-9 * radii[0] {
            return Err(format!(
                "polar table is not periodic: its last row ({}, {}) must close the turn, at angle \
                 {} + 2 pi with the first radius {} (angles are in rad)",
                angles[n - 1],
                radii[n - 1],
                angles[0],
                radii[0]
            ));
        }
        if !angle.is_finite() {
            return Err(format!("curve angle {angle} is not finite"));
        }
        let r = PeriodicSpline::new(angles, radii)?;
        Ok(Curve::Polar(PolarProfile { centre, angle, r }))
    }

    /// A polar profile about the body-frame `centre`, phi measured from `angle`, its
    /// radius the expression `text` of phi (rad). Checked on `EXPRESSION_CHECKS` equal
    /// steps of [0, 2 pi]: r finite and > 0 with finite derivatives (to the third), and
    /// r, r', r'' the same at 0 and 2 pi (to `EXPRESSION_SEAM_TOL`).
    pub fn polar_expression(centre: [f64; 2], angle: f64, text: &str) -> Result<Curve, String> {
        let r = Expression::parse(text, "phi").map_err(|e| format!("curve r '{text}': {e}"))?;
        if !angle.is_finite() {
            return Err(format!("curve angle {angle} is not finite"));
        }
        // the size of r and of each derivative over the turn (for the seam's tolerance), and
        // where r is least
        let (mut most, mut least) = ([0.0f64; 3], (f64::INFINITY, 0.0));
        for k in 0..=EXPRESSION_CHECKS {
            let phi = TAU * k as f64 / EXPRESSION_CHECKS as f64;
            let v = r.eval3(phi);
            if !v.iter().all(|x| x.is_finite()) {
                let why = r.diagnose3(phi).unwrap_or_else(|| format!("(r, r', r'', r''') = {v:?}"));
                return Err(format!("curve r is not finite at phi = {phi}: {why}"));
            }
            if v[0] < least.0 {
                least = (v[0], phi);
            }
            for j in 0..3 {
                most[j] = most[j].max(v[j].abs());
            }
        }
        if least.0 <= 0.0 {
            return Err(format!(
                "curve r '{text}' is {} at phi = {} (its least value): a polar profile's radius must be \
                 > 0 all round (phi in rad)",
                least.0, least.1
            ));
        }
        let (start, end) = (r.eval3(0.0), r.eval3(TAU));
        let names = ["r", "r'", "r''"];
        for j in 0..3 {
            let tol = EXPRESSION_SEAM_TOL * most[0].max(most[j]);
            if (end[j] - start[j]).abs() > tol {
                return Err(format!(
                    "curve r '{text}' is not periodic: {n}(0) = {} but {n}(2 pi) = {} (r, r' and r'' must \
                     meet at phi = 0 and 2 pi, phi in rad)",
                    start[j],
                    end[j],
                    n = names[j]
                ));
            }
        }
        Ok(Curve::PolarExpression(ExpressionProfile { centre, angle, r }))
    }

    /// c(s), c'(s), c''(s), c'''(s).
    #[inline]
    pub fn eval(&self, s: f64) -> CurvePoint {
        match self {
            Curve::Circle(k) => polar_point(k.centre, k.angle, s, [k.radius, 0.0, 0.0, 0.0]),
            Curve::Spline(k) => {
                let (x, y) = (k.x.eval(s), k.y.eval(s));
                CurvePoint { c: [x[0], y[0]], d1: [x[1], y[1]], d2: [x[2], y[2]], d3: [x[3], y[3]] }
            }
            Curve::Polar(k) => polar_point(k.centre, k.angle, s, k.r.eval(s)),
            // r is read on one turn: dr/ds = dr/dphi, since phi = s - 2 pi n
            Curve::PolarExpression(k) => polar_point(k.centre, k.angle, s, k.r.eval3(s.rem_euclid(TAU))),
        }
    }

    /// c''''(s), for the exact sensitivities of the followers whose rows hold the tangent
    /// (`sensitivity::jet::curve`): 0 on a spline curve (cubic pieces), from r and its
    /// derivatives on a circle and a polar profile (r'''' = 0 on the cubic pieces); NaN on a
    /// polar expression, whose fourth derivative is not computed.
    pub fn fourth(&self, s: f64) -> [f64; 2] {
        let polar = |angle: f64, rj: [f64; 4]| {
            let (sin, cos) = (s + angle).sin_cos();
            let [r, r1, r2, r3] = rj;
            // c'''' = (r'''' - 6 r'' + r) e + (4 r''' - 4 r') e', with r'''' = 0
            let (a, b) = (r - 6.0 * r2, 4.0 * (r3 - r1));
            [a * cos - b * sin, a * sin + b * cos]
        };
        match self {
            Curve::Circle(k) => polar(k.angle, [k.radius, 0.0, 0.0, 0.0]),
            Curve::Spline(_) => [0.0, 0.0],
            Curve::Polar(k) => polar(k.angle, k.r.eval(s)),
            Curve::PolarExpression(_) => [f64::NAN, f64::NAN],
        }
    }

    /// +1 if s runs counter-clockwise round the curve, -1 if clockwise.
    pub fn orientation(&self) -> f64 {
        match self {
            Curve::Circle(_) | Curve::Polar(_) | Curve::PolarExpression(_) => 1.0,
            Curve::Spline(k) => k.orientation,
        }
    }

    /// Parameters that sample the curve densely enough to bracket its features: at least
    /// 64 over the turn, 8 per spline interval, 720 for an expression; in [0, 2 pi).
    pub fn samples(&self) -> impl Iterator<Item = f64> {
        let n = match self {
            Curve::Circle(_) => 64,
            Curve::Spline(k) => (8 * k.x.n_intervals()).max(64),
            Curve::Polar(k) => (8 * k.r.n_intervals()).max(64),
            Curve::PolarExpression(_) => EXPRESSION_SAMPLES,
        };
        (0..n).map(move |k| TAU * k as f64 / n as f64)
    }

    /// Signed curvature (c' x c'') / |c'|^3: > 0 where the curve turns left along s.
    pub fn curvature(&self, s: f64) -> f64 {
        let p = self.eval(s);
        let speed = p.d1[0].hypot(p.d1[1]);
        (p.d1[0] * p.d2[1] - p.d1[1] * p.d2[0]) / (speed * speed * speed)
    }

    /// The parameter of the curve point nearest `p` (body frame): the best of a dense
    /// sampling, refined by Newton on (c - p) . c' = 0 within one sample spacing.
    pub fn nearest(&self, p: [f64; 2]) -> f64 {
        let dist2 = |s: f64| {
            let c = self.eval(s).c;
            (c[0] - p[0]).powi(2) + (c[1] - p[1]).powi(2)
        };
        let slope = |s: f64| {
            let k = self.eval(s);
            let d = [k.c[0] - p[0], k.c[1] - p[1]];
            (
                d[0] * k.d1[0] + d[1] * k.d1[1],
                k.d1[0].powi(2) + k.d1[1].powi(2) + d[0] * k.d2[0] + d[1] * k.d2[1],
            )
        };
        let (best, spacing) = self.best_sample(|s| -dist2(s));
        root_near(slope, best, spacing)
    }

    /// The parameter where the tangent is perpendicular to `n` (body frame) and the curve
    /// touches the line n . (x - p) = 0 most nearly: of the two extremes of n . c(s)
    /// (the curve's support points across n), the one nearer the line.
    pub fn tangent_to_line(&self, n: [f64; 2], p: [f64; 2]) -> f64 {
        let height = |s: f64| {
            let c = self.eval(s).c;
            n[0] * c[0] + n[1] * c[1]
        };
        let slope = |s: f64| {
            let k = self.eval(s);
            (n[0] * k.d1[0] + n[1] * k.d1[1], n[0] * k.d2[0] + n[1] * k.d2[1])
        };
        let (top, spacing) = self.best_sample(height);
        let (bottom, _) = self.best_sample(|s| -height(s));
        let (top, bottom) = (root_near(slope, top, spacing), root_near(slope, bottom, spacing));
        let line = n[0] * p[0] + n[1] * p[1];
        if (height(top) - line).abs() <= (height(bottom) - line).abs() {
            top
        } else {
            bottom
        }
    }

    /// The sample maximising `score`, and the sample spacing.
    fn best_sample(&self, score: impl Fn(f64) -> f64) -> (f64, f64) {
        let (mut best, mut best_score, mut n) = (0.0, f64::NEG_INFINITY, 0usize);
        for s in self.samples() {
            let v = score(s);
            if v > best_score {
                (best, best_score) = (s, v);
            }
            n += 1;
        }
        (best, TAU / n as f64)
    }
}

/// A root of f (given with its derivative, `f_and_df(s) = (f, f')`) near `s0`: safeguarded
/// Newton in [s0 - h, s0 + h] when f changes sign there, else s0 itself.
fn root_near(f_and_df: impl Fn(f64) -> (f64, f64), s0: f64, h: f64) -> f64 {
    let (mut lo, mut hi) = (s0 - h, s0 + h);
    let (f_lo, f_hi) = (f_and_df(lo).0, f_and_df(hi).0);
    if f_lo == 0.0 {
        return lo;
    }
    if f_hi == 0.0 {
        return hi;
    }
    if (f_lo < 0.0) == (f_hi < 0.0) {
        return s0;
    }
    // keep f(lo) < 0 < f(hi)
    if f_lo > 0.0 {
        (lo, hi) = (hi, lo);
    }
    let mut s = s0;
    for _ in 0..100 {
        let (f, df) = f_and_df(s);
        if f == 0.0 {
            return s;
        }
        if f < 0.0 {
            lo = s;
        } else {
            hi = s;
        }
        let newton = s - f / df;
        let inside = (newton - lo) * (newton - hi) < 0.0;
        let next = if df != 0.0 && inside { newton } else { 0.5 * (lo + hi) };
        if (next - s).abs() <= 4.0 * f64::EPSILON * (1.0 + s.abs()) {
            return next;
        }
        s = next;
    }
    s
}

/// The point centre + r(s) e(s + angle) and its derivatives from r and its derivatives
/// (rj = [r, r', r'', r''']): with e' = e_perp and e_perp' = -e,
/// c' = r' e + r e_perp, c'' = (r'' - r) e + 2 r' e_perp,
/// c''' = (r''' - 3 r') e + (3 r'' - r) e_perp.
#[inline]
pub fn polar_point(centre: [f64; 2], angle: f64, s: f64, rj: [f64; 4]) -> CurvePoint {
    let (sin, cos) = (s + angle).sin_cos();
    let e = [cos, sin];
    let ep = [-sin, cos];
    let comb = |a: f64, b: f64| [a * e[0] + b * ep[0], a * e[1] + b * ep[1]];
    let [r, r1, r2, r3] = rj;
    let c = comb(r, 0.0);
    CurvePoint {
        c: [centre[0] + c[0], centre[1] + c[1]],
        d1: comb(r1, r),
        d2: comb(r2 - r, 2.0 * r1),
        d3: comb(r3 - 3.0 * r1, 3.0 * r2 - r),
    }
}

impl PeriodicSpline {
    /// The periodic cubic spline through (knots[k], values[k]), k = 0..=n, where the last
    /// knot is knots[0] + 2 pi (set exactly here) and the last value repeats the first.
    pub fn new(mut knots: Vec<f64>, mut values: Vec<f64>) -> Result<Self, String> {
        if knots.len() < 4 || values.len() != knots.len() {
            return Err(format!(
                "a periodic spline needs at least 4 knots (3 intervals) and as many values, got {} and {}",
                knots.len(),
                values.len()
            ));
        }
        let n = knots.len() - 1;
        knots[n] = knots[0] + TAU;
        values[n] = values[0];
        let h: Vec<f64> = (0..n).map(|k| knots[k + 1] - knots[k]).collect();
        if let Some(k) = (0..n).find(|&k| h[k] <= 0.0) {
            return Err(format!("spline knots {k} and {} do not increase", k + 1));
        }
        // continuity of s'' and s' at every knot, cyclically (knot n is knot 0):
        // h[k-1]/6 m[k-1] + (h[k-1] + h[k])/3 m[k] + h[k]/6 m[k+1] = slope[k] - slope[k-1]
        let slope: Vec<f64> = (0..n).map(|k| (values[k + 1] - values[k]) / h[k]).collect();
        let prev = |k: usize| (k + n - 1) % n;
        let sub: Vec<f64> = (0..n).map(|k| h[prev(k)] / 6.0).collect();
        let diag: Vec<f64> = (0..n).map(|k| (h[prev(k)] + h[k]) / 3.0).collect();
        let sup: Vec<f64> = (0..n).map(|k| h[k] / 6.0).collect();
        let rhs: Vec<f64> = (0..n).map(|k| slope[k] - slope[prev(k)]).collect();
        let mut second = solve_cyclic(&sub, &diag, &sup, &rhs);
        second.push(second[0]);
        Ok(PeriodicSpline { knots, values, second })
    }

    pub fn n_intervals(&self) -> usize {
        self.knots.len() - 1
    }

    /// [f, f', f'', f'''] at s (any real: the spline repeats every 2 pi).
    #[inline]
    pub fn eval(&self, s: f64) -> [f64; 4] {
        let (t, y, m) = (&self.knots, &self.values, &self.second);
        let n = t.len() - 1;
        let x = t[0] + (s - t[0]).rem_euclid(TAU);
        // interval k with t[k] <= x < t[k+1] (x may round to t[n]: the last interval)
        let k = t.partition_point(|&tk| tk <= x).clamp(1, n) - 1;
        let h = t[k + 1] - t[k];
        let a = (t[k + 1] - x) / h;
        let b = (x - t[k]) / h;
        let f = a * y[k] + b * y[k + 1] + ((a * a * a - a) * m[k] + (b * b * b - b) * m[k + 1]) * h * h / 6.0;
        let f1 = (y[k + 1] - y[k]) / h - (3.0 * a * a - 1.0) / 6.0 * h * m[k]
            + (3.0 * b * b - 1.0) / 6.0 * h * m[k + 1];
        let f2 = a * m[k] + b * m[k + 1];
        let f3 = (m[k + 1] - m[k]) / h;
        [f, f1, f2, f3]
    }
}

/// Solves the cyclic tridiagonal system sub[k] x[k-1] + diag[k] x[k] + sup[k] x[k+1] =
/// rhs[k] (indices mod n, n >= 3) by Sherman-Morrison on a tridiagonal one (Thomas): the
/// corners sub[0] (row 0, column n-1) and sup[n-1] (row n-1, column 0) are a rank-one
/// update. The spline systems are strictly diagonally dominant, so no pivoting is needed.
pub fn solve_cyclic(sub: &[f64], diag: &[f64], sup: &[f64], rhs: &[f64]) -> Vec<f64> {
    let n = diag.len();
    let (alpha, beta) = (sup[n - 1], sub[0]);
    let gamma = -diag[0];
    let mut d = diag.to_vec();
    d[0] -= gamma;
    d[n - 1] -= alpha * beta / gamma;
    let x = thomas(sub, &d, sup, rhs);
    let mut u = vec![0.0; n];
    u[0] = gamma;
    u[n - 1] = alpha;
    let z = thomas(sub, &d, sup, &u);
    let fact = (x[0] + beta * x[n - 1] / gamma) / (1.0 + z[0] + beta * z[n - 1] / gamma);
    x.iter().zip(&z).map(|(xk, zk)| xk - fact * zk).collect()
}

/// Tridiagonal solve (sub[0] and sup[n-1] unused).
fn thomas(sub: &[f64], diag: &[f64], sup: &[f64], rhs: &[f64]) -> Vec<f64> {
    let n = diag.len();
    let mut c = vec![0.0; n];
    let mut x = vec![0.0; n];
    let mut pivot = diag[0];
    c[0] = sup[0] / pivot;
    x[0] = rhs[0] / pivot;
    for k in 1..n {
        pivot = diag[k] - sub[k] * c[k - 1];
        c[k] = if k + 1 < n { sup[k] / pivot } else { 0.0 };
        x[k] = (rhs[k] - sub[k] * x[k - 1]) / pivot;
    }
    for k in (0..n - 1).rev() {
        x[k] -= c[k] * x[k + 1];
    }
    x
}

/// c(s) and c'(s) of a curve at the jet s (`Curve::eval` and `Curve::fourth` give the
/// derivatives the truncation needs).
#[inline]
pub fn at_jet<const W: usize>(curve: &Curve, s: Jet<W>) -> (Vec2<W>, Vec2<W>) {
    let k = curve.eval(s.value());
    let d4 = curve.fourth(s.value());
    let c = std::array::from_fn(|i| s.compose([k.c[i], k.d1[i], k.d2[i], k.d3[i]]));
    let c1 = std::array::from_fn(|i| s.compose([k.d1[i], k.d2[i], k.d3[i], d4[i]]));
    (c, c1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cyclic_solve_matches_the_dense_system() {
        let n = 7;
        let sub: Vec<f64> = (0..n).map(|k| 0.1 + 0.05 * k as f64).collect();
        let sup: Vec<f64> = (0..n).map(|k| 0.3 - 0.02 * k as f64).collect();
        let diag: Vec<f64> = (0..n).map(|k| 1.0 + 0.1 * (k as f64).sin()).collect();
        let rhs: Vec<f64> = (0..n).map(|k| (k as f64 * 0.7).cos()).collect();
        let x = solve_cyclic(&sub, &diag, &sup, &rhs);
        for k in 0..n {
            let r = sub[k] * x[(k + n - 1) % n] + diag[k] * x[k] + sup[k] * x[(k + 1) % n];
            assert!((r - rhs[k]).abs() < 1e-14, "row {k}: {r} vs {}", rhs[k]);
        }
    }
}

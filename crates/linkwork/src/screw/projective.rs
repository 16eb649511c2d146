//! Homogeneous points and lines: join (the line through two points), meet (the point
//! where two lines cross, at infinity for parallel lines), and a gauge that makes the
//! degeneracy tests independent of units and of where the world origin is.

use super::{ScrewError, DEGENERATE};

/// A homogeneous point (X, Y, W): (X/W, Y/W), or the direction (X, Y) at infinity when
/// W = 0. As the pole of a twist it carries the twist's magnitude: (-vy, vx, w).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Point(pub [f64; 3]);

/// A homogeneous line (a, b, c): a x + b y + c = 0. As the line of action of a wrench it
/// carries the wrench's magnitude: (-fy, fx, m).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Line(pub [f64; 3]);

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

pub(crate) fn unit3(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    if n > 0.0 {
        [a[0] / n, a[1] / n, a[2] / n]
    } else {
        [0.0; 3]
    }
}

impl Point {
    /// The finite point (x, y).
    pub fn finite(p: [f64; 2]) -> Point {
        Point([p[0], p[1], 1.0])
    }

    /// The point at infinity in the direction d.
    pub fn at_infinity(d: [f64; 2]) -> Point {
        Point([d[0], d[1], 0.0])
    }

    /// (x, y) if W is not exactly zero.
    pub fn xy(&self) -> Option<[f64; 2]> {
        (self.0[2] != 0.0).then(|| [self.0[0] / self.0[2], self.0[1] / self.0[2]])
    }

    pub fn scaled(&self, s: f64) -> Point {
        Point([self.0[0] * s, self.0[1] * s, self.0[2] * s])
    }
}

impl Line {
    /// a x + b y + c: for a wrench's line, its moment about p.
    pub fn at(&self, p: [f64; 2]) -> f64 {
        self.0[0] * p[0] + self.0[1] * p[1] + self.0[2]
    }

    /// l . P: zero when the point lies on the line; for a wrench and a twist, W . T.
    pub fn dot(&self, p: &Point) -> f64 {
        dot(self.0, p.0)
    }

    pub fn scaled(&self, s: f64) -> Line {
        Line([self.0[0] * s, self.0[1] * s, self.0[2] * s])
    }
}

/// A length scale and a centre: points are compared as ((X - c_x W)/L, (Y - c_y W)/L, W),
/// normalised, so "coincident", "parallel" and "collinear" mean the same in metres and in
/// millimetres, near the origin or far from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gauge {
    pub centre: [f64; 2],
    pub scale: f64,
}

impl Default for Gauge {
    fn default() -> Gauge {
        Gauge { centre: [0.0, 0.0], scale: 1.0 }
    }
}

impl Gauge {
    /// A gauge centred on the points' mean, scaled by their largest distance from it.
    pub fn around(points: &[[f64; 2]]) -> Gauge {
        let n = points.len().max(1) as f64;
        let c = points.iter().fold([0.0, 0.0], |s, p| [s[0] + p[0] / n, s[1] + p[1] / n]);
        let r = points.iter().map(|p| (p[0] - c[0]).hypot(p[1] - c[1])).fold(0.0, f64::max);
        Gauge { centre: c, scale: if r > 0.0 && r.is_finite() { r } else { 1.0 } }
    }

    /// The point in gauge coordinates, ((X - c_x W)/L, (Y - c_y W)/L, W): a linear map, so
    /// weights and sums of points carry over.
    pub fn map(&self, p: &Point) -> [f64; 3] {
        let [x, y, w] = p.0;
        [(x - self.centre[0] * w) / self.scale, (y - self.centre[1] * w) / self.scale, w]
    }

    /// The point in gauge coordinates, normalised to unit length (zero stays zero).
    pub fn point(&self, p: &Point) -> [f64; 3] {
        unit3(self.map(p))
    }

    /// The line in gauge coordinates, normalised to unit length.
    pub fn line(&self, l: &Line) -> [f64; 3] {
        let [a, b, c] = l.0;
        unit3([a * self.scale, b * self.scale, a * self.centre[0] + b * self.centre[1] + c])
    }

    /// True when the point is at infinity (or so far away that it cannot be told apart).
    pub fn is_at_infinity(&self, p: &Point) -> bool {
        self.point(p)[2].abs() <= DEGENERATE
    }

    /// True when the point is the zero vector (no point at all: a zero twist).
    pub fn is_zero_point(&self, p: &Point) -> bool {
        norm(p.0) == 0.0
    }

    /// True when the two points are the same point.
    pub fn same_point(&self, p: &Point, q: &Point) -> bool {
        norm(cross(self.point(p), self.point(q))) <= DEGENERATE
    }

    /// |det(a, b, c)| of the normalised points, in [0, 1]: 0 when they are collinear.
    pub fn collinearity(&self, a: &Point, b: &Point, c: &Point) -> f64 {
        dot(self.point(a), cross(self.point(b), self.point(c))).abs()
    }

    /// The line through p and q: p x q. As a wrench, the force q - p through p when both
    /// are finite points with W = 1.
    pub fn join(&self, p: &Point, q: &Point) -> Result<Line, ScrewError> {
        if self.same_point(p, q) || norm(p.0) == 0.0 || norm(q.0) == 0.0 {
            return Err(ScrewError::SamePoint);
        }
        Ok(Line(cross(p.0, q.0)))
    }

    /// The point where l and k cross: l x k (at infinity when they are parallel).
    pub fn meet(&self, l: &Line, k: &Line) -> Result<Point, ScrewError> {
        let (a, b) = (self.line(l), self.line(k));
        if norm(cross(a, b)) <= DEGENERATE || norm(l.0) == 0.0 || norm(k.0) == 0.0 {
            return Err(ScrewError::SameLine);
        }
        Ok(Point(cross(l.0, k.0)))
    }

    /// The point as (x, y, 1), or as a unit direction (dx, dy, 0) when at infinity.
    pub fn normalize(&self, p: &Point) -> Point {
        let [x, y, w] = p.0;
        if self.is_at_infinity(p) {
            let n = x.hypot(y);
            if n > 0.0 {
                return Point([x / n, y / n, 0.0]);
            }
            return Point([0.0; 3]);
        }
        Point([x / w, y / w, 1.0])
    }
}

/// The line through p and q (see `Gauge::join`; measured in the world's own units).
pub fn join(p: &Point, q: &Point) -> Result<Line, ScrewError> {
    Gauge::default().join(p, q)
}

/// The point where two lines cross (see `Gauge::meet`).
pub fn meet(l: &Line, k: &Line) -> Result<Point, ScrewError> {
    Gauge::default().meet(l, k)
}

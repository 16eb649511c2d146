"""Curves in a body's frame, for the joints that follow them: circle, closed periodic
cubic spline through points, polar profile r(phi) (a periodic cubic spline through a
table, or an expression of phi evaluated on the reference's own jets). Each gives c(s),
c'(s), c''(s) and c'''(s) (the followers' tangency rows need the third for their
gamma). The parameterisations are the engine's (docs/cams.md): s is an angle of period
2 pi.

Plain NumPy: a periodic spline's second derivatives come from one dense solve of its
cyclic system; the starting parameter from a dense sampling refined by Newton.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .laws import expression3

__all__ = [
    "PeriodicSpline",
    "Circle",
    "ClosedSpline",
    "PolarProfile",
    "ExpressionProfile",
    "build_curve",
    "world_points",
]

TAU = 2.0 * math.pi


def rot(theta: float) -> np.ndarray:
    """A(theta), the 2x2 rotation."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


def perp(v: np.ndarray) -> np.ndarray:
    """v rotated by +90 degrees."""
    return np.array([-v[1], v[0]])


class PeriodicSpline:
    """The periodic cubic spline through (knots[k], values[k]), k = 0..n, with
    knots[n] = knots[0] + 2 pi and values[n] = values[0].

    The second derivatives m_k at the knots make the slope continuous at every knot,
    cyclically: h_{k-1}/6 m_{k-1} + (h_{k-1} + h_k)/3 m_k + h_k/6 m_{k+1} =
    (y_{k+1} - y_k)/h_k - (y_k - y_{k-1})/h_{k-1}, indices modulo n.
    """

    def __init__(self, knots: Any, values: Any) -> None:
        t = np.array(knots, dtype=float)
        y = np.array(values, dtype=float)
        t[-1] = t[0] + TAU
        y[-1] = y[0]
        n = len(t) - 1
        h = np.diff(t)
        A = np.zeros((n, n))
        rhs = np.zeros(n)
        for k in range(n):
            hp, hk = h[k - 1], h[k]  # h[-1]: the last interval, the first's neighbour
            A[k, (k - 1) % n] += hp / 6.0
            A[k, k] += (hp + hk) / 3.0
            A[k, (k + 1) % n] += hk / 6.0
            rhs[k] = (y[k + 1] - y[k]) / hk - (y[k] - y[(k - 1) % n]) / hp
        m = np.linalg.solve(A, rhs)
        self.t, self.y, self.m = t, y, np.append(m, m[0])

    def __call__(self, s: float) -> np.ndarray:
        """[f, f', f'', f'''] at s (the spline repeats every 2 pi)."""
        t, y, m = self.t, self.y, self.m
        x = t[0] + (s - t[0]) % TAU
        k = int(np.clip(np.searchsorted(t, x, side="right") - 1, 0, len(t) - 2))
        h = t[k + 1] - t[k]
        a, b = (t[k + 1] - x) / h, (x - t[k]) / h
        return np.array(
            [
                a * y[k] + b * y[k + 1] + ((a**3 - a) * m[k] + (b**3 - b) * m[k + 1]) * h * h / 6.0,
                (y[k + 1] - y[k]) / h
                - (3 * a * a - 1) / 6.0 * h * m[k]
                + (3 * b * b - 1) / 6.0 * h * m[k + 1],
                a * m[k] + b * m[k + 1],
                (m[k + 1] - m[k]) / h,
            ]
        )


def polar_point(centre: np.ndarray, angle: float, s: float, r: np.ndarray) -> tuple[np.ndarray, ...]:
    """c = centre + r e(s + angle) and its derivatives from r = [r, r', r'', r''']:
    c' = r' e + r e_perp, c'' = (r'' - r) e + 2 r' e_perp, c''' = (r''' - 3 r') e + (3 r'' - r) e_perp."""
    e = np.array([math.cos(s + angle), math.sin(s + angle)])
    ep = perp(e)
    return (
        centre + r[0] * e,
        r[1] * e + r[0] * ep,
        (r[2] - r[0]) * e + 2.0 * r[1] * ep,
        (r[3] - 3.0 * r[1]) * e + (3.0 * r[2] - r[0]) * ep,
    )


class Circle:
    """c(s) = centre + radius e(s + angle)."""

    orientation = 1.0

    def __init__(self, centre: np.ndarray, radius: float, angle: float) -> None:
        self.centre, self.radius, self.angle = centre, radius, angle
        self.n_samples = 64

    def __call__(self, s: float) -> tuple[np.ndarray, ...]:
        return polar_point(self.centre, self.angle, s, np.array([self.radius, 0.0, 0.0, 0.0]))


class PolarProfile:
    """c(s) = centre + r(s) e(s + angle), r a periodic spline through the table."""

    orientation = 1.0

    def __init__(self, centre: np.ndarray, angle: float, angles: Any, radii: Any) -> None:
        self.centre, self.angle = centre, angle
        self.r = PeriodicSpline(angles, radii)
        self.n_samples = max(64, 8 * (len(angles) - 1))

    def __call__(self, s: float) -> tuple[np.ndarray, ...]:
        return polar_point(self.centre, self.angle, s, self.r(s))


class ExpressionProfile:
    """c(s) = centre + r(phi) e(s + angle), r an expression of phi read on one turn:
    phi = s mod 2 pi (so r's derivatives in s are those in phi)."""

    orientation = 1.0
    n_samples = 720  # every half degree: an expression has no knots to follow

    def __init__(self, centre: np.ndarray, angle: float, text: str) -> None:
        self.centre, self.angle = centre, angle
        self.r = expression3(text, "phi")

    def __call__(self, s: float) -> tuple[np.ndarray, ...]:
        return polar_point(self.centre, self.angle, s, np.array(self.r(s % TAU)))


def check_expression(text: str, where: str) -> None:
    """``ValueError`` naming ``where`` unless r(phi) is finite with its three derivatives
    and > 0 at 4096 equal steps of [0, 2 pi], and r, r', r'' meet at 0 and 2 pi to 1e-9
    of the profile's size (the engine's checks, docs/cams.md)."""
    try:
        r = expression3(text, "phi")
    except ValueError as e:
        raise ValueError(f"{where}: curve r: {e}") from None
    grid = np.linspace(0.0, TAU, 4097)
    values = []
    for phi in grid:
        try:
            v = r(float(phi))
        except (ValueError, ZeroDivisionError, OverflowError) as e:
            raise ValueError(f"{where}: curve r is not finite at phi = {phi}: {e}") from None
        if not all(math.isfinite(x) for x in v):
            raise ValueError(f"{where}: curve r is not finite at phi = {phi}: {v}")
        values.append(v)
    table = np.array(values)
    k = int(np.argmin(table[:, 0]))
    if table[k, 0] <= 0.0:
        raise ValueError(f"{where}: curve r {text!r} is {table[k, 0]} at phi = {grid[k]}; it must be > 0")
    size = np.max(np.abs(table[:, :3]), axis=0)
    for j, name in enumerate(("r", "r'", "r''")):
        if abs(table[-1, j] - table[0, j]) > 1e-9 * max(size[0], size[j]):
            raise ValueError(f"{where}: curve r {text!r} is not periodic: {name} differs at 0 and 2 pi")


class ClosedSpline:
    """c(s) = (x(s), y(s)), periodic splines through the points at chordal knots
    s_k = 2 pi (polygon length up to point k) / perimeter."""

    def __init__(self, points: np.ndarray) -> None:
        closed = np.vstack([points, points[:1]])
        chords = np.hypot(*np.diff(closed, axis=0).T)
        knots = TAU * np.concatenate([[0.0], np.cumsum(chords)]) / chords.sum()
        self.x = PeriodicSpline(knots, closed[:, 0])
        self.y = PeriodicSpline(knots, closed[:, 1])
        # the sign of the shoelace area: +1 counter-clockwise
        x, y = closed[:-1, 0], closed[:-1, 1]
        area2 = float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
        self.orientation = -1.0 if area2 < 0.0 else 1.0
        self.n_samples = max(64, 8 * len(points))

    def __call__(self, s: float) -> tuple[np.ndarray, ...]:
        x, y = self.x(s), self.y(s)
        return tuple(np.array([x[k], y[k]]) for k in range(4))


def build_curve(desc: Any, start: tuple[float, float, float], where: str) -> Any:
    """The curve of a description in the frame of a body starting at ``start`` (x, y,
    theta); ``ValueError`` naming ``where`` for a bad curve."""
    if not isinstance(desc, dict):
        raise ValueError(f"{where}: its curve must be a dict, not {type(desc).__name__}")
    x0, y0, th0 = start

    def local(p: Any) -> np.ndarray:
        return rot(th0).T @ (np.asarray(p, dtype=float) - np.array([x0, y0]))

    kind = desc.get("type")
    if kind == "circle":
        radius = float(desc["radius"])
        if not radius > 0.0:
            raise ValueError(f"{where}: curve radius {radius} must be > 0")
        return Circle(local(desc["centre"]), radius, -th0)
    if kind == "spline":
        points = np.array(desc["points"], dtype=float).reshape(-1, 2)
        if len(points) < 3:
            raise ValueError(f"{where}: a closed spline needs at least 3 points, got {len(points)}")
        closed = np.vstack([points, points[:1]])
        chords = np.hypot(*np.diff(closed, axis=0).T)
        if np.any(chords <= 1e-12 * chords.sum()):
            raise ValueError(
                f"{where}: consecutive spline points coincide (the first is not repeated at the end)"
            )
        return ClosedSpline(np.array([local(p) for p in points]))
    if kind == "polar":
        angles = np.array(desc["angles"], dtype=float)
        radii = np.array(desc["radii"], dtype=float)
        if len(angles) != len(radii) or len(angles) < 4:
            raise ValueError(f"{where}: a polar table needs at least 4 rows of (angle, radius)")
        if np.any(radii <= 0.0):
            raise ValueError(f"{where}: polar table radii must be > 0")
        if np.any(np.diff(angles) <= 0.0):
            raise ValueError(f"{where}: polar table angles must increase strictly")
        if abs(angles[-1] - angles[0] - TAU) > 1e-9 * TAU or abs(radii[-1] - radii[0]) > 1e-9 * radii[0]:
            raise ValueError(f"{where}: polar table is not periodic (its last row must close the turn)")
        return PolarProfile(local(desc["centre"]), -th0, angles, radii)
    if kind == "polar_expression":
        text = str(desc["r"])
        check_expression(text, where)
        return ExpressionProfile(local(desc["centre"]), -th0, text)
    raise ValueError(f"{where}: unknown curve type {kind!r}")


def world_points(desc: dict[str, Any]) -> list[tuple[float, float]]:
    """Points showing the curve's extent at the start (for the characteristic length):
    the circle's bounding-box corners, the spline's points, the polar table's points, a
    polar expression's points at 64 equal steps of phi."""
    kind = desc.get("type")
    if kind == "circle":
        (cx, cy), r = desc["centre"], abs(float(desc["radius"]))
        return [(cx - r, cy - r), (cx + r, cy + r)]
    if kind == "spline":
        return [(float(x), float(y)) for x, y in desc["points"]]
    if kind == "polar":
        cx, cy = desc["centre"]
        return [(cx + r * math.cos(a), cy + r * math.sin(a)) for a, r in zip(desc["angles"], desc["radii"])]
    if kind == "polar_expression":
        cx, cy = desc["centre"]
        points = []
        for a in (TAU * k / 64 for k in range(64)):
            # a bad expression shows its centre only: building the joint refuses it by name
            try:
                r = expression3(str(desc["r"]), "phi")(a)[0]
            except (ValueError, ZeroDivisionError, OverflowError):
                return [(cx, cy)]
            if math.isfinite(r):
                points.append((cx + r * math.cos(a), cy + r * math.sin(a)))
        return points
    return []


def _refine(f: Any, s: float, h: float) -> float:
    """Newton on f(s) = (value, slope) from s, kept within [s - h, s + h]."""
    lo, hi = s - h, s + h
    for _ in range(60):
        value, slope = f(s)
        if slope == 0.0:
            break
        step = -value / slope
        s_new = min(max(s + step, lo), hi)
        if abs(s_new - s) <= 1e-16 * (1.0 + abs(s)):
            return s_new
        s = s_new
    return s


def nearest(curve: Any, p: np.ndarray) -> float:
    """The parameter of the curve point nearest p (body frame): the best of a dense
    sampling, then Newton on (c - p) . c' = 0."""
    grid = np.linspace(0.0, TAU, 4 * curve.n_samples, endpoint=False)
    best = float(grid[np.argmin([np.sum((curve(s)[0] - p) ** 2) for s in grid])])

    def f(s: float) -> tuple[float, float]:
        c, d1, d2, _ = curve(s)
        return float((c - p) @ d1), float(d1 @ d1 + (c - p) @ d2)

    return _refine(f, best, grid[1])


def tangent_to_line(curve: Any, n: np.ndarray, p: np.ndarray) -> float:
    """Of the two points where the tangent is perpendicular to n (the extremes of
    n . c(s)), the one nearer the line n . (x - p) = 0."""
    grid = np.linspace(0.0, TAU, 4 * curve.n_samples, endpoint=False)
    heights = np.array([n @ curve(s)[0] for s in grid])

    def f(s: float) -> tuple[float, float]:
        _, d1, d2, _ = curve(s)
        return float(n @ d1), float(n @ d2)

    candidates = [_refine(f, float(grid[k]), grid[1]) for k in (np.argmax(heights), np.argmin(heights))]
    return min(candidates, key=lambda s: abs(float(n @ (curve(s)[0] - p))))

"""The constraints a designer states on a curve-synthesis problem, as residuals
g(x) <= 0 with their exact gradients in the design vector x of `TrackingProblem`:

- the smallest transmission angle mu over the traced stretch: cos mu = (r3^2 + r4^2 -
  d^2) / (2 r3 r4), d^2 = r1^2 + r2^2 - 2 r1 r2 cos theta2, so |cos mu| is largest where
  d is extreme, at theta2 = 0 or pi (mod 2 pi) or at an end of the stretch: the exact
  smallest angle over the stretch is the smallest over those crank angles;
- the ratio of the longest link to the shortest (the four of r1..r4);
- Grashof types: the crank shortest (crank-rocker), the ground shortest (double-crank),
  and for every type s + l <= p + q;
- regions (an axis-aligned box or a disc) for the ground pivots O2, O4 and the coupler
  point P; a point's residual is its signed distance outside the region (the largest
  over the box's sides).

Contradictory constraints raise `SynthesisError` naming them.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...errors import SynthesisError

__all__ = [
    "Region",
    "region",
    "angle",
    "GRASHOF",
    "grashof_type",
    "transmission_cos",
    "smallest_transmission",
]

#: The Grashof types a problem can ask for: the crank turns fully in each.
GRASHOF = ("crank-rocker", "double-crank", "full-turn")
# the engine's tolerance on s + l = p + q, relative to the four lengths' sum
# (crates/linkwork/src/analysis/linkages.rs, LENGTH_TOL)
_CHANGE_POINT_TOL = 1e-9


def grashof_type(r1: float, r2: float, r3: float, r4: float) -> str:
    """The Grashof type of ground r1, crank r2, coupler r3, rocker r4 by the engine's rule
    (`Linkage.kind_of`), from the lengths alone: for a design the engine cannot assemble
    as drawn (at a dead point) and so cannot describe."""
    links = [float(r1), float(r2), float(r3), float(r4)]
    shortest = int(np.argmin(links))
    sl = links[shortest] + max(links)
    pq = sum(links) - sl
    if abs(sl - pq) <= _CHANGE_POINT_TOL * sum(links):
        return "change point"
    if sl > pq:
        return "non-Grashof triple-rocker"
    return ("double-crank", "crank-rocker", "Grashof double-rocker", "rocker-crank")[shortest]


#: The places a region can be stated for.
PLACES = ("O2", "O4", "P")


@dataclass(frozen=True)
class Region:
    """An axis-aligned box (``x``, ``y``: (lower, upper)) or a disc (``centre``,
    ``radius``)."""

    x: tuple[float, float] | None = None
    y: tuple[float, float] | None = None
    centre: tuple[float, float] | None = None
    radius: float | None = None

    def outside(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The signed distance of points p (m x 2) outside the region (<= 0 inside) and
        its gradient in p (m x 2)."""
        p = np.atleast_2d(p)
        if self.centre is not None:
            assert self.radius is not None
            v = p - np.asarray(self.centre)
            d = np.hypot(v[:, 0], v[:, 1])
            grad = v / np.where(d > 0.0, d, 1.0)[:, None]
            return d - self.radius, grad
        assert self.x is not None and self.y is not None
        (x0, x1), (y0, y1) = self.x, self.y
        sides = np.column_stack([x0 - p[:, 0], p[:, 0] - x1, y0 - p[:, 1], p[:, 1] - y1])
        k = np.argmax(sides, axis=1)
        grads = np.array([[-1.0, 0.0], [1.0, 0.0], [0.0, -1.0], [0.0, 1.0]])
        return sides[np.arange(len(p)), k], grads[k]

    def __str__(self) -> str:
        if self.centre is not None:
            return f"disc centre {list(self.centre)} radius {self.radius}"
        return f"box x {list(self.x or ())} y {list(self.y or ())}"


def _pair(name: str, value: Any) -> tuple[float, float]:
    try:
        a, b = (float(v) for v in value)
    except (TypeError, ValueError):
        raise SynthesisError(f"{name} is two numbers, not {value!r}") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise SynthesisError(f"{name} must be finite numbers, got {value!r}")
    return a, b


def region(name: str, value: Any) -> Region:
    """A `Region` from a `Region` or a mapping: {"x": [lo, hi], "y": [lo, hi]} (a box) or
    {"centre": [x, y], "radius": r} (a disc; "center" also read). An empty box or a
    radius <= 0 is a contradiction (`SynthesisError` naming ``name``)."""
    if isinstance(value, Region):
        value = {k: v for k, v in vars(value).items() if v is not None}
    if not isinstance(value, Mapping):
        raise SynthesisError(
            f"region {name}: a box {{x = [lo, hi], y = [lo, hi]}} or a disc {{centre, radius}}"
        )
    keys = set(value)
    if keys == {"x", "y"}:
        x, y = _pair(f"region {name} x", value["x"]), _pair(f"region {name} y", value["y"])
        for axis, (lo, hi) in (("x", x), ("y", y)):
            if lo > hi:
                raise SynthesisError(f"contradictory region {name}: an empty box, {axis} from {lo} to {hi}")
        return Region(x=x, y=y)
    centre = value.get("centre", value.get("center"))
    if keys in ({"centre", "radius"}, {"center", "radius"}):
        c = _pair(f"region {name} centre", centre)
        try:
            r = float(value["radius"])
        except (TypeError, ValueError):
            raise SynthesisError(f"region {name}: radius is a number, not {value['radius']!r}") from None
        if not r > 0.0:
            raise SynthesisError(f"contradictory region {name}: a disc of radius {r} is empty")
        return Region(centre=c, radius=r)
    raise SynthesisError(
        f"region {name}: a box has keys x and y, a disc centre and radius; "
        f"got {', '.join(sorted(map(str, keys)))}"
    )


def angle(name: str, value: Any) -> float:
    """An angle stated with its unit: "40 deg", "0.7 rad" or a number (rad)."""
    if isinstance(value, str):
        m = re.fullmatch(r"\s*([-+0-9.eE]+)\s*(deg|rad)\s*", value)
        if not m:
            raise SynthesisError(f"{name} is a number with its unit, '40 deg' or '0.7 rad', not {value!r}")
        try:
            v = float(m.group(1))
        except ValueError:
            raise SynthesisError(f"{name}: {m.group(1)!r} is not a number") from None
        return math.radians(v) if m.group(2) == "deg" else v
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise SynthesisError(
            f"{name} is an angle ('40 deg', '0.7 rad' or a number in rad), not {value!r}"
        ) from None
    if not math.isfinite(v):
        raise SynthesisError(f"{name} must be finite, got {value!r}")
    return v


def transmission_cos(r: np.ndarray, theta2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """cos mu at crank angles theta2 (m) and its gradient (m x 5) in (r1, r2, r3, r4,
    theta2), in closed form."""
    r1, r2, r3, r4 = (float(v) for v in r[:4])
    th = np.asarray(theta2, dtype=float)
    d2 = r1 * r1 + r2 * r2 - 2.0 * r1 * r2 * np.cos(th)
    c = (r3 * r3 + r4 * r4 - d2) / (2.0 * r3 * r4)
    grad = np.column_stack(
        [
            -(r1 - r2 * np.cos(th)) / (r3 * r4),
            -(r2 - r1 * np.cos(th)) / (r3 * r4),
            1.0 / r4 - c / r3,
            1.0 / r3 - c / r4,
            -r1 * r2 * np.sin(th) / (r3 * r4),
        ]
    )
    return c, grad


def stretch_angles(x: np.ndarray, closed: bool) -> tuple[np.ndarray, np.ndarray]:
    """The crank angles where |cos mu| is largest over the traced stretch (its ends and
    the multiples of pi inside it; 0 and pi for a closed curve, a whole turn) and, for
    each, which crank angle of x it is (-1: a fixed angle)."""
    if closed:
        return np.array([0.0, math.pi]), np.array([-1, -1])
    th = x[9:]
    first, last = float(th[0]), float(th[-1])
    inner = np.arange(math.ceil(first / math.pi), math.floor(last / math.pi) + 1) * math.pi
    inner = inner[(inner > first) & (inner < last)]
    n = len(th)
    which = np.concatenate([[0, n - 1], -np.ones(inner.size, dtype=int)])
    return np.concatenate([[first, last], inner]), which


def smallest_transmission(x: np.ndarray, closed: bool) -> tuple[float, np.ndarray]:
    """The smallest transmission angle (rad, as its distance from 0 or pi) over the traced
    stretch, exactly, and its gradient in x."""
    th, which = stretch_angles(x, closed)
    c, grad = transmission_cos(x[:4], th)
    k = int(np.argmax(np.abs(c)))
    a = min(abs(float(c[k])), 1.0)
    mu = math.acos(a)
    g = np.zeros(x.size)
    # d mu / d |c| = -1 / sin mu; where mu is 0 the design is at a dead point
    s = -math.copysign(1.0, float(c[k])) / max(math.sqrt(max(1.0 - a * a, 0.0)), 1e-300)
    g[:4] = s * grad[k, :4]
    if which[k] >= 0:
        g[9 + which[k]] = s * grad[k, 4]
    return mu, g

"""Curves for pins in curved slots and cam profiles (``Mechanism.pin_in_slot``,
``Mechanism.cam_follower``).

Each function returns the curve's description (a plain dict), in world coordinates at
the starting configuration like every other point of a mechanism; the joint fixes it in
its first body, which carries it along. Every curve is closed and parameterised by an
angle-like s of period 2 pi, which becomes the joint's own coordinate "<joint>.s":

- ``circle``: s is the polar angle about the centre, from the world x axis at the start;
- ``polar``: a cam profile r(phi) tabulated over one turn (a periodic cubic spline
  through the table), s = phi, measured the same way;
- ``polar_expression``: a cam profile r(phi) written as a formula of phi (rad), exact to
  its third derivative, s = phi as for ``polar``;
- ``spline``: a closed cubic spline through points, s = 2 pi times the fraction of the
  polygon's length up to the point (chordal parameterisation).

The engine checks them when the mechanism compiles (radii > 0, at least 3 points, a
table or a formula that closes one turn) and names the joint at fault. See docs/cams.md.

>>> import math
>>> from linkwork import curves
>>> curves.circle((0.02, 0.0), 0.05)
{'type': 'circle', 'centre': [0.02, 0.0], 'radius': 0.05}
>>> c = curves.polar((0, 0), [0, 90, 180, 270, 360], [1.0, 1.2, 1.1, 1.2, 1.0], degrees=True)
>>> c["angles"][-1] == 2 * math.pi
True
>>> curves.polar_expression("0.05 + 0.01*(1 - cos(phi))")
{'type': 'polar_expression', 'centre': [0.0, 0.0], 'r': '0.05 + 0.01*(1 - cos(phi))'}
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any, Callable

from . import _core

__all__ = ["circle", "spline", "polar", "polar_function", "polar_expression", "description"]

KINDS = ("circle", "spline", "polar", "polar_expression")


def _xy(p: Sequence[float]) -> list[float]:
    x, y = p
    return [float(x), float(y)]


def circle(centre: Sequence[float], radius: float) -> dict[str, Any]:
    """A circle of ``radius`` about ``centre``; s is the polar angle about the centre."""
    return {"type": "circle", "centre": _xy(centre), "radius": float(radius)}


def spline(points: Iterable[Sequence[float]]) -> dict[str, Any]:
    """A closed (periodic, C2) cubic spline through ``points`` (at least 3, the first
    not repeated at the end); s runs from the first point in their order."""
    return {"type": "spline", "points": [_xy(p) for p in points]}


def polar(
    centre: Sequence[float], angles: Iterable[float], radii: Iterable[float], degrees: bool = False
) -> dict[str, Any]:
    """A cam profile r(phi) about ``centre``: a periodic cubic spline through the table
    (phi, r). The angles increase over exactly one turn and the last row closes it (its
    angle is the first plus 360 degrees, its radius the first radius). Angles in rad, or
    in degrees with ``degrees=True``."""
    to_rad = math.radians if degrees else float
    return {
        "type": "polar",
        "centre": _xy(centre),
        "angles": [to_rad(float(a)) for a in angles],
        "radii": [float(r) for r in radii],
    }


def polar_function(centre: Sequence[float], r: Callable[[float], float], n: int = 360) -> dict[str, Any]:
    """A polar profile tabulated from a Python function r(phi) (phi in rad) at ``n``
    equal steps of one turn, the closing row included.

    >>> p = polar_function((0, 0), lambda phi: 1.0 + 0.1 * math.cos(phi), n=4)
    >>> [round(r, 3) for r in p["radii"]]
    [1.1, 1.0, 0.9, 1.0, 1.1]
    """
    angles = [2.0 * math.pi * k / n for k in range(n + 1)]
    radii = [float(r(a)) for a in angles[:n]]
    return polar(centre, angles, radii + radii[:1])


def polar_expression(r: str, centre: Sequence[float] = (0.0, 0.0)) -> dict[str, Any]:
    """A cam profile about ``centre`` whose radius is the expression ``r`` of ``phi``
    (in rad, whatever the model's angle unit; from the world x axis at the start), written
    as for `linkwork.Expression`: ``"0.05 + 0.01*(1 - cos(phi))"``. The engine
    differentiates it exactly (c', c'' and c''' as accurate as c), reads it on one turn,
    phi in [0, 2 pi), and repeats it.

    The text is parsed at once; a text that is not an expression raises `ExpressionError`
    with the column at fault. When the mechanism compiles, r must be finite and > 0 all
    round and join itself at 2 pi with its first two derivatives (see docs/cams.md):

    >>> polar_expression("0.05 + 0.01*(1 - cos(x))")
    Traceback (most recent call last):
    ...
    linkwork.errors.ExpressionError: unknown name 'x' at column 22; the variable is 'phi'
    """
    _core.parse_expression(str(r), "phi")
    return {"type": "polar_expression", "centre": _xy(centre), "r": str(r)}


def description(curve: Any) -> dict[str, Any]:
    """A copy of a curve's description, refusing what is not one (a curve is a dict made
    by the functions above, or read from a model file).

    >>> description((0.0, 1.0))
    Traceback (most recent call last):
    ...
    TypeError: a curve is a dict made by linkwork.curves (circle, spline, polar, polar_expression), not tuple
    """
    if not isinstance(curve, dict):
        raise TypeError(
            "a curve is a dict made by linkwork.curves (circle, spline, polar, polar_expression), "
            f"not {type(curve).__name__}"
        )
    if curve.get("type") not in KINDS:
        raise ValueError(f"unknown curve type {curve.get('type')!r}; curves are {', '.join(KINDS)}")
    return dict(curve)

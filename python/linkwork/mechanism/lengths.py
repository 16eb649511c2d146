"""Lengths first: the classical linkages from the lengths a designer's table gives, an
assembly mode, and optionally a coupler point. Nothing is drawn by hand: each builder
gives every pin in its bodies' own frames (`Mechanism.revolute`'s and
`Mechanism.prismatic`'s ``pin_a``, ``pin_b``) and the engine draws the mechanism on the
branch asked (`Mechanism.assemble`, which `compile` does first), with the lengths exactly
as given.

Each returns an ordinary `Mechanism` that can be extended like any other: more bodies on
the coupler, another driver (``m.remove("crank_angle")`` first), masses, loads. Names and
frames are those of `linkwork.examples` (R. L. Norton, *Design of Machinery*): bodies
"crank", "coupler" (or "rod"), "rocker" (or "slider"), each with its frame at its first
pin and its x axis towards the next, revolutes "O2", "A", "B", "O4", the crank driven by
"crank_angle" = theta0 + omega t (rad, rad/s; ``omega=None``: no driver). Lengths in the
model's length unit (metres unless ``units`` says otherwise).

>>> import numpy as np, linkwork as lw
>>> m = lw.build.four_bar(ground=0.35, crank=0.20, coupler=0.35, rocker=0.25, branch="open")
>>> res = m.compile().sweep(np.linspace(0.0, 2 * np.pi / 5.0, 361))
>>> round(float(res.body("rocker").theta[0]), 9)
1.047197551
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from .. import _args
from ..errors import InputError
from ..motion import Linear
from .builder import Mechanism

__all__ = ["four_bar", "slider_crank", "inverted_slider_crank"]


def _lengths(**lengths: float) -> dict[str, float]:
    return {k: _args.number(v, k, positive=True) for k, v in lengths.items()}


def _drive(m: Mechanism, omega: float | None, theta0: float) -> None:
    if omega is not None:
        m.drive_angle(
            "crank", Linear(_args.number(theta0, "theta0"), _args.number(omega, "omega")), name="crank_angle"
        )


def four_bar(
    ground: float,
    crank: float,
    coupler: float,
    rocker: float,
    branch: str = "open",
    coupler_point: Sequence[float] | None = None,
    omega: float | None = 5.0,
    theta0: float = 0.0,
    name: str = "four-bar",
) -> Mechanism:
    """A pin-jointed four-bar from its four lengths: ground pivots O2 = (0, 0) and
    O4 = (ground, 0), the crank O2->A, the coupler A->B, the rocker O4->B; ``branch``
    "open" or "crossed" (the circuits of `closed_form.four_bar`). ``coupler_point``:
    the point "P" of the coupler at (along, across) in its frame, along A->B and to its
    left. Sweeps as `examples.four_bar` of the same lengths (drawn in closed form) to
    round-off.
    """
    n = _lengths(ground=ground, crank=crank, coupler=coupler, rocker=rocker)
    m = Mechanism(name)
    c, k, r = m.body("crank"), m.body("coupler"), m.body("rocker")
    m.revolute(m.ground, c, name="O2", pin_a=(0.0, 0.0), pin_b=(0.0, 0.0))
    m.revolute(c, k, name="A", pin_a=(n["crank"], 0.0), pin_b=(0.0, 0.0))
    m.revolute(k, r, name="B", pin_a=(n["coupler"], 0.0), pin_b=(n["rocker"], 0.0))
    m.revolute(m.ground, r, name="O4", pin_a=(n["ground"], 0.0), pin_b=(0.0, 0.0))
    if coupler_point is not None:
        # the coupler's rough pose is its frame's (0, 0, 0): a point there is in its frame
        m.point("P", k, coupler_point)
    _drive(m, omega, theta0)
    m.branch = _args.choice(branch, "branch", ("open", "crossed"))
    return m


def slider_crank(
    crank: float,
    rod: float,
    offset: float = 0.0,
    branch: str = "open",
    omega: float | None = 5.0,
    theta0: float = 0.0,
    name: str = "slider-crank",
) -> Mechanism:
    """An offset slider-crank from its crank and rod lengths and the offset of the slide
    line (y = ``offset``, along +x): crank O2->A with O2 = (0, 0), rod A->B, the slider's
    frame at its pin B, parallel to the ground's. ``branch`` "open" (the slider ahead of
    the crank pin along +x) or "crossed". The slide s of prismatic "S" is measured from
    x = 0 (where the slider's pin would be at the slide line's pin (0, offset)). Sweeps
    as `examples.slider_crank` to round-off.
    """
    n = _lengths(crank=crank, rod=rod)
    offset = _args.number(offset, "offset")
    m = Mechanism(name)
    c, r, s = m.body("crank"), m.body("rod"), m.body("slider")
    m.revolute(m.ground, c, name="O2", pin_a=(0.0, 0.0), pin_b=(0.0, 0.0))
    m.revolute(c, r, name="A", pin_a=(n["crank"], 0.0), pin_b=(0.0, 0.0))
    m.revolute(r, s, name="B", pin_a=(n["rod"], 0.0), pin_b=(0.0, 0.0))
    m.prismatic(m.ground, s, name="S", pin_a=(0.0, offset), pin_b=(0.0, 0.0), axis=(1.0, 0.0))
    _drive(m, omega, theta0)
    m.branch = _args.choice(branch, "branch", ("open", "crossed"))
    return m


def inverted_slider_crank(
    ground: float,
    crank: float,
    omega: float | None = 5.0,
    theta0: float = 0.0,
    name: str = "inverted slider-crank",
) -> Mechanism:
    """The inverted slider-crank of a Whitworth or crank-shaper quick return, from its
    ground and crank lengths (ground > crank, so the rocker oscillates): crank O2->A,
    O2 = (0, 0); "rocker" pivoted at O4 = (ground, 0), its x axis from O4 towards A;
    "block" pinned to the crank at A and sliding along the rocker (prismatic "S", its
    frame parallel to the rocker's). Its one assembly mode with the rocker pointing at A
    is taken from the rough pose (the rocker's angle at the start, from the two pivots
    and A). Sweeps as `examples.inverted_slider_crank` to round-off.
    """
    n = _lengths(ground=ground, crank=crank)
    if not n["ground"] > n["crank"]:
        raise InputError("the inverted slider-crank needs ground > crank > 0")
    theta0 = _args.number(theta0, "theta0")
    m = Mechanism(name)
    c = m.body("crank")
    # a rough pose only: the mode where the rocker's x axis points at the crank pin
    ax, ay = n["crank"] * math.cos(theta0), n["crank"] * math.sin(theta0)
    phi = math.atan2(ay, ax - n["ground"])
    r = m.body("rocker", (n["ground"], 0.0), phi)
    b = m.body("block", (ax, ay), phi)
    m.revolute(m.ground, c, name="O2", pin_a=(0.0, 0.0), pin_b=(0.0, 0.0))
    m.revolute(c, b, name="A", pin_a=(n["crank"], 0.0), pin_b=(0.0, 0.0))
    m.revolute(m.ground, r, name="O4", pin_a=(n["ground"], 0.0), pin_b=(0.0, 0.0))
    m.prismatic(r, b, name="S", pin_a=(0.0, 0.0), pin_b=(0.0, 0.0), axis_a=(1.0, 0.0))
    _drive(m, omega, theta0)
    return m

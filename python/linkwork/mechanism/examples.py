"""Built-in textbook mechanisms, each a ``Mechanism`` assembled exactly at t = 0.

Every builder takes its dimensions in metres, the crank angle ``theta0`` in radians and
the crank speed ``omega`` in rad/s; the crank is driven by ``crank_angle`` =
``Linear(theta0, omega)``, so one revolution takes 2 pi / omega seconds. Bodies are placed
with the closed forms of ``linkwork.closed_form`` or with exact circle intersections.

>>> from linkwork import examples
>>> sorted(examples.ALL)
['four_bar', 'inverted_slider_crank', 'six_bar_stephenson', 'six_bar_watt', 'slider_crank']
"""

from __future__ import annotations

import math
from typing import Callable

from ..motion import Constant, Linear
from ..reference import closed_form
from .builder import Mechanism

__all__ = ["four_bar", "slider_crank", "inverted_slider_crank", "six_bar", "chain", "ALL"]

Point = tuple[float, float]


def _polar(origin: Point, length: float, angle: float) -> Point:
    return (origin[0] + length * math.cos(angle), origin[1] + length * math.sin(angle))


def _circles(p1: Point, r1: float, p2: Point, r2: float, left: bool) -> Point:
    """Intersection of the circles (p1, r1) and (p2, r2): the one on the left of the
    directed line p1 -> p2 if ``left``, else the one on the right."""
    dx, dy = p2[0] - p1[0], p2[1] - p1[1]
    dist = math.hypot(dx, dy)
    along = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist)
    h2 = r1 * r1 - along * along
    if h2 < 0.0:
        raise ValueError(f"cannot assemble: circles of radii {r1} and {r2} at distance {dist} do not meet")
    across = math.sqrt(h2) * (1.0 if left else -1.0)
    ex, ey = dx / dist, dy / dist
    return (p1[0] + along * ex - across * ey, p1[1] + along * ey + across * ex)


def _angle(p: Point, q: Point) -> float:
    return math.atan2(q[1] - p[1], q[0] - p[0])


def four_bar(
    ground: float = 0.35,
    crank: float = 0.20,
    coupler: float = 0.35,
    rocker: float = 0.25,
    omega: float = 5.0,
    theta0: float = 0.0,
    branch: str = "open",
) -> Mechanism:
    """Pin-jointed four-bar (default: Grashof crank-rocker, lengths in metres).

    Ground pivots O2 = (0, 0) and O4 = (ground, 0); bodies "crank" (O2->A), "coupler"
    (A->B) and "rocker" (O4->B), each with its frame at the first point and x axis along
    the bar, so their thetas are theta2, theta3, theta4 of ``closed_form.four_bar``;
    revolutes "O2", "A", "B", "O4"; driver "crank_angle" = theta0 + omega t (rad, rad/s);
    point "P" at the coupler's midpoint. ``branch`` is "open" or "crossed".
    """
    cf = closed_form.four_bar(ground, crank, coupler, rocker, theta0, omega, 0.0, branch)
    theta3, theta4 = (math.remainder(float(cf[k]), 2.0 * math.pi) for k in ("theta3", "theta4"))
    O2, O4 = (0.0, 0.0), (float(ground), 0.0)
    A = _polar(O2, crank, theta0)
    B = _polar(A, coupler, theta3)
    m = Mechanism("four-bar")
    crank_b = m.body("crank", O2, theta0)
    coupler_b = m.body("coupler", A, theta3)
    rocker_b = m.body("rocker", O4, theta4)
    m.revolute(m.ground, crank_b, O2, name="O2")
    m.revolute(crank_b, coupler_b, A, name="A")
    m.revolute(coupler_b, rocker_b, B, name="B")
    m.revolute(m.ground, rocker_b, O4, name="O4")
    m.drive_angle(crank_b, Linear(theta0, omega), name="crank_angle")
    m.point("P", coupler_b, ((A[0] + B[0]) / 2.0, (A[1] + B[1]) / 2.0))
    return m


def slider_crank(
    crank: float = 0.10, rod: float = 0.35, offset: float = 0.02, omega: float = 5.0, theta0: float = 0.0
) -> Mechanism:
    """Offset slider-crank (lengths in metres): crank pivot O2 = (0, 0), slider pin B on the
    line y = offset, on the +x side.

    Bodies "crank" (O2->A), "rod" (A->B, theta = theta3 of ``closed_form.slider_crank``),
    "slider" (origin at B, angle 0, so slider.x is the slider position x); revolutes "O2",
    "A", "B"; prismatic "S" between the ground and the slider along x through B; driver
    "crank_angle" = theta0 + omega t (rad, rad/s).
    """
    cf = closed_form.slider_crank(crank, rod, offset, theta0, omega)
    theta3 = float(cf["theta3"])
    O2 = (0.0, 0.0)
    A = _polar(O2, crank, theta0)
    B = (float(cf["x"]), float(offset))
    m = Mechanism("slider-crank")
    crank_b = m.body("crank", O2, theta0)
    rod_b = m.body("rod", A, theta3)
    slider_b = m.body("slider", B, 0.0)
    m.revolute(m.ground, crank_b, O2, name="O2")
    m.revolute(crank_b, rod_b, A, name="A")
    m.revolute(rod_b, slider_b, B, name="B")
    m.prismatic(m.ground, slider_b, B, (1.0, 0.0), name="S")
    m.drive_angle(crank_b, Linear(theta0, omega), name="crank_angle")
    return m


def inverted_slider_crank(
    ground: float = 0.30, crank: float = 0.10, omega: float = 5.0, theta0: float = 0.0
) -> Mechanism:
    """Inverted slider-crank, the core of the Whitworth / crank-shaper quick return
    (lengths in metres; ground > crank, so the rocker oscillates).

    Crank "crank" O2->A with O2 = (0, 0); "rocker" pivoted at O4 = (ground, 0), its x axis
    pointing from O4 towards A; "block" at A (same angle as the rocker) pinned to the crank
    and sliding along the rocker. Revolutes "O2", "A" (crank-block), "O4"; prismatic "S"
    (rocker-block, along the rocker through A); driver "crank_angle" = theta0 + omega t.
    """
    if not ground > crank > 0.0:
        raise ValueError("the inverted slider-crank needs ground > crank > 0")
    O2, O4 = (0.0, 0.0), (float(ground), 0.0)
    A = _polar(O2, crank, theta0)
    phi = _angle(O4, A)
    m = Mechanism("inverted slider-crank")
    crank_b = m.body("crank", O2, theta0)
    rocker_b = m.body("rocker", O4, phi)
    block_b = m.body("block", A, phi)
    m.revolute(m.ground, crank_b, O2, name="O2")
    m.revolute(crank_b, block_b, A, name="A")
    m.revolute(m.ground, rocker_b, O4, name="O4")
    m.prismatic(rocker_b, block_b, A, (math.cos(phi), math.sin(phi)), name="S")
    m.drive_angle(crank_b, Linear(theta0, omega), name="crank_angle")
    return m


# Six-bar dimensions (metres). Both start from the same Grashof crank-rocker four-bar
# O2-A-B-O4 (crank 0.10, coupler 0.35, rocker 0.30, ground 0.35: s + l = 0.45 < p + q = 0.65).
_SIX_BAR = {
    "watt": {
        # rocker O4-B-C is ternary: C at 0.25 from O4, 0.3 rad counter-clockwise of O4->B;
        # dyad C->D (0.25) and output O6->D (0.15), O6 = (0.15, 0.45)
        "c_arm": 0.25,
        "c_angle": 0.3,
        "link5": 0.25,
        "output": 0.15,
        "O6": (0.15, 0.45),
    },
    "stephenson": {
        # coupler A-B-C is ternary: C at 0.25 from A, 0.3 rad clockwise of A->B;
        # dyad C->D (0.25) and output O6->D (0.15), O6 = (0.20, -0.15)
        "c_arm": 0.25,
        "c_angle": -0.3,
        "link5": 0.25,
        "output": 0.15,
        "O6": (0.20, -0.15),
    },
}


def six_bar(kind: str = "watt", omega: float = 5.0, theta0: float = 0.0) -> Mechanism:
    """Six-bar linkages of one degree of freedom built on a Grashof crank-rocker four-bar
    O2-A-B-O4 (crank 0.10 m, coupler 0.35 m, rocker 0.30 m, O2 = (0, 0), O4 = (0.35, 0)).

    - ``"watt"`` (Watt II): the rocker is a ternary link O4-B-C (|O4 C| = 0.25 m, 0.3 rad
      counter-clockwise of O4->B); a dyad "link5" C->D (0.25 m) and "output" O6->D
      (0.15 m), O6 = (0.15, 0.45), makes a second four-bar driven by the first one's
      rocker. Transmission angles: 44-87 deg (first loop), 69-112 deg at D; the output
      swings 63 deg.
    - ``"stephenson"`` (Stephenson III): the coupler is a ternary link A-B-C (|A C| =
      0.25 m, 0.3 rad clockwise of A->B); the dyad "link5" C->D (0.25 m) and "output"
      O6->D (0.15 m), O6 = (0.20, -0.15), follows the coupler point C. Transmission
      angle at D 66-112 deg; the output swings 68 deg.

    Bodies "crank", "coupler", "rocker", "link5", "output" (frames at O2, A, O4, C, O6;
    thetas are the bar angles O2->A, A->B, O4->B, C->D, O6->D); revolutes "O2", "A",
    "B", "O4", "C", "D", "O6"; driver "crank_angle" = theta0 + omega t (rad, rad/s);
    point "C". D is on the right of the directed line C -> O6.
    """
    if kind not in _SIX_BAR:
        raise ValueError(f"six_bar kind must be 'watt' or 'stephenson', not {kind!r}")
    dims = _SIX_BAR[kind]
    ground, crank, coupler, rocker = 0.35, 0.10, 0.35, 0.30
    cf = closed_form.four_bar(ground, crank, coupler, rocker, theta0, omega, 0.0, "open")
    theta3, theta4 = (math.remainder(float(cf[k]), 2.0 * math.pi) for k in ("theta3", "theta4"))
    O2, O4, O6 = (0.0, 0.0), (ground, 0.0), tuple(float(v) for v in dims["O6"])
    A = _polar(O2, crank, theta0)
    B = _polar(A, coupler, theta3)
    if kind == "watt":
        C = _polar(O4, dims["c_arm"], theta4 + dims["c_angle"])
    else:
        C = _polar(A, dims["c_arm"], theta3 + dims["c_angle"])
    # D: the intersection on the right of C -> O6 (the branch the dimensions were chosen for)
    D = _circles(C, dims["link5"], O6, dims["output"], left=False)

    m = Mechanism(f"six-bar ({'Watt II' if kind == 'watt' else 'Stephenson III'})")
    crank_b = m.body("crank", O2, theta0)
    coupler_b = m.body("coupler", A, theta3)
    rocker_b = m.body("rocker", O4, theta4)
    link5_b = m.body("link5", C, _angle(C, D))
    output_b = m.body("output", O6, _angle(O6, D))
    ternary = rocker_b if kind == "watt" else coupler_b
    m.revolute(m.ground, crank_b, O2, name="O2")
    m.revolute(crank_b, coupler_b, A, name="A")
    m.revolute(coupler_b, rocker_b, B, name="B")
    m.revolute(m.ground, rocker_b, O4, name="O4")
    m.revolute(ternary, link5_b, C, name="C")
    m.revolute(link5_b, output_b, D, name="D")
    m.revolute(m.ground, output_b, O6, name="O6")
    m.drive_angle(crank_b, Linear(theta0, omega), name="crank_angle")
    m.point("C", ternary, C)
    return m


def chain(
    loops: int = 3,
    ground: float = 0.35,
    crank: float = 0.20,
    coupler: float = 0.35,
    rocker: float = 0.25,
    omega: float = 5.0,
    theta0: float = 0.0,
    offset: float = 0.0,
    spacing: float = 0.0,
) -> Mechanism:
    """A closed chain of ``loops`` four-bar loops in series (3 bodies per loop): the
    scaling benchmark's mechanism. Not in ``ALL``.

    Loop k (k = 1 .. loops) is the Grashof crank-rocker of ``four_bar`` (default: the
    textbook one, lengths in metres) with ground pivots O2 = ((k - 1) spacing, 0) and
    O4 = O2 + (ground, 0): by default (spacing 0) the loops share their pivots, stacked
    in parallel planes, so coordinates stay of the size of one loop. Bodies "crank{k}",
    "coupler{k}", "rocker{k}" (frames and thetas as in ``four_bar``), revolutes "O2_{k}",
    "A{k}", "B{k}", "O4_{k}", open branch. Only loop 1's crank is driven ("crank_angle" =
    theta0 + omega t); loop k+1's crank is tied to loop k's rocker by the relative-angle
    driver "tie{k+1}": theta_crank{k+1} - theta_rocker{k} = ``offset`` (a ``Constant``
    law). A crank-rocker assembles at every crank angle, so the whole chain does, and its
    closed form is the four-bar's applied loop after loop (input angle, rate and
    acceleration of loop k+1 are loop k's rocker angle, rate and acceleration, plus
    ``offset`` on the angle).
    """
    if loops < 1:
        raise ValueError(f"a chain needs at least one loop, not {loops}")
    m = Mechanism(f"chain of {loops} four-bar loops")
    theta2 = float(theta0)
    previous = None
    for k in range(1, loops + 1):
        cf = closed_form.four_bar(ground, crank, coupler, rocker, theta2, omega, 0.0, "open")
        theta3, theta4 = (math.remainder(float(cf[key]), 2.0 * math.pi) for key in ("theta3", "theta4"))
        O2 = ((k - 1) * spacing, 0.0)
        O4 = (O2[0] + ground, 0.0)
        A = _polar(O2, crank, theta2)
        B = _polar(A, coupler, theta3)
        crank_b = m.body(f"crank{k}", O2, theta2)
        coupler_b = m.body(f"coupler{k}", A, theta3)
        rocker_b = m.body(f"rocker{k}", O4, theta4)
        m.revolute(m.ground, crank_b, O2, name=f"O2_{k}")
        m.revolute(crank_b, coupler_b, A, name=f"A{k}")
        m.revolute(coupler_b, rocker_b, B, name=f"B{k}")
        m.revolute(m.ground, rocker_b, O4, name=f"O4_{k}")
        if previous is None:
            m.drive_angle(crank_b, Linear(theta0, omega), name="crank_angle")
        else:
            m.drive_relative_angle(previous, crank_b, Constant(offset), name=f"tie{k}")
        previous = rocker_b
        theta2 = theta4 + offset
    return m


def six_bar_watt() -> Mechanism:
    """Watt II six-bar with the default dimensions (see ``six_bar``)."""
    return six_bar("watt")


def six_bar_stephenson() -> Mechanism:
    """Stephenson III six-bar with the default dimensions (see ``six_bar``)."""
    return six_bar("stephenson")


ALL: dict[str, Callable[[], Mechanism]] = {
    "four_bar": four_bar,
    "slider_crank": slider_crank,
    "inverted_slider_crank": inverted_slider_crank,
    "six_bar_watt": six_bar_watt,
    "six_bar_stephenson": six_bar_stephenson,
}

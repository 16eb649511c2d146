"""Jansen's leg (Theo Jansen's "holy numbers", in centimetres, here in metres) for the
one-design benchmarks: seven moving bodies on one crank, three RRR dyads in a chain.

The crank (15 cm) turns about O = (0, 0); the frame's second pivot is Q = (-38, -7.8) cm.
Pins: C at the crank's tip; P1 (bars j from C, b from Q) and P3 (k from C, c from Q);
P2, the third corner of the rigid triangle b-d-e about Q; the knee P4 (f from P2, g from
P3); the foot F, the third corner of the rigid triangle g-h-i about P3. ``pins(theta)``
gives them by circle intersections (the reference), ``mechanism()`` the linkwork model.
"""

from __future__ import annotations

import math

from linkwork import Mechanism
from linkwork.motion import Linear

Point = tuple[float, float]

# Jansen's lengths, cm -> m
L = {
    k: v / 100.0
    for k, v in dict(
        a=38.0, b=41.5, c=39.3, d=40.1, e=55.8, f=39.4, g=36.7, h=65.7, i=49.0, j=50.0, k=61.9, l=7.8, m=15.0
    ).items()
}
CRANK_PIVOT: Point = (0.0, 0.0)
Q: Point = (-L["a"], -L["l"])
# the bars as (name, pin, pin); the triangles b-d-e and g-h-i are rigid bodies
BARS = (
    ("j", "C", "P1"),
    ("b", "Q", "P1"),
    ("k", "C", "P3"),
    ("c", "Q", "P3"),
    ("d", "Q", "P2"),
    ("e", "P1", "P2"),
    ("f", "P2", "P4"),
    ("g", "P3", "P4"),
    ("i", "P3", "F"),
    ("h", "P4", "F"),
)


def _circles(p1: Point, r1: float, p2: Point, r2: float, left: bool) -> Point:
    """The intersection of the circles (p1, r1) and (p2, r2) on the left of p1 -> p2 if
    ``left``, else on the right."""
    dx, dy = p2[0] - p1[0], p2[1] - p1[1]
    dist = math.hypot(dx, dy)
    along = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist)
    across = math.sqrt(r1 * r1 - along * along) * (1.0 if left else -1.0)
    ex, ey = dx / dist, dy / dist
    return (p1[0] + along * ex - across * ey, p1[1] + along * ey + across * ex)


def pins(theta: float) -> dict[str, Point]:
    """The pins at crank angle ``theta`` on the leg's working assembly (P1 above, P3 below
    the crank, P2 and the knee P4 behind, the foot at the bottom)."""
    c = (L["m"] * math.cos(theta), L["m"] * math.sin(theta))
    p1 = _circles(c, L["j"], Q, L["b"], left=False)
    p3 = _circles(c, L["k"], Q, L["c"], left=True)
    p2 = _circles(Q, L["d"], p1, L["e"], left=True)
    p4 = _circles(p2, L["f"], p3, L["g"], left=False)
    foot = _circles(p3, L["i"], p4, L["h"], left=True)
    return {"O": CRANK_PIVOT, "Q": Q, "C": c, "P1": p1, "P2": p2, "P3": p3, "P4": p4, "F": foot}


def mechanism(omega: float = 5.0, theta0: float = 0.0) -> Mechanism:
    """The leg as a linkwork model, drawn at crank angle ``theta0``, the crank driven by
    ``crank_angle`` = theta0 + omega t: bodies "crank" (O->C), "j" (C->P1), "bde" (the
    triangle, frame at Q), "k" (C->P3), "c" (Q->P3), "f" (P2->P4), "ghi" (the triangle,
    frame at P3); the foot is the point "F"."""
    p = pins(theta0)
    m = Mechanism("Jansen's leg")
    crank = m.link("crank", CRANK_PIVOT, p["C"])
    j = m.link("j", p["C"], p["P1"])
    bde = m.link("bde", Q, p["P1"])
    k = m.link("k", p["C"], p["P3"])
    c = m.link("c", Q, p["P3"])
    f = m.link("f", p["P2"], p["P4"])
    ghi = m.link("ghi", p["P3"], p["P4"])
    m.revolute(m.ground, crank, CRANK_PIVOT, name="O")
    m.revolute(crank, j, p["C"], name="C")
    m.revolute(crank, k, p["C"], name="C2")
    m.revolute(j, bde, p["P1"], name="P1")
    m.revolute(m.ground, bde, Q, name="Q")
    m.revolute(m.ground, c, Q, name="Q2")
    m.revolute(k, c, p["P3"], name="P3")
    m.revolute(c, ghi, p["P3"], name="P3b")
    m.revolute(bde, f, p["P2"], name="P2")
    m.revolute(f, ghi, p["P4"], name="P4")
    m.drive_angle(crank, Linear(theta0, omega), name="crank_angle")
    m.point("F", ghi, p["F"])
    return m

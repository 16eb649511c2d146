"""Building a mechanism: bodies placed in an approximate starting configuration,
joints placed at world points, drivers with motion laws.

A ``Mechanism`` is a plain description (``to_dict``). The engine compiles it
(``Mechanism.compile()``, validation included) and the NumPy reference reads the very
same description, so both solve exactly the same model.

Conventions (absolute coordinates): every moving body has q_i = (x_i, y_i, theta_i),
the world position of its frame origin and its rotation. Points and joints are given
in world coordinates at the starting configuration; the local vectors are derived from
each body's starting pose, u = A(theta_0)^T (P - R_0). The ground is the fixed frame,
named ``"ground"``; it has no coordinates.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .motion import Law

if TYPE_CHECKING:
    from .model import Model

__all__ = ["Body", "Mechanism", "GROUND"]

GROUND = "ground"


@dataclass(frozen=True)
class Body:
    """A handle on a body of a mechanism (or on the ground)."""

    name: str

    @property
    def is_ground(self) -> bool:
        return self.name == GROUND


BodyLike = "Body | str"


def _name(body: Body | str) -> str:
    return body.name if isinstance(body, Body) else str(body)


def _xy(p: Sequence[float]) -> list[float]:
    x, y = p
    return [float(x), float(y)]


class Mechanism:
    """A planar mechanism under construction.

    >>> import math, linkwork as lw
    >>> m = lw.Mechanism("four-bar")
    >>> crank = m.link("crank", (0, 0), (0.2, 0))
    >>> m.revolute(m.ground, crank, at=(0, 0))          # doctest: +ELLIPSIS
    'A'
    """

    def __init__(self, name: str = "mechanism") -> None:
        self.name = name
        self.ground = Body(GROUND)
        self._bodies: list[dict[str, Any]] = []
        self._joints: list[dict[str, Any]] = []
        self._drivers: list[dict[str, Any]] = []
        self._points: list[dict[str, Any]] = []

    # -- bodies ---------------------------------------------------------------------
    def body(self, name: str, origin: Sequence[float] = (0.0, 0.0), angle: float = 0.0) -> Body:
        """A moving body whose frame starts at ``origin`` rotated by ``angle`` (rad)."""
        x, y = _xy(origin)
        self._bodies.append({"name": str(name), "x": x, "y": y, "theta": float(angle)})
        return Body(str(name))

    def link(self, name: str, start: Sequence[float], end: Sequence[float]) -> Body:
        """A bar from ``start`` to ``end``: frame at ``start``, x axis along the bar,
        so the body's theta is the bar's angle."""
        sx, sy = _xy(start)
        ex, ey = _xy(end)
        return self.body(name, (sx, sy), math.atan2(ey - sy, ex - sx))

    def point(self, name: str, body: Body | str, at: Sequence[float]) -> str:
        """A named point fixed in ``body``, at world ``at`` in the starting configuration
        (a coupler point, say); results give its position, velocity and acceleration."""
        self._points.append({"name": str(name), "body": _name(body), "at": _xy(at)})
        return str(name)

    # -- joints ---------------------------------------------------------------------
    def _auto(self, prefix: str, name: str | None) -> str:
        if name is not None:
            return str(name)
        used = {j["name"] for j in self._joints} | {d["name"] for d in self._drivers}
        if prefix == "":
            # revolutes are named A, B, C, ... as on textbook figures
            for k in range(26 * 27):
                cand = chr(65 + k % 26) + ("" if k < 26 else str(k // 26))
                if cand not in used:
                    return cand
        k = 1
        while f"{prefix}{k}" in used:
            k += 1
        return f"{prefix}{k}"

    def revolute(
        self, body_a: Body | str, body_b: Body | str, at: Sequence[float], name: str | None = None
    ) -> str:
        """A pin joint at world point ``at``: 2 rows, r_P(b) - r_P(a) = 0."""
        name = self._auto("", name)
        self._joints.append(
            {
                "type": "revolute",
                "name": name,
                "body_a": _name(body_a),
                "body_b": _name(body_b),
                "at": _xy(at),
            }
        )
        return name

    def prismatic(
        self,
        body_a: Body | str,
        body_b: Body | str,
        at: Sequence[float],
        axis: Sequence[float],
        name: str | None = None,
    ) -> str:
        """A translational joint: ``body_b`` slides on ``body_a`` along ``axis`` (world
        direction at the start, fixed in ``body_a``) through ``at``. 2 rows: no relative
        rotation, no offset across the axis. The slide s is 0 at the start."""
        name = self._auto("P", name)
        self._joints.append(
            {
                "type": "prismatic",
                "name": name,
                "body_a": _name(body_a),
                "body_b": _name(body_b),
                "at": _xy(at),
                "axis": _xy(axis),
            }
        )
        return name

    def fixed(self, body_a: Body | str, body_b: Body | str, name: str | None = None) -> str:
        """A weld: ``body_b`` keeps its starting pose relative to ``body_a`` (3 rows)."""
        name = self._auto("W", name)
        self._joints.append({"type": "fixed", "name": name, "body_a": _name(body_a), "body_b": _name(body_b)})
        return name

    # -- drivers --------------------------------------------------------------------
    def _driver(self, kind: str, name: str | None, law: Law, **fields: Any) -> str:
        if not isinstance(law, Law):
            raise TypeError(f"driver law must be a linkwork motion law, got {type(law).__name__}")
        name = self._auto("D", name)
        self._drivers.append({"type": kind, "name": name, **fields, "law": law.to_dict()})
        return name

    def drive_angle(self, body: Body | str, law: Law, name: str | None = None) -> str:
        """theta_body = f(t) (absolute angle, rad)."""
        return self._driver("angle", name, law, body=_name(body))

    def drive_relative_angle(
        self, body_a: Body | str, body_b: Body | str, law: Law, name: str | None = None
    ) -> str:
        """theta_b - theta_a = f(t) (either may be the ground)."""
        return self._driver("relative_angle", name, law, body_a=_name(body_a), body_b=_name(body_b))

    def drive_distance(
        self,
        body_a: Body | str,
        at_a: Sequence[float],
        body_b: Body | str,
        at_b: Sequence[float],
        law: Law,
        name: str | None = None,
    ) -> str:
        """|r_Pb - r_Pa| = f(t): a linear actuator between a point of a and a point of b."""
        return self._driver(
            "distance", name, law, body_a=_name(body_a), at_a=_xy(at_a), body_b=_name(body_b), at_b=_xy(at_b)
        )

    def drive_coordinate(
        self, body: Body | str, at: Sequence[float], axis: str, law: Law, name: str | None = None
    ) -> str:
        """x (``axis="x"``) or y (``axis="y"``) of a point of ``body`` = f(t)."""
        return self._driver("coordinate", name, law, body=_name(body), at=_xy(at), axis=str(axis))

    def drive_translation(self, joint: str, law: Law, name: str | None = None) -> str:
        """The slide s of prismatic joint ``joint`` = f(t) (s = 0 at the start)."""
        return self._driver("translation", name, law, joint=str(joint))

    # -- description ------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The model description shared by the engine and the reference (plain data)."""
        return {
            "name": self.name,
            "bodies": [dict(b) for b in self._bodies],
            "joints": [dict(j) for j in self._joints],
            "drivers": [dict(d) for d in self._drivers],
            "points": [dict(p) for p in self._points],
        }

    def compile(self, **options: Any) -> Model:
        """Validate and compile into an engine model (raises ``ModelError``)."""
        from .model import Model

        return Model(self, **options)

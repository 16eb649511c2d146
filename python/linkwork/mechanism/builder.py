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

import functools
import inspect
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Callable

from .. import _args, curves
from ..errors import InputError, LinkworkError, ModelError
from ..kinds import GROUND, PINNED
from ..model.compiled import Model
from ..motion import Law
from . import assembly, files

__all__ = ["Body", "Mechanism", "GROUND"]


@dataclass(frozen=True)
class Body:
    """A handle on a body of a mechanism (or on the ground)."""

    name: str

    @property
    def is_ground(self) -> bool:
        return self.name == GROUND


BodyLike = "Body | str"
# a curve's description, as made by ``linkwork.curves``
Curve = dict[str, Any]


def _name(body: Body | str) -> str:
    if isinstance(body, Body):
        return body.name
    if not isinstance(body, str):
        raise InputError(f"a body is given by its name (or the Body returned by body/link), not {body!r}")
    return body


def _xy(p: Sequence[float]) -> list[float]:
    try:
        x, y = p
        xy = [float(x), float(y)]
    except (TypeError, ValueError):
        raise InputError(f"a point or direction is a pair of numbers (x, y), not {p!r}") from None
    if not all(math.isfinite(v) for v in xy):
        raise InputError(f"a point or direction must be finite, not {p!r}")
    return xy


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
        self._loads: list[dict[str, Any]] = []
        self.gravity: tuple[float, float] = (0.0, 0.0)
        self._python_laws: dict[str, Callable[[float], Any]] = {}
        #: the units the numbers are written in, e.g. ``{"length": "mm", "angle": "deg"}``;
        #: None for metres and radians (see docs/model-format.md)
        self.units: dict[str, str] | None = None
        #: what a sweep keeps unless told otherwise (`Model.sweep`'s ``outputs``: bodies,
        #: columns, named points, joints); None keeps every coordinate
        self.outputs: list[str] | None = None
        #: the assembly mode a mechanism given by its pins is drawn on ("open", "crossed",
        #: or {linkage: circuit}; `assemble`); None: the one nearest the bodies' rough poses
        self.branch: str | dict[str, str] | None = None
        #: where a joint gives both its drawn point ``at`` and its pins and they disagree:
        #: None, a `ClosureError` naming the joint and the miss; "given", the engine keeps
        #: the pins and moves the bodies until the joints hold (least squares); "drawn", it
        #: keeps the drawing's points. What was done is `Model.closing`.
        self.close: str | None = None
        #: compile with the undriven coordinates free (forward dynamics, equilibrium)
        self.free: bool = False
        #: a simulation's initial rates by coordinate column ("crank.theta") or revolute or
        #: prismatic joint name, in the model's units; the other rates follow from the
        #: joints (`Model.simulate`)
        self.initial_rates: dict[str, float] = {}
        # (file, {(kind, name): line}) of a mechanism read from a file, for compile errors
        self._source: tuple[str, dict[tuple[str, str], int]] | None = None

    # -- bodies ---------------------------------------------------------------------
    def body(
        self,
        name: str,
        origin: Sequence[float] = (0.0, 0.0),
        angle: float = 0.0,
        mass: float = 0.0,
        inertia: float = 0.0,
        com: Sequence[float] | None = None,
    ) -> Body:
        """A moving body whose frame starts at ``origin`` rotated by ``angle`` (rad).

        For inverse dynamics: ``mass``, ``inertia`` (about the centre of mass) and ``com``
        (the centre of mass, a world point at the start; default the origin)."""
        if not isinstance(name, str) or not name:
            raise InputError(f"a body's name is a non-empty string, not {name!r}")
        x, y = _xy(origin)
        body: dict[str, Any] = {"name": str(name), "x": x, "y": y, "theta": float(angle)}
        if mass or inertia:
            body.update(mass=float(mass), inertia=float(inertia))
        if com is not None:
            body["com"] = _xy(com)
        self._bodies.append(body)
        return Body(str(name))

    def link(
        self,
        name: str,
        start: Sequence[float],
        end: Sequence[float],
        mass: float = 0.0,
        inertia: float | None = None,
        com: Sequence[float] | None = None,
    ) -> Body:
        """A bar from ``start`` to ``end``: frame at ``start``, x axis along the bar,
        so the body's theta is the bar's angle.

        With a ``mass``, the bar is a uniform slender rod unless told otherwise: centre of
        mass at its middle, inertia m L^2 / 12 about it."""
        sx, sy = _xy(start)
        ex, ey = _xy(end)
        if com is None and mass:
            com = ((sx + ex) / 2.0, (sy + ey) / 2.0)
        if inertia is None:
            inertia = float(mass) * ((ex - sx) ** 2 + (ey - sy) ** 2) / 12.0
        return self.body(name, (sx, sy), math.atan2(ey - sy, ex - sx), mass, inertia, com)

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
        self,
        body_a: Body | str,
        body_b: Body | str,
        at: Sequence[float] | None = None,
        name: str | None = None,
        pin_a: Sequence[float] | None = None,
        pin_b: Sequence[float] | None = None,
    ) -> str:
        """A pin joint: 2 rows, r_P(b) - r_P(a) = 0. Drawn: at the world point ``at``.
        Lengths first: at ``pin_a`` in ``body_a``'s frame and ``pin_b`` in ``body_b``'s (the
        ground's frame is the world), the bodies' poses then rough or left at 0 and found
        by the engine (`assemble`, done by `compile`), on ``branch``'s assembly mode.

        >>> m = Mechanism("four-bar, lengths first")
        >>> m.revolute(m.ground, m.body("crank"), pin_a=(0, 0), pin_b=(0, 0))
        'A'
        """
        name = self._auto("", name)
        if at is None and (pin_a is None or pin_b is None):
            raise InputError(
                f"revolute {name!r}: give its world point `at`, or its pin in each body (pin_a, pin_b)"
            )
        joint: dict[str, Any] = {
            "type": "revolute",
            "name": name,
            "body_a": _name(body_a),
            "body_b": _name(body_b),
        }
        for key, value in (("at", at), ("pin_a", pin_a), ("pin_b", pin_b)):
            if value is not None:
                joint[key] = _xy(value)
        self._joints.append(joint)
        return name

    def prismatic(
        self,
        body_a: Body | str,
        body_b: Body | str,
        at: Sequence[float] | None = None,
        axis: Sequence[float] | None = None,
        name: str | None = None,
        pin_a: Sequence[float] | None = None,
        pin_b: Sequence[float] | None = None,
        axis_a: Sequence[float] | None = None,
        angle: float | None = None,
        travel: Sequence[float] | None = None,
    ) -> str:
        """A translational joint: ``body_b`` slides on ``body_a``. 2 rows: no relative
        rotation, no offset across the axis. Drawn: along ``axis`` (a world direction at
        the start, fixed in ``body_a``) through the world point ``at``; the slide s is 0 at
        the start. Lengths first: along the line through ``pin_a`` in ``body_a``'s frame,
        in the direction ``axis_a`` there (or the world ``axis``, for a slide on the
        ground), with ``body_b``'s point ``pin_b`` (in its frame) on it, ``angle`` =
        theta_b - theta_a (default 0); s is 0 where ``pin_b`` is at ``pin_a``.
        ``travel`` = (min, max): the range of s (a stroke's stops); a sweep reports where
        the slider crosses either end and goes on, a simulation where it reaches one
        (`Model.simulate`, ``at_travel_end``): "end_of_travel" events.

        >>> m = Mechanism("slider, lengths first")
        >>> m.prismatic(m.ground, m.body("slider"), pin_a=(0, 0.02), pin_b=(0, 0), axis=(1, 0))
        'P1'
        """
        name = self._auto("P", name)
        if at is None and (pin_a is None or pin_b is None):
            raise InputError(
                f"prismatic {name!r}: give its world point `at`, or its pin in each body (pin_a, pin_b)"
            )
        if axis is None and axis_a is None:
            raise InputError(
                f"prismatic {name!r}: give its direction, `axis` (world) or `axis_a` (in body_a)"
            )
        joint: dict[str, Any] = {
            "type": "prismatic",
            "name": name,
            "body_a": _name(body_a),
            "body_b": _name(body_b),
        }
        for key, value in (
            ("at", at),
            ("axis", axis),
            ("pin_a", pin_a),
            ("pin_b", pin_b),
            ("axis_a", axis_a),
        ):
            if value is not None:
                joint[key] = _xy(value)
        if angle is not None:
            joint["angle"] = float(angle)
        if travel is not None:
            joint["travel"] = _xy(travel)
        self._joints.append(joint)
        return name

    def fixed(self, body_a: Body | str, body_b: Body | str, name: str | None = None) -> str:
        """A weld: ``body_b`` keeps its starting pose relative to ``body_a`` (3 rows)."""
        name = self._auto("W", name)
        self._joints.append({"type": "fixed", "name": name, "body_a": _name(body_a), "body_b": _name(body_b)})
        return name

    # -- joints without coordinates of their own (docs/joints.md) -------------------
    def _joint(self, kind: str, prefix: str, name: str | None, **fields: Any) -> str:
        name = self._auto(prefix, name)
        given = {k: v for k, v in fields.items() if v is not None}
        self._joints.append({"type": kind, "name": name, **given})
        return name

    def distance(
        self,
        body_a: Body | str,
        at_a: Sequence[float],
        body_b: Body | str,
        at_b: Sequence[float],
        length: float | None = None,
        name: str | None = None,
    ) -> str:
        """A massless coupler between the point ``at_a`` of ``body_a`` and ``at_b`` of
        ``body_b`` (world points at the start): 1 row, (d.d - L^2) / (2 L) = 0 with
        d = r_b - r_a. ``length`` L defaults to the distance in the drawing."""
        return self._joint(
            "distance", "R", name, body_a=_name(body_a), at_a=_xy(at_a), body_b=_name(body_b),
            at_b=_xy(at_b), length=None if length is None else float(length),
        )  # fmt: skip

    def point_on_line(
        self,
        body_a: Body | str,
        body_b: Body | str,
        at: Sequence[float],
        axis: Sequence[float],
        through: Sequence[float] | None = None,
        offset: float | None = None,
        name: str | None = None,
    ) -> str:
        """The pin ``at`` of ``body_a`` in a straight slot of ``body_b``: the line through
        ``through`` (default ``at``) along ``axis`` (world, at the start), fixed in
        ``body_b``. 1 row, n.(r_a(at) - r_b(through)) - offset = 0, n the axis turned by
        +90 degrees; ``offset`` defaults to the drawing's. With ``through`` off the pin
        it is a slider block pinned to ``body_a`` sliding along an offset line of ``body_b``."""
        return self._joint(
            "point_on_line", "S", name, body_a=_name(body_a), body_b=_name(body_b), at=_xy(at),
            axis=_xy(axis), through=None if through is None else _xy(through),
            offset=None if offset is None else float(offset),
        )  # fmt: skip

    def gear(
        self,
        body_a: Body | str,
        body_b: Body | str,
        radii: Sequence[float] | None = None,
        ratio: float | None = None,
        internal: bool = False,
        carrier: Body | str | None = None,
        centres: Sequence[Sequence[float]] | None = None,
        name: str | None = None,
    ) -> str:
        """Spur gears rolling without slipping, by pitch ``radii`` (r_a, r_b) or by the
        speed ratio r_a / r_b (radii then from the distance between the ``centres``,
        world points at the start, default the bodies' origins). 1 row:
        r_a (theta_a - theta_c) +- r_b (theta_b - theta_c) = const (from the drawing),
        divided by max(r_a, r_b); theta_c is the ``carrier``'s angle (a planetary
        train's arm) or 0 with both centres fixed in the ground. External gears (+) turn
        opposite ways, ``internal`` ones (-) the same way."""
        r_a, r_b = (None, None) if radii is None else (float(radii[0]), float(radii[1]))
        c_a, c_b = (None, None) if centres is None else (_xy(centres[0]), _xy(centres[1]))
        return self._joint(
            "gear", "G", name, body_a=_name(body_a), body_b=_name(body_b), radius_a=r_a,
            radius_b=r_b, ratio=None if ratio is None else float(ratio), centre_a=c_a,
            centre_b=c_b, internal=bool(internal) or None,
            carrier=None if carrier is None else _name(carrier),
        )  # fmt: skip

    def rack_pinion(
        self,
        pinion: Body | str,
        rack: Body | str,
        radius: float,
        axis: Sequence[float],
        centre: Sequence[float] | None = None,
        name: str | None = None,
    ) -> str:
        """A pinion (pitch ``radius``, centre ``centre``, default its origin) meshing with a
        rack (a body, or the ground) along ``axis`` (world, at the start, fixed in the
        rack). 1 row: e.(r_pinion(centre) - r_rack(centre)) + r (theta_pinion -
        theta_rack - const) = 0: a counter-clockwise turn dtheta moves the rack by
        r dtheta along ``axis``."""
        return self._joint(
            "rack_pinion", "RP", name, body_a=_name(pinion), body_b=_name(rack), radius=float(radius),
            axis=_xy(axis), centre=None if centre is None else _xy(centre),
        )  # fmt: skip

    def belt(
        self,
        body_a: Body | str,
        body_b: Body | str,
        radii: Sequence[float] | None = None,
        ratio: float | None = None,
        crossed: bool = False,
        carrier: Body | str | None = None,
        name: str | None = None,
    ) -> str:
        """A belt or chain between two pulleys, by pitch ``radii`` or by the ratio
        r_a / r_b. 1 row: r_a (theta_a - theta_c) -+ r_b (theta_b - theta_c) = const,
        divided by max(r_a, r_b): an open belt (-) turns both the same way, a ``crossed``
        one (+) opposite ways; theta_c is the ``carrier``'s angle, or 0."""
        r_a, r_b = (None, None) if radii is None else (float(radii[0]), float(radii[1]))
        return self._joint(
            "belt", "BT", name, body_a=_name(body_a), body_b=_name(body_b), radius_a=r_a, radius_b=r_b,
            ratio=None if ratio is None else float(ratio), crossed=bool(crossed) or None,
            carrier=None if carrier is None else _name(carrier),
        )  # fmt: skip

    def fixed_orientation(
        self, body_a: Body | str, body_b: Body | str, angle: float | None = None, name: str | None = None
    ) -> str:
        """``body_b`` keeps its angle to ``body_a``; both translate freely. 1 row,
        theta_b - theta_a - angle = 0 (``angle`` defaults to the drawing's)."""
        return self._joint(
            "fixed_orientation", "O", name, body_a=_name(body_a), body_b=_name(body_b),
            angle=None if angle is None else float(angle),
        )  # fmt: skip

    def parallel(
        self,
        body_a: Body | str,
        body_b: Body | str,
        axis_a: Sequence[float],
        axis_b: Sequence[float],
        name: str | None = None,
    ) -> str:
        """The line of ``body_a`` along ``axis_a`` stays parallel to the line of ``body_b``
        along ``axis_b`` (world directions at the start). 1 row, (A_a e_a) x (A_b e_b) = 0."""
        return self._joint(
            "parallel", "PL", name, body_a=_name(body_a), body_b=_name(body_b), axis_a=_xy(axis_a),
            axis_b=_xy(axis_b),
        )  # fmt: skip

    def linear_coupling(
        self,
        body_a: Body | str,
        body_b: Body | str,
        coefficients_a: dict[str, float] | None = None,
        coefficients_b: dict[str, float] | None = None,
        value: float | None = None,
        name: str | None = None,
    ) -> str:
        """A linear relation between the coordinates of at most two bodies (either may be
        the ground): sum of c_k q_k over ``coefficients_a`` and ``coefficients_b`` (keys
        "x", "y", "theta") = ``value`` (default: the drawing's). 1 row.

        >>> m = Mechanism()
        >>> a, b = m.body("a"), m.body("b", (0.3, 0.0))
        >>> m.linear_coupling(a, b, {"theta": 2.0}, {"theta": 1.0})   # 2 theta_a + theta_b = const
        'K1'
        """
        fields: dict[str, Any] = {}
        for key, given in (("coefficients_a", coefficients_a), ("coefficients_b", coefficients_b)):
            if given:
                unknown = set(given) - {"x", "y", "theta"}
                if unknown:
                    raise ValueError(f"{key} may name 'x', 'y' and 'theta', not {sorted(unknown)}")
                fields[key] = {k: float(v) for k, v in given.items()}
        return self._joint(
            "linear_coupling", "K", name, body_a=_name(body_a), body_b=_name(body_b), **fields,
            value=None if value is None else float(value),
        )  # fmt: skip

    def pin_in_slot(
        self,
        body_a: Body | str,
        body_b: Body | str,
        at: Sequence[float],
        curve: Curve,
        name: str | None = None,
    ) -> str:
        """A pin of ``body_b`` at world point ``at`` in a curved slot of ``body_a``: the pin
        stays on ``curve`` (from ``linkwork.curves``, world coordinates at the start), which
        ``body_a`` carries. 2 rows, r_b(P) - (R_a + A_a c(s)) = 0, and one own coordinate,
        the curve parameter "<name>.s" (see docs/cams.md). The slot's ends are not enforced:
        the curve is closed."""
        name = self._auto("S", name)
        self._joints.append(
            {
                "type": "pin_in_slot",
                "name": name,
                "body_a": _name(body_a),
                "body_b": _name(body_b),
                "at": _xy(at),
                "curve": curves.description(curve),
            }
        )
        return name

    def cam_follower(
        self,
        cam: Body | str,
        follower: Body | str,
        at: Sequence[float],
        profile: Curve,
        kind: str = "knife",
        radius: float | None = None,
        face: Sequence[float] | None = None,
        name: str | None = None,
    ) -> str:
        """A cam (``cam``, with its ``profile`` from ``linkwork.curves``, world coordinates
        at the start) and its ``follower``, in contact. ``kind``:

        - ``"knife"``: the follower's tip ``at`` stays on the profile (2 rows, as
          ``pin_in_slot``);
        - ``"roller"``: a roller of ``radius`` centred at ``at`` rolls on the profile: the
          centre is ``radius`` from the contact point, along the profile's normal there;
        - ``"flat"``: the follower's face, the line through ``at`` along ``face`` (a world
          direction at the start), is tangent to the profile.

        Each adds one own coordinate, the contact's curve parameter "<name>.s". How the
        follower moves (translating, oscillating) is its own joint to the ground (or a
        frame): ``prismatic`` or ``revolute``. See docs/cams.md."""
        if kind not in ("knife", "roller", "flat"):
            raise ValueError(f"cam follower kind must be 'knife', 'roller' or 'flat', not {kind!r}")
        name = self._auto("C", name)
        joint: dict[str, Any] = {
            "type": "cam_follower",
            "name": name,
            "body_a": _name(cam),
            "body_b": _name(follower),
            "follower": kind,
            "at": _xy(at),
            "curve": curves.description(profile),
        }
        if radius is not None:
            joint["radius"] = float(radius)
        if face is not None:
            joint["face"] = _xy(face)
        self._joints.append(joint)
        return name

    # -- drivers --------------------------------------------------------------------
    def _driver(self, kind: str, name: str | None, law: Law, **fields: Any) -> str:
        if not isinstance(law, Law):
            raise InputError(f"driver law must be a linkwork motion law (Linear, Expression...), not {law!r}")
        name = self._auto("D", name)
        self._register(law)
        self._drivers.append({"type": kind, "name": name, **fields, "law": law.to_dict()})
        return name

    def _register(self, law: Law) -> None:
        """Keeps the Python functions of ``law`` to hand them to the engine with the description."""
        for fname, func in law.python_functions().items():
            known = self._python_laws.get(fname)
            if known is not None and known is not func:
                raise ModelError(
                    f"two different Python laws are named {fname!r}; give one another name "
                    "(PythonLaw(func, name=...))"
                )
            self._python_laws[fname] = func

    @property
    def python_laws(self) -> dict[str, Callable[[float], Any]]:
        """The functions of the `PythonLaw` laws used, by name (passed to the engine)."""
        return dict(self._python_laws)

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

    def set_mass(
        self, body: Body | str, mass: float, inertia: float, com: Sequence[float] | None = None
    ) -> None:
        """Mass properties of a body already added: ``mass``, ``inertia`` about the centre
        of mass, and ``com`` (a world point at the start; unchanged if not given)."""
        name = _name(body)
        for b in self._bodies:
            if b["name"] == name:
                b.update(mass=float(mass), inertia=float(inertia))
                if com is not None:
                    b["com"] = _xy(com)
                return
        raise KeyError(f"no body named {name!r}")

    # -- loads (inverse dynamics) ------------------------------------------------------
    def set_gravity(self, g: Sequence[float] = (0.0, -9.81)) -> None:
        """Gravitational acceleration in world axes (default 9.81 m/s^2 down -y)."""
        self.gravity = (float(g[0]), float(g[1]))

    def force(
        self,
        body: Body | str,
        at: Sequence[float],
        direction: Sequence[float],
        law: Law,
        name: str | None = None,
    ) -> str:
        """A force of magnitude f(t) along the fixed world ``direction`` at world point ``at``
        (at the start) of ``body``."""
        self._register(law)
        return self._load(
            "force", name, body=_name(body), at=_xy(at), direction=_xy(direction), law=law.to_dict()
        )

    def torque(self, body: Body | str, law: Law, name: str | None = None) -> str:
        """A torque f(t) on ``body`` (counter-clockwise positive)."""
        self._register(law)
        return self._load("torque", name, body=_name(body), law=law.to_dict())

    def spring(
        self,
        body_a: Body | str,
        at_a: Sequence[float],
        body_b: Body | str,
        at_b: Sequence[float],
        stiffness: float,
        free_length: float | None = None,
        damping: float = 0.0,
        name: str | None = None,
    ) -> str:
        """A linear spring-damper between two points: tension k (L - free_length) + c dL/dt.
        ``free_length`` defaults to the distance at the start."""
        pa, pb = _xy(at_a), _xy(at_b)
        if free_length is None:
            free_length = math.dist(pa, pb)
        return self._load(
            "spring", name, body_a=_name(body_a), at_a=pa, body_b=_name(body_b), at_b=pb,
            stiffness=float(stiffness), free_length=float(free_length), damping=float(damping),
        )  # fmt: skip

    def torsion_spring(
        self,
        body_a: Body | str,
        body_b: Body | str,
        stiffness: float,
        free_angle: float | None = None,
        damping: float = 0.0,
        name: str | None = None,
    ) -> str:
        """A torsional spring-damper: torque on b of -(k (theta_b - theta_a - free_angle) +
        c (w_b - w_a)) and the opposite on a. ``free_angle`` defaults to the start's."""
        if free_angle is None:
            free_angle = self._theta(_name(body_b)) - self._theta(_name(body_a))
        return self._load(
            "torsion_spring", name, body_a=_name(body_a), body_b=_name(body_b),
            stiffness=float(stiffness), free_angle=float(free_angle), damping=float(damping),
        )  # fmt: skip

    def joint_force(
        self,
        joint: str,
        law: Law,
        of: str = "coordinate",
        name: str | None = None,
        of_joint: str | None = None,
    ) -> str:
        """A torque (revolute joint) or a force along the axis (prismatic joint) of magnitude
        law(x) between the joint's bodies, on body_b and its reaction on body_a; ``of``
        "coordinate" (x: theta_b - theta_a, or the slide from the start) or "rate" (x') of
        the joint ``of_joint``, a revolute or prismatic joint (default: ``joint`` itself; a
        piston's gas force of the crank angle: ``joint_force("cylinder", law,
        of_joint="main")``)."""
        if of not in ("coordinate", "rate"):
            raise InputError(f'joint_force: of must be "coordinate" or "rate", not {of!r}')
        if not isinstance(law, Law):
            raise InputError(
                f"joint_force: law must be a linkwork motion law (Spline, Linear...), not {law!r}"
            )
        self._register(law)
        read = {} if of_joint is None or str(of_joint) == str(joint) else {"of_joint": str(of_joint)}
        return self._load("joint_force", name, joint=str(joint), of=of, **read, law=law.to_dict())

    def motor(
        self, joint: str, stall: float, no_load_speed: float, name: str | None = None, clip: bool = False
    ) -> str:
        """A motor at a joint with the linear torque-speed curve
        f = stall (1 - rate / no_load_speed) (a force-speed curve at a prismatic joint). The
        line goes on beyond its ends (a DC motor driven past its no-load speed brakes,
        driven backwards it exceeds its stall torque); ``clip=True`` holds f between 0 and
        stall: no torque from the no-load speed on (a starter's overrunning clutch), stall
        torque at and below zero speed."""
        fields: dict[str, Any] = {"stall": float(stall), "no_load_speed": float(no_load_speed)}
        if clip:
            fields["clip"] = True
        return self._load("motor", name, joint=str(joint), **fields)

    def friction(
        self,
        joint: str,
        viscous: float = 0.0,
        coulomb: float = 0.0,
        smoothing: float | None = None,
        name: str | None = None,
    ) -> str:
        """Friction at a revolute or prismatic joint: f = -viscous rate - coulomb
        tanh(rate / smoothing), a constant Coulomb magnitude smoothed over rates of about
        ``smoothing`` (needed when ``coulomb`` > 0)."""
        fields: dict[str, Any] = {"viscous": float(viscous), "coulomb": float(coulomb)}
        if smoothing is not None:
            fields["smoothing"] = float(smoothing)
        return self._load("friction", name, joint=str(joint), **fields)

    def _theta(self, body: str) -> float:
        if body == GROUND:
            return 0.0
        for b in self._bodies:
            if b["name"] == body:
                return float(b["theta"])
        raise KeyError(f"no body named {body!r}")

    def _load(self, kind: str, name: str | None, **fields: Any) -> str:
        if name is None:
            used = {ld["name"] for ld in self._loads}
            k = 1
            while f"L{k}" in used:
                k += 1
            name = f"L{k}"
        self._loads.append({"type": kind, "name": str(name), **fields})
        return str(name)

    def remove(self, name: str) -> None:
        """Removes the joint, driver, point or load called ``name`` (to re-drive a mechanism, say)."""
        for group in (self._joints, self._drivers, self._points, self._loads):
            for k, item in enumerate(group):
                if item["name"] == name:
                    del group[k]
                    return
        raise KeyError(f"no joint, driver or point named {name!r}")

    # -- description ------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The model description shared by the engine and the reference (plain data)."""
        desc: dict[str, Any] = {"name": self.name}
        if self.units:
            desc["units"] = dict(self.units)
        if self.outputs:
            desc["outputs"] = list(self.outputs)
        if self.branch is not None:
            desc["branch"] = self.branch if isinstance(self.branch, str) else dict(self.branch)
        if self.close is not None:
            desc["close"] = self.close
        if self.free:
            desc["free"] = True
        if self.initial_rates:
            desc["initial_rates"] = {str(k): float(v) for k, v in self.initial_rates.items()}
        return desc | {
            "bodies": [dict(b) for b in self._bodies],
            "joints": [dict(j) for j in self._joints],
            "drivers": [dict(d) for d in self._drivers],
            "points": [dict(p) for p in self._points],
            "gravity": list(self.gravity),
            "loads": [dict(ld) for ld in self._loads],
        }

    @classmethod
    def from_dict(cls, desc: dict[str, Any]) -> Mechanism:
        """A mechanism from its description (``to_dict``'s inverse)."""
        from .. import _args

        desc = _args.mapping(desc, "desc")
        for key in ("bodies", "joints", "drivers", "points", "loads"):
            _args.each(desc.get(key, []), key, lambda item, name: _args.mapping(item, name))
        g = desc.get("gravity", (0.0, 0.0))
        if not (isinstance(g, (list, tuple)) and len(g) == 2):
            raise InputError(f"gravity must be a pair of numbers (gx, gy), not {g!r}")
        g = (_args.number(g[0], "gravity[0]"), _args.number(g[1], "gravity[1]"))
        m = cls(str(desc.get("name", "mechanism")))
        m._bodies = [dict(b) for b in desc.get("bodies", [])]
        m._joints = [dict(j) for j in desc.get("joints", [])]
        m._drivers = [dict(d) for d in desc.get("drivers", [])]
        m._points = [dict(p) for p in desc.get("points", [])]
        m._loads = [dict(ld) for ld in desc.get("loads", [])]
        m.gravity = g
        units = desc.get("units")
        m.units = dict(units) if units else None
        m.branch = desc.get("branch")
        m.close = desc.get("close")
        m.free = bool(desc.get("free", False))
        rates = desc.get("initial_rates") or {}
        m.initial_rates = {str(k): _args.number(v, f"initial_rates[{k!r}]") for k, v in dict(rates).items()}
        outputs = desc.get("outputs")
        if outputs is not None:
            if isinstance(outputs, str) or not all(isinstance(o, str) for o in outputs):
                raise InputError(f"outputs must be a list of names, not {outputs!r}")
            m.outputs = list(outputs) or None
        return m

    # -- model files (files.py) ---------------------------------------------------------
    def save(self, path: str | os.PathLike[str]) -> None:
        """Writes the mechanism as a model file: TOML if ``path`` ends in ``.toml``, JSON if
        in ``.json`` (docs/model-format.md). ``load`` reads back an equal description:
        same keys, same numbers. A mechanism driven by a `PythonLaw` cannot be saved: a
        file cannot hold a Python function."""
        files.save(self.to_dict(), path)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> Mechanism:
        """Reads a model file, TOML (``.toml``) or JSON (``.json``), written by ``save``
        or by hand. A bad file raises `ModelError` naming the file, line, column and field;
        errors found later by ``compile`` name the element and its line in the file.
        JSON written before format versions existed reads as version 1, metres, radians."""
        text, fmt = files.read_text(path)
        m = cls._read(text, fmt, os.fspath(path))
        m.units_declared, m.units_warning = files.units_check(m.to_dict(), text, fmt, os.fspath(path))
        return m

    @classmethod
    def from_toml(cls, text: str, file: str = "model.toml") -> Mechanism:
        """A mechanism from the text of a TOML model file (``file`` names it in errors).

        >>> import linkwork as lw
        >>> m = lw.Mechanism.from_toml(lw.examples.four_bar().to_toml())
        >>> m.to_dict() == lw.examples.four_bar().to_dict()
        True
        """
        return cls._read(text, "toml", file)

    def to_toml(self) -> str:
        """The mechanism as the text of a TOML model file."""
        return files.write(self.to_dict(), "toml")

    #: set by ``load``: whether the file declared its units, and a warning if it did not
    #: and its numbers look like millimetres or degrees (``None`` when there is nothing to say)
    units_declared: bool = True
    units_warning: str | None = None

    @classmethod
    def _read(cls, text: str, fmt: str, file: str) -> Mechanism:
        desc, lines = files.parse(text, fmt, file)
        m = cls.from_dict(desc)
        m._source = (file, lines)
        return m

    def is_drawn(self) -> bool:
        """Whether every joint is placed in the drawing (no revolute or prismatic given only
        by its pins in the bodies' frames, which `assemble` places)."""
        return all("at" in j for j in self._joints if j.get("type") in PINNED)

    def assemble(self, t: float = 0.0, branch: str | dict[str, str] | None = None) -> Mechanism:
        """The mechanism drawn: its bodies at the configuration the engine assembles at
        time ``t`` from the joints' pins (on ``branch``'s assembly mode, default
        `Mechanism.branch`: "open", "crossed" or {linkage: circuit}; else the one nearest
        the bodies' rough poses), each revolute at its world point, each slide through
        its ``pin_b`` (its pins kept: its slide is still measured from them), every named
        point and joint point carried with its body. Lengths are the pins' exactly; a
        joint that cannot close is an `AssemblyError` naming it. A copy is returned; a
        drawn mechanism comes back unchanged (compiling it checks that any pins it also
        gives meet their drawn points: `close`).

        >>> from linkwork import Linear
        >>> m = Mechanism("four-bar")
        >>> crank, coupler, rocker = m.body("crank"), m.body("coupler"), m.body("rocker")
        >>> _ = m.revolute(m.ground, crank, pin_a=(0, 0), pin_b=(0, 0))
        >>> _ = m.revolute(crank, coupler, pin_a=(0.2, 0), pin_b=(0, 0))
        >>> _ = m.revolute(coupler, rocker, pin_a=(0.35, 0), pin_b=(0.25, 0))
        >>> _ = m.revolute(rocker, m.ground, pin_a=(0, 0), pin_b=(0.35, 0))
        >>> _ = m.drive_angle(crank, Linear(0.0, 5.0))
        >>> drawn = m.assemble(branch="open")
        >>> [round(v, 6) for v in drawn.to_dict()["joints"][2]["at"]]
        [0.475, 0.216506]
        """
        if self.is_drawn():
            return self
        t = _args.number(t, "t")
        desc = assembly.drawn(self.to_dict(), self.python_laws, t, self.branch if branch is None else branch)
        drawn = Mechanism.from_dict(desc)
        drawn._python_laws = dict(self._python_laws)
        return drawn

    def compile(self, **options: Any) -> Model:
        """Validate and compile into an engine model (raises ``ModelError``; for a
        mechanism read from a file, the message gives the line of the element at fault).
        A mechanism given by its joints' pins is drawn first (`assemble`; `Model` does the
        same)."""
        try:
            return Model(self, **options)
        except ModelError as e:
            element = getattr(e, "element", None)
            line = self._source[1].get(tuple(element)) if self._source and element else None
            if line is None:
                raise
            # the same kind of error (a ClosureError stays one), its attributes kept
            located = type(e)(f"{self._source[0]}: line {line}: {e}")
            located.__dict__.update(e.__dict__)
            raise located from None

    # -- what a notebook shows ----------------------------------------------------------
    def draw(self, ax: Any = None, t: float = 0.0) -> Any:
        """Draws the mechanism assembled at time ``t`` on matplotlib axes ``ax`` (default: a
        new figure) and returns the axes; a mechanism that cannot be assembled yet is drawn
        as described, its title saying why."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.notebook import draw_mechanism

        return draw_mechanism(self, ax, t)

    def _repr_png_(self) -> bytes:
        """The drawing a notebook shows (PNG)."""
        # declared lazy import, upward: a convenience method of the view
        from ..view.notebook import mechanism_png

        return mechanism_png(self)


def _checked(method: Callable[..., Any]) -> Callable[..., Any]:
    """A builder method whose argument conversions (float(...) of a name, a pair that is
    not one) raise the project's InputError naming the method, not a bare TypeError."""

    @functools.wraps(method)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return method(*args, **kwargs)
        except LinkworkError:
            raise
        except (TypeError, ValueError, OverflowError) as e:
            raise InputError(f"Mechanism.{method.__name__}: {e}") from None

    return wrapper


for _attr, _value in list(vars(Mechanism).items()):
    if not _attr.startswith("_") and inspect.isfunction(_value):
        setattr(Mechanism, _attr, _checked(_value))

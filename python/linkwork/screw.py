"""Screw theory for planar mechanisms: twists, wrenches, join and meet, serial arms,
instant centres and the singularities of closed loops.

Conventions (world frame; every screw is a NumPy array of 3):

- a **twist** ``T = (vx, vy, w)`` is the velocity of the body point at the world origin and
  the angular rate, so the point p moves at ``(vx - w p_y, vy + w p_x)``;
- the **axis screw** of a revolute joint at ``(x, y)`` with unit rate is ``(y, -x, 1)``; a
  prismatic joint along the unit direction ``(ux, uy)`` is ``(ux, uy, 0)``;
- a **wrench** ``W = (fx, fy, m)`` is a force and its moment about the world origin; the
  **line screw** of a unit force at angle t through ``(x, y)`` is
  ``(cos t, sin t, x sin t - y cos t)``;
- the **reciprocal product** (virtual power) is ``W . T = fx vx + fy vy + m w``;
- **points** and **lines** are homogeneous: ``(X, Y, W)`` is the point ``(X/W, Y/W)``, or
  the direction ``(X, Y)`` at infinity when ``W = 0``. A twist's pole (the point that
  does not move) is ``(-vy, vx, w)``; a wrench's line of action is ``(-fy, fx, m)``.

Everything but the one-line formulas runs in the Rust engine (``linkwork._core``), with
degeneracy tests scaled by the problem's length; a degenerate question raises
`ScrewError` naming the joints at fault.

>>> import numpy as np
>>> from linkwork import screw
>>> screw.revolute((2.0, 1.0)).tolist()              # (y, -x, 1)
[1.0, -2.0, 1.0]
>>> T = 0.5 * screw.revolute((2.0, 1.0))
>>> screw.velocity_at(T, (2.0, 1.0)).tolist()        # the pivot does not move
[0.0, 0.0]
>>> W = screw.line_screw(np.pi / 2, (3.0, 0.0))      # unit force along +y through (3, 0)
>>> round(float(screw.reciprocal(W, T)), 12)         # its power on T: f . v at (3, 0)
0.5
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Union

import numpy as np

from . import _core

__all__ = [
    "revolute",
    "prismatic",
    "line_screw",
    "force",
    "couple",
    "reciprocal",
    "velocity_at",
    "body_twist",
    "pole",
    "line_of",
    "normalize",
    "join",
    "meet",
    "twist_to_world",
    "twist_to_local",
    "wrench_to_world",
    "wrench_to_local",
    "SerialArm",
    "ArmState",
    "Barycentre",
    "Centres",
    "LoopSingularity",
    "instant_centres",
    "kennedy_centres",
    "loop_singularity",
]

ArrayLike = Union[Sequence[float], np.ndarray]


def _vec(v: ArrayLike, n: int, what: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    if a.shape[-1:] != (n,):
        raise ValueError(f"{what} must have {n} components in its last axis, got shape {a.shape}")
    return a


def _t3(v: ArrayLike, what: str) -> tuple[float, float, float]:
    a = _vec(v, 3, what)
    if a.ndim != 1:
        raise ValueError(f"{what} must be one vector of 3, got shape {a.shape}")
    return (float(a[0]), float(a[1]), float(a[2]))


def _point3(p: ArrayLike) -> tuple[float, float, float]:
    """A point given as (x, y) or homogeneous (X, Y, W)."""
    a = np.asarray(p, dtype=np.float64)
    if a.shape == (2,):
        return (float(a[0]), float(a[1]), 1.0)
    return _t3(a, "a point")


def _f64(v: ArrayLike, what: str) -> np.ndarray:
    a = np.ascontiguousarray(v, dtype=np.float64)
    if a.ndim != 1:
        raise ValueError(f"{what} must be one-dimensional, got shape {a.shape}")
    return a


# -- elements -------------------------------------------------------------------------


def revolute(at: ArrayLike) -> np.ndarray:
    """The axis screw of a revolute joint at ``at``, unit rate: ``(y, -x, 1)``.

    >>> revolute((1.0, 0.0)).tolist()
    [0.0, -1.0, 1.0]
    """
    p = _vec(at, 2, "at")
    return np.stack([p[..., 1], -p[..., 0], np.ones_like(p[..., 0])], axis=-1)


def prismatic(direction: ArrayLike) -> np.ndarray:
    """The screw of a prismatic joint along ``direction`` (normalised), unit rate: ``(ux, uy, 0)``.

    >>> prismatic((0.0, 2.0)).tolist()
    [0.0, 1.0, 0.0]
    """
    d = _vec(direction, 2, "direction")
    n = np.hypot(d[..., 0], d[..., 1])
    if np.any(n == 0) or not np.all(np.isfinite(n)):
        raise ValueError("a slide direction must be finite and non-zero")
    return np.stack([d[..., 0] / n, d[..., 1] / n, np.zeros_like(n)], axis=-1)


def line_screw(angle: float | np.ndarray, through: ArrayLike) -> np.ndarray:
    """The line screw of a unit force at ``angle`` (rad) through ``through``:
    ``(cos t, sin t, x sin t - y cos t)``.

    >>> np.round(line_screw(0.0, (0.0, 2.0)), 12).tolist()    # along +x, 2 above the origin
    [1.0, 0.0, -2.0]
    """
    p = _vec(through, 2, "through")
    c, s = np.cos(angle), np.sin(angle)
    return np.stack(np.broadcast_arrays(c, s, p[..., 0] * s - p[..., 1] * c), axis=-1)


def force(f: ArrayLike, at: ArrayLike) -> np.ndarray:
    """The wrench of the force ``f`` acting at ``at``: ``(fx, fy, x fy - y fx)``.

    >>> force((0.0, -10.0), (2.0, 0.0)).tolist()
    [0.0, -10.0, -20.0]
    """
    fv, p = _vec(f, 2, "f"), _vec(at, 2, "at")
    m = p[..., 0] * fv[..., 1] - p[..., 1] * fv[..., 0]
    return np.stack(np.broadcast_arrays(fv[..., 0], fv[..., 1], m), axis=-1)


def couple(m: float) -> np.ndarray:
    """A pure couple: the wrench ``(0, 0, m)`` (the line screw of the line at infinity)."""
    return np.array([0.0, 0.0, float(m)])


def reciprocal(wrench: ArrayLike, twist: ArrayLike) -> np.ndarray:
    """The reciprocal product ``W . T = fx vx + fy vy + m w``: the power of the wrench on the
    twist (zero when the force line passes through the twist's pole)."""
    return np.sum(_vec(wrench, 3, "wrench") * _vec(twist, 3, "twist"), axis=-1)


def velocity_at(twist: ArrayLike, point: ArrayLike) -> np.ndarray:
    """The velocity ``(vx - w y, vy + w x)`` of the body point at ``point``."""
    t, p = _vec(twist, 3, "twist"), _vec(point, 2, "point")
    return np.stack([t[..., 0] - t[..., 2] * p[..., 1], t[..., 1] + t[..., 2] * p[..., 0]], axis=-1)


def body_twist(pose: ArrayLike, rate: ArrayLike) -> np.ndarray:
    """The twist of a body at pose ``(x, y, theta)`` moving at ``(xd, yd, thetad)``:
    ``(xd + thetad y, yd - thetad x, thetad)``.

    >>> body_twist((1.0, 0.0, 0.0), (0.0, 2.0, 2.0)).tolist()   # turning about the origin
    [0.0, 0.0, 2.0]
    """
    q, r = _vec(pose, 3, "pose"), _vec(rate, 3, "rate")
    return np.stack(
        [r[..., 0] + r[..., 2] * q[..., 1], r[..., 1] - r[..., 2] * q[..., 0], r[..., 2]], axis=-1
    )


def pole(twist: ArrayLike) -> np.ndarray:
    """The twist's pole as the homogeneous point ``(-vy, vx, w)`` (weighted by the rate; at
    infinity for a translation). ``normalize`` turns it into ``(x, y, 1)``.

    >>> pole(3.0 * revolute((1.0, 2.0))).tolist()
    [3.0, 6.0, 3.0]
    """
    t = _vec(twist, 3, "twist")
    return np.stack([-t[..., 1], t[..., 0], t[..., 2]], axis=-1)


def line_of(wrench: ArrayLike) -> np.ndarray:
    """The wrench's line of action ``(-fy, fx, m)``: ``a x + b y + c`` at a point is the
    wrench's moment about it."""
    w = _vec(wrench, 3, "wrench")
    return np.stack([-w[..., 1], w[..., 0], w[..., 2]], axis=-1)


def normalize(point: ArrayLike, centre: ArrayLike = (0.0, 0.0), scale: float = 1.0) -> np.ndarray:
    """A homogeneous point as ``(x, y, 1)``, or as a unit direction ``(dx, dy, 0)`` when it is
    at infinity (judged in the gauge ``centre``, ``scale``).

    >>> normalize((2.0, 4.0, 2.0)).tolist()
    [1.0, 2.0, 1.0]
    """
    c = _vec(centre, 2, "centre")
    return np.array(_core.screw_normalize(_point3(point), (float(c[0]), float(c[1])), float(scale)))


def _unit_wrench(line: np.ndarray) -> np.ndarray:
    w = np.array([line[1], -line[0], line[2]])
    f = float(np.hypot(w[0], w[1]))
    return w / f if f > 1e-12 * abs(w[2]) else np.array([0.0, 0.0, float(np.sign(w[2]))])


def join(p: ArrayLike, q: ArrayLike) -> np.ndarray:
    """The line through two points (``(x, y)`` or homogeneous) as a unit line screw: a unit
    force from p towards q (a unit couple for the line at infinity). Raises `ScrewError`
    when the points coincide.

    >>> (np.round(join((0.0, 1.0), (2.0, 1.0)), 12) + 0.0).tolist()   # along +x through y = 1
    [1.0, 0.0, -1.0]
    >>> (np.round(join((1.0, 0.0), (0.0, 1.0, 0.0)), 12) + 0.0).tolist()  # towards +y at infinity
    [0.0, 1.0, 1.0]
    """
    return _unit_wrench(np.array(_core.screw_join(_point3(p), _point3(q))))


def meet(s1: ArrayLike, s2: ArrayLike) -> np.ndarray:
    """The point where the lines of action of two wrenches (line screws) cross, normalised:
    ``(x, y, 1)``, or ``(dx, dy, 0)`` at infinity for parallel lines. Raises `ScrewError`
    when the lines coincide.

    >>> np.round(meet(line_screw(0.0, (0, 1)), line_screw(np.pi / 2, (3, 0))), 12).tolist()
    [3.0, 1.0, 1.0]
    >>> np.round(np.abs(meet(line_screw(0.3, (0, 0)), line_screw(0.3, (0, 1)))), 6).tolist()
    [0.955336, 0.29552, 0.0]
    """
    return np.array(_core.screw_meet(tuple(line_of(_t3(s1, "s1"))), tuple(line_of(_t3(s2, "s2")))))


def _transport(kind: str, to: str, v: ArrayLike, pose: ArrayLike) -> np.ndarray:
    return np.array(_core.screw_transport(kind, to, _t3(pose, "pose"), _t3(v, kind)))


def twist_to_world(twist: ArrayLike, pose: ArrayLike) -> np.ndarray:
    """A twist given in the frame at ``pose`` = (x, y, theta) (its (vx, vy) the velocity of
    the frame's origin, in the frame's axes) expressed in the world."""
    return _transport("twist", "world", twist, pose)


def twist_to_local(twist: ArrayLike, pose: ArrayLike) -> np.ndarray:
    """A world twist expressed in the frame at ``pose``.

    >>> T = revolute((1.0, 1.0))                      # turning about (1, 1)
    >>> np.round(twist_to_local(T, (1.0, 1.0, 0.3)), 12).tolist()   # the frame origin is still
    [0.0, 0.0, 1.0]
    """
    return _transport("twist", "local", twist, pose)


def wrench_to_world(wrench: ArrayLike, pose: ArrayLike) -> np.ndarray:
    """A wrench given in the frame at ``pose`` (moment about the frame's origin) in the world."""
    return _transport("wrench", "world", wrench, pose)


def wrench_to_local(wrench: ArrayLike, pose: ArrayLike) -> np.ndarray:
    """A world wrench expressed in the frame at ``pose``; the reciprocal product is the same
    in both frames."""
    return _transport("wrench", "local", wrench, pose)


# -- serial arms ----------------------------------------------------------------------


@dataclass(frozen=True)
class Barycentre:
    """The barycentre construction of an inverse velocity.

    ``rates`` (n,); ``pole`` (3,) the pole of the twist left to the unknown joints
    (homogeneous, weight = its angular rate); with three unknowns, ``vertex`` (a joint
    index a) and ``foot`` (3,): the line from joint a through the pole meets the line
    through the other two unknown joints at the foot D. The pole divides a-D and D divides
    the other two in the inverse ratio of the rates.
    """

    rates: np.ndarray
    pole: np.ndarray
    vertex: int | None
    foot: np.ndarray | None


class ArmState:
    """A serial arm at one configuration (``SerialArm.forward(q)``): joint axes, the screw
    Jacobian, the end pose, and the velocity and force questions answered with screws.

    >>> arm = SerialArm.from_lengths([1.0, 0.8, 0.5])
    >>> st = arm.forward(np.radians([30.0, 45.0, -60.0]))
    >>> w = [1.0, -0.5, 2.0]
    >>> np.round(st.inverse_velocity(st.twist(w)), 12).tolist()
    [1.0, -0.5, 2.0]
    """

    def __init__(self, core: Any) -> None:
        self._core = core

    names = property(lambda self: self._core.names, doc="Joint names.")
    kinds = property(lambda self: self._core.kinds, doc="'R' or 'P' per joint, as one string.")
    q = property(lambda self: self._core.q, doc="Joint values (n,).")
    points = property(lambda self: self._core.points, doc="Joint axes as homogeneous points (n, 3).")
    positions = property(lambda self: self._core.positions, doc="Joint positions (n, 2).")
    axes = property(lambda self: self._core.axes, doc="Slide directions (n, 2).")
    jacobian = property(lambda self: self._core.jacobian, doc="The screw Jacobian J = [$_1 ... $_n] (3, n).")
    gauge = property(lambda self: self._core.gauge, doc="(centre, length scale) of the degeneracy tests.")

    @property
    def n_joints(self) -> int:
        return len(self.names)

    @property
    def end(self) -> np.ndarray:
        """The end frame's pose (x, y, theta)."""
        return np.array(self._core.end)

    @property
    def end_point(self) -> np.ndarray:
        """The end point (2,): the end frame's origin."""
        return self.end[:2]

    def _w(self, w: ArrayLike, what: str = "w") -> np.ndarray:
        return _f64(w, what)

    def twist(self, w: ArrayLike) -> np.ndarray:
        """Forward velocity: the end link's twist ``T = J w`` (3,)."""
        return np.array(self._core.twist(self._w(w)))

    def pole(self, w: ArrayLike) -> np.ndarray:
        """The velocity pole: the barycentre of the joint axes with weights ``w``, as
        ``(x, y, 1)`` (or a unit direction at infinity for a pure translation)."""
        c, s = self.gauge
        return normalize(self._core.pole(self._w(w)), c, s)

    def end_velocity(self, w: ArrayLike) -> np.ndarray:
        """The end point's velocity (2,)."""
        return np.array(self._core.end_velocity(self._w(w)))

    def joint_velocities(self, w: ArrayLike, point: ArrayLike | None = None) -> np.ndarray:
        """Each joint's share of the velocity of ``point`` (default: the end point), (n, 2):
        ``w_i $_i`` evaluated there. The rows add up to the point's velocity."""
        p = self.end_point if point is None else _vec(point, 2, "point")
        w = self._w(w)
        return velocity_at(self.jacobian.T * w[:, None], p)

    def velocity_centres(self, w: ArrayLike) -> dict[tuple[int, int], np.ndarray]:
        """For every pair of joints (j, k): the pole of their motion alone at rates
        ``(w_j, w_k)``, the barycentre ``w_j P_j + w_k P_k`` (homogeneous, (3,))."""
        pairs, pts = self._core.velocity_centres(self._w(w))
        return {tuple(p): pts[i] for i, p in enumerate(pairs)}

    def _given(self, given: Mapping[int | str, float] | None) -> list[tuple[int, float]] | None:
        if not given:
            return None
        out = []
        for k, v in given.items():
            i = self.names.index(k) if isinstance(k, str) else int(k)
            out.append((i, float(v)))
        return out

    def inverse_velocity(
        self, twist: ArrayLike, given: Mapping[int | str, float] | None = None
    ) -> np.ndarray:
        """Inverse velocity by the line-screw formula ``w_i = S_jk . T / S_jk . $_i``, with
        ``S_jk`` the line through the other two unknown joints. ``given`` fixes the rates
        of some joints (index or name -> rate); at most three rates may be unknown (with
        fewer, the twist must be one they can produce)."""
        return self._core.inverse_velocity(_t3(twist, "twist"), self._given(given))

    def barycentre(self, twist: ArrayLike, given: Mapping[int | str, float] | None = None) -> Barycentre:
        """Inverse velocity by the barycentre construction (see `Barycentre`)."""
        rates, p, vertex, foot = self._core.inverse_velocity_barycentre(
            _t3(twist, "twist"), self._given(given)
        )
        return Barycentre(rates, np.array(p), vertex, None if foot is None else np.array(foot))

    def line_screws(self, unknown: Sequence[int] = (0, 1, 2)) -> np.ndarray:
        """The unit line screws (3, 3), one per row, of the line-screw formula for the three
        ``unknown`` joints: row i passes through the axes of the other two."""
        a, b, c = (int(i) for i in unknown)
        return self._core.line_screws((a, b, c))

    def torques(self, wrench: ArrayLike) -> np.ndarray:
        """Inverse force: ``tau = J^T W`` (n,), the moment of the end wrench about each pivot
        (its component along each slide)."""
        return self._core.torques(_t3(wrench, "wrench"))

    def lever_arms(self, wrench: ArrayLike) -> np.ndarray:
        """``tau_i / |f|`` (n,): for a pivot the signed perpendicular distance p_i from the
        pivot to the force line (``tau_i = |f| p_i``); for a slide the direction cosine."""
        return self._core.lever_arms(_t3(wrench, "wrench"))

    def torque_centres(self, tau: ArrayLike) -> dict[tuple[int, int], np.ndarray]:
        """For every pair of joints (j, k): the torque centre ``tau_k P_j - tau_j P_k``
        (homogeneous, (3,)), the point on the line through their axes about which the end
        force has no moment. It equals the velocity centre of the pair at rates
        ``(tau_k, -tau_j)``, the motion of the pair that does no work."""
        pairs, pts = self._core.torque_centres(_f64(tau, "tau"))
        return {tuple(p): pts[i] for i, p in enumerate(pairs)}

    def force(self, tau: ArrayLike, through: ArrayLike | None = None) -> np.ndarray:
        """Forward force: the end wrench (3,) the joint torques ``tau`` produce, as the line
        through the torque centres, scaled so that ``J^T W = tau``. A two-joint arm needs
        the point ``through`` which the force passes (default: the end point)."""
        t = None if through is None else tuple(float(v) for v in _vec(through, 2, "through"))
        return np.array(self._core.force(_f64(tau, "tau"), t))

    def dependencies(self) -> list[tuple[str, ...]]:
        """Minimal sets of joints whose screws are dependent (coincident pivots, parallel
        slides, collinear axes): where the arm loses a direction of motion."""
        return [tuple(self.names[i] for i in s) for s in self._core.dependencies()]

    def __repr__(self) -> str:
        return (
            f"<ArmState {self.kinds} q={np.round(self.q, 6).tolist()} end={np.round(self.end, 6).tolist()}>"
        )


class SerialArm:
    """A serial planar arm of revolute ('R') and prismatic ('P') joints, described in its
    home configuration (joint values zero). Forward kinematics is the product of
    exponentials: joint i turns (or slides) everything after it about its current axis.

    ``joints``: a list of ``(name, "R", (x, y))`` and ``(name, "P", (x, y), (ux, uy))``;
    ``end``: the home pose (x, y, theta) of the end frame, whose origin is the end point.

    >>> arm = SerialArm([("A", "R", (0, 0)), ("B", "P", (1, 0), (1, 0))], end=(1.5, 0, 0))
    >>> arm.forward([np.pi / 2, 0.25]).end_point.round(12).tolist()
    [0.0, 1.75]
    """

    def __init__(self, joints: Sequence[Sequence[Any]], end: ArrayLike) -> None:
        spec = []
        for j in joints:
            name, kind, at = str(j[0]), str(j[1]).upper(), _vec(j[2], 2, "joint position")
            axis = _vec(j[3], 2, "slide direction") if len(j) > 3 else np.array([1.0, 0.0])
            spec.append((name, kind, (float(at[0]), float(at[1])), (float(axis[0]), float(axis[1]))))
        self._init(_core.SerialArm(spec, _t3(end, "end")))

    def _init(self, core: Any) -> None:
        self._core = core

    @classmethod
    def _wrap(cls, core: Any) -> SerialArm:
        arm = cls.__new__(cls)
        arm._init(core)
        return arm

    @classmethod
    def from_lengths(cls, lengths: ArrayLike, kinds: str | None = None) -> SerialArm:
        """An arm from its link lengths: joint i at the start of link i, all links along x in
        the home configuration, so revolute values are the relative joint angles (0 =
        straight) and a prismatic joint lengthens its link. ``kinds``: e.g. "RPR" (default
        all revolute). Joints are named "1", "2", ...

        >>> st = SerialArm.from_lengths([1.0, 1.0]).forward([0.0, np.pi / 2])
        >>> st.end_point.round(12).tolist()
        [1.0, 1.0]
        """
        ls = [float(v) for v in np.asarray(lengths, dtype=np.float64).ravel()]
        return cls._wrap(_core.SerialArm.from_links(kinds if kinds is not None else "R" * len(ls), ls))

    @classmethod
    def from_model(cls, model: Any, end_point: str | None = None) -> SerialArm:
        """The serial chain ground - body - ... of a linkwork `Model` or `Mechanism` (joined
        by revolute and prismatic joints; drivers are ignored). Home = the described
        starting configuration; a joint's value is the outer body's angle relative to the
        inner one, or its slide, since the start. ``end_point``: a named point on the last
        body (default: its frame origin)."""
        desc = model.description if hasattr(model, "description") else model.to_dict()
        return cls._wrap(_core.SerialArm.from_description(json.dumps(desc), end_point))

    names = property(lambda self: self._core.names, doc="Joint names.")
    kinds = property(lambda self: self._core.kinds, doc="'R' or 'P' per joint, as one string.")
    home_positions = property(lambda self: self._core.home_positions, doc="Home joint positions (n, 2).")
    home_axes = property(lambda self: self._core.home_axes, doc="Home slide directions (n, 2).")
    end_home = property(lambda self: np.array(self._core.end_home), doc="Home pose of the end frame.")

    @property
    def n_joints(self) -> int:
        return len(self.names)

    def forward(self, q: ArrayLike) -> ArmState:
        """Forward kinematics at joint values ``q`` (n,): an `ArmState`."""
        return ArmState(self._core.forward(_f64(q, "q")))

    def joint_values(self, state: Any, step: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """For an arm from ``from_model``: the arm's joint values and rates (q, w) at a
        model `State` (or `Results` row ``step``)."""
        q, qd = _coords(state, step)
        return self._core.joint_values(q, qd)

    def model_end(self, state: Any, step: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """For an arm from ``from_model``: the end frame's pose and twist computed from the
        model's own coordinates and velocities (to check the arm against the engine)."""
        q, qd = _coords(state, step)
        pose, twist = self._core.model_end(q, qd)
        return np.array(pose), twist

    def __repr__(self) -> str:
        return repr(self._core)


# -- closed mechanisms ------------------------------------------------------------------


def _coords(state: Any, step: int | None) -> tuple[np.ndarray, np.ndarray]:
    """(q, qd) of a State, of a Results row, or of a Model as drawn (qd = 0)."""
    if not hasattr(state, "q") and hasattr(state, "q_start"):
        q = np.asarray(state.q_start, dtype=np.float64)
        return np.ascontiguousarray(q), np.zeros_like(q)
    q, qd = np.asarray(state.q, dtype=np.float64), np.asarray(state.qd, dtype=np.float64)
    if q.ndim == 2:
        if step is None:
            raise ValueError("a Results holds many steps: say which with step=")
        q, qd = q[step], qd[step]
    return np.ascontiguousarray(q), np.ascontiguousarray(qd)


def _description(state: Any) -> str:
    model = state if hasattr(state, "description") else state.model
    return json.dumps(model.description)


@dataclass(frozen=True)
class Centres:
    """The instant centre of every pair of bodies ("ground" first).

    ``points[(a, b)]`` is the centre of bodies a and b (names, in body order) as
    ``(x, y, 1)``, or ``(dx, dy, 0)`` at infinity, or None where there is none (the two
    bodies do not move relative to each other) or none was found. ``kennedy`` is the
    largest departure from Kennedy's theorem (``|det|`` of three normalised centres,
    0 = collinear) over all triples of bodies, with that triple.
    """

    bodies: list[str]
    points: dict[tuple[str, str], np.ndarray | None]
    kennedy: tuple[float, tuple[str, str, str]] | None
    gauge: tuple[tuple[float, float], float]

    def centre(self, a: str, b: str) -> np.ndarray | None:
        """The centre of bodies a and b (either order)."""
        if (a, b) in self.points:
            return self.points[(a, b)]
        if (b, a) in self.points:
            return self.points[(b, a)]
        raise KeyError(f"no bodies {a!r} and {b!r}; bodies: {', '.join(self.bodies)}")

    def table(self) -> str:
        """One line per pair: the centre, or the direction at infinity."""
        lines = []
        for (a, b), p in self.points.items():
            if p is None:
                where = "none"
            elif p[2] == 0.0:
                where = f"at infinity, direction ({p[0]:+.4f}, {p[1]:+.4f})"
            else:
                where = f"({p[0]:+.6f}, {p[1]:+.6f})"
            lines.append(f"  {a + '-' + b:<24}{where}")
        return "\n".join(lines)


def _centres(raw: dict[str, Any]) -> Centres:
    names = raw["bodies"]
    pts = {(names[i], names[j]): (None if p is None else np.array(p)) for i, j, p in raw["pairs"]}
    k = raw["kennedy"]
    kennedy = None if k is None else (k[0], tuple(names[i] for i in k[1]))
    return Centres(names, pts, kennedy, raw["gauge"])  # type: ignore[arg-type]


def instant_centres(state: Any, step: int | None = None) -> Centres:
    """Instant centres of every pair of bodies from the velocities the engine computed: the
    poles of the relative twists ``T_b - T_a``, body twists from (x, y, theta) and their
    rates. ``state``: a `State` (``model.solve(t)``) or a `Results` with ``step``.

    >>> import linkwork as lw
    >>> st = lw.examples.four_bar().compile().solve(0.1)
    >>> c = instant_centres(st)
    >>> (c.centre("ground", "crank").round(12) + 0.0).tolist()   # the pivot O2
    [0.0, 0.0, 1.0]
    >>> c.kennedy[0] < 1e-12                                  # three centres on one line
    True
    """
    q, qd = _coords(state, step)
    return _centres(_core.screw_centres_from_velocities(_description(state), q, qd))


def kennedy_centres(state: Any, step: int | None = None) -> Centres:
    """Instant centres from the geometry alone: each joint gives the centre of its two bodies
    (the pivot; the point at infinity across a slide), and Kennedy's theorem (the centre of
    a and b is on the line through the centres ak and bk, for every other body k) finds the
    rest as meets of such lines. Pairs it cannot reach are None. ``state`` may also be a
    `Model`: its drawn configuration."""
    q, _ = _coords(state, step)
    return _centres(_core.screw_centres_by_kennedy(_description(state), q))


@dataclass(frozen=True)
class LoopSingularity:
    """The loop screws of a closed mechanism at one configuration.

    ``joints``: the passive joints (not locked by a driver); ``locked``: the driven ones;
    ``loops``: the joints of every independent loop; ``singular_values`` of the loop
    matrix (columns scaled to unit length); ``rank``; ``singular``: the passive joints'
    screws have collapsed (rank < number of passive joints), so they can move with the
    drivers held, or cannot follow them; ``involved``: the joints of that null motion;
    ``dependent``: minimal dependent sets (coincident pivots, collinear pivots, ...) in
    each loop.
    """

    joints: list[str]
    locked: list[str]
    loops: list[list[str]]
    singular_values: np.ndarray
    rank: int
    singular: bool
    involved: list[str]
    dependent: list[list[str]]


def loop_singularity(state: Any, step: int | None = None, tol: float = 1e-9) -> LoopSingularity:
    """Screw analysis of a closed mechanism's loops at a `State` (or `Results` row): around
    every loop the joints' relative twists add up to zero; with the driven joints locked,
    the passive joints' screws must stay independent. ``tol``: singular values below
    ``tol`` times the largest count as zero. ``state`` may also be a `Model`: its drawn
    configuration, which the engine may be unable to solve at (a dead point).

    >>> import linkwork as lw
    >>> s = loop_singularity(lw.examples.four_bar().compile().solve(0.0))
    >>> s.locked, s.joints, s.singular
    (['O2'], ['A', 'B', 'O4'], False)
    """
    q, _ = _coords(state, step)
    raw = _core.screw_loop_singularity(_description(state), q, float(tol))
    return LoopSingularity(**raw)

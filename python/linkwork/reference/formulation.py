"""The constraint formulation in absolute coordinates, written out joint by joint.

Every moving body i has q_i = (x_i, y_i, theta_i). A point fixed in body i is
r = R_i + A(theta_i) u, with A the 2x2 rotation and u the point's local vector, taken
from the body's starting pose: u = A(theta_0)^T (P_world - R_0). The ground is the
identity frame and has no coordinates.

Each joint or driver below is a small class that, given the poses (and rates) of its
two bodies, returns
- ``phi``: its residual rows,
- ``jacobian``: one (n_rows x 3) block per body, columns (x, y, theta),
- ``nu``: the right-hand side of Phi_q qd = nu (-Phi_t),
- ``gamma``: the right-hand side of Phi_q qdd = gamma, in closed form.
Nothing here knows global row or column numbers; ``ReferenceModel`` places the blocks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from . import curves
from .laws import check_law, motion_law

GROUND = "ground"


def rot(theta: float) -> np.ndarray:
    """A(theta), the 2x2 rotation."""
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def rot_d(theta: float) -> np.ndarray:
    """dA/dtheta = A(theta + pi/2)."""
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[-s, -c], [c, -s]])


def perp(v: np.ndarray) -> np.ndarray:
    """v rotated by +90 degrees."""
    return np.array([-v[1], v[0]])


@dataclass
class Pose:
    """One body's state: position R, angle theta (and A, dA/dtheta), rates Rd, thd."""

    R: np.ndarray  # 2
    theta: float
    Rd: np.ndarray  # 2
    thd: float

    def __post_init__(self) -> None:
        self.A = rot(self.theta)  # 2 x 2
        self.B = rot_d(self.theta)  # 2 x 2, dA/dtheta

    def r(self, u: np.ndarray) -> np.ndarray:
        """World position of the point with local vector u."""
        return self.R + self.A @ u

    def v(self, u: np.ndarray) -> np.ndarray:
        """World velocity of the point with local vector u."""
        return self.Rd + self.B @ u * self.thd

    def centripetal(self, u: np.ndarray) -> np.ndarray:
        """A u thd^2: the velocity-squared part of the point's acceleration, negated."""
        return self.A @ u * self.thd**2


# --- shared pieces ----------------------------------------------------------------------


def _pin(pa: Pose, pb: Pose, ua: np.ndarray, ub: np.ndarray):
    """d = r_b(u_b) - r_a(u_a): value (2), blocks (2 x 3), gamma (2)."""
    value = pb.r(ub) - pa.r(ua)
    jac_a = np.column_stack([-np.eye(2), -(pa.B @ ua)])
    jac_b = np.column_stack([np.eye(2), pb.B @ ub])
    gamma = pb.centripetal(ub) - pa.centripetal(ua)
    return value, jac_a, jac_b, gamma


def _relative_angle(pa: Pose, pb: Pose):
    """theta_b - theta_a: value, blocks (1 x 3), gamma."""
    return pb.theta - pa.theta, np.array([[0.0, 0.0, -1.0]]), np.array([[0.0, 0.0, 1.0]]), 0.0


def _projection(pa: Pose, pb: Pose, ua: np.ndarray, ub: np.ndarray, w_local: np.ndarray):
    """s = w^T d with w = A_a w_local (a direction fixed in a) and d = r_b(u_b) - r_a(u_a).

    ds/dt = wd^T d + w^T dd, wd = B_a w_local thd_a. Differentiating once more, the terms
    without qdd are -w^T d thd_a^2 + 2 wd^T dd + w^T (A_a u_a thd_a^2 - A_b u_b thd_b^2),
    so gamma = w^T d thd_a^2 - 2 thd_a (B_a w_local)^T dd + w^T (A_b u_b thd_b^2 - A_a u_a thd_a^2).
    """
    w = pa.A @ w_local
    w_theta = pa.B @ w_local  # dw/dtheta_a
    d = pb.r(ub) - pa.r(ua)
    d_dot = pb.v(ub) - pa.v(ua)
    value = w @ d
    jac_a = np.array([[-w[0], -w[1], w_theta @ d - w @ (pa.B @ ua)]])
    jac_b = np.array([[w[0], w[1], w @ (pb.B @ ub)]])
    gamma = (
        (w @ d) * pa.thd**2 - 2.0 * pa.thd * (w_theta @ d_dot) + w @ (pb.centripetal(ub) - pa.centripetal(ua))
    )
    return value, jac_a, jac_b, gamma


# --- joints -------------------------------------------------------------------------------


class Constraint:
    """Rows g(q) - f(t) = 0 between bodies ``a`` and ``b`` (either may be the ground)."""

    name: str
    kind: str
    a: str
    b: str
    n_rows: int
    length_rows: list[bool]  # per row: True if it measures a length, False for an angle
    row_labels: list[str]
    n_own = 0  # coordinates the constraint adds to q (a curve parameter: ``CurveJoint``)

    def law_value(self, t: float) -> tuple[float, float, float]:
        """(f, f', f'') of the row's motion law; zero for joints."""
        return 0.0, 0.0, 0.0

    def evaluate(self, pa: Pose, pb: Pose):
        """g (n_rows), dg/dq_a, dg/dq_b (n_rows x 3), gamma of g (n_rows)."""
        raise NotImplementedError

    def phi(self, pa: Pose, pb: Pose, t: float) -> np.ndarray:
        g = np.atleast_1d(self.evaluate(pa, pb)[0])
        return g - self.law_value(t)[0]

    def jacobian(self, pa: Pose, pb: Pose, t: float) -> tuple[np.ndarray, np.ndarray]:
        _, jac_a, jac_b, _ = self.evaluate(pa, pb)
        return np.atleast_2d(jac_a), np.atleast_2d(jac_b)

    def nu(self, t: float) -> np.ndarray:
        """-Phi_t = f'(t) on every row (a driver has one row)."""
        return np.full(self.n_rows, self.law_value(t)[1])

    def gamma(self, pa: Pose, pb: Pose, t: float) -> np.ndarray:
        """-(Phi_q qd)_q qd - 2 Phi_qt qd - Phi_tt; Phi_qt = 0 and -Phi_tt = f''(t)."""
        g = np.atleast_1d(np.asarray(self.evaluate(pa, pb)[3], dtype=float))
        return g + self.law_value(t)[2]


class Revolute(Constraint):
    """Pin at P: r_b(P) - r_a(P) = 0 (2 rows)."""

    kind = "revolute"
    n_rows = 2

    def __init__(self, name: str, a: str, b: str, ua: np.ndarray, ub: np.ndarray):
        self.name, self.a, self.b, self.ua, self.ub = name, a, b, ua, ub
        self.length_rows = [True, True]
        self.row_labels = [f"{name}.x", f"{name}.y"]

    def evaluate(self, pa, pb):
        return _pin(pa, pb, self.ua, self.ub)


class Prismatic(Constraint):
    """b slides on a along the unit axis e' fixed in a, through P (2 rows):
    theta_b - theta_a - (theta_b0 - theta_a0) = 0 and n^T (r_b(P) - r_a(P)) = 0 with
    n = A_a n', n' = rot90(e')."""

    kind = "prismatic"
    n_rows = 2

    def __init__(self, name, a, b, ua, ub, e_local, angle0):
        self.name, self.a, self.b, self.ua, self.ub = name, a, b, ua, ub
        self.e_local = e_local
        self.n_local = perp(e_local)
        self.angle0 = angle0
        self.length_rows = [False, True]
        self.row_labels = [f"{name}.angle", f"{name}.normal"]

    def evaluate(self, pa, pb):
        ang, ja1, jb1, g1 = _relative_angle(pa, pb)
        off, ja2, jb2, g2 = _projection(pa, pb, self.ua, self.ub, self.n_local)
        return (
            np.array([ang - self.angle0, off]),
            np.vstack([ja1, ja2]),
            np.vstack([jb1, jb2]),
            np.array([g1, g2]),
        )


class Fixed(Constraint):
    """Weld: r_b(origin) - r_a(u_a) = 0 and theta_b - theta_a - (theta_b0 - theta_a0) = 0."""

    kind = "fixed"
    n_rows = 3

    def __init__(self, name, a, b, ua, angle0):
        self.name, self.a, self.b, self.ua = name, a, b, ua
        self.ub = np.zeros(2)
        self.angle0 = angle0
        self.length_rows = [True, True, False]
        self.row_labels = [f"{name}.x", f"{name}.y", f"{name}.angle"]

    def evaluate(self, pa, pb):
        d, ja1, jb1, g1 = _pin(pa, pb, self.ua, self.ub)
        ang, ja2, jb2, g2 = _relative_angle(pa, pb)
        return (
            np.array([d[0], d[1], ang - self.angle0]),
            np.vstack([ja1, ja2]),
            np.vstack([jb1, jb2]),
            np.array([g1[0], g1[1], g2]),
        )


def _cross(u: np.ndarray, v: np.ndarray) -> float:
    """z component of u x v."""
    return float(u[0] * v[1] - u[1] * v[0])


def _unit(v: Any, what: str) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    norm = float(np.hypot(v[0], v[1]))
    if not (np.isfinite(norm) and norm > 0.0):
        raise ValueError(f"{what} {list(v)} must be a finite, non-zero direction")
    return v / norm


class DistanceJoint(Constraint):
    """A massless coupler of length l between P_a and P_b (1 row, a length):
    (d^T d - l^2) / (2 l) = 0, d = r_b(u_b) - r_a(u_a).

    g' = d^T dd / l, g'' = (dd^T dd + d^T ddd) / l with ddd = (terms in qdd) -
    (A_b u_b thd_b^2 - A_a u_a thd_a^2), so gamma = (d^T c - dd^T dd) / l, c = that bracket."""

    kind = "distance"
    n_rows = 1

    def __init__(self, name, a, b, ua, ub, length):
        self.name, self.a, self.b, self.ua, self.ub, self.length = name, a, b, ua, ub, length
        self.length_rows = [True]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        d, ja, jb, c = _pin(pa, pb, self.ua, self.ub)
        d_dot = pb.v(self.ub) - pa.v(self.ua)
        length = self.length
        gamma = (d @ c - d_dot @ d_dot) / length
        value = (d @ d - length**2) / (2.0 * length)
        return value, (d @ ja)[None, :] / length, (d @ jb)[None, :] / length, gamma


class PointOnLine(Constraint):
    """The pin P of a on the line of b through Q along e' (fixed in b), at a constant
    offset (1 row, a length): n^T (r_a(P) - r_b(Q)) - offset = 0 with n = A_b rot90(e')."""

    kind = "point_on_line"
    n_rows = 1

    def __init__(self, name, a, b, ua, ub, e_local, offset):
        self.name, self.a, self.b, self.ua, self.ub = name, a, b, ua, ub
        self.n_local = perp(e_local)
        self.offset = offset
        self.length_rows = [True]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        # the projection with the roles swapped: the direction is fixed in b
        value, jac_b, jac_a, gamma = _projection(pb, pa, self.ub, self.ua, self.n_local)
        return value - self.offset, jac_a, jac_b, gamma


class GearPair(Constraint):
    """Gears (or pulleys) rolling without slip, 1 row, an angle:
    k_a theta_a + k_b theta_b - value = 0 with centres fixed in the ground; k_a = r_a / r_max,
    k_b = +r_b / r_max for external gears and crossed belts (opposite turns), -r_b / r_max
    for internal gears and open belts (same turns).

    With a carrier, the engine's row is relative to the carrier's angle; here it is written
    without the carrier, from the line of centres C_a -> C_b instead (the carrier holds
    both centres, so its direction psi turns with the carrier):
    k_a (theta_a - psi) + k_b (theta_b - psi) = value', i.e. psi = chi mod 2 pi with
    chi = (k_a theta_a + k_b theta_b - value') / K, K = k_a + k_b. As a row that stays
    smooth through whole turns (a length): h = e(chi) x d = |d| sin(psi - chi) = 0,
    d = C_b - C_a, e(chi) = (cos chi, sin chi). With e' = de/dchi = rot90(e):
    dh = e x dd - (e^T d) dchi and gamma = e x c + 2 (e^T dd) chid + h chid^2,
    c = A_b u_b thd_b^2 - A_a u_a thd_a^2."""

    n_rows = 1

    def __init__(self, name, kind, a, b, k_a, k_b, start, carrier=None, centres=None):
        self.name, self.kind, self.a, self.b = name, kind, a, b
        self.k_a, self.k_b = k_a, k_b
        self.carrier = carrier
        self.row_labels = [name]
        theta_a0, theta_b0 = start
        if carrier is None:
            self.length_rows = [False]
            self.value = k_a * theta_a0 + k_b * theta_b0
        else:
            self.length_rows = [True]
            self.ua, self.ub, d0 = centres  # the centres in a's and b's frames, C_b - C_a
            self.value = k_a * theta_a0 + k_b * theta_b0 - (k_a + k_b) * math.atan2(d0[1], d0[0])

    def evaluate(self, pa, pb):
        k_a, k_b = self.k_a, self.k_b
        if self.carrier is None:
            g = k_a * pa.theta + k_b * pb.theta - self.value
            return g, np.array([[0.0, 0.0, k_a]]), np.array([[0.0, 0.0, k_b]]), 0.0
        K = k_a + k_b
        chi = (k_a * pa.theta + k_b * pb.theta - self.value) / K
        chi_d = (k_a * pa.thd + k_b * pb.thd) / K
        d, ja, jb, c = _pin(pa, pb, self.ua, self.ub)
        d_dot = pb.v(self.ub) - pa.v(self.ua)
        e = np.array([math.cos(chi), math.sin(chi)])
        h = _cross(e, d)
        jac_a = np.array([[_cross(e, ja[:, k]) for k in range(3)]])
        jac_b = np.array([[_cross(e, jb[:, k]) for k in range(3)]])
        jac_a[0, 2] -= (e @ d) * k_a / K
        jac_b[0, 2] -= (e @ d) * k_b / K
        gamma = _cross(e, c) + 2.0 * (e @ d_dot) * chi_d + h * chi_d**2
        return h, jac_a, jac_b, gamma


class RackPinion(Constraint):
    """Pinion a (centre C, pitch radius r) and rack b (unit axis e' fixed in b), 1 row, a
    length: e^T (r_a(C) - r_b(C)) + r (theta_a - theta_b - delta0) = 0, e = A_b e'.
    A counter-clockwise pinion turn dtheta moves the rack by r dtheta along +e."""

    kind = "rack_pinion"
    n_rows = 1

    def __init__(self, name, a, b, ua, ub, e_local, radius, delta0):
        self.name, self.a, self.b, self.ua, self.ub = name, a, b, ua, ub
        self.e_local, self.radius, self.delta0 = e_local, radius, delta0
        self.length_rows = [True]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        value, jac_b, jac_a, gamma = _projection(pb, pa, self.ub, self.ua, self.e_local)
        r = self.radius
        jac_a, jac_b = jac_a.copy(), jac_b.copy()
        jac_a[0, 2] += r
        jac_b[0, 2] -= r
        return value + r * (pa.theta - pb.theta - self.delta0), jac_a, jac_b, gamma


class FixedOrientation(Constraint):
    """theta_b - theta_a - angle = 0 (1 row, an angle)."""

    kind = "fixed_orientation"
    n_rows = 1

    def __init__(self, name, a, b, angle):
        self.name, self.a, self.b, self.angle = name, a, b, angle
        self.length_rows = [False]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        ang, ja, jb, g = _relative_angle(pa, pb)
        return ang - self.angle, ja, jb, g


class Parallel(Constraint):
    """u x v = 0 with u = A_a e_a', v = A_b e_b' (1 row, an angle: the sine between them).

    d/dt (u x v) = ud x v + u x vd with ud = B_a e_a' thd_a; the second derivative without
    qdd is -(u x v) thd_a^2 + 2 ud x vd - (u x v) thd_b^2, negated for gamma."""

    kind = "parallel"
    n_rows = 1

    def __init__(self, name, a, b, ea_local, eb_local):
        self.name, self.a, self.b, self.ea, self.eb = name, a, b, ea_local, eb_local
        self.length_rows = [False]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        u, v = pa.A @ self.ea, pb.A @ self.eb
        u_theta, v_theta = pa.B @ self.ea, pb.B @ self.eb
        g = _cross(u, v)
        jac_a = np.array([[0.0, 0.0, _cross(u_theta, v)]])
        jac_b = np.array([[0.0, 0.0, _cross(u, v_theta)]])
        gamma = g * pa.thd**2 - 2.0 * _cross(u_theta * pa.thd, v_theta * pb.thd) + g * pb.thd**2
        return g, jac_a, jac_b, gamma


class LinearCoupling(Constraint):
    """c_a^T q_a + c_b^T q_b - value = 0 (1 row; a length if any x or y is involved)."""

    kind = "linear_coupling"
    n_rows = 1

    def __init__(self, name, a, b, c_a, c_b, value):
        self.name, self.a, self.b = name, a, b
        self.c_a, self.c_b, self.value = np.asarray(c_a, float), np.asarray(c_b, float), value
        self.length_rows = [bool(np.any(self.c_a[:2] != 0.0) or np.any(self.c_b[:2] != 0.0))]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        qa = np.array([pa.R[0], pa.R[1], pa.theta])
        qb = np.array([pb.R[0], pb.R[1], pb.theta])
        return self.c_a @ qa + self.c_b @ qb - self.value, self.c_a[None, :], self.c_b[None, :], 0.0


# --- drivers ------------------------------------------------------------------------------


class Driver(Constraint):
    """One row g(q) - f(t) = 0."""

    n_rows = 1
    law: dict[str, Any]

    def law_value(self, t):
        return motion_law(self.law, t)


class AngleDriver(Driver):
    """theta_body - f(t) = 0 (body is b; a is the ground)."""

    kind = "angle"

    def __init__(self, name, body, law):
        self.name, self.a, self.b, self.law = name, GROUND, body, law
        self.length_rows = [False]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        return pb.theta, np.zeros((1, 3)), np.array([[0.0, 0.0, 1.0]]), 0.0


class RelativeAngleDriver(Driver):
    """theta_b - theta_a - f(t) = 0."""

    kind = "relative_angle"

    def __init__(self, name, a, b, law):
        self.name, self.a, self.b, self.law = name, a, b, law
        self.length_rows = [False]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        return _relative_angle(pa, pb)


class DistanceDriver(Driver):
    """|r_b(Pb) - r_a(Pa)| - f(t) = 0.

    With d = r_b - r_a, l = |d|, e = d / l: dl/dt = e^T dd, and
    gamma = e^T (A_b u_b thd_b^2 - A_a u_a thd_a^2) - (|dd|^2 - (e^T dd)^2) / l (+ f'')."""

    kind = "distance"

    def __init__(self, name, a, b, ua, ub, law):
        self.name, self.a, self.b, self.ua, self.ub, self.law = name, a, b, ua, ub, law
        self.length_rows = [True]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        d, ja, jb, g = _pin(pa, pb, self.ua, self.ub)
        length = float(np.hypot(d[0], d[1]))
        if length == 0.0:
            raise ZeroDivisionError(f"distance driver {self.name!r}: its two points coincide")
        e = d / length
        d_dot = pb.v(self.ub) - pa.v(self.ua)
        gamma = e @ g - (d_dot @ d_dot - (e @ d_dot) ** 2) / length
        return length, (e @ ja)[None, :], (e @ jb)[None, :], gamma


class CoordinateDriver(Driver):
    """(R + A u)_k - f(t) = 0, k = x or y (body is b; a is the ground)."""

    kind = "coordinate"

    def __init__(self, name, body, u, axis, law):
        self.name, self.a, self.b, self.u, self.law = name, GROUND, body, u, law
        self.k = {"x": 0, "y": 1}[axis]
        self.length_rows = [True]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        k = self.k
        jac_b = np.zeros((1, 3))
        jac_b[0, k] = 1.0
        jac_b[0, 2] = (pb.B @ self.u)[k]
        return pb.r(self.u)[k], np.zeros((1, 3)), jac_b, pb.centripetal(self.u)[k]


class TranslationDriver(Driver):
    """e^T (r_b(P) - r_a(P)) - f(t) = 0 for a prismatic joint, e = A_a e' (the slide s)."""

    kind = "translation"

    def __init__(self, name, joint: Prismatic, law):
        self.name, self.a, self.b, self.law = name, joint.a, joint.b, law
        self.joint = joint
        self.length_rows = [True]
        self.row_labels = [name]

    def evaluate(self, pa, pb):
        j = self.joint
        return _projection(pa, pb, j.ua, j.ub, j.e_local)


# --- building from the description ----------------------------------------------------------


def build_constraints(desc: dict[str, Any], start: dict[str, tuple[float, float, float]]) -> list[Constraint]:
    """All joints in description order, then all drivers in order."""

    def body(name: Any, where: str) -> str:
        if name not in start:
            raise ValueError(f"{where} refers to unknown body {name!r}")
        return name

    def local(name: str, p: Any) -> np.ndarray:
        x0, y0, th0 = start[name]
        return rot(th0).T @ (np.asarray(p, dtype=float) - np.array([x0, y0]))

    out: list[Constraint] = []
    prismatics: dict[str, Prismatic] = {}
    seen: set[str] = set()

    def register(name: Any, where: str) -> str:
        if name in seen:
            raise ValueError(f"{where}: the name {name!r} is used twice")
        seen.add(name)
        return str(name)

    for j in desc.get("joints", []):
        kind = j.get("type")
        name = register(j.get("name"), f"joint {j.get('name')!r}")
        where = f"{kind} joint {name!r}"
        a, b = body(j["body_a"], where), body(j["body_b"], where)
        if a == b:
            raise ValueError(f"{where} joins body {a!r} to itself")
        if kind in ("pin_in_slot", "cam_follower"):
            out.append(curve_joint(j, name, a, b, start[a], start[b]))
        elif kind == "revolute":
            out.append(Revolute(name, a, b, local(a, j["at"]), local(b, j["at"])))
        elif kind == "prismatic":
            axis = np.asarray(j["axis"], dtype=float)
            norm = float(np.hypot(axis[0], axis[1]))
            if not norm > 0.0:
                raise ValueError(f"{where} has a zero axis")
            e_local = rot(start[a][2]).T @ (axis / norm)
            joint = Prismatic(
                name, a, b, local(a, j["at"]), local(b, j["at"]), e_local, start[b][2] - start[a][2]
            )
            prismatics[name] = joint
            out.append(joint)
        elif kind == "fixed":
            x0, y0, _ = start[b]
            out.append(Fixed(name, a, b, local(a, (x0, y0)), start[b][2] - start[a][2]))
        elif kind in _LIBRARY:
            out.append(_LIBRARY[kind](j, name, where, a, b, start, local))
        else:
            raise ValueError(f"joint {name!r} has unknown type {kind!r}")

    for d in desc.get("drivers", []):
        kind = d.get("type")
        name = register(d.get("name"), f"driver {d.get('name')!r}")
        where = f"{kind} driver {name!r}"
        law = d.get("law")
        if not isinstance(law, dict):
            raise ValueError(f"{where} has no motion law")
        try:
            check_law(law)
        except ValueError as err:
            raise ValueError(f"{where}: {err}") from None
        if kind in ("angle", "coordinate") and d.get("body") == GROUND:
            raise ValueError(f"{where} drives the ground")
        if kind == "angle":
            out.append(AngleDriver(name, body(d["body"], where), law))
        elif kind == "relative_angle":
            a, b = body(d["body_a"], where), body(d["body_b"], where)
            if a == b:
                raise ValueError(f"{where} measures body {a!r} against itself")
            out.append(RelativeAngleDriver(name, a, b, law))
        elif kind == "distance":
            a, b = body(d["body_a"], where), body(d["body_b"], where)
            out.append(DistanceDriver(name, a, b, local(a, d["at_a"]), local(b, d["at_b"]), law))
        elif kind == "coordinate":
            b = body(d["body"], where)
            if d.get("axis") not in ("x", "y"):
                raise ValueError(f"{where}: axis must be 'x' or 'y', not {d.get('axis')!r}")
            out.append(CoordinateDriver(name, b, local(b, d["at"]), d["axis"], law))
        elif kind == "translation":
            if d.get("joint") not in prismatics:
                raise ValueError(f"{where}: {d.get('joint')!r} is not a prismatic joint")
            out.append(TranslationDriver(name, prismatics[d["joint"]], law))
        else:
            raise ValueError(f"driver {name!r} has unknown type {kind!r}")
    return out


# --- the joint library: one builder per type, from its description ----------------------------


def _positive(j: dict[str, Any], key: str, where: str, default: float | None = None) -> float:
    value = j.get(key, default)
    if value is None or not (math.isfinite(float(value)) and float(value) > 0.0):
        raise ValueError(f"{where}: {key} {value} must be finite and > 0")
    return float(value)


def _pitch_radii(j: dict[str, Any], where: str, distance: float | None) -> tuple[float, float]:
    """(r_a, r_b) from radius_a and radius_b, or from the ratio r_a / r_b: radii from the
    centre distance for gears, (ratio, 1) for belts (only the ratio matters there)."""
    given = tuple(j.get(k) is not None for k in ("radius_a", "radius_b", "ratio"))
    if given == (True, True, False):
        return _positive(j, "radius_a", where), _positive(j, "radius_b", where)
    if given != (False, False, True):
        raise ValueError(f"{where} needs either radius_a and radius_b, or ratio")
    k = _positive(j, "ratio", where)
    if distance is None:
        return k, 1.0
    if not distance > 0.0:
        raise ValueError(f"{where}: its centres coincide, so a ratio does not give the radii")
    if j.get("internal", False):
        if k == 1.0:
            raise ValueError(f"{where}: an internal gear pair cannot have ratio 1")
        r_b = distance / abs(k - 1.0)
    else:
        r_b = distance / (k + 1.0)
    return k * r_b, r_b


def _gear_pair(j, name, where, a, b, start, local) -> GearPair:
    kind = j["type"]
    origin = {n: (start[n][0], start[n][1]) for n in (a, b)}
    centre_a = np.asarray(j.get("centre_a") or origin[a], dtype=float)
    centre_b = np.asarray(j.get("centre_b") or origin[b], dtype=float)
    distance = float(np.hypot(*(centre_b - centre_a))) if kind == "gear" else None
    r_a, r_b = _pitch_radii(j, where, distance)
    same_sense = bool(j.get("internal", False)) if kind == "gear" else not j.get("crossed", False)
    if kind == "gear" and same_sense and r_a == r_b:
        raise ValueError(f"{where}: an internal gear and its pinion need different radii")
    r_max = max(r_a, r_b)
    k_a, k_b = r_a / r_max, (-1.0 if same_sense else 1.0) * r_b / r_max
    carrier, centres = j.get("carrier"), None
    if carrier is not None:
        if carrier not in start:
            raise ValueError(f"{where}: its carrier {carrier!r} is not a body")
        if carrier in (a, b):
            raise ValueError(f"{where}: its carrier {carrier!r} is one of its own two bodies")
        if carrier == GROUND:
            carrier = None
        else:
            centres = (local(a, centre_a), local(b, centre_b), centre_b - centre_a)
    return GearPair(name, kind, a, b, k_a, k_b, (start[a][2], start[b][2]), carrier, centres)


def _distance(j, name, where, a, b, start, local) -> DistanceJoint:
    pa, pb = np.asarray(j["at_a"], dtype=float), np.asarray(j["at_b"], dtype=float)
    drawn = float(np.hypot(*(pb - pa)))
    if not drawn > 0.0:
        raise ValueError(f"{where}: its two points coincide")
    return DistanceJoint(name, a, b, local(a, pa), local(b, pb), _positive(j, "length", where, drawn))


def _point_on_line(j, name, where, a, b, start, local) -> PointOnLine:
    at = np.asarray(j["at"], dtype=float)
    through = np.asarray(j["through"] if j.get("through") is not None else at, dtype=float)
    e = _unit(j["axis"], f"{where}: axis")
    offset = j.get("offset")
    if offset is None:
        offset = float(perp(e) @ (at - through))
    return PointOnLine(name, a, b, local(a, at), local(b, through), rot(start[b][2]).T @ e, float(offset))


def _rack_pinion(j, name, where, a, b, start, local) -> RackPinion:
    if a == GROUND:
        raise ValueError(f"{where}: its pinion is the ground, which cannot turn")
    centre = j.get("centre") or (start[a][0], start[a][1])
    e_local = rot(start[b][2]).T @ _unit(j["axis"], f"{where}: axis")
    radius = _positive(j, "radius", where)
    return RackPinion(
        name, a, b, local(a, centre), local(b, centre), e_local, radius, start[a][2] - start[b][2]
    )


def _fixed_orientation(j, name, where, a, b, start, local) -> FixedOrientation:
    angle = j.get("angle")
    return FixedOrientation(name, a, b, start[b][2] - start[a][2] if angle is None else float(angle))


def _parallel(j, name, where, a, b, start, local) -> Parallel:
    ea, eb = _unit(j["axis_a"], f"{where}: axis_a"), _unit(j["axis_b"], f"{where}: axis_b")
    if abs(ea @ eb) <= 1e-6:
        raise ValueError(f"{where}: its two lines are perpendicular at the start")
    return Parallel(name, a, b, rot(start[a][2]).T @ ea, rot(start[b][2]).T @ eb)


def _linear_coupling(j, name, where, a, b, start, local) -> LinearCoupling:
    def coefficients(key: str, body: str) -> np.ndarray:
        given = dict(j.get(key) or {})
        unknown = set(given) - {"x", "y", "theta"}
        if unknown:
            raise ValueError(f"{where}: {key} has unknown coordinates {sorted(unknown)}")
        c = np.array([float(given.get(k, 0.0)) for k in ("x", "y", "theta")])
        if body == GROUND and np.any(c != 0.0):
            raise ValueError(f"{where}: {key} are on the ground, whose coordinates are fixed")
        return c

    c_a, c_b = coefficients("coefficients_a", a), coefficients("coefficients_b", b)
    if not (np.any(c_a != 0.0) or np.any(c_b != 0.0)):
        raise ValueError(f"{where} has no non-zero coefficient")
    value = j.get("value")
    if value is None:
        value = float(c_a @ np.asarray(start[a]) + c_b @ np.asarray(start[b]))
    return LinearCoupling(name, a, b, c_a, c_b, float(value))


_LIBRARY = {
    "distance": _distance,
    "point_on_line": _point_on_line,
    "gear": _gear_pair,
    "rack_pinion": _rack_pinion,
    "belt": _gear_pair,
    "fixed_orientation": _fixed_orientation,
    "parallel": _parallel,
    "linear_coupling": _linear_coupling,
}
# --- joints with their own coordinate: a parameter along a curve of body a ------------------


@dataclass
class Own:
    """A joint's own coordinate: the curve parameter s and its rate sd."""

    s: float
    sd: float = 0.0


def _along(pose: Pose, v: np.ndarray, v1: np.ndarray, v2: np.ndarray, sd: float):
    """A vector A v(s) carried by a body, v depending on the curve parameter s: its value,
    its rate B v thd + A v' sd, and the velocity-squared part of its second derivative,
    -A v thd^2 + 2 B v' thd sd + A v'' sd^2."""
    w = pose.thd
    return (
        pose.A @ v,
        pose.B @ v * w + pose.A @ v1 * sd,
        -(pose.A @ v) * w**2 + 2.0 * (pose.B @ v1) * w * sd + pose.A @ v2 * sd**2,
    )


class CurveJoint(Constraint):
    """A joint whose rows also depend on its own coordinate s, the parameter of the curve
    ``curve`` fixed in body a (``curves``). The model passes ``own`` (s and its rate) to
    ``phi``, ``jacobian``, ``jacobian_own`` and ``gamma``; ``evaluate_own`` gives the
    rows, their blocks, the column d phi / d s and gamma."""

    n_own = 1
    n_rows = 2
    curve: Any
    ub: np.ndarray

    def own_start(self, pa: Pose, pb: Pose) -> float:
        """s where the described configuration fits best (nearest curve point)."""
        return curves.nearest(self.curve, pa.A.T @ (pb.r(self.ub) - pa.R))

    def evaluate_own(self, pa: Pose, pb: Pose, own: Own):
        """g (2), dg/dq_a, dg/dq_b (2 x 3), dg/ds (2), gamma (2)."""
        raise NotImplementedError

    def _rows(self, pa: Pose, pb: Pose, own: Own | None):
        if own is None:
            raise ValueError(f"{self.kind} joint {self.name!r} needs the value of its own coordinate s")
        return self.evaluate_own(pa, pb, own)

    def phi(self, pa: Pose, pb: Pose, t: float, own: Own | None = None) -> np.ndarray:
        return self._rows(pa, pb, own)[0]

    def jacobian(self, pa: Pose, pb: Pose, t: float, own: Own | None = None) -> tuple[np.ndarray, np.ndarray]:
        rows = self._rows(pa, pb, own)
        return rows[1], rows[2]

    def jacobian_own(self, pa: Pose, pb: Pose, t: float, own: Own | None = None) -> np.ndarray:
        return self._rows(pa, pb, own)[3]

    def gamma(self, pa: Pose, pb: Pose, t: float, own: Own | None = None) -> np.ndarray:
        return self._rows(pa, pb, own)[4]


class PointOnCurve(CurveJoint):
    """The point u_b of b on the curve c(s) of a (pin in slot, knife-edge follower):
    r_b(u_b) - (R_a + A_a c(s)) = 0 (2 rows)."""

    def __init__(self, name, kind, a, b, curve, ub):
        self.name, self.kind, self.a, self.b, self.curve, self.ub = name, kind, a, b, curve, ub
        self.length_rows = [True, True]
        self.row_labels = [f"{name}.x", f"{name}.y"]

    def evaluate_own(self, pa, pb, own):
        c, c1, c2, _ = self.curve(own.s)
        C, _, Cq = _along(pa, c, c1, c2, own.sd)
        g = pb.r(self.ub) - (pa.R + C)
        jac_a = np.column_stack([-np.eye(2), -(pa.B @ c)])
        jac_b = np.column_stack([np.eye(2), pb.B @ self.ub])
        # d2/dt2 of r_b has velocity-squared part -A_b u_b thd_b^2
        gamma = pb.centripetal(self.ub) + Cq
        return g, jac_a, jac_b, -(pa.A @ c1), gamma


class RollerFollower(CurveJoint):
    """A roller of radius rho centred at u_b of b on the profile c(s) of a: with
    d = r_b(u_b) - (R_a + A_a c(s)) and T = A_a c'(s), (d.d - rho^2) / (2 rho) = 0 and
    d.T / rho = 0 (the centre is rho from the contact point, along the normal)."""

    def __init__(self, name, a, b, curve, ub, rho):
        self.name, self.kind, self.a, self.b, self.curve, self.ub = name, "cam_follower", a, b, curve, ub
        self.rho = rho
        self.length_rows = [True, True]
        self.row_labels = [f"{name}.distance", f"{name}.normal"]

    def evaluate_own(self, pa, pb, own):
        rho, sd = self.rho, own.sd
        c, c1, c2, c3 = self.curve(own.s)
        C, Cd, Cq = _along(pa, c, c1, c2, sd)
        T, Td, Tq = _along(pa, c1, c2, c3, sd)
        d = pb.r(self.ub) - (pa.R + C)
        dd = pb.v(self.ub) - (pa.Rd + Cd)
        dq = -pb.centripetal(self.ub) - Cq
        Bc, Bc1, Bu = pa.B @ c, pa.B @ c1, pb.B @ self.ub
        g = np.array([(d @ d - rho**2) / (2.0 * rho), d @ T / rho])
        jac_a = np.array([[-d[0], -d[1], -(d @ Bc)], [-T[0], -T[1], d @ Bc1 - Bc @ T]]) / rho
        jac_b = np.array([[d[0], d[1], d @ Bu], [T[0], T[1], Bu @ T]]) / rho
        jac_s = np.array([-(d @ T), d @ (pa.A @ c2) - T @ T]) / rho
        gamma = -np.array([dd @ dd + d @ dq, dq @ T + 2.0 * dd @ Td + d @ Tq]) / rho
        return g, jac_a, jac_b, jac_s, gamma


class FlatFollower(CurveJoint):
    """The face of b (the line through u_b with unit normal n_b) tangent to the profile
    c(s) of a: with n = A_b n_b, n.(R_a + A_a c(s) - r_b(u_b)) = 0 and n.A_a c'(s) = 0."""

    def __init__(self, name, a, b, curve, ub, nb):
        self.name, self.kind, self.a, self.b, self.curve, self.ub = name, "cam_follower", a, b, curve, ub
        self.nb = nb
        self.length_rows = [True, True]
        self.row_labels = [f"{name}.face", f"{name}.tangent"]

    def own_start(self, pa, pb):
        n = pa.A.T @ (pb.A @ self.nb)
        return curves.tangent_to_line(self.curve, n, pa.A.T @ (pb.r(self.ub) - pa.R))

    def evaluate_own(self, pa, pb, own):
        sd, wb = own.sd, pb.thd
        c, c1, c2, c3 = self.curve(own.s)
        C, Cd, Cq = _along(pa, c, c1, c2, sd)
        T, Td, Tq = _along(pa, c1, c2, c3, sd)
        n, n_theta = pb.A @ self.nb, pb.B @ self.nb
        e = pa.R + C - pb.r(self.ub)
        ed = pa.Rd + Cd - pb.v(self.ub)
        eq = Cq + pb.centripetal(self.ub)
        nd, nq = n_theta * wb, -n * wb**2
        g = np.array([n @ e, n @ T])
        jac_a = np.array([[n[0], n[1], n @ (pa.B @ c)], [0.0, 0.0, n @ (pa.B @ c1)]])
        jac_b = np.array([[-n[0], -n[1], n_theta @ e - n @ (pb.B @ self.ub)], [0.0, 0.0, n_theta @ T]])
        jac_s = np.array([n @ T, n @ (pa.A @ c2)])
        gamma = -np.array([nq @ e + 2.0 * nd @ ed + n @ eq, nq @ T + 2.0 * nd @ Td + n @ Tq])
        return g, jac_a, jac_b, jac_s, gamma


def curve_joint(j: dict[str, Any], name: str, a: str, b: str, start_a, start_b) -> CurveJoint:
    """A ``pin_in_slot`` or ``cam_follower`` joint of the description; ``ValueError``
    naming the joint for bad fields."""
    kind = j["type"]
    where = f"{kind} joint {name!r}"
    curve = curves.build_curve(j.get("curve"), start_a, where)
    ub = rot(start_b[2]).T @ (np.asarray(j["at"], dtype=float) - np.array(start_b[:2]))
    if kind == "pin_in_slot":
        return PointOnCurve(name, kind, a, b, curve, ub)
    follower = j.get("follower")
    if "radius" in j and follower != "roller":
        raise ValueError(f"{where}: gives a radius, which only a roller follower has")
    if "face" in j and follower != "flat":
        raise ValueError(f"{where}: gives a face direction, which only a flat-faced follower has")
    if follower == "knife":
        return PointOnCurve(name, kind, a, b, curve, ub)
    if follower == "roller":
        rho = float(j.get("radius", 0.0))
        if not rho > 0.0:
            raise ValueError(f"{where}: roller radius {rho} must be > 0")
        return RollerFollower(name, a, b, curve, ub, rho)
    if follower == "flat":
        face = rot(start_b[2]).T @ np.asarray(j.get("face", (0.0, 0.0)), dtype=float)
        norm = float(np.hypot(*face))
        if not norm > 0.0:
            raise ValueError(f"{where}: face direction must be non-zero")
        return FlatFollower(name, a, b, curve, ub, perp(face / norm))
    raise ValueError(f"{where}: follower must be 'knife', 'roller' or 'flat', not {follower!r}")

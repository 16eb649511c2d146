"""Inverse dynamics in absolute coordinates, written out the textbook way.

The equations of motion of the constrained system are

    M(q) qdd + Phi_q^T lambda = Q(q, qd, t),

so once the kinematics (q, qd, qdd) are known, the Lagrange multipliers follow from one
linear solve, Phi_q^T lambda = Q - M qdd. Here every piece is a dense matrix:

- M, block-diagonal, one 3 x 3 block per body. With the centre of mass at the local
  vector u_c (r_c = R + A u_c), the kinetic energy T = 1/2 m |Rd + B u_c thd|^2 +
  1/2 J_c thd^2 (B = dA/dtheta) gives

      M_i = [[ m I_2,          m B u_c            ],
             [ m (B u_c)^T,    J_c + m |u_c|^2    ]].

- Q = Q_v + Q_g + Q_loads:
  Q_v, the quadratic velocity term of a body whose origin is not its centre of mass
  (from -(dr_c/dq)^T m a_c with a_c = Rdd + B u_c thdd - A u_c thd^2): (m thd^2 A u_c, 0);
  Q_g = (m g, (B u_c)^T m g);
  a force F at the local point u adds (F, (B u)^T F); a torque adds to the theta entry.
  A joint load of magnitude f (a law of x or x' of the joint or of another joint, a
  motor, clipped or not, friction) is a torque f on b and -f on a at a revolute
  (x = theta_b - theta_a); at a prismatic, with x = n . d (n = A_a e,
  d = r_b(u_b) - r_a(u_a)), the force f n at b's point, -f n at a's and the moment
  f (n x d) on a, since the axis turns with a: together f dx/dq.

From lambda: the generalized force that constraint k exerts on its side b is
Q_b = -(dPhi_k/dq_b)^T lambda_k: a world force (Fx, Fy) and the moment about b's origin,
moved to the constraint's anchor point p on b with M_p = M_o - (p - R_b) x F. The power
it delivers is Q_a . qd_a + Q_b . qd_b = -lambda_k . (Phi_q qd)_k (zero for joints; for a
driver in motion, its effort times its rate). A driver's effort is -lambda of its row.

This module reads the same description dict as the engine and never imports it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .formulation import (
    GROUND,
    AngleDriver,
    Constraint,
    CoordinateDriver,
    CurveJoint,
    DistanceDriver,
    DistanceJoint,
    Fixed,
    FixedOrientation,
    GearPair,
    LinearCoupling,
    Parallel,
    PointOnLine,
    Pose,
    Prismatic,
    RackPinion,
    RelativeAngleDriver,
    Revolute,
    TranslationDriver,
    rot,
    rot_d,
)
from .laws import check_law, motion_law

if TYPE_CHECKING:
    from linkwork.reference import ReferenceModel

__all__ = [
    "MassProperties",
    "Load",
    "build_mass_properties",
    "build_loads",
    "anchor_b",
    "body_mass_matrix",
    "mass_matrix",
    "generalized_forces",
    "reactions",
    "inverse_dynamics",
    "sweep_forces",
    "energy",
    "DRIVER_KINDS",
]

# the constraint kinds that are drivers (one row each; their effort is -lambda)
DRIVER_KINDS = ("angle", "relative_angle", "distance", "coordinate", "translation")


@dataclass
class MassProperties:
    """One body's mass m, moment of inertia J_c about its centre of mass, and the centre
    of mass's local vector u_c."""

    mass: float
    inertia: float
    u_c: np.ndarray


def is_finite(value: Any, n: int | None = None) -> bool:
    """True if value is a finite number (n None) or a finite vector of n numbers."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    if n is not None and arr.shape != (n,):
        return False
    return bool(np.all(np.isfinite(arr)))


def _local(start: tuple[float, float, float], p: Any) -> np.ndarray:
    x0, y0, th0 = start
    return rot(th0).T @ (np.asarray(p, dtype=float) - np.array([x0, y0]))


def build_mass_properties(
    desc: dict[str, Any], start: dict[str, tuple[float, float, float]]
) -> dict[str, MassProperties]:
    """Mass properties of every moving body; ``com`` is a world point at the start
    (default: the body's origin). Raises ``ValueError`` naming the body."""
    out: dict[str, MassProperties] = {}
    for b in desc.get("bodies", []):
        name = b["name"]
        mass, inertia = b.get("mass", 0.0), b.get("inertia", 0.0)
        for what, v in (("mass", mass), ("moment of inertia", inertia)):
            if not (is_finite(v) and float(v) >= 0.0):
                raise ValueError(f"body {name!r}: {what} {v} must be finite and >= 0")
        com = b.get("com")
        if com is None:
            com = (start[name][0], start[name][1])
        elif not is_finite(com, 2):
            raise ValueError(f"body {name!r}: centre of mass {com} is not a finite point")
        out[name] = MassProperties(float(mass), float(inertia), _local(start[name], com))
    return out


def body_mass_matrix(mp: MassProperties, theta: float) -> np.ndarray:
    """The 3 x 3 mass matrix of one body in (x, y, theta) at angle theta."""
    Bu = rot_d(theta) @ mp.u_c  # B u_c, B = dA/dtheta
    M = np.zeros((3, 3))
    M[0, 0] = M[1, 1] = mp.mass
    M[0:2, 2] = M[2, 0:2] = mp.mass * Bu
    M[2, 2] = mp.inertia + mp.mass * float(mp.u_c @ mp.u_c)
    return M


# --- loads ------------------------------------------------------------------------------------


@dataclass
class Load:
    """A compiled load: ``kind`` is "force", "torque", "spring" or "torsion_spring"; ``a``
    and ``b`` its sides (a is the ground for forces and torques); the other fields as the
    description gives them, points as local vectors, the force direction made unit."""

    name: str
    kind: str
    a: str
    b: str
    u_a: np.ndarray | None = None
    u_b: np.ndarray | None = None
    direction: np.ndarray | None = None
    law: dict[str, Any] | None = None
    stiffness: float = 0.0
    free_length: float = 0.0
    free_angle: float = 0.0
    damping: float = 0.0
    # joint loads: "turn" (revolute) or "slide" (prismatic, axis e_local in a), and theirs
    axis: str = ""
    e_local: np.ndarray | None = None
    of_rate: bool = False
    scale: float = 1.0
    stall: float = 0.0
    no_load_speed: float = 1.0
    clip: bool = False
    viscous: float = 0.0
    coulomb: float = 0.0
    smoothing: float = 1.0
    # a joint force's law of another joint's x: that joint (kind "joint", its axis and sides)
    reads: Load | None = None

    def joint_coordinate(self, pa: Pose, pb: Pose) -> tuple[float, float]:
        """(x, x') of a joint load's joint: theta_b - theta_a, or the slide n . d with
        n = A_a e and d = r_b(u_b) - r_a(u_a) (zero at the start)."""
        if self.axis == "turn":
            return pb.theta - pa.theta, pb.thd - pa.thd
        assert self.e_local is not None and self.u_a is not None and self.u_b is not None
        n, nd = pa.A @ self.e_local, pa.B @ self.e_local * pa.thd
        d = pb.r(self.u_b) - pa.r(self.u_a)
        return float(n @ d), float(nd @ d + n @ (pb.v(self.u_b) - pa.v(self.u_a)))

    def magnitude(self, x: float, xd: float) -> float:
        """A joint load's torque or force at (x, x')."""
        if self.kind == "joint_force":
            assert self.law is not None
            return motion_law(self.law, self.scale * (xd if self.of_rate else x))[0]
        if self.kind == "motor":
            share = 1.0 - xd / self.no_load_speed
            # clipped: no torque beyond the no-load speed, stall torque against it
            return self.stall * (min(max(share, 0.0), 1.0) if self.clip else share)
        return -self.viscous * xd - self.coulomb * math.tanh(xd / self.smoothing)

    def forces(
        self, pa: Pose, pb: Pose, t: float, read: tuple[Pose, Pose] | None = None
    ) -> list[tuple[str, np.ndarray, float]]:
        """The load as (side, world force at its point, torque) acting on each side:
        side "a" or "b", the force F (2) at u_a or u_b (zero for pure torques) and a
        torque. ``read``: the poses of the sides of the joint ``reads``, if any."""
        if self.kind == "force":
            assert self.direction is not None and self.law is not None
            return [("b", motion_law(self.law, t)[0] * self.direction, 0.0)]
        if self.kind == "torque":
            assert self.law is not None
            return [("b", np.zeros(2), motion_law(self.law, t)[0])]
        if self.kind == "spring":
            assert self.u_a is not None and self.u_b is not None
            d = pb.r(self.u_b) - pa.r(self.u_a)
            length = float(np.hypot(d[0], d[1]))
            e = d / length
            length_rate = float(e @ (pb.v(self.u_b) - pa.v(self.u_a)))
            tension = self.stiffness * (length - self.free_length) + self.damping * length_rate
            # a tension pulls the two points towards each other
            return [("b", -tension * e, 0.0), ("a", tension * e, 0.0)]
        if self.kind == "torsion_spring":
            tau = self.stiffness * (pb.theta - pa.theta - self.free_angle) + self.damping * (pb.thd - pa.thd)
            return [("b", np.zeros(2), -tau), ("a", np.zeros(2), tau)]
        if self.kind in ("joint_force", "motor", "friction"):
            if self.reads is not None:
                assert read is not None
                f = self.magnitude(*self.reads.joint_coordinate(*read))
            else:
                f = self.magnitude(*self.joint_coordinate(pa, pb))
            if self.axis == "turn":
                return [("b", np.zeros(2), f), ("a", np.zeros(2), -f)]
            assert self.e_local is not None and self.u_a is not None and self.u_b is not None
            # f along n at the slider's point, its reaction on a at a's point and the moment
            # of the reaction's offset d (the axis turns with a)
            n = pa.A @ self.e_local
            d = pb.r(self.u_b) - pa.r(self.u_a)
            return [("b", f * n, 0.0), ("a", -f * n, f * cross(n, d))]
        raise ValueError(f"load {self.name!r} has unknown type {self.kind!r}")


def build_loads(
    desc: dict[str, Any],
    start: dict[str, tuple[float, float, float]],
    length_scale: float,
    constraints: list[Constraint] | None = None,
) -> list[Load]:
    """Compiles and validates the loads; errors name the load."""
    used = {j.get("name") for j in desc.get("joints", [])} | {d.get("name") for d in desc.get("drivers", [])}
    out: list[Load] = []

    def body(name: Any, where: str) -> str:
        if name not in start:
            raise ValueError(f"{where} refers to unknown body {name!r}")
        return str(name)

    def non_negative(where: str, what: str, v: Any) -> float:
        if not (is_finite(v) and float(v) >= 0.0):
            raise ValueError(f"{where}: {what} {v} must be finite and >= 0")
        return float(v)

    def law_of(where: str, ld: dict[str, Any]) -> dict[str, Any]:
        law = ld.get("law")
        if not isinstance(law, dict):
            raise ValueError(f"{where} has no law")
        try:
            check_law(law)
        except ValueError as err:
            raise ValueError(f"{where}: {err}") from None
        return law

    def joint_load(name: str, kind: str, joint_name: Any, where: str) -> Load:
        joint = next((c for c in constraints or [] if c.name == joint_name), None)
        if not isinstance(joint, (Revolute, Prismatic)):
            raise ValueError(f"{where}: {joint_name!r} is not a revolute or prismatic joint")
        load = Load(name, kind, joint.a, joint.b)
        if isinstance(joint, Revolute):
            load.axis = "turn"
        else:
            load.axis, load.e_local = "slide", np.asarray(joint.e_local, dtype=float)
            load.u_a, load.u_b = np.asarray(joint.ua, dtype=float), np.asarray(joint.ub, dtype=float)
        return load

    for ld in desc.get("loads", []):
        kind, name = ld.get("type"), ld.get("name")
        where = f"{kind} load {name!r}"
        if name in used:
            raise ValueError(f"{where}: the name {name!r} is used twice")
        used.add(name)
        if kind == "force":
            b = body(ld.get("body"), where)
            direction = ld.get("direction")
            if not (is_finite(ld.get("at"), 2) and is_finite(direction, 2)):
                raise ValueError(f"{where}: point and direction must be finite")
            norm = float(np.hypot(*np.asarray(direction, dtype=float)))
            if not norm > 0.0:
                raise ValueError(f"{where} has a zero direction")
            load = Load(
                name, kind, GROUND, b, u_b=_local(start[b], ld["at"]),
                direction=np.asarray(direction, dtype=float) / norm, law=law_of(where, ld),
            )  # fmt: skip
        elif kind == "torque":
            load = Load(name, kind, GROUND, body(ld.get("body"), where), law=law_of(where, ld))
        elif kind == "spring":
            a, b = body(ld.get("body_a"), where), body(ld.get("body_b"), where)
            if a == b:
                raise ValueError(f"{where} joins body {a!r} to itself")
            if not (is_finite(ld.get("at_a"), 2) and is_finite(ld.get("at_b"), 2)):
                raise ValueError(f"{where}: its points must be finite")
            gap = math.dist(np.asarray(ld["at_a"], dtype=float), np.asarray(ld["at_b"], dtype=float))
            if gap <= 1e-12 * length_scale:
                raise ValueError(f"{where}: its two points coincide at the start")
            load = Load(
                name, kind, a, b, u_a=_local(start[a], ld["at_a"]), u_b=_local(start[b], ld["at_b"]),
                stiffness=non_negative(where, "stiffness", ld.get("stiffness")),
                free_length=non_negative(where, "free length", ld.get("free_length")),
                damping=non_negative(where, "damping", ld.get("damping", 0.0)),
            )  # fmt: skip
        elif kind == "torsion_spring":
            a, b = body(ld.get("body_a"), where), body(ld.get("body_b"), where)
            if a == b:
                raise ValueError(f"{where} joins body {a!r} to itself")
            if not is_finite(ld.get("free_angle")):
                raise ValueError(f"{where}: free angle {ld.get('free_angle')} is not finite")
            load = Load(
                name, kind, a, b, free_angle=float(ld["free_angle"]),
                stiffness=non_negative(where, "stiffness", ld.get("stiffness")),
                damping=non_negative(where, "damping", ld.get("damping", 0.0)),
            )  # fmt: skip
        elif kind in ("joint_force", "motor", "friction"):
            load = joint_load(name, kind, ld.get("joint"), where)
            other = ld.get("of_joint") if kind == "joint_force" else None
            if other is not None and other != ld.get("joint"):
                load.reads = joint_load(str(other), "joint", other, where)
                # the law's argument is in the unit of the joint it reads
                load.reads.scale = float(ld.get("of_scale", 1.0))
            if kind == "joint_force":
                if ld.get("of", "coordinate") not in ("coordinate", "rate"):
                    raise ValueError(f"{where}: of must be coordinate or rate")
                load.law, load.of_rate = law_of(where, ld), ld.get("of") == "rate"
                load.scale = float(ld.get("scale", 1.0)) if load.reads is None else load.reads.scale
            elif kind == "motor":
                load.stall, load.no_load_speed = float(ld["stall"]), float(ld["no_load_speed"])
                load.clip = bool(ld.get("clip", False))
                if not (
                    is_finite(load.stall) and is_finite(load.no_load_speed) and load.no_load_speed != 0.0
                ):
                    raise ValueError(f"{where}: stall and no-load speed must be finite, the speed non-zero")
            else:
                load.viscous = non_negative(where, "viscous coefficient", ld.get("viscous", 0.0))
                load.coulomb = non_negative(where, "Coulomb friction", ld.get("coulomb", 0.0))
                if load.coulomb > 0.0:
                    eps = ld.get("smoothing")
                    if not (is_finite(eps) and float(eps) > 0.0):
                        raise ValueError(f"{where}: Coulomb friction needs a smoothing rate > 0")
                    load.smoothing = float(eps)
        else:
            raise ValueError(f"load {name!r} has unknown type {kind!r}")
        if load.a == GROUND and load.b == GROUND:
            raise ValueError(f"{where} acts on the ground only, which cannot move")
        out.append(load)
    return out


def anchor_b(c: Constraint) -> np.ndarray:
    """The local vector, on side b, of the point a constraint's reaction torque is taken
    about: the pin or slide point, the driven point, or b's origin (welds and angle
    drivers)."""
    if isinstance(
        c, (Revolute, Prismatic, DistanceDriver, DistanceJoint, PointOnLine, RackPinion, CurveJoint)
    ):
        return np.asarray(c.ub, dtype=float)
    if isinstance(c, TranslationDriver):
        return np.asarray(c.joint.ub, dtype=float)
    if isinstance(c, CoordinateDriver):
        return np.asarray(c.u, dtype=float)
    if isinstance(
        c, (Fixed, AngleDriver, RelativeAngleDriver, GearPair, FixedOrientation, Parallel, LinearCoupling)
    ):
        return np.zeros(2)
    raise TypeError(f"no anchor for constraint type {type(c).__name__}")


def cross(r: np.ndarray, f: np.ndarray) -> float:
    """z component of r x f."""
    return float(r[0] * f[1] - r[1] * f[0])


def point_force(Bu: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Generalized force (x, y, theta) of the world force F at a point with B u = Bu."""
    return np.array([F[0], F[1], float(Bu @ F)])


# --- assembled over the whole model ---------------------------------------------------------------
# The functions below take a ReferenceModel (``ref``): its bodies, columns, constraints and
# rows, its Phi_q and nu, and the mass properties and loads it compiled with the functions
# above.


def mass_matrix(ref: ReferenceModel, q: np.ndarray) -> np.ndarray:
    """M(q) (n_coords x n_coords), block-diagonal."""
    M = np.zeros((ref.n_coords, ref.n_coords))
    for name in ref.body_names:
        i = ref._col[name]
        M[i : i + 3, i : i + 3] = body_mass_matrix(ref.mass_properties[name], float(q[i + 2]))
    return M


def generalized_forces(ref: ReferenceModel, q: np.ndarray, qd: np.ndarray, t: float) -> dict[str, np.ndarray]:
    """The terms of Q (n_coords each): "velocity" (quadratic velocity terms), "gravity"
    and "loads". Q is their sum."""
    g = np.asarray(ref.gravity, dtype=float)
    Q_v = np.zeros(ref.n_coords)
    Q_g = np.zeros(ref.n_coords)
    Q_loads = np.zeros(ref.n_coords)
    for name in ref.body_names:
        i = ref._col[name]
        mp = ref.mass_properties[name]
        pose = ref._pose(name, q, qd)
        Q_v[i : i + 2] = mp.mass * pose.thd**2 * (pose.A @ mp.u_c)
        Q_g[i : i + 3] = point_force(pose.B @ mp.u_c, mp.mass * g)
    for load in ref.loads:
        pa, pb = ref._pose(load.a, q, qd), ref._pose(load.b, q, qd)
        r = load.reads
        read = None if r is None else (ref._pose(r.a, q, qd), ref._pose(r.b, q, qd))
        for side, F, torque in load.forces(pa, pb, t, read):
            body, pose, u = (load.b, pb, load.u_b) if side == "b" else (load.a, pa, load.u_a)
            if body == GROUND:
                continue
            i = ref._col[body]
            Bu = pose.B @ u if u is not None else np.zeros(2)
            Q_loads[i : i + 3] += point_force(Bu, F)
            Q_loads[i + 2] += torque
    return {"velocity": Q_v, "gravity": Q_g, "loads": Q_loads}


def reactions(ref: ReferenceModel, q: np.ndarray, qd: np.ndarray, lam: np.ndarray, t: float) -> np.ndarray:
    """(n_constraints x 4): for each constraint, the force (Fx, Fy) it exerts on its side
    b, the torque about its anchor on b, and the power it delivers.

    The power is what the constraint's generalized forces do on the velocities,
    Q_a . qd_a + Q_b . qd_b = -lambda_k . (Phi_q qd)_k: zero for a joint, a driver's effort
    times its rate in motion (there Phi_q qd = nu), and zero at rest (qd = 0).
    """
    out = np.zeros((len(ref.constraints), 4))
    for k, (c, r) in enumerate(zip(ref.constraints, ref._row)):
        pa, pb = ref._pose(c.a, q, qd), ref._pose(c.b, q, qd)
        own = ref._own(c, q, qd)
        jac_a, jac_b = c.jacobian(pa, pb, t, **own)
        lam_k = lam[r : r + c.n_rows]
        Q_a = -(jac_a.T @ lam_k)
        Q_b = -(jac_b.T @ lam_k)  # (Fx, Fy, moment about b's origin)
        F = Q_b[:2]
        arm = pb.A @ anchor_b(c)  # from b's origin to the anchor, world axes
        out[k, 0:2] = F
        out[k, 2] = Q_b[2] - cross(arm, F)
        power = 0.0
        for body, Q_side, pose in ((c.a, Q_a, pa), (c.b, Q_b, pb)):
            if body != GROUND:
                power += float(Q_side @ np.array([pose.Rd[0], pose.Rd[1], pose.thd]))
        out[k, 3] = power
    return out


def inverse_dynamics(
    ref: ReferenceModel, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, t: float
) -> dict[str, Any]:
    """Solves Phi_q^T lambda = Q - M qdd at one state.

    Returns "lambda" (n_rows), "reactions" (n_constraints x 4, as ``reactions``), "Q"
    (n_coords, the total), "Q_parts" (``generalized_forces``), "M", "efforts" (driver name
    -> -lambda of its row) and "load_power" (Q_loads . qd).
    """
    q, qd, qdd = (np.asarray(x, dtype=float) for x in (q, qd, qdd))
    M = mass_matrix(ref, q)
    parts = generalized_forces(ref, q, qd, t)
    Q = parts["velocity"] + parts["gravity"] + parts["loads"]
    phi_q = ref.phi_q(q, t)
    if phi_q.shape[0] != phi_q.shape[1]:
        raise ValueError(
            f"inverse dynamics needs a square Phi_q, got {phi_q.shape[0]} rows x {phi_q.shape[1]} coordinates"
        )
    lam = np.linalg.solve(phi_q.T, Q - M @ qdd)
    efforts = {c.name: -float(lam[r]) for c, r in zip(ref.constraints, ref._row) if c.kind in DRIVER_KINDS}
    return {
        "lambda": lam,
        "reactions": reactions(ref, q, qd, lam, t),
        "Q": Q,
        "Q_parts": parts,
        "M": M,
        "efforts": efforts,
        "load_power": float(parts["loads"] @ qd),
    }


def sweep_forces(ref: ReferenceModel, times: Any) -> dict[str, Any]:
    """``ref.sweep(times)`` followed by the inverse dynamics at every step. Adds "lambda"
    (n_steps x n_rows), "reactions" (n_steps x n_constraints x 4), "efforts" (driver name
    -> (n_steps,)) and "load_power" (n_steps,) to the kinematics."""
    out = ref.sweep(times)
    n = out["times"].size
    out["lambda"] = np.zeros((n, ref.n_rows))
    out["reactions"] = np.zeros((n, len(ref.constraints), 4))
    out["load_power"] = np.zeros(n)
    drivers = [c.name for c in ref.constraints if c.kind in DRIVER_KINDS]
    out["efforts"] = {name: np.zeros(n) for name in drivers}
    for k, t in enumerate(out["times"]):
        step = inverse_dynamics(ref, out["q"][k], out["qd"][k], out["qdd"][k], float(t))
        out["lambda"][k] = step["lambda"]
        out["reactions"][k] = step["reactions"]
        out["load_power"][k] = step["load_power"]
        for name in drivers:
            out["efforts"][name][k] = step["efforts"][name]
    return out


def energy(ref: ReferenceModel, q: np.ndarray, qd: np.ndarray) -> tuple[float, float]:
    """(kinetic energy 1/2 qd^T M qd, gravitational potential -sum m g . r_c) at one state."""
    q, qd = np.asarray(q, dtype=float), np.asarray(qd, dtype=float)
    g = np.asarray(ref.gravity, dtype=float)
    kinetic = 0.5 * float(qd @ mass_matrix(ref, q) @ qd)
    potential = -sum(
        ref.mass_properties[name].mass * float(g @ ref._pose(name, q).r(ref.mass_properties[name].u_c))
        for name in ref.body_names
    )
    return kinetic, float(potential)

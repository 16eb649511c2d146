"""The source document's chained Stephenson six-bar, designed by precision points and
analysed for input torque: every dyad solution, the printed answer checked, every
combination assembled and screened, and the torque over a cycle two independent ways.

The document: a coupler carrying B, D and the point P passes P1..P5 while the input
link QA turns about Q by phi_n and the coupler turns by theta_n. Dyad 1 (A on QA, B on
the coupler) keeps |A - B|; dyad 2 (D on the coupler, C on a link DC that the chain turns
by phi_n) keeps C on a circle about the origin O.

Reading chosen (and why): the chain is taken at its kinematic word, "DC turns by phi_n
as QA does": one row theta_DC - theta_QA = const, the engine's belt joint with ratio 1
and the ground as carrier (an open chain over equal sprockets). With five moving bodies
(QA, AB, coupler, DC, OC), six revolutes (Q, A, B, D, C, O) and the chain, the mechanism
the equations define has mobility 15 - 12 - 1 = 2: the prescribed coupler rotations
theta_n are a second input. The model drives QA (phi) and the coupler (theta) on one
schedule: the crank turns once, t = its rotation (rad), and theta(t) is a natural cubic
spline through the five precision values and back to 0 at the end of the turn.

Mass properties (stated for the torque example, SI with lengths read as metres): the
coupler only, mass 2 kg at the centroid of triangle B D P at position 1, 0.5 kg m^2 about
it; gravity 9.81 m/s^2 down -y; the crank turns at 1 rad/s.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from . import synthesis as S
from .errors import SolveError
from .mechanism import Mechanism
from .motion import Linear, Spline

POINTS = np.array([[1.0, 2.8], [-2.8, -3.8], [-8.3, -7.3], [-8.9, -6.7], [-7.2, 3.2]])
Q = np.array([-3.7, 12.9])
PHI_DEG = np.array([0.0, -45.0, -90.0, -150.0, -210.0])
THETA_DEG = np.array([0.0, 0.5, 16.5, 27.0, 27.0])
#: the document's link-length table a1..a5
LINK_TABLE = (10.0, 20.4, 8.2, 7.2, 20.1)
#: the document's printed answer (Newton from one start)
PRINTED = {"A1": (4.368, -3.770), "B1": (-1.599, 11.49), "C1": (18.43, 20.37), "D1": (12.23, 22.38)}
#: the printed program input differs in two numbers
PROGRAM_INPUT = {"P4x": -8.30, "Qx": -8.70}
MASS, INERTIA, OMEGA = 2.0, 0.5, 1.0


def _rot(a: float) -> np.ndarray:
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


def residuals(
    a1: np.ndarray,
    b1: np.ndarray,
    c1: np.ndarray,
    d1: np.ndarray,
    points: np.ndarray = POINTS,
    q: np.ndarray = Q,
) -> tuple[np.ndarray, np.ndarray]:
    """The two dyads' equations at positions 1..5, in world length units: the change of
    |A_n - B_n| and of |C_n - O| from position 1."""
    phi, theta = np.radians(PHI_DEG), np.radians(THETA_DEG)
    r1, r2 = [], []
    for n in range(5):
        an = q + _rot(phi[n]) @ (a1 - q)
        bn = points[n] + _rot(theta[n]) @ (b1 - points[0])
        r1.append(np.hypot(*(an - bn)) - np.hypot(*(a1 - b1)))
        dn = points[n] + _rot(theta[n]) @ (d1 - points[0])
        cn = dn + _rot(phi[n]) @ (c1 - d1)
        r2.append(np.hypot(*cn) - np.hypot(*c1))
    return np.array(r1), np.array(r2)


def printed_answer_check() -> list[tuple[str, float, float]]:
    """Largest residual of the printed answer's two dyads under the stated data and under
    the printed program input's variants: (which data, dyad 1, dyad 2)."""
    a1, b1, c1, d1 = (np.array(PRINTED[k]) for k in ("A1", "B1", "C1", "D1"))
    out = []
    for p4x, qx in itertools.product((POINTS[3, 0], PROGRAM_INPUT["P4x"]), (Q[0], PROGRAM_INPUT["Qx"])):
        pts = POINTS.copy()
        pts[3, 0] = p4x
        q = np.array([qx, Q[1]])
        r1, r2 = residuals(a1, b1, c1, d1, pts, q)
        out.append((f"P4x = {p4x:g}, Qx = {qx:g}", float(np.abs(r1).max()), float(np.abs(r2).max())))
    return out


def dyads(method: str = "homotopy") -> tuple[S.DyadSolutions, S.DyadSolutions]:
    """Every solution of both dyad systems."""
    kw = dict(points=POINTS, input_angles=PHI_DEG, coupler_angles=THETA_DEG, angles="deg", method=method)
    return S.dyads("chain1", pivot=Q, **kw), S.dyads("chain2", **kw)


def _angle(u: np.ndarray, v: np.ndarray) -> float:
    return math.atan2(float(v[1] - u[1]), float(v[0] - u[0]))


def schedule() -> tuple[np.ndarray, np.ndarray]:
    """Spline knots of theta(t) (t = crank rotation, rad): the precision positions and the
    end of the turn."""
    t = np.append(-np.radians(PHI_DEG), 2.0 * math.pi)
    return t, np.append(np.radians(THETA_DEG), 0.0)


def model(one: S.Dyad, two: S.Dyad) -> Mechanism:
    """The six-bar at position 1 from a dyad-1 solution (A1 = ground, B1 = moving) and a
    dyad-2 solution (C1 = ground, D1 = moving)."""
    a1, b1, c1, d1 = one.ground, one.moving, two.ground, two.moving
    p1, o = POINTS[0], np.zeros(2)
    m = Mechanism("chained six-bar")
    qa = m.body("QA", tuple(Q), _angle(Q, a1))
    ab = m.body("AB", tuple(a1), _angle(a1, b1))
    coupler = m.body("coupler", tuple(p1), 0.0)
    dc = m.body("DC", tuple(d1), _angle(d1, c1))
    oc = m.body("OC", (0.0, 0.0), _angle(o, c1))
    m.revolute(m.ground, qa, tuple(Q), name="Q")
    m.revolute(qa, ab, tuple(a1), name="A")
    m.revolute(ab, coupler, tuple(b1), name="B")
    m.revolute(coupler, dc, tuple(d1), name="D")
    m.revolute(dc, oc, tuple(c1), name="C")
    m.revolute(m.ground, oc, (0.0, 0.0), name="O")
    m.belt(qa, dc, ratio=1.0, name="chain")
    m.point("P", coupler, tuple(p1))
    t, th = schedule()
    m.drive_angle(qa, Linear(_angle(Q, a1), -OMEGA), name="phi")
    m.drive_angle(coupler, Spline([float(v) / OMEGA for v in t], [float(v) for v in th]), name="theta")
    centroid = (b1 + d1 + p1) / 3.0
    m.set_mass(coupler, MASS, INERTIA, tuple(centroid))
    m.set_gravity((0.0, -9.81))
    return m


@dataclass
class Combination:
    """One dyad-1 and dyad-2 pair, assembled and swept over the cycle."""

    one: S.Dyad
    two: S.Dyad
    completed: bool
    stopped_at: float | None
    position_error: tuple[float, ...]
    events: int
    message: str

    @property
    def ok(self) -> bool:
        return self.completed and max(self.position_error) < 1e-6 and self.events == 0


def screen(one: S.Dyad, two: S.Dyad, steps: int = 720) -> Combination:
    """Sweep a combination over the turn; check every precision position is met."""
    t_prec = -np.radians(PHI_DEG) / OMEGA
    grid = np.union1d(np.linspace(0.0, 2.0 * math.pi / OMEGA, steps + 1), t_prec)
    compiled = model(one, two).compile()
    message, stopped = "", None
    try:
        res = compiled.sweep(grid, derivatives=0, on_singular="stop")
    except SolveError as e:
        res, stopped, message = getattr(e, "partial", None), getattr(e, "time", None), str(e).splitlines()[0]
    n = 0 if res is None else len(res.times)
    errs = []
    for j, tj in enumerate(t_prec):
        k = int(np.searchsorted(grid, tj))
        if res is None or k >= n:
            errs.append(math.inf)
        else:
            errs.append(float(np.hypot(*(res.point("P").position[k] - POINTS[j]))))
    return Combination(
        one, two, n == len(grid), stopped, tuple(errs), 0 if res is None else len(res.events), message
    )


@dataclass
class Torque:
    """Input torques over the cycle (N m): ``phi`` on QA (the motor at sprocket 1; it
    includes what the chain passes to DC), ``chain`` the chain's torque on DC (sprocket
    2), ``theta`` the second input's on the coupler; ``total`` = phi + theta summed onto
    one shaft turning at the crank's rate; ``virtual_work``: the same total from
    d(T + V)/dt over the crank rate, computed from the motion alone (no multipliers)."""

    t: np.ndarray
    phi: np.ndarray
    chain: np.ndarray
    theta: np.ndarray
    total: np.ndarray
    virtual_work: np.ndarray


def torque(one: S.Dyad, two: S.Dyad, steps: int = 2000) -> Torque:
    """Inverse dynamics of a combination over the turn, checked by virtual work."""
    t = np.linspace(0.0, 2.0 * math.pi / OMEGA, steps + 1)
    res = model(one, two).compile().sweep(t, forces=True)
    tau_phi, tau_theta = res.effort("phi"), res.effort("theta")
    # sum onto the crank shaft by power: tau_total * omega_crank = sum of driver powers
    w_phi = -OMEGA
    total = (res.power("phi") + res.power("theta")) / w_phi
    chain = res.reaction("chain").torque
    # virtual work: the power in equals (T + V)' = m v.a + J w w' + m g v_y, from the
    # engine's kinematics alone (velocities and accelerations, no multipliers)
    c = res.body("coupler")
    com = res.point_at("coupler", tuple((one.moving + two.moving + POINTS[0]) / 3.0 - POINTS[0]))
    v, a = com.velocity, com.acceleration
    assert v is not None and a is not None and c.thetad is not None and c.thetadd is not None
    power = MASS * np.sum(v * a, axis=1) + INERTIA * c.thetad * c.thetadd + MASS * 9.81 * v[:, 1]
    vw = power / w_phi
    return Torque(t, tau_phi, np.asarray(chain), tau_theta, total, vw)


def report() -> str:
    """The whole study as text (docs/synthesis.md carries its output)."""
    one, two = dyads()
    r_one, r_two = dyads("resultant")
    lines = ["Chained six-bar (source document): dyad solutions"]
    for name, s, r in (("dyad 1 (A1, B1)", one, r_one), ("dyad 2 (C1, D1)", two, r_two)):
        lines.append(
            f"  {name}: {len(s)} roots ({len(s.real)} real), {s.paths} paths, {s.at_infinity} at infinity, "
            f"{s.failed} failed, all certified: {all(d.certified for d in s)}; "
            f"elimination finds {len(r)} ({len(r.real)} real)"
        )
        for d in s.real:
            lines.append(
                f"    ({d.ground[0]:.4f}, {d.ground[1]:.4f})  ({d.moving[0]:.4f}, {d.moving[1]:.4f})  "
                f"residual {d.residual:.1e}"
            )
    lines.append("  printed answer A1 B1 C1 D1, largest residual (length units) of dyad 1, dyad 2:")
    for which, e1, e2 in printed_answer_check():
        lines.append(f"    {which}: {e1:.3f}, {e2:.3f}")
    lines.append("  combinations swept over one turn of QA (theta on its spline schedule):")
    combos = [screen(a, b) for a in one.real for b in two.real]
    for c in combos:
        err = max(c.position_error)
        state = "completes" if c.completed else f"stops at t = {c.stopped_at:.4g}: {c.message}"
        lines.append(
            f"    A1 ({c.one.ground[0]:.3f}, {c.one.ground[1]:.3f}) "
            f"C1 ({c.two.ground[0]:.3f}, {c.two.ground[1]:.3f}): "
            f"{state}; precision error {err:.1e}; events {c.events}"
        )
    good = [c for c in combos if c.ok]
    if good:
        best = good[0]
        tq = torque(best.one, best.two)
        lines.append(
            f"  torque of the first defect-free combination over the turn: phi {np.abs(tq.phi).max():.4g}, "
            f"theta {np.abs(tq.theta).max():.4g}, summed {np.abs(tq.total).max():.4g} N m (peaks); "
            f"virtual work agrees to {np.abs(tq.total - tq.virtual_work).max():.2e} N m"
        )
    else:
        lines.append("  no combination completes the turn without a defect")
    return "\n".join(lines)

"""The chained Stephenson six-bar by precision points, for any data: every dyad solution
of both dyad problems, certified, every real combination assembled as a six-bar, swept by
the engine and judged over its precision-point stroke, and the input torque over a turn
two independent ways.

The mechanism: a coupler carrying B, D and the point P passes P_1..P_n (n = 5) while the
input link QA turns about the input pivot Q by phi_n and the coupler turns by theta_n
(both from position 1). Dyad 1 (A_1 on QA, B_1 on the coupler) keeps |A - B|; dyad 2 (D_1
on the coupler, C_1 on the link DC that the chain turns by phi_n as QA) keeps C on a
circle about the output pivot O. Bodies QA, AB, coupler, DC, OC; revolutes Q, A, B, D, C,
O; the chain is the engine's belt with ratio 1 and the ground as carrier (theta_DC -
theta_QA = const). Mobility 2: the coupler's rotation is a second input, so a design's
model drives QA ("phi") and the coupler ("theta") on one schedule: t is the input's
rotation from position 1 (rad, in the direction that meets the positions in order) and
theta(t) a natural cubic spline through the precision values and back to theta_1 after
a whole turn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import SingularError, SolveError, SynthesisError
from ..mechanism.builder import Mechanism
from ..motion import Linear, Spline
from .designs import DyadDesign, _order
from .dyad import POSITION_TOLERANCE, Dyad, DyadSolutions, _angles, _array, dyads

__all__ = [
    "ChainedSixBarDesign",
    "ChainedSixBarSynthesis",
    "SixBarDefects",
    "Torque",
    "chained_six_bar",
    "residuals",
    "torque",
]

#: Sweep events that make a stroke defective when met before its last position: the
#: mechanism cannot pass them driven as prescribed (a limit) or may leave its branch there.
SINGULAR_EVENTS = ("limit", "bifurcation", "branch_jump")


def _rot(a: float) -> np.ndarray:
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


def _angle(u: np.ndarray, v: np.ndarray) -> float:
    return math.atan2(float(v[1] - u[1]), float(v[0] - u[0]))


def residuals(
    a1: Any,
    b1: Any,
    c1: Any,
    d1: Any,
    points: Any,
    input_angles: Any,
    coupler_angles: Any,
    input_pivot: Any,
    output_pivot: Any,
) -> tuple[np.ndarray, np.ndarray]:
    """The two dyads' equations at every position (angles in rad), in length units: the
    change of |A_n - B_n| and of |C_n - O| from position 1."""
    pts = np.asarray(points, dtype=float)
    q, o = np.asarray(input_pivot, dtype=float), np.asarray(output_pivot, dtype=float)
    a1, b1, c1, d1 = (np.asarray(v, dtype=float) for v in (a1, b1, c1, d1))
    phi = np.asarray(input_angles, dtype=float) - float(input_angles[0])
    theta = np.asarray(coupler_angles, dtype=float) - float(coupler_angles[0])
    r1, r2 = [], []
    for n in range(len(pts)):
        an = q + _rot(phi[n]) @ (a1 - q)
        bn = pts[n] + _rot(theta[n]) @ (b1 - pts[0])
        r1.append(np.hypot(*(an - bn)) - np.hypot(*(a1 - b1)))
        dn = pts[n] + _rot(theta[n]) @ (d1 - pts[0])
        cn = dn + _rot(phi[n]) @ (c1 - d1)
        r2.append(np.hypot(*(cn - o)) - np.hypot(*(c1 - o)))
    return np.array(r1), np.array(r2)


@dataclass(frozen=True)
class SixBarDefects:
    """What the engine found driving a six-bar from position 1 over a whole turn of its
    input, in the direction that meets the positions in order, with the coupler on its
    schedule.

    The stroke is the input's rotation from position 1 to the last position. ``order``:
    the input does not meet the positions in the prescribed order, turning either way.
    ``branch``: before the last position, the sweep meets a limit of motion, a
    bifurcation or a branch jump (``events``), or cannot go on: reaching the positions
    beyond needs the input reversed or the linkage taken apart. ``circuit``: a position
    is met at its input rotation but on the other assembly (with phi and theta driven,
    the coupler's place solves two circle conditions, B about A and C about O: two
    assemblies). ``full_turn`` (a property, not a defect): the input turns a whole
    revolution with no such event. ``reached[j]`` / ``error[j]``: position j + 1 met on
    the design's assembly, and the distance of P from it there (inf if not reached).
    ``events``: (kind, input rotation from position 1) of the singular events met over
    the turn, and ``stopped``: the input rotation where the sweep could not go on (None:
    it completed the turn). ``stroke`` and ``targets`` (the positions' input rotations)
    are read from position 1 in the input's ``direction`` (+1 counterclockwise).
    """

    order: bool
    branch: bool
    circuit: bool
    full_turn: bool
    reached: tuple[bool, ...]
    error: tuple[float, ...]
    events: tuple[tuple[str, float], ...]
    stopped: float | None
    stroke: float
    targets: tuple[float, ...]
    direction: int

    @property
    def ok(self) -> bool:
        """No order, branch or circuit defect over the stroke."""
        return not (self.order or self.branch or self.circuit)

    def where(self) -> str:
        """Which property fails and where, in a line."""
        out = []
        if self.order:
            out.append("order: the input does not meet the positions in order turning either way")
        if self.branch:
            first = next((e for e in self.events if e[1] <= self.stroke), None)
            at = first[1] if first is not None else self.stopped
            cause = f"{first[0]} at" if first is not None else "the sweep stops at"
            cause = f"{cause} input rotation {math.degrees(at):.4g} deg" if at is not None else "not reached"
            after = [j + 1 for j, t in enumerate(self.targets) if at is not None and t >= at]
            out.append(f"branch: {cause}" + (f" before position {after[0]}" if after else ""))
        if self.circuit:
            wrong = [
                f"P{j + 1} (off by {self.error[j]:.3g})"
                for j, r in enumerate(self.reached)
                if not r and not math.isinf(self.error[j])
            ]
            out.append("circuit: met on the other assembly at " + ", ".join(wrong))
        return "; ".join(out) if out else "defect-free"

    def __str__(self) -> str:
        turn = "turns fully" if self.full_turn else "does not turn fully"
        if not self.full_turn:
            limit = next((e for e in self.events), None)
            if limit is not None:
                turn += f" ({limit[0]} at {math.degrees(limit[1]):.4g} deg)"
            elif self.stopped is not None:
                turn += f" (stops at {math.degrees(self.stopped):.4g} deg)"
        worst = max((e for e in self.error if not math.isinf(e)), default=math.nan)
        return (
            f"{self.where()}; stroke {math.degrees(self.stroke):.4g} deg, "
            f"largest precision error {worst:.1e}; input {turn}"
        )


@dataclass
class ChainedSixBarDesign(DyadDesign):
    """One chained six-bar: dyad 1 (``a1`` on the input link QA, ``b1`` on the coupler)
    and dyad 2 (``d1`` on the coupler, ``c1`` on the link DC), with the input pivot ``q``
    and the output pivot ``o``, all at position 1; ``p``: the coupler point at position
    1. ``positions``: the precision points (n x 2); ``input_angles`` / ``coupler_angles``:
    phi_n and theta_n from position 1 (rad); ``dyads``: the two dyad solutions."""

    q: np.ndarray
    o: np.ndarray
    a1: np.ndarray
    b1: np.ndarray
    c1: np.ndarray
    d1: np.ndarray
    positions: np.ndarray
    input_angles: np.ndarray
    coupler_angles: np.ndarray
    dyads: tuple[Dyad, Dyad]
    _defects: SixBarDefects | None = field(default=None, repr=False)

    @property
    def p(self) -> np.ndarray:
        return self.positions[0]

    @property
    def lengths(self) -> dict[str, float]:
        d = lambda u, v: float(np.hypot(*(u - v)))  # noqa: E731
        return {
            "QO": d(self.q, self.o),
            "QA": d(self.q, self.a1),
            "AB": d(self.a1, self.b1),
            "BD": d(self.b1, self.d1),
            "DC": d(self.d1, self.c1),
            "OC": d(self.o, self.c1),
        }

    def schedule(self) -> tuple[int, np.ndarray, np.ndarray]:
        """(direction, knots t, theta at the knots): the input turns ``direction`` (+1
        counterclockwise, -1 clockwise) and t is its rotation from position 1; the
        coupler's rotation passes theta_n at the positions' t and returns to its start
        after a whole turn. Out of order, the knots are the positions' t sorted."""
        rot = self.input_angles - self.input_angles[0]
        direction, _ = _order(rot)
        t = np.mod(direction * rot, 2.0 * math.pi)
        t[0] = 0.0
        k = np.argsort(t, kind="stable")
        return direction, np.append(t[k], 2.0 * math.pi), np.append(self.coupler_angles[k], 0.0)

    def precision_times(self) -> np.ndarray:
        """The time of `model` (omega 1) at each precision position, in the positions'
        order: the input's rotation from position 1 the schedule's way, in [0, 2 pi)."""
        direction, _, _ = self.schedule()
        t = np.mod(direction * (self.input_angles - self.input_angles[0]), 2.0 * math.pi)
        t[0] = 0.0
        return t

    def model(self, name: str = "chained six-bar", omega: float = 1.0) -> Mechanism:
        """The design as a linkwork mechanism at position 1: bodies "QA", "AB",
        "coupler", "DC", "OC"; revolutes "Q", "A", "B", "D", "C", "O"; the belt "chain"
        (QA to DC, ratio 1); point "P" on the coupler; drivers "phi" (QA's angle, turning
        at ``omega`` rad/s in the schedule's direction) and "theta" (the coupler's angle
        on the schedule's spline in omega t)."""
        q, o, a1, b1, c1, d1, p1 = self.q, self.o, self.a1, self.b1, self.c1, self.d1, self.p
        m = Mechanism(name)
        qa = m.body("QA", tuple(q), _angle(q, a1))
        ab = m.body("AB", tuple(a1), _angle(a1, b1))
        coupler = m.body("coupler", tuple(p1), 0.0)
        dc = m.body("DC", tuple(d1), _angle(d1, c1))
        oc = m.body("OC", tuple(o), _angle(o, c1))
        m.revolute(m.ground, qa, tuple(q), name="Q")
        m.revolute(qa, ab, tuple(a1), name="A")
        m.revolute(ab, coupler, tuple(b1), name="B")
        m.revolute(coupler, dc, tuple(d1), name="D")
        m.revolute(dc, oc, tuple(c1), name="C")
        m.revolute(m.ground, oc, tuple(o), name="O")
        m.belt(qa, dc, ratio=1.0, name="chain")
        m.point("P", coupler, tuple(p1))
        direction, t, theta = self.schedule()
        m.drive_angle(qa, Linear(_angle(q, a1), direction * omega), name="phi")
        m.drive_angle(coupler, Spline([float(v) / omega for v in t], [float(v) for v in theta]), name="theta")
        return m

    @property
    def defects(self) -> SixBarDefects:
        """The engine's screening over the stroke and the turn (computed once)."""
        if self._defects is None:
            self._defects = _screen(self)
        return self._defects

    def __str__(self) -> str:
        f = lambda v: f"({v[0]:.6g}, {v[1]:.6g})"  # noqa: E731
        return (
            f"chained six-bar A1 {f(self.a1)} B1 {f(self.b1)} C1 {f(self.c1)} D1 {f(self.d1)}; "
            f"residual {self.residual:.1e}{'' if self.certified else ', NOT certified'}; {self.defects}"
        )


def _screen(design: ChainedSixBarDesign, steps: int = 720) -> SixBarDefects:
    """Sweep the design over a whole turn of its input (one assembly, followed from
    position 1) and judge the stroke: every position reached, in order, on that assembly,
    with no singular event before the last."""
    rot = design.input_angles - design.input_angles[0]
    direction, in_order = _order(rot)
    targets = np.mod(direction * rot, 2.0 * math.pi)
    targets[0] = 0.0
    stroke = float(targets.max()) if in_order else 2.0 * math.pi
    grid = np.union1d(np.linspace(0.0, 2.0 * math.pi, steps + 1), targets)
    compiled = design.model().compile()
    stopped: float | None = None
    res: Any
    try:
        # "continue": limits, bifurcations and branch jumps are reported as events and
        # judged below (a bifurcation passed on the same branch still counts before the
        # last position); the sweep raises only where it cannot go on
        res = compiled.sweep(grid, derivatives=0, on_singular="continue")
    except (SingularError, SolveError) as e:
        res = getattr(e, "partial", None)
        t_stop = getattr(e, "time", None)
        n_done = 0 if res is None else len(res.times)
        stopped = float(t_stop) if t_stop is not None else float(grid[min(n_done, len(grid) - 1)])
    events = tuple(
        (ev.kind, float(ev.time))
        for ev in (res.events if res is not None else [])
        if ev.kind in SINGULAR_EVENTS
    )
    n_done = 0 if res is None else len(res.times)
    size = max(design.lengths.values())
    tolerance = POSITION_TOLERANCE * size
    reached: list[bool] = []
    errors: list[float] = []
    branch = circuit = False
    for j, tj in enumerate(targets):
        k = int(np.searchsorted(grid, tj))
        if res is None or k >= n_done or (stopped is not None and tj >= stopped):
            reached.append(False)
            errors.append(math.inf)
            branch = True
            continue
        err = float(np.hypot(*(res.point("P").position[k] - design.positions[j])))
        reached.append(err <= tolerance)
        errors.append(err)
        circuit |= err > tolerance
    # the events condition: a singular event before the last position is a branch defect
    # even when every position is still met. At a limit the sweep stops too (positions
    # beyond are not reached either way); a bifurcation or branch jump it passes on its
    # branch is caught by this alone.
    branch |= any(t <= stroke for _, t in events)
    return SixBarDefects(
        order=not in_order,
        branch=branch,
        circuit=circuit,
        full_turn=stopped is None and not events,
        reached=tuple(reached),
        error=tuple(errors),
        events=events,
        stopped=stopped,
        stroke=stroke,
        targets=tuple(float(t) for t in targets),
        direction=direction,
    )


@dataclass
class ChainedSixBarSynthesis:
    """The chained six-bar's synthesis: ``dyads`` (dyad 1 then dyad 2, every root with
    its certificate), ``designs`` (every combination of a real dyad 1 with a real dyad 2,
    defect-free first, then those whose input turns fully), and the data."""

    points: np.ndarray
    input_angles: np.ndarray
    coupler_angles: np.ndarray
    input_pivot: np.ndarray
    output_pivot: np.ndarray
    dyads: list[DyadSolutions]
    designs: list[ChainedSixBarDesign]
    problem: str = "chained six-bar"

    @property
    def defect_free(self) -> list[ChainedSixBarDesign]:
        return [d for d in self.designs if d.defects.ok]

    def report(self) -> str:
        """Every root of both dyads (by role), then every combination: which property
        fails and where."""
        f = lambda v: f"({v[0]:.6g}, {v[1]:.6g})"  # noqa: E731
        lines = [
            f"{self.problem}: {len(self.points)} positions, input pivot Q {f(self.input_pivot)}, "
            f"output pivot O {f(self.output_pivot)}"
        ]
        for s, name, pin, body in (
            (self.dyads[0], "dyad 1", "A1 (on QA)", "B1 (on the coupler)"),
            (self.dyads[1], "dyad 2", "C1 (on DC)", "D1 (on the coupler)"),
        ):
            lines += s.report_lines(name, pin, body, gap="  ")
        lines.append(
            f"  designs: {len(self.designs)} combinations ({len(self.defect_free)} defect-free over the "
            f"stroke, {sum(d.defects.full_turn for d in self.designs)} turning fully)"
        )
        for i, design in enumerate(self.designs, 1):
            lines.append(f"    {i}. {design}")
        return "\n".join(lines)


def chained_six_bar(
    points: Any,
    input_angles: Any,
    coupler_angles: Any,
    input_pivot: Any,
    output_pivot: Any,
    angles: str = "rad",
    method: str = "homotopy",
) -> ChainedSixBarSynthesis:
    """Every chained six-bar that carries the coupler point through 5 ``points`` while
    the input link turns about ``input_pivot`` (Q) by ``input_angles`` and the coupler by
    ``coupler_angles`` (both read from position 1), with the output link about
    ``output_pivot`` (O).

    Both dyad problems are solved completely (``method`` "homotopy" or "resultant");
    every combination of a real dyad 1 with a real dyad 2 is a `ChainedSixBarDesign`,
    screened by the engine (`SixBarDefects`).
    """
    pts = _array(points, "points", 2)
    phi = _angles(_array(input_angles, "input_angles", 1), angles, "input angles")
    theta = _angles(_array(coupler_angles, "coupler_angles", 1), angles, "coupler angles")
    q = _pivot(input_pivot, "input_pivot")
    o = _pivot(output_pivot, "output_pivot")
    if not len(pts) == len(phi) == len(theta) == 5:
        raise SynthesisError(
            f"the chained six-bar takes 5 points, 5 input angles and 5 coupler angles; got "
            f"{len(pts)}, {len(phi)} and {len(theta)}"
        )
    rot = np.mod(phi - phi[0], 2.0 * math.pi)
    for i in range(5):
        for j in range(i + 1, 5):
            if abs(math.remainder(rot[i] - rot[j], 2.0 * math.pi)) < 1e-12:
                raise SynthesisError(
                    f"input angles {i + 1} and {j + 1} are the same rotation: the input cannot meet "
                    "both positions on its turn"
                )
    kw: dict[str, Any] = dict(points=pts, input_angles=phi, coupler_angles=theta, method=method)
    one = dyads("chain1", pivot=q.tolist(), **kw)
    two = dyads("chain2", pivot=o.tolist(), **kw)
    designs = [
        ChainedSixBarDesign(
            q,
            o,
            a.ground,
            a.moving,
            b.ground,
            b.moving,
            pts,
            phi - phi[0],
            theta - theta[0],
            (a, b),
        )
        for a in one.real
        for b in two.real
    ]
    designs.sort(key=lambda d: (not d.defects.ok, not d.defects.full_turn))
    return ChainedSixBarSynthesis(pts, phi, theta, q, o, [one, two], designs)


def _pivot(value: Any, what: str) -> np.ndarray:
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise SynthesisError(f"{what} must be a point (x, y): {e}") from None
    if v.shape != (2,):
        raise SynthesisError(f"{what} must be a point (x, y), got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise SynthesisError(f"{what} is not finite")
    return v


@dataclass
class Torque:
    """Input torques over a turn (N m): ``phi`` on QA (the motor at sprocket 1; it
    includes what the chain passes to DC), ``chain`` the chain's torque on DC (sprocket
    2), ``theta`` the second input's on the coupler; ``total`` = phi + theta summed onto
    one shaft turning at the input's rate; ``virtual_work``: the same total from
    d(T + V)/dt over the input's rate, computed from the motion alone (no multipliers)."""

    t: np.ndarray
    phi: np.ndarray
    chain: np.ndarray
    theta: np.ndarray
    total: np.ndarray
    virtual_work: np.ndarray


def torque(
    design: ChainedSixBarDesign,
    mass: float = 2.0,
    inertia: float = 0.5,
    gravity: float = 9.81,
    omega: float = 1.0,
    steps: int = 2000,
) -> Torque:
    """Inverse dynamics of a design over a whole turn of its input, checked by virtual
    work. Mass properties (SI, lengths read as metres): the coupler only, ``mass`` (kg) at
    the centroid of B1, D1, P1, ``inertia`` (kg m^2) about it; ``gravity`` (m/s^2) along
    -y; the input turns at ``omega`` (rad/s). Raises `SolveError` if the design does not
    turn fully."""
    t = np.linspace(0.0, 2.0 * math.pi / omega, steps + 1)
    centroid = (design.b1 + design.d1 + design.p) / 3.0
    m = design.model(omega=omega)
    m.set_mass("coupler", mass, inertia, tuple(centroid))
    m.set_gravity((0.0, -gravity))
    res = m.compile().sweep(t, forces=True)
    # sum onto the input shaft by power: tau_total * omega_input = sum of driver powers
    w_in = design.schedule()[0] * omega
    total = (res.power("phi") + res.power("theta")) / w_in
    # virtual work: the power in equals (T + V)' = m v.a + J w w' + m g v_y, from the
    # engine's kinematics alone (velocities and accelerations, no multipliers)
    c = res.body("coupler")
    com = res.point_at("coupler", tuple(centroid - design.p))
    v, a = com.velocity, com.acceleration
    assert v is not None and a is not None and c.thetad is not None and c.thetadd is not None
    power = mass * np.sum(v * a, axis=1) + inertia * c.thetad * c.thetadd + mass * gravity * v[:, 1]
    return Torque(
        t,
        res.effort("phi"),
        np.asarray(res.reaction("chain").torque),
        res.effort("theta"),
        total,
        power / w_in,
    )

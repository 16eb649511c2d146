"""Designs from solved dyads and the engine's screening of them: `FourBarDesign` (a model
built and swept through its precision positions), its `Defects` (order, branch, circuit;
transmission, Grashof type), `MERIT`, and the results `Synthesis` and `Curves`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import SingularError, SolveError
from ..mechanism.builder import Mechanism
from ..motion import Linear
from ..view.design import DesignPictures
from .dyad import POSITION_TOLERANCE, Dyad, DyadSolutions

__all__ = ["MERIT", "Defects", "DyadDesign", "FourBarDesign", "Curves", "Synthesis"]


#: How designs are ordered: defect-free first, then the larger worst transmission angle
#: (distance of the transmission angle from 0 or 180 deg, over the precision range), then
#: the smaller ratio of longest to shortest link.
MERIT = "defect-free first; then larger worst transmission angle; then smaller link-length ratio"


@dataclass(frozen=True)
class Defects:
    """What the engine found sweeping a design through its precision positions with the
    input turning one way from position 1.

    ``order``: the input does not meet the positions in the prescribed order (turning
    either way). ``branch``: a dead point (limit of the input's motion) lies before a
    position, so reaching it needs the input reversed through a toggle. ``circuit``: a
    position is met at its input angle but the design is then in another assembly (the
    other circuit): it cannot be reached without taking the linkage apart.
    ``reached[j]``: position j+1 reached on the design's circuit; ``error[j]``: the pose
    error there (length units; inf if not reached). ``dead_points``: input rotations (rad,
    from position 1) of the limits met. ``grashof``: the Grashof type.
    ``transmission``: (min, max) transmission angle (deg) over the swept range.
    ``length_ratio``: longest over shortest link.
    """

    order: bool
    branch: bool
    circuit: bool
    reached: tuple[bool, ...]
    error: tuple[float, ...]
    dead_points: tuple[float, ...]
    grashof: str
    transmission: tuple[float, float]
    length_ratio: float
    direction: int

    @property
    def ok(self) -> bool:
        """No order, branch or circuit defect."""
        return not (self.order or self.branch or self.circuit)

    @property
    def worst_transmission(self) -> float:
        """Smallest distance (deg) of the transmission angle from 0 or 180 over the range."""
        lo, hi = self.transmission
        return min(lo, 180.0 - hi)

    def __str__(self) -> str:
        flags = [
            n for n, f in (("order", self.order), ("branch", self.branch), ("circuit", self.circuit)) if f
        ]
        return (
            f"{'defect-free' if not flags else 'defects: ' + ', '.join(flags)}; {self.grashof}; "
            f"transmission {self.transmission[0]:.1f}..{self.transmission[1]:.1f} deg; "
            f"link ratio {self.length_ratio:.2f}"
        )


def _grashof(lengths: list[float]) -> str:
    s, l_ = min(lengths), max(lengths)
    p_q = sum(lengths) - s - l_
    if abs(s + l_ - p_q) <= 1e-9 * l_:
        return "change point"
    return "Grashof" if s + l_ < p_q else "non-Grashof"


class DyadDesign(DesignPictures):
    """A design made of two solved dyads (``dyads``): its residual and certificate, and
    its pictures (`DesignPictures`)."""

    dyads: tuple[Dyad, Dyad]

    @property
    def residual(self) -> float:
        """Largest change of a dyad's length over the positions (length units)."""
        return max(d.residual for d in self.dyads)

    @property
    def certified(self) -> bool:
        """Both dyads certified real roots."""
        return all(d.certified and d.real for d in self.dyads)


@dataclass
class FourBarDesign(DyadDesign):
    """A four-bar from two real dyads: input crank ``o2`` -> ``a`` (the first dyad),
    coupler ``a`` -> ``b`` carrying the precision point ``p``, rocker ``o4`` -> ``b``, all
    at position 1. ``positions``: the precision points (n x 2); ``coupler_angles``: the
    coupler's rotation from position 1 at each; ``input_angles``: the crank's. Its
    pictures mark them (`DesignPictures`: ``to_html``, ``to_svg``, ``to_dxf``, ``plot``).
    """

    o2: np.ndarray
    a: np.ndarray
    o4: np.ndarray
    b: np.ndarray
    p: np.ndarray
    positions: np.ndarray
    coupler_angles: np.ndarray
    input_angles: np.ndarray | None
    dyads: tuple[Dyad, Dyad]
    _defects: Defects | None = field(default=None, repr=False)
    #: pose error (length units) up to which a position counts as reached; None: the exact
    #: methods' POSITION_TOLERANCE of the design's size
    tolerance: float | None = None

    @property
    def lengths(self) -> dict[str, float]:
        d = lambda u, v: float(np.hypot(*(u - v)))  # noqa: E731
        return {
            "ground": d(self.o2, self.o4),
            "crank": d(self.o2, self.a),
            "coupler": d(self.a, self.b),
            "rocker": d(self.o4, self.b),
        }

    def crank_rotations(self) -> np.ndarray:
        """The crank's rotation at each precision position, from position 1 (rad): as
        prescribed (timed problems) or from the coupler poses (motion generation)."""
        if self.input_angles is not None:
            return np.asarray(self.input_angles, dtype=float) - float(self.input_angles[0])
        rot = np.exp(1j * self.coupler_angles)
        a1 = complex(*self.a)
        p1 = complex(*self.p)
        pts = self.positions[:, 0] + 1j * self.positions[:, 1]
        a_j = pts + (a1 - p1) * rot
        o2 = complex(*self.o2)
        return np.angle((a_j - o2) / (a1 - o2))

    def precision_times(self) -> np.ndarray:
        """The time of `model` at each precision position: the crank's rotation from
        position 1, turning the way that meets the positions in order (the first way if
        neither does), in [0, 2 pi) that way."""
        rot = self.crank_rotations()
        direction, _ = _order(rot)
        t = direction * np.mod(direction * rot, 2.0 * math.pi)
        t[0] = 0.0
        return t

    def model(self, name: str = "four-bar design") -> Mechanism:
        """The design as a linkwork mechanism at position 1: bodies "crank", "coupler",
        "rocker"; revolutes "O2", "A", "B", "O4"; point "P"; driver "crank_angle" = the
        crank's angle at position 1 plus t (t is the crank rotation, rad)."""
        ang = lambda u, v: math.atan2(float(v[1] - u[1]), float(v[0] - u[0]))  # noqa: E731
        m = Mechanism(name)
        crank = m.body("crank", tuple(self.o2), ang(self.o2, self.a))
        coupler = m.body("coupler", tuple(self.a), ang(self.a, self.b))
        rocker = m.body("rocker", tuple(self.o4), ang(self.o4, self.b))
        m.revolute(m.ground, crank, tuple(self.o2), name="O2")
        m.revolute(crank, coupler, tuple(self.a), name="A")
        m.revolute(coupler, rocker, tuple(self.b), name="B")
        m.revolute(m.ground, rocker, tuple(self.o4), name="O4")
        m.drive_angle(crank, Linear(ang(self.o2, self.a), 1.0), name="crank_angle")
        m.point("P", coupler, tuple(self.p))
        return m

    @property
    def defects(self) -> Defects:
        """The engine's screening (computed once)."""
        if self._defects is None:
            self._defects = _screen(self)
        return self._defects

    def __str__(self) -> str:
        L = self.lengths
        return (
            f"four-bar O2 ({self.o2[0]:.6g}, {self.o2[1]:.6g}) O4 ({self.o4[0]:.6g}, {self.o4[1]:.6g}); "
            f"ground {L['ground']:.4g}, crank {L['crank']:.4g}, "
            f"coupler {L['coupler']:.4g}, rocker {L['rocker']:.4g}; "
            f"{self.defects}"
        )


def _order(rot: np.ndarray) -> tuple[int, bool]:
    """Direction (+1 / -1) in which the crank meets the positions in order, and whether it
    does at all (rotations in [0, 2 pi) increasing one way)."""
    for s in (1, -1):
        r = np.mod(s * rot, 2.0 * math.pi)
        r[0] = 0.0
        if np.all(np.diff(r) > 0):
            return s, True
    return 1, False


def _screen(design: FourBarDesign, steps: int = 720) -> Defects:
    rot = design.crank_rotations()
    direction, in_order = _order(rot)
    targets = np.mod(direction * rot, 2.0 * math.pi)
    targets[0] = 0.0
    last = float(targets.max()) if in_order else 2.0 * math.pi
    grid = np.union1d(np.linspace(0.0, last, steps + 1), targets[targets <= last])
    model = design.model()
    m = Mechanism.from_dict(model.to_dict())
    # drive with the chosen direction: crank angle = angle_1 + direction t
    ang1 = math.atan2(float(design.a[1] - design.o2[1]), float(design.a[0] - design.o2[0]))
    m.remove("crank_angle")
    m.drive_angle("crank", Linear(ang1, float(direction)), name="crank_angle")
    compiled = m.compile()
    dead: list[float] = []
    try:
        res = compiled.sweep(grid, on_singular="stop", derivatives=0)
    except SingularError as e:
        res = e.partial  # type: ignore[attr-defined]
        if e.time is not None:  # type: ignore[attr-defined]
            dead.append(direction * float(e.time))  # type: ignore[attr-defined]
    except SolveError as e:
        res = getattr(e, "partial", None)
    dead += [direction * ev.time for ev in (res.events if res is not None else []) if ev.kind == "limit"]
    n_done = 0 if res is None else len(res.times)
    reached: list[bool] = []
    errors: list[float] = []
    circuit = branch = False
    scale = max(design.lengths.values())
    theta0 = math.atan2(float(design.b[1] - design.a[1]), float(design.b[0] - design.a[0]))
    for j, tj in enumerate(targets):
        k = int(np.searchsorted(grid, tj))
        if res is None or k >= n_done or not in_order and tj > last:
            reached.append(False)
            errors.append(math.inf)
            branch = True
            continue
        p = res.point("P")
        th = res.body("coupler").theta[k]
        err_p = float(np.hypot(*(p.position[k] - design.positions[j])))
        err_a = abs(math.remainder(th - theta0 - design.coupler_angles[j], 2.0 * math.pi)) * scale
        e = max(err_p, err_a)
        ok = e <= (design.tolerance if design.tolerance is not None else POSITION_TOLERANCE * scale)
        reached.append(ok)
        errors.append(e)
        circuit |= not ok
    # transmission angle at B between the coupler (A->B, its body x axis) and the rocker
    # (O4->B, its body x axis), over the swept range
    if res is not None and n_done > 0:
        c, r = res.body("coupler").theta, res.body("rocker").theta
        mu = np.degrees(np.arccos(np.clip(np.cos(c - r), -1.0, 1.0)))
        trans = (float(mu.min()), float(mu.max()))
    else:
        trans = (0.0, 0.0)
    L = list(design.lengths.values())
    return Defects(
        order=not in_order,
        branch=branch,
        circuit=circuit,
        reached=tuple(reached),
        error=tuple(errors),
        dead_points=tuple(dead),
        grashof=_grashof(L),
        transmission=trans,
        length_ratio=max(L) / max(min(L), 1e-300),
        direction=direction,
    )


def _merit(d: FourBarDesign) -> tuple[int, float, float]:
    f = d.defects
    return (0 if f.ok else 1, -f.worst_transmission, f.length_ratio)


@dataclass
class Curves:
    """Four-pose Burmester curves, sampled: ``circle_points`` (moving pivots at pose 1)
    and ``centre_points`` (their ground pivots), n x 2, row k of one matching row k of the
    other; every pair is an exact four-pose dyad."""

    circle_points: np.ndarray
    centre_points: np.ndarray


@dataclass
class Synthesis:
    """A synthesis result: ``dyads`` (every solution found, with their certificates),
    ``designs`` (the four-bars assembled from real dyads, screened and sorted by
    `MERIT`), ``curves`` (four poses), ``problem``."""

    problem: str
    dyads: DyadSolutions | list[DyadSolutions]
    designs: list[Any]
    curves: Curves | None = None

    @property
    def defect_free(self) -> list[Any]:
        return [d for d in self.designs if d.defects.ok]

    def report(self) -> str:
        lines = [f"{self.problem}:"]
        sets = self.dyads if isinstance(self.dyads, list) else [self.dyads]
        for k, s in enumerate(sets):
            which = "" if len(sets) == 1 else f" ({k + 1})"
            lines += s.report_lines(f"dyads{which}")
        lines.append(
            f"  designs: {len(self.designs)} ({len(self.defect_free)} defect-free), sorted by: {MERIT}"
        )
        for i, d in enumerate(self.designs, 1):
            lines.append(f"    {i}. {d}")
        return "\n".join(lines)


def _pair_designs(
    reals: list[Dyad],
    positions: np.ndarray,
    coupler_angles: np.ndarray,
    input_angles: np.ndarray | None,
    first: Dyad | None = None,
) -> list[FourBarDesign]:
    designs = []
    p1 = positions[0]
    if first is None:
        pairs = [(a, b) for i, a in enumerate(reals) for b in reals[i + 1 :]]
        # each pair both ways: either dyad may be the input crank
        pairs += [(b, a) for a, b in pairs]
    else:
        pairs = [(first, b) for b in reals]
    for a, b in pairs:
        if np.allclose(a.ground, b.ground, atol=1e-9) and np.allclose(a.moving, b.moving, atol=1e-9):
            continue
        designs.append(
            FourBarDesign(
                a.ground,
                a.moving,
                b.ground,
                b.moving,
                np.array(p1, dtype=float),
                positions,
                coupler_angles,
                input_angles,
                (a, b),
            )
        )
    return designs

"""Synthesis: link dimensions from precision points, every solution, certified, and each
design screened by the engine.

Problems (lengths in any unit, angles in radians unless ``angles="deg"``):

- `motion` (motion generation): a body must take 2 to 5 poses (x, y, angle). Five poses:
  Burmester's dyads, all of them (at most 4), and the four-bars they pair into. Four:
  the circle-point and centre-point curves, sampled (`Curves`). Three: a moving (or
  ground) pivot chosen per dyad, the other by the circumcentre. Two: moving pivots
  chosen, ground pivots on the bisectors.
- `path` (path generation with prescribed timing): a coupler point through 5 points
  while the crank turns by 5 given angles: every input dyad (at most 4), each completed
  by the Burmester dyads of the coupler motion it implies.
- `function` (Freudenstein): a four-bar or slider-crank through 3 precision pairs
  (Chebyshev spacing by `chebyshev`), with its structural error over the range.
- `nine_points` (Alt's problem): every four-bar whose coupler curve passes nine points,
  by parameter homotopy from 1442 shipped generic classes, with the Roberts cognates.
- `motion_least_squares`: more than five poses, by least squares from the exact dyads of
  five-pose subsets, with bounds on link lengths and the transmission angle.
- `path_least_squares`: more than five timed points, the same way (the input dyad from
  the exact timed dyads of five-point subsets, then the follower from the motion it
  implies).
- `chained_six_bar`: the chained Stephenson six-bar (linkwork.synthesis.six_bar): a
  coupler point through 5 points while the input link and the coupler turn by given
  angles, every dyad of both problems and every six-bar they combine into.
- `dyads`: the raw dyad solutions of any of these, by "homotopy" (every root,
  alpha-certified) or "resultant" (the independent elimination, every root too,
  certified the same way; about 20 times faster on these problems).

Every exact solution is a root of a small polynomial system solved by parameter
homotopy (linkwork-homotopy): each comes with ``residual`` (largest change of its link
length over the positions), ``certified`` (Smale's alpha test: a root lies within
``radius``) and ``real`` (certified real). A `FourBarDesign` is a model the engine builds
and sweeps through its precision positions; its `Defects` say whether it reaches every
position in order on one circuit without a dead point. Designs sort by `MERIT`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import _core
from ..errors import SingularError, SolveError, SynthesisError
from ..mechanism.builder import Mechanism
from ..motion import Linear
from ..view.targets import DesignPictures

__all__ = [
    "Dyad",
    "DyadSolutions",
    "Defects",
    "FourBarDesign",
    "SliderCrankDesign",
    "FunctionFourBar",
    "Synthesis",
    "Curves",
    "MERIT",
    "dyads",
    "motion",
    "path",
    "function",
    "chebyshev",
    "generic_root_count",
    "nine_points",
    "NinePointResult",
    "motion_least_squares",
    "path_least_squares",
    "chained_six_bar",
]

#: How designs are ordered: defect-free first, then the larger worst transmission angle
#: (distance of the transmission angle from 0 or 180 deg, over the precision range), then
#: the smaller ratio of longest to shortest link.
MERIT = "defect-free first; then larger worst transmission angle; then smaller link-length ratio"

#: A precision position counts as reached when the swept pose matches it to this, relative
#: to the design's size (the sweep's own error is ~1e-12).
POSITION_TOLERANCE = 1e-7


def _angles(values: np.ndarray, unit: str, what: str) -> np.ndarray:
    if unit not in ("rad", "deg"):
        raise SynthesisError(f"angles must be 'rad' or 'deg', not {unit!r}")
    if unit == "deg":
        return np.radians(values)
    if values.size and float(np.max(np.abs(values))) > 2.0 * math.pi + 1e-9:
        raise SynthesisError(
            f"{what} reach {float(np.max(np.abs(values))):.4g} rad, more than a turn: they look like "
            "degrees; pass angles='deg' (or give radians)"
        )
    return values


def _array(value: Any, what: str, columns: int) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise SynthesisError(f"{what} must be numbers in rows of {columns}: {e}") from None
    if a.ndim == 1 and columns == 1:
        return a
    if a.ndim != 2 or a.shape[1] != columns:
        raise SynthesisError(f"{what} must be an array of shape (n, {columns}), got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        bad = int(np.argwhere(~np.isfinite(a))[0][0])
        raise SynthesisError(f"{what}: row {bad + 1} is not finite")
    return a


@dataclass(frozen=True)
class Dyad:
    """One RR dyad at position 1: ``ground`` (the fixed pivot, or for a chained problem
    the pivot on the guiding link) and ``moving`` (the pivot on the guided body), in world
    coordinates. A complex solution keeps its imaginary parts in ``*_imag``.
    ``residual``: the largest change of the link length over the positions (length units);
    ``backward_error``, ``condition`` (|Df| |Df^-1|), ``certified``, ``real`` and
    ``radius`` come from the root's certificate. Dyads of `nine_points` designs carry their
    class's largest backward error and ``condition`` NaN (their roots are certified per
    class, in 24 unknowns, not per dyad); least-squares dyads are not certified."""

    ground: np.ndarray
    moving: np.ndarray
    ground_imag: np.ndarray
    moving_imag: np.ndarray
    real: bool
    certified: bool
    residual: float
    backward_error: float
    condition: float
    radius: float

    @property
    def length(self) -> float:
        return float(np.hypot(*(self.moving - self.ground)))


@dataclass(frozen=True)
class DyadSolutions:
    """Every dyad of one problem, and what the paths did: ``paths`` tracked,
    ``at_infinity``, ``failed``, ``singular``; ``distinct``: the certified roots are
    pairwise distinct (disjoint certification balls). For the resultant, ``paths``
    counts the elimination's candidates and ``failed`` those Newton did not take to a
    root (the spurious ones)."""

    dyads: list[Dyad]
    method: str
    paths: int | None = None
    at_infinity: int | None = None
    failed: int | None = None
    singular: int | None = None
    distinct: bool | None = None

    @property
    def real(self) -> list[Dyad]:
        return [d for d in self.dyads if d.real]

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(self.dyads)

    def __len__(self) -> int:
        return len(self.dyads)

    @classmethod
    def _from_raw(cls, raw: dict[str, Any], method: str) -> DyadSolutions:
        dyads = [
            Dyad(
                np.array(raw["ground"][k]),
                np.array(raw["moving"][k]),
                np.array(raw["ground_imag"][k]),
                np.array(raw["moving_imag"][k]),
                bool(raw["real"][k]),
                bool(raw["certified"][k]),
                float(raw["residual"][k]),
                float(raw["backward_error"][k]),
                float(raw["condition"][k]),
                float(raw["radius"][k]),
            )
            for k in range(len(raw["real"]))
        ]
        return cls(
            dyads,
            method,
            raw.get("paths"),
            raw.get("at_infinity"),
            raw.get("failed"),
            raw.get("singular"),
            raw.get("distinct"),
        )


def generic_root_count() -> int:
    """Roots of the dyad family at generic parameters: the paths every dyad problem tracks."""
    return int(_core.synth_start_set()[0])


def dyads(
    problem: str,
    poses: Any = None,
    points: Any = None,
    input_angles: Any = None,
    coupler_angles: Any = None,
    pivot: Sequence[float] | None = None,
    method: str = "homotopy",
    angles: str = "rad",
) -> DyadSolutions:
    """Every dyad of one exact problem.

    ``problem``: "burmester" (``poses``: 5 x 3), "timed" (``points``: 5 x 2 and
    ``input_angles``), "chain1" / "chain2" (the chained six-bar's dyads: ``points``,
    ``input_angles`` phi_n, ``coupler_angles`` theta_n, and as ``pivot`` the input
    link's pivot Q for "chain1", the output pivot O for "chain2"; `chained_six_bar`
    solves both and assembles the designs). ``method``: "homotopy" (every root,
    certified) or "resultant" (elimination; every root, certified).
    """
    if method not in ("homotopy", "resultant"):
        raise SynthesisError(f"method must be 'homotopy' or 'resultant', not {method!r}")
    if problem == "burmester":
        p = _array(poses, "poses", 3).copy()
        p[:, 2] = _angles(p[:, 2], angles, "pose angles")
        raw = _core.synth_dyads("burmester", method, p.ravel().tolist())
    elif problem == "timed":
        pts = _array(points, "points", 2)
        a = _angles(_array(input_angles, "input_angles", 1), angles, "input angles")
        raw = _core.synth_dyads("timed", method, pts.ravel().tolist(), a.tolist())
    elif problem in ("chain1", "chain2"):
        pts = _array(points, "points", 2)
        a = _angles(_array(input_angles, "input_angles", 1), angles, "input angles")
        b = _angles(_array(coupler_angles, "coupler_angles", 1), angles, "coupler angles")
        q = [] if pivot is None else [float(v) for v in pivot]
        if len(q) != 2:
            which = "the input link's pivot Q" if problem == "chain1" else "the output pivot O"
            raise SynthesisError(f"{problem} needs {which} as pivot=(x, y)")
        raw = _core.synth_dyads(problem, method, pts.ravel().tolist(), a.tolist(), b.tolist(), q)
    else:
        raise SynthesisError(f"unknown problem {problem!r}: 'burmester', 'timed', 'chain1' or 'chain2'")
    return DyadSolutions._from_raw(raw, method)


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
            head = f"  dyads{which}: {len(s.dyads)} roots, {len(s.real)} real"
            if s.paths is not None:
                head += f"; {s.paths} paths, {s.at_infinity} at infinity, {s.failed} failed"
                head += f"; distinct: {s.distinct}"
            lines.append(head)
            for d in s.dyads:
                kind = "real" if d.real else "complex"
                cert = "certified" if d.certified else "NOT certified"
                lines.append(
                    f"    ground ({d.ground[0]:.6g}, {d.ground[1]:.6g}) "
                    f"moving ({d.moving[0]:.6g}, {d.moving[1]:.6g}) "
                    f"{kind}, {cert}, residual {d.residual:.1e}, radius {d.radius:.1e}"
                )
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


def motion(
    poses: Any,
    moving: Any = None,
    ground: Any = None,
    along: Sequence[float] = (0.0, 0.0),
    samples: int = 360,
    angles: str = "rad",
) -> Synthesis:
    """Motion generation through 2 to 5 poses (rows x, y, angle; the pose's reference
    point is the coupler point P of the designs).

    5 poses: every Burmester dyad and every four-bar pairing two real ones (either as
    input). 4: `Curves` sampled along ``samples`` rays. 3: give two moving pivots
    (``moving``, 2 x 2, world at pose 1) or two ground pivots (``ground``). 2: two moving
    pivots; ground pivots on their bisectors, ``along`` from the midpoints.
    """
    p = _array(poses, "poses", 3).copy()
    p[:, 2] = _angles(p[:, 2], angles, "pose angles")
    n = len(p)
    positions = p[:, :2]
    rot = p[:, 2] - p[0, 2]
    if n == 5:
        sols = DyadSolutions._from_raw(
            _core.synth_dyads("burmester", "homotopy", p.ravel().tolist()), "homotopy"
        )
        designs = _pair_designs(sols.real, positions, rot, None)
        designs.sort(key=_merit)
        return Synthesis("motion generation, 5 poses (Burmester)", sols, designs)
    if n == 4:
        raw = _core.synth_motion("four_curves", p.ravel().tolist(), [], 0.0, int(samples))
        return Synthesis(
            "motion generation, 4 poses (Burmester curves)",
            DyadSolutions._from_raw(raw, "closed form"),
            [],
            Curves(np.array(raw["moving"]).reshape(-1, 2), np.array(raw["ground"]).reshape(-1, 2)),
        )
    if n in (2, 3):
        if (moving is None) == (ground is None) or (n == 2 and moving is None):
            need = "moving=(2 x 2)" if n == 2 else "moving=(2 x 2) or ground=(2 x 2)"
            raise SynthesisError(f"{n} poses leave free choices: give {need}, one point per dyad")
        chosen = _array(
            moving if moving is not None else ground, "moving" if moving is not None else "ground", 2
        )
        if len(chosen) != 2:
            raise SynthesisError("give exactly two points, one per dyad")
        out = []
        for k in range(2):
            if n == 3:
                kind = "three_ground" if moving is not None else "three_moving"
                raw = _core.synth_motion(kind, p.ravel().tolist(), chosen[k].tolist())
            else:
                raw = _core.synth_motion(
                    "two_ground", p.ravel().tolist(), chosen[k].tolist(), float(along[k])
                )
            out.append(DyadSolutions._from_raw(raw, "closed form").dyads[0])
        sols = DyadSolutions(out, "closed form")
        designs = [
            FourBarDesign(
                out[0].ground,
                out[0].moving,
                out[1].ground,
                out[1].moving,
                positions[0],
                positions,
                rot,
                None,
                (out[0], out[1]),
            )
        ]
        return Synthesis(f"motion generation, {n} poses", sols, designs)
    raise SynthesisError(f"motion generation takes 2 to 5 poses for the exact methods; got {n}")


def path(points: Any, input_angles: Any, angles: str = "rad") -> Synthesis:
    """Path generation with prescribed timing: the coupler point through 5 ``points``
    while the crank turns by ``input_angles`` (from position 1). Every input dyad, each
    completed by the Burmester dyads of the coupler motion it implies."""
    pts = _array(points, "points", 2)
    a = _angles(_array(input_angles, "input_angles", 1), angles, "input angles")
    first = dyads("timed", points=pts, input_angles=a)
    designs: list[FourBarDesign] = []
    followers = []
    for d in first.real:
        # coupler rotations implied by this input dyad
        g, a1, p1 = complex(*d.ground), complex(*d.moving), complex(*pts[0])
        a_j = g + (a1 - g) * np.exp(1j * (a - a[0]))
        theta = np.angle((pts[:, 0] + 1j * pts[:, 1] - a_j) / (p1 - a1))
        poses = np.column_stack([pts, theta])
        f = dyads("burmester", poses=poses)
        followers.append(f)
        others = [
            b
            for b in f.real
            if not (np.allclose(b.ground, d.ground, atol=1e-7) and np.allclose(b.moving, d.moving, atol=1e-7))
        ]
        designs += _pair_designs(others, pts, theta, a, first=d)
    designs.sort(key=_merit)
    return Synthesis("path generation with prescribed timing, 5 points", [first, *followers], designs)


def chebyshev(lo: float, hi: float, n: int = 3) -> np.ndarray:
    """Chebyshev spacing of ``n`` precision points on [lo, hi]."""
    return np.array(_core.synth_chebyshev(float(lo), float(hi), int(n)))


@dataclass
class SliderCrankDesign:
    """A slider-crank from Freudenstein's equation: crank ``a`` about (0, 0), rod ``b``,
    slider on y = ``e`` (position s along x)."""

    a: float
    b: float
    e: float


def function(input_angles: Any, output: Any, kind: str = "four_bar", ground: float = 1.0) -> Any:
    """Freudenstein function generation through exactly 3 precision pairs.

    ``kind`` "four_bar": ``output`` the rocker angles (rad), ground pivots (0, 0) and
    (``ground``, 0); returns a `FunctionFourBar`. "slider_crank": ``output`` the slider
    positions; returns a `SliderCrankDesign`. Place the pairs with `chebyshev`.
    """
    phi = _array(input_angles, "input_angles", 1)
    out = _array(output, "output", 1)
    if kind == "four_bar":
        a, b, c, d = _core.synth_freudenstein("four_bar", phi.tolist(), out.tolist(), float(ground))
        return FunctionFourBar(a, b, c, d, phi.copy(), out.copy())
    if kind == "slider_crank":
        a, b, e = _core.synth_freudenstein("slider_crank", phi.tolist(), out.tolist(), 0.0)
        return SliderCrankDesign(a, b, e)
    raise SynthesisError(f"kind must be 'four_bar' or 'slider_crank', not {kind!r}")


@dataclass
class FunctionFourBar:
    """A four-bar function generator from Freudenstein's equation: ground pivots (0, 0)
    and (d, 0); signed crank ``a`` and rocker ``c`` (a negative one points the other way
    at the same angle), coupler ``b``; ``pairs_in`` / ``pairs_out``: the precision pairs."""

    a: float
    b: float
    c: float
    d: float
    pairs_in: np.ndarray
    pairs_out: np.ndarray

    def model(self, name: str = "function generator") -> Mechanism:
        """The generator at the first precision pair; driver "crank_angle": the crank's
        input angle phi = t (rad), so a sweep over phi is a sweep over t."""
        phi1, psi1 = float(self.pairs_in[0]), float(self.pairs_out[0])
        a1 = self.a * complex(math.cos(phi1), math.sin(phi1))
        o4 = complex(self.d, 0.0)
        b1 = o4 + self.c * complex(math.cos(psi1), math.sin(psi1))
        m = Mechanism(name)
        crank = m.body("crank", (0.0, 0.0), math.atan2(a1.imag, a1.real))
        coupler = m.body("coupler", (a1.real, a1.imag), math.atan2((b1 - a1).imag, (b1 - a1).real))
        rocker = m.body("rocker", (self.d, 0.0), math.atan2((b1 - o4).imag, (b1 - o4).real))
        m.revolute(m.ground, crank, (0.0, 0.0), name="O2")
        m.revolute(crank, coupler, (a1.real, a1.imag), name="A")
        m.revolute(coupler, rocker, (b1.real, b1.imag), name="B")
        m.revolute(m.ground, rocker, (self.d, 0.0), name="O4")
        m.drive_angle(crank, Linear(math.atan2(a1.imag, a1.real) - phi1, 1.0), name="crank_angle")
        return m

    def output(self, input_angles: Any) -> np.ndarray:
        """The rocker angle psi the generator gives at each input angle (by the engine,
        on the circuit of the first precision pair); raises `SolveError` (with
        ``.partial``) where it cannot follow."""
        phi = _array(input_angles, "input_angles", 1)
        if phi.size > 1 and not np.all(np.diff(phi) > 0):
            raise SynthesisError("input_angles must increase")
        psi1 = float(self.pairs_out[0])
        b1 = self.c * complex(math.cos(psi1), math.sin(psi1))
        # the sweep follows the drawing (the first pair) along the driver to every phi
        r = self.model().compile().sweep(phi, derivatives=0).body("rocker").theta
        return psi1 + np.remainder(r - math.atan2(b1.imag, b1.real) + math.pi, 2.0 * math.pi) - math.pi

    def structural_error(self, input_angles: Any, desired: Any) -> np.ndarray:
        """Desired minus generated output angle at each input angle (rad)."""
        want = _array(desired, "desired", 1)
        return want - self.output(input_angles)


@dataclass(frozen=True)
class NinePointResult:
    """Alt's nine-point problem at one instance: ``classes`` roots found (1442 for
    generic points), of which ``physical_classes`` are real four-bars, each giving three
    Roberts cognates as ``designs`` (screened, sorted by `MERIT`); ``paths``, ``failed``
    (of which ``over_budget``: stopped by the step or time budget of a nearly degenerate
    instance), ``at_infinity``, ``singular``, ``duplicates``: what the 1442 paths did;
    ``certified``: roots passing the alpha test; ``seconds``: the homotopy's wall time."""

    points: np.ndarray
    classes: int
    certified: int
    distinct: bool
    physical_classes: int
    paths: int
    failed: int
    over_budget: int
    at_infinity: int
    singular: int
    duplicates: int
    max_residual: float
    seconds: float
    designs: list[FourBarDesign]

    def report(self) -> str:
        lines = [
            "Alt's nine-point path synthesis:",
            f"  {self.paths} paths in {self.seconds:.2f} s: {self.classes} classes of roots "
            f"({self.certified} certified, distinct: {self.distinct}), {self.failed} failed "
            f"({self.over_budget} over budget), "
            f"{self.at_infinity} at infinity, {self.singular} singular, {self.duplicates} duplicates; "
            f"largest backward error {self.max_residual:.1e}",
            f"  {self.physical_classes} real four-bars (classes), "
            f"{len(self.designs)} designs with their cognates, "
            f"{sum(d.defects.ok for d in self.designs)} defect-free; sorted by: {MERIT}",
        ]
        for i, d in enumerate(self.designs[:10], 1):
            lines.append(f"    {i}. {d}")
        if len(self.designs) > 10:
            lines.append(f"    ... {len(self.designs) - 10} more")
        return "\n".join(lines)


def nine_points(points: Any, screen: bool = True, seconds: float = 30.0) -> NinePointResult:
    """Alt's problem: every four-bar whose coupler curve passes through the nine
    ``points`` (9 x 2), by parameter homotopy from the shipped start set of 1442 generic
    classes (docs/synthesis.md says how it was made). Each real four-bar comes with its
    two Roberts cognates; with ``screen``, each design is swept by the engine (is every
    point reached, in order, on one circuit?) and the list sorted by `MERIT`. A generic
    instance takes a few seconds; a nearly degenerate one stops after ``seconds``, its
    unfinished paths counted as failed and ``over_budget``."""
    pts = _array(points, "points", 2)
    if len(pts) != 9:
        raise SynthesisError(f"Alt's problem takes exactly 9 points; got {len(pts)}")
    raw = _core.synth_alt(pts.ravel().tolist(), seconds=float(seconds))
    designs = []
    for k in range(len(raw["class"])):
        a, b = _alt_dyads(raw, k, pts)
        designs.append(
            FourBarDesign(
                a.ground,
                a.moving,
                b.ground,
                b.moving,
                pts[0].copy(),
                pts,
                np.concatenate([[0.0], raw["coupler_angles"][k]]),
                None,
                (a, b),
            )
        )
    if screen:
        designs.sort(key=_merit)
    return NinePointResult(
        pts,
        raw["roots"],
        raw["certified"],
        raw["distinct"],
        raw["physical_classes"],
        raw["paths"],
        raw["failed"],
        raw["over_budget"],
        raw["at_infinity"],
        raw["singular"],
        raw["duplicates"],
        raw["max_residual"],
        raw["seconds"],
        designs,
    )


def _alt_dyads(raw: dict[str, Any], k: int, pts: np.ndarray) -> tuple[Dyad, Dyad]:
    """The two dyads of four-bar k, with their residual: the largest change of the crank
    length over the nine positions (pin at P_j + x theta_j, x = pin - P_0 at position 0)."""
    theta = np.exp(1j * np.concatenate([[0.0], raw["coupler_angles"][k]]))
    p = pts[:, 0] + 1j * pts[:, 1]
    out = []
    for g, m in (("ground_a", "moving_a"), ("ground_b", "moving_b")):
        ground, moving = complex(*raw[g][k]), complex(*raw[m][k])
        lengths = np.abs(p + (moving - p[0]) * theta - ground)
        zero = np.zeros(2)
        out.append(
            Dyad(
                np.array(raw[g][k]),
                np.array(raw[m][k]),
                zero,
                zero,
                True,
                True,
                float(np.ptp(lengths)),
                float(raw["max_residual"]),
                math.nan,
                0.0,
            )
        )
    return out[0], out[1]


def _least_squares() -> Any:
    try:
        from scipy.optimize import least_squares
    except ImportError:  # pragma: no cover - optional dependency
        raise SynthesisError(
            "least-squares synthesis needs scipy: pip install 'linkwork[synthesis]'"
        ) from None
    return least_squares


def _length_range(length_range: tuple[float, float] | None) -> tuple[float, float]:
    lo, hi = length_range if length_range is not None else (0.0, np.inf)
    if not 0.0 <= lo < hi:
        raise SynthesisError(f"length_range must be 0 <= lo < hi, got {length_range}")
    return lo, hi


def _subsets(n: int, count: int, seed: int) -> list[np.ndarray]:
    """Five-point subsets: evenly spread, then random ones."""
    rng = np.random.default_rng(seed)
    chosen = [np.linspace(0, n - 1, 5).round().astype(int)]
    while len(chosen) < count:
        chosen.append(np.sort(rng.choice(n, 5, replace=False)))
    return chosen


def _fit_dyad(
    residual: Callable[[np.ndarray], np.ndarray], z0: np.ndarray, lo: float, hi: float, size: float
) -> Dyad:
    """One dyad (G, M, R) = z by trust-region least squares from z0, R in [lo, hi]."""
    z0 = z0.copy()
    z0[4] = float(np.clip(z0[4], lo, hi if np.isfinite(hi) else None))
    bounds = ([-np.inf] * 4 + [lo], [np.inf] * 4 + [hi])
    fit = _least_squares()(residual, z0, bounds=bounds, x_scale="jac", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    res = residual(fit.x)
    return Dyad(
        np.array(fit.x[:2]),
        np.array(fit.x[2:4]),
        np.zeros(2),
        np.zeros(2),
        True,
        False,
        float(np.max(np.abs(res))),
        float(np.sqrt(np.mean(res**2)) / size),
        float(np.linalg.cond(fit.jac)) if fit.jac.size else math.inf,
        0.0,
    )


def _add_new(found: list[Dyad], dyad: Dyad, size: float) -> None:
    if not any(_same_dyad(dyad, e, 1e-5 * size) for e in found):
        found.append(dyad)


def _same_dyad(a: Dyad, b: Dyad, tol: float) -> bool:
    return bool(np.allclose(a.ground, b.ground, atol=tol) and np.allclose(a.moving, b.moving, atol=tol))


def _screened(paired: list[FourBarDesign], size: float, min_transmission: float) -> list[FourBarDesign]:
    """Least-squares designs screened by the engine with the tolerance their fit allows
    (a design meets its positions only as well as its dyads fit them), those whose
    transmission angle comes closer than ``min_transmission`` to 0 or 180 deg dropped."""
    for d in paired:
        d.tolerance = 10.0 * max(x.residual for x in d.dyads) + POSITION_TOLERANCE * size
    return [d for d in paired if d.defects.worst_transmission >= min_transmission]


def _motion_dyads(p: np.ndarray, lo: float, hi: float, subsets: int, seed: int) -> list[Dyad]:
    """Least-squares dyads guiding a body through poses p (n x 3, n > 5), started from
    the real Burmester dyads of five-pose subsets."""
    n = len(p)
    pts = p[:, 0] + 1j * p[:, 1]
    rot = np.exp(1j * (p[:, 2] - p[0, 2]))
    size = float(np.ptp(p[:, :2])) or 1.0

    def residual(z: np.ndarray) -> np.ndarray:
        g, m, r = complex(z[0], z[1]), complex(z[2], z[3]), z[4]
        return np.abs(pts + (m - pts[0]) * rot - g) - r

    found: list[Dyad] = []
    reason = "no five-pose subset has a real Burmester dyad"
    for idx in _subsets(n, subsets, seed):
        try:
            exact = dyads("burmester", poses=p[idx])
        except SynthesisError as e:
            reason = f"the subset of poses {', '.join(str(i + 1) for i in idx)}, numbered 1 to 5 in it: {e}"
            continue
        for d in exact.real:
            # the exact dyad's moving pivot is given at the subset's first pose
            k0 = int(idx[0])
            m1 = pts[0] + (complex(*d.moving) - pts[k0]) / rot[k0]
            g = complex(*d.ground)
            r0 = float(np.median(np.abs(pts + (m1 - pts[0]) * rot - g)))
            z0 = np.array([g.real, g.imag, m1.real, m1.imag, r0])
            _add_new(found, _fit_dyad(residual, z0, lo, hi, size), size)
    if not found:
        raise SynthesisError(f"no dyad to start the least squares from ({reason})")
    return found


def motion_least_squares(
    poses: Any,
    length_range: tuple[float, float] | None = None,
    min_transmission: float = 0.0,
    subsets: int = 12,
    angles: str = "rad",
    seed: int = 0,
) -> Synthesis:
    """Motion generation through more poses than the exact methods take (n > 5): dyads
    minimizing the change of their link length over all poses, then four-bars screened
    by the engine.

    Each dyad (ground pivot G, moving pivot M fixed in the body, length R) minimizes
    sum_j (|M_j - G| - R)^2 by trust-region least squares (scipy), R bounded by
    ``length_range``; the starts are the real Burmester dyads of ``subsets`` five-pose
    subsets (exact, certified), so every local minimum near an exact design of some five
    poses is found. Dyads' ``residual`` is the largest |M_j - G| - R over the poses. Designs
    pair two dyads, are swept by the engine (`Defects`), and those whose transmission
    angle comes closer than ``min_transmission`` (deg) to 0 or 180 are dropped; sorted by
    `MERIT`. Needs scipy (``pip install linkwork[synthesis]``).
    """
    _least_squares()
    p = _array(poses, "poses", 3).copy()
    p[:, 2] = _angles(p[:, 2], angles, "pose angles")
    n = len(p)
    if n <= 5:
        raise SynthesisError(
            f"least squares is for more than 5 poses (got {n}); use motion() for exact synthesis"
        )
    lo, hi = _length_range(length_range)
    size = float(np.ptp(p[:, :2])) or 1.0
    found = _motion_dyads(p, lo, hi, subsets, seed)
    sols = DyadSolutions(found, "least squares")
    designs = _screened(_pair_designs(found, p[:, :2], p[:, 2] - p[0, 2], None), size, min_transmission)
    designs.sort(key=_merit)
    return Synthesis(f"motion generation, {n} poses (least squares)", sols, designs)


def path_least_squares(
    points: Any,
    input_angles: Any,
    length_range: tuple[float, float] | None = None,
    min_transmission: float = 0.0,
    subsets: int = 12,
    angles: str = "rad",
    seed: int = 0,
) -> Synthesis:
    """Path generation with prescribed timing through more points than the exact method
    takes (n > 5): the coupler point through ``points`` while the crank turns by
    ``input_angles`` (from position 1), by least squares, then four-bars screened by the
    engine.

    The input dyad (ground pivot G, crank pin A_1, coupler-side length R = |P - A|)
    minimizes sum_j (|P_j - A_j| - R)^2 with A_j = G + (A_1 - G) e^{i(phi_j - phi_1)}, R
    bounded by ``length_range``; its starts are the real timed dyads of ``subsets``
    five-point subsets (exact, certified). Each fitted input dyad implies the coupler
    rotations theta_j = arg((P_j - A_j) / (P_1 - A_1)); the follower dyads are then the
    least-squares motion dyads of the poses (P_j, theta_j) (as in `motion_least_squares`).
    A design's ``tolerance`` is ten times its dyads' largest residual. Designs whose
    transmission angle comes closer than ``min_transmission`` (deg) to 0 or 180 are
    dropped; sorted by `MERIT`. Needs scipy (``pip install linkwork[synthesis]``).
    """
    _least_squares()
    pts = _array(points, "points", 2)
    a = _angles(_array(input_angles, "input_angles", 1), angles, "input angles")
    n = len(pts)
    if n <= 5:
        raise SynthesisError(
            f"least squares is for more than 5 points (got {n}); use path() for exact synthesis"
        )
    if len(a) != n:
        raise SynthesisError(f"{n} points need {n} input angles, got {len(a)}")
    lo, hi = _length_range(length_range)
    size = float(np.ptp(pts)) or 1.0
    pc = pts[:, 0] + 1j * pts[:, 1]
    turn = np.exp(1j * (a - a[0]))

    def crank_pins(z: np.ndarray) -> np.ndarray:
        g, a1 = complex(z[0], z[1]), complex(z[2], z[3])
        return g + (a1 - g) * turn

    def residual(z: np.ndarray) -> np.ndarray:
        return np.abs(pc - crank_pins(z)) - z[4]

    inputs: list[Dyad] = []
    reason = "no five-point subset has a real timed dyad"
    for idx in _subsets(n, subsets, seed):
        try:
            exact = dyads("timed", points=pts[idx], input_angles=a[idx] - a[idx[0]])
        except SynthesisError as e:
            reason = f"the subset of points {', '.join(str(i + 1) for i in idx)}, numbered 1 to 5 in it: {e}"
            continue
        for d in exact.real:
            # the exact dyad's crank pin is given at the subset's first point
            g, k0 = complex(*d.ground), int(idx[0])
            a1 = g + (complex(*d.moving) - g) / turn[k0]
            z0 = np.array([g.real, g.imag, a1.real, a1.imag, 0.0])
            z0[4] = float(np.median(np.abs(pc - crank_pins(z0))))
            _add_new(inputs, _fit_dyad(residual, z0, lo, hi, size), size)
    if not inputs:
        raise SynthesisError(f"no input dyad to start the least squares from ({reason})")
    designs: list[FourBarDesign] = []
    followers: list[DyadSolutions] = []
    for d in inputs:
        pins = crank_pins(np.r_[d.ground, d.moving, 0.0])
        theta = np.angle((pc - pins) / (pc[0] - pins[0]))
        found = _motion_dyads(np.column_stack([pts, theta]), lo, hi, subsets, seed)
        others = [b for b in found if not _same_dyad(b, d, 1e-5 * size)]
        followers.append(DyadSolutions(found, "least squares"))
        designs += _screened(_pair_designs(others, pts, theta, a, first=d), size, min_transmission)
    designs.sort(key=_merit)
    return Synthesis(
        f"path generation with prescribed timing, {n} points (least squares)",
        [DyadSolutions(inputs, "least squares"), *followers],
        designs,
    )


def chained_six_bar(
    points: Any,
    input_angles: Any,
    coupler_angles: Any,
    input_pivot: Any,
    output_pivot: Any,
    angles: str = "rad",
    method: str = "homotopy",
) -> Any:
    """The chained six-bar's synthesis for any data (`linkwork.synthesis.six_bar.chained_six_bar`):
    every dyad of both problems and every real combination as a screened design."""
    from .six_bar import chained_six_bar as solve

    return solve(points, input_angles, coupler_angles, input_pivot, output_pivot, angles, method)

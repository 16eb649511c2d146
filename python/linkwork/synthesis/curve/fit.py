"""Refinement and multistart for the tracking-error problem: bounded trust-region least
squares (scipy.optimize.least_squares, "trf") on the residuals, with the engine's exact
Jacobian (`TrackingProblem.evaluate`), from many starting designs on all cores.

Inside the refinement free crank angles are written as the first angle and the
increments to the next, each in [0, 2 pi], so they stay increasing; the constraints that
are not bounds (the crank the shortest link, the ordering, a closed curve's one turn)
are penalty residuals whose weight grows until they hold. A trial step whose design
leaves its circuit or stops turning fully scores as a very large residual, so the trust
region rejects it and shrinks: every accepted design turns fully on its circuit. Where
the refinement ends on linear constraints (Grashof's s + l = p + q above all, where the
residuals steepen without bound across the boundary and the trust region collapses), it
goes on within their null space, holding them, and then again from there; `fit` does
so only for starts whose f is within _REACH times the best of all starts.

A time budget (``seconds``) is checked before each start and at each evaluation: once it
is spent no start begins, and a refinement under way stops with the best design it has
evaluated. Within the budget the answer is the one without it (the clock is only read).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import SingularError, SolveError, SynthesisError
from ...mechanism.builder import Mechanism
from ...view.design import DesignPictures
from .constraints import grashof_type
from .target import TargetCurve
from .threads import map_starts
from .tracking import TWO_PI, CircuitError, TrackingProblem, coupler_points

__all__ = [
    "CurveDesign",
    "CurveFit",
    "refine",
    "random_seeds",
    "fit",
    "ranked",
    "smallest_f_note",
    "CURVE_MERIT",
    "USABLE_TRANSMISSION",
]

#: The smallest transmission angle (rad) of a usable design where the problem states
#: none: 30 degrees, the floor of light-duty linkages (40 is the general rule of thumb);
#: nearer 0 or 180 the coupler and rocker fold and the output torque is under half the
#: input's. It ranks designs, never drops them; a stated ``transmission`` replaces it.
USABLE_TRANSMISSION = math.radians(30.0)

#: How `fit` (and `fit_six_bars`) order their designs (`ranked`).
CURVE_MERIT = (
    "defect-free and within the constraints first; of them first the usable (smallest "
    "transmission angle at least the stated bound, else 30 deg); then the smaller tracking error f"
)

_WEIGHTS = (1e1, 1e3, 1e5, 1e7)
# a constraint within _BAND (times the target's size) of its boundary is held there by
# the refinement along the constraints; a round of it that lowers the sum of squares by
# less than the fraction _GAIN is the last
_BAND = 1e-6
_GAIN = 1e-9
# the refinement along Grashof's limit in `fit`: only for starts within _REACH times the
# best f after the penalised refinements
_REACH = 10.0
# fit(agree=...): starts refined in rounds of _ROUND; designs agree within the fraction _AGREE_TOL
_ROUND = 4
_AGREE_TOL = 0.01


@dataclass
class TracedDesign(DesignPictures):
    """What every refined design of a curve problem holds (`CurveDesign`, the six-bars'
    `SixBarDesign`): its ``problem``, ``x`` (the design numbers, then the crank angles),
    ``f`` (the tracking error), ``max_deviation`` (the largest |P(theta2_i) - P_i|),
    ``transmission`` (the smallest transmission angle of the four-bar loop over the
    traced stretch, rad, as its distance from 0 or pi), ``violation`` (largest constraint
    violation, 0 when they hold), ``grashof`` (the engine's type of the four-bar loop),
    ``defects`` (order, branch, circuit over the traced stretch; empty when free of
    them), ``nfev`` and ``seconds`` of its refinement, ``start`` (the index of its
    starting design), ``family`` (where that came from), ``margins`` (each stated
    constraint's margin), ``cut`` (True: the time budget stopped its refinement, this is
    the best it had evaluated). Its pictures (`to_html`, `to_svg`, `plot`) draw the
    traced curve over a crank turn with the target points marked and each point's
    deviation drawn."""

    problem: Any = field(repr=False)
    x: np.ndarray
    f: float
    max_deviation: float
    transmission: float
    violation: float
    grashof: str
    defects: tuple[str, ...]
    nfev: int
    seconds: float
    start: int = -1
    family: str = "given"
    margins: dict[str, float] = field(default_factory=dict)
    cut: bool = False

    #: the name `model` gives the mechanism unless told
    model_name = "curve design"

    @property
    def positions(self) -> np.ndarray:
        """The target points (the pictures' targets)."""
        return np.array(self.problem.target.points)

    coupler_angles = None

    def crank_angles(self) -> np.ndarray:
        return np.array(self.x[self.problem.size :])

    def precision_times(self) -> np.ndarray:
        """The model's time at each target point: its crank angle within the turn."""
        return np.mod(self.crank_angles(), TWO_PI)

    @property
    def circuit(self) -> str:
        return self.problem.circuit

    @property
    def ok(self) -> bool:
        """Defect-free and within the constraints (to 1e-12 of the target's size)."""
        return not self.defects and self.violation <= 1e-12 * self.problem.target.size

    @property
    def smallest_transmission(self) -> float:
        """The smallest transmission angle `usable` judges (rad): the four-bar loop's."""
        return self.transmission

    @property
    def usable(self) -> bool:
        """`ok` and its `smallest_transmission` at least the problem's stated bound, else
        `USABLE_TRANSMISSION`."""
        bound = getattr(self.problem, "transmission", None)
        return self.ok and self.smallest_transmission >= (USABLE_TRANSMISSION if bound is None else bound)

    def plot(self, path: str, **options: Any) -> list[str]:  # type: ignore[override]
        """A PNG of the target points against the traced curve, each point's deviation
        drawn, beside the linkage (`pictures.plot_design`; ``options``: ``title``,
        ``dpi``)."""
        from .pictures import plot_design

        return [plot_design(self, path, **options)]

    def model(self, name: str | None = None) -> Mechanism:
        """The design as a linkwork mechanism (time = crank angle theta2 from the ground line)."""
        return self.problem.model(self.x, name or self.model_name)


@dataclass
class CurveDesign(TracedDesign):
    """A refined four-bar (`TracedDesign`): ``x`` the full vector of `TrackingProblem`,
    ``family`` "random", "atlas", "alt", "timed" or "given"."""

    problem: TrackingProblem = field(repr=False)

    def linkage_at(self, t: float) -> tuple[list[np.ndarray], np.ndarray]:
        """The bodies (crank, coupler with its point, rocker, each the polygon of its pins)
        and the ground pivots at crank angle ``t``, in closed form."""
        x = self.x
        r1, r2, r3, th0, x0, y0 = x[0], x[1], x[2], x[6], x[7], x[8]
        o2 = np.array([x0, y0])
        o4 = o2 + r1 * np.array([math.cos(th0), math.sin(th0)])
        a = o2 + r2 * np.array([math.cos(th0 + t), math.sin(th0 + t)])
        probe = np.array(x[:9], dtype=float)
        probe[4:6] = (r3, 0.0)
        b = coupler_points(probe, [t], self.circuit)[0]
        p = coupler_points(x, [t], self.circuit)[0]
        return [np.array([o2, a]), np.array([a, b, p]), np.array([b, o4])], np.array([o2, o4])

    def __str__(self) -> str:
        r = ", ".join(f"{k} {v:.6g}" for k, v in zip(("r1", "r2", "r3", "r4", "rcx", "rcy"), self.x[:6]))
        pose = f"theta0 {self.x[6]:.6g}, O2 ({self.x[7]:.6g}, {self.x[8]:.6g})"
        state = "defect-free" if not self.defects else "defects: " + ", ".join(self.defects)
        if self.ok and not self.usable:
            state += "; transmission below the usable"
        if self.violation > 1e-12 * self.problem.target.size:
            state += f"; constraints violated by {self.violation:.3g}"
        if self.cut:
            state += "; refinement cut short by the time budget"
        return (
            f"f {self.f:.4g} (largest deviation {self.max_deviation:.4g}); {r}; {pose}; {self.circuit}; "
            f"{self.grashof}; smallest transmission {math.degrees(self.transmission):.1f} deg; {state}"
        )


@dataclass
class CurveFit:
    """`fit`'s answer: ``designs`` sorted by `CURVE_MERIT`, ``failures`` (starting designs
    dropped, with why), ``seconds`` (wall time), ``budget`` (the time budget asked, s;
    None: none), ``unstarted`` (starts the budget left unrefined) and ``unrefined``
    (starts left once enough designs agreed, `fit`'s ``agree``)."""

    designs: list[CurveDesign]
    failures: list[str]
    seconds: float
    budget: float | None = None
    unstarted: int = 0
    unrefined: int = 0

    @property
    def budget_ended(self) -> bool:
        """True when the time budget ended the fit: a start was left or cut short."""
        return self.unstarted > 0 or any(d.cut for d in self.designs)

    def budget_note(self) -> str:
        """A line saying whether the time budget ended the fit ("" without a budget)."""
        if self.budget is None:
            return ""
        if not self.budget_ended:
            return f"every start refined to the end within the time budget of {self.budget:.4g} s"
        cut = sum(d.cut for d in self.designs)
        return (
            f"the time budget of {self.budget:.4g} s ended the fit: {cut} refinements cut short, "
            f"{self.unstarted} starts not begun"
        )

    @property
    def best(self) -> CurveDesign:
        if not self.designs:
            why = "; ".join(self.failures[:3])
            if self.unstarted:
                why = f"the time budget of {self.budget:.4g} s was spent before any start" + (
                    f"; {why}" if why else ""
                )
            raise SynthesisError("no starting design could be refined: " + why)
        return self.designs[0]

    def report(self, count: int = 5) -> str:
        total = len(self.designs) + len(self.failures) + self.unstarted + self.unrefined
        lines = [
            f"{len(self.designs)} designs from {total} "
            f"starts in {self.seconds:.2f} s ({len(self.failures)} dropped); sorted: {CURVE_MERIT}"
        ]
        if self.unrefined:
            lines.append(f"{self.unrefined} starts left unrefined: enough designs agreed on the smallest f")
        if self.budget is not None:
            lines.append(self.budget_note())
        lines += [f"{k + 1}. [{d.family}] {d}" for k, d in enumerate(self.designs[:count])]
        note = self.smallest_f_note()
        if note:
            lines.append(note)
        return "\n".join(lines)

    def smallest_f_note(self, designs: list[CurveDesign] | None = None) -> str:
        """`smallest_f_note` of ``designs`` (default the fit's, in their order)."""
        return smallest_f_note(self.designs if designs is None else designs)


def ranked(designs: Sequence[Any]) -> list[Any]:
    """``designs`` (`TracedDesign`s) in the order of `CURVE_MERIT`, none dropped; ties by
    the index of their start."""
    return sorted(designs, key=lambda d: (not d.ok, not d.usable, d.f, d.start))


def smallest_f_note(designs: Sequence[Any]) -> str:
    """A line naming the defect-free design of smallest f among ``designs`` (in their
    order) where a usable one of larger f is ranked before it ("" otherwise)."""
    ok = [d for d in designs if d.ok]
    low = min(ok, key=lambda d: (d.f, d.start), default=None)
    if low is None or low is ok[0]:
        return ""
    k = [id(d) for d in designs].index(id(low)) + 1
    return (
        f"the smallest f of a defect-free design, {low.f:.4g}, is #{k}'s: "
        f"its smallest transmission angle is {math.degrees(low.smallest_transmission):.1f} deg"
    )


def _least_squares() -> Any:
    try:
        from scipy.optimize import least_squares
    except ImportError:  # pragma: no cover - optional dependency
        raise SynthesisError("curve synthesis needs scipy: pip install 'linkwork[synthesis]'") from None
    return least_squares


class _Spent(Exception):
    """The time budget ran out during a refinement."""


class _Refinement:
    """The map between the refinement's variables z and the design vector x (its first
    ``problem.size`` entries the design numbers, then the crank angles), and the best
    point evaluated at the current weight (what a refinement the budget stops returns)."""

    def __init__(
        self, problem: Any, x: np.ndarray, deadline: float | None = None, weights: Any = None
    ) -> None:
        self.problem = problem
        self.deadline = deadline
        # each point's weight on both its residuals (None: all 1)
        self.rows = None if weights is None else np.repeat(np.asarray(weights, dtype=float), 2)
        self.best: tuple[float, np.ndarray | None] = (math.inf, None)
        self.base = problem.complete(x)
        free = problem.free()
        nd = self.nd = int(problem.size)
        self.design = np.flatnonzero(free[:nd])
        self.timing = bool(free[nd:].any())
        n = problem.n
        lo, hi = problem.lower_upper()
        zlo, zhi = [lo[self.design]], [hi[self.design]]
        if self.timing:
            zlo.append(np.zeros(n))
            zhi.append(np.full(n, TWO_PI))
        self.lower, self.upper = np.concatenate(zlo), np.concatenate(zhi)
        # d x / d z: the design entries one to one, each crank angle the sum of increments
        self.dxdz = np.zeros((nd + n, self.lower.size))
        self.dxdz[self.design, np.arange(self.design.size)] = 1.0
        if self.timing:
            self.dxdz[nd:, self.design.size :] = np.tril(np.ones((n, n)))
        self.cache: dict[bytes, tuple[np.ndarray, ...] | None] = {}
        self.m = len(problem.constraint_names())
        # the penalties aim a little inside the constraints, so that what a finite weight
        # leaves of a violation stays inside them; nearer Grashof's limit than 1e-8 the
        # design is so near a change point that the engine's sweep loses its circuit
        self.inset = 1e-8 * problem.target.size
        self.big = 1e6 * max(problem.target.size, 1.0)

    def z_of(self, x: np.ndarray) -> np.ndarray:
        z = [x[self.design]]
        if self.timing:
            th = x[self.nd :]
            z.append(np.concatenate([[np.mod(th[0], TWO_PI)], np.diff(th)]))
        return np.clip(np.concatenate(z), self.lower, self.upper)

    def x_of(self, z: np.ndarray) -> np.ndarray:
        x = self.base.copy()
        x[self.design] = z[: self.design.size]
        if self.timing:
            x[self.nd :] = np.cumsum(z[self.design.size :])
        return x

    def evaluate(self, z: np.ndarray) -> tuple[np.ndarray, ...] | None:
        key = z.tobytes()
        if key not in self.cache:
            try:
                self.cache = {key: self.problem.evaluate_all(self.x_of(z))}
            except CircuitError:
                self.cache = {key: None}
        return self.cache[key]

    def residuals(self, z: np.ndarray, weight: float) -> np.ndarray:
        if self.deadline is not None and time.perf_counter() >= self.deadline:
            raise _Spent
        out = self.evaluate(z)
        if out is None:
            return np.full(2 * self.problem.n + self.m, self.big)
        r = out[0] if self.rows is None else self.rows * out[0]
        res = np.concatenate([r, weight * np.maximum(out[2] + self.inset, 0.0)])
        cost = float(res @ res)
        if cost < self.best[0]:
            self.best = (cost, z.copy())
        return res

    def minimise(self, z: np.ndarray, max_nfev: int) -> tuple[np.ndarray, int, bool]:
        """The least-squares refinement from z: (the refined z, evaluations, True if the
        time budget stopped it). The penalised refinement (`penalised`), then, where it
        ends on Grashof's limit, the refinement along the constraints (`continued`)."""
        z, nfev, cut, weight = self.penalised(z, max_nfev)
        if cut or not self.on_grashof_limit(z):
            return z, nfev, cut
        z, extra, cut = self.continued(z, max_nfev, weight)
        return z, nfev + extra, cut

    def continued(self, z: np.ndarray, max_nfev: int, weight: float) -> tuple[np.ndarray, int, bool]:
        """From the end z of a penalised refinement on Grashof's limit: while a round
        gains and half of ``max_nfev`` more evaluations are not spent, one along the
        linear constraints it ends on (`along_active`) and the penalised one again from
        there. (z, the evaluations it spent, True if the time budget stopped it.)"""
        extra, more, cut = 0, max(max_nfev // 2, 1), False
        while not cut and extra < more:
            try:
                moved, k = self.along_active(z, more - extra, weight)
            except _Spent:
                return self.best_turning(z), extra, True
            extra += k
            if moved is None:
                break
            z, k, cut, weight = self.penalised(moved, max(more - extra, 1))
            extra += k
        return z, extra, cut

    def on_grashof_limit(self, z: np.ndarray) -> bool:
        """True where the design is within _BAND target sizes of s + l = p + q: there
        "trf" stalls (`along_active`); elsewhere its own stop stands."""
        names = self.problem.constraint_names()
        out = self.evaluate(z)
        if out is None or "grashof (s + l <= p + q)" not in names:
            return False
        g = out[2][names.index("grashof (s + l <= p + q)")]
        return bool(g > -_BAND * self.problem.target.size)

    def best_turning(self, z: np.ndarray) -> np.ndarray:
        """The best point evaluated at the current weight, else z (it turns fully: a
        point that does not scores far above the start)."""
        if self.best[1] is not None and self.evaluate(self.best[1]) is not None:
            return self.best[1]
        return z

    def penalised(self, z: np.ndarray, max_nfev: int) -> tuple[np.ndarray, int, bool, float]:
        """scipy's bounded "trf" from z under growing penalty weights: (the refined z,
        evaluations, True if the time budget stopped it, the last weight)."""
        least_squares = _least_squares()
        nfev = 0
        for w in _WEIGHTS:
            self.best = (math.inf, None)
            try:
                sol = least_squares(
                    self.residuals,
                    z,
                    jac=self.jacobian,
                    bounds=(self.lower, self.upper),
                    method="trf",
                    x_scale="jac",
                    ftol=1e-15,
                    xtol=1e-15,
                    gtol=1e-15,
                    max_nfev=max_nfev,
                    args=(w,),
                )
            except _Spent:
                return self.best_turning(z), nfev, True, w
            nfev += int(sol.nfev)
            if self.evaluate(sol.x) is not None:
                z = sol.x
            if self.problem.violation(self.x_of(z)) <= 1e-12 * self.problem.target.size:
                break
        return z, nfev, False, w

    def along_active(self, z: np.ndarray, max_nfev: int, weight: float) -> tuple[np.ndarray | None, int]:
        """Least squares from z within the linear constraints (and bounds) it ends on,
        z + N y with N spanning their null space: those constraints keep their values
        exactly. At Grashof's s + l = p + q the coupler's angle goes as the square root
        of the margin at the crank angle of the fold, so the residuals' Jacobian across
        the boundary grows without bound; every "trf" step that leans across it is
        rejected and the trust region collapses with the design far from its best along
        the boundary. Along it the residuals are smooth. (None: no such constraint or no
        gain; evaluations.)"""
        out = self.evaluate(z)
        linear = getattr(self.problem, "linear_constraints", None)
        if out is None or linear is None or self.m == 0:
            return None, 0
        band = _BAND * self.problem.target.size
        dg = np.array(out[3], dtype=float).reshape(self.m, -1) @ self.dxdz
        held = np.asarray(linear(), dtype=bool) & (out[2] > -band)
        at_bound = (z - self.lower <= band) | (self.upper - z <= band)
        rows, values = [dg[held]], [out[2][held]]
        pieces = getattr(self.problem, "grashof_pieces", None)
        if pieces is not None and held.any():
            pv, pg = pieces(self.x_of(z), band)
            near = pv > -band
            rows.append(pg[near] @ self.dxdz)
            values.append(pv[near])
        active = np.vstack([*rows, np.eye(z.size)[at_bound]])
        if active.shape[0] == 0:
            return None, 0
        before = self.residuals(z, weight)
        # first onto the penalties' inset (a design nearer the boundary is nearly a
        # change point, where the engine's sweep meets a singular position)
        lift = np.concatenate(
            [np.minimum(-self.inset - np.concatenate(values), 0.0), np.zeros(int(at_bound.sum()))]
        )
        if np.any(lift < 0.0):
            lifted = np.clip(z + np.linalg.lstsq(active, lift, rcond=None)[0], self.lower, self.upper)
            if self.evaluate(lifted) is not None:
                z = lifted
        from scipy.linalg import null_space

        tangent = null_space(active)
        if tangent.shape[1] == 0:
            return None, 0

        def inside(y: np.ndarray) -> np.ndarray:
            return z + tangent @ y

        def residuals(y: np.ndarray) -> np.ndarray:
            zy = inside(y)
            if np.any(zy < self.lower) or np.any(zy > self.upper):  # a bound not held: rejected
                return np.full(2 * self.problem.n + self.m, self.big)
            return self.residuals(zy, weight)

        def jacobian(y: np.ndarray) -> np.ndarray:
            return self.jacobian(inside(y), weight) @ tangent

        self.best = (math.inf, None)
        sol = _least_squares()(
            residuals,
            np.zeros(tangent.shape[1]),
            jac=jacobian,
            method="trf",
            x_scale="jac",
            ftol=1e-15,
            xtol=1e-15,
            gtol=1e-15,
            max_nfev=max_nfev,
        )
        moved = inside(sol.x)
        if self.evaluate(moved) is None or not 2.0 * sol.cost < (1.0 - _GAIN) * float(before @ before):
            return None, int(sol.nfev)
        return moved, int(sol.nfev)

    def jacobian(self, z: np.ndarray, weight: float) -> np.ndarray:
        out = self.evaluate(z)
        if out is None:  # not reached: a rejected step's Jacobian is never asked for
            return np.zeros((2 * self.problem.n + self.m, self.lower.size))
        # the constraints' exact gradients (`TrackingProblem.constraints`), where they bind
        dg = np.array(out[3], dtype=float).reshape(self.m, -1)
        dg[out[2] + self.inset <= 0.0] = 0.0
        jac = out[1] if self.rows is None else self.rows[:, None] * out[1]
        return np.vstack([jac, weight * dg]) @ self.dxdz


@dataclass
class _Start:
    """A start of `fit` after its penalised refinement (`_Refinement.penalised`)."""

    start: int
    family: str
    ref: _Refinement
    z: np.ndarray
    nfev: int
    cut: bool
    weight: float
    f: float
    seconds: float


def refine(
    problem: TrackingProblem,
    x: Any,
    max_nfev: int = 400,
    start: int = -1,
    deadline: float | None = None,
    weights: Any = None,
) -> CurveDesign:
    """One design refined from ``x`` (a full design vector), stopped at ``deadline`` (a
    `time.perf_counter` instant) if given, with the best design evaluated by then
    (``cut``). ``weights``: one a point, multiplying both its residuals (the design's
    ``f`` stays the unweighted tracking error). `CircuitError` if ``x`` itself does not
    turn fully on the problem's circuit."""
    t0 = time.perf_counter()
    ref = start_refinement(problem, x, start, deadline, weights)
    z, nfev, cut = ref.minimise(ref.z_of(ref.base), max_nfev)
    d = _design(problem, ref.x_of(z), nfev, time.perf_counter() - t0, start)
    d.cut = cut
    return d


def start_refinement(
    problem: Any, x: Any, start: int, deadline: float | None = None, weights: Any = None
) -> _Refinement:
    """The refinement's map for a start ``x``; `CircuitError` if ``x`` does not turn
    fully on its circuit."""
    ref = _Refinement(problem, problem.complete(x), deadline, weights)
    if ref.evaluate(ref.z_of(ref.base)) is None:
        raise CircuitError(
            f"starting design {start} (within the bounds) does not turn fully on the {problem.assembly}"
        )
    return ref


def _design(problem: TrackingProblem, x: np.ndarray, nfev: int, seconds: float, start: int) -> CurveDesign:
    r, _ = problem.evaluate(x)
    dev = np.hypot(*r.reshape(-1, 2).T)
    defects, trans, kind = _screen(problem, x)
    return CurveDesign(
        problem,
        x,
        float(r @ r),
        float(dev.max()),
        trans,
        problem.violation(x),
        kind,
        defects,
        nfev,
        seconds,
        start,
        margins=problem.margins(x),
    )


def screened_stretch(th: np.ndarray, closed: bool) -> tuple[list[str], np.ndarray, float]:
    """The crank angles' order defect (not increasing, or a closed curve's beyond one turn)
    and the times a screening sweep takes: from the drawn start (0) to the first angle
    (returned, where the stretch starts) in 72 equal steps, then over the traced stretch
    (a whole turn for a closed curve) in 360: a degree a step over a turn."""
    defects = []
    if np.any(np.diff(th) <= 0.0) or (closed and th[-1] - th[0] >= TWO_PI):
        defects.append("order")
    first = float(np.mod(th[0], TWO_PI))
    end = first + (TWO_PI if closed else float(th[-1] - th[0]))
    return defects, np.union1d(np.linspace(0.0, first, 73), np.linspace(first, end, 361)), first


def _screen(problem: TrackingProblem, x: np.ndarray) -> tuple[tuple[str, ...], float, str]:
    """The engine's sweep over the traced stretch (the first crank angle to the last, a
    whole turn for a closed curve), reached from the drawn start: order (the crank angles
    not increasing, or a closed curve's beyond one turn), branch (a dead point met) and
    circuit (the coupler point off the circuit's closed form) defects; the smallest
    transmission angle over the stretch and the engine's Grashof type."""
    defects, times, first = screened_stretch(x[9:], problem.target.closed)
    model = problem.model(x).compile()
    try:
        linkage = model.linkages()[0]
    except SingularError:
        # drawn at a dead point: no configuration to describe, no step to take from it
        return (*defects, "branch", "circuit"), 0.0, grashof_type(*x[:4])
    try:
        res = model.sweep(times, derivatives=0, on_singular="stop")
    except SingularError as e:
        res = e.partial  # type: ignore[attr-defined]
        defects.append("branch")
    except SolveError as e:
        res = getattr(e, "partial", None)
        defects.append("branch")
    if res is None or len(res.times) == 0:
        return (*defects, "circuit"), 0.0, linkage.kind_of
    if any(ev.kind == "limit" for ev in res.events) and "branch" not in defects:
        defects.append("branch")
    ref = coupler_points(x, res.times, problem.circuit)
    miss = np.hypot(*(res.point("P").position - ref).T)
    if not np.all(miss <= 1e-7 * max(problem.target.size, float(np.max(x[:4])))):
        defects.append("circuit")
    stretch = res.times >= first - 1e-12
    mu = linkage.transmission_angle_of(res)[stretch]
    trans = float(np.min(np.minimum(mu, math.pi - mu))) if mu.size else 0.0
    return tuple(defects), trans, linkage.kind_of


def _procrustes(c: np.ndarray, p: np.ndarray, rotate: bool) -> tuple[float, float, np.ndarray]:
    """Scale s, rotation a and translation t with s R(a) c + t nearest p (no reflection);
    ``rotate=False``: the scale alone (about the origin)."""
    if not rotate:
        return max(float(np.sum(c * p) / np.sum(c * c)), 1e-9), 0.0, np.zeros(2)
    cz = (c[:, 0] - c[:, 0].mean()) + 1j * (c[:, 1] - c[:, 1].mean())
    pz = (p[:, 0] - p[:, 0].mean()) + 1j * (p[:, 1] - p[:, 1].mean())
    k = np.vdot(cz, pz) / np.vdot(cz, cz).real  # s e^{ia}
    s, a = abs(k), float(np.angle(k))
    rc = s * complex(math.cos(a), math.sin(a)) * complex(c[:, 0].mean(), c[:, 1].mean())
    t = np.array([p[:, 0].mean() - rc.real, p[:, 1].mean() - rc.imag])
    return max(s, 1e-9), a, t


def random_seeds(
    target: TargetCurve,
    count: int,
    seed: int = 0,
    circuits: Sequence[str] = ("open", "crossed"),
    grashof: str = "crank-rocker",
) -> list[tuple[str, np.ndarray]]:
    """``count`` starting designs (circuit, full x): random Grashof crank-rockers from a
    seeded generator, crank angles spread over the points (a turn for a closed curve),
    each placed on the target by the similarity that fits its points best (its scale
    alone where theta0, x0, y0 are prescribed: Cabrera's timed problem has them 0);
    ``grashof="double-crank"``: double-cranks (the ground the shortest link)."""
    rng = np.random.default_rng(seed)
    n = len(target)
    out: list[tuple[str, np.ndarray]] = []
    while len(out) < count:
        r1, r3, r4 = rng.uniform(1.0, 5.0, 3)
        r2 = rng.uniform(0.1, 1.0) * min(r1, r3, r4)
        if grashof == "double-crank":  # the same lengths with the shortest as the ground
            r1, r2 = r2, r1
        lengths = sorted([r1, r2, r3, r4])
        if lengths[0] + lengths[3] > lengths[1] + lengths[2]:
            continue
        rc = rng.uniform(-4.0, 4.0, 2)
        if target.crank_angles is not None:
            th = np.array(target.crank_angles)
        else:
            span = TWO_PI * (n - 1) / n if target.closed else rng.uniform(math.pi / 3, TWO_PI * (n - 1) / n)
            th = rng.uniform(0.0, TWO_PI) + np.linspace(0.0, span, n)
        circuit = circuits[len(out) % len(circuits)]
        x = np.concatenate([[r1, r2, r3, r4, *rc, 0.0, 0.0, 0.0], th])
        c = coupler_points(x, th, circuit)
        if not np.all(np.isfinite(c)):
            continue
        s, a, t = _procrustes(c, target.points, rotate=not target.timed)
        x[:6] *= s
        x[6:9] = [a, t[0], t[1]]
        out.append((circuit, x))
    return out


def fit(
    target: TargetCurve,
    seeds: Sequence[tuple[Any, ...]] | None = None,
    starts: int = 16,
    seed: int = 0,
    workers: int | None = None,
    max_nfev: int = 400,
    seconds: float | None = None,
    agree: int | None = None,
    **problem: Any,
) -> CurveFit:
    """Multistart: each starting design (``seeds``: (circuit, x) pairs or (circuit, x,
    family) triples such as `linkwork.synthesis.curve.seeds`' `Seed`; default
    `random_seeds` (``starts`` of them, ``seed``)) refined as by `refine` on ``workers``
    threads (default: every core; the engine releases the GIL while it sweeps), except
    that the refinement along Grashof's limit runs, after every start's penalised one,
    only for those within _REACH (10) times the best f then (`refine` runs it for any), on the
    `TrackingProblem` of ``target`` with the options ``problem`` (``lengths``,
    ``coupler``, ``pivot``, ``fixed``, ``ordered`` and the designer's constraints
    ``grashof``, ``transmission``, ``links``, ``ratio``, ``regions``). A start that does not turn fully on
    its circuit is dropped with why (``failures``). The answer does not depend on the
    number of workers. Designs are sorted by `CURVE_MERIT`: none is dropped for its
    transmission angle, but the usable come first (`CurveFit.smallest_f_note` names a
    better f ranked after them).

    ``seconds``: a time budget for the whole fit (from its call). Once spent no start
    begins and the refinements under way stop with the best design each has evaluated
    (`CurveFit.budget_ended`, `CurveFit.budget_note`); when it does not end the fit the
    answer is the one without it, reproducible with ``seed``.

    ``agree``: the starts are refined in rounds of 4, in order, until ``agree``
    defect-free designs within the constraints come within 1 % of the smallest f of them
    (`CurveFit.unrefined`: the starts left); None (the default): every start."""
    t0 = time.perf_counter()
    deadline = None if seconds is None else t0 + budget_seconds(seconds)
    if seeds is None:
        grashof = problem.get("grashof", "crank-rocker")
        seeds = [(c, x, "random") for c, x in random_seeds(target, starts, seed, grashof=grashof)]
    problems = {c: TrackingProblem(target, circuit=c, **problem) for c in ("open", "crossed")}
    jobs = list(enumerate(seeds))

    def first(job: tuple[int, tuple[Any, ...]]) -> _Start | str | None:
        k, (circuit, x, *family) = job
        if circuit not in problems:
            return f"start {k}: circuit {circuit!r} is not 'open' or 'crossed'"
        if deadline is not None and time.perf_counter() >= deadline:
            return None  # the budget is spent: not begun
        t = time.perf_counter()
        try:
            ref = start_refinement(problems[circuit], x, k, deadline)
        except CircuitError as e:
            return f"start {k}: {e} ({family[0] if family else 'given'} seed)"
        z, nfev, cut, weight = ref.penalised(ref.z_of(ref.base), max_nfev)
        out = ref.evaluate(z)
        f = math.inf if out is None else float(out[0] @ out[0])
        name = str(family[0]) if family else "given"
        return _Start(k, name, ref, z, nfev, cut, weight, f, time.perf_counter() - t)

    # the refinement along Grashof's limit only where the penalised one ended on it, within
    # _REACH times the best f of the starts so far (it lowers f by factors, not by orders)
    best = [math.inf]

    def then(s: _Start | str | None) -> CurveDesign | str | None:
        if not isinstance(s, _Start):
            return s
        t = time.perf_counter()
        z, nfev, cut = s.z, s.nfev, s.cut
        if not cut and s.f <= _REACH * best[0] and s.ref.on_grashof_limit(z):
            if deadline is not None and time.perf_counter() >= deadline:
                cut = True  # its refinement along the limit is left undone
            else:
                z, extra, cut = s.ref.continued(z, max_nfev, s.weight)
                nfev += extra
        d = _design(s.ref.problem, s.ref.x_of(z), nfev, s.seconds + time.perf_counter() - t, s.start)
        d.cut, d.family = cut, s.family
        return d

    done: list[CurveDesign | str | None] = []
    step = _ROUND if agree else max(len(jobs), 1)
    ran = 0
    while ran < len(jobs) and not (agree and _agreed(done, int(agree), target.size)):
        begun = map_starts(first, jobs[ran : ran + step], workers)
        ran += step
        best[0] = min([best[0]] + [s.f for s in begun if isinstance(s, _Start) and not s.cut])
        done += map_starts(then, begun, workers)
    designs = [d for d in done if isinstance(d, CurveDesign)]
    designs = ranked(designs)
    failures = [d for d in done if isinstance(d, str)]
    budget = None if seconds is None else float(seconds)
    unstarted = sum(d is None for d in done)
    return CurveFit(designs, failures, time.perf_counter() - t0, budget, unstarted, max(len(jobs) - ran, 0))


def _agreed(done: list[Any], agree: int, size: float) -> bool:
    """``agree`` defect-free designs within the constraints whose f is within the
    fraction _AGREE_TOL of the smallest such f (or 1e-20 target sizes squared of it: a
    curve a four-bar passes exactly)."""
    fs = sorted(d.f for d in done if isinstance(d, CurveDesign) and d.ok)
    return len(fs) >= agree and fs[agree - 1] <= (1.0 + _AGREE_TOL) * fs[0] + 1e-20 * size * size


def budget_seconds(seconds: Any) -> float:
    """A time budget checked: a number of seconds >= 0 (`SynthesisError` otherwise)."""
    try:
        value = float(seconds)
    except (TypeError, ValueError):
        raise SynthesisError(f"the time budget is a number of seconds, not {seconds!r}") from None
    if isinstance(seconds, bool) or not value >= 0.0:
        raise SynthesisError(f"the time budget is a number of seconds >= 0, not {seconds!r}")
    return value

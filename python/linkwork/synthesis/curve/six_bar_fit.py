"""Six-bars refined from the best four-bars (`fit_six_bars`): each of the best four-bar
designs gets dyads C-D-F (`dyad_seeds`: F a ground pivot O6 for a Stephenson III, a pin
E on the rocker for a Watt I; lengths that assemble over the whole crank turn; D on
either side) with the tracer P put at C, so every start traces its four-bar's curve and
begins at its tracking error; the refinement is the four-bar's bounded trust-region least
squares on the extended design vector of `SixBarProblem`. Each refined six-bar is
screened by the engine's sweep over its traced stretch for order, branch and circuit
defects, with the smallest transmission angles at B (the four-bar loop) and at D (the
dyad).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import SingularError, SolveError, SynthesisError
from .constraints import grashof_type
from .fit import (
    CURVE_MERIT,
    CurveDesign,
    CurveFit,
    TracedDesign,
    budget_seconds,
    fit,
    ranked,
    screened_stretch,
    smallest_f_note,
    start_refinement,
)
from .six_bars import KINDS, SIDES, SixBarProblem, six_bar_points
from .target import TargetCurve
from .threads import map_starts
from .tracking import TWO_PI, CircuitError, coupler_points

__all__ = ["SixBarDesign", "SixBarFit", "dyad_seeds", "fit_six_bars", "refine_six_bar", "SIX_BAR_MERIT"]

#: How `fit_six_bars` orders its designs: as `fit` (`ranked`), the smallest transmission
#: angle the smaller of those at B and at D.
SIX_BAR_MERIT = CURVE_MERIT + " (the smaller of those at B and at D)"


@dataclass
class SixBarDesign(TracedDesign):
    """A refined six-bar (`TracedDesign`): ``x`` the vector of `SixBarProblem`,
    ``transmission`` the four-bar loop's at B and ``transmission_dyad`` at D, ``grashof``
    the four-bar loop's type, ``family`` the four-bar it grew from. `model` is the
    six-bar."""

    problem: SixBarProblem = field(repr=False)
    family: str = ""
    transmission_dyad: float = math.nan

    model_name = "six-bar curve design"

    @property
    def kind(self) -> str:
        return self.problem.kind

    @property
    def smallest_transmission(self) -> float:
        """The smaller of the transmission angles at B and at D (rad), which `usable` judges."""
        return min(self.transmission, self.transmission_dyad)

    def residuals(self) -> np.ndarray:
        """P(theta2_i) - P_i at the target points (n x 2), from the engine."""
        r, _ = self.problem.evaluate(self.x)
        return r.reshape(-1, 2)

    def linkage_at(self, t: float) -> tuple[list[np.ndarray], np.ndarray]:
        """The bodies (each the polygon of its pins and points) and the ground pivots at
        crank angle ``t``, in closed form."""
        p = {k: v[0] for k, v in self.problem.points(self.x, [t]).items()}
        rocker = [p["O4"], p["B"]] + ([p["F"]] if self.kind == "watt" else [])
        bodies = [
            np.array([p["O2"], p["A"]]),
            np.array([p["A"], p["B"], p["C"]]),
            np.array(rocker),
            np.array([p["C"], p["D"], p["P"]]),
            np.array([p["F"], p["D"]]),
        ]
        pivots = [p["O2"], p["O4"]] + ([p["F"]] if self.kind == "stephenson" else [])
        return bodies, np.array(pivots)

    def __str__(self) -> str:
        names = ("r1", "r2", "r3", "r4", "rcx", "rcy")
        r = ", ".join(f"{k} {v:.6g}" for k, v in zip(names, self.x[:6]))
        far = "O6" if self.kind == "stephenson" else "E (rocker)"
        dyad = (
            f"r5 {self.x[9]:.6g}, r6 {self.x[10]:.6g}, {far} ({self.x[11]:.6g}, {self.x[12]:.6g}), "
            f"P ({self.x[13]:.6g}, {self.x[14]:.6g})"
        )
        state = "defect-free" if not self.defects else "defects: " + ", ".join(self.defects)
        if self.ok and not self.usable:
            state += "; transmission below the usable"
        if self.violation > 1e-12 * self.problem.target.size:
            state += f"; constraints violated by {self.violation:.3g}"
        if self.cut:
            state += "; refinement cut short by the time budget"
        return (
            f"{self.kind} six-bar: f {self.f:.4g} (largest deviation {self.max_deviation:.4g}); {r}; "
            f"theta0 {self.x[6]:.6g}, O2 ({self.x[7]:.6g}, {self.x[8]:.6g}); {dyad}; "
            f"{self.problem.assembly}; {self.grashof}; smallest transmission "
            f"{math.degrees(self.transmission):.1f} deg at B, {math.degrees(self.transmission_dyad):.1f} deg "
            f"at D; {state}"
        )


@dataclass
class SixBarFit:
    """`fit_six_bars`' answer: ``designs`` sorted by `SIX_BAR_MERIT`, ``failures``
    (starts dropped, with why), ``four_bars`` (the four-bar fit they grew from),
    ``seconds`` (wall time), ``budget`` and ``unstarted`` (as `CurveFit`'s)."""

    designs: list[SixBarDesign]
    failures: list[str]
    four_bars: CurveFit
    seconds: float
    budget: float | None = None
    unstarted: int = 0

    @property
    def budget_ended(self) -> bool:
        return self.unstarted > 0 or any(d.cut for d in self.designs) or self.four_bars.budget_ended

    @property
    def best(self) -> SixBarDesign:
        if not self.designs:
            why = "; ".join(self.failures[:3]) or "no start"
            if self.unstarted:
                why = f"the time budget of {self.budget:.4g} s was spent first; {why}"
            raise SynthesisError("no six-bar could be refined: " + why)
        return self.designs[0]

    def report(self, count: int = 5) -> str:
        four = self.four_bars.best
        lines = [
            f"{len(self.designs)} six-bars from {len(self.designs) + len(self.failures) + self.unstarted} "
            f"starts in {self.seconds:.2f} s ({len(self.failures)} dropped); sorted: {SIX_BAR_MERIT}",
            f"the best four-bar they grew from: f {four.f:.4g} (largest deviation {four.max_deviation:.4g})",
        ]
        if self.budget is not None:
            ended = "ended the fit" if self.budget_ended else "did not end the fit"
            lines.append(f"the time budget of {self.budget:.4g} s {ended}")
        lines += [f"{k + 1}. [{d.family}] {d}" for k, d in enumerate(self.designs[:count])]
        note = smallest_f_note(self.designs)
        if note:
            lines.append(note)
        return "\n".join(lines)


def dyad_seeds(
    design: CurveDesign | Any, kind: str, count: int, rng: np.random.Generator
) -> list[tuple[str, np.ndarray]]:
    """``count`` dyads C-D-F added to a four-bar design (a `CurveDesign`, or its
    (circuit, x)), as (side, six-bar vector y): F a ground pivot O6 (Stephenson) at 1.3
    to 3 times the radius of C's curve from its centre, or E on the rocker (Watt) within
    its length's reach, both random from ``rng``; r5 + r6 between 1.15 and 1.6 times the
    largest |C - F| over the crank turn and |r5 - r6| below the smallest, so the dyad
    assembles over the whole turn; D's side alternating; P at C (the six-bar traces the
    four-bar's curve)."""
    circuit, x = (design.circuit, design.x) if isinstance(design, CurveDesign) else design
    x = np.asarray(x, dtype=float)
    th = np.linspace(0.0, TWO_PI, 360, endpoint=False)
    c = coupler_points(x, th, circuit)
    if not np.all(np.isfinite(c)):
        raise SynthesisError("the four-bar does not turn fully: no dyad is added to it")
    centre = c.mean(axis=0)
    radius = max(float(np.max(np.hypot(*(c - centre).T))), 1e-12)
    out: list[tuple[str, np.ndarray]] = []
    tries = 0
    while len(out) < count and tries < 50 * max(count, 1):
        tries += 1
        if kind == "stephenson":
            phi, rho = rng.uniform(0.0, TWO_PI), radius * rng.uniform(1.3, 3.0)
            far = centre + rho * np.array([math.cos(phi), math.sin(phi)])
        else:
            far = float(x[3]) * np.array([rng.uniform(-1.0, 2.0), rng.uniform(-1.5, 1.5)])
        y = np.concatenate([x[:9], [1.0, 1.0, far[0], far[1], 0.0, 0.0], x[9:]])
        pts = six_bar_points(y, th, kind, circuit, "left")
        d = np.hypot(*(pts["C"] - pts["F"]).T)
        if float(d.min()) <= 0.05 * float(d.max()):
            continue
        total = float(d.max()) * rng.uniform(1.15, 1.6)
        diff = float(d.min()) * rng.uniform(0.0, 0.8)
        r5, r6 = (total + diff) / 2.0, (total - diff) / 2.0
        if rng.uniform() < 0.5:
            r5, r6 = r6, r5
        y[9:11] = (r5, r6)
        out.append((SIDES[len(out) % 2], y))
    return out


def refine_six_bar(
    problem: SixBarProblem, y: Any, max_nfev: int = 400, start: int = -1, deadline: float | None = None
) -> SixBarDesign:
    """One six-bar refined from ``y`` (`refine`'s least squares on `SixBarProblem`, at
    most ``max_nfev`` evaluations, 400 as `refine`'s); `CircuitError` if ``y`` does not
    turn fully on its assembly."""
    t0 = time.perf_counter()
    ref = start_refinement(problem, y, start, deadline)
    z, nfev, cut = ref.minimise(ref.z_of(ref.base), max_nfev)
    x = ref.x_of(z)
    r, _ = problem.evaluate(x)
    dev = np.hypot(*r.reshape(-1, 2).T)
    defects, mu_b, mu_d, kind = _screen(problem, x)
    return SixBarDesign(
        problem,
        x,
        float(r @ r),
        float(dev.max()),
        mu_b,
        problem.violation(x),
        kind,
        defects,
        nfev,
        time.perf_counter() - t0,
        start,
        margins=problem.margins(x),
        cut=cut,
        transmission_dyad=mu_d,
    )


def _smallest(u: np.ndarray, v: np.ndarray) -> float:
    """The smallest angle between the bars u and v (rows), as its distance from 0 or pi."""
    cos = np.sum(u * v, axis=1) / (np.hypot(*u.T) * np.hypot(*v.T))
    return float(math.acos(min(float(np.max(np.abs(cos))), 1.0))) if cos.size else 0.0


def _screen(problem: SixBarProblem, y: np.ndarray) -> tuple[tuple[str, ...], float, float, str]:
    """The engine's sweep over the traced stretch (as the four-bar's screening): order,
    branch and circuit defects; the smallest transmission angles at B and at D over the
    stretch; the four-bar loop's Grashof type."""
    defects, times, first = screened_stretch(y[problem.size :], problem.target.closed)
    model = problem.model(y).compile()
    try:
        linkage = model.linkages()[0]
    except SingularError:
        # drawn at a dead point: no configuration to describe, no step to take from it
        return (*defects, "branch", "circuit"), 0.0, 0.0, grashof_type(*y[:4])
    res: Any
    try:
        res = model.sweep(times, derivatives=0, on_singular="stop")
    except (SingularError, SolveError) as e:
        res = getattr(e, "partial", None)
        defects.append("branch")
    if res is None or len(res.times) == 0:
        return (*defects, "circuit"), 0.0, 0.0, linkage.kind_of
    if any(ev.kind == "limit" for ev in res.events) and "branch" not in defects:
        defects.append("branch")
    pts = problem.points(y, res.times)
    miss = np.hypot(*(res.point("P").position - pts["P"]).T)
    if not np.all(miss <= 1e-7 * max(problem.target.size, float(np.max(np.abs(y[: problem.size]))))):
        defects.append("circuit")
    on = res.times >= first - 1e-12
    mu_b = _smallest((pts["A"] - pts["B"])[on], (pts["O4"] - pts["B"])[on])
    mu_d = _smallest((pts["C"] - pts["D"])[on], (pts["F"] - pts["D"])[on])
    return tuple(defects), mu_b, mu_d, linkage.kind_of


def fit_six_bars(
    target: TargetCurve,
    four_bars: CurveFit | Sequence[CurveDesign] | None = None,
    kinds: Sequence[str] = KINDS,
    best: int = 3,
    dyads: int = 4,
    seed: int = 0,
    workers: int | None = None,
    max_nfev: int = 400,
    seconds: float | None = None,
    starts: int = 16,
    agree: int | None = None,
    **problem: Any,
) -> SixBarFit:
    """Six-bars of each of ``kinds`` grown from the ``best`` best four-bars of
    ``four_bars`` (a `CurveFit` or designs; default `fit` of ``target`` with ``starts``
    random starts, ``seed``, ``agree`` and half the budget), ``dyads`` dyads each (`dyad_seeds`,
    from a generator seeded with ``seed``), refined on ``workers`` threads on the
    `SixBarProblem` with the options ``problem`` (those of `fit`). ``seconds``: a time
    budget for the whole call, as `fit`'s. The answer does not depend on the number of
    workers. Designs are sorted by `SIX_BAR_MERIT` (`ranked`, usable judged by the
    smaller transmission angle of B and D); none is dropped for it."""
    t0 = time.perf_counter()
    deadline = None if seconds is None else t0 + budget_seconds(seconds)
    for k in kinds:
        if k not in KINDS:
            raise SynthesisError(f"a six-bar is one of {', '.join(KINDS)}, not {k!r}")
    SixBarProblem(target, **problem)  # the options checked before any four-bar is fitted
    if four_bars is None:
        half = None if seconds is None else budget_seconds(seconds) / 2.0
        four_bars = fit(
            target,
            starts=starts,
            seed=seed,
            workers=workers,
            max_nfev=max_nfev,
            seconds=half,
            agree=agree,
            **problem,
        )
    base = four_bars if isinstance(four_bars, CurveFit) else CurveFit(list(four_bars), [], 0.0)
    if not base.designs:
        raise SynthesisError("no four-bar to grow six-bars from: " + "; ".join(base.failures[:3]))
    rng = np.random.default_rng(seed)
    jobs: list[tuple[str, str, str, np.ndarray, str]] = []
    for rank, d in enumerate(base.designs[: max(int(best), 0)], 1):
        for kind in kinds:
            for side, y in dyad_seeds(d, kind, dyads, rng):
                jobs.append((kind, d.circuit, side, y, f"four-bar {rank}"))
    problems = {
        (k, c, s): SixBarProblem(target, kind=k, circuit=c, side=s, **problem)
        for k in kinds
        for c in {j[1] for j in jobs}
        for s in SIDES
    }

    def run(job: tuple[int, tuple[str, str, str, np.ndarray, str]]) -> SixBarDesign | str | None:
        k, (kind, circuit, side, y, family) = job
        if deadline is not None and time.perf_counter() >= deadline:
            return None
        try:
            d = refine_six_bar(problems[(kind, circuit, side)], y, max_nfev, k, deadline)
        except CircuitError as e:
            return f"start {k}: {e} ({kind} from {family})"
        d.family = family
        return d

    done = map_starts(run, enumerate(jobs), workers)
    designs = [d for d in done if isinstance(d, SixBarDesign)]
    return SixBarFit(
        ranked(designs),
        [d for d in done if isinstance(d, str)],
        base,
        time.perf_counter() - t0,
        None if seconds is None else float(seconds),
        sum(d is None for d in done),
    )

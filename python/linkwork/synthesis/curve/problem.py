"""A curve-synthesis problem file (``problem = "curve"``, read by ``linkwork synth``):
its tables checked key by key, the fit run, the ranked table of designs.

    problem = "curve"
    angles = "deg"                 # unit of the file's bare angles ("rad" default)
    [curve]
    file = "points.csv"            # or points = [[x, y], ...] or svg = "drawing.svg"
    closed = true                  # default false; an svg: closed when its path ends with Z
    timing = "free"                # or "prescribed": crank_angles = [...] or the CSV's third column
    samples = 64                   # svg: points sampled along the path
    [constraints]                  # all optional
    grashof = "crank-rocker"       # double-crank | full-turn
    transmission = 35              # smallest transmission angle ("35 deg" also read)
    lengths = [lo, hi]             # every link; links = {r2 = [lo, hi]} one link
    ratio = [1, 6]                 # longest link over the shortest
    fixed = {theta0 = 0, x0 = 0, y0 = 0}
    ordered = false
    [constraints.regions]
    O2 = {x = [lo, hi], y = [lo, hi]}     # a box; or {centre = [x, y], radius = r}
    P = {centre = [x, y], radius = r}
    [fit]
    starts = 16, seed = 1, max_nfev = 400, workers = 2, keep = 5
    seconds = 20                   # a time budget for the fit (default none)
    agree = 2                      # rounds of 4 starts until 2 designs agree (default every start)
    [six_bars]                     # optional: six-bars grown from the best four-bars
    kinds = ["watt", "stephenson"] # default both
    best = 2, dyads = 4            # four-bars grown from, dyads added to each (per kind)

Every missing, unknown or ill-shaped key raises `SynthesisError` naming it. With
[six_bars] the designs kept are the six-bars (the four-bars' table is reported above
theirs) and the time budget spans both, half of it for the four-bars.
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np

from ...errors import SynthesisError
from .constraints import angle
from .fit import CURVE_MERIT, CurveDesign, CurveFit, fit, smallest_f_note
from .six_bar_fit import SIX_BAR_MERIT, SixBarDesign, SixBarFit, fit_six_bars
from .six_bars import KINDS
from .target import TargetCurve, from_csv, from_svg, target

__all__ = [
    "read_target",
    "read_options",
    "read_six_bars",
    "solve_curve",
    "table",
    "six_bar_table",
    "distinct",
]

CURVE_KEYS = ("points", "file", "svg", "samples", "closed", "timing", "crank_angles")
CONSTRAINT_KEYS = (
    "grashof",
    "transmission",
    "lengths",
    "links",
    "ratio",
    "regions",
    "fixed",
    "ordered",
    "coupler",
    "pivot",
)
FIT_KEYS = ("starts", "seed", "max_nfev", "workers", "keep", "seconds", "agree")
SIX_BAR_KEYS = ("kinds", "best", "dyads")


def _table(problem: dict[str, Any], name: str, keys: tuple[str, ...], required: bool) -> dict[str, Any]:
    value = problem.get(name)
    if value is None:
        if required:
            raise SynthesisError(f"a curve problem needs a [{name}] table")
        return {}
    if not isinstance(value, dict):
        raise SynthesisError(f"[{name}] must be a table, not {value!r:.60}")
    bad = sorted(set(value) - set(keys))
    if bad:
        raise SynthesisError(f"[{name}] has unknown key(s) {', '.join(bad)}; it takes {', '.join(keys)}")
    return value


def _integer(table: str, key: str, value: Any, least: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < least:
        raise SynthesisError(f"{table}.{key} must be an integer >= {least}, not {value!r}")
    return value


def _flag(table: str, key: str, value: Any) -> bool:
    if not isinstance(value, bool):
        raise SynthesisError(f"{table}.{key} must be true or false, not {value!r}")
    return value


def _pair(table: str, key: str, value: Any) -> tuple[float, float]:
    if not (isinstance(value, list) and len(value) == 2):
        raise SynthesisError(f"{table}.{key} must be [lower, upper], not {value!r}")
    try:
        return float(value[0]), float(value[1])
    except (TypeError, ValueError):
        raise SynthesisError(f"{table}.{key} must be two numbers, not {value!r}") from None


def read_target(problem: dict[str, Any], base: str = ".") -> TargetCurve:
    """The `TargetCurve` of the [curve] table (files relative to ``base``)."""
    curve = _table(problem, "curve", CURVE_KEYS, True)
    unit = problem.get("angles", "rad")
    sources = [k for k in ("points", "file", "svg") if k in curve]
    if len(sources) != 1:
        raise SynthesisError(
            "[curve] gives the target as exactly one of points, file (CSV) or svg"
            + (f"; it has {', '.join(sources)}" if sources else "")
        )
    closed = _flag("curve", "closed", curve.get("closed", False))
    timing = curve.get("timing", "free")
    if timing not in ("free", "prescribed"):
        raise SynthesisError(f"curve.timing is 'free' or 'prescribed', not {timing!r}")
    if "samples" in curve and "svg" not in curve:
        raise SynthesisError("curve.samples is for an svg target")
    if sources == ["points"]:
        pts = curve["points"]
        try:
            arr = np.array(pts, dtype=float)
        except (TypeError, ValueError):
            raise SynthesisError("curve.points must be rows of [x, y] numbers") from None
        t = target(arr, closed=closed)
    elif sources == ["file"]:
        path = os.path.join(base, str(curve["file"]))
        if not os.path.isfile(path):
            raise SynthesisError(f"curve.file: no file {path}")
        t = from_csv(path, closed=closed)
    else:
        path = os.path.join(base, str(curve["svg"]))
        if not os.path.isfile(path):
            raise SynthesisError(f"curve.svg: no file {path}")
        samples = _integer("curve", "samples", curve.get("samples", 64), 4)
        # closed unless stated: as the path says (ending with Z)
        t = from_svg(path, samples=samples, closed=closed if "closed" in curve else None)
    angles = t.crank_angles
    if "crank_angles" in curve:
        if timing != "prescribed":
            raise SynthesisError("curve.crank_angles is given but curve.timing is not 'prescribed'")
        if angles is not None:
            raise SynthesisError("curve.crank_angles is given and the CSV has a crank-angle column: give one")
        try:
            angles = np.array(curve["crank_angles"], dtype=float)
        except (TypeError, ValueError):
            raise SynthesisError("curve.crank_angles must be numbers") from None
        if unit == "deg":
            angles = np.radians(angles)
    if timing == "prescribed" and angles is None:
        raise SynthesisError("curve.timing = 'prescribed' needs crank_angles (or a CSV's third column, rad)")
    if timing == "free":
        angles = None
    return target(t.points, closed=t.closed, crank_angles=angles)


def read_options(problem: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """The `TrackingProblem` options of [constraints] and `fit`'s of [fit]."""
    unit = problem.get("angles", "rad")
    c = _table(problem, "constraints", CONSTRAINT_KEYS, False)
    options: dict[str, Any] = {}
    for key in ("lengths", "ratio", "coupler", "pivot"):
        if key in c:
            options[key] = _pair("constraints", key, c[key])
    if "grashof" in c:
        options["grashof"] = c["grashof"]
    if "transmission" in c:
        value = c["transmission"]
        if not isinstance(value, str):
            number = isinstance(value, (int, float)) and not isinstance(value, bool)
            value = f"{value} {unit}" if number else value
        angle("constraints.transmission", value)  # its form here; its bound in the problem
        options["transmission"] = value
    if "ordered" in c:
        options["ordered"] = _flag("constraints", "ordered", c["ordered"])
    for key in ("links", "regions", "fixed"):
        if key in c and not isinstance(c[key], dict):
            raise SynthesisError(f"constraints.{key} must be a table, not {c[key]!r:.60}")
    if "links" in c:
        options["links"] = {k: _pair("constraints.links", k, v) for k, v in c["links"].items()}
    if "regions" in c:
        options["regions"] = dict(c["regions"])
    if "fixed" in c:
        fixed = {}
        for k, v in c["fixed"].items():
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise SynthesisError(f"constraints.fixed.{k} must be a number, not {v!r}")
            fixed[k] = math.radians(v) if k == "theta0" and unit == "deg" else float(v)
        options["fixed"] = fixed
    f = _table(problem, "fit", FIT_KEYS, False)
    run: dict[str, Any] = {
        "starts": _integer("fit", "starts", f.get("starts", 16), 1),
        "seed": _integer("fit", "seed", f.get("seed", 0), 0),
        "max_nfev": _integer("fit", "max_nfev", f.get("max_nfev", 400), 1),
        "keep": _integer("fit", "keep", f.get("keep", 5), 1),
    }
    if "workers" in f:
        run["workers"] = _integer("fit", "workers", f["workers"], 1)
    if "seconds" in f:
        value = f["seconds"]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
            raise SynthesisError(f"fit.seconds (a time budget) must be a number > 0, not {value!r}")
        run["seconds"] = float(value)
    if "agree" in f:
        run["agree"] = _integer("fit", "agree", f["agree"], 1)
    return options, run


def read_six_bars(problem: dict[str, Any]) -> dict[str, Any] | None:
    """`fit_six_bars`' options of the [six_bars] table (None without one)."""
    if "six_bars" not in problem:
        return None
    t = _table(problem, "six_bars", SIX_BAR_KEYS, True)
    kinds = t.get("kinds", list(KINDS))
    if not (isinstance(kinds, list) and kinds and all(k in KINDS for k in kinds)):
        raise SynthesisError(f"six_bars.kinds must be a list of {', '.join(KINDS)}, not {kinds!r}")
    return {
        "kinds": tuple(kinds),
        "best": _integer("six_bars", "best", t.get("best", 2), 1),
        "dyads": _integer("six_bars", "dyads", t.get("dyads", 4), 1),
    }


def six_bar_table(result: SixBarFit, count: int) -> str:
    """The ranked table of the first ``count`` six-bars."""
    designs = result.designs
    starts = len(designs) + len(result.failures) + result.unstarted
    lines = [
        f"{len(designs)} six-bars from {starts} starts in {result.seconds:.2f} s "
        f"({len(result.failures)} dropped); sorted: {SIX_BAR_MERIT}",
        f"{'#':>3}  {'f':>10}  {'largest dev.':>12}  {'at B':>8}  {'at D':>8}  {'kind':<11} "
        "defects; constraints",
    ]
    if result.budget is not None:
        ended = "ended" if result.budget_ended else "did not end"
        lines.insert(1, f"the time budget of {result.budget:.4g} s {ended} the fit")
    for k, d in enumerate(designs[:count], 1):
        defects = ", ".join(d.defects) or "none"
        state = "hold" if d.violation <= 1e-12 * d.problem.target.size else f"violated by {d.violation:.3g}"
        lines.append(
            f"{k:>3}  {d.f:>10.4g}  {d.max_deviation:>12.4g}  {math.degrees(d.transmission):>4.1f} deg  "
            f"{math.degrees(d.transmission_dyad):>4.1f} deg  {d.kind:<11} {defects}; {state}"
        )
    note = smallest_f_note(designs)
    if note:
        lines.append(note)
    for k, d in enumerate(designs[:count], 1):
        lines.append(f"six-bar {k}: {d}")
        if d.margins:
            lines.append("  margins: " + ", ".join(f"{n} {v:.4g}" for n, v in d.margins.items()))
    return "\n".join(lines)


def table(result: CurveFit, count: int, designs: list[CurveDesign] | None = None) -> str:
    """The ranked table of the first ``count`` of ``designs`` (default the fit's)."""
    designs = result.designs if designs is None else designs
    starts = len(result.designs) + len(result.failures) + result.unstarted + result.unrefined
    lines = [
        f"{len(designs)} distinct designs from {starts} starts in {result.seconds:.2f} s "
        f"({len(result.failures)} dropped); sorted: {CURVE_MERIT}",
        f"{'#':>3}  {'f':>10}  {'largest dev.':>12}  {'transmission':>12}  {'circuit':<8} "
        f"{'Grashof type':<16} defects; constraints",
    ]
    if result.budget is not None:
        lines.insert(1, result.budget_note())
    if result.unrefined:
        lines.insert(1, f"{result.unrefined} starts left unrefined: enough designs agreed on the smallest f")
    for k, d in enumerate(designs[:count], 1):
        defects = ", ".join(d.defects) or "none"
        state = "hold" if d.violation <= 1e-12 * d.problem.target.size else f"violated by {d.violation:.3g}"
        lines.append(
            f"{k:>3}  {d.f:>10.4g}  {d.max_deviation:>12.4g}  {math.degrees(d.transmission):>8.1f} deg  "
            f"{d.circuit:<8} {d.grashof:<16} {defects}; {state}"
        )
    note = result.smallest_f_note(designs)
    if note:
        lines.append(note)
    for k, d in enumerate(designs[:count], 1):
        lines.append(f"design {k}: {d}")
        if d.margins:
            lines.append("  margins: " + ", ".join(f"{n} {v:.4g}" for n, v in d.margins.items()))
    return "\n".join(lines)


def solve_curve(
    problem: dict[str, Any], base: str = "."
) -> tuple[str, list[CurveDesign] | list[SixBarDesign], np.ndarray]:
    """(the ranked table, the best designs, the target points) of a curve problem file:
    the four-bars, or with [six_bars] the six-bars grown from them."""
    t = read_target(problem, base)
    options, run = read_options(problem)
    six = read_six_bars(problem)
    keep = run.pop("keep")
    timing = "prescribed" if t.timed else "free"
    head = (
        f"curve synthesis: {len(t)} target points ({'closed' if t.closed else 'open'}, {timing} timing), "
        f"{run['starts']} starts, seed {run['seed']}"
        + (f", agree {run['agree']} (rounds of 4 starts)" if "agree" in run else "")
    )
    if six is None:
        result = fit(t, **run, **options)
        designs = distinct(result.designs)
        return head + "\n" + table(result, keep, designs), designs[:keep], t.points
    grown = fit_six_bars(t, **six, **run, **options)
    four = grown.four_bars
    text = [head, table(four, keep, distinct(four.designs)), six_bar_table(grown, keep)]
    return "\n".join(text), grown.designs[:keep], t.points


def distinct(designs: list[CurveDesign]) -> list[CurveDesign]:
    """The designs without repeats (two starts refined to the same linkage: the same
    circuit, lengths, coupler point and pivot to 1e-6 of the target's size, theta0 the
    same modulo a turn), in order."""
    out: list[CurveDesign] = []
    for d in designs:
        tol = 1e-6 * d.problem.target.size
        key = np.concatenate([d.x[:6], d.x[7:9]])
        same = False
        for e in out:
            turn = abs(math.remainder(float(d.x[6] - e.x[6]), 2.0 * math.pi))
            other = np.concatenate([e.x[:6], e.x[7:9]])
            if e.circuit == d.circuit and turn <= 1e-6 and np.max(np.abs(key - other)) <= tol:
                same = True
                break
        if not same:
            out.append(d)
    return out

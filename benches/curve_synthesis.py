"""Synthesis from a curve, by the tracking error: linkwork's multistart (random Grashof
crank-rockers refined by bounded trust-region least squares with the engine's exact
Jacobian) against scipy's differential evolution on the same objective, in one process,
at the same wall-time budget, on the problems of the notes that are given for tuning:
Cabrera's vertical line (6 points, free timing), Cabrera's elliptic arc (5 points,
timed, theta0 = x0 = y0 = 0) and Kunjur's closed curve (18 points, free timing).

Constraint set everywhere: a Grashof crank-rocker (the crank the shortest link, turning
fully on its circuit); the ordering r2 <= r3 <= r4 <= r1 only on the row that says so.
Differential evolution gets the closed form of the objective, vectorised (faster per
evaluation than the engine), the same bounds and crank-angle parametrisation, a penalty
outside the constraints, and stops at the budget (no final polish).

Then the seeds' effect (atlas + Alt + random against random only, on the free-timing
problems), the shape problems (McGarva, Ullah and Kota: mean nearest distance after the
best similarity) and, at linkwork's wall time on each, pylinkage's particle swarm
(`pylinkage.optimization.particle_swarm_optimization`, its documented entry point, with
``dimensions`` and an ``eval_func`` that ignores the linkage and scores the same
closed-form objective) and scipy's differential evolution on the same objective.

    python benches/curve_synthesis.py            # print
    python benches/curve_synthesis.py --write    # also add it to the day's log in benches/results/
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import subprocess
import time
from pathlib import Path

import numpy as np
import runlog  # benches/, beside this script
from scipy.optimize import differential_evolution

import linkwork
from linkwork.synthesis import curve as C
from linkwork.synthesis.curve.descriptors import nearest_distances, shape_error
from linkwork.synthesis.curve.shape import traced

ROOT = Path(__file__).resolve().parent.parent
DATA = Path(os.environ.get("LINKWORK_PATH_DATA", "/work/shared/data/path-synthesis"))
TWO_PI = 2.0 * math.pi

# name, file, closed, problem options, best known f (the notes' figure and its design)
PROBLEMS = [
    (
        "Cabrera 6-pt vertical line",
        "cabrera_6pt_vertical_line.csv",
        False,
        {},
        3.9e-28,
        "Mechanisms.jl's README",
    ),
    (
        "Cabrera 5-pt elliptic arc (timed)",
        "cabrera_5pt_elliptic_arc_timed.csv",
        False,
        {"fixed": {"theta0": 0.0, "x0": 0.0, "y0": 0.0}, "lengths": (1e-3, 5.0), "coupler": (-5.0, 5.0)},
        7.4e-7,
        "the notes, Grashof crank-rocker only",
    ),
    (
        "Cabrera 5-pt elliptic arc (timed, ordered)",
        "cabrera_5pt_elliptic_arc_timed.csv",
        False,
        {
            "fixed": {"theta0": 0.0, "x0": 0.0, "y0": 0.0},
            "lengths": (1e-3, 5.0),
            "coupler": (-5.0, 5.0),
            "ordered": True,
        },
        4.7e-4,
        "the notes, under r2 <= r3 <= r4 <= r1",
    ),
    (
        "Kunjur 18-pt closed",
        "kunjur_18pt_closed.csv",
        True,
        {},
        0.00314,
        "local polish of Bulatovic et al.'s",
    ),
]


def _closed_form_f(problem: C.TrackingProblem, xs: np.ndarray) -> np.ndarray:
    """f for many full design vectors (m x (9 + n)) in closed form, with a penalty outside
    the constraints (not a crank-rocker with the crank shortest; a point not assembled)."""
    t = problem.target
    size2 = t.size**2
    out = np.empty(len(xs))
    for k, x in enumerate(xs):
        r = sorted(x[:4])
        grashof_gap = r[0] + r[3] - r[1] - r[2]
        g = np.append(problem.constraints(x)[0], grashof_gap)
        bad = float(np.maximum(g, 0.0).sum())
        c = C.coupler_points(x, x[9:], problem.circuit)
        if bad > 0.0 or not np.all(np.isfinite(c)):
            out[k] = 1e3 * size2 * (1.0 + bad)
            continue
        out[k] = float(np.sum((c - t.points) ** 2))
    return out


def de_run(problem: C.TrackingProblem, budget: float, seed: int) -> tuple[float, float, int]:
    """Differential evolution for ``budget`` seconds (it stops at the first generation
    past it): the best f within the constraints, the time it ran, the evaluations."""
    lo, hi = problem.lower_upper()
    free = problem.free()
    design = np.flatnonzero(free[:9])
    timing = bool(free[9:].any())
    n = problem.n
    zlo = list(lo[design]) + ([0.0] * n if timing else [])
    zhi = list(hi[design]) + ([TWO_PI] * n if timing else [])
    base = problem.complete(np.zeros(9 + n))

    def xs_of(z: np.ndarray) -> np.ndarray:
        xs = np.repeat(base[None, :], z.shape[1], axis=0)
        xs[:, design] = z[: design.size].T
        if timing:
            xs[:, 9:] = np.cumsum(z[design.size :].T, axis=1)
        return xs

    evals = [0]

    def f(z: np.ndarray) -> np.ndarray:
        evals[0] += z.shape[1]
        return _closed_form_f(problem, xs_of(z))

    t0 = time.perf_counter()
    sol = differential_evolution(
        f,
        list(zip(zlo, zhi)),
        seed=seed,
        maxiter=10**9,
        tol=0.0,
        atol=0.0,
        polish=False,
        vectorized=True,
        updating="deferred",
        callback=lambda *a, **k: time.perf_counter() - t0 > budget,
    )
    x = xs_of(sol.x[:, None])[0]
    value = _closed_form_f(problem, x[None, :])[0]
    return float(value), time.perf_counter() - t0, evals[0]


def run(starts: int, seed: int) -> list[dict]:
    rows = []
    for name, file, closed, options, best, source in PROBLEMS:
        target = C.from_csv(DATA / file, closed=closed)
        t0 = time.perf_counter()
        fit = C.fit(target, starts=starts, seed=seed, workers=2, **options)
        seconds = time.perf_counter() - t0
        ok = [d for d in fit.designs if d.ok]
        # the smallest f of a defect-free design (the literature's figure, whatever its
        # transmission angle) and the first usable design of the ranking
        top = min(ok, key=lambda d: d.f) if ok else fit.designs[0]
        usable = next((d for d in fit.designs if d.usable), None)
        # the same wall time, half on each circuit
        des = [
            de_run(C.TrackingProblem(target, circuit=c, **options), seconds / 2, seed)
            for c in ("open", "crossed")
        ]
        de_f, de_n = min(d[0] for d in des), sum(d[2] for d in des)
        rows.append(
            dict(
                name=name,
                n=len(target),
                f=top.f,
                dev=top.max_deviation,
                ok=top.ok,
                circuit=top.circuit,
                trans=math.degrees(top.transmission),
                seconds=seconds,
                dropped=len(fit.failures),
                best=best,
                source=source,
                de_f=de_f,
                de_n=de_n,
                nfev=sum(d.nfev for d in fit.designs),
                usable=None if usable is None else (usable.f, math.degrees(usable.transmission)),
            )
        )
    return rows


def table(starts: int, seed: int, aside: bool = False, shapes_only: bool = False) -> str:
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    try:
        commit = subprocess.check_output(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, text=True).strip()
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    rows = [] if shapes_only else run(starts, seed)
    extra = seeds_and_shapes(seed, aside, shapes_only)
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    lines = [
        f"Measured {stamp} with linkwork {linkwork.__version__} at {commit}, "
        f"Python {platform.python_version()}, {os.cpu_count()} cores (load average {load}); "
        f"`python benches/curve_synthesis.py --starts {starts} --seed {seed}"
        f"{' --aside' if aside else ''}{' --shapes-only' if shapes_only else ''}"
        f"{f' --sizes {SIZES:g}' if SIZES != 3.0 else ''}"
        f"{f' --full-budget {FULL_BUDGET:g}' if FULL_BUDGET else ''}`.",
        "",
        "Tracking error f = sum |C(theta2_i) - P_i|^2 under a Grashof crank-rocker (crank "
        f"shortest), no ordering unless said. linkwork: {starts} random crank-rockers (seed {seed}) "
        "refined on 2 threads, the defect-free design within the constraints of smallest f (its "
        "transmission angle as it comes), and the first usable one of the ranking (smallest "
        "transmission angle at least 30 deg). Differential "
        "evolution (scipy, closed-form objective, vectorised, one process, seed the same) for the same "
        "wall time, half of it on each circuit.",
        "",
        "| problem | points | linkwork f | largest deviation | time | evaluations | starts dropped "
        "| smallest transmission | first usable design: f, transmission "
        "| best known f | DE f (same time) | DE evaluations |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        usable = "none" if r["usable"] is None else f"{r['usable'][0]:.4g}, {r['usable'][1]:.1f} deg"
        lines.append(
            f"| {r['name']} | {r['n']} | {r['f']:.4g}{'' if r['ok'] else ' (with defects)'} | {r['dev']:.3g} "
            f"| {r['seconds']:.1f} s | {r['nfev']} | {r['dropped']} | {r['trans']:.1f} deg | {usable} "
            f"| {r['best']:.3g} ({r['source']}) "
            f"| {r['de_f']:.4g} | {r['de_n']} |"
        )
    return "\n".join(lines + extra)


# ---- seeds, shapes and pylinkage ------------------------------------------------------------
# free-timing tracking problems (name, file, closed, best known f and its source)
FREE = [
    ("Cabrera 6-pt vertical line", "cabrera_6pt_vertical_line.csv", False, 3.9e-28, "Mechanisms.jl"),
    ("Kunjur 18-pt closed", "kunjur_18pt_closed.csv", True, 0.00314, "local polish of Bulatovic et al.'s"),
    ("Yu, Tang, Wang 2007 case 1", "yu_2007_case1.csv", True, 0.854, "local polish of Yu et al.'s"),
]
# shape problems (name, file, the literature design's mean nearest distance, per the notes)
SHAPES = [
    ("McGarva 1994", "mcgarva_1994.csv", 1.52),
    ("Ullah and Kota 1997", "ullah_kota_1997.csv", 0.070),
]
# kept aside to check the method, not to tune it (run with --aside): Hernandez, Munoyerro,
# Urizar and Amezua 2021's triangle (as in KmolYuan/four-bar-rs test-fb/triangle.closed.csv;
# a corner no four-bar follows), and the coupler curve of Wu, Ge, Gao and Guo 2011's case-1
# design (four-bar-rs refer/wu1.closed.ron: l1..l4 = 11, 6, 8, 10, l5 = 7, g = 0.6981,
# a = 0.1745, O2 = (10, 14)) on the open circuit at 60 even crank angles (a four-bar
# traces it exactly: its optimum is 0)
TRIANGLE = [
    (0, 0), (9, 0), (18, 0), (27, 0), (36, 0), (45, 0), (41.79, 3.21), (38.57, 6.43), (35.35, 9.65),
    (32.13, 12.87), (28.92, 16.08), (25.7, 19.3), (22.5, 22.5), (19.3, 19.3), (16.08, 16.08),
    (12.87, 12.87), (9.65, 9.65), (6.43, 6.43), (3.21, 3.21),
]  # fmt: skip
WU1 = [11.0, 6.0, 8.0, 10.0, 7.0 * math.cos(0.6981), 7.0 * math.sin(0.6981), 0.1745, 10.0, 14.0]


def aside_shapes() -> list[tuple[str, np.ndarray, float | None]]:
    """The kept-aside shape problems: (name, points, literature figure or None)."""
    wu = C.coupler_points(WU1, np.linspace(0.0, TWO_PI, 60, endpoint=False), "open")
    return [
        ("Hernandez et al. 2021 triangle (aside)", np.array(TRIANGLE, dtype=float), None),
        ("Wu et al. 2011 case 1 curve (aside)", wu, None),
    ]


class _Budget(Exception):
    """Raised inside an objective when the wall-time budget is spent."""


def _pso(objective, lo, hi, budget: float) -> tuple[float, int]:  # noqa: ANN001
    """pylinkage's particle swarm (defaults but ``verbose``) on ``objective`` (one vector
    -> cost) within ``lo``..``hi`` for ``budget`` seconds: the best cost it evaluated by
    then and its evaluations. The linkage it asks for only lends its joints' coordinates,
    which the objective ignores; pylinkage seeds its generator from the system."""
    import pylinkage as pl
    from pylinkage.optimization import particle_swarm_optimization

    o2, o4 = pl.Ground(0.0, 0.0), pl.Ground(3.0, 0.0)
    crank = pl.Crank(o2, 1.0)
    linkage = pl.Linkage([o2, o4, crank, pl.RRRDyad(crank.output, o4, 3.0, 1.0)])
    best, evals, t0 = [math.inf], [0], time.perf_counter()

    def score(_linkage, dims, _coords) -> float:  # noqa: ANN001
        if time.perf_counter() - t0 > budget:
            raise _Budget
        evals[0] += 1
        v = float(objective(np.asarray(dims, dtype=float)))
        best[0] = min(best[0], v)
        return v

    try:
        particle_swarm_optimization(
            score,
            linkage,
            dimensions=len(lo),
            bounds=(list(lo), list(hi)),
            order_relation=min,
            iterations=10**9,
            verbose=False,
        )
    except _Budget:
        pass
    return best[0], evals[0]


def _z_space(problem: C.TrackingProblem):  # noqa: ANN202
    """The bounds and the map z -> x of `de_run` (crank angles as a first angle and increments)."""
    lo, hi = problem.lower_upper()
    free = problem.free()
    design = np.flatnonzero(free[:9])
    n = problem.n
    zlo = np.array(list(lo[design]) + [0.0] * n)
    zhi = np.array(list(hi[design]) + [TWO_PI] * n)
    base = problem.complete(np.zeros(9 + n))

    def x_of(z: np.ndarray) -> np.ndarray:
        x = base.copy()
        x[design] = z[: design.size]
        x[9:] = np.cumsum(z[design.size :])
        return x

    return zlo, zhi, x_of


def pso_tracking(target: C.TargetCurve, budget: float) -> tuple[float, int]:
    """pylinkage's swarm on the tracking error (the closed form with `de_run`'s penalty),
    half the budget on each circuit."""
    out = []
    for circuit in ("open", "crossed"):
        problem = C.TrackingProblem(target, circuit=circuit)
        zlo, zhi, x_of = _z_space(problem)
        out.append(
            _pso(lambda z, p=problem, f=x_of: _closed_form_f(p, f(z)[None, :])[0], zlo, zhi, budget / 2)
        )
    return min(o[0] for o in out), sum(o[1] for o in out)


def _shape_objective(points: np.ndarray, circuit: str):  # noqa: ANN202
    """The mean nearest distance of the traced curve of the nine design numbers (the
    similarity is in them), a large penalty where the crank does not turn fully."""
    size = float(np.hypot(*np.ptp(points, axis=0)))

    def f(x: np.ndarray) -> float:
        c = traced(x, circuit, 360)
        if not np.all(np.isfinite(c)):
            return 1e3 * size
        return float(nearest_distances(points, c).mean())

    return f


# the shape problems' design space, in target sizes (--sizes)
SIZES = 3.0
# linkwork's atlas seeds on a shape problem (shape_fit's default)
SHAPE_SEEDS = 12
# the baselines on the shape problems again for this many seconds (--full-budget; 0: not run)
FULL_BUDGET = 0.0


def _shape_space(points: np.ndarray) -> dict[str, tuple[float, float]]:
    """The design space of every method on the shape problems: lengths up to SIZES
    sizes, the coupler point within SIZES sizes, the pivot O2 within SIZES - 1 sizes of
    the points."""
    size = float(np.hypot(*np.ptp(points, axis=0)))
    lo, hi = float(points.min()) - (SIZES - 1.0) * size, float(points.max()) + (SIZES - 1.0) * size
    return {
        "lengths": (1e-3 * size, SIZES * size),
        "coupler": (-SIZES * size, SIZES * size),
        "pivot": (lo, hi),
    }


def _shape_bounds(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    b = _shape_space(points)
    return (
        np.array([b["lengths"][0]] * 4 + [b["coupler"][0]] * 2 + [-math.pi] + [b["pivot"][0]] * 2),
        np.array([b["lengths"][1]] * 4 + [b["coupler"][1]] * 2 + [math.pi] + [b["pivot"][1]] * 2),
    )


def _de(objective, lo, hi, budget: float, seed: int) -> int:  # noqa: ANN001
    """scipy's differential evolution on ``objective`` for ``budget`` seconds (no polish):
    its evaluations."""
    t0, evals = time.perf_counter(), [0]

    def h(x: np.ndarray) -> float:
        evals[0] += 1
        return objective(x)

    differential_evolution(
        h,
        list(zip(lo, hi)),
        seed=seed,
        maxiter=10**9,
        tol=0.0,
        atol=0.0,
        polish=False,
        callback=lambda *a, **k: time.perf_counter() - t0 > budget,
    )
    return evals[0]


class _Best:
    """An objective that remembers the best point it was asked about."""

    def __init__(self, f) -> None:  # noqa: ANN001
        self.f, self.x, self.v = f, None, math.inf

    def __call__(self, x: np.ndarray) -> float:
        v = self.f(x)
        if v < self.v:
            self.x, self.v = np.array(x), v
        return v


def baselines_shape(points: np.ndarray, budget: float, seed: int) -> tuple[float, int, float, int]:
    """pylinkage's swarm and scipy's differential evolution on the shape objective over
    the nine design numbers, each for ``budget`` (half on each circuit): the mean nearest
    distance after the best similarity of the best each found, and its evaluations."""
    lo, hi = _shape_bounds(points)
    means = {"pso": [math.inf], "de": [math.inf]}
    evals = {"pso": 0, "de": 0}
    for circuit in ("open", "crossed"):
        for key in ("pso", "de"):
            best = _Best(_shape_objective(points, circuit))
            if key == "pso":
                evals[key] += _pso(best, lo, hi, budget / 2)[1]
            else:
                evals[key] += _de(best, lo, hi, budget / 2, seed)
            if best.x is not None and np.all(np.isfinite(traced(best.x, circuit))):
                # as placed or after the similarity shape_error finds, the smaller (as linkwork's)
                c = traced(best.x, circuit)
                placed = float(nearest_distances(points, c).mean())
                means[key].append(min(placed, shape_error(points, c, polish=False).mean))
    return min(means["pso"]), evals["pso"], min(means["de"]), evals["de"]


def _full_columns() -> str:
    b = f"{FULL_BUDGET:g} s"
    return f" PSO, {b} | DE, {b} | ratio, {b} |" if FULL_BUDGET else ""


def seeds_and_shapes(seed: int, aside: bool = False, shapes_only: bool = False) -> list[str]:
    """The tables of the seeds' effect and of the shape problems, with the baselines."""
    lines = [
        "",
        "Seeds' effect on the free-timing problems (f: the defect-free design of smallest f): "
        "linkwork from 8 atlas seeds, Alt's 16 "
        "crank-rockers of smallest tracking error through nine points along the target (the "
        "homotopy bounded by 10 s) and 8 random ones (seeds; refined in rounds of 4 until two "
        "defect-free designs agree on the smallest f to 1 %, `agree=2`) against 32 random ones; the time "
        f"includes the seeds' (seed {seed}). Then pylinkage 1.3.0's particle swarm "
        "(`particle_swarm_optimization`, its defaults: 100 particles; an `eval_func` scoring the "
        "same closed-form objective with the same penalty as DE; its generator is not seedable) "
        "and scipy's DE, each for the seeded run's wall time, half on each circuit, one process.",
        "",
        "| problem | seeded f | best from | time | Alt: real four-bars with cognates (seeds kept), time "
        "| random-only f | time | pylinkage PSO f | PSO evaluations | DE f | best known f |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, file, closed, best, source in [] if shapes_only else FREE:
        target = C.from_csv(DATA / file, closed=closed)
        t0 = time.perf_counter()
        sd = C.make_seeds(target, atlas=8, alt=16, random=8, seed=seed, seconds=10.0)
        seeded = C.fit(target, seeds=list(sd), workers=2, agree=2)
        t_seeded = time.perf_counter() - t0
        alone = C.fit(target, starts=32, seed=seed, workers=2)
        top = min((d for d in seeded.designs if d.ok), key=lambda d: d.f, default=seeded.best)
        top_r = min((d for d in alone.designs if d.ok), key=lambda d: d.f, default=alone.best)
        pso_f, pso_n = pso_tracking(target, t_seeded)
        de_f = min(
            de_run(C.TrackingProblem(target, circuit=c), t_seeded / 2, seed)[0] for c in ("open", "crossed")
        )
        # the penalty's floor: nothing within the constraints was found
        shown = [f"{v:.4g}" if v < 1e3 * target.size**2 else "none feasible" for v in (pso_f, de_f)]
        alt_note = next((n for n in sd.notes if n.startswith("Alt:")), "Alt: not run")
        if "real four-bars" in alt_note:
            alt = f"{alt_note.split(': ', 1)[1].split(' real')[0]} ({sd.counts.get('alt', 0)} kept), "
            alt += f"{sd.seconds.get('alt', 0.0):.1f} s"
        else:
            alt = "none: no four-bar passes nine collinear points" if "line" in alt_note else alt_note
        lines.append(
            f"| {name} | {top.f:.4g}{'' if top.ok else ' (with defects)'} | {top.family} | {t_seeded:.1f} s "
            f"| {alt} | {top_r.f:.4g} | {alone.seconds:.1f} s | {shown[0]} | {pso_n} | {shown[1]} "
            f"| {best:.3g} ({source}) |"
        )
    lines += [
        "",
        "Shape problems: mean nearest distance from the target points to the traced curve after the "
        "best similarity (position, rotation, scale and start free). Every method searches the same "
        f"design space (lengths up to {SIZES:g} target sizes, the coupler point within {SIZES:g} sizes, "
        f"O2 within {SIZES - 1:g} sizes of the points; size: the diagonal of the points' box). "
        "linkwork: `shape_fit(points, "
        f"seed={seed}, **space)` (12 atlas seeds, the target run either way, refined in rounds of 4, "
        "nearest first, until two refined designs agree on the best mean to 1 %, by the tracking "
        "error with free crank angles on 36 of the points, scored on all, the best polished by "
        "reweighted least squares on all the points until a round moves the mean by less than 1e-5 "
        "of it) on 2 threads. The atlas alone: its nearest "
        "design, placed by the best similarity. pylinkage's swarm and scipy's DE on the mean nearest "
        "distance itself over the nine design numbers (closed form, 360 crank angles), each for "
        "linkwork's wall time, half on each circuit. Ratio: the better baseline over linkwork."
        + (
            f" Then both again for the problem's whole budget of {FULL_BUDGET:g} s (half on each circuit)."
            if FULL_BUDGET
            else ""
        ),
        "",
        "| problem | points | linkwork mean | largest | time | seeds refined | atlas alone | pylinkage PSO "
        "| DE | ratio | literature design | target (half) |" + _full_columns(),
        "|---|---|---|---|---|---|---|---|---|---|---|---|" + ("---|---|---|" if FULL_BUDGET else ""),
    ]
    problems = [(name, C.from_csv(DATA / file, closed=True).points, lit) for name, file, lit in SHAPES]
    for name, pts, lit in problems + (aside_shapes() if aside else []):
        res = C.shape_fit(pts, k=SHAPE_SEEDS, seed=seed, workers=2, **_shape_space(pts))
        hits = C.load_atlas().query(pts, k=6)
        atlas_alone = min(shape_error(pts, h.curve(720)).mean for h in hits)
        pso_m, _, de_m, _ = baselines_shape(pts, res.seconds, seed)
        b = res.best
        lit_s = "" if lit is None else f"{lit:.3g} | {lit / 2:.3g}"
        full = ""
        if FULL_BUDGET:
            pso_f, _, de_f, _ = baselines_shape(pts, FULL_BUDGET, seed)
            full = f" {pso_f:.4g} | {de_f:.4g} | {min(pso_f, de_f) / b.mean:.3g} |"
        lines.append(
            f"| {name} | {len(pts)} | {b.mean:.4g} | {b.largest:.3g} | {res.seconds:.1f} s "
            f"| {SHAPE_SEEDS - res.unrefined} | {atlas_alone:.4g} "
            f"| {pso_m:.4g} | {de_m:.4g} | {min(pso_m, de_m) / b.mean:.3g} | {lit_s or ' | '} |" + full
        )
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--starts", type=int, default=16)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--write", action="store_true", help="add the run to benches/results/")
    ap.add_argument("--aside", action="store_true", help="also the shape problems kept aside")
    ap.add_argument("--shapes-only", action="store_true", help="only the shape problems")
    ap.add_argument(
        "--sizes", type=float, default=3.0, help="the shape problems' design space, in target sizes"
    )
    ap.add_argument(
        "--full-budget",
        type=float,
        default=0.0,
        help="also run the shape problems' baselines for this many seconds (0: not)",
    )
    args = ap.parse_args()
    global SIZES, FULL_BUDGET
    SIZES = args.sizes
    FULL_BUDGET = args.full_budget
    text = table(args.starts, args.seed, args.aside, args.shapes_only)
    print(text)
    if args.write:
        stamp = text.split(" with ", 1)[0].removeprefix("Measured ")
        runlog.append_run("curve_synthesis.py", stamp, text)


if __name__ == "__main__":
    main()

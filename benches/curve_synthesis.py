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
        g = np.append(problem.constraints(x), grashof_gap)
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
        top = ok[0] if ok else fit.designs[0]
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
            )
        )
    return rows


def table(starts: int, seed: int) -> str:
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    try:
        commit = subprocess.check_output(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, text=True).strip()
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    rows = run(starts, seed)
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    lines = [
        f"Measured {stamp} with linkwork {linkwork.__version__} at {commit}, "
        f"Python {platform.python_version()}, {os.cpu_count()} cores (load average {load}); "
        f"`python benches/curve_synthesis.py --starts {starts} --seed {seed}`.",
        "",
        "Tracking error f = sum |C(theta2_i) - P_i|^2 under a Grashof crank-rocker (crank "
        f"shortest), no ordering unless said. linkwork: {starts} random crank-rockers (seed {seed}) "
        "refined on 2 threads, the best defect-free design within the constraints. Differential "
        "evolution (scipy, closed-form objective, vectorised, one process, seed the same) for the same "
        "wall time, half of it on each circuit.",
        "",
        "| problem | points | linkwork f | largest deviation | time | starts dropped | smallest transmission "
        "| best known f | DE f (same time) | DE evaluations |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['name']} | {r['n']} | {r['f']:.4g}{'' if r['ok'] else ' (with defects)'} | {r['dev']:.3g} "
            f"| {r['seconds']:.1f} s | {r['dropped']} | {r['trans']:.1f} deg "
            f"| {r['best']:.3g} ({r['source']}) "
            f"| {r['de_f']:.4g} | {r['de_n']} |"
        )
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--starts", type=int, default=16)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--write", action="store_true", help="add the run to benches/results/")
    args = ap.parse_args()
    text = table(args.starts, args.seed)
    print(text)
    if args.write:
        stamp = text.split(" with ", 1)[0].removeprefix("Measured ")
        runlog.append_run("curve_synthesis.py", stamp, text)


if __name__ == "__main__":
    main()

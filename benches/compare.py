"""Speed against error, in one run: linkwork against what users would otherwise run.

    python benches/compare.py            # measure and print the full report (Markdown)
    python benches/compare.py --write    # and add it to benches/results/performance-<date>.md
                                         # (with the plot and the figures as JSON) and write
                                         # the verdicts into docs/performance.md
    python benches/compare.py --load benches/results/compare-<date>-<time>.json --write
                                         # the verdicts of a saved run again, no measuring

Everything runs in this one process (the memory probe in a child per chain length), so
the ratios are read from one run on one machine: the machines are shared and noisy, the
ratios are what to read. Times are the best of a few repeats, compile and JIT excluded.

1. The textbook four-bar (ground 0.35, crank 0.20, coupler 0.35, rocker 0.25 m, crank at
   5 rad/s), one revolution in 100,000 steps: linkwork's ``sweep`` (every linear solver
   kind the engine has; positions only, + velocities, + accelerations), pylinkage's numba
   fast path (``step_fast``, ``step_fast_with_kinematics``; optional: "not installed"
   otherwise), SciPy's fsolve (positions only), the closed form itself (vectorised
   NumPy) and ``linkwork.reference``; each against ``linkwork.closed_form.four_bar``.
2. The other built-in mechanisms: time per step per coordinate against the four-bar's.
3. Scaling: ``examples.chain(K)``, K four-bar loops in series (3K bodies), K = 1 ..
   10,000: time per step, per body, the fitted exponent, peak memory.
4. Many designs at once: ``linkwork.sweep_batch`` on 1 and 2 threads.
5. Speed against error: Newton tolerance and step count swept; the plot.
6. The targets of the performance issue, met or missed, and by how much.
"""

from __future__ import annotations

import argparse
import gc
import inspect
import json
import math
import os
import platform
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any, Callable

import numpy as np

import linkwork
from linkwork import closed_form, examples
from linkwork.reference import ReferenceModel

sys.path.insert(0, str(Path(__file__).resolve().parent))
import baselines  # noqa: E402
import runlog  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
DIMS = dict(ground=0.35, crank=0.20, coupler=0.35, rocker=0.25)
OMEGA = 5.0
PERIOD = 2.0 * math.pi / OMEGA
QUANTITIES = {0: "p", 1: "p+v", 2: "p+v+a"}
CHAIN_H = PERIOD / 100_000  # the chain's step: the four-bar's at 100,000 steps per revolution
HAS_DERIVATIVES = "derivatives" in inspect.signature(linkwork.Model.sweep).parameters
HAS_BATCH = hasattr(linkwork, "sweep_batch")

SLIDER_TEXT = """
`examples.slider_crank()` (crank 0.10 m, rod 0.35 m, offset 0.02 m, 5 rad/s), {steps:,}
steps over one revolution, fresh output memory for every row, errors against
`linkwork.closed_form.slider_crank`. pylinkage 1.3's numba paths solve the crank and
leave the slider where it was drawn (their errors show it): its one path that moves the
slider is its Python loop `step` ({py_steps:,} steps, positions only; its
`step_with_derivatives` gives the slider no rates).
"""

FOUR_BAR_TEXT = """
{steps:,} steps over one revolution (the reference: {ref_steps:,}; its time per step does not depend
on the step count). Errors: the largest absolute errors of the coupler and rocker angle, angular
velocity and angular acceleration against `linkwork.closed_form.four_bar` (alpha peaks at 112 rad/s^2
here). *time / linkwork's*: against linkwork's auto row computing the same quantities (p: positions,
v: velocities, a: accelerations). The closed-form row is the vectorised NumPy formula the errors are
measured against: a floor, not a solver of general mechanisms. Not measured here (quoted from the
issue, measured on the same kind of machine): Exudyn 1.13 8-17 us per step (alpha error about 1e-2),
Pinocchio 4.1 with a hand-written Newton loop 35 us, SolveSpace 22-45 us (positions only).
"""

CHAIN_TEXT = """
Each loop the textbook four-bar, all on the same two ground pivots (stacked in parallel planes);
loop k+1's crank tied to loop k's rocker by a constant relative angle of {offset:.4f} rad; only
loop 1's crank driven. Step h = one revolution / 100,000 at every K (so the Newton work
per step is the four-bar's), steps = {budget:,.0f} / K (at most 100,000, at least 100), best of 3 (2
at K = 10,000). Errors against the four-bar closed form applied loop after loop, over every body.
That tie angle makes the chain settle where a loop's gain d theta4 / d theta2 is -0.97, so the
motion fades slowly along the chain (the last rocker's largest rate is given). With a tie of 0 it
settles where the gain is 0.8 and beyond loop ~3,000 the rates underflow into subnormal numbers,
which this processor handles about a hundred times slower: a property of that chain, not of the
solver, so it is avoided here.
"""

TRADEOFF_TEXT = """
The same four-bar; x: time per step (positions, velocities and accelerations), y: the largest alpha
error over the revolution. Swept: the Newton tolerance (`tol_residual` = `tol_step`) at a fixed step
count, and the steps per revolution at the default tolerance 1e-12.
"""


def para(text: str) -> str:
    """One Markdown paragraph from a wrapped text."""
    return " ".join(text.split())


class Unavailable(Exception):
    """An API this benchmark would use is not in this build of linkwork."""


def best_of(repeats: int, fn: Callable[[], Any]) -> tuple[float, Any]:
    """Shortest wall time of ``repeats`` calls, and the last call's result."""
    best, out = math.inf, None
    for _ in range(repeats):
        out = None
        gc.collect()
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return best, out


class Task:
    """One thing to time: ``setup()`` (not timed) returns the argument of ``run(arg)``."""

    def __init__(self, key: str, run: Callable[[Any], Any], setup: Callable[[], Any] = lambda: None):
        self.key, self.run, self.setup = key, run, setup


def interleaved(
    tasks: list[Task], repeats: int, clock: Callable[[], float] = time.perf_counter
) -> dict[str, tuple[float, Any]]:
    """Shortest time of each task over ``repeats`` rounds, the tasks taking turns within a
    round, so a burst of noise on the shared machine costs each task one repeat at most
    instead of all of one task's; with each task's last result. ``clock``: wall-clock time
    by default; ``time.thread_time`` counts this thread's CPU time only (the sweeps and
    numba's loops run in the calling thread), not the turns other processes take."""
    best: dict[str, float] = {t.key: math.inf for t in tasks}
    out: dict[str, Any] = {}
    for _ in range(repeats):
        for task in tasks:
            arg = task.setup()
            out.pop(task.key, None)  # free the previous result before timing the next
            gc.collect()
            start = clock()
            result = task.run(arg)
            best[task.key] = min(best[task.key], clock() - start)
            out[task.key] = result
    return {k: (best[k], out[k]) for k in best}


def engine_sweep(model: Any, t: np.ndarray, derivatives: int = 2) -> Any:
    if HAS_DERIVATIVES:
        return model.sweep(t, derivatives=derivatives)
    if derivatives == 2:
        return model.sweep(t)
    raise Unavailable("model.sweep(times, derivatives=...) is not in this build")


def linear_kinds() -> list[str]:
    """The linear solver kinds this build accepts, besides "auto"."""
    kinds = []
    for kind in ("refactor", "small", "dense", "sparse"):
        try:
            examples.four_bar().compile(linear=kind)
        except (ValueError, linkwork.LinkworkError):
            continue
        kinds.append(kind)
    return kinds


def wrap(angle: np.ndarray) -> np.ndarray:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def max_abs(a: np.ndarray) -> float:
    return float(np.max(np.abs(a)))


M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3


def mallopt(param: int, value: int) -> bool:
    """glibc's mallopt; False where there is none."""
    try:
        import ctypes

        return bool(ctypes.CDLL("libc.so.6").mallopt(param, value))
    except (OSError, AttributeError):
        return False


def cold_outputs() -> bool:
    """Fixes glibc's mmap threshold at its default (128 KiB), which turns its adaptive
    threshold off, and returns the free memory to the system: every large output buffer
    is then fresh memory, as in a process's first sweep, instead of depending on what the
    process freed before."""
    ok = mallopt(M_MMAP_THRESHOLD, 128 * 1024) and mallopt(M_TRIM_THRESHOLD, 128 * 1024)
    if ok:
        import ctypes

        ctypes.CDLL("libc.so.6").malloc_trim(0)  # and give back what warmer settings kept
    return ok


def warm_outputs() -> bool:
    """Keeps freed memory mapped, so a sweep's outputs reuse pages already touched."""
    return mallopt(M_MMAP_THRESHOLD, 1 << 30) and mallopt(M_TRIM_THRESHOLD, 1 << 30)


# ---------------------------------------------------------------- 1. the four-bar


def four_bar_errors(s: baselines.Solved) -> dict[str, float | None]:
    """Largest absolute errors of the coupler and rocker angle (rad), rate (rad/s) and
    acceleration (rad/s^2) against the closed form, at the crank angles solved for."""
    cf = closed_form.four_bar(**DIMS, theta2=s["theta2"], omega2=OMEGA, alpha2=0.0)
    e: dict[str, float | None] = {"theta": None, "omega": None, "alpha": None}
    for key in e:
        if key + "3" in s:
            d3, d4 = s[key + "3"] - cf[key + "3"], s[key + "4"] - cf[key + "4"]
            if key == "theta":
                d3, d4 = wrap(d3), wrap(d4)
            e[key] = max(max_abs(d3), max_abs(d4))
    return e


def engine_solved(res: Any, derivatives: int) -> baselines.Solved:
    cols = res.columns
    j3, j4 = cols.index("coupler.theta"), cols.index("rocker.theta")
    s: baselines.Solved = {"theta2": OMEGA * res.times, "theta3": res.q[:, j3], "theta4": res.q[:, j4]}
    if derivatives >= 1:
        s["omega3"], s["omega4"] = res.qd[:, j3], res.qd[:, j4]
    if derivatives >= 2:
        s["alpha3"], s["alpha4"] = res.qdd[:, j3], res.qdd[:, j4]
    return s


def four_bar_section(steps: int, ref_steps: int, repeats: int, notes: list[str]) -> dict[str, Any]:
    mech = examples.four_bar(**DIMS, omega=OMEGA)
    t = np.linspace(0.0, PERIOD, steps)
    rows: list[dict[str, Any]] = []

    def add(name: str, derivatives: int, n: int, secs: float, err: dict, **extra: Any) -> None:
        rows.append({"name": name, "d": derivatives, "steps": n, "us": secs / n * 1e6, "err": err, **extra})

    auto = mech.compile()
    kinds = linear_kinds()
    notes.append(
        f"linear solver kinds in this build: auto (= {auto.linear} for the four-bar), {', '.join(kinds)}"
    )
    derivs = (2, 1, 0) if HAS_DERIVATIVES else (2,)
    if not HAS_DERIVATIVES:
        notes.append("skipped linkwork p and p+v: model.sweep(times, derivatives=...) is not in this build")
    models = {kind: mech.compile(linear=kind) for kind in kinds if kind != auto.linear}
    warm = warm_outputs() and cold_outputs()
    tasks, meta = [], {}

    def cold(_: Any = None) -> None:
        cold_outputs()

    general = mech.compile(solver="general")
    how = "the groups in closed form" if auto.solver == "structured" else f"{auto.linear} LU"
    for d in derivs:
        tasks.append(Task(f"auto{d}", lambda _, d=d: engine_sweep(auto, t, d), cold))
        meta[f"auto{d}"] = (
            f"**linkwork** `sweep` (auto: {how})",
            d,
            {"engine": True, "kind": "auto"},
        )
        # the whole model as one sparse system, as every model was solved before the plan
        tasks.append(Task(f"general{d}", lambda _, d=d: engine_sweep(general, t, d), cold))
        meta[f"general{d}"] = (
            f"linkwork `sweep` (general path: {general.linear} LU)",
            d,
            {"engine": True, "kind": "general"},
        )
    if warm:
        for d in (2, 0) if HAS_DERIVATIVES else (2,):
            tasks.append(Task(f"warm{d}", lambda _, d=d: engine_sweep(auto, t, d), warm_outputs))
            meta[f"warm{d}"] = ("linkwork `sweep` (auto), output memory already mapped", d, {"warm": True})
        notes.append(
            "the rows 'output memory already mapped' and the closed-form row ran with glibc told to keep "
            "freed memory (mallopt), every other row with fresh output memory, as a process's first sweep has"
        )
    for kind, model in models.items():
        tasks.append(Task(kind, lambda _, model=model: engine_sweep(model, t, 2), cold))
        meta[kind] = (f"linkwork `sweep` ({kind} LU)", 2, {"engine": True, "kind": kind})
    version = baselines.pylinkage_version()
    decoders = {}
    if version is None:
        notes.append("pylinkage (with numba): not installed (`pip install pylinkage==1.3.0 numba`)")
    else:
        notes.append(f"{version}: numba JIT compilation excluded (a first call compiles)")
        for kinematics, label in ((True, "step_fast_with_kinematics"), (False, "step_fast")):
            build, run, decode = baselines.pylinkage_four_bar(DIMS, OMEGA, steps, kinematics)
            run(build())  # JIT warm-up

            def setup(build: Callable[[], Any] = build) -> Any:
                cold_outputs()
                return build()

            tasks.append(Task(label, run, setup))
            decoders[label] = decode
            meta[label] = (f"pylinkage-numba `{label}`", 2 if kinematics else 0, {"pylinkage": True})
    # the closed form's dozens of temporaries would each be fresh memory with the cold setting
    tasks.append(
        Task("closed", lambda _: closed_form.four_bar(**DIMS, theta2=OMEGA * t, omega2=OMEGA), warm_outputs)
    )
    timed = interleaved(tasks, repeats)
    cold_outputs()
    closed_secs = timed["closed"][0]
    for key, (secs, r) in timed.items():
        if key == "closed":
            continue
        name, d, extra = meta[key]
        if key in decoders:
            add(name, d, steps, secs, four_bar_errors(decoders[key](r)), **extra)
        else:
            diag = {"residual": float(r.residual.max()), "iterations": float(r.iterations.mean())}
            add(name, d, steps, secs, four_bar_errors(engine_solved(r, d)), **diag, **extra)
    del timed

    try:
        import scipy

        theta2 = OMEGA * t
        cf0 = closed_form.four_bar(**DIMS, theta2=0.0, omega2=OMEGA)
        start = (float(cf0["theta3"]), float(cf0["theta4"]))
        secs, s = best_of(1, lambda: baselines.fsolve_four_bar(DIMS, theta2, start))
        label = f"SciPy {scipy.__version__} `fsolve`: 2 loop equations, warm start, xtol 1e-12"
        add(label, 0, steps, secs, four_bar_errors(s))
    except ImportError:
        notes.append("SciPy: not installed")

    add("closed form, vectorised NumPy (`linkwork.closed_form`)", 2, steps, closed_secs, {}, floor=True)

    ref = ReferenceModel(mech)
    t_ref = np.linspace(0.0, PERIOD, ref_steps)
    secs, out = best_of(1, lambda: ref.sweep(t_ref))
    s = {
        "theta2": OMEGA * t_ref,
        "theta3": out["q"][:, 5],
        "theta4": out["q"][:, 8],
        "omega3": out["qd"][:, 5],
        "omega4": out["qd"][:, 8],
        "alpha3": out["qdd"][:, 5],
        "alpha4": out["qdd"][:, 8],
    }
    add(
        "linkwork.reference (NumPy Newton)",
        2,
        ref_steps,
        secs,
        four_bar_errors(s),
        iterations=float(out["iterations"].mean()),
        reference=True,
    )
    return {"rows": rows}


def four_bar_table(section: dict[str, Any]) -> str:
    rows = section["rows"]
    base = {r["d"]: r["us"] for r in rows if r.get("engine") and r["kind"] == "auto"}
    lines = [
        "| tool | computes | steps | us per step | steps per second | time / linkwork's | "
        "max error theta [rad] | omega [rad/s] | alpha [rad/s^2] | max residual | Newton iterations |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        ref_us = base.get(r["d"], base.get(2))
        err = r["err"]
        cells = [
            r["name"],
            QUANTITIES[r["d"]],
            f"{r['steps']:,}",
            f"{r['us']:.3f}",
            f"{1e6 / r['us']:,.0f}",
            f"{r['us'] / ref_us:.2f}x" if ref_us else "-",
            *(f"{err[k]:.1e}" if err.get(k) is not None else "-" for k in ("theta", "omega", "alpha")),
            f"{r['residual']:.1e}" if "residual" in r else "-",
            f"{r['iterations']:.2f}" if "iterations" in r else "-",
        ]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


# ---------------------------------------------------------------- 1b. the slider-crank

SLIDER = (0.10, 0.35, 0.02)  # crank, rod, offset of examples.slider_crank
SLIDER_PY_STEPS = 2_000  # pylinkage's Python loop (its time per step does not depend on them)


def slider_errors(s: baselines.Solved, t_crank: np.ndarray) -> dict[str, float | None]:
    """Largest absolute errors of the rod angle (rad) and the slider's x (m), and of their
    rates and accelerations, against the closed form at the crank angles solved for."""
    cf = closed_form.slider_crank(*SLIDER, theta2=t_crank, omega2=OMEGA)
    e: dict[str, float | None] = {}
    for key, angle in (
        ("theta3", True),
        ("x", False),
        ("omega3", False),
        ("v", False),
        ("alpha3", False),
        ("a", False),
    ):
        if key in s:
            d = s[key] - cf[key]
            e[key] = max_abs(wrap(d) if angle else d)
        else:
            e[key] = None
    return e


def slider_crank_section(steps: int, repeats: int, notes: list[str]) -> list[dict[str, Any]]:
    """linkwork's slider-crank against pylinkage's, interleaved, with errors."""
    t = np.linspace(0.0, PERIOD, steps)
    model = examples.slider_crank().compile()
    tasks, meta, decoders = [], {}, {}
    for d in (2, 0):
        tasks.append(Task(f"auto{d}", lambda _, d=d: engine_sweep(model, t, d), lambda: cold_outputs()))
        meta[f"auto{d}"] = (
            "**linkwork** `sweep` (auto: the groups in closed form)",
            d,
            steps,
            {"engine": True},
        )
    version = baselines.pylinkage_version()
    if version is not None:
        for mode, d in (("step_fast_with_kinematics", 2), ("step_fast", 0)):
            build, run, decode = baselines.pylinkage_slider_crank(*SLIDER, OMEGA, steps, mode)
            run(build())  # JIT warm-up

            def setup(build: Callable[[], Any] = build) -> Any:
                cold_outputs()
                return build()

            tasks.append(Task(mode, run, setup))
            decoders[mode] = decode
            meta[mode] = (f"pylinkage-numba `{mode}`", d, steps, {"pylinkage": True})
    timed = interleaved(tasks, repeats)
    rows = []
    for key, (secs, r) in timed.items():
        name, d, n, extra = meta[key]
        if key in decoders:
            s = decoders[key](r)
        else:
            cols = r.columns
            j3, jx = cols.index("rod.theta"), cols.index("slider.x")
            s = {"theta3": r.q[:, j3], "x": r.q[:, jx]}
            if d >= 2:
                s.update(omega3=r.qd[:, j3], v=r.qd[:, jx], alpha3=r.qdd[:, j3], a=r.qdd[:, jx])
            s["theta2"] = OMEGA * t
        rows.append(
            {
                "name": name,
                "d": d,
                "steps": n,
                "us": secs / n * 1e6,
                "err": slider_errors(s, s["theta2"]),
                **extra,
            }
        )
    if version is not None:
        # its Python loop: the one pylinkage path that moves the slider (positions only)
        build, run, decode = baselines.pylinkage_slider_crank(*SLIDER, OMEGA, SLIDER_PY_STEPS, "step")
        secs, out = best_of(1, lambda: run(build()))
        s = decode(out)
        rows.append(
            {
                "name": "pylinkage `step` (Python loop)",
                "d": 0,
                "steps": SLIDER_PY_STEPS,
                "us": secs / SLIDER_PY_STEPS * 1e6,
                "err": slider_errors(s, s["theta2"]),
                "pylinkage_python": True,
            }
        )
    else:
        notes.append("pylinkage's slider-crank: not installed")
    return rows


def slider_crank_table(rows: list[dict[str, Any]]) -> str:
    base = {r["d"]: r["us"] for r in rows if r.get("engine")}
    lines = [
        "| tool | computes | steps | us per step | time / linkwork's | max error rod angle [rad] | "
        "slider x [m] | rod omega [rad/s] | slider v [m/s] | rod alpha [rad/s^2] | slider a [m/s^2] |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        err = r["err"]
        cells = [
            r["name"],
            QUANTITIES[r["d"]],
            f"{r['steps']:,}",
            f"{r['us']:.3f}",
            f"{r['us'] / base[r['d']]:.2f}x" if r["d"] in base else "-",
            *(
                f"{err[k]:.1e}" if err.get(k) is not None else "-"
                for k in ("theta3", "x", "omega3", "v", "alpha3", "a")
            ),
        ]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


# ---------------------------------------------------------------- 2. other mechanisms


def relative_errors(pairs: list[tuple[np.ndarray, np.ndarray, bool]]) -> float:
    """Largest |a - b| / max |b| over the pairs (a, b, is_angle)."""
    worst = 0.0
    for a, b, angle in pairs:
        d = wrap(a - b) if angle else a - b
        worst = max(worst, max_abs(d) / max(max_abs(b), 1e-300))
    return worst


def mechanisms_section(steps: int, repeats: int) -> list[dict[str, Any]]:
    rows = []
    t = np.linspace(0.0, PERIOD, steps)
    mechs = {
        "four_bar": examples.four_bar(),
        "slider_crank": examples.slider_crank(),
        "inverted_slider_crank": examples.inverted_slider_crank(),
        "six_bar_watt": examples.six_bar_watt(),
        "six_bar_stephenson": examples.six_bar_stephenson(),
    }
    models = {name: mech.compile() for name, mech in mechs.items()}
    timed = interleaved(
        [Task(name, lambda _, model=model: engine_sweep(model, t, 2)) for name, model in models.items()],
        repeats,
    )
    for name, mech in mechs.items():
        model = models[name]
        secs, r = timed.pop(name)
        cols = r.columns
        if name == "four_bar":
            cf = closed_form.four_bar(**DIMS, theta2=OMEGA * t, omega2=OMEGA)
            j3, j4 = cols.index("coupler.theta"), cols.index("rocker.theta")
            against = "closed form"
            err = [
                relative_errors([(m[:, j3], cf[k + "3"], i == 0), (m[:, j4], cf[k + "4"], i == 0)])
                for i, (m, k) in enumerate(((r.q, "theta"), (r.qd, "omega"), (r.qdd, "alpha")))
            ]
        elif name == "slider_crank":
            cf = closed_form.slider_crank(0.10, 0.35, 0.02, theta2=OMEGA * t, omega2=OMEGA)
            j3, jx = cols.index("rod.theta"), cols.index("slider.x")
            against = "closed form"
            err = [
                relative_errors([(m[:, j3], cf[k3], i == 0), (m[:, jx], cf[kx], False)])
                for i, (m, k3, kx) in enumerate(
                    ((r.q, "theta3", "x"), (r.qd, "omega3", "v"), (r.qdd, "alpha3", "a"))
                )
            ]
        else:
            every = max(1, steps // 1000)
            out = ReferenceModel(mech).sweep(t[::every])
            against = f"linkwork.reference ({len(t[::every])} steps)"
            angle = np.array([c.endswith(".theta") for c in cols])
            err = []
            for m, key in ((r.q, "q"), (r.qd, "qd"), (r.qdd, "qdd")):
                mine, theirs = m[::every], out[key]
                pairs = [(mine[:, j], theirs[:, j], bool(angle[j] and key == "q")) for j in range(len(cols))]
                err.append(relative_errors(pairs))
        rows.append(
            {
                "name": name,
                "coords": model.n_coords,
                "linear": "structured" if model.solver == "structured" else model.linear,
                "us": secs / steps * 1e6,
                "err": err,
                "against": against,
                "iterations": float(r.iterations.mean()),
            }
        )
    return rows


def mechanisms_table(rows: list[dict[str, Any]], steps: int) -> str:
    per = {r["name"]: r["us"] / r["coords"] for r in rows}
    lines = [
        f'One revolution in {steps:,} steps, positions + velocities + accelerations, `linear="auto"`. '
        "Errors: largest error over the sweep divided by the largest value of the quantity "
        "(position, velocity, acceleration), against the closed form where there is one, else "
        "against linkwork.reference on every n-th step.",
        "",
        "| mechanism | coordinates | solver | us per step | us per coordinate | per coordinate / four-bar's "
        "| Newton iterations | rel. error q | qd | qdd | against |",
        "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['name']} | {r['coords']} | {r['linear']} | {r['us']:.3f} | {per[r['name']]:.3f} "
            f"| {per[r['name']] / per['four_bar']:.2f} | {r['iterations']:.2f} | "
            + " | ".join(f"{e:.1e}" for e in r["err"])
            + f" | {r['against']} |"
        )
    return "\n".join(lines)


# ---------------------------------------------------------------- 3. scaling


def chain_offset(gain: float = -0.97) -> float:
    """The tie angle c that makes the chain settle where a loop's gain d theta4 / d theta2
    is ``gain``: the fixed point theta* = theta4(theta*) + c of the loop-to-loop map.

    With the tie 0, the chain settles where the gain is 0.8: the motion fades as 0.8^k and
    beyond loop ~3,000 the rates underflow into subnormal numbers, which x86 processes
    about a hundred times slower. At -0.97 every loop keeps moving and nothing underflows."""

    def g(theta: float) -> float:
        return float(closed_form.four_bar(**DIMS, theta2=theta, omega2=1.0)["omega4"]) - gain

    # the crossing nearest theta = 0 on a grid, then bisection
    grid = np.linspace(-math.pi, math.pi, 20_001)
    values = closed_form.four_bar(**DIMS, theta2=grid, omega2=1.0)["omega4"] - gain
    crossings = np.flatnonzero(np.sign(values[:-1]) != np.sign(values[1:]))
    i = int(crossings[np.argmin(np.abs(grid[crossings]))])
    lo, hi = float(grid[i]), float(grid[i + 1])
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if (g(mid) > 0) == (g(lo) > 0) else (lo, mid)
    star = 0.5 * (lo + hi)
    theta4 = float(closed_form.four_bar(**DIMS, theta2=star, omega2=1.0)["theta4"])
    return star - math.remainder(theta4, 2.0 * math.pi)


CHAIN_OFFSET = chain_offset()


def chain_closed_form(loops: int, times: np.ndarray) -> np.ndarray:
    """(3, n_steps, loops, 3): theta, omega, alpha of (crank, coupler, rocker) of each loop."""
    n = len(times)
    out = np.empty((3, n, loops, 3))
    th2, w2, a2 = OMEGA * times, np.full(n, OMEGA), np.zeros(n)
    for k in range(loops):
        cf = closed_form.four_bar(**DIMS, theta2=th2, omega2=w2, alpha2=a2)
        for i, (th, w, a) in enumerate(((th2, w2, a2), (cf["theta3"], cf["omega3"], cf["alpha3"]))):
            out[0, :, k, i], out[1, :, k, i], out[2, :, k, i] = th, w, a
        out[0, :, k, 2], out[1, :, k, 2], out[2, :, k, 2] = cf["theta4"], cf["omega4"], cf["alpha4"]
        th2, w2, a2 = cf["theta4"] + CHAIN_OFFSET, cf["omega4"], cf["alpha4"]
    return out


def chain_steps(loops: int, budget: float) -> int:
    return int(min(100_000, max(100, budget / loops)))


def _proc_status(key: str) -> int:
    """A /proc/self/status figure in bytes (VmRSS, VmHWM)."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    raise KeyError(key)


def probe_memory(loops: int, steps: int) -> dict[str, Any]:
    """In a fresh process: build the chain, then the peak RSS growth of compile + sweep."""
    mech = examples.chain(loops, **DIMS, omega=OMEGA, offset=CHAIN_OFFSET)
    gc.collect()
    base = _proc_status("VmRSS")
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")  # resets VmHWM to the current RSS
        reset = True
    except OSError:
        reset = False
    model = mech.compile()
    r = engine_sweep(model, np.arange(steps) * CHAIN_H, 2)
    peak = _proc_status("VmHWM")
    outputs = sum(a.nbytes for a in (r.times, r.q, r.qd, r.qdd, r.iterations, r.residual, r.pivot_ratio))
    return {"peak": peak - base, "outputs": outputs, "reset": reset, "nnz": model._core.nnz}


def scaling_section(loops_list: list[int], budget: float, repeats: int, mem_steps: int) -> dict[str, Any]:
    rows = []
    for loops in loops_list:
        steps = chain_steps(loops, budget)
        t = np.arange(steps) * CHAIN_H
        mech = examples.chain(loops, **DIMS, omega=OMEGA, offset=CHAIN_OFFSET)
        start = time.perf_counter()
        model = mech.compile()
        compile_s = time.perf_counter() - start
        runs = repeats if loops < 10_000 else max(1, repeats - 1)
        secs, r = best_of(runs, lambda model=model, t=t: engine_sweep(model, t, 2))
        cf = chain_closed_form(loops, t)
        got = [m.reshape(steps, loops, 3, 3)[:, :, :, 2] for m in (r.q, r.qd, r.qdd)]
        err = [max_abs(wrap(got[0] - cf[0])), max_abs(got[1] - cf[1]), max_abs(got[2] - cf[2])]
        iterations = float(r.iterations.mean())
        pivot = float(r.pivot_ratio.min())
        last_omega = max_abs(got[1][:, -1, 2])
        del r, got, cf
        probe = subprocess.run(
            [sys.executable, __file__, "--probe-memory", str(loops), str(mem_steps)],
            capture_output=True,
            text=True,
            check=True,
        )
        mem = json.loads(probe.stdout)
        rows.append(
            {
                "loops": loops,
                "bodies": 3 * loops,
                "coords": model.n_coords,
                # the solver the steps took: the groups in order, or the general path's LU
                "linear": "structured" if model.solver == "structured" else model.linear,
                "nnz": mem["nnz"],
                "steps": steps,
                "us": secs / steps * 1e6,
                "compile_s": compile_s,
                "iterations": iterations,
                "pivot": pivot,
                "last_omega": last_omega,
                "err": err,
                "mem": mem,
            }
        )
    k = np.array([r["loops"] for r in rows], dtype=float)
    us = np.array([r["us"] for r in rows])
    fits = {"all": float(np.polyfit(np.log(k), np.log(us), 1)[0])}
    big = k >= 10
    if big.sum() >= 2:
        fits["K >= 10"] = float(np.polyfit(np.log(k[big]), np.log(us[big]), 1)[0])
    mem_peak = np.array([r["mem"]["peak"] for r in rows], dtype=float)
    mem_ok = (k >= 100) & (mem_peak > 0)
    mem_fit = (
        float(np.polyfit(np.log(k[mem_ok]), np.log(mem_peak[mem_ok]), 1)[0]) if mem_ok.sum() >= 2 else None
    )
    return {"rows": rows, "fits": fits, "mem_fit": mem_fit, "mem_steps": mem_steps}


def scaling_table(section: dict[str, Any]) -> str:
    rows = section["rows"]
    reset = all(r["mem"]["reset"] for r in rows)
    lines = [
        "| loops K | bodies | coordinates | solver | nnz(Phi_q) | steps | us per step | us per body per step "
        "| Newton iterations | min pivot ratio | compile [s] | last rocker's max omega [rad/s] "
        "| max error theta [rad] | omega [rad/s] | alpha [rad/s^2] "
        f"| peak RSS growth, {section['mem_steps']} steps [MB] | of which outputs [MB] "
        "| rest per body [kB] |",
        "|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        m = r["mem"]
        rest = f"{(m['peak'] - m['outputs']) / r['bodies'] / 1e3:.2f}" if r["loops"] >= 100 else "-"
        lines.append(
            f"| {r['loops']:,} | {r['bodies']:,} | {r['coords']:,} | {r['linear']} | {r['nnz']:,} "
            f"| {r['steps']:,} | {r['us']:.2f} | {r['us'] / r['bodies']:.3f} | "
            f"{r['iterations']:.2f} | {r['pivot']:.2f} | {r['compile_s']:.2f} | {r['last_omega']:.1e} | "
            + " | ".join(f"{e:.1e}" for e in r["err"])
            + f" | {m['peak'] / 1e6:.1f} | {m['outputs'] / 1e6:.1f} | {rest} |"
        )
    fits = "; ".join(f"{span}: **{value:.3f}**" for span, value in section["fits"].items())
    lines += [
        "",
        f"Fitted exponent of time per step against K (least squares on log-log), {fits}.",
    ]
    if section["mem_fit"] is not None:
        lines.append(
            f"Fitted exponent of the peak memory growth against K (K >= 100; below that it is "
            f"lost in the allocator's granularity): **{section['mem_fit']:.3f}**."
        )
    lines.append(
        "Memory: the growth of the process's peak resident set (`VmHWM`, "
        + ("reset through `/proc/self/clear_refs` " if reset else "not reset: it includes building ")
        + "after building the mechanism in Python) over `compile()` and a sweep, measured in a fresh "
        "process per K; it includes the JSON hand-over and the transient description, the compiled "
        "model, the workspace and the outputs (q, qd, qdd and diagnostics, whose exact size is given)."
    )
    return "\n".join(lines)


# ---------------------------------------------------------------- 4. batches


def batch_section(designs: int, steps: int, repeats: int, notes: list[str]) -> dict[str, Any]:
    t = np.linspace(0.0, PERIOD, steps)
    models = [
        examples.four_bar(**{**DIMS, "crank": c}, omega=OMEGA).compile()
        for c in np.linspace(0.15, 0.22, designs)
    ]
    rows = []
    pool = ThreadPoolExecutor(2)
    # the results are dropped at once (each batch's are half a gigabyte)
    tasks = [
        Task("loop", lambda _: len([engine_sweep(m, t, 2) for m in models]), cold_outputs),
        Task("pool", lambda _: len(list(pool.map(lambda m: engine_sweep(m, t, 2), models))), cold_outputs),
    ]
    warm = HAS_BATCH and warm_outputs() and cold_outputs()
    if HAS_BATCH:
        for threads in (1, 2):
            run = lambda _, th=threads: len(linkwork.sweep_batch(models, t, threads=th))  # noqa: E731
            tasks.append(Task(f"batch{threads}", run, cold_outputs))
            if warm:
                tasks.append(Task(f"warm{threads}", run, warm_outputs))
    timed = {key: secs for key, (secs, _) in interleaved(tasks, repeats).items()}
    cold_outputs()
    pool.shutdown()
    rows.append(("Python loop over `model.sweep`", 1, timed["loop"]))
    rows.append(("`ThreadPoolExecutor` over `model.sweep` (GIL released in the sweep)", 2, timed["pool"]))
    if HAS_BATCH:
        for threads in (1, 2):
            rows.append(("`linkwork.sweep_batch`", threads, timed[f"batch{threads}"]))
        if warm:
            for threads in (1, 2):
                rows.append((WARM_BATCH, threads, timed[f"warm{threads}"]))
    else:
        notes.append("linkwork.sweep_batch: not in this build; the batch rows use a ThreadPoolExecutor")
    return {"rows": rows, "designs": designs, "steps": steps}


WARM_BATCH = "`linkwork.sweep_batch`, output memory already mapped"


def one_thread(section: dict[str, Any], name: str) -> float:
    """The serial time a row is compared with: for the rows with fresh output memory the
    faster of the Python loop and sweep_batch on 1 thread (the same work, so a burst of
    noise on one of them does not inflate the speed-up); else the row's own 1-thread run."""
    by = {(n, th): secs for n, th, secs in section["rows"]}
    if name == WARM_BATCH:
        return by[(WARM_BATCH, 1)]
    return min(by.get(("`linkwork.sweep_batch`", 1), math.inf), by[("Python loop over `model.sweep`", 1)])


def batch_speedup(section: dict[str, Any]) -> tuple[str, float]:
    """(which, speed-up from 1 to 2 threads) of sweep_batch, else of the thread pool."""
    by = {(name, th): s for name, th, s in section["rows"]}
    for name in (
        "`linkwork.sweep_batch`",
        "`ThreadPoolExecutor` over `model.sweep` (GIL released in the sweep)",
    ):
        if (name, 2) in by:
            return name, one_thread(section, name) / by[(name, 2)]
    raise KeyError("no batch rows")


def batch_table(section: dict[str, Any]) -> str:
    n = section["designs"] * section["steps"]
    lines = [
        f"{section['designs']} four-bar designs (crank 0.15 .. 0.22 m, the rest as above), one revolution "
        f"in {section['steps']:,} steps each, positions + velocities + accelerations; "
        f"{os.cpu_count()} cores on this machine.",
        "",
        "| how | threads | wall time [s] | us per design-step | speed-up over 1 thread (see below) |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, threads, secs in section["rows"]:
        lines.append(
            f"| {name} | {threads} | {secs:.3f} | {secs / n * 1e6:.3f} "
            f"| {one_thread(section, name) / secs:.2f}x |"
        )
    which, s2 = batch_speedup(section)
    serial = min(max(2.0 / s2 - 1.0, 0.0), 1.0)
    proj = ", ".join(f"{p} cores {1.0 / (serial + (1.0 - serial) / p):.1f}x" for p in (4, 8, 16, 32))
    lines += [
        "",
        "The 1-thread time of the rows with fresh output memory is the faster of the Python loop and "
        "`sweep_batch` on 1 thread (the same work). "
        f"Speed-up from 1 to 2 threads ({which}): **{s2:.2f}x**. How it would grow with cores "
        f"(a projection, not measured: Amdahl's law with the serial fraction {serial:.3f} that this "
        f"speed-up implies): {proj}. A design-step writes about 240 bytes of output (9 coordinates "
        "in 3 arrays, and diagnostics), a few hundred MB/s per core, so memory bandwidth is far from "
        "a limit on more cores.",
    ]
    return "\n".join(lines)


# ---------------------------------------------------------------- 5. speed against error


def tradeoff_section(repeats: int, notes: list[str]) -> dict[str, list[tuple[str, float, float]]]:
    mech = examples.four_bar(**DIMS, omega=OMEGA)
    curves: dict[str, list[tuple[str, float, float]]] = {}

    def engine_point(model: Any, steps: int) -> tuple[float, float]:
        t = np.linspace(0.0, PERIOD, steps)
        secs, r = best_of(repeats if steps <= 300_000 else 1, lambda: engine_sweep(model, t, 2))
        err = four_bar_errors(engine_solved(r, 2))["alpha"]
        return secs / steps * 1e6, float(err)

    for steps in (1_000, 100_000):
        curve = []
        for tol in (1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-13):
            try:
                model = mech.compile(tol_residual=tol, tol_step=tol)
                us, err = engine_point(model, steps)
            except linkwork.LinkworkError as e:
                notes.append(
                    f"speed-vs-error: tolerance {tol:g} at {steps:,} steps failed ({type(e).__name__})"
                )
                continue
            curve.append((f"tol {tol:.0e}", us, err))
        curves[f"linkwork, {steps:,} steps, Newton tolerance swept"] = curve
    model = mech.compile()
    curves["linkwork, tolerance 1e-12, steps per revolution swept"] = [
        (f"{n:,} steps", *engine_point(model, n)) for n in (1_000, 3_000, 10_000, 30_000, 100_000, 1_000_000)
    ]
    if baselines.pylinkage_version() is not None:
        curve = []
        for n in (1_000, 10_000, 100_000, 1_000_000):
            build, run, decode = baselines.pylinkage_four_bar(DIMS, OMEGA, n, True)
            run(build())
            best, out = math.inf, None
            for _ in range(repeats if n <= 300_000 else 1):
                linkage = build()
                secs, out = best_of(1, lambda linkage=linkage, run=run: run(linkage))
                best = min(best, secs)
            curve.append((f"{n:,} steps", best / n * 1e6, float(four_bar_errors(decode(out))["alpha"])))
        curves["pylinkage-numba step_fast_with_kinematics, steps swept"] = curve
    curve = []
    for tol in (1e-6, 1e-9, 1e-12):
        ref = ReferenceModel(mech, tol=tol)
        t = np.linspace(0.0, PERIOD, 500)
        secs, out = best_of(1, lambda ref=ref, t=t: ref.sweep(t))
        s = {"theta2": OMEGA * t, "alpha3": out["qdd"][:, 5], "alpha4": out["qdd"][:, 8]}
        s.update(theta3=out["q"][:, 5], theta4=out["q"][:, 8])
        curve.append((f"tol {tol:.0e}", secs / len(t) * 1e6, float(four_bar_errors(s)["alpha"])))
    curves["linkwork.reference, 500 steps, tolerance swept"] = curve
    return curves


def tradeoff_table(curves: dict[str, list[tuple[str, float, float]]]) -> str:
    lines = ["| curve | point | us per step | max error alpha [rad/s^2] |", "|---|---|---:|---:|"]
    for name, points in curves.items():
        for label, us, err in points:
            lines.append(f"| {name} | {label} | {us:.3f} | {err:.1e} |")
    return "\n".join(lines)


def tradeoff_plot(curves: dict[str, list[tuple[str, float, float]]], path: Path, stamp: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5.8), dpi=110)
    for (name, points), marker in zip(curves.items(), "osD^v"):
        xs = [p[1] for p in points]
        ys = [max(p[2], 1e-16) for p in points]
        (line,) = ax.plot(xs, ys, marker=marker, label=name)
        for label, x, y in (points[0], points[-1]) if len(points) > 1 else points:
            ax.annotate(
                label,
                (x, max(y, 1e-16)),
                textcoords="offset points",
                xytext=(5, -3),
                fontsize=7,
                color=line.get_color(),
            )
    ax.axhline(1e-10, color="grey", linestyle="--", linewidth=1)
    ax.annotate(
        "target: alpha error <= 1e-10",
        (0.01, 1e-10),
        xycoords=("axes fraction", "data"),
        xytext=(0, 3),
        textcoords="offset points",
        fontsize=7,
        color="grey",
    )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time per step [us] (positions + velocities + accelerations)")
    ax.set_ylabel("max error of the coupler and rocker alpha [rad/s^2]")
    ax.set_title(f"Textbook four-bar, one revolution: speed against error ({stamp})", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


# ---------------------------------------------------------------- 6. targets


def targets_table(
    fb: dict[str, Any],
    mechs: list[dict[str, Any]],
    scaling: dict[str, Any],
    batch: dict,
    slider: list[dict[str, Any]] | None = None,
) -> str:
    rows = fb["rows"]

    def find(pred: Callable[[dict[str, Any]], bool]) -> dict[str, Any] | None:
        return next((r for r in rows if pred(r)), None)

    lw2 = find(lambda r: r.get("engine") and r["kind"] == "auto" and r["d"] == 2)
    lw0 = find(lambda r: r.get("engine") and r["kind"] == "auto" and r["d"] == 0)
    pl2 = find(lambda r: r.get("pylinkage") and r["d"] == 2)
    pl0 = find(lambda r: r.get("pylinkage") and r["d"] == 0)
    ref = find(lambda r: r.get("reference"))
    out = ["| target | measured | verdict |", "|---|---|---|"]

    def line(target: str, measured: str, ok: bool | None, miss: str = "") -> None:
        verdict = "not measured" if ok is None else ("**met**" if ok else f"**missed** {miss}".rstrip())
        out.append(f"| {target} | {measured} | {verdict} |")

    def ratio_line(target: str, slow: dict | None, fast: dict | None, need: float, what: str) -> None:
        if slow is None or fast is None:
            line(target, f"{what}: not measured (not installed or not in this build)", None)
            return
        ratio = slow["us"] / fast["us"]
        line(
            target,
            f"{fast['us']:.3f} vs {slow['us']:.3f} us per step: {ratio:.2f}x",
            ratio >= need,
            f"by {need / ratio:.2f}x (needs {need / ratio:.2f} times less time per step)",
        )

    ratio_line("four-bar p+v+a >= 2x faster than pylinkage-numba with kinematics", pl2, lw2, 2.0, "pylinkage")
    if lw2:
        for key, limit, unit in (
            ("theta", 1e-12, "rad"),
            ("omega", 1e-11, "rad/s"),
            ("alpha", 1e-10, "rad/s^2"),
        ):
            e = lw2["err"][key]
            line(f"error {key} <= {limit:.0e} {unit}", f"{e:.1e} {unit}", e <= limit, f"by {e / limit:.1f}x")
        line(
            "residual <= 1e-12",
            f"{lw2['residual']:.1e}",
            lw2["residual"] <= 1e-12,
            f"by {lw2['residual'] / 1e-12:.1f}x",
        )
    # positions only: 1x, not 2x: linkwork's step keeps its per-step branch guard, which pylinkage's
    # step has no counterpart of; instruction counts showed 2x out of reach with the guard
    ratio_line("positions only >= 1x as fast as pylinkage-numba `step_fast`", pl0, lw0, 1.0, "positions only")
    sc = slider or []
    sc2 = next((r for r in sc if r.get("engine") and r["d"] == 2), None)
    sc0 = next((r for r in sc if r.get("engine") and r["d"] == 0), None)
    for d, mine, label, need in ((2, sc2, "p+v+a", 2.0), (0, sc0, "positions only", 1.0)):
        theirs = next((r for r in sc if r.get("pylinkage") and r["d"] == d), None)
        if theirs is not None and mine is not None:
            wrong = theirs["err"]["x"]
            ratio = theirs["us"] / mine["us"]
            line(
                f"slider-crank {label} >= {need:g}x "
                f"{'faster than' if need > 1 else 'as fast as'} pylinkage-numba "
                f"`{'step_fast_with_kinematics' if d == 2 else 'step_fast'}`",
                f"{mine['us']:.3f} vs {theirs['us']:.3f} us per step: {ratio:.2f}x; its numba path leaves "
                f"the slider where it was drawn (x error {wrong:.2f} m)",
                ratio >= need,
                f"by {need / ratio:.2f}x",
            )
    py = next((r for r in sc if r.get("pylinkage_python")), None)
    if py is not None and sc0 is not None:
        ratio = py["us"] / sc0["us"]
        line(
            "slider-crank positions only >= 2x faster than pylinkage's correct path (`step`, Python)",
            f"{sc0['us']:.3f} vs {py['us']:.3f} us per step: {ratio:.0f}x",
            ratio >= 2.0,
        )
    per = {r["name"]: r["us"] / r["coords"] for r in mechs}
    for name in ("slider_crank", "six_bar_stephenson"):
        ratio = per[name] / per["four_bar"]
        line(
            f"{name} within 2x of the four-bar per coordinate",
            f"{ratio:.2f}x the four-bar's time per coordinate",
            ratio <= 2.0,
            f"by {ratio / 2.0:.2f}x",
        )
    ratio_line(">= 500x faster than linkwork.reference", ref, lw2, 500.0, "reference")
    fit = scaling["fits"]["all"]
    line(
        "chain of K loops: time per step linear in K (exponent <= 1.1), K = 1 .. 10,000",
        "fitted exponent " + ", ".join(f"{v:.3f} ({k})" for k, v in scaling["fits"].items()),
        fit <= 1.1,
        f"(exponent {fit:.3f})",
    )
    k1000 = next((r for r in scaling["rows"] if r["loops"] == 1000), None)
    if k1000:
        per_body = k1000["us"] / k1000["bodies"]
        line(
            "K = 1,000: <= 0.3 us per body per step",
            f"{per_body:.3f} us",
            per_body <= 0.3,
            f"by {per_body / 0.3:.2f}x",
        )
    if scaling["mem_fit"] is not None:
        line(
            "memory linear in K (exponent <= 1.1)",
            f"fitted exponent {scaling['mem_fit']:.3f}",
            scaling["mem_fit"] <= 1.1,
        )
    which, s2 = batch_speedup(batch)
    by = {(name, th): secs for name, th, secs in batch["rows"]}
    warm = ""
    if (WARM_BATCH, 2) in by:
        ratio = one_thread(batch, WARM_BATCH) / by[(WARM_BATCH, 2)]
        warm = f"; {ratio:.2f}x with the output memory already mapped"
    line(
        "batch: speed-up from 1 to 2 threads >= 1.8x",
        f"{s2:.2f}x ({which}){warm}",
        s2 >= 1.8,
        f"by {1.8 / s2:.2f}x",
    )
    line(
        "no heap allocation inside the per-step loop",
        "not timed here: `cargo test -p linkwork --test allocations` counts them",
        None,
    )
    return "\n".join(out)


# ---------------------------------------------------------------- the short report


def errors_text(err: dict[str, Any], keys: tuple[tuple[str, str, str], ...]) -> str:
    shown = [f"{label} {err[key]:.1e} {unit}" for key, label, unit in keys if err.get(key) is not None]
    return ", ".join(shown) or "-"


FOUR_BAR_ERRORS = (("theta", "theta", "rad"), ("omega", "omega", "rad/s"), ("alpha", "alpha", "rad/s^2"))
SLIDER_ERRORS = (("x", "slider x", "m"), ("v", "v", "m/s"), ("a", "a", "m/s^2"))


def peers_table(m: dict[str, Any]) -> str:
    """linkwork's time and error against each peer's, on the same mechanism and quantities."""
    fb, sc = m["fb"]["rows"], m["slider"]

    def first(rows: list[dict[str, Any]], **want: Any) -> dict[str, Any] | None:
        return next((r for r in rows if all(r.get(k) == v for k, v in want.items())), None)

    lw = {d: first(fb, engine=True, kind="auto", d=d) for d in (0, 2)}
    lw_sc = {d: first(sc, engine=True, d=d) for d in (0, 2)}
    fsolve = next((r for r in fb if r["name"].startswith("SciPy")), None)
    lines = [
        "| peer | mechanism | computes | linkwork [us/step] | peer [us/step] | peer's time / linkwork's "
        "| linkwork's largest error | peer's largest error |",
        "|---|---|---|---:|---:|---:|---|---|",
    ]

    def add(
        label: str, mech: str, mine: dict | None, theirs: dict | None, keys: tuple, truth: bool = False
    ) -> None:
        if mine is None or theirs is None:
            lines.append(f"| {label} | {mech} | | | | not measured (not installed) | | |")
            return
        d = QUANTITIES[theirs["d"]]
        theirs_err = "- (the errors are measured against it)" if truth else errors_text(theirs["err"], keys)
        lines.append(
            f"| {label} | {mech} | {d} | {mine['us']:.3f} | {theirs['us']:.3f} "
            f"| {theirs['us'] / mine['us']:.2f}x "
            f"| {errors_text(mine['err'], keys)} | {theirs_err} |"
        )

    pl = "pylinkage-numba"
    add(
        f"{pl} `step_fast_with_kinematics`",
        "four-bar",
        lw[2],
        first(fb, pylinkage=True, d=2),
        FOUR_BAR_ERRORS,
    )
    add(f"{pl} `step_fast`", "four-bar", lw[0], first(fb, pylinkage=True, d=0), FOUR_BAR_ERRORS)
    add(
        f"{pl} `step_fast_with_kinematics`",
        "slider-crank",
        lw_sc[2],
        first(sc, pylinkage=True, d=2),
        SLIDER_ERRORS,
    )
    add(f"{pl} `step_fast`", "slider-crank", lw_sc[0], first(sc, pylinkage=True, d=0), SLIDER_ERRORS)
    add(
        "pylinkage `step` (Python)", "slider-crank", lw_sc[0], first(sc, pylinkage_python=True), SLIDER_ERRORS
    )
    add("SciPy `fsolve`, warm start", "four-bar", lw[0], fsolve, FOUR_BAR_ERRORS)
    add("linkwork.reference (NumPy Newton)", "four-bar", lw[2], first(fb, reference=True), FOUR_BAR_ERRORS)
    add(
        "closed form, vectorised NumPy", "four-bar", lw[2], first(fb, floor=True), FOUR_BAR_ERRORS, truth=True
    )
    return "\n".join(lines)


def scale_table(m: dict[str, Any]) -> str:
    """The chain, the other mechanisms and the batch in one figure each."""
    scaling, batch = m["scaling"], m["batch"]
    fits = ", ".join(f"{v:.3f} ({k})" for k, v in scaling["fits"].items())
    ks = [r["loops"] for r in scaling["rows"]]
    lines = ["| measure | figure |", "|---|---|"]
    lines.append(
        f"| chain of K four-bar loops, K = {min(ks):,} .. {max(ks):,}: "
        f"exponent of time per step in K | {fits} |"
    )
    for r in scaling["rows"]:
        if r["loops"] == 1000:
            lines.append(f"| chain, K = 1,000: time per body and step | {r['us'] / r['bodies']:.3f} us |")
    if scaling["mem_fit"] is not None:
        lines.append(f"| chain: exponent of peak memory in K | {scaling['mem_fit']:.3f} |")
    per = {r["name"]: r["us"] / r["coords"] for r in m["mechs"]}
    others = ", ".join(f"{name} {v / per['four_bar']:.2f}" for name, v in per.items() if name != "four_bar")
    lines.append(f"| other mechanisms: time per coordinate / the four-bar's | {others} |")
    which, s2 = batch_speedup(batch)
    lines.append(
        f"| {batch['designs']} designs at once: speed-up from 1 to 2 threads ({which}) | {s2:.2f}x |"
    )
    return "\n".join(lines)


def readme_paragraph(m: dict[str, Any]) -> str:
    """The README's speed sentence, every figure from the run."""
    fb = m["fb"]["rows"]
    lw = {d: next(r for r in fb if r.get("engine") and r["kind"] == "auto" and r["d"] == d) for d in (0, 2)}
    pl = {d: next((r for r in fb if r.get("pylinkage") and r["d"] == d), None) for d in (0, 2)}
    ref = next(r for r in fb if r.get("reference"))
    load = re.search(r"(\d+) cores \(1-minute load average ([\d.]+) at the start, ([\d.]+)", m["where"])
    where = f"{load[1]} cores, load average {load[2]} to {load[3]}" if load else "a shared machine"
    where += "".join(f"; {note}" for note in m["args"].get("note") or [])
    text = (
        f"In the latest run ({m['stamp'][:10]}, {where}), on the textbook "
        f"four-bar linkwork's `sweep` takes {lw[2]['us']:.2f} us per step from Python with velocities and "
        f"accelerations and {lw[0]['us']:.2f} us with positions only, {ref['us'] / lw[2]['us']:,.0f} times "
        f"as fast as the NumPy reference"
    )
    if pl[2] is not None and pl[0] is not None:
        text += (
            f" and {pl[2]['us'] / lw[2]['us']:.2f} and {pl[0]['us'] / lw[0]['us']:.2f} times as fast as "
            "pylinkage's closed-form dyads with numba (which report no diagnostics)"
        )
    err = lw[2]["err"]
    k1000 = next((r for r in m["scaling"]["rows"] if r["loops"] == 1000), None)
    text += f", at errors of {err['theta']:.1e} rad in angles and {err['alpha']:.1e} rad/s^2 in accelerations"
    if k1000 is not None:
        text += f"; a chain of 1,000 loops costs {k1000['us'] / k1000['bodies']:.3f} us per body and step"
    _, s2 = batch_speedup(m["batch"])
    return text + f", and a batch of designs runs {s2:.2f} times as fast on 2 threads as on 1."


def short_report(m: dict[str, Any], link: str) -> str:
    """The verdicts for docs/performance.md: every figure from the run, the full log linked."""
    targets = targets_table(m["fb"], m["mechs"], m["scaling"], m["batch"], m["slider"])
    verdicts = [line.rsplit("|", 2)[-2].strip() for line in targets.splitlines()[2:]]
    met = sum(v == "**met**" for v in verdicts)
    missed = sum(v.startswith("**missed**") for v in verdicts)
    return "\n".join(
        [
            f"Measured {m['stamp']} on {m['where']}"
            + "".join(f"; {note}" for note in m["args"].get("note") or [])
            + f". The full log, with every table, the speed against error plot and the notes: "
            f"[{m['stamp'][:10]}]({link}).",
            "",
            "### Against the peers",
            "",
            "Above 1x linkwork is faster by that factor, below 1x the peer is.",
            "",
            peers_table(m),
            "",
            "### Scale",
            "",
            scale_table(m),
            "",
            "### Targets of the performance issue",
            "",
            f"{met} met, {missed} missed, {len(verdicts) - met - missed} not measured by this command.",
            "",
            targets,
        ]
    )


# ---------------------------------------------------------------- the report


def plain(value: Any) -> Any:
    """A NumPy scalar or array as JSON takes it (anything else as its text)."""
    return value.tolist() if hasattr(value, "tolist") else str(value)


def revision() -> str:
    try:
        rev = subprocess.run(
            ["git", "-C", str(ROOT), "describe", "--always", "--dirty"], capture_output=True, text=True
        ).stdout.strip()
    except OSError:
        rev = ""
    return rev or "?"


def machine(load: tuple[float, float], rev: str) -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    import scipy

    return (
        f"{cpu}, {os.cpu_count()} cores (1-minute load average {load[0]:.2f} at the start, "
        f"{load[1]:.2f} at the end); CPython {platform.python_version()}, numpy {np.__version__}, "
        f"scipy {scipy.__version__}, {baselines.pylinkage_version() or 'pylinkage not installed'}; "
        f"linkwork {getattr(linkwork, '__version__', '?')} at `{rev}`"
    )


def full_report(m: dict[str, Any], plot: str) -> str:
    """The run's whole log: every table, from the measured figures ``m``."""
    args = m["args"]
    fb, slider, mechs, scaling, batch = m["fb"], m["slider"], m["mechs"], m["scaling"], m["batch"]
    return "\n".join(
        [
            f"Measured {m['stamp']} with `python benches/compare.py --write` on {m['where']}.",
            "",
            "### Targets of the performance issue",
            "",
            targets_table(fb, mechs, scaling, batch, slider),
            "",
            "### The textbook four-bar, one revolution",
            "",
            para(FOUR_BAR_TEXT.format(steps=args["steps"], ref_steps=args["reference_steps"])),
            "",
            four_bar_table(fb),
            "",
            "### The slider-crank against pylinkage",
            "",
            para(SLIDER_TEXT.format(steps=args["steps"], py_steps=SLIDER_PY_STEPS)),
            "",
            slider_crank_table(slider),
            "",
            "### Other mechanisms: time per coordinate",
            "",
            mechanisms_table(mechs, args["steps"]),
            "",
            "### Scaling: a chain of K four-bar loops (`examples.chain(K)`, 3K bodies)",
            "",
            para(CHAIN_TEXT.format(budget=args["chain_budget"], offset=CHAIN_OFFSET)),
            "",
            scaling_table(scaling),
            "",
            "### Many designs at once",
            "",
            batch_table(batch),
            "",
            "### Speed against error",
            "",
            f"![speed against error]({plot})",
            "",
            para(TRADEOFF_TEXT),
            "",
            tradeoff_table(m["curves"]),
            "",
            "Notes: " + "; ".join(m["notes"]) + ".",
        ]
    )


def measure(args: argparse.Namespace) -> dict[str, Any]:
    """Run every section; the figures as plain data (what --save keeps, --load reads)."""
    stamp = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    load_start = os.getloadavg()[0]
    rev = revision()  # the code measured, before anything can change the work tree
    notes: list[str] = list(args.note or [])
    if not cold_outputs():
        notes.append("not glibc: the allocator's adaptive thresholds were left as they are")
    clock = time.perf_counter()

    def say(what: str) -> None:
        print(f"[{time.perf_counter() - clock:6.1f} s] {what}", file=sys.stderr)

    say("four-bar")
    m: dict[str, Any] = {"fb": four_bar_section(args.steps, args.reference_steps, args.repeats, notes)}
    say("slider-crank")
    m["slider"] = slider_crank_section(args.steps, args.repeats, notes)
    say("mechanisms")
    m["mechs"] = mechanisms_section(args.steps, args.repeats)
    say("scaling")
    m["scaling"] = scaling_section([int(k) for k in args.loops.split(",")], args.chain_budget, 3, 100)
    say("batch")
    m["batch"] = batch_section(24, args.steps, 4, notes)
    say("speed against error")
    m["curves"] = tradeoff_section(2 if args.quick else 3, notes)
    say("done")
    where = machine((load_start, os.getloadavg()[0]), rev)
    m.update(stamp=stamp, where=where, args=vars(args), notes=notes)
    # through JSON, so that a run read back with --load renders exactly as this one
    return json.loads(json.dumps(m, default=plain))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=100_000, help="four-bar steps per revolution")
    parser.add_argument("--reference-steps", type=int, default=2_000, help="reference steps (default 2000)")
    parser.add_argument("--repeats", type=int, default=5, help="best of this many runs (default 5)")
    parser.add_argument("--loops", type=str, default="1,10,100,1000,10000", help="chain lengths K")
    parser.add_argument("--chain-budget", type=float, default=1e6, help="chain steps x K per row")
    parser.add_argument("--quick", action="store_true", help="fewer steps and repeats (a smoke test)")
    parser.add_argument(
        "--write",
        action="store_true",
        help="add the run to benches/results/ (log, figures as JSON, plot) and rewrite docs/performance.md",
    )
    parser.add_argument("--note", action="append", help="a note on the run for its log (e.g. the build)")
    parser.add_argument("--save", metavar="FILE", help="also save the measured figures as JSON")
    parser.add_argument(
        "--load",
        metavar="FILE",
        help="render a saved run instead of measuring (--write: the verdicts and README only)",
    )
    parser.add_argument("--probe-memory", nargs=2, type=int, metavar=("K", "STEPS"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.probe_memory:
        print(json.dumps(probe_memory(*args.probe_memory)))
        return
    if args.quick:
        args.steps, args.reference_steps, args.repeats = 20_000, 200, 2
        args.loops, args.chain_budget = "1,10,100,1000", 1e5

    m = json.loads(Path(args.load).read_text()) if args.load else measure(args)
    day_time = m["stamp"][:16].replace(" ", "-").replace(":", "")
    plot = runlog.RESULTS / f"speed_vs_error-{day_time}.png"
    figures = runlog.RESULTS / f"compare-{day_time}.json"
    text = json.dumps(m, indent=1) + "\n"
    if args.save:
        Path(args.save).write_text(text)
    report = full_report(m, plot.name)
    print(report)
    if not args.write:
        return
    if args.load:
        link = runlog.link(m["stamp"], "compare.py")
    else:
        tradeoff_plot(m["curves"], plot, m["stamp"])
        figures.write_text(text)
        link = runlog.append_run("compare.py", m["stamp"], report)
        print(f"wrote {runlog.log_path(m['stamp'])}, {plot.name} and {figures.name}", file=sys.stderr)
    runlog.replace_block("compare.py", short_report(m, link))
    runlog.replace_block("compare.py", readme_paragraph(m), ROOT / "README.md")
    runlog.set_latest("compare.py", f"[{m['stamp']}]({link})")
    print(f"wrote {runlog.DOC} and README.md", file=sys.stderr)


if __name__ == "__main__":
    main()

"""Six-bars for synthesis from a curve: on curves a four-bar cannot follow (a straight
side with corners), the best four-bar of a multistart (random crank-rockers refined with
the engine's exact Jacobian) against the Watt I and Stephenson III six-bars grown from
its best designs (`fit_six_bars`: dyads added on the coupler point, the extended design
refined the same way), and the whole run under a time budget of 30 s; each curve without
a transmission bound and with one (15 degrees at B and at D).

The curves (closed unless said, free timing, a Grashof crank-rocker four-bar loop):
a D (8 points along a straight side of 4, 12 around a half circle back), a triangle
(6 points a side, sides 4, 4.24 and 3.16), and an open L (7 points up a side of 3, a
right-angle corner, 5 points along a side of 2).

    python benches/curve_six_bars.py            # print
    python benches/curve_six_bars.py --write    # also add it to the day's log in benches/results/
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

import linkwork
from linkwork.synthesis import curve as C

ROOT = Path(__file__).resolve().parent.parent


def d_shape() -> np.ndarray:
    line = np.column_stack([np.linspace(0.0, 4.0, 9)[:-1], np.zeros(8)])
    a = np.linspace(0.0, math.pi, 13)[:-1]
    return np.vstack([line, np.column_stack([2.0 + 2.0 * np.cos(a), 2.0 * np.sin(a)])])


def triangle() -> np.ndarray:
    s = np.linspace(0.0, 1.0, 7)[:-1]
    p = np.array([[0.0, 0.0], [4.0, 0.0], [1.0, 3.0]])
    return np.vstack([p[i] + np.outer(s, p[(i + 1) % 3] - p[i]) for i in range(3)])


def l_shape() -> np.ndarray:
    up = np.column_stack([np.zeros(7), np.linspace(3.0, 0.0, 7)])
    along = np.column_stack([np.linspace(0.0, 2.0, 6)[1:], np.zeros(5)])
    return np.vstack([up, along])


CURVES = [
    ("D (straight side, two corners)", d_shape, True),
    ("triangle", triangle, True),
    ("open L", l_shape, False),
]


def table(starts: int, seed: int, best: int, dyads: int, budget: float, transmission: float) -> str:
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    try:
        commit = subprocess.check_output(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, text=True).strip()
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    rows = []
    for bound, (name, make, closed) in [(b, c) for b in (None, transmission) for c in CURVES]:
        t = C.target(make(), closed=closed)
        options = {} if bound is None else {"transmission": f"{bound:g} deg"}
        t0 = time.perf_counter()
        four = C.fit(t, starts=starts, seed=seed, workers=2, **options)
        t_four = time.perf_counter() - t0
        t0 = time.perf_counter()
        six = C.fit_six_bars(t, four, best=best, dyads=dyads, seed=seed, workers=2, **options)
        t_six = time.perf_counter() - t0
        timed = C.fit_six_bars(
            t, best=best, dyads=dyads, seed=seed, workers=2, starts=starts, seconds=budget, **options
        )
        fb, sb, tb = four.best, six.best, timed.best
        rows.append(
            f"| {name} | {'-' if bound is None else f'{bound:g} deg'} | {len(t)} "
            f"| {fb.f:.4g} ({fb.max_deviation:.3g}) | {t_four:.1f} s "
            f"| {sb.f:.4g} ({sb.max_deviation:.3g}) | {sb.kind}, {'defect-free' if sb.ok else 'DEFECTS'}, "
            f"{math.degrees(sb.transmission):.0f} / {math.degrees(sb.transmission_dyad):.0f} deg "
            f"| {t_six:.1f} s | {fb.f / max(sb.f, 1e-300):.3g} "
            f"| {tb.f:.4g}, {timed.seconds:.1f} s, {'ended' if timed.budget_ended else 'not ended'} |"
        )
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    lines = [
        f"Measured {stamp} with linkwork {linkwork.__version__} at {commit}, "
        f"Python {platform.python_version()}, {os.cpu_count()} cores (load average {load}); "
        f"`python benches/curve_six_bars.py --starts {starts} --seed {seed} --best {best} --dyads {dyads} "
        f"--budget {budget:g} --transmission {transmission:g}`.",
        "",
        f"Tracking error f (largest deviation) of the best four-bar of {starts} random crank-rockers "
        f"(seed {seed}) and of the best six-bar grown from its {best} best designs, {dyads} dyads each of "
        "each kind, on 2 threads; the six-bar's kind, screening and smallest transmission angles at B and "
        f"at D over the traced stretch; then both in one call under a time budget of {budget:g} s "
        "(`fit_six_bars(..., seconds=...)`, half of it for the four-bars). Each curve without a "
        f"transmission bound, then with {transmission:g} degrees at B and at D.",
        "",
        "| curve | transmission bound | points | four-bar f | time | six-bar f | six-bar | time "
        f"| four-bar f / six-bar f | in {budget:g} s: f, wall time, budget |",
        "|---|---|---|---|---|---|---|---|---|---|",
        *rows,
    ]
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--starts", type=int, default=16)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--best", type=int, default=2)
    ap.add_argument("--dyads", type=int, default=4)
    ap.add_argument("--budget", type=float, default=30.0)
    ap.add_argument("--transmission", type=float, default=15.0, help="the bound of the second run, deg")
    ap.add_argument("--write", action="store_true", help="add the run to benches/results/")
    args = ap.parse_args()
    text = table(args.starts, args.seed, args.best, args.dyads, args.budget, args.transmission)
    print(text)
    if args.write:
        stamp = text.split(" with ", 1)[0].removeprefix("Measured ")
        runlog.append_run("curve_six_bars.py", stamp, text)


if __name__ == "__main__":
    main()

"""Speed against error, in one run: the engine and linkwork.reference on the textbook
four-bar (ground 0.35, crank 0.20, coupler 0.35, rocker 0.25 m, crank at 5 rad/s) over one
revolution, both measured against the closed form.

    python benches/compare.py            # print the table
    python benches/compare.py --write    # and write it into docs/performance.md

Each tool sweeps the same revolution; the reference, about a thousand times slower, gets
fewer steps (its time per step does not depend on the step count). Times are the best of
a few repeats (the machines are shared); the ratio is what to read.
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np

from linkwork import closed_form, examples
from linkwork.reference import ReferenceModel

DIMS = dict(ground=0.35, crank=0.20, coupler=0.35, rocker=0.25)
OMEGA = 5.0


def best_of(repeats: int, fn):
    best, out = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return best, out


def errors(times: np.ndarray, columns: list[str], q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> dict:
    """Largest absolute error of the coupler and rocker angles, rates and accelerations."""
    cf = closed_form.four_bar(**DIMS, theta2=OMEGA * times, omega2=OMEGA, alpha2=0.0)
    e = {"theta [rad]": 0.0, "omega [rad/s]": 0.0, "alpha [rad/s^2]": 0.0}
    for body, k in (("coupler", "3"), ("rocker", "4")):
        j = columns.index(f"{body}.theta")
        d = (q[:, j] - cf["theta" + k] + math.pi) % (2 * math.pi) - math.pi
        e["theta [rad]"] = max(e["theta [rad]"], float(np.max(np.abs(d))))
        e["omega [rad/s]"] = max(e["omega [rad/s]"], float(np.max(np.abs(qd[:, j] - cf["omega" + k]))))
        e["alpha [rad/s^2]"] = max(e["alpha [rad/s^2]"], float(np.max(np.abs(qdd[:, j] - cf["alpha" + k]))))
    return e


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=100_000, help="engine steps (default 100000)")
    parser.add_argument("--reference-steps", type=int, default=2_000, help="reference steps (default 2000)")
    parser.add_argument("--write", action="store_true", help="write docs/performance.md")
    args = parser.parse_args()

    mech = examples.four_bar(**DIMS, omega=OMEGA)
    period = 2 * math.pi / OMEGA
    rows = []

    t = np.linspace(0.0, period, args.steps)
    for linear in ("dense", "sparse"):
        sweep = mech.compile(linear=linear).sweep
        secs, r = best_of(5, lambda sweep=sweep: sweep(t))
        err = errors(t, r.columns, r.q, r.qd, r.qdd)
        rows.append((f"linkwork engine ({linear} LU)", args.steps, secs, err, float(r.iterations.mean())))

    ref = ReferenceModel(mech)
    t_ref = np.linspace(0.0, period, args.reference_steps)
    secs, out = best_of(1, lambda: ref.sweep(t_ref))
    err = errors(t_ref, ref.columns, out["q"], out["qd"], out["qdd"])
    rows.append(
        ("linkwork.reference (NumPy)", args.reference_steps, secs, err, float(out["iterations"].mean()))
    )

    engine_us = rows[0][2] / rows[0][1] * 1e6
    lines = [
        "| tool | steps | us per step | steps per second | vs engine | max error theta [rad] "
        "| omega [rad/s] | alpha [rad/s^2] | mean Newton iterations |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, n, secs, err, iters in rows:
        us = secs / n * 1e6
        lines.append(
            f"| {name} | {n} | {us:.3f} | {n / secs:,.0f} | {us / engine_us:.2f}x | "
            f"{err['theta [rad]']:.1e} | {err['omega [rad/s]']:.1e} | {err['alpha [rad/s^2]']:.1e} "
            f"| {iters:.2f} |"
        )
    table = "\n".join(lines)
    print(table)
    if args.write:
        doc = Path(__file__).resolve().parent.parent / "docs" / "performance.md"
        text = doc.read_text() if doc.exists() else ""
        begin, end = "<!-- compare.py begin -->", "<!-- compare.py end -->"
        block = (
            f"{begin}\nMeasured {time.strftime('%Y-%m-%d')} on {platform.machine()} "
            f"({platform.python_implementation()} {platform.python_version()}, numpy {np.__version__}) "
            f"with `python benches/compare.py --write`:\n\n{table}\n{end}"
        )
        if begin in text:
            text = text[: text.index(begin)] + block + text[text.index(end) + len(end) :]
        else:
            text += "\n" + block + "\n"
        doc.write_text(text)
        print(f"wrote {doc}", file=sys.stderr)


if __name__ == "__main__":
    main()

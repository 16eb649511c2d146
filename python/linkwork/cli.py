"""The command line: ``linkwork demo`` sweeps a built-in mechanism and writes its results.

    linkwork demo [four_bar|slider_crank|...] [--steps N] [--revolutions R] [--out DIR]

prints a summary (range of every coordinate, worst residual, Newton iterations, closest
approach to a singular configuration, speed) and writes DIR/<name>.csv and DIR/<name>.png.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numpy as np

from . import examples
from .errors import LinkworkError


def demo(args: argparse.Namespace) -> int:
    mech = examples.ALL[args.example]()
    model = mech.compile()
    omega = float(mech.to_dict()["drivers"][0]["law"]["rate"])
    t1 = args.revolutions * 2.0 * math.pi / abs(omega)
    times = np.linspace(0.0, t1, args.steps)
    print(f"{model!r}")
    start = time.perf_counter()
    try:
        results = model.sweep(times, progress=sys.stderr.isatty())
    except LinkworkError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    elapsed = time.perf_counter() - start
    print(results.summary())
    print(f"  speed                   {elapsed / args.steps * 1e6:.3f} us per step "
          f"(positions, velocities, accelerations; {args.steps} steps in {elapsed:.3f} s)")  # fmt: skip
    os.makedirs(args.out, exist_ok=True)
    csv_path = os.path.join(args.out, f"{args.example}.csv")
    png_path = os.path.join(args.out, f"{args.example}.png")
    results.to_csv(csv_path)
    results.plot(png_path, every=max(1, args.steps // 2000))  # the plot needs no more points
    print(f"wrote {csv_path} and {png_path}")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="linkwork", description="Planar mechanism kinematics.")
    sub = parser.add_subparsers(dest="command", required=True)
    d = sub.add_parser("demo", help="sweep a built-in mechanism, print a summary, write CSV and PNG")
    d.add_argument("example", nargs="?", default="four_bar", choices=sorted(examples.ALL))
    d.add_argument("--steps", type=int, default=100_000, help="time steps (default 100000)")
    d.add_argument("--revolutions", type=float, default=1.0, help="crank revolutions (default 1)")
    d.add_argument("--out", default="linkwork-out", help="output folder (default linkwork-out)")
    args = parser.parse_args(argv)
    if args.command == "demo":
        if args.steps < 2:
            parser.error("--steps must be at least 2")
        return demo(args)
    return 2


if __name__ == "__main__":
    sys.exit(main())

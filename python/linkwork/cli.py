"""The command line.

    linkwork demo [four_bar|slider_crank|...] [--steps N] [--revolutions R] [--out DIR]
    linkwork run MODEL.json [--t0 T0] [--t1 T1] [--steps N] [--forces] [--plot] [--out DIR]

``demo`` sweeps a built-in mechanism: it prints a summary (range of every coordinate, worst
residual, Newton iterations, closest approach to a singular configuration, speed) and
writes DIR/<name>.csv and DIR/<name>.png. ``run`` does the same for a model file; with
``--forces`` it adds the inverse dynamics (peak efforts and their parts, peak pin forces,
the energy balance) and DIR/<model>_forces.csv (.png with ``--plot``).
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


def run(args: argparse.Namespace) -> int:
    from .mechanism import Mechanism

    try:
        mech = Mechanism.load(args.model)
        model = mech.compile()
    except (OSError, ValueError) as e:
        print(f"error: {args.model}: {e}", file=sys.stderr)
        return 1
    times = np.linspace(args.t0, args.t1, args.steps)
    print(f"{model!r}")
    try:
        results = model.sweep(times, progress=sys.stderr.isatty(), forces=args.forces)
    except LinkworkError as e:
        print(f"error: {e}", file=sys.stderr)
        partial = getattr(e, "partial", None)
        if partial is not None and len(partial):
            print(f"(the {len(partial)} steps before the failure are in the output)", file=sys.stderr)
            results, status = partial, 1
        else:
            return 1
    else:
        status = 0
    print(results.summary())
    stem = os.path.splitext(os.path.basename(args.model))[0]
    os.makedirs(args.out, exist_ok=True)
    written = [os.path.join(args.out, f"{stem}.csv")]
    results.to_csv(written[0])
    every = max(1, args.steps // 2000)
    if args.plot:
        written.append(os.path.join(args.out, f"{stem}.png"))
        results.plot(written[-1], every=every)
    if args.forces:
        print(results.forces_summary())
        written.append(os.path.join(args.out, f"{stem}_forces.csv"))
        results.forces_to_csv(written[-1])
        if args.plot:
            written.append(os.path.join(args.out, f"{stem}_forces.png"))
            results.plot_forces(written[-1], every=every)
    print("wrote " + ", ".join(written))
    return status


def check(args: argparse.Namespace) -> int:
    """Counts bodies, rows and degrees of freedom, finds redundant rows and each driver's
    limits of motion, without sweeping; exit status 1 if the model has a problem."""
    from .mechanism import Mechanism

    try:
        model = Mechanism.load(args.model).compile()
    except (OSError, ValueError) as e:
        # a model error already names the joints at fault (redundant rows, a structure)
        print(f"error: {args.model}: {e}", file=sys.stderr)
        return 1
    print(f"{model!r}")
    try:
        mob = model.mobility(t=args.t)
    except LinkworkError as e:
        print(f"error: cannot assemble at t = {args.t}: {e}", file=sys.stderr)
        return 1
    print(mob.report())
    problem = mob.redundant or mob.dof_driven > 0
    drivers = [c[0] for c in model.constraints if c[1] == "driver"]
    for name in drivers:
        try:
            print(f"  limits of motion        {model.motion_limits(name, t=args.t, q_guess=mob.q)}")
        except LinkworkError as e:
            print(f"  limits of motion        {name}: not found ({e})")
    print("problems found" if problem else "ok")
    return 1 if problem else 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="linkwork", description="Planar mechanism kinematics.")
    sub = parser.add_subparsers(dest="command", required=True)
    d = sub.add_parser("demo", help="sweep a built-in mechanism, print a summary, write CSV and PNG")
    d.add_argument("example", nargs="?", default="four_bar", choices=sorted(examples.ALL))
    d.add_argument("--steps", type=int, default=100_000, help="time steps (default 100000)")
    d.add_argument("--revolutions", type=float, default=1.0, help="crank revolutions (default 1)")
    d.add_argument("--out", default="linkwork-out", help="output folder (default linkwork-out)")
    r = sub.add_parser("run", help="sweep a JSON model file; write CSV (and PNG with --plot)")
    r.add_argument("model", help="model file (JSON, as written by Mechanism.save)")
    r.add_argument("--t0", type=float, default=0.0, help="first time [s] (default 0)")
    r.add_argument("--t1", type=float, default=1.0, help="last time [s] (default 1)")
    r.add_argument("--steps", type=int, default=1001, help="time steps (default 1001)")
    r.add_argument("--forces", action="store_true", help="inverse dynamics: driver efforts, joint reactions")
    r.add_argument("--plot", action="store_true", help="also write PNG plots")
    r.add_argument("--out", default="linkwork-out", help="output folder (default linkwork-out)")
    c = sub.add_parser("check", help="count bodies, rows, degrees of freedom; find redundancy and limits")
    c.add_argument("model", help="model file (JSON, as written by Mechanism.save)")
    c.add_argument("--t", type=float, default=0.0, help="time of the configuration checked (default 0)")
    args = parser.parse_args(argv)
    if args.command == "check":
        return check(args)
    if args.steps < 2:
        parser.error("--steps must be at least 2")
    if args.command == "demo":
        return demo(args)
    return run(args)


if __name__ == "__main__":
    sys.exit(main())

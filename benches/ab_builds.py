"""Two builds of linkwork side by side: the same sweeps, alternating between them, each in
a fresh process, so that a refactor's cost (or gain) is read as a ratio on a noisy machine.

    python benches/ab_builds.py OLD_PYTHONPATH NEW_PYTHONPATH [--rounds 5] [--simulate]

``--simulate`` times forward dynamics instead: IFToMM A01 and A02 (N = 1 and 2) over 10 s
and Andrews' squeezer over 0.03 s, 1,001 rows each, rk8 at rtol = atol 1e-3, 1e-4, 1e-6
and 1e-8, each the best of 5 runs in its process.

Each path is a directory holding a `linkwork` package with its built extension (a
worktree's python/ after `pip install -e .` or scripts/dev-build.sh). Prints, for each
mechanism, the best time of each build over the rounds and new / old.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

# the sweeps timed: the textbook four-bar, a slider-crank and a six-bar, 100,000 steps over
# one crank turn (5 rad/s), positions, velocities and accelerations; best of 5 per process
PROBE = r"""
import json, math, time
import numpy as np
import linkwork as lw
t = np.linspace(0.0, 2.0 * math.pi / 5.0, 100_001)
out = {}
for name in ("four_bar", "slider_crank", "six_bar_watt"):
    m = lw.examples.ALL[name]().compile()
    m.sweep(t)
    best = math.inf
    for _ in range(5):
        s = time.perf_counter()
        m.sweep(t)
        best = min(best, time.perf_counter() - s)
    out[name] = best
print(json.dumps(out))
"""

SIMULATE = r"""
import json, math, time
import numpy as np
from linkwork.mechanism import benchmarks
out = {}
cases = [("A01", benchmarks.pendulum(), 10.0), ("A02 N=1", benchmarks.n_four_bar(1), 10.0),
         ("A02 N=2", benchmarks.n_four_bar(2), 10.0), ("Andrews", benchmarks.andrews_squeezer(), 0.03)]
for name, b, t_end in cases:
    m = b.mechanism.compile(free=True)
    t = np.linspace(0.0, t_end, 1001)
    for rtol in (1e-3, 1e-4, 1e-6, 1e-8):
        best = math.inf
        for _ in range(5):
            s = time.perf_counter()
            m.simulate(t, rtol=rtol, atol=rtol, qd0=b.qd0)
            best = min(best, time.perf_counter() - s)
        out[f"{name} rtol {rtol:g}"] = best
print(json.dumps(out))
"""


def _run(path: str, probe: str) -> dict[str, float]:
    # one BLAS thread: numpy's idle threads would otherwise share the two cores
    env = {**os.environ, "PYTHONPATH": path, "OPENBLAS_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--simulate", action="store_true", help="time forward dynamics instead")
    args = parser.parse_args()
    probe = SIMULATE if args.simulate else PROBE
    best: dict[str, dict[str, float]] = {"old": {}, "new": {}}
    for k in range(args.rounds):
        # which build goes first alternates too: a process's place in the pair is no bias
        for which in ("old", "new") if k % 2 == 0 else ("new", "old"):
            for name, seconds in _run(getattr(args, which), probe).items():
                best[which][name] = min(best[which].get(name, float("inf")), seconds)
    if args.simulate:
        print(f"best of {args.rounds} alternating rounds (x5 runs each), 1,001 rows, rk8")
    else:
        print(f"best of {args.rounds} alternating rounds (x5 sweeps each), 100,001 steps, p+v+a")
    print("| case | old [s] | new [s] | new / old |")
    print("|---|---:|---:|---:|")
    for name in best["old"]:
        old, new = best["old"][name], best["new"][name]
        print(f"| {name} | {old:.5f} | {new:.5f} | {new / old:.3f} |")


if __name__ == "__main__":
    main()

"""Two builds of linkwork side by side: the same sweeps, alternating between them, each in
a fresh process, so that a refactor's cost (or gain) is read as a ratio on a noisy machine.

    python benches/ab_builds.py OLD_PYTHONPATH NEW_PYTHONPATH [--rounds 5]

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


def _run(path: str) -> dict[str, float]:
    env = {**os.environ, "PYTHONPATH": path}
    done = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    best: dict[str, dict[str, float]] = {"old": {}, "new": {}}
    for _ in range(args.rounds):
        for which in ("old", "new"):
            for name, seconds in _run(getattr(args, which)).items():
                best[which][name] = min(best[which].get(name, float("inf")), seconds)
    print(f"best of {args.rounds} alternating rounds (x5 sweeps each), 100,001 steps, p+v+a")
    print("| mechanism | old [s] | new [s] | new / old |")
    print("|---|---:|---:|---:|")
    for name in best["old"]:
        old, new = best["old"][name], best["new"][name]
        print(f"| {name} | {old:.5f} | {new:.5f} | {new / old:.3f} |")


if __name__ == "__main__":
    main()

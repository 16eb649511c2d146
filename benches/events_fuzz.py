"""Random runs of a spinning parallelogram through its change points: does the event watch
report every one, and does each run either finish or stop with a named error?

    python benches/events_fuzz.py --n 400 --seed 1 --rtol 1e-10 1e-3 --methods rk8 gen-alpha
    python benches/events_fuzz.py --n 300 --seed 7 --rtol 1e-5 1e-1 --methods rk8

A free parallelogram (crank 0.1, coupler and ground 0.3) started at crank angle th in
[0.1, 3] turning at w in [17, 120] rad/s passes a change point (all bars on the ground
line) every time its crank passes a multiple of pi. Each run draws w, th, rtol
(log-uniform in the range), a method and the rows' spacing (0.001 to 0.1 s), simulates
1 s, and counts the bifurcations reported against the multiples of pi the crank passed
(from its angle at the last row), and the rows' energy balance against the start. Printed:
each run that missed or added one ("MISS", with its draws), each whose T + V left its
start by more than 5 % of the energies at some row ("OFF": rates off the motion), each
that raised ("ERR", with the error's first words), and the counts.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from linkwork import Model

PARALLELOGRAM = {
    "name": "parallelogram",
    "gravity": [0.0, -9.81],
    "bodies": [
        {"name": "crank", "x": 0.0, "y": 0.0, "theta": 0.5, "mass": 0.4, "inertia": 0.002},
        {
            "name": "coupler",
            "x": 0.08775825618903728,
            "y": 0.0479425538604203,
            "theta": 0.0,
            "mass": 1.1,
            "inertia": 0.01,
        },
        {"name": "rocker", "x": 0.3, "y": 0.0, "theta": 0.5, "mass": 0.7, "inertia": 0.003},
    ],
    "joints": [
        {"type": "revolute", "name": "O2", "body_a": "ground", "body_b": "crank", "at": [0.0, 0.0]},
        {
            "type": "revolute",
            "name": "A",
            "body_a": "crank",
            "body_b": "coupler",
            "at": [0.08775825618903728, 0.0479425538604203],
        },
        {
            "type": "revolute",
            "name": "B",
            "body_a": "coupler",
            "body_b": "rocker",
            "at": [0.3877582561890373, 0.0479425538604203],
        },
        {"type": "revolute", "name": "O4", "body_a": "ground", "body_b": "rocker", "at": [0.3, 0.0]},
    ],
}


# a run whose rows' T + V - W leaves its start by more than this part of the energies has
# left the motion somewhere (only gravity acts: T + V holds to the tolerance)
OFF_BALANCE = 0.05


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=400)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--rtol", type=float, nargs=2, default=[1e-10, 1e-3], metavar=("LO", "HI"))
    ap.add_argument("--methods", nargs="+", default=["rk8", "gen-alpha"])
    args = ap.parse_args()
    model = Model(PARALLELOGRAM, free=True)
    rng = np.random.default_rng(args.seed)
    lo, hi = np.log10(args.rtol[0]), np.log10(args.rtol[1])
    counts = {"finished": 0, "missed": 0, "off": 0, "errors": 0}
    start = time.time()
    for _ in range(args.n):
        w, th = rng.uniform(17, 120), rng.uniform(0.1, 3.0)
        rtol = 10.0 ** rng.uniform(lo, hi)
        method = str(rng.choice(args.methods))
        dt = float(rng.choice([0.001, 0.005, 0.02, 0.1]))
        times = np.arange(0.0, 1.0 + dt / 2, dt)
        q0 = [0.0, 0.0, th, 0.1 * np.cos(th), 0.1 * np.sin(th), 0.0, 0.3, 0.0, th]
        qd0 = [0.0, 0.0, w, -0.1 * w * np.sin(th), 0.1 * w * np.cos(th), 0.0, 0.0, 0.0, w]
        draws = f"{method} w={w!r} th={th!r} rtol={rtol!r} dt={dt}"
        try:
            sim = model.simulate(times, q0=q0, qd0=qd0, rtol=rtol, atol=rtol, method=method)
        except Exception as e:  # every error is counted and shown: none may be a surprise
            counts["errors"] += 1
            print("ERR", draws, type(e).__name__, str(e)[:160])
            continue
        counts["finished"] += 1
        passed = int(np.floor(sim.q[-1, 2] / np.pi) - np.floor(th / np.pi))
        found = [e for e in sim.events if str(e.kind) == "bifurcation"]
        off = max((abs(e.q[2] - np.pi * round(e.q[2] / np.pi)) for e in found), default=0.0)
        energy = sim.energy()
        balance = np.abs(energy.balance).max() / (energy.kinetic[0] + abs(energy.potential[0]))
        if balance > OFF_BALANCE:
            counts["off"] += 1
            print("OFF", draws, f"T + V - W leaves its start by {balance:.1%} of the energies")
        if len(found) != passed:
            counts["missed"] += 1
            print("MISS", draws, "passed", passed, "reported", len(found))
        else:
            print(
                "ok", draws, f"crossings {passed}, farthest {off:.1e} rad from k pi ({off / rtol:.0f} rtol)"
            )
    print(counts, f"{time.time() - start:.0f} s")


if __name__ == "__main__":
    main()

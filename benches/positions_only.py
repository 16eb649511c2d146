"""One design, side by side with pylinkage-numba in one process: linkwork ``model.sweep``
of positions only (``derivatives=0``) and of positions, velocities and accelerations,
against pylinkage's ``step_fast`` and ``step_fast_with_kinematics``, on the four-bar and
the slider-crank of ``compare.py`` and Jansen's leg (``jansen.py``), one revolution in N
steps, the tasks taking turns in each round (``compare.interleaved``). Prints each one's
best time per step and the ratio pylinkage / linkwork (above 1: linkwork faster), and
checks both tools' foot paths of Jansen's leg against its circle intersections.

    PYTHONPATH=python python benches/positions_only.py [--steps 100000] [--repeats 7] [--clock cpu]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

from linkwork import examples

sys.path.insert(0, str(Path(__file__).parent))
import baselines  # noqa: E402
import jansen  # noqa: E402
from compare import DIMS, OMEGA, PERIOD, SLIDER, Task, cold_outputs, interleaved  # noqa: E402

NAMES = ("four-bar", "slider-crank", "Jansen's leg")
# the foot of Jansen's leg against its circle intersections, at every this many steps
FOOT_EVERY = 997


def foot_errors(steps: int) -> dict[str, float]:
    """The largest distance (m) of each tool's foot of Jansen's leg from ``jansen.pins``,
    positions only and with rates, every ``FOOT_EVERY`` steps of one revolution."""
    t = np.linspace(0.0, PERIOD, steps)
    model = jansen.mechanism(omega=OMEGA).compile()
    rows = np.arange(0, steps, FOOT_EVERY)

    def error(path: np.ndarray, angles: np.ndarray) -> float:
        ref = np.array([jansen.pins(float(a))["F"] for a in angles])
        return float(np.max(np.hypot(*(path[rows] - ref).T)))

    out = {
        f"linkwork d={d}": error(
            np.asarray(model.sweep(t, derivatives=d).point("F").position), OMEGA * t[rows]
        )
        for d in (0, 2)
    }
    if baselines.pylinkage_version() is not None:
        for d in (0, 2):
            build, run, foot = baselines.pylinkage_jansen(OMEGA, steps, d == 2)
            out[f"pylinkage d={d}"] = error(foot(run(build())), (rows + 1.0) * (2.0 * np.pi / steps))
    return out


def tasks(steps: int) -> tuple[list[Task], dict[str, tuple[str, str, int]]]:
    t = np.linspace(0.0, PERIOD, steps)
    models = {
        "four-bar": examples.four_bar(**DIMS, omega=OMEGA).compile(),
        "slider-crank": examples.slider_crank().compile(),
        "Jansen's leg": jansen.mechanism(omega=OMEGA).compile(),
    }
    out: list[Task] = []
    meta: dict[str, tuple[str, str, int]] = {}
    for name, model in models.items():
        for d in (0, 2):
            key = f"linkwork {name} d={d}"
            out.append(Task(key, lambda _, m=model, d=d: m.sweep(t, derivatives=d), lambda: cold_outputs()))
            meta[key] = (name, "linkwork", d)
    if baselines.pylinkage_version() is None:
        return out, meta
    for mode, d in (("step_fast", 0), ("step_fast_with_kinematics", 2)):
        kinematics = d == 2
        pairs: list[tuple[str, Callable[[], Any], Callable[[Any], Any]]] = []
        b, r, _ = baselines.pylinkage_four_bar(DIMS, OMEGA, steps, kinematics)
        pairs.append(("four-bar", b, r))
        b, r, _ = baselines.pylinkage_slider_crank(*SLIDER, OMEGA, steps, mode)
        pairs.append(("slider-crank", b, r))
        b, r, _ = baselines.pylinkage_jansen(OMEGA, steps, kinematics)
        pairs.append(("Jansen's leg", b, r))
        for name, build, run in pairs:
            run(build())  # numba's compilation, not timed
            key = f"pylinkage {name} d={d}"

            def setup(build: Callable[[], Any] = build) -> Any:
                cold_outputs()
                return build()

            out.append(Task(key, run, setup))
            meta[key] = (name, "pylinkage", d)
    return out, meta


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument(
        "--clock",
        choices=("wall", "cpu"),
        default="wall",
        help="wall-clock time, or this thread's CPU time (not the turns other processes take)",
    )
    args = parser.parse_args()
    if os.environ.get("PYTHONHASHSEED") != "0":
        # pylinkage's builder and numba path order Jansen's pins by its sets' order, Python's
        # hash seed: on some seeds its leg leaves the assembly (NaN); one fixed seed, the
        # same leg on every run
        os.execve(sys.executable, [sys.executable, *sys.argv], {**os.environ, "PYTHONHASHSEED": "0"})
    print(f"load average before: {os.getloadavg()}")
    for key, err in foot_errors(args.steps).items():
        print(f"Jansen's leg, {key}: foot {err:.1e} m from the circle intersections")
        assert err < 1e-9, f"{key}: the foot is off the leg's assembly"
    ts, meta = tasks(args.steps)
    timed = interleaved(ts, args.repeats, time.thread_time if args.clock == "cpu" else time.perf_counter)
    us = {k: secs / args.steps * 1e6 for k, (secs, _) in timed.items()}
    for key in sorted(us):
        print(f"{key:40s} {us[key]:8.4f} us/step")
    for name in NAMES:
        for d in (0, 2):
            lw, pl = f"linkwork {name} d={d}", f"pylinkage {name} d={d}"
            if pl in us:
                print(f"{name} d={d}: pylinkage / linkwork = {us[pl] / us[lw]:.2f}x")
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()

"""What users would otherwise run, on the textbook four-bar and slider-crank, for
``compare.py``, and on Jansen's leg, for ``positions_only.py``.

- pylinkage (optional; ``pip install pylinkage==1.3.0 numba``): its numba fast path,
  closed-form dyads (circle-circle intersections) applied joint after joint.
  ``Mechanism.step_fast`` gives positions only, ``step_fast_with_kinematics`` positions,
  velocities and accelerations of every joint. The crank advances by a fixed angle per
  step, so a sweep of N steps over one revolution has row k at crank angle
  (k + 1) 2 pi / N; angular rates come from the joints' linear velocities and
  accelerations: omega = (r x v) / |r|^2 and alpha = (r x a) / |r|^2 along each bar.
- SciPy ``fsolve`` (MINPACK hybrd, forward-difference Jacobian), positions only, on the
  two loop-closure equations in (theta3, theta4) at each crank angle, warm-started from
  the previous step's solution, ``xtol`` = 1e-12.

Each tool returns the crank angles it solved at and the coupler and rocker angles, rates
and accelerations it found (None for what it does not compute), for ``compare.errors``.
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

Solved = dict[str, Any]


def pylinkage_version() -> str | None:
    """pylinkage's version with numba's, or None if either is missing."""
    try:
        import numba
        import pylinkage
    except ImportError:
        return None
    return f"pylinkage {pylinkage.__version__}, numba {numba.__version__}"


def pylinkage_four_bar(
    dims: dict[str, float], omega: float, steps: int, kinematics: bool
) -> tuple[Callable[[], Any], Callable[[Any], Any], Callable[[Any], Solved]]:
    """(build, run, decode): ``build()`` makes the linkage and its solver arrays (not
    timed, as linkwork's compile is not); ``run(linkage)`` sweeps one revolution in
    ``steps`` steps with pylinkage's numba path; ``decode(out)`` gives the angles."""
    from pylinkage.mechanism import fourbar

    def build() -> Any:
        m = fourbar(
            crank=dims["crank"],
            coupler=dims["coupler"],
            rocker=dims["rocker"],
            ground=dims["ground"],
            omega=2.0 * math.pi / steps,  # rad per step
            initial_angle=0.0,
            branch=1,  # B above the ground line: linkwork's open branch
        )
        if kinematics:
            m.set_input_velocity(m._driver_links[0], omega, 0.0)  # rad/s, rad/s^2
        m.compile()
        return m

    def run(m: Any) -> Any:
        return m.step_fast_with_kinematics(iterations=steps) if kinematics else m.step_fast(iterations=steps)

    names = [j.name for j in build().joints]
    i_a, i_d = names.index("coupler.0_crank.tip"), names.index("ground.D_rocker.1")
    i_b = names.index("coupler.1_rocker.0")

    def decode(out: Any) -> Solved:
        pos, vel, acc = out if kinematics else (out, None, None)
        theta2 = (np.arange(steps) + 1.0) * (2.0 * math.pi / steps)
        r3 = pos[:, i_b] - pos[:, i_a]  # coupler A -> B
        r4 = pos[:, i_b] - pos[:, i_d]  # rocker O4 -> B
        solved: Solved = {
            "theta2": theta2,
            "theta3": np.arctan2(r3[:, 1], r3[:, 0]),
            "theta4": np.arctan2(r4[:, 1], r4[:, 0]),
        }
        if vel is None:
            return solved

        def rate(r: np.ndarray, d: np.ndarray) -> np.ndarray:
            return (r[:, 0] * d[:, 1] - r[:, 1] * d[:, 0]) / np.sum(r * r, axis=1)

        solved["omega3"] = rate(r3, vel[:, i_b] - vel[:, i_a])
        solved["omega4"] = rate(r4, vel[:, i_b] - vel[:, i_d])
        solved["alpha3"] = rate(r3, acc[:, i_b] - acc[:, i_a])
        solved["alpha4"] = rate(r4, acc[:, i_b] - acc[:, i_d])
        return solved

    return build, run, decode


def pylinkage_slider_crank(
    crank: float, rod: float, offset: float, omega: float, steps: int, mode: str
) -> tuple[Callable[[], Any], Callable[[Any], Any], Callable[[Any], Solved]]:
    """(build, run, decode) for pylinkage's slider-crank (the slide along x at height
    ``offset``, the slider on the side of +x, as linkwork's open branch): ``mode`` is
    "step_fast_with_kinematics", "step_fast" (numba) or "step" (its Python loop, positions
    only). ``decode`` gives the rod angle ``theta3`` and the slider's ``x`` (with
    ``omega3``, ``v``, ``alpha3``, ``a`` where computed) at the crank angles."""
    from pylinkage.mechanism import slider_crank

    def build() -> Any:
        m = slider_crank(
            crank=crank,
            rod=rod,
            omega=2.0 * math.pi / steps,  # rad per step
            initial_angle=0.0,
            slide_through=(0.0, offset),
            slide_direction=(-1.0, 0.0),  # its circle-line pick then lands on +x
        )
        if mode == "step_fast_with_kinematics":
            m.set_input_velocity(m._driver_links[0], omega, 0.0)
        if mode != "step":
            m.compile()
        return m

    def run(m: Any) -> Any:
        if mode == "step":
            return np.array(list(m.step(iterations=steps)))
        return getattr(m, mode)(iterations=steps)

    m = build()
    names = [j.name for j in m.joints]
    # step() yields the joints in its solving order; the fast paths in m.joints' order
    first = list(m.step(iterations=1))[0] if mode == "step" else None
    if first is not None:
        i_a = next(i for i, p in enumerate(first) if abs(math.hypot(*p) - crank) < 1e-9)
        i_b = next(i for i, p in enumerate(first) if abs(p[1] - offset) < 1e-12 and p[0] > crank)
    else:
        i_a = next(i for i, n in enumerate(names) if n.startswith("crank.tip"))
        i_b = next(i for i, n in enumerate(names) if n.startswith("rod."))

    def decode(out: Any) -> Solved:
        pos, vel, acc = out if mode == "step_fast_with_kinematics" else (out, None, None)
        pos = np.asarray(pos, dtype=float)
        r3 = pos[:, i_b] - pos[:, i_a]
        solved: Solved = {
            "theta2": (np.arange(steps) + 1.0) * (2.0 * math.pi / steps),
            "theta3": np.arctan2(r3[:, 1], r3[:, 0]),
            "x": pos[:, i_b, 0],
        }
        if vel is not None:
            rr = np.sum(r3 * r3, axis=1)
            dv, da = vel[:, i_b] - vel[:, i_a], acc[:, i_b] - acc[:, i_a]
            solved["omega3"] = (r3[:, 0] * dv[:, 1] - r3[:, 1] * dv[:, 0]) / rr
            solved["alpha3"] = (r3[:, 0] * da[:, 1] - r3[:, 1] * da[:, 0]) / rr
            solved["v"], solved["a"] = vel[:, i_b, 0], acc[:, i_b, 0]
        return solved

    return build, run, decode


def pylinkage_jansen(
    omega: float, steps: int, kinematics: bool
) -> tuple[Callable[[], Any], Callable[[Any], Any], Callable[[Any], np.ndarray]]:
    """(build, run, foot) for Jansen's leg (``jansen.py``, its lengths and assembly) in
    pylinkage: each of its ten bars a binary link (a rigid triangle is three bars; pylinkage
    1.3's numba path leaves a ternary link's third port behind), each pin where two of
    them meet, on the branch that draws the leg of ``jansen.pins(0)``. ``foot(out)`` gives
    the foot's path, row k at crank angle (k + 1) 2 pi / steps."""
    import jansen
    from pylinkage.mechanism import MechanismBuilder

    def build() -> Any:
        b = MechanismBuilder(name="Jansen's leg")
        b.add_ground_link("ground", ports={"O": jansen.CRANK_PIVOT, "Q": jansen.Q})
        b.add_driver_link("crank", length=jansen.L["m"], motor_port="O", omega=2.0 * math.pi / steps)
        ports: dict[str, set[str]] = {"O": {"crank.motor", "ground.O"}, "C": {"crank.tip"}, "Q": {"ground.Q"}}
        for bar, *ends in jansen.BARS:
            b.add_link(bar, length=jansen.L[bar])
            for end, pin in enumerate(ends):
                if pin in ports:
                    b.connect(min(ports[pin]), f"{bar}.{end}")
                ports.setdefault(pin, set()).add(f"{bar}.{end}")
        # which two pins the builder solves a pin from, so what its branch 0 or 1 means,
        # follows its sets' order (Python's hash seed): whatever it draws, every pin is then
        # put where jansen.pins(0) has it, and the numba path follows the nearest solution
        m = b.build()
        drawn = jansen.pins(0.0)
        where = {frozenset(v): drawn[pin] for pin, v in ports.items()}
        m.set_joint_positions([where[frozenset(j.name.split("_"))] for j in m.joints])
        if kinematics:
            m.set_input_velocity(m._driver_links[0], omega, 0.0)
        m.compile()
        return m

    def run(m: Any) -> Any:
        return m.step_fast_with_kinematics(iterations=steps) if kinematics else m.step_fast(iterations=steps)

    i_foot = next(i for i, j in enumerate(build().joints) if j.name == "h.1_i.1")

    def foot(out: Any) -> np.ndarray:
        pos = out[0] if kinematics else out
        return np.asarray(pos)[:, i_foot]

    return build, run, foot


def fsolve_four_bar(dims: dict[str, float], theta2: np.ndarray, start: tuple[float, float]) -> Solved:
    """Positions by SciPy's fsolve on the loop equations at each crank angle, warm-started."""
    from scipy.optimize import fsolve

    a, b, c, d = dims["crank"], dims["coupler"], dims["rocker"], dims["ground"]

    def loop(x: np.ndarray, th2: float) -> list[float]:
        return [
            a * math.cos(th2) + b * math.cos(x[0]) - c * math.cos(x[1]) - d,
            a * math.sin(th2) + b * math.sin(x[0]) - c * math.sin(x[1]),
        ]

    out = np.empty((len(theta2), 2))
    x = np.array(start, dtype=float)
    for k, th2 in enumerate(theta2):
        x = fsolve(loop, x, args=(float(th2),), xtol=1e-12)
        out[k] = x
    return {"theta2": theta2, "theta3": out[:, 0], "theta4": out[:, 1]}

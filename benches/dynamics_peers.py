"""Forward dynamics side by side: Exudyn's integrators against the exact references of
IFToMM A01 (simple pendulum) and A02 (N-four-bar, N = 2), 10 s of motion each, and
against the published angles of Andrews' squeezer (0.03 s).

Exudyn (``pip install exudyn``, the ``bench`` extra) runs its generalized-alpha (index 3)
and its trapezoidal index-2 solvers at a ladder of fixed step sizes; each row gives the
wall time of ``SolveDynamic``, the largest error of the reported point (A01's tip P1,
A02's B0) against the exact solution at the sampled times (every 0.01 s), and for A02
whether the run stayed on the branch (every crank at the same angle); for Andrews'
squeezer the error is the test set's, the worst relative error of the seven angles.
The engine's ``Model.simulate`` is a column of its own when it exists (a ladder of tolerances), with
the speed ratio at equal error: each Exudyn row against the cheapest linkwork run at or below
its error (``--repeat k``: every row the fastest of k runs); the NumPy reference
(``linkwork.reference.simulate``) is listed for accuracy, not speed.

    python benches/dynamics_peers.py            # prints the tables
    python benches/dynamics_peers.py --write    # and adds them to benches/results/dynamics-<day>.md
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import time
from functools import partial
from pathlib import Path
from typing import Any, Callable

import numpy as np

from linkwork.mechanism import benchmarks
from linkwork.model.compiled import Model
from linkwork.reference import exact
from linkwork.reference import simulate as reference_simulate

RESULTS = Path(__file__).resolve().parent / "results"
T_END = 10.0
SAMPLE = 0.01  # sensor period, s
STEPS = [1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4]
SOLVERS = ("GeneralizedAlpha", "TrapezoidalIndex2")
# the timer of every run: wall time, or with --cpu this process's CPU time (less disturbed
# by other work on a shared machine; Exudyn's and linkwork's runs are both one thread here)
CLOCK: Callable[[], float] = time.perf_counter
RTOLS = [1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 1e-6, 1e-8, 1e-10, 1e-11, 1e-12]  # linkwork's ladder
BRANCH_TOL = 1e-3  # rad: cranks further apart than this have left the branch


def _settings(exu: Any, h: float, t_end: float) -> Any:
    s = exu.SimulationSettings()
    s.timeIntegration.numberOfSteps = int(round(t_end / h))
    s.timeIntegration.endTime = t_end
    s.timeIntegration.verboseMode = 0
    s.show.statistics = False
    s.show.computationTime = False
    s.solution.file.write = False
    s.solution.sensors.writePeriod = SAMPLE
    s.timeIntegration.generalizedAlpha.computeInitialAccelerations = True
    return s


def exudyn_pendulum(h: float, solver: str, t_end: float = T_END) -> dict[str, Any]:
    """A01 in Exudyn as its pendulumIftommBenchmark.py builds it (a mass point and a
    distance constraint), started from (L, 0) as the benchmark specifies."""
    import exudyn as exu
    from exudyn.itemInterface import (
        DistanceConstraint,
        Force,
        MarkerBodyPosition,
        MarkerNodePosition,
        MassPoint2D,
        NodePoint2D,
        ObjectGround,
        SensorNode,
    )

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ObjectGround(referencePosition=[0, 0, 0]))
    node = mbs.AddNode(NodePoint2D(referenceCoordinates=[1.0, 0.0], initialCoordinates=[0, 0]))
    mbs.AddObject(MassPoint2D(mass=1.0, nodeNumber=node))
    m_mass = mbs.AddMarker(MarkerNodePosition(nodeNumber=node))
    m_ground = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[0, 0, 0]))
    mbs.AddObject(DistanceConstraint(markerNumbers=[m_ground, m_mass], distance=1.0))
    mbs.AddLoad(Force(markerNumber=m_mass, loadVector=[0, -9.81, 0]))
    sensor = mbs.AddSensor(
        SensorNode(nodeNumber=node, storeInternal=True, outputVariableType=exu.OutputVariableType.Position)
    )
    mbs.Assemble()
    settings = _settings(exu, h, t_end)
    start = CLOCK()
    try:
        mbs.SolveDynamic(settings, solverType=getattr(exu.DynamicSolverType, solver))
    except Exception:  # Exudyn reports a failed run (Newton not converging) by raising
        return {"wall": CLOCK() - start, "error": math.inf, "branch": False, "failed": True}
    wall = CLOCK() - start
    data = mbs.GetSensorStoredData(sensor)
    x, y = exact.pendulum_tip(data[:, 0])
    error = float(np.max(np.hypot(data[:, 1] - x, data[:, 2] - y)))
    return {"wall": wall, "error": error, "branch": True}


def exudyn_n_four_bar(h: float, solver: str, n: int = 2, t_end: float = T_END) -> dict[str, Any]:
    """A02 in Exudyn as its fourBarMechanismIftomm.py builds it (RigidBody2D bars with
    their nodes at the centres, RevoluteJoint2D pins), for any N."""
    import exudyn as exu
    from exudyn.itemInterface import (
        LoadMassProportional,
        MarkerBodyMass,
        MarkerBodyPosition,
        MarkerBodyRigid,
        NodeRigidBody2D,
        ObjectGround,
        RevoluteJoint2D,
        RigidBody2D,
        SensorBody,
        SensorNode,
    )

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    L, mass, inertia = 1.0, 1.0, 1.0 / 12.0
    cranks = [([k * L, 0.5 * L, 0.5 * math.pi], [0.5, 0.0, -1.0]) for k in range(n + 1)]
    couplers = [([(k - 0.5) * L, L, 0.0], [1.0, 0.0, 0.0]) for k in range(1, n + 1)]
    bodies, nodes, left, right = [], [], [], []
    for ref, vel in cranks + couplers:
        node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=ref, initialVelocities=vel))
        body = mbs.AddObject(RigidBody2D(nodeNumber=node, mass=mass, inertia=inertia))
        mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=body)),
                                         loadVector=[0, -9.81, 0]))  # fmt: skip
        left.append(mbs.AddMarker(MarkerBodyPosition(bodyNumber=body, localPosition=[-0.5 * L, 0, 0])))
        right.append(mbs.AddMarker(MarkerBodyPosition(bodyNumber=body, localPosition=[0.5 * L, 0, 0])))
        bodies.append(body)
        nodes.append(node)
    ground = mbs.AddObject(ObjectGround())
    for k in range(n + 1):
        pivot = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localPosition=[k * L, 0, 0]))
        mbs.AddObject(RevoluteJoint2D(markerNumbers=[pivot, left[k]]))
    for k in range(1, n + 1):
        coupler = n + k  # couplers follow the cranks
        mbs.AddObject(RevoluteJoint2D(markerNumbers=[right[k - 1], left[coupler]]))
        mbs.AddObject(RevoluteJoint2D(markerNumbers=[right[coupler], right[k]]))
    tip = mbs.AddSensor(
        SensorBody(bodyNumber=bodies[0], localPosition=[0.5 * L, 0, 0], storeInternal=True,
                   outputVariableType=exu.OutputVariableType.Position)
    )  # fmt: skip
    angles = [
        mbs.AddSensor(SensorNode(nodeNumber=nodes[k], storeInternal=True,
                                 outputVariableType=exu.OutputVariableType.Coordinates))
        for k in range(n + 1)
    ]  # fmt: skip
    mbs.Assemble()
    settings = _settings(exu, h, t_end)
    start = CLOCK()
    try:
        mbs.SolveDynamic(settings, solverType=getattr(exu.DynamicSolverType, solver))
    except Exception:  # Exudyn reports a failed run (Newton not converging) by raising
        return {"wall": CLOCK() - start, "error": math.inf, "branch": False, "failed": True}
    wall = CLOCK() - start
    data = mbs.GetSensorStoredData(tip)
    branch = exact.n_four_bar_branch(n, t_end)
    x, y, _, _ = branch.tip(np.clip(data[:, 0], 0.0, t_end))
    error = float(np.max(np.hypot(data[:, 1] - x, data[:, 2] - y)))
    phis = np.column_stack([mbs.GetSensorStoredData(s)[:, 3] for s in angles])
    spread = float(np.max(np.ptp(phis, axis=1)))
    return {"wall": wall, "error": error, "branch": spread < BRANCH_TOL, "spread": spread}


def exudyn_andrews(h: float, solver: str) -> dict[str, Any]:
    """Andrews' squeezer in Exudyn, built from the same description: a RigidBody2D per
    body (its node at the centre of mass, turned by the body's angle), RevoluteJoint2D
    pins, a spring-damper from C to D and the torque on body 1. Its error is the test
    set's: 10^-scd, the worst relative error of the seven angles at t = 0.03."""
    import exudyn as exu
    from exudyn.itemInterface import (
        MarkerBodyPosition,
        MarkerBodyRigid,
        NodeRigidBody2D,
        ObjectConnectorSpringDamper,
        ObjectGround,
        RevoluteJoint2D,
        RigidBody2D,
        SensorNode,
        Torque,
    )

    from linkwork.reference import ReferenceModel

    b = benchmarks.andrews_squeezer()
    ref = ReferenceModel(b.mechanism)
    q = ref.q_start()
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    bodies: dict[str, tuple[int, np.ndarray]] = {}
    sensors = []
    for k, name in enumerate(ref.body_names):
        mp = ref.mass_properties[name]
        x, y, th = q[3 * k : 3 * k + 3]
        c, s = math.cos(th), math.sin(th)
        com = np.array([x, y]) + np.array([[c, -s], [s, c]]) @ mp.u_c
        node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[com[0], com[1], th]))
        body = mbs.AddObject(RigidBody2D(nodeNumber=node, mass=mp.mass, inertia=mp.inertia))
        bodies[name] = (body, mp.u_c)
        kind = exu.OutputVariableType.Coordinates  # displacements from the reference coordinates
        sensor = SensorNode(nodeNumber=node, storeInternal=True, outputVariableType=kind)
        sensors.append(mbs.AddSensor(sensor))

    def marker(name: str, u: np.ndarray) -> int:
        if name == "ground":
            return mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[u[0], u[1], 0.0]))
        body, u_c = bodies[name]
        d = u - u_c  # from the centre of mass, in the body's axes
        return mbs.AddMarker(MarkerBodyPosition(bodyNumber=body, localPosition=[d[0], d[1], 0.0]))

    for joint in ref.constraints:
        mbs.AddObject(RevoluteJoint2D(markerNumbers=[marker(joint.a, joint.ua), marker(joint.b, joint.ub)]))
    for load in ref.loads:
        if load.kind == "spring":
            assert load.u_a is not None and load.u_b is not None
            mbs.AddObject(ObjectConnectorSpringDamper(
                markerNumbers=[marker(load.a, load.u_a), marker(load.b, load.u_b)],
                referenceLength=load.free_length, stiffness=load.stiffness, damping=0.0))  # fmt: skip
        else:
            rigid = mbs.AddMarker(MarkerBodyRigid(bodyNumber=bodies[load.b][0], localPosition=[0, 0, 0]))
            mbs.AddLoad(Torque(markerNumber=rigid, loadVector=[0, 0, exact.ANDREWS["mom"]]))
    mbs.Assemble()
    settings = _settings(exu, h, exact.ANDREWS_T_END)
    settings.solution.sensors.writePeriod = exact.ANDREWS_T_END / 3
    start = CLOCK()
    try:
        mbs.SolveDynamic(settings, solverType=getattr(exu.DynamicSolverType, solver))
    except Exception:  # Exudyn reports a failed run (Newton not converging) by raising
        return {"wall": CLOCK() - start, "error": math.inf, "branch": False, "failed": True}
    wall = CLOCK() - start
    theta = q[2::3] + np.array([mbs.GetSensorStoredData(sensor)[-1, 3] for sensor in sensors])
    angles = benchmarks.andrews_angles(np.column_stack([np.zeros(7), np.zeros(7), theta]).ravel())
    return {"wall": wall, "error": 10.0 ** -exact.scd(angles), "branch": True}


def reference_row(problem: str, rtol: float, t_end: float = T_END) -> dict[str, Any]:
    """The NumPy reference (index 1, DOP853, projection every 0.1 s)."""
    times = np.linspace(0.0, t_end, int(round(t_end / 0.1)) + 1)
    if problem == "andrews":
        b = benchmarks.andrews_squeezer()
        times = np.linspace(0.0, exact.ANDREWS_T_END, 4)
        run = reference_simulate(b.mechanism, times, rtol=rtol, atol=rtol * 1e-2)
        angles = benchmarks.andrews_angles(run["q"][-1])
        return {"wall": run["wall"], "error": 10.0 ** -exact.scd(angles), "branch": True}
    if problem == "A01":
        b = benchmarks.pendulum()
        run = reference_simulate(b.mechanism, times, qd0=b.qd0, rtol=rtol, atol=rtol)
        x, y = exact.pendulum_tip(times)
        ok = True
    else:
        b = benchmarks.n_four_bar(2)
        run = reference_simulate(b.mechanism, times, qd0=b.qd0, rtol=rtol, atol=rtol, singular_tol=1e-6)
        x, y, _, _ = exact.n_four_bar_branch(2, t_end).tip(times)
        ok = float(np.max(np.ptp(run["q"][:, 2::3][:, :3], axis=1))) < BRANCH_TOL
    q = run["q"]
    xs, ys = q[:, 0] + np.cos(q[:, 2]), q[:, 1] + np.sin(q[:, 2])
    return {"wall": run["wall"], "error": float(np.max(np.hypot(xs - x, ys - y))), "branch": ok}


def engine_row(problem: str, rtol: float, t_end: float = T_END) -> dict[str, Any]:
    """The engine's ``Model.simulate`` (measured only where it exists): the model compiled
    with its free coordinates, started from the benchmark's initial velocities."""
    makers = {"A01": benchmarks.pendulum, "A02": lambda: benchmarks.n_four_bar(2)}
    b = makers.get(problem, benchmarks.andrews_squeezer)()
    model = b.mechanism.compile(free=True)
    if problem == "andrews":
        t_end = exact.ANDREWS_T_END
    times = np.arange(0.0, t_end + 0.5 * SAMPLE, SAMPLE)
    start = CLOCK()
    res = model.simulate(times, rtol=rtol, atol=rtol, qd0=b.qd0)
    wall = CLOCK() - start
    q = np.asarray(res.q)
    if problem == "andrews":
        return {"wall": wall, "error": 10.0 ** -exact.scd(benchmarks.andrews_angles(q[-1])), "branch": True}
    xs, ys = q[:, 0] + np.cos(q[:, 2]), q[:, 1] + np.sin(q[:, 2])
    if problem == "A01":
        x, y = exact.pendulum_tip(times)
        ok = True
    else:
        x, y, _, _ = exact.n_four_bar_branch(2, t_end).tip(times)
        ok = float(np.max(np.ptp(q[:, 2::3][:, :3], axis=1))) < BRANCH_TOL
    return {"wall": wall, "error": float(np.max(np.hypot(xs - x, ys - y))), "branch": ok}


def time_at_error(rows: list[dict[str, Any]], error: float) -> float | None:
    """The wall time of the cheapest run of a ladder on the branch whose error is at or
    below ``error``; None if none reaches it."""
    walls = [r["wall"] for r in rows if r["branch"] and r["error"] <= error]
    return min(walls) if walls else None


def best_of(repeat: int, run: Callable[[], dict[str, Any]]) -> dict[str, Any]:
    """The run with the least wall time of ``repeat`` (the same numbers each time)."""
    return min((run() for _ in range(max(repeat, 1))), key=lambda r: r["wall"])


def table(
    title: str,
    column: str,
    ladder: list[Any],
    rows: list[dict[str, Any]],
    extra: str = "",
    error: str = "max error (m)",
) -> list[str]:
    out = [
        f"#### {title}",
        "",
        f"| {column} | {'CPU' if CLOCK is time.process_time else 'wall'} (s) | {error} | on branch |{extra}",
        "|---|---|---|---|",
    ]
    if extra:
        out[-1] += "---|"
    for step, r in zip(ladder, rows):
        branch = "failed" if r.get("failed") else ("yes" if r["branch"] else "no")
        line = f"| {step:g} | {r['wall']:.4f} | {r['error']:.3e} | {branch} |"
        if extra:
            line += f" {r.get('ratio', '')} |"
        out.append(line)
    return out + [""]


ANDREWS_STEPS = [1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6, 1e-6]
TITLES = {
    "A01": f"A01, {T_END:g} s",
    "A02": f"A02 (N = 2), {T_END:g} s",
    "andrews": "Andrews' squeezer, 0.03 s",
}


def run(
    problems: list[str],
    steps: list[float],
    rtols: list[float],
    with_reference: bool,
    repeat: int = 1,
    solvers: tuple[str, ...] = SOLVERS,
) -> str:
    peers: dict[str, Callable[..., dict[str, Any]]] = {
        "A01": exudyn_pendulum,
        "A02": exudyn_n_four_bar,
        "andrews": exudyn_andrews,
    }
    lines: list[str] = []
    has_engine = hasattr(Model, "simulate")
    for problem in problems:
        lines += [f"### {TITLES[problem]}", ""]
        ladder = ANDREWS_STEPS if problem == "andrews" else steps
        error = "worst relative angle error (10^-scd)" if problem == "andrews" else "max error (m)"
        engine = [best_of(repeat, partial(engine_row, problem, r)) for r in rtols] if has_engine else []
        for solver in solvers:
            rows = [best_of(repeat, partial(peers[problem], h, solver)) for h in ladder]
            for r in rows:
                t_engine = time_at_error(engine, r["error"]) if has_engine else None
                r["ratio"] = "" if t_engine is None else f"{r['wall'] / t_engine:.1f}x"
            extra = " linkwork faster by |" if has_engine else ""
            lines += table(f"Exudyn {solver}", "step (s)", ladder, rows, extra, error)
        if has_engine:
            lines += table("linkwork Model.simulate", "rtol", rtols, engine, error=error)
        else:
            lines += ["linkwork: `Model.simulate` does not exist in this build; not measured.", ""]
        if with_reference:
            rows = [reference_row(problem, r) for r in rtols]
            lines += table("NumPy reference (accuracy, not speed)", "rtol", rtols, rows, error=error)
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--write", action="store_true", help="add the run to benches/results/dynamics-<day>.md"
    )
    parser.add_argument("--problems", nargs="+", default=["A01", "A02", "andrews"], choices=sorted(TITLES))
    parser.add_argument("--steps", nargs="+", type=float, default=STEPS)
    parser.add_argument("--rtols", nargs="+", type=float, default=RTOLS)
    parser.add_argument("--repeat", type=int, default=1, help="runs of each row, the fastest kept")
    parser.add_argument("--cpu", action="store_true", help="time runs in CPU time, not wall time")
    parser.add_argument("--solvers", nargs="+", default=list(SOLVERS), choices=SOLVERS)
    parser.add_argument("--reference", action="store_true", help="also run the NumPy reference")
    args = parser.parse_args()
    if args.cpu:
        global CLOCK
        CLOCK = time.process_time
    import exudyn

    now = datetime.datetime.now(datetime.timezone.utc)
    stamp = now.strftime("%Y-%m-%d %H:%M UTC")
    head = [
        f"## Forward dynamics against Exudyn, {stamp}",
        "",
        f"`python benches/dynamics_peers.py {' '.join(a for a in __import__('sys').argv[1:])}`".rstrip(),
        f"Exudyn {exudyn.__version__}, Python {platform.python_version()}, {platform.machine()}; "
        f"errors against the exact solutions sampled every {SAMPLE:g} s.",
        "",
    ]
    load_before = os.getloadavg()
    body = run(args.problems, args.steps, args.rtols, args.reference, args.repeat, tuple(args.solvers))
    load_after = os.getloadavg()
    before, after = (", ".join(f"{a:.2f}" for a in load) for load in (load_before, load_after))
    head.insert(-1, f"Load average (1, 5, 15 min): {before} before, {after} after.")
    report = "\n".join(head) + body
    print(report)
    if args.write:
        path = RESULTS / f"dynamics-{stamp[:10]}.md"
        if not path.exists():
            path.write_text(
                f"# Forward-dynamics runs of {stamp[:10]}\n\nEach section is one run, as measured then.\n"
            )
        with path.open("a") as f:
            f.write("\n" + report + "\n")


if __name__ == "__main__":
    main()

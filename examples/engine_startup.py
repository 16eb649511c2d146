"""A single-cylinder engine with a flywheel, spun up from rest by its starter motor: a
slider-crank whose piston carries the gas force of the air trapped in the cylinder (a
table of the piston's slide, compressed and expanded along p V^1.3 = constant: the
engine is motored, not fired), against friction at the main bearing and the piston.
The crank's speed rises towards the speed where the starter's torque meets the
friction, rippled by the compression strokes; the energy balance counts the starter's
and the friction's work. Builds the model, checks that examples/dynamics/
engine_startup.toml holds the same description, simulates 3 s and prints the numbers.

    python examples/engine_startup.py [output folder]
    linkwork simulate examples/dynamics/engine_startup.toml --t1 3 --steps 601

Parameters: crank 0.03 m with a flywheel of 0.3 kg m^2, rod 0.12 m of 0.4 kg, piston
0.3 kg, bore 0.05 m, compression ratio 8 from 1 bar; starter 60 N m at stall, 40 rad/s
without load; friction 0.05 N m s and 0.5 N m (smoothed over 0.5 rad/s) at the main
bearing, 2 N s/m and 20 N (over 0.05 m/s) at the piston; gravity 9.81 m/s^2.
"""

import math
import sys
from pathlib import Path

import numpy as np

import linkwork as lw

R, L, BORE, RATIO, P0, N = 0.03, 0.12, 0.05, 8.0, 1.0e5, 1.3
J_FLYWHEEL, STALL, NO_LOAD = 0.3, 60.0, 40.0


def gas_force_table(x_start: float, points: int = 33) -> tuple[list[float], list[float]]:
    """The gas force along the cylinder's axis (+x, towards the head) against the
    piston's slide from x_start: -(p - p0) A, p = p0 (V_bdc / V)^1.3 of the volume
    V = A (clearance + x_tdc - x), over the stroke and 1 mm beyond each end."""
    area = math.pi * BORE**2 / 4.0
    clearance = 2.0 * R / (RATIO - 1.0)
    x_tdc = R + L
    xs = np.linspace(L - R - 1e-3, L + R + 1e-3, points)
    pressure = P0 * ((clearance + 2.0 * R) / (clearance + x_tdc - xs)) ** N
    return [float(v) for v in xs - x_start], [float(v) for v in -(pressure - P0) * area]


def engine() -> lw.Mechanism:
    """The engine drawn with the crank at 90 degrees, at rest."""
    theta = math.pi / 2.0
    pin = (R * math.cos(theta), R * math.sin(theta))
    x_piston = pin[0] + math.sqrt(L**2 - pin[1] ** 2)
    phi = math.atan2(-pin[1], x_piston - pin[0])
    m = lw.Mechanism("engine start-up")
    m.set_gravity((0.0, -9.81))
    crank = m.body("crank", angle=theta, mass=5.0, inertia=J_FLYWHEEL)
    mid = ((pin[0] + x_piston) / 2.0, pin[1] / 2.0)
    rod = m.body("rod", origin=pin, angle=phi, mass=0.4, inertia=0.4 * L**2 / 12.0, com=mid)
    piston = m.body("piston", origin=(x_piston, 0.0), mass=0.3, inertia=1e-4)
    m.revolute(m.ground, crank, at=(0.0, 0.0), name="main")
    m.revolute(crank, rod, at=pin, name="crankpin")
    m.revolute(rod, piston, at=(x_piston, 0.0), name="wristpin")
    m.prismatic(m.ground, piston, at=(x_piston, 0.0), axis=(1.0, 0.0), name="cylinder")
    slide, force = gas_force_table(x_piston)
    m.joint_force("cylinder", lw.Spline(slide, force), name="gas")
    m.motor("main", stall=STALL, no_load_speed=NO_LOAD, name="starter")
    m.friction("main", viscous=0.05, coulomb=0.5, smoothing=0.5, name="bearing")
    m.friction("cylinder", viscous=2.0, coulomb=20.0, smoothing=0.05, name="rings")
    m.free = True
    return m


if __name__ == "__main__":
    here = Path(__file__).resolve().parent
    built = engine()
    filed = lw.Mechanism.load(here / "dynamics" / "engine_startup.toml")
    assert filed.to_dict() == lw.Mechanism.from_dict(built.to_dict()).to_dict(), "the model file is stale"
    model = filed.compile()
    times = np.linspace(0.0, 3.0, 601)
    sim = model.simulate(times, rtol=1e-9, atol=1e-9)
    w = sim.qd[:, model.columns.index("crank.theta")]
    turns = (sim.q[:, model.columns.index("crank.theta")] - sim.q[0, model.columns.index("crank.theta")]) / (
        2 * math.pi
    )
    last = times >= times[-1] - 2 * math.pi / w[-1]  # the last revolution
    mean = float(np.mean(w[last]))
    energy = sim.energy()
    scale = float(np.max(np.abs(energy.kinetic)))
    print(f"{model!r}: {sim.n_steps_taken} steps, {sim.n_evaluations} evaluations")
    print(f"after {times[-1]:g} s: {turns[-1]:.2f} turns, crank at {w[-1]:.3f} rad/s")
    print(f"last revolution: mean {mean:.3f} rad/s, ripple (max - min) / mean {np.ptp(w[last]) / mean:.4f}")
    print(f"t to 90% of that mean: {times[np.argmax(w >= 0.9 * mean)]:.3f} s")
    print(f"work of starter, friction and gas {energy.work[-1]:.3f} J, kinetic {energy.kinetic[-1]:.3f} J")
    print(f"energy balance within {np.max(np.abs(energy.balance)):.2e} J of {scale:.1f} J")
    # the starter keeps the crank below its no-load speed; friction keeps it below the speed
    # where the starter meets the bearing's viscous friction alone; the balance closes
    assert 0.0 < mean < STALL / (STALL / NO_LOAD + 0.05)
    assert np.max(np.abs(energy.balance)) < 1e-6 * scale
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
    out.mkdir(parents=True, exist_ok=True)
    sim.to_csv(str(out / "engine_startup.csv"))

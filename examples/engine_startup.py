"""A single-cylinder four-stroke engine with a flywheel, cranked from rest by its starter
until it fires and runs: a slider-crank whose piston carries the gas force of the
cylinder's pressure, a table of the crank angle over the 720 degrees of the cycle
(intake, compression, combustion and expansion, exhaust), against friction at the main
bearing and the piston. The starter drives through an overrunning clutch (its motor
curve clipped: no torque beyond its no-load speed); the engine runs up to the speed where
its mean gas torque meets the friction, rippled by the firing strokes; the energy balance
counts the starter's, the gas's and the friction's work. Builds the model, checks that
examples/dynamics/engine_startup.toml holds the same description, simulates 3 s and
prints the numbers.

    python examples/engine_startup.py [output folder]
    linkwork simulate examples/dynamics/engine_startup.toml --t1 3 --steps 601

Parameters: crank 0.03 m with a flywheel of 0.2 kg m^2, rod 0.12 m of 0.4 kg, piston
0.3 kg, bore 0.05 m, compression ratio 8 from 1 bar, p V^1.3 constant, combustion
raising the pressure to 3.5 times the compression curve's (a Wiebe burn from 10 degrees
before top dead centre over 60 degrees), the exhaust valve opening 50 degrees before
bottom dead centre; starter 60 N m at stall, 40 rad/s without load; friction 0.1 N m s
and 0.5 N m (smoothed over 0.5 rad/s) at the main bearing, 2 N s/m and 20 N (over
0.05 m/s) at the piston; gravity 9.81 m/s^2.
"""

import math
import sys
from pathlib import Path

import numpy as np

import linkwork as lw

R, L, BORE, RATIO, P0, N = 0.03, 0.12, 0.05, 8.0, 1.0e5, 1.3
FIRE, BURN_START, BURN, EXHAUST = 3.5, math.radians(-10.0), math.radians(60.0), math.radians(50.0)
J_FLYWHEEL, STALL, NO_LOAD = 0.2, 60.0, 40.0


def gas_force(phi: np.ndarray) -> np.ndarray:
    """The gas force on the piston along the cylinder's axis (+x, towards the head),
    -(p - p0) A, at crank angles phi in [0, 4 pi]: top dead centre at 0, 2 pi (firing)
    and 4 pi. Intake and exhaust at p0; between them p0 (V_bdc / V)^1.3 of the volume
    V = A (clearance + x_tdc - x), raised by the fraction burnt, and let down to p0 by
    the exhaust valve over the last EXHAUST of the expansion."""
    area = math.pi * BORE**2 / 4.0
    clearance = 2.0 * R / (RATIO - 1.0)
    x = R * np.cos(phi) + np.sqrt(L**2 - (R * np.sin(phi)) ** 2)
    compressed = P0 * ((clearance + 2.0 * R) / (clearance + R + L - x)) ** N
    burnt = 1.0 - np.exp(-5.0 * (np.clip(phi - 2 * math.pi - BURN_START, 0.0, None) / BURN) ** 3)
    valve = np.clip((3 * math.pi - phi) / EXHAUST, 0.0, 1.0)
    closed = (phi > math.pi) & (phi < 3 * math.pi)
    pressure = np.where(closed, P0 + (compressed * (1.0 + (FIRE - 1.0) * burnt) - P0) * valve, P0)
    return (P0 - pressure) * area


def gas_force_law(step_deg: float = 10.0) -> lw.Periodic:
    """`gas_force` tabulated every step_deg of crank angle, repeated every 720 degrees."""
    phi = np.radians(np.arange(0.0, 720.0 + step_deg / 2, step_deg))
    table = lw.Spline([float(v) for v in phi], [float(v) for v in gas_force(phi)])
    return lw.Periodic(table, period=4 * math.pi)


def engine() -> lw.Mechanism:
    """The engine drawn with the crank at 90 degrees (the middle of the intake stroke),
    at rest."""
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
    m.joint_force("cylinder", gas_force_law(), of_joint="main", name="gas")
    m.motor("main", stall=STALL, no_load_speed=NO_LOAD, clip=True, name="starter")
    m.friction("main", viscous=0.1, coulomb=0.5, smoothing=0.5, name="bearing")
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
    crank = model.columns.index("crank.theta")
    angle, w = sim.q[:, crank], sim.qd[:, crank]
    last = angle >= angle[-1] - 4 * math.pi  # the last cycle: two turns
    mean = float(np.mean(w[last]))
    energy = sim.energy()
    scale = float(np.max(np.abs(energy.kinetic)))
    # the gas's work over a cycle from the table: the integral of f dx over 720 degrees
    phi = np.linspace(0.0, 4 * math.pi, 14401)
    slide = R * np.cos(phi) + np.sqrt(L**2 - (R * np.sin(phi)) ** 2)
    cycle_work = float(np.trapezoid(gas_force(phi) * np.gradient(slide, phi), phi))
    turns = (angle[-1] - angle[0]) / (2 * math.pi)
    print(
        f"{model!r}: {sim.n_steps_taken} steps ({sim.n_rejected} rejected), {sim.n_evaluations} evaluations"
    )
    print(f"gas work per cycle {cycle_work:.2f} J: a mean torque of {cycle_work / (4 * math.pi):.3f} N m")
    print(f"first firing (crank at 360 deg) at t = {times[np.argmax(angle >= 2 * math.pi)]:.3f} s")
    print(
        f"past the starter's no-load speed (its clutch lets go) at t = {times[np.argmax(w > NO_LOAD)]:.3f} s"
    )
    print(f"after {times[-1]:g} s: {turns:.2f} turns, crank at {w[-1]:.3f} rad/s")
    print(f"last cycle: mean {mean:.3f} rad/s, ripple (max - min) / mean {np.ptp(w[last]) / mean:.4f}")
    print(f"work of starter, gas and friction {energy.work[-1]:.3f} J, kinetic {energy.kinetic[-1]:.3f} J")
    print(f"energy balance within {np.max(np.abs(energy.balance)):.2e} J of {scale:.1f} J")
    # the engine runs on its own, beyond the starter's reach; the balance closes
    assert mean > NO_LOAD and cycle_work > 0.0
    assert np.max(np.abs(energy.balance)) < 1e-6 * scale
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
    out.mkdir(parents=True, exist_ok=True)
    sim.to_csv(str(out / "engine_startup.csv"))

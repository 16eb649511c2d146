"""Watt II and Stephenson III six-bars from their model files: positions, velocities,
accelerations and the crank torque (masses, gravity) over a crank revolution, engine
against the independent NumPy reference (linkwork.reference).

    python examples/six_bars.py [output folder]

Parameters: four-bar crank 0.10 m, coupler 0.35 m, rocker 0.30 m, O2O4 0.35 m; link5
0.25 m, output 0.15 m; O6 = (0.15, 0.45) m (Watt II) or (0.20, -0.15) m (Stephenson
III); masses in kg, inertias in kg m^2 in the files, gravity 9.81 m/s^2; the crank at 5
rad/s.
"""

import math
import sys
from pathlib import Path

import numpy as np

import linkwork as lw
from linkwork.reference import ReferenceModel

here = Path(__file__).resolve().parent
out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)
times = np.linspace(0.0, 2 * math.pi / 5.0, 181)  # one crank turn, every 2 degrees


def rel(got: np.ndarray, want: np.ndarray) -> float:
    """Worst error over the turn, relative to each column's largest magnitude."""
    return float((np.abs(got - want).max(axis=0) / np.maximum(np.abs(want).max(axis=0), 1e-300)).max())


for kind in ("watt", "stephenson"):
    mech = lw.Mechanism.load(here / f"six_bar_{kind}.toml")
    res = mech.compile().sweep(times, forces=True)  # masses, gravity: efforts and reactions too
    ref = ReferenceModel(mech).sweep_forces(times)
    errs = {key: rel(getattr(res, key), ref[key]) for key in ("q", "qd", "qdd")}
    torque = res.effort("crank_angle")
    errs["torque"] = rel(torque, ref["efforts"]["crank_angle"])
    output = res.body("output").theta
    print(f"{mech.name}: output swings {math.degrees(output.max() - output.min()):.2f} deg; ", end="")
    print(f"crank torque {torque.min():+.3f} .. {torque.max():+.3f} N m")
    print("  engine vs reference: " + ", ".join(f"{k} {v:.1e}" for k, v in errs.items()))
    assert max(errs.values()) < 1e-10, errs
    energy = res.energy()  # driver power = rate of kinetic + potential energy
    balance, power = np.abs(energy.balance).max(), np.abs(energy.driver_power).max()
    print(f"  energy balance {balance:.1e} W of a peak crank power {power:.2f} W")
    res.plot_forces(str(out / f"six_bar_{kind}_forces.png"), every=2)
print(f"wrote {out / 'six_bar_watt_forces.png'}, {out / 'six_bar_stephenson_forces.png'}")

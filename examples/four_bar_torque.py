"""The torque that drives a steel four-bar under gravity: sweep one crank revolution with
forces, print the peak crank torque and its parts (inertia, gravity), the peak pin forces
and the energy balance, and plot the torque over the cycle.

    python examples/four_bar_torque.py [output folder]

Parameters: the four-bar of four_bar (m) in steel bars 30 mm x 8 mm (7850 kg/m^3: 1.884
kg/m, uniform slender rods), the crank at 60 rpm (2 pi rad/s), gravity 9.81 m/s^2.
"""

import math
import sys
from pathlib import Path

import numpy as np

import linkwork as lw
from linkwork import closed_form

out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)

# a Grashof crank-rocker: ground 0.35, crank 0.20, coupler 0.35, rocker 0.25 m, drawn at
# crank angle 0; links cut from 30 x 8 mm steel flat bar (7850 kg/m^3: 1.88 kg/m), each a
# uniform slender rod (centre of mass at its middle, inertia m L^2 / 12)
ground, crank_len, coupler_len, rocker_len = 0.35, 0.20, 0.35, 0.25
kg_per_m = 7850.0 * 0.030 * 0.008
rpm = 60.0
omega = rpm * 2.0 * math.pi / 60.0

cf0 = closed_form.four_bar(ground, crank_len, coupler_len, rocker_len, theta2=0.0, omega2=0.0)
A = (crank_len, 0.0)
B = (A[0] + coupler_len * math.cos(cf0["theta3"]), A[1] + coupler_len * math.sin(cf0["theta3"]))

m = lw.Mechanism("steel four-bar at 60 rpm")
crank = m.link("crank", (0.0, 0.0), A, mass=kg_per_m * crank_len)
coupler = m.link("coupler", A, B, mass=kg_per_m * coupler_len)
rocker = m.link("rocker", (ground, 0.0), B, mass=kg_per_m * rocker_len)
m.revolute(m.ground, crank, at=(0.0, 0.0), name="O2")
m.revolute(crank, coupler, at=A, name="A")
m.revolute(coupler, rocker, at=B, name="B")
m.revolute(m.ground, rocker, at=(ground, 0.0), name="O4")
m.drive_angle(crank, lw.Linear(0.0, omega), name="crank_angle")
m.set_gravity((0.0, -9.81))

times = np.linspace(0.0, 2.0 * math.pi / omega, 3601)
res = m.compile().sweep(times, forces=True)

torque = res.effort("crank_angle")
parts = res.effort_parts("crank_angle")
k = int(np.argmax(np.abs(torque)))
print(f"{res.model.name}: {len(res)} steps over one revolution ({times[-1]:.3f} s)")
angle = math.degrees(res.body("crank").theta[k])
print(
    f"peak crank torque {torque[k]:+.3f} N m at crank angle {angle:.1f} deg"
    f" = inertia {parts['inertia'][k]:+.3f} + gravity {parts['gravity'][k]:+.3f} N m"
)
for part, value in parts.items():
    print(f"  largest {part:<8} part {np.abs(value).max():8.3f} N m")
# the samples of one period without its repeated end: the mean of a periodic function
print(f"mean crank torque over the cycle {torque[:-1].mean():+.1e} N m (no losses: zero net work)")
for joint in ("O2", "A", "B", "O4"):
    force = np.linalg.norm(res.reaction(joint).force, axis=1)
    print(f"peak force at pin {joint:<2} {force.max():7.2f} N")

e = res.energy()
largest = max(np.abs(p).max() for p in (e.driver_power, e.kinetic_rate, e.gravity_rate))
balance = np.abs(e.balance).max() / largest
print(f"energy balance: driver power = dT/dt + dV/dt to {balance:.1e} of the largest power ({largest:.2f} W)")
assert balance < 1e-9

path = out / "four_bar_torque.png"
res.plot_forces(str(path), every=5)
print(f"wrote {path}")

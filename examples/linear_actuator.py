"""A boom luffed by a hydraulic cylinder (a distance driver) from its model file: the
boom's angle against the triangle heel-base-rod end (law of cosines), and the force that
holds the boom at rest (`model.statics`) against the moment balance about the heel.

    python examples/linear_actuator.py [output folder]

Parameters: boom of 50 kg from its heel (0, 0) to its tip (2.0, 0.4) m; cylinder from
(0.6, -0.5) m to the boom's (1.0, 0.2) m, extending 0.1 (1 - cos t) m from 0.806226 m;
gravity 9.81 m/s^2.
"""

import math
import sys
from pathlib import Path

import numpy as np

import linkwork as lw
from linkwork.view import figures

here = Path(__file__).resolve().parent
out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)
base, rod_end, com, mass, g = np.array([0.6, -0.5]), np.array([1.0, 0.2]), np.array([1.0, 0.2]), 50.0, 9.81

model = lw.Mechanism.load(here / "linear_actuator.toml").compile()
times = np.linspace(0.0, 2 * math.pi, 629)
res = model.sweep(times)
length = np.linalg.norm(rod_end - base) + 0.1 * (1 - np.cos(times))  # the cylinder's law
a, b = np.linalg.norm(rod_end), np.linalg.norm(base)  # heel to rod end, heel to base
# the angle base-heel-rod end grows with the cylinder's length; the boom turns as much
opening = np.arccos((a**2 + b**2 - length**2) / (2 * a * b))
theta = res.body("boom").theta
err = np.abs((theta - theta[0]) - (opening - opening[0])).max()
low, high = np.degrees(theta.min()), np.degrees(theta.max())
print(f"boom angle {low:.3f} .. {high:.3f} deg; vs closed form {err:.1e} rad")
assert err < 1e-12

worst = 0.0
for t in (0.0, 1.0, 2.0, math.pi):
    held = model.statics(t)  # the efforts that hold this configuration at rest
    turn = held.body("boom").theta - theta[0]
    rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    r_rod, r_com = rot @ rod_end, rot @ com
    line = (r_rod - base) / np.linalg.norm(r_rod - base)
    force = (
        mass * g * r_com[0] / abs(r_rod[0] * line[1] - r_rod[1] * line[0])
    )  # moment of gravity / lever arm
    worst = max(worst, abs(abs(held.effort("cylinder")) / force - 1))
    print(
        f"t = {t:.3f} s: cylinder holds {abs(held.effort('cylinder')):.3f} N (moment balance {force:.3f} N)"
    )
print(f"static force vs moment balance: {worst:.1e} relative")
assert worst < 1e-12
figures.plot_paths(res, str(out / "linear_actuator_paths.png"))
print(f"wrote {out / 'linear_actuator_paths.png'}")

"""A crank-rocker four-bar built by hand: sweep one revolution, print the summary, compare
with the closed form, and draw the coupler curve.

    python examples/four_bar.py [output folder]

Parameters: ground 0.35 m, crank 0.20 m, coupler 0.35 m, rocker 0.25 m (its model file:
the same in mm); the crank at 5 rad/s (286.48 deg/s in the file) from 0 rad; coupler
point P at the coupler's middle.
"""

import math
import sys
from pathlib import Path

import numpy as np

import linkwork as lw
from linkwork import closed_form

out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)

# ground 0.35, crank 0.20, coupler 0.35, rocker 0.25 m, drawn at crank angle 0
m = lw.Mechanism("four-bar")
cf0 = closed_form.four_bar(0.35, 0.20, 0.35, 0.25, theta2=0.0, omega2=0.0)
a = (0.20, 0.0)
b = (a[0] + 0.35 * math.cos(cf0["theta3"]), a[1] + 0.35 * math.sin(cf0["theta3"]))
crank = m.link("crank", (0.0, 0.0), a)
coupler = m.link("coupler", a, b)
rocker = m.link("rocker", (0.35, 0.0), b)
m.revolute(m.ground, crank, at=(0.0, 0.0), name="O2")
m.revolute(crank, coupler, at=a, name="A")
m.revolute(coupler, rocker, at=b, name="B")
m.revolute(rocker, m.ground, at=(0.35, 0.0), name="O4")
m.drive_angle(crank, lw.Linear(0.0, 5.0), name="crank_angle")
m.point("P", coupler, ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2 + 0.1))

model = m.compile()
times = np.linspace(0.0, 2 * math.pi / 5.0, 20_001)
res = model.sweep(times)
print(res.summary())

cf = closed_form.four_bar(0.35, 0.20, 0.35, 0.25, theta2=5.0 * times, omega2=5.0)
err = np.abs(res.body("rocker").thetadd - cf["alpha4"]).max() / np.abs(cf["alpha4"]).max()
print(f"rocker angular acceleration vs closed form: {err:.1e} relative")
assert err < 1e-10

res.plot(str(out / "four_bar_example.png"), every=10)
print(f"wrote {out / 'four_bar_example.png'}")

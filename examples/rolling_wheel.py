"""A wheel rolling on the ground from its model file (linear couplings, a coordinate
driver): the valve's path, velocity and acceleration against the cycloid's closed form.

    python examples/rolling_wheel.py [output folder]

With the hub at x(t), the wheel turns by -x / R and the valve, at the bottom at the start,
is at (x - R sin(x / R), R (1 - cos(x / R))); its velocity x' (1 - cos, sin) and
acceleration x'' (1 - cos, sin) + x'^2 / R (sin, cos).

Parameters: wheel radius 300 mm; the hub pushed along x = 100 t + 200 t^2 mm (file in
mm, deg: the coupling's coefficient 5.236 mm/deg).
"""

import sys
from pathlib import Path

import numpy as np

import linkwork as lw

here = Path(__file__).resolve().parent
out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)
R = 300.0  # mm

model = lw.Mechanism.load(here / "rolling_wheel.toml").compile()
times = np.linspace(0.0, 3.0, 601)
res = model.sweep(times)
valve = res.point("valve")
x, xd, xdd = 100 * times + 200 * times**2, 100 + 400 * times, 400.0 + 0 * times  # the driver's law
s, c = np.sin(x / R), np.cos(x / R)
want = {
    "position": np.stack([x - R * s, R * (1 - c)], 1),
    "velocity": xd[:, None] * np.stack([1 - c, s], 1),
    "acceleration": xdd[:, None] * np.stack([1 - c, s], 1) + (xd**2 / R)[:, None] * np.stack([s, c], 1),
}
for key, value in want.items():
    err = np.abs(getattr(valve, key) - value).max() / np.abs(value).max()
    print(f"valve {key} vs cycloid: {err:.1e} relative")
    assert err < 1e-12
unit = res.units("wheel.x")  # the file's length unit; angles in results are always radians
turned = -np.degrees(res.body("wheel").theta[-1])
height = valve.position[-1, 1]
print(f"hub moved {x[-1]:.0f} {unit}, wheel turned {turned:.3f} deg, valve at height {height:.3f} {unit}")
res.plot(str(out / "rolling_wheel.png"))
print(f"wrote {out / 'rolling_wheel.png'}")

"""A Ferris wheel from its model file: three cars kept level by a fixed_orientation joint,
a parallel joint and a relative-angle driver. Each car only translates, so its seat runs
on a circle of the wheel's radius centred 2 m below the hub (the closed form).

    python examples/ferris_wheel.py [output folder]

Parameters: wheel radius 10 m, one turn a minute (2 pi / 60 rad/s); seats 2 m below
their pins.
"""

import math
import sys
from pathlib import Path

import numpy as np

import linkwork as lw

here = Path(__file__).resolve().parent
out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)
radius, drop, omega = 10.0, 2.0, 2 * math.pi / 60.0  # m, m, rad/s

model = lw.Mechanism.load(here / "ferris_wheel.toml").compile()
times = np.linspace(0.0, 60.0, 361)
res = model.sweep(times)
for k, start in enumerate((90.0, 210.0, 330.0), start=1):
    car, seat = res.body(f"car{k}"), res.point(f"seat{k}")  # a body's and a named point's motion
    phi = math.radians(start) + omega * times
    circle = radius * np.stack([np.cos(phi), np.sin(phi) - drop / radius], 1)
    speed, accel = np.hypot(*seat.velocity.T), np.hypot(*seat.acceleration.T)
    err = max(np.abs(seat.position - circle).max() / radius, np.abs(car.theta).max())
    err = max(err, np.abs(speed / (omega * radius) - 1).max(), np.abs(accel / (omega**2 * radius) - 1).max())
    print(f"car {k}: tilt {np.abs(car.theta).max():.1e} rad; seat vs circle {err:.1e} relative")
    assert err < 1e-12
print(f"every seat: speed {speed.mean():.6f} m/s, acceleration {accel.mean():.6f} m/s^2 (omega R, omega^2 R)")
res.plot(str(out / "ferris_wheel.png"))
print(f"wrote {out / 'ferris_wheel.png'}")

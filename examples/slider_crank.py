"""An offset slider-crank from its model file: slider position, velocity and acceleration
over a revolution against the textbook closed form.

    python examples/slider_crank.py

Parameters: crank 0.10 m, rod 0.35 m, slide line 0.02 m above the crank pivot; the crank
at 5 rad/s from 0 rad.
"""

import math
from pathlib import Path

import numpy as np

import linkwork as lw
from linkwork import closed_form

model = lw.Mechanism.load(Path(__file__).resolve().parent / "slider_crank.toml").compile()
times = np.linspace(0.0, 2 * math.pi / 5.0, 10_001)
res = model.sweep(times)
slider = res.body("slider")
cf = closed_form.slider_crank(0.10, 0.35, 0.02, theta2=5.0 * times, omega2=5.0)
for name, got, want in (("x", slider.x, cf["x"]), ("v", slider.xd, cf["v"]), ("a", slider.xdd, cf["a"])):
    err = np.abs(got - want).max() / np.abs(want).max()
    print(
        f"slider {name}: range {got.min():+.6f} .. {got.max():+.6f}, error vs closed form {err:.1e} relative"
    )
    assert err < 1e-10
print(
    f"stroke {slider.x.max() - slider.x.min():.6f} m; Newton iterations per step {res.iterations.mean():.2f}"
)

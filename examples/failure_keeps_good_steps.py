"""What a failure looks like: a slider-crank whose slider is pulled beyond the reach of
crank + rod. The error names the step and the joint; the good steps are kept.

    python examples/failure_keeps_good_steps.py

Parameters: the slider-crank of slider_crank without offset (crank 0.10 m, rod 0.35 m),
crank from 1 rad, its slider pulled along x at 0.1 m/s.
"""

import numpy as np

import linkwork as lw
from linkwork import examples

m = examples.slider_crank(crank=0.10, rod=0.35, offset=0.0, theta0=1.0)
x0 = m.to_dict()["joints"][2]["at"][0]  # the slider pin B
m.remove("crank_angle")  # drive the slider instead of the crank
m.drive_coordinate("slider", (x0, 0.0), "x", lw.Linear(x0 - 0.1, 0.1), name="pull")
try:
    m.compile().sweep(np.linspace(0.0, 3.0, 301))
except lw.SolveError as e:
    print(f"{type(e).__name__}: {e}")
    good = e.partial
    x = good.body("slider").x[-1]
    print(f"kept {len(good)} good steps, up to t = {good.times[-1]:.2f} s, slider at x = {x:.4f} m")
    print(f"pivot ratio over the last steps: {np.array2string(good.pivot_ratio[-4:], precision=3)}")
else:
    raise SystemExit("expected the sweep to fail beyond the reach of crank + rod")

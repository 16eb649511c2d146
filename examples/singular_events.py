"""What the sweep reports at singular configurations: a parallelogram through its change
points (bifurcations), a non-Grashof four-bar driven onto the limit of its input, and a
slider-crank whose slider stops at its dead centres (locks). Prints the events and draws
docs/analysis_events.png.

    python examples/singular_events.py [output folder]

Parameters: a parallelogram (ground = coupler = 0.3 m, crank = rocker = 0.1 m, crank
from 0.5 rad at 1 rad/s); a non-Grashof four-bar (ground 0.40, crank 0.30, coupler 0.25,
rocker 0.20 m, 1 rad/s); the slider-crank of slider_crank at 1 rad/s.
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import linkwork as lw  # noqa: E402
from linkwork import examples  # noqa: E402

out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)

# a parallelogram: ground = coupler = 0.3 m, crank = rocker = 0.1 m, crank at 0.5 + t rad
th, r1, r2 = 0.5, 0.3, 0.1
a = (r2 * np.cos(th), r2 * np.sin(th))
par = lw.Mechanism("parallelogram")
par.body("crank", (0.0, 0.0), th)
par.body("coupler", a, 0.0)
par.body("rocker", (r1, 0.0), th)
par.revolute("ground", "crank", (0.0, 0.0), name="O2")
par.revolute("crank", "coupler", a, name="A")
par.revolute("coupler", "rocker", (r1 + a[0], a[1]), name="B")
par.revolute("ground", "rocker", (r1, 0.0), name="O4")
par.drive_angle("crank", lw.Linear(th, 1.0), name="crank_angle")
p = par.compile().sweep(np.linspace(0.0, 2 * np.pi, 400))

# non-Grashof: the input can only rock; driving it on stops at its limit
ng = examples.four_bar(ground=0.40, crank=0.30, coupler=0.25, rocker=0.20, omega=1.0).compile()
try:
    ng.sweep(np.linspace(0.0, 2.0, 400))
    raise SystemExit("expected the non-Grashof input to stop at its limit")
except lw.SingularError as e:
    n = e.partial
    print(f"non-Grashof four-bar: {e}")
print(f"  {ng.motion_limits()}")

# the slider's dead centres are locks of the output
sc = examples.slider_crank(omega=1.0).compile().sweep(np.linspace(0.0, 2 * np.pi, 400), locks=True)

for e in p.events + n.events + sc.events:
    print(f"  {e}")

fig, ax = plt.subplots(3, 1, figsize=(7, 8), constrained_layout=True)
ax[0].semilogy(p.q[:, 2], p.pivot_ratio, label="pivot ratio")
for e in p.events:
    ax[0].axvline(e.driver(), color="r", ls="--", lw=1)
ax[0].set(title="parallelogram: change points (bifurcations, red)", xlabel="crank angle [rad]")
ax[0].legend()
ax[1].plot(n.q[:, 2], n.q[:, 8], label="rocker angle")
ax[1].axvline(n.events[-1].driver(), color="r", ls="--", lw=1, label="limit of the input")
ax[1].set(title="non-Grashof four-bar driven onto its limit", xlabel="input angle [rad]", ylabel="rad")
ax[1].legend()
ax[2].plot(sc.times, sc.body("slider").x, label="slider x [m]")
for e in sc.events:
    ax[2].axvline(e.time, color="g", ls="--", lw=1)
ax[2].set(title="slider-crank: the slider locks at its dead centres (green)", xlabel="t [s]")
ax[2].legend()
fig.savefig(out / "analysis_events.png", dpi=110)
print(f"wrote {out / 'analysis_events.png'}")

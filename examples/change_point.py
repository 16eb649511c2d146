"""The promise at a change point: a parallelogram (crank (0, 0)-(0, 0.4), coupler to
(1, 0.4), rocker (1, 0)-(1, 0.4), crank driven from pi/2 at 1 rad/s) swept over half a turn
on grids whose points land exactly on the change point, next to it, and far from it. Every
step stays on the parallelogram (the branch whose velocity is continuous), rates included,
and the change point is reported once. Draws docs/analysis_change_point.png.

    python examples/change_point.py [output folder]

Parameters: a parallelogram: crank and rocker 0.4 m, ground and coupler 1 m; the crank
from pi/2 rad at 1 rad/s.
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import linkwork as lw  # noqa: E402

out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)

m = lw.Mechanism("parallelogram")
crank = m.link("crank", (0, 0), (0, 0.4))
coupler = m.link("coupler", (0, 0.4), (1, 0.4))
rocker = m.link("rocker", (1, 0), (1, 0.4))
m.revolute(m.ground, crank, at=(0, 0))
m.revolute(crank, coupler, at=(0, 0.4))
m.revolute(coupler, rocker, at=(1, 0.4))
m.revolute(rocker, m.ground, at=(1, 0))
m.drive_angle(crank, lw.Linear(np.pi / 2, 1))
model = m.compile()

fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
for n, style in ((1001, "-"), (25, "o"), (8, "s")):
    res = model.sweep(np.linspace(0.0, np.pi, n))
    crank_angle = np.degrees(np.pi / 2 + res.times)
    dev = np.abs(np.angle(np.exp(1j * (res.body("rocker").theta - res.body("crank").theta))))
    rate = np.abs(res.body("rocker").thetad - 1.0)
    label = f"{n} steps" + (" (step 500 on the change point)" if n == 1001 else "")
    axes[0].semilogy(crank_angle, np.maximum(dev, 1e-17), style, ms=4, label=label)
    axes[1].semilogy(crank_angle, np.maximum(rate, 1e-17), style, ms=4, label=label)
    axes[2].semilogy(crank_angle, np.maximum(res.pivot_ratio, 1e-17), style, ms=4, label=label)
    events = [(e.kind, round(float(np.degrees(np.pi / 2 + e.time)), 6)) for e in res.events]
    print(f"{n:5d} steps: |rocker - crank| <= {dev.max():.1e} rad, ", end="")
    print(f"|rocker rate - 1| <= {rate.max():.1e} rad/s, events: {events}")
for ax, title in zip(
    axes,
    (
        "parallelogram: |theta_rocker - theta_crank| [rad]",
        "|omega_rocker - omega_crank| [rad/s]",
        "pivot ratio",
    ),
):
    ax.axvline(180.0, color="0.6", lw=0.8, ls="--")
    ax.set_xlabel("crank angle [deg]; change point at 180 (dashed)")
    ax.set_title(title, fontsize=10)
axes[0].legend(fontsize=8)
fig.tight_layout()
fig.savefig(out / "analysis_change_point.png", dpi=110)
print(f"wrote {out / 'analysis_change_point.png'}")

"""Rack-and-pinion steering from its model file: both wheels' steer angles over the rack's
travel against the closed form of each side (a circle-circle intersection), and the
Ackermann error against the ideal cot(d_outer) - cot(d_inner) = track / wheelbase.

    python examples/steering.py [output folder]

Parameters: pinion pitch radius 8 mm; rack 0.20 m behind the axle, its ends at +-0.25 m;
steering arms 0.15 m angled 10 deg inward; kingpins 1.2 m apart, wheelbase 2.5 m; the
steering wheel 8 sin(pi t) rad; tyre torsion springs in N m/rad.
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
track, wheelbase = 1.2, 2.5  # m, kingpin to kingpin and axle to axle

mech = lw.Mechanism.load(here / "steering.toml")
res = mech.compile().sweep(np.linspace(0.0, 2.0, 401), forces=True)  # the steering wheel, both ways
u = res.body("rack").x - res.body("rack").x[0]  # rack travel
joints = {j["name"]: j for j in mech.to_dict()["joints"]}


def steer_closed_form(side: str) -> np.ndarray:
    """The knuckle's turn from the drawing's geometry: the arm's end E is on the circle of
    the arm about the kingpin K and on the circle of the tie rod about the rack's end R."""
    K, R0, E0 = (np.array(v) for v in (joints[f"kingpin_{side}"]["at"], *(
        joints[f"tie_rod_{side}"][k] for k in ("at_a", "at_b"))))  # fmt: skip
    arm, rod = np.linalg.norm(E0 - K), np.linalg.norm(E0 - R0)
    d = R0 + np.outer(u, (1.0, 0.0)) - K  # kingpin to rack end, per step
    dist = np.linalg.norm(d, axis=1)
    along = (arm**2 - rod**2 + dist**2) / (2 * dist)
    across = np.sqrt(arm**2 - along**2) * np.sign(
        np.linalg.det(np.stack([R0 - K, E0 - K]))
    )  # the drawing's side
    E = (along[:, None] * d + across[:, None] * np.stack([-d[:, 1], d[:, 0]], 1)) / dist[:, None]
    return np.arctan2(E[:, 1], E[:, 0]) - math.atan2(*(E0 - K)[::-1])


steer = {}
for side in ("left", "right"):
    theta = res.body(f"knuckle_{side}").theta
    steer[side] = theta - theta[0]
    err = np.abs(steer[side] - steer_closed_form(side)).max()
    low, high = np.degrees(steer[side].min()), np.degrees(steer[side].max())
    print(f"{side} wheel: steer {low:+.2f} .. {high:+.2f} deg, error vs closed form {err:.1e} rad")
    assert err < 1e-12

inner = np.maximum(np.abs(steer["left"]), np.abs(steer["right"]))  # the inner wheel turns more
outer = np.minimum(np.abs(steer["left"]), np.abs(steer["right"]))
turning = inner > math.radians(1.0)
ideal = np.arctan(1.0 / (1.0 / np.tan(inner[turning]) + track / wheelbase))
error = np.degrees(outer[turning] - ideal)
print(
    f"rack travel +-{np.abs(u).max() * 1000:.1f} mm; at full lock inner {np.degrees(inner.max()):.2f} deg, ",
    end="",
)
print(f"outer {np.degrees(outer.max()):.2f} deg, Ackermann's outer {np.degrees(ideal.max()):.2f} deg")
print(f"Ackermann error (outer - ideal) {error.min():+.2f} .. {error.max():+.2f} deg")
torque = res.effort("steering")  # what the driver holds against the tyres' springs
pull = np.linalg.norm(res.reaction("tie_rod_left").force, axis=1)
print(f"peak steering torque {np.abs(torque).max():.2f} N m, tie rod force {pull.max():.0f} N")
figures.plot_outputs(res, str(out / "steering.png"), ["knuckle_left", "knuckle_right", "rack.x"])
print(f"wrote {out / 'steering.png'}")

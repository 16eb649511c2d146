"""Gear trains from their model files: a compound spur train against the product of its
tooth ratios, and a planetary differential (sun and ring both driven) against Willis'
formula, (w_sun - w_arm) / (w_ring - w_arm) = -r_ring / r_sun.

    python examples/gear_trains.py

Parameters: compound train: pitch radii 20, 60, 25, 50 mm, the input at 360 deg/s (file
in mm, deg); planetary: sun 0.05 m, planet 0.03 m, ring 0.11 m (internal), the sun at 6
rad/s, the ring 0.5 sin(3 t) rad.
"""

import math
from pathlib import Path

import numpy as np

import linkwork as lw

here = Path(__file__).resolve().parent

compound = lw.Mechanism.load(here / "gear_train_compound.toml").compile()
res = compound.sweep(np.linspace(0.0, 1.0, 361))
w_in, w_out = res.body("input").thetad, res.body("output").thetad  # rad/s, whatever the file's unit
ratio, ratio_cf = w_out / w_in, (20.0 / 60.0) * (25.0 / 50.0)
turns = (res.body("output").theta[-1] - res.body("output").theta[0]) / (2 * math.pi)
err = np.abs(ratio / ratio_cf - 1.0).max()
print(f"compound train: speed ratio {ratio.mean():.15f} (closed form 1/6)")
print(f"  the output turns {turns:.12f} times per input turn")
print(f"  error {err:.1e} relative")
assert err < 1e-12 and abs(turns - ratio_cf) < 1e-12

r_sun, r_planet, r_ring = 0.05, 0.03, 0.11  # m, as in the model file
planetary = lw.Mechanism.load(here / "gear_train_planetary.toml").compile()
res = planetary.sweep(np.linspace(0.0, 2 * math.pi / 3.0, 721))  # one period of the ring
w = {b: res.body(b).thetad for b in ("sun", "ring", "arm", "planet")}
a = {b: res.body(b).thetadd for b in ("sun", "ring", "arm", "planet")}
# Willis, solved for the arm: w_arm = (r_sun w_sun + r_ring w_ring) / (r_sun + r_ring)
for name, rate in (("velocity", w), ("acceleration", a)):
    arm = (r_sun * rate["sun"] + r_ring * rate["ring"]) / (r_sun + r_ring)
    planet = rate["arm"] - r_sun / r_planet * (rate["sun"] - rate["arm"])  # relative to the arm
    scale = np.abs(rate["sun"]).max() + np.abs(rate["ring"]).max()
    err = max(np.abs(rate["arm"] - arm).max(), np.abs(rate["planet"] - planet).max()) / scale
    print(f"planetary: arm and planet angular {name} vs Willis: {err:.1e} relative")
    assert err < 1e-12
print(f"  arm speed {w['arm'].min():.4f} .. {w['arm'].max():.4f} rad/s (sun 6 rad/s, ring 1.5 cos 3t)")

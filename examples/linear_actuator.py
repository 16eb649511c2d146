"""A boom luffed by a hydraulic cylinder: a distance driver between a ground point and a
point of the boom, extended harmonically. Prints the boom's angle range and the tip's
largest speed.

    python examples/linear_actuator.py
"""

import math

import numpy as np

import linkwork as lw

m = lw.Mechanism("luffing boom")
boom = m.link("boom", (0.0, 0.0), (2.0, 0.4))
m.revolute(m.ground, boom, at=(0.0, 0.0), name="heel")
base, rod_end = (0.6, -0.5), (1.0, 0.2)
stroke0 = math.dist(base, rod_end)
m.drive_distance(
    m.ground, base, boom, rod_end, lw.Harmonic(stroke0 + 0.1, 0.1, 1.0, -math.pi / 2), name="cylinder"
)
m.point("tip", boom, (2.0, 0.4))

res = m.compile().sweep(np.linspace(0.0, 2 * math.pi, 2001))
theta = np.degrees(res.body("boom").theta)
speed = np.linalg.norm(res.point("tip").velocity, axis=1)
print(f"boom angle {theta.min():.2f} .. {theta.max():.2f} deg; tip speed up to {speed.max():.4f} m/s")
print(f"smallest pivot ratio {res.pivot_ratio.min():.3f}")

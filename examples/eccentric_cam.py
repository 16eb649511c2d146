"""An eccentric cam from its model file with a knife-edge follower and a flat-faced one:
their displacement, velocity and acceleration against the closed forms, and where the
contacts run on the cam (the joints' own coordinates).

    python examples/eccentric_cam.py [output folder]

With the cam at angle th (its centre at e (cos th, sin th)) the knife edge is at
y = e sin th + S, S = sqrt(R^2 - e^2 cos^2 th), and the flat face at y = e sin th - R.

Parameters: disc radius 50 mm, its centre 20 mm from the pivot; the cam at one turn a
second (2 pi rad/s).
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
e, R, w = 0.02, 0.05, 2 * math.pi  # m, m, rad/s

model = lw.Mechanism.load(here / "eccentric_cam.toml").compile()
times = np.linspace(0.0, 1.0, 361)
res = model.sweep(times)
th = w * times
S = np.sqrt(R**2 - e**2 * np.cos(th) ** 2)
dy = e * np.cos(th) + e**2 * np.sin(2 * th) / (2 * S)  # dy/dth of the knife edge
ddy = -e * np.sin(th) + e**2 * np.cos(2 * th) / S - e**4 * np.sin(2 * th) ** 2 / (4 * S**3)
want = {
    "knife": (e * np.sin(th) + S, dy * w, ddy * w**2),
    "flat": (e * np.sin(th) - R, e * np.cos(th) * w, -e * np.sin(th) * w**2),
}
for name, (y, v, a) in want.items():
    body = res.body(name)
    pairs = ((body.y, y), (body.yd, v), (body.ydd, a))
    err = [np.abs(got - ref).max() / np.abs(ref).max() for got, ref in pairs]
    print(f"{name}: lift {1000 * (y.max() - y.min()):.3f} mm; vs closed form ", end="")
    print(f"y {err[0]:.1e}, v {err[1]:.1e}, a {err[2]:.1e}")
    assert max(err) < 1e-10
s = res.q[:, res.columns.index("flat_face.s")]  # the contact's parameter on the circle
print(
    f"the flat face touches the cam at s = {s[0]:.4f} .. {s[-1]:.4f} rad: one turn backwards round the disc"
)
figures.plot_outputs(res, str(out / "eccentric_cam.png"), ["knife.y", "flat.y"])  # as `linkwork plot`
print(f"wrote {out / 'eccentric_cam.png'}")

"""A pin in a curved slot driven by a slider, from its model file: the pin's path against
the closed form (the point of the slot's circle at the link's length from the slider
pin), every coordinate against the NumPy reference, and the slot's own coordinate s.

    python examples/curved_slot.py [output folder]

Parameters: slider on y = -0.15 m, driven 0.08 sin(2 pi t) m from x = 0.10 m; link 0.20
m; slot a circle of radius 0.10 m about the origin.
"""

import math
import sys
from pathlib import Path

import numpy as np

import linkwork as lw
from linkwork.reference import ReferenceModel
from linkwork.view import figures

here = Path(__file__).resolve().parent
out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)
radius, link, y_guide, x0 = 0.10, 0.20, -0.15, 0.10  # m, as in the model file

mech = lw.Mechanism.load(here / "curved_slot.toml")
times = np.linspace(0.0, 1.0, 181)
res = mech.compile().sweep(times)
x = x0 + 0.08 * np.sin(2 * math.pi * times)  # the slider pin B, from the translation law
B = np.stack([x, np.full_like(x, y_guide)], 1)
dist = np.linalg.norm(B, axis=1, keepdims=True)
along = (radius**2 - link**2 + dist**2) / (2 * dist)
P = (along * B + np.sqrt(radius**2 - along**2) * np.stack([-B[:, 1], B[:, 0]], 1)) / dist
err_p = np.abs(res.point("P").position - P).max() / radius
ref = ReferenceModel(mech).sweep(times)
errs = [np.abs(getattr(res, k) - ref[k]).max() / np.abs(ref[k]).max() for k in ("q", "qd", "qdd")]
print(f"pin P vs closed form {err_p:.1e}; vs reference q {errs[0]:.1e}, qd {errs[1]:.1e}, qdd {errs[2]:.1e}")
assert err_p < 1e-12 and max(errs) < 1e-10
s = res.q[:, res.columns.index("slot.s")]  # the pin's polar angle on the slot
print(
    f"the pin runs over {math.degrees(s.min()):.3f} .. {math.degrees(s.max()):.3f} deg of the slot's circle"
)
assert np.allclose(s, np.arctan2(P[:, 1], P[:, 0]), rtol=0, atol=1e-12)
figures.plot_paths(res, str(out / "curved_slot_paths.png"))  # paths over the drawn mechanism
print(f"wrote {out / 'curved_slot_paths.png'}")

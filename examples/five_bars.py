"""Five-bars from their model files: driven at both cranks (a linear law and an expression
law), the point C against the closed form (a circle-circle intersection) and every
coordinate against the NumPy reference; and chained (one driver, a chain coupling the
cranks), against the reference.

    python examples/five_bars.py [output folder]

Parameters: cranks 0.10 m about O1 = (0, 0) and O2 = (0.30, 0) m, links 0.30 m; crank 1
at 2 pi rad/s, crank 2 pi/2 + 0.8 sin(2 pi t) rad (chained: a chain of ratio 1, crank 2
a quarter turn ahead).
"""

import math
import sys
from pathlib import Path

import numpy as np

import linkwork as lw
from linkwork.reference import ReferenceModel

here = Path(__file__).resolve().parent
out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)
times = np.linspace(0.0, 1.0, 121)
crank, link, O2 = 0.10, 0.30, np.array([0.30, 0.0])  # m, as in the model files


def point_c(theta1: np.ndarray, theta2: np.ndarray) -> np.ndarray:
    """C from the two crank angles: on the left of A -> B, at the link's length from both."""
    A = crank * np.stack([np.cos(theta1), np.sin(theta1)], 1)
    B = O2 + crank * np.stack([np.cos(theta2), np.sin(theta2)], 1)
    d = B - A
    half = np.linalg.norm(d, axis=1, keepdims=True) / 2
    up = np.sqrt(link**2 - half**2) * np.stack([-d[:, 1], d[:, 0]], 1) / (2 * half)
    return A + d / 2 + up


for name in ("five_bar_two_inputs", "chained_six_bar"):
    mech = lw.Mechanism.load(here / f"{name}.toml")
    res = mech.compile().sweep(times)
    ref = ReferenceModel(mech).sweep(times)
    errs = [np.abs(getattr(res, k) - ref[k]).max() / np.abs(ref[k]).max() for k in ("q", "qd", "qdd")]
    theta1, theta2 = res.body("crank1").theta, res.body("crank2").theta
    c_err = np.abs(res.point("C").position - point_c(theta1, theta2)).max() / link
    print(f"{mech.name}: vs reference q {errs[0]:.1e}, qd {errs[1]:.1e}, qdd {errs[2]:.1e}; ", end="")
    print(f"C vs closed form {c_err:.1e}")
    assert max(errs) < 1e-10 and c_err < 1e-12

# the expression law on its own: law.evaluate gives (f, f', f'') at each time
law = lw.Expression("pi/2 + 0.8*sin(2*pi*t)")
mech = lw.Mechanism.load(here / "five_bar_two_inputs.toml")
res = mech.compile().sweep(times)
res.plot(str(out / "five_bar_two_inputs.png"), bodies=["crank1", "crank2", "link1", "link2"])
crank2 = res.body("crank2")
f = law.evaluate(times)
err = max(
    np.abs(crank2.theta - f[:, 0]).max(), np.abs(crank2.thetadd - f[:, 2]).max() / np.abs(f[:, 2]).max()
)
print(f"crank 2 follows its expression law to {err:.1e}; peak rate {np.abs(f[:, 1]).max():.3f} rad/s")
assert err < 1e-12
chain = lw.Mechanism.load(here / "chained_six_bar.toml").compile().sweep(times)
lag = chain.body("crank2").theta - chain.body("crank1").theta
print(
    f"chained: crank 2 leads crank 1 by {math.degrees(lag.min()):.12f} .. {math.degrees(lag.max()):.12f} deg"
)
assert np.abs(lag - math.pi / 2).max() < 1e-12
print(f"wrote {out / 'five_bar_two_inputs.png'}")

"""A disc cam designed from a rise-dwell-fall program for a translating roller follower,
its profile a polar spline table: the follower's displacement, velocity and acceleration
against the program.

    python examples/cam_rise_dwell_fall.py [output folder]

The program (cam angle over one turn): a 15 mm cycloidal rise over 120 degrees, a dwell
of 60, a 3-4-5 polynomial fall over 120, a dwell of 60. The roller's centre must follow
the pitch curve R = base + roller + s; the profile is that curve offset inward by the
roller's radius, tabulated as r(phi) every degree (cam_rise_dwell_fall.toml). The
spline through the table is exact to O(h^4) in r, so the follower's displacement is
(measured here) O(h^4), its velocity O(h^3) and its acceleration O(h^2).

Parameters: base circle 40 mm, roller 10 mm; a 15 mm cycloidal rise over 120 deg, dwell
60 deg, 3-4-5 fall over 120 deg, dwell 60 deg; the cam at one turn a second (2 pi rad/s,
clockwise); the file in m and rad.
"""

import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import linkwork as lw  # noqa: E402

here = Path(__file__).resolve().parent
out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)
base, roller, lift = 0.040, 0.010, 0.015  # m
program = lw.Cam([lw.Cam.rise(1 / 3, lift, "cycloidal"), lw.Cam.dwell(1 / 6),
                  lw.Cam.fall(1 / 3, lift, "polynomial_345"), lw.Cam.dwell(1 / 6)])  # fmt: skip


def profile(n: int) -> dict:
    """The cam profile as a polar table of n + 1 rows (one turn)."""
    psi = np.linspace(0.0, 2 * math.pi, n + 1)  # cam angle under the follower; 1 s per turn
    s = program.evaluate(psi / (2 * math.pi))
    R, dR = base + roller + s[:, 0], s[:, 1] / (2 * math.pi)  # the pitch curve and dR/dpsi
    e, e_perp = np.array([np.cos(psi), np.sin(psi)]), np.array([-np.sin(psi), np.cos(psi)])
    contact = R * e - roller * (R * e - dR * e_perp) / np.hypot(R, dR)  # inward along the normal
    phi, r = np.unwrap(np.arctan2(contact[1], contact[0])), np.hypot(contact[0], contact[1])
    phi[-1], r[-1] = phi[0] + 2 * math.pi, r[0]  # close the turn exactly
    return lw.curves.polar((0.0, 0.0), phi, r)


mech = lw.Mechanism.load(here / "cam_rise_dwell_fall.toml")
table = next(j["curve"] for j in mech.to_dict()["joints"] if j["name"] == "contact")
assert np.allclose(table["radii"], profile(360)["radii"], rtol=0, atol=1e-15), "the file is not the design"
times = np.linspace(0.0, 1.0, 3601)
want = program.evaluate(times)  # (s, s', s'') of the program
for n in (180, 360, 720):
    mech.remove("contact")
    mech.cam_follower("cam", "follower", (base + roller, 0.0), profile(n), "roller", roller, name="contact")
    follower = mech.compile().sweep(times).body("follower")
    got = (follower.x - base - roller, follower.xd, follower.xdd)
    err = [np.abs(g - w).max() / np.abs(w).max() for g, w in zip(got, want.T)]
    print(f"table every {360 / n:.2f} deg: errors vs program: s {err[0]:.1e}, v {err[1]:.1e}, a {err[2]:.1e}")
    if n == 360:  # the file's table; bounds 2x the measured errors, which fall as h^4, h^3, h^2
        assert err[0] < 3e-8 and err[1] < 5e-6 and err[2] < 1.2e-3, err
        plotted = got
v_peak, a_peak = np.abs(want[:, 1:]).max(axis=0)
print(f"peak follower velocity {v_peak:.4f} m/s, acceleration {a_peak:.3f} m/s^2")

fig, axes = plt.subplots(3, 1, sharex=True, figsize=(6, 6))
for ax, g, w, label in zip(axes, plotted, want.T, ("s [m]", "v [m/s]", "a [m/s^2]")):
    ax.plot(360 * times, w, lw=3, color="0.8", label="program")
    ax.plot(360 * times, g, lw=1, color="C0", label="follower (linkwork)")
    ax.set_ylabel(label)
axes[0].legend(loc="upper right", fontsize=8)
axes[-1].set_xlabel("cam angle [deg]")
fig.tight_layout()
fig.savefig(out / "cam_rise_dwell_fall.png", dpi=80)
print(f"wrote {out / 'cam_rise_dwell_fall.png'}")

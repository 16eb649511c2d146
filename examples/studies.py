"""Design studies of the textbook four-bar: a coupler-curve atlas of a four-bar family
(crank length by coupler-point offset, on a grid) and a tolerance study (Monte Carlo
beside first order), each with its dataset and report.

    python examples/studies.py [output folder]

The same study on a Dask cluster is one argument more: ``scheduler="tcp://host:8786"``
(or ``"local"``) in ``study.run`` and ``study.tolerance``.

Parameters: the four-bar of four_bar (m, 5 rad/s): the atlas varies the crank length
from 0.08 to 0.20 m and the coupler point P's y from 0 to 0.3 m (5 x 5 grid); the
tolerance study gives the links +-0.05 mm (3 sigma; the rocker's uniform) and the
rocker's pivot +-0.1 mm.
"""

import math
import sys
from pathlib import Path

import numpy as np

import linkwork as lw
from linkwork import study as S

out = Path(sys.argv[1] if len(sys.argv) > 1 else "linkwork-out")
out.mkdir(parents=True, exist_ok=True)

mechanism = lw.examples.four_bar()  # ground 0.35, crank 0.20, coupler 0.35, rocker 0.25 m
turn = np.linspace(0.0, 2 * math.pi / 5.0, 400)  # one crank revolution at 5 rad/s

# the atlas: five crank lengths by five coupler points (P moved across the coupler)
study = lw.Study(mechanism, turn, ["path P", "transmission_min", "grashof"])
atlas = study.run(S.grid({"length crank": np.linspace(0.08, 0.2, 5), "point P.y": np.linspace(0.0, 0.3, 5)}))
print(atlas)
S.atlas_figure(atlas, str(out / "studies_atlas.png"))
atlas.save(str(out / "studies_atlas.nc"))

# check one design against its own sweep: the dataset holds exactly that curve
k = 7
alone = lw.Model(S.apply(mechanism, atlas.designs.design(k))).sweep(turn, derivatives=0)
assert np.array_equal(atlas.dataset.path_P.values[k], alone.point("P").position)
minimum = np.degrees(atlas.dataset.transmission_min.values)
print(
    f"smallest transmission angle over the family: {np.nanmin(minimum):.1f} deg, "
    f"largest {np.nanmax(minimum):.1f}"
)

# tolerances: links to +-0.05 mm (3 sigma), the rocker's pivot placed within +-0.1 mm
tol_study = lw.Study(mechanism, turn, ["path P", "angle rocker", "transmission_min"])
tolerances = {
    "length crank": S.Normal(0.05e-3 / 3),
    "length coupler": S.Normal(0.05e-3 / 3),
    "length rocker": S.Uniform(0.05e-3),
    "pivot O4.x": S.Interval(-0.1e-3, 0.1e-3),
    "pivot O4.y": S.Interval(-0.1e-3, 0.1e-3),
}
tol = tol_study.tolerance(tolerances, n=500, seed=1)
print(tol.summary())
tol.report(str(out), stem="studies_tolerance")
rows = {r["component"]: r for r in tol.comparison()}
# small tolerances: Monte Carlo and first order agree to the sampling error (~6 % at 500)
assert abs(rows["angle_rocker"]["mc_std"] / rows["angle_rocker"]["linear_rss"] - 1.0) < 0.15
print(f"wrote {out / 'studies_atlas.png'} and the tolerance report {out / 'studies_tolerance.md'}")

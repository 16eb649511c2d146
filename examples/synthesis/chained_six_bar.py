"""The source document's chained six-bar through the general call: its numbers read from
chained_six_bar.toml beside this script, every design reported, the document's printed
answer checked against the equations (with the stated data and with its program's two
differing inputs), and the input torque over a turn, checked by virtual work.

    python examples/synthesis/chained_six_bar.py
"""

import itertools
import sys
from pathlib import Path

import numpy as np

from linkwork.synthesis import six_bar as C

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python < 3.11
    import tomli as tomllib

data = tomllib.loads((Path(__file__).parent / "chained_six_bar.toml").read_text())
problem = {k: data[k] for k in ("points", "input_angles", "coupler_angles", "input_pivot", "output_pivot")}
result = C.chained_six_bar(angles=data["angles"], **problem)
print(result.report())

# the document's printed answer, with the stated data and the program input's P4x and Qx
printed, program = data["document"]["printed_answer"], data["document"]["program_input"]
points, q = np.array(problem["points"]), np.array(problem["input_pivot"])
phi, theta = np.radians(problem["input_angles"]), np.radians(problem["coupler_angles"])
print("printed answer A1 B1 C1 D1, largest residual (length units) of dyad 1, dyad 2:")
for p4x, qx in itertools.product((points[3, 0], program["P4x"]), (q[0], program["Qx"])):
    pts, qq = points.copy(), q.copy()
    pts[3, 0], qq[0] = p4x, qx
    r1, r2 = C.residuals(
        *(printed[k] for k in ("A1", "B1", "C1", "D1")), pts, phi, theta, qq, problem["output_pivot"]
    )
    print(f"  P4x = {p4x:g}, Qx = {qx:g}: {np.abs(r1).max():.3f}, {np.abs(r2).max():.3f}")

full = [d for d in result.designs if d.defects.ok and d.defects.full_turn]
tq = C.torque(full[0], **data["torque"])
k = result.designs.index(full[0]) + 1
print(
    f"input torque of design {k} over a turn: phi {np.abs(tq.phi).max():.4g}, "
    f"theta {np.abs(tq.theta).max():.4g}, summed {np.abs(tq.total).max():.4g} N m (peaks); "
    f"virtual work agrees to {np.abs(tq.total - tq.virtual_work).max():.2e} N m"
)

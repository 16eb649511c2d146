"""Crank-shaper quick-return: the time ratio of the cutting and return strokes, and the
stroke, located by the sweep's lock events, against the closed forms.

    python examples/quick_return_shaper.py [output folder]

The ram stops where the lever does, at the two crank angles where the crank is
perpendicular to the lever: the crank sweeps 180 + alpha degrees on the cutting stroke
and 180 - alpha on the return, alpha = 2 asin(crank / O2O4); the ram moves the lever's
tip sideways by 2 lever crank / O2O4.

Parameters: crank 100 mm, O2O4 300 mm, lever 500 mm, link 150 mm, ram guide 210 mm above
O2, tool tip 30 mm ahead of and 60 mm below the ram pin; the crank at 360 deg/s.
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
crank, d, lever = 100.0, 300.0, 500.0  # mm, as in the model file

model = lw.Mechanism.load(here / "quick_return_shaper.toml").compile()
res = model.sweep(np.linspace(0.0, 1.0, 721), locks=True)  # one crank turn
# locks=True locates where each output (the lever, the ram's slide) stops and reverses
stops = sorted(e.time for e in res.events if e.kind == "lock" and e.output == "guide (slide)")
assert len(stops) == 2, res.events
between = stops[1] - stops[0]  # one stroke; the other takes the rest of the 1 s turn
ratio = max(between, 1.0 - between) / min(between, 1.0 - between)
alpha = math.degrees(2.0 * math.asin(crank / d))
ratio_cf = (180.0 + alpha) / (180.0 - alpha)
tool_x = [model.solve(t).point("tool").position[0] for t in stops]  # on the welded tool post
stroke, stroke_cf = abs(tool_x[1] - tool_x[0]), 2.0 * lever * crank / d
print(f"time ratio {ratio:.12f}, closed form (180 + {alpha:.4f}) / (180 - {alpha:.4f}) = {ratio_cf:.12f}")
print(f"stroke {stroke:.9f} mm, closed form {stroke_cf:.9f} mm")
ram = res.body("ram")
print(f"peak ram speed: cutting {-ram.xd.min():.1f} mm/s, return {ram.xd.max():.1f} mm/s")
err_ratio, err_stroke = abs(ratio / ratio_cf - 1.0), abs(stroke / stroke_cf - 1.0)
print(f"errors: time ratio {err_ratio:.1e}, stroke {err_stroke:.1e} relative")
assert err_ratio < 1e-9 and err_stroke < 1e-9
figures.plot_outputs(res, str(out / "quick_return_shaper.png"), ["lever", "ram.x"])  # as `linkwork plot`
print(f"wrote {out / 'quick_return_shaper.png'}")

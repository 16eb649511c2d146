"""Whitworth quick-return: time ratio and stroke against the closed forms, the ram's
extremes located by the sweep's lock events.

    python examples/whitworth.py [output folder]

The ram stops where the lever lies along the ram's line, so where the crank pin crosses
that line: the crank sweeps 180 + alpha degrees on the slow stroke and 180 - alpha on the
quick one, alpha = 2 asin(O2O4 / crank); the stroke is twice the lever's arm O4C.

Parameters: crank 0.10 m, O4 0.05 m below O2, lever arm O4C 0.08 m, link 0.25 m; the
crank at 2 pi rad/s.
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
crank, d, arm = 0.10, 0.05, 0.08  # m, as in the model file

model = lw.Mechanism.load(here / "whitworth.toml").compile()
res = model.sweep(np.linspace(0.0, 1.0, 721), locks=True)  # one crank turn
stops = sorted(e.time for e in res.events if e.kind == "lock" and e.output == "guide (slide)")
assert len(stops) == 2, res.events
between = stops[1] - stops[0]
ratio = max(between, 1.0 - between) / min(between, 1.0 - between)
alpha = math.degrees(2.0 * math.asin(d / crank))
ratio_cf = (180.0 + alpha) / (180.0 - alpha)
tool = [model.solve(t).point("tool").position[0] for t in stops]  # (x, y) of the named point
stroke = abs(tool[1] - tool[0])
print(f"time ratio {ratio:.12f}, closed form (180 + {alpha:.1f}) / (180 - {alpha:.1f}) = {ratio_cf:.12f}")
print(f"stroke {stroke:.12f} m, closed form 2 O4C = {2 * arm:.12f} m")
v = res.point("tool").velocity[:, 0]  # the tool's x velocity over the turn
slow, quick = sorted((v.max(), -v.min()))
print(f"peak tool speed: slow stroke {slow:.4f} m/s, quick stroke {quick:.4f} m/s")
err_ratio, err_stroke = abs(ratio / ratio_cf - 1.0), abs(stroke / (2 * arm) - 1.0)
print(f"errors: time ratio {err_ratio:.1e}, stroke {err_stroke:.1e} relative")
assert err_ratio < 1e-9 and err_stroke < 1e-9
figures.plot_outputs(res, str(out / "whitworth.png"), ["lever", "ram.x"])  # as `linkwork plot`
print(f"wrote {out / 'whitworth.png'}")

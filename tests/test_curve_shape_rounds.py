"""The shape fit's agreement rule: its seeds are refined in rounds of four, nearest
first, until two refined designs agree on the best mean nearest distance (to 1 %)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork.synthesis import curve as C

pytest.importorskip("scipy")

KNOWN = np.array([4.0, 1.0, 3.5, 3.0, 1.5, 1.0, 0.0, 0.0, 0.0])


def test_the_rounds_stop_when_two_designs_agree() -> None:
    # a four-bar's curve, every point moved by noise of 2 % of the crank
    th = 0.4 + np.linspace(0.0, 2.0 * math.pi, 36, endpoint=False)
    pts = C.coupler_points(KNOWN, th, "open")
    pts += np.random.default_rng(3).normal(0.0, 0.02, pts.shape)
    every = C.shape_fit(pts, k=8, seed=0, workers=2, polish=0, agree=None)
    assert every.unrefined == 0 and len(every.designs) > 4
    stopped = C.shape_fit(pts, k=8, seed=0, workers=2, polish=0)
    # the first round of four already has three designs at the best mean (0.01678 measured)
    assert stopped.unrefined == 4 and len(stopped.designs) <= 4
    assert "4 seeds left: 2 starts agreed on the best" in stopped.report()
    means = sorted(d.mean for d in stopped.designs)
    assert means[1] <= 1.01 * means[0]
    # the round it ran is the full run's first, its designs the same to the bit
    full = [d.x for d in every.designs]
    assert all(any(np.array_equal(d.x, x) for x in full) for d in stopped.designs)
    assert stopped.best.mean <= 1.01 * every.best.mean

"""The shape fit's polish runs to convergence: rounds of reweighted least squares until
one moves the mean nearest distance by less than the fraction _POLISH_GAIN of the round
before's, ending well before the cap, below what four rounds refined to their end reach,
with the best round's design."""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

from linkwork.synthesis import curve as C

pytest.importorskip("scipy")

SH = importlib.import_module("linkwork.synthesis.curve.shape")
KNOWN = np.array([4.0, 1.0, 3.5, 3.0, 1.5, 1.0, 0.0, 0.0, 0.0])


def test_the_polish_runs_until_a_round_gains_under_its_fraction(monkeypatch: pytest.MonkeyPatch) -> None:
    # a known four-bar's curve with every third point pushed off it (as in test_curve_seeds)
    th = 0.4 + np.linspace(0.0, 2.0 * math.pi, 36, endpoint=False)
    pts = C.coupler_points(KNOWN, th, "open")
    pts[::3] += np.random.default_rng(3).normal(0.0, 0.2, (12, 2))
    start = C.shape_fit(pts, k=4, seed=0, workers=2, polish=0).best
    four = SH._score(pts, SH._polish(pts, start, 4, 200, {}), start.circuit)[1]
    means: list[float] = []
    score = SH._score

    def spy(points: np.ndarray, x: np.ndarray, circuit: str):  # noqa: ANN202
        out = score(points, x, circuit)
        means.append(math.inf if out is None else out[1])
        return out

    monkeypatch.setattr(SH, "_score", spy)
    cap = 200
    y = SH._polish(pts, start, cap, SH._POLISH_NFEV, {})
    assert 4 < len(means) < cap  # the rule ended it, not the cap
    moves = np.abs(np.diff(means)) / np.array(means[:-1])
    assert moves[-1] < SH._POLISH_GAIN and np.all(moves[:-1] >= SH._POLISH_GAIN)
    assert score(pts, y, start.circuit)[1] == min(means) < four

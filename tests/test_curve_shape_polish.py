"""The shape fit's polish runs to convergence: rounds of reweighted least squares, each
first of _POLISH_NFEV evaluations; a round that moves the mean nearest distance by less
than the fraction _POLISH_GAIN of the round before's gives the next four times as many,
and at the most a round may spend it is the last. It ends before the cap, below what
four rounds refined to their end reach, with the best round's design."""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

from linkwork.synthesis import curve as C

pytest.importorskip("scipy")

SH = importlib.import_module("linkwork.synthesis.curve.shape")
KNOWN = np.array([4.0, 1.0, 3.5, 3.0, 1.5, 1.0, 0.0, 0.0, 0.0])


def test_the_polish_runs_until_a_full_round_moves_under_its_fraction(monkeypatch: pytest.MonkeyPatch) -> None:
    # a known four-bar's curve with every third point pushed off it (as in test_curve_seeds)
    th = 0.4 + np.linspace(0.0, 2.0 * math.pi, 36, endpoint=False)
    pts = C.coupler_points(KNOWN, th, "open")
    pts[::3] += np.random.default_rng(3).normal(0.0, 0.2, (12, 2))
    start = C.shape_fit(pts, k=4, seed=0, workers=2, polish=0).best
    four = SH._score(pts, SH._polish(pts, start, 4, 200, {}), start.circuit)[1]
    means: list[float] = []
    nfevs: list[int] = []
    score, refine = SH._score, SH.refine

    def spy_score(points: np.ndarray, x: np.ndarray, circuit: str):  # noqa: ANN202
        out = score(points, x, circuit)
        means.append(math.inf if out is None else out[1])
        return out

    def spy_refine(*args: object, max_nfev: int, **kwargs: object):  # noqa: ANN202
        nfevs.append(max_nfev)
        return refine(*args, max_nfev=max_nfev, **kwargs)

    monkeypatch.setattr(SH, "_score", spy_score)
    monkeypatch.setattr(SH, "refine", spy_refine)
    cap = 200
    y = SH._polish(pts, start, cap, 200, {})
    assert 4 < len(means) < cap and len(nfevs) == len(means)  # the rule ended it, not the cap
    moves = np.abs(np.diff(means)) / np.array(means[:-1])
    stalled = np.flatnonzero(moves < SH._POLISH_GAIN) + 1  # the rounds that moved too little
    assert nfevs[0] == SH._POLISH_NFEV and stalled[-1] == len(means) - 1 and nfevs[-1] == 200
    expected = [SH._POLISH_NFEV]
    for k in range(1, len(means)):
        expected.append(min(4 * expected[-1], 200) if k - 1 in stalled else expected[-1])
    assert nfevs == expected
    assert score(pts, y, start.circuit)[1] == min(means) < four

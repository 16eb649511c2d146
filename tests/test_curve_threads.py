"""The multistarts' pool (linkwork.synthesis.curve.threads): BLAS on one thread inside
it, restored after, the answers in the jobs' order; and a refinement's point weights."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork.synthesis import curve as C
from linkwork.synthesis.curve.threads import map_starts, one_blas_thread

threadpoolctl = pytest.importorskip("threadpoolctl")
pytest.importorskip("scipy")


def _blas_threads() -> list[int]:
    import scipy.linalg  # noqa: F401  (loads the BLAS scipy uses)

    return [i["num_threads"] for i in threadpoolctl.threadpool_info() if i["user_api"] == "blas"]


def test_one_blas_thread_inside_and_restored() -> None:
    before = _blas_threads()
    with one_blas_thread():
        assert _blas_threads() and all(n == 1 for n in _blas_threads())
        inside = map_starts(lambda k: _blas_threads(), range(3), 2)
    assert all(n == 1 for row in inside for n in row)
    assert _blas_threads() == before


def test_map_starts_keeps_the_order() -> None:
    assert map_starts(lambda k: k * k, range(20), 3) == [k * k for k in range(20)]


def test_refine_weights_the_points() -> None:
    # a curve no four-bar passes through exactly: weighting one point heavily pulls the
    # design onto it and lowers the weighted sum of squares
    th = np.linspace(0.0, 2.0 * math.pi, 12, endpoint=False)
    pts = np.column_stack([np.cos(th), 0.6 * np.sin(th) + 0.3 * np.cos(2 * th)])
    pts[4] += (0.25, 0.15)
    target = C.target(pts, closed=True)
    start = C.random_seeds(target, 1, seed=2)[0]
    problem = C.TrackingProblem(target, circuit=start[0])
    # refined twice: the second run starts where the first stopped, at its minimum
    plain = C.refine(problem, C.refine(problem, start[1]).x)
    w = np.ones(12)
    w[4] = 30.0
    heavy = C.refine(problem, plain.x, weights=w)
    miss = lambda d: float(np.hypot(*(C.coupler_points(d.x, d.x[9:], d.circuit)[4] - pts[4])))  # noqa: E731
    assert miss(heavy) < 0.5 * miss(plain)
    weighted = lambda d: float(np.sum((w[:, None] * (C.coupler_points(d.x, d.x[9:], d.circuit) - pts)) ** 2))  # noqa: E731
    # the weighted sum drops by at least half of point 4's weighted share of it at the
    # unweighted minimum (0.0283 to 0.0207 measured, point 4's share 0.0083)
    assert weighted(plain) - weighted(heavy) > 0.5 * (w[4] * miss(plain)) ** 2

"""The refinement on an active Grashof constraint (s + l = p + q): it keeps descending
along the boundary instead of stopping where its first step across it is refused."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork.synthesis import curve as C

pytest.importorskip("scipy")

# a crank-rocker 1e-7 inside Grashof's limit: r2 + r3 = r1 + r4 - 1e-9 (r2 shortest, r3 longest)
_BEST = np.array([4.0, 1.0, 4.5, 1.5 + 1e-7, 1.2, 0.8, 0.3, 0.1, -0.2])
_THETA = np.linspace(0.0, 2.0 * math.pi, 12, endpoint=False) + 0.05


def _problem() -> C.TrackingProblem:
    target = C.target(C.coupler_points(_BEST, _THETA, "open"), closed=True)
    return C.TrackingProblem(target, circuit="open")


@pytest.mark.parametrize("lengths", [(0.2, 0.0, 0.0, 0.2), (0.2, 0.0, 0.2, 0.0)], ids=["inside", "on"])
def test_refine_reaches_the_optimum_on_the_grashof_boundary(lengths: tuple[float, ...]) -> None:
    # the target is traced exactly by _BEST, whose Grashof margin is 1e-7: from a start
    # inside (r1, r4 longer) or on the boundary (r1, r3 longer together) the refinement
    # meets the boundary and must reach _BEST along it
    problem = _problem()
    start = np.concatenate([_BEST, _THETA])
    start[:4] += lengths
    start[4:9] += [0.1, -0.1, 0.05, 0.05, -0.05]
    start[9:] += 0.03 * np.sin(np.arange(12))
    assert problem.objective(start) > 0.1
    d = C.refine(problem, start)
    # f ~ 1e-29 measured; the stalled refinement stopped at 6.6e-5
    assert d.f <= 1e-20
    assert np.max(np.abs(d.x[:9] - _BEST)) <= 1e-9
    assert d.violation == 0.0
    assert all(m >= 0.0 for m in d.margins.values())


def test_two_starts_on_the_boundary_reach_the_same_f() -> None:
    # the weights test's curve (tests/test_curve_threads.py): from random starts 2 and 4
    # the refinement meets s + l = p + q and, stalled there, stopped at f 0.188 and
    # 0.104; going on along the boundary both reach 0.0201 (0.020076, 0.020055 measured)
    th = np.linspace(0.0, 2.0 * math.pi, 12, endpoint=False)
    pts = np.column_stack([np.cos(th), 0.6 * np.sin(th) + 0.3 * np.cos(2 * th)])
    pts[4] += (0.25, 0.15)
    target = C.target(pts, closed=True)
    found = []
    for seed in (2, 4):
        circuit, x = C.random_seeds(target, 1, seed=seed)[0]
        d = C.refine(C.TrackingProblem(target, circuit=circuit), x)
        assert d.violation == 0.0
        s, p, q, l_ = np.sort(d.x[:4])
        assert s + l_ <= p + q and 0.0 <= d.margins["grashof crank-rocker"] <= 1e-5 * target.size
        found.append(d.f)
    assert abs(found[0] - found[1]) <= 0.005 * min(found)
    assert max(found) < 0.021


def test_fit_continues_along_the_boundary_only_near_the_best(monkeypatch: pytest.MonkeyPatch) -> None:
    # two starts on the boundary curve: the generating design itself (f 0 at once) and the
    # "on" start of the first test, whose penalised refinement stalls on Grashof's limit
    # far above 10 times 0: fit does not continue it (refine alone does, to f <= 1e-20)
    import importlib

    fit_module = importlib.import_module("linkwork.synthesis.curve.fit")
    problem = _problem()
    exact = np.concatenate([_BEST, _THETA])
    start = exact.copy()
    start[:4] += (0.2, 0.0, 0.2, 0.0)
    start[4:9] += [0.1, -0.1, 0.05, 0.05, -0.05]
    start[9:] += 0.03 * np.sin(np.arange(12))
    seeds = [("open", exact), ("open", start)]
    alone = C.refine(problem, start)
    assert alone.f <= 1e-20
    result = C.fit(problem.target, seeds=seeds, workers=2)
    far = next(d for d in result.designs if d.start == 1)
    assert result.best.f <= 1e-24 and far.f > 1e-8 and far.nfev < alone.nfev
    # without the rule every start continues: fit gives refine's designs, bit for bit
    monkeypatch.setattr(fit_module, "_REACH", math.inf)
    result = C.fit(problem.target, seeds=seeds, workers=1)
    far = next(d for d in result.designs if d.start == 1)
    assert np.array_equal(far.x, alone.x) and far.nfev == alone.nfev

"""Synthesis from a curve (linkwork.synthesis.curve): target input and its errors by
name, the tracking-error problem's exact Jacobian against central differences, the
engine's coupler point against the closed form, and the multistart on Cabrera's
problems."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from linkwork.errors import SynthesisError
from linkwork.synthesis import curve as C

pytest.importorskip("scipy")

# the two Cabrera problems, as in the notes (kept here so the tests do not need the data)
VERTICAL = np.column_stack([np.full(6, 20.0), np.arange(20.0, 46.0, 5.0)])
ARC = np.array([[3.0, 3.0], [2.759, 3.363], [2.372, 3.663], [1.89, 3.862], [1.355, 3.943]])
ARC_ANGLES = np.radians([30.0, 45.0, 60.0, 75.0, 90.0])


# ---- targets and their errors ------------------------------------------------------------
def test_too_few_points_is_named() -> None:
    with pytest.raises(SynthesisError, match="at least 3 points"):
        C.target([[0.0, 0.0], [1.0, 0.0]])
    t = C.target([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    with pytest.raises(SynthesisError, match="needs at least 4 target points"):
        C.TrackingProblem(t)


def test_non_finite_and_repeated_points_are_named() -> None:
    with pytest.raises(SynthesisError, match="point 2 is not finite"):
        C.target([[0.0, 0.0], [np.nan, 1.0], [1.0, 1.0]])
    with pytest.raises(SynthesisError, match="points 2 and 3 coincide"):
        C.target([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0], [2.0, 0.0]])
    with pytest.raises(SynthesisError, match="repeats its first point"):
        C.target([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [0.0, 0.0]], closed=True)
    with pytest.raises(SynthesisError, match="4 crank angles for 3"):
        C.target([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]], crank_angles=[0.0, 1.0, 2.0, 3.0])


def test_contradictory_bounds_are_named() -> None:
    t = C.target(VERTICAL)
    with pytest.raises(SynthesisError, match="contradictory length bounds"):
        C.TrackingProblem(t, lengths=(5.0, 1.0))
    with pytest.raises(SynthesisError, match="contradictory pivot bounds"):
        C.TrackingProblem(t, pivot=(1.0, -1.0))
    with pytest.raises(SynthesisError, match=r"coupler point bounds are \(lower, upper\)"):
        C.TrackingProblem(t, coupler=("a", 1.0))
    with pytest.raises(SynthesisError, match="only theta0, x0, y0"):
        C.TrackingProblem(t, fixed={"r1": 1.0})


def test_svg_without_a_path_is_named() -> None:
    with pytest.raises(SynthesisError, match="no <path>"):
        C.from_svg('<svg xmlns="http://www.w3.org/2000/svg"><circle r="3"/></svg>')
    with pytest.raises(SynthesisError, match="does not parse"):
        C.svg_path_points("M 0 0 A 1 1 0 0 1 2 2")


def test_csv_reads_timing_from_a_third_column(tmp_path: Path) -> None:
    f = tmp_path / "arc.csv"
    rows = "\n".join(f"{x!r},{y!r},{a!r}" for (x, y), a in zip(ARC.tolist(), ARC_ANGLES.tolist()))
    f.write_text("x,y,crank_angle_rad\n" + rows + "\n")
    t = C.from_csv(f)
    assert t.timed and np.array_equal(t.crank_angles, ARC_ANGLES) and np.array_equal(t.points, ARC)
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n1,2\n3\n")
    with pytest.raises(SynthesisError, match="every row is x, y"):
        C.from_csv(bad)


def test_svg_square_sampled_evenly_relative_equals_absolute() -> None:
    # a closed square of side 10 drawn absolutely and relatively: 8 samples land on the
    # corners and the midpoints of the sides, 5 apart along the path (y flipped up)
    absolute = '<svg xmlns="http://www.w3.org/2000/svg"><path d="M0,0 L10,0 L10,10 L0,10 Z"/></svg>'
    relative = '<svg xmlns="http://www.w3.org/2000/svg"><g><path d="m0 0 h10 v10 l-10 0 z"/></g></svg>'
    a, b = C.from_svg(absolute, samples=8), C.from_svg(relative, samples=8)
    assert a.closed and b.closed
    np.testing.assert_allclose(a.points, b.points, atol=1e-12)
    expected = [[0, 0], [5, 0], [10, 0], [10, -5], [10, -10], [5, -10], [0, -10], [0, -5]]
    np.testing.assert_allclose(a.points, expected, atol=1e-9)


def test_svg_bezier_sampled_on_the_curve() -> None:
    # a quarter circle's cubic approximation: every sample within 3e-4 of the unit circle,
    # equally spaced along it; Q and relative c agree with their absolute forms
    k = 0.5522847498
    pts, closed = C.svg_path_points(f"M1,0 C1,{k} {k},1 0,1", samples=9)
    assert not closed
    np.testing.assert_allclose(np.hypot(*pts.T), 1.0, atol=3e-4)
    steps = np.hypot(*np.diff(pts, axis=0).T)
    np.testing.assert_allclose(steps, steps.mean(), rtol=2e-3)
    rel, _ = C.svg_path_points(f"M1,0 c0,{k} {k - 1},1 -1,1", samples=9)
    np.testing.assert_allclose(rel, pts, atol=1e-12)
    q, _ = C.svg_path_points("M0,0 Q1,2 2,0", samples=3)
    np.testing.assert_allclose(q[1], [1.0, 1.0], atol=1e-6)  # the apex of the parabola


# ---- the engine against the closed form, the Jacobian against differences ---------------
def _random_designs(target: C.TargetCurve, count: int, seed: int) -> list[tuple[str, np.ndarray]]:
    return C.random_seeds(target, count, seed)


@pytest.mark.parametrize("seed", [3, 4])
def test_engine_coupler_point_equals_closed_form(seed: int) -> None:
    t = C.target(VERTICAL)
    for circuit, x in _random_designs(t, 6, seed):
        problem = C.TrackingProblem(t, circuit=circuit)
        r, _ = problem.evaluate(x)
        closed = C.coupler_points(x, x[9:], circuit)
        scale = max(np.abs(closed).max(), 1.0)
        assert np.abs(r.reshape(-1, 2) + t.points - closed).max() <= 1e-12 * scale
        # the other circuit's closed form is far: the test can tell them apart
        other = C.coupler_points(x, x[9:], "crossed" if circuit == "open" else "open")
        assert np.abs(closed - other).max() > 1e-3 * t.size


@pytest.mark.parametrize("circuit", ["open", "crossed"])
def test_jacobian_agrees_with_central_differences(circuit: str) -> None:
    t = C.target(VERTICAL)
    x = next(x for c, x in _random_designs(t, 8, 11) if c == circuit)
    problem = C.TrackingProblem(t, circuit=circuit)
    r, jac = problem.evaluate(x)
    fd = np.zeros_like(jac)
    for k in range(x.size):
        h = 1e-5 * max(1.0, abs(x[k]))
        e = np.zeros_like(x)
        e[k] = h
        fd[:, k] = (problem.evaluate(x + e)[0] - problem.evaluate(x - e)[0]) / (2.0 * h)
    assert np.abs(fd - jac).max() <= 1e-7 * np.abs(jac).max()
    # the objective's gradient 2 J^T r against differences of f
    grad = 2.0 * jac.T @ r
    fd_f = np.array(
        [
            (problem.objective(x + h * e) - problem.objective(x - h * e)) / (2.0 * h)
            for e, h in ((e, 1e-5 * max(1.0, abs(v))) for e, v in zip(np.eye(x.size), x))
        ]
    )
    assert np.abs(fd_f - grad).max() <= 1e-7 * np.abs(grad).max()


def test_a_design_that_cannot_turn_is_a_named_failure() -> None:
    t = C.target(VERTICAL)
    # the crank longer than the ground: no full turn (not a crank-rocker)
    x = np.concatenate([[10.0, 12.0, 8.0, 9.0, 1.0, 1.0, 0.0, 20.0, 20.0], np.linspace(0.0, 2.0, 6)])
    with pytest.raises(C.CircuitError, match="does not assemble"):
        C.TrackingProblem(t).evaluate(x)
    good = _random_designs(t, 1, 5)[0]
    result = C.fit(t, seeds=[("open", x), good], max_nfev=20, workers=1)
    assert len(result.designs) == 1 and result.designs[0].start == 1
    assert len(result.failures) == 1 and result.failures[0].startswith("start 0:")


# ---- the benchmark problems -------------------------------------------------------------
def test_vertical_line_reaches_zero_from_a_seeded_multistart() -> None:
    result = C.fit(C.target(VERTICAL), starts=8, seed=1, workers=2)
    best = result.best
    assert best.f <= 1e-20
    assert best.ok and best.grashof == "crank-rocker"
    assert np.all(np.diff(best.crank_angles()) > 0.0)
    # the model the design gives traces the points at its crank angles
    res = best.model().compile().sweep(np.union1d(np.linspace(0.0, 2 * math.pi, 73), best.crank_angles()))
    at = np.searchsorted(res.times, best.crank_angles())
    np.testing.assert_allclose(res.point("P").position[at], VERTICAL, atol=1e-9)


def test_timed_arc_holds_the_fixed_numbers_and_is_reproducible() -> None:
    t = C.target(ARC, crank_angles=ARC_ANGLES)
    fixed = {"theta0": 0.0, "x0": 0.0, "y0": 0.0}
    a = C.fit(t, starts=4, seed=2, workers=2, fixed=fixed, lengths=(1e-3, 5.0), coupler=(-5.0, 5.0))
    b = C.fit(t, starts=4, seed=2, workers=1, fixed=fixed, lengths=(1e-3, 5.0), coupler=(-5.0, 5.0))
    assert [d.f for d in a.designs] == [d.f for d in b.designs]
    for d in a.designs:
        assert np.array_equal(d.x[6:9], [0.0, 0.0, 0.0])
        assert np.array_equal(d.crank_angles(), ARC_ANGLES)
        assert np.all(d.x[:4] <= 5.0) and np.all(np.abs(d.x[4:6]) <= 5.0)
        r, _ = d.problem.evaluate(d.x)
        assert d.f == pytest.approx(float(r @ r), rel=1e-12)
    assert a.best.f < 1e-3  # a real fit of five timed points (the best known is 7.4e-7)


def test_ordering_constraint_holds_on_the_designs_listed_first() -> None:
    t = C.target(ARC, crank_angles=ARC_ANGLES)
    options = {"fixed": {"theta0": 0.0, "x0": 0.0, "y0": 0.0}, "lengths": (1e-3, 5.0), "coupler": (-5.0, 5.0)}
    result = C.fit(t, starts=8, seed=2, workers=2, ordered=True, **options)
    ok = [d for d in result.designs if d.ok]
    assert ok and result.designs[: len(ok)] == ok
    for d in ok:
        r1, r2, r3, r4 = d.x[:4]
        tol = 1e-12 * t.size
        assert r2 <= r3 + tol and r3 <= r4 + tol and r4 <= r1 + tol
    # the ordering costs accuracy: the unordered optimum is lower
    free = C.fit(t, starts=8, seed=2, workers=2, **options)
    assert free.best.f < ok[0].f

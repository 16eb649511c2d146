"""Six-bars for synthesis from a curve (linkwork.synthesis.curve.six_bars, six_bar_fit):
the engine's tracer against the closed form, the exact Jacobian of the extended design
vector against central differences for both kinds and both sides, the dyads added to a
four-bar tracing its curve exactly, and a curve with a long straight stretch and corners
where the six-bars grown from the best four-bar beat it many times over."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from linkwork.errors import SynthesisError
from linkwork.synthesis import curve as C

pytest.importorskip("scipy")

VERTICAL = np.column_stack([np.full(6, 20.0), np.arange(20.0, 46.0, 5.0)])


def _d_shape() -> np.ndarray:
    """A closed D: 8 points along a straight side of 4, then 12 around a half circle
    back to the start (a corner at each end of the straight side)."""
    line = np.column_stack([np.linspace(0.0, 4.0, 9)[:-1], np.zeros(8)])
    a = np.linspace(0.0, math.pi, 13)[:-1]
    return np.vstack([line, np.column_stack([2.0 + 2.0 * np.cos(a), 2.0 * np.sin(a)])])


def _six_bars(kind: str, count: int, seed: int) -> list[tuple[C.SixBarProblem, np.ndarray]]:
    t = C.target(VERTICAL)
    rng = np.random.default_rng(seed)
    out = []
    for circuit, x in C.random_seeds(t, count, seed):
        for side, y in C.dyad_seeds((circuit, x), kind, 2, rng):
            y[13:15] = rng.uniform(-5.0, 5.0, 2)  # P off C: every dyad number matters
            out.append((C.SixBarProblem(t, kind=kind, circuit=circuit, side=side), y))
    return out


@pytest.mark.parametrize("kind", ["stephenson", "watt"])
def test_engine_tracer_equals_closed_form_and_the_dyad_matters(kind: str) -> None:
    for problem, y in _six_bars(kind, 4, 7):
        r, _ = problem.evaluate(y)
        closed = problem.points(y, y[15:])["P"]
        np.testing.assert_allclose(r.reshape(-1, 2) + problem.target.points, closed, atol=1e-9)
        # D on the other side traces another curve: the assembly is told apart
        other = C.six_bars.six_bar_points(
            y, y[15:], kind, problem.circuit, "right" if problem.side == "left" else "left"
        )["P"]
        assert np.abs(other - closed).max() > 1e-3 * problem.target.size


@pytest.mark.parametrize("kind", ["stephenson", "watt"])
def test_six_bar_jacobian_agrees_with_central_differences(kind: str) -> None:
    sides = set()
    for problem, y in _six_bars(kind, 2, 11):
        sides.add(problem.side)
        r, jac = problem.evaluate(y)
        fd = np.zeros_like(jac)
        for k in range(y.size):
            h = 1e-5 * max(1.0, abs(y[k]))
            e = np.zeros_like(y)
            e[k] = h
            fd[:, k] = (problem.evaluate(y + e)[0] - problem.evaluate(y - e)[0]) / (2.0 * h)
        assert np.abs(fd - jac).max() <= 1e-7 * np.abs(jac).max()
        # every dyad number moves P (the columns are not left zero)
        assert np.all(np.abs(jac[:, 9:15]).max(axis=0) > 1e-6)
    assert sides == {"left", "right"}


def test_a_dyad_on_the_coupler_point_traces_the_four_bar() -> None:
    t = C.target(VERTICAL)
    circuit, x = C.random_seeds(t, 1, 4)[0]
    four = C.TrackingProblem(t, circuit=circuit)
    rng = np.random.default_rng(2)
    for kind in ("stephenson", "watt"):
        for side, y in C.dyad_seeds((circuit, x), kind, 2, rng):
            six = C.SixBarProblem(t, kind=kind, circuit=circuit, side=side)
            assert six.objective(y) == pytest.approx(four.objective(x), rel=1e-9)


def test_bad_six_bar_input_is_named() -> None:
    t = C.target(VERTICAL)
    with pytest.raises(SynthesisError, match="one of stephenson, watt"):
        C.SixBarProblem(t, kind="hoeken")
    with pytest.raises(SynthesisError, match="'left' or 'right'"):
        C.SixBarProblem(t, side="up")
    with pytest.raises(SynthesisError, match="region for P"):
        C.SixBarProblem(t, regions={"P": {"centre": (0, 0), "radius": 1}})
    with pytest.raises(SynthesisError, match="has 21 entries, not 15"):
        C.SixBarProblem(t).objective(np.ones(15))
    with pytest.raises(SynthesisError, match="no four-bar to grow six-bars from"):
        C.fit_six_bars(t, four_bars=[])
    # named before any four-bar is fitted
    with pytest.raises(SynthesisError, match="one of stephenson, watt, not 'hoeken'"):
        C.fit_six_bars(t, kinds=["hoeken"])
    with pytest.raises(SynthesisError, match="region for P"):
        C.fit_six_bars(t, regions={"P": {"centre": (0, 0), "radius": 1}})


def test_six_bars_beat_the_best_four_bar_on_a_d_shape(tmp_path: Path) -> None:
    t = C.target(_d_shape(), closed=True)
    four = C.fit(t, starts=8, seed=1, workers=2)
    six = C.fit_six_bars(t, four, best=1, dyads=2, seed=1, workers=2)
    best = six.best
    # the four-bar cannot follow the straight side into the corners (f 0.24 here, the
    # largest deviation 0.25 on a curve 4 wide); a six-bar grown from it follows within 0.03
    assert four.best.f > 0.1
    assert best.f < 0.05 * four.best.f
    assert best.ok and best.grashof == "crank-rocker" and not best.cut
    # every six-bar is no worse than the four-bar it started on (the dyad starts on C)
    assert all(d.f <= four.best.f * (1.0 + 1e-9) for d in six.designs)
    # the model it gives traces the points at its crank angles, as the objective says
    th = best.crank_angles()
    res = best.model().compile().sweep(np.union1d(np.linspace(0.0, 2 * math.pi, 73), np.mod(th, 2 * math.pi)))
    at = np.searchsorted(res.times, np.mod(th, 2 * math.pi))
    traced = res.point("P").position[at]
    assert float(np.sum((traced - t.points) ** 2)) == pytest.approx(best.f, rel=1e-6)
    assert np.hypot(*(traced - t.points).T).max() == pytest.approx(best.max_deviation, rel=1e-6)
    assert 0.0 < best.transmission <= math.pi / 2 and 0.0 < best.transmission_dyad <= math.pi / 2
    assert "six-bar" in six.report() and f"{four.best.f:.4g}" in six.report()
    png = best.plot(str(tmp_path / "six.png"))[0]
    assert Path(png).stat().st_size > 10_000
    assert 'class="target' in best.to_svg()


@pytest.mark.parametrize("kind", ["stephenson", "watt"])
def test_transmission_at_d_gradient_agrees_with_central_differences(kind: str) -> None:
    t = C.target(VERTICAL)
    rng = np.random.default_rng(3)
    for circuit, x in C.random_seeds(t, 2, 5):
        for side, y in C.dyad_seeds((circuit, x), kind, 2, rng):
            y[13:15] = rng.uniform(-5.0, 5.0, 2)
            problem = C.SixBarProblem(t, kind=kind, circuit=circuit, side=side, transmission="10 deg")
            assert problem.constraint_names()[-1] == "transmission at D"
            g, dg = problem.constraints(y)
            fd = np.zeros(y.size)
            for k in range(y.size):
                h = 1e-6 * max(1.0, abs(y[k]))
                e = np.zeros_like(y)
                e[k] = h
                fd[k] = (problem.constraints(y + e)[0][-1] - problem.constraints(y - e)[0][-1]) / (2.0 * h)
            assert np.abs(fd - dg[-1]).max() <= 1e-7 * np.abs(dg[-1]).max()
            # the value is the closed form's largest |cos mu| at D over the sweep's steps on
            # the traced stretch (the first crank angle to the last: the line is open)
            times, _ = problem.grid(y)
            th = y[15:]
            times = times[np.mod(times - th[0], 2.0 * math.pi) <= th[-1] - th[0]]
            p = problem.points(y, times)
            u, v = p["C"] - p["D"], p["F"] - p["D"]
            cos = np.abs(np.sum(u * v, axis=1)) / (y[9] * y[10])
            expected = t.size * (cos.max() - math.cos(math.radians(10.0)))
            assert g[-1] == pytest.approx(expected, rel=1e-9, abs=1e-9 * t.size)


def test_a_transmission_bound_holds_at_d() -> None:
    t = C.target(VERTICAL)
    bound = math.radians(35.0)
    four = C.fit(t, starts=4, seed=1, workers=2, transmission=bound)
    six = C.fit_six_bars(t, four, best=1, dyads=4, seed=2, workers=2, transmission=bound)
    ok = [d for d in six.designs if d.ok]
    assert ok and six.designs[: len(ok)] == ok
    for d in ok:
        assert d.margins["transmission at D"] >= -1e-9
        # the screening's finer sweep (361 steps) sees the angle between the constraint's steps
        assert d.transmission_dyad >= bound - math.radians(1.0)
        assert d.transmission >= bound - math.radians(1.0)


def test_six_bars_do_not_depend_on_the_workers_and_keep_to_a_budget() -> None:
    t = C.target(VERTICAL)
    four = C.fit(t, starts=2, seed=1, workers=2, max_nfev=30)
    a = C.fit_six_bars(t, four, best=2, dyads=1, seed=4, workers=1, max_nfev=30)
    b = C.fit_six_bars(t, four, best=2, dyads=1, seed=4, workers=2, max_nfev=30, seconds=600.0)
    assert len(a.designs) + len(a.failures) == 4
    assert [d.f for d in a.designs] == [d.f for d in b.designs]
    assert all(np.array_equal(d.x, e.x) for d, e in zip(a.designs, b.designs))
    assert not b.budget_ended and "did not end the fit" in b.report()
    spent = C.fit_six_bars(t, four, best=2, dyads=1, seed=4, workers=1, seconds=0.0)
    assert spent.unstarted == 4 and spent.budget_ended
    with pytest.raises(SynthesisError, match="time budget of 0 s was spent first"):
        _ = spent.best

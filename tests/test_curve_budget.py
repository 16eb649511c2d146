"""The time budget of curve synthesis (`fit(seconds=...)`, the problem file's [fit]
seconds): a budget that does not end the fit changes nothing (the answer is the seeded
one, bit for bit); one that does stops the starts, returns the best design each had
evaluated, and says so."""

from __future__ import annotations

import time

import numpy as np
import pytest

from linkwork.errors import SynthesisError
from linkwork.synthesis import curve as C
from linkwork.synthesis.curve.problem import read_options, table

pytest.importorskip("scipy")

VERTICAL = np.column_stack([np.full(6, 20.0), np.arange(20.0, 46.0, 5.0)])


def test_a_budget_that_does_not_end_the_fit_changes_nothing() -> None:
    t = C.target(VERTICAL)
    free = C.fit(t, starts=4, seed=3, workers=2)
    timed = C.fit(t, starts=4, seed=3, workers=1, seconds=600.0)
    assert not timed.budget_ended and timed.unstarted == 0
    assert [d.f for d in timed.designs] == [d.f for d in free.designs]
    assert all(np.array_equal(a.x, b.x) for a, b in zip(timed.designs, free.designs))
    assert "every start refined to the end within the time budget" in timed.report()
    assert free.budget is None and "budget" not in free.report()


def test_a_spent_budget_stops_the_fit_with_the_best_so_far() -> None:
    t = C.target(VERTICAL)
    seeds = C.random_seeds(t, 64, seed=5)
    budget = 0.4
    t0 = time.perf_counter()
    result = C.fit(t, seeds=seeds, workers=1, seconds=budget)
    wall = time.perf_counter() - t0
    assert result.budget_ended
    # one thread: the start under way at the deadline is cut short, those after it never
    # begin; a start before it is cut only if its refinement along Grashof's limit was due
    last = max(d.start for d in result.designs)
    assert result.unstarted > 0 and next(d for d in result.designs if d.start == last).cut
    for d in result.designs:
        if d.cut and d.start != last:
            assert d.margins["grashof crank-rocker"] <= 1e-6 * t.size
    assert len(result.designs) + len(result.failures) + result.unstarted == len(seeds)
    # the clock is read at every evaluation: the fit stops within one start's screening of it
    assert wall < budget + 5.0
    cut = sum(d.cut for d in result.designs)
    assert f"the time budget of 0.4 s ended the fit: {cut} refinements cut short" in result.report()
    for d in result.designs:
        # every design returned is what it says: its f is the engine's at its x, and a cut
        # refinement is no worse than its start
        assert d.f == pytest.approx(d.problem.objective(d.x), rel=1e-12)
        start = d.problem.objective(d.problem.complete(seeds[d.start][1]))
        assert d.f <= start * (1.0 + 1e-12)
        assert ("cut short by the time budget" in str(d)) == d.cut


def test_no_time_left_names_the_budget() -> None:
    result = C.fit(C.target(VERTICAL), starts=3, seed=1, workers=1, seconds=0.0)
    assert result.designs == [] and result.unstarted == 3
    with pytest.raises(SynthesisError, match="time budget of 0 s was spent before any start"):
        _ = result.best
    with pytest.raises(SynthesisError, match="number of seconds >= 0"):
        C.fit(C.target(VERTICAL), starts=1, seconds=-1.0)
    with pytest.raises(SynthesisError, match="number of seconds"):
        C.fit(C.target(VERTICAL), starts=1, seconds="soon")


def test_the_problem_file_reads_the_budget() -> None:
    _, run = read_options({"fit": {"seconds": 12}})
    assert run["seconds"] == 12.0
    for bad in (0, -3, "10", True):
        with pytest.raises(SynthesisError, match="fit.seconds"):
            read_options({"fit": {"seconds": bad}})
    result = C.fit(C.target(VERTICAL), starts=2, seed=1, workers=1, seconds=600.0)
    assert "within the time budget of 600 s" in table(result, 2)

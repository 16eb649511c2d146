"""Positions-only and velocity-only sweeps; many designs on threads (sweep_batch)."""

from __future__ import annotations

import numpy as np
import pytest

import linkwork as lw
from helpers import revolution, spins_while
from linkwork import examples


@pytest.mark.parametrize("derivatives", [0, 1])
def test_fewer_derivatives_give_the_same_positions(derivatives):
    model = examples.four_bar().compile()
    t = revolution(n=2001)
    full = model.sweep(t)
    r = model.sweep(t, derivatives=derivatives)
    # both converge to within the Newton tolerance (1e-12 scaled) of the same solution
    assert np.max(np.abs(r.q - full.q)) < 1e-11
    assert r.qdd is None and (r.qd is None) == (derivatives == 0)
    if derivatives == 1:
        assert np.max(np.abs(r.qd - full.qd)) < 1e-9
    b = r.body("rocker")
    assert b.thetadd is None and np.array_equal(b.theta, r.q[:, 8])
    assert r.point("P").acceleration is None
    assert "rocker.theta" in r.summary()


def test_derivatives_are_checked():
    model = examples.four_bar().compile()
    with pytest.raises(lw.InputError, match="derivatives"):
        model.sweep([0.0, 0.1], derivatives=3)
    with pytest.raises(lw.InputError, match="forces"):
        model.sweep([0.0, 0.1], derivatives=1, forces=True)


def designs(n: int) -> list[lw.Model]:
    return [examples.four_bar(crank=0.16 + 0.01 * k).compile() for k in range(n)]


@pytest.mark.parametrize("threads", [1, 2])
def test_a_batch_equals_the_sweeps_one_by_one(threads):
    models = designs(5)
    t = revolution(n=721)
    calls: list[tuple[int, int]] = []
    out = lw.sweep_batch(models, t, threads=threads, progress=lambda d, n: calls.append((d, n)))
    assert len(out) == 5 and calls[-1] == (5, 5)
    for model, r in zip(models, out):
        one = model.sweep(t)
        assert np.array_equal(r.q, one.q) and np.array_equal(r.qdd, one.qdd)


@pytest.mark.parametrize("derivatives", [0, 2])
def test_a_batch_keeps_only_what_is_asked(derivatives):
    """``outputs=``: each model keeps the asked point and column, the same bits as its own
    sweep asked the same; nothing else is stored."""
    models = designs(3)
    t = revolution(n=361)
    out = lw.sweep_batch(models, t, derivatives=derivatives, outputs=["P", "rocker.theta"], threads=2)
    for model, r in zip(models, out):
        one = model.sweep(t, derivatives=derivatives, outputs=["P", "rocker.theta"])
        assert r.q.shape == (361, 1) and np.array_equal(r.q, one.q)
        assert np.array_equal(r.point("P").position, one.point("P").position)
        assert (r.qd is None) == (derivatives == 0)
        with pytest.raises(KeyError, match="not kept"):
            r.body("coupler")
    with pytest.raises(lw.InputError, match="nowhere"):
        lw.sweep_batch(models, t, outputs=["nowhere"])


def test_a_batch_with_forces_and_positions_only():
    models = designs(3)
    t = revolution(n=361)
    only_q = lw.sweep_batch(models, t, derivatives=0)
    assert all(r.qd is None for r in only_q)
    heavy = []
    for k in range(2):
        m = examples.four_bar(crank=0.18 + 0.01 * k)
        m.set_mass("coupler", 1.0, 0.01)
        m.set_gravity()
        heavy.append(m.compile())
    with_forces = lw.sweep_batch(heavy, t, forces=True)
    for model, r in zip(heavy, with_forces):
        assert np.array_equal(r.effort("crank_angle"), model.sweep(t, forces=True).effort("crank_angle"))


def test_failures_in_a_batch_are_raised_or_returned():
    good = examples.four_bar().compile()
    # a non-Grashof four-bar: its crank cannot turn fully, so the sweep fails part-way
    m = lw.Mechanism.from_dict(examples.four_bar(ground=0.35, crank=0.30, coupler=0.20, rocker=0.25,
                                                 theta0=0.6).to_dict())  # fmt: skip
    bad = m.compile()
    t = revolution(n=721)
    with pytest.raises(lw.SolveError) as info:
        lw.sweep_batch([good, bad], t)
    assert info.value.index == 1 and 0 < len(info.value.partial) < 721
    out = lw.sweep_batch([good, bad, good], t, errors="return")
    assert isinstance(out[1], lw.SolveError) and len(out[0]) == len(out[2]) == 721
    assert len(out[1].partial) == len(info.value.partial)


def test_a_batch_releases_the_gil():
    models = designs(4)
    t = np.linspace(0.0, 20.0, 200_000)
    ticks, elapsed = spins_while(lambda: lw.sweep_batch(models, t, threads=2))
    assert ticks > 20_000 * elapsed, (ticks, elapsed)


def test_every_kth_step_is_kept_with_the_worst_diagnostics():
    model = examples.four_bar().compile()
    t = revolution(n=1001)
    full = model.sweep(t)
    r = model.sweep(t, every=10)
    assert len(r) == 101 and np.array_equal(r.times, t[::10]) and np.array_equal(r.q, full.q[::10])
    assert r.pivot_ratio[5] == full.pivot_ratio[41:51].min()
    with pytest.raises(lw.InputError, match="every"):
        model.sweep(t, every=0)

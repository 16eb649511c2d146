"""Every public function's arguments thrown at with arbitrary values: each call either
works (and returns finite numbers) or raises a linkwork error naming the argument;
never a Python internal exception (TypeError, OverflowError, AttributeError...), a
panic, a hang or a NaN. Bounded: a few hundred examples, small time grids."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import linkwork as lw
from linkwork import examples

MODEL = examples.four_bar().compile()
SLIDER = examples.slider_crank().compile()

anything = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(2**70), 2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=8),
    st.lists(st.floats(-10, 10), max_size=12),
    st.lists(st.integers(-3, 3), max_size=4),
    st.dictionaries(st.text(max_size=4), st.integers(), max_size=2),
    st.just(np.array([[0.0, 1.0], [2.0, 3.0]])),
    st.just(np.arange(5, dtype=np.float64)),
    st.just(np.int64(2)),
    st.just(object()),
)
times_like = st.one_of(anything, st.lists(st.floats(-1, 1), min_size=1, max_size=20).map(sorted))
SETTINGS = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _finite(x: Any) -> None:
    if isinstance(x, np.ndarray) and x.dtype.kind == "f":
        assert np.isfinite(x).all(), "no NaN may come back silently"
    elif isinstance(x, float):
        assert math.isfinite(x)


def attempt(call: Any) -> Any:
    try:
        out = call()
    except lw.LinkworkError as e:
        assert str(e), "a named error says what is wrong"
        assert not isinstance(e, lw.InternalError), f"a panic crossed: {e}"
        return None
    return out


@SETTINGS
@given(
    times=times_like,
    derivatives=anything,
    every=anything,
    forces=anything,
    on_singular=st.one_of(anything, st.sampled_from(["continue", "stop", "switch"])),
    locks=anything,
    q_guess=anything,
)
def test_sweep_arguments(times, derivatives, every, forces, on_singular, locks, q_guess):
    res = attempt(
        lambda: MODEL.sweep(
            times,
            q_guess=q_guess,
            derivatives=derivatives,
            every=every,
            forces=forces,
            on_singular=on_singular,
            locks=locks,
        )
    )
    if res is not None:
        _finite(res.q)
        for arr in (res.qd, res.qdd):
            if arr is not None:
                _finite(arr)


@SETTINGS
@given(
    progress=anything, threads=anything, models=st.one_of(anything, st.just([MODEL, SLIDER])), errors=anything
)
def test_sweep_batch_arguments(progress, threads, models, errors):
    out = attempt(
        lambda: lw.sweep_batch(models, [0.0, 0.01], threads=threads, progress=progress, errors=errors)
    )
    if out is not None:
        for r in out:
            if isinstance(r, lw.Results):
                _finite(r.q)


@SETTINGS
@given(
    t=anything,
    q_guess=anything,
    assemble=anything,
    tries=anything,
    rng=anything,
    steps=anything,
    driver=anything,
)
def test_single_time_analyses_arguments(t, q_guess, assemble, tries, rng, steps, driver):
    st_ = attempt(lambda: MODEL.solve(t, q_guess=q_guess))
    if st_ is not None:
        _finite(st_.q)
        _finite(st_.qdd)
    s = attempt(lambda: MODEL.statics(t, q_guess=q_guess))
    if s is not None:
        _finite(s.multipliers)
    attempt(lambda: MODEL.mobility(t, q_guess=q_guess, assemble=assemble))
    attempt(lambda: MODEL.linkages(t, q_guess=q_guess))
    attempt(lambda: MODEL.assembly_modes(t, tries=tries) if isinstance(tries, int) and tries < 300 else None)
    attempt(
        lambda: MODEL.motion_limits(
            driver, t=t, range=rng, steps=steps if not isinstance(steps, int) else None
        )
    )


@SETTINGS
@given(
    desc=anything,
    options=st.dictionaries(
        st.sampled_from(
            [
                "linear",
                "tol_residual",
                "tol_step",
                "max_iter",
                "max_iter_assembly",
                "singular_tol",
                "dense_max",
                "redundant",
                "bogus",
            ]
        ),
        anything,
        max_size=3,
    ),
)
def test_model_building_arguments(desc, options):
    attempt(lambda: lw.Mechanism.from_dict(desc))
    model = attempt(lambda: examples.four_bar().compile(**options))
    if model is not None:
        # odd options (one Newton iteration) may make the sweep fail: with a named error
        res = attempt(lambda: model.sweep([0.0, 0.01]))
        if res is not None:
            _finite(res.q)


@pytest.mark.parametrize(
    "desc",
    [
        {"bodies": None},
        {"bodies": [None]},
        {"bodies": [{"name": 3}]},
        {"gravity": "down"},
        {"gravity": [1.0]},
        {"joints": [{"type": "revolute"}]},
    ],
)
def test_bad_descriptions_are_named_errors(desc):
    with pytest.raises(lw.LinkworkError):
        lw.Mechanism.from_dict(desc).compile()


@SETTINGS
@given(
    name=anything,
    p=anything,
    q=anything,
    angle=anything,
    law=st.one_of(anything, st.just(lw.Linear(0.0, 1.0))),
)
def test_mechanism_builder_arguments(name, p, q, angle, law):
    # the builder's methods: a bad name, point, angle or law is an InputError at the call
    m = lw.Mechanism("fuzz")
    m.link("crank", (0.0, 0.0), (0.1, 0.0))
    attempt(lambda: m.link(name, p, q))
    attempt(lambda: m.body(name, p, angle))
    attempt(lambda: m.revolute(m.ground, name, p))
    attempt(lambda: m.prismatic(m.ground, "crank", p, q))
    attempt(lambda: m.point(name, "crank", p))
    attempt(lambda: m.drive_angle("crank", law))
    attempt(lambda: m.compile())

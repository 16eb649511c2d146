"""Ends of a slider's travel in a kinematic sweep: an offset slider-crank whose prismatic
joint is given a travel, against the closed form x(theta) = r cos(theta) +
sqrt(l^2 - (r sin(theta) - e)^2), on every path a sweep takes, in a study, and a slide
a translation driver moves past its stops."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import linkwork as lw

R, L, E, OMEGA, THETA0 = 0.10, 0.35, 0.02, 5.0, 1.5


def x_of(theta: float, r: float = R) -> float:
    return r * math.cos(theta) + math.sqrt(L**2 - (r * math.sin(theta) - E) ** 2)


def stroke(r: float = R) -> tuple[float, float]:
    """The stroke's ends as slides from the start."""
    x0 = x_of(THETA0, r)
    return math.sqrt((L - r) ** 2 - E**2) - x0, math.sqrt((L + r) ** 2 - E**2) - x0


def slider_crank(travel: tuple[float, float] | None) -> lw.Mechanism:
    """`examples.slider_crank` (crank 0.1, rod 0.35, offset 0.02) with the slide's travel."""
    x0 = x_of(THETA0)
    a = (R * math.cos(THETA0), R * math.sin(THETA0))
    m = lw.Mechanism("slider-crank")
    crank = m.body("crank", (0.0, 0.0), THETA0)
    rod = m.body("rod", a, math.asin((E - a[1]) / L))
    slider = m.body("slider", (x0, E), 0.0)
    m.revolute(m.ground, crank, (0.0, 0.0), name="O2")
    m.revolute(crank, rod, a, name="A")
    m.revolute(rod, slider, (x0, E), name="B")
    m.prismatic(m.ground, slider, (x0, E), (1.0, 0.0), name="S", travel=travel)
    m.drive_angle(crank, lw.Linear(THETA0, OMEGA), name="crank_angle")
    return m


def closed_crossings(bound: float, t1: float) -> list[float]:
    """Where the closed-form slide crosses ``bound`` in [0, t1]: sign changes on a fine
    grid, each root by Brent to round-off."""

    def f(t: float) -> float:
        return x_of(THETA0 + OMEGA * t) - x_of(THETA0) - bound

    grid = np.linspace(0.0, t1, 20001)
    values = [f(t) for t in grid]
    return [
        brentq(f, a, b, xtol=1e-15, rtol=1e-15)
        for a, b, fa, fb in zip(grid[:-1], grid[1:], values[:-1], values[1:])
        if (fa > 0) != (fb > 0)
    ]


TIMES = np.linspace(0.0, 3 * 2 * math.pi / OMEGA, 151)  # three turns, 7.2 degrees a step


def ends(results: lw.Results) -> list[lw.Event]:
    return [e for e in results.events if e.kind == "end_of_travel"]


PATHS = [
    ("auto", {}),
    ("auto", {"derivatives": 0}),
    ("general", {}),
    ("general", {"derivatives": 0}),
]


@pytest.mark.parametrize(("solver", "kwargs"), PATHS)
def test_a_travel_inside_the_stroke_is_crossed_at_both_ends_every_turn(solver: str, kwargs: dict) -> None:
    """5 mm inside the stroke at both ends: out and back in at each end on every turn, at
    the closed form's times to 1e-9 s [measured below 1e-13: the slide solved to Newton's
    tolerance, moving at >= 0.1 m/s there], naming the joint and the end; the rows are
    those of the sweep without a travel (it goes on through the stops)."""
    lo, hi = stroke()
    travel = (lo + 0.005, hi - 0.005)
    res = slider_crank(travel).compile(solver=solver).sweep(TIMES, **kwargs)
    expected = sorted(
        [(t, "min") for t in closed_crossings(travel[0], TIMES[-1])]
        + [(t, "max") for t in closed_crossings(travel[1], TIMES[-1])]
    )
    assert len(expected) == 12
    got = ends(res)
    assert [e.output for e in got] == ["S"] * 12
    np.testing.assert_allclose([e.time for e in got], [t for t, _ in expected], rtol=0, atol=1e-9)
    for e, (_, end) in zip(got, expected):
        assert f"its {end}" in e.message and "slider 'S'" in e.message
        assert TIMES[e.step - 1] < e.time <= TIMES[e.step]
    # leaving the travel first at each end, then coming back
    outward = ["reaches the end of its travel" in e.message for e in got]
    assert outward == [True, False] * 6
    free = slider_crank(None).compile(solver=solver).sweep(TIMES, **kwargs)
    assert np.array_equal(res.q, free.q) and not ends(free)


@pytest.mark.parametrize(("solver", "kwargs"), PATHS)
def test_a_travel_covering_the_stroke_reports_none_and_one_clipping_it_each_turn(
    solver: str, kwargs: dict
) -> None:
    """Covering the stroke by 1 mm: no event. Its max 1e-7 m inside the stroke's: out and
    back in around each outer dead centre, both inside one step of the grid (found from
    the slide's turn there), at the closed form's times to 1e-9 s."""
    lo, hi = stroke()
    res = slider_crank((lo - 1e-3, hi + 1e-3)).compile(solver=solver).sweep(TIMES, **kwargs)
    assert not ends(res)
    bound = hi - 1e-7
    expected = closed_crossings(bound, TIMES[-1])
    assert len(expected) == 6
    assert all(
        np.searchsorted(TIMES, a) == np.searchsorted(TIMES, b) for a, b in zip(expected[::2], expected[1::2])
    )
    res = slider_crank((lo - 1e-3, bound)).compile(solver=solver).sweep(TIMES, **kwargs)
    got = ends(res)
    np.testing.assert_allclose([e.time for e in got], expected, rtol=0, atol=1e-9)
    assert all("its max" in e.message for e in got)


def test_a_study_counts_the_travel_ends_of_each_design() -> None:
    """A study's ``events`` count them per design, on both of its paths: a longer crank
    overruns the same travel (5 mm inside the nominal stroke) further, a shorter one
    (0.09, stroke 2 r = 0.18 against the travel's 0.19) stays inside it."""
    lo, hi = stroke()
    mech = slider_crank((lo + 0.005, hi - 0.005))
    study = lw.Study(mech, TIMES, ["events"])
    designs = [{"length crank": 0.09}, {"length crank": 0.10}, {"length crank": 0.11}]
    counts = [study.run(designs, variants=variants).figures["events"].tolist() for variants in (True, False)]
    assert counts == [[0, 12, 12], [0, 12, 12]]


def test_a_driven_slide_beyond_its_travel_is_reported() -> None:
    """A slide set by a translation driver at 0.4 m/s on a travel [-0.1, 0.5] passes the
    max at t = 1.25 (to 1e-12 s), the event naming the driver; the sweep goes on."""
    m = lw.Mechanism("driven slider")
    s = m.body("slider")
    m.prismatic(m.ground, s, at=(0.0, 0.0), axis=(1.0, 0.0), name="guide", travel=(-0.1, 0.5))
    m.drive_translation("guide", lw.Linear(0.0, 0.4), name="push")
    t = np.linspace(0.0, 2.0, 41)
    for derivatives in (0, 2):
        res = m.compile().sweep(t, derivatives=derivatives)
        (e,) = res.events
        assert e.kind == "end_of_travel" and e.output == "guide"
        assert abs(e.time - 1.25) < 1e-12
        assert "its max" in e.message and "translation driver 'push'" in e.message and "goes on" in e.message
        np.testing.assert_allclose(res.body("slider").x, 0.4 * t, rtol=0, atol=1e-12)

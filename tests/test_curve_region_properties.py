"""The region of the coupler point P holds over the traced stretch, no more and no less
(linkwork.synthesis.curve.tracking, one engine sweep each): its constraint row is the
largest distance of P outside a disc over the stretch from the first crank angle to the
last (a whole turn for a closed curve), against the closed form sampled densely, on
stretches whose largest distance is at the first and at the last crank angle, in a disc
that P leaves elsewhere in the turn."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork.synthesis import curve as C
from linkwork.synthesis.curve.tracking import coupler_points

X = np.array([2.0, 0.5, 1.8, 1.5, 0.4, 0.3, 0.2, 0.1, -0.2])  # a crank-rocker
TH = np.linspace(0.4, 2.0, 5)


def _row(closed: bool, at: float, th: np.ndarray = TH) -> tuple[float, float, float]:
    """The row of a disc around P(at) of radius 0.9 of P's largest distance from its
    centre over the stretch; that distance over the stretch and over the whole turn by
    the closed form (36,000 steps a turn and the crank angles themselves)."""
    centre = coupler_points(X, [at], "open")[0]
    t = np.union1d(np.linspace(0.0, 2 * math.pi, 36_001), th)
    far = np.hypot(*(coupler_points(X, t, "open") - centre).T)
    stretch = far[(t >= th[0]) & (t <= th[-1])].max()
    radius = 0.9 * (far.max() if closed else stretch)
    problem = C.TrackingProblem(
        C.target(coupler_points(X, th, "open"), closed=closed),
        regions={"P": {"centre": centre.tolist(), "radius": radius}},
    )
    g, _ = problem.constraints(np.concatenate([X, th]))
    row = dict(zip(problem.constraint_names(), g, strict=True))["region P"]
    return float(row) + radius, float(stretch), float(far.max())


@pytest.mark.parametrize(
    ("at", "end"),
    [(1.7, 0), (1.2, -1)],  # P's farthest point of the stretch from P(1.7): its start; from P(1.2): its end
)
def test_the_region_of_p_is_held_over_the_open_stretch_only(at: float, end: int) -> None:
    """The farthest point is a crank angle, a step of the sweep: the row is the closed
    form's to the engine's accuracy. P goes 0.5 farther elsewhere in the turn, and a
    stretch cut at the second angle, or carried past the last, would give another value."""
    got, stretch, turn = _row(False, at)
    assert got == pytest.approx(stretch, abs=1e-9)
    centre = coupler_points(X, [at], "open")[0]
    assert np.hypot(*(coupler_points(X, [TH[end]], "open")[0] - centre)) == pytest.approx(stretch, abs=1e-12)
    assert turn > stretch + 0.4
    shorter = _row(False, at, TH[1:])[0] if end == 0 else _row(False, at, np.append(TH, 2.4))[0]
    assert abs(shorter - got) > 0.05


def test_the_region_of_p_is_held_over_the_whole_turn_of_a_closed_curve() -> None:
    """Closed: the whole turn, sampled by the sweep at a degree a step, approaches the
    largest distance from below, within (h / 2)^2 / 2 |f''| < 2e-5 (h = 2 pi / 360; the
    distance's |f''| < 0.4 within a step of its largest, at theta2 = 4.53)."""
    got, stretch, turn = _row(True, 1.7)
    assert turn > stretch + 0.4
    assert -2e-5 <= got - turn <= 1e-9


def test_the_region_of_p_is_held_over_a_stretch_late_in_the_turn() -> None:
    """A stretch from 4.0 to 5.5 rad (its angles add up past a turn, its span is less):
    held over the stretch only; P's farthest point from P(4.8) there is its end, 0.32
    away, and 1.0 elsewhere in the turn."""
    th = np.linspace(4.0, 5.5, 5)
    got, stretch, turn = _row(False, 4.8, th)
    assert got == pytest.approx(stretch, abs=1e-9)
    assert turn > stretch + 0.4


@pytest.mark.parametrize(("at", "angle"), [(1.7, 0), (1.2, 4)])
def test_the_rows_gradient_in_the_crank_angle_at_the_farthest_point(at: float, angle: int) -> None:
    """Where P's farthest point is a crank angle's own sample (the first, seen from
    P(1.7); the last, from P(1.2)), the row moves with that angle alone: its gradient in
    it is the central difference's (h = 1e-6: agreement to 1e-7 of the row's scale),
    and zero in the other crank angles."""
    centre = coupler_points(X, [at], "open")[0]
    problem = C.TrackingProblem(
        C.target(coupler_points(X, TH, "open")), regions={"P": {"centre": centre.tolist(), "radius": 0.1}}
    )
    row = problem.constraint_names().index("region P")
    x = np.concatenate([X, TH])
    _, jac = problem.constraints(x)
    h = 1e-6
    for i in range(9, 9 + len(TH)):
        e = np.zeros_like(x)
        e[i] = h
        fd = (problem.constraints(x + e)[0][row] - problem.constraints(x - e)[0][row]) / (2 * h)
        assert jac[row, i] == pytest.approx(fd, abs=1e-7)
        assert (abs(jac[row, i]) > 0.1) == (i == 9 + angle)


def test_the_violation_is_the_region_rows_excess_and_zero_inside() -> None:
    x = np.concatenate([X, TH])
    for radius, outside in ((0.3, True), (5.0, False)):
        problem = C.TrackingProblem(
            C.target(coupler_points(X, TH, "open")), regions={"P": {"centre": [0.0, 0.5], "radius": radius}}
        )
        g, _ = problem.constraints(x)
        assert (g.max() > 0.0) == outside
        assert problem.violation(x) == (float(g.max()) if outside else 0.0)

"""The designer's constraints of curve synthesis (linkwork.synthesis.curve.constraints):
their exact gradients against central differences, contradictions by name, and the
refined designs holding them with their margins."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from linkwork.errors import SynthesisError
from linkwork.synthesis import curve as C
from linkwork.synthesis.curve import constraints as K

pytest.importorskip("scipy")

# Kunjur and Krishnamurty's 18-point closed curve (as in examples/synthesis/kunjur_18pt.csv)
KUNJUR = np.loadtxt(
    Path(__file__).parents[1] / "examples" / "synthesis" / "kunjur_18pt.csv", delimiter=",", skiprows=1
)
OPEN = KUNJUR[:9]


def _design(open_curve: bool) -> tuple[C.TrackingProblem, np.ndarray]:
    """A crank-rocker and crank angles over most of a turn (open: 1 to 6.5 rad, so the
    stretch holds theta2 = pi and 2 pi inside it)."""
    t = C.target(OPEN if open_curve else KUNJUR, closed=not open_curve)
    n = len(t)
    th = np.linspace(1.0, 6.5, n) if open_curve else np.linspace(0.3, 0.3 + 2 * math.pi * (n - 1) / n, n)
    x = np.concatenate([[2.0, 0.5, 1.8, 1.5, 0.4, 0.3, 0.2, 0.1, -0.2], th])
    problem = C.TrackingProblem(
        t,
        transmission="20 deg",
        ratio=(1.0, 8.0),
        regions={
            "O2": {"centre": [0.0, 0.0], "radius": 0.1},
            "O4": {"x": [0.0, 1.0], "y": [0.0, 1.0]},
            "P": {"centre": [0.3, 0.6], "radius": 0.5},
        },
    )
    return problem, x


def _central(fun, x: np.ndarray, h: float) -> np.ndarray:
    cols = []
    for k in range(x.size):
        e = np.zeros(x.size)
        e[k] = h * max(1.0, abs(x[k]))
        cols.append((fun(x + e) - fun(x - e)) / (2.0 * e[k]))
    return np.array(cols).T


@pytest.mark.parametrize("open_curve", [True, False])
def test_transmission_gradient_is_exact(open_curve: bool) -> None:
    problem, x = _design(open_curve)
    mu, grad = K.smallest_transmission(x, problem.target.closed)
    fd = _central(lambda y: np.array([K.smallest_transmission(y, problem.target.closed)[0]]), x, 1e-6)[0]
    assert np.max(np.abs(fd - grad)) <= 1e-7 * np.max(np.abs(grad))
    # the closed form's smallest angle is the smallest over a fine sampling of the stretch
    # (which approaches it from above, to second order in its step of 3e-4 rad)
    th = np.linspace(x[9], x[-1], 20001) if open_curve else np.linspace(0.0, 2 * math.pi, 20001)
    c, _ = K.transmission_cos(x[:4], th)
    assert -1e-15 <= float(np.arccos(np.abs(c).max())) - mu <= 1e-7
    if open_curve:  # an end of the stretch and pi are among the candidates
        assert set(np.round(K.stretch_angles(x, False)[0], 12)) == {
            1.0,
            6.5,
            round(math.pi, 12),
            round(2 * math.pi, 12),
        }


@pytest.mark.parametrize("open_curve", [True, False])
def test_constraint_jacobian_is_exact(open_curve: bool) -> None:
    """Every constraint row's gradient against central differences; P's region through
    the engine's sweep (its sensitivities) as well."""
    problem, x = _design(open_curve)
    g, dg = problem.constraints(x)
    assert g.shape == (len(problem.constraint_names()),)
    fd = _central(lambda y: problem.constraints(y)[0], x, 1e-6)
    # P's region: differences of the engine's sweep (solved to ~1e-13) carry ~1e-7 noise
    for row, name in enumerate(problem.constraint_names()):
        scale = max(1.0, float(np.max(np.abs(dg[row]))))
        tol = 1e-6 if name == "region P" else 1e-7
        assert np.max(np.abs(fd[row] - dg[row])) <= tol * scale, name


def test_contradictory_constraints_are_named() -> None:
    t = C.target(KUNJUR, closed=True)
    cases = [
        ({"transmission": "100 deg"}, "contradictory transmission bound '100 deg'"),
        ({"transmission": 1.7}, "contradictory transmission bound 1.7"),
        ({"transmission": "forty"}, "transmission is a number with its unit"),
        ({"ratio": (4.0, 2.0)}, "contradictory ratio .* bounds: lower 4.0 > upper 2.0"),
        ({"ratio": (0.2, 0.5)}, "contradictory ratio: the longest link"),
        ({"ratio": (50.0, 60.0), "lengths": (1.0, 10.0)}, r"contradictory constraints: ratio >= 50"),
        ({"links": {"r2": (3.0, 1.0)}}, "contradictory link r2 bounds"),
        ({"links": {"r2": (30.0, 40.0)}, "lengths": (0.1, 10.0)}, "contradictory range of link r2"),
        ({"links": {"r7": (1.0, 2.0)}}, "links ranges are for r1, r2, r3, r4"),
        ({"regions": {"O4": {"x": [1.0, 0.0], "y": [0.0, 1.0]}}}, "contradictory region O4: an empty box, x"),
        (
            {"regions": {"P": {"centre": [0.0, 0.0], "radius": 0.0}}},
            "contradictory region P: a disc of radius",
        ),
        ({"regions": {"O3": {"centre": [0.0, 0.0], "radius": 1.0}}}, "regions are for O2, O4, P"),
        ({"regions": {"O2": {"x": [0.0, 1.0]}}}, "region O2: a box has keys x and y"),
        (
            {"regions": {"O2": {"x": [50.0, 60.0], "y": [0.0, 1.0]}}},
            "region of O2 .* outside the pivot bounds",
        ),
        ({"grashof": "double-crank", "ordered": True}, "contradictory constraints: ordered"),
        ({"grashof": "drag-link"}, "grashof is one of crank-rocker, double-crank, full-turn"),
    ]
    for options, message in cases:
        with pytest.raises(SynthesisError, match=message):
            C.TrackingProblem(t, **options)
    with pytest.raises(SynthesisError, match="O2 is fixed outside its region"):
        C.TrackingProblem(
            t, fixed={"x0": 2.0, "y0": 0.0}, regions={"O2": {"centre": [0.0, 0.0], "radius": 1.0}}
        )


def test_angles_state_their_unit() -> None:
    assert K.angle("a", "40 deg") == pytest.approx(math.radians(40.0), rel=1e-15)
    assert K.angle("a", "0.5 rad") == 0.5
    assert K.angle("a", 0.5) == 0.5


def test_refined_designs_hold_the_constraints() -> None:
    """On Kunjur's curve with a transmission bound, a ratio range, a box for O2, a disc
    for O4 and a disc for P: the designs counted within the constraints have every margin
    >= 0 (to 1e-9 of the curve's size), and the best of them is such a design."""
    t = C.target(KUNJUR, closed=True)
    options = {
        "transmission": "35 deg",
        "ratio": (1.5, 6.0),
        "regions": {
            "O2": {"x": [-1.0, 0.5], "y": [-1.0, 0.5]},
            "O4": {"centre": [0.5, 0.0], "radius": 2.0},
            "P": {"centre": [0.3, 0.65], "radius": 0.7},
        },
    }
    result = C.fit(t, starts=6, seed=1, max_nfev=150, workers=2, **options)
    best = result.best
    assert best.ok
    tol = 1e-9 * t.size
    for d in result.designs:
        if d.ok:
            assert set(d.margins) == {
                "grashof crank-rocker",
                "ratio",
                "transmission",
                "region O2",
                "region O4",
                "region P",
            }
            assert min(d.margins.values()) >= -tol, d.margins
            # the exact smallest transmission angle is at most the engine's sampled one
            assert d.transmission >= math.radians(35.0) - tol
    # the unconstrained problem reaches a smaller error: the constraints bind
    free = C.fit(t, starts=6, seed=1, max_nfev=150, workers=2)
    assert free.best.f < best.f


def test_double_crank() -> None:
    """grashof="double-crank": the ground is the shortest link and the crank turns fully
    (with a transmission bound: unbounded, the fit runs to the change point s + l = p + q
    where the crank meets a dead point)."""
    t = C.target(KUNJUR, closed=True)
    result = C.fit(
        t, starts=4, seed=2, max_nfev=100, workers=2, grashof="double-crank", transmission="20 deg"
    )
    best = result.best
    r = best.x[:4]
    assert best.ok
    assert r[0] <= r[1:].min()
    assert best.grashof == "double-crank"
    assert min(best.margins.values()) >= -1e-9 * t.size


def test_link_ranges_are_bounds() -> None:
    """links = {"r2": ..., "r3": ...}: bounds the refinement never leaves; their margins."""
    t = C.target(OPEN)
    result = C.fit(t, starts=3, seed=4, max_nfev=60, workers=2, links={"r2": (0.2, 0.3), "r3": (0.8, 1.2)})
    for d in result.designs:
        assert 0.2 <= d.x[1] <= 0.3 and 0.8 <= d.x[2] <= 1.2
        assert min(d.margins["link r2"], d.margins["link r3"]) >= 0.0
        assert d.margins["link r2"] == pytest.approx(min(d.x[1] - 0.2, 0.3 - d.x[1]), abs=1e-15)

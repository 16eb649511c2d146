"""Properties of a curve-synthesis problem's constraints that decide which designs hold,
fast and without the engine (no region for P): each residual is the textbook quantity
(Grashof's s + l - p - q, the shortest link's excess, the ratio's bounds, the signed
distance of O2 and O4 outside their regions), it is <= 0 exactly when the constraint
holds, the margins say the same in their own units, and the Jacobian of every row
matches central differences."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork.errors import SynthesisError
from linkwork.synthesis import curve as C
from linkwork.synthesis.curve import constraints as K

POINTS = np.array([[0.0, 0.0], [1.0, 0.2], [1.5, 1.0], [1.0, 1.8], [0.2, 1.5]])
TH = np.linspace(0.5, 4.0, 5)  # pi inside the stretch


def _x(r, rc=(0.4, 0.3), th0=0.2, o2=(0.1, -0.2), th=TH) -> np.ndarray:
    return np.concatenate([r, rc, [th0], o2, th])


def _rows(problem: C.TrackingProblem, x: np.ndarray) -> dict[str, float]:
    g, _ = problem.constraints(x)
    return dict(zip(problem.constraint_names(), g, strict=True))


def test_grashof_rows_are_the_textbook_quantities_for_each_type() -> None:
    """r = (2.0, 0.5, 1.8, 1.5): s = 0.5 (the crank), l = 2.0, p + q = 3.3: s + l - p - q
    = -0.8; the crank's excess over r1, r3, r4 is -1.5, -1.3, -1.0. Shuffled so that the
    ground is the shortest, the crank-rocker's rows fail and the double-crank's hold."""
    t = C.target(POINTS)
    rocker = _rows(C.TrackingProblem(t), _x([2.0, 0.5, 1.8, 1.5]))
    assert rocker == pytest.approx(
        {
            "crank shortest (r2 <= r1)": -1.5,
            "crank shortest (r2 <= r3)": -1.3,
            "crank shortest (r2 <= r4)": -1.0,
            "grashof (s + l <= p + q)": -0.8,
        },
        abs=1e-15,
    )
    swapped = _x([0.5, 2.0, 1.8, 1.5])
    assert max(_rows(C.TrackingProblem(t), swapped).values()) == pytest.approx(1.5, abs=1e-15)
    double = _rows(C.TrackingProblem(t, grashof="double-crank"), swapped)
    assert double == pytest.approx(
        {
            "ground shortest (r1 <= r2)": -1.5,
            "ground shortest (r1 <= r3)": -1.3,
            "ground shortest (r1 <= r4)": -1.0,
            "grashof (s + l <= p + q)": -0.8,
        },
        abs=1e-15,
    )
    # a non-Grashof chain fails the Grashof row whichever link is the crank: 0.5 + 3 > 1.8 + 1.5
    assert _rows(C.TrackingProblem(t, grashof="full-turn"), _x([3.0, 0.5, 1.8, 1.5])) == pytest.approx(
        {"grashof (s + l <= p + q)": 0.2}, abs=1e-15
    )


def test_ratio_ordering_and_one_turn_rows() -> None:
    t = C.target(POINTS, closed=True)
    n = len(t)
    problem = C.TrackingProblem(t, ordered=True, ratio=(2.0, 3.0))
    th = np.linspace(0.5, 0.5 + 2 * math.pi * (n - 1) / n, n)
    rows = _rows(problem, _x([2.0, 0.5, 1.2, 1.5], th=th))  # l / s = 4: above the ratio's 3
    assert rows == pytest.approx(
        {
            "crank shortest (r2 <= r1)": -1.5,
            "crank shortest (r2 <= r3)": -0.7,
            "crank shortest (r2 <= r4)": -1.0,
            "grashof (s + l <= p + q)": -0.2,
            "ordered (r3 <= r4)": -0.3,
            "ordered (r4 <= r1)": -0.5,
            "within one turn": th[-1] - th[0] - 2 * math.pi,
            "ratio upper": 2.0 - 3.0 * 0.5,
            "ratio lower": 2.0 * 0.5 - 2.0,
        },
        abs=1e-15,
    )
    assert rows["within one turn"] < 0.0 and rows["ratio upper"] > 0.0
    assert problem.violation(_x([2.0, 0.5, 1.2, 1.5], th=th)) == pytest.approx(0.5, abs=1e-15)
    # an unbounded ratio above never binds, and the design then holds every constraint
    open_top = C.TrackingProblem(t, ordered=True, ratio=(2.0, math.inf))
    rows = _rows(open_top, _x([2.0, 0.5, 1.2, 1.5], th=th))
    assert rows["ratio upper"] == -1.0 and open_top.violation(_x([2.0, 0.5, 1.2, 1.5], th=th)) == 0.0


def test_pivot_regions_are_distances_of_o2_and_o4_outside_them() -> None:
    """O2 at (0.1, -0.2), theta0 = 0.2, r1 = 2: O4 = O2 + 2 (cos 0.2, sin 0.2)."""
    t = C.target(POINTS)
    o4 = np.array([0.1, -0.2]) + 2.0 * np.array([math.cos(0.2), math.sin(0.2)])
    problem = C.TrackingProblem(
        t,
        regions={"O2": {"centre": [0.0, 0.0], "radius": 0.1}, "O4": {"x": [0.0, 1.0], "y": [0.0, 1.0]}},
    )
    rows = _rows(problem, _x([2.0, 0.5, 1.8, 1.5]))
    assert rows["region O2"] == pytest.approx(math.hypot(0.1, 0.2) - 0.1, abs=1e-15)
    assert rows["region O4"] == pytest.approx(o4[0] - 1.0, abs=1e-15)
    margins = problem.margins(_x([2.0, 0.5, 1.8, 1.5]))
    assert margins["region O2"] == pytest.approx(-rows["region O2"], abs=0.0)
    assert margins["region O4"] == pytest.approx(-rows["region O4"], abs=0.0)


@pytest.mark.parametrize("grashof", ["crank-rocker", "double-crank", "full-turn"])
def test_margins_are_non_negative_exactly_when_the_constraints_hold(grashof: str) -> None:
    """Over designs scattered about a crank-rocker (a double-crank for that type), each
    margin's sign agrees with its rows' (margins in their own units: the ratio in the
    ratio, the transmission in rad), and the margins' values are the textbook ones."""
    t = C.target(POINTS)
    base = [0.6, 2.0, 1.8, 1.5] if grashof == "double-crank" else [2.0, 0.5, 1.8, 1.5]
    o4 = np.array([0.1, -0.2]) + base[0] * np.array([math.cos(0.2), math.sin(0.2)])
    problem = C.TrackingProblem(
        t,
        grashof=grashof,
        ordered=grashof == "crank-rocker",
        ratio=(1.5, 4.0),
        transmission="25 deg",
        links={"r3": (1.0, 2.0)},
        regions={"O4": {"centre": list(o4), "radius": 0.3}},
    )
    rng = np.random.default_rng(38)
    names = problem.constraint_names()
    held = 0
    for _ in range(200):
        r = np.array(base) * rng.uniform(0.4, 1.6, 4)  # the shortest link changes in some
        x = _x(r)
        g, _ = problem.constraints(x)
        m = problem.margins(x)
        s = np.sort(r)
        grashof_rows = [v for n, v in zip(names, g, strict=True) if "shortest" in n or "grashof" in n]
        assert (m[f"grashof {grashof}"] >= 0.0) == (max(grashof_rows) <= 0.0)
        assert m[f"grashof {grashof}"] == pytest.approx(-max(grashof_rows), abs=1e-15)
        if grashof == "crank-rocker":
            assert m["ordered"] == pytest.approx(min(r[2] - r[1], r[3] - r[2], r[0] - r[3]), abs=1e-15)
        assert m["ratio"] == pytest.approx(min(s[3] / s[0] - 1.5, 4.0 - s[3] / s[0]), abs=1e-14)
        assert (m["ratio"] >= 0.0) == (
            max(g[names.index("ratio upper")], g[names.index("ratio lower")]) <= 0.0
        )
        mu = K.smallest_transmission(x, False)[0]
        assert m["transmission"] == pytest.approx(mu - math.radians(25.0), abs=1e-15)
        assert (m["transmission"] >= 0.0) == (g[names.index("transmission")] <= 0.0)
        assert m["link r3"] == pytest.approx(min(r[2] - 1.0, 2.0 - r[2]), abs=1e-15)
        ok = min(m.values()) >= 0.0
        held += ok
        # the link range is a bound, not a row: the rows alone decide the violation
        rows_hold = bool(np.all(g <= 0.0))
        assert (problem.violation(x) == 0.0) == rows_hold
        assert problem.violation(x) == pytest.approx(max(0.0, float(g.max())), abs=0.0)
    assert 0 < held < 200  # both outcomes were seen


@pytest.mark.parametrize("closed", [False, True])
def test_every_row_has_an_exact_gradient(closed: bool) -> None:
    t = C.target(POINTS, closed=closed)
    n = len(t)
    th = np.linspace(0.5, 0.5 + 2 * math.pi * (n - 1) / n, n) if closed else TH
    x = _x([2.0, 0.5, 1.7, 1.5], th=th)
    for options in (
        {"ordered": True, "ratio": (1.0, 8.0), "transmission": "20 deg"},
        {"grashof": "double-crank", "regions": {"O4": {"x": [0.0, 1.0], "y": [0.0, 1.0]}}},
        {"grashof": "full-turn", "regions": {"O2": {"centre": [0.5, 0.5], "radius": 0.2}}},
        {"regions": {"O4": {"x": [0.0, 5.0], "y": [1.0, 2.0]}}},  # O4 below it: binding in y
    ):
        problem = C.TrackingProblem(t, **options)
        _, dg = problem.constraints(x)
        for k in range(x.size):
            e = np.zeros(x.size)
            e[k] = 1e-6 * max(1.0, abs(x[k]))
            fd = (problem.constraints(x + e)[0] - problem.constraints(x - e)[0]) / (2 * e[k])
            np.testing.assert_allclose(dg[:, k], fd, rtol=0.0, atol=1e-7 * max(1.0, np.abs(dg).max()))


def test_bounds_free_entries_and_completion() -> None:
    """Link ranges narrow the lengths' bounds, a box for O2 narrows the pivot's; fixed
    entries and prescribed crank angles are not free and `complete` sets them."""
    t = C.target(POINTS)
    problem = C.TrackingProblem(
        t,
        lengths=(0.1, 5.0),
        pivot=(-3.0, 3.0),
        links={"r2": (0.05, 0.8), "r4": (1.0, 9.0)},
        regions={"O2": {"x": [-1.0, 4.0], "y": [0.5, 1.0]}},
        fixed={"theta0": 0.3},
    )
    lo, hi = problem.lower_upper()
    c = 10.0 * t.size  # the coupler point's default bound
    inf = [math.inf] * len(t)  # the crank angles: unbounded
    np.testing.assert_array_equal(
        lo, [0.1, 0.1, 0.1, 1.0, -c, -c, -2 * math.pi, -1.0, 0.5, *(-np.array(inf))]
    )
    np.testing.assert_array_equal(hi, [5.0, 0.8, 5.0, 5.0, c, c, 2 * math.pi, 3.0, 1.0, *inf])
    np.testing.assert_array_equal(problem.free(), [True] * 6 + [False] + [True] * (2 + len(t)))
    assert problem.complete(np.zeros(9 + len(t)))[6] == 0.3
    timed = C.TrackingProblem(C.target(POINTS, crank_angles=TH), fixed={"x0": 0.5, "y0": -0.5})
    assert not np.any(timed.free()[9:]) and not np.any(timed.free()[7:9]) and np.all(timed.free()[:7])
    x = timed.complete(np.zeros(9 + len(t)))
    np.testing.assert_array_equal(x[7:], np.concatenate([[0.5, -0.5], TH]))
    with pytest.raises(SynthesisError, match=f"has {9 + len(t)} entries, not 3"):
        problem.complete([1.0, 2.0, 3.0])


def test_constraints_on_the_boundary_are_consistent_and_beyond_it_contradictory() -> None:
    """Bounds met with equality are stated constraints; beyond them, named contradictions."""
    t = C.target(POINTS)
    lengths = (0.5, 2.0)
    C.TrackingProblem(t, transmission="90 deg")
    C.TrackingProblem(t, transmission=0.0)
    C.TrackingProblem(t, ratio=(1.0, 1.0))
    C.TrackingProblem(t, lengths=lengths, ratio=(4.0, 5.0))  # 4 = 2.0 / 0.5: reachable
    C.TrackingProblem(t, lengths=lengths, links={"r2": (2.0, 3.0)})  # meets the bound at 2.0
    C.TrackingProblem(t, regions={"O2": {"centre": [0.0, 0.0], "radius": 1.0}}, fixed={"x0": 1.0, "y0": 0.0})
    C.TrackingProblem(t, regions={"O2": {"x": [1.0, 1.0], "y": [0.0, 1.0]}})  # O2 on a segment
    cases = [
        ({"transmission": "-1 deg"}, "contradictory transmission bound"),
        ({"transmission": "90.001 deg"}, "contradictory transmission bound"),
        ({"ratio": (1.0, 0.999)}, "contradictory ratio"),
        ({"lengths": lengths, "ratio": (4.001, 5.0)}, "ratio >= 4.001 with lengths"),
        ({"lengths": lengths, "links": {"r2": (2.001, 3.0)}}, "contradictory range of link r2"),
        ({"ordered": True, "grashof": "full-turn"}, "ordered"),
        (
            {"regions": {"O2": {"centre": [0.0, 0.0], "radius": 1.0}}, "fixed": {"x0": 1.001, "y0": 0.0}},
            "O2 is fixed outside its region",
        ),
        ({"regions": {"O2": {"x": [50.0, 60.0], "y": [0.0, 1.0]}}}, "outside the pivot bounds"),
        ({"regions": {"O2": {"x": [-60.0, -50.0], "y": [0.0, 1.0]}}}, "outside the pivot bounds"),
        ({"regions": {"O2": {"x": [0.0, 1.0], "y": [50.0, 60.0]}}}, "outside the pivot bounds"),
        ({"lengths": (0.0, 1.0)}, "must be > 0"),
        ({"lengths": (math.nan, 1.0)}, r"length bounds must be numbers, got \(nan, 1.0\)"),
        ({"pivot": (-1.0, math.nan)}, r"pivot bounds must be numbers, got \(-1.0, nan\)"),
        ({"coupler": (1.0,)}, r"coupler point bounds are \(lower, upper\) numbers, not \(1.0,\)"),
        ({"links": {"rcx": (0.0, 1.0)}}, "links ranges are for r1, r2, r3, r4, not 'rcx'"),
    ]
    for options, message in cases:
        with pytest.raises(SynthesisError, match=message):
            C.TrackingProblem(t, **options)

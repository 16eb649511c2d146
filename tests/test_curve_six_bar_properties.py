"""Properties of how six-bar curve designs are started and screened
(linkwork.synthesis.curve.six_bar_fit), fast (one engine sweep each, no refinement): the
dyads added to a four-bar assemble over the whole crank turn within the stated ranges,
with P on C; the screening finds no defect on a six-bar that traces its four-bar's curve
forwards, and its smallest transmission angles at B and at D are the closed form's over
the traced stretch only, at the sweep's steps; crank angles out of order, a four-bar loop
that cannot turn through the stretch, a dyad too short to follow C, a traced point off
the closed form by more than 1e-7 of the scale, and a sweep that gives no row are each
reported as the defect they are."""

from __future__ import annotations

import importlib
import inspect
import math
import time
from typing import Any

import numpy as np
import pytest

from linkwork.errors import SolveError, SynthesisError
from linkwork.synthesis import curve as C
from linkwork.synthesis.curve import constraints as K
from linkwork.synthesis.curve.tracking import coupler_points

SB = importlib.import_module("linkwork.synthesis.curve.six_bar_fit")

X = np.array([2.0, 0.5, 1.8, 1.5, 0.4, 0.3, 0.2, 0.1, -0.2])  # a crank-rocker
TH = np.array([0.4, 1.3, 2.0, 3.9, 5.0])


def _target(th: np.ndarray = TH, closed: bool = False) -> C.TargetCurve:
    return C.target(coupler_points(X, th, "open"), closed=closed)


def _six_bar(kind: str, side_index: int = 0, th: np.ndarray = TH, closed: bool = False, seed: int = 3):
    """A six-bar of the crank-rocker X with a dyad from `dyad_seeds` (P at C: it traces
    X's coupler curve), on the target X traces at the crank angles ``th``."""
    side, y = SB.dyad_seeds(("open", np.concatenate([X, th])), kind, 2, np.random.default_rng(seed))[
        side_index
    ]
    return C.SixBarProblem(_target(th, closed), kind=kind, side=side), y


def _angle_from_0_or_pi(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    mu = np.arccos(np.clip(np.sum(u * v, axis=1) / (np.hypot(*u.T) * np.hypot(*v.T)), -1.0, 1.0))
    return np.minimum(mu, math.pi - mu)


def _stretch_angles(problem: C.SixBarProblem, y: np.ndarray) -> tuple[float, float, float, float]:
    """The smallest transmission angles at B and at D by the closed form at the screening
    sweep's steps: over the traced stretch, and over the whole sweep (lead-in included)."""
    _, times, first = SB.screened_stretch(y[problem.size :], problem.target.closed)
    p = problem.points(y, times)
    on = times >= first - 1e-12
    b = _angle_from_0_or_pi(p["A"] - p["B"], p["O4"] - p["B"])
    d = _angle_from_0_or_pi(p["C"] - p["D"], p["F"] - p["D"])
    return float(b[on].min()), float(d[on].min()), float(b.min()), float(d.min())


# ---- the dyads --------------------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["stephenson", "watt"])
def test_dyad_seeds_assemble_over_the_whole_turn_within_the_stated_ranges(kind: str) -> None:
    x = np.concatenate([X, TH])
    out = SB.dyad_seeds(("open", x), kind, 6, np.random.default_rng(5))
    assert len(out) == 6 and [s for s, _ in out] == ["left", "right"] * 3
    th = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
    c = coupler_points(X, th, "open")
    centre = c.mean(axis=0)
    radius = np.hypot(*(c - centre).T).max()
    for side, y in out:
        np.testing.assert_array_equal(y[:9], X)
        np.testing.assert_array_equal(y[15:], TH)
        assert np.array_equal(y[13:15], [0.0, 0.0])  # P at C
        pts = C.six_bars.six_bar_points(y, th, kind, "open", side)
        np.testing.assert_allclose(pts["P"], c, atol=1e-12)  # it traces the four-bar's curve
        assert np.all(np.isfinite(pts["D"]))  # the dyad assembles over the whole turn
        d = np.hypot(*(pts["C"] - pts["F"]).T)
        r5, r6 = y[9:11]
        # the sampling of dyad_seeds (360 steps) sees the extremes to within 1e-4 of them
        assert 1.15 * d.max() * (1 - 1e-4) <= r5 + r6 <= 1.6 * d.max() * (1 + 1e-4)
        assert abs(r5 - r6) <= 0.8 * d.min() * (1 + 1e-4)
        if kind == "stephenson":
            assert 1.3 * radius * (1 - 1e-3) <= np.hypot(*(y[11:13] - centre)) <= 3.0 * radius * (1 + 1e-3)
        else:  # E on the rocker, within (-1, 2) x (-1.5, 1.5) of its length
            assert -1.0 <= y[11] / X[3] <= 2.0 and -1.5 <= y[12] / X[3] <= 1.5
    # the same generator gives the same dyads; a CurveDesign is taken as its (circuit, x)
    again = SB.dyad_seeds(("open", x), kind, 6, np.random.default_rng(5))
    assert all(np.array_equal(a[1], b[1]) for a, b in zip(out, again))


def test_a_four_bar_that_does_not_turn_fully_gets_no_dyad() -> None:
    x = np.concatenate([[2.0, 1.0, 1.2, 1.5], X[4:], TH])  # not Grashof: no full turn
    with pytest.raises(SynthesisError, match="does not turn fully"):
        SB.dyad_seeds(("open", x), "stephenson", 2, np.random.default_rng(0))
    assert SB.dyad_seeds(("open", np.concatenate([X, TH])), "watt", 0, np.random.default_rng(0)) == []


def test_the_smallest_angle_between_bars_is_measured_from_0_or_180_degrees() -> None:
    u = np.array([[1.0, 0.0], [1.0, 0.0], [1.0, 0.0]])
    for angle in (0.3, math.pi - 0.3, math.pi / 2):
        v = np.array([[math.cos(a), math.sin(a)] for a in (angle, math.pi / 2, 2.0)]) * [[2.0], [3.0], [0.5]]
        assert SB._smallest(u, v) == pytest.approx(min(angle, math.pi - angle, math.pi - 2.0), abs=1e-12)
    assert SB._smallest(u, -u) == 0.0 and SB._smallest(u[:0], u[:0]) == 0.0
    # parallel bars whose cosine rounds to 1 + 2e-16: 0, not a domain error
    w = np.array([[2.1444256595254156, -2.798486548167214]])
    assert SB._smallest(w, w * 3.6753116875067264) == 0.0


# ---- the screening ---------------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["stephenson", "watt"])
@pytest.mark.parametrize("side_index", [0, 1])
def test_a_six_bar_traced_forwards_is_defect_free_with_the_closed_forms_angles(
    kind: str, side_index: int
) -> None:
    problem, y = _six_bar(kind, side_index)
    defects, mu_b, mu_d, grashof = SB._screen(problem, y)
    assert defects == () and grashof == "crank-rocker"
    b, d, _, _ = _stretch_angles(problem, y)
    # the engine's positions against the closed form's: equal to its solve tolerance
    assert mu_b == pytest.approx(b, abs=1e-9) and mu_d == pytest.approx(d, abs=1e-9)
    # and at B the exact smallest angle over the stretch, approached from above
    assert -1e-12 <= mu_b - K.smallest_transmission(np.concatenate([X, TH]), closed=False)[0] <= 1e-4


@pytest.mark.parametrize("kind", ["stephenson", "watt"])
def test_the_angles_are_over_the_traced_stretch_only(kind: str) -> None:
    """A stretch from 4.0 to 5.5 rad: the lead-in from the drawing (0) passes the four-bar's
    smallest angle (at theta2 = 0), which does not count."""
    th = np.linspace(4.0, 5.5, 5)
    problem, y = _six_bar(kind, th=th)
    defects, mu_b, mu_d, _ = SB._screen(problem, y)
    b, d, b_all, _ = _stretch_angles(problem, y)
    assert defects == () and b_all < b - 0.05
    assert mu_b == pytest.approx(b, abs=1e-9) and mu_d == pytest.approx(d, abs=1e-9)


@pytest.mark.parametrize("kind", ["stephenson", "watt"])
def test_a_six_bar_drawn_exactly_at_a_dead_point_is_reported_not_raised(kind: str) -> None:
    """The four-bar loop made r1 - r2 = r4 - r3 exactly (2 - 0.5 = 1.75 - 0.25): folded at
    the drawing, where the engine can neither assemble nor step: a branch defect (and,
    no row swept, a circuit defect, no angles) and the type from the lengths, not
    SingularError."""
    problem, y = _six_bar(kind)
    y[:4] = [2.0, 0.5, 0.25, 1.75]
    assert SB._screen(problem, y) == (("branch", "circuit"), 0.0, 0.0, "change point")


def test_crank_angles_out_of_order_are_an_order_defect() -> None:
    problem, y = _six_bar("stephenson")
    backwards = y.copy()
    backwards[15:] = TH[::-1]
    assert "order" in SB._screen(problem, backwards)[0]
    closed, yc = _six_bar("watt", th=TH, closed=True)
    assert SB._screen(closed, yc)[0] == ()
    yc[-1] = TH[0] + 2 * math.pi  # a closed curve traced over a whole turn
    assert SB._screen(closed, yc)[0] == ("order",)


def test_a_four_bar_loop_that_cannot_turn_through_the_stretch_is_a_branch_defect() -> None:
    """r = (2.0, 1.0, 1.2, 1.5) assembles only for theta2 <= 2.18 rad from the drawing: a
    stretch from 3.5 to 5.0 rad is not reached (no transmission angle: 0); one from 0.4 to
    5.0 meets the dead point inside it."""
    for th, unreached in ((np.linspace(3.5, 5.0, 5), True), (TH, False)):
        problem, y = _six_bar("stephenson", th=th)
        y[:4] = (2.0, 1.0, 1.2, 1.5)
        y[9:11] = (10.0, 10.0)  # a dyad that reaches C wherever the loop puts it
        defects, mu_b, mu_d, grashof = SB._screen(problem, y)
        assert "branch" in defects and "order" not in defects and grashof != "crank-rocker"
        assert (mu_b == 0.0 and mu_d == 0.0) == unreached


def test_a_sweep_stopped_right_after_the_drawing_is_a_branch_defect_only() -> None:
    """r4 1e-7 above the toggle at the drawing (r1 - r2 = r3 + r4 at theta2 = 0): the
    sweep's first row is the drawing, on its circuit, and it stops before the next: a
    branch defect, no circuit defect, no angle over the stretch."""
    problem, y = _six_bar("stephenson")
    y[:4] = (2.0, 0.5, 0.8, 0.7 + 1e-7)
    assert SB._screen(problem, y)[:3] == (("branch",), 0.0, 0.0)


class _NoRow:
    """A compiled model whose sweep fails before its first row, with no partial result."""

    def __init__(self, model: Any) -> None:
        self.model = model

    def linkages(self) -> Any:
        return self.model.linkages()

    def sweep(self, *args: Any, **kwargs: Any) -> Any:
        raise SolveError("no row")


def test_a_sweep_that_gives_no_row_is_a_circuit_defect_without_angles(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The design cannot be followed from its drawing at all: reported (branch and
    circuit), not an error, with no transmission angle."""
    problem, y = _six_bar("watt")
    model = problem.model

    class Drawn:
        def __init__(self, y: Any) -> None:
            self.mech = model(y)

        def compile(self) -> _NoRow:
            return _NoRow(self.mech.compile())

    monkeypatch.setattr(problem, "model", Drawn)
    assert SB._screen(problem, y)[:3] == (("branch", "circuit"), 0.0, 0.0)


def test_a_dyad_too_short_to_follow_c_is_a_branch_defect() -> None:
    problem, y = _six_bar("stephenson")
    pts = problem.points(y, np.linspace(0.0, 2 * math.pi, 360))
    d = np.hypot(*(pts["C"] - pts["F"]).T)
    y[9:11] = 0.5 * (d.min() + d.max()) / 2.0  # r5 + r6 between the nearest and the farthest
    assert SB._screen(problem, y)[0] == ("branch",)


@pytest.mark.parametrize(("off", "defect"), [(0.6e-7, False), (1.4e-7, True)])
def test_a_traced_point_off_the_closed_form_by_more_than_1e_7_of_the_scale_is_a_circuit_defect(
    monkeypatch: pytest.MonkeyPatch, off: float, defect: bool
) -> None:
    """The scale is the larger of the target's size and the largest of the six-bar's
    numbers: here O6's x, 30 (the size is 3.3): the closed form's P moved by off * 30 is
    on the circuit below 1e-7 of it, off it above."""
    problem, y = _six_bar("stephenson")
    y[11] = 30.0
    y[9:11] = (30.0, 1.0)  # r5, r6: reaching O6 from C over the whole turn
    scale = max(problem.target.size, float(np.max(np.abs(y[:15]))))
    assert scale == 30.0 and problem.target.size < 5.0
    assert SB._screen(problem, y)[0] == ()
    points = problem.points

    def moved(y: Any, t: Any) -> dict[str, np.ndarray]:
        p = dict(points(y, t))
        if np.size(t) > 1:  # the screening's reference; the model's drawing (one angle) as it is
            p["P"] = p["P"] + [off * scale, 0.0]
        return p

    monkeypatch.setattr(problem, "points", moved)
    assert ("circuit" in SB._screen(problem, y)[0]) == defect


# ---- what a six-bar design and the fit's answer say --------------------------------------------
def _design(kind: str = "stephenson", **fields: Any) -> Any:
    problem, y = _six_bar(kind)
    values: dict[str, Any] = dict(
        f=0.125, max_deviation=0.25, transmission=math.radians(40.0), violation=0.0, grashof="crank-rocker",
        defects=(), nfev=7, seconds=0.5, transmission_dyad=math.radians(30.0),
    )  # fmt: skip
    values.update(fields)
    return SB.SixBarDesign(problem, y, **values)


@pytest.mark.parametrize("kind", ["stephenson", "watt"])
def test_a_six_bar_design_draws_its_bodies_and_pivots(kind: str) -> None:
    """Five bodies (crank, coupler with C, rocker, the dyad's two links) at the closed
    form's points; the ground pivots O2, O4 and, for a Stephenson, O6 (F); a Watt's F is
    on the rocker."""
    d = _design(kind)
    p = {k: v[0] for k, v in d.problem.points(d.x, [0.9]).items()}
    bodies, pivots = d.linkage_at(0.9)
    want = [
        ["O2", "A"],
        ["A", "B", "C"],
        ["O4", "B"] + (["F"] if kind == "watt" else []),
        ["C", "D", "P"],
        ["F", "D"],
    ]
    assert len(bodies) == 5
    for body, names in zip(bodies, want):
        np.testing.assert_array_equal(body, np.array([p[n] for n in names]))
    ground = ["O2", "O4"] + (["F"] if kind == "stephenson" else [])
    np.testing.assert_array_equal(pivots, np.array([p[n] for n in ground]))
    assert d.kind == kind
    np.testing.assert_allclose(
        d.residuals(), d.problem.points(d.x, d.x[15:])["P"] - d.problem.target.points, atol=1e-9
    )


def test_a_six_bar_design_states_its_numbers_and_state() -> None:
    d = _design()
    text = str(d)
    assert text.startswith("stephenson six-bar: f 0.125 (largest deviation 0.25); r1 2, r2 0.5")
    assert f"O6 ({d.x[11]:.6g}, {d.x[12]:.6g})" in text and "P (0, 0)" in text
    assert (
        "40.0 deg at B, 30.0 deg at D; defect-free" in text and "violated" not in text and "cut" not in text
    )
    assert "E (rocker)" in str(_design("watt"))
    size = d.problem.target.size
    assert "violated" not in str(_design(violation=1e-12 * size))
    bad = str(_design(violation=2e-12 * size, defects=("order", "branch"), cut=True))
    assert "defects: order, branch; constraints violated by" in bad and "cut short by the time budget" in bad


def test_a_six_bar_fit_reports_its_designs_and_why_none() -> None:
    problem = C.TrackingProblem(_target())
    x = np.concatenate([X, TH])
    four = C.CurveFit([C.CurveDesign(problem, x, 0.5, 0.75, 0.7, 0.0, "crank-rocker", (), 1, 0.0)], [], 0.0)
    designs = [_design(f=0.125), _design(f=0.25)]
    fit = SB.SixBarFit(designs, ["start 3: no"], four, 1.5)
    assert fit.best is designs[0] and not fit.budget_ended
    lines = fit.report(count=1).splitlines()
    assert lines[0].startswith("2 six-bars from 3 starts in 1.50 s (1 dropped); sorted: defect-free")
    assert lines[1] == "the best four-bar they grew from: f 0.5 (largest deviation 0.75)"
    assert len(lines) == 3 and lines[2].startswith("1. [] stephenson six-bar: f 0.125")
    assert len(SB.SixBarFit(designs * 4, [], four, 1.0).report().splitlines()) == 2 + 5  # five unless asked
    budget = SB.SixBarFit(designs, [], four, 1.5, budget=2.0, unstarted=1)
    assert budget.budget_ended and "the time budget of 2 s ended the fit" in budget.report()
    assert "did not end the fit" in SB.SixBarFit(designs, [], four, 1.5, budget=2.0).report()
    assert SB.SixBarFit([_design(cut=True)], [], four, 1.0).budget_ended
    with pytest.raises(SynthesisError, match="no six-bar could be refined: start 3: no; b"):
        _ = SB.SixBarFit([], ["start 3: no", "b"], four, 1.0).best
    with pytest.raises(SynthesisError, match="the time budget of 2 s was spent first; no start"):
        _ = SB.SixBarFit([], [], four, 1.0, budget=2.0, unstarted=4).best


@pytest.mark.parametrize("kind", ["stephenson", "watt"])
def test_dyad_seeds_cover_their_stated_ranges(kind: str) -> None:
    """Over 200 dyads (a seeded generator: the same every run) the random numbers fill
    the ranges `dyad_seeds` states, not narrower ones: O6 at 1.3 to 3 radii all round,
    E over (-1, 2) x (-1.5, 1.5) of the rocker's length, r5 + r6 from 1.15 to 1.6 of the
    farthest |C - F| and |r5 - r6| up to 0.8 of the nearest, either link the longer;
    every one asked for is given, none with F on C's curve (nearest below 0.05 of the
    farthest)."""
    out = SB.dyad_seeds(("open", np.concatenate([X, TH])), kind, 200, np.random.default_rng(7))
    assert len(out) == 200
    th = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    c = coupler_points(X, th, "open")
    centre = c.mean(axis=0)
    radius = np.hypot(*(c - centre).T).max()
    far = np.array([y[11:13] for _, y in out])
    if kind == "stephenson":
        rho = np.hypot(*(far - centre).T) / radius
        phi = np.mod(np.arctan2(*(far - centre).T[::-1]), 2 * math.pi)
        assert rho.min() < 1.35 and rho.max() > 2.95 and phi.min() < 0.1 and phi.max() > 2 * math.pi - 0.1
    else:
        e = far / X[3]
        assert (
            e[:, 0].min() < -0.95 and e[:, 0].max() > 1.95 and e[:, 1].min() < -1.45 and e[:, 1].max() > 1.45
        )
    total, diff, longer = [], [], 0
    for side, y in out:
        p = C.six_bars.six_bar_points(y, th, kind, "open", side)
        d = np.hypot(*(p["C"] - p["F"]).T)
        assert d.min() > 0.05 * d.max()
        total.append((y[9] + y[10]) / d.max())
        diff.append(abs(y[9] - y[10]) / d.min())
        longer += int(y[9] > y[10])
    assert min(total) < 1.17 and max(total) > 1.58 and max(diff) > 0.78
    assert 70 <= longer <= 130


class _CountingRng:
    """A generator that counts its draws (each `uniform` call)."""

    def __init__(self, seed: int) -> None:
        self.rng, self.calls = np.random.default_rng(seed), 0

    def uniform(self, *args: float) -> float:
        self.calls += 1
        return float(self.rng.uniform(*args))


def test_a_draw_with_f_near_cs_curve_is_refused_at_any_size() -> None:
    """E drawn on the rocker of X scaled ten times: about one draw in 200 puts F within
    0.05 of the farthest |C - F| of C's curve (measured: the rule is relative, the same
    draws at either size); those are drawn again, so every dyad given keeps F off the
    curve by that fraction and all those asked for are given."""
    x = np.concatenate([X[:6] * 10.0, X[6:7], X[7:] * 10.0, TH])
    rng = _CountingRng(7)
    out = SB.dyad_seeds(("open", x), "watt", 400, rng)
    assert len(out) == 400
    assert rng.calls > 5 * 400  # an accepted draw takes 5 numbers, a refused one 2: some were refused
    th = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    for side, y in out:
        p = C.six_bars.six_bar_points(y, th, "watt", "open", side)
        d = np.hypot(*(p["C"] - p["F"]).T)
        assert d.min() > 0.05 * d.max()


@pytest.mark.parametrize("count", [1, 3])
def test_dyad_seeds_give_up_after_fifty_draws_for_each_dyad_asked(
    monkeypatch: pytest.MonkeyPatch, count: int
) -> None:
    """A four-bar on which every draw puts F on C's curve: each is refused, and the search
    ends after 50 draws for each dyad asked (2 numbers each, O6's angle and radius),
    giving none rather than looping."""
    real = SB.six_bar_points

    def f_on_c(y: np.ndarray, th: np.ndarray, *args: Any) -> dict[str, np.ndarray]:
        pts = dict(real(y, th, *args))
        pts["F"] = pts["C"][::-1].copy()  # F runs along C's curve the other way: they cross
        return pts

    monkeypatch.setattr(SB, "six_bar_points", f_on_c)
    rng = _CountingRng(1)
    assert SB.dyad_seeds(("open", np.concatenate([X, TH])), "stephenson", count, rng) == []
    assert rng.calls == 2 * 50 * count


# ---- the refinement and the fit, a few evaluations each -------------------------------------------
def test_a_refined_six_bar_states_what_its_numbers_give() -> None:
    """The design a refinement returns: its f, largest deviation, constraint violation,
    margins and screening are those of its own numbers, no worse than its start's f."""
    problem, y = _six_bar("stephenson", 1)
    y[13:15] = (0.2, -0.1)  # P off C: the start is not on the points
    t0 = time.perf_counter()
    d = SB.refine_six_bar(problem, y, max_nfev=4, start=5)
    assert 0.0 < d.seconds <= time.perf_counter() - t0
    r, _ = problem.evaluate(d.x)
    assert d.f == pytest.approx(float(r @ r), rel=1e-12) and d.f <= float(
        problem.evaluate(y)[0] @ problem.evaluate(y)[0]
    )
    assert d.max_deviation == pytest.approx(float(np.hypot(*r.reshape(-1, 2).T).max()), rel=1e-12)
    assert d.violation == problem.violation(d.x) and d.margins == problem.margins(d.x)
    assert (d.defects, d.transmission, d.transmission_dyad, d.grashof) == SB._screen(problem, d.x)
    assert d.start == 5 and 0 < d.nfev and not d.cut
    assert SB.refine_six_bar(problem, y, max_nfev=1).start == -1  # no start index unless given


def test_six_bars_grown_from_given_four_bars_are_sorted_and_labelled() -> None:
    target = _target()
    four = C.CurveDesign(
        C.TrackingProblem(target), np.concatenate([X, TH]), 0.0, 0.0, 0.5, 0.0, "crank-rocker", (), 1, 0.0
    )
    t0 = time.perf_counter()
    fit = SB.fit_six_bars(
        target, [four, four], kinds=["watt", "stephenson"], best=1, dyads=2, seed=4, workers=1, max_nfev=2
    )
    assert len(fit.designs) + len(fit.failures) == 4 and fit.unstarted == 0 and fit.budget is None
    assert {d.kind for d in fit.designs} <= {"watt", "stephenson"} and all(
        d.family == "four-bar 1" for d in fit.designs
    )
    keys = [(not d.ok, d.f, d.start) for d in fit.designs]
    assert keys == sorted(keys) and sorted(d.start for d in fit.designs) == sorted(
        set(d.start for d in fit.designs)
    )
    assert fit.four_bars.designs == [four, four] and 0.0 < fit.seconds <= time.perf_counter() - t0
    none = SB.fit_six_bars(target, [four], best=0, workers=1)  # no four-bar taken: no start
    assert not none.designs and not none.failures and none.unstarted == 0
    spent = SB.fit_six_bars(target, [four], kinds=["watt"], best=1, dyads=2, seed=4, workers=1, seconds=0.0)
    assert spent.unstarted == 2 and not spent.designs and spent.budget == 0.0


def test_the_six_bar_fit_unless_asked(monkeypatch: pytest.MonkeyPatch) -> None:
    """Without four-bars, `fit` gives them (16 starts, the seed, half the budget, the
    same evaluations); the best three grow four dyads of each kind, each refined with
    400 evaluations unless asked; a start that does not turn is a failure with its kind."""
    target = _target()
    four = C.CurveDesign(
        C.TrackingProblem(target), np.concatenate([X, TH]), 0.0, 0.0, 0.5, 0.0, "crank-rocker", (), 1, 0.0
    )
    asked: dict[str, Any] = {}
    refined: list[tuple[int, int]] = []

    def fit(t: Any, **options: Any) -> Any:
        asked.update(options)
        return C.CurveFit([four] * 4, [], 0.0)

    def refine(problem: Any, y: Any, max_nfev: int, start: int, deadline: Any) -> Any:
        refined.append((max_nfev, start))
        raise C.CircuitError("stood in")

    monkeypatch.setattr(SB, "fit", fit)
    monkeypatch.setattr(SB, "refine_six_bar", refine)
    six = SB.fit_six_bars(target, workers=1, seconds=60.0)
    assert asked["starts"] == 16 and asked["seed"] == 0 and asked["max_nfev"] == 400
    assert asked["seconds"] == pytest.approx(SB.budget_seconds(60.0) / 2.0)
    assert len(refined) == 3 * 2 * 4 and all(n == 400 for n, _ in refined) and six.unstarted == 0
    assert sorted(k for _, k in refined) == list(range(24))
    assert len(six.failures) == 24 and six.failures[0].endswith("(stephenson from four-bar 1)")
    assert six.budget == 60.0 and not six.designs
    SB.fit_six_bars(target, workers=1, starts=5, seed=9, max_nfev=7)
    assert asked["starts"] == 5 and asked["seed"] == 9 and asked["max_nfev"] == 7 and asked["seconds"] is None


def test_a_six_bar_refinement_unless_asked_spends_the_four_bars_evaluations(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """`refine_six_bar` called alone spends at most 400 evaluations, the four-bar
    refinement's default (`refine`), and what it is asked otherwise, and is numbered as
    `refine` numbers a refinement that is none of a fit's starts (-1) (the least squares
    stood in for: it records its budget and stops)."""
    spent: list[tuple[int, Any]] = []
    starts: list[int] = []

    class Stop(Exception):
        pass

    class Refinement:
        base = np.zeros(3)

        def z_of(self, x: Any) -> Any:
            return x

        def minimise(self, z: Any, max_nfev: int) -> Any:
            spent.append((max_nfev, z))
            raise Stop

    monkeypatch.setattr(
        SB, "start_refinement", lambda problem, y, start, deadline: starts.append(start) or Refinement()
    )
    for call in (lambda: SB.refine_six_bar(None, None), lambda: SB.refine_six_bar(None, None, max_nfev=7)):
        with pytest.raises(Stop):
            call()
    assert [n for n, _ in spent] == [400, 7]
    assert inspect.signature(C.refine).parameters["max_nfev"].default == 400
    assert starts == [-1, -1] == [inspect.signature(C.refine).parameters["start"].default] * 2

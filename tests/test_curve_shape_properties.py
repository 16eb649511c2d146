"""Properties of the shape problem's closed-form steps (linkwork.synthesis.curve.shape),
fast and without a fit: a design moved by a similarity traces its curve moved by it (any
scale, rotation and offset; theta0 kept within a turn), a design is scored as placed or
as moved by the similarity the shape error finds, whichever is nearer the points, by the
mean and largest nearest distance of all the points, and a design that does not turn
fully is not scored."""

from __future__ import annotations

import importlib
import math
import time
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from linkwork.errors import SynthesisError
from linkwork.synthesis.curve.descriptors import ShapeFit, nearest_distances
from linkwork.synthesis.curve.fit import refine
from linkwork.synthesis.curve.seeds import crank_angles_along
from linkwork.synthesis.curve.target import target
from linkwork.synthesis.curve.tracking import TrackingProblem, coupler_points

SH = importlib.import_module("linkwork.synthesis.curve.shape")

X = np.array([2.0, 0.5, 1.8, 1.5, 0.4, 0.3, 0.2, 0.1, -0.2])  # a crank-rocker


def test_traced_is_the_closed_form_over_a_turn() -> None:
    got = SH.traced(X, "crossed", 48)
    np.testing.assert_array_equal(
        got, coupler_points(X, np.linspace(0.0, 2 * math.pi, 48, endpoint=False), "crossed")
    )
    assert SH.traced(X, "open").shape == (720, 2)
    stuck = np.array([2.0, 1.0, 1.2, 1.5, *X[4:]])  # not Grashof: NaN where it does not assemble
    assert np.isnan(SH.traced(stuck, "open", 36)).any()


@settings(max_examples=30, deadline=None)
@given(
    scale=st.floats(0.01, 100.0),
    rotation=st.floats(-20.0, 20.0),
    offset=st.tuples(st.floats(-50.0, 50.0), st.floats(-50.0, 50.0)),
    circuit=st.sampled_from(["open", "crossed"]),
)
def test_a_moved_design_traces_its_curve_moved(
    scale: float, rotation: float, offset: tuple[float, float], circuit: str
) -> None:
    sim = ShapeFit(0.0, 0.0, scale, rotation, np.array(offset))
    y = SH.moved(np.concatenate([X, [0.7, 1.1]]), sim)
    assert -math.pi <= y[6] <= math.pi  # within the refinement's bounds
    np.testing.assert_array_equal(y[9:], [0.7, 1.1])  # the crank angles are not moved
    np.testing.assert_allclose(y[:6], scale * X[:6], rtol=1e-15)
    size = scale * 4.0 + float(np.hypot(*offset))
    np.testing.assert_allclose(
        SH.traced(y, circuit, 90), sim.apply(SH.traced(X, circuit, 90)), rtol=0.0, atol=1e-13 * size
    )


def test_a_design_is_scored_as_placed_or_as_moved_whichever_is_nearer() -> None:
    th = np.linspace(0.0, 2 * math.pi, 40, endpoint=False) + 0.3
    points = coupler_points(X, th, "open")
    # on the points as it is: at distance zero to the 720-step polygon's chord error
    # (below 1e-5 here), and no farther than as placed
    z, mean, largest = SH._score(points, X, "open")
    assert 0.0 <= mean <= largest < 1e-5
    assert mean <= float(nearest_distances(points, SH.traced(X, "open")).mean())
    np.testing.assert_allclose(z, X, rtol=0.0, atol=1e-4)
    # shrunk and turned away from them: the similarity found carries it back
    sim = ShapeFit(0.0, 0.0, 0.5, 1.0, np.array([4.0, 4.0]))
    z, mean, largest = SH._score(points, SH.moved(X, sim), "open")
    assert largest < 1e-5 and not np.allclose(z, SH.moved(X, sim))
    d = nearest_distances(points, SH.traced(z, "open"))
    assert mean == pytest.approx(float(d.mean()), rel=1e-12) and largest == pytest.approx(
        float(d.max()), rel=1e-12
    )
    # a design that does not turn fully is not scored
    assert SH._score(points, np.array([2.0, 1.0, 1.2, 1.5, *X[4:]]), "open") is None


def test_a_placed_design_moved_by_a_worse_similarity_stays_as_placed(monkeypatch: pytest.MonkeyPatch) -> None:
    """The score takes the placement with the smaller mean nearest distance, not the
    similarity's because it is the similarity's."""
    points = coupler_points(X, np.linspace(0.0, 2 * math.pi, 30, endpoint=False), "open")
    monkeypatch.setattr(SH, "shape_error", lambda *a, **k: ShapeFit(0.0, 0.0, 1.0, 0.0, np.array([0.3, 0.0])))
    z, mean, _ = SH._score(points, X, "open")
    np.testing.assert_array_equal(z, X)
    assert mean < 1e-5
    moved = X.copy()
    moved[7] -= 0.3  # 0.3 off in x: the similarity's offset puts it back
    z, mean, _ = SH._score(points, moved, "open")
    np.testing.assert_allclose(z, X, atol=1e-15)
    assert mean < 1e-5


def test_a_shape_result_lists_its_designs_by_mean_distance() -> None:
    def design(mean: float) -> SH.ShapeDesign:
        return SH.ShapeDesign(X.copy(), "open", mean, 2.0 * mean, "atlas", False, None)

    result = SH.ShapeResult([design(0.01), design(0.02), design(0.03)], 1.25)
    assert result.best.mean == 0.01
    lines = result.report(count=2).splitlines()
    assert lines[0] == "3 designs in 1.25 s, by mean nearest distance" and len(lines) == 3
    assert lines[1].startswith("1. mean nearest distance 0.01 (largest 0.02); r1 2, r2 0.5")
    assert "theta0 0.2, O2 (0.1, -0.2); open; from atlas" in lines[1]
    assert len(SH.ShapeResult([design(0.01)] * 7, 0.0).report().splitlines()) == 6  # five by default
    with pytest.raises(SynthesisError, match="no starting design could be refined"):
        _ = SH.ShapeResult([], 0.0).best
    np.testing.assert_array_equal(design(0.1).curve(12), SH.traced(X, "open", 12))


def test_the_placement_with_the_smaller_mean_is_kept_when_the_other_has_the_smaller_largest(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The score orders the two placements by the mean nearest distance, the quantity
    the shape problem minimises, not by the largest: X's own curve with one point 1 off
    it, against X moved 0.3 towards that point (the similarity found: nearer the outlier,
    farther from the rest)."""
    points = coupler_points(X, np.linspace(0.0, 2 * math.pi, 30, endpoint=False), "open")
    right = int(np.argmax(points[:, 0]))
    points = np.vstack([points, points[right] + [1.0, 0.0]])
    shift = ShapeFit(0.0, 0.0, 1.0, 0.0, np.array([0.3, 0.0]))
    monkeypatch.setattr(SH, "shape_error", lambda *a, **k: shift)
    as_placed = nearest_distances(points, SH.traced(X, "open"))
    moved = nearest_distances(points, SH.traced(SH.moved(X, shift), "open"))
    # the premise: the two orders disagree
    assert as_placed.mean() < moved.mean() and moved.max() < as_placed.max()
    z, mean, largest = SH._score(points, X, "open")
    np.testing.assert_array_equal(z, X)
    assert mean == pytest.approx(float(as_placed.mean()), rel=1e-12)
    assert largest == pytest.approx(float(as_placed.max()), rel=1e-12)


def test_the_polish_lowers_the_mean_distance_below_least_squares_whichever_way_the_points_run() -> None:
    """`_polish` minimises the mean nearest distance itself (reweighted least squares):
    on X's points with every third one pushed off, from a design near X, it returns nine
    design numbers whose mean nearest distance is below the start's and below the one
    plain least squares on the same points reaches (measured: 0.0355 against 0.0373, X
    itself 0.0288); the points given the other way round give the same design (it runs
    them the way the design does); a start that cannot be beaten gives none."""
    th = 0.4 + np.linspace(0.0, 2 * math.pi, 36, endpoint=False)
    points = coupler_points(X, th, "open")
    points[::3] += np.random.default_rng(3).normal(0.0, 0.1, (12, 2))
    start = X + np.array([0.05, -0.02, 0.04, 0.03, -0.05, 0.04, 0.03, -0.04, 0.02])
    z, mean, largest = SH._score(points, start, "open")
    design = SH.ShapeDesign(z, "open", mean, largest, "atlas", False, None)
    y = SH._polish(points, design, 4, 200, {})
    assert y is not None and y.shape == (9,)
    polished = SH._score(points, y, "open")
    assert polished is not None
    tracking = TrackingProblem(target(points, closed=True), circuit="open")
    x0 = np.concatenate([z, crank_angles_along(z, "open", points, True)])
    plain = SH._score(points, refine(tracking, x0, max_nfev=200).x[:9], "open")
    assert plain is not None
    assert polished[1] < 0.97 * plain[1] < 0.97 * mean
    backwards = SH._polish(points[::-1].copy(), design, 4, 200, {})
    assert backwards is not None
    np.testing.assert_allclose(backwards, y, rtol=0.0, atol=1e-9)
    unbeatable = SH.ShapeDesign(z, "open", 0.0, 0.0, "atlas", False, None)
    assert SH._polish(points, unbeatable, 2, 50, {}) is None


class _Stop(SynthesisError):
    """Raised by a stand-in refinement after it has recorded its call: the polish ends."""


def _first_refinement(monkeypatch: pytest.MonkeyPatch, points: np.ndarray, design: SH.ShapeDesign) -> dict:
    """The arguments of the polish's first refinement (the polish stopped there)."""
    seen: dict = {}

    def record(problem: TrackingProblem, x: np.ndarray, max_nfev: int, weights: np.ndarray) -> None:
        seen.update(problem=problem, x=np.array(x), max_nfev=max_nfev, weights=np.array(weights))
        raise _Stop("recorded")

    monkeypatch.setattr(SH, "refine", record)
    assert SH._polish(points, design, 3, 200, {}) is None
    return seen


def _noisy(x: np.ndarray, sigma: float, seed: int) -> np.ndarray:
    """36 points of x's open curve, every third pushed off it."""
    points = coupler_points(x, 0.4 + np.linspace(0.0, 2 * math.pi, 36, endpoint=False), "open")
    points[::3] += np.random.default_rng(seed).normal(0.0, sigma, (12, 2))
    return points


@pytest.mark.parametrize("seed", [2, 3, 4])
def test_the_polish_refines_the_closed_curve_from_a_start_that_meets_its_constraints(
    monkeypatch: pytest.MonkeyPatch, seed: int
) -> None:
    """The shape problem's curve is closed: the polish's tracking problem is that of the
    closed curve (its crank angles within one turn), and it starts from crank angles
    that meet it (not decreasing, within a turn), also where the points' nearest angles step
    back and forth so much that their forward steps add up to more than a turn (these
    noisy points: 6.9 to 7.3 rad measured)."""
    points = _noisy(X, 0.1, seed)
    design = SH.ShapeDesign(X.copy(), "open", 1.0, 1.0, "atlas", False, None)
    seen = _first_refinement(monkeypatch, points, design)
    problem, x = seen["problem"], seen["x"]
    assert problem.target.closed and "within one turn" in problem.constraint_names()
    th = x[9:]
    assert np.all(np.diff(th) >= 0.0) and th[-1] - th[0] < 2 * math.pi
    assert problem.violation(x) == 0.0


@pytest.mark.parametrize("rotation", np.linspace(0.0, 2 * math.pi, 8, endpoint=False))
@pytest.mark.parametrize("backwards", [False, True])
def test_the_polish_runs_the_points_the_way_the_design_traces_them(
    monkeypatch: pytest.MonkeyPatch, rotation: float, backwards: bool
) -> None:
    """Points on the design's own curve (at the crank angles the start samples, so each
    lies on the curve exactly), turned any way and given either way round: the polish
    refines them in the order the design's crank traces them, its start on every point
    (the other order puts the start far from most of them)."""
    sim = ShapeFit(0.0, 0.0, 1.0, float(rotation), np.array([0.3, -0.2]))
    x = SH.moved(X, sim)
    th = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)[7::20]
    ahead = coupler_points(x, th, "open")
    points = ahead[::-1].copy() if backwards else ahead
    design = SH.ShapeDesign(x, "open", 1.0, 1.0, "atlas", False, None)
    seen = _first_refinement(monkeypatch, points, design)
    np.testing.assert_array_equal(seen["problem"].target.points, ahead)
    start = coupler_points(seen["x"], seen["x"][9:], "open")
    np.testing.assert_allclose(start, ahead, rtol=0.0, atol=1e-12)


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_the_polish_weighs_a_point_by_its_distance_floored_at_a_thousandth_of_the_mean(
    monkeypatch: pytest.MonkeyPatch, scale: float
) -> None:
    """Weiszfeld's device: a round weighs each point by 1 / sqrt(its distance from the
    start's point at its crank angle), so the weighted sum of squares is the sum of the
    distances; the distances are floored at 1e-3 of their mean, at any size of the
    curve, so a point on the curve (a third of these, to rounding) weighs sqrt(1000) times
    one at the mean distance, not all the weight. Only the ratios of the weights count
    (least squares' minimiser does not move with a common factor)."""
    x = SH.moved(X, ShapeFit(0.0, 0.0, scale, 0.5, np.array([scale, 2 * scale])))
    th = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)[7::20]
    points = coupler_points(x, th, "open")
    points[1::3] += np.random.default_rng(5).normal(0.0, 0.002 * scale, (12, 2))
    points[2::3] += np.random.default_rng(6).normal(0.0, 0.01 * scale, (12, 2))
    design = SH.ShapeDesign(x, "open", 1.0, 1.0, "atlas", False, None)
    seen = _first_refinement(monkeypatch, points, design)
    way = seen["problem"].target.points
    d = np.hypot(*(coupler_points(seen["x"], seen["x"][9:], "open") - way).T)
    assert np.sum(d < 1e-9 * d.mean()) >= 10  # the premise: points on the curve (to rounding)
    floored = np.maximum(d, 1e-3 * d.mean())
    w = seen["weights"]
    np.testing.assert_allclose(w / w[0], np.sqrt(floored[0] / floored), rtol=1e-12)
    assert seen["max_nfev"] == SH._POLISH_NFEV


def test_the_polish_keeps_the_round_of_smallest_mean_and_lengthens_rounds_that_stall(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The polish's rounds, the refinement and the score stood in for (each round moves
    the pivot O2 by 1e-3, so its design is known): a round of 10 evaluations; one that
    moves the mean nearest distance by less than 1e-5 of the round before's gives the
    next four times as many, up to ``max_nfev``; a round at ``max_nfev`` that stalls is
    the last; at most ``rounds`` rounds. The design returned is the round's with the
    smallest mean, which here is neither the last round's nor the one with the smallest
    largest distance (every largest distance is above the start's mean)."""
    # (mean, largest) of each round; the start's mean is 0.01
    rounds = [
        (0.012, 0.02),  # the first round may rise above the start
        (0.009, 0.05),
        (0.0089, 0.03),  # moves by 1.1e-2 of the mean before: not stalled
        (0.0089 * (1 - 1e-7), 0.04),  # stalled: 40 next
        (0.0085, 0.04),
        (0.0085 * (1 + 1e-7), 0.06),  # stalled: 160 next
        (0.0085 * (1 - 2e-7), 0.9),  # stalled: 200 (max_nfev) next; the smallest mean
        (0.0085 * (1 - 1e-7), 0.011),  # stalled at max_nfev: the last
    ]
    nfevs: list[int] = []

    def refine(problem: TrackingProblem, x: np.ndarray, max_nfev: int, weights: np.ndarray):  # noqa: ANN202
        nfevs.append(max_nfev)
        y = np.array(x)
        y[7] += 1e-3
        return SimpleNamespace(x=y)

    def score(points: np.ndarray, x: np.ndarray, circuit: str):  # noqa: ANN202
        assert len(nfevs) <= len(scripted), "the polish ran past a stalled round of max_nfev"
        mean, largest = scripted[len(nfevs) - 1]
        return x, mean, largest

    monkeypatch.setattr(SH, "refine", refine)
    monkeypatch.setattr(SH, "_score", score)
    points = coupler_points(X, np.linspace(0.0, 2 * math.pi, 24, endpoint=False), "open")
    design = SH.ShapeDesign(X.copy(), "open", 0.01, 0.01, "atlas", False, None)
    scripted = rounds
    y = SH._polish(points, design, 50, 200, {})
    assert nfevs == [10, 10, 10, 10, 40, 40, 160, 200]
    assert y is not None and y.shape == (9,)
    np.testing.assert_allclose(y[7] - X[7], 7e-3, rtol=1e-9)  # the seventh round's
    # at most `rounds` rounds: the best of the first three is the third
    nfevs.clear()
    y = SH._polish(points, design, 3, 200, {})
    assert nfevs == [10, 10, 10] and y is not None
    np.testing.assert_allclose(y[7] - X[7], 3e-3, rtol=1e-9)
    # no round below the start's mean: none
    nfevs.clear()
    scripted = [(0.02, 0.02), (0.03, 0.03)]
    assert SH._polish(points, design, 2, 200, {}) is None


def _oval(n: int) -> np.ndarray:
    """n points round an egg-shaped closed curve, unevenly spaced, none repeated."""
    t = np.linspace(0.0, 2 * math.pi, n, endpoint=False) + 0.3 * np.sin(np.linspace(0.0, 2 * math.pi, n))
    return np.column_stack([2.0 * np.cos(t) + 0.3 * np.cos(2 * t), np.sin(t)])


class _Atlas:
    """An atlas stand-in: ``hits`` for every query, the queries recorded."""

    def __init__(self, hits: list) -> None:
        self.hits, self.asked = hits, []

    def query(self, points: np.ndarray, k: int, closed: bool) -> list:
        self.asked.append(dict(k=k, closed=closed))
        return self.hits[:k]


@settings(max_examples=40, deadline=None)
@given(n=st.integers(3, 150), refine_points=st.integers(1, 80))
def test_the_shape_fit_refines_on_every_sth_point_the_fewest_steps_that_keep_within_its_count(
    n: int, refine_points: int
) -> None:
    """The tracking refinement (the random seeds drawn for it too) takes every s-th
    target point, s the smallest step that leaves at most ``refine_points`` of them
    (4 at the least): all the points when there are no more; the scores take them all."""
    pts = _oval(n)
    drawn: list = []
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(SH, "random_seeds", lambda t, count, seed: drawn.append(t) or [])
        result = SH.shape_fit(pts, k=1, random=1, atlas=_Atlas([]), refine_points=refine_points)
    assert result.designs == [] and len(drawn) == 1
    cap = max(refine_points, 4)
    s = next(s for s in range(1, n + 1) if len(pts[::s]) <= cap)
    np.testing.assert_array_equal(drawn[0].points, pts[::s])
    assert drawn[0].closed


def _fits(monkeypatch: pytest.MonkeyPatch, means: dict[float, tuple[float, float]]) -> dict[str, list]:
    """Stand-ins for the refinement (`fit`: each seed's design is the seed), the random
    draws (one crank-rocker), the score (the mean and largest of ``means`` by x[0]) and
    the polish (returns X with x[0] 99); their calls recorded."""
    calls: dict[str, list] = {"fit": [], "random": [], "polish": []}

    def fit(
        target: object, seeds: list, workers: object, max_nfev: int, **problem: object
    ) -> SimpleNamespace:
        calls["fit"].append(dict(target=target, families=[s.family for s in seeds], max_nfev=max_nfev))
        return SimpleNamespace(
            designs=[SimpleNamespace(x=s.x, circuit=s.circuit, family=s.family) for s in seeds]
        )

    def random_seeds(target: object, count: int, seed: int) -> list:
        calls["random"].append(dict(target=target, count=count, seed=seed))
        return [("open", np.concatenate([X * [1, 1, 1, 1, 1, 1, 1, 1, 1], np.zeros(len(target.points))]))][
            :count
        ]

    def score(points: np.ndarray, x: np.ndarray, circuit: str) -> tuple:
        return np.array(x[:9]), *means[float(x[0])]

    def polish(points: np.ndarray, design: SH.ShapeDesign, rounds: int, max_nfev: int, problem: dict):  # noqa: ANN202
        calls["polish"].append(dict(design=design, rounds=rounds, max_nfev=max_nfev))
        y = X.copy()
        y[0] = 99.0
        return y

    monkeypatch.setattr(SH, "fit", fit)
    monkeypatch.setattr(SH, "random_seeds", random_seeds)
    monkeypatch.setattr(SH, "_score", score)
    monkeypatch.setattr(SH, "_polish", polish)
    return calls


def _hit(r1: float, reverse: bool) -> SimpleNamespace:
    return SimpleNamespace(vector=np.concatenate([[r1], X[1:]]), circuit="open", reverse=reverse)


def test_the_shape_fits_defaults_are_its_documented_ones(monkeypatch: pytest.MonkeyPatch) -> None:
    """Called with the target alone: the 12 nearest atlas curves, no random seed (seed
    0), 200 evaluations a refinement, a polish of at most 24 rounds of at most 200, the
    refinement on at most 36 of the points (here 19 of 37), the rounds stopped when two
    designs agree (here after the first: the means of `NEAR`)."""
    r1 = [2.0 + 0.01 * k for k in range(20)]
    means = {r: (m, 2 * m) for r, m in zip(r1, NEAR + [0.1 + 0.01 * k for k in range(10)])}
    calls = _fits(monkeypatch, {**means, 99.0: (0.02, 0.03)})
    atlas = _Atlas([_hit(r, False) for r in r1])
    result = SH.shape_fit(_oval(37), atlas=atlas)
    assert result.unrefined == 8 and len(result.designs) == 4
    head = result.report().splitlines()[0]
    assert head.startswith("4 designs in") and head.endswith("(8 seeds left: 2 starts agreed on the best)")
    assert atlas.asked == [dict(k=12, closed=True)]
    assert [(c["count"], c["seed"]) for c in calls["random"]] == [(0, 0)]
    assert len(calls["random"][0]["target"].points) == 19
    assert calls["fit"] and all(c["max_nfev"] == 200 for c in calls["fit"])
    assert [(c["rounds"], c["max_nfev"]) for c in calls["polish"]] == [(24, 200)]


def test_random_seeds_are_refined_on_the_points_they_were_drawn_for(monkeypatch: pytest.MonkeyPatch) -> None:
    """A random crank-rocker's crank angles are drawn for the points as given: it is
    refined on those (not on the points run backwards, which the atlas's reversed hits
    are refined on)."""
    calls = _fits(monkeypatch, {2.0: (0.01, 0.02), 2.1: (0.02, 0.03), X[0]: (0.03, 0.04)})
    SH.shape_fit(
        _oval(30), k=2, random=1, atlas=_Atlas([_hit(2.0, True), _hit(2.1, False)]), polish=0, agree=None
    )
    (drawn,) = calls["random"]
    refined = [c for c in calls["fit"] if "random" in c["families"]]
    assert len(refined) == 1 and len(calls["fit"]) == 2
    np.testing.assert_array_equal(refined[0]["target"].points, drawn["target"].points)
    (backwards,) = [c for c in calls["fit"] if c["families"] == ["atlas"]]
    np.testing.assert_array_equal(backwards["target"].points, drawn["target"].points[::-1])


@pytest.mark.parametrize(("polished", "kept"), [((0.009, 0.5), True), ((0.011, 0.001), False)])
def test_the_polish_starts_from_the_best_design_and_is_kept_only_below_its_mean(
    monkeypatch: pytest.MonkeyPatch, polished: tuple[float, float], kept: bool
) -> None:
    """The polish starts from the design of smallest mean nearest distance (not the
    first refined, nor the one of smallest largest distance); its design is put first
    when its mean is below that design's, whatever its largest distance, and left out
    otherwise."""
    means = {2.3: (0.03, 0.005), 2.1: (0.01, 0.2), 2.2: (0.02, 0.1), 99.0: polished}
    calls = _fits(monkeypatch, means)
    hits = [_hit(2.3, False), _hit(2.1, True), _hit(2.2, False)]
    result = SH.shape_fit(_oval(30), k=3, atlas=_Atlas(hits), agree=None)
    (asked,) = calls["polish"]
    assert asked["design"].mean == 0.01 and asked["design"].x[0] == 2.1
    got = [(d.x[0], d.mean) for d in result.designs]
    rest = [(2.1, 0.01), (2.2, 0.02), (2.3, 0.03)]
    assert got == ([(99.0, polished[0])] + rest if kept else rest)
    if kept:
        best = result.best
        assert best.largest == polished[1] and best.tracking is None
        assert best.reverse and best.family == "atlas" and best.circuit == "open"


# the means of ten seeds' designs: in the first round of four two within 1 % of the best
# (0.5 %; a third 1.5 % off), in the second a third (0.9 %)
NEAR = [0.05, 0.01, 0.01005, 0.01015, 0.04, 0.01009, 0.06, 0.07, 0.08, 0.09]
# a curve traced exactly: its two best designs 0 and 1e-12 (1e-12 of the target's size is 4.5e-12)
EXACT = [0.05, 0.0, 1e-12, 0.03, 0.04, 0.06, 0.07, 0.08, 0.09, 0.1]


@pytest.mark.parametrize(
    ("agree", "means", "refined"),
    [(2, NEAR, 4), (3, NEAR, 8), (None, NEAR, 10), (0, NEAR, 10), (2, EXACT, 4)],
)
def test_the_shape_fits_seeds_are_refined_in_rounds_of_four_until_enough_agree(
    monkeypatch: pytest.MonkeyPatch, agree: int | None, means: list[float], refined: int
) -> None:
    """Ten atlas hits, nearest first, refined in rounds of four (each round's hits run
    forwards and backwards refined apart) until ``agree`` designs are within 1 % of the
    best mean (or within 1e-12 of the target's size of it, for a curve traced exactly);
    the seeds of the rounds not run are reported as left (none when every seed is
    refined, ``agree`` None or 0)."""
    r1 = [2.0 + 0.01 * k for k in range(10)]
    calls = _fits(monkeypatch, {r: (m, 2 * m) for r, m in zip(r1, means)})
    hits = [_hit(r, k % 3 == 0) for k, r in enumerate(r1)]
    t0 = time.perf_counter()
    result = SH.shape_fit(_oval(30), k=10, atlas=_Atlas(hits), polish=0, agree=agree)
    assert 0.0 <= result.seconds <= time.perf_counter() - t0  # the wall time it took
    assert sorted(d.x[0] for d in result.designs) == r1[:refined]
    assert [d.mean for d in result.designs] == sorted(means[:refined])
    assert result.unrefined == 10 - refined
    assert sum(len(c["families"]) for c in calls["fit"]) == refined
    assert all(d.reverse == (r1.index(d.x[0]) % 3 == 0) for d in result.designs)

"""Properties of the seeds' closed-form steps, fast and without the homotopy: a drawn
four-bar maps back to the design numbers and circuit it was drawn from, the crank angles
found along a design's own coupler curve are the ones it was traced at (to the search's
grid of 2 pi / 720), the crank-rocker filter is Grashof's condition with the crank the
shortest (equality included), the seed error is the tracking error, and the points
spread along the target are evenly spaced by arc length."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork.errors import SynthesisError
from linkwork.synthesis import curve as C
from linkwork.synthesis.curve import seeds as S
from linkwork.synthesis.curve.tracking import coupler_points

X = np.array([2.0, 0.5, 1.8, 1.5, 0.4, 0.3, 0.2, 0.1, -0.2])
GRID = 2.0 * math.pi / 720


def _drawing(x: np.ndarray, th2: float, circuit: str):
    """O2, A, O4, B and P of design x drawn at crank angle th2."""
    probe = x.copy()
    probe[4:6] = (x[2], 0.0)
    b = coupler_points(probe, [th2], circuit)[0]
    p = coupler_points(x, [th2], circuit)[0]
    o2 = x[7:9]
    o4 = o2 + x[0] * np.array([math.cos(x[6]), math.sin(x[6])])
    a = o2 + x[1] * np.array([math.cos(x[6] + th2), math.sin(x[6] + th2)])
    return o2, a, o4, b, p


@pytest.mark.parametrize("circuit", ["open", "crossed"])
@pytest.mark.parametrize("th2", [0.3, 2.5, -2.0])
def test_a_drawn_four_bar_maps_back_to_its_design_and_circuit(circuit: str, th2: float) -> None:
    got = S.design_vectors(*_drawing(X, th2, circuit))
    assert got is not None and got[0] == circuit
    np.testing.assert_allclose(got[1], np.append(X, th2), rtol=0.0, atol=1e-12)


@pytest.mark.parametrize("circuit", ["open", "crossed"])
def test_crank_angles_along_its_own_curve_are_the_traced_ones(circuit: str) -> None:
    th = np.array([0.4, 1.3, 2.0, 3.9, 5.0, 6.9])  # past a turn: increasing, unwrapped
    pts = coupler_points(X, th, circuit)
    got = S.crank_angles_along(X, circuit, pts, closed=False)
    assert np.all(np.diff(got) > 0.0)
    np.testing.assert_allclose(got, th, rtol=0.0, atol=GRID / 2 + 1e-12)
    # points met backwards are not a step back: the angle stays
    back = S.crank_angles_along(X, circuit, pts[[0, 2, 1]], closed=False)
    assert back[2] == back[1] and back[1] - back[0] == pytest.approx(1.6, abs=GRID)


def test_a_closed_curves_crank_angles_stay_within_one_turn() -> None:
    """Points all round the curve whose nearest steps add to more than a turn are spread
    back within (n - 1) / n of it."""
    th = np.linspace(0.1, 0.1 + 2 * math.pi, 9)[:-1]
    pts = coupler_points(X, th, "open")
    got = S.crank_angles_along(X, "open", pts, closed=True)
    np.testing.assert_allclose(got, th, rtol=0.0, atol=GRID / 2 + 1e-12)
    assert got[-1] - got[0] < 2 * math.pi
    # a last point at the first one's angle (a full turn of steps): rescaled into the turn
    full = S.crank_angles_along(X, "open", np.vstack([pts, pts[:1]]), closed=True)
    assert full[-1] - full[0] == pytest.approx(2 * math.pi * 8 / 9, rel=1e-12)
    # ... about the first point, which keeps its angle
    turn = np.append(th, th[0] + 2 * math.pi)
    np.testing.assert_allclose(full, th[0] + (turn - th[0]) * 8 / 9, rtol=0.0, atol=GRID / 2 + 1e-12)
    # within a turn, however far round it starts, the angles are kept as they are
    late = np.array([1.5, 2.5, 3.5, 4.5, 5.5])
    got = S.crank_angles_along(X, "open", coupler_points(X, late, "open"), closed=True)
    np.testing.assert_allclose(got, late, rtol=0.0, atol=GRID / 2 + 1e-12)
    with pytest.raises(SynthesisError, match="does not assemble"):
        S.crank_angles_along([9.0, 0.5, 1.0, 1.0, 0, 0, 0, 0, 0], "open", pts, closed=True)


def test_the_crank_rocker_filter_is_grashof_with_the_crank_shortest() -> None:
    assert S._crank_rocker(np.array([2.0, 0.5, 1.8, 1.5]))
    assert S._crank_rocker(np.array([2.0, 0.5, 1.0, 1.5]))  # s + l = p + q: a change point, kept
    assert not S._crank_rocker(np.array([2.0, 0.5, 0.9, 1.5]))  # 2.5 > 2.4: not Grashof
    assert S._crank_rocker(np.array([2.0, 0.5, 0.5, 2.0]))  # the crank ties for the shortest
    assert not S._crank_rocker(np.array([0.5, 2.0, 1.8, 1.5]))  # the ground is shortest
    assert not S._crank_rocker(np.array([2.0, 0.6, 1.8, 0.5]))  # the rocker is shortest
    # a whole design vector: only its four lengths count, not a coupler point nearer
    assert S._crank_rocker(np.append(X, 1.1)) and S._crank_rocker(np.array([2.0, 0.5, 1.8, 1.5, 0.1, 0.0]))


def test_the_seed_error_is_the_tracking_error_of_the_seed_as_it_stands() -> None:
    th = np.array([0.4, 1.3, 2.0, 3.9, 5.0])
    pts = coupler_points(X, th, "open")
    shift = np.array([[0.1, 0.0], [0.0, -0.2], [0.0, 0.0], [0.3, 0.4], [0.0, 0.0]])
    target = C.target(pts + shift)
    seed = S.Seed("open", np.append(X, th), "alt")
    assert S.seed_error(seed, target) == pytest.approx(0.01 + 0.04 + 0.25, rel=1e-12)
    # a timed target's own crank angles are used, not the seed's
    timed = C.target(pts + shift, crank_angles=th)
    late = S.Seed("open", np.append(X, th + 0.5), "alt")
    assert S.seed_error(late, timed) == pytest.approx(0.30, rel=1e-12)
    # a seed that does not assemble at a target's crank angle has no finite error
    apart = np.append([9.0, 0.5, 1.0, 1.0], X[4:])
    assert S.seed_error(S.Seed("open", np.append(apart, th), "alt"), target) == math.inf


def test_nine_points_are_evenly_spaced_by_arc_length() -> None:
    """Around a square of side 4 (perimeter 16) nine points 16 / 9 apart along it; along
    an open L of legs 3 and 1, nine points 0.5 apart from its first point to its last."""
    square = C.target(np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]]), closed=True)
    nine = S.nine_along(square)
    assert nine.shape == (9, 2)
    np.testing.assert_allclose(nine[0], [0.0, 0.0])
    step = 16.0 / 9.0
    np.testing.assert_allclose(nine[1:3], [[step, 0.0], [2 * step, 0.0]], atol=1e-14)
    np.testing.assert_allclose(nine[-1], [0.0, 4.0 - (8 * step - 12.0)], atol=1e-14)
    ell = C.target(np.array([[0.0, 0.0], [1.5, 0.0], [3.0, 0.0], [3.0, 1.0]]))
    got = S.nine_along(ell)
    np.testing.assert_allclose(got[:, 0], [0, 0.5, 1, 1.5, 2, 2.5, 3, 3, 3], atol=1e-14)
    np.testing.assert_allclose(got[:, 1], [0, 0, 0, 0, 0, 0, 0, 0.5, 1.0], atol=1e-14)


def test_five_timed_points_spread_by_index_first_and_last_included() -> None:
    def five(n: int) -> list[int]:
        th = np.linspace(0.0, 3.0, n)
        pts = np.column_stack([np.cos(th), np.sin(th)]) * (1.0 + 0.1 * th[:, None])
        return S.five_along(C.target(pts, crank_angles=th)).tolist()

    assert five(5) == [0, 1, 2, 3, 4]
    assert five(9) == [0, 2, 4, 6, 8]
    assert five(12) == [0, 3, 6, 8, 11]  # round(2.75) = 3, round(5.5) = 6, round(8.25) = 8


def test_a_drawn_design_with_its_crank_angle_seeds_the_problem_with_the_targets_angles() -> None:
    """`design_vectors`' answer (nine numbers and the drawing's crank angle) becomes a seed
    of the problem's size: the nine numbers, then one crank angle per target point."""
    th = np.array([0.4, 1.3, 2.0, 3.9, 5.0])
    target = C.target(coupler_points(X, th, "open"))
    seed = S._with_angles(np.append(X, 1.1), "open", target, "alt")
    assert seed.x.shape == (9 + len(th),) and seed.family == "alt"
    np.testing.assert_array_equal(seed.x[:9], X)
    np.testing.assert_allclose(seed.x[9:], th, rtol=0.0, atol=GRID / 2 + 1e-12)


def test_atlas_seeds_are_eight_by_default_and_run_the_targets_way() -> None:
    """The shipped atlas's nearest curves, placed by the two normalisations, with the
    crank angles along the target: eight unless asked, each within 1 % of the target's
    size (root mean square; 0.42 % here) of the points as it stands. Run the other way
    they miss by about half the size (these against the points backwards: 56 %; the
    atlas's curves queried backwards and placed on the points: 50 %)."""
    known = np.array([10.0, 2.5, 8.75, 7.5, 3.75, 3.0, 0.7, 12.0, -3.0])
    th = 0.3 + np.linspace(0.0, 2.0 * math.pi, 24, endpoint=False)
    target = C.target(coupler_points(known, th, "open"), closed=True)
    seeds = S.atlas_seeds(target)
    assert len(seeds) == 8 and len(S.atlas_seeds(target, k=3)) == 3
    rms = [math.sqrt(S.seed_error(s, target) / len(target)) for s in seeds]
    assert max(rms) < 0.01 * target.size
    backwards = C.target(target.points[::-1], closed=True)
    assert min(math.sqrt(S.seed_error(s, backwards) / len(target)) for s in seeds) > 0.2 * target.size


def test_alt_seeds_keep_the_crank_rockers_of_the_four_bars_found(monkeypatch: pytest.MonkeyPatch) -> None:
    """Alt's four-bars (here given, in place of the homotopy, which must not screen them
    itself: every real one is offered) are kept each way round where that makes a
    Grashof crank-rocker, as their own design numbers, with crank angles along the
    target; ``keep``: that many, the smallest seed error first."""
    from types import SimpleNamespace

    import linkwork.synthesis.exact as exact

    def drawn(x: np.ndarray, th2: float, circuit: str) -> SimpleNamespace:
        o2, a, o4, b, p = _drawing(x, th2, circuit)
        return SimpleNamespace(o2=o2, a=a, o4=o4, b=b, p=p)

    other = np.array([2.2, 0.6, 2.0, 1.6, -0.3, 0.5, 0.9, 0.4, 0.2])  # another crank-rocker
    drag_link = np.array([0.5, 2.0, 1.8, 1.5, *X[4:]])  # ground shortest: two cranks, no crank-rocker
    found = [
        drawn(X, 0.3, "open"),
        drawn(np.array([2.0, 1.0, 1.2, 1.5, *X[4:]]), 0.3, "open"),
        drawn(drag_link, 0.3, "open"),
        drawn(other, 1.0, "crossed"),
    ]
    asked: dict[str, object] = {}

    def nine_points(points: np.ndarray, screen: bool, seconds: float) -> SimpleNamespace:
        asked.update(points=points, screen=screen, seconds=seconds)
        return SimpleNamespace(designs=found, failed=2)

    monkeypatch.setattr(exact, "nine_points", nine_points)
    target = C.target(coupler_points(X, np.linspace(0.2, 2.5, 9), "open"))
    seeds, info = S.alt_seeds(target)
    assert asked["screen"] is False and asked["seconds"] == 10.0
    np.testing.assert_array_equal(asked["points"], S.nine_along(target))
    assert [s.circuit for s in seeds] == ["open", "crossed"] and all(s.family == "alt" for s in seeds)
    np.testing.assert_allclose(seeds[0].x[:9], X, atol=1e-12)
    np.testing.assert_allclose(seeds[1].x[:9], other, atol=1e-12)
    assert {k: info[k] for k in ("four_bars", "crank_rockers", "kept", "failed")} == {
        "four_bars": 4, "crank_rockers": 2, "kept": 2, "failed": 2
    }  # fmt: skip
    kept, info = S.alt_seeds(target, seconds=3.0, points=target.points, keep=1)
    assert asked["seconds"] == 3.0 and np.array_equal(asked["points"], target.points)
    assert len(kept) == 1 and info["kept"] == 1 and info["crank_rockers"] == 2
    np.testing.assert_allclose(kept[0].x[:9], X, atol=1e-12)  # X traced the target: the smaller error
    assert S.alt_seeds(target, keep=-1)[0] == []

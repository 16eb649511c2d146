"""Seeds for synthesis from a curve (linkwork.synthesis.curve.seeds) and the shape
problem (linkwork.synthesis.curve.shape): atlas seeds start fits that reach a known
four-bar's curve (moved, turned and scaled), Alt's four-bars through nine points of a
known four-bar's curve include that four-bar, and the shape fit improves on its seed."""

from __future__ import annotations

import importlib
import math
from types import SimpleNamespace

import numpy as np
import pytest

from linkwork.errors import SynthesisError
from linkwork.synthesis import curve as C
from linkwork.synthesis.curve import seeds as S
from linkwork.synthesis.curve.shape import moved, traced

SH = importlib.import_module("linkwork.synthesis.curve.shape")

pytest.importorskip("scipy")

# a Grashof crank-rocker (ground 4, crank 1, coupler 3.5, rocker 3, coupler point
# (1.5, 1.2)), scaled by 2.5, turned by 0.7 rad and moved to (12, -3)
KNOWN = np.array([10.0, 2.5, 8.75, 7.5, 3.75, 3.0, 0.7, 12.0, -3.0])


def _gap(x: np.ndarray, y: np.ndarray) -> float:
    """Largest difference of two design-number rows (theta0 modulo a turn)."""
    d = np.asarray(x[:9], dtype=float) - np.asarray(y[:9], dtype=float)
    d[6] = math.remainder(d[6], 2.0 * math.pi)
    return float(np.abs(d).max())


def test_design_vectors_invert_the_drawing() -> None:
    # the drawing at theta2 = 0.4 on each circuit, read back: same numbers and circuit
    for circuit in ("open", "crossed"):
        th2 = 0.4
        c0, s0 = math.cos(KNOWN[6]), math.sin(KNOWN[6])
        o2 = KNOWN[7:9]
        o4 = o2 + KNOWN[0] * np.array([c0, s0])
        a = o2 + KNOWN[1] * np.array([math.cos(KNOWN[6] + th2), math.sin(KNOWN[6] + th2)])
        probe = KNOWN.copy()
        probe[4:6] = (KNOWN[2], 0.0)
        b = C.coupler_points(probe, [th2], circuit)[0]
        p = C.coupler_points(KNOWN, [th2], circuit)[0]
        got = S.design_vectors(o2, a, o4, b, p)
        assert got is not None
        assert got[0] == circuit
        assert _gap(got[1], KNOWN) < 1e-12 * 10.0
        assert got[1][9] == pytest.approx(th2, abs=1e-12)


@pytest.mark.parametrize("circuit", ["open", "crossed"])
def test_atlas_seeds_reach_a_known_curve(circuit: str) -> None:
    th = 0.3 + np.linspace(0.0, 2.0 * math.pi, 24, endpoint=False)
    t = C.target(C.coupler_points(KNOWN, th, circuit), closed=True)
    seeds = S.atlas_seeds(t, k=6)
    assert len(seeds) == 6 and all(s.family == "atlas" and s.x.shape == (33,) for s in seeds)
    # the crank angles a seed brings increase, within a turn
    assert all(np.all(np.diff(s.x[9:]) >= 0.0) and s.x[-1] - s.x[9] < 2.0 * math.pi for s in seeds)
    result = C.fit(t, seeds=seeds, workers=2)
    best = result.best
    assert best.family == "atlas"
    # the known design scores 0: reached to rounding (f in squared lengths, size ~6)
    assert best.f < 1e-20 * t.size**2
    assert best.ok


@pytest.mark.parametrize("circuit", ["open", "crossed"])
def test_alt_seeds_include_the_generating_design(circuit: str) -> None:
    nine = C.coupler_points(KNOWN, 0.2 + 0.9 * np.linspace(0.0, 2.0 * math.pi, 9, endpoint=False), circuit)
    seeds, info = S.alt_seeds(C.target(nine), seconds=30.0, points=nine)
    assert info["four_bars"] >= 3 and info["kept"] == len(seeds) > 0
    assert all(s.family == "alt" for s in seeds)
    # every seed is a crank-rocker, the crank the shortest link
    assert all(s.x[1] <= min(s.x[0], s.x[2], s.x[3]) for s in seeds)
    gaps = [_gap(s.x, KNOWN) for s in seeds]
    k = int(np.argmin(gaps))
    # the homotopy's roots are refined to rounding: the generating four-bar to 1e-9
    assert gaps[k] < 1e-9 * 10.0
    assert seeds[k].circuit == circuit


def test_nine_points_along_a_target() -> None:
    square = C.target([[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0]], closed=True)
    nine = S.nine_along(square)
    # perimeter 12: a point every 12 / 9 along it, from the first corner, counterclockwise
    side = lambda a: {0: (a, 0.0), 1: (3.0, a - 3.0), 2: (9.0 - a, 3.0), 3: (0.0, 12.0 - a)}[int(a // 3.0)]  # noqa: E731
    assert np.allclose(nine, [side(k * 12.0 / 9.0) for k in range(9)], atol=1e-12)
    line = S.nine_along(C.target([[0.0, 0.0], [8.0, 0.0], [8.0, 4.0]]))
    assert line[0] == pytest.approx([0.0, 0.0]) and line[-1] == pytest.approx([8.0, 4.0])


def test_make_seeds_labels_every_family() -> None:
    th = np.linspace(0.0, 2.0 * math.pi, 18, endpoint=False)
    t = C.target(C.coupler_points(KNOWN, th, "open"), closed=True)
    got = S.make_seeds(t, atlas=3, alt=False, random=2, seed=4)
    assert [s.family for s in got] == ["atlas"] * 3 + ["random"] * 2
    assert got.counts == {"atlas": 3, "random": 2}
    result = C.fit(t, seeds=list(got), workers=2, max_nfev=20)
    assert result.designs
    # each refined design keeps the family of the seed it started from
    assert all(d.family == got.seeds[d.start].family for d in result.designs)
    assert f"[{result.best.family}]" in result.report()


def test_shape_fit_improves_on_its_seed() -> None:
    # a known four-bar's curve moved, turned, scaled and started elsewhere, 40 points
    th = 1.1 + np.linspace(0.0, 2.0 * math.pi, 40, endpoint=False)
    x = KNOWN.copy()
    x[4:6] = (-2.0, 5.0)
    pts = C.coupler_points(x, th, "crossed")
    hit = C.load_atlas().query(pts, k=1)[0]
    seed_mean = C.shape_error(pts, hit.curve(720), polish=False).mean
    result = C.shape_fit(pts, k=4, seed=0, workers=2)
    best = result.best
    assert best.mean < 0.5 * seed_mean
    # the design is placed: its own curve, unmoved, is as near the points as reported
    from linkwork.synthesis.curve.descriptors import nearest_distances

    assert nearest_distances(pts, best.curve()).mean() == pytest.approx(best.mean, rel=1e-12)
    assert result.seconds < 60.0


def test_shape_fit_does_not_depend_on_the_way_the_points_run() -> None:
    """The same points given the other way round: each seed is refined on the points
    run its own way, so the same designs come out with the opposite direction (36
    points: the refinement takes them all, the same points either way)."""
    th = 1.1 + np.linspace(0.0, 2.0 * math.pi, 36, endpoint=False)
    x = KNOWN.copy()
    x[4:6] = (-2.0, 5.0)
    pts = C.coupler_points(x, th, "crossed")
    pts[::3] += np.random.default_rng(1).normal(0.0, 0.3, (12, 2))
    ahead = C.shape_fit(pts, k=4, seed=0, workers=1)
    back = C.shape_fit(pts[::-1].copy(), k=4, seed=0, workers=1)
    assert len(back.designs) == len(ahead.designs) > 1
    for a, b in zip(ahead.designs, back.designs):
        assert b.mean == pytest.approx(a.mean, rel=1e-6) and b.reverse != a.reverse


def test_random_seeds_of_a_shape_fit_run_the_points_as_given() -> None:
    """Random crank-rockers are drawn for the points as given: their designs say they
    run the points forwards (only atlas hits of the curve run backwards are reversed)."""
    th = np.linspace(0.0, 2.0 * math.pi, 36, endpoint=False)
    result = C.shape_fit(C.coupler_points(KNOWN, th, "open"), k=1, random=3, workers=1, polish=0, agree=None)
    drawn = [d for d in result.designs if d.family == "random"]
    assert drawn and not any(d.reverse for d in drawn)


def test_a_shape_fit_without_a_refined_design_says_so(monkeypatch: pytest.MonkeyPatch) -> None:
    """No seed refined (every fit empty): the result has no design and asking for the
    best is a named error; there is nothing to polish."""
    monkeypatch.setattr(SH, "fit", lambda *a, **k: SimpleNamespace(designs=[]))
    th = np.linspace(0.0, 2.0 * math.pi, 36, endpoint=False)
    result = SH.shape_fit(C.coupler_points(KNOWN, th, "open"), k=2, polish=4)
    assert result.designs == [] and result.unrefined == 0
    with pytest.raises(SynthesisError, match="no starting design could be refined"):
        _ = result.best


def test_moved_carries_the_curve() -> None:
    sim = C.ShapeFit(0.0, 0.0, 1.7, -0.4, np.array([3.0, -1.0]))
    y = moved(KNOWN, sim)
    assert np.allclose(traced(y, "open", 90), sim.apply(traced(KNOWN, "open", 90)), atol=1e-12)


def test_shape_fit_refuses_timed_targets() -> None:
    t = C.target([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], crank_angles=[0.0, 1.0, 2.0, 3.0])
    with pytest.raises(SynthesisError, match="free timing"):
        C.shape_fit(t)


def test_moved_keeps_theta0_within_a_turn() -> None:
    # a rotation that would carry theta0 past 2 pi (the refinement's bound) wraps it
    sim = C.ShapeFit(0.0, 0.0, 1.0, 6.0, np.zeros(2))
    y = moved(KNOWN, sim)
    assert -math.pi <= y[6] <= math.pi
    assert np.allclose(traced(y, "open", 90), sim.apply(traced(KNOWN, "open", 90)), atol=1e-9)


def test_shape_polish_lowers_the_mean_distance() -> None:
    # a known four-bar's curve with every third point pushed off it: the least-squares
    # fit spreads the misses, the reweighted polish minimises their mean
    th = 0.4 + np.linspace(0.0, 2.0 * math.pi, 36, endpoint=False)
    pts = C.coupler_points(KNOWN, th, "open")
    rng = np.random.default_rng(3)
    pts[::3] += rng.normal(0.0, 0.2, (12, 2))
    plain = C.shape_fit(pts, k=4, seed=0, workers=2, polish=0).best
    polished = C.shape_fit(pts, k=4, seed=0, workers=2, polish=4).best
    assert polished.mean < 0.995 * plain.mean


@pytest.mark.parametrize("circuit", ["open", "crossed"])
def test_timed_dyads_give_back_the_four_bar(circuit: str) -> None:
    # five points of a known four-bar at prescribed crank angles: its crank is a timed
    # dyad, its rocker a Burmester dyad of the poses, and the pair is among the seeds
    th = np.array([0.3, 1.2, 2.0, 3.1, 4.4])
    t = C.target(C.coupler_points(KNOWN, th, circuit), crank_angles=th)
    got, info = S.timed_seeds(t)
    assert info["kept"] == len(got) > 0
    assert all(s.family == "timed" for s in got)
    mine = [s for s in got if s.circuit == circuit]
    assert min(_gap(s.x, KNOWN) for s in mine) < 1e-9
    assert min(S.seed_error(s, t) for s in got) < 1e-20
    # kept by the smallest tracking error
    best, _ = S.timed_seeds(t, keep=1)
    assert S.seed_error(best[0], t) == min(S.seed_error(s, t) for s in got)


def test_timed_seeds_in_make_seeds_and_refusals() -> None:
    th = np.linspace(0.2, 4.0, 8)
    t = C.target(C.coupler_points(KNOWN, th, "open"), crank_angles=th)
    got = S.make_seeds(t, atlas=0, alt=0, random=2, timed=3, seed=1)
    assert got.counts["timed"] == 3 and [s.family for s in got][:3] == ["timed"] * 3
    assert any(n.startswith("timed dyads:") for n in got.notes)
    fitted = C.fit(t, seeds=list(got), workers=2)
    assert min(d.f for d in fitted.designs if d.family == "timed") < 1e-18
    # a free-timing target has no timed dyads; four points are too few
    untimed = C.target(C.coupler_points(KNOWN, th, "open"))
    assert "timed" not in S.make_seeds(untimed, atlas=0, alt=0, random=1).counts
    with pytest.raises(SynthesisError, match="prescribed crank angles"):
        S.timed_seeds(untimed)
    with pytest.raises(SynthesisError, match="five timed points"):
        S.timed_seeds(C.target(C.coupler_points(KNOWN, th[:4], "open"), crank_angles=th[:4]))

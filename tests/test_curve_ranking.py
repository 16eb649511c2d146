"""The ranking of curve designs: defect-free and within the constraints first, of them
the usable (smallest transmission angle at least the stated bound, else 30 degrees) before
the rest, then by f; no design is dropped for its transmission angle."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork.synthesis import curve as C

pytest.importorskip("scipy")

# A traces the target exactly but its transmission angle comes to 19.2 deg of 0 or 180;
# B is 47.5 deg at worst and misses the target (f 2.29)
A = np.array([4.0, 1.5, 4.3, 2.0, 1.0, 0.6, 0.2, 0.0, 0.0])
B = np.array([4.0, 1.2, 3.8, 2.6, 1.0, 0.6, 0.2, 0.0, 0.0])
TH = np.linspace(0.0, 2.0 * math.pi, 12, endpoint=False) + 0.1


def _fit(**options: object) -> C.CurveFit:
    t = C.target(C.coupler_points(A, TH, "open"), closed=True)
    seeds = [("open", np.concatenate([A, TH]), "a"), ("open", np.concatenate([B, TH]), "b")]
    # one evaluation a weight: the designs are the seeds as they stand
    return C.fit(t, seeds=seeds, workers=2, max_nfev=1, **options)


def test_a_usable_design_ranks_before_a_better_fit_below_30_degrees() -> None:
    result = _fit()
    a, b = sorted(result.designs, key=lambda d: d.family)
    assert a.ok and b.ok and a.f < 1e-20 < 1.0 < b.f
    assert math.degrees(a.transmission) == pytest.approx(19.2, abs=0.1) and not a.usable
    assert math.degrees(b.transmission) > 30.0 and b.usable
    assert [d.family for d in result.designs] == ["b", "a"]
    # nothing hidden: the smaller f is named with its transmission angle
    assert f"the smallest f of a defect-free design, {a.f:.4g}, is #2's" in result.report()
    assert "19.2 deg" in result.smallest_f_note()


def test_a_stated_transmission_bound_replaces_the_default() -> None:
    result = _fit(transmission="15 deg")
    assert [d.family for d in result.designs] == ["a", "b"]
    assert all(d.usable for d in result.designs) and result.smallest_f_note() == ""
    assert C.USABLE_TRANSMISSION == pytest.approx(math.radians(30.0))


def test_fit_stops_when_two_designs_agree() -> None:
    # four starts near A (its curve the target) reach f ~ 0 in the first round of four:
    # with agree=2 the four random starts after them are left
    t = C.target(C.coupler_points(A, TH, "open"), closed=True)
    rng = np.random.default_rng(2)
    near = [("open", np.concatenate([A + rng.normal(0.0, 0.01, 9), TH])) for _ in range(4)]
    seeds = near + C.random_seeds(t, 4, seed=1)
    every = C.fit(t, seeds=seeds, workers=2, max_nfev=100)
    stopped = C.fit(t, seeds=seeds, workers=2, max_nfev=100, agree=2)
    assert every.unrefined == 0 and len(every.designs) + len(every.failures) == 8
    assert stopped.unrefined == 4 and {d.start for d in stopped.designs} <= {0, 1, 2, 3}
    ok = sorted(d.f for d in stopped.designs if d.ok)
    assert len(ok) >= 2 and ok[1] <= 1e-20 * t.size**2
    assert stopped.best.f == pytest.approx(every.best.f, abs=1e-20 * t.size**2)
    assert "4 starts left unrefined: enough designs agreed" in stopped.report()


def test_six_bars_rank_usable_first_judged_at_b_and_at_d() -> None:
    # Watt six-bars grown from A (f ~ 0, 19.2 deg at B) and B (f 2.29, 47.5 deg at B), P
    # at C and one evaluation each: they trace their four-bar's curve, D's angle random
    t = C.target(C.coupler_points(A, TH, "open"), closed=True)
    six = C.fit_six_bars(t, _fit(), kinds=("watt",), best=2, dyads=4, seed=1, workers=2, max_nfev=1)
    designs = six.designs
    # nothing hidden: every start is a design, all defect-free and within the constraints
    assert len(designs) == 8 and not six.failures and all(d.ok for d in designs)
    bound = math.radians(30.0)
    for d in designs:
        assert d.usable == (min(d.transmission, d.transmission_dyad) >= bound)
    # usable first, then by f: a usable six-bar of f 2.29 ranks before one of f ~ 0
    assert [(not d.usable, d.f) for d in designs] == sorted((not d.usable, d.f) for d in designs)
    usable = [d for d in designs if d.usable]
    rest = [d for d in designs if not d.usable]
    assert usable and rest and rest[0].f < 1e-20 < 1.0 < min(d.f for d in usable)
    # judged at D too: a six-bar of B's four-bar (47.5 deg at B) with D below 30 deg ranks last
    assert any(d.transmission >= bound > d.transmission_dyad for d in rest)
    k = next(k for k, d in enumerate(designs, 1) if d is rest[0])
    assert f"the smallest f of a defect-free design, {rest[0].f:.4g}, is #{k}'s" in six.report()
    # a stated bound replaces the default on the six-bar problem as on the four-bar's
    assert C.SixBarProblem(t, transmission="15 deg").transmission == pytest.approx(math.radians(15.0))

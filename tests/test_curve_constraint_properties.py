"""Properties of the curve-synthesis constraints' building blocks, fast and without a fit:
a region's residual is the signed distance outside it (a disc: Euclidean; a box: the
largest excess over its sides), cos mu is the law of cosines of the assembled linkage,
the smallest transmission angle over a stretch is the smallest over a fine sampling of
it, and every gradient matches central differences (step 1e-6, agreement 1e-7
relative: the differences' truncation and rounding errors are below 1e-9 here)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkwork.errors import SynthesisError
from linkwork.synthesis.curve import constraints as K


def _central(fun, x: np.ndarray, h: float = 1e-6) -> np.ndarray:
    cols = []
    for k in range(x.size):
        e = np.zeros(x.size)
        e[k] = h * max(1.0, abs(x[k]))
        cols.append((np.atleast_1d(fun(x + e)) - np.atleast_1d(fun(x - e))) / (2.0 * e[k]))
    return np.array(cols).T


def test_a_disc_region_is_the_signed_euclidean_distance_outside_it() -> None:
    disc = K.region("P", {"centre": [1.0, -2.0], "radius": 0.5})
    pts = np.array([[1.0, -2.0], [1.3, -2.4], [1.0, -1.5], [4.0, 2.0], [-0.2, -2.0]])
    out, grad = disc.outside(pts)
    expected = [-0.5, 0.0, 0.0, 4.5, 0.7]
    np.testing.assert_allclose(out, expected, rtol=0.0, atol=1e-15)
    # the gradient is the outward unit normal; at the centre it is zero, not NaN
    np.testing.assert_array_equal(grad[0], [0.0, 0.0])
    np.testing.assert_allclose(
        grad[1:], (pts[1:] - [1.0, -2.0]) / np.hypot(*(pts[1:] - [1.0, -2.0]).T)[:, None]
    )
    np.testing.assert_allclose(np.hypot(grad[1:, 0], grad[1:, 1]), 1.0, rtol=1e-15)


def test_a_box_region_is_the_largest_excess_over_its_sides() -> None:
    """Beyond each of the four sides by 0.3, inside (minus the distance to the nearest
    side) and past a corner (the larger of the two excesses), each with the unit normal
    of the side that binds."""
    box = K.region("O4", {"x": [1.0, 3.0], "y": [-1.0, 0.0]})
    pts = np.array([[0.7, -0.5], [3.3, -0.5], [2.0, -1.3], [2.0, 0.3], [1.2, -0.5], [3.5, 0.1]])
    out, grad = box.outside(pts)
    np.testing.assert_allclose(out, [0.3, 0.3, 0.3, 0.3, -0.2, 0.5], rtol=0.0, atol=1e-15)
    np.testing.assert_array_equal(grad, [[-1, 0], [1, 0], [0, -1], [0, 1], [-1, 0], [1, 0]])
    # a degenerate box (one point in x) is a region, an inverted one is a contradiction
    assert K.region("O2", {"x": [1.0, 1.0], "y": [0.0, 1.0]}).outside(np.array([1.0, 0.5]))[0][0] == 0.0
    with pytest.raises(SynthesisError, match="empty box, y from 2.0 to 1.0"):
        K.region("O2", {"x": [0.0, 1.0], "y": [2.0, 1.0]})


def _cos_mu_of_the_linkage(r: np.ndarray, theta2: np.ndarray) -> np.ndarray:
    """cos mu from the assembled linkage: O2 at the origin, O4 at (r1, 0), A on the crank;
    the coupler AB (r3) and the rocker O4B (r4) meet at B, d = |A - O4|."""
    r1, r2, r3, r4 = r
    a = r2 * np.column_stack([np.cos(theta2), np.sin(theta2)])
    d = np.hypot(a[:, 0] - r1, a[:, 1])
    return (r3 * r3 + r4 * r4 - d * d) / (2.0 * r3 * r4)


def test_transmission_cosine_is_the_law_of_cosines_with_an_exact_gradient() -> None:
    r = np.array([2.0, 0.5, 1.8, 1.5])
    th = np.linspace(-4.0, 7.0, 23)
    c, grad = K.transmission_cos(r, th)
    np.testing.assert_allclose(c, _cos_mu_of_the_linkage(r, th), rtol=0.0, atol=1e-14)
    for i, t in enumerate(th):
        fd = _central(lambda y: K.transmission_cos(y[:4], np.array([y[4]]))[0], np.append(r, t))[0]
        np.testing.assert_allclose(grad[i], fd, rtol=0.0, atol=1e-7 * max(1.0, np.abs(grad[i]).max()))


def _design(r: list[float], th: np.ndarray) -> np.ndarray:
    return np.concatenate([r, [0.4, 0.3, 0.2, 0.1, -0.2], th])


def _sampled_smallest(r: np.ndarray, first: float, last: float) -> float:
    c = _cos_mu_of_the_linkage(r, np.linspace(first, last, 200001))
    return float(np.arccos(np.abs(c).max()))


@pytest.mark.parametrize(
    ("r", "first", "last"),
    [
        ([2.0, 0.5, 1.8, 1.5], 0.2, 2.9),  # no multiple of pi inside: an end decides
        ([2.0, 0.5, 1.8, 1.5], 2.0, 2.5),  # the nearer end to pi
        ([2.0, 0.5, 1.8, 1.5], -5.0, 2.0),  # -pi and 0 inside
        ([2.0, 0.9, 1.8, 1.5], 1.0, 7.0),  # pi and 2 pi inside; mu obtuse at pi
        ([2.0, 0.3, 1.5, 1.2], 2.0, 2.6),  # mu obtuse (cos mu < 0) over the stretch
    ],
)
def test_smallest_transmission_of_an_open_stretch_is_the_sampled_minimum(
    r: list[float], first: float, last: float
) -> None:
    """Sampled at steps of ~5e-5 rad, the sampling approaches the exact minimum from above
    to second order: within 1e-8; the gradient (lengths and the end angles) is exact."""
    x = _design(r, np.linspace(first, last, 6))
    mu, g = K.smallest_transmission(x, closed=False)
    assert -1e-15 <= _sampled_smallest(np.array(r), first, last) - mu <= 1e-8
    fd = _central(lambda y: K.smallest_transmission(y, False)[0], x)[0]
    np.testing.assert_allclose(g, fd, rtol=0.0, atol=1e-7 * max(1.0, np.abs(g).max()))
    # the interior crank angles never decide it, nor do the coupler point and the pivot
    assert np.all(g[4:9] == 0.0) and np.all(g[10:-1] == 0.0)


@pytest.mark.parametrize("r", [[2.0, 0.5, 1.8, 1.5], [2.0, 0.5, 1.5, 1.2]])  # extreme at 0; at pi
def test_smallest_transmission_of_a_closed_curve_covers_the_whole_turn(r: list[float]) -> None:
    """A closed curve is traced over a whole turn whatever its crank angles: the smallest
    angle is that of the turn (at theta2 = 0 or pi), and the crank angles do not move it."""
    x = _design(r, np.linspace(0.3, 1.0, 5))
    mu, g = K.smallest_transmission(x, closed=True)
    assert -1e-15 <= _sampled_smallest(np.array(r), 0.0, 2 * math.pi) - mu <= 1e-8
    assert np.all(g[9:] == 0.0)
    fd = _central(lambda y: K.smallest_transmission(y, True)[0], x)[0]
    np.testing.assert_allclose(g, fd, rtol=0.0, atol=1e-7 * max(1.0, np.abs(g).max()))


def test_the_candidate_angles_are_the_ends_and_the_multiples_of_pi_strictly_inside() -> None:
    th, which = K.stretch_angles(_design([1, 1, 1, 1], np.linspace(-math.pi, 3.0 * math.pi, 4)), False)
    np.testing.assert_allclose(th, [-math.pi, 3.0 * math.pi, 0.0, math.pi, 2.0 * math.pi], atol=1e-15)
    np.testing.assert_array_equal(which, [0, 3, -1, -1, -1])
    th, which = K.stretch_angles(_design([1, 1, 1, 1], np.linspace(0.5, 3.0, 4)), False)
    np.testing.assert_allclose(th, [0.5, 3.0])
    np.testing.assert_array_equal(which, [0, 3])


def test_angles_read_with_their_unit_and_refuse_what_is_not_finite() -> None:
    assert K.angle("t", " 45 deg ") == pytest.approx(math.pi / 4, rel=1e-15)
    assert K.angle("t", "0.7 rad") == 0.7 and K.angle("t", 0.7) == 0.7
    for bad in (math.inf, math.nan, "1e999x deg"):
        with pytest.raises(SynthesisError, match="^t "):
            K.angle("t", bad)
    with pytest.raises(SynthesisError, match="radius 0.0 is empty"):
        K.region("P", {"center": [0.0, 0.0], "radius": 0.0})
    with pytest.raises(SynthesisError, match="finite"):
        K.region("P", {"centre": [math.inf, 0.0], "radius": 1.0})


def test_a_stretch_through_a_dead_point_has_a_zero_transmission_angle() -> None:
    """r = (2.0, 1.0, 1.2, 1.5) does not assemble at theta2 = pi (d = 3.0 > r3 + r4):
    |cos mu| passes 1 there, and the smallest angle is 0 (a dead point), not an error."""
    x = _design([2.0, 1.0, 1.2, 1.5], np.linspace(0.5, 4.0, 5))
    for closed in (False, True):
        mu, g = K.smallest_transmission(x, closed)
        assert mu == 0.0 and np.all(np.isfinite(g))
